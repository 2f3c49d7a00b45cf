"""Water adsorption isotherms: film thickness against relative humidity, and the disjoining pressure.

An isotherm gives the thickness ``e`` (m) of the water film adsorbed on a *flat* surface of a
body in equilibrium with vapour at relative humidity RH (Paper B Fig. 7, after Asay and Kim
2005; Paper C Sec. 4). Its inverse ``RH_iso(e)`` defines the disjoining pressure of the film
::

    Pi(e) = -(R_g T / V) ln RH_iso(e)        (Pa; > 0, decreasing in e)

because on a flat the liquid pressure under the free surface, ``-Pi(e)``, must equal the
Kelvin pressure ``(R_g T / V) ln RH``. ``Pi`` is what stops a film from draining off the peaks
in the levelling problem (:mod:`tribobem.interactions.films`).

Shipped isotherms (APPROXIMATE; shape of Asay and Kim 2005 and Verdaguer et al. 2007,
matching Paper C's 0.9 nm on SiO2 and 0.6 nm on Si at 35 % RH; the thesis prints no table):

======  ====  ====  ====  ====  ====  ====  ====  ====  ====  ====  ====  ====
RH      0     .10   .20   .30   .35   .40   .50   .60   .70   .80   .90   .95
SiO2    0     0.30  0.55  0.80  0.90  0.95  1.05  1.20  1.35  1.60  2.00  2.60 nm
======  ====  ====  ====  ====  ====  ====  ====  ====  ====  ====  ====  ====

Si: two thirds of the SiO2 thicknesses.

Conventions used by every isotherm here:

* RH is a fraction in [0, 1]; thickness in m, >= 0. ``thickness(0) = 0``.
* ``thickness(1)`` is the film at saturation: ``inf`` when the isotherm diverges there (FHH and
  the extrapolated tables), i.e. bulk water.
* ``Pi(e) -> +inf`` as ``e -> 0`` (``RH_iso -> 0``): a film cannot be squeezed to nothing by a
  finite Laplace pressure. Below a floor thickness ``floor = thickness(RH_FLOOR)``,
  ``RH_FLOOR = 1e-6`` (where ``Pi`` already exceeds ``(R_g T / V) ln 1e6``, about 1.9 GPa at
  295 K), ``ln RH_iso`` is continued *logarithmically*, ``ln RH_iso(e) = ln RH_iso(floor) +
  b ln(e / floor)`` with ``b`` matching the slope (C1): for a table, whose RH rises linearly
  from 0, this is the interpolant's own behaviour (b = 1), and it keeps a power-law isotherm
  (FHH) free of overflow. ``Pi(0) = +inf``; a negative thickness is an input error.
"""

from __future__ import annotations

import math
from abc import ABC, abstractmethod

import numpy as np
from scipy.interpolate import CubicHermiteSpline, PchipInterpolator

from ..errors import InputError
from .water import Water
from ..units import to_si

__all__ = [
    "Isotherm",
    "TableIsotherm",
    "FHHIsotherm",
    "DryIsotherm",
    "SIO2",
    "SI",
    "SIO2_TABLE",
    "RH_FLOOR",
    "isotherm_from_spec",
]

#: Relative humidity whose film thickness is the floor below which ln RH_iso is continued logarithmically.
RH_FLOOR = 1e-6

_DEFAULT_WATER = Water()


def _as_rh(rh, field: str) -> np.ndarray:
    try:
        arr = np.asarray(rh, dtype=float)
    except (TypeError, ValueError):
        raise InputError(field, f"relative humidity must be numbers in [0, 1], got {rh!r}") from None
    if np.any(~np.isfinite(arr)) or np.any(arr < 0.0) or np.any(arr > 1.0):
        raise InputError(field, f"relative humidity must be finite fractions in [0, 1], got {rh!r}")
    return arr


def _as_thickness(e, field: str) -> np.ndarray:
    try:
        arr = np.asarray(e, dtype=float)
    except (TypeError, ValueError):
        raise InputError(field, f"film thickness must be numbers >= 0 m, got {e!r}") from None
    if np.any(np.isnan(arr)) or np.any(arr < 0.0):
        raise InputError(field, f"film thickness must be >= 0 m (not NaN), got {e!r}")
    return arr


def _out(arr):
    """A float for 0-d results, the array otherwise."""
    return float(arr) if np.ndim(arr) == 0 else arr


class Isotherm(ABC):
    """Film thickness on a flat against relative humidity, and the disjoining pressure it implies.

    Subclasses implement ``_thickness`` (RH -> e), ``_relative_humidity`` (e -> RH) and
    ``_log_rh_above_floor`` (``ln RH_iso(e)`` and its derivative for ``e >= floor``).
    """

    #: Short name (e.g. "SiO2"), used in reports.
    name: str = "isotherm"

    @property
    def dry(self) -> bool:
        """True for a body that adsorbs no water (:class:`DryIsotherm`)."""
        return False

    # ------------------------------------------------------------------ to implement
    @abstractmethod
    def _thickness(self, rh: np.ndarray) -> np.ndarray:
        """Thickness (m) for validated RH values in [0, 1]."""

    @abstractmethod
    def _relative_humidity(self, e: np.ndarray) -> np.ndarray:
        """RH for validated thicknesses (m, >= 0)."""

    @abstractmethod
    def _log_rh_above_floor(self, e: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """``ln RH_iso(e)`` and ``d ln RH_iso / de`` (1/m) for ``e >= floor``."""

    # ------------------------------------------------------------------ public
    @property
    def floor(self) -> float:
        """Thickness (m) below which ``ln RH_iso`` and ``Pi`` are continued logarithmically (module docstring)."""
        f = getattr(self, "_floor", None)
        if f is None:
            f = float(self._thickness(np.asarray(RH_FLOOR)))
            self._floor = f
            g, dg = self._log_rh_above_floor(np.asarray(f))
            self._floor_log, self._floor_slope = float(g), float(dg)
        return f

    def thickness(self, rh):
        """Adsorbed film thickness on a flat (m) at relative humidity ``rh``.

        Parameters
        ----------
        rh : float or array_like
            Relative humidity, fractions in [0, 1].

        Returns
        -------
        float or ndarray
            Thickness in m, >= 0, non-decreasing in RH; ``inf`` at RH = 1 where the isotherm
            diverges (bulk water).

        Raises
        ------
        InputError
            RH outside [0, 1] or NaN.
        """
        return _out(self._thickness(_as_rh(rh, "rh")))

    def relative_humidity(self, thickness):
        """The relative humidity RH_iso(e) at which a flat carries a film of this thickness.

        Parameters
        ----------
        thickness : float or array_like
            Film thickness e in m, >= 0 (``inf`` allowed: RH = 1).

        Returns
        -------
        float or ndarray
            RH in [0, 1], increasing in e; the inverse of :meth:`thickness`.

        Raises
        ------
        InputError
            A negative or NaN thickness.
        """
        return _out(self._relative_humidity(_as_thickness(thickness, "thickness")))

    def log_relative_humidity(self, e, derivative: bool = False):
        """``ln RH_iso(e)`` (and optionally its derivative in 1/m).

        Below :attr:`floor` the function is continued logarithmically (module docstring): it
        is finite for every ``e > 0``, C1, strictly increasing, and ``-inf`` at ``e = 0``.

        Parameters
        ----------
        e : float or array_like
            Thickness in m, >= 0.
        derivative : bool
            Also return ``d ln RH_iso / de`` (1/m, >= 0; +inf at e = 0).

        Returns
        -------
        float or ndarray
            ``ln RH_iso(e)`` (dimensionless, <= 0), shape of ``e``; with ``derivative`` the
            pair ``(ln RH_iso, d ln RH_iso / de)``.

        Raises
        ------
        InputError
            A negative or NaN thickness.
        """
        e = _as_thickness(e, "thickness")
        with np.errstate(divide="ignore"):
            g, dg = self._log_rh(e)
        if derivative:
            return _out(g), _out(dg)
        return _out(g)

    def _log_rh(self, e: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """``ln RH_iso`` and its slope for thicknesses e >= 0, unvalidated (the solvers' fast path)."""
        floor = self.floor
        low = e < floor
        g, dg = self._log_rh_above_floor(np.where(low, floor, e))
        if np.any(low):
            b = self._floor_slope * floor
            el = np.where(low, e, floor)
            g = np.where(low, self._floor_log + b * np.log(el / floor), g)
            dg = np.where(low, b / el, dg)
        return g, dg

    def disjoining_pressure(self, e, water: Water = _DEFAULT_WATER):
        """Disjoining pressure Pi(e) = -(R_g T / V) ln RH_iso(e), in Pa.

        Parameters
        ----------
        e : float or array_like
            Film thickness in m, >= 0 (below :attr:`floor`: the logarithmic continuation).
        water : Water
            Supplies R_g T / V.

        Returns
        -------
        float or ndarray
            Pi in Pa: positive, decreasing in e, about 1.9 GPa at the floor, +inf at e = 0,
            0 where RH_iso = 1.
        """
        return _out(-water.pressure_scale * np.asarray(self.log_relative_humidity(e)))

    def disjoining_pressure_derivative(self, e, water: Water = _DEFAULT_WATER):
        """dPi/de in Pa/m (<= 0: Pi decreases with the thickness).

        The film solvers need it for the Newton Jacobian ``gamma k^2 - Pi'(e)``.

        Parameters
        ----------
        e : float or array_like
            Film thickness in m, >= 0.
        water : Water
            Supplies R_g T / V.

        Returns
        -------
        float or ndarray
            dPi/de (Pa/m), shape of ``e``; -inf at e = 0.

        Raises
        ------
        InputError
            A negative or NaN thickness.
        """
        _, dg = self.log_relative_humidity(e, derivative=True)
        return _out(-water.pressure_scale * np.asarray(dg))


# ----------------------------------------------------------------------------- table
class TableIsotherm(Isotherm):
    """An isotherm interpolated monotonically from a measured table.

    Parameters
    ----------
    rh : array_like
        Relative humidities, fractions in [0, 1], strictly increasing, at least 2 points.
    thickness : array_like
        Film thicknesses in m, >= 0, strictly increasing, same length as ``rh``.
    name : str, optional
        Name used in reports.

    Raises
    ------
    InputError
        Fewer than 2 points, lengths differ, NaN/inf, RH outside [0, 1], negative thickness,
        values not strictly increasing, a film at RH = 0 (``thickness > 0`` at ``rh = 0``:
        the disjoining pressure would be infinite on a finite film) or a zero film at RH > 0.

    Notes
    -----
    *Interpolation.* A PCHIP (Fritsch-Carlson, :class:`scipy.interpolate.PchipInterpolator`)
    of RH against thickness: monotone, C1, no overshoot, and it passes through every table
    point; at the last point (RH < 1) the slope is the secant of the last interval instead of
    the one-sided PCHIP formula (which gives 0 for the SiO2 table), still monotone. The disjoining
    pressure (evaluated on every node at every solver iteration) is
    then a direct evaluation, and :meth:`thickness` is its exact numerical inverse
    (bracketed bisection on the cubic of the table interval, to round-off), so
    ``relative_humidity(thickness(rh)) == rh``. A table that does not start at RH = 0 gets the
    point (0, 0) prepended (no vapour, no film).

    *Above the last point* (RH_n < 1, e_n): a Frenkel-Halsey-Hill tail
    ``ln RH = ln RH_n (e_n / e)^s`` matched in value and slope to the interpolant at e_n
    (``s = e_n RH'(e_n) / (RH_n |ln RH_n|)`` with RH'(e_n) the last secant). It is monotone, finite
    for every RH < 1 and diverges at RH = 1
    (``thickness(1) = inf``: bulk water), like a multilayer film. For the shipped SiO2 table
    s = 4.45: 3.75 nm at RH 0.99, 6.3 nm at 0.999. A table that ends at RH = 1 has a finite
    saturated film; beyond it RH_iso = 1 and Pi = 0 (bulk water).
    """

    def __init__(self, rh, thickness, name: str | None = None):
        field = "isotherm"
        try:
            r = np.asarray(rh, dtype=float).ravel()
            t = np.asarray(thickness, dtype=float).ravel()
        except (TypeError, ValueError):
            raise InputError(field, "rh and thickness must be lists of numbers") from None
        if r.size != t.size:
            raise InputError(field, f"rh and thickness must have the same length, got {r.size} and {t.size}")
        if r.size < 2:
            raise InputError(field, f"a table needs at least 2 points, got {r.size}")
        if not (np.all(np.isfinite(r)) and np.all(np.isfinite(t))):
            raise InputError(field, "rh and thickness must be finite numbers (no NaN or inf)")
        if np.any(r < 0.0) or np.any(r > 1.0):
            raise InputError(f"{field}.rh", f"relative humidity must be fractions in [0, 1], got {r.tolist()}")
        if np.any(t < 0.0):
            raise InputError(f"{field}.thickness", f"thickness must be >= 0 m, got {t.tolist()}")
        if np.any(np.diff(r) <= 0.0):
            raise InputError(f"{field}.rh", f"relative humidity must be strictly increasing, got {r.tolist()}")
        if np.any(np.diff(t) <= 0.0):
            raise InputError(
                f"{field}.thickness",
                f"thickness must be strictly increasing with RH (a plateau has no disjoining pressure), got {t.tolist()}",
            )
        if r[0] == 0.0 and t[0] != 0.0:
            raise InputError(f"{field}.thickness", f"the film at RH = 0 must be 0 m, got {t[0]!r}")
        if r[0] > 0.0:
            if t[0] == 0.0:
                raise InputError(f"{field}.thickness", f"a zero film at RH = {r[0]} > 0 cannot be inverted; "
                                                       "start the table at RH = 0")
            r = np.concatenate([[0.0], r])
            t = np.concatenate([[0.0], t])
        self.name = name or "table"
        self.table_rh = r
        self.table_thickness = t
        # PCHIP node slopes (Fritsch-Carlson), except at the last point where the secant of
        # the last interval is used: the one-sided PCHIP end formula is often 0 there (it is
        # for the SiO2 table), which would give the FHH tail a zero exponent. 0 < d_n =
        # delta_n <= 3 delta_n keeps the interpolant monotone (Fritsch and Carlson 1980).
        slopes = PchipInterpolator(t, r).derivative()(t)
        last_secant = float((r[-1] - r[-2]) / (t[-1] - t[-2]))
        if r[-1] < 1.0:
            slopes[-1] = last_secant
        self._pchip = CubicHermiteSpline(t, r, slopes, extrapolate=False)
        self._dpchip = self._pchip.derivative()
        self._e_end = float(t[-1])
        self._rh_end = float(r[-1])
        if self._rh_end < 1.0:
            self.tail_exponent = self._e_end * last_secant / (self._rh_end * -math.log(self._rh_end))
        else:
            self.tail_exponent = math.inf  # no tail: RH_iso = 1 beyond the table

    def __repr__(self) -> str:
        return f"TableIsotherm(name={self.name!r}, points={self.table_rh.size}, rh_max={self._rh_end})"

    def _thickness(self, rh):
        rh = np.asarray(rh, dtype=float)
        out = np.empty(rh.shape)
        inside = rh <= self._rh_end
        if np.any(inside):
            out[inside] = self._invert(rh[inside])
        tail = ~inside
        if np.any(tail):
            lr = np.log(rh[tail])
            with np.errstate(divide="ignore", over="ignore"):
                ratio = math.log(self._rh_end) / np.where(lr < 0.0, lr, -1.0)
                out[tail] = np.where(lr < 0.0, self._e_end * ratio ** (1.0 / self.tail_exponent), np.inf)
        return out

    def _invert(self, rh: np.ndarray) -> np.ndarray:
        """Thickness with PCHIP(thickness) == rh, by bisection inside the bracketing table interval."""
        r, t = self.table_rh, self.table_thickness
        i = np.clip(np.searchsorted(r, rh, side="right") - 1, 0, r.size - 2)
        lo, hi = t[i].copy(), t[i + 1].copy()
        # the interpolant is monotone on [t_i, t_i+1] and takes the values r_i, r_i+1 at the
        # ends, so the root is bracketed; 80 halvings reach round-off for any interval
        for _ in range(80):
            mid = 0.5 * (lo + hi)
            below = self._pchip(mid) < rh
            lo = np.where(below, mid, lo)
            hi = np.where(below, hi, mid)
        out = 0.5 * (lo + hi)
        # table points map exactly onto their thickness (RH = 0 onto a zero film)
        exact = r[i] == rh
        return np.where(exact, t[i], out)

    def _relative_humidity(self, e):
        e = np.asarray(e, dtype=float)
        inside = e <= self._e_end
        out = np.ones(e.shape)
        if np.any(inside):
            out[inside] = self._pchip(e[inside])
        tail = ~inside
        if np.any(tail) and self._rh_end < 1.0:
            out[tail] = np.exp(math.log(self._rh_end) * (self._e_end / e[tail]) ** self.tail_exponent)
        return out

    def _log_rh_above_floor(self, e):
        e = np.asarray(e, dtype=float)
        inside = e <= self._e_end
        ei = np.where(inside, e, self._e_end)  # keep the PCHIP inside its range on every node
        r = self._pchip(ei)
        g = np.log(r)
        dg = self._dpchip(ei) / r
        if not np.all(inside):
            if self._rh_end < 1.0:
                gt = math.log(self._rh_end) * (self._e_end / np.where(inside, self._e_end, e)) ** self.tail_exponent
                g = np.where(inside, g, gt)
                dg = np.where(inside, dg, -self.tail_exponent * gt / np.where(inside, self._e_end, e))
            else:
                g = np.where(inside, g, 0.0)
                dg = np.where(inside, dg, 0.0)
        return g, dg


# ----------------------------------------------------------------------------- FHH
class FHHIsotherm(Isotherm):
    """Frenkel-Halsey-Hill multilayer isotherm ``ln RH = -a (monolayer / e)^exponent``.

    Parameters
    ----------
    a : float
        Dimensionless strength A > 0 (``-ln RH`` at which the film is one monolayer thick).
    monolayer : float
        Thickness of one monolayer e_m in m (> 0); default one water molecule, 0.28 nm.
    exponent : float
        FHH exponent s > 0 (dimensionless); 2-3 for van der Waals dominated multilayers,
        default 3 (the non-retarded van der Waals value).
    name : str, optional
        Name used in reports.

    Notes
    -----
    ``thickness(RH) = e_m (a / (-ln RH))^(1/s)``, 0 at RH = 0 and ``inf`` at RH = 1;
    ``Pi(e) = (R_g T / V) a (e_m / e)^s`` and ``dPi/de = -s Pi / e``.
    """

    def __init__(self, a: float, monolayer: float = 0.28e-9, exponent: float = 3.0, name: str | None = None):
        for field, v in (("isotherm.fhh.a", a), ("isotherm.fhh.monolayer", monolayer), ("isotherm.fhh.exponent", exponent)):
            try:
                ok = math.isfinite(float(v)) and float(v) > 0.0
            except (TypeError, ValueError):
                ok = False
            if not ok:
                raise InputError(field, f"must be a finite number > 0, got {v!r}")
        self.a = float(a)
        self.monolayer = float(monolayer)
        self.exponent = float(exponent)
        self.name = name or "FHH"

    def __repr__(self) -> str:
        return f"FHHIsotherm(a={self.a!r}, monolayer={self.monolayer!r}, exponent={self.exponent!r})"

    def _thickness(self, rh):
        rh = np.asarray(rh, dtype=float)
        with np.errstate(divide="ignore"):
            x = -np.log(rh)  # +inf at RH = 0, 0 at RH = 1
            return self.monolayer * (self.a / x) ** (1.0 / self.exponent)

    def _relative_humidity(self, e):
        e = np.asarray(e, dtype=float)
        with np.errstate(divide="ignore"):
            return np.exp(-self.a * (self.monolayer / e) ** self.exponent)

    def _log_rh_above_floor(self, e):
        g = -self.a * (self.monolayer / e) ** self.exponent
        return g, -self.exponent * g / e


# ----------------------------------------------------------------------------- dry
class DryIsotherm(Isotherm):
    """A body that adsorbs no water: zero film at every RH (e.g. Paper B's rigid dry flat).

    It has no disjoining pressure and no inverse: :meth:`relative_humidity` and
    :meth:`disjoining_pressure` raise :class:`InputError`; the film solvers return a zero
    film for it directly.
    """

    name = "dry"

    @property
    def dry(self) -> bool:
        """Always True: the body adsorbs no water."""
        return True

    @property
    def floor(self) -> float:
        """0 m: there is no film, so no floor thickness."""
        return 0.0

    def __repr__(self) -> str:
        return "DryIsotherm()"

    def _thickness(self, rh):
        return np.zeros(np.shape(rh))

    def _relative_humidity(self, e):
        raise InputError("isotherm", "a dry body has no film: RH_iso(e) is undefined")

    def _log_rh_above_floor(self, e):
        raise InputError("isotherm", "a dry body has no film: its disjoining pressure is undefined")

    def _log_rh(self, e):
        raise InputError("isotherm", "a dry body has no film: its disjoining pressure is undefined")


# ----------------------------------------------------------------------------- shipped defaults
#: The shipped SiO2 table: (RH, thickness in m). APPROXIMATE (shape of Asay and Kim 2005).
SIO2_TABLE = (
    (0.0, 0.10, 0.20, 0.30, 0.35, 0.40, 0.50, 0.60, 0.70, 0.80, 0.90, 0.95),
    tuple(v * 1e-9 for v in (0.0, 0.30, 0.55, 0.80, 0.90, 0.95, 1.05, 1.20, 1.35, 1.60, 2.00, 2.60)),
)

#: Water on hydrophilic SiO2 (APPROXIMATE default; 0.9 nm at 35 % RH as in Paper C).
SIO2 = TableIsotherm(SIO2_TABLE[0], SIO2_TABLE[1], name="SiO2")

#: Water on Si with its native oxide (APPROXIMATE default: two thirds of SiO2; 0.6 nm at 35 % RH).
SI = TableIsotherm(SIO2_TABLE[0], [2.0 * v / 3.0 for v in SIO2_TABLE[1]], name="Si")

_NAMED = {"sio2": SIO2, "si": SI}


def isotherm_from_spec(spec, field: str = "film.isotherm") -> Isotherm:
    """Build an isotherm from a scenario value (file-contract ``film = { isotherm = ... }``).

    Parameters
    ----------
    spec : str, dict, Isotherm or None
        ``"SiO2"`` | ``"Si"`` (case-insensitive) | ``"dry"`` / ``"none"`` / ``None`` |
        ``{"rh": [...], "thickness": [...]}`` (thickness in m, or strings with a length unit)
        | ``{"fhh": {"a": A, "monolayer": e_m, "exponent": s}}`` (monolayer in m or with a
        unit; exponent optional, default 3) | an :class:`Isotherm` (returned as is). A dict
        ``{"isotherm": ...}`` (the whole ``film`` table) is unwrapped.
    field : str
        Name of the input for error messages.

    Returns
    -------
    Isotherm

    Raises
    ------
    InputError
        Unknown name, unknown keys, or an invalid table / FHH parameters.
    """
    if spec is None:
        return DryIsotherm()
    if isinstance(spec, Isotherm):
        return spec
    if isinstance(spec, str):
        key = spec.strip().lower()
        if key in ("dry", "none"):
            return DryIsotherm()
        if key in _NAMED:
            return _NAMED[key]
        raise InputError(field, f"unknown isotherm {spec!r}; use 'SiO2', 'Si', 'dry', a table {{rh, thickness}} "
                                "or {fhh = {...}}")
    if isinstance(spec, dict):
        keys = set(spec)
        if keys == {"isotherm"}:
            return isotherm_from_spec(spec["isotherm"], field)
        if keys == {"rh", "thickness"}:
            thick = spec["thickness"]
            if not isinstance(thick, (list, tuple, np.ndarray)):
                raise InputError(f"{field}.thickness", f"must be a list of lengths, got {thick!r}")
            t = [to_si(v, "length", f"{field}.thickness") for v in thick]
            rh = spec["rh"]
            if not isinstance(rh, (list, tuple, np.ndarray)):
                raise InputError(f"{field}.rh", f"must be a list of fractions, got {rh!r}")
            try:
                return TableIsotherm(rh, t)
            except InputError as exc:
                raise InputError(field, str(exc)) from None
        if keys == {"fhh"} and isinstance(spec["fhh"], dict):
            p = dict(spec["fhh"])
            unknown = set(p) - {"a", "monolayer", "exponent"}
            if unknown or "a" not in p:
                raise InputError(f"{field}.fhh", f"takes a (required), monolayer and exponent; got {sorted(p)}")
            kwargs = {"a": to_si(p["a"], "dimensionless", f"{field}.fhh.a")}
            if "monolayer" in p:
                kwargs["monolayer"] = to_si(p["monolayer"], "length", f"{field}.fhh.monolayer")
            if "exponent" in p:
                kwargs["exponent"] = to_si(p["exponent"], "dimensionless", f"{field}.fhh.exponent")
            return FHHIsotherm(**kwargs)
        raise InputError(field, f"a table needs exactly the keys rh and thickness, or fhh = {{...}}; got {sorted(keys)}")
    raise InputError(field, f"expected a name, a table or None, got {spec!r}")
