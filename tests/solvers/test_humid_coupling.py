"""The coupling loop with the capillary model (humid friction): shear only on the compressive
contact, every prescribed stress in the force balance, islands that do not settle flagged, and
the counterface's film moving with it."""

import warnings

import numpy as np
import pytest

from tribobem.errors import ConvergenceWarning
from tribobem.grid import Grid
from tribobem.runs.humid_friction import capillary_model
from tribobem.scenario.build import build_problem
from tribobem.scenario.schema import parse_scenario
from tribobem.solvers.capillary import CapillaryModel
from tribobem.solvers.coupling import solve_coupled

F = 1e-6
MU = 0.3


def _problem(n=48):
    """A rigid SiO2 sphere (R = 1 um) on an elastic Si flat: a dissimilar pair (coupled)."""
    sc = parse_scenario({
        "kind": "partial_slip",
        "grid": {"n": n, "size": "0.3 um"},
        "body1": {"E": "130 GPa", "nu": 0.28, "film": {"isotherm": "Si"}},
        "body2": {"rigid": True, "shape": {"kind": "sphere", "radius": "1 um"}, "film": {"isotherm": "SiO2"}},
        "load": {"force": "1 uN"},
        "friction": {"coefficient": MU, "tangential_forces": [0.0]},
        "humidity": {"rh": [0.5], "van_der_waals": False},
    })
    return build_problem(sc)


@pytest.fixture(scope="module")
def humid_state():
    pb = _problem()
    model, _, _ = capillary_model(pb, 0.5, 1e-10)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ConvergenceWarning)
        zero = solve_coupled(pb.operator, pb.gap, friction_coefficient=MU, normal_force=F, interaction=model)
        ft = 0.6 * MU * zero.normal.repulsive_force
        res = solve_coupled(pb.operator, pb.gap, friction_coefficient=MU, normal_force=F, interaction=model,
                            tangential_force=(ft, 0.0), initial=zero)
    return pb, model, res, ft


def test_shear_acts_on_the_compressive_contact_only_never_in_a_meniscus(humid_state):
    pb, _, res, ft = humid_state
    assert res.converged, res.message
    cap = res.capillary
    p = np.asarray(res.normal.pressure)
    contact = np.asarray(res.normal.contact, bool)
    meniscus = np.asarray(cap.islands.active, bool) & ~contact
    assert meniscus.sum() > 5 * contact.sum() > 0  # the meniscus is much wider than the contact
    q = np.hypot(*np.asarray(res.tangential.shear))
    assert np.all(q[~(contact & (p > 0))] == 0.0)
    assert np.all(q[meniscus] == 0.0)
    # the shear carries the whole tangential force within the Coulomb bound
    qx = np.asarray(res.tangential.shear[0])
    assert abs(qx.sum() * pb.grid.cell_area - ft) / ft < 1e-6
    assert np.all(q <= MU * np.maximum(p, 0.0) * (1 + 1e-9) + 1e-300)


def test_force_balance_includes_every_prescribed_stress(humid_state):
    _, _, res, _ = humid_state
    cap = res.capillary
    parts = cap.contact_force + cap.capillary_force + cap.solid_solid_force + cap.water_solid_force
    assert abs(cap.total_force - F) / F < 1e-8
    assert abs(parts - F) / F < 1e-8
    assert cap.capillary_force < -F  # the meniscus pulls harder than the load pushes (R = 1 um, RH 0.5)
    assert abs(res.normal.repulsive_force - (F - cap.capillary_force)) / F < 1e-6
    row = res.scalars()
    assert row["capillary_force"] == cap.capillary_force and row["island_count"] == 1
    assert row["islands_converged"] and row["converged"]


def test_islands_that_cycle_are_flagged_and_the_step_returns(monkeypatch):
    """An island fixed point that cycles inside a tangential step: the step comes back with
    converged = False and a ConvergenceWarning naming the islands; the state is usable."""
    import tribobem.solvers.capillary as capmod

    real = capmod.island_fixed_point

    def cycling(islands, step, max_outer):
        state, used, outer, _, history = real(islands, step, max_outer)
        return state, used, outer, "cycle", history

    monkeypatch.setattr(capmod, "island_fixed_point", cycling)
    pb = _problem(32)
    model, _, _ = capillary_model(pb, 0.5, 1e-10)
    with pytest.warns(ConvergenceWarning, match="meniscus islands: the island fixed point cycles"):
        res = solve_coupled(pb.operator, pb.gap, friction_coefficient=MU, normal_force=F, interaction=model,
                            tangential_force=(0.1 * MU * F, 0.0))
    assert not res.converged and not res.capillary.converged
    assert res.scalars()["islands_converged"] is False and res.scalars()["converged"] is False
    assert abs(res.tangential.force_x - 0.1 * MU * F) < 1e-9 * F


def test_counterface_film_moves_with_it_without_accumulating_error():
    g = Grid.square(64, 1e-6, periodic=True)
    x, y = g.meshgrid()
    k = 2 * np.pi / g.lx
    film = 1e-9 * (1.2 + np.sin(k * x))
    m = CapillaryModel(np.zeros(g.shape), film, {}, g)
    quarter = (g.lx / 4, 0.0)
    moved = m.moved(quarter)
    # body 2 moved by +lx/4: its film value at x is the one that was at x - lx/4
    np.testing.assert_allclose(moved.film2, 1e-9 * (1.2 - np.cos(k * x)), atol=1e-21)
    np.testing.assert_array_equal(moved.film1, m.film1)  # body 1's film stays
    # a path of small moves ends where one move to the total offset does (each from the origin)
    path = m
    for step in np.linspace(0, g.lx / 4, 7)[1:]:
        path = path.moved((step, 0.0))
    np.testing.assert_allclose(path.film2, moved.film2, atol=1e-21)
    assert path.offset == quarter


def test_humid_loop_on_a_window_equals_the_whole_grid():
    """Without van der Waals terms the capillary model's stresses have a finite support (active
    menisci, Dugdale zone): a loop solved on a window around them is the whole grid's loop."""
    from tribobem.solvers.hysteresis import hysteresis_loop

    pb = _problem(48)
    model, _, _ = capillary_model(pb, 0.5, 1e-10)
    kw = dict(normal_force=F, friction_coefficient=MU, amplitude=0.8, cycles=1, steps=8, interaction=model,
              tol=1e-10, tangential_tol=1e-9, coupling_tol=1e-8)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ConvergenceWarning)
        win = hysteresis_loop(pb.operator, pb.gap, window=True, **kw)
        full = hysteresis_loop(pb.operator, pb.gap, window=False, **kw)
    assert "window" in win.steps[-1].normal.info  # it did run on a window
    assert "window" not in full.steps[-1].normal.info
    for a, b in zip(win.steps, full.steps):
        assert a.converged and b.converged
        assert abs(a.tangential.displacement_x - b.tangential.displacement_x) <= 1e-6 * abs(b.tangential.displacement_x) + 1e-15
        assert abs(a.capillary.capillary_force - b.capillary.capillary_force) <= 1e-6 * abs(b.capillary.capillary_force)
        assert a.capillary.islands.active.shape == pb.grid.shape  # the whole grid's islands on the result
        np.testing.assert_array_equal(a.capillary.islands.active, b.capillary.islands.active)


def test_a_window_that_cuts_the_meniscus_grows_to_hold_it():
    from tribobem.solvers.window import Window, solve_coupled_windowed

    pb = _problem(48)
    model, _, _ = capillary_model(pb, 0.5, 1e-10)
    n = pb.grid.nx
    small = Window(n // 2 - 6, n // 2 + 6, n // 2 - 6, n // 2 + 6)  # the contact only, not the meniscus
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ConvergenceWarning)
        res, used = solve_coupled_windowed(small, pb.operator, pb.gap, interaction=model, friction_coefficient=MU,
                                           normal_force=F, tangential_force=(0.2 * MU * F, 0.0))
        ref = solve_coupled(pb.operator, pb.gap, friction_coefficient=MU, normal_force=F, interaction=model,
                            tangential_force=(0.2 * MU * F, 0.0))
    assert used is None or used.shape[0] > small.shape[0]
    men = np.asarray(ref.capillary.islands.active)
    if used is not None:
        inside = np.zeros(pb.grid.shape, bool)
        inside[used.i0:used.i1, used.j0:used.j1] = True
        assert not (men & ~inside).any()
    assert abs(res.capillary.capillary_force / ref.capillary.capillary_force - 1) < 1e-6
    assert abs(res.normal.repulsive_force / ref.normal.repulsive_force - 1) < 1e-6
