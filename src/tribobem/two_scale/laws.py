"""The laws of a rough interface, tabulated from micro windows: what the macro solve uses.

A periodic window of the two bodies' roughness, pressed at a nominal (mean) pressure p, has a
mean separation g of its mean planes (the mean gap of the window, m), a real contact fraction
A_r/A, a largest local pressure, and (with friction) a stick fraction and a tangential
response.  Tabulated over a ladder of pressures and averaged over roughness realisations,
they are the interface's constitutive law: at macro scale a node of nominal pressure p sits at
the mean separation g(p).

:class:`NormalInterfaceLaw` holds the normal law: g(p) decreasing in p, from the separation at
first touch g(0) (the window's highest summit) down to the table's largest pressure.  Between
the tabulated pressures it interpolates g against ln p with a monotone cubic (PCHIP: continuous
slope, no overshoot, so the macro Newton iteration sees a smooth, strictly monotone law); below
the smallest tabulated pressure p_1 it follows a single asperity's Hertz law,
g = g(0) - (g(0) - g(p_1)) (p/p_1)^(2/3), which reaches g(0) at p = 0 with an infinite
compliance, as the first touching summit does; above the largest one it continues the last
segment's slope in ln p and the caller is told (:meth:`NormalInterfaceLaw.beyond_table`).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from scipy.interpolate import PchipInterpolator

__all__ = ["NormalInterfaceLaw"]

#: Exponent of the single-asperity (Hertz) branch below the smallest tabulated pressure:
#: an asperity's approach grows as its force to the 2/3.
HERTZ_EXPONENT = 2.0 / 3.0


@dataclass
class NormalInterfaceLaw:
    """Mean separation, contact fraction and peak pressure of a rough interface against p.

    Attributes
    ----------
    pressures : ndarray, shape (m,)
        Nominal pressures of the table (Pa), increasing, > 0.
    gaps : ndarray, shape (m,)
        Mean separation at each pressure (m), the mean over the realisations; decreasing.
    touch_gap : float
        Mean separation at first touch, g(0) (m): the mean over the realisations of the
        window's highest point above its mean plane (combined roughness).
    contact_fractions : ndarray, shape (m,)
        Real contact area over nominal area at each pressure (mean over realisations).
    max_pressures : ndarray, shape (m,)
        Largest local pressure of the windows at each pressure (Pa; the largest over the
        realisations).
    gap_spread : ndarray, shape (m,)
        Standard deviation of the mean separation between realisations (m; 0 for one).
    fraction_spread : ndarray, shape (m,)
        Standard deviation of the contact fraction between realisations.
    realisations : int
        Number of roughness realisations averaged.
    converged : bool
        Whether every micro solve converged.
    info : dict
        What the table was computed from (window size, cells, tolerance, ...), for the summary.
    patch_cells : ndarray, shape (m,), optional
        Equivalent diameter (cells) of the largest contact patch of the windows at each
        pressure (the largest over the realisations): whether the windows resolve their
        asperity contacts (>= 3 cells).
    menisci : dict, optional
        With menisci at one RH: ``repulsive_pressures`` and ``capillary_pressures`` (Pa, the
        windows' mean repulsive and meniscus pressures, the latter negative) and
        ``wetted_fractions`` at each pressure (means over the realisations).
    """

    pressures: np.ndarray
    gaps: np.ndarray
    touch_gap: float
    contact_fractions: np.ndarray
    max_pressures: np.ndarray
    gap_spread: np.ndarray
    fraction_spread: np.ndarray
    realisations: int = 1
    converged: bool = True
    info: dict = field(default_factory=dict)
    patch_cells: np.ndarray | None = None
    menisci: dict | None = None

    def __post_init__(self):
        self.pressures = np.asarray(self.pressures, dtype=float)
        self.gaps = np.asarray(self.gaps, dtype=float)
        if self.pressures.ndim != 1 or self.pressures.size < 3:
            raise ValueError("an interface law needs at least 3 tabulated pressures")
        if not (np.all(self.pressures > 0) and np.all(np.diff(self.pressures) > 0)):
            raise ValueError("the tabulated pressures must be positive and increasing")
        if not np.all(np.diff(self.gaps) < 0) or not self.touch_gap > self.gaps[0]:
            raise ValueError("the mean separation must decrease with the pressure from its value at first "
                             f"touch (g(0) = {self.touch_gap:.4g} m, table {self.gaps[:3]} ...)")
        self._lnp = np.log(self.pressures)
        self._spline = PchipInterpolator(self._lnp, self.gaps, extrapolate=True)
        self._slope = self._spline.derivative()
        fine = np.linspace(self._lnp[0], self._lnp[-1], 4096)
        self._inverse_lnp, self._inverse_g = fine[::-1], self._spline(fine)[::-1]  # g increasing
        # dg/dln p at the ends (the extrapolation above the table continues the last slope)
        self._end_slope = float(self._slope(self._lnp[-1]))
        if not self._end_slope < 0:  # PCHIP's shape-preserving end slope can be 0: the last secant
            self._end_slope = float((self.gaps[-1] - self.gaps[-2]) / (self._lnp[-1] - self._lnp[-2]))
        self._fraction = PchipInterpolator(self._lnp, np.asarray(self.contact_fractions, float), extrapolate=True)
        self._pmax = PchipInterpolator(self._lnp, np.log(np.maximum(np.asarray(self.max_pressures, float), 1e-300)),
                                       extrapolate=True)

    # -- the law and its derivative -------------------------------------------------------
    def gap(self, p):
        """Mean separation g(p) (m) at nominal pressures ``p`` (Pa, >= 0; array)."""
        p = np.asarray(p, dtype=float)
        out = np.empty_like(p)
        p1, g1, g0 = self.pressures[0], self.gaps[0], self.touch_gap
        low = p < p1
        high = p > self.pressures[-1]
        mid = ~(low | high)
        out[low] = g0 - (g0 - g1) * (np.maximum(p[low], 0.0) / p1) ** HERTZ_EXPONENT
        out[mid] = self._spline(np.log(p[mid]))
        out[high] = self.gaps[-1] + self._end_slope * (np.log(p[high]) - self._lnp[-1])
        return out

    def compliance(self, p, floor: float | None = None):
        """-dg/dp (m/Pa, > 0): the interface's normal compliance at nominal pressures ``p``.

        Parameters
        ----------
        p : array_like
            Nominal pressures (Pa).
        floor : float, optional
            Pressures below it (Pa) are evaluated at it (the Hertz branch's compliance is
            infinite at p = 0); default 1e-6 of the smallest tabulated pressure.
        """
        p = np.asarray(p, dtype=float)
        p1, g1, g0 = self.pressures[0], self.gaps[0], self.touch_gap
        floor = 1e-6 * p1 if floor is None else floor
        q = np.maximum(p, floor)
        out = np.empty_like(q)
        low = q < p1
        high = q > self.pressures[-1]
        mid = ~(low | high)
        out[low] = (g0 - g1) * HERTZ_EXPONENT / p1 * (q[low] / p1) ** (HERTZ_EXPONENT - 1.0)
        out[mid] = -self._slope(np.log(q[mid])) / q[mid]
        out[high] = -self._end_slope / q[high]
        return out

    def pressure(self, g):
        """The inverse law: nominal pressure (Pa) at mean separations ``g`` (m); 0 for g >= g(0)."""
        g = np.asarray(g, dtype=float)
        out = np.zeros_like(g)
        g0, g1, p1 = self.touch_gap, self.gaps[0], self.pressures[0]
        low = (g < g0) & (g > g1)
        out[low] = p1 * ((g0 - g[low]) / (g0 - g1)) ** (1.0 / HERTZ_EXPONENT)
        mid = (g <= g1) & (g >= self.gaps[-1])
        if np.any(mid):
            # the monotone spline inverted on a fine ln p grid (the table is short), built once
            out[mid] = np.exp(np.interp(g[mid], self._inverse_g, self._inverse_lnp))
        high = g < self.gaps[-1]
        # far below the table's last gap the extrapolated pressure overflows: cap its exponent
        out[high] = np.exp(np.minimum(self._lnp[-1] + (g[high] - self.gaps[-1]) / self._end_slope, 700.0))
        return out

    # -- what users read --------------------------------------------------------------------
    def contact_fraction(self, p):
        """Real contact fraction A_r/A at nominal pressures ``p`` (Pa); the table's first value
        scaled linearly in p below it (a few asperities), 0 at p = 0."""
        p = np.asarray(p, dtype=float)
        p1 = self.pressures[0]
        out = np.where(p < p1, float(self.contact_fractions[0]) * np.maximum(p, 0.0) / p1, 0.0)
        inside = p >= p1
        out[inside] = np.clip(self._fraction(np.log(p[inside])), 0.0, 1.0)
        return out

    def max_pressure(self, p):
        """Largest local (asperity) pressure (Pa) in a window at nominal pressures ``p``; the
        table's first value below it (the first summit's pressure does not vanish with p)."""
        p = np.asarray(p, dtype=float)
        out = np.where(p > 0, float(self.max_pressures[0]), 0.0)
        inside = p >= self.pressures[0]
        out[inside] = np.exp(self._pmax(np.log(p[inside])))
        return out

    def meniscus(self, key: str, p):
        """A meniscus column (``repulsive_pressures``, ``capillary_pressures``: Pa;
        ``wetted_fractions``) at nominal pressures ``p`` (Pa): linear in ln p on the table, its
        ratio to p held below and above it; 0 where p <= 0.  Dry: p, 0 and 0."""
        p = np.asarray(p, dtype=float)
        if self.menisci is None:
            return p.copy() if key == "repulsive_pressures" else np.zeros_like(p)
        col = np.asarray(self.menisci[key], float)
        if key == "wetted_fractions":
            vals = np.interp(np.log(np.maximum(p, 1e-300)), self._lnp, col)
        else:
            vals = np.interp(np.log(np.maximum(p, 1e-300)), self._lnp, col / self.pressures) * p
        return np.where(p > 0, vals, 0.0)

    def patch_cells_at(self, p: float) -> float | None:
        """The windows' largest contact patch (equivalent diameter, cells) at nominal pressure
        ``p`` (Pa): the tabulated value at the nearest pressure at or below ``p``; None without."""
        if self.patch_cells is None:
            return None
        k = int(np.clip(np.searchsorted(self.pressures, p, side="right") - 1, 0, self.pressures.size - 1))
        return float(np.asarray(self.patch_cells)[k])

    def beyond_table(self, p) -> bool:
        """Whether any pressure in ``p`` (Pa) lies above the table's largest (extrapolated)."""
        return bool(np.any(np.asarray(p) > self.pressures[-1] * (1 + 1e-9)))

    def as_dict(self) -> dict:
        """The table as plain lists (SI), for summary.json and the cache."""
        return {
            "pressures": self.pressures.tolist(), "gaps": self.gaps.tolist(), "touch_gap": float(self.touch_gap),
            "contact_fractions": np.asarray(self.contact_fractions, float).tolist(),
            "max_pressures": np.asarray(self.max_pressures, float).tolist(),
            "gap_spread": np.asarray(self.gap_spread, float).tolist(),
            "fraction_spread": np.asarray(self.fraction_spread, float).tolist(),
            "realisations": int(self.realisations), "converged": bool(self.converged), "info": dict(self.info),
            "patch_cells": None if self.patch_cells is None else np.asarray(self.patch_cells, float).tolist(),
            "menisci": self.menisci,
        }

    @classmethod
    def from_dict(cls, d: dict) -> "NormalInterfaceLaw":
        """The inverse of :meth:`as_dict`."""
        return cls(**{k: d[k] for k in ("pressures", "gaps", "touch_gap", "contact_fractions", "max_pressures",
                                        "gap_spread", "fraction_spread", "realisations", "converged", "info")},
                   patch_cells=d.get("patch_cells"), menisci=d.get("menisci"))

    @classmethod
    def from_realisations(cls, pressures, tables: list[dict], info: dict | None = None) -> "NormalInterfaceLaw":
        """Average per-realisation tables into one law.

        Parameters
        ----------
        pressures : array_like
            The common ladder of nominal pressures (Pa).
        tables : list of dict
            One per realisation: ``gaps`` (m), ``touch_gap`` (m), ``contact_fractions``,
            ``max_pressures`` (Pa), ``converged`` (bool per pressure or one bool).
        info : dict, optional
            Provenance for :attr:`info`.
        """
        gaps = np.array([t["gaps"] for t in tables], dtype=float)
        frac = np.array([t["contact_fractions"] for t in tables], dtype=float)
        pmax = np.array([t["max_pressures"] for t in tables], dtype=float)
        return cls(pressures=np.asarray(pressures, float), gaps=gaps.mean(axis=0),
                   touch_gap=float(np.mean([t["touch_gap"] for t in tables])),
                   contact_fractions=frac.mean(axis=0), max_pressures=pmax.max(axis=0),
                   gap_spread=gaps.std(axis=0), fraction_spread=frac.std(axis=0), realisations=len(tables),
                   converged=bool(all(np.all(t["converged"]) for t in tables)), info=dict(info or {}),
                   patch_cells=(np.array([t["patch_cells"] for t in tables], dtype=float).max(axis=0)
                                if all("patch_cells" in t for t in tables) else None),
                   menisci=({k: np.mean([t[k] for t in tables], axis=0).tolist()
                             for k in ("repulsive_pressures", "capillary_pressures", "wetted_fractions")}
                            if all("repulsive_pressures" in t for t in tables) else None))
