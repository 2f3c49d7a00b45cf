"""Smooth ball on a Gaussian rough flat: adhesion versus roughness rms (thesis Paper A section 7,
Paper D section 3.2).

A rigid smooth ball of radius ``R = 100 um`` is pressed with ``F0 = 10 uN`` on an elastic
half-space (``E = 130 GPa``, ``nu = 0.3``) whose surface is a Gaussian rough flat with an
exponential ACF (Hu and Tonder).  One base surface is generated once and scaled to each rms
with :func:`~tribobem.geometry.scale_to_rms`, so the asperity layout is the same at every rms
(Papers A, D).  Adhesion is Dugdale (Maugis) with the work of adhesion chosen from the Tabor
parameter of the *smooth* ball, ``mu_T = (R dgamma^2 / (E*^2 z0^3))^(1/3)``.  The ball is a
single contact, so the free-boundary (zero-padded) operator is used.

For every (Tabor parameter, rms) the study reports

* the pull-off force: the most negative force of the displacement-controlled unloading curve
  started from the preload ``F0`` (Papers A, C; :func:`~tribobem.solvers.normal_paths.pull_off`);
* at ``F0`` (force control): the repulsive force ``F0+`` (sum of p > 0), the adhesive force
  ``F0-`` (sum of p < 0, negative) and ``F0-/F0`` (Paper A Fig. 11a), the contact area
  (nodes with g = 0), the cohesive-zone ("adhesive") area (0 < g < h0) and the area ratio
  of Paper A Fig. 11b (defined in :func:`rough_ball_study`).

The work of adhesion follows from mu_T of the smooth sphere; Paper A Fig. 9 and 11 keep it
fixed while the rms changes, and so does this study.
"""

from __future__ import annotations

import math
import time
import warnings
from typing import Callable, Sequence

import numpy as np

from tribobem.analytic.adhesion import maugis_dugdale, maugis_dugdale_pull_off, maugis_parameter
from tribobem.elasticity.operators import free_boundary_operator
from tribobem.errors import ConvergenceWarning, InputError
from tribobem.geometry import gaussian_surface, rms_slope, scale_to_rms, sphere
from tribobem.grid import Grid
from tribobem.interactions.dugdale import DugdaleAdhesion
from tribobem.materials import ContactPair, Material
from tribobem.solvers.normal import solve_normal
from tribobem.solvers.normal_paths import pull_off

__all__ = [
    "PAPER_D_RMS",
    "PAPER_D_SLOPE",
    "calibrate_correlation_length",
    "rough_ball_study",
    "study_table",
    "peak_summary",
]

#: Paper D section 3.2: the base profile has rms 20 z0 = 5 nm and rms slope 0.113.
PAPER_D_RMS = 5e-9
PAPER_D_SLOPE = 0.113


def calibrate_correlation_length(grid: Grid, rms: float = PAPER_D_RMS, slope: float = PAPER_D_SLOPE,
                                 seed=1, bounds=None) -> float:
    """Correlation length (m) for which the Hu-Tonder surface of ``seed`` on ``grid`` with
    rms height ``rms`` has rms slope ``slope``.

    The exponential ACF has no smallest wavelength, so the rms slope of its samples depends on
    the cell size: roughly ``slope^2 ~ 2 ln(10) rms^2 / (beta dx)`` (both directions, forward
    differences, ``dx << beta``).  A correlation length matched to Paper D's slope at one
    ``dx`` is therefore only valid on that grid; the study calibrates it on its own grid.

    Parameters
    ----------
    grid : Grid
    rms, slope : float
        Target rms height (m) and rms slope (-), default Paper D's 5 nm and 0.113.
    seed : int
        Seed of the surface (the same one the study uses).
    bounds : (float, float), optional
        Search interval (m); default ``(dx/2, min(lx, ly)/2)``.

    Returns
    -------
    float
        Correlation length beta (m), the 10 % level of the ACF.
    """
    from scipy.optimize import brentq

    lo, hi = bounds if bounds is not None else (0.5 * min(grid.dx, grid.dy), 0.5 * min(grid.lx, grid.ly))

    def f(beta):
        return rms_slope(gaussian_surface(grid, rms, beta, seed=seed), grid) - slope

    flo, fhi = f(lo), f(hi)
    if flo * fhi > 0:
        raise InputError(
            "roughness.rms_slope",
            f"no correlation length in [{lo:.3g}, {hi:.3g}] m gives rms slope {slope:g} at rms {rms:.3g} m "
            f"on this grid (slopes {flo + slope:.3g} .. {fhi + slope:.3g})",
        )
    return float(brentq(f, lo, hi, xtol=1e-4 * grid.dx))


def rough_ball_study(
    rms_values: Sequence[float],
    tabor_values: Sequence[float] = (1, 2),
    radius: float = 100e-6,
    size: float = 10e-6,
    n: int = 256,
    z0: float = 0.25e-9,
    E: float = 130e9,
    nu: float = 0.3,
    force: float = 10e-6,
    correlation_length: float | None = None,
    seed: int = 1,
    target_slope: float = PAPER_D_SLOPE,
    surface_n: int | None = None,
    domain: float | None = None,
    n_steps: int = 30,
    refine: int = 6,
    tol: float = 1e-9,
    max_iterations: int = 10000,
    keep_fields: bool = False,
    progress: Callable[[int, int], None] | None = None,
):
    """Adhesion of a smooth rigid ball on a rough elastic flat versus the roughness rms.

    Parameters
    ----------
    rms_values : sequence of float
        rms heights of the rough flat (m), >= 0 (0 = smooth; include it as the reference).
    tabor_values : sequence of float
        Tabor parameters mu_T of the smooth ball; each gives the work of adhesion
        ``dgamma = sqrt(mu_T^3 E*^2 z0^3 / R)``.
    radius : float
        Ball radius R (m).
    size : float
        Side of the square computational domain (m), default 10 um (Paper D).
    n : int
        Cells per side.  256 on 10 um gives dx = 39 nm (see Notes on resolution).
    z0 : float
        Equilibrium separation (m); h0 = 0.974 z0.
    E, nu : float
        Elastic flat (the ball is rigid), default Si of Paper D (130 GPa, 0.3).
    force : float
        Normal force F0 (N) at which forces and areas are reported, and the preload of the
        pull-off.
    correlation_length : float, optional
        Correlation length beta of the exponential ACF (m).  Default: calibrated with
        :func:`calibrate_correlation_length` so that rms 5 nm gives rms slope
        ``target_slope`` (0.113, Paper D) on this grid.
    seed : int
        Seed of the single base surface.
    surface_n : int, optional
        Cells per side of the grid the base surface is generated (and its correlation length
        calibrated) on; default ``n``.  With ``surface_n < n`` the surface is Fourier-
        interpolated (it is periodic) onto the ``n x n`` solver grid: the *same* surface
        solved on a finer grid, for resolution checks.
    domain : float, optional
        Side (m) of the central part of the ``size x size`` surface that is solved (the
        ball's apex is at its centre), default ``size``.  With ``domain < size`` the surface
        is generated on ``size`` (``surface_n`` cells), Fourier-interpolated to cells of
        ``domain / n`` and cropped to the central ``n x n`` cells: the same surface near the
        ball at a finer cell size, for the same cost.  Contacts can then only form within
        the domain (the returned ``edge_contact`` says whether the F0 contact or cohesive
        zone touches its border).
    n_steps, refine : int
        Unloading steps and golden-section refinements of the pull-off
        (:func:`~tribobem.solvers.normal_paths.pull_off`).
    tol, max_iterations
        Solver settings.
    keep_fields : bool
        Also return the pressure at F0, ``pressure(tabor, rms, x, y)`` (Paper A Figs. 8, 10).
    progress : callable, optional
        ``progress(done, total)`` after each (tabor, rms) case.

    Returns
    -------
    xarray.Dataset
        Dimensions ``tabor`` and ``rms`` (m); coordinates ``rms_over_z0``, ``rms_slope``
        (forward differences), ``work_of_adhesion``, ``sigma0``, ``h0``, ``maugis``.  Variables
        (SI; forces negative when tensile):

        ``pull_off_force``, ``pull_off_approach``
            Most negative force of the unloading curve from F0, and its approach.
        ``pull_off_contact_area``
            Contact area (g = 0) in the state at pull-off.
        ``repulsive_force`` (F0+), ``adhesive_force`` (F0-), ``adhesive_force_ratio`` (F0-/F0)
            At F0 (force control); F0+ + F0- = F0.
        ``contact_area``
            Nodes with g = 0 (whatever their pressure, -sigma0 < p), m^2.
        ``contact_area_tensile``
            Contact nodes with -sigma0 < p < 0 (Paper D Eq. 11, A_c^2).
        ``adhesive_area``
            Cohesive zone outside contact, 0 < g < h0, where p = -sigma0.
        ``negative_stress_area``
            All nodes with p < 0 = ``contact_area_tensile + adhesive_area``.
        ``area_ratio``
            Paper A Fig. 11b: "the integral of the area with a negative stress over the
            contact area", ``negative_stress_area / contact_area``.  It can exceed 1 (the
            cohesive zone lies outside the contact).
        ``edge_contact``
            True when the contact or cohesive zone at F0 touches the domain's border.
        ``converged``, ``iterations``, ``time``
            Of the F0 solve (``converged`` also requires every pull-off step converged);
            ``time`` is the CPU time of the whole case (s).
        ``dmt_pull_off``, ``jkr_pull_off``, ``md_pull_off`` (per tabor)
            Smooth-sphere references -2 pi R dgamma, -1.5 pi R dgamma and the
            Maugis-Dugdale value (force control) for lambda = 1.16 mu_T.
        ``smooth_contact_radius``, ``smooth_cohesive_radius`` (per tabor)
            Equivalent radii sqrt(A/pi) of the contact and of contact + cohesive zone of the
            smooth ball at F0 on this grid; ``md_contact_radius``, ``md_cohesive_radius``:
            the Maugis-Dugdale values; ``cohesive_zone_cells``: (c - a)/dx of the numerical
            smooth solution, the resolution of the cohesive zone.

    Notes
    -----
    Resolution.  At F0 = 10 uN the smooth ball (E* = 143 GPa) has a ~= 0.37 um, c ~= 0.44 um
    (Maugis-Dugdale, mu_T = 1) and a ~= 0.53 um, c ~= 0.57 um (mu_T = 2): at dx = 39 nm
    (10 um on 256^2) the contact spans ~20-28 cells but the cohesive annulus only ~1.7 and
    ~0.9 cells; at pull-off (mu_T = 2: a = 0.32 um, c - a = 35 nm) it is under-resolved too.
    The discrete contact edge then advances cell by cell ("lattice trapping"): the unloading
    curve is jagged and its minimum, the pull-off, is overestimated against Maugis-Dugdale
    (by ~10-35 % at dx = 39 nm depending on mu_T and on the solver version; ~10 % remains at
    dx = 10 nm).  ``md_pull_off`` and ``cohesive_zone_cells`` are returned to show it.  The
    trend with rms is computed on one grid, so it compares like with like; ``domain`` and
    ``surface_n`` refine the grid on the same surface.  ``size`` must keep the asperities the
    ball can reach at the largest rms (the ball drops by r^2/2R: 45 nm at r = 3 um).

    Large rms.  An exponential ACF has roughness down to the cell size, so at large rms the
    ball rests on one- or two-cell asperities and the pull-off tends to sigma0 dx^2 (one
    cell at -sigma0): a grid-dependent floor, not a converged value.

    Examples
    --------
    >>> ds = rough_ball_study([0, 0.5e-9, 2.5e-9], tabor_values=[1], n=64, size=2.5e-6)  # doctest: +SKIP
    >>> ds.pull_off_force.sel(tabor=1).values  # doctest: +SKIP
    """
    import xarray as xr

    rms_values = np.asarray(rms_values, dtype=float)
    tabor_values = np.asarray(tabor_values, dtype=float)
    if rms_values.ndim != 1 or len(rms_values) == 0 or not np.all(np.isfinite(rms_values)) or np.any(rms_values < 0):
        raise InputError("rms_values", "must be a non-empty list of finite rms heights >= 0 m")
    if tabor_values.ndim != 1 or len(tabor_values) == 0 or not np.all(np.isfinite(tabor_values)) or np.any(tabor_values <= 0):
        raise InputError("tabor_values", "must be a non-empty list of Tabor parameters > 0")
    if not force > 0:
        raise InputError("load.force", f"must be > 0 N, got {force!r}")

    domain = float(size) if domain is None else float(domain)
    if not (0 < domain <= size):
        raise InputError("domain", f"must be in (0, size = {size:g}] m, got {domain!r}")
    grid = Grid.square(int(n), domain, periodic=False)
    pair = ContactPair(Material(E, nu, "flat"), Material.rigid("ball"))
    E_star = pair.effective_modulus
    op = free_boundary_operator(grid, pair)
    n_full = int(round(n * size / domain))
    surface_n = n_full if surface_n is None else int(surface_n)
    if surface_n > n_full or surface_n < 2:
        raise InputError("surface_n", f"must be in [2, n size / domain = {n_full}], got {surface_n}")
    sgrid = Grid.square(surface_n, float(size), periodic=False)
    if correlation_length is None:
        correlation_length = calibrate_correlation_length(sgrid, PAPER_D_RMS, target_slope, seed=seed)
    base = gaussian_surface(sgrid, 1.0, correlation_length, seed=seed)
    if surface_n != n_full:
        from scipy.signal import resample

        base = scale_to_rms(resample(resample(base, n_full, axis=0), n_full, axis=1), 1.0)
    # ``base`` has zero mean and unit rms over the whole size x size surface; ``rms`` below
    # is that of the whole surface, also when only its central part is solved.
    if n_full != n:
        i0 = (n_full - int(n)) // 2
        base = base[i0:i0 + int(n), i0:i0 + int(n)]
    ball = sphere(grid, radius)
    slopes = np.array([rms_slope(r * base, grid) for r in rms_values])

    shape = (len(tabor_values), len(rms_values))
    names = ["pull_off_force", "pull_off_approach", "pull_off_contact_area", "repulsive_force",
             "adhesive_force", "adhesive_force_ratio", "contact_area", "contact_area_tensile",
             "adhesive_area", "negative_stress_area", "area_ratio", "iterations", "time"]
    out = {k: np.full(shape, np.nan) for k in names}
    converged = np.zeros(shape, dtype=bool)
    edge_contact = np.zeros(shape, dtype=bool)
    pressures = np.zeros(shape + grid.shape) if keep_fields else None
    per_tabor = {k: np.full(len(tabor_values), np.nan) for k in (
        "work_of_adhesion", "sigma0", "h0", "maugis", "dmt_pull_off", "jkr_pull_off", "md_pull_off",
        "smooth_contact_radius", "smooth_cohesive_radius", "md_contact_radius", "md_cohesive_radius",
        "cohesive_zone_cells")}

    total, done = len(tabor_values) * len(rms_values), 0
    cell = grid.cell_area
    for i, mu in enumerate(tabor_values):
        ad = DugdaleAdhesion.from_tabor(float(mu), radius, E_star, z0)
        dg = ad.work_of_adhesion
        lam = maugis_parameter(radius, dg, E_star, z0)
        per_tabor["work_of_adhesion"][i] = dg
        per_tabor["sigma0"][i] = ad.sigma0
        per_tabor["h0"][i] = ad.h0
        per_tabor["maugis"][i] = lam
        per_tabor["dmt_pull_off"][i] = -2.0 * math.pi * radius * dg
        per_tabor["jkr_pull_off"][i] = -1.5 * math.pi * radius * dg
        per_tabor["md_pull_off"][i] = float(maugis_dugdale_pull_off(lam, "force")) * math.pi * radius * dg
        # Resolution of the smooth case at F0 (one cheap solve, reused if rms = 0 is asked).
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", ConvergenceWarning)
            smooth = solve_normal(op, ball, force=force, interaction=ad, tol=tol, max_iterations=max_iterations)
        md = maugis_dugdale(radius, dg, E_star, z0, force=force)
        per_tabor["smooth_contact_radius"][i] = smooth.contact_radius()
        per_tabor["smooth_cohesive_radius"][i] = smooth.cohesive_radius()
        per_tabor["md_contact_radius"][i] = float(md.contact_radius)
        per_tabor["md_cohesive_radius"][i] = float(md.cohesive_radius)
        per_tabor["cohesive_zone_cells"][i] = (smooth.cohesive_radius() - smooth.contact_radius()) / grid.dx

        for j, rms in enumerate(rms_values):
            c0 = time.process_time()
            gap = ball - rms * base
            gap = gap - gap.min()
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", ConvergenceWarning)
                if rms == 0.0:
                    res = smooth
                else:
                    res = solve_normal(op, gap, force=force, interaction=ad, tol=tol, max_iterations=max_iterations)
                try:
                    po = pull_off(op, gap, ad, preload=force, n_steps=n_steps, refine=refine, tol=tol,
                                  max_iterations=max_iterations)
                except InputError as exc:  # no converged preload: record the case as failed
                    warnings.warn(f"mu_T = {mu:g}, rms = {rms:.3g} m: pull-off failed ({exc})", ConvergenceWarning,
                                  stacklevel=2)
                    po = None
            p = res.pressure
            neg = float(np.count_nonzero(p < 0)) * cell
            if po is not None:
                out["pull_off_force"][i, j] = po.force
                out["pull_off_approach"][i, j] = po.approach
                state = getattr(po, "state", None)
                if state is not None:
                    out["pull_off_contact_area"][i, j] = state.contact_area
                else:
                    ok = np.where(po.curve.converged)[0]
                    if len(ok):
                        out["pull_off_contact_area"][i, j] = po.curve.contact_area[ok[np.argmin(po.curve.force[ok])]]
            out["repulsive_force"][i, j] = res.repulsive_force
            out["adhesive_force"][i, j] = res.adhesive_force
            out["adhesive_force_ratio"][i, j] = res.adhesive_force / force
            out["contact_area"][i, j] = res.contact_area
            out["contact_area_tensile"][i, j] = res.contact_area_tensile
            out["adhesive_area"][i, j] = res.adhesive_area
            out["negative_stress_area"][i, j] = neg
            out["area_ratio"][i, j] = neg / res.contact_area if res.contact_area > 0 else np.nan
            out["iterations"][i, j] = res.iterations
            converged[i, j] = bool(res.converged and po is not None and np.all(po.curve.converged))
            zone = res.contact | res.adhesive
            edge_contact[i, j] = bool(zone[0].any() or zone[-1].any() or zone[:, 0].any() or zone[:, -1].any())
            if keep_fields:
                pressures[i, j] = p
            out["time"][i, j] = time.process_time() - c0
            done += 1
            if progress:
                progress(done, total)

    dims = ("tabor", "rms")
    data = {k: (dims, v) for k, v in out.items()}
    data["converged"] = (dims, converged)
    data["edge_contact"] = (dims, edge_contact)
    for k, v in per_tabor.items():
        if k in ("work_of_adhesion", "sigma0", "h0", "maugis"):
            continue
        data[k] = (("tabor",), v)
    if keep_fields:
        data["pressure"] = (dims + ("x", "y"), pressures)
    coords = {
        "tabor": tabor_values,
        "rms": rms_values,
        "rms_over_z0": ("rms", rms_values / z0),
        "rms_slope": ("rms", slopes),
        "work_of_adhesion": ("tabor", per_tabor["work_of_adhesion"]),
        "sigma0": ("tabor", per_tabor["sigma0"]),
        "h0": ("tabor", per_tabor["h0"]),
        "maugis": ("tabor", per_tabor["maugis"]),
    }
    if keep_fields:
        coords["x"] = grid.x
        coords["y"] = grid.y
    ds = xr.Dataset(data, coords=coords)
    ds.attrs.update({
        "study": "smooth rigid ball on a Gaussian rough elastic flat (thesis Paper A sec. 7, Paper D sec. 3.2)",
        "radius": float(radius), "size": float(size), "n": int(n), "dx": grid.dx, "z0": float(z0),
        "E": float(E), "nu": float(nu), "effective_modulus": E_star, "force": float(force),
        "correlation_length": float(correlation_length), "seed": int(seed),
        "target_slope": float(target_slope), "surface_n": surface_n, "domain": domain, "n_steps": int(n_steps),
        "refine": int(refine), "tol": float(tol),
        "operator": "free boundary (zero-padded DC-FFT)",
        "area_ratio_definition": "area with p < 0 (contact nodes with -sigma0 < p < 0 plus the cohesive zone "
                                 "0 < g < h0) divided by the contact area (g = 0), at F0",
        "pull_off_definition": "most negative force of the displacement-controlled unloading curve from F0",
    })
    for name, unit in (("rms", "m"), ("pull_off_force", "N"), ("repulsive_force", "N"), ("adhesive_force", "N"),
                       ("contact_area", "m^2"), ("adhesive_area", "m^2"), ("negative_stress_area", "m^2")):
        ds[name].attrs["units"] = unit
    return ds


def study_table(ds):
    """A flat table (pandas DataFrame) of a :func:`rough_ball_study` result, one row per
    (tabor, rms), with the normalised columns of Paper A Figs. 9 and 11:
    ``pull_off_over_smooth`` (pull-off / pull-off at rms = 0, if present),
    ``pull_off_over_piRdg`` (pull-off / (pi R dgamma), negative)."""
    import pandas as pd

    scalar = [v for v in ds.data_vars if set(ds[v].dims) == {"tabor", "rms"}]
    df = ds[scalar].to_dataframe().reset_index()
    for c in ("rms_over_z0", "rms_slope"):
        df[c] = np.tile(ds[c].values, ds.sizes["tabor"])
    dg = np.repeat(ds["work_of_adhesion"].values, ds.sizes["rms"])
    df["work_of_adhesion"] = dg
    df["pull_off_over_piRdg"] = df["pull_off_force"] / (math.pi * ds.attrs["radius"] * dg)
    if np.any(ds["rms"].values == 0):
        smooth = ds["pull_off_force"].sel(rms=0.0)
        ref = np.repeat(smooth.values, ds.sizes["rms"])
        df["pull_off_over_smooth"] = df["pull_off_force"] / ref
        ref_a = np.repeat(ds["adhesive_force"].sel(rms=0.0).values, ds.sizes["rms"])
        df["adhesive_force_over_smooth"] = df["adhesive_force"] / ref_a
    first = ["tabor", "rms", "rms_over_z0", "rms_slope"]
    return pd.DataFrame(df[first + [c for c in df.columns if c not in first]])


def peak_summary(ds, variable: str = "pull_off_force") -> list[dict]:
    """Where |variable| peaks along rms, per Tabor parameter.

    Returns a list of dicts ``{"tabor", "peak_rms", "peak_rms_over_z0", "peak_value",
    "smooth_value", "last_value", "rise_then_fall"}``; ``rise_then_fall`` is True when the
    magnitude at the peak exceeds both the first (smallest rms) and the last (largest rms)
    values, i.e. the peak is interior.
    """
    rows = []
    for mu in ds["tabor"].values:
        v = np.abs(ds[variable].sel(tabor=mu).values)
        k = int(np.nanargmax(v))
        rows.append({
            "tabor": float(mu),
            "peak_rms": float(ds["rms"].values[k]),
            "peak_rms_over_z0": float(ds["rms_over_z0"].values[k]),
            "peak_value": float(ds[variable].sel(tabor=mu).values[k]),
            "smooth_value": float(ds[variable].sel(tabor=mu).values[0]),
            "last_value": float(ds[variable].sel(tabor=mu).values[-1]),
            "rise_then_fall": bool(0 < k < len(v) - 1 and v[k] > v[0] and v[k] > v[-1]),
        })
    return rows
