"""Frozen ADC lanes of a window (docs/spec.md 3.13), bit-true: ``WIN_ADC``.

A lane is frozen in a window when the window has at least two conversions and every one of them (every
conversion whose sampling instant lies in the window, blanked ones too: the set the overcurrent comparator
sees) returned the same raw code on it. A live current sensor never does with 1 us oversampling (noise, PWM
ripple); one stuck on a code always does. The firmware's sensor check counts frozen windows
(golden.firmware.protection.frozen_check).
"""

from __future__ import annotations

import numpy as np

from golden.regmap import WIN_ADC_FROZEN_A_MASK, WIN_ADC_FROZEN_B_MASK


def frozen_lanes(code_a: np.ndarray, code_b: np.ndarray) -> int:
    """``WIN_ADC`` of a window from the raw codes of its conversions on lanes A and B (1-D, one length)."""
    if len(code_a) < 2:
        return 0
    return ((WIN_ADC_FROZEN_A_MASK if (code_a == code_a[0]).all() else 0)
            | (WIN_ADC_FROZEN_B_MASK if (code_b == code_b[0]).all() else 0))
