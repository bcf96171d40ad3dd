"""Modulator: voltage references + injection -> three compare values, bit-true.

docs/spec.md, section 3.5. At each compare latch (carrier bottom, ``sign = -1``, for the rising half;
carrier top, ``sign = +1``, for the falling half; spec 2.1 "double update") the active registers
``V_D, V_Q, V_H, SIN, COS`` give

1. square-wave injection (``CTRL.INJ_ROT = 0``): ``vd = V_D + sign*V_H`` (s17), ``vq = V_Q``, the
   injection on the estimated d-axis, ``v_dh = V_h * -sign(d cw/dt)`` (Benevieri et al. 2023, eq. (14));
   rotating injection (``INJ_ROT = 1``): ``vd = V_D``, ``vq = V_Q`` and ``(C, S)`` = the injection's
   sin/cos below;
2. inverse Park, ``v_alpha = round_shr(vd*COS - vq*SIN + V_H*C, 15)``,
   ``v_beta = round_shr(vd*SIN + vq*COS + V_H*S, 15)`` (``C = S = 0`` for the square wave): the rotating
   vector ``V_H (cos phi, sin phi)`` of Tap et al. 2023, eq. (9), added in the stationary frame as a third
   product of each sum (one rounding); ``C, S = sincos_q15(phi)`` of the injection phase ``phi``
   (``golden.fpga.cordic``, WIDTH 32, 16 iterations, as the firmware's sin/cos of spec 5.2), the same for
   both halves of the period;
3. inverse Clarke, ``v_a = v_alpha``, ``v_b = round_shr(-v_alpha*2^14 + v_beta*28378, 15)``,
   ``v_c = round_shr(-v_alpha*2^14 - v_beta*28378, 15)`` (28378 = round(2^15*sqrt(3)/2));
4. min-max zero sequence, ``off = shr(max + min, 1)``, ``v_x' = v_x - off``;
5. ``cmp_x = clamp(H/2 + round_shr(v_x'*H, 15), 0, H)``: duty ``cmp_x/H = 1/2 + v_x'/V_dc`` (voltages
   are s16 with 2^15 = V_dc), over-modulation clipped per leg.

Widths (the spec states only s17 and s18; these are the worst case over every register value,
SIN/COS not required to lie on the unit circle): ``vd`` s17; the Park products fit s32 (|vd| <= 65535)
and their sums s33 (square wave: |vd| <= 65535, two products; rotating: |vd| <= 32768, three products:
below 3*2^30 in magnitude either way); ``v_alpha, v_beta`` within +-98303 (s18); the Clarke sums s33; ``v_b, v_c`` within
+-101517 (s18); ``max + min`` s18; ``v_x'`` within +-87916 (s18); ``v_x'*H`` s34 (H <= 65534, u16).
Plain Python ints (no numpy): this is called twice per PWM period in the closed loop.

Direct-vector mode (``CTRL.DIRECT``, spec 3.10; the 003 method): at the carrier-top latch the state is
:func:`direct_state` (the inverse Park of step 2 without any injection term, then
``golden.fpga.fcs_mpc.choose_vector`` with the state applied until then, 0 after reset and while the mode
is off), and both that latch and the following bottom one use :func:`direct_compares` of it (no dead-time
compensation). golden/closedloop.py does so when ``HardwareConfig.direct`` is set.
"""

from __future__ import annotations

from golden.fixed import round_shr, shr

SQRT3_HALF_Q15 = 28378
"""round(2^15 * sqrt(3) / 2), the inverse Clarke coefficient (u15)."""

SIGN_BOTTOM = -1
"""Injection sign for the compares latched at the carrier bottom (rising half), eq. (14)."""
SIGN_TOP = 1
"""Injection sign for the compares latched at the carrier top (falling half), eq. (14)."""

_S16_MIN, _S16_MAX = -32768, 32767


def compares(v_d: int, v_q: int, v_h: int, sin_q15: int, cos_q15: int, half: int,
             sign: int, rot: tuple[int, int] | None = None) -> tuple[int, int, int]:
    """Compare values of legs a, b, c for one carrier half period (spec 3.5).

    Parameters
    ----------
    v_d, v_q : int
        ``V_D``, ``V_Q`` registers, s16, 2^15 = V_dc.
    v_h : int
        Injection amplitude, u15 (0..32767), same scale: the ``V_H`` register (a 15-bit field), or 0
        while ``CTRL.INJ_EN`` is clear (the register map's injection enable; spec 3.5 does not name it).
    sin_q15, cos_q15 : int
        ``SIN``, ``COS`` registers of the estimated angle, s16 Q1.15.
    half : int
        Effective carrier half period ``H`` [ticks], even, 4..65534.
    sign : int
        Injection sign: -1 for the compares latched at the carrier bottom (rising half), +1 at the
        top (falling half); Benevieri et al. 2023, eq. (14).
    rot : tuple of int, optional
        ``(C, S)``, s16 Q1.15: cosine and sine of the rotating injection's phase (``CTRL.INJ_ROT = 1``):
        ``V_H`` is then the amplitude of the rotating vector instead of the square wave's. ``None``:
        the square wave.

    Returns
    -------
    tuple of int
        ``(cmp_a, cmp_b, cmp_c)`` in ``0..H`` ticks: the high switch of leg x conducts ``cmp_x`` ticks
        of the half period (spec 2.4).

    Raises
    ------
    ValueError
        If an argument is not an integer of its register range, ``half`` is odd or outside 4..65534,
        or ``sign`` is not -1 or +1.
    """
    if rot is not None:
        c_r, s_r = rot
        if not (type(c_r) is int and type(s_r) is int and _S16_MIN <= c_r <= _S16_MAX
                and _S16_MIN <= s_r <= _S16_MAX):
            c_r, s_r = (_validate_int(name, value, _S16_MIN, _S16_MAX)
                        for name, value in (("injection cos", c_r), ("injection sin", s_r)))
    # Fast path check: Python ints of the right ranges (numpy ints and bad values take the slow path).
    if not (type(v_d) is int and type(v_q) is int and type(v_h) is int and type(sin_q15) is int
            and type(cos_q15) is int and type(half) is int and type(sign) is int
            and _S16_MIN <= v_d <= _S16_MAX and _S16_MIN <= v_q <= _S16_MAX and 0 <= v_h <= _S16_MAX
            and _S16_MIN <= sin_q15 <= _S16_MAX and _S16_MIN <= cos_q15 <= _S16_MAX
            and 4 <= half <= 65534 and not half & 1 and (sign == 1 or sign == -1)):
        v_d, v_q, v_h, sin_q15, cos_q15, half, sign = _validate(v_d, v_q, v_h, sin_q15, cos_q15,
                                                                half, sign)
    vq = v_q
    if rot is None:
        # Injection on the estimated d-axis, eq. (14): s17.
        vd = v_d + sign * v_h
        # Inverse Park: s17 x s16 products (fit s32), sums s33, results s18.
        v_al = round_shr(vd * cos_q15 - vq * sin_q15, 15)
        v_be = round_shr(vd * sin_q15 + vq * cos_q15, 15)
    else:
        # Inverse Park plus the rotating vector V_H (C, S) (Tap et al. 2023, eq. (9)): sums s33.
        vd = v_d
        v_al = round_shr(vd * cos_q15 - vq * sin_q15 + v_h * c_r, 15)
        v_be = round_shr(vd * sin_q15 + vq * cos_q15 + v_h * s_r, 15)
    # Inverse Clarke: v_a = v_alpha, v_b/c = -v_alpha/2 +- sqrt(3)/2 v_beta (sums s33, results s18).
    a_part = -v_al * 16384
    b_part = v_be * SQRT3_HALF_Q15
    v_a = v_al
    v_b = round_shr(a_part + b_part, 15)
    v_c = round_shr(a_part - b_part, 15)
    # Min-max zero sequence.
    if v_a > v_b:
        if v_b > v_c:
            hi, lo = v_a, v_c
        else:
            hi, lo = (v_a if v_a > v_c else v_c), v_b
    elif v_a > v_c:
        hi, lo = v_b, v_c
    else:
        hi, lo = (v_b if v_b > v_c else v_c), v_a
    off = shr(hi + lo, 1)
    # Compares: H/2 + v'*H/2^15, clipped to 0..H per leg.
    mid = half >> 1
    cmp_a = mid + round_shr((v_a - off) * half, 15)
    cmp_b = mid + round_shr((v_b - off) * half, 15)
    cmp_c = mid + round_shr((v_c - off) * half, 15)
    return (0 if cmp_a < 0 else (half if cmp_a > half else cmp_a),
            0 if cmp_b < 0 else (half if cmp_b > half else cmp_b),
            0 if cmp_c < 0 else (half if cmp_c > half else cmp_c))


def _validate_int(name, value, lo, hi) -> int:
    """An integer (Python or numpy) within ``lo..hi`` as a Python int, or a ValueError that says why."""
    if isinstance(value, bool) or not hasattr(value, "__index__"):
        raise ValueError(f"{name} must be an integer, got {value!r}")
    value = value.__index__()
    if not lo <= value <= hi:
        raise ValueError(f"{name} = {value} is outside {lo}..{hi}")
    return value


def _validate(v_d, v_q, v_h, sin_q15, cos_q15, half, sign):
    """Slow path of :func:`compares`: explain what is wrong, or convert numpy integers to ints."""
    out = [_validate_int(name, value, lo, hi)
           for name, value, lo, hi in (("V_D", v_d, _S16_MIN, _S16_MAX), ("V_Q", v_q, _S16_MIN, _S16_MAX),
                                       ("V_H", v_h, 0, _S16_MAX), ("SIN", sin_q15, _S16_MIN, _S16_MAX),
                                       ("COS", cos_q15, _S16_MIN, _S16_MAX), ("half period", half, 4, 65534),
                                       ("sign", sign, -1, 1))]
    if out[5] & 1:
        raise ValueError(f"half period {out[5]} must be even (use carrier.effective_half())")
    if out[6] == 0:
        raise ValueError("sign must be -1 (carrier bottom, rising half) or +1 (carrier top, falling half)")
    return tuple(out)


# ---------------------------------------------------------------- direct-vector mode (CTRL.DIRECT)

def direct_alpha_beta(v_d: int, v_q: int, sin_q15: int, cos_q15: int) -> tuple[int, int]:
    """``(v_alpha, v_beta)`` of the direct-vector mode (spec 3.10): the inverse Park of step 2 above
    without any injection term (``V_H``, the period square wave and the rotating injection are ignored),
    ``round_shr(V_D*COS - V_Q*SIN, 15)``, ``round_shr(V_D*SIN + V_Q*COS, 15)``; s18."""
    for name, value in (("V_D", v_d), ("V_Q", v_q), ("SIN", sin_q15), ("COS", cos_q15)):
        _validate_int(name, value, _S16_MIN, _S16_MAX)
    return (round_shr(v_d * cos_q15 - v_q * sin_q15, 15), round_shr(v_d * sin_q15 + v_q * cos_q15, 15))


def direct_state(v_d: int, v_q: int, sin_q15: int, cos_q15: int, a1: int, a2: int, phi_min: int,
                 constrain: bool, state_now: int) -> int:
    """The inverter state (3 bits, bit 0 = phase a) that the carrier-top latch of the direct-vector mode
    chooses (spec 3.10): :func:`golden.fpga.fcs_mpc.choose_vector` on :func:`direct_alpha_beta` of the
    active registers, ``A1, A2, PHI_MIN, CONSTRAIN`` from ``FCS_A, FCS_CTRL``; ``state_now`` is the state
    applied until this latch (0 after reset and while the mode is off). The following bottom latch
    reuses it."""
    from golden.fpga.fcs_mpc import choose_vector
    v_al, v_be = direct_alpha_beta(v_d, v_q, sin_q15, cos_q15)
    return choose_vector(v_al, v_be, sin_q15, cos_q15, a1, a2, phi_min, constrain, state_now)[0]


def direct_compares(state: int, half: int) -> tuple[int, int, int]:
    """Compares of the direct-vector mode (spec 3.10): ``cmp_x = H`` if bit x of ``state`` is set (bit 0
    = phase a), else 0, for both halves of the period; no dead-time compensation."""
    state = _validate_int("state", state, 0, 7)
    half = _validate_int("half period", half, 4, 65534)
    return tuple(half if (state >> x) & 1 else 0 for x in range(3))
