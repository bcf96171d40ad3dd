"""The algebraic saturation model of a synchronous reluctance machine, vectorised, and its fit to measurements.

The model (Hinkkanen et al., IEEE TIA 2017; the plant's ``MAG_ALGEBRAIC``, golden/plant/src/plant.c) gives the
currents from the flux linkages (no magnet: ``x = psi_d``, ``y = psi_q``; d the axis of lower inductance)::

    i_d = (a_d0 + a_dd |x|^S + a_dq / (V + 2) |x|^U |y|^(V + 2)) x
    i_q = (a_q0 + a_qq |y|^T + a_dq / (U + 2) |x|^(U + 2) |y|^V) y

with coefficients ``a_* >= 0`` and integer exponents. Its Jacobian is the inverse incremental inductance matrix.
:func:`fit_inductances` fits the coefficients, and the exponents from :data:`EXPONENTS`, to incremental inductances
measured at currents (the commissioning's map and its low-frequency chords, docs/commissioning.md): the controller of
a reluctance machine needs flux maps, and the measured points are too few and too far apart to interpolate (the 003
SyRM's d inductance falls from 1 H to 0.05 H within 0.5 A). scripts/fit_syrm_preset.py fits the same model to the
003 paper's flux curves for the plant's preset.
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass

import numpy as np

COEF_NAMES = ("a_d0", "a_dd", "a_q0", "a_qq", "a_dq")
EXPONENT_NAMES = ("S", "T", "U", "V")
EXPONENT_RANGE = {"S": (1, 8), "T": (1, 8), "U": (0, 2), "V": (0, 2)}
"""The exponents :func:`fit_inductances` may choose (self-saturation 1..8, cross-saturation 0..2 on each axis)."""
EXPONENT_START = {"S": 1, "T": 5, "U": 0, "V": 1}
"""Where its search starts: Hinkkanen et al.'s exponents for a SyRM (their d axis, the high-inductance one, is the
plant's q: their S = 5, T = 1, U = 1, V = 0 are T, S, V, U here)."""
LOG_COEF_LIMIT = 30.0
"""The fit keeps each coefficient within exp(+-30) (a diverging fit otherwise overflows)."""


def currents(c: dict, psi_d, psi_q):
    """Currents ``(i_d, i_q)`` [A] of the model ``c`` (coefficients and exponents) at fluxes ``(psi_d, psi_q)``."""
    x, y = np.asarray(psi_d, float), np.asarray(psi_q, float)
    ax, ay = np.abs(x), np.abs(y)
    i_d = (c["a_d0"] + c["a_dd"] * ax ** c["S"] + c["a_dq"] / (c["V"] + 2) * ax ** c["U"] * ay ** (c["V"] + 2)) * x
    i_q = (c["a_q0"] + c["a_qq"] * ay ** c["T"] + c["a_dq"] / (c["U"] + 2) * ax ** (c["U"] + 2) * ay ** c["V"]) * y
    return i_d, i_q


def jacobian(c: dict, psi_d, psi_q):
    """``d(i_d, i_q)/d(psi_d, psi_q)``, the inverse incremental inductance matrix: ``(g_dd, g_dq, g_qq)``
    (``g_dq = di_d/dpsi_q = di_q/dpsi_d``, the model derives from an energy)."""
    x, y = np.asarray(psi_d, float), np.asarray(psi_q, float)
    ax, ay = np.abs(x), np.abs(y)
    S, T, U, V = (c[k] for k in EXPONENT_NAMES)
    g_dd = c["a_d0"] + c["a_dd"] * (S + 1) * ax ** S + c["a_dq"] / (V + 2) * (U + 1) * ax ** U * ay ** (V + 2)
    g_qq = c["a_q0"] + c["a_qq"] * (T + 1) * ay ** T + c["a_dq"] / (U + 2) * (V + 1) * ax ** (U + 2) * ay ** V
    g_dq = c["a_dq"] * ax ** U * x * ay ** V * y
    return g_dd, g_dq, g_qq


def fluxes(c: dict, i_d, i_q, tol: float = 1e-13, max_iter: int = 200, start=None):
    """The fluxes ``(psi_d, psi_q)`` [V*s] at which the model carries the currents ``(i_d, i_q)``: Newton's method
    with backtracking from ``start`` (fluxes of the same shape; default the unsaturated inductances', above the root
    on each axis: the model's energy is convex, the root unique), vectorised. RuntimeError when it does not
    converge."""
    i_d, i_q = np.broadcast_arrays(np.asarray(i_d, float), np.asarray(i_q, float))
    if start is None:
        x, y = i_d / c["a_d0"], i_q / c["a_q0"]
    else:
        x, y = np.array(start[0], float), np.array(start[1], float)
    for _ in range(max_iter):
        r_d, r_q = currents(c, x, y)
        r_d, r_q = r_d - i_d, r_q - i_q
        res = np.hypot(r_d, r_q)
        if np.all(res < tol * (1.0 + np.hypot(i_d, i_q))):
            return x, y
        g_dd, g_dq, g_qq = jacobian(c, x, y)
        det = g_dd * g_qq - g_dq * g_dq
        dx, dy = (g_qq * r_d - g_dq * r_q) / det, (g_dd * r_q - g_dq * r_d) / det
        step = np.ones_like(x)
        for _ in range(30):                      # accept a step only where it lowers the residual
            n_d, n_q = currents(c, x - step * dx, y - step * dy)
            bad = np.hypot(n_d - i_d, n_q - i_q) > res
            if not np.any(bad):
                break
            step = np.where(bad, 0.5 * step, step)
        x, y = x - step * dx, y - step * dy
    raise RuntimeError("flux inversion did not converge")


def levenberg_marquardt(residuals, theta: np.ndarray, iters: int = 60, rtol: float = 1e-6,
                        step_tol: float = 0.0) -> tuple[np.ndarray, float]:
    """Minimise ``|residuals(theta)|^2`` (Levenberg-Marquardt, forward-difference Jacobian) until a step lowers it
    by less than ``rtol`` of itself or moves no parameter by ``step_tol``, or ``iters`` steps; returns ``theta`` and
    the residuals' RMS. A ``residuals`` that raises RuntimeError (no solution there) counts as a rejected step."""
    theta = np.asarray(theta, float)
    r = residuals(theta)
    lam = 1e-2
    for _ in range(iters):
        jac = np.empty((r.size, theta.size))
        for k in range(theta.size):
            d = np.zeros_like(theta)
            d[k] = 1e-6
            jac[:, k] = (residuals(theta + d) - r) / 1e-6
        a, g = jac.T @ jac, jac.T @ r
        improved = False
        for _ in range(20):
            step = np.linalg.solve(a + lam * np.diag(np.diag(a) + 1e-12), -g)
            try:
                r_new = residuals(theta + step)
            except RuntimeError:
                lam *= 10.0
                continue
            if r_new @ r_new < r @ r:
                gain = 1.0 - (r_new @ r_new) / (r @ r)
                theta, r, lam, improved = theta + step, r_new, max(lam / 3.0, 1e-9), True
                break
            lam *= 10.0
        if not improved or gain < rtol or np.max(np.abs(step)) < step_tol:
            break
    return theta, float(np.sqrt(r @ r / r.size))


@dataclass(frozen=True)
class InductanceData:
    """What the fit is given. ``points``: rows ``(i_d, i_q, L_dd, L_dq, L_qq, w_dd, w_dq, w_qq)``, the incremental
    inductance matrix [H] measured at the currents [A] with a weight per entry (0: not used); ``chords``: rows
    ``(axis, i_lo, i_hi, L, w)``, a chord inductance ``(psi(i_hi) - psi(i_lo)) / (i_hi - i_lo)`` along ``axis``
    (0: d, 1: q; the other current zero)."""

    points: np.ndarray
    chords: np.ndarray


def residuals(c: dict, data: InductanceData, guess: dict | None = None) -> np.ndarray:
    """Relative errors of the model's inductances against ``data``, weighted; the cross term relative to the
    geometric mean of the self inductances. ``guess``: a dict that keeps the last fluxes solved (``"psi"``) as the
    start of the next solution (a fit's steps are small: a few Newton iterations instead of tens)."""
    p, ch = data.points, data.chords
    n = len(p)
    on_q = ch[:, 0] == 1                                     # the chords' ends, solved with the points at once
    ends = np.concatenate([ch[:, 1], ch[:, 2]])
    i_d = np.concatenate([p[:, 0], np.where(np.tile(on_q, 2), 0.0, ends)])
    i_q = np.concatenate([p[:, 1], np.where(np.tile(on_q, 2), ends, 0.0)])
    psi_d, psi_q = fluxes(c, i_d, i_q, start=None if guess is None else guess.get("psi"))
    if guess is not None:
        guess["psi"] = (psi_d, psi_q)
    g_dd, g_dq, g_qq = jacobian(c, psi_d[:n], psi_q[:n])
    det = g_dd * g_qq - g_dq * g_dq
    l_dd, l_dq, l_qq = g_qq / det, -g_dq / det, g_dd / det
    psi = np.where(np.tile(on_q, 2), psi_q[n:], psi_d[n:])
    m = len(ch)
    chord = (psi[m:] - psi[:m]) / (ch[:, 2] - ch[:, 1])
    return np.concatenate([(l_dd / p[:, 2] - 1.0) * p[:, 5], (l_dq - p[:, 3]) / np.sqrt(p[:, 2] * p[:, 4]) * p[:, 6],
                           (l_qq / p[:, 4] - 1.0) * p[:, 7], (chord / ch[:, 3] - 1.0) * ch[:, 4]])


def fit_inductances(data: InductanceData, start: dict | None = None) -> tuple[dict, float]:
    """The model (coefficients and exponents) whose incremental inductances fit ``data`` best, and its RMS residual.

    For a set of exponents, a Levenberg-Marquardt fit of the logarithms of the coefficients (so they stay positive);
    the exponents by a descent over :data:`EXPONENT_RANGE` from ``start`` (default :data:`EXPONENT_START`): each
    pass fits the sets one exponent away (+-1) from the best so far, each from the best's coefficients, and moves to
    the best of them while it lowers the residual (a search of all 576 sets takes minutes; this one 20-40 fits)."""
    p = data.points
    coefs = np.log([1.0 / np.max(p[:, 2]), 100.0, 1.0 / np.max(p[:, 4]), 1.0, 1.0])

    def fit(exps: dict, theta0: np.ndarray):
        guess: dict = {}

        def res(theta):
            if np.max(np.abs(theta)) > LOG_COEF_LIMIT:
                raise RuntimeError("coefficient out of range")
            with np.errstate(all="ignore"):
                r = residuals({**dict(zip(COEF_NAMES, np.exp(theta))), **exps}, data, guess)
            if not np.all(np.isfinite(r)):
                raise RuntimeError("no finite residual")
            return r
        try:
            return levenberg_marquardt(res, theta0)
        except RuntimeError:                          # no flux solution at the start: this set cannot be judged
            return theta0, np.inf

    exps = dict(start or EXPONENT_START)
    theta, rms = fit(exps, coefs)
    tried = {tuple(exps.values())}
    while True:
        moves = []
        for name, step in itertools.product(EXPONENT_NAMES, (-1, 1)):
            e = dict(exps, **{name: exps[name] + step})
            lo, hi = EXPONENT_RANGE[name]
            if lo <= e[name] <= hi and tuple(e.values()) not in tried:
                tried.add(tuple(e.values()))
                moves.append((e, *fit(e, theta)))
        if not moves:
            break
        e, th, r = min(moves, key=lambda m: m[2])
        if r >= rms:
            break
        exps, theta, rms = e, th, r
    if not np.isfinite(rms):
        raise RuntimeError("no exponent set gave a model that fits the measured inductances")
    return {**dict(zip(COEF_NAMES, (float(v) for v in np.exp(theta)))), **exps}, rms
