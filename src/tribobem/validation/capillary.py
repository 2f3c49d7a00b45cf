"""Validation of capillary adhesion with water films (Papers B, C).

Cases
-----
``sphere_flat_capillary``
    Paper B 4.1: a rigid sphere touching a rigid flat (prescribed approach: the lowest node
    touches; no elastic solve, :func:`~tribobem.solvers.capillary.solve_capillary` with
    ``operator=None``), SiO2 films on both bodies from the shipped isotherm
    (:data:`~tribobem.interactions.isotherms.SIO2`), water at 295 K, no van der Waals terms
    (the thesis' analytic force omits them), R = 1 and 10 um.  The capillary force of the
    island rule against the toroidal meniscus of thesis A.27-A.29, 3 % for RH 0.3-0.7 (the
    model difference, measured 0.1-1.1 %: the island rule drops the neck curvature 1/r2 and the
    cos phi factors).  RH 0.9 (quick and full) and 0.95 (full) are INFORMATIONAL rows
    (tolerance inf): there the island rule's meniscus height 2 |r_k| + e1 + e2 exceeds the
    toroidal meniscus by 2.9 % and 5.0 % (R = 1 um), 0.8 % and 1.3 % (R = 10 um).  Each RH also
    has a row against the island rule's own exact value for the exact sphere,
    pi (2 R S - S^2) dP_cap (1 %): the discretisation alone (0.1-0.3 % at 256^2).  The domain is
    2.4 x the wetted radius at the highest RH, 256^2 (quick) or 512^2 (full): >= 40 cells across
    the meniscus at RH 0.3.
``capillary_force_balance``
    An elastic silica flat (73 GPa, 0.17) under a rigid sphere (R = 1 um), 128^2 free
    boundary, force control F0 = 1 uN, RH 0.5, SiO2 films, Dugdale adhesion (50 mJ/m^2,
    z0 = 0.3 nm) and the water-solid terms: the discrete problem's balance (total force = F0,
    1e-8; contact + capillary + solid-solid + water-solid = total, 1e-10), F_cap = dP_cap x
    wetted area (1e-12) and self-consistency of the islands (islands of the final gap = the
    islands of the final solve: 0 differing nodes).
``capillary_force_balance_normcg``
    The same with NormCG as the normal solver of the island fixed point
    (``[solver] method = "normcg"``): the same balances and tolerances.
``thin_film_levelling``
    The thin-film equation with the disjoining pressure (closed system) on a periodic cosine
    surface h_s = a cos(k x), a = 1e-3 e0 (e0 the SiO2 isotherm thickness at RH 0.5), wavelength
    2 pi times the healing length sqrt(gamma / |Pi'(e0)|), integrated to its steady state: the
    film's first harmonic against the linear theory e1 = -a gamma k^2 / (gamma k^2 + |Pi'(e0)|)
    = -a / 2 (2e-3: the second-order terms in a / e0), and the mean thickness against e0 (the
    volume; 1e-10).
"""

from __future__ import annotations

import math
import warnings
from typing import Callable

import numpy as np

from ..analytic.capillary import sphere_flat_capillary, sphere_flat_island_force
from ..elasticity import free_boundary_operator
from ..errors import ConvergenceWarning
from ..geometry.shapes import sphere
from ..grid import Grid
from ..interactions.dugdale import DugdaleAdhesion
from ..interactions.films import film_thickness
from ..interactions.isotherms import SIO2
from ..interactions.menisci import meniscus_islands
from ..interactions.water import Water
from ..solvers.capillary import solve_capillary
from .common import PAIR, ValidationRow, _row

__all__ = ["CASES", "sphere_flat_rows", "sphere_flat_case"]

#: Relative humidities checked against A.27-A.29 (3 %) and reported only (informational).
RH_CHECKED = {True: (0.3, 0.5, 0.7), False: (0.3, 0.4, 0.5, 0.6, 0.7)}
RH_INFO = {True: (0.9,), False: (0.9, 0.95)}


def sphere_flat_case(radius: float, rh: float, n: int, top_rh: float, water: Water | None = None):
    """One rigid sphere-flat solve against the two references.

    Parameters
    ----------
    radius : float
        Sphere radius R (m).
    rh : float
        Relative humidity of the solve.
    n : int
        Cells per side.
    top_rh : float
        Highest RH of the case: the domain is 2.4 x its wetted radius, so that every RH of a
        case runs on the same grid.
    water : Water, optional
        Water properties; default :class:`~tribobem.interactions.water.Water`.

    Returns
    -------
    tuple of float
        (BEM capillary force, A.27-A.29 force, island-rule force on the exact sphere), N.
    """
    water = Water() if water is None else water
    e = float(SIO2.thickness(rh))
    rk, dp = water.kelvin_radius(rh), water.capillary_pressure(rh)
    # Domain: 2.4 x the wetted radius at the highest RH (island rule, exact sphere).
    e_top = float(SIO2.thickness(top_rh))
    S_top = 2 * abs(water.kelvin_radius(top_rh)) + 2 * e_top
    grid = Grid.square(n, 2.4 * math.sqrt(2 * radius * S_top))
    h = sphere(grid, radius, exact=True)
    res = solve_capillary(None, h, grid=grid, approach=float(h.min()), film1=e, film2=e, kelvin_radius=rk,
                          capillary_pressure=dp, van_der_waals=False)
    ref = sphere_flat_capillary(radius, rk, dp, film_ball=e, film_flat=e).force
    isl = sphere_flat_island_force(radius, rk, dp, film_ball=e, film_flat=e)
    return res.capillary_force, ref, isl


def sphere_flat_rows(quick: bool = True) -> list[ValidationRow]:
    """Rows of ``sphere_flat_capillary`` (module docstring).

    Parameters
    ----------
    quick : bool
        256^2 and three checked RH (else 512^2, five, and RH 0.95 informational).

    Returns
    -------
    list of ValidationRow
    """
    n = 256 if quick else 512
    rows = []
    rhs = RH_CHECKED[quick] + RH_INFO[quick]
    for R in (1e-6, 10e-6):
        case = f"sphere_flat_capillary R={R * 1e6:g}um {n}^2"
        for rh in rhs:
            F, ref, isl = sphere_flat_case(R, rh, n, max(rhs))
            if rh in RH_INFO[quick]:
                rows.append(_row(case, f"F_cap at RH {rh:g} vs A.27-A.29 (informational: island height 2|r_k| "
                                       f"vs the toroidal meniscus)", ref, F, math.inf))
            else:
                rows.append(_row(case, f"F_cap at RH {rh:g} vs A.27-A.29", ref, F, 0.03))
            rows.append(_row(case, f"F_cap at RH {rh:g} vs the island rule on the exact sphere", isl, F, 0.01))
    return rows


def force_balance_rows(quick: bool = True, normal_method: str = "polonsky_keer") -> list[ValidationRow]:
    """Rows of ``capillary_force_balance`` (module docstring); ``normal_method``: the normal
    solver of the island fixed point (``capillary_force_balance_normcg`` runs NormCG)."""
    water = Water()
    rh, F0, R = 0.5, 1e-6, 1e-6
    e = float(SIO2.thickness(rh))
    grid = Grid.square(128, 400e-9)
    op = free_boundary_operator(grid, PAIR)
    h = sphere(grid, R)
    rk, dp = water.kelvin_radius(rh), water.capillary_pressure(rh)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ConvergenceWarning)
        r = solve_capillary(op, h, normal_force=F0, film1=e, film2=e, kelvin_radius=rk, capillary_pressure=dp,
                            adhesion=DugdaleAdhesion(0.05, 0.3e-9), normal_method=normal_method)
    case = "capillary_force_balance 128^2" + (", NormCG" if normal_method == "normcg" else "")
    total = r.total_force if r.converged else math.nan
    parts = r.contact_force + r.capillary_force + r.solid_solid_force + r.water_solid_force
    again = meniscus_islands(r.normal.gap, e, e, rk, r.normal.contact, periodic=False)
    differ = int(np.count_nonzero(again.active != r.islands.active))
    return [
        _row(case, "total force = F0 (capillary, Dugdale and van der Waals included)", F0, total, 1e-8),
        _row(case, "contact + capillary + solid-solid + water-solid = total", r.total_force, parts, 1e-10),
        _row(case, "F_cap = dP_cap x wetted area", dp * r.wetted_area, r.capillary_force, 1e-12),
        _row(case, "islands of the final gap = islands of the final solve (differing nodes)", 0.0, differ, 0.0,
             scale=1.0),
    ]


def thin_film_rows(quick: bool = True) -> list[ValidationRow]:
    """Rows of ``thin_film_levelling`` (module docstring)."""
    water, rh = Water(), 0.5
    e0 = float(SIO2.thickness(rh))
    stiffness = abs(float(SIO2.disjoining_pressure_derivative(e0, water)))
    gamma = water.surface_tension
    k = math.sqrt(stiffness / gamma)  # wavelength 2 pi x the healing length: e1 = -a / 2
    n = 32
    grid = Grid.square(n, 2.0 * math.pi / k, periodic=True)
    x = np.arange(n) * grid.dx
    a = 1e-3 * e0
    hs = np.repeat((a * np.cos(k * x))[:, None], n, axis=1)
    f = film_thickness(hs, grid, SIO2, rh, water, mode="thin_film", disjoining=True)
    e = f.thickness[:, 0]
    e1 = 2.0 * float(np.mean((e - e.mean()) * np.cos(k * x))) if f.converged else math.nan
    e1_ref = -a * gamma * k * k / (gamma * k * k + stiffness)
    case = "thin_film_levelling cos surface, RH 0.5, 32^2"
    return [
        _row(case, "film amplitude e1 vs -a gamma k^2 / (gamma k^2 + |Pi'|) (m)", e1_ref, e1, 2e-3),
        _row(case, "mean film thickness = isotherm thickness (volume, m)", e0, f.mean_thickness, 1e-10),
    ]


CASES: dict[str, Callable[[bool], list[ValidationRow]]] = {
    "sphere_flat_capillary": sphere_flat_rows,
    "capillary_force_balance": force_balance_rows,
    "capillary_force_balance_normcg": lambda quick=True: force_balance_rows(quick, "normcg"),
    "thin_film_levelling": thin_film_rows,
}
