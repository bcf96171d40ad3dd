"""Run one scenario file and write its outputs (``hfi run``, ``make run``).

A scenario with a ``[control]`` table runs a closed loop (the default, ``scenarios/fullload_start.toml``)
on one of the backends of :mod:`hfi.backends` (default ``$BACKEND`` or ``rtl``):

- ``rtl``: the firmware (firmware/, C) on the VexRiscv of the Verilated ``hfi_soc`` drives the C plant
  through the RTL (:mod:`hfi.rtl_backend`; an FST waveform on request);
- ``golden``: the bit-true Python model of the same system (:mod:`golden.closedloop`), ~30x faster;
- ``hls``: the HLS-style C++ kernels of hls/ (native C simulation) with the host build of the firmware
  and the C plant (:mod:`hfi.hls_backend`), the fastest.

All give identical traces (tests/test_rtl_identity.py, tests/test_hls_identity.py); :mod:`hfi.report`
writes ``trace.npz``, ``metrics.json`` (docs/metrics.md), ``closed_loop.png``, ``angles.png`` and
``phase_current.png``. A scenario without one is the open-loop injection study of
:mod:`hfi.openloop_run` (square-wave injection on a fixed estimated d-axis), reported by
:mod:`hfi.openloop_report`. Outputs go to ``out_dir`` or the scenario's ``output.dir``.
"""

from __future__ import annotations

import os
from dataclasses import dataclass

from golden.scenario import load_scenario
from hfi import backends, openloop_report, report
from hfi.openloop_run import simulate

DEFAULT_BACKEND = "rtl"
"""Backend when neither the caller nor ``$BACKEND`` names one."""


@dataclass
class RunOutput:
    """What a run wrote: its metrics, the files, and the firmware's UART log (rtl backend, else "")."""

    metrics: dict
    files: list[str]
    uart_log: str


def default_backend() -> str:
    """``$BACKEND`` if set and not empty, else :data:`DEFAULT_BACKEND`."""
    return os.environ.get("BACKEND") or DEFAULT_BACKEND


def run_file(path: str, backend: str | None = None, out_dir: str | None = None, progress: bool = True,
             fst: str | None = None, fst_window: tuple[float, float] = (0.0, 0.002),
             every_block: bool = False) -> RunOutput:
    """Load ``path``, run it (closed loop on ``backend``, or the open-loop study) and write the outputs.

    ``fst``: FST waveform of the SoC over ``fst_window`` [s] (rtl backend only). ``every_block``: the FPGA build with
    every optional block in instead of the scenario's system (rtl backend only). Raises ScenarioError, OSError,
    ValueError (unknown backend, ``fst`` or ``every_block`` on another backend), PlantError, BackendError.
    """
    backend = default_backend() if backend is None else backend
    backends.get(backend)
    if fst is not None and backend != "rtl":
        raise ValueError(f"an FST waveform needs the rtl backend (not {backend})")
    if every_block and backend != "rtl":
        raise ValueError(f"--every-block chooses the rtl backend's FPGA build (not {backend}'s)")
    if not fst_window[0] < fst_window[1]:
        raise ValueError(f"FST window {fst_window[0]} .. {fst_window[1]} s is empty")
    sc = load_scenario(path)
    if fst is not None and not 0 <= fst_window[0] < sc.duration:
        raise ValueError(f"FST window {fst_window[0]} .. {fst_window[1]} s: it must start within the run's "
                         f"0 .. {sc.duration:g} s")
    out_dir = out_dir or sc.output.dir
    os.makedirs(out_dir, exist_ok=True)
    if sc.control is None:
        if fst is not None or every_block:
            raise ValueError(f"{path}: no [control] table (open-loop study): no SoC to simulate")
        res = simulate(sc, progress=progress)
        metrics, files = openloop_report.write_all(sc, res, out_dir)
        return RunOutput(metrics, files, "")
    options = {"fst": fst, "fst_window": tuple(fst_window)} if fst is not None else {}
    if every_block:
        from hfi.rtl_backend import EVERY_BLOCK
        options["options"] = EVERY_BLOCK
    res = backends.run(sc, backend, progress=progress, **options)
    metrics, files = report.write_all(sc, res, out_dir)
    return RunOutput(metrics, files, "" if res.soc is None else res.soc["uart_log"])
