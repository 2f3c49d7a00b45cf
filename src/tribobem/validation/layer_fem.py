"""An independent finite-element reference for the coated half-space's surface compliances.

Plane strain, one half wavelength of a sinusoidal surface traction (scikit-fem, quadratic
quadrilaterals): the layer (thickness t) on the substrate, truncated at a depth of two
wavelengths and clamped there (the field decays as exp(-2 pi z / lambda): 4e-6 at the bottom).
Symmetry planes at x = 0 and x = lambda / 2: for the pressure p cos(q x), u_x = 0 there; for the
shear q cos(q x), u_z = 0 there.  The surface displacement at x = 0 divided by the amplitude of
the load is the compliance C(q) (m/Pa), against :func:`tribobem.elasticity.bodies.layered.layer_factors`.

scikit-fem is an optional dependency of the validation (``pip install scikit-fem``).
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["fem_layer_compliance"]


def fem_layer_compliance(q: float, thickness: float, layer: tuple, substrate: tuple, load: str = "normal",
                         nx: int = 24, n_layer: int = 12, n_sub: int = 40) -> float:
    """Surface compliance of a coated half-space under a sinusoidal load, by finite elements.

    Parameters
    ----------
    q : float
        Wavenumber (rad/m).
    thickness : float
        Layer thickness t (m).
    layer, substrate : tuple
        (E, nu) of the layer and of the substrate (Pa, -).
    load : {"normal", "shear"}
        p cos(q x) (compliance u_z / p) or a shear q cos(q x) along x (u_x / q).
    nx, n_layer, n_sub : int
        Elements across the half wavelength, in the layer and in the substrate (graded).

    Returns
    -------
    float
        The compliance at the wavenumber (m/Pa).
    """
    from skfem import Basis, BilinearForm, ElementQuad2, ElementVector, FacetBasis, LinearForm, MeshQuad, asm
    from skfem import condense, solve
    from skfem.helpers import ddot, sym_grad, trace

    lam_w = 2.0 * math.pi / q
    depth = 2.0 * lam_w
    xs = np.linspace(0.0, 0.5 * lam_w, nx + 1)
    yl = -np.linspace(0.0, thickness, n_layer + 1)
    # substrate: graded from the interface down
    g = np.linspace(0.0, 1.0, n_sub + 1) ** 2
    ys_sub = -(thickness + (depth - thickness) * g[1:])
    ys = np.sort(np.concatenate([yl, ys_sub]))
    mesh = MeshQuad.init_tensor(xs, ys)
    e = ElementVector(ElementQuad2())
    basis = Basis(mesh, e, intorder=4)

    def lame(E, nu):
        G = E / (2 * (1 + nu))
        return 2 * G * nu / (1 - 2 * nu), G

    lam_l, mu_l = lame(*layer)
    lam_s, mu_s = lame(*substrate)

    @BilinearForm
    def stiffness(u, v, w):
        in_layer = -w.x[1] < thickness
        lam = np.where(in_layer, lam_l, lam_s)
        mu = np.where(in_layer, mu_l, mu_s)
        eu, ev = sym_grad(u), sym_grad(v)
        return 2.0 * mu * ddot(eu, ev) + lam * trace(eu) * trace(ev)

    top = mesh.facets_satisfying(lambda x: np.abs(x[1]) < 1e-12 * depth)
    fb = FacetBasis(mesh, e, facets=top, intorder=6)

    @LinearForm
    def traction(v, w):
        c = np.cos(q * w.x[0])
        if load == "normal":
            return -c * v[1]   # p cos(q x) pushing into the body (-y)
        return c * v[0]        # shear cos(q x) along +x

    K = asm(stiffness, basis)
    f = asm(traction, fb)
    bottom = basis.get_dofs(lambda x: np.abs(x[1] + depth) < 1e-9 * depth)
    sides = basis.get_dofs(lambda x: (np.abs(x[0]) < 1e-12 * lam_w) | (np.abs(x[0] - 0.5 * lam_w) < 1e-12 * lam_w))
    comp = "u^1" if load == "normal" else "u^2"
    fixed = np.concatenate([bottom.all(), sides.nodal[comp]])
    u = solve(*condense(K, f, D=np.unique(fixed)))
    probe = basis.probes(np.array([[0.0], [0.0]]))
    ux, uy = (probe @ u).reshape(2) if probe.shape[0] == 2 else (probe @ u)[:2]
    return float(-uy) if load == "normal" else float(ux)
