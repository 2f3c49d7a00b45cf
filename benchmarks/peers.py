"""Large grids beside the peers: tribobem, ASPHER and Tamaas on the same problems, in one run.

Two problems (both on a unit square, E = 1 against a rigid surface):

* ``periodic``: a periodic self-affine surface (spectral filter: Hurst 0.8, flat below
  wavenumber n/16, zero above n/4, in grid units), scaled to rms slope 1; nu = 0.3; mean
  pressure 0.01 E*.
* ``free``: the free-boundary (non-periodic) problem: the same kind of field scaled to rms
  slope 0.05, nu = 0, plus a crown (x^2 + y^2) / (2 x 2.0) about the centre; gap = crown +
  max(z) - z, shifted to min 0; mean pressure 2e-4 E* over the square (0.7 % contact).

Codes and modes (each run in a fresh subprocess, so that its peak memory is its own):

* ``tribobem``: ``solve_normal_cg`` at tol 1e-8: on the whole grid in double precision
  (``whole``, what every solve did before the candidate-set solve), with a scenario's defaults
  (``default``: ``precision="auto"``, the candidate-set solve where it applies; at these sizes
  auto is single) and in its fastest mode (``fast``: ``precision="single"``; the convergence
  test is in double precision in every mode);
* ``aspher``: ``aspher.solve_nested(..., tol=1e-8)`` in double (``double``) and in its fastest
  mode (``fast``: single precision with the active set, ``light_result``); backend "h2" on the
  free boundary, "periodic" on the periodic one.  Install: Debian's ``libeigen3-dev``, then
  ``pip install aspher`` (it builds from its source distribution);
* ``tamaas``: ``PolonskyKeerRey`` at tol 1e-8 (periodic only; ``pip install tamaas``).

A missing peer is skipped with a notice.  Each run reports the CPU time of the solve
(``time.process_time``, all threads), its wall time, the peak resident set of the solve above
the process before it (``/proc/self/status`` VmHWM after resetting it with ``clear_refs``), in
bytes per grid node, the contact nodes, the contact fraction and the force balance.  The
accuracy columns compare every run's contact fraction with tribobem's double solve.

    python benchmarks/peers.py --problem free --n 1024 2048
    python benchmarks/peers.py --problem periodic --n 1024 2048 --codes tribobem aspher tamaas
    python benchmarks/peers.py --problem free --n 8192 --codes tribobem --modes fast
    python benchmarks/peers.py --json out.json --markdown out.md ...

Threads: ``--threads`` (default 2) for every code (OMP_NUM_THREADS, TRIBOBEM_FFT_WORKERS), and
OMP_WAIT_POLICY=passive, as on a shared machine.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import subprocess
import sys
import time

import numpy as np

TOL = 1e-8
CROWN_RADIUS = 2.0
FREE_PRESSURE = 2e-4     # mean pressure / E* over the square (free problem)
PERIODIC_PRESSURE = 0.01  # mean pressure / E* (periodic problem)
MODES = {"tribobem": ("whole", "default", "fast"), "aspher": ("double", "fast"), "tamaas": ("default",)}


# --------------------------------------------------------------------------------------
# The problems
# --------------------------------------------------------------------------------------
def self_affine(n: int, seed: int = 7) -> np.ndarray:
    """A periodic self-affine height field (grid units): spectral filter with Hurst 0.8, flat
    below wavenumber n/16, zero above n/4, random phases; mean 0."""
    rng = np.random.default_rng(seed)
    k = np.fft.fftfreq(n) * n
    kr = np.fft.rfftfreq(n) * n
    q = np.hypot(k[:, None], kr[None, :])
    with np.errstate(divide="ignore"):
        amp = np.where(q < n / 16, (n / 16) ** (-1.8), q ** -1.8)
    amp[q > n / 4] = 0.0
    amp[0, 0] = 0.0
    phase = np.exp(2j * np.pi * rng.random(q.shape))
    z = np.fft.irfft2(amp * phase, s=(n, n))
    return z - z.mean()


def rms_slope(z: np.ndarray, dx: float) -> float:
    """Spectral rms slope of a periodic field."""
    n = z.shape[0]
    k = 2 * np.pi * np.fft.fftfreq(n, dx)
    kr = 2 * np.pi * np.fft.rfftfreq(n, dx)
    q2 = k[:, None] ** 2 + kr[None, :] ** 2
    Z = np.abs(np.fft.rfft2(z)) ** 2
    w = np.full(Z.shape, 2.0)
    w[:, 0] = 1.0
    if n % 2 == 0:
        w[:, -1] = 1.0
    return math.sqrt(float((w * q2 * Z).sum()) / n**4)


def problem(name: str, n: int) -> dict:
    """Gap (m, min 0), grid spacing, modulus, Poisson's ratio and force of a benchmark problem."""
    dx = 1.0 / n
    z = self_affine(n)
    if name == "periodic":
        z *= 1.0 / rms_slope(z, dx)
        nu = 0.3
        e_star = 1.0 / (1 - nu**2)
        gap = z.max() - z
        return {"gap": gap, "dx": dx, "E": 1.0, "nu": nu, "force": PERIODIC_PRESSURE * e_star, "periodic": True}
    z *= 0.05 / rms_slope(z, dx)
    x = (np.arange(n) + 0.5) * dx - 0.5
    crown = (x[:, None] ** 2 + x[None, :] ** 2) / (2 * CROWN_RADIUS)
    gap = crown + z.max() - z
    gap -= gap.min()
    return {"gap": gap, "dx": dx, "E": 1.0, "nu": 0.0, "force": FREE_PRESSURE, "periodic": False}


# --------------------------------------------------------------------------------------
# Memory probes (Linux)
# --------------------------------------------------------------------------------------
def _status_kb(key: str) -> int:
    with open("/proc/self/status") as f:
        for line in f:
            if line.startswith(key + ":"):
                return int(line.split()[1])
    return 0


_PROCESS_PEAK = [0]


def reset_peak() -> int:
    """Reset the peak resident set to the current one (keeping the process's peak so far for
    :func:`process_peak`); returns the current RSS (bytes)."""
    _PROCESS_PEAK[0] = max(_PROCESS_PEAK[0], peak())
    try:
        with open("/proc/self/clear_refs", "w") as f:
            f.write("5")
    except OSError:
        pass
    return _status_kb("VmRSS") * 1024


def peak() -> int:
    """Peak resident set (bytes) since the last :func:`reset_peak`."""
    return _status_kb("VmHWM") * 1024


def process_peak() -> int:
    """Peak resident set (bytes) of the whole process, the problem's generation included."""
    return max(_PROCESS_PEAK[0], peak())


# --------------------------------------------------------------------------------------
# The runs (children)
# --------------------------------------------------------------------------------------
def run_tribobem(pb: dict, mode: str) -> dict:
    from tribobem.elasticity.operators import make_operator
    from tribobem.grid import Grid
    from tribobem.materials import ContactPair, Material
    from tribobem.solvers.normal_cg import solve_normal_cg

    n = pb["gap"].shape[0]
    grid = Grid.square(n, 1.0, periodic=pb["periodic"])
    pair = ContactPair(Material(pb["E"], pb["nu"]), Material.rigid())
    gap = pb.pop("gap")
    kw = {"whole": {"candidates": False}, "default": {"precision": "auto"}, "fast": {"precision": "single"}}[mode]
    base = reset_peak()
    c0, w0 = time.process_time(), time.perf_counter()
    op = make_operator(grid, pair)
    res = solve_normal_cg(op, gap, force=pb["force"], tol=TOL, **kw)
    cpu, wall = time.process_time() - c0, time.perf_counter() - w0
    top = peak()
    contact = np.asarray(res.contact)
    return {"cpu_s": cpu, "wall_s": wall, "peak_bytes": top - base, "contact_nodes": int(contact.sum()),
            "contact_fraction": float(contact.mean()), "force": float(np.asarray(res.pressure).sum()) / n**2,
            "iterations": res.iterations, "converged": bool(res.converged),
            "info": {k: v for k, v in res.info.items() if isinstance(v, (int, float, str, bool))}}


def run_aspher(pb: dict, mode: str) -> dict:
    import aspher

    n = pb["gap"].shape[0]
    gap = pb.pop("gap")
    e_star = pb["E"] / (1 - pb["nu"] ** 2)
    # ASPHER works with E* = 1 (its pressures in units of E*): scale the load
    backend = "periodic" if pb["periodic"] else "h2"
    kw = dict(backend=backend, tol=TOL)
    if mode == "fast":
        # its fastest mode; the active set needs the H2 backend (free boundary only)
        kw.update(single_precision=True, light_result=True, active_set=not pb["periodic"])
    base = reset_peak()
    c0, w0 = time.process_time(), time.perf_counter()
    res = aspher.solve_nested(n, gap, pb["force"] / e_star, **kw)
    cpu, wall = time.process_time() - c0, time.perf_counter() - w0
    top = peak()
    p = np.asarray(res.pressure).reshape(n, n) if getattr(res, "pressure", None) is not None else None
    nodes = int((p > 0).sum()) if p is not None else None
    frac = float(res.contact_area) if getattr(res, "contact_area", None) is not None else nodes / n**2
    return {"cpu_s": cpu, "wall_s": wall, "peak_bytes": top - base, "contact_nodes": nodes,
            "contact_fraction": frac, "force": float(p.mean()) * e_star if p is not None else None}


def run_tamaas(pb: dict, mode: str) -> dict:
    import tamaas as tm

    n = pb["gap"].shape[0]
    gap = pb.pop("gap")
    model = tm.ModelFactory.createModel(tm.model_type.basic_2d, [1.0, 1.0], [n, n])
    model.E, model.nu = pb["E"], pb["nu"]
    surface = -gap  # Tamaas: heights of the rigid body
    base = reset_peak()
    c0, w0 = time.process_time(), time.perf_counter()
    solver = tm.PolonskyKeerRey(model, surface, TOL)
    solver.solve(pb["force"])
    cpu, wall = time.process_time() - c0, time.perf_counter() - w0
    top = peak()
    p = np.array(model.traction)
    return {"cpu_s": cpu, "wall_s": wall, "peak_bytes": top - base, "contact_nodes": int((p > 0).sum()),
            "contact_fraction": float((p > 0).mean()), "force": float(p.mean())}


RUNNERS = {"tribobem": run_tribobem, "aspher": run_aspher, "tamaas": run_tamaas}


def child(code: str, mode: str, name: str, n: int) -> None:
    pb = problem(name, n)
    out = RUNNERS[code](pb, mode)
    out.update(code=code, mode=mode, problem=name, n=n, bytes_per_node=out["peak_bytes"] / n**2,
               process_peak_bytes=process_peak())
    print("RESULT " + json.dumps(out), flush=True)


# --------------------------------------------------------------------------------------
# The parent
# --------------------------------------------------------------------------------------
def available(code: str) -> bool:
    mod = {"tribobem": "tribobem", "aspher": "aspher", "tamaas": "tamaas"}[code]
    try:
        __import__(mod)
        return True
    except Exception:
        return False


def spawn(code: str, mode: str, name: str, n: int, threads: int, timeout: float) -> dict:
    env = dict(os.environ, OMP_NUM_THREADS=str(threads), TRIBOBEM_FFT_WORKERS=str(threads),
               OMP_WAIT_POLICY="passive", PYTHONWARNINGS="ignore")
    cmd = [sys.executable, __file__, "--child", code, mode, name, str(n)]
    try:
        proc = subprocess.run(cmd, env=env, capture_output=True, text=True, timeout=timeout)
    except subprocess.TimeoutExpired:
        return {"code": code, "mode": mode, "problem": name, "n": n, "error": f"over {timeout:.0f} s"}
    for line in proc.stdout.splitlines():
        if line.startswith("RESULT "):
            return json.loads(line[7:])
    tail = (proc.stderr or proc.stdout).strip().splitlines()[-3:]
    return {"code": code, "mode": mode, "problem": name, "n": n, "error": " | ".join(tail)}


def table(rows: list[dict]) -> str:
    ref = {}
    for r in rows:  # the reference: tribobem's double solve on the whole grid, else its default
        if r["code"] == "tribobem" and r["mode"] in ("whole", "default") and "error" not in r:
            if r["mode"] == "whole" or (r["problem"], r["n"]) not in ref:
                ref[(r["problem"], r["n"])] = r
    lines = ["| problem | n | code | mode | CPU s | wall s | solve peak GB | B/node | process peak GB | contact fraction "
             "| vs tribobem double |",
             "|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        head = f"| {r['problem']} | {r['n']} | {r['code']} | {r['mode']} |"
        if "error" in r:
            lines.append(head + f" failed: {r['error']} | | | | | | |")
            continue
        base = ref.get((r["problem"], r["n"]))
        rel = (f"{r['contact_fraction'] / base['contact_fraction'] - 1:+.1e}" if base else "-")
        lines.append(head + f" {r['cpu_s']:.2f} | {r['wall_s']:.2f} | {r['peak_bytes'] / 1e9:.3f} | "
                     f"{r['bytes_per_node']:.0f} | {r['process_peak_bytes'] / 1e9:.3f} | {r['contact_fraction']:.5f} | "
                     f"{rel} |")
    return "\n".join(lines)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--child", nargs=4, metavar=("CODE", "MODE", "PROBLEM", "N"), help=argparse.SUPPRESS)
    ap.add_argument("--problem", nargs="+", default=["free"], choices=["free", "periodic"])
    ap.add_argument("--n", nargs="+", type=int, default=[1024])
    ap.add_argument("--codes", nargs="+", default=["tribobem", "aspher", "tamaas"], choices=list(MODES))
    ap.add_argument("--modes", nargs="+", default=None, help="restrict to these modes (e.g. fast)")
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--slow-max", type=int, default=2048,
                    help="largest n for the slow modes (tribobem whole, ASPHER double; default 2048)")
    ap.add_argument("--timeout", type=float, default=3600.0, help="per run (s)")
    ap.add_argument("--json", default=None)
    ap.add_argument("--markdown", default=None)
    args = ap.parse_args(argv)
    if args.child:
        code, mode, name, n = args.child
        child(code, mode, name, int(n))
        return 0
    rows = []
    for code in args.codes:
        if not available(code):
            print(f"NOTICE: {code} is not installed; skipped "
                  + {"aspher": "(apt install libeigen3-dev; pip install aspher)",
                     "tamaas": "(pip install tamaas)", "tribobem": ""}[code], file=sys.stderr)
    for name in args.problem:
        for n in args.n:
            for code in args.codes:
                if not available(code) or (code == "tamaas" and name == "free"):
                    continue
                for mode in MODES[code]:
                    if args.modes and mode not in args.modes:
                        continue
                    if mode in ("whole", "double") and n > args.slow_max and name == "free":
                        print(f"NOTICE: {code} {mode} skipped at n = {n} (--slow-max {args.slow_max})", file=sys.stderr)
                        continue
                    r = spawn(code, mode, name, n, args.threads, args.timeout)
                    rows.append(r)
                    print(json.dumps(r), flush=True)
    md = table(rows)
    print("\n" + md)
    if args.json:
        with open(args.json, "w") as f:
            json.dump(rows, f, indent=1)
    if args.markdown:
        with open(args.markdown, "w") as f:
            f.write(md + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
