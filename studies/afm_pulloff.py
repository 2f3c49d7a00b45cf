"""AFM colloidal-probe pull-off on measured substrates, spot by spot (thesis Paper C, vacuum).

A smooth SiO2 sphere (R = 2.5 um, E = 64 GPa, nu = 0.17) is pressed on a measured substrate
topography (Si, E = 130 GPa, nu = 0.28) with Dugdale adhesion of work dgamma = 88 mJ/m^2
(Paper C: 2 gamma_SiO2, vacuum state, no water) and unloaded until it separates.  Paper C
measured the substrate at five spots and reports the mean and spread of the predicted
pull-off (Fig. 5); here the "spots" are non-overlapping sub-windows of one measured scan,
each the rough flat under the sphere, whose apex sits over the window's centre
(free-boundary operator: a measured window is not periodic).

Limitations (see :func:`afm_pull_off_spots`): the probe is smooth (Paper C also measured
the probe's roughness, which dominated the combined roughness before its tests); nothing
outside the window exists for the solver; a window is a sample of the scan's roughness at
the scan's resolution.
"""

from __future__ import annotations

import math
import time
import warnings
from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable

import numpy as np

from tribobem.analytic.adhesion import maugis_dugdale_pull_off, maugis_parameter, tabor_parameter
from tribobem.elasticity.operators import free_boundary_operator
from tribobem.errors import ConvergenceWarning, InputError
from tribobem.geometry import read_topography, rms_height, rms_slope, sphere
from tribobem.grid import Grid
from tribobem.interactions.dugdale import DugdaleAdhesion
from tribobem.materials import ContactPair, Material
from tribobem.solvers.normal import solve_normal
from tribobem.solvers.normal_paths import pull_off

__all__ = ["SIO2", "SI", "AFMPullOff", "spot_origins", "afm_pull_off_spots"]

#: Paper C Table 2.
SIO2 = Material(64e9, 0.17, "SiO2")
SI = Material(130e9, 0.28, "Si")


@dataclass
class AFMPullOff:
    """Pull-off of a smooth sphere on several spots of a measured substrate.

    Attributes
    ----------
    table : pandas.DataFrame
        One row per spot: ``spot``, ``ix0``, ``iy0`` (first cell of the window in the scan),
        ``x0``, ``y0`` (its lower-left corner, m, from the scan's lower-left corner),
        ``window`` (side, m), ``n`` (cells per side of the solver grid), ``dx`` (m), ``rms``
        and ``rms_slope`` of the window after its detrending, ``pull_off_force`` (N, negative),
        ``pull_off_approach`` (m), ``pull_off_over_dmt`` (pull-off / (-2 pi R dgamma)),
        ``contact_area`` and ``adhesive_area`` at the preload (m^2), ``edge_contact`` (True
        when contact or cohesive-zone nodes touch the window's border at the preload: the
        window truncates the surface the probe touches), ``converged``, ``time`` (CPU s).
    mean, std : float
        Mean and sample standard deviation (ddof = 1) of the pull-off over the spots (N).
    dmt, jkr, maugis_dugdale : float
        Smooth-sphere pull-off forces (N, negative): -2 pi R dgamma, -1.5 pi R dgamma and the
        Maugis-Dugdale value (force control) at this Maugis parameter.
    smooth : float
        Pull-off of the smooth sphere on a flat, computed on the same window grid (N):
        the discretised reference of the spots.
    info : dict
        Inputs and derived values (E*, Tabor and Maugis parameters, sigma0, h0, file
        statistics, detrending, ...).
    """

    table: "object"
    mean: float
    std: float
    dmt: float
    jkr: float
    maugis_dugdale: float
    smooth: float
    info: dict = field(default_factory=dict)

    def summary(self) -> dict:
        """Scalars for reports: mean, std, min, max, references (N) and the ratios to them."""
        f = np.asarray(self.table["pull_off_force"], dtype=float)
        return {
            "file": Path(self.info.get("path", "")).name,
            "n_spots": int(len(f)),
            "window": float(self.info.get("window", float("nan"))),
            "mean": self.mean, "std": self.std, "min": float(np.min(f)), "max": float(np.max(f)),
            "smooth": self.smooth, "dmt": self.dmt, "jkr": self.jkr, "maugis_dugdale": self.maugis_dugdale,
            "mean_over_smooth": self.mean / self.smooth if self.smooth else float("nan"),
            "mean_rms": float(np.mean(self.table["rms"])),
        }


def spot_origins(n_cells: tuple[int, int], window_cells: tuple[int, int], n_spots: int) -> list[tuple[int, int]]:
    """First cells of ``n_spots`` non-overlapping windows spread over a scan.

    The scan is covered by a k x k lattice of window positions, k = ceil(sqrt(n_spots)),
    evenly spaced from one border to the other (touching when the windows tile the scan);
    ``n_spots`` of the k^2 positions are taken evenly in row-major order (for 5 spots on a
    3 x 3 lattice: the four corners and the centre, like the five on a die).

    Raises
    ------
    InputError
        ``window`` if k windows do not fit side by side in the scan.
    """
    if n_spots < 1:
        raise InputError("n_spots", f"must be >= 1, got {n_spots!r}")
    k = math.ceil(math.sqrt(n_spots))
    starts = []
    for axis, (N, w) in enumerate(zip(n_cells, window_cells)):
        if w < 2 or k * w > N:
            raise InputError(
                "window",
                f"{k} non-overlapping windows of {w} cells do not fit in the {N} cells of the scan along "
                f"{'xy'[axis]}; use a window of at most {N // k} cells ({n_spots} spots need a {k} x {k} lattice)",
            )
        starts.append(np.round(np.linspace(0, N - w, k)).astype(int) if k > 1 else np.array([(N - w) // 2]))
    lattice = [(int(ix), int(iy)) for ix in starts[0] for iy in starts[1]]
    pick = np.round(np.linspace(0, len(lattice) - 1, n_spots)).astype(int) if n_spots > 1 else [len(lattice) // 2]
    return [lattice[i] for i in pick]


def _edge_touch(mask: np.ndarray) -> bool:
    return bool(mask[0, :].any() or mask[-1, :].any() or mask[:, 0].any() or mask[:, -1].any())


def afm_pull_off_spots(
    path,
    n_spots: int = 5,
    window: float | None = None,
    radius: float = 2.5e-6,
    probe: Material = SIO2,
    substrate: Material = SI,
    dgamma: float = 0.088,
    z0: float = 0.3e-9,
    n: int | None = None,
    preload: float = 100e-9,
    channel=None,
    detrend: str = "center",
    window_detrend: str = "height",
    spots: list[tuple[int, int]] | None = None,
    n_steps: int = 30,
    refine: int = 6,
    tol: float = 1e-9,
    max_iterations: int = 10000,
    progress: Callable[[int, int], None] | None = None,
) -> AFMPullOff:
    """Pull-off of a smooth colloidal probe on ``n_spots`` windows of a measured substrate.

    Parameters
    ----------
    path : str or path-like
        Measured topography (any format :func:`~tribobem.geometry.read_topography` reads).
    n_spots : int
        Number of non-overlapping windows ("spots"), placed by :func:`spot_origins`.
    window : float, optional
        Window side (m).  Default: the largest that fits the ``k x k`` lattice,
        ``min(lx, ly) / ceil(sqrt(n_spots))``.
    radius : float
        Probe radius R (m); Paper C: a 5 um diameter SiO2 sphere.
    probe, substrate : Material
        Body 2 (the sphere) and body 1 (the substrate); Paper C Table 2.
    dgamma : float
        Work of adhesion (J/m^2); Paper C: 2 gamma_SiO2 = 88 mJ/m^2 (native oxide on Si).
    z0 : float
        Equilibrium separation (m).  Paper C only gives the range 0.2-0.4 nm; the default
        0.3 nm gives mu_T ~= 0.71 on Si (lambda ~= 0.82).
    n : int, optional
        Cells per side of the solver grid: each window is resampled (bilinear) to ``n x n``.
        Default: the scan's own pixels.  Resample when the scan's pixel is not small against
        the contact radius (~56 nm for the smooth probe at zero load); bilinear interpolation
        adds no roughness below the scan's pixel, so the result is then an upper bound of the
        adhesion of a surface with finer roughness.
    preload : float
        Compressive force (N) from which the probe is unloaded; Paper C: 100 nN set-point.
    channel
        Channel of the file (default: the reader's default height channel).
    detrend : str
        Detrending of the whole scan on reading ("center": remove the mean).
    window_detrend : {"none", "center", "height", "curvature"}
        Detrending of each window.  Default "height" (remove the best plane): a sphere on a
        tilted plane touches it the same way (small slopes), while a scan's tilt (sample
        mounting) would otherwise dominate the window's rms.
    spots : list of (ix0, iy0), optional
        Explicit window origins (cells), instead of :func:`spot_origins`.
    n_steps, refine, tol, max_iterations
        Pull-off path and solver settings (:func:`~tribobem.solvers.normal_paths.pull_off`).
    progress : callable, optional
        ``progress(done, total)`` after each spot (the smooth reference is spot 0).

    Returns
    -------
    AFMPullOff
    """
    import pandas as pd

    topo = read_topography(path, channel=channel, detrend=detrend)
    g0 = topo.grid
    if window is None:
        window = min(g0.lx, g0.ly) / math.ceil(math.sqrt(n_spots))
    if not (isinstance(window, (int, float)) and math.isfinite(window) and window > 0):
        raise InputError("window", f"must be a length > 0 m, got {window!r}")
    wx, wy = int(math.floor(window / g0.dx + 1e-9)), int(math.floor(window / g0.dy + 1e-9))
    if spots is None:
        spots = spot_origins(g0.shape, (wx, wy), n_spots)
    pair = ContactPair(substrate, probe)
    E_star = pair.effective_modulus
    ad = DugdaleAdhesion(dgamma, z0)
    lam = maugis_parameter(radius, dgamma, E_star, z0)

    # Solver grid: the window (resampled to n x n when asked); one operator for every spot.
    lx, ly = wx * g0.dx, wy * g0.dy
    grid = Grid(wx, wy, lx, ly, False) if n is None else Grid(int(n), int(n), lx, ly, False)
    op = free_boundary_operator(grid, pair)
    ball = sphere(grid, radius)

    def solve(gap):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", ConvergenceWarning)
            pre = solve_normal(op, gap, force=preload, interaction=ad, tol=tol, max_iterations=max_iterations)
            po = pull_off(op, gap, ad, preload=preload, n_steps=n_steps, refine=refine, tol=tol,
                          max_iterations=max_iterations)
        return pre, po

    total = len(spots) + 1
    _, po_smooth = solve(ball)
    if progress:
        progress(1, total)

    rows = []
    for k, (ix0, iy0) in enumerate(spots):
        c0 = time.process_time()
        w = topo.window(int(ix0), int(iy0), wx, wy)
        if n is not None:
            w = w.resample(grid)
        h1 = w.detrended(window_detrend).heights if window_detrend not in (None, "none") else w.heights
        gap = ball - h1
        gap = gap - gap.min()
        pre, po = solve(gap)
        rows.append({
            "spot": k + 1, "ix0": int(ix0), "iy0": int(iy0), "x0": ix0 * g0.dx, "y0": iy0 * g0.dy,
            "window": lx, "n": grid.nx, "dx": grid.dx,
            "rms": rms_height(h1), "rms_slope": rms_slope(h1, grid),
            "pull_off_force": po.force, "pull_off_approach": po.approach,
            "pull_off_over_dmt": po.force / (-2.0 * math.pi * radius * dgamma),
            "contact_area": pre.contact_area, "adhesive_area": pre.adhesive_area,
            "edge_contact": _edge_touch(pre.contact | pre.adhesive),
            "converged": bool(pre.converged and np.all(po.curve.converged)),
            "time": time.process_time() - c0,
        })
        if progress:
            progress(k + 2, total)

    table = pd.DataFrame(rows)
    f = table["pull_off_force"].to_numpy(dtype=float)
    stats = topo.stats()
    info = {
        "path": str(path), "window": lx, "n_spots": len(spots), "radius": radius, "dgamma": dgamma, "z0": z0,
        "preload": preload, "effective_modulus": E_star, "tabor": tabor_parameter(radius, dgamma, E_star, z0),
        "maugis": lam, "sigma0": ad.sigma0, "h0": ad.h0, "probe": probe, "substrate": substrate,
        "detrend": detrend, "window_detrend": window_detrend, "scan_grid": g0, "solver_grid": grid,
        "scan_rms": stats["rms_height"], "scan_rms_slope": stats["rms_slope"],
        "scan_rms_plane_removed": rms_height(topo.detrended("height").heights),
        "smooth_pull_off_approach": po_smooth.approach,
    }
    return AFMPullOff(
        table=table,
        mean=float(np.mean(f)),
        std=float(np.std(f, ddof=1)) if len(f) > 1 else 0.0,
        dmt=-2.0 * math.pi * radius * dgamma,
        jkr=-1.5 * math.pi * radius * dgamma,
        maugis_dugdale=float(maugis_dugdale_pull_off(lam, "force")) * math.pi * radius * dgamma,
        smooth=float(po_smooth.force),
        info=info,
    )
