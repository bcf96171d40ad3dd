"""The motor / inverter / sensor plant: a C library (``src/``) with a cffi binding."""

from golden.plant.binding import (GATE_BITS, MAG_KINDS, STATE_DTYPE, Plant, PlantError, ShootThroughError,
                                  mag_eval)
from golden.plant.defaults import default_params, merge

__all__ = ["GATE_BITS", "MAG_KINDS", "STATE_DTYPE", "Plant", "PlantError", "ShootThroughError", "default_params",
           "mag_eval", "merge"]
