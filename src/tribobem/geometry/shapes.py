"""Smooth shapes of the upper body (body 2).

Sign convention (used by every generator in :mod:`tribobem.geometry`): a shape is the height
(m) of body 2's lower surface above the plane ``z = 0``, measured upward, on the cell centres
of a :class:`~tribobem.grid.Grid` (``x_i = (i + 1/2) dx - lx/2``, so the domain centre is
``(0, 0)``; for even ``n`` it lies between the four middle cells). The initial gap is
``h = h2 - h1`` (:func:`tribobem.geometry.combine_gap`), with ``h1`` the topography of the
lower body (positive up).

All functions return float64 arrays of shape ``grid.shape`` indexed ``[ix, iy]``.
"""

from __future__ import annotations

import math

import numpy as np

from ..errors import InputError
from ..grid import Grid

__all__ = ["flat", "sphere", "cylinder", "wavy_sphere", "bisinusoidal", "burl"]


def _positive(value, field: str, unit: str = "m") -> float:
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise InputError(field, f"must be a number > 0 {unit}, got {value!r}") from None
    if not (math.isfinite(v) and v > 0):
        raise InputError(field, f"must be a finite value > 0 {unit}, got {value!r}")
    return v


def _finite(value, field: str, unit: str = "m") -> float:
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise InputError(field, f"must be a finite number ({unit}), got {value!r}") from None
    if not math.isfinite(v):
        raise InputError(field, f"must be a finite number ({unit}), got {value!r}")
    return v


def _centre(center, field: str = "shape.center") -> tuple[float, float]:
    try:
        cx, cy = center
    except (TypeError, ValueError):
        raise InputError(field, f"must be a pair (x0, y0) in m, got {center!r}") from None
    return _finite(cx, field), _finite(cy, field)


def _radius_from(grid: Grid, center) -> np.ndarray:
    cx, cy = _centre(center)
    X, Y = grid.meshgrid()
    return np.hypot(X - cx, Y - cy)


def flat(grid: Grid) -> np.ndarray:
    """A flat surface.

    Parameters
    ----------
    grid : Grid
        Grid of the result.

    Returns
    -------
    ndarray, shape (nx, ny)
        Zeros (m).
    """
    return np.zeros(grid.shape)


def sphere(grid: Grid, radius: float, exact: bool = False, center=(0.0, 0.0)) -> np.ndarray:
    """A sphere of radius ``R`` touching ``z = 0`` at ``center``.

    Parameters
    ----------
    grid : Grid
        Grid of the result.
    radius : float
        Sphere radius ``R`` (m), > 0.
    exact : bool
        False: the paraboloid ``r^2 / (2 R)`` (Hertz). True: the exact cap
        ``R - sqrt(R^2 - r^2)``; every cell centre must then lie within ``r <= R``.
    center : (float, float)
        Position ``(x0, y0)`` of the lowest point (m), relative to the domain centre.

    Returns
    -------
    ndarray, shape (nx, ny)
        Heights (m), minimum 0 at ``center``.

    Raises
    ------
    InputError
        ``shape.radius`` if ``R <= 0`` or, with ``exact=True``, if the grid extends beyond ``R``.
    """
    R = _positive(radius, "shape.radius")
    r = _radius_from(grid, center)
    if not exact:
        return r**2 / (2 * R)
    rmax = float(r.max())
    if rmax > R:
        raise InputError(
            "shape.radius",
            f"the exact sphere needs R >= the largest distance from its centre on the grid "
            f"({rmax:.6g} m), got R = {R:.6g} m; use a smaller grid or exact=False",
        )
    # R - sqrt(R^2 - r^2) written without cancellation for r << R
    return r**2 / (R + np.sqrt(np.maximum(R * R - r * r, 0.0)))


def cylinder(grid: Grid, radius: float, axis: str = "y", center: float = 0.0) -> np.ndarray:
    """A cylinder (paraboloid in one direction) touching ``z = 0`` along a line.

    Parameters
    ----------
    grid : Grid
        Grid of the result.
    radius : float
        Cylinder radius ``R`` (m), > 0.
    axis : {"y", "x"}
        Direction of the cylinder axis. ``"y"``: ``h = (x - x0)^2 / (2 R)``;
        ``"x"``: ``h = (y - y0)^2 / (2 R)``.
    center : float
        Offset of the contact line from the domain centre (m), across the axis.

    Returns
    -------
    ndarray, shape (nx, ny)
        Heights (m).
    """
    R = _positive(radius, "shape.radius")
    c = _finite(center, "shape.center")
    X, Y = grid.meshgrid()
    if axis == "y":
        return (X - c) ** 2 / (2 * R)
    if axis == "x":
        return (Y - c) ** 2 / (2 * R)
    raise InputError("shape.axis", f"must be 'x' or 'y', got {axis!r}")


def wavy_sphere(
    grid: Grid, radius: float, amplitude: float, wavelength: float, center=(0.0, 0.0)
) -> np.ndarray:
    """Axisymmetric wavy sphere ``h = r^2/(2R) + A (1 - cos(2 pi r / xi))`` (thesis Paper A).

    Parameters
    ----------
    grid : Grid
        Grid of the result.
    radius : float
        Sphere radius ``R`` (m), > 0.
    amplitude : float
        Wave amplitude ``A`` (m), >= 0.
    wavelength : float
        Radial wavelength ``xi`` (m), > 0.
    center : (float, float)
        Position of the axis (m), relative to the domain centre.

    Returns
    -------
    ndarray, shape (nx, ny)
        Heights (m), 0 at the centre.
    """
    R = _positive(radius, "shape.radius")
    A = _finite(amplitude, "shape.amplitude")
    if A < 0:
        raise InputError("shape.amplitude", f"must be >= 0 m, got {amplitude!r}")
    xi = _positive(wavelength, "shape.wavelength")
    r = _radius_from(grid, center)
    return r**2 / (2 * R) + A * (1.0 - np.cos(2 * np.pi * r / xi))


def bisinusoidal(grid: Grid, amplitude: float, wavelength_x: float, wavelength_y: float) -> np.ndarray:
    """Bisinusoidal surface ``h = S cos(2 pi x / lx) cos(2 pi y / ly)`` (thesis Paper A Eq. 31).

    Parameters
    ----------
    grid : Grid
        Grid of the result; ``x, y`` are its cell-centre coordinates, so a crest
        (``h = S``) sits at the domain centre ``(0, 0)``. On a periodic grid whose sides equal
        the wavelengths and an even number of cells, the crest falls between the four middle
        cells (no cell centre reaches exactly ``S``).
    amplitude : float
        ``S`` (m), >= 0.
    wavelength_x, wavelength_y : float
        Wavelengths ``lx, ly`` (m), > 0.

    Returns
    -------
    ndarray, shape (nx, ny)
        Heights (m) in ``[-S, S]``.

    Notes
    -----
    This is the raw Eq. 31 surface (zero mean over a period). For contact with body 2
    above it, use it as the lower body's topography (``h1``) or build the upper body's gap
    as ``h.max() - h`` so that the lowest point of body 2 touches ``z = 0``.
    """
    S = _finite(amplitude, "shape.amplitude")
    if S < 0:
        raise InputError("shape.amplitude", f"must be >= 0 m, got {amplitude!r}")
    wx = _positive(wavelength_x, "shape.wavelength_x")
    wy = _positive(wavelength_y, "shape.wavelength_y")
    return S * np.cos(2 * np.pi * grid.x / wx)[:, None] * np.cos(2 * np.pi * grid.y / wy)[None, :]


def burl(grid: Grid, radius: float, edge_radius: float, crown: float | None = None,
         center=(0.0, 0.0)) -> np.ndarray:
    """A burl: a flat (or crowned) circular top whose edge rounds off (the rounded flat punch).

    ``h(r) = max(r - b, 0)^2 / (2 R) + r^2 / (2 R_c)``: a flat top of radius ``b`` whose edge
    falls away as a paraboloid of radius ``R`` beyond ``r = b`` (slope and height continuous at
    ``b``), and an optional spherical crown of radius ``R_c`` over the whole burl.

    Parameters
    ----------
    grid : Grid
        Grid of the result.
    radius : float
        Radius ``b`` of the flat top (m), > 0.
    edge_radius : float
        Radius ``R`` of the rounded edge (m), > 0; ``R << b`` approaches the sharp flat punch
        (its reference, :func:`tribobem.analytic.punch.flat_punch`, needs the rounding to rise
        above the approach within a cell).
    crown : float, optional
        Radius ``R_c`` of the spherical crown (m), > 0; None: a flat top.
    center : (float, float)
        Position of the burl's axis (m), relative to the domain centre.

    Returns
    -------
    ndarray, shape (nx, ny)
        Heights (m) of the shape, positive away from the interface (the convention of
        :func:`sphere`), 0 on the flat top (at the axis with a crown).

    Raises
    ------
    InputError
        ``shape.radius``, ``shape.edge_radius`` or ``shape.crown`` if not finite and > 0.
    """
    b = _positive(radius, "shape.radius")
    R = _positive(edge_radius, "shape.edge_radius")
    Rc = None if crown is None else _positive(crown, "shape.crown")
    r = _radius_from(grid, center)
    h = np.maximum(r - b, 0.0) ** 2 / (2.0 * R)
    if Rc is not None:
        h = h + r**2 / (2.0 * Rc)
    return h
