"""Exceptions and warnings raised by tribobem.

Every error names the offending field and, where it applies, the allowed range, so a
user can fix a scenario file without reading the source.
"""

from __future__ import annotations


class TribobemError(Exception):
    """Base class of all tribobem errors."""


class InputError(TribobemError, ValueError):
    """Invalid user input (a parameter, a topography, a scenario key).

    Parameters
    ----------
    field : str
        Name of the offending input (e.g. ``"body1.nu"``).
    message : str
        What is wrong and what is allowed.
    """

    def __init__(self, field: str, message: str):
        self.field = field
        self.reason = message
        super().__init__(f"{field}: {message}")


class TopographyError(InputError):
    """A measured topography could not be read or contains unusable data."""


class MemoryBudgetError(TribobemError, MemoryError):
    """The requested grid would not fit in memory (estimated before allocating)."""


class ConvergenceError(TribobemError, RuntimeError):
    """Raised instead of :class:`ConvergenceWarning` when the caller asked for strictness."""


class ConvergenceWarning(UserWarning):
    """A solver stopped before reaching its tolerance; its result has ``converged=False``."""


class ResultWarning(UserWarning):
    """A result check fired: a number of the run that the grid or the model cannot back.

    :func:`tribobem.run_scenario` issues one per check that fired (with the check's own
    subclass, :data:`RESULT_WARNINGS`); the same lines are in ``RunResult.warnings`` and
    summary.json ``warnings``.  ``warnings.simplefilter("error", ResultWarning)`` turns them
    into exceptions; a subclass filters one check only.
    """

    #: The check's name (the prefix of its message).
    check = ""


class EdgeWarning(ResultWarning):
    """The contact or the cohesive zone touches the edge of the free-boundary domain."""

    check = "edge"


class CohesiveZoneWarning(ResultWarning):
    """The Dugdale cohesive zone is narrower than a few cells: adhesive forces are set by the grid."""

    check = "cohesive_zone"


class CohesiveRangeWarning(ResultWarning):
    """The gap crosses the Dugdale range within one cell: the cohesive zone cannot be resolved."""

    check = "cohesive_range"


class CohesiveEdgeWarning(ResultWarning):
    """The grid's band of Dugdale equilibria is wide, or the cohesive zone is not resolved."""

    check = "cohesive_edge"


class FullContactWarning(ResultWarning):
    """The contact covers nearly the whole domain."""

    check = "full_contact"


class LargeContactWarning(ResultWarning):
    """The contact radius is too large a fraction of the sphere radius for the half-space model."""

    check = "large_contact"


class ContactCellsWarning(ResultWarning):
    """The largest contact patch is only a few solver cells across."""

    check = "contact_cells"


class TopographyPixelsWarning(ResultWarning):
    """The largest contact patch is only a few pixels of the measured scan across."""

    check = "topography_pixels"


class StickZoneWarning(ResultWarning):
    """The stick zone is only a few cells across: the slip quantities are set by the grid."""

    check = "stick_zone"


#: Check name -> its :class:`ResultWarning` subclass (one category per check of
#: :mod:`tribobem.output.checks`; the names are its ``CHECKS``).
RESULT_WARNINGS: dict[str, type] = {cls.check: cls for cls in (
    EdgeWarning, CohesiveZoneWarning, CohesiveRangeWarning, CohesiveEdgeWarning,
    FullContactWarning, LargeContactWarning, ContactCellsWarning, TopographyPixelsWarning, StickZoneWarning,
)}


def result_warning_category(message: str) -> type:
    """The :class:`ResultWarning` subclass of a warning line ``"name: message"``.

    Parameters
    ----------
    message : str
        A line of summary.json ``warnings``.

    Returns
    -------
    type
        The check's subclass, else :class:`ResultWarning` itself (lines of other origins).
    """
    return RESULT_WARNINGS.get(str(message).split(":", 1)[0].strip(), ResultWarning)
