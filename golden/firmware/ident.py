"""Self-commissioning on the drive: the identification program executor (docs/commissioning.md).

The host (:mod:`golden.commission`) writes a *program*: a list of steps, each holding a current reference
in its own frame, an HF square-wave amplitude on that frame's d axis (the 002 hardware injection,
``V_H``), and how the frame moves. The firmware runs the steps one window at a time, closes the current
loops, and sums what it sees over the last ``m`` windows of each step: the window-mean currents, the
voltage references applied in the window (in the step's frame) and the demodulated HF responses
``GAMMA_D``, ``GAMMA`` (and one sum of their squares over the scan steps, for the noise). The host turns these sums into R_s, L_d, L_q, the saturation
map, psi_f, J and the friction (:mod:`golden.commission`).

The firmware itself makes the decisions the next steps depend on:

* **HF level** (``F_LEVEL``): a probe step at the amplitude ``s_vh`` measures the HF response ``G``; from
  then on every step's amplitude is ``min(shr(s_vh * lvl, 16), vh_max)`` with ``lvl = min(c_lvl / G,
  lvl_max)`` (Q16; the host's ``lvl_max`` = 1: the level only lowers the amplitude of a motor whose HF current
  would exceed the host's cap). ``G <= 0``: no HF response, the program stops (``failed``);

* **rotor angle** (``F_FIT``, after the scan steps ``F_SCAN``): with the injection on a frame at the
  angles ``phi_k`` (k = 0..K-1, spread over half a turn), the responses are
  ``g_d - j g_q = Y0 + Y2 exp(j 2 (phi - theta_r))`` (``Y0``, ``Y2``: the mean and half the difference of
  the inverse incremental inductances), so ``sum_k (G_d - j G_q) exp(-j 2 phi_k) = K Y2 exp(-j 2 theta_r)``
  and ``theta_r = -arg(.) / 2`` (mod half a turn), i.e. half the angle of ``(x, y) = sum_k (G_d c_k - G_q s_k,
  G_d s_k + G_q c_k)`` with ``(s_k, c_k)`` of ``2 phi_k`` (``Y2 > 0``: the plant's d axis is the low-inductance one
  for every machine, docs/motors.md). The sums are integer (s64), the angle by the vectoring CORDIC
  (:func:`~golden.firmware.vector.vector_angle`) after shifting both sums into its range.
  The scan takes each angle twice, at ``v_h`` (``F_SCAN | F_NEG``: its sums count negative) and at ``2 v_h``:
  the difference is the response to ``v_h`` without the dead time's share, which does not grow with the
  amplitude while the HF current crosses zero (docs/commissioning.md);
* **current-loop gains** (``F_FIT``, on the last scan step, the ``2 v_h`` one of a pair): ``kp = c_kp (v_h(k) -
  v_h(k - 1)) / sum_k G_d`` (the amplitude difference of the pair; the mean inverse inductance sets
  ``kp = L w_c``; ``c_kp`` holds the hardware's HF gain, the bandwidth and the formats), ``ki = kp c_ki / 2^16``
  (integral zero at a fixed share of the bandwidth: no resistance is known yet). ``F_GAIN`` sets them from one
  step's response instead, ``kp = c_gain v_h / G`` (the probe of a reluctance machine, whose scan needs a bias
  current and so current control before the fit; ``c_kp = 0``: ``F_FIT`` leaves the gains). Steps before the
  gains are set must be ``F_OPEN`` (no current control);
* **magnet polarity** (``F_POL``): the step before it had ``+I_p`` on d, this one ``-I_p``; a larger HF
  response now (smaller incremental inductance: saturation) means the magnet's north is on ``-d``:
  ``theta_r`` turns by half a turn.

``F_SNAP`` (with ``F_SET``): the frame turns at a constant speed from its start to the nearest phase axis (a
multiple of 60 deg in the stator) over the step, and stops there at its end: the rotor, aligned with the
current at the start, follows it there without a swing (``w = c_div(wrap(axis - theta, 32), n - 1)``: the
step's first call does not move the frame).

Frame of a step: ``F_SET`` puts it at ``theta_r + phi`` at rest at the step start; the references in use and
the PI integrators turn with the jump, and so do the window means of the step's first two calls (measured in
the frame before it); otherwise the frame keeps moving: per period ``w += dw``, then ``theta += w`` (the speed
``w`` in binary angle per period). The references approach the step's at ``i_slew`` per period. A step
``F_OPEN`` writes zero voltage (current control off).

Timing: the outputs of a call are active two windows later (docs/spec.md 2), so the host leaves at least
two windows of a step before its ``m`` measured ones. At the end of the program the firmware turns the
gates off (``MODE_DONE``).
"""

from __future__ import annotations

from dataclasses import dataclass, field

from golden.firmware.estimator import park, window_voltage
from golden.firmware.pi import PiParams, pi_step
from golden.firmware.vector import INPUT_LIMIT, vector_angle
from golden.fixed import c_div, sat, shr, uwrap, wrap
from golden.fpga.cordic import sincos_q15

F_SET, F_SCAN, F_FIT, F_POL, F_OPEN, F_LEVEL, F_NEG, F_SNAP, F_GAIN = 1, 2, 4, 8, 16, 32, 128, 256, 512
"""Step flags (module docstring; 64 is not used)."""
IDENT_MAX = 160
"""Most steps in a program (the C arrays' length)."""
HALF_TURN = 1 << 31
M_MAX = 32767
"""Most measured windows of a step: the s16 means sum into s32 (``r_id, r_iq, r_vd, r_vq``)."""
G2_SHIFT, G2_BITS = 8, 24
"""The scan's noise sum: ``g2 += shr(sat(g_d, 24)^2 + sat(g_q, 24)^2, 8)`` (at most 2^40 per window)."""
SIXTH = (1 << 32) // 6
"""A sixth of a turn, rounded down (the phase axes are at ``(k << 32) // 6``)."""
KP_MAX = (1 << 31) - 1


@dataclass(frozen=True)
class IdentParams:
    """The program (one tuple per step field, all of one length ``<= IDENT_MAX``) and the gain constants.

    Attributes
    ----------
    s_n, s_m : tuple of int
        Windows of each step (>= 1) and how many of its last windows are summed (0..n).
    s_id, s_iq : tuple of int
        Current references in the step's frame [current LSB].
    s_vh : tuple of int
        HF square-wave amplitude on the frame's d axis [voltage LSB, 0..32767].
    s_phi : tuple of int
        Frame angle relative to the rotor angle found (u32 binary angle), used by ``F_SET``.
    s_dw : tuple of int
        Frame speed change per period [speed LSB per period] while the step runs.
    s_flags : tuple of int
        ``F_*`` flags.
    c_kp : int
        ``kp = c_kp v_h / sum G_d`` at ``F_FIT`` (0 <= c_kp < 2^46).
    c_ki : int
        ``ki = shr(kp * c_ki, 16)`` (Q16, 0..2^16).
    v_lim : int
        Current PIs' output limit [voltage LSB].
    c_gain : int
        ``F_GAIN``: ``kp = c_gain v_h / G`` (0 <= c_gain < 2^46).
    c_lvl, lvl_max, vh_max : int
        ``F_LEVEL``: ``lvl = min(c_lvl / G, lvl_max)`` (0 <= c_lvl < 2^46, 0 <= lvl_max <= 2^24) and the largest
        amplitude [voltage LSB, 0..32767].
    i_slew : int
        Largest change of a current reference per period [current LSB, 1..2^20]: a step's references are
        approached at this rate (a 12 A step at 1 kHz PWM otherwise overshoots to the trip level).
    """

    s_n: tuple
    s_m: tuple
    s_id: tuple
    s_iq: tuple
    s_vh: tuple
    s_phi: tuple
    s_dw: tuple
    s_flags: tuple
    c_kp: int
    c_ki: int
    v_lim: int
    c_lvl: int = 0
    c_gain: int = 0
    lvl_max: int = 1 << 16
    i_slew: int = 1 << 20
    vh_max: int = 32767
    n_steps: int = field(init=False)

    def __post_init__(self) -> None:
        n = len(self.s_n)
        cols = ("s_m", "s_id", "s_iq", "s_vh", "s_phi", "s_dw", "s_flags")
        if not 1 <= n <= IDENT_MAX or any(len(getattr(self, c)) != n for c in cols):
            raise ValueError(f"an identification program has 1..{IDENT_MAX} steps, every column as long as s_n")
        for k in range(n):
            f = self.s_flags[k]
            if self.s_n[k] < 1 or not 0 <= self.s_m[k] <= min(self.s_n[k], M_MAX):
                raise ValueError(f"step {k}: n {self.s_n[k]} must be >= 1 and m {self.s_m[k]} in 0..min(n, {M_MAX})")
            if not 0 <= self.s_vh[k] <= 32767:
                raise ValueError(f"step {k}: v_h {self.s_vh[k]} outside 0..32767")
            if not (-32768 <= self.s_id[k] <= 32767 and -32768 <= self.s_iq[k] <= 32767):
                raise ValueError(f"step {k}: current references outside s16")
            if f & (F_FIT | F_POL) and k == 0:
                raise ValueError("step 0 cannot compare with a step before it (F_FIT, F_POL)")
            if f & F_FIT and self.s_vh[k] <= self.s_vh[k - 1]:
                raise ValueError(f"step {k}: F_FIT needs an amplitude above the step before (the pair v, 2v)")
            if f & F_SNAP and self.s_n[k] < 2:
                raise ValueError(f"step {k}: F_SNAP needs n >= 2")
        if not (0 <= self.c_kp < 1 << 46 and 0 <= self.c_ki <= 1 << 16 and 1 <= self.v_lim <= 32767
                and 0 <= self.c_lvl < 1 << 46 and 0 <= self.c_gain < 1 << 46 and 0 <= self.lvl_max <= 1 << 24
                and 0 <= self.vh_max <= 32767 and 1 <= self.i_slew <= 1 << 20):
            raise ValueError("c_kp, c_ki, v_lim, c_lvl, c_gain, lvl_max, vh_max or i_slew out of range")
        object.__setattr__(self, "n_steps", n)


@dataclass
class Ident:
    """State of the executor: the step, the frame, the fitted angle and gains, the sums of every step."""

    p: IdentParams
    k: int = 0                        # step index
    n: int = 0                        # windows into the step
    theta: int = 0                    # frame angle (u32)
    w: int = 0                        # frame speed [binary angle per period]
    theta_r: int = 0                  # rotor angle found (u32)
    kp: int = 0                       # current-PI gains (Q16), set at F_FIT
    ki: int = 0
    lvl: int = 1 << 16                # HF level factor (Q16), set at F_LEVEL
    ref_d: int = 0                    # current references in use (slew-limited towards the step's)
    ref_q: int = 0
    jump: int = 0                     # u32: the frame's turn at the last F_SET
    fit_x: int = 0                    # scan sums (s64)
    fit_y: int = 0
    fit_y0: int = 0
    failed: int = 0                   # 1: the probe or the scan saw no HF response (G <= 0)
    done: int = 0
    r_id: list = field(default_factory=lambda: [0] * IDENT_MAX)   # per-step sums over the last m windows (s32
    #                                                               for the s16 means; s64 for the responses)
    r_iq: list = field(default_factory=lambda: [0] * IDENT_MAX)
    r_vd: list = field(default_factory=lambda: [0] * IDENT_MAX)
    r_vq: list = field(default_factory=lambda: [0] * IDENT_MAX)
    r_gd: list = field(default_factory=lambda: [0] * IDENT_MAX)
    r_gq: list = field(default_factory=lambda: [0] * IDENT_MAX)
    g2: int = 0                       # the scan steps' noise sum (s64, G2_SHIFT)

    def __post_init__(self) -> None:
        self._start()

    def _start(self) -> None:
        """Enter step ``k``: ``F_SET`` puts the frame at ``theta_r + phi``, at rest."""
        f = self.p.s_flags[self.k]
        if f & F_SET:
            theta = uwrap(self.theta_r + self.p.s_phi[self.k], 32)
            self.jump, self.theta, self.w = uwrap(theta - self.theta, 32), theta, 0
            if f & F_SNAP:
                axis = ((((theta + (SIXTH >> 1)) // SIXTH) % 6) << 32) // 6
                self.w = c_div(wrap(axis - theta, 32), max(self.p.s_n[self.k] - 1, 1))

    def measure(self, i_d: int, i_q: int, gamma_d: int, gamma_q: int, now, before) -> None:
        """One window: sum it when it is one of the step's last ``m``; at the step's end, its action."""
        p, k = self.p, self.k
        self.n += 1
        if self.n > p.s_n[k] - p.s_m[k]:
            a, b = window_voltage(now, before)
            v_d, v_q = park(a, b, now.sin, now.cos)
            self.r_id[k] += i_d
            self.r_iq[k] += i_q
            self.r_vd[k] += v_d
            self.r_vq[k] += v_q
            self.r_gd[k] += gamma_d
            self.r_gq[k] += gamma_q
            if p.s_flags[k] & F_SCAN:
                g_d, g_q = sat(gamma_d, G2_BITS), sat(gamma_q, G2_BITS)
                self.g2 += shr(g_d * g_d + g_q * g_q, G2_SHIFT)
        if self.n < p.s_n[k]:
            return
        self._finish(k)
        self.k, self.n = k + 1, 0
        if self.k == p.n_steps:
            self.done = 1
        else:
            self._start()

    def v_h(self, k: int) -> int:
        """The HF amplitude of step ``k`` after the level factor."""
        return min(shr(self.p.s_vh[k] * self.lvl, 16), self.p.vh_max)

    def _finish(self, k: int) -> None:
        """The decisions at the end of step ``k`` (module docstring)."""
        p, f = self.p, self.p.s_flags[k]
        if f & F_GAIN:                                   # (before F_LEVEL: at the amplitude the step ran with)
            if self.r_gd[k] <= 0:
                self.failed = 1
            else:
                self.kp = min(c_div(p.c_gain * self.v_h(k), self.r_gd[k]), KP_MAX)
                self.ki = shr(self.kp * p.c_ki, 16)
        if f & F_LEVEL:
            if self.r_gd[k] <= 0:
                self.failed = 1
            else:
                self.lvl = min(c_div(p.c_lvl, self.r_gd[k]), p.lvl_max)
        if f & F_SCAN:
            s2, c2 = sincos_q15(uwrap(2 * p.s_phi[k], 32))
            g_d, g_q = (-self.r_gd[k], -self.r_gq[k]) if f & F_NEG else (self.r_gd[k], self.r_gq[k])
            self.fit_x += g_d * c2 - g_q * s2
            self.fit_y += g_d * s2 + g_q * c2
            self.fit_y0 += g_d
        if f & F_FIT:
            x, y = self.fit_x, self.fit_y
            while max(abs(x), abs(y)) > INPUT_LIMIT:
                x, y = shr(x, 1), shr(y, 1)
            a, _ = vector_angle(x, y)
            self.theta_r = a >> 1
            if self.fit_y0 <= 0:
                self.failed = 1
            elif p.c_kp:
                self.kp = min(c_div(p.c_kp * (self.v_h(k) - self.v_h(k - 1)), self.fit_y0), KP_MAX)
                self.ki = shr(self.kp * p.c_ki, 16)

        if f & F_SNAP:
            self.w = 0
        if f & F_POL and self.r_gd[k] > self.r_gd[k - 1]:
            self.theta_r = uwrap(self.theta_r + HALF_TURN, 32)

    def refs(self, i_d: int, i_q: int, st) -> tuple[int, int, int, int, int, int]:
        """The step's outputs after :meth:`measure`: advance the frame, run the current PIs (integrators in
        ``st.id_int``, ``st.iq_int``); returns ``(v_d, v_q, v_h, theta, i_d_ref, i_q_ref)``. The window means of
        the first two calls of an ``F_SET`` step ran in the frame before its jump: they are turned by the jump
        (all others are used as measured: a frame turning at a steady speed carries the currents with it)."""
        p, k = self.p, self.k
        if p.s_flags[k] & F_SET and self.n == 0:
            # the current and voltage vectors are continuous in the stator: the references in use and the
            # PI integrators turn into the new frame
            s, c = sincos_q15(self.jump)
            self.ref_d, self.ref_q = (sat(x, 16) for x in park(self.ref_d, self.ref_q, s, c))
            st.id_int, st.iq_int = park(st.id_int, st.iq_int, s, c)
        else:
            self.w = sat(self.w + p.s_dw[k], 32)
        self.theta = uwrap(self.theta + (self.w if self.n or not p.s_flags[k] & F_SET else 0), 32)
        self.ref_d = min(max(p.s_id[k], self.ref_d - p.i_slew), self.ref_d + p.i_slew)
        self.ref_q = min(max(p.s_iq[k], self.ref_q - p.i_slew), self.ref_q + p.i_slew)
        r_d, r_q = self.ref_d, self.ref_q
        if p.s_flags[k] & F_SET and self.n < 2:
            s, c = sincos_q15(self.jump)
            i_d, i_q = park(i_d, i_q, s, c)
        if p.s_flags[k] & F_OPEN:
            v_d = v_q = st.id_int = st.iq_int = 0
        else:
            pi = PiParams(self.kp, 16, self.ki, 16, p.v_lim)
            v_d, st.id_int = pi_step(st.id_int, r_d, i_d, pi)
            v_q, st.iq_int = pi_step(st.iq_int, r_q, i_q, pi)
        return v_d, v_q, self.v_h(k), self.theta, r_d, r_q
