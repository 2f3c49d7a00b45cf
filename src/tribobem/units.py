"""Physical quantities with units: parsing user input to SI, and choosing display units.

Numbers are taken as SI already (m, N, Pa, J/m^2).  Strings may carry a unit and are parsed
with :mod:`pint` (``"10 uN"``, ``"0.2 nm"``, ``"130 GPa"``, ``"50 mJ/m^2"``, ``"5 µm"``);
their dimensionality is checked against the expected one, so a length given where a force is
expected is an error that names the input key::

    >>> to_si("10 uN", "force")
    1e-05
    >>> to_si("3 nm", "force", field="load.force")
    Traceback (most recent call last):
    ...
    tribobem.errors.InputError: load.force: expected a force (N), got '3 nm'
"""

from __future__ import annotations

import math
import re
from functools import lru_cache
from numbers import Integral, Real

from .errors import InputError

__all__ = ["DIMENSIONS", "UnitMismatch", "to_si", "convert", "parse_quantity", "si_value", "si_unit", "registry",
           "display_unit", "format_quantity", "format_value", "ZERO_FRACTION"]

#: Known dimensions: name -> (pint dimensionality, SI unit, description used in messages).
DIMENSIONS: dict[str, tuple[str, str, str]] = {
    "length": ("[length]", "m", "a length"),
    "area": ("[length] ** 2", "m^2", "an area"),
    "force": ("[force]", "N", "a force"),
    "pressure": ("[pressure]", "Pa", "a pressure"),
    "modulus": ("[pressure]", "Pa", "an elastic modulus"),
    "stress": ("[pressure]", "Pa", "a stress"),
    "surface_energy": ("[energy] / [length] ** 2", "J/m^2", "a work of adhesion / surface energy"),
    "surface_tension": ("[force] / [length]", "N/m", "a surface tension"),
    "stiffness": ("[force] / [length]", "N/m", "a stiffness"),
    "energy": ("[energy]", "J", "an energy"),
    "temperature": ("[temperature]", "K", "a temperature"),
    "molar_volume": ("[length] ** 3 / [substance]", "m^3/mol", "a molar volume"),
    "time": ("[time]", "s", "a time"),
    "dimensionless": ("", "", "a dimensionless number"),
}

# Spellings pint does not know, replaced before parsing.
_ALIASES = (
    (re.compile(r"\u00b5|\u03bc"), "u"),  # micro sign / Greek mu -> u (pint knows um, uN)
    (re.compile(r"\bmicrons?\b"), "um"),
    (re.compile(r"\u00c5|\u212b"), "angstrom"),
)


@lru_cache(maxsize=1)
def registry():
    """The shared :class:`pint.UnitRegistry`.

    Built on first use and cached, so that importing tribobem (and every scenario without a
    unit string) does not pay for building it; ``%RH`` (``percent_rh``) is defined on it.

    Returns
    -------
    pint.UnitRegistry
        The same registry at every call.
    """
    import pint

    ureg = pint.UnitRegistry()
    ureg.define("percent_rh = 0.01 = %RH")
    return ureg


def _describe(dimension: str) -> tuple[str, str, str]:
    try:
        return DIMENSIONS[dimension]
    except KeyError:
        raise ValueError(f"unknown dimension {dimension!r}; known: {', '.join(DIMENSIONS)}") from None


class UnitMismatch(ValueError):
    """A value that is not a valid quantity of the expected dimension (message without the
    field name; :func:`to_si` adds it)."""


def to_si(value, dimension: str, field: str = "value") -> float:
    """Convert a number or a string with a unit to a float in SI units.

    Parameters
    ----------
    value : float, int or str
        A number (taken as SI) or a string such as ``"10 uN"`` / ``"130 GPa"``.  A string
        without a unit (``"1e-9"``) is taken as SI too.  ``"inf"`` is accepted (a rigid
        modulus); the caller checks ranges.
    dimension : str
        One of :data:`DIMENSIONS` (``"length"``, ``"force"``, ``"pressure"``,
        ``"surface_energy"``, ...).
    field : str
        Name of the input (e.g. ``"load.force"``), used in error messages.

    Returns
    -------
    float
        The value in SI units (m, N, Pa, J/m^2, K, ...).

    Raises
    ------
    InputError
        If the string cannot be parsed, or has the wrong dimensionality, e.g.
        ``load.force: expected a force (N), got '3 nm'``.
    """
    try:
        return convert(value, dimension)
    except UnitMismatch as exc:
        raise InputError(field, str(exc)) from None


def convert(value, dimension: str) -> float:
    """:func:`to_si` without the field name: raises :class:`UnitMismatch` (a ValueError).

    For callers that attach their own context to the error (a schema validator, a table
    column) instead of :func:`to_si`'s ``field: message``.

    Parameters
    ----------
    value : float, int or str
        A number (taken as SI) or a string with a unit, as for :func:`to_si`.
    dimension : str
        One of :data:`DIMENSIONS`.

    Returns
    -------
    float
        The value in SI units.

    Raises
    ------
    UnitMismatch
        An unparsable string, the wrong dimensionality, a boolean or NaN.
    ValueError
        An unknown ``dimension``.
    """
    dim, si, what = _describe(dimension)
    unit_hint = f" ({si})" if si else ""
    if isinstance(value, bool):
        raise UnitMismatch(f"expected {what}{unit_hint}, got {value!r}")
    if isinstance(value, Real):
        return float(value)
    if not isinstance(value, str):
        raise UnitMismatch(f"expected {what}{unit_hint} as a number or a string with a unit, got {value!r}")
    text = value.strip()
    if not text:
        raise UnitMismatch(f"expected {what}{unit_hint}, got an empty string")
    try:
        return float(text)  # plain number in a string: SI
    except ValueError:
        pass
    ureg = registry()
    try:
        q = _parse(text)
    except Exception as exc:  # pint raises several types (UndefinedUnitError, DefinitionSyntaxError, ...)
        raise UnitMismatch(f"cannot parse {value!r} as {what}{unit_hint}: {_short(exc)}") from None
    if not hasattr(q, "dimensionality"):
        return float(q)
    want = ureg.Quantity(1, si).dimensionality if si else ureg.Quantity(1).dimensionality
    if q.dimensionality != want:
        raise UnitMismatch(f"expected {what}{unit_hint}, got {value!r}")
    try:
        out = float(q.to(si).magnitude) if si else float(q.to("").magnitude)
    except Exception as exc:  # offset units (degC) etc.
        raise UnitMismatch(f"cannot convert {value!r} to {si or 'a number'}: {_short(exc)}") from None
    if math.isnan(out):
        raise UnitMismatch(f"expected {what}{unit_hint}, got NaN")
    # round away the binary noise of the prefix conversion (10 uN -> 1e-05, not 9.999...e-06)
    return float(f"{out:.14g}") if math.isfinite(out) else out


def _short(exc: BaseException) -> str:
    return " ".join(str(exc).split())[:200]


def _parse(text: str):
    """``text`` (aliases replaced) parsed by the shared registry; pint's exceptions pass through."""
    for pattern, repl in _ALIASES:
        text = pattern.sub(repl, text)
    return registry().Quantity(text)


# ----------------------------------------------------------------------------- dimension-free parsing
def parse_quantity(text: str):
    """A string with a unit as a :class:`pint.Quantity` of the shared registry, or None.

    The spellings :func:`convert` accepts (``µm``, ``micron``, ``Å``) are accepted here too.

    Parameters
    ----------
    text : str
        E.g. ``"30 mJ/m^2"``.

    Returns
    -------
    pint.Quantity or None
        None when pint cannot parse the string or it is not a quantity (a plain number).
    """
    try:
        q = _parse(text)
    except Exception:  # pint raises several types
        return None
    return q if hasattr(q, "dimensionality") else None


def si_value(value):
    """A number, or a string with units (``"30 mJ/m^2"``, ``"100 um"``), as an SI float, with no
    expected dimension (the value in SI base units).

    Integers stay integers; other values (booleans, None, strings that are not quantities,
    tables) come back unchanged.  Parameter grids (:mod:`tribobem.sweep`) use it to give every
    swept value a numerical coordinate.

    Parameters
    ----------
    value : object
        Any scenario value.

    Returns
    -------
    int, float or object
        The SI float (base units, rounded to 14 significant digits), an int for an int, or
        ``value`` itself.
    """
    if isinstance(value, bool) or value is None:
        return value
    if isinstance(value, Integral):
        return int(value)
    if isinstance(value, Real):
        return float(value)
    if isinstance(value, str):
        try:
            return float(value)
        except ValueError:
            pass
        q = parse_quantity(value.strip())
        if q is None:
            return value
        try:
            mag = float(q.to_base_units().magnitude)
        except Exception:
            return value
        return float(f"{mag:.14g}")  # "100 um" -> 1e-4, not 9.999999999999999e-05
    return value


def si_unit(value) -> str:
    """The SI base unit of a quantity string, in pint's spelling.

    The companion of :func:`si_value`: the unit its number is in.

    Parameters
    ----------
    value : object
        Any scenario value.

    Returns
    -------
    str
        E.g. ``"kilogram / meter / second ** 2"`` for ``"130 GPa"``; ``""`` for anything else
        (a number, a plain-number string, an unparsable string).
    """
    if not isinstance(value, str):
        return ""
    try:
        float(value)
        return ""
    except ValueError:
        pass
    q = parse_quantity(value.strip())
    try:
        return str(q.to_base_units().units) if q is not None else ""
    except Exception:
        return ""


# ----------------------------------------------------------------------------- display units
_PREFIXES = (("G", 1e9), ("M", 1e6), ("k", 1e3), ("", 1.0), ("m", 1e-3), ("u", 1e-6), ("n", 1e-9), ("p", 1e-12),
             ("f", 1e-15), ("a", 1e-18))
_LENGTH_CHOICES = (("m", 1.0), ("mm", 1e-3), ("um", 1e-6), ("nm", 1e-9), ("pm", 1e-12))


def display_unit(values, dimension: str, ascii_only: bool = False) -> tuple[float, str]:
    """A readable display unit for a set of values.

    Parameters
    ----------
    values : array_like or float
        Values in SI units.
    dimension : {"length", "force", "pressure", "area", "energy"}
    ascii_only : bool
        Write "u" instead of the micro sign.

    Returns
    -------
    (factor, label)
        Divide SI values by ``factor`` to express them in ``label`` (e.g. ``(1e-9, "nm")``).
        The unit is chosen so that the largest magnitude lies in [1, 1000).
    """
    import numpy as np

    a = np.abs(np.asarray(values, dtype=float))
    a = a[np.isfinite(a) & (a > 0)]
    peak = float(a.max()) if a.size else 1.0
    micro = "u" if ascii_only else "\u00b5"
    if dimension == "length":
        choices = _LENGTH_CHOICES
        base = None
    elif dimension == "area":
        choices = (("m\u00b2", 1.0), ("mm\u00b2", 1e-6), (f"{micro}m\u00b2", 1e-12), ("nm\u00b2", 1e-18))
        if ascii_only:
            choices = (("m^2", 1.0), ("mm^2", 1e-6), ("um^2", 1e-12), ("nm^2", 1e-18))
        base = None
    else:
        base = {"force": "N", "pressure": "Pa", "energy": "J"}.get(dimension)
        if base is None:
            return 1.0, DIMENSIONS.get(dimension, ("", "", ""))[1]
        choices = tuple((p + base, f) for p, f in _PREFIXES)
        if dimension == "pressure":  # kPa..GPa only
            choices = tuple(c for c in choices if c[1] >= 1.0)
    for label, factor in choices:
        if peak >= factor * (1 - 1e-12):
            break
    label = label.replace("u", micro, 1) if (label.startswith("u") and not ascii_only) else label
    return factor, label


def format_quantity(value, dimension: str, digits: int = 4, ascii_only: bool = False) -> str:
    """``value`` (SI) as a string in a readable unit, e.g. ``format_quantity(1.2e-6, "force")
    == '1.2 µN'``.

    Parameters
    ----------
    value : float or None
        The value in SI units.
    dimension : str
        As for :func:`display_unit`.
    digits : int
        Significant digits.
    ascii_only : bool
        Write "u" instead of the micro sign.

    Returns
    -------
    str
        ``"<number> <unit>"``; ``"n/a"`` for None, ``str(value)`` for a non-number or a
        non-finite value.
    """
    if value is None:
        return "n/a"
    try:
        v = float(value)
    except (TypeError, ValueError):
        return str(value)
    if not math.isfinite(v):
        return str(v)
    if v != 0.0:
        v = float(f"{v:.{digits}g}")  # round first: the unit then fits the printed number (1 µN, not 1e+03 nN)
    factor, label = display_unit([v], dimension, ascii_only=ascii_only)
    scaled = v / factor
    text = f"{scaled:.0f}" if abs(scaled) >= 10**digits and abs(scaled) < 1e7 else f"{scaled:.{digits}g}"
    return f"{text} {label}".strip()


#: A value below this fraction of its scale prints as 0 (:func:`format_value`).  The net force of
#: an adhesive state is the difference of a repulsive and an adhesive part of nearly equal size,
#: which the iterative solves resolve to about 1e-6 of either (the demo's state at zero external
#: load: -0.43 pN from 363 nN against -363 nN); 1e-5 of the run's largest force is below
#: anything a figure or a 4-digit table can show next to that force.
ZERO_FRACTION = 1e-5


def format_value(value, dimension: str, digits: int = 3, scale=None, zero_fraction: float = ZERO_FRACTION,
                 ascii_only: bool = False) -> str:
    """``value`` (SI) for a title or a table: rounded before its unit is chosen, and 0 when it is
    solver noise against ``scale``.

    As :func:`format_quantity` (the value rounded to ``digits`` significant digits before its
    unit is chosen: ``"1 µN"``, not ``"1e+03 nN"``), and a value whose magnitude is at most
    ``zero_fraction`` x ``|scale|`` prints as ``"0 <SI unit>"`` (e.g. the -4e-13 N of a state solved at zero load, against a run's
    force of 2.5e-7 N).

    Parameters
    ----------
    value : float or None
        The value in SI units.
    dimension : str
        As for :func:`display_unit` (``"force"``, ``"length"``, ``"pressure"`` ...).
    digits : int
        Significant digits.
    scale : float or array_like, optional
        The magnitude the value is read against, in the same SI unit (e.g. the largest force
        of the run, N); an array: its largest finite magnitude.  None: no value is zeroed.
    zero_fraction : float
        Fraction of ``scale`` at or below which the value prints as 0 (dimensionless).
    ascii_only : bool
        Write "u" instead of the micro sign.

    Returns
    -------
    str
        ``"<number> <unit>"``; ``"n/a"`` for None, ``str(value)`` for a non-number or a
        non-finite value.

    Examples
    --------
    >>> format_value(9.9999999e-7, "force")
    '1 µN'
    >>> format_value(-4e-16, "force", scale=1e-6)
    '0 N'
    """
    if value is None:
        return "n/a"
    try:
        v = float(value)
    except (TypeError, ValueError):
        return str(value)
    if not math.isfinite(v):
        return str(v)
    if scale is not None:
        import numpy as np

        a = np.abs(np.asarray(scale, dtype=float)).ravel()
        a = a[np.isfinite(a)]
        if a.size and abs(v) <= zero_fraction * float(a.max()):
            v = 0.0
    return format_quantity(v, dimension, digits, ascii_only=ascii_only)
