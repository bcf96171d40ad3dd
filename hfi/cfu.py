"""The fixed-point instructions of the soft core: what each one computes (the reference of rtl/hfi_cfu.v).

The firmware's arithmetic is golden's integer arithmetic in C: sums of 32 x 32-bit products in int64, then
a shift, a rounding and a saturation (``golden.fixed``). On RV32IM each product is a ``mul`` and a
``mulh``, each 64-bit sum an add with a carry, each shift three instructions and each saturation two
compares of a 64-bit value: 12-15 instructions for ``sat(round_shr(a b + c d, 15), 32)``. The core's CFU
port (LiteX's, ``hfi/vexriscv_gen.py``) takes RISC-V custom-0 R-type instructions (``funct3`` the operation,
``funct7`` a shift ``k`` in 0..63) to the unit rtl/hfi_cfu.v, which keeps a 64-bit accumulator ``acc``
(``kb``: ``k`` rounded down to a multiple of 8, a byte shift, cheap beside the accumulator's adder):

=====  =========================================================  ========
op     effect (``a`` = rs1, ``b`` = rs2, both int32)              rd
=====  =========================================================  ========
MUL    ``acc = (a b) >> kb``                                      0
MAC    ``acc += (a b) >> kb``                                     0
MSU    ``acc -= (a b) >> kb``                                     0
ADD    ``acc += (a << kb) + b``                                   0
SET    ``acc = (a << 32) + (b as uint32)`` (k ignored)            0
RND    ``sat(round_shr(acc, k), a)``                              result
FLR    ``sat(acc >> k, a)``                                       result
DIV    ``sat(c_div(acc, d), w)``, ``d = (a << 32) + (b as uint32)``  result
=====  =========================================================  ========

``>>`` is the arithmetic shift (floor), ``round_shr`` rounds half up (``golden.fixed.round_shr``), the sums
wrap modulo 2^64 (the firmware's int64, whose documented ranges never overflow). The saturation's width is
the low 6 bits of ``a``: 1..32 saturate to that many bits (``golden.fixed.sat``); 0 and 33..63 take the low
32 bits of the value as they are (the C cast ``(int32_t)``). DIV divides the accumulator by the 64-bit ``d``
(truncating, ``golden.fixed.c_div``) and saturates to ``w`` bits, ``w`` = ``k`` clamped to 2..32; a zero divisor
answers the limit of the accumulator's sign (``2^(w-1) - 1`` for 0 and above, ``-2^(w-1)`` below); the accumulator is
kept (the 003 observer's saturated quotients, docs/soc.md "The 003 observer's divisions"). The C side is
firmware/src/fw_fx.h: the same operations as macros, inline assembly on the SoC (``-DFW_CFU``) and plain int64 C
in the host build.
"""

from __future__ import annotations

from golden.fixed import c_div, sat, wrap
from hfi.soc_platform import CFU_OPS

def _s64(x: int) -> int:
    return wrap(x, 64)


def _s32(x: int) -> int:
    return wrap(x, 32)


def result(acc: int, k: int, bits: int, rounding: bool) -> int:
    """RND (``rounding``) or FLR of ``acc`` (int64) with shift ``k`` and saturation field ``bits``: an int32."""
    v = _s64(acc + (1 << (k - 1))) >> k if rounding and k else acc >> k    # the 64-bit adder wraps
    w = bits & 63
    return sat(v, w) if 1 <= w <= 32 else _s32(v)


def div_width(k: int) -> int:
    """DIV's saturation width from its ``k`` (0..63): clamped to 2..32."""
    return min(max(k, 2), 32)


def quotient(n: int, d: int, k: int) -> int:
    """DIV's answer: ``sat(c_div(n, d), w)`` (int64 ``n``, ``d``), ``w = div_width(k)``; ``d = 0``: the limit of
    ``n``'s sign."""
    w = div_width(k)
    if d == 0:
        return (1 << (w - 1)) - 1 if n >= 0 else -(1 << (w - 1))
    return sat(c_div(n, d), w)


class CfuModel:
    """The unit's accumulator and the value each instruction answers (``op``: funct3, ``k``: funct7)."""

    def __init__(self) -> None:
        self.acc = 0

    def step(self, op: int, k: int, a: int, b: int) -> int:
        """Execute one instruction; ``a``, ``b`` as int32 (or uint32) values; returns rd (int32)."""
        a, b, k = _s32(a), _s32(b), k & 63
        kb = k & 56
        if op == CFU_OPS["MUL"]:
            self.acc = _s64((a * b) >> kb)
        elif op == CFU_OPS["MAC"]:
            self.acc = _s64(self.acc + ((a * b) >> kb))
        elif op == CFU_OPS["MSU"]:
            self.acc = _s64(self.acc - ((a * b) >> kb))
        elif op == CFU_OPS["ADD"]:
            self.acc = _s64(self.acc + (a << kb) + b)
        elif op == CFU_OPS["SET"]:
            self.acc = _s64((a << 32) + (b & 0xFFFF_FFFF))
        elif op == CFU_OPS["RND"]:
            return result(self.acc, k, a, True)
        elif op == CFU_OPS["FLR"]:
            return result(self.acc, k, a, False)
        elif op == CFU_OPS["DIV"]:
            return quotient(self.acc, (a << 32) + (b & 0xFFFF_FFFF), k)
        return 0
