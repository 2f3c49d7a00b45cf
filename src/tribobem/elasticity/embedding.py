"""The displacement of a whole free-boundary grid from tractions confined to a box of it.

A candidate-set solve (:mod:`tribobem.solvers.candidates`) solves on a box of m1 x m2 nodes
and then needs the displacement of every node of the n1 x n2 grid.  The zero-padded operator
would transform 2n1 x 2n2 points with a kernel spectrum of that size (16 bytes per grid node,
built once).  The offsets between a node of the box and a node of the grid only span
n1 + m1 - 1 rows and n2 + m2 - 1 columns, so a cyclic convolution of that length (rounded up to
a fast FFT length) is already exact: about (1 + m/n)^2 / 4 of the points, a kernel spectrum
made for this box alone, and the traction transformed from its m1 rows only.  The work is laid
out as in :meth:`~tribobem.elasticity.backend.Backend.convolve_padded_blocked` (real FFTs along
y of rows, complex FFTs along x of blocks of columns), so that the only full-size work array is
the n1 x (N2/2 + 1) half-spectrum of the result's rows.
"""

from __future__ import annotations

from concurrent.futures import ThreadPoolExecutor

import numpy as np
import scipy.fft as sfft

from .backend import _pocketfft, default_workers
from .bodies import body_model_of

__all__ = ["box_to_grid"]

#: Points per block of columns / rows of the transforms (1 MB complex blocks).
_BLOCK_POINTS = 1 << 16
#: Coefficients computed per block of the kernel build (per thread).
_KERNEL_BLOCK_POINTS = 1 << 20


def _fft_cols(a, forward: bool, w: int):
    """In-place FFT of ``a`` along its first axis (inverse normalised by 1/N)."""
    if _pocketfft is not None:
        _pocketfft.c2c(a, (0,), forward, 0 if forward else 2, a, w)
    else:
        a[...] = (sfft.fft if forward else sfft.ifft)(a, axis=0, workers=w)


def _lengths(n1, n2, m1, m2):
    return sfft.next_fast_len(n1 + m1 - 1), sfft.next_fast_len(n2 + m2 - 1, real=True)


def _kernel_spectrum(pair, key, n1, n2, m1, m2, i0, j0, dx, dy, N1, N2):
    """FFT (rfft along y, fft along x) of the cyclic kernel of the box at (i0, j0): the
    influence coefficient of offset d (grid node minus box node) at index d mod N."""
    model = body_model_of(pair)
    lo1, hi1 = -(i0 + m1 - 1), n1 - i0  # offsets lo..hi-1 along x
    lo2, hi2 = -(j0 + m2 - 1), n2 - j0
    H = N2 // 2 + 1
    C = np.zeros((N1, H), dtype=complex)
    yc = (np.arange(lo2, hi2 + 1) - 0.5) * dy
    step = max(1, _KERNEL_BLOCK_POINTS // max(N2, 1))

    def block(a):
        b = min(hi1, a + step)
        xc = (np.arange(a, b + 1) - 0.5) * dx
        coeff = model.influence_coefficients(pair, key, xc, yc)  # offsets a..b-1 x lo2..hi2-1
        row = np.zeros((b - a, N2))
        row[:, :hi2] = coeff[:, -lo2:]
        if lo2 < 0:
            row[:, N2 + lo2:] = coeff[:, :-lo2]
        spec = sfft.rfft(row, axis=1)
        # rows of offsets a..b-1 at index d mod N1 (one run each side of 0)
        for s0, s1 in ((max(a, 0), b), (a, min(b, 0))):
            if s1 > s0:
                C[s0 % N1:(s0 % N1) + (s1 - s0)] = spec[s0 - a:s1 - a]
        return None

    starts = list(range(lo1, hi1, step))
    threads = min(default_workers(), 8, len(starts))
    if threads > 1:
        with ThreadPoolExecutor(max_workers=threads) as pool:
            list(pool.map(block, starts))
    else:
        for a in starts:
            block(a)
    if _pocketfft is not None:  # in place: no second array of the spectrum's size
        _pocketfft.c2c(C, (0,), True, 0, C, default_workers())
        return C
    return sfft.fft(C, axis=0, overwrite_x=True, workers=default_workers())


def box_to_grid(op, i0: int, j0: int, traction, out=None) -> np.ndarray:
    """The displacement (m) of every node of ``op``'s grid from a traction on a box of it.

    Parameters
    ----------
    op : ConvolutionOperator
        A single-component free-boundary operator of the whole grid (its pair, grid and cell
        size; its own spectrum is not used).
    i0, j0 : int
        The box's first row and column on the grid.
    traction : ndarray
        Traction (Pa) on the box, shape (m1, m2), zero outside it.
    out : ndarray, optional
        Float64 array of the grid's shape for the result.

    Returns
    -------
    ndarray
        The displacement K t (m) on the whole grid, equal to ``op.apply`` of the traction
        embedded in zeros (to round-off).
    """
    g = op.grid
    n1, n2 = g.nx, g.ny
    t = np.ascontiguousarray(np.asarray(op.backend.to_numpy(traction), dtype=float))
    m1, m2 = t.shape
    N1, N2 = _lengths(n1, n2, m1, m2)
    H = N2 // 2 + 1
    w = default_workers()
    K = _kernel_spectrum(op.pair, "zz", n1, n2, m1, m2, i0, j0, g.dx, g.dy, N1, N2)
    S = sfft.rfft(t, n=N2, axis=1, workers=w)  # m1 x H: the box's rows only
    rows = (np.arange(n1) - i0) % N1  # grid row i is cyclic index i - i0
    R = np.empty((n1, H), dtype=complex)
    cb = max(1, min(H, _BLOCK_POINTS // N1))
    col = np.empty((N1, cb), dtype=complex)
    for c0 in range(0, H, cb):
        k = min(cb, H - c0)
        blk = col[:, :k]
        blk[:m1] = S[:, c0:c0 + k]
        blk[m1:] = 0.0
        _fft_cols(blk, True, w)
        blk *= K[:, c0:c0 + k]
        _fft_cols(blk, False, w)
        R[:, c0:c0 + k] = blk[rows]
    del S, K, col
    u = out if out is not None else np.empty((n1, n2))
    cols = (np.arange(n2) - j0) % N2
    rb = max(1, min(n1, _BLOCK_POINTS // N2))
    for r0 in range(0, n1, rb):
        k = min(rb, n1 - r0)
        u[r0:r0 + k] = sfft.irfft(R[r0:r0 + k], n=N2, axis=1, workers=w)[:, cols]
    return op.xp.asarray(u)
