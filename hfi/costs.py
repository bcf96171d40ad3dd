"""The firmware cost of each compared system (``hfi compare``, docs/compare.md): CPU clocks per control step
on the soft core, measured on the ``rtl`` backend (the C firmware on the VexRiscv of the Verilated hfi_soc)
in the system's own scenario, never typed in.

Each system's base scenario (its sweep spec with ``[set]``) runs for :data:`DURATION` (start-up, polarity
detection and the speed loop in RUN for every system). A step that takes longer than its own PWM period stops
the co-simulation; the system is then measured on a slower copy (the switching frequency divided by the next
of :data:`SLOWER`, everything else as written) and the report says so: the clocks per step barely depend on the
period, the share of the period is taken against the system's own. Results are cached in ``costs.json`` of the
report's directory, keyed by the scenario and by the firmware and RTL sources (a second call only reports).
"""

from __future__ import annotations

import copy
import json
from dataclasses import asdict, dataclass, replace
from pathlib import Path
from typing import Callable

from golden.scenario import Scenario, parse_scenario
from hfi import soc_platform
from hfi.backends import BackendError

ROOT = Path(__file__).resolve().parent.parent
DURATION = 0.5
"""Simulated seconds per system: every compared scenario is in RUN well before (the 001 drive, the latest,
from about 0.24 s)."""
SLOWER = (1, 2, 4)
"""Divisors of the switching frequency tried in turn when a step overruns its period."""
OVERRUN = "longer than a PWM period"
"""The rtl backend's words for a step that overran its period (hfi.rtl_backend, sim/soc_sim.cpp)."""
SOURCES = ("firmware/src", "firmware/link.ld", "rtl")
"""What the measured clocks depend on besides the scenario and the core: the cache key hashes these files."""


@dataclass(frozen=True)
class Cost:
    """One system's firmware cost: CPU clocks per step (in RUN, and over every step), measured at
    ``measured_f_sw``; ``period_clocks`` is the system's own period in CPU clocks; ``error`` if none could be
    measured."""

    system: str
    f_sw: float
    measured_f_sw: float
    period_clocks: int
    run_mean: float | None = None
    run_max: int | None = None
    mean: float | None = None
    max: int | None = None
    error: str = ""

    def share(self, clocks: float | None) -> float | None:
        """``clocks`` as a share of the system's own period."""
        return None if clocks is None else clocks / self.period_clocks


def rtl_soc(sc: Scenario) -> dict:
    """The ``soc`` dictionary of a run of ``sc`` on the rtl backend."""
    from hfi.rtl_backend import RtlClosedLoop

    return RtlClosedLoop(sc).run(progress=False).soc


def measure(system: str, sc: Scenario, run: Callable[[Scenario], dict] = rtl_soc) -> Cost:
    """The firmware cost of ``sc`` (run for :data:`DURATION`), on a slower copy if its step overruns."""
    f_sw = sc.pwm.f_sw
    period = round(sc.pwm.tick_hz / soc_platform.CPU_CLOCK_DIVIDER / f_sw)
    error = ""
    for k in SLOWER:
        copy_ = replace(sc, duration=DURATION, pwm=replace(sc.pwm, f_sw=f_sw / k))
        try:
            soc = run(copy_)
        except BackendError as exc:       # reported in the table
            error = str(exc).splitlines()[0]
            if OVERRUN in str(exc):
                continue
            break
        return Cost(system, f_sw, f_sw / k, period, soc["fw_cycles_run_mean"], soc["fw_cycles_run_max"],
                    soc["fw_cycles_mean"], soc["fw_cycles_max"])
    return Cost(system, f_sw, float("nan"), period, error=error)


def source_digest(extra: str) -> str:
    """The cache key: ``extra``, every file under :data:`SOURCES` and the soft core's Verilog (its caches and
    branch prediction set the clocks too; hfi.rtl_backend.digest)."""
    from hfi.rtl_backend import cpu_source, digest

    files = [p for top in SOURCES for p in (sorted((ROOT / top).rglob("*")) if (ROOT / top).is_dir() else [ROOT / top])
             if p.is_file()]
    return digest(files + [cpu_source()], extra)


def costs(bases: dict[str, dict], cache: Path, log=print,
          run: Callable[[Scenario], dict] = rtl_soc) -> list[Cost]:
    """The cost of each system from its base scenario tree (``Spec.base``), measured or read from ``cache``."""
    known = json.loads(cache.read_text()) if cache.exists() else {}
    out = []
    for system, base in bases.items():
        key = source_digest(json.dumps(base, sort_keys=True, default=str))
        if known.get(system, {}).get("key") == key:
            out.append(Cost(**known[system]["cost"]))
            continue
        log(f"firmware cost of {system}: {DURATION} s on the rtl backend")
        cost = measure(system, parse_scenario(copy.deepcopy(base), f"{system} base scenario"), run)
        known[system] = {"key": key, "cost": asdict(cost)}
        cache.parent.mkdir(parents=True, exist_ok=True)
        cache.write_text(json.dumps(known, indent=1, default=str))
        out.append(cost)
    return out


def _clocks(mean: float | None, worst: int | None) -> str:
    return "-" if mean is None else f"{mean:.0f} / {worst}"


def _share(c: Cost, mean: float | None, worst: int | None) -> str:
    return "-" if mean is None else f"{100 * c.share(mean):.0f} % / {100 * c.share(worst):.0f} %"


def worst_of_period(c: Cost) -> str:
    """The headline's cell: the worst step in RUN against the system's own period (where it was measured)."""
    if c.error or c.run_max is None:
        return "not measured"
    at = "" if c.measured_f_sw == c.f_sw else f" (at {c.measured_f_sw / 1e3:g} kHz)"
    return f"{c.run_max} / {c.period_clocks}{at}"


def table(items: list[Cost], labels: dict[str, str]) -> list[str]:
    """The report's section: per system, CPU clocks per step in RUN against its own period."""
    lines = ["## Firmware cost", "",
             "CPU clocks per control step of the firmware on the soft core (VexRiscv, 16 KiB instruction cache, the "
             "`hfi_soc_acc` accelerators), measured by this command on the `rtl` backend in each system's scenario "
             f"({DURATION} s: start-up, polarity detection, RUN; hfi/costs.py). Share: of the system's own control "
             "period. A system whose step overruns its period is measured on a slower copy (column `measured at`).",
             "", "| system | period [CPU clocks] | RUN, mean / worst | share of the period | all steps, mean / worst | "
             "measured at |", "|---|---|---|---|---|---|"]
    for c in items:
        name = labels.get(c.system, c.system)
        if c.error:
            lines.append(f"| {name} | {c.period_clocks} | not measured: {c.error} | - | - | - |")
            continue
        at = f"{c.measured_f_sw / 1e3:g} kHz" + ("" if c.measured_f_sw == c.f_sw else
                                                 f" (its {c.f_sw / 1e3:g} kHz overruns)")
        lines.append(f"| {name} | {c.period_clocks} | {_clocks(c.run_mean, c.run_max)} | "
                     f"{_share(c, c.run_mean, c.run_max)} | {_clocks(c.mean, c.max)} | {at} |")
    return lines
