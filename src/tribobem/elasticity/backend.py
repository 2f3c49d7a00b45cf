"""Array and FFT backend: NumPy + an FFT library on the CPU, CuPy on a GPU.

Solvers never import numpy directly for field arithmetic; they call ``backend.xp``
so that the same code runs on CuPy arrays.  Real FFTs only (``rfft2``/``irfft2``).

FFT engines on the CPU (``Backend.fft``; env ``TRIBOBEM_FFT`` = ``auto`` (default),
``pyfftw``, ``mkl_fft`` or ``scipy``):

* ``pyfftw`` -- FFTW through pyFFTW (optional: ``pip install tribobem[fast]``), with plans
  made once per transform shape (FFTW_MEASURE from 128^2 on) and reused buffers;
* ``mkl_fft`` -- Intel MKL (optional);
* ``scipy`` -- ``scipy.fft`` (pocketfft), always available: the fallback.

``auto`` takes the first installed of pyfftw, mkl_fft, scipy: the order of their speed on one
convolution, measured by ``benchmarks/fft_backends.py`` (numbers in benchmarks/README.md).  All
engines agree to 1e-15 relative.

The engine does the whole-array transforms (:meth:`Backend.rfft2` / :meth:`Backend.irfft2`:
the periodic operators and the kernel spectra).  The lean transforms -- zero-padded ones (free
boundary: :meth:`Backend.rfft2_padded` and :meth:`Backend.irfft2_rows` skip the padding rows in
the real passes) and the preconditioners' box transforms (:meth:`Backend.rfft2_into`) -- write
into reused arrays through pocketfft's ``out`` argument, with every engine: they beat the other
engines' whole-array transforms with their copies (a 512^2 free-boundary convolution 7.6 ms
against pyFFTW's 10.3 ms, 2048^2 135 against 203 ms; the adhesive loop of
benchmarks/adhesive_loop.py 46 against 59 s of CPU).
Threads: transforms of at most ``SMALL_FFT`` points run on one thread (two threads cost more CPU
there and, between the NumPy work of a solver, more wall time).
"""

from __future__ import annotations

import os
import threading
from dataclasses import dataclass, field

import numpy as np
import scipy.fft

from .._fft import default_workers  # noqa: F401  (re-exported: the backend's public helper)
from .._fft import pocketfft as _pocketfft
from ..errors import InputError

_ENGINES = ("pyfftw", "mkl_fft", "scipy")
#: The complex type of the real FFT of each real type.
_COMPLEX = {np.float32: np.complex64, np.float64: np.complex128}





def available_fft_engines() -> list[str]:
    """The CPU FFT engines that import here, fastest first (``scipy`` always).

    Returns
    -------
    list of str
        Engine names in the order of ``pyfftw``, ``mkl_fft``, ``scipy`` (the order of their
        speed on one convolution); ``scipy`` is always last, as the fallback.
    """
    out = []
    for name in _ENGINES[:-1]:
        try:
            __import__(name)
            out.append(name)
        except Exception:  # not installed or broken: skip it
            pass
    return out + ["scipy"]


def default_fft() -> str:
    """The CPU FFT engine: env ``TRIBOBEM_FFT`` or ``auto`` (the fastest installed).

    Returns
    -------
    str
        One of ``"pyfftw"``, ``"mkl_fft"``, ``"scipy"``.

    Raises
    ------
    InputError
        When ``TRIBOBEM_FFT`` names no known engine.
    """
    env = os.environ.get("TRIBOBEM_FFT", "auto").strip().lower() or "auto"
    if env == "auto":
        return available_fft_engines()[0]
    if env not in _ENGINES:

        raise InputError("TRIBOBEM_FFT", f"must be one of auto, {', '.join(_ENGINES)}; got {env!r}")
    return env


#: Transforms of at most this many points run on ``small_fft_threads`` threads (default 1): below
#: this size a second thread costs more CPU than it saves wall time between a solver's NumPy work;
#: from 1024^2 on the threads pay (measurements in benchmarks/README.md).
SMALL_FFT = 512 * 512


def default_small_fft_threads() -> int | None:
    """Threads for transforms of <= SMALL_FFT points: 1, or None (= ``workers``) when the env
    ``TRIBOBEM_FFT_WORKERS`` sets the threads explicitly.

    Returns
    -------
    int or None
        1 by default (a second thread costs more than it saves on small grids, see
        ``SMALL_FFT``); None when the user chose the thread count, which then holds for all sizes.
    """
    return None if os.environ.get("TRIBOBEM_FFT_WORKERS") else 1


#: Free-boundary convolutions on padded grids of at least this many points run in blocks
#: (:meth:`Backend.convolve_padded_blocked`): about 4 grid fields less at the peak, which is what
#: keeps a 4096^2 whole-burl solve under 3 GB.  Measured on 2 cores with blocks of 2^16 points:
#: as fast as the unblocked transforms at 1024^2 and 2048^2 grids (0.20-0.22 s against 0.23 s
#: per convolution at 2048^2; 2^18-2^22-point blocks were 25-60 % slower: they leave the cache).
#: Below it the unblocked transforms (one call per direction) are kept.  Env
#: ``TRIBOBEM_BLOCKED_FFT_POINTS`` overrides (tests force it small).
BLOCKED_FFT_POINTS = 2048 * 2048

#: Points per block of the blocked transforms (1 MB complex work blocks: they stay in cache).
_BLOCK_POINTS = 1 << 16


def times_spectrum(T, spec, reciprocal: bool = False):
    """``T`` times the kernel spectrum ``spec`` in place, or divided by it (``reciprocal``: the
    inverse operator without a second stored spectrum).

    Parameters
    ----------
    T : array
        Complex spectrum (or a block of columns of it), overwritten.
    spec : array
        Kernel spectrum of the same shape, real or complex.
    reciprocal : bool
        Divide instead of multiply.

    Returns
    -------
    array
        ``T``.
    """
    if reciprocal:
        T /= spec
    else:
        T *= spec
    return T


def blocked_fft_points() -> int:
    """The padded-grid size from which free-boundary convolutions run in blocks
    (``BLOCKED_FFT_POINTS``, or env ``TRIBOBEM_BLOCKED_FFT_POINTS``).

    Returns
    -------
    int
        Number of points of the padded (2 nx x 2 ny) transform grid.
    """
    env = os.environ.get("TRIBOBEM_BLOCKED_FFT_POINTS")
    return max(1, int(env)) if env else BLOCKED_FFT_POINTS


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
    small_fft_threads: int | None = field(default_factory=default_small_fft_threads)
    fft: str = field(default_factory=default_fft)
    # FFTW plans with their buffers, per (direction, shape): made once, reused.
    _plans: dict = field(default_factory=dict, compare=False, repr=False)
    # Per-thread reusable work arrays (work_buffers): backends are shared by the threads of a
    # threaded Dask worker.
    _work: threading.local = field(default_factory=threading.local, init=False, compare=False, repr=False)

    def __post_init__(self):
        if self.fft not in _ENGINES:

            raise InputError("solver.fft", f"must be one of {', '.join(_ENGINES)}; got {self.fft!r}")

    def threads(self, shape) -> int:
        """Threads for one transform on the grid ``shape`` (see ``SMALL_FFT``).

        Parameters
        ----------
        shape : tuple of int
            The (padded) transform grid, nodes.

        Returns
        -------
        int
            ``workers`` above ``SMALL_FFT`` points (or when ``small_fft_threads`` is None), else
            ``small_fft_threads`` capped by ``workers``.
        """
        if self.small_fft_threads is None or int(shape[0]) * int(shape[1]) > SMALL_FFT:
            return self.workers
        return max(1, min(self.workers, self.small_fft_threads))

    @property
    def xp(self):
        """The array module of this backend: :mod:`numpy`, or :mod:`cupy` (imported on first use)."""
        if self.name == "numpy":
            return np
        import cupy

        return cupy

    def rfft2(self, a, s=None):
        """2-D real FFT of ``a`` (zero-padded to ``s``); a new array.

        Parameters
        ----------
        a : array
            Real field on this backend (any unit; the transform is unnormalised).
        s : tuple of int, optional
            Transform grid (N1, N2) >= ``a.shape``; None: ``a.shape``.

        Returns
        -------
        array
            Complex spectrum of shape (N1, N2 // 2 + 1), a fresh array (never a shared plan buffer).
        """
        if self.name == "numpy":
            if self.fft == "pyfftw":
                return self._fftw_rfft2(a, s)
            if self.fft == "mkl_fft":
                import mkl_fft

                return mkl_fft.rfft2(np.asarray(a, dtype=float), s=s)
            return scipy.fft.rfft2(a, s=s, workers=self.threads(a.shape if s is None else s))
        import cupyx.scipy.fft as cfft

        return cfft.rfft2(a, s=s)

    def irfft2(self, a, s):
        """Inverse of :meth:`rfft2` on the grid ``s``; a new array (``a`` is not modified).

        Parameters
        ----------
        a : array
            Complex spectrum of shape (N1, N2 // 2 + 1).
        s : tuple of int
            The real grid (N1, N2) (needed: N2 is not determined by the half spectrum).

        Returns
        -------
        array
            Real field of shape ``s``, normalised so that ``irfft2(rfft2(x), x.shape) == x``.
        """
        if self.name == "numpy":
            if self.fft == "pyfftw":
                return self._fftw_irfft2(a, s)
            if self.fft == "mkl_fft":
                import mkl_fft

                return mkl_fft.irfft2(a, s=s)
            return scipy.fft.irfft2(a, s=s, workers=self.threads(s))
        import cupyx.scipy.fft as cfft

        return cfft.irfft2(a, s=s)

    # -- transforms into work arrays (pocketfft, every engine) -----------------------

    def rfft2_into(self, a, out):
        """:meth:`rfft2` of ``a`` (not padded) written into ``out``: the pocketfft call of
        ``scipy.fft.rfft2``, so the same numbers to the last bit, without a fresh spectrum per
        call (the preconditioners run at every step of their CG).  Lean transforms only
        (:meth:`_lean`).

        Parameters
        ----------
        a : ndarray
            Real field (float64, or float32 for a single-precision transform).
        out : ndarray
            Complex work array of shape (N1, N2 // 2 + 1) (complex64 for float32 input).

        Returns
        -------
        ndarray
            ``out``.
        """
        _pocketfft.r2c(np.ascontiguousarray(a), (0, 1), True, 0, out, self.threads(a.shape))
        return out

    def irfft2_into(self, A, s, out):
        """:meth:`irfft2` of ``A`` on the grid ``s`` written into ``out`` (``A`` is kept): the
        pocketfft call of ``scipy.fft.irfft2``, the same numbers to the last bit.  Lean transforms
        only (:meth:`_lean`).

        Parameters
        ----------
        A : ndarray
            Complex spectrum of shape (N1, N2 // 2 + 1).
        s : tuple of int
            The real grid (N1, N2).
        out : ndarray
            Real work array of shape ``s`` (float32 for a complex64 spectrum).

        Returns
        -------
        ndarray
            ``out``.
        """
        _pocketfft.c2r(A, (0, 1), int(s[1]), False, 2, out, self.threads(s))
        return out

    # -- zero-padded transforms (free boundary) ---------------------------------------

    def rfft2_padded(self, a, s, out=None, single: bool = False):
        """:meth:`rfft2` of ``a`` (m1 x m2) zero-padded to ``s`` (N1 x N2, N >= m).

        Lean (:meth:`_lean`, every engine of the NumPy backend): the real FFT along y of the m1
        rows only (the N1 - m1 padding rows transform to zero), then the complex FFT along x in
        place; written into ``out`` (complex, N1 x (N2/2 + 1)) when given, through pocketfft's
        ``out`` argument (no fresh multi-MB array per call: their page faults cost a sizeable part
        of a transform, figures in benchmarks/README.md).  Other backends (CuPy): :meth:`rfft2`.

        Parameters
        ----------
        a : array
            Real field of shape (m1, m2).
        s : tuple of int
            Padded transform grid (N1, N2), N1 >= m1, N2 >= m2.
        out : ndarray, optional
            Complex work array of shape (N1, N2 // 2 + 1) to write into (lean path only;
            complex64 in single precision).
        single : bool
            Transform in single precision (complex64; :attr:`single_precision` backends only,
            ignored by the others).

        Returns
        -------
        array
            The complex spectrum (N1, N2 // 2 + 1): ``out`` when given on the lean path,
            else a new array.
        """
        if not self._lean():
            return self.rfft2(a, s=s)
        m1, m2 = a.shape
        N1, N2 = int(s[0]), int(s[1])
        w = self.threads(s)
        real = np.float32 if single else np.float64
        T = out if out is not None else np.empty((N1, N2 // 2 + 1), dtype=_COMPLEX[real])
        if m2 != N2:
            row = self._real_rows(m1, m2, N2, real)
            dirty = work_buffers(self).pop(("rows dirty", m1, m2, N2, real), False)
            if dirty:  # lent as the out of irfft2_rows: clear the padding again
                row[:, m2:] = 0.0
            row[:, :m2] = a
            src = row
        else:
            src = np.ascontiguousarray(a, dtype=real)
        _pocketfft.r2c(src, (1,), True, 0, T[:m1], w)
        T[m1:] = 0.0
        _pocketfft.c2c(T, (0,), True, 0, T, w)
        return T

    def irfft2_rows(self, A, s, rows: int, out=None):
        """The first ``rows`` rows of :meth:`irfft2` (``A`` on the grid ``s``), all N2 columns.

        Lean: ``A`` is overwritten (the inverse FFT along x in place), then the real
        inverse FFT along y of the kept rows only (into ``out``, real rows x N2, when given).
        Other backends (CuPy): :meth:`irfft2` (``A`` kept) and a slice.

        Parameters
        ----------
        A : array
            Complex spectrum of shape (N1, N2 // 2 + 1); overwritten on the lean path.
        s : tuple of int
            The real grid (N1, N2).
        rows : int
            Number of leading rows to return (the unpadded m1: the padding rows are never needed).
        out : ndarray, optional
            Real work array of shape (rows, N2) to write into (lean path only).

        Returns
        -------
        array
            Real array of shape (rows, N2): ``out`` when given on the lean path, else new
            (on the other paths a slice of the full inverse).
        """
        if not self._lean():
            return self.irfft2(A, s=s)[:rows]
        N2 = int(s[1])
        w = self.threads(s)
        _pocketfft.c2c(A, (0,), False, 2, A, w)
        u = out if out is not None else np.empty((rows, N2), dtype=np.float32 if A.dtype == np.complex64 else float)
        _pocketfft.c2r(A[:rows], (1,), N2, False, 2, u, w)
        return u

    def convolve_padded_blocked(self, a, spec, s, out=None, reciprocal: bool = False, single: bool = False):
        """The zero-padded (free-boundary) convolution of ``a`` with the kernel spectrum ``spec``
        in blocks: the same transforms as :meth:`rfft2_padded`, ``spec`` and
        :meth:`irfft2_rows`, but the FFT along x runs on blocks of columns and the real FFTs
        along y on blocks of rows, so that the only full-size work array is the m1 x (N2/2 + 1)
        half-spectrum of the unpadded rows (about 2 grid fields) instead of the N1 x (N2/2 + 1)
        padded spectrum and the m1 x N2 rows (about 6).  Every 1-D transform is the one of the
        unblocked path, so the result is the same to the last bit (tested).  Lean transforms only
        (``_lean``).

        Parameters
        ----------
        a : ndarray
            Real field of shape (m1, m2).
        spec : ndarray
            Kernel spectrum, real or complex, of shape (N1, N2 // 2 + 1).
        s : tuple of int
            Padded transform grid (N1, N2).
        out : ndarray, optional
            Real array of shape (m1, m2) for the result (may be ``a``).
        reciprocal : bool
            Divide by ``spec`` instead of multiplying (the inverse operator, with no second
            spectrum stored).
        single : bool
            Transform in single precision (complex64 work arrays, half the memory); ``spec``
            should then be single precision too (a double one is cast block by block).

        Returns
        -------
        ndarray
            The first m1 x m2 values of the inverse transform: ``out`` when given (float32
            with ``single`` when not given).
        """
        m1, m2 = a.shape
        N1, N2 = int(s[0]), int(s[1])
        H = N2 // 2 + 1
        w = self.threads(s)
        bufs = work_buffers(self)
        rb = max(1, min(m1, _BLOCK_POINTS // N2))
        cb = max(1, min(H, _BLOCK_POINTS // N1))
        real = np.float32 if single else np.float64
        cplx = _COMPLEX[real]
        key = ("blocked", m1, m2, N1, N2, rb, cb, real)
        got = bufs.get(key)
        if got is None:
            if len(bufs) > 16:
                bufs.clear()
            # (a single-precision solve uses both: the double one only for its exact checks, so
            # that the full-size half-spectrum of the other precision is dropped first)
            for k in [k for k in bufs if k[0] == "blocked" and k[1:7] == key[1:7]]:
                del bufs[k]
            got = bufs[key] = (np.empty((m1, H), dtype=cplx), np.zeros((rb, N2), dtype=real),
                               np.empty((N1, cb), dtype=cplx))
        S, row, col = got
        # real FFT along y of the unpadded rows (the padding rows would transform to 0)
        for i0 in range(0, m1, rb):
            k = min(rb, m1 - i0)
            row[:k, :m2] = a[i0:i0 + k]
            row[:k, m2:] = 0.0  # the inverse below wrote there
            _pocketfft.r2c(row[:k], (1,), True, 0, S[i0:i0 + k], w)
        # FFT along x of each block of columns, zero-padded to N1 rows, times the kernel, back
        for j0 in range(0, H, cb):
            k = min(cb, H - j0)
            C = col if k == cb else np.empty((N1, k), dtype=cplx)
            C[:m1] = S[:, j0:j0 + k]
            C[m1:] = 0.0
            _pocketfft.c2c(C, (0,), True, 0, C, w)
            times_spectrum(C, spec[:, j0:j0 + k], reciprocal)
            _pocketfft.c2c(C, (0,), False, 2, C, w)
            S[:, j0:j0 + k] = C[:m1]
        # real inverse FFT along y of the kept rows, in blocks of rows
        u = out if out is not None else np.empty((m1, m2), dtype=real)
        for i0 in range(0, m1, rb):
            k = min(rb, m1 - i0)
            _pocketfft.c2r(S[i0:i0 + k], (1,), N2, False, 2, row[:k], w)
            u[i0:i0 + k] = row[:k, :m2]
        return u

    def blocked(self, s) -> bool:
        """Whether free-boundary convolutions on the padded grid ``s`` run in blocks
        (:meth:`convolve_padded_blocked`): lean transforms, and a padded grid of at least
        ``BLOCKED_FFT_POINTS`` points (env ``TRIBOBEM_BLOCKED_FFT_POINTS``)."""
        return self._lean() and int(s[0]) * int(s[1]) >= blocked_fft_points()

    def rows_buffer(self, m1: int, m2: int, N2: int, dtype=np.float64):
        """The (per-thread) m1 x N2 real work array of :meth:`rfft2_padded`, lent as the ``out`` of
        :meth:`irfft2_rows` (lean path): no fresh m1 x N2 array per inverse transform.  Its
        contents are valid until the next transform on this thread; the next forward transform
        clears the padding columns it overwrote.

        Parameters
        ----------
        m1, m2, N2 : int
            Rows, unpadded and padded columns.
        dtype : numpy dtype
            float64, or float32 for a single-precision transform.

        Returns
        -------
        ndarray
            Real array of shape (m1, N2).
        """
        real = np.float32 if np.dtype(dtype) == np.float32 else np.float64
        row = self._real_rows(m1, m2, N2, real)
        work_buffers(self)[("rows dirty", m1, m2, N2, real)] = True
        return row

    def _lean(self) -> bool:
        """Whether the lean (pocketfft, work-array) transforms run: the NumPy backend, with any
        engine (module docstring), where this scipy has pocketfft's ``out`` calls."""
        return self.name == "numpy" and _pocketfft is not None

    @property
    def single_precision(self) -> bool:
        """Whether transforms of float32 input run in single precision.

        The lean transforms of the NumPy backend (pocketfft, every engine) transform float32
        arrays in single precision: about 1.7x faster than double for the row-skipping padded transforms
        of a 188^2 box (375^2), about 3x for whole 2-D real transforms of that size
        (benchmarks/README.md, the adhesive loop's single precision in TangCG).  The tangential
        solver uses it where an error of ~1e-7 relative to the transformed field is harmless:
        the images of its search directions and its preconditioner (the residual is taken from
        a double-precision K q).  CuPy: False (double precision throughout).
        """
        return self._lean()

    def _real_rows(self, m1: int, m2: int, N2: int, real=np.float64):
        """A real work array of m1 x N2 whose columns m2.. are 0 (only [:, :m2] is ever
        written into it), per thread."""
        bufs = work_buffers(self)
        key = ("rows", m1, m2, N2, real)
        b = bufs.get(key)
        if b is None:
            if len(bufs) > 16:
                bufs.clear()
            b = bufs[key] = np.zeros((m1, N2), dtype=real)
        return b

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
                fft = pyfftw.FFTW(r, c, axes=(0, 1), direction="FFTW_FORWARD", flags=flags, threads=self.threads(s))
            else:
                fft = pyfftw.FFTW(c, r, axes=(0, 1), direction="FFTW_BACKWARD", flags=flags, threads=self.threads(s))
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
        """Move ``a`` to this backend (no copy when it already lives there).

        Parameters
        ----------
        a : array_like
            Host or device data.
        dtype : dtype, optional
            Target dtype; None keeps ``a``'s.

        Returns
        -------
        array
            ``a`` as an array of :attr:`xp`.
        """
        return self.xp.asarray(a, dtype=dtype)

    def to_numpy(self, a) -> np.ndarray:
        """Bring an array back to host memory as a NumPy array.

        Parameters
        ----------
        a : array
            A NumPy or CuPy array.

        Returns
        -------
        numpy.ndarray
            ``a`` itself on the host (no copy), or a host copy of a device array.
        """
        if self.name == "numpy" or isinstance(a, np.ndarray):
            return np.asarray(a)
        return a.get()


def single_spectrum(owner, key, spec, keep_real: bool = False):
    """The single-precision copy (complex64, also of a real spectrum, unless ``keep_real``) of
    the kernel spectrum ``spec``, cached on ``owner`` under ``key`` (made again when ``spec`` is
    another array than the one cached).

    Parameters
    ----------
    owner : object
        The operator the spectrum belongs to (the copy is kept in its
        ``cache.single_spectra``, :class:`~tribobem.elasticity.cache.OperatorCache`).
    key : hashable
        Name of the spectrum (e.g. the block and the transform shape).
    spec : ndarray
        The double-precision spectrum.
    keep_real : bool
        A real spectrum stays real (float32: half the memory of complex64; the normal solvers'
        large free-boundary grids, whose transforms run in blocks).

    Returns
    -------
    ndarray
        Its single-precision copy.
    """
    cache = owner.cache.single_spectra
    real = keep_real and np.dtype(spec.dtype).kind != "c"
    key = (key, real)
    got = cache.get(key)
    if got is None or got[0] is not spec:
        if len(cache) >= 32:
            cache.clear()
        # complex64 also for a real spectrum (zero imaginary parts): the same products, and NumPy
        # multiplies complex64 by complex64 faster than by a float32 array (cast in chunks)
        got = cache[key] = (spec, spec.astype(np.float32 if real else np.complex64))
    return got[1]



def work_buffers(owner) -> dict:
    """A dict of reusable work arrays attached to ``owner``, one per thread (operators and
    backends are shared by the threads of a threaded Dask worker).

    Parameters
    ----------
    owner : object
        The object the buffers belong to: an operator (its ``cache.work``,
        :class:`~tribobem.elasticity.cache.OperatorCache`) or a :class:`Backend` (its own
        thread-local store).

    Returns
    -------
    dict
        This thread's buffers of ``owner``, keyed by whatever the caller chooses; callers clear
        it when it grows (a bounded cache, not a registry).
    """
    cache = getattr(owner, "cache", None)
    tls = owner._work if cache is None else cache.work
    bufs = getattr(tls, "bufs", None)
    if bufs is None:
        bufs = tls.bufs = {}
    return bufs


def work_array(owner, key, shape, dtype, xp=np, limit: int = 32):
    """A reusable work array of ``owner`` (per thread, :func:`work_buffers`), made on first use
    under ``key`` with this shape and dtype; its content is whatever the last user left.  When
    ``owner`` already holds ``limit`` arrays they are all dropped first (the box shapes of a load
    path change: the memory stays bounded).

    Parameters
    ----------
    owner : object
        The operator the array belongs to.
    key : hashable
        The caller's name for the array (shape and dtype are added to it).
    shape : tuple of int
    dtype : dtype
    xp : module
        The array module to allocate with (NumPy or CuPy).
    limit : int
        Largest number of arrays kept per owner and thread.

    Returns
    -------
    ndarray
    """
    bufs = work_buffers(owner)
    full = (key, tuple(int(n) for n in shape), np.dtype(dtype).str)
    b = bufs.get(full)
    if b is None:
        if len(bufs) >= limit:
            bufs.clear()
        b = bufs[full] = xp.empty(shape, dtype=dtype)
    return b


def cupy_available() -> bool:
    """True when CuPy imports and sees at least one CUDA device.

    Returns
    -------
    bool
        False on any import or CUDA runtime error (a missing driver is not an error here).
    """
    try:
        import cupy

        return cupy.cuda.runtime.getDeviceCount() > 0
    except Exception:
        return False
