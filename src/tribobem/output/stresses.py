"""Subsurface stresses of a run's saved states (``[output] stresses = true``).

For every elastic body and every state saved in fields.nc, the stress tensor on planes at the
requested depths (:func:`tribobem.elasticity.subsurface.body_stresses`), stored as its
invariants: von Mises stress, maximum shear stress and the three principal stresses, dims
(step, depth, x, y), float32.  The run's summary gets ``subsurface``: the depths and, per body,
the largest von Mises stress, its depth, position and state, and the largest maximum shear
stress and its depth.

The default depths follow the contact's length scale l, the equivalent radius sqrt(A / pi) of
the largest connected contact patch of the most loaded saved state: 24 planes from 0.05 l to
2 l.  The bodies are homogeneous half-spaces; residual stresses of plastic states (a hardness
cap) are not included: the field is the elastic one of the state's tractions.
"""

from __future__ import annotations

import math

import numpy as np

from ..elasticity.subsurface import body_stresses

__all__ = ["contact_length_scale", "stress_depths", "add_stress_fields"]

#: Number of planes of the default depths.
DEFAULT_PLANES = 24


def contact_length_scale(contact: np.ndarray, cell_area: float) -> float:
    """Equivalent radius sqrt(A / pi) of the largest connected contact patch (m); 0 without contact."""
    from scipy import ndimage

    labels, n = ndimage.label(np.asarray(contact, dtype=bool))
    if n == 0:
        return 0.0
    sizes = np.bincount(labels.ravel())[1:]
    return math.sqrt(float(sizes.max()) * cell_area / math.pi)


def stress_depths(results, grid, depths=None) -> np.ndarray:
    """The planes (m): ``depths`` as given, else 0.05 to 2 times the contact's length scale."""
    if depths is not None:
        return np.asarray(depths, dtype=float)
    if not results:
        return np.zeros(0)
    loaded = max(results, key=lambda r: r.force)
    ell = contact_length_scale(loaded.contact, grid.cell_area)
    if ell <= 0:
        ell = 4.0 * max(grid.dx, grid.dy)
    return np.linspace(0.05, 2.0, DEFAULT_PLANES) * ell


def add_stress_fields(ds, summary: dict, results, tangential, grid, pair, depths=None, summary_steps=None) -> None:
    """Add the subsurface stress fields of ``results`` to ``ds`` and ``summary["subsurface"]``.

    Parameters
    ----------
    ds : xarray.Dataset
        The run's fields (the states of ``results``, in order).
    summary : dict
        The run's summary (gets ``subsurface``).
    results : sequence of NormalResult
        The saved states.
    tangential : sequence of TangentialResult or None, or None
        Their tangential solutions (shear on body 1), where the run has them.
    grid : Grid
    pair : ContactPair
        The bodies (a rigid one has no stresses).
    depths : sequence of float, optional
        Planes (m); default :func:`stress_depths`.
    summary_steps : sequence of int, optional
        Index in summary.json steps of each state.
    """
    z = stress_depths(results, grid, depths)
    info = {"depths": [float(v) for v in z], "bodies": {}}
    if z.size == 0 or not results:
        summary["subsurface"] = info
        return
    ds.coords["depth"] = ("depth", z, {"units": "m", "long_name": "depth below the surface"})
    for b, mat in ((1, pair.body1), (2, pair.body2)):
        if mat.is_rigid:
            continue
        vm = np.empty((len(results), z.size) + tuple(grid.shape), np.float32)
        ts = np.empty_like(vm)
        pr = np.empty((len(results), 3, z.size) + tuple(grid.shape), np.float32)
        for i, res in enumerate(results):
            t = tangential[i] if tangential else None
            shear = getattr(t, "shear", None) if t is not None else None
            s = body_stresses(grid, res.pressure, shear, depths=z, nu=mat.nu, body=b)
            principal = s.principal()
            vm[i] = s.von_mises()
            ts[i] = 0.5 * (principal[0] - principal[2])
            pr[i] = principal
            del s, principal
        name = f"body{b}"
        ds[f"von_mises_{name}"] = (("step", "depth", "x", "y"), vm,
                                   {"units": "Pa", "long_name": f"von Mises stress in {name}"})
        ds[f"max_shear_{name}"] = (("step", "depth", "x", "y"), ts,
                                   {"units": "Pa", "long_name": f"maximum shear stress (s1 - s3) / 2 in {name}"})
        ds[f"principal_stress_{name}"] = (("step", "principal", "depth", "x", "y"), pr,
                                          {"units": "Pa", "long_name": f"principal stresses s1 >= s2 >= s3 in {name} "
                                                                       "(tension positive)"})
        k = np.unravel_index(int(np.argmax(vm)), vm.shape)
        kt = np.unravel_index(int(np.argmax(ts)), ts.shape)
        step = int(summary_steps[k[0]]) if summary_steps is not None else int(k[0])
        info["bodies"][name] = {
            "max_von_mises": float(vm[k]), "max_von_mises_depth": float(z[k[1]]),
            "max_von_mises_x": float(grid.x[k[2]]), "max_von_mises_y": float(grid.y[k[3]]),
            "max_von_mises_step": step, "max_von_mises_state": str(ds["label"].values[k[0]]),
            "max_shear": float(ts[kt]), "max_shear_depth": float(z[kt[1]]),
            "max_tensile_principal": float(pr[:, 0].max()),
        }
        summary[f"max_von_mises_{name}"] = float(vm[k])
        summary[f"max_von_mises_depth_{name}"] = float(z[k[1]])
    if "principal" not in ds.coords and any(v.startswith("principal_stress") for v in ds.data_vars):
        ds.coords["principal"] = ("principal", np.arange(1, 4, dtype=np.int32), {"long_name": "principal stress index"})
    summary["subsurface"] = info
