"""The FPGA resources of each compared system (``hfi compare``, docs/compare.md): what its own hardware adds to
the blocks every system shares, measured by synthesis, never typed in.

A system's own hardware is the build options (golden.build_options; docs/rtl.md "Build options") its estimator
methods name in ``MethodInfo.hardware``: hfi_dsp's ROT_INJ, DIFF_CIC, FCS_MPC and the accelerators' FLUX_LUT. The
shared base is ``hfi_dsp`` and ``hfi_soc_acc`` with every option left out; a system's cost is each of the two
synthesized with its options in, less the base. Synthesis: ``scripts/synth_module.py --xc7-only`` (Yosys
``synth_xilinx -family xc7``, about 20 s per run), so the numbers are those of docs/rtl.md's tables. Results are
cached in ``resources.json`` of the report's directory, keyed by the RTL sources and the parameters.
"""

from __future__ import annotations

import json
import subprocess
import sys
from dataclasses import dataclass
from pathlib import Path
from typing import Callable

from golden.build_options import ACC_OPTIONS, DSP_OPTIONS, needed
from golden.scenario import Scenario

ROOT = Path(__file__).resolve().parent.parent
TOPS = {"hfi_dsp": DSP_OPTIONS, "hfi_soc_acc": ACC_OPTIONS}
"""The synthesized modules and the options each takes."""
COUNTS = ("lut", "ff", "dsp", "bram")
"""The Xilinx 7-series counts reported (LUT, flip-flops, DSP48E1, RAMB)."""

Synth = Callable[[str, dict], dict]
"""synth(top, {option: 0 or 1}) -> {count: value} for every name of :data:`COUNTS`."""


def options(sc: Scenario) -> tuple[str, ...]:
    """The build options the scenario's estimator methods need, in golden.build_options order."""
    return needed(sc.estimator.low, sc.estimator.high)


def synth_module(top: str, params: dict) -> dict:
    """The xc7 counts of ``top`` with ``params``, from scripts/synth_module.py (its last output line is JSON)."""
    cmd = [sys.executable, str(ROOT / "scripts" / "synth_module.py"), top, "--xc7-only", "--json",
           *(f"-P{k}={v}" for k, v in sorted(params.items()))]
    proc = subprocess.run(cmd, cwd=ROOT, capture_output=True, text=True)
    if proc.returncode != 0:
        raise RuntimeError(f"synthesis of {top} {params} failed:\n{proc.stdout[-2000:]}{proc.stderr[-2000:]}")
    xc7 = json.loads(proc.stdout.strip().splitlines()[-1])["xc7"]
    return {k: xc7[k] for k in COUNTS}


def rtl_digest() -> str:
    """The cache key's part that follows the RTL (hfi.rtl_backend.digest over rtl/)."""
    from hfi.rtl_backend import digest

    return digest(sorted(p for p in (ROOT / "rtl").rglob("*") if p.is_file()), "xc7")


@dataclass(frozen=True)
class Resources:
    """One system's own hardware: its options and what they add to the base, per synthesized module."""

    system: str
    options: tuple[str, ...]
    added: dict                     # top -> {count: added value}; empty for a system without options


def resources(systems: dict[str, Scenario], cache: Path, log=print, synth: Synth = synth_module,
              key: Callable[[], str] = rtl_digest) -> tuple[dict, list[Resources]]:
    """(the base counts per module, each system's Resources), synthesized or read from ``cache``."""
    known = json.loads(cache.read_text()) if cache.exists() else {}
    digest = key()
    if known.get("key") != digest:
        known = {"key": digest, "runs": {}}

    def counts(top: str, on: tuple[str, ...]) -> dict:
        params = {o: int(o in on) for o in TOPS[top]}
        name = f"{top} " + " ".join(f"{k}={v}" for k, v in params.items())
        if name not in known["runs"]:
            log(f"FPGA resources: synthesizing {name} (xc7)")
            known["runs"][name] = synth(top, params)
            cache.parent.mkdir(parents=True, exist_ok=True)
            cache.write_text(json.dumps(known, indent=1))
        return known["runs"][name]

    base = {top: counts(top, ()) for top in TOPS}
    out = []
    for system, sc in systems.items():
        need = options(sc)
        added = {}
        for top, own in TOPS.items():
            mine = tuple(o for o in need if o in own)
            if mine:
                c = counts(top, mine)
                added[top] = {k: c[k] - base[top][k] for k in COUNTS}
        out.append(Resources(system, need, added))
    return base, out


def summary(r: Resources) -> str:
    """The headline's cell: what the system's own blocks add, over both modules."""
    if not r.added:
        return "none (the shared base)"
    total = {k: sum(a[k] for a in r.added.values()) for k in COUNTS}
    return f"{', '.join(r.options)}: {_added(total)}"


def _counts(c: dict) -> str:
    return f"{c['lut']} LUT, {c['ff']} FF, {c['dsp']} DSP, {c['bram']} BRAM"


def _added(c: dict) -> str:
    return ", ".join(f"{c[k]:+d} {k.upper() if k != 'ff' else 'FF'}" for k in COUNTS if c[k]) or "+0"


def table(base: dict, items: list[Resources], labels: dict[str, str]) -> list[str]:
    """The report's section: the shared base and what each system's own hardware adds to it."""
    lines = ["## FPGA resources", "",
             "Xilinx 7-series counts (Yosys `synth_xilinx`, out of context) measured by this command (hfi/resources.py): "
             "the blocks every system shares, then what each system's own blocks add (the build options its methods "
             "name, docs/rtl.md \"Build options\"; a build for one system can leave the others out).", "",
             *(f"- shared `{top}` (every option out): {_counts(c)}" for top, c in base.items()), "",
             "| system | its own blocks | `hfi_dsp` adds | accelerators add |", "|---|---|---|---|"]
    for r in items:
        own = ", ".join(f"`{o}`" for o in r.options) or "none"
        dsp = _added(r.added["hfi_dsp"]) if "hfi_dsp" in r.added else "+0"
        acc = _added(r.added["hfi_soc_acc"]) if "hfi_soc_acc" in r.added else "+0"
        lines.append(f"| {labels.get(r.system, r.system)} | {own} | {dsp} | {acc} |")
    return lines

