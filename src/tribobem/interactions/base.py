"""The interaction protocol used by the normal solver."""

from __future__ import annotations

from typing import Protocol, runtime_checkable


@runtime_checkable
class Interaction(Protocol):
    """Gap-dependent stress law acting outside the contact (see package docstring)."""

    floor: float

    def outside_stress(self, gap, xp):  # pragma: no cover - protocol
        """Traction (Pa) on non-contact nodes as a function of their gap (m)."""


class NoInteraction:
    """Non-adhesive contact: no stress outside the contact, pressure >= 0 inside."""

    floor = 0.0
    range = 0.0

    def outside_stress(self, gap, xp):
        return xp.zeros_like(gap)

    def __repr__(self) -> str:
        return "NoInteraction()"
