"""Fault detection of the firmware (docs/faults.md): the checks the supervisor runs every period in RUN.

Each check compares a quantity the firmware already has with a limit computed on the host from the
scenario's ``[protection]`` table (:func:`golden.control_config.protection_params`); the first check
that fires names the fault, and the supervisor answers with its safe state (``MODE_FAULT``). None reads an
estimator's internals: they use the window means, the voltages the firmware applied, the current
references it gave and the filtered speed of the estimator in charge.

``overspeed``         ``|omega_f| > w_max + w_catch``: ``w_catch`` is 0, or after a flying start (the supervisor's
                      CATCH) the speed caught, until the hand-over down to the low-speed estimator (a rotor
                      an active load spun beyond ``w_max`` while the drive coasted is braked, not tripped
                      again, even when the speed estimate dips on the way; a speed that keeps growing from
                      there still trips).
``lock_loss``         the stator-voltage equation does not hold for the angle and speed in use: with the
                      voltage ``v`` active in the window and its current means ``i`` (both in the frame
                      of the angle in use), the residual
                      ``e_d = v_d - R i_d + omega psi_q``, ``e_q = v_q - R i_q - omega psi_d`` with
                      ``psi_d = psi_f + L_d i_d``, ``psi_q = L_q i_q`` (steady state, nominal motor)
                      is small while the angle and speed are right; a wrong angle rotates the back-EMF
                      into ``e_d`` and a wrong speed leaves ``(omega - omega_hat) psi_f`` in ``e_q``.
                      ``e_d`` and ``e_q`` each through a first-order filter (signed: what the steady-state
                      model leaves out and averages to zero, ``L di/dt`` of the ripple, noise, drops out),
                      ``|f_d| + |f_q|`` above ``emf_tol + |omega_f| psi_rel`` (the model's error grows with
                      the back-EMF: 11 % of it at 4500 r/min on the Table I motor with the estimator locked
                      within 1.5 deg). Under the ``fcs_mpc`` law ``v`` is the voltage of the states the
                      inverter applied (the supervisor's ``_applied_dq``), not the law's.
``current_tracking``  ``|i_d* - i_d| + |i_q* - i_q|`` (the references of the previous period) through a
                      first-order filter above ``track_tol``: an open phase, a switch that never turns
                      on, a dc link too low for the current.
``overload``          the speed PI's output at its limit for ``ovl_n`` periods in a row, or at its limit
                      with the speed error ``|speed_ref - omega_f|`` grown by more than ``ovl_w`` since the
                      limit was reached, for ``ovl_m`` periods in a row: the drive cannot hold the speed (a
                      blocked rotor, a load above the current limit that turns the motor against it). A
                      reference step saturates the PI too, but its error then shrinks: whenever it has shrunk
                      by more than ``ovl_w`` since the count started, the count starts again (the drive is
                      making progress: a long acceleration, or a flying start braking a rotor an active load
                      has spun up, at the current limit for longer than ``ovl_n``; ``ovl_w = 0``: never).
                      Its third part, the load beyond the drive: the load's share of the acceleration from the
                      motion equation ``J d omega/dt = T_e - T_L``, in speed LSB per period,
                      ``a = shr(ld_ct i_q + shr(ld_cr i_d i_q, 16), 24) - (omega_f - omega_f[k-1])`` (``i_d, i_q``
                      the window means saturated to s16; ``ld_ct``, ``ld_cr``: ``n_p T_e / J`` of the nominal
                      motor per current LSB and LSB^2, Q24 and Q40, as the motion observer's feed-forward), through
                      a first-order filter (``ld_k``), ``|f| > ld_max`` (a share beyond the acceleration the drive's
                      largest torque gives: no current it can give holds that load). It needs no speed reference,
                      so a reference step never fires it, and it sees the load's acceleration as it starts, where
                      the speed error takes the speed loop's time to grow (a load driving the motor at three times
                      the rated torque: docs/faults.md). The first period of RUN only takes the speed.

``hf_response``       the d-axis response of the square-wave injection (``GAMMA_D``, the window's sum of the
                      current along d_hat times the carrier's sign: INJ_SQW_D methods) against its level
                      learned at start-up. The current sensors' gains set it: a phase sensor whose gain
                      changed scales it by a factor that depends on the angle (a gain of 0.7 on phase a:
                      0.7 with d_hat on phase a, 1.0 across it), while L_d moves it little (its
                      saturation under rated load: the filtered deviation stays within 6 % on the Table I
                      motor, docs/faults.md). ``|GAMMA_D - hf_ref|`` through a first-order filter
                      (``hf_k``) above ``shr(hf_ref * hf_tol, 16)``. The reference learns in every
                      CONVERGE period (:func:`hf_learn`: injection on, rotor at rest, no current); the
                      check runs while the square wave was on for the whole window (the registers active
                      in the window and in the one before both with ``V_H != 0``), else its filter is 0.
                      What moves the response is named by the check, not guessed: besides a sensor's gain,
                      a dc link off its nominal voltage scales the injection (the modulator normalises
                      to the nominal link; :func:`dc_link_check` names a link beyond its limits), and a
                      slipping angle turns d_hat towards q (L_q != L_d).

``lock_loss``         (the slip check, with two estimator slots, :func:`slip_check`) the low-speed slot in charge
                      and the high-speed slot beside it more than 90 deg apart (``SLIP_TRIP``) within
                      ``slip_n`` periods of a period in which they agreed: within 45 deg (``SLIP_AGREE``), their
                      speeds (the filtered speed in use and the high slot's own) of one sign and both above
                      ``slip_w``. An HF estimator is blind to the magnet's direction: beyond 90 deg it runs on to
                      the opposite polarity, where it holds the rotor half a turn off and the torque reverses
                      (docs/faults.md, "Polarity slips"); the model-based observer beside it sees the magnet, and
                      above the speed where the back-EMF exceeds the inverter's dead-time voltage it stays within
                      tens of degrees, so a slot that leaves it by 90 deg within a few milliseconds of agreeing is
                      the one that slipped. Only a recent agreement arms the check: where the observer is off on
                      its own (low speed, a load transient) the slots disagree without having agreed first.

The software overcurrent on the window means (``i_trip``) is checked in every mode by the supervisor
itself (``FAULT_OVERCURRENT``), and so are the hardware's own trips (``FAULT_HARDWARE``: a fault latch of
``STATUS`` set, ``WindowResult.status``; the hardware has already turned the gates off) and the dc link
(:func:`dc_link_check`: ``undervoltage``, ``overvoltage``, the code of the ADC's dc-link channel, ``VDC``,
below ``vdc_lo`` or above ``vdc_hi`` for ``vdc_n`` periods in a row). In RUN, before the checks above, the sensor
check (:func:`frozen_check`, ``sensor``): a current lane whose every conversion of a window returned one code
(``WIN_ADC``), ``frz_n`` windows in a row.

Units: voltage, current and speed LSB of the window formats (docs/spec.md 1); flux in ``v_lsb / (2 pi
f_sw)`` per LSB, so that ``shr(omega * psi, 32)`` is a voltage in LSB (``omega`` in binary angle per
period). All products in int64 (C: ``int64_t``), shifts floored (``shr``). The two filters are first-order with a
power-of-two time constant, ``f += shr(x - f, k)`` on s32 values (2^k periods; ``x - f`` in 33 bits, C
``int64_t``; the firmware runs them every period in RUN, docs/faults.md).
"""

from __future__ import annotations

from dataclasses import dataclass

from golden.fixed import sat, shr
from golden.regmap import WIN_ADC_FROZEN_A_MASK, WIN_ADC_FROZEN_B_MASK

(FAULT_NONE, FAULT_OVERCURRENT, FAULT_OVERSPEED, FAULT_LOCK_LOSS, FAULT_TRACKING, FAULT_OVERLOAD,
 FAULT_HARDWARE, FAULT_IDENT, FAULT_HF_RESPONSE, FAULT_UNDERVOLTAGE, FAULT_OVERVOLTAGE, FAULT_SENSOR) = range(12)
FAULT_NAMES = ("none", "overcurrent", "overspeed", "lock_loss", "current_tracking", "overload", "hardware", "ident",
               "hf_response", "undervoltage", "overvoltage", "sensor")
"""Fault codes of the firmware (``struct fw_state.fault``, the trace column ``fault``; C ``enum fw_fault``)."""


@dataclass(frozen=True)
class ProtParams:
    """Integer limits of the checks (0 turns a check off).

    Attributes
    ----------
    r : int
        R_s [voltage LSB per current LSB, Q16].
    ld, lq : int
        L_d, L_q [flux LSB per current LSB, Q16].
    psi_f : int
        Magnet flux [flux LSB].
    emf_k, emf_tol : int
        Residual filter's shift (time constant ``2^emf_k`` periods, 0..30) and limit at standstill
        [voltage LSB].
    psi_rel : int
        The limit's growth with speed [flux LSB]: ``emf_tol + shr(|omega_f| psi_rel, 32)``.
    track_k, track_tol : int
        Tracking-error filter's shift and limit [current LSB].
    ovl_n : int
        Periods at the speed PI's limit before ``overload``.
    ovl_w, ovl_m : int
        Growth of the speed error at the limit [speed LSB] that is ``overload`` after ``ovl_m`` periods in a row.
    w_max : int
        Overspeed limit on ``|omega_f|`` [speed LSB].
    w_asc : int
        Above this ``|omega_f|`` at the fault the safe state is the active short circuit (zero voltage),
        below it the gates are off (coast) [speed LSB].
    restarts, restart_n : int
        Automatic restarts: at most ``restarts`` (0: none), each ``restart_n`` periods after the tripping one.
    catch_n : int
        The flying start: every start (power-up and restart) first spends ``catch_n`` periods in CATCH (0: off;
        only with a high-speed estimator, golden.firmware.supervisor).
    hf_k, hf_tol : int
        The HF response check: filter shift (reference and deviation, 0..30) and the limit as a share of the
        learned reference [Q16].
    vdc_lo, vdc_hi, vdc_n : int
        The dc-link check: under- and overvoltage limits [codes of ``VDC``] and the periods in a row beyond
        one before it trips (``vdc_n = 0``: off, as without a dc-link channel).
    frz_n, frz_min : int
        The sensor check (:func:`frozen_check`): the periods in a row with a frozen current lane before it trips
        (0: off) and the fewest samples a window needs to count (fewer: the count starts again).
    probe_min : int
        The flying start's short-circuit probe (golden.firmware.catch_probe, with ``catch_n``): the least window
        mean of a pulse's first quarter that finds the rotor [current LSB] (0: no probe).
    slip_w, slip_n : int
        The slip check (:func:`slip_check`): the speed above which the slots' agreement arms it [speed LSB]
        (0: off) and the periods an agreement keeps it armed.
    ld_ct, ld_cr, ld_k, ld_max : int
        The overload check's load part: ``n_p T_e / J`` per current LSB (Q24, ``|ld_ct| <= 2^46``) and per LSB^2
        (Q40, ``|ld_cr| <= 2^32``) in speed LSB per period, the filter's shift (0..30) and the limit on the
        filtered load acceleration [speed LSB per period] (0: off).
    """

    r: int = 0
    ld: int = 0
    lq: int = 0
    psi_f: int = 0
    emf_k: int = 0
    emf_tol: int = 0
    psi_rel: int = 0
    track_k: int = 0
    track_tol: int = 0
    ovl_n: int = 0
    ovl_w: int = 0
    ovl_m: int = 0
    w_max: int = 0
    w_asc: int = 0
    restarts: int = 0
    restart_n: int = 0
    catch_n: int = 0
    hf_k: int = 0
    hf_tol: int = 0
    vdc_lo: int = 0
    vdc_hi: int = 0
    vdc_n: int = 0
    frz_n: int = 0
    frz_min: int = 0
    probe_min: int = 0
    slip_w: int = 0
    slip_n: int = 0
    ld_ct: int = 0
    ld_cr: int = 0
    ld_k: int = 0
    ld_max: int = 0


def emf_residual(p: ProtParams, v_d: int, v_q: int, i_d: int, i_q: int, omega: int) -> tuple[int, int]:
    """``(sat(e_d, 32), sat(e_q, 32))`` of the module docstring [voltage LSB]."""
    psi_d = sat(p.psi_f + shr(p.ld * i_d, 16), 32)
    psi_q = sat(shr(p.lq * i_q, 16), 32)
    e_d = v_d - shr(p.r * i_d, 16) + shr(omega * psi_q, 32)
    e_q = v_q - shr(p.r * i_q, 16) - shr(omega * psi_d, 32)
    return sat(e_d, 32), sat(e_q, 32)


def emf_level(st) -> int:
    """``sat(|f_d| + |f_q|, 32)``: the filtered residual the lock check compares [voltage LSB]."""
    return sat(abs(st.emf_d) + abs(st.emf_q), 32)


OVL_CAP = 1 << 30
"""The overload count stops here (s32 in C)."""


def hf_learn(st, p: ProtParams, gamma_d: int) -> None:
    """One CONVERGE period of the HF response check's reference: ``hf_ref += shr(GAMMA_D - hf_ref, hf_k)`` (s32)."""
    if p.hf_tol:
        st.hf_ref = sat(st.hf_ref + shr(gamma_d - st.hf_ref, p.hf_k), 32)


SLIP_AGREE = 1 << 29
"""The slip check: two slots within 45 deg (binary angle) agree."""
SLIP_TRIP = 1 << 30
"""The slip check: two slots more than 90 deg apart (binary angle) disagree: the HF estimator's edge of lock."""


def slip_check(st, p: ProtParams, low_in_charge: bool, gap: int, omega_f: int, omega_hi: int) -> int:
    """One RUN period of the slip check (module docstring) with a high slot: ``gap`` the low slot's angle less the
    high slot's (s32 binary angle), ``omega_f`` the filtered speed in use, ``omega_hi`` the high slot's speed.
    ``st.slip_left`` counts the periods the last agreement still arms it (0: disarmed; 0 too while the high slot
    is in charge, and at power-up and every restart). Returns ``FAULT_LOCK_LOSS`` or ``FAULT_NONE``."""
    if not p.slip_w:
        return FAULT_NONE
    if not low_in_charge:
        st.slip_left = 0
        return FAULT_NONE
    if (abs(gap) < SLIP_AGREE and (omega_f > 0) == (omega_hi > 0)
            and min(abs(omega_f), abs(omega_hi)) > p.slip_w):
        st.slip_left = p.slip_n
    elif st.slip_left > 0:
        st.slip_left -= 1
    return FAULT_LOCK_LOSS if abs(gap) > SLIP_TRIP and st.slip_left > 0 else FAULT_NONE


def dc_link_check(st, p: ProtParams, vdc: int) -> int:
    """One period of the dc-link check (every mode; ``st.vdc_lo_n``, ``st.vdc_hi_n`` count the periods in a
    row below ``vdc_lo`` / above ``vdc_hi``, capped); returns ``FAULT_UNDERVOLTAGE``, ``FAULT_OVERVOLTAGE``
    once a count reaches ``vdc_n``, else ``FAULT_NONE``."""
    if not p.vdc_n:
        return FAULT_NONE
    st.vdc_lo_n = min(st.vdc_lo_n + 1, OVL_CAP) if vdc < p.vdc_lo else 0
    st.vdc_hi_n = min(st.vdc_hi_n + 1, OVL_CAP) if vdc > p.vdc_hi else 0
    if st.vdc_lo_n >= p.vdc_n:
        return FAULT_UNDERVOLTAGE
    if st.vdc_hi_n >= p.vdc_n:
        return FAULT_OVERVOLTAGE
    return FAULT_NONE


def frozen_check(st, p: ProtParams, frozen: int, n_samples: int) -> int:
    """One RUN period of the sensor check: ``st.frz_a``, ``st.frz_b`` count the periods in a row whose window has
    at least ``frz_min`` samples and lane A / B frozen (``WIN_ADC``, golden.fpga.adc_frozen; capped); returns
    ``FAULT_SENSOR`` once a count reaches ``frz_n``, else ``FAULT_NONE``. A stuck current channel is found in
    ``frz_n`` periods, before the current controller has driven the unmeasured current far; in DS mode (two
    samples a window) the check never counts."""
    if not p.frz_n:
        return FAULT_NONE
    enough = n_samples >= p.frz_min
    st.frz_a = min(st.frz_a + 1, OVL_CAP) if enough and frozen & WIN_ADC_FROZEN_A_MASK else 0
    st.frz_b = min(st.frz_b + 1, OVL_CAP) if enough and frozen & WIN_ADC_FROZEN_B_MASK else 0
    return FAULT_SENSOR if max(st.frz_a, st.frz_b) >= p.frz_n else FAULT_NONE


def protect_step(st, p: ProtParams, v_d: int, v_q: int, i_d: int, i_q: int, i_d_ref: int,
                 i_q_ref: int, omega_f: int, speed_ref: int, at_limit: bool, hf: int | None = None) -> int:
    """One RUN period of the checks, in the order overspeed, lock loss, tracking, overload, HF response; returns
    the first fault found (``FAULT_NONE``: none). ``st`` holds the filter states ``emf_d``, ``emf_q``,
    ``track_f``, ``hf_f``, ``ld_f`` (s32, the filtered values themselves; a filter whose check is off stays), the
    counts ``ovl_n``, ``ovl_e`` and the speed error when the limit was reached, ``e0``, the last speed ``ld_w``
    and whether it holds one, ``ld_n`` (0 at every start), the caught speed ``w_catch`` (the supervisor's), and
    the HF response check's
    reference ``hf_ref`` (the supervisor's :class:`~golden.firmware.supervisor.Firmware`); all are stepped every
    period. ``hf``: the window's ``GAMMA_D`` when the square wave was on for all of it, else None."""
    if p.emf_tol:                                     # a check that is off costs nothing
        e_d, e_q = emf_residual(p, v_d, v_q, i_d, i_q, omega_f)
        st.emf_d += shr(e_d - st.emf_d, p.emf_k)
        st.emf_q += shr(e_q - st.emf_q, p.emf_k)
    if p.track_tol:
        st.track_f += shr(sat(abs(i_d_ref - i_d) + abs(i_q_ref - i_q), 32) - st.track_f, p.track_k)
    st.ovl_n = min(st.ovl_n + 1, OVL_CAP) if at_limit else 0
    err = sat(abs(speed_ref - omega_f), 32)
    if st.ovl_n == 1 or (at_limit and p.ovl_w and st.e0 - err > p.ovl_w):   # at the limit from here, or progress
        st.ovl_n, st.e0 = 1, err
    st.ovl_e = min(st.ovl_e + 1, OVL_CAP) if at_limit and err - st.e0 > p.ovl_w else 0
    if p.ld_max:
        if not st.ld_n:                               # the first period of RUN: no speed before it
            st.ld_w, st.ld_n = omega_f, 1
        i_d16, i_q16 = sat(i_d, 16), sat(i_q, 16)
        torque = shr(p.ld_ct * i_q16 + shr(p.ld_cr * (i_d16 * i_q16), 16), 24)    # n_p T_e / J
        load = sat(torque - (omega_f - st.ld_w), 32)                               # ... less n_p J d omega/dt / J
        st.ld_f = sat(st.ld_f + shr(load - st.ld_f, p.ld_k), 32)
        st.ld_w = omega_f
    if p.hf_tol:
        if hf is None or st.hf_ref <= 0:
            st.hf_f = 0
        else:
            st.hf_f = sat(st.hf_f + shr(sat(abs(hf - st.hf_ref), 32) - st.hf_f, p.hf_k), 32)
    if p.w_max and abs(omega_f) > p.w_max + st.w_catch:
        return FAULT_OVERSPEED
    if p.emf_tol and emf_level(st) > p.emf_tol + shr(abs(omega_f) * p.psi_rel, 32):
        return FAULT_LOCK_LOSS
    if p.track_tol and st.track_f > p.track_tol:
        return FAULT_TRACKING
    if (p.ovl_n and st.ovl_n >= p.ovl_n) or (p.ovl_m and st.ovl_e >= p.ovl_m) or (p.ld_max and
                                                                                 abs(st.ld_f) > p.ld_max):
        return FAULT_OVERLOAD
    if p.hf_tol and st.hf_f > shr(st.hf_ref * p.hf_tol, 16):
        return FAULT_HF_RESPONSE
    return FAULT_NONE
