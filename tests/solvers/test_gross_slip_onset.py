"""The gross-slip onset: TangCG on states without stick, and the onset search of the ramp.

* TangCG solves a force-controlled state in which every node slips (a coupled contact above its
  onset, below mu F0+) itself: converged, no projected-gradient fallback, Coulomb's law on every
  node (|q| = mu p, slip opposite to the traction), and the projected gradient's solution.
* ``unused_friction`` is 1 - Q/(mu P) on Cattaneo-Mindlin (the tractions all point along x).
* ``_locate_onset``: on synthetic indicators G = C (F* - F)^p the bracket closes around F* within
  the required width in at most 4 probes (bisection: 7); on an indicator that misleads the
  extrapolation it still closes (bisection fallback).
* ``_locate_onset_displacement``: displacement-controlled probes on a synthetic ramp bracket
  the onset in force within the required width (with and without the estimate).
* ``tangential_ramp`` on Paper D 3.1 (32^2): the same onset as a pure bisection, within the
  required width, in fewer solves; with displacement-controlled probes (the default from
  512^2 nodes, asked for here) the brackets overlap the force bisection's.
"""

from __future__ import annotations

import math
import warnings
from types import SimpleNamespace

import numpy as np
import pytest

from tribobem import ConvergenceWarning
from tribobem.solvers import tangential_paths
from tribobem.solvers.coupling import solve_coupled
from tribobem.solvers.tangential_paths import _locate_onset, tangential_ramp, unused_friction
from tribobem.solvers.tangential import solve_tangential
from tribobem.validation.tangential import cattaneo_problem, paper_d_problem

MU_D = 0.2


@pytest.fixture(scope="module")
def paper_d_zero():
    grid, gap, op, pair, a, F0 = paper_d_problem(32)
    z = solve_coupled(op, gap, friction_coefficient=MU_D, normal_force=F0)
    return op, gap, F0, z


def test_tangcg_solves_a_state_without_stick_itself(paper_d_zero):
    op, gap, F0, z = paper_d_zero
    p, contact = z.normal.pressure, z.normal.contact
    cap = MU_D * z.normal.repulsive_force
    F = (0.97 * cap, 0.0)  # above the coupled onset (0.91 mu F0+ here), below mu F0+
    cg = solve_tangential(op, p, contact, friction_coefficient=MU_D, force=F, tol=1e-10)
    assert cg.converged, cg.message
    assert "projected gradient" not in cg.message  # the old TangCG handed this state over
    assert cg.gross_slip and not cg.stick.any()
    assert cg.force_x == pytest.approx(F[0], rel=1e-10) and abs(cg.force_y) < 1e-10 * F[0]
    c = contact & (p > 0)
    qm = np.hypot(*cg.shear)[c]
    np.testing.assert_allclose(qm, MU_D * p[c], rtol=1e-8)
    # slip opposite to the traction: no perpendicular part, negative along it
    sx, sy = cg.slip[0][c], cg.slip[1][c]
    qx, qy = cg.shear[0][c], cg.shear[1][c]
    smag = np.hypot(sx, sy)
    scale = cg.info["slip_scale"]
    assert np.abs(sx * qy - sy * qx).max() / (qm.max() * scale) < 1e-6
    assert np.all(sx * qx + sy * qy <= 1e-6 * scale * qm)
    assert smag.max() > 1e-3 * scale  # it really slips
    # the same state as the projected gradient's, in far fewer iterations
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ConvergenceWarning)
        pg = solve_tangential(op, p, contact, friction_coefficient=MU_D, force=F, tol=1e-10, method="fista")
    assert pg.converged
    np.testing.assert_allclose(cg.shear, pg.shear, atol=1e-6 * MU_D * p.max())
    assert cg.displacement_x == pytest.approx(pg.displacement_x, rel=1e-5)
    assert cg.iterations < pg.iterations


def test_unused_friction_is_one_minus_q_over_mu_p_for_cattaneo_mindlin():
    from tribobem.solvers.normal import solve_normal

    grid, gap, op, pair, a = cattaneo_problem(64)
    mu, P = 0.3, 10.0
    nr = solve_normal(op, gap, force=P, tol=1e-12)
    for ratio in (0.3, 0.7):
        t = solve_tangential(op, nr.pressure, nr.contact, friction_coefficient=mu, force=(ratio * mu * P, 0.0),
                             tol=1e-10)
        res = SimpleNamespace(tangential=t, normal=nr)
        assert unused_friction(res) == pytest.approx(1.0 - ratio, abs=2e-3)
    # no stick: nothing unused
    t.stick[...] = False
    assert unused_friction(SimpleNamespace(tangential=t, normal=nr)) == 0.0


class _Calls(list):
    def __init__(self):
        super().__init__()
        self.starts = []


def _synthetic(G, F0=1.0, mu=1.0):
    """probe(value, start) for an indicator G(F) (> 0 with stick, <= 0: gross slip) and its call
    log (the probed values; ``calls.starts``: the warm start of each probe)."""
    calls = _Calls()

    def state(value):
        return SimpleNamespace(F=value, G=max(G(value), 0.0), normal=SimpleNamespace(repulsive_force=F0),
                               tangential=SimpleNamespace(gross_slip=G(value) <= 0))

    def probe(value, start=None, extra=None):
        calls.append(value)
        calls.starts.append(start)
        s = state(value)
        return s.tangential.gross_slip, (None if s.tangential.gross_slip else s)

    return probe, state, calls


@pytest.mark.parametrize("p", [1.0, 1.5])
@pytest.mark.parametrize("onset", [0.917, 0.9855, 0.9991])
def test_onset_search_on_power_laws(monkeypatch, p, onset):
    monkeypatch.setattr(tangential_paths, "unused_friction", lambda res: res.G)
    probe, state, calls = _synthetic(lambda F: 0.3 * max(onset - F, -1.0) ** p if F < onset else onset - F)
    lo, hi = 0.8, 1.0  # the ramp's last step with stick and the first without (steps of 0.1)
    out = _locate_onset(probe, lo, hi, state(lo), (0.7, state(0.7)), 1e-3, 1.0, 40, True, 1.0)
    lo, hi, lo_res, n = out
    assert lo <= onset < hi and hi - lo <= 1e-3
    assert not lo_res.tangential.gross_slip and lo_res.G > 0
    assert n == len(calls) <= 4  # the bisection of the 0.2 bracket to 1e-3 takes 8
    # each probe starts from the nearest state with stick below it: the bracket's lower end
    below = 0.8
    for value, start in zip(calls, calls.starts):
        assert start.F == below and start.F < value
        if not state(value).tangential.gross_slip:
            below = value


def test_onset_search_survives_a_misleading_indicator(monkeypatch):
    # unused friction that stays flat and then drops within 1e-4: every extrapolation is far off
    onset = 0.9373

    def G(F):
        if F >= onset:
            return onset - F
        return 0.2 if F < onset - 1e-4 else 0.2 * (onset - F) / 1e-4

    monkeypatch.setattr(tangential_paths, "unused_friction", lambda res: res.G)
    probe, state, calls = _synthetic(G)
    lo, hi, lo_res, n = _locate_onset(probe, 0.8, 1.0, state(0.8), (0.7, state(0.7)), 1e-3, 1.0, 40, True, 1.0)
    assert lo <= onset < hi and hi - lo <= 1e-3
    assert n <= 12


def _synthetic_displacement(d_star, p, Q_star=0.985, slope_above=0.02):
    """probe(delta, start, extra) on a synthetic displacement ramp: G = 0.3 (d* - d)^p below the
    onset d*, Q(d) rising as Cattaneo-Mindlin's 1 - (1 - d/d*)^1.5 scaled to Q* at d* and then
    slowly (``slope_above``) beyond it; with the call log."""
    calls = []

    def Q(d):
        if d < d_star:
            return Q_star * (1.0 - (1.0 - d / d_star) ** 1.5)
        return Q_star + slope_above * (d - d_star)

    def state(d):
        gross = d >= d_star
        return SimpleNamespace(d=d, Q=Q(d), G=0.0 if gross else 0.3 * (d_star - d) ** p,
                               normal=SimpleNamespace(repulsive_force=1.0),
                               tangential=SimpleNamespace(gross_slip=gross))

    def probe(d, start=None, extra=None):
        calls.append((d, start))
        s = state(d)
        return s.tangential.gross_slip, s

    return probe, state, calls


@pytest.mark.parametrize("p", [1.0, 1.5])
@pytest.mark.parametrize("d_star", [0.93, 1.0, 1.3])
@pytest.mark.parametrize("estimate", [True, False])
def test_displacement_onset_search_brackets_the_force(monkeypatch, p, d_star, estimate):
    monkeypatch.setattr(tangential_paths, "unused_friction", lambda res: res.G)
    if not estimate:
        monkeypatch.setattr(tangential_paths, "_extrapolate_onset", lambda pts: None)  # pure bisection in delta
    probe, state, calls = _synthetic_displacement(d_star, p)
    Q_star = state(d_star).Q
    # the force ramp: last step with stick at delta = 0.7 (before it 0.6), first without at Q = 1
    lo, before = state(0.7), state(0.6)
    q_lo, q_hi, lo_res, n = tangential_paths._locate_onset_displacement(
        probe, lo, before, 1.0, 1e-3, 1.0, 40, lambda r: r.d, lambda r: r.Q, 0.0)
    assert q_lo <= Q_star < q_hi and q_hi - q_lo <= 1e-3
    assert not lo_res.tangential.gross_slip and lo_res.Q == q_lo
    assert n == len(calls) <= (4 if estimate else 8)  # measured: 2-3 and 6
    # each probe starts from the nearest state with stick below it
    below = 0.7
    for d, start in calls:
        assert start.d == below < d
        if d < d_star:
            below = d


def test_ramp_onset_in_displacement_equals_the_force_bisection(monkeypatch):
    grid, gap, op, pair, a, F0 = paper_d_problem(32)
    forces = [0.0, 0.5e-6, 1.0e-6, 1.5e-6, 2.0e-6]
    kw = dict(normal_force=F0, friction_coefficient=MU_D, forces=forces, refine_tol=1e-3)
    auto = tangential_ramp(op, gap, **kw)  # 32^2: below DISPLACEMENT_ONSET_NODES, the force search
    assert "displacement-controlled" not in auto.message
    smart = tangential_ramp(op, gap, onset_by="displacement", **kw)
    assert "displacement-controlled probes" in smart.message
    monkeypatch.setattr(tangential_paths, "_extrapolate_onset", lambda pts: None)  # pure bisection
    plain = tangential_ramp(op, gap, onset_by="force", **kw)
    assert "displacement-controlled" not in plain.message
    assert auto.onset_bracket != smart.onset_bracket
    need = 1e-3 * MU_D * smart.onset_state.normal.repulsive_force
    (l1, h1), (l2, h2) = smart.onset_bracket, plain.onset_bracket
    assert h1 - l1 <= need and h2 - l2 <= need
    assert max(l1, l2) < min(h1, h2)  # the brackets overlap: the same onset
    assert abs(smart.onset - plain.onset) <= need
    # the state at the lower end: its force is the bracket's, and the same pre-sliding curve
    assert smart.onset_state.tangential.force_x == pytest.approx(l1, rel=1e-9)
    assert math.isclose(smart.onset_ratio, plain.onset_ratio, rel_tol=2e-3)
    assert math.isclose(smart.presliding_displacement, plain.presliding_displacement, rel_tol=2e-2)


def test_ramp_onset_equals_the_bisection(monkeypatch):
    grid, gap, op, pair, a, F0 = paper_d_problem(32)
    forces = [0.0, 0.5e-6, 1.0e-6, 1.5e-6, 2.0e-6]
    kw = dict(normal_force=F0, friction_coefficient=MU_D, forces=forces, refine_tol=1e-3, onset_by="force")
    smart = tangential_ramp(op, gap, **kw)
    monkeypatch.setattr(tangential_paths, "_extrapolate_onset", lambda pts: None)  # pure bisection
    plain = tangential_ramp(op, gap, **kw)
    need = 1e-3 * MU_D * smart.onset_state.normal.repulsive_force
    (l1, h1), (l2, h2) = smart.onset_bracket, plain.onset_bracket
    assert h1 - l1 <= need and h2 - l2 <= need
    assert max(l1, l2) < min(h1, h2)  # the brackets overlap: the same onset
    assert abs(smart.onset - plain.onset) <= need
    assert smart.refine_steps < plain.refine_steps
    assert math.isclose(smart.onset_ratio, plain.onset_ratio, rel_tol=2e-3)


def test_force_at_mu_fn_without_adhesion_is_gross_slip_before_any_solve(paper_d_zero, monkeypatch):
    import tribobem.solvers.coupling as C
    from tribobem.solvers.tangential import GrossSlipError

    op, gap, F0, z = paper_d_zero
    calls = []
    monkeypatch.setattr(C, "solve_normal", lambda *a, **k: calls.append(1))
    monkeypatch.setattr(C, "solve_tangential", lambda *a, **k: calls.append(2))
    for f in (MU_D * F0, (0.0, 1.2 * MU_D * F0)):
        with pytest.raises(GrossSlipError, match="mu F0\\+") as err:
            solve_coupled(op, gap, friction_coefficient=MU_D, normal_force=F0, tangential_force=f, initial=z)
        assert err.value.max_force == pytest.approx(MU_D * F0, rel=1e-12)
    assert calls == []  # known without a solve: the contact carries exactly F_N
