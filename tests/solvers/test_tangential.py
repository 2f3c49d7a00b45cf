"""Tangential contact with Coulomb friction: partial slip at a given pressure, the
normal-tangential coupling loop and the tangential ramp to gross slip.

* Cattaneo-Mindlin (identical steel bodies, free boundary): stick radius and rigid shift against
  the analytic values, force balance, Coulomb inequality, no shear outside p > 0, slip opposing
  the shear, zero slip on the stick nodes.
* Displacement control = force control; incremental mode with a zero reference = total mode;
  a monotonic two-step loading = one step; unloading is history dependent (Mindlin-Deresiewicz).
* Coupling: identical materials make one pass; a rigid ball on silicon keeps a slip annulus at
  F_x = 0 and the sign of the coupling flips with the bodies (Paper D 3.1).
* Periodic operator: Cattaneo in a periodic cell.
* Reliability: bad friction coefficient, gross slip, non-finite loads, wrong shapes,
  non-convergence.
* tangential_ramp: gross-slip onset bracketed to 1e-3 mu F0+, pre-sliding displacement.

The analytic formulas are those of :mod:`tribobem.validation.tangential`.
"""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest

from tribobem import ConvergenceError, ConvergenceWarning, InputError
from tribobem.elasticity.tangential import tangential_operator
from tribobem.solvers.coupling import solve_coupled
from tribobem.solvers.normal import solve_normal
from tribobem.solvers.normal_paths import normal_path
from tribobem.solvers.tangential_paths import tangential_ramp
from tribobem.solvers.tangential import GrossSlipError, solve_tangential
from tribobem.validation.tangential import _mindlin_k, cattaneo_problem, paper_d_problem

P, MU = 10.0, 0.3          # Cattaneo: normal force (N), friction coefficient
TOL = 1e-9                 # tangential tolerance of the accuracy tests
MU_D = 0.2                 # Paper D friction coefficient


def quiet(fn, *a, **kw):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ConvergenceWarning)
        return fn(*a, **kw)


# --------------------------------------------------------------------------------------
# Cattaneo-Mindlin problems (cached per module: several tests share the same solves)
# --------------------------------------------------------------------------------------

class Cattaneo:
    """The identical-steel sphere of validation.tangential at one grid size, with its normal
    solution and a cache of total-mode force-controlled tangential solutions."""

    def __init__(self, n, periodic=False):
        self.grid, self.gap, self.op, self.pair, self.a = cattaneo_problem(n, periodic=periodic)
        self.normal = solve_normal(self.op, self.gap, force=P, tol=1e-12)
        assert self.normal.converged
        self.p = self.normal.pressure
        self.k = _mindlin_k(self.pair)
        self.delta0 = 3 * MU * P * self.k / (16 * self.a)
        self._cache = {}

    def solve(self, **kw):
        kw.setdefault("tol", TOL)
        return solve_tangential(self.op, self.p, self.normal.contact, friction_coefficient=MU, **kw)

    def total(self, ratio):
        """Total mode, force control at Q = ratio mu P (cached)."""
        if ratio not in self._cache:
            self._cache[ratio] = self.solve(force=(ratio * MU * P, 0.0))
        return self._cache[ratio]

    def c_ref(self, ratio):
        return self.a * (1 - ratio) ** (1 / 3)

    def delta_ref(self, ratio):
        return self.delta0 * (1 - (1 - ratio) ** (2 / 3))


@pytest.fixture(scope="module")
def catt():
    cache = {}

    def get(n):
        if n not in cache:
            cache[n] = Cattaneo(n)
        return cache[n]

    return get


def stick_radius(t):
    return math.sqrt(t.stick_area / math.pi)


# --------------------------------------------------------------------------------------
# Cattaneo-Mindlin, free boundary
# --------------------------------------------------------------------------------------

@pytest.mark.parametrize("ratio", [0.3, 0.8])
@pytest.mark.parametrize("n", [48, 64])
def test_cattaneo_mindlin_free_boundary(catt, n, ratio):
    """16 and 21 cells across a; observed errors <= 1.2% (radius), 0.1% (shift)."""
    c = catt(n)
    t = c.total(ratio)
    F = ratio * MU * P
    assert t.converged, t.message
    assert t.mode == "total" and t.control == "force" and not t.gross_slip
    assert stick_radius(t) == pytest.approx(c.c_ref(ratio), rel=0.03)
    assert t.displacement_x == pytest.approx(c.delta_ref(ratio), rel=0.03)
    assert abs(t.displacement_y) < 1e-9 * t.displacement_x

    # force balance: sum(q) dx dy = F, both as computed from the field and as reported
    cell = c.grid.cell_area
    assert float(t.shear[0].sum()) * cell == pytest.approx(F, rel=1e-9)
    assert abs(float(t.shear[1].sum()) * cell) < 1e-9 * F
    assert t.force_x == pytest.approx(F, rel=1e-9) and abs(t.force_y) < 1e-9 * F

    # Coulomb: |q| <= mu p everywhere, no shear where p <= 0
    p = c.p
    qm = np.hypot(*t.shear)
    pmax = float(p.max())
    assert np.all(qm <= MU * np.clip(p, 0, None) + 1e-9 * MU * pmax)
    assert np.all(t.shear[:, p <= 0] == 0.0)
    assert np.array_equal(t.contact, c.normal.contact & (p > 0))

    # slip nodes: on the rim, the shear opposes the slip
    s = t.slip
    sm = np.hypot(*s)
    slip = t.slip_mask
    assert slip.sum() > 20 and t.stick.sum() > 20
    assert np.all(qm[slip] >= MU * p[slip] * (1 - 1e-6))
    big = slip & (sm > 1e-3 * sm[t.contact].max())
    assert big.sum() >= 0.9 * slip.sum()
    cos = (t.shear[0] * s[0] + t.shear[1] * s[1]) / np.where(qm * sm > 0, qm * sm, 1.0)
    assert cos[big].max() < -0.999
    # slip is along -x mostly: q on body 1 is along +F, the body slips against it
    assert s[0][big].mean() < 0

    # stick nodes: strictly inside the disc, slip small against the shift (observed ~1e-8)
    assert np.all(qm[t.stick] < MU * p[t.stick])
    assert sm[t.stick].max() < 1e-5 * t.displacement_x
    # the slip of the slip zone is not small: the stick test above is meaningful
    assert sm[t.contact].max() > 0.05 * t.displacement_x


def test_displacement_control_equals_force_control(catt):
    c = catt(48)
    tf = c.total(0.5)
    td = c.solve(displacement=(tf.displacement_x, tf.displacement_y))
    assert td.converged, td.message
    assert td.control == "displacement"
    assert td.displacement_x == tf.displacement_x  # given, returned unchanged
    assert td.force_x == pytest.approx(tf.force_x, rel=1e-6)
    assert abs(td.force_y) < 1e-6 * tf.force_x
    assert np.count_nonzero(td.stick != tf.stick) <= 3
    assert np.abs(td.shear - tf.shear).max() < 1e-4 * MU * c.p.max()
    # a scalar displacement is (delta, 0)
    ts = c.solve(displacement=tf.displacement_x)
    assert ts.force_x == pytest.approx(td.force_x, rel=1e-9)


def test_scalar_force_is_along_x(catt):
    c = catt(48)
    t = c.solve(force=0.5 * MU * P)
    assert t.force_x == pytest.approx(0.5 * MU * P, rel=1e-9)
    assert t.displacement_x == pytest.approx(c.total(0.5).displacement_x, rel=1e-6)


def test_force_along_y_is_the_rotated_solution(catt):
    """Axisymmetric contact on a square grid: a force along y gives the transposed state."""
    c = catt(48)
    tx = c.total(0.5)
    ty = c.solve(force=(0.0, 0.5 * MU * P))
    assert ty.displacement_y == pytest.approx(tx.displacement_x, rel=1e-6)
    assert abs(ty.displacement_x) < 1e-6 * tx.displacement_x
    assert np.count_nonzero(ty.stick != tx.stick.T) <= 3


def test_incremental_with_zero_reference_equals_total(catt):
    c = catt(48)
    tt = c.total(0.5)
    ti = c.solve(force=(0.5 * MU * P, 0.0), reference=np.zeros((2,) + c.grid.shape))
    assert ti.mode == "incremental" and ti.converged
    assert np.array_equal(ti.stick, tt.stick)
    assert np.abs(ti.shear - tt.shear).max() <= 1e-9 * MU * c.p.max()
    assert ti.displacement_x == pytest.approx(tt.displacement_x, rel=1e-9)
    np.testing.assert_allclose(ti.slip, ti.relative_displacement, atol=0)


def test_monotonic_two_step_loading_equals_one_step(catt):
    """Cattaneo under a monotonic ramp is path independent: 0.3 then 0.6 mu P (reference
    carried) = one total step to 0.6 mu P."""
    c = catt(48)
    t1 = c.total(0.3)
    t6 = c.total(0.6)
    t2 = c.solve(force=(0.6 * MU * P, 0.0), reference=t1.relative_displacement, initial_shear=t1.shear)
    assert t2.converged and t2.mode == "incremental"
    assert stick_radius(t2) == pytest.approx(stick_radius(t6), rel=0.02)
    assert stick_radius(t2) == pytest.approx(c.c_ref(0.6), rel=0.03)
    assert t2.displacement_x == pytest.approx(t6.displacement_x, rel=0.005)
    # the slip increment vanishes on the stick nodes; the total relative displacement is
    # rigid there too (the stick zone shrank monotonically)
    assert np.hypot(*t2.slip)[t2.stick].max() < 1e-5 * t2.displacement_x


def test_unloading_is_history_dependent(catt):
    """Unloading from +0.6 to +0.2 mu P (incremental): a counter-slip annulus forms
    (Mindlin-Deresiewicz); the state is not the total-mode state at 0.2."""
    c = catt(48)
    t6 = c.total(0.6)
    t2_total = c.total(0.2)
    tu = c.solve(force=(0.2 * MU * P, 0.0), reference=t6.relative_displacement, initial_shear=t6.shear)
    assert tu.converged, tu.message
    assert tu.force_x == pytest.approx(0.2 * MU * P, rel=1e-9)
    # shift: Mindlin-Deresiewicz unloading branch, observed 0.1%; the total state
    # (virgin loading curve) is 30% lower
    qs, q = 0.6, 0.2
    d_md = c.delta0 * (2 * (1 - (qs - q) / 2) ** (2 / 3) - (1 - qs) ** (2 / 3) - 1)
    assert tu.displacement_x == pytest.approx(d_md, rel=0.03)
    assert abs(tu.displacement_x / t2_total.displacement_x - 1) > 0.05
    # counter-slip: the slip annulus carries shear AGAINST the force (q_x < 0 on every slip
    # node), while in the total state at 0.2 the slip annulus carries it along the force
    slip_u, slip_t = tu.slip_mask, t2_total.slip_mask
    assert slip_u.sum() > 20 and slip_t.sum() > 20
    assert np.all(tu.shear[0][slip_u] < 0)
    assert np.all(t2_total.shear[0][slip_t] > 0)
    # the counter-slip annulus starts at b = a (1 - (Q* - Q)/(2 mu P))^(1/3)
    b = c.a * (1 - (qs - q) / 2) ** (1 / 3)
    assert stick_radius(tu) == pytest.approx(b, rel=0.03)


# --------------------------------------------------------------------------------------
# Coupling (dissimilar materials)
# --------------------------------------------------------------------------------------

def test_identical_materials_are_uncoupled_one_pass():
    grid, gap, op, pair, a = cattaneo_problem(32)
    top = tangential_operator(op)
    assert top.coupled is False
    assert tangential_operator(op) is top  # cached view
    r = solve_coupled(op, gap, friction_coefficient=MU, normal_force=P, tangential_force=(0.5 * MU * P, 0.0))
    assert r.converged and r.coupling_iterations == 1
    assert r.tangential.force_x == pytest.approx(0.5 * MU * P, rel=1e-9)
    # at F_x = 0 identical bodies stick everywhere (no shear at all)
    z = solve_coupled(op, gap, friction_coefficient=MU, normal_force=P)
    assert z.coupling_iterations == 1
    assert z.tangential.stick_ratio == 1.0
    assert np.abs(z.tangential.shear).max() == 0.0


@pytest.fixture(scope="module")
def paper_d():
    """Paper D 3.1 on 32^2 (+-2a) in both body orders: the F_x = 0 and F_x = 0.5 mu F0+ states."""
    out = {}
    for swap in (False, True):
        grid, gap, op, pair, a, F0 = paper_d_problem(32, swap)
        z = solve_coupled(op, gap, friction_coefficient=MU_D, normal_force=F0)
        zx = solve_coupled(op, gap, friction_coefficient=MU_D, normal_force=F0,
                           tangential_force=(0.5 * MU_D * z.normal.repulsive_force, 0.0), initial=z)
        out[swap] = dict(grid=grid, gap=gap, op=op, a=a, F0=F0, zero=z, half=zx)
    return out


def test_coupling_leaves_a_slip_annulus_at_zero_force(paper_d):
    d = paper_d[False]
    z = d["zero"]
    t = z.tangential
    assert tangential_operator(d["op"]).coupled is True
    assert z.converged, z.message
    assert z.coupling_iterations > 1
    # The outer loop stops on its estimated remaining error: check the actual pressure error
    # against a loop converged far tighter (the default coupling_tol is 1e-7).
    ref = solve_coupled(d["op"], d["gap"], friction_coefficient=MU_D, normal_force=d["F0"], coupling_tol=1e-12,
                        tangential_tol=1e-10)
    err = np.abs(z.normal.pressure - ref.normal.pressure).sum() / np.abs(ref.normal.pressure).sum()
    assert err < 1e-7
    assert 0 < t.stick_ratio < 0.5
    assert t.slip_mask.sum() > 0.5 * t.contact.sum()
    # no net force, but shear on the slip nodes at the friction limit
    assert abs(t.force_x) < 1e-12 and abs(t.force_y) < 1e-12
    qm = np.hypot(*t.shear)
    p = z.normal.pressure
    assert np.all(qm <= MU_D * np.clip(p, 0, None) * (1 + 1e-9) + 1e-12)
    assert np.all(qm[t.slip_mask] >= MU_D * p[t.slip_mask] * (1 - 1e-6))
    # the shear on the elastic flat (body 1 carries q) points outward in the annulus
    X, Y = d["grid"].meshgrid()
    rr = np.hypot(X, Y)
    radial = (t.shear[0] * X + t.shear[1] * Y) / np.where(rr > 0, rr, 1.0)
    assert radial[t.slip_mask].min() > 0
    # the stick core is centred
    a = d["a"]
    assert abs(X[t.stick].mean()) < 0.05 * a and abs(Y[t.stick].mean()) < 0.05 * a


def test_coupling_sign_flips_when_the_bodies_are_swapped(paper_d):
    X, Y = paper_d[False]["grid"].meshgrid()
    a = paper_d[False]["a"]
    for swap, sign in ((False, -1.0), (True, 1.0)):
        d = paper_d[swap]
        zx = d["half"]
        assert zx.converged and zx.coupling_iterations > 1
        assert zx.tangential.force_x == pytest.approx(0.5 * MU_D * d["zero"].normal.repulsive_force, rel=1e-9)
        st = zx.tangential.stick
        assert st.any()
        xc = float(X[st].mean()) / a
        assert sign * xc > 0.1, (swap, xc)
    # the swap flips the coupling: the zero-force shear on body 1 changes sign, the contact
    # and the stick zone stay the same
    t0, t1 = paper_d[False]["zero"].tangential, paper_d[True]["zero"].tangential
    assert np.array_equal(t0.stick, t1.stick)
    np.testing.assert_allclose(t1.shear, -t0.shear, atol=1e-6 * np.abs(t0.shear).max())
    # and the dragged stick zones are mirror images
    st0, st1 = paper_d[False]["half"].tangential.stick, paper_d[True]["half"].tangential.stick
    assert np.count_nonzero(st0 != st1[::-1, :]) <= 4


def test_coupling_loop_not_converged_warns(paper_d):
    d = paper_d[False]
    with pytest.warns(ConvergenceWarning, match="coupling"):
        r = solve_coupled(d["op"], d["gap"], friction_coefficient=MU_D, normal_force=d["F0"], max_coupling=2)
    assert not r.converged
    assert r.coupling_iterations == 2 and len(r.coupling_history) == 2
    with pytest.raises(InputError, match="max_coupling"):
        solve_coupled(d["op"], d["gap"], friction_coefficient=MU_D, normal_force=d["F0"], max_coupling=0)


def test_coupled_gross_slip_is_an_error(paper_d):
    d = paper_d[False]
    with pytest.raises(GrossSlipError) as err:
        solve_coupled(d["op"], d["gap"], friction_coefficient=MU_D, normal_force=d["F0"],
                      tangential_force=(1.5 * MU_D * d["F0"], 0.0))
    assert err.value.max_force == pytest.approx(MU_D * d["F0"], rel=1e-6)


# --------------------------------------------------------------------------------------
# Periodic operator
# --------------------------------------------------------------------------------------

def test_cattaneo_periodic():
    """a = L/6 on 128^2 (21 cells across a): stick radius (observed 0.6%) and the rigid shift
    against the Cattaneo-Mindlin traction applied to the same periodic operator (0.7%)."""
    c = Cattaneo(128, periodic=True)
    assert c.op.periodic
    r = 0.5
    t = c.total(r)
    assert t.converged, t.message
    cr = c.c_ref(r)
    assert stick_radius(t) == pytest.approx(cr, rel=0.03)
    p0 = 3 * P / (2 * math.pi * c.a**2)
    R2 = c.grid.radius() ** 2
    qx = MU * p0 * (np.sqrt(np.clip(1 - R2 / c.a**2, 0, None)) - (cr / c.a) * np.sqrt(np.clip(1 - R2 / cr**2, 0, None)))
    ux, _ = tangential_operator(c.op).shear_displacement(qx, np.zeros_like(qx))
    d_ref = float(np.asarray(ux)[R2 < (0.8 * cr) ** 2].mean())
    assert t.displacement_x == pytest.approx(d_ref, rel=0.03)
    assert t.force_x == pytest.approx(r * MU * P, rel=1e-9)


# --------------------------------------------------------------------------------------
# Reliability
# --------------------------------------------------------------------------------------

@pytest.fixture(scope="module")
def small():
    """A 32^2 Cattaneo problem for the input checks."""
    return Cattaneo(32)


@pytest.mark.parametrize("mu", [-0.1, -1e-12, math.nan, math.inf, -math.inf, None, "0.3", True])
def test_bad_friction_coefficient(small, mu):
    with pytest.raises(InputError) as err:
        solve_tangential(small.op, small.p, small.normal.contact, friction_coefficient=mu, force=(1.0, 0.0))
    assert err.value.field == "solve_tangential.friction_coefficient"
    assert ">= 0" in str(err.value)


@pytest.mark.parametrize("mu", [np.float32(0.3), np.float64(0.3), np.int64(1)])
def test_numpy_friction_coefficients_accepted(small, mu):
    t = solve_tangential(small.op, small.p, small.normal.contact, friction_coefficient=mu,
                         force=(1.0, 0.0), tol=1e-8)
    assert t.converged
    assert t.friction_coefficient == pytest.approx(float(mu), rel=1e-12)
    assert isinstance(t.friction_coefficient, float)


def test_frictionless_with_a_force_is_gross_slip(small):
    with pytest.raises(GrossSlipError) as err:
        solve_tangential(small.op, small.p, small.normal.contact, friction_coefficient=0.0, force=(1e-3, 0.0))
    assert "frictionless" in str(err.value)
    assert err.value.field == "friction.tangential_force"
    assert err.value.max_force == 0.0
    assert isinstance(err.value, InputError)
    # without a force (or under displacement control) mu = 0 is a valid, shear-free state
    for kw in ({"force": (0.0, 0.0)}, {"displacement": (1e-9, 0.0)}):
        t = solve_tangential(small.op, small.p, small.normal.contact, friction_coefficient=0.0, **kw)
        assert t.converged and np.all(t.shear == 0.0) and t.force_x == 0.0


@pytest.mark.parametrize("force", [(1.0001, 0.0), (0.6, 0.8), (0.0, -2.0)])
def test_force_beyond_capacity_is_gross_slip(small, force):
    cap = MU * small.normal.repulsive_force  # mu F0+
    with pytest.raises(GrossSlipError) as err:
        solve_tangential(small.op, small.p, small.normal.contact, friction_coefficient=MU,
                         force=(force[0] * cap, force[1] * cap))
    assert err.value.max_force == pytest.approx(cap, rel=1e-9)
    assert "mu F0+" in str(err.value) and "gross sliding" in str(err.value)
    assert f"{cap:.6g}" in str(err.value)


def test_force_just_below_capacity_is_solved(small):
    cap = MU * small.normal.repulsive_force
    t = solve_tangential(small.op, small.p, small.normal.contact, friction_coefficient=MU,
                         force=(0.99 * cap, 0.0), tol=1e-8)
    assert t.converged and t.stick.any()
    assert t.force_x == pytest.approx(0.99 * cap, rel=1e-9)
    assert t.info["capacity"] == pytest.approx(cap, rel=1e-9)


def test_tangential_load_without_compressive_contact(small):
    tension = -np.abs(small.p)  # no p > 0 anywhere
    with pytest.raises(GrossSlipError, match="no compressive contact"):
        solve_tangential(small.op, tension, small.normal.contact, friction_coefficient=MU, force=(1e-3, 0.0))
    # zero force, or displacement control: a valid state without shear
    t = solve_tangential(small.op, tension, small.normal.contact, friction_coefficient=MU, displacement=(1e-9, 0))
    assert t.converged and t.force_x == 0.0 and not t.contact.any()


@pytest.mark.parametrize("kw,field", [
    ({"force": (math.nan, 0.0)}, "solve_tangential.force"),
    ({"force": (0.0, math.inf)}, "solve_tangential.force"),
    ({"force": -math.inf}, "solve_tangential.force"),
    ({"displacement": (math.nan, 0.0)}, "solve_tangential.displacement"),
    ({"displacement": (0.0, -math.inf)}, "solve_tangential.displacement"),
    ({}, "friction"),
    ({"force": (1.0, 0.0), "displacement": (1e-9, 0.0)}, "friction"),
    ({"force": (1.0, 0.0), "tol": 0.0}, "solve_tangential.tol"),
    ({"force": (1.0, 0.0), "tol": math.nan}, "solve_tangential.tol"),
])
def test_bad_load(small, kw, field):
    with pytest.raises(InputError) as err:
        solve_tangential(small.op, small.p, small.normal.contact, friction_coefficient=MU, **kw)
    assert err.value.field == field
    assert not isinstance(err.value, GrossSlipError)


@pytest.mark.parametrize("force", [(1.0,), (1.0, 0.0, 0.0), "1 N", ("a", "b")])
def test_force_with_wrong_number_of_components(small, force):
    with pytest.raises(InputError) as err:
        solve_tangential(small.op, small.p, small.normal.contact, friction_coefficient=MU, force=force)
    assert err.value.field == "solve_tangential.force"


def test_non_finite_direction_of_a_ramp():
    grid, gap, op, pair, a = cattaneo_problem(16)
    for bad in (math.nan, math.inf):
        with pytest.raises(InputError) as err:
            tangential_ramp(op, gap, normal_force=P, friction_coefficient=MU, forces=[0.0, 1.0], direction=bad)
        assert err.value.field == "direction_vector.direction_deg"
        with pytest.raises(InputError) as err:
            normal_path(op, gap, normal_forces=[P], friction_coefficient=MU, direction=bad)
        assert err.value.field == "direction_vector.direction_deg"


def test_non_finite_pressure_and_wrong_pressure_shape(small):
    p = small.p.copy()
    p[3, 3] = math.nan
    with pytest.raises(InputError, match="pressure"):
        solve_tangential(small.op, p, small.normal.contact, friction_coefficient=MU, force=(1.0, 0.0))
    with pytest.raises(InputError, match="pressure"):
        solve_tangential(small.op, small.p[:-1], small.normal.contact[:-1], friction_coefficient=MU, force=(1.0, 0.0))


@pytest.mark.parametrize("name", ["reference", "initial_shear"])
@pytest.mark.parametrize("shape", [(2, 32, 31), (32, 32), (3, 32, 32)])
def test_wrong_shaped_reference_or_initial_shear(small, name, shape):
    with pytest.raises(InputError) as err:
        solve_tangential(small.op, small.p, small.normal.contact, friction_coefficient=MU, force=(1.0, 0.0),
                         **{name: np.zeros(shape)})
    assert err.value.field == name
    assert "(2, 32, 32)" in str(err.value)


def test_non_convergence_is_not_silent(small):
    kw = dict(friction_coefficient=MU, force=(0.5 * MU * P, 0.0), max_iterations=3)
    with pytest.warns(ConvergenceWarning, match="not converged after 3 iterations"):
        t = solve_tangential(small.op, small.p, small.normal.contact, **kw)
    assert not t.converged
    assert t.iterations == 3 and len(t.residual_history) == 3
    assert t.residual > 1e-8
    # the returned (unconverged) state still balances the force and obeys Coulomb
    assert t.force_x == pytest.approx(0.5 * MU * P, rel=1e-9)
    assert np.all(np.hypot(*t.shear) <= MU * np.clip(small.p, 0, None) * (1 + 1e-12))
    with pytest.raises(ConvergenceError, match="not converged"):
        solve_tangential(small.op, small.p, small.normal.contact, strict=True, **kw)


@pytest.mark.parametrize("max_iterations", [0, -1, 2.5])
def test_bad_max_iterations(small, max_iterations):
    with pytest.raises(InputError) as err:
        solve_tangential(small.op, small.p, small.normal.contact, friction_coefficient=MU, force=(1.0, 0.0),
                         max_iterations=max_iterations)
    assert err.value.field == "solve_tangential.max_iterations"


def test_warm_start_from_the_solution_converges_at_once(catt):
    c = catt(48)
    t = c.total(0.5)
    w = c.solve(force=(0.5 * MU * P, 0.0), initial_shear=t.shear)
    assert w.converged and w.iterations < 0.2 * t.iterations
    assert np.array_equal(w.stick, t.stick)


# --------------------------------------------------------------------------------------
# tangential_ramp (Paper D smooth ball, 32^2)
# --------------------------------------------------------------------------------------

@pytest.fixture(scope="module")
def ramp_problem():
    grid, gap, op, pair, a, F0 = paper_d_problem(32)
    return op, gap, F0


def test_ramp_to_gross_slip(ramp_problem):
    op, gap, F0 = ramp_problem
    cap = MU_D * F0
    ramp = tangential_ramp(op, gap, normal_force=F0, friction_coefficient=MU_D, forces=[0.0, 1e-6, 2e-6])
    assert ramp.gross_slip and ramp.control == "force"
    assert len(ramp.steps) == 2 and ramp.values == [0.0, 1e-6]
    assert all(s.converged for s in ramp.steps)
    # 2 uN = mu F0+ exactly: no equilibrium, reported with the capacity
    assert ramp.max_force == pytest.approx(cap, rel=1e-9)
    assert "gross slip at step 2" in ramp.message
    lo, hi = ramp.onset_bracket
    f0p = ramp.onset_state.normal.repulsive_force
    assert 1e-6 <= lo < hi <= 2e-6
    assert hi - lo <= 1e-3 * MU_D * f0p
    assert ramp.onset == pytest.approx(0.5 * (lo + hi), rel=1e-12)
    assert 0.85 < ramp.onset_ratio < 1.0  # observed 0.912 on 32^2 (Paper D: 0.97 on coarse cells)
    assert ramp.onset_ratio == pytest.approx(ramp.onset / (MU_D * f0p), rel=1e-12)
    # the onset state still sticks, a little
    assert ramp.onset_state.tangential.stick.any()
    assert ramp.onset_state.tangential.stick_ratio < 0.05
    assert ramp.presliding_displacement > 0
    # delta at the onset minus delta at F = 0
    d_onset = ramp.onset_state.tangential.displacement_x
    d_zero = ramp.zero_state.tangential.displacement_x
    assert ramp.presliding_displacement == pytest.approx(d_onset - d_zero, rel=1e-12)
    # force-displacement curve rises
    assert ramp.steps[1].tangential.displacement_x > ramp.steps[0].tangential.displacement_x


def test_ramp_without_gross_slip(ramp_problem):
    op, gap, F0 = ramp_problem
    calls = []
    ramp = tangential_ramp(op, gap, normal_force=F0, friction_coefficient=MU_D, forces=[0.5e-6, 1e-6],
                           direction=90.0, progress=lambda d, t: calls.append((d, t)))
    assert not ramp.gross_slip
    assert math.isnan(ramp.onset) and math.isnan(ramp.onset_ratio) and math.isnan(ramp.presliding_displacement)
    assert ramp.onset_state is None and math.isnan(ramp.max_force)
    assert len(ramp.steps) == 2 and calls == [(1, 2), (2, 2)]
    assert ramp.zero_state is not None  # F = 0 solved for the pre-sliding origin
    t = ramp.steps[-1].tangential
    # direction = 90 degrees: the force is along y
    assert t.force_y == pytest.approx(1e-6, rel=1e-9) and abs(t.force_x) < 1e-15
    assert t.displacement_y > 0 and abs(t.displacement_x) < 1e-6 * t.displacement_y


def test_ramp_input_errors(ramp_problem):
    op, gap, F0 = ramp_problem
    kw = dict(normal_force=F0, friction_coefficient=MU_D)
    with pytest.raises(InputError, match="exactly one"):
        tangential_ramp(op, gap, **kw)
    with pytest.raises(InputError, match="exactly one"):
        tangential_ramp(op, gap, forces=[0.0], displacements=[0.0], **kw)
    with pytest.raises(InputError) as err:
        tangential_ramp(op, gap, forces=[0.0], slip="cumulative", **kw)
    assert err.value.field == "tangential_ramp.slip"
    with pytest.raises(InputError) as err:
        normal_path(op, gap, normal_forces=[F0, F0], tangential_forces=[0.0], friction_coefficient=MU_D)
    assert err.value.field == "normal_path.tangential_forces"


# --------------------------------------------------------------------------------------
# Coupled steps: predictor, reused slip scale, partial fields (speed work, issues 6 and 7)
# --------------------------------------------------------------------------------------

def test_partial_fields_and_given_slip_scale_change_nothing_but_the_fields(paper_d):
    d = paper_d[False]
    z = d["zero"]
    kw = dict(friction_coefficient=MU_D, force=(0.4 * MU_D * z.normal.repulsive_force, 0.0), tol=1e-9)
    full = solve_tangential(d["op"], z.normal.pressure, z.normal.contact, **kw)
    part = solve_tangential(d["op"], z.normal.pressure, z.normal.contact, full_fields=False,
                            slip_scale=full.info["slip_scale"], **kw)
    assert full.converged and part.converged
    np.testing.assert_array_equal(part.shear, full.shear)
    np.testing.assert_array_equal(part.stick, full.stick)
    assert part.displacement_x == full.displacement_x
    assert np.isnan(part.slip).all() and np.isnan(part.relative_displacement).all()
    assert np.isfinite(full.slip).all()


@pytest.mark.parametrize("extrapolate", [False, True])
def test_predictor_step_matches_the_plain_loop_and_a_tight_reference(paper_d, monkeypatch, extrapolate):
    """Incremental steps of a force ramp: the predictor (tangential solve at the predicted
    pressure first) changes the path to the fixed point, not the fixed point: pressure and
    rigid shift agree with the plain alternation and with a loop converged far tighter, in no
    more passes."""
    from tribobem.solvers import coupling as C

    d = paper_d[False]
    z = d["zero"]
    F = MU_D * z.normal.repulsive_force
    loads = (0.2 * F, 0.3 * F, 0.4 * F)

    def ramp(predictor, **tols):
        monkeypatch.setattr(C, "PREDICTOR", predictor)
        prev, older, out = z, None, []
        for k, f in enumerate(loads):
            extra = (older, 1.0) if (extrapolate and older is not None) else None
            r = solve_coupled(d["op"], d["gap"], friction_coefficient=MU_D, normal_force=d["F0"],
                              tangential_force=(f, 0.0), initial=prev, extrapolate=extra,
                              reference=prev.tangential.relative_displacement, **tols)
            assert r.converged, r.message
            out.append(r)
            older, prev = prev, r
        return out

    pred, plain = ramp(True), ramp(False)
    ref = ramp(False, coupling_tol=1e-12, tangential_tol=1e-11, tol=1e-12)
    for a, b, c in zip(pred, plain, ref):
        scale = np.abs(c.normal.pressure).sum()
        assert np.abs(a.normal.pressure - c.normal.pressure).sum() / scale < 1e-6
        assert np.abs(b.normal.pressure - c.normal.pressure).sum() / scale < 1e-6
        assert a.tangential.displacement_x == pytest.approx(c.tangential.displacement_x, rel=1e-5)
        assert np.array_equal(a.tangential.stick, c.tangential.stick)
        assert np.isfinite(a.tangential.relative_displacement).all()  # the final pass builds the fields
    assert sum(r.coupling_iterations for r in pred) <= sum(r.coupling_iterations for r in plain)


def test_a_pass_without_pressure_change_measures_no_contraction():
    """A pass at round-off (no pressure change) gives no contraction factor, and a factor of 0
    is no hint: taken on to the next step it stopped that step after two passes whatever their
    change (a plain loop at coupling_tol 1e-12 stopped at a change of 5.6e-3)."""
    from tribobem.solvers.coupling import _contraction, _remaining

    assert _contraction([1e-3, 5e-5], None, 0) == pytest.approx(0.05)
    assert _contraction([1e-3, 0.0], None, 0) is None
    assert _contraction([0.0, 5.6e-3], 0.0, 1) is None
    assert _contraction([0.0, 5.6e-3], 0.05, 1) == pytest.approx(0.1)
    assert _remaining(5.6e-3, 0.1) > 1e-12


def test_likely_last_pass_uses_the_larger_contraction():
    """The pass predicted to be the last is solved at the run's normal tolerance; the prediction
    takes the larger of the step's measured contraction and the last step's, because the
    contraction grows over a step's passes (numbers of the adhesive loop's four-pass steps:
    changes 6.4e-3, 2.6e-4, then 1.8e-5 with rho 0.07 -> another pass was needed)."""
    from tribobem.solvers.coupling import _likely_last

    tol = 1e-6
    # measured rho 0.04 alone predicts a remaining error 4.4e-7 < tol: taken as the last ...
    assert _likely_last(0.04, None, True, 2.6e-4, tol)
    # ... but with the last step's 0.1 the prediction is 2.9e-6 > tol: not the last
    assert not _likely_last(0.04, 0.1, True, 2.6e-4, tol)
    # a three-pass step (changes 1.3e-3, 8.1e-5; rho 0.064, last step 0.069): the last
    assert _likely_last(0.064, 0.069, True, 8.1e-5, tol)
    # before the step has measured its own contraction: twice the hint, with a 5x margin
    assert _likely_last(0.1, 0.05, False, 2.0e-4, tol)
    assert not _likely_last(0.1, 0.05, False, 1.0e-3, tol)
    assert not _likely_last(None, 0.05, True, 1e-12, tol)
