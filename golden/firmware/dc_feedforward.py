"""DC-link voltage feed-forward (``control.dc_feedforward``, docs/faults.md): the voltage registers scaled by the
nominal over the measured link, so that the inverter applies the commanded voltages whatever the link.

The modulator turns a voltage register into a duty cycle against the nominal link (``inverter.V_dc``, spec 3.5):
at a link 10 % low every applied voltage is 10 % low, the current loop's gain with it, and the square-wave
injection's HF response too, which the HF response check (golden.firmware.protection) reads as a lost angle. With
the feed-forward the firmware writes each voltage times ``V_nom / V_meas``; the estimators and the checks keep
the unscaled values (the voltages the inverter applies), so only the register writes change.

Integers (``ff_nom``, ``ff_lo``, ``ff_hi`` of FirmwareParams: the nominal link and the dc-link check's limits in
codes of the dc-link channel, ``control_config.dc_feedforward_params``):

1. ``vdc = min(max(VDC, ff_lo), ff_hi)``, the window's carrier-bottom sample clamped to the limits outside which
   the dc-link check trips: a sample beyond them (a dead lane reads 0) scales by at most ``1/undervoltage``
   before that check stops the drive;
2. ``k = (ff_nom 2^14 + vdc // 2) // vdc``: ``V_nom / V_meas`` in Q14, rounded half up (``ff_nom < 2^16`` and
   ``ff_lo >= 1``: the operands below 2^31, ``k <= 2^30``; C forms the products of step 3 in int64);
3. ``v_d, v_q = sat(round_shr(v k, 14), 16)``; ``v_h = min(max(round_shr(v_h k, 14), 0), 0x7FFF)`` (the
   register's 15 unsigned bits); the other outputs unchanged.

Only under the ``foc_pwm`` law (the ``fcs_mpc`` law writes no voltages: its states are the inverter's), and not in
the identification program.
"""

from __future__ import annotations

from dataclasses import replace

from golden.fixed import round_shr, sat

FF_FRAC = 14
"""Fraction bits of the gain ``k``."""
V_H_MAX = 0x7FFF
"""The largest ``V_H`` (its register field: 15 bits)."""


def ff_gain(vdc: int, ff_nom: int, ff_lo: int, ff_hi: int) -> int:
    """``k`` of the module docstring (steps 1-2)."""
    v = min(max(vdc, ff_lo), ff_hi)
    return ((ff_nom << FF_FRAC) + v // 2) // v


def dc_feedforward(out, vdc: int, ff_nom: int, ff_lo: int, ff_hi: int):
    """The :class:`~golden.firmware.supervisor.Outputs` ``out`` with its voltages scaled (step 3)."""
    k = ff_gain(vdc, ff_nom, ff_lo, ff_hi)
    return replace(out, v_d=sat(round_shr(out.v_d * k, FF_FRAC), 16), v_q=sat(round_shr(out.v_q * k, FF_FRAC), 16),
                   v_h=min(max(round_shr(out.v_h * k, FF_FRAC), 0), V_H_MAX))
