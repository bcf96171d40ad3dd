"""Estimator ``hfo_proj``: the 003 method (Varatharajan et al., IEEE Access 2020, Secs. II-B, III-C, IV).

A hybrid flux observer with flux-map look-up tables, two position-error signals formed by projection
vectors (the low-speed one from the current ripple the FCS-MPC causes, the adaptive one (APP) from the
fundamental model), their speed-dependent fusion and a PLL. It runs with the direct-vector mode
(``CTRL.DIRECT``; the control law ``fcs_mpc`` of :mod:`golden.firmware.fcs_law`), once per period, on the
carrier-top currents ``TOP_I`` (the instants the inverter state changes, spec 3.11) and the state applied
since the last top (``VECTOR``, read one step earlier). All vectors are in the plant's frame (d = the
low-inductance axis; docs/motors.md 5): the paper's q-axis projection is a d-axis projection here.

Step ``k`` (``th`` the angle predicted for top ``k``, ``w`` the PLL speed; flux in the units of
:data:`golden.firmware.flux_lut.FLUX_FRAC`):

0. the top currents corrected for the current sensors' lag ``tau`` (a first-order sensor of bandwidth
   ``f_s`` reads the current ``tau = 1/(2 pi f_s)`` late, and the top is where the slope changes):
   ``i = TOP_I + shr(c_lag (TOP_I - TOP_I_prev), 16)``, ``c_lag = tau / T`` (Q16); the slope before the
   top is the last period's change. Uncorrected, the lag shifts each difference of eq. (26) by ``tau``
   times the change of slope: 0.05 A of the low-inductance current per vector at 2 p.u. (0.8 deg of bias);

1. eq. (5), forward Euler from top ``k-1`` to top ``k``, in the stationary frame:
   ``psi += a - shr(r_f i_prev, 16) + shr(c_g (lam_prev - psi), 16)`` per component, ``a`` the flux of the
   state applied, with the dead time of the legs that switched at top ``k-1``
   (:func:`~golden.firmware.applied_flux.applied_flux`, ``dt_f``), ``i_prev`` and
   ``lam_prev`` the top current and the current model's flux at ``k-1`` (eq. (8): ``e^{J th} Lambda(
   e^{-J th} i)``), ``c_g = g T`` (Q16; g = 2 pi 10 rad/s, the cross-over of the current and voltage models);
2. the current model at top ``k``: ``i_dq`` = Park of ``TOP_I`` at ``th``, the table's flux and incremental
   inductances (:func:`~golden.firmware.flux_lut.lut_point`, eq. (12)), ``lam`` = its inverse Park;
3. the projection's coefficients for the d-projection (eqs. (28)-(30), corrected), from ``l`` and ``dl``
   normalised by the table's ``l_shift``: ``a1 = (l_d^2 - l_d l_q + 2 l_dq^2 + dl_d l_dq - dl_dq l_d) / det``, ``a2 =
   (l_dq (l_d + l_q) + dl_d l_q - dl_dq l_dq) / det`` (Q12, ``det = l_d l_q - l_dq^2``): the first row of
   ``J - l J l^-1 - dl l^-1``. Eq. (28) has only ``J - l J l^-1``: it takes ``l`` as independent of the
   position error. It is not: the table is read at the estimated-frame current, which turns with the
   error (``i_hat = e^{J err} i``), so ``l(i_hat) = l + err dl`` with ``dl`` the derivative of ``l`` along
   ``J i`` (:mod:`golden.firmware.flux_lut`), and ``e = dpsi - l(i_hat) di`` gets ``-err dl l^-1 dpsi`` more.
   Under load on a cross-saturated map that term is as large as the first: without it the gain of the
   error per applied vector ranges from -4 to +4 at 2 p.u. (wrong sign for some vector angles: the lock
   losses after the 2 p.u. step); with it, 0.9 to 1.2 for every vector at 3 deg of error
   (docs/methods.md). The strength of a flux change ``dpsi`` is ``S = round_shr(a1 dpsi_q - a2 dpsi_d, 12)``;
4. low speed, eqs. (26)-(29): **both flux changes are formed in the stationary frame** and the result is
   rotated once, at the angle of the middle of the period (``th - w_i/2``; PITFALLS: the frame decides the
   result). ``dpsi = psi_k - psi_{k-1}`` is the observer's. The current model's change ``l di`` of eq. (26)
   is taken as the map's own secant, each top current at the rotor angle of its instant: ``lam_k`` (step
   2, at ``th``) less ``lam_p``, the map at ``i_{k-1}`` turned by ``th - w_i``, back in the stationary
   frame. Two details decide the result: (a) the rotor frame turns by ``w T`` over the period, and the
   rotor-frame map's flux (1 V*s here) turns with it; taking both currents in one frame drops ``w T J
   lambda``, 4 mV*s at 190 r/min (a 10 deg bias); taking the previous step's ``lam`` instead would turn it
   by the PLL's correction too (``k_p eps``, 2.6 mV*s per 0.15 deg), so the previous instant's angle is
   ``th - w_i``, the integrator's speed; (b) one active vector swings the low-inductance current by up to
   3 A here, across the map's curvature, and a tangent ``l`` at either end misses the swing's flux by
   several per cent of the vector; the secant does not (:func:`~golden.firmware.flux_lut.lut_flux`).
   ``e_d = dpsi_d - dlam_d`` in the middle frame; the strength ``S`` of ``dpsi`` itself (eq. (29): the
   observer's flux change is at hand, the approximation ``dpsi ~ v T`` of eq. (30) is not needed here; the
   hardware's constraint uses eq. (30) on the candidate vectors); valid when ``|S| > phi_min << 8``
   (eq. (31)'s threshold), then ``eps_h = e_d / S`` (rad) for ``|S| >= s_knee`` and ``e_d S / s_knee^2``
   below it (``e_d`` saturated to s24 first), else ``eps_h = 0`` and the count of consecutive rejections
   ``n_rej`` grows; with ``hold`` a rejected period's error is instead ``th_meas - th``, ``th_meas`` the
   angle the last valid error measured (``th + eps_h``) advanced by ``w_i`` every period, for ``n_max``
   periods: zeros would cut the PLL's bandwidth by the share of rejected periods (about two thirds at
   standstill; PITFALLS), and scaling the next valid error up instead multiplies its noise (tried: kicks
   of 20-30 deg at 2 p.u.). The ratio alone amplifies the errors of ``e_d`` (the current sensors' lag and gain, the
   inverter model: about 1 mV*s) by ``1/S``: up to 10 deg per sample for a vector just above the threshold,
   the outliers that jolted the angle after the 2 p.u. step. Below ``s_knee`` (``phi_knee T``, the flux of a
   quarter of ``V_dc``) the error is the least-squares one, ``e S`` over a fixed ``S^2``: the weak vectors count
   little, none can swing the angle; ``constrain = n_rej > n_max`` while the low-speed model has weight;
5. high speed, APP, eqs. (33)-(37): ``x = park(psi, th) - lam``, the auxiliary flux of eq. (35) with its
   misprint corrected, ``lam_a = (J L^i - l J) i = (-lam_q + l_d i_q - l_dq i_d, lam_d + l_dq i_q - l_q i_d)``
   (``L^i i = Lambda(i)`` by eq. (8), so no apparent inductance is divided out), and eq. (37) written out:
   ``eps_t = (lam_a . x) / |lam_a|^2 - (g / w) (lam_a_q x_d - lam_a_d x_q) / |lam_a|^2`` (rad), with
   ``lam_a`` and ``x`` normalised to 15 bits together (``x`` saturated there);
6. fusion, eq. (38): ``f = clamp((g + w_g - |w_i|) / (2 w_g), 0, 1)`` (Q16), ``eps = f eps_h + (1 - f) eps_t``
   (each computed only where its weight is not 0); each error is limited to ``eps_max``. ``w_i =
   shr(integ, 24)`` is the PLL integrator's speed, in the fusion and in eq. (37): the PLL's output ``w``
   carries ``k_p eps``, whose noise at standstill (one limited error is 26 Hz electrical) would switch to
   the fundamental model for a period (the paper uses a filtered speed estimate);
7. PLL, eqs. (39)-(40) (``golden.firmware.pll``'s form): ``integ += ki eps``, ``w = shr(kp eps, 16) +
   shr(integ, 24)``, ``th += w``;
8. outputs: ``theta = th + shr(w k_delay, 16)``, ``k_delay`` = 1.5 periods: ``th`` is now the angle of top
   ``k + 1``, and the state chosen from this step's outputs is applied from top ``k + 2`` to top ``k + 3``
   (the commit at the next window boundary, the choice at the top after it), so ``theta`` is the angle
   in the middle of that period; ``omega = w``; the flux ``psi`` at top ``k``; ``a1, a2`` for the
   hardware's constraint (eq. (30) on the candidates, spec 3.10); ``constrain`` (eq. (31): ``n_rej >
   n_max`` while the low-speed model has weight), but **not again in the two steps after it**: the state
   chosen from this step's outputs is applied two periods on and measured one period after that, so the
   count still exceeds ``n_max`` at the next two steps although a forced strong vector is on its way; a second
   forced vector (tried) doubles the kick of the low-inductance current (two full vectors, 6 A here), and
   the two-period-late deadbeat answers with the opposite vectors: the burst that tripped the overcurrent
   limit after the 2 p.u. step.

Radians to binary angle: ``shr(x_q16 * RAD_BIN, 16)``, ``RAD_BIN = round(2^32 / 2 pi)``.
"""

from __future__ import annotations

from dataclasses import dataclass

from golden.firmware.applied_flux import applied_flux
from golden.firmware.estimator import METHOD_HFO_PROJ, Estimator, Measurement, inv_park, park
from golden.firmware.flux_lut import FLUX_FRAC, FluxLut, LutPoint, lut_flux, lut_point
from golden.fixed import c_div, round_shr, sat, shr, uwrap, wrap
from golden.fpga.cordic import sincos_q15

RAD_BIN = 683565276
"""round(2^32 / 2 pi): binary angle per radian."""
ONE_Q16 = 1 << 16


@dataclass(frozen=True)
class HfoParams:
    """Integers of the estimator (host side: :func:`golden.control_config.hfo_proj_params`).

    ``lut``: the flux map; ``c_lag``: the current sensors' lag over the period (Q16, step 0); ``r_f``: ``R_s`` as flux per period per current LSB (Q16); ``dt_f``, ``vth_f``: ``V_dc t_d`` and
    ``V_th T`` [flux units] (:mod:`golden.firmware.applied_flux`); ``c_g``: ``g T``
    (Q16); ``phi_min``:
    eq. (31)'s threshold [voltage LSB]; ``s_knee``: the strength below which the low-speed error is
    weighted [flux units, 1..2^23]; ``n_max``: eq. (31)'s count; ``g_b``, ``wg_b``: ``g`` and
    ``omega_g`` [binary angle per period], ``wg_b`` >= 1; ``kp``, ``ki``: PLL gains (Q16, Q24; eq. (40));
    ``k_delay``: periods from the next top to the output angle (Q16); ``eps_max``: the limit of each error
    [binary angle]; ``hold``: 1 = a rejected period's error is that of the angle the last valid one
    measured, advanced by the speed (for ``n_max`` periods), 0 = the paper's zeros."""

    lut: FluxLut
    c_lag: int
    r_f: int
    dt_f: int
    vth_f: int
    c_g: int
    phi_min: int
    s_knee: int
    n_max: int
    g_b: int
    wg_b: int
    kp: int
    ki: int
    k_delay: int
    eps_max: int
    hold: int


class HybridFluxProjection(Estimator):
    """Hybrid flux observer, projection vectors, fusion and PLL (module docstring)."""

    METHOD = METHOD_HFO_PROJ
    PARAMS = "hfo"

    def __init__(self, p: HfoParams):
        self.p = p
        self.th = 0                      # angle predicted for the next carrier top (u32)
        self.integ = 0
        self.psi_al = self.psi_be = 0    # observed stator flux at the last top (stationary frame)
        self.lam_al = self.lam_be = 0    # the current model's flux at the last top
        self.i_al = self.i_be = 0        # the last top currents (lag-corrected)
        self.r_al = self.r_be = 0        # and as sampled
        self.vec = 0                     # the state applied since the last top (VECTOR of the last step)
        self.vec_old = 0                 # the state before it
        self.n_rej = 0
        self.since = 0                   # periods since the last valid low-speed error
        self.th_meas = 0                 # the angle the last valid error measured, advanced by the speed
        self.eps_h = self.eps_t = self.f = 0
        self.e_d = self.s_h = 0          # diagnostics: the last low-speed error and strength [flux units]
        self.theta = self.omega = 0
        self.fcs_a1 = self.fcs_a2 = self.constrain = 0
        self.cons_wait = 0               # steps before the constraint may be set again

    def step(self, m: Measurement) -> None:
        p, lut = self.p, self.p.lut
        w_i = shr(self.integ, 24)                                   # the PLL's integral: its speed estimate
        r_al, r_be = m.win.top_ia, m.win.top_ib                     # TOP_I, as sampled
        i_al = r_al + shr(p.c_lag * (r_al - self.r_al), 16)          # the current at the top (step 0)
        i_be = r_be + shr(p.c_lag * (r_be - self.r_be), 16)
        a_al, a_be = applied_flux(self.vec_old, self.vec, self.i_al, self.i_be, p.dt_f, p.vth_f)
        # 1. eq. (5): the hybrid flux observer, forward Euler from the last top
        psi_al = sat(self.psi_al + a_al - shr(p.r_f * self.i_al, 16)
                     + shr(p.c_g * (self.lam_al - self.psi_al), 16), 32)
        psi_be = sat(self.psi_be + a_be - shr(p.r_f * self.i_be, 16)
                     + shr(p.c_g * (self.lam_be - self.psi_be), 16), 32)
        # 2. the current model at this top (eqs. (8), (12))
        s, c = sincos_q15(self.th)
        i_d, i_q = park(i_al, i_be, s, c)
        pt = lut_point(lut, i_d, i_q)
        lam_al, lam_be = inv_park(pt.lam_d, pt.lam_q, s, c)
        # 3. eq. (30)'s coefficients, d-projection (the plant's low-inductance axis)
        a1, a2 = projection_coefficients(pt, lut.l_shift)
        # 6. fusion weight (eq. (38b))
        f = min(max(c_div((p.g_b + p.wg_b - abs(w_i)) << 16, 2 * p.wg_b), 0), ONE_Q16)
        # 4. low speed: differences in the stationary frame, rotated at the middle of the period
        eps_h = 0
        valid = False
        self.e_d = self.s_h = 0
        if f > 0:
            sp, cp = sincos_q15(uwrap(self.th - w_i, 32))
            lp_al, lp_be = inv_park(*lut_flux(lut, *park(self.i_al, self.i_be, sp, cp)), sp, cp)
            sm, cm = sincos_q15(uwrap(self.th - shr(w_i, 1), 32))
            dpd, dpq = park(psi_al - self.psi_al, psi_be - self.psi_be, sm, cm)
            dld, _ = park(lam_al - lp_al, lam_be - lp_be, sm, cm)
            e_d = dpd - dld
            strength = round_shr(a1 * dpq - a2 * dpd, 12)            # eq. (29): phi_qh^-1 T
            valid = abs(strength) > (p.phi_min << FLUX_FRAC)
            if valid:
                if abs(strength) >= p.s_knee:
                    q = c_div(e_d << 16, strength)
                else:
                    q = c_div((sat(e_d, 24) * strength) << 16, p.s_knee * p.s_knee)
                eps_h = self._limit(_to_bin(sat(q, 32)))
                self.th_meas = uwrap(self.th + eps_h, 32)
            elif p.hold and self.since < p.n_max:
                eps_h = self._limit(wrap(self.th_meas - self.th, 32))
            self.e_d, self.s_h = e_d, strength
        self.n_rej = 0 if valid else min(self.n_rej + 1, 1 << 16)
        self.since = 0 if valid else min(self.since + 1, 1 << 16)
        self.th_meas = uwrap(self.th_meas + w_i, 32)
        # 5. high speed: APP (eqs. (33)-(37))
        eps_t = 0
        if f < ONE_Q16 and w_i != 0:
            pd, pq = park(psi_al, psi_be, s, c)
            x_d, x_q = pd - pt.lam_d, pq - pt.lam_q
            a_d = -pt.lam_q + shr(pt.l_d * i_q - pt.l_dq * i_d, lut.shift)
            a_q = pt.lam_d + shr(pt.l_dq * i_q - pt.l_q * i_d, lut.shift)
            nb = max(max(abs(a_d), abs(a_q)).bit_length() - 15, 0)
            a_d, a_q = shr(a_d, nb), shr(a_q, nb)
            x_d, x_q = sat(shr(x_d, nb), 16), sat(shr(x_q, nb), 16)
            sq = a_d * a_d + a_q * a_q
            if sq > 0:
                q1 = sat(c_div((a_d * x_d + a_q * x_q) << 16, sq), 21)
                q2 = sat(c_div((a_q * x_d - a_d * x_q) << 16, sq), 21)
                eps_t = self._limit(_to_bin(sat(q1 - c_div(q2 * p.g_b, w_i), 32)))
        eps = sat(shr(f * eps_h + (ONE_Q16 - f) * eps_t, 16), 32)
        # 7. PLL (eqs. (39)-(40))
        self.integ = sat(self.integ + p.ki * eps, 64)
        w = sat(shr(p.kp * eps, 16) + shr(self.integ, 24), 32)
        self.th = uwrap(self.th + w, 32)
        # 8. state and outputs
        self.psi_al, self.psi_be, self.lam_al, self.lam_be = psi_al, psi_be, lam_al, lam_be
        self.i_al, self.i_be, self.vec_old, self.vec = i_al, i_be, self.vec, m.win.vector
        self.r_al, self.r_be = r_al, r_be
        self.eps_h, self.eps_t, self.f = eps_h, eps_t, f
        self.fcs_a1, self.fcs_a2 = a1, a2
        self.constrain = int(f > 0 and self.n_rej > p.n_max and self.cons_wait == 0)
        self.cons_wait = 2 if self.constrain else max(self.cons_wait - 1, 0)
        self.omega = w
        self.theta = uwrap(self.th + shr(w * p.k_delay, 16), 32)

    def _limit(self, e: int) -> int:
        return min(max(e, -self.p.eps_max), self.p.eps_max)

    def turn(self, delta: int) -> None:
        self.th = uwrap(self.th + delta, 32)
        self.theta = uwrap(self.theta + delta, 32)

    def sync(self, theta: int, omega: int) -> None:
        self.th = uwrap(theta - shr(omega * self.p.k_delay, 16), 32)
        self.integ = omega << 24
        self.theta, self.omega = theta, omega


def projection_coefficients(pt: LutPoint, l_shift: int) -> tuple[int, int]:
    """``(a1, a2)`` (Q12, s16) of the low-speed projection at the table point ``pt`` (module docstring,
    step 3): the strength of a flux change is ``round_shr(a1 dpsi_q - a2 dpsi_d, 12)``; ``(0, 0)`` if the
    normalised inductance matrix is not positive definite."""
    ld, lq, ldq = shr(pt.l_d, l_shift), shr(pt.l_q, l_shift), shr(pt.l_dq, l_shift)
    dld, dldq = shr(pt.dl_d, l_shift), shr(pt.dl_dq, l_shift)
    det = ld * lq - ldq * ldq
    if det <= 0:
        return 0, 0
    return (sat(c_div((ld * ld - ld * lq + 2 * ldq * ldq + dld * ldq - dldq * ld) << 12, det), 16),
            sat(c_div((ldq * (ld + lq) + dld * lq - dldq * ldq) << 12, det), 16))


def _to_bin(x_q16: int) -> int:
    """Radians (Q16) to binary angle."""
    return shr(x_q16 * RAD_BIN, 16)
