#!/usr/bin/env python3
"""The firmware's deepest stack chain, from GCC's call graph (``-fcallgraph-info=su``: a ``.ci`` file beside each
object of an image, ``$(OUT)/obj``): the stack the image needs, against the reservation its link asks for
(docs/soc.md, "The stack").

    python scripts/fw_stack.py [--image DIR ...]    the images built (default: all under out/firmware)
    python scripts/fw_stack.py --need OBJ_DIR         the bytes to reserve (firmware/Makefile's link)

The interrupt is enabled only in ``run`` (main.c, ``irq_enable``), so the deepest chain is the larger of
``main``'s own deepest path and ``main`` > ``run``'s deepest path > a trap frame > ``irq_handler``'s deepest path >
a second trap frame > ``exception_handler``'s path (a fault inside the interrupt, which reports and stops). A call
through the estimator plug-in table (``__indirect_call``) is taken as the deepest of the table's members
(``fw_methods`` in control.c), and an indirect call anywhere else is refused (its targets are unknown); a function
without a node (libgcc's 64-bit division and shifts) as ``EXTERNAL_FRAME`` bytes. The trap frame is crt0.S's
``addi sp, sp, -N`` of ``trap_entry``. Every other number is GCC's own (``-fstack-usage``
frames), so the result is exact up to libgcc.
"""

from __future__ import annotations

import argparse
import re
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
EXTERNAL_FRAME = 64
"""Stack bytes assumed for a callee outside the call graph: libgcc's ``__divdi3``, ``__ashldi3`` and ``__clzdi2``
of Debian's riscv64-unknown-elf-gcc 12 are leaves that move no stack pointer (2026-11-30); ``memset`` and
``memcpy`` of mem.c have nodes."""
MARGIN = 128
"""Bytes reserved beyond the deepest chain, which is exact up to libgcc (module docstring): for a libgcc of
another toolchain deeper than ``EXTERNAL_FRAME``."""
INDIRECT = "__indirect_call"

_NODE = re.compile(r'node: \{ title: "([^"]+)" label: "([^"]*)"')
_EDGE = re.compile(r'edge: \{ sourcename: "([^"]+)" targetname: "([^"]+)"(?: label: "([^"]*)")?')
_BYTES = re.compile(r"\\n(\d+) bytes \((static|dynamic[^)]*)\)")


def _name(title: str) -> str:
    """A node's function name (a static function's title is ``file:name``, so two of one name stay apart)."""
    return title.rsplit(":", 1)[-1]


def title_of(frames: dict[str, int], name: str) -> str:
    """The node of the one defined function called ``name``."""
    found = [t for t in frames if _name(t) == name]
    if len(found) != 1:
        raise ValueError(f"{len(found)} functions called {name} in the call graph (one expected)")
    return found[0]


def parse_callgraph(texts: list[str]) -> tuple[dict[str, int], dict[str, set[str]], list[str]]:
    """Frames [bytes] and callees by node title, and the source locations (``file:line:col``) of the indirect
    calls, from the ``.ci`` texts. A dynamic frame (``alloca``, VLAs) is refused: its size is not known."""
    frames: dict[str, int] = {}
    calls: dict[str, set[str]] = {}
    sites: list[str] = []
    for text in texts:
        for title, label in _NODE.findall(text):
            m = _BYTES.search(label)
            if m is None:
                continue                                  # a declaration (its node is in the defining file)
            if m.group(2) != "static":
                raise ValueError(f"{_name(title)}: a dynamic stack frame ({m.group(2)}); the depth is not bounded")
            frames[title] = int(m.group(1))
        for src, dst, where in _EDGE.findall(text):
            calls.setdefault(src, set()).add(dst)
            if dst == INDIRECT:
                sites.append(where)
    return frames, calls, sites


def check_indirect_sites(sites: list[str]) -> None:
    """Every indirect call must go through the plug-in table (its source line indexes ``fw_methods`` or calls
    through ``ops``, control.c's name for a ``const struct fw_est_ops *`` into it): the targets of any other are
    unknown to this model."""
    for where in sites:
        path, line = where.rsplit(":", 2)[:2]
        text = Path(path).read_text().splitlines()[int(line) - 1]
        if "fw_methods[" not in text and "ops->" not in text:
            raise ValueError(f"{where}: an indirect call outside the plug-in table fw_methods (its targets are "
                             f"unknown to scripts/fw_stack.py): {text.strip()}")


def plugin_members(control_c: str) -> set[str]:
    """The functions of the estimator plug-in table ``fw_methods`` (control.c): the targets of its calls."""
    m = re.search(r"fw_methods\[FW_METHODS\](?: STEP_TABLE)? = \{(.*?)\n\};", control_c, re.S)
    if m is None:
        raise ValueError("control.c: no fw_methods table")
    return set(re.findall(r"\b(fw_\w+)\b", m.group(1))) - {"fw_methods"}


def deepest(frames: dict[str, int], calls: dict[str, set[str]], indirect: set[str], root: str) -> tuple[int, list[str]]:
    """The deepest path from the node ``root``: its bytes (frames summed) and its functions' names. ``indirect``:
    the nodes an indirect call may reach. Recursion is refused."""
    done: dict[str, tuple[int, tuple[str, ...]]] = {}
    active: set[str] = set()

    def walk(fn: str) -> tuple[int, tuple[str, ...]]:
        if fn in done:
            return done[fn]
        if fn in active:
            raise ValueError(f"recursion through {_name(fn)}: the depth is not bounded")
        if fn not in frames:
            return EXTERNAL_FRAME, (_name(fn),)
        active.add(fn)
        best: tuple[int, tuple[str, ...]] = (0, ())
        for callee in sorted(calls.get(fn, ())):
            for target in (sorted(indirect) if callee == INDIRECT else (callee,)):
                got = walk(target)
                best = got if got[0] > best[0] else best
        active.discard(fn)
        done[fn] = (frames[fn] + best[0], (_name(fn),) + best[1])
        return done[fn]

    n, path = walk(root)
    return n, list(path)


def trap_frame(crt0: str) -> int:
    """The bytes ``trap_entry`` of crt0.S takes (its ``addi sp, sp, -N``)."""
    m = re.search(r"trap_entry:.*?addi\s+sp,\s*sp,\s*-(\d+)", crt0, re.S)
    if m is None:
        raise ValueError("crt0.S: trap_entry takes no stack frame")
    return int(m.group(1))


def image_depth(obj_dir: Path) -> tuple[int, list[str]]:
    """The deepest chain (module docstring) of the image whose objects' call graphs (``*.ci``) are in
    ``obj_dir``: bytes and the functions along it (``<trap>`` for a trap frame)."""
    texts = [p.read_text() for p in sorted(obj_dir.glob("*.ci"))]
    if not texts:
        raise FileNotFoundError(f"{obj_dir}: no .ci files (build the image: make -C firmware)")
    frames, calls, sites = parse_callgraph(texts)
    check_indirect_sites(sites)
    indirect = {title_of(frames, n) for n in plugin_members((ROOT / "firmware/src/control.c").read_text())}
    trap = trap_frame((ROOT / "firmware/src/crt0.S").read_text())
    main, run = title_of(frames, "main"), title_of(frames, "run")
    if run not in calls.get(main, ()):
        raise ValueError("main does not call run, where the interrupt is enabled: the model no longer holds")
    total, chain = frames[main], ["main"]
    irq, exc = title_of(frames, "irq_handler"), title_of(frames, "exception_handler")
    for root, frame in ((run, 0), (irq, trap), (exc, trap)):
        n, path = deepest(frames, calls, indirect, root)
        total += frame + n
        chain += (["<trap>"] if frame else []) + path
    alone, path = deepest(frames, calls, indirect, main)
    return (total, chain) if total >= alone else (alone, path)


def need(obj_dir: Path) -> int:
    """The stack bytes to reserve: the deepest chain plus ``MARGIN``, rounded up to 16 (the ABI's alignment)."""
    return -(-(image_depth(obj_dir)[0] + MARGIN) // 16) * 16


def reservation(image_dir: Path) -> int:
    """The stack bytes the image's link asked for (``hfi_stack_bytes`` in its map)."""
    text = (image_dir / "hfi_fw.map").read_text()
    m = re.search(r"0x([0-9a-f]+)\s+hfi_stack_bytes = ", text)
    if m is None:
        raise ValueError(f"{image_dir}/hfi_fw.map: no hfi_stack_bytes")
    return int(m.group(1), 16)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--image", action="append", type=Path, help="an image's build directory (with hfi_fw.map)")
    ap.add_argument("--need", type=Path, metavar="OBJ_DIR", help="print the bytes to reserve for these objects")
    args = ap.parse_args(argv)
    if args.need is not None:
        try:
            print(need(args.need))
        except (OSError, ValueError) as e:
            print(f"fw_stack: {e}", file=sys.stderr)
            return 1
        return 0
    images = args.image or sorted(p.parent for p in (ROOT / "out/firmware").glob("**/hfi_fw.map"))
    if not images:
        print("fw_stack: no image built (make -C firmware)", file=sys.stderr)
        return 1
    failed = 0
    for d in images:
        try:
            n, chain = image_depth(d / "obj")
            have = reservation(d)
        except (OSError, ValueError) as e:
            print(f"fw_stack: {e}", file=sys.stderr)
            failed = 1
            continue
        print(f"{d.relative_to(ROOT) if d.is_relative_to(ROOT) else d}: deepest chain {n} bytes, "
              f"reserved {have} ({have - n} to spare)")
        print("  " + " > ".join(chain))
    return failed


if __name__ == "__main__":
    sys.exit(main())
