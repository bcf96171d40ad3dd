"""The closed-loop backends behind one interface, registered in one place.

A backend takes a validated :class:`golden.scenario.Scenario` with a ``[control]`` table and returns a
:class:`golden.closedloop.ClosedLoopResult` (the same trace format on every backend, so reports, plots
and the identity tests use one code path):

* ``golden``: the bit-true Python model (:class:`golden.closedloop.ClosedLoop`), the specification;
* ``rtl``: the C firmware on the VexRiscv of the Verilated ``hfi_soc`` (:mod:`hfi.rtl_backend`);
* ``hls``: the HLS C++ kernels with the host build of the firmware (:mod:`hfi.hls_backend`).

Use :func:`get` (``get("hls").run(sc)``) or :func:`run`; :data:`NAMES` lists them.
"""

from __future__ import annotations

import importlib
from dataclasses import dataclass
from typing import Callable

from golden.closedloop import ClosedLoopResult
from golden.firmware.estimator import METHODS
from golden.scenario import Scenario


class BackendError(RuntimeError):
    """A backend could not build or run (base of the backends' own error types)."""


@dataclass(frozen=True)
class Backend:
    """One backend: its name, a one-line description, and where its closed-loop class lives.

    ``loop`` is ``"module:Class"``; the class takes a scenario and has ``run(progress=..., **options)``.
    The module is imported on first use (the rtl and hls backends load cffi libraries and build tools).
    """

    name: str
    description: str
    loop: str

    def _class(self) -> Callable:
        module, cls = self.loop.split(":")
        return getattr(importlib.import_module(module), cls)

    def run(self, sc: Scenario, progress: bool = True, **options) -> ClosedLoopResult:
        """Run ``sc`` on this backend; ``options`` are backend-specific (rtl: ``fst``, ``fst_window``).
        Raises BackendError when a slot's estimator does not run on this backend (``MethodInfo.backends``)."""
        est = sc.estimator
        if est is not None:
            for name in (est.low, est.high):
                m = METHODS.get(name)
                if m is not None and self.name not in m.backends:
                    raise BackendError(f"scenario {sc.name}: estimator {name} runs on the "
                                       f"{', '.join(m.backends)} backend(s) only, not on {self.name} (hfi methods)")
        return self._class()(sc).run(progress=progress, **options)


BACKENDS: dict[str, Backend] = {b.name: b for b in (
    Backend("golden", "bit-true Python model (the specification)", "golden.closedloop:ClosedLoop"),
    Backend("rtl", "C firmware on VexRiscv in the Verilated hfi_soc, C plant", "hfi.rtl_backend:RtlClosedLoop"),
    Backend("hls", "HLS C++ kernels + host firmware + C plant, native", "hfi.hls_backend:HlsClosedLoop"),
)}
"""Every backend, by name (the order is the order of ``hfi methods`` and the CLI's help)."""

NAMES = tuple(BACKENDS)


def get(name: str) -> Backend:
    """The backend called ``name``; ValueError naming the valid ones otherwise."""
    try:
        return BACKENDS[name]
    except KeyError:
        raise ValueError(f"unknown backend {name!r} (valid: {', '.join(NAMES)})") from None


def run(sc: Scenario, backend: str = "golden", progress: bool = True, **options) -> ClosedLoopResult:
    """Run ``sc`` on the named backend."""
    return get(backend).run(sc, progress=progress, **options)
