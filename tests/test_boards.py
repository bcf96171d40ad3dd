"""Board tops and their pin constraints (docs/boards.md, scripts/bitstream.py), without the long flow:
every bit of every port of each top has exactly one pin, no pin carries two signals, every pin of the
constraints belongs to a port, the command refuses an unknown board with a clear message, and it reads
nextpnr's utilisation report to stop before placing a design that does not fit."""

from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "scripts"))
import bitstream  # noqa: E402


def port_bits(top: Path) -> set[str]:
    """``name`` or ``name[i]`` for every bit of the top's ports (ANSI declarations)."""
    bits = set()
    for width, name in re.findall(r"^\s*(?:input|output)\s+wire\s+(?:\[(\d+):0\]\s+)?(\w+)", top.read_text(), re.M):
        bits |= {f"{name}[{i}]" for i in range(int(width) + 1)} if width else {name}
    return bits


def pin_map(board: bitstream.Board) -> dict[str, str]:
    """Signal bit -> pin of the board's constraint file (LPF LOCATE or CST IO_LOC); a signal twice fails."""
    text = (ROOT / "boards" / board.name / board.constraints).read_text()
    pattern = (r'^LOCATE COMP "([^"]+)" SITE "([^"]+)"' if board.flow == "ecp5"
               else r'^IO_LOC\s+"([^"]+)"\s+([\w,]+);')
    pins: dict[str, str] = {}
    for sig, pin in re.findall(pattern, text, re.M):
        assert sig not in pins, f"{board.name}: {sig} constrained twice"
        pins[sig] = pin
    return pins


@pytest.mark.parametrize("name", sorted(bitstream.BOARDS))
def test_every_port_bit_has_one_pin(name):
    board = bitstream.BOARDS[name]
    bits = port_bits(ROOT / "boards" / name / f"{board.top}.v")
    pins = pin_map(board)
    assert len(bits) >= 20, bits                      # the parser found the ports
    assert bits - set(pins) == set(), f"{name}: ports without a pin"
    assert set(pins) - bits == set(), f"{name}: pins without a port"
    used = list(pins.values())
    assert len(used) == len(set(used)), f"{name}: a pin carries two signals"


def test_unknown_board_is_refused():
    proc = subprocess.run([sys.executable, str(ROOT / "scripts" / "bitstream.py"), "nosuchboard"],
                          capture_output=True, text=True, cwd=ROOT)
    assert proc.returncode == 2
    assert "unknown board 'nosuchboard'" in proc.stderr and "ulx3s" in proc.stderr
    assert "Traceback" not in proc.stderr


def test_over_capacity_reads_nextpnrs_utilisation():
    """The pack-only check of scripts/bitstream.py: the Tang Nano's report of 2026-11-27 with the accelerators
    (20 938 LUT4 of 20 736) is over, the one without them is not."""
    over = """Info: Device utilisation:
Info: \t                 VCC:       1/      1   100%
Info: \t                LUT4:   20938/  20736   100%
Info: \t                 ALU:    5682/  15552    36%
Info: \t               BSRAM:      42/     46    91%
Info: \t          DUMMY_CELL:      44/      0     0%
"""
    assert bitstream.over_capacity(over) == ["LUT4 20938 of 20736"]
    assert bitstream.over_capacity(over.replace("20938/", "14148/")) == []
