"""cocotb side of test_dsp_options.py: hfi_dsp built with every option in (HFI_OPTIONS_ON = 1) or out (0).

What a build option changes: with the block out its registers read 0 and its mode leaves the compares, VECTOR and
the CIC results at their idle values (asserted exactly); with it in, the mode acts (asserted as "not idle"). The
values a block computes are compared with the golden closed loop window by window, every result register and
every gate edge, by the replays of test_dsp_replay.py (rotating injection, period square wave with the CIC) on
the build with every block in; the direct-vector mode by hfi_modulator's bench (test_modulator.py, its
direct_random and direct_cases against golden direct_state / direct_compares) and the 003 drive's identity test on
the SoC (tests/test_rtl_identity.py, varatharajan2020_early_step). Each test also runs tb_hfi_dsp's window-copy check
(tb_dsp_replay.window_copy_check) over its windows, in both builds."""

from __future__ import annotations

import os

import cocotb
from cocotb.triggers import ClockCycles

from dsp_bench import start as bench_start
from golden import regmap as rm
from tb_dsp_replay import WINDOW_COPY_MASK, window_copy_check

ON = int(os.environ["HFI_OPTIONS_ON"])
H = rm.PWM_HALF_VALUE_RESET
P = 2 * H
WINDOWS = 4
"""Windows each mode runs (one commit per window) before the checks."""


def s(name: str) -> int:
    return rm.REGISTERS[name]["addr"]


async def run_windows(dut, axi, **v_dq) -> None:
    """WINDOWS windows, each with V_DQ, V_H = 8000 and a commit."""
    for _ in range(WINDOWS):
        await axi.write(s("V_DQ"), rm.pack("V_DQ", V_D=v_dq.get("V_D", 0), V_Q=v_dq.get("V_Q", 0)))
        await axi.write(s("V_H"), rm.pack("V_H", VALUE=8000))
        await axi.write(s("COMMIT"), rm.pack("COMMIT", GO=1))
        await ClockCycles(dut.clk, P)


async def start(dut):
    """dsp_bench.start with tb_hfi_dsp's window-copy check on (checked at the end of each test: check_copy)."""
    dut.win_copy_mask.value = WINDOW_COPY_MASK
    return await bench_start(dut)


def check_copy(dut) -> None:
    """No window-copy register changed within 64 clocks of a window_tog flip; one flip per window run at least."""
    window_copy_check(dut)
    assert int(dut.win_tog_flips.value) >= WINDOWS


def compares(dut) -> list[int]:
    return [int(getattr(dut.dut, f"cmp_{half}_{leg}").value) for half in ("top", "bot") for leg in "abc"]


@cocotb.test()
async def rotating_injection(dut):
    axi = await start(dut)
    caps, _ = await axi.read(s("CAPS"))
    assert rm.unpack("CAPS", caps) == {"ROT_INJ": ON, "DIFF_CIC": ON, "FCS_MPC": ON}
    await axi.write(s("INJ_STEP"), rm.pack("INJ_STEP", VALUE=1 << 29))      # an eighth of a turn per period
    await axi.write(s("CTRL"), rm.pack("CTRL", ENABLE=1, INJ_EN=1, INJ_ROT=1))
    await run_windows(dut, axi)
    cmps = compares(dut)
    if ON:
        assert any(c != H // 2 for c in cmps), f"no rotating voltage with the block in: {cmps}"
    else:
        assert cmps == [H // 2] * 6, f"a voltage without the block: {cmps}"
    check_copy(dut)


@cocotb.test()
async def period_square_wave_cic(dut):
    axi = await start(dut)
    await axi.write(s("CTRL"), rm.pack("CTRL", ENABLE=1, INJ_EN=1, INJ_PER=1))
    await run_windows(dut, axi)
    got = {name: rm.unpack(name, (await axi.read(s(name)))[0])["VALUE"]
           for name in ("CIC_QA", "CIC_QB", "ENV_A", "ENV_B")}
    if ON:
        assert any(got.values()), f"no CIC result with the block in: {got}"
    else:
        assert got == dict.fromkeys(got, 0), got
    check_copy(dut)


@cocotb.test()
async def direct_vector_mode(dut):
    axi = await start(dut)
    await axi.write(s("CTRL"), rm.pack("CTRL", ENABLE=1, DIRECT=1))
    await run_windows(dut, axi, V_D=12000)
    vector = rm.unpack("VECTOR", (await axi.read(s("VECTOR")))[0])
    cmps = compares(dut)
    if ON:
        assert vector["NEXT"] != 0 and any(cmps), f"no active vector with the block in: {vector}, {cmps}"
    else:
        assert vector == {"STATE": 0, "NEXT": 0} and cmps == [0] * 6, f"{vector}, {cmps}"
    check_copy(dut)
