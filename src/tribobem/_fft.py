"""The FFT pieces every layer uses: pocketfft's transforms with an ``out`` argument (what
``scipy.fft`` calls) and the FFT thread count.  Below the subpackages, so that geometry
(statistics) and elasticity (operators) share them; :mod:`tribobem.elasticity.backend` re-exports
both."""

from __future__ import annotations

import os

import numpy as np
import scipy.fft

__all__ = ["pocketfft", "default_workers"]


def _private_pocketfft():
    """pocketfft's transforms with an ``out`` argument (what scipy.fft calls), if this scipy has
    them with the signatures used here -- checked once against scipy.fft on a small array; else
    None and the public functions are used (a private API: it may change without notice)."""
    try:
        from scipy.fft._pocketfft import pypocketfft as pf

        a = np.arange(12.0).reshape(3, 4) ** 1.5
        T = np.empty((6, 5), dtype=complex)
        pf.r2c(np.pad(a, ((0, 0), (0, 4))), (1,), True, 0, T[:3], 1)
        T[3:] = 0.0
        pf.c2c(T, (0,), True, 0, T, 1)
        if not np.allclose(T, scipy.fft.rfft2(a, s=(6, 8)), rtol=1e-12, atol=1e-12):
            return None
        u = np.empty((3, 8))
        pf.c2c(T, (0,), False, 2, T, 1)
        pf.c2r(T[:3], (1,), 8, False, 2, u, 1)
        if not np.allclose(u[:, :4], a, rtol=1e-12, atol=1e-12):
            return None
        return pf
    except Exception:  # pragma: no cover - another scipy layout or signature
        return None


pocketfft = _private_pocketfft()


def default_workers() -> int:
    """Threads for ``scipy.fft`` (env ``TRIBOBEM_FFT_WORKERS`` overrides; default all cores).

    Returns
    -------
    int
        The number of FFT threads, at least 1.
    """
    env = os.environ.get("TRIBOBEM_FFT_WORKERS")
    if env:
        return max(1, int(env))
    return os.cpu_count() or 1
