"""A sphere on a hardness-capped flat: an axisymmetric reference, independent of the grid solvers.

The cap model bounds the contact pressure by the hardness, 0 <= p(r) <= H; where p = H the
overlap is taken up plastically.  For a paraboloid gap h(r) = r^2 / (2 R) under a rigid
approach delta the pressure is the minimiser over the box [0, H] of the elastic energy

    Pi(p) = 1/2 <p, u(p)> + <p, h - delta>,

u(p) the normal displacement of the half-space.  Here p is piecewise constant on N concentric
rings and u at the ring midpoints comes from the closed-form displacement of a uniformly
loaded disc (Johnson, Contact Mechanics, 1985, Eq. 3.36-3.37, for a disc of radius b under a
pressure q):

    u(r) = (4 q b / (pi E*)) E(r / b)                                 r <= b,
    u(r) = (4 q r / (pi E*)) [E(b / r) - (1 - b^2 / r^2) K(b / r)]      r >  b,

K and E the complete elliptic integrals of modulus k.  A ring is the difference of two discs.
The area-weighted influence matrix is symmetric (reciprocity), so the box-constrained
quadratic programme is convex; it is solved by SciPy's L-BFGS-B with bounds.  Force control
solves for delta by Brent's method.  Nothing here shares code with the grid solvers.

With H above Hertz's p0 it is Hertz's solution (the first test of the reference).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy import optimize, special

__all__ = ["CappedSphere", "capped_sphere", "coated_ring_influence", "disc_displacement"]


def disc_displacement(r, b: float, effective_modulus: float):
    """Normal displacement (m) at radii ``r`` (m) of a unit pressure (1 Pa) on a disc of radius b (m).

    Parameters
    ----------
    r : array_like
        Radii (m), >= 0, not equal to ``b``.
    b : float
        Disc radius (m), > 0.
    effective_modulus : float
        E* (Pa).
    """
    r = np.asarray(r, dtype=float)
    out = np.empty_like(r)
    inside = r <= b
    k = r[inside] / b
    out[inside] = 4.0 * b / (math.pi * effective_modulus) * special.ellipe(k * k)
    ro = r[~inside]
    k = b / ro
    out[~inside] = 4.0 * ro / (math.pi * effective_modulus) * (special.ellipe(k * k) - (1.0 - k * k) * special.ellipk(k * k))
    return out


@dataclass(frozen=True)
class CappedSphere:
    """The axisymmetric capped state.

    Attributes
    ----------
    r : ndarray
        Ring midpoints (m).
    pressure : ndarray
        Ring pressures (Pa), in [0, H].
    force : float
        Total force (N).
    approach : float
        Rigid approach (m).
    contact_radius : float
        Outer radius of the loaded rings (m).
    plastic_radius : float
        Outer radius of the rings at p = H (m; 0 when none).
    """

    r: np.ndarray
    pressure: np.ndarray
    force: float
    approach: float
    contact_radius: float
    plastic_radius: float


def _influence(edges: np.ndarray, effective_modulus: float) -> np.ndarray:
    r = 0.5 * (edges[1:] + edges[:-1])
    cols = [disc_displacement(r, b, effective_modulus) for b in edges[1:]]
    A = np.stack(cols, axis=1)  # A[i, j]: displacement at r_i of unit pressure on disc edges[j+1]
    A[:, 1:] -= A[:, :-1].copy()
    return r, A


def capped_sphere(radius: float, effective_modulus: float, hardness: float, *, force: float | None = None,
                  approach: float | None = None, outer: float | None = None, rings: int = 400,
                  influence=None) -> CappedSphere:
    """The capped sphere under a force or an approach.

    Parameters
    ----------
    radius : float
        Composite sphere radius R (m).
    effective_modulus : float
        E* (Pa).
    hardness : float
        H (Pa), > 0 (``math.inf``: Hertz).
    force, approach : float
        Total force (N, > 0) or rigid approach (m, > 0); exactly one.
    outer : float, optional
        Outer radius of the ring mesh (m); default: 1.6 times the radius of the rigid-plastic
        contact sqrt(F / (pi H)) or of Hertz's contact, whichever is larger.
    rings : int
        Number of rings.
    influence : callable, optional
        ``influence(edges) -> A`` with ``A[i, j]`` the displacement (m/Pa) at the midpoint of
        ring i of a unit pressure on ring j (edges in m); default: the homogeneous half-space of
        ``effective_modulus`` (:func:`disc_displacement`).  A coated flat:
        :func:`coated_ring_influence`.
    """
    if (force is None) == (approach is None):
        raise ValueError("give exactly one of force and approach")
    if outer is None:
        f = force if force is not None else 16.0 / 3.0 * effective_modulus * math.sqrt(radius) * approach ** 1.5 / 4.0
        a_h = (3.0 * f * radius / (4.0 * effective_modulus)) ** (1.0 / 3.0)
        a_p = math.sqrt(f / (math.pi * hardness)) if math.isfinite(hardness) else 0.0
        outer = 1.6 * max(a_h, a_p, math.sqrt(2.0 * radius * approach) if approach is not None else 0.0)
    edges = np.linspace(0.0, outer, rings + 1)
    if influence is None:
        r, A = _influence(edges, effective_modulus)
    else:
        r, A = 0.5 * (edges[1:] + edges[:-1]), np.asarray(influence(edges), dtype=float)
    w = math.pi * (edges[1:] ** 2 - edges[:-1] ** 2)
    Q = w[:, None] * A
    Q = 0.5 * (Q + Q.T)  # symmetric up to round-off (reciprocity)
    h = r * r / (2.0 * radius)
    # dimensionless unknowns x = p / P (P the smaller of H and Hertz's scale), energies / Z
    P = min(hardness, effective_modulus * outer / radius)
    Qs = Q * P * P
    x_max = hardness / P if math.isfinite(hardness) else None
    bounds = [(0.0, x_max)] * rings

    def solve(delta, p0):
        c = w * (h - delta) * P
        Z = float(np.abs(c).sum()) or 1.0
        res = optimize.minimize(lambda x: ((0.5 * x @ Qs @ x + c @ x) / Z, (Qs @ x + c) / Z), p0 / P, jac=True,
                                method="L-BFGS-B", bounds=bounds,
                                options={"maxiter": 50000, "maxfun": 100000, "ftol": 1e-16, "gtol": 1e-13})
        return res.x * P

    p_guess = np.zeros(rings)
    if approach is not None:
        delta = float(approach)
        p = solve(delta, p_guess)
    else:
        cache = {}

        def mismatch(d):
            cache[d] = solve(d, p_guess)
            return float(w @ cache[d]) - force

        d_hi = max(force / (math.pi * hardness) / radius if math.isfinite(hardness) else 0.0,
                   (9.0 * force ** 2 / (16.0 * radius * effective_modulus ** 2)) ** (1.0 / 3.0))
        while mismatch(d_hi) < 0:
            d_hi *= 2.0
        delta = optimize.brentq(mismatch, 0.0, d_hi, xtol=1e-14 * d_hi, rtol=1e-12)
        p = cache.get(delta)
        if p is None:
            p = solve(delta, p_guess)
    loaded = p > 1e-9 * (hardness if math.isfinite(hardness) else float(p.max()))
    at_cap = p >= hardness * (1.0 - 1e-6) if math.isfinite(hardness) else np.zeros(rings, bool)
    a = float(edges[1:][loaded].max()) if loaded.any() else 0.0
    c = float(edges[1:][at_cap].max()) if at_cap.any() else 0.0
    return CappedSphere(r, p, float(w @ p), float(delta), a, c)


def coated_ring_influence(compliance, reference_modulus: float, length: float, q_max_factor: float = 40.0):
    """Ring influence of a compliance C(q) (m/Pa, a function of the wavenumber q in rad/m), for
    :func:`capped_sphere`: the half-space of ``reference_modulus`` (E*, closed form) plus the
    Hankel transform of the difference, u(r) = int_0^inf [C(q) - 2 / (E* q)] (b2 J1(q b2) - b1 J1(q b1))
    J0(q r) dq, by the trapezoidal rule up to ``q_max_factor / length`` (the difference decays as
    exp(-2 q t) for a layer of thickness t = ``length``).

    Returns
    -------
    callable
        ``influence(edges) -> A``.
    """
    from scipy.special import j0, j1

    def influence(edges):
        edges = np.asarray(edges, dtype=float)
        r, A = _influence(edges, reference_modulus)
        span = float(edges[-1])
        q = np.linspace(0.0, q_max_factor / length, 1 + int(40 * q_max_factor * span / length) + 2000)[1:]
        w = np.full(q.size, q[1] - q[0])
        dC = np.asarray(compliance(q), dtype=float) - 2.0 / (reference_modulus * q)
        Jr = j0(np.outer(r, q))                       # (rings, nq)
        disc = edges[1:, None] * j1(np.outer(edges[1:], q))
        disc[1:] -= edges[1:-1, None] * j1(np.outer(edges[1:-1], q))
        A = A + (Jr * (dC * w)[None, :]) @ disc.T
        return A

    return influence
