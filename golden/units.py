"""Physical quantities written as ``"<number> <unit>"`` strings, converted to SI floats.

A scenario value is either a bare number, meaning the SI base unit of its field, or a string such as
``"5.59 mH"``, ``"4 us"`` or ``"250 rpm"``. Every field has a *dimension* (a key of
:data:`DIMENSIONS`); a unit of another dimension is an error that names the field and lists the
units it accepts.

Units are a plain table, :data:`UNITS`: ``symbol -> Unit(dimension, exponent, factor)``. The SI value
is ``float(Decimal(number) * 10**exponent) * factor``: decimal prefixes are applied exactly, so
``"5.59 mH"`` is the float nearest to 5.59e-3 (``== 5.59e-3``), and the non-decimal factors (rpm,
degrees) are one float multiplication, ``250 * (2*pi/60)``.

Symbols are matched after Unicode NFKC normalisation, so the micro sign ``µ``, the Greek ``μ`` and
``u`` are the same prefix, the ohm sign ``Ω`` is the Greek capital omega, and ``·`` may stand for
``*``.
"""

from __future__ import annotations

import math
import re
import unicodedata
from decimal import Decimal
from typing import NamedTuple

DIMENSIONS: dict[str, tuple[str, str]] = {
    "time": ("a time", "s, ms, us, ns"),
    "frequency": ("a frequency", "Hz, kHz, MHz"),
    "voltage": ("a voltage", "V, mV, kV"),
    "current": ("a current", "A, mA"),
    "inductance": ("an inductance", "H, mH, uH"),
    "flux": ("a flux linkage", "Wb, mWb, V*s"),
    "resistance": ("a resistance", "ohm, mohm, Ω"),
    "capacitance": ("a capacitance", "F, uF, nF, pF"),
    "torque": ("a torque", "N*m, mN*m"),
    "inertia": ("an inertia", "kg*m^2, kg*cm^2, g*cm^2"),
    "angle": ("an angle", "rad, deg"),
    "speed": ("a mechanical speed", "rad/s, rpm, r/min"),
    "viscous_friction": ("a viscous friction coefficient", "N*m*s/rad"),
    "dimensionless": ("a dimensionless number", "no unit, or %"),
    "current_rate": ("a rate of change of current", "A/s, A/ms"),
}
"""Dimension name -> (description with its article, the units listed in error messages)."""

PREFIXES: dict[str, int] = {"p": -12, "n": -9, "u": -6, "μ": -6, "m": -3, "k": 3, "M": 6}
"""SI prefixes (after NFKC normalisation the micro sign ``µ`` is the Greek ``μ``)."""


class Unit(NamedTuple):
    """One unit symbol: SI value = ``float(Decimal(number) * 10**exponent) * factor``."""

    dimension: str
    exponent: int = 0
    factor: float = 1.0


_PREFIXABLE: dict[str, str] = {
    "s": "time",
    "Hz": "frequency",
    "V": "voltage",
    "A": "current",
    "H": "inductance",
    "Wb": "flux",
    "V*s": "flux",
    "ohm": "resistance",
    "Ω": "resistance",
    "F": "capacitance",
    "N*m": "torque",
    "rad": "angle",
    "N*m*s/rad": "viscous_friction",
}
"""SI units that take a prefix (``"mH"``, ``"kohm"``, ``"mN*m"``, ``"mrad"``)."""

_OTHER_UNITS: dict[str, Unit] = {
    "Nm": Unit("torque"),
    "kg*m^2": Unit("inertia"),
    "kg*cm^2": Unit("inertia", -4),
    "g*cm^2": Unit("inertia", -7),
    "deg": Unit("angle", 0, math.pi / 180),
    "°": Unit("angle", 0, math.pi / 180),
    "rad/s": Unit("speed"),
    "rpm": Unit("speed", 0, 2 * math.pi / 60),
    "r/min": Unit("speed", 0, 2 * math.pi / 60),
    "N*m*s": Unit("viscous_friction"),
    "%": Unit("dimensionless", -2),
    "A/s": Unit("current_rate"),
    "A/ms": Unit("current_rate", 3),
}


def _build_units() -> dict[str, Unit]:
    """The unit table: every prefixable unit with and without each prefix, plus the others."""
    units = {symbol: Unit(dim) for symbol, dim in _PREFIXABLE.items()}
    for symbol, dim in _PREFIXABLE.items():
        for prefix, exponent in PREFIXES.items():
            units[prefix + symbol] = Unit(dim, exponent)
    units.update(_OTHER_UNITS)
    return units


UNITS: dict[str, Unit] = _build_units()
"""Unit symbol (NFKC-normalised) -> :class:`Unit`."""

_QUANTITY = re.compile(r"\s*([-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?)\s*(.*?)\s*")


class UnitError(ValueError):
    """A value that is not a quantity of the expected dimension; the message names the field."""


def normalize_unit(symbol: str) -> str:
    """Canonical spelling of a unit symbol: NFKC (µ -> μ, Ω -> Ω) and ``·``/``⋅`` -> ``*``."""
    return unicodedata.normalize("NFKC", symbol).replace("·", "*").replace("⋅", "*")


def expected(dimension: str) -> str:
    """``"an inductance (H, mH, uH)"``: the phrase used in error messages for ``dimension``."""
    description, examples = DIMENSIONS[dimension]
    return f"{description} ({examples})"


def parse_quantity(value: object, dimension: str, path: str = "value") -> float:
    """Convert a bare number or a ``"<number> <unit>"`` string to a float in SI units.

    Parameters
    ----------
    value : int, float or str
        A bare number (already in the SI base unit of ``dimension``) or a string such as
        ``"5.59 mH"``; a string without unit (``"5"``) is also in the SI base unit.
    dimension : str
        A key of :data:`DIMENSIONS`.
    path : str
        The field name used in error messages, e.g. ``"motor.magnetic.L_d"``.

    Returns
    -------
    float
        The value in SI base units (rad/s mechanical for speeds, rad for angles).

    Raises
    ------
    UnitError
        If ``value`` is not a finite number or a parsable string, or its unit is unknown or of
        another dimension.
    """
    if isinstance(value, bool) or not isinstance(value, (int, float, str)):
        raise UnitError(f"{path}: expected {expected(dimension)} as a number or a "
                        f"'<number> <unit>' string, got {type_name(value)}")
    if isinstance(value, str):
        return _parse_string(value, dimension, path)
    return finite_float(value, path)


def finite_float(value: int | float, path: str) -> float:
    """``float(value)``, or a :class:`UnitError` for infinities, NaN and huge integers."""
    try:
        result = float(value)
    except OverflowError:
        raise UnitError(f"{path}: {value!r} is out of range") from None
    if not math.isfinite(result):
        raise UnitError(f"{path}: {value!r} is not a finite number")
    return result


def _parse_string(text: str, dimension: str, path: str) -> float:
    """:func:`parse_quantity` for a string value."""
    match = _QUANTITY.fullmatch(text)
    if match is None:
        raise UnitError(f"{path}: {text!r} is not a quantity, expected '<number> <unit>' for "
                        f"{expected(dimension)}")
    number, symbol = match.groups()
    unit = UNITS.get(normalize_unit(symbol)) if symbol else Unit(dimension)
    if unit is None:
        raise UnitError(f"{path}: unknown unit {symbol!r} in {text!r}, expected {expected(dimension)}")
    if unit.dimension != dimension:
        raise UnitError(f"{path}: {text!r} is {DIMENSIONS[unit.dimension][0]}, "
                        f"expected {expected(dimension)}")
    try:
        scaled = Decimal(number).scaleb(unit.exponent)
    except ArithmeticError as exc:
        raise UnitError(f"{path}: {text!r} is out of range") from exc
    result = float(scaled) * unit.factor
    if not math.isfinite(result):
        raise UnitError(f"{path}: {text!r} is out of range")
    return result


def split_quantity(text: str, path: str = "value") -> tuple[str, str]:
    """``"1.2 N*m"`` -> ``("1.2", "N*m")``: the number and the unit symbol as written (``""`` without a
    unit). UnitError if ``text`` is not ``"<number> <unit>"``."""
    match = _QUANTITY.fullmatch(text)
    if match is None:
        raise UnitError(f"{path}: {text!r} is not a quantity, expected '<number> <unit>'")
    number, symbol = match.groups()
    return number, symbol


def scale_quantity(value: object, factor: float, path: str = "value") -> int | float | str:
    """``value`` (a bare number or a ``"<number> <unit>"`` string) times ``factor``, in the same unit:
    ``scale_quantity("1.2 N*m", 0.5) == "0.6 N*m"``. The number is scaled in decimal, so the result
    reads as a person would write it. UnitError if ``value`` is neither."""
    if isinstance(value, bool) or not isinstance(value, (int, float, str)):
        raise UnitError(f"{path}: cannot scale {type_name(value)}, expected a number or a '<number> <unit>' string")
    factor = finite_float(factor, f"{path} (scale factor)")
    if not isinstance(value, str):
        return finite_float(value, path) * factor
    number, symbol = split_quantity(value, path)
    scaled = Decimal(number) * Decimal(repr(factor))
    text = format(scaled.normalize(), "f") if scaled != 0 else "0"
    return f"{text} {symbol}" if symbol else text


def type_name(value: object) -> str:
    """The TOML type of a parsed value, with its article, for error messages."""
    names = {bool: "a boolean", int: "an integer", float: "a number", str: "a string",
             list: "an array", dict: "a table"}
    return names.get(type(value), "a date/time")


def format_quantity(value: float, symbol: str) -> str:
    """Format an SI value with an SI prefix, e.g. ``format_quantity(4e-6, "s") == "4 us"``.

    Parameters
    ----------
    value : float
        Value in the SI base unit ``symbol``.
    symbol : str
        The base unit symbol to append (``"s"``, ``"Hz"``, ``"V"``...).

    Returns
    -------
    str
        Up to 6 significant digits and the prefix that puts the mantissa in [1, 1000).
    """
    if value == 0 or not math.isfinite(value):
        return f"{value:g} {symbol}"
    exponent = min(max(3 * math.floor(math.log10(abs(value)) / 3), -12), 6)
    prefix = {-12: "p", -9: "n", -6: "u", -3: "m", 0: "", 3: "k", 6: "M"}[exponent]
    return f"{value / 10.0 ** exponent:.6g} {prefix}{symbol}"
