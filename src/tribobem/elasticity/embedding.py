"""The displacement of a whole free-boundary grid from tractions confined to a box of it.

A candidate-set solve (:mod:`tribobem.solvers.candidates`) solves on a box of m1 x m2 nodes
and then needs the displacement of every node of the n1 x n2 grid.  The zero-padded operator
would transform 2n1 x 2n2 points with a kernel spectrum of that size (16 bytes per grid node,
built once).  The offsets between a node of the box and a node of the grid lie within
+-N/2 for N = 2 max(n - i0 - 1, i0 + m - 1) (about n + m for a box near the centre), so a
cyclic convolution of period N1 x N2 (even fast lengths) is already exact: about
(1 + m/n)^2 / 4 of the points.  The kernel is even in x and in y, so its spectrum is real and
even: one quadrant of it, (N1/2 + 1)(N2/2 + 1) values, the DCT-I of one quadrant of the
influence coefficients (2-3 bytes per grid node, and a quarter of the coefficients to compute).
The traction is transformed from its m1 rows only.  The work is laid
out as in :meth:`~tribobem.elasticity.backend.Backend.convolve_padded_blocked` (real FFTs along
y of rows, complex FFTs along x of blocks of columns), so that the only full-size work array is
the n1 x (N2/2 + 1) half-spectrum of the result's rows.
"""

from __future__ import annotations

from concurrent.futures import ThreadPoolExecutor

import numpy as np
import scipy.fft as sfft

from .._fft import default_workers
from .._fft import pocketfft as _pocketfft
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


def _lengths(n1, n2, m1, i0, j0, m2):
    """Even fast FFT lengths N with N/2 >= every |offset| between a box node and a grid node."""
    need1 = max(n1 - i0 - 1, i0 + m1 - 1, 1)
    need2 = max(n2 - j0 - 1, j0 + m2 - 1, 1)
    return 2 * sfft.next_fast_len(need1), 2 * sfft.next_fast_len(need2)


def _even_spectrum(pair, key, N1, N2, dx, dy):
    """The spectrum of the even cyclic kernel of period N1 x N2 (the coefficient of offset
    (a, b) at index (a mod N1, b mod N2) for |a| <= N1/2, |b| <= N2/2), for frequencies
    0..N1/2 x 0..N2/2: real, and even in the frequency, so that these (N1/2 + 1)(N2/2 + 1)
    values are the whole spectrum.  It is the DCT-I of the coefficients of one quadrant of
    offsets (the kernel is even in x and in y: the cell is centred on its node)."""
    model = body_model_of(pair)
    h1, h2 = N1 // 2, N2 // 2
    Q = np.empty((h1 + 1, h2 + 1))
    yc = (np.arange(0, h2 + 2) - 0.5) * dy
    step = max(1, _KERNEL_BLOCK_POINTS // (h2 + 1))

    def block(a):
        b = min(h1 + 1, a + step)
        xc = (np.arange(a, b + 1) - 0.5) * dx
        Q[a:b] = model.influence_coefficients(pair, key, xc, yc)

    starts = list(range(0, h1 + 1, step))
    threads = min(default_workers(), 8, len(starts))
    if threads > 1:
        with ThreadPoolExecutor(max_workers=threads) as pool:
            list(pool.map(block, starts))
    else:
        for a in starts:
            block(a)
    w = default_workers()
    Q = sfft.dct(Q, type=1, axis=1, overwrite_x=True, workers=w)
    return sfft.dct(Q, type=1, axis=0, overwrite_x=True, workers=w)


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
        Float64 host array of the grid's shape for the result.

    Returns
    -------
    numpy.ndarray
        The displacement K t (m) on the whole grid, on the host (a result's field), equal to
        ``op.apply`` of the traction embedded in zeros (to round-off).
    """
    g = op.grid
    n1, n2 = g.nx, g.ny
    t = np.ascontiguousarray(np.asarray(op.backend.to_numpy(traction), dtype=float))
    m1, m2 = t.shape
    N1, N2 = _lengths(n1, n2, m1, i0, j0, m2)
    H = N2 // 2 + 1
    w = default_workers()
    K = _even_spectrum(op.pair, "zz", N1, N2, g.dx, g.dy)  # (N1/2 + 1) x H, real
    fold = np.minimum(np.arange(N1), N1 - np.arange(N1))  # frequency f1 is N1 - f1's
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
        blk *= K[fold, c0:c0 + k]
        _fft_cols(blk, False, w)
        R[:, c0:c0 + k] = blk[rows]
    del S, K, col
    u = out if out is not None else np.empty((n1, n2))
    cols = (np.arange(n2) - j0) % N2
    rb = max(1, min(n1, _BLOCK_POINTS // N2))
    for r0 in range(0, n1, rb):
        k = min(rb, n1 - r0)
        u[r0:r0 + k] = sfft.irfft(R[r0:r0 + k], n=N2, axis=1, workers=w)[:, cols]
    return u
