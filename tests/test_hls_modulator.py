"""HLS modulator kernel (hls/src/hfi_modulator.cpp) against golden/fpga/modulator.py compares (C simulation).

The vectors are those of cocotb_tests/tb_modulator.py (golden/testvectors/modulator.py): 100 000 random
register sets and the directed corner vectors, each at the top (sign +1) and the bottom (sign -1). As in
the RTL test, the compare chain of the closed loop (hfi_modulator, then hfi_deadtime_comp when
DTC_GAIN != 0) is also compared with golden compares + compensate.
Seed: ``HFI_SEED`` if set, else a fresh one, printed.
"""

from __future__ import annotations

import numpy as np

from golden.fpga.deadtime_comp import compensate
from golden.fpga.modulator import compares
from golden.testvectors.modulator import REGS, corner_vectors, draw_registers
from hfi.hls_build import csim

N_RANDOM = 100_000

ffi, lib = csim()


def ptr(ctype: str, arr: np.ndarray):
    return ffi.cast(ctype, ffi.from_buffer(arr))


def hls_compares(r: dict[str, np.ndarray], top: bool) -> np.ndarray:
    """hfi_modulator on every vector: (n, 3) compares."""
    n = r["v_d"].size
    a = {k: np.ascontiguousarray(r[k], dtype=np.int16) for k in ("v_d", "v_q", "v_h", "sin_q15", "cos_q15")}
    half = np.ascontiguousarray(r["half"], dtype=np.uint16)
    topv = np.full(n, int(top), dtype=np.uint8)
    out = np.zeros(3 * n, dtype=np.uint16)
    lib.csim_modulator(n, *(ptr("int16_t *", a[k]) for k in ("v_d", "v_q", "v_h", "sin_q15", "cos_q15")),
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
    cols = [r[k].tolist() for k in REGS]
    vecs = [dict(zip(REGS, v)) for v in zip(*cols)]
    for top, sign in ((True, 1), (False, -1)):
        got = hls_compares(r, top)
        want = np.array([compares(v["v_d"], v["v_q"], v["v_h"], v["sin_q15"], v["cos_q15"], v["half"], sign)
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


def test_random(seed):
    check(draw_registers(np.random.default_rng(seed), N_RANDOM), "random vector")


def test_corner_vectors():
    vecs = corner_vectors()
    check({k: np.array([v[k] for v in vecs], dtype=np.int64) for k in REGS}, "corner vector")
