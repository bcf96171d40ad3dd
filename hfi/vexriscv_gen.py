"""The soft core's Verilog, generated: VexRiscv (the LiteX "standard" configuration) with a larger
instruction cache, from the generator sources that the PyPI package pythondata-cpu-vexriscv ships.

Why (docs/soc.md, "The instruction cache"): the package's Verilog files all have a 4 KiB instruction
cache; the control step's code (6-14 KiB per method) does not fit it, and refilling it took 30-45 % of
every step. The core's own generator (``vexriscv.GenCoreDefault``, the program LiteX runs to make the
package's files) takes the cache size as an option, so the project runs it instead of changing any
Verilog: the same configuration as the package's ``VexRiscv.v`` (RV32IM, 4 KiB data cache, the same
ports), only ``--iCacheSize``, ``--prediction`` and ``--cfu`` differ (``--cfu true`` adds the CFU port of LiteX's
``full+cfu`` cores, the package's ``VexRiscv_FullCfu.v``: custom-0 instructions answered by rtl/hfi_cfu.v).

How, without sbt (whose plug-in repository is not reachable here): the Scala sources are copied from the
installed package; Maven fetches the compiler and SpinalHDL from Maven Central (Scala 2.11.12 with
SpinalHDL 1.7.1: the 1.6.0 and 1.7.0a of the package's build files are not on Maven Central; 1.7.1
compiles the same sources unchanged); ``scalac`` compiles the library, then the generator against it
(two passes, as sbt's two projects: the generator defines its own ``vexriscv.SpinalConfig``), and the
generator writes ``out/cpu/<name>.v``. Needs ``java`` (17 tested) and ``mvn`` (scripts/setup.sh installs
them when missing); about one minute and 63 MB of downloads the first time, cached in ``out/cpu/cache``.

    python -m hfi.vexriscv_gen [--icache BYTES] [--prediction KIND] [--cfu | --no-cfu]
                                    (defaults: soc_platform.CPU_ICACHE_BYTES, CPU_PREDICTION, CPU_CFU)
"""

from __future__ import annotations

import argparse
import importlib
import shutil
import subprocess
import sys
import time
from pathlib import Path

from hfi import soc_platform

ROOT = Path(__file__).resolve().parent.parent
OUT = ROOT / "out" / "cpu"
CACHE = OUT / "cache"
SCALA = "2.11.12"
SPINAL = "1.7.1"
JAVA_OPTS = ["-Xss16m", "-Xmx3g"]

POM = f"""<project xmlns="http://maven.apache.org/POM/4.0.0">
  <modelVersion>4.0.0</modelVersion>
  <groupId>local</groupId><artifactId>hfi-vexriscv-gen</artifactId><version>1</version>
  <packaging>pom</packaging>
  <dependencies>
    <dependency><groupId>org.scala-lang</groupId><artifactId>scala-compiler</artifactId><version>{SCALA}</version></dependency>
    <dependency><groupId>org.scala-lang</groupId><artifactId>scala-library</artifactId><version>{SCALA}</version></dependency>
    <dependency><groupId>org.scala-lang</groupId><artifactId>scala-reflect</artifactId><version>{SCALA}</version></dependency>
    <dependency><groupId>com.github.spinalhdl</groupId><artifactId>spinalhdl-core_2.11</artifactId><version>{SPINAL}</version></dependency>
    <dependency><groupId>com.github.spinalhdl</groupId><artifactId>spinalhdl-lib_2.11</artifactId><version>{SPINAL}</version></dependency>
    <dependency><groupId>com.github.spinalhdl</groupId><artifactId>spinalhdl-idsl-plugin_2.11</artifactId><version>{SPINAL}</version></dependency>
    <dependency><groupId>org.yaml</groupId><artifactId>snakeyaml</artifactId><version>1.8</version></dependency>
  </dependencies>
</project>
"""


class CoreGenError(RuntimeError):
    """The core could not be generated (a tool missing, a download or compile failure)."""


CFU_VARIANT = "VexRiscv_FullCfu.v"
"""The package's core with the CFU port (LiteX ``full+cfu``), whose port the generated one must match."""

PREDICTIONS = ("none", "static", "dynamic", "dynamic_target")
"""The generator's branch predictors (``GenCoreDefault --prediction``); the package's files are ``static``."""


def core_name(icache_bytes: int, prediction: str, cfu: bool = False) -> str:
    """File stem of the generated core with this instruction cache, branch prediction and CFU port (module
    name stays ``VexRiscv``): ``VexRiscv_I16K`` for the package's static prediction,
    ``VexRiscv_I16K_dynamic_target``, ``VexRiscv_I16K_dynamic_target_cfu``."""
    return (f"VexRiscv_I{icache_bytes // 1024}K" + ("" if prediction == "static" else f"_{prediction}")
            + ("_cfu" if cfu else ""))


def core_path(icache_bytes: int = soc_platform.CPU_ICACHE_BYTES,
              prediction: str = soc_platform.CPU_PREDICTION, cfu: bool = soc_platform.CPU_CFU) -> Path:
    return OUT / f"{core_name(icache_bytes, prediction, cfu)}.v"


def _package_dir() -> Path:
    try:
        pd = importlib.import_module(soc_platform.CPU_PACKAGE)
    except ImportError as e:
        raise CoreGenError("pythondata-cpu-vexriscv is not installed: run `make setup`") from e
    d = Path(pd.data_location)
    if not (d / "src/main/scala/vexriscv/GenCoreDefault.scala").is_file():
        raise CoreGenError(f"{d} has no VexRiscv generator sources (GenCoreDefault.scala)")
    return d


def _run(cmd: list[str], what: str, cwd: Path | None = None) -> None:
    t0 = time.monotonic()
    proc = subprocess.run(cmd, cwd=cwd, capture_output=True, text=True)
    if proc.returncode != 0:
        raise CoreGenError(f"{what} failed (exit {proc.returncode}):\n{proc.stdout[-3000:]}{proc.stderr[-3000:]}")
    print(f"[vexriscv] {what}: {time.monotonic() - t0:.0f} s", flush=True)


CFU_PORT = "CfuPlugin_bus_"
"""Prefix of the CFU port's signals (the package's ``VexRiscv_FullCfu.v``)."""


def _ports(verilog: Path, cfu: bool | None = None) -> list[str]:
    """The port lines of ``verilog``'s module ``VexRiscv``: all of them, or only those of the CFU port
    (``cfu`` True) or only the others (False)."""
    text = verilog.read_text()
    start = text.index("module VexRiscv (")
    lines = [ln.strip() for ln in text[start:text.index(");", start)].splitlines()[1:]]
    return [ln for ln in lines if cfu is None or (CFU_PORT in ln) == cfu]


def generate(icache_bytes: int = soc_platform.CPU_ICACHE_BYTES,
             prediction: str = soc_platform.CPU_PREDICTION, cfu: bool = soc_platform.CPU_CFU) -> Path:
    """Generate (once) the core with ``icache_bytes`` of instruction cache, the branch predictor
    ``prediction`` and (``cfu``) the CFU port; returns its Verilog."""
    if icache_bytes < 1024 or icache_bytes & (icache_bytes - 1):
        raise CoreGenError(f"instruction cache of {icache_bytes} bytes: a power of two >= 1024 is required")
    if prediction not in PREDICTIONS:
        raise CoreGenError(f"branch prediction {prediction!r}: one of {', '.join(PREDICTIONS)} is required")
    out = core_path(icache_bytes, prediction, cfu)
    if out.is_file():
        return out
    for tool in ("java", "mvn"):
        if shutil.which(tool) is None:
            raise CoreGenError(f"`{tool}` is not on PATH: run `make setup` (it installs a JDK and Maven)")
    pkg = _package_dir()
    jars, classes = CACHE / "jars", CACHE / "classes"
    if not (jars / ".done").is_file():
        CACHE.mkdir(parents=True, exist_ok=True)
        (CACHE / "pom.xml").write_text(POM)
        shutil.rmtree(jars, ignore_errors=True)
        _run(["mvn", "-B", "-q", "-f", str(CACHE / "pom.xml"), f"-Dmaven.repo.local={CACHE / 'm2'}",
              "dependency:copy-dependencies", f"-DoutputDirectory={jars}"], "jars from Maven Central")
        (jars / ".done").touch()
    compiler = ":".join(str(jars / f"{a}-{SCALA}.jar") for a in ("scala-compiler", "scala-library", "scala-reflect"))
    compiler += ":" + ":".join(str(p) for p in jars.glob("scala-xml_2.11-*.jar"))
    libs = ":".join(str(p) for p in sorted(jars.glob("*.jar")) if "scala-compiler" not in p.name)
    plugin = ["-Xplugin:" + str(jars / f"spinalhdl-idsl-plugin_2.11-{SPINAL}.jar"), "-Xplugin-require:idsl-plugin",
              "-nowarn"]
    scalac = ["java", *JAVA_OPTS, "-cp", compiler, "scala.tools.nsc.Main", *plugin]
    if not (classes / ".done").is_file():
        shutil.rmtree(classes, ignore_errors=True)
        (classes / "vex").mkdir(parents=True)
        (classes / "gen").mkdir()
        sources = sorted(str(p) for p in (pkg / "ext/VexRiscv/src/main/scala").rglob("*.scala"))
        (CACHE / "sources.txt").write_text("\n".join(sources) + "\n")
        _run([*scalac, "-classpath", libs, "-d", str(classes / "vex"), "@" + str(CACHE / "sources.txt")],
             f"compile the VexRiscv library ({len(sources)} files)")
        _run([*scalac, "-classpath", f"{libs}:{classes / 'vex'}", "-d", str(classes / "gen"),
              str(pkg / "src/main/scala/vexriscv/GenCoreDefault.scala")], "compile GenCoreDefault")
        (classes / ".done").touch()
    work = CACHE / "gen"
    work.mkdir(exist_ok=True)
    name = core_name(icache_bytes, prediction, cfu)
    _run(["java", *JAVA_OPTS, "-cp", f"{classes / 'gen'}:{classes / 'vex'}:{libs}", "vexriscv.GenCoreDefault",
          "--iCacheSize", str(icache_bytes), "--prediction", prediction, "--cfu", "true" if cfu else "false",
          "--outputFile", name], f"generate {name}", cwd=work)
    made = work / f"{name}.v"
    if _ports(made, False) != _ports(pkg / soc_platform.CPU_VARIANT):
        raise CoreGenError(f"{made}: its ports differ from the package's {soc_platform.CPU_VARIANT}")
    if _ports(made, True) != (_ports(pkg / CFU_VARIANT, True) if cfu else []):
        raise CoreGenError(f"{made}: its CFU port differs from the package's {CFU_VARIANT}")
    OUT.mkdir(parents=True, exist_ok=True)
    tmp = out.with_suffix(".v.tmp")
    shutil.copyfile(made, tmp)
    tmp.replace(out)   # atomic: a half-written core is never taken
    return out


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--icache", type=int, default=soc_platform.CPU_ICACHE_BYTES,
                    help=f"instruction cache bytes (default {soc_platform.CPU_ICACHE_BYTES})")
    ap.add_argument("--prediction", choices=PREDICTIONS, default=soc_platform.CPU_PREDICTION,
                    help=f"branch prediction (default {soc_platform.CPU_PREDICTION})")
    ap.add_argument("--cfu", action=argparse.BooleanOptionalAction, default=soc_platform.CPU_CFU,
                    help=f"the CFU port for hfi_cfu (default {soc_platform.CPU_CFU})")
    args = ap.parse_args(argv)
    try:
        print(generate(args.icache, args.prediction, args.cfu))
    except CoreGenError as e:
        print(f"vexriscv_gen: {e}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
