"""The interaction protocol used by the normal solver.

Required: ``floor`` and ``outside_stress(gap, xp)`` (package docstring).  The gap passed to
``outside_stress`` is either grid-shaped or the flat C-order ravel of a grid-shaped field (the
normal solver passes the flat one); a law that depends on the POSITION (e.g. meniscus
islands, local film thicknesses: :class:`~tribobem.interactions.capillary.CapillaryInteraction`)
must accept both.  ``floor`` should equal the law's limit at zero gap, s(0+), so that a node
leaving the contact continues its stress.

Optional, for laws that vary SMOOTHLY with the gap (van der Waals 1/g^3 terms):
``outside_branch(gap, xp)`` returns, per node, an integer or boolean label of the piece of a
piecewise-smooth law the node is on (the law being continuous in the gap within a piece).
The normal solver then treats a change of outside stress without a change of piece as a
fixed-point update of the load (no restart of its conjugate directions), and a change of
piece, like a change of the contact set, as a change of the problem.  Without the method
(Dugdale: a step law; no interaction) every change of an outside stress counts as a change of
the problem, as before.
"""

from __future__ import annotations

from typing import Protocol, runtime_checkable


@runtime_checkable
class Interaction(Protocol):
    """Gap-dependent stress law acting outside the contact (see package docstring)."""

    floor: float

    def outside_stress(self, gap, xp):  # pragma: no cover - protocol
        """Traction (Pa) on non-contact nodes as a function of their gap (m).

        Parameters
        ----------
        gap : ndarray
            Gap of the nodes (m), grid-shaped or its flat C-order ravel.
        xp : module
            Array namespace of ``gap`` (``numpy`` or ``cupy``), so that the law runs on the
            solver's device.

        Returns
        -------
        ndarray
            Stress (Pa, negative = tensile), shape of ``gap``.
        """


class NoInteraction:
    """Non-adhesive contact: no stress outside the contact, pressure >= 0 inside."""

    floor = 0.0
    range = 0.0

    def outside_stress(self, gap, xp):
        """Zero traction (Pa) on every non-contact node.

        Parameters
        ----------
        gap : ndarray
            Gap of the nodes (m), grid-shaped or its flat C-order ravel.
        xp : module
            Array namespace of ``gap`` (``numpy`` or ``cupy``), so that the law runs on the
            solver's device.

        Returns
        -------
        ndarray
            Zeros, shape of ``gap``.
        """
        return xp.zeros_like(gap)

    def __repr__(self) -> str:
        return "NoInteraction()"
