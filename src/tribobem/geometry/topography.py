"""Measured topographies: reading (SurfaceTopography), units, detrending, cropping, resampling,
and the gap between the two bodies.

Sign convention: heights are positive upward (m). Body 1 is the lower body, body 2 the upper;
the initial gap is ``h = h2 - h1`` (:func:`combine_gap`), where ``h2`` is the height of body
2's lower surface above ``z = 0`` (a shape from :mod:`tribobem.geometry.shapes` plus its
roughness) and ``h1`` the topography of body 1 (positive up).
"""

from __future__ import annotations

import functools
import math
import os
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..errors import InputError, TopographyError
from ..grid import Grid
from . import stats as _stats

__all__ = [
    "Topography",
    "periodic_component",
    "split_at_wavelength",
    "read_topography",
    "detrend_heights",
    "validate_heights",
    "combine_gap",
    "gap_from_bodies",
    "unit_to_metres",
    "DETREND_MODES",
]

#: Accepted ``detrend`` modes (SurfaceTopography names; "height" removes the best plane,
#: "curvature" the best quadratic, both in the least-squares sense).
DETREND_MODES = ("none", "center", "height", "curvature")

_UNITS = {
    "m": 1.0,
    "km": 1e3,
    "dm": 1e-1,
    "cm": 1e-2,
    "mm": 1e-3,
    "\u00b5m": 1e-6,  # micro sign
    "\u03bcm": 1e-6,  # Greek mu
    "um": 1e-6,
    "micron": 1e-6,
    "nm": 1e-9,
    "\u00c5": 1e-10,  # Angstrom sign
    "\u212b": 1e-10,
    "A": 1e-10,
    "pm": 1e-12,
}


@functools.lru_cache(maxsize=1)
def _unit_registry():
    import pint

    return pint.UnitRegistry()


def unit_to_metres(unit, field: str = "topography.unit") -> float:
    """Factor converting a length unit to metres.

    Parameters
    ----------
    unit : str
        Unit as reported by SurfaceTopography (``'m'``, ``'mm'``, ``'µm'``, ``'nm'``, ...);
        anything else is parsed with pint.
    field : str
        Name used in the error.

    Returns
    -------
    float
        Metres per unit.
    """
    if isinstance(unit, str):
        key = unit.strip()
        if key in _UNITS:
            return _UNITS[key]
        try:
            ureg = _unit_registry()
            return float(ureg.Quantity(1.0, key.replace("\u00b5", "u").replace("\u03bc", "u")).to("m").magnitude)
        except Exception as exc:  # pint raises many types
            raise InputError(field, f"unknown length unit {unit!r} ({exc})") from None
    raise InputError(field, f"expected a length unit such as 'm', 'um' or 'nm', got {unit!r}")


def validate_heights(h, field: str = "topography", grid: Grid | None = None) -> np.ndarray:
    """Check a height array: 2D, finite, and (optionally) of the grid's shape.

    Parameters
    ----------
    h : array_like
        Heights (m).
    field : str
        Name of the input, used in the error message.
    grid : Grid, optional
        If given, ``h.shape`` must equal ``grid.shape``.

    Returns
    -------
    ndarray
        ``h`` as a float64 array.

    Raises
    ------
    InputError
        Naming ``field`` if ``h`` is not 2D, has the wrong shape, or contains NaN/inf
        (the message gives their number).
    """
    if isinstance(h, Topography):
        h = h.heights
    if isinstance(h, np.ma.MaskedArray):
        h = np.ma.filled(h.astype(float), np.nan)
    try:
        a = np.asarray(h, dtype=float)
    except (TypeError, ValueError) as exc:
        raise InputError(field, f"heights must be numbers: {exc}") from None
    if a.ndim != 2:
        raise InputError(field, f"expected a 2D array of heights [ix, iy], got {a.ndim} dimension(s)")
    if grid is not None and a.shape != grid.shape:
        raise InputError(field, f"array shape {a.shape} does not match the grid {grid.shape}")
    bad = int(a.size - np.count_nonzero(np.isfinite(a)))
    if bad:
        raise InputError(
            field, f"{bad} of {a.size} height values are NaN or infinite; all heights must be finite (m)"
        )
    return a


def detrend_heights(h, grid: Grid, mode: str = "center") -> np.ndarray:
    """Remove a polynomial trend (least squares).

    Parameters
    ----------
    h : array_like, shape (nx, ny)
        Heights (m).
    grid : Grid
        Grid of ``h``.
    mode : {"none", "center", "height", "curvature"}
        ``"center"``: subtract the mean; ``"height"``: the plane ``a + b x + c y`` that
        minimises the rms height; ``"curvature"``: the quadratic
        ``a + b x + c y + d x^2 + e x y + f y^2`` that minimises it (SurfaceTopography's
        ``detrend_mode`` of the same names).

    Returns
    -------
    ndarray, shape (nx, ny)
        Detrended heights (m).
    """
    h = np.asarray(h, dtype=float)
    if mode is None or mode == "none":
        return h.copy()
    if mode == "center":
        return h - h.mean()
    if mode not in DETREND_MODES:
        raise InputError("topography.detrend", f"must be one of {DETREND_MODES}, got {mode!r}")
    x = (grid.x / grid.lx)[:, None] * np.ones((1, grid.ny))
    y = np.ones((grid.nx, 1)) * (grid.y / grid.ly)[None, :]
    cols = [np.ones(h.size), x.ravel(), y.ravel()]
    if mode == "curvature":
        cols += [x.ravel() ** 2, (x * y).ravel(), y.ravel() ** 2]
    A = np.stack(cols, axis=1)
    coef, *_ = np.linalg.lstsq(A, h.ravel(), rcond=None)
    return h - (A @ coef).reshape(h.shape)


@dataclass
class Topography:
    """A topography on a regular grid, in SI units.

    Parameters
    ----------
    heights : ndarray, shape (nx, ny)
        Heights (m), positive up, indexed ``[ix, iy]``.
    grid : Grid
        The grid (cell sizes and side lengths in m).
    source : str
        Path of the file it was read from, or ``""``.
    info : dict
        Metadata: ``format``, ``reader``, ``instrument``, ``channel``, ``original_unit``,
        ``detrend``, ``filled_points``, and a ``history`` of the operations applied.
    """

    heights: np.ndarray
    grid: Grid
    source: str = ""
    info: dict = field(default_factory=dict)

    def __post_init__(self):
        self.heights = validate_heights(self.heights, "topography.heights", self.grid)
        self.source = str(self.source) if self.source else ""
        self.info = dict(self.info)

    # ---------------------------------------------------------------- helpers
    def _derived(self, heights, grid, step: str) -> "Topography":
        info = dict(self.info)
        info["history"] = list(self.info.get("history", [])) + [step]
        return Topography(heights, grid, self.source, info)

    @property
    def shape(self) -> tuple[int, int]:
        """``(nx, ny)``."""
        return self.grid.shape

    def stats(self) -> dict:
        """Scalar statistics, see :func:`tribobem.geometry.stats.summary`.

        Returns
        -------
        dict
            rms height (m), rms slope, rms curvature (1/m), skewness, kurtosis, correlation
            length (m), peak-to-valley (m), mean (m).
        """
        return _stats.summary(self.heights, self.grid)

    # ---------------------------------------------------------------- operations
    def detrended(self, mode: str = "center") -> "Topography":
        """A copy with a polynomial trend removed (see :func:`detrend_heights`).

        Parameters
        ----------
        mode : {"none", "center", "height", "curvature"}
            Trend to remove.

        Returns
        -------
        Topography
        """
        return self._derived(detrend_heights(self.heights, self.grid, mode), self.grid, f"detrend({mode})")

    def window(self, ix0: int, iy0: int, nx: int, ny: int, periodic: bool = False) -> "Topography":
        """A sub-array of cells ``[ix0:ix0+nx, iy0:iy0+ny]``.

        Parameters
        ----------
        ix0, iy0 : int
            First cell (0-based, from the lower-left corner).
        nx, ny : int
            Number of cells (>= 2).
        periodic : bool
            Periodicity flag of the new grid.

        Returns
        -------
        Topography
            With a grid of ``nx x ny`` cells of the original size ``dx x dy``.
        """
        NX, NY = self.grid.shape
        for name, i0, n, N in (("x", ix0, nx, NX), ("y", iy0, ny, NY)):
            if not all(isinstance(v, (int, np.integer)) for v in (i0, n)):
                raise InputError(f"topography.window.{name}", f"indices must be integers, got {i0!r}, {n!r}")
            if i0 < 0 or n < 2 or i0 + n > N:
                raise InputError(
                    f"topography.window.{name}",
                    f"cells [{i0}, {i0 + n}) must lie within [0, {N}) and span >= 2 cells",
                )
        grid = Grid(int(nx), int(ny), nx * self.grid.dx, ny * self.grid.dy, periodic)
        h = self.heights[ix0 : ix0 + nx, iy0 : iy0 + ny].copy()
        return self._derived(h, grid, f"window({ix0}, {iy0}, {nx}, {ny})")

    def crop(self, x0: float, y0: float, lx: float, ly: float, periodic: bool = False) -> "Topography":
        """A rectangular sub-region given in metres.

        Parameters
        ----------
        x0, y0 : float
            Lower-left corner of the region (m), measured from the lower-left corner of the
            topography (not from its centre).
        lx, ly : float
            Side lengths (m).
        periodic : bool
            Periodicity flag of the new grid.

        Returns
        -------
        Topography
            The cells whose index range is ``round(x0/dx) .. round(x0/dx) + round(lx/dx)``
            (the region is snapped to whole cells; the new grid's sides are multiples of
            ``dx, dy``).
        """
        g = self.grid
        vals = {}
        for name, v in (("x0", x0), ("y0", y0), ("lx", lx), ("ly", ly)):
            try:
                vals[name] = float(v)
            except (TypeError, ValueError):
                raise InputError(f"topography.crop.{name}", f"must be a length in m, got {v!r}") from None
            if not math.isfinite(vals[name]):
                raise InputError(f"topography.crop.{name}", f"must be finite, got {v!r}")
        ix0, iy0 = int(round(vals["x0"] / g.dx)), int(round(vals["y0"] / g.dy))
        nx, ny = int(round(vals["lx"] / g.dx)), int(round(vals["ly"] / g.dy))
        if ix0 < 0 or iy0 < 0 or nx < 2 or ny < 2 or ix0 + nx > g.nx or iy0 + ny > g.ny:
            raise InputError(
                "topography.crop",
                f"region x in [{x0}, {vals['x0'] + vals['lx']}] m, y in [{y0}, {vals['y0'] + vals['ly']}] m "
                f"must lie within [0, {g.lx:.6g}] x [0, {g.ly:.6g}] m and span >= 2 cells",
            )
        return self.window(ix0, iy0, nx, ny, periodic)

    def resample(self, grid: Grid, offset=(0.0, 0.0)) -> "Topography":
        """Linear interpolation onto another grid.

        Parameters
        ----------
        grid : Grid
            Target grid. Its centre is placed at ``offset`` from this topography's centre, so
            a grid of the same physical size covers the same area, and a smaller one a
            centred (or offset) sub-window.
        offset : (float, float)
            Position of the target grid's centre relative to this one's (m).

        Returns
        -------
        Topography
            Heights at the target cell centres (bilinear interpolation). Target points within
            half a cell of the edge take the edge value (periodic topographies wrap).

        Notes
        -----
        Linear interpolation does not low-pass filter: when coarsening a rough scan by a
        large factor, short wavelengths alias (crop or detrend first if that matters).
        """
        from scipy.ndimage import map_coordinates

        if not isinstance(grid, Grid):
            raise InputError("topography.resample.grid", f"expected a Grid, got {type(grid).__name__}")
        try:
            ox, oy = (float(v) for v in offset)
        except (TypeError, ValueError):
            raise InputError("topography.resample.offset", f"must be a pair (x, y) in m, got {offset!r}") from None
        g = self.grid
        tx, ty = grid.x + ox, grid.y + oy
        if not g.periodic:
            eps = 1e-9 * max(g.lx, g.ly)
            if (tx.min() < -g.lx / 2 - eps or tx.max() > g.lx / 2 + eps or ty.min() < -g.ly / 2 - eps
                    or ty.max() > g.ly / 2 + eps):
                raise InputError(
                    "topography.resample.grid",
                    f"target grid spans x in [{tx.min():.6g}, {tx.max():.6g}] m, y in [{ty.min():.6g}, "
                    f"{ty.max():.6g}] m, outside the topography [{-g.lx / 2:.6g}, {g.lx / 2:.6g}] x "
                    f"[{-g.ly / 2:.6g}, {g.ly / 2:.6g}] m",
                )
        fx = (tx - g.x[0]) / g.dx
        fy = (ty - g.y[0]) / g.dy
        FX, FY = np.meshgrid(fx, fy, indexing="ij")
        mode = "grid-wrap" if g.periodic else "nearest"
        h = map_coordinates(self.heights, [FX, FY], order=1, mode=mode)
        return self._derived(h, grid, f"resample({grid.nx}x{grid.ny}, {grid.lx:.6g}x{grid.ly:.6g} m)")


# ----------------------------------------------------------------------------- reading
def _reader_message(exc: BaseException, limit: int = 400) -> str:
    msg = " ".join(str(exc).split())
    return f"{type(exc).__name__}: {msg[:limit]}{' ...' if len(msg) > limit else ''}"


def _select_channel(reader, channel, path):
    channels = list(reader.channels)
    names = [c.name for c in channels]
    if channel is None:
        return reader.default_channel
    if isinstance(channel, (int, np.integer)) and not isinstance(channel, bool):
        if 0 <= channel < len(channels):
            return channels[int(channel)]
        raise TopographyError(
            "topography.channel", f"index {channel} out of range for {path} ({len(channels)} channels: {names})"
        )
    if isinstance(channel, str):
        for c in channels:
            if c.name == channel:
                return c
        for c in channels:
            if str(c.name).lower() == channel.lower():
                return c
        raise TopographyError("topography.channel", f"no channel named {channel!r} in {path}; channels: {names}")
    raise TopographyError("topography.channel", f"must be None, an index or a name, got {channel!r}")


def read_topography(
    path,
    channel=None,
    detrend: str = "height",
    fill: str = "harmonic",
    periodic: bool = False,
    physical_sizes=None,
    unit: str | None = None,
    size=None,
) -> Topography:
    """Read a measured topography file through SurfaceTopography and convert it to SI.

    Parameters
    ----------
    path : str or path-like
        File in any format SurfaceTopography reads (AFM .tiff/.di/.spm/.ibw/.gwy, confocal
        .plu, .x3p, .datx, .sdf, text, .npy, ...).
    channel : None, int or str
        Channel index or name (case-insensitive). Default: the reader's default channel
        (for multi-channel AFM files the first height channel, e.g. ``HeightTrace`` in an
        Asylum .ibw).
    detrend : {"none", "center", "height", "curvature"}
        Trend removed after filling (see :func:`detrend_heights`). Default ``"height"``: the
        least-squares plane, as is conventional for a measured scan, whose tilt (the sample's
        mounting, the scanner's drift) is no part of the roughness. ``"center"`` removes only
        the mean and keeps the tilt (on a tilted scan the rms height is then mostly tilt and
        the correlation length often undefined).
    fill : {"harmonic", "none"}
        Undefined (masked) points are filled by harmonic interpolation
        (SurfaceTopography ``interpolate_undefined_data``); ``"none"`` raises instead.
    periodic : bool
        Periodicity flag of the resulting grid (measured scans are normally not periodic).
    physical_sizes : (float, float), optional
        Side lengths, in ``unit`` (or the file's unit), for files that do not store them.
    unit : str, optional
        Length unit for files that do not store one (e.g. ``"nm"``).
    size : (float, float), optional
        Side lengths in metres, for files that do not store them: the alternative to
        ``physical_sizes`` (converted to the heights' unit, ``unit`` or the file's own).

    Returns
    -------
    Topography
        Heights and grid in metres; ``info`` holds ``format``, ``reader``, ``instrument``,
        ``channel``, ``channel_index``, ``channels``, ``original_unit``, ``detrend``,
        ``filled_points``.

    Raises
    ------
    TopographyError
        ``topography.path`` if the file is missing, empty or unreadable (with the reader's
        message); ``topography.channel`` for a bad channel or a non-height channel;
        ``topography.heights`` if NaN/inf remain (with their number); ``topography.grid``
        for line scans and non-uniform data; ``topography.unit`` / ``physical_sizes`` if
        the file lacks them and they are not given.
    """
    import SurfaceTopography as st

    p = Path(os.fspath(path))
    if detrend is None:
        detrend = "none"
    if detrend not in DETREND_MODES:
        raise InputError("topography.detrend", f"must be one of {DETREND_MODES}, got {detrend!r}")
    if fill not in ("harmonic", "none"):
        raise InputError("topography.fill", f"must be 'harmonic' or 'none', got {fill!r}")
    if not p.exists():
        raise TopographyError("topography.path", f"file {p} not found")
    if not p.is_file():
        raise TopographyError("topography.path", f"{p} is not a file")
    if p.stat().st_size == 0:
        raise TopographyError("topography.path", f"file {p} is empty")
    try:
        reader = st.open_topography(str(p))
    except Exception as exc:
        raise TopographyError("topography.path", f"cannot read {p}: {_reader_message(exc)}") from exc
    try:
        ch = _select_channel(reader, channel, p)
        kwargs = {"channel_index": ch.index, "periodic": bool(periodic)}
        if size is not None and physical_sizes is None:
            size_unit = unit if unit is not None else getattr(ch, "unit", None)
            if size_unit is None or isinstance(size_unit, (tuple, list)):
                raise TopographyError("topography.unit", f"{p} does not say the length unit of its heights, "
                                      "needed to read its size; pass unit= (e.g. unit='nm')")
            f = unit_to_metres(size_unit)
            physical_sizes = tuple(float(s) / f for s in size)
        if physical_sizes is not None:
            kwargs["physical_sizes"] = tuple(float(s) for s in physical_sizes)
        if unit is not None:
            kwargs["unit"] = unit
        try:
            t = reader.topography(**kwargs)
        except TopographyError:
            raise
        except Exception as exc:
            msg = _reader_message(exc)
            fieldname = "topography.physical_sizes" if "physical_sizes" in msg else "topography.path"
            raise TopographyError(fieldname, f"cannot read channel {ch.name!r} of {p}: {msg}") from exc
        if t.dim != 2 or not t.is_uniform:
            raise TopographyError(
                "topography.grid",
                f"{p} holds a {'non-uniform ' if not t.is_uniform else ''}{t.dim}D line scan, not a 2D map "
                "on a uniform grid; tribobem needs a 2D topography",
            )
        t_unit = t.unit if unit is None else unit
        if t_unit is None:
            raise TopographyError(
                "topography.unit",
                f"{p} does not say its length unit; pass unit= (e.g. unit='nm')",
            )
        if isinstance(t_unit, (tuple, list)):
            raise TopographyError(
                "topography.channel",
                f"channel {ch.name!r} of {p} has no length unit ({t_unit!r}); it is probably not a "
                "height channel (pick one with channel=) or pass unit=",
            )
        try:
            factor = unit_to_metres(t_unit)
        except InputError as exc:
            raise TopographyError("topography.unit", f"{p}: {exc}") from None
        n_undefined = 0
        if t.has_undefined_data:
            n_undefined = int(np.ma.count_masked(t.heights()))
            if fill == "none":
                raise TopographyError(
                    "topography.heights",
                    f"{p} has {n_undefined} undefined (masked) points; use fill='harmonic' to interpolate them",
                )
            try:
                t = t.interpolate_undefined_data("harmonic")
            except Exception as exc:
                raise TopographyError("topography.heights", f"filling undefined data of {p} failed: "
                                      f"{_reader_message(exc)}") from exc
        raw = t.heights()
        if isinstance(raw, np.ma.MaskedArray):
            raw = np.ma.filled(raw.astype(float), np.nan)
        raw = np.asarray(raw, dtype=float)
        bad = int(raw.size - np.count_nonzero(np.isfinite(raw)))
        if bad:
            raise TopographyError(
                "topography.heights", f"{p}: {bad} of {raw.size} height values are NaN or infinite after reading"
            )
        nx, ny = (int(n) for n in t.nb_grid_pts)
        sx, sy = (float(s) * factor for s in t.physical_sizes)
        try:
            grid = Grid(nx, ny, sx, sy, bool(periodic))
        except InputError as exc:
            raise TopographyError("topography.grid", f"{p}: {exc}") from None
        heights = detrend_heights(raw * factor, grid, detrend)
        tinfo = getattr(t, "info", {}) or {}
        instrument = tinfo.get("instrument", {}) or {}
        info = {
            "format": reader.format(),
            "reader": reader.name(),
            "instrument": instrument.get("name", ""),
            "vendor": instrument.get("vendor", ""),
            "channel": ch.name,
            "channel_index": int(ch.index),
            "channels": [c.name for c in reader.channels],
            "original_unit": t_unit,
            "unit_factor": factor,
            "detrend": detrend,
            "filled_points": n_undefined,
            "history": [f"read({p.name})", f"detrend({detrend})"],
        }
        if "acquisition_time" in tinfo:
            info["acquisition_time"] = str(tinfo["acquisition_time"])
        return Topography(heights, grid, str(p), info)
    finally:
        close = getattr(reader, "close", None)
        if close is not None:
            try:
                close()
            except Exception:  # pragma: no cover
                pass


# ----------------------------------------------------------------------------- the gap
def _as_heights(a, field: str):
    if a is None:
        return None
    if isinstance(a, Topography):
        return a.heights
    a = np.asarray(a, dtype=float)
    if a.ndim == 0:
        return a
    return validate_heights(a, field)


def combine_gap(lower, upper) -> np.ndarray:
    """Initial gap ``h = h2 - h1`` between the upper and the lower body.

    Parameters
    ----------
    lower : array_like or Topography or float
        ``h1``: topography of body 1, the lower body (m, positive up).
    upper : array_like or Topography or float
        ``h2``: height of body 2's lower surface above ``z = 0`` (m, positive up), e.g. a
        sphere plus its roughness.

    Returns
    -------
    ndarray
        ``upper - lower`` (m).

    Raises
    ------
    InputError
        ``gap`` if the two arrays have different shapes, or either holds NaN/inf.
    """
    lo = _as_heights(lower, "gap.lower")
    up = _as_heights(upper, "gap.upper")
    if lo.ndim == 2 and up.ndim == 2 and lo.shape != up.shape:
        raise InputError("gap", f"lower body {lo.shape} and upper body {up.shape} topographies differ in shape")
    out = np.asarray(up - lo, dtype=float)
    if not np.all(np.isfinite(out)):
        raise InputError("gap", "the gap contains NaN or infinite values")
    return out


def gap_from_bodies(grid: Grid, upper_shape=None, upper_roughness=None, lower_roughness=None) -> np.ndarray:
    """Gap ``(shape_2 + roughness_2) - roughness_1`` on a grid; missing parts are flat.

    Parameters
    ----------
    grid : Grid
        Grid all parts live on.
    upper_shape : array_like, optional
        Shape of body 2 (m), e.g. :func:`~tribobem.geometry.shapes.sphere`.
    upper_roughness : array_like or Topography, optional
        Roughness of body 2 (m, positive up).
    lower_roughness : array_like or Topography, optional
        Topography of body 1 (m, positive up).

    Returns
    -------
    ndarray, shape (nx, ny)
        Initial gap (m).
    """
    parts = {}
    for name, a in (("upper_shape", upper_shape), ("upper_roughness", upper_roughness),
                    ("lower_roughness", lower_roughness)):
        parts[name] = np.zeros(grid.shape) if a is None else validate_heights(a, f"gap.{name}", grid)
    return combine_gap(parts["lower_roughness"], parts["upper_shape"] + parts["upper_roughness"])


def periodic_component(h: np.ndarray) -> np.ndarray:
    """The periodic part of a non-periodic height map (Moisan's periodic-plus-smooth split).

    ``h = p + s``: ``s`` is the smooth field (harmonic inside, driven by the jumps between
    opposite edges) that carries the map's edge discontinuities, ``p`` is periodic and keeps the
    map's local content (its summits, slopes and curvatures away from the edges).  A scan cut
    into periodic windows keeps its asperities without the steps a plain periodic repeat puts at
    the window's edges.

    Parameters
    ----------
    h : ndarray, shape (nx, ny)
        Heights (m).

    Returns
    -------
    ndarray
        The periodic component p (m), with the mean of ``h``.

    References
    ----------
    L. Moisan, "Periodic plus smooth image decomposition", J. Math. Imaging Vis. 39 (2011) 161.
    """
    h = np.asarray(h, dtype=float)
    nx, ny = h.shape
    v = np.zeros_like(h)
    jx = h[-1, :] - h[0, :]
    jy = h[:, -1] - h[:, 0]
    v[0, :] += jx
    v[-1, :] -= jx
    v[:, 0] += jy
    v[:, -1] -= jy
    cx = 2.0 * np.cos(2.0 * np.pi * np.arange(nx) / nx)[:, None]
    cy = 2.0 * np.cos(2.0 * np.pi * np.arange(ny) / ny)[None, :]
    den = cx + cy - 4.0
    den[0, 0] = 1.0
    s_hat = np.fft.fft2(v) / den
    s_hat[0, 0] = 0.0
    return h - np.real(np.fft.ifft2(s_hat))


def split_at_wavelength(h: np.ndarray, dx: float, dy: float, wavelength: float) -> tuple[np.ndarray, np.ndarray]:
    """Split a non-periodic height map into wavelengths longer and shorter than ``wavelength``.

    The map's periodic component (:func:`periodic_component`) is filtered in Fourier space (a
    sharp cut at |q| = 2 pi / wavelength); the smooth component, which carries the edge
    discontinuities and varies over the whole map, goes with the long part.

    Parameters
    ----------
    h : ndarray, shape (nx, ny)
        Heights (m).
    dx, dy : float
        Cell sizes (m).
    wavelength : float
        Cut-off wavelength (m).

    Returns
    -------
    (long, short) : ndarray, ndarray
        ``long + short == h``; ``short`` is periodic over the map with zero mean.
    """
    h = np.asarray(h, dtype=float)
    p = periodic_component(h)
    qx = 2.0 * np.pi * np.fft.fftfreq(h.shape[0], dx)[:, None]
    qy = 2.0 * np.pi * np.fft.rfftfreq(h.shape[1], dy)[None, :]
    keep = np.hypot(qx, qy) < 2.0 * np.pi / float(wavelength)
    long_p = np.fft.irfft2(np.fft.rfft2(p) * keep, s=h.shape)
    long = (h - p) + long_p
    return long, h - long
