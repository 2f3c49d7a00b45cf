"""Scenario -> problem: grid, materials, initial gap, elastic operator, interaction.

This is the one place where a validated :class:`~tribobem.scenario.schema.Scenario` becomes
arrays and objects; data flows one way (scenario -> bodies and gap -> operator -> solver).

Sign conventions of scenario files
----------------------------------
* A body's ``shape`` is convex toward the other body (a sphere on body 2 points down, a
  sphere on body 1 points up); shapes add to the gap.
* A body's ``roughness`` holds heights *as measured on that body*: positive out of the body,
  toward the counter-surface (what a profilometer or AFM scan of that surface gives).
  Asperities therefore close the gap, whichever body carries them.
* A body's ``texture`` (dimples, pillars, grooves) and ``waviness`` are topography too, with
  the roughness's sign (a pillar closes the gap, a dimple opens it); they add to its roughness
  (:mod:`tribobem.geometry.textures`), and :attr:`Problem.roughness1` / ``roughness2`` hold
  the sum (the body's whole topography).
* The initial gap is ``h = shape1 + shape2 - roughness1 - roughness2``, shifted so that its
  minimum is 0: approach 0 is the first touch.
"""

from __future__ import annotations

import math
import os
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import scipy.fft as sfft

from ..errors import InputError, TopographyError
from ..grid import Grid
from ..materials import ContactPair, Material
from .schema import BodySpec, Scenario
from .. import geometry as geo
from ..data import DATA_PREFIX, topography_path
from ..elasticity.backend import default_workers
from ..elasticity.bodies import CoatedHalfSpace
from ..elasticity.operators import make_operator
from ..geometry import stats as geostats, read_topography, unit_to_metres, Topography
from ..interactions.hardness import HardnessCap
from ..interactions.base import law_summary_info
from ..interactions.isotherms import isotherm_from_spec
from ..interactions.registry import LawContext, get_law
from ..interactions.van_der_waals import DEFAULT_CUTOFF, HAMAKER_SI, HAMAKER_SIO2
from ..interactions.water import Water

__all__ = ["Problem", "HumiditySetup", "build_problem", "body_material", "resolve_path", "humidity_setup"]


@dataclass
class Problem:
    """Everything a solver needs, built from a scenario.

    Attributes
    ----------
    scenario : Scenario
    grid : Grid
    pair : ContactPair
    operator : ConvolutionOperator
        Periodic or free-boundary operator, as ``grid.periodic`` says.
    gap : ndarray
        Initial gap h (m), minimum 0.
    roughness1, roughness2 : ndarray
        The bodies' topographies (m, positive toward the counter-surface): roughness plus
        texture plus waviness.
    shape1, shape2 : ndarray
        The bodies' shapes (m, convex toward the other body).
    interaction : Interaction or None
        The stress law of ``[adhesion]`` (its registered builder's; None without one).
    humidity : HumiditySetup or None
        The water, isotherms, Hamaker constants and meniscus options of a capillary run (or a
        humid pull-off); None without ``[humidity]``.
    info : dict
        Derived scalars (E*, sigma0, h0, Tabor/Maugis parameters, roughness statistics,
        resolved file paths) for the summary.
    warnings : list of str
    base_dir : Path
        Folder that relative paths in the scenario are resolved against.
    """

    scenario: Scenario
    grid: Grid
    pair: ContactPair
    operator: object
    gap: np.ndarray
    roughness1: np.ndarray
    roughness2: np.ndarray
    shape1: np.ndarray
    shape2: np.ndarray
    interaction: object = None
    humidity: object = None
    info: dict = field(default_factory=dict)
    warnings: list = field(default_factory=list)
    base_dir: Path = Path(".")
    two_scale: object = None

    @property
    def upper_moves_visibly(self) -> bool:
        """True when shifting body 2 changes the gap (it has a shape or a roughness)."""
        return bool(np.ptp(self.shape2) > 0 or np.ptp(self.roughness2) > 0)

    def shifted_gap(self, offset) -> np.ndarray:
        """The initial gap with body 2 moved rigidly by ``offset`` = (dx, dy) in m.

        Body 1 stays on the grid; body 2's shape and roughness are shifted: exactly (a Fourier
        phase shift) on a periodic grid, by cubic interpolation on a free-boundary grid (values
        beyond the edge repeat the edge).  Same reference as :attr:`gap` (no re-zeroing), so
        approaches stay comparable.  Used for gross sliding against a rough counterface (thesis
        recommendation 3: new contact pairs form).

        Parameters
        ----------
        offset : (float, float)
            Rigid displacement (dx, dy) of body 2 (m).

        Returns
        -------
        ndarray, shape ``grid.shape``
            The gap (m) with body 2 moved, minus the same :attr:`gap_offset` as the unshifted
            gap (so its minimum need not be 0).
        """
        moved = self.grid.translate(self.shape2 - self.roughness2, offset)
        lower = self.shape1 - self.roughness1
        return lower + moved - self.gap_offset

    def refined(self, factor: int) -> "Problem":
        """The same scenario on a grid ``factor`` times finer per side over the same domain.

        A measured topography is resampled onto it (bilinear below its pixels), and the stress
        law is built for its cells (a softened Dugdale law has the finer cell's ramp).

        Parameters
        ----------
        factor : int
            Cells per side multiplied by this (>= 1).

        Returns
        -------
        Problem
        """
        sc = self.scenario.model_copy(deep=True)
        grid = sc.grid
        if grid.n is not None:
            grid.n = grid.n * int(factor)
        else:
            grid.nx, grid.ny = grid.nx * int(factor), grid.ny * int(factor)
        return build_problem(sc, self.base_dir)

    @property
    def gap_offset(self) -> float:
        """The constant subtracted from shape1 + shape2 - rough1 - rough2 to make min(gap) = 0."""
        return float(np.min(self.shape1 + self.shape2 - self.roughness1 - self.roughness2))


@dataclass
class HumiditySetup:
    """What a capillary run needs beyond the elastic problem, in SI.

    Attributes
    ----------
    rh : list of float
        Relative humidities (fractions in (0, 1]), in the scenario's order.
    water : Water
        Temperature, surface tension and molar volume.
    isotherm1, isotherm2 : Isotherm
        Each body's adsorption isotherm (:class:`~tribobem.interactions.isotherms.DryIsotherm`
        for a body without ``film``).
    surface1, surface2 : ndarray
        Each body's undeformed topography as seen from the body (m, positive outward): its
        roughness minus its shape (a shape is convex toward the other body, so it recedes from
        its own body's outward normal).  The films are levelled on these, before contact.
    hamaker1, hamaker2 : float
        The bodies' own Hamaker constants in vacuum (J).
    water_hamaker : float
        Water's own Hamaker constant in vacuum (J).
    levelling : str
        ``"equilibrium"``, ``"thin_film"`` or ``"uniform"``.
    system : str
        ``"open"`` or ``"closed"``.
    disjoining : bool
        Thin-film levelling with the disjoining pressure (``humidity.disjoining``).
    contact_angles : tuple of float
        theta1, theta2 in radians.
    critical_distance : float
        d_cr (m).
    cutoff : float
        Short-range cut-off of the 1/g^3 terms (m): ``humidity.cutoff``, else ``adhesion.z0``,
        else 0.3 nm.
    contribution : str
        ``"none"`` or ``"linear_30_60"`` (Paper C).
    van_der_waals : bool
        Water-solid terms on or off.
    film_time : float or None
        Thin-film levelling: the physical time to integrate to (s, ``humidity.film_time``);
        None: to the steady state.
    """

    rh: list
    water: object
    isotherm1: object
    isotherm2: object
    surface1: np.ndarray
    surface2: np.ndarray
    hamaker1: float
    hamaker2: float
    water_hamaker: float
    levelling: str
    system: str
    disjoining: bool
    contact_angles: tuple
    critical_distance: float
    cutoff: float
    contribution: str
    van_der_waals: bool
    film_time: float | None = None

    def info(self) -> dict:
        """Scalars for summary.json ``problem.humidity``."""
        return {
            "temperature": self.water.temperature, "surface_tension": self.water.surface_tension,
            "molar_volume": self.water.molar_volume, "isotherm1": self.isotherm1.name,
            "isotherm2": self.isotherm2.name, "hamaker1": self.hamaker1, "hamaker2": self.hamaker2,
            "water_hamaker": self.water_hamaker, "levelling": self.levelling, "film_system": self.system,
            "disjoining": self.disjoining, "film_time": self.film_time,
            "contact_angles_deg": [math.degrees(a) for a in self.contact_angles],
            "critical_distance": self.critical_distance, "cutoff": self.cutoff,
            "contribution": self.contribution, "van_der_waals": self.van_der_waals,
        }


def humidity_setup(sc: Scenario, shape1, shape2, rough1, rough2) -> HumiditySetup | None:
    """The :class:`HumiditySetup` of a scenario with ``[humidity]`` (None without).

    Parameters
    ----------
    sc : Scenario
        The validated scenario.
    shape1, shape2 : ndarray
        The bodies' shapes (m, positive away from the interface), on the grid.
    rough1, rough2 : ndarray
        The bodies' roughness (m, positive out of the body), on the grid; each body's undeformed
        surface for its film is ``rough - shape``.

    Returns
    -------
    HumiditySetup or None
        Water, isotherms, surfaces, Hamaker constants (J), contact angles (rad), critical
        distance and cutoff (m) of the capillary model; None without ``[humidity]``.

    Raises
    ------
    InputError
        RH = 1 with a film that has no finite thickness there (an open-system equilibrium film
        at RH = 1, or an isotherm that diverges at saturation: bulk water, outside the model),
        checked here before any solve.
    """
    hum = sc.humidity
    if hum is None:
        return None
    water = Water(hum.temperature, hum.surface_tension, hum.molar_volume)
    isos, hams = [], []
    for name in ("body1", "body2"):
        body = getattr(sc, name)
        spec = body.film.isotherm if body.film is not None else None
        iso = isotherm_from_spec(spec, f"{name}.film.isotherm")
        isos.append(iso)
        if body.hamaker is not None:
            hams.append(float(body.hamaker))
        else:  # the shipped defaults (approximate): silicon's for an "Si" film, else silica's
            named_si = isinstance(spec, str) and spec.strip().lower() == "si"
            hams.append(HAMAKER_SI if named_si else HAMAKER_SIO2)
    for rh in hum.rh or []:
        if rh < 1.0:
            continue
        for name, iso in zip(("body1", "body2"), isos):
            if iso.dry:
                continue
            if hum.levelling == "equilibrium" and hum.system == "open":
                raise InputError("humidity.rh", f"RH = 1 with an open-system equilibrium film on {name}: the Kelvin "
                                 "pressure is 0 and a flat film is bulk water (no finite film, an infinite Kelvin "
                                 "radius); use RH < 1 (e.g. 0.99), or film_system = 'closed' with an isotherm that "
                                 "is finite at RH = 1")
            if not math.isfinite(float(iso.thickness(1.0))):
                raise InputError("humidity.rh", f"RH = 1: the {iso.name} isotherm of {name} diverges at saturation "
                                 "(bulk water, outside the model); use RH < 1 (e.g. 0.99) or a table that ends "
                                 "with a finite thickness at RH = 1")
    if hum.cutoff is not None:
        cutoff = float(hum.cutoff)
    elif getattr(sc.adhesion, "z0", None) is not None:  # a law with a Lennard-Jones z0 (none, dugdale)
        cutoff = float(sc.adhesion.z0)
    else:
        cutoff = DEFAULT_CUTOFF
    return HumiditySetup(
        rh=list(hum.rh or []), water=water, isotherm1=isos[0], isotherm2=isos[1],
        surface1=np.asarray(rough1 - shape1, dtype=float), surface2=np.asarray(rough2 - shape2, dtype=float),
        hamaker1=hams[0], hamaker2=hams[1], water_hamaker=float(hum.water_hamaker), levelling=hum.levelling,
        system=hum.system, disjoining=bool(hum.disjoining), contact_angles=tuple(math.radians(a) for a in hum.contact_angles),
        critical_distance=float(hum.critical_distance), cutoff=cutoff, contribution=hum.contribution,
        van_der_waals=bool(hum.van_der_waals),
        film_time=float(hum.film_time) if hum.film_time is not None else None)


def resolve_path(path: str, base_dir: Path) -> Path:
    """``path`` with ``~`` and environment variables expanded, relative to ``base_dir``.

    ``"data:NAME"`` names a measured topography of tribobem's data folder (the files shipped
    with the package, or ``$TRIBOBEM_DATA_DIR`` when set): :func:`tribobem.data.topography_path`,
    which raises :class:`InputError` when the file is not there.

    Parameters
    ----------
    path : str
        The path as the scenario gives it.
    base_dir : Path
        The scenario file's folder (relative paths are taken from there, so a scenario keeps
        working when run from another directory).

    Returns
    -------
    Path
        Absolute when ``path`` or ``base_dir`` is (not resolved further, not checked to exist
        except for ``"data:"`` names).
    """
    if str(path).startswith(DATA_PREFIX):
        return topography_path(str(path))
    p = Path(os.path.expandvars(os.path.expanduser(path)))
    return p if p.is_absolute() else (Path(base_dir) / p)


def body_material(spec: BodySpec, name: str) -> Material:
    """The :class:`Material` of a body section.

    Parameters
    ----------
    spec : BodySpec
        The ``[body1]`` or ``[body2]`` section (E in Pa, nu, ``rigid``).
    name : str
        Label used when the section gives no ``name`` (``"body1"``, ``"body2"``).

    Returns
    -------
    Material
        A rigid body is E = inf, nu = 0 (it adds no compliance to the pair).
    """
    label = spec.name or name
    if spec.rigid:
        return Material(math.inf, 0.0, label)
    return Material(float(spec.E), float(spec.nu), label)


def _rewrap(exc: InputError, prefix: str) -> InputError:
    """Re-label a geometry error (``topography.path: ...``) with the scenario key."""
    fieldname = getattr(exc, "field", "") or ""
    text = str(exc)
    msg = text[len(fieldname) + 2:] if fieldname and text.startswith(fieldname + ": ") else text
    sub = fieldname.split(".", 1)[1] if "." in fieldname else fieldname
    sub = {"heights": "path", "grid": "path"}.get(sub, sub)
    cls = TopographyError if isinstance(exc, TopographyError) else InputError
    return cls(f"{prefix}.{sub}" if sub else prefix, msg)


class _Loader:
    """Reads measured topographies once (sizing the grid and building the gap use them)."""

    def __init__(self, base_dir: Path):
        self.base_dir = Path(base_dir)
        self.cache: dict = {}

    def topography(self, spec, key: str):
        """The (detrended, cropped) Topography of a file/array roughness section."""
        if key in self.cache:
            return self.cache[key]

        try:
            path = resolve_path(spec.path, self.base_dir)
        except InputError as exc:  # a data: name that is not in the data folder
            raise _rewrap(exc, key) from None
        if not path.exists():
            raise FileNotFoundError(f"{key}.path: file {path} not found (paths are relative to the scenario "
                                    "file's folder; data:NAME names a file shipped with tribobem)")
        if spec.kind == "file":
            try:
                topo = read_topography(path, channel=spec.channel, detrend=spec.detrend, fill=spec.fill,
                                       periodic=False, size=spec.physical_size, unit=spec.unit)
            except InputError as exc:
                raise _rewrap(exc, key) from None
        else:  # array
            try:
                arr = np.load(path, allow_pickle=False)
            except Exception as exc:
                raise TopographyError(f"{key}.path", f"cannot read {path} as a .npy array: {exc}") from None
            arr = np.asarray(arr, dtype=float)
            if arr.ndim != 2 or min(arr.shape) < 2:
                raise TopographyError(f"{key}.path", f"{path} holds an array of shape {arr.shape}; need a 2D map")
            if not np.all(np.isfinite(arr)):
                bad = int(arr.size - np.count_nonzero(np.isfinite(arr)))
                raise TopographyError(f"{key}.path", f"{path}: {bad} of {arr.size} values are NaN or infinite")
            try:
                factor = unit_to_metres(spec.unit, f"{key}.unit")
            except InputError as exc:
                raise _rewrap(exc, key) from None
            if spec.size is not None:
                lx = ly = spec.size
            elif spec.lx is not None:
                lx, ly = spec.lx, spec.ly
            else:
                lx = ly = None  # filled in by the caller from the grid
            topo = (arr * factor, lx, ly, str(path))
            self.cache[key] = topo
            return topo
        if spec.crop is not None:
            c = spec.crop
            try:
                topo = topo.crop(c.x0, c.y0, c.lx, c.ly)
            except InputError as exc:
                raise _rewrap(exc, key) from None
        self.cache[key] = topo
        return topo

    def array_topography(self, spec, key: str, grid_lengths):

        heights, lx, ly, source = self.topography(spec, key)
        if lx is None:
            if grid_lengths is None:
                raise InputError(f"{key}.size", "required (or lx and ly) when [grid] has no size")
            lx, ly = grid_lengths
        nx, ny = heights.shape
        try:
            topo = Topography(heights, Grid(nx, ny, lx, ly, False), source, {"format": "npy"})
            topo = topo.detrended(spec.detrend)
            if spec.crop is not None:
                c = spec.crop
                topo = topo.crop(c.x0, c.y0, c.lx, c.ly)
        except InputError as exc:
            raise _rewrap(exc, key) from None
        return topo


def _grid(sc: Scenario, loader: _Loader) -> Grid:
    nx, ny = sc.grid.shape
    lengths = sc.grid.lengths
    if lengths is None:
        for body in ("body1", "body2"):
            r = getattr(sc, body).roughness
            key = f"{body}.roughness"
            if r.kind == "file":
                g = loader.topography(r, key).grid
                lengths = (g.lx, g.ly)
                break
            if r.kind == "array" and (r.size is not None or r.lx is not None):
                lengths = (r.size, r.size) if r.size is not None else (r.lx, r.ly)
                break
        if lengths is None:
            raise InputError("grid.size", "required (or lx and ly): no roughness file gives the size")
    return Grid(int(nx), int(ny), float(lengths[0]), float(lengths[1]), bool(sc.grid.periodic))


def _shape(spec, grid: Grid, key: str) -> np.ndarray:

    try:
        if spec.kind == "flat":
            return geo.flat(grid)
        if spec.kind == "sphere":
            return geo.sphere(grid, spec.radius, exact=spec.exact, center=tuple(spec.center))
        if spec.kind == "cylinder":
            return geo.cylinder(grid, spec.radius, axis=spec.axis, center=spec.center)
        if spec.kind == "wavy_sphere":
            return geo.wavy_sphere(grid, spec.radius, spec.amplitude, spec.wavelength, center=tuple(spec.center))
        if spec.kind == "bisinusoidal":
            wx = spec.wavelength_x if spec.wavelength_x is not None else grid.lx
            wy = spec.wavelength_y if spec.wavelength_y is not None else grid.ly
            h = geo.bisinusoidal(grid, spec.amplitude, wx, wy)
            return h - h.min()
        if spec.kind == "burl":
            return geo.burl(grid, spec.radius, spec.edge_radius, crown=spec.crown, center=tuple(spec.center))
    except InputError as exc:
        raise _rewrap(exc, key) from None
    raise InputError(f"{key}.kind", f"unknown shape {spec.kind!r}")  # pragma: no cover (schema checks)


def _roughness(spec, grid: Grid, key: str, loader: _Loader, info: dict, warns: list) -> np.ndarray:

    try:
        if spec.kind == "none":
            return np.zeros(grid.shape)
        if spec.kind == "gaussian":
            return geo.gaussian_surface(grid, spec.rms, spec.correlation_length,
                                        correlation_length_y=spec.correlation_length_y, seed=spec.seed,
                                        skewness=spec.skewness, kurtosis=spec.kurtosis)
        if spec.kind == "self_affine":
            return geo.self_affine_surface(grid, spec.hurst, rms_height=spec.rms, rms_slope=spec.rms_slope,
                                           rolloff_wavelength=spec.rolloff, short_cutoff=spec.short_cutoff,
                                           long_cutoff=spec.long_cutoff, seed=spec.seed)
    except InputError as exc:
        raise _rewrap(exc, key) from None
    # measured: file or array
    if spec.kind == "file":
        topo = loader.topography(spec, key)
    else:
        topo = loader.array_topography(spec, key, (grid.lx, grid.ly))
    tg = topo.grid
    same = (tg.shape == grid.shape and math.isclose(tg.lx, grid.lx, rel_tol=1e-9)
            and math.isclose(tg.ly, grid.ly, rel_tol=1e-9) and spec.offset == [0.0, 0.0])
    try:
        h = topo.heights.copy() if same else topo.resample(grid, offset=tuple(spec.offset)).heights
        if spec.rms is not None:
            h = geo.scale_to_rms(h, spec.rms)
    except InputError as exc:
        raise _rewrap(exc, key) from None
    if spec.invert:
        h = -h
    info.setdefault("files", {})[key] = {
        "path": str(topo.source or spec.path),
        "scan_grid": [int(tg.nx), int(tg.ny)],
        "scan_size": [float(tg.lx), float(tg.ly)],
        "resampled": not same,
        "format": topo.info.get("format", ""),
        "channel": topo.info.get("channel", ""),
        "original_unit": topo.info.get("original_unit", ""),
    }
    if grid.periodic:
        warns.append(f"{key}: a measured topography is not periodic; the periodic operator repeats it "
                     "with steps at the edges (use periodic = false for free-boundary contact)")
    if not same and (grid.dx > 1.5 * tg.dx or grid.dy > 1.5 * tg.dy):
        info.setdefault("notes", []).append(
            f"{key}: scan of {tg.nx} x {tg.ny} points resampled (linear interpolation) to the "
            f"{grid.nx} x {grid.ny} solver grid; wavelengths below {2 * grid.dx:.3g} m are aliased")
    return h


def _texture_and_waviness(body: BodySpec, grid: Grid, name: str, window=None) -> np.ndarray | None:
    """A body's texture plus waviness (m, positive out of the body), None when it has neither.

    The grid's resolution is checked first (features of >= 3 cells, a burl within the domain:
    :func:`tribobem.geometry.textures.check_body_geometry`): the schema checks the same when the
    scenario gives the grid's size, this catches a grid sized by a topography file.  With a
    two-scale ``window`` (its :class:`TwoScaleSpec`) a texture that tiles the window belongs to
    the micro windows and is left out here.
    """
    from ..geometry.textures import check_body_geometry, texture_fits_window

    win = (window.window, window.window_n) if window is not None else None
    check_body_geometry(body, grid.dx, grid.dy, (grid.lx, grid.ly), name, window=win)
    out = None
    if body.texture is not None and not (win is not None and texture_fits_window(body.texture.pitch, win[0])):
        t = body.texture
        out = geo.texture(grid, t.kind, t.pitch, t.size, t.depth, t.angle, key=f"{name}.texture")
    if body.waviness is not None:
        w = body.waviness
        wav = geo.waviness(grid, w.amplitude, w.wavelength, w.angle, key=f"{name}.waviness")
        out = wav if out is None else out + wav
    return out


#: A micro window should hold at least this many correlation lengths (Gaussian roughness) or
#: long-wavelength cut-offs (self-affine): fewer and the window's own extreme summits and its
#: missing long wavelengths set the law (the window study: 2 roll-off wavelengths miss the
#: contact area by up to 20 %, 5 represent it within 4 %).
MIN_WINDOW_WAVELENGTHS = 5.0


def _longest_wavelength(spec) -> tuple[float, str] | None:
    """The roughness' longest wavelength that a window must hold (m) and the key that sets it."""
    if spec.kind == "gaussian":
        return max(spec.correlation_length, spec.correlation_length_y or 0.0), "correlation_length"
    if spec.kind == "self_affine":
        for key in ("long_cutoff", "rolloff"):
            if getattr(spec, key) is not None:
                return float(getattr(spec, key)), key
    return None


def _scan_tiles(spec, wgrid: Grid, key: str, loader, info: dict):
    """A measured roughness split at the window's side: its windows and its long wavelengths.

    The scan (detrended and cropped as its section says, scaled to ``rms`` when given) is split
    at the wavelength of the window's side (:func:`tribobem.geometry.topography.split_at_wavelength`).
    The short part is cut into non-overlapping squares of the window's side, row by row, each
    resampled to the window's cells (linear interpolation) and made periodic by its
    periodic-plus-smooth split (no steps at the window's edges): the micro windows.  The long
    part, returned as a Topography, goes to the macro grid.
    """
    from ..geometry.topography import Topography, periodic_component, split_at_wavelength

    if spec.kind != "file":
        raise InputError(key, "windows are cut from a measured scan given as a file (kind = 'file'); an array "
                         "topography has no physical size of its own here")
    topo = loader.topography(spec, key)
    tg = topo.grid
    kx, ky = int(tg.lx // (wgrid.lx * (1 - 1e-9))), int(tg.ly // (wgrid.ly * (1 - 1e-9)))
    if kx * ky == 0:
        raise InputError("two_scale.window", f"{wgrid.lx:.4g} m is larger than {key}'s scan ({tg.lx:.4g} x "
                         f"{tg.ly:.4g} m): the windows are cut from the scan")
    h = topo.heights - float(np.mean(topo.heights))
    if spec.rms is not None:
        h = h * (float(spec.rms) / float(np.sqrt(np.mean(h ** 2))))
    if spec.invert:
        h = -h
    long, short = split_at_wavelength(h, tg.dx, tg.dy, wgrid.lx)
    fine = Topography(short, tg, source=topo.source)
    out = []
    box = Grid(wgrid.nx, wgrid.ny, wgrid.lx, wgrid.ly, periodic=False)
    for j in range(ky):
        for i in range(kx):
            # the resample offset is from the scan's centre to the window's centre
            off = ((i + 0.5) * wgrid.lx - 0.5 * tg.lx, (j + 0.5) * wgrid.ly - 0.5 * tg.ly)
            p = periodic_component(fine.resample(box, offset=off).heights)
            out.append(p - p.mean())
    rms = float(np.sqrt(np.mean(h ** 2)))
    info.setdefault("files", {})[key] = {"path": str(topo.source or spec.path), "scan_grid": [int(tg.nx), int(tg.ny)],
                                         "scan_size": [float(tg.lx), float(tg.ly)], "windows": kx * ky,
                                         "scan_rms": rms, "window_rms": float(np.sqrt(np.mean(short ** 2))),
                                         "macro_rms": float(np.sqrt(np.mean(long ** 2)))}
    return out, Topography(long, tg, source=topo.source)


def _micro_windows(sc: Scenario, grid: Grid, pair, interaction, info: dict, warns: list, loader=None):
    """The periodic micro windows of a ``[two_scale]`` run: one gap per roughness realisation.

    Each window holds both bodies' roughness, generated on the window grid with the seeds
    ``seed + k`` (k = 0 .. realisations - 1; seed 0 when the scenario gives none, so that a
    rerun reuses the cached tables) or cut from a measured scan (window k: the scan's k-th
    square, :func:`_scan_tiles`), and the textures that tile it.
    """
    from ..geometry.textures import texture_fits_window
    from ..two_scale.micro import MicroWindows

    ts = sc.two_scale
    if pair is None:
        raise InputError("two_scale", "a two-scale run needs an elastic body (both bodies are rigid)")
    wgrid = Grid(int(ts.window_n), int(ts.window_n), float(ts.window), float(ts.window), True)
    specs = {name: getattr(sc, name).roughness for name in ("body1", "body2")}
    split = {name: _scan_tiles(spec, wgrid, f"{name}.roughness", loader, info)
             for name, spec in specs.items() if spec.kind in ("file", "array")}
    tiles = {name: t for name, (t, _) in split.items()}
    realisations = int(ts.realisations)
    for name, t in tiles.items():
        if len(t) < realisations:
            warns.append(f"two_scale.realisations: {name}'s scan holds {len(t)} window(s) of {ts.window:.3g} m; "
                         f"{len(t)} realisation(s) instead of {realisations}")
            realisations = len(t)
    for name, spec in specs.items():
        longest = _longest_wavelength(spec)
        if longest is not None and ts.window < MIN_WINDOW_WAVELENGTHS * longest[0] * (1 - 1e-9):
            raise InputError("two_scale.window", f"{ts.window:.4g} m holds {ts.window / longest[0]:.2f} of "
                             f"{name}.roughness.{longest[1]} ({longest[0]:.4g} m); a window must hold at least "
                             f"{MIN_WINDOW_WAVELENGTHS:g} (>= {MIN_WINDOW_WAVELENGTHS * longest[0]:.4g} m) so that "
                             "its summits and long wavelengths are those of the surface")
        if spec.kind == "gaussian" and spec.correlation_length < 3 * wgrid.dx:
            warns.append(f"two_scale.window_n: the window's cells ({wgrid.dx:.3g} m) resolve {name}'s "
                         f"correlation length ({spec.correlation_length:.3g} m) with "
                         f"{spec.correlation_length / wgrid.dx:.1f} cells (< 3): the asperity tips are not resolved")
    for name in ("body1", "body2"):
        tex = getattr(sc, name).texture
        if tex is not None and tex.pitch < ts.window and not texture_fits_window(tex.pitch, ts.window):
            raise InputError("two_scale.window", f"{ts.window:.4g} m holds {ts.window / tex.pitch:.3f} periods of "
                             f"{name}.texture ({tex.pitch:.4g} m): a texture shorter than the window belongs to the "
                             "periodic windows, which must hold a whole number of its periods "
                             f"(e.g. {round(ts.window / tex.pitch) * tex.pitch:.4g} m)")
        shape = getattr(sc, name).shape
        if getattr(shape, "kind", None) == "burl":
            # the edge zone: where the burl's edge falls by the interface's height scale (4 rms
            # of the combined roughness), over which the nominal pressure drops to zero
            rms = math.sqrt(sum((float(np.std(tiles[n][0])) if n in tiles else float(getattr(sp, "rms", None) or 0.0))
                                ** 2 for n, sp in specs.items()))
            edge = math.sqrt(2.0 * float(shape.edge_radius) * 4.0 * rms) if rms > 0 else None
            if edge is not None and grid.dx > 0.5 * edge:
                warns.append(f"grid.n: the macro cells ({grid.dx:.3g} m) are coarser than half the burl's edge zone "
                             f"({edge:.3g} m: where its edge falls by 4 rms of the roughness); the nominal pressure "
                             "at the edge is not resolved: refine grid.n")
    if all(spec.kind == "none" for spec in specs.values()):
        raise InputError("two_scale", "a two-scale run needs a rough body (body1 or body2 roughness): the micro "
                         "windows hold the roughness")
    gaps = []
    first: dict = {}  # each body's roughness in the first window, for the summary's statistics
    surfaces = []
    for k in range(realisations):
        own = {}
        for name, spec in specs.items():
            surf = np.zeros(wgrid.shape)
            if name in tiles:
                surf = surf + tiles[name][k]
                first.setdefault(name, (tiles[name][k], wgrid))
            elif spec.kind != "none":
                seeded = spec.model_copy(update={"seed": int(spec.seed or 0) + k})
                rough = _roughness(seeded, wgrid, f"{name}.roughness", None, {}, [])
                surf = surf + rough
                first.setdefault(name, (rough, wgrid))
            tex = getattr(sc, name).texture
            if tex is not None and texture_fits_window(tex.pitch, ts.window):
                surf = surf + geo.texture(wgrid, tex.kind, tex.pitch, tex.size, tex.depth, tex.angle,
                                          key=f"{name}.texture")
            own[name] = surf
        topo = own["body1"] + own["body2"]
        surfaces.append((own["body1"], own["body2"]))
        gaps.append(topo.max() - topo)  # gap = -(topography1 + topography2), shifted to min 0
    short = [f"{n}.texture" for n in ("body1", "body2") if getattr(sc, n).texture is not None
             and texture_fits_window(getattr(sc, n).texture.pitch, ts.window)]
    winfo = {"window": float(ts.window), "window_n": int(ts.window_n), "window_dx": float(wgrid.dx),
             "realisations": int(realisations), "measured": sorted(tiles), "macro_dx": float(grid.dx),
             "seeds": [int(getattr(specs[n], "seed", None) or 0) for n in ("body1", "body2")], "window_textures": short}
    info["two_scale"] = winfo
    zero = np.zeros(wgrid.shape)
    # each window's own water films rest on its own two surfaces
    hum = [humidity_setup(sc, zero, zero, s1, s2) for s1, s2 in surfaces] if sc.humidity is not None else None
    windows = MicroWindows(wgrid, pair, gaps, interaction, dict(winfo), surfaces=surfaces, humidity=hum)
    windows.info["roughness_of"] = {n: r for n, (r, _) in first.items()}
    # a measured scan's wavelengths longer than the window: part of the macro geometry
    windows.info["macro_roughness"] = {n: lt for n, (_, lt) in split.items()}
    return windows


def _sphere_radius(sc: Scenario) -> float | None:
    """Composite radius 1/R = 1/R1 + 1/R2 when the bodies are spheres (else None)."""
    curv, found = 0.0, False
    for body in (sc.body1, sc.body2):
        s = body.shape
        if s.kind in ("sphere", "wavy_sphere"):
            curv += 1.0 / s.radius
            found = True
        elif s.kind != "flat":
            return None
    return 1.0 / curv if found else None


#: ``[solver] backend = "cupy"`` on grids of fewer nodes is solved with NumPy, which is faster
#: there.  Measured with benchmarks/gpu.py (H100, CuPy 14.2, against 2 CPU cores): a free-boundary
#: Hertz solve takes 0.34 / 1.08 / 1.65 s on the GPU at 256^2 / 512^2 / 1024^2 against 0.19 /
#: 0.53 / 2.66 s on the CPU, and the coupled kinds at 64^2-128^2 are 10-15x slower on the GPU
#: (per-iteration launches and host round trips), 29x faster at 2048^2 (the burl ramp).  The
#: first CuPy call of a machine also compiles kernels (38 s; 4-5 s in later processes, which read
#: CuPy's on-disk kernel cache).  Env ``TRIBOBEM_CUPY_MIN_NODES`` overrides (0: always CuPy).
CUPY_MIN_NODES = 1024 * 1024


def _backend_for(requested: str, grid: Grid, info: dict) -> str:
    """The array backend a scenario runs on: NumPy for ``cupy`` below ``CUPY_MIN_NODES`` nodes
    (said in ``info["backend"]``), else the requested one."""
    env = os.environ.get("TRIBOBEM_CUPY_MIN_NODES")
    limit = int(env) if env else CUPY_MIN_NODES
    if requested == "cupy" and grid.nx * grid.ny < limit:
        info["backend"] = (f"numpy (cupy requested; grids below {limit} nodes run on NumPy, which is faster "
                           f"there than a GPU; TRIBOBEM_CUPY_MIN_NODES=0 forces cupy)")
        return "numpy"
    info["backend"] = requested
    return requested


def build_problem(scenario: Scenario, base_dir=None) -> Problem:
    """Build the grid, materials, gap, operator and interaction of a scenario.

    Parameters
    ----------
    scenario : Scenario
        A validated scenario (see :func:`tribobem.scenario.parse_scenario`).
    base_dir : path-like, optional
        Folder that relative file paths are resolved against (the scenario file's folder;
        default: the current directory).

    Returns
    -------
    Problem

    Raises
    ------
    InputError, TopographyError, MemoryBudgetError, FileNotFoundError
    """
    # the surfaces' generation and statistics transform full grids (padded, for the statistics
    # of a free grid): on the solvers' FFT threads, not one (they were a third of the build of a
    # 4096^2 burl)
    with sfft.set_workers(default_workers()):
        return _build_problem(scenario, base_dir)


def _body_model(sc):
    """The pair's body model: a coated body (``[bodyN] layer``), else None (two half-spaces)."""
    coated = [(i, b.layer) for i, b in ((1, sc.body1), (2, sc.body2)) if b.layer is not None]
    if not coated:
        return None
    if len(coated) > 1:
        raise InputError("body2.layer", "only one of the two bodies may carry a layer")
    if sc.two_scale is not None:
        raise InputError(f"body{coated[0][0]}.layer", "a coated body is not available with [two_scale] yet; leave "
                         "[two_scale] out (whole-grid contact), or the layer out")
    i, layer = coated[0]
    return CoatedHalfSpace(i, float(layer.E), float(layer.nu), float(layer.thickness))


def _hardness(sc) -> float | None:
    """The pressure cap (Pa): the smaller hardness of the two bodies, None when neither has one."""
    values = [b.hardness for b in (sc.body1, sc.body2) if b.hardness is not None]
    if values and sc.two_scale is not None:
        key = "body1.hardness" if sc.body1.hardness is not None else "body2.hardness"
        raise InputError(key, "a hardness cap is not available with [two_scale] yet (each micro window would "
                              "need its own plastic history); leave [two_scale] out to cap a whole-grid "
                              "contact, or leave the hardness out")
    return min(values) if values else None


def _build_problem(scenario: Scenario, base_dir) -> Problem:
    sc = scenario
    base = Path(base_dir) if base_dir is not None else Path.cwd()
    loader = _Loader(base)
    grid = _grid(sc, loader)
    grid.check_memory()
    both_rigid = sc.body1.rigid and sc.body2.rigid  # only a capillary run at an approach (schema)
    pair = None if both_rigid else ContactPair(body_material(sc.body1, "body1"), body_material(sc.body2, "body2"),
                                               model=_body_model(sc))

    info: dict = {}
    warns: list = []
    shape1 = _shape(sc.body1.shape, grid, "body1.shape")
    shape2 = _shape(sc.body2.shape, grid, "body2.shape")
    ts = sc.two_scale
    if ts is None:
        rough1 = _roughness(sc.body1.roughness, grid, "body1.roughness", loader, info, warns)
        rough2 = _roughness(sc.body2.roughness, grid, "body2.roughness", loader, info, warns)
    else:  # the roughness lives in the micro windows (_micro_windows); [grid] is the macro grid
        rough1, rough2 = np.zeros(grid.shape), np.zeros(grid.shape)
    stats_of = {"body1": rough1, "body2": rough2}  # the roughness proper, for its statistics
    for name in ("body1", "body2"):
        extra = _texture_and_waviness(getattr(sc, name), grid, name, window=ts)
        if extra is not None:
            if name == "body1":
                rough1 = rough1 + extra
            else:
                rough2 = rough2 + extra
    gap = shape1 + shape2 - rough1 - rough2
    if not np.all(np.isfinite(gap)):
        raise InputError("gap", "the initial gap contains NaN or infinite values")
    gap = gap - float(gap.min())

    # Friction needs the coupled 3x3 operator (tangential and normal-tangential blocks).
    components = ("x", "y", "z") if (sc.friction is not None and sc.friction.coefficient is not None) else ("z",)
    backend = _backend_for(sc.solver.backend, grid, info)
    try:
        if both_rigid:
            # No elasticity: the capillary solver takes operator=None (rigid bodies).
            op = None
        elif grid.periodic:
            op = make_operator(grid, pair, components, backend=backend, kernel=sc.solver.kernel)
        else:
            op = make_operator(grid, pair, components, backend=backend)
    except (ImportError, ModuleNotFoundError) as exc:
        raise InputError("solver.backend", f"backend {backend!r} is not available: {exc}") from None
    if op is not None and op.backend.name == "numpy":
        # the FFT engine of the operator's whole-array transforms (elasticity/backend.py): runs on
        # different engines differ by round-off, which a multistable adhesive contact can carry
        # to another branch
        info["fft"] = op.backend.fft

    # the registered law of [adhesion] (interactions/registry.py); None: no stress law
    E_star = pair.effective_modulus if pair is not None else None  # None: both bodies rigid
    interaction = get_law(sc.adhesion.model).build(sc.adhesion, LawContext(grid, E_star))
    hardness = _hardness(sc)
    if hardness is not None:
        # the pressure cap of the softer surface, around the law (interactions/hardness.py)
        interaction = HardnessCap(hardness, interaction)
    humidity = humidity_setup(sc, shape1, shape2, rough1, rough2)
    windows = _micro_windows(sc, grid, pair, interaction, info, warns, loader) if ts is not None else None
    if windows is not None and windows.info.get("macro_roughness"):
        # a measured scan's wavelengths longer than the window are part of the macro geometry
        macro = windows.info.pop("macro_roughness")
        for name, long in macro.items():
            spec = getattr(sc, name).roughness
            h = long.resample(grid, offset=tuple(spec.offset)).heights
            if name == "body1":
                rough1 = rough1 + h
            else:
                rough2 = rough2 + h
            gap = gap - h
        # the approach is then measured from the first touch of the macro gap with its long
        # wavelengths; this shift takes it back to the mean planes of the undeformed bodies
        info["two_scale"]["macro_gap_shift"] = float(gap.min())
        gap = gap - float(gap.min())

    info.update({
        "grid": {"nx": grid.nx, "ny": grid.ny, "lx": grid.lx, "ly": grid.ly, "dx": grid.dx, "dy": grid.dy,
                 "periodic": grid.periodic},
        "operator": op.kind if op is not None else "none (both bodies rigid)",
        "effective_modulus": E_star,
        # a coated body: its layer (the pair's E* above is the substrates')
        **({"layer": {"body": pair.model.coated, "E": pair.model.E, "nu": pair.model.nu,
                      "thickness": pair.model.thickness}}
           if pair is not None and isinstance(pair.model, CoatedHalfSpace) else {}),
        "gap_peak_to_valley": float(gap.max()),
    })
    radius = _sphere_radius(sc)
    if radius is not None:
        info["radius"] = radius
    info.update(law_summary_info(interaction, radius, E_star))  # the law's own scalars (Dugdale: sigma0, h0, ...)
    if windows is not None:  # the roughness lives in the windows: its statistics are the first window's
        stats_of = windows.info.pop("roughness_of")
    for name, h in stats_of.items():
        kind = getattr(sc, name).roughness.kind
        if kind != "none":
            try:
                s = geostats.summary(h, windows.grid if windows is not None else grid)
            except Exception as exc:  # statistics are informative only
                s = {"error": str(exc)}
            info.setdefault("roughness", {})[name] = {k: float(v) for k, v in s.items() if isinstance(v, (int, float))}
    if humidity is not None:
        info["humidity"] = humidity.info()
    return Problem(sc, grid, pair, op, gap, rough1, rough2, shape1, shape2, interaction, humidity, info, warns, base,
                   two_scale=windows)
