"""Test vectors of the modulator (golden/fpga/modulator.py) and of its compare chain with the dead-time
compensation, shared by cocotb_tests/tb_modulator.py and tests/test_hls_modulator.py.

:func:`draw_registers` covers the full ranges of the modulator's registers with their extremes, typical
small values, unit-circle SIN/COS, powers of two for SIN/COS and H (exact half-LSB ties of the rounding
shifts), DTC_GAIN = 0 for half the vectors, RECIP_H = round(2^32/H) mostly and any u32 sometimes, and
about 3 % vectors built to tie in the min-max (v_a = v_b, v_a = v_c, v_b = v_c, all three), and the
rotating injection (``rot = 1``, ``CTRL.INJ_ROT``) in 30 % of the vectors with ``inj_sin, inj_cos`` drawn
as SIN/COS. :func:`rot_arg` turns a vector into ``compares``' ``rot`` argument.
:func:`corner_vectors` lists the register extremes, over-modulation, min-max ties and DTC extremes.
"""

from __future__ import annotations

import numpy as np

from golden.fixed import round_shr
from golden.fpga.deadtime_comp import recip_half
from golden.fpga.modulator import SQRT3_HALF_Q15

REGS = ("v_d", "v_q", "v_h", "sin_q15", "cos_q15", "i_d_ref", "i_q_ref", "half", "dead", "dtc_gain",
        "hf_amp", "recip_h", "rot", "inj_sin", "inj_cos")
"""Register names of one vector (the hfi_modulator ports)."""
U32 = (1 << 32) - 1


def _mix(rng, n, lo, hi, extremes, p_ext=0.15):
    """Uniform in lo..hi, a fraction p_ext replaced by one of the extremes."""
    x = rng.integers(lo, hi, size=n, endpoint=True, dtype=np.int64)
    m = rng.random(n) < p_ext
    x[m] = rng.choice(np.asarray(extremes, dtype=np.int64), size=int(m.sum()))
    return x


def _logu(rng, n, hi):
    """Log-uniform integers in 1..hi (small values as often as large ones)."""
    return np.clip(np.exp(rng.uniform(0.0, np.log(hi + 1.0), n)).astype(np.int64), 1, hi)


def _where(rng, n, p, a, b):
    return np.where(rng.random(n) < p, a, b)


def draw_registers(rng, n: int) -> dict[str, np.ndarray]:
    """Random register values (int64 arrays) over the full ranges of the modulator's inputs."""
    s16x = [-32768, -32767, -1, 0, 1, 32767]
    r = {}
    for name in ("v_d", "v_q"):
        small = _logu(rng, n, 32767) * rng.choice([-1, 1], n)
        r[name] = _where(rng, n, 0.3, small, _mix(rng, n, -32768, 32767, s16x))
    r["v_h"] = _where(rng, n, 0.3, _logu(rng, n, 32767) - 1, _mix(rng, n, 0, 32767, [0, 1, 32767]))
    theta = rng.uniform(0.0, 2.0 * np.pi, n)
    unit_s = np.clip(np.round(32768.0 * np.sin(theta)), -32768, 32767).astype(np.int64)
    unit_c = np.clip(np.round(32768.0 * np.cos(theta)), -32768, 32767).astype(np.int64)
    unit = rng.random(n) < 0.4
    # powers of two make round_shr(., 15) ties (x + 2^14 = k*2^15) frequent, so every rounding
    # constant is checked at its boundary
    sc_ext = [-32768, -32767, -16384, -8192, -1, 0, 1, 8192, 16384, 32767]
    r["sin_q15"] = np.where(unit, unit_s, _mix(rng, n, -32768, 32767, sc_ext, 0.3))
    r["cos_q15"] = np.where(unit, unit_c, _mix(rng, n, -32768, 32767, sc_ext, 0.3))
    r["rot"] = (rng.random(n) < 0.3).astype(np.int64)
    phi = rng.uniform(0.0, 2.0 * np.pi, n)
    unit = rng.random(n) < 0.5
    r["inj_sin"] = np.where(unit, np.clip(np.round(32768.0 * np.sin(phi)), -32768, 32767).astype(np.int64),
                            _mix(rng, n, -32768, 32767, sc_ext, 0.3))
    r["inj_cos"] = np.where(unit, np.clip(np.round(32768.0 * np.cos(phi)), -32768, 32767).astype(np.int64),
                            _mix(rng, n, -32768, 32767, sc_ext, 0.3))
    for name in ("i_d_ref", "i_q_ref"):
        small = (_logu(rng, n, 32768) - 1) * rng.choice([-1, 1], n)
        r[name] = _where(rng, n, 0.4, small, _mix(rng, n, -32768, 32767, s16x))
    r["half"] = 2 * _mix(rng, n, 256, 32767, [256, 257, 4096, 8192, 32767], 0.2)   # H = 2^13, 2^14: ties
    r["dead"] = _where(rng, n, 0.5, _logu(rng, n, 65535), _mix(rng, n, 1, 65535, [1, 2, 65535], 0.2))
    gain = _where(rng, n, 0.5, _logu(rng, n, 65535), _mix(rng, n, 1, 65535, [1, 256, 65535], 0.2))
    r["dtc_gain"] = np.where(rng.random(n) < 0.5, 0, gain)
    r["hf_amp"] = _where(rng, n, 0.3, _logu(rng, n, 32768) - 1, _mix(rng, n, 0, 32767, [0, 1, 32767]))
    nominal = ((1 << 33) // r["half"] + 1) // 2                    # recip_half, vectorised
    any_u32 = _mix(rng, n, 0, U32, [0, 1, 1 << 31, U32], 0.2)
    r["recip_h"] = np.where(rng.random(n) < 0.8, nominal, any_u32)
    _inject_ties(rng, r, frac=0.03)
    return r


def rot_arg(r: dict) -> tuple[int, int] | None:
    """``compares``' ``rot`` argument of one vector: ``(inj_cos, inj_sin)`` if ``rot`` else ``None``."""
    return (r["inj_cos"], r["inj_sin"]) if r["rot"] else None


def v_abc(v_d, v_q, v_h, s, c, sign, rot=0, inj_s=0, inj_c=0):
    """Phase voltages v_a, v_b, v_c before the min-max (a replica of compares' first steps, int64
    arrays; used only to build tie vectors and to measure coverage, never as expected values)."""
    vd = v_d + sign * v_h * (1 - rot)
    vr = v_h * rot
    al = round_shr(vd * c - v_q * s + vr * inj_c, 15)
    be = round_shr(vd * s + v_q * c + vr * inj_s, 15)
    bp = be * SQRT3_HALF_Q15
    return al, round_shr(-al * 16384 + bp, 15), round_shr(-al * 16384 - bp, 15)


def _inject_ties(rng, r, frac):
    """Replace a fraction of the vectors by ones whose v_a, v_b, v_c tie (for either sign)."""
    n = len(r["v_d"])
    idx = np.flatnonzero(rng.random(n) < frac)
    if idx.size == 0:
        return
    # candidates: small vectors, where exact ties of the rounded phase voltages are common
    m = 40 * idx.size + 1000
    cand = {"v_d": rng.integers(-300, 300, m, endpoint=True), "v_q": rng.integers(-300, 300, m, endpoint=True),
            "v_h": rng.integers(0, 200, m, endpoint=True),
            "sin_q15": rng.integers(-32768, 32767, m, endpoint=True),
            "cos_q15": rng.integers(-32768, 32767, m, endpoint=True)}
    kind = rng.integers(0, 4, m)
    z = np.zeros(m, dtype=np.int64)
    cand["v_q"] = np.where(kind == 0, z, cand["v_q"])                 # v_q = SIN = 0 -> v_beta = 0: b = c
    cand["sin_q15"] = np.where(kind == 0, z, cand["sin_q15"])
    for name in ("v_d", "v_q", "v_h"):                                 # all zero: a = b = c
        cand[name] = np.where(kind == 1, z, cand[name])
    tie = np.zeros(m, dtype=bool)
    for sign in (1, -1):
        a, b, c = v_abc(cand["v_d"], cand["v_q"], cand["v_h"], cand["sin_q15"], cand["cos_q15"], sign)
        tie |= (a == b) | (a == c) | (b == c)
    good = np.flatnonzero(tie)
    pick = good[rng.integers(0, good.size, idx.size)]
    for name in cand:
        r[name][idx] = cand[name][pick]
    r["rot"][idx] = 0                                                  # the ties are square-wave vectors


def as_dicts(r: dict[str, np.ndarray]) -> list[dict]:
    cols = [r[k].tolist() for k in REGS]
    return [dict(zip(REGS, vals)) for vals in zip(*cols)]


def corner_vectors() -> list[dict]:
    """Extremes of every register (full-scale voltages, sin/cos -32768, H 512 and 65534, D 1 and
    65535, DTC_GAIN 0 / 1 / 65535, RECIP_H nominal / 0 / 2^32-1, HF_AMP 0 / 32767), and ties."""
    out = []
    base = dict(v_d=0, v_q=0, v_h=0, sin_q15=0, cos_q15=32767, i_d_ref=0, i_q_ref=0, half=10000,
                dead=400, dtc_gain=0, hf_amp=0, recip_h=recip_half(10000), rot=0, inj_sin=0, inj_cos=0)
    vs = (-32768, 32767)
    for v_d in vs:
        for v_q in vs:
            for v_h in (0, 32767):
                for s, c in ((-32768, -32768), (32767, -32768), (-32768, 32767), (32767, 32767),
                             (0, -32768), (-32768, 0)):
                    for half in (512, 65534):
                        out.append(base | dict(v_d=v_d, v_q=v_q, v_h=v_h, sin_q15=s, cos_q15=c, half=half,
                                               recip_h=recip_half(half)))
    dtc = []
    for r in out[::3]:
        for gain, dead, hf, rh, idr, iqr in ((65535, 65535, 32767, U32, -32768, -32768),
                                              (65535, 1, 32767, U32, 32767, 32767),
                                              (1, 65535, 32767, 0, -32768, 32767),
                                              (256, 400, 32767, None, 0, 0),
                                              (65535, 65535, 0, 1, 32767, -32768),
                                              (1, 1, 32767, 1 << 31, -32768, -32768)):
            dtc.append(r | dict(dtc_gain=gain, dead=dead, hf_amp=hf, i_d_ref=idr, i_q_ref=iqr,
                                recip_h=recip_half(r["half"]) if rh is None else rh))
    ties = [base | dict(v_d=0, v_q=0, v_h=0),                                  # a = b = c = 0
            base | dict(v_d=1000, v_q=0, v_h=500, sin_q15=0, cos_q15=32767),  # v_beta = 0: b = c
            base | dict(v_d=-32768, v_q=0, v_h=32767, sin_q15=0, cos_q15=-32768, half=65534,
                        recip_h=recip_half(65534)),
            base | dict(v_d=123, v_q=-77, v_h=0, sin_q15=0, cos_q15=0),         # sin = cos = 0
            base | dict(v_d=32767, v_q=32767, v_h=32767, sin_q15=-32768, cos_q15=-32768,
                        dtc_gain=65535, dead=65535, hf_amp=32767, recip_h=U32)]
    # rotating injection: every register extreme with the injection's sin/cos extremes (the Park sums'
    # bound 3*2^30 - 2^15 is reached with all three products at full scale)
    rot = [r | dict(rot=1, inj_sin=s, inj_cos=c) for r in out[::4]
           for s, c in ((-32768, -32768), (32767, 32767), (-32768, 32767), (0, 0))]
    return out + dtc + ties + rot
