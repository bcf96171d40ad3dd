"""The host side of firmware/src/fw_fx.h (the fixed-point idioms as int64 C) against hfi/cfu.py, the model the
SoC's unit rtl/hfi_cfu.v is tested against (cocotb_tests/test_cfu.py): the firmware's host build and its SoC
build then compute the same values. A small C program runs instruction lists through the host macros; the
model runs the same lists."""

from __future__ import annotations

import os
import subprocess

import numpy as np
import pytest

from hfi.cfu import CfuModel
from hfi.soc_platform import CFU_OPS

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
PROGRAM = r"""
#include <stdio.h>
#include <stdlib.h>
#include "fw_fx.h"

int main(void)
{
    int op, k;
    long a, b;
    FX_ACC(acc) = 0;
    while (scanf("%d %d %ld %ld", &op, &k, &a, &b) == 4) {
        int32_t r = 0;
        switch (op) {
        case HFI_CFU_MUL: FX_MUL(acc, a, b, k); break;
        case HFI_CFU_MAC: FX_MAC(acc, a, b, k); break;
        case HFI_CFU_MSU: FX_MSU(acc, a, b, k); break;
        case HFI_CFU_ADD: FX_ADD(acc, a, k, b); break;
        case HFI_CFU_SET: FX_SET(acc, a, b); break;
        case HFI_CFU_RND: r = FX_RND(acc, k, a); break;
        case HFI_CFU_FLR: r = FX_FLR(acc, k, a); break;
        case HFI_CFU_DIV: r = FX_DIV(acc, (int64_t)((uint64_t)(uint32_t)a << 32 | (uint32_t)b), k); break;
        case 8: r = FX_DOT(a, b, (int32_t)k - 1000, 7, 15, 32); break;   /* the two-product idioms */
        case 9: r = FX_CROSS(a, b, (int32_t)k - 1000, 7, 15, 21); break;
        case 10: r = FX_SHR(a, b, 16, 0); break;
        case 11: r = FX_SUM(a, b, 32); break;
        case 12: r = FX_PROD(a, b, 17, 26); break;
        default: return 2;
        }
        printf("%d\n", r);
    }
    return 0;
}
"""


@pytest.fixture(scope="module")
def runner(tmp_path_factory):
    d = tmp_path_factory.mktemp("fx")
    (d / "fx.c").write_text(PROGRAM)
    exe = d / "fx"
    subprocess.run(["cc", "-std=c11", "-O2", "-Wall", "-Wextra", "-Werror", f"-I{ROOT}/firmware/src",
                    f"-I{ROOT}/firmware/include", "-o", str(exe), str(d / "fx.c")], check=True)

    def run(prog):
        text = "".join(f"{op} {k} {a} {b}\n" for op, k, a, b in prog)
        out = subprocess.run([str(exe)], input=text, capture_output=True, text=True, check=True).stdout
        return [int(v) for v in out.split()]
    return run


def _s32(rng, n):
    pick = rng.integers(0, 3, size=n)
    full = rng.integers(-(1 << 31), 1 << 31, size=n)
    small = rng.integers(-(1 << 16), 1 << 16, size=n)
    corner = rng.choice([0, 1, -1, -(1 << 31), (1 << 31) - 1, 1 << 30, -(1 << 30)], size=n)
    return np.choose(pick, [full, small, corner]).tolist()


def test_host_macros_equal_the_unit_model(runner):
    """20 000 random instructions of every kind (shifts 0..63, widths 0..63; DIV's divisors from the two words, zero
    sometimes)."""
    rng = np.random.default_rng(int(os.environ.get("HFI_SEED", "12345")))
    n = 20_000
    ops, ks = rng.integers(0, 8, size=n).tolist(), rng.integers(0, 64, size=n).tolist()
    a, b = _s32(rng, n), _s32(rng, n)
    prog = []
    for i in range(n):
        op = ops[i]
        if op in (CFU_OPS["RND"], CFU_OPS["FLR"]):
            prog.append((op, ks[i], int(rng.choice([0, 1, 16, 21, 26, 32, 33, 63])), 0))
        elif op == CFU_OPS["DIV"] and rng.random() < 0.1:
            prog.append((op, ks[i], 0, 0))
        else:
            prog.append((op, ks[i], a[i], b[i]))
    model = CfuModel()
    want = [model.step(op, k, x, y) for op, k, x, y in prog]
    assert sum(op == CFU_OPS["DIV"] and x == y == 0 for op, _, x, y in prog) > 10
    assert runner(prog) == want


def test_div_model_is_the_saturated_quotient():
    """hfi/cfu.py's DIV (the reference of the unit and of the host macro) = sat(c_div(n, d), w) of golden.fixed,
    the firmware's saturated quotients (fw_sat_div64), on 20 000 dividends and divisors of every size and sign,
    the quotients around each width's limit."""
    from golden.fixed import c_div, sat
    from hfi.cfu import quotient

    rng = np.random.default_rng(11)
    hits = 0
    for _ in range(20_000):
        n = int(rng.integers(-(1 << 62), 1 << 62)) >> int(rng.integers(0, 63))
        w = int(rng.choice([2, 16, 18, 21, 22, 32]))
        d = int(rng.integers(-(1 << 62), 1 << 62)) >> int(rng.integers(0, 63)) if rng.random() < 0.5 else \
            (max(abs(n) >> (w - 1), 1) + int(rng.integers(-1, 2))) * int(rng.choice([-1, 1]))
        if d == 0:
            continue
        want = sat(c_div(n, d), w)
        hits += abs(want) in ((1 << (w - 1)) - 1, 1 << (w - 1))
        assert quotient(n, d, w) == want, (n, d, w)
    assert quotient(5, 0, 16) == 32767 and quotient(-5, 0, 16) == -32768 and quotient(0, 0, 2) == 1
    assert hits > 2000, hits


def test_two_product_idioms_equal_golden(runner):
    """FX_DOT, FX_CROSS, FX_SHR, FX_SUM, FX_PROD against golden.fixed's expressions."""
    from golden.fixed import round_shr, sat, shr, wrap

    rng = np.random.default_rng(7)
    n = 5_000
    a, b, c = _s32(rng, n), _s32(rng, n), rng.integers(-1000, 1000, size=n).tolist()
    prog, want = [], []
    for i in range(n):
        x, y, z = a[i], b[i], c[i]
        prog += [(8, z + 1000, x, y), (9, z + 1000, x, y), (10, 0, x, y), (11, 0, x, y), (12, 0, x, y)]
        want += [sat(round_shr(x * y + z * 7, 15), 32), sat(round_shr(x * y - z * 7, 15), 21),
                 wrap(shr(x * y, 16), 32), sat(x + y, 32), sat(round_shr(x * y, 17), 26)]
    assert runner(prog) == want
