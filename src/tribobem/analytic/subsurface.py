"""Closed-form stresses below a Hertz contact: the sphere (Huber 1904) and the sliding cylinder
(McEwen 1949).

Conventions: tension positive, z the depth into the body (m), a the contact radius or
half-width (m), p0 the maximum Hertz pressure (Pa); the results are in Pa.

Sphere (Huber 1904; Johnson, *Contact Mechanics*, 1985, Eqs. 3.44-3.45), with
u = [(r^2 + z^2 - a^2) + sqrt((r^2 + z^2 - a^2)^2 + 4 a^2 z^2)] / 2::

    sigma_r / p0 = (1 - 2 nu) / 3 (a^2 / r^2) (1 - (z / sqrt u)^3)
                   + (z / sqrt u)^3 a^2 u / (u^2 + a^2 z^2)
                   + (z / sqrt u) [(1 - nu) u / (a^2 + u) + (1 + nu) (sqrt u / a) atan(a / sqrt u) - 2]
    sigma_t / p0 = -(1 - 2 nu) / 3 (a^2 / r^2) (1 - (z / sqrt u)^3)
                   - (z / sqrt u) [2 nu + (1 - nu) u / (a^2 + u) - (1 + nu) (sqrt u / a) atan(a / sqrt u)]
    sigma_z / p0 = -(z / sqrt u)^3 a^2 u / (u^2 + a^2 z^2)
    tau_rz / p0 = -r z^2 / (u^2 + a^2 z^2) a^2 sqrt u / (a^2 + u)

On the axis: sigma_z = -p0 / (1 + z^2 / a^2), sigma_r = sigma_t =
-p0 [(1 + nu) (1 - (z / a) atan(a / z)) - 1 / (2 (1 + z^2 / a^2))]; for nu = 0.3 the largest
shear stress (sigma_z - sigma_r) / 2 is 0.31 p0 at z = 0.48 a.

Sliding cylinder (plane strain; McEwen 1949; Johnson Eqs. 4.49 and 7.14; the tangential
traction q = mu p acts on the body's surface in +x), with
m^2 = [sqrt((a^2 - x^2 + z^2)^2 + 4 x^2 z^2) + (a^2 - x^2 + z^2)] / 2,
n^2 = [sqrt(...) - (a^2 - x^2 + z^2)] / 2, n of the sign of x::

    normal:      sigma_x = -(p0 / a) [m (1 + (z^2 + n^2) / (m^2 + n^2)) - 2 z]
                 sigma_z = -(p0 / a) m (1 - (z^2 + n^2) / (m^2 + n^2))
                 tau_xz  = -(p0 / a) n (m^2 - z^2) / (m^2 + n^2)
    tangential:  sigma_x = (q0 / a) [n (2 - (z^2 - m^2) / (m^2 + n^2)) - 2 x]
                 sigma_z = -(q0 / a) n (m^2 - z^2) / (m^2 + n^2)
                 tau_xz  = -(q0 / a) [m (1 + (z^2 + n^2) / (m^2 + n^2)) - 2 z]

(the signs here make the surface values -p, -q: sigma_z = -p0 sqrt(1 - x^2 / a^2) and tau_xz =
-q0 sqrt(1 - x^2 / a^2) under the contact, the traction t = -sigma . e_z of a body below the
surface); sigma_y = nu (sigma_x + sigma_z) in plane strain.
"""

from __future__ import annotations

import numpy as np

__all__ = ["hertz_axis_stresses", "huber_stresses", "mcewen_stresses"]


def hertz_axis_stresses(z, a: float, p0: float, nu: float) -> tuple[np.ndarray, np.ndarray]:
    """(sigma_r = sigma_theta, sigma_z) on the axis of a Hertz sphere contact (Pa) at depths ``z`` (m)."""
    z = np.asarray(z, dtype=float)
    zeta = z / a
    with np.errstate(divide="ignore", invalid="ignore"):
        atan = np.where(zeta > 0, np.arctan(1.0 / np.where(zeta > 0, zeta, 1.0)), np.pi / 2)
    sz = -p0 / (1.0 + zeta ** 2)
    sr = -p0 * ((1.0 + nu) * (1.0 - zeta * atan) - 0.5 / (1.0 + zeta ** 2))
    return sr, sz


def huber_stresses(r, z, a: float, p0: float, nu: float) -> dict:
    """Huber's stresses below a Hertz sphere contact (module docstring), at radii ``r`` and depths
    ``z`` (m, broadcast; z > 0): ``{"rr", "tt", "zz", "rz"}`` (Pa)."""
    r = np.asarray(r, dtype=float)
    z = np.asarray(z, dtype=float)
    r, z = np.broadcast_arrays(r, z)
    A = r * r + z * z - a * a
    u = 0.5 * (A + np.sqrt(A * A + 4.0 * a * a * z * z))
    su = np.sqrt(u)
    zs = z / su
    rr = np.where(r > 0, r, 1.0)
    edge = np.where(r > 0, (a * a / (rr * rr)) * (1.0 - zs ** 3), 1.5 * a * a / (a * a + z * z))
    # (on the axis the edge term's limit is 3 a^2 / (2 (a^2 + z^2)))
    at = (su / a) * np.arctan(a / su)
    srr = (1 - 2 * nu) / 3 * edge + zs ** 3 * a * a * u / (u * u + a * a * z * z) \
        + zs * ((1 - nu) * u / (a * a + u) + (1 + nu) * at - 2.0)
    stt = -(1 - 2 * nu) / 3 * edge - zs * (2 * nu + (1 - nu) * u / (a * a + u) - (1 + nu) * at)
    szz = -zs ** 3 * a * a * u / (u * u + a * a * z * z)
    srz = -r * z * z / (u * u + a * a * z * z) * a * a * su / (a * a + u)
    return {"rr": p0 * srr, "tt": p0 * stt, "zz": p0 * szz, "rz": p0 * srz}


def mcewen_stresses(x, z, a: float, p0: float, mu: float = 0.0, nu: float = 0.3) -> dict:
    """McEwen's stresses below a sliding Hertz line contact (module docstring), at ``x``, ``z``
    (m, broadcast; z >= 0), with q0 = mu p0: ``{"xx", "yy", "zz", "xz"}`` (Pa)."""
    x = np.asarray(x, dtype=float)
    z = np.asarray(z, dtype=float)
    x, z = np.broadcast_arrays(x, z)
    B = a * a - x * x + z * z
    root = np.sqrt(B * B + 4.0 * x * x * z * z)
    m = np.sqrt(np.maximum(0.5 * (root + B), 0.0))
    n = np.sign(x) * np.sqrt(np.maximum(0.5 * (root - B), 0.0))
    mn = m * m + n * n
    ratio = np.where(mn > 0, (z * z + n * n) / np.where(mn > 0, mn, 1.0), 1.0)
    diff = np.where(mn > 0, (m * m - z * z) / np.where(mn > 0, mn, 1.0), 0.0)
    sx = -(p0 / a) * (m * (1 + ratio) - 2 * z)
    sz = -(p0 / a) * m * (1 - ratio)
    txz = -(p0 / a) * n * diff
    if mu:
        q0 = mu * p0
        sx = sx + (q0 / a) * (n * (2 + diff) - 2 * x)
        sz = sz - (q0 / a) * n * diff
        txz = txz - (q0 / a) * (m * (1 + ratio) - 2 * z)
    return {"xx": sx, "yy": nu * (sx + sz), "zz": sz, "xz": txz}
