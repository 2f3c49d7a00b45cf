"""fields.nc: the fields of a run as a NetCDF file (xarray), written atomically.

Layout (dims ``(step, x, y)``; coordinates in m; every variable has a ``units`` attribute):

============================  ==============  ==========================================
variable                      dims            meaning
============================  ==============  ==========================================
``pressure``                  step, x, y      normal traction p (Pa), > 0 compressive
``gap``                       step, x, y      gap g (m), 0 on contact
``displacement``              step, x, y      composite normal displacement u (m)
``contact``                   step, x, y      1 on contact nodes (g = 0)
``adhesive``                  step, x, y      1 in the cohesive zone outside contact
``initial_gap``               x, y            undeformed gap h (m), minimum 0
``roughness_body1/2``         x, y            roughness heights of each body (m)
``label``                     step            "loading 3", "preload", "pull-off", ...
``normal_force``, ``approach``  step          force (N) and approach (m) of the step
``summary_step``              step            index of the step in summary.json (-1: none)
============================  ==============  ==========================================
"""

from __future__ import annotations

from pathlib import Path
from typing import Sequence

import numpy as np

from .summary import atomic_path

__all__ = ["build_fields", "write_fields", "read_fields", "representative_step"]

_ENCODE = {"zlib": True, "complevel": 4}


def build_fields(grid, results: Sequence, labels: Sequence[str], *, initial_gap, roughness1=None,
                 roughness2=None, summary_steps: Sequence[int] | None = None, attrs: dict | None = None):
    """An :class:`xarray.Dataset` of the fields of a run.

    Parameters
    ----------
    grid : Grid
    results : sequence of NormalResult
        One per saved step (may be empty: only the geometry is stored).
    labels : sequence of str
        A label per result ("loading 0", "pull-off", ...).
    initial_gap : ndarray
        Undeformed gap (m).
    roughness1, roughness2 : ndarray, optional
        Roughness heights of the bodies (m).
    summary_steps : sequence of int, optional
        Index of each saved result in summary.json ``steps`` (-1 when not there).
    attrs : dict, optional
        Global attributes (bools become 0/1, None is dropped).

    Returns
    -------
    xarray.Dataset
    """
    import xarray as xr

    n = len(results)
    if len(labels) != n:
        raise ValueError("one label per result")
    if summary_steps is None:
        summary_steps = list(range(n))
    shape = (n,) + tuple(grid.shape)

    def stack(name, dtype=float):
        if n == 0:
            return np.zeros(shape, dtype=dtype)
        return np.stack([np.asarray(getattr(r, name)).astype(dtype, copy=False) for r in results])

    coords = {
        "step": ("step", np.arange(n, dtype=np.int32)),
        "x": ("x", np.asarray(grid.x, dtype=float), {"units": "m", "long_name": "cell-centre x"}),
        "y": ("y", np.asarray(grid.y, dtype=float), {"units": "m", "long_name": "cell-centre y"}),
        "label": ("step", np.array([str(s) for s in labels], dtype=object), {"long_name": "step label"}),
        "normal_force": ("step", np.array([r.force for r in results], dtype=float),
                         {"units": "N", "long_name": "total normal force"}),
        "approach": ("step", np.array([r.approach for r in results], dtype=float),
                     {"units": "m", "long_name": "rigid approach"}),
        "summary_step": ("step", np.asarray(summary_steps, dtype=np.int32),
                         {"long_name": "index of the step in summary.json steps (-1: not listed)"}),
    }
    data = {
        "pressure": (("step", "x", "y"), stack("pressure"),
                     {"units": "Pa", "long_name": "normal traction (positive compressive)"}),
        "gap": (("step", "x", "y"), stack("gap"), {"units": "m", "long_name": "gap"}),
        "displacement": (("step", "x", "y"), stack("displacement"),
                         {"units": "m", "long_name": "composite normal displacement"}),
        "contact": (("step", "x", "y"), stack("contact", np.int8),
                    {"units": "1", "long_name": "contact mask (gap = 0)", "flag_values": "0 1"}),
        "adhesive": (("step", "x", "y"), stack("adhesive", np.int8),
                     {"units": "1", "long_name": "cohesive-zone mask outside contact", "flag_values": "0 1"}),
        "initial_gap": (("x", "y"), np.asarray(initial_gap, dtype=float),
                        {"units": "m", "long_name": "undeformed gap (minimum 0)"}),
    }
    for name, h in (("roughness_body1", roughness1), ("roughness_body2", roughness2)):
        if h is not None:
            data[name] = (("x", "y"), np.asarray(h, dtype=float),
                          {"units": "m", "long_name": f"roughness of {name[-5:]} (positive toward the counter-surface)"})
    ds = xr.Dataset(data, coords=coords)
    clean = {}
    for k, v in (attrs or {}).items():
        if v is None:
            continue
        if isinstance(v, (bool, np.bool_)):
            v = int(v)
        elif not isinstance(v, (int, float, str, np.integer, np.floating)):
            v = str(v)
        clean[k] = v
    clean.setdefault("Conventions", "CF-1.8")
    clean.setdefault("dx", float(grid.dx))
    clean.setdefault("dy", float(grid.dy))
    clean.setdefault("periodic", int(grid.periodic))
    ds.attrs.update(clean)
    return ds


def write_fields(ds, path) -> Path:
    """Write a fields dataset to NetCDF atomically (temporary file, then ``os.replace``).

    Parameters
    ----------
    ds : xarray.Dataset
    path : path-like
        Target file, or a folder (then ``fields.nc`` in it).

    Returns
    -------
    Path
    """
    path = Path(path)
    if path.is_dir():
        path = path / "fields.nc"
    encoding = {name: dict(_ENCODE) for name, var in ds.data_vars.items() if var.ndim >= 2}
    encoding["label"] = {"dtype": str}
    with atomic_path(path) as tmp:
        ds.to_netcdf(tmp, mode="w", format="NETCDF4", engine=_engine(), encoding=encoding)
    return path


def _engine() -> str:
    try:
        import netCDF4  # noqa: F401

        return "netcdf4"
    except ImportError:  # pragma: no cover
        return "h5netcdf"


def read_fields(path):
    """Read a fields.nc (file or result folder) fully into memory (the file is closed)."""
    import xarray as xr

    path = Path(path)
    if path.is_dir():
        path = path / "fields.nc"
    if not path.exists():
        raise FileNotFoundError(f"{path} not found")
    with xr.open_dataset(path, engine=_engine()) as ds:
        return ds.load()


def representative_step(ds) -> int | None:
    """The step the maps show: the one labelled ``pull-off`` if any, else the most loaded
    (largest normal force); None when the dataset has no steps."""
    n = ds.sizes.get("step", 0)
    if n == 0:
        return None
    labels = [str(v) for v in ds["label"].values]
    if "pull-off" in labels:
        return labels.index("pull-off")
    f = np.asarray(ds["normal_force"].values, dtype=float)
    if not np.any(np.isfinite(f)):
        return n - 1
    return int(np.nanargmax(f))
