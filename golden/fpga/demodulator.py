"""Demodulator and window sums: the integrator of the HF q-current error and the per-window sums.

docs/spec.md, section 3.4 (Benevieri et al. 2023, Sec. II-B, eq. (19)). Per sample of an integration
window (spec 2.1: the instants in ``[k*P + H/2, (k+1)*P + H/2)``), with ``w`` the weight
``sin(-cw*pi/2)`` of the sample (:func:`golden.fpga.cordic.demod_weight`):

* ``acc_q += i_q*w``, ``acc_d += i_d*w`` (s48), ``sum_d += i_d``, ``sum_q += i_q``, ``wsum += w``,
  ``n += 1`` (``n`` saturates at 65535; the accumulation goes on);

and at the window boundary the results are latched:

* ``GAMMA = sat(shr(acc_q, 15), 32)``, ``GAMMA_D = sat(shr(acc_d, 15), 32)``,
  ``SUM_ID = sat(sum_d, 32)``, ``SUM_IQ = sat(sum_q, 32)``, ``WSUM = sat(wsum, 32)``, ``N_SAMPLES = n``.

``eps = i_q^ * sin(-cw*pi/2)`` and ``gamma = sum of eps`` over one period are eq. (19); ``GAMMA`` is that
sum in current LSB x samples (the product is Q1.15, hence the floor shift by 15).

The model sums exactly (int64: the products are at most 2^30 in magnitude). The spec states that the
s48 accumulators cannot overflow; a window whose exact ``acc_q`` or ``acc_d`` leaves s48 is therefore
outside the specification and raises ValueError instead of wrapping silently. (With two's-complement
accumulators only the final value matters: intermediate excursions wrap back.) ``sum_d``, ``sum_q`` and
``wsum`` are saturated from their exact values, as the spec writes them.

:func:`demodulate` checks its arguments; :func:`demodulate_kernel` is the unchecked form and
:func:`latch_window` the latch shared with :mod:`golden.fpga.window_dsp`.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from golden.fixed import sat, shr

ACC_BITS = 48
"""Width of the product accumulators ``acc_q``, ``acc_d``."""
N_MAX = 0xFFFF
"""Saturation value of the sample counter ``N_SAMPLES`` (u16)."""

_S16_MIN, _S16_MAX = -(1 << 15), (1 << 15) - 1


@dataclass(frozen=True)
class WindowResult:
    """Latched results of one integration window (the status registers, spec 3.4).

    Attributes
    ----------
    gamma : int
        ``GAMMA``, s32: ``sat(shr(sum i_q*w, 15), 32)``, eq. (19) (current LSB x samples).
    gamma_d : int
        ``GAMMA_D``, s32: ``sat(shr(sum i_d*w, 15), 32)``.
    sum_id : int
        ``SUM_ID``, s32: ``sat(sum i_d, 32)`` (current LSB).
    sum_iq : int
        ``SUM_IQ``, s32: ``sat(sum i_q, 32)``.
    wsum : int
        ``WSUM``, s32: ``sat(sum w, 32)`` (Q1.15).
    n_samples : int
        ``N_SAMPLES``, u16: samples in the window, saturated at 65535.
    inj_phase : int
        ``INJ_PHASE``, u32: the rotating injection's phase in the window (``golden.fpga.rot_injection``;
        not the demodulator's, latched with its results at the same boundary; 0 while off).
    cic_qa, cic_qb : int
        ``CIC_QA``, ``CIC_QB``, s21 in s32: the interpolated position quadrature signals of the window's
        carrier-bottom sample (``golden.fpga.diff_cic``, latched at the same boundary; 0 while the period
        square wave never ran).
    env_a, env_b : int
        ``ENV_A``, ``ENV_B``, s17 in s32: the held envelope (the CIC's input) of the same sample.
    vector : int
        ``VECTOR.STATE``, u3: the inverter state the direct-vector mode chose at the window's carrier top
        (spec 3.10; 0 while the mode is off).
    vector_next : int
        ``VECTOR.NEXT``, u3: the state it applies from the next carrier top, chosen from the registers
        committed at the window boundary (spec 3.10; 0 while the mode is off).
    top_ia, top_ib : int
        ``TOP_I``, s16 each: the Clarke currents of the window's carrier-top sample (spec 3.11; the
        previous window's while a window has none).
    vdc : int
        ``VDC.CODE``, uB: the code of the ADC's dc-link channel of the window's carrier-bottom sample
        (spec 3.12; unipolar, 0 V at code 0).
    status : int
        ``WIN_FAULT``: the fault latches (``OC``, ``WDT``, ``STO``, ``DESAT``) as they stood at the boundary that
        ends the window (spec 2.2, 3.7): nonzero once the hardware turned the gates off by itself. The golden
        closed loop models the overcurrent comparator (golden.fpga.overcurrent); it drives no STO or DESAT and
        its firmware never misses a commit, so only ``OC`` can be set.
    frozen : int
        ``WIN_ADC``: the current lanes whose every conversion in the window returned one code (``FROZEN_A``,
        ``FROZEN_B``; golden.fpga.adc_frozen, spec 3.13).
    """

    gamma: int
    gamma_d: int
    sum_id: int
    sum_iq: int
    wsum: int
    n_samples: int
    inj_phase: int = 0
    cic_qa: int = 0
    cic_qb: int = 0
    env_a: int = 0
    env_b: int = 0
    vector: int = 0
    vector_next: int = 0
    top_ia: int = 0
    top_ib: int = 0
    vdc: int = 0
    status: int = 0
    frozen: int = 0


def _window_array(x, name: str) -> np.ndarray:
    """One window's s16 samples as a 1-D int64 array (an empty sequence of any dtype is allowed)."""
    a = np.asarray(x)
    if a.ndim != 1:
        raise ValueError(f"{name} must be 1-D (one window's samples), got shape {a.shape}")
    if a.size == 0:
        return np.zeros(0, dtype=np.int64)
    if a.dtype.kind not in "iu":
        raise TypeError(f"{name} must hold integers, got dtype {a.dtype}")
    if int(a.min()) < _S16_MIN or int(a.max()) > _S16_MAX:
        idx = np.flatnonzero((a < _S16_MIN) | (a > _S16_MAX))[0]
        raise ValueError(f"{name}[{idx}] = {int(a[idx])} is not an s16 value")
    return a if a.dtype == np.int64 else a.astype(np.int64)


def demodulate(i_d, i_q, w) -> WindowResult:
    """Integrate one window: the demodulated q-current error and the window sums (spec 3.4).

    Parameters
    ----------
    i_d, i_q : array_like of int
        Park currents of the window's samples, s16 (spec 3.2), in sampling order.
    w : array_like of int
        Demodulation weights of the same samples, s16 Q1.15 (spec 3.3), Benevieri et al. 2023,
        eq. (19). The three arrays have the same length, which may be 0 (all results 0).

    Returns
    -------
    WindowResult
        The latched ``GAMMA, GAMMA_D, SUM_ID, SUM_IQ, WSUM, N_SAMPLES`` (Python ints).

    Raises
    ------
    ValueError
        If the arrays are not 1-D of one length, a value is outside s16, or the window is so long that
        an exact product sum leaves the s48 accumulator (more than 2^17 extreme samples; the spec
        states that it cannot happen).
    TypeError
        If an array does not hold integers.
    """
    d = _window_array(i_d, "i_d")
    q = _window_array(i_q, "i_q")
    ww = _window_array(w, "w")
    if not len(d) == len(q) == len(ww):
        raise ValueError(f"i_d, i_q and w must have one length, got {len(d)}, {len(q)}, {len(ww)}")
    return demodulate_kernel(d, q, ww)


def demodulate_kernel(i_d: np.ndarray, i_q: np.ndarray, w: np.ndarray) -> WindowResult:
    """Unchecked form of :func:`demodulate`: five numpy reductions, then :func:`latch_window`.

    ``i_d``, ``i_q``, ``w``: 1-D int64 arrays of one length holding s16 values (checked by the caller).
    Exact in int64: ``|i*w| <= 2^30``, so the dot products cannot overflow for any array that fits in
    memory (numpy's integer dot product has no floating-point path).
    """
    return latch_window(int(i_q @ w), int(i_d @ w), int(i_d.sum()), int(i_q.sum()), int(w.sum()),
                        len(i_d))


def latch_window(acc_q: int, acc_d: int, sum_d: int, sum_q: int, wsum: int, n: int) -> WindowResult:
    """The window-boundary latch (spec 3.4) from the exact sums of a window of ``n`` samples.

    ``acc_q = sum i_q*w``, ``acc_d = sum i_d*w``, ``sum_d``, ``sum_q``, ``wsum``: exact Python ints.
    Returns ``GAMMA = sat(shr(acc_q, 15), 32)``, ``GAMMA_D``, the saturated sums and
    ``N_SAMPLES = min(n, 65535)``. Raises ValueError if ``acc_q`` or ``acc_d`` leaves s48 (outside
    the specification, see the module docstring).
    """
    lim = 1 << (ACC_BITS - 1)
    if not (-lim <= acc_q < lim and -lim <= acc_d < lim):
        name, acc = ("acc_q", acc_q) if not -lim <= acc_q < lim else ("acc_d", acc_d)
        raise ValueError(f"{name} = {acc} leaves the s{ACC_BITS} accumulator ({n} samples): "
                         "outside spec 3.4, which states that it cannot overflow")
    return WindowResult(
        gamma=sat(shr(acc_q, 15), 32),
        gamma_d=sat(shr(acc_d, 15), 32),
        sum_id=sat(sum_d, 32),
        sum_iq=sat(sum_q, 32),
        wsum=sat(wsum, 32),
        n_samples=n if n < N_MAX else N_MAX,
    )
