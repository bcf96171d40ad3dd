"""``hfi sweep`` (hfi/sweep.py, docs/sweep.md): the spec's checks, the design's expansion, the run hash,
and a small sweep on a local Dask cluster against runs made directly on the backend."""

from __future__ import annotations

import copy
import dataclasses
import hashlib
import json
import math
from pathlib import Path

import pyarrow.parquet as pq
import pytest

from golden.scenario import parse_scenario
from golden.units import UnitError, scale_quantity, split_quantity
from hfi import sweep as sw
from hfi.backends import run
from hfi.cli import main
from hfi.crb import bound
from hfi.report import metrics_of
from hfi.ripple import audible_torque, copper_loss

ROOT = Path(__file__).resolve().parents[1]




def spec_file(tmp_path, params: str, sweep: str = "", duration: str = "30 ms"):
    text = (ROOT / "scenarios" / "fullload_start.toml").read_text()
    assert 'duration = "2.4 s"' in text
    (tmp_path / "base.toml").write_text(text.replace('duration = "2.4 s"', f'duration = "{duration}"'))
    path = tmp_path / "spec.toml"
    path.write_text(f'[sweep]\nscenario = "base.toml"\nbackend = "golden"\n{sweep}\n[params]\n{params}\n')
    return path


def test_scale_quantity_keeps_the_unit_and_scales_in_decimal():
    assert scale_quantity("1.2 N*m", 0.5) == "0.6 N*m"
    assert scale_quantity("28 V", 1.5) == "42 V"
    assert scale_quantity("-100 rpm", 2.0) == "-200 rpm"
    assert scale_quantity("5e-3 H", 1.2) == "0.006 H"
    assert scale_quantity("2 N*m", 0) == "0 N*m"
    assert scale_quantity(3, 0.5) == 1.5
    assert split_quantity("1.2 N*m") == ("1.2", "N*m")
    with pytest.raises(UnitError, match="not a quantity"):
        scale_quantity("fast", 2.0)
    with pytest.raises(UnitError, match="cannot scale a boolean"):
        scale_quantity(True, 2.0)


def test_every_problem_of_a_spec_is_listed(tmp_path):
    path = spec_file(tmp_path, '"load.torq" = [1]\n"injection.V_h" = { uniform = ["10 V", "20 V"] }\n'
                     '"pwm.f_sw" = { scale = [] }\n"control.v_max" = { double = [2] }',
                     sweep='design = "grid"\nsamples = 3\nworkers = 2\nwindows = [["2 s", "1 s"]]\nangle_at = "top"')
    with pytest.raises(sw.SweepError) as exc:
        sw.load_spec(path)
    text = str(exc.value)
    for words in ("params.'load.torq': not a scenario key", "sweep.workers: unknown key",
                  "uniform draws at random; it needs sweep.design = \"random\"", "samples: only for design",
                  "pwm.f_sw'.scale: expected a non-empty list", "unknown form 'double'",
                  "sweep.windows[0]: expected 0 <= t0 < t1", "sweep.angle_at: 'top', expected one of method, middle, bottom"):
        assert words in text, words
    path.write_text('[sweep]\nscenario = "missing.toml"\nbackend = "fpga"\n[params]\n"injection.V_h" = ["1 V"]\n')
    with pytest.raises(sw.SweepError) as exc:
        sw.load_spec(path)
    assert "sweep.backend: 'fpga' is not a backend" in str(exc.value)
    assert "sweep.scenario: cannot read" in str(exc.value)


@pytest.mark.parametrize("sweep, words", [
    ("windows = 0", "sweep.windows: expected a list of [t0, t1] pairs, got 0"),
    ("angle_at = []", "sweep.angle_at: [], expected one of method, middle, bottom"),
    ("design = {}", "sweep.design: {}, expected one of grid, random, one_at_a_time"),
    ("seeds = 1000000", "the design expands to 2 points x 1000000 seeds = 2000000 runs, more than 100000"),
    ('[set]\n"scenario.seed" = inf', "the base scenario with [set]: scenario.seed: expected an integer"),
    ('[set]\n"injection.V_h" = 1979-05-27', "set.'injection.V_h': datetime.date(1979, 5, 27) is not a scenario value"),
    ('name = "../elsewhere"', "sweep.name: '../elsewhere' must be a plain name"),
    ('name = "/tmp/x"', "sweep.name: '/tmp/x' must be a plain name"),
])
def test_a_malformed_spec_is_refused_before_it_expands(tmp_path, sweep, words):
    """Found by fuzzing the spec (2026-11-30): each of these raised a TypeError or OverflowError (a traceback from
    hfi sweep), and seeds = 10^12 filled 10 GB expanding its jobs before anything ran."""
    with pytest.raises(sw.SweepError) as exc:
        sw.load_spec(spec_file(tmp_path, '"injection.V_h" = ["20 V", "40 V"]', sweep=sweep))
    assert words in str(exc.value)


def test_values_that_no_scenario_holds_and_files_not_in_utf8_are_refused(tmp_path):
    """Found by probing the command (2026-11-30): a TOML date among an axis's values reached the run's hash (a
    TypeError), [set] into a base value that is not a table raised a TypeError, and a spec or base scenario not in
    UTF-8 gave the codec's message without the file's name."""
    with pytest.raises(sw.SweepError, match=r"params.'injection.V_h': datetime.datetime\(1979, 5, 27, 7, 32, "
                                            r"tzinfo=datetime.timezone.utc\) is not a scenario value"):
        sw.load_spec(spec_file(tmp_path, '"injection.V_h" = ["20 V", 1979-05-27T07:32:00Z]'))
    path = spec_file(tmp_path, '"injection.V_h" = ["20 V"]')
    (tmp_path / "base.toml").write_bytes(b"[scenario]\nname = \"\xe6\"\n")
    with pytest.raises(sw.SweepError, match=r"sweep.scenario: .*base.toml is not a text file in UTF-8"):
        sw.load_spec(path)
    (tmp_path / "base.toml").write_text('load = "x"\n[scenario]\nname = "b"\n')
    path = spec_file(tmp_path, '"injection.V_h" = ["20 V"]', sweep='[set]\n"load.torque" = []')
    (tmp_path / "base.toml").write_text('load = "x"\n[scenario]\nname = "b"\n')
    with pytest.raises(sw.SweepError, match="set.'load.torque': load of the base scenario is a string, not a table"):
        sw.load_spec(path)
    path.write_bytes(b"\xff\xfe[sweep]")
    with pytest.raises(sw.SweepError, match="not a text file in UTF-8"):
        sw.load_spec(path)


def test_grid_is_the_cartesian_product_and_scale_scales_the_profile(tmp_path):
    spec = sw.load_spec(spec_file(tmp_path, '"load.torque" = { scale = [0, 0.5, 1.5] }\n'
                                  '"injection.V_h" = ["20 V", "40 V"]'))
    assert spec.design == "grid" and spec.name == "spec"
    jobs = sw.jobs(spec, "v1")
    assert len(jobs) == 6 and [j.point for j in jobs] == list(range(6))
    base = spec.base["load"]["torque"]
    for j in jobs:
        (_, f), (_, v) = j.settings["load.torque"], j.settings["injection.V_h"]
        assert j.tree["injection"]["V_h"] == v
        assert [p[0] for p in j.tree["load"]["torque"]] == [p[0] for p in base]
        assert [p[1] for p in j.tree["load"]["torque"]] == [scale_quantity(p[1], f) for p in base]
        assert j.tree["scenario"] == spec.base["scenario"]       # no seeds: the scenario's own seed
    assert len({j.key for j in jobs}) == 6
    assert [j.key for j in sw.jobs(spec, "v1")] == [j.key for j in jobs]      # stable
    assert not {j.key for j in sw.jobs(spec, "v2")} & {j.key for j in jobs}   # the source version is in it


def test_set_replaces_base_values_before_the_axes_scale_them(tmp_path):
    spec = sw.load_spec(spec_file(tmp_path, '"load.torque" = { scale = [2] }',
                                  sweep='[set]\n"load.torque" = [["0 s", "0 N*m"], ["1 s", "1.5 N*m"]]\n'
                                        '"control.i_max" = "4 A"'))
    (job,) = sw.jobs(spec, "v")
    assert job.tree["load"]["torque"] == [["0 s", "0 N*m"], ["1 s", "3 N*m"]]
    assert job.tree["control"]["i_max"] == "4 A"
    with pytest.raises(sw.SweepError, match="set.'control.i_maximum': not a scenario key"):
        sw.load_spec(spec_file(tmp_path, '"load.torque" = { scale = [2] }', sweep='[set]\n"control.i_maximum" = 1'))


def test_command_line_set_values_override_the_spec_and_name_their_own_output(tmp_path, capsys):
    assert sw.parse_set(["control.speed_bw=12 Hz", 'injection.V_h="30 V"', "estimator.sqw_bangbang.pll_kp=400",
                         'load.torque=[["0 s", "0 N*m"], ["1 s", "1 N*m"]]']) == {
        "control.speed_bw": "12 Hz", "injection.V_h": "30 V", "estimator.sqw_bangbang.pll_kp": 400,
        "load.torque": [["0 s", "0 N*m"], ["1 s", "1 N*m"]]}
    with pytest.raises(ValueError, match="--set 'speed': expected KEY=VALUE"):
        sw.parse_set(["speed"])
    path = spec_file(tmp_path, '"load.torque" = { scale = [2] }',
                     sweep='name = "s"\n[set]\n"load.torque" = [["0 s", "0 N*m"], ["1 s", "1.5 N*m"]]\n"control.i_max" = "4 A"')
    spec = sw.load_spec(path, sw.parse_set(["control.i_max=5 A", "control.speed_bw=12 Hz"]))
    assert spec.name == "s+control.i_max=5A+control.speed_bw=12Hz"
    (job,) = sw.jobs(spec, "v")
    assert (job.tree["control"]["i_max"], job.tree["control"]["speed_bw"]) == ("5 A", "12 Hz")
    assert job.tree["load"]["torque"] == [["0 s", "0 N*m"], ["1 s", "3 N*m"]]     # the spec's own [set], scaled
    assert job.key != sw.jobs(sw.load_spec(path), "v")[0].key
    profile = [[f"{t} s", f"{t / 10} N*m"] for t in range(10)]          # longer than sw.SET_SUFFIX_MAX
    assert sw.set_suffix({"load.torque": profile}) == \
        "+load.torque=" + hashlib.sha256(json.dumps(profile).encode()).hexdigest()[:12]
    with pytest.raises(sw.SweepError, match="set.'control.i_maximum': not a scenario key"):
        sw.load_spec(path, {"control.i_maximum": 1})
    assert main(["sweep", str(path), "--set", "i_max"]) == 1
    assert capsys.readouterr().err == "hfi sweep: --set 'i_max': expected KEY=VALUE (a dotted scenario key, docs/scenario.md)\n"


def test_seeds_and_initial_angles(tmp_path):
    spec = sw.load_spec(spec_file(tmp_path, '"injection.V_h" = ["20 V"]', sweep="seeds = 3"))
    jobs = sw.jobs(spec, "v")
    base_seed = spec.base["scenario"]["seed"]
    pole_pairs = parse_scenario(copy.deepcopy(spec.base)).plant["mech"]["pole_pairs"]
    assert [j.seed for j in jobs] == [base_seed + 1000 + k for k in range(3)]
    for j in jobs:
        assert j.tree["scenario"]["seed"] == j.seed
        assert j.tree["load"]["initial"]["theta_m"] == f"{j.theta_m0_deg} deg"
        assert 0 <= j.theta_m0_deg < 360 / pole_pairs
    assert len({j.theta_m0_deg for j in jobs}) == 3


def test_random_design_is_reproducible_and_inside_its_bounds(tmp_path):
    spec = sw.load_spec(spec_file(tmp_path, '"injection.V_h" = { uniform = ["10 V", "30 V"] }\n'
                                  '"pwm.dead_time" = { scale_uniform = [0.8, 1.2] }\n"control.speed_bw" = ["2 Hz", "4 Hz"]',
                                  sweep='design = "random"\nsamples = 40\nseed = 7'))
    pts = sw.points(spec)
    assert pts == sw.points(spec) and len(pts) == 40
    assert pts != sw.points(dataclasses.replace(spec, seed=8))
    for p in pts:
        how, v = p["injection.V_h"]
        assert how == "value" and v.endswith(" V") and 10 <= float(v.split()[0]) <= 30
        how, f = p["pwm.dead_time"]
        assert how == "scale" and 0.8 <= f <= 1.2
        assert p["control.speed_bw"] == ("value", "2 Hz") or p["control.speed_bw"] == ("value", "4 Hz")
    assert {p["control.speed_bw"][1] for p in pts} == {"2 Hz", "4 Hz"}


def test_a_sweep_on_dask_equals_direct_runs_resumes_and_keeps_failures(tmp_path, capsys):
    path = spec_file(tmp_path, '"injection.V_h" = ["20 V", "-5 V"]\n"control.speed_bw" = ["4 Hz", "6 Hz"]',
                     sweep='name = "t"\nwindows = [["10 ms", "30 ms"], ["20 ms", "30 ms"]]\ncrb = true')
    spec = sw.load_spec(path)
    out = tmp_path / "out"
    rows = sw.sweep(spec, out, workers=1, dashboard=False, progress=False)
    assert len(rows) == 4
    table = pq.read_table(out / "results.parquet").to_pylist()
    assert [r["run_key"] for r in table] == [r["run_key"] for r in rows]
    good = [r for r in table if not r["error"]]
    assert len(good) == 2 and all(r["injection.V_h"] == "20 V" and r["injection.V_h.si"] == 20.0 for r in good)
    bad = [r for r in table if r["error"]]
    assert len(bad) == 2 and all("ScenarioError" in r["error"] and "injection.V_h" in r["error"] for r in bad)
    # the reference: the same scenario run directly on the backend
    for r in good:
        job = next(j for j in sw.jobs(spec, sw.source_version()) if j.key == r["run_key"])
        sc = parse_scenario(copy.deepcopy(job.tree))
        res = run(sc, "golden", progress=False)
        m = metrics_of(sc, res)
        assert r["angle_error_after_start.rms_deg"] == m["angle_error_after_start"]["rms_deg"]
        assert r["locked"] == m["locked"] and r["final_mode"] == m["final_mode"]
        sel = (res.t >= 0.01) & (res.t < 0.03)
        err = res.angle_error_deg()[sel]
        assert r["win0.err_peak_deg"] == round(float(abs(err).max()), 4)
        assert r["win0.err_rms_deg"] == round(math.sqrt(float((err ** 2).mean())), 4)
        assert r["win0.torque_std_nm"] == round(float(res.windows["torque"][sel].std()), 4)
        # the second window: copper loss, audible torque and the bound (the rotor stands still in start-up)
        late = (res.t >= 0.02) & (res.t < 0.03)
        total, ripple = copper_loss(res.windows, res.t, late, sc.plant["R_s"])
        assert (r["win1.cu_loss_w"], r["win1.cu_ripple_w"]) == (float(f"{total:.6g}"), float(f"{ripple:.6g}"))
        assert r["win1.torque_audible_nm"] == float(f"{audible_torque(res.windows, res.t, late):.6g}")
        b = bound(sc.plant, res.tick_hz, res, sw.angle_error(res, sc, "method"), 0.02, 0.03)
        assert r["win1.crb_window_deg"] == float(f"{b.crb_window_deg:.6g}") and 0 < b.crb_window_deg < math.inf
        assert r["win1.efficiency"] == float(f"{b.efficiency:.6g}")
        assert "win0.crb_window_deg" not in r          # the bound's replay needs 20 ms before its stretch: win0
    # resume: nothing runs again, the same table
    log: list[str] = []
    again = sw.sweep(spec, out, workers=1, dashboard=False, progress=False, log=log.append)
    assert "4 cached, 0 to run" in log[0]
    assert pq.read_table(out / "results.parquet").to_pylist() == table and again == rows
    # the command: exit status 1 when a run failed, the errors listed
    capsys.readouterr()
    assert main(["sweep", str(path), "--out", str(out), "--quiet"]) == 1
    text = capsys.readouterr().out
    assert "4 cached, 0 to run" in text and "(4 rows, 2 failed)" in text
    assert "point 2: ScenarioError: sweep t (base.toml): 1 problem: injection.V_h: must be >= 0, got '-5 V'" in text


def test_a_scheduler_address_gives_the_rows_of_the_local_cluster(tmp_path, capsys):
    """The cluster path: scripts/sweep_cluster.py starts `dask scheduler` and `dask worker` processes and runs
    `hfi sweep --scheduler ADDRESS` against them; every column but the wall times equals the local cluster's."""
    import importlib.util

    import psutil
    spec_ = importlib.util.spec_from_file_location("sweep_cluster", ROOT / "scripts" / "sweep_cluster.py")
    script = importlib.util.module_from_spec(spec_)
    spec_.loader.exec_module(script)
    path = spec_file(tmp_path, '"injection.V_h" = ["20 V"]', duration="20 ms",
                     sweep='name = "c"\nseeds = 2\nwindows = [["10 ms", "20 ms"]]')
    local = sw.sweep(sw.load_spec(path), tmp_path / "local", workers=1, dashboard=False, progress=False)
    capsys.readouterr()
    assert script.main([str(path), "--workers", "1", "--out", str(tmp_path / "cluster"), "--quiet"]) == 0
    text = capsys.readouterr().out
    assert "sweep_cluster: scheduler tcp://127.0.0.1:" in text and "1 points x 2 seeds = 2 runs on golden; 0 cached, 2 to run" in text
    remote = pq.read_table(tmp_path / "cluster" / "results.parquet").to_pylist()
    wall = {"wall_s", "realtime_factor", "run_wall_s"}
    assert len(remote) == 2 and not any(r["error"] for r in remote)
    assert [{k: v for k, v in r.items() if k not in wall} for r in remote] == \
        [{k: v for k, v in r.items() if k not in wall} for r in local]
    assert not [p for p in psutil.Process().children(recursive=True) if "dask" in " ".join(p.cmdline())]
    assert script.main([str(tmp_path / "missing.toml"), "--quiet"]) == 2
    assert capsys.readouterr().err.startswith("sweep_cluster: ")


def test_the_command_reports_a_bad_spec_on_stderr(tmp_path, capsys):
    path = spec_file(tmp_path, '"injection.V_h" = []')
    assert main(["sweep", str(path)]) == 1
    assert "params.'injection.V_h': the list of values is empty" in capsys.readouterr().err
    assert main(["sweep", str(tmp_path / "nope.toml")]) == 1
    assert "cannot read it" in capsys.readouterr().err


def test_one_at_a_time_varies_each_axis_alone_around_the_base(tmp_path):
    spec = sw.load_spec(spec_file(tmp_path, '"model_error.L_d" = [0.8, 1.2]\n"model_error.R_s" = [1.5]\n'
                                  '"load.torque" = { scale = [0.5, 2] }', sweep='design = "one_at_a_time"'))
    assert sw.points(spec) == [{}, {"model_error.L_d": ("value", 0.8)}, {"model_error.L_d": ("value", 1.2)},
                               {"model_error.R_s": ("value", 1.5)},
                               {"load.torque": ("scale", 0.5)}, {"load.torque": ("scale", 2)}]
    base, first = sw.jobs(spec, "v")[:2]
    assert base.tree == spec.base and first.tree["model_error"] == {"L_d": 0.8}


def test_the_angle_error_is_referred_where_the_estimator_in_charge_refers_its_angle():
    """angle_at = "method": per window, the quarters the slot in charge declares (MethodInfo.angle_quarters)."""
    import types

    import numpy as np

    from golden.firmware.estimator import METHODS
    res = types.SimpleNamespace(windows={"est": np.array([0, 1, 1, 0])},
                                angle_error_deg=lambda quarters: np.full(4, 10.0 * quarters))
    sc = types.SimpleNamespace(estimator=types.SimpleNamespace(low="sqw_cic", high="rfo"))
    assert (METHODS["sqw_cic"].angle_quarters, METHODS["rfo"].angle_quarters) == (3, 2)
    assert list(sw.angle_error(res, sc, "method")) == [30.0, 20.0, 20.0, 30.0]
    assert list(sw.angle_error(res, sc, "middle")) == [20.0] * 4
    assert list(sw.angle_error(res, sc, "bottom")) == [30.0] * 4


def test_root_keys_that_are_values_can_vary_tables_cannot(tmp_path):
    spec = sw.load_spec(spec_file(tmp_path, 'faults = [[{ kind = "dc_link", factor = 0.8, at = "0 s" }]]'))
    (job,) = sw.jobs(spec, "v")
    assert job.tree["faults"] == [{"kind": "dc_link", "factor": 0.8, "at": "0 s"}]
    parse_scenario(copy.deepcopy(job.tree))
    with pytest.raises(sw.SweepError, match="params.'load': not a scenario key"):
        sw.load_spec(spec_file(tmp_path, 'load = [1]'))


def test_the_source_version_covers_every_module_a_run_imports():
    """A run imports hfi.sweep's run path and one backend's module: each ``hfi`` module it loads must be in
    ``CODE``, or a change to it would reuse stale cached runs."""
    import subprocess
    import sys
    from hfi.backends import BACKENDS
    mods = [b.loop.split(":")[0] for b in BACKENDS.values()]
    code = ("import sys, importlib; import hfi.sweep, hfi.report, hfi.ripple, hfi.crb\n"
            f"for m in {mods!r}: importlib.import_module(m)\n"
            "print(' '.join(sorted(m for m in sys.modules if m == 'hfi' or m.startswith('hfi.'))))")
    loaded = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True,
                            cwd=sw.ROOT).stdout.split()
    files = {"hfi/__init__.py" if m == "hfi" else m.replace(".", "/") + ".py" for m in loaded}
    assert files <= set(sw.CODE), sorted(files - set(sw.CODE))
    assert "hfi/compare.py" not in sw.CODE                 # a report's change keeps the runs


@pytest.mark.parametrize("path", sorted((ROOT / "sweeps").glob("*.toml")), ids=lambda p: p.name)
def test_every_shipped_spec_expands_into_valid_scenarios(path):
    """Each sweep spec of sweeps/ loads, and every point of its design (its first seed) is a scenario the
    validation accepts: a spec the docs cite cannot rot unnoticed."""
    spec = sw.load_spec(path)
    js = sw.jobs(spec, "test")
    assert js and not [j.error for j in js if j.error]
    first = {}
    for j in js:
        first.setdefault(j.point, j)
    for j in first.values():
        parse_scenario(j.tree, f"{path.name} point {j.point}")
