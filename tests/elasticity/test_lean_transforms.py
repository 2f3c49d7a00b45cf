"""The zero-padded transforms of the scipy.fft engine (Backend.rfft2_padded / irfft2_rows) and
the free-boundary ``ConvolutionOperator.apply`` that uses them: the same numbers as the plain
``rfft2`` / ``irfft2`` (to round-off), including reused output buffers and changing shapes."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.fft

from tribobem.elasticity.backend import Backend
from tribobem.elasticity.operators import free_boundary_operator
from tribobem.grid import Grid
from tribobem.materials import ContactPair, Material

pytestmark = pytest.mark.skipif(not Backend("numpy", fft="scipy")._lean(),
                                reason="pocketfft's out= API not available in this scipy")


@pytest.mark.parametrize("m, N", [((8, 8), (16, 16)), ((20, 13), (40, 26)), ((17, 31), (36, 64)), ((24, 24), (24, 48))])
def test_padded_forward_and_row_inverse(m, N):
    be = Backend("numpy", fft="scipy", workers=1)
    rng = np.random.default_rng(3)
    a = rng.normal(size=m)
    ref = scipy.fft.rfft2(a, s=N)
    out = np.full((N[0], N[1] // 2 + 1), np.nan + 1j)  # garbage in the buffer must not leak
    T = be.rfft2_padded(a, N, out=out)
    assert T is out
    assert np.abs(T - ref).max() < 1e-12 * np.abs(ref).max()
    # a second, smaller input through the same thread-local row buffer
    b = rng.normal(size=(m[0], max(1, m[1] - 3)))
    assert np.abs(be.rfft2_padded(b, N) - scipy.fft.rfft2(b, s=N)).max() < 1e-12 * np.abs(ref).max()
    spec = ref * rng.normal(size=ref.shape)
    u_ref = scipy.fft.irfft2(spec, s=N)[: m[0]]
    u = be.irfft2_rows(spec.copy(), N, m[0])
    assert u.shape == (m[0], N[1])
    assert np.abs(u - u_ref).max() < 1e-12 * np.abs(u_ref).max()


@pytest.mark.parametrize("components", [("z",), ("x", "y", "z")])
def test_free_boundary_apply_lean_equals_plain(monkeypatch, components):
    grid = Grid(24, 18, 24e-6, 18e-6, False)
    pair = ContactPair(Material(70e9, 0.3, "a"), Material(200e9, 0.25, "b"))
    be = Backend("numpy", fft="scipy", workers=1)
    op = free_boundary_operator(grid, pair, components, backend=be)
    rng = np.random.default_rng(5)
    t = rng.normal(size=((len(components),) if len(components) > 1 else ()) + grid.shape)
    lean = op.apply(t)
    monkeypatch.setattr(Backend, "_lean", lambda self: False)
    plain = op.apply(t)
    assert lean.shape == plain.shape == t.shape
    assert np.abs(lean - plain).max() < 1e-12 * np.abs(plain).max()


def test_public_path_when_the_private_api_is_missing(monkeypatch):
    """Without pocketfft's private out= API (another scipy) the plain transforms are used."""
    import tribobem.elasticity.backend as B
    import tribobem.elasticity.columns as C

    grid = Grid(20, 16, 20e-6, 16e-6, False)
    pair = ContactPair(Material(70e9, 0.3, "a"), Material(200e9, 0.25, "b"))
    be = Backend("numpy", fft="scipy", workers=1)
    op = free_boundary_operator(grid, pair, ("x", "y", "z"), backend=be)
    t = np.random.default_rng(2).normal(size=(3,) + grid.shape)
    lean = op.apply(t)
    lean_z = C.convolve(op.normal, t[2])
    monkeypatch.setattr(B, "_pocketfft", None)
    monkeypatch.setattr(C, "_pocketfft", None)
    assert not be._lean()
    assert np.abs(op.apply(t) - lean).max() < 1e-12 * np.abs(lean).max()
    assert np.abs(C.convolve(op.normal, t[2]) - lean_z).max() < 1e-12 * np.abs(lean_z).max()
    from tribobem import _fft

    assert _fft._private_pocketfft() is not None  # this scipy has it (checked against scipy.fft)


@pytest.mark.parametrize("reciprocal", [False, True])
@pytest.mark.parametrize("shape, block", [((24, 18), 64), ((17, 31), 100), ((32, 32), 1 << 18)])
def test_blocked_convolution_is_bitwise_the_unblocked(monkeypatch, shape, block, reciprocal):
    """The blocked free-boundary convolution (large grids: ~4 grid fields less) runs the same
    1-D transforms as the unblocked one: the same numbers to the last bit, with ragged last
    blocks, odd sizes, ``out`` aliasing the input, and division by the spectrum."""
    import tribobem.elasticity.backend as B
    from tribobem.elasticity.operators import ConvolutionOperator

    grid = Grid(shape[0], shape[1], shape[0] * 1e-6, shape[1] * 1e-6, False)
    pair = ContactPair(Material(70e9, 0.3, "a"), Material(200e9, 0.25, "b"))
    be = Backend("numpy", fft="scipy", workers=1)
    base = free_boundary_operator(grid, pair, ("z",), backend=be)
    op = ConvolutionOperator(grid, pair, ("z",), {"zz": base.spectrum()}, base.fft_shape, be, "t",
                             reciprocal=reciprocal)
    t = np.random.default_rng(7).normal(size=grid.shape)
    monkeypatch.setenv("TRIBOBEM_BLOCKED_FFT_POINTS", str(10**12))
    assert not be.blocked(op.fft_shape)
    plain = op.apply(t).copy()
    monkeypatch.setenv("TRIBOBEM_BLOCKED_FFT_POINTS", "1")
    monkeypatch.setattr(B, "_BLOCK_POINTS", block)
    assert be.blocked(op.fft_shape)
    blocked = op.apply(t)
    assert np.array_equal(blocked, plain)
    again = op.apply(t)  # reused work arrays: nothing left over from the previous call
    assert np.array_equal(again, plain)
    u = t.copy()
    assert op.apply(u, out=u) is u and np.array_equal(u, plain)


@pytest.mark.parametrize("dtype", [np.float64, np.float32])
def test_transforms_into_work_arrays_are_bitwise_scipy(dtype):
    """Backend.rfft2_into / irfft2_into (the preconditioners' transforms) give scipy.fft.rfft2 /
    irfft2 to the last bit: the adhesive solves are multistable, and a normal solve's
    preconditioner that rounds differently from the strict (CuPy-like) backend moved an adhesive
    unloading to another branch."""
    be = Backend("numpy", fft="scipy", workers=1)
    rng = np.random.default_rng(5)
    a = rng.normal(size=(30, 22)).astype(dtype)
    ctype = np.complex64 if dtype == np.float32 else complex
    T = be.rfft2_into(a, np.full((30, 12), np.nan, dtype=ctype))
    assert np.array_equal(T, scipy.fft.rfft2(a))
    u = be.irfft2_into(T, (30, 22), np.full((30, 22), np.nan, dtype=dtype))
    assert np.array_equal(u, scipy.fft.irfft2(T, s=(30, 22)))


@pytest.mark.parametrize("engine", ["pyfftw", "mkl_fft"])
def test_every_engine_takes_the_lean_transforms(engine):
    """With an optional engine selected (installed or not: the lean transforms never call it) the
    zero-padded, box and blocked transforms are pocketfft's, the same numbers to the last bit as
    with the scipy engine: the engines' whole-array transforms with their copies were slower on
    the free boundary (the adhesive loop of benchmarks/adhesive_loop.py took 59 s of CPU with
    pyFFTW against 46 s)."""
    be, ref = Backend("numpy", fft=engine, workers=1), Backend("numpy", fft="scipy", workers=1)
    assert be._lean() and be.single_precision and be.blocked((4096, 4096))
    rng = np.random.default_rng(11)
    a = rng.normal(size=(20, 13))
    T = be.rfft2_padded(a, (40, 26))
    assert np.array_equal(T, ref.rfft2_padded(a, (40, 26)))
    assert np.array_equal(be.irfft2_rows(T.copy(), (40, 26), 20), ref.irfft2_rows(T.copy(), (40, 26), 20))
    box = np.empty((20, 7), dtype=complex)
    assert np.array_equal(be.rfft2_into(a, box), scipy.fft.rfft2(a))
