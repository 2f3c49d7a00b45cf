"""Validation cases of the normal (non-adhesive) contact and the force balance.

Cases (:data:`CASES`)
---------------------
``hertz``
    Rigid sphere on an elastic flat, free-boundary (DC-FFT) operator, domain +-2a (Paper A 5.1).
    Contact radius, p0, approach.  Quick: 128^2 (64 cells across the contact), 3%; full:
    512^2, 1%.
``westergaard``
    1D sinusoid on an nx x 8 periodic grid: contact fraction and maximum pressure, 1%.  Quick:
    spectral kernel at pbar = 0.3 p*; full: both periodic kernels at 0.1, 0.3, 0.7 p*.
``bisinusoidal_small_load``
    h = S cos cos at pbar = 1e-3 p*: crest p0 (Hertz asymptote), 1%; contact fraction (light-load
    JGH asymptote), 3% at 512^2 (quick) and 2% at 1024^2 (full).  The area tolerance is looser
    than 1% because the staircase contact area of a crest spot of 18 (36) cells radius
    overestimates the area by ~2% (~1.5%); the asymptote itself is accurate to < 0.5% at this
    load (see tests/solvers/test_normal.py).
``bisinusoidal_near_full``
    pbar = 0.95 p*: contact fraction 1% and non-contact fraction 3% of the JGH lake asymptote.
``force_balance``
    Force control: total force = F0 to 1e-8 without and with Dugdale adhesion (the cohesive zone
    outside the contact included), and F0+ + F0- = F.
``periodic_vs_free``
    A Hertz contact of radius L/8 in a periodic cell vs the free-boundary solution on the same
    grid: contact area and p0, 1%.
"""

from __future__ import annotations

from typing import Callable

import numpy as np

from ..analytic import bisinusoidal_asymptotes, hertz, westergaard
from ..elasticity import free_boundary_operator, periodic_operator
from ..geometry.shapes import bisinusoidal, sphere
from ..grid import Grid
from .adhesion import maugis_dugdale_problem
from .common import PAIR, ValidationRow, _row, _solve

__all__ = ["CASES"]

_HERTZ_R = 1e-3
_HERTZ_A = 1e-6


def _hertz_rows(quick: bool) -> list[ValidationRow]:
    n, tol = (128, 0.03) if quick else (512, 0.01)
    E = PAIR.effective_modulus
    F = 4 * E * _HERTZ_A**3 / (3 * _HERTZ_R)
    grid = Grid.square(n, 4 * _HERTZ_A)
    res = _solve(free_boundary_operator(grid, PAIR), sphere(grid, _HERTZ_R), force=F, tol=1e-10)
    ref = hertz(force=F, radius=_HERTZ_R, E_star=E)
    case = f"hertz {n}^2"
    return [
        _row(case, "contact radius", ref.contact_radius, res.contact_radius(), tol),
        _row(case, "max pressure p0", ref.max_pressure, res.max_pressure, tol),
        _row(case, "approach", ref.approach, res.approach, tol),
    ]


def _westergaard_rows(quick: bool) -> list[ValidationRow]:
    L, A, nx = 2e-6, 10e-9, 1024
    E = PAIR.effective_modulus
    grid = Grid(nx, 8, L, 8 * L / nx, periodic=True)
    h = A * (1 - np.cos(2 * np.pi * grid.x / L))[:, None] * np.ones(grid.ny)
    p_star = np.pi * E * A / L
    rows = []
    kernels = ("spectral",) if quick else ("spectral", "influence")
    ratios = (0.3,) if quick else (0.1, 0.3, 0.7)
    for kernel in kernels:
        op = periodic_operator(grid, PAIR, kernel=kernel)
        for ratio in ratios:
            ref = westergaard(ratio * p_star, A, L, E)
            res = _solve(op, h, force=ratio * p_star * grid.area, tol=1e-10)
            case = f"westergaard {kernel} {nx}x8"
            rows.append(_row(case, f"contact fraction at {ratio:g} p*", ref.contact_fraction, res.contact_fraction, 0.01))
            rows.append(_row(case, f"max pressure at {ratio:g} p*", ref.max_pressure, res.max_pressure, 0.01))
    return rows


_BISIN_L, _BISIN_S = 1e-6, 5e-9


def _bisinusoidal_problem(n):
    grid = Grid.square(n, _BISIN_L, periodic=True)
    h = -bisinusoidal(grid, _BISIN_S, _BISIN_L, _BISIN_L)
    return grid, periodic_operator(grid, PAIR), h - h.min()


def _bisinusoidal_small_rows(quick: bool) -> list[ValidationRow]:
    n, tol_area = (512, 0.03) if quick else (1024, 0.02)
    E = PAIR.effective_modulus
    grid, op, h = _bisinusoidal_problem(n)
    p_star = bisinusoidal_asymptotes(0.0, _BISIN_S, _BISIN_L, E).p_star
    asym = bisinusoidal_asymptotes(1e-3 * p_star, _BISIN_S, _BISIN_L, E)
    F = asym.mean_pressure * grid.area
    res = _solve(op, h, force=F, tol=1e-10)
    crest = hertz(force=F / 2, radius=asym.crest_radius, E_star=E)
    case = f"bisinusoidal {n}^2, pbar = 1e-3 p*"
    return [
        _row(case, "crest max pressure (Hertz)", crest.max_pressure, res.max_pressure, 0.01),
        _row(case, "contact fraction (light-load JGH)", asym.contact_fraction_light, res.contact_fraction, tol_area),
    ]


def _bisinusoidal_full_rows(quick: bool) -> list[ValidationRow]:
    n = 256
    E = PAIR.effective_modulus
    grid, op, h = _bisinusoidal_problem(n)
    p_star = bisinusoidal_asymptotes(0.0, _BISIN_S, _BISIN_L, E).p_star
    asym = bisinusoidal_asymptotes(0.95 * p_star, _BISIN_S, _BISIN_L, E)
    res = _solve(op, h, force=asym.mean_pressure * grid.area, tol=1e-10)
    case = f"bisinusoidal {n}^2, pbar = 0.95 p*"
    return [
        _row(case, "contact fraction (JGH lakes)", asym.contact_fraction_full, res.contact_fraction, 0.01),
        _row(case, "non-contact fraction (JGH lakes)", 1 - asym.contact_fraction_full, 1 - res.contact_fraction, 0.03),
    ]


def _periodic_vs_free_rows(quick: bool) -> list[ValidationRow]:
    n, L = 256, 8 * _HERTZ_A
    E = PAIR.effective_modulus
    F = 4 * E * _HERTZ_A**3 / (3 * _HERTZ_R)
    gf, gp = Grid.square(n, L), Grid.square(n, L, periodic=True)
    h = sphere(gf, _HERTZ_R)
    free = _solve(free_boundary_operator(gf, PAIR), h, force=F, tol=1e-10)
    rows = []
    for kernel in (("spectral",) if quick else ("spectral", "influence")):
        per = _solve(periodic_operator(gp, PAIR, kernel=kernel), h, force=F, tol=1e-10)
        case = f"periodic ({kernel}) vs free {n}^2, a = L/8"
        rows.append(_row(case, "contact area", free.contact_area, per.contact_area, 0.01))
        rows.append(_row(case, "max pressure", free.max_pressure, per.max_pressure, 0.01))
    return rows


def _force_balance_rows(quick: bool) -> list[ValidationRow]:
    rows = []
    E = PAIR.effective_modulus
    F = 4 * E * _HERTZ_A**3 / (3 * _HERTZ_R)
    grid = Grid.square(64, 4 * _HERTZ_A)
    res = _solve(free_boundary_operator(grid, PAIR), sphere(grid, _HERTZ_R), force=F, tol=1e-10)
    rows.append(_row("force balance, no adhesion", "total force = F0", F, res.force, 1e-8))
    prob = maugis_dugdale_problem(1.0, n=64)
    F0 = 0.5 * prob.F_scale
    res = _solve(prob.operator, prob.gap, force=F0, interaction=prob.adhesion, tol=1e-10)
    case = "force balance, Dugdale lambda=1"
    rows.append(_row(case, "total force = F0 (cohesive zone included)", F0, res.force, 1e-8))
    rows.append(_row(case, "F0+ + F0- = F", res.force, res.repulsive_force + res.adhesive_force, 1e-10))
    n_adh = int(np.count_nonzero(res.adhesive))
    rows.append(_row(case, "cohesive-zone force = -sigma0 A_adh",
                     -prob.adhesion.sigma0 * n_adh * prob.grid.cell_area,
                     float(res.pressure[res.adhesive].sum()) * prob.grid.cell_area, 1e-12))
    return rows


#: The cases of this module, in the order they run: name -> ``rows(quick)``.
CASES: dict[str, Callable[[bool], list[ValidationRow]]] = {
    "hertz": _hertz_rows,
    "westergaard": _westergaard_rows,
    "bisinusoidal_small_load": _bisinusoidal_small_rows,
    "bisinusoidal_near_full": _bisinusoidal_full_rows,
    "force_balance": _force_balance_rows,
    "periodic_vs_free": _periodic_vs_free_rows,
}
