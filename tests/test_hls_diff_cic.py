"""HLS differencing / envelope / CIC kernel (hls/src/hfi_diff_cic.cpp: hfi_diff_cic_reset, hfi_diff_cic_step)
against golden.fpga.diff_cic.DiffCic (spec 3.9; Xue et al. 2022, eqs. (7)-(8)), bit for bit, native C simulation.

The wrapper csim_diff_cic_run runs a whole step sequence from reset (with an optional reset before any
step); every output (q_a, q_b, e_a, e_b) of every step is compared with the golden DiffCic (a fresh one at
each reset) and with an independent reference written from the definition: e = i - p across a ``plus``
period once a previous sample exists, else held; q = the sum of the last M held values since the last
rate change or reset (M = CIC_M clamped to 1..16).

* random: >= 100 000 steps of s16 currents (the extremes -32768 / 32767 frequent), random ``plus``,
  CIC_M mostly 2 with runs of random register values 0..255 (0, 1, 16, 17, 255 frequent), a few resets;
* directed: the integrator at its extremes (M = 16, long runs of full-scale steps: the comb output swings
  by +-131070 and y sweeps the whole moving-sum range +-1048560 many times), rate changes 2 -> 5 -> 16 ->
  1 -> 0 -> 255 (and register changes that keep the clamped M, which do not restart), resets in the middle
  and the first sample after reset, runs of plus = 0 (e holds, q settles at M * e).

Note: in this comb-then-integrator form y is always the exact moving sum, which lies in s21, so the 21-bit
wrap of the integrator never changes a value (asserted below); the wrap is exercised only in the sense
that the kernel forms y + c in 22 bits and truncates, as golden wraps.

Random inputs use ``numpy.random.default_rng(seed)``; the seed is ``HFI_SEED`` if set, else a fresh one,
and is printed.
"""

from __future__ import annotations

import numpy as np

from golden.fpga.diff_cic import D_BITS, M_MAX, Y_BITS, DiffCic, cic_m
from hfi.hls_build import csim

N_RANDOM = 120_000
S16_MIN, S16_MAX = -(1 << 15), (1 << 15) - 1
Q_MAX = M_MAX * (S16_MAX - S16_MIN)          # largest |q|: 16 x 65535 = 1048560 < 2^20
OUT_NAMES = ("q_a", "q_b", "e_a", "e_b")

ffi, lib = csim()


def ptr(ctype: str, arr: np.ndarray):
    return ffi.cast(ctype, ffi.from_buffer(arr))


class Steps:
    """A step sequence as the arrays of csim_diff_cic_run."""

    def __init__(self):
        self.reset: list[int] = []
        self.ia: list[int] = []
        self.ib: list[int] = []
        self.plus: list[int] = []
        self.m: list[int] = []

    def add(self, ia, ib, plus, m, reset=0) -> None:
        n = len(ia)
        self.ia.extend(int(v) for v in ia)
        self.ib.extend(int(v) for v in ib)
        self.plus.extend(int(bool(v)) for v in (plus if np.ndim(plus) else [plus] * n))
        self.m.extend(int(v) for v in (m if np.ndim(m) else [m] * n))
        self.reset.extend([0] * n)
        if reset and n:
            self.reset[-n] = 1

    def __len__(self) -> int:
        return len(self.ia)


def run_hls(s: Steps, with_reset: bool = True) -> np.ndarray:
    """The kernel's outputs, shape (n, 4): q_a, q_b, e_a, e_b."""
    n = len(s)
    reset = np.array(s.reset, dtype=np.uint8)
    ia, ib = np.array(s.ia, dtype=np.int16), np.array(s.ib, dtype=np.int16)
    plus, m = np.array(s.plus, dtype=np.uint8), np.array(s.m, dtype=np.uint8)
    out = [np.zeros(n, dtype=np.int32) for _ in range(4)]
    lib.csim_diff_cic_run(n, ptr("uint8_t *", reset) if with_reset else ffi.NULL, ptr("int16_t *", ia),
                          ptr("int16_t *", ib), ptr("uint8_t *", plus), ptr("uint8_t *", m),
                          *(ptr("int32_t *", o) for o in out))
    return np.stack(out, axis=1)


def run_golden(s: Steps) -> np.ndarray:
    g = DiffCic()
    out = np.zeros((len(s), 4), dtype=np.int64)
    for k, (r, a, b, p, m) in enumerate(zip(s.reset, s.ia, s.ib, s.plus, s.m)):
        if r:
            g = DiffCic()
        out[k] = g.step(a, b, bool(p), m)
    return out


def run_reference(s: Steps) -> tuple[np.ndarray, np.ndarray]:
    """Independent of golden: (outputs (n, 4), restart flags (n,)). q is the plain sum of the last M held
    envelope values since the last rate change or reset."""
    out = np.zeros((len(s), 4), dtype=np.int64)
    restart = np.zeros(len(s), dtype=bool)
    valid, p, e, hist, m_use = False, [0, 0], [0, 0], [[], []], 0
    for k, (r, a, b, pl, reg) in enumerate(zip(s.reset, s.ia, s.ib, s.plus, s.m)):
        if r:
            valid, p, e, hist, m_use = False, [0, 0], [0, 0], [[], []], 0
        m = 1 if reg == 0 else min(reg, M_MAX)
        if m != m_use:
            m_use, hist, restart[k] = m, [[], []], True
        q = [0, 0]
        for c, i in enumerate((a, b)):
            if valid and pl:
                e[c] = i - p[c]
            p[c] = i
            hist[c].append(e[c])
            del hist[c][:-M_MAX]
            q[c] = sum(hist[c][-m:])
        valid = True
        out[k] = (q[0], q[1], e[0], e[1])
    return out, restart


def check(s: Steps, label: str, with_reset: bool = True) -> tuple[np.ndarray, np.ndarray]:
    """Kernel == golden == reference at every step; returns (outputs, restart flags)."""
    hls = run_hls(s, with_reset).astype(np.int64)
    gold = run_golden(s)
    ref, restart = run_reference(s)
    for name, want in (("golden", gold), ("reference", ref)):
        bad = np.flatnonzero(np.any(hls != want, axis=1))
        if bad.size:
            k = int(bad[0])
            lo = max(0, k - 3)
            raise AssertionError(
                f"{label}: step {k} of {len(s)} ({bad.size} steps differ): HLS {dict(zip(OUT_NAMES, hls[k].tolist()))}, "
                f"{name} {dict(zip(OUT_NAMES, want[k].tolist()))}; inputs from step {lo}: "
                f"reset {s.reset[lo:k + 1]}, i_alpha {s.ia[lo:k + 1]}, i_beta {s.ib[lo:k + 1]}, "
                f"plus {s.plus[lo:k + 1]}, CIC_M {s.m[lo:k + 1]}")
    assert np.all(np.abs(hls[:, :2]) <= Q_MAX) and np.all(np.abs(hls[:, 2:]) <= S16_MAX - S16_MIN)
    assert Q_MAX < 1 << (Y_BITS - 1) and S16_MAX - S16_MIN < 1 << (D_BITS - 1)
    return hls, restart


def random_currents(rng, n: int) -> np.ndarray:
    """s16 currents, a quarter each -32768 and 32767, the rest uniform."""
    kind = rng.integers(0, 4, n)
    return np.where(kind == 0, S16_MIN, np.where(kind == 1, S16_MAX, rng.integers(S16_MIN, S16_MAX + 1, n)))


def random_cic_m(rng) -> int:
    if rng.random() < 0.4:
        return int(rng.choice([0, 1, 2, 15, 16, 17, 255]))
    return int(rng.integers(0, 256))


def test_random(seed):
    rng = np.random.default_rng(seed)
    s = Steps()
    n_resets = 0
    while len(s) < N_RANDOM:
        n = int(rng.geometric(1 / 400))
        m = 2 if rng.random() < 0.6 else random_cic_m(rng)
        reset = rng.random() < 0.02
        n_resets += reset
        s.add(random_currents(rng, n), random_currents(rng, n), rng.random(n) < 0.5, m, reset=reset)
    out, restart = check(s, f"random (HFI_SEED={seed})")
    m = np.array(s.m)
    assert np.mean(m == 2) > 0.4 and np.mean(np.isin(m, (0, 1))) > 0 and np.mean(m > M_MAX) > 0
    print(f"{len(s)} steps, {int(restart.sum())} restarts, {n_resets} resets, max |q| {int(np.abs(out[:, :2]).max())}")


def test_random_no_reset_array(seed):
    """The wrapper with reset = NULL (a single run from reset), rate changing every few steps."""
    rng = np.random.default_rng(seed + 1)
    n = 5000
    m = np.repeat([random_cic_m(rng) for _ in range(n // 5)], 5)
    s = Steps()
    s.add(random_currents(rng, n), random_currents(rng, n), rng.random(n) < 0.5, m)
    check(s, f"random, reset NULL (HFI_SEED={seed})", with_reset=False)


def test_integrator_extremes():
    """M = 16, full-scale steps: e = +65535 held (plus on the rising steps only) for 100 steps, then
    -65535 (plus on the falling steps), and so on; then random full-scale currents. q sweeps +-1048560."""
    s = Steps()
    n_per = 100
    hi_lo = np.tile([S16_MIN, S16_MAX], n_per // 2)
    for rep in range(100):
        rising = np.tile([0, 1], n_per // 2) if rep % 2 == 0 else np.tile([1, 0], n_per // 2)
        s.add(hi_lo, hi_lo[::-1], rising, 16)
    rng = np.random.default_rng(2022)
    n = 20_000
    s.add(rng.choice([S16_MIN, S16_MAX], n), rng.choice([S16_MIN, S16_MAX], n), rng.random(n) < 0.7,
          rng.choice([16, 17, 255], n))
    out, restart = check(s, "integrator extremes")
    assert restart.sum() == 1, "16, 17 and 255 all clamp to M = 16: no restart"
    assert out[:, 0].max() == Q_MAX and out[:, 0].min() == -Q_MAX
    assert out[:, 1].max() == Q_MAX and out[:, 1].min() == -Q_MAX
    # the comb output c = e - x[15] is +-131070 in the 16 steps after each of the 99 sign flips of e
    assert np.sum(np.abs(np.diff(out[:10_000, 0])) == 2 * (S16_MAX - S16_MIN)) == 99 * M_MAX


def test_rate_changes(seed):
    rng = np.random.default_rng(seed + 2)
    s = Steps()
    seq = [2, 5, 16, 1, 0, 255, 17, 16, 3, 0, 1, 2]       # clamped: 2 5 16 1 1 16 16 16 3 1 1 2
    starts = []
    for m in seq:
        n = 40
        starts.append(len(s))
        s.add(random_currents(rng, n), random_currents(rng, n), rng.random(n) < 0.6, m)
    # a change at every step
    n = 400
    s.add(random_currents(rng, n), random_currents(rng, n), rng.random(n) < 0.6, rng.integers(0, 20, n))
    out, restart = check(s, f"rate changes (HFI_SEED={seed})")
    clamped = [cic_m(m) for m in seq]
    for j, k in enumerate(starts):
        assert restart[k] == (j == 0 or clamped[j] != clamped[j - 1]), (seq[j - 1:j + 1], k)
        if restart[k]:      # x and y cleared: the first output is the held envelope alone
            assert tuple(out[k, :2]) == tuple(out[k, 2:]), (seq[j], k)


def test_reset_in_middle(seed):
    rng = np.random.default_rng(seed + 3)
    s = Steps()
    resets = []
    for j in range(40):
        n = int(rng.integers(1, 60)) if j % 4 else 1        # consecutive resets and one-step runs too
        resets.append(len(s))
        s.add(random_currents(rng, n), random_currents(rng, n), np.ones(n) if j % 3 else rng.random(n) < 0.5,
              int(rng.choice([2, 2, 5, 16, 0])), reset=j > 0)
    out, _ = check(s, f"reset in the middle (HFI_SEED={seed})")
    for k in resets:        # the first sample after reset only fills p: e = 0, q = 0 even with plus
        assert not out[k].any(), (k, out[k])
        if k + 1 < len(s) and not s.reset[k + 1] and s.plus[k + 1]:
            assert out[k + 1, 2] == s.ia[k + 1] - s.ia[k] and out[k + 1, 3] == s.ib[k + 1] - s.ib[k]


def test_plus_zero_runs(seed):
    """Runs of plus = 0: e holds whatever the current does, and q settles at M * e after M steps."""
    rng = np.random.default_rng(seed + 4)
    s = Steps()
    runs = []
    for j in range(60):
        m = int(rng.choice([1, 2, 2, 7, 16]))
        s.add(random_currents(rng, 3), random_currents(rng, 3), 1, m)      # a fresh envelope
        runs.append((len(s), m))
        n = 40
        s.add(random_currents(rng, n), random_currents(rng, n), 0, m)
    out, _ = check(s, f"plus = 0 runs (HFI_SEED={seed})")
    for k, m in runs:
        e = out[k - 1, 2:]
        assert np.all(out[k:k + 40, 2:] == e)
        assert np.all(out[k + m - 1:k + 40, :2] == m * e)
