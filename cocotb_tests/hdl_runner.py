"""Shared pytest side of the cocotb tests: build an RTL top with the cocotb runner and run a testbench.

Every module test (``cocotb_tests/test_<module>.py``) calls :func:`run_cocotb` from a pytest function,
once per simulator and parameter set; the cocotb coroutines live in ``cocotb_tests/tb_<module>.py``.

Random vectors: the testbenches draw from ``numpy.random.default_rng(seed)`` with ``seed =
random_seed()``: ``HFI_SEED`` from the environment if set, else a fresh seed; the seed is printed (and
recorded in the test log) so a failure can be replayed with ``HFI_SEED=<seed> make test``.
``HFI_RANDOM_N`` overrides the number of random vectors (default under Verilator :data:`RANDOM_N_SUITE` in ``make
test`` and :data:`RANDOM_N` in ``make deep``, which sets ``HFI_DEEP=1``; under Icarus, which runs about ten times
slower, :data:`RANDOM_N_ICARUS_SUITE` and :data:`RANDOM_N_ICARUS`).

Verilator builds are shared (:func:`shared_build`): tests that build the same top from the same sources with the
same parameters and arguments (the five safety cases and the four replays of ``tb_hfi_dsp``, ...) compile it once
into ``out/cocotb_builds/`` and each runs it in its own directory.
"""

from __future__ import annotations

import fcntl
import hashlib
import os
import re
import secrets
import shutil
import sys
import time
from importlib import metadata
from pathlib import Path

from cocotb_tools.runner import get_results, get_runner

ROOT = Path(__file__).resolve().parents[1]
RTL = ROOT / "rtl"
TB_DIR = Path(__file__).resolve().parent
VENV_BIN = Path(sys.executable).parent

RANDOM_N = 100_000
"""Random vectors per datapath module under Verilator in ``make deep`` (``HFI_DEEP=1``; issue 4: at least 100 000)."""
RANDOM_N_SUITE = 20_000
"""Random vectors per datapath module under Verilator in ``make test`` (README "Tests": the suite's 15 minutes on 2
cores; the depth of issue 4 runs in ``make deep``)."""
RANDOM_N_ICARUS = 10_000
"""Random vectors per datapath module under Icarus (the second simulator; about 10x slower) in ``make deep``."""
RANDOM_N_ICARUS_SUITE = 2_000
"""The same in ``make test``: Icarus checks that the RTL means the same to a second simulator, the random depth is
Verilator's (docs/rtl.md, Verification)."""
SIMULATORS = ("verilator", "icarus")
BUILD_CACHE = ROOT / "out" / "cocotb_builds"
"""Where the shared Verilator builds live (:func:`shared_build`), one directory per build key."""
STALE_S = 86400.0
"""A shared build not used for this long [s] is removed when its top is built anew."""


def _env_int(name: str) -> int | None:
    """The integer in environment variable ``name`` (decimal or 0x...), None if unset."""
    env = os.environ.get(name)
    if not env:
        return None
    try:
        return int(env, 0)
    except ValueError:
        raise ValueError(f"{name}={env!r} is not an integer") from None


def random_seed() -> int:
    """The seed of this run: ``HFI_SEED`` if set, else a new random one (printed by the testbench)."""
    seed = _env_int("HFI_SEED")
    return secrets.randbits(32) if seed is None else seed


def fuzz_seed() -> int:
    """The fuzzers' seed: ``FUZZ_SEED`` if set (decimal or 0x...), else :func:`random_seed`."""
    seed = _env_int("FUZZ_SEED")
    return random_seed() if seed is None else seed


def deep() -> bool:
    """True in ``make deep`` (``HFI_DEEP=1``): the full-depth verification."""
    return os.environ.get("HFI_DEEP", "") not in ("", "0")


def random_count(sim: str) -> int:
    """Number of random vectors for ``sim`` (``HFI_RANDOM_N`` overrides)."""
    env = os.environ.get("HFI_RANDOM_N")
    if env:
        return int(env)
    if sim != "verilator":
        return RANDOM_N_ICARUS if deep() else RANDOM_N_ICARUS_SUITE
    return RANDOM_N if deep() else RANDOM_N_SUITE


def rtl_sources(*names: str) -> list[Path]:
    """Paths of RTL files by name relative to ``rtl/`` (checked to exist)."""
    paths = [RTL / n for n in names]
    missing = [str(p) for p in paths if not p.is_file()]
    if missing:
        raise FileNotFoundError(f"RTL sources missing: {missing}")
    return paths


def core_rtl_files(core: Path = ROOT / "hfi_dsp.core") -> tuple[str, ...]:
    """The Verilog sources of the IP (names relative to ``rtl/``, in the order of ``core``): the
    ``rtl/...`` entries of its filesets (the regex of tests/test_rtl_package.py::core_files) without the
    include files (``.vh``, found through the include path)."""
    listed = re.findall(r"^\s+- (rtl/\S+?)(?::|$)", core.read_text(), flags=re.M)
    files = tuple(p.removeprefix("rtl/") for p in listed if p.endswith(".v"))
    if not files:
        raise ValueError(f"{core}: no rtl/*.v sources listed")
    return files


def public_top_vlt(toplevel: str) -> str:
    """A Verilator control file that makes the signals of the module ``toplevel`` public, and only those: with
    ``--no-public-flat-rw`` after cocotb's ``--public-flat-rw`` (which keeps every net of the design, and Verilator
    then evaluates all of its combinational logic at every evaluation, twice per clock), the design below is
    optimised as in a plain build. For testbenches that drive and read only their top's signals."""
    return f'`verilator_config\npublic_flat_rw -module "{toplevel}" -var "*"\n'


def _public_top_file(toplevel: str) -> Path:
    """:func:`public_top_vlt` of ``toplevel`` as a file in :data:`BUILD_CACHE` (a source of the build)."""
    path = BUILD_CACHE / "public" / f"{toplevel}.vlt"
    path.parent.mkdir(parents=True, exist_ok=True)
    text = public_top_vlt(toplevel)
    if not path.is_file() or path.read_text() != text:
        tmp = path.with_name(f"{path.name}.{os.getpid()}")
        tmp.write_text(text)
        os.replace(tmp, path)
    return path


def run_cocotb(*, sim: str, toplevel: str, sources: list[Path], tb_module: str, build_dir: Path,
               parameters: dict | None = None, env: dict | None = None, expect_tests: int | None = None,
               random_n: int | None = None, build_args: list[str] | None = None, waves: bool = False,
               public_all: bool = False) -> None:
    """Build ``toplevel`` from ``sources`` on ``sim`` and run the cocotb module ``tb_module``.

    ``env`` is passed to the testbench (strings); the seed and vector count are added as
    ``HFI_SEED`` / ``HFI_RANDOM_N`` so the testbench and the log agree (``random_n`` sets the count
    for this run, e.g. fewer vectors for the non-default points of a parameter sweep, unless
    ``HFI_RANDOM_N`` is set in the environment). Asserts that no cocotb test
    failed and, if ``expect_tests`` is given, that exactly that many ran. On Verilator only the top module's
    signals are visible to the testbench (:func:`public_top_vlt`: 2.4 times faster for the dsp replay); ``public_all``
    for a testbench that reaches into the instances below (cocotb's own ``--public-flat-rw``)."""
    os.environ["PATH"] = f"{VENV_BIN}{os.pathsep}{os.environ.get('PATH', '')}"
    if sim == "verilator" and shutil.which("ccache"):
        os.environ.setdefault("OBJCACHE", "ccache")   # Verilator's makefiles: the runtime compiles once
    seed = random_seed()
    if "HFI_SEED" in os.environ:   # the simulator takes the environment's value over extra_env: give it decimal
        os.environ["HFI_SEED"] = str(seed)
    count = random_n if random_n is not None and not os.environ.get("HFI_RANDOM_N") else random_count(sim)
    extra_env = {"HFI_SEED": str(seed), "HFI_RANDOM_N": str(count),
                 "PYTHONPATH": os.pathsep.join([str(TB_DIR), str(ROOT), os.environ.get("PYTHONPATH", "")])}
    extra_env.update({k: str(v) for k, v in (env or {}).items()})
    print(f"{tb_module} on {sim}: HFI_SEED={seed} HFI_RANDOM_N={extra_env['HFI_RANDOM_N']} "
          f"parameters={parameters or {}}")
    build_args = (["--threads", "1"] if sim == "verilator" else []) + list(build_args or [])
    if sim == "verilator" and not public_all:
        sources = [_public_top_file(toplevel), *sources]
        build_args.append("--no-public-flat-rw")
    runner = get_runner(sim)
    build = dict(sources=[str(s) for s in sources], hdl_toplevel=toplevel, parameters=parameters or {},
                 timescale=("1ns", "1ps"), build_args=build_args, includes=[str(RTL)], waves=waves, always=True)
    sim_dir = shared_build(runner, build) if sim == "verilator" else None
    if sim_dir is None:
        runner.build(build_dir=build_dir, **build)
        sim_dir = build_dir
    build_dir.mkdir(parents=True, exist_ok=True)
    # the language given: a runner whose build was shared never saw the sources it would guess it from
    results = runner.test(test_module=tb_module, hdl_toplevel=toplevel, hdl_toplevel_lang="verilog", build_dir=sim_dir,
                          test_dir=build_dir, results_xml=str(build_dir / "results.xml"),
                          extra_env=extra_env, waves=waves)
    total, failed = get_results(results)
    assert failed == 0, f"{failed} of {total} cocotb tests of {tb_module} failed on {sim} (HFI_SEED={seed})"
    if expect_tests is not None:
        assert total == expect_tests, f"{total} cocotb tests ran, expected {expect_tests}"


def shared_build(runner, build: dict) -> Path | None:
    """The directory of a Verilator build of ``build`` (``runner.build``'s arguments but ``build_dir``) in
    :data:`BUILD_CACHE`, built there unless a build of the same key is (a file lock serialises the pytest
    workers). The key: the top, every source's and include file's name and bytes, the parameters, the arguments and the
    Verilator and cocotb versions. None (build in the test's own directory) when a parameter names a file (an
    image the test wrote: its path is the test's own)."""
    params = build["parameters"]
    if any(os.sep in str(v) for v in params.values()):
        return None
    h = hashlib.sha256()
    for item in (build["hdl_toplevel"], sorted((k, str(v)) for k, v in params.items()), build["build_args"],
                 build["waves"], build["timescale"], metadata.version("verilator"), metadata.version("cocotb")):
        h.update(repr(item).encode())
    for f in [Path(s) for s in build["sources"]] + sorted(RTL.rglob("*.vh")):
        h.update(f.name.encode() + b"\0" + f.read_bytes())
    key = h.hexdigest()
    path = BUILD_CACHE / f"{build['hdl_toplevel']}-{key[:16]}"
    BUILD_CACHE.mkdir(parents=True, exist_ok=True)
    with open(BUILD_CACHE / f"{path.name}.lock", "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        stamp = path / "build.sha256"
        if stamp.is_file() and stamp.read_text() == key:
            stamp.touch()
            return path
        # a new build of this top: its builds unused for a day go (sources changed since)
        for old in BUILD_CACHE.glob(f"{build['hdl_toplevel']}-*/build.sha256"):
            if time.time() - old.stat().st_mtime > STALE_S:
                shutil.rmtree(old.parent, ignore_errors=True)
                old.parent.with_name(old.parent.name + ".lock").unlink(missing_ok=True)
        shutil.rmtree(path, ignore_errors=True)
        runner.build(build_dir=path, **build)
        stamp.write_text(key)
    return path
