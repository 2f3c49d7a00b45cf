"""Closed-form influence coefficients for piecewise-constant surface tractions.

A uniform traction on a rectangle of half-sides (a, b) centred at the origin, acting on an
elastic half-space (G, nu), displaces the surface point (x, y) by ``C(x, y)`` times the
traction.  Love (1929); Liu, Wang & Liu (2000); Chen & Wang (2008).  With the corner sum

    R[F](x, y) = F(x+a, y+b) - F(x+a, y-b) - F(x-a, y+b) + F(x-a, y-b)

the coefficients are R applied to antiderivatives F with d^2F/dXdY = point kernel.
``X ln(Y + rho)`` is written ``X asinh(Y/|X|)``: the dropped ``X ln|X|`` term cancels in
the corner sum, and the asinh form has no catastrophic cancellation far from the load.

Units: coefficients are in m/Pa (displacement per unit traction).  Components are named by
(displacement, traction): ``"zz"`` is u_z from p, ``"xz"`` is u_x from p, ``"zx"`` u_z from
q_x, and so on.
"""

from __future__ import annotations

import numpy as np

from ..materials import ContactPair, Material

COMPONENTS = ("xx", "xy", "xz", "yx", "yy", "yz", "zx", "zy", "zz")


def _xasinh(X, Y):
    """X * asinh(Y / |X|), with the X = 0 limit (= 0)."""
    with np.errstate(divide="ignore", invalid="ignore"):
        out = X * np.arcsinh(Y / np.abs(X))
    return np.where(X == 0.0, 0.0, out)


def _H(X, Y):
    """(Y/2) ln(X^2 + Y^2) + X arctan(Y/X), whose mixed derivative is X / rho^2."""
    r2 = X * X + Y * Y
    with np.errstate(divide="ignore", invalid="ignore"):
        t1 = np.where(Y == 0.0, 0.0, 0.5 * Y * np.log(r2))
        t2 = np.where(X == 0.0, 0.0, X * np.arctan(Y / X))
    return t1 + t2


def _corner_sum(F, x, y, a, b):
    return F(x + a, y + b) - F(x + a, y - b) - F(x - a, y + b) + F(x - a, y - b)


def _primitive(component: str, nu: float):
    """Antiderivative F for one body of unit shear modulus (factor 1/G applied later)."""
    c = 1.0 / (2.0 * np.pi)
    if component == "zz":
        return lambda X, Y: c * (1.0 - nu) * (_xasinh(X, Y) + _xasinh(Y, X))
    if component == "xx":
        return lambda X, Y: c * ((1.0 - nu) * _xasinh(X, Y) + _xasinh(Y, X))
    if component == "yy":
        return lambda X, Y: c * (_xasinh(X, Y) + (1.0 - nu) * _xasinh(Y, X))
    if component in ("xy", "yx"):
        return lambda X, Y: -c * nu * np.hypot(X, Y)
    k = (1.0 - 2.0 * nu) / (4.0 * np.pi)
    if component == "zx":  # u_z from q_x: +(1-2nu) X / (4 pi G rho^2)
        return lambda X, Y: k * _H(X, Y)
    if component == "xz":  # reciprocity: K_xz = -K_zx
        return lambda X, Y: -k * _H(X, Y)
    if component == "zy":
        return lambda X, Y: k * _H(Y, X)
    if component == "yz":
        return lambda X, Y: -k * _H(Y, X)
    raise ValueError(f"unknown component {component!r}; expected one of {COMPONENTS}")


def single_body_coefficients(component: str, material: Material, x, y, dx: float, dy: float) -> np.ndarray:
    """Influence coefficients of one half-space for a ``dx x dy`` cell centred at 0.

    Parameters
    ----------
    component : str
        Two letters, displacement then traction direction (e.g. ``"zz"``).
    material : Material
        The half-space; a rigid body gives zeros.
    x, y : array_like
        Offsets (m) of the observation points from the loaded cell's centre.
    dx, dy : float
        Cell size (m).

    Returns
    -------
    ndarray
        Displacement (m) per unit traction (Pa) at the observation points.
    """
    x, y = np.broadcast_arrays(np.asarray(x, float), np.asarray(y, float))
    if material.is_rigid:
        return np.zeros(x.shape)
    F = _primitive(component, material.nu)
    return _corner_sum(F, x, y, 0.5 * dx, 0.5 * dy) / material.shear_modulus


def composite_coefficients(component: str, pair: ContactPair, x, y, dx: float, dy: float) -> np.ndarray:
    """Influence coefficients of the interface of two bodies.

    Normal and in-plane parts add (both bodies displace into themselves); the normal-
    tangential coupling (``"xz", "zx", "yz", "zy"``) subtracts, since body 2 carries the
    opposite traction.  ``"zz"`` integrates 1/(pi E* rho).

    Parameters
    ----------
    component : str
        Block key ``out + in`` (e.g. ``"zz"``, ``"xz"``: u_x from q_z).
    pair : ContactPair
        The two bodies; a rigid body contributes nothing.
    x, y : array_like
        Offsets (m) of the observation points from the loaded cell's centre.
    dx, dy : float
        Cell size (m).

    Returns
    -------
    ndarray
        Displacement (m) of the interface per unit traction (Pa) on the cell.
    """
    c1 = single_body_coefficients(component, pair.body1, x, y, dx, dy)
    c2 = single_body_coefficients(component, pair.body2, x, y, dx, dy)
    if component in ("xz", "zx", "yz", "zy"):
        return c1 - c2
    return c1 + c2


def lattice_coefficients(component: str, pair: ContactPair, xc, yc) -> np.ndarray:
    """Influence coefficients of the interface on a regular grid, from its corner lattice.

    The corner sum of a cell centred at offset (x, y) takes the antiderivative at the four
    corners (x +- dx/2, y +- dy/2).  On a regular grid neighbouring cells share corners, so the
    antiderivative is evaluated once per corner of the lattice and the coefficients are its
    mixed second difference: the same sum as :func:`composite_coefficients` with a quarter of
    the transcendental evaluations (the cost of building a free-boundary operator).

    Parameters
    ----------
    component : str
        Block key ``out + in`` (e.g. ``"zz"``).
    pair : ContactPair
        The two bodies; a rigid body contributes nothing.
    xc, yc : array_like, 1-D
        Corner coordinates (m), ascending and evenly spaced: cell ``(i, j)`` spans
        ``[xc[i], xc[i+1]] x [yc[j], yc[j+1]]`` relative to the loaded cell's centre.

    Returns
    -------
    ndarray, shape (len(xc) - 1, len(yc) - 1)
        Displacement (m) of the interface per unit traction (Pa) on the loaded cell, at the
        offsets of the cells' centres.
    """
    xc = np.asarray(xc, float)[:, None]
    yc = np.asarray(yc, float)[None, :]
    out = np.zeros((xc.shape[0] - 1, yc.shape[1] - 1))
    sign = -1.0 if component in ("xz", "zx", "yz", "zy") else 1.0
    for body, s in ((pair.body1, 1.0), (pair.body2, sign)):
        if body.is_rigid:
            continue
        Fc = _primitive(component, body.nu)(xc, yc)
        # mixed second difference F(+,+) - F(+,-) - F(-,+) + F(-,-), in the corner sum's order
        d = Fc[1:, 1:] - Fc[1:, :-1]
        d -= Fc[:-1, 1:]
        d += Fc[:-1, :-1]
        out += (s / body.shear_modulus) * d
    return out


def point_kernel(component: str, material: Material, x, y) -> np.ndarray:
    """Point-load kernels of one half-space, used to verify the coefficients.

    Parameters
    ----------
    component : str
        Block key ``out + in``: ``"zz"``, ``"xx"``, ``"yy"``, ``"xy"``/``"yx"``, or a coupling
        block ``"zx"``, ``"xz"``, ``"zy"``, ``"yz"``.
    material : Material
        The half-space (shear modulus G in Pa, Poisson ratio nu).
    x, y : array_like
        Offsets (m) of the observation points from the point load (not both 0: singular there).

    Returns
    -------
    ndarray
        Displacement (m) per unit point force (N), i.e. in m/N.
    """
    G, nu = material.shear_modulus, material.nu
    x, y = np.broadcast_arrays(np.asarray(x, float), np.asarray(y, float))
    rho = np.hypot(x, y)
    two_pi_G = 2.0 * np.pi * G
    if component == "zz":
        return (1 - nu) / (two_pi_G * rho)
    if component == "xx":
        return ((1 - nu) / rho + nu * x**2 / rho**3) / two_pi_G
    if component == "yy":
        return ((1 - nu) / rho + nu * y**2 / rho**3) / two_pi_G
    if component in ("xy", "yx"):
        return nu * x * y / (two_pi_G * rho**3)
    k = (1 - 2 * nu) / (4 * np.pi * G * rho**2)
    return {"zx": k * x, "xz": -k * x, "zy": k * y, "yz": -k * y}[component]
