"""Flux-map look-up table of the firmware (Varatharajan et al. 2020, Fig. 2, eqs. (8) and (12)), bit-true.

The table holds the flux linkages ``Lambda(i) = (lambda_d, lambda_q)`` of the motor in the plant's rotor
frame (d = the low-inductance axis, docs/motors.md 5) on the first quadrant of the current plane: a
grid of ``n_d x n_q`` points, row-major by ``i_q``, s16 values in units of ``2^f_shift`` flux units
(:data:`FLUX_FRAC`; the soft core's RAM is small: a table point's rounding is 1/2 of ``2^f_shift`` flux
units, 26 uV*s here, against the 1 mV*s of the other errors of the low-speed projection; the inductance
tables below stay s32: their derivative along the rotation is a difference of neighbours, and ``l_d``
spans 100:1 between no load and 2 p.u.). The
grid is uniform, step ``2^shift`` current LSB, in the warped current ``u = warp(|i|)``: ``u = x`` below
``knee``, ``u = knee + shr(x - knee, coarse)`` above (``knee`` a multiple of ``2^shift``): the step grows
by ``2^coarse`` beyond the knee, so the steep rib region near zero gets the fine step without the grid
growing over the whole current range. ``t[r * n_d + c]`` is the point ``u_d = c << shift``, ``u_q = r << shift``. A synchronous reluctance machine's map is odd in each current:
``lambda_d(-i_d, i_q) = -lambda_d(i_d, i_q)``, ``lambda_d(i_d, -i_q) = lambda_d(i_d, i_q)`` and the same
with d and q exchanged, so the other quadrants follow by sign (``sgn 0 = +1``).

Look-up (bilinear) at ``x = warp(|i_d|)``, ``y = warp(|i_q|)``:

    c = min(x >> shift, n_d - 2),  fx = x - (c << shift)      (r, fy the same for y and n_q)
    a = t00 + shr((t01 - t00) * fx, shift),  b = t10 + shr((t11 - t10) * fx, shift)
    value = (a + shr((b - a) * fy, shift)) << f_shift         (the inductance tables: no shift)

with ``t00 = t[r n_d + c]``, ``t01 = t[r n_d + c + 1]``, ``t10 = t[(r + 1) n_d + c]``, ``t11 = t[(r + 1) n_d + c + 1]``.
Beyond the grid the flux is extrapolated linearly from the last cell (``fx`` above ``2^shift``): one
active vector kicks the low-inductance current by 3 A, beyond any grid a small firmware can hold, and a
clamped map would see no flux change at all there (a secant error of 20 mV*s, tried); the saturated
map is nearly linear out there. The inductance tables are not extrapolated (their fractions are
clamped to ``2^shift``: the edge values hold).

Incremental inductances (eq. (12)): the paper differences the map over a small ``delta i``. On a bilinear
table that quotient is the cell's slope, constant across the cell and stepping at its edges: near the
ribs' knee of a SyRM (docs/motors.md 5) it is 2.4 times the true ``l_d`` at -0.27 A on a 0.31 A grid, and
``e = dpsi - l di`` of eq. (26) then carries ``(1 - l_lut / l) dpsi`` for every vector with a d component
(an angle error of tens of degrees). So the incremental inductances have tables of their own on the same
grid (``l_d``, ``l_q``, ``l_dq``: the map's derivatives at the grid points, made on the host, in flux units
per ``2^shift`` current LSB), interpolated as the flux:

    l_d = bilinear(t_ld),  l_q = bilinear(t_lq),  l_dq = sgn(i_d) sgn(i_q) bilinear(t_ldq)

(``l_d`` and ``l_q`` are even in each current, ``l_dq`` odd in each).

Their change with the position error (the correction of the low-speed projection, golden.firmware.hfo_proj):
the estimated-frame current turns with the error, ``i_hat = e^{J err} i``, so the table's ``l`` at
``i_hat`` changes by ``err * dl`` with ``dl = -i_q dl/di_d + i_d dl/di_q`` (the derivative along ``J i``).
With the cell's slopes of each inductance table ``t``,

    gx = (t01 - t00) (2^shift - fy) + (t11 - t10) fy,   gy = (t10 - t00) (2^shift - fx) + (t11 - t01) fx

(``2^(2 shift)`` times the slope per grid step), ``wx = 2^coarse`` below the knee and 1 beyond it (the grid
step in current grows by ``2^coarse`` there), ``wy`` the same for q, and the signs ``sd = sgn i_d``, ``sq = sgn i_q`` (+1 for 0):

    dl_d  = shr(-i_q sd gx(t_ld) wx + i_d sq gy(t_ld) wy, 2 shift + coarse)      (and dl_q from t_lq)
    dl_dq = shr(-|i_q| gx(t_ldq) wx + |i_d| gy(t_ldq) wy, 2 shift + coarse)

in the units of ``l`` per radian. Products are at most s32 x s32 x s3: int64 in C.
"""

from __future__ import annotations

from dataclasses import dataclass

from golden.fixed import shr

FLUX_FRAC = 8
"""Flux unit of the firmware: ``v_lsb * T / 2^FLUX_FRAC`` volt-seconds (``v_lsb`` the voltage LSB, ``T``
the control period): the flux of one voltage LSB applied for one period is ``2^FLUX_FRAC``."""

LUT_MAX_AXIS = 64
"""Most grid points per axis."""
LUT_MAX_POINTS = 1024
"""Most grid points of a table (``n_d n_q``; the C reserves this many entries per table)."""


@dataclass(frozen=True)
class FluxLut:
    """``n_d x n_q`` points, step ``2^shift`` current LSB below ``knee``, ``2^coarse`` times that above, maps ``t_d``,
    ``t_q`` (s16, units of ``2^f_shift`` flux units) and incremental inductances ``t_ld``, ``t_lq``,
    ``t_ldq`` (s32, flux units per ``2^shift`` current LSB), ``n_d n_q`` each; ``l_shift`` brings the
    largest inductance below 2^15 for the projection's products (golden.firmware.hfo_proj)."""

    n_d: int
    n_q: int
    shift: int
    knee: int
    coarse: int
    f_shift: int
    l_shift: int
    t_d: tuple
    t_q: tuple
    t_ld: tuple
    t_lq: tuple
    t_ldq: tuple


@dataclass(frozen=True, slots=True)
class LutPoint:
    """The map, its incremental inductances and their derivatives along the rotation (module docstring) at
    one current (flux units; ``l_*`` and ``dl_*`` per ``2^shift`` current LSB)."""

    lam_d: int
    lam_q: int
    l_d: int
    l_q: int
    l_dq: int
    dl_d: int
    dl_q: int
    dl_dq: int


def _cell(lut: FluxLut, i_d: int, i_q: int) -> tuple[int, int, int]:
    """``(k, fx, fy)``: the index of the cell's first corner and the fractions (beyond ``2^shift`` outside
    the grid; module docstring)."""
    n, s = lut.n_d, lut.shift
    x, y = warp(abs(i_d), lut.knee, lut.coarse), warp(abs(i_q), lut.knee, lut.coarse)
    c, r = min(x >> s, n - 2), min(y >> s, lut.n_q - 2)
    return r * n + c, x - (c << s), y - (r << s)


def lut_flux(lut: FluxLut, i_d: int, i_q: int) -> tuple[int, int]:
    """The map's flux ``(lam_d, lam_q)`` alone at ``(i_d, i_q)`` (as :func:`lut_point`)."""
    k, fx, fy = _cell(lut, i_d, i_q)
    n, s = lut.n_d, lut.shift
    lam_d, lam_q = (_bilinear(t[k], t[k + 1], t[k + n], t[k + n + 1], fx, fy, s) << lut.f_shift
                    for t in (lut.t_d, lut.t_q))
    return (-lam_d if i_d < 0 else lam_d), (-lam_q if i_q < 0 else lam_q)


def lut_point(lut: FluxLut, i_d: int, i_q: int) -> LutPoint:
    """Flux and incremental inductances at ``(i_d, i_q)`` [current LSB, s32] (module docstring)."""
    k, fx, fy = _cell(lut, i_d, i_q)
    n, s = lut.n_d, lut.shift
    one = 1 << s
    lam_d, lam_q = (_bilinear(t[k], t[k + 1], t[k + n], t[k + n + 1], fx, fy, s) << lut.f_shift
                    for t in (lut.t_d, lut.t_q))
    fx, fy = min(fx, one), min(fy, one)
    l_d, l_q, l_dq = (_bilinear(t[k], t[k + 1], t[k + n], t[k + n + 1], fx, fy, s)
                      for t in (lut.t_ld, lut.t_lq, lut.t_ldq))
    w = 1 << lut.coarse
    wx, wy = (w if abs(i_d) < lut.knee else 1), (w if abs(i_q) < lut.knee else 1)
    sd, sq = (-1 if i_d < 0 else 1), (-1 if i_q < 0 else 1)
    g = []
    for t in (lut.t_ld, lut.t_lq, lut.t_ldq):
        t00, t01, t10, t11 = t[k], t[k + 1], t[k + n], t[k + n + 1]
        g.append((((t01 - t00) * (one - fy) + (t11 - t10) * fy) * wx, ((t10 - t00) * (one - fx) + (t11 - t01) * fx) * wy))
    dl_d = shr(-i_q * sd * g[0][0] + i_d * sq * g[0][1], 2 * s + lut.coarse)
    dl_q = shr(-i_q * sd * g[1][0] + i_d * sq * g[1][1], 2 * s + lut.coarse)
    dl_dq = shr(-abs(i_q) * g[2][0] + abs(i_d) * g[2][1], 2 * s + lut.coarse)
    return LutPoint(sd * lam_d, sq * lam_q, l_d, l_q, sd * sq * l_dq, dl_d, dl_q, dl_dq)


def warp(x: int, knee: int, coarse: int) -> int:
    """The grid coordinate of a current magnitude ``x`` >= 0 (module docstring)."""
    return x if x < knee else knee + shr(x - knee, coarse)


def unwarp(u: int, knee: int, coarse: int) -> int:
    """The current magnitude of the grid coordinate ``u`` (host side: where the grid points lie)."""
    return u if u < knee else knee + ((u - knee) << coarse)


def _bilinear(t00: int, t01: int, t10: int, t11: int, fx: int, fy: int, s: int) -> int:
    a = t00 + shr((t01 - t00) * fx, s)
    b = t10 + shr((t11 - t10) * fx, s)
    return a + shr((b - a) * fy, s)
