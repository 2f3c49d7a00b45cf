"""A hardness cap on the contact pressure, with the plastic surface displacement it leaves.

The cap model (a rigid-perfectly-plastic surface layer on an elastic body): the contact
pressure never exceeds the hardness H of the softer surface, 0 <= p <= H (floor <= p <= H
with adhesion).  A node at p = H is *plastic*: its gap would be negative, and the overlap
-g is taken up as a permanent displacement of the surface into the body (the asperity is
flattened).  Nodes below H are elastic contact nodes (g = 0) as without the cap.

:class:`HardnessCap` wraps the stress law outside the contact (or none) and keeps the plastic
displacement it has accumulated: it is the state of the yielding surface.  Every normal solve
given the cap as its ``interaction`` solves on the gap raised by that displacement, enforces
p <= H, and adds the overlap of its plastic nodes to it once it has converged, so that
unloading, a later pull-off and later tangential steps of the same run see the flattened
topography.  The update is idempotent: a second solve at the same load adds nothing.

"Yield" in a cap model means p_max = H.  A real solid first yields below the surface at a mean
pressure of about 1.1 Y (a Hertz maximum pressure of about 1.6 Y, Y the yield stress in
tension), while the indentation hardness is about 2.8 Y: real yield starts near 0.57 H, and the
cap model ignores the elastic-plastic range between (no hardening, no subsurface plastic zone).
"""

from __future__ import annotations

import math

import numpy as np

from ..errors import InputError
from .base import NoInteraction

__all__ = ["HardnessCap", "unwrap_cap"]


class HardnessCap:
    """Pressure cap p <= H on a stress law, with the accumulated plastic displacement.

    Parameters
    ----------
    hardness : float
        Hardness H of the softer surface (Pa), > 0: the largest contact pressure.
    law : Interaction, optional
        The stress law outside the contact (adhesion); None: none.
    plastic : ndarray, optional
        Plastic (permanent) surface displacement already in the body (m, >= 0, the grid's
        shape); None: none yet.

    Attributes
    ----------
    plastic : ndarray or None
        The accumulated plastic displacement (m, >= 0): the gap every solve adds to its own.
    """

    def __init__(self, hardness: float, law=None, plastic=None):
        if not (isinstance(hardness, (int, float)) and math.isfinite(hardness) and hardness > 0):
            raise InputError("hardness", f"must be a finite pressure > 0 Pa, got {hardness!r}")
        self.hardness = float(hardness)
        self.law = law if law is not None else NoInteraction()
        if plastic is not None:
            plastic = np.asarray(plastic, dtype=float)
            if not (np.all(np.isfinite(plastic)) and float(plastic.min(initial=0.0)) >= 0.0):
                raise InputError("plastic", "the plastic displacement must be finite and >= 0 m")
        self.plastic = plastic

    def __getattr__(self, name):
        # the law's own attributes (floor, outside_stress, range, summary_info, ...); the guard
        # keeps copies and pickles (Dask) from recursing before ``law`` is set
        if name == "law" or name.startswith("__"):
            raise AttributeError(name)
        return getattr(self.law, name)

    def __repr__(self) -> str:
        return f"HardnessCap(hardness={self.hardness!r}, law={self.law!r})"

    @property
    def adhesive(self) -> bool:
        """Whether the wrapped law acts outside the contact."""
        return not isinstance(self.law, NoInteraction)

    def offset(self, shape, xp=np):
        """The plastic displacement as an array of ``xp`` (m), or None when there is none yet.

        Parameters
        ----------
        shape : tuple of int
            The grid's shape (checked).
        xp : module
            Array namespace of the solve.
        """
        if self.plastic is None:
            return None
        if tuple(self.plastic.shape) != tuple(shape):
            raise InputError("plastic", f"shape {self.plastic.shape} does not match the grid {tuple(shape)}")
        return xp.asarray(self.plastic)

    def commit(self, increment) -> None:
        """Add a converged solve's plastic overlap (m, >= 0, host array) to the body's displacement."""
        inc = np.asarray(increment, dtype=float)
        if not bool(np.any(inc > 0)):
            return
        self.plastic = inc.copy() if self.plastic is None else self.plastic + inc

    def reset(self) -> None:
        """Forget the plastic history (an undeformed surface)."""
        self.plastic = None

    @property
    def max_plastic_displacement(self) -> float:
        """Largest plastic displacement so far (m; 0 without one)."""
        return float(self.plastic.max()) if self.plastic is not None else 0.0

    def summary_info(self, radius: float | None = None, effective_modulus: float | None = None) -> dict:
        """The law's scalars (if any) and the hardness (Pa)."""
        fn = getattr(self.law, "summary_info", None)
        info = dict(fn(radius, effective_modulus)) if fn is not None else {}
        info["hardness"] = self.hardness
        return info


def unwrap_cap(interaction):
    """Split an interaction into (law, cap): the law outside the contact and the cap or None.

    Parameters
    ----------
    interaction : Interaction, HardnessCap or None

    Returns
    -------
    tuple
        (the stress law or None, the :class:`HardnessCap` or None).
    """
    if isinstance(interaction, HardnessCap):
        law = interaction.law
        return (None if isinstance(law, NoInteraction) else law), interaction
    return interaction, None
