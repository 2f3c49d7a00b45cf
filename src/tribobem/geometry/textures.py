"""Surface textures (dimples, pillars, grooves) and waviness of a body.

Unlike a shape (:mod:`.shapes`, positive away from the interface), a texture or a waviness is
part of a body's *topography*, like its roughness (:mod:`.rough`): heights in m, positive out
of the body, toward the counter-surface.  A pillar therefore adds ``+depth`` and a dimple or a
groove ``-depth``; the scenario adds them to the body's roughness
(:func:`tribobem.scenario.build.build_problem`), so every feature closes or opens the gap
whichever body carries it.

Patterns are sampled at the cell centres of a :class:`~tribobem.grid.Grid` (``x, y`` relative
to the domain centre), with no anti-aliasing: a feature is a set of whole cells, and
:func:`check_resolution` refuses features narrower than :data:`MIN_CELLS` cells, where the
staircase would no longer represent the feature's size.  A lattice point sits at the domain
centre; on a periodic grid whose sides are whole multiples of the pitch (and ``angle = 0``)
the pattern is periodic with the cell.

All functions return float64 arrays of shape ``grid.shape`` indexed ``[ix, iy]``.
"""

from __future__ import annotations

import math

import numpy as np

from ..errors import InputError
from ..grid import Grid
from .shapes import _finite, _positive

__all__ = ["TEXTURE_KINDS", "MIN_CELLS", "dimples", "pillars", "grooves", "texture", "waviness",
           "check_resolution", "check_body_geometry"]

#: The texture kinds: circular pits, circular pillars, parallel grooves.
TEXTURE_KINDS = ("dimples", "pillars", "grooves")
#: Fewest cells across a feature (``size``) and across the space between features
#: (``pitch - size``): below it the sampled pattern misstates the feature's area by more than
#: about a third (a disc of 3 cells' diameter covers 9 or 5 cells against pi 9/4 = 7.1).
MIN_CELLS = 3.0


def _rotated(grid: Grid, angle: float, key: str = "texture"):
    """Coordinates (m) along and across the direction ``angle`` (degrees from the x axis)."""
    t = math.radians(_finite(angle, f"{key}.angle", "deg"))
    X, Y = grid.meshgrid()
    return X * math.cos(t) + Y * math.sin(t), -X * math.sin(t) + Y * math.cos(t)


def _folded(u, pitch: float):
    """Distance (m, signed) of ``u`` from the nearest lattice line ``k pitch``."""
    return u - pitch * np.round(u / pitch)


def _lattice_discs(grid: Grid, pitch: float, size: float, angle: float, key: str) -> np.ndarray:
    """Mask of the discs of diameter ``size`` on a square lattice of ``pitch`` at ``angle``."""
    u, v = _rotated(grid, angle, key)
    return np.hypot(_folded(u, pitch), _folded(v, pitch)) < 0.5 * size


def _sizes(pitch, size, depth, key: str) -> tuple[float, float, float]:
    p = _positive(pitch, f"{key}.pitch")
    s = _positive(size, f"{key}.size")
    d = _positive(depth, f"{key}.depth")
    if s >= p:
        raise InputError(f"{key}.size", f"must be smaller than the pitch ({p:.6g} m): features of {s:.6g} m "
                                        "would merge into one another")
    return p, s, d


def dimples(grid: Grid, pitch: float, size: float, depth: float, angle: float = 0.0,
            key: str = "texture") -> np.ndarray:
    """Circular pits of diameter ``size`` and depth ``depth`` on a square lattice of ``pitch``.

    Parameters
    ----------
    grid : Grid
        Grid of the result.
    pitch : float
        Period of the square lattice (m), > ``size``.
    size : float
        Diameter of a pit (m), > 0.
    depth : float
        Depth of a pit (m), > 0.
    angle : float
        Rotation of the lattice (degrees from the x axis).
    key : str
        Scenario key of the texture, for error messages.

    Returns
    -------
    ndarray, shape (nx, ny)
        Heights (m, positive out of the body): ``-depth`` in the pits, 0 elsewhere.
    """
    p, s, d = _sizes(pitch, size, depth, key)
    return np.where(_lattice_discs(grid, p, s, angle, key), -d, 0.0)


def pillars(grid: Grid, pitch: float, size: float, depth: float, angle: float = 0.0,
            key: str = "texture") -> np.ndarray:
    """Circular flat-topped pillars of diameter ``size`` and height ``depth`` on a square
    lattice of ``pitch``.

    Parameters
    ----------
    grid : Grid
        Grid of the result.
    pitch : float
        Period of the square lattice (m), > ``size``.
    size : float
        Diameter of a pillar (m), > 0.
    depth : float
        Height of a pillar (m), > 0.
    angle : float
        Rotation of the lattice (degrees from the x axis).
    key : str
        Scenario key of the texture, for error messages.

    Returns
    -------
    ndarray, shape (nx, ny)
        Heights (m, positive out of the body): ``+depth`` on the pillars, 0 elsewhere.
    """
    p, s, d = _sizes(pitch, size, depth, key)
    return np.where(_lattice_discs(grid, p, s, angle, key), d, 0.0)


def grooves(grid: Grid, pitch: float, size: float, depth: float, angle: float = 0.0,
            key: str = "texture") -> np.ndarray:
    """Parallel flat-bottomed grooves of width ``size`` and depth ``depth``, ``pitch`` apart.

    Parameters
    ----------
    grid : Grid
        Grid of the result.
    pitch : float
        Distance between groove centrelines (m), > ``size``.
    size : float
        Width of a groove (m), > 0.
    depth : float
        Depth of a groove (m), > 0.
    angle : float
        Direction of the grooves (degrees from the x axis): 0 runs them along x.
    key : str
        Scenario key of the texture, for error messages.

    Returns
    -------
    ndarray, shape (nx, ny)
        Heights (m, positive out of the body): ``-depth`` in the grooves, 0 elsewhere; a groove
        is centred on the line through the domain centre.
    """
    p, s, d = _sizes(pitch, size, depth, key)
    _, v = _rotated(grid, angle, key)
    return np.where(np.abs(_folded(v, p)) < 0.5 * s, -d, 0.0)


def check_resolution(kind: str, pitch: float, size: float, dx: float, key: str = "texture") -> None:
    """Refuse a texture whose features or gaps span fewer than :data:`MIN_CELLS` cells.

    Parameters
    ----------
    kind : str
        One of :data:`TEXTURE_KINDS` (the rule is the same for all).
    pitch, size : float
        Period and feature size (diameter or width) of the texture (m).
    dx : float
        The larger cell side of the grid (m).
    key : str
        Scenario key of the texture (``"body1.texture"``), named in the error.

    Raises
    ------
    InputError
        ``<key>.size`` if ``size < 3 dx``; ``<key>.pitch`` if ``pitch - size < 3 dx``.
    """
    what = {"dimples": "pit", "pillars": "pillar", "grooves": "groove"}.get(kind, "feature")
    need = MIN_CELLS * dx
    if size < need * (1 - 1e-9):
        raise InputError(f"{key}.size", f"a {what} of {size:.4g} m spans {size / dx:.2f} cells of {dx:.4g} m; the "
                                        f"grid resolves features of >= {MIN_CELLS:g} cells: give size >= {need:.4g} m "
                                        "or a finer grid")
    if pitch - size < need * (1 - 1e-9):
        raise InputError(f"{key}.pitch", f"the space between {what}s (pitch - size = {pitch - size:.4g} m) spans "
                                         f"{(pitch - size) / dx:.2f} cells of {dx:.4g} m; the grid resolves "
                                         f">= {MIN_CELLS:g} cells: give pitch >= size + {need:.4g} m or a finer grid")


def texture(grid: Grid, kind: str, pitch: float, size: float, depth: float, angle: float = 0.0,
            key: str = "texture") -> np.ndarray:
    """A texture of ``kind`` on ``grid``, after :func:`check_resolution`.

    Parameters
    ----------
    grid : Grid
        Grid of the result.
    kind : {"dimples", "pillars", "grooves"}
        The pattern (:func:`dimples`, :func:`pillars`, :func:`grooves`).
    pitch, size, depth : float
        Period, feature diameter or width, and depth or height (m), all > 0, ``size < pitch``.
    angle : float
        Rotation of the lattice or direction of the grooves (degrees).
    key : str
        Scenario key of the texture, named in errors.

    Returns
    -------
    ndarray, shape (nx, ny)
        Heights (m, positive out of the body).

    Raises
    ------
    InputError
        Naming ``<key>.kind``, ``.pitch``, ``.size`` or ``.depth``.
    """
    makers = {"dimples": dimples, "pillars": pillars, "grooves": grooves}
    if kind not in makers:
        raise InputError(f"{key}.kind", f"must be one of {', '.join(map(repr, TEXTURE_KINDS))}, got {kind!r}")
    p, s, _ = _sizes(pitch, size, depth, key)
    check_resolution(kind, p, s, max(grid.dx, grid.dy), key)
    return makers[kind](grid, pitch, size, depth, angle, key)


def waviness(grid: Grid, amplitude: float, wavelength: float, angle: float = 0.0,
             key: str = "waviness") -> np.ndarray:
    """Long-wavelength form (waviness of a wafer): ``A cos(2 pi (x cos t + y sin t) / lambda)``.

    Parameters
    ----------
    grid : Grid
        Grid of the result.
    amplitude : float
        Amplitude ``A`` (m), >= 0 (peak to valley ``2 A``).
    wavelength : float
        Wavelength ``lambda`` (m), > 0, at least :data:`MIN_CELLS` cells.
    angle : float
        Direction ``t`` of the wave vector (degrees from the x axis).
    key : str
        Scenario key of the waviness, named in errors.

    Returns
    -------
    ndarray, shape (nx, ny)
        Heights (m, positive out of the body), a crest at the domain centre.

    Raises
    ------
    InputError
        ``<key>.amplitude`` if negative, ``<key>.wavelength`` if not > 0 or under 3 cells.
    """
    A = _finite(amplitude, f"{key}.amplitude")
    if A < 0:
        raise InputError(f"{key}.amplitude", f"must be >= 0 m, got {amplitude!r}")
    lam = _positive(wavelength, f"{key}.wavelength")
    dx = max(grid.dx, grid.dy)
    if lam < MIN_CELLS * dx * (1 - 1e-9):
        raise InputError(f"{key}.wavelength", f"{lam:.4g} m spans {lam / dx:.2f} cells of {dx:.4g} m; give >= "
                                              f"{MIN_CELLS:g} cells ({MIN_CELLS * dx:.4g} m) or a finer grid")
    u, _ = _rotated(grid, angle, key)
    return A * np.cos(2.0 * np.pi * u / lam)


def texture_fits_window(pitch: float, window: float) -> bool:
    """Whether a texture of period ``pitch`` (m) tiles a periodic window of side ``window`` (m):
    the window holds a whole number (>= 1) of periods (to 1e-6).  A two-scale run solves such a
    texture in its micro windows and a longer one at macro scale."""
    k = window / pitch
    return k >= 1 - 1e-6 and abs(k - round(k)) <= 1e-6 * max(1.0, k)


def check_body_geometry(body, dx: float, dy: float, lengths, name: str, window=None) -> None:
    """Refuse a body's texture, waviness or burl that the grid cannot represent.

    Parameters
    ----------
    body : BodySpec
        A validated ``[body1]`` or ``[body2]`` section (its ``shape``, ``texture`` and
        ``waviness``; duck-typed so that the geometry does not import the scenario package).
    dx, dy : float
        Cell sides (m).
    lengths : (float, float)
        Sides ``lx, ly`` of the domain (m).
    name : str
        ``"body1"`` or ``"body2"``, for the keys named in errors.
    window : (float, int), optional
        A two-scale run's micro window: its side (m) and cells per side.  A texture that tiles
        it (:func:`texture_fits_window`) is checked against the window's cells instead.

    Raises
    ------
    InputError
        ``<name>.texture.size`` / ``.pitch`` (:func:`check_resolution`),
        ``<name>.waviness.wavelength`` (under 3 cells), ``<name>.shape.radius`` (a burl whose
        flat top is wider than the domain: its radius over half the smaller side).
    """
    cell = max(float(dx), float(dy))
    tex = getattr(body, "texture", None)
    if tex is not None:
        if window is not None and float(tex.pitch) < float(window[0]) and not texture_fits_window(
                float(tex.pitch), float(window[0])):
            k = float(window[0]) / float(tex.pitch)
            raise InputError("two_scale.window", f"{float(window[0]):.4g} m holds {k:.3f} periods of {name}.texture "
                             f"({float(tex.pitch):.4g} m): a texture shorter than the window belongs to the periodic "
                             "windows, which must hold a whole number of its periods (e.g. "
                             f"{round(k) * float(tex.pitch):.4g} m)")
        if window is not None and texture_fits_window(float(tex.pitch), float(window[0])):
            check_resolution(tex.kind, float(tex.pitch), float(tex.size), float(window[0]) / int(window[1]),
                             f"{name}.texture")
        else:
            check_resolution(tex.kind, float(tex.pitch), float(tex.size), cell, f"{name}.texture")
    wav = getattr(body, "waviness", None)
    if wav is not None and float(wav.wavelength) < MIN_CELLS * cell * (1 - 1e-9):
        raise InputError(f"{name}.waviness.wavelength",
                         f"{float(wav.wavelength):.4g} m spans {float(wav.wavelength) / cell:.2f} cells of {cell:.4g} m; "
                         f"give >= {MIN_CELLS:g} cells ({MIN_CELLS * cell:.4g} m) or a finer grid")
    shape = getattr(body, "shape", None)
    if shape is not None and getattr(shape, "kind", None) == "burl":
        half = 0.5 * min(float(lengths[0]), float(lengths[1]))
        if float(shape.radius) > half:
            raise InputError(f"{name}.shape.radius",
                             f"the burl's flat top (radius {float(shape.radius):.4g} m) is wider than the domain "
                             f"(half side {half:.4g} m): the contact would be cut by the domain edge; give a larger "
                             "grid.size or a smaller radius")
