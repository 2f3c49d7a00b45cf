"""A body coated by an elastic layer perfectly bonded to it: its surface compliances per wavenumber.

Per wave vector of modulus q (rotated onto x), the layer (shear modulus G_l, nu_l, thickness t)
on the substrate (G_s, nu_s) is two problems: the in-plane (plane-strain) one, which carries
the normal load, the shear along q and their coupling, and the antiplane one, which carries the
shear across q.  Each is solved with the harmonic potentials of the half-space solution
(tribobem.elasticity.subsurface: Papkovich-Neuber A and B in plane strain, the torsional E
antiplane), with growing and decaying exponentials in the layer and decaying ones in the
substrate: six amplitudes in plane strain, three antiplane, fixed by the surface tractions and
the continuity of displacements and tractions at z = t.  The growing terms are scaled by
exp(-q t) so that thick layers stay well conditioned.

The results are the dimensionless factors f(s), s = q t, of the surface compliances
C(q) = f(q t) / (G_l q):

* ``zz``: u_z per unit pressure (the half-space's 1 - nu);
* ``xz``: u_x per unit pressure, imaginary (the half-space's i (1 - 2 nu) / 2);
* ``zx``: u_z per unit shear along q (the half-space's -i (1 - 2 nu) / 2);
* ``L``: u_x per unit shear along q (the half-space's 1 - nu);
* ``T``: u_y per unit shear across q (the half-space's 1).

As s -> infinity they tend to the layer's half-space values, as s -> 0 to the substrate's
(times G_l / G_s).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache
from typing import ClassVar

import numpy as np

from ...errors import InputError
from .base import BodyModel

__all__ = ["CoatedHalfSpace", "layer_factors"]


def _halfspace_factors(nu: float) -> dict:
    """A homogeneous half-space's factors (zz, L, T, xz / i; module docstring): its compliances
    times G q, the limits of a layer of Poisson's ratio ``nu`` as q t -> infinity."""
    return {"zz": 1.0 - nu, "L": 1.0 - nu, "T": 1.0, "xz": 0.5 * (1.0 - 2.0 * nu)}


def _plane_rows(z, G, nu, grow, shift):
    """Rows (u_x, u_z, s_zz, s_xz) of the plane-strain potentials at depth z (q = 1).

    ``grow``: the growing pair exp(z - shift) (layer) is included besides the decaying
    exp(-(z - shift0)); returns an array (4, n, k) with k = 4 (layer) or 2 (substrate) columns
    [A_dec, A_grow, B_dec, B_grow] / [A_dec, B_dec].
    """
    z = np.asarray(z, dtype=float)
    e = np.exp(-(z - shift[0]))
    cols = []
    # A decaying: phi = e
    cols.append((1j * e / (2 * G), -e / (2 * G), e, -1j * e))
    if grow:
        f = np.exp(z - shift[1])
        cols.append((1j * f / (2 * G), f / (2 * G), f, 1j * f))
    # B decaying: omega = e
    cols.append((1j * z * e / (2 * G), (-z - (3 - 4 * nu)) * e / (2 * G), (z + 2 * (1 - nu)) * e,
                 1j * (-z - (1 - 2 * nu)) * e))
    if grow:
        cols.append((1j * z * f / (2 * G), (z - (3 - 4 * nu)) * f / (2 * G), (z - 2 * (1 - nu)) * f,
                     1j * (z - (1 - 2 * nu)) * f))
    return np.stack([np.stack([np.broadcast_to(c[r], z.shape) for c in cols], -1) for r in range(4)])


def _anti_rows(z, G, grow, shift):
    """Rows (u_y, s_yz) of the antiplane potential chi at depth z (q = 1)."""
    z = np.asarray(z, dtype=float)
    e = np.exp(-(z - shift[0]))
    cols = [(-1j * e / (2 * G), 0.5j * e)]           # chi = e: chi_z = -e, s_yz = -(i/2) chi_z
    if grow:
        f = np.exp(z - shift[1])
        cols.append((-1j * f / (2 * G), -0.5j * f))
    return np.stack([np.stack([np.broadcast_to(c[r], z.shape) for c in cols], -1) for r in range(2)])


def layer_factors(s, nu_layer: float, nu_substrate: float, shear_ratio: float) -> dict:
    """The dimensionless surface compliances of a coated half-space (module docstring).

    Parameters
    ----------
    s : array_like
        q t, the wavenumber times the layer's thickness (> 0).
    nu_layer, nu_substrate : float
        Poisson's ratios.
    shear_ratio : float
        G_substrate / G_layer (> 0; ``inf`` for a rigid substrate).

    Returns
    -------
    dict
        ``zz``, ``xz``, ``zx``, ``L``, ``T`` -> arrays of the shape of ``s`` (complex for the
        coupling factors), C(q) = f(q t) / (G_layer q).
    """
    s = np.atleast_1d(np.asarray(s, dtype=float))
    n = s.size
    Gl = 1.0
    rigid = not np.isfinite(shear_ratio)
    Gs = shear_ratio if not rigid else 1.0
    zero = np.zeros(n)
    # plane strain: unknowns [A1 A2 B1 B2 | A3 B3]; decaying layer terms scaled at z = 0,
    # growing ones at z = t, substrate ones at z = t
    top = _plane_rows(zero, Gl, nu_layer, True, (zero, s))          # (4, n, 4)
    bot_l = _plane_rows(s, Gl, nu_layer, True, (zero, s))
    M = np.zeros((n, 6, 6), complex)
    M[:, 0, :4] = top[2]          # s_zz(0) = -p
    M[:, 1, :4] = top[3]          # s_xz(0) = -q
    if rigid:
        # bonded to a rigid substrate: u = 0 at z = t (the substrate amplitudes unused)
        M[:, 2, :4] = bot_l[0]
        M[:, 3, :4] = bot_l[1]
        M[:, 4, 4] = 1.0
        M[:, 5, 5] = 1.0
    else:
        bot_s = _plane_rows(s, Gs, nu_substrate, False, (s, s))     # (4, n, 2)
        for r in range(4):        # u_x, u_z, s_zz, s_xz continuous at z = t
            M[:, 2 + r, :4] = bot_l[r]
            M[:, 2 + r, 4:] = -bot_s[r]
    rhs = np.zeros((n, 6, 2), complex)
    rhs[:, 0, 0] = -1.0           # unit pressure
    rhs[:, 1, 1] = -1.0           # unit shear along q
    sol = np.linalg.solve(M, rhs)  # (n, 6, 2)
    ux = np.einsum("nk,nkc->nc", top[0], sol[:, :4, :])
    uz = np.einsum("nk,nkc->nc", top[1], sol[:, :4, :])
    # antiplane: unknowns [X1 X2 | X3]
    ta = _anti_rows(zero, Gl, True, (zero, s))
    ba = _anti_rows(s, Gl, True, (zero, s))
    Ma = np.zeros((n, 3, 3), complex)
    Ma[:, 0, :2] = ta[1]
    if rigid:
        Ma[:, 1, :2] = ba[0]
        Ma[:, 2, 2] = 1.0
    else:
        bs = _anti_rows(s, Gs, False, (s, s))
        for r in range(2):
            Ma[:, 1 + r, :2] = ba[r]
            Ma[:, 1 + r, 2:] = -bs[r]
    ra = np.zeros((n, 3), complex)
    ra[:, 0] = -1.0
    xa = np.linalg.solve(Ma, ra[..., None])[..., 0]
    uy = np.einsum("nk,nk->n", ta[0], xa[:, :2])
    return {"zz": uz[:, 0].real, "xz": ux[:, 0], "zx": uz[:, 1], "L": ux[:, 1].real, "T": uy.real}


# ----------------------------------------------------------------------------- the body model

#: The factors are tabulated on log-spaced s = q t in [S_MIN, S_MAX] and splined; beyond S_MAX
#: they are the layer's half-space values (exp(-2 S_MAX) of them), below S_MIN the table's first.
S_MIN, S_MAX, S_POINTS = 1e-5, 40.0, 3000
#: Free boundary: the smooth remainder of the kernel is kept out to R_CUT layer thicknesses
#: (beyond, it decays as (t / r)^3 relative to the half-space terms: 5e-6 there).
R_CUT = 60.0


@lru_cache(maxsize=32)
def _factor_splines(nu_layer: float, nu_substrate: float, shear_ratio: float):
    from scipy.interpolate import CubicSpline

    s = np.geomspace(S_MIN, S_MAX, S_POINTS)
    f = layer_factors(s, nu_layer, nu_substrate, shear_ratio)
    ls = np.log(s)
    return {"zz": CubicSpline(ls, f["zz"]), "xz": CubicSpline(ls, f["xz"].imag), "L": CubicSpline(ls, f["L"]),
            "T": CubicSpline(ls, f["T"])}


def _rect_inverse_distance(xc, yc, t: float) -> np.ndarray:
    """Integrals of 1 / sqrt(x^2 + y^2 + t^2) over the lattice's cells (m), from the antiderivative
    F = x ln(y + rho) + y ln(x + rho) - t atan(x y / (t rho)) at the corners."""
    X = np.asarray(xc, float)[:, None]
    Y = np.asarray(yc, float)[None, :]
    rho = np.sqrt(X * X + Y * Y + t * t)
    F = X * np.log(Y + rho) + Y * np.log(X + rho) - t * np.arctan2(X * Y, t * rho)
    return F[1:, 1:] - F[:-1, 1:] - F[1:, :-1] + F[:-1, :-1]



@lru_cache(maxsize=16)
def _remainder_tables(nu_layer: float, nu_substrate: float, shear_ratio: float, t: float):
    """The smooth parts of the coated body's kernels in real space (x G_l, per unit force).

    Each block's remainder over the layer's half-space, R(q) G_l = (f(q t) - f_layer) / q, is
    A e^(-q t) / q (A its q -> 0 limit, in closed form in real space) plus a bounded R2(q)
    decaying as exp(-q t), whose Hankel transform int_0^inf R2(q) J_n(q r) q dq is tabulated on
    [0, R_CUT t] (it decays as (t / r)^3): n = 0 for "zz" (normal) and "S" (the isotropic part
    of the in-plane blocks, (L + T) / 2), n = 2 for "D" ((L - T) / 2, with cos 2 phi), n = 1 for
    "c" (the coupling, with cos phi).

    Returns
    -------
    r : ndarray
        The radii (m).
    tables : dict
        name -> (A, I(r)) (dimensionless, 1/m^2 x m^... per unit force x G_l).
    """
    from scipy.special import j0, j1

    def jn(order, x):
        # J2 = 2 J1(x) / x - J0(x) (the recurrence; scipy's jv is 40x slower than j0, j1)
        if order == 0:
            return j0(x)
        if order == 1:
            return j1(x)
        xs = np.where(x > 0, x, 1.0)
        return np.where(x > 0, 2.0 * j1(xs) / xs - j0(xs), 0.0)

    sp = _factor_splines(nu_layer, nu_substrate, shear_ratio)
    l0 = math.log(S_MIN)
    lay = _halfspace_factors(nu_layer)
    q = np.linspace(0.0, 40.0 / t, 1 + int(40.0 * 8 * R_CUT))[1:]  # dq = 1 / (8 R_CUT t); R2 ~ exp(-40) beyond
    sq = q * t
    ls = np.log(np.clip(sq, S_MIN, S_MAX))
    thick = sq >= S_MAX

    def diff(key):
        f = np.where(thick, lay[key], sp[key](ls))
        return f - lay[key], float(sp[key](l0)) - lay[key]

    dzz, azz = diff("zz")
    dL, aL = diff("L")
    dT, aT = diff("T")
    dc, ac = diff("xz")
    parts = {"zz": (dzz, azz, 0), "S": (0.5 * (dL + dT), 0.5 * (aL + aT), 0),
             "D": (0.5 * (dL - dT), 0.5 * (aL - aT), 2), "c": (dc, ac, 1)}
    w = np.full(q.size, q[1] - q[0])
    w[0] *= 0.5
    r = np.concatenate([np.linspace(0.0, 4.0 * t, 241), np.geomspace(4.0 * t, R_CUT * t, 300)[1:]])
    decay = np.exp(-sq)
    tables = {}
    for name, (d, A, order) in parts.items():
        if not np.any(d) and A == 0.0:  # a layer of the substrate's own material
            tables[name] = (0.0, np.zeros(r.size))
            continue
        R2 = (d - A * decay) / q
        out = np.empty(r.size)
        for k0 in range(0, r.size, 64):
            rr = r[k0:k0 + 64, None]
            out[k0:k0 + 64] = (jn(order, rr * q[None, :]) * (R2 * q * w)[None, :]).sum(axis=1)
        tables[name] = (A, out)
    return r, tables


def _analytic(order: int, r, t: float):
    """int_0^inf e^(-q t) J_n(q r) dq (1/m): 1/rho, (rho - t) / (r rho), (rho - t)^2 / (r^2 rho)."""
    rho = np.sqrt(r * r + t * t)
    if order == 0:
        return 1.0 / rho
    rs = np.where(r > 0, r, 1.0)
    base = np.where(r > 0, (rho - t) / rs, 0.0)
    return base ** order / rho


@dataclass(frozen=True)
class CoatedHalfSpace(BodyModel):
    """One body of the pair carries an elastic layer perfectly bonded to it (the other is a
    homogeneous half-space or rigid).

    Parameters
    ----------
    coated : {1, 2}
        Which body carries the layer; its own E, nu are the substrate's.
    E, nu : float
        The layer's Young's modulus (Pa) and Poisson's ratio.
    thickness : float
        The layer's thickness (m), > 0.
    """

    name: ClassVar[str] = "coated"
    coated: int = 1
    E: float = 0.0
    nu: float = 0.0
    thickness: float = 0.0

    def __post_init__(self):
        if self.coated not in (1, 2):
            raise InputError("layer.body", f"must be 1 or 2, got {self.coated!r}")
        if not (math.isfinite(self.E) and self.E > 0):
            raise InputError("layer.E", f"must be a finite modulus > 0 Pa, got {self.E!r}")
        if not (-1.0 < self.nu < 0.5):
            raise InputError("layer.nu", f"must lie in (-1, 0.5), got {self.nu!r}")
        if not (math.isfinite(self.thickness) and self.thickness > 0):
            raise InputError("layer.thickness", f"must be a finite length > 0 m, got {self.thickness!r}")

    @property
    def layer_shear_modulus(self) -> float:
        """G of the layer (Pa)."""
        return self.E / (2.0 * (1.0 + self.nu))

    def _substrate(self, pair):
        sub = pair.body1 if self.coated == 1 else pair.body2
        if sub.is_rigid:
            return sub, math.inf
        return sub, sub.shear_modulus / self.layer_shear_modulus

    def _splines(self, pair):
        sub, ratio = self._substrate(pair)
        return _factor_splines(float(self.nu), float(sub.nu), float(ratio))

    def _factors(self, pair, q):
        """The coated body's (C_zz, C_L, C_T, C_xz / i) at wavenumbers q (m/Pa)."""
        sp = self._splines(pair)
        s = q * self.thickness
        ls = np.log(np.clip(s, S_MIN, S_MAX))
        thick = s >= S_MAX
        Gq = self.layer_shear_modulus * q
        lay = _halfspace_factors(self.nu)
        return tuple(np.where(thick, lay[k], sp[k](ls)) / Gq for k in ("zz", "L", "T", "xz"))

    def symbol(self, pair, key, qx, qy):
        """The composite Fourier kernels (m/Pa): the coated body's from :func:`layer_factors`,
        rotated onto (qx, qy), plus the other body's half-space kernels."""
        qx, qy = np.broadcast_arrays(np.asarray(qx, float), np.asarray(qy, float))
        q = np.hypot(qx, qy)
        qs = np.where(q > 0, q, 1.0)
        c, s = qx / qs, qy / qs
        total = {"zz": 0.0, "xx": 0.0, "yy": 0.0, "xy": 0.0, "xz": 0.0}
        for b, mat, sign in ((1, pair.body1, 1.0), (2, pair.body2, -1.0)):
            if b == self.coated:
                zz, L, T, xz = self._factors(pair, qs)
            elif mat.is_rigid:
                continue
            else:
                hs = _halfspace_factors(mat.nu)
                zz, L, T, xz = (hs[k] / (mat.shear_modulus * qs) for k in ("zz", "L", "T", "xz"))
            total["zz"] = total["zz"] + zz
            total["xx"] = total["xx"] + L * c * c + T * s * s
            total["yy"] = total["yy"] + L * s * s + T * c * c
            total["xy"] = total["xy"] + (L - T) * c * s
            total["xz"] = total["xz"] + sign * xz
        if key == "zz":
            return total["zz"]
        if key in ("xx", "yy"):
            return total[key]
        if key in ("xy", "yx"):
            return total["xy"]
        # the coupling: u_x from p is i C_xz cos(theta) (body 1), u_z from q_x its negative
        cx = 1j * total["xz"]
        return {"xz": cx * c, "zx": -cx * c, "yz": cx * s, "zy": -cx * s}[key]

    def influence_coefficients(self, pair, key: str, xc, yc) -> np.ndarray:
        """The coefficients on a free-boundary grid (m/Pa): the layer's half-space (Love's and
        Cerruti's closed forms, :func:`~tribobem.elasticity.influence.lattice_coefficients`) plus
        the remainder of the coated body's kernel over it (:func:`_remainder_tables`: its
        long-wavelength term in closed form, the rest by its Hankel transform; the normal block's
        long-wavelength term integrated exactly over each cell, everything else by a 6 x 6 Gauss
        rule on each cell), and the other body's half-space coefficients."""
        from ...materials import ContactPair, Material
        from ..influence import lattice_coefficients

        blocks = ("zz", "xx", "yy", "xy", "yx", "xz", "zx", "yz", "zy")
        if key not in blocks:
            raise InputError("key", f"must be one of {', '.join(blocks)}, got {key!r}")
        xc = np.asarray(xc, float)
        yc = np.asarray(yc, float)
        dx, dy = float(xc[1] - xc[0]), float(yc[1] - yc[0])
        t = self.thickness
        if t < 0.5 * max(dx, dy):
            raise InputError("layer.thickness", f"{t:.3g} m is thinner than half a cell ({max(dx, dy):.3g} m): the "
                             "layer is below the free-boundary grid's resolution; refine grid.n, or model the body "
                             "without the layer")
        Gl = self.layer_shear_modulus
        layer = Material(self.E, self.nu)
        rigid = Material.rigid()
        # the coated body's layer as a half-space, and the other body, each on its own side
        own = ContactPair(layer, rigid) if self.coated == 1 else ContactPair(rigid, layer)
        out = lattice_coefficients(key, own, xc, yc)
        other = pair.body2 if self.coated == 1 else pair.body1
        if not other.is_rigid:
            out += lattice_coefficients(key, ContactPair(rigid, other) if self.coated == 1
                                        else ContactPair(other, rigid), xc, yc)
        sub, ratio = self._substrate(pair)
        r_tab, tables = _remainder_tables(float(self.nu), float(sub.nu), float(ratio), float(t))
        sign = -1.0 if (self.coated == 2 and key in ("xz", "zx", "yz", "zy")) else 1.0
        if key == "zz":
            out += tables["zz"][0] / (2.0 * math.pi * Gl) * _rect_inverse_distance(xc, yc, t)

        def kernel(X, Y):
            """The remainder's point kernel (x 2 pi G_l) at offsets X, Y (m)."""
            r = np.hypot(X, Y)
            rs = np.where(r > 0, r, 1.0)
            c, sn = X / rs, Y / rs

            def H(name, order):
                A, tab = tables[name]
                smooth = np.interp(r, r_tab, tab, right=0.0)
                return (smooth + A * _analytic(order, r, t)) if name != "zz" else smooth

            if key == "zz":
                return H("zz", 0)  # (its long-wavelength term is integrated exactly above)
            if key in ("xx", "yy"):
                c2 = c * c - sn * sn
                return H("S", 0) + (-c2 if key == "xx" else c2) * H("D", 2)
            if key in ("xy", "yx"):
                return -2.0 * c * sn * H("D", 2)
            ang = c if key in ("xz", "zx") else sn
            # u_x from p is -cos(phi) H1[R_c]; u_z from q_x its negative (Betti)
            return (-1.0 if key in ("xz", "yz") else 1.0) * ang * H("c", 1)

        gx, gw = np.polynomial.legendre.leggauss(6)
        xm = 0.5 * (xc[1:] + xc[:-1])
        ym = 0.5 * (yc[1:] + yc[:-1])
        reach = R_CUT * t + max(dx, dy)
        if key != "zz":
            reach = math.inf  # the long-wavelength terms reach every cell
        ix = np.flatnonzero(np.abs(xm) <= reach)
        iy = np.flatnonzero(np.abs(ym) <= reach)
        if ix.size and iy.size:
            Xg = 0.5 * dx * gx
            Yg = ym[iy][:, None, None] + 0.5 * dy * gx[None, None, :]
            Wt = (0.25 * dx * dy) * gw[:, None] * gw[None, :]
            acc = np.zeros((ix.size, iy.size))
            for k in range(ix.size):  # one row of cells at a time (memory)
                X = (xm[ix[k]] + Xg)[None, :, None]
                acc[k] = (kernel(X, Yg) * Wt[None]).sum(axis=(-2, -1))
            out[np.ix_(ix, iy)] += sign * acc / (2.0 * math.pi * Gl)
        return out
