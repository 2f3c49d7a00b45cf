"""The design table: one row per design point, its score against the targets, its rank.

:func:`design_table` reads the sweep's point records (``OUTDIR/points/<hash>.json``) and the
points' detail files (``OUTDIR/design/<hash>.json``) into rows; :func:`rank_rows` scores them
(targets met, then the distance to the missed ones); :func:`write_table` writes
``design.nc`` (xarray, a ``point`` dimension) and ``design.csv``.
"""

from __future__ import annotations

import csv
import io
import math
import os
from collections.abc import Mapping
from pathlib import Path

import numpy as np

from ..output.atomic import atomic_path, atomic_write_text
from ..sweep import read_points
from ..sweep.values import _canonical
from ..units import si_unit, si_value
from .chain import VALUE_KEYS, read_detail

__all__ = ["design_table", "rank_rows", "write_table", "TABLE_VALUES"]

#: The value columns of the table, in order (SI units).
TABLE_VALUES = ("static_friction_force", "static_friction_ratio", "presliding_displacement", "lateral_stiffness_A",
                "lateral_stiffness_B", "lateral_stiffness_C", "pull_off_force", "contact_area", "max_pressure",
                "peak_pressure", "repulsive_force", "capillary_force", "clamp_load", "friction_coefficient", "ramp_max_force")

_UNITS = {"force": "N", "length": "m", "area": "m^2", "pressure": "Pa", "stiffness": "N/m", "dimensionless": "1"}


def _float(v) -> float:
    try:
        f = float(v)
    except (TypeError, ValueError):
        return math.nan
    return f if math.isfinite(f) else math.nan


def design_table(design, tasks, outdir, records: Mapping | None = None) -> list[dict]:
    """One row per design point, in sweep order.

    Parameters
    ----------
    design : DesignSpec
        The design (its targets set ``exceeds_hardness``).
    tasks : list of (str, dict)
        ``(hash, overrides)`` of every point.
    outdir : path
        The design folder.
    records : mapping, optional
        Hash -> sweep record (default: :func:`tribobem.sweep.read_points` of ``outdir``).

    Returns
    -------
    list of dict
        ``index``, ``hash``, ``point`` (the overrides as written), ``status`` ("ok" | "failed"
        | "missing"), ``message`` (the error of a failed point), every :data:`TABLE_VALUES`
        column (SI; NaN when not computed; a failed point keeps the numbers of its stages that
        ran, from its detail file), ``warnings`` (list of str), ``n_warnings``, ``stages``
        (stage -> status, message, elapsed), ``elapsed`` (s), ``exceeds_hardness`` (True,
        False or None without a hardness or a pressure).
    """
    records = read_points(outdir) if records is None else records
    hardness = next((t.max for t in design.targets if t.column == "hardness"), None)
    rows = []
    for i, (h, o) in enumerate(tasks):
        rec = records.get(h)
        det = read_detail(outdir, h)
        status = rec.get("status", "missing") if rec else "missing"
        row = {"index": i, "hash": h, "point": dict(o), "status": status,
               "message": (rec or {}).get("error") or "", "elapsed": _float((rec or {}).get("elapsed"))}
        src = dict((rec or {}).get("outputs") or {}) if status == "ok" else {}
        if det is not None and det.get("values"):
            # the detail file of this very run (a failed point keeps its stages' numbers there)
            src = {**dict(det["values"]), **src} if status == "ok" else dict(det["values"])
        for k in TABLE_VALUES:
            row[k] = _float(src.get(k))
        if det is not None:
            row["warnings"] = list(det.get("warnings") or [])
            row["stages"] = dict(det.get("stages") or {})
        else:
            row["warnings"] = ([] if status != "ok" else
                               [f"({int(src.get('n_warnings') or 0)} warnings; the detail file design/{h}.json is "
                                "missing)"] if src.get("n_warnings") else [])
            row["stages"] = {}
        row["n_warnings"] = len(row["warnings"])
        p = row["peak_pressure"]
        row["exceeds_hardness"] = None if hardness is None or math.isnan(p) else bool(p > hardness)
        rows.append(row)
    return rows


def rank_rows(rows: list[dict], targets) -> list[dict]:
    """Score every row against the targets and rank them (in place; returns ``rows``).

    Parameters
    ----------
    rows : list of dict
        :func:`design_table` rows.
    targets : list of Target
        The design's targets.

    Returns
    -------
    list of dict
        The same rows with ``targets_met`` (count), ``n_targets``, ``distance`` (sum of the
        relative shortfalls of the missed targets, 0 when all are met), ``margin`` (the
        smallest relative margin over the targets; NaN without targets), ``met`` (target label
        -> bool) and ``rank`` (1 = best: most targets met, then the smallest distance, then
        the largest margin; failed and missing points after every computed one).
    """
    for r in rows:
        met, dist, margins, labels = 0, 0.0, [], {}
        for t in targets:
            ok, d, m = t.evaluate(r.get(t.value_column))
            met += ok
            dist += d
            margins.append(m)
            labels[t.label()] = ok
        r["targets_met"] = met
        r["n_targets"] = len(targets)
        r["distance"] = dist
        finite = [m for m in margins if not math.isnan(m)]
        r["margin"] = min(finite) if finite and len(finite) == len(margins) else math.nan
        r["met"] = labels

    def key(r):
        margin = r["margin"] if not math.isnan(r["margin"]) else -math.inf
        return (r["status"] != "ok", -r["targets_met"], r["distance"], -margin, r["index"])

    for k, r in enumerate(sorted(rows, key=key), start=1):
        r["rank"] = k
    return rows


def _param_keys(rows) -> list[str]:
    keys: list[str] = []
    for r in rows:
        for k in r["point"]:
            if k not in keys:
                keys.append(k)
    return keys


def _coord(values: list):
    """SI floats when every value is a number or a quantity string, else strings."""
    conv = [si_value(v) for v in values]
    if all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in conv):
        attrs = {"labels": [str(v) for v in values]}
        units = {si_unit(v) for v in values if isinstance(v, str)}
        if len(units) == 1 and "" not in units:
            attrs["units"] = units.pop()
        return np.array(conv, dtype=float), attrs
    return np.array([v if isinstance(v, str) else _canonical(v) for v in values], dtype=str), {}


def to_dataset(rows: list[dict], attrs: Mapping | None = None):
    """The table as an ``xarray.Dataset`` on a ``point`` dimension.

    Parameters
    ----------
    rows : list of dict
        Ranked rows (:func:`rank_rows`).
    attrs : mapping, optional
        Global attributes (design name, targets, ...).

    Returns
    -------
    xarray.Dataset
        Coordinates: ``point`` and each varied key (SI floats with ``units`` and ``labels``
        where the values carry units, else the values as text).  Variables: every
        :data:`TABLE_VALUES` column (SI, with ``units``), ``exceeds_hardness`` (1, 0, NaN: no
        hardness target or no pressure), ``rank``, ``targets_met``, ``n_targets``,
        ``distance``, ``margin``, ``n_warnings``, ``status``, ``message``, ``warnings`` (joined
        by newlines), ``hash``, ``elapsed`` (s).
    """
    import xarray as xr

    n = len(rows)
    coords = {"point": np.arange(n)}
    for k in _param_keys(rows):
        vals = [r["point"].get(k) for r in rows]
        if any(v is None for v in vals):
            arr, cattrs = np.array([_canonical(v) for v in vals], dtype=str), {}
        else:
            arr, cattrs = _coord(vals)
        coords[k] = xr.Variable(("point",), arr, cattrs)
    data = {}
    for k in TABLE_VALUES:
        dim, desc = VALUE_KEYS[k]
        data[k] = (("point",), np.array([r[k] for r in rows], dtype=float), {"units": _UNITS[dim], "long_name": desc})
    eh = [math.nan if r["exceeds_hardness"] is None else float(r["exceeds_hardness"]) for r in rows]
    data["exceeds_hardness"] = (("point",), np.array(eh), {"long_name": "peak pressure above the hardness target "
                                                                       "(1 yes, 0 no, NaN: no hardness target)"})
    for k in ("rank", "targets_met", "n_targets", "n_warnings"):
        data[k] = (("point",), np.array([r[k] for r in rows], dtype=np.int64))
    data["distance"] = (("point",), np.array([r["distance"] for r in rows], dtype=float),
                        {"long_name": "sum of the relative shortfalls of the missed targets"})
    data["margin"] = (("point",), np.array([r["margin"] for r in rows], dtype=float),
                      {"long_name": "smallest relative margin over the targets"})
    data["elapsed"] = (("point",), np.array([r["elapsed"] for r in rows], dtype=float), {"units": "s"})
    for k in ("status", "message", "hash"):
        data[k] = (("point",), np.array([str(r[k]) for r in rows], dtype=str))
    data["warnings"] = (("point",), np.array(["\n".join(r["warnings"]) for r in rows], dtype=str))
    return xr.Dataset(data, coords=coords, attrs=dict(attrs or {}))


def _cell(v):
    if v is None:
        return ""
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, float):
        return "" if math.isnan(v) else repr(v)
    if isinstance(v, (dict, list)):
        return _canonical(v)
    return v


def to_csv(rows: list[dict]) -> str:
    """The table as CSV text: one row per point in sweep order (``rank`` gives the ranking).

    Parameters
    ----------
    rows : list of dict
        Ranked rows.

    Returns
    -------
    str
        Columns: rank, hash, status, the varied keys (as written), the value columns (SI),
        exceeds_hardness, targets_met, n_targets, distance, n_warnings, elapsed (s), message,
        warnings (joined by " | ").
    """
    keys = _param_keys(rows)
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(["rank", "hash", "status"] + keys + list(TABLE_VALUES) +
               ["exceeds_hardness", "targets_met", "n_targets", "distance", "n_warnings", "elapsed", "message",
                "warnings"])
    for r in rows:
        w.writerow([r["rank"], r["hash"], r["status"]] + [_cell(r["point"].get(k)) for k in keys] +
                   [_cell(r[k]) for k in TABLE_VALUES] +
                   [_cell(r["exceeds_hardness"]), r["targets_met"], r["n_targets"], _cell(r["distance"]),
                    r["n_warnings"], _cell(r["elapsed"]), r["message"], " | ".join(r["warnings"])])
    return buf.getvalue()


def write_table(rows: list[dict], outdir: str | os.PathLike, attrs: Mapping | None = None) -> tuple[Path, Path]:
    """Write ``design.nc`` and ``design.csv`` (each atomically).

    Parameters
    ----------
    rows : list of dict
        Ranked rows.
    outdir : path
        The design folder.
    attrs : mapping, optional
        Global attributes of the NetCDF file.

    Returns
    -------
    design_nc, design_csv : Path
    """
    outdir = Path(outdir)
    ds = to_dataset(rows, attrs)
    nc = outdir / "design.nc"
    with atomic_path(nc) as tmp:
        ds.to_netcdf(tmp)
    csv_path = outdir / "design.csv"
    atomic_write_text(csv_path, to_csv(rows))
    return nc, csv_path
