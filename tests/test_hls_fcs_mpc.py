"""HLS FCS-MPC kernel (hls/src/hfi_fcs_mpc.cpp) against golden/fpga/fcs_mpc.py choose_vector and
golden/fpga/modulator.py direct_state / direct_compares (C simulation; docs/spec.md 3.10).

* ``hfi_fcs_choose`` on 100 000 random vectors: v_alpha, v_beta over s18 (full range, the modulator's
  +-98303, small), SIN/COS full s16 or on the unit circle, A1/A2 full s16, typical Q12 or extremes,
  PHI_MIN over u16 (and 0, 65535, near typical strengths), CONSTRAIN and the state now at random;
  coverage of every state, the zero vectors 000/111, the constraint dropped and the zero vector excluded
  by it is required;
* directed: every sector on a fine angle sweep, exact d ties (zero vs active, active vs active),
  d_1 - d_0 = +-1, the zero vector by each state now, the constraint on/off/dropped, extremes;
* ``hfi_modulator_direct`` (the carrier-top latch: inverse Park without injection, the choice, the
  compares H/0) on 100 000 random register sets in sequence, the state carried from latch to latch.
Seed: ``HFI_SEED`` if set, else a fresh one, printed.
"""

from __future__ import annotations

import math
import os

import numpy as np

from golden.fixed import round_shr
from golden.fpga.fcs_mpc import VX, VY, choose_vector
from golden.fpga.modulator import direct_compares, direct_state
from hfi.hls_build import csim

N_RANDOM = 100_000
ffi, lib = csim()


def _seed() -> int:
    seed = int(os.environ.get("HFI_SEED", np.random.SeedSequence().entropy % (1 << 32)))
    print(f"HFI_SEED={seed}")
    return seed


def ptr(ctype: str, arr: np.ndarray):
    return ffi.cast(ctype, ffi.from_buffer(arr))


def _s16(g, n):
    kind = g.integers(0, 4, n)
    return np.where(kind == 0, g.integers(-32768, 32768, n),
                    np.where(kind == 1, g.integers(-8192, 8193, n),
                             np.where(kind == 2, g.choice(np.array([-32768, 32767, 0, 4096, -4096]), n),
                                      g.integers(-600, 601, n))))


def draw(g, n) -> dict[str, np.ndarray]:
    kind = g.integers(0, 4, n)
    ang = g.random(n) * 2 * math.pi
    s = np.where(kind == 0, g.integers(-32768, 32768, n), np.round(32767 * np.sin(ang)).astype(np.int64))
    c = np.where(kind == 0, g.integers(-32768, 32768, n), np.round(32767 * np.cos(ang)).astype(np.int64))
    def s18(k):
        kk = g.integers(0, 4, k)
        return np.where(kk == 0, g.integers(-(1 << 17), 1 << 17, k),
                        np.where(kk == 1, g.integers(-98303, 98304, k),
                                 np.where(kk == 2, g.integers(-30000, 30001, k), g.integers(-12000, 12001, k))))
    pk = g.integers(0, 5, n)
    phi = np.where(pk == 0, g.integers(0, 65536, n), np.where(pk == 1, g.integers(0, 4096, n),
                   np.where(pk == 2, g.integers(0, 30000, n), np.where(pk == 3, 0, 65535))))
    return {"v_al": s18(n), "v_be": s18(n), "sin": s, "cos": c, "a1": _s16(g, n), "a2": _s16(g, n),
            "phi": phi, "con": g.integers(0, 2, n), "now": g.integers(0, 8, n)}


def hls_choose(r) -> np.ndarray:
    n = r["v_al"].size
    i32 = {k: np.ascontiguousarray(r[k], dtype=np.int32) for k in ("v_al", "v_be")}
    i16 = {k: np.ascontiguousarray(r[k], dtype=np.int16) for k in ("sin", "cos", "a1", "a2")}
    phi = np.ascontiguousarray(r["phi"], dtype=np.uint16)
    u8 = {k: np.ascontiguousarray(r[k], dtype=np.uint8) for k in ("con", "now")}
    out = np.zeros(n, dtype=np.uint8)
    lib.csim_fcs_choose(n, ptr("int32_t *", i32["v_al"]), ptr("int32_t *", i32["v_be"]),
                        ptr("int16_t *", i16["sin"]), ptr("int16_t *", i16["cos"]), ptr("int16_t *", i16["a1"]),
                        ptr("int16_t *", i16["a2"]), ptr("uint16_t *", phi), ptr("uint8_t *", u8["con"]),
                        ptr("uint8_t *", u8["now"]), ptr("uint8_t *", out))
    return out


def check_choose(r, label):
    got = hls_choose(r)
    cov = dict.fromkeys(("s0", "s7", "dropped", "zero_excluded", "differs"), 0)
    seen = set()
    for i in range(got.size):
        args = tuple(int(r[k][i]) for k in ("v_al", "v_be", "sin", "cos", "a1", "a2", "phi"))
        con, now = bool(r["con"][i]), int(r["now"][i])
        want = choose_vector(*args, con, now)[0]
        assert int(got[i]) == want, f"{label} {i}: HLS {int(got[i])} golden {want}; {args} con={con} now={now}"
        seen.add(want)
        cov["s0"] += want == 0
        cov["s7"] += want == 7
        if con:
            free = choose_vector(*args, False, now)[0]
            cov["differs"] += free != want
            cov["zero_excluded"] += free in (0, 7) and want not in (0, 7)
            c_, s_ = args[3], args[2]
            p = [round_shr(args[4] * round_shr(y * c_ - x * s_, 15) - args[5] * round_shr(x * c_ + y * s_, 15), 12)
                 for x, y in zip(VX, VY)]
            cov["dropped"] += not any(abs(pj) > args[6] for pj in p)
    return cov, seen


def test_choose_random():
    g = np.random.default_rng([_seed(), 31])
    cov, seen = check_choose(draw(g, N_RANDOM), "random")
    print(cov)
    assert seen == set(range(8)), seen
    assert all(v > 0 for v in cov.values()), cov


def _vec(v_al, v_be, s=0, c=-32768, a1=0, a2=0, phi=0, con=0, now=0):
    return dict(v_al=v_al, v_be=v_be, sin=s, cos=c, a1=a1, a2=a2, phi=phi, con=con, now=now)


def test_choose_directed():
    vecs = []
    for mag in (10000, 10922, 10923, 11000, 15000, 30000, 98303, 131071):
        for tenth in range(0, 3600, 25):
            a = math.radians(tenth / 10 + 0.05)
            for now in (0, 3, 7):
                vecs.append(_vec(round(mag * math.cos(a)), round(mag * math.sin(a)), now=now))
    for al, be in ((14921, 3998), (0, 20000), (0, -20000), (11022, 6364), (21746, 12555), (-11022, -6364),
                   (-21746, -12555), (-131072, -131072), (131071, 131071), (-131072, 131071), (0, 0)):
        for d in ((0, 0), (1, 0), (-1, 0), (0, 1), (0, -1)):
            for now in range(8):
                vecs.append(_vec(al + d[0] if abs(al + d[0]) < 131072 else al, be + d[1] if abs(be + d[1]) < 131072 else be, now=now))
    for a1, a2 in ((4096, 0), (0, 4096), (3000, -2000), (32767, -32768), (-32768, 32767), (0, 0), (-32768, -32768)):
        for phi in (0, 1, 5000, 10000, 20000, 65535):
            for con in (0, 1):
                for s, c in ((12000, 30000), (-32768, -32768), (32767, 0), (0, 32767), (-20000, 25000)):
                    vecs.append(_vec(3000, 2000, s, c, a1, a2, phi, con, 3))
                    vecs.append(_vec(0, 0, s, c, a1, a2, phi, con, 5))
                    vecs.append(_vec(-98303, 98303, s, c, a1, a2, phi, con, 1))
    r = {k: np.array([v[k] for v in vecs]) for k in vecs[0]}
    cov, seen = check_choose(r, "directed")
    print(cov)
    assert seen == set(range(8)), seen
    assert all(v > 0 for v in cov.values()), cov


def test_modulator_direct_sequence():
    """hfi_modulator_direct on random register sets in sequence against golden direct_state /
    direct_compares, the state carried (from a non-zero initial state)."""
    g = np.random.default_rng([_seed(), 37])
    n = N_RANDOM
    r = draw(g, n)
    v_d, v_q = _s16(g, n), _s16(g, n)
    half = 2 * g.integers(2, 32768, n)
    arr16 = {k: np.ascontiguousarray(v, dtype=np.int16)
             for k, v in (("v_d", v_d), ("v_q", v_q), ("sin", r["sin"]), ("cos", r["cos"]), ("a1", r["a1"]),
                          ("a2", r["a2"]))}
    phi = np.ascontiguousarray(r["phi"], dtype=np.uint16)
    con = np.ascontiguousarray(r["con"], dtype=np.uint8)
    h = np.ascontiguousarray(half, dtype=np.uint16)
    states = np.zeros(n, dtype=np.uint8)
    cmps = np.zeros(3 * n, dtype=np.uint16)
    lib.csim_modulator_direct(n, ptr("int16_t *", arr16["v_d"]), ptr("int16_t *", arr16["v_q"]),
                              ptr("int16_t *", arr16["sin"]), ptr("int16_t *", arr16["cos"]),
                              ptr("int16_t *", arr16["a1"]), ptr("int16_t *", arr16["a2"]), ptr("uint16_t *", phi),
                              ptr("uint8_t *", con), ptr("uint16_t *", h), 6, ptr("uint8_t *", states),
                              ptr("uint16_t *", cmps))
    cmps = cmps.reshape(n, 3)
    state = 6
    for i in range(n):
        state = direct_state(int(v_d[i]), int(v_q[i]), int(r["sin"][i]), int(r["cos"][i]), int(r["a1"][i]),
                             int(r["a2"][i]), int(r["phi"][i]), bool(r["con"][i]), state)
        assert int(states[i]) == state, f"latch {i}: HLS state {int(states[i])} golden {state}"
        assert tuple(int(x) for x in cmps[i]) == direct_compares(state, int(half[i])), f"latch {i}: compares"
