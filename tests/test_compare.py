"""``hfi compare`` (hfi/compare.py): the specs' p.u. bases are the motors' rated values, and the summary of
a sweep's rows counts and reduces exactly."""

from __future__ import annotations

import copy
import math

import pytest

from golden import motors
from golden.scenario import parse_scenario
from golden.units import parse_quantity
from hfi import compare as cmp
from hfi.sweep import jobs, load_spec
from hfi.cli import main


@pytest.mark.parametrize("system", cmp.SYSTEMS)
def test_one_pu_is_the_motors_rating_and_the_grid_is_the_issues(system):
    spec = load_spec(cmp.spec_path(system))
    rated = motors.preset(spec.base["motor"]["preset"])["rated"]
    speed = parse_quantity(spec.base["reference"]["speed"][-1][1], "speed") * 30 / math.pi
    torque = parse_quantity(spec.base["load"]["torque"][-1][1], "torque")
    assert speed == pytest.approx(rated["speed_rpm"], rel=1e-9)
    assert torque == pytest.approx(rated["torque"], rel=2e-4)      # 23.87 N*m written for 23.873
    axes = {a.key: a for a in spec.axes}
    assert axes["reference.speed"].items == (0, 0.1, 0.5)          # standstill, 10 % and 50 % speed
    assert axes["load.torque"].items == (0, 0.5, 1.0, 1.5, 2.0)     # 0 to 2 p.u.
    assert spec.seeds >= 20 and spec.backend == "hls"
    for job in jobs(spec, "v")[:: len(jobs(spec, "v")) // 3]:
        parse_scenario(copy.deepcopy(job.tree))                    # every point is a valid scenario


def row(speed, load, locked=True, fault="none", rms=1.0, peak=2.0, high=0.0, error="", ripple=(3.0, 0.5),
        cu=4.0, audible=0.2):
    r = {"reference.speed.scale": speed, "load.torque.scale": load, "error": error}
    if not error:
        r.update({"locked": locked, "faults.code": fault, "win0.err_rms_deg": rms, "win0.err_peak_deg": peak,
                  "win0.high_share": high, "win0.speed_ripple_rpm": ripple[0], "win0.torque_std_nm": ripple[1],
                  "win0.cu_ripple_w": cu, "win0.torque_audible_nm": audible})
    return r


def test_summary_counts_lost_and_failed_runs_and_reduces_the_locked_ones():
    rows = [row(0, 1, rms=1.0, peak=3.0), row(0, 1, rms=3.0, peak=4.0), row(0, 1, rms=2.0, peak=9.0),
            row(0, 1, locked=False, rms=90.0, peak=180.0), row(0, 1, fault="overcurrent", rms=0.5, peak=0.5),
            row(0, 1, error="ScenarioError: x"),
            row(0.5, 0, rms=1.0, high=1.0), row(0.5, 0, rms=1.0, high=0.4)]
    rows[0]["win0.torque_std_nm"] = 0.1
    rows[1]["win0.cu_ripple_w"], rows[2]["win0.cu_ripple_w"] = 1.0, 9.0
    rows[1]["win0.torque_audible_nm"] = 2.0
    a, b = cmp.summarize("000", rows, rated_nm=2.0, rated_cu_w=8.0)
    assert (a.speed_pu, a.load_pu, a.n, a.lost, a.failed) == (0, 1, 6, 2, 1)
    assert (a.rms_median, a.rms_worst, a.peak_worst, a.estimator) == (2.0, 3.0, 9.0, "low")
    assert (a.speed_ripple, a.torque_ripple) == (3.0, 0.25)     # medians of the locked runs; 0.5 / 2 N*m
    assert a.cu_ripple == 0.5                                    # median 4 W of 8 W rated
    assert a.audible_db == pytest.approx(20.0)                   # median 0.2 N*m = 10 x 1 % of 2 N*m
    assert math.isnan(a.crb_deg) and math.isnan(a.efficiency)    # no run had the bound's columns
    assert (b.n, b.lost, b.estimator) == (2, 0, "both")
    (c,) = cmp.summarize("000", [row(0, 0, locked=False)])
    assert c.lost == 1 and math.isnan(c.rms_median) and c.estimator == "-"


def test_bound_table_takes_the_medians_of_the_runs_that_have_the_bound():
    rows = [row(0, 1), row(0, 1), row(0, 1), row(0, 0)]
    for r, (crb, eff) in zip(rows, ((0.3, 0.02), (0.5, 0.04), (0.4, 0.01))):
        r.update({"win0.crb_window_deg": crb, "win0.err_std_deg": 10 * crb, "win0.tau_c_ms": 2.0,
                  "win0.efficiency": eff})
    pts = cmp.summarize("002", rows)
    assert (pts[1].crb_deg, pts[1].err_std_deg, pts[1].tau_c_ms, pts[1].efficiency) == (0.4, 4.0, 2.0, 0.02)
    lines = cmp.bound_table(pts, {"002": "002: a"})
    assert "| 002: a | 1 p.u. | 0.400 | 4.000 | 2.00 | 2 |" in lines
    assert not any("| 0 p.u. |" in x for x in lines)            # the no-load point has no bound


def test_report_and_figure_from_points(tmp_path):
    pts = cmp.summarize("002", [row(s, lo, rms=1 + lo, peak=2 + lo) for s in (0, 0.1) for lo in (0, 1)])
    pts += cmp.summarize("001", [row(0, 0, locked=False), row(0, 0)])
    labels = {"002": "002: a", "001": "001: b"}
    text = cmp.report(pts, labels, 2, tmp_path)
    assert "| 0 % | 1 p.u. | 1 | 0 | 2.00 | 2.00 | 3.00 | 3.00 | 50.00 | 400.00 | 26.02 | low |" in text
    assert "| 0 % | 0 p.u. | 2 | 1 | 1.00 | 1.00 | 2.00 | 3.00 | 50.00 | 400.00 | 26.02 | low |" in text
    assert "| 002: a | 2.00 / 3.00 | 0 of 4 | 26.02 | 400.00 |" in text     # headline: standstill, 1 p.u.
    assert "| 001: b | - / - | 1 of 2 | - | - |" in text
    assert (tmp_path / "results.csv").read_text().count("\n") == 1 + len(pts)
    cmp.figure(pts, labels, tmp_path / "f.png")
    assert (tmp_path / "f.png").stat().st_size > 10_000
    cmp.ripple_figure(pts, labels, tmp_path / "r.png")
    assert (tmp_path / "r.png").stat().st_size > 10_000


def test_command_refuses_unknown_systems(capsys):
    assert main(["compare", "--systems", "002,004"]) == 1
    assert "--systems: unknown 004 (valid: 002, 000, 001, 001r, 003)" in capsys.readouterr().err
    with pytest.raises(SystemExit):                 # argparse's usage error (tests/test_cli.py checks its line)
        main(["compare", "--seeds", "0"])
    assert "argument --seeds: '0': expected an integer >= 1" in capsys.readouterr().err


def test_sensitivity_study_changes_one_thing_at_a_time_at_its_point():
    from hfi.sweep import points
    base = load_spec(cmp.spec_path("002"))
    spec = cmp.sensitivity_spec(base)
    pts = points(spec)
    assert pts[0] == {} and len(pts) == 1 + sum(len(v) for _, v in cmp.SENSITIVITY.values())
    assert all(len(p) == 1 for p in pts[1:])
    assert spec.base["reference"]["speed"][-1][1] == "500 rpm"          # 0.1 p.u. of the spec's 5000 r/min
    assert spec.base["load"]["torque"] == base.base["load"]["torque"]    # 1 p.u.
    assert cmp.change_of({"model_error.L_d": 0.8}) == "L_d x0.8"
    assert cmp.change_of({"pwm.dead_time.scale": 2.0}) == "dead_time x2"
    assert cmp.change_of({"reference.speed.scale": 0.1}) == "nominal"
    own = cmp.sensitivity_spec(load_spec(cmp.spec_path("003")))       # the 003 maps' own changes, last
    assert [a.key for a in own.axes][-2:] == ["estimator.hfo_proj.map_scale_d", "estimator.hfo_proj.map_scale_q"]
    assert len(points(own)) == len(pts) + 4
    assert cmp.change_of({"estimator.hfo_proj.map_scale_q": 1.1}) == "map_scale_q x1.1"


def test_sensitivity_figure_table(tmp_path):
    rows = {"002": [dict(row(0.1, 1, rms=2.0), **{"model_error.L_d": 0.8}), dict(row(0.1, 1, locked=False),
                                                                              **{"model_error.L_d": 0.8}),
                    row(0.1, 1, rms=1.0)]}
    rows["003"] = [dict(row(0.1, 1, rms=3.0), **{"estimator.hfo_proj.map_scale_d": 0.9})]
    table = cmp.sensitivity_figure(rows, {"002": "002", "003": "003"}, tmp_path / "s.png")
    assert ("002", "nominal", 1, 0, 0, 1.0, 2.0) in table
    assert ("002", "L_d x0.8", 2, 1, 0, 2.0, 2.0) in table
    assert ("003", "map_scale_d x0.9", 1, 0, 0, 3.0, 2.0) in table
    assert not any(t[0] == "002" and t[1].startswith("map_scale") for t in table)
    assert cmp.change_of({"faults": '[{"kind": "dc_link", "factor": 0.8, "at": "0 s"}]'}) == "V_dc x0.8 (sag)"
    assert (tmp_path / "s.png").is_file()
