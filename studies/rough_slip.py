"""Smooth ball on a Gaussian rough flat under a tangential ramp: stick ratio, static friction
and pre-sliding displacement against the roughness rms and the Tabor parameter (thesis
Paper D section 3.2).

The study is a resumable scenario sweep (``examples/studies/rough_ball_slip.toml`` over the
base scenario ``examples/studies/rough_ball_slip_base.toml``, kind ``partial_slip``); this
module holds what the sweep cannot do by itself:

* :func:`flat_surface` / :func:`write_flat`: the 10 x 10 um Hu-Tonder flat of Papers A and D,
  generated as in :mod:`studies.rough_ball` (seed, exponential ACF whose correlation
  length gives rms 5 nm an rms slope of 0.113 on the generation grid), written as a ``.npy``
  height map that the base scenario reads as ``roughness = { kind = "array", crop = ... }``;
* :func:`gather`: one table row per sweep point (rms, mu_T, F0+, F0-, onset ratio, pre-sliding
  displacement, stick ratio at F = 0, contact extent, cohesive-zone resolution) and one
  table of the ramp curves (stick ratio and displacement against F_x / (mu F0+)), read from
  the point records and the kept runs (``keep_runs = true``: ``runs/<hash>/summary.json``);
* :func:`plot_study`: the four-panel figure.

Conventions.  ``rms`` is the rms of the whole 10 um flat (Paper D's scaling: the flat minus its
mean, times a factor); the scenario's ``roughness.rms`` rescales the solved (cropped) window,
so the sweep gives ``rms_window = window_ratio x rms`` and :func:`gather` converts back
(to 4 significant digits: the sweep file writes the window values to 6).
``tabor`` is 0 for the non-adhesive points, else the Tabor parameter of the smooth ball,
``mu_T = (R dgamma^2 / (E*^2 z0^3))^(1/3)`` with ``R`` the ball radius.
"""

from __future__ import annotations

import json
import math
import os
import warnings
from pathlib import Path

import numpy as np

from tribobem.errors import InputError

__all__ = [
    "RADIUS", "E_FLAT", "NU_FLAT", "FORCE", "FRICTION", "Z0", "FLAT_SIZE", "FLAT_N", "SEED",
    "MIN_COHESIVE_CELLS", "UnresolvedCohesiveZoneWarning",
    "effective_modulus", "work_of_adhesion", "tabor_parameter",
    "flat_surface", "write_flat", "window_ratio",
    "gather", "study_table", "paper_d_checks", "stick_zone_track", "repulsive_force_scan", "plot_study",
]

#: Paper D sections 3.1-3.2: rigid ball R = 100 um, elastic flat E = 130 GPa, nu = 0.3,
#: F0 = 10 uN, mu = 0.2, z0 = 0.2 nm.
RADIUS = 100e-6
E_FLAT = 130e9
NU_FLAT = 0.3
FORCE = 10e-6
FRICTION = 0.2
Z0 = 0.2e-9
#: Fewer cells than this across the smooth ball's cohesive zone (c - a): results qualitative.
MIN_COHESIVE_CELLS = 3.0


class UnresolvedCohesiveZoneWarning(UserWarning):
    """The cohesive zone of an adhesive case spans fewer than MIN_COHESIVE_CELLS cells."""


#: The flat: 10 x 10 um on 1024^2 cells (dx = 9.77 nm), seed 1, rms 5 nm, rms slope 0.113.
FLAT_SIZE = 10e-6
FLAT_N = 1024
SEED = 1
FLAT_RMS = 5e-9
FLAT_SLOPE = 0.113


def effective_modulus(E: float = E_FLAT, nu: float = NU_FLAT) -> float:
    """E* of a rigid ball on an elastic flat, E / (1 - nu^2) (Pa)."""
    return E / (1.0 - nu * nu)


def work_of_adhesion(tabor: float, radius: float = RADIUS, z0: float = Z0, E_star: float | None = None) -> float:
    """Work of adhesion (J/m^2) that gives the smooth ball Tabor parameter ``tabor``
    (:meth:`~tribobem.interactions.dugdale.DugdaleAdhesion.from_tabor`)."""
    from tribobem.interactions.dugdale import DugdaleAdhesion

    E_star = effective_modulus() if E_star is None else E_star
    return DugdaleAdhesion.from_tabor(float(tabor), radius, E_star, z0).work_of_adhesion


def tabor_parameter(dgamma: float, radius: float = RADIUS, z0: float = Z0, E_star: float | None = None) -> float:
    """mu_T = (R dgamma^2 / (E*^2 z0^3))^(1/3); 0 for dgamma = 0."""
    E_star = effective_modulus() if E_star is None else E_star
    return float((radius * dgamma**2 / (E_star**2 * z0**3)) ** (1.0 / 3.0)) if dgamma > 0 else 0.0


def flat_surface(n: int = FLAT_N, size: float = FLAT_SIZE, seed: int = SEED, rms: float = FLAT_RMS,
                 slope: float = FLAT_SLOPE, correlation_length: float | None = None):
    """The Hu-Tonder Gaussian flat of Papers A and D.

    As :func:`~studies.rough_ball.rough_ball_study` generates it: an exponential-ACF
    Gaussian surface of ``seed`` on ``n x n`` cells over ``size``, whose correlation length is
    calibrated (:func:`~studies.rough_ball.calibrate_correlation_length`) so that the
    surface at rms ``rms`` has rms slope ``slope`` on this grid, scaled to rms ``rms`` (mean 0).

    Returns
    -------
    heights : ndarray (n, n)
        m, zero mean, rms ``rms``.
    info : dict
        ``correlation_length``, ``rms``, ``rms_slope``, ``dx``, ``size``, ``n``, ``seed``.
    """
    from tribobem.geometry import gaussian_surface, rms_slope, scale_to_rms
    from tribobem.grid import Grid
    from .rough_ball import calibrate_correlation_length

    grid = Grid.square(int(n), float(size), periodic=False)
    if correlation_length is None:
        correlation_length = calibrate_correlation_length(grid, rms, slope, seed=seed)
    h = scale_to_rms(gaussian_surface(grid, 1.0, correlation_length, seed=seed), rms)
    info = {"correlation_length": float(correlation_length), "rms": float(rms),
            "rms_slope": float(rms_slope(h, grid)), "dx": grid.dx, "size": float(size), "n": int(n),
            "seed": int(seed)}
    return h, info


def write_flat(path: str | os.PathLike = "results/rough_ball_slip_flat.npy", **kw) -> dict:
    """Write :func:`flat_surface` (keywords passed on) to ``path`` (``.npy``, m) and its
    ``info`` next to it (``.json``); returns the info."""
    path = Path(path)
    h, info = flat_surface(**kw)
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_name("." + path.name + ".tmp.npy")
    np.save(tmp, h)
    os.replace(tmp, path)
    path.with_suffix(".json").write_text(json.dumps(info, indent=1) + "\n", encoding="utf-8")
    return info


def _crop_cells(shape, size, crop) -> tuple[slice, slice]:
    """Index ranges of a ``crop = {x0, y0, lx, ly}`` (m) on a map of ``shape`` over ``size``
    (as :meth:`tribobem.geometry.Topography.crop` snaps it)."""
    (nx, ny), (lx, ly) = shape, size
    dx, dy = lx / nx, ly / ny
    ix0, iy0 = int(round(crop["x0"] / dx)), int(round(crop["y0"] / dy))
    mx, my = int(round(crop["lx"] / dx)), int(round(crop["ly"] / dy))
    return slice(ix0, ix0 + mx), slice(iy0, iy0 + my)


def window_ratio(heights: np.ndarray, size, crop) -> float:
    """rms of the cropped window (mean removed) over the rms of the whole map."""
    sx, sy = _crop_cells(heights.shape, size, crop)
    w = heights[sx, sy]
    return float(np.std(w) / np.std(heights))


# ----------------------------------------------------------------------------- gathering

def _roughness_source(base_scn, base_dir: Path):
    """(heights, (lx, ly), crop dict in m, grid info) of the base scenario's array roughness."""
    from tribobem.scenario.schema import parse_scenario

    sc = parse_scenario(base_scn)
    r = sc.body1.roughness
    if r.kind != "array":
        raise InputError("body1.roughness.kind", "the rough-ball slip study expects an 'array' roughness "
                         f"(the flat written by write_flat), got {r.kind!r}")
    path = Path(r.path)
    if not path.is_absolute():
        path = (base_dir / path).resolve()
    if not path.is_file():
        raise FileNotFoundError(f"the flat {path} is missing: write it with "
                                "studies.rough_slip.write_flat() (the study script does)")
    heights = np.load(path)
    if r.size is not None:
        size = (r.size, r.size)
    elif r.lx is not None:
        size = (r.lx, r.ly)
    else:
        size = sc.grid.lengths
    crop = ({"x0": r.crop.x0, "y0": r.crop.y0, "lx": r.crop.lx, "ly": r.crop.ly} if r.crop is not None
            else {"x0": 0.0, "y0": 0.0, "lx": size[0], "ly": size[1]})
    return heights, size, crop, sc, path


def _read_json(path: Path):
    try:
        return json.loads(path.read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return None


def _extent(fields_path: Path) -> dict:
    """Contact (p > 0) and interaction (p != 0) extents of the stored state of a run."""
    out = {"contact_extent": math.nan, "interaction_extent": math.nan, "edge_margin_cells": math.nan,
           "touches_edge": None, "stored_state": ""}
    if not fields_path.is_file():
        return out
    import xarray as xr

    with xr.open_dataset(fields_path) as ds:
        if "pressure" not in ds or ds.sizes.get("step", 0) == 0:
            return out
        p = ds["pressure"].isel(step=-1).values
        x, y = ds["x"].values, ds["y"].values
        out["stored_state"] = str(ds["label"].values[-1]) if "label" in ds.coords else ""
    X, Y = np.meshgrid(x - 0.5 * (x[0] + x[-1]), y - 0.5 * (y[0] + y[-1]), indexing="ij")
    dx = float(x[1] - x[0])
    half = 0.5 * (x[-1] - x[0]) + 0.5 * dx
    for name, mask in (("contact_extent", p > 0), ("interaction_extent", p != 0)):
        if mask.any():
            out[name] = float(max(np.abs(X[mask]).max(), np.abs(Y[mask]).max()) + 0.5 * dx)
    if math.isfinite(out["interaction_extent"]):
        out["edge_margin_cells"] = (half - out["interaction_extent"]) / dx
        m = p != 0
        out["touches_edge"] = bool(m[0].any() or m[-1].any() or m[:, 0].any() or m[:, -1].any())
    return out


def gather(sweep, outdir):
    """Gather a rough-ball slip sweep.

    Parameters
    ----------
    sweep : path, dict or SweepSpec
        The sweep (``examples/studies/rough_ball_slip.toml``); its base scenario must have an
        ``array`` roughness on body 1 (the flat of :func:`write_flat`) with a ``crop``.
    outdir : path
        The sweep's results folder (``points/``, ``runs/``).

    Returns
    -------
    table : pandas.DataFrame
        One row per point, sorted by (tabor, rms); see :func:`study_table` for the columns.
        Points without a successful record have NaN results and their ``status``.
    curves : pandas.DataFrame
        One row per solved ramp step of every point (``tabor``, ``rms``, ``step``,
        ``force_x``, ``force_ratio`` = F_x/(mu F0+), ``stick_ratio``, ``displacement_x``
        (rigid shift relative to the F_x = 0 state), ``contact_area``, ``stick_area``,
        ``repulsive_force``, ``gross_slip``), plus one row ``step = -1`` per point at the
        refined onset (the last state with stick; its stick ratio is not stored, NaN).
    """
    import pandas as pd

    from tribobem.sweep import load_sweep, read_points

    spec = load_sweep(sweep)
    outdir = Path(outdir)
    base_dir = (spec.scenario_path.parent if spec.scenario_path else
                (spec.source.parent if spec.source else Path.cwd()))
    records = read_points(outdir)
    heights0, size0, crop0, _, flat_path = _roughness_source(spec.base, base_dir)
    grid_info = {}
    rows, curves = [], []
    for h, o in spec.tasks():
        scn = spec.scenario_for(o)
        if any(k.startswith("body1.roughness.") and k != "body1.roughness.rms" for k in o):
            heights, size, crop, sc, _ = _roughness_source(scn, base_dir)
        else:
            from tribobem.scenario.schema import parse_scenario

            heights, size, crop, sc = heights0, size0, crop0, parse_scenario(scn)
        ratio = window_ratio(heights, size, crop)
        rms_window = float(sc.body1.roughness.rms or 0.0)
        mu = float(sc.friction.coefficient)
        dgamma = float(sc.adhesion.work_of_adhesion) if sc.adhesion.enabled else 0.0
        z0 = float(sc.adhesion.z0) if sc.adhesion.z0 is not None else Z0
        R = float(sc.body2.shape.radius)
        E_star = effective_modulus(float(sc.body1.E), float(sc.body1.nu))
        tabor = tabor_parameter(dgamma, R, z0, E_star)
        nx, ny = sc.grid.shape
        lx, ly = sc.grid.lengths
        dx = lx / nx
        grid_info = {"n": nx, "window": lx, "dx": dx}
        rec = records.get(h)
        status = rec.get("status", "missing") if rec else "missing"
        row = {"hash": h, "status": status, "tabor": round(tabor, 3), "work_of_adhesion": dgamma,
               "rms": float(f"{rms_window / ratio:.4g}") if ratio > 0 else math.nan, "rms_window": rms_window,
               "window_ratio": ratio, "friction_coefficient": mu, "normal_force": float(sc.load.force),
               "z0": z0, "radius": R, "n": nx, "window": lx, "dx": dx,
               "elapsed": float(rec["elapsed"]) if rec and rec.get("elapsed") is not None else math.nan}
        if dgamma > 0:
            from tribobem.interactions.dugdale import DugdaleAdhesion

            ad = DugdaleAdhesion(dgamma, z0)
            row.update(sigma0=ad.sigma0, h0=ad.h0)
        else:
            row.update(sigma0=0.0, h0=math.nan)
        summ = _read_json(outdir / "runs" / h / "summary.json") if status == "ok" else None
        run = summ or {}
        steps = run.get("steps") or []
        row.update({
            "repulsive_force": run.get("repulsive_force", math.nan),
            "adhesive_force": run.get("adhesive_force", math.nan),
            "static_friction_force": run.get("static_friction_force", math.nan),
            "static_friction_ratio": run.get("static_friction_ratio", math.nan),
            "onset_repulsive_force": run.get("onset_repulsive_force", math.nan),
            "presliding_displacement": run.get("presliding_displacement", math.nan),
            "zero_force_stick_ratio": run.get("zero_force_stick_ratio", math.nan),
            "gross_slip": run.get("gross_slip"),
            "converged": run.get("converged"),
            "n_ramp_steps": len(steps),
            "onset_refinement_steps": run.get("onset_refinement_steps", math.nan),
            "solve_time": (run.get("timings") or {}).get("solve", math.nan),
            "warnings": "; ".join(run.get("warnings") or []),
        })
        for k in ("repulsive_force", "adhesive_force", "static_friction_force", "static_friction_ratio",
                  "onset_repulsive_force", "presliding_displacement", "zero_force_stick_ratio"):
            if row[k] is None:
                row[k] = math.nan
        row["onset_over_mu_F0"] = row["static_friction_force"] / (mu * row["normal_force"])
        # F = 0 state (the first ramp step when the ramp starts at 0): areas and resolution.
        s0 = steps[0] if steps and abs(steps[0].get("tangential_force_x", 1.0)) < 1e-15 else None
        if s0 is not None:
            ac, aa = float(s0.get("contact_area", math.nan)), float(s0.get("adhesive_area", 0.0) or 0.0)
            row["contact_area"] = ac
            row["adhesive_area"] = aa
            a_eq, c_eq = math.sqrt(ac / math.pi), math.sqrt((ac + aa) / math.pi)
            row["contact_radius"] = a_eq
            row["cohesive_radius"] = c_eq
            row["cohesive_zone_cells"] = (c_eq - a_eq) / dx if dgamma > 0 else math.nan
            row["contact_cells"] = ac / dx**2
        else:
            row.update(contact_area=math.nan, adhesive_area=math.nan, contact_radius=math.nan,
                       cohesive_radius=math.nan, cohesive_zone_cells=math.nan, contact_cells=math.nan)
        row.update(_extent(outdir / "runs" / h / "fields.nc"))
        rows.append(row)
        if not steps:
            continue
        x0 = float(steps[0].get("displacement_x", 0.0)) if s0 is not None else 0.0
        for k, s in enumerate(steps):
            curves.append({"hash": h, "tabor": row["tabor"], "rms": row["rms"], "step": k,
                           "force_x": s.get("tangential_force_x"), "force_ratio": s.get("force_ratio"),
                           "stick_ratio": s.get("stick_ratio"),
                           "displacement_x": float(s.get("displacement_x", math.nan)) - x0,
                           "contact_area": s.get("contact_area"), "stick_area": s.get("stick_area"),
                           "repulsive_force": s.get("repulsive_force"), "gross_slip": bool(s.get("gross_slip"))})
        if math.isfinite(row["static_friction_ratio"]):
            curves.append({"hash": h, "tabor": row["tabor"], "rms": row["rms"], "step": -1,
                           "force_x": row["static_friction_force"], "force_ratio": row["static_friction_ratio"],
                           "stick_ratio": math.nan, "displacement_x": row["presliding_displacement"],
                           "contact_area": math.nan, "stick_area": math.nan,
                           "repulsive_force": row["onset_repulsive_force"], "gross_slip": False})
    table = pd.DataFrame(rows).sort_values(["tabor", "rms"], kind="stable").reset_index(drop=True)
    for _, r in table[(table["tabor"] > 0) & (table["rms"] == 0)].iterrows():
        cz = r["cohesive_zone_cells"]
        if math.isfinite(cz) and cz < MIN_COHESIVE_CELLS:
            warnings.warn(f"mu_T = {r['tabor']:g}: the cohesive zone of the smooth ball spans {cz:.1f} cells "
                          f"(< {MIN_COHESIVE_CELLS:g}; dx = {r['dx'] * 1e9:.2f} nm): the adhesive results of this "
                          "mu_T are qualitative", UnresolvedCohesiveZoneWarning, stacklevel=2)
    table.attrs.update(grid_info)
    table.attrs["flat"] = str(flat_path)
    curves = pd.DataFrame(curves)
    return table, curves


#: Columns of the published table, in order.
TABLE_COLUMNS = [
    "tabor", "rms", "rms_window", "work_of_adhesion", "repulsive_force", "adhesive_force",
    "static_friction_force", "static_friction_ratio", "onset_over_mu_F0", "onset_repulsive_force",
    "presliding_displacement", "zero_force_stick_ratio", "contact_area", "adhesive_area",
    "contact_radius", "cohesive_radius", "cohesive_zone_cells", "contact_cells", "contact_extent",
    "interaction_extent", "edge_margin_cells", "touches_edge", "n_ramp_steps", "onset_refinement_steps",
    "converged", "status", "elapsed", "n", "window", "dx", "z0", "sigma0", "h0", "hash",
]


def study_table(table):
    """The published columns of a :func:`gather` table.

    ``tabor`` (0 = non-adhesive), ``rms`` (flat rms, m), ``rms_window`` (rms of the solved
    window, m), ``work_of_adhesion`` (J/m^2), ``repulsive_force`` F0+ and ``adhesive_force``
    F0- (N, at F_x = 0), ``static_friction_force`` (N) and ``static_friction_ratio``
    F_x/(mu F0+) at the refined gross-slip onset, ``onset_over_mu_F0`` F_x/(mu F0),
    ``onset_repulsive_force`` (F0+ at the onset), ``presliding_displacement`` (m),
    ``zero_force_stick_ratio`` (A_stick/A_contact at F_x = 0), ``contact_area`` and
    ``adhesive_area`` (cohesive zone outside contact) at F_x = 0 (m^2), the equivalent radii
    ``contact_radius`` sqrt(A_c/pi) and ``cohesive_radius`` sqrt((A_c + A_adh)/pi) (m),
    ``cohesive_zone_cells`` ((c - a)/dx, adhesive only), ``contact_cells``, the extents
    (max |x|, |y| from the window centre of p > 0 and of p != 0 in the stored state, m) and
    ``edge_margin_cells`` (cells between the interaction zone and the window's border),
    ``touches_edge``, the ramp bookkeeping and ``elapsed`` (s of the point)."""
    cols = [c for c in TABLE_COLUMNS if c in table.columns]
    return table[cols]


def paper_d_checks(table, curves=None, tracks=None, scan=None) -> list[dict]:
    """Paper D section 3.2's findings, each with ``finding``, ``verdict`` (``"reproduced"``,
    ``"not reproduced"``, ``"partly"`` or ``"missing data"``) and ``detail`` (numbers).

    ``tracks``: optional ``{label: stick_zone_track(...) table}``; each adds the check that
    the stick zone is dragged against the force to the contact's rear edge and shrinks.
    ``scan``: optional :func:`repulsive_force_scan` table; adds the F0+ peak on its denser rms."""
    out = []
    t = table[table["status"] == "ok"]
    na = t[t["tabor"] == 0].sort_values("rms")

    def add(finding, verdict, detail):
        out.append({"finding": finding, "verdict": verdict, "detail": detail})

    # 1. slip annulus at F = 0 from the coupling
    if len(na):
        s = na["zero_force_stick_ratio"].values
        add("slip at F_x = 0 from the normal-tangential coupling (A_stick/A_contact < 1)",
            "reproduced" if np.all(s < 1) else "not reproduced",
            "non-adhesive stick ratio at F_x = 0: " + ", ".join(f"{v:.3f}" for v in s)
            + " (rms " + ", ".join(f"{r * 1e9:g}" for r in na["rms"].values) + " nm)")
    else:
        add("slip at F_x = 0 from the normal-tangential coupling", "missing data", "")
    # 1b. the stick zone is dragged to the rear and shrinks (Paper D Fig. 3)
    for label, tr in (tracks or {}).items():
        if tr is None or len(tr) < 3:
            add(f"stick zone dragged to the rear and shrinking ({label})", "missing data", "")
            continue
        cen = tr["stick_x_centroid"].values
        dx = float(tr["dx"].iloc[0])
        dragged = bool(np.all(np.diff(cen) <= 0.5 * dx) and cen[-1] < cen[0] - dx)
        reach = float(np.min(tr["stick_x_min"].values - tr["contact_x_min"].values)) / dx
        shrink = bool(tr["stick_ratio"].values[-1] < tr["stick_ratio"].values[0])
        add(f"stick zone dragged to the rear and shrinking ({label})",
            "reproduced" if (dragged and shrink and reach <= 2.5) else ("partly" if dragged or shrink else "not reproduced"),
            f"stick centroid {cen[0] * 1e9:.0f} -> {cen[-1] * 1e9:.0f} nm (force along +x), closest approach of the stick "
            f"zone to the contact's rear edge {reach:.1f} cells, stick ratio {tr['stick_ratio'].values[0]:.3f} -> "
            f"{tr['stick_ratio'].values[-1]:.3f} at F_x/(mu F0+) = {tr['force_ratio'].values[-1]:.2f}")
    # 2. non-adhesive: static friction independent of the rms
    if len(na) >= 2:
        r = na["static_friction_ratio"].values
        spread = np.nanmax(r) - np.nanmin(r)
        add("non-adhesive: onset ratio F_x/(mu F0+) independent of the rms",
            "reproduced" if spread < 0.05 else ("partly" if spread < 0.1 else "not reproduced"),
            "onset ratios " + ", ".join(f"{v:.3f}" for v in r) + f" (spread {spread:.3f})")
        s0 = na["zero_force_stick_ratio"].values
        rough_lower = bool(np.all(s0[1:] < s0[0])) if na["rms"].values[0] == 0 else None
        if rough_lower is not None:
            add("non-adhesive: rough contacts start (F_x = 0) with a smaller stick ratio than the smooth one",
                "reproduced" if rough_lower else "not reproduced",
                f"smooth {s0[0]:.3f}, rough " + ", ".join(f"{v:.3f}" for v in s0[1:]))
        d = na["presliding_displacement"].values
        inc = bool(np.all(np.diff(d) > 0))
        add("non-adhesive: pre-sliding displacement rises with the rms",
            "reproduced" if inc else ("partly" if d[-1] > d[0] else "not reproduced"),
            "pre-sliding (nm) " + ", ".join(f"{v * 1e9:.3f}" for v in d))
    else:
        add("non-adhesive: onset ratio independent of the rms; pre-sliding rises", "missing data", "")
    # 2b. adhesion: the onset is set by F0+ (ratio unchanged by mu_T), pre-sliding raised on the
    # smooth ball, not cumulative with roughness
    ad = t[t["tabor"] > 0]
    if len(ad) and len(na):
        dev = []
        for _, r in ad.iterrows():
            ref = na[np.isclose(na["rms"], r["rms"], rtol=1e-6, atol=1e-15)]
            if len(ref):
                dev.append(abs(r["static_friction_ratio"] - ref["static_friction_ratio"].iloc[0]))
        if dev:
            add("adhesive: the onset is mu F0+ times the non-adhesive ratio (F0+, not F0, controls gross slip)",
                "reproduced" if max(dev) < 0.02 else "partly",
                f"largest |onset ratio - non-adhesive ratio at the same rms| = {max(dev):.4f} over {len(dev)} points")
        sm = t[t["rms"] == 0].sort_values("tabor")
        if len(sm) >= 2:
            d = sm["presliding_displacement"].values
            add("smooth ball: adhesion raises the pre-sliding displacement",
                "reproduced" if np.all(np.diff(d) > 0) else "not reproduced",
                ", ".join(f"mu_T = {m:g}: {v * 1e9:.3f} nm" for m, v in zip(sm["tabor"], d)))
        non_cum = []
        for mu_t in sorted(set(ad["tabor"])):
            s = t[t["tabor"] == mu_t].sort_values("rms")
            d = s["presliding_displacement"].values
            non_cum.append((mu_t, bool(np.any(np.diff(d) < 0)), float(np.nanmax(d)), float(d[0])))
        add("adhesive: roughness and adhesion not cumulative (pre-sliding not monotonic in rms with adhesion)",
            "reproduced" if all(c[1] for c in non_cum) else ("partly" if any(c[1] for c in non_cum) else "not reproduced"),
            "; ".join(f"mu_T = {c[0]:g}: pre-sliding {'falls somewhere' if c[1] else 'monotonic'} along rms "
                      f"(smooth {c[3] * 1e9:.3f} nm, max {c[2] * 1e9:.3f} nm)" for c in non_cum))
    # 3. adhesive: F0+ rises then falls with rms, the peak moving to higher rms with mu_T
    peaks = []
    for mu_t in sorted(set(t["tabor"]) - {0.0}):
        s = t[t["tabor"] == mu_t].sort_values("rms")
        if len(s) < 3:
            continue
        f = s["repulsive_force"].values
        k = int(np.nanargmax(f))
        peaks.append((mu_t, float(s["rms"].values[k]), bool(0 < k < len(f) - 1 and f[k] > f[0]), f[k], f[0]))
    if peaks:
        rtf = all(p[2] for p in peaks)
        moving = all(peaks[i + 1][1] >= peaks[i][1] for i in range(len(peaks) - 1))
        strictly = len(peaks) > 1 and peaks[-1][1] > peaks[0][1]
        add("adhesive: F0+ first rises then falls with the rms",
            "reproduced" if rtf else ("partly" if any(p[2] for p in peaks) else "not reproduced"),
            "; ".join(f"mu_T = {p[0]:g}: peak {p[3] * 1e6:.1f} uN at rms {p[1] * 1e9:g} nm (smooth {p[4] * 1e6:.1f} uN)"
                      for p in peaks))
        add("adhesive: the F0+ peak moves to higher rms as mu_T rises",
            "reproduced" if (moving and strictly) else ("partly" if moving else "not reproduced"),
            ", ".join(f"mu_T = {p[0]:g}: {p[1] * 1e9:g} nm" for p in peaks))
    else:
        add("adhesive: F0+ rises then falls with rms, peak moving with mu_T", "missing data", "")
    if scan is not None and len(scan):
        pk = []
        for mu_t in sorted(set(scan["tabor"]) - {0.0}):
            s = scan[np.isclose(scan["tabor"], mu_t)].sort_values("rms")
            f = s["repulsive_force"].values
            k = int(np.nanargmax(f))
            pk.append((mu_t, float(s["rms"].values[k]), f[k], f[0], bool(0 < k < len(f) - 1)))
        moving = all(pk[i + 1][1] >= pk[i][1] for i in range(len(pk) - 1)) and pk[-1][1] > pk[0][1]
        add("adhesive (dense normal-solve scan): F0+ peak interior and moving to higher rms with mu_T",
            "reproduced" if (moving and all(p[4] for p in pk)) else "partly",
            "; ".join(f"mu_T = {p[0]:g}: peak {p[2] * 1e6:.1f} uN at rms {p[1] * 1e9:g} nm (smooth {p[3] * 1e6:.1f})"
                      for p in pk) + f"; scanned rms (nm) {', '.join(f'{r * 1e9:g}' for r in sorted(set(scan['rms'])))}")
    return out


# ----------------------------------------------------------------------------- stick zone

def stick_zone_track(scenario, base_dir=None):
    """Where the stick zone lies along a tangential ramp (Paper D Fig. 3: dragged to the rear
    and shrinking from it).

    Runs ``scenario`` (a ``partial_slip`` scenario dict; nothing is written) and reports, per
    solved ramp step with stick, in the x direction of the force: the contact's extent
    ``contact_x_min``, ``contact_x_max`` and the stick zone's ``stick_x_min``, ``stick_x_max``
    and centroid ``stick_x_centroid`` (m, from the centroid of the F_x = 0 contact), with
    ``force_ratio`` F_x/(mu F0+) and ``stick_ratio``.  Choose forces below the onset: steps
    past it are dropped (no stick).

    Returns
    -------
    pandas.DataFrame
    """
    import copy

    import pandas as pd

    from tribobem.scenario import run_scenario

    scn = copy.deepcopy(dict(scenario))
    scn["output"] = {"fields": "all", "figures": False, "report": False}
    kw = {"outdir": None, "progress": False, "quiet": True}
    if base_dir is not None:
        kw["base_dir"] = base_dir
    res = run_scenario(scn, **kw)
    rows = res.summary["steps"]
    grid = res.problem.grid
    X, Y = np.meshgrid(grid.x, grid.y, indexing="ij")
    out, xc0 = [], None
    for row, tr in zip(rows, res.tangential):
        c, st = np.asarray(tr.contact, bool), np.asarray(tr.stick, bool)
        if xc0 is None:
            xc0 = float(X[c].mean()) if c.any() else 0.0
        if not st.any():
            continue
        out.append({"force_ratio": row.get("force_ratio"), "stick_ratio": tr.stick_ratio,
                    "contact_x_min": float(X[c].min()) - xc0, "contact_x_max": float(X[c].max()) - xc0,
                    "stick_x_min": float(X[st].min()) - xc0, "stick_x_max": float(X[st].max()) - xc0,
                    "stick_x_centroid": float(X[st].mean()) - xc0, "dx": grid.dx})
    return pd.DataFrame(out)


# ----------------------------------------------------------------------------- F0+ scan

def repulsive_force_scan(base_scenario, rms_values, works_of_adhesion, base_dir=None):
    """F0+ and F0- against the flat rms from normal solves alone (no friction): a dense,
    cheap companion of the sweep's F_x = 0 states (the normal-tangential coupling changes F0+
    by ~0.1 % there) that locates the F0+ peak between the sweep's rms values.

    Parameters
    ----------
    base_scenario : dict
        The study's base scenario (its grid, flat, crop, ball, load and z0 are used).
    rms_values : sequence of float
        rms of the whole flat (m).
    works_of_adhesion : sequence of float
        J/m^2 (0: non-adhesive).
    base_dir : path, optional
        Folder of the base scenario (its relative paths).

    Returns
    -------
    pandas.DataFrame
        ``tabor``, ``work_of_adhesion``, ``rms``, ``rms_window``, ``repulsive_force``,
        ``adhesive_force``, ``contact_area``, ``converged``.
    """
    import copy

    import pandas as pd

    from tribobem.scenario import run_scenario

    base_dir = Path(base_dir) if base_dir is not None else Path.cwd()
    heights, size, crop, sc0, _ = _roughness_source(base_scenario, base_dir)
    ratio = window_ratio(heights, size, crop)
    E_star = effective_modulus(float(sc0.body1.E), float(sc0.body1.nu))
    z0 = float(sc0.adhesion.z0) if sc0.adhesion.z0 is not None else Z0
    R = float(sc0.body2.shape.radius)
    rows = []
    for dg in works_of_adhesion:
        for rms in rms_values:
            scn = copy.deepcopy(dict(base_scenario))
            scn["kind"] = "normal"
            scn.pop("friction", None)
            scn["body1"]["roughness"]["rms"] = float(rms) * ratio
            scn["adhesion"] = ({"model": "dugdale", "work_of_adhesion": float(dg), "z0": z0} if dg > 0
                               else {"model": "none"})
            scn["output"] = {"fields": "none", "figures": False, "report": False}
            res = run_scenario(scn, outdir=None, progress=False, quiet=True, base_dir=base_dir)
            st = res.summary["steps"][-1]
            rows.append({"tabor": round(tabor_parameter(float(dg), R, z0, E_star), 3), "work_of_adhesion": float(dg),
                         "rms": float(rms), "rms_window": float(rms) * ratio,
                         "repulsive_force": st.get("repulsive_force"), "adhesive_force": st.get("adhesive_force"),
                         "contact_area": st.get("contact_area"), "converged": bool(res.summary.get("converged"))})
    return pd.DataFrame(rows)


# ----------------------------------------------------------------------------- figure

def plot_study(table, curves, path, title: str | None = None, scan=None) -> None:
    """Four panels: (a) stick ratio against F_x/(mu F0+), non-adhesive, one curve per rms;
    (b) onset ratio F_x/(mu F0+), (c) pre-sliding displacement and (d) F0+ against the rms,
    one line per mu_T.  ``scan``: a :func:`repulsive_force_scan` table, drawn in (d) as thin
    lines (normal solves, no friction)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    t = table[table["status"] == "ok"]
    fig, axs = plt.subplots(2, 2, figsize=(11, 8.6))
    (ax_a, ax_b), (ax_c, ax_d) = axs
    # (a)
    na = t[t["tabor"] == 0].sort_values("rms")
    cmap = plt.get_cmap("viridis")
    for i, (_, r) in enumerate(na.iterrows()):
        c = cmap(i / max(1, len(na) - 1) * 0.9)
        cv = curves[(curves["hash"] == r["hash"]) & (curves["step"] >= 0) & (~curves["gross_slip"])]
        x = list(cv["force_ratio"].values)
        y = list(cv["stick_ratio"].values)
        ax_a.plot(x, y, "o-", color=c, ms=4, label=f"rms {r['rms'] * 1e9:g} nm")
        on = r["static_friction_ratio"]
        if np.isfinite(on) and x:
            ax_a.plot([x[-1], on], [y[-1], 0.0], ":", color=c, lw=1)
            ax_a.plot([on], [0.0], "v", color=c, ms=7)
    ax_a.set_xlabel(r"$F_x / (\mu F_0^+)$")
    ax_a.set_ylabel(r"$A_{stick} / A_{contact}$")
    ax_a.set_xlim(0, 1.02)
    ax_a.set_ylim(0, None)
    ax_a.set_title("(a) non-adhesive: stick ratio along the ramp\n"
                   r"(triangles: refined gross-slip onset; dotted: last solved step to onset)", fontsize=9)
    ax_a.legend(fontsize=8)
    # (b)-(d)
    taus = sorted(set(t["tabor"]))
    palette = ["C0", "C1", "C3", "C2", "C4", "C5"]
    colors = {mu_t: ("k" if mu_t == 0 else palette[i % len(palette)])
              for i, mu_t in enumerate(m for m in taus if m != 0)}
    colors[0.0] = "k"
    rms_all = np.concatenate([t["rms"].values, scan["rms"].values if scan is not None and len(scan) else []])
    lin = np.min(rms_all[rms_all > 0]) if np.any(rms_all > 0) else 1e-9
    for mu_t in taus:
        s = t[t["tabor"] == mu_t].sort_values("rms")
        lab = "non-adhesive" if mu_t == 0 else rf"$\mu_T$ = {mu_t:g}"
        c = colors[mu_t]
        x = s["rms"].values * 1e9
        ax_b.plot(x, s["static_friction_ratio"].values, "o-", color=c, label=lab)
        ax_c.plot(x, s["presliding_displacement"].values * 1e9, "o-", color=c, label=lab)
        ax_d.plot(x, s["repulsive_force"].values * 1e6, "o-", color=c, label=lab)
        if scan is not None and len(scan) and mu_t > 0:
            sc = scan[np.isclose(scan["tabor"], mu_t)].sort_values("rms")
            ax_d.plot(sc["rms"].values * 1e9, sc["repulsive_force"].values * 1e6, "-", color=c, lw=0.8, alpha=0.6)
    for ax in (ax_b, ax_c, ax_d):
        ax.set_xscale("symlog", linthresh=lin * 1e9)
        ax.set_xlabel("flat rms (nm)  (symlog; 0 = smooth)")
        ax.grid(alpha=0.3, which="both")
        ax.legend(fontsize=8)
    ax_b.set_ylabel(r"onset $F_x / (\mu F_0^+)$")
    ax_b.set_title("(b) static friction: onset ratio at gross slip", fontsize=9)
    ax_c.set_ylabel("pre-sliding displacement (nm)")
    ax_c.set_yscale("log")
    ax_c.set_title(r"(c) pre-sliding displacement $\delta_x$ at the onset (from $F_x$ = 0)", fontsize=9)
    ax_d.set_ylabel(r"$F_0^+$ at $F_x$ = 0 ($\mu$N)")
    ax_d.set_yscale("log")
    ax_d.axhline(FORCE * 1e6, color="k", lw=0.8, ls="--")
    ax_d.set_title(r"(d) repulsive force $F_0^+$ at $F_x$ = 0 ($F_0$ = 10 $\mu$N dashed)" +
                   ("\nthin lines: normal solves alone, denser rms" if scan is not None else ""), fontsize=9)
    a = table.attrs
    if title is None:
        title = (f"Rigid ball R = 100 um on the Hu-Tonder flat (E = 130 GPa), F0 = 10 uN, mu = 0.2, z0 = 0.2 nm; "
                 f"{a.get('n', '?')}^2 cells on {a.get('window', float('nan')) * 1e6:g} um "
                 f"(dx = {a.get('dx', float('nan')) * 1e9:.2f} nm)")
    fig.suptitle(title, fontsize=9)
    fig.tight_layout()
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=120)
    plt.close(fig)
