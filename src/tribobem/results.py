"""Result objects with named fields (SI units)."""

from __future__ import annotations

from dataclasses import dataclass, field

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

    @property
    def residual(self) -> float:
        """Final residual (relative pressure change of the last iteration)."""
        return float(self.residual_history[-1]) if len(self.residual_history) else float("nan")

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
