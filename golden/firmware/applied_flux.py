"""The firmware's model of the volt-seconds one period of the direct-vector mode applied, bit-true.

The hybrid flux observer integrates the applied voltage (Varatharajan et al. 2020, eq. (5)), and the
paper computes it "from the measured DC link voltage, incorporating dead-time compensation" (Sec. II-C).
In the direct-vector mode (spec 3.10) the state changes at the carrier top, and every leg that switches
waits the dead time ``t_d`` with both switches off; during it the phase current's diode holds the leg:
a leg turning on (0 -> 1) with its current flowing out of it (``i > 0``, into the motor) stays low for
``t_d``, a leg turning off (1 -> 0) with ``i < 0`` stays high for ``t_d``; otherwise the diode already
conducts the new way and the edge is not delayed. Per period (flux units of
:data:`golden.firmware.flux_lut.FLUX_FRAC`):

    flux = (VX_j, VY_j) << FLUX_FRAC                     (the ideal state, golden.fpga.fcs_mpc.state_voltage)
    e_x  = -(s_new,x - s_old,x) * dt_f   if (s_new,x - s_old,x) * sgn(i_x) > 0, else 0     (x = a, b, c)
           - sgn(i_x) * vth_f
    flux += (round_shr((2 e_a - e_b - e_c) * 10923, 15), round_shr((e_b - e_c) * 18919, 15))

with ``dt_f = V_dc t_d`` in flux units (``round(2^(15 + FLUX_FRAC) t_d / T)``) and the phase currents'
signs from the Clarke currents at the switching instant: ``i_a = i_alpha``, ``sgn i_b = sgn(56756 i_beta -
32768 i_alpha)``, ``sgn i_c = sgn(-32768 i_alpha - 56756 i_beta)`` (``56756 = round(sqrt(3) 2^15)``). The
switches' and diodes' forward drops: a phase conducts through a switch or a diode of its leg in every
state, so its terminal voltage loses about ``V_th sgn(i_x) + r_on i_x`` whatever the state: the threshold
part is ``vth_f`` (``V_th T`` in flux units) above, the resistive part is added to the stator resistance
by the host (``[control] inv_v_drop``, ``inv_r_drop``: the inverter's data-sheet values). At standstill
the hybrid observer's flux is off by the uncompensated voltage over ``g`` (2.5 V / 63 rad/s = 40 mV*s,
a third of the low-inductance axis's flux at 2 p.u.).
"""

from __future__ import annotations

from golden.firmware.flux_lut import FLUX_FRAC
from golden.fixed import round_shr
from golden.fpga.fcs_mpc import state_voltage


def _sgn(x: int) -> int:
    return (x > 0) - (x < 0)


def applied_flux(old: int, new: int, i_al: int, i_be: int, dt_f: int, vth_f: int) -> tuple[int, int]:
    """Flux [flux units] that the state ``new`` (applied after ``old``, 3 bits each) adds in one period, with
    the dead-time delays and the threshold drops for the Clarke currents ``i_al, i_be`` at the switching
    instant (module docstring)."""
    v_al, v_be = state_voltage(new)
    signs = (_sgn(i_al), _sgn(56756 * i_be - 32768 * i_al), _sgn(-32768 * i_al - 56756 * i_be))
    e = [0, 0, 0]
    for x in range(3):
        ds = ((new >> x) & 1) - ((old >> x) & 1)
        e[x] = (-ds * dt_f if ds * signs[x] > 0 else 0) - signs[x] * vth_f
    return ((v_al << FLUX_FRAC) + round_shr((2 * e[0] - e[1] - e[2]) * 10923, 15),
            (v_be << FLUX_FRAC) + round_shr((e[1] - e[2]) * 18919, 15))
