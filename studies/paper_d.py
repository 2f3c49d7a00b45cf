"""Paper D Table 1: gross-slip onset of a smooth adhesive ball on an elastic flat (thesis Paper D
section 3.1).

A rigid ball (R = 10 um) is pressed with F0 = 10 uN on an elastic half-space (E = 130 GPa,
nu = 0.3): dissimilar bodies (Dundurs beta = 0.286), so the pressure alone leaves a slip annulus
at F_x = 0.  Adhesion is Dugdale (Maugis) with the work of adhesion set by the Tabor parameter
``mu_T = (R dgamma^2 / (E*^2 z0^3))^(1/3)`` (z0 = 0.2 nm; mu_T = 0: no adhesion).  For each
mu_T a tangential force ramp along x ("total" slip: each step is the one-shot problem of
Paper D) is solved with the normal-tangential coupling loop up to gross slip, and the onset
(the stick area vanishes) is bisected to 1e-3 mu F0+ (:func:`~tribobem.solvers.tangential_paths.tangential_ramp`).

Reported per (mu_T, grid): F0- and F0+ of the F_x = 0 state (Paper D Eq. 16), the onset ratio
F_x / (mu F0+), Paper D's F_nr = F_x / (mu F0), the stick ratio at F_x = 0, the pre-sliding
displacement, and the resolution (cells across the contact radius a and the cohesive zone c - a).
The Maugis-Dugdale state at F0 (a, c and the integral of its negative pressure, the analytic
F0-) is reported beside the numerical one.

The domain is the square -k r0 < x, y < k r0 with r0 the Maugis-Dugdale cohesive radius c0 at
F0 (Paper D takes -c0 < x, y < c0 and zero-pads it; here the free-boundary operator zero-pads
too) or the Hertz radius for mu_T = 0, and k = ``half_width`` (default 2).  The onset ratio is
a property of the discretised contact edge, so it is established by a resolution study
(:func:`paper_d_table1` over several ``n``), not taken from one grid.
"""

from __future__ import annotations

import math
import time
import warnings
from dataclasses import dataclass, field
from typing import Callable, Sequence

import numpy as np

from tribobem.analytic.adhesion import maugis_dugdale, maugis_dugdale_pressure, maugis_parameter
from tribobem.elasticity.operators import free_boundary_operator
from tribobem.errors import ConvergenceWarning, InputError
from tribobem.geometry import sphere
from tribobem.grid import Grid
from tribobem.interactions.dugdale import DugdaleAdhesion
from tribobem.materials import ContactPair, Material
from tribobem.solvers.coupling import solve_coupled
from tribobem.solvers.normal import solve_normal
from tribobem.solvers.tangential_paths import tangential_ramp

__all__ = [
    "PAPER_D_TABLE1",
    "DEFAULT_FRACTIONS",
    "PaperDCase",
    "md_reference",
    "paper_d_case",
    "zero_state",
    "paper_d_table1",
    "study_table",
    "resolution_summary",
]

#: Paper D Table 1: mu_T -> (F0- uN, F0+ uN, F_nr = F_x/(mu F0), F_x/(mu F0+)) at gross slip.
PAPER_D_TABLE1 = {
    0.0: (0.0, 10.000, 0.97, 0.9700),
    0.5: (-6.088, 16.088, 1.56, 0.9697),
    1.0: (-16.018, 26.018, 2.52, 0.9685),
    2.0: (-42.114, 52.114, 5.04, 0.9690),
}

#: Ramp values as fractions of mu F0+ (F0+ of the F_x = 0 state): denser where the onset lies.
DEFAULT_FRACTIONS = (0.0, 0.15, 0.3, 0.45, 0.6, 0.7, 0.8, 0.85, 0.88, 0.91, 0.94, 0.97, 0.99)


def _hertz_radius(radius: float, force: float, E_star: float) -> float:
    return (3.0 * force * radius / (4.0 * E_star)) ** (1.0 / 3.0)


def md_reference(tabor: float, radius: float, E_star: float, z0: float, force: float) -> dict:
    """Maugis-Dugdale state of the smooth ball at ``force`` (the stable branch).

    Returns a dict with ``contact_radius`` a, ``cohesive_radius`` c (m), ``maugis`` lambda,
    ``work_of_adhesion``, ``sigma0`` and ``adhesive_force``: the integral of the negative part of
    the MD pressure (the cohesive annulus a < r < c at -sigma0 plus the tensile rim inside the
    contact), the analytic counterpart of Paper D's F0- (Eq. 16c), N (<= 0);
    ``annulus_force``, the annulus alone, -sigma0 pi (c^2 - a^2); and ``repulsive_force``
    = force - adhesive_force.  mu_T = 0 gives the Hertz state (no adhesive force).
    """
    if tabor == 0:
        a = _hertz_radius(radius, force, E_star)
        return {"contact_radius": a, "cohesive_radius": a, "maugis": 0.0, "work_of_adhesion": 0.0, "sigma0": 0.0,
                "adhesive_force": 0.0, "annulus_force": 0.0, "repulsive_force": force}
    ad = DugdaleAdhesion.from_tabor(float(tabor), radius, E_star, z0)
    dg = ad.work_of_adhesion
    md = maugis_dugdale(radius, dg, E_star, z0, force=force)
    a, c = float(md.contact_radius), float(md.cohesive_radius)
    # The tensile rim inside the contact: p(r) < 0 for r0 < r < a; integrate on a fine radial
    # grid refined towards the edge (p has a square-root behaviour at r = a).
    t = np.linspace(0.0, 1.0, 200001)
    r = a * (1.0 - (1.0 - t) ** 2)  # clustered at r = a
    p = np.asarray(maugis_dugdale_pressure(r, radius, dg, E_star, z0, force=force))
    f = np.minimum(p, 0.0) * r
    inner = 2.0 * math.pi * float(np.sum(0.5 * (f[1:] + f[:-1]) * np.diff(r)))
    annulus = -ad.sigma0 * math.pi * (c * c - a * a)
    adh = inner + annulus
    return {"contact_radius": a, "cohesive_radius": c, "maugis": float(maugis_parameter(radius, dg, E_star, z0)),
            "work_of_adhesion": dg, "sigma0": ad.sigma0, "adhesive_force": adh, "annulus_force": annulus,
            "repulsive_force": force - adh}


def _setup(tabor, n, half_width, radius, E, nu, force, z0, backend):
    """(MD reference, grid, 3x3 free-boundary operator, gap, adhesion or None)."""
    pair = ContactPair(Material(E, nu, "flat"), Material.rigid("ball"))
    E_star = pair.effective_modulus
    md = md_reference(float(tabor), radius, E_star, z0, force)
    grid = Grid.square(int(n), 2.0 * half_width * md["cohesive_radius"])
    op = free_boundary_operator(grid, pair, ("x", "y", "z"), backend=backend)
    ad = DugdaleAdhesion.from_tabor(float(tabor), radius, E_star, z0) if tabor > 0 else None
    return md, grid, op, sphere(grid, radius), ad


def _edge(res) -> bool:
    zone = res.normal.contact | res.normal.adhesive
    return bool(zone[0].any() or zone[-1].any() or zone[:, 0].any() or zone[:, -1].any())


def zero_state(
    tabor: float,
    n: int,
    *,
    half_width: float = 2.0,
    radius: float = 10e-6,
    E: float = 130e9,
    nu: float = 0.3,
    force: float = 10e-6,
    friction_coefficient: float = 0.2,
    z0: float = 0.2e-9,
    backend: str = "numpy",
    **solver_kw,
) -> dict:
    """The coupled F_x = 0 state alone (no ramp): F0-, F0+, stick ratio and the resolution of
    the contact and the cohesive zone, cheap enough for grids finer than the ramps can afford
    (the grid convergence of F0- against Maugis-Dugdale).

    Returns a dict with ``tabor``, ``n``, ``dx``, ``repulsive_force``, ``adhesive_force``,
    ``normal_only_repulsive_force`` (the normal problem without the coupling),
    ``zero_stick_ratio``, ``contact_radius``, ``cohesive_radius`` (equivalent radii, m),
    ``cells_across_contact``, ``cells_across_cohesive_zone``, ``converged``, ``edge_contact``,
    ``md`` (:func:`md_reference`), ``wall_time``, ``cpu_time``.
    """
    t0, c0 = time.perf_counter(), time.process_time()
    md, grid, op, gap, ad = _setup(tabor, n, half_width, radius, E, nu, force, z0, backend)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ConvergenceWarning)
        tol = solver_kw.get("tol", 1e-10)
        nrm = solve_normal(op, gap, force=force, interaction=ad, tol=tol)
        res = solve_coupled(op, gap, friction_coefficient=float(friction_coefficient), normal_force=force,
                            interaction=ad, initial=None, **solver_kw)
    a, c = res.normal.contact_radius(), res.normal.cohesive_radius()
    return {"tabor": float(tabor), "n": int(n), "dx": grid.dx, "size": grid.lx, "half_width": float(half_width),
            "repulsive_force": res.normal.repulsive_force, "adhesive_force": res.normal.adhesive_force,
            "normal_only_repulsive_force": nrm.repulsive_force, "zero_stick_ratio": res.tangential.stick_ratio,
            "contact_radius": a, "cohesive_radius": c, "cells_across_contact": a / grid.dx,
            "cells_across_cohesive_zone": (c - a) / grid.dx, "converged": bool(res.converged and nrm.converged),
            "edge_contact": _edge(res), "md": md,
            "wall_time": time.perf_counter() - t0, "cpu_time": time.process_time() - c0}


@dataclass
class PaperDCase:
    """One tangential ramp of the Paper D study (one mu_T on one grid).

    Scalars are SI (N, m, s).  ``forces`` (F_x), ``force_ratios`` (F_x / (mu F0+) with the
    step's own F0+, as ``onset_ratio``), ``repulsive_forces`` (F0+ of each step),
    ``stick_ratios`` (A_stick / A_contact) and ``displacements`` (delta_x minus its value at
    F_x = 0) describe the ramp steps with stick, followed by the last state with stick at the
    refined onset.

    ``onset_ratio`` is the onset force over mu F0+ of the onset state (the largest force the
    contact could carry there); ``onset_ratio_zero`` divides by F0+ of the F_x = 0 state
    instead (the two differ by the change of F0+ along the ramp: the shear-induced normal
    displacement changes the pressure, by ~1 % with strong adhesion).
    ``force_ratio_paper_d`` is Paper D's F_nr = onset / (mu F0) (Eq. 15).
    """

    tabor: float
    n: int
    size: float
    dx: float
    half_width: float
    friction_coefficient: float
    work_of_adhesion: float
    sigma0: float
    # F_x = 0 state
    repulsive_force: float
    adhesive_force: float
    zero_stick_ratio: float
    contact_radius: float
    cohesive_radius: float
    # onset
    gross_slip: bool
    onset_force: float
    onset_bracket: tuple
    onset_ratio: float
    onset_ratio_zero: float
    onset_repulsive_force: float
    onset_adhesive_force: float
    force_ratio_paper_d: float
    presliding_displacement: float
    refine_steps: int
    converged: bool
    edge_contact: bool
    # analytic reference
    md: dict
    # ramp curve
    forces: np.ndarray
    force_ratios: np.ndarray
    repulsive_forces: np.ndarray
    stick_ratios: np.ndarray
    displacements: np.ndarray
    coupling_iterations: np.ndarray
    wall_time: float
    cpu_time: float
    message: str = ""
    extra: dict = field(default_factory=dict)

    @property
    def cells_across_contact(self) -> float:
        """a / dx with a the equivalent radius sqrt(A_c/pi) of the F_x = 0 contact."""
        return self.contact_radius / self.dx

    @property
    def cells_across_cohesive_zone(self) -> float:
        """(c - a) / dx of the numerical F_x = 0 state (equivalent radii)."""
        return (self.cohesive_radius - self.contact_radius) / self.dx

    @property
    def bracket_width(self) -> float:
        """Width of the final onset bracket over mu F0+ of the onset state."""
        lo, hi = self.onset_bracket
        return (hi - lo) / (self.friction_coefficient * self.onset_repulsive_force)

    def row(self) -> dict:
        """A flat dict for a table (SI units)."""
        return {
            "tabor": self.tabor, "n": self.n, "size": self.size, "dx": self.dx, "half_width": self.half_width,
            "friction_coefficient": self.friction_coefficient,
            "work_of_adhesion": self.work_of_adhesion, "sigma0": self.sigma0,
            "repulsive_force": self.repulsive_force, "adhesive_force": self.adhesive_force,
            "zero_stick_ratio": self.zero_stick_ratio,
            "contact_radius": self.contact_radius, "cohesive_radius": self.cohesive_radius,
            "cells_across_contact": self.cells_across_contact,
            "cells_across_cohesive_zone": self.cells_across_cohesive_zone,
            "gross_slip": self.gross_slip, "onset_force": self.onset_force,
            "onset_bracket_lo": self.onset_bracket[0], "onset_bracket_hi": self.onset_bracket[1],
            "onset_bracket_width": self.bracket_width,
            "onset_ratio": self.onset_ratio, "onset_ratio_zero": self.onset_ratio_zero,
            "onset_repulsive_force": self.onset_repulsive_force, "onset_adhesive_force": self.onset_adhesive_force,
            "force_ratio_paper_d": self.force_ratio_paper_d,
            "presliding_displacement": self.presliding_displacement, "refine_steps": self.refine_steps,
            "converged": self.converged, "edge_contact": self.edge_contact,
            "md_contact_radius": self.md["contact_radius"], "md_cohesive_radius": self.md["cohesive_radius"],
            "md_adhesive_force": self.md["adhesive_force"], "md_annulus_force": self.md["annulus_force"],
            "md_repulsive_force": self.md["repulsive_force"],
            "md_cells_across_cohesive_zone": (self.md["cohesive_radius"] - self.md["contact_radius"]) / self.dx,
            "ramp_steps": len(self.forces), "wall_time": self.wall_time, "cpu_time": self.cpu_time,
        }


def paper_d_case(
    tabor: float,
    n: int = 128,
    *,
    half_width: float = 2.0,
    radius: float = 10e-6,
    E: float = 130e9,
    nu: float = 0.3,
    force: float = 10e-6,
    friction_coefficient: float = 0.2,
    z0: float = 0.2e-9,
    fractions: Sequence[float] = DEFAULT_FRACTIONS,
    refine_tol: float = 1e-3,
    backend: str = "numpy",
    **solver_kw,
) -> PaperDCase:
    """Solve the F_x = 0 state, then the tangential ramp to gross slip, for one Tabor parameter.

    Parameters
    ----------
    tabor : float
        mu_T >= 0 (0: no adhesion); the work of adhesion is
        :meth:`DugdaleAdhesion.from_tabor` of the ball.
    n : int
        Cells per side.
    half_width : float
        The domain is -k r0 < x, y < k r0, k = ``half_width``, r0 the Maugis-Dugdale cohesive
        radius at ``force`` (the Hertz radius for mu_T = 0).
    radius, E, nu, force, friction_coefficient, z0 : float
        Paper D: 10 um, 130 GPa, 0.3, 10 uN, 0.2, 0.2 nm (the ball is rigid).
    fractions : sequence of float
        Ramp values F_x / (mu F0+) with F0+ of the F_x = 0 state; they must increase and end
        beyond the onset (the ramp stops at gross slip; 0.99 by default).
    refine_tol : float
        Bisection of the onset to ``refine_tol`` mu F0+.
    backend : str
        "numpy" (default) or "cupy".
    **solver_kw
        Passed to :func:`~tribobem.solvers.coupling.solve_coupled` (tol, tangential_tol,
        coupling_tol, ...).

    Returns
    -------
    PaperDCase
    """
    if not (math.isfinite(tabor) and tabor >= 0):
        raise InputError("tabor", f"must be >= 0, got {tabor!r}")
    fr = np.asarray(fractions, dtype=float)
    if fr.ndim != 1 or len(fr) < 2 or np.any(np.diff(fr) <= 0) or fr[0] < 0:
        raise InputError("fractions", "must be an increasing list of F_x/(mu F0+) values >= 0")
    if not (isinstance(half_width, (int, float)) and half_width > 1.0):
        raise InputError("half_width", f"must be > 1 (the domain must hold the cohesive zone), got {half_width!r}")
    t0, c0 = time.perf_counter(), time.process_time()
    md, grid, op, gap, ad = _setup(tabor, n, half_width, radius, E, nu, force, z0, backend)
    size = grid.lx
    mu = float(friction_coefficient)
    kw = dict(solver_kw)

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ConvergenceWarning)
        zero = solve_coupled(op, gap, friction_coefficient=mu, normal_force=force, interaction=ad, **kw)
    f0p = zero.normal.repulsive_force
    ramp = tangential_ramp(op, gap, normal_force=force, friction_coefficient=mu, forces=list(fr * mu * f0p),
                           direction=0.0, interaction=ad, slip="total", refine_tol=float(refine_tol), **kw)

    # The curve: the ramp steps with stick (the first gross-slip step, if any, is dropped), then
    # the last state with stick at the refined onset.
    states = [s for s in ramp.steps if not s.tangential.gross_slip]
    if ramp.onset_state is not None:
        states.append(ramp.onset_state)
    fx = np.array([s.tangential.force_x for s in states])
    stick = np.array([s.tangential.stick_ratio for s in states])
    dxs = np.array([s.tangential.displacement_x for s in states])
    z = ramp.zero_state if ramp.zero_state is not None else zero
    dxs = dxs - z.tangential.displacement_x
    coup = np.array([s.coupling_iterations for s in states])
    f0p_steps = np.array([s.normal.repulsive_force for s in states])
    ok = bool(zero.converged and all(s.converged for s in states))
    ons = ramp.onset_state
    edge = _edge(zero)
    onset = float(ramp.onset)
    return PaperDCase(
        tabor=float(tabor), n=int(n), size=size, dx=grid.dx, half_width=float(half_width), friction_coefficient=mu,
        work_of_adhesion=md["work_of_adhesion"], sigma0=md["sigma0"],
        repulsive_force=f0p, adhesive_force=zero.normal.adhesive_force,
        zero_stick_ratio=zero.tangential.stick_ratio,
        contact_radius=zero.normal.contact_radius(), cohesive_radius=zero.normal.cohesive_radius(),
        gross_slip=bool(ramp.gross_slip), onset_force=onset, onset_bracket=tuple(float(v) for v in ramp.onset_bracket),
        onset_ratio=float(ramp.onset_ratio), onset_ratio_zero=onset / (mu * f0p),
        onset_repulsive_force=ons.normal.repulsive_force if ons is not None else float("nan"),
        onset_adhesive_force=ons.normal.adhesive_force if ons is not None else float("nan"),
        force_ratio_paper_d=onset / (mu * force),
        presliding_displacement=float(ramp.presliding_displacement), refine_steps=int(ramp.refine_steps),
        converged=ok, edge_contact=edge, md=md,
        forces=fx, force_ratios=fx / (mu * f0p_steps), repulsive_forces=f0p_steps, stick_ratios=stick,
        displacements=dxs,
        coupling_iterations=coup,
        wall_time=time.perf_counter() - t0, cpu_time=time.process_time() - c0, message=ramp.message,
    )


def paper_d_table1(
    tabor_values: Sequence[float] = (0.0, 0.5, 1.0, 2.0),
    grids: Sequence[int] = (128, 192),
    *,
    progress: Callable[[PaperDCase], None] | None = None,
    **case_kw,
) -> list:
    """Run :func:`paper_d_case` for every (mu_T, n): the table and its resolution study.

    Parameters
    ----------
    tabor_values : sequence of float
    grids : sequence of int
        Cells per side; the same ``half_width`` for all, so they differ in dx only.
    progress : callable, optional
        Called with each finished :class:`PaperDCase`.
    **case_kw
        Passed to :func:`paper_d_case`.

    Returns
    -------
    list of PaperDCase
        Ordered by mu_T, then n.
    """
    if not len(tabor_values) or not len(grids):
        raise InputError("paper_d_table1", "give at least one Tabor parameter and one grid")
    out = []
    for mu_t in tabor_values:
        for n in grids:
            case = paper_d_case(float(mu_t), int(n), **case_kw)
            out.append(case)
            if progress:
                progress(case)
    return out


def _paper_d_columns(tabor: float) -> dict:
    ref = PAPER_D_TABLE1.get(float(tabor))
    nan = float("nan")
    return {"paper_d_adhesive_force": ref[0] * 1e-6 if ref else nan,
            "paper_d_repulsive_force": ref[1] * 1e-6 if ref else nan,
            "paper_d_force_ratio": ref[2] if ref else nan, "paper_d_onset_ratio": ref[3] if ref else nan}


def study_table(cases: Sequence[PaperDCase], zero_states: Sequence[dict] = ()):
    """A pandas DataFrame with one row per ramp (``ramp`` True) and one per F_x = 0 state of
    :func:`zero_state` (``ramp`` False; the onset columns are NaN), SI units, with Paper D's
    values per mu_T (``paper_d_adhesive_force``, ``paper_d_repulsive_force`` in N,
    ``paper_d_force_ratio``, ``paper_d_onset_ratio``) and the Maugis-Dugdale reference
    (``md_*``: a, c, the integral of p < 0, the annulus alone, F0 minus that integral, and
    (c - a)/dx)."""
    import pandas as pd

    rows = []
    for z in zero_states:
        md = z["md"]
        r = {k: v for k, v in z.items() if k != "md"}
        r.update({"ramp": False, "md_contact_radius": md["contact_radius"], "md_cohesive_radius": md["cohesive_radius"],
                  "md_adhesive_force": md["adhesive_force"], "md_annulus_force": md["annulus_force"],
                  "md_repulsive_force": md["repulsive_force"],
                  "md_cells_across_cohesive_zone": (md["cohesive_radius"] - md["contact_radius"]) / z["dx"]})
        r.update(_paper_d_columns(z["tabor"]))
        rows.append(r)
    for c in cases:
        r = c.row()
        r["ramp"] = True
        r.update(_paper_d_columns(c.tabor))
        rows.append(r)
    df = pd.DataFrame(rows)
    first = ["tabor", "ramp", "n", "dx"]
    df = df[first + [c for c in df.columns if c not in first]]
    return df.sort_values(["tabor", "ramp", "n"], ascending=[True, False, True]).reset_index(drop=True)


def resolution_summary(cases: Sequence[PaperDCase], agree: float = 0.005) -> list[dict]:
    """Per mu_T: the onset ratio on every grid, the change between the two finest grids and
    whether it is below ``agree`` (the study's convergence criterion).

    Returns a list of dicts ``{"tabor", "n", "dx", "onset_ratio", "finest_change", "converged"}``
    with ``n``, ``dx``, ``onset_ratio`` lists ordered by n.
    """
    out = []
    for mu_t in sorted({c.tabor for c in cases}):
        cs = sorted((c for c in cases if c.tabor == mu_t), key=lambda c: c.n)
        ratios = [c.onset_ratio for c in cs]
        change = abs(ratios[-1] - ratios[-2]) if len(cs) > 1 else float("nan")
        out.append({"tabor": mu_t, "n": [c.n for c in cs], "dx": [c.dx for c in cs], "onset_ratio": ratios,
                    "finest_change": change, "converged": bool(len(cs) > 1 and change <= agree)})
    return out
