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
        """The per-step scalars of the summary.json file contract (SPEC 9.1)."""
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
