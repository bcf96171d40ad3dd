"""The flying start's short-circuit probe (docs/faults.md, "The flying start"): the rotor's angle and speed from two
zero-voltage pulses, before any current control, so that a rotor spinning too fast for the current-control catch
(its first windows at zero voltage drive the short-circuit current: above about 1000 r/min on the Table I motor) is
caught with the back-EMF already cancelled.

With the gates switched on at zero voltage (every leg at half duty: the line-to-line voltages zero) the stator is
short-circuited, and from zero current ``L di/dt = -e`` (R i and the dead time's voltage small beside the back-EMF
at the speeds the probe is for): the current grows opposite to the back-EMF ``e = j omega psi_f exp(j theta)``.
``CTRL.ENABLE`` takes effect at the carrier bottom three quarters into the period after the step that writes it
(docs/spec.md 2.2), so a step that enables and the next that disables give a pulse of exactly one period, and the
window in which it starts sees its first quarter: the window mean ``d`` is the ramp's mean, along ``-e`` at the
ramp's centroid, ``T/12`` after the pulse's start (the mean of a ramp from zero weighs ``e(s)`` by ``T/4 - s``),
i.e. ``5/6`` into that window. The schedule (``n``: the supervisor's window count in CATCH, 1 at the first step):

=====  ============================================  ===========================================
n      the window it measures (n - 1)               outputs
=====  ============================================  ===========================================
1      gates off: the sensors' offsets ``m0``        enable (pulse 1 from 3/4 of window 1), 0 V
2      pulse 1's first quarter: ``d1 = m - m0``     disable (pulse 1 ends at 3/4 of window 2)
3..G   pulse 1's rest, the current decays; off       disabled
G + 1  gates off                                     enable (pulse 2 from 3/4 of window G + 1)
G + 2  pulse 2's first quarter: ``d2 = m - m0``     disable; :func:`probe_estimate`; if found,
                                                     the back-EMF voltage in the frame of window
                                                     G + 3
G + 3  pulse 2's rest                                the current-control catch from the probe:
                                                     the high-speed estimator synced, the q
                                                     current PI preset to that voltage
=====  ============================================  ===========================================

``G`` = PROBE_GAP. The frame of windows 0 to G + 2 is the stator's (``SIN`` 0, ``COS`` 32767: the window means
are ``i_alpha, i_beta``). The angle of ``d2`` less that of ``d1`` is the back-EMF's advance over the G periods
between the pulses, ``delta``; its sign is the direction of rotation, ``delta / G`` the speed per period. The
rotor's angle at pulse 2's centroid is the back-EMF's (``d2``'s plus half a turn) less a quarter turn in the
direction of rotation. The gap: the longer, the smaller the speed's error from the angles' (the dead time's
voltage, about 11 V on the Table I drive, turns the current by a few degrees, and differently in each 60 deg
sector), as long as the advance stays below half a turn: 6 periods at 5 kHz are 144 deg at 5000 r/min on the
Table I motor (3 periods: a speed 10 % low at 2500 r/min). Found when both pulses'
currents reach ``i_min`` (``ProtParams.probe_min``; a slower rotor, or none: the current-control catch, which
handles those, continues) and ``delta != 0``.

Fixed point: the window means (current LSB; saturated to +-2^28, the range of
:func:`golden.firmware.vector.vector_angle`), u32 binary angles,
``delta`` s32, ``c_div`` for the divisions by ``G`` and ``3 G`` (C ``/`` on int64).
"""

from __future__ import annotations

from golden.firmware.vector import vector_angle
from golden.fixed import c_div, sat, uwrap, wrap

PROBE_GAP = 6
"""Periods between the two pulses (the module docstring)."""
PROBE_END = PROBE_GAP + 3
"""The CATCH window count at which a found probe starts the current-control catch (the table above)."""
HALF_TURN = 1 << 31
QUARTER_TURN = 1 << 30


def probe_enable(n: int) -> int:
    """``CTRL.ENABLE`` of step ``n`` (1 .. PROBE_END - 1) of the schedule: on in the steps that start a pulse."""
    return int(n in (1, PROBE_GAP + 1))


def probe_estimate(d1x: int, d1y: int, d2x: int, d2y: int, i_min: int) -> tuple[int, int, int]:
    """``(found, theta, delta)`` from the two pulses' offset-free window means (module docstring): ``theta`` the
    rotor's electrical angle (u32) at pulse 2's centroid, ``delta`` the back-EMF's advance over the PROBE_GAP
    periods between the pulses (s32, binary angle). Not found: ``(0, 0, 0)``."""
    a1, m1 = vector_angle(sat(d1x, 29), sat(d1y, 29))       # the vector angle's range, +-2^28
    a2, m2 = vector_angle(sat(d2x, 29), sat(d2y, 29))
    delta = wrap(a2 - a1, 32)
    if m1 < i_min or m2 < i_min or delta == 0:
        return 0, 0, 0
    turn = QUARTER_TURN if delta > 0 else -QUARTER_TURN
    return 1, uwrap(a2 + HALF_TURN - turn, 32), delta


def probe_angles(theta: int, delta: int) -> tuple[int, int, int]:
    """``(omega, theta_a, theta_b)``: the speed per period and the rotor's angle at the middle of windows G + 3 and
    G + 4 (``5/3`` and ``8/3`` periods after pulse 2's centroid) from :func:`probe_estimate`'s ``theta`` and
    ``delta``: ``delta / G``, ``theta + 5 delta / (3 G)``, ``theta + 8 delta / (3 G)`` (``c_div``)."""
    return (c_div(delta, PROBE_GAP), uwrap(theta + c_div(5 * delta, 3 * PROBE_GAP), 32),
            uwrap(theta + c_div(8 * delta, 3 * PROBE_GAP), 32))
