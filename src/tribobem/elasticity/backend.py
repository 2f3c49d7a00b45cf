"""Array and FFT backend: NumPy + an FFT library on the CPU, CuPy on a GPU.

Solvers never import numpy directly for field arithmetic; they call ``backend.xp``
so that the same code runs on CuPy arrays.  Real FFTs only (``rfft2``/``irfft2``).

FFT engines on the CPU (``Backend.fft``; env ``TRIBOBEM_FFT`` = ``auto`` (default),
``pyfftw``, ``mkl_fft`` or ``scipy``):

* ``pyfftw`` -- FFTW through pyFFTW (optional: ``pip install tribobem[fast]``), with plans
  made once per transform shape (FFTW_MEASURE from 128^2 on) and reused buffers;
* ``mkl_fft`` -- Intel MKL (optional);
* ``scipy`` -- ``scipy.fft`` (pocketfft), always available: the fallback.

``auto`` takes the first installed of pyfftw, mkl_fft, scipy: the order measured by
``benchmarks/fft_backends.py`` (one convolution rfft2 x kernel irfft2, 1 thread, CPU time
relative to scipy.fft on a loaded 2-core machine: pyFFTW 0.54 / 0.62 / 0.69 at 512^2 /
1024^2 / 2048^2 and 0.72 / 0.64 on zero-padded 512^2 / 1024^2; mkl_fft 1.12 / 0.85 / 0.72
and 0.74 / 0.70).  FFTW plans cost about 0.6 s (1024^2) and 0.9 s (2048^2) once per
shape and process.  All engines agree to 1e-15 relative.
"""

from __future__ import annotations

import os
import threading
from dataclasses import dataclass, field
from functools import lru_cache

import numpy as np
import scipy.fft

_ENGINES = ("pyfftw", "mkl_fft", "scipy")


def available_fft_engines() -> list[str]:
    """The CPU FFT engines that import here, fastest first (``scipy`` always)."""
    out = []
    for name in _ENGINES[:-1]:
        try:
            __import__(name)
            out.append(name)
        except Exception:  # not installed or broken: skip it
            pass
    return out + ["scipy"]


def default_fft() -> str:
    """The CPU FFT engine: env ``TRIBOBEM_FFT`` or ``auto`` (the fastest installed)."""
    env = os.environ.get("TRIBOBEM_FFT", "auto").strip().lower() or "auto"
    if env == "auto":
        return available_fft_engines()[0]
    if env not in _ENGINES:
        from ..errors import InputError

        raise InputError("TRIBOBEM_FFT", f"must be one of auto, {', '.join(_ENGINES)}; got {env!r}")
    return env


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
    fft : {"pyfftw", "mkl_fft", "scipy"}
        FFT engine of the NumPy backend (default: env ``TRIBOBEM_FFT`` or the fastest
        installed, see the module docstring; ignored on CuPy).
    """

    name: str = "numpy"
    workers: int = field(default_factory=default_workers)
    fft: str = field(default_factory=default_fft)
    # FFTW plans with their buffers, per (direction, shape): made once, reused.
    _plans: dict = field(default_factory=dict, compare=False, repr=False)

    def __post_init__(self):
        if self.fft not in _ENGINES:
            from ..errors import InputError

            raise InputError("solver.fft", f"must be one of {', '.join(_ENGINES)}; got {self.fft!r}")

    @property
    def xp(self):
        if self.name == "numpy":
            return np
        import cupy

        return cupy

    def rfft2(self, a, s=None):
        """2-D real FFT of ``a`` (zero-padded to ``s``); a new array."""
        if self.name == "numpy":
            if self.fft == "pyfftw":
                return self._fftw_rfft2(a, s)
            if self.fft == "mkl_fft":
                import mkl_fft

                return mkl_fft.rfft2(np.asarray(a, dtype=float), s=s)
            return scipy.fft.rfft2(a, s=s, workers=self.workers)
        import cupyx.scipy.fft as cfft

        return cfft.rfft2(a, s=s)

    def irfft2(self, a, s):
        """Inverse of :meth:`rfft2` on the grid ``s``; a new array (``a`` is not modified)."""
        if self.name == "numpy":
            if self.fft == "pyfftw":
                return self._fftw_irfft2(a, s)
            if self.fft == "mkl_fft":
                import mkl_fft

                return mkl_fft.irfft2(a, s=s)
            return scipy.fft.irfft2(a, s=s, workers=self.workers)
        import cupyx.scipy.fft as cfft

        return cfft.irfft2(a, s=s)

    # -- FFTW -------------------------------------------------------------------------

    def _fftw_plan(self, kind: str, s: tuple):
        """(lock, real buffer, complex buffer, FFTW object) for a transform of shape ``s``."""
        key = (kind, s)
        plan = self._plans.get(key)
        if plan is None:
            import pyfftw

            r = pyfftw.empty_aligned(s, dtype=np.float64)
            c = pyfftw.empty_aligned((s[0], s[1] // 2 + 1), dtype=np.complex128)
            # MEASURE finds plans 1.6-1.7x faster than ESTIMATE at >= 1024^2 (planning
            # 0.6-0.9 s once per shape); tiny grids are not worth it.
            flags = ("FFTW_MEASURE",) if s[0] * s[1] >= 128 * 128 else ("FFTW_ESTIMATE",)
            if kind == "r2c":
                fft = pyfftw.FFTW(r, c, axes=(0, 1), direction="FFTW_FORWARD", flags=flags, threads=self.workers)
            else:
                fft = pyfftw.FFTW(c, r, axes=(0, 1), direction="FFTW_BACKWARD", flags=flags, threads=self.workers)
            r[...] = 0.0  # planning wrote into the buffers; the padding must be 0
            # [nx, ny] last written into r by rfft2: beyond it r is 0.
            plan = self._plans.setdefault(key, (threading.Lock(), r, c, fft, [0, 0]))
        return plan

    def _fftw_rfft2(self, a, s):
        a = np.asarray(a, dtype=np.float64)
        s = tuple(a.shape) if s is None else tuple(int(v) for v in s)
        lock, r, c, fft, extent = self._fftw_plan("r2c", s)
        nx, ny = a.shape
        with lock:  # the buffers are shared: one transform at a time per plan
            # Zero padding: clear what an earlier, larger input left beyond (nx, ny) (an
            # out-of-place r2c preserves its input, so r is otherwise unchanged).
            if extent[0] > nx:
                r[nx:extent[0], :] = 0.0
            if extent[1] > ny:
                r[:nx, ny:extent[1]] = 0.0
            extent[:] = [nx, ny]
            r[:nx, :ny] = a
            fft.execute()
            return c.copy()

    def _fftw_irfft2(self, a, s):
        s = tuple(int(v) for v in s)
        lock, r, c, fft, _ = self._fftw_plan("c2r", s)
        with lock:
            c[...] = a  # a multi-dimensional c2r destroys its input: work on a copy
            fft.execute()  # unnormalised
            return np.multiply(r, 1.0 / (s[0] * s[1]))

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
