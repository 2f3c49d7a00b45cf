"""Parameter sweeps: one scenario (or one library function) over a grid of parameters.

A sweep file (TOML) names what to run and what to vary::

    name = "dugdale-pulloff"                  # optional label
    scenario = "base.toml"                    # a scenario file, relative to this file ...
    # [base] ...                              # ... or an inline base scenario table
    # function = "package.module:callable"   # ... or a library function (keyword arguments)
    outputs = ["pull_off_force", "contact_area"]

    [parameters]                              # cartesian product of the lists
    "adhesion.work_of_adhesion" = ["30 mJ/m^2", "50 mJ/m^2"]
    "grid.n" = [64, 128]

    [[points]]                                # optional explicit points (combined with the
    "body2.shape.radius" = "10 um"            # product of [parameters] when both are given)

Each point is the base scenario with the point's dotted keys overridden.  It runs through
:func:`tribobem.scenario.run_scenario` (or the function) on a Dask cluster: a
``LocalCluster`` of processes by default, an existing scheduler given by its address, or
``"synchronous"`` (in-process, no Dask).  Every finished point is written at once and
atomically to ``OUTDIR/points/<hash>.json``, the hash being a stable digest of what the
point computes (runner, base and overrides, the point's effective solver options and the
solver version :data:`tribobem._solver_version.SOLVER_VERSION`), so a killed sweep loses no
finished point, a restart with the same spec computes only the points without a successful
record (failed points are retried), and a restart after a change of the solver (a bumped
solver version, a new default tolerance) recomputes every point instead of mixing old and new
results.  At the end every point is gathered into ``OUTDIR/results.nc``
(xarray; one dimension per parameter for a full grid, else a ``point`` dimension) and
``OUTDIR/results.csv``, both written atomically.
"""

from __future__ import annotations

import copy
import csv
import hashlib
import importlib
import io
import itertools
import json
import math
import os
import signal
import socket
import sys
import threading
import time
import tomllib
import traceback
from contextlib import contextmanager
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable, Iterable, Mapping

import numpy as np

from . import _solver_version
from ._solver_version import SOLVER_VERSION  # noqa: F401 (re-exported; read at call time below)
from .errors import InputError
from .output.atomic import TMP_GLOB, atomic_path, atomic_write_text, file_state, staged  # noqa: F401 (re-exported)
from .output.summary import jsonable
from .units import parse_quantity, si_unit, si_value

__all__ = [
    "SweepSpec",
    "SweepResult",
    "load_sweep",
    "run_sweep",
    "sweep_command",
    "point_hash",
    "solver_options",
    "SOLVER_VERSION",
    "read_points",
    "gather",
]

#: Top-level keys of a sweep file.
SPEC_KEYS = {"name", "description", "scenario", "base", "function", "parameters", "points",
             "outputs", "keep_runs", "scheduler", "workers"}
#: Top-level sections of a scenario (SPEC 9.1); a dotted key must start with one of these
#: or with a key of the base scenario.
SCENARIO_SECTIONS = {"kind", "name", "title", "description", "grid", "body1", "body2", "load",
                     "adhesion", "friction", "humidity", "solver", "output", "path"}
#: Record format version written into every point file.
RECORD_VERSION = 1


# --------------------------------------------------------------------------------------
# Values, hashing, merging
# --------------------------------------------------------------------------------------

def _jsonable(value):
    """Plain JSON types (:func:`tribobem.output.summary.jsonable`: numpy scalars and arrays
    converted, non-finite floats -> None); any other object as its ``repr``, as the point
    hashes have always been made."""
    return jsonable(value, fallback=repr)


def _canonical(obj) -> str:
    return json.dumps(_jsonable(obj), sort_keys=True, separators=(",", ":"), ensure_ascii=True)


def point_hash(runner: str, base: Mapping, point: Mapping, solver: Mapping | None = None,
               solver_version: int | None = None) -> str:
    """Stable 16-hex-digit digest of what a point computes.

    Parameters
    ----------
    runner : str
        ``"scenario"``, ``"function:module:attr"`` or ``"callable:..."``.
    base : mapping
        The base scenario (or the fixed keyword arguments of a function).
    point : mapping
        The point's overrides (dotted keys).
    solver : mapping, optional
        The point's effective solver options (:func:`solver_options`): the defaults that the
        base and the point leave unset are part of what the point computes, so a changed
        default (a tighter tolerance, another method) recomputes the point.
    solver_version : int, optional
        Default: :data:`tribobem._solver_version.SOLVER_VERSION` (read at each call), which is
        bumped when results change.

    Returns
    -------
    str
        The first 16 hex digits of a SHA-256 of the canonical JSON of all of the above, so
        editing the base, a solver default or the solver version invalidates every point,
        while reordering the sweep file (or the keys of a table) changes nothing.
    """
    if solver_version is None:
        solver_version = _solver_version.SOLVER_VERSION
    text = _canonical({"runner": runner, "base": base, "point": point, "solver": dict(solver or {}),
                       "solver_version": int(solver_version)})
    return hashlib.sha256(text.encode("ascii")).hexdigest()[:16]


def _scenario_solver_defaults() -> dict:
    """Defaults of the scenario's ``[solver]`` section (tolerance, max_iterations, ...), read
    from the schema so that a new option or a changed default enters the hash by itself."""
    from .scenario.schema import SolverSpec

    out = {}
    for name, info in SolverSpec.model_fields.items():
        if not info.is_required():
            out[name] = info.get_default(call_default_factory=True)
    return out


#: JSON scalar types a keyword default must have to enter the hash (a default object, e.g. a
#: random generator, has no stable text and is left out).
_PLAIN = (bool, int, float, str, type(None))


def _plain(value) -> bool:
    if isinstance(value, (list, tuple)):
        return all(_plain(v) for v in value)
    return isinstance(value, _PLAIN)


def _function_defaults(dotted: str) -> dict:
    """Plain keyword defaults of ``module:callable`` (its solver options: tol, max_iterations,
    kernel, ...); empty when the function cannot be imported here (the point then fails with
    that message when it runs)."""
    import inspect

    try:
        fn = _resolve_function(dotted)
        params = inspect.signature(fn).parameters.values()
    except (InputError, TypeError, ValueError):
        return {}
    return {p.name: p.default for p in params
            if p.default is not inspect.Parameter.empty and _plain(p.default)}


def solver_options(runner: str, base: Mapping, point: Mapping, _defaults: Mapping | None = None) -> dict:
    """The effective solver options of one point (what :func:`point_hash` covers beyond the
    base and the overrides).

    Scenario runner: the ``[solver]`` section of the point's scenario over the schema's
    defaults (tolerance, max_iterations, backend, kernel, ...).  Function runner: the
    function's plain keyword defaults that the base and the point leave unset (e.g.
    ``tol``, ``max_iterations``, ``kernel`` of a study's point function).  Callable runner
    (a Python function given to :func:`run_sweep`): none.

    Parameters
    ----------
    runner : str
        As for :func:`point_hash`.
    base, point : mapping
        Base scenario (or keyword arguments) and the point's dotted overrides.

    Returns
    -------
    dict
    """
    if runner == "scenario":
        defaults = _scenario_solver_defaults() if _defaults is None else dict(_defaults)
        given = apply_overrides(base, point).get("solver")
        if isinstance(given, Mapping):
            defaults.update(given)
        return defaults
    if runner.startswith("function:"):
        defaults = _function_defaults(runner[len("function:"):]) if _defaults is None else dict(_defaults)
        given = apply_overrides(base, point)
        return {k: v for k, v in defaults.items() if k not in given}
    return {}


#: Tables that are values of a scenario key, not nested sections: a range ``{start, stop, num}``.
_VALUE_TABLES = ({"start", "stop", "num"},)


def _flatten(table: Mapping, prefix: str = "") -> dict:
    """Nested tables -> dotted keys (``{"a": {"b": 1}}`` -> ``{"a.b": 1}``); a range table
    ``{start, stop, num}`` is a value and stays whole."""
    out = {}
    for key, value in table.items():
        name = f"{prefix}{key}"
        if isinstance(value, Mapping) and value and set(value) not in _VALUE_TABLES:
            out.update(_flatten(value, name + "."))
        else:
            out[name] = value
    return out


def set_dotted(tree: dict, key: str, value) -> None:
    """Set ``tree["a"]["b"] = value`` for ``key = "a.b"``, creating tables on the way."""
    parts = key.split(".")
    node = tree
    for i, part in enumerate(parts[:-1]):
        nxt = node.get(part)
        if nxt is None:
            nxt = node[part] = {}
        elif not isinstance(nxt, dict):
            raise InputError(key, f"cannot set it: {'.'.join(parts[:i + 1])!r} is a value ({nxt!r}), not a table")
        node = nxt
    node[parts[-1]] = copy.deepcopy(value)


def apply_overrides(base: Mapping, point: Mapping) -> dict:
    """A deep copy of ``base`` with every dotted key of ``point`` set."""
    tree = copy.deepcopy(dict(base))
    for key, value in point.items():
        set_dotted(tree, key, value)
    return tree


# Quantities: one parser for the whole package (tribobem.units).  ``to_si`` here takes no
# expected dimension: a quantity string becomes its value in SI base units, anything else
# (numbers aside) comes back unchanged.
_quantity = parse_quantity
to_si = si_value
_si_unit = si_unit


# --------------------------------------------------------------------------------------
# The sweep spec
# --------------------------------------------------------------------------------------

@dataclass
class SweepSpec:
    """A parsed sweep file.

    Attributes
    ----------
    base : dict
        Base scenario (scenario runner) or fixed keyword arguments (function runner).
    parameters : dict[str, list]
        Dotted key -> values; the sweep is their cartesian product (in file order, the last
        key varying fastest).
    points : list[dict]
        Explicit override dicts; combined with the product of ``parameters`` when both are
        given (every point for every parameter combination).
    outputs : list[str]
        Scalars to gather: run-level keys of the summary, else the last step's.  Empty:
        every scalar the runs return.
    function : str or None
        ``"package.module:callable"``; the callable takes the merged keyword arguments
        (base plus point, unit strings converted to SI floats) and returns a dict of
        scalars (or one float, gathered as ``value``).  None: run scenarios.
    scenario_path : Path or None
        Where the base scenario came from (its folder resolves relative paths).
    source : Path or None
        The sweep file.
    keep_runs : bool
        Scenario runner: keep each run's results folder under ``OUTDIR/runs/<hash>/``.
    """

    base: dict = field(default_factory=dict)
    parameters: dict = field(default_factory=dict)
    points: list = field(default_factory=list)
    outputs: list = field(default_factory=list)
    function: str | None = None
    name: str = "sweep"
    description: str = ""
    scenario_path: Path | None = None
    source: Path | None = None
    keep_runs: bool = False
    scheduler: str | None = None
    workers: int | None = None

    def __post_init__(self):
        self.base = dict(self.base or {})
        self.parameters = {str(k): list(v) if isinstance(v, (list, tuple)) else v
                           for k, v in _flatten_parameters(self.parameters or {}).items()}
        self.points = [_flatten(dict(p)) for p in (self.points or [])]
        self.outputs = list(self.outputs or [])
        self.validate()

    # -- construction ------------------------------------------------------------------
    @classmethod
    def from_dict(cls, data: Mapping, source: str | os.PathLike | None = None) -> "SweepSpec":
        """Build from the parsed TOML table; relative paths resolve against ``source``'s folder."""
        unknown = sorted(set(data) - SPEC_KEYS)
        if unknown:
            raise InputError(f"sweep.{unknown[0]}", f"unknown key; allowed: {', '.join(sorted(SPEC_KEYS))}")
        src = Path(source).resolve() if source is not None else None
        folder = src.parent if src is not None else Path.cwd()
        given = [k for k in ("scenario", "base", "function") if k in data]
        if "scenario" in data and "base" in data:
            raise InputError("sweep.scenario", "give either scenario = \"file.toml\" or an inline [base] table, not both")
        if not given:
            raise InputError("sweep.scenario", "missing: give scenario = \"file.toml\", an inline [base] table, "
                             "or function = \"module:callable\"")
        base, scen_path = {}, None
        if "scenario" in data:
            if "function" in data:
                raise InputError("sweep.function", "a function sweep takes its fixed arguments from [base], not scenario")
            scen = data["scenario"]
            if isinstance(scen, Mapping):
                base = dict(scen)
            else:
                scen_path = (folder / str(scen)).resolve()
                if not scen_path.is_file():
                    raise InputError("sweep.scenario", f"scenario file not found: {scen_path}")
                try:
                    base = tomllib.loads(scen_path.read_text(encoding="utf-8"))
                except tomllib.TOMLDecodeError as exc:
                    raise InputError("sweep.scenario", f"{scen_path} is not valid TOML: {exc}") from None
        elif "base" in data:
            if not isinstance(data["base"], Mapping):
                raise InputError("sweep.base", "must be a table")
            base = dict(data["base"])
        outputs = data.get("outputs", [])
        if isinstance(outputs, str):
            outputs = [outputs]
        return cls(
            base=base,
            parameters=data.get("parameters", {}),
            points=data.get("points", []),
            outputs=outputs,
            function=data.get("function"),
            name=str(data.get("name", src.stem if src is not None else "sweep")),
            description=str(data.get("description", "")),
            scenario_path=scen_path,
            source=src,
            keep_runs=bool(data.get("keep_runs", False)),
            scheduler=data.get("scheduler"),
            workers=data.get("workers"),
        )

    @classmethod
    def from_file(cls, path: str | os.PathLike) -> "SweepSpec":
        """Read a sweep TOML file."""
        path = Path(path)
        if not path.is_file():
            raise InputError("sweep", f"sweep file not found: {path}")
        try:
            data = tomllib.loads(path.read_text(encoding="utf-8"))
        except tomllib.TOMLDecodeError as exc:
            raise InputError("sweep", f"{path} is not valid TOML: {exc}") from None
        return cls.from_dict(data, source=path)

    # -- checks --------------------------------------------------------------------------
    def validate(self) -> None:
        if self.function is not None:
            if not isinstance(self.function, str) or ":" not in self.function:
                raise InputError("sweep.function", f"must be 'package.module:callable', got {self.function!r}")
        if not isinstance(self.outputs, list) or not all(isinstance(o, str) for o in self.outputs):
            raise InputError("sweep.outputs", "must be a list of names")
        for key, values in self.parameters.items():
            if not isinstance(values, list) or not values:
                raise InputError(f"parameters.{key}", "must be a non-empty list of values")
            seen = [_canonical(v) for v in values]
            if len(set(seen)) != len(seen):
                raise InputError(f"parameters.{key}", "has a repeated value")
        if not self.parameters and not self.points:
            raise InputError("sweep.parameters", "nothing to sweep: give [parameters] lists and/or [[points]]")
        for i, p in enumerate(self.points):
            if not isinstance(p, dict):
                raise InputError(f"points[{i}]", "must be a table of overrides")
            clash = sorted(set(p) & set(self.parameters))
            if clash:
                raise InputError(f"points[{i}].{clash[0]}", "is also swept in [parameters]; give it in one place")
        if self.function is None:
            known = SCENARIO_SECTIONS | set(self.base)
            for key in list(self.parameters) + [k for p in self.points for k in p]:
                if key.split(".")[0] not in known:
                    raise InputError(f"parameters.{key}", f"does not name a scenario key; top-level sections: "
                                     f"{', '.join(sorted(SCENARIO_SECTIONS))}")
        if self.workers is not None and (not isinstance(self.workers, int) or self.workers < 1):
            raise InputError("sweep.workers", f"must be an integer >= 1, got {self.workers!r}")
        hashes = [h for h, _ in self.tasks()]
        if len(set(hashes)) != len(hashes):
            raise InputError("sweep.points", "two points are identical (same overrides)")

    # -- the points ----------------------------------------------------------------------
    @property
    def is_grid(self) -> bool:
        """True when the points are the full cartesian product of ``parameters``."""
        return bool(self.parameters) and not self.points

    @property
    def runner(self) -> str:
        return f"function:{self.function}" if self.function else "scenario"

    def overrides(self) -> list[dict]:
        """Every point's overrides, in sweep order."""
        keys = list(self.parameters)
        combos = [dict(zip(keys, vals)) for vals in itertools.product(*self.parameters.values())] if keys else [{}]
        if not self.points:
            return combos
        return [{**pt, **combo} for pt in self.points for combo in combos]

    def tasks(self, runner: str | None = None) -> list[tuple[str, dict]]:
        """``(hash, overrides)`` of every point (the hash includes the point's effective
        solver options and the solver version, see :func:`point_hash`)."""
        runner = runner or self.runner
        defaults = None  # the schema's or the function's defaults, looked up once per call
        if runner == "scenario":
            defaults = _scenario_solver_defaults()
        elif runner.startswith("function:"):
            defaults = _function_defaults(runner[len("function:"):])
        return [(point_hash(runner, self.base, o, solver_options(runner, self.base, o, defaults)), o)
                for o in self.overrides()]

    def __len__(self) -> int:
        return len(self.overrides())

    def swept_keys(self) -> list[str]:
        """Every key that some point overrides, in first-seen order."""
        keys: list[str] = []
        for o in self.overrides():
            for k in o:
                if k not in keys:
                    keys.append(k)
        return keys

    def scenario_for(self, overrides: Mapping) -> dict:
        """The full scenario (or keyword arguments) of one point."""
        return apply_overrides(self.base, overrides)


def _flatten_parameters(params: Mapping) -> dict:
    out = {}
    for key, value in params.items():
        if isinstance(value, Mapping):
            for k, v in _flatten_parameters(value).items():
                out[f"{key}.{k}"] = v
        else:
            out[str(key)] = value
    return out


def load_sweep(path_or_spec) -> SweepSpec:
    """A :class:`SweepSpec` from a path, a dict (parsed TOML) or a spec."""
    if isinstance(path_or_spec, SweepSpec):
        return path_or_spec
    if isinstance(path_or_spec, Mapping):
        return SweepSpec.from_dict(path_or_spec)
    return SweepSpec.from_file(path_or_spec)


# --------------------------------------------------------------------------------------
# Running one point (on a worker)
# --------------------------------------------------------------------------------------

def _scalar(value):
    if isinstance(value, (bool, np.bool_)):
        return bool(value)
    if isinstance(value, (int, float, np.integer, np.floating)):
        return float(value) if isinstance(value, (float, np.floating)) else int(value)
    if isinstance(value, np.ndarray) and value.ndim == 0:
        return _scalar(value.item())
    return None


def extract_outputs(summary: Mapping, outputs: Iterable[str]) -> dict:
    """Scalars named in ``outputs`` from a summary (SPEC 9.1): run-level key, else last step.

    With no names, every run-level scalar and every scalar of the last step (run-level wins).
    A name that is absent, or not a scalar, gives None (NaN in the gathered files).
    """
    steps = summary.get("steps") or []
    last = steps[-1] if steps and isinstance(steps[-1], Mapping) else {}
    outputs = list(outputs)
    if not outputs:
        out = {k: _scalar(v) for k, v in last.items() if _scalar(v) is not None}
        out.update({k: _scalar(v) for k, v in summary.items()
                    if k not in ("steps", "inputs", "versions", "timings") and _scalar(v) is not None})
        return out
    out = {}
    for name in outputs:
        if name in summary and _scalar(summary[name]) is not None:
            out[name] = _scalar(summary[name])
        elif name in last:
            out[name] = _scalar(last[name])
        else:
            out[name] = None
    return out


def _resolve_function(dotted: str) -> Callable:
    mod_name, _, attr = dotted.partition(":")
    try:
        obj = importlib.import_module(mod_name)
    except ImportError as exc:
        raise InputError("sweep.function", f"cannot import {mod_name!r}: {exc}") from None
    for part in attr.split("."):
        try:
            obj = getattr(obj, part)
        except AttributeError:
            raise InputError("sweep.function", f"{mod_name!r} has no attribute {attr!r}") from None
    if not callable(obj):
        raise InputError("sweep.function", f"{dotted!r} is not callable")
    return obj


def _normalise_result(result, outputs) -> dict:
    if isinstance(result, Mapping) and "summary" not in result:
        values = dict(result)
    elif hasattr(result, "summary"):
        return extract_outputs(result.summary, outputs)
    elif isinstance(result, Mapping):
        return extract_outputs(result["summary"], outputs)
    else:
        values = {"value": result}
    if outputs:
        return {k: _scalar(values.get(k)) for k in outputs}
    return {k: _scalar(v) for k, v in values.items() if _scalar(v) is not None}


def run_point(task: Mapping) -> dict:
    """Run one point and return its record (never raises for an error of the point itself).

    ``task`` holds ``hash``, ``point`` (overrides), ``mode`` ("callable" | "function" |
    "scenario") and what that mode needs.  KeyboardInterrupt and SystemExit propagate.
    """
    t0 = time.perf_counter()
    started = time.strftime("%Y-%m-%dT%H:%M:%S%z")
    record = {
        "version": RECORD_VERSION,
        "solver_version": _solver_version.SOLVER_VERSION,
        "hash": task["hash"],
        "point": _jsonable(task["point"]),
        "status": "ok",
        "outputs": {},
        "error": None,
        "started": started,
        "host": socket.gethostname(),
        "pid": os.getpid(),
    }
    try:
        mode = task["mode"]
        outputs = task.get("outputs") or []
        if mode == "callable":
            result = task["func"](dict(task["point"]))
        elif mode == "function":
            fn = _resolve_function(task["function"])
            kwargs = {k: to_si(v) for k, v in apply_overrides(task["base"], task["point"]).items()}
            result = fn(**kwargs)
        elif mode == "scenario":
            from .scenario import run_scenario  # imported on the worker

            scenario = apply_overrides(task["base"], task["point"])
            kw = {"outdir": task.get("run_dir"), "progress": False, "quiet": True}
            if task.get("base_dir"):
                kw["base_dir"] = task["base_dir"]
            try:
                result = run_scenario(scenario, **kw)
            except TypeError as exc:  # a runner without base_dir
                if "base_dir" not in kw or "base_dir" not in str(exc):
                    raise
                kw.pop("base_dir")
                result = run_scenario(scenario, **kw)
        else:  # pragma: no cover - internal
            raise ValueError(f"unknown mode {mode!r}")
        record["outputs"] = _jsonable(_normalise_result(result, outputs))
        if mode == "scenario":
            summ = getattr(result, "summary", None) or (result.get("summary") if isinstance(result, Mapping) else None)
            if isinstance(summ, Mapping) and "converged" in summ:
                record["converged"] = bool(summ["converged"])
    except (KeyboardInterrupt, SystemExit):
        raise
    except Exception as exc:  # the point failed: record why, retry on the next run
        record["status"] = "failed"
        record["error"] = f"{type(exc).__name__}: {exc}"
        record["traceback"] = traceback.format_exc(limit=20)
    record["elapsed"] = time.perf_counter() - t0
    record["finished"] = time.strftime("%Y-%m-%dT%H:%M:%S%z")
    return record


# --------------------------------------------------------------------------------------
# Point files
# --------------------------------------------------------------------------------------

def _point_file(outdir: Path, h: str) -> Path:
    return outdir / "points" / f"{h}.json"


def write_record(outdir: Path, record: Mapping) -> Path:
    """Write one point record atomically to ``outdir/points/<hash>.json``."""
    path = _point_file(outdir, record["hash"])
    atomic_write_text(path, json.dumps(_jsonable(record), indent=1, sort_keys=True) + "\n")
    return path


def read_points(outdir: str | os.PathLike) -> dict[str, dict]:
    """Every readable point record under ``outdir/points``, by hash (corrupt files skipped)."""
    folder = Path(outdir) / "points"
    out = {}
    if not folder.is_dir():
        return out
    for f in folder.glob("*.json"):
        try:
            rec = json.loads(f.read_text(encoding="utf-8"))
        except (OSError, ValueError):
            continue
        if _is_record(rec, f.stem):
            out[f.stem] = rec
    return out


def _is_record(rec, h: str) -> bool:
    """A whole point record of point ``h`` (a file that is not one, e.g. one cut short by a
    crash of a writer that was not atomic, counts as missing and its point is computed again)."""
    return (isinstance(rec, dict) and rec.get("hash") == h and rec.get("status") in ("ok", "failed")
            and isinstance(rec.get("outputs"), dict))


# --------------------------------------------------------------------------------------
# Gathering
# --------------------------------------------------------------------------------------

def _coord_values(values: list):
    """Coordinate array for a parameter: SI floats when every value is a number or a
    quantity string of one unit, else strings.  Returns (array, attrs)."""
    conv = [to_si(v) for v in values]
    if all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in conv):
        attrs = {}
        units = {_si_unit(v) for v in values if isinstance(v, str)}
        if len(units) == 1 and "" not in units:
            attrs["units"] = units.pop()
        if any(isinstance(v, str) for v in values):
            attrs["labels"] = [str(v) for v in values]
        return np.array(conv, dtype=float), attrs
    return np.array([v if isinstance(v, str) else _canonical(v) for v in values], dtype=object), {}


def _output_names(spec: SweepSpec, records: Mapping[str, dict]) -> list[str]:
    names = list(spec.outputs)
    if not names:
        for rec in records.values():
            for k in (rec.get("outputs") or {}):
                if k not in names:
                    names.append(k)
    return names


RESERVED = {"status", "elapsed", "hash", "point", "error"}


def _var_names(names: list[str], keys: Iterable[str]) -> dict[str, str]:
    """Variable / column name of each output: the output's own name, or ``out.<name>`` when
    it clashes with a swept key or a reserved name (a function that echoes its inputs)."""
    taken = set(keys) | RESERVED
    return {n: (f"out.{n}" if n in taken else n) for n in names}


def _value(rec, name):
    if rec is None or rec.get("status") != "ok":
        return math.nan
    v = (rec.get("outputs") or {}).get(name)
    if v is None or isinstance(v, str):
        return math.nan
    return float(v)


def gather(spec: SweepSpec, outdir: str | os.PathLike, records: Mapping[str, dict] | None = None,
           runner: str | None = None):
    """Collect the point records of ``spec`` into an ``xarray.Dataset``.

    A full grid gets one dimension per parameter (coordinates in SI where the values carry
    units); otherwise a ``point`` dimension with one coordinate per swept key.  Data
    variables: every output (NaN where a point failed or is missing), ``status``
    ("ok" | "failed" | "missing"), ``elapsed`` (s), ``hash``.
    """
    import xarray as xr

    outdir = Path(outdir)
    records = read_points(outdir) if records is None else records
    tasks = spec.tasks(runner)
    recs = [records.get(h) for h, _ in tasks]
    names = _output_names(spec, {h: r for (h, _), r in zip(tasks, recs) if r is not None})
    status = np.array([(r or {}).get("status", "missing") if r else "missing" for r in recs], dtype=object)
    elapsed = np.array([float(r.get("elapsed", math.nan)) if r else math.nan for r in recs])
    hashes = np.array([h for h, _ in tasks], dtype=object)
    keys = list(spec.parameters) if spec.is_grid else spec.swept_keys()
    vnames = _var_names(names, keys)
    data = {vnames[n]: np.array([_value(r, n) for r in recs]) for n in names}
    attrs = {"sweep": spec.name, "description": spec.description, "runner": runner or spec.runner,
             "n_points": len(tasks), "n_ok": int(np.sum(status == "ok")),
             "n_failed": int(np.sum(status == "failed")), "n_missing": int(np.sum(status == "missing")),
             "base": _canonical(spec.base)}
    if spec.is_grid:
        dims = list(spec.parameters)
        shape = tuple(len(v) for v in spec.parameters.values())
        coords = {}
        for k, vals in spec.parameters.items():
            arr, cattrs = _coord_values(vals)
            coords[k] = xr.Variable((k,), arr, cattrs)
        variables = {n: (dims, v.reshape(shape)) for n, v in data.items()}
        variables["status"] = (dims, status.reshape(shape).astype(str))
        variables["elapsed"] = (dims, elapsed.reshape(shape), {"units": "s"})
        variables["hash"] = (dims, hashes.reshape(shape).astype(str))
        return xr.Dataset(variables, coords=coords, attrs=attrs)
    overrides = [o for _, o in tasks]
    coords = {"point": np.arange(len(tasks))}
    for k in spec.swept_keys():
        vals = [o.get(k) for o in overrides]
        if all(v is not None for v in vals):
            arr, cattrs = _coord_values(vals)
        else:
            arr, cattrs = np.array([_canonical(v) for v in vals], dtype=object).astype(str), {}
        coords[k] = xr.Variable(("point",), arr if arr.dtype != object else arr.astype(str), cattrs)
    variables = {n: (("point",), v) for n, v in data.items()}
    variables["status"] = (("point",), status.astype(str))
    variables["elapsed"] = (("point",), elapsed, {"units": "s"})
    variables["hash"] = (("point",), hashes.astype(str))
    return xr.Dataset(variables, coords=coords, attrs=attrs)


def write_results(spec: SweepSpec, outdir: str | os.PathLike, records: Mapping[str, dict] | None = None,
                  runner: str | None = None) -> tuple[Path, Path]:
    """Write ``results.nc`` and ``results.csv`` (atomically, and both moved into place
    together) and return their paths."""
    outdir = Path(outdir)
    records = read_points(outdir) if records is None else records
    with staged():
        return _write_results(spec, outdir, records, runner)


def _write_results(spec, outdir: Path, records, runner) -> tuple[Path, Path]:
    ds = gather(spec, outdir, records, runner)
    nc = outdir / "results.nc"
    with atomic_path(nc) as tmp:
        ds.to_netcdf(tmp, engine="netcdf4" if _has_netcdf4() else None)
    tasks = spec.tasks(runner)
    names = _output_names(spec, {h: records[h] for h, _ in tasks if h in records})
    keys = spec.swept_keys()
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    vnames = _var_names(names, keys)
    w.writerow(["hash", "status"] + keys + [vnames[n] for n in names] + ["elapsed", "error"])
    for h, o in tasks:
        rec = records.get(h)
        row = [h, rec.get("status", "missing") if rec else "missing"]
        row += [_csv_cell(o.get(k)) for k in keys]
        row += [_csv_cell(_value(rec, n)) for n in names]
        row += [_csv_cell(rec.get("elapsed")) if rec else "", (rec or {}).get("error") or ""]
        w.writerow(row)
    csv_path = outdir / "results.csv"
    atomic_write_text(csv_path, buf.getvalue())
    return nc, csv_path


def _csv_cell(v):
    if v is None:
        return ""
    if isinstance(v, float):
        return "" if math.isnan(v) else repr(v)
    if isinstance(v, (dict, list)):
        return _canonical(v)
    return v


def _has_netcdf4() -> bool:
    try:
        import netCDF4  # noqa: F401

        return True
    except ImportError:
        return False


# --------------------------------------------------------------------------------------
# Running the sweep
# --------------------------------------------------------------------------------------

@dataclass
class SweepResult:
    """What :func:`run_sweep` did.

    Attributes
    ----------
    outdir : Path
    n_points : int
        Points in the sweep.
    n_done_before : int
        Points with a successful record before this run (skipped).
    n_run : int
        Points computed in this run.
    n_ok, n_failed : int
        Points with a successful / failed record after this run.
    wall_time : float
        Seconds this run took.
    results_nc, results_csv : Path or None
        The gathered files.
    dataset : xarray.Dataset or None
    failed : dict
        hash -> error message of the failed points.
    """

    outdir: Path
    n_points: int
    n_done_before: int
    n_run: int
    n_ok: int
    n_failed: int
    wall_time: float
    results_nc: Path | None = None
    results_csv: Path | None = None
    dataset: Any = None
    failed: dict = field(default_factory=dict)

    @property
    def complete(self) -> bool:
        return self.n_ok == self.n_points

    @property
    def exit_code(self) -> int:
        """0 when every point succeeded, 1 otherwise (for the CLI)."""
        return 0 if self.complete else 1

    def as_dict(self) -> dict:
        return {"outdir": str(self.outdir), "n_points": self.n_points, "n_done_before": self.n_done_before,
                "n_run": self.n_run, "n_ok": self.n_ok, "n_failed": self.n_failed,
                "wall_time": self.wall_time,
                "results_nc": str(self.results_nc) if self.results_nc else None,
                "results_csv": str(self.results_csv) if self.results_csv else None,
                "failed": dict(self.failed)}


class _Progress:
    """Rich progress bar (or nothing)."""

    def __init__(self, enabled: bool, total: int, label: str):
        self.bar = None
        if enabled and total:
            try:
                from rich.progress import (BarColumn, MofNCompleteColumn, Progress, TextColumn,
                                           TimeElapsedColumn, TimeRemainingColumn)

                self.bar = Progress(TextColumn("[bold]{task.description}"), BarColumn(), MofNCompleteColumn(),
                                    TimeElapsedColumn(), TimeRemainingColumn(), transient=False)
                self.task = self.bar.add_task(label, total=total)
                self.bar.start()
            except Exception:  # pragma: no cover - rich missing or no terminal
                self.bar = None

    def advance(self, failed: bool = False):
        if self.bar is not None:
            self.bar.advance(self.task)

    def close(self):
        if self.bar is not None:
            self.bar.stop()


def _say(msg: str, quiet: bool) -> None:
    if not quiet:
        print(msg, file=sys.stderr, flush=True)


def run_sweep(
    spec,
    outdir: str | os.PathLike,
    scheduler=None,
    n_workers: int | None = None,
    progress: bool = True,
    func: Callable[[dict], Mapping] | None = None,
    *,
    quiet: bool | None = None,
    retry_failed: bool = True,
    gather_results: bool = True,
    max_points: int | None = None,
) -> SweepResult:
    """Run every point of a sweep that has no successful record in ``outdir``.

    Parameters
    ----------
    spec : SweepSpec, path or dict
        The sweep (a path is read with :meth:`SweepSpec.from_file`).
    outdir : path
        Results folder: ``points/<hash>.json`` per point, ``results.nc``, ``results.csv``,
        ``sweep.json`` (the spec echoed).
    scheduler : None, "synchronous", "local", address or distributed.Client
        None / "local": a ``LocalCluster`` of ``n_workers`` single-threaded worker
        processes, closed at the end.  An address (``"tcp://host:8786"``): an existing
        scheduler.  "synchronous": in this process, no Dask (tests, debugging).
    n_workers : int, optional
        Local cluster size (default ``min(2, cpu count)``).
    progress : bool
        Show a progress bar.
    func : callable, optional
        ``func(point) -> dict of scalars`` replaces the spec's runner (library use; the
        point is the dict of overrides as written in the spec).
    quiet : bool, optional
        No messages (default: ``not progress``).
    retry_failed : bool
        Run the points whose record says "failed" again (default).
    gather_results : bool
        Write ``results.nc`` / ``results.csv`` at the end.
    max_points : int, optional
        Run at most this many of the missing points (the rest stay missing).

    Returns
    -------
    SweepResult
    """
    t0 = time.perf_counter()
    spec = load_sweep(spec)
    quiet = (not progress) if quiet is None else quiet
    outdir = Path(outdir)
    (outdir / "points").mkdir(parents=True, exist_ok=True)
    if func is not None:
        runner = "callable:" + getattr(func, "__module__", "?") + ":" + getattr(func, "__qualname__", repr(func))
    else:
        runner = spec.runner
    tasks = spec.tasks(runner)
    atomic_write_text(outdir / "sweep.json", json.dumps(_jsonable({
        "name": spec.name, "description": spec.description, "runner": runner,
        "source": str(spec.source) if spec.source else None,
        "scenario": str(spec.scenario_path) if spec.scenario_path else None,
        "base": spec.base, "parameters": spec.parameters, "points": spec.points,
        "outputs": spec.outputs, "is_grid": spec.is_grid, "n_points": len(tasks),
        "solver_version": _solver_version.SOLVER_VERSION,
        "hashes": [h for h, _ in tasks],
    }), indent=1) + "\n")

    _clean_stale_tmp(outdir)
    records = read_points(outdir)
    done = {h for h, _ in tasks if records.get(h, {}).get("status") == "ok"}
    todo = [(h, o) for h, o in tasks if h not in done and (retry_failed or h not in records)]
    if max_points is not None:
        todo = todo[:max(0, int(max_points))]
    _say(f"sweep {spec.name!r}: {len(done)} of {len(tasks)} points done, running {len(todo)}", quiet)

    base_task = {"outputs": spec.outputs}
    if func is not None:
        base_task.update(mode="callable", func=func)
    elif spec.function:
        base_task.update(mode="function", function=spec.function, base=spec.base)
    else:
        base_task.update(mode="scenario", base=spec.base,
                         base_dir=str(spec.scenario_path.parent) if spec.scenario_path else
                         (str(spec.source.parent) if spec.source else None))

    def make_task(h, o):
        t = dict(base_task, hash=h, point=o)
        if t["mode"] == "scenario" and spec.keep_runs:
            t["run_dir"] = str((outdir / "runs" / h).resolve())
        return t

    n_run = 0
    bar = _Progress(progress and not quiet, len(todo), spec.name)

    def finish(rec):
        nonlocal n_run
        write_record(outdir, rec)
        records[rec["hash"]] = rec
        n_run += 1
        bar.advance(rec["status"] != "ok")
        if rec["status"] != "ok":
            _say(f"point {rec['hash']} {rec.get('point')} failed: {rec.get('error')}", quiet or bar.bar is not None)

    try:
        if not todo:
            pass
        elif scheduler == "synchronous" or scheduler == "sync":
            for h, o in todo:
                finish(run_point(make_task(h, o)))
        else:
            _run_distributed(todo, make_task, finish, scheduler, n_workers, quiet)
    finally:
        bar.close()

    nc = csv_path = ds = None
    if gather_results:
        nc, csv_path = write_results(spec, outdir, records, runner)
        ds = gather(spec, outdir, records, runner)
    final = [records.get(h) for h, _ in tasks]
    n_ok = sum(1 for r in final if r and r.get("status") == "ok")
    failed = {h: r.get("error") for (h, _), r in zip(tasks, final) if r and r.get("status") == "failed"}
    res = SweepResult(outdir=outdir, n_points=len(tasks), n_done_before=len(done), n_run=n_run, n_ok=n_ok,
                      n_failed=len(failed), wall_time=time.perf_counter() - t0, results_nc=nc,
                      results_csv=csv_path, dataset=ds, failed=failed)
    _say(f"sweep {spec.name!r}: {n_ok} of {len(tasks)} ok, {len(failed)} failed, "
         f"{len(tasks) - n_ok - len(failed)} missing ({res.wall_time:.1f} s)" +
         (f"; results in {nc}" if nc else ""), quiet)
    return res


def _clean_stale_tmp(outdir: Path, age: float = 60.0) -> None:
    """Remove temporary files a killed sweep left behind (older than ``age`` seconds, so a
    write in progress elsewhere is never touched)."""
    now = time.time()
    for folder in (outdir, outdir / "points", *sorted((outdir / "runs").glob("*"))):
        for f in folder.glob(TMP_GLOB):
            try:
                if now - f.stat().st_mtime > age:
                    f.unlink()
            except OSError:
                pass


@contextmanager
def _sigint_ignored():
    """Ignore SIGINT in this process while a local cluster starts its worker processes.

    The workers inherit the ignored signal, so a Ctrl-C at the terminal, which goes to the
    whole process group, is handled by this process alone: it stops the cluster and says what
    is saved, instead of every worker printing a traceback.  (A Ctrl-C during these seconds
    is lost; the next one works.)  Outside the main thread nothing changes."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    try:
        old = signal.signal(signal.SIGINT, signal.SIG_IGN)
    except (ValueError, OSError):  # pragma: no cover - no signals here
        yield
        return
    try:
        yield
    finally:
        signal.signal(signal.SIGINT, old if old is not None else signal.SIG_DFL)


def _run_distributed(todo, make_task, finish, scheduler, n_workers, quiet):
    from distributed import Client, LocalCluster, as_completed

    cluster = None
    own_client = True
    if isinstance(scheduler, Client):
        client, own_client = scheduler, False
    elif scheduler in (None, "local", "processes"):
        n = n_workers or min(2, os.cpu_count() or 1)
        with _sigint_ignored():  # the worker processes never see a Ctrl-C
            cluster = LocalCluster(n_workers=n, threads_per_worker=1, processes=True, dashboard_address=":0",
                                   silence_logs=50)
        client = Client(cluster)
        _say(f"local Dask cluster: {n} worker process(es)", quiet)
    elif isinstance(scheduler, str):
        client = Client(scheduler)
        _say(f"Dask scheduler {scheduler}", quiet)
    else:
        raise InputError("scheduler", f"must be None, 'synchronous', 'local', an address or a Client, got {scheduler!r}")
    futures = {}
    try:
        for h, o in todo:
            fut = client.submit(run_point, make_task(h, o), pure=False, key=f"point-{h}-{os.getpid()}-{time.time_ns()}")
            futures[fut] = (h, o)
        for fut in as_completed(list(futures)):
            h, o = futures.pop(fut)
            try:
                rec = fut.result()
            except (KeyboardInterrupt, SystemExit):
                raise
            except Exception as exc:  # the worker died, or the task could not run
                rec = {"version": RECORD_VERSION, "solver_version": _solver_version.SOLVER_VERSION, "hash": h,
                       "point": _jsonable(o), "status": "failed",
                       "outputs": {}, "error": f"{type(exc).__name__}: {exc}", "elapsed": None,
                       "finished": time.strftime("%Y-%m-%dT%H:%M:%S%z")}
            finish(rec)
    finally:
        for fut in futures:
            fut.cancel()
        if own_client:
            client.close()
        if cluster is not None:
            cluster.close()


# --------------------------------------------------------------------------------------
# CLI hook
# --------------------------------------------------------------------------------------

def default_outdir(path: str | os.PathLike) -> Path:
    """``results/<sweep file stem>`` under the current folder (like ``tribobem run``)."""
    return Path("results") / Path(path).stem


def sweep_command(path, out=None, scheduler=None, workers=None, quiet=False, json_output=False) -> int:
    """Entry point for ``tribobem sweep SWEEP.toml`` (the CLI wires its options to these).

    Parameters
    ----------
    path : str
        The sweep file.
    out : str, optional
        Results folder (default ``results/<stem>`` in the current folder, as for ``tribobem run``).
    scheduler : str, optional
        ``ADDRESS`` of a Dask scheduler, "local" (default) or "synchronous"; default from
        the sweep file's ``scheduler`` key.
    workers : int, optional
        Local cluster size; default from the sweep file's ``workers`` key, else min(2, cpus).
    quiet : bool
        No progress bar and no messages.
    json_output : bool
        Print the :class:`SweepResult` as JSON on stdout.

    Returns
    -------
    int
        Exit code: 0 when every point succeeded, 1 when some failed, 130 when interrupted
        (Ctrl-C; the finished points are kept).
    """
    spec = SweepSpec.from_file(path)
    outdir = Path(out) if out else default_outdir(path)
    before = [file_state(outdir / name) for name in ("results.nc", "results.csv")]
    try:
        res = run_sweep(spec, outdir, scheduler=scheduler or spec.scheduler, n_workers=workers or spec.workers,
                        progress=not quiet and not json_output, quiet=quiet or json_output)
    except KeyboardInterrupt:
        print(interrupted_message(spec, outdir, before), file=sys.stderr, flush=True)
        return 130
    if json_output:
        print(json.dumps(res.as_dict(), indent=1))
    return res.exit_code


def interrupted_message(spec: SweepSpec, outdir: Path, before: list) -> str:
    """The one line ``tribobem sweep`` prints on Ctrl-C: how many points are saved (each point
    record is whole: written atomically, as soon as the point finished) and what became of
    results.nc / results.csv (``before``: their :func:`~tribobem.output.atomic.file_state`
    when the sweep started)."""
    records = read_points(outdir)
    saved = sum(1 for h, _ in spec.tasks() if records.get(h, {}).get("status") == "ok")
    after = [file_state(outdir / name) for name in ("results.nc", "results.csv")]
    if after != before and None not in after:
        results = "results.nc and results.csv are the new complete ones"
    elif None in before:
        results = "results.nc and results.csv were not written"
    else:
        results = "results.nc and results.csv are the previous complete ones, not updated"
    rest = "run the same command again to compute the rest" if saved < len(spec) else "all points are done"
    return f"interrupted: {saved} of {len(spec)} points are saved in {outdir} ({results}); {rest}"
