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

Optional, for smooth laws: ``outside_slope(gap, xp)`` (ds/dg, Pa/m), with which the solvers
relax a node's update by its own response, and ``tension_limit`` (Pa), the law's most tensile
stress where it is not the floor (a law that vanishes at contact, as the Lennard-Jones 9-3 one),
to which a relaxed update is clipped.

Optional, what callers would otherwise find out from the law's type (each read through the
helper of the same purpose below, which supplies the default for a law that does not declare
it; :mod:`tribobem.interactions.registry` ties a law to its ``[adhesion]`` table):

* ``windowable`` (bool, default False): the law depends on the gap alone and vanishes beyond a
  finite range, so that :mod:`tribobem.solvers.window` may solve a free-boundary step on a
  window of the grid (:func:`law_windowable`);
* ``summary_info(radius, effective_modulus)``: the law's derived scalars for summary.json
  ``problem`` (Dugdale: sigma0, h0, the Tabor and Maugis parameters; default none,
  :func:`law_summary_info`);
* ``result_checks`` (set of check names of :data:`tribobem.output.checks.CHECKS`, default
  none): the law-specific resolution checks that apply to its runs (the cohesive-zone checks
  of a cohesive-zone law with a stress ``sigma0`` and a range ``h0``, :func:`law_result_checks`);
* ``report_rows`` (class attribute, default none): ``(key, label, dimension)`` of the keys of
  ``summary_info`` that the HTML report lists under the problem's scalars.
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
    #: Nothing acts outside the contact: a window solve is exact.
    windowable = True

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


def law_windowable(law) -> bool:
    """Whether a window solve may use this law (its declared ``windowable``; default False).

    Parameters
    ----------
    law : Interaction or None
        The stress law outside contact; None: no law (a window is exact).

    Returns
    -------
    bool
    """
    return law is None or bool(getattr(law, "windowable", False))


def law_summary_info(law, radius: float | None = None, effective_modulus: float | None = None) -> dict:
    """The law's derived scalars for summary.json ``problem`` (its ``summary_info``; default none).

    Parameters
    ----------
    law : Interaction or None
        The stress law outside contact.
    radius : float, optional
        Composite sphere radius R (m), when the bodies have one.
    effective_modulus : float, optional
        Composite modulus E* (Pa); None when both bodies are rigid.

    Returns
    -------
    dict
        Key -> value (SI), in the order summary.json lists them; empty without a law.
    """
    info = getattr(law, "summary_info", None)
    return dict(info(radius, effective_modulus)) if info is not None else {}


def law_result_checks(law) -> frozenset:
    """The law-specific checks of :mod:`tribobem.output.checks` that apply to the law's runs.

    Parameters
    ----------
    law : Interaction or None
        The stress law outside contact.

    Returns
    -------
    frozenset of str
        Check names (its declared ``result_checks``); empty without a law or a declaration.
    """
    return frozenset(getattr(law, "result_checks", ()) or ())


def require_positive(law, **units) -> None:
    """Check that each named parameter of a law is finite and > 0 (its ``__post_init__``).

    Parameters
    ----------
    law : object
        The law (a dataclass).
    **units : str
        Parameter name -> its unit, for the message (``work_of_adhesion="J/m^2"``).

    Raises
    ------
    InputError
        Naming ``adhesion.<parameter>``.
    """
    import math

    from ..errors import InputError

    for name, unit in units.items():
        value = getattr(law, name)
        if not (math.isfinite(value) and value > 0):
            raise InputError(f"adhesion.{name}", f"must be > 0 {unit}, got {value!r}")
