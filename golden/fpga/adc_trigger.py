"""ADC trigger: current sampling instants per PWM period and per integration window, and blanking.

docs/spec.md, section 2.3 (Benevieri et al. 2023: 1 us current oversampling, Sec. II-B; blanking after
the switching instants, Fig. 8). ``ADC_MODE`` selects the sampling instants within each period
``P = 2H`` (phases ``phi = t mod P``, see ``golden/fpga/carrier.py``):

* ``MODE_OS`` (0): ``phi = m*OS_TICKS`` for ``m = 0, 1, ...`` while ``phi <= P - OS_MIN``. The sequence restarts
  at every period start, so when ``OS_TICKS`` does not divide ``P`` the last gap of a period is
  shorter than ``OS_TICKS``.
* ``MODE_DS`` (1): ``phi = 0`` and ``phi = H`` (carrier bottom and top).
* ``MODE_OS_BLANK`` (2): the ``MODE_OS`` instants minus those within ``BLANK_TICKS`` after a switching
  instant (:func:`blank_mask`; the switching instants come from the gate generator).
* Mode 3 is reserved; the hardware treats it as ``MODE_OS`` (documented safe behaviour).
"""

from __future__ import annotations

import numpy as np

from golden.fpga.checks import int_param

from golden.fpga.carrier import check_half, window_start

MODE_OS = 0
MODE_DS = 1
MODE_OS_BLANK = 2
MODE_RESERVED = 3
"""Reserved ``ADC_MODE`` value: behaves as ``MODE_OS``."""

U16_MAX = 0xFFFF


OS_MIN_DEFAULT = 40
"""``OS_MIN`` of the default hardware (32 CORDIC iterations, an ADC cycle of at most 40 ticks)."""


def os_min_ticks(iterations: int = 32, adc_cycle: int = 0) -> int:
    """Shortest sampling interval of the hardware: ``OS_MIN = max(iterations + 8, adc_cycle)`` ticks
    (the CORDIC's clocks plus its pipeline, and the serial ADC's conversion + read-out cycle,
    ``hfi_adc_if.CYCLE``; docs/spec.md 2.3)."""
    return max(int_param(iterations, 1, 32, "iterations") + 8, int_param(adc_cycle, 0, U16_MAX, "adc_cycle"))


def effective_os_ticks(register: int, iterations: int = 32, adc_cycle: int = 0) -> int:
    """The oversampling interval the hardware uses: ``OS_TICKS`` but at least :func:`os_min_ticks`
    (docs/spec.md 2.3). ``register`` must be a u16."""
    if not 0 <= register <= 0xFFFF:
        raise ValueError(f"OS_TICKS = {register} is not a u16 register value")
    return max(register, os_min_ticks(iterations, adc_cycle))


def sample_phases(mode: int, half: int, os_ticks: int, os_min: int = OS_MIN_DEFAULT) -> np.ndarray:
    """Sampling phases within one PWM period (spec 2.3).

    Parameters
    ----------
    mode : int
        ``ADC_MODE``: ``MODE_OS``, ``MODE_DS``, ``MODE_OS_BLANK`` or 3 (reserved, as ``MODE_OS``).
        For ``MODE_OS_BLANK`` these are the ``MODE_OS`` phases; the blanking is applied separately by
        :func:`blank_mask` because it depends on the switching instants.
    half : int
        Effective carrier half period ``H`` [ticks] (even, 4..65534).
    os_ticks : int
        ``OS_TICKS`` register, u16, at least 1 (validated in every mode, although ``MODE_DS`` ignores it).
    os_min : int
        The hardware's ``OS_MIN`` (:func:`os_min_ticks`): an OS instant is taken only if the next period
        starts at least ``os_min`` ticks after it (``phi <= P - os_min``), so the ADC and the CORDIC
        are free again for the sample at the period start. Phase 0 is always taken.

    Returns
    -------
    ndarray of int64
        Sorted phases in ``[0, 2H)``: ``0, OS_TICKS, 2*OS_TICKS, ...`` up to ``2H - os_min`` in the OS
        modes, ``[0, H]`` in ``MODE_DS``.

    Raises
    ------
    ValueError
        If ``mode`` is not 0..3, ``os_ticks`` not in 1..65535 or ``half`` not a valid half period.
    """
    mode = int_param(mode, 0, 3, "ADC_MODE")
    h = check_half(half)
    os_ticks = int_param(os_ticks, 1, U16_MAX, "OS_TICKS")
    os_min = int_param(os_min, 1, U16_MAX, "os_min")
    if mode == MODE_DS:
        return np.array([0, h], dtype=np.int64)
    return np.arange(0, max(2 * h - os_min + 1, 1), os_ticks, dtype=np.int64)


def window_sample_ticks(k: int, mode: int, half: int, os_ticks: int, os_min: int = OS_MIN_DEFAULT) -> np.ndarray:
    """Every sampling instant of integration window ``k`` (before blanking), as absolute ticks.

    Window ``k`` holds ``[k*P + H/2, (k+1)*P + H/2)`` (spec 2.1): the phases ``>= H/2`` of period
    ``k`` followed by the phases ``< H/2`` of period ``k + 1``, so a window holds exactly as many
    instants as a period.

    Parameters
    ----------
    k : int
        Window index (may be negative).
    mode, half, os_ticks, os_min
        As in :func:`sample_phases`.

    Returns
    -------
    ndarray of int64
        Sorted ticks in ``[window_start(k), window_start(k + 1))``.
    """
    if isinstance(k, (bool, np.bool_)) or not isinstance(k, (int, np.integer)):
        raise ValueError(f"window index must be an integer, got {k!r}")
    phases = sample_phases(mode, half, os_ticks, os_min)
    h = int(half)
    period = 2 * h
    late = phases[phases >= h // 2] + k * period          # rest of period k
    early = phases[phases < h // 2] + (k + 1) * period    # start of period k + 1
    ticks = np.concatenate([late, early])
    assert ticks.size == 0 or (ticks[0] >= window_start(k, h) and ticks[-1] < window_start(k + 1, h))
    return ticks


def blank_mask(sample_ticks, switch_ticks, blank_ticks: int) -> np.ndarray:
    """Which samples the ``OS_BLANK`` mode drops (spec 2.3; Benevieri et al. 2023, Fig. 8).

    A sample at tick ``t`` is dropped if some leg's ideal switch signal changed at a tick ``t_s`` with
    ``0 <= t - t_s < BLANK_TICKS``: a sample exactly at a switching instant is dropped, one at
    ``t_s + BLANK_TICKS`` is kept.

    Parameters
    ----------
    sample_ticks : array_like of int
        Sampling instants [ticks], any order.
    switch_ticks : array_like of int
        Ticks at which any leg's ideal switch signal changed (union of the three legs; any order,
        duplicates allowed).
    blank_ticks : int
        ``BLANK_TICKS`` register, u16; 0 drops nothing.

    Returns
    -------
    ndarray of bool
        Same shape as ``sample_ticks``; True where the sample is dropped.

    Raises
    ------
    ValueError
        If ``blank_ticks`` is not in 0..65535 or the ticks are not integers.
    """
    blank = int_param(blank_ticks, 0, U16_MAX, "BLANK_TICKS")
    t = np.asarray(sample_ticks)
    sw = np.asarray(switch_ticks).ravel()
    for name, arr in (("sample ticks", t), ("switch ticks", sw)):
        if arr.size and arr.dtype.kind not in "iu":
            raise ValueError(f"{name} must be integers, got dtype {arr.dtype}")
    t = t.astype(np.int64)
    if blank == 0 or sw.size == 0:
        return np.zeros(t.shape, dtype=bool)
    sw = np.sort(sw.astype(np.int64))
    idx = np.searchsorted(sw, t, side="right") - 1          # latest switching tick <= t
    latest = sw[np.maximum(idx, 0)]
    return (idx >= 0) & (t - latest < blank)
