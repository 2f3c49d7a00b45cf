"""Water: Kelvin radius, capillary (Laplace) pressure and the relative humidity (Papers B, C).

At thermodynamic equilibrium with vapour at relative humidity RH, a water surface has the
mean curvature set by the Kelvin equation (thesis Eq. A.25, Paper B Eq. 5, Paper C Eq. 6)::

    r_k = gamma V / (R_g T ln RH)                       (m)
    dP_cap = gamma / r_k = R_g T ln RH / V              (Pa, thesis Eq. A.26, Paper B Eq. 10)

with ``ln`` the natural logarithm and RH a fraction in (0, 1]. Sign convention:
for RH < 1, ``ln RH < 0`` so ``r_k < 0`` (the meniscus is concave: it curves *into* the
liquid) and ``dP_cap < 0`` is tensile (the liquid pulls the bodies together). The thesis
writes the left side of A.25 as ``(1/r1 - 1/r2)^-1`` and A.28 with the opposite sign
fixes it: wherever a *length* is meant (the meniscus height ``2 |r_k|`` of Paper B Eq. 9) the
absolute value ``|r_k|`` is used.

RH = 1 (saturated vapour) is allowed: ``ln RH = 0``, the Kelvin meniscus is flat
(``r_k = -inf``, its curvature ``1/r_k = 0``) and the Laplace pressure vanishes
(``dP_cap = 0``), so a meniscus exerts no capillary force from its Laplace pressure.
RH = 0 (no vapour at all) is excluded: ``ln 0 = -inf``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..errors import InputError

__all__ = ["GAS_CONSTANT", "WATER_MOLECULE_DIAMETER", "Water", "check_rh"]

#: Universal gas constant R_g (J/(mol K)), CODATA 2018 exact value.
GAS_CONSTANT = 8.314462618

#: Diameter of a water molecule (m), about 0.28 nm (the O-O distance in liquid water, or
#: (V / N_A)^(1/3) = 0.31 nm from the molar volume). Paper B takes the critical film-to-film
#: distance as three molecule diameters: d_cr = 3 x 0.28 nm = 0.84 nm (default).
WATER_MOLECULE_DIAMETER = 0.28e-9


def check_rh(rh, field: str = "humidity.rh"):
    """Validate a relative humidity (a fraction, not a percentage).

    Parameters
    ----------
    rh : float or array_like
        Relative humidity, dimensionless, each value in (0, 1].
    field : str
        Name of the input used in the error message.

    Returns
    -------
    float or ndarray
        ``rh`` as a float (scalar input) or a float ndarray.

    Raises
    ------
    InputError
        A value is not a finite number in (0, 1]. RH = 0 has ``ln RH = -inf``; RH > 1 is
        supersaturated vapour (bulk condensation, outside the model); a value such as 35
        is most likely a percentage.
    """
    try:
        arr = np.asarray(rh, dtype=float)
    except (TypeError, ValueError):
        raise InputError(field, f"relative humidity must be a number in (0, 1], got {rh!r}") from None
    if arr.size == 0:
        raise InputError(field, "relative humidity is empty")
    bad = ~np.isfinite(arr) | (arr <= 0.0) | (arr > 1.0)
    if np.any(bad):
        value = arr[bad].flat[0] if arr.ndim else float(arr)
        hint = " (a percentage? give a fraction, e.g. 0.35 for 35 %)" if 1.0 < value <= 100.0 else ""
        raise InputError(field, f"relative humidity must be a fraction in (0, 1], got {value!r}{hint}")
    return float(arr) if arr.ndim == 0 else arr


def _positive(value, field: str, unit: str) -> float:
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise InputError(field, f"must be a finite number > 0 {unit}, got {value!r}") from None
    if not (math.isfinite(v) and v > 0.0):
        raise InputError(field, f"must be a finite number > 0 {unit}, got {value!r}")
    return v


@dataclass(frozen=True)
class Water:
    """Liquid water in equilibrium with its vapour (defaults).

    Parameters
    ----------
    temperature : float
        Absolute temperature T in K (default 295 K, i.e. 22 C as in Paper C).
    surface_tension : float
        Surface tension gamma of water in N/m (default 0.0725 N/m).
    molar_volume : float
        Molar volume V of liquid water in m^3/mol (default 18.05e-6 m^3/mol).

    Raises
    ------
    InputError
        A parameter is not a finite number > 0.
    """

    temperature: float = 295.0
    surface_tension: float = 0.0725
    molar_volume: float = 18.05e-6

    #: Diameter of a water molecule, m (see :data:`WATER_MOLECULE_DIAMETER`).
    molecule_diameter = WATER_MOLECULE_DIAMETER

    def __post_init__(self):
        # frozen dataclass: store the validated floats with object.__setattr__
        object.__setattr__(self, "temperature", _positive(self.temperature, "humidity.temperature", "K"))
        object.__setattr__(self, "surface_tension", _positive(self.surface_tension, "humidity.surface_tension", "N/m"))
        object.__setattr__(self, "molar_volume", _positive(self.molar_volume, "humidity.molar_volume", "m^3/mol"))

    @property
    def pressure_scale(self) -> float:
        """R_g T / V in Pa: the pressure of one e-fold of humidity (about 1.36e8 Pa at 295 K)."""
        return GAS_CONSTANT * self.temperature / self.molar_volume

    @property
    def critical_distance(self) -> float:
        """Default critical film-to-film distance d_cr = 3 molecule diameters = 0.84 nm, in m."""
        return 3.0 * self.molecule_diameter

    def capillary_pressure(self, rh):
        """Laplace (capillary) pressure dP_cap = R_g T ln(RH) / V in Pa (thesis Eq. A.26).

        Parameters
        ----------
        rh : float or array_like
            Relative humidity in (0, 1].

        Returns
        -------
        float or ndarray
            Pressure in Pa, negative (tensile) for RH < 1 and exactly 0.0 at RH = 1 (flat
            meniscus: no Laplace pressure, no capillary force from it).
        """
        rh = check_rh(rh)
        p = self.pressure_scale * np.log(rh)
        return float(p) if np.ndim(p) == 0 else p

    def chemical_potential_pressure(self, rh):
        """The liquid pressure in equilibrium with vapour at RH, (R_g T / V) ln RH, in Pa.

        The same number as :meth:`capillary_pressure`: the chemical potential of water,
        R_g T ln RH, per molar volume. It is the right side of the film equilibrium
        ``-gamma lap(h_w) - Pi(e) = (R_g T / V) ln RH``.  It has its own name because
        the film solvers use it as a chemical potential, not as a meniscus pressure.

        Parameters
        ----------
        rh : float or array_like
            Relative humidity in (0, 1].

        Returns
        -------
        float or ndarray
            Pressure in Pa (<= 0, 0 at RH = 1).
        """
        return self.capillary_pressure(rh)

    def kelvin_radius(self, rh):
        """Kelvin radius r_k = gamma V / (R_g T ln RH) in m (thesis Eq. A.25).

        Parameters
        ----------
        rh : float or array_like
            Relative humidity in (0, 1].

        Returns
        -------
        float or ndarray
            r_k in m: negative for RH < 1 (concave meniscus; use ``abs`` for a length)
            and ``-inf`` at RH = 1 (flat meniscus). About -0.77 nm at RH = 0.5.
        """
        rh = check_rh(rh)
        log_rh = np.log(rh)
        with np.errstate(divide="ignore"):
            # ln(1) = +0.0, so 1/(-0.0) would give +inf: make the RH = 1 limit -inf explicitly
            # (r_k -> -inf as RH -> 1 from below).
            safe = np.where(log_rh < 0.0, log_rh, -1.0)
            r = np.where(log_rh < 0.0, self.surface_tension / (self.pressure_scale * safe), -np.inf)
        return float(r) if np.ndim(r) == 0 else r

    def relative_humidity(self, kelvin_radius):
        """The RH whose Kelvin radius is ``kelvin_radius``, the inverse of :meth:`kelvin_radius`.

        Parameters
        ----------
        kelvin_radius : float or array_like
            r_k (m, < 0; ``-inf`` gives RH = 1).

        Returns
        -------
        float or ndarray
            RH = exp(gamma V / (R_g T r_k)) in (0, 1].

        Raises
        ------
        InputError
            A NaN or non-negative Kelvin radius.
        """
        r = np.asarray(kelvin_radius, dtype=float)
        if np.any(np.isnan(r)) or np.any(r >= 0.0):
            raise InputError("kelvin_radius", f"must be < 0 m (concave meniscus) or -inf, got {kelvin_radius!r}")
        out = np.exp(self.surface_tension / (self.pressure_scale * r))
        return float(out) if out.ndim == 0 else out
