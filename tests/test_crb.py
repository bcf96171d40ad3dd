"""hfi.crb: the Fisher information of the ADC samples about the rotor angle against its closed form on a
lossless salient machine, and the correlation time and efficiency against exact cases."""

import math

import numpy as np
import pytest

from golden.plant.defaults import default_params
from hfi import crb

TICK = 100e6
V_DC, L_D, L_Q = 300.0, 5.59e-3, 6.26e-3
HIGH_A = 1 | 2 << 2 | 2 << 4        # vector 100: leg a high, b and c low
HIGH_BC = 2 | 1 << 2 | 1 << 4       # vector 011


def lossless_plant(sigma: float) -> dict:
    p = default_params()
    p["R_s"] = 0.0
    p["mag"].update(psi_f=0.0, L_d=L_D, L_q=L_Q)
    p["inv"]["V_dc"] = V_DC
    p["sens"].update(noise_rms=sigma, adc_bits=16, adc_range=10.0)
    return p


@pytest.mark.parametrize("theta_e", [0.3, 1.1, 2.0])
def test_information_of_a_square_wave_on_alpha_matches_the_closed_form(theta_e):
    """Vectors 100 and 011 alternating every 100 us put +-2/3 V_dc on alpha. Without resistance or magnet,
    i_ab = L_ab^-1(theta) (Phi, 0) with Phi the volt-seconds since the replay began, and
    d L_ab^-1 / d theta = 2c [[-sin 2th, cos 2th], [cos 2th, sin 2th]], c = (1/L_d - 1/L_q) / 2."""
    period, n = 20_000, 2000                                        # 200 us, 0.4 s
    e_tick = np.arange(n) * (period // 2)
    e_mask = np.where(np.arange(n) % 2 == 0, HIGH_A, HIGH_BC)
    sigma = 0.015
    plant = lossless_plant(sigma)
    t0, t1 = 0.1, 0.3
    samples = np.arange(0, n * period // 2, 100)                    # every 1 us
    info = crb.sample_information(plant, TICK, (e_tick, e_mask), samples, theta_e, t0, t1)

    ticks = samples[(samples >= t0 * TICK) & (samples < t1 * TICK)]
    start = ticks[0] - crb.SETTLE_S * TICK
    rel = (ticks - start) % period / TICK                           # the replay starts at a period's start
    half = period / 2 / TICK
    v = 2 / 3 * V_DC
    phi = np.where(rel < half, v * rel, v * (2 * half - rel))       # triangle, 0 at each period's start
    c = (1 / L_D - 1 / L_Q) / 2
    d_al, d_be = -2 * c * phi * math.sin(2 * theta_e), 2 * c * phi * math.cos(2 * theta_e)
    d_a, d_b = d_al, -0.5 * d_al + math.sqrt(3) / 2 * d_be
    lsb = 20.0 / 2 ** 16
    expect = float(np.sum(d_a ** 2 + d_b ** 2)) / (sigma ** 2 + lsb ** 2 / 12)
    assert info == pytest.approx(expect, rel=1e-6)


def test_sample_information_refuses_an_empty_or_early_stretch():
    plant = lossless_plant(0.01)
    edges = (np.array([0]), np.array([HIGH_A]))
    with pytest.raises(ValueError, match="no ADC sample"):
        crb.sample_information(plant, TICK, edges, np.array([100]), 0.0, 0.1, 0.2)
    with pytest.raises(ValueError, match="at least 0.02 s into the run"):
        crb.sample_information(plant, TICK, edges, np.array([100_000]), 0.0, 0.0, 0.2)


def test_correlation_time_by_batch_means():
    """Blocks of B equal values: the block means are the values, so tau = B * var_ddof1 / var_ddof0 = B * 20/19;
    an alternating sequence averages to 0 in every block: tau = 0."""
    rng = np.random.default_rng(3)
    values = rng.normal(size=crb.BLOCKS)
    x = np.repeat(values, 7)
    assert crb.correlation_time(x) == pytest.approx(7 * crb.BLOCKS / (crb.BLOCKS - 1), rel=1e-12)
    assert crb.correlation_time(np.tile([1.0, -1.0], 10 * crb.BLOCKS)) == pytest.approx(0.0, abs=1e-12)
    assert crb.correlation_time(np.zeros(100)) == 1.0
    with pytest.raises(ValueError, match="cannot make 20 blocks"):
        crb.correlation_time(np.ones(19))


def test_efficiency_is_the_ratio_of_the_stretch_means_variances():
    assert crb.efficiency(0.5, 2e-4, 1.0, 4e-3) == pytest.approx(0.25 * 2e-4 / 4e-3, rel=1e-12)
    assert math.isnan(crb.efficiency(0.5, 2e-4, 0.0, 4e-3))      # a frozen error: no efficiency
    assert math.isnan(crb.efficiency(0.5, 2e-4, 1.0, 0.0))
    assert math.isnan(crb.efficiency(math.inf, 2e-4, 1.0, 4e-3))  # no information (the gates are off)
