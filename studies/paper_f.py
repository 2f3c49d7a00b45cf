"""Paper F: pre-sliding of a rough polymer ball on a silicon wafer (friction loops and the
lateral stiffness K_L at the points A, B, C).

The workflow of Paper F section 4: a polymer ball (R = 5 mm; HDPE E = 0.98 GPa or POM
E = 1.38 GPa, nu = 0.5) with its measured roughness on a smooth, elastic Si wafer (E = 130 GPa,
nu = 0.28); normal force F0 = 25, 50, 75 mN; friction coefficient and stroke from Paper F
Table 1; four displacement cycles 0 -> +d_s/2 -> -d_s/2 -> ... (Paper F Fig. 5), the last one
used; K_L from the Paper F Eq. 3 fit of the last branch from -F* to +F* at F_x/(mu F0) = -0.5,
0, 0.5 (A, B, C), beside the Mindlin-Deresiewicz slope of that branch and Paper F Eq. 6.

Each case is a ``hysteresis`` scenario (:func:`scenario`, run by
:func:`tribobem.scenario.run_scenario` into its own result folder, which ``tribobem
compare-loop`` accepts); K_L is taken with :mod:`tribobem.analysis.loops` (the same fit that
``compare-loop`` applies to a measured loop).

Choices (documented, see also ``examples/studies/paper_f.py``):

* Bodies: the wafer is body 1 (lower, smooth, elastic), the ball body 2 (upper: sphere plus the
  measured roughness; file-contract signs: F_x acts on the ball, delta_x is the ball's displacement).
* Roughness: the Sensofar confocal file ``plu-1.plu`` (1.27 x 0.96 mm, 768 x 576 points) stands
  in for Paper F's ball scans (1.1 mm, Sensofar, 1024^2).  Its "center"-detrended rms (2.83 um)
  is almost all a tilt and the ball's form: with the best quadratic removed (``detrend =
  "curvature"``, Paper F's "flattened" view, Fig. 16) the scan has rms 18.2 nm and rms slope
  0.0046.  The WHOLE flattened scan is scaled to the Table 2 rms (3.17 um HDPE, 0.67 um POM:
  factors 174 and 37); the solver domain is the central window of the scan, resampled (linear
  interpolation) to the grid.  The scenario's ``roughness.rms`` rescales the resampled window,
  so it is given the window's own rms after that scaling (:func:`window_rms`; about 0.8 x the
  Table 2 value: the window misses the longest wavelengths of the scan).
* Domain: free boundary, square, centred on the scan.  A normal-contact check on a 600 um
  window (128^2) put every contact within r < 142 um (HDPE, 75 mN) and r < 95 um (POM, 75
  mN) of the centre, so the domains are 320 um (HDPE) and 240 um (POM): +-(2.7-3.8) a for HDPE
  and +-(2.2-3.2) a for POM, a the Hertz radius (37-60 um).  The records store the smallest
  distance (in cells) between the contact and the domain edge.
* Grid and steps: 96^2 (dx = 3.3 um HDPE, 2.5 um POM) and 96 steps per cycle.  The path's
  Chebyshev-cosine steps are densest at the reversals; the pre-sliding part of a branch (about
  2 delta0 = 0.1-0.3 um of a 2.7-4.3 um stroke) then holds 7-12 steps, enough for the 3-parameter
  Eq. 3 fit.  The six cases take 14 min on a shared 2-core machine (409 steps each).
  Resolution check (50 mN, one cycle; K_L at A / B / C in kN/m): HDPE 64^2 67.2 / 46.8 / 23.8,
  96^2 57.1 / 47.5 / 34.1, 128^2 56.3 / 43.7 / 28.0; POM 64^2 99.6 / 81.5 / 57.9, 96^2 98.7 /
  79.5 / 54.6, 128^2 98.7 / 77.2 / 50.8.  A is converged, B within ~5 %, C (slip spreading over
  asperity contacts of a few cells) within ~10 % (POM) and ~20 % (HDPE, 50-60 contact cells).
* Cycles: every stroke ends in gross sliding, which erases the history, so cycles 2-4 repeat
  cycle 1 (loop change below 2e-3 mu F0; one cycle gives the same K_L to all digits shown).
* References (smooth Hertz ball, both bodies' compliance ``k = sum (2 - nu_i)/G_i``; the wafer
  adds 0.7-1 %): Mindlin-Deresiewicz slope of the branch from -mu F0, ``K0 (1 - (F + mu F0)/
  (2 mu F0))^(1/3)`` (file-contract ``mindlin_stiffness``), and Paper F Eq. 6 (the virgin-curve slope
  at the same |F|), ``K0 (1 - |F|/(mu F0))^(1/3)``, ``K0 = 8 a/k``.  The loop energy of a
  Mindlin-Deresiewicz loop driven into gross sliding by a stroke d_s is
  ``2 mu F0 (d_s - 1.6 delta0)`` (the rectangle 2 mu F0 x d_s less the two pre-sliding corners).
"""

from __future__ import annotations

import contextlib
import json
import math
import time
from dataclasses import asdict, dataclass
from pathlib import Path

import numpy as np

from tribobem.data import topography_path
from tribobem.errors import InputError

__all__ = [
    "RADIUS", "WAFER", "MATERIALS", "TABLE1", "LOADS", "DOMAIN", "DETREND", "TOPOGRAPHY",
    "Case", "cases", "default_topography", "full_scan_rms", "window_rms", "scenario",
    "hertz_radius", "compliance", "mindlin_delta0", "mindlin_branch_stiffness", "eq6_stiffness",
    "mindlin_loop_energy", "run_case", "paper_f_study", "stiffness_table", "findings",
    "plot_loops", "plot_maps", "write_csv",
]

#: Ball radius (m).
RADIUS = 5e-3
#: The silicon wafer (Paper F Table 2): body 1, smooth.
WAFER = {"name": "Si wafer", "E": 130e9, "nu": 0.28}
#: The balls (Paper F Table 2): E (Pa), nu, rms roughness of the flattened scan (m).
MATERIALS = {
    "HDPE": {"E": 0.98e9, "nu": 0.5, "rms": 3.17e-6},
    "POM": {"E": 1.38e9, "nu": 0.5, "rms": 0.67e-6},
}
#: Paper F Table 1: F0 (mN) -> material -> (stroke d_s (m), friction coefficient).
TABLE1 = {
    25: {"HDPE": (2.805e-6, 0.153), "POM": (2.700e-6, 0.108)},
    50: {"HDPE": (2.943e-6, 0.146), "POM": (3.370e-6, 0.104)},
    75: {"HDPE": (3.697e-6, 0.129), "POM": (4.264e-6, 0.099)},
}
#: Normal forces (mN).
LOADS = (25, 50, 75)
#: Solver domain side (m) per material (see the module docstring).
DOMAIN = {"HDPE": 320e-6, "POM": 240e-6}
#: The ball form is removed with the best quadratic (Paper F's "flattened" scans).
DETREND = "curvature"
#: The stand-in measured ball topography (shipped with tribobem: tribobem.data.topography_path).
TOPOGRAPHY = "plu-1.plu"
#: Defaults of the study.
N_DEFAULT, STEPS_DEFAULT, CYCLES_DEFAULT = 96, 96, 4


@dataclass(frozen=True)
class Case:
    """One Paper F case: material and normal force with its Table 1 stroke and friction."""

    material: str
    load_mN: int
    stroke: float
    mu: float
    E: float
    nu: float
    rms: float

    @property
    def force(self) -> float:
        """Normal force F0 (N)."""
        return self.load_mN * 1e-3

    @property
    def name(self) -> str:
        return f"{self.material.lower()}_{self.load_mN}mN"


def cases(materials=("HDPE", "POM"), loads=LOADS) -> list[Case]:
    """The Paper F cases (Table 1 x Table 2)."""
    out = []
    for m in materials:
        if m not in MATERIALS:
            raise InputError("material", f"unknown {m!r}; Paper F has {', '.join(MATERIALS)}")
        for f in loads:
            if int(f) not in TABLE1:
                raise InputError("load", f"Paper F Table 1 has F0 = {', '.join(map(str, TABLE1))} mN, got {f!r}")
            stroke, mu = TABLE1[int(f)][m]
            mat = MATERIALS[m]
            out.append(Case(m, int(f), stroke, mu, mat["E"], mat["nu"], mat["rms"]))
    return out


# ----------------------------------------------------------------------------- topography
def default_topography() -> Path:
    """``plu-1.plu``, the measured file shipped with tribobem (:func:`tribobem.data.topography_path`:
    the package's data folder, or ``$TRIBOBEM_DATA_DIR`` when set); InputError if it is not there."""
    return topography_path(TOPOGRAPHY)


_RMS_CACHE: dict = {}


def _flattened(path):
    from tribobem.geometry import read_topography

    key = str(Path(path).resolve())
    if key not in _RMS_CACHE:
        import warnings

        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            _RMS_CACHE[key] = read_topography(path, detrend=DETREND)
    return _RMS_CACHE[key]


def full_scan_rms(path) -> float:
    """rms height (m) of the whole scan with the best quadratic removed."""
    return float(np.std(_flattened(path).heights))


def window_rms(path, n: int, size: float, target: float) -> float:
    """The ``roughness.rms`` that makes the resampled central ``size`` x ``size`` window on
    ``n x n`` cells equal to the whole flattened scan scaled to rms ``target``."""
    from tribobem.grid import Grid

    topo = _flattened(path)
    w = topo.resample(Grid(int(n), int(n), float(size), float(size), False)).heights
    return float(target * np.std(w) / full_scan_rms(path))


def scenario(case: Case, n: int = N_DEFAULT, size: float | None = None, steps: int = STEPS_DEFAULT,
             cycles: int = CYCLES_DEFAULT, topography=None, tolerance: float | None = None) -> dict:
    """The ``hysteresis`` scenario (dict, SI numbers) of a case."""
    topo = Path(topography) if topography is not None else default_topography()
    size = DOMAIN[case.material] if size is None else float(size)
    sc = {
        "kind": "hysteresis",
        "name": f"Paper F: {case.material} ball on Si, F0 = {case.load_mN} mN",
        "grid": {"n": int(n), "size": size, "periodic": False},
        "body1": {"name": WAFER["name"], "E": WAFER["E"], "nu": WAFER["nu"]},
        "body2": {"name": f"{case.material} ball", "E": case.E, "nu": case.nu,
                  "shape": {"kind": "sphere", "radius": RADIUS},
                  "roughness": {"kind": "file", "path": str(topo), "detrend": DETREND,
                                "rms": window_rms(topo, n, size, case.rms)}},
        "load": {"force": case.force},
        "friction": {"coefficient": case.mu,
                     "path": {"control": "displacement", "stroke": case.stroke, "cycles": int(cycles),
                              "steps": int(steps)}},
    }
    if tolerance is not None:
        sc["solver"] = {"tolerance": float(tolerance)}
    return sc


# ----------------------------------------------------------------------------- references
def compliance(case: Case) -> float:
    """k = sum_i (2 - nu_i)/G_i of ball and wafer (1/Pa)."""
    return sum((2.0 - nu) * 2.0 * (1.0 + nu) / E for E, nu in ((case.E, case.nu), (WAFER["E"], WAFER["nu"])))


def hertz_radius(case: Case) -> float:
    """Hertz contact radius of the smooth ball (m)."""
    inv = (1.0 - case.nu**2) / case.E + (1.0 - WAFER["nu"] ** 2) / WAFER["E"]
    return (3.0 * case.force * RADIUS * inv / 4.0) ** (1.0 / 3.0)


def mindlin_delta0(case: Case) -> float:
    """delta0 = 3 mu F0 k/(16 a) (m): the virgin curve's gross-slip displacement."""
    return 3.0 * case.mu * case.force * compliance(case) / (16.0 * hertz_radius(case))


def _k0(case: Case) -> float:
    return 8.0 * hertz_radius(case) / compliance(case)


def mindlin_branch_stiffness(case: Case, force, turn_force=None) -> float:
    """Slope (N/m) of the Mindlin-Deresiewicz branch from ``turn_force`` (default -mu F0, the
    sliding loop's turning point) at the tangential force ``force`` (N)."""
    muP = case.mu * case.force
    turn = -muP if turn_force is None else float(turn_force)
    return float(_k0(case) * max(1.0 - (float(force) - turn) / (2.0 * muP), 0.0) ** (1.0 / 3.0))


def eq6_stiffness(case: Case, force) -> float:
    """Paper F Eq. 6 (N/m): the virgin-curve slope at |F| (Eq. 6 at delta_x from Eq. 4)."""
    return float(_k0(case) * max(1.0 - abs(float(force)) / (case.mu * case.force), 0.0) ** (1.0 / 3.0))


def mindlin_loop_energy(case: Case) -> float:
    """Energy (J) of a Mindlin-Deresiewicz loop driven by the stroke into gross sliding:
    2 mu F0 (d_s - 1.6 delta0)."""
    return 2.0 * case.mu * case.force * (case.stroke - 1.6 * mindlin_delta0(case))


# ----------------------------------------------------------------------------- running a case
@contextlib.contextmanager
def _keep_states():
    """Keep the HysteresisRun that the hysteresis runner computes (every step's state), for the
    stick/slip maps at A, B, C: fields.nc holds only the start and the turning points."""
    from tribobem.runs import hysteresis as runner

    kept = {}
    original = runner.hysteresis_loop

    def keeping(*args, **kwargs):
        res = original(*args, **kwargs)
        kept["run"] = res
        return res

    runner.hysteresis_loop = keeping
    try:
        yield kept
    finally:
        runner.hysteresis_loop = original


def _edge_margin(mask) -> int:
    """Smallest number of cells between a True cell and the domain edge (-1: none)."""
    idx = np.argwhere(mask)
    if idx.size == 0:
        return -1
    nx, ny = mask.shape
    return int(min(idx[:, 0].min(), idx[:, 1].min(), nx - 1 - idx[:, 0].max(), ny - 1 - idx[:, 1].max()))


def _maps(kept, summary, fit, loop, points, mu) -> dict:
    """Pressure at the start and |q|/(mu p) and stick masks at the steps nearest A, B, C."""
    run = kept.get("run")
    if run is None:
        return {}
    states = [run.start] + list(run.steps)
    out = {"pressure_start": np.asarray(run.start.normal.pressure, float)}
    F = loop.force
    for row in points:
        if not math.isfinite(row["displacement"]):
            continue
        br = np.arange(fit.start, fit.fit_end + 1)
        k = int(br[np.argmin(np.abs(F[br] - row["force"]))])
        st = states[k]
        p = np.asarray(st.normal.pressure, float)
        q = np.asarray(st.tangential.shear, float)
        with np.errstate(invalid="ignore", divide="ignore"):
            ratio = np.where(p > 0, np.hypot(q[0], q[1]) / (mu * p), np.nan)
        out[f"shear_ratio_{row['point']}"] = ratio
        out[f"stick_{row['point']}"] = np.asarray(st.tangential.stick, bool)
        out[f"force_{row['point']}"] = np.array(F[k])
        out[f"step_{row['point']}"] = np.array(k)
    return out


def run_case(case: Case, outdir, n: int = N_DEFAULT, size: float | None = None, steps: int = STEPS_DEFAULT,
             cycles: int = CYCLES_DEFAULT, topography=None, force: bool = False, progress=None,
             figures: bool = True) -> dict:
    """Run one case into ``outdir/<case.name>`` and return its record (also written there as
    ``paper_f_case.json``, with the maps in ``maps.npz``).  A finished case with the same
    parameters is read back instead of recomputed unless ``force``.  ``figures = False`` writes
    summary.json only (no fields.nc, figures or report: tests)."""
    from tribobem.analysis.loops import fit_branch, loop_from_summary, stiffness_points
    from tribobem.analysis.loops import STIFFNESS_POINTS
    from tribobem.scenario import run_scenario

    size = DOMAIN[case.material] if size is None else float(size)
    sc = scenario(case, n=n, size=size, steps=steps, cycles=cycles, topography=topography)
    folder = Path(outdir) / case.name
    rec_path = folder / "paper_f_case.json"
    params = {"case": asdict(case), "n": int(n), "size": size, "steps": int(steps), "cycles": int(cycles),
              "topography": sc["body2"]["roughness"]["path"], "roughness_rms": sc["body2"]["roughness"]["rms"]}
    if not force and rec_path.is_file():
        try:
            rec = json.loads(rec_path.read_text(encoding="utf-8"))
            if rec.get("params") == json.loads(json.dumps(params)):
                return rec
        except (OSError, ValueError):
            pass
    import warnings

    from tribobem.errors import ConvergenceWarning

    t0 = time.perf_counter()
    with _keep_states() as kept, warnings.catch_warnings():
        warnings.simplefilter("ignore", ConvergenceWarning)
        result = run_scenario(sc, outdir=folder if figures else None,
                              progress=progress if progress is not None else False, quiet=True)
    wall = time.perf_counter() - t0
    if not figures:
        from tribobem.output.summary import write_summary

        folder.mkdir(parents=True, exist_ok=True)
        write_summary(folder / "summary.json", result.summary)
    summary = result.summary
    loop = loop_from_summary(summary)
    fit_error = None
    try:
        fit = fit_branch(loop)
        pts = stiffness_points(loop, fit)
    except InputError as exc:  # too few pre-sliding steps: keep the run, report the fit as missing
        fit_error = str(exc)
        fit = None
        pts = [{"point": p, "force_ratio": v, "force": v * case.mu * case.force, "displacement": math.nan,
                "stiffness": math.nan} for p, v in STIFFNESS_POINTS.items()]
    a = hertz_radius(case)
    muP = case.mu * case.force
    f0p = summary.get("repulsive_force", case.force)
    table = []
    runner_k = {r["point"]: r.get("stiffness") for r in summary.get("lateral_stiffness") or []}
    for r in pts:
        k_md = mindlin_branch_stiffness(case, r["force"], fit.turn_force if fit is not None else None)
        k_eq6 = eq6_stiffness(case, r["force"])
        table.append({"point": r["point"], "force_ratio": r["force_ratio"], "force": r["force"],
                      "displacement": r["displacement"], "stiffness": r["stiffness"], "mindlin_stiffness": k_md,
                      "eq6_stiffness": k_eq6, "ratio_to_mindlin": r["stiffness"] / k_md if k_md > 0 else math.nan,
                      "runner_stiffness": runner_k.get(r["point"])})
    maps = _maps(kept, summary, fit, loop, pts, case.mu) if fit is not None else {}
    kept.clear()
    p0 = maps.get("pressure_start")
    contact = p0 > 0 if p0 is not None else None
    last = [i for i, s in enumerate(summary["steps"]) if s.get("cycle") == cycles]
    first_last = last[0] - 1 if last else 0
    energies = summary.get("dissipated_energy") or []
    start = summary["steps"][0]
    rec = {
        "params": params,
        "material": case.material, "load_mN": case.load_mN, "normal_force": case.force, "mu": case.mu,
        "stroke": case.stroke, "E": case.E, "nu": case.nu, "rms": case.rms,
        "roughness_rms_window": sc["body2"]["roughness"]["rms"],
        "n": int(n), "size": size, "dx": size / n, "steps_per_cycle": int(steps), "cycles": int(cycles),
        "n_steps": len(summary["steps"]),
        "hertz_radius": a, "mindlin_delta0": mindlin_delta0(case), "mindlin_k0": _k0(case),
        "repulsive_force": f0p,
        "contact_area": start.get("contact_area"), "max_pressure": start.get("max_pressure"),
        "contact_cells": int(np.count_nonzero(contact)) if contact is not None else None,
        "contact_radius_max": (float(np.max(np.hypot(*np.meshgrid(result.problem.grid.x, result.problem.grid.y,
                                                                   indexing="ij"))[contact]))
                               if contact is not None and contact.any() else None),
        "edge_margin_cells": _edge_margin(contact) if contact is not None else None,
        "sliding_force": summary.get("sliding_force"),
        "sliding_ratio": (summary.get("sliding_force") or math.nan) / muP,
        "static_friction_force": summary.get("static_friction_force"),
        "presliding_displacement": summary.get("presliding_displacement"),
        "loop_energy": energies[-1] if energies else None, "loop_energies": energies,
        "mindlin_loop_energy": mindlin_loop_energy(case),
        "loop_change": summary.get("loop_change"),
        "converged": bool(summary.get("converged")), "failed_steps": summary.get("failed_steps", []),
        "fit": fit.as_dict() if fit is not None else None, "fit_error": fit_error, "stiffness": table,
        "last_loop": {"displacement": [float(v) for v in loop.displacement[first_last:]],
                      "force": [float(v) for v in loop.force[first_last:]]},
        "wall_time": wall, "solve_time": summary.get("timings", {}).get("solve"),
        "result_folder": str(folder),
    }
    from tribobem.output.atomic import atomic_write_bytes
    from tribobem.output.summary import jsonable

    if maps:
        import io

        buf = io.BytesIO()
        np.savez_compressed(buf, **maps)
        atomic_write_bytes(folder / "maps.npz", buf.getvalue())
    atomic_write_bytes(rec_path, (json.dumps(jsonable(rec), indent=1) + "\n").encode("utf-8"))
    return json.loads(json.dumps(jsonable(rec)))


def paper_f_study(outdir, materials=("HDPE", "POM"), loads=LOADS, n: int = N_DEFAULT, steps: int = STEPS_DEFAULT,
                  cycles: int = CYCLES_DEFAULT, size: float | None = None, topography=None, force: bool = False,
                  progress=None) -> list[dict]:
    """Run (or read back) every case; ``progress(done, total, record)`` after each."""
    todo = cases(materials, loads)
    recs = []
    for i, c in enumerate(todo):
        rec = run_case(c, outdir, n=n, size=size, steps=steps, cycles=cycles, topography=topography, force=force)
        recs.append(rec)
        if progress:
            progress(i + 1, len(todo), rec)
    return recs


# ----------------------------------------------------------------------------- tables
def stiffness_table(records) -> list[dict]:
    """One row per case and point: K_L (fit), the Mindlin-Deresiewicz branch slope, Paper F
    Eq. 6, with the case's sliding force, loop energy and run time."""
    rows = []
    for r in records:
        for s in r["stiffness"]:
            rows.append({
                "material": r["material"], "F0_mN": r["load_mN"], "mu": r["mu"], "stroke_um": r["stroke"] * 1e6,
                "point": s["point"], "force_ratio": s["force_ratio"], "tangential_force_mN": s["force"] * 1e3,
                "K_L_fit_kN_per_m": _num(s["stiffness"]) / 1e3,
                "K_mindlin_branch_kN_per_m": _num(s["mindlin_stiffness"]) / 1e3,
                "K_eq6_kN_per_m": _num(s["eq6_stiffness"]) / 1e3,
                "fit_over_mindlin": _num(s["ratio_to_mindlin"]),
                "fit_points": (r["fit"] or {}).get("points"), "fit_n": (r["fit"] or {}).get("n", math.nan),
                "sliding_force_mN": _num(r["sliding_force"]) * 1e3, "sliding_over_muF0": _num(r["sliding_ratio"]),
                "loop_energy_nJ": _num(r["loop_energy"]) * 1e9,
                "mindlin_loop_energy_nJ": _num(r["mindlin_loop_energy"]) * 1e9,
                "hertz_radius_um": r["hertz_radius"] * 1e6, "contact_area_um2": _num(r["contact_area"]) * 1e12,
                "max_pressure_MPa": _num(r["max_pressure"]) / 1e6,
                "n": r["n"], "domain_um": r["size"] * 1e6, "steps_per_cycle": r["steps_per_cycle"],
                "cycles": r["cycles"], "edge_margin_cells": r["edge_margin_cells"], "converged": r["converged"],
                "wall_time_s": r["wall_time"],
            })
    return rows


def _num(v) -> float:
    try:
        return float(v) if v is not None else math.nan
    except (TypeError, ValueError):
        return math.nan


def write_csv(rows, path) -> Path:
    """Write rows (dicts with the same keys) as CSV (atomically)."""
    import csv
    import io

    from tribobem.output.atomic import atomic_write_bytes

    buf = io.StringIO()
    w = csv.DictWriter(buf, fieldnames=list(rows[0].keys()), lineterminator="\n")
    w.writeheader()
    for r in rows:
        w.writerow({k: (f"{v:.6g}" if isinstance(v, float) else v) for k, v in r.items()})
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    return atomic_write_bytes(path, buf.getvalue().encode("utf-8"))


def findings(records) -> dict:
    """Paper F's findings checked on the records: K_L falls from A to C (per case), POM stiffer
    than HDPE (per load and point, where both were run)."""
    falls = {}
    for r in records:
        k = {s["point"]: _num(s["stiffness"]) for s in r["stiffness"]}
        falls[f"{r['material']} {r['load_mN']} mN"] = bool(k.get("A", math.nan) > k.get("B", math.nan) > k.get("C", math.nan))
    stiffer = {}
    by = {(r["material"], r["load_mN"]): r for r in records}
    for (m, f), r in by.items():
        if m != "POM" or ("HDPE", f) not in by:
            continue
        kp = {s["point"]: _num(s["stiffness"]) for s in r["stiffness"]}
        kh = {s["point"]: _num(s["stiffness"]) for s in by[("HDPE", f)]["stiffness"]}
        for p in kp:
            stiffer[f"{f} mN {p}"] = bool(kp[p] > kh.get(p, math.nan))
    return {"K_falls_A_to_C": falls, "POM_stiffer_than_HDPE": stiffer,
            "all_fall": all(falls.values()) if falls else None,
            "all_POM_stiffer": all(stiffer.values()) if stiffer else None}


# ----------------------------------------------------------------------------- figures
_COLORS = {25: "C0", 50: "C1", 75: "C2"}
_MARK = {"HDPE": "o", "POM": "s"}


def plot_loops(records, path) -> Path:
    """The README figure: (a, b) last loops per material; (c, d) the last rising branch from its
    turning point with the Eq. 3 fits and A, B, C; (e) K_L at A, B, C against F0 beside the
    Mindlin-Deresiewicz branch slope; (f) K_L / K_MD."""
    import io

    from matplotlib.figure import Figure

    from tribobem.output.atomic import atomic_write_bytes

    fig = Figure(figsize=(15, 8.6), layout="constrained")
    axs = fig.subplots(2, 3)
    mats = [m for m in MATERIALS if any(r["material"] == m for r in records)]
    for col, m in enumerate(mats[:2]):
        ax, bx = axs[0, col], axs[1, col]
        for r in (r for r in records if r["material"] == m):
            c = _COLORS.get(r["load_mN"], None)
            d = np.array(r["last_loop"]["displacement"])
            F = np.array(r["last_loop"]["force"])
            ax.plot(d * 1e6, F * 1e3, "-", color=c, lw=1.3,
                    label=f"{r['load_mN']} mN, \u03bc = {r['mu']:g}, d_s = {r['stroke'] * 1e6:.3g} \u00b5m")
            fit = r["fit"]
            if not fit:
                continue
            # branch from the turning point: rebuild from the last loop
            k0 = int(np.argmin(d))
            dd, dF = d[k0:] - d[k0], F[k0:] - F[k0]
            d_fit = dd[min(fit["fit_end"] - fit["start"], len(dd) - 1)]
            sel = dd <= 2.5 * d_fit
            bx.plot(dd[sel] * 1e9, dF[sel] * 1e3, "o", color=c, ms=3.5, alpha=0.7)
            xf = np.linspace(0.0, d_fit, 100)
            yf = fit["c1"] * (1.0 - np.clip(1.0 - fit["c2"] * xf, 0.0, None) ** fit["n"])
            bx.plot(xf * 1e9, yf * 1e3, "-", color=c, lw=1.5,
                    label=f"{r['load_mN']} mN: Eq. 3 fit, n = {fit['n']:.2f}, {fit['points']} points")
            for s in r["stiffness"]:
                if math.isfinite(_num(s["displacement"])):
                    bx.plot((s["displacement"] - fit["turn_displacement"]) * 1e9, (s["force"] - fit["turn_force"]) * 1e3,
                            "D", color=c, mfc="white", ms=7, mew=1.5)
                    bx.annotate(s["point"], ((s["displacement"] - fit["turn_displacement"]) * 1e9,
                                             (s["force"] - fit["turn_force"]) * 1e3),
                                xytext=(-12, 3), textcoords="offset points", fontsize=8, color=c)
        E = MATERIALS[m]["E"]
        r0 = next(r for r in records if r["material"] == m)
        ax.set_title(f"({'ab'[col]}) {m} ball (E = {E / 1e9:g} GPa, rms {MATERIALS[m]['rms'] * 1e6:g} \u00b5m) on Si\n"
                     f"last of {r0['cycles']} displacement cycles", fontsize=9)
        ax.set_xlabel("displacement of the ball \u03b4_x (\u00b5m)")
        ax.set_ylabel("friction force F_x (mN)")
        ax.legend(fontsize=7.5, loc="center")
        ax.grid(alpha=0.3)
        bx.set_title(f"({'cd'[col]}) {m}: last rising branch from its turning point (-\u03bc F0), "
                     "pre-sliding part;\nPaper F Eq. 3 fits, A, B, C at F_x/(\u03bc F0) = -0.5, 0, 0.5", fontsize=9)
        bx.set_xlabel("\u03b4_x - \u03b4_turn (nm)")
        bx.set_ylabel("F_x - F_turn (mN)")
        bx.legend(fontsize=7.5, loc="lower right")
        bx.grid(alpha=0.3)
    ax = axs[0, 2]
    off = {"A": -2.0, "B": 0.0, "C": 2.0}
    pcol = {"A": "C3", "B": "C4", "C": "C5"}
    for m in mats:
        rs = sorted((r for r in records if r["material"] == m), key=lambda r: r["load_mN"])
        for p in ("A", "B", "C"):
            F0 = np.array([r["load_mN"] for r in rs], float)
            k = np.array([_num(next(s for s in r["stiffness"] if s["point"] == p)["stiffness"]) for r in rs])
            kmd = np.array([_num(next(s for s in r["stiffness"] if s["point"] == p)["mindlin_stiffness"]) for r in rs])
            ls = "-" if m == "POM" else "--"
            ax.plot(F0 + off[p] * (1 if m == "POM" else -1) * 0.5, k / 1e3, _MARK[m], color=pcol[p], ms=7,
                    mfc=pcol[p] if m == "POM" else "white", label=f"{m} {p} (fit)")
            ax.plot(F0, kmd / 1e3, ls, color=pcol[p], lw=0.9, alpha=0.7)
    ax.set_title("(e) K_L at A, B, C: BEM fit (filled POM, open HDPE);\nlines: Mindlin-Deresiewicz, smooth ball "
                 "(POM solid, HDPE dashed)", fontsize=9)
    ax.set_xlabel("normal force F0 (mN)")
    ax.set_ylabel("lateral stiffness K_L (kN/m)")
    ax.set_xticks(sorted({r["load_mN"] for r in records}))
    ax.legend(fontsize=7, ncol=2)
    ax.grid(alpha=0.3)
    ax = axs[1, 2]
    for m in mats:
        for r in sorted((r for r in records if r["material"] == m), key=lambda r: r["load_mN"]):
            ratios = [_num(s["ratio_to_mindlin"]) for s in r["stiffness"]]
            ax.plot([0, 1, 2], ratios, _MARK[m] + ("-" if m == "POM" else "--"), color=_COLORS.get(r["load_mN"]),
                    mfc=_COLORS.get(r["load_mN"]) if m == "POM" else "white", label=f"{m} {r['load_mN']} mN")
    ax.axhline(1.0, color="k", lw=0.8)
    ax.set_xticks([0, 1, 2], ["A", "B", "C"])
    ax.set_ylabel("K_L (rough ball, BEM) / K_MD (smooth ball)")
    ax.set_title("(f) rough ball (BEM fit) over the smooth\nMindlin-Deresiewicz branch slope", fontsize=9)
    ax.legend(fontsize=7.5, ncol=2)
    ax.grid(alpha=0.3)
    r0 = records[0]
    doms = ", ".join(f"{m} {r['size'] * 1e6:g} \u00b5m" for m in mats
                     for r in [next(q for q in records if q["material"] == m)])
    fig.suptitle(f"Paper F: polymer ball (R = 5 mm) on a Si wafer, measured ball roughness ({TOPOGRAPHY} flattened, "
                 f"scaled to Table 2 rms); free boundary, {r0['n']}\u00b2 cells on {doms}; "
                 f"{r0['steps_per_cycle']} steps per cycle", fontsize=10)
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=110)
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    return atomic_write_bytes(path, buf.getvalue())


def plot_maps(records, path) -> Path | None:
    """Pressure at F_x = 0 (start) and |q|/(mu p) at the steps nearest A, B, C of the last
    rising branch, one row per case (Paper F Figs. 7, 8, 10, 11), zoomed on the contact."""
    import io

    from matplotlib.colors import LogNorm
    from matplotlib.figure import Figure

    from tribobem.output.atomic import atomic_write_bytes

    rows = []
    for r in records:
        f = Path(r["result_folder"]) / "maps.npz"
        if f.is_file():
            with np.load(f) as z:
                rows.append((r, {k: z[k] for k in z.files}))
    if not rows:
        return None
    fig = Figure(figsize=(12, 2.7 * len(rows) + 0.6), layout="constrained")
    axs = np.atleast_2d(fig.subplots(len(rows), 4))
    for i, (r, mp) in enumerate(rows):
        p = mp["pressure_start"]
        n = p.shape[0]
        half = r["size"] / 2 * 1e6
        x = (np.arange(n) + 0.5) / n * r["size"] * 1e6 - half
        contact = p > 0
        idx = np.argwhere(contact)
        pad = 3
        lo, hi = (np.maximum(idx.min(0) - pad, 0), np.minimum(idx.max(0) + pad, n - 1)) if idx.size else ((0, 0), (n - 1, n - 1))
        ext = [x[lo[0]] - 0.5 * r["dx"] * 1e6, x[hi[0]] + 0.5 * r["dx"] * 1e6,
               x[lo[1]] - 0.5 * r["dx"] * 1e6, x[hi[1]] + 0.5 * r["dx"] * 1e6]
        sub = (slice(lo[0], hi[0] + 1), slice(lo[1], hi[1] + 1))
        pm = np.where(contact, p, np.nan)[sub]
        ax = axs[i, 0]
        im = ax.imshow(pm.T / 1e6, origin="lower", extent=ext, cmap="viridis",
                       norm=LogNorm(vmin=max(np.nanmin(pm) / 1e6, np.nanmax(pm) / 1e9), vmax=np.nanmax(pm) / 1e6)
                       if np.isfinite(pm).any() else None)
        fig.colorbar(im, ax=ax, shrink=0.85, label="p (MPa)")
        ax.set_title(f"{r['material']} {r['load_mN']} mN: pressure at F_x = 0", fontsize=8)
        ax.set_ylabel("y (\u00b5m)", fontsize=8)
        for j, pt in enumerate(("A", "B", "C")):
            ax = axs[i, j + 1]
            key = f"shear_ratio_{pt}"
            if key not in mp:
                ax.set_axis_off()
                continue
            im = ax.imshow(mp[key][sub].T, origin="lower", extent=ext, cmap="coolwarm", vmin=0.0, vmax=1.0)
            st = mp[f"stick_{pt}"][sub]
            if st.any():
                ax.contour(x[sub[0]], x[sub[1]], st.T.astype(float), levels=[0.5], colors="k", linewidths=0.6)
            ncont = np.count_nonzero(np.isfinite(mp[key]))
            ratio = np.count_nonzero(mp[f"stick_{pt}"]) / ncont if ncont else math.nan
            ax.set_title(f"{pt}: F_x = {float(mp[f'force_{pt}']) * 1e3:.3g} mN, stick {ratio:.0%} of contact",
                         fontsize=8)
            if j == 2:
                fig.colorbar(im, ax=ax, shrink=0.85, label="|q| / (\u03bc p)")
        for ax in axs[i]:
            ax.tick_params(labelsize=7)
            ax.set_aspect("equal")
    fig.suptitle("Paper F: contact pressure at F_x = 0 and normalised shear |q|/(\u03bc p) at the steps nearest "
                 "A, B, C of the last rising branch (1 = slip; black lines: stick-zone edges)", fontsize=10)
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=100)
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    return atomic_write_bytes(path, buf.getvalue())
