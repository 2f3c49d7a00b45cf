"""The cache of finished points: point hashes, the point records, resuming a sweep.

Every point of a sweep is identified by :func:`point_hash`, a stable digest of what it
computes (runner, base and overrides, the point's effective solver options and the solver
version :data:`tribobem._solver_version.SOLVER_VERSION`).  Its record is written atomically
to ``OUTDIR/points/<hash>.json`` as soon as it finishes (a scenario point's own results
folder, with ``keep_runs``, is ``OUTDIR/runs/<hash>/``), so a restart with the same spec
finds the finished points by their hashes (:func:`read_points`) and computes only the
others (:func:`pending`), and a changed solver changes every hash, so nothing old is reused.

The hashes are the keys of existing sweep folders: the canonical JSON they are made of
(:func:`tribobem.sweep.values._canonical`) must not change.
"""

from __future__ import annotations

import hashlib
import inspect
import json
import os
import time
from collections.abc import Iterable, Mapping
from pathlib import Path

from .. import _solver_version
from ..errors import InputError
from ..output.atomic import TMP_GLOB, atomic_write_text
from ..scenario.schema import SolverSpec
from .point import _resolve_function
from .values import _canonical, _jsonable, apply_overrides

__all__ = ["point_hash", "solver_options", "point_tasks", "write_record", "read_points", "pending"]


# --------------------------------------------------------------------------------------
# Hashing
# --------------------------------------------------------------------------------------

def point_hash(runner: str, base: Mapping, point: Mapping, solver: Mapping | None = None,
               solver_version: int | None = None) -> str:
    """Stable 16-hex-digit digest of what a point computes.

    Parameters
    ----------
    runner : str
        ``"scenario"``, ``"function:module:attr"`` or ``"callable:..."``.
    base : mapping
        The base scenario (or the fixed keyword arguments of a function), units as written
        (``"10 um"`` and ``1e-5`` are different texts, so different hashes).
    point : mapping
        The point's overrides (dotted keys), units as written.
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
    (a Python function given to :func:`tribobem.sweep.run_sweep`): none.

    Parameters
    ----------
    runner : str
        As for :func:`point_hash`.
    base, point : mapping
        Base scenario (or keyword arguments) and the point's dotted overrides.
    _defaults : mapping, optional
        Internal: the schema's or the function's defaults, looked up once by
        :func:`point_tasks` instead of once per point.

    Returns
    -------
    dict
        Option name -> value, in the units the scenario schema (SI) or the function uses.
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


def point_tasks(runner: str, base: Mapping, overrides: Iterable[Mapping]) -> list[tuple[str, dict]]:
    """``(hash, overrides)`` of every point of a sweep.

    Parameters
    ----------
    runner : str
        As for :func:`point_hash`.
    base : mapping
        Base scenario (or keyword arguments), units as written.
    overrides : iterable of mapping
        Every point's dotted overrides, in sweep order, units as written.

    Returns
    -------
    list of (str, dict)
        The hash covers each point's effective solver options (:func:`solver_options`; the
        schema's or the function's defaults are looked up once per call) and the solver
        version.
    """
    defaults = None
    if runner == "scenario":
        defaults = _scenario_solver_defaults()
    elif runner.startswith("function:"):
        defaults = _function_defaults(runner[len("function:"):])
    return [(point_hash(runner, base, o, solver_options(runner, base, o, defaults)), o) for o in overrides]


# --------------------------------------------------------------------------------------
# Point records
# --------------------------------------------------------------------------------------

def _point_file(outdir: Path, h: str) -> Path:
    return outdir / "points" / f"{h}.json"


def write_record(outdir: Path, record: Mapping) -> Path:
    """Write one point record atomically.

    Parameters
    ----------
    outdir : Path
        The sweep's results folder.
    record : mapping
        A record of :func:`tribobem.sweep.point.run_point` (its ``hash`` names the file).

    Returns
    -------
    Path
        ``outdir/points/<hash>.json``.
    """
    path = _point_file(outdir, record["hash"])
    atomic_write_text(path, json.dumps(_jsonable(record), indent=1, sort_keys=True) + "\n")
    return path


def read_points(outdir: str | os.PathLike) -> dict[str, dict]:
    """Every readable point record of a sweep folder.

    Parameters
    ----------
    outdir : path
        The sweep's results folder (the records are under ``outdir/points``).

    Returns
    -------
    dict
        Hash -> record (``outputs`` in the runner's units: SI for scenarios; ``elapsed`` in s).
        Files that are not whole records (corrupt, cut short, another point's) are skipped,
        so their points count as missing.
    """
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
# Resuming
# --------------------------------------------------------------------------------------

def pending(tasks: list[tuple[str, dict]], records: Mapping[str, dict], retry_failed: bool = True,
            max_points: int | None = None) -> tuple[set[str], list[tuple[str, dict]]]:
    """What a (re)started sweep has done and what it still has to run.

    Parameters
    ----------
    tasks : list of (str, dict)
        ``(hash, overrides)`` of every point (:func:`point_tasks`).
    records : mapping
        The records found (:func:`read_points`).
    retry_failed : bool
        Run the points whose record says "failed" again.
    max_points : int, optional
        Run at most this many of the missing points.

    Returns
    -------
    done : set of str
        Hashes of the points with a successful record (skipped).
    todo : list of (str, dict)
        The points to run, in sweep order.
    """
    done = {h for h, _ in tasks if records.get(h, {}).get("status") == "ok"}
    todo = [(h, o) for h, o in tasks if h not in done and (retry_failed or h not in records)]
    if max_points is not None:
        todo = todo[:max(0, int(max_points))]
    return done, todo


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
