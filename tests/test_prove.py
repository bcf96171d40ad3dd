"""Formal proofs of the RTL (scripts/prove.py, SymbiYosys + z3): the gate generator's dead-time safety
holds for every input sequence, and the cover trace shows the properties are not vacuous."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def test_prove_gate_generator(tmp_path):
    proc = subprocess.run([sys.executable, str(ROOT / "scripts" / "prove.py"), "--workdir", str(tmp_path)],
                          capture_output=True, text=True, timeout=600)
    assert proc.returncode == 0, f"scripts/prove.py failed:\n{proc.stdout}\n{proc.stderr}"
    for task in ("prove", "prove8", "cover"):
        assert f"hfi_gate_gen.sby {task}: PASS" in proc.stdout, proc.stdout
