"""Current sensors, ADC, determinism and the plant's input checks (docs/plant.md, "Sensors")."""

from __future__ import annotations

import math

import numpy as np
import pytest

from golden.plant import Plant, PlantError, ShootThroughError, default_params, merge

TICK = 100e6


def locked(**over) -> dict:
    return merge(merge(default_params(), {"mech": {"imposed_speed": 1}}), over)


def d_axis_volts(v: float) -> list[float]:
    """Phase voltages putting v on the alpha axis (the d axis of a rotor at theta = 0)."""
    return [v, -v / 2, -v / 2]


def expected_code(current: np.ndarray, bits: int, rng: float) -> np.ndarray:
    """Mid-scale = 0 A; LSB = 2 rng / 2^bits; round half up; clip to the code range."""
    full = 2 ** bits
    return np.clip(np.floor(current / (2 * rng / full) + full / 2 + 0.5), 0, full - 1).astype(int)


def test_adc_codes_quantise_the_sensed_current():
    p = locked(sens={"adc_bits": 12, "adc_range": 10.0, "gain": [1.02, 0.97, 1.0], "offset": [0.05, -0.03, 0.0]})
    out = Plant(p).run([0], np.arange(0, 300_001, 1000), volts=[d_axis_volts(40.0)], analog=True, truth=True)
    i_abc = out["truth"]["i_abc"]
    analog = np.array([1.02, 0.97, 1.0]) * i_abc + np.array([0.05, -0.03, 0.0])
    np.testing.assert_allclose(out["analog"], analog, rtol=0, atol=1e-15)
    np.testing.assert_array_equal(out["adc"], expected_code(out["analog"], 12, 10.0))
    assert out["adc"][:, 0].max() > 2048 + 300  # the test really moves through the codes


def test_adc_clips_outside_its_range():
    p = locked(R_s=0.5, sens={"adc_bits": 10, "adc_range": 2.0})
    out = Plant(p).run([0], [0, 2_000_000], volts=[d_axis_volts(60.0)], truth=True)
    assert out["truth"]["i_abc"][-1, 0] > 2.0 and out["truth"]["i_abc"][-1, 1] < -2.0
    np.testing.assert_array_equal(out["adc"][-1], [1023, 0, 0])
    np.testing.assert_array_equal(out["adc"][0], [512, 512, 512])


def test_sensor_bandwidth_is_first_order():
    """R_s = 0 and an ideal voltage step: the current is an exact ramp k t, and a first-order sensor
    of time constant tau reads k (t - tau (1 - exp(-t / tau)))."""
    bw = 50e3
    tau = 1 / (2 * math.pi * bw)
    p = locked(R_s=0.0, sens={"bandwidth_hz": bw, "adc_bits": 24, "adc_range": 50.0})
    samples = np.arange(0, 5001, 7)
    out = Plant(p).run([0], samples, volts=[d_axis_volts(30.0)], analog=True, truth=True)
    t = samples / TICK
    k = 30.0 / 5.59e-3
    np.testing.assert_allclose(out["truth"]["i_abc"][:, 0], k * t, rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(out["analog"][:, 0], k * (t - tau * (1 - np.exp(-t / tau))), rtol=1e-9, atol=1e-12)


def test_ringing_after_each_turn_on():
    """A turn-on of leg a adds A s exp(-dt/tau) sin(2 pi f dt) to channel a (s = +1 high, -1 low
    switch) and ring_cross times that to b and c; edges superpose."""
    A, f, tau, cross = 0.2, 300e3, 2e-6, 0.25
    p = locked(sens={"ring_amp": A, "ring_freq": f, "ring_tau": tau, "ring_cross": cross, "adc_bits": 24})
    plant = Plant(p)
    edges = [(1000, 0b000001, +1.0), (1800, 0b000010, -1.0)]  # a high on, then a low on (after a
    # forbidden-free transition: a high off and a low on at the same tick)
    analog, expected = [], []
    for tick in range(1000, 4000, 13):
        for e_tick, mask, _ in edges:
            if e_tick == tick or (tick - 13 < e_tick < tick):
                plant.advance(e_tick)
                plant.set_gates(mask)
        plant.advance(tick)
        _, a = plant.sample()
        y = plant.state()["sensor_y"]
        ring = sum(s * A * math.exp(-(tick - et) / TICK / tau) * math.sin(2 * math.pi * f * (tick - et) / TICK)
                   for et, _, s in edges if et <= tick)
        analog.append(a[:3] - y)
        expected.append([ring, cross * ring, cross * ring])
    np.testing.assert_allclose(np.array(analog), np.array(expected), rtol=0, atol=1e-12)
    assert np.max(np.abs(expected)) > 0.1


def test_noise_statistics_and_seed():
    p = locked(seed=7, sens={"noise_rms": 0.03, "adc_bits": 24})
    samples = np.arange(0, 100_000 * 100, 100)
    a = Plant(p).run([0], samples, volts=[[0.0, 0.0, 0.0]], analog=True)["analog"]
    n = a.size
    assert abs(a.mean()) < 4 * 0.03 / math.sqrt(n)
    assert a.std() == pytest.approx(0.03, rel=4 / math.sqrt(2 * n) * 2)
    # channels and successive samples uncorrelated
    assert abs(np.corrcoef(a[:, 0], a[:, 1])[0, 1]) < 4 / math.sqrt(len(a))
    assert abs(np.corrcoef(a[1:, 0], a[:-1, 0])[0, 1]) < 4 / math.sqrt(len(a))


def realistic(seed: int) -> dict:
    return merge(default_params(), {"seed": seed, "mag": {"kind": 1, "dsat_a": 0.05},
                                    "inv": {"C_node": 1e-9},
                                    "sens": {"noise_rms": 0.02, "bandwidth_hz": 100e3, "ring_amp": 0.1,
                                             "ring_tau": 2e-6, "ring_freq": 300e3, "ring_cross": 0.3}})


def gate_pattern():
    from golden.openloop import PwmConfig, gate_edges, injection_compares
    cfg = PwmConfig()
    return gate_edges(cfg, injection_compares(cfg, 20, 560.0, 100.0, 0.3, v_d=5.0, v_q=20.0))


def test_same_seed_is_bit_identical_and_batch_equals_per_event():
    ticks, masks = gate_pattern()
    samples = np.arange(0, 20 * 20000, 100)
    a = Plant(realistic(3)).run(ticks, samples, gates=masks, analog=True)
    b = Plant(realistic(3)).run(ticks, samples, gates=masks, analog=True)
    np.testing.assert_array_equal(a["adc"], b["adc"])
    assert a["analog"].tobytes() == b["analog"].tobytes()
    # the per-event API, fed the same events in the same order, gives the same bits
    plant = Plant(realistic(3))
    events = sorted([(t, 0, m) for t, m in zip(ticks, masks)] + [(t, 1, 0) for t in samples])
    got = []
    for tick, kind, mask in events:
        plant.advance(tick)
        if kind == 0:
            plant.set_gates(mask)
        else:
            got.append(plant.sample()[1][:3])
    assert np.array(got).tobytes() == a["analog"].tobytes()


def test_different_seed_changes_only_the_noise():
    ticks, masks = gate_pattern()
    samples = np.arange(0, 20 * 20000, 100)
    a = Plant(realistic(3)).run(ticks, samples, gates=masks, analog=True, truth=True)
    b = Plant(realistic(4)).run(ticks, samples, gates=masks, analog=True, truth=True)
    assert np.mean(a["adc"] != b["adc"]) > 0.5
    np.testing.assert_array_equal(a["truth"]["i_abc"], b["truth"]["i_abc"])


def test_shoot_through_is_refused_and_counted():
    plant = Plant(default_params())
    plant.advance(100)
    with pytest.raises(ShootThroughError, match="both switches"):
        plant.set_gates(0b000011)
    plant.advance(300)
    assert plant.state()["shoot_through_ticks"] == 200
    with pytest.raises(ShootThroughError):
        Plant(default_params()).run([10], [20], gates=[0b110000])


@pytest.mark.parametrize("over, message", [
    ({"mag": {"L_d": -1e-3}}, "mag.L_d must be > 0"),
    ({"mag": {"kind": 7}}, "mag.kind 7 is not a magnetic model"),
    ({"mag": {"kind": 1, "psi_f": 0.0}}, "psi_f must be > 0"),
    ({"mech": {"J": 0.0}}, "mech.J must be > 0"),
    ({"sens": {"adc_bits": 0}}, "adc_bits must be in 1..24"),
    ({"sens": {"gain": [1.0, 0.0, 1.0]}}, "sens.gain[1] must be > 0"),
    ({"inv": {"V_dc": float("nan")}}, "inv.V_dc must be > 0"),
    ({"load": {"t": [0.0, -1.0], "v": [0.0, 1.0]}}, "load: times must not decrease"),
    ({"max_substep_ticks": 0}, "max_substep_ticks must be >= 1"),
])
def test_bad_parameters_are_refused_with_a_message(over, message):
    with pytest.raises(PlantError, match=message.replace("[", r"\[").replace("]", r"\]").replace(".", r"\.")):
        Plant(merge(default_params(), over))


def test_bad_inputs_are_refused():
    plant = Plant(default_params())
    plant.advance(1000)
    with pytest.raises(PlantError, match="before the plant's time"):
        plant.advance(999)
    with pytest.raises(PlantError, match="6-bit"):
        plant.set_gates(64)
    with pytest.raises(PlantError, match="non-decreasing"):
        plant.run([2000, 1500], [], gates=[1, 2])
    with pytest.raises(PlantError, match="not a plant parameter"):
        Plant(merge(default_params(), {}) | {"bogus": 1})


def test_a_diverged_state_is_reported_not_converted():
    """An ideal voltage of 1e308 V drives the currents past the double range: a sample of a state that is no
    longer finite has no ADC code (a NaN has no int conversion in C), so the batch and the per-event API refuse it
    with PLANT_NOT_FINITE's message instead of returning a code."""
    volts = [d_axis_volts(1e308)]
    with pytest.raises(PlantError, match=r"^the plant's state is no longer finite \(NaN or infinite\)"):
        Plant(locked()).run([0], [0, 100_000], volts=volts)
    plant = Plant(locked())
    plant.set_voltage(volts[0])
    plant.advance(100_000)
    with pytest.raises(PlantError, match=r"^the plant's state is no longer finite"):
        plant.sample()
    ok = Plant(locked())
    ok.set_voltage(d_axis_volts(1.0))
    ok.advance(100_000)
    assert ok.sample()[0].dtype == np.int32        # a finite state samples as before
