r"""Statistical rough-contact theories: Greenwood-Williamson and Persson (thesis 2.1.1-2.1.2).

Greenwood & Williamson (1966), thesis Eqs. 2.1-2.4
--------------------------------------------------
N = eta A0 spherical summits of radius beta with Gaussian heights (rms sigma_s) against a flat
at separation d (measured from the mean summit height)::

    phi(z) = exp(-z^2/(2 sigma_s^2)) / (sqrt(2 pi) sigma_s)
    n   = N int_d^inf phi(z) dz                            = N F_0(h)
    A_c = pi beta N int_d^inf (z - d) phi(z) dz            = pi beta N sigma_s F_1(h)
    F   = (4/3) E* sqrt(beta) N int_d^inf (z-d)^1.5 phi dz = (4/3) E* sqrt(beta) N sigma_s^1.5 F_1.5(h)

with h = d/sigma_s and F_n(h) = (2 pi)^(-1/2) int_h^inf (s - h)^n exp(-s^2/2) ds
= Gamma(n+1) exp(-h^2/4) D_{-n-1}(h) / sqrt(2 pi) (D: parabolic cylinder function).
Two typos of the thesis are corrected: Eq. 2.1 omits the sqrt(2 pi) of the normalised Gaussian,
and Eq. 2.4 prints 3/2 instead of the Hertz factor 4/3 (F = (4/3) E* sqrt(beta) w^1.5 per summit).

Persson (2001), thesis Eqs. 2.5-2.12
------------------------------------
PSD convention (Persson's): C(q) = (2 pi)^-2 int d^2x <h(x) h(0)> exp(-i q.x), so that::

    h_rms^2  = int d^2q C(q)       = 2 pi int q   C(q) dq
    h'_rms^2 = int d^2q q^2 C(q)   = 2 pi int q^3 C(q) dq     (rms slope, |grad h|)

    G(zeta) = (pi/4) E*^2 int_{q_L}^{zeta q_L} q^3 C(q) dq  (= E*^2 h'_rms^2 / 8 over the full band)
    P(sigma, zeta) = [exp(-(sigma - sigma_u)^2/(4G)) - exp(-(sigma + sigma_u)^2/(4G))] / (2 sqrt(pi G))
    A/A0 = P(zeta) = erf(sigma_u / (2 sqrt G))

Magnification zeta = q/q_L is measured from the smallest wavevector q_L of the spectrum.
Small-load limit: A/A0 -> sigma_u/sqrt(pi G) = sqrt(8/pi) sigma_u/(E* h'_rms).

Self-affine PSD (Eq. 2.11): C = C0 for q_L <= q <= q0 (roll-off), C0 (q/q0)^(-2(H+1)) for
q0 < q <= q1; C0 from h_rms (Eq. 2.12, with q1 -> inf)::

    h_rms^2 = pi C0 q0^2 / (alpha H),  alpha = 1/(1 + H - H (q_L/q0)^2)

and with a finite short cut-off q1: h_rms^2 = pi C0 [q0^2 - q_L^2 + (q0^2/H)(1 - (q0/q1)^(2H))].
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.integrate import cumulative_trapezoid, quad
from scipy.special import erf, gamma, pbdv

from ..errors import InputError

__all__ = [
    "greenwood_williamson_F", "GreenwoodWilliamsonResult", "greenwood_williamson",
    "persson_G", "persson_P_sigma", "persson_contact_area", "persson_self_affine_C0",
    "persson_self_affine_psd", "persson_self_affine_G", "persson_area_self_affine",
]


def _out(x):
    x = np.asarray(x, float)
    return float(x) if x.ndim == 0 else x


def _pos(name, v):
    a = np.asarray(v, float)
    if a.size == 0 or not np.all(np.isfinite(a)) or np.any(a <= 0):
        raise InputError(name, f"must be finite and > 0, got {v!r}")
    return float(a) if a.ndim == 0 else a


# ----------------------------------------------------------------------------------------------
# Greenwood-Williamson
# ----------------------------------------------------------------------------------------------

def _F_quad(n, h):
    f = lambda s: (s - h) ** n * np.exp(-0.5 * s * s)  # noqa: E731
    lo = h
    val = quad(f, lo, max(h, 0.0) + 40.0, limit=200, epsabs=0.0, epsrel=1e-13)[0]
    return val / np.sqrt(2.0 * np.pi)


def greenwood_williamson_F(n, h):
    """Greenwood-Williamson integral F_n(h) = (2 pi)^-1/2 int_h^inf (s-h)^n exp(-s^2/2) ds.

    Parameters
    ----------
    n : float
        Order (> -1); 0, 1 and 1.5 are used by the GW model.
    h : float or array_like
        Normalised separation d/sigma_s.

    Returns
    -------
    float or ndarray
        Evaluated as Gamma(n+1) exp(-h^2/4) D_{-n-1}(h)/sqrt(2 pi) (scipy ``pbdv``) for
        h >= -20, by adaptive quadrature below.
    """
    h = np.asarray(h, float)
    out = np.empty(h.shape)
    ok = h >= -20.0
    if np.any(ok):
        d, _ = pbdv(-n - 1.0, h[ok])
        out[ok] = gamma(n + 1.0) * np.exp(-0.25 * h[ok] ** 2) * d / np.sqrt(2.0 * np.pi)
    if np.any(~ok):
        out[~ok] = [_F_quad(n, hv) for hv in h[~ok]]
    return _out(out)


@dataclass(frozen=True)
class GreenwoodWilliamsonResult:
    """Greenwood-Williamson contact state.

    Attributes
    ----------
    n_contacts : float or ndarray
        Expected number of summits in contact.
    contact_area : float or ndarray
        Real contact area A_c (m^2).
    force : float or ndarray
        Total normal force F (N).
    mean_pressure : float or ndarray
        F / area (Pa), the nominal pressure.
    """

    n_contacts: float | np.ndarray
    contact_area: float | np.ndarray
    force: float | np.ndarray
    mean_pressure: float | np.ndarray


def greenwood_williamson(separation, sigma_s, beta_radius, density, E_star, area) -> GreenwoodWilliamsonResult:
    """Greenwood-Williamson model of a rough surface on a flat (thesis Eqs. 2.1-2.4, corrected).

    Parameters
    ----------
    separation : float or array_like
        d, distance from the mean summit height to the flat (m); may be negative.
    sigma_s : float
        Standard deviation of summit heights (m).
    beta_radius : float
        Summit radius of curvature beta (m).
    density : float
        Summit density eta (1/m^2).
    E_star : float
        Composite modulus (Pa).
    area : float
        Nominal area A0 (m^2); N = eta A0 summits.

    Returns
    -------
    GreenwoodWilliamsonResult
        n = N F_0(h), A_c = pi beta N sigma_s F_1(h), F = (4/3) E* beta^0.5 N sigma_s^1.5 F_1.5(h),
        h = d/sigma_s.
    """
    s = float(_pos("sigma_s", sigma_s))
    b = float(_pos("beta_radius", beta_radius))
    eta = float(_pos("density", density))
    Es = float(_pos("E_star", E_star))
    A0 = float(_pos("area", area))
    d = np.asarray(separation, float)
    if not np.all(np.isfinite(d)):
        raise InputError("separation", "must be finite")
    h = d / s
    N = eta * A0
    n = N * np.asarray(greenwood_williamson_F(0.0, h))
    Ac = np.pi * b * N * s * np.asarray(greenwood_williamson_F(1.0, h))
    F = 4.0 / 3.0 * Es * np.sqrt(b) * N * s**1.5 * np.asarray(greenwood_williamson_F(1.5, h))
    return GreenwoodWilliamsonResult(n_contacts=_out(n), contact_area=_out(Ac), force=_out(F),
                                     mean_pressure=_out(F / A0))


# ----------------------------------------------------------------------------------------------
# Persson
# ----------------------------------------------------------------------------------------------

def persson_G(q, C, E_star, q_upper=None, cumulative=False):
    """Persson's G = (pi/4) E*^2 int_{q_L}^{q_upper} q^3 C(q) dq (Pa^2), thesis Eq. 2.10.

    Parameters
    ----------
    q : array_like
        Increasing wavevectors (rad/m); q[0] is q_L.
    C : array_like or callable
        Isotropic PSD C(q) (m^4) in Persson's convention h_rms^2 = 2 pi int q C dq, tabulated on
        ``q`` (trapezoidal rule) or a callable (adaptive quadrature between consecutive ``q``,
        which then serve as breakpoints, e.g. ``[qL, q0, q1]`` for the self-affine PSD).
    E_star : float
        Composite modulus (Pa).
    q_upper : float, optional
        Upper limit zeta q_L (default: q[-1]).
    cumulative : bool
        If True return G at every q (tabulated C only).

    Returns
    -------
    float or ndarray
    """
    Es = float(_pos("E_star", E_star))
    q = np.asarray(q, float)
    if q.ndim != 1 or q.size < 2 or np.any(np.diff(q) <= 0):
        raise InputError("q", "must be a 1D increasing array of at least two wavevectors")
    pref = 0.25 * np.pi * Es**2
    qu = q[-1] if q_upper is None else float(q_upper)
    if qu < q[0] or qu > q[-1]:
        raise InputError("q_upper", f"must lie in [{q[0]:.6g}, {q[-1]:.6g}]")
    if callable(C):
        def integral(upper):
            edges = np.append(q[q < upper], upper)
            return sum(quad(lambda x: x**3 * C(x), lo, hi, epsabs=0.0, epsrel=1e-12, limit=400)[0]
                       for lo, hi in zip(edges[:-1], edges[1:]))
        if cumulative:
            return _out([pref * integral(qi) for qi in q])
        return pref * integral(qu)
    Cv = np.asarray(C, float)
    if Cv.shape != q.shape:
        raise InputError("C", "must have the shape of q")
    y = q**3 * Cv
    if cumulative:
        return _out(pref * cumulative_trapezoid(y, q, initial=0.0))
    keep = q < qu
    qq = np.append(q[keep], qu)
    yy = np.append(y[keep], np.interp(qu, q, y))
    return float(pref * np.trapezoid(yy, qq))


def persson_P_sigma(sigma, sigma_u, G):
    """Persson's stress distribution P(sigma, zeta) (1/Pa), thesis Eq. 2.8.

    [exp(-(sigma - sigma_u)^2/(4G)) - exp(-(sigma + sigma_u)^2/(4G))] / (2 sqrt(pi G)), the
    solution of the diffusion equation 2.6 with P(0) = 0; its integral over sigma > 0 is the
    area fraction (2.9) and its first moment is sigma_u (force balance).

    Parameters
    ----------
    sigma : float or array_like
        Contact stress(es) sigma (Pa).
    sigma_u : float
        Nominal pressure (Pa), the initial condition P = delta(sigma - sigma_u) at zeta = 1.
    G : float
        Persson's G at the magnification of interest (Pa^2), > 0.

    Returns
    -------
    float or ndarray
        P(sigma) (1/Pa), shape of ``sigma``.
    """
    s = np.asarray(sigma, float)
    G = float(_pos("G", G))
    su = float(sigma_u)
    return _out((np.exp(-(s - su) ** 2 / (4.0 * G)) - np.exp(-(s + su) ** 2 / (4.0 * G)))
                / (2.0 * np.sqrt(np.pi * G)))


def persson_contact_area(sigma_u, G):
    """Relative contact area A/A0 = erf(sigma_u / (2 sqrt G)) (thesis Eq. 2.9).

    Parameters
    ----------
    sigma_u : float or array_like
        Nominal pressure (Pa).
    G : float or array_like
        Persson's G at the magnification of interest (Pa^2).

    Returns
    -------
    float or ndarray
        A/A0 (dimensionless, in [0, 1]), broadcast over the inputs.
    """
    return _out(erf(np.asarray(sigma_u, float) / (2.0 * np.sqrt(np.asarray(G, float)))))


def _self_affine_checks(hurst, q0, qL, q1):
    H = float(hurst)
    if not (0.0 < H <= 1.0):
        raise InputError("hurst", f"must lie in (0, 1], got {hurst!r}")
    q0 = float(_pos("q0", q0))
    qL = float(_pos("qL", qL))
    if qL > q0:
        raise InputError("qL", "the smallest wavevector qL must be <= the roll-off q0")
    if q1 is not None:
        q1 = float(_pos("q1", q1))
        if q1 < q0:
            raise InputError("q1", "the short cut-off q1 must be >= q0")
    return H, q0, qL, q1


def persson_self_affine_C0(rms, hurst, q0, qL, q1=None):
    """Plateau C0 (m^4) of the self-affine PSD (Eq. 2.11) giving rms height ``rms`` (Eq. 2.12).

    Parameters
    ----------
    rms : float
        h_rms (m).
    hurst : float
        Hurst exponent H in (0, 1].
    q0 : float
        Roll-off wavevector (rad/m).
    qL : float
        Smallest wavevector (rad/m), <= q0.
    q1 : float, optional
        Short cut-off (rad/m); None means q1 -> inf, i.e. exactly Eq. 2.12.

    Returns
    -------
    float
        C0 (m^4), from h_rms^2 = 2 pi int q C(q) dq over [qL, q1].

    Raises
    ------
    InputError
        H outside (0, 1], a non-positive wavevector, qL > q0 or q1 < q0.
    """
    H, q0, qL, q1 = _self_affine_checks(hurst, q0, qL, q1)
    tail = 1.0 if q1 is None else 1.0 - (q0 / q1) ** (2.0 * H)
    return float(rms) ** 2 / (np.pi * (q0**2 - qL**2 + q0**2 / H * tail))


def persson_self_affine_psd(q, C0, hurst, q0, qL, q1=None):
    """Self-affine PSD of Eq. 2.11: C0 on [qL, q0], C0 (q/q0)^(-2(H+1)) on (q0, q1], 0 outside (m^4).

    Parameters
    ----------
    q : float or array_like
        Wavevector magnitudes (rad/m).
    C0 : float
        Plateau of the PSD (m^4), e.g. from :func:`persson_self_affine_C0`.
    hurst : float
        Hurst exponent H in (0, 1].
    q0 : float
        Roll-off wavevector (rad/m).
    qL : float
        Smallest wavevector (rad/m), <= q0.
    q1 : float, optional
        Short cut-off (rad/m); None: no cut-off.

    Returns
    -------
    float or ndarray
        C(q) (m^4), shape of ``q``.

    Raises
    ------
    InputError
        As :func:`persson_self_affine_C0`.
    """
    H, q0, qL, q1 = _self_affine_checks(hurst, q0, qL, q1)
    q = np.asarray(q, float)
    C = np.where(q <= q0, C0, C0 * (np.maximum(q, q0) / q0) ** (-2.0 * (H + 1.0)))
    C = np.where(q < qL, 0.0, C)
    if q1 is not None:
        C = np.where(q > q1, 0.0, C)
    return _out(C)


def persson_self_affine_G(E_star, C0, hurst, q0, qL, q_upper):
    """Closed-form G (Pa^2) of the self-affine PSD integrated from qL to q_upper.

    The closed form of :func:`persson_G` for the PSD of :func:`persson_self_affine_psd`
    (without short cut-off: ``q_upper`` plays the role of zeta qL).

    Parameters
    ----------
    E_star : float
        Composite modulus (Pa).
    C0 : float
        Plateau of the PSD (m^4), e.g. from :func:`persson_self_affine_C0`.
    hurst : float
        Hurst exponent H in (0, 1].
    q0 : float
        Roll-off wavevector (rad/m).
    qL : float
        Smallest wavevector (rad/m), <= q0.
    q_upper : float or array_like
        Upper limit of the integral (rad/m), >= qL.

    Returns
    -------
    float or ndarray
        G (Pa^2), shape of ``q_upper``.

    Raises
    ------
    InputError
        As :func:`persson_self_affine_C0`.
    """
    H, q0, qL, _ = _self_affine_checks(hurst, q0, qL, None)
    qu = np.asarray(q_upper, float)
    low = np.minimum(qu, q0)
    I = C0 * (low**4 - qL**4) / 4.0
    hi = np.maximum(qu, q0)
    if H == 1.0:
        I = I + C0 * q0**4 * np.log(hi / q0)
    else:
        I = I + C0 * q0 ** (2.0 * H + 2.0) * (hi ** (2.0 - 2.0 * H) - q0 ** (2.0 - 2.0 * H)) / (2.0 - 2.0 * H)
    return _out(0.25 * np.pi * float(E_star) ** 2 * I)


def persson_area_self_affine(mean_pressure, E_star, *, rms_slope=None, rms=None, C0=None,
                             hurst=None, q0=None, qL=None, q1=None, magnification=None):
    """Persson relative contact area A/A0 for a self-affine surface (Eqs. 2.9-2.12).

    Give either ``rms_slope`` (then G = E*^2 h'_rms^2/8, the full band) or the PSD parameters
    ``hurst, q0, qL, q1`` with ``rms`` or ``C0``; ``magnification`` zeta limits the band to
    q <= zeta qL (default: up to q1).

    Parameters
    ----------
    mean_pressure : float or array_like
        Nominal pressure sigma_u (Pa).
    E_star : float
        Composite modulus (Pa).
    rms_slope : float, optional
        h'_rms (dimensionless) of the whole band; replaces every PSD parameter.
    rms : float, optional
        h_rms (m); C0 follows from :func:`persson_self_affine_C0`.
    C0 : float, optional
        PSD plateau (m^4), instead of ``rms``.
    hurst : float, optional
        Hurst exponent H in (0, 1].
    q0, qL, q1 : float, optional
        Roll-off, smallest and short cut-off wavevectors (rad/m); all three are required
        without ``rms_slope``.
    magnification : float, optional
        zeta: G is integrated up to ``min(zeta qL, q1)``.

    Returns
    -------
    float or ndarray
        erf(sigma_u / (2 sqrt G)), shape of ``mean_pressure``.

    Raises
    ------
    InputError
        Neither ``rms_slope`` nor the full set ``hurst, q0, qL, q1``; not exactly one of
        ``rms`` and ``C0``; invalid PSD parameters.
    """
    Es = float(_pos("E_star", E_star))
    if rms_slope is not None:
        G = Es**2 * float(rms_slope) ** 2 / 8.0
    else:
        if hurst is None or q0 is None or qL is None or q1 is None:
            raise InputError("persson_area_self_affine", "give rms_slope= or hurst, q0, qL, q1")
        if (rms is None) == (C0 is None):
            raise InputError("persson_area_self_affine", "give exactly one of rms= and C0=")
        if C0 is None:
            C0 = persson_self_affine_C0(rms, hurst, q0, qL, q1)
        qu = float(q1) if magnification is None else min(float(magnification) * float(qL), float(q1))
        G = float(persson_self_affine_G(Es, C0, hurst, q0, qL, qu))
    return persson_contact_area(mean_pressure, G)
