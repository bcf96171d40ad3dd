#!/usr/bin/env python3
"""Generate the register map outputs from the SystemRDL sources of ``MAPS``.

Three register maps (``MAPS`` below), each compiled the same way into five outputs:

- ``rtl/regs/hfi_regs.rdl`` (addrmap ``hfi_regs``, the hfi_dsp peripheral): ``firmware/include/hfi_regs.h``,
  ``golden/regmap.py``, ``docs/registers.md``, ``out/docs/registers/``, ``rtl/regs/hfi_regs_map.vh``;
- ``rtl/regs/hfi_soc.rdl`` (addrmap ``hfi_soc``, the SoC control block hfi_soc_ctl):
  ``firmware/include/hfi_soc_regs.h``, ``golden/socmap.py``, ``docs/soc_registers.md``,
  ``out/docs/soc_registers/``, ``rtl/regs/hfi_soc_map.vh``;
- ``rtl/regs/hfi_acc.rdl`` (addrmap ``hfi_acc``, the SoC's accelerators hfi_soc_acc):
  ``firmware/include/hfi_acc_regs.h``, ``golden/accmap.py``, ``docs/acc_registers.md``,
  ``out/docs/acc_registers/``, ``rtl/regs/hfi_acc_map.vh``.

Outputs (paths relative to the repository root), all written deterministically:

- C header: PeakRDL-cheader (register unions with bit-fields, per-field ``_bm``/``_bp``/``_bw``/
  ``_reset`` macros, the ``<top>_t`` block struct), plus a block of register byte-offset macros
  ``<TOP>__<REG>_offset`` (``HFI_REGS__CTRL_offset``, ``HFI_SOC__CTRL_offset``) added here
  (PeakRDL-cheader 1.1 has none) with C11 static checks of ``<top>_t`` against them;
- Python constants, from our own walker, with ``pack``/``unpack``/``field_range`` bound from the shared
  helper ``golden/regfields.py``;
- Markdown: PeakRDL-markdown;
- HTML: PeakRDL-html (static site, 8 MB of fonts and scripts: built, not committed; open
  ``index.html``);
- Verilog ``localparam`` constants (addresses, field positions, widths, reset values; prefix ``HFI_``
  for ``rtl/hfi_regs.v``, ``SOC_`` for ``rtl/hfi_soc_ctl.v``, ``ACC_`` for ``rtl/hfi_soc_acc.v``), from our own walker.
  (PeakRDL-regblock's output is SystemVerilog with packed structs and an interface port, which Yosys
  cannot read and Icarus only partly; the IP must synthesize with the open flow, so the blocks are
  plain Verilog-2005 written against these constants and tested against the Python constants.)

Usage::

    python scripts/gen_regs.py            # (re)write every output of every map
    python scripts/gen_regs.py --check    # regenerate into a temporary directory; exit 1 and list
                                          # the outputs that differ from the files in the tree
    python scripts/gen_regs.py --map hfi_soc [--check]   # one map only

Without ``--map`` it also runs ``scripts/gen_platform.py`` (the platform files of hfi_soc: memory map,
trace record, window record), so ``make regs`` regenerates every generated interface file.

An error in an RDL prints the compiler's message and exits with status 1 (nothing is written).
"""

from __future__ import annotations

import argparse
import filecmp
import hashlib
import shutil
import sys
import tempfile
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path

from systemrdl import RDLCompileError, RDLCompiler, RDLListener, RDLWalker
from systemrdl.node import AddrmapNode, FieldNode, RegNode
from systemrdl.rdltypes import AccessType, OnReadType, OnWriteType

ROOT = Path(__file__).resolve().parents[1]


@dataclass(frozen=True)
class RegMap:
    """One register map: its SystemRDL source and its outputs (paths relative to ROOT)."""

    rdl: str  # the source; also the name written into the outputs
    top: str  # addrmap elaborated; the C prefix is top.upper(), the C block struct <top>_t
    block: str  # the RTL block it describes (Verilog header comment, HTML title)
    summary: str  # first line of the Python module's docstring
    header: str  # C header
    python: str  # Python constants, pack/unpack
    markdown: str
    html_dir: str  # built, not committed, not checked
    verilog: str  # Verilog localparams
    verilog_prefix: str  # of every Verilog constant

    @property
    def files(self) -> tuple[str, ...]:
        """The single-file outputs (committed; compared by --check)."""
        return (self.header, self.python, self.markdown, self.verilog)

    @property
    def html_title(self) -> str:
        return f"{self.block} registers ({self.top})"


MAPS = (
    RegMap(rdl="rtl/regs/hfi_regs.rdl", top="hfi_regs", block="hfi_dsp",
           summary="Register map of the hfi_dsp peripheral (docs/spec.md, section 4; docs/registers.md).",
           header="firmware/include/hfi_regs.h", python="golden/regmap.py", markdown="docs/registers.md",
           html_dir="out/docs/registers", verilog="rtl/regs/hfi_regs_map.vh", verilog_prefix="HFI_"),
    RegMap(rdl="rtl/regs/hfi_soc.rdl", top="hfi_soc", block="hfi_soc_ctl",
           summary="Register map of the SoC control block hfi_soc_ctl (docs/soc.md; docs/soc_registers.md).",
           header="firmware/include/hfi_soc_regs.h", python="golden/socmap.py",
           markdown="docs/soc_registers.md", html_dir="out/docs/soc_registers",
           verilog="rtl/regs/hfi_soc_map.vh", verilog_prefix="SOC_"),
    RegMap(rdl="rtl/regs/hfi_acc.rdl", top="hfi_acc", block="hfi_soc_acc",
           summary="Register map of the SoC's arithmetic accelerators hfi_soc_acc (docs/soc.md; docs/acc_registers.md).",
           header="firmware/include/hfi_acc_regs.h", python="golden/accmap.py",
           markdown="docs/acc_registers.md", html_dir="out/docs/acc_registers",
           verilog="rtl/regs/hfi_acc_map.vh", verilog_prefix="ACC_"),
)
MAPS_BY_TOP = {m.top: m for m in MAPS}


class GenError(Exception):
    """A problem of the register map (reported without traceback)."""


# ---------------------------------------------------------------- compile
def compile_rdl(rdl_path: Path, top: str) -> AddrmapNode:
    """Compile the RDL and elaborate addrmap ``top``; the compiler prints its messages, then
    RDLCompileError."""
    from peakrdl_regblock.udps import ALL_UDPS

    rdlc = RDLCompiler()
    # Soft definitions: the RDL declares the ones it uses (is_signed), which makes them official.
    for udp in ALL_UDPS:
        rdlc.register_udp(udp)
    rdlc.compile_file(str(rdl_path))
    return rdlc.elaborate(top).top


# ---------------------------------------------------------------- our walker: the register model
@dataclass
class FieldInfo:
    name: str
    lsb: int
    width: int
    reset: int | None
    access: str
    signed: bool
    lock: str | None = None   # "REG.FIELD" whose 1 blocks software writes (SystemRDL swwel), else None

    @property
    def mask(self) -> int:
        return ((1 << self.width) - 1) << self.lsb


@dataclass
class RegInfo:
    name: str
    addr: int
    title: str
    fields: list[FieldInfo] = field(default_factory=list)
    window_copy: bool = False   # the project's UDP window_copy (rtl/regs/hfi_regs.rdl): held from the window's
                                # results until the next boundary, read by the CPU from hfi_soc's copy


def field_access(node: FieldNode) -> str:
    """Short access code: ro, rw, wo, w1c (write 1 to clear), w1s, w1p (write 1 = pulse), rc."""
    sw = node.get_property("sw")
    onwrite = node.get_property("onwrite")
    if node.get_property("singlepulse"):
        return "w1p"
    if onwrite == OnWriteType.woclr:
        return "w1c"
    if onwrite == OnWriteType.woset:
        return "w1s"
    if onwrite is not None:
        raise GenError(f"{node.get_path()}: onwrite={onwrite.name} not supported by scripts/gen_regs.py")
    if node.get_property("onread") == OnReadType.rclr:
        return "rc"
    return {AccessType.r: "ro", AccessType.rw: "rw", AccessType.rw1: "rw", AccessType.w: "wo",
            AccessType.w1: "wo"}.get(sw, sw.name)


def field_lock(node: FieldNode) -> str | None:
    """``"REG.FIELD"`` of the field that locks this one (``swwel``: writes ignored while it is 1), or
    None. Other write-enable forms (``swwe``, a constant, a signal) are not supported."""
    if node.get_property("swwe") is not False:
        raise GenError(f"{node.get_path()}: swwe not supported by scripts/gen_regs.py (use swwel)")
    lock = node.get_property("swwel")
    if lock is False:
        return None
    if not isinstance(lock, FieldNode) or lock.width != 1 or lock.parent.parent != node.parent.parent:
        raise GenError(f"{node.get_path()}: swwel must name a 1-bit field of the same address map")
    return f"{lock.parent.inst_name}.{lock.inst_name}"


class RegCollector(RDLListener):
    """Collect every register (in address order) with its fields (in bit order)."""

    def __init__(self) -> None:
        self.regs: list[RegInfo] = []

    def enter_Reg(self, node: RegNode) -> None:
        if node.is_array:
            raise GenError(f"{node.get_path()}: register arrays are not supported by scripts/gen_regs.py")
        reg = RegInfo(node.inst_name, node.absolute_address, node.get_property("name"),
                      window_copy=bool(node.get_property("window_copy", default=False)))
        for f in node.fields():
            reset = f.get_property("reset")
            if reset is not None and not isinstance(reset, int):
                raise GenError(f"{f.get_path()}: reset must be a constant")
            reg.fields.append(FieldInfo(f.inst_name, f.lsb, f.width, reset, field_access(f),
                                        bool(f.get_property("is_signed", default=False)), field_lock(f)))
        reg.fields.sort(key=lambda fi: fi.lsb)
        self.regs.append(reg)


def collect(top: AddrmapNode) -> list[RegInfo]:
    listener = RegCollector()
    RDLWalker(unroll=False).walk(top, listener)
    regs = sorted(listener.regs, key=lambda r: r.addr)
    names: dict[str, str] = {}
    for reg in regs:
        consts = [f"{reg.name}_ADDR"] + [f"{reg.name}_{f.name}_{s}" for f in reg.fields
                                         for s in ("LSB", "WIDTH", "MASK", "RESET")]
        for c in consts:
            if c in names:
                raise GenError(f"constant {c} of {reg.name} collides with one of {names[c]}")
            names[c] = reg.name
    return regs


# ---------------------------------------------------------------- golden/regmap.py, golden/socmap.py
def regmap_doc(m: RegMap) -> str:
    """The generated module's first comment and docstring, naming its own RDL."""
    return (f"# generated by scripts/gen_regs.py from {m.rdl}, do not edit\n"
            f'"""{m.summary}\n\n'
            f"Generated by scripts/gen_regs.py from {m.rdl}, do not edit: change the RDL and run\n"
            "``make regs``.\n\n" + REGMAP_DOC_BODY)


REGMAP_DOC_BODY = '''\
Per register ``<REG>_ADDR`` (byte address); per field ``<REG>_<FIELD>_LSB``, ``_WIDTH``, ``_MASK``
(in the register) and ``_RESET`` (None for hardware-driven fields, which have no reset of their own).

``REGISTERS[name] = {"addr", "reset", "signed", "fields"}``: ``reset`` the register's reset value
(fields without reset count as 0), ``signed`` the names of the signed (two's complement) fields,
``fields[name] = (lsb, width, reset, access)`` with access one of ``ro`` (read-only), ``rw``,
``wo`` (write-only), ``w1c`` (read; write 1 to clear), ``w1s`` (write 1 to set), ``w1p`` (write 1:
one-clock pulse; reads 0), ``rc`` (clear on read).

``LOCKED_BY[(reg, field)] = (lock_reg, lock_field)``: the fields whose software writes are ignored
(and answered SLVERR) while the 1-bit lock field is 1 (SystemRDL ``swwel``).

``WINDOW_COPY`` (maps that have the RDL property ``window_copy``): the registers set between the window
boundary and the window interrupt and held until the next boundary, which hfi_soc's CPU reads from its copy.

``pack(reg, **fields)`` builds a register value (fields not named are 0); ``unpack(reg, value)``
splits one (signed fields sign-extended). Both raise ValueError on unknown registers or fields and on
values that do not fit (golden.regfields.RegisterFields, shared by every generated map).
"""
'''

REGMAP_HELPERS = '''
_FIELDS = RegisterFields(REGISTERS, REGWIDTH)
field_range = _FIELDS.field_range
pack = _FIELDS.pack
unpack = _FIELDS.unpack
'''


def _num(v: int | None) -> str:
    if v is None:
        return "None"
    return str(v) if v < 0x10000 else f"0x{v:08X}"


def render_regmap(m: RegMap, regs: list[RegInfo]) -> str:
    lines = [regmap_doc(m), "from __future__ import annotations", "", "from golden.regfields import RegisterFields",
             "", "REGWIDTH = 32", ""]
    for reg in regs:
        lines.append(f"# {reg.name} @ 0x{reg.addr:02X}: {reg.title}")
        lines.append(f"{reg.name}_ADDR = 0x{reg.addr:02X}")
        for f in reg.fields:
            p = f"{reg.name}_{f.name}"
            signed = ", signed" if f.signed else ""
            locked = f", locked by {f.lock}" if f.lock else ""
            lines.append(f"{p}_LSB = {f.lsb}  # {f.access}{signed}{locked}")
            lines.append(f"{p}_WIDTH = {f.width}")
            lines.append(f"{p}_MASK = 0x{f.mask:08X}")
            lines.append(f"{p}_RESET = {_num(f.reset)}")
        lines.append("")
    lines.append("")
    lines.append("REGISTERS = {")
    for reg in regs:
        reset = sum((f.reset or 0) << f.lsb for f in reg.fields)
        signed = "".join(f'"{f.name}", ' for f in reg.fields if f.signed)
        signed = f"({signed.rstrip(' ')})" if signed else "()"
        lines.append(f'    "{reg.name}": {{"addr": 0x{reg.addr:02X}, "reset": 0x{reset:08X}, '
                     f'"signed": {signed}, "fields": {{')
        for f in reg.fields:
            lines.append(f'        "{f.name}": ({f.lsb}, {f.width}, {_num(f.reset)}, "{f.access}"),')
        lines.append("    }},")
    lines.append("}")
    lines.append("")
    lines.append("LOCKED_BY = {")
    for reg in regs:
        for f in reg.fields:
            if f.lock:
                lines.append(f'    ("{reg.name}", "{f.name}"): ("{f.lock.split(".")[0]}", "{f.lock.split(".")[1]}"),')
    lines.append("}")
    copies = [reg.name for reg in regs if reg.window_copy]
    if copies:
        lines += ["", "WINDOW_COPY = ("] + [f'    "{name}",' for name in copies] + [")"]
    return "\n".join(lines) + "\n" + REGMAP_HELPERS


# ---------------------------------------------------------------- C header
OFFSETS_ANCHOR = "\n#ifdef __cplusplus\n}\n#endif\n"


def add_offset_macros(header: Path, regs: list[RegInfo], top: AddrmapNode) -> None:
    """Insert register byte-offset macros (and static checks) before the header's closing C++ guard."""
    text = header.read_text(encoding="utf-8")
    if text.count(OFFSETS_ANCHOR) != 1:
        raise GenError(f"{header}: PeakRDL-cheader output changed: cannot find where to add the offsets")
    name, top_size = top.inst_name, top.size
    prefix = name.upper()
    block = ["", "// Register byte offsets from the peripheral base address (added by scripts/gen_regs.py)"]
    block += [f"#define {prefix}__{reg.name}_offset 0x{reg.addr:02x}" for reg in regs]
    block += ["", "// Layout checks of the block struct against the offsets (C11 and later)",
              "#if defined(__STDC_VERSION__) && __STDC_VERSION__ >= 201112L", "#include <stddef.h>",
              f'_Static_assert(sizeof({name}_t) == 0x{top_size:x}, "{name}_t: size");']
    block += [f'_Static_assert(offsetof({name}_t, {reg.name}) == {prefix}__{reg.name}_offset, '
              f'"{name}_t: {reg.name} offset");' for reg in regs]
    block += ["#endif"]
    text = text.replace(OFFSETS_ANCHOR, "\n".join(block) + "\n" + OFFSETS_ANCHOR)
    header.write_text(text, encoding="utf-8")


# ---------------------------------------------------------------- rtl/regs/*_map.vh
VERILOG_ADDR_BITS = 8  # localparam [7:0] <P><REG>_ADDR


def render_verilog_map(m: RegMap, regs: list[RegInfo]) -> str:
    """Verilog localparams (P = ``m.verilog_prefix``): ``P<REG>_ADDR`` (byte address) and per field
    ``P<REG>_<FIELD>_LSB``, ``_WIDTH``, ``_RESET`` (0 for hardware-driven fields); include inside a
    module body."""
    p = m.verilog_prefix
    lines = [f"// generated by scripts/gen_regs.py from {m.rdl}, do not edit",
             f"// Register map constants of {m.block} ({m.markdown}); `include inside a module body.",
             f"// Per register {p}<REG>_ADDR (byte address); per field {p}<REG>_<FIELD>_LSB, _WIDTH,",
             "// _RESET (0 for hardware-driven fields) and, as a comment, the software access.", ""]
    for reg in regs:
        if reg.addr >= 1 << VERILOG_ADDR_BITS:
            raise GenError(f"{m.rdl}: {reg.name} @ 0x{reg.addr:X} does not fit the {VERILOG_ADDR_BITS}-bit "
                           f"Verilog addresses")
        lines.append(f"// {reg.name} @ 0x{reg.addr:02X}: {reg.title}")
        lines.append(f"localparam [{VERILOG_ADDR_BITS - 1}:0] {p}{reg.name}_ADDR = "
                     f"{VERILOG_ADDR_BITS}'h{reg.addr:02X};")
        for f in reg.fields:
            base = f"{p}{reg.name}_{f.name}"
            lines.append(f"localparam integer {base}_LSB = {f.lsb};  // {f.access}{', signed' if f.signed else ''}"
                         f"{f', locked by {f.lock}' if f.lock else ''}")
            lines.append(f"localparam integer {base}_WIDTH = {f.width};")
            lines.append(f"localparam [{f.width - 1}:0] {base}_RESET = {f.width}'h{(f.reset or 0):X};")
        lines.append("")
    locks = sorted({f.lock for r in regs for f in r.fields if f.lock})
    for lock in locks:
        name = lock.replace(".", "_")
        addrs = ", ".join(f"{p}{r.name}_ADDR" for r in regs if any(f.lock == lock for f in r.fields))
        lines += [f"// Registers whose fields {lock} locks (swwel): software writes ignored while it is 1.",
                  f"function {p.lower()}locked_by_{name.lower()}(input [{VERILOG_ADDR_BITS - 1}:0] a);",
                  "    case (a)",
                  f"        {addrs}: {p.lower()}locked_by_{name.lower()} = 1'b1;",
                  f"        default: {p.lower()}locked_by_{name.lower()} = 1'b0;",
                  "    endcase",
                  "endfunction", ""]
    copies = [reg for reg in regs if reg.window_copy]
    if copies:
        words = 1 << (VERILOG_ADDR_BITS - 2)
        mask = sum(1 << (reg.addr // 4) for reg in copies)
        lines += ["// Registers with the RDL property window_copy (bit i = the word at byte address 4*i): set between",
                  "// the window boundary and IRQ_STATUS.WINDOW, held until the next boundary; the CPU of hfi_soc",
                  "// reads them from its copy (rtl/hfi_win_copy.v). " + ", ".join(r.name for r in copies) + ".",
                  f"localparam [{words - 1}:0] {p}WINDOW_COPY_WORDS = {words}'h{mask:0{words // 4}X};", ""]
    return "\n".join(lines)


# ---------------------------------------------------------------- all outputs
def generate(out_root: Path, m: RegMap, rdl_path: Path, html: bool = True) -> None:
    """Compile ``rdl_path`` (the source of ``m``) and write the outputs of ``m`` under ``out_root``
    (same layout as the repository); ``html=False`` skips the HTML site (not committed, so not
    checked). A compile error: GenError after the compiler's messages."""
    from peakrdl_cheader.c_standards import CStandard
    from peakrdl_cheader.exporter import CHeaderExporter
    from peakrdl_markdown import MarkdownExporter

    try:
        top = compile_rdl(rdl_path, m.top)
    except RDLCompileError:
        # The compiler has already printed the message(s) with the source location.
        raise GenError(f"{_rel(rdl_path)}: compilation failed") from None
    regs = collect(top)
    for rel in (*m.files, m.html_dir + "/x"):
        (out_root / rel).parent.mkdir(parents=True, exist_ok=True)

    header = out_root / m.header
    # gnu99: the header then includes only <stdint.h> (gnu11/gnu17 add <assert.h> for static_assert,
    # which a freestanding rv32 toolchain without a C library lacks); anonymous unions are not needed.
    CHeaderExporter().export(top, str(header), std=CStandard.gnu99, reuse_typedefs=False,
                             generate_bitfields=True)
    add_offset_macros(header, regs, top)

    (out_root / m.python).write_text(render_regmap(m, regs), encoding="utf-8")

    MarkdownExporter().export(top, str(out_root / m.markdown), input_files=[m.rdl])

    if html:
        _export_html(m, top, rdl_path, out_root / m.html_dir)

    (out_root / m.verilog).write_text(render_verilog_map(m, regs), encoding="utf-8")


def _export_html(m: RegMap, top: AddrmapNode, rdl_path: Path, html: Path) -> None:
    from peakrdl_html import HTMLExporter

    if html.exists():
        shutil.rmtree(html)
    # build_ts (cache-busting URL suffix, time.time() by default) from the source: deterministic.
    build_ts = int(hashlib.sha256(rdl_path.read_bytes()).hexdigest()[:8], 16)
    HTMLExporter(generate_source_links=False, user_context={"build_ts": build_ts},
                 extra_doc_properties=["is_signed"]).export(
        top, str(html), title=m.html_title, footer=f"Generated from {m.rdl} by scripts/gen_regs.py")


def _source(repo_root: Path, m: RegMap, sources: Mapping[str, Path] | None) -> Path:
    """The RDL compiled for ``m``: ``sources[m.top]`` if given (tests), else its file in ``repo_root``."""
    return (sources or {}).get(m.top, repo_root / m.rdl)


def write(repo_root: Path = ROOT, maps: Sequence[RegMap] = MAPS,
          sources: Mapping[str, Path] | None = None) -> None:
    """Generate every map into a temporary directory, then install every output (nothing written if
    any map fails)."""
    with tempfile.TemporaryDirectory(prefix="gen_regs_") as tmp:
        tmp_root = Path(tmp)
        for m in maps:
            generate(tmp_root, m, _source(repo_root, m, sources))
        for m in maps:
            for rel in m.files:
                (repo_root / rel).parent.mkdir(parents=True, exist_ok=True)
                shutil.copyfile(tmp_root / rel, repo_root / rel)
            if (repo_root / m.html_dir).exists():
                shutil.rmtree(repo_root / m.html_dir)  # no stale pages of removed registers
            shutil.copytree(tmp_root / m.html_dir, repo_root / m.html_dir)


def check(repo_root: Path = ROOT, maps: Sequence[RegMap] = MAPS,
          sources: Mapping[str, Path] | None = None) -> list[str]:
    """Regenerate every map into a temporary directory; the outputs that differ from ``repo_root``
    ([] if none).

    Returns lines ``<path>: differs|missing`` (the HTML sites under out/ are not checked).
    """
    problems = []
    with tempfile.TemporaryDirectory(prefix="gen_regs_") as tmp:
        tmp_root = Path(tmp)
        for m in maps:
            generate(tmp_root, m, _source(repo_root, m, sources), html=False)
            for rel in m.files:
                if not (repo_root / rel).is_file():
                    problems.append(f"{rel}: missing")
                elif not filecmp.cmp(repo_root / rel, tmp_root / rel, shallow=False):
                    problems.append(f"{rel}: differs")
    return problems


def _rel(path: Path) -> str:
    try:
        return path.resolve().relative_to(ROOT).as_posix()
    except ValueError:
        return str(path)


def _gen_platform():
    """scripts/gen_platform.py as a module (scripts/ is not a package)."""
    import importlib.util

    spec = importlib.util.spec_from_file_location("gen_platform", ROOT / "scripts" / "gen_platform.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--check", action="store_true",
                    help="regenerate into a temporary directory and list the outputs that differ (exit 1)")
    ap.add_argument("--map", choices=list(MAPS_BY_TOP), help="only this register map (default: all)")
    ap.add_argument("--rdl", type=Path, help=argparse.SUPPRESS)  # tests: another source for --map
    args = ap.parse_args(argv)
    if args.rdl is not None and args.map is None:
        ap.error("--rdl needs --map")
    maps = (MAPS_BY_TOP[args.map],) if args.map else MAPS
    sources = {args.map: args.rdl} if args.rdl is not None else {}
    if args.map is None:
        status = _gen_platform().main(["--check"] if args.check else [])
        if status:
            return status
    try:
        if args.check:
            problems = check(maps=maps, sources=sources)
            if problems:
                print("gen_regs: generated register files are out of date (run `make regs`):", file=sys.stderr)
                for p in problems:
                    print(f"  {p}", file=sys.stderr)
                return 1
            print("gen_regs: generated register files are up to date")
            return 0
        write(ROOT, maps, sources)
    except GenError as e:
        print(f"gen_regs: {e}", file=sys.stderr)
        return 1
    for m in maps:
        for rel in (*m.files, m.html_dir + "/"):
            print(f"wrote {rel}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
