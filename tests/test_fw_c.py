"""The firmware's C control algorithms (firmware/src/control.c, host build) equal the golden model bit for bit.

Every C function is called once per input through cffi (hfi/fw_c.py) and compared with its golden
twin of golden/firmware/ (and golden.fpga.cordic.sincos_q15): at least 100 000 random inputs each, drawn
over the full legal ranges of the golden docstrings with the extremes and the saturating cases frequent,
plus directed corner cases. fw_step is compared with Firmware.step on random parameter sets and window
sequences that visit every supervisor state, every state field and every output after every step.

Random inputs: ``numpy.random.default_rng(seed + k)`` (k fixed per test); the seed is ``HFI_SEED`` if
set, else a fresh one, and it is printed (replay: ``HFI_SEED=<seed> .venv/bin/python -m pytest ...``).
"""

from __future__ import annotations

import functools
import gc
import shutil
import typing
from dataclasses import fields as dataclass_fields, replace
from pathlib import Path

import numpy as np
import pytest

from golden.firmware import mtpa, rot_bpf
from golden.firmware.bangbang import bangbang_step
from golden.firmware.biquad import BiquadCoef, BiquadState, biquad_step
from golden.firmware.dc_feedforward import dc_feedforward
from golden.firmware.eemf_smo import SmoParams
from golden.control_config import firmware_params
from golden.firmware.estimator import (METHOD_EEMF_SMO, METHOD_HFO_PROJ, METHOD_RFO, METHOD_ROT_BPF,
                                       METHOD_SQW_BANGBANG, METHOD_SQW_CIC, METHODS, SLOT_HIGH, SLOT_LOW, Measurement,
                                       injection_voltage)
from golden.firmware import flux_lut as flux_lut_mod
from golden.firmware.applied_flux import applied_flux
from golden.firmware.fcs_law import LAW_FCS_MPC, LAW_FOC_PWM, FcsParams, deadbeat_voltage, flux_reference
from golden.firmware.flux_lut import LUT_MAX_POINTS, FluxLut, lut_flux, lut_point, warp
from golden.firmware.hfo_proj import HfoParams, HybridFluxProjection, projection_coefficients
from golden.firmware import ident as ident_mod
from golden.firmware.ident import IDENT_MAX, Ident, IdentParams
from golden.fpga.fcs_mpc import state_voltage
from golden.firmware.methods import CLASSES
from golden.firmware.lowpass import lowpass_out, lowpass_step
from golden.firmware.means import window_means
from golden.firmware.pi import PiParams, pi_step
from golden.firmware.pll import PllState, pll_step
from golden.firmware import protection
from golden.firmware.protection import FAULT_NAMES, ProtParams, emf_residual, protect_step
from golden.firmware.rfo import Q_LIMIT, RfoParams
from golden.firmware.rot_bpf import RotParams
from golden.firmware.sqw_bangbang import SqwParams
from golden.firmware.sqw_cic import CicParams, SquareWaveCic
from golden.firmware.load_observer import LoadObsParams
from golden.firmware.vector import vector_angle
from golden.firmware.supervisor import (MODE_CATCH, MODE_CONVERGE, MODE_DONE, MODE_FAULT, MODE_FIXED, MODE_IDENT, MODE_NAMES,
                                        MODE_POL_NEG, MODE_POL_POS, MODE_RELAX, MODE_RUN, POL_CURRENT, POL_NONE, POL_PILOT, Firmware,
                                        FirmwareParams, Outputs)
from golden.fixed import c_div, sat, uwrap
from golden.fpga.cordic import sincos_q15
from golden.fpga.demodulator import WindowResult
from golden.scenario import load_scenario
from hfi import fw_c

S32_MIN, S32_MAX = -(1 << 31), (1 << 31) - 1
S64_MIN, S64_MAX = -(1 << 63), (1 << 63) - 1
U16_MAX, U32_MAX = (1 << 16) - 1, (1 << 32) - 1
S16_MIN, S16_MAX = -(1 << 15), (1 << 15) - 1
F_MIN, F_MAX = -(1 << 47), (1 << 47) - 1        # speed-filter state: shr(F, 16) in s32
N_RANDOM = 100_000
METHODS_BY_ID = tuple(sorted(m.method for m in METHODS.values()))
LOW_METHODS = tuple(sorted(m.method for m in METHODS.values() if SLOT_LOW in m.slots))
HIGH_METHODS = tuple(sorted(m.method for m in METHODS.values() if SLOT_HIGH in m.slots))
S21_MIN, S21_MAX = -(1 << 20), (1 << 20) - 1     # CIC_QA, CIC_QB (golden.fpga.diff_cic)
CIC_CT_MAX, CIC_CR_MAX = 1 << 46, 1 << 32        # |c_t|, |c_r| (control.h, struct fw_cic_params)
ROOT = Path(__file__).resolve().parents[1]

ffi, lib = fw_c.load()


def draw_array(rng: np.random.Generator, n: int, lo: int, hi: int, specials=()) -> np.ndarray:
    """``n`` ints in ``lo..hi`` (within int64), int64 array: 40 % uniform, 40 % of log-uniform magnitude
    with a random sign (clipped to the range), 20 % from the extremes ``lo, lo+1, -1, 0, 1, hi-1, hi`` and
    ``specials`` (those inside the range)."""
    uniform = rng.integers(lo, hi, size=n, endpoint=True, dtype=np.int64)
    shift = rng.integers(1, 64, size=n)
    mag = rng.integers(0, S64_MAX, size=n, endpoint=True, dtype=np.int64) >> shift
    logu = np.clip(np.where(rng.random(n) < 0.5, -mag, mag), lo, hi)
    pool = np.array(sorted({v for v in (lo, lo + 1, -1, 0, 1, hi - 1, hi, *specials) if lo <= v <= hi}),
                    dtype=np.int64)
    extreme = rng.choice(pool, size=n)
    kind = rng.random(n)
    return np.where(kind < 0.4, uniform, np.where(kind < 0.8, logu, extreme))


def draw(rng: np.random.Generator, n: int, lo: int, hi: int, specials=()) -> list[int]:
    """:func:`draw_array` as Python ints."""
    return draw_array(rng, n, lo, hi, specials).tolist()


def draw_one(rng: np.random.Generator, lo: int, hi: int, specials=()) -> int:
    return draw(rng, 1, lo, hi, specials)[0]


def random_pi(rng: np.random.Generator) -> PiParams:
    """A valid PiParams (golden.firmware.pi.PiParams ranges), gains and limit of any magnitude."""
    kp, ki, limit = draw(rng, 3, 0, S32_MAX, (1 << 16, 1 << 24))
    sp, si = (int(v) for v in rng.integers(0, 31, size=2, endpoint=True))
    return PiParams(kp=kp, sp=sp, ki=ki, si=si, limit=max(limit, 1))


# ---- build and header ---------------------------------------------------------------------------------
def test_header_parsed_and_modes_match_golden():
    """cffi parsed control.h: the enum equals the golden MODE_* constants."""
    c_modes = [lib.FW_CONVERGE, lib.FW_POL_POS, lib.FW_POL_NEG, lib.FW_RELAX, lib.FW_RUN, lib.FW_FIXED,
               lib.FW_FAULT, lib.FW_IDENT, lib.FW_DONE, lib.FW_CATCH]
    assert c_modes == [MODE_CONVERGE, MODE_POL_POS, MODE_POL_NEG, MODE_RELAX, MODE_RUN, MODE_FIXED, MODE_FAULT,
                       MODE_IDENT, MODE_DONE, MODE_CATCH]
    assert len(MODE_NAMES) == len(c_modes)
    assert "#" not in fw_c.header_cdef()


def test_fault_codes_and_names_match_golden():
    """enum fw_fault and fw_fault_name equal golden.firmware.protection's FAULT_* and FAULT_NAMES."""
    codes = {name: getattr(protection, name) for name in dir(protection) if name.startswith("FAULT_")
             and isinstance(getattr(protection, name), int)}
    assert {name: getattr(lib, "FW_" + name) for name in codes} == codes
    assert lib.FW_FAULTS == len(FAULT_NAMES) == len(codes)
    assert [ffi.string(lib.fw_fault_name(k)).decode() for k in range(-1, len(FAULT_NAMES) + 1)] == \
        ["?", *FAULT_NAMES, "?"]


def test_method_ids_and_slots_match_golden():
    """enum fw_method / fw_slot equal golden.firmware.estimator's ids; every registered method has a C entry."""
    assert (lib.FW_METHOD_SQW_BANGBANG, lib.FW_METHOD_RFO) == (METHOD_SQW_BANGBANG, METHOD_RFO)
    assert {name: getattr(lib, f"FW_METHOD_{name.upper()}") for name in METHODS} == \
        {name: m.method for name, m in METHODS.items()}
    assert lib.FW_METHOD_SQW_CIC == METHOD_SQW_CIC
    assert lib.FW_METHOD_HFO_PROJ == METHOD_HFO_PROJ
    assert set(LOW_METHODS) == {METHOD_SQW_BANGBANG, METHOD_ROT_BPF, METHOD_SQW_CIC, METHOD_HFO_PROJ}, LOW_METHODS
    assert (lib.FW_POL_CURRENT, lib.FW_POL_PILOT, lib.FW_POL_NONE) == (POL_CURRENT, POL_PILOT, POL_NONE)
    assert (lib.FW_LAW_FOC_PWM, lib.FW_LAW_FCS_MPC) == (LAW_FOC_PWM, LAW_FCS_MPC)
    assert set(HIGH_METHODS) == {METHOD_RFO, METHOD_EEMF_SMO}, HIGH_METHODS
    assert (lib.FW_SLOT_LOW, lib.FW_SLOT_HIGH) == (SLOT_LOW, SLOT_HIGH)
    assert lib.FW_METHODS == 1 + max(m.method for m in METHODS.values())


def test_blocks_match_golden_fields():
    """hfi/fw_c.py converts by field name: each method's struct fw_<field>_params has its params dataclass's
    fields in their order, struct fw_cic_state the attributes of SquareWaveCic, struct fw_window the shared
    fields of WindowResult (all but the host-only ENV_A/B)."""
    hints = typing.get_type_hints(FirmwareParams)
    for cls in CLASSES.values():
        params = next(t for t in typing.get_args(hints[cls.PARAMS]) if t is not type(None))
        c_fields = [name for name, _ in ffi.typeof(f"struct fw_{cls.PARAMS}_params").fields]
        assert c_fields == [f.name for f in dataclass_fields(params)], cls
    p = CicParams(*range(1, 10))
    assert [name for name, _ in ffi.typeof("struct fw_cic_state").fields] == \
        [k for k in vars(SquareWaveCic(p)) if k != "p"]
    assert [name for name, _ in ffi.typeof("struct fw_window").fields] == list(fw_c.WINDOW_RESULT_FIELDS)
    assert {f.name for f in dataclass_fields(WindowResult)} - set(fw_c.WINDOW_RESULT_FIELDS) == \
        set(fw_c.WINDOW_HOST_ONLY)
    cic = dict(ffi.typeof("struct fw_cic_params").fields)
    assert cic["c_t"].type.cname == cic["c_r"].type.cname == "int64_t"
    # the 003 method: its state (every attribute of HybridFluxProjection), the LUT, the law's parameters
    assert [name for name, _ in ffi.typeof("struct fw_hfo_state").fields] == \
        [k for k in vars(HybridFluxProjection(_hfo_host())) if k != "p"]
    assert [name for name, _ in ffi.typeof("struct fw_flux_lut").fields] == [f.name for f in dataclass_fields(FluxLut)]
    assert [name for name, _ in ffi.typeof("struct fw_lut_point").fields] == \
        [f.name for f in dataclass_fields(flux_lut_mod.LutPoint)]
    assert [name for name, _ in ffi.typeof("struct fw_fcs_params").fields] == \
        [f.name for f in dataclass_fields(FcsParams)] + ["len"]
    lut = dict(ffi.typeof("struct fw_flux_lut").fields)
    assert {lut[t].type.length for t in ("t_d", "t_q", "t_ld", "t_lq", "t_ldq")} == {LUT_MAX_POINTS}
    assert [lut[t].type.item.cname for t in ("t_d", "t_q", "t_ld", "t_lq", "t_ldq")] == \
        ["int16_t"] * 2 + ["int32_t"] * 3
    fcs = dict(ffi.typeof("struct fw_fcs_params").fields)
    assert fcs["t_d"].type.length == fcs["t_q"].type.length == mtpa.MTPA_LEN
    assert [name for name, _ in ffi.typeof("struct fw_outputs").fields] == list(fw_c.OUTPUT_FIELDS) == \
        [f.name for f in dataclass_fields(Outputs)]
    assert set(fw_c.STATE_FIELDS) <= {f.name for f in dataclass_fields(Firmware)}
    assert "vec_before" in fw_c.STATE_FIELDS
    # the identification program: outside fw_params / fw_state (the RISC-V image's RAM, control.h), in a struct
    # fw_ident the state points to (NULL: none); its parameters and the executor's state, field by field under
    # the golden names
    params_fields, state_fields = dict(ffi.typeof("struct fw_params").fields), dict(ffi.typeof("struct fw_state").fields)
    assert not {"ident", "ident_on"} & set(params_fields)
    assert state_fields["ident"].type.kind == "pointer" and state_fields["ident"].type.item.cname == "struct fw_ident"
    assert list(state_fields)[-1] == "ident"
    assert [(name, f.type.cname) for name, f in ffi.typeof("struct fw_ident").fields] == \
        [("p", "struct fw_ident_params"), ("s", "struct fw_ident_state")]
    assert [name for name, _ in ffi.typeof("struct fw_ident_params").fields] == \
        [f.name for f in dataclass_fields(IdentParams)]
    assert [name for name, _ in ffi.typeof("struct fw_ident_state").fields] == \
        [f.name for f in dataclass_fields(Ident) if f.name != "p"]
    assert sorted(name for name, _ in ffi.typeof("struct fw_ident_state").fields) == \
        sorted([*fw_c.IDENT_FIELDS, *fw_c.IDENT_ARRAYS])
    ip, ist = dict(ffi.typeof("struct fw_ident_params").fields), dict(ffi.typeof("struct fw_ident_state").fields)
    assert {ip[n].type.length for n in ("s_n", "s_m", "s_id", "s_iq", "s_vh", "s_phi", "s_dw", "s_flags")} == \
        {ist[n].type.length for n in fw_c.IDENT_ARRAYS} == {IDENT_MAX}
    assert ip["s_phi"].type.item.cname == "uint32_t"
    assert ip["c_kp"].type.cname == ip["c_lvl"].type.cname == ip["c_gain"].type.cname == "int64_t"
    # the s16 means sum in s32 over at most M_MAX windows, the responses in s64
    assert {n: ist[n].type.item.cname for n in fw_c.IDENT_ARRAYS} == \
        {"r_id": "int32_t", "r_iq": "int32_t", "r_vd": "int32_t", "r_vq": "int32_t", "r_gd": "int64_t", "r_gq": "int64_t"}
    assert {n: ist[n].type.cname for n in ("theta", "theta_r", "fit_x", "fit_y", "fit_y0", "g2")} == \
        {"theta": "uint32_t", "theta_r": "uint32_t", "fit_x": "int64_t", "fit_y": "int64_t", "fit_y0": "int64_t",
         "g2": "int64_t"}


def test_build_failure_reports_make_output(tmp_path):
    """A copy of the firmware tree with a broken control.c: build() raises with the compiler's message."""
    shutil.copytree(fw_c.ROOT / "firmware", tmp_path / "firmware")
    src = tmp_path / "firmware" / "src" / "control.c"
    src.write_text(src.read_text() + "\nint fw_broken(void) { return undeclared_name; }\n")
    with pytest.raises(fw_c.FirmwareBuildError) as err:
        fw_c.build(tmp_path)
    assert "undeclared_name" in str(err.value)
    assert not (tmp_path / fw_c.LIBRARY).exists()


# ---- window means ---------------------------------------------------------------------------------------
def _c_means(sum_id: int, sum_iq: int, n: int, out, div=None) -> tuple[int, int]:
    """fw_window_means with a fresh divisor (its magic number computed for n), or with ``div`` kept from the
    calls before (recomputed only when n changes)."""
    lib.fw_window_means(ffi.new("struct fw_divisor *") if div is None else div, sum_id, sum_iq, n, out[0], out[1])
    return out[0][0], out[1][0]


def _out_pair():
    return ffi.new("int32_t *"), ffi.new("int32_t *")


def test_window_means_random(seed):
    rng = np.random.default_rng(seed + 1)
    sid = draw(rng, N_RANDOM, S32_MIN, S32_MAX)
    n = draw(rng, N_RANDOM, 0, U16_MAX, (2, 3, 7))
    small = draw(rng, N_RANDOM, -(1 << 30) + 1, (1 << 30) - 1)     # the multiply's range (control.c, div_by)
    out, div = _out_pair(), ffi.new("struct fw_divisor *")
    for k in range(N_RANDOM):
        got = _c_means(sid[k], small[k], n[k], out, div if k % 2 else None)
        assert got == window_means(sid[k], small[k], n[k]), (seed, sid[k], small[k], n[k], got)
    assert n.count(0) > 1000


def test_window_means_every_divisor():
    """The magic number of every N against golden's c_div, at the edges of the multiply's range (|x| < 2^30), at
    multiples of N and one off them (where a magic number one too small or too large shows first), and on both
    sides of the switch to the core's divide."""
    div, out = ffi.new("struct fw_divisor *"), _out_pair()
    edge = (1 << 30) - 1
    for n in range(0, U16_MAX + 1):
        k = edge // n if n else 0
        for x in (edge, -edge, k * n, -k * n, k * n - 1, 1 - k * n, n, -n, n - 1, 1 - n, 1 << 30, -(1 << 30)):
            assert _c_means(x, -x, n, out, div) == window_means(x, -x, n), (x, n)


@pytest.mark.parametrize("sum_id, sum_iq, n", [
    (-7, 7, 2), (-1, 1, 2), (-3, 3, 2), (S32_MIN, S32_MAX, 2), (-65535, 65534, 65535), (S32_MIN, S32_MAX, 1),
    (S32_MIN, S32_MAX, 3),
    (S32_MIN, -1, U16_MAX), (123, -456, 0), (S32_MIN, S32_MAX, 0)])
def test_window_means_corners(sum_id, sum_iq, n):
    """Truncation toward zero of negative sums, n = 0, the s32 extremes."""
    assert _c_means(sum_id, sum_iq, n, _out_pair()) == window_means(sum_id, sum_iq, n)


# ---- bang-bang --------------------------------------------------------------------------------------------
def _rfo_correction(psi_f: int, mag: int) -> int:
    """golden.firmware.rfo step 5 (the same expression as RotorFluxObserver.step)."""
    q = c_div((psi_f - mag) << 16, mag if mag > 0 else 1)
    return Q_LIMIT if q > Q_LIMIT else -Q_LIMIT if q < -Q_LIMIT else q


def test_rfo_correction_random(seed):
    """The observer's normalised correction without a 64-bit division (control.c) equals the golden
    expression: random psi_f and |eta| over their ranges, both near each other (the unclamped quotients)."""
    _, lib = fw_c.load()
    rng = np.random.default_rng(seed)
    psi = rng.integers(0, 2**27 + 1, size=30_000)
    mag = np.concatenate([rng.integers(0, 2**31, size=10_000),
                          np.clip(psi[10_000:] + rng.integers(-2**12, 2**12, size=20_000) * (psi[10_000:] >> 16), 0, 2**31 - 1)])
    unclamped = 0
    for p, m in zip(psi.tolist(), mag.tolist()):
        want = _rfo_correction(p, m)
        unclamped += abs(want) < Q_LIMIT
        assert lib.fw_rfo_correction(p, m) == want, (p, m)
    assert unclamped > 10_000


@pytest.mark.parametrize("psi_f, mag", [(0, 0), (1, 0), (0, 1), (2**27, 0), (2**27, 2**31 - 1), (2**27, 2**27),
                                        (3, 1), (2, 1), (131071, 65536), (131072, 65536), (65537, 65536),
                                        (0, -5), (2**27, -(2**31))])
def test_rfo_correction_corners(psi_f, mag):
    """Clamp edges (quotients of exactly 2^17 and 2^17 + 1), a zero magnitude and, off the range, negative."""
    _, lib = fw_c.load()
    assert lib.fw_rfo_correction(psi_f, mag) == _rfo_correction(psi_f, mag)


# ---- the 64-bit saturated division (the 003 observer's quotients) ------------------------------------------
SAT_DIV_BITS = (16, 18, 21, 22)
"""The widths fw_sat_div64 is used with (control.c: the projection's coefficients, the fusion weight, the
low-speed and APP errors)."""


def _sat_div_cases(rng, n_cases: int, bits: int) -> list[tuple[int, int]]:
    """Random (n, d) with |n|, |d| < 2^62: divisors of every size, numerators that give quotients on both sides of
    the saturation limit 2^(bits-1), near multiples of d (one off them) and at the limit itself."""
    lim = 1 << (bits - 1)
    out = []
    for _ in range(n_cases):
        d = int(rng.integers(1, 1 << int(rng.integers(1, 62))))
        kind = int(rng.integers(0, 4))
        if kind == 0:          # anything
            n = int(rng.integers(-(1 << 62) + 1, 1 << 62))
        elif kind == 1:        # an unsaturated quotient
            n = int(rng.integers(0, lim)) * d + int(rng.integers(0, d))
        elif kind == 2:        # at a multiple, one off it
            n = int(rng.integers(0, lim + 2)) * d + int(rng.integers(-1, 2))
        else:                  # around the limit
            n = lim * d + int(rng.integers(-2 * d, 2 * d + 1))
        n = max(min(n, (1 << 62) - 1), 0)
        out.append((-n if rng.integers(0, 2) else n, -d if rng.integers(0, 2) else d))
    return out


@pytest.mark.parametrize("bits", SAT_DIV_BITS)
def test_sat_div64_random(seed, bits):
    """fw_sat_div64(n, d, bits) = golden's sat(c_div(n, d), bits) (truncation toward zero, then saturation), over
    random operands of every size and sign, quotients below, at and beyond the limit."""
    _, lib = fw_c.load()
    rng = np.random.default_rng(seed + 71 + bits)
    saturated = 0
    for n, d in _sat_div_cases(rng, N_RANDOM // 4, bits):
        want = sat(c_div(n, d), bits)
        saturated += abs(want) >= (1 << (bits - 1)) - 1
        assert lib.fw_sat_div64(n, d, bits) == want, (n, d, bits)
    assert N_RANDOM // 40 < saturated < N_RANDOM // 4 - N_RANDOM // 40


@pytest.mark.parametrize("n, d", [(0, 1), (0, -7), (1, 1), (-1, 1), (1, -1), (5, 3), (-5, 3), (5, -3), (-5, -3),
                                  ((1 << 62) - 1, 1), (-(1 << 62) + 1, 1), ((1 << 62) - 1, (1 << 62) - 1),
                                  ((1 << 62) - 1, (1 << 61) + 1), (1 << 40, (1 << 40) + 1), (3 << 30, 1 << 31),
                                  ((1 << 61) - 1, (1 << 41) - 1), ((1 << 61) - 1, 1 << 41)])
@pytest.mark.parametrize("bits", SAT_DIV_BITS)
def test_sat_div64_corners(n, d, bits):
    """Zero, signs, the largest operands, divisors just above a power of two (the rounded-up digit divisor), and
    quotients at exactly 2^(bits-1) and one below."""
    _, lib = fw_c.load()
    lim = 1 << (bits - 1)
    for nn, dd in ((n, d), (lim * d, d), (lim * d - 1, d), (-lim * d, d), (-lim * d + 1, d), ((lim - 1) * d, -d)):
        if abs(nn) < 1 << 63:
            assert lib.fw_sat_div64(nn, dd, bits) == sat(c_div(nn, dd), bits), (nn, dd, bits)


def test_bangbang_random(seed):
    rng = np.random.default_rng(seed + 2)
    theta = draw(rng, N_RANDOM, 0, U32_MAX)
    gamma = draw(rng, N_RANDOM, S32_MIN, S32_MAX)
    k_bb = draw(rng, N_RANDOM, 0, U32_MAX, (27_342_611, 1 << 31))
    step = lib.fw_bangbang_step
    for k in range(N_RANDOM):
        assert step(theta[k], gamma[k], k_bb[k]) == bangbang_step(theta[k], gamma[k], k_bb[k]), \
            (seed, theta[k], gamma[k], k_bb[k])
    assert gamma.count(0) > 1000


@pytest.mark.parametrize("theta, gamma, k_bb", [
    (U32_MAX, 1, 1), (0, -1, 1), (U32_MAX - 5, S32_MAX, 27_342_611), (3, S32_MIN, 27_342_611), (77, 0, 5)])
def test_bangbang_wrap(theta, gamma, k_bb):
    """The angle wraps at 0 / 2^32 both ways; gamma == 0 leaves it."""
    assert lib.fw_bangbang_step(theta, gamma, k_bb) == bangbang_step(theta, gamma, k_bb)


# ---- PLL ------------------------------------------------------------------------------------------------------
def _c_pll(s: PllState, theta_hat: int, kp: int, ki: int, c=None) -> PllState:
    c = fw_c.pll_to_c(ffi, s) if c is None else c
    c.theta, c.omega, c.integ = s.theta, s.omega, s.integ
    lib.fw_pll_step(c, theta_hat, kp, ki)
    return fw_c.pll_from_c(c)


def test_pll_random(seed):
    rng = np.random.default_rng(seed + 3)
    theta = draw(rng, N_RANDOM, 0, U32_MAX)
    integ = draw(rng, N_RANDOM, S64_MIN, S64_MAX, (S64_MAX - (1 << 40), S64_MIN + (1 << 40)))
    omega = draw(rng, N_RANDOM, S32_MIN, S32_MAX)
    theta_hat = draw(rng, N_RANDOM, 0, U32_MAX)
    kp = draw(rng, N_RANDOM, 0, S32_MAX, (2621,))
    ki = draw(rng, N_RANDOM, 0, S32_MAX, (6711,))
    c = ffi.new("struct fw_pll *")
    sat_integ = sat_omega = 0
    for k in range(N_RANDOM):
        s = PllState(theta[k], integ[k], omega[k])
        want = pll_step(s, theta_hat[k], kp[k], ki[k])
        got = _c_pll(s, theta_hat[k], kp[k], ki[k], c)
        assert got == want, (seed, s, theta_hat[k], kp[k], ki[k], got, want)
        sat_integ += want.integ in (S64_MIN, S64_MAX)
        sat_omega += want.omega in (S32_MIN, S32_MAX)
    assert sat_integ > 1000 and sat_omega > 1000, (sat_integ, sat_omega)


@pytest.mark.parametrize("state, theta_hat, kp, ki, field, value", [
    (PllState(0, S64_MAX - 5, 0), 1000, 0, 1, "integ", S64_MAX),              # saturates up
    (PllState(1000, S64_MIN + 5, 0), 0, 0, 1, "integ", S64_MIN),              # saturates down
    (PllState(0, S64_MAX, 0), S32_MAX, S32_MAX, S32_MAX, "integ", S64_MAX),   # stays saturated
    (PllState(0, S64_MIN, 0), 1 << 31, S32_MAX, S32_MAX, "integ", S64_MIN),   # e = INT32_MIN
    (PllState(0, 0, 0), S32_MAX, S32_MAX, 0, "omega", S32_MAX),
    (PllState(1 << 31, 0, 0), 0, S32_MAX, 0, "omega", S32_MIN),
    (PllState(U32_MAX, 0, 0), 0, 1 << 16, 0, "theta", 0),                     # e = +1: 2^32 -> 0
    (PllState(0, 0, 0), U32_MAX, 1 << 16, 0, "theta", U32_MAX),               # e = -1: 0 -> 2^32 - 1
])
def test_pll_corners(state, theta_hat, kp, ki, field, value):
    """int64 integrator saturation at INT64_MAX/MIN, omega saturation, the angle wrap at 0 / 2^32."""
    want = pll_step(state, theta_hat, kp, ki)
    assert _c_pll(state, theta_hat, kp, ki) == want
    assert getattr(want, field) == value, want     # the case really reaches its corner


# ---- fault checks ------------------------------------------------------------------------------------------
def test_emf_residual_random(seed):
    rng = np.random.default_rng(seed + 40)
    c = ffi.new("struct fw_prot_params *")
    e_d, e_q = ffi.new("int32_t *"), ffi.new("int32_t *")
    for k in range(N_RANDOM // 10):
        p = random_prot(rng)
        fw_c._fill(c, p)
        v_d, v_q, i_d, i_q, w = draw(rng, 5, S32_MIN, S32_MAX, (0, 1, -1))
        lib.fw_emf_residual(c, v_d, v_q, i_d, i_q, w, e_d, e_q)
        assert (e_d[0], e_q[0]) == emf_residual(p, v_d, v_q, i_d, i_q, w), (seed, k, p, v_d, v_q, i_d, i_q, w)


def test_slip_check_random_sequences(seed):
    """The slip check (protection.slip_check) over sequences: the slots' gap around 45 and 90 deg and at half a turn,
    speeds of either sign around the arming speed, the high slot in charge now and then; the state and the code
    equal at every period, and the check both trips and holds back."""
    rng = np.random.default_rng(seed + 43)
    c, st = ffi.new("struct fw_prot_params *"), ffi.new("struct fw_state *")
    seen = set()
    edges = (0, protection.SLIP_AGREE - 1, protection.SLIP_AGREE, protection.SLIP_TRIP, protection.SLIP_TRIP + 1,
             -protection.SLIP_AGREE, -protection.SLIP_TRIP - 1, S32_MIN, S32_MAX)
    for q in range(N_RANDOM // 200):
        p = random_prot(rng)
        fw_c._fill(c, p)
        gold = Firmware(_params())
        st.slip_left = gold.slip_left = 0
        for k in range(30):
            low = int(rng.random() < 0.9)
            gap = draw_one(rng, S32_MIN, S32_MAX, edges)
            near = [max(min(v, S32_MAX), S32_MIN) for v in (-p.slip_w - 2, p.slip_w + 2, p.slip_w + 1, -p.slip_w - 1)]
            w_f, w_hi = (draw_one(rng, near[0], near[1], (0, p.slip_w, near[2], near[3]))
                         if rng.random() < 0.5 else draw_one(rng, S32_MIN, S32_MAX) for _ in range(2))
            want = protection.slip_check(gold, p, bool(low), gap, w_f, w_hi)
            got = lib.fw_slip_check(st, c, low, gap, w_f, w_hi)
            assert (got, st.slip_left) == (want, gold.slip_left), (seed, q, k, p, low, gap, w_f, w_hi)
            seen.add((want, gold.slip_left > 0))
    assert {(protection.FAULT_LOCK_LOSS, True), (protection.FAULT_NONE, True), (protection.FAULT_NONE, False)} <= seen


def test_protect_step_random_sequences(seed):
    """Sequences of checks with one parameter set each, the HF response check's reference learned over a few periods
    first (``hf_learn``); every fault code is reached."""
    rng = np.random.default_rng(seed + 41)
    c, st = ffi.new("struct fw_prot_params *"), ffi.new("struct fw_state *")
    seen = set()
    for q in range(N_RANDOM // 200):
        p = random_prot(rng)
        fw_c._fill(c, p)
        gold = Firmware(_params())
        st.emf_d = st.emf_q = st.track_f = st.ovl_n = st.ovl_e = st.e0 = st.hf_ref = st.hf_f = 0
        st.ld_w = st.ld_n = st.ld_f = 0
        at_limit = rng.random() < 0.5
        level = draw_one(rng, S32_MIN >> (q % 20), S32_MAX >> (q % 20), (1_786_000, 0))   # a GAMMA_D level
        for k in range(int(rng.integers(0, 6))):
            g = max(min(level + int(rng.integers(-1000, 1001)), S32_MAX), S32_MIN)
            protection.hf_learn(gold, p, g)
            lib.fw_hf_learn(st, c, g)
            assert st.hf_ref == gold.hf_ref, (seed, q, k, p)
        for k in range(20):
            v_d, v_q, i_d, i_q, i_dr, i_qr, w, ref = draw(rng, 8, S32_MIN >> (q % 20), S32_MAX >> (q % 20))
            limit = int(at_limit or rng.random() < 0.1)
            hf_on = int(rng.random() < 0.8)
            hf = level + draw_one(rng, S32_MIN >> (q % 20 + 3), S32_MAX >> (q % 20 + 3), (0, 200_000))
            hf = max(min(hf, S32_MAX), S32_MIN)
            want = protect_step(gold, p, v_d, v_q, i_d, i_q, i_dr, i_qr, w, ref, bool(limit), hf if hf_on else None)
            got = lib.fw_protect_step(st, c, v_d, v_q, i_d, i_q, i_dr, i_qr, w, ref, limit, hf_on, hf)
            assert (got, st.emf_d, st.emf_q, st.track_f, st.ovl_n, st.ovl_e, st.e0, st.hf_f, st.ld_w, st.ld_n,
                    st.ld_f) == \
                (want, gold.emf_d, gold.emf_q, gold.track_f, gold.ovl_n, gold.ovl_e, gold.e0, gold.hf_f, gold.ld_w,
                 gold.ld_n, gold.ld_f), (seed, q, k, p)
            seen.add(want)
    assert seen == set(range(len(FAULT_NAMES))) - {protection.FAULT_OVERCURRENT, protection.FAULT_HARDWARE,
                                                    protection.FAULT_IDENT, protection.FAULT_UNDERVOLTAGE,
                                                    protection.FAULT_OVERVOLTAGE, protection.FAULT_SENSOR}, seen


def prot_sequences(rng: np.random.Generator):
    """N_RANDOM / 50 sequences of one check: ``(q, p, c, st, gold)`` with random limits ``p`` (:func:`random_prot`)
    in the C struct ``c``, one C state ``st`` for all (the check's counts reset by the caller) and a fresh golden
    firmware state ``gold``."""
    c, st = ffi.new("struct fw_prot_params *"), ffi.new("struct fw_state *")
    for q in range(N_RANDOM // 50):
        p = random_prot(rng)
        fw_c._fill(c, p)
        yield q, p, c, st, Firmware(_params())


def test_dc_link_check_random_sequences(seed):
    """Sequences of VDC codes (u16, around the limits and anywhere) through the dc-link check, golden == C,
    counts included; both of its codes are reached, and so is no trip."""
    rng = np.random.default_rng(seed + 42)
    seen = set()
    for q, p, c, st, gold in prot_sequences(rng):
        st.vdc_lo_n = st.vdc_hi_n = 0
        for k in range(10):
            vdc = draw_one(rng, 0, 65535, (0, 65535, p.vdc_lo - 1, p.vdc_lo, p.vdc_hi, p.vdc_hi + 1))
            vdc = min(max(vdc, 0), 65535)
            want = protection.dc_link_check(gold, p, vdc)
            got = lib.fw_dc_link_check(st, c, vdc)
            assert (got, st.vdc_lo_n, st.vdc_hi_n) == (want, gold.vdc_lo_n, gold.vdc_hi_n), (seed, q, k, p, vdc)
            seen.add(want)
    assert seen == {protection.FAULT_NONE, protection.FAULT_UNDERVOLTAGE, protection.FAULT_OVERVOLTAGE}, seen


def test_frozen_check_random_sequences(seed):
    """Sequences of WIN_ADC values and sample counts (around frz_min and anywhere) through the sensor check, golden ==
    C, counts included; its code and no trip are both reached."""
    rng = np.random.default_rng(seed + 44)
    seen = set()
    for q, p, c, st, gold in prot_sequences(rng):
        st.frz_a = st.frz_b = 0
        for k in range(10):
            frozen = int(rng.integers(0, 4)) if rng.random() < 0.8 else draw_one(rng, 0, U32_MAX)
            n = draw_one(rng, 0, U16_MAX, (p.frz_min - 1, p.frz_min, 200))
            n = min(max(n, 0), U16_MAX)
            want = protection.frozen_check(gold, p, frozen, n)
            got = lib.fw_frozen_check(st, c, frozen, n)
            assert (got, st.frz_a, st.frz_b) == (want, gold.frz_a, gold.frz_b), (seed, q, k, p, frozen, n)
            seen.add(want)
    assert seen == {protection.FAULT_NONE, protection.FAULT_SENSOR}, seen


def test_dc_feedforward_random(seed):
    """fw_dc_feedforward == golden dc_feedforward: random register voltages (s16, V_H over s32: the step's random
    parameters write any V_H, the hardware takes 15 bits) and VDC codes
    (u16, inside and beyond the clamp) for random feed-forward integers; the saturations are reached."""
    rng = np.random.default_rng(seed + 43)
    n = N_RANDOM
    nom = draw_array(rng, n, 1, 65535, (2048,))
    lo = np.maximum(1, (nom * rng.random(n)).astype(np.int64))
    lo = np.where(rng.random(n) < 0.2, np.where(rng.random(n) < 0.5, 1, nom), lo)
    hi = nom + ((65535 - nom) * rng.random(n)).astype(np.int64)
    hi = np.where(rng.random(n) < 0.2, np.where(rng.random(n) < 0.5, nom, 65535), hi)
    edges = np.stack([np.zeros(n, np.int64), lo - 1, lo, nom, hi, hi + 1, np.full(n, 65535)])
    vdc = np.where(rng.random(n) < 0.5, draw_array(rng, n, 0, 65535), edges[rng.integers(0, 7, size=n), np.arange(n)])
    vdc = np.clip(vdc, 0, 65535)
    v_dq = draw_array(rng, 2 * n, -(1 << 15), (1 << 15) - 1).reshape(2, n)
    v_h = draw_array(rng, n, -S32_MAX, S32_MAX, ((1 << 15) - 1,))
    rest = [draw_array(rng, n, -32768, 32767), draw_array(rng, n, -32768, 32767),
            draw_array(rng, n, S32_MIN, S32_MAX), draw_array(rng, n, S32_MIN, S32_MAX)]
    cols = [c.tolist() for c in (nom, lo, hi, vdc, v_dq[0], v_dq[1], v_h, *rest)]
    out = ffi.new("struct fw_outputs *")
    names = [f.name for f in dataclass_fields(Outputs)]
    saturated = 0
    for k, (f_nom, f_lo, f_hi, v, d, q, h, s_, c_, r_d, r_q) in enumerate(zip(*cols)):
        o = Outputs(d, q, h, s_, c_, 1, r_d, r_q)
        want = dc_feedforward(o, v, f_nom, f_lo, f_hi)
        for name in names:
            setattr(out, name, getattr(o, name))
        lib.fw_dc_feedforward(out, v, f_nom, f_lo, f_hi)
        assert fw_c.outputs_from_c(out) == want, (seed, k, o, v, f_nom, f_lo, f_hi)
        saturated += want.v_h == 0x7FFF or abs(want.v_d) >= (1 << 15) - 1
    assert saturated > 100, saturated


@pytest.mark.parametrize("vdc, want", [(2048, (1000, -1000, 300)), (1843, (1111, -1111, 333)),   # 10 % low
                                       (0, (1333, -1333, 400)), (65535, (800, -800, 240))])       # clamped
def test_dc_feedforward_corners(vdc, want):
    """The 002 drive's codes (nominal 2048, limits 1536 and 2560): the gain is nominal over the clamped sample,
    k = (2048 * 2^14 + v // 2) // v, and each voltage round_shr(v k, 14) (worked out by hand)."""
    o = Outputs(1000, -1000, 300, 0, 32767, 1)
    got = dc_feedforward(o, vdc, 2048, 1536, 2560)
    assert (got.v_d, got.v_q, got.v_h) == want and (got.sin, got.cos, got.enable) == (0, 32767, 1)


# ---- speed filter --------------------------------------------------------------------------------------------
def test_lowpass_random(seed):
    rng = np.random.default_rng(seed + 4)
    f = draw(rng, N_RANDOM, F_MIN, F_MAX)
    x = draw(rng, N_RANDOM, S32_MIN, S32_MAX)
    a = draw(rng, N_RANDOM, 0, 1 << 16, (2425, (1 << 16) - 1))
    step, out = lib.fw_lowpass_step, lib.fw_lowpass_out
    beyond_int64 = 0
    for k in range(N_RANDOM):
        assert step(f[k], x[k], a[k]) == lowpass_step(f[k], x[k], a[k]), (seed, f[k], x[k], a[k])
        assert out(f[k]) == lowpass_out(f[k]), (seed, f[k])
        beyond_int64 += abs(((x[k] << 16) - f[k]) * a[k]) > S64_MAX
    assert beyond_int64 > 1000, beyond_int64     # the split product is exercised


@pytest.mark.parametrize("f, x, a", [
    (F_MIN, S32_MAX, 1 << 16), (F_MAX, S32_MIN, 1 << 16), (F_MIN, S32_MAX, (1 << 16) - 1),
    (F_MAX, S32_MIN, (1 << 16) - 1), (F_MAX, S32_MIN, 1), (F_MIN, S32_MAX, 0), (-1, 0, 1 << 16),
    (-1, -1, 2425), (F_MAX, S32_MAX, 1 << 16)])
def test_lowpass_corners(f, x, a):
    """|d| up to 2^48 - 2^16 with a = 65536 (a plain int64 d * a would overflow), flooring of negatives."""
    assert lib.fw_lowpass_step(f, x, a) == lowpass_step(f, x, a)
    assert lib.fw_lowpass_out(f) == lowpass_out(f)


# ---- PI -------------------------------------------------------------------------------------------------------
PI_SETS = 2000
PI_PER_SET = N_RANDOM // PI_SETS


def test_pi_random(seed):
    rng = np.random.default_rng(seed + 5)
    integ_c = ffi.new("int64_t *")
    n_pos = n_neg = n_frozen = 0
    for _ in range(PI_SETS):
        p = random_pi(rng)
        cp = fw_c.pi_params_to_c(ffi, p)
        lim_i = p.limit << p.si
        integ = draw(rng, PI_PER_SET, -lim_i, lim_i)
        ref = draw(rng, PI_PER_SET, S32_MIN, S32_MAX)
        meas = draw(rng, PI_PER_SET, S32_MIN, S32_MAX)
        for k in range(PI_PER_SET):
            integ_c[0] = integ[k]
            u = lib.fw_pi_step(integ_c, ref[k], meas[k], cp)
            want = pi_step(integ[k], ref[k], meas[k], p)
            assert (u, integ_c[0]) == want, (seed, p, integ[k], ref[k], meas[k])
            n_pos += want[0] == p.limit
            n_neg += want[0] == -p.limit
            n_frozen += want[1] == integ[k] and p.ki and ref[k] != meas[k] and abs(integ[k]) != lim_i
    assert min(n_pos, n_neg) > 10_000 and n_frozen > 1000, (n_pos, n_neg, n_frozen)


def test_pi_random_32bit_words(seed):
    """The drive's own ranges, where the C takes its 32-bit path (|prop| < 2^30, limit < 2^30): gains, limits and
    errors of current and speed loops, and the path's edges (|prop| and limit at 2^30 - 1 and 2^30); every result
    against golden, frozen and integrating calls both present."""
    rng = np.random.default_rng(seed + 7)
    integ_c = ffi.new("int64_t *")
    n_frozen = n_taken = 0
    for _ in range(PI_SETS):
        limit = int(rng.choice([int(rng.integers(1, 1 << 16)), (1 << 30) - 1, 1 << 30]))
        sp, si = (int(v) for v in rng.integers(0, 31, size=2, endpoint=True))
        kp = int(rng.integers(0, 1 << 16)) if rng.random() < 0.8 else int(rng.integers(0, S32_MAX))
        p = PiParams(kp=kp, sp=sp, ki=int(rng.integers(0, 1 << 20)), si=si, limit=limit)
        cp = fw_c.pi_params_to_c(ffi, p)
        lim_i = p.limit << p.si
        integ = draw(rng, PI_PER_SET, -lim_i, lim_i)
        span = 1 << int(rng.integers(1, 32))
        ref = draw(rng, PI_PER_SET, -span, span - 1)
        meas = draw(rng, PI_PER_SET, -span, span - 1)
        for k in range(PI_PER_SET):
            integ_c[0] = integ[k]
            u = lib.fw_pi_step(integ_c, ref[k], meas[k], cp)
            want = pi_step(integ[k], ref[k], meas[k], p)
            assert (u, integ_c[0]) == want, (seed, p, integ[k], ref[k], meas[k])
            frozen = want[1] == integ[k] and p.ki and ref[k] != meas[k] and abs(integ[k]) != lim_i
            n_frozen += frozen
            n_taken += not frozen
    assert n_frozen > 1000 and n_taken > 10_000, (n_frozen, n_taken)


def _pi_sequence(p: PiParams, errors, integ=0):
    """Run golden and C side by side over (ref, meas) pairs; returns the golden (u, integ) per call."""
    cp = fw_c.pi_params_to_c(ffi, p)
    integ_c = ffi.new("int64_t *", integ)
    seq = []
    for ref, meas in errors:
        u = lib.fw_pi_step(integ_c, ref, meas, cp)
        u_g, integ = pi_step(integ, ref, meas, p)
        assert (u, integ_c[0]) == (u_g, integ), (p, ref, meas)
        seq.append((u_g, integ))
    return seq


def test_pi_saturation_both_ways():
    p = PiParams(kp=1 << 16, sp=16, ki=0, si=16, limit=100)
    assert _pi_sequence(p, [(1000, 0), (0, 1000), (S32_MAX, S32_MIN), (S32_MIN, S32_MAX)]) == \
        [(100, 0), (-100, 0), (100, 0), (-100, 0)]
    big = PiParams(kp=S32_MAX, sp=0, ki=S32_MAX, si=31, limit=S32_MAX)
    seq = _pi_sequence(big, [(S32_MAX, S32_MIN)] * 3 + [(S32_MIN, S32_MAX)] * 3, integ=big.limit << 31)
    assert [u for u, _ in seq] == [S32_MAX] * 3 + [-S32_MAX] * 3


def test_pi_anti_windup_freeze_and_release():
    """Integrates to the limit, freezes while the error pushes further, releases when it reverses."""
    p = PiParams(kp=1 << 16, sp=16, ki=1 << 16, si=16, limit=100)
    seq = _pi_sequence(p, [(50, 0), (50, 0), (50, 0), (-1, 0), (-1, 0)]) \
        + _pi_sequence(p, [(-50, 0), (-50, 0), (-50, 0), (1, 0)])
    assert seq == [(100, 50 << 16), (100, 50 << 16), (100, 50 << 16), (48, 49 << 16), (47, 48 << 16),
                   (-100, -50 << 16), (-100, -50 << 16), (-100, -50 << 16), (-48, -49 << 16)]


# ---- sin/cos ----------------------------------------------------------------------------------------------------
def test_sincos_random(seed):
    rng = np.random.default_rng(seed + 6)
    quarter = 1 << 30
    edges = [q * quarter + d for q in range(5) for d in (-2, -1, 0, 1, 2) if 0 <= q * quarter + d <= U32_MAX]
    angles = draw(rng, N_RANDOM, 0, U32_MAX, edges) + edges
    s_want, c_want = (v.tolist() for v in sincos_q15(np.array(angles, dtype=np.int64)))
    s_c, c_c = _out_pair()
    for k, a in enumerate(angles):
        lib.fw_sincos_q15(a, s_c, c_c)
        assert (s_c[0], c_c[0]) == (s_want[k], c_want[k]), (seed, a)
    assert {32767, -32768} <= set(s_want) | set(c_want)


# ---- control task ----------------------------------------------------------------------------------------------
class Pair:
    """A golden Firmware and its C twin (fw_init), stepped together and compared after every step."""

    def __init__(self, p: FirmwareParams, fw: Firmware | None = None):
        self.p, self.fw = p, Firmware(p) if fw is None else fw
        self.cp = fw_c.params_to_c(ffi, p)
        if fw is None:
            self.st = fw_c.new_state(ffi, p)      # with p.ident: st.ident points at its program
            lib.fw_init(self.st, self.cp)
        else:
            self.st = fw_c.state_to_c(ffi, fw)
        self.win = ffi.new("struct fw_window *")
        self.out = ffi.new("struct fw_outputs *")
        self.check_state()

    def check_state(self, ctx=()) -> None:
        diff = state_diff(fw_c.state_from_c(self.st, self.p), self.fw)
        if diff:
            pytest.fail(f"state differs (C, golden) {diff} {ctx}")

    def step(self, w: WindowResult, speed_ref: int, ctx=()) -> Outputs:
        want = self.fw.step(w, speed_ref)
        lib.fw_step(self.st, self.cp, fw_c.window_to_c(ffi, w, self.win), speed_ref, self.out)
        got = fw_c.outputs_from_c(self.out)
        assert got == want, (ctx, got, want)
        self.check_state(ctx)
        return want


def state_diff(a: Firmware, b: Firmware) -> dict:
    """The fields of two firmware states that differ: the shared scalars, the slot outputs, the output
    history and every attribute of each slot's estimator."""
    diff = {k: (getattr(a, k), getattr(b, k)) for k in (*fw_c.STATE_FIELDS, "est_theta", "est_omega", "act", "prev",
                                                         "nd", "nq")
            if getattr(a, k) != getattr(b, k)}
    for slot, (ea, eb) in enumerate(zip(a.slots, b.slots)):
        if ea is not None:
            diff.update({(slot, k): (v, vars(eb)[k]) for k, v in vars(ea).items() if v != vars(eb)[k]})
    if (a.ident is None) != (b.ident is None):
        diff["ident"] = (a.ident, b.ident)
    elif a.ident is not None:
        diff.update({("ident", k): (getattr(a.ident, k), getattr(b.ident, k))
                     for k in (*fw_c.IDENT_FIELDS, *fw_c.IDENT_ARRAYS) if getattr(a.ident, k) != getattr(b.ident, k)})
    return diff


def random_rfo(rng: np.random.Generator) -> RfoParams:
    """Observer integers over their documented ranges (golden.firmware.rfo), with the 002 values frequent."""
    r_s, l_s = draw(rng, 2, 0, S32_MAX, (2923, 11_700_000))
    return RfoParams(r_s=r_s, l_s=l_s, psi_f=draw_one(rng, 1, 1 << 27, (11_000_000,)),
                     k_c=draw_one(rng, 0, 1 << 16, (5519,)), k_min=draw_one(rng, 0, 1 << 16, (411,)),
                     k_r=draw_one(rng, 0, S32_MAX, (205887,)), pll_kp=draw_one(rng, 0, S32_MAX, (13107,)),
                     pll_ki=draw_one(rng, 0, S32_MAX, (167772,)), i_d=draw_one(rng, -S32_MAX, 0, (-2621,)),
                     l_dq=draw_one(rng, -S32_MAX, S32_MAX, (0, -1_252_000)))


def random_coef(rng: np.random.Generator) -> BiquadCoef:
    """Q28 coefficients over their range (|.| < 2^30), a real band-pass or notch in one set of three."""
    if rng.random() < 1 / 3:
        return BiquadCoef(*(int(v) for v in rng.choice([[23_022_048, 0, -23_022_048, -397_327_563, 222_391_887],
                                                         [252_062_643, -409_380_286, 252_062_643, -409_380_286,
                                                          235_689_270]])))
    return BiquadCoef(*draw(rng, 5, -(1 << 30) + 1, (1 << 30) - 1, (0,)))


def random_rot(rng: np.random.Generator) -> RotParams:
    """rot_bpf integers over their documented ranges (golden.firmware.rot_bpf; i_d <= 0, the magnetizing current of
    estimator.rot_bpf.i_d_min; half with a cross-saturation table), the 000 values frequent; half
    the sets track with the motion observer (its gains over struct fw_cic_params' ranges, the tap2023_step
    values ROT_MOTION_HOST frequent)."""
    q_sin, q_cos = sincos_q15(draw_one(rng, 0, U32_MAX, (3_972_844_748,)))
    h = ROT_MOTION_HOST
    c1, c2, c3 = (draw_one(rng, S32_MIN, S32_MAX, (h[k],)) for k in ("c1", "c2", "c3"))
    xs_shift, xs_angle, _ = random_mtpa(rng) if rng.random() < 0.5 else (0, (), ())
    return RotParams(q_cos=q_cos, q_sin=q_sin, bpf=random_coef(rng), n_avg=draw_one(rng, 1, rot_bpf.N_MAX, (20,)),
                     offset=draw_one(rng, 0, U32_MAX, (1 << 30, 3 << 30)), pll_kp=draw_one(rng, 0, S32_MAX, (655,)),
                     pll_ki=draw_one(rng, 0, S32_MAX, (419,)), k_delay=draw_one(rng, -(1 << 24) + 1, (1 << 24) - 1,
                                                                                (2_033_024,)),
                     n_hold=draw_one(rng, 0, 30, (0, 1)), tracking=int(rng.integers(0, 2)), c1=c1, c2=c2, c3=c3,
                     c_t=draw_one(rng, -CIC_CT_MAX, CIC_CT_MAX, (h["c_t"], 0)),
                     c_r=draw_one(rng, -CIC_CR_MAX, CIC_CR_MAX, (h["c_r"], 0)),
                     i_d=draw_one(rng, -S32_MAX, 0, (0, -491)), xs_shift=xs_shift, xs_angle=xs_angle)


def random_smo(rng: np.random.Generator) -> SmoParams:
    """eemf_smo integers over their documented ranges (golden.firmware.eemf_smo)."""
    c_v, c_r, c_x, k_lin = draw(rng, 4, -(1 << 24) + 1, (1 << 24) - 1, (0, 2521, 212, 3306))
    a_min, a_max = sorted(draw(rng, 2, 0, 1 << 16, (206, 30573, 1 << 16)))
    return SmoParams(c_v=c_v, c_r=c_r, c_x=c_x, k_lin=k_lin, z_max=draw_one(rng, 0, (1 << 15) - 1, (18725,)),
                     c_a=draw_one(rng, 0, 1 << 16, (3217,)), a_min=a_min, a_max=a_max,
                     lag0=draw_one(rng, 0, U32_MAX, (317_115_495,)), pll_kp=draw_one(rng, 0, S32_MAX, (1966,)),
                     pll_ki=draw_one(rng, 0, S32_MAX, (3775,)),
                     k_delay=draw_one(rng, -(1 << 24) + 1, (1 << 24) - 1, (136_975,)),
                     e_min=draw_one(rng, 0, S32_MAX, (0, 47872)), w_dir=draw_one(rng, 0, S32_MAX, (715_828,)),
                     i_d=draw_one(rng, -S32_MAX, 0, (0,)))


CIC_HOST = CicParams(g=124_104, c1=4162, c2=198_701, c3=12_353, c_t=4_199_825_053, c_r=-1_327_144_717,
                    k_delay=147_456, q_min=328, n_hold=4)
"""golden.control_config.sqw_cic_params of scenarios/xue2022_noload.toml (test_cic_params_of_the_scenario)."""
ROT_MOTION_HOST = {"c1": 2, "c2": 1272, "c3": 988, "c_t": 3_733_178, "c_r": -44_720_359}
"""The motion observer's gains of rot_bpf in scenarios/tap2023_step.toml (test_rot_observer_of_the_scenario)."""


def random_cic(rng: np.random.Generator) -> CicParams:
    """sqw_cic integers over the ranges control.h documents (struct fw_cic_params: any int32 but c_t, c_r,
    |c_t| <= 2^46, |c_r| <= 2^32, and i_d <= 0; half with a cross-saturation table), the extremes and the host's
    values (CIC_HOST) frequent."""
    h = CIC_HOST
    g, c1, c2, c3, k_delay = (draw_one(rng, S32_MIN, S32_MAX, (v,)) for v in (h.g, h.c1, h.c2, h.c3, h.k_delay))
    xs_shift, xs_angle, _ = random_mtpa(rng) if rng.random() < 0.5 else (0, (), ())
    return CicParams(g=g, c1=c1, c2=c2, c3=c3, c_t=draw_one(rng, -CIC_CT_MAX, CIC_CT_MAX, (h.c_t, 0)),
                     c_r=draw_one(rng, -CIC_CR_MAX, CIC_CR_MAX, (h.c_r, 0)),
                     k_delay=k_delay, q_min=draw_one(rng, S32_MIN, S32_MAX, (h.q_min, 0)),
                     n_hold=draw_one(rng, -2, 12, (h.n_hold, 0)) if rng.random() < 0.8
                     else draw_one(rng, S32_MIN, S32_MAX), i_d=draw_one(rng, -S32_MAX, 0, (0, -2621)),
                     xs_shift=xs_shift, xs_angle=xs_angle)


def random_mtpa(rng: np.random.Generator) -> tuple[int, tuple, tuple]:
    n = int(rng.integers(2, mtpa.MTPA_LEN + 1))
    return (int(rng.integers(0, 21)), tuple(draw(rng, n, -(1 << 15), (1 << 15) - 1)),
            tuple(draw(rng, n, -(1 << 15), (1 << 15) - 1)))


def random_params(rng: np.random.Generator, fixed: bool, prot: bool = False) -> FirmwareParams:
    """Valid parameters (PiParams, pll_gains, lowpass_coef, k_bb_raw ranges), short start-up counts; the
    low slot one of the low-slot methods (the square wave, the rotating injection, the period square wave
    with CIC), the high slot none or one of the high-slot methods (the rotor flux observer, the EEMF
    observer), with hand-over speeds that switch often; the 000 blocks (pilot polarity, MTPA,
    notch, speed-loop divider, rotating injection) each on in about half of the sets; the 003 ones: the
    hybrid flux observer in the low slot, the fcs_mpc law (mostly with it, sometimes with the others), no
    polarity detection (a third of the sets each with current pulses and pilot voltages); the fault checks
    (:func:`random_prot`) with ``prot``, else off."""
    k_bb, pll_kp, pll_ki = draw(rng, 3, 0, S32_MAX, (27_342_611, 2621, 6711))
    inj_rot = int(rng.random() < 0.5)
    v_h = draw_one(rng, 0, (1 << 15) - 1, (2621,)) if inj_rot else draw_one(rng, -S32_MAX, S32_MAX, (300,))
    i_pulse = draw_one(rng, -S32_MAX, S32_MAX, (5851,))
    n_converge, n_pulse = (int(v) for v in rng.integers(-1, 25, size=2))
    low = LOW_METHODS[int(rng.integers(0, len(LOW_METHODS)))]
    law = LAW_FCS_MPC if rng.random() < (0.7 if low == METHOD_HFO_PROJ else 0.2) else LAW_FOC_PWM
    high = (0, *HIGH_METHODS)[int(rng.integers(0, len(HIGH_METHODS) + 1))]
    w_down = int(rng.integers(0, S32_MAX - (1 << 24))) if rng.random() < 0.5 else draw_one(rng, 0, 1 << 24, (0, 100))
    step = draw_one(rng, 0, U32_MAX, (214_748_365,))
    (inj_sd, inj_cd), (inj_s2, inj_c2) = sincos_q15(step), sincos_q15(2 * step % (1 << 32))
    shift, t_d, t_q = random_mtpa(rng) if rng.random() < 0.5 else (0, (), ())
    xs_shift, xs_gamma, _ = random_mtpa(rng) if rng.random() < 0.5 else (0, (), ())
    return FirmwareParams(
        low=low, high=high, sqw=(SqwParams(k_bb, pll_kp, pll_ki, i_d=draw_one(rng, -S32_MAX, 0, (0, -2621)), xs_shift=xs_shift,
                        xs_gamma=xs_gamma)
             if low == METHOD_SQW_BANGBANG else None),
        rfo=random_rfo(rng) if high == METHOD_RFO else None,
        rot=random_rot(rng) if low == METHOD_ROT_BPF else None,
        smo=random_smo(rng) if high == METHOD_EEMF_SMO else None,
        cic=random_cic(rng) if low == METHOD_SQW_CIC else None,
        hfo=random_hfo(rng) if low == METHOD_HFO_PROJ else None,
        law=law, fcs=random_fcs(rng) if law == LAW_FCS_MPC else None,
        w_up=w_down + draw_one(rng, 0, 1 << 24, (0, 1)), w_down=w_down,
        merge=draw_one(rng, 0, 1 << 16, (0, 1 << 16, 2000)), speed_lp=draw_one(rng, 0, 1 << 16, (2425,)),
        speed_pi=random_pi(rng), id_pi=random_pi(rng), iq_pi=random_pi(rng), v_h=v_h, i_pulse=i_pulse,
        n_converge=n_converge, n_pulse=n_pulse, n_settle=int(rng.integers(-1, 12)),
        i_trip=draw_one(rng, 0, S32_MAX, (1000, 32767)),
        fixed_angle=draw_one(rng, 0, U32_MAX) if fixed else None,
        inj_rot=inj_rot, inj_cd=inj_cd, inj_sd=inj_sd, inj_c2=inj_c2, inj_s2=inj_s2, hf_dtc=draw_one(rng, 0, 1 << 15, (597,)),
        pol_mode=(POL_PILOT, POL_CURRENT, POL_NONE)[int(rng.integers(0, 3))], v_pilot=draw_one(rng, 0, (1 << 15) - 1, (9362,)),
        mtpa_shift=shift, mtpa_id=t_d, mtpa_iq=t_q, notch=random_coef(rng) if rng.random() < 0.5 else None,
        speed_div=draw_one(rng, 1, 20, (1, 10)), i_slew=draw_one(rng, 0, 1 << 30, (0, 1, 33)),
        prot=random_prot(rng) if prot else ProtParams(),
        lobs=random_lobs(rng) if rng.random() < 0.5 else LoadObsParams(),
        **(random_ff(rng) if rng.random() < 0.5 else {}), **(random_wd(rng) if rng.random() < 0.5 else {}))


def random_wd(rng: np.random.Generator) -> dict:
    """The hand-over's watchdog on: any angle gap (its edges too), speed and hold."""
    return dict(wd_delta=draw_one(rng, 1, 1 << 31, (1, 1 << 31, 0x1000_0000)),
                wd_speed=draw_one(rng, 0, S32_MAX, (0, 1 << 20)), wd_hold=draw_one(rng, 0, 1 << 16, (0, 1, 250)))


def random_ff(rng: np.random.Generator) -> dict:
    """The dc-link feed-forward's integers over control_config's ranges (1 <= ff_lo <= ff_nom <= ff_hi <= 2^16 - 1,
    the 002 drive's codes frequent; golden.firmware.dc_feedforward)."""
    nom = draw_one(rng, 1, 65535, (2048, 1, 65535))
    lo = draw_one(rng, 1, nom, (1536, 1, nom))
    return {"ff_nom": nom, "ff_lo": lo, "ff_hi": draw_one(rng, nom, 65535, (2560, nom, 65535))}


LOBS_HOST = LoadObsParams(g=31302, l1=63249, l2g=8179263)
"""golden.control_config.load_observer_params of scenarios/varatharajan2020_torquestep.toml (3 Hz)."""


def random_lobs(rng: np.random.Generator) -> LoadObsParams:
    """Load-observer integers over the ranges control.h documents (0 < g, l1, l2g < 2^31), LOBS_HOST's frequent."""
    return LoadObsParams(*(draw_one(rng, 1, S32_MAX, (v, 1)) for v in (LOBS_HOST.g, LOBS_HOST.l1, LOBS_HOST.l2g)))


def random_prot(rng: np.random.Generator) -> ProtParams:
    """Fault-check limits over their ranges (control_config's formats): Q16 motor constants up to 2^24,
    fluxes and speeds over s32 (mostly the magnitudes of real motors), limits that trip or not."""
    r, ld, lq = draw(rng, 3, 0, 1 << 24, (4389, 256_900, 287_691))
    psi_f, psi_rel = draw(rng, 2, 0, S32_MAX, (270_227, 67_557))
    emf_k, track_k = draw(rng, 2, 0, 30, (0, 5, 7))
    emf_tol, track_tol = draw(rng, 2, 0, S32_MAX, (0, 2011, 1 << 20))
    w_max, w_asc = draw(rng, 2, 0, S32_MAX, (0, 10_021_590, 300_690_740))
    vdc_lo = draw_one(rng, 0, 65535, (0, 1536, 65535))
    return ProtParams(r=r, ld=ld, lq=lq, psi_f=psi_f, emf_k=emf_k, emf_tol=emf_tol, psi_rel=psi_rel,
                      track_k=track_k, track_tol=track_tol, ovl_n=draw_one(rng, 0, 2000, (0, 1, 2500)),
                      ovl_w=draw_one(rng, 0, S32_MAX, (0, 1_202_591)), ovl_m=draw_one(rng, 0, 300, (0, 1, 250)),
                      w_max=w_max, w_asc=w_asc,
                      restarts=draw_one(rng, 0, 3, (0,)), restart_n=draw_one(rng, 0, 20, (0, 1)),
                      catch_n=draw_one(rng, 0, 20, (0, 0, 1)),
                      hf_k=draw_one(rng, 0, 30, (0, 4)), hf_tol=draw_one(rng, 0, 1 << 16, (0, 5898, 1 << 16)),
                      vdc_lo=vdc_lo, vdc_hi=draw_one(rng, vdc_lo, 65535, (vdc_lo, 65535)),
                      vdc_n=draw_one(rng, 0, 20, (0, 1, 5)),
                      frz_n=draw_one(rng, 0, 12, (0, 1, 4)), frz_min=draw_one(rng, 0, 300, (2, 16)),
                      probe_min=draw_one(rng, 0, 1 << 16, (0, 0, 1, 130)),
                      slip_w=draw_one(rng, 0, S32_MAX, (0, 0, 1, 10_416_233)), slip_n=draw_one(rng, 0, 60, (0, 1, 25)),
                      ld_ct=draw_one(rng, -(1 << 46), 1 << 46, (0, 154_343_571, 4_199_825_053)),
                      ld_cr=draw_one(rng, -(1 << 32), 1 << 32, (0, -17_586_767, -1_327_144_717)),
                      ld_k=draw_one(rng, 0, 30, (0, 5)), ld_max=draw_one(rng, 0, S32_MAX, (0, 0, 1, 38, 126_622)))


def random_cic_q(rng: np.random.Generator, count: int) -> np.ndarray:
    """``count`` values of CIC_QA or CIC_QB: s21 (the register) with its extremes, one in ten over s32 (the
    C field; golden saturates to 29 bits) with the edges of that saturation."""
    s21 = draw_array(rng, count, S21_MIN, S21_MAX)
    s32 = draw_array(rng, count, S32_MIN, S32_MAX, (-(1 << 28) - 1, -(1 << 28), (1 << 28) - 1, 1 << 28))
    return np.where(rng.random(count) < 0.9, s21, s32)


def healthy_vdc(p) -> int:
    """A VDC code the dc-link check of ``p`` passes: the middle of its band."""
    return (p.prot.vdc_lo + p.prot.vdc_hi) // 2


def random_windows(rng: np.random.Generator, count: int, i_trip: int, gamma_d_bias: int,
                   vdc: int = 0) -> list[WindowResult]:
    """``count`` window results whose means stay within +-i_trip (no trip); gamma_d shifted by the bias;
    CIC_QA/QB as :func:`random_cic_q`; VECTOR.STATE and NEXT 0..7, TOP_I s16 (mostly within +-4000); VDC ``vdc``
    (:func:`healthy_vdc`: the dc-link check passes; its trips are tested on their own); WIN_ADC 0 in seven windows
    of ten, else any of its four values."""
    gamma, gamma_d, wsum = (draw_array(rng, count, S32_MIN, S32_MAX) for _ in range(3))
    gamma_d = np.clip(gamma_d // 2 + gamma_d_bias, S32_MIN, S32_MAX)
    n = draw_array(rng, count, 0, U16_MAX, (1, 2, 10, 200))
    # sum = m n + r with |r| < n of m's sign: c_div(sum, n) = m (|m| <= i_trip); saturated to s32, the
    # mean only shrinks; with n = 0 the sums are arbitrary (the means are 0)
    means = draw_array(rng, 2 * count, -i_trip, i_trip).reshape(2, count)
    rems = rng.integers(0, np.maximum(n, 1), size=(2, count)) * np.sign(means)
    sums = np.clip(means * n + rems, S32_MIN, S32_MAX)
    sums = np.where(n == 0, draw_array(rng, 2 * count, S32_MIN, S32_MAX).reshape(2, count), sums)
    inj_phase = draw_array(rng, count, 0, U32_MAX)
    zeros = np.zeros(count, dtype=np.int64)
    vector, vector_next = (rng.integers(0, 8, size=count) for _ in range(2))
    top = [np.where(rng.random(count) < 0.8, rng.integers(-4000, 4001, size=count), draw_array(rng, count, S16_MIN, S16_MAX))
           for _ in range(2)]
    # WIN_ADC: mostly live lanes, runs of frozen ones (the sensor check counts them in RUN)
    frozen = np.where(rng.random(count) < 0.7, 0, rng.integers(0, 4, size=count))
    cols = (gamma, gamma_d, sums[0], sums[1], wsum, n, inj_phase, random_cic_q(rng, count), random_cic_q(rng, count),
            zeros, zeros, vector, vector_next, top[0], top[1], np.full(count, vdc), zeros, frozen)
    return [WindowResult(*row) for row in zip(*(c.tolist() for c in cols))]


def trip_window(rng: np.random.Generator, i_trip: int) -> WindowResult:
    """A window result with one mean beyond +-i_trip (the other within), or, one time in two, means within and
    a fault latch of STATUS (the hardware's own trip)."""
    gamma, gamma_d, wsum = draw(rng, 3, S32_MIN, S32_MAX)
    if rng.random() < 0.5:
        status = int(rng.choice([0x1, 0x2, 0x10, 0x20, 0x33]))
        return WindowResult(gamma=gamma, gamma_d=gamma_d, sum_id=draw_one(rng, -i_trip, i_trip),
                            sum_iq=draw_one(rng, -i_trip, i_trip), wsum=wsum, n_samples=1, status=status)
    if i_trip == S32_MAX:      # only abs(INT32_MIN) = 2^31 exceeds it
        n, over = 1, S32_MIN
    else:
        big = draw_one(rng, i_trip + 1, S32_MAX)
        n = draw_one(rng, 1, max(1, min(4, S32_MAX // big)))
        over = big * n if rng.random() < 0.5 else -big * n
    sums = [over, draw_one(rng, -i_trip, i_trip)]
    if rng.random() < 0.5:
        sums.reverse()
    return WindowResult(gamma=gamma, gamma_d=gamma_d, sum_id=sums[0], sum_iq=sums[1], wsum=wsum, n_samples=n)


STEP_CHUNKS = 4
SEQ_LEN = 200
SEQS_PER_CHUNK = N_RANDOM // (STEP_CHUNKS * SEQ_LEN)
TRIP_FROM = (MODE_CONVERGE, MODE_POL_POS, MODE_POL_NEG, MODE_RELAX, MODE_RUN, MODE_FIXED)


@pytest.mark.parametrize("chunk", range(STEP_CHUNKS))
def test_fw_step_random_sequences(seed, chunk):
    """SEQS_PER_CHUNK sequences of SEQ_LEN windows; each trips (if at all) from a chosen state, by the
    overcurrent or the hardware's STATUS, and in RUN also by the fault checks (on in those sets only, so that
    the other sets reach RUN with every method)."""
    rng = np.random.default_rng(seed + 100 + chunk)
    visited, trips_from, flips, switches, running, codes = set(), set(), set(), set(), set(), set()
    load_observed = False                        # the load observer ran in RUN and holds a load
    for q in range(SEQS_PER_CHUNK):
        fixed = q % 8 == 0
        trip_mode = MODE_FIXED if fixed else (None, *TRIP_FROM[:5])[q % 6]       # None: never trips
        p = random_params(rng, fixed, prot=trip_mode == MODE_RUN)
        pair = Pair(p)
        bias = draw_one(rng, -(1 << 20), 1 << 20) if q % 5 else 0
        speed_ref = draw_one(rng, S32_MIN, S32_MAX)
        windows = random_windows(rng, SEQ_LEN, p.i_trip, bias, healthy_vdc(p))
        for k, w in enumerate(windows):
            before, active = pair.fw.mode, pair.fw.active
            if before == trip_mode and rng.random() < 0.25:
                w = trip_window(rng, p.i_trip)
            if rng.random() < 0.02:
                speed_ref = draw_one(rng, S32_MIN, S32_MAX)
            pair.step(w, speed_ref, (seed, chunk, q, k, p))
            visited.add(pair.fw.mode)
            if pair.fw.mode == MODE_FAULT and before != MODE_FAULT:
                trips_from.add(before)
                codes.add(pair.fw.fault)
            if before == MODE_POL_NEG and pair.fw.mode == MODE_RELAX:
                flips.add(pair.fw.flipped)
            if pair.fw.active != active:
                switches.add(pair.fw.active)
            if pair.fw.mode == MODE_RUN:
                running.add((p.low if pair.fw.active == SLOT_LOW else p.high, p.pol_mode))
                load_observed |= p.lobs.g != 0 and pair.fw.lobs_i != 0
    assert load_observed
    assert SLOT_HIGH in switches, switches       # hand-overs happen (both ways: test_hand_over_*)
    assert visited == set(range(7)) | {MODE_CATCH}, visited      # CATCH: the flying start of random_prot's sets
    assert set(TRIP_FROM) <= trips_from <= set(TRIP_FROM) | {MODE_CATCH}, trips_from
    assert {protection.FAULT_OVERCURRENT, protection.FAULT_HARDWARE} <= codes, codes
    assert flips == {0, 1}, flips
    assert {m for m, _ in running} == set(METHODS_BY_ID) and \
        {pol for _, pol in running} == {POL_CURRENT, POL_PILOT, POL_NONE}, running


def test_steps_that_do_not_read_gamma_ignore_it(seed):
    """fw_reads_gamma (main.c reads GAMMA and GAMMA_D only when it says so): for every parameter set where it says
    no, two C twins stepped over the same random windows, one given the windows' GAMMA and GAMMA_D and one given 0,
    keep equal outputs and states; where it says yes, the square wave's estimator or the current-pulse polarity is
    configured."""
    rng = np.random.default_rng(seed + 11)
    quiet = 0
    for q in range(60):
        p = random_params(rng, fixed=False, prot=q % 2 == 0)
        cp = fw_c.params_to_c(ffi, p)
        twins = [fw_c.new_state(ffi, p) for _ in range(2)]
        for st in twins:
            lib.fw_init(st, cp)
        reads = lib.fw_reads_gamma(twins[0], cp)
        assert reads == (METHOD_SQW_BANGBANG in (p.low, p.high) or p.pol_mode == POL_CURRENT), p
        if reads:
            continue
        quiet += 1
        win, out = ffi.new("struct fw_window *"), [ffi.new("struct fw_outputs *") for _ in range(2)]
        speed_ref = draw_one(rng, S32_MIN, S32_MAX)
        for k, w in enumerate(random_windows(rng, SEQ_LEN, p.i_trip, 0, healthy_vdc(p))):
            for st, o, g in zip(twins, out, (w, replace(w, gamma=0, gamma_d=0))):
                lib.fw_step(st, cp, fw_c.window_to_c(ffi, g, win), speed_ref, o)
            assert fw_c.outputs_from_c(out[0]) == fw_c.outputs_from_c(out[1]), (seed, q, k, p)
            diff = state_diff(fw_c.state_from_c(twins[0], p), fw_c.state_from_c(twins[1], p))
            assert not diff, (seed, q, k, diff)
    assert quiet >= 10, quiet


def _params(**kw) -> FirmwareParams:
    pi = PiParams(kp=1 << 16, sp=16, ki=1 << 10, si=16, limit=2000)
    base = dict(low=METHOD_SQW_BANGBANG, high=0, sqw=SqwParams(27_342_611, 2621, 6711), rfo=None,
                speed_lp=2425, speed_pi=pi, id_pi=pi, iq_pi=pi,
                v_h=5851, i_pulse=300, n_converge=3, n_pulse=4, n_settle=1, i_trip=1000, fixed_angle=None)
    base.update(kw)
    return FirmwareParams(**base)


def _win(gamma=1, gamma_d=0, sum_id=0, sum_iq=0, n=10) -> WindowResult:
    return WindowResult(gamma=gamma, gamma_d=gamma_d, sum_id=sum_id, sum_iq=sum_iq, wsum=0, n_samples=n)


@pytest.mark.parametrize("fixed_angle", [None, 0, 123_456_789, U32_MAX, (1 << 32) + 5, -1])
def test_fw_init(fixed_angle):
    """fw_init equals Firmware(params): CONVERGE, or FIXED at uwrap(fixed_angle, 32)."""
    pair = Pair(_params(fixed_angle=fixed_angle))
    assert pair.st.mode == (MODE_CONVERGE if fixed_angle is None else MODE_FIXED)


def test_start_up_with_and_without_flip():
    """CONVERGE -> POL_POS -> POL_NEG -> RELAX -> RUN; the larger -I_p response flips theta_hat by pi."""
    for pos, neg, flipped in ((5, 9, 1), (9, 5, 0), (7, 7, 0)):
        pair = Pair(_params())
        modes = []
        for k in range(16):
            mode = pair.fw.mode
            gamma_d = pos if mode == MODE_POL_POS else neg if mode == MODE_POL_NEG else 0
            pair.step(_win(gamma=(-1) ** k, gamma_d=gamma_d, sum_id=30, sum_iq=-25), 5000)
            modes.append(pair.fw.mode)
        assert modes[:13] == [MODE_CONVERGE] * 2 + [MODE_POL_POS] * 4 + [MODE_POL_NEG] * 4 + [MODE_RELAX] \
            + [MODE_RUN] * 2
        assert pair.fw.flipped == pair.st.flipped == flipped


@pytest.mark.parametrize("mode", [MODE_CONVERGE, MODE_POL_POS, MODE_POL_NEG, MODE_RELAX, MODE_RUN, MODE_FIXED])
def test_fault_by_trip(mode):
    """A window mean beyond i_trip in any state: FAULT outputs (0,0,0,0,32767,0), integrators cleared."""
    fw = Firmware(_params(fixed_angle=7 if mode == MODE_FIXED else None))
    fw.mode, fw.n, fw.id_int, fw.iq_int, fw.speed_int = mode, 1, 12345 << 16, -777 << 16, 99 << 20
    pair = Pair(fw.p, fw)
    assert pair.step(_win(sum_id=10, sum_iq=-1001, n=1), 100) == Outputs(0, 0, 0, 0, 32767, 0)
    assert (pair.st.mode, pair.st.n, pair.st.id_int, pair.st.iq_int) == (MODE_FAULT, 0, 0, 0)
    for _ in range(3):      # FAULT is kept, the estimator is off
        pair.step(_win(gamma=5, n=0), 100)
    assert pair.st.n == 3


def test_trip_on_int32_min_mean():
    """abs(INT32_MIN) = 2^31 exceeds i_trip = INT32_MAX (the C takes abs in int64)."""
    pair = Pair(_params(i_trip=S32_MAX))
    pair.step(_win(sum_id=S32_MAX, sum_iq=S32_MAX - 1, n=1), 0)
    assert pair.st.mode == MODE_CONVERGE
    pair.step(_win(sum_iq=S32_MIN, n=1), 0)
    assert pair.st.mode == MODE_FAULT


def test_window_counter_saturates_at_int32_max():
    """n saturates at INT32_MAX in the C (the golden int counts on: 2^31 does not fit s32 n)."""
    fw = Firmware(_params())
    fw.mode, fw.n = MODE_RUN, S32_MAX - 1
    pair = Pair(fw.p, fw)
    pair.step(_win(), 10)
    assert pair.st.n == S32_MAX
    lib.fw_step(pair.st, pair.cp, fw_c.window_to_c(ffi, _win(), pair.win), 10, pair.out)
    want = pair.fw.step(_win(), 10)
    assert pair.fw.n == 1 << 31 and pair.st.n == S32_MAX
    assert fw_c.outputs_from_c(pair.out) == want
    pair.fw.n = S32_MAX
    pair.check_state()


def _running(active: int, speed_f: int, w_up: int, w_down: int, **wd) -> Firmware:
    """A firmware in RUN with the rotor flux observer as the high slot, the given slot in charge and
    filtered speed (Q16 state), distinct angles in the two slots (0x0800_0000 apart: 11.25 deg); ``wd``: the
    watchdog's parameters."""
    rfo = RfoParams(r_s=2923, l_s=11_700_000, psi_f=11_000_000, k_c=5519, k_min=411, k_r=205887, pll_kp=13107,
                    pll_ki=167772, i_d=-2621, l_dq=-1_252_000)
    fw = Firmware(_params(high=METHOD_RFO, rfo=rfo, w_up=w_up, w_down=w_down, merge=2000, **wd))
    fw.mode, fw.n, fw.active, fw.speed_f = MODE_RUN, 5, active, speed_f
    fw.slots[SLOT_LOW].theta = fw.est_theta[SLOT_LOW] = 0x1000_0000
    fw.slots[SLOT_HIGH].theta = fw.est_theta[SLOT_HIGH] = 0x1800_0000
    fw.slots[SLOT_HIGH].x_al, fw.slots[SLOT_HIGH].x_be = 11_000_000, 3_000_000
    fw.theta_hat = fw.est_theta[active]
    return fw


def test_hand_over_up_is_bumpless_and_stops_the_injection():
    """|omega_f| > w_up with the low slot in charge: the high slot takes charge, the angle in use is the low
    slot's (offset = low - high), no injection and the observer's d-current from this step on; C = golden."""
    fw0 = _running(SLOT_LOW, (1 << 30) << 16, w_up=1 << 29, w_down=1 << 28)   # far above what one step moves
    pair = Pair(fw0.p, fw0)
    fw = pair.fw
    out = pair.step(_win(gamma=0, sum_id=0, sum_iq=0), 4000)
    assert fw.active == pair.st.active == SLOT_HIGH
    assert fw.theta_hat == fw.est_theta[SLOT_LOW] == 0x1000_0000          # gamma 0: the bang-bang held
    assert fw.offset == (fw.theta_hat - fw.est_theta[SLOT_HIGH] + 2**31) % 2**32 - 2**31
    assert out.v_h == 0
    assert out.i_d_ref == -2621                                          # the observer's d-current


def test_hand_over_down_syncs_the_low_slot_and_restarts_the_injection():
    """|omega_f| < w_down with the high slot in charge: the low slot continues from the angle in use and
    the high slot's speed, holds gamma for one step, the injection is back; C = golden."""
    fw0 = _running(SLOT_HIGH, 0, w_up=1 << 30, w_down=1 << 30)                 # far above what one step moves
    fw0.offset = 1 << 20
    pair = Pair(fw0.p, fw0)
    fw = pair.fw
    out = pair.step(_win(gamma=5, sum_id=0, sum_iq=0), 0)
    lo = fw.slots[SLOT_LOW]
    assert fw.active == pair.st.active == SLOT_LOW
    assert lo.hold == 1 and lo.theta == fw.theta_hat == fw.est_theta[SLOT_LOW]
    assert lo.omega == fw.est_omega[SLOT_HIGH]
    assert out.v_h == fw.p.v_h and out.i_d_ref == 0
    pair.step(_win(gamma=5, sum_id=0, sum_iq=0), 0)      # the hold step: gamma ignored, PLL speed added
    assert lo.hold == 0


@pytest.mark.parametrize("gap_limit, speed_limit, takes", [
    (0x0400_0000, 1 << 20, True),      # 5.6 deg < 11.25 deg apart, 2^24 LSB/period above the speed limit: acts
    (0x0C00_0000, 1 << 20, False),     # the angles within 16.9 deg: no
    (0x0400_0000, 1 << 28, False),     # below its speed: no
])
def test_watchdog_hands_over_when_the_slots_disagree(gap_limit, speed_limit, takes):
    """The watchdog (docs/methods.md): low slot in charge below w_up, the slots 11.25 deg apart; beyond
    wd_delta above wd_speed the high slot takes charge at its own angle (offset 0) and holds for wd_hold
    periods, even at zero speed; C = golden in every step."""
    fw0 = _running(SLOT_LOW, (1 << 24) << 16, w_up=1 << 29, w_down=1 << 28, wd_delta=gap_limit,
                   wd_speed=speed_limit, wd_hold=3)
    pair = Pair(fw0.p, fw0)
    fw = pair.fw
    pair.step(_win(gamma=0, sum_id=0, sum_iq=0), 0)
    assert fw.active == pair.st.active == (SLOT_HIGH if takes else SLOT_LOW)
    if not takes:
        return
    assert fw.offset == 0 and fw.theta_hat == fw.est_theta[SLOT_HIGH] and fw.wd_n == 3
    fw.speed_f = pair.st.speed_f = 0                      # far below w_down: the hold keeps the high slot
    for n in (2, 1, 0):
        pair.step(_win(gamma=0, sum_id=0, sum_iq=0), 0)
        assert (fw.active, fw.wd_n) == (SLOT_HIGH, n)
    pair.step(_win(gamma=0, sum_id=0, sum_iq=0), 0)        # the hold over: the ordinary hand-back
    assert fw.active == SLOT_LOW


# ---- the 000 blocks: band-pass/notch section, MTPA table, injection voltage ---------------------------------
def test_array_lengths_match_golden():
    """control.h writes the ring buffer and MTPA table lengths as literals (cffi parses it): they are
    golden.firmware.rot_bpf.N_MAX and golden.firmware.mtpa.MTPA_LEN."""
    rot = dict(ffi.typeof("struct fw_rot_state").fields)
    assert rot["buf_d"].type.length == rot["buf_q"].type.length == rot_bpf.N_MAX
    fields = dict(ffi.typeof("struct fw_params").fields)
    assert fields["mtpa_id"].type.length == fields["mtpa_iq"].type.length == mtpa.MTPA_LEN


def test_biquad_random(seed):
    """fw_biquad_step = biquad_step on N_RANDOM random states, inputs (|x| < 2^20) and coefficients."""
    rng = np.random.default_rng(seed + 40)
    xs = draw(rng, N_RANDOM, -(1 << 20) + 1, (1 << 20) - 1)
    st = ffi.new("struct fw_biquad *")
    c = ffi.new("struct fw_biquad_coef *")
    for k in range(N_RANDOM):
        if k % 10 == 0:                  # a new section and state every 10 steps
            coef = random_coef(rng)
            c.b0, c.b1, c.b2, c.a1, c.a2 = coef.b0, coef.b1, coef.b2, coef.a1, coef.a2
            x1, x2 = draw(rng, 2, -(1 << 20) + 1, (1 << 20) - 1)
            y1, y2 = draw(rng, 2, S32_MIN, S32_MAX)
            g = BiquadState(x1, x2, y1, y2)
            st.x1, st.x2, st.y1, st.y2 = x1, x2, y1, y2
        g = biquad_step(g, xs[k], coef)
        lib.fw_biquad_step(st, xs[k], c)
        assert (st.x1, st.x2, st.y1, st.y2) == (g.x1, g.x2, g.y1, g.y2), (k, coef, xs[k])


def test_mtpa_lookup_random(seed):
    """fw_mtpa_lookup = mtpa_lookup on N_RANDOM magnitudes (0..2^31, inside and beyond the table)."""
    rng = np.random.default_rng(seed + 41)
    out_d, out_q = ffi.new("int32_t *"), ffi.new("int32_t *")
    t_d, t_q = ffi.new("int32_t[]", mtpa.MTPA_LEN), ffi.new("int32_t[]", mtpa.MTPA_LEN)
    for k in range(N_RANDOM // 100):
        shift, d, q = random_mtpa(rng)
        t_d[0:len(d)], t_q[0:len(q)] = list(d), list(q)
        for i_s in draw(rng, 100, 0, 1 << 31, ((len(d) - 1) << shift, (len(d) - 2) << shift)):
            lib.fw_mtpa_lookup(i_s, shift, len(d), t_d, t_q, out_d, out_q)
            assert (out_d[0], out_q[0]) == mtpa.mtpa_lookup(i_s, shift, d, q), (shift, d, q, i_s)


def test_injection_voltage_random(seed):
    """fw_injection_voltage = injection_voltage on N_RANDOM amplitudes (0..2^15) and Q15 angles."""
    rng = np.random.default_rng(seed + 42)
    a, b = _out_pair()
    v_now, v_before = (draw(rng, N_RANDOM, 0, 1 << 15) for _ in range(2))
    for k in range(N_RANDOM):
        s_, c_ = sincos_q15(draw_one(rng, 0, U32_MAX))
        sd, cd = sincos_q15(draw_one(rng, 0, U32_MAX, (214_748_365,)))
        lib.fw_injection_voltage(v_now[k], v_before[k], s_, c_, cd, sd, a, b)
        assert (a[0], b[0]) == injection_voltage(v_now[k], v_before[k], s_, c_, cd, sd), k


# ---- estimator sqw_cic (golden.firmware.sqw_cic; Xue et al. 2022) -------------------------------------------
CIC_STATE = tuple(name for name, _ in ffi.typeof("struct fw_cic_state").fields)
W_SPECIALS = (S64_MAX - 1, S64_MIN + 1, S64_MAX - (1 << 40), S64_MIN + (1 << 40), 1 << 62, -(1 << 62))
"""Saturation corners of the observer's w and z (int64)."""
S16_EDGES = (-(1 << 15) - 1, -(1 << 15), (1 << 15) - 1, 1 << 15)
HALF_TURN = 1 << 31


class _EstimatorPair:
    """The C structs one estimator step needs (a fw_state with its method's block, the params, a window,
    the measurement, the outputs) for a golden estimator and its C functions on the same state."""

    def __init__(self):
        self.st = ffi.new("struct fw_state *")
        self.cp = ffi.new("struct fw_params *")
        self.win = ffi.new("struct fw_window *")
        self.m = ffi.new("struct fw_meas *")
        self.m.win = self.win
        self.theta, self.omega = ffi.new("uint32_t *"), ffi.new("int32_t *")
        self.p = None


class CicPair(_EstimatorPair):
    """SquareWaveCic and fw_cic_step / turn / sync on the same state (the C's cic block of a fw_state)."""

    def load(self, p: CicParams, state: dict) -> SquareWaveCic:
        """A golden estimator with params ``p`` and ``state`` (attributes by name), the same into the C."""
        if p is not self.p:
            for f in dataclass_fields(p):
                setattr(self.cp.cic, f.name, getattr(p, f.name))
            self.p = p
        est = SquareWaveCic(p)
        for name, v in state.items():
            setattr(est, name, v)
            setattr(self.st.cic, name, v)
        return est

    def step(self, est: SquareWaveCic, qa: int, qb: int, i_d: int, i_q: int) -> tuple[int, int]:
        """One step of both; the C's outputs (theta, omega)."""
        self.win.cic_qa, self.win.cic_qb = qa, qb
        self.m.i_d, self.m.i_q = i_d, i_q
        est.step(Measurement(WindowResult(0, 0, 0, 0, 0, 0, cic_qa=qa, cic_qb=qb), i_d, i_q, 0, 32767, 0, 0))
        lib.fw_cic_step(self.st, self.cp, self.m, self.theta, self.omega)
        return self.theta[0], self.omega[0]

    def diff(self, est: SquareWaveCic) -> dict:
        """The state fields that differ: name -> (C, golden)."""
        return {k: (getattr(self.st.cic, k), getattr(est, k)) for k in CIC_STATE
                if getattr(self.st.cic, k) != getattr(est, k)}


def _cic_cancel_case(rng: np.random.Generator, p: CicParams, qa: int, qb: int, sign: int):
    """Params and state in which w + z leaves int64 but w + z + c2 e + ff does not (the wraps of the C's two
    adds cancel): e saturated against the sign of z (theta_o a quarter turn off psi, g = c2 ~ 2^31), the
    feed-forward c_t i_q ~ 2^61 the same way, z ~ sign 2^62, w ~ sign 2^63; c_r = 0, hold = 0, q_min = 0, no
    cross-saturation table."""
    psi, _ = vector_angle(max(min(qa, (1 << 28) - 1), -(1 << 28)), max(min(qb, (1 << 28) - 1), -(1 << 28)))
    p = replace(p, g=S32_MAX, c1=draw_one(rng, -(1 << 20), 1 << 20), c2=S32_MAX - int(rng.integers(0, 1 << 20)),
                c_t=-sign * (CIC_CT_MAX - int(rng.integers(0, 1 << 30))), c_r=0, q_min=0, xs_angle=())
    r, r2 = (int(v) for v in rng.integers(0, 1 << 60, size=2))
    state = dict(theta_o=uwrap(psi + sign * (1 << 30), 32), hold=0, z=sign * ((1 << 62) + r),
                 w=S64_MAX - r2 if sign > 0 else S64_MIN + r2)
    return p, state, S32_MAX if rng.random() < 0.5 else (1 << 15) - 1


def test_cic_step_random(seed):
    """fw_cic_step = SquareWaveCic.step on N_RANDOM random parameter sets (a new one every 10 inputs), states
    (w and z over int64 with their saturation corners, hold around 0) and measurements (CIC_QA/QB, window
    means over s32 with the s16 edges); one in twenty inputs is a case whose wrapping adds cancel."""
    rng = np.random.default_rng(seed + 50)
    n = N_RANDOM
    theta_o, theta = (draw(rng, n, 0, U32_MAX) for _ in range(2))
    w, z = (draw(rng, n, S64_MIN, S64_MAX, W_SPECIALS) for _ in range(2))
    hold = np.where(rng.random(n) < 0.8, draw_array(rng, n, -4, 3), draw_array(rng, n, S32_MIN, S32_MAX)).tolist()
    err, mag, omega = (draw(rng, n, S32_MIN, S32_MAX) for _ in range(3))
    qa, qb = random_cic_q(rng, n).tolist(), random_cic_q(rng, n).tolist()
    i_d, i_q = (draw(rng, n, S32_MIN, S32_MAX, S16_EDGES) for _ in range(2))
    cancel_at = rng.random(n) < 0.05
    pair = CicPair()
    count = dict.fromkeys(("w_max", "w_min", "z_max", "z_min", "e_max", "e_min", "held", "weak", "cancel",
                           "q_sat"), 0)
    for k in range(n):
        if k % 10 == 0:
            p_set = random_cic(rng)
        p, iq = p_set, i_q[k]
        state = dict(theta_o=theta_o[k], w=w[k], z=z[k], hold=hold[k], err=err[k], mag=mag[k], theta=theta[k],
                     omega=omega[k])
        if cancel_at[k]:
            p, crafted, iq = _cic_cancel_case(rng, p, qa[k], qb[k], 1 if rng.random() < 0.5 else -1)
            state.update(crafted)
        est = pair.load(p, state)
        out = pair.step(est, qa[k], qb[k], i_d[k], iq)
        ctx = (seed, k, p, state, qa[k], qb[k], i_d[k], iq)
        assert pair.diff(est) == {} and out == (est.theta, est.omega), (ctx, pair.diff(est), out)
        count["w_max"] += est.w == S64_MAX
        count["w_min"] += est.w == S64_MIN
        count["z_max"] += est.z == S64_MAX
        count["z_min"] += est.z == S64_MIN
        count["e_max"] += est.err == S32_MAX
        count["e_min"] += est.err == S32_MIN
        count["held"] += state["hold"] > 0
        count["weak"] += state["hold"] <= 0 and est.mag < p.q_min
        count["cancel"] += not S64_MIN <= state["w"] + est.z <= S64_MAX and S64_MIN < est.w < S64_MAX
        count["q_sat"] += max(abs(qa[k]), abs(qb[k])) > 1 << 28
    assert min(count.values()) > 1000, count


def test_cic_sync_turn_random(seed):
    """fw_cic_sync / fw_cic_turn = SquareWaveCic.sync / turn on N_RANDOM random states, angles, speeds
    (s32, with k_delay over s32) and turns."""
    rng = np.random.default_rng(seed + 51)
    n = N_RANDOM
    theta_o, theta, arg = (draw(rng, n, 0, U32_MAX, (HALF_TURN,)) for _ in range(3))
    w, z = (draw(rng, n, S64_MIN, S64_MAX, W_SPECIALS) for _ in range(2))
    hold, err, mag, omega, speed = (draw(rng, n, S32_MIN, S32_MAX) for _ in range(5))
    pair = CicPair()
    for k in range(n):
        if k % 10 == 0:
            p = random_cic(rng)
        state = dict(theta_o=theta_o[k], w=w[k], z=z[k], hold=hold[k], err=err[k], mag=mag[k], theta=theta[k],
                     omega=omega[k])
        est = pair.load(p, state)
        if k % 2:
            est.sync(arg[k], speed[k])
            lib.fw_cic_sync(pair.st, pair.cp, arg[k], speed[k])
        else:
            est.turn(arg[k])
            lib.fw_cic_turn(pair.st, arg[k])
        assert pair.diff(est) == {}, (seed, k, p, state, arg[k], speed[k], pair.diff(est))
    assert lib.fw_cic_i_d(pair.cp) == SquareWaveCic(p).i_d == p.i_d      # estimator.sqw_cic.i_d_min, drawn in random_cic



@pytest.mark.parametrize("p, state, qa, qb, i_d, i_q", [
    # the scenario's values, restarting (hold) and running, the signal below and above q_min
    (CIC_HOST, dict(hold=4), 1000, 2000, 300, -200),
    (CIC_HOST, dict(theta_o=123_456_789, w=5 << 24), 100, -50, 300, -200),
    (CIC_HOST, dict(theta_o=123_456_789, w=-(5 << 24)), 100_000, -50_000, -32768, 32767),
    # the products at their documented limits: c_t i_q = +-2^61, c_r i_d i_q = +-2^62, c2 e = 2^62
    (replace(CIC_HOST, c_t=CIC_CT_MAX, c_r=CIC_CR_MAX), {}, 1, 0, -32768, -32768),
    (replace(CIC_HOST, c_t=-CIC_CT_MAX, c_r=-CIC_CR_MAX), {}, 1, 0, -32768, -32768),
    (replace(CIC_HOST, c_t=-CIC_CT_MAX, c_r=CIC_CR_MAX), {}, 1, 0, 32767, -32768),
    (CicParams(g=S32_MAX, c1=S32_MIN, c2=S32_MIN, c3=S32_MIN, c_t=CIC_CT_MAX, c_r=CIC_CR_MAX, k_delay=S32_MIN,
               q_min=S32_MIN, n_hold=0), dict(theta_o=HALF_TURN), -(1 << 20), 0, S32_MIN, S32_MIN),
    # w and z saturate both ways and stay saturated; omega = sat(w >> 24) at the s32 edges
    (CicParams(g=S32_MAX, c1=S32_MAX, c2=S32_MAX, c3=S32_MAX, c_t=CIC_CT_MAX, c_r=0, k_delay=S32_MAX, q_min=0,
               n_hold=0), dict(theta_o=1 << 30, w=S64_MAX, z=S64_MAX), (1 << 20) - 1, 0, 0, S32_MAX),
    (CicParams(g=S32_MAX, c1=S32_MAX, c2=S32_MAX, c3=S32_MAX, c_t=CIC_CT_MAX, c_r=0, k_delay=S32_MAX, q_min=0,
               n_hold=0), dict(theta_o=3 << 30, w=S64_MIN, z=S64_MIN), (1 << 20) - 1, 0, 0, S32_MIN),
    # the quadrature signal beyond s29 (saturated), (0, 0) with q_min 0 and 1
    (CIC_HOST, {}, S32_MIN, S32_MAX, 0, 0),
    (replace(CIC_HOST, q_min=0), {}, 0, 0, 0, 0),
    (replace(CIC_HOST, q_min=1), {}, 0, 0, 0, 0),
])
def test_cic_step_corners(p, state, qa, qb, i_d, i_q):
    """fw_cic_step = SquareWaveCic.step at the corners of the documented ranges, twice in a row."""
    pair = CicPair()
    est = pair.load(p, state)
    for _ in range(2):
        out = pair.step(est, qa, qb, i_d, i_q)
        assert pair.diff(est) == {} and out == (est.theta, est.omega), (pair.diff(est), out)


def test_rot_observer_of_the_scenario():
    """scenarios/tap2023_step.toml tracks with the motion observer: its gains (golden.control_config.motion_gains,
    8 Hz) are ROT_MOTION_HOST, inside the ranges control.h documents, and convert into struct fw_params
    unchanged."""
    p = firmware_params(load_scenario(ROOT / "scenarios" / "tap2023_step.toml"))
    r = p.rot
    assert r is not None and r.tracking == rot_bpf.TRACK_OBSERVER
    assert {k: getattr(r, k) for k in ROT_MOTION_HOST} == ROT_MOTION_HOST
    cp = fw_c.params_to_c(ffi, p)
    assert (cp.rot.tracking, cp.rot.c1, cp.rot.c2, cp.rot.c3, cp.rot.c_t, cp.rot.c_r) == \
        (r.tracking, r.c1, r.c2, r.c3, r.c_t, r.c_r)


def test_cic_params_of_the_scenario():
    """The host's parameters of scenarios/xue2022_noload.toml lie in the ranges control.h documents (c_t
    beyond int32 with the torque feed-forward on), convert into struct fw_params unchanged, and the C
    firmware equals the golden one on a run of synthetic windows through start-up (pilot polarity) and 300
    windows of RUN: a quadrature signal turning with the rotor at 100 r/min with noise, small window-mean
    currents."""
    # the fault checks off: the synthetic windows below are no motor's (their currents jump at random)
    p = replace(firmware_params(load_scenario(ROOT / "scenarios" / "xue2022_noload.toml")), prot=ProtParams())
    c = p.cic
    assert p.low == METHOD_SQW_CIC and c is not None
    assert all(S32_MIN <= getattr(c, f) <= S32_MAX for f in ("g", "c1", "c2", "c3", "k_delay", "q_min", "n_hold"))
    assert abs(c.c_t) <= CIC_CT_MAX and abs(c.c_r) <= CIC_CR_MAX, c
    cp = fw_c.params_to_c(ffi, p)
    table = {f.name for f in dataclass_fields(c) if isinstance(getattr(c, f.name), tuple)}    # the xs table (empty)
    assert {f.name: getattr(cp.cic, f.name) for f in dataclass_fields(c) if f.name not in table} == \
        {k: v for k, v in vars(c).items() if k not in table}
    assert all(tuple(getattr(cp.cic, f)[0:len(getattr(c, f))]) == getattr(c, f) for f in table)
    rng = np.random.default_rng(7)
    pair, theta_r, step = Pair(p), 0.35, 2 * np.pi * 4 * 100 / 60 / 1000      # electrical rad per period
    running = 0
    for k in range(20_000):
        theta_r += step
        qa, qb = (int(v) for v in np.round((1 << 18) * np.array([np.cos(theta_r), np.sin(theta_r)])
                                           + rng.normal(0, 2000, 2)))
        n = 100
        i_d, i_q = (int(v) for v in rng.integers(-400, 400, size=2))
        w = WindowResult(gamma=0, gamma_d=0, sum_id=i_d * n, sum_iq=i_q * n, wsum=0, n_samples=n,
                         cic_qa=qa, cic_qb=qb, env_a=qa >> 4, env_b=qb >> 4)
        pair.step(w, 200_000, (k,))
        running += pair.fw.mode == MODE_RUN
        if running == 300:
            break
    assert running == 300 and pair.fw.mode == MODE_RUN, (k, pair.fw.mode)


# ---- the 003 method (Varatharajan et al. 2020): vector choice, flux LUT, applied flux, hfo_proj, fcs_mpc --------
SYRM_SCENARIO = ROOT / "scenarios" / "varatharajan2020_torquestep.toml"


@functools.lru_cache(maxsize=None)
def _syrm_params() -> FirmwareParams:
    """golden.control_config.firmware_params of scenarios/varatharajan2020_torquestep.toml (law fcs_mpc, low
    hfo_proj, the LUT built by golden.flux_tables.flux_lut from the preset varatharajan2020_syrm)."""
    return firmware_params(load_scenario(SYRM_SCENARIO))


def _hfo_host() -> HfoParams:
    return _syrm_params().hfo


@functools.lru_cache(maxsize=None)
def _syrm_luts() -> tuple[FluxLut, ...]:
    """The host's LUT and the same map on the grids of the other coarse steps (0..3) that fit LUT_MAX_POINTS
    (golden.flux_tables.flux_lut with hfo_proj_params' arguments)."""
    from golden.control_config import flux_lsb, scales
    from golden.flux_tables import flux_lut as build_lut
    sc = load_scenario(SYRM_SCENARIO)
    t, sc_ = sc.estimator.params["hfo_proj"], scales(sc)
    luts = [_hfo_host().lut]
    for coarse in range(4):
        if coarse == luts[0].coarse:
            continue
        try:
            luts.append(build_lut(sc.plant["mag"], sc_.i_lsb, flux_lsb(sc), t["lut_step"], t["lut_knee"], coarse,
                                  t["lut_max_d"], t["lut_max_q"], t["map_scale_d"], t["map_scale_q"]))
        except ValueError:
            pass
    return tuple(luts)


def _lut_to_c(lut: FluxLut):
    c = ffi.new("struct fw_flux_lut *")
    fw_c._fill(c, lut)
    return c


def random_hfo(rng: np.random.Generator) -> HfoParams:
    """hfo_proj integers over the ranges control.h documents (struct fw_hfo_params), around the host's values
    (varatharajan2020_torquestep) with the extremes frequent; the host's LUT (or a coarser/finer grid of the
    same map) with its f_shift and l_shift, or (one in four) with any f_shift of control.h's range 0..16: at 16 the
    map's flux beyond the grid exceeds s32, where the C's Park of the flux leaves the fixed-point unit."""
    h = _hfo_host()
    luts = _syrm_luts()
    lut = luts[int(rng.integers(0, len(luts)))]
    if rng.random() < 0.25:
        lut = replace(lut, f_shift=int(rng.integers(0, 17)))
    return replace(h, lut=lut, c_lag=draw_one(rng, 0, 1 << 16, (h.c_lag, 0)),
                   r_f=draw_one(rng, 0, 1 << 26, (h.r_f,)), dt_f=draw_one(rng, 0, 1 << 28, (h.dt_f, 0)),
                   vth_f=draw_one(rng, 0, 1 << 28, (h.vth_f, 0)), c_g=draw_one(rng, 0, 1 << 16, (h.c_g,)),
                   phi_min=draw_one(rng, 0, U16_MAX, (h.phi_min, 0)), s_knee=draw_one(rng, 1, 1 << 23, (h.s_knee,)),
                   n_max=draw_one(rng, -1, 12, (h.n_max, 0)), g_b=draw_one(rng, 1, 1 << 26, (h.g_b,)),
                   wg_b=draw_one(rng, 1, 1 << 26, (h.wg_b,)), kp=draw_one(rng, 0, 1 << 20, (h.kp,)),
                   ki=draw_one(rng, 0, 1 << 20, (h.ki,)), k_delay=draw_one(rng, -(1 << 20), 1 << 20, (h.k_delay,)),
                   eps_max=draw_one(rng, 0, S32_MAX, (h.eps_max, 0)), hold=int(rng.random() < 0.7))


def random_fcs(rng: np.random.Generator) -> FcsParams:
    """fcs_mpc integers over the ranges control.h documents (struct fw_fcs_params): the host's table or a random
    one (t_d <= 0, t_q >= 0, |t| < 2^29), the scalars around the host's values."""
    h = _syrm_params().fcs
    if rng.random() < 0.5:
        shift, t_d, t_q = h.shift, h.t_d, h.t_q
    else:
        n = int(rng.integers(2, mtpa.MTPA_LEN + 1))
        shift = int(rng.integers(0, 21))
        t_d = tuple(-v for v in draw(rng, n, 0, (1 << 29) - 1))
        t_q = tuple(draw(rng, n, 0, (1 << 29) - 1))
    return replace(h, r_f=draw_one(rng, 0, 1 << 26, (h.r_f,)), r_v=draw_one(rng, 0, 1 << 20, (h.r_v,)),
                   dt_f=draw_one(rng, 0, 1 << 28, (h.dt_f, 0)), vth_f=draw_one(rng, 0, 1 << 28, (h.vth_f, 0)),
                   shift=shift, t_d=t_d, t_q=t_q, phi_min=draw_one(rng, 0, U16_MAX, (h.phi_min,)),
                   v_lim=draw_one(rng, 1, S16_MAX, (h.v_lim, 1)))


def test_state_voltage():
    """fw_state_voltage = state_voltage, all 8 states."""
    a, b = _out_pair()
    for state in range(8):
        lib.fw_state_voltage(state, a, b)
        assert (a[0], b[0]) == state_voltage(state)


LUT_I_MAX = 1 << 18
"""The currents control.h documents for the LUT (|i_d|, |i_q| <= 2^18; the step's are within +-46341)."""


def _lut_currents(rng: np.random.Generator, lut: FluxLut, n: int) -> list[int]:
    """Currents over +-2^18: on the grid, beyond it (extrapolated), at the knee and the grid's edges."""
    edge = flux_lut_mod.unwarp((max(lut.n_d, lut.n_q) - 1) << lut.shift, lut.knee, lut.coarse)
    specials = (lut.knee - 1, lut.knee, lut.knee + 1, -lut.knee, edge, edge + 1, -edge, 1 << lut.shift)
    grid = draw_array(rng, n, -edge - 2000, edge + 2000, specials)
    wide = draw_array(rng, n, -LUT_I_MAX, LUT_I_MAX, specials)
    return np.where(rng.random(n) < 0.7, grid, wide).tolist()


def test_lut_point_and_flux_random(seed):
    """fw_warp / fw_lut_flux / fw_lut_point / fw_projection_coefficients = warp / lut_flux / lut_point /
    projection_coefficients on N_RANDOM currents (inside and beyond the grid, every quadrant) with the LUT of
    the varatharajan2020_syrm preset (and its other coarse grids), l_shift around the host's."""
    rng = np.random.default_rng(seed + 62)
    luts = [(lut, _lut_to_c(lut)) for lut in _syrm_luts()]
    pt = ffi.new("struct fw_lut_point *")
    ld, lq = ffi.new("int64_t *"), ffi.new("int64_t *")
    a1, a2 = _out_pair()
    names = [f.name for f in dataclass_fields(flux_lut_mod.LutPoint)]
    per = N_RANDOM // len(luts) + 1
    beyond = inside = nonzero = 0
    for lut, c in luts:
        i_d, i_q = _lut_currents(rng, lut, per), _lut_currents(rng, lut, per)
        host_shift = lut.l_shift
        shifts = rng.integers(max(host_shift - 2, 0), host_shift + 3, size=per).tolist()
        for k in range(per):
            d, q = i_d[k], i_q[k]
            assert lib.fw_warp(abs(d), lut.knee, lut.coarse) == warp(abs(d), lut.knee, lut.coarse)
            lib.fw_lut_flux(c, d, q, ld, lq)
            assert (ld[0], lq[0]) == lut_flux(lut, d, q), (lut.coarse, d, q)
            want = lut_point(lut, d, q)
            lib.fw_lut_point(c, d, q, pt)
            got = {name: getattr(pt, name) for name in names}
            assert got == {name: getattr(want, name) for name in names}, (lut.coarse, d, q, got, want)
            lib.fw_projection_coefficients(pt, shifts[k], a1, a2)
            w = projection_coefficients(want, shifts[k])
            assert (a1[0], a2[0]) == w, (lut.coarse, d, q, shifts[k])
            nonzero += w != (0, 0)
            x, y = warp(abs(d), lut.knee, lut.coarse), warp(abs(q), lut.knee, lut.coarse)
            if x > (lut.n_d - 1) << lut.shift or y > (lut.n_q - 1) << lut.shift:
                beyond += 1
            else:
                inside += 1
    assert min(beyond, inside, nonzero) > 10_000, (beyond, inside, nonzero)


def test_applied_flux_random(seed):
    """fw_applied_flux = applied_flux on N_RANDOM state pairs, currents (s16 with zeros and the sign edges of
    the b and c phases) and dead-time / threshold fluxes (0..2^28)."""
    rng = np.random.default_rng(seed + 63)
    n = N_RANDOM
    old, new = (rng.integers(0, 8, size=n).tolist() for _ in range(2))
    i_al, i_be = (draw(rng, n, S16_MIN, S16_MAX) for _ in range(2))
    for k in range(0, n, 10):                 # i_b = 0 or i_c = 0 exactly: 56756 i_be = +-32768 i_al
        m = draw_one(rng, -8, 8)
        i_al[k], i_be[k] = 56756 * m, 32768 * m * (1 if k % 20 else -1)
        i_al[k], i_be[k] = i_al[k] // 4096, i_be[k] // 4096
    dt_f, vth_f = (draw(rng, n, 0, 1 << 28, (83886, 17088, 0)) for _ in range(2))
    a, b = _out_pair()
    for k in range(n):
        lib.fw_applied_flux(old[k], new[k], i_al[k], i_be[k], dt_f[k], vth_f[k], a, b)
        assert (a[0], b[0]) == applied_flux(old[k], new[k], i_al[k], i_be[k], dt_f[k], vth_f[k]), \
            (k, old[k], new[k], i_al[k], i_be[k], dt_f[k], vth_f[k])


def _fcs_to_c(p: FcsParams):
    c = ffi.new("struct fw_fcs_params *")
    fw_c._fill(c, p)
    c.len = len(p.t_d)
    return c


def test_flux_reference_and_deadbeat_random(seed):
    """fw_flux_reference / fw_deadbeat_voltage = flux_reference / deadbeat_voltage (and its sin, cos = sincos_q15 of the
    angle) on N_RANDOM inputs: random
    law parameters (a new set every 10), observed flux (s32, mostly the motor's), TOP_I s16, the states
    before top k, from it and from top k + 1 (VECTOR.NEXT), the angle, speed and current command; the voltage
    limit's shifts often."""
    rng = np.random.default_rng(seed + 64)
    n = N_RANDOM
    psi = [np.where(rng.random(n) < 0.8, draw_array(rng, n, -(1 << 27), 1 << 27), draw_array(rng, n, S32_MIN, S32_MAX))
           .tolist() for _ in range(2)]
    i_al, i_be = (draw(rng, n, S16_MIN, S16_MAX) for _ in range(2))
    before, vector, nxt = (rng.integers(0, 8, size=n).tolist() for _ in range(3))
    theta = draw(rng, n, 0, U32_MAX)
    omega, i_s = (draw(rng, n, S32_MIN, S32_MAX, (0,)) for _ in range(2))
    vd, vq = _out_pair()
    sn, cs = _out_pair()
    limited = 0
    for k in range(n):
        if k % 10 == 0:
            p = random_fcs(rng)
            cp = _fcs_to_c(p)
        lib.fw_flux_reference(cp, i_s[k], vd, vq)
        assert (vd[0], vq[0]) == flux_reference(p, i_s[k]), (k, p, i_s[k])
        want = deadbeat_voltage(p, psi[0][k], psi[1][k], i_al[k], i_be[k], before[k], vector[k], nxt[k], theta[k],
                                omega[k], i_s[k])
        lib.fw_deadbeat_voltage(cp, psi[0][k], psi[1][k], i_al[k], i_be[k], before[k], vector[k], nxt[k], theta[k],
                                omega[k], i_s[k], vd, vq, sn, cs)
        assert (sn[0], cs[0]) == sincos_q15(theta[k]), (k, theta[k])
        assert (vd[0], vq[0]) == want, (k, p, psi[0][k], psi[1][k], i_al[k], i_be[k], before[k], vector[k], nxt[k],
                                         theta[k], omega[k], i_s[k])
        limited += max(abs(want[0]), abs(want[1])) > p.v_lim // 2
    assert limited > 1000, limited


HFO_STATE = tuple(name for name, _ in ffi.typeof("struct fw_hfo_state").fields)


class HfoPair(_EstimatorPair):
    """HybridFluxProjection and fw_hfo_step / turn / sync on the same state (the hfo block of a fw_state)."""

    def __init__(self):
        super().__init__()
        self.flux = ffi.new("struct fw_est_flux *")

    def load(self, p: HfoParams, state: dict) -> HybridFluxProjection:
        if p is not self.p:
            fw_c._fill(self.cp.hfo, p)
            self.p = p
        est = HybridFluxProjection(p)
        for name, v in state.items():
            setattr(est, name, v)
        fw_c._estimator_into(self.st.hfo, est)            # every field (the others at their initial values)
        return est

    def step(self, est: HybridFluxProjection, vector: int, ia: int, ib: int) -> tuple[int, int]:
        self.win.vector, self.win.top_ia, self.win.top_ib = vector, ia, ib
        est.step(Measurement(WindowResult(0, 0, 0, 0, 0, 0, vector=vector, top_ia=ia, top_ib=ib), 0, 0, 0, 32767, 0, 0))
        lib.fw_hfo_step(self.st, self.cp, self.m, self.theta, self.omega)
        return self.theta[0], self.omega[0]

    def diff(self, est: HybridFluxProjection) -> dict:
        d = {k: (getattr(self.st.hfo, k), getattr(est, k)) for k in HFO_STATE if getattr(self.st.hfo, k) != getattr(est, k)}
        lib.fw_hfo_flux(self.st, self.flux)
        for k in ("psi_al", "psi_be", "fcs_a1", "fcs_a2", "constrain"):
            if getattr(self.flux, k) != getattr(est, k):
                d[("flux", k)] = (getattr(self.flux, k), getattr(est, k))
        return d


def _random_hfo_state(rng: np.random.Generator, p: HfoParams) -> dict:
    """A state over the fields' ranges: the PLL's speed mostly below the fusion's band (both models on), the
    flux mostly the motor's, the counters around n_max."""
    band = p.g_b + p.wg_b
    w_i = draw_one(rng, -2 * band, 2 * band, (0, band, -band, p.g_b - p.wg_b, 1)) if rng.random() < 0.8 \
        else draw_one(rng, -(1 << 38), 1 << 38)
    flux = (lambda: draw_one(rng, -(1 << 26), 1 << 26)) if rng.random() < 0.9 else (lambda: draw_one(rng, S32_MIN, S32_MAX))
    return dict(th=draw_one(rng, 0, U32_MAX), integ=(w_i << 24) + int(rng.integers(0, 1 << 24)),
                psi_al=flux(), psi_be=flux(), lam_al=flux(), lam_be=flux(),
                i_al=draw_one(rng, -3 << 15, 3 << 15), i_be=draw_one(rng, -3 << 15, 3 << 15),
                r_al=draw_one(rng, S16_MIN, S16_MAX), r_be=draw_one(rng, S16_MIN, S16_MAX),
                vec=int(rng.integers(0, 8)), vec_old=int(rng.integers(0, 8)),
                n_rej=draw_one(rng, 0, 1 << 16, (p.n_max, p.n_max + 1, 1 << 16)),
                since=draw_one(rng, 0, 1 << 16, (p.n_max - 1, p.n_max, 1 << 16)), th_meas=draw_one(rng, 0, U32_MAX),
                cons_wait=int(rng.integers(0, 3)), theta=draw_one(rng, 0, U32_MAX), omega=draw_one(rng, S32_MIN, S32_MAX))


HFO_SEQ = 10
HFO_CHUNKS = 4


@pytest.mark.parametrize("chunk", range(HFO_CHUNKS))
def test_hfo_step_random(seed, chunk):
    """fw_hfo_step = HybridFluxProjection.step on N_RANDOM steps (in HFO_CHUNKS chunks): sequences of HFO_SEQ steps from random
    states (a new parameter set every ten sequences) with random TOP_I (mostly within +-4000, the s16
    extremes) and VECTOR; every state field (the diagnostics eps_h, eps_t, f, e_d, s_h too), the outputs and
    the flux outputs compared after every step; the branches (valid, knee, hold, APP, constraint) each often."""
    rng = np.random.default_rng(seed + 65 + 1000 * chunk)
    pair = HfoPair()
    count = dict.fromkeys(("valid", "knee", "held", "app", "constrain", "fused"), 0)
    for q in range(N_RANDOM // (HFO_SEQ * HFO_CHUNKS)):
        if q % 10 == 0:
            p = random_hfo(rng) if q % 20 else _hfo_host()
        est = pair.load(p, _random_hfo_state(rng, p))
        big = rng.random() < 0.2
        for k in range(HFO_SEQ):
            ia, ib = (draw(rng, 2, S16_MIN, S16_MAX) if big else rng.integers(-4000, 4001, size=2).tolist())
            vec = int(rng.integers(0, 8))
            since = est.since
            out = pair.step(est, vec, ia, ib)
            assert pair.diff(est) == {} and out == (est.theta, est.omega), (seed, q, k, p, pair.diff(est))
            count["valid"] += est.n_rej == 0
            count["knee"] += est.n_rej == 0 and abs(est.s_h) < p.s_knee
            count["held"] += est.n_rej > 0 and est.eps_h != 0 and since < p.n_max
            count["app"] += est.eps_t != 0
            count["constrain"] += est.constrain
            count["fused"] += 0 < est.f < 1 << 16
    assert min(count.values()) > 100, count


def test_hfo_idle_writes_nothing(seed):
    """fw_hfo_idle and fw_idle (the idle loop's work, beside golden: docs/methods.md) leave every byte of the state
    as it was, from random states with the PLL's speed anywhere and (every other one) just below the fusion band's
    lower edge, where the step warms the 003 step's code."""
    rng = np.random.default_rng(seed + 67)
    pair = HfoPair()
    warmed = 0
    for q in range(400):
        if q % 20 == 0:
            p = random_hfo(rng) if q % 40 else _hfo_host()
            pair.cp.low = METHOD_HFO_PROJ
        state = _random_hfo_state(rng, p)
        edge = p.g_b - p.wg_b
        if q % 2 and edge >= 4:                             # inside the warmed range: the step runs on a copy
            w = int(rng.integers(edge // 2 + 1, edge + 1)) * (1 if rng.random() < 0.5 else -1)
            state["integ"] = (w << 24) + int(rng.integers(0, 1 << 24))
            warmed += 1
        pair.load(p, state)
        before = bytes(ffi.buffer(pair.st))
        (lib.fw_hfo_idle if q % 3 else lib.fw_idle)(pair.st, pair.cp)
        assert bytes(ffi.buffer(pair.st)) == before, (seed, q)
    assert warmed > 100


def test_hfo_sync_turn_random(seed):
    """fw_hfo_sync / fw_hfo_turn = HybridFluxProjection.sync / turn on N_RANDOM random angles and speeds, from
    a new random state every 20 operations."""
    rng = np.random.default_rng(seed + 66)
    pair = HfoPair()
    for k in range(N_RANDOM):
        if k % 1000 == 0:
            p = random_hfo(rng)
        if k % 20 == 0:                                     # a new random state, then 20 operations on it
            est = pair.load(p, _random_hfo_state(rng, p))
        arg, speed = draw_one(rng, 0, U32_MAX, (HALF_TURN,)), draw_one(rng, S32_MIN, S32_MAX)
        if k % 2:
            est.sync(arg, speed)
            lib.fw_hfo_sync(pair.st, pair.cp, arg, speed)
        else:
            est.turn(arg)
            lib.fw_hfo_turn(pair.st, arg)
        assert pair.diff(est) == {}, (seed, k, arg, speed, pair.diff(est))
    assert lib.fw_hfo_i_d(pair.cp) == HybridFluxProjection(p).i_d == 0


@pytest.mark.parametrize("chunk", range(2))
def test_fw_step_fcs_hfo_sequences(seed, chunk):
    """The whole firmware with the 003 scenario's parameters (law fcs_mpc, low hfo_proj, no polarity detection;
    golden.control_config.firmware_params of varatharajan2020_torquestep, start-up shortened): C = golden on
    random window results (VECTOR 0..7, TOP_I s16) and speed references, outputs and state after every step,
    through CONVERGE, RELAX and RUN."""
    rng = np.random.default_rng(seed + 67 + chunk)
    base = _syrm_params()
    assert base.law == LAW_FCS_MPC and base.low == METHOD_HFO_PROJ and base.pol_mode == POL_NONE
    cp = fw_c.params_to_c(ffi, base)
    lut = base.hfo.lut
    assert (cp.hfo.lut.n_d, cp.hfo.lut.n_q, cp.hfo.lut.coarse) == (lut.n_d, lut.n_q, lut.coarse)
    assert list(cp.hfo.lut.t_ldq[0:len(lut.t_ldq)]) == list(lut.t_ldq) and cp.fcs.len == len(base.fcs.t_d)
    visited, fused, constrained = set(), 0, 0
    for q in range(N_RANDOM // (4 * SEQ_LEN)):
        p = replace(base, n_converge=int(rng.integers(-1, 6)), n_settle=int(rng.integers(-1, 6)))
        pair = Pair(p)
        speed_ref = draw_one(rng, -(1 << 22), 1 << 22, (0,))
        for k, w in enumerate(random_windows(rng, SEQ_LEN, p.i_trip, 0, healthy_vdc(p))):
            if rng.random() < 0.05:
                speed_ref = draw_one(rng, -(1 << 22), 1 << 22, (0,))
            out = pair.step(w, speed_ref, (seed, chunk, q, k))
            visited.add(pair.fw.mode)
            fused += 0 < pair.fw.slots[SLOT_LOW].f
            constrained += out.fcs_constrain
    assert {MODE_CONVERGE, MODE_RELAX, MODE_RUN} <= visited, visited
    assert fused > 100 and constrained > 0, (fused, constrained)


def test_hfo_fcs_params_of_the_scenario():
    """The host's hfo_proj and fcs_mpc integers of varatharajan2020_torquestep lie in the ranges control.h
    documents and convert into struct fw_params unchanged (the LUT and the flux reference table included)."""
    p = _syrm_params()
    h, f, lut = p.hfo, p.fcs, p.hfo.lut
    assert 0 <= h.c_lag <= 1 << 16 and 0 <= h.dt_f <= 1 << 28 and 0 <= h.vth_f <= 1 << 28
    assert 0 <= lut.f_shift <= 16 and 0 <= lut.l_shift <= 16
    assert 0 <= h.phi_min <= U16_MAX and 1 <= h.s_knee <= 1 << 23 and h.wg_b >= 1 and h.eps_max >= 0
    assert all(S32_MIN <= getattr(h, k) <= S32_MAX for k in ("r_f", "c_g", "kp", "ki", "k_delay", "g_b", "wg_b"))
    assert lut.n_d * lut.n_q <= LUT_MAX_POINTS and lut.shift <= 12 and 0 <= lut.coarse <= 4
    assert max(abs(v) for t in (lut.t_d, lut.t_q) for v in t) < 1 << 15
    assert max(abs(v) for t in (lut.t_ld, lut.t_lq, lut.t_ldq) for v in t) < 1 << 28
    assert 2 <= len(f.t_d) == len(f.t_q) <= mtpa.MTPA_LEN and max(map(abs, f.t_d + f.t_q)) < 1 << 29
    assert 0 <= f.dt_f <= 1 << 28 and 0 <= f.vth_f <= 1 << 28 and 1 <= f.v_lim <= S16_MAX and 0 <= f.phi_min <= U16_MAX
    cp = fw_c.params_to_c(ffi, p)
    assert (cp.law, cp.pol_mode, cp.low) == (LAW_FCS_MPC, POL_NONE, METHOD_HFO_PROJ)
    for name in ("t_d", "t_q", "t_ld", "t_lq", "t_ldq"):
        assert list(getattr(cp.hfo.lut, name)[0:lut.n_d * lut.n_q]) == list(getattr(lut, name)), name
    assert {k: getattr(cp.hfo, k) for k in vars(h) if k != "lut"} == {k: v for k, v in vars(h).items() if k != "lut"}
    assert list(cp.fcs.t_d[0:cp.fcs.len]) == list(f.t_d) and list(cp.fcs.t_q[0:cp.fcs.len]) == list(f.t_q)


# ---- self-commissioning: the identification program (golden.firmware.ident, MODE_IDENT / MODE_DONE) -----------
F = ident_mod
IDENT_PROGRAMS = 400


def random_ident(rng: np.random.Generator) -> IdentParams:
    """A random program that IdentParams accepts: 1..12 steps (one in twenty 100..IDENT_MAX one-window steps, the
    arrays' ends), each of 1..6 windows and 0..n summed, s16 currents (mostly small, sometimes the extremes), any
    amplitude, angle and speed change (the frame speed saturates), random flags; F_SNAP only on steps of n >= 2,
    F_FIT and F_POL only from the second step on, an F_FIT step's amplitude above its predecessor's (kp >= 0);
    gain constants over their ranges."""
    long = rng.random() < 0.05
    n = int(rng.integers(100, IDENT_MAX + 1)) if long else int(rng.integers(1, 13))
    s_n = [1] * n if long else [int(v) for v in rng.integers(1, 7, size=n)]
    s_m = [int(rng.integers(0, k + 1)) for k in s_n]
    cur = [draw(rng, n, -(1 << 15), (1 << 15) - 1, (0,)) if rng.random() < 0.6
           else draw(rng, n, -3000, 3000, (0,)) for _ in range(2)]
    s_vh = draw(rng, n, 0, S16_MAX, (0, 1, 300))
    s_phi = draw(rng, n, 0, U32_MAX, (0, 1 << 30, 1 << 31, 3 << 30))
    s_dw = draw(rng, n, -(1 << 16), 1 << 16, (0,)) if rng.random() < 0.7 else draw(rng, n, S32_MIN, S32_MAX)
    base = (F.F_SET, F.F_SCAN, F.F_NEG, F.F_OPEN, F.F_LEVEL, F.F_SNAP, F.F_GAIN, 64)   # 64: unused, both ignore it
    s_flags = []
    for k in range(n):
        f = sum(b for b in base if rng.random() < 0.4 and (b != F.F_SNAP or s_n[k] >= 2))
        if k > 0 and s_vh[k - 1] < S16_MAX and rng.random() < 0.3:
            f |= F.F_FIT
            s_vh[k] = max(s_vh[k], s_vh[k - 1] + 1)
        if k > 0 and rng.random() < 0.3:
            f |= F.F_POL
        s_flags.append(f)
    return IdentParams(s_n=tuple(s_n), s_m=tuple(s_m), s_id=tuple(cur[0]), s_iq=tuple(cur[1]), s_vh=tuple(s_vh),
                       s_phi=tuple(s_phi), s_dw=tuple(s_dw), s_flags=tuple(s_flags),
                       c_kp=draw_one(rng, 0, (1 << 46) - 1, (0, 1 << 30)), c_ki=draw_one(rng, 0, 1 << 16, (4096,)),
                       c_gain=draw_one(rng, 0, (1 << 46) - 1, (0, 1 << 30)),
                       v_lim=draw_one(rng, 1, S16_MAX, (2000,)), c_lvl=draw_one(rng, 0, (1 << 46) - 1, (1 << 36,)),
                       lvl_max=draw_one(rng, 0, 1 << 24, (1 << 16, 1 << 24)),
                       i_slew=draw_one(rng, 1, 1 << 20, (1, 100, 1 << 20)), vh_max=draw_one(rng, 0, S16_MAX, (S16_MAX, 3000)))


def ident_windows(rng: np.random.Generator, count: int, i_trip: int, vdc: int) -> list[WindowResult]:
    """:func:`random_windows` with s16 current means (the hardware's: sums of s16 samples; control.h) and
    GAMMA, GAMMA_D within +-scale (2^20, 2^23: around the noise sum's 24-bit saturation, or all of s32), GAMMA_D
    mostly of one sign (biased positive in two programs of three: the probe and the scan see a response, the
    program runs on)."""
    scale = int(rng.choice([1 << 20, 1 << 23, 1 << 31]))
    bias = scale // 2 if rng.random() < 2 / 3 else draw_one(rng, -scale // 2, scale // 2)
    g = draw(rng, count, max(-scale, S32_MIN), min(scale, S32_MAX))
    gd = draw_array(rng, count, -scale // 2, scale // 2)
    gd = np.clip(np.where(rng.random(count) < 0.8, gd // 8, gd) + bias, S32_MIN, S32_MAX).tolist()
    windows = random_windows(rng, count, min(i_trip, S16_MAX), 0, vdc)
    return [replace(w, gamma=a, gamma_d=b) for w, a, b in zip(windows, g, gd)]


def test_ident_random_programs(seed):
    """IDENT_PROGRAMS random programs (random_ident) on random parameter sets (sometimes with FIXED, whose angle
    the program overrides, and with restarts after a fault): fw_step = Firmware.step through the program, a few
    windows of DONE after it, trips by the overcurrent or STATUS in IDENT and DONE (one program in eight); every
    output and every state field (the executor's scalars and sum arrays included) after every step."""
    rng = np.random.default_rng(seed + 300)
    seen, codes, flips, gains = set(), set(), 0, 0
    for q in range(IDENT_PROGRAMS):
        base = random_params(rng, fixed=q % 7 == 0, prot=q % 3 == 0)
        ip = random_ident(rng)
        p = replace(base, ident=ip)
        pair = Pair(p)
        assert pair.fw.mode == MODE_IDENT == pair.st.mode
        total = sum(ip.s_n) + int(rng.integers(0, 6))
        trip_in = (None, MODE_IDENT, MODE_DONE)[int(rng.integers(0, 3))] if q % 8 == 0 else None
        speed_ref = draw_one(rng, S32_MIN, S32_MAX)
        for k, w in enumerate(ident_windows(rng, total, p.i_trip, healthy_vdc(p))):
            before = pair.fw.mode
            if before == trip_in and rng.random() < 0.2:
                w = trip_window(rng, p.i_trip)
            pair.step(w, speed_ref, (seed, q, k, p))
            seen.add(pair.fw.mode)
            if pair.fw.mode == MODE_FAULT and before != MODE_FAULT:
                codes.add((before, pair.fw.fault))
        if pair.fw.ident is not None:
            flips += pair.fw.ident.theta_r >= 1 << 31
            gains += pair.fw.ident.kp > 0
    assert {MODE_IDENT, MODE_DONE, MODE_FAULT} <= seen, seen
    assert (MODE_IDENT, protection.FAULT_IDENT) in codes, codes
    assert {(MODE_IDENT, protection.FAULT_HARDWARE), (MODE_DONE, protection.FAULT_HARDWARE)} & codes, codes
    assert flips > 0 and gains > 0, (flips, gains)


def _ident_params(ip: IdentParams, **kw) -> FirmwareParams:
    return _params(**{"ident": ip, "i_trip": 1 << 20, **kw})


def _program(steps, **kw) -> IdentParams:
    """An IdentParams from (n, m, i_d, i_q, v_h, phi, dw, flags) rows."""
    cols = list(zip(*steps))
    return IdentParams(*(tuple(c) for c in cols), **{"c_kp": 1 << 30, "c_ki": 4096, "v_lim": 2000,
                                                      "lvl_max": 1 << 20, "i_slew": 150, **kw})


def test_ident_probe_without_response_trips():
    """F_LEVEL with sum GAMMA_D <= 0 over its summed windows: FAULT with FAULT_IDENT at the step's end, the
    reset outputs (gates off); the same in C."""
    for gd in (0, -1, -5000):
        ip = _program([(4, 2, 0, 0, 300, 0, 0, F.F_SET | F.F_OPEN | F.F_LEVEL), (3, 3, 0, 0, 300, 0, 0, F.F_OPEN)],
                      c_lvl=1 << 36)
        pair = Pair(_ident_params(ip))
        for k in range(4):
            out = pair.step(_win(gamma=7, gamma_d=gd if k >= 2 else 10 ** 6, sum_id=30), 0, (gd, k))
        assert pair.fw.mode == MODE_FAULT and pair.fw.fault == protection.FAULT_IDENT == pair.st.fault
        assert out == Outputs(0, 0, 0, 0, 32767, 0) and pair.fw.ident.failed == 1
        assert ffi.string(lib.fw_fault_name(pair.st.fault)).decode() == "ident"
        pair.step(_win(), 0)
        assert pair.fw.mode == MODE_FAULT


def test_ident_program_runs_to_done():
    """A commissioning-like program: a probe (F_LEVEL), a scan of four angles in pairs at v_h and 2 v_h (F_SCAN,
    F_NEG; F_FIT on the last), a polarity pair under current control (F_POL), a moving step (dw), a frame jump by
    three quarters of a turn; the response depends on the frame angle, so the fit and the gains are non-trivial. C = golden
    every window; then DONE with the gates off."""
    steps = [(6, 3, 0, 0, 200, 0, 0, F.F_SET | F.F_OPEN | F.F_LEVEL)]
    for j in range(4):
        phi = j << 30 >> 1                       # 0, 45, 90, 135 deg
        steps += [(4, 2, 0, 0, 1000, phi, 0, F.F_SET | F.F_OPEN | F.F_SCAN | F.F_NEG),
                  (4, 2, 0, 0, 2000, phi, 0, F.F_SET | F.F_OPEN | F.F_SCAN | (F.F_FIT if j == 3 else 0))]
    steps += [(5, 3, 400, 0, 1000, 0, 0, F.F_SET), (5, 3, -400, 0, 1000, 0, 0, F.F_SET | F.F_POL),
              (8, 4, 0, 300, 1000, 0, 5000, F.F_SET), (6, 2, 300, 0, 0, 1 << 28, 0, F.F_SET | F.F_SNAP),
              (4, 2, 200, 0, 0, 3 << 30, 0, F.F_SET)]
    ip = _program(steps, c_lvl=1 << 29, vh_max=3000)
    pair = Pair(_ident_params(ip))
    theta_true = 1 << 29
    n = 0
    while pair.fw.mode == MODE_IDENT:
        act = pair.fw.act[0]
        ang = (act.sin, act.cos)
        phase = (uwrap(theta_true, 32) - (int(np.arctan2(ang[0], ang[1]) / (2 * np.pi) * 2 ** 32))) % (1 << 32)
        resp = int(act.v_h * (20 + 5 * np.cos(2 * np.pi * phase / 2 ** 32 * 2)))
        i_d = act.v_d // 4
        pair.step(_win(gamma=resp // 3, gamma_d=resp, sum_id=i_d * 10, sum_iq=-i_d * 5), 0, n)
        n += 1
        assert n < 200
    assert n == sum(ip.s_n)
    idn = pair.fw.ident
    assert pair.fw.mode == MODE_DONE and idn.done == 1 and idn.failed == 0 and idn.k == ip.n_steps
    assert idn.lvl != 1 << 16 and idn.kp > 0 and idn.ki > 0 and idn.g2 > 0
    for _ in range(3):
        assert pair.step(_win(gamma=5, gamma_d=5), 0) == Outputs(0, 0, 0, 0, 32767, 0)
    assert pair.fw.mode == MODE_DONE


def test_ident_block_converters():
    """new_state / state_to_c / state_from_c: fw_state.ident NULL <-> None; a program's block (n_steps included)
    kept alive with the state; fw_init keeps the pointer and starts the program, and starts CONVERGE without one
    (a params block does not carry the program)."""
    ip = _program([(3, 2, 100, -5, 1000, 7, 3, F.F_SET | F.F_OPEN), (2, 1, 0, 0, 0, 0, 0, F.F_SET)])
    st = fw_c.new_state(ffi, _params())
    assert st.ident == ffi.NULL and fw_c.state_from_c(st, _params()).ident is None
    p = _ident_params(ip)
    st = fw_c.new_state(ffi, p)
    block = st.ident
    gc.collect()
    assert fw_c.ident_params_from_c(block.p) == ip and block.p.n_steps == 2
    lib.fw_init(st, fw_c.params_to_c(ffi, p))
    assert st.ident == block and st.mode == MODE_IDENT and block.s.lvl == 1 << 16
    assert fw_c.state_from_c(st, replace(p, ident=None)).ident.p == ip     # the program from the block
    assert fw_c.state_from_c(st, p).ident == Firmware(p).ident
    fw = Firmware(p)
    fw.ident.r_gd[5], fw.ident.g2 = -(1 << 40), 1 << 50
    c = fw_c.state_to_c(ffi, fw)
    assert fw_c.ident_params_from_c(c.ident.p) == ip and fw_c.state_from_c(c, p).ident == fw.ident
    assert fw_c.state_to_c(ffi, Firmware(_params())).ident == ffi.NULL


def test_ident_programs_refused():
    """The programs the C does not handle (control.h) are refused by IdentParams: F_FIT or F_POL on step 0 (no step
    before), F_FIT not above the step before, F_SNAP with n < 2, currents beyond s16, m beyond M_MAX."""
    ok = (3, 2, 0, 0, 1000, 0, 0, F.F_SET | F.F_OPEN | F.F_SCAN)
    _program([ok, (3, 2, 0, 0, 2000, 0, 0, F.F_SET | F.F_OPEN | F.F_SCAN | F.F_FIT | F.F_POL)])
    _program([(F.M_MAX + 1, F.M_MAX, -(1 << 15), (1 << 15) - 1, 0, 0, 0, F.F_SET | F.F_SNAP)])
    for steps in ([(3, 2, 0, 0, 3000, 0, 0, F.F_SET | F.F_OPEN | F.F_SCAN | F.F_FIT), ok],
                  [(3, 2, 0, 0, 3000, 0, 0, F.F_SET | F.F_POL), ok],
                  [ok, (3, 2, 0, 0, 1000, 0, 0, F.F_SET | F.F_OPEN | F.F_SCAN | F.F_FIT)],
                  [ok, (1, 0, 0, 0, 0, 0, 0, F.F_SET | F.F_SNAP)],
                  [ok, (3, 2, 1 << 15, 0, 0, 0, 0, F.F_SET)], [ok, (3, 2, 0, -(1 << 15) - 1, 0, 0, 0, F.F_SET)],
                  [ok, (F.M_MAX + 1, F.M_MAX + 1, 0, 0, 0, 0, 0, F.F_SET)]):
        with pytest.raises(ValueError):
            _program(steps)


def test_ident_sums_at_their_limits():
    """A step of M_MAX + 1 windows summed over M_MAX at the extremes the formats allow (control.h): s16 current
    means, the voltages at the PI limit 32767 (a scan pair first sets the largest kp; the current errors of
    65535), s32 responses (the noise sum saturates them to 24 bits, the scan sums reach 2^61); a fit after it.
    C = golden: the outputs every window, the state every 1000."""
    n = F.M_MAX + 1
    ip = _program([(3, 2, 0, 0, 1000, 0, 0, F.F_SET | F.F_OPEN | F.F_SCAN | F.F_NEG),
                   (3, 2, 0, 0, 2000, 0, 0, F.F_SET | F.F_OPEN | F.F_SCAN | F.F_FIT),
                   (n, F.M_MAX, -(1 << 15), (1 << 15) - 1, 1000, 0, 0, F.F_SET | F.F_SCAN),
                   (4, 3, 0, 0, 2000, 0, 0, F.F_SET | F.F_SCAN | F.F_FIT)],
                  v_lim=S16_MAX, c_kp=(1 << 46) - 1, c_ki=1 << 16, i_slew=1 << 20)
    pair = Pair(_ident_params(ip, i_trip=S32_MAX))
    for k in range(6):
        pair.step(_win(gamma=0, gamma_d=1000 if k < 3 else 5000), 0, k)
    assert pair.fw.ident.kp == F.KP_MAX
    w = _win(gamma=S32_MIN, gamma_d=S32_MAX, sum_id=S16_MAX, sum_iq=S16_MIN, n=1)
    for k in range(n + 4):
        want = pair.fw.step(w, 0)
        lib.fw_step(pair.st, pair.cp, fw_c.window_to_c(ffi, w, pair.win), 0, pair.out)
        assert fw_c.outputs_from_c(pair.out) == want, k
        if k % 1000 == 0 or k >= n - 2:
            pair.check_state(k)
    idn = pair.fw.ident
    assert pair.fw.mode == MODE_DONE and idn.failed == 0
    assert (idn.r_id[2], idn.r_iq[2]) == (S16_MAX * F.M_MAX, S16_MIN * F.M_MAX)
    assert idn.r_vd[2] < -S16_MAX * (F.M_MAX - 4) and idn.r_vq[2] > S16_MAX * (F.M_MAX - 4)
    assert idn.r_gd[2] == S32_MAX * F.M_MAX and idn.fit_x > 1 << 60
    assert idn.g2 >= F.M_MAX * ((1 << 2 * (F.G2_BITS - 1) + 1) - (1 << F.G2_BITS)) >> F.G2_SHIFT