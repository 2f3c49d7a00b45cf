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
``plastic``                   step, x, y      with a hardness: 1 on contact nodes at p = H
``plastic_displacement``      step, x, y      with a hardness: the surface's permanent
                                              (plastic) displacement so far (m)
``initial_gap``               x, y            undeformed gap h (m), minimum 0
``roughness_body1/2``         x, y            roughness heights of each body (m)
``label``                     step            "loading 3", "preload", "pull-off", ...
``normal_force``              step            force of the step (N)
``approach``                  step            approach of the step (m)
``summary_step``              step            index of the step in summary.json (-1: none)
============================  ==============  ==========================================

Tangential kinds (``partial_slip``, ``hysteresis``; only when tangential results are given;
steps without one hold NaN, and 0 in ``stick``):

============================  ==============  ==========================================
variable                      dims            meaning
============================  ==============  ==========================================
``shear_x``, ``shear_y``      step, x, y      tangential traction q on body 1 (Pa)
``slip_x``, ``slip_y``        step, x, y      slip s = u1 - u2 - delta (m): total, or the
                                              increment of the step (``slip_mode`` attr)
``stick``                     step, x, y      1 on stick nodes (|q| < mu p, no slip)
``tangential_force_x/_y``     step            tangential force on body 2 (N)
``displacement_x/_y``         step            rigid displacement of body 2 rel. body 1 (m)
``stick_ratio``               step            A_stick / A_contact (p > 0)
============================  ==============  ==========================================

Slip nodes are the compressive contact (``pressure > 0``) that does not stick.  The global
attribute ``friction_coefficient`` (mu) is set from the tangential results when the caller
does not give it.
"""

from __future__ import annotations

from pathlib import Path
from typing import Sequence

import numpy as np

from .atomic import atomic_path

__all__ = ["build_fields", "write_fields", "read_fields", "representative_step"]

_ENCODE = {"zlib": True, "complevel": 4}


def build_fields(grid, results: Sequence, labels: Sequence[str], *, initial_gap, roughness1=None,
                 roughness2=None, summary_steps: Sequence[int] | None = None, attrs: dict | None = None,
                 tangential: Sequence | None = None):
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
    tangential : sequence of TangentialResult or None, optional
        One entry per result (None where the step has no tangential solution): adds
        ``shear_x/_y``, ``slip_x/_y``, ``stick`` and the per-step tangential coordinates.

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
    if any(getattr(r, "plastic", None) is not None for r in results):
        # a hardness cap: the plastic nodes of each state and the flattening it has left
        def plastic_field(r, name, dtype):
            v = getattr(r, name, None)
            return np.zeros(grid.shape, dtype) if v is None else np.asarray(v).astype(dtype, copy=False)

        data["plastic"] = (("step", "x", "y"), np.stack([plastic_field(r, "plastic", np.int8) for r in results]),
                           {"units": "1", "long_name": "plastic nodes (contact at p = hardness)", "flag_values": "0 1"})
        data["plastic_displacement"] = (
            ("step", "x", "y"), np.stack([plastic_field(r, "plastic_displacement", float) for r in results]),
            {"units": "m", "long_name": "permanent (plastic) surface displacement into the body"})
    for name, h in (("roughness_body1", roughness1), ("roughness_body2", roughness2)):
        if h is not None:
            data[name] = (("x", "y"), np.asarray(h, dtype=float),
                          {"units": "m", "long_name": f"roughness of {name[-5:]} (positive toward the counter-surface)"})
    attrs = dict(attrs or {})
    if tangential is not None:
        if len(tangential) != n:
            raise ValueError("tangential: one entry (a TangentialResult or None) per result")
        _add_tangential(data, coords, tangential, shape, attrs)
    ds = xr.Dataset(data, coords=coords)
    clean = {}
    for k, v in attrs.items():
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


def _add_tangential(data: dict, coords: dict, tangential: Sequence, shape: tuple, attrs: dict) -> None:
    """The tangential variables and per-step coordinates (in place)."""
    n = shape[0]
    shear = np.full((2,) + shape, np.nan)
    slip = np.full((2,) + shape, np.nan)
    stick = np.zeros(shape, dtype=np.int8)
    scal = {k: np.full(n, np.nan) for k in ("tangential_force_x", "tangential_force_y", "displacement_x",
                                              "displacement_y", "stick_ratio")}
    modes, mus = [], []
    for i, t in enumerate(tangential):
        if t is None:
            continue
        q = np.asarray(t.shear, dtype=float)
        s = np.asarray(t.slip, dtype=float)
        if q.shape != (2,) + shape[1:] or s.shape != q.shape:
            raise ValueError(f"tangential[{i}]: shear and slip must have shape {(2,) + shape[1:]}, got "
                             f"{q.shape} and {s.shape}")
        shear[:, i], slip[:, i] = q, s
        stick[i] = np.asarray(t.stick).astype(np.int8)
        scal["tangential_force_x"][i] = t.force_x
        scal["tangential_force_y"][i] = t.force_y
        scal["displacement_x"][i] = t.displacement_x
        scal["displacement_y"][i] = t.displacement_y
        scal["stick_ratio"][i] = t.stick_ratio
        modes.append(str(t.mode))
        mus.append(float(t.friction_coefficient))
    mode = modes[0] if modes and all(m == modes[0] for m in modes) else ("mixed" if modes else "none")
    slip_name = {"total": "total slip", "incremental": "slip increment of the step"}.get(mode, "slip")
    dims = ("step", "x", "y")
    for c, comp in enumerate("xy"):
        data[f"shear_{comp}"] = (dims, shear[c], {"units": "Pa", "long_name": f"tangential traction q_{comp} on body 1"})
    for c, comp in enumerate("xy"):
        data[f"slip_{comp}"] = (dims, slip[c], {"units": "m", "slip_mode": mode,
                                                "long_name": f"{slip_name} s_{comp} = u1 - u2 - delta"})
    data["stick"] = (dims, stick, {"units": "1", "long_name": "stick mask (|q| < mu p, no slip)",
                                   "flag_values": "0 1"})
    for comp in "xy":
        coords[f"tangential_force_{comp}"] = ("step", scal[f"tangential_force_{comp}"],
                                              {"units": "N", "long_name": f"tangential force on body 2 along {comp}"})
        coords[f"displacement_{comp}"] = ("step", scal[f"displacement_{comp}"],
                                          {"units": "m", "long_name": f"rigid displacement of body 2 along {comp}"})
    coords["stick_ratio"] = ("step", scal["stick_ratio"],
                             {"units": "1", "long_name": "stick area / compressive contact area"})
    if mus and attrs.get("friction_coefficient") is None and all(m == mus[0] for m in mus):
        attrs["friction_coefficient"] = mus[0]
    attrs.setdefault("slip_mode", mode)


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
    """Read a fields.nc (file or result folder) fully into memory (the file is closed).

    Loading and closing at once keeps no file handle open, so the result folder can be
    rewritten (or removed on Windows) while the dataset is in use.

    Parameters
    ----------
    path : path-like
        The ``fields.nc`` file or the result folder that holds it.

    Returns
    -------
    xarray.Dataset
        The fields in SI units, loaded into memory.

    Raises
    ------
    FileNotFoundError
        No such file.
    """
    import xarray as xr

    path = Path(path)
    if path.is_dir():
        path = path / "fields.nc"
    if not path.exists():
        raise FileNotFoundError(f"{path} not found")
    with xr.open_dataset(path, engine=_engine()) as ds:
        return ds.load()


def representative_step(ds) -> int | None:
    """The step the maps show: the one labelled ``pull-off`` if any, else the most loaded.

    Parameters
    ----------
    ds : xarray.Dataset
        A fields dataset (:func:`read_fields`).

    Returns
    -------
    int or None
        Index along ``step``: the ``pull-off`` step, else the largest normal force (the last
        step when no force is finite); None when the dataset has no steps.
    """
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
