"""Surface interactions: stresses that act where the bodies are *not* in contact.

An interaction tells the normal solver two things (the one interface every term uses):

* ``floor`` (Pa, <= 0): the lowest pressure a contact node may carry (``-sigma0`` for
  Dugdale adhesion, 0 without adhesion);
* ``outside_stress(gap, xp)``: the traction (Pa, negative = tensile) on a non-contact node
  whose gap is ``gap``.

New physics (capillary bridges, water-solid van der Waals) is a new file here implementing
this protocol, not a copy of the solver.  A law may also declare what the solvers, checks and
report may do with it (``windowable``, ``summary_info``, ``result_checks``, ``report_rows``:
:mod:`~tribobem.interactions.base`), and a law a scenario names in ``[adhesion] model`` is
registered in :mod:`~tribobem.interactions.registry` with the spec of its table.

The hardness cap (:class:`~tribobem.interactions.hardness.HardnessCap`) is the one term on the
compressive side: it wraps the outside law, caps the contact pressure at H and keeps the
plastic surface displacement that the capped solves leave.
"""

from .base import Interaction, NoInteraction
from .capillary import CapillaryInteraction, ForceSplit
from .dugdale import DugdaleAdhesion, SoftenedDugdale
from .exponential import ExponentialAdhesion
from .hardness import HardnessCap
from .registry import LAWS, LawContext, StressLaw, register_law
from .menisci import Islands, contribution_coefficient, meniscus_islands
from .van_der_waals import VanDerWaals, combine_hamaker
from .films import FilmResult, film_thickness, levelling_time
from .isotherms import SI, SIO2, DryIsotherm, FHHIsotherm, Isotherm, TableIsotherm, isotherm_from_spec
from .water import Water, check_rh

__all__ = ["Interaction", "NoInteraction", "DugdaleAdhesion", "SoftenedDugdale", "ExponentialAdhesion", "HardnessCap",
           "LAWS", "LawContext", "StressLaw", "register_law",
           "Water", "check_rh", "Isotherm", "TableIsotherm", "FHHIsotherm", "DryIsotherm", "SIO2", "SI",
           "isotherm_from_spec", "FilmResult", "film_thickness", "levelling_time",
           "CapillaryInteraction", "ForceSplit", "Islands", "meniscus_islands", "contribution_coefficient",
           "VanDerWaals", "combine_hamaker"]
