"""The scenario file schema (file-contract): pydantic v2 models with strict key checking.

A scenario is a TOML file (or a dict) with the sections ``[grid]``, ``[body1]``, ``[body2]``,
``[load]``, ``[adhesion]``, ``[friction]``, ``[humidity]``, ``[solver]`` and ``[output]``
and the top-level keys ``kind``, ``name``, ``description`` and ``expected`` (metadata: the
value the run should give and its reference, :class:`ExpectedSpec`; the run ignores it but
echoes it in summary.json beside the computed value).

* Unknown keys are errors that name the key and list the allowed ones.
* Values with a dimension may be numbers (SI) or strings with a unit (``"10 uN"``), parsed by
  :mod:`tribobem.units`; a value of the wrong dimension is an error naming the key.
* Ranges are checked (``nu`` in (-1, 0.5], ``E > 0``, ``n >= 8``, ``rh`` in (0, 1], ...).

:func:`parse_scenario` turns a dict into a :class:`Scenario` with every quantity in SI, or
raises :class:`ScenarioError` (an :class:`~tribobem.errors.InputError`) whose message lists
each problem as ``section.key: what is wrong``.
"""

from __future__ import annotations

import math
from typing import Annotated, Any, Literal, Optional, Union

from pydantic import (BaseModel, BeforeValidator, ConfigDict, Field, PlainValidator, SerializeAsAny, StrictBool,
                      TypeAdapter, ValidationError, model_validator)
from pydantic_core import PydanticCustomError

from ..errors import InputError
from ..runs import KINDS as RUN_KINDS
from ..runs import RUNNERS
from ..units import DIMENSIONS, UnitMismatch, convert
from ..interactions.base import NoInteraction
from ..interactions.dugdale import SoftenedDugdale, build_dugdale
from ..interactions.exponential import ExponentialAdhesion
from ..interactions.lennard_jones import LennardJonesAdhesion
from ..interactions.isotherms import isotherm_from_spec
from ..interactions.registry import LAWS, one_of, register_law
from ..units import registry

__all__ = [
    "KINDS",
    "IMPLEMENTED_KINDS",
    "Scenario",
    "ScenarioError",
    "parse_scenario",
    "GridSpec",
    "BodySpec",
    "LoadSpec",
    "AdhesionSpec",
    "NoAdhesionSpec",
    "DugdaleAdhesionSpec", "ExponentialAdhesionSpec", "LennardJonesAdhesionSpec",
    "adhesion_model",
    "FrictionSpec",
    "HumiditySpec",
    "SolverSpec",
    "OutputSpec",
    "ExpectedSpec",
    "EXPECTED_KEYS",
]

#: Run kinds the schema accepts: those of the registry :data:`tribobem.runs.KINDS`.
KINDS = tuple(RUN_KINDS)
#: Run kinds this version can run (every kind of the registry has a runner).
IMPLEMENTED_KINDS = tuple(k for k in KINDS if k in RUNNERS)


# ----------------------------------------------------------------------------- errors
class ScenarioError(InputError):
    """One or more problems in a scenario; ``errors`` lists ``(field, message)`` pairs.

    All problems are collected and raised together, so a user fixes a scenario in one pass
    rather than one error per run.

    Parameters
    ----------
    errors : list of (str, str)
        ``(field, message)`` pairs, at least one; the first gives ``field``.
    source : str, optional
        The scenario file, quoted in the message.
    """

    def __init__(self, errors: list[tuple[str, str]], source: str | None = None):
        self.errors = list(errors)
        self.source = source
        first_field, first_msg = self.errors[0]
        self.field = first_field
        where = f" in {source}" if source else ""
        if len(self.errors) == 1:
            text = f"{first_field}: {first_msg}"
            if source:
                text = f"{text} ({source})"
        else:
            text = f"{len(self.errors)} problems{where}: " + "; ".join(f"{f}: {m}" for f, m in self.errors)
        Exception.__init__(self, text)


def _fail(key: str | None, message: str):
    """Raise a validation error for ``key`` (dotted, relative to the current section)."""
    raise PydanticCustomError("scenario", "{message}", {"message": message, "key": key or ""})


def _fmt(v) -> str:
    return f"{v:g}" if isinstance(v, float) else repr(v)


def _range_text(gt=None, ge=None, lt=None, le=None, unit: str = "") -> str:
    u = f" {unit}" if unit else ""
    lo = f"({_fmt(gt)}" if gt is not None else (f"[{_fmt(ge)}" if ge is not None else None)
    hi = f"{_fmt(lt)})" if lt is not None else (f"{_fmt(le)}]" if le is not None else None)
    if lo and hi:
        return f"in {lo}, {hi}{u}"
    if gt is not None:
        return f"> {_fmt(gt)}{u}"
    if ge is not None:
        return f">= {_fmt(ge)}{u}"
    if lt is not None:
        return f"< {_fmt(lt)}{u}"
    if le is not None:
        return f"<= {_fmt(le)}{u}"
    return "finite"


def _check_range(v: float, raw, gt, ge, lt, le, unit: str, allow_inf: bool = False) -> float:
    if math.isnan(v) or (math.isinf(v) and not allow_inf):
        raise PydanticCustomError("range", "{message}", {"message": f"must be a finite number, got {raw!r}"})
    bad = ((gt is not None and not v > gt) or (ge is not None and not v >= ge)
           or (lt is not None and not v < lt) or (le is not None and not v <= le))
    if bad:
        got = repr(raw) if isinstance(raw, str) else _fmt(v)
        raise PydanticCustomError("range", "{message}", {"message": f"must be {_range_text(gt, ge, lt, le, unit)}, got {got}"})
    return v


def Quantity(dimension: str, *, gt=None, ge=None, lt=None, le=None, allow_inf: bool = False):
    """A float with a dimension: number (SI) or string with a unit, range-checked."""
    unit = DIMENSIONS[dimension][1]

    def validate(raw):
        try:
            v = convert(raw, dimension)
        except UnitMismatch as exc:
            raise PydanticCustomError("quantity", "{message}", {"message": str(exc)}) from None
        return _check_range(v, raw, gt, ge, lt, le, unit, allow_inf)

    return Annotated[float, BeforeValidator(validate)]


def Number(*, gt=None, ge=None, lt=None, le=None):
    """A dimensionless float (a number, or a string such as ``"30 %"``), range-checked."""
    return Quantity("dimensionless", gt=gt, ge=ge, lt=lt, le=le)


def RelativeHumidity():
    """A relative humidity: a fraction in (0, 1] (a number, or a string such as ``"40 %"``).

    A bare number in (1, 100] is refused with the fraction it most likely means: RH is not
    given in per cent."""
    def hint(raw):
        if isinstance(raw, (int, float)) and not isinstance(raw, bool) and 1.0 < raw <= 100.0:
            raise PydanticCustomError("range", "{message}", {
                "message": f"relative humidity is a fraction in (0, 1], not per cent: write {raw / 100:g} "
                           f"(or '{raw:g} %') for {raw:g} %, got {raw!r}"})
        return raw

    return Annotated[Number(gt=0, le=1), BeforeValidator(hint)]


def Int(*, ge=None, le=None):
    """An integer (no bools, no fractional floats), range-checked."""
    def validate(raw):
        if isinstance(raw, bool) or not (isinstance(raw, int) or (isinstance(raw, float) and raw.is_integer())):
            raise PydanticCustomError("int", "{message}", {"message": f"must be an integer, got {raw!r}"})
        v = int(raw)
        if (ge is not None and v < ge) or (le is not None and v > le):
            raise PydanticCustomError("range", "{message}",
                                      {"message": f"must be an integer {_range_text(ge=ge, le=le)}, got {raw!r}"})
        return v

    return Annotated[int, BeforeValidator(validate)]


def QuantityList(dimension: str, *, gt=None, ge=None, lt=None, le=None, min_length: int = 1, auto: bool = False):
    """A list of quantities, or a table ``{start, stop, num}`` (evenly spaced, both ends in); with
    ``auto``, also the string ``"auto"`` (the run picks the values)."""
    unit = DIMENSIONS[dimension][1]

    def one(raw, i):
        try:
            v = convert(raw, dimension)
        except UnitMismatch as exc:
            raise PydanticCustomError("quantity", "{message}", {"message": f"item {i}: {exc}"}) from None
        try:
            return _check_range(v, raw, gt, ge, lt, le, unit)
        except PydanticCustomError as exc:
            raise PydanticCustomError("range", "{message}", {"message": f"item {i}: {exc.context['message']}"}) from None

    def validate(raw):
        if auto and raw == "auto":
            return raw
        if isinstance(raw, dict):
            extra = set(raw) - {"start", "stop", "num"}
            if extra or not {"start", "stop", "num"} <= set(raw):
                raise PydanticCustomError("scenario", "{message}", {"message": (
                    "a range table needs exactly the keys start, stop, num"
                    + (f" (unknown: {', '.join(sorted(extra))})" if extra else ""))})
            num = raw["num"]
            if isinstance(num, bool) or not isinstance(num, int) or num < 1:
                raise PydanticCustomError("scenario", "{message}", {"message": f"num must be an integer >= 1, got {num!r}"})
            a, b = one(raw["start"], "start"), one(raw["stop"], "stop")
            if num == 1:
                return [a]
            return [float(f"{a + (b - a) * k / (num - 1):.14g}") for k in range(num)]
        if isinstance(raw, (str, int, float)) and not isinstance(raw, bool):
            raw = [raw]
        if not isinstance(raw, (list, tuple)):
            raise PydanticCustomError("scenario", "{message}",
                                      {"message": f"must be a list (or {{start, stop, num}}), got {raw!r}"})
        if len(raw) < min_length:
            raise PydanticCustomError("scenario", "{message}", {"message": f"needs at least {min_length} value(s)"})
        return [one(v, i) for i, v in enumerate(raw)]

    if auto:
        return Annotated[Union[Literal["auto"], list[float]], BeforeValidator(validate)]
    return Annotated[list[float], BeforeValidator(validate)]


# ----------------------------------------------------------------------------- base class
class Section(BaseModel):
    """Base of every scenario section: unknown keys are errors that list the allowed keys."""

    model_config = ConfigDict(extra="forbid", populate_by_name=False, validate_assignment=False)

    @classmethod
    def allowed_keys(cls) -> list[str]:
        return list(cls.model_fields)

    @model_validator(mode="before")
    @classmethod
    def _known_keys(cls, data: Any):
        if isinstance(data, dict):
            allowed = cls.allowed_keys()
            for key in data:
                if key not in allowed:
                    raise PydanticCustomError(
                        "unknown_key", "unknown key {key!r}; allowed keys: {allowed}",
                        {"key": str(key), "allowed": ", ".join(allowed)},
                    )
        return data


# ----------------------------------------------------------------------------- grid
class GridSpec(Section):
    """``[grid]``: ``n`` (or ``nx`` and ``ny``) cells, ``size`` (or ``lx`` and ``ly``), ``periodic``.

    ``size`` may be left out when a body's roughness is a measured file: the grid then takes
    the file's physical size (after cropping).
    """

    n: Optional[Int(ge=8)] = None
    nx: Optional[Int(ge=8)] = None
    ny: Optional[Int(ge=8)] = None
    size: Optional[Quantity("length", gt=0)] = None
    lx: Optional[Quantity("length", gt=0)] = None
    ly: Optional[Quantity("length", gt=0)] = None
    periodic: StrictBool = False

    @model_validator(mode="after")
    def _combos(self):
        if self.n is not None and (self.nx is not None or self.ny is not None):
            _fail("n", "give n or nx and ny, not both")
        if self.n is None:
            if self.nx is None and self.ny is None:
                _fail("n", "required: the number of cells per side (or nx and ny), >= 8")
            if self.nx is None or self.ny is None:
                _fail("ny" if self.ny is None else "nx", "nx and ny go together")
        if self.size is not None and (self.lx is not None or self.ly is not None):
            _fail("size", "give size or lx and ly, not both")
        if (self.lx is None) != (self.ly is None):
            _fail("ly" if self.ly is None else "lx", "lx and ly go together")
        return self

    @property
    def shape(self) -> tuple[int, int]:
        """Grid nodes (nx, ny): (n, n) when ``n`` is given, else (nx, ny) (None before sizing)."""
        return (self.n, self.n) if self.n is not None else (self.nx, self.ny)

    @property
    def lengths(self) -> tuple[float, float] | None:
        """(lx, ly) in m, or None when the size comes from a topography file."""
        if self.size is not None:
            return (self.size, self.size)
        if self.lx is not None:
            return (self.lx, self.ly)
        return None


# ----------------------------------------------------------------------------- roughness
class CropSpec(Section):
    """Region of a measured file, from its lower-left corner (m)."""

    x0: Quantity("length", ge=0) = 0.0
    y0: Quantity("length", ge=0) = 0.0
    lx: Quantity("length", gt=0)
    ly: Quantity("length", gt=0)


Pair = Annotated[list[Quantity("length")], Field(min_length=2, max_length=2)]


class NoRoughness(Section):
    kind: Literal["none"] = "none"


class GaussianRoughness(Section):
    """Gaussian surface with an exponential ACF (Hu and Tonder)."""

    kind: Literal["gaussian"]
    rms: Quantity("length", ge=0)
    correlation_length: Quantity("length", gt=0)
    correlation_length_y: Optional[Quantity("length", gt=0)] = None
    seed: Optional[Int(ge=0)] = None
    skewness: Optional[Number()] = None
    kurtosis: Optional[Number(gt=1)] = None


class SelfAffineRoughness(Section):
    """Self-affine surface with Persson's PSD; give ``rms`` or ``rms_slope``."""

    kind: Literal["self_affine"]
    hurst: Number(gt=0, le=1)
    rms: Optional[Quantity("length", ge=0)] = None
    rms_slope: Optional[Number(ge=0)] = None
    rolloff: Optional[Quantity("length", gt=0)] = None
    short_cutoff: Optional[Quantity("length", gt=0)] = None
    long_cutoff: Optional[Quantity("length", gt=0)] = None
    seed: Optional[Int(ge=0)] = None

    @model_validator(mode="after")
    def _one_rms(self):
        if (self.rms is None) == (self.rms_slope is None):
            _fail("rms", "give exactly one of rms (m) or rms_slope (-)")
        return self


Detrend = Literal["none", "center", "height", "curvature"]


class FileRoughness(Section):
    """A measured topography file (any format SurfaceTopography reads).

    ``path`` is relative to the scenario file's folder, or ``"data:NAME"`` for a measured file
    shipped with tribobem (e.g. ``"data:example_ps.tiff"``; :func:`tribobem.data.topography_path`,
    whose folder ``$TRIBOBEM_DATA_DIR`` replaces).  ``detrend`` is the trend removed from the
    scan first: ``"height"`` (the default) the least-squares plane, the convention for a
    measured scan, whose tilt is no part of the roughness, ``"center"`` only the mean,
    ``"curvature"`` the best quadratic, ``"none"`` nothing.  The scan is detrended, optionally
    cropped (``crop = {x0, y0, lx, ly}``), then resampled onto the solver grid, whose centre
    sits at ``offset`` (m) from the centre of the (cropped) scan.  ``rms`` rescales the heights;
    ``invert = true`` flips them (valleys become peaks).
    """

    kind: Literal["file"]
    path: str
    channel: Optional[Union[int, str]] = None
    detrend: Detrend = "height"
    fill: Literal["harmonic", "none"] = "harmonic"
    unit: Optional[str] = None
    physical_size: Optional[Pair] = None
    crop: Optional[CropSpec] = None
    offset: Pair = Field(default_factory=lambda: [0.0, 0.0])
    rms: Optional[Quantity("length", ge=0)] = None
    invert: StrictBool = False


class ArrayRoughness(Section):
    """Heights from a ``.npy`` file (``unit`` of the values, default m) of physical ``size``
    (or ``lx``, ``ly``; default: the grid's size, and then the array must match the grid)."""

    kind: Literal["array"]
    path: str
    size: Optional[Quantity("length", gt=0)] = None
    lx: Optional[Quantity("length", gt=0)] = None
    ly: Optional[Quantity("length", gt=0)] = None
    unit: str = "m"
    detrend: Detrend = "none"
    crop: Optional[CropSpec] = None
    offset: Pair = Field(default_factory=lambda: [0.0, 0.0])
    rms: Optional[Quantity("length", ge=0)] = None
    invert: StrictBool = False

    @model_validator(mode="after")
    def _sizes(self):
        if self.size is not None and (self.lx is not None or self.ly is not None):
            _fail("size", "give size or lx and ly, not both")
        if (self.lx is None) != (self.ly is None):
            _fail("ly" if self.ly is None else "lx", "lx and ly go together")
        return self


ROUGHNESS_KINDS = ("none", "gaussian", "self_affine", "file", "array")
Roughness = Annotated[
    Union[NoRoughness, GaussianRoughness, SelfAffineRoughness, FileRoughness, ArrayRoughness],
    Field(discriminator="kind"),
]


def Angle():
    """An angle in degrees: a number (degrees) or a string with an angle unit (``"30 deg"``,
    ``"0.5 rad"``), finite."""
    angle_units = {"degree", "radian", "arcminute", "arcsecond", "turn", "gradian"}

    def validate(raw):
        message = f"expected an angle in degrees (a number, or a string such as \"30 deg\"), got {raw!r}"
        if isinstance(raw, bool):
            raise PydanticCustomError("quantity", "{message}", {"message": message})
        if isinstance(raw, (int, float)):
            v = float(raw)
        elif isinstance(raw, str):
            try:
                v = float(raw.strip())
            except ValueError:

                try:
                    q = registry().Quantity(raw.strip())
                except Exception:
                    raise PydanticCustomError("quantity", "{message}", {"message": message}) from None
                if not hasattr(q, "units") or str(q.units) not in angle_units:
                    raise PydanticCustomError("quantity", "{message}", {"message": message})
                v = float(q.to("degree").magnitude)
        else:
            raise PydanticCustomError("quantity", "{message}", {"message": message})
        return _check_range(v, raw, None, None, None, None, "deg")

    return Annotated[float, BeforeValidator(validate)]


# ----------------------------------------------------------------------------- shapes
class FlatShape(Section):
    kind: Literal["flat"] = "flat"


class SphereShape(Section):
    """Sphere of ``radius`` (paraboloid, or the exact cap with ``exact = true``)."""

    kind: Literal["sphere"]
    radius: Quantity("length", gt=0)
    exact: StrictBool = False
    center: Pair = Field(default_factory=lambda: [0.0, 0.0])


class CylinderShape(Section):
    kind: Literal["cylinder"]
    radius: Quantity("length", gt=0)
    axis: Literal["x", "y"] = "y"
    center: Quantity("length") = 0.0


class WavySphereShape(Section):
    """r^2/(2R) + A (1 - cos(2 pi r / wavelength)) (Guduru; Paper A)."""

    kind: Literal["wavy_sphere"]
    radius: Quantity("length", gt=0)
    amplitude: Quantity("length", ge=0)
    wavelength: Quantity("length", gt=0)
    center: Pair = Field(default_factory=lambda: [0.0, 0.0])


class BisinusoidalShape(Section):
    """S cos(2 pi x/wx) cos(2 pi y/wy) (Paper A Eq. 31); wavelengths default to the grid sides."""

    kind: Literal["bisinusoidal"]
    amplitude: Quantity("length", ge=0)
    wavelength_x: Optional[Quantity("length", gt=0)] = None
    wavelength_y: Optional[Quantity("length", gt=0)] = None


class BurlShape(Section):
    """A burl (the rounded flat punch): a flat top whose edge rounds off, optionally crowned.

    ``h(r) = max(r - b, 0)^2 / (2 R) + r^2 / (2 R_c)`` (m, positive away from the interface, like
    the sphere; :func:`tribobem.geometry.shapes.burl`).

    ============  ====  ========  =====================================================
    key           unit  default   meaning
    ============  ====  ========  =====================================================
    radius        m     required  radius ``b`` of the flat top, > 0, at most half the
                                  smaller side of the grid
    edge_radius   m     required  radius ``R`` of the rounded edge beyond ``r = b``, > 0
    crown         m     none      radius ``R_c`` of a spherical crown over the whole
                                  burl, > 0 (none: a flat top)
    center        m     [0, 0]    position (x0, y0) of the axis from the domain centre
    ============  ====  ========  =====================================================

    References: :mod:`tribobem.analytic.punch` (rounded punch, flat punch, Kendall's pull-off,
    the full-stick tangential stiffness), checked by ``tribobem validate --physics burl``.
    """

    kind: Literal["burl"]
    radius: Quantity("length", gt=0)
    edge_radius: Quantity("length", gt=0)
    crown: Optional[Quantity("length", gt=0)] = None
    center: Pair = Field(default_factory=lambda: [0.0, 0.0])


SHAPE_KINDS = ("flat", "sphere", "cylinder", "wavy_sphere", "bisinusoidal", "burl")
Shape = Annotated[
    Union[FlatShape, SphereShape, CylinderShape, WavySphereShape, BisinusoidalShape, BurlShape],
    Field(discriminator="kind"),
]


# ----------------------------------------------------------------------------- textures, waviness
class TextureSpec(Section):
    """``texture`` of a body: a periodic pattern cut into or standing on its surface.

    Heights are part of the body's topography (positive out of the body, like ``roughness``)
    and add to its ``roughness`` and ``shape`` (:mod:`tribobem.geometry.textures`).

    ========  ====  ========  ==========================================================
    key       unit  default   meaning
    ========  ====  ========  ==========================================================
    kind      -     required  ``"dimples"`` (circular pits), ``"pillars"`` (circular
                              flat-topped pillars) or ``"grooves"`` (parallel grooves)
    pitch     m     required  period of the square lattice (dimples, pillars) or
                              distance between groove centrelines, > ``size``
    size      m     required  diameter of a pit or pillar, width of a groove, > 0
    depth     m     required  depth of a pit or groove, height of a pillar, > 0
    angle     deg   0         rotation of the lattice; direction of the grooves from
                              the x axis (0: grooves along x)
    ========  ====  ========  ==========================================================

    A lattice point (a groove's centreline) passes through the domain centre.  The grid must
    resolve the pattern: ``size`` and ``pitch - size`` each span at least 3 cells, else an
    error names the key (:func:`tribobem.geometry.textures.check_resolution`).
    """

    kind: Literal["dimples", "pillars", "grooves"]
    pitch: Quantity("length", gt=0)
    size: Quantity("length", gt=0)
    depth: Quantity("length", gt=0)
    angle: Angle() = 0.0

    @model_validator(mode="after")
    def _fits(self):
        if self.size >= self.pitch:
            _fail("size", f"must be smaller than the pitch ({self.pitch:g} m), got {self.size:g} m: the "
                          "features would merge")
        return self


class WavinessSpec(Section):
    """``waviness`` of a body: its long-wavelength form (a wafer's waviness), one sinusoid
    ``A cos(2 pi (x cos t + y sin t) / lambda)`` added to its topography (positive out of the
    body, a crest at the domain centre; :func:`tribobem.geometry.textures.waviness`).

    ==========  ====  ========  ========================================================
    key         unit  default   meaning
    ==========  ====  ========  ========================================================
    amplitude   m     required  amplitude ``A``, >= 0 (peak to valley ``2 A``)
    wavelength  m     required  wavelength ``lambda``, > 0, at least 3 cells
    angle       deg   0         direction ``t`` of the wave vector from the x axis
    ==========  ====  ========  ========================================================
    """

    amplitude: Quantity("length", ge=0)
    wavelength: Quantity("length", gt=0)
    angle: Angle() = 0.0


# ----------------------------------------------------------------------------- bodies
class FilmSpec(Section):
    """``film`` of a body (capillary kinds): the adsorption isotherm of its water film.

    ``isotherm``: ``"SiO2"`` | ``"Si"`` (the shipped approximate tables) | ``"dry"`` |
    ``{ rh = [...], thickness = [...] }`` (a measured table, monotone interpolation; thickness
    in m or strings with a length unit) | ``{ fhh = { a = ..., monolayer = ..., exponent = ... } }``
    (Frenkel-Halsey-Hill).  A body without ``film`` is dry.  Checked by
    :func:`tribobem.interactions.isotherms.isotherm_from_spec` (a non-monotone or negative
    table is an error naming the key).
    """

    isotherm: Union[str, dict[str, Any]] = "SiO2"

    @model_validator(mode="after")
    def _isotherm(self):

        try:
            isotherm_from_spec(self.isotherm, "isotherm")
        except InputError as exc:
            import re

            # the innermost "isotherm...: " prefix names the key (a table wraps its item's error)
            field, msg = "isotherm", str(exc)
            while (m := re.match(r"(isotherm[\w.\[\]]*): (.*)", msg, re.S)):
                field, msg = m.group(1), m.group(2)
            _fail(field, msg)
        return self


class LayerSpec(Section):
    """``[bodyN] layer``: an elastic layer perfectly bonded to the body (a coating); the body's
    own ``E``, ``nu`` are the substrate's.

    ==========  =====  ========  =====================================================
    key         unit   default   meaning
    ==========  =====  ========  =====================================================
    E           Pa     required  the layer's Young's modulus, > 0
    nu          -      required  the layer's Poisson's ratio in (-1, 0.5)
    thickness   m      required  the layer's thickness, > 0
    ==========  =====  ========  =====================================================
    """

    E: Quantity("modulus", gt=0)
    nu: Number(gt=-1, lt=0.5)
    thickness: Quantity("length", gt=0)


class BodySpec(Section):
    """``[body1]`` / ``[body2]``: ``E`` and ``nu`` (or ``rigid = true``), ``roughness``, ``shape``,
    ``texture``, ``waviness``; for the capillary kinds ``film`` (:class:`FilmSpec`; absent: a dry
    body) and ``hamaker``, the body's own Hamaker constant in vacuum (J, > 0; default: 19e-20 J
    for a body whose film isotherm is ``"Si"``, else SiO2's 6.5e-20 J, approximate).

    ==========  =====  ========  =====================================================
    key         unit   default   meaning
    ==========  =====  ========  =====================================================
    E           Pa     required  Young's modulus, > 0 (or ``rigid = true``)
    nu          -      required  Poisson's ratio in (-1, 0.5] (with ``E``)
    rigid       -      false     a rigid body (no ``E``, no ``nu``)
    name        -      none      label in the outputs
    roughness   -      none      random or measured heights (``kind = ...``)
    shape       -      flat      smooth shape: flat, sphere, cylinder, wavy_sphere,
                                 bisinusoidal, burl (:class:`BurlShape`)
    texture     -      none      dimples, pillars or grooves (:class:`TextureSpec`)
    waviness    -      none      a long-wavelength sinusoid (:class:`WavinessSpec`)
    film        -      dry       capillary kinds: the water film (:class:`FilmSpec`)
    hamaker     J      material  capillary kinds: own Hamaker constant, > 0
    hardness    Pa     none      indentation hardness H: the contact pressure is capped
                                 at the softer body's H and the overlap stays as a
                                 plastic flattening of the surface (elastic bodies only)
    layer       -      none      a bonded elastic coating (:class:`LayerSpec`); E, nu
                                 are then the substrate's
    ==========  =====  ========  =====================================================

    The initial gap is ``(shape1 + shape2) - (topography1 + topography2)`` with a body's
    topography its roughness + texture + waviness (positive out of the body), shifted so that
    its minimum is 0 (first touch at approach 0).
    """

    E: Optional[Quantity("modulus", gt=0, allow_inf=True)] = None
    nu: Optional[Number(gt=-1, le=0.5)] = None
    rigid: StrictBool = False
    name: Optional[str] = None
    roughness: Roughness = Field(default_factory=NoRoughness)
    shape: Shape = Field(default_factory=FlatShape)
    texture: Optional[TextureSpec] = None
    waviness: Optional[WavinessSpec] = None
    film: Optional[FilmSpec] = None
    hamaker: Optional[Quantity("energy", gt=0)] = None
    hardness: Optional[Quantity("pressure", gt=0)] = None
    layer: Optional[LayerSpec] = None

    @model_validator(mode="after")
    def _material(self):
        said_rigid = "rigid" in self.model_fields_set and self.rigid  # (E = inf sets rigid below)
        if self.rigid:
            if self.E is not None and math.isfinite(self.E):
                _fail("E", "give either E or rigid = true, not both")
        elif self.E is None:
            _fail("E", "required: a Young's modulus > 0 (e.g. \"130 GPa\"), or rigid = true")
        elif math.isinf(self.E):
            self.rigid = True
        if said_rigid and "nu" in self.model_fields_set:
            # (E = inf with a nu stays allowed: the limit of an elastic body, where nu drops out)
            _fail("nu", "a rigid body (rigid = true) has no Poisson's ratio; leave nu out, or give a finite "
                        "E and nu for an elastic body")
        if not self.rigid and self.nu is None:
            _fail("nu", "required with E: Poisson's ratio in (-1, 0.5]")
        if self.rigid and self.layer is not None:
            _fail("layer", "a coating on a rigid body is not modelled (its substrate would not deform); give the "
                           "coated body its substrate's E and nu, or make the layer the body")
        if self.rigid and self.hardness is not None:
            _fail("hardness", "a rigid body does not yield; give the hardness to the elastic body "
                              "(the softer surface's hardness caps the contact pressure)")
        return self


# ----------------------------------------------------------------------------- load and physics
class LoadSpec(Section):
    """``[load]``: one of ``force``, ``approach``, ``forces``, ``approaches`` (kind normal);
    ``preload``, ``control``, ``steps``, ``refine``, ``loading`` (kind pulloff); ``force`` (held
    during the tangential ramp) or ``forces`` (a normal-load path) for kind partial_slip;
    ``force`` for kind hysteresis.

    ``preload`` (kind pulloff, optional, N, > 0): the compressive force from which the
    unloading starts.  Left out, the unloading starts from the adhesive equilibrium at zero
    external load (the bodies brought into contact and let go: F = 0 on the contact branch).
    Either way the start is reached by loading under displacement control from the first touch
    (:func:`tribobem.solvers.normal_paths.solve_at_force`); a periodic cell that reaches full contact
    below the preload starts from its last state short of full contact (a warning says so).

    ``grid_levels`` (kind pulloff, default 0): repeat the pull-off on grids 2, 4, ... 2^k times
    finer over the same domain, a measured topography interpolated bilinearly below its pixels;
    summary.json ``grid_levels`` gives each level's pull-off and the change between the last
    two, and a change above 5 % is warned about."""

    force: Optional[Quantity("force")] = None
    approach: Optional[Quantity("length")] = None
    forces: Optional[QuantityList("force")] = None
    approaches: Optional[QuantityList("length")] = None
    unload: StrictBool = False
    preload: Optional[Quantity("force", gt=0)] = None
    control: Literal["displacement", "force"] = "displacement"
    steps: Int(ge=2, le=100000) = 40
    refine: Int(ge=0, le=100) = 8
    loading: StrictBool = True
    grid_levels: Int(ge=0, le=4) = 0

    @property
    def given(self) -> list[str]:
        """Which of ``force``, ``approach``, ``forces``, ``approaches`` the scenario sets."""
        return [k for k in ("force", "approach", "forces", "approaches") if getattr(self, k) is not None]


# ----------------------------------------------------------------------------- adhesion: the stress laws
class AdhesionSpec(Section):
    """``[adhesion]``: the stress law that acts outside the contact, chosen by ``model``; the
    other keys are the law's (:class:`NoAdhesionSpec`, :class:`DugdaleAdhesionSpec`,
    :class:`ExponentialAdhesionSpec`, :class:`LennardJonesAdhesionSpec`).

    ======  ====  ========  ==========================================================
    key     unit  default   meaning
    ======  ====  ========  ==========================================================
    model   -     see text  the law, a name of the stress-law registry
                            (:data:`tribobem.interactions.registry.LAWS`): ``"none"``,
                            ``"dugdale"``, ``"exponential"`` or ``"lennard_jones"``;
                            left out: ``"dugdale"`` when ``work_of_adhesion`` is given,
                            else ``"none"``
    ======  ====  ========  ==========================================================

    An unknown ``model`` is an error that lists the registered ones.  Each law's table is a
    subclass of this model whose ``model`` is ``Literal[name]``, registered beside its law with
    :func:`tribobem.interactions.registry.register_law`.
    """

    model: Optional[str] = None

    @classmethod
    def model_validate(cls, obj, *args, **kwargs):
        """Validate a table; on this base class, with the spec of the registered law its
        ``model`` names (the tagged union :data:`Adhesion`), on a law's spec as that spec."""
        if cls is AdhesionSpec:
            return _ADHESION.validate_python(obj, *args, **kwargs)
        return super().model_validate(obj, *args, **kwargs)

    @property
    def enabled(self) -> bool:
        """Whether a stress law acts outside the contact (every law but ``none``)."""
        return True


class NoAdhesionSpec(AdhesionSpec):
    """``[adhesion] model = "none"`` (also no ``[adhesion]`` at all): no stress outside the
    contact, a compressive contact pressure.

    ================  ======  ========  ================================================
    key               unit    default   meaning
    ================  ======  ========  ================================================
    model             -       "none"    no stress law
    work_of_adhesion  J/m^2   none      unused (accepted, so that a sweep may switch
                                        Dugdale on by ``model`` alone)
    z0                m       none      unused but as the default of ``humidity.cutoff``
    ================  ======  ========  ================================================
    """

    model: Literal["none"] = "none"
    work_of_adhesion: Optional[Quantity("surface_energy", gt=0)] = None
    z0: Optional[Quantity("length", gt=0)] = None

    @property
    def enabled(self) -> bool:
        """False: no stress law acts outside the contact."""
        return False


class DugdaleAdhesionSpec(AdhesionSpec):
    """``[adhesion] model = "dugdale"``: the Dugdale (Maugis) cohesive zone
    (:class:`~tribobem.interactions.dugdale.DugdaleAdhesion`), a tension sigma0 = 16 dgamma /
    (9 sqrt3 z0) where the gap is below h0 = dgamma / sigma0.

    ================  ======  =========  ================================================
    key               unit    default    meaning
    ================  ======  =========  ================================================
    model             -       "dugdale"  the Dugdale law (the default when
                                         ``work_of_adhesion`` is given)
    work_of_adhesion  J/m^2   required   work of adhesion dgamma, > 0
    z0                m       required   equilibrium separation of the Lennard-Jones
                                         potential, > 0 (typically 0.2-0.4 nm)
    discretisation    -       "auto"     ``"softened"``: the step at h0 softened to a ramp
                                         of width 3 sigma0 C (C the cell's
                                         self-compliance), one equilibrium whatever the
                                         solver; ``"step"``: the thesis' step law;
                                         ``"auto"``: softened where the ramp is at most
                                         h0 / 5 wide, else the step
    ================  ======  =========  ================================================
    """

    model: Literal["dugdale"] = "dugdale"
    work_of_adhesion: Optional[Quantity("surface_energy", gt=0)] = None
    z0: Optional[Quantity("length", gt=0)] = None
    discretisation: Literal["auto", "softened", "step"] = "auto"

    @model_validator(mode="after")
    def _complete(self):
        if self.work_of_adhesion is None:
            _fail("work_of_adhesion", "required with model = 'dugdale' (e.g. \"50 mJ/m^2\")")
        if self.z0 is None:
            _fail("z0", "required with model = 'dugdale' (e.g. \"0.3 nm\")")
        return self


class ExponentialAdhesionSpec(AdhesionSpec):
    """``[adhesion] model = "exponential"``: exponential adhesion with a hard wall
    (:class:`~tribobem.interactions.exponential.ExponentialAdhesion`), a tension
    (w / rho) exp(-g / rho) outside the contact.

    ================  ======  ==============  ===========================================
    key               unit    default         meaning
    ================  ======  ==============  ===========================================
    model             -       "exponential"   the exponential law
    work_of_adhesion  J/m^2   required        work of adhesion w, > 0
    rho               m       required        decay length rho, > 0 (the Contact Mechanics
                                              Challenge: 2.071 nm)
    ================  ======  ==============  ===========================================
    """

    model: Literal["exponential"] = "exponential"
    work_of_adhesion: Optional[Quantity("surface_energy", gt=0)] = None
    rho: Optional[Quantity("length", gt=0)] = None

    @model_validator(mode="after")
    def _complete(self):
        if self.work_of_adhesion is None:
            _fail("work_of_adhesion", "required with model = 'exponential' (e.g. \"50 mJ/m^2\")")
        if self.rho is None:
            _fail("rho", "required with model = 'exponential' (e.g. \"2 nm\")")
        return self


class LennardJonesAdhesionSpec(AdhesionSpec):
    """``[adhesion] model = "lennard_jones"``: the 9-3 Lennard-Jones stress with a hard wall at its
    zero-force separation (:class:`~tribobem.interactions.lennard_jones.LennardJonesAdhesion`;
    gap datum: contact is D = z0).

    ================  ======  ================  =========================================
    key               unit    default           meaning
    ================  ======  ================  =========================================
    model             -       "lennard_jones"   the Lennard-Jones 9-3 law
    work_of_adhesion  J/m^2   required          work of adhesion dgamma, > 0
    z0                m       required          equilibrium separation, > 0
    ================  ======  ================  =========================================
    """

    model: Literal["lennard_jones"] = "lennard_jones"
    work_of_adhesion: Optional[Quantity("surface_energy", gt=0)] = None
    z0: Optional[Quantity("length", gt=0)] = None

    @model_validator(mode="after")
    def _complete(self):
        if self.work_of_adhesion is None:
            _fail("work_of_adhesion", "required with model = 'lennard_jones' (e.g. \"50 mJ/m^2\")")
        if self.z0 is None:
            _fail("z0", "required with model = 'lennard_jones' (e.g. \"0.3 nm\")")
        return self


# The built-in laws (a new law: its module in tribobem/interactions/, its spec above, one line here).
register_law("none", NoAdhesionSpec, NoInteraction, build=lambda spec, context: None)  # None: no law
register_law("dugdale", DugdaleAdhesionSpec, SoftenedDugdale, build=build_dugdale)
register_law("exponential", ExponentialAdhesionSpec, ExponentialAdhesion)
register_law("lennard_jones", LennardJonesAdhesionSpec, LennardJonesAdhesion)


def adhesion_model(table: Any) -> Any:
    """The law an ``[adhesion]`` table names: its ``model``, else ``"dugdale"`` when it gives a
    work of adhesion, else ``"none"``.

    Parameters
    ----------
    table : dict
        The raw ``[adhesion]`` table.

    Returns
    -------
    str
        The tag (not checked against the registry: an unknown ``model`` is returned as given).
    """
    model = table.get("model")
    if model is None:
        return "dugdale" if table.get("work_of_adhesion") is not None else "none"
    return model


def _adhesion_law(raw):
    """Validate ``[adhesion]`` with the spec of the registered law its ``model`` names (a tagged
    union over the registry, read at validation time, so that a law registered later counts)."""
    if isinstance(raw, AdhesionSpec):
        return raw
    if not isinstance(raw, dict):
        raise PydanticCustomError("scenario", "{message}", {"message": f"must be a table of keys, got {raw!r}"})
    model = adhesion_model(raw)
    law = LAWS.get(model) if isinstance(model, str) else None
    if law is None:
        raise PydanticCustomError("scenario", "{message}",
                                  {"message": f"must be one of {one_of()}, got {model!r}", "key": "model"})
    return law.spec.model_validate({**raw, "model": model})


#: The ``[adhesion]`` field: any registered law's spec (serialised as its own class).
Adhesion = Annotated[SerializeAsAny[AdhesionSpec], PlainValidator(_adhesion_law)]
_ADHESION = TypeAdapter(Adhesion)


class PathSpec(Section):
    """``friction.path`` of a hysteresis run (file-contract, Paper E).

    ``control = "force"``: the tangential force cycles between +-F*, ``amplitude`` =
    F*/(mu F0+ at F_x = 0) in (0, 1] (default 0.999).  ``control = "displacement"``: the rigid
    shift cycles 0 -> +stroke/2 -> -stroke/2 -> ..., ``stroke`` (peak to peak, > 0 m) required.
    ``cycles`` (>= 1) does not count the initial loading; ``steps`` (>= 2) per cycle.
    """

    control: Literal["force", "displacement"] = "force"
    amplitude: Optional[Number(gt=0, le=1)] = None
    stroke: Optional[Quantity("length", gt=0)] = None
    cycles: Int(ge=1) = 1
    steps: Int(ge=2) = 40

    @model_validator(mode="after")
    def _control_keys(self):
        if self.control == "force":
            if self.stroke is not None:
                _fail("stroke", "only with control = 'displacement'; a force-controlled path takes "
                                "amplitude in (0, 1] (F*/(mu F0+))")
            if self.amplitude is None:
                self.amplitude = 0.999
        else:
            if self.amplitude is not None:
                _fail("amplitude", "only with control = 'force'; a displacement-controlled path takes "
                                   "stroke > 0 m (peak to peak)")
            if self.stroke is None:
                _fail("stroke", "required with control = 'displacement': the peak-to-peak stroke, > 0 m "
                                "(e.g. \"3 um\")")
        return self


class FrictionSpec(Section):
    """``[friction]`` of the tangential kinds (file-contract).

    ``coefficient`` mu >= 0 (0: frictionless; required by partial_slip and hysteresis).
    partial_slip: ``tangential_forces`` (N, along ``direction``; may be negative) or
    ``tangential_displacements`` (m, rigid shifts of body 2 along ``direction``), each a list
    or a ``{start, stop, num}`` table; omitted: 0.  ``tangential_forces = "auto"``: a ramp to
    gross slip, 13 steps from 0 to 1.2 mu F0+ (F0+ the repulsive force at zero tangential load,
    solved first, so adhesion and menisci are included).  ``direction`` in degrees from the x axis
    (default 0).  ``slip``: ``"total"`` (one step from the undeformed state, Paper D) or
    ``"incremental"`` (slip increments, history).  hysteresis: ``path`` (:class:`PathSpec`).
    """

    coefficient: Optional[Number(ge=0)] = None
    tangential_forces: Optional[QuantityList("force", auto=True)] = None
    tangential_displacements: Optional[QuantityList("length")] = None
    direction: Angle() = 0.0
    slip: Literal["total", "incremental"] = "total"
    path: Optional[PathSpec] = None

    @property
    def tangential_given(self) -> list[str]:
        """Which of ``tangential_forces``, ``tangential_displacements`` the scenario sets."""
        return [k for k in ("tangential_forces", "tangential_displacements") if getattr(self, k) is not None]


class HumiditySpec(Section):
    """``[humidity]`` of the capillary kinds (``kind = "capillary"``, and
    ``kind = "pulloff"`` for a humid pull-off).

    ``rh``: relative humidities, fractions in (0, 1] (a list, or one value), run in the order
    given.  ``temperature`` (K, default 295), ``surface_tension`` (N/m, default 0.0725),
    ``molar_volume`` (m^3/mol, default 18.05e-6) of water.  ``levelling``: how each body's
    adsorbed film is distributed over its undeformed topography (``equilibrium``, the default;
    ``thin_film``, Paper B Eq. 8; ``uniform``, the isotherm thickness everywhere, Paper B
    Fig. 18), ``film_system``: ``open`` (RH fixes the chemical potential; the default of the
    equilibrium) or ``closed`` (the mean thickness fixed to the isotherm's; the only choice of
    the volume-conserving thin-film mode, its default).  ``disjoining`` (thin_film only, default
    false): add the isotherm's disjoining pressure to the liquid pressure of the thin-film
    equation, so that the film relaxes to the closed equilibrium and the integration stops at
    its steady state; false is Paper B's Eq. 8 as written, whose film drains off the peaks
    without an end state.  ``film_time`` (s, > 0, thin_film only): the physical time to which
    the thin-film equation is integrated and at which the films are taken, required with
    ``disjoining = false`` (no steady state to stop at: refused without it), optional with
    ``disjoining = true`` (default: to the steady state).  The run shows the time reached per
    film and records it per step (``film_time_1`` / ``_2`` in s, ``film_time_tau_slow_1`` /
    ``_2`` in units of tau_slow, the relaxation time of the slowest mode).  ``contact_angles``:
    theta1, theta2 in degrees, in [0, 180] (Paper B Eq. 9; default 0, 0).  ``cutoff`` (m, > 0): the short-range
    cut-off of the 1/g^3 van der Waals terms without a Dugdale zone (default: ``adhesion.z0``
    when given, else 0.3 nm).  ``critical_distance`` (m, >= 0): a film-to-film air gap below it
    seeds a meniscus (default 0.84 nm, three water-molecule diameters).  ``contribution``:
    ``none`` or ``linear_30_60`` (Paper C: the capillary pressure times (RH - 0.3)/0.3 clipped to
    [0, 1]).  ``water_hamaker`` (J, > 0): water's own Hamaker constant in vacuum (default
    3.7e-20 J).  ``van_der_waals``: the water-solid terms on (default) or off.  Each body's film
    (isotherm) and own Hamaker constant are keys of ``[body1]`` / ``[body2]`` (``film``,
    ``hamaker``).
    """

    rh: Optional[Annotated[list[RelativeHumidity()], BeforeValidator(lambda v: v if isinstance(v, list) else [v])]] = None
    temperature: Quantity("temperature", gt=0) = 295.0
    surface_tension: Quantity("surface_tension", gt=0) = 0.0725
    molar_volume: Quantity("molar_volume", gt=0) = 18.05e-6
    levelling: Literal["equilibrium", "thin_film", "uniform"] = "equilibrium"
    film_system: Optional[Literal["open", "closed"]] = None
    disjoining: StrictBool = False
    film_time: Optional[Quantity("time", gt=0)] = None
    contact_angles: Annotated[list[Angle()], Field(min_length=2, max_length=2)] = Field(default_factory=lambda: [0.0, 0.0])
    cutoff: Optional[Quantity("length", gt=0)] = None
    critical_distance: Quantity("length", ge=0) = 0.84e-9
    contribution: Literal["none", "linear_30_60"] = "none"
    water_hamaker: Quantity("energy", gt=0) = 3.7e-20
    van_der_waals: StrictBool = True

    @model_validator(mode="after")
    def _humidity(self):
        for i, a in enumerate(self.contact_angles):
            if not 0.0 <= a <= 180.0:
                _fail(f"contact_angles[{i}]", f"must be in [0, 180] degrees, got {a:g}")
        if self.levelling == "thin_film" and self.film_system == "open":
            _fail("film_system", "levelling = 'thin_film' conserves the film volume: it is a closed system "
                                 "(give film_system = 'closed' or leave it out)")
        if self.disjoining and self.levelling != "thin_film":
            _fail("disjoining", f"adds the disjoining pressure to the thin-film equation: it needs levelling = "
                                f"'thin_film', not {self.levelling!r} (the equilibrium films include it already)")
        if self.film_time is not None and self.levelling != "thin_film":
            _fail("film_time", f"is the end time of the thin-film integration: it needs levelling = 'thin_film', "
                               f"not {self.levelling!r}")
        if self.levelling == "thin_film" and not self.disjoining and self.film_time is None:
            _fail("film_time", "levelling = 'thin_film' without disjoining has no steady state (its films drain off "
                               "the peaks for as long as one integrates), so the run would only stop at its step "
                               "limit; give film_time (the physical time to integrate to, e.g. '1 ms') or set "
                               "disjoining = true (the films then relax to the closed equilibrium)")
        if self.rh is not None and len(self.rh) == 0:
            _fail("rh", "needs at least one relative humidity in (0, 1]")
        return self

    @property
    def system(self) -> str:
        """The film system in effect: the given one, else closed for thin_film, open otherwise."""
        if self.film_system is not None:
            return self.film_system
        return "closed" if self.levelling == "thin_film" else "open"


class TwoScaleSpec(Section):
    """``[two_scale]``: solve the contact at two scales instead of on one grid.

    The rough interface is solved on periodic micro windows (the bodies' roughness and the
    textures whose period divides the window, at asperity resolution) at a ladder of nominal
    pressures; their mean gap against pressure, averaged over roughness realisations, is the
    interface law with which the macro problem (``[grid]``: the bodies' shapes, waviness and
    long textures, at macro cells) is solved.  Without the section the whole problem is solved
    on ``[grid]``, roughness included.

    ============  =====  ===========  ==================================================
    key           unit   default      meaning
    ============  =====  ===========  ==================================================
    window        m      required     side of the periodic micro window
    window_n      -      256          cells per side of the window (>= 8)
    realisations  -      4            roughness realisations (seeds seed, seed + 1, ...)
    pressures     -      32           nominal pressures of the table (>= 4)
    min_pressure  Pa     automatic    smallest tabulated pressure
    max_pressure  Pa     automatic    largest tabulated pressure
    scheduler     -      synchronous  micro windows: ``synchronous``, ``threads``,
                                      ``processes`` or a Dask scheduler address
    cache         -      true         reuse tables computed before (same windows)
    ============  =====  ===========  ==================================================

    Automatic range: from 1e-3 of the mean nominal pressure over the smooth macro contact to
    twice its largest pressure (solved first, in a fraction of the macro time).
    """

    window: Quantity("length", gt=0)
    window_n: Int(ge=8) = 256
    realisations: Int(ge=1) = 4
    pressures: Int(ge=4) = 32
    min_pressure: Optional[Quantity("pressure", gt=0)] = None
    max_pressure: Optional[Quantity("pressure", gt=0)] = None
    scheduler: str = "synchronous"
    cache: StrictBool = True

    @model_validator(mode="after")
    def _range(self):
        if self.min_pressure is not None and self.max_pressure is not None and self.min_pressure >= self.max_pressure:
            _fail("max_pressure", f"must exceed min_pressure ({self.min_pressure:g} Pa), got {self.max_pressure:g} Pa")
        return self


class SolverSpec(Section):
    """``[solver]``: ``tolerance``, ``max_iterations``, ``backend`` (numpy | cupy; cupy grids below
    1024^2 nodes run on NumPy, faster there, see ``TRIBOBEM_CUPY_MIN_NODES``), ``kernel``
    (spectral | influence; periodic grids only), ``method`` (auto | polonsky_keer | normcg: the
    normal solver of kind ``normal``, of every coupling pass of kinds ``partial_slip`` and
    ``hysteresis``, and of the meniscus fixed point of the humid runs (``capillary``, and
    ``pulloff``, ``partial_slip``, ``hysteresis`` with ``[humidity]``); auto, the default, is
    normcg -- Vollebregt's preconditioned CG, 2-4x fewer iterations on rough contacts, the same
    equilibrium -- without adhesion and without ``[humidity]``, polonsky_keer otherwise, where the
    non-convex problem may let normcg settle on another valid equilibrium (give normcg to use it
    there: on a rough burl with menisci it is as fast at 96^2, 2.5x faster at 192^2, and at 384^2
    takes 142 s where polonsky_keer had not finished after 65 min); the dry pull-off solves
    with polonsky_keer and refuses normcg).  ``precision`` (auto | single | double; kind
    ``normal``'s NormCG solves): single transforms the search directions and the preconditioner
    in single precision while the convergence test stays in double, so the converged state
    passes the double-precision test at ``tolerance``; auto, the default, is single from 512^2
    nodes on the NumPy backend, double otherwise and wherever Polonsky-Keer solves."""

    tolerance: Number(gt=0, lt=1) = 1e-10
    max_iterations: Int(ge=1) = 10000
    backend: Literal["numpy", "cupy"] = "numpy"
    kernel: Literal["spectral", "influence"] = "spectral"
    method: Literal["auto", "polonsky_keer", "normcg"] = "auto"
    precision: Literal["auto", "single", "double"] = "auto"


class OutputSpec(Section):
    """``[output]``: which fields go to fields.nc (``all`` steps, the ``last``/representative
    ones, or ``none``), and whether to draw figures and the HTML report.

    ``stresses = true``: the subsurface stresses of the saved states in each elastic body
    (von Mises, maximum shear and principal stresses on planes below the surface, in fields.nc;
    the largest von Mises stress and its depth per body in summary.json, a figure), on the
    planes ``stress_depths`` (m, >= 0; default: 24 planes from 0.05 to 2 times the equivalent
    radius of the largest contact patch)."""

    fields: Literal["all", "last", "none"] = "all"
    figures: StrictBool = True
    report: StrictBool = True
    stresses: StrictBool = False
    stress_depths: Optional[QuantityList("length", ge=0)] = None

    @model_validator(mode="after")
    def _stresses(self):
        if self.stress_depths is not None and not self.stresses:
            _fail("stress_depths", "planes for the subsurface stresses: set stresses = true as well")
        if self.stresses and self.fields == "none":
            _fail("stresses", "the subsurface stresses are fields of the saved states: fields = \"none\" saves none")
        return self


# ----------------------------------------------------------------------------- expected (metadata)
#: Summary keys an ``expected`` table may state, with their dimension: what the run kinds
#: produce (:meth:`tribobem.runs.kind.RunKind.result_keys`: run-level values such as
#: ``pull_off_force`` and step keys, read at ``expected.step``, default the last step).
EXPECTED_KEYS: dict[str, str] = {k: d for kind in RUN_KINDS.values() for k, d in kind.result_keys().items()}
#: ... and those of ``[output] stresses`` (any kind; output/stresses.py)
EXPECTED_KEYS.update({f"max_von_mises{s}_body{b}": d for b in (1, 2)
                      for s, d in (("", "pressure"), ("_depth", "length"))})
#: Names of the result checks an ``expected.warnings`` list may name: those of
#: :data:`tribobem.output.checks.CHECKS` (repeated here so that parsing a scenario does not import
#: the output package; a test keeps the two equal).
CHECK_NAMES = ("edge", "cohesive_zone", "cohesive_range", "cohesive_edge", "full_contact", "large_contact", "contact_cells",
               "topography_pixels", "stick_zone")


class ExpectedSpec(Section):
    """``expected``: what the scenario should give, and where that number comes from (metadata).

    An inline table such as ``expected = { pull_off_force = "-0.250 uN", reference =
    "Maugis-Dugdale (tribobem.analytic)", tolerance = "3 %" }``:

    * one or more value keys from :data:`EXPECTED_KEYS`, each a quantity of its dimension (a
      number in SI or a string with a unit); a step key is read at ``step`` (an index into
      summary.json ``steps``, default the last);
    * ``rh``: in a humid run (``[humidity]``), a run-level key that is a list in RH order is read
      at this RH (one of ``humidity.rh``);
    * ``reference`` (required): what the value comes from (an analytic solution, a published
      result, a finer grid);
    * ``tolerance`` (required with a value): the relative deviation the reference admits, in
      (0, 1) (e.g. ``"3 %"`` or ``0.03``);
    * ``warnings``: result checks the run is expected to raise (an example that cannot be
      resolved says so), names from :data:`CHECK_NAMES`.

    The run itself ignores it; summary.json ``expected`` lists computed against expected values
    (:func:`tribobem.output.checks.compare_expected`).
    """

    reference: str = Field(min_length=1)
    tolerance: Optional[Number(gt=0, lt=1)] = None
    step: Optional[Int()] = None
    rh: Optional[RelativeHumidity()] = None
    warnings: list[Literal[CHECK_NAMES]] = Field(default_factory=list)
    values: dict[str, float] = Field(default_factory=dict)

    @classmethod
    def allowed_keys(cls) -> list[str]:
        """The keys ``[expected]`` accepts: its own settings and every known result key."""
        return [k for k in cls.model_fields if k != "values"] + list(EXPECTED_KEYS)

    @model_validator(mode="before")
    @classmethod
    def _known_keys(cls, data: Any):
        # Replaces Section._known_keys: the value keys are gathered into ``values`` (SI).
        if not isinstance(data, dict):
            return data
        allowed = cls.allowed_keys()
        out, values = {}, {}
        for key, raw in data.items():
            if key not in allowed:
                raise PydanticCustomError("unknown_key", "unknown key {key!r}; allowed keys: {allowed}",
                                          {"key": str(key), "allowed": ", ".join(allowed)})
            if key in EXPECTED_KEYS:
                try:
                    values[key] = convert(raw, EXPECTED_KEYS[key])
                except UnitMismatch as exc:
                    raise PydanticCustomError("scenario", "{message}", {"message": str(exc), "key": key}) from None
                if not math.isfinite(values[key]):
                    raise PydanticCustomError("scenario", "{message}",
                                              {"message": f"must be finite, got {raw!r}", "key": key})
            else:
                out[key] = raw
        out["values"] = values
        return out

    @model_validator(mode="after")
    def _something(self):
        if not self.values and not self.warnings:
            _fail(None, "give at least one expected value (e.g. pull_off_force = \"-0.25 uN\") or the warnings "
                        f"the run is expected to raise; value keys: {', '.join(EXPECTED_KEYS)}")
        if self.values and self.tolerance is None:
            _fail("tolerance", "required with an expected value: the relative deviation the reference admits, "
                               "in (0, 1) (e.g. \"3 %\")")
        return self


# ----------------------------------------------------------------------------- scenario
class Scenario(Section):
    """A complete, validated scenario (all quantities in SI)."""

    kind: Literal[KINDS] = "normal"
    name: Optional[str] = None
    description: Optional[str] = None
    grid: GridSpec
    body1: BodySpec
    body2: BodySpec
    load: LoadSpec = Field(default_factory=LoadSpec)
    adhesion: Adhesion = Field(default_factory=lambda: NoAdhesionSpec(model="none"))
    friction: Optional[FrictionSpec] = None
    humidity: Optional[HumiditySpec] = None
    two_scale: Optional[TwoScaleSpec] = None
    solver: SolverSpec = Field(default_factory=SolverSpec)
    output: OutputSpec = Field(default_factory=OutputSpec)
    expected: Optional[ExpectedSpec] = None

    @model_validator(mode="after")
    def _consistent(self):
        # The rules live with the kind (tribobem.runs.<kind>.KIND): the sections and keys it
        # reads -- anything else the scenario gives is an error, never silently dropped -- and
        # its own consistency checks.  Only what holds for every kind is checked here.
        kind = RUN_KINDS[self.kind]
        unused = kind.unused(self, RUN_KINDS)
        if unused:
            _fail(*unused[0])
        if "kernel" in self.solver.model_fields_set and self.solver.kernel != "influence" and not self.grid.periodic:
            _fail("solver.kernel", f"{self.solver.kernel!r} is for periodic grids; a free-boundary grid always "
                  "uses the influence coefficients of uniform pressure on its cells (leave kernel out)")
        for key in (self.expected.values if self.expected is not None else ()):
            if key.startswith("max_von_mises"):
                if not self.output.stresses:
                    _fail(f"expected.{key}", "the subsurface stresses are computed with [output] stresses = true")
                continue
            if key not in kind.result_keys():
                by = [k for k, kd in RUN_KINDS.items() if key in kd.result_keys()]
                _fail(f"expected.{key}", f"kind = {self.kind!r} does not produce it (produced by kind "
                      f"{', '.join(repr(k) for k in by)}); the expected value could never be compared")
        if self.solver.precision == "single":
            if self.kind != "normal":
                _fail("solver.precision", f"single precision is for the NormCG solves of kind 'normal'; kind "
                      f"{self.kind!r} runs in double precision (leave precision out)")
            if self.adhesion.enabled or self.solver.method == "polonsky_keer":
                _fail("solver.precision", "single precision is NormCG's (non-adhesive contact); this run's solver "
                      "is Polonsky-Keer, which runs in double precision (leave precision out)")
        _geometry_fits_grid(self)
        if kind.check is not None:
            try:
                kind.check(self)
            except InputError as exc:
                _fail(exc.field, exc.reason)
        return self

    @property
    def implemented(self) -> bool:
        """Whether this version can run the scenario's kind (it has a runner)."""
        return self.kind in RUNNERS


def _geometry_fits_grid(sc: "Scenario") -> None:
    """The grid resolves each texture and waviness and holds each burl's top (when the grid's
    size is known here; a grid sized by a topography file is checked when the problem is built,
    :func:`tribobem.scenario.build.build_problem`, by the same rules)."""
    from ..geometry.textures import check_body_geometry

    lengths = sc.grid.lengths
    nx, ny = sc.grid.shape
    if lengths is None or nx is None:
        return
    window = (sc.two_scale.window, sc.two_scale.window_n) if sc.two_scale is not None else None
    for name in ("body1", "body2"):
        try:
            check_body_geometry(getattr(sc, name), lengths[0] / nx, lengths[1] / ny, lengths, name, window=window)
        except InputError as exc:
            _fail(exc.field, exc.reason)


# ----------------------------------------------------------------------------- parsing
_TAGGED = {"roughness": ROUGHNESS_KINDS, "shape": SHAPE_KINDS}


def _clean_loc(loc) -> list:
    out: list = []
    for item in loc:
        if out and isinstance(item, str) and out[-1] in _TAGGED and item in _TAGGED[out[-1]]:
            continue  # the discriminated-union tag pydantic inserts
        out.append(item)
    return out


def _join(loc) -> str:
    text = ""
    for item in loc:
        if isinstance(item, int):
            text += f"[{item}]"
        else:
            text += ("." if text else "") + str(item)
    return text


def _render(err: dict) -> tuple[str, str]:
    loc = _clean_loc(err.get("loc", ()))
    typ = err.get("type", "")
    ctx = err.get("ctx") or {}
    inp = err.get("input")
    if typ == "unknown_key":
        section = f"[{_join(loc)}]" if loc else "the top level"
        return _join(loc + [ctx["key"]]), f"unknown key; allowed keys in {section}: {ctx['allowed']}"
    if typ == "scenario" and ctx.get("key"):
        return _join(loc + ctx["key"].split(".")), ctx["message"]
    if "message" in ctx and typ in ("scenario", "quantity", "range", "int"):
        return _join(loc), ctx["message"]
    if typ == "missing":
        return _join(loc), "required"
    if typ == "literal_error":
        return _join(loc), f"must be one of {ctx.get('expected')}, got {inp!r}"
    if typ == "union_tag_invalid":
        tags = ", ".join(repr(t) for t in _TAGGED.get(loc[-1] if loc else "", ())) or ctx.get("expected_tags")
        return _join(loc + ["kind"]), f"must be one of {tags}, got {ctx.get('tag')!r}"
    if typ == "union_tag_not_found":
        tags = ", ".join(repr(t) for t in _TAGGED.get(loc[-1] if loc else "", ()))
        return _join(loc + ["kind"]), f"required (one of {tags})"
    if typ in ("model_type", "model_attributes_type", "dict_type"):
        what = "a table of keys" if not loc or loc[-1] not in _TAGGED else "an inline table {kind = ..., ...}"
        return _join(loc), f"must be {what}, got {inp!r}"
    if typ in ("bool_type", "bool_parsing"):
        return _join(loc), f"must be true or false, got {inp!r}"
    if typ in ("string_type",):
        return _join(loc), f"must be a string, got {inp!r}"
    if typ in ("list_type", "too_short", "too_long"):
        return _join(loc), f"{err.get('msg', 'invalid list')} (got {inp!r})"
    msg = err.get("msg", "invalid value")
    return _join(loc), f"{msg} (got {inp!r})"


def parse_scenario(data: dict, source: str | None = None) -> Scenario:
    """Validate a scenario dict (e.g. a parsed TOML file).

    Parameters
    ----------
    data : dict
        The scenario; quantities may be numbers (SI) or strings with units.
    source : str, optional
        Where it came from (a file name), for error messages.

    Returns
    -------
    Scenario
        With every quantity converted to SI.

    Raises
    ------
    ScenarioError
        Listing every problem as ``section.key: message``.
    """
    if isinstance(data, Scenario):
        return data
    if not isinstance(data, dict):
        raise ScenarioError([("scenario", f"must be a table of sections, got {type(data).__name__}")], source)
    try:
        return Scenario.model_validate(data)
    except ValidationError as exc:
        errors, seen = [], set()
        for err in exc.errors(include_url=False):
            item = _render(err)
            if item not in seen:
                seen.add(item)
                errors.append(item)
        raise ScenarioError(errors, source) from None
