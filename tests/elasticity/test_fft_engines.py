"""FFT engines (elasticity/backend.py): every installed engine gives scipy.fft's transforms,
including a zero-padded transform after a full-size one of the same FFT shape (a reused FFTW
input buffer must not keep the previous data in its padding: regression, helper report)."""

from __future__ import annotations

import numpy as np
import pytest

from tribobem.elasticity.backend import Backend, available_fft_engines


@pytest.mark.parametrize("engine", available_fft_engines())
def test_engine_matches_scipy_including_padding_after_full_size(engine):
    be = Backend("numpy", fft=engine)
    ref = Backend("numpy", fft="scipy")
    rng = np.random.default_rng(0)
    full = rng.standard_normal((256, 256))
    small = rng.standard_normal((128, 128))
    a = be.rfft2(full, s=(256, 256))  # fills the engine's buffer of this shape
    b = be.rfft2(small, s=(256, 256))  # zero-padded into the same shape
    assert np.allclose(a, ref.rfft2(full, s=(256, 256)), rtol=0, atol=1e-9)
    assert np.allclose(b, ref.rfft2(small, s=(256, 256)), rtol=0, atol=1e-9)
    assert b[0, 0].real == pytest.approx(small.sum(), rel=1e-12)
    back = be.irfft2(b, s=(256, 256))
    assert np.allclose(back[:128, :128], small, atol=1e-12) and np.allclose(back[128:, :], 0.0, atol=1e-12)
