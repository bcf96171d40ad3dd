"""The fault matrix (hfi/faults.py, docs/faults.md): single cells on the golden closed loop, judged against
the issue's targets (a lost lock tripped within 20 ms, no runaway with the gates on), and the command's
errors. The whole matrix: `hfi faults` / `make faults`."""

from __future__ import annotations

from pathlib import Path

import pytest

from hfi import cli, faults

LOCK_DETECT_MS = 20.0
"""Issue 19: a loss of lock is detected within 20 ms."""


@pytest.mark.parametrize("name, rpm, code", [("phase open (a)", 250.0, "lock_loss"),
                                             ("switch open (a high)", 250.0, "lock_loss"),
                                             ("ADC lane dead (b)", 50.0, "hardware"),
                                             ("sensor gain x0.7 (a)", 50.0, "hf_response"),
                                             ("sensor gain x0.7 (a)", 250.0, "overload")])
def test_a_fault_cell_is_detected_with_its_code(tmp_path, name, rpm, code):
    """Rated load. The gain error at 250 r/min is found by the overload check's load part (the torque the
    measured currents give does not match the speed's change) before the angle passes 60 deg; before that part it
    lost the angle and the HF response check tripped 7.4 ms later."""
    row = faults.run_one((name, rpm, True, faults.DURATION_SHORT_S, str(tmp_path)))
    assert (row["verdict"], row["code"], row["reaction"]) == ("detected", code, "coast")
    assert 0 < row["detect_ms"] < 1e3 * (faults.DURATION_SHORT_S - faults.ONSET_S)
    assert (row["lock_lost"], row["lock_detect_ms"]) == (False, None)    # tripped before the angle passed 60 deg
    assert not row["runaway_gates_on"] and Path(row["figure"]).is_file()


@pytest.mark.parametrize("name, rpm, load, code, within_ms",
                         [("load drives at -3x rated", 0.0, True, "lock_loss", 5.8),
                          ("sensor gain x0.7 (a)", 250.0, False, "lock_loss", 1.2)],
                         ids=["driving_load_standstill", "gain_250_no_load"])
def test_a_lost_lock_is_detected_within_20_ms(tmp_path, name, rpm, load, code, within_ms):
    """The angle error passes 60 deg. A load driving the motor at three times the rated torque at standstill under
    rated load: the lock check trips 5.8 ms after. A sensor gain of 0.7 at 250 r/min without load: the HF estimator
    slips towards the opposite polarity (docs/faults.md, "Polarity slips") and the slip check (the rotor flux
    observer beside it stays within 3 deg) trips 1.2 ms after (66 ms before the check, by the HF response check).
    Both within the issue's 20 ms; the times are the golden run's."""
    row = faults.run_one((name, rpm, load, faults.DURATION_SHORT_S, str(tmp_path)))
    assert (row["verdict"], row["code"], row["lock_lost"]) == ("detected", code, True)
    assert row["lock_detect_ms"] == pytest.approx(within_ms, abs=1e-9) and row["lock_detect_ms"] <= LOCK_DETECT_MS


@pytest.mark.parametrize("rpm, within_ms", [(50.0, 38.45), (250.0, 51.25)])
def test_a_load_beyond_the_drive_trips_before_it_runs_away(tmp_path, rpm, within_ms):
    """A load driving the motor at three times the rated torque under rated load (net -4 N*m against the drive's
    2.7 N*m): the overload check's load part trips 38.45 / 51.25 ms after the impact, before the motor has been 300
    r/min off its reference for 50 ms with the gates on (the matrix's two runaways before that part, tripped after
    87 and 91 ms by the growth of the speed error); the times are the golden run's."""
    row = faults.run_one(("load drives at -3x rated", rpm, True, faults.DURATION_SHORT_S, str(tmp_path)))
    assert (row["verdict"], row["code"], row["runaway_gates_on"]) == ("detected", "overload", False)
    assert row["detect_ms"] == pytest.approx(within_ms, abs=1e-9)


def test_the_healthy_cell_does_not_trip(tmp_path):
    row = faults.run_one(("none", 50.0, True, faults.DURATION_SHORT_S, str(tmp_path)))
    assert (row["verdict"], row["code"], row["detect_ms"]) == ("healthy", "none", None)


def test_unknown_rows_are_refused(capsys):
    assert cli.main(["faults", "--only", "phase open (a),no such fault"]) == 1
    assert "unknown fault rows ['no such fault']" in capsys.readouterr().err


def test_a_restart_takes_the_drive_back_once_the_fault_clears():
    """[protection] restarts = 1: a dc-link sag from 0.8 to 0.85 s trips the undervoltage check; 0.2 s later the
    firmware starts again (CONVERGE, the polarity test, RUN) and the drive is locked at 50 r/min again. Without
    load: the default scenario's load is an active torque, which turns the coasting motor backwards, and the HF
    estimator cannot catch a motor spinning at hundreds of r/min (the restart then trips again and stays; the
    flying start can: test_a_flying_start_brakes_the_rotor_the_rated_load_spun_up)."""
    import tomllib

    import numpy as np

    from golden.closedloop import ClosedLoop
    from golden.firmware.supervisor import MODE_CONVERGE, MODE_FAULT, MODE_RUN
    from golden.scenario import parse_scenario

    data = tomllib.loads(faults.BASE.read_text())
    data["scenario"]["duration"] = "1.6 s"
    data["reference"]["speed"] = [["0 s", "0 rpm"], ["0.3 s", "0 rpm"], ["0.5 s", "50 rpm"]]
    data["load"]["torque"] = [["0 s", "0 N*m"]]
    data["faults"] = [dict(faults.FAULTS["dc-link sag -30 %"], at="0.8 s", until="0.85 s")]
    data["protection"] = {"restarts": 1, "restart_delay": "0.2 s"}
    res = ClosedLoop(parse_scenario(data)).run(progress=False)
    mode, t = res.windows["mode"], res.t
    changes = [(float(t[k]), int(mode[k])) for k in np.flatnonzero(np.diff(mode)) + 1]
    trip = next(k for k, (_, m) in enumerate(changes) if m == MODE_FAULT)
    assert 0.8 <= changes[trip][0] < 0.801 and changes[trip + 1][1] == MODE_CONVERGE
    assert changes[trip + 1][0] == pytest.approx(changes[trip][0] + 0.2, abs=1e-3)
    assert changes[-1][1] == MODE_RUN and mode[-1] == MODE_RUN
    err = res.angle_error_deg()[t > 1.4]
    assert np.sqrt(np.mean(err ** 2)) < 15.0                 # locked again (healthy: about 5 deg)


@pytest.mark.parametrize("name, code", [("dc-link sag -30 %", "undervoltage"), ("dc-link surge +40 %", "overvoltage")])
def test_a_dc_link_step_trips_after_its_periods(name, code):
    """A step of the link at the onset (0.8 s = a carrier bottom): the bottom sample of that window reads it, and
    the check trips in the window ``vdc_n - 1`` later (every VDC reading beyond the limit: 392 V and 784 V against
    420 V and 700 V); the first FAULT window is that one, with the check's code."""
    import numpy as np

    from golden.closedloop import ClosedLoop
    from golden.control_config import hardware_config, protection_params
    from golden.firmware.protection import FAULT_NAMES

    sc = faults.scenario(faults.FAULTS[name], 50.0, True, faults.DURATION_SHORT_S)
    P = 2 * hardware_config(sc).pwm_half
    onset = round(faults.ONSET_S * sc.pwm.tick_hz)
    prot = protection_params(sc)
    res = ClosedLoop(sc).run(progress=False)
    first_low = onset // P - 1                    # window k's bottom sample is at (k + 1) P
    assert onset % P == 0
    vdc = res.windows["vdc"]
    beyond = (vdc < prot.vdc_lo) | (vdc > prot.vdc_hi)
    assert not beyond[:first_low].any() and beyond[first_low:first_low + prot.vdc_n].all()
    fault = res.windows["fault"]
    k = int(np.flatnonzero(fault)[0])
    assert (k, FAULT_NAMES[fault[k]]) == (first_low + prot.vdc_n - 1, code)


def test_the_restart_part_relocks_after_a_transient_sag(tmp_path):
    """The restart part of the matrix (hfi.faults.run_restart): a 50 ms sag of 30 % without load trips
    undervoltage, the firmware starts again RESTART_DELAY_S later and holds 50 r/min locked at the end."""
    row = faults.run_restart(("dc-link sag -30 %", False, False, faults.DURATION_S, str(tmp_path)))
    assert (row["code"], row["second_code"], row["locked_at_end"]) == ("undervoltage", "none", True)
    assert row["restart_s"] == pytest.approx(row["trip_s"] + faults.RESTART_DELAY_S, abs=1e-3)
    assert row["trip_s"] >= faults.ONSET_S and Path(row["figure"]).is_file()


@pytest.mark.parametrize("flying", [False, True])
def test_a_flying_start_brakes_the_rotor_the_rated_load_spun_up(tmp_path, flying):
    """The same sag under the rated load, an active torque: in the 0.2 s the drive coasts, the load spins the motor
    to about -900 r/min. The standstill restart (the paper's drive) cannot start a spinning motor: it trips on
    overcurrent and the load takes the motor to thousands of r/min. The flying start (CATCH, the rotor flux
    observer) catches it, brakes it at the current limit through the hand-over down to the HF estimator, and holds
    50 r/min locked at the end, the current within the trip limit throughout."""
    row = faults.run_restart(("dc-link sag -30 %", True, flying, faults.DURATION_S + faults.RESTART_EXTRA_S,
                              str(tmp_path)))
    assert row["code"] == "undervoltage"
    assert row["restart_s"] == pytest.approx(row["trip_s"] + faults.RESTART_DELAY_S, abs=1e-3)
    assert row["extreme_speed_rpm"] < -800.0                 # the load had spun the coasting motor backwards
    from golden.scenario import load_scenario
    if flying:
        assert (row["second_code"], row["locked_at_end"]) == ("none", True)
        assert row["peak_current_a"] < load_scenario(faults.BASE).control.i_trip
        assert row["extreme_speed_rpm"] > -1500.0
    else:
        assert (row["second_code"], row["locked_at_end"]) == ("overcurrent", False)
