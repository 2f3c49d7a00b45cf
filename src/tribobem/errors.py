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
