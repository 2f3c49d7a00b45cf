"""The result types of every solver, in one place (named fields, SI units).

==================  ===============================================================  =====================================
type                what                                                             returned by
==================  ===============================================================  =====================================
NormalResult        one normal (and adhesive) state: pressure, gap, contact          ``solvers.normal.solve_normal``
TangentialResult    one partial-slip state at a given pressure: shear, slip, stick   ``solvers.tangential.solve_tangential``
CoupledResult       a normal and a tangential state that agree (dissimilar bodies)   ``solvers.coupling.solve_coupled``
LoadCurve           a force-approach curve, loading and unloading, with its jumps    ``solvers.normal_paths.force_curve``
PullOff             the pull-off force, its state and the curve it was taken from    ``solvers.normal_paths.pull_off``
SlipRamp            a tangential ramp to gross slip and its onset                     ``solvers.tangential_paths.tangential_ramp``
CyclePath           the tangential load path of a hysteresis run (values, turnings)  ``solvers.hysteresis.cycle_path``
HysteresisRun       the states of a hysteresis run and its loop energies             ``solvers.hysteresis.hysteresis_loop``
CapillaryResult     a self-consistent capillary state (menisci, forces)              ``solvers.capillary.solve_capillary``
==================  ===============================================================  =====================================
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any, Optional

import numpy as np

from .grid import Grid


@dataclass
class NormalResult:
    """Solution of one normal (possibly adhesive) contact problem.

    Attributes
    ----------
    grid : Grid
    pressure : ndarray
        Normal traction p (Pa), positive compressive, negative tensile (adhesion).
    gap : ndarray
        Gap g = h + u - delta (m), >= 0; exactly 0 on contact nodes.
    displacement : ndarray
        Composite normal displacement u (m).
    contact : ndarray of bool
        Contact nodes (g = 0): p > 0 without adhesion, p > -sigma0 with Dugdale adhesion.
    adhesive : ndarray of bool
        Cohesive-zone nodes outside contact that carry a tensile stress (0 < g < h0).
    force : float
        Total normal force (N), = repulsive_force + adhesive_force.
    approach : float
        Rigid approach delta (m).  For periodic grids it is measured from the state with
        zero mean displacement.  NaN when no node is in contact under force control.
    iterations : int
    residual_history : ndarray
        Relative pressure change per iteration.
    converged : bool
    time : float
        Wall time of the solve (s).
    message : str
        Why the solver stopped.
    control : {"force", "displacement"}
        Whether the force or the approach was prescribed.
    info : dict
        Diagnostics of the solve: ``max_penetration`` (m), the interaction and operator, and
        the solver's own entries (e.g. its counters).
    plastic : ndarray of bool or None
        With a hardness cap: the contact nodes at p = H (plastic); None without a cap.
    plastic_increment : ndarray or None
        With a hardness cap: the overlap of the plastic nodes that this solve added to the
        surface's permanent displacement (m, >= 0); None when no node is plastic.
    plastic_displacement : ndarray or None
        With a hardness cap: the surface's accumulated plastic displacement after this solve
        (m, >= 0; :class:`~tribobem.interactions.hardness.HardnessCap`); None without one.
    """

    grid: Grid
    pressure: np.ndarray
    gap: np.ndarray
    displacement: np.ndarray
    contact: np.ndarray
    adhesive: np.ndarray
    force: float
    approach: float
    iterations: int
    residual_history: np.ndarray
    converged: bool
    time: float
    message: str = ""
    control: str = "force"
    info: dict = field(default_factory=dict)
    plastic: Optional[np.ndarray] = None
    plastic_increment: Optional[np.ndarray] = None
    plastic_displacement: Optional[np.ndarray] = None

    @property
    def residual(self) -> float:
        """Final residual (relative pressure change of the last iteration)."""
        return float(self.residual_history[-1]) if len(self.residual_history) else float("nan")

    @property
    def yielded_area(self) -> float:
        """Area with a permanent (plastic) displacement so far (m^2; 0 without a hardness cap)."""
        d = self.plastic_displacement
        return float(np.count_nonzero(d > 0)) * self.grid.cell_area if d is not None else 0.0

    @property
    def plastic_area(self) -> float:
        """Area of the plastic nodes, p = H (m^2; 0 without a hardness cap)."""
        return float(np.count_nonzero(self.plastic)) * self.grid.cell_area if self.plastic is not None else 0.0

    @property
    def contact_area(self) -> float:
        """Area of the contact nodes (m^2)."""
        return float(np.count_nonzero(self.contact)) * self.grid.cell_area

    @property
    def contact_area_compressive(self) -> float:
        """Contact area carrying p >= 0 (Paper D Eq. 11, A_c^1), m^2."""
        return float(np.count_nonzero(self.contact & (self.pressure >= 0))) * self.grid.cell_area

    @property
    def contact_area_tensile(self) -> float:
        """Contact area carrying -sigma0 < p < 0 (Paper D Eq. 11, A_c^2), m^2."""
        return float(np.count_nonzero(self.contact & (self.pressure < 0))) * self.grid.cell_area

    @property
    def adhesive_area(self) -> float:
        """Area of the cohesive zone outside contact (0 < g < h0), m^2."""
        return float(np.count_nonzero(self.adhesive)) * self.grid.cell_area

    @property
    def contact_fraction(self) -> float:
        """Contact area over the nominal area lx ly (dimensionless)."""
        return self.contact_area / self.grid.area

    @property
    def repulsive_force(self) -> float:
        """F0+ = sum of p > 0 times the cell area (Paper D Eq. 16b), N."""
        return float(np.sum(np.where(self.pressure > 0, self.pressure, 0.0))) * self.grid.cell_area

    @property
    def adhesive_force(self) -> float:
        """F0- = sum of p < 0 times the cell area (Paper D Eq. 16c), N (<= 0)."""
        return float(np.sum(np.where(self.pressure < 0, self.pressure, 0.0))) * self.grid.cell_area

    @property
    def max_pressure(self) -> float:
        """Largest pressure on the grid (Pa)."""
        return float(np.max(self.pressure))

    @property
    def mean_gap(self) -> float:
        """Mean gap over the whole domain (m)."""
        return float(np.mean(self.gap))

    def contact_radius(self) -> float:
        """Equivalent radius sqrt(A_c / pi) of the contact (m); for single round contacts."""
        return float(np.sqrt(self.contact_area / np.pi))

    def cohesive_radius(self) -> float:
        """Equivalent outer radius sqrt((A_c + A_adh) / pi) of the cohesive zone (m)."""
        return float(np.sqrt((self.contact_area + self.adhesive_area) / np.pi))

    def scalars(self) -> dict:
        """The per-step scalars of the summary.json file contract (file-contract)."""
        return {
            "normal_force": self.force,
            "approach": self.approach,
            "contact_area": self.contact_area,
            "repulsive_force": self.repulsive_force,
            "adhesive_force": self.adhesive_force,
            "adhesive_area": self.adhesive_area,
            "contact_area_compressive": self.contact_area_compressive,
            "contact_area_tensile": self.contact_area_tensile,
            "max_pressure": self.max_pressure,
            "mean_gap": self.mean_gap,
            "iterations": self.iterations,
            "residual": self.residual,
            "converged": self.converged,
            "time": self.time,
            **({} if self.plastic is None else {
                "plastic_area": self.plastic_area,
                "yielded_area": self.yielded_area,
                "max_plastic_displacement": (float(self.plastic_displacement.max())
                                             if self.plastic_displacement is not None else 0.0)}),
        }


@dataclass
class TangentialResult:
    """Solution of one tangential (partial-slip) problem at a given pressure.

    Conventions: ``shear`` is the traction q = (q_x, q_y) acting on body 1
    (body 2 receives -q); ``force_x, force_y`` is the tangential force applied to body 2, equal
    to the sum of q times the cell area; ``displacement_x, displacement_y`` (delta) is the rigid
    displacement of body 2 relative to body 1; ``slip`` is s = u1 - u2 - delta (m), the relative
    tangential displacement (total mode) or its increment since the previous step (incremental
    mode).  On slip nodes |q| = mu p and q opposes the slip; on stick nodes |q| < mu p and the
    slip (increment) vanishes.  Shear acts only where p > 0 (compressive contact, Paper D).

    Attributes
    ----------
    grid : Grid
    shear : ndarray, shape (2, nx, ny)
        q_x, q_y on body 1 (Pa).
    slip : ndarray, shape (2, nx, ny)
        Slip s_x, s_y (m) on every node (meaningful on the compressive contact).
    relative_displacement : ndarray, shape (2, nx, ny)
        Total relative tangential displacement u1 - u2 - delta (m) of every node: the
        reference of the next step in incremental mode.
    contact : ndarray of bool
        Compressive contact (p > 0): where shear may act.
    stick : ndarray of bool
        Stick nodes (|q| < mu p, zero slip).
    force_x, force_y : float
        Tangential force on body 2 (N).
    displacement_x, displacement_y : float
        Rigid tangential displacement of body 2 relative to body 1 (m).
    friction_coefficient : float
    mode : {"total", "incremental"}
    control : {"force", "displacement"}
    iterations : int
    residual_history : ndarray
        max(relative traction change, complementarity residual) per iteration.
    converged : bool
    gross_slip : bool
        True when no node sticks (gross sliding).
    time : float
    message : str
    info : dict
    """

    grid: Grid
    shear: np.ndarray
    slip: np.ndarray
    relative_displacement: np.ndarray
    contact: np.ndarray
    stick: np.ndarray
    force_x: float
    force_y: float
    displacement_x: float
    displacement_y: float
    friction_coefficient: float
    mode: str
    control: str
    iterations: int
    residual_history: np.ndarray
    converged: bool
    gross_slip: bool
    time: float
    message: str = ""
    info: dict = field(default_factory=dict)

    @property
    def residual(self) -> float:
        """Final residual (the last entry of ``residual_history``; NaN when empty)."""
        return float(self.residual_history[-1]) if len(self.residual_history) else float("nan")

    @property
    def slip_mask(self) -> np.ndarray:
        """Slip nodes: compressive contact that does not stick."""
        return self.contact & ~self.stick

    @property
    def stick_area(self) -> float:
        """Area of the stick nodes (m^2)."""
        return float(np.count_nonzero(self.stick)) * self.grid.cell_area

    @property
    def slip_area(self) -> float:
        """Area of the slip nodes (m^2)."""
        return float(np.count_nonzero(self.slip_mask)) * self.grid.cell_area

    @property
    def contact_area(self) -> float:
        """Area of the compressive contact (p > 0), m^2."""
        return float(np.count_nonzero(self.contact)) * self.grid.cell_area

    @property
    def stick_ratio(self) -> float:
        """A_stick / A_contact (compressive contact, file-contract); 0 without contact."""
        n = np.count_nonzero(self.contact)
        return float(np.count_nonzero(self.stick)) / n if n else 0.0

    def scalars(self) -> dict:
        """The per-step tangential scalars of the summary.json file contract (file-contract)."""
        return {
            "tangential_force_x": self.force_x,
            "tangential_force_y": self.force_y,
            "displacement_x": self.displacement_x,
            "displacement_y": self.displacement_y,
            "stick_area": self.stick_area,
            "slip_area": self.slip_area,
            "stick_ratio": self.stick_ratio,
            "tangential_iterations": self.iterations,
            "tangential_residual": self.residual,
            "tangential_converged": self.converged,
            "gross_slip": self.gross_slip,
        }


@dataclass
class CoupledResult:
    """One step of the normal-tangential coupling loop (Paper D Fig. 2).

    Attributes
    ----------
    normal : NormalResult
        The (adhesive) normal solution, with the shear-induced normal displacement in its gap.
    tangential : TangentialResult
    coupling_iterations : int
        Outer (Panagiotopoulos) iterations.
    coupling_history : ndarray
        Relative pressure change per outer iteration.
    converged : bool
        Both levels and the outer loop converged (and, with capillarity, the meniscus islands).
    message : str
    capillary : CapillaryResult or None
        With a capillary model (humid friction): the self-consistent capillary state of the last
        normal solve (forces by origin, islands, wetted area); None otherwise.
    """

    normal: NormalResult
    tangential: TangentialResult
    coupling_iterations: int
    coupling_history: np.ndarray
    converged: bool
    message: str = ""
    capillary: object = field(default=None, repr=False)

    def scalars(self) -> dict:
        """The per-step scalars of the summary.json file contract (file-contract).

        Returns
        -------
        dict
            The normal and tangential scalars, the normal solve's ``converged`` renamed
            ``normal_converged``, ``coupling_iterations``, and ``converged`` of the whole step.
        """
        row = self.normal.scalars()
        row["normal_converged"] = row.pop("converged")
        row.update(self.tangential.scalars())
        row["coupling_iterations"] = self.coupling_iterations
        cap = self.capillary
        if cap is not None:
            row.update({
                "normal_force": float(cap.total_force),
                "capillary_force": float(cap.capillary_force),
                "solid_solid_force": float(cap.solid_solid_force),
                "water_solid_force": float(cap.water_solid_force),
                "adhesive_force_total": float(cap.capillary_force + cap.solid_solid_force + cap.water_solid_force),
                "wetted_area": float(cap.wetted_area),
                "island_count": int(cap.island_count),
                "kelvin_radius": float(cap.kelvin_radius),
                "capillary_pressure": float(cap.capillary_pressure),
                "island_iterations": int(cap.outer_iterations),
                "islands_converged": bool(cap.converged),
            })
        row["converged"] = self.converged
        return row


@dataclass
class LoadCurve:
    """A force-approach curve with its loading and unloading branches.

    Attributes
    ----------
    control : {"displacement", "force"}
    branch : ndarray of str
        "loading" or "unloading" for each point.
    approach, force : ndarray
        Rigid approach (m) and total normal force (N) of each point.
    contact_area, adhesive_area : ndarray
        m^2.
    repulsive_force, adhesive_force : ndarray
        F0+ and F0- (N).
    iterations : ndarray of int
    converged : ndarray of bool
    jumps : list of dict
        ``{"index", "branch", "kind" ("jump-in" | "jump-off"), "approach", "force"}``.
    results : list of NormalResult
        Full fields per point (only when ``keep_fields=True``; else empty).
    steps : list of dict
        The scalar summary of each point (:meth:`NormalResult.scalars` plus ``"branch"``; SI units).
    """

    control: str
    branch: np.ndarray
    approach: np.ndarray
    force: np.ndarray
    contact_area: np.ndarray
    adhesive_area: np.ndarray
    repulsive_force: np.ndarray
    adhesive_force: np.ndarray
    iterations: np.ndarray
    converged: np.ndarray
    jumps: list = field(default_factory=list)
    results: list = field(default_factory=list)
    steps: list = field(default_factory=list)

    @property
    def pull_off_force(self) -> float:
        """Most negative force on the curve (N); 0 if the curve has no tensile point."""
        ok = self.converged
        if not np.any(ok):
            return float("nan")
        return float(min(np.min(self.force[ok]), 0.0))

    @property
    def pull_off_approach(self) -> float:
        """Approach (m) of the converged point with the most negative force; NaN if no point converged.

        Unlike :attr:`pull_off_force` it is not clipped at zero: without a tensile point it is the
        approach of the smallest (compressive) force.
        """
        ok = np.where(self.converged)[0]
        if not len(ok):
            return float("nan")
        return float(self.approach[ok[np.argmin(self.force[ok])]])

    def branch_mask(self, name: str) -> np.ndarray:
        """Which points of the curve lie on a branch.

        Parameters
        ----------
        name : {"loading", "unloading"}
            The branch.

        Returns
        -------
        ndarray of bool
            True for each point of branch ``name`` (same length as :attr:`approach`; converged or not).
        """
        return self.branch == name

    @property
    def hysteresis_energy(self) -> float:
        """Energy (J) lost over the load cycle: the area between the loading and unloading
        force-approach branches, integral of (F_loading - F_unloading) d(delta) over the
        approaches both branches cover (displacement control)."""
        lo, un = self.branch_mask("loading") & self.converged, self.branch_mask("unloading") & self.converged
        if lo.sum() < 2 or un.sum() < 2:
            return float("nan")
        dl, fl = self.approach[lo], self.force[lo]
        du, fu = self.approach[un], self.force[un]
        order_l, order_u = np.argsort(dl), np.argsort(du)
        dl, fl, du, fu = dl[order_l], fl[order_l], du[order_u], fu[order_u]
        grid = np.union1d(dl, du)
        grid = grid[(grid >= max(dl[0], du[0])) & (grid <= min(dl[-1], du[-1]))]
        if len(grid) < 2:
            return float("nan")
        diff = np.interp(grid, dl, fl) - np.interp(grid, du, fu)
        return float(np.sum(0.5 * (diff[1:] + diff[:-1]) * np.diff(grid)))

    def scalars(self) -> list[dict]:
        """One summary.json step entry per point (file-contract keys)."""
        return self.steps


@dataclass
class PullOff:
    """Pull-off of an adhesive contact.

    Attributes
    ----------
    force : float
        Pull-off force (N), the most negative force on the unloading curve (negative).
    approach : float
        Approach at pull-off (m).
    curve : LoadCurve
        The unloading curve it was taken from.
    state : NormalResult
        The solution at pull-off (pressure, gap, contact and cohesive zone).
    preload_state : NormalResult
        The state the unloading started from (its ``force`` is the preload actually applied).
    notes : list of str
        What the start had to give way to (e.g. a periodic cell in full contact below the
        requested preload), for the run's warnings.
    """

    force: float
    approach: float
    curve: LoadCurve
    state: NormalResult | None = None
    preload_state: NormalResult | None = None
    notes: list = field(default_factory=list)

    @property
    def preload(self) -> float:
        """The force (N) of the state the unloading started from."""
        return float(self.preload_state.force) if self.preload_state is not None else math.nan


@dataclass
class SlipRamp:
    """A tangential ramp at a fixed normal load.

    Attributes
    ----------
    steps : list of CoupledResult
        One per solved value of the ramp (up to and including the first gross-slip step).
    values : list of float
        The ramp values (N for force control, m for displacement control) of ``steps``.
    control : {"force", "displacement"}
    direction : ndarray
        Unit vector of the ramp.
    gross_slip : bool
        The ramp reached gross slip.
    onset : float
        Tangential force (N) at the gross-slip onset (NaN when not reached), the midpoint of the
        final bracket.
    onset_bracket : tuple of float
        (last value with stick, first value without) after refinement.
    onset_ratio : float
        onset / (mu F0+) with F0+ of the state at the onset.
    presliding_displacement : float
        delta along the ramp at the onset (last state with stick) minus delta at F_t = 0 (m).
    max_force : float
        With a force beyond what the contact carries: the largest force with an equilibrium.
    message : str
    """

    steps: list
    values: list
    control: str
    direction: np.ndarray
    gross_slip: bool = False
    onset: float = float("nan")
    onset_bracket: tuple = (float("nan"), float("nan"))
    onset_ratio: float = float("nan")
    presliding_displacement: float = float("nan")
    onset_state: CoupledResult | None = None
    zero_state: CoupledResult | None = None
    max_force: float = float("nan")
    message: str = ""
    refine_steps: int = 0
    extra: dict = field(default_factory=dict)


@dataclass
class CyclePath:
    """Values of a cyclic tangential path.

    Attributes
    ----------
    values : ndarray
        Force (N) or displacement (m) along the path direction, one per step (not the start).
    cycle : ndarray of int
        0 for the initial loading, then 1..cycles.
    branch : ndarray of str
        "loading" (0 -> +), "unloading" (+ -> -), "reloading" (- -> +).
    turning : ndarray of bool
        True at a turning point (the last step of a branch).
    control : {"force", "displacement"}
    """

    values: np.ndarray
    cycle: np.ndarray
    branch: np.ndarray
    turning: np.ndarray
    control: str


@dataclass
class HysteresisRun:
    """The states of a hysteresis run.

    Attributes
    ----------
    start : CoupledResult
        The one-shot state at F_t = 0 (Paper E point A).
    steps : list of CoupledResult
        One per value of ``path`` (fewer if the run stopped).
    path : CyclePath
    direction : ndarray
        Unit vector of the tangential load.
    peak_force : float
        F* (N) for force control; NaN for displacement control.
    failed : list of int
        Steps whose solve did not converge (the run goes on; flagged in summary and report).
    message : str
    dissipation : list of ndarray
        Frictional dissipation per cycle (J/m^2): sum over the cycle's steps of q . ds.
    accumulated_slip : list of ndarray
        Accumulated slip length per cycle (m): sum of |ds|.
    """

    start: object
    steps: list
    path: CyclePath
    direction: np.ndarray
    peak_force: float = float("nan")
    failed: list = field(default_factory=list)
    message: str = ""
    dissipation: list = field(default_factory=list)
    accumulated_slip: list = field(default_factory=list)
    offsets: list = field(default_factory=list)


@dataclass
class CapillaryResult:
    """A self-consistent capillary contact state (SI units; forces negative when tensile).

    Attributes
    ----------
    normal : NormalResult
        The last normal solve (pressure, gap, contact, ...).
    islands : Islands
        The meniscus islands whose law the last solve used.
    capillary_force, solid_solid_force, water_solid_force : float
        F_cap (dP_cap over the wetted area), F_ss (Dugdale zone outside the contact), F_ws
        (water-filled and air-gap van der Waals), N.
    contact_force : float
        Sum of the pressure on the contact nodes (N); NaN for rigid bodies in contact.
    repulsive_force : float
        F0+, its compressive part (N); NaN for rigid bodies in contact.
    total_force : float
        contact + capillary + solid-solid + water-solid (N): the applied normal force.
    contact_area, wetted_area : float
        Contact area and meniscus area outside the contact carrying dP_cap (m^2).
    island_count : int
        Number of ACTIVE meniscus islands.
    outer_iterations : int
        Normal solves of the island fixed point.
    converged : bool
        The island mask repeated and the last normal solve converged.
    message : str
    kelvin_radius, capillary_pressure : float
        r_k (m) and the APPLIED capillary pressure (Pa, after the contribution coefficient).
    interaction : CapillaryInteraction
        The stress law of the last solve.
    history : list of int
        Active nodes after each outer iteration.
    time : float
        Wall time (s).
    """

    normal: NormalResult
    islands: Any  # tribobem.interactions.menisci.Islands (a layer above this module)
    capillary_force: float
    solid_solid_force: float
    water_solid_force: float
    contact_force: float
    repulsive_force: float
    total_force: float
    contact_area: float
    wetted_area: float
    island_count: int
    outer_iterations: int
    converged: bool
    message: str
    kelvin_radius: float
    capillary_pressure: float
    interaction: Any = field(repr=False, default=None)  # tribobem.interactions.capillary.CapillaryInteraction
    history: list = field(default_factory=list)
    time: float = 0.0

    def scalars(self) -> dict:
        """Per-step scalars (file-contract keys), the normal solve's plus the capillary ones."""
        d = self.normal.scalars()
        d.update({
            "normal_force": self.total_force,
            "repulsive_force": self.repulsive_force,
            "capillary_force": self.capillary_force,
            "solid_solid_force": self.solid_solid_force,
            "water_solid_force": self.water_solid_force,
            "wetted_area": self.wetted_area,
            "contact_area": self.contact_area,
            "island_count": self.island_count,
            "kelvin_radius": self.kelvin_radius,
            "capillary_pressure": self.capillary_pressure,
            "outer_iterations": self.outer_iterations,
            "converged": self.converged,
        })
        return d
