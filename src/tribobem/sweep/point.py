"""Running one point of a sweep (on a Dask worker or in this process) and its record.

:func:`run_point` is what a worker executes: it runs the point's scenario (or function, or
callable) and returns the point's record, a JSON-ready dict that
:func:`tribobem.sweep.cache.write_record` stores as ``OUTDIR/points/<hash>.json``.
"""

from __future__ import annotations

import importlib
import os
import socket
import time
import traceback
import warnings
from collections.abc import Callable, Iterable, Mapping

import numpy as np

from .. import _solver_version
from ..errors import InputError, ResultWarning
from ..scenario import run_scenario
from ..units import si_value
from .values import _jsonable, apply_overrides

__all__ = ["RECORD_VERSION", "extract_outputs", "run_point", "failed_record"]

#: Record format version written into every point file.
RECORD_VERSION = 1


def _scalar(value):
    if isinstance(value, (bool, np.bool_)):
        return bool(value)
    if isinstance(value, (int, float, np.integer, np.floating)):
        return float(value) if isinstance(value, (float, np.floating)) else int(value)
    if isinstance(value, np.ndarray) and value.ndim == 0:
        return _scalar(value.item())
    return None


def extract_outputs(summary: Mapping, outputs: Iterable[str]) -> dict:
    """Scalars named in ``outputs`` from a run summary.

    Parameters
    ----------
    summary : mapping
        A run summary (file-contract): run-level keys and a ``steps`` list of per-step tables.
        Values are in the summary's units (SI).
    outputs : iterable of str
        Names to pick: a run-level key, else the last step's.  Empty: every run-level scalar
        and every scalar of the last step (run-level wins).

    Returns
    -------
    dict
        Name -> Python scalar (bool, int or float, in the summary's units); a name that is
        absent, or not a scalar, gives None (NaN in the gathered files).
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
    """The callable named by ``"package.module:attr"`` (an InputError when there is none)."""
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

    Parameters
    ----------
    task : mapping
        ``hash``, ``point`` (the overrides, units as written in the sweep file), ``mode``
        ("callable" | "function" | "scenario") and what that mode needs: ``func``;
        ``function`` and ``base`` (a function's keyword arguments get their quantity strings
        converted to SI floats); ``base``, ``base_dir`` and ``run_dir`` (a scenario).
        ``outputs``: the names to keep.

    Returns
    -------
    dict
        The record: ``status`` ("ok" | "failed"), ``outputs`` (name -> scalar, in the units
        the runner returns: SI for scenarios), ``error`` and ``traceback`` of a failed point,
        ``elapsed`` (s), ``started`` / ``finished`` (local time stamps), ``host``, ``pid``,
        the record and solver versions.

    Raises
    ------
    KeyboardInterrupt, SystemExit
        Propagate (a Ctrl-C stops the sweep; the point gets no record).
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
            kwargs = {k: si_value(v) for k, v in apply_overrides(task["base"], task["point"]).items()}
            result = fn(**kwargs)
        elif mode == "scenario":
            # Deferred: the scenario runner (solvers, elasticity, output) is imported on the
            # worker that runs a scenario point, not by every import of tribobem.sweep.

            scenario = apply_overrides(task["base"], task["point"])
            kw = {"outdir": task.get("run_dir"), "progress": False, "quiet": True}
            if task.get("base_dir"):
                kw["base_dir"] = task["base_dir"]
            try:
                with warnings.catch_warnings():  # the result checks are the point's outputs, not stderr
                    warnings.simplefilter("ignore", ResultWarning)
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


def failed_record(h: str, point: Mapping, exc: BaseException) -> dict:
    """The record of a point whose task never returned one (its worker died, or the task
    could not be sent).

    Parameters
    ----------
    h : str
        The point's hash.
    point : mapping
        Its overrides (units as written in the sweep file).
    exc : BaseException
        What the scheduler raised for it.

    Returns
    -------
    dict
        A "failed" record (no outputs; ``elapsed`` None), retried on the next run.
    """
    return {"version": RECORD_VERSION, "solver_version": _solver_version.SOLVER_VERSION, "hash": h,
            "point": _jsonable(point), "status": "failed",
            "outputs": {}, "error": f"{type(exc).__name__}: {exc}", "elapsed": None,
            "finished": time.strftime("%Y-%m-%dT%H:%M:%S%z")}
