"""summary.json: the scalar results of a run (file contract), written atomically.

Keys every version writes: ``kind``, ``converged`` (all steps), ``inputs`` (the parsed
scenario, SI), ``versions``, ``timings`` and ``steps`` (one dict per load / approach step with
``normal_force``, ``approach``, ``contact_area``, ``repulsive_force``, ``adhesive_force``,
``adhesive_area``, ``max_pressure``, ``mean_gap``, ``iterations``, ``residual``,
``converged``, ...), plus run-level scalars where they apply (``pull_off_force``, ...).
Non-finite numbers are written as ``null`` (strict JSON).
"""

from __future__ import annotations

import json
import math
import os
import platform
import sys
from collections.abc import Mapping
from pathlib import Path

import numpy as np

from .._version import __version__
from ..errors import InputError
from .atomic import atomic_write_text

__all__ = ["STEP_KEYS", "REQUIRED_KEYS", "versions", "jsonable", "write_summary", "read_summary"]

#: Step keys of the 9.1 contract a normal/pull-off step carries.
STEP_KEYS = ("normal_force", "approach", "contact_area", "repulsive_force", "adhesive_force", "adhesive_area",
             "max_pressure", "mean_gap", "iterations", "residual", "converged")
#: Top-level keys every summary.json has.
REQUIRED_KEYS = ("kind", "converged", "inputs", "versions", "timings", "steps")


def versions() -> dict:
    """Versions of tribobem, numpy, scipy and python (and the optional libraries in use).

    Returns
    -------
    dict
        Library name -> version string; pyfftw and mkl_fft where the run imported them (the FFT
        engine); xarray, matplotlib and SurfaceTopography only where they are installed (the
        version of the module the run imported, else the installed distribution's).
    """
    from importlib.metadata import version

    import scipy

    try:
        tb = version("tribobem")
    except Exception:  # pragma: no cover - not installed
        tb = __version__
    out = {"tribobem": tb, "numpy": np.__version__, "scipy": scipy.__version__,
           "python": platform.python_version()}
    for mod in ("pyfftw", "mkl_fft"):  # an optional FFT engine, where the run used it
        m = sys.modules.get(mod)
        if m is not None:
            out[mod] = getattr(m, "__version__", "")
    for mod in ("xarray", "matplotlib", "SurfaceTopography"):
        # the imported module's version where the run imported it, else the installed
        # distribution's (read from its metadata: importing SurfaceTopography and matplotlib only
        # for their versions cost about half a second of every run)
        m = sys.modules.get(mod)
        if m is not None:
            out[mod] = getattr(m, "__version__", "")
            continue
        try:
            out[mod] = version(mod)
        except Exception:  # not installed
            pass
    return out


def jsonable(obj, fallback=str):
    """``obj`` with numpy scalars/arrays turned into Python types and NaN/inf into None.

    Mappings become dicts with string keys, tuples lists, path-like objects strings; any
    other object becomes ``fallback(obj)`` (the sweep's hashes use ``repr``).  NaN becomes None
    because strict JSON has no NaN.

    Parameters
    ----------
    obj : object
        Any value.
    fallback : callable
        Applied to values of no known type.

    Returns
    -------
    object
        A value that ``json.dumps(..., allow_nan=False)`` accepts (if ``fallback`` returns one).
    """
    if isinstance(obj, Mapping):
        return {str(k): jsonable(v, fallback) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [jsonable(v, fallback) for v in obj]
    if isinstance(obj, np.ndarray):
        return jsonable(obj.tolist(), fallback)
    if isinstance(obj, (bool, np.bool_)):
        return bool(obj)
    if isinstance(obj, (int, np.integer)):
        return int(obj)
    if isinstance(obj, (float, np.floating)):
        v = float(obj)
        return v if math.isfinite(v) else None
    if obj is None or isinstance(obj, str):
        return obj
    if isinstance(obj, os.PathLike):
        return os.fspath(obj)
    return fallback(obj)


def write_summary(path, summary: dict) -> Path:
    """Write ``summary`` as strict JSON (NaN -> null), atomically.

    Parameters
    ----------
    path : path-like
        Target file (``.../summary.json``) or a folder (then ``summary.json`` in it).
    summary : dict

    Returns
    -------
    Path
    """
    path = Path(path)
    if path.is_dir():
        path = path / "summary.json"
    text = json.dumps(jsonable(summary), indent=2, allow_nan=False)
    return atomic_write_text(path, text + "\n")


def read_summary(path) -> dict:
    """Read a summary.json (a file or the result folder that holds it).

    Parameters
    ----------
    path : path-like
        The ``summary.json`` file or the result folder.

    Returns
    -------
    dict
        The parsed summary (NaN and inf were written as null).

    Raises
    ------
    FileNotFoundError
        No such file.
    InputError
        The file is not valid JSON.
    """
    path = Path(path)
    if path.is_dir():
        path = path / "summary.json"
    if not path.exists():
        raise FileNotFoundError(f"{path} not found")
    with open(path, encoding="utf-8") as fh:
        try:
            return json.load(fh)
        except json.JSONDecodeError as exc:
            raise InputError("summary", f"{path} is not valid JSON: {exc}") from None
