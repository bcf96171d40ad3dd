"""argparse types shared by the ``hfi`` command and the scripts: a value no run can use (a duration of NaN, a
count of 0) is refused by argparse's own one-line usage error instead of a traceback later."""

from __future__ import annotations

import argparse
import math


def positive_finite(text: str) -> float:
    """A finite number > 0 (durations, seconds, volts)."""
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a number") from None
    if not (math.isfinite(value) and value > 0):
        raise argparse.ArgumentTypeError(f"{text!r}: expected a finite number > 0")
    return value


def positive_int(text: str) -> int:
    """An integer >= 1 (counts: seeds, repeats)."""
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not an integer") from None
    if value < 1:
        raise argparse.ArgumentTypeError(f"{text!r}: expected an integer >= 1")
    return value
