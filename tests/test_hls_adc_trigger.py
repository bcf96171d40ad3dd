"""HLS ADC trigger kernels (hls/src/hfi_adc_trigger.cpp) against golden/fpga/adc_trigger.py (C simulation).

* effective_os_ticks: every u16 register value for several OS_MIN (golden os_min_ticks of CORDIC
  iterations and ADC cycles);
* hfi_adc_trigger over every phase of a period equals golden sample_phases, for random (mode, H,
  OS_TICKS, OS_MIN) drawn as in cocotb_tests/tb_adc_trigger.py (golden/testvectors/adc_trigger.py) and
  directed extremes (full-scale H, OS_MIN above the period, DS);
* hfi_blank_tick per tick from reset equals golden blank_mask with the switching instants of golden
  GateGenerator runs (take_switch_ticks) and of random event pulses; hfi_blanked on random distances.
Seed: ``HFI_SEED`` if set, else a fresh one, printed.
"""

from __future__ import annotations

import numpy as np
import pytest

from golden.fpga.adc_trigger import (MODE_DS, MODE_OS, blank_mask, effective_os_ticks, os_min_ticks,
                                     sample_phases)
from golden.fpga.carrier import effective_half
from golden.testvectors import gate_gen as gate_vectors
from golden.testvectors.adc_trigger import (OS_MIN_SWEEP, random_blank, random_half_reg, random_os,
                                            random_switch_pulses)
from hfi.hls_build import csim

N_PARAM_SETS = 3000
"""Random (mode, H, OS_TICKS, OS_MIN) sets, each checked over a whole period (about 3.5 M phases)."""
N_BLANKED = 100_000

ffi, lib = csim()


def ptr(ctype: str, arr: np.ndarray):
    return ffi.cast(ctype, ffi.from_buffer(arr))


def hls_phases(mode: int, h: int, os_reg: int, os_min: int) -> np.ndarray:
    hit = np.zeros(2 * h, dtype=np.uint8)
    lib.csim_adc_trigger_period(mode, h, os_reg, os_min, ptr("uint8_t *", hit))
    return np.flatnonzero(hit)


@pytest.mark.parametrize("iterations, adc_cycle", [(32, 0), (1, 0), (32, 38), (24, 100), (1, 65535)])
def test_effective_os_every_register(iterations, adc_cycle):
    os_min = os_min_ticks(iterations, adc_cycle)
    regs = np.arange(1 << 16, dtype=np.uint16)
    mins = np.full(regs.size, os_min, dtype=np.uint16)
    out = np.zeros_like(regs)
    lib.csim_adc_trigger_effective_os(regs.size, ptr("uint16_t *", regs), ptr("uint16_t *", mins),
                                      ptr("uint16_t *", out))
    want = np.array([effective_os_ticks(int(r), iterations, adc_cycle) for r in regs], dtype=np.uint16)
    np.testing.assert_array_equal(out, want)


def check_period(mode: int, h: int, os_reg: int, os_min: int) -> int:
    want = sample_phases(mode, h, max(os_reg, os_min), os_min)
    got = hls_phases(mode, h, os_reg, os_min)
    np.testing.assert_array_equal(got, want, err_msg=f"mode={mode} H={h} OS_TICKS={os_reg} OS_MIN={os_min}")
    return 2 * h


def test_trigger_random(seed):
    rng = np.random.default_rng(seed)
    phases = 0
    for _ in range(N_PARAM_SETS):
        r = rng.random()
        os_min = int(rng.choice(OS_MIN_SWEEP)) if r < 0.7 else int(rng.integers(1, 200))
        h = effective_half(random_half_reg(rng))
        os_reg = random_os(rng, os_min, h) if r < 0.95 else int(rng.integers(0, 65536))
        phases += check_period(int(rng.integers(0, 4)), h, os_reg, os_min)
    print(f"{N_PARAM_SETS} parameter sets, {phases} phases")


@pytest.mark.parametrize("mode, h, os_reg, os_min", [
    (MODE_OS, 65534, 0, 40), (MODE_OS, 65534, 65535, 40), (MODE_OS, 65534, 1, 1), (2, 65534, 131, 7),
    (MODE_DS, 65534, 0, 40), (MODE_DS, 512, 7, 7), (3, 10000, 100, 40), (2, 10000, 100, 40),
    (MODE_OS, 512, 0, 1024), (MODE_OS, 512, 5, 65535), (MODE_OS, 512, 1023, 2), (MODE_OS, 512, 1022, 2),
    (MODE_OS, 512, 1, 1), (3, 512, 65535, 1)])
def test_trigger_directed(mode, h, os_reg, os_min):
    check_period(mode, h, os_reg, os_min)


def blank_case(switch_ticks: np.ndarray, n: int, blank: int) -> None:
    sw = np.zeros(n, dtype=np.uint8)
    sw[switch_ticks] = 1
    blank_t = np.full(n, blank, dtype=np.uint16)
    dropped = np.zeros(n, dtype=np.uint8)
    lib.csim_adc_trigger_blank_run(n, ptr("uint8_t *", sw), ptr("uint16_t *", blank_t), ptr("uint8_t *", dropped))
    want = blank_mask(np.arange(n, dtype=np.int64), switch_ticks, blank)
    bad = np.flatnonzero(dropped.astype(bool) != want)
    assert bad.size == 0, f"BLANK_TICKS={blank}: tick {bad[0]} HLS {dropped[bad[0]]}, golden {want[bad[0]]}"


def test_blank_tick_gate_generator_runs(seed):
    """Switching instants of golden GateGenerator runs (the gate generator's test vectors)."""
    rng = np.random.default_rng(seed + 1)
    ticks = 0
    while ticks < 300_000:
        h_reg = gate_vectors.random_half_reg(rng)
        dead_reg = gate_vectors.random_dead_reg(rng, h_reg, 50)
        run = gate_vectors.plan_run(rng, h_reg, dead_reg, 50, int(rng.integers(6, 40)), 0.25, 0.1, 0.0,
                                    gate_vectors.new_stats())
        sw = gate_vectors.golden_edges(run, 50)[2]
        blank_case(sw, run.end, random_blank(rng, run.h))
        ticks += run.end
    print(f"{ticks} ticks")


def test_blank_tick_event_pulses(seed):
    """Random event pulses of 1..3 ticks (as cocotb_tests/tb_adc_trigger.py), BLANK_TICKS 0..65535."""
    rng = np.random.default_rng(seed + 2)
    ticks = 0
    for k in range(60):
        h = effective_half(random_half_reg(rng))
        n = int(rng.integers(2, 30)) * 2 * h
        sw = np.array([t + i for t, m in random_switch_pulses(rng, h, n) for i in range(m)], dtype=np.int64)
        blank_case(sw, n, random_blank(rng, h) if k > 2 else (0, 1, 65535)[k])
        ticks += n
    print(f"{ticks} ticks")


def test_blanked_random(seed):
    rng = np.random.default_rng(seed + 3)
    blanks = np.concatenate([[0, 1, 2, 65535], rng.integers(0, 65536, 196)]).astype(np.uint16)
    per = N_BLANKED // blanks.size
    for blank in blanks:
        since = np.concatenate([rng.integers(0, 2 * int(blank) + 2, per - 6),
                                [0, max(int(blank) - 1, 0), int(blank), int(blank) + 1, 1 << 40, (1 << 62) - 1]])
        since = since.astype(np.uint64)
        b = np.full(since.size, blank, dtype=np.uint16)
        out = np.zeros(since.size, dtype=np.uint8)
        lib.csim_adc_trigger_blanked(since.size, ptr("uint64_t *", since), ptr("uint16_t *", b), ptr("uint8_t *", out))
        want = blank_mask(since.astype(np.int64), [0], int(blank))
        np.testing.assert_array_equal(out.astype(bool), want, err_msg=f"BLANK_TICKS={blank}")
