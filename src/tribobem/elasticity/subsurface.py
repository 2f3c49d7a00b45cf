"""Stresses below the surface of a homogeneous half-space from its surface tractions.

Given the normal pressure p (Pa, compressive positive) and the tangential traction q (Pa, the
traction acting on the body's surface) on the grid, the stress tensor on planes at depths z
below the surface follows from three harmonic potentials per wave vector (alpha, beta),
k = |(alpha, beta)|, each decaying as exp(-k z) into the body (Barber, *Elasticity*, the
Papkovich-Neuber solutions A and B and the torsional solution E):

* A: 2 mu u = grad phi;
* B: 2 mu u = grad(z omega) - 4 (1 - nu) omega e_z;
* E: 2 mu u = curl(chi e_z).

Their amplitudes Phi, W, X follow from the surface conditions sigma_zz = -p, sigma_xz = -q_x,
sigma_yz = -q_y at z = 0 (z into the body, the traction t = -sigma . e_z); with
S = -i (alpha q_x + beta q_y) / k^2:

    W = -p / k - S,   Phi = (S - (1 - 2 nu) W) / k,   X = -2 i (beta q_x - alpha q_y) / k^3,

and then, with e = exp(-k z),

    sigma_xx = e [-alpha^2 Phi + (2 nu k - alpha^2 z) W - alpha beta X]
    sigma_yy = e [-beta^2 Phi + (2 nu k - beta^2 z) W + alpha beta X]
    sigma_zz = e [k^2 Phi + (2 (1 - nu) k + k^2 z) W]
    sigma_xy = e [-alpha beta (Phi + z W) + (alpha^2 - beta^2) X / 2]
    sigma_xz = e [-i alpha (k Phi + (k z + 1 - 2 nu) W) - i beta k X / 2]
    sigma_yz = e [-i beta (k Phi + (k z + 1 - 2 nu) W) + i alpha k X / 2]

(normal load alone: sigma_zz = -p (1 + k z) exp(-k z), the classical result).  The uniform
mode (k = 0) is the limit of a large uniformly loaded area (the plane mean of the periodic
images' Boussinesq and Cerruti fields): sigma_zz = -mean p, sigma_xz, sigma_yz = -mean q,
sigma_xx = sigma_yy = -(1 + 2 nu) mean p / 2 (Johnson, 1985, section 3.5).

The traction is a cell average: each wave vector carries the cell's shape factor
sinc(alpha dx / 2) sinc(beta dy / 2).  On a periodic grid the result is the periodic field.  On
a free-boundary grid the tractions are zero-padded to a period ``pad`` times the domain per side
before the transform: the padded field differs from the isolated one by the periodic images of
the load, an error of order (contact size / period)^2 of the contact stresses (0.3 % on the
Hertz sphere of the tests at pad = 4).  Planes closer to the surface than about two cells
resolve the cell-average traction only to the grid.

The stresses are the body's own: it is loaded by the traction (p, q) in the frame of
:func:`subsurface_stress`.  The upper body of a pair (body 2) is loaded by the same pressure
and -q in a frame mirrored about the surface: :func:`body_stresses` does that bookkeeping.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..errors import InputError

__all__ = ["SubsurfaceStress", "subsurface_stress", "body_stresses", "COMPONENTS", "DEFAULT_PAD"]

#: The stress components, in the order of :attr:`SubsurfaceStress.components`.
COMPONENTS = ("xx", "yy", "zz", "xy", "xz", "yz")
#: Free boundary: the period of the padded transform as a multiple of the domain (per side).
DEFAULT_PAD = 4


@dataclass
class SubsurfaceStress:
    """The stress tensor on planes below the surface.

    Attributes
    ----------
    depths : ndarray
        Depths z below the surface (m), shape (nz,).
    components : ndarray
        sigma_xx, yy, zz, xy, xz, yz (Pa; tension positive) on each plane, shape (6, nz, nx, ny).
    nu : float
        Poisson's ratio of the body.
    """

    depths: np.ndarray
    components: np.ndarray
    nu: float

    def component(self, name: str) -> np.ndarray:
        """One component (``"xx"``, ..., ``"yz"``), shape (nz, nx, ny) (Pa)."""
        return self.components[COMPONENTS.index(name)]

    def principal(self) -> np.ndarray:
        """Principal stresses sigma_1 >= sigma_2 >= sigma_3 (Pa), shape (3, nz, nx, ny)."""
        xx, yy, zz, xy, xz, yz = self.components
        t = np.stack([np.stack([xx, xy, xz], -1), np.stack([xy, yy, yz], -1), np.stack([xz, yz, zz], -1)], -2)
        ev = np.linalg.eigvalsh(t)  # ascending
        return np.moveaxis(ev[..., ::-1], -1, 0)

    def von_mises(self) -> np.ndarray:
        """Von Mises equivalent stress (Pa), shape (nz, nx, ny)."""
        xx, yy, zz, xy, xz, yz = self.components
        return np.sqrt(0.5 * ((xx - yy) ** 2 + (yy - zz) ** 2 + (zz - xx) ** 2) + 3.0 * (xy ** 2 + xz ** 2 + yz ** 2))

    def max_shear(self) -> np.ndarray:
        """Maximum shear stress (sigma_1 - sigma_3) / 2 (Pa), shape (nz, nx, ny)."""
        s = self.principal()
        return 0.5 * (s[0] - s[2])


def _depths(depths) -> np.ndarray:
    z = np.atleast_1d(np.asarray(depths, dtype=float))
    if z.ndim != 1 or z.size == 0 or not np.all(np.isfinite(z)) or np.any(z < 0):
        raise InputError("depths", f"must be one or more finite depths >= 0 m, got {depths!r}")
    return z


def subsurface_stress(grid, pressure, shear=None, *, depths, nu: float, pad: int | None = None) -> SubsurfaceStress:
    """The stress tensor in a homogeneous half-space below the loaded surface (module docstring).

    Parameters
    ----------
    grid : Grid
        The surface grid (periodic or free boundary).
    pressure : array_like
        Normal pressure p (Pa, compressive positive), ``grid.shape``.
    shear : array_like, optional
        Tangential traction (q_x, q_y) on the body's surface (Pa), shape (2, nx, ny); None: none.
    depths : float or sequence of float
        Depths below the surface (m), >= 0.
    nu : float
        Poisson's ratio of the body, in (-1, 0.5].
    pad : int, optional
        Free boundary: the period of the transform in domains per side (default
        :data:`DEFAULT_PAD`); ignored on a periodic grid.

    Returns
    -------
    SubsurfaceStress
    """
    if not (-1.0 < nu <= 0.5):
        raise InputError("nu", f"Poisson's ratio must lie in (-1, 0.5], got {nu!r}")
    z = _depths(depths)
    p = np.asarray(pressure, dtype=float)
    if p.shape != grid.shape:
        raise InputError("pressure", f"shape {p.shape} does not match the grid {grid.shape}")
    q = None
    if shear is not None:
        q = np.asarray(shear, dtype=float)
        if q.shape != (2,) + tuple(grid.shape):
            raise InputError("shear", f"shape {q.shape} is not (2,) + the grid's {grid.shape}")
    nx, ny = grid.shape
    if grid.periodic:
        mx, my = nx, ny
    else:
        m = DEFAULT_PAD if pad is None else int(pad)
        if m < 2:
            raise InputError("pad", f"must be >= 2 (a period of at least twice the domain), got {pad!r}")
        mx, my = m * nx, m * ny
    dx, dy = grid.dx, grid.dy
    alpha = 2.0 * np.pi * np.fft.fftfreq(mx, dx)[:, None]
    beta = 2.0 * np.pi * np.fft.rfftfreq(my, dy)[None, :]
    k = np.sqrt(alpha ** 2 + beta ** 2)
    # the cell-average traction's shape factor (np.sinc(x) = sin(pi x) / (pi x))
    shape = np.sinc(alpha * dx / (2 * np.pi)) * np.sinc(beta * dy / (2 * np.pi))
    p_hat = np.fft.rfft2(p, s=(mx, my)) * shape
    zero = k == 0.0
    ks = np.where(zero, 1.0, k)
    if q is not None:
        qx_hat = np.fft.rfft2(q[0], s=(mx, my)) * shape
        qy_hat = np.fft.rfft2(q[1], s=(mx, my)) * shape
        S = -1j * (alpha * qx_hat + beta * qy_hat) / ks ** 2
        X = -2j * (beta * qx_hat - alpha * qy_hat) / ks ** 3
    else:
        qx_hat = qy_hat = None
        S = np.zeros_like(p_hat)
        X = np.zeros_like(p_hat)
    W = -p_hat / ks - S
    Phi = (S - (1.0 - 2.0 * nu) * W) / ks
    for a in (W, Phi, X):
        a[zero] = 0.0
    # the uniform mode (the padded period's means)
    n_cells = mx * my
    p_mean = float(p_hat[0, 0].real) / n_cells
    qx_mean = float(qx_hat[0, 0].real) / n_cells if qx_hat is not None else 0.0
    qy_mean = float(qy_hat[0, 0].real) / n_cells if qy_hat is not None else 0.0
    # the large-loaded-area limit (the plane mean of the periodic images' Boussinesq fields;
    # Johnson 3.5: the centre of a uniformly loaded disc carries sigma_r = -(1 + 2 nu) p / 2)
    lateral = -0.5 * (1.0 + 2.0 * nu) * p_mean

    out = np.empty((6, z.size, nx, ny))
    a2, b2, ab = alpha ** 2, beta ** 2, alpha * beta
    for i, zi in enumerate(z):
        e = np.exp(-k * zi)
        comps = (
            e * (-a2 * Phi + (2 * nu * k - a2 * zi) * W - ab * X),
            e * (-b2 * Phi + (2 * nu * k - b2 * zi) * W + ab * X),
            e * (k ** 2 * Phi + (2 * (1 - nu) * k + k ** 2 * zi) * W),
            e * (-ab * (Phi + zi * W) + 0.5 * (a2 - b2) * X),
            e * (-1j * alpha * (k * Phi + (k * zi + 1 - 2 * nu) * W) - 0.5j * beta * k * X),
            e * (-1j * beta * (k * Phi + (k * zi + 1 - 2 * nu) * W) + 0.5j * alpha * k * X),
        )
        uniform = (lateral, lateral, -p_mean, 0.0, -qx_mean, -qy_mean)
        for c, (field, u0) in enumerate(zip(comps, uniform)):
            field[zero] = u0 * n_cells
            out[c, i] = np.fft.irfft2(field, s=(mx, my))[:nx, :ny]
    return SubsurfaceStress(z, out, float(nu))


def body_stresses(grid, pressure, shear, *, depths, nu: float, body: int, pad: int | None = None) -> SubsurfaceStress:
    """The stresses in body 1 (below the interface) or body 2 (above it) of a contact pair.

    Body 1 carries the pressure and the shear q (the traction on body 1, the convention of
    :class:`~tribobem.results.TangentialResult`); body 2 the same pressure and -q.  Body 2's
    field is computed in its own right-handed frame with depth into it (the interface mirrored,
    y reversed) and returned on the grid's (x, y) nodes; its shear components are in that frame,
    the invariants (von Mises, principal and maximum shear stresses) are frame-free.

    Parameters
    ----------
    grid, pressure, shear, depths, nu, pad
        As for :func:`subsurface_stress` (``shear`` the traction on body 1, or None).
    body : {1, 2}
    """
    if body == 1:
        return subsurface_stress(grid, pressure, shear, depths=depths, nu=nu, pad=pad)
    if body != 2:
        raise InputError("body", f"must be 1 or 2, got {body!r}")
    p = np.asarray(pressure, dtype=float)[:, ::-1]
    q2 = None
    if shear is not None:
        q = np.asarray(shear, dtype=float)
        q2 = np.stack([-q[0][:, ::-1], q[1][:, ::-1]])  # -q, then y -> -y flips the y component
    s = subsurface_stress(grid, p, q2, depths=depths, nu=nu, pad=pad)
    s.components = np.ascontiguousarray(s.components[..., ::-1])
    return s


def default_depths(length_scale: float, n: int = 8) -> np.ndarray:
    """Depths (m) for a contact of length scale ``length_scale`` (m): 0.1 to 2 times it."""
    if not (math.isfinite(length_scale) and length_scale > 0):
        raise InputError("length_scale", f"must be a length > 0 m, got {length_scale!r}")
    return np.linspace(0.1, 2.0, n) * length_scale
