"""Cattaneo-Mindlin, Mindlin-Deresiewicz and Spence."""

import math

import numpy as np
import pytest
from scipy.integrate import quad
from scipy.linalg import cholesky, solve_triangular
from scipy.optimize import lsq_linear
from scipy.special import ellipe, ellipk

from tribobem.analytic import (
    MindlinLoop, cattaneo_mindlin_displacement, cattaneo_mindlin_traction, cattaneo_stick_ratio,
    hertz, mindlin_compliance_k, mindlin_delta0, mindlin_deresiewicz_loop,
    mindlin_initial_stiffness, mindlin_loop_energy, mindlin_reloading_displacement,
    mindlin_reloading_stick_ratio, mindlin_reloading_stiffness, mindlin_unloading_displacement,
    mindlin_unloading_stick_ratio, mindlin_unloading_stiffness, mindlin_virgin_stiffness,
    spence_beta_over_mu, spence_stick_ratio, spence_traction,
)
from tribobem.errors import InputError
from tribobem.materials import ContactPair, Material

# Paper E section 3.1-like numbers: identical bodies E = 70 GPa, nu = 0.3, R = 50 um, 10 uN
E, NU, RAD, P, MU = 70e9, 0.3, 50e-6, 10e-6, 0.2
G = E / (2 * (1 + NU))
K_ID = mindlin_compliance_k(E, NU, E, NU)
A_C = hertz(force=P, radius=RAD / 2, E_star=E / (2 * (1 - NU**2))).contact_radius
KW = dict(P=P, a=A_C, mu=MU, k=K_ID)


def _num_deriv(f, x, h):
    return (f(x + h) - f(x - h)) / (2 * h)


# ----------------------------------------------------------------------------------------------
# compliance and initial stiffness
# ----------------------------------------------------------------------------------------------

def test_compliance_k():
    k1 = (2 - NU) / G
    assert mindlin_compliance_k(E, NU) == pytest.approx(k1, rel=1e-15)               # rigid body 2
    assert mindlin_compliance_k(math.inf, 0.1, E, NU) == pytest.approx(k1, rel=1e-15)  # rigid 1
    assert K_ID == pytest.approx(2 * k1, rel=1e-15)
    k = mindlin_compliance_k(130e9, 0.28, 0.98e9, 0.5)
    assert k == pytest.approx(1.72 * 2 * 1.28 / 130e9 + 1.5 * 2 * 1.5 / 0.98e9, rel=1e-14)
    with pytest.raises(InputError):
        mindlin_compliance_k(math.inf, 0.3, math.inf, 0.3)
    with pytest.raises(InputError):
        mindlin_compliance_k(E, 0.6)
    with pytest.raises(InputError):
        mindlin_compliance_k(-E, 0.3)


def test_initial_stiffness_is_8a_over_k_from_the_virgin_curve():
    K0 = mindlin_initial_stiffness(A_C, K_ID)
    assert K0 == pytest.approx(8 * A_C / K_ID, rel=1e-15)
    # derivative of the virgin curve at Q = 0 (not a restatement of the formula)
    h = 1e-7 * MU * P      # central difference: O(h/(6 mu P)) error from the x|x| term
    slope = _num_deriv(lambda q: cattaneo_mindlin_displacement(q, **KW), 0.0, h)
    assert 1 / slope == pytest.approx(K0, rel=1e-7)
    # identical bodies: thesis Eq. 2.26 "4 G a/(2 - nu)"; rigid counterface: Paper F "8"
    assert K0 == pytest.approx(4 * G * A_C / (2 - NU), rel=1e-14)
    k_rig = mindlin_compliance_k(E, NU)
    assert mindlin_initial_stiffness(A_C, k_rig) == pytest.approx(8 * G * A_C / (2 - NU), rel=1e-14)
    # independent of mu: 3 mu P/(2 delta0) for any mu
    for mu in (0.05, 0.2, 1.0):
        d0 = mindlin_delta0(P=P, a=A_C, mu=mu, k=K_ID)
        assert 1.5 * mu * P / d0 == pytest.approx(K0, rel=1e-14)


# ----------------------------------------------------------------------------------------------
# Cattaneo-Mindlin
# ----------------------------------------------------------------------------------------------

def test_cattaneo_displacement_shape_and_limits():
    d0 = mindlin_delta0(**KW)
    assert d0 == pytest.approx(3 * MU * P * K_ID / (16 * A_C), rel=1e-15)
    assert cattaneo_mindlin_displacement(MU * P, **KW) == pytest.approx(d0, rel=1e-14)
    assert cattaneo_mindlin_displacement(0.0, **KW) == 0.0
    Q = np.array([-0.9, -0.3, 0.3, 0.9]) * MU * P
    d = cattaneo_mindlin_displacement(Q, **KW)
    np.testing.assert_allclose(d, -d[::-1], rtol=1e-15)
    assert d[2] == pytest.approx(d0 * (1 - 0.7 ** (2 / 3)), rel=1e-14)
    np.testing.assert_allclose(cattaneo_stick_ratio(Q, P=P, mu=MU),
                               np.cbrt(1 - np.abs(Q) / (MU * P)))
    assert cattaneo_stick_ratio(MU * P, P=P, mu=MU) == 0.0
    with pytest.raises(InputError):
        cattaneo_mindlin_displacement(1.01 * MU * P, **KW)


@pytest.mark.parametrize("x", [0.0, 0.2, 0.6, 0.95, 1.0])
def test_cattaneo_traction_force_bound_and_centre_displacement(x):
    Q = x * MU * P
    a = A_C
    p0 = 3 * P / (2 * np.pi * a**2)
    c = a * cattaneo_stick_ratio(Q, P=P, mu=MU)
    q = lambda r: cattaneo_mindlin_traction(r, Q, P=P, a=a, mu=MU)  # noqa: E731
    pts = [c] if 0 < c < a else None
    total = quad(lambda r: 2 * np.pi * r * q(r), 0, a, points=pts, epsabs=0, epsrel=1e-12)[0]
    assert total == pytest.approx(Q, rel=1e-9, abs=1e-12 * MU * P)
    # slip annulus at the limit, stick disc below it
    r = np.linspace(0, 0.999 * a, 400)
    pr = p0 * np.sqrt(1 - (r / a) ** 2)
    qr = q(r)
    assert np.all(qr <= MU * pr * (1 + 1e-12))
    np.testing.assert_allclose(qr[r > c], MU * pr[r > c], rtol=1e-12)
    if x < 1:
        assert np.all(qr[r < 0.99 * c] < MU * pr[r < 0.99 * c])
    # independent displacement: the centre is stuck, so its Cerruti displacement (sum over
    # both bodies) is the rigid shift: u_x(0) = int q [(1-nu)/r + nu cos^2/r]/(2 pi G) dA
    #                                        = (k/2) int_0^a q(r) dr
    ux0 = 0.5 * K_ID * quad(q, 0, a, points=pts, epsabs=0, epsrel=1e-12)[0]
    assert ux0 == pytest.approx(cattaneo_mindlin_displacement(Q, **KW), rel=1e-9, abs=1e-25)
    assert q(1.01 * a) == 0.0
    assert cattaneo_mindlin_traction(0.3 * a, -Q, P=P, a=a, mu=MU) == pytest.approx(-q(0.3 * a))


def test_virgin_stiffness_forms_and_numerical_derivative():
    d0 = mindlin_delta0(**KW)
    Q = np.linspace(-0.95, 0.95, 9) * MU * P
    K_Q = mindlin_virgin_stiffness(Q=Q, **KW)
    d = cattaneo_mindlin_displacement(Q, **KW)
    K_d = mindlin_virgin_stiffness(delta=d, **KW)
    np.testing.assert_allclose(K_Q, K_d, rtol=1e-12)
    np.testing.assert_allclose(K_d, 1.5 * MU * P / d0 * np.sqrt(1 - np.abs(d) / d0), rtol=1e-14)
    h = 1e-7 * MU * P
    num = 2 * h / (cattaneo_mindlin_displacement(Q + h, **KW)
                   - cattaneo_mindlin_displacement(Q - h, **KW))
    np.testing.assert_allclose(K_Q, num, rtol=1e-6)
    assert mindlin_virgin_stiffness(Q=MU * P, **KW) == 0.0
    with pytest.raises(InputError):
        mindlin_virgin_stiffness(**KW)


# ----------------------------------------------------------------------------------------------
# Mindlin-Deresiewicz
# ----------------------------------------------------------------------------------------------

@pytest.mark.parametrize("r", [0.1, 0.5, 0.9, 1.0])
def test_loop_closes(r):
    Qs = r * MU * P
    d_star = cattaneo_mindlin_displacement(Qs, **KW)
    assert mindlin_unloading_displacement(Qs, Qs, **KW) == pytest.approx(d_star, rel=1e-13)
    d_low = mindlin_unloading_displacement(-Qs, Qs, **KW)
    assert d_low == pytest.approx(-d_star, rel=1e-13)
    assert mindlin_reloading_displacement(-Qs, Qs, **KW) == pytest.approx(d_low, rel=1e-13)
    assert mindlin_reloading_displacement(Qs, Qs, **KW) == pytest.approx(d_star, rel=1e-13)
    # odd symmetry of the two branches
    Q = np.linspace(-Qs, Qs, 11)
    np.testing.assert_allclose(mindlin_reloading_displacement(Q, Qs, **KW),
                               -mindlin_unloading_displacement(-Q, Qs, **KW),
                               rtol=1e-13, atol=1e-25)


@pytest.mark.parametrize("r", [0.2, 0.7, 1.0])
def test_branches_follow_masing(r):
    """Independent form: unloading = delta* - 2 delta_virgin((Q* - Q)/2) (Masing's rule)."""
    Qs = r * MU * P
    Q = np.linspace(-Qs, Qs, 21)
    d_star = cattaneo_mindlin_displacement(Qs, **KW)
    masing = d_star - 2 * cattaneo_mindlin_displacement((Qs - Q) / 2, **KW)
    np.testing.assert_allclose(mindlin_unloading_displacement(Q, Qs, **KW), masing,
                               rtol=1e-12, atol=1e-24)
    masing_up = -d_star + 2 * cattaneo_mindlin_displacement((Qs + Q) / 2, **KW)
    np.testing.assert_allclose(mindlin_reloading_displacement(Q, Qs, **KW), masing_up,
                               rtol=1e-12, atol=1e-24)


def test_thesis_eq_2_27c_as_printed_does_not_close():
    """The thesis prints (1 + Q*/(mu P))^(2/3) in the reloading branch: the loop stays open."""
    r = 0.5
    Qs = r * MU * P
    d0 = mindlin_delta0(**KW)

    def printed(Q):
        return -d0 * (2 * (1 - (Qs + Q) / (2 * MU * P)) ** (2 / 3) - (1 + r) ** (2 / 3) - 1)

    d_star = cattaneo_mindlin_displacement(Qs, **KW)
    d_low = mindlin_unloading_displacement(-Qs, Qs, **KW)
    miss_start = abs(printed(-Qs) - d_low) / d_star
    miss_end = abs(printed(Qs) - d_star) / d_star
    assert miss_start > 1.0 and miss_end > 1.0           # misses by more than the amplitude
    miss = d0 * ((1 + r) ** (2 / 3) - (1 - r) ** (2 / 3))
    assert abs(printed(Qs) - d_star) == pytest.approx(miss, rel=1e-12)
    # the corrected branch closes
    assert mindlin_reloading_displacement(Qs, Qs, **KW) == pytest.approx(d_star, rel=1e-13)


@pytest.mark.parametrize("r", [0.05, 0.3, 0.6, 0.9, 1.0])
def test_loop_energy_equals_enclosed_area(r):
    Qs = r * MU * P
    W = mindlin_loop_energy(Qs, **KW)
    f = lambda Q: (mindlin_unloading_displacement(Q, Qs, **KW)  # noqa: E731
                   - mindlin_reloading_displacement(Q, Qs, **KW))
    area = quad(f, -Qs, Qs, epsabs=0, epsrel=1e-12, limit=200)[0]
    assert W == pytest.approx(area, rel=1e-6)
    loop = mindlin_deresiewicz_loop(Qs, **KW, n=4001)
    shoelace = 0.5 * abs(np.sum(loop.Q[:-1] * loop.delta[1:] - loop.Q[1:] * loop.delta[:-1]))
    assert shoelace == pytest.approx(W, rel=1e-5)


def test_loop_energy_small_amplitude_and_gross_slip():
    Qs = 1e-3 * MU * P
    W_cubic = K_ID * Qs**3 / (36 * A_C * MU * P)
    assert mindlin_loop_energy(Qs, **KW) == pytest.approx(W_cubic, rel=1e-2)
    W1 = mindlin_loop_energy(MU * P, **KW)
    assert W1 == pytest.approx(9 * MU**2 * P**2 * K_ID / (10 * A_C) * (1 - 5 / 6), rel=1e-14)


@pytest.mark.parametrize("r", [0.3, 0.8])
def test_branch_slopes_and_stick_radii(r):
    Qs = r * MU * P
    K0 = 8 * A_C / K_ID
    Q = np.linspace(-0.98, 0.98, 9) * Qs
    h = 1e-7 * Qs
    branches = (
        (mindlin_unloading_displacement, mindlin_unloading_stiffness,
         mindlin_unloading_stick_ratio),
        (mindlin_reloading_displacement, mindlin_reloading_stiffness,
         mindlin_reloading_stick_ratio),
    )
    for disp, stiff, stick in branches:
        num = 2 * h / (disp(Q + h, Qs, **KW) - disp(Q - h, Qs, **KW))
        K = stiff(Q, Qs, **KW)
        np.testing.assert_allclose(K, num, rtol=1e-6)
        np.testing.assert_allclose(K, K0 * stick(Q, Qs, P=P, mu=MU), rtol=1e-14)
    # turning points: full stick (slope K0), and back to the virgin stick radius at the far end
    assert mindlin_unloading_stiffness(Qs, Qs, **KW) == pytest.approx(K0, rel=1e-14)
    assert mindlin_reloading_stiffness(-Qs, Qs, **KW) == pytest.approx(K0, rel=1e-14)
    c_v = cattaneo_stick_ratio(Qs, P=P, mu=MU)
    assert mindlin_unloading_stick_ratio(-Qs, Qs, P=P, mu=MU) == pytest.approx(c_v, rel=1e-14)
    assert mindlin_reloading_stick_ratio(Qs, Qs, P=P, mu=MU) == pytest.approx(c_v, rel=1e-14)
    # slope from -Q*: K0 (1 - (Q* + Q)/(2 mu P))^(1/3)
    assert mindlin_reloading_stiffness(0.0, Qs, **KW) == pytest.approx(K0 * (1 - r / 2) ** (1 / 3))


def test_loop_arrays():
    Qs = 0.6 * MU * P
    loop = mindlin_deresiewicz_loop(Qs, **KW, n=51)
    assert isinstance(loop, MindlinLoop)
    assert loop.Q.shape == loop.delta.shape == (101,)
    assert loop.Q[0] == loop.Q[-1] == Qs and loop.delta[0] == loop.delta[-1] == loop.delta_star
    assert loop.Q[50] == -Qs and loop.delta[50] == -loop.delta_star
    assert loop.virgin_delta[-1] == pytest.approx(loop.delta_star, rel=1e-14)
    assert loop.energy == mindlin_loop_energy(Qs, **KW)
    # hysteresis: the unloading branch lies above the reloading one
    Q = np.linspace(-0.9, 0.9, 7) * Qs
    assert np.all(mindlin_unloading_displacement(Q, Qs, **KW)
                  > mindlin_reloading_displacement(Q, Qs, **KW))
    with pytest.raises(InputError):
        mindlin_deresiewicz_loop(1.1 * MU * P, **KW)
    with pytest.raises(InputError):
        mindlin_unloading_displacement(1.1 * Qs, Qs, **KW)


# ----------------------------------------------------------------------------------------------
# Spence (1975): normal loading with friction of dissimilar bodies
# ----------------------------------------------------------------------------------------------

def _copson_G1(t, bm):
    """G'(t)/(mu p0) from the defining integrals (quadrature + finite differences), p0 = a = 1.

    G_N(t) = -2 pi int_t^1 sqrt(1-u^2) sqrt(u^2-t^2) du  (Copson transform of the slip-traction
    potential), G_U(t) - U(0) = t int_0^t U'(r)/sqrt(t^2-r^2) dr with U' = P(r)/r.
    """
    def GN(t):
        return -2 * np.pi * quad(lambda u: np.sqrt((1 - u * u) * (u * u - t * t)), t, 1,
                                 epsabs=1e-14, epsrel=1e-13)[0]

    def GU(t):
        w = lambda r: 2 * np.pi / 3 * (1 - (1 - r * r) ** 1.5) / r  # noqa: E731
        return t * quad(lambda th: w(t * np.sin(th)), 0, np.pi / 2, epsabs=1e-14, epsrel=1e-13)[0]

    h = 1e-4
    return bm * _num_deriv(GU, t, h) - _num_deriv(GN, t, h)


@pytest.mark.parametrize("b", [0.2, 0.5, 0.8, 0.95])
def test_spence_closed_form_matches_copson_transforms(b):
    """beta/mu = b K(sqrt(1-b^2))/artanh b  <=>  d/dt[G'(t)/t^2] = 0 at t = b (module doc)."""
    bm = spence_beta_over_mu(b)
    h = 1e-3 * (1 - b)
    ratio = lambda t: _copson_G1(t, bm) / t**2  # noqa: E731
    d_ratio = _num_deriv(ratio, b, h)
    scale = abs(_copson_G1(b, bm)) / b**3 + abs(_copson_G1(b, 0.0)) / b**3
    assert abs(d_ratio) < 1e-5 * scale
    # and the elliptic reduction of each transform
    for t in (0.3, b):
        m = 1 - t * t
        exact = bm * np.pi * (t + m * np.arctanh(t)) - 2 * np.pi * t * (ellipk(m) - ellipe(m))
        assert _copson_G1(t, bm) == pytest.approx(exact, rel=1e-7)


def test_spence_table_limits_and_inverse():
    # brentq on b K(sqrt(1-b^2))/artanh(b) = beta/mu, computed separately to 1e-15
    table = {0.2: 0.9999996986, 0.5: 0.9962276537, 0.75: 0.9680646012, 1.0: 0.9037539643,
             1.5: 0.7014982038, 2.0: 0.4851269303, 3.0: 0.1953222274, 5.0: 0.0269387478}
    for bm, ca in table.items():
        assert spence_stick_ratio(bm) == pytest.approx(ca, rel=1e-8)
        assert spence_stick_ratio(-bm) == spence_stick_ratio(bm)
    b = np.array([1e-9, 1e-3, 0.1, 0.5, 0.9, 0.999, 1 - 1e-9])
    np.testing.assert_allclose(spence_stick_ratio(spence_beta_over_mu(b)), b, rtol=1e-12)
    bm = np.logspace(-0.8, 1.4, 31)         # below ~0.1, 1 - c/a < 1e-16 (rounds to 1)
    ca = spence_stick_ratio(bm)
    assert np.all(np.diff(ca) < 0)
    np.testing.assert_allclose(spence_beta_over_mu(ca), bm, rtol=1e-10)
    assert spence_stick_ratio(0.0) == 1.0 and spence_stick_ratio(np.inf) == 0.0
    assert spence_beta_over_mu(0.0) == np.inf and spence_beta_over_mu(1.0) == 0.0
    # asymptotes: 1 - c/a ~ 2 exp(-pi mu/beta) (slow approach to full stick), c/a ~ 4 exp(-beta/mu)
    assert 1 - spence_stick_ratio(0.25) == pytest.approx(2 * np.exp(-np.pi / 0.25), rel=1e-2)
    assert spence_stick_ratio(12.0) == pytest.approx(4 * np.exp(-12.0), rel=1e-3)
    with pytest.raises(InputError):
        spence_beta_over_mu(1.5)


@pytest.mark.parametrize("bm", [0.8, 1.5, 2.5])
def test_spence_traction_is_admissible(bm):
    b = spence_stick_ratio(bm)
    rho = np.linspace(0.0, 0.999, 300)
    q = spence_traction(rho, bm)
    p = np.sqrt(1 - rho**2)
    assert q[0] == 0.0
    assert np.all(q >= -1e-12) and np.all(q <= p * (1 + 1e-9))          # 0 <= q <= mu p
    np.testing.assert_allclose(q[rho > b], p[rho > b], rtol=1e-12)
    assert np.all(q[rho < 0.98 * b] < p[rho < 0.98 * b])
    # q and dq/drho continuous at the stick boundary (the selection condition), q ~ (c-r)^(3/2)
    eps = 1e-3
    q_in = spence_traction([b - 2 * eps, b - eps], bm)
    p_in = np.sqrt(1 - np.array([b - 2 * eps, b - eps]) ** 2)
    deficit = p_in - q_in                      # (c - r)^(3/2), not (c - r)^(1/2) or (c - r)
    assert deficit[0] / deficit[1] == pytest.approx(2**1.5, rel=0.03)
    assert np.all(spence_traction(rho, -bm) == -q)
    assert spence_traction(1.2, bm) == 0.0


def _ring_radial_matrix(N):
    """Radial displacement at band centres from unit radial traction on bands of width 1/N.

    Only the longitudinal (curl-free) part of the tangential compliance acts on an axisymmetric
    radial field, and its sum over both bodies is 2/E*: u = (1/(pi E*)) int q_vec/rho dA
    (E* = 1).  Ring integral of cos(theta)/rho in closed form (elliptic integrals).
    """
    h = 1.0 / N
    e = np.arange(N + 1) * h
    rc = e[:-1] + h / 2

    def ring(r, s):
        m = np.minimum(4 * r * s / (r + s) ** 2, 1 - 1e-16)
        return 4.0 / ((r + s) * m) * ((2 - m) * ellipk(m) - 2 * ellipe(m))

    xg, wg = np.polynomial.legendre.leggauss(8)
    A = np.empty((N, N))
    for j in range(N):
        s = e[j] + (xg + 1) / 2 * h
        A[:, j] = (ring(rc[:, None], s[None, :]) * s * wg * h / 2).sum(1)
        for i in range(max(0, j - 1), min(N, j + 2)):
            f = lambda s, i=i: s * ring(rc[i], s)  # noqa: E731
            if i == j:
                A[i, j] = (quad(f, e[j], rc[i], limit=200)[0]
                           + quad(f, rc[i], e[j + 1], limit=200)[0])
            else:
                A[i, j] = quad(f, e[j], e[j + 1], limit=200)[0]
    return A / np.pi, rc, e, h


def _incremental_ring_solution(beta, mu, N=120, a0=0.1, growth=1.02):
    """Independent check: march a Hertz contact (E* = R = 1, pressure Hertzian) from a0 to 1
    with Coulomb friction and history (slip increments measured from the previous step).
    Each step is the box QP  min 1/2 q.Mq + q.(area (s_p - u_prev)),  |q| <= mu p."""
    A, rc, e, h = _ring_radial_matrix(N)
    area = 2 * np.pi * rc * h
    u_prev = np.zeros(N)
    a = a0
    while True:
        p = 2 * a / np.pi * np.sqrt(np.clip(1 - (rc / a) ** 2, 0, None))
        Pr = 4 / 3 * (a**3 - np.clip(a * a - rc * rc, 0, None) ** 1.5)   # load inside r
        sp = -(beta / np.pi) * Pr / rc                      # -C_c P(r)/r, C_c = beta/(pi E*)
        idx = np.flatnonzero(p > 0)
        M = area[idx, None] * A[np.ix_(idx, idx)]
        L = cholesky(0.5 * (M + M.T), lower=True)
        rhs = -solve_triangular(L, area[idx] * (sp[idx] - u_prev[idx]), lower=True)
        q = np.zeros(N)
        q[idx] = lsq_linear(L.T, rhs, bounds=(-mu * p[idx], mu * p[idx]), method="bvls",
                            tol=1e-12).x
        u_prev = A @ q + sp
        if a >= 1.0:
            break
        a = min(a * growth, 1.0)
    stick = (p > 0) & (np.abs(q) < mu * p * (1 - 1e-6))
    c = e[stick.nonzero()[0].max() + 1]           # outer edge of the last stuck band (+0..h)
    return c, rc, q / (mu * 2 / np.pi)


def test_spence_against_incremental_ring_solution():
    """c/a and q(r) of the closed form against a direct history-dependent solution (coarse:
    120 bands, 2 % load steps; c is resolved to a band, 1/120)."""
    bm = 1.5
    c, rc, q_num = _incremental_ring_solution(beta=0.3, mu=0.3 / bm)
    assert c == pytest.approx(spence_stick_ratio(bm), abs=0.02)
    sel = (rc > 0.1) & (rc < 0.97)                 # the band at r = 0 is not resolved
    np.testing.assert_allclose(q_num[sel], spence_traction(rc[sel], bm), atol=0.01)


@pytest.mark.slow
@pytest.mark.parametrize("bm", [0.75, 1.0, 2.0, 3.0])
def test_spence_against_fine_incremental_ring_solution(bm):
    """The same on 400 bands with 0.5 % load steps (minutes)."""
    c, rc, q_num = _incremental_ring_solution(beta=0.3, mu=0.3 / bm, N=400, a0=0.05, growth=1.005)
    assert c == pytest.approx(spence_stick_ratio(bm), abs=0.006)
    sel = (rc > 0.1) & (rc < 0.99)                 # piecewise-constant q is poor near r = 0
    np.testing.assert_allclose(q_num[sel], spence_traction(rc[sel], bm), atol=0.004)


def test_spence_beta_from_contact_pair():
    """beta of a rigid ball on nu = 0.3 (Paper D) and the resulting stick ratio for mu = 0.2."""
    beta = ContactPair(Material(130e9, 0.3), Material.rigid()).dundurs_beta
    assert beta == pytest.approx((1 - 2 * 0.3) / (2 * (1 - 0.3)), rel=1e-12)
    assert spence_stick_ratio(beta / 0.2) == pytest.approx(spence_stick_ratio(0.4 / 1.4 / 0.2),
                                                           rel=1e-12)
    assert 0.7 < spence_stick_ratio(beta / 0.2) < 0.75
