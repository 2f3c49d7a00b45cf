"""Validation of the material models: the hardness cap with plastic history, subsurface stresses,
coated bodies.

Cases (``tribobem validate --physics materials``):

``hardness_hertz``
    A sphere whose Hertz pressure stays below the cap (H = 1.2 p0): the capped solve is Hertz's
    (approach and contact radius against Hertz, no plastic node).
``hardness_sphere``
    The sphere beyond p_max = H (H = 0.8 and 0.5 p0): approach, contact radius and radius of the
    flat top (p = H) against the axisymmetric capped-sphere reference
    (:mod:`tribobem.analytic.capped_sphere`, an independent box-constrained programme on rings).
``hardness_rigid_plastic``
    A periodic rough surface with E* / H = 10, 100, 1000 at a mean pressure of 2 % of H: the real
    area tends to the rigid-plastic F / H (the elastic fringe of each spot shrinks).
``hardness_pulloff``
    A Dugdale sphere (Maugis lambda ~ 0.8) preloaded to ten pull-offs with H = p0 / 2 and
    unloaded: the flattened top adheres more than the elastic sphere (at least 1.5 times; the
    elastic pull-off itself against Maugis-Dugdale's).
``subsurface_hertz``
    The stresses below the solved Hertz contact (nu = 0.3) against Huber's closed form: the
    largest shear stress 0.31 p0 at 0.48 a on the axis, and the whole field on two planes.
``subsurface_sliding``
    A sliding Hertz line contact (mu = 0.3, plane strain on a long periodic strip) against
    McEwen's closed form.
``subsurface_equilibrium``
    div sigma = 0 inside, and the plane integrals of sigma_zz and sigma_xz against the load, for
    a rough periodic traction with shear.
``layer_limits``
    A coated half-space's surface compliances (normal, along and across the wave vector,
    coupling) tend to the substrate's as the layer thins and to the layer's as it thickens.
``layer_fem``
    The normal and longitudinal compliances of a SiO2 layer on Si at q t = 0.2, 1 and 3 against a
    plane-strain finite-element model (scikit-fem, :mod:`tribobem.validation.layer_fem`).
``layer_sphere``
    A sphere on a coated flat: the free-boundary grid (the kernel's Hankel transform) against a
    periodic cell four times wider (the kernel's symbol): contact radius and largest pressure;
    and its approach and largest pressure against an axisymmetric ring solution of the same
    kernel (no grid).
"""

from __future__ import annotations

import math
from types import SimpleNamespace
from typing import Callable

import numpy as np

from ..analytic.adhesion import maugis_dugdale_pull_off_force
from ..analytic.capped_sphere import capped_sphere, coated_ring_influence
from ..analytic.subsurface import huber_stresses, mcewen_stresses
from ..elasticity import free_boundary_operator, make_operator
from ..elasticity.subsurface import subsurface_stress
from ..geometry.rough import self_affine_surface
from ..geometry.shapes import sphere
from ..grid import Grid
from ..interactions.dugdale import build_dugdale
from ..interactions.hardness import HardnessCap
from ..interactions.registry import LawContext
from ..materials import ContactPair, Material
from ..solvers.normal_paths import pull_off
from .common import ValidationRow, _row, _solve

__all__ = ["CASES"]

_PAIR = ContactPair(Material(100e9, 0.3, "elastic flat"), Material.rigid("ball"))
_R, _F = 1e-3, 1.0


def _hertz_scales(pair=_PAIR, radius=_R, force=_F):
    es = pair.effective_modulus
    a = (3 * force * radius / (4 * es)) ** (1 / 3)
    return es, a, 3 * force / (2 * math.pi * a * a)


def _sphere_problem(n: int, a: float, radius: float = _R, span: float = 3.0):
    grid = Grid.square(n, span * a)
    return grid, sphere(grid, radius)


def _hertz_rows(quick: bool) -> list[ValidationRow]:
    es, a, p0 = _hertz_scales()
    n = 64 if quick else 128
    grid, h = _sphere_problem(n, a)
    res = _solve(free_boundary_operator(grid, _PAIR), h, force=_F, interaction=HardnessCap(1.2 * p0), tol=1e-10)
    case = f"hardness_hertz H=1.2 p0 {n}^2"
    return [
        _row(case, "approach against Hertz a^2 / R", a * a / _R, res.approach, 2e-3),
        _row(case, "contact radius against Hertz", a, math.sqrt(res.contact_area / math.pi), grid.dx / a),
        _row(case, "plastic area (none below the cap)", 0.0, res.plastic_area, 0.0),
    ]


def _sphere_rows(quick: bool) -> list[ValidationRow]:
    es, a, p0 = _hertz_scales()
    rows = []
    for n in ((128,) if quick else (128, 256)):
        op = None
        for h_rel in (0.8, 0.5):
            ref = capped_sphere(_R, es, h_rel * p0, force=_F, rings=400)
            grid, h = _sphere_problem(n, a)
            op = op or free_boundary_operator(grid, _PAIR)
            res = _solve(op, h, force=_F, interaction=HardnessCap(h_rel * p0), tol=1e-10)
            case = f"hardness_sphere H={h_rel:g} p0 {n}^2"
            # radii: a node count on the grid and a ring count in the reference
            tol_r = grid.dx / ref.contact_radius
            rows += [
                _row(case, "approach against the axisymmetric capped sphere", ref.approach,
                     res.approach if res.converged else math.nan, 5e-4),
                _row(case, "contact radius against the axisymmetric capped sphere", ref.contact_radius,
                     math.sqrt(res.contact_area / math.pi), tol_r),
                _row(case, "flat-top (p = H) radius against the axisymmetric capped sphere", ref.plastic_radius,
                     math.sqrt(res.plastic_area / math.pi), tol_r),
                _row(case, "largest pressure against H", h_rel * p0, float(res.pressure.max()), 1e-12),
            ]
    return rows


def _rigid_plastic_rows(quick: bool) -> list[ValidationRow]:
    n = 128
    grid = Grid(n, n, 1.0, 1.0, periodic=True)
    s = self_affine_surface(grid, 0.8, rms_slope=1.0, short_cutoff=4 / n, seed=3)
    pair = ContactPair(Material(1.0, 0.3), Material.rigid())
    op = make_operator(grid, pair)
    rows = []
    # the elastic fringe of the spots: measured 2.2 %, 0.40 %, 0.10 % of F / H on this surface
    for ratio, tol in ((10.0, 0.05), (100.0, 0.01), (1000.0, 0.003)):
        H = pair.effective_modulus / ratio
        f = 0.02 * H
        res = _solve(op, s.max() - s, force=f, interaction=HardnessCap(H), tol=1e-10)
        rows.append(_row(f"hardness_rigid_plastic E*/H={ratio:g} {n}^2", "real area against F / H", f / H,
                         res.contact_area if res.converged else math.nan, tol))
    return rows


def _pulloff_rows(quick: bool) -> list[ValidationRow]:
    pair = ContactPair(Material(10e9, 0.0), Material.rigid())
    radius, w, z0, load = 100e-9, 0.1, 0.3e-9, 6e-7
    es, a, p0 = _hertz_scales(pair, radius, load)
    # the elastic pull-off is grid-limited at 128^2 (1 nm cells, the step law): measured +10.6 %,
    # +4.1 % at 256^2 over the same domain, +0.3 % at 256^2 over half of it (the softened law)
    n, span, tol = (128, 8.0, 0.12) if quick else (256, 4.0, 0.01)
    grid, h = _sphere_problem(n, a, radius, span=span)
    op = free_boundary_operator(grid, pair)
    law = build_dugdale(SimpleNamespace(work_of_adhesion=w, z0=z0, discretisation="auto"), LawContext(grid, es))
    elastic = pull_off(op, h, law, preload=load)
    plastic = pull_off(op, h, HardnessCap(0.5 * p0, law), preload=load)
    case = f"hardness_pulloff H=0.5 p0 {n}^2"
    ratio = plastic.force / elastic.force
    return [
        _row(case, "elastic pull-off (the curve's minimum) against Maugis-Dugdale",
             maugis_dugdale_pull_off_force(radius, w, es, z0), elastic.force, tol),
        ValidationRow(case, "pull-off after plastic loading / elastic pull-off (>= 1.5)", 1.5, ratio,
                      max(0.0, (1.5 - ratio) / 1.5), 0.0, bool(ratio >= 1.5)),
    ]


def _subsurface_hertz_rows(quick: bool) -> list[ValidationRow]:
    es, a, p0 = _hertz_scales()
    n = 128 if quick else 256
    grid, h = _sphere_problem(n, a, span=4.0)
    res = _solve(free_boundary_operator(grid, _PAIR), h, force=_F, tol=1e-10)
    nu = _PAIR.body1.nu
    z = np.linspace(0.3, 0.7, 41) * a
    st = subsurface_stress(grid, res.pressure, depths=z, nu=nu)
    c = n // 2
    tau = st.max_shear()[:, c - 1:c + 1, c - 1:c + 1].mean(axis=(1, 2))
    k = int(np.argmax(tau))
    case = f"subsurface_hertz nu={nu:g} {n}^2"
    rows = [_row(case, "largest shear stress on the axis / p0 (Huber: 0.31)", 0.3100, tau[k] / p0, 0.01),
            _row(case, "its depth / a (Huber: 0.48)", 0.48, z[k] / a, 0.03)]
    X, Y = grid.meshgrid()
    R = np.hypot(X, Y)
    for zr in (0.48, 1.0):
        s1 = subsurface_stress(grid, res.pressure, depths=[zr * a], nu=nu)
        hb = huber_stresses(R, zr * a, a, p0, nu)
        cs, sn = X / R, Y / R
        ref = {"xx": hb["rr"] * cs ** 2 + hb["tt"] * sn ** 2, "zz": hb["zz"], "xz": hb["rz"] * cs}
        err = max(float(np.abs(s1.component(q)[0] - v).max()) for q, v in ref.items())
        rows.append(_row(case, f"largest deviation from Huber's field at z = {zr:g} a (xx, zz, xz) / p0", 0.0,
                         err / p0, 0.01, scale=1.0))
    return rows


def _subsurface_sliding_rows(quick: bool) -> list[ValidationRow]:
    nx, ny, L, mu, nu = 8192, 4, 128.0, 0.3, 0.3
    grid = Grid(nx, ny, L, L * ny / nx, periodic=True)
    x = (np.arange(nx) - nx / 2 + 0.5) * grid.dx
    P = np.sqrt(np.clip(1 - x ** 2, 0, None))[:, None] * np.ones((1, ny))
    near = np.abs(x) < 2
    rows = []
    for z in (0.3, 0.78):
        st = subsurface_stress(grid, P, np.stack([mu * P, 0 * P]), depths=[z], nu=nu)
        m = mcewen_stresses(x, z, 1.0, 1.0, mu, nu)
        for q, tol in (("zz", 1e-3), ("xz", 1e-3), ("xx", 5e-3)):
            err = float(np.abs(st.component(q)[0][near, 0] - m[q][near]).max())
            rows.append(_row(f"subsurface_sliding mu={mu:g} z={z:g} a", f"sigma_{q}: largest deviation from McEwen / p0",
                             0.0, err, tol, scale=1.0))
    return rows


def _subsurface_equilibrium_rows(quick: bool) -> list[ValidationRow]:
    n = 128
    grid = Grid(n, n, 1.0, 1.0, periodic=True)
    s = self_affine_surface(grid, 0.8, rms_slope=1.0, short_cutoff=8 / n, seed=5)
    res = _solve(make_operator(grid, _PAIR), s.max() - s, force=0.02 * _PAIR.effective_modulus, tol=1e-10)
    p = res.pressure
    q = np.stack([0.3 * p, -0.1 * p])
    h = 1e-4
    z0 = 0.05
    st = subsurface_stress(grid, p, q, depths=[z0 - h, z0, z0 + h], nu=0.3)
    kx = 2 * np.pi * np.fft.fftfreq(n, grid.dx)[:, None]
    ky = 2 * np.pi * np.fft.fftfreq(n, grid.dy)[None, :]

    def d(f, k):
        return np.fft.ifft2(1j * k * np.fft.fft2(f)).real

    C = {c: st.component(c) for c in ("xx", "yy", "zz", "xy", "xz", "yz")}
    res_x = d(C["xx"][1], kx) + d(C["xy"][1], ky) + (C["xz"][2] - C["xz"][0]) / (2 * h)
    res_z = d(C["xz"][1], kx) + d(C["yz"][1], ky) + (C["zz"][2] - C["zz"][0]) / (2 * h)
    scale = float(np.abs(p).max()) / z0
    case = f"subsurface_equilibrium rough periodic {n}^2"
    return [
        _row(case, "|div sigma|_x / (p_max / z)", 0.0, float(np.abs(res_x).max()) / scale, 1e-4, scale=1.0),
        _row(case, "|div sigma|_z / (p_max / z)", 0.0, float(np.abs(res_z).max()) / scale, 1e-4, scale=1.0),
        _row(case, "plane integral of sigma_zz against -F", -res.force, float(C["zz"][1].sum()) * grid.cell_area, 1e-10),
        _row(case, "plane integral of sigma_xz against -Q_x", -float(q[0].sum()) * grid.cell_area,
             float(C["xz"][1].sum()) * grid.cell_area, 1e-10),
    ]


_SIO2 = (64e9, 0.17)
_SI = (130e9, 0.28)


def _layer_limit_rows(quick: bool) -> list[ValidationRow]:
    from ..elasticity.bodies.layered import layer_factors

    (El, nl), (Es, ns) = _SIO2, _SI
    Gl, Gs = El / (2 * (1 + nl)), Es / (2 * (1 + ns))
    thin = layer_factors([1e-5], nl, ns, Gs / Gl)
    thick = layer_factors([40.0], nl, ns, Gs / Gl)
    r = Gl / Gs
    ref_sub = {"zz": (1 - ns) * r, "L": (1 - ns) * r, "T": r, "xz": 0.5 * (1 - 2 * ns) * r}
    ref_lay = {"zz": 1 - nl, "L": 1 - nl, "T": 1.0, "xz": 0.5 * (1 - 2 * nl)}
    rows = []
    for key in ("zz", "L", "T", "xz"):
        rows.append(_row("layer_limits SiO2 on Si, q t = 1e-5", f"{key} compliance against the substrate's half-space",
                         ref_sub[key], float(np.abs(thin[key][0])), 1e-4))
        rows.append(_row("layer_limits SiO2 on Si, q t = 40", f"{key} compliance against the layer's half-space",
                         ref_lay[key], float(np.abs(thick[key][0])), 1e-12))
    return rows


def _layer_fem_rows(quick: bool) -> list[ValidationRow]:
    from ..elasticity.bodies.layered import layer_factors
    from .layer_fem import fem_layer_compliance

    (El, nl), (Es, ns) = _SIO2, _SI
    Gl, Gs = El / (2 * (1 + nl)), Es / (2 * (1 + ns))
    rows = []
    q = 1.0
    mult = 1 if quick else 2
    # the finite elements' own error: measured 0.3-2.1 % at the finer mesh (first order in the mesh)
    tol = 0.04 if quick else 0.025
    for st in (0.2, 1.0, 3.0):
        f = layer_factors([st], nl, ns, Gs / Gl)
        for load, key in (("normal", "zz"), ("shear", "L")):
            c = fem_layer_compliance(q, st / q, _SIO2, _SI, load, nx=24 * mult, n_layer=12 * mult, n_sub=40 * mult)
            rows.append(_row(f"layer_fem SiO2 on Si, q t = {st:g}", f"{load} compliance: finite elements against "
                             "the potentials' solution", c, float(f[key][0]) / (Gl * q), tol))
    return rows


def _layer_sphere_rows(quick: bool) -> list[ValidationRow]:
    from ..elasticity.bodies.layered import CoatedHalfSpace
    from ..elasticity.operators import periodic_operator

    sub = Material(*_SI)
    probe = Material(*_SIO2)
    radius, force, t = 2.5e-6, 1e-6, 40e-9
    pair = ContactPair(sub, probe, model=CoatedHalfSpace(1, _SIO2[0], _SIO2[1], t))
    n = 96 if quick else 128
    L = 0.2e-6
    free = Grid.square(n, L)
    rf = _solve(free_boundary_operator(free, pair), sphere(free, radius), force=force, tol=1e-10)
    per = Grid.square(4 * n, 4 * L, periodic=True)
    rp = _solve(periodic_operator(per, pair), sphere(per, radius), force=force, tol=1e-10)
    case = f"layer_sphere 40 nm SiO2 on Si, {n}^2 free / {4 * n}^2 periodic"
    rows = [
        _row(case, "contact area, free-boundary against periodic", rp.contact_area, rf.contact_area, 0.005),
        _row(case, "largest pressure, free-boundary against periodic", float(rp.pressure.max()),
             float(rf.pressure.max()), 1e-3),
    ]
    # the load-approach point against the axisymmetric ring solution with the coated kernel's
    # Hankel transform (analytic/capped_sphere.py; no grid, no DC-FFT)
    eref = ContactPair(probe, probe).effective_modulus  # the layer (SiO2) against the SiO2 probe

    def compliance(q):
        return np.real(pair.model.symbol(pair, "zz", q, np.zeros_like(q)))

    ax = capped_sphere(radius, eref, math.inf, force=force, rings=300,
                       influence=coated_ring_influence(compliance, eref, t))
    rows += [
        _row(f"layer_sphere 40 nm SiO2 on Si, {n}^2", "approach against the axisymmetric coated solution",
             ax.approach, rf.approach, 2e-3),
        _row(f"layer_sphere 40 nm SiO2 on Si, {n}^2", "largest pressure against the axisymmetric coated solution",
             float(ax.pressure.max()), float(rf.pressure.max()), 5e-3),
    ]
    return rows


#: The cases of this module, in the order they run: name -> ``rows(quick)``.
CASES: dict[str, Callable[[bool], list[ValidationRow]]] = {
    "hardness_hertz": _hertz_rows,
    "hardness_sphere": _sphere_rows,
    "hardness_rigid_plastic": _rigid_plastic_rows,
    "hardness_pulloff": _pulloff_rows,
    "subsurface_hertz": _subsurface_hertz_rows,
    "subsurface_sliding": _subsurface_sliding_rows,
    "subsurface_equilibrium": _subsurface_equilibrium_rows,
    "layer_limits": _layer_limit_rows,
    "layer_fem": _layer_fem_rows,
    "layer_sphere": _layer_sphere_rows,
}
