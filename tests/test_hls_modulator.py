"""HLS modulator kernel (hls/src/hfi_modulator.cpp) against golden/fpga/modulator.py compares (C simulation).

The vectors of cocotb_tests/tb_modulator.py (golden/testvectors/modulator.py): 100 000 random register
sets and the directed corner vectors, each at the top (sign +1) and the bottom (sign -1), in the mode
each vector says (``rot``: the rotating injection, ``compares(..., rot=(inj_cos, inj_sin))``; else the
square wave, ``rot=None``, whose kernel call still gets the vector's inj_sin/inj_cos, to be ignored).
As in the RTL test, the compare chain of the closed loop (hfi_modulator, then hfi_deadtime_comp when
DTC_GAIN != 0) is also compared with golden compares + compensate.

The rotating injection (spec 3.5) also on its own: 100 000 more random register sets, every one rotating,
with (C, S) half the CORDIC's sincos_q15 of a random phase (what the closed loop feeds), half any s16 pair
with its extremes, and about 3 % built to tie in the min-max; the corners are every corner vector crossed
with the extreme (C, S) pairs, the register corners at the smallest H (4, 6) and full-scale Park sums
(three products at full scale: the width bound 3*2^30 of the golden docstring).
Seed: ``HFI_SEED`` if set, else a fresh one, printed.
"""

from __future__ import annotations

import numpy as np

from golden.fpga.cordic import sincos_q15
from golden.fpga.deadtime_comp import compensate, recip_half
from golden.fpga.modulator import compares
from golden.testvectors.modulator import REGS, as_dicts, corner_vectors, draw_registers, rot_arg, v_abc
from hfi.hls_build import csim

N_RANDOM = 100_000
CS_EXTREMES = ((-32768, -32768), (32767, 32767), (-32768, 32767), (32767, -32768), (0, -32768), (-32768, 0),
               (0, 32767), (32767, 0))
"""(C, S) pairs of the rotating corner vectors."""

ffi, lib = csim()


def ptr(ctype: str, arr: np.ndarray):
    return ffi.cast(ctype, ffi.from_buffer(arr))


def hls_compares(r: dict[str, np.ndarray], top: bool) -> np.ndarray:
    """hfi_modulator on every vector: (n, 3) compares, in the mode of r["rot"]."""
    n = r["v_d"].size
    a = {k: np.ascontiguousarray(r[k], dtype=np.int16)
         for k in ("v_d", "v_q", "v_h", "inj_sin", "inj_cos", "sin_q15", "cos_q15")}
    half = np.ascontiguousarray(r["half"], dtype=np.uint16)
    topv = np.full(n, int(top), dtype=np.uint8)
    rotv = np.ascontiguousarray(r["rot"], dtype=np.uint8)
    out = np.zeros(3 * n, dtype=np.uint16)
    lib.csim_modulator(n, ptr("int16_t *", a["v_d"]), ptr("int16_t *", a["v_q"]), ptr("int16_t *", a["v_h"]),
                       ptr("uint8_t *", rotv), ptr("int16_t *", a["inj_sin"]), ptr("int16_t *", a["inj_cos"]),
                       ptr("int16_t *", a["sin_q15"]), ptr("int16_t *", a["cos_q15"]),
                       ptr("uint16_t *", half), ptr("uint8_t *", topv), ptr("uint16_t *", out))
    return out.reshape(n, 3)


def hls_compensate(r: dict[str, np.ndarray], cmps: np.ndarray, top: bool) -> np.ndarray:
    """hfi_deadtime_comp on the compares of every vector: (n, 3)."""
    n = cmps.shape[0]
    u16 = {k: np.ascontiguousarray(r[k], dtype=np.uint16) for k in ("half", "dead", "dtc_gain", "hf_amp")}
    s16 = {k: np.ascontiguousarray(r[k], dtype=np.int16) for k in ("i_d_ref", "i_q_ref", "sin_q15", "cos_q15")}
    recip = np.ascontiguousarray(r["recip_h"], dtype=np.uint32)
    cin = np.ascontiguousarray(cmps, dtype=np.uint16).ravel()
    topv = np.full(n, int(top), dtype=np.uint8)
    out = np.zeros(3 * n, dtype=np.uint16)
    lib.csim_deadtime_comp(n, ptr("uint16_t *", cin), ptr("uint8_t *", topv), ptr("uint16_t *", u16["half"]),
                           ptr("uint16_t *", u16["dead"]), ptr("uint16_t *", u16["dtc_gain"]),
                           ptr("int16_t *", s16["i_d_ref"]), ptr("int16_t *", s16["i_q_ref"]),
                           ptr("uint16_t *", u16["hf_amp"]), ptr("int16_t *", s16["sin_q15"]),
                           ptr("int16_t *", s16["cos_q15"]), ptr("uint32_t *", recip), ptr("uint16_t *", out))
    return out.reshape(n, 3)


def check(r: dict[str, np.ndarray], label: str) -> None:
    """Kernel and compare chain against golden compares (``rot=(C, S)`` where r["rot"], else ``None``) and
    compensate, at both signs."""
    vecs = as_dicts(r)
    for top, sign in ((True, 1), (False, -1)):
        got = hls_compares(r, top)
        want = np.array([compares(v["v_d"], v["v_q"], v["v_h"], v["sin_q15"], v["cos_q15"], v["half"], sign,
                                  rot_arg(v))
                         for v in vecs], dtype=np.int64)
        bad = np.flatnonzero((got != want).any(axis=1))
        assert bad.size == 0, f"{label} {bad[0]} sign {sign}: HLS {got[bad[0]]}, golden {want[bad[0]]}: {vecs[bad[0]]}"
        chain = np.where((r["dtc_gain"] != 0)[:, None], hls_compensate(r, got, top), got)
        want_chain = np.array([compensate(w, sign, v["half"], v["dead"], v["dtc_gain"], v["i_d_ref"], v["i_q_ref"],
                                          v["hf_amp"], v["sin_q15"], v["cos_q15"], v["recip_h"])
                               if v["dtc_gain"] else w for v, w in zip(vecs, want.tolist())], dtype=np.int64)
        bad = np.flatnonzero((chain != want_chain).any(axis=1))
        assert bad.size == 0, (f"{label} {bad[0]} chain sign {sign}: HLS {chain[bad[0]]}, golden "
                               f"{want_chain[bad[0]]}: {vecs[bad[0]]}")


def as_arrays(vecs: list[dict]) -> dict[str, np.ndarray]:
    return {k: np.array([v[k] for v in vecs], dtype=np.int64) for k in REGS}


def _mix(rng, n, lo, hi, extremes, p_ext):
    """Uniform in lo..hi, a fraction p_ext replaced by one of the extremes."""
    x = rng.integers(lo, hi, size=n, endpoint=True, dtype=np.int64)
    m = rng.random(n) < p_ext
    x[m] = rng.choice(np.asarray(extremes, dtype=np.int64), size=int(m.sum()))
    return x


def draw_rotation(rng, n: int) -> dict[str, np.ndarray]:
    """Every vector rotating, (C, S): half sincos_q15 of a random u32 phase (the closed loop's values), half
    any s16 pair (extremes and powers of two, for the rounding ties, 30 %)."""
    s, c = sincos_q15(rng.integers(0, 1 << 32, n, dtype=np.int64))
    ext = [-32768, -32767, -16384, -8192, -1, 0, 1, 8192, 16384, 32767]
    cordic = rng.random(n) < 0.5
    return {"rot": np.ones(n, dtype=np.int64),
            "inj_cos": np.where(cordic, c, _mix(rng, n, -32768, 32767, ext, 0.3)),
            "inj_sin": np.where(cordic, s, _mix(rng, n, -32768, 32767, ext, 0.3))}


def inject_rot_ties(rng, r: dict[str, np.ndarray], frac: float) -> None:
    """Replace a fraction of the vectors by rotating ones whose v_a, v_b, v_c tie (v_abc: a replica of
    compares' first steps, only to find them)."""
    n = r["v_d"].size
    idx = np.flatnonzero(rng.random(n) < frac)
    if idx.size == 0:
        return
    m = 40 * idx.size + 1000
    cand = {"v_d": rng.integers(-300, 300, m, endpoint=True), "v_q": rng.integers(-300, 300, m, endpoint=True),
            "v_h": rng.integers(0, 300, m, endpoint=True)}
    for name in ("sin_q15", "cos_q15", "inj_cos", "inj_sin"):
        cand[name] = rng.integers(-32768, 32767, m, endpoint=True)
    kind = rng.integers(0, 4, m)
    for name in ("v_q", "sin_q15", "inj_sin"):                       # v_beta = 0: b = c
        cand[name] = np.where(kind == 0, 0, cand[name])
    for name in ("v_d", "v_q", "v_h"):                                 # all zero: a = b = c
        cand[name] = np.where(kind == 1, 0, cand[name])
    a, b, c = v_abc(cand["v_d"], cand["v_q"], cand["v_h"], cand["sin_q15"], cand["cos_q15"], 1, 1,
                    cand["inj_sin"], cand["inj_cos"])
    good = np.flatnonzero((a == b) | (a == c) | (b == c))
    pick = good[rng.integers(0, good.size, idx.size)]
    for name in cand:
        r[name][idx] = cand[name][pick]
    r["rot"][idx] = 1


def rot_corner_vectors() -> list[dict]:
    """Every corner vector with every extreme (C, S); the register corners (no compensation) at the
    smallest H (4, 6); full-scale Park sums (three products at full scale) at H 4, 512 and 65534."""
    corners = corner_vectors()
    out = [v | dict(rot=1, inj_cos=c, inj_sin=s) for v in corners for c, s in CS_EXTREMES]
    out += [v | dict(rot=1, half=h, recip_h=recip_half(h), dtc_gain=0, inj_cos=c, inj_sin=s)
            for v in corners[:96] for h in (4, 6) for c, s in CS_EXTREMES[:4]]
    base = corners[0]
    for half in (4, 512, 65534):
        for sgn in (1, -1):       # each Park sum sgn*(3*2^30 - small): all three products at full scale
            big = dict(v_d=-32768 if sgn > 0 else 32767, v_q=-32768 if sgn > 0 else 32767, v_h=32767,
                       sin_q15=32767 if sgn > 0 else -32768, cos_q15=-32768 if sgn > 0 else 32767,
                       inj_cos=32767 if sgn > 0 else -32768, inj_sin=-32768 if sgn > 0 else 32767)
            out.append(base | big | dict(rot=1, half=half, recip_h=recip_half(half)))
    return out


def test_random(seed):
    """The shared random vectors (both modes), in the mode each one says."""
    r = draw_registers(np.random.default_rng(seed), N_RANDOM)
    assert 0 < r["rot"].sum() < N_RANDOM
    check(r, "random vector")


def test_corner_vectors():
    check(as_arrays(corner_vectors()), "corner vector")


def test_random_rotating(seed):
    rng = np.random.default_rng([seed, 2])
    r = draw_registers(rng, N_RANDOM)
    r.update(draw_rotation(rng, N_RANDOM))
    inject_rot_ties(rng, r, frac=0.03)
    check(r, "random rotating vector")


def test_corner_vectors_rotating():
    vecs = rot_corner_vectors()
    r = as_arrays(vecs)
    park = (r["v_d"] * r["cos_q15"] - r["v_q"] * r["sin_q15"] + r["v_h"] * r["inj_cos"],
            r["v_d"] * r["sin_q15"] + r["v_q"] * r["cos_q15"] + r["v_h"] * r["inj_sin"])
    # the corners reach the extremes of the Park sums over every register value
    assert max(p.max() for p in park) == 3 * 2**30 - 2**16 + 1    # v_beta: 2^30 + 2^30 + 32767^2
    assert min(p.min() for p in park) == -3 * 2**30 + 2**16       # v_alpha: -(2^30 - 2^15) - 2^30 - (2^30 - 2^15)
    check(r, "rotating corner vector")
