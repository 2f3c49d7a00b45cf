"""Statistics of surface topographies (heights in m on a :class:`~tribobem.grid.Grid`).

All functions take ``(h, grid)`` with ``h`` an array of heights (m) indexed ``[ix, iy]`` of
shape ``grid.shape``. Heights are measured about their mean wherever a moment is computed.

Derivatives
-----------
Slopes and curvatures depend on how the derivative is discretised. The default follows the
grid:

* ``grid.periodic is True``: spectral (Fourier) derivatives, evaluated through Parseval's
  theorem, ``<|grad h|^2> = sum_q |q|^2 |h_q|^2 / N^2``. The Nyquist modes are included with
  ``|q| = pi/dx``. For a sampled sinusoid of amplitude ``A`` and wavenumber ``k`` below
  Nyquist this gives exactly ``A k / sqrt(2)``.
* ``grid.periodic is False``: one-sided (forward) finite differences between neighbouring
  cells, ``sqrt(<(dh/dx)^2> + <(dh/dy)^2>)`` with each mean taken over the ``(nx-1) x ny``
  resp. ``nx x (ny-1)`` differences. This is the convention of SurfaceTopography's
  ``rms_gradient`` (and so of the values quoted in the topography README). Central
  differences, which cancel the Nyquist mode and read 5-11 % lower on real AFM scans, are
  available with ``method="central"``.

PSD convention
--------------
With ``h_q = dx dy sum_x h(x) exp(-i q.x)`` and ``A = lx ly``, ``C(q) = |h_q|^2 / A`` (m^4), so
that ``rms^2 = integral C(q) d^2q / (2 pi)^2 = sum_q C(q) dqx dqy / (2 pi)^2`` exactly
(Parseval, mean removed). The isotropic average :func:`psd` keeps this normalisation:
``rms^2 ~= sum_bins C(q_b) 2 pi q_b dq / (2 pi)^2`` (the approximation is only the counting
of lattice points per annulus).
"""

from __future__ import annotations

import math

import numpy as np
import scipy.fft as sfft

from ..errors import InputError
from ..grid import Grid

__all__ = [
    "rms_height",
    "rms_slope",
    "rms_curvature",
    "skewness",
    "kurtosis",
    "psd",
    "acf",
    "correlation_length",
    "summary",
]

_SLOPE_METHODS = ("spectral", "forward", "central")


# ----------------------------------------------------------------------------- helpers
def _check(h, grid: Grid | None = None, field: str = "heights") -> np.ndarray:
    """Return ``h`` as a float array after checking its shape against ``grid``."""
    h = np.asarray(h, dtype=float)
    if h.ndim != 2:
        raise InputError(field, f"expected a 2D array of heights, got {h.ndim} dimension(s)")
    if grid is not None and h.shape != grid.shape:
        raise InputError(field, f"array shape {h.shape} does not match the grid {grid.shape}")
    return h


def _wavevectors(grid: Grid) -> tuple[np.ndarray, np.ndarray]:
    """Angular wavevectors (rad/m) of the ``rfft2`` half spectrum, shapes (nx, 1), (1, ny//2+1)."""
    qx = 2 * np.pi * sfft.fftfreq(grid.nx, grid.dx)
    qy = 2 * np.pi * sfft.rfftfreq(grid.ny, grid.dy)
    if grid.nx % 2 == 0:  # Nyquist taken positive: |q| = pi/dx (sign irrelevant for |q|^2)
        qx[grid.nx // 2] = np.pi / grid.dx
    return qx[:, None], qy[None, :]


def _rfft_weights(ny: int) -> np.ndarray:
    """Multiplicity of each ``rfft`` column in the full spectrum (1 or 2), shape (1, ny//2+1)."""
    w = np.full(ny // 2 + 1, 2.0)
    w[0] = 1.0
    if ny % 2 == 0:
        w[-1] = 1.0
    return w[None, :]


def _spectral_moment(h: np.ndarray, grid: Grid, power: int) -> float:
    """``<|q|^(2 power) |h_q|^2>`` normalised so that power=0 gives the variance."""
    hq = sfft.rfft2(h - h.mean())
    qx, qy = _wavevectors(grid)
    q2 = qx**2 + qy**2
    n = h.size
    return float(np.sum(_rfft_weights(grid.ny) * q2**power * np.abs(hq) ** 2) / n**2)


def _method(method: str | None, grid: Grid) -> str:
    if method is None:
        return "spectral" if grid.periodic else "forward"
    if method not in _SLOPE_METHODS:
        raise InputError("stats.method", f"must be one of {_SLOPE_METHODS} or None, got {method!r}")
    return method


# ----------------------------------------------------------------------------- scalars
def rms_height(h, grid: Grid | None = None) -> float:
    """Root-mean-square height about the mean.

    Parameters
    ----------
    h : array_like, shape (nx, ny)
        Heights (m).
    grid : Grid, optional
        Only used to check the shape.

    Returns
    -------
    float
        ``sqrt(<(h - <h>)^2>)`` (m).
    """
    h = _check(h, grid)
    return float(np.sqrt(np.mean((h - h.mean()) ** 2)))


def rms_slope(h, grid: Grid, method: str | None = None) -> float:
    """Root-mean-square gradient ``sqrt(<|grad h|^2>)`` (dimensionless).

    Parameters
    ----------
    h : array_like, shape (nx, ny)
        Heights (m).
    grid : Grid
        Grid of ``h`` (cell sizes in m, periodicity).
    method : {None, "spectral", "forward", "central"}
        Derivative. None: ``"spectral"`` on a periodic grid, ``"forward"`` (one-sided
        differences between neighbouring cells, as SurfaceTopography's ``rms_gradient``)
        otherwise. ``"central"`` uses ``(h[i+1] - h[i-1]) / (2 dx)`` on interior cells.

    Returns
    -------
    float
        rms slope (m/m).
    """
    h = _check(h, grid)
    m = _method(method, grid)
    if m == "spectral":
        return math.sqrt(_spectral_moment(h, grid, 1))
    if m == "forward":
        gx = np.diff(h, axis=0) / grid.dx
        gy = np.diff(h, axis=1) / grid.dy
    else:  # central
        if grid.nx < 3 or grid.ny < 3:
            raise InputError("stats.method", "central differences need at least 3 x 3 cells")
        gx = (h[2:, :] - h[:-2, :]) / (2 * grid.dx)
        gy = (h[:, 2:] - h[:, :-2]) / (2 * grid.dy)
    return float(np.sqrt(np.mean(gx**2) + np.mean(gy**2)))


def rms_curvature(h, grid: Grid, method: str | None = None) -> float:
    """Root-mean-square mean curvature ``sqrt(<(lap h / 2)^2>)`` (1/m).

    Half the rms Laplacian, i.e. the rms of the mean curvature ``(k1 + k2)/2`` in the
    small-slope approximation (the definition of SurfaceTopography's
    ``rms_curvature_from_area``).

    Parameters
    ----------
    h : array_like, shape (nx, ny)
        Heights (m).
    grid : Grid
        Grid of ``h``.
    method : {None, "spectral", "forward", "central"}
        None: spectral on a periodic grid (``|q|^4`` moment), otherwise the 3-point
        second-difference stencil on interior cells (``"forward"`` and ``"central"`` both
        mean this stencil).

    Returns
    -------
    float
        rms curvature (1/m).
    """
    h = _check(h, grid)
    m = _method(method, grid)
    if m == "spectral":
        return 0.5 * math.sqrt(_spectral_moment(h, grid, 2))
    if grid.nx < 3 or grid.ny < 3:
        raise InputError("heights", "curvature needs at least 3 x 3 cells")
    c = h[1:-1, 1:-1]
    lap = (h[2:, 1:-1] - 2 * c + h[:-2, 1:-1]) / grid.dx**2 + (h[1:-1, 2:] - 2 * c + h[1:-1, :-2]) / grid.dy**2
    return float(0.5 * np.sqrt(np.mean(lap**2)))


def skewness(h, grid: Grid | None = None) -> float:
    """Skewness ``<(h - <h>)^3> / rms^3`` (dimensionless; NaN for a flat surface).

    Parameters
    ----------
    h : array_like, shape (nx, ny)
        Heights (m).
    grid : Grid, optional
        Only used to check the shape.

    Returns
    -------
    float
        Skewness (0 for a Gaussian surface).
    """
    h = _check(h, grid)
    d = h - h.mean()
    s2 = np.mean(d**2)
    with np.errstate(invalid="ignore", divide="ignore"):
        return float(np.mean(d**3) / s2**1.5) if s2 > 0 else float("nan")


def kurtosis(h, grid: Grid | None = None) -> float:
    """Kurtosis ``<(h - <h>)^4> / rms^4`` (non-excess: 3 for a Gaussian surface).

    Parameters
    ----------
    h : array_like, shape (nx, ny)
        Heights (m).
    grid : Grid, optional
        Only used to check the shape.

    Returns
    -------
    float
        Kurtosis (dimensionless; NaN for a flat surface).
    """
    h = _check(h, grid)
    d = h - h.mean()
    s2 = np.mean(d**2)
    return float(np.mean(d**4) / s2**2) if s2 > 0 else float("nan")


# ----------------------------------------------------------------------------- spectra
def psd(h, grid: Grid, nbins: int | None = None, average: str = "mean") -> tuple[np.ndarray, np.ndarray]:
    """Isotropic (radially averaged) power spectral density.

    Parameters
    ----------
    h : array_like, shape (nx, ny)
        Heights (m); the mean is removed (the ``q = 0`` mode is excluded).
    grid : Grid
        Grid of ``h``. The DFT treats ``h`` as one period; for non-periodic data the edges
        leak power to high ``q`` (detrend or window first if that matters).
    nbins : int, optional
        Number of linear ``|q|`` bins from ``q_min/2`` to the largest ``|q|`` of the grid
        (the corner of the spectrum). Default: bin width equal to the smallest non-zero
        ``|q| = 2 pi / max(lx, ly)``.
    average : {"mean", "annulus"}
        ``"mean"``: the mean of ``C`` over the Fourier modes in each annulus (the best
        estimate of the value ``C(q)``; use it to plot and fit). ``"annulus"``: the power in
        each annulus divided by the annulus area, ``sum_k C_k dqx dqy / (2 pi q dq)``, which
        makes the integral identity below exact (use it to integrate moments).

    Returns
    -------
    q : ndarray
        Bin centres (rad/m). All bins have the same width ``dq`` (the spacing of
        consecutive centres); with ``"mean"`` empty bins are dropped.
    C : ndarray
        Radially averaged ``C(q) = |h_q|^2 / (lx ly)`` (m^4).

    Notes
    -----
    Normalisation: ``rms^2 = integral C(q) d^2q / (2 pi)^2``; in terms of the output,
    ``rms_height(h)^2 = sum(C * 2 pi q dq) / (2 pi)^2`` (``2 pi q dq`` is exactly the area of
    each annulus). With ``average="annulus"`` this holds to round-off. With ``"mean"`` it
    holds up to the count of lattice points per annulus, which differs from the annulus area
    in the first few rings (+27 % in the first) and beyond the Nyquist circle
    ``|q| > pi / max(dx, dy)``, where only the corners of the spectrum fill the annulus: a few
    percent for surfaces whose power lies well inside the Nyquist circle, more for surfaces
    with much power in the corners (e.g. correlation lengths of a few cells). Fit slopes
    on ``|q| <= pi / max(dx, dy)``.
    """
    h = _check(h, grid)
    hq = sfft.rfft2(h - h.mean())
    qx, qy = _wavevectors(grid)
    qn = np.sqrt(qx**2 + qy**2)
    c = (grid.dx * grid.dy) ** 2 * np.abs(hq) ** 2 / grid.area
    w = np.broadcast_to(_rfft_weights(grid.ny), c.shape)
    keep = qn > 0
    qn, c, w = qn[keep], c[keep], w[keep]
    q0 = 2 * np.pi / max(grid.lx, grid.ly)
    qlo, qhi = 0.5 * q0, float(qn.max()) * (1 + 1e-12)
    if nbins is None:
        nbins = max(1, int(math.ceil((qhi - qlo) / q0)))
        qhi = qlo + nbins * q0
    elif not (isinstance(nbins, (int, np.integer)) and nbins >= 1):
        raise InputError("stats.nbins", f"must be an integer >= 1, got {nbins!r}")
    if average not in ("mean", "annulus"):
        raise InputError("stats.average", f"must be 'mean' or 'annulus', got {average!r}")
    edges = np.linspace(qlo, qhi, int(nbins) + 1)
    idx = np.clip(np.searchsorted(edges, qn, side="right") - 1, 0, int(nbins) - 1)
    counts = np.bincount(idx, weights=w, minlength=nbins)
    sums = np.bincount(idx, weights=w * c, minlength=nbins)
    centres = 0.5 * (edges[1:] + edges[:-1])
    if average == "annulus":
        cell = (2 * np.pi / grid.lx) * (2 * np.pi / grid.ly)  # q-space area per mode
        dq = edges[1] - edges[0]
        return centres, sums * cell / (2 * np.pi * centres * dq)
    ok = counts > 0
    return centres[ok], sums[ok] / counts[ok]


def acf(h, grid: Grid) -> tuple[np.ndarray, np.ndarray]:
    """Radially averaged height autocorrelation function.

    Parameters
    ----------
    h : array_like, shape (nx, ny)
        Heights (m); the mean is removed.
    grid : Grid
        Grid of ``h``. Periodic grids use the circular autocorrelation; free grids the
        zero-padded, overlap-normalised (unbiased) estimate
        ``R(d) = sum h(x) h(x+d) / (number of overlapping pairs)``.

    Returns
    -------
    r : ndarray
        Mean lag distance of each bin (m), from 0 to ``min(lx, ly)/2``; bins are
        ``min(dx, dy)`` wide and centred on multiples of it.
    R : ndarray
        ``R(r)`` (m^2); ``R[0]`` is the variance.
    """
    h = _check(h, grid)
    d = h - h.mean()
    nx, ny = grid.shape
    if grid.periodic:
        R2 = sfft.irfft2(np.abs(sfft.rfft2(d)) ** 2, s=(nx, ny)) / d.size
        ix = (np.arange(nx) + nx // 2) % nx - nx // 2
        iy = (np.arange(ny) + ny // 2) % ny - ny // 2
    else:
        mx, my = nx // 2, ny // 2
        ix = np.r_[0:mx + 1, -mx:0]
        iy = np.r_[0:my + 1, -my:0]
        R2 = _padded_autocorrelation(d, ix, iy)
        pairs = (nx - np.abs(ix))[:, None] * (ny - np.abs(iy))[None, :]
        R2 /= pairs
    r = np.hypot(ix[:, None] * grid.dx, iy[None, :] * grid.dy)
    rmax = 0.5 * min(grid.lx, grid.ly)
    keep = r <= rmax * (1 + 1e-12)
    r, R2 = r[keep], R2[keep]
    step = min(grid.dx, grid.dy)
    b = np.rint(r / step).astype(np.int64)
    cnt = np.bincount(b)
    ok = cnt > 0
    rb = np.bincount(b, weights=r)[ok] / cnt[ok]
    Rb = np.bincount(b, weights=R2)[ok] / cnt[ok]
    return rb, Rb


def _padded_autocorrelation(d, ix, iy):
    """sum_x d(x) d(x + l) at the lags (ix, iy) (ix[:, None], iy[None, :]), by the FFT on the
    zero-padded 2nx x 2ny grid.  The transforms skip the padding rows and write in place (the
    lean pocketfft calls of the elasticity backend), and only the kept lags' rows are transformed
    back: about 7 grid fields at the peak, against 12 with whole-array transforms (a 8192^2
    burl's problem build was bounded by this)."""
    from .._fft import default_workers
    from .._fft import pocketfft as _pocketfft

    nx, ny = d.shape
    N1, N2 = 2 * nx, 2 * ny
    if _pocketfft is None:  # another scipy: the whole-array transforms
        X = sfft.rfft2(d, s=(N1, N2))
        P = np.square(X.real)
        P += np.square(X.imag)
        del X
        return sfft.irfft2(P, s=(N1, N2))[np.ix_(ix % N1, iy % N2)]
    w = default_workers()
    T = np.empty((N1, ny + 1), dtype=complex)
    step = max(1, (1 << 16) // (ny + 1))
    row = np.zeros((step, N2))
    for i0 in range(0, nx, step):  # along y, the unpadded rows in blocks
        k = min(step, nx - i0)
        row[:k, :ny] = d[i0:i0 + k]
        _pocketfft.r2c(row[:k], (1,), True, 0, T[i0:i0 + k], w)
    del row
    T[nx:] = 0.0
    _pocketfft.c2c(T, (0,), True, 0, T, w)
    for i0 in range(0, N1, step):  # |X|^2, in blocks (no full-size temporary)
        blk = T[i0:i0 + step]
        np.multiply(blk, blk.conj(), out=blk)
    _pocketfft.c2c(T, (0,), False, 2, T, w)
    # back along y for the kept rows only, in blocks, keeping the kept columns
    rows, cols = ix % N1, iy % N2
    out = np.empty((len(rows), len(cols)))
    buf = np.empty((step, N2))
    for k0 in range(0, len(rows), step):
        r = rows[k0:k0 + step]
        b = buf[:len(r)]
        _pocketfft.c2r(T[r], (1,), N2, False, 2, b, w)
        out[k0:k0 + len(r)] = b[:, cols]
    return out


def correlation_length(h, grid: Grid, threshold: float = 0.1) -> float:
    """Distance at which the normalised radial ACF first drops below ``threshold``.

    Parameters
    ----------
    h : array_like, shape (nx, ny)
        Heights (m).
    grid : Grid
        Grid of ``h``.
    threshold : float
        Level in (0, 1) of ``R(r)/R(0)``; 0.1 is the definition of Hu and Tonder (1992)
        used by :func:`tribobem.geometry.gaussian_surface` (so a generated surface reads
        back its input). Other conventions are a level away: ``1/e`` (the decay length of an
        exponential ACF, which is ``ln 10 = 2.30`` times shorter than its 10 % length) and
        0.2, the level of ISO 25178's autocorrelation length *Sal* (which takes the
        shortest direction of the 2D ACF, where this takes the radial mean).

    Returns
    -------
    float
        Correlation length (m), linearly interpolated between ACF bins; NaN if the ACF does
        not drop below ``threshold`` within ``min(lx, ly)/2`` or the surface is flat.

    Notes
    -----
    A tilt or a curvature left in the heights keeps the ACF high at every lag (a plane
    ``h = s x`` has ``R(r)/R(0)`` near 1 for ``r`` much shorter than the scan), so on a
    measured scan with only its mean removed this is often NaN: remove the plane first
    (``detrend="height"``, the default of :func:`tribobem.geometry.read_topography`).
    """
    if not (0.0 < threshold < 1.0):
        raise InputError("stats.threshold", f"must be in (0, 1), got {threshold!r}")
    r, R = acf(h, grid)
    if not R[0] > 0:
        return float("nan")
    rho = R / R[0]
    below = np.nonzero(rho < threshold)[0]
    if below.size == 0:
        return float("nan")
    i = int(below[0])
    r0, r1, p0, p1 = r[i - 1], r[i], rho[i - 1], rho[i]
    return float(r0 + (p0 - threshold) * (r1 - r0) / (p0 - p1))


def summary(h, grid: Grid) -> dict:
    """All scalar statistics of a topography.

    Parameters
    ----------
    h : array_like, shape (nx, ny)
        Heights (m).
    grid : Grid
        Grid of ``h`` (selects spectral or finite-difference derivatives).

    Returns
    -------
    dict
        ``rms_height`` (m), ``rms_slope`` (-), ``rms_curvature`` (1/m), ``skewness`` (-),
        ``kurtosis`` (-, non-excess), ``correlation_length`` (m, ACF 10 % level),
        ``peak_to_valley`` (m), ``mean`` (m).
    """
    h = _check(h, grid)
    return {
        "rms_height": rms_height(h, grid),
        "rms_slope": rms_slope(h, grid),
        "rms_curvature": rms_curvature(h, grid),
        "skewness": skewness(h, grid),
        "kurtosis": kurtosis(h, grid),
        "correlation_length": correlation_length(h, grid),
        "peak_to_valley": float(h.max() - h.min()),
        "mean": float(h.mean()),
    }
