"""The one cache object of an operator (:class:`tribobem.elasticity.cache.OperatorCache`).

What the solvers derive from an operator (its blocks, the tangential view, the kernel columns,
NormCG's preconditioner, the self-compliance, the box spectra, work arrays) lives in
``op.cache``, nowhere else: after normal, NormCG and tangential solves the operator's attributes
are still its dataclass fields, and each slot holds what its builder returns on the next call.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from tribobem.elasticity.cache import OperatorCache
from tribobem.elasticity.columns import KernelColumns
from tribobem.elasticity.operators import ConvolutionOperator
from tribobem.elasticity.tangential import tangential_operator
from tribobem.solvers.normal import _self_compliance, solve_normal
from tribobem.solvers.normal_cg import fft_preconditioner
from tribobem.solvers.tangential import solve_tangential
from tribobem.validation.tangential import cattaneo_problem

FIELDS = {f.name for f in dataclasses.fields(ConvolutionOperator)}


@pytest.fixture(scope="module")
def solved():
    grid, gap, op, pair, a = cattaneo_problem(32)
    pk = solve_normal(op, gap, force=10.0, tol=1e-10, method="polonsky_keer")
    cg = solve_normal(op, gap, force=10.0, tol=1e-10, method="normcg")
    st = solve_tangential(op, pk.pressure, pk.contact, friction_coefficient=0.3, force=(1.0, 0.0), tol=1e-8)
    assert pk.converged and cg.converged and st.converged
    return op


def test_every_operator_has_its_own_empty_cache():
    grid, gap, op, pair, a = cattaneo_problem(16)
    assert isinstance(op.cache, OperatorCache)
    assert op.cache.tangential is None and op.cache.blocks == {}
    normal = op.normal
    assert normal.cache is not op.cache and isinstance(normal.cache, OperatorCache)
    assert "empty" in repr(normal.cache) or "blocks" not in repr(normal.cache)


def test_solves_leave_no_attribute_outside_the_cache(solved):
    op = solved
    for o in (op, op.normal, op.normal.cache.normcg_preconditioner):
        assert set(vars(o)) == FIELDS, set(vars(o)) - FIELDS


def test_the_slots_hold_what_the_builders_return(solved):
    op = solved
    normal = op.normal
    assert op.cache.blocks["zz"] is normal
    assert op.cache.tangential is tangential_operator(op)
    assert normal.cache.normcg_preconditioner is fft_preconditioner(op)
    assert normal.cache.kernel_columns is None or normal.cache.kernel_columns is KernelColumns.of(normal)
    c = _self_compliance(normal)
    assert normal.cache.self_compliance == c > 0.0
    top = op.cache.tangential
    assert isinstance(top.cache, OperatorCache) and top.cache is not op.cache
    assert top.cache.preconditioner_spectra, "TangCG's FFT preconditioner spectra were not kept"
    assert set(vars(top)) >= {"cache"} and not any(k.startswith("_pre") or k.startswith("_box") for k in vars(top))


def test_kernel_columns_are_cached_on_the_operator():
    grid, gap, op, pair, a = cattaneo_problem(16)
    normal = op.normal
    cols = KernelColumns.of(normal)
    assert normal.cache.kernel_columns is cols and KernelColumns.of(normal) is cols


def test_cached_preconditioner_gives_the_numbers_of_a_fresh_one():
    """The cache changes no number: the preconditioner of a fresh operator (same spectra) applies
    bit for bit as the cached one."""
    grid, gap, op, pair, a = cattaneo_problem(16)
    first = fft_preconditioner(op)
    fresh = ConvolutionOperator(op.grid, op.pair, op.components, op.spectra, op.fft_shape, op.backend, op.kind)
    x = np.random.default_rng(0).standard_normal(grid.shape)
    assert np.array_equal(first.apply(x), fft_preconditioner(fresh).apply(x))
    assert fft_preconditioner(op) is first


def test_a_copy_of_an_operator_starts_with_an_empty_cache():
    """``cache`` is no constructor argument: ``dataclasses.replace`` (other spectra, say) cannot
    carry the original's derived data over."""
    grid, gap, op, pair, a = cattaneo_problem(16)
    fft_preconditioner(op)
    copy = dataclasses.replace(op.normal)
    assert copy.cache is not op.normal.cache and copy.cache.normcg_preconditioner is None
