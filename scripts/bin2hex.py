#!/usr/bin/env python3
"""Raw little-endian binary -> $readmemh text (one 32-bit hex word per line, word 0 first).

Usage: bin2hex.py IN.bin OUT.hex [--words N]   (N: pad with zeros to N words; error if larger)
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path


def to_words(data: bytes) -> list[int]:
    data = data + bytes(-len(data) % 4)
    return [int.from_bytes(data[i:i + 4], "little") for i in range(0, len(data), 4)]


def write_hex(words: list[int], path: Path) -> None:
    path.write_text("".join(f"{w:08x}\n" for w in words), encoding="ascii")


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("input", type=Path)
    ap.add_argument("output", type=Path)
    ap.add_argument("--words", type=int, default=None, help="pad to this many words")
    a = ap.parse_args(argv)
    words = to_words(a.input.read_bytes())
    if a.words is not None:
        if len(words) > a.words:
            print(f"bin2hex: {a.input} has {len(words)} words, more than the RAM's {a.words}", file=sys.stderr)
            return 1
        words += [0] * (a.words - len(words))
    write_hex(words, a.output)
    return 0


if __name__ == "__main__":
    sys.exit(main())
