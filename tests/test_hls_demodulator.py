"""HLS demodulator kernels (hls/src/hfi_demodulator.cpp: hfi_demod_clear, hfi_demod_sample,
hfi_demod_latch) against golden.fpga.demodulator.demodulate (spec 3.4), native C simulation.

Vectors: golden/testvectors/demodulator.py, the same random windows, directed event sequence and long
constant windows as the RTL testbench cocotb_tests/tb_demodulator.py. The wrapper csim_demodulator_run
runs a whole event sequence from reset (sample / latch / reset); the golden result of each latch is
``demodulate`` of the kept samples since the previous latch or reset. Random inputs use
``numpy.random.default_rng(seed)``; the seed is ``HFI_SEED`` if set, else a fresh one, and is printed.
"""

from __future__ import annotations

import numpy as np

from golden.fpga.demodulator import demodulate
from golden.testvectors import demodulator as testvectors
from hfi import hls_build

N_ACCEPTED = 100_000               # kept samples of the random windows
SAMPLE, LATCH, RESET = 0, 1, 2     # event kinds of csim_demodulator_run (hls/csim/csim_demodulator.h)
OUT_NAMES = ("gamma", "gamma_d", "sum_id", "sum_iq", "wsum", "n_samples")


class Events:
    """An event sequence as the arrays of csim_demodulator_run, with the golden result of every latch."""

    def __init__(self):
        self.kind, self.keep, self.i_d, self.i_q, self.w = [], [], [], [], []
        self.labels: list[str] = []
        self.expected: list[tuple[int, ...]] = []
        self._window: list[np.ndarray] = []          # kept (i_d, i_q, w) blocks since the last clear

    def samples(self, keep, i_d, i_q, w) -> None:
        n = len(keep)
        self.kind += [SAMPLE] * n
        for dst, src in ((self.keep, keep), (self.i_d, i_d), (self.i_q, i_q), (self.w, w)):
            dst.extend(src)
        block = np.array([i_d, i_q, w], dtype=np.int64).reshape(3, n)
        self._window.append(block[:, np.asarray(keep, dtype=bool)])

    def latch(self, label: str) -> None:
        self._marker(LATCH)
        d, q, w = np.concatenate(self._window, axis=1) if self._window else np.zeros((3, 0), dtype=np.int64)
        r = demodulate(d, q, w)
        self.expected.append((r.gamma, r.gamma_d, r.sum_id, r.sum_iq, r.wsum, r.n_samples))
        self.labels.append(label)
        self._window = []

    def reset(self) -> None:
        self._marker(RESET)
        self._window = []

    def _marker(self, kind: int) -> None:
        self.kind.append(kind)
        for dst in (self.keep, self.i_d, self.i_q, self.w):
            dst.append(0)

    def run_and_check(self, label: str) -> None:
        ffi, lib = hls_build.csim()
        kind = np.array(self.kind, dtype=np.uint8)
        keep = np.array(self.keep, dtype=np.uint8)
        d, q, w = (np.array(x, dtype=np.int16) for x in (self.i_d, self.i_q, self.w))
        out = np.zeros((max(len(self.expected), 1), 6), dtype=np.int32)
        n = lib.csim_demodulator_run(len(kind), ffi.from_buffer("uint8_t[]", kind), ffi.from_buffer("uint8_t[]", keep),
                                     ffi.from_buffer("int16_t[]", d), ffi.from_buffer("int16_t[]", q),
                                     ffi.from_buffer("int16_t[]", w), ffi.from_buffer("int32_t[]", out))
        assert n == len(self.expected), f"{label}: {n} latches, expected {len(self.expected)}"
        for j, exp in enumerate(self.expected):
            got = tuple(int(v) for v in out[j])
            assert got == exp, (f"{label}: latch {j} {self.labels[j]}: HLS {dict(zip(OUT_NAMES, got))}, "
                                f"golden {dict(zip(OUT_NAMES, exp))}")


def test_random_windows(seed):
    rng = np.random.default_rng(seed)
    windows = testvectors.random_windows(rng, N_ACCEPTED)
    ev = Events()
    for k, (keep, d, q, w) in enumerate(windows):
        ev.samples(keep, d, q, w)
        ev.latch(f"(window {k}, {len(keep)} samples)")
    ev.run_and_check(f"random (HFI_SEED={seed})")
    print(f"{len(windows)} windows, {len(ev.kind) - len(windows)} samples, "
          f"{sum(sum(win[0]) for win in windows)} kept")


def test_directed_events():
    ev = Events()
    for e in testvectors.directed_events():
        if e[0] == "sample":
            ev.samples([e[1]], [e[2]], [e[3]], [e[4]])
        elif e[0] == "latch":
            ev.latch(e[1])
        else:
            ev.reset()
    ev.run_and_check("directed")
    assert any(r[0] == (1 << 30) >> 15 for r in ev.expected), "no window of one full-scale product"


def test_long_windows():
    """Windows at the specified maximum of the largest products, blanked full-scale samples, and 70000
    samples (N_SAMPLES saturates at 65535 while the sums go on)."""
    ev = Events()
    for n, keep, i_d, i_q, w in testvectors.long_windows():
        ev.samples([keep] * n, [i_d] * n, [i_q] * n, [w] * n)
        ev.latch(f"({n} x {(i_d, i_q, w)}, keep {keep})")
    ev.run_and_check("long windows")
    assert ev.expected[-1][5] == 65535 and ev.expected[-1][2] == 3 * 70000
