"""The dc-link voltage channel of the plant's ADC (plant_api.h ``sens.vdc_*``, docs/plant.md).

Expected codes come from the channel's definition, computed here: the link voltage (the source with its
faults, less ``R_dc`` times the current the legs on the positive rail draw), times the divider gain, plus
noise of a stream of its own, quantised unipolar ``floor(v 2^B / vdc_range + 1/2)`` clipped to the codes.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from golden.plant import Plant, PlantError, default_params, merge
from golden.plant.binding import ffi

TICK = 100e6
DC_LINK = ffi.typeof("enum fault_kind").relements["FAULT_DC_LINK"]


def vdc_code(v: float, bits: int, full_range: float) -> int:
    full = 2 ** bits
    return min(max(math.floor(v * full / full_range + 0.5), 0), full - 1)


def params(**sens) -> dict:
    return merge(default_params(), {"inv": {"V_dc": 560.0}, "mech": {"imposed_speed": 1},
                                    "sens": {"adc_bits": 12, "vdc_range": 1000.0, **sens}})


def test_code_quantises_the_divided_link_voltage():
    out = Plant(params(vdc_gain=1.02)).run([0], [10, 20], gates=[0b101010], analog=True)   # every leg low
    assert out["vdc_analog"][0] == pytest.approx(560.0 * 1.02, rel=1e-15)
    assert out["vdc"].tolist() == [vdc_code(560.0 * 1.02, 12, 1000.0)] * 2 == [2340] * 2


def test_no_channel_reads_code_zero_and_clips_at_full_scale():
    assert Plant(params(vdc_range=0.0)).run([0], [10], gates=[0b101010])["vdc"].tolist() == [0]
    assert Plant(params(vdc_range=500.0)).run([0], [10], gates=[0b101010])["vdc"].tolist() == [4095]


def test_the_sensor_sees_the_sag_of_the_current_drawn():
    """Leg a high, b and c low with current flowing: the reading is the state's own link voltage."""
    p = params()
    p["inv"]["R_dc"] = 0.5
    p["theta_m0"] = 0.1
    ticks = np.arange(100, 200_000, 997)
    out = Plant(p).run([0], ticks, gates=[0b101001], analog=True, truth=True)
    i_a = out["truth"]["i_abc"][:, 0]
    assert i_a[-1] > 1.0                                        # the test really draws current
    np.testing.assert_allclose(out["vdc_analog"], 560.0 - 0.5 * i_a, rtol=1e-12)
    np.testing.assert_allclose(out["vdc_analog"], out["truth"]["v_dc"], rtol=1e-12)


def test_dc_link_fault_moves_the_reading():
    p = params()
    p["faults"] = [{"kind": DC_LINK, "channel": 0, "tick": round(1e-3 * TICK), "until": 0, "value": 0.7, "rate": 0.0}]
    out = Plant(p).run([0], [round(0.5e-3 * TICK), round(2e-3 * TICK)], gates=[0b101010])
    assert out["vdc"].tolist() == [vdc_code(560.0, 12, 1000.0), vdc_code(392.0, 12, 1000.0)]


def test_noise_has_its_own_stream():
    """The currents' samples are the same bits with the link's noise on or off; the link's noise has its
    stated deviation."""
    sens = {"noise_rms": 0.05, "adc_bits": 16}
    ticks = np.arange(0, 20_000 * 100, 100)
    quiet = Plant(params(**sens)).run([0], ticks, gates=[0b101010], analog=True)
    noisy = Plant(params(**sens, vdc_noise_rms=2.0)).run([0], ticks, gates=[0b101010], analog=True)
    assert quiet["analog"].tobytes() == noisy["analog"].tobytes()
    np.testing.assert_array_equal(quiet["adc"], noisy["adc"])
    dev = noisy["vdc_analog"] - 560.0
    n = len(dev)
    assert abs(dev.mean()) < 4 * 2.0 / math.sqrt(n)
    assert dev.std() == pytest.approx(2.0, rel=4 / math.sqrt(2 * n))


@pytest.mark.parametrize("bad, message", [
    ({"vdc_range": -1.0}, "vdc_range must be >= 0"),
    ({"vdc_gain": 0.0}, "vdc_gain must be > 0"),
    ({"vdc_noise_rms": -0.1}, "vdc_noise_rms must be >= 0"),
])
def test_bad_channel_parameters_are_refused(bad, message):
    with pytest.raises(PlantError, match=message):
        Plant(params(**bad))


def test_a_dead_dc_link_lane_reads_zero_and_the_currents_are_untouched():
    """FAULT_ADC_STUCK on channel 3 (the dc link) from 1 ms: its code is 0 from there on, the current channels'
    codes are the healthy plant's."""
    stuck = {"kind": ffi.typeof("enum fault_kind").relements["FAULT_ADC_STUCK"], "channel": 3,
             "tick": round(1e-3 * TICK), "until": 0, "value": 0.0, "rate": 0.0}
    ticks = [round(0.5e-3 * TICK), round(2e-3 * TICK)]
    healthy = Plant(params(noise_rms=0.05)).run([0], ticks, gates=[0b101010])
    p = params(noise_rms=0.05)
    p["faults"] = [stuck]
    dead = Plant(p).run([0], ticks, gates=[0b101010])
    assert dead["vdc"].tolist() == [vdc_code(560.0, 12, 1000.0), 0]
    np.testing.assert_array_equal(dead["adc"], healthy["adc"])
