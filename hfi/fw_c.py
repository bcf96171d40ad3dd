"""cffi access to the host build of the firmware's control algorithms (``firmware/src/control.c``).

:func:`load` builds the shared library with ``make -C firmware host`` (make rebuilds it only when
``control.c`` or a header changed) and returns the cffi pair ``(ffi, lib)``. cffi parses
``firmware/src/control.h`` itself (its preprocessor lines stripped), so the header is the only place the
struct layouts and prototypes are written.

The converters map the golden objects of :mod:`golden.firmware` and :mod:`golden.fpga.demodulator` to
the C structs and back, field by field under the same names. cffi raises ``OverflowError`` when a
golden value does not fit its C field (e.g. an unbounded Python int beyond the C type).

The identification program (``FirmwareParams.ident``, the executor ``Firmware.ident``) is not part of
``struct fw_params`` / ``struct fw_state``: it sits in a ``struct fw_ident`` that ``fw_state.ident`` points to
(NULL: none; control.h). :func:`new_state` and :func:`state_to_c` allocate that block and keep it alive as long
as the state object (:data:`_IDENT_BLOCKS`).
"""

from __future__ import annotations

import fcntl
import functools
import subprocess
import weakref
from dataclasses import fields as dataclass_fields, is_dataclass, replace
from pathlib import Path

import cffi

from golden.firmware.biquad import BiquadState
from golden.firmware.ident import IDENT_MAX, Ident, IdentParams
from golden.firmware.pi import PiParams
from golden.firmware.pll import PllState
from golden.firmware.supervisor import Firmware, FirmwareParams, Outputs
from golden.fixed import uwrap
from golden.fpga.demodulator import WindowResult

ROOT = Path(__file__).resolve().parents[1]
HEADER = Path("firmware/src/control.h")
"""The interface of control.c, relative to the project root."""
LIBRARY = Path("out/firmware/host/libhfifw.so")
"""The host build (firmware/Makefile, target ``host``), relative to the project root."""

STATE_FIELDS = ("mode", "n", "theta_hat", "flipped", "speed_f", "speed_int", "id_int", "iq_int",
                "pol_pos", "pol_neg", "i_d", "i_q", "i_d_ref", "i_q_ref", "active", "offset", "speed_cnt", "i_s_ref", "i_s_cmd",
                "vec_before", "fault", "asc", "emf_d", "emf_q", "track_f", "ovl_n", "ovl_e", "e0", "hf_ref", "hf_f",
                "vdc_lo_n", "vdc_hi_n", "frz_a", "frz_b", "restarts",
                "lobs_w", "lobs_i", "wd_n")
"""Scalar fields shared by ``struct fw_state`` and :class:`~golden.firmware.supervisor.Firmware`
(besides the slot outputs ``est_theta``/``est_omega``, the output history ``act``/``prev`` and each
method's state block, named by the method's ``PARAMS``)."""
WINDOW_HOST_ONLY = ("wsum", "env_a", "env_b")
"""Fields of :class:`~golden.fpga.demodulator.WindowResult` that no estimator reads (``WSUM``; ``ENV_A``, ``ENV_B``:
diagnostics of the differencing block), so ``struct fw_window`` has no field for them."""
WINDOW_RESULT_FIELDS = tuple(f.name for f in dataclass_fields(WindowResult) if f.name not in WINDOW_HOST_ONLY)
"""Fields shared by ``struct fw_window`` and :class:`~golden.fpga.demodulator.WindowResult`, in the struct's
order (tests/test_fw_c.py checks both)."""
OUTPUT_FIELDS = ("v_d", "v_q", "v_h", "sin", "cos", "enable", "i_d_ref", "i_q_ref", "fcs_a1", "fcs_a2", "fcs_phi_min",
                 "fcs_constrain")
"""Fields shared by ``struct fw_outputs`` and :class:`~golden.firmware.supervisor.Outputs`."""
PI_FIELDS = ("kp", "sp", "ki", "si", "limit", "lim_i")
"""Fields shared by ``struct fw_pi_params`` and :class:`~golden.firmware.pi.PiParams`."""
IDENT_FIELDS = ("k", "n", "theta", "w", "theta_r", "kp", "ki", "lvl", "ref_d", "ref_q", "jump", "fit_x", "fit_y",
                "fit_y0", "failed", "done", "g2")
"""Scalar fields shared by ``struct fw_ident_state`` and :class:`~golden.firmware.ident.Ident` (besides its
per-step sum arrays, :data:`IDENT_ARRAYS`)."""
IDENT_ARRAYS = ("r_id", "r_iq", "r_vd", "r_vq", "r_gd", "r_gq")
"""The per-step sum arrays of ``struct fw_ident_state`` and :class:`~golden.firmware.ident.Ident` (IDENT_MAX each)."""


_IDENT_BLOCKS: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()
"""``struct fw_state *`` -> the ``struct fw_ident *`` its ``ident`` points to (made by :func:`new_state`,
:func:`state_to_c`, :func:`attach_ident`): the block lives as long as the state object."""


class FirmwareBuildError(RuntimeError):
    """``make -C firmware host`` failed; the message holds its output."""


def cdef_text(*headers: Path, drop: tuple[str, ...] = ()) -> str:
    """The C headers' text for ``cffi.FFI.cdef``: without preprocessor lines and the C++ linkage block
    (``extern "C" {`` and its closing line ``}``, which cffi cannot parse), and without the lines
    starting with one of ``drop`` (e.g. forward declarations cffi already has)."""
    lines = "\n".join(Path(h).read_text() for h in headers).splitlines()
    return "\n".join(line for line in lines if not line.lstrip().startswith("#") and not line.startswith(drop)
                     and line.strip() not in ('extern "C" {', "}"))


def header_cdef(root: Path = ROOT) -> str:
    """The text of ``control.h`` for cffi (:func:`cdef_text`)."""
    return cdef_text(root / HEADER)


def build(root: Path = ROOT) -> Path:
    """Run ``make -C <root>/firmware host`` and return the library's path.

    The make runs under an exclusive lock (``out/firmware/host/.build.lock``): parallel pytest workers
    must not relink the library while another one loads it. Raises FirmwareBuildError with make's output
    if the build fails.
    """
    out_dir = root / "out" / "firmware"
    cmd = ["make", "-C", str(root / "firmware"), "host", f"OUT={out_dir}"]
    (out_dir / "host").mkdir(parents=True, exist_ok=True)
    with open(out_dir / "host" / ".build.lock", "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        proc = subprocess.run(cmd, capture_output=True, text=True)
    if proc.returncode != 0:
        raise FirmwareBuildError(f"`{' '.join(cmd)}` failed (exit {proc.returncode}):\n"
                                 f"{proc.stdout}{proc.stderr}")
    return root / LIBRARY


@functools.lru_cache(maxsize=None)
def load(root: Path = ROOT) -> tuple[cffi.FFI, object]:
    """Build the host library if needed and return ``(ffi, lib)`` (cached per root)."""
    path = build(root)
    ffi = cffi.FFI()
    ffi.cdef(header_cdef(root))
    return ffi, ffi.dlopen(str(path))


# ---- golden -> C --------------------------------------------------------------------------------------
def _fill(c, obj) -> None:
    """Copy a frozen params dataclass into the C struct ``c`` field by field, by name (nested dataclasses
    into nested structs); the C struct is the layout, the dataclass the values. A derived field (``init=False``,
    such as ``PiParams.lim_i``) goes in when the struct has it."""
    for f in dataclass_fields(obj):
        if not f.init and f.name not in dir(c):
            continue
        v = getattr(obj, f.name)
        if is_dataclass(v):
            _fill(getattr(c, f.name), v)
        elif isinstance(v, tuple):
            getattr(c, f.name)[0:len(v)] = list(v)
        elif v is not None:
            setattr(c, f.name, v)


def pi_params_to_c(ffi: cffi.FFI, p: PiParams):
    """``struct fw_pi_params *`` holding ``p``."""
    c = ffi.new("struct fw_pi_params *")
    _fill(c, p)
    return c


def params_to_c(ffi: cffi.FFI, p: FirmwareParams):
    """``struct fw_params *`` holding ``p`` (a method's block stays zero when its field is None; nested
    dataclasses such as ``HfoParams.lut`` and tuples such as the tables go into their structs and arrays);
    ``fixed_enable = 1`` and ``fixed_angle = uwrap(angle, 32)`` for an open-loop test angle (as
    ``Firmware.__post_init__``), both 0 for ``fixed_angle=None``; ``fcs.len`` = ``len(fcs.t_d)`` (C only, as
    ``mtpa_len``). ``p.ident`` (the identification program) does not go here: it goes with the state
    (:func:`new_state`, ``struct fw_ident``)."""
    c = ffi.new("struct fw_params *")
    _fill(c, replace(p, fixed_angle=None, ident=None))
    c.fixed_enable = 0 if p.fixed_angle is None else 1
    c.fixed_angle = 0 if p.fixed_angle is None else uwrap(p.fixed_angle, 32)
    c.mtpa_len = len(p.mtpa_id)
    c.notch_on = 0 if p.notch is None else 1
    c.fcs.len = 0 if p.fcs is None else len(p.fcs.t_d)
    return c


def ident_to_c(ffi: cffi.FFI, ip: IdentParams):
    """``struct fw_ident *`` with the program ``ip`` in ``p`` (``n_steps`` too) and the executor's state ``s`` zero
    (``fw_init`` starts it)."""
    c = ffi.new("struct fw_ident *")
    _fill(c.p, ip)
    return c


def attach_ident(ffi: cffi.FFI, st, ip: IdentParams | None):
    """Point ``st.ident`` (a ``struct fw_state *``) at a new :func:`ident_to_c` block of ``ip``, kept alive with
    ``st``, or set it NULL for ``ip=None``; returns the block (or None)."""
    if ip is None:
        st.ident = ffi.NULL
        _IDENT_BLOCKS.pop(st, None)
        return None
    block = ident_to_c(ffi, ip)
    st.ident = block
    _IDENT_BLOCKS[st] = block
    return block


def new_state(ffi: cffi.FFI, p: FirmwareParams):
    """A zero ``struct fw_state *`` for ``fw_init(st, params_to_c(p))``: its ``ident`` points at a block holding
    ``p.ident`` (:func:`attach_ident`; NULL for ``ident=None``), so that fw_init starts the identification
    program as ``Firmware(p)`` does."""
    st = ffi.new("struct fw_state *")
    attach_ident(ffi, st, p.ident)
    return st


def window_to_c(ffi: cffi.FFI, w: WindowResult, c=None):
    """``struct fw_window *`` holding ``w`` (written into ``c`` if given, else a new struct)."""
    if c is None:
        c = ffi.new("struct fw_window *")
    for name in WINDOW_RESULT_FIELDS:
        setattr(c, name, getattr(w, name))
    return c


def pll_to_c(ffi: cffi.FFI, s: PllState):
    """``struct fw_pll *`` holding ``s``."""
    c = ffi.new("struct fw_pll *")
    c.theta, c.omega, c.integ = s.theta, s.omega, s.integ
    return c


def _outputs_into(c, o: Outputs) -> None:
    for name in OUTPUT_FIELDS:
        setattr(c, name, getattr(o, name))


def _estimator_into(c, est) -> None:
    """A golden estimator's state into its method's block: every attribute the block has, by name."""
    for name, v in vars(est).items():
        if name == "p" or not hasattr(c, name):
            continue
        if isinstance(v, PllState):
            c.pll.theta, c.pll.omega, c.pll.integ = v.theta, v.omega, v.integ
        elif isinstance(v, BiquadState):
            _biquad_into(getattr(c, name), v)
        elif isinstance(v, list):
            getattr(c, name)[0:len(v)] = v
        else:
            setattr(c, name, v)


def _biquad_into(c, s: BiquadState) -> None:
    c.x1, c.x2, c.y1, c.y2 = s.x1, s.x2, s.y1, s.y2


def _biquad_from(c) -> BiquadState:
    return BiquadState(c.x1, c.x2, c.y1, c.y2)


def state_to_c(ffi: cffi.FFI, fw: Firmware):
    """``struct fw_state *`` holding the state of ``fw`` (its parameters go by :func:`params_to_c`); with an
    executor (``fw.ident``) ``ident`` points at a block of its program and state (NULL for None)."""
    c = ffi.new("struct fw_state *")
    for name in STATE_FIELDS:
        setattr(c, name, getattr(fw, name))
    for k in range(2):
        c.est_theta[k], c.est_omega[k] = fw.est_theta[k], fw.est_omega[k]
    c.hist_at = 0                       # the output history's ring (control.h): act[0], act[1], prev from slot 0
    for k, out in enumerate((*fw.act, fw.prev)):
        _outputs_into(c.hist[k], out)
    _biquad_into(c.nd, fw.nd)
    _biquad_into(c.nq, fw.nq)
    for est in fw.slots:
        if est is not None:
            _estimator_into(getattr(c, est.PARAMS), est)
    block = attach_ident(ffi, c, None if fw.ident is None else fw.ident.p)
    if block is not None:
        for name in IDENT_FIELDS:
            setattr(block.s, name, getattr(fw.ident, name))
        for name in IDENT_ARRAYS:
            getattr(block.s, name)[0:IDENT_MAX] = getattr(fw.ident, name)
    return c


# ---- C -> golden --------------------------------------------------------------------------------------
def pll_from_c(c) -> PllState:
    """The :class:`PllState` held by a ``struct fw_pll``."""
    return PllState(theta=c.theta, integ=c.integ, omega=c.omega)


def outputs_from_c(c) -> Outputs:
    """The :class:`Outputs` held by a ``struct fw_outputs``."""
    return Outputs(*(getattr(c, name) for name in OUTPUT_FIELDS))


def ident_params_from_c(c) -> IdentParams:
    """The :class:`IdentParams` held by a ``struct fw_ident_params`` (its first ``n_steps`` steps)."""
    n = c.n_steps
    return IdentParams(**{f.name: tuple(getattr(c, f.name)[0:n]) if f.name.startswith("s_") else getattr(c, f.name)
                          for f in dataclass_fields(IdentParams) if f.init})


def state_from_c(c, p: FirmwareParams) -> Firmware:
    """A golden :class:`Firmware` with parameters ``p`` and the state held by a ``struct fw_state``; its executor
    from the block ``c.ident`` points to (None for NULL, whatever ``p.ident``; one with the block's program when
    ``p.ident`` is None)."""
    fw = Firmware(p)
    for name in STATE_FIELDS:
        setattr(fw, name, getattr(c, name))
    fw.est_theta = [c.est_theta[0], c.est_theta[1]]
    fw.est_omega = [c.est_omega[0], c.est_omega[1]]
    act0, act1, prev = (c.hist[(c.hist_at + k) % 3] for k in range(3))   # the ring (control.h)
    fw.act = [outputs_from_c(act0), outputs_from_c(act1)]
    fw.prev = outputs_from_c(prev)
    fw.nd, fw.nq = _biquad_from(c.nd), _biquad_from(c.nq)
    for est in fw.slots:
        if est is None:
            continue
        block = getattr(c, est.PARAMS)
        for name, v in list(vars(est).items()):
            if name == "p" or not hasattr(block, name):
                continue
            if isinstance(v, PllState):
                v = pll_from_c(block.pll)
            elif isinstance(v, BiquadState):
                v = _biquad_from(getattr(block, name))
            elif isinstance(v, list):
                v = list(getattr(block, name))[:len(v)]
            else:
                v = getattr(block, name)
            setattr(est, name, v)
    # NULL: no executor; otherwise its state from the block
    fw.ident = None if not c.ident else ident_from_c(c.ident, fw.ident.p if fw.ident is not None else None)
    return fw


def ident_from_c(c, ip: IdentParams | None = None) -> Ident:
    """A golden :class:`Ident` with the executor's state held by a ``struct fw_ident`` ``c`` (its ``s``, by name);
    its program ``ip``, or the block's own (:func:`ident_params_from_c`) for None."""
    ident = Ident(ident_params_from_c(c.p) if ip is None else ip)
    s = c.s
    for name in IDENT_FIELDS:
        setattr(ident, name, getattr(s, name))
    for name in IDENT_ARRAYS:
        setattr(ident, name, list(getattr(s, name)))
    return ident
