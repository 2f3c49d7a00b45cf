"""Rounded and sharp flat punches, Kendall's pull-off, the full-stick stiffness (analytic.punch).

The closed forms are checked against a direct quadrature of Sneddon's integrals, against their
limits (Hertz for b -> 0, the flat punch for R -> 0) and against an independent derivation
(Kendall by the compliance method).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import quad

from tribobem.analytic import hertz
from tribobem.analytic.punch import (
    bonded_punch_stiffness,
    flat_punch,
    flat_punch_pressure,
    full_stick_stiffness,
    kendall_pull_off,
    rounded_punch,
    rounded_punch_approach,
    rounded_punch_force,
)
from tribobem.errors import InputError

E_STAR = 100e9


def _sneddon(a, fprime):
    """delta = a int f'/sqrt(a^2-r^2), P = 2 E* int r^2 f'/sqrt(a^2-r^2), by quadrature with the
    algebraic end-point weight (a different route from the closed forms)."""
    w = dict(weight="alg", wvar=(0.0, -0.5))  # (r - 0)^0 (a - r)^-0.5
    d, _ = quad(lambda r: fprime(r) / math.sqrt(a + r), 0.0, a, **w, epsabs=0, epsrel=1e-12, limit=200)
    P, _ = quad(lambda r: r * r * fprime(r) / math.sqrt(a + r), 0.0, a, **w, epsabs=0, epsrel=1e-12, limit=200)
    return a * d, 2.0 * E_STAR * P


@pytest.mark.parametrize("a_over_b", [1.001, 1.2, 2.0, 5.0])
@pytest.mark.parametrize("crown", [None, 3e-3])
def test_closed_form_matches_sneddon_quadrature(a_over_b, crown):
    b, R = 1e-6, 20e-6
    a = a_over_b * b

    def fprime(r):
        v = max(r - b, 0.0) / R
        return v + (r / crown if crown else 0.0)

    d_ref, P_ref = _sneddon(a, fprime)
    assert rounded_punch_approach(a, b, R, crown) == pytest.approx(d_ref, rel=1e-9)
    assert rounded_punch_force(a, b, R, E_STAR, crown) == pytest.approx(P_ref, rel=1e-9)


def test_no_flat_is_hertz():
    R, P = 10e-6, 1e-3
    h = hertz(force=P, radius=R, E_star=E_STAR)
    s = rounded_punch(force=P, flat_radius=0.0, edge_radius=R, E_star=E_STAR)
    assert s.contact_radius == pytest.approx(h.contact_radius, rel=1e-10)
    assert s.approach == pytest.approx(h.approach, rel=1e-10)


def test_sharp_edge_limit_is_the_flat_punch():
    # R -> 0 at a fixed load: a -> b and delta -> P/(2 b E*); the rounded zone a - b ~ R^(2/3)
    b, P = 1e-6, 1e-2
    flat = flat_punch(force=P, radius=b, E_star=E_STAR)
    errs = []
    for R in (1e-8, 1e-10, 1e-12):
        s = rounded_punch(force=P, flat_radius=b, edge_radius=R, E_star=E_STAR)
        errs.append(abs(s.approach / flat.approach - 1))
        assert s.contact_radius > b
    assert errs[-1] < 2e-3 and errs[0] > errs[1] > errs[2]
    s = rounded_punch(force=P, flat_radius=b, edge_radius=1e-12, E_star=E_STAR)
    assert s.contact_radius == pytest.approx(b, rel=1e-3)


def test_inversions_round_trip_and_grow():
    b, R = 1e-6, 50e-6
    for a in (1.05e-6, 1.5e-6, 3e-6):
        P = rounded_punch_force(a, b, R, E_STAR)
        d = rounded_punch_approach(a, b, R)
        kw = dict(flat_radius=b, edge_radius=R, E_star=E_STAR)
        assert rounded_punch(force=P, **kw).contact_radius == pytest.approx(a, rel=1e-10)
        assert rounded_punch(approach=d, **kw).contact_radius == pytest.approx(a, rel=1e-10)
    z = rounded_punch(force=0.0, flat_radius=b, edge_radius=R, E_star=E_STAR)
    assert z.contact_radius == b and z.approach == 0.0 and z.force == 0.0
    # the rounded punch is more compliant than the sharp flat punch of radius a at the same load
    s = rounded_punch(force=1e-2, flat_radius=b, edge_radius=R, E_star=E_STAR)
    assert s.approach > s.flat_punch_approach
    with pytest.raises(InputError, match="contact_radius"):
        rounded_punch(contact_radius=0.5e-6, flat_radius=b, edge_radius=R, E_star=E_STAR)


def test_crowned_burl_is_hertz_until_the_edge():
    b, R, Rc = 1e-6, 50e-6, 1e-3
    a = 0.8 * b
    h = hertz(approach=a * a / Rc, radius=Rc, E_star=E_STAR)
    s = rounded_punch(contact_radius=a, flat_radius=b, edge_radius=R, E_star=E_STAR, crown=Rc)
    assert s.force == pytest.approx(h.force, rel=1e-12)
    # continuous through a = b (the edge term starts at zero with zero slope)
    lo = rounded_punch(contact_radius=b * (1 - 1e-9), flat_radius=b, edge_radius=R, E_star=E_STAR, crown=Rc)
    hi = rounded_punch(contact_radius=b * (1 + 1e-9), flat_radius=b, edge_radius=R, E_star=E_STAR, crown=Rc)
    assert hi.force == pytest.approx(lo.force, rel=1e-6)


def test_flat_punch_pressure_carries_the_load():
    b, P = 1e-6, 1e-3
    sol = flat_punch(force=P, radius=b, E_star=E_STAR)
    assert sol.approach == pytest.approx(P / (2 * b * E_STAR), rel=1e-14)
    # r = b sin(phi) removes the edge singularity; Gauss-Kronrod never evaluates phi = pi/2
    total, _ = quad(lambda f: 2 * math.pi * b * math.sin(f) * flat_punch_pressure(b * math.sin(f), P, b)
                    * b * math.cos(f), 0, math.pi / 2, epsabs=0, epsrel=1e-12)
    assert total == pytest.approx(P, rel=1e-9)
    assert flat_punch_pressure(0.0, P, b) == pytest.approx(0.5 * P / (math.pi * b * b), rel=1e-14)


def test_kendall_by_the_compliance_method():
    # G = (P^2 / 2) dC/dA with C(a) = 1/(2 E* a), A = pi a^2; G = dgamma gives the pull-off
    b, w = 2e-6, 0.05
    P = abs(kendall_pull_off(b, w, E_STAR))
    dC_dA = (1.0 / (2 * E_STAR * b * b)) / (2 * math.pi * b)
    assert 0.5 * P * P * dC_dA == pytest.approx(w, rel=1e-12)
    assert kendall_pull_off(b, w, E_STAR) < 0


def test_full_stick_stiffness_and_the_bonded_punch():
    a, E = 1e-6, 3e9
    G = E / 3.0
    # nu = 0.5 on a rigid counterface: no coupling, 8 G a/(2 - nu) = bonded punch
    K = full_stick_stiffness(a, E, 0.5, math.inf, 0.0)
    assert K == pytest.approx(8 * G * a / 1.5, rel=1e-14)
    assert bonded_punch_stiffness(a, E, 0.5) == pytest.approx(K, rel=1e-14)
    # nu = 0: the coupling stiffens the bonded punch by 8/7
    K0 = full_stick_stiffness(a, E, 0.0, math.inf, 0.0)
    assert bonded_punch_stiffness(a, E, 0.0) / K0 == pytest.approx(8 / 7, rel=1e-12)
    # identical bodies: half the rigid-counterface stiffness
    assert full_stick_stiffness(a, E, 0.3, E, 0.3) == pytest.approx(0.5 * full_stick_stiffness(a, E, 0.3, math.inf, 0), rel=1e-14)


def test_bad_arguments_name_themselves():
    with pytest.raises(InputError, match="edge_radius"):
        rounded_punch(force=1.0, flat_radius=1e-6, edge_radius=0.0, E_star=E_STAR)
    with pytest.raises(InputError, match="exactly one"):
        rounded_punch(force=1.0, approach=1e-9, flat_radius=1e-6, edge_radius=1e-6, E_star=E_STAR)
    with pytest.raises(InputError, match="work_of_adhesion"):
        kendall_pull_off(1e-6, -1.0, E_STAR)
    assert np.isfinite(flat_punch(approach=-1e-9, radius=1e-6, E_star=E_STAR).force)
