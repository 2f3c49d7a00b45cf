"""Elastic bodies and their composite moduli.

Conventions: body 1 is the lower body, body 2 the upper one; either may be
rigid (``E = inf``).  All moduli are in Pa.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from .errors import InputError


@dataclass(frozen=True)
class Material:
    """An isotropic linear-elastic half-space.

    Parameters
    ----------
    E : float
        Young's modulus in Pa; ``math.inf`` for a rigid body.
    nu : float
        Poisson's ratio, in (-1, 0.5].
    name : str, optional
        Label used in reports.
    """

    E: float
    nu: float = 0.0
    name: str = ""

    def __post_init__(self):
        field = self.name or "material"
        if not isinstance(self.E, (int, float)) or math.isnan(self.E) or self.E <= 0:
            raise InputError(f"{field}.E", f"Young's modulus must be > 0 Pa (or inf for rigid), got {self.E!r}")
        if not (-1.0 < self.nu <= 0.5) or math.isnan(self.nu):
            raise InputError(f"{field}.nu", f"Poisson's ratio must lie in (-1, 0.5], got {self.nu!r}")

    @classmethod
    def rigid(cls, name: str = "rigid") -> "Material":
        """A rigid body (infinite modulus).

        Parameters
        ----------
        name : str
            Label used in reports.

        Returns
        -------
        Material
            ``Material(math.inf, 0.0, name)``; nu does not matter for a rigid body.
        """
        return cls(math.inf, 0.0, name)

    @property
    def is_rigid(self) -> bool:
        """True for an infinite Young's modulus."""
        return math.isinf(self.E)

    @property
    def shear_modulus(self) -> float:
        """G = E / (2 (1 + nu)) in Pa (inf when rigid)."""
        return self.E / (2.0 * (1.0 + self.nu))

    @property
    def normal_compliance(self) -> float:
        """(1 - nu^2) / E in 1/Pa (0 when rigid)."""
        return 0.0 if self.is_rigid else (1.0 - self.nu**2) / self.E


@dataclass(frozen=True)
class ContactPair:
    """Two bodies in contact; gives the composite moduli of the interface.

    Parameters
    ----------
    body1, body2 : Material
        Lower and upper body.  At least one must be elastic.
    model : BodyModel, optional
        How the two bodies respond, a :class:`tribobem.elasticity.bodies.BodyModel`; None: two
        homogeneous half-spaces (``"halfspace"``).  The operators take their kernels from it
        (:func:`tribobem.elasticity.bodies.body_model_of`, which also checks its type: this
        module, below the elasticity, does not import it).
    """

    body1: Material
    body2: Material
    model: object | None = None

    def __post_init__(self):
        if self.body1.is_rigid and self.body2.is_rigid:
            raise InputError("bodies", "both bodies are rigid; at least one must have a finite E")

    @property
    def effective_modulus(self) -> float:
        """E* with 1/E* = (1 - nu1^2)/E1 + (1 - nu2^2)/E2, in Pa."""
        return 1.0 / (self.body1.normal_compliance + self.body2.normal_compliance)

    @property
    def coupling_compliance(self) -> float:
        """C_c = (1 - 2 nu1)/(4 pi G1) - (1 - 2 nu2)/(4 pi G2) in 1/Pa.

        Zero for identical materials.  The normal-tangential coupling of the two bodies
        subtracts because body 2 receives the opposite traction.
        """
        def term(m: Material) -> float:
            return 0.0 if m.is_rigid else (1.0 - 2.0 * m.nu) / (4.0 * math.pi * m.shear_modulus)

        return term(self.body1) - term(self.body2)

    @property
    def dundurs_beta(self) -> float:
        """Johnson's beta, with C_c = beta / (pi E*)."""
        return self.coupling_compliance * math.pi * self.effective_modulus


def effective_modulus(E1: float, nu1: float, E2: float = math.inf, nu2: float = 0.0) -> float:
    """Composite modulus E* (Pa) of two bodies; ``E2=inf`` (default) makes body 2 rigid.

    Parameters
    ----------
    E1, nu1 : float
        Young's modulus (Pa; ``math.inf`` for rigid) and Poisson's ratio of body 1.
    E2, nu2 : float
        The same for body 2.

    Returns
    -------
    float
        E* with 1/E* = (1 - nu1^2)/E1 + (1 - nu2^2)/E2 (Pa).

    Raises
    ------
    InputError
        An invalid modulus or Poisson's ratio, or two rigid bodies.
    """
    return ContactPair(Material(E1, nu1, "body1"), Material(E2, nu2, "body2")).effective_modulus
