"""``hfi sweep SPEC.toml``: a grid or a random design over scenario parameters, run on Dask (docs/sweep.md).

A sweep spec names a base scenario file, values that replace the file's for every run (``[set]``), and the
parameters to vary (``[params]``), each by its dotted scenario path (``"load.torque"``, ``"injection.V_h"``,
``"estimator.rot_bpf.f_inj"``):

* a list of values: each replaces the base value (grid axis; a random design picks one);
* ``{ scale = [f1, f2, ...] }``: the base value times each factor, in its own unit; on a profile the
  value column is scaled (``load.torque`` of a scenario whose load rises to rated: the p.u. load);
* ``{ uniform = [lo, hi] }`` and ``{ scale_uniform = [lo, hi] }`` (random design only): a value drawn
  uniformly, or the base value times a factor drawn uniformly (a +-20 % parameter error).

Designs: ``grid`` (every combination), ``random`` (``samples`` points drawn), ``one_at_a_time`` (the base
point, then each value of each axis alone: a sensitivity study; constants go in ``[set]``).

Each point runs ``seeds`` times with seeds ``scenario.seed + 1000 + k`` and an initial rotor angle drawn from
that seed (as ``scripts/seed_sweep.py``); without ``seeds`` a point runs once with the scenario's own seed
and angle. Every run is a pure function of its scenario tree, backend, metric windows and the source
version, and is cached under that hash in ``OUT/runs/``: an interrupted sweep resumes where it stopped.
A run that fails (invalid scenario, a backend that does not run the method, an exception) is a row with
its ``error``, never dropped. The rows go to ``OUT/results.parquet`` (one row per run: the point's
parameters, seed, initial angle, every scalar metric of ``metrics.json`` flattened with dots, and the
spec's angle-error windows).

The local cluster starts worker *processes*: a script that calls :func:`sweep` needs the
``if __name__ == "__main__":`` guard (Python's spawn start method imports the main module again).
"""

from __future__ import annotations

import copy
import hashlib
import itertools
import json
import math
import os
import re
import subprocess
import sys
import time
import tomllib
import warnings
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from golden.firmware.estimator import METHODS
from golden.scenario import SCHEMA, parse_scenario
from golden.units import UnitError, parse_quantity, scale_quantity, split_quantity, type_name

ROOT = Path(__file__).resolve().parent.parent
DESIGNS = ("grid", "random", "one_at_a_time")
MAX_RUNS = 100_000
"""The most runs a spec may expand to (points x seeds): every run is a scenario tree in memory before the first one
starts (about 10 KB each), and 100 000 runs of a 2 s scenario on the hls backend take most of a day on two cores.
A larger design is refused before it is expanded (a seeds = 10^12 once took 10 GB and never started); split it."""
ANGLE_AT = {"method": None, "middle": 2, "bottom": 3}
"""``sweep.angle_at``: where in a window the true angle of the windows' error is taken (quarters of the window,
``ClosedLoopResult.angle_error_deg``): ``method`` (default), where the estimator in charge of that window
says its angle refers to (``MethodInfo.angle_quarters``: the middle, or the carrier bottom for the 001 and
003 methods); or always the middle (``angle_error_after_start``) or always the bottom
(``angle_error_at_bottom``; docs/metrics.md)."""


def angle_error(res, sc, angle_at: str) -> np.ndarray:
    """The electrical angle error of every window [deg], referred as ``angle_at`` says (:data:`ANGLE_AT`)."""
    q = ANGLE_AT[angle_at]
    if q is not None:
        return res.angle_error_deg(quarters=q)
    est = sc.estimator
    q_low, q_high = (METHODS[n].angle_quarters if n in METHODS else 2 for n in (est.low, est.high))
    low, high = res.angle_error_deg(quarters=q_low), res.angle_error_deg(quarters=q_high)
    return np.where(res.windows["est"] == 1, high, low)
SEED_OFFSET = 1000
"""Seed of a point's k-th run: the base scenario's seed + SEED_OFFSET + k (scripts/seed_sweep.py)."""


class SweepError(ValueError):
    """An invalid sweep spec; the message lists every problem, each with its key."""

    def __init__(self, source: str, problems: list[str]):
        self.problems = problems
        super().__init__(f"{source}: invalid sweep spec:\n" + "\n".join(f"  {p}" for p in problems))


@dataclass(frozen=True)
class Axis:
    """One varied parameter: its dotted scenario ``key`` and how it varies (``kind``: ``values``,
    ``scale``, ``uniform`` or ``scale_uniform``; ``items``: the values, factors or the two bounds)."""

    key: str
    kind: str
    items: tuple


@dataclass(frozen=True)
class Spec:
    """A validated sweep spec (see the module docstring and docs/sweep.md)."""

    name: str
    scenario: Path
    backend: str
    design: str
    axes: tuple[Axis, ...]
    seeds: int | None = None
    samples: int = 0
    seed: int = 1
    windows: tuple[tuple[float, float], ...] = ()
    angle_at: str = "method"
    crb: bool = False
    base: dict = field(default_factory=dict, compare=False)
    pole_pairs: int = 1
    """The base scenario's (the seeds' initial angles are drawn over one pole pitch)."""


# ---------------------------------------------------------------------------------------------- the spec
def _is_key(key: str) -> bool:
    """A scenario value's dotted path: ``table.key`` (``"load.torque"``), or a root key that is not a table
    (``"faults"``, the ``[[faults]]`` list)."""
    section, _, name = key.rpartition(".")
    field_ = SCHEMA.get(section, {}).get(name)
    return field_ is not None and field_.kind != "table"


def _plain_value(v: object) -> bool:
    """Whether ``v`` can stand in a scenario file as a value: a number, string or boolean, or a list or inline table
    of them (``faults`` is a list of tables); not a TOML date or time."""
    if isinstance(v, list):
        return all(_plain_value(x) for x in v)
    if isinstance(v, dict):
        return all(_plain_value(x) for x in v.values())
    return isinstance(v, (bool, int, float, str))


def _axis(key: str, raw: object, design: str, problems: list[str]) -> Axis | None:
    path = f"params.{key!r}"
    if not _is_key(key):
        problems.append(f"{path}: not a scenario key (docs/scenario.md lists them)")
        return None
    if isinstance(raw, list):
        if not raw:
            problems.append(f"{path}: the list of values is empty")
            return None
        bad = [v for v in raw if not _plain_value(v)]
        if bad:
            problems.append(f"{path}: {bad[0]!r} is not a scenario value (numbers, strings, booleans, lists "
                            f"and inline tables of them; a TOML date or time is none)")
            return None
        return Axis(key, "values", tuple(raw))
    if not isinstance(raw, dict) or len(raw) != 1:
        problems.append(f"{path}: expected a list of values or one of {{ scale = [...] }}, "
                        f"{{ uniform = [lo, hi] }}, {{ scale_uniform = [lo, hi] }}; got {type_name(raw)}")
        return None
    (kind, items), = raw.items()
    if kind not in ("scale", "uniform", "scale_uniform"):
        problems.append(f"{path}: unknown form {kind!r} (scale, uniform, scale_uniform)")
        return None
    if kind != "scale" and design != "random":
        problems.append(f"{path}: {kind} draws at random; it needs sweep.design = \"random\"")
        return None
    if not isinstance(items, list) or not items or (kind != "scale" and len(items) != 2):
        problems.append(f"{path}.{kind}: expected {'a non-empty list of factors' if kind == 'scale' else '[lo, hi]'}")
        return None
    if kind in ("scale", "scale_uniform"):
        bad = [x for x in items if isinstance(x, bool) or not isinstance(x, (int, float)) or not math.isfinite(x)]
        if bad:
            problems.append(f"{path}.{kind}: factors must be numbers, got {bad[0]!r}")
            return None
    if kind == "uniform":
        section, _, name = key.rpartition(".")
        dim = SCHEMA[section][name].dimension
        try:
            lo, hi = (parse_quantity(x, dim, f"{path}.uniform") for x in items)
        except UnitError as exc:
            problems.append(str(exc))
            return None
        unit = {split_quantity(x)[1] if isinstance(x, str) else "" for x in items}
        if len(unit) != 1 or lo > hi:
            problems.append(f"{path}.uniform: [lo, hi] need one unit and lo <= hi, got {items!r}")
            return None
    return Axis(key, kind, tuple(items))


def parse_set(items: list[str]) -> dict:
    """``KEY=VALUE`` items of the command line's ``--set`` as a ``[set]`` table: VALUE as a TOML value where it
    is one (``400``, ``"12 Hz"``, ``[["0 s", "0 N*m"]]``), else as text (``12 Hz``, the shell having eaten the
    quotes). ValueError for an item without ``=``."""
    table = {}
    for item in items:
        key, eq, value = item.partition("=")
        if not eq or not key.strip():
            raise ValueError(f"--set {item!r}: expected KEY=VALUE (a dotted scenario key, docs/scenario.md)")
        try:
            table[key.strip()] = tomllib.loads(f"v = {value}")["v"]
        except tomllib.TOMLDecodeError:
            table[key.strip()] = value.strip()
    return table


SET_SUFFIX_MAX = 60
"""Longest ``+key=value`` of an output folder's name; a longer one (a profile) names its value by a hash."""


def set_suffix(overrides: dict) -> str:
    """The output folder's suffix for command-line ``--set`` values: ``+key=value`` each, in a file name's
    characters (a sweep with other values must not overwrite the spec's own table)."""
    parts = []
    for k, v in overrides.items():
        text = v if isinstance(v, str) else json.dumps(v)
        part = re.sub(r"[^A-Za-z0-9._=-]", "", f"{k}={text}")
        if len(part) > SET_SUFFIX_MAX:
            part = re.sub(r"[^A-Za-z0-9._=-]", "", f"{k}=") + hashlib.sha256(text.encode()).hexdigest()[:12]
        parts.append("+" + part)
    return "".join(parts)


def load_spec(path: str | Path, overrides: dict | None = None) -> Spec:
    """Read and validate a sweep spec; SweepError listing every problem. ``overrides``: ``[set]`` values that
    replace or extend the spec's own (the command line's ``--set``); the name then gets :func:`set_suffix`."""
    path = Path(path)
    try:
        data = tomllib.loads(path.read_text(encoding="utf-8"))
    except tomllib.TOMLDecodeError as exc:
        raise SweepError(str(path), [f"TOML syntax error: {exc}"]) from None
    except UnicodeDecodeError:
        raise SweepError(str(path), ["not a text file in UTF-8"]) from None
    except OSError as exc:
        raise SweepError(str(path), [f"cannot read it: {exc.strerror}"]) from None
    problems: list[str] = []
    sw = data.get("sweep")
    if not isinstance(sw, dict):
        raise SweepError(str(path), ["missing the [sweep] table (scenario = \"...\" at least)"])
    known = {"name", "scenario", "backend", "design", "samples", "seed", "seeds", "windows", "angle_at", "crb"}
    problems += [f"sweep.{k}: unknown key (valid: {', '.join(sorted(known))})" for k in sw if k not in known]
    problems += [f"{k}: unknown table (valid: sweep, set, params)" for k in data if k not in ("sweep", "set", "params")]
    from hfi.backends import NAMES
    backend = sw.get("backend", "hls")
    if not isinstance(backend, str) or backend not in NAMES:
        problems.append(f"sweep.backend: {backend!r} is not a backend ({', '.join(NAMES)})")
    design = sw.get("design", "grid")
    if not isinstance(design, str) or design not in DESIGNS:
        problems.append(f"sweep.design: {design!r}, expected one of {', '.join(DESIGNS)}")

    def integer(key: str, default: int | None, low: int) -> int | None:
        v = sw.get(key, default)
        if v is not None and (isinstance(v, bool) or not isinstance(v, int) or v < low):
            problems.append(f"sweep.{key}: expected an integer >= {low}, got {v!r}")
            return default
        return v

    seeds, samples, seed = integer("seeds", None, 1), integer("samples", 0, 0), integer("seed", 1, 0)
    angle_at = sw.get("angle_at", "method")
    if not isinstance(angle_at, str) or angle_at not in ANGLE_AT:
        problems.append(f"sweep.angle_at: {angle_at!r}, expected one of {', '.join(ANGLE_AT)}")
    crb = sw.get("crb", False)
    if not isinstance(crb, bool):
        problems.append(f"sweep.crb: expected true or false, got {crb!r}")
    if design == "random" and not samples:
        problems.append("sweep.samples: a random design needs samples >= 1")
    if design != "random" and samples:
        problems.append("sweep.samples: only for design = \"random\" (a grid runs every combination)")
    windows = []
    raw_windows = sw.get("windows", [])
    if not isinstance(raw_windows, list):
        problems.append(f"sweep.windows: expected a list of [t0, t1] pairs, got {raw_windows!r}")
        raw_windows = []
    for i, w in enumerate(raw_windows):
        try:
            if not isinstance(w, list) or len(w) != 2:
                raise UnitError(f"sweep.windows[{i}]: expected [t0, t1], got {w!r}")
            t0, t1 = (parse_quantity(x, "time", f"sweep.windows[{i}]") for x in w)
            if not 0 <= t0 < t1:
                raise UnitError(f"sweep.windows[{i}]: expected 0 <= t0 < t1, got {w!r}")
            windows.append((t0, t1))
        except UnitError as exc:
            problems.append(str(exc))
    scenario = sw.get("scenario")
    base: dict = {}
    if not isinstance(scenario, str):
        problems.append("sweep.scenario: expected the base scenario's file name (relative to the spec)")
    else:
        scenario_path = (path.parent / scenario)
        try:
            base = tomllib.loads(scenario_path.read_text(encoding="utf-8"))
        except UnicodeDecodeError:
            problems.append(f"sweep.scenario: {scenario_path} is not a text file in UTF-8")
        except (OSError, tomllib.TOMLDecodeError) as exc:
            problems.append(f"sweep.scenario: cannot read {scenario_path}: {exc}")
    fixed = data.get("set", {})
    if not isinstance(fixed, dict):
        problems.append(f"set: expected a table of dotted scenario keys, got {type_name(fixed)}")
        fixed = {}
    fixed = {**fixed, **(overrides or {})}
    for key, value in fixed.items():
        if not _is_key(key):
            problems.append(f"set.{key!r}: not a scenario key (docs/scenario.md lists them)")
        elif not _plain_value(value):
            problems.append(f"set.{key!r}: {value!r} is not a scenario value")
        elif base:
            try:
                _set(base, key, value)
            except ValueError as exc:
                problems.append(f"set.{key!r}: {exc}")
    params = data.get("params", {})
    if not isinstance(params, dict) or not params:
        problems.append("params: expected a table with at least one parameter to vary")
        params = {}
    axes = [a for a in (_axis(k, v, design, problems) for k, v in params.items()) if a is not None]
    for a in axes:
        if a.kind in ("scale", "scale_uniform") and base and _get(base, a.key) is None:
            problems.append(f"params.{a.key!r}: {a.kind} needs a value in the base scenario, which has none")
    pole_pairs = 1
    if base and not problems:
        # the base with [set] is a scenario of its own (its seed numbers the runs): refused here, not in every run
        try:
            pole_pairs = parse_scenario(copy.deepcopy(base), str(scenario_path)).plant["mech"]["pole_pairs"]
        except ValueError as exc:
            problems += [f"the base scenario with [set]: {p}" for p in getattr(exc, "problems", [str(exc)])]
    if not problems:
        n_points = (samples if design == "random" else 1 + sum(len(a.items) for a in axes) if design == "one_at_a_time"
                    else math.prod(len(a.items) for a in axes))
        if n_points * (seeds or 1) > MAX_RUNS:
            problems.append(f"the design expands to {n_points} points x {seeds or 1} seeds = {n_points * (seeds or 1)} "
                            f"runs, more than {MAX_RUNS} (hfi.sweep.MAX_RUNS): split it")
    name = sw.get("name", path.stem)
    if not isinstance(name, str) or not name or name in (".", "..") or "/" in name or "\\" in name:
        problems.append(f"sweep.name: {name!r} must be a plain name (the results go to out/sweep/<name>)")
    elif overrides:
        name += set_suffix(overrides)
    if problems:
        raise SweepError(str(path), problems)
    return Spec(name, scenario_path, backend, design, tuple(axes), seeds, samples,
                seed, tuple(windows), angle_at, crb is True, base, pole_pairs)


# ---------------------------------------------------------------------------------------------- the runs
def _get(tree: dict, key: str) -> object:
    node: object = tree
    for part in key.split("."):
        if not isinstance(node, dict) or part not in node:
            return None
        node = node[part]
    return node


def _set(tree: dict, key: str, value: object) -> None:
    """``tree[a][b]... = value`` for ``key = "a.b..."``, making missing tables; ValueError if a part on the way
    holds a value that is not a table."""
    *tables, last = key.split(".")
    node = tree
    for i, part in enumerate(tables):
        node = node.setdefault(part, {})
        if not isinstance(node, dict):
            raise ValueError(f"{'.'.join(tables[:i + 1])} of the base scenario is {type_name(node)}, not a table")
    node[last] = value


def scaled(value: object, factor: float, key: str) -> object:
    """A scenario value times ``factor``: a quantity, each of a vector's three, or a profile's values."""
    if isinstance(value, list):
        if all(isinstance(p, list) and len(p) == 2 for p in value):
            return [[t, scale_quantity(v, factor, key)] for t, v in value]
        return [scale_quantity(v, factor, key) for v in value]
    return scale_quantity(value, factor, key)


def points(spec: Spec) -> list[dict]:
    """The design: one ``{key: setting}`` per point, a setting being ``("value", v)`` or ``("scale", f)``."""
    def setting(a: Axis, item: object) -> tuple[str, object]:
        return ("scale", item) if a.kind in ("scale", "scale_uniform") else ("value", item)

    if spec.design == "grid":
        return [{a.key: setting(a, item) for a, item in zip(spec.axes, combo)}
                for combo in itertools.product(*(a.items for a in spec.axes))]
    if spec.design == "one_at_a_time":
        return [{}] + [{a.key: setting(a, item)} for a in spec.axes for item in a.items]
    rng = np.random.default_rng(spec.seed)
    out = []
    for _ in range(spec.samples):
        p = {}
        for a in spec.axes:
            if a.kind in ("values", "scale"):
                p[a.key] = setting(a, a.items[int(rng.integers(len(a.items)))])
            elif a.kind == "scale_uniform":
                p[a.key] = ("scale", round(float(rng.uniform(*a.items)), 6))
            else:
                (lo, unit), (hi, _) = (split_quantity(x) if isinstance(x, str) else (x, "") for x in a.items)
                x = float(f"{rng.uniform(float(lo), float(hi)):.6g}")
                p[a.key] = ("value", f"{x:g} {unit}" if unit else x)
        out.append(p)
    return out


@dataclass(frozen=True)
class Job:
    """One run: the scenario tree, where it came from (point index, its settings, seed) and its hash."""

    point: int
    settings: dict
    seed: int | None
    theta_m0_deg: float | None
    tree: dict
    key: str
    error: str = ""


CODE = ("golden", "firmware", "hls", "sim", "rtl", "requirements.txt", "hfi/__init__.py", "hfi/backends.py",
        "hfi/hls_backend.py", "hfi/hls_build.py", "hfi/rtl_backend.py", "hfi/soc_platform.py", "hfi/fw_c.py",
        "hfi/report.py", "hfi/paper.py", "hfi/sweep.py", "hfi/ripple.py", "hfi/crb.py")
"""What a run's result depends on besides its scenario tree: the source version hashes these paths only, so a
commit of documentation, of another sweep's spec or of a report (``hfi compare``) keeps the cache. The ``hfi``
modules are those a run imports (tests/test_sweep.py holds the list to it)."""


def source_version() -> str:
    """The git objects of :data:`CODE` at HEAD, with a hash of their uncommitted diff if there is one
    ("unversioned" outside git): part of every run's hash, so a changed model never reuses an old result."""
    try:
        trees = subprocess.run(["git", "-C", str(ROOT), "rev-parse", *(f"HEAD:{c}" for c in CODE)],
                               capture_output=True, text=True, check=True).stdout.split()
        diff = subprocess.run(["git", "-C", str(ROOT), "diff", "HEAD", "--", *CODE], capture_output=True,
                              check=True).stdout
    except (OSError, subprocess.CalledProcessError):
        return "unversioned"
    version = hashlib.sha256(" ".join(trees).encode()).hexdigest()[:16]
    return version + ("+" + hashlib.sha256(diff).hexdigest()[:12] if diff else "")


def jobs(spec: Spec, version: str) -> list[Job]:
    """Every run of the sweep, in order: points x seeds."""
    base_seed = int(_get(spec.base, "scenario.seed") or 0)
    out = []
    for i, p in enumerate(points(spec)):
        tree, error = copy.deepcopy(spec.base), ""
        for key, (how, x) in p.items():
            try:
                _set(tree, key, scaled(_get(tree, key), x, key) if how == "scale" else x)
            except UnitError as exc:
                error = f"UnitError: {exc}"
        runs = [(None, None)]
        if spec.seeds:
            runs = []
            for k in range(spec.seeds):
                seed = base_seed + SEED_OFFSET + k
                theta = float(np.random.default_rng(seed).uniform(0, 360.0 / spec.pole_pairs))
                runs.append((seed, round(theta, 4)))
        for seed, theta in runs:
            t = copy.deepcopy(tree)
            if seed is not None:
                _set(t, "scenario.seed", seed)
                _set(t, "load.initial.theta_m", f"{theta} deg")
            blob = json.dumps({"tree": t, "backend": spec.backend, "windows": spec.windows, "angle_at": spec.angle_at,
                               "crb": spec.crb, "version": version}, sort_keys=True)
            out.append(Job(i, p, seed, theta, t, hashlib.sha256(blob.encode()).hexdigest()[:24], error))
    return out


def _flat(prefix: str, value: object, row: dict) -> None:
    if isinstance(value, dict):
        for k, v in value.items():
            _flat(f"{prefix}{k}.", v, row)
    elif value is None or isinstance(value, (bool, int, float, str)):
        row[prefix[:-1]] = value


STILL_DEG = 10.0
"""``sweep.crb``: a window's Cramér-Rao columns are filled where the true electrical angle moved by less than this
[deg] (the bound is computed on a locked rotor: hfi.crb) and the window starts ``hfi.crb.SETTLE_S`` or later
(its replay starts that long before it)."""


def run_job(job: Job, backend: str, windows: tuple[tuple[float, float], ...], source: str,
            angle_at: str = "method", crb: bool = False) -> dict:
    """Run one job and return its row (on a Dask worker). Never raises: a failure is the row's ``error``."""
    from hfi.backends import run
    from hfi.report import metrics_of
    from hfi.crb import SETTLE_S, bound
    from hfi.ripple import audible_torque, copper_loss

    if job.error:
        return {"error": job.error}
    row: dict = {"error": ""}
    t0 = time.perf_counter()
    try:
        sc = parse_scenario(copy.deepcopy(job.tree), source)
        res = run(sc, backend, progress=False)
        m = metrics_of(sc, res)
    except Exception as exc:      # a row records it; the sweep goes on (docs/sweep.md)
        row["error"] = f"{type(exc).__name__}: {exc}"
        row["run_wall_s"] = round(time.perf_counter() - t0, 3)
        return row
    for k, v in m.items():
        if k == "segments":
            for i, s in enumerate(v):
                _flat(f"seg{i}.", {a: b for a, b in s.items() if not isinstance(b, list)}, row)
        elif not isinstance(v, list):
            _flat(f"{k}.", v, row)
    err = angle_error(res, sc, angle_at)
    rpm = res.windows["omega_m"] * (60 / (2 * math.pi))
    for i, (a, b) in enumerate(windows):
        sel = (res.t >= a) & (res.t < b)
        if not sel.any():
            row["error"] = f"window {i} [{a:g}, {b:g}) s holds no control window of this run"
            continue
        e = err[sel]
        row[f"win{i}.err_rms_deg"] = round(float(np.sqrt(np.mean(e ** 2))), 4)
        row[f"win{i}.err_peak_deg"] = round(float(np.max(np.abs(e))), 4)
        row[f"win{i}.err_mean_deg"] = round(float(np.mean(e)), 4)
        row[f"win{i}.speed_mean_rpm"] = round(float(np.mean(rpm[sel])), 3)
        row[f"win{i}.speed_ripple_rpm"] = round(float(0.5 * (np.max(rpm[sel]) - np.min(rpm[sel]))), 3)
        row[f"win{i}.high_share"] = round(float(np.mean(res.windows["est"][sel] == 1)), 4)
        row[f"win{i}.torque_mean_nm"] = round(float(np.mean(res.windows["torque"][sel])), 4)
        row[f"win{i}.torque_std_nm"] = round(float(np.std(res.windows["torque"][sel])), 4)
        try:
            total, ripple = copper_loss(res.windows, res.t, sel, sc.plant["R_s"])
            row[f"win{i}.cu_loss_w"], row[f"win{i}.cu_ripple_w"] = _sig(total), _sig(ripple)
            row[f"win{i}.torque_audible_nm"] = _sig(audible_torque(res.windows, res.t, sel))
        except ValueError as exc:
            row["error"] = f"window {i} [{a:g}, {b:g}) s: {exc}"
        if crb and a >= SETTLE_S:
            theta = np.unwrap(res.windows["theta_e"][sel].astype(float) * (2 * math.pi / 2 ** 32))
            if np.degrees(np.ptp(theta)) < STILL_DEG:
                try:
                    bd = bound(sc.plant, res.tick_hz, res, err, a, b)
                except ValueError as exc:
                    row["error"] = f"window {i} [{a:g}, {b:g}) s: {exc}"
                    continue
                for name in ("crb_window_deg", "err_std_deg", "tau_c_ms", "efficiency"):
                    row[f"win{i}.{name}"] = _sig(getattr(bd, name))
    row["run_wall_s"] = round(time.perf_counter() - t0, 3)
    return row


def _sig(x: float) -> float:
    """``x`` to six significant digits (a loss or a ripple spans decades)."""
    return float(f"{x:.6g}")


def _param_columns(job: Job) -> dict:
    cols: dict = {"point": job.point, "seed": job.seed, "theta_m0_deg": job.theta_m0_deg}
    for key, (how, x) in job.settings.items():
        if how == "scale":
            cols[f"{key}.scale"] = float(x)
            continue
        cols[key] = x if isinstance(x, (int, float, str)) and not isinstance(x, bool) else json.dumps(x)
        section, _, name = key.rpartition(".")
        f = SCHEMA[section][name]
        if f.kind == "quantity":
            try:
                cols[f"{key}.si"] = parse_quantity(x, f.dimension, key)
            except UnitError:
                pass
    return cols


# ---------------------------------------------------------------------------------------------- Dask
def start_client(scheduler: str | None, workers: int | None, dashboard: bool):
    """A Dask client: connected to ``scheduler``, or on a new local cluster of ``workers`` single-threaded
    processes (default: the cores; the dashboard on port 8787 or the next free one). Returns (client,
    cluster or None)."""
    from distributed import Client, LocalCluster

    if scheduler:
        return Client(scheduler), None
    n = workers or os.cpu_count() or 1
    with warnings.catch_warnings():       # port 8787 taken: Dask takes another one, and we print the link
        warnings.simplefilter("ignore", UserWarning)
        cluster = LocalCluster(n_workers=n, threads_per_worker=1, processes=True,
                               dashboard_address=":8787" if dashboard else ":0", silence_logs=40)
    return Client(cluster), cluster


def write_table(rows: list[dict], path: Path) -> None:
    """``rows`` as one Parquet table: the union of their columns (missing cells null); a column whose rows
    mix text and numbers is written as text."""
    import pyarrow as pa
    import pyarrow.parquet as pq

    names = list(dict.fromkeys(k for r in rows for k in r))
    cols = {}
    for n in names:
        vals = [r.get(n) for r in rows]
        kinds = {type(v) for v in vals if v is not None}
        if str in kinds and len(kinds) > 1:
            vals = [None if v is None else str(v) for v in vals]
        elif kinds == {bool, int} or kinds == {bool, float}:
            vals = [None if v is None else float(v) for v in vals]
        cols[n] = pa.array(vals)
    path.parent.mkdir(parents=True, exist_ok=True)
    pq.write_table(pa.table(cols), path)


def sweep(spec: Spec, out: Path, scheduler: str | None = None, workers: int | None = None,
          dashboard: bool = True, progress: bool = True, log=print, client=None) -> list[dict]:
    """Run every job of ``spec`` not yet in ``out/runs`` on Dask, write ``out/results.parquet``; return the
    rows in job order. ``client``: a ``distributed.Client`` to use (and leave open), instead of connecting
    to ``scheduler`` or starting a local cluster of ``workers`` processes."""
    t0 = time.monotonic()
    version = source_version()
    todo_all = jobs(spec, version)
    cache = out / "runs"
    cache.mkdir(parents=True, exist_ok=True)
    rows: dict[str, dict] = {}
    for j in todo_all:
        f = cache / f"{j.key}.json"
        if f.exists():
            rows[j.key] = json.loads(f.read_text())
    todo = [j for j in todo_all if j.key not in rows]
    n_points = len({j.point for j in todo_all})
    log(f"sweep {spec.name}: {n_points} points x {spec.seeds or 1} seeds = {len(todo_all)} runs on "
        f"{spec.backend}; {len(todo_all) - len(todo)} cached, {len(todo)} to run")
    if todo:
        from distributed import as_completed
        from tqdm import tqdm

        own = client is None
        if own:
            client, cluster = start_client(scheduler, workers, dashboard)
        try:
            if own and dashboard and client.dashboard_link:
                log(f"dashboard: {client.dashboard_link}")
            source = f"sweep {spec.name} ({spec.scenario.name})"
            futures = {client.submit(run_job, j, spec.backend, spec.windows, source, spec.angle_at, spec.crb,
                                     key=f"run-{j.key}", pure=False): j for j in todo}
            bar = tqdm(total=len(futures), desc=spec.name, unit="run", disable=not progress, file=sys.stderr)
            for fut in as_completed(futures):
                j = futures[fut]
                try:
                    row = fut.result()
                    (cache / f"{j.key}.json").write_text(json.dumps(row))
                except Exception as exc:        # the worker died or the cluster failed: a row, not cached
                    row = {"error": f"{type(exc).__name__}: {exc}"}
                rows[j.key] = row
                bar.update()
            bar.close()
        finally:
            if own:
                client.close()
                if cluster is not None:
                    cluster.close()
    table = [{**_param_columns(j), "run_key": j.key, **rows[j.key]} for j in todo_all]
    write_table(table, out / "results.parquet")
    failed = [r for r in table if r["error"]]
    log(f"results: {out / 'results.parquet'} ({len(table)} rows, {len(failed)} failed), "
        f"{time.monotonic() - t0:.1f} s wall")
    for r in failed[:5]:
        seed = "" if r["seed"] is None else f" seed {r['seed']}"
        log(f"  point {r['point']}{seed}: {' '.join(r['error'].split())[:300]}")
    return table
