"""Columns of a convolution operator in real space: K e_j without an FFT.

``K p`` for a pressure that differs from a known one on a few nodes only is the known
displacement plus a few columns of K.  A column is the real-space kernel (the inverse
transform of the kernel spectrum on ``op.fft_shape``) shifted to node j; on the nx x ny
domain it is two slices per axis of that kernel, so adding ``v K e_j`` to a field costs
about two passes over the grid (no ``np.roll`` copies), against one rfft2 + irfft2 pair for
the whole product.  Used by the Polonsky-Keer solver (solvers/normal.py) when few nodes
change status in an iteration.

* Periodic operator (``fft_shape == grid.shape``): K[x, y; j] = k[(x - jx) mod nx,
  (y - jy) mod ny].
* Free-boundary operator (DC-FFT, ``fft_shape == 2 * grid.shape``): the kernel is the
  2nx x 2ny wrap-around coefficient array; for x >= jx the offset x - jx indexes rows
  0 .. nx - jx - 1, for x < jx rows 2nx - jx .. 2nx - 1 (and likewise in y).

The kernel is computed once per operator (one inverse FFT) and cached on it.
"""

from __future__ import annotations

import numpy as np

from .backend import _pocketfft  # pocketfft's out= transforms, checked (None: the public API)


def convolve(op, traction, out=None, spectrum=None):
    """``op.apply(traction)`` for a single-component operator, leaner with scipy.fft.

    With the NumPy backend and the ``scipy`` FFT engine, the inverse transform is done as
    an in-place inverse FFT along x on the (owned) product spectrum followed by a real
    inverse FFT along y (of the nx rows kept, for the zero-padded free-boundary operator),
    instead of ``irfft2``, which copies the spectrum first: the same arithmetic (equal
    results, tested), less CPU time than ``op.apply`` (figures in benchmarks/README.md) and one
    complex half-spectrum less at the peak.  Other engines and backends: ``op.apply`` (which runs
    the zero-padded operator's lean transforms with every engine of the NumPy backend).

    ``out`` (real, ``grid.shape``) and ``spectrum`` (complex, the rfft2 shape), periodic
    operator only: work buffers reused across calls.  Each transform then writes into them
    (pocketfft's ``out`` argument): no fresh arrays, whose first touch (page faults, zeroing)
    costs a sizeable part of a convolution on large grids; the result is ``out``.  ``out`` must
    not be ``traction``.

    Parameters
    ----------
    op : ConvolutionOperator
        A single-component operator (e.g. ``op.normal``); multi-component ones go to
        ``op.apply``.
    traction : array, shape ``grid.shape``
        Traction (Pa).
    out : ndarray, optional
        Real work array of ``grid.shape`` for the result (not ``traction``).
    spectrum : ndarray, optional
        Complex work array of the rfft2 shape (nx, ny // 2 + 1), overwritten.

    Returns
    -------
    array, shape ``grid.shape``
        Displacement (m): ``out`` when it was given, else a new array.
    """
    be = op.backend
    spec = op.spectra.get("zz") if len(op.components) == 1 else None
    if spec is None or be.name != "numpy" or be.fft != "scipy":
        return op.apply(traction)
    import scipy.fft

    nx, ny = op.grid.nx, op.grid.ny
    Nx, Ny = op.fft_shape
    w = be.threads((Nx, Ny))
    if (out is not None and spectrum is not None and _pocketfft is not None and (Nx, Ny) == (nx, ny)
            and traction.dtype == out.dtype == spec.real.dtype):
        try:
            T = spectrum
            _pocketfft.r2c(traction, (1,), True, 0, T, w)   # rfft along y
            _pocketfft.c2c(T, (0,), True, 0, T, w)          # fft along x, in place
            T *= spec
            _pocketfft.c2c(T, (0,), False, 2, T, w)         # ifft along x (1/nx), in place
            _pocketfft.c2r(T, (1,), Ny, False, 2, out, w)   # irfft along y (1/ny)
            return out
        except TypeError:  # pragma: no cover - another pocketfft signature
            pass
    if (Nx, Ny) != (nx, ny) and be._lean():
        # zero-padded (free boundary): ConvolutionOperator.apply skips the padding rows itself
        u = op.apply(traction)
        if out is not None:
            out[...] = u
            return out
        return u
    T = scipy.fft.rfft2(traction, s=(Nx, Ny), workers=w)
    T *= spec
    scipy.fft.ifft(T, axis=0, overwrite_x=True, workers=w)
    if Nx != nx:
        T = T[:nx]
    u = scipy.fft.irfft(T, n=Ny, axis=1, workers=w)
    if Ny != ny:
        u = u[:, :ny]
    if out is not None:
        out[...] = u
        return out
    return u


def convolve_buffers(op):
    """(out, spectrum) work buffers for :func:`convolve` on ``op``, or (None, None) where
    it would not use them (other engines, backends, the zero-padded operator).

    Parameters
    ----------
    op : ConvolutionOperator
        The operator the buffers are for.

    Returns
    -------
    tuple
        ``(out, spectrum)``: a real ``grid.shape`` array and a complex (nx, ny // 2 + 1) array
        (uninitialised), or ``(None, None)``.
    """
    be = op.backend
    if (_pocketfft is None or be.name != "numpy" or be.fft != "scipy" or len(op.components) != 1
            or tuple(op.fft_shape) != tuple(op.grid.shape) or op.spectra.get("zz") is None):
        return None, None

    nx, ny = op.grid.shape
    return np.empty((nx, ny)), np.empty((nx, ny // 2 + 1), dtype=complex)


class KernelColumns:
    """Adds columns of the single-component operator ``op`` to displacement fields.

    Periodic operator: a column is the flattened kernel rolled by the flat index of the
    node (two contiguous segments), which is right for y >= jy and one row off for y < jy;
    those y (or, when jy > ny/2, the roll by one row less and the y >= jy) are corrected
    with the row difference D[x] = k[x] - k[x - 1] of the kernel: about 3 passes over the
    grid, an order of magnitude cheaper than a convolution (figures in benchmarks/README.md).
    Free-boundary operator: four 2-D slice blocks of the 2nx x 2ny kernel (strided, so slower
    per column than the periodic case).

    Parameters
    ----------
    op : ConvolutionOperator
        A single-component operator (``op.normal``); its kernel (m/Pa per node) is inverted
        once here.
    spectrum : ndarray, optional
        Complex work buffer of the rfft2 shape (see :func:`convolve_buffers`), to invert the
        kernel spectrum without temporaries (periodic operator only).

    Raises
    ------
    ValueError
        When ``op`` has more than one component.
    """

    def __init__(self, op, spectrum=None):
        """``spectrum``: optional complex work buffer of the rfft2 shape (see
        :func:`convolve_buffers`), to invert the kernel spectrum without temporaries."""
        if len(op.components) != 1:
            raise ValueError("KernelColumns needs a single-component operator (use op.normal)")
        spec = op.spectra.get("zz")
        xp = self.xp = op.xp
        self.shape = tuple(op.grid.shape)
        self.fft_shape = tuple(op.fft_shape)
        self.periodic = self.fft_shape == self.shape
        self.kernel = self.rowdiff = None
        if spec is None:
            return
        if spectrum is not None and self.periodic and _pocketfft is not None:
            w = op.backend.workers
            spectrum[...] = spec
            _pocketfft.c2c(spectrum, (0,), False, 2, spectrum, w)
            self.kernel = _pocketfft.c2r(spectrum, (1,), self.fft_shape[1], False, 2, None, w)
        else:
            self.kernel = op.backend.irfft2(spec, s=self.fft_shape)
        if self.periodic:
            k = self.kernel
            D = self.rowdiff = xp.empty_like(k)  # D[x] = k[x] - k[x - 1], no temporaries
            xp.subtract(k[1:], k[:-1], out=D[1:])
            xp.subtract(k[:1], k[-1:], out=D[:1])
    @classmethod
    def of(cls, op, spectrum=None) -> "KernelColumns":
        """The (cached) columns of ``op``.

        Parameters
        ----------
        op : ConvolutionOperator
            A single-component operator; the columns are cached on it (``op.cache.kernel_columns``),
            so the kernel's inverse FFT is done once per operator.
        spectrum : ndarray, optional
            Work buffer passed to the constructor on the first call only.

        Returns
        -------
        KernelColumns
        """
        cols = op.cache.kernel_columns
        if cols is None:
            cols = op.cache.kernel_columns = cls(op, spectrum)
        return cols

    def _blocks(self, j: int, n: int, N: int):
        """(output slice, kernel slice) pairs along one axis for source index j."""
        out = [(slice(j, n), slice(0, n - j))]
        if j > 0:
            out.append((slice(0, j), slice(N - j, N)))
        return out

    def add(self, u, nodes, values, scratch) -> None:
        """u += sum_k values[k] K e_{nodes[k]}, in place.

        Parameters
        ----------
        u : array, shape ``grid.shape``
            Displacement field to update.
        nodes : sequence of int
            Flat (row-major) indices of the source nodes.
        values : sequence of float
            Their pressure increments (Pa).
        scratch : array, shape ``grid.shape``
            Work array (overwritten).
        """
        if self.kernel is None:
            return
        if self.periodic:
            for j, v in zip(nodes, values):
                v = float(v)
                if v != 0.0:
                    self._add_periodic(u, int(j), v, scratch)
            return
        xp, k = self.xp, self.kernel
        nx, ny = self.shape
        Nx, Ny = self.fft_shape
        for j, v in zip(nodes, values):
            v = float(v)
            if v == 0.0:
                continue
            jx, jy = divmod(int(j), ny)
            for xs, ks in self._blocks(jx, nx, Nx):
                for ys, ls in self._blocks(jy, ny, Ny):
                    tmp = scratch[xs, ys]
                    xp.multiply(k[ks, ls], v, out=tmp)
                    o = u[xs, ys]
                    o += tmp

    def _add_periodic(self, u, j: int, v: float, scratch) -> None:
        xp = self.xp
        nx, ny = self.shape
        N = nx * ny
        jx, jy = divmod(j, ny)
        low = 2 * jy <= ny
        s = j if low else (j - ny) % N
        kf, uf, sf = self.kernel.reshape(-1), u.reshape(-1), scratch.reshape(-1)
        # uf[i] += v kf[(i - s) mod N]
        xp.multiply(kf[:N - s], v, out=sf[s:])
        if s:
            xp.multiply(kf[N - s:], v, out=sf[:s])
        uf += sf
        D = self.rowdiff
        if low:
            if jy == 0:
                return
            # y < jy got k[(x - jx - 1) % nx, y - jy + ny]: add v D[(x - jx) % nx, y - jy + ny]
            r0, ys, ls = (-jx) % nx, slice(0, jy), slice(ny - jy, ny)
            sign = v
        else:
            # y >= jy got k[(x - jx + 1) % nx, y - jy]: subtract v D[(x - jx + 1) % nx, y - jy]
            r0, ys, ls = (1 - jx) % nx, slice(jy, ny), slice(0, ny - jy)
            sign = -v
        # output row x uses kernel row (x + r0) % nx
        for xs, ks in ((slice(0, nx - r0), slice(r0, nx)), (slice(nx - r0, nx), slice(0, r0))):
            if xs.start == xs.stop:
                continue
            tmp = scratch[xs, ys]
            xp.multiply(D[ks, ls], sign, out=tmp)
            o = u[xs, ys]
            o += tmp

    def column(self, j: int):
        """K e_j on the grid (a new array), for tests.

        Parameters
        ----------
        j : int
            Flat (row-major) index of the loaded node.

        Returns
        -------
        array, shape ``grid.shape``
            Displacement (m) from a unit pressure (1 Pa) on node j.
        """
        xp = self.xp
        u = xp.zeros(self.shape)
        self.add(u, [j], [1.0], xp.empty(self.shape))
        return u
