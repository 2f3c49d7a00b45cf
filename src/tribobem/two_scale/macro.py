"""Macro scale: normal contact of a body whose surface is a nonlinear compliant layer.

At macro scale a node carries the nominal pressure p of the rough interface beneath it, and its
mean-plane separation is the interface law's g(p) (:class:`~tribobem.two_scale.laws.
NormalInterfaceLaw`).  With the undeformed macro gap h (the burl's shape, waviness and the
textures longer than the micro window; m, min 0), the elastic displacement G p of the bodies
(the free-boundary or periodic operator, m) and the rigid approach delta (m):

    h + G p - delta = g(p)   where p > 0,
    h + G p - delta >= g(0)  where p = 0,                     sum(p) dA = F.

Since g decreases with p, this is the stationarity condition of the convex functional
1/2 p.G p + (h - delta).p - sum Psi(p), Psi(p) = int_0^p g, under p >= 0: one solution.  It is
solved by a projected Newton iteration: on the active set (p > 0, or a node the bodies reach) the
law is linearised, g(p') ~ g(p) - D (p' - p) with D = -dg/dp > 0, which gives the linear system
(G + D) p' - delta' = g(p) + D p - h; it and the force balance are solved by two
Jacobi-preconditioned conjugate-gradient solves ((G + D) x = b and (G + D) y = 1, then
delta' from the force), negative pressures are set to zero, and the step is repeated until the
law holds everywhere to ``tol`` (relative to g(0) + max |G p|).  D is large where the interface is soft
(low p) and G's largest eigenvalues are the body's long-wave compliance, so G + D is well
conditioned and the CG solves take tens of iterations.

Where the Hertz branch of the law makes the tangent D infinite (p -> 0), the law is linearised
by its secant from p = 0 instead (:func:`_linearised_law`).
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field

import numpy as np

from ..errors import InputError

__all__ = ["InterfaceNormalResult", "solve_interface_normal", "pressure_length", "radial_pressure_profile"]


@dataclass
class InterfaceNormalResult:
    """The macro normal solution with an interface law.

    Attributes
    ----------
    pressure : ndarray
        Nominal pressure of each macro cell (Pa, >= 0).
    separation : ndarray
        Mean-plane separation h + G p - delta of each cell (m): the interface's mean gap.
    displacement : ndarray
        Elastic displacement G p (m).
    approach : float
        Rigid approach delta (m), from the mean planes' touching position of the undeformed
        macro gap (h = 0 and a separation of g(0)).
    force : float
        Total normal force (N).
    nominal_area : float
        Area of the cells that carry pressure (m^2).
    real_contact_area : float
        Sum over the cells of the law's real contact fraction times the cell area (m^2).
    max_pressure : float
        Largest local pressure of the windows at the cells' nominal pressures (Pa).
    max_nominal_pressure : float
        Largest nominal pressure (Pa).
    newton_iterations, cg_iterations : int
        Outer (Newton) and total inner (CG) iterations.
    residual : float
        max |h + G p - delta - g(p)| over the loaded cells, over g(0) + max |G p|.
    converged : bool
    beyond_table : bool
        Whether a cell's nominal pressure exceeds the interface table's largest.
    time : float
        Wall time (s).
    """

    pressure: np.ndarray
    separation: np.ndarray
    displacement: np.ndarray
    approach: float
    force: float
    nominal_area: float
    real_contact_area: float
    max_pressure: float
    max_nominal_pressure: float
    newton_iterations: int
    cg_iterations: int
    residual: float
    converged: bool
    beyond_table: bool
    time: float = 0.0
    history: list = field(default_factory=list)


def _cg(apply, b, diag, x0, rtol: float, max_iter: int):
    """Jacobi-preconditioned CG for an SPD ``apply``; returns (x, iterations)."""
    x = x0.copy()
    r = b - apply(x)
    z = r / diag
    d = z.copy()
    # element-wise reductions, not BLAS dot products: the arrays are small and a threaded BLAS
    # contends with the FFT threads
    rz = float((r * z).sum())
    bnorm = float(np.sqrt((b * b).sum())) or 1.0
    for k in range(1, max_iter + 1):
        ad = apply(d)
        alpha = rz / float((d * ad).sum())
        x += alpha * d
        r -= alpha * ad
        if float(np.sqrt((r * r).sum())) <= rtol * bnorm:
            return x, k
        z = r / diag
        rz_new = float((r * z).sum())
        d = z + (rz_new / rz) * d
        rz = rz_new
    return x, max_iter


def _self_compliance(op) -> float:
    """Displacement of a cell under its own unit pressure (m/Pa), from the operator."""
    nx, ny = op.grid.nx, op.grid.ny
    e = np.zeros((nx, ny))
    e[nx // 2, ny // 2] = 1.0
    return float(op.apply(e)[nx // 2, ny // 2])


def _winkler_start(h, law, force, dA):
    """The rigid-body start: pressures p = g^-1(h - delta), delta set by bisection to the force."""
    def total(delta):
        return float(law.pressure(h - delta).sum()) * dA
    lo, hi = -law.touch_gap, -law.touch_gap + 1e-12
    while total(hi) < force:
        hi = lo + 2.0 * (hi - lo) + 1e-12
        if hi - lo > 1.0:  # no equilibrium (1 m of approach)
            raise InputError("force", f"the interface law cannot carry {force:.4g} N on this grid")
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if total(mid) < force:
            lo = mid
        else:
            hi = mid
        if hi - lo < 1e-15 * max(1.0, abs(hi)):
            break
    delta = 0.5 * (lo + hi)
    return law.pressure(h - delta), delta


def _linearised_law(law, p, sep, h, active):
    """The law linearised about the current state: (D, b) of (G + D) p' - delta' = b.

    On the table (p >= p_1) the tangent, g(p') ~ g(p) - D (p' - p).  On the Hertz branch below
    p_1 (first touching summits, where the tangent compliance is infinite at p = 0) the secant
    through (0, g(0)) and (p_ref, g(p_ref)), g(p') ~ g(0) - S p', with p_ref the larger of the
    node's pressure and the pressure the law gives at its current separation: a node that the
    bodies reach enters with a finite compliance, and the secant is exact at p' = 0, so a node
    that should carry a tiny pressure does not flip in and out of the active set.
    """
    g0, p1 = float(law.touch_gap), float(law.pressures[0])
    p_ref = np.where(active, np.maximum(p, law.pressure(np.where(active, sep, g0))), 0.0)
    hertz = active & (p_ref < p1)
    tangent = active & ~hertz
    D = np.zeros_like(p)
    b = np.zeros_like(p)
    if hertz.any():
        pr = np.maximum(p_ref[hertz], 1e-12 * p1)
        D[hertz] = (g0 - law.gap(pr)) / pr
        b[hertz] = g0 - h[hertz]
    if tangent.any():
        D[tangent] = law.compliance(p[tangent])
        b[tangent] = law.gap(p[tangent]) + D[tangent] * p[tangent] - h[tangent]
    return D, b


def solve_interface_normal(operator, gap, law, force: float, *, tol: float = 1e-8, max_newton: int = 100,
                           cg_tol: float = 1e-10, max_cg: int = 2000) -> InterfaceNormalResult:
    """Normal contact under a force with a tabulated rough-interface law (module docstring).

    Parameters
    ----------
    operator : ConvolutionOperator
        The macro elastic operator (its normal block is used), free-boundary or periodic.
    gap : ndarray
        Undeformed macro gap h (m), grid-shaped; its minimum is the first touch of the mean
        planes' envelope (usually 0).
    law : NormalInterfaceLaw
        The interface's mean separation against nominal pressure.
    force : float
        Total normal force (N), > 0.
    tol : float
        Convergence: max |h + G p - delta - g(p)| over the loaded cells, relative to
        g(0) + max |G p| (the size of the equation's terms).
    max_newton : int
        Newton iterations at most.
    cg_tol, max_cg : float, int
        Relative residual and iteration cap of each inner CG solve.

    Returns
    -------
    InterfaceNormalResult

    Raises
    ------
    InputError
        ``force`` (not positive, or more than the law can carry), ``gap`` (wrong shape or not
        finite).
    """
    t0 = time.perf_counter()
    op = operator.normal if len(getattr(operator, "components", ("z",))) > 1 else operator
    h = np.asarray(gap, dtype=float)
    if h.shape != op.grid.shape or not np.all(np.isfinite(h)):
        raise InputError("gap", f"must be a finite array of the grid's shape {op.grid.shape}, got {h.shape}")
    if not force > 0:
        raise InputError("force", f"must be positive (compressive), got {force!r}")
    dA = op.grid.dx * op.grid.dy
    c0 = _self_compliance(op)
    g0 = float(law.touch_gap)
    p, delta = _winkler_start(h, law, force, dA)
    total_cg, history = 0, []
    converged, residual = False, np.inf
    for it in range(1, max_newton + 1):
        u = op.apply(p)
        sep = h + u - delta
        loaded = p > 0
        # relative to the larger of the interface's gap and the elastic displacement (the terms of
        # the equation): a stiff layer (g0 << u) is then judged at the round-off of u
        scale = g0 + float(np.max(np.abs(u)))
        residual = float(np.max(np.abs(sep[loaded] - law.gap(p[loaded])))) / scale if loaded.any() else np.inf
        reached = (~loaded) & (sep < g0 - tol * scale)
        history.append((residual, int(loaded.sum()), int(reached.sum())))
        if residual <= tol and not reached.any():
            converged = True
            break
        active = loaded | reached
        D, b = _linearised_law(law, p, sep, h, active)
        mask = active.astype(float)

        def apply(x, mask=mask, D=D):
            return mask * op.apply(mask * x) + D * x + (1.0 - mask) * x

        diag = np.where(active, c0 + D, 1.0)
        x, kx = _cg(apply, b, diag, np.where(active, p, 0.0), cg_tol, max_cg)
        y, ky = _cg(apply, mask, diag, np.zeros_like(p), cg_tol, max_cg)
        total_cg += kx + ky
        delta_new = (force / dA - float(x[active].sum())) / float(y[active].sum())
        p_new = np.where(active, x + delta_new * y, 0.0)
        p = np.maximum(p_new, 0.0)
        # the projection changed the force: restore it with delta (the active nodes' y)
        if p.sum() * dA != force:
            keep = p > 0
            corr = (force / dA - float(p[keep].sum())) / float(y[keep].sum())
            p = np.where(keep, np.maximum(p + corr * y, 0.0), 0.0)
            delta_new += corr
        delta = delta_new
    u = op.apply(p)
    sep = h + u - delta
    real = float(law.contact_fraction(p).sum()) * dA
    return InterfaceNormalResult(
        pressure=p, separation=sep, displacement=u, approach=float(delta), force=float(p.sum() * dA),
        nominal_area=float((p > 0).sum() * dA), real_contact_area=real,
        max_pressure=float(law.max_pressure(p).max()), max_nominal_pressure=float(p.max()),
        newton_iterations=it, cg_iterations=total_cg, residual=residual, converged=converged,
        beyond_table=law.beyond_table(p), time=time.perf_counter() - t0, history=history)


def pressure_length(pressure: np.ndarray, dx: float, dy: float) -> dict:
    """The length over which the nominal pressure changes, p / |grad p| (m), over the loaded cells.

    The scale-separation condition of the two-scale solve: the interface law of a window holds
    where the nominal pressure is uniform over the window, i.e. where the window is small
    against this length.  Taken over the cells above a tenth of the mean loaded pressure (the
    very edge, where p -> 0, would give 0).

    Parameters
    ----------
    pressure : ndarray
        Nominal pressure of the macro cells (Pa).
    dx, dy : float
        Macro cell sides (m).

    Returns
    -------
    dict
        ``median`` and ``p05`` (the 5th percentile: the contact edge) in m; NaN without
        loaded cells.
    """
    loaded = pressure > 0
    if not loaded.any():
        return {"median": float("nan"), "p05": float("nan")}
    gx, gy = np.gradient(pressure, dx, dy)
    grad = np.hypot(gx, gy)
    sel = pressure > 0.1 * float(pressure[loaded].mean())
    length = pressure[sel] / np.maximum(grad[sel], np.finfo(float).tiny)
    return {"median": float(np.median(length)), "p05": float(np.percentile(length, 5))}


def radial_pressure_profile(pressure: np.ndarray, dx: float, dy: float, width: float, rmax: float) -> dict:
    """The azimuthal mean of a pressure field in rings about the grid's centre.

    On a whole-grid solve the rings average the asperity pressures into the nominal pressure
    profile; on a macro grid they average its cells.

    Parameters
    ----------
    pressure : ndarray
        Pressure (Pa), local or nominal.
    dx, dy : float
        Cell sides (m).
    width : float
        Ring width (m).
    rmax : float
        Outer radius of the last ring (m).

    Returns
    -------
    dict
        ``radius`` (m, the rings' mid radii) and ``pressure`` (Pa, their mean pressure; NaN in a
        ring without cells).
    """
    nx, ny = pressure.shape
    x = (np.arange(nx) + 0.5) * dx - 0.5 * nx * dx
    y = (np.arange(ny) + 0.5) * dy - 0.5 * ny * dy
    r = np.hypot(x[:, None], y[None, :]).ravel()
    edges = np.arange(0.0, rmax + 0.5 * width, width)
    k = np.digitize(r, edges) - 1
    ok = (k >= 0) & (k < edges.size - 1)
    total = np.bincount(k[ok], weights=np.asarray(pressure, float).ravel()[ok], minlength=edges.size - 1)
    count = np.bincount(k[ok], minlength=edges.size - 1)
    with np.errstate(invalid="ignore", divide="ignore"):
        mean = np.where(count > 0, total / np.maximum(count, 1), np.nan)
    return {"radius": (0.5 * (edges[:-1] + edges[1:])).tolist(), "pressure": mean.tolist()}
