"""hfi.ripple: copper loss and audible torque from the plant's running integrals, against closed forms."""

import math

import numpy as np
import pytest

from hfi.ripple import a_weighting, audible_torque, copper_loss


@pytest.mark.parametrize("exponent, db", [(1.3, -50.5), (2.0, -19.1), (3.0, 0.0), (3.4, 1.3), (4.0, -2.5)])
def test_a_weighting_matches_the_iec_61672_table(exponent, db):
    """The table's nominal 20, 100, 1000, 2500, 10 000 Hz are the exact base-ten frequencies 10^(k/10)."""
    assert 20 * math.log10(float(a_weighting(10 ** exponent))) == pytest.approx(db, abs=0.05)


def windows_of(means: np.ndarray, within: np.ndarray, step: float, i_d: float = 0.0, i_q: np.ndarray | None = None,
               r_s: float = 1.0) -> tuple[dict, np.ndarray]:
    """A trace whose windows (after a first one at t = step) have these torque means and variances, a
    constant i_d and per-window i_q (no ripple inside the windows)."""
    n = means.size
    i_q = np.zeros(n) if i_q is None else i_q
    z = np.zeros(1)
    cum = lambda x: np.concatenate((z, np.cumsum(x * step)))      # noqa: E731 (integral at window ends)
    w = {"t_int": cum(means), "t2_int": cum(means ** 2 + within), "q_d": cum(np.full(n, i_d)), "q_q": cum(i_q),
         "e_cu": cum(1.5 * r_s * (i_d ** 2 + i_q ** 2))}
    return w, step * np.arange(1, n + 2)


def test_copper_loss_and_its_ripple_part():
    """i_q = 2 + sin: total 1.5 R (i_d^2 + 4 + 1/2), ripple part 1.5 R / 2 (whole periods)."""
    n, step, r_s = 1000, 1e-4, 0.8
    i_q = 2 + np.sin(2 * np.pi * 50 * step * np.arange(n))       # 5 whole periods of 50 Hz
    w, t = windows_of(np.zeros(n), np.zeros(n), step, i_d=-0.5, i_q=i_q, r_s=r_s)
    sel = np.ones(n + 1, dtype=bool)
    total, ripple = copper_loss(w, t, sel, r_s)
    assert total == pytest.approx(1.5 * r_s * (0.25 + 4 + 0.5), rel=1e-12)
    assert ripple == pytest.approx(1.5 * r_s * 0.5, rel=1e-9)


def test_audible_torque_inside_the_windows_is_weighted_at_the_window_rate():
    n, step, sigma = 500, 2e-4, 0.03
    w, t = windows_of(np.full(n, 4.0), np.full(n, sigma ** 2), step)
    assert audible_torque(w, t, np.ones(n + 1, dtype=bool)) == pytest.approx(sigma * float(a_weighting(5000.0)),
                                                                             rel=1e-9)


def test_audible_torque_of_a_1khz_variation_of_the_window_means():
    """A 1 kHz sine of amplitude a on the bin grid: a / sqrt(2), A-weighted (about 1 at 1 kHz)."""
    n, step, a = 2000, 5e-5, 0.2
    means = 3.0 + a * np.sin(2 * np.pi * 1000 * step * np.arange(n))
    w, t = windows_of(means, np.zeros(n), step)
    expect = a / math.sqrt(2) * float(a_weighting(1000.0))
    assert audible_torque(w, t, np.ones(n + 1, dtype=bool)) == pytest.approx(expect, rel=5e-3)


def test_audible_torque_leaves_out_what_is_below_20hz():
    n, step, a = 2000, 5e-4, 0.2                                   # 1 s, a 5 Hz sine
    means = a * np.sin(2 * np.pi * 5 * step * np.arange(n))
    w, t = windows_of(means, np.zeros(n), step)
    assert audible_torque(w, t, np.ones(n + 1, dtype=bool)) < 1e-3 * a


def test_a_stretch_of_only_the_first_window_is_refused():
    w, t = windows_of(np.zeros(3), np.zeros(3), 1e-4)
    sel = np.array([True, False, False, False])
    with pytest.raises(ValueError, match="no window after the first"):
        copper_loss(w, t, sel, 1.0)
