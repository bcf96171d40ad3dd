"""cffi binding of the C plant (``golden/plant/src``).

The struct layouts come from ``plant_api.h`` itself (cffi parses it), so the C header is the only
place they are written. Parameters are nested dicts keyed by the C field names
(:func:`golden.plant.defaults.default_params`).
"""

from __future__ import annotations

import re
from pathlib import Path

import cffi
import numpy as np

_HERE = Path(__file__).resolve().parent
HEADER = _HERE / "src" / "plant_api.h"
LIBRARY = _HERE / "libhfiplant.so"

ffi = cffi.FFI()
ffi.cdef(HEADER.read_text())
_lib = None
ADC_CHANNELS, ADC_VDC = (int(re.search(rf"#define {name} (\d+)", HEADER.read_text())[1])
                         for name in ("PLANT_ADC_CHANNELS", "PLANT_ADC_VDC"))
"""ADC channels per sample and the dc link's among them (``PLANT_ADC_CHANNELS``, ``PLANT_ADC_VDC`` of the
header): the currents a, b, c, then the dc link."""


MAG_KINDS = {"linear": 0, "dsat": 1, "algebraic": 2, "table": 3}
GATE_BITS = {"a_hi": 0, "a_lo": 1, "b_hi": 2, "b_lo": 3, "c_hi": 4, "c_lo": 5}
"""Gate mask layout: bit 2k is the high switch of leg k (a, b, c), bit 2k+1 its low switch."""


class PlantError(ValueError):
    """A parameter or input the plant refuses (the message says which and why)."""


class ShootThroughError(RuntimeError):
    """Both switches of an inverter leg were commanded on: the hardware must never do this."""


def library():
    """The loaded C library; a clear error if it was not built."""
    global _lib
    if _lib is None:
        if not LIBRARY.exists():
            raise PlantError(f"plant library {LIBRARY} is missing: run `make setup` (scripts/setup.sh) first")
        if LIBRARY.stat().st_mtime < max(p.stat().st_mtime for p in (_HERE / "src").iterdir()):
            raise PlantError(f"plant library {LIBRARY} is older than its sources: run `make setup`")
        _lib = ffi.dlopen(str(LIBRARY))
    return _lib


def _numpy_dtype(ctype) -> np.dtype:
    """numpy structured dtype with the exact layout of a cffi struct type."""
    scalar = {"double": np.float64, "int": np.int32, "long long": np.int64}
    names, formats, offsets = [], [], []
    for name, field in ctype.fields:
        t = field.type
        if t.kind == "array":
            formats.append((scalar[t.item.cname], t.length))
        else:
            formats.append(scalar[t.cname])
        names.append(name)
        offsets.append(field.offset)
    return np.dtype({"names": names, "formats": formats, "offsets": offsets, "itemsize": ffi.sizeof(ctype)})


STATE_DTYPE = _numpy_dtype(ffi.typeof("struct plant_state"))
"""dtype of the true-state records returned by :meth:`Plant.run` (fields of ``struct plant_state``)."""


def _fill(cstruct, values: dict, keep: list, path: str) -> None:
    """Copy a nested dict into a cffi struct; arrays behind pointers are allocated and kept alive."""
    fields = dict(ffi.typeof(cstruct).fields)
    for key, value in values.items():
        where = f"{path}{key}"
        if key not in fields:
            raise PlantError(f"{where}: not a plant parameter (valid: {', '.join(fields)})")
        ftype = fields[key].type
        if ftype.kind == "struct":
            if not isinstance(value, dict):
                raise PlantError(f"{where}: expected a table of fields")
            if ftype.cname == "struct profile":
                value = dict(value)
                t, v = value.pop("t", []), value.pop("v", [])
                if len(t) != len(v):
                    raise PlantError(f"{where}: t and v have different lengths")
                value["n"] = len(t)
                for name, arr in (("t", t), ("v", v)):
                    buf = ffi.new("double[]", [float(x) for x in arr]) if len(arr) else ffi.NULL
                    keep.append(buf)
                    setattr(getattr(cstruct, key), name, buf)
            _fill(getattr(cstruct, key), value, keep, where + ".")
        elif ftype.kind == "pointer" and ftype.item.cname == "struct fault":
            faults = list(value)
            buf = ffi.new("struct fault[]", max(len(faults), 1))
            keep.append(buf)
            for k, fault in enumerate(faults):
                _fill(buf[k], fault, keep, f"{where}[{k}].")
            cstruct.faults, cstruct.n_faults = buf, len(faults)
        elif ftype.kind == "pointer":
            if value is None:
                setattr(cstruct, key, ffi.NULL)
            else:
                buf = ffi.new("double[]", [float(x) for x in np.ravel(value)])
                keep.append(buf)
                setattr(cstruct, key, buf)
        elif ftype.kind == "array":
            if len(value) != ftype.length:
                raise PlantError(f"{where}: expected {ftype.length} values")
            setattr(cstruct, key, [float(x) for x in value])
        else:
            try:
                setattr(cstruct, key, value)
            except (TypeError, OverflowError) as exc:
                raise PlantError(f"{where}: {exc}") from None


class Plant:
    """One motor + inverter + sensors, advanced in integer FPGA clock ticks.

    Parameters
    ----------
    params : dict
        Complete parameter tree (see :func:`golden.plant.defaults.default_params`).
    """

    def __init__(self, params: dict):
        lib = library()
        keep: list = []
        cparams = ffi.new("struct plant_params *")
        _fill(cparams[0], params, keep, "")
        err = ffi.new("char[]", 256)
        handle = lib.plant_create(cparams, err, 256)
        if handle == ffi.NULL:
            raise PlantError(ffi.string(err).decode())
        self._lib = lib
        self._p = ffi.gc(handle, lib.plant_free)
        self.params = params
        self._run = lib.plant_run
        self._state = ffi.new("struct plant_state *")
        self._state_bytes = ffi.buffer(self._state)
        self._snapshot = None

    # ---- per-event API ---------------------------------------------------------------------------
    @property
    def tick(self) -> int:
        """Current time in ticks."""
        return int(self.state()["tick"])

    def advance(self, tick: int) -> None:
        """Integrate up to ``tick`` with the present gate state or ideal voltages."""
        if self._lib.plant_advance(self._p, int(tick)) != 0:
            raise PlantError(f"tick {tick} is before the plant's time {self.tick}")

    def set_gates(self, gates: int) -> None:
        """Apply a 6-bit gate mask (see ``GATE_BITS``) at the present tick."""
        if not 0 <= int(gates) < 64:
            raise PlantError(f"gate mask {gates} is not a 6-bit value")
        if self._lib.plant_set_gates(self._p, int(gates)) == self._lib.PLANT_SHOOT_THROUGH:
            raise ShootThroughError(f"gate mask {int(gates):#04x} turns on both switches of a leg")

    def set_voltage(self, v_abc) -> None:
        """Drive the machine with ideal phase voltages (averaged inverter) from the present tick."""
        v = ffi.new("double[3]", [float(x) for x in v_abc])
        self._lib.plant_set_voltage(self._p, v)

    def sample(self):
        """Sample the ``ADC_CHANNELS`` channels now: (ADC codes, analog values): the phase currents a, b,
        c [A], then the dc link [V]."""
        adc = ffi.new("int[]", ADC_CHANNELS)
        analog = ffi.new("double[]", ADC_CHANNELS)
        if (status := self._lib.plant_sample(self._p, adc, analog)) != 0:
            raise status_error(status)
        return np.array(list(adc), dtype=np.int32), np.array(list(analog))

    def state(self) -> np.void:
        """True state now, as a record of ``STATE_DTYPE``."""
        self._lib.plant_get_state(self._p, self._state)
        # a fresh writable record (np.frombuffer of a copy is far cheaper than np.zeros of this dtype)
        return np.frombuffer(bytearray(self._state_bytes), dtype=STATE_DTYPE)[0]

    def checkpoint(self) -> None:
        """Remember the plant's present moment (``plant_save`` into one buffer of its own, kept until the next
        checkpoint): :meth:`rollback` goes back to it."""
        if self._snapshot is None:
            self._snapshot = ffi.new("char[]", self._lib.plant_snapshot_size())
        self._lib.plant_save(self._p, self._snapshot)

    def rollback(self) -> None:
        """Back to the moment of the last :meth:`checkpoint` (``plant_restore``)."""
        if self._snapshot is None:
            raise PlantError("rollback without a checkpoint")
        self._lib.plant_restore(self._p, self._snapshot)

    # ---- batch API -------------------------------------------------------------------------------
    def run(self, edge_ticks, sample_ticks, gates=None, volts=None, analog=False, truth=False) -> dict:
        """Apply input changes and take samples, merged by tick, in one C call.

        Parameters
        ----------
        edge_ticks : array of int
            Ticks of the input changes (non-decreasing).
        sample_ticks : array of int
            Sample ticks (non-decreasing); at equal ticks, an input change comes first.
        gates : array of int, optional
            Gate mask after each edge.
        volts : array (n, 3), optional
            Ideal phase voltages after each edge (instead of ``gates``).
        analog, truth : bool
            Also return the analog sensor values / the true state at each sample.

        Returns
        -------
        dict with ``adc`` (n, 3) int32 (the phase currents' codes) and ``vdc`` (n,) int32 (the dc-link
        channel's codes), and ``analog`` (n, 3) [A] with ``vdc_analog`` (n,) [V], ``truth`` (n,)
        ``STATE_DTYPE`` if asked.
        """
        # Called once per PWM window by the closed loop: kept lean (the C call checks the tick order
        # and the gate masks, so no numpy pass over the inputs is needed here).
        edge_ticks = np.ascontiguousarray(edge_ticks, dtype=np.int64)
        sample_ticks = np.ascontiguousarray(sample_ticks, dtype=np.int64)
        n_e, n_s = len(edge_ticks), len(sample_ticks)
        if (gates is None) == (volts is None) and n_e:
            raise PlantError("give exactly one of gates and volts")
        p_gates = p_volts = ffi.NULL
        if gates is not None:
            g = np.ascontiguousarray(gates, dtype=np.int32)
            if len(g) != n_e or (g is not gates and not _masks_ok(gates)):
                raise status_error(library().PLANT_BAD_MASK)
            if n_e:
                p_gates = ffi.from_buffer("int[]", g)
        if volts is not None:
            volts = np.ascontiguousarray(volts, dtype=np.float64).reshape(n_e, 3)
            if n_e:
                p_volts = ffi.from_buffer("double[]", volts)
        adc = np.zeros((n_s, ADC_CHANNELS), dtype=np.int32)
        out = {"adc": adc[:, :3], "vdc": adc[:, ADC_VDC]}
        p_analog = p_truth = ffi.NULL
        if analog:
            a = np.zeros((n_s, ADC_CHANNELS))
            out["analog"], out["vdc_analog"] = a[:, :3], a[:, ADC_VDC]
            if n_s:
                p_analog = ffi.from_buffer("double[]", a)
        if truth:
            out["truth"] = tr = np.zeros(n_s, dtype=STATE_DTYPE)
            if n_s:
                p_truth = ffi.from_buffer("struct plant_state[]", tr)
        status = self._run(self._p, n_e, ffi.from_buffer("long long[]", edge_ticks) if n_e else ffi.NULL,
                           p_gates, p_volts, n_s, ffi.from_buffer("long long[]", sample_ticks) if n_s else ffi.NULL,
                           ffi.from_buffer("int[]", adc) if n_s else ffi.NULL, p_analog, p_truth)
        if status != 0:
            raise status_error(status)
        return out


def status_error(status: int) -> Exception:
    """The exception of a plant call's non-zero status, with the library's own message (``plant_status_text``:
    one wording for every binding); a shoot-through is a :class:`ShootThroughError`."""
    lib = library()
    text = ffi.string(lib.plant_status_text(int(status))).decode()
    return (ShootThroughError if status == lib.PLANT_SHOOT_THROUGH else PlantError)(text)


def _masks_ok(gates) -> bool:
    """Every value of ``gates`` is in 0..63 (checked on the caller's values, before a conversion to
    int32 could wrap them; plant_run checks the converted masks)."""
    g = np.asarray(gates)
    return g.size == 0 or bool(g.min() >= 0 and g.max() <= 63)


def mag_eval(mag: dict, psi_d: float, psi_q: float) -> np.ndarray:
    """Magnetic model: ``[i_d, i_q, di_d/dpsi_d, di_d/dpsi_q, di_q/dpsi_d, di_q/dpsi_q]``."""
    keep: list = []
    m = ffi.new("struct mag_params *")
    _fill(m[0], mag, keep, "mag.")
    out = ffi.new("double[6]")
    library().plant_mag_eval(m, float(psi_d), float(psi_q), out)
    return np.array(list(out))
