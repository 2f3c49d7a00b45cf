"""Two-scale burls against whole-burl solves: the normal contact of a rough burl.

The validation burls fit one grid at asperity resolution (10 nm cells: 1024^2 for a 3 um top,
2048^2 for a 6 um top; SiC burl on a Si wafer, Gaussian roughness of 1.5 nm rms and 50 nm
correlation length on the wafer, about 53 MPa over the flat top).  Each is solved

* whole: the burl with its roughness on the whole grid (NormCG, free boundary), for several
  roughness realisations (their scatter is the reference's own uncertainty);
* two-scale: periodic micro windows of the same roughness statistics at the SAME cells (so that
  both sides resolve the same asperities) give the interface law; the burl's shape is solved at
  macro cells with it (:mod:`tribobem.two_scale`).

Compared: the approach of the mean planes (the whole grid's approach less the offset that made
its gap start at 0; the two-scale approach is measured from the mean planes by construction)
and the real contact area.  The approach is judged against the rms roughness, not against
itself: it is a difference of the burl's elastic displacement and the interface's mean gap
(a few nm each), and its zero is the mean planes' touching position, so its relative error has
no meaning.

Usage::

    python -m studies.two_scale --whole --out results/two_scale        # the whole-burl references (minutes)
    python -m studies.two_scale --convergence --out results/two_scale  # window, cells, realisations, macro
    python -m studies.two_scale --quick                                 # 512^2, one realisation (seconds)
    python -m studies.two_scale --real                                  # the 300 um burl, window cells 10-1.25 nm
    python -m studies.two_scale --whole-slip --out results/two_scale   # whole-burl ramps (2 min per 1024^2)
    python -m studies.two_scale --whole-loop --out results/two_scale   # whole-burl friction loops
    python -m studies.two_scale --whole-humid --out results/two_scale  # whole-burl ramps at RH 0.5
    python -m studies.two_scale --real-chain                           # the 300 um burl: normal, ramp, loop

The whole-burl numbers are committed in :data:`tribobem.validation.two_scale.WHOLE_BURLS`
(``--whole`` prints them in that form); ``tribobem validate --physics two_scale`` computes only
the two-scale side against them.
"""

from __future__ import annotations

import argparse
import json
import time
import warnings
from pathlib import Path

from tribobem.elasticity import free_boundary_operator
from tribobem.errors import ConvergenceWarning
from tribobem.geometry.rough import gaussian_surface
from tribobem.geometry.shapes import burl
from tribobem.grid import Grid
from tribobem.solvers.normal import solve_normal
from tribobem.validation.two_scale import (BURLS, CORRELATION, LOOP_AMPLITUDE, LOOP_STEPS, PAIR, RMS,
                                          two_scale_burl)

#: Seeds of the whole-burl roughness realisations (the windows use 0, 1, 2, ...).
WHOLE_SEEDS = (100, 101, 102, 103)

#: The real-size burl's scenario (300 um top, 0.3 N) and the window cells of its study.
REAL_SCENARIO = Path(__file__).resolve().parents[1] / "examples" / "studies" / "two_scale_real_burl.toml"
REAL_WINDOW_CELLS = (100, 200, 400, 800)


_REAL_CHILD = """
import json, resource, sys, time, tomllib, warnings
warnings.simplefilter("ignore")
from tribobem.scenario import parse_scenario, run_scenario
d = tomllib.load(open(sys.argv[1], "rb"))
d["two_scale"]["window_n"] = int(sys.argv[2])
d["two_scale"]["cache"] = False
t = time.process_time()
r = run_scenario(parse_scenario(d), outdir=None, progress=False, warn=False)
s = r.summary
st, ts = s["steps"][0], s["two_scale"]
print(json.dumps({"window_n": int(sys.argv[2]), "cpu_s": time.process_time() - t,
                  "peak_rss_gb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1e6,
                  "converged": s["converged"], "approach": st["approach"], "contact_area": st["contact_area"],
                  "nominal_contact_area": st["nominal_contact_area"], "max_pressure": st["max_pressure"],
                  "max_nominal_pressure": st["max_nominal_pressure"], "patch_cells": ts["window_patch_cells"],
                  "window_over_pressure_length": ts["window_over_pressure_length"],
                  "rms_slope": s["problem"]["roughness"]["body1"]["rms_slope"], "warnings": s["warnings"]}))
"""


_CHAIN_CHILD = """
import json, os, resource, sys, tempfile, time, tomllib, warnings
warnings.simplefilter("ignore")
os.environ["TRIBOBEM_CACHE"] = tempfile.mkdtemp()  # the chain's stages share their tables, nothing before
from tribobem.scenario import parse_scenario, run_scenario
d = tomllib.load(open(sys.argv[1], "rb"))
d["two_scale"]["window_n"] = int(sys.argv[2])
out = {"window_n": int(sys.argv[2])}
t0 = time.process_time()
stages = {"normal": {}, "pulloff": {"kind": "pulloff", "load": {"preload": d["load"]["force"], "refine": 4}},
          "ramp": {"kind": "partial_slip", "friction": {"coefficient": 0.2, "tangential_forces": "auto"}},
          "hysteresis": {"kind": "hysteresis", "friction": {"coefficient": 0.2, "path": {
              "control": "force", "amplitude": 0.9, "cycles": 1, "steps": 24}}}}
rh = None if sys.argv[3] == "dry" else float(sys.argv[3])
out["rh"] = rh
for name, change in stages.items():
    if name == "pulloff" and rh is None:
        continue  # dry and without adhesion: nothing pulls
    sc = dict(d, **change)
    if rh is not None and name != "normal":  # the normal kind is dry; the humid ramp's first state is not
        sc["body1"] = dict(sc["body1"], film={"isotherm": "Si"})
        sc["body2"] = dict(sc["body2"], film={"isotherm": "SiO2"})
        sc["humidity"] = {"rh": rh, "van_der_waals": False}
    t = time.process_time()
    s = run_scenario(parse_scenario(sc), outdir=None, progress=False, warn=False).summary
    r = {"cpu_s": time.process_time() - t, "converged": s["converged"], "warnings": s["warnings"]}
    if name == "normal":
        st = s["steps"][0]
        r.update(approach=st["approach"], contact_area=st["contact_area"], max_pressure=st["max_pressure"],
                 nominal_contact_area=st["nominal_contact_area"])
    elif name == "pulloff":
        r.update(pull_off_force=s["pull_off_force"][0], strength=s["two_scale"]["strength"])
    elif name == "ramp":
        r.update(static_friction_force=s["static_friction_force"], d50=s["displacement_at_half_static_friction"],
                 d90=s["displacement_at_0p9_static_friction"], presliding=s["presliding_displacement"],
                 repulsive_force=s.get("repulsive_force"), capillary_force=s.get("capillary_force"),
                 wetted_area=s.get("wetted_area"))
    else:
        r.update(dissipated_energy=s["dissipated_energy"][0],
                 lateral_stiffness={k["point"]: k["stiffness"] for k in s["lateral_stiffness"]})
    out[name] = r
out["cpu_s"] = time.process_time() - t0
out["peak_rss_gb"] = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1e6
print(json.dumps(out))
"""


def real_chain(window_n: int = 400, rh: float | None = None) -> dict:
    """The real-size burl's chain (normal at 0.3 N, pull-off from it at ``rh``, ramp to gross slip,
    one friction loop at 0.9 of the static friction; the pull-off, the ramp and the loop at ``rh``
    with Si and SiO2 films, or dry without a pull-off) in one
    fresh process with an empty table cache: CPU time and peak memory of the whole chain."""
    import subprocess
    import sys

    out = subprocess.run([sys.executable, "-c", _CHAIN_CHILD, str(REAL_SCENARIO), str(window_n),
                          "dry" if rh is None else str(rh)], check=True, capture_output=True, text=True)
    return json.loads(out.stdout.strip().splitlines()[-1])


def real_burl(window_n: int) -> dict:
    """The real-size burl with windows of ``window_n`` cells, in a fresh process (its CPU time and
    peak memory are its own)."""
    import subprocess
    import sys

    out = subprocess.run([sys.executable, "-c", _REAL_CHILD, str(REAL_SCENARIO), str(window_n)], check=True,
                         capture_output=True, text=True)
    return json.loads(out.stdout.strip().splitlines()[-1])


def whole_burl(name: str, seed: int, n: int | None = None) -> dict:
    """The whole-grid solve of validation burl ``name`` with roughness realisation ``seed``."""
    b = BURLS[name]
    n = b["n"] if n is None else n
    grid = Grid(n, n, b["size"], b["size"])
    topo = gaussian_surface(grid, RMS, CORRELATION, seed=seed)
    H = burl(grid, b["radius"], b["edge_radius"]) - topo
    offset = -float(H.min())
    t = time.process_time()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ConvergenceWarning)
        res = solve_normal(free_boundary_operator(grid, PAIR), H + offset, force=b["force"], tol=1e-8)
    return {"burl": name, "n": n, "seed": seed, "approach": res.approach - offset, "contact_area": res.contact_area,
            "max_pressure": res.max_pressure, "converged": bool(res.converged), "cpu_s": time.process_time() - t}


def _small_burl_scenario(kind: str, n: int, seed: int, friction: dict) -> dict:
    """The whole small burl as a scenario of ``kind`` on ``n``^2 cells, roughness seed ``seed``."""
    b = BURLS["small"]
    return {"kind": kind, "grid": {"n": n, "size": b["size"]},
            "body1": {"E": PAIR.body1.E, "nu": PAIR.body1.nu,
                      "roughness": {"kind": "gaussian", "rms": RMS, "correlation_length": CORRELATION, "seed": seed}},
            "body2": {"E": PAIR.body2.E, "nu": PAIR.body2.nu,
                      "shape": {"kind": "burl", "radius": b["radius"], "edge_radius": b["edge_radius"]}},
            "load": {"force": b["force"]}, "friction": friction}


def whole_burl_slip(n: int, seed: int) -> dict:
    """The whole small burl's partial-slip ramp (``tangential_forces = "auto"``, mu = 0.2, the coupled
    dissimilar pair) on ``n``^2 cells, roughness seed ``seed``: static friction and the tangential
    displacement at 0.5 and 0.9 of it."""
    from tribobem.scenario import parse_scenario, run_scenario
    from tribobem.validation.two_scale import MU

    sc = _small_burl_scenario("partial_slip", n, seed, {"coefficient": MU, "tangential_forces": "auto"})
    t = time.process_time()
    s = run_scenario(parse_scenario(sc), outdir=None, progress=False, warn=False).summary
    fx = [r["tangential_force_x"] for r in s["steps"]]
    dx = [r["displacement_x"] for r in s["steps"]]
    fs = s["static_friction_force"]
    import numpy as np

    return {"n": n, "seed": seed, "static_friction_force": fs, "static_friction_ratio": s["static_friction_ratio"],
            "d50": float(np.interp(0.5 * fs, fx, dx)), "d90": float(np.interp(0.9 * fs, fx, dx)),
            "presliding_displacement": s["presliding_displacement"], "cpu_s": time.process_time() - t}


def whole_burl_loop(n: int, seed: int, amplitude: float = LOOP_AMPLITUDE, steps: int = LOOP_STEPS) -> dict:
    """The whole small burl's friction loop (``kind = "hysteresis"``, force path 0 -> +F* -> -F* ->
    +F* with F* = ``amplitude`` mu F0+, one cycle, mu = 0.2, the coupled dissimilar pair) on ``n``^2
    cells, roughness seed ``seed``: the loop energy, K_L at A, B, C and the loop itself."""
    from tribobem.scenario import parse_scenario, run_scenario
    from tribobem.validation.two_scale import MU

    sc = _small_burl_scenario("hysteresis", n, seed, {"coefficient": MU, "path": {
        "control": "force", "amplitude": amplitude, "cycles": 1, "steps": steps}})
    t = time.process_time()
    s = run_scenario(parse_scenario(sc), outdir=None, progress=False, warn=False).summary
    return {"n": n, "seed": seed, "amplitude": amplitude, "steps": steps, "converged": s["converged"],
            "peak_force": s["peak_force"], "dissipated_energy": s["dissipated_energy"][0],
            "lateral_stiffness": {r["point"]: r["stiffness"] for r in s["lateral_stiffness"]},
            "loop": {"force": [r["tangential_force_x"] for r in s["steps"]],
                     "displacement": [r["displacement_x"] for r in s["steps"]],
                     "branch": [r["branch"] for r in s["steps"]]},
            "cpu_s": time.process_time() - t}


def whole_burl_humid(n: int, seed: int, rh: float = 0.5) -> dict:
    """The whole small burl's humid ramp at ``rh`` (Si and SiO2 films, meniscus forces without van
    der Waals, mu = 0.2, ``tangential_forces = "auto"``) on ``n``^2 cells, roughness seed
    ``seed``: static friction, F0+ and the meniscus force at zero tangential load, and the
    tangential displacement at 0.5 and 0.9 of the static friction."""
    import numpy as np

    from tribobem.scenario import parse_scenario, run_scenario
    from tribobem.validation.two_scale import MU

    sc = _small_burl_scenario("partial_slip", n, seed, {"coefficient": MU, "tangential_forces": "auto", "slip": "total"})
    sc["body1"]["film"] = {"isotherm": "Si"}
    sc["body2"]["film"] = {"isotherm": "SiO2"}
    sc["humidity"] = {"rh": [rh], "van_der_waals": False}
    t = time.process_time()
    s = run_scenario(parse_scenario(sc), outdir=None, progress=False, warn=False).summary
    rows = [r for r in s["steps"] if r.get("rh") == rh]
    fx = [r["tangential_force_x"] for r in rows]
    dx = [r["displacement_x"] for r in rows]
    fs = s["static_friction_force"][0]
    return {"n": n, "seed": seed, "rh": rh, "static_friction_force": fs, "repulsive_force": rows[0]["repulsive_force"],
            "capillary_force": rows[0]["capillary_force"], "wetted_area": rows[0].get("wetted_area"),
            "contact_area": rows[0]["contact_area"], "d50": float(np.interp(0.5 * fs, fx, dx)) - dx[0],
            "d90": float(np.interp(0.9 * fs, fx, dx)) - dx[0], "converged": s["converged"],
            "cpu_s": time.process_time() - t}


def whole_burl_pulloff(n: int, seed: int, rh: float | None = 0.5, steps: int = 40) -> dict:
    """The whole small burl's pull-off from the validation force (``kind = "pulloff"``) on ``n``^2
    cells, roughness seed ``seed``: at ``rh`` with Si and SiO2 films and meniscus forces without van
    der Waals, or (``rh`` None) dry with Dugdale adhesion (:data:`tribobem.validation.two_scale.
    DUGDALE`).  The pull-off force and approach, the unloading curve."""
    from tribobem.scenario import parse_scenario, run_scenario
    from tribobem.validation.two_scale import DUGDALE

    sc = _small_burl_scenario("pulloff", n, seed, {"coefficient": 0.0})
    del sc["friction"]
    sc["load"] = {"preload": BURLS["small"]["force"], "steps": steps, "refine": 4}
    if rh is None:
        sc["adhesion"] = dict(DUGDALE)
    else:
        sc["body1"]["film"] = {"isotherm": "Si"}
        sc["body2"]["film"] = {"isotherm": "SiO2"}
        sc["humidity"] = {"rh": [rh], "van_der_waals": False}
    t = time.process_time()
    s = run_scenario(parse_scenario(sc), outdir=None, progress=False, warn=False).summary
    po = s["pull_off_force"][0] if isinstance(s["pull_off_force"], list) else s["pull_off_force"]
    pa = s["pull_off_approach"][0] if isinstance(s["pull_off_approach"], list) else s["pull_off_approach"]
    return {"n": n, "seed": seed, "rh": rh, "pull_off_force": po, "pull_off_approach": pa,
            "converged": s["converged"], "cpu_s": time.process_time() - t,
            "curve": {"approach": [r.get("approach") for r in s["steps"]],
                      "force": [r.get("normal_force") for r in s["steps"]]}}


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--whole", action="store_true", help="compute the whole-burl references")
    ap.add_argument("--convergence", action="store_true", help="the two-scale convergence study")
    ap.add_argument("--quick", action="store_true", help="512^2 and one realisation")
    ap.add_argument("--real", action="store_true", help="the 300 um burl at four window resolutions")
    ap.add_argument("--whole-slip", action="store_true", help="whole-burl partial-slip ramps (512^2 and 1024^2)")
    ap.add_argument("--whole-loop", action="store_true", help="whole-burl friction loops (512^2 and 1024^2)")
    ap.add_argument("--whole-humid", action="store_true", help="whole-burl humid ramps at RH 0.5 (512^2, 1024^2)")
    ap.add_argument("--whole-pulloff", action="store_true",
                    help="whole-burl pull-off at RH 0.5 (512^2, 1024^2) and with Dugdale adhesion (512^2, 4 seeds)")
    ap.add_argument("--real-chain", action="store_true", help="the 300 um burl's normal, ramp and loop chain")
    ap.add_argument("--humid-only", action="store_true", help="with --real-chain: the chain at RH 0.5 only")
    ap.add_argument("--out", default="results/two_scale", help="folder for the JSON records")
    args = ap.parse_args(argv)
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    if args.quick:
        w = whole_burl("small", WHOLE_SEEDS[0], n=512)
        t = two_scale_burl("small", window_n=50)
        print(json.dumps({"whole": w, "two_scale": t}, indent=1))
        return 0
    if args.whole_slip:
        rows = [whole_burl_slip(512, 100)] + [whole_burl_slip(1024, seed) for seed in WHOLE_SEEDS[:2]]
        for r in rows:
            print(json.dumps(r), flush=True)
        (out / "whole_slip.json").write_text(json.dumps(rows, indent=1))
    if args.whole_loop:
        rows = []
        for n, seed in ((512, 100), (1024, 100), (1024, 101)):
            r = whole_burl_loop(n, seed)
            rows.append(r)
            print(json.dumps(r), flush=True)
        (out / "whole_loop.json").write_text(json.dumps(rows, indent=1))
    if args.whole_humid:
        rows = []
        for n, seed in ((512, 100), (512, 101), (1024, 100), (1024, 101)):
            r = whole_burl_humid(n, seed)
            rows.append(r)
            print(json.dumps(r), flush=True)
        (out / "whole_humid.json").write_text(json.dumps(rows, indent=1))
    if args.whole_pulloff:
        rows = []
        for n, seed, rh in ((512, 100, 0.5), (512, 101, 0.5), *((512, sd, None) for sd in WHOLE_SEEDS),
                            (1024, 100, 0.5)):
            r = whole_burl_pulloff(n, seed, rh)
            rows.append(r)
            print(json.dumps({k: v for k, v in r.items() if k != "curve"}), flush=True)
            (out / "whole_pulloff.json").write_text(json.dumps(rows, indent=1))
    if args.real_chain:
        rows = [real_chain(rh=0.5)] if args.humid_only else [real_chain(), real_chain(rh=0.5)]
        for r in rows:
            print(json.dumps(r), flush=True)
        (out / "real_chain.json").write_text(json.dumps(rows, indent=1))
    if args.real:
        rows = []
        for n in REAL_WINDOW_CELLS:
            r = real_burl(n)
            rows.append(r)
            print(json.dumps(r), flush=True)
        (out / "real.json").write_text(json.dumps(rows, indent=1))
    if args.whole:
        rows = []
        for name in BURLS:
            for seed in WHOLE_SEEDS:
                r = whole_burl(name, seed)
                rows.append(r)
                print(json.dumps(r), flush=True)
        (out / "whole.json").write_text(json.dumps(rows, indent=1))
        print("\nWHOLE_BURLS = {")
        for name in BURLS:
            mine = [r for r in rows if r["burl"] == name]
            approach = [round(r["approach"], 15) for r in mine]
            area = [float(format(r["contact_area"], ".6e")) for r in mine]
            print(f'    "{name}": {{"approach": {approach}, "contact_area": {area}}},')
        print("}")
    if args.convergence:
        rows = []
        for name in BURLS:
            for label, kw in [("base", {}), ("window 0.5 um", {"window": 0.5e-6}), ("window 2 um", {"window": 2e-6}),
                              ("1 realisation", {"realisations": 1}), ("8 realisations", {"realisations": 8}),
                              ("macro 64^2", {"macro_n": 64}), ("macro 256^2", {"macro_n": 256}),
                              ("window cells x2 (5 nm)", {"cells_factor": 2}),
                              ("16 pressures", {"pressures": 16}), ("64 pressures", {"pressures": 64})]:
                r = two_scale_burl(name, **kw)
                r.update({"burl": name, "variant": label})
                rows.append(r)
                print(json.dumps(r), flush=True)
        (out / "convergence.json").write_text(json.dumps(rows, indent=1))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
