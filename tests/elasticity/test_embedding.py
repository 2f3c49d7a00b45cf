"""The box-to-grid displacement and the single-precision operator apply."""

import numpy as np
import pytest

from tribobem.elasticity.embedding import box_to_grid
from tribobem.elasticity.operators import make_operator
from tribobem.grid import Grid
from tribobem.materials import ContactPair, Material

PAIR = ContactPair(Material(70e9, 0.3), Material(200e9, 0.25))


@pytest.mark.parametrize("n1, n2, box", [
    (64, 48, (10, 30, 5, 20)),     # inside
    (100, 90, (0, 7, 80, 90)),     # at a corner
    (96, 96, (0, 96, 0, 96)),      # the whole grid
    (128, 64, (60, 61, 31, 32)),   # one node
])
def test_box_to_grid_is_the_padded_convolution(n1, n2, box):
    """Tolerance 1e-13 of the largest displacement: the same influence coefficients, another
    FFT length (a wrong offset layout is off by O(1))."""
    i0, i1, j0, j1 = box
    op = make_operator(Grid(n1, n2, n1 * 1e-6, n2 * 1.3e-6, False), PAIR)
    rng = np.random.default_rng(n1 + n2)
    t = rng.random((i1 - i0, j1 - j0)) * 1e6
    p = np.zeros((n1, n2))
    p[i0:i1, j0:j1] = t
    u = op.apply(p)
    v = box_to_grid(op, i0, j0, t)
    assert v.shape == (n1, n2)
    assert np.abs(v - u).max() <= 1e-13 * np.abs(u).max()


@pytest.mark.parametrize("periodic", [True, False])
@pytest.mark.parametrize("blocked", [False, True])
def test_single_precision_apply(periodic, blocked, monkeypatch):
    """float32 transforms: within 2e-6 of the double-precision displacement (single precision
    resolves ~1e-7; a double-precision path would agree to 1e-15, a wrong spectrum by O(1))."""
    if blocked:
        monkeypatch.setenv("TRIBOBEM_BLOCKED_FFT_POINTS", "1")
    n = 96
    op = make_operator(Grid.square(n, 1e-4, periodic=periodic), PAIR)
    p = np.random.default_rng(3).random((n, n)) * 1e6
    u = op.apply(p)
    u32 = op.apply(p, single=True)
    assert u32.dtype == np.float32
    err = np.abs(u32 - u).max() / np.abs(u).max()
    assert 1e-10 < err < 2e-6
    out = np.empty((n, n))
    assert op.apply(p, out=out, single=True) is out
    assert np.abs(out - u).max() <= 2e-6 * np.abs(u).max()


def test_large_free_grid_makes_its_spectrum_on_first_use():
    from tribobem.elasticity.operators import LAZY_SPECTRA_NODES

    n = int(np.sqrt(LAZY_SPECTRA_NODES))
    op = make_operator(Grid.square(n, 1e-3, periodic=False), PAIR)
    assert not op.spectra.built
    assert op.spectrum() is not None and op.spectra.built
