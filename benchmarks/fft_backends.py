"""Which FFT library is fastest for tribobem's convolution?  (issue 9, item 8)

Times one convolution u = irfft2(rfft2(p, s) * K(q), s) -- what ``op.apply`` does -- with

* ``scipy.fft`` (pocketfft, ``workers=``), tribobem's default and fallback;
* ``numpy.fft`` (pocketfft, NumPy >= 2 C++ port; no threads);
* ``mkl_fft`` (Intel MKL; threads from ``MKL_NUM_THREADS``, set before import);
* ``pyFFTW`` planned transforms (``pyfftw.builders``, FFTW_MEASURE, reused buffers), which is
  what :class:`tribobem.elasticity.backend.Backend` uses with ``fft="pyfftw"``;
* the tribobem backend itself (``Backend(fft=...)``) for each engine it can use.

on periodic n x n grids (fft size n) and free-boundary grids (zero padding to 2n).  Timings are
interleaved (one call of each engine per round) and the minimum over rounds is reported, both
wall time and CPU time (``time.process_time``: all threads of the process), because the machine
may be shared.  Engines that are not installed are skipped.

    TRIBOBEM_FFT_WORKERS=1 MKL_NUM_THREADS=1 python benchmarks/fft_backends.py
    python benchmarks/fft_backends.py --sizes 1024 2048 --workers 2 --repeats 10
"""

from __future__ import annotations

import math
import os
import sys
import time

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from common import markdown_table  # noqa: E402


def engines(workers: int) -> dict:
    """name -> factory(shape, s) returning conv(p, spec) -> u (a fresh array)."""
    out = {}
    import scipy.fft

    def scipy_factory(shape, s):
        def conv(p, spec):
            T = scipy.fft.rfft2(p, s=s, workers=workers)
            T *= spec
            return scipy.fft.irfft2(T, s=s, workers=workers)[: shape[0], : shape[1]]
        return conv

    out[f"scipy.fft (workers={workers})"] = scipy_factory

    def numpy_factory(shape, s):
        def conv(p, spec):
            T = np.fft.rfft2(p, s=s)
            T *= spec
            return np.fft.irfft2(T, s=s)[: shape[0], : shape[1]]
        return conv

    out["numpy.fft"] = numpy_factory

    try:
        import mkl_fft

        def mkl_factory(shape, s):
            def conv(p, spec):
                T = mkl_fft.rfft2(p, s=s)
                T *= spec
                return mkl_fft.irfft2(T, s=s)[: shape[0], : shape[1]]
            return conv

        out[f"mkl_fft (MKL_NUM_THREADS={os.environ.get('MKL_NUM_THREADS', 'default')})"] = mkl_factory
    except ImportError:
        pass

    try:
        import pyfftw

        def fftw_factory(shape, s):
            a = pyfftw.empty_aligned(s, dtype=float)
            c = pyfftw.empty_aligned((s[0], s[1] // 2 + 1), dtype=complex)
            fwd = pyfftw.FFTW(a, c, axes=(0, 1), direction="FFTW_FORWARD", flags=("FFTW_MEASURE",), threads=workers)
            bwd = pyfftw.FFTW(c, a, axes=(0, 1), direction="FFTW_BACKWARD", flags=("FFTW_MEASURE",), threads=workers)
            a[...] = 0.0
            nx, ny = shape

            def conv(p, spec):
                a[:nx, :ny] = p  # the padding stays 0 (the backward transform overwrites a: re-zero)
                if (nx, ny) != tuple(s):
                    a[nx:, :] = 0.0
                    a[:nx, ny:] = 0.0
                fwd()
                np.multiply(c, spec, out=c)
                bwd()  # FFTW.__call__ normalises the inverse like irfft2
                return a[:nx, :ny].copy()
            return conv

        out[f"pyfftw planned (threads={workers})"] = fftw_factory
    except ImportError:
        pass

    try:
        from tribobem.elasticity.backend import Backend, available_fft_engines
    except ImportError:  # an older tribobem without the engine choice
        return out
    for eng in available_fft_engines():
        def tri_factory(shape, s, eng=eng):
            be = Backend("numpy", workers, fft=eng, small_fft_threads=None)

            def conv(p, spec):
                T = be.rfft2(p, s=s)
                T *= spec
                return be.irfft2(T, s=s)[: shape[0], : shape[1]]
            return conv

        out[f"tribobem Backend(fft={eng!r})"] = tri_factory
    return out


def bench(n: int, padded: bool, workers: int, repeats: int) -> list:
    shape = (n, n)
    s = (2 * n, 2 * n) if padded else shape
    rng = np.random.default_rng(0)
    p = rng.random(shape)
    spec = 1.0 / (1.0 + np.hypot(*np.meshgrid(np.fft.fftfreq(s[0]), np.fft.rfftfreq(s[1]), indexing="ij")))
    ref = None
    convs = {}
    for name, fac in engines(workers).items():
        conv = fac(shape, s)
        u = conv(p, spec)  # warm-up (plans, caches)
        if ref is None:
            ref = u.copy()
        err = float(np.abs(u - ref).max() / np.abs(ref).max())
        convs[name] = (conv, err)
    wall = {k: math.inf for k in convs}
    cpu = {k: math.inf for k in convs}
    for _ in range(repeats):
        for name, (conv, _) in convs.items():
            c0, t0 = time.process_time(), time.perf_counter()
            conv(p, spec)
            t1, c1 = time.perf_counter(), time.process_time()
            wall[name] = min(wall[name], t1 - t0)
            cpu[name] = min(cpu[name], c1 - c0)
    base = next(iter(convs))
    return [[f"{n}^2" + (f" (padded {s[0]}^2)" if padded else ""), name, 1e3 * wall[name], 1e3 * cpu[name],
             cpu[name] / cpu[base], convs[name][1]] for name in convs]


def main(argv=None) -> int:
    import argparse

    from common import environment

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sizes", type=int, nargs="+", default=[512, 1024, 2048])
    ap.add_argument("--padded-sizes", type=int, nargs="*", default=[512, 1024],
                    help="free-boundary grids (FFT of size 2n)")
    ap.add_argument("--workers", type=int, default=int(os.environ.get("TRIBOBEM_FFT_WORKERS", "1")))
    ap.add_argument("--repeats", type=int, default=7)
    args = ap.parse_args(argv)
    print("## FFT engines for one convolution (rfft2, kernel multiply, irfft2)\n")
    print(environment(), "\n")
    rows = []
    for n in args.sizes:
        rows += bench(n, False, args.workers, args.repeats)
    for n in args.padded_sizes:
        rows += bench(n, True, args.workers, args.repeats)
    print(markdown_table(["grid", "engine", "wall ms (min)", "CPU ms (min)", "CPU / first engine",
                          "max rel. diff"], rows))
    return 0


if __name__ == "__main__":
    sys.exit(main())
