"""Flux maps: inversion of the plant's magnetic models and flux-map tables.

The plant's state is the rotor-frame flux linkage; its magnetic models give currents from fluxes
(``i = f(psi)``). Measured flux maps are the other way round (``psi = Lambda(i)``, as in
Varatharajan et al. 2020, Fig. 2). This module inverts either direction with Newton's method and
builds the plant's ``MAG_TABLE`` (currents on a regular flux grid) from any model or measured map.
"""

from __future__ import annotations

import numpy as np

from golden.plant.binding import MAG_KINDS, PlantError, mag_eval


BACKTRACK_ITER = 400
"""Steps of :func:`psi_from_current`'s second, backtracking attempt."""


def psi_from_current(mag: dict, i_d: float, i_q: float, tol: float = 1e-13, max_iter: int = 60) -> np.ndarray:
    """Flux linkages ``[psi_d, psi_q]`` at which the model ``mag`` carries the currents (i_d, i_q).

    Newton's method on ``f(psi) - i`` with the model's analytic Jacobian, from the linear guess, each step damped
    to 0.5 V*s at most. When that does not converge within ``max_iter`` steps (a stiff model, e.g. a controller's
    saturation model with an extreme coefficient, cycles), it starts again halving each step while it does not
    lower the residual, for up to ``BACKTRACK_ITER`` steps (the models it converged on before keep their results).
    """
    target = np.array([i_d, i_q], dtype=float)
    for backtrack, n_iter in ((False, max_iter), (True, BACKTRACK_ITER)):
        psi = np.array([mag.get("psi_f", 0.0), 0.0])
        out = mag_eval(mag, psi[0], psi[1])
        for _ in range(n_iter):
            resid = out[:2] - target
            if np.max(np.abs(resid)) <= tol * max(1.0, np.max(np.abs(target))):
                return psi
            step = np.linalg.solve(out[2:].reshape(2, 2), resid)
            # damp steps that would jump too far on a strongly saturating curve
            scale = min(1.0, 0.5 / max(np.max(np.abs(step)), 1e-300))
            trial = psi - scale * step
            out_t = mag_eval(mag, trial[0], trial[1])
            for _ in range(60 if backtrack else 0):
                if np.all(np.isfinite(out_t)) and np.linalg.norm(out_t[:2] - target) < np.linalg.norm(resid):
                    break
                scale *= 0.5
                trial = psi - scale * step
                out_t = mag_eval(mag, trial[0], trial[1])
            psi, out = trial, out_t
    raise PlantError(f"flux map inversion did not converge at i = ({i_d}, {i_q})")


def incremental_inductance(mag: dict, psi_d: float, psi_q: float) -> np.ndarray:
    """Incremental inductance matrix ``d(psi)/d(i)`` (2x2) at the given flux linkages."""
    return np.linalg.inv(mag_eval(mag, psi_d, psi_q)[2:].reshape(2, 2))


def table_from_model(mag: dict, psid_grid: np.ndarray, psiq_grid: np.ndarray) -> dict:
    """A ``MAG_TABLE`` parameter set sampling the model ``mag`` on a regular flux grid."""
    psid_grid, psiq_grid = np.asarray(psid_grid, float), np.asarray(psiq_grid, float)
    _check_grid(psid_grid, "psid_grid")
    _check_grid(psiq_grid, "psiq_grid")
    i_d = np.empty((len(psiq_grid), len(psid_grid)))
    i_q = np.empty_like(i_d)
    for r, pq in enumerate(psiq_grid):
        for c, pd in enumerate(psid_grid):
            out = mag_eval(mag, pd, pq)
            i_d[r, c], i_q[r, c] = out[0], out[1]
    return _table(mag.get("psi_f", 0.0), psid_grid, psiq_grid, i_d, i_q)


def table_from_flux_map(id_grid, iq_grid, psi_d_map, psi_q_map, psid_grid, psiq_grid) -> dict:
    """A ``MAG_TABLE`` from a measured flux map ``psi_d_map[iq, id], psi_q_map[iq, id]``.

    The map is interpolated bilinearly and inverted by Newton's method at every point of the
    (psid_grid, psiq_grid) flux grid. ``psi_f`` is set to the d flux at zero current.
    """
    id_grid, iq_grid = np.asarray(id_grid, float), np.asarray(iq_grid, float)
    psi_d_map, psi_q_map = np.asarray(psi_d_map, float), np.asarray(psi_q_map, float)
    for grid, name in ((id_grid, "id_grid"), (iq_grid, "iq_grid"), (psid_grid, "psid_grid"),
                       (psiq_grid, "psiq_grid")):
        _check_grid(np.asarray(grid, float), name)
    shape = (len(iq_grid), len(id_grid))
    if psi_d_map.shape != shape or psi_q_map.shape != shape:
        raise PlantError(f"flux maps must have shape (len(iq_grid), len(id_grid)) = {shape}")
    forward = {"kind": MAG_KINDS["table"], "tab_nd": len(id_grid), "tab_nq": len(iq_grid),
               "tab_psid0": id_grid[0], "tab_dpsid": id_grid[1] - id_grid[0],
               "tab_psiq0": iq_grid[0], "tab_dpsiq": iq_grid[1] - iq_grid[0],
               "tab_id": psi_d_map.ravel(), "tab_iq": psi_q_map.ravel()}
    # the forward map psi(i) has the same bilinear form as the plant's table, so mag_eval evaluates it
    psi_f = mag_eval(forward, 0.0, 0.0)[0]
    i_d = np.empty((len(psiq_grid), len(psid_grid)))
    i_q = np.empty_like(i_d)
    for r, pq in enumerate(psiq_grid):
        for c, pd in enumerate(psid_grid):
            cur = np.zeros(2)
            for _ in range(60):
                out = mag_eval(forward, cur[0], cur[1])
                resid = out[:2] - (pd, pq)
                if np.max(np.abs(resid)) < 1e-13:
                    break
                cur = cur - np.linalg.solve(out[2:].reshape(2, 2), resid)
            else:
                raise PlantError(f"flux map is not invertible at psi = ({pd}, {pq})")
            i_d[r, c], i_q[r, c] = cur
    return _table(psi_f, np.asarray(psid_grid, float), np.asarray(psiq_grid, float), i_d, i_q)


def _check_grid(grid: np.ndarray, name: str) -> None:
    if grid.ndim != 1 or len(grid) < 2:
        raise PlantError(f"{name} needs at least 2 points")
    step = np.diff(grid)
    if np.any(step <= 0) or not np.allclose(step, step[0], rtol=1e-9, atol=0.0):
        raise PlantError(f"{name} must be increasing and evenly spaced")


def _table(psi_f, psid_grid, psiq_grid, i_d, i_q) -> dict:
    return {"kind": MAG_KINDS["table"], "psi_f": float(psi_f),
            "tab_nd": len(psid_grid), "tab_nq": len(psiq_grid),
            "tab_psid0": float(psid_grid[0]), "tab_dpsid": float(psid_grid[1] - psid_grid[0]),
            "tab_psiq0": float(psiq_grid[0]), "tab_dpsiq": float(psiq_grid[1] - psiq_grid[0]),
            "tab_id": i_d.ravel(), "tab_iq": i_q.ravel()}
