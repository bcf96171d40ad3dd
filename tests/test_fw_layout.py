"""The firmware's code layout against the 16 KiB direct-mapped instruction cache (firmware/link.ld, docs/soc.md
"The instruction cache"): the 000 step's functions (link.ld's first two groups) and the 002 step's (the shared
group and the 002 group) each lie within one cache size, so no line of a step evicts another of the same step.
When the 000 step outgrew the cache (2026-11-28: 18 KiB), its drive overran the 10 kHz period on the soft core;
this test names the cause before a co-simulation has to find it."""

from __future__ import annotations

import importlib.util
import re
import sys
from pathlib import Path

import pytest

from hfi import soc_platform
from hfi.rtl_backend import build_firmware

ROOT = Path(__file__).resolve().parents[1]


def link_groups() -> dict[str, list[str]]:
    """The functions of each commented group (``/* 000 */``, ``/* shared */``, ...) of link.ld's .text, in order."""
    text = (ROOT / "firmware" / "link.ld").read_text()
    body = text[text.index(".text : {"):]
    groups: dict[str, list[str]] = {}
    name = None
    for line in body.splitlines():
        m = re.match(r"\s*/\* (\w+) \*/\s*$", line)
        if m:
            name = m.group(1)
            groups[name] = []
            continue
        m = re.match(r"\s*\*\(\.text\.(?:unlikely\.|startup\.)?(\w+)", line)
        if m and name:
            groups[name].append(m.group(1))
        if line.strip() == "*(.text .text.*)":
            name = None
    return groups


@pytest.fixture(scope="module")
def symbols() -> dict[str, tuple[int, int]]:
    """name -> (start, end) of the image's functions (scripts/fw_profile.py's reading of ``nm``; a static
    function's clone, ``applied_dq.isra.0``, under its own name)."""
    spec = importlib.util.spec_from_file_location("fw_profile", ROOT / "scripts" / "fw_profile.py")
    fw_profile = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(fw_profile)
    return {name.split(".")[0]: (start, end) for start, end, name in fw_profile.functions(str(build_firmware()))}


def span(symbols: dict, names: list[str]) -> int:
    missing = [n for n in names if n not in symbols]
    assert not missing, f"link.ld names functions the image does not have: {missing}"
    return max(symbols[n][1] for n in names) - min(symbols[n][0] for n in names)


def test_link_script_has_the_groups():
    groups = link_groups()
    assert {"000", "shared", "002", "001", "003"} <= set(groups), groups
    assert "fw_step" in groups["shared"] and "fw_rot_step" in groups["000"] and "fw_sqw_step" in groups["002"]


OUTSIDE = {"shared": "every step's code", "idle": "the idle loop and the log, between the steps"}
TOO_LARGE = {"003": "its step is about 23 KiB with the shared code, and its group holds the code no step runs as well "
                    "(scripts/fw_layout.py; docs/soc.md, 'The instruction cache')"}
"""Groups of link.ld that are not a method's step, and the method whose step cannot fit (and why)."""


@pytest.mark.parametrize("method", [
    pytest.param(g, marks=pytest.mark.xfail(strict=True, reason=TOO_LARGE[g])) if g in TOO_LARGE else g
    for g in link_groups() if g not in OUTSIDE])
def test_a_step_fits_the_instruction_cache(symbols, method):
    """Every method's step with the shared code spans at most the instruction cache; the one that does not (TOO_LARGE)
    is a strict xfail, which fails the day it fits (then the entry goes)."""
    groups = link_groups()
    names = groups[method] + groups["shared"]
    assert span(symbols, names) <= soc_platform.CPU_ICACHE_BYTES, (
        f"the {method} step's functions span {span(symbols, names)} bytes, more than the "
        f"{soc_platform.CPU_ICACHE_BYTES}-byte instruction cache (docs/soc.md, 'The instruction cache')")


def test_the_build_without_accelerators_links():
    """The ACC=0 CFU=0 image (the Tang Nano 20K's: software sin/cos and flux-map look-up, fw_fx.h's plain C) fits the
    RAM with the stack link.ld asks for (its ASSERT fails the link otherwise; 2026-11-29 the ACC=0 image did, with
    64-byte alignment)."""
    elf = build_firmware(acc=False, cfu=False)
    assert elf.exists() and (elf.parent.parent.name, elf.parent.name) == ("noacc", "nocfu")


def _fw_layout():
    spec = importlib.util.spec_from_file_location("fw_layout", ROOT / "scripts" / "fw_layout.py")
    mod = importlib.util.module_from_spec(spec)
    sys.modules["fw_layout"] = mod                      # its dataclass looks its module up there
    spec.loader.exec_module(mod)
    return mod


MAP_TEXT = """ *(.text.fw_a)
 .text.fw_a     0x00000040       0x24 /tmp/cc1.o
                0x00000040                fw_a
 *fill*         0x00000064       0x1c
 .text.unlikely.fw_b
                0x00000080       0x30 /tmp/cc1.o
 .text          0x000000b0       0x10 /usr/lib/gcc/riscv64-unknown-elf/13/rv32im/ilp32/libgcc.a(_divdi3.o)
 .text.empty    0x000000c0        0x0 /tmp/cc1.o
"""


def test_layout_tool_reads_the_link_map_and_places_with_alignment(tmp_path):
    """map_sections reads both line forms of a GNU ld map (name and address on one line or two) and drops empty
    sections; place keeps 64-byte alignment for C functions and a word for the library and unlikely sections."""
    fl = _fw_layout()
    (tmp_path / "x.map").write_text(MAP_TEXT)
    secs = fl.map_sections(tmp_path / "x.map")
    assert [(s.name, s.addr, s.size) for s in secs] == [(".text.fw_a", 0x40, 0x24), (".text.unlikely.fw_b", 0x80, 0x30),
                                                         (".text", 0xB0, 0x10)]
    assert [s.align for s in secs] == [64, 4, 4]
    assert [s.link_line() for s in secs] == ["*(.text.fw_a)", "*(.text.unlikely.fw_b)", "*libgcc.a:_divdi3.o(.text .text.*)"]
    addrs, end = fl.place([secs[2], secs[0], secs[1]], 0x44)
    assert addrs == [0x44, 0x80, 0xA4] and end == 0xD4


def test_layout_tool_cost_counts_the_lines_that_share_a_set():
    """conflict_cost: lines one cache size apart share a set; each set costs the shares of its running lines less
    the largest (a line's share: its clocks over 8, at most 1)."""
    fl = _fw_layout()
    n = fl.SETS
    assert fl.conflict_cost({0: 8.0, n: 8.0}) == 1.0                      # two lines that run every period
    assert fl.conflict_cost({0: 16.0, n: 4.0, 2 * n: 2.0}) == 0.75         # 1 + 0.5 + 0.25 less 1
    assert fl.conflict_cost({0: 8.0, 1: 8.0, n + 2: 8.0}) == 0.0           # three sets, one line each


def test_layout_tool_eviction_cost_charges_lines_new_to_the_step():
    """eviction_cost: a line of the step that did not run before it is charged its share when a line that ran before
    it used its set; a line that ran before, or one in a set nothing used, costs nothing."""
    fl = _fw_layout()
    n = fl.SETS
    before = {0: 8.0, 1: 8.0}
    assert fl.eviction_cost(before, {n: 8.0}) == 1.0                      # new line, set 0 used before
    assert fl.eviction_cost(before, {n + 1: 2.0}) == 0.25                 # its share: 2 clocks over 8
    assert fl.eviction_cost(before, {0: 8.0, 2: 8.0, n + 5: 8.0}) == 0.0   # ran before; sets 2 and 5 unused


def test_layout_tool_search_swaps_two_sections():
    """search also swaps two sections, which keeps those between them in place: four one-line sections A, B (that run)
    and C, D (that do not) after lines that run in cache sets 1 and 3; A sits in set 1. No move of one section
    leaves both A and B out of sets 1 and 3 (checked here over every move); swapping A with D does, and search
    finds it from the present order alone."""
    import numpy as np
    fl = _fw_layout()
    lib = "/usr/lib/libgcc.a(_x.o)"                                   # word-aligned sections
    cache = soc_platform.CPU_ICACHE_BYTES
    head = [fl.Section(".text.h1", cache + 32, 32, lib), fl.Section(".text.h3", cache + 96, 32, lib)]
    tail = [fl.Section(f".text.{n}", 32 * (k + 1), 32, lib) for k, n in enumerate("abcd")]
    clocks = np.zeros((cache + 128 - soc_platform.RAM_BASE) // 4)
    for s in head + tail[:2]:
        clocks[(s.addr - soc_platform.RAM_BASE) // 4] = 8.0
    fixed = fl.line_clocks(head, [s.addr for s in head], clocks)

    def cost(order):
        return fl.conflict_cost({**fixed, **fl.line_clocks(order, fl.place(order, 32)[0], clocks)})

    assert cost(tail) == 1.0
    moves = [tail[:i] + tail[i + 1:] for i in range(4)]
    assert min(cost(m[:j] + [tail[i]] + m[j:]) for i, m in enumerate(moves) for j in range(4)) == 1.0
    order, c, c0 = fl.search(head, tail, [clocks], restarts=0, seed=1, progress=False)
    assert (c0, c) == (1.0, 0.0) and [s.name[6:] for s in order] == ["d", "b", "c", "a"]


def test_link_script_names_only_sections_the_image_has():
    """Every line of link.ld's last group names a section of the image's link map (a renamed function would
    otherwise fall silently to the catch-all, out of the chosen order)."""
    fl = _fw_layout()
    build_firmware()
    lines = {s.link_line() for s in fl.map_sections(ROOT / "out" / "firmware" / "hfi_fw.map")}
    text = (ROOT / "firmware" / "link.ld").read_text()
    a, b = fl.group_bounds(text)
    stale = [ln.strip() for ln in text[a:b].splitlines() if ln.strip() and ln.strip() not in lines]
    assert not stale, f"link.ld's /* 003 */ group names sections the image does not have: {stale}"
