"""Closed-loop backend ``rtl``: the firmware on the VexRiscv of ``hfi_soc`` drives the plant through the RTL.

The Verilated SoC, the serial ADC, the clock and the C plant all run inside one native library
(``sim/soc_sim.cpp``, API ``sim/soc_sim.h``; built here on first use with Verilator). Python creates
the plant from the scenario exactly as the golden loop does (:class:`golden.plant.Plant`), writes the
run's configuration block into the firmware's RAM image, runs the co-simulation in chunks (progress on
stderr) and turns its records into the same :class:`golden.closedloop.ClosedLoopResult` as the golden
backend, so reports, plots and the identity test use one format:

* window results (SUM_ID, SUM_IQ, N_SAMPLES, INJ_PHASE, VDC, WIN_FAULT, WIN_ADC, CIC_QA/QB when the period
  square wave runs, VECTOR and TOP_I in the direct-vector mode, CTRL.DIRECT) and
  the speed reference from the firmware's register reads, the firmware's register writes (V_DQ, V_H,
  SINCOS, I_REF, CTRL), compares, LATE_COUNT, the ADC mode in use, ENV_A/ENV_B and GAMMA, GAMMA_D, WSUM
  (which the firmware reads only when it uses them, so the harness samples them) at each window interrupt;
* estimator and controller state from the firmware's trace records (:data:`hfi.soc_platform.TRACE`:
  every trace word named like a column of ``WINDOW_FIELDS`` fills that column);
* gate edges, ADC samples and the plant state at each window end from the harness (sim/plant_loop.h).

``soc`` of the result adds what only the hardware has: firmware cycles per control step (the core's
own ``rdcycle`` count from the handler's entry to the COMMIT write), clocks from the interrupt to the
COMMIT write, late commits, simulated clocks and clocks per wall second, and the UART log.
"""

from __future__ import annotations

import dataclasses
import fcntl
import functools
import hashlib
import importlib
import os
import shutil
import subprocess
import sys
import time
from pathlib import Path

import cffi
import numpy as np

from golden import regmap as rm
from golden import socmap
from golden.build_options import OPTIONS, left_out
from golden.closedloop import OUTPUT_FIELDS, WINDOW_FIELDS, ClosedLoopResult, speed_references, truth_columns
from golden.control_config import HardwareConfig, firmware_params, hardware_config, scales
from golden.fixed import wrap
from golden.firmware.supervisor import MODE_RUN, FirmwareParams
from golden.plant import Plant, binding
from golden.scenario import Scenario, load_scenario
from hfi import soc_platform
from hfi.backends import BackendError
from hfi.fw_c import cdef_text, ident_from_c, ident_to_c, params_to_c

ROOT = Path(__file__).resolve().parents[1]
SIM_DIR = ROOT / "sim"
OUT_SIM = ROOT / "out" / "sim"
FW_OUT = ROOT / "out" / "firmware"
FW_HEADERS = ("firmware/src/control.h", "firmware/src/fw_config.h")
SIM_SOURCES = ("soc_sim.cpp", "plant_loop.cpp")
"""C++ sources of the co-simulation library in sim/ (the harness and the plant loop it shares with hls)."""
SIM_HEADERS = ("soc_sim.h", "soc_sim.vlt", "plant_loop.h", "plant_records.h")
PGO_TRAIN = ("scenarios/fullload_start.toml", 0.02)
"""The training run of the profile-guided build (build_sim): the default scenario's start, 2 M clocks (the 002
firmware's start-up on the soft core and the DSP path in every clock). Measured 2026-11-29: 2.37 -> 2.85 M clocks
per second (scripts/bench_rtl.py; docs/soc.md)."""

EVERY_BLOCK: dict[str, int] = {name: 1 for name in OPTIONS}
"""The build options of the build with every optional block in (build_sim, RtlClosedLoop.run)."""

FW_BUDGET = 0.25
"""Performance target of the firmware at PWM periods of at least FW_BUDGET_LONG_PERIOD: its control step
in at most this share of the period (issue 15: the 002 system at 5 kHz), counted in CPU clocks (the tick
clock / soc_platform.CPU_CLOCK_DIVIDER)."""
FW_BUDGET_SHORT = 0.70
"""The share at shorter periods (the 10 kHz methods: the whole step with 30 % of the period to spare,
issue 18; docs/soc.md, "Firmware budget")."""
FW_BUDGET_LONG_PERIOD = 200e-6
"""[s] The period from which FW_BUDGET applies."""


def fw_budget_share(period_s: float) -> float:
    """The share of a PWM period of ``period_s`` seconds the firmware's control step may take."""
    return FW_BUDGET if period_s >= FW_BUDGET_LONG_PERIOD * (1 - 1e-9) else FW_BUDGET_SHORT

CHUNK_CYCLES = 2_000_000
"""Clocks per call into the co-simulation (progress granularity, ~0.5 s wall)."""


class RtlBackendError(BackendError):
    """A build step failed, or the co-simulation stopped (the message says why)."""


# ---------------------------------------------------------------- building
def _run(cmd: list[str], what: str, cwd: Path = ROOT) -> None:
    proc = subprocess.run(cmd, cwd=cwd, capture_output=True, text=True)
    if proc.returncode != 0:
        raise RtlBackendError(f"{what} failed (exit {proc.returncode}): {' '.join(cmd)}\n"
                              f"{proc.stdout[-4000:]}{proc.stderr[-4000:]}")


def _package_file(package: str, name: str) -> Path:
    """A Verilog file of an installed pythondata package (not part of this repository)."""
    try:
        pd = importlib.import_module(package)
    except ImportError as e:
        raise RtlBackendError(f"{package.replace('_', '-')} is not installed: run `make setup`") from e
    path = Path(pd.data_location) / name
    if not path.is_file():
        raise RtlBackendError(f"{path} is missing from the {package.replace('_', '-')} package")
    return path


_warned_fallback = False


def cpu_source(icache_bytes: int = soc_platform.CPU_ICACHE_BYTES,
               prediction: str = soc_platform.CPU_PREDICTION) -> Path:
    """The soft core's Verilog: VexRiscv generated with ``icache_bytes`` of instruction cache, the branch
    predictor ``prediction`` and the CFU port (hfi/vexriscv_gen.py; ``make setup`` generates the default
    one). Without it (a machine where the generator cannot run: no JDK or Maven Central) the package's
    ``VexRiscv_FullCfu.v`` (LiteX's ``full+cfu``: the same ports, a 4 KiB instruction cache): every value is
    the same, the firmware's cycles are not those of docs/soc.md; said once on stderr, and ``cpu_core`` of the
    run's ``soc`` metrics names the core."""
    global _warned_fallback
    from hfi import vexriscv_gen

    path = vexriscv_gen.core_path(icache_bytes, prediction)
    if path.is_file():
        return path
    if not _warned_fallback:
        print(f"hfi: {path} is missing (`make setup` generates it; it needs a JDK and Maven Central): the SoC "
              f"runs the package's {vexriscv_gen.CFU_VARIANT} with a 4 KiB instruction cache instead",
              file=sys.stderr)
        _warned_fallback = True
    return _package_file(soc_platform.CPU_PACKAGE, vexriscv_gen.CFU_VARIANT)


def picorv32_source() -> Path:
    """``picorv32.v`` of the pythondata-cpu-picorv32 package: hfi_soc uses its ``picorv32_axi_adapter``
    (native bus to AXI4-Lite) in front of hfi_dsp."""
    return _package_file("pythondata_cpu_picorv32", "picorv32.v")


def soc_sources(icache_bytes: int = soc_platform.CPU_ICACHE_BYTES,
                prediction: str = soc_platform.CPU_PREDICTION) -> list[Path]:
    """Verilog sources of hfi_soc: the project's RTL, the core (with ``icache_bytes`` of instruction cache and
    the branch predictor ``prediction``), and the AXI4-Lite adapter's file."""
    return sorted((ROOT / "rtl").glob("*.v")) + [cpu_source(icache_bytes, prediction), picorv32_source()]


def digest(paths: list[Path], extra: str) -> str:
    """sha256 of ``extra`` and of each file (its path and its bytes): the key of a build or a cached result."""
    h = hashlib.sha256(extra.encode())
    for p in paths:
        h.update(str(p).encode())
        h.update(p.read_bytes())
    return h.hexdigest()


def build_firmware(acc: bool = True, ident: bool = False, cfu: bool = True) -> Path:
    """``make -C firmware``: the RAM image ``out/firmware/hfi_fw.bin`` (and .elf, .hex, .lst); ``acc=False``:
    the build for a SoC without the accelerators (``ACC=0``, into ``out/firmware/noacc``); ``cfu=False``: for a
    SoC without the fixed-point unit (``CFU=0``: fw_fx.h's plain C, into ``.../nocfu``); ``ident``: the
    commissioning image (``IDENT=1``, into ``.../ident``: the identification executor, for a SoC with
    ``soc_platform.IDENT_RAM_BYTES`` of RAM). A file lock serialises concurrent builds (two ``make`` in one output
    directory would write the same objects at once)."""
    FW_OUT.mkdir(parents=True, exist_ok=True)
    with open(FW_OUT / ".lock", "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        _run(["make", "-C", str(ROOT / "firmware"), f"PYTHON={sys.executable}", f"ACC={int(acc)}",
              f"CFU={int(cfu)}", f"IDENT={int(ident)}"], "firmware build")
    return ((FW_OUT if acc else FW_OUT / "noacc") / ("" if cfu else "nocfu") / ("ident" if ident else "")
            / "hfi_fw.elf")


@functools.lru_cache(maxsize=1)
def _pgo_system() -> dict[str, int]:
    """The build options of the profile-guided build: those :data:`PGO_TRAIN`'s scenario leaves out (its file
    read once per process)."""
    sc = load_scenario(ROOT / PGO_TRAIN[0])
    return left_out(sc.estimator.low, sc.estimator.high)


def build_sim(fst: bool = False, profile: bool = False, options: dict[str, int] | None = None,
              ram_bytes: int | None = None, acc: bool = True, cfu: bool = True) -> Path:
    """Verilate hfi_soc with the harness into ``out/sim/<variant>/libhfisoc.so`` (rebuilt when a source
    changed; a file lock serialises concurrent builds). ``fst``: the variant with FST waveforms;
    ``profile``: the variant that records the firmware profile (``SOC_PROF_*`` of sim/soc_sim.h);
    ``options``: build options (golden.build_options, docs/rtl.md), {name: 0 or 1}; those at 0 make a variant of its
    own (the default 1 names none: ``{}`` and :data:`EVERY_BLOCK` are the same build, every block in);
    ``ram_bytes``: a RAM other than ``soc_platform.RAM_BYTES`` (the commissioning image's), likewise; ``acc=False``:
    the SoC without the accelerators (``hfi_soc`` parameter ``ACC = 0``), likewise; ``cfu=False``: without the
    fixed-point unit (``CFU = 0``; the Tang Nano 20K's SoC has neither), likewise. The default scenario's system is
    built profile-guided; with ``HFI_SIM_PGO=0`` in the environment (``make test``) a plain build beside it
    (``<variant>_plain``) unless the profile-guided one is up to date."""
    from golden.plant.binding import LIBRARY as PLANT_LIB

    if fst and profile:
        raise RtlBackendError("the FST waveform and the firmware profile are separate builds: ask for one")
    options = dict(options or {})
    for name, value in options.items():
        if name not in OPTIONS or value not in (0, 1):
            raise RtlBackendError(f"build option {name}={value!r}: expected one of {', '.join(OPTIONS)} = 0 or 1")
    # hfi_soc's parameters other than their defaults: the build options left out and the RAM size
    params = {name: 0 for name, value in options.items() if value == 0}
    if not acc:
        params["ACC"] = 0
    if not cfu:
        params["CFU"] = 0
    if ram_bytes is not None and ram_bytes != soc_platform.RAM_BYTES:
        if profile:
            raise RtlBackendError("the firmware profile counts the words of the default RAM: no other RAM size")
        params["RAM_BYTES"] = ram_bytes
    variant = ("fst" if fst else "prof" if profile else "fast") + "".join(f"_{k}{v}" for k, v in sorted(params.items()))
    srcs = soc_sources() + [SIM_DIR / n for n in SIM_SOURCES + SIM_HEADERS] + [
        ROOT / "golden/plant/src/plant_api.h"] + sorted((ROOT / "firmware/include").glob("*.h"))
    srcs += sorted((ROOT / "rtl").rglob("*.vh"))
    verilator = shutil.which("verilator")
    if verilator is None:
        raise RtlBackendError("verilator is not on PATH: run `make setup` and `source scripts/env.sh`")
    # profile-guided for the system of the default scenario (PGO_TRAIN's: the build `make run` and `make bench`
    # simulate; `make test` a plain one, below); the other systems' builds, the waveform and profile variants, the
    # commissioning RAM and the SoC without the accelerators are compiled once (a profile of their own would need a
    # training run of their own)
    pgo = not (fst or profile) and params == _pgo_system()
    # hidden visibility and no semantic interposition: calls inside the library bind locally, without the PLT (its
    # interface is soc_sim.h's, pushed default there): 8-20 % more clocks per second (docs/soc.md, "Measured")
    cflags = (f"-fPIC -fno-semantic-interposition -fvisibility=hidden -fvisibility-inlines-hidden -O3 -I{SIM_DIR} "
              f"-I{ROOT / 'golden/plant/src'} -I{ROOT / 'firmware/include'}"
              + (" -DHFI_FST" if fst else "") + (" -DHFI_PROFILE" if profile else ""))
    ldflags = f"-shared -L{PLANT_LIB.parent} -lhfiplant -Wl,-rpath,{PLANT_LIB.parent}"
    key = digest(srcs, f"{variant} {verilator} pgo={pgo} {cflags} {ldflags}")
    if pgo and os.environ.get("HFI_SIM_PGO") == "0" and not _up_to_date(OUT_SIM / variant, key):
        # `make test` (HFI_SIM_PGO=0): the training run and the second compile cost the suite about 90 s of CPU and
        # its runs win about 10; a profile-guided build already up to date serves, else a plain one beside it
        pgo, variant = False, variant + "_plain"
        key = digest(srcs, f"{variant} {verilator} pgo={pgo} {cflags} {ldflags}")
    build = OUT_SIM / variant
    lib = build / "libhfisoc.so"
    OUT_SIM.mkdir(parents=True, exist_ok=True)
    with open(OUT_SIM / f".{variant}.lock", "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        if _up_to_date(build, key):
            return lib
        if build.exists():
            shutil.rmtree(build)
        build.mkdir(parents=True)

        def verilate(extra_cflags: str = "", extra_ldflags: str = "") -> None:
            cmd = [verilator, "--cc", "--exe", "--build", "-j", "2", "-O3", "--x-assign", "fast",
                   "--x-initial", "fast", "--noassert", "-Wno-fatal", "-Wno-lint", "-Wno-style",
                   "--top-module", "hfi_soc", "--flatten", f"-I{ROOT / 'rtl'}", "--Mdir", str(build / "obj"),
                   "-CFLAGS", cflags + extra_cflags, "-LDFLAGS", ldflags + extra_ldflags, "-o", str(lib)]
            if fst:
                cmd.append("--trace-fst")
            cmd += [f"-G{k}={v}" for k, v in sorted(params.items())]
            cmd += [str(SIM_DIR / "soc_sim.vlt")] + [str(p) for p in soc_sources()]
            cmd += [str(SIM_DIR / n) for n in SIM_SOURCES]
            _run(cmd, "Verilator build of hfi_soc")

        if pgo:
            # GCC's profile-guided optimisation (Verilator's manual, "Compiler Profile-Guided Optimization"): an
            # instrumented build runs PGO_TRAIN, then the objects are compiled again with its profile; integer code
            # and the harness's float code compute the same values either way (no fast-math, baseline x86-64)
            prof = build / "pgo"
            verilate(f" -fprofile-generate={prof}", f" -fprofile-generate={prof}")
            train = lib.rename(build / "train.so")
            # in a process of its own: the instrumented library writes its profile when the process exits
            _run([sys.executable, "-c", f"from hfi.rtl_backend import pgo_train; pgo_train({str(train)!r})"],
                 "training run of the profile-guided build")
            for p in (build / "obj").iterdir():
                if p.suffix in (".o", ".a", ".gch"):
                    p.unlink()
            verilate(f" -fprofile-use={prof} -fprofile-correction -Wno-missing-profile")
            train.unlink()
        else:
            verilate()
        (build / "digest").write_text(key)
    return lib


def _up_to_date(build: Path, key: str) -> bool:
    """Whether the co-simulation library in ``build`` was built for ``key`` (build_sim)."""
    stamp = build / "digest"
    return (build / "libhfisoc.so").is_file() and stamp.is_file() and stamp.read_text() == key


def pgo_train(sim_lib: str) -> None:
    """The training run of the profile-guided build (build_sim): :data:`PGO_TRAIN` on the library ``sim_lib``."""
    sc = load_scenario(ROOT / PGO_TRAIN[0])
    RtlClosedLoop(dataclasses.replace(sc, duration=PGO_TRAIN[1])).run(progress=False, workdir=Path(sim_lib).parent,
                                                                       sim_lib=Path(sim_lib))


# ---------------------------------------------------------------- the run's RAM image
_cfg_ffi = cffi.FFI()
_cfg_ffi.cdef(cdef_text(*(ROOT / h for h in FW_HEADERS)))
_cfg_consts = _cfg_ffi.dlopen(None)      # the header's enum constants (no library functions used)


def config_block(sc: Scenario, hw: HardwareConfig, fp: FirmwareParams) -> bytes:
    """``struct fw_config`` of the scenario (firmware/src/fw_config.h) with its firmware parameters ``fp``
    (golden.control_config.firmware_params), as the RV32 little-endian bytes."""
    cfg = _cfg_ffi.new("struct fw_config *")
    h = cfg.hw
    h.magic = _cfg_consts.FW_CONFIG_MAGIC
    h.version = _cfg_consts.FW_CONFIG_VERSION
    h.pwm_half, h.dead_ticks, h.os_ticks, h.blank_ticks = hw.pwm_half, hw.dead_ticks, hw.os_ticks, hw.blank_ticks
    h.cw_angle_step, h.dtc_gain, h.hf_amp, h.recip_h = hw.cw_angle_step, hw.dtc_gain, hw.hf_amp, hw.recip_h
    h.adc_offset = rm.pack("ADC_OFFSET", A=hw.adc_offset[0], B=hw.adc_offset[1])
    h.adc_gain = rm.pack("ADC_GAIN", A=hw.adc_gain[0], B=hw.adc_gain[1])
    h.oc_limit = rm.pack("OC_LIMIT", VALUE=hw.oc_limit)
    h.wdt_periods = rm.WDT_PERIODS_VALUE_RESET
    h.adc_mode, h.inj_en, h.inj_rot, h.inj_step = hw.adc_mode, 1, hw.inj_rot, hw.inj_step
    h.inj_per, h.cic_m, h.direct = hw.inj_per, hw.cic_m, hw.direct
    p = params_to_c(_cfg_ffi, fp)   # without the identification program (ram_image puts it at fw_ident)
    cfg.fw = p[0]
    return bytes(_cfg_ffi.buffer(cfg))


def _symbols(elf: Path) -> dict[str, tuple[int, int]]:
    """The ELF's data and code symbols that have a size: name -> (address, size in bytes)."""
    nm = shutil.which("riscv64-unknown-elf-nm") or "riscv64-unknown-elf-nm"
    proc = subprocess.run([nm, "-S", str(elf)], capture_output=True, text=True)
    out = {}
    for line in proc.stdout.splitlines():
        parts = line.split()
        if len(parts) == 4:
            out[parts[3]] = (int(parts[0], 16), int(parts[1], 16))
    return out


def _placed(elf: Path, name: str, size: int) -> int:
    """The address of the RAM block ``name``, whose size in the image must be ``size`` (the host's struct)."""
    found = _symbols(elf).get(name)
    if found is None:
        raise RtlBackendError(f"symbol {name} not found in {elf}")
    if found[1] != size:
        raise RtlBackendError(f"{name} in {elf} has {found[1]} bytes, the host's struct {size}: rebuild the firmware")
    return found[0]


def ram_image(sc: Scenario, hw: HardwareConfig, elf: Path, out: Path, ram_bytes: int = soc_platform.RAM_BYTES,
              fp: FirmwareParams | None = None) -> Path:
    """Firmware image with the scenario's configuration block at ``fw_config`` and, for ``control.mode =
    "commission"`` (the commissioning image, ``elf`` built with ``ident``), the identification program at
    ``fw_ident``, as $readmemh text. ``fp``: the scenario's firmware parameters if the caller has them (for the
    003 drive with its flux maps they take about a second to compute)."""
    image = bytearray((elf.with_suffix(".bin")).read_bytes())
    fp = firmware_params(sc) if fp is None else fp
    blocks = [("fw_config", config_block(sc, hw, fp))]
    program = fp.ident
    if program is not None:
        if "fw_ident" not in _symbols(elf):
            raise RtlBackendError(f"scenario {sc.name}: control.mode = \"commission\" needs the commissioning image "
                                  "(build_firmware(ident=True)); this one has no identification executor")
        blocks.append(("fw_ident", bytes(_cfg_ffi.buffer(ident_to_c(_cfg_ffi, program)))))
    for name, block in blocks:
        at = _placed(elf, name, len(block))
        if at + len(block) > len(image):
            raise RtlBackendError(f"{name} at 0x{at:x} lies outside the image ({len(image)} bytes)")
        image[at:at + len(block)] = block
    image += bytes(-len(image) % 4)
    if len(image) > ram_bytes:
        raise RtlBackendError(f"firmware image {len(image)} bytes > RAM {ram_bytes}")
    words = np.frombuffer(bytes(image), dtype="<u4")
    out.write_text("".join(f"{w:08x}\n" for w in words), encoding="ascii")
    return out


def _read_ident(lib, sim, elf: Path, program):
    """The identification executor's state at the end of a run: ``fw_ident`` read from the SoC RAM, as a golden
    :class:`~golden.firmware.ident.Ident` (hfi.fw_c.ident_from_c, the hls backend's converter)."""
    size = _cfg_ffi.sizeof("struct fw_ident")
    at = _placed(elf, "fw_ident", size)
    words = _sim_ffi.new("unsigned[]", size // 4)
    if lib.soc_sim_read_ram(sim, at, size // 4, words) != 0:
        raise RtlBackendError(f"fw_ident at 0x{at:x} lies outside the SoC RAM")
    block = _cfg_ffi.new("struct fw_ident *")
    _cfg_ffi.memmove(block, _sim_ffi.buffer(words), size)
    return ident_from_c(block, program)


# ---------------------------------------------------------------- the co-simulation
_sim_ffi = cffi.FFI()
_sim_ffi.include(binding.ffi)
_sim_ffi.cdef(cdef_text(SIM_DIR / "plant_records.h", SIM_DIR / "soc_sim.h",
                        drop=("struct plant;", "struct plant_state;")))
_KINDS = {"edges": (0, "struct gate_edge"), "samples": (1, "struct adc_sample"), "truth": (2, "struct plant_state"),
          "trace": (3, "uint32_t"), "writes": (4, "struct soc_bus"), "reads": (5, "struct soc_bus"),
          "irqs": (6, "struct soc_irq"), "uart": (7, "uint8_t"), "prof_cycles": (8, "uint64_t"),
          "prof_fetch": (9, "uint64_t"), "prof_dfetch": (10, "uint64_t")}


def _records(lib, sim, kind: str, dtype) -> np.ndarray:
    code, ctype = _KINDS[kind]
    n = lib.soc_sim_count(sim, code)
    buf = _sim_ffi.new(f"{ctype}[]", max(n, 1))
    if lib.soc_sim_copy(sim, code, 0, n, buf) != 0:
        raise RtlBackendError(f"soc_sim_copy({kind}) failed")
    raw = bytes(_sim_ffi.buffer(buf, n * _sim_ffi.sizeof(ctype)))
    return np.frombuffer(raw, dtype=dtype).copy() if n else np.zeros(0, dtype=dtype)


_EDGE = np.dtype([("tick", "<i8"), ("mask", "<i8")])
_SAMPLE = np.dtype([("tick", "<i8"), ("a", "<i4"), ("b", "<i4"), ("vdc", "<i4"), ("pad", "<i4")])
_BUS = np.dtype([("tick", "<i8"), ("addr", "<u4"), ("data", "<u4")])
_IRQ = np.dtype([("tick", "<i8"), ("commit", "<i8"), ("cmp", "<i4", (6,)), ("late", "<i4"), ("adc_mode", "<i4"),
                 ("env", "<i4", (2,)), ("dem", "<i4", (3,))], align=True)   # padded to 8 bytes as struct soc_irq


def _s16(v: np.ndarray) -> np.ndarray:
    return wrap(v.astype(np.int64) & 0xFFFF, 16)


def _per_window(bus: np.ndarray, addr: int, n: int, what: str) -> np.ndarray:
    sel = bus["data"][bus["addr"] == addr].astype(np.int64)
    if len(sel) < n:
        raise RtlBackendError(f"{what}: {len(sel)} accesses for {n} windows")
    return sel[:n]


class RtlClosedLoop:
    """The ``rtl`` backend of one scenario (``[control]`` mode closed or fixed_angle, OS or OS_BLANK)."""

    def __init__(self, sc: Scenario):
        if sc.control is None:
            raise ValueError(f"scenario {sc.name} has no [control] settings")
        if sc.control.switch_to_ds_at is not None:
            raise ValueError(f"scenario {sc.name}: control.switch_to_ds_at (a host-side ADC mode switch "
                             "during the run) is supported by the golden backend only")
        self.sc = sc
        self.hw = hardware_config(sc)
        self.scales = scales(sc)
        self.profile: dict[str, np.ndarray] | None = None
        if self.hw.adc_bits != soc_platform.ADC_BITS:
            raise RtlBackendError(f"scenario {sc.name}: sensors.adc_bits = {self.hw.adc_bits}, but the SoC's ADC "
                                  f"has {soc_platform.ADC_BITS} bits (hfi_soc ADC_BITS, hfi/soc_platform.py): "
                                  "the rtl backend would read other codes than the plant converts")
        if int(sc.pwm.tick_hz) != 100_000_000:
            raise ValueError(f"scenario {sc.name}: the rtl backend runs at the SoC clock, pwm.tick_hz must "
                             f"be 100 MHz (got {sc.pwm.tick_hz})")

    def run(self, progress: bool = True, fst: str | None = None, fst_window: tuple[float, float] | None = None,
            workdir: Path | None = None, profile: bool = False,
            options: dict[str, int] | None = None, sim_lib: Path | None = None, acc: bool = True,
            cfu: bool = True) -> ClosedLoopResult:
        """Run the co-simulation. ``fst``: FST waveform file; ``fst_window``: its time span [s]
        (default: the first 2 ms). ``profile``: record the firmware profile into ``self.profile``
        (``cycles`` and ``fetch``: one count per RAM word, sim/soc_sim.h; scripts/fw_profile.py).
        ``options``: the FPGA build's options (build_sim); by default the scenario's system, every block its
        estimator methods do not need left out (golden.build_options.left_out, as ``hfi compare`` synthesizes it;
        :data:`EVERY_BLOCK` keeps them all; the firmware refuses to start when the scenario's methods need a block the
        build lacks: RtlBackendError with the UART log). ``sim_lib``: a
        co-simulation library built already (build_sim's training run of the profile-guided build). ``acc=False``:
        the SoC without the accelerators and its firmware image (``make -C firmware ACC=0``); ``cfu=False``: without the
        fixed-point unit, likewise (``CFU=0``: the Tang Nano 20K's SoC has neither)."""
        sc, hw = self.sc, self.hw
        H = hw.pwm_half
        tick_hz = sc.pwm.tick_hz
        speed_ref = speed_references(sc, hw, self.scales)
        n_win = len(speed_ref)

        # control.mode = "commission": the commissioning image on a SoC with its larger RAM (soc_platform)
        fp = firmware_params(sc)
        program = fp.ident
        ram_bytes = soc_platform.RAM_BYTES if program is None else soc_platform.IDENT_RAM_BYTES
        elf = build_firmware(acc=acc, ident=program is not None, cfu=cfu)
        if options is None:
            options = left_out(sc.estimator.low, sc.estimator.high)
        lib_path = sim_lib or build_sim(fst=fst is not None, profile=profile, options=options, ram_bytes=ram_bytes,
                                        acc=acc, cfu=cfu)
        lib = _sim_ffi.dlopen(str(lib_path))
        workdir = Path(workdir or OUT_SIM / "runs")
        workdir.mkdir(parents=True, exist_ok=True)
        # one image per process: two runs of the same scenario name at once (pytest -n, a sweep) would
        # otherwise write one file while the other's simulation reads it
        ram = ram_image(sc, hw, elf, workdir / f"{sc.name}_{os.getpid()}_ram.hex", ram_bytes, fp)

        plant = Plant(sc.plant)
        keep = []
        setup = _sim_ffi.new("struct soc_sim_setup *")
        keep.append(_sim_ffi.new("char[]", str(ram).encode()))
        setup.ram_hex = keep[-1]
        if fst is not None:
            keep.append(_sim_ffi.new("char[]", str(fst).encode()))
            setup.fst_path = keep[-1]
            t0, t1 = fst_window or (0.0, 0.002)
            t1 = min(t1, sc.duration)                       # an end beyond the run (inf included): the run's end
            setup.fst_from_tick, setup.fst_to_tick = round(t0 * tick_hz), round(t1 * tick_hz)
        else:
            setup.fst_path = _sim_ffi.NULL
        setup.half = H
        setup.n_windows = n_win
        refs = _sim_ffi.new("int32_t[]", speed_ref.tolist())
        setup.speed_ref = refs
        setup.adc_bits = hw.adc_bits
        setup.uart_div = socmap.UART_DIV_VALUE_RESET
        setup.cpu_div = soc_platform.CPU_CLOCK_DIVIDER
        setup.trace_words = len(soc_platform.TRACE)
        err = _sim_ffi.new("char[]", 512)
        sim = lib.soc_sim_create(setup, _sim_ffi.cast("struct plant *", plant._p), err, 512)
        if sim == _sim_ffi.NULL:
            raise RtlBackendError(_sim_ffi.string(err).decode())
        try:
            t_start = time.perf_counter()
            bar = None
            if progress:
                from tqdm import tqdm
                bar = tqdm(total=n_win, desc=f"{sc.name} [rtl]", unit="win", mininterval=0.5)
            while True:
                st = lib.soc_sim_run(sim, CHUNK_CYCLES)
                if bar is not None:
                    done = min(n_win, lib.soc_sim_count(sim, 3) // len(soc_platform.TRACE))
                    bar.update(done - bar.n)
                if st == 1:
                    break
                if st < 0:
                    uart = bytes(_records(lib, sim, "uart", np.uint8)).decode(errors="replace")
                    raise RtlBackendError(f"co-simulation stopped: {_sim_ffi.string(lib.soc_sim_error(sim)).decode()}"
                                          f"\nUART log:\n{uart}")
            if bar is not None:
                bar.close()
            wall = time.perf_counter() - t_start
            cycles = lib.soc_sim_cycles(sim)
            rec = {k: _records(lib, sim, k, dt) for k, dt in (
                ("edges", _EDGE), ("samples", _SAMPLE), ("truth", binding.STATE_DTYPE), ("trace", "<u4"),
                ("writes", _BUS), ("reads", _BUS), ("irqs", _IRQ), ("uart", np.uint8))}
            if profile:
                self.profile = {"cycles": _records(lib, sim, "prof_cycles", "<u8"),
                                "fetch": _records(lib, sim, "prof_fetch", "<u8"),
                                "dfetch": _records(lib, sim, "prof_dfetch", "<u8")}
            ident = None if program is None else _read_ident(lib, sim, elf, program)
        finally:
            lib.soc_sim_free(sim)
        return self._result(rec, n_win, wall, cycles, options, ident)

    def _result(self, rec: dict, n_win: int, wall: float, cycles: int, options: dict[str, int],
                ident=None) -> ClosedLoopResult:
        hw, sc = self.hw, self.sc
        H, P = hw.pwm_half, 2 * hw.pwm_half
        end = n_win * P + H // 2
        tr = rec["trace"].reshape(-1, len(soc_platform.TRACE))[:n_win].astype(np.int64)
        t = {word.name: wrap(tr[:, i], 32) if word.signed else tr[:, i]
             for i, word in enumerate(soc_platform.TRACE)}
        if not np.array_equal(t["window"], np.arange(n_win)):
            raise RtlBackendError("firmware trace records are not one per window in order")
        # window -1's interrupt reads the registers too (a step on a copy of the state, firmware/src/main.c): its
        # reads come before window 0's end
        reads, writes = rec["reads"][rec["reads"]["tick"] >= P + H // 2], rec["writes"]
        w = {name: np.zeros(n_win, dtype=np.int64) for name in WINDOW_FIELDS}
        w["tick"] = (np.arange(n_win, dtype=np.int64) + 1) * P + H // 2
        results = [("sum_id", "SUM_ID", True), ("sum_iq", "SUM_IQ", True), ("n_samples", "N_SAMPLES", False),
                   ("speed_ref", "SPEED_REF", True), ("inj_phase", "INJ_PHASE", False), ("vdc", "VDC", False),
                   ("win_fault", "WIN_FAULT", False), ("win_adc", "WIN_ADC", False)]
        if hw.inj_per:      # the firmware reads the CIC outputs only with the period square wave (0 else)
            results += [("cic_qa", "CIC_QA", True), ("cic_qb", "CIC_QB", True)]
        for col, reg, signed in results:
            v = _per_window(reads, rm.REGISTERS[reg]["addr"], n_win, reg)
            w[col] = wrap(v, 32) if signed else v
        if hw.direct:       # VECTOR (STATE, NEXT) and TOP_I: read only in the direct-vector mode (0 else, as in golden)
            vec = _per_window(reads, rm.REGISTERS["VECTOR"]["addr"], n_win, "VECTOR")
            for col, fld in (("vector", "STATE"), ("vector_next", "NEXT")):
                lsb, width = rm.REGISTERS["VECTOR"]["fields"][fld][:2]
                w[col] = (vec >> lsb) & ((1 << width) - 1)
            top = _per_window(reads, rm.REGISTERS["TOP_I"]["addr"], n_win, "TOP_I")
            w["top_ia"], w["top_ib"] = _s16(top), _s16(top >> 16)
        vdq = _per_window(writes, rm.V_DQ_ADDR, n_win, "V_DQ")
        sincos = _per_window(writes, rm.SINCOS_ADDR, n_win, "SINCOS")
        iref = _per_window(writes, rm.I_REF_ADDR, n_win, "I_REF")
        vh = _per_window(writes, rm.V_H_ADDR, n_win, "V_H")
        ctrl_w = writes[(writes["addr"] == rm.CTRL_ADDR) & (writes["tick"] >= 0)]
        ctrl = ctrl_w["data"].astype(np.int64)[:n_win]
        # the first CTRL write that enables the outputs takes effect at the carrier bottom three quarters of a
        # period after the window boundary before it (docs/spec.md 2.2): ticks to spare before that bottom
        # (negative: the gates started a period late, and the run differs from golden's from then on)
        on = np.flatnonzero((ctrl_w["data"] >> rm.CTRL_ENABLE_LSB) & 1)
        enable_margin = (int((P - H // 2) - (int(ctrl_w["tick"][on[0]]) - H // 2) % P) if len(on) else None)
        w["v_d"], w["v_q"] = _s16(vdq), _s16(vdq >> 16)
        w["sin"], w["cos"] = _s16(sincos), _s16(sincos >> 16)
        for name in WINDOW_FIELDS:
            if name in t:
                w[name] = t[name]
        irqs = rec["irqs"]
        if len(irqs) < n_win + 1:
            raise RtlBackendError(f"{len(irqs)} window interrupts for {n_win} windows")
        # interrupt k rises in window k: the compares latched for it and the ADC mode its sampling uses
        w["adc_mode"] = irqs["adc_mode"][:n_win].astype(np.int64)
        cmp = irqs["cmp"][:n_win].astype(np.int64)
        for i, name in enumerate(("cmp_top_a", "cmp_top_b", "cmp_top_c", "cmp_bot_a", "cmp_bot_b", "cmp_bot_c")):
            w[name] = cmp[:, i]
        # ENV_A/ENV_B latched at the end of window k, sampled by the harness at interrupt k + 1 (the
        # firmware does not read them: sim/soc_sim.h)
        env = irqs["env"][1:n_win + 1].astype(np.int64)
        w["env_a"], w["env_b"] = env[:, 0], env[:, 1]
        # GAMMA, GAMMA_D, WSUM the same way (the firmware reads the first two only when it uses them, WSUM never)
        dem = irqs["dem"][1:n_win + 1].astype(np.int64)
        w["gamma"], w["gamma_d"], w["wsum"] = dem[:, 0], dem[:, 1], dem[:, 2]
        w.update(truth_columns(rec["truth"][:n_win], self.scales.pole_pairs))

        samples = rec["samples"]
        samples = samples[samples["tick"] < end]
        edges = rec["edges"]
        edges = edges[edges["tick"] < end]
        out = {"v_d": w["v_d"], "v_q": w["v_q"], "v_h": vh & 0x7FFF, "sin": w["sin"], "cos": w["cos"],
               "enable": (ctrl >> rm.CTRL_ENABLE_LSB) & 1, "i_d_ref": _s16(iref), "i_q_ref": _s16(iref >> 16)}
        writes_out = {f: np.asarray(out[f], dtype=np.int64) for f in OUTPUT_FIELDS}

        # interrupts 1..n_win report windows 0..n_win-1; their COMMIT latency and the core's cycles
        rep = irqs[1:n_win + 1]
        in_run = t["mode"] == MODE_RUN
        commit_lat = rep["commit"] - rep["tick"]
        late = int(irqs["late"][n_win]) - 2
        soc = {
            "cpu_core": cpu_source().stem,
            "left_out": [name for name in OPTIONS if options.get(name, 1) == 0],
            "fw_cycles_max": int(t["cycles"].max()),
            "fw_cycles_mean": round(float(t["cycles"].mean()), 1),
            "fw_cycles_target": int(fw_budget_share(P / sc.pwm.tick_hz) * P / soc_platform.CPU_CLOCK_DIVIDER),
            "fw_cycles_run_mean": round(float(t["cycles"][in_run].mean()), 1) if in_run.any() else None,
            "fw_cycles_run_max": int(t["cycles"][in_run].max()) if in_run.any() else None,
            "fw_cycles_run_max_at_s": (round(float(w["tick"][in_run][np.argmax(t["cycles"][in_run])]) / sc.pwm.tick_hz, 6)
                                       if in_run.any() else None),
            "irq_to_commit_cycles_max": int(commit_lat.max()) if (commit_lat >= 0).all() else None,
            "deadline_cycles": int(P - soc_platform.IRQ_LATENCY),
            "enable_margin_ticks": enable_margin,
            "late_commits": late,
            "sim_cycles": int(cycles),
            "wall_s": round(wall, 2),
            "mcycles_per_s": round(cycles / wall / 1e6, 3),
            "uart_log": bytes(rec["uart"]).decode(errors="replace"),
        }
        samples_out = {"tick": samples["tick"].astype(np.int64), "adc_a": samples["a"].astype(np.uint16),
                       "adc_b": samples["b"].astype(np.uint16), "adc_vdc": samples["vdc"].astype(np.uint16)}
        edges_out = {"tick": edges["tick"].astype(np.int64), "mask": edges["mask"].astype(np.int64)}
        return ClosedLoopResult(w, samples_out, edges_out, writes_out, hw, self.scales, sc.pwm.tick_hz,
                                int(t["flipped"][-1]), wall, soc=soc, backend="rtl", ident=ident)
