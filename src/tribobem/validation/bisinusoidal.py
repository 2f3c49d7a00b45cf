"""Pull-off force of a bisinusoidal interface with Dugdale adhesion (Paper A section 6).

The computation behind the published 625-case study (the repository's ``studies.bisinusoidal``
adds Paper A's tables and the fit) and the ``bisinusoidal_resolution`` validation case
(:mod:`tribobem.validation.studies`); it lives in the package so that ``tribobem validate``
needs no study, and a sweep names it as
``function = "tribobem.validation.bisinusoidal:pull_off_point"``.

Geometry (Paper A Eqs. 31-34).  The upper, rigid body carries the bisinusoid
``S cos(2 pi x / lx) cos(2 pi y / ly)`` above an elastic flat (E* = E, nu = 0).  Its crests
have the radii of curvature ``Rx = lx^2 / (4 pi^2 S)`` and ``Ry = ly^2 / (4 pi^2 S)``, the
effective radius ``R_c = sqrt(Rx Ry) = lx ly / (4 pi^2 S)`` and the wavelength ratio
``k = ly / lx <= 1``.  Given (R_c, k, S) the cell is therefore

    lx = 2 pi sqrt(R_c S / k),    ly = k lx.

The periodic cell ``lx x ly`` holds two crests: one at the origin and one at the cell
centre ``(lx/2, ly/2)`` (Paper A: "1 in the center and 4 quarters in the corners"), so the
pull-off force per cell is that of two crests; Paper A Table 2 (a = 10.39) is per cell,
``a/2 = 5.20`` per crest lies between JKR (3 pi / 2) and DMT (2 pi).

Gap.  ``h = S - S cos(2 pi x / lx) cos(2 pi y / ly)`` on the nodes ``x_i = i dx``,
``y_j = j dy`` (both crests fall on nodes for even nx, ny), min h = 0 at the crests.

Pull-off.  Displacement control throughout (Paper A: "the force-approach curve ... the
largest negative force on the curve"): load from a zero approach (jump-in at the crests,
starting from zero pressure so the contact forms at the crests only) to a small positive
approach, unload in steps until the surfaces separate, then refine the minimum force by
golden-section search between the neighbours of the most negative step, each solve
warm-started from the previous one.  Force control is not used for the start: from a
uniform initial pressure a periodic cell may settle in full contact, where the mean
pressure is undetermined (the periodic kernel has no zero-frequency term).

Units: SI throughout (J/m^2, m, Pa, N).
"""

from __future__ import annotations

import math
import warnings

import numpy as np

from ..elasticity.operators import periodic_operator
from ..errors import ConvergenceWarning, InputError
from ..grid import Grid
from ..interactions.dugdale import DugdaleAdhesion
from ..materials import ContactPair, Material
from ..solvers.normal import solve_normal

__all__ = [
    "PAPER_A_S",
    "DEFAULT_Z0",
    "DEFAULT_N",
    "bisinusoidal_cell",
    "bisinusoidal_gap",
    "bisinusoidal_pull_off",
    "pull_off_point",
]

#: Amplitude of the bisinusoid in Paper A section 6 (m).
PAPER_A_S = 5e-9
#: z0 used for the study (Paper A does not give it): 0.3 nm puts the 625 cases at Maugis
#: lambda 0.71-2.80 (Tabor 0.61-2.42), inside the Maugis-Dugdale range (0.1 < lambda < 5).
DEFAULT_Z0 = 0.3e-9
#: Cells per side of the periodic cell (nx = ny = n, so dx / dy = 1 / k, like the contact
#: ellipse); chosen by the resolution check documented in the README / report.
DEFAULT_N = 128


def bisinusoidal_cell(R_c: float, k: float, S: float = PAPER_A_S) -> tuple[float, float]:
    """Cell sides ``(lx, ly)`` (m) of the bisinusoid with crest radius ``R_c`` and ratio ``k``.

    ``R_c = lx ly / (4 pi^2 S)`` and ``k = ly / lx`` give ``lx = 2 pi sqrt(R_c S / k)``.

    Parameters
    ----------
    R_c : float
        Effective crest radius sqrt(Rx Ry) (m).
    k : float
        Wavelength ratio ly / lx in (0, 1].
    S : float
        Amplitude (m).

    Returns
    -------
    lx, ly : float
        Cell sides (m).

    Raises
    ------
    InputError
        A non-positive ``R_c`` or ``S``, or ``k`` outside (0, 1].
    """
    for name, v in (("R_c", R_c), ("S", S)):
        if not (math.isfinite(v) and v > 0):
            raise InputError(name, f"must be a finite value > 0 m, got {v!r}")
    if not (math.isfinite(k) and 0 < k <= 1):
        raise InputError("k", f"wavelength ratio ly/lx must lie in (0, 1], got {k!r}")
    lx = 2.0 * math.pi * math.sqrt(R_c * S / k)
    return lx, k * lx


def bisinusoidal_gap(grid: Grid, S: float) -> np.ndarray:
    """Initial gap ``S - S cos(2 pi x / lx) cos(2 pi y / ly)`` on the nodes ``x_i = i dx``.

    The crests (gap 0) sit on the nodes (0, 0) and (nx/2, ny/2) (even nx, ny), so the
    contact starts on a node and the pull-off does not depend on a sub-cell offset.

    Parameters
    ----------
    grid : Grid
        The periodic cell (lx, ly are the wavelengths).
    S : float
        Amplitude (m).

    Returns
    -------
    ndarray
        Gap (m), shape ``grid.shape``, in [0, 2 S].
    """
    x = np.arange(grid.nx) * grid.dx
    y = np.arange(grid.ny) * grid.dy
    return S - S * np.outer(np.cos(2.0 * np.pi * x / grid.lx), np.cos(2.0 * np.pi * y / grid.ly))


def _solve(op, h, d, adh, tol, max_iterations, prev):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ConvergenceWarning)
        return solve_normal(op, h, approach=float(d), interaction=adh, tol=tol,
                            max_iterations=max_iterations, initial_pressure=prev)


def _crest_widths(res, mask) -> tuple[int, int]:
    """Cells of ``mask`` along x through the crest row and along y through the crest column."""
    m = np.asarray(mask, dtype=bool)
    return int(m[:, 0].sum()), int(m[0, :].sum())


def bisinusoidal_pull_off(
    dgamma: float,
    R_c: float,
    E_star: float,
    k: float,
    S: float = PAPER_A_S,
    z0: float = DEFAULT_Z0,
    n: int = DEFAULT_N,
    *,
    nx: int | None = None,
    ny: int | None = None,
    kernel: str = "spectral",
    n_steps: int = 40,
    refine: int = 10,
    tol: float = 1e-9,
    max_iterations: int = 20000,
    details: bool = False,
):
    """Pull-off force (N, magnitude > 0) of one periodic cell of a bisinusoidal interface.

    Parameters
    ----------
    dgamma : float
        Work of adhesion (J/m^2).
    R_c : float
        Effective crest radius sqrt(Rx Ry) (m).
    E_star : float
        Effective modulus (Pa) (elastic flat, nu = 0, against a rigid bisinusoid).
    k : float
        Wavelength ratio ly / lx in (0, 1].
    S : float
        Amplitude (m); 5 nm in Paper A.
    z0 : float
        Dugdale equilibrium distance (m): sigma0 = 16 dgamma / (9 sqrt3 z0), h0 = 0.974 z0.
    n : int
        Cells per side (nx = ny = n) unless ``nx`` / ``ny`` are given; even.
    nx, ny : int, optional
        Cells along x and y (even), instead of ``n``.
    kernel : {"spectral", "influence"}
        Periodic kernel (see :func:`tribobem.elasticity.operators.periodic_operator`).
    n_steps : int
        Unloading steps between the loaded state and the separation.
    refine : int
        Golden-section refinements of the minimum force.
    tol, max_iterations
        Solver settings of each point.
    details : bool
        Return a dict (force, approach, curve, contact widths in cells at pull-off, ...)
        instead of the force.

    Returns
    -------
    float or dict
        |F_pull-off| in N (per cell, i.e. two crests).
    """
    nx = int(nx or n)
    ny = int(ny or n)
    if nx % 2 or ny % 2:
        raise InputError("n", f"cells per side must be even (crests on nodes), got {nx} x {ny}")
    for name, v in (("dgamma", dgamma), ("E_star", E_star), ("z0", z0)):
        if not (math.isfinite(v) and v > 0):
            raise InputError(name, f"must be a finite value > 0, got {v!r}")
    lx, ly = bisinusoidal_cell(R_c, k, S)
    grid = Grid(nx, ny, lx, ly, periodic=True)
    h = bisinusoidal_gap(grid, S)
    op = periodic_operator(grid, ContactPair(Material(E_star, 0.0, "flat"), Material.rigid("bisinusoid")),
                           kernel=kernel)
    adh = DugdaleAdhesion(dgamma, z0)
    h0 = adh.h0
    # JKR approach scale of one crest; the load-controlled pull-off of JKR is at -0.36 d_jkr,
    # the separation under displacement control at -0.75 d_jkr (DMT: about -h0).
    d_jkr = (math.pi**2 * dgamma**2 * R_c / E_star**2) ** (1.0 / 3.0)
    d_top = 0.5 * d_jkr + 2.0 * h0
    d_bottom = -(1.5 * d_jkr + 4.0 * h0)

    n_solves, iters = 0, 0
    prev = None
    for d in np.linspace(0.0, d_top, 4):  # loading: jump-in at the crests, then press
        prev = _solve(op, h, d, adh, tol, max_iterations, prev)
        n_solves += 1
        iters += prev.iterations
    rows = []
    states = []
    for d in np.linspace(d_top, d_bottom, n_steps + 1)[1:]:
        res = _solve(op, h, d, adh, tol, max_iterations, prev)
        n_solves += 1
        iters += res.iterations
        rows.append((float(d), res.force, res.converged, res.contact_area, res.adhesive_area))
        states.append(res)
        prev = res
        if res.contact_area == 0 and res.adhesive_area == 0:
            break
    forces = np.array([r[1] if r[2] else np.inf for r in rows])
    i = int(np.argmin(forces))
    best = states[i]
    if i == len(rows) - 1 and not (rows[i][3] == 0 and rows[i][4] == 0):
        warnings.warn("bisinusoidal_pull_off: the force was still falling at the last step; "
                      "the unloading range is too short", ConvergenceWarning, stacklevel=2)
    if refine > 0 and 0 < i < len(rows) - 1:
        warm = states[i - 1]
        a, b = rows[i + 1][0], rows[i - 1][0]
        gr = (math.sqrt(5.0) - 1.0) / 2.0
        cache: dict[float, object] = {}

        def f(d):
            nonlocal n_solves, iters
            if d not in cache:
                cache[d] = _solve(op, h, d, adh, tol, max_iterations, warm)
                n_solves += 1
                iters += cache[d].iterations
            r = cache[d]
            return r.force if r.converged else np.inf

        c, e = b - gr * (b - a), a + gr * (b - a)
        for _ in range(refine):
            if f(c) < f(e):
                b = e
            else:
                a = c
            c, e = b - gr * (b - a), a + gr * (b - a)
        cand = min(cache.values(), key=lambda r: r.force if r.converged else np.inf)
        if cand.converged and cand.force < best.force:
            best = cand
    force = float(best.force)
    if not details:
        return -min(force, 0.0)
    cx, cy = _crest_widths(best, best.contact)
    zx, zy = _crest_widths(best, best.contact | best.adhesive)
    converged = bool(best.converged and all(r[2] for r in rows))
    return {
        "pull_off_force": min(force, 0.0),
        "pull_off_approach": float(best.approach),
        "lx": lx,
        "ly": ly,
        "dx": grid.dx,
        "dy": grid.dy,
        "nx": nx,
        "ny": ny,
        "contact_area": float(best.contact_area),
        "adhesive_area": float(best.adhesive_area),
        # cells across the contact (g = 0) and across contact + cohesive zone, through
        # the crest at the origin, along x and y (both crests together: halve for one)
        "contact_cells_x": cx,
        "contact_cells_y": cy,
        "zone_cells_x": zx,
        "zone_cells_y": zy,
        "tabor": adh.tabor_parameter(R_c, E_star),
        "maugis": adh.maugis_parameter(R_c, E_star),
        "sigma0": adh.sigma0,
        "h0": h0,
        "n_solves": n_solves,
        "iterations": iters,
        "converged": converged,
        "curve": rows,
    }


def pull_off_point(dgamma, R_c, E_star, k, S=PAPER_A_S, z0=DEFAULT_Z0, n=DEFAULT_N, nx=None, ny=None,
                   kernel="spectral", n_steps=40, refine=10, tol=1e-9, max_iterations=20000) -> dict:
    """One sweep point (``function = "tribobem.validation.bisinusoidal:pull_off_point"``).

    A sweep point must return plain scalars, hence a dict without the curve.

    Parameters
    ----------
    dgamma, R_c, E_star, k, S, z0, n, nx, ny, kernel, n_steps, refine, tol, max_iterations
        As for :func:`bisinusoidal_pull_off` (J/m^2, m, Pa, -, m, m, cells, ...).

    Returns
    -------
    dict
        The scalars of :func:`bisinusoidal_pull_off` (``details=True``) without the curve,
        with ``pull_off_force`` negative (SPEC sign: tensile < 0, N) and
        ``normalised_pull_off = |F| / (R_c dgamma)`` (dimensionless).
    """
    out = bisinusoidal_pull_off(dgamma, R_c, E_star, k, S=S, z0=z0, n=int(n), nx=nx, ny=ny, kernel=kernel,
                                n_steps=int(n_steps), refine=int(refine), tol=tol,
                                max_iterations=int(max_iterations), details=True)
    out.pop("curve")
    out["normalised_pull_off"] = -out["pull_off_force"] / (R_c * dgamma)
    return out
