"""The ``hfi`` command (hfi/cli.py): help, check, methods, run, and its one-line errors."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest

from hfi import cli
from hfi.cli import BENCH_SCRIPTS, main
from hfi.machine_speed import REFERENCE_PLANT_X

ROOT = Path(__file__).resolve().parents[1]
HFI = Path(sys.executable).parent / "hfi"
BAD_SCENARIO = '[scenario]\nname = "x"\nduration = "1 ms"\n[pwm]\ndead_time = "150 us"\n'

METRICS_KEYS = {"scenario", "backend", "duration_s", "windows", "samples", "final_mode", "run_from_s",
                "polarity_flipped", "angle_error_after_start", "angle_error_at_bottom", "locked", "segments",
                "estimator_switches", "estimator_switch_events", "faults", "dc_link", "late_commits", "wall_s",
                "realtime_factor"}
"""The keys of a golden-backend metrics.json, as docs/metrics.md lists them."""


def hfi(*args: str, timeout: float = 120) -> subprocess.CompletedProcess:
    """The installed console script, as a user runs it."""
    return subprocess.run([str(HFI), *args], capture_output=True, text=True, timeout=timeout, cwd=ROOT)


def short_default_scenario(tmp_path: Path, duration: str = "50 ms") -> Path:
    text = (ROOT / "scenarios" / "fullload_start.toml").read_text()
    assert 'duration = "2.4 s"' in text
    path = tmp_path / "short.toml"
    path.write_text(text.replace('duration = "2.4 s"', f'duration = "{duration}"'))
    return path


def test_console_script_help_lists_every_command():
    proc = hfi("--help")
    assert proc.returncode == 0, proc.stderr
    for command in ("run", "check", "methods", "paper", "bench", "sweep"):
        assert f"    {command} " in proc.stdout


@pytest.mark.parametrize("command, words", [
    ("run", ("--backend", "golden", "rtl", "hls", "$BACKEND", "--fst-window", "--every-block", "docs/metrics.md")),
    ("check", ("exit status 1",)),
    ("methods", ("golden.firmware.estimator.METHODS",)),
    ("paper", ("--short", "--only", "fig6_7", "table3")),
    ("bench", ("scripts/bench_plant.py", "scripts/bench_hls.py")),
])
def test_subcommand_help(capsys, command, words):
    with pytest.raises(SystemExit) as exc:
        main([command, "--help"])
    assert exc.value.code == 0
    out = " ".join(capsys.readouterr().out.split())
    for word in words:
        assert word in out


def test_check_valid_file(capsys):
    assert main(["check", "scenarios/openloop_injection.toml"]) == 0
    out = capsys.readouterr().out.splitlines()
    assert out == ["scenarios/openloop_injection.toml: ok (openloop_injection: 50 ms, motor benevieri2023_table1 "
                   "(dsat), torque load (0 points), f_sw 5 kHz, dead time 4 us, V_h 100 V; open-loop study)"]


def test_check_bad_and_missing_files(tmp_path):
    bad = tmp_path / "bad.toml"
    bad.write_text(BAD_SCENARIO)
    proc = hfi("check", "scenarios/openloop_injection.toml", str(bad), str(tmp_path / "missing.toml"))
    assert proc.returncode == 1
    assert proc.stdout.splitlines() == [proc.stdout.splitlines()[0]]
    assert proc.stdout.startswith("scenarios/openloop_injection.toml: ok (")
    err = proc.stderr.splitlines()
    assert len(err) == 2, proc.stderr
    assert err[0].startswith(f"{bad}: pwm.dead_time: 150 us must be shorter than half the PWM period")
    assert err[1] == f"{tmp_path / 'missing.toml'}: No such file or directory"


def test_methods_lists_every_estimator_with_the_backends(capsys):
    assert main(["methods"]) == 0
    lines = capsys.readouterr().out.splitlines()
    assert [line.split(":")[0] for line in lines] == ["sqw_bangbang", "rfo", "rot_bpf", "eemf_smo", "sqw_cic",
                                                      "hfo_proj"]
    assert lines[0].startswith("sqw_bangbang: Benevieri et al., IEEE TPEL 2023 (002); slots low; "
                               "injection square wave on d_hat at f_sw; ")
    assert lines[1].startswith("rfo: Ortega et al. 2011")
    assert "; slots high; injection none; " in lines[1]
    assert lines[2].startswith("rot_bpf: Tap et al., IEEE Access 2023 (000); slots low; injection vector rotating")
    assert lines[3].startswith("eemf_smo: Tap et al.") and "; slots high; injection none; " in lines[3]
    assert lines[4].startswith("sqw_cic: Xue et al., Electronics 2022 (001); slots low; injection square wave on "
                               "d_hat at f_sw/2")
    assert lines[5].startswith("hfo_proj: Varatharajan et al., IEEE Access 2020 (003); slots low; injection none")
    assert all(line.endswith("; backends golden, rtl, hls") for line in lines)


def _restrict(monkeypatch, name: str, backends: tuple[str, ...]) -> None:
    """METHODS[name] runs on ``backends`` only (every method runs on every backend today; the refusal
    of hfi/backends.py stays tested with a restricted MethodInfo)."""
    import dataclasses

    from golden.firmware.estimator import METHODS

    monkeypatch.setitem(METHODS, name, dataclasses.replace(METHODS[name], backends=backends))


def test_no_method_is_restricted_to_some_backends():
    from golden.firmware.estimator import METHODS
    from hfi.backends import NAMES

    assert all(m.backends == NAMES for m in METHODS.values())


def test_a_method_is_refused_on_a_backend_without_it(capsys, monkeypatch):
    """hfi/backends.py refuses a scenario whose estimator does not run on the backend, before building
    or running anything; the CLI turns it into one line and exit status 1; `hfi methods` lists the
    backends it has."""
    from golden.scenario import load_scenario
    from hfi.backends import BackendError, get

    _restrict(monkeypatch, "sqw_cic", ("golden",))
    sc = load_scenario(ROOT / "scenarios" / "xue2022_noload.toml")
    for backend in ("hls", "rtl"):
        with pytest.raises(BackendError, match=f"estimator sqw_cic runs on the golden backend\\(s\\) only, "
                                               f"not on {backend}"):
            get(backend).run(sc, progress=False)
    assert main(["run", str(ROOT / "scenarios" / "xue2022_noload.toml"), "--backend", "hls", "--quiet"]) == 1
    err = capsys.readouterr().err
    assert "estimator sqw_cic runs on the golden backend(s) only, not on hls" in err
    assert main(["methods"]) == 0
    assert capsys.readouterr().out.splitlines()[4].endswith("; backends golden")
    _restrict(monkeypatch, "rfo", ("golden", "hls"))       # a high-speed slot's method, two backends
    sc = load_scenario(ROOT / "scenarios" / "handover_short.toml")
    with pytest.raises(BackendError, match="estimator rfo runs on the golden, hls backend\\(s\\) only, not on rtl"):
        get("rtl").run(sc, progress=False)


def test_run_golden_writes_the_documented_outputs(tmp_path):
    scen = short_default_scenario(tmp_path)
    out = tmp_path / "out"
    proc = hfi("run", str(scen), "--backend", "golden", "--out", str(out), "--quiet")
    assert proc.returncode == 0, proc.stderr
    m = json.loads((out / "metrics.json").read_text())
    assert set(m) == METRICS_KEYS
    assert m["backend"] == "golden" and m["scenario"] == "fullload_start"
    assert m["windows"] == 249                  # (0.05 s * 100 MHz - H/2) // P, H = 10000 ticks, P = 2H
    assert m["samples"] == 249 * 200            # one ADC sample per us
    assert m["final_mode"] == "CONVERGE"        # the polarity test starts after 60 ms
    assert m["segments"] == []                  # no settled part: RUN never reached
    assert m["estimator_switches"] == 0 and m["estimator_switch_events"] == []
    assert m["faults"] == {"code": "none", "at_s": None, "injected": []}
    for name in ("trace.npz", "closed_loop.png", "angles.png", "phase_current.png"):
        assert (out / name).stat().st_size > 1000
    assert proc.stdout.splitlines()[-1] == "wrote " + ", ".join(
        str(out / f) for f in ("trace.npz", "metrics.json", "closed_loop.png", "angles.png", "phase_current.png"))


@pytest.mark.parametrize("args, message", [
    (["--backend", "nope"], "hfi run: unknown backend 'nope' (valid: golden, rtl, hls)"),
    (["--backend", "golden", "--fst", "x.fst"], "hfi run: an FST waveform needs the rtl backend (not golden)"),
    (["--backend", "hls", "--every-block"], "hfi run: --every-block chooses the rtl backend's FPGA build (not hls's)"),
])
def test_run_bad_options_one_line(tmp_path, args, message):
    proc = hfi("run", str(short_default_scenario(tmp_path)), "--out", str(tmp_path / "out"), *args)
    assert proc.returncode == 1
    assert proc.stderr == message + "\n"
    assert not (tmp_path / "out").exists()


def test_run_bad_backend_from_environment(tmp_path, monkeypatch, capsys):
    monkeypatch.setenv("BACKEND", "vhdl")
    assert main(["run", str(short_default_scenario(tmp_path)), "--out", str(tmp_path / "out")]) == 1
    assert capsys.readouterr().err == "hfi run: unknown backend 'vhdl' (valid: golden, rtl, hls)\n"


def test_run_bad_scenario_and_missing_file(tmp_path):
    bad = tmp_path / "bad.toml"
    bad.write_text(BAD_SCENARIO)
    proc = hfi("run", str(bad), "--backend", "golden")
    assert proc.returncode == 1
    assert len(proc.stderr.splitlines()) == 1 and "Traceback" not in proc.stderr
    assert proc.stderr.startswith(f"hfi run: {bad}: pwm.dead_time: 150 us must be shorter")
    proc = hfi("run", str(tmp_path / "missing.toml"), "--backend", "golden")
    assert proc.returncode == 1
    assert proc.stderr == f"hfi run: {tmp_path / 'missing.toml'}: No such file or directory\n"


def test_usage_errors_are_one_line_exit_1():
    proc = hfi("frobnicate")
    assert proc.returncode == 1
    assert proc.stderr.startswith("hfi: argument COMMAND: invalid choice: 'frobnicate'")
    assert proc.stderr.endswith("(see hfi --help)\n") and len(proc.stderr.splitlines()) == 1
    proc = hfi("paper", "--only", "fig99")
    assert proc.returncode == 1
    assert proc.stderr.startswith("hfi paper: unknown group(s) fig99 (known: fig6_7, ")


@pytest.mark.parametrize("argv, words", [
    (["faults", "--only", ","], "hfi faults: --only ',' names nothing (leave the option out for all)"),
    (["paper", "--only", " , "], "hfi paper: --only ' , ' names nothing"),
    (["compare", "--systems", ""], "hfi compare: --systems '' names nothing"),
    (["run", "scenarios/fullload_start.toml", "--backend", ""], "hfi run: unknown backend '' (valid: golden, rtl, hls)"),
    (["run", "scenarios/fullload_start.toml", "--backend", "rtl", "--fst", "w.fst", "--fst-window", "3", "inf"],
     "hfi run: FST window 3.0 .. inf s: it must start within the run's 0 .. 2.4 s"),
])
def test_arguments_that_name_nothing_or_no_process_are_refused(argv, words, capsys):
    """Found by probing the command (2026-11-30): an empty selection ran everything or nothing, --backend "" the
    default backend, and an infinite FST window raised an OverflowError after the build. Each is one line now,
    before anything runs."""
    assert cli.main(argv) == 1
    err = capsys.readouterr().err
    assert err.startswith(words) and err.count("\n") == 1, err


@pytest.mark.parametrize("argv, words", [
    (["faults", "--jobs", "0"], "argument --jobs: '0': expected an integer >= 1"),
    (["paper", "--jobs", "-2"], "argument --jobs: '-2': expected an integer >= 1"),
    (["compare", "--systems", "002", "--workers", "-1"], "argument --workers: '-1': expected an integer >= 1"),
    (["compare", "--systems", "002", "--workers", "0"], "argument --workers: '0': expected an integer >= 1"),
    (["compare", "--seeds", "0"], "argument --seeds: '0': expected an integer >= 1"),
    (["sweep", "spec.toml", "--workers", "0"], "argument --workers: '0': expected an integer >= 1"),
])
def test_counts_below_one_are_usage_errors(argv, words, capsys):
    """A process or seed count below 1 (--workers -1 hung a cluster without workers, --jobs 0 became 1): a usage
    error in one line, exit status 1, from the one type the scripts use too (hfi.argtypes.positive_int)."""
    with pytest.raises(SystemExit) as exc:
        cli.main(argv)
    assert exc.value.code == 1
    assert capsys.readouterr().err == f"hfi {argv[0]}: {words} (see hfi {argv[0]} --help)\n"


def test_argument_types_refuse_what_no_run_can_use():
    import argparse

    from hfi.argtypes import positive_finite, positive_int
    assert positive_finite("0.25") == 0.25 and positive_int("3") == 3
    for bad, words in (("nan", "'nan': expected a finite number > 0"), ("inf", "'inf': expected a finite number > 0"),
                       ("0", "'0': expected a finite number > 0"), ("x", "'x' is not a number")):
        with pytest.raises(argparse.ArgumentTypeError, match=words):
            positive_finite(bad)
    for bad, words in (("0", "'0': expected an integer >= 1"), ("1.5", "'1.5' is not an integer")):
        with pytest.raises(argparse.ArgumentTypeError, match=words):
            positive_int(bad)


def test_a_script_reports_an_input_it_cannot_run_in_one_line(capsys):
    def refuse():
        raise ValueError("V_H = 58514286 is outside\n0..32767")
    assert cli.run_script("injection_sweep", refuse) == 2
    assert capsys.readouterr().err == "injection_sweep: V_H = 58514286 is outside 0..32767\n"
    assert cli.run_script("seed_sweep", lambda: 1) == 1


def test_bench_runs_the_four_benchmarks_of_make_bench():
    assert BENCH_SCRIPTS == ("bench_plant.py", "bench_golden.py", "bench_rtl.py", "bench_hls.py")
    assert sorted(p.name for p in (ROOT / "scripts").glob("bench_*.py")) == sorted(BENCH_SCRIPTS)
    assert set(cli.BENCH_TARGETS) == set(BENCH_SCRIPTS)


def test_bench_summary_holds_each_last_line_against_its_target(tmp_path, monkeypatch, capsys):
    """hfi bench echoes every benchmark's output and ends with each one's last value against the issue's target,
    measured and scaled to the reference machine by the plant benchmark (scripts stood in for by ones that print a
    line and a value; the plant at half the reference speed: every value doubled)."""
    values = {"bench_plant.py": REFERENCE_PLANT_X / 2, "bench_golden.py": 0.6, "bench_rtl.py": 2.0,
              "bench_hls.py": 10.0}
    (tmp_path / "scripts").mkdir()
    for name, v in values.items():
        (tmp_path / "scripts" / name).write_text(f"print('running {name}')\nprint('x_per_y: {v}')\n")
    monkeypatch.setattr(cli, "ROOT", tmp_path)
    assert cli.main(["bench"]) == 0
    out = capsys.readouterr().out
    assert "running bench_rtl.py" in out
    head, summary = out.split("== summary (issue 21's targets; ")[1].split("\n", 1)
    assert head == ("this machine 2.00 times slower than the reference by the plant benchmark: the last column "
                    "scales to it, docs/testing.md)")
    assert summary.splitlines() == [
        f"the plant alone, x real time     {REFERENCE_PLANT_X / 2:8.3f}",
        "golden backend, x real time         0.600  target >= 1: NOT met  at the reference speed    1.200: met",
        "rtl backend, M clocks/s             2.000  target >= 5: NOT met  at the reference speed    4.000: NOT met",
        "hls backend, x real time           10.000  target >= 10: met      at the reference speed   20.000: met"]
