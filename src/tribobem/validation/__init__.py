"""Validation of the solvers against analytic references (``tribobem validate``).

Every case solves small, self-contained problems with the library's own operators and solvers
and compares them with :mod:`tribobem.analytic`.  :func:`run_validation` returns one
:class:`ValidationRow` per checked quantity; the CLI prints them as a table.

One module per physics, each with a dict ``CASES`` (name -> ``rows(quick)``) and the case
descriptions in its docstring; this package assembles them into one registry (:data:`CASES`,
in the order they run):

:mod:`~tribobem.validation.normal`
    ``hertz``, ``westergaard``, ``bisinusoidal_small_load``, ``bisinusoidal_near_full``,
    ``force_balance``, ``periodic_vs_free``.
:mod:`~tribobem.validation.adhesion`
    ``maugis_dugdale``, ``md_pull_off``, ``md_grid_band``, ``md_step``, ``md_solver_agreement``,
    ``exponential``, ``guduru``.
:mod:`~tribobem.validation.studies`
    ``bisinusoidal_resolution`` (the published 625-case table of Paper A section 6).
:mod:`~tribobem.validation.burl`
    ``rounded_punch``, ``flat_punch``, ``burl_stiffness``, ``kendall``, ``texture_cell``.
:mod:`~tribobem.validation.two_scale`
    ``two_scale_smooth``, ``two_scale_layer``, ``two_scale_whole_burl``, ``two_scale_partial_slip``,
    ``two_scale_hysteresis``, ``two_scale_humid``.
:mod:`~tribobem.validation.materials`
    ``hardness_hertz``, ``hardness_sphere``, ``hardness_rigid_plastic``, ``hardness_pulloff``,
    ``subsurface_hertz``, ``subsurface_sliding``, ``subsurface_equilibrium``.

Three tiers: ``quick`` (small grids), ``ci`` (the gating tier of CI: the cases that protect
published numbers at a resolution that still discriminates and fits CI's time budget per
physics, :mod:`~tribobem.validation.gate`) and ``full`` (every accuracy bar).  Their run times
are in benchmarks/README.md.

Shared pieces (:class:`ValidationRow`, the row arithmetic, the silica/rigid-ball pair) live in
:mod:`~tribobem.validation.common`.  A new physics is a new module and one line in
:data:`PHYSICS`.
"""

from __future__ import annotations

from importlib import import_module
from typing import Callable, Iterable

from ..errors import InputError
from .adhesion import (
    MD_LAMBDAS,
    guduru_compare,
    guduru_extrema,
    guduru_problem,
    guduru_rows,
    maugis_dugdale_problem,
    maugis_dugdale_rows,
    md_pull_off,
    md_pull_off_scan,
)
from .common import PAIR, SILICA, CaseFunction, ValidationRow, _row, _solve  # noqa: F401 (re-exported)
from .gate import gate_rows

__all__ = [
    "CASES", "PHYSICS", "PHYSICS_CASES", "LEVELS", "ValidationRow", "run_validation",
    "maugis_dugdale_problem", "md_pull_off_scan", "maugis_dugdale_rows",
    "guduru_problem", "guduru_rows", "guduru_compare",
    "guduru_extrema", "md_pull_off", "MD_LAMBDAS",
]

#: The physics modules, in the order their cases run: one line per physics.
PHYSICS = (
    "normal",      # hertz, westergaard, bisinusoidal_small_load, bisinusoidal_near_full, force_balance, periodic_vs_free
    "adhesion",    # maugis_dugdale, md_pull_off, md_grid_band, md_step, md_solver_agreement, exponential, guduru
    "tangential",  # cattaneo_mindlin, cattaneo_periodic, mindlin_stiffness, coupling_sign, spence
    "hysteresis",  # mindlin_deresiewicz
    "paper_e",     # paper_e (dissimilar adhesive hysteresis, Paper E 3.2)
    "studies",     # bisinusoidal_resolution (the published Paper A section 6 table)
    "capillary",   # sphere_flat_capillary, capillary_force_balance (Papers B, C)
    "humid_friction",  # humid_dry_limit, humid_uncoupled_onset, humid_coupled_onset, humid_force_balance,
                       # humid_loop_energy (partial_slip and hysteresis with [humidity])
    "burl",        # rounded_punch, flat_punch, burl_stiffness, kendall, texture_cell (burls and textures)
    "two_scale",   # two_scale_smooth, _layer, _whole_burl, _partial_slip, _hysteresis, _humid
    "materials",   # hardness_hertz, _sphere, _rigid_plastic, _pulloff; subsurface_hertz, _sliding, _equilibrium
)


def _assemble() -> tuple[dict[str, CaseFunction], dict[str, tuple[str, ...]]]:
    cases: dict[str, CaseFunction] = {}
    by_physics: dict[str, tuple[str, ...]] = {}
    for physics in PHYSICS:
        module_cases = import_module(f"{__name__}.{physics}").CASES
        for name, fn in module_cases.items():
            if name in cases:
                raise RuntimeError(f"validation case {name!r} is defined twice (validation.{physics})")
            cases[name] = fn
        by_physics[physics] = tuple(module_cases)
    return cases, by_physics


#: name -> case function ``rows(quick) -> list[ValidationRow]``, in the order they run;
#: physics -> the names of its cases.
CASE_FUNCTIONS, PHYSICS_CASES = _assemble()
_RUNNERS = CASE_FUNCTIONS  # the name of the single-module version

#: The validation cases, in the order they run.
CASES = tuple(CASE_FUNCTIONS)

#: The tiers of :func:`run_validation`.
LEVELS = ("quick", "ci", "full")


def run_validation(quick: bool = True, cases: Iterable[str] | None = None,
                   progress: Callable[[int, int, str], None] | None = None, *, level: str | None = None,
                   physics: Iterable[str] | None = None) -> list[ValidationRow]:
    """Run validation cases and return their rows.

    Parameters
    ----------
    quick : bool
        Small grids or the full accuracy bars of the specification (512^2 Hertz, all six
        Maugis parameters up to a 1248^2 grid for lambda = 5, Guduru at 192^2: by far the
        costliest tier).
    cases : iterable of str, optional
        Names from :data:`CASES`; all by default.
    progress : callable, optional
        Called as ``progress(done, total, case)`` after each case.
    level : {"quick", "ci", "full"}, optional
        The tier; overrides ``quick``.  ``"ci"``: the gating tier of CI
        (:mod:`tribobem.validation.gate`: published numbers at a resolution that fits CI's time
        budget per physics).
    physics : iterable of str, optional
        Only the cases of these physics modules (names from :data:`PHYSICS`); combined with
        ``cases`` the two selections intersect.

    Returns
    -------
    list of ValidationRow
        The rows of every selected case, in the order of :data:`CASES`.

    Raises
    ------
    InputError
        For an unknown case name, physics or level.
    """
    if level is None:
        level = "quick" if quick else "full"
    if level not in LEVELS:
        raise InputError("validate.level", f"must be one of {', '.join(LEVELS)}, got {level!r}")
    names = list(CASES) if cases is None else list(cases)
    unknown = [c for c in names if c not in CASE_FUNCTIONS]
    if unknown:
        raise InputError("validate.cases", f"unknown case(s) {', '.join(map(repr, unknown))}; "
                                           f"choose among {', '.join(CASES)}")
    if physics is not None:
        physics = list(physics)
        bad = [p for p in physics if p not in PHYSICS_CASES]
        if bad:
            raise InputError("validate.physics", f"unknown physics {', '.join(map(repr, bad))}; "
                                                 f"choose among {', '.join(PHYSICS)}")
        selected = {c for p in physics for c in PHYSICS_CASES[p]}
        names = [c for c in names if c in selected]
    rows: list[ValidationRow] = []
    for k, name in enumerate(names):
        if level == "ci":

            rows += gate_rows(name, CASE_FUNCTIONS[name])
        else:
            rows += CASE_FUNCTIONS[name](level == "quick")
        if progress:
            progress(k + 1, len(names), name)
    return rows
