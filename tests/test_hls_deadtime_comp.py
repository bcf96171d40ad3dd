"""HLS dead-time compensation kernel (hls/src/hfi_deadtime_comp.cpp) against golden/fpga/deadtime_comp.py
compensate (C simulation), on the vectors of cocotb_tests/tb_deadtime_comp.py
(golden/testvectors/deadtime_comp.py): 100 000 random compare sets, the register extremes and leg a's
predicted current around the saturation bound of the RTL (the kernel saturates i_x to s25 too).
Seed: ``HFI_SEED`` if set, else a fresh one, printed.
"""

from __future__ import annotations

import numpy as np

from golden.fpga.deadtime_comp import compensate
from golden.testvectors.deadtime_comp import HELD, SAMPLED, corner_vectors, draw, saturation_vectors
from hfi.hls_build import csim

N_RANDOM = 100_000

ffi, lib = csim()


def ptr(ctype: str, arr: np.ndarray):
    return ffi.cast(ctype, ffi.from_buffer(arr))


def golden(r: dict) -> tuple[int, int, int]:
    return compensate((r["cmp_a_in"], r["cmp_b_in"], r["cmp_c_in"]), 1 if r["sign_top"] else -1, r["half"],
                      r["dead"], r["gain"], r["i_d_ref"], r["i_q_ref"], r["hf_amp"], r["sin_q15"],
                      r["cos_q15"], r["recip_h"])


def hls(vecs: list[dict]) -> np.ndarray:
    n = len(vecs)
    col = {k: np.array([v[k] for v in vecs], dtype=np.int64) for k in HELD + SAMPLED}
    u16 = {k: col[k].astype(np.uint16) for k in ("half", "dead", "gain", "hf_amp")}
    s16 = {k: col[k].astype(np.int16) for k in ("i_d_ref", "i_q_ref", "sin_q15", "cos_q15")}
    recip = col["recip_h"].astype(np.uint32)
    top = col["sign_top"].astype(np.uint8)
    cin = np.ascontiguousarray(np.stack([col["cmp_a_in"], col["cmp_b_in"], col["cmp_c_in"]], axis=1),
                               dtype=np.uint16).ravel()
    out = np.zeros(3 * n, dtype=np.uint16)
    lib.csim_deadtime_comp(n, ptr("uint16_t *", cin), ptr("uint8_t *", top), ptr("uint16_t *", u16["half"]),
                           ptr("uint16_t *", u16["dead"]), ptr("uint16_t *", u16["gain"]),
                           ptr("int16_t *", s16["i_d_ref"]), ptr("int16_t *", s16["i_q_ref"]),
                           ptr("uint16_t *", u16["hf_amp"]), ptr("int16_t *", s16["sin_q15"]),
                           ptr("int16_t *", s16["cos_q15"]), ptr("uint32_t *", recip), ptr("uint16_t *", out))
    return out.reshape(n, 3)


def check(vecs: list[dict], label: str) -> None:
    got = hls(vecs)
    want = np.array([golden(v) for v in vecs], dtype=np.int64)
    bad = np.flatnonzero((got != want).any(axis=1))
    assert bad.size == 0, f"{label} {bad[0]}: HLS {got[bad[0]]}, golden {want[bad[0]]}: {vecs[bad[0]]}"


def test_random(seed):
    check(draw(np.random.default_rng(seed), N_RANDOM), "random vector")


def test_corner_vectors(seed):
    check(corner_vectors(np.random.default_rng(seed + 3)), "corner vector")


def test_saturation_vectors():
    check(saturation_vectors(), "saturation vector")
