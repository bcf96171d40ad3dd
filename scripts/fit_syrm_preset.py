#!/usr/bin/env python3
"""Fit the MAG_ALGEBRAIC coefficients of the ``varatharajan2020_syrm`` preset (``golden/motors.py``).

The 003 paper (Varatharajan et al. 2020, Table I: 1.1 kW, 1500 r/min, 7.1 N*m, 340 V, 2.3 A,
2 pole pairs) shows its flux maps only as curves (Figs. 2-3). This script turns a written description of
those curves into target points, fits the algebraic saturation model of Hinkkanen et al. (IEEE TIA 2017)
to them and prints the coefficients that ``golden/motors.py`` holds as literals, with the checks quoted in
``docs/motors.md``. It needs numpy only (matplotlib for ``--plot``).

Everything here is in the convention of the plant (``golden/plant/src/plant_api.h``): d = the axis of
LOWER inductance (the 003 paper's q axis, the one with the ribs), q = the axis of higher inductance
(the paper's d axis). Currents and fluxes are peak values of the amplitude-invariant rotor frame.

The model gives currents from fluxes (psi_f = 0, so x = psi_d, y = psi_q)::

    i_d = (a_d0 + a_dd|x|^S + a_dq/(V+2) |x|^U |y|^(V+2)) x
    i_q = (a_q0 + a_qq|y|^T + a_dq/(U+2) |x|^(U+2) |y|^V) y

Usage::

    python scripts/fit_syrm_preset.py                  # fit, print coefficients and checks
    python scripts/fit_syrm_preset.py --plot docs/img/syrm_fluxmaps.png
"""

from __future__ import annotations

import argparse
import itertools
import math

import numpy as np

from golden.saturation_fit import COEF_NAMES, fluxes, jacobian, levenberg_marquardt

# ---- 003 paper, Table I (rated values) -----------------------------------------------------------
POLE_PAIRS = 2
R_S = 4.5                                  # [ohm]
T_RATED = 7.1                              # [N*m]
N_RATED = 1500.0                           # [r/min]
U_RATED = 340.0                            # [V] line-to-line rms
I_RATED_RMS = 2.3                          # [A] rms (see docs/motors.md: rms, not peak)
I_RATED = I_RATED_RMS * math.sqrt(2.0)     # 3.2527 A peak = |i| in the dq frame
W_E_RATED = 2.0 * math.pi * N_RATED / 60.0 * POLE_PAIRS   # 314.16 rad/s electrical
U_PHASE_PEAK = U_RATED * math.sqrt(2.0 / 3.0)              # 277.6 V peak phase


# ---- target curves (our convention), read from the description of the paper's Figs. 2-3 -----------
# q = high-inductance axis (paper d): steep rise (about 1 H at i = 0), 0.83 Vs at 1 A, then saturating
# towards 1.2 Vs.
Q_SELF = np.array([  # (i_q [A], psi_q [Vs]) at i_d = 0
    (0.25, 0.24), (0.5, 0.47), (0.75, 0.68), (1.0, 0.83), (1.25, 0.91), (1.5, 0.96), (2.0, 1.02),
    (3.0, 1.09), (4.0, 1.14), (5.0, 1.18)])
# d = low-inductance axis (paper q): the ribs carry ~0.05 Vs with a high inductance close to i = 0,
# saturate by ~0.1 A, then the flux rises slowly through the flux barriers (about 25 mH): 0.1-0.2 Vs
# at a few amperes.
D_SELF = np.array([  # (i_d [A], psi_d [Vs]) at i_q = 0 (fitted with the sign of i_d < 0)
    (0.05, 0.035), (0.1, 0.050), (0.2, 0.055), (0.5, 0.063), (1.0, 0.075), (2.0, 0.100),
    (3.0, 0.125), (4.0, 0.150), (5.0, 0.175)])
D_WEIGHT = 2.0             # the d flux is small: its errors count double
# cross-saturation: the high-axis flux drops when the low-axis current grows, 3.5 % per ampere of |i_d|
CROSS_DROP_PER_A = 0.035
CROSS_ID = (1.0, 2.0, 3.0, 4.0)
CROSS_IQ = (0.5, 1.0, 1.5, 2.0, 3.0)
CROSS_WEIGHT = 1.0
# a point near the rated operating point (|i| = I_RATED, 67 deg from the q axis), consistent with the
# curves above (0.91 Vs * (1 - 3 * 0.035) = 0.81 Vs): T = 3 (psi_d i_q - psi_q i_d) = 7.0 N*m there,
# and |psi| = 0.83 Vs gives 320 V line rms at 1500 r/min
RATED_POINT = (-3.0, 1.25, -0.125, 0.82)   # i_d, i_q, psi_d, psi_q
RATED_WEIGHT = 3.0
# the paper: "saliency disappears at no load" -> unsaturated incremental inductances l_d(0) = l_q(0);
# residual ORIGIN_WEIGHT * ln(a_d0/a_q0) (without it a_d0 is nearly undetermined by the points, and
# drifts to l_d(0) = 1.3 l_q(0) or, with other targets, to a_d0 -> 0, an infinite l_d at i = 0)
ORIGIN_WEIGHT = 0.2


# ---- the model: golden.saturation_fit (the plant's MAG_ALGEBRAIC, vectorised) ------------------------------------
def torque(c: dict, i_d, i_q):
    """Torque T = 1.5 p (psi_d i_q - psi_q i_d) [N*m] at currents ``(i_d, i_q)``."""
    psi_d, psi_q = fluxes(c, i_d, i_q)
    return 1.5 * POLE_PAIRS * (psi_d * i_q - psi_q * i_d)


def mtpa(c: dict, current: float):
    """Maximum torque per ampere at ``|i| = current``, motoring with i_d < 0 < i_q.

    Returns
    -------
    tuple of float
        ``(gamma, i_d, i_q, T)``, gamma = angle of the current from the +q axis towards -d [rad].
    """
    g = np.linspace(0.0, 0.5 * math.pi, 721)
    t = torque(c, -current * np.sin(g), current * np.cos(g))
    k = int(np.argmax(t))
    lo, hi = g[max(k - 1, 0)], g[min(k + 1, len(g) - 1)]
    phi = (math.sqrt(5.0) - 1.0) / 2.0

    def f(a):
        return float(torque(c, -current * math.sin(a), current * math.cos(a)))

    for _ in range(80):  # golden section on the bracket
        a1, a2 = hi - phi * (hi - lo), lo + phi * (hi - lo)
        if f(a1) > f(a2):
            hi = a2
        else:
            lo = a1
    a = 0.5 * (lo + hi)
    return a, -current * math.sin(a), current * math.cos(a), f(a)


def mtpa_current_for(c: dict, torque_ref: float):
    """Smallest current magnitude whose MTPA torque reaches ``torque_ref`` (bisection)."""
    lo, hi = 0.0, 20.0
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        if mtpa(c, mid)[3] < torque_ref:
            lo = mid
        else:
            hi = mid
    return 0.5 * (lo + hi)


def steady_voltage(c: dict, i_d: float, i_q: float, w_e: float = W_E_RATED):
    """Steady-state voltage vector v = R i + j w psi; returns (v_d, v_q, |v| peak phase)."""
    psi_d, psi_q = fluxes(c, i_d, i_q)
    v_d = R_S * i_d - w_e * psi_q
    v_q = R_S * i_q + w_e * psi_d
    return float(v_d), float(v_q), float(math.hypot(v_d, v_q))


def inductances(c: dict, i_d: float, i_q: float):
    """Incremental inductance matrix L = J^-1 at the currents ``(i_d, i_q)`` [H]: (l_dd, l_dq, l_qq)."""
    psi_d, psi_q = fluxes(c, i_d, i_q)
    g_dd, g_dq, g_qq = (float(v) for v in jacobian(c, psi_d, psi_q))
    det = g_dd * g_qq - g_dq * g_dq
    return g_qq / det, -g_dq / det, g_dd / det


# ---- fit --------------------------------------------------------------------------------------------
def targets():
    """Target points ``(i_d, i_q, psi_d, psi_q, w_d, w_q)``; a weight 0 leaves that flux free."""
    rows = []
    for i, p in Q_SELF:
        rows.append((0.0, i, 0.0, p, 0.0, 1.0))
    for i, p in D_SELF:
        rows.append((-i, 0.0, -p, 0.0, D_WEIGHT, 0.0))
    for i_d in CROSS_ID:
        for i_q in CROSS_IQ:
            psi_q = np.interp(i_q, Q_SELF[:, 0], Q_SELF[:, 1]) * (1.0 - CROSS_DROP_PER_A * i_d)
            rows.append((-i_d, i_q, 0.0, psi_q, 0.0, CROSS_WEIGHT))
    i_d, i_q, p_d, p_q = RATED_POINT
    rows.append((i_d, i_q, p_d, p_q, RATED_WEIGHT, RATED_WEIGHT))
    return np.array(rows)


def residuals(c: dict, tg: np.ndarray):
    psi_d, psi_q = fluxes(c, tg[:, 0], tg[:, 1])
    return np.concatenate([(psi_d - tg[:, 2]) * tg[:, 4], (psi_q - tg[:, 3]) * tg[:, 5],
                           [ORIGIN_WEIGHT * math.log(c["a_d0"] / c["a_q0"])]])


def fit(exps: dict, tg: np.ndarray, start: dict | None = None, iters: int = 200):
    """Levenberg-Marquardt on log-coefficients (keeps every coefficient > 0), flux-space residuals."""
    c0 = start or {"a_d0": 1.2, "a_dd": 100.0, "a_q0": 1.1, "a_qq": 1.0, "a_dq": 1.0}

    def mk(t):
        return {**dict(zip(COEF_NAMES, np.exp(t))), **exps}

    th, rms = levenberg_marquardt(lambda t: residuals(mk(t), tg), np.log([c0[k] for k in COEF_NAMES]), iters=iters,
                                  rtol=0.0, step_tol=1e-10)
    return mk(th), rms


def positive_definite_margin(c: dict, i_max: float = 2.0 * I_RATED):
    """Smallest det(J)/(g_dd g_qq) over currents |i_d|, |i_q| <= i_max (1 = no coupling, <= 0 = bad)."""
    g = np.linspace(-i_max, i_max, 81)
    i_d, i_q = np.meshgrid(g, g)
    psi_d, psi_q = fluxes(c, i_d, i_q)
    g_dd, g_dq, g_qq = jacobian(c, psi_d, psi_q)
    return float(np.min((g_dd * g_qq - g_dq ** 2) / (g_dd * g_qq)))


def report(c: dict):
    """Print the checks quoted in docs/motors.md."""
    print("coefficients: " + ", ".join(f"{k}={c[k]:.6g}" for k in (*COEF_NAMES, "S", "T", "U", "V")))
    l0 = inductances(c, 0.0, 0.0)
    print(f"incremental inductances at i = 0: l_d = {l0[0]*1e3:.1f} mH, l_q = {l0[2]*1e3:.1f} mH, "
          f"l_q/l_d = {l0[2]/l0[0]:.3f}")
    for i_d, i_q in ((0.0, 0.0), (0.0, 1.0), (-1.0, 0.0), (-3.0, 0.0), (0.0, 3.0)):
        p = fluxes(c, i_d, i_q)
        print(f"  psi(i_d={i_d:+.1f}, i_q={i_q:+.1f}) = ({float(p[0]):+.4f}, {float(p[1]):+.4f}) Vs")
    gam, i_d, i_q, t = mtpa(c, I_RATED)
    p = fluxes(c, i_d, i_q)
    v = steady_voltage(c, i_d, i_q)[2]
    l = inductances(c, i_d, i_q)
    print(f"MTPA at |i| = {I_RATED:.4f} A peak (2.3 A rms): gamma = {math.degrees(gam):.2f} deg from +q, "
          f"i_d = {i_d:.4f} A, i_q = {i_q:.4f} A, T = {t:.4f} N*m ({t/T_RATED*100:.1f} % of 7.1)")
    print(f"  psi = ({float(p[0]):+.4f}, {float(p[1]):+.4f}) Vs, |psi| = {float(np.hypot(*p)):.4f} Vs; at 1500 r/min "
          f"|v| = {v:.1f} V peak phase = {v*math.sqrt(1.5):.1f} V line rms (rated 340 V)")
    e = W_E_RATED * float(np.hypot(*p))
    print(f"  back-EMF w|psi| at 1500 r/min = {e:.1f} V peak phase = {e*math.sqrt(1.5):.1f} V line rms")
    r_d, r_q = round(i_d, 3), round(i_q, 3)
    print(f"  rounded rated point (golden/motors.py): i_d = {r_d}, i_q = {r_q}: T = {float(torque(c, r_d, r_q)):.4f} N*m")
    print(f"  incremental l_d = {l[0]*1e3:.1f} mH, l_q = {l[2]*1e3:.1f} mH, l_dq = {l[1]*1e3:.2f} mH, "
          f"l_q/l_d = {l[2]/l[0]:.3f}")
    i_t = mtpa_current_for(c, T_RATED)
    gam_t, i_dt, i_qt, _ = mtpa(c, i_t)
    v_t = steady_voltage(c, i_dt, i_qt)[2]
    print(f"7.1 N*m on the MTPA path needs |i| = {i_t:.4f} A peak = {i_t/math.sqrt(2):.4f} A rms "
          f"({(i_t/I_RATED-1)*100:+.1f} % vs 2.3 A rms), gamma = {math.degrees(gam_t):.2f} deg, "
          f"|v| at 1500 r/min = {v_t:.1f} V peak = {v_t*math.sqrt(1.5):.1f} V line rms")
    for cross in (1.0, 3.0):
        drop = 1.0 - float(fluxes(c, -cross, 1.25)[1] / fluxes(c, 0.0, 1.25)[1])
        print(f"cross-saturation: psi_q(i_q = 1.25 A) drops {drop*100:.1f} % at i_d = -{cross:g} A")
    for i_d_, i_q_ in ((-0.05, 0.0), (-0.2, 0.0), (0.0, 0.2), (-0.1, 0.1), (0.0, 1.0), (-1.0, 0.0)):
        l = inductances(c, i_d_, i_q_)
        print(f"  l_q/l_d at (i_d={i_d_:+.2f}, i_q={i_q_:+.2f}) = {l[2]/l[0]:.2f} "
              f"(l_d {l[0]*1e3:.0f} mH, l_q {l[2]*1e3:.0f} mH)")
    print(f"det(J) margin over |i_d|,|i_q| <= {2*I_RATED:.2f} A: {positive_definite_margin(c):.4f}")


def plot(c: dict, path: str):
    """Flux-linkage curves along each axis for several cross currents and the incremental saliency map."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(1, 3, figsize=(15, 4.6))
    i = np.linspace(0.0, 6.0, 241)
    for k, cross in enumerate((0.0, 1.0, 2.0, 3.0, 4.0)):
        col = f"C{k}"
        ax[0].plot(i, fluxes(c, -cross, i)[1], col, label=f"|i_d| = {cross:g} A")
        ax[1].plot(i, -fluxes(c, -i, cross)[0], col, label=f"i_q = {cross:g} A")
    ax[0].plot(Q_SELF[:, 0], Q_SELF[:, 1], "ko", ms=4, label="target, i_d = 0")
    ax[1].plot(D_SELF[:, 0], D_SELF[:, 1], "ko", ms=4, label="target, i_q = 0")
    ax[0].set(xlabel="i_q [A]", ylabel="psi_q [Vs]",
              title="high-inductance axis q (paper's d)")
    ax[1].set(xlabel="-i_d [A]", ylabel="-psi_d [Vs]",
              title="low-inductance axis d (paper's q, ribs)")
    for a in ax[:2]:
        a.axvline(I_RATED, color="0.6", ls=":", lw=1)
        a.grid(True, alpha=0.3)
        a.legend(fontsize=8)

    g = np.linspace(-5.0, 5.0, 101)
    i_d, i_q = np.meshgrid(g, g)
    psi_d, psi_q = fluxes(c, i_d, i_q)
    g_dd, _, g_qq = jacobian(c, psi_d, psi_q)
    sal = g_dd / g_qq  # l_q/l_d of the incremental inductance matrix L = J^-1 (l_q/l_d = g_dd/g_qq)
    levels = np.linspace(0.0, 12.0, 25)
    cs = ax[2].contourf(i_d, i_q, np.minimum(sal, 12.0), levels=levels, cmap="viridis", extend="max")
    cl = ax[2].contour(i_d, i_q, sal, levels=[1.0, 2.0, 4.0, 8.0], colors="w", linewidths=0.8)
    ax[2].clabel(cl, fmt="%g", fontsize=7)
    fig.colorbar(cs, ax=ax[2], label="incremental saliency l_q / l_d (clipped at 12)")
    curr = np.linspace(0.0, 5.0, 21)
    pts = np.array([mtpa(c, x)[1:3] for x in curr[1:]])
    ax[2].plot(np.r_[0.0, pts[:, 0]], np.r_[0.0, pts[:, 1]], "r-", lw=1.5, label="MTPA")
    th = np.linspace(0, 2 * math.pi, 200)
    ax[2].plot(I_RATED * np.cos(th), I_RATED * np.sin(th), "w--", lw=1, label="|i| = 2.3 A rms")
    _, r_d, r_q, r_t = mtpa(c, I_RATED)
    ax[2].plot([r_d], [r_q], "r*", ms=10, label=f"rated MTPA point, {r_t:.2f} N*m")
    ax[2].set(xlabel="i_d [A]", ylabel="i_q [A]", title="incremental saliency l_q/l_d", aspect="equal")
    ax[2].legend(fontsize=8, loc="lower left")
    fig.suptitle("varatharajan2020_syrm: MAG_ALGEBRAIC fit (plant convention: d = low-inductance axis)")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    print(f"wrote {path}")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--plot", metavar="PNG", help="write the flux-map figure here")
    ap.add_argument("--scan", action="store_true", help="fit every exponent set of the scan and list them")
    args = ap.parse_args()
    tg = targets()
    if args.scan:
        for S, T, (U, V) in itertools.product((1, 2, 3), (4, 5, 6, 7, 8), ((0, 0), (0, 1), (1, 0), (1, 1), (0, 2))):
            exps = {"S": S, "T": T, "U": U, "V": V}
            try:
                c, rms = fit(exps, tg)
                t = mtpa(c, I_RATED)[3]
                print(f"S={S} T={T} U={U} V={V}: rms {rms*1e3:7.2f} mVs  T_mtpa={t:.3f}  "
                      f"pd={positive_definite_margin(c):.3f}", flush=True)
            except RuntimeError as e:
                print(f"S={S} T={T} U={U} V={V}: {e}")
        return
    c, rms = fit(dict(EXPONENTS), tg)
    print(f"weighted rms flux error: {rms*1e3:.2f} mVs")
    # golden/motors.py holds the coefficients to 4 significant digits: every check uses those
    c = {k: (float(f"{v:.4g}") if k in COEF_NAMES else v) for k, v in c.items()}
    print("literal for golden/motors.py:")
    print("    " + ", ".join(f'"{k}": {c[k]!r}' for k in (*COEF_NAMES, "S", "T", "U", "V")))
    print(f"weighted rms flux error with the rounded literals: {np.sqrt(np.mean(residuals(c, tg) ** 2))*1e3:.2f} mVs")
    report(c)
    if args.plot:
        plot(c, args.plot)


EXPONENTS = {"S": 2, "T": 7, "U": 0, "V": 1}
"""Exponents of the preset (chosen from ``--scan``; see docs/motors.md)."""

if __name__ == "__main__":
    main()
