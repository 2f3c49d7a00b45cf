"""The body-model protocol: what the elastic operators, solvers and checks need from the bodies.

A body model describes the composite elastic response of the two bodies of a
:class:`~tribobem.materials.ContactPair` (the interface's relative displacement per unit
traction).  It supplies

* :meth:`BodyModel.periodic_spectra` -- the kernel spectra (normal, tangential, coupling) on a
  periodic grid (m/Pa), for :func:`~tribobem.elasticity.operators.periodic_operator`;
* :meth:`BodyModel.influence_coefficients` -- the real-space coefficients of a piecewise-constant
  traction (m/Pa), laid out by :func:`~tribobem.elasticity.operators.free_boundary_operator`
  on its zero-padded DC-FFT grid;
* :meth:`BodyModel.self_compliance` -- a cell's displacement under its own unit pressure (m/Pa),
  for the result checks (:func:`tribobem.output.checks.cell_self_compliance`);
* :meth:`BodyModel.preconditioner_stiffness` -- the shape of the normal stiffness 1/K(q) on a
  periodic box, the settled-phase preconditioner of the Polonsky-Keer CG
  (``tribobem.solvers.normal._stiffness_box``).

The operators and solvers ask the pair's model (:func:`~tribobem.elasticity.bodies.body_model_of`,
``op.body_model``) and do not know its type; everything else they need (NormCG's and TangCG's FFT preconditioners, the box
spectra, the self-compliances of the solvers) they derive from the operator's own spectra.

A model is a frozen (hashable) object holding its own parameters only -- the materials come with
the pair passed to every method -- because the operators' spectra are cached per pair and the
pair carries its model.  A new model subclasses :class:`BodyModel` and either overrides the
methods or supplies its Fourier symbol (:meth:`BodyModel.symbol`), from which the default
:meth:`periodic_spectra` and :meth:`preconditioner_stiffness` are built; it is registered under its
``name`` with :func:`~tribobem.elasticity.bodies.register_body_model`.
"""

from __future__ import annotations

import math
from typing import ClassVar

import numpy as np

from ...errors import InputError

__all__ = ["BodyModel", "ODD_IN_X", "ODD_IN_Y"]

#: Blocks whose kernel is odd in x (y): their DFT vanishes on the Nyquist row (column) of an even
#: grid, as that of any odd periodic kernel does.
ODD_IN_X = ("xy", "yx", "zx", "xz")
ODD_IN_Y = ("xy", "yx", "zy", "yz")


class BodyModel:
    """The composite elastic response of two bodies (base class of the registered models).

    Subclasses set ``name`` (the registry key) and override what they provide; the defaults
    below build a periodic operator from :meth:`symbol` and have no free-boundary coefficients.

    Attributes
    ----------
    name : str
        The model's name in :data:`~tribobem.elasticity.bodies.BODY_MODELS`.
    """

    name: ClassVar[str] = ""

    # -- Fourier symbol (the defaults below are built from it) -------------------------

    def symbol(self, pair, key: str, qx, qy):
        """The continuous Fourier kernel of block ``key`` at the wavevectors (qx, qy) (m/Pa).

        Parameters
        ----------
        pair : ContactPair
            The two bodies' materials.
        key : str
            Block ``out + in``, e.g. ``"zz"`` (u_z from p).
        qx, qy : ndarray
            Wavevector components (rad/m), broadcastable; q = 0 only at index [0, 0], whose value
            is discarded.

        Returns
        -------
        ndarray or None
            The kernel (complex for the odd coupling blocks); None for a block that is zero.
        """
        raise NotImplementedError(f"body model {self.name!r} supplies no Fourier symbol")

    # -- what the operators need ---------------------------------------------------------

    def periodic_spectra(self, pair, grid, components: tuple, kernel: str = "spectral", n_alias: int = 8) -> dict:
        """The rfft2 kernel spectra of one periodic cell (m/Pa), host arrays.

        The default samples :meth:`symbol` at the DFT wavevectors (``kernel="spectral"``) or sums
        it over aliases times the cell's sincs (``kernel="influence"``: the DFT of the periodised
        piecewise-constant coefficients, as :func:`~tribobem.elasticity.operators.periodic_operator`
        describes); the q = 0 mode of every block is 0, the Nyquist row (column) of the blocks odd
        in x (y) is 0.

        Parameters
        ----------
        pair : ContactPair
            The two bodies.
        grid : Grid
            The periodic cell.
        components : tuple of str
            Traction / displacement components, a subset of ("x", "y", "z").
        kernel : {"spectral", "influence"}
            How the continuous kernels become the cell's spectra.
        n_alias : int
            Alias images per direction for ``kernel="influence"``.

        Returns
        -------
        dict
            ``out + in`` -> ndarray of shape (nx, ny // 2 + 1); zero blocks left out.
        """
        qx = 2.0 * np.pi * np.fft.fftfreq(grid.nx, grid.dx)[:, None]
        qy = 2.0 * np.pi * np.fft.rfftfreq(grid.ny, grid.dy)[None, :]
        out = {}
        for key in (o + i for o in components for i in components):
            if kernel == "spectral":
                spec = self._symbol_at(pair, key, qx, qy)
            else:
                gx, gy = 2.0 * np.pi / grid.dx, 2.0 * np.pi / grid.dy
                spec = None
                for mx in range(-n_alias, n_alias + 1):
                    Qx = qx + mx * gx
                    sx = np.sinc(Qx * grid.dx / (2.0 * np.pi))
                    for my in range(-n_alias, n_alias + 1):
                        Qy = qy + my * gy
                        term = self._symbol_at(pair, key, Qx, Qy)
                        if term is None:
                            break
                        term = term * (sx * np.sinc(Qy * grid.dy / (2.0 * np.pi)))
                        spec = term if spec is None else spec + term
                    if spec is None:
                        break
            if spec is None:
                continue
            spec = np.array(np.broadcast_to(spec, (qx.shape[0], qy.shape[1])))
            if grid.nx % 2 == 0 and key in ODD_IN_X:
                spec[grid.nx // 2, :] = 0.0
            if grid.ny % 2 == 0 and key in ODD_IN_Y:
                spec[:, grid.ny // 2] = 0.0
            spec[0, 0] = 0.0  # q = 0: the mean displacement is carried by the rigid shifts
            out[key] = np.ascontiguousarray(spec)
        return out

    def _symbol_at(self, pair, key, qx, qy):
        """:meth:`symbol` with the division warnings of the q = 0 point (index [0, 0]) silenced:
        its value is replaced by the caller."""
        with np.errstate(divide="ignore", invalid="ignore"):
            return self.symbol(pair, key, qx, qy)

    def influence_coefficients(self, pair, key: str, xc, yc) -> np.ndarray:
        """Real-space coefficients of the interface on a regular grid of cells (m/Pa).

        Parameters
        ----------
        pair : ContactPair
            The two bodies.
        key : str
            Block ``out + in``.
        xc, yc : array_like, 1-D
            Corner coordinates (m), ascending and evenly spaced: cell ``(i, j)`` spans
            ``[xc[i], xc[i+1]] x [yc[j], yc[j+1]]`` relative to the loaded cell's centre.

        Returns
        -------
        ndarray, shape (len(xc) - 1, len(yc) - 1)
            Displacement (m) at the cells' centres per unit traction (Pa) on the loaded cell.

        Raises
        ------
        InputError
            The default: the model has no free-boundary coefficients (periodic grids only).
        """
        raise InputError("grid.periodic", f"the body model {self.name!r} has no free-boundary influence "
                                          "coefficients: use a periodic grid")

    def self_compliance(self, pair, dx: float, dy: float) -> float:
        """Displacement (m/Pa) of a cell's centre under a unit pressure on that cell alone.

        The default is the zz influence coefficient at zero offset
        (:meth:`influence_coefficients`), the diagonal of the free-boundary influence matrix.

        Parameters
        ----------
        pair : ContactPair
            The two bodies.
        dx, dy : float
            Cell size (m).

        Returns
        -------
        float
            m/Pa.
        """
        c = self.influence_coefficients(pair, "zz", [-0.5 * dx, 0.5 * dx], [-0.5 * dy, 0.5 * dy])
        return float(c[0, 0])

    def preconditioner_stiffness(self, pair, shape: tuple, dx: float, dy: float) -> np.ndarray:
        """The normal stiffness 1/K_zz(q) on a periodic box, up to a constant factor (rfft2 layout).

        The default is 1/:meth:`symbol` (zz) at the box's wavevectors; the mean (q = 0) gets the
        value of the longest wavelength along either axis.

        Parameters
        ----------
        pair : ContactPair
            The two bodies.
        shape : tuple of int
            The box (n1, n2), nodes.
        dx, dy : float
            Node spacing (m).

        Returns
        -------
        ndarray, shape (n1, n2 // 2 + 1)
            Real, positive (any unit: a preconditioner does not need the constant).
        """
        n1, n2 = int(shape[0]), int(shape[1])
        qx = 2.0 * math.pi * np.fft.fftfreq(n1, d=dx)
        qy = 2.0 * math.pi * np.fft.rfftfreq(n2, d=dy)
        K = np.real(np.asarray(self._symbol_at(pair, "zz", qx[:, None], qy[None, :]), dtype=complex))
        M = np.empty(K.shape)
        M[...] = 1.0 / K
        longest = [M[1, 0]] if n1 > 1 else []
        longest += [M[0, 1]] if n2 > 1 else []
        M[0, 0] = min(longest) if longest else 1.0
        return M
