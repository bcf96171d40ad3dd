"""Closed-loop backend ``hls``: the HLS kernels of ``hls/`` (native C simulation), the host build of the
firmware and the C plant, window by window in one native library (``hls/backend/hls_loop.cpp``).

It runs the same scenario files as the golden and rtl backends and returns the same
:class:`golden.closedloop.ClosedLoopResult` (so reports, plots and the identity test share one format).
The plant is created from the scenario exactly as the golden loop does (:class:`golden.plant.Plant`);
the firmware parameters come from :func:`golden.control_config.firmware_params`, converted field by field
into ``struct fw_params`` (:func:`hfi.fw_c.params_to_c`). Python only runs the loop in chunks of
windows (progress on stderr) and collects the records.
"""

from __future__ import annotations

import functools
import math
import time

import cffi
import numpy as np

from golden.closedloop import OUTPUT_FIELDS, ClosedLoopResult, speed_references, truth_columns
from golden.control_config import firmware_params, hardware_config, scales
from golden.fpga.adc_trigger import OS_MIN_DEFAULT
from golden.fpga.gate_generator import DEAD_MIN_DEFAULT
from golden.fpga.overcurrent import fault_delay, gate_off_delay
from golden.plant import Plant, binding
from golden.scenario import Scenario
from hfi import hls_build
from hfi.backends import BackendError
from hfi.fw_c import OUTPUT_FIELDS as FW_OUTPUT_FIELDS, cdef_text, ident_from_c, ident_to_c, params_to_c

HEADERS = tuple(hls_build.ROOT / h for h in ("firmware/src/control.h", "sim/plant_records.h",
                                              "hls/backend/hls_window.h", "hls/backend/hls_loop.h"))
CHUNK_WINDOWS = 1000
"""Windows per call into the native loop (progress granularity)."""
_KINDS = {"windows": 0, "outputs": 1, "truth": 2, "samples": 3, "edges": 4}
INT64_MAX = (1 << 63) - 1


class HlsBackendError(BackendError):
    """The native loop refused its setup or stopped (the message says why)."""


@functools.lru_cache(maxsize=None)
def _library():
    ffi = cffi.FFI()
    ffi.cdef(cdef_text(*HEADERS, drop=("struct plant;", "struct fw_params;", "struct fw_ident;")).replace(
        "struct hls_loop;", "struct hls_loop; struct plant;"))
    return ffi, ffi.dlopen(str(hls_build.build("loop")))


def _records(lib, h, kind: str, size: int, dtype=None) -> np.ndarray:
    """The records of one kind (``size`` bytes each in C) as a structured array of ``dtype``, or, for
    ``dtype=None`` (a struct of int64 fields only), as an int64 array with one column per field."""
    n = lib.hls_loop_count(h, _KINDS[kind])
    buf = bytearray(n * size)
    if n:
        lib.hls_loop_copy(h, _KINDS[kind], _library()[0].from_buffer(buf))
    if dtype is None:
        return np.frombuffer(buf, dtype=np.int64).reshape(n, size // 8)
    if np.dtype(dtype).itemsize != size:
        raise HlsBackendError(f"{kind} records: {size} bytes in C, {np.dtype(dtype).itemsize} in numpy")
    return np.frombuffer(buf, dtype=dtype)


class HlsClosedLoop:
    """The ``hls`` backend of one scenario (every ``[control]`` setting the golden loop supports)."""

    def __init__(self, sc: Scenario):
        if sc.control is None:
            raise ValueError(f"scenario {sc.name} has no [control] settings")
        self.sc = sc
        self.hw = hardware_config(sc)
        self.scales = scales(sc)

    def run(self, progress: bool = True) -> ClosedLoopResult:
        sc, hw = self.sc, self.hw
        H = hw.pwm_half
        tick_hz = sc.pwm.tick_hz
        speed_ref = speed_references(sc, hw, self.scales)
        n_win = len(speed_ref)
        ffi, lib = _library()
        setup = ffi.new("struct hls_setup *")
        for name, value in (("half", H), ("dead_ticks", hw.dead_ticks),
                            ("dead_min", DEAD_MIN_DEFAULT), ("os_ticks", hw.os_ticks),
                            ("os_min", OS_MIN_DEFAULT), ("blank_ticks", hw.blank_ticks), ("adc_mode", hw.adc_mode),
                            ("adc_bits", hw.adc_bits), ("adc_offset_a", hw.adc_offset[0]),
                            ("adc_offset_b", hw.adc_offset[1]), ("adc_gain_a", hw.adc_gain[0]),
                            ("adc_gain_b", hw.adc_gain[1]), ("cw_angle_step", hw.cw_angle_step),
                            ("dtc_gain", hw.dtc_gain), ("hf_amp", hw.hf_amp), ("recip_h", hw.recip_h),
                            ("inj_rot", hw.inj_rot), ("inj_step", hw.inj_step), ("inj_per", hw.inj_per),
                            ("cic_m", hw.cic_m), ("direct", hw.direct), ("n_windows", n_win),
                            ("oc_limit", hw.oc_limit), ("oc_gate_delay", gate_off_delay(hw.adc_bits)),
                            ("oc_fault_delay", fault_delay(hw.adc_bits))):
            try:
                setattr(setup, name, int(value))
            except OverflowError:      # beyond the C field: the same refusal as the native loop's range checks
                raise HlsBackendError(f"scenario {sc.name}: {name} = {int(value)} is outside the range of its "
                                      "register") from None
        ds = sc.control.switch_to_ds_at
        setup.ds_from_tick = INT64_MAX if ds is None else math.ceil(ds * tick_hz)
        refs = ffi.from_buffer("int32_t[]", speed_ref)
        setup.speed_ref = refs
        fp = firmware_params(sc)
        fwp = params_to_c(ffi, fp)    # without the identification program: it goes in its own block
        # control.mode = "commission": the program and its executor's state in a struct fw_ident that the loop's
        # fw_state.ident points to (hls_loop_set_ident); kept alive here until the run's state is read back
        block = None if fp.ident is None else ident_to_c(ffi, fp.ident)
        plant = Plant(sc.plant)
        err = ffi.new("char[]", 512)
        h = lib.hls_loop_create(setup, fwp, ffi.cast("struct plant *", plant._p), err, 512)
        if h == ffi.NULL:
            raise HlsBackendError(f"scenario {sc.name}: {ffi.string(err).decode()}")
        try:
            if block is not None and lib.hls_loop_set_ident(h, block) != 0:
                raise HlsBackendError(f"scenario {sc.name}: the loop refused the identification block")
            t0 = time.perf_counter()
            bar = None
            if progress:
                from tqdm import tqdm
                bar = tqdm(total=n_win, desc=f"{sc.name} [hls]", unit="win", mininterval=0.5)
            done = 0
            while done < n_win:
                done = lib.hls_loop_run(h, CHUNK_WINDOWS)
                if done < 0:
                    raise HlsBackendError(f"scenario {sc.name}: {ffi.string(lib.hls_loop_error(h)).decode()}")
                if bar is not None:
                    bar.update(done - bar.n)
            if bar is not None:
                bar.close()
            wall = time.perf_counter() - t0
            win = _records(lib, h, "windows", ffi.sizeof("struct hls_window"))
            outs = _records(lib, h, "outputs", ffi.sizeof("struct fw_outputs"),
                            [(f, "<i4") for f in FW_OUTPUT_FIELDS])
            truth = _records(lib, h, "truth", binding.ffi.sizeof("struct plant_state"), binding.STATE_DTYPE)
            samples = _records(lib, h, "samples", ffi.sizeof("struct adc_sample"),
                               [("tick", "<i8"), ("a", "<i4"), ("b", "<i4"), ("vdc", "<i4"), ("pad", "<i4")])
            edges = _records(lib, h, "edges", ffi.sizeof("struct gate_edge"), [("tick", "<i8"), ("mask", "<i8")])
            flipped = int(lib.hls_loop_flipped(h))
            plant_s = float(lib.hls_loop_plant_seconds(h))
            ident = None if block is None else ident_from_c(block, fp.ident)
        finally:
            lib.hls_loop_free(h)
        columns = [f.name if isinstance(f, str) else f[0] for f in ffi.typeof("struct hls_window").fields]
        windows = {name: win[:, i].copy() for i, name in enumerate(columns)}
        windows.update(truth_columns(truth, self.scales.pole_pairs))
        writes = {f: outs[f].astype(np.int64) for f in OUTPUT_FIELDS}
        samples_out = {"tick": samples["tick"].copy(), "adc_a": samples["a"].astype(np.uint16),
                       "adc_b": samples["b"].astype(np.uint16), "adc_vdc": samples["vdc"].astype(np.uint16)}
        edges_out = {"tick": edges["tick"].copy(), "mask": edges["mask"].astype(np.int32)}
        return ClosedLoopResult(windows, samples_out, edges_out, writes, hw, self.scales, tick_hz, flipped, wall,
                                backend="hls", plant_wall_s=plant_s, ident=ident)
