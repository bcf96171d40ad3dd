"""The estimator plug-in interface of the firmware (docs/methods.md): one per method, bit-true.

An *estimator* turns what the firmware sees once per control period (the window results of the FPGA,
the window-mean currents in the estimated frame, and the voltages and angle that were active during the
window) into an electrical angle and speed for the field-oriented control, and says which injection the
hardware must add while it is in charge. The supervisor (:mod:`golden.firmware.supervisor`) owns two
*slots*: a low-speed estimator (in charge from start-up) and an optional high-speed one (running in
parallel from start-up, in charge above the hand-over speed). It calls only this interface; it never
reads a method's internals. The C firmware has the same interface (``struct fw_est_ops`` in
``firmware/src/control.h``) and the same members, bit for bit (tests/test_fw_c.py).

Contract of a member (a subclass of :class:`Estimator`, listed in :mod:`golden.firmware.methods`):

* ``METHOD``: its id (``enum fw_method`` in control.h), the key of its line in :data:`METHODS` (name,
  paper, slots, injection while in charge); ``PARAMS``: the name of its field in
  :class:`~golden.firmware.supervisor.FirmwareParams` (and ``struct fw_params``);
* ``__init__(params)`` with its own frozen params dataclass (integers computed on the host by
  :mod:`golden.control_config`);
* ``step(m)``: one control period, integer arithmetic only; afterwards ``theta`` (u32 binary angle the
  FOC should use for the window after next, the one the outputs of this step will be active in) and
  ``omega`` (s32, binary angle per period) are this estimator's outputs;
* ``turn(delta)``: rotate every angle it holds by ``delta`` (polarity detection: half a turn);
* ``sync(theta, omega)``: take over from the other slot: continue from this angle and speed;
* ``i_d``: the d-current reference [current LSB] it asks the speed-controlled FOC for while it is in
  charge (0 for most; the rotor flux observer keeps the current out of the dead-time compensation's
  uncertain zone).

A method whose ``MethodInfo.flux`` is true also observes the stator flux for the direct-vector control law
(:mod:`golden.firmware.fcs_law`) and has, after ``step``: ``psi_al, psi_be`` (the stator flux at the last
carrier top, stationary frame, units of :data:`golden.firmware.flux_lut.FLUX_FRAC`), ``fcs_a1, fcs_a2``
(the ``FCS_A`` coefficients of the vector strength, spec 3.10) and ``constrain`` (``FCS_CTRL.CONSTRAIN``).
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from dataclasses import dataclass

from golden.firmware.pll import PllState
from golden.fixed import round_shr, sat, uwrap
from golden.fpga.demodulator import WindowResult

METHOD_SQW_BANGBANG, METHOD_RFO, METHOD_ROT_BPF, METHOD_EEMF_SMO, METHOD_SQW_CIC, METHOD_HFO_PROJ = 1, 2, 3, 4, 5, 6
"""Method ids (``enum fw_method`` in firmware/src/control.h; 0 is "no estimator" in a slot)."""

INJ_NONE, INJ_SQW_D, INJ_ROT, INJ_SQW_P = 0, 1, 2, 3
"""Injection modes: none; the square wave +-V_H on the estimated d-axis at the switching frequency
(Benevieri et al. 2023, eq. (14)); the vector V_H e^{j phi} rotating in the stationary frame (Tap et al.
2023, eq. (9); ``CTRL.INJ_ROT``, ``INJ_STEP``); the square wave on the estimated d-axis whose sign holds
for a whole PWM period, at f_sw / 2 (Xue et al. 2022, eq. (3); ``CTRL.INJ_PER``). The firmware writes
the ``V_H`` register as 0 while the estimator in charge has ``INJ_NONE``; the rotating and the period
modes are set once at start-up (hardware config)."""

SLOT_LOW, SLOT_HIGH = 0, 1
"""Estimator slots of the supervisor: in charge from start-up, and above the hand-over speed."""


@dataclass(frozen=True, slots=True)
class Measurement:
    """What every estimator gets once per control period (all integers of docs/spec.md).

    ``win``: the window results; ``i_d, i_q``: window-mean currents in the estimated frame [current LSB];
    ``sin, cos``: the angle active during the window (Q1.15, the Park angle of its currents);
    ``v_al, v_be``: the mean stator-voltage reference over the window in the stationary frame [voltage
    LSB] (:func:`window_voltage`, plus :func:`injection_voltage` when the rotating injection is on);
    ``inj_sin, inj_cos``: sin/cos of ``INJ_PHASE`` (Q1.15; 0 and 32767 when the injection does not rotate).
    """

    win: WindowResult
    i_d: int
    i_q: int
    sin: int
    cos: int
    v_al: int
    v_be: int
    inj_sin: int = 0
    inj_cos: int = 32767


def park(a: int, b: int, s: int, c: int) -> tuple[int, int]:
    """``(round_shr(a*c + b*s, 15), round_shr(b*c - a*s, 15))``: a stationary-frame vector (s32) into the
    frame of Q1.15 ``s, c`` (int64 products in C)."""
    return round_shr(a * c + b * s, 15), round_shr(b * c - a * s, 15)


def inv_park(d: int, q: int, s: int, c: int) -> tuple[int, int]:
    """``(sat(round_shr(d*c - q*s, 15), 32), sat(round_shr(d*s + q*c, 15), 32))``: the modulator's inverse
    Park (spec 3.5) for s32 ``d, q`` and Q1.15 ``s, c`` (the saturation acts only beyond s16 inputs)."""
    return sat(round_shr(d * c - q * s, 15), 32), sat(round_shr(d * s + q * c, 15), 32)


def window_voltage(now, before) -> tuple[int, int]:
    """Mean alpha/beta voltage reference over a window from the register sets active in it (``now``)
    and in the window before (``before``), each with ``v_d, v_q, sin, cos``.

    A window runs from a rising zero crossing of the carrier to the next (docs/spec.md 2); its first
    quarter period is the end of the rising half whose compares were latched from ``before``, the other
    three quarters are the falling and rising halves latched from ``now``. So the mean is
    ``round_shr(3 * v(now) + v(before), 2)`` per component, with ``v`` the inverse Park of each set.
    Ignoring that quarter period puts the flux a quarter period late (6 deg at 5000 r/min on the 002
    motor). The injection's mean over the window is ``(V_h(now) - V_h(before)) / 4`` and is left out.
    """
    a1, b1 = inv_park(now.v_d, now.v_q, now.sin, now.cos)
    a0, b0 = inv_park(before.v_d, before.v_q, before.sin, before.cos)
    return round_shr(3 * a1 + a0, 2), round_shr(3 * b1 + b0, 2)


def injection_voltage(v_now: int, v_before: int, s: int, c: int, cd: int, sd: int) -> tuple[int, int]:
    """Mean of the rotating injection over a window (docs/spec.md 3.5): its last three quarters ran on
    ``INJ_PHASE`` with the amplitude ``v_now`` (``V_H`` active in the window), its first quarter on
    ``INJ_PHASE - INJ_STEP`` with ``v_before``. ``(s, c)``: sin/cos of ``INJ_PHASE``; ``(sd, cd)``: of
    ``INJ_STEP`` (Q15). ``c_b = round_shr(c cd + s sd, 15)``, ``s_b = round_shr(s cd - c sd, 15)``, then
    ``round_shr(3 v_now c + v_before c_b, 17)`` and the same with ``s, s_b`` (``v`` in 0..2^15)."""
    c_b = round_shr(c * cd + s * sd, 15)
    s_b = round_shr(s * cd - c * sd, 15)
    return round_shr(3 * v_now * c + v_before * c_b, 17), round_shr(3 * v_now * s + v_before * s_b, 17)


class Estimator(ABC):
    """Base of every estimator plug-in (see the module docstring for the contract)."""

    METHOD: int
    PARAMS: str

    theta: int = 0
    omega: int = 0
    i_d: int = 0
    psi_al: int = 0
    psi_be: int = 0
    fcs_a1: int = 0
    fcs_a2: int = 0
    constrain: int = 0

    @abstractmethod
    def step(self, m: Measurement) -> None:
        """One control period: update the state and ``theta``, ``omega``."""

    @abstractmethod
    def turn(self, delta: int) -> None:
        """Rotate every angle of the state by ``delta`` (binary angle)."""

    def turn_pll(self, delta: int) -> None:
        """``turn`` of a method whose angles are its PLL's and its output (the PLL ``pll`` a
        :class:`~golden.firmware.pll.PllState`): both turned by ``delta``."""
        self.pll = PllState(uwrap(self.pll.theta + delta, 32), self.pll.integ, self.pll.omega)
        self.theta = uwrap(self.theta + delta, 32)

    @abstractmethod
    def sync(self, theta: int, omega: int) -> None:
        """Continue from ``theta`` and ``omega`` (hand-over from the other slot)."""


@dataclass(frozen=True)
class MethodInfo:
    """One line of ``hfi methods``: the scenario name, the id, the paper, the slots, the injection."""

    name: str
    method: int
    paper: str
    slots: tuple[int, ...]
    injection: int
    summary: str
    backends: tuple[str, ...] = ("golden", "rtl", "hls")
    """The closed-loop backends that run it (hfi/backends.py refuses the others with a clear error)."""
    flux: bool = False
    """It observes the stator flux for the direct-vector control law ``fcs_mpc`` (and runs only with it)."""
    angle_quarters: int = 2
    """Where in a control window its angle refers to, in quarters of the window: 2, the middle (the window
    means); 3, the carrier bottom (the 001 method's samples, the 003 method's applied state). Reports take the
    true angle there (``ClosedLoopResult.angle_error_deg``, docs/metrics.md)."""
    hardware: tuple[str, ...] = ()
    """The optional FPGA blocks it needs (golden.build_options: ROT_INJ, DIFF_CIC, FCS_MPC, FLUX_LUT); the firmware
    refuses to start on a build without them (CAPS), ``hfi compare`` counts their resources as the method's."""


METHODS: dict[str, MethodInfo] = {m.name: m for m in (
    MethodInfo("sqw_bangbang", METHOD_SQW_BANGBANG,
               "Benevieri et al., IEEE TPEL 2023 (002)", (SLOT_LOW,), INJ_SQW_D,
               "square-wave injection at f_sw on d_hat, OS demodulation, bang-bang + PLL"),
    MethodInfo("rfo", METHOD_RFO,
               "Ortega et al. 2011 gradient flux observer, as used by Choi et al., TPEL 2017 (002 ref. [10])",
               (SLOT_HIGH,), INJ_NONE,
               "rotor (active) flux observer in the stationary frame, CORDIC angle, PLL speed"),
    MethodInfo("rot_bpf", METHOD_ROT_BPF, "Tap et al., IEEE Access 2023 (000)", (SLOT_LOW,), INJ_ROT,
               "rotating injection, one band-pass at 2 f_h, N-sample average, normalised PLL",
               hardware=("ROT_INJ",)),
    MethodInfo("eemf_smo", METHOD_EEMF_SMO, "Tap et al., IEEE Access 2023 (000), eqs. (20)-(22)",
               (SLOT_HIGH,), INJ_NONE,
               "extended-EMF sliding-mode observer in the stationary frame, CORDIC angle, PLL speed"),
    MethodInfo("sqw_cic", METHOD_SQW_CIC, "Xue et al., Electronics 2022 (001)", (SLOT_LOW,), INJ_SQW_P,
               "square wave at f_sw/2 on d_hat, sample differencing, CIC interpolation, Luenberger observer",
               angle_quarters=3, hardware=("DIFF_CIC",)),
    MethodInfo("hfo_proj", METHOD_HFO_PROJ, "Varatharajan et al., IEEE Access 2020 (003)", (SLOT_LOW,), INJ_NONE,
               "hybrid flux observer with flux maps, FCS-MPC ripple projection + APP, fusion, PLL",
               flux=True, angle_quarters=3, hardware=("FCS_MPC", "FLUX_LUT")),
)}
"""Every estimator, by scenario name (``estimator.low`` / ``estimator.high``)."""

BY_ID: dict[int, MethodInfo] = {m.method: m for m in METHODS.values()}
"""The same lines by method id."""
