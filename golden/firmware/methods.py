"""The estimator classes by method id: the one list the supervisor builds its slots from.

A new method adds its class here and its line to :data:`golden.firmware.estimator.METHODS`
(docs/methods.md has the whole checklist).
"""

from __future__ import annotations

from golden.firmware.eemf_smo import EemfSmo
from golden.firmware.estimator import Estimator
from golden.firmware.hfo_proj import HybridFluxProjection
from golden.firmware.rfo import RotorFluxObserver
from golden.firmware.rot_bpf import RotatingBpf
from golden.firmware.sqw_bangbang import SquareWaveBangBang
from golden.firmware.sqw_cic import SquareWaveCic

CLASSES: dict[int, type[Estimator]] = {cls.METHOD: cls for cls in (SquareWaveBangBang, RotorFluxObserver,
                                                                   RotatingBpf, EemfSmo, SquareWaveCic,
                                                                   HybridFluxProjection)}
"""Method id -> estimator class."""
