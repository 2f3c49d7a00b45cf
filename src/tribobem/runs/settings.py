"""The solver settings of a run: one object, built once from ``[solver]`` and the kind.

A scenario's ``[solver] tolerance`` is not the tolerance of every solve: the tangential kinds
floor it for their tangential solves, hold their coupling loop at a fixed tolerance, bracket the
gross-slip onset to a fixed width, and the humid runs floor the films' levelling tolerance.  Each
of those rules lives here, once, as a constant with the measurement behind it, and
:class:`SolverSettings` holds the values they give for one run: the runner hands them to every
solver call (:meth:`SolverSettings.normal_kw`, :meth:`SolverSettings.coupled_kw`, ...) and
summary.json records them (``solver``: :meth:`SolverSettings.summary`).  No runner reads a
tolerance from another kind's module, and none writes what ``method = "auto"`` stood for into
the built problem: the settings say it.

Inside one coupled step :func:`~tribobem.solvers.coupling.solve_coupled` loosens its early
passes further (:data:`~tribobem.solvers.coupling.PREDICTOR_TOL`,
:data:`~tribobem.solvers.coupling.INEXACT_TANGENTIAL`,
:data:`~tribobem.solvers.coupling.INEXACT_NORMAL`): those are the solver's own, read here only to
be recorded (the final pass of every step is at the settings' tolerances).
"""

from __future__ import annotations

from dataclasses import asdict, dataclass
from typing import Optional

from ..solvers import coupling as _coupling
from .common import normal_method as _normal_method

__all__ = ["SolverSettings", "TANGENTIAL_TOLERANCE", "COUPLING_TOLERANCE", "ONSET_TOLERANCE"]

#: Floor of the tangential solver's tolerance (traction change and complementarity residual) in
#: the tangential kinds: their tangential solves use max([solver] tolerance, this).  Measured on
#: the Paper D ramp (96^2): the onset ratio and the pre-sliding displacement agree to 5 and 6
#: digits with 1e-8 / 1e-7, in 0.6x the time; on Cattaneo-Mindlin (256^2) the stick area is
#: exact (vs a 1e-11 reference) from 1e-6 on.
TANGENTIAL_TOLERANCE = 1e-7
#: Tolerance of the tangential kinds' coupling loop (relative pressure change), whatever
#: ``[solver] tolerance`` is (same measurement as :data:`TANGENTIAL_TOLERANCE`).
COUPLING_TOLERANCE = 1e-6
#: Bisection of the gross-slip onset (kind ``partial_slip``): bracket width relative to mu F0+
#: (file-contract).
ONSET_TOLERANCE = 1e-3
#: Floor of the films' levelling tolerance in the humid runs: below it the levelling does not
#: converge (:func:`~tribobem.interactions.films.film_thickness`).
FILM_TOLERANCE_FLOOR = 1e-12

#: Kinds whose steps are solved by the normal-tangential coupling loop
#: (:func:`~tribobem.solvers.coupling.solve_coupled`): their settings carry the tangential and
#: coupling tolerances and the loop's own inexact ones.
COUPLED_KINDS = frozenset({"partial_slip", "hysteresis"})
#: Kinds that bracket the gross-slip onset (:func:`~tribobem.solvers.tangential_paths.tangential_ramp`).
ONSET_KINDS = frozenset({"partial_slip"})
#: Kinds whose dry path takes no normal solver: :func:`~tribobem.solvers.normal_paths.pull_off` solves
#: its Dugdale states with Polonsky-Keer (NormCG only as its last resort) and the kind refuses
#: ``method = "normcg"``; with ``[humidity]`` the kind's solves take the method like the others.
OWN_METHOD_KINDS = frozenset({"pulloff"})


@dataclass(frozen=True)
class SolverSettings:
    """The effective solver settings of one run (module docstring).

    Attributes
    ----------
    kind : str
        The run kind they were built for.
    tolerance : float
        ``[solver] tolerance``: the relative tolerance of the normal solves (dimensionless).
    max_iterations : int
        ``[solver] max_iterations``: per solver call.
    method : str
        ``[solver] method`` as given (``"auto"``, ``"polonsky_keer"`` or ``"normcg"``).
    precision : str or None
        ``[solver] precision`` (``"auto"``, ``"single"`` or ``"double"``): the arithmetic of the
        NormCG solves of kind ``normal`` (:func:`~tribobem.solvers.normal_cg.solve_normal_cg`);
        None for the other kinds, whose solves run in double precision.
    normal_method : str or None
        The normal solver ``method`` stands for (``"polonsky_keer"`` or ``"normcg"``;
        :func:`tribobem.solvers.normal.resolve_method`); None where the run's normal solves take
        no method (the dry pull-off, :data:`OWN_METHOD_KINDS`).
    tangential_tolerance : float or None
        The coupled kinds' tangential solver tolerance, max(``tolerance``,
        :data:`TANGENTIAL_TOLERANCE`); None for the other kinds.
    coupling_tolerance : float or None
        The coupled kinds' coupling-loop tolerance (relative pressure change),
        :data:`COUPLING_TOLERANCE`; None for the other kinds.
    onset_tolerance : float or None
        Width of the gross-slip onset bracket relative to mu F0+, :data:`ONSET_TOLERANCE`
        (:data:`ONSET_KINDS`); None for the other kinds.
    film_tolerance : float or None
        The films' levelling tolerance with ``[humidity]``, max(``tolerance``,
        :data:`FILM_TOLERANCE_FLOOR`); None without.
    """

    kind: str
    tolerance: float
    max_iterations: int
    method: str = "auto"
    normal_method: Optional[str] = "polonsky_keer"
    precision: Optional[str] = None
    tangential_tolerance: Optional[float] = None
    coupling_tolerance: Optional[float] = None
    onset_tolerance: Optional[float] = None
    film_tolerance: Optional[float] = None

    @classmethod
    def from_scenario(cls, sc, kind: Optional[str] = None) -> "SolverSettings":
        """The settings of a scenario's run: its ``[solver]`` section and the rules of its kind.

        Parameters
        ----------
        sc : Scenario
            The validated scenario.
        kind : str, optional
            The run kind (default: the scenario's ``kind``).

        Returns
        -------
        SolverSettings
        """
        kind = sc.kind if kind is None else kind
        solver = sc.solver
        tol = solver.tolerance
        coupled = kind in COUPLED_KINDS
        takes_method = kind not in OWN_METHOD_KINDS or sc.humidity is not None
        return cls(
            kind=kind, tolerance=tol, max_iterations=solver.max_iterations, method=solver.method,
            precision=solver.precision if kind == "normal" else None,
            normal_method=_normal_method(sc) if takes_method else None,
            tangential_tolerance=max(tol, TANGENTIAL_TOLERANCE) if coupled else None,
            coupling_tolerance=COUPLING_TOLERANCE if coupled else None,
            onset_tolerance=ONSET_TOLERANCE if kind in ONSET_KINDS else None,
            film_tolerance=max(tol, FILM_TOLERANCE_FLOOR) if sc.humidity is not None else None,
        )

    # ------------------------------------------------------------------ the coupling loop's own
    @property
    def coupled(self) -> bool:
        """Whether the run's steps go through the coupling loop (:data:`COUPLED_KINDS`)."""
        return self.coupling_tolerance is not None

    @property
    def predictor_tolerance(self) -> Optional[float]:
        """Tolerance of the coupling loop's predictor tangential solve, max(tangential tolerance,
        :data:`~tribobem.solvers.coupling.PREDICTOR_TOL`) (read-only: the solver's own); None
        outside the coupled kinds."""
        return max(self.tangential_tolerance, _coupling.PREDICTOR_TOL) if self.coupled else None

    @property
    def inexact_tangential_tolerance(self) -> Optional[float]:
        """Loosest tangential tolerance of the coupling loop's early passes,
        :data:`~tribobem.solvers.coupling.INEXACT_TANGENTIAL` (read-only; each early pass uses
        max(tangential tolerance, min(this, 1e-2 x the last pressure change))); None outside the
        coupled kinds."""
        return _coupling.INEXACT_TANGENTIAL if self.coupled else None

    @property
    def inexact_normal_tolerance(self) -> Optional[float]:
        """Loosest normal tolerance of the coupling loop's early passes,
        :data:`~tribobem.solvers.coupling.INEXACT_NORMAL` (read-only, as
        :attr:`inexact_tangential_tolerance`); None outside the coupled kinds."""
        return _coupling.INEXACT_NORMAL if self.coupled else None

    # ------------------------------------------------------------------ keyword arguments
    def path_kw(self) -> dict:
        """``tol`` and ``max_iterations``: the keywords of a solve that picks its own normal
        solver (:func:`~tribobem.solvers.normal_paths.pull_off`,
        :func:`~tribobem.solvers.capillary.solve_capillary`, whose solver comes with its options)."""
        return {"tol": self.tolerance, "max_iterations": self.max_iterations}

    def normal_kw(self) -> dict:
        """``tol``, ``max_iterations`` and ``method``: the keywords of
        :func:`~tribobem.solvers.normal.solve_normal` and the normal load paths."""
        return {**self.path_kw(), "method": self._method()}

    def normal_run_kw(self) -> dict:
        """:meth:`normal_kw` and ``precision``: the keywords of kind ``normal``'s solves and load
        curves (Polonsky-Keer, the method of adhesive runs, keeps double precision)."""
        precision = self.precision or "double"
        if self._method() != "normcg" and precision == "single":
            precision = "auto"  # (the schema refuses single with Polonsky-Keer)
        return {**self.normal_kw(), "precision": precision}

    def coupled_kw(self) -> dict:
        """``tol``, ``max_iterations``, ``tangential_tol``, ``coupling_tol`` and ``normal_method``:
        the keywords of :func:`~tribobem.solvers.coupling.solve_coupled` and the tangential paths
        built on it (``tangential_ramp``, ``normal_path``, ``hysteresis_loop``)."""
        if not self.coupled:
            raise ValueError(f"kind {self.kind!r} does not solve the coupled problem: no tangential or coupling "
                             "tolerance")
        return {**self.path_kw(), "tangential_tol": self.tangential_tolerance,
                "coupling_tol": self.coupling_tolerance, "normal_method": self._method()}

    def _method(self) -> str:
        if self.normal_method is None:
            raise ValueError(f"kind {self.kind!r} takes no normal solver here (its path picks its own)")
        return self.normal_method

    # ------------------------------------------------------------------ summary.json
    def summary(self) -> dict:
        """summary.json ``solver``: the effective values of this run (those that apply).

        Returns
        -------
        dict
            ``tolerance``, ``max_iterations``, ``method`` (as given) and, where they apply,
            ``normal_method``, ``tangential_tolerance``, ``coupling_tolerance``,
            ``onset_tolerance``, ``film_tolerance``, and the coupling loop's own
            ``predictor_tolerance``, ``inexact_tangential_tolerance`` and
            ``inexact_normal_tolerance`` (all tolerances dimensionless).
        """
        out = {k: v for k, v in asdict(self).items() if k != "kind" and v is not None}
        if self.coupled:
            out.update(predictor_tolerance=self.predictor_tolerance,
                       inexact_tangential_tolerance=self.inexact_tangential_tolerance,
                       inexact_normal_tolerance=self.inexact_normal_tolerance)
        return out
