"""Array and FFT backend: NumPy + ``scipy.fft`` on the CPU, CuPy on a GPU.

Solvers never import numpy directly for field arithmetic; they call ``backend.xp``
so that the same code runs on CuPy arrays.  Real FFTs only (``rfft2``/``irfft2``).
"""

from __future__ import annotations

import os
from dataclasses import dataclass, field
from functools import lru_cache

import numpy as np
import scipy.fft


def default_workers() -> int:
    """Threads for ``scipy.fft`` (env ``TRIBOBEM_FFT_WORKERS`` overrides; default all cores)."""
    env = os.environ.get("TRIBOBEM_FFT_WORKERS")
    if env:
        return max(1, int(env))
    return os.cpu_count() or 1


@dataclass(frozen=True)
class Backend:
    """An array module with real 2-D FFTs.

    Parameters
    ----------
    name : {"numpy", "cupy"}
        Which array library holds the fields.
    workers : int
        FFT threads for the NumPy backend (ignored on CuPy).
    """

    name: str = "numpy"
    workers: int = field(default_factory=default_workers)

    @property
    def xp(self):
        if self.name == "numpy":
            return np
        import cupy

        return cupy

    def rfft2(self, a, s=None):
        if self.name == "numpy":
            return scipy.fft.rfft2(a, s=s, workers=self.workers)
        import cupyx.scipy.fft as cfft

        return cfft.rfft2(a, s=s)

    def irfft2(self, a, s):
        if self.name == "numpy":
            return scipy.fft.irfft2(a, s=s, workers=self.workers)
        import cupyx.scipy.fft as cfft

        return cfft.irfft2(a, s=s)

    def asarray(self, a, dtype=None):
        """Move ``a`` to this backend (no copy when it already lives there)."""
        return self.xp.asarray(a, dtype=dtype)

    def to_numpy(self, a) -> np.ndarray:
        """Bring an array back to host memory as a NumPy array."""
        if self.name == "numpy" or isinstance(a, np.ndarray):
            return np.asarray(a)
        return a.get()


@lru_cache(maxsize=None)
def get_backend(name: str = "numpy") -> Backend:
    """The backend called ``name`` ("numpy" or "cupy"); raises if CuPy is unusable."""
    if name not in ("numpy", "cupy"):
        from ..errors import InputError

        raise InputError("solver.backend", f"must be 'numpy' or 'cupy', got {name!r}")
    if name == "cupy":
        if not cupy_available():
            from ..errors import InputError

            raise InputError("solver.backend", "CuPy with a working CUDA device is not available; install tribobem[gpu]")
    return Backend(name)


def cupy_available() -> bool:
    """True when CuPy imports and sees at least one CUDA device."""
    try:
        import cupy

        return cupy.cuda.runtime.getDeviceCount() > 0
    except Exception:
        return False
