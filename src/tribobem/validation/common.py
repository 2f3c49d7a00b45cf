"""Shared pieces of the validation cases: the result row, the tolerance arithmetic, the
silica/rigid-ball pair of Paper A and a solver call that keeps convergence warnings quiet (a
case reports non-convergence through its rows)."""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass
from typing import Callable

from ..errors import ConvergenceWarning
from ..materials import ContactPair, Material
from ..solvers.normal import solve_normal

__all__ = ["ValidationRow", "SILICA", "PAIR", "CaseFunction"]

#: Silica flat against a rigid ball (Paper A 5.1).
SILICA = Material(73e9, 0.17, "silica")
PAIR = ContactPair(SILICA, Material.rigid("ball"))


@dataclass
class ValidationRow:
    """One checked quantity.

    Attributes
    ----------
    case : str
        Case name (one of :data:`CASES`), with its variant, e.g. ``"maugis_dugdale lambda=1"``.
    quantity : str
        What is compared, with the load point.
    reference : float
        Analytic value (SI units).
    computed : float
        Numerical value (SI units).
    rel_error : float
        ``|computed - reference| / scale`` (the scale is ``|reference|`` unless the case says otherwise).
    tolerance : float
        Largest accepted ``rel_error``.
    passed : bool
        ``rel_error <= tolerance``.
    """

    case: str
    quantity: str
    reference: float
    computed: float
    rel_error: float
    tolerance: float
    passed: bool


def _row(case: str, quantity: str, reference: float, computed: float, tolerance: float,
         scale: float | None = None) -> ValidationRow:
    reference, computed = float(reference), float(computed)
    denom = abs(reference) if scale is None else max(abs(reference), float(scale))
    if not math.isfinite(computed):
        err = math.inf
    elif denom > 0:
        err = abs(computed - reference) / denom
    else:
        err = abs(computed - reference)
    return ValidationRow(case, quantity, reference, computed, err, float(tolerance), bool(err <= tolerance))


def _solve(*args, **kw):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ConvergenceWarning)
        return solve_normal(*args, **kw)


#: A case: ``rows(quick) -> list[ValidationRow]`` (quick: small grids; else the full accuracy bars).
CaseFunction = Callable[[bool], list[ValidationRow]]
