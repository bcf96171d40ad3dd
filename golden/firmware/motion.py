"""Motion observer: a third-order Luenberger observer of angle, speed and load on an angle error, with the
motion equation's torque feed-forward. A block the estimator plug-ins share (``sqw_cic``, ``rot_bpf``);
C twin ``fw_motion_step`` in ``firmware/src/control.c``.

Xue et al. 2022, eqs. (9)-(12) (the 001 method's observer): the poles at ``-a`` (``K1 = a^3 J``,
``K2 = 3 a^2 J``, ``K3 = 3 a J``, divided by ``J``), the torque feed-forward written as the motion equation
means it, ``d omega/dt = n_p T_e / J + ...`` (eq. (9) as printed multiplies ``T_e`` by the error). Once per
control period, with ``e`` the angle error (s32 binary angle, slope 1) and the window-mean currents:

* ``ff = c_t i_q + shr(c_r i_d i_q, 16)`` (``i_d, i_q`` saturated to s16; ``c_t, c_r``: ``n_p T_e / J`` per
  current LSB and per LSB^2, Q24 and Q40 binary angle per period^2; 0 when both are 0);
* ``z = sat(z + c1 e, 64)``                    (Q24 binary angle per period^2: the load's acceleration;
  ``c1 = a^3 T^3``)
* ``w = sat(w + z + c2 e + ff, 64)``           (Q24 binary angle per period; ``c2 = 3 a^2 T^2``)
* ``omega = sat(shr(w, 24), 32)``
* ``theta_o = uwrap(theta_o + omega + shr(c3 e, 16), 32)``   (``c3 = 3 a T``, Q16)

Without the feed-forward the load's acceleration ``z`` must carry every torque change through the error;
with it the observer follows a commanded acceleration without lag, and ``z`` only the load's (the 000
method's 0 -> 100 r/min step under load: docs/methods.md). Host side: ``golden.control_config.motion_gains``.
"""

from __future__ import annotations

from typing import Protocol

from golden.fixed import sat, shr, uwrap

Q_W = 24
"""Fraction bits of the speed ``w`` and the load's acceleration ``z``."""


class MotionGains(Protocol):
    """The observer's integers, as fields of a method's parameters (module docstring): ``c1, c2`` Q24 and
    ``c3`` Q16 (any s32), ``c_t`` Q24 with ``|c_t| <= 2^46``, ``c_r`` Q40 with ``|c_r| <= 2^32``."""

    c1: int
    c2: int
    c3: int
    c_t: int
    c_r: int


class MotionState(Protocol):
    """The observer's state, as fields of a method's state: ``theta_o`` u32 binary angle, ``w`` and ``z`` s64
    (Q24), ``omega`` s32 (``sat(shr(w, 24), 32)``)."""

    theta_o: int
    w: int
    z: int
    omega: int


def motion_step(s: MotionState, e: int, i_d: int, i_q: int, p: MotionGains) -> None:
    """One period of the observer on the error ``e`` (s32) and the window means ``i_d, i_q``: updates ``s``."""
    i_d, i_q = sat(i_d, 16), sat(i_q, 16)
    ff = p.c_t * i_q + shr(p.c_r * (i_d * i_q), 16)       # n_p T_e / J: the torque feed-forward
    s.z = sat(s.z + p.c1 * e, 64)                          # Xue et al. 2022, eqs. (9)-(12): poles at -a
    s.w = sat(s.w + s.z + p.c2 * e + ff, 64)
    s.omega = sat(shr(s.w, Q_W), 32)
    s.theta_o = uwrap(s.theta_o + s.omega + shr(p.c3 * e, 16), 32)


def motion_sync(s: MotionState, theta_o: int, omega: int) -> None:
    """The observer at ``theta_o`` turning at ``omega`` (binary angle per period), no load acceleration."""
    s.theta_o, s.w, s.z, s.omega = uwrap(theta_o, 32), omega << Q_W, 0, omega
