"""Angle and magnitude of a vector by the vectoring CORDIC (docs/spec.md 5.3), for the firmware.

The same 16-entry arctangent table and gain as the firmware's sin/cos (:func:`golden.fpga.cordic.sincos_q15`,
``fw_cordic_atan`` / ``FW_CORDIC_X0`` in firmware/src/fw_cordic_table.h).

1. if ``x < 0``: ``x, y = -x, -y`` and ``z = 2^31`` (half a turn), else ``z = 0``;
2. for ``i`` in 0..15: if ``y > 0``: ``x, y = x + shr(y, i), y - shr(x, i)``, ``z += ATAN[i]``;
   else: ``x, y = x - shr(y, i), y + shr(x, i)``, ``z -= ATAN[i]`` (each step uses the old x and y);
3. ``angle = uwrap(z, 32)``; ``magnitude = shr(x * X0, 30)`` (X0 = K_16 2^30 removes the CORDIC gain).

Inputs |x|, |y| <= 2^28 (the callers saturate), so x stays below 1.65 * 2^28.5 < 2^30 and every
intermediate fits int32; ``x * X0`` < 2^60 fits int64. The angle error is below 2 * atan(2^-15) (0.004 deg)
plus the rounding of the shifts; ``(0, 0)`` gives magnitude 0 and an angle of no meaning.
"""

from __future__ import annotations

from golden.fixed import shr, uwrap
from golden.fpga.cordic import atan_table, x0

ITERATIONS = 16
ATAN = tuple(atan_table(ITERATIONS))
X0 = x0(32, ITERATIONS)
INPUT_LIMIT = 1 << 28
"""|x|, |y| must not exceed this (the callers saturate to it)."""


def vector_angle(x: int, y: int) -> tuple[int, int]:
    """``(angle, magnitude)`` of ``(x, y)``: u32 binary angle of ``atan2(y, x)`` and ``~sqrt(x^2 + y^2)``.

    C (``int32_t x, y; uint32_t z``): the steps of the module docstring with ``>>`` on int32_t
    (arithmetic, GCC), ``z += (uint32_t)ATAN[i]`` wrapping, and ``(int32_t)(((int64_t)x * X0) >> 30)``.
    """
    z = 0
    if x < 0:
        x, y, z = -x, -y, 1 << 31
    for i in range(ITERATIONS):
        xs, ys = shr(x, i), shr(y, i)
        if y > 0:
            x, y, z = x + ys, y - xs, z + ATAN[i]
        else:
            x, y, z = x - ys, y + xs, z - ATAN[i]
    return uwrap(z, 32), shr(x * X0, 30)
