"""Argument checks shared by the FPGA block models: clear ValueError/TypeError, never a silent wrap."""

from __future__ import annotations

import numpy as np


def int_param(value, lo: int, hi: int, name: str) -> int:
    """``value`` as a Python int in ``lo..hi``; ValueError for non-integers (bools, floats) or out of range."""
    if type(value) is int and lo <= value <= hi:        # fast path: a plain int in range
        return value
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, (int, np.integer)):
        raise ValueError(f"{name} must be an int, got {type(value).__name__}")
    value = int(value)
    if not lo <= value <= hi:
        raise ValueError(f"{name} = {value} must be in {lo}..{hi}")
    return value


def int_or_array(x, name: str, as_int64: bool = False):
    """A Python int for an integer scalar; an integer numpy array (int64 copy if ``as_int64``, else as
    given) for an integer array; TypeError otherwise, ValueError for uint64 beyond the int64 range."""
    if isinstance(x, np.ndarray):
        if x.dtype.kind not in "iu":
            raise TypeError(f"{name} must be an integer array, got dtype {x.dtype}")
        if x.dtype == np.uint64 and x.size and int(x.max()) > np.iinfo(np.int64).max:
            raise ValueError(f"{name} holds values above the int64 range")
        return x.astype(np.int64) if as_int64 else x
    if isinstance(x, (bool, np.bool_)) or not isinstance(x, (int, np.integer)):
        raise TypeError(f"{name} must be an int or an integer numpy array, got {type(x).__name__}")
    return int(x)
