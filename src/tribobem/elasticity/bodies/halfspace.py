"""The homogeneous isotropic half-space: every body model's reference (the model of a
:class:`~tribobem.materials.ContactPair` that names none).

Each body is a linear-elastic half-space (G, nu); the two bodies' kernels combine as
:mod:`tribobem.elasticity.operators` describes (normal and in-plane blocks add, the coupling
blocks subtract, a rigid body adds 0).

* Periodic grids: the Boussinesq-Cerruti Fourier kernels (zz = 2/(E* q), the full set in
  :func:`~tribobem.elasticity.operators.periodic_operator`), sampled at the DFT wavevectors
  (``kernel="spectral"``) or summed over aliases with the cell's sincs (``"influence"``).
* Free-boundary grids: Love's closed-form coefficients of a uniformly loaded rectangle
  (:func:`~tribobem.elasticity.influence.lattice_coefficients`).
* Self-compliance: Love's coefficient at zero offset, through E* alone
  (:func:`halfspace_self_compliance`).
* Preconditioner stiffness: |q| (1/K = E* |q| / 2 up to the constant).

The numbers are those of the code before the body models existed, operation for operation.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from ..influence import composite_coefficients, lattice_coefficients
from .base import BodyModel

__all__ = ["HalfSpace", "halfspace_self_compliance"]


def _wavevectors(grid):
    qx = 2.0 * np.pi * np.fft.fftfreq(grid.nx, grid.dx)[:, None]
    qy = 2.0 * np.pi * np.fft.rfftfreq(grid.ny, grid.dy)[None, :]
    return qx, qy


def _body_constants(pair) -> dict:
    """Material factors of the two-body Fourier kernels (1/Pa), see
    :func:`~tribobem.elasticity.operators.periodic_operator`.

    ``n``: sum (1 - nu_i)/G_i = 2/E*; ``t``: sum 1/G_i; ``nu``: sum nu_i/G_i; ``c``: the
    coupling (1 - 2 nu_1)/(2 G_1) - (1 - 2 nu_2)/(2 G_2) = 2 pi C_c.  Rigid bodies give 0.
    """
    elastic = [(m, sign) for m, sign in ((pair.body1, 1.0), (pair.body2, -1.0)) if not m.is_rigid]
    return {
        "n": 2.0 / pair.effective_modulus,
        "t": sum(1.0 / m.shear_modulus for m, _ in elastic),
        "nu": sum(m.nu / m.shear_modulus for m, _ in elastic),
        "c": sum(sign * (1.0 - 2.0 * m.nu) / (2.0 * m.shear_modulus) for m, sign in elastic),
    }


#: Wavevector sums each block needs: S1 = 1/q, Sxx = qx^2/q^3, Syy = qy^2/q^3,
#: Sxy = qx qy/q^3, Sx = qx/q^2, Sy = qy/q^2 (times the cell sincs for kernel="influence").
_BLOCK_SUMS = {"zz": ("S1",), "xx": ("S1", "Sxx"), "yy": ("S1", "Syy"), "xy": ("Sxy",), "yx": ("Sxy",),
               "zx": ("Sx",), "xz": ("Sx",), "zy": ("Sy",), "yz": ("Sy",)}


def _shape_sums(Qx, Qy, weight, names, acc) -> None:
    """Add ``weight`` times the wavevector functions ``names`` at (Qx, Qy) to ``acc``.

    q = 0 can only occur at index [0, 0] (the unaliased zero mode); its value is arbitrary
    here and is set to 0 by the caller.
    """
    Q2 = Qx * Qx + Qy * Qy
    if Q2[0, 0] == 0.0:
        Q2[0, 0] = 1.0
    if any(n in names for n in ("S1", "Sxx", "Syy", "Sxy")):
        w1 = weight / np.sqrt(Q2)                           # weight / q
        if "S1" in names:
            acc["S1"] += w1
        if any(n in names for n in ("Sxx", "Syy", "Sxy")):
            w3 = w1 / Q2                                    # weight / q^3
            if "Sxx" in names:
                acc["Sxx"] += w3 * (Qx * Qx)
            if "Syy" in names:
                acc["Syy"] += w3 * (Qy * Qy)
            if "Sxy" in names:
                acc["Sxy"] += w3 * (Qx * Qy)
    if "Sx" in names or "Sy" in names:
        w2 = weight / Q2                                    # weight / q^2
        if "Sx" in names:
            acc["Sx"] += w2 * Qx
        if "Sy" in names:
            acc["Sy"] += w2 * Qy


def halfspace_self_compliance(dx: float, dy: float, effective_modulus: float) -> float:
    """Love's zz coefficient at zero offset: a dx x dy cell's centre under its own unit pressure.

    w = (4 / (pi E*)) [a asinh(b / a) + b asinh(a / b)] with a = dx/2, b = dy/2 (m/Pa).

    Parameters
    ----------
    dx, dy : float
        Cell size (m).
    effective_modulus : float
        Composite modulus E* of the pair (Pa).

    Returns
    -------
    float
        m/Pa.
    """
    from ...materials import ContactPair, Material

    # the zz coefficient depends on the pair through E* alone: a body of modulus E*, nu = 0
    pair = ContactPair(Material(effective_modulus, 0.0), Material.rigid())
    return float(composite_coefficients("zz", pair, 0.0, 0.0, dx, dy))


@dataclass(frozen=True)
class HalfSpace(BodyModel):
    """Two homogeneous isotropic half-spaces (the default body model; no parameters)."""

    name: ClassVar[str] = "halfspace"

    def periodic_spectra(self, pair, grid, components: tuple, kernel: str = "spectral", n_alias: int = 8) -> dict:
        """The Boussinesq-Cerruti spectra of one periodic cell (m/Pa), host arrays.

        See :func:`~tribobem.elasticity.operators.periodic_operator` for the kernels, and
        :meth:`BodyModel.periodic_spectra` for the arguments.  Blocks that vanish for these
        materials are left out (the coupling of identical bodies, xy/yx when both nu are 0);
        "yx" is the same array as "xy".
        """
        c = _body_constants(pair)
        # blocks that are nonzero for these materials (the coupling vanishes for identical bodies)
        keys = [o + i for o in components for i in components]
        keys = [k for k in keys if not (k in ("zx", "xz", "zy", "yz") and c["c"] == 0.0)
                and not (k in ("xy", "yx") and c["nu"] == 0.0)]
        names = sorted({s for k in keys for s in _BLOCK_SUMS[k]})
        qx, qy = _wavevectors(grid)
        shape = np.broadcast_shapes(qx.shape, qy.shape)
        acc = {s: np.zeros(shape) for s in names}
        if kernel == "spectral":
            _shape_sums(qx, qy, 1.0, names, acc)
        else:
            # Poisson summation: DFT of the periodised piecewise-constant coefficients
            gx, gy = 2.0 * np.pi / grid.dx, 2.0 * np.pi / grid.dy
            Qys = [qy + my * gy for my in range(-n_alias, n_alias + 1)]
            sys_ = [np.sinc(Qy * grid.dy / (2.0 * np.pi)) for Qy in Qys]  # np.sinc(t) = sin(pi t)/(pi t)
            for mx in range(-n_alias, n_alias + 1):
                Qx = qx + mx * gx
                sx = np.sinc(Qx * grid.dx / (2.0 * np.pi))
                for Qy, sy in zip(Qys, sys_):
                    _shape_sums(Qx, Qy, sx * sy, names, acc)
        # the kernels odd in qx (qy) have no Nyquist term: the odd periodic kernel sums to 0 there
        nyq_x = grid.nx // 2 if grid.nx % 2 == 0 else None
        nyq_y = grid.ny // 2 if grid.ny % 2 == 0 else None
        for s in names:
            if nyq_x is not None and s in ("Sxy", "Sx"):
                acc[s][nyq_x, :] = 0.0
            if nyq_y is not None and s in ("Sxy", "Sy"):
                acc[s][:, nyq_y] = 0.0
            acc[s][0, 0] = 0.0  # q = 0: the mean displacement is carried by the rigid shifts
        build = {
            "zz": lambda: c["n"] * acc["S1"],
            "xx": lambda: c["t"] * acc["S1"] - c["nu"] * acc["Sxx"],
            "yy": lambda: c["t"] * acc["S1"] - c["nu"] * acc["Syy"],
            "xy": lambda: -c["nu"] * acc["Sxy"],
            "zx": lambda: -1j * c["c"] * acc["Sx"],
            "xz": lambda: 1j * c["c"] * acc["Sx"],
            "zy": lambda: -1j * c["c"] * acc["Sy"],
            "yz": lambda: 1j * c["c"] * acc["Sy"],
        }
        spectra = {}
        for k in keys:
            if k == "yx" and "xy" in spectra:
                spectra[k] = spectra["xy"]  # the same (real, symmetric) kernel
                continue
            spectra[k] = np.ascontiguousarray(build["xy" if k == "yx" else k]())
        return spectra

    def influence_coefficients(self, pair, key: str, xc, yc) -> np.ndarray:
        """Love's coefficients from their corner lattice
        (:func:`~tribobem.elasticity.influence.lattice_coefficients`); arguments as
        :meth:`BodyModel.influence_coefficients`."""
        return lattice_coefficients(key, pair, xc, yc)

    def self_compliance(self, pair, dx: float, dy: float) -> float:
        """:func:`halfspace_self_compliance` of the pair's E* (m/Pa); arguments as
        :meth:`BodyModel.self_compliance`."""
        return halfspace_self_compliance(dx, dy, pair.effective_modulus)

    def preconditioner_stiffness(self, pair, shape: tuple, dx: float, dy: float) -> np.ndarray:
        """|q| on the box (rad/m): the half-space's stiffness 1/K(q) = E* |q| / 2 up to the
        constant, which a preconditioner does not need (so one M serves every material pair);
        the mean gets the longest wavelength's |q|.  Arguments as
        :meth:`BodyModel.preconditioner_stiffness`."""
        n1, n2 = int(shape[0]), int(shape[1])
        qx = 2.0 * math.pi * np.fft.fftfreq(n1, d=dx)
        qy = 2.0 * math.pi * np.fft.rfftfreq(n2, d=dy)
        q = np.sqrt(qx[:, None] ** 2 + qy[None, :] ** 2)
        # the mean: the longest wavelength's stiffness (the force-balanced CG never uses it)
        q[0, 0] = min(float(qx[1]) if n1 > 1 else math.inf, float(qy[1]) if n2 > 1 else math.inf)
        return q
