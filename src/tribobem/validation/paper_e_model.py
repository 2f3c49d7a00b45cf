"""Paper E section 3.2: friction hysteresis loops of a smooth rigid ball on an elastic flat with
Dugdale adhesion (thesis Paper E Figs. 6, 7, 9): the model problem, one loop and its
measures.

The ``paper_e`` validation case (:mod:`tribobem.validation.paper_e`) runs these loops, so they
live in the package; the repository's study (``studies.paper_e``, driver
``examples/studies/paper_e.py``) re-exports them and adds the study over every dgamma and its
tables.  Paper E's published number (:data:`~tribobem.validation.references.PAPER_E_SMOOTH_REPULSIVE_FORCE`)
is in :mod:`tribobem.validation.references`.

A rigid ball (R = 50 um) is pressed with F0 = 10 uN on an elastic half-space (E = 70 GPa,
nu = 0.3; Dundurs beta = 0.286, so the pressure alone slips an annulus at F_x = 0), mu = 0.2.
The work of adhesion is dgamma = 0, 50 or 100 mJ/m^2 (Dugdale law).  Paper E does not give z0:
0.2 nm is taken, as for Paper D ("100 z0 = 20 nm").  The tangential force is cycled (force
control, :func:`~tribobem.solvers.hysteresis.hysteresis_loop`) 0 -> +F* -> -F* -> +F* -> ...
with F* = 0.999 mu F0+ (F0+ of the F_x = 0 state), one initial loading and two full cycles
(Paper E: "repeated for two more loops").  Every step after the start is incremental (Paper E
Eq. 5) with the normal-tangential coupling loop and the adhesion active.

F* is chosen ``"right before the start of gross-sliding"`` (Paper E 3): the first loading from A
is ramped incrementally to its gross-slip onset (the stick zone vanishes; bisected to 1e-3
mu F0+) and F* = 0.999 x the last force with stick (``peak="onset"``).  In this model the onset
comes at ~0.97-0.98 mu F0+, not at mu F0+: beyond it the whole contact slips while the force
is still below mu F0+ (the slip directions spread), the displacement is no longer pinned by a
stick zone and a cycle through it ratchets.  With adhesion, mu F0+ of A is not carried at all:
the shear lowers F0+ through the coupling (~1.5 % at the onset).  Paper E's literal
F* = 0.999 mu F0+ is ``peak="repulsive"`` (adapted just below the largest carried force).

The domain is -2a < x, y < 2a (Paper E) with ``a`` the analytic contact radius: Maugis-Dugdale
at F0 for dgamma > 0 (:func:`md_state`), Hertz for dgamma = 0.  Paper E uses 256^2 cells (dx 2 to
6 nm); a whole loop at 256^2 is too costly for a study over every dgamma (run time:
benchmarks/README.md), so the published study uses a coarser grid and reports the cells across
the contact and across the cohesive zone c - a (the adhesive cases are under-resolved below
``MIN_COHESIVE_CELLS`` cells across c - a).

Points (Paper E Fig. 3): ``A`` the start (F_x = 0, one-shot solve), ``A'`` the first step,
``D`` the first turning point (+F*), ``D'`` the step after it, ``H`` (-F*, cycle 1) and ``H'``,
``L`` (+F*, cycle 1) and ``L'``, then ``H2`` and ``L2`` (cycle 2).

Measures (:func:`loop_metrics`): F0+ and F0- at A, the static friction (the gross-slip onset of
the first loading, and F* = the largest force of the path, with the stick ratio at D near 0)
over mu F0 beside F0+/F0 (Paper E: "the static friction force is controlled by the contact
repulsive force"), the pre-sliding displacement delta(D) - delta(A) (and delta at the onset),
the stick ratios at A, A', D, D', the loop width
delta(+F*) - delta(-F*) per cycle, its centre offset (delta(+F*) + delta(-F*))/2 relative to the
width (loop symmetry), the change of the turning-point displacements between the last two
cycles relative to the width (a stationary loop), the largest difference of the stick ratio
between the unloading branch at F and the reloading branch at -F of the last cycle (a symmetric
slip development), the point symmetry of the last loop about its centre, and the loop energy
per cycle.  :func:`start_state` gives the F_x = 0 state alone on finer grids (F0+ against
Maugis-Dugdale and Paper E's 29.165 uN at dgamma = 50 mJ/m^2).
"""

from __future__ import annotations

import math
import time
import warnings
from dataclasses import dataclass, field
from typing import Callable, Sequence

import numpy as np

from ..analytic.adhesion import maugis_dugdale, maugis_dugdale_pressure
from ..analytic.hertz import hertz
from ..elasticity.operators import free_boundary_operator
from ..errors import ConvergenceWarning, InputError
from ..geometry import sphere
from ..grid import Grid
from ..interactions.dugdale import DugdaleAdhesion
from ..materials import ContactPair, Material
from ..solvers.coupling import solve_coupled
from ..solvers.hysteresis import hysteresis_loop, loop_energies
from ..solvers.tangential_paths import tangential_ramp
from ..solvers.tangential import GrossSlipError
from .references import PAPER_E_SMOOTH_REPULSIVE_FORCE

__all__ = [
    "RADIUS", "E_FLAT", "NU_FLAT", "FORCE", "FRICTION", "Z0", "WORKS", "PAPER_E_SMOOTH_REPULSIVE_FORCE",
    "MIN_COHESIVE_CELLS", "DEFAULT_SOLVER", "RAMP_FRACTIONS",
    "md_state", "paper_e_problem", "start_state", "PaperELoop", "paper_e_loop", "loop_metrics",
]

#: Paper E section 3: rigid ball R = 50 um, elastic flat E = 70 GPa, nu = 0.3, F0 = 10 uN, mu = 0.2.
RADIUS = 50e-6
E_FLAT = 70e9
NU_FLAT = 0.3
FORCE = 10e-6
FRICTION = 0.2
#: Not given by Paper E: 0.2 nm as for Paper D.
Z0 = 0.2e-9
#: Paper E section 3.2: dgamma = 0, 50, 100 mJ/m^2 (J/m^2 here).
WORKS = (0.0, 0.05, 0.1)
#: Fewer cells than this across the cohesive zone c - a: the adhesive force is under-resolved.
MIN_COHESIVE_CELLS = 3.0
#: F_x / (mu F0+ of A) of the first-loading ramp to the gross-slip onset (then bisected).
RAMP_FRACTIONS = (0.3, 0.6, 0.8, 0.9, 0.95, 0.97, 0.98, 0.99, 0.999)
#: Solver tolerances of the study (those of the ``hysteresis`` run kind).
DEFAULT_SOLVER = {"tol": 1e-10, "tangential_tol": 1e-7, "coupling_tol": 1e-6}


def _pair(E: float = E_FLAT, nu: float = NU_FLAT) -> ContactPair:
    return ContactPair(Material(E, nu, "flat"), Material.rigid("ball"))


def md_state(work_of_adhesion: float, *, radius: float = RADIUS, E: float = E_FLAT, nu: float = NU_FLAT,
             force: float = FORCE, z0: float = Z0) -> dict:
    """Analytic state of the smooth ball at ``force``: Maugis-Dugdale (stable branch) for
    dgamma > 0, Hertz for dgamma = 0.

    Parameters
    ----------
    work_of_adhesion : float
        dgamma (J/m^2), >= 0.
    radius : float
        Ball radius R (m).
    E, nu : float
        Young's modulus (Pa) and Poisson's ratio of the flat (the ball is rigid).
    force : float
        Normal force F0 (N).
    z0 : float
        Dugdale equilibrium distance (m).

    Returns
    -------
    dict
        ``contact_radius`` a, ``cohesive_radius`` c (m), ``maugis`` lambda, ``sigma0`` (Pa),
        ``adhesive_force`` (the integral of p < 0: the -sigma0 annulus a < r < c and the
        tensile rim inside the contact, N, <= 0), ``repulsive_force`` (force minus it: the
        analytic F0+, N) and ``mindlin_k`` = (2 - nu)/G of the flat (1/Pa; the rigid ball adds
        nothing).

    Raises
    ------
    InputError
        A negative or non-finite work of adhesion.
    """
    E_star = _pair(E, nu).effective_modulus
    G = E / (2.0 * (1.0 + nu))
    k = (2.0 - nu) / G
    if work_of_adhesion == 0:
        a = float(hertz(force=force, radius=radius, E_star=E_star).contact_radius)
        return {"contact_radius": a, "cohesive_radius": a, "maugis": 0.0, "sigma0": 0.0, "adhesive_force": 0.0,
                "repulsive_force": force, "mindlin_k": k}
    if not (math.isfinite(work_of_adhesion) and work_of_adhesion > 0):
        raise InputError("work_of_adhesion", f"must be >= 0 J/m^2, got {work_of_adhesion!r}")
    md = maugis_dugdale(radius, work_of_adhesion, E_star, z0, force=force)
    a, c = float(md.contact_radius), float(md.cohesive_radius)
    # The tensile rim inside the contact (p < 0 near r = a): fine radial grid clustered at r = a.
    t = np.linspace(0.0, 1.0, 200001)
    r = a * (1.0 - (1.0 - t) ** 2)
    p = np.asarray(maugis_dugdale_pressure(r, radius, work_of_adhesion, E_star, z0, force=force))
    f = np.minimum(p, 0.0) * r
    inner = 2.0 * math.pi * float(np.sum(0.5 * (f[1:] + f[:-1]) * np.diff(r)))
    adh = inner - md.sigma0 * math.pi * (c * c - a * a)
    return {"contact_radius": a, "cohesive_radius": c, "maugis": float(md.lam), "sigma0": float(md.sigma0),
            "adhesive_force": adh, "repulsive_force": force - adh, "mindlin_k": k}


def paper_e_problem(work_of_adhesion: float, n: int, *, half_width: float = 2.0, radius: float = RADIUS,
                    E: float = E_FLAT, nu: float = NU_FLAT, force: float = FORCE, z0: float = Z0,
                    backend: str = "numpy"):
    """The Paper E 3.2 problem on n^2 cells over -k a < x, y < k a.

    k = ``half_width``, a the analytic contact radius (:func:`md_state`), so that the domain
    follows the contact as dgamma changes.

    Parameters
    ----------
    work_of_adhesion : float
        dgamma (J/m^2), 0 for no adhesion.
    n : int
        Cells per side (>= 8).
    half_width : float
        Half side of the domain in units of a (> 1; the domain must hold the cohesive zone).
    radius : float
        Ball radius R (m).
    E, nu : float
        Young's modulus (Pa) and Poisson's ratio of the flat (the ball is rigid).
    force : float
        Normal force F0 (N).
    z0 : float
        Dugdale equilibrium distance (m).
    backend : str
        Array backend of the operator (``"numpy"``, ...).

    Returns
    -------
    grid : Grid
    gap : ndarray
        Paraboloid gap of the ball (m).
    operator
        3x3 (x, y, z) free-boundary operator.
    adhesion : DugdaleAdhesion or None
        None for dgamma = 0.
    md : dict
        The analytic state, :func:`md_state`.

    Raises
    ------
    InputError
        ``n`` < 8, ``half_width`` <= 1 or a domain that does not hold the cohesive zone.
    """
    if not (isinstance(n, (int, np.integer)) and n >= 8):
        raise InputError("n", f"must be an integer >= 8, got {n!r}")
    if not (math.isfinite(half_width) and half_width > 1.0):
        raise InputError("half_width", f"must be > 1, got {half_width!r}")
    md = md_state(work_of_adhesion, radius=radius, E=E, nu=nu, force=force, z0=z0)
    if half_width * md["contact_radius"] <= md["cohesive_radius"] * 1.05:
        raise InputError("half_width", "the domain must hold the cohesive zone")
    pair = _pair(E, nu)
    grid = Grid.square(int(n), 2.0 * half_width * md["contact_radius"])
    op = free_boundary_operator(grid, pair, ("x", "y", "z"), backend=backend)
    ad = DugdaleAdhesion(float(work_of_adhesion), z0) if work_of_adhesion > 0 else None
    return grid, sphere(grid, radius), op, ad, md


def start_state(work_of_adhesion: float, n: int, *, friction_coefficient: float = FRICTION, force: float = FORCE,
                half_width: float = 2.0, backend: str = "numpy", **solver_kw) -> dict:
    """The coupled F_x = 0 state alone (point A) on n^2 cells over +-2a: cheap enough for Paper E's
    256^2 and finer, for the grid convergence of F0+ (the loops run on coarser grids).

    Parameters
    ----------
    work_of_adhesion : float
        dgamma (J/m^2), 0 for no adhesion.
    n : int
        Cells per side.
    friction_coefficient : float
        mu.
    force : float
        Normal force F0 (N).
    half_width : float
        Half side of the domain in units of a.
    backend : str
        Array backend of the operator.
    **solver_kw
        Passed to :func:`~tribobem.solvers.coupling.solve_coupled` (over
        :data:`DEFAULT_SOLVER`).

    Returns
    -------
    dict
        ``work_of_adhesion`` (J/m^2), ``n``, ``dx`` (m), ``repulsive_force``,
        ``adhesive_force`` (N), ``stick_ratio``, ``contact_radius``, ``cohesive_radius``
        (equivalent radii, m), ``cells_across_contact``, ``cells_across_cohesive_zone``
        (numerical and ``md_`` analytic), ``md_repulsive_force`` (N), ``converged``,
        ``wall_time``, ``cpu_time`` (s).
    """
    t0, c0 = time.perf_counter(), time.process_time()
    grid, gap, op, ad, md = paper_e_problem(work_of_adhesion, n, half_width=half_width, force=force, backend=backend)
    kw = dict(DEFAULT_SOLVER)
    kw.update(solver_kw)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ConvergenceWarning)
        z = solve_coupled(op, gap, friction_coefficient=float(friction_coefficient), normal_force=force,
                          interaction=ad, **kw)
    a, c = z.normal.contact_radius(), z.normal.cohesive_radius()
    return {"work_of_adhesion": float(work_of_adhesion), "n": int(n), "dx": grid.dx,
            "repulsive_force": z.normal.repulsive_force, "adhesive_force": z.normal.adhesive_force,
            "stick_ratio": z.tangential.stick_ratio, "contact_radius": a, "cohesive_radius": c,
            "cells_across_contact": a / grid.dx, "cells_across_cohesive_zone": (c - a) / grid.dx,
            "md_cells_across_cohesive_zone": (md["cohesive_radius"] - md["contact_radius"]) / grid.dx,
            "md_repulsive_force": md["repulsive_force"], "converged": bool(z.converged),
            "wall_time": time.perf_counter() - t0, "cpu_time": time.process_time() - c0}


@dataclass
class PaperELoop:
    """One hysteresis run of the study (one dgamma on one grid), SI units.

    The step arrays hold the start (A, index 0) followed by every path step: ``forces`` (F_x),
    ``displacements`` (delta_x), ``stick_ratios`` (A_stick / A_contact), ``repulsive_forces``
    (F0+ of each step), ``cycles`` (0: start and initial loading), ``branches`` ("start",
    "loading", "unloading", "reloading"), ``turning`` (True at +-F*), ``converged``.
    ``points`` maps the named points (A, A', D, D', H, H', L, L', H2, L2) to step indices.
    ``onset_*`` describe the gross-slip onset of the first loading (the incremental ramp from A,
    bisected): ``onset_force`` (bracket midpoint, N), ``onset_bracket``, ``onset_repulsive_force``
    and ``onset_stick_ratio`` of the last state with stick, ``onset_presliding_displacement``
    (its delta_x minus delta_x at A); ``ramp_*`` the ramp's states with stick (delta from A).
    ``peak`` says how F* was chosen (see :func:`paper_e_loop`); ``amplitude`` = F* / (mu F0+ of
    A).

    Attributes
    ----------
    work_of_adhesion : float
        dgamma (J/m^2).
    n : int
        Cells per side.
    size, dx : float
        Domain side and cell size (m).
    half_width : float
        Half side of the domain in units of the analytic a.
    friction_coefficient : float
        mu.
    normal_force : float
        F0 (N).
    z0 : float
        Dugdale equilibrium distance (m).
    steps_per_cycle : int
        Path steps per full cycle.
    peak : str
        ``"onset"`` or ``"repulsive"``.
    amplitude, amplitude_requested, amplitude_limit : float
        F* / (mu F0+ of A) used, requested, and the largest carried fraction found when the
        requested one slipped (NaN otherwise).
    peak_force : float
        F* (N).
    repulsive_force, adhesive_force : float
        F0+ and F0- at A (N).
    contact_radius, cohesive_radius : float
        Equivalent radii a, c at A (m).
    md : dict
        The analytic state, :func:`md_state`.
    onset_force : float
        Gross-slip onset of the first loading, bracket midpoint (N); NaN without onset.
    onset_bracket : tuple of float
        The bisection bracket of the onset (N).
    onset_repulsive_force, onset_presliding_displacement, onset_stick_ratio : float
        F0+ (N), delta_x - delta_x(A) (m) and the stick ratio of the last state with stick.
    ramp_forces, ramp_displacements, ramp_stick_ratios, ramp_repulsive_forces : ndarray
        The ramp's states with stick: F_x (N), delta_x - delta_x(A) (m), stick ratio, F0+ (N).
    forces, displacements, stick_ratios, repulsive_forces : ndarray
        Per step (A first): F_x (N), delta_x (m), A_stick / A_contact, F0+ (N).
    cycles, branches, turning, converged : ndarray
        Per step: cycle number, branch name, turning-point flag, convergence flag.
    points : dict
        Named points -> step indices.
    loop_energies : list of float
        Energy dissipated per cycle (J).
    wall_time, cpu_time : float
        Cost of the run (s).
    message : str
        Messages of the ramp and the loop.
    extra : dict
        Free-form additions of a study.
    """

    work_of_adhesion: float
    n: int
    size: float
    dx: float
    half_width: float
    friction_coefficient: float
    normal_force: float
    z0: float
    steps_per_cycle: int
    peak: str
    amplitude: float
    amplitude_requested: float
    amplitude_limit: float
    peak_force: float
    repulsive_force: float
    adhesive_force: float
    contact_radius: float
    cohesive_radius: float
    md: dict
    onset_force: float
    onset_bracket: tuple
    onset_repulsive_force: float
    onset_presliding_displacement: float
    onset_stick_ratio: float
    ramp_forces: np.ndarray
    ramp_displacements: np.ndarray
    ramp_stick_ratios: np.ndarray
    ramp_repulsive_forces: np.ndarray
    forces: np.ndarray
    displacements: np.ndarray
    stick_ratios: np.ndarray
    repulsive_forces: np.ndarray
    cycles: np.ndarray
    branches: np.ndarray
    turning: np.ndarray
    converged: np.ndarray
    points: dict
    loop_energies: list
    wall_time: float
    cpu_time: float
    message: str = ""
    extra: dict = field(default_factory=dict)

    @property
    def cells_across_contact(self) -> float:
        """a / dx, a = sqrt(A_c/pi) of the F_x = 0 state."""
        return self.contact_radius / self.dx

    @property
    def cells_across_cohesive_zone(self) -> float:
        """(c - a) / dx of the numerical F_x = 0 state (equivalent radii); 0 without adhesion."""
        return (self.cohesive_radius - self.contact_radius) / self.dx

    @property
    def md_cells_across_cohesive_zone(self) -> float:
        """(c - a) / dx of the analytic (Maugis-Dugdale) state."""
        return (self.md["cohesive_radius"] - self.md["contact_radius"]) / self.dx

    @property
    def under_resolved(self) -> bool:
        """An adhesive case with fewer than MIN_COHESIVE_CELLS cells across c - a."""
        return self.work_of_adhesion > 0 and min(self.cells_across_cohesive_zone,
                                                 self.md_cells_across_cohesive_zone) < MIN_COHESIVE_CELLS


def _points(cycles, branches, turning) -> dict:
    """Step indices (start = 0) of A, A', D, D', H, H', L, L', H2, L2, ..."""
    pts = {"A": 0, "A'": 1}
    turns = [i for i in range(len(turning)) if turning[i]]
    names = []
    for i in turns:
        c, b = int(cycles[i]), branches[i]
        if c == 0:
            names.append(("D", i))
        else:
            base = "H" if b == "unloading" else "L"
            names.append((base if c == 1 else f"{base}{c}", i))
    for name, i in names:
        pts[name] = i
        if i + 1 < len(turning):
            pts[name + "'"] = i + 1
    return pts


def paper_e_loop(
    work_of_adhesion: float,
    n: int = 128,
    *,
    steps: int = 24,
    cycles: int = 2,
    peak: str = "onset",
    amplitude: float = 0.999,
    ramp_fractions: Sequence[float] = RAMP_FRACTIONS,
    refine_tol: float = 1e-3,
    half_width: float = 2.0,
    radius: float = RADIUS,
    E: float = E_FLAT,
    nu: float = NU_FLAT,
    force: float = FORCE,
    friction_coefficient: float = FRICTION,
    z0: float = Z0,
    backend: str = "numpy",
    margin: float = 0.002,
    progress: Callable[[int, int], None] | None = None,
    **solver_kw,
) -> PaperELoop:
    """The gross-slip onset of the first loading, then the force-controlled loop, of one dgamma.

    Parameters
    ----------
    work_of_adhesion : float
        dgamma (J/m^2), 0 for no adhesion.
    n : int
        Cells per side over -k a < x, y < k a (k = ``half_width``).
    steps, cycles : int
        Steps per cycle (Chebyshev-cosine spacing, steps/4 on the initial loading) and full
        cycles after the initial loading.
    peak : {"onset", "repulsive"}
        The amplitude F*.  ``"onset"`` (default): ``amplitude`` x the largest force of the first
        loading that still leaves stick (the incremental ramp from A, bisected to ``refine_tol``
        mu F0+): Paper E's "right before the start of gross-sliding", which in this model comes
        at ~0.97-0.98 mu F0+, not at mu F0+.  ``"repulsive"``: Paper E's literal
        F* = ``amplitude`` x mu F0+ of A; with adhesion the shear lowers F0+ (coupling) and this
        force cannot be carried: the loop is then rerun at ``(1 - margin)`` x the largest carried
        force (up to three times; the amplitude used, the one requested and that limit are
        recorded), and the turning points are in full slip (their displacement not pinned).
    amplitude : float
        Fraction in (0, 1] of the force that ``peak`` names (0.999: Paper E's "0.999 mu F0+").
    ramp_fractions : sequence of float
        Values F_x / (mu F0+ of A) of the onset ramp (increasing, in (0, 1]).
    refine_tol : float
        Bisection tolerance of the onset, in units of mu F0+ of A.
    half_width : float
        Half side of the domain in units of the analytic a.
    radius, E, nu, force, friction_coefficient, z0 : float
        Paper E: 50 um, 70 GPa, 0.3, 10 uN, 0.2; z0 = 0.2 nm (not in Paper E).
    backend : str
        Array backend of the operator.
    margin : float
        Relative distance below the largest carried force when F* is not carried
        (``peak="repulsive"``, above).
    progress : callable, optional
        ``progress(done, total)`` along the loop.
    **solver_kw
        Passed to :func:`~tribobem.solvers.coupling.solve_coupled` (default
        :data:`DEFAULT_SOLVER`).

    Returns
    -------
    PaperELoop

    Raises
    ------
    InputError
        An unknown ``peak``, ``amplitude`` outside (0, 1], bad ``ramp_fractions`` or problem
        parameters.
    GrossSlipError
        F* still not carried after three reductions.
    """
    if peak not in ("onset", "repulsive"):
        raise InputError("peak", f"must be 'onset' or 'repulsive', got {peak!r}")
    if not (0 < amplitude <= 1):
        raise InputError("amplitude", f"must be in (0, 1], got {amplitude!r}")
    fr = np.asarray(ramp_fractions, float)
    if fr.ndim != 1 or len(fr) < 2 or np.any(np.diff(fr) <= 0) or fr[0] <= 0 or fr[-1] > 1:
        raise InputError("ramp_fractions", "must increase in (0, 1]")
    t0, c0 = time.perf_counter(), time.process_time()
    grid, gap, op, ad, md = paper_e_problem(work_of_adhesion, n, half_width=half_width, radius=radius, E=E, nu=nu,
                                            force=force, z0=z0, backend=backend)
    kw = dict(DEFAULT_SOLVER)
    kw.update(solver_kw)
    mu = float(friction_coefficient)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ConvergenceWarning)
        start = solve_coupled(op, gap, friction_coefficient=mu, normal_force=force, interaction=ad, **kw)
        f0p = start.normal.repulsive_force
        # The first loading from A (incremental), to the gross-slip onset (no stick node left).
        ramp = tangential_ramp(op, gap, normal_force=force, friction_coefficient=mu,
                               forces=[0.0] + list(fr * mu * f0p), interaction=ad, slip="incremental",
                               refine_tol=float(refine_tol), **kw)
        if ramp.gross_slip and ramp.onset_state is not None:
            onset, lo = float(ramp.onset), float(ramp.onset_bracket[0])
            onset_state = ramp.onset_state
        else:  # stick left up to the last fraction: no onset below it
            onset = lo = float("nan")
            onset_state = ramp.steps[-1]
        keep = [s for s in ramp.steps if not s.tangential.gross_slip]
        if ramp.onset_state is not None and ramp.onset_state is not keep[-1]:
            keep.append(ramp.onset_state)
        requested = float(amplitude)
        limit = float("nan")
        if peak == "onset" and math.isfinite(lo):
            amp = amplitude * lo / (mu * f0p)
        else:
            amp = float(amplitude)
        for attempt in range(4):
            try:
                run = hysteresis_loop(op, gap, normal_force=force, friction_coefficient=mu, control="force",
                                      amplitude=amp, cycles=cycles, steps=steps, interaction=ad,
                                      progress=progress, **kw)
                break
            except GrossSlipError as exc:
                # F* beyond what the contact carries (the shear lowers F0+): just below the largest
                # carried force, as a fraction of mu F0+ of A.
                if attempt == 3:
                    raise
                limit = exc.max_force / (mu * f0p)
                amp = min(amp, limit) * (1.0 - margin)
    states = [run.start] + run.steps
    F = np.array([s.tangential.force_x for s in states])
    D = np.array([s.tangential.displacement_x for s in states])
    S = np.array([s.tangential.stick_ratio for s in states])
    P = np.array([s.normal.repulsive_force for s in states])
    C = np.concatenate([[0], run.path.cycle]).astype(int)
    B = np.concatenate([["start"], run.path.branch]).astype(object)
    T = np.concatenate([[False], run.path.turning]).astype(bool)
    ok = np.array([bool(s.converged) for s in states])
    z = run.start
    d_a = float(ramp.steps[0].tangential.displacement_x)
    return PaperELoop(
        work_of_adhesion=float(work_of_adhesion), n=int(n), size=grid.lx, dx=grid.dx, half_width=float(half_width),
        friction_coefficient=mu, normal_force=float(force), z0=float(z0), steps_per_cycle=int(steps), peak=peak,
        amplitude=float(amp), amplitude_requested=requested, amplitude_limit=float(limit),
        peak_force=float(run.peak_force),
        repulsive_force=z.normal.repulsive_force, adhesive_force=z.normal.adhesive_force,
        contact_radius=z.normal.contact_radius(), cohesive_radius=z.normal.cohesive_radius(), md=md,
        onset_force=onset, onset_bracket=tuple(float(v) for v in ramp.onset_bracket),
        onset_repulsive_force=float(onset_state.normal.repulsive_force),
        onset_presliding_displacement=float(onset_state.tangential.displacement_x) - d_a,
        onset_stick_ratio=float(onset_state.tangential.stick_ratio),
        ramp_forces=np.array([s.tangential.force_x for s in keep]),
        ramp_displacements=np.array([s.tangential.displacement_x for s in keep]) - d_a,
        ramp_stick_ratios=np.array([s.tangential.stick_ratio for s in keep]),
        ramp_repulsive_forces=np.array([s.normal.repulsive_force for s in keep]),
        forces=F, displacements=D, stick_ratios=S, repulsive_forces=P, cycles=C, branches=B, turning=T,
        converged=ok, points=_points(C, B, T), loop_energies=loop_energies(F, D, C),
        wall_time=time.perf_counter() - t0, cpu_time=time.process_time() - c0,
        message="; ".join(m for m in (ramp.message, run.message) if m),
    )


def loop_metrics(loop: PaperELoop) -> dict:
    """The scalar measures of one loop (see the module docstring), SI units.

    Parameters
    ----------
    loop : PaperELoop
        A run of :func:`paper_e_loop`.

    Returns
    -------
    dict
        Flat dict of scalars (N, m, J, s or dimensionless), described below.

    Notes
    -----
    Keys: ``repulsive_force``, ``adhesive_force`` (at A), ``md_repulsive_force``,
    ``md_adhesive_force``, ``static_friction`` (F at D = F*), ``static_friction_ratio``
    (F(D) / (mu F0+ of A)), ``static_friction_over_mu_f0`` (F(D) / (mu F0), Paper E Fig. 9's
    peak), ``f0p_over_f0``, ``presliding_displacement`` (delta(D) - delta(A)), the gross-slip
    onset of the first loading ``onset_force`` (bracket midpoint), ``onset_ratio`` (over mu F0+
    of the onset state), ``onset_ratio_start`` (over mu F0+ of A), ``onset_over_mu_f0``,
    ``onset_presliding_displacement`` (delta at the last state with stick minus delta(A)),
    ``mindlin_delta0`` (3 mu F0+ k / (16 a),
    the identical-body Mindlin distance at full slip with F0+ and the numerical a),
    ``stick_A``, ``stick_A1`` (A'), ``stick_D``, ``stick_D1`` (D'), ``stick_H``, ``stick_H1``,
    per cycle c: ``width_c``, ``offset_c`` (centre of the loop), ``asymmetry_c``
    (|delta(+F*) + delta(-F*)| / width), then ``loop_change`` (largest change of delta(+-F*)
    between the last two cycles over the last width), ``stick_branch_asymmetry`` (largest
    |stick(unloading, F) - stick(reloading, -F)| in the last cycle), ``branch_point_asymmetry``
    (largest |delta_un(F) + delta_re(-F) - 2 centre| / width in the last cycle: the loop is
    point-symmetric about its centre), ``half_width`` (of the last loop) beside
    ``mindlin_delta_star`` (Mindlin-Deresiewicz delta at F*: the half width of a Mindlin loop),
    ``loop_energy_c``,
    ``all_converged``, ``cells_across_contact``, ``cells_across_cohesive_zone``,
    ``md_cells_across_cohesive_zone``, ``under_resolved``.
    """
    p = loop.points
    F, D, S = loop.forces, loop.displacements, loop.stick_ratios
    mu, f0p = loop.friction_coefficient, loop.repulsive_force
    out = {
        "work_of_adhesion": loop.work_of_adhesion, "n": loop.n, "dx": loop.dx, "size": loop.size,
        "repulsive_force": f0p, "adhesive_force": loop.adhesive_force,
        "md_repulsive_force": loop.md["repulsive_force"], "md_adhesive_force": loop.md["adhesive_force"],
        "md_contact_radius": loop.md["contact_radius"], "md_cohesive_radius": loop.md["cohesive_radius"],
        "contact_radius": loop.contact_radius, "cohesive_radius": loop.cohesive_radius,
        "peak_force": loop.peak_force, "amplitude": loop.amplitude, "amplitude_requested": loop.amplitude_requested,
        "amplitude_limit": loop.amplitude_limit,
        "static_friction": float(F[p["D"]]), "static_friction_ratio": float(F[p["D"]]) / (mu * f0p),
        "static_friction_over_mu_f0": float(F[p["D"]]) / (mu * loop.normal_force),
        "f0p_over_f0": f0p / loop.normal_force,
        "repulsive_force_at_D": float(loop.repulsive_forces[p["D"]]),
        "static_friction_ratio_at_D": float(F[p["D"]]) / (mu * float(loop.repulsive_forces[p["D"]])),
        "presliding_displacement": float(D[p["D"]] - D[p["A"]]),
        "onset_force": loop.onset_force, "onset_bracket_lo": loop.onset_bracket[0],
        "onset_bracket_hi": loop.onset_bracket[1], "onset_repulsive_force": loop.onset_repulsive_force,
        "onset_ratio": loop.onset_force / (mu * loop.onset_repulsive_force),
        "onset_ratio_start": loop.onset_force / (mu * f0p),
        "onset_over_mu_f0": loop.onset_force / (mu * loop.normal_force),
        "onset_presliding_displacement": loop.onset_presliding_displacement,
        "onset_stick_ratio": loop.onset_stick_ratio,
        "mindlin_delta0": 3.0 * mu * f0p * loop.md["mindlin_k"] / (16.0 * loop.contact_radius),
    }
    for name in ("A", "A'", "D", "D'", "H", "H'", "L", "L'"):
        if name in p:
            out["stick_" + name.replace("'", "1")] = float(S[p[name]])
    n_cyc = int(loop.cycles.max())
    for c in range(1, n_cyc + 1):
        lo, hi = ("H", "L") if c == 1 else (f"H{c}", f"L{c}")
        if lo in p and hi in p:
            dm, dp = float(D[p[lo]]), float(D[p[hi]])
            w = dp - dm
            out[f"width_{c}"] = w
            out[f"offset_{c}"] = 0.5 * (dp + dm)
            out[f"asymmetry_{c}"] = abs(dp + dm) / w if w > 0 else float("nan")
    if n_cyc >= 2:
        a, b = n_cyc - 1, n_cyc
        lo_a, hi_a = ("H", "L") if a == 1 else (f"H{a}", f"L{a}")
        lo_b, hi_b = f"H{b}", f"L{b}"
        if all(k in p for k in (lo_a, hi_a, lo_b, hi_b)):
            ch = max(abs(D[p[lo_b]] - D[p[lo_a]]), abs(D[p[hi_b]] - D[p[hi_a]]))
            out["loop_change"] = float(ch) / out[f"width_{b}"]
    last = int(loop.cycles.max())
    un = np.flatnonzero((loop.cycles == last) & (loop.branches == "unloading"))
    re = np.flatnonzero((loop.cycles == last) & (loop.branches == "reloading"))
    if len(un) and len(un) == len(re):
        # The branches share |F| at mirrored steps: unloading F_k = -(reloading F_k).
        out["stick_branch_asymmetry"] = float(np.max(np.abs(S[un] - S[re])))
        w = out.get(f"width_{last}", float("nan"))
        c = out.get(f"offset_{last}", float("nan"))
        # Point symmetry of the loop about its centre: delta_un(F) - c = -(delta_re(-F) - c).
        out["branch_point_asymmetry"] = float(np.max(np.abs(D[un] + D[re] - 2.0 * c))) / w
    # Mindlin-Deresiewicz for comparison: delta* at F* with P = F0+ and the numerical a; the
    # steady loop's width is 2 delta* there.
    r = min(float(F[p["D"]]) / (mu * f0p), 1.0)
    out["mindlin_delta_star"] = out["mindlin_delta0"] * (1.0 - (1.0 - r) ** (2.0 / 3.0))
    if f"width_{last}" in out:
        out["half_width"] = 0.5 * out[f"width_{last}"]
    for c, e in enumerate(loop.loop_energies, start=1):
        out[f"loop_energy_{c}"] = e
    out.update({
        "all_converged": bool(loop.converged.all()), "cells_across_contact": loop.cells_across_contact,
        "cells_across_cohesive_zone": loop.cells_across_cohesive_zone,
        "md_cells_across_cohesive_zone": loop.md_cells_across_cohesive_zone, "under_resolved": loop.under_resolved,
        "steps": len(F) - 1, "wall_time": loop.wall_time, "cpu_time": loop.cpu_time,
    })
    return out
