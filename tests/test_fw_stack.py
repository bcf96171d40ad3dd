"""The firmware's stack reservation (scripts/fw_stack.py, firmware/Makefile, link.ld; docs/soc.md, "The stack").

* the deepest-chain walk on small call graphs in GCC's ``.ci`` form (exact sums: the plug-in table's members for an
  indirect call, ``EXTERNAL_FRAME`` for a function without a node; recursion and dynamic frames refused);
* an indirect call outside the plug-in table refused, with its source line;
* crt0.S's trap frame read from its ``addi``;
* each image built (default, without the accelerators, commissioning) reserves what the script computes from its
  own objects, and its deepest chain runs through the interrupt (main alone is shallower).
"""

from __future__ import annotations

import importlib.util
import re
import sys
from pathlib import Path

import pytest

from hfi.rtl_backend import build_firmware

ROOT = Path(__file__).resolve().parents[1]


@pytest.fixture(scope="module")
def fw_stack():
    spec = importlib.util.spec_from_file_location("fw_stack", ROOT / "scripts" / "fw_stack.py")
    mod = importlib.util.module_from_spec(spec)
    sys.modules["fw_stack"] = mod
    spec.loader.exec_module(mod)
    return mod


def _ci(nodes: dict[str, int | None], edges: list[tuple[str, str, str]]) -> str:
    """A ``.ci`` text: nodes with a frame (None: a declaration without one) and edges with a location."""
    lines = ['graph: { title: "x.c"']
    for name, frame in nodes.items():
        size = "" if frame is None else f"\\n{frame} bytes (static)"
        lines.append(f'node: {{ title: "x.c:{name}" label: "{name}\\nx.c:1:1{size}" }}')
    for src, dst, where in edges:
        target = f"x.c:{dst}" if dst in nodes else dst          # a defined function's node, or a name without one
        lines.append(f'edge: {{ sourcename: "x.c:{src}" targetname: "{target}" label: "{where}" }}')
    return "\n".join(lines + ["}"])


def test_deepest_sums_the_frames_of_the_deepest_path(fw_stack):
    text = _ci({"main": 16, "a": 32, "b": 100, "c": 8, "step_x": 200, "step_y": 40},
               [("main", "a", "x.c:2:1"), ("main", "b", "x.c:3:1"), ("a", "c", "x.c:4:1"),
                ("a", "__indirect_call", "x.c:5:1"), ("c", "__divdi3", "x.c:6:1")])
    frames, calls, sites = fw_stack.parse_callgraph([text])
    want = {"main": 16, "a": 32, "b": 100, "c": 8, "step_x": 200, "step_y": 40}
    assert frames == {f"x.c:{k}": v for k, v in want.items()}
    assert sites == ["x.c:5:1"]
    # main > a > step_x (the table's deepest member) = 16 + 32 + 200; main > b = 116; main > a > c > __divdi3 = 120
    assert fw_stack.deepest(frames, calls, {"x.c:step_x", "x.c:step_y"}, "x.c:main") == (248, ["main", "a", "step_x"])
    # without the indirect call's members: main > a > c > external
    n, path = fw_stack.deepest(frames, calls, set(), "x.c:main")
    assert (n, path) == (16 + 32 + 8 + fw_stack.EXTERNAL_FRAME, ["main", "a", "c", "__divdi3"])


def test_recursion_and_dynamic_frames_are_refused(fw_stack):
    frames, calls, _ = fw_stack.parse_callgraph([_ci({"f": 8, "g": 8}, [("f", "g", "x.c:1:1"), ("g", "f", "x.c:2:1")])])
    with pytest.raises(ValueError, match="recursion"):
        fw_stack.deepest(frames, calls, set(), "x.c:f")
    # two static functions of one name in two files stay apart; a root must name one function
    two = [_ci({"h": 8}, []), _ci({"h": 24}, []).replace("x.c", "y.c")]
    frames2, _, _ = fw_stack.parse_callgraph(two)
    assert frames2 == {"x.c:h": 8, "y.c:h": 24}
    with pytest.raises(ValueError, match="2 functions called h"):
        fw_stack.title_of(frames2, "h")
    dynamic = 'node: { title: "h" label: "h\\nx.c:1:1\\n24 bytes (dynamic,bounded)" }'
    with pytest.raises(ValueError, match="dynamic"):
        fw_stack.parse_callgraph([dynamic])


def test_an_indirect_call_outside_the_plugin_table_is_refused(fw_stack, tmp_path):
    src = tmp_path / "x.c"
    src.write_text("void f(void)\n{\n    fw_methods[m].step(st);\n    hook(st);\n    ops->flux(st, &f);\n}\n")
    fw_stack.check_indirect_sites([f"{src}:3:5", f"{src}:5:5"])
    with pytest.raises(ValueError, match=r"x\.c:4:5: an indirect call outside .*hook\(st\);"):
        fw_stack.check_indirect_sites([f"{src}:3:5", f"{src}:4:5"])


def test_trap_frame_is_read_from_crt0(fw_stack):
    assert fw_stack.trap_frame("trap_entry:\n    addi sp, sp, -80\n    sw ra, 0(sp)\n") == 80
    with pytest.raises(ValueError):
        fw_stack.trap_frame("reset:\n    addi sp, sp, -16\n")


@pytest.mark.parametrize("acc, ident", [(True, False), (False, False), (True, True)])
def test_each_image_reserves_its_deepest_chain(fw_stack, acc, ident):
    """The link's ``hfi_stack_bytes`` is the script's need for the image's own objects (deepest chain + margin,
    16-aligned), the chain passes through the interrupt, and the link's ASSERT held (the image exists)."""
    image = build_firmware(acc=acc, ident=ident).parent
    n, chain = fw_stack.image_depth(image / "obj")
    assert fw_stack.reservation(image) == fw_stack.need(image / "obj") == -(-(n + fw_stack.MARGIN) // 16) * 16
    assert chain[:2] == ["main", "run"] and chain.count("<trap>") == 2 and "irq_handler" in chain
    text = (image / "hfi_fw.map").read_text()
    bss_end = int(re.search(r"0x([0-9a-f]+)\s+_bss_end = \.", text).group(1), 16)
    top = int(re.search(r"0x([0-9a-f]+)\s+_stack_top = ", text).group(1), 16)
    assert top - bss_end >= fw_stack.reservation(image)
