"""The speed of this machine against the one the project's time targets were set on (docs/testing.md).

The targets (the suite within 15 minutes on 2 cores; the benchmarks of issue 21) were written when the plant
benchmark (``scripts/bench_plant.py``, batch API, one core) read :data:`REFERENCE_PLANT_X`. The shared VM has since
run at 0.4 to 1 times that speed with no code changed, and the suite's CPU time and the benchmarks followed the
plant benchmark (docs/testing.md). A time measured here, scaled by the plant benchmark measured beside it, is the
estimate of the same time on the reference machine; the scripts print both, and the measured one comes first.
"""

from __future__ import annotations

REFERENCE_PLANT_X = 6.4
"""The plant benchmark's realtime factor on the reference machine: issue 21's text, filed with issues 14 to 20 on
2026-11-25 ("the plant alone about 6.4x")."""


def slowdown(plant_x: float) -> float:
    """How many times slower than the reference this machine ran, from a plant benchmark ``plant_x`` (> 0)."""
    if not plant_x > 0:
        raise ValueError(f"plant benchmark {plant_x!r}: expected a realtime factor > 0")
    return REFERENCE_PLANT_X / plant_x
