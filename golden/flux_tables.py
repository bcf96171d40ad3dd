"""Host side: the controller's flux-map tables, made from the plant's magnetic model.

Varatharajan et al. 2020 identify the flux maps on a test bench (Fig. 2) and give the controller the same
maps as look-up tables ("accurate flux maps are assumed"). Here the maps come from the plant's own
model (docs/motors.md 5), sampled on the firmware's grid; a robustness case scales them
(``map_scale_d``, ``map_scale_q``: the controller's map is the true one times these factors).

* :func:`flux_lut`: ``Lambda(i)`` on the first quadrant (:mod:`golden.firmware.flux_lut`);
* :func:`mtpa_point`: the maximum-torque-per-ampere point of a current magnitude on the map;
* :func:`flux_reference_table`: the MTPA flux over the current magnitude with the minimum d flux
  (:mod:`golden.firmware.fcs_law`);
* :func:`nominal_motor`: the linear data the controller's other tunings take (``L_d``, ``L_q``, ``psi_f``,
  the torque per ampere), from the linear model's own values or, for a map, at a stated operating point;
* :func:`hf_inductances`: the inductances an HF injection meets at rest with a given d-current.
"""

from __future__ import annotations

import math

from golden.firmware.flux_lut import LUT_MAX_AXIS, LUT_MAX_POINTS, FluxLut, unwarp, warp
from golden.firmware.mtpa import table_grid
from golden.fixed import to_fixed
from golden.plant.binding import MAG_KINDS
from golden.plant.fluxmap import incremental_inductance, psi_from_current

_GOLD = (math.sqrt(5) - 1) / 2


def is_linear(mag: dict) -> bool:
    """Whether the magnetic model's ``L_d``, ``L_q``, ``psi_f`` describe the machine (linear and d-saturating
    PMSM models); a reluctance map (algebraic, table) has only the map."""
    return mag["kind"] in (MAG_KINDS["linear"], MAG_KINDS["dsat"])


def mtpa_point(mag: dict, i_s: float, pole_pairs: int) -> tuple[float, float, float, float, float]:
    """``(i_d, i_q, psi_d, psi_q, torque)`` of the MTPA point of the current magnitude ``i_s`` >= 0 [A] on the
    map (``i_d <= 0``, ``i_q >= 0``, the plant's frame): a golden-section search of the current angle in
    ``(0, 90 deg)`` for the largest ``1.5 p (psi_d i_q - psi_q i_d)``."""
    if i_s <= 0:
        return 0.0, 0.0, 0.0, 0.0, 0.0

    def torque(a: float):
        i_d, i_q = -i_s * math.cos(a), i_s * math.sin(a)
        psi = psi_from_current(mag, i_d, i_q)
        return 1.5 * pole_pairs * (psi[0] * i_q - psi[1] * i_d), i_d, i_q, psi

    lo, hi = 1e-4, math.pi / 2 - 1e-4
    for _ in range(60):
        a1, a2 = hi - _GOLD * (hi - lo), lo + _GOLD * (hi - lo)
        if torque(a1)[0] < torque(a2)[0]:
            lo = a1
        else:
            hi = a2
    t, i_d, i_q, psi = torque(0.5 * (lo + hi))
    return i_d, i_q, float(psi[0]), float(psi[1]), t


def flux_lut(mag: dict, i_lsb: float, flux_lsb: float, step: float, knee: float, coarse: int, max_d: float,
             max_q: float, scale_d: float = 1.0, scale_q: float = 1.0) -> FluxLut:
    """The firmware's flux LUT: grid step ``step`` [A] rounded to a power of two of ``i_lsb`` up to ``knee``
    [A] (rounded to a grid point), ``2^coarse`` times that beyond, covering ``0..max_d`` and ``0..max_q`` [A]; values ``Lambda / flux_lsb`` times the scale factors, and the incremental inductances
    (the model's Jacobian, inverted, at each point: eq. (12) with ``delta i -> 0``) as flux per grid step,
    scaled the same way (``l_dq`` by the geometric mean of the factors). Raises ValueError if the grid
    needs more than ``LUT_MAX_AXIS`` points on an axis or ``LUT_MAX_POINTS`` in all, or a value leaves s32."""
    shift = max(round(math.log2(step / i_lsb)), 0)
    h = (1 << shift) * i_lsb
    k = round(knee / h) << shift
    n_d, n_q = (max(math.ceil(warp(math.ceil(m / i_lsb), k, coarse) / (1 << shift)), 1) + 1 for m in (max_d, max_q))
    if max(n_d, n_q) > LUT_MAX_AXIS or n_d * n_q > LUT_MAX_POINTS:
        raise ValueError(f"flux LUT: {n_d} x {n_q} points for lut_max_d {max_d:g} A, lut_max_q {max_q:g} A at "
                         f"lut_step {h:g} A; at most {LUT_MAX_AXIS} per axis and {LUT_MAX_POINTS} in all "
                         "(raise lut_step or lower the ranges)")
    if unwarp((max(n_d, n_q) - 1) << shift, k, coarse) > 32767:
        raise ValueError(f"flux LUT: {max(max_d, max_q):g} A is beyond the current range "
                         f"{32767 * i_lsb:g} A (sensors.adc_range)")
    cell = (1 << shift) * i_lsb / flux_lsb                # flux units per grid step per henry
    tabs = ([], [], [], [], [])                           # floats first, then s16 with a shift per kind
    for r in range(n_q):
        for c in range(n_d):
            psi = psi_from_current(mag, unwarp(c << shift, k, coarse) * i_lsb, unwarp(r << shift, k, coarse) * i_lsb)
            l = incremental_inductance(mag, psi[0], psi[1])
            for tab, v in zip(tabs, (scale_d * psi[0] / flux_lsb, scale_q * psi[1] / flux_lsb, scale_d * l[0, 0] * cell,
                                     scale_q * l[1, 1] * cell, (scale_d * scale_q) ** 0.5 * l[0, 1] * cell)):
                tab.append(float(v))

    def to_s16(group):                                    # one shift for the group, values in s16
        top = max(abs(v) for tab in group for v in tab)
        sh = max(to_fixed(top, 0).bit_length() - 15, 0)
        return sh, [tuple(to_fixed(v / 2**sh, 0) for v in tab) for tab in group]

    f_shift, (t_d, t_q) = to_s16(tabs[:2])
    t_ld, t_lq, t_ldq = (tuple(to_fixed(v, 0) for v in tab) for tab in tabs[2:])
    l_shift = max(max(map(abs, t_ld + t_lq + t_ldq)).bit_length() - 15, 0)
    if f_shift > 16 or l_shift > 16:
        raise ValueError("flux LUT: the map's flux beyond 2^31 flux units (the motor's flux for this voltage scale)")
    return FluxLut(n_d, n_q, shift, k, coarse, f_shift, l_shift, t_d, t_q, t_ld, t_lq, t_ldq)


def flux_reference_table(mag: dict, pole_pairs: int, i_lsb: float, flux_lsb: float, i_max: int,
                         flux_min: float, points: int = 33) -> tuple[int, tuple[int, ...], tuple[int, ...]]:
    """``(shift, t_d, t_q)``: the MTPA flux ``(psi_d <= 0, |psi_q|)`` [flux units] over the current magnitude
    ``0..i_max`` [current LSB] on a power-of-two grid of at most ``points`` points, with ``|psi_d| >=
    flux_min`` [V*s] (:mod:`golden.firmware.fcs_law`)."""
    shift, n = table_grid(i_max, points, "flux reference table")
    t_d, t_q = [], []
    for k in range(n):
        _, _, psi_d, psi_q, _ = mtpa_point(mag, min(k << shift, 32767) * i_lsb, pole_pairs)
        t_d.append(-to_fixed(max(abs(psi_d), flux_min) / flux_lsb, 0))
        t_q.append(to_fixed(abs(psi_q) / flux_lsb, 0))
    return shift, tuple(t_d), tuple(t_q)


def nominal_motor(mag: dict, pole_pairs: int, i_nom: float) -> dict:
    """``{"L_d", "L_q", "psi_f", "k_t"}``: a linear model's own values (``k_t = 1.5 p psi_f``; without a magnet,
    the torque per ampere of its MTPA point at ``i_nom`` [A], which needs ``L_q > L_d``: ValueError otherwise),
    or, for a map, the apparent inductances ``psi / i`` and the torque per ampere of the MTPA point (``psi_f =
    0``)."""
    if is_linear(mag):
        nom = {"L_d": mag["L_d"], "L_q": mag["L_q"], "psi_f": mag["psi_f"], "k_t": 1.5 * pole_pairs * mag["psi_f"]}
        if mag["psi_f"] == 0:
            t = mtpa_point(mag, i_nom, pole_pairs)[4]
            if not t > 0:
                raise ValueError(f"a linear model without a magnet (psi_f = 0) needs L_q > L_d to make torque "
                                 f"(L_d = {mag['L_d']:g} H, L_q = {mag['L_q']:g} H)")
            nom["k_t"] = t / i_nom
        return nom
    i_d, i_q, psi_d, psi_q, t = mtpa_point(mag, i_nom, pole_pairs)
    return {"L_d": psi_d / i_d, "L_q": psi_q / i_q, "psi_f": 0.0, "k_t": t / i_nom}


def hf_inductances(mag: dict, i_d: float) -> tuple[float, float]:
    """``(L_d, L_q)`` [H] that an HF injection meets at rest (``i_q = 0``) with the d-current ``i_d`` [A]: a linear
    model's own values (the d-saturating model's at zero current, as the HF methods' tunings took them before the
    maps), or a map's incremental inductances ``d psi / d i`` at that point. The parameter dict of a map also
    carries the defaults' ``L_d``, ``L_q`` (5.59 / 6.26 mH, whatever the machine), which must not be read: on the
    003 SyRM at the 0.3 A magnetizing current the map gives 75.9 mH / 1.02 H."""
    if is_linear(mag):
        return mag["L_d"], mag["L_q"]
    psi = psi_from_current(mag, i_d, 0.0)
    m = incremental_inductance(mag, float(psi[0]), float(psi[1]))
    return float(m[0, 0]), float(m[1, 1])
