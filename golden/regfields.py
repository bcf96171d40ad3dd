"""Field packing of register values, shared by the generated register maps (``golden/regmap.py``,
``golden/socmap.py``; scripts/gen_regs.py writes only their tables and binds these helpers to them).

A map is ``REGISTERS[name] = {"addr", "reset", "signed", "fields"}`` with ``fields[name] = (lsb, width,
reset, access)`` and ``signed`` the names of the signed (two's complement) fields.
"""

from __future__ import annotations


class RegisterFields:
    """``pack``/``unpack``/``field_range`` over one register table of ``regwidth``-bit registers."""

    def __init__(self, registers: dict, regwidth: int):
        self.registers = registers
        self.regwidth = regwidth

    def _reg(self, reg_name: str) -> dict:
        try:
            return self.registers[reg_name]
        except KeyError:
            raise ValueError(f"unknown register {reg_name!r} (known: {', '.join(self.registers)})") from None

    def field_range(self, reg_name: str, field_name: str) -> tuple[int, int]:
        """Inclusive range of the values a field accepts in ``pack`` (signed range for signed fields)."""
        reg = self._reg(reg_name)
        if field_name not in reg["fields"]:
            raise ValueError(f"register {reg_name} has no field {field_name!r} (fields: {', '.join(reg['fields'])})")
        width = reg["fields"][field_name][1]
        if field_name in reg["signed"]:
            return -(1 << (width - 1)), (1 << (width - 1)) - 1
        return 0, (1 << width) - 1

    def pack(self, reg_name: str, **fields: int) -> int:
        """Register value with the given field values (fields not named are 0).

        Signed fields take values in their signed range (stored in two's complement), unsigned fields in
        0 .. 2^width - 1. Raises ValueError on an unknown register or field or a value that does not fit.
        """
        reg = self._reg(reg_name)
        value = 0
        for name, v in fields.items():
            lo, hi = self.field_range(reg_name, name)
            if not isinstance(v, int):
                raise ValueError(f"{reg_name}.{name} = {v!r}: not an integer")
            if not lo <= v <= hi:
                kind = "signed" if name in reg["signed"] else "unsigned"
                raise ValueError(f"{reg_name}.{name} = {v} does not fit the {kind} {reg['fields'][name][1]}-bit "
                                 f"field ({lo} .. {hi})")
            lsb, width = reg["fields"][name][:2]
            value |= (v & ((1 << width) - 1)) << lsb
        return value

    def unpack(self, reg_name: str, value: int) -> dict[str, int]:
        """Field values of a register value (signed fields sign-extended).

        Raises ValueError on an unknown register or a value outside 0 .. 2^regwidth - 1.
        """
        reg = self._reg(reg_name)
        if not isinstance(value, int) or not 0 <= value < (1 << self.regwidth):
            raise ValueError(f"{reg_name} value {value!r} is not a {self.regwidth}-bit unsigned integer")
        out = {}
        for name, (lsb, width, _reset, _access) in reg["fields"].items():
            v = (value >> lsb) & ((1 << width) - 1)
            if name in reg["signed"] and v >> (width - 1):
                v -= 1 << width
            out[name] = v
        return out
