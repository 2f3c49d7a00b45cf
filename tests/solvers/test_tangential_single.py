"""TangCG's single-precision search directions (``Backend.single_precision``, see solvers/tangential.py).

On the NumPy backend with scipy.fft the images K v of TangCG's search directions and its FFT
preconditioner are transformed in single precision; every check of the element division
recomputes K q in double precision and measures the residual from it.  So the box convolution in
single precision must match the double one to float32 round-off (and be single precision, or the
option does nothing), and the solution must be the double-precision iteration's to the solver
tolerance: the same stick nodes (Cattaneo-Mindlin, against the analytic stick radius in
test_tangential.py) and the same coupled state of dissimilar bodies (Paper D's ball).
"""

from __future__ import annotations

import numpy as np
import pytest

from tribobem.elasticity.backend import Backend
from tribobem.elasticity.tangential import tangential_operator
from tribobem.solvers.coupling import solve_coupled
from tribobem.solvers.normal import solve_normal
from tribobem.validation.tangential import cattaneo_problem, paper_d_problem

P, MU, TOL = 10.0, 0.3, 1e-9


def _double_precision(monkeypatch) -> None:
    """TangCG in double precision throughout: the backend reports no single-precision transforms
    (as CuPy's does), the reference of the single-precision search directions."""
    monkeypatch.setattr(Backend, "single_precision", property(lambda self: False))


@pytest.fixture(scope="module")
def catt():
    grid, gap, op, pair, a = cattaneo_problem(64)
    normal = solve_normal(op, gap, force=P, tol=1e-12)
    assert normal.converged
    return op, normal


def test_box_convolution_in_single_precision(catt):
    """K_tt on a 40 x 36 box: float32 results within 1e-6 of the double ones (relative to the
    largest displacement), and not equal to them (the transforms are single precision)."""
    op, _ = catt
    top = tangential_operator(op)
    rng = np.random.default_rng(3)
    qx, qy = rng.standard_normal((2, 40, 36)) * 1e8
    ux, uy = top.box_shear_displacement(qx, qy)
    sx, sy = top.box_shear_displacement(qx, qy, single=True)
    assert ux.dtype == np.float64 and sx.dtype == np.float32
    scale = max(np.abs(ux).max(), np.abs(uy).max())
    err = max(np.abs(sx - ux).max(), np.abs(sy - uy).max()) / scale
    assert 1e-12 < err < 1e-6


def test_preconditioner_in_single_precision(catt):
    op, _ = catt
    top = tangential_operator(op)
    rng = np.random.default_rng(4)
    rx, ry = rng.standard_normal((2, 48, 48)) * 1e-9
    zx, zy = top.precondition(rx, ry)
    sx, sy = top.precondition(rx.astype(np.float32), ry.astype(np.float32))
    assert sx.dtype == np.float32
    scale = max(np.abs(zx).max(), np.abs(zy).max())
    assert max(np.abs(sx - zx).max(), np.abs(sy - zy).max()) < 1e-5 * scale


@pytest.mark.parametrize("ratio", [0.3, 0.8])
def test_cattaneo_solution_unchanged(catt, ratio, monkeypatch):
    """Force control at ratio mu P: the same stick nodes, shear and rigid shift as the double
    iteration to 10 x the tolerance, in at most 25 % more iterations."""
    from tribobem.solvers.tangential import solve_tangential

    op, normal = catt

    def solve():
        return solve_tangential(op, normal.pressure, normal.contact, friction_coefficient=MU,
                                force=(ratio * MU * P, 0.0), tol=TOL)

    single = solve()
    _double_precision(monkeypatch)
    double = solve()
    assert single.converged and double.converged
    assert np.array_equal(single.stick, double.stick)
    # measured: shear 1.4-2.0e-9 of its largest value, shift 3-6e-12, iterations 24/24, 28/26
    qmax = np.abs(double.shear).max()
    assert np.abs(single.shear - double.shear).max() < 10 * TOL * qmax
    assert single.displacement_x == pytest.approx(double.displacement_x, rel=10 * TOL)
    assert single.iterations <= 1.25 * double.iterations


def test_coupled_ball_unchanged(monkeypatch):
    """Paper D's rigid ball on an elastic flat (dissimilar: the coupling loop), F_x = 0.5 mu F0:
    the same contact and stick nodes, pressures and shift to the loop's tolerances."""
    grid, gap, op, pair, a, P0 = paper_d_problem(48)
    kw = dict(friction_coefficient=0.2, normal_force=P0, tangential_force=(0.5 * 0.2 * P0, 0.0),
              tol=1e-10, tangential_tol=1e-9, coupling_tol=1e-9)
    single = solve_coupled(op, gap, **kw)
    _double_precision(monkeypatch)
    double = solve_coupled(op, gap, **kw)
    assert single.converged and double.converged
    assert np.array_equal(single.normal.contact, double.normal.contact)
    assert np.array_equal(single.tangential.stick, double.tangential.stick)
    # measured: pressure 4.8e-12 (L1, relative), shift 8.6e-11; the coupling tolerance is 1e-9
    p = np.abs(double.normal.pressure).sum()
    assert np.abs(single.normal.pressure - double.normal.pressure).sum() < 1e-9 * p
    assert single.tangential.displacement_x == pytest.approx(double.tangential.displacement_x, rel=1e-9)


@pytest.mark.parametrize("dtype", [np.float64, np.float32])
def test_preconditioner_in_work_arrays_gives_the_plain_numbers(catt, dtype):
    """TangCG's preconditioner on NumPy with scipy.fft transforms into reused work arrays: the
    numbers of the plain rfft2 / irfft2 products to the last bit (float32: with the spectra in
    single precision)."""
    import scipy.fft

    op, _ = catt
    top = tangential_operator(op)
    if not top.be._lean():
        pytest.skip("scipy.fft's pocketfft out= API not available")
    rng = np.random.default_rng(6)
    rx, ry = (rng.standard_normal((2, 40, 44)) * 1e-9).astype(dtype)
    spec = top.preconditioner_spectra((40, 44))
    ctype = np.complex64 if dtype == np.float32 else complex
    s = {k: v.astype(ctype) for k, v in spec.items()}
    Rx, Ry = scipy.fft.rfft2(rx), scipy.fft.rfft2(ry)
    ref_x = scipy.fft.irfft2(Rx * s["xx"] + Ry * s["xy"], s=(40, 44))
    ref_y = scipy.fft.irfft2(Rx * s["yx"] + Ry * s["yy"], s=(40, 44))
    zx, zy = top.precondition(rx, ry)
    assert zx.dtype == dtype
    assert np.array_equal(zx, ref_x) and np.array_equal(zy, ref_y)
