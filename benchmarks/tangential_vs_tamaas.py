"""Partial slip (Cattaneo-Mindlin) of a rigid sphere on an elastic half-space: tribobem vs Tamaas.

Problem (issue: tangential benchmark): periodic square cell L = 1 on an n x n grid, rigid
paraboloid h = r^2/(2R), R = 1, against one elastic half-space E = 1, nu = 0.5 and 0.3;
normal force P from Hertz for a contact radius a = L/8 (P = 4 E* a^3/(3R)); friction
coefficient mu = 0.5; tangential force Q = 0.5 mu P along x, applied in one step with P
(total slip, force control of both loads).

Tamaas: ``PolonskyKeerTan(model, s, tol, mu).solve([Q/L^2, 0, P/L^2])`` on a ``surface_2d``
model.  This solver has no "given pressure" entry: it solves the normal and the tangential
problem together (three traction components, Coulomb cone), from a uniform start (a second
``solve`` does not warm-start).  Its ``surface_2d`` operator is the full Boussinesq 3x3
kernel, so for nu != 0.5 it INCLUDES the normal-tangential coupling (checked: at nu = 0.3 its
pressure differs from the frictionless one by ~20 % of p_max and agrees with tribobem's coupled
solution).

tribobem, like for like:

* nu = 0.5 (no coupling): ``solve_normal`` (tol 1e-10), then ``solve_tangential`` at that
  pressure, force control;
* nu = 0.3: ``solve_coupled`` (alternating normal and tangential solves, Paper D), because that
  is the problem Tamaas solves, with one tolerance (the ladder value below) for its normal,
  tangential and coupling iterations; the time of its tangential and normal passes is reported
  separately (the two inner solvers are wrapped with timers).  The decoupled tangential solve the
  issue first asked for (operator without the xz/yz/zx/zy blocks, at the frictionless
  pressure) is timed as well, in a separate table: Tamaas has no counterpart for it.

Equal accuracy: the stick area (node count, stick = p > 0 and |q| < (1 - 1e-9) mu p, the same
rule on both tractions) to 1e-3 relative.  tribobem: the loosest tolerance of a ladder
(1e-3 ... 1e-8; ``--quick``: ... 1e-7) whose stick area, and that of every tighter one, is within
1e-3 of the tightest (its tangential force is exact at any tolerance: the projection imposes it).
Tamaas: its error measure does not go to zero on a partial-slip problem (it levels off at
1.40e-7 for nu = 0.5 and 4.88e-7 for nu = 0.3 at every n, after dipping below that early on,
when the stick area is still 12 % off), so no tolerance stops it at a given accuracy; it runs a
fixed number of iterations (``max_iter``, tolerance 0): the smallest multiple of 25 at which the
stick area is within 1e-3 of its converged value AND its tangential force within 1e-3 of Q
(Tamaas does not impose Q exactly during the iterations; at the stick-only count it can still
be 0.35 % short).  ``--calibrate`` measures both counts by bisection against a 1200-iteration
run; ``TAMAAS_ITERATIONS`` holds the values measured on 2026-11-23.

Timing: the tangential solve only for tribobem, and the normal + tangential (or coupled) total;
for Tamaas its one-shot solve (it cannot be split).  Wall and CPU (``time.process_time``, all
threads) in one process, interleaved runs, minimum reported.

    python benchmarks/tangential_vs_tamaas.py                   # 256 512, nu 0.5 and 0.3, 2 repeats
    python benchmarks/tangential_vs_tamaas.py --quick           # 256 only, 1 repeat
    python benchmarks/tangential_vs_tamaas.py --sizes 512 --nus 0.5 --repeats 3
    python benchmarks/tangential_vs_tamaas.py --sizes 256 --calibrate   # re-measure Tamaas's iterations

Always exits 0 when it ran (without Tamaas it times tribobem alone).
"""

from __future__ import annotations

import argparse
import contextlib
import json
import math
import os
import sys
import time
import warnings

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import common  # noqa: E402
from common import Samples, markdown_table, timed  # noqa: E402

L = 1.0
E = 1.0
R = 1.0
MU = 0.5
Q_OVER_MU_P = 0.5
CONTACT_RADIUS = L / 8
NUS = (0.5, 0.3)
STICK_RIM = 1.0 - 1e-9
AREA_RTOL = 1e-3
NORMAL_TOL = 1e-10
TRIBOBEM_TOLS = (1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8)
TRIBOBEM_TOLS_QUICK = (1e-3, 1e-4, 1e-5, 1e-6, 1e-7)
MAX_ITERATIONS = 20000
#: Tamaas PolonskyKeerTan iterations (smallest multiples of 25, ``--calibrate``): (stick area within
#: 1e-3 of converged, stick area AND tangential force within 1e-3).  The timed runs use the second.
#: Measured 2026-11-23, see benchmarks/README.md.
TAMAAS_ITERATIONS = {(128, 0.5): (225, 275), (128, 0.3): (175, 275), (256, 0.5): (275, 275),
                     (256, 0.3): (300, 300), (512, 0.5): (300, 300), (512, 0.3): (300, 300)}
#: ``solve_tangential(method=...)`` for every tribobem tangential solve (``--tangential-method``); None: its default.
TANGENTIAL_METHOD: str | None = None
CALIBRATION_LONG = 1200  # iterations of the "converged" Tamaas run in --calibrate
CALIBRATION_STEP = 25


# --------------------------------------------------------------------------------------
# Problem
# --------------------------------------------------------------------------------------


class Runs(Samples):
    """Samples that also keep every run's info (for the per-pass split of the coupled solve)."""

    def add(self, wall: float, cpu: float, info: dict) -> None:
        super().add(wall, cpu, info)
        self.__dict__.setdefault("infos", []).append({k: v for k, v in info.items() if k not in ("pressure", "shear")})

    def min_of(self, key: str) -> float:
        return min(i[key] for i in self.__dict__.get("infos", [])) if self.times else math.nan


def loads(nu: float) -> tuple[float, float]:
    e_star = E / (1.0 - nu**2)
    P = 4.0 * e_star * CONTACT_RADIUS**3 / (3.0 * R)
    return P, Q_OVER_MU_P * MU * P


def sphere(n: int) -> np.ndarray:
    """Heights of the rigid sphere (Tamaas convention: heights of the rigid body), apex at node (n/2, n/2)."""
    x = np.arange(n) * (L / n) - L / 2
    X, Y = np.meshgrid(x, x, indexing="ij")
    return np.ascontiguousarray(-(X**2 + Y**2) / (2.0 * R))


def stick_mask(p: np.ndarray, qx: np.ndarray, qy: np.ndarray) -> np.ndarray:
    return (p > 0) & (np.hypot(qx, qy) < STICK_RIM * MU * p)


def rel(a: float, b: float) -> float:
    return abs(a - b) / abs(b) if b else (0.0 if a == b else math.inf)


# --------------------------------------------------------------------------------------
# tribobem
# --------------------------------------------------------------------------------------


def tribobem_operators(n: int, nu: float, workers: int | None):
    """The 3x3 periodic spectral operator and its copy without the coupling blocks."""
    from tribobem.elasticity.backend import Backend
    from tribobem.elasticity.operators import ConvolutionOperator, periodic_operator
    from tribobem.grid import Grid
    from tribobem.materials import ContactPair, Material

    backend = Backend("numpy", workers, small_fft_threads=None) if workers else Backend("numpy")
    grid = Grid.square(n, L, periodic=True)
    op = periodic_operator(grid, ContactPair(Material(E, nu), Material.rigid()), components=("x", "y", "z"),
                           backend=backend)
    spectra = {k: v for k, v in op.spectra.items() if k not in ("xz", "yz", "zx", "zy")}
    dec = ConvolutionOperator(op.grid, op.pair, op.components, spectra, op.fft_shape, op.backend,
                              op.kind + " without coupling")
    return op, dec


def run_tribobem_normal(op, h, P):
    from tribobem.solvers.normal import solve_normal

    wall, cpu, res = timed(solve_normal, op, h, force=P, tol=NORMAL_TOL, max_iterations=MAX_ITERATIONS)
    return wall, cpu, res


#: CPU seconds and calls of the tangential-block convolutions (``TangentialOperator._combine``: rfft2 of
#: the inputs, the 2x2 (or 2x1, 1x2) spectral multiply, irfft2 of the outputs), while ``conv_timer`` is on.
_CONV = [0.0, 0]


@contextlib.contextmanager
def conv_timer():
    """Time every tangential-block convolution inside a solve (about 1 us of overhead per call)."""
    from tribobem.solvers import tangential

    cls = getattr(tangential, "TangentialOperator", None)
    orig = getattr(cls, "_combine", None)
    if orig is None:  # another solver version: no split
        yield
        return

    def timed_combine(self, *a, **kw):
        c0 = time.process_time()
        res = orig(self, *a, **kw)
        _CONV[0] += time.process_time() - c0
        _CONV[1] += 1
        return res

    cls._combine = timed_combine
    try:
        yield
    finally:
        cls._combine = orig


def method_kw() -> dict:
    """``method=TANGENTIAL_METHOD`` if set (older tribobem versions have no such argument)."""
    if TANGENTIAL_METHOD is None:
        return {}
    import inspect

    from tribobem.solvers.tangential import solve_tangential

    if "method" not in inspect.signature(solve_tangential).parameters:
        raise SystemExit("this tribobem's solve_tangential has no 'method' argument")
    return {"method": TANGENTIAL_METHOD}


def run_tribobem_tangential(op, normal, Q, tol) -> tuple[float, float, dict]:
    from tribobem.solvers.tangential import solve_tangential

    c0, k0 = _CONV
    with warnings.catch_warnings(), conv_timer():
        warnings.simplefilter("ignore")
        wall, cpu, res = timed(solve_tangential, op, normal.pressure, normal.contact, friction_coefficient=MU,
                               force=(Q, 0.0), tol=tol, max_iterations=MAX_ITERATIONS, **method_kw())
    p = normal.pressure
    return wall, cpu, {
        "iterations": res.iterations, "converged": res.converged, "pressure": p, "shear": res.shear,
        "stick_nodes": int(np.count_nonzero(stick_mask(p, res.shear[0], res.shear[1]))),
        "stick_nodes_own": int(np.count_nonzero(res.stick)),
        "contact_nodes": int(np.count_nonzero(res.contact)),
        "force_x": res.force_x, "force_y": res.force_y, "normal_force": float(p.sum()) * (L / p.shape[0]) ** 2,
        "convolutions": _CONV[1] - k0, "convolution_cpu": _CONV[0] - c0, "tangential_cpu_run": cpu,
    }


@contextlib.contextmanager
def split_timers(acc: dict):
    """Time the normal and tangential passes inside ``solve_coupled`` (wall, CPU, iterations)."""
    import tribobem.solvers.coupling as coupling

    originals = coupling.solve_normal, coupling.solve_tangential

    def wrap(name, fn):
        extra = method_kw() if name == "tangential" else {}

        def inner(*a, **kw):
            kw.update(extra)
            v0, k0 = _CONV
            c0, t0 = time.process_time(), time.perf_counter()
            res = fn(*a, **kw)
            rec = acc.setdefault(name, [0.0, 0.0, 0, 0, 0, 0.0])
            rec[0] += time.perf_counter() - t0
            rec[1] += time.process_time() - c0
            rec[2] += res.iterations
            rec[3] += 1
            rec[4] += _CONV[1] - k0
            rec[5] += _CONV[0] - v0
            return res
        return inner

    coupling.solve_normal, coupling.solve_tangential = wrap("normal", originals[0]), wrap("tangential", originals[1])
    try:
        with conv_timer():
            yield acc
    finally:
        coupling.solve_normal, coupling.solve_tangential = originals


def run_tribobem_coupled(op, h, P, Q, tol) -> tuple[float, float, dict]:
    from tribobem.solvers.coupling import solve_coupled

    acc: dict = {}
    with warnings.catch_warnings(), split_timers(acc):
        warnings.simplefilter("ignore")
        wall, cpu, res = timed(solve_coupled, op, h, friction_coefficient=MU, normal_force=P, tangential_force=(Q, 0.0),
                               tol=tol, tangential_tol=tol, coupling_tol=tol,
                               max_iterations=MAX_ITERATIONS)
    p, sh = res.normal.pressure, res.tangential.shear
    tn, tt = acc.get("normal", [0.0] * 6), acc.get("tangential", [0.0] * 6)
    return wall, cpu, {
        "iterations": int(tt[2]), "normal_iterations": int(tn[2]), "passes": res.coupling_iterations,
        "converged": res.converged, "pressure": p, "shear": sh,
        "stick_nodes": int(np.count_nonzero(stick_mask(p, sh[0], sh[1]))),
        "stick_nodes_own": int(np.count_nonzero(res.tangential.stick)),
        "contact_nodes": int(np.count_nonzero(res.tangential.contact)),
        "force_x": res.tangential.force_x, "force_y": res.tangential.force_y,
        "normal_force": float(p.sum()) * (L / p.shape[0]) ** 2,
        "tangential_wall": tt[0], "tangential_cpu": tt[1], "normal_wall": tn[0], "normal_cpu": tn[1],
        "convolutions": int(tt[4]), "convolution_cpu": tt[5], "tangential_cpu_run": tt[1],
    }


# --------------------------------------------------------------------------------------
# Tamaas
# --------------------------------------------------------------------------------------


def run_tamaas_normal(s, n, nu, P):
    tm = common.tm
    model = tm.ModelFactory.createModel(tm.model_type.basic_2d, [L, L], [n, n])
    model.E, model.nu = E, nu
    solver = tm.PolonskyKeerRey(model, s, NORMAL_TOL, tm.PolonskyKeerRey.pressure, tm.PolonskyKeerRey.pressure)
    solver.max_iter = MAX_ITERATIONS
    with common.capture_fd1() as log:
        wall, cpu, _ = timed(solver.solve, P / L**2)
    p = np.array(model.traction, dtype=float, copy=True).reshape(n, n)
    return wall, cpu, {"iterations": common.tamaas_iterations(log["text"]), "pressure": p,
                       "contact_nodes": int(np.count_nonzero(p > 0))}


def run_tamaas_tangential(s, n, nu, P, Q, iterations: int) -> tuple[float, float, dict]:
    """PolonskyKeerTan one-shot solve, run for exactly ``iterations`` iterations (tolerance 0)."""
    tm = common.tm
    model = tm.ModelFactory.createModel(tm.model_type.surface_2d, [L, L], [n, n])
    model.E, model.nu = E, nu
    solver = tm.PolonskyKeerTan(model, s, 0.0, MU)
    solver.max_iter = iterations
    with common.capture_fd1():
        wall, cpu, err = timed(solver.solve, [Q / L**2, 0.0, P / L**2])
    t = np.array(model.traction, dtype=float, copy=True).reshape(n, n, 3)
    qx, qy, p = t[..., 0], t[..., 1], t[..., 2]
    cell = (L / n) ** 2
    return wall, cpu, {
        "iterations": iterations, "error": float(err), "pressure": p, "shear": np.stack([qx, qy]),
        "stick_nodes": int(np.count_nonzero(stick_mask(p, qx, qy))),
        "contact_nodes": int(np.count_nonzero(p > 0)),
        "force_x": float(qx.sum()) * cell, "force_y": float(qy.sum()) * cell, "normal_force": float(p.sum()) * cell,
    }


def calibrate_tamaas(s, n, nu, P, Q) -> dict:
    """Tamaas iterations (multiples of CALIBRATION_STEP, by doubling then bisection) at which

    * ``stick``: the stick area is within AREA_RTOL of a long run's (CALIBRATION_LONG iterations);
    * ``iterations``: in addition the tangential force is within AREA_RTOL of Q (Tamaas does not
      impose it exactly during the iterations: it converges to Q, like the stick area).
    """
    long = run_tamaas_tangential(s, n, nu, P, Q, CALIBRATION_LONG)[2]
    ref = long["stick_nodes"]
    seen: dict[int, dict] = {}

    def run(it):
        if it not in seen:
            info = run_tamaas_tangential(s, n, nu, P, Q, it)[2]
            seen[it] = {"stick": rel(info["stick_nodes"], ref) <= AREA_RTOL,
                        "force": abs(info["force_x"] / Q - 1.0) <= AREA_RTOL}
            print(f"  calibrate n={n} nu={nu}: {it} it -> stick {info['stick_nodes']} (converged {ref}), "
                  f"F_x/Q = {info['force_x'] / Q:.6f}", flush=True)
        return seen[it]

    def smallest(ok) -> int:
        lo, hi = 0, CALIBRATION_STEP
        while not ok(run(hi)):
            lo, hi = hi, 2 * hi
            if hi >= CALIBRATION_LONG:
                return CALIBRATION_LONG
        while hi - lo > CALIBRATION_STEP:
            mid = (lo + hi) // 2 // CALIBRATION_STEP * CALIBRATION_STEP
            if mid <= lo:
                break
            if ok(run(mid)):
                hi = mid
            else:
                lo = mid
        return hi

    return {"stick": smallest(lambda r: r["stick"]), "iterations": smallest(lambda r: r["stick"] and r["force"]),
            "converged_stick": ref, "long_force_x_over_Q": long["force_x"] / Q}


def tamaas_iterations_for(n: int, nu: float) -> tuple[int, int] | None:
    return TAMAAS_ITERATIONS.get((n, nu))


# --------------------------------------------------------------------------------------
# One case
# --------------------------------------------------------------------------------------


def choose_tol(samples: dict[float, dict]) -> float:
    """Loosest tolerance whose stick area, and that of every tighter one, is within AREA_RTOL of the tightest."""
    tols = sorted(samples)  # tight -> loose
    ref = samples[tols[0]]["stick_nodes"]
    chosen = tols[0]
    for t in tols[1:]:
        if rel(samples[t]["stick_nodes"], ref) <= AREA_RTOL:
            chosen = t
        else:
            break
    return chosen


def bench_case(n: int, nu: float, args, use_tamaas: bool) -> dict:
    s = sphere(n)
    h = s.max() - s
    P, Q = loads(nu)
    coupled = nu != 0.5
    op, dec = tribobem_operators(n, nu, args.workers)
    out = {"n": n, "nu": nu, "P": P, "Q": Q, "coupled": coupled}

    # ---- normal solves, reported separately
    nt, nt_cpu, normal = run_tribobem_normal(op, h, P)
    out["tribobem_normal"] = {"wall": nt, "cpu": nt_cpu, "iterations": normal.iterations,
                              "contact_nodes": int(np.count_nonzero(normal.contact))}
    if use_tamaas:
        w, c, info = run_tamaas_normal(s, n, nu, P)
        out["tamaas_normal"] = {"wall": w, "cpu": c, "iterations": info["iterations"],
                                "contact_nodes": info["contact_nodes"],
                                "pressure_max_diff": float(np.abs(info["pressure"] - normal.pressure).max()
                                                           / info["pressure"].max())}

    def tri_run(tol, which="main"):
        if which == "main" and coupled:
            return run_tribobem_coupled(op, h, P, Q, tol)
        return run_tribobem_tangential(dec if coupled else op, normal, Q, tol)

    # ---- tribobem tolerance ladder (tight first: the reference)
    ladder = TRIBOBEM_TOLS_QUICK if args.quick else TRIBOBEM_TOLS
    tri_samples: dict[float, tuple] = {}
    for tol in sorted(ladder):
        tri_samples[tol] = tri_run(tol)
    tol = choose_tol({t: v[2] for t, v in tri_samples.items()})
    out["tol"] = tol
    out["ladder"] = {f"{t:g}": {"stick_nodes": v[2]["stick_nodes"], "iterations": v[2]["iterations"],
                                "cpu": v[1], "converged": v[2]["converged"]} for t, v in sorted(tri_samples.items())}
    out["tribobem_reference_stick"] = tri_samples[min(ladder)][2]["stick_nodes"]
    tri = Runs()
    tri.add(*tri_samples[tol])

    # decoupled variant at nu != 0.5 (tribobem only)
    dec_s = None
    if coupled:
        dsamp = {t: tri_run(t, "decoupled") for t in sorted(ladder)}
        dtol = choose_tol({t: v[2] for t, v in dsamp.items()})
        dec_s = Runs()
        dec_s.add(*dsamp[dtol])
        out["decoupled_tol"] = dtol
        out["decoupled_reference_stick"] = dsamp[min(ladder)][2]["stick_nodes"]

    # ---- Tamaas iterations
    tam = Runs()
    if use_tamaas:
        pair = None if args.calibrate else tamaas_iterations_for(n, nu)
        if pair is None:
            cal = calibrate_tamaas(s, n, nu, P, Q)
            pair = (cal["stick"], cal["iterations"])
            out["tamaas_calibration"] = cal
        out["tamaas_iterations_stick_only"], its = pair
        out["tamaas_iterations"] = its
        tam.add(*run_tamaas_tangential(s, n, nu, P, Q, its))

    # ---- further timed rounds, interleaved
    for r in range(1, args.repeats):
        order = ["tri", "dec", "tam"] if r % 2 else ["tam", "dec", "tri"]
        for who in order:
            if who == "tam" and use_tamaas:
                tam.add(*run_tamaas_tangential(s, n, nu, P, Q, out["tamaas_iterations"]))
            elif who == "tri":
                tri.add(*tri_run(tol))
            elif who == "dec" and dec_s is not None:
                dec_s.add(*tri_run(out["decoupled_tol"], "decoupled"))
    out.update(tribobem=tri, decoupled=dec_s, tamaas=tam if use_tamaas else None, normal=normal)

    # ---- agreement
    if use_tamaas:
        a, b = tri.info, tam.info
        pmax = float(b["pressure"].max())
        out["agreement"] = {
            "stick_rel_diff": rel(a["stick_nodes"], b["stick_nodes"]),
            "stick_ratio": a["stick_nodes"] / b["stick_nodes"] if b["stick_nodes"] else math.nan,
            "contact_rel_diff": rel(a["contact_nodes"], b["contact_nodes"]),
            "stick_mismatch_nodes": int(np.count_nonzero(stick_mask(a["pressure"], *a["shear"])
                                                          != stick_mask(b["pressure"], *b["shear"]))),
            "pressure_max_diff": float(np.abs(a["pressure"] - b["pressure"]).max()) / pmax,
            "shear_max_diff": float(np.abs(a["shear"] - b["shear"]).max()) / (MU * pmax),
            "tamaas_vs_tribobem_reference": rel(b["stick_nodes"], out["tribobem_reference_stick"]),
        }
    return out


def tribobem_version() -> str:
    """Where tribobem was imported from and the git blob ids of the solver files timed here,
    compared with the repository's HEAD (other work may leave the working tree modified)."""
    import hashlib
    import subprocess

    import tribobem
    import tribobem.solvers.coupling as coupling
    import tribobem.solvers.normal as normal
    import tribobem.solvers.tangential as tangential

    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

    def git(*a):
        try:
            return subprocess.run(["git", "-C", root, *a], capture_output=True, text=True, timeout=10).stdout.strip()
        except Exception:
            return ""

    head = git("rev-parse", "--short", "HEAD") or "?"
    parts = []
    for mod in (normal, tangential, coupling):
        with open(mod.__file__, "rb") as f:
            data = f.read()
        blob = hashlib.sha1(b"blob %d\0" % len(data) + data).hexdigest()
        name = os.path.basename(mod.__file__)
        same = git("rev-parse", f"HEAD:src/tribobem/solvers/{name}") == blob
        parts.append(f"{name} {blob[:10]}{' (= HEAD)' if same else ' (differs from HEAD)'}")
    return f"tribobem from {os.path.dirname(tribobem.__file__)}, repository HEAD {head}; " + ", ".join(parts)


# --------------------------------------------------------------------------------------
# Main
# --------------------------------------------------------------------------------------


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", type=int, nargs="+", default=[256, 512], help="grid sizes n (n x n cells)")
    parser.add_argument("--repeats", type=int, default=2, help="timed runs per code and case (the minimum is reported)")
    parser.add_argument("--quick", action="store_true", help="256 only, one repeat, shorter tolerance ladder")
    parser.add_argument("--workers", type=int, default=None, help="scipy.fft workers for tribobem (default: all cores)")
    parser.add_argument("--no-tamaas", action="store_true", help="time tribobem only")
    parser.add_argument("--nus", type=float, nargs="+", default=list(NUS), help="Poisson ratios (0.5: no coupling)")
    parser.add_argument("--calibrate", action="store_true",
                        help="measure Tamaas's iteration count for 1e-3 stick accuracy (bisection; slow)")
    parser.add_argument("--tangential-method", default=None,
                        help="solve_tangential(method=...) for all tribobem tangential solves, e.g. 'fista' "
                             "(default: the solver's default)")
    parser.add_argument("--json", help="write the measured numbers to this file")
    args = parser.parse_args(argv)
    global TANGENTIAL_METHOD
    TANGENTIAL_METHOD = args.tangential_method
    if args.quick:
        args.sizes = [n for n in args.sizes if n <= 256] or [256]
        args.repeats = 1
    use_tamaas = common.HAVE_TAMAAS and not args.no_tamaas
    if not common.HAVE_TAMAAS:
        print("NOTICE: tamaas is not installed (pip install tamaas); timing tribobem only.")
    print("## Partial slip of a rigid sphere on an elastic half-space: tribobem vs Tamaas PolonskyKeerTan\n")
    print(common.environment())
    print(tribobem_version())
    print(f"Problem: periodic L = {L}, rigid paraboloid R = {R}, E = {E}, Hertz a = L/8, mu = {MU}, "
          f"Q = {Q_OVER_MU_P} mu P along x, one-step loading; stick area to {AREA_RTOL:g}; "
          f"repeats {args.repeats} (min reported); tribobem tangential method: "
          f"{TANGENTIAL_METHOD or 'solver default'}\n", flush=True)

    results = []
    for n in args.sizes:
        for nu in args.nus:
            r = bench_case(n, nu, args, use_tamaas)
            results.append(r)
            tri, tam = r["tribobem"], r["tamaas"]
            line = (f"n={n} nu={nu}: tribobem {'coupled' if r['coupled'] else 'tangential'} tol {r['tol']:g}: "
                    f"{tri.best:.3f} s, CPU {tri.best_cpu:.3f} s ({tri.info['iterations']} it), "
                    f"stick {tri.info['stick_nodes']}")
            if tam is not None:
                line += (f"; Tamaas {tam.best:.3f} s, CPU {tam.best_cpu:.3f} s ({tam.info['iterations']} it), "
                         f"stick {tam.info['stick_nodes']}")
            print(line, flush=True)

    # ---- tables
    print("\n### Time of the tangential solve (minimum over repeats)\n")
    print("tribobem: `solve_tangential` alone (nu = 0.5) or the tangential passes of `solve_coupled` (nu != 0.5, "
          "summed); Tamaas: the one-shot `PolonskyKeerTan.solve` (normal + tangential, cannot be split).\n")
    headers = ["n", "nu", "Tamaas s (it)", "tribobem tangential s (it)", "time ratio", "CPU ratio",
               "tribobem normal + tangential s", "time ratio (total)", "CPU ratio (total)",
               "stick nodes Tamaas / tribobem", "stick rel. diff", "tribobem tol"]
    rows = []
    for r in results:
        tri, tam = r["tribobem"], r["tamaas"]
        if r["coupled"]:
            t_wall, t_cpu = tri.min_of("tangential_wall"), tri.min_of("tangential_cpu")
            tot_wall, tot_cpu = tri.best, tri.best_cpu
            it = f"{tri.info['iterations']} in {tri.info['passes']} passes"
        else:
            t_wall, t_cpu = tri.best, tri.best_cpu
            tot_wall = tri.best + r["tribobem_normal"]["wall"]
            tot_cpu = tri.best_cpu + r["tribobem_normal"]["cpu"]
            it = str(tri.info["iterations"])
        if tam is not None:
            ag = r["agreement"]
            rows.append([r["n"], r["nu"], f"{tam.best:.3g} ({tam.info['iterations']})", f"{t_wall:.3g} ({it})",
                         t_wall / tam.best, t_cpu / tam.best_cpu, f"{tot_wall:.3g}", tot_wall / tam.best,
                         tot_cpu / tam.best_cpu, f"{tam.info['stick_nodes']} / {tri.info['stick_nodes']}",
                         ag["stick_rel_diff"], f"{r['tol']:g}"])
        else:
            rows.append([r["n"], r["nu"], "-", f"{t_wall:.3g} ({it})", math.nan, math.nan, f"{tot_wall:.3g}",
                         math.nan, math.nan, f"- / {tri.info['stick_nodes']}", math.nan, f"{r['tol']:g}"])
    print(markdown_table(headers, rows))

    print("\n### Details: CPU seconds, normal solves, per-iteration cost\n")
    headers = ["n", "nu", "Tamaas CPU s", "Tamaas ms/it", "tribobem tangential CPU s", "tribobem tangential ms/it",
               "tribobem normal s (it)", "Tamaas PKR normal s (it)", "CPU/wall tribobem", "CPU/wall Tamaas",
               "Tamaas it, stick area only", "CPU ratio vs that (scaled)", "tribobem tangential convolutions",
               "CPU ms per convolution (in the solve)", "share of the tangential CPU in them"]
    rows = []
    for r in results:
        tri, tam = r["tribobem"], r["tamaas"]
        if r["coupled"]:
            t_wall, t_cpu = tri.min_of("tangential_wall"), tri.min_of("tangential_cpu")
            nrm = f"{tri.min_of('normal_wall'):.3g} ({tri.info['normal_iterations']}, in the loop)"
        else:
            t_wall, t_cpu = tri.best, tri.best_cpu
            nrm = f"{r['tribobem_normal']['wall']:.3g} ({r['tribobem_normal']['iterations']})"
        tn = r.get("tamaas_normal")
        conv_n, conv_cpu = tri.info.get("convolutions") or 0, tri.info.get("convolution_cpu") or 0.0
        rows.append([r["n"], r["nu"], tam.best_cpu if tam else math.nan,
                     1e3 * tam.best / tam.info["iterations"] if tam else math.nan, t_cpu,
                     1e3 * t_wall / max(tri.info["iterations"], 1), nrm,
                     f"{tn['wall']:.3g} ({tn['iterations']})" if tn else "-", tri.cpu_per_wall,
                     tam.cpu_per_wall if tam else math.nan, r.get("tamaas_iterations_stick_only"),
                     t_cpu / (tam.best_cpu * r["tamaas_iterations_stick_only"] / tam.info["iterations"])
                     if tam else math.nan, conv_n, 1e3 * conv_cpu / conv_n if conv_n else math.nan,
                     conv_cpu / tri.info["tangential_cpu_run"]])
    print(markdown_table(headers, rows))

    if use_tamaas:
        print("\n### Accuracy\n")
        headers = ["n", "nu", "contact nodes Tamaas / tribobem", "stick nodes Tamaas / tribobem",
                   "tribobem stick at tightest tol", "Tamaas vs that", "nodes classified differently",
                   "max |dp| / max p", "max |dq| / (mu max p)", "F_x / Q Tamaas, tribobem", "Tamaas it"]
        rows = []
        for r in results:
            a, b, ag = r["tribobem"].info, r["tamaas"].info, r["agreement"]
            rows.append([r["n"], r["nu"], f"{b['contact_nodes']} / {a['contact_nodes']}",
                         f"{b['stick_nodes']} / {a['stick_nodes']}", r["tribobem_reference_stick"],
                         ag["tamaas_vs_tribobem_reference"], ag["stick_mismatch_nodes"], ag["pressure_max_diff"],
                         ag["shear_max_diff"], f"{b['force_x'] / r['Q']:.6f}, {a['force_x'] / r['Q']:.6f}",
                         r["tamaas_iterations"]])
        print(markdown_table(headers, rows))

    print("\n### tribobem tolerance ladder (stick nodes / iterations)\n")
    tols = sorted({t for r in results for t in r["ladder"]}, key=float, reverse=True)
    headers = ["n", "nu"] + [f"tol {t}" for t in tols] + ["chosen"]
    rows = [[r["n"], r["nu"]] + [f"{r['ladder'][t]['stick_nodes']} / {r['ladder'][t]['iterations']}"
                                 if t in r["ladder"] else "-" for t in tols] + [f"{r['tol']:g}"] for r in results]
    print(markdown_table(headers, rows))

    dec = [r for r in results if r["decoupled"] is not None]
    if dec:
        print("\n### nu != 0.5 without coupling (tribobem only: Tamaas's surface_2d operator always couples)\n")
        headers = ["n", "nu", "tribobem decoupled tangential s (it)", "CPU s", "stick nodes", "tol",
                   "Cattaneo-Mindlin stick nodes pi c^2/dx^2", "vs Tamaas coupled solve: time ratio", "CPU ratio"]
        rows = []
        for r in dec:
            d, tam = r["decoupled"], r["tamaas"]
            c = CONTACT_RADIUS * (1 - Q_OVER_MU_P) ** (1 / 3)
            rows.append([r["n"], r["nu"], f"{d.best:.3g} ({d.info['iterations']})", d.best_cpu,
                         d.info["stick_nodes"], f"{r['decoupled_tol']:g}", math.pi * c * c / (L / r["n"]) ** 2,
                         d.best / tam.best if tam else math.nan, d.best_cpu / tam.best_cpu if tam else math.nan])
        print(markdown_table(headers, rows))

    if args.json:
        dump = []
        for r in results:
            d = {k: v for k, v in r.items() if k not in ("tribobem", "decoupled", "tamaas", "normal")}
            for k in ("tribobem", "decoupled", "tamaas"):
                smp = r[k]
                if smp is not None and smp.times:
                    d[k] = {"times": smp.times, "cpu": smp.cpu,
                            **{kk: vv for kk, vv in smp.info.items() if kk not in ("pressure", "shear")}}
            dump.append(d)
        with open(args.json, "w") as f:
            json.dump(dump, f, indent=1, default=float)
    return 0


if __name__ == "__main__":
    sys.exit(main())
