"""Validation of the tangential (partial-slip) solvers (Paper D).

Cases
-----
``cattaneo_mindlin``
    Two identical steel bodies (no normal-tangential coupling), sphere R = 10 mm, P = 10 N,
    mu = 0.3, free boundary over +-1.5a: the stick radius sqrt(A_stick/pi) against
    c/a = (1 - Q/(mu P))^(1/3) and the rigid shift against
    delta = (3 mu P k/(16 a)) [1 - (1 - Q/(mu P))^(2/3)], k = sum (2 - nu_i)/G_i, 3%.
    Quick: Q/(mu P) = 0.2, 0.5, 0.9 on 96^2 (32 cells across a); full: 0.2 to 0.9 on 192^2.
``cattaneo_periodic``
    The same contact in a periodic cell (a = L/6): the periodic reference shift is NOT the
    half-space one, so the Cattaneo-Mindlin traction is applied to the same periodic operator
    and its displacement averaged over the analytic stick zone is the reference, 3%.
``mindlin_stiffness``
    Initial tangential stiffness Q/delta at Q = 0.02 mu P against Mindlin's 8a/k, 3%.
``coupling_sign``
    Rigid ball (R = 10 um) on an elastic flat (E = 130 GPa, nu = 0.3), F0 = 10 uN, mu = 0.2
    (Paper D 3.1), 64^2 over +-2a: the coupling leaves a slip annulus at F_x = 0 (stick ratio
    below 0.5), the shear on the elastic body points outward there (physics: the rigid ball
    restrains the inward surface motion of a compressible body, independent of the thesis),
    and at F_x = 0.5 mu F0+ the stick zone is dragged to -x; with the bodies swapped (rigid flat,
    elastic ball: the coupling changes sign) the stick zone moves to +x.  Rows compare signs
    (reference +-1, computed the sign found).
``spence``
    Normal loading with friction of a rigid sphere on a compressible half-space (incremental
    slip, geometric load steps from 0.01 P to P; 96 on 48^2 quick, 192 on 64^2 full): the stick
    radius ratio c/a at the final load against the self-similar solution of the Spence problem
    (:func:`tribobem.analytic.spence_stick_ratio`), 3%, for beta/mu = 1 and 1.5 (and 2, full).
    The analytic relation neglects the shear's effect on the pressure (Goodman), so the BEM runs
    with ``shear_on_pressure=False`` here; with the full coupling c/a comes out about 5% lower
    (0.658 against 0.696 at beta/mu = 1.5), as an independent coupled ring-element calculation
    also finds (-4.8% at beta = 0.286, mu = 0.2; :mod:`tribobem.analytic.mindlin`).  The discrete
    result converges slowly in the load step (0.628, 0.647, 0.658 for 24, 48, 96 coupled steps).
"""

from __future__ import annotations

import math
import warnings

import numpy as np

from ..analytic import spence_stick_ratio
from ..analytic.hertz import hertz
from ..analytic.mindlin import (
    cattaneo_mindlin_displacement,
    cattaneo_mindlin_traction,
    cattaneo_stick_ratio,
    mindlin_compliance_k,
    mindlin_initial_stiffness,
)
from ..elasticity.operators import free_boundary_operator, make_operator
from ..elasticity.tangential import tangential_operator
from ..errors import ConvergenceWarning
from ..grid import Grid
from ..materials import ContactPair, Material
from ..solvers.coupling import solve_coupled
from ..solvers.normal import solve_normal
from ..solvers.normal_paths import normal_path
from ..solvers.tangential import solve_tangential
from .common import _row

__all__ = ["CASES", "cattaneo_problem"]

STEEL = Material(210e9, 0.3, "steel")


def _quiet(fn, *a, **kw):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ConvergenceWarning)
        return fn(*a, **kw)


def _mindlin_k(pair: ContactPair) -> float:
    """k = sum (2 - nu_i) / G_i of the pair (rigid bodies contribute 0)."""
    return mindlin_compliance_k(pair.body1.E, pair.body1.nu, pair.body2.E, pair.body2.nu)


def cattaneo_problem(n: int, periodic: bool = False, radius: float = 10e-3, force: float = 10.0):
    """Grid, gap, operator and Hertz radius of the identical-steel sphere (free or periodic).

    Parameters
    ----------
    n : int
        Cells per side.
    periodic : bool
        Periodic cell of side 6 a (else a free-boundary domain of side 3 a).
    radius : float
        Sphere radius (m).
    force : float
        Normal force (N); sets the Hertz contact radius a and so the domain.

    Returns
    -------
    grid : Grid
    gap : ndarray
        Paraboloid gap r^2/(2R) (m).
    op : operator
        Three-component (x, y, z) operator of the steel-steel pair.
    pair : ContactPair
    a : float
        Hertz contact radius (m).
    """
    pair = ContactPair(STEEL, STEEL)
    a = float(hertz(force=force, radius=radius, E_star=pair.effective_modulus).contact_radius)
    size = 6.0 * a if periodic else 3.0 * a
    grid = Grid.square(n, size, periodic)
    X, Y = grid.meshgrid()
    gap = (X**2 + Y**2) / (2.0 * radius)
    op = make_operator(grid, pair, ("x", "y", "z"))
    return grid, gap, op, pair, a


def _cattaneo_rows(quick: bool) -> list:


    n = 96 if quick else 192
    ratios = (0.2, 0.5, 0.9) if quick else (0.2, 0.3, 0.5, 0.7, 0.8, 0.9)
    P, mu = 10.0, 0.3
    grid, gap, op, pair, a = cattaneo_problem(n)
    nr = _quiet(solve_normal, op, gap, force=P, tol=1e-12)
    k = _mindlin_k(pair)
    rows = []
    prev = None
    for r in ratios:
        tr = _quiet(solve_tangential, op, nr.pressure, nr.contact, friction_coefficient=mu, force=(r * mu * P, 0.0),
                    initial_shear=prev, tol=1e-9)
        prev = tr.shear
        c_ref = a * float(cattaneo_stick_ratio(r * mu * P, P=P, mu=mu))
        d_ref = float(cattaneo_mindlin_displacement(r * mu * P, P=P, a=a, mu=mu, k=k))
        case = f"cattaneo_mindlin {n}^2"
        rows.append(_row(case, f"stick radius c at Q/(mu P)={r:g}", c_ref, math.sqrt(tr.stick_area / math.pi), 0.03))
        rows.append(_row(case, f"rigid shift delta at Q/(mu P)={r:g}", d_ref, tr.displacement_x, 0.03))
    return rows


def _cattaneo_periodic_rows(quick: bool) -> list:

    n = 192 if quick else 384
    P, mu, r = 10.0, 0.3, 0.5
    grid, gap, op, pair, a = cattaneo_problem(n, periodic=True)
    nr = _quiet(solve_normal, op, gap, force=P, tol=1e-12)
    tr = _quiet(solve_tangential, op, nr.pressure, nr.contact, friction_coefficient=mu, force=(r * mu * P, 0.0), tol=1e-9)
    # Reference: the Cattaneo-Mindlin traction on the same periodic operator.

    c = a * float(cattaneo_stick_ratio(r * mu * P, P=P, mu=mu))
    R2 = grid.radius() ** 2
    qx = np.asarray(cattaneo_mindlin_traction(np.sqrt(R2), r * mu * P, P=P, a=a, mu=mu), dtype=float)
    top = tangential_operator(op)
    ux, _ = top.shear_displacement(qx, np.zeros_like(qx))
    core = R2 < (0.8 * c) ** 2
    d_ref = float(np.asarray(ux)[core].mean())
    case = f"cattaneo_periodic {n}^2"
    return [
        _row(case, "rigid shift vs analytic traction on the periodic operator", d_ref, tr.displacement_x, 0.03),
        _row(case, "stick radius c at Q/(mu P)=0.5", c, math.sqrt(tr.stick_area / math.pi), 0.03),
    ]


def _stiffness_rows(quick: bool) -> list:

    n = 96 if quick else 192
    P, mu, r = 10.0, 0.3, 0.02
    grid, gap, op, pair, a = cattaneo_problem(n)
    nr = _quiet(solve_normal, op, gap, force=P, tol=1e-12)
    tr = _quiet(solve_tangential, op, nr.pressure, nr.contact, friction_coefficient=mu, force=(r * mu * P, 0.0), tol=1e-10)

    K_ref = mindlin_initial_stiffness(a, _mindlin_k(pair))
    return [_row(f"mindlin_stiffness {n}^2", "initial stiffness Q/delta (N/m) vs 8a/k", K_ref,
                 tr.force_x / tr.displacement_x, 0.03)]


def paper_d_problem(n: int, swap: bool = False):
    """Rigid ball (R = 10 um) and elastic flat (130 GPa, 0.3), F0 = 10 uN, +-2a (Paper D 3.1)."""
    elastic, rigid = Material(130e9, 0.3, "flat"), Material.rigid("ball")
    pair = ContactPair(rigid, elastic) if swap else ContactPair(elastic, rigid)
    R, P = 10e-6, 10e-6
    a = float(hertz(force=P, radius=R, E_star=pair.effective_modulus).contact_radius)
    grid = Grid.square(n, 4.0 * a)
    X, Y = grid.meshgrid()
    gap = (X**2 + Y**2) / (2.0 * R)
    return grid, gap, free_boundary_operator(grid, pair, ("x", "y", "z")), pair, a, P


def _sign(v: float) -> float:
    return float(np.sign(v)) if math.isfinite(v) else float("nan")


def _coupling_sign_rows(quick: bool) -> list:

    rows = []
    mu = 0.2
    for swap in (False, True):
        grid, gap, op, pair, a, P = paper_d_problem(64, swap)
        X, Y = grid.meshgrid()
        z = _quiet(solve_coupled, op, gap, friction_coefficient=mu, normal_force=P, tangential_force=(0.0, 0.0))
        t = z.tangential
        label = "rigid flat, elastic ball" if swap else "elastic flat, rigid ball"
        case = f"coupling_sign ({label})"
        if not swap:
            rows.append(_row(case, f"slip annulus at F_x=0 (1: stick ratio {t.stick_ratio:.3f} < 0.5)", 1.0,
                             1.0 if t.stick_ratio < 0.5 else 0.0, 0.0, scale=1.0))
            slip = t.contact & ~t.stick
            rr = np.hypot(X, Y)
            radial = (t.shear[0] * X + t.shear[1] * Y) / np.where(rr > 0, rr, 1.0)
            # Shear on the ELASTIC body: body 1 carries q (elastic flat here).
            rows.append(_row(case, "sign of the radial shear on the elastic body in the annulus (+1: outward)",
                             1.0, _sign(float(radial[slip].mean())), 0.0, scale=1.0))
        zx = _quiet(solve_coupled, op, gap, friction_coefficient=mu, normal_force=P,
                    tangential_force=(0.5 * mu * z.normal.repulsive_force, 0.0), initial=z)
        st = zx.tangential.stick
        xc = float(X[st].mean()) / a if st.any() else float("nan")
        rows.append(_row(case, "sign of the stick-zone centroid x at F_x = 0.5 mu F0+",
                         1.0 if swap else -1.0, _sign(xc), 0.0, scale=1.0))
    return rows


def spence_problem(beta_over_mu: float, n: int):
    """Rigid sphere on an elastic half-space whose nu gives the wanted beta/mu at mu = 0.2."""
    mu = 0.2
    beta = beta_over_mu * mu
    # Rigid body 2 on elastic body 1: beta = (1 - 2 nu) / (2 (1 - nu)); solve for nu.
    nu = (1.0 - 2.0 * beta) / (2.0 - 2.0 * beta)

    pair = ContactPair(Material(100e9, nu, "half-space"), Material.rigid("sphere"))
    R, P = 10e-6, 10e-6
    a = float(hertz(force=P, radius=R, E_star=pair.effective_modulus).contact_radius)
    grid = Grid.square(n, 2.6 * a)
    X, Y = grid.meshgrid()
    gap = (X**2 + Y**2) / (2.0 * R)
    return grid, gap, free_boundary_operator(grid, pair, ("x", "y", "z")), pair, a, P, mu


def spence_stick_ratio_bem(beta_over_mu: float, n: int, steps: int = 24, goodman: bool = True,
                           start: float = 1e-3) -> tuple[float, float]:
    """(c/a from the BEM, the pair's beta/mu) at the end of an incremental normal-load path of
    ``steps`` geometric steps from ``start`` x P to P; ``goodman``: the shear does not act on the
    pressure (the assumption of the analytic solution)."""
    grid, gap, op, pair, a, P, mu = spence_problem(beta_over_mu, n)
    loads = list(np.geomspace(P * start, P, steps))
    path = _quiet(normal_path, op, gap, normal_forces=loads, friction_coefficient=mu, slip="incremental",
                  shear_on_pressure=not goodman)
    last = path[-1]
    c = math.sqrt(last.tangential.stick_area / math.pi)
    a_num = math.sqrt(last.tangential.contact_area / math.pi)
    return c / a_num, pair.dundurs_beta / mu


def _spence_rows(quick: bool) -> list:

    rows = []
    n, steps = (48, 96) if quick else (64, 192)
    for bm in ((1.0, 1.5) if quick else (1.0, 1.5, 2.0)):
        ratio, bm_true = spence_stick_ratio_bem(bm, n, steps, goodman=True, start=1e-2)
        rows.append(_row(f"spence {n}^2, {steps} load steps (Goodman)", f"stick radius ratio c/a at beta/mu={bm_true:.3g}",
                         float(spence_stick_ratio(bm_true)), ratio, 0.03))
    return rows


#: name -> rows(quick)
CASES = {
    "cattaneo_mindlin": _cattaneo_rows,
    "cattaneo_periodic": _cattaneo_periodic_rows,
    "mindlin_stiffness": _stiffness_rows,
    "coupling_sign": _coupling_sign_rows,
    "spence": _spence_rows,
}
