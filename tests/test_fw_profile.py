"""The firmware profile of the rtl co-simulation (sim/soc_sim.h ``SOC_PROF_*``, scripts/fw_profile.py).

The profiled build must not change what the SoC does (its run equals the golden model's, window by
window), its instruction-bus counts must be whole cache lines of the firmware's code, and the script must
attribute the step's clocks to the firmware's functions.
"""

from __future__ import annotations

import dataclasses
import importlib.util
from pathlib import Path

import numpy as np
import pytest

from golden.closedloop import WINDOW_FIELDS, ClosedLoop
from golden.scenario import load_scenario
from hfi import soc_platform
from hfi.rtl_backend import FW_OUT, RtlBackendError, RtlClosedLoop, build_sim

pytestmark = pytest.mark.xdist_group("fw_profile")
"""The module's tests share a module fixture: one worker runs them all (make test: --dist loadgroup)."""

ROOT = Path(__file__).resolve().parents[1]
LINE_WORDS = 8


@pytest.fixture(scope="module")
def profiled():
    sc = dataclasses.replace(load_scenario(ROOT / "scenarios" / "fullload_start.toml"), duration=0.004)
    loop = RtlClosedLoop(sc)
    res = loop.run(progress=False, profile=True)
    return sc, loop, res


def test_profiled_run_equals_golden(profiled):
    sc, _, res = profiled
    gold = ClosedLoop(sc).run(progress=False)
    for k in WINDOW_FIELDS:
        assert np.array_equal(gold.windows[k], res.windows[k]), k


def test_fetches_are_whole_lines_of_code(profiled):
    _, loop, _ = profiled
    fetch = loop.profile["fetch"]
    assert len(fetch) == soc_platform.RAM_BYTES // 4
    lines = fetch.reshape(-1, LINE_WORDS)
    assert (lines == lines[:, :1]).all(), "a refill that is not a whole 8-word line"
    code_end = (FW_OUT / "hfi_fw.bin").stat().st_size // 4
    assert fetch.sum() > 0 and fetch[-(-code_end // LINE_WORDS) * LINE_WORDS:].sum() == 0


def _script():
    spec = importlib.util.spec_from_file_location("fw_profile", ROOT / "scripts" / "fw_profile.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def test_step_clocks_land_in_the_step(profiled):
    _, loop, res = profiled
    funcs = {name: (a // 4, b // 4) for a, b, name in _script().functions(str(FW_OUT / "hfi_fw.elf"))}
    cycles = loop.profile["cycles"]
    a, b = funcs["fw_step"]
    assert cycles[a:b].sum() > 0
    assert cycles.sum() <= res.soc["sim_cycles"] // soc_platform.CPU_CLOCK_DIVIDER


def test_script_prints_the_table(profiled, capsys):
    _, _, res = profiled
    assert _script().main(["--duration", "0.004", "--top", "2"]) == 0
    out = capsys.readouterr().out.splitlines()
    assert out[0].startswith(f"scenario fullload_start: {len(res.t)} periods;")
    code, data = out[:6], out[6:]
    assert {code[2].split()[0], code[3].split()[0]} <= {"fw_step", "irq_handler", "fw_window_voltage"}
    assert code[4].startswith("(the step)") and "100.0%" in code[4]
    assert code[5].startswith("start-up, idle loop, log")
    # the data cache's refills by object: at most --top rows between the header lines and the total
    assert data[0].startswith(f"data cache ({soc_platform.CPU_DCACHE_BYTES} bytes") and data[-1].startswith("(all)") and len(data) <= 2 + 2 + 1


LISTING = """\
00006700 <fw_step>:
fw_step():
/src/control.c:2051
    6700:\t000087b7          \tlui\ta5,0x8
/src/control.c:80 (discriminator 1)
    6704:\t00052803          \tlw\ta6,0(a0)
    6708:\tf5010113          \tadd\tsp,sp,-176
/src/control.c:2051
    670c:\tfff78793          \tadd\ta5,a5,-1 # 7fff <fw_window_voltage+0x33f>
"""


def test_clocks_by_source_line():
    """Each instruction counts to the location printed last before it (a discriminator is the same line);
    per line the clocks are summed and divided by the periods, largest first."""
    fp = _script()
    table = fp.parse_line_table(LISTING)
    assert table == {0x6700: ("/src/control.c", 2051), 0x6704: ("/src/control.c", 80),
                     0x6708: ("/src/control.c", 80), 0x670C: ("/src/control.c", 2051)}
    base = 0x6700
    cycles = np.array([4, 30, 6, 2])
    assert fp.line_clocks(table, cycles, base, 2) == [("/src/control.c", 80, 18.0, 2), ("/src/control.c", 2051, 3.0, 2)]


def test_script_splits_a_function_by_line(capsys):
    assert _script().main(["--duration", "0.002", "--top", "40", "--lines", "fw_step"]) == 0
    out = capsys.readouterr().out.splitlines()
    head = next(i for i, t in enumerate(out) if t.startswith("fw_step: "))
    assert out[head + 1].split() == ["clocks/period", "insns", "line"]
    rows = out[head + 2:]
    assert len(rows) == 40 and all(r.split()[2].split(":")[1].isdigit() for r in rows)   # file:line
    clocks = [float(r.split()[0]) for r in rows]
    assert clocks == sorted(clocks, reverse=True)
    # an inlined helper's statement counts to the helper's own line: the output history's record copy
    # (push_outputs, inlined into fw_step), among the largest
    text = "\n".join(rows)
    assert "st->hist[at == 0 ? 2 : at - 1] = *out;" in text
    assert _script().main(["--duration", "0.002", "--lines", "no_such_function"]) == 1
    assert "no function no_such_function" in capsys.readouterr().err


def test_bad_arguments_are_refused(capsys):
    assert _script().main(["--duration", "0"]) == 1
    assert "--duration and --f-sw must be > 0" in capsys.readouterr().err
    assert _script().main(["--f-sw=-5e3"]) == 1
    assert "--duration and --f-sw must be > 0" in capsys.readouterr().err
    assert _script().main(["--scenario", "no_such_scenario.toml"]) == 1
    assert "no_such_scenario.toml" in capsys.readouterr().err


def test_waveform_and_profile_together_are_refused():
    with pytest.raises(RtlBackendError, match="separate builds"):
        build_sim(fst=True, profile=True)
