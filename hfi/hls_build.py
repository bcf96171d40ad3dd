"""Build and load the native (C-simulation) builds of the HLS-style C++ of ``hls/``.

* :func:`ap_types_dir`: the Xilinx ap_types headers (``ap_int.h``, ``ap_fixed.h``) that the pinned PyPI
  package ``hls4ml`` carries (found without importing hls4ml);
* :func:`build`: ``make -C hls <target>`` under a lock (parallel pytest workers share ``out/hls``);
* :func:`csim`: the cffi pair ``(ffi, lib)`` of ``libhfihls_csim.so``, whose C-ABI wrappers
  (``hls/csim/*.h``, one header per block) run the kernels over numpy arrays for the tests.
"""

from __future__ import annotations

import fcntl
import functools
import importlib.util
import subprocess
from pathlib import Path

import cffi

from hfi.backends import BackendError
from hfi.fw_c import cdef_text

ROOT = Path(__file__).resolve().parents[1]
OUT = ROOT / "out" / "hls"
CSIM_LIBRARY = OUT / "libhfihls_csim.so"
LOOP_LIBRARY = OUT / "libhfihls_loop.so"
LOOP_SOURCES = ("hls/backend/hls_loop.cpp", "sim/plant_loop.cpp")
"""C++ sources of the hls backend's loop besides the kernels (the plant loop is shared with the rtl backend)."""
LOOP_HEADERS = ("hls/backend/hls_loop.h", "hls/backend/hls_window.h", "sim/plant_loop.h", "sim/plant_records.h",
                "firmware/src/fw_trace.h", "firmware/src/control.h", "firmware/include/hfi_regs.h",
                "golden/plant/src/plant_api.h")
"""Headers the loop library depends on (hls/Makefile lists only the kernels' headers): a newer one rebuilds it."""


class HlsBuildError(BackendError):
    """The C++ build failed (the message holds the compiler's output) or its headers are missing."""


def ap_types_dir() -> Path:
    """The ap_types include directory inside the installed hls4ml package."""
    spec = importlib.util.find_spec("hls4ml")
    if spec is None or not spec.submodule_search_locations:
        raise HlsBuildError("the Python package hls4ml (which carries the Xilinx ap_types headers) is not "
                            "installed: run `make setup`")
    d = Path(list(spec.submodule_search_locations)[0]) / "templates" / "vivado" / "ap_types"
    if not (d / "ap_int.h").is_file():
        raise HlsBuildError(f"ap_int.h not found in {d}: the hls4ml package layout changed")
    return d


def build(target: str) -> Path:
    """``make -C hls <target>`` (``csim`` or ``loop``) and the library's path; make rebuilds only what
    changed. ``loop`` first builds the host firmware library (``make -C firmware host``)."""
    if target not in ("csim", "loop"):
        raise ValueError(f"unknown HLS build target {target!r} (csim or loop)")
    if target == "loop":
        from hfi import fw_c
        fw_c.build()
    OUT.mkdir(parents=True, exist_ok=True)
    cmd = ["make", "-s", "-C", str(ROOT / "hls"), target, f"OUT={OUT}", f"AP_TYPES={ap_types_dir()}"]
    if target == "loop":
        cmd.append("LOOP=" + " ".join(str(ROOT / p) for p in LOOP_SOURCES))
    with open(OUT / f".{target}.lock", "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        if target == "loop" and LOOP_LIBRARY.is_file() and max(
                (ROOT / p).stat().st_mtime for p in LOOP_HEADERS) > LOOP_LIBRARY.stat().st_mtime:
            LOOP_LIBRARY.unlink()
        proc = subprocess.run(cmd, capture_output=True, text=True)
    if proc.returncode != 0:
        raise HlsBuildError(f"`{' '.join(cmd)}` failed (exit {proc.returncode}):\n{proc.stdout}{proc.stderr}")
    return CSIM_LIBRARY if target == "csim" else LOOP_LIBRARY


@functools.lru_cache(maxsize=None)
def csim():
    """``(ffi, lib)`` of the C-simulation library (built if needed); its cdef is every ``hls/csim/*.h``."""
    path = build("csim")
    ffi = cffi.FFI()
    ffi.cdef(cdef_text(*sorted((ROOT / "hls" / "csim").glob("*.h"))))
    return ffi, ffi.dlopen(str(path))
