"""Gathering the point records of a sweep into ``results.nc`` and ``results.csv``.

A full grid becomes an ``xarray.Dataset`` with one dimension per parameter (coordinates in
SI where the values carry units), any other sweep one with a ``point`` dimension; the CSV
has one row per point.  Both files are written atomically and moved into place together.
"""

from __future__ import annotations

import csv
import io
import math
import os
from collections.abc import Iterable, Mapping
from pathlib import Path

import numpy as np

from ..output.atomic import atomic_path, atomic_write_text, staged
from ..units import si_unit, si_value
from .cache import read_points
from .spec import SweepSpec
from .values import _canonical

__all__ = ["gather", "write_results", "RESERVED"]


def _coord_values(values: list):
    """Coordinate array for a parameter: SI floats when every value is a number or a
    quantity string of one unit, else strings.  Returns (array, attrs)."""
    conv = [si_value(v) for v in values]
    if all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in conv):
        attrs = {}
        units = {si_unit(v) for v in values if isinstance(v, str)}
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


#: Names of the gathered variables / columns that are not outputs: an output of one of these
#: names (or of a swept key) is gathered as ``out.<name>``.
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

    Parameters
    ----------
    spec : SweepSpec
        The sweep.
    outdir : path
        Its results folder (the records are read from there when ``records`` is None).
    records : mapping, optional
        Hash -> record (:func:`~tribobem.sweep.cache.read_points`).
    runner : str, optional
        The runner the hashes were made with (default ``spec.runner``; a callable's own).

    Returns
    -------
    xarray.Dataset
        A full grid gets one dimension per parameter (coordinates in SI where the values
        carry units, with a ``units`` attribute, and the values as written in ``labels``);
        otherwise a ``point`` dimension with one coordinate per swept key.  Data variables:
        every output, in the runner's units (SI for scenarios; NaN where a point failed or is
        missing), ``status`` ("ok" | "failed" | "missing"), ``elapsed`` (s), ``hash``.
    """
    # Deferred: xarray is heavy to import and only needed when the results are gathered.
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
    """Write ``results.nc`` and ``results.csv`` (atomically, and both moved into place together).

    Parameters
    ----------
    spec : SweepSpec
        The sweep.
    outdir : path
        Its results folder, where both files go.
    records : mapping, optional
        Hash -> record (default: :func:`~tribobem.sweep.cache.read_points` of ``outdir``).
    runner : str, optional
        As for :func:`gather`.

    Returns
    -------
    results_nc, results_csv : Path
        The dataset of :func:`gather` (NetCDF) and one CSV row per point: hash, status, the
        swept values as written, the outputs (runner's units), elapsed (s) and the error.
    """
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
    """Whether the netCDF4 engine can be imported (else xarray picks its default engine)."""
    try:
        import netCDF4  # noqa: F401

        return True
    except ImportError:
        return False
