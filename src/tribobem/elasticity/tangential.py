"""The tangential and coupling blocks of a 3x3 elastic operator (the elasticity of the tangential
solver, :mod:`tribobem.solvers.tangential`).

:class:`TangentialOperator` applies K_tt (shear -> in-plane displacement), K_tz (pressure ->
in-plane displacement) and K_zt (shear -> normal displacement) of a
:class:`~tribobem.elasticity.operators.ConvolutionOperator` with components ("x", "y", "z")
with real FFTs, and provides what TangCG needs on the contact's bounding box: the cyclic
convolution of K_tt on a box of a free-boundary grid (:meth:`TangentialOperator.box_spectra`,
exact for tractions confined to the box) and the FFT preconditioner, the inverse 2x2 symbol of
Strang's circulant approximation of K_tt on a box (:meth:`TangentialOperator.preconditioner_spectra`).
Units: tractions in Pa, displacements in m, spectra of K in m/Pa and of its inverse in Pa/m.
"""

from __future__ import annotations

import numpy as np

from ..errors import InputError
from .backend import single_spectrum, work_array
from .cache import OperatorCache
from .operators import ConvolutionOperator

__all__ = ["TangentialOperator", "tangential_operator"]


class TangentialOperator:
    """The tangential and coupling blocks of a 3x3 operator, applied with real FFTs.

    Parameters
    ----------
    op : ConvolutionOperator
        An operator with components ("x", "y", "z") (free boundary or periodic).

    Attributes
    ----------
    cache : OperatorCache
        This view's own derived data (preconditioner and box spectra, single-precision spectra,
        work arrays; :mod:`tribobem.elasticity.cache`), apart from ``op.cache``.

    Notes
    -----
    ``shear_displacement`` costs two forward and two inverse FFTs; ``from_pressure`` one
    forward and two inverse; ``normal_from_shear`` two forward and one inverse.  Blocks that are
    zero (the coupling of identical materials) are skipped.
    """

    def __init__(self, op: ConvolutionOperator):
        if tuple(op.components) != ("x", "y", "z"):
            raise InputError("operator", "the tangential solver needs an operator with components "
                                         f"('x', 'y', 'z'), got {op.components!r}")
        self.op = op
        self.cache = OperatorCache()
        self.be = op.backend
        self.xp = op.xp
        self.grid = op.grid
        self.shape = op.grid.shape
        self.fft_shape = op.fft_shape
        self.periodic = op.periodic
        self.spec = {k: op.spectra.get(k) for k in ("xx", "xy", "yx", "yy", "xz", "yz", "zx", "zy")}
        self.coupled = any(self.spec[k] is not None for k in ("xz", "yz", "zx", "zy"))
        # Self-compliances (m/Pa) of a cell for x and y shear: the diagonal of K_tt.
        e = self.xp.zeros(self.shape)
        e[0, 0] = 1.0
        ux, _ = self.shear_displacement(e, self.xp.zeros(self.shape))
        _, uy = self.shear_displacement(self.xp.zeros(self.shape), e)
        self.self_compliance = (float(self.be.to_numpy(ux)[0, 0]), float(self.be.to_numpy(uy)[0, 0]))
        # Largest eigenvalue of K_tt (m/Pa): the step bound of the projected gradient.  The
        # restriction of the (circulant) operator to the contact cannot exceed the largest
        # eigenvalue of its 2x2 symbol.
        sx, sy = self.spec["xx"], self.spec["yy"]
        sxy = self.spec["xy"]
        sx = np.abs(self.be.to_numpy(sx)) if sx is not None else 0.0
        sy = np.abs(self.be.to_numpy(sy)) if sy is not None else 0.0
        sxy = np.abs(self.be.to_numpy(sxy)) if sxy is not None else 0.0
        lam = 0.5 * (sx + sy) + np.sqrt(0.25 * (sx - sy) ** 2 + sxy**2)
        self.lipschitz = float(np.max(lam))

    def _crop(self, u):
        return u if self.periodic else u[: self.shape[0], : self.shape[1]]

    def _combine(self, outs: str, ins: str, fields, spectra=None, fft_shape=None, single=False,
                 scratch=False) -> list:
        be = self.be
        spectra = self.spec if spectra is None else spectra
        boxed = fft_shape is not None
        fft_shape = self.fft_shape if fft_shape is None else fft_shape
        if be._lean() and not self.periodic:
            return self._combine_padded(outs, ins, fields, spectra, fft_shape, single and be.single_precision,
                                        scratch)
        F = {c: be.rfft2(f, s=fft_shape) for c, f in zip(ins, fields) if f is not None}
        res = []
        for o in outs:
            acc = self._product(o, F, spectra)
            if acc is None:
                res.append(None)
            else:
                u = be.irfft2(acc, s=fft_shape)
                res.append(u if boxed else self._crop(u))
        return res

    def _product(self, o: str, F: dict, spectra: dict):
        """sum_c F[c] x spectra[o + c] (None when every block is zero), accumulated in two reused
        spectral buffers: a fresh multi-MB array per product costs page faults (glibc returns
        large blocks to the OS on free) comparable to the FFTs themselves."""
        xp = self.xp
        acc = None
        for c, T in F.items():
            spec = spectra.get(o + c)
            if spec is None:
                continue
            if acc is None:
                acc = self._work(0, T.shape, T.dtype)
                xp.multiply(T, spec, out=acc)
            else:
                tmp = self._work(1, T.shape, T.dtype)
                xp.multiply(T, spec, out=tmp)
                acc += tmp
        return acc

    def _combine_padded(self, outs, ins, fields, spectra, fft_shape, single=False, scratch=False) -> list:
        """``_combine`` for zero-padded (free-boundary or box) transforms, lean (pocketfft, every
        engine): the transforms of :meth:`Backend.rfft2_padded` and :meth:`Backend.irfft2_rows`
        (the padding rows skipped, no fresh spectra: every array reused), results m1 x m2 as the
        inputs (float32 with ``single``: single-precision transforms and spectra; ``scratch``: in reused
        work arrays, valid until the next call)."""
        be = self.be
        m1, m2 = next(f for f in fields if f is not None).shape
        shp = (fft_shape[0], fft_shape[1] // 2 + 1)
        if single:
            spectra = {k: single_spectrum(self, (tuple(fft_shape), k), v) for k, v in spectra.items()}
        F = {}
        for k, (c, f) in enumerate(zip(ins, fields)):
            if f is not None:
                F[c] = be.rfft2_padded(f, fft_shape, out=self._work(10 + k, shp, np.complex64 if single else complex),
                                       single=single)
        res = []
        real = np.float32 if single else np.float64
        for i, o in enumerate(outs):
            acc = self._product(o, F, spectra)
            if acc is None:
                res.append(None)
            else:
                out = self._work(30 + i, (m1, fft_shape[1]), real) if scratch else None
                u = be.irfft2_rows(acc, fft_shape, m1, out=out)
                res.append(u[:, :m2])
        return res

    def _work(self, i: int, shape, dtype):
        """Reused spectral work array number ``i`` (its content is overwritten by the caller)."""
        return work_array(self, i, shape, dtype, self.xp)

    def shear_displacement(self, qx, qy):
        """In-plane relative displacement from the shear: K_tt q.

        Parameters
        ----------
        qx, qy : array
            Shear tractions (Pa), shape ``grid.shape``.

        Returns
        -------
        tuple of array
            (u_x, u_y) in m, shape ``grid.shape`` (zeros for a zero block).
        """
        ux, uy = self._combine("xy", "xy", (qx, qy))
        z = self.xp.zeros(self.shape)
        return (z if ux is None else ux), (z if uy is None else uy)

    def _kernel(self, key):
        """Real-space kernel (m/Pa) of the block ``key`` on the FFT grid (not kept: at 2048^2 the
        three padded kernels would hold 384 MB; they are needed once per box shape)."""
        spec = self.spec.get(key)
        if spec is None:
            return None
        return np.asarray(self.be.to_numpy(self.be.irfft2(spec, s=self.fft_shape)), dtype=float)

    def preconditioner_spectra(self, box) -> dict:
        """Spectra of the FFT preconditioner M of K_tt on a periodic box of cells.

        M is the inverse, wavevector by wavevector, of the 2x2 symbol of Strang's circulant
        approximation of K_tt on the box (cached per box shape).

        Parameters
        ----------
        box : tuple of int
            (m1, m2), the box size in cells.

        Returns
        -------
        dict
            rfft2 spectra (Pa/m) of shape (m1, m2 // 2 + 1) under the keys "xx", "yy" and,
            when the off-diagonal block is not zero, "xy" = "yx".

        Notes
        -----
        The kernels of K_tt are cut to the offsets |d| <= m/2 of the box and wrapped onto it (at
        an even m the two offsets +-m/2 fall on one cell and get their mean, which keeps the
        symmetries: xx, yy even, xy = yx odd in x and in y, so the symbol is real and
        symmetric); on a periodic operator with the box = the grid that is the operator itself.
        Modes where the symbol is not positive definite (q = 0 of a periodic cell) get m0 I, m0
        the smallest eigenvalue of M over the others (the stiffness of the longest wavelength),
        as the normal preconditioner of :mod:`tribobem.solvers.normal_cg` does.
        """
        box = (int(box[0]), int(box[1]))
        cache = self.cache.preconditioner_spectra
        if box in cache:
            return cache[box]
        N1, N2 = self.fft_shape

        def offsets(m, N):
            """Kernel indices of the box cells 0..m-1 (offsets 0..m//2, then negative)."""
            d = np.arange(m)
            return np.where(d <= m // 2, d, d - m) % N

        def wrap(k):
            if k is None:
                # a block the operator leaves out (xy when both nu are 0): a zero *spectrum*,
                # the rfft2 shape of the box, like the blocks that are present
                return np.zeros((box[0], box[1] // 2 + 1))
            m1, m2 = box
            i1, i2 = offsets(m1, N1), offsets(m2, N2)
            kb = k[np.ix_(i1, i2)].copy()
            # even box: the offsets +m/2 and -m/2 share a cell (mean of the two)
            if m1 % 2 == 0 and m1 < N1:
                kb[m1 // 2, :] = 0.5 * (k[m1 // 2, i2] + k[(-(m1 // 2)) % N1, i2])
            if m2 % 2 == 0 and m2 < N2:
                col = 0.5 * (k[np.ix_(i1, [m2 // 2])] + k[np.ix_(i1, [(-(m2 // 2)) % N2])])[:, 0]
                if m1 % 2 == 0 and m1 < N1:
                    col[m1 // 2] = 0.25 * (k[m1 // 2, m2 // 2] + k[-(m1 // 2) % N1, m2 // 2]
                                           + k[m1 // 2, -(m2 // 2) % N2] + k[-(m1 // 2) % N1, -(m2 // 2) % N2])
                kb[:, m2 // 2] = col
            return np.real(np.fft.rfft2(kb))

        kxx, kyy, kxy = wrap(self._kernel("xx")), wrap(self._kernel("yy")), wrap(self._kernel("xy"))
        det = kxx * kyy - kxy * kxy
        tr = kxx + kyy
        scale = float(np.max(np.abs(tr)))
        good = (kxx > 0) & (kyy > 0) & (det > 1e-12 * scale * scale)
        mxx, myy, mxy = np.zeros(kxx.shape), np.zeros(kxx.shape), np.zeros(kxx.shape)
        mxx[good] = kyy[good] / det[good]
        myy[good] = kxx[good] / det[good]
        mxy[good] = -kxy[good] / det[good]
        # smallest eigenvalue of M over the good modes: 1 / (largest eigenvalue of K)
        lam_max = 0.5 * tr[good] + np.sqrt(0.25 * (kxx[good] - kyy[good]) ** 2 + kxy[good] ** 2)
        m0 = float(1.0 / lam_max.max()) if lam_max.size else 1.0
        mxx[~good] = m0
        myy[~good] = m0
        mxy[~good] = 0.0
        be = self.be
        pre = {"xx": be.asarray(mxx), "yy": be.asarray(myy)}
        if np.any(mxy != 0.0):
            pre["xy"] = pre["yx"] = be.asarray(mxy)
        cache[box] = pre
        return pre

    def precondition(self, rx, ry):
        """Apply the preconditioner M (see :meth:`preconditioner_spectra`) on a box.

        Parameters
        ----------
        rx, ry : array
            Residuals (m, slip) on a box of (m1, m2) cells, the box taken periodic (float32:
            applied in single precision where the backend supports it).

        Returns
        -------
        tuple of array
            (z_x, z_y) = M (r_x, r_y) in Pa, shape (m1, m2): two forward and two inverse FFTs of
            the box.
        """
        box = tuple(rx.shape)
        spec = self.preconditioner_spectra(box)
        be = self.be
        if rx.dtype == np.float32 and be.single_precision:
            # single-precision residuals: single-precision transforms and spectra
            spec = {k: single_spectrum(self, ("preconditioner", box, k), v) for k, v in spec.items()}
        if be._lean():
            return self._precondition_lean(rx, ry, box, spec)
        Rx, Ry = be.rfft2(rx, s=box), be.rfft2(ry, s=box)
        if "xy" in spec:
            Zx = Rx * spec["xx"] + Ry * spec["xy"]
            Zy = Rx * spec["yx"] + Ry * spec["yy"]
        else:
            Zx, Zy = Rx * spec["xx"], Ry * spec["yy"]
        return be.irfft2(Zx, s=box), be.irfft2(Zy, s=box)

    def _precondition_lean(self, rx, ry, box, spec):
        """:meth:`precondition`, lean (pocketfft, every engine): the same transforms
        (:meth:`Backend.rfft2_into`, :meth:`Backend.irfft2_into`: the same numbers) into reused
        spectra and fields instead of six fresh arrays per call (the preconditioner runs at every
        TangCG step).  The fields returned are work arrays, valid until the next call."""
        be, xp = self.be, self.xp
        single = rx.dtype == np.float32
        ctype = np.complex64 if single else complex
        shp = (box[0], box[1] // 2 + 1)
        Rx = be.rfft2_into(rx, self._work(20, shp, ctype))
        Ry = be.rfft2_into(ry, self._work(21, shp, ctype))
        Zx = self._work(22, shp, ctype)
        if "xy" in spec:
            Zy = self._work(23, shp, ctype)
            xp.multiply(Rx, spec["xx"], out=Zx)
            xp.multiply(Ry, spec["xy"], out=Zy)
            Zx += Zy
            xp.multiply(Ry, spec["yy"], out=Zy)
            xp.multiply(Rx, spec["yx"], out=Rx)
            Zy += Rx
        else:
            xp.multiply(Rx, spec["xx"], out=Zx)
            Zy = xp.multiply(Ry, spec["yy"], out=Ry)
        real = np.float32 if single else np.float64
        return be.irfft2_into(Zx, box, self._work(24, box, real)), be.irfft2_into(Zy, box, self._work(25, box, real))

    def box_spectra(self, box) -> tuple | None:
        """FFT shape and spectra of K_tt for tractions confined to a box of a free-boundary grid.

        Parameters
        ----------
        box : tuple of int
            (m1, m2), the box size in cells.

        Returns
        -------
        tuple or None
            ``((N1, N2), spectra)``: the transform shape, N >= 2m - 1 per axis, and the rfft2
            spectra (m/Pa) of K_tt on it (keys "xx", "yy", "xy", "yx"; missing blocks are zero),
            cached per transform shape; None for a periodic operator.

        Notes
        -----
        The linear convolution of tractions on the box, read on the box, needs the kernel at the
        offsets |d| <= m - 1 only, so a cyclic convolution of N >= 2m - 1 points per axis is exact
        (the padded operator uses N = 2n for the whole grid): the same numbers as the padded
        operator at (N1 N2) / (4 nx ny) of its FFT size.  A periodic operator has no box
        spectra: the cyclic convolution of the whole cell is the operator itself.
        """
        if self.periodic:
            return None
        import scipy.fft

        N = tuple(scipy.fft.next_fast_len(2 * int(m) - 1, real=True) for m in box)
        # Cached per transform shape N, not per box: the kernel is laid out for every offset
        # |d| <= (N - 1) // 2, which serves every box with 2m - 1 <= N (the contact's box changes
        # by a node or two along a path; its N rarely does).
        cache = self.cache.box_spectra
        if N in cache:
            return cache[N]
        F1, F2 = self.fft_shape
        spectra = {}
        for key in ("xx", "xy", "yx", "yy"):
            k = self._kernel(key)
            if k is None:
                continue
            h1 = min((N[0] - 1) // 2, F1 // 2 - 1)
            h2 = min((N[1] - 1) // 2, F2 // 2 - 1)
            d1 = np.arange(-h1, h1 + 1)
            d2 = np.arange(-h2, h2 + 1)
            kb = np.zeros(N)
            kb[np.ix_(d1 % N[0], d2 % N[1])] = k[np.ix_(d1 % F1, d2 % F2)]
            spec = np.fft.rfft2(kb)
            if np.abs(spec.imag).max() <= 1e-12 * max(np.abs(spec.real).max(), 1e-300):
                # even or odd-odd kernels: real symbols, kept complex with zero imaginary parts
                # (the same products; NumPy multiplies complex by complex faster than by real)
                spec = spec.real.astype(complex)
            spectra[key] = self.be.asarray(spec)
        if len(cache) >= 8:  # keep the latest transform shapes only
            cache.pop(next(iter(cache)))
        cache[N] = (N, spectra)
        return cache[N]

    def box_shear_displacement(self, qx, qy, single: bool = False, scratch: bool = False):
        """K_tt q on a box of a free-boundary grid, for a shear that vanishes outside the box.

        Parameters
        ----------
        qx, qy : array
            Shear tractions (Pa) on a box of (m1, m2) cells.
        single : bool
            Single-precision transforms (float32 results, relative error ~1e-7; for the images
            of TangCG's search directions) where the backend supports them
            (``Backend.single_precision``).
        scratch : bool
            Return the displacements in work arrays of the operator, overwritten by its next
            call (for a caller that reads them at once, as TangCG does).

        Returns
        -------
        tuple of array
            (u_x, u_y) in m on the same box (exact, see :meth:`box_spectra`): two forward and
            two inverse FFTs of the box's transform size.
        """
        box = tuple(qx.shape)
        N, spec = self.box_spectra(box)
        ux, uy = self._combine("xy", "xy", (qx, qy), spectra=spec, fft_shape=N, single=single, scratch=scratch)
        z = self.xp.zeros(box)
        return (z if ux is None else ux[: box[0], : box[1]]), (z if uy is None else uy[: box[0], : box[1]])

    def from_pressure(self, p):
        """In-plane relative displacement from the pressure: the coupling K_tz p.

        Parameters
        ----------
        p : array
            Pressure (Pa), shape ``grid.shape``.

        Returns
        -------
        tuple of array
            (u_x, u_y) in m, shape ``grid.shape`` (zeros for identical materials).
        """
        ux, uy = self._combine("xy", "z", (p,))
        z = self.xp.zeros(self.shape)
        return (z if ux is None else ux), (z if uy is None else uy)

    def normal_from_shear(self, qx, qy):
        """Normal relative displacement from the shear: K_zx q_x + K_zy q_y.

        Parameters
        ----------
        qx, qy : array
            Shear tractions (Pa), shape ``grid.shape``.

        Returns
        -------
        array
            Normal displacement (m, into the bodies), shape ``grid.shape`` (zeros for identical
            materials).
        """
        (uz,) = self._combine("z", "xy", (qx, qy))
        return self.xp.zeros(self.shape) if uz is None else uz


def tangential_operator(op: ConvolutionOperator) -> TangentialOperator:
    """The :class:`TangentialOperator` view of a 3x3 operator, cached on the operator
    (``op.cache.tangential``).

    Parameters
    ----------
    op : ConvolutionOperator
        Operator with components ("x", "y", "z").

    Returns
    -------
    TangentialOperator
        The same object for every call with the same operator.

    Raises
    ------
    InputError
        When ``op`` does not have the components ("x", "y", "z").
    """
    view = op.cache.tangential
    if view is None:
        view = op.cache.tangential = TangentialOperator(op)
    return view
