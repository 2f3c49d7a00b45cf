"""The library's normal solver default (``solve_normal(method="auto")``) and NormCG's share of
``solve_normal``'s arguments.

* ``method="auto"`` (the default) is the rule of a scenario's ``[solver] method = "auto"``
  (one function, :func:`tribobem.solvers.normal.resolve_method`): NormCG without an outside
  stress law -- on a rough periodic contact the same contact nodes as Polonsky-Keer in fewer
  iterations -- and Polonsky-Keer with Dugdale adhesion (bit for bit the explicit call).
* NormCG honours ``initial_displacement`` (one convolution fewer, the same solution; a warm start
  from the converged state converges at once) and ``precondition`` (False: the unpreconditioned
  bound-constrained CG, ``info["method"] == "bccg"``), which the NormCG branch of
  ``solve_normal`` used to drop.
"""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest

from tribobem import ContactPair, Grid, Material
from tribobem.elasticity import free_boundary_operator, periodic_operator
from tribobem.errors import InputError
from tribobem.geometry.rough import self_affine_surface
from tribobem.geometry.shapes import sphere
from tribobem.interactions import DugdaleAdhesion
from tribobem.runs.common import normal_method
from tribobem.solvers.normal import resolve_method, solve_normal

SILICA = Material(73e9, 0.17, "silica")
PAIR = ContactPair(SILICA, Material.rigid())
E_STAR = PAIR.effective_modulus


def _rough(n=128):
    """The benchmark's rough contact (self-affine, H = 0.8, rms slope 1) at mean pressure 0.01 E*."""
    grid = Grid.square(n, 1e-6, periodic=True)
    s = self_affine_surface(grid, 0.8, rms_slope=1.0, short_cutoff=4 * grid.dx, long_cutoff=grid.lx / 4, seed=3)
    return periodic_operator(grid, PAIR), s.max() - s, 0.01 * E_STAR * grid.lx * grid.ly


@pytest.fixture(scope="module")
def rough():
    op, h, F = _rough()
    default = solve_normal(op, h, force=F, tol=1e-10)
    pk = solve_normal(op, h, force=F, tol=1e-10, method="polonsky_keer")
    cg = solve_normal(op, h, force=F, tol=1e-10, method="normcg")
    return op, h, F, default, pk, cg


def test_default_is_normcg_without_adhesion(rough):
    op, h, F, default, pk, cg = rough
    assert default.converged and pk.converged
    assert default.info["method"] == "normcg" and pk.info["method"] == "polonsky_keer"
    # the explicit NormCG call, bit for bit
    assert default.iterations == cg.iterations
    assert np.array_equal(default.pressure, cg.pressure)
    # the same equilibrium as Polonsky-Keer (the old default) in fewer iterations
    assert 0.02 < default.contact.mean() < 0.5
    assert np.array_equal(default.contact, pk.contact)
    assert np.abs(default.pressure - pk.pressure).max() < 1e-8 * pk.pressure.max()
    assert default.iterations < pk.iterations


def test_default_is_polonsky_keer_with_dugdale():
    grid = Grid.square(64, 1.2e-6)
    op = free_boundary_operator(grid, PAIR)
    h = sphere(grid, 20e-6)
    inter = DugdaleAdhesion(0.05, 0.5e-9)
    default = solve_normal(op, h, force=2e-6, interaction=inter, tol=1e-10)
    pk = solve_normal(op, h, force=2e-6, interaction=inter, tol=1e-10, method="polonsky_keer")
    assert default.converged and default.info["method"] == "polonsky_keer"
    assert default.iterations == pk.iterations
    assert np.array_equal(default.pressure, pk.pressure)
    assert np.array_equal(default.contact, pk.contact) and np.array_equal(default.adhesive, pk.adhesive)
    assert default.adhesive.any()  # a real cohesive zone


@pytest.mark.parametrize("method", ["auto", "polonsky_keer", "normcg"])
@pytest.mark.parametrize("adhesion, humidity", [(False, None), (True, None), (False, object())])
def test_scenario_rule_is_the_library_rule(method, adhesion, humidity):
    """The scenario runners resolve ``[solver] method`` with the library's function."""
    sc = SimpleNamespace(solver=SimpleNamespace(method=method), adhesion=SimpleNamespace(enabled=adhesion),
                         humidity=humidity)
    expected = method if method != "auto" else ("polonsky_keer" if adhesion or humidity is not None else "normcg")
    assert normal_method(sc) == expected
    assert resolve_method(method, adhesion or humidity is not None) == expected


def test_unknown_method_names_the_key():
    op, h, F = _rough(32)
    with pytest.raises(InputError, match=r"^solve_normal\.method: must be 'auto', 'polonsky_keer' or 'normcg'"):
        solve_normal(op, h, force=F, method="newton")


def test_normcg_honours_initial_displacement(rough):
    """The converged state's displacement replaces NormCG's first convolution: the same solution,
    one convolution fewer; restarted from the converged state it converges at once."""
    op, h, F, default, pk, cg = rough
    # the same load, warm from the converged state (force balance scale ~1 to round-off)
    same = solve_normal(op, h, force=F, tol=1e-10, initial_pressure=cg, initial_displacement=cg.displacement)
    assert same.converged and same.info["method"] == "normcg"
    assert same.iterations <= 2
    assert np.array_equal(same.contact, cg.contact)
    # a new load (rescaled start, no outside law: K of the rescaled pressure is the rescaled u)
    plain = solve_normal(op, h, force=1.2 * F, tol=1e-10, initial_pressure=cg)
    given = solve_normal(op, h, force=1.2 * F, tol=1e-10, initial_pressure=cg, initial_displacement=cg.displacement)
    assert plain.converged and given.converged
    assert given.info["convolutions"] == plain.info["convolutions"] - 1
    assert np.array_equal(given.contact, plain.contact)
    assert np.abs(given.pressure - plain.pressure).max() < 1e-8 * plain.pressure.max()
    # displacement control from the converged state's approach (no rescale)
    plain_d = solve_normal(op, h, approach=cg.approach, tol=1e-10, initial_pressure=cg)
    given_d = solve_normal(op, h, approach=cg.approach, tol=1e-10, initial_pressure=cg,
                           initial_displacement=cg.displacement)
    assert given_d.converged and given_d.iterations <= 2
    assert given_d.info["convolutions"] == plain_d.info["convolutions"] - 1
    assert np.array_equal(given_d.contact, cg.contact)
    # a warm start the solver changes (a negative pressure raised to 0): the displacement given
    # is not its K p and is not used
    low = cg.pressure.copy()
    low[np.unravel_index(np.argmax(cg.pressure), low.shape)] = -1.0
    ref = solve_normal(op, h, force=F, tol=1e-10, initial_pressure=low)
    wrong = solve_normal(op, h, force=F, tol=1e-10, initial_pressure=low, initial_displacement=cg.displacement)
    assert wrong.info["convolutions"] == ref.info["convolutions"]
    assert np.array_equal(wrong.pressure, ref.pressure)


def test_normcg_honours_precondition():
    """``precondition=False`` reaches NormCG: its unpreconditioned CG, same contact, more iterations."""
    op, h, F = _rough(64)
    pre = solve_normal(op, h, force=F, tol=1e-10)
    plain = solve_normal(op, h, force=F, tol=1e-10, precondition=False)
    assert pre.converged and plain.converged
    assert pre.info["method"] == "normcg" and plain.info["method"] == "bccg"
    assert np.array_equal(pre.contact, plain.contact)
    assert plain.iterations > pre.iterations
