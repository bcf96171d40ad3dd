"""The firmware's code layout against the 16 KiB direct-mapped instruction cache (firmware/link.ld, docs/soc.md
"The instruction cache"): the 000 step's functions (link.ld's first two groups) and the 002 step's (the shared
group and the 002 group) each lie within one cache size, so no line of a step evicts another of the same step.
When the 000 step outgrew the cache (2026-11-28: 18 KiB), its drive overran the 10 kHz period on the soft core;
this test names the cause before a co-simulation has to find it."""

from __future__ import annotations

import importlib.util
import re
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
        m = re.match(r"\s*\*\(\.text\.(\w+)", line)
        if m and name:
            groups[name].append(m.group(1))
        if line.strip().startswith("*libgcc") or line.strip() == "*(.text .text.*)":
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
TOO_LARGE = {"003": "its step is about 23 KiB with the shared code (docs/soc.md, 'The instruction cache')"}
"""Groups of link.ld that are not a method's step, and the method whose step cannot fit (and why)."""


@pytest.mark.parametrize("method", [g for g in link_groups() if g not in OUTSIDE])
def test_a_step_fits_the_instruction_cache(symbols, method):
    if method in TOO_LARGE:
        pytest.skip(TOO_LARGE[method])
    groups = link_groups()
    names = groups[method] + groups["shared"]
    assert span(symbols, names) <= soc_platform.CPU_ICACHE_BYTES, (
        f"the {method} step's functions span {span(symbols, names)} bytes, more than the "
        f"{soc_platform.CPU_ICACHE_BYTES}-byte instruction cache (docs/soc.md, 'The instruction cache')")


def test_the_build_without_accelerators_links():
    """The ACC=0 image (the Tang Nano 20K's: software sin/cos and flux-map look-up) fits the RAM with the stack
    link.ld asks for (its ASSERT fails the link otherwise; 2026-11-29 it did, with 64-byte alignment)."""
    elf = build_firmware(acc=False)
    assert elf.exists() and elf.parent.name == "noacc"
