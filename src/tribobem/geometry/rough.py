"""Random rough surfaces (periodic by construction).

* :func:`gaussian_surface`: Hu and Tonder (1992) FFT filtering of white noise with an
  exponential autocorrelation function, optionally made non-Gaussian (skewness, kurtosis)
  with Johnson's translator system.
* :func:`self_affine_surface`: random-phase surface with Persson's self-affine PSD.
* :func:`scale_to_rms`: remove the mean and scale to an rms (thesis Papers A, D: this keeps
  skewness, kurtosis and the positions of peaks and valleys).

All generators return heights (m) indexed ``[ix, iy]`` with zero mean. They are periodic over
the grid whatever ``grid.periodic`` says (a free-boundary grid simply sees one period).
``seed`` may be None, an int, or a :class:`numpy.random.Generator`.
"""

from __future__ import annotations

import math

import numpy as np
import scipy.fft as sfft

from ..errors import InputError
from ..grid import Grid
from . import stats

__all__ = ["gaussian_surface", "self_affine_surface", "scale_to_rms"]

#: Decay constant of the exponential ACF: R(beta) / R(0) = exp(-ln 10) = 0.1 exactly
#: (Hu and Tonder round it to 2.3).
ACF_DECAY = math.log(10.0)


def _pos(value, field, unit="m", allow_zero=False):
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise InputError(field, f"must be a number ({unit}), got {value!r}") from None
    ok = math.isfinite(v) and (v >= 0 if allow_zero else v > 0)
    if not ok:
        raise InputError(field, f"must be a finite value {'>=' if allow_zero else '>'} 0 {unit}, got {value!r}")
    return v


def scale_to_rms(h, rms: float) -> np.ndarray:
    """Subtract the mean and scale to an exact rms height.

    Parameters
    ----------
    h : array_like
        Heights (m), any shape.
    rms : float
        Target rms height (m), >= 0.

    Returns
    -------
    ndarray
        ``(h - <h>) * rms / rms(h)`` (m). Skewness, kurtosis and the locations of peaks
        and valleys are unchanged (thesis Paper A, section 7).

    Raises
    ------
    InputError
        ``roughness.rms`` if ``rms`` is negative or not finite, or if ``h`` is flat and
        ``rms > 0``.
    """
    target = _pos(rms, "roughness.rms", allow_zero=True)
    h = np.asarray(h, dtype=float)
    d = h - h.mean()
    cur = float(np.sqrt(np.mean(d**2)))
    if target == 0.0:
        return np.zeros_like(d)
    if not cur > 0:
        raise InputError("roughness.rms", "cannot scale a flat surface to a non-zero rms")
    return d * (target / cur)


# ----------------------------------------------------------------------------- Johnson system
def _moments(x: np.ndarray) -> tuple[float, float]:
    d = x - x.mean()
    s2 = np.mean(d * d)
    return float(np.mean(d**3) / s2**1.5), float(np.mean(d**4) / s2**2)


def _lognormal_kurtosis(skew: float) -> float:
    """Kurtosis of the lognormal distribution with the given skewness (|skew|)."""
    b1 = skew * skew
    # (w - 1)(w + 2)^2 = b1 for w = exp(sigma^2) >= 1: solve the cubic numerically
    roots = np.roots([1.0, 3.0, 0.0, -4.0 - b1])
    w = max(float(r.real) for r in roots if abs(r.imag) < 1e-9)
    return w**4 + 2 * w**3 + 3 * w**2 - 3


def johnson_quantiles(n: int, skewness: float, kurtosis: float) -> np.ndarray:
    """``n`` sorted values of a standardised Johnson variate with exact sample moments.

    The values are ``f((u - gamma)/delta)`` at the normal quantiles
    ``u_i = Phi^-1((i + 1/2)/n)`` with ``f = sinh`` (S_U), the logistic function (S_B) or
    ``exp`` (S_L, on the lognormal line), and ``gamma, delta`` solved so that the sample
    skewness and kurtosis of the ``n`` values equal the targets.

    Parameters
    ----------
    n : int
        Number of values (> 10).
    skewness : float
        Target skewness.
    kurtosis : float
        Target (non-excess) kurtosis; must exceed ``1 + skewness^2``.

    Returns
    -------
    ndarray, shape (n,)
        Sorted values with zero mean and unit standard deviation.
    """
    from scipy.optimize import brentq, least_squares
    from scipy.special import ndtri

    S, K = float(skewness), float(kurtosis)
    if not (math.isfinite(S) and math.isfinite(K)):
        raise InputError("roughness.kurtosis", "skewness and kurtosis must be finite")
    if K <= 1.0 + S * S:
        raise InputError(
            "roughness.kurtosis",
            f"must be > 1 + skewness^2 = {1 + S * S:.6g} for any distribution, got {K:.6g}",
        )
    u = ndtri((np.arange(n) + 0.5) / n)
    sign = -1.0 if S < 0 else 1.0
    S = abs(S)
    tol = 1e-9

    def standardise(x):
        x = np.sort(x)
        return (x - x.mean()) / x.std()

    if S < 1e-12 and abs(K - 3.0) < 1e-12:
        return standardise(u)

    k_ln = _lognormal_kurtosis(S) if S > 0 else 3.0

    if abs(K - k_ln) <= 1e-9 * K and S > 0:  # S_L: lognormal
        def f1(a):
            return _moments(np.exp(a * u))[0] - S

        a = brentq(f1, 1e-6, 10.0)
        x = standardise(np.exp(a * u))
        return x if sign > 0 else np.sort(-x)

    family = "SU" if K > k_ln else "SB"

    def transform(p):
        g, logd = p
        z = np.clip((u - g) / math.exp(logd), -700, 700)
        if family == "SU":
            return np.sinh(z)
        return 0.5 * (1.0 + np.tanh(0.5 * z))  # logistic, overflow-free

    def resid(p):
        x = transform(p)
        if not np.all(np.isfinite(x)) or x.std() == 0:
            return np.array([1e6, 1e6])
        s, k = _moments(x)
        return np.array([s - S, (k - K) / max(K, 1.0)])

    best = None
    gammas = (0.0, -0.5, -2.0) if family == "SU" else (0.0, 0.5, 2.0)
    for g0 in gammas:
        for d0 in (0.3, 1.0, 3.0):
            sol = least_squares(resid, x0=[g0, math.log(d0)], xtol=1e-14, ftol=1e-14, gtol=1e-14)
            if best is None or sol.cost < best.cost:
                best = sol
            if best.cost < 0.5 * tol**2:
                break
        if best.cost < 0.5 * tol**2:
            break
    s, k = _moments(transform(best.x))
    if abs(s - S) > 1e-6 or abs(k - K) > 1e-6 * max(K, 1.0):
        raise InputError(
            "roughness.kurtosis",
            f"could not reach skewness {sign * S:.6g} and kurtosis {K:.6g} with {n} points "
            f"(got {sign * s:.6g}, {k:.6g}); use a larger grid or less extreme moments",
        )
    x = standardise(transform(best.x))
    return x if sign > 0 else np.sort(-x)


def _rng(seed) -> np.random.Generator:
    if isinstance(seed, np.random.Generator):
        return seed
    try:
        return np.random.default_rng(seed)
    except (TypeError, ValueError) as exc:
        raise InputError("roughness.seed", f"must be None, an int >= 0 or a numpy Generator: {exc}") from None


# ----------------------------------------------------------------------------- Gaussian (Hu-Tonder)
def gaussian_surface(
    grid: Grid,
    rms: float,
    correlation_length: float,
    correlation_length_y: float | None = None,
    seed=None,
    skewness: float | None = None,
    kurtosis: float | None = None,
) -> np.ndarray:
    """Random rough surface with an exponential ACF by FFT filtering (Hu and Tonder 1992).

    Parameters
    ----------
    grid : Grid
        Grid of the result; the surface is periodic over ``lx x ly``.
    rms : float
        rms height (m), >= 0; the result is scaled to it exactly.
    correlation_length : float
        ``beta_x`` (m), > 0: the distance along x at which the ACF falls to 10 % of its
        value at zero lag.
    correlation_length_y : float, optional
        ``beta_y`` (m); default ``beta_x`` (isotropic).
    seed : None, int or numpy.random.Generator
        Random state; the same seed gives the same surface.
    skewness, kurtosis : float, optional
        Target skewness and (non-excess) kurtosis. If either is given, the Gaussian field is
        mapped rank-by-rank onto a Johnson translator-system variate (S_U, S_B or S_L,
        chosen from the moments) fitted so that the final surface has these sample moments
        exactly (to ~1e-9). Defaults when only one is given: skewness 0, kurtosis 3.
        Must satisfy ``kurtosis > 1 + skewness^2``.

    Returns
    -------
    ndarray, shape (nx, ny)
        Heights (m), zero mean, rms equal to ``rms``.

    Notes
    -----
    Target ACF ``R(X, Y) = rms^2 exp(-ln(10) sqrt((X/beta_x)^2 + (Y/beta_y)^2))`` (Hu and
    Tonder write 2.3 for ``ln 10``), sampled at the minimum-image lags of the periodic grid.
    Its DFT ``S`` (negative values from periodic truncation clipped to 0) gives the filter
    ``sqrt(S)`` applied to unit Gaussian white noise, so the expected ACF of the result is
    the target. The Johnson mapping is monotone, so it keeps the ranks (positions of peaks
    and valleys) but changes the ACF slightly for strongly non-Gaussian targets (Hu and
    Tonder instead transform the input noise; that route often cannot reach the target
    for correlation lengths of many cells).
    """
    sigma = _pos(rms, "roughness.rms", allow_zero=True)
    bx = _pos(correlation_length, "roughness.correlation_length")
    by = bx if correlation_length_y is None else _pos(correlation_length_y, "roughness.correlation_length_y")
    want_moments = skewness is not None or kurtosis is not None
    sk = 0.0 if skewness is None else skewness
    ku = 3.0 if kurtosis is None else kurtosis
    try:
        sk, ku = float(sk), float(ku)
    except (TypeError, ValueError):
        raise InputError("roughness.skewness", "skewness and kurtosis must be numbers") from None
    if want_moments and ku <= 1.0 + sk * sk:  # check before drawing anything
        raise InputError(
            "roughness.kurtosis", f"must be > 1 + skewness^2 = {1 + sk * sk:.6g}, got {ku:.6g}"
        )
    rng = _rng(seed)
    nx, ny = grid.shape
    ix = (np.arange(nx) + nx // 2) % nx - nx // 2
    iy = (np.arange(ny) + ny // 2) % ny - ny // 2
    lag = np.hypot((ix * grid.dx / bx)[:, None], (iy * grid.dy / by)[None, :])
    acf = np.exp(-ACF_DECAY * lag)
    spec = np.maximum(sfft.rfft2(acf).real, 0.0)
    noise = rng.standard_normal(grid.shape)
    z = sfft.irfft2(np.sqrt(spec) * sfft.rfft2(noise), s=grid.shape)
    if want_moments and not (sk == 0.0 and ku == 3.0):
        values = johnson_quantiles(z.size, sk, ku)
        out = np.empty(z.size)
        out[np.argsort(z, axis=None, kind="stable")] = values
        z = out.reshape(grid.shape)
    return scale_to_rms(z, sigma)


# ----------------------------------------------------------------------------- self-affine (Persson)
def persson_psd(q, hurst: float, q_long: float, q_rolloff: float, q_short: float, c0: float = 1.0):
    """Persson's self-affine PSD with a roll-off.

    Parameters
    ----------
    q : array_like
        Wavevector magnitudes (rad/m).
    hurst : float
        Hurst exponent ``H``.
    q_long, q_rolloff, q_short : float
        ``q_L <= q_r < q_s`` (rad/m).
    c0 : float
        Plateau value (m^4).

    Returns
    -------
    ndarray
        ``C0`` for ``q_L <= q < q_r``, ``C0 (q/q_r)^(-2(H+1))`` for ``q_r <= q <= q_s``,
        0 elsewhere (m^4).
    """
    q = np.asarray(q, dtype=float)
    with np.errstate(divide="ignore"):
        tail = c0 * (np.maximum(q, q_rolloff) / q_rolloff) ** (-2.0 * (hurst + 1.0))
    return np.where((q >= q_long) & (q <= q_short), tail, 0.0)


def self_affine_surface(
    grid: Grid,
    hurst: float,
    rms_height: float | None = None,
    rms_slope: float | None = None,
    rolloff_wavelength: float | None = None,
    short_cutoff: float | None = None,
    long_cutoff: float | None = None,
    seed=None,
) -> np.ndarray:
    """Random-phase self-affine surface with Persson's PSD.

    Parameters
    ----------
    grid : Grid
        Grid of the result; the surface is periodic over ``lx x ly``.
    hurst : float
        Hurst exponent ``H`` in (0, 1].
    rms_height : float, optional
        rms height (m). Give exactly one of ``rms_height`` and ``rms_slope``.
    rms_slope : float, optional
        rms slope (-), as computed by :func:`tribobem.geometry.stats.rms_slope` on ``grid``
        (spectral on a periodic grid, forward differences otherwise).
    rolloff_wavelength : float, optional
        ``lambda_r = 2 pi / q_r`` (m). Default: ``long_cutoff`` (no plateau).
    short_cutoff : float, optional
        ``lambda_s = 2 pi / q_s`` (m). Default: ``2 max(dx, dy)`` (the Nyquist circle).
    long_cutoff : float, optional
        ``lambda_L = 2 pi / q_L`` (m). Default: ``max(lx, ly)`` (all modes).
    seed : None, int or numpy.random.Generator
        Random state of the phases.

    Returns
    -------
    ndarray, shape (nx, ny)
        Heights (m), zero mean, scaled to the requested rms exactly.

    Notes
    -----
    ``C(q) = C0`` for ``q_L <= q < q_r``, ``C0 (q/q_r)^(-2(H+1))`` for ``q_r <= q <= q_s``,
    0 otherwise. Every Fourier mode gets amplitude ``sqrt(C(|q|))`` and a uniformly random
    phase (no amplitude scatter), so the realised PSD follows ``C(q)`` closely; ``C0`` is
    then fixed by the rms scaling.
    """
    try:
        H = float(hurst)
    except (TypeError, ValueError):
        raise InputError("roughness.hurst", f"must be a number in (0, 1], got {hurst!r}") from None
    if not (0.0 < H <= 1.0):
        raise InputError("roughness.hurst", f"must be in (0, 1], got {hurst!r}")
    if (rms_height is None) == (rms_slope is None):
        raise InputError("roughness.rms_height", "give exactly one of rms_height (m) or rms_slope (-)")
    if rms_height is not None:
        target = _pos(rms_height, "roughness.rms_height", allow_zero=True)
    else:
        target = _pos(rms_slope, "roughness.rms_slope", unit="(dimensionless)", allow_zero=True)
    lam_L = max(grid.lx, grid.ly) if long_cutoff is None else _pos(long_cutoff, "roughness.long_cutoff")
    lam_s = 2 * max(grid.dx, grid.dy) if short_cutoff is None else _pos(short_cutoff, "roughness.short_cutoff")
    lam_r = lam_L if rolloff_wavelength is None else _pos(rolloff_wavelength, "roughness.rolloff_wavelength")
    if not lam_s < lam_L:
        raise InputError("roughness.short_cutoff", f"must be < long_cutoff = {lam_L:.6g} m, got {lam_s:.6g} m")
    if not (lam_s < lam_r <= lam_L):
        raise InputError(
            "roughness.rolloff_wavelength",
            f"must be in (short_cutoff, long_cutoff] = ({lam_s:.6g}, {lam_L:.6g}] m, got {lam_r:.6g} m",
        )
    rng = _rng(seed)
    qx, qy = stats._wavevectors(grid)
    q = np.sqrt(qx**2 + qy**2)
    amp = np.sqrt(persson_psd(q, H, 2 * np.pi / lam_L, 2 * np.pi / lam_r, 2 * np.pi / lam_s))
    amp[0, 0] = 0.0
    if not np.any(amp > 0):
        raise InputError(
            "roughness.short_cutoff",
            "no Fourier mode of the grid lies between the cut-offs; widen them or refine the grid",
        )
    w = sfft.rfft2(rng.standard_normal(grid.shape))
    phase = w / np.maximum(np.abs(w), np.finfo(float).tiny)
    h = sfft.irfft2(amp * phase, s=grid.shape)
    h -= h.mean()
    if rms_height is not None:
        return scale_to_rms(h, target)
    current = stats.rms_slope(h, grid)
    return h * (target / current)
