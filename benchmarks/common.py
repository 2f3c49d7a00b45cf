"""Shared helpers of the tribobem-vs-Tamaas benchmarks (not a test module, not timed by CI).

What lives here:

* the benchmark problem: a periodic self-affine surface generated WITH TAMAAS
  (``SurfaceGeneratorFilter2D`` + ``Isopowerlaw2D``) and rescaled to a spectral rms slope
  of 1, so that both codes get the identical array (a NumPy fallback with the same PSD,
  but other random numbers, is used when Tamaas is not installed);
* the gap convention: Tamaas takes the surface as the heights of the rigid rough body
  pushed onto the elastic flat; tribobem takes the undeformed gap ``h = max(s) - s``.
  Both give the same gap field up to a constant, which the periodic problem absorbs;
* interleaved timing (A, B, A, B, ... keep the minimum), which is what a machine shared
  with other jobs allows: report ratios, not absolute times;
* peak-memory probes in a fresh subprocess per (code, problem, size);
* a capture of Tamaas's C++ log (written to file descriptor 1) to read its iteration count.

Run ``python benchmarks/common.py --probe-memory CODE PROBLEM N`` to get one memory
probe as JSON (that is what the benchmark scripts do).
"""

from __future__ import annotations

import argparse
import contextlib
import ctypes
import gc
import json
import math
import os
import platform
import re
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass, field

import numpy as np

try:  # Tamaas is optional: without it the scripts time tribobem alone.
    import tamaas as tm

    HAVE_TAMAAS = True
except Exception:  # pragma: no cover - depends on the environment
    tm = None
    HAVE_TAMAAS = False

# --------------------------------------------------------------------------------------
# The benchmark problem (documented in benchmarks/README.md)
# --------------------------------------------------------------------------------------

#: Side length of the periodic cell (m); the problem is scale-free, so 1 is as good as any.
L = 1.0
#: Young's modulus and Poisson's ratio of the elastic body (the other one is rigid).
#: nu != 0 checks that both codes use E* = E / (1 - nu^2).
E, NU = 1.0, 0.3
E_STAR = E / (1.0 - NU**2)
#: PSD of the self-affine surface (Tamaas ``Isopowerlaw2D``, wavenumbers in units of 2 pi / L).
HURST = 0.8
Q0 = 4  # long-wavelength cut-off: no roughness with wavelength > L/4
Q1 = 4  # roll-off (= Q0: no plateau, the power law starts right at Q0)
#: Seed of Tamaas's generator.
SEED = 1
#: Target spectral rms slope of the surface.
RMS_SLOPE = 1.0


def q2_for(n: int) -> int:
    """Short-wavelength cut-off: n/4, i.e. 4 grid cells per shortest wavelength."""
    return max(n // 4, Q1 + 1)


def spectral_rms_slope(h: np.ndarray, lx: float = L, ly: float = L) -> float:
    """rms |grad h| of a periodic array, from its DFT (Parseval): sqrt(sum |q|^2 |H_q|^2).

    Spectral (exact for the trigonometric interpolant), not finite differences.
    """
    nx, ny = h.shape
    qx = 2.0 * np.pi * np.fft.fftfreq(nx, lx / nx)[:, None]
    qy = 2.0 * np.pi * np.fft.fftfreq(ny, ly / ny)[None, :]
    H = np.fft.fft2(h) / h.size
    return float(np.sqrt(np.sum((qx**2 + qy**2) * np.abs(H) ** 2)))


def _numpy_self_affine(n: int, hurst: float, q0: int, q1: int, q2: int, seed: int) -> np.ndarray:
    """Fallback generator with Tamaas's Isopowerlaw PSD (other random numbers)."""
    rng = np.random.default_rng(seed)
    k = np.fft.fftfreq(n, 1.0 / n)
    K = np.hypot(k[:, None], k[None, :])
    amp = np.zeros_like(K)
    band = (K >= q0) & (K <= q2)
    amp[band] = np.maximum(K[band], q1) ** (-(1.0 + hurst))  # sqrt of PSD ~ q^-2(1+H)
    white = np.fft.fft2(rng.standard_normal((n, n)))
    return np.fft.ifft2(white * amp).real


def make_surface(n: int, *, hurst: float = HURST, q0: int = Q0, q1: int = Q1, q2: int | None = None,
                 seed: int = SEED, rms_slope: float = RMS_SLOPE) -> tuple[np.ndarray, str]:
    """Zero-mean periodic self-affine surface on an n x n grid of side L, spectral rms slope ``rms_slope``.

    Returns the surface (a C-contiguous float64 array, heights of the rough body) and
    the name of the generator used.
    """
    q2 = q2_for(n) if q2 is None else q2
    if HAVE_TAMAAS:
        sg = tm.SurfaceGeneratorFilter2D([n, n])
        sg.random_seed = seed
        spectrum = tm.Isopowerlaw2D()
        spectrum.q0, spectrum.q1, spectrum.q2, spectrum.hurst = q0, q1, q2, hurst
        sg.spectrum = spectrum
        s = np.array(sg.buildSurface(), dtype=float, copy=True)
        gen = f"tamaas.SurfaceGeneratorFilter2D(Isopowerlaw2D q0={q0} q1={q1} q2={q2} H={hurst}) seed={seed}"
    else:
        s = _numpy_self_affine(n, hurst, q0, q1, q2, seed)
        gen = f"numpy fallback (Isopowerlaw PSD q0={q0} q1={q1} q2={q2} H={hurst}) seed={seed}"
    s -= s.mean()
    s *= rms_slope / spectral_rms_slope(s)
    return np.ascontiguousarray(s), gen


# --------------------------------------------------------------------------------------
# tribobem side
# --------------------------------------------------------------------------------------


def tribobem_operator(n: int, workers: int | None = None):
    """Periodic spectral operator 2/(E*|q|) on the n x n grid (kernel computed and cached here)."""
    from tribobem.elasticity.backend import Backend
    from tribobem.elasticity.operators import periodic_operator
    from tribobem.grid import Grid
    from tribobem.materials import ContactPair, Material

    backend = Backend("numpy", workers, small_fft_threads=None) if workers else Backend("numpy")
    grid = Grid.square(n, L, periodic=True)
    pair = ContactPair(Material(E, NU), Material.rigid())
    return periodic_operator(grid, pair, backend=backend)


def time_apply(op, repeats: int = 5) -> float:
    """Minimum wall time (s) of one ``op.apply`` (rfft2, multiply by the kernel, irfft2)."""
    rng = np.random.default_rng(0)
    p = rng.random(op.grid.shape)
    op.apply(p)
    best = math.inf
    for _ in range(repeats):
        t0 = time.perf_counter()
        op.apply(p)
        best = min(best, time.perf_counter() - t0)
    return best


# --------------------------------------------------------------------------------------
# Tamaas side
# --------------------------------------------------------------------------------------

_ITER_LINE = re.compile(r"^\s*(\d+)\s+([-+0-9.eEinfa]+)\s+([-+0-9.eEinfa]+)\s*$")


@contextlib.contextmanager
def capture_fd1():
    """Capture what C/C++ code writes to file descriptors 1 and 2 (Tamaas logs to stderr)."""
    libc = ctypes.CDLL(None)
    sys.stdout.flush()
    sys.stderr.flush()
    saved = {fd: os.dup(fd) for fd in (1, 2)}
    out: dict = {"text": ""}
    with tempfile.TemporaryFile() as f:
        for fd in saved:
            os.dup2(f.fileno(), fd)
        try:
            yield out
        finally:
            libc.fflush(None)
            for fd, keep in saved.items():
                os.dup2(keep, fd)
                os.close(keep)
            f.seek(0)
            out["text"] = f.read().decode(errors="replace")


def tamaas_iterations(log: str) -> int | None:
    """Iterations from Tamaas's log.

    PolonskyKeerRey prints ``n cost error`` at n = 0 and after the last iteration with
    the 0-based index of that iteration, so the count is last n + 1 (checked: on the
    same problem it equals tribobem's count, with pressures equal to 1e-14).
    """
    last = None
    for line in log.splitlines():
        m = _ITER_LINE.match(line)
        if m:
            last = int(m.group(1))
    return None if last is None else last + 1


def tamaas_model(n: int):
    """Tamaas basic_2d model of the same cell and materials."""
    model = tm.ModelFactory.createModel(tm.model_type.basic_2d, [L, L], [n, n])
    model.E = E
    model.nu = NU
    return model


def tamaas_threads_note() -> str:
    if not HAVE_TAMAAS:
        return "Tamaas not installed"
    info = tm.TamaasInfo
    return f"Tamaas {info.version} backend={info.backend} (cpp = serial, no OpenMP/threads)"


# --------------------------------------------------------------------------------------
# Timing
# --------------------------------------------------------------------------------------


@dataclass
class Samples:
    """Timed runs of one contestant."""

    times: list = field(default_factory=list)
    cpu: list = field(default_factory=list)
    info: dict = field(default_factory=dict)

    def add(self, wall: float, cpu: float, info: dict) -> None:
        self.times.append(wall)
        self.cpu.append(cpu)
        self.info = info

    @property
    def best(self) -> float:
        return min(self.times) if self.times else math.nan

    @property
    def best_cpu(self) -> float:
        """Minimum CPU time (all threads of the process) over the runs: less sensitive to a loaded machine."""
        return min(self.cpu) if self.cpu else math.nan

    @property
    def median(self) -> float:
        return float(np.median(self.times)) if self.times else math.nan

    @property
    def cpu_per_wall(self) -> float:
        """CPU seconds / wall seconds of the fastest run (about the threads really used)."""
        if not self.times:
            return math.nan
        i = int(np.argmin(self.times))
        return self.cpu[i] / self.times[i] if self.times[i] > 0 else math.nan


def timed(fn, *args, **kw):
    """(wall, cpu, result) of one call; collects garbage first so that it is not timed."""
    gc.collect()
    c0, t0 = time.process_time(), time.perf_counter()
    res = fn(*args, **kw)
    t1, c1 = time.perf_counter(), time.process_time()
    return t1 - t0, c1 - c0, res


# --------------------------------------------------------------------------------------
# Memory
# --------------------------------------------------------------------------------------


def _status_kib(key: str) -> int | None:
    try:
        with open("/proc/self/status") as f:
            for line in f:
                if line.startswith(key + ":"):
                    return int(line.split()[1])
    except OSError:
        pass
    return None


def reset_peak_rss() -> bool:
    """Reset the kernel's high-water mark of the resident set (Linux >= 4.0)."""
    try:
        with open("/proc/self/clear_refs", "w") as f:
            f.write("5")
        return True
    except OSError:
        return False


def peak_rss_kib() -> int:
    hwm = _status_kib("VmHWM")
    if hwm is not None:
        return hwm
    import resource

    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss


def current_rss_kib() -> int:
    rss = _status_kib("VmRSS")
    return rss if rss is not None else peak_rss_kib()


def probe_memory(code: str, problem: str, n: int, params: dict) -> dict:
    """Peak memory of one solve, in this (fresh) process.

    ``rss_delta_mib``: peak resident set while building the operator (tribobem: kernel
    spectrum; Tamaas: model and solver, which preallocate their work arrays) and solving,
    minus the resident set before (libraries and the input surface excluded).  For tribobem also
    ``traced_peak_mib``: peak of the NumPy allocations (tracemalloc) during the solve.
    Both are also given in units of one n x n float64 array.
    """
    import tracemalloc

    s, _ = make_surface(n)
    h = s.max() - s
    grid_mib = n * n * 8 / 2**20
    out = {"code": code, "problem": problem, "n": n, "grid_array_mib": grid_mib}
    from tribobem.elasticity import operators  # noqa: F401  (imports outside the measurement)
    from tribobem.interactions.dugdale import DugdaleAdhesion
    from tribobem.solvers.normal import solve_normal

    gc.collect()
    base = current_rss_kib()
    exact = reset_peak_rss()
    if code == "tribobem":
        tracemalloc.start()
        op = tribobem_operator(n, params.get("workers"))
        if problem == "normal":
            kw = dict(force=params["mean_pressure"] * L * L)
        else:
            kw = dict(approach=params["approach"],
                      interaction=DugdaleAdhesion.from_stress(params["sigma0"], params["h0"]))
        res = solve_normal(op, h, tol=params["tol"], max_iterations=params.get("max_iterations", 10000), **kw)
        peak = peak_rss_kib()
        _, traced = tracemalloc.get_traced_memory()
        tracemalloc.stop()
        out.update(traced_peak_mib=traced / 2**20, iterations=res.iterations)
    else:
        model = tamaas_model(n)
        if problem == "normal":
            solver = tm.PolonskyKeerRey(model, s, params["tol"])
            target = params["mean_pressure"]
        else:
            solver = tm.PolonskyKeerRey(model, s, params["tol"], tm.PolonskyKeerRey.gap, tm.PolonskyKeerRey.gap)
            adh = tm.MaugisAdhesionFunctional(s)
            adh.parameters = {"rho": params["h0"], "surface_energy": params["sigma0"] * params["h0"]}
            solver.addFunctionalTerm(adh)
            target = params["mean_gap"]
        solver.max_iter = params.get("max_iterations", 10000)
        with capture_fd1():
            solver.solve(target)
        peak = peak_rss_kib()
    out.update(rss_delta_mib=(peak - base) / 1024, rss_peak_mib=peak / 1024, hwm_reset=exact)
    out["rss_delta_grids"] = out["rss_delta_mib"] / grid_mib
    if "traced_peak_mib" in out:
        out["traced_peak_grids"] = out["traced_peak_mib"] / grid_mib
    return out


def run_memory_probe(code: str, problem: str, n: int, params: dict, timeout: float = 3600) -> dict | None:
    """Run :func:`probe_memory` in a fresh interpreter; None if it failed."""
    cmd = [sys.executable, os.path.abspath(__file__), "--probe-memory", code, problem, str(n), json.dumps(params)]
    try:
        cp = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout)
    except subprocess.TimeoutExpired:
        return None
    for line in reversed(cp.stdout.splitlines()):
        if line.startswith("{"):
            return json.loads(line)
    sys.stderr.write(cp.stderr[-2000:])
    return None


# --------------------------------------------------------------------------------------
# Reporting
# --------------------------------------------------------------------------------------


def markdown_table(headers: list[str], rows: list[list]) -> str:
    def fmt(v):
        if isinstance(v, float):
            if math.isnan(v):
                return "-"
            a = abs(v)
            if a != 0 and (a < 1e-3 or a >= 1e5):
                return f"{v:.3g}"
            return f"{v:.4g}"
        return "-" if v is None else str(v)

    lines = ["| " + " | ".join(headers) + " |", "|" + "|".join("---" for _ in headers) + "|"]
    lines += ["| " + " | ".join(fmt(v) for v in r) + " |" for r in rows]
    return "\n".join(lines)


def solver_version() -> str:
    """tribobem commit (+ 'dirty' and a hash of solvers/normal.py), to tie tables to a solver version."""
    import hashlib

    import tribobem.solvers.normal as normal

    with open(normal.__file__, "rb") as f:
        digest = hashlib.sha1(f.read()).hexdigest()[:10]
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    try:
        commit = subprocess.run(["git", "-C", root, "rev-parse", "--short", "HEAD"], capture_output=True,
                                text=True, timeout=10).stdout.strip()
        dirty = subprocess.run(["git", "-C", root, "status", "--porcelain", "--", "src"], capture_output=True,
                               text=True, timeout=10).stdout.strip()
    except Exception:
        commit, dirty = "?", ""
    return f"tribobem {commit}{' (src modified)' if dirty else ''}, solvers/normal.py sha1 {digest}"


def environment() -> str:
    import scipy

    from tribobem.elasticity.backend import default_workers

    load = os.getloadavg() if hasattr(os, "getloadavg") else ("?",)
    blas = os.environ.get("OPENBLAS_NUM_THREADS") or os.environ.get("OMP_NUM_THREADS") or "default"
    return (f"{solver_version()}; python {platform.python_version()}, numpy {np.__version__}, "
            f"scipy {scipy.__version__}, {tamaas_threads_note()}; {os.cpu_count()} CPU cores "
            f"({platform.processor() or platform.machine()}), tribobem FFT workers default {default_workers()}, "
            f"BLAS threads {blas}; load average {tuple(round(x, 2) for x in load)}")


def base_parser(description: str, default_sizes: list[int]) -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(description=description)
    p.add_argument("--sizes", type=int, nargs="+", default=default_sizes, help="grid sizes n (n x n cells)")
    p.add_argument("--repeats", type=int, default=3, help="timed runs per code and size (the minimum is reported)")
    p.add_argument("--quick", action="store_true", help="smallest sizes only, one repeat, no memory probes")
    p.add_argument("--workers", type=int, default=None, help="scipy.fft workers for tribobem (default: all cores)")
    p.add_argument("--serial", action="store_true",
                   help="also time tribobem with 1 FFT worker (Tamaas's cpp backend is single-threaded)")
    p.add_argument("--no-memory", action="store_true", help="skip the peak-memory probes (subprocesses)")
    p.add_argument("--no-tamaas", action="store_true", help="time tribobem only")
    return p


if __name__ == "__main__":
    if len(sys.argv) >= 6 and sys.argv[1] == "--probe-memory":
        res = probe_memory(sys.argv[2], sys.argv[3], int(sys.argv[4]), json.loads(sys.argv[5]))
        print(json.dumps(res))
    else:
        print(__doc__)
