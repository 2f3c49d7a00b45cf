"""Paper C: colloidal-probe pull-off on Si and SiO2 flats, humid (35 % RH) and in vacuum,
spot by spot (mean and spread, like Paper C Fig. 5), as a resumable sweep of ``pulloff`` runs.

Set-up (Paper C sections 3-4) and what stands in for what we do not have:

* probe: a SiO2 sphere (E = 64 GPa, nu = 0.17) of radius R = 2.5 um: Paper C's "5 um probe" is
  read as a diameter (a 5 um radius would double every smooth-sphere reference); it is smooth
  here (Paper C measured its roughness before and after the tests; we have no such scan);
* flats: Si(100) (E = 130 GPa, nu = 0.28) and SiO2 (64 GPa, 0.17), both with Dugdale adhesion
  of dgamma = 88 mJ/m^2 (= 2 gamma_SiO2, Paper C: a native oxide on Si) and z0 = 0.3 nm (the
  middle of the thesis' 0.2-0.4 nm; Paper C gives no value);
* topography: Paper C's own 2 x 2 um scans are not available; the Park Systems AFM scan
  ``example_ps.tiff`` (1 x 1 um, 512^2, the instrument family of Paper C) stands in for both,
  its best plane removed and scaled as a whole to Paper C's rms, 0.46 nm (Si) and 0.74 nm
  (SiO2).  The same scan scaled twice: the two flats differ by their rms (and E), not by their
  texture;
* spots: five non-overlapping 1/3 um windows of the scan (the corners and the centre, as
  :func:`studies.afm_pulloff.spot_origins` places them), each on the scan's own
  170^2 pixels (1.95 nm), free boundary, under the probe's apex.  Each keeps its own rms (the
  scan's scale factor times its own rms);
* humid state: 35 % RH at 295 K, water films from the shipped isotherms (0.90 nm on
  SiO2, 0.60 nm on Si at 35 %; the probe is SiO2), equilibrium levelling, the capillary
  pressure times Paper C's contribution coefficient (0.17 at 35 % RH), water-solid van der
  Waals with the default Hamaker constants (Si 19e-20 J, SiO2 6.5e-20 J, water 3.7e-20 J);
* vacuum: Paper C models it as 1-2 % RH without water: the dry Dugdale pull-off (no films, no
  menisci; the contribution coefficient is 0 there anyway);
* pull-off: unloading from Paper C's 100 nN set-point under displacement control, the most
  tensile force of the curve (with [humidity]: the menisci recomputed at every step).
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from tribobem.data import topography_path

__all__ = ["PARK_SCAN", "SUBSTRATES", "sweep_spec", "gather", "summary_table", "plot_study", "spot_windows"]

#: The stand-in topography (see the module docstring): the measured scan shipped with tribobem
#: (:func:`tribobem.data.topography_path`; ``$TRIBOBEM_DATA_DIR`` replaces its folder).
PARK_SCAN = topography_path("example_ps.tiff", must_exist=False)
#: substrate -> (E, nu, rms of Paper C, isotherm, Hamaker constant)
SUBSTRATES = {
    "Si": ("130 GPa", 0.28, 0.46e-9, "Si", "19e-20 J"),
    "SiO2": ("64 GPa", 0.17, 0.74e-9, "SiO2", "6.5e-20 J"),
}
RADIUS = 2.5e-6
DGAMMA = 0.088
Z0 = 0.3e-9
PRELOAD = 100e-9
RH_AMBIENT = 0.35
N_SPOTS = 5


def spot_windows(path=PARK_SCAN, n_spots: int = N_SPOTS, window_cells: int | None = None) -> dict:
    """The spots: window origins and sizes (m) on the scan, the scan's plane-removed rms and the
    windows' own rms after the same processing as the scenario (plane removed from the whole
    scan, then cropped; mean removed).

    Returns
    -------
    dict
        ``spots`` (list of ``{"x0", "y0", "lx", "ly", "rms"}``, m), ``scan_rms`` (m), ``dx`` (m),
        ``cells`` (window side in cells), ``path``.
    """
    from tribobem.geometry import read_topography
    from .afm_pulloff import spot_origins

    topo = read_topography(path, detrend="height")
    g = topo.grid
    k = math.ceil(math.sqrt(n_spots))
    w = window_cells or min(g.nx, g.ny) // k
    spots = []
    for ix0, iy0 in spot_origins(g.shape, (w, w), n_spots):
        h = topo.window(int(ix0), int(iy0), w, w).heights
        spots.append({"x0": ix0 * g.dx, "y0": iy0 * g.dy, "lx": w * g.dx, "ly": w * g.dy,
                      "rms": float(np.std(h - h.mean()))})
    return {"spots": spots, "scan_rms": float(np.std(topo.heights - topo.heights.mean())), "dx": g.dx,
            "cells": w, "path": str(path)}


def _scenario(substrate: str, path, humid: bool, quick: bool) -> dict:
    E, nu, _, iso, ham = SUBSTRATES[substrate]
    scn = {
        "kind": "pulloff",
        "name": f"{substrate} {'35 % RH' if humid else 'vacuum'}",
        "grid": {"n": 48 if quick else 170, "periodic": False},
        "body1": {"name": f"{substrate} flat", "E": E, "nu": nu,
                  "roughness": {"kind": "file", "path": str(path), "detrend": "height",
                                "crop": {"x0": 0.0, "y0": 0.0, "lx": "0.33203125 um", "ly": "0.33203125 um"},
                                "rms": "0.5 nm"}},
        "body2": {"name": "SiO2 probe", "E": "64 GPa", "nu": 0.17,
                  "shape": {"kind": "sphere", "radius": f"{RADIUS * 1e6:g} um"}},
        "adhesion": {"model": "dugdale", "work_of_adhesion": f"{DGAMMA * 1e3:g} mJ/m^2", "z0": f"{Z0 * 1e9:g} nm"},
        "load": {"preload": f"{PRELOAD * 1e9:g} nN", "steps": 12 if quick else 24, "refine": 3 if quick else 5,
                 "loading": False},
        "solver": {"tolerance": 1e-9},
        "output": {"fields": "last", "figures": False, "report": False},
    }
    if humid:
        scn["body1"].update(film={"isotherm": iso}, hamaker=ham)
        scn["body2"].update(film={"isotherm": "SiO2"}, hamaker="6.5e-20 J")
        scn["humidity"] = {"rh": [RH_AMBIENT], "temperature": "295 K", "contribution": "linear_30_60"}
    return scn


def sweep_spec(path=PARK_SCAN, quick: bool = False) -> dict:
    """The study's sweep: Si and SiO2, humid and vacuum, at every spot (20 points; ``quick``:
    two spots resampled to 48^2, 8 points).

    The spot's ``crop`` and ``rms`` (the scan's scale factor to Paper C's rms times the window's
    own rms) are point overrides; the point's ``name`` says substrate, state and spot.
    """
    try:  # the sweep package exports it as flatten (formerly _flatten)
        from tribobem.sweep import flatten as _flatten
    except ImportError:
        from tribobem.sweep import _flatten

    sw = spot_windows(path, 2 if quick else N_SPOTS)
    base = _scenario("Si", path, False, quick)
    flat_base = _flatten(base)
    points = []
    for substrate, (_, _, rms, _, _) in SUBSTRATES.items():
        factor = rms / sw["scan_rms"]
        for humid in (True, False):
            for k, sp in enumerate(sw["spots"]):
                scn = _scenario(substrate, path, humid, quick)
                scn["name"] = f"{scn['name']}, spot {k + 1}"
                scn["body1"]["roughness"].update(
                    crop={"x0": f"{sp['x0'] * 1e9:.6f} nm", "y0": f"{sp['y0'] * 1e9:.6f} nm",
                          "lx": f"{sp['lx'] * 1e9:.6f} nm", "ly": f"{sp['ly'] * 1e9:.6f} nm"},
                    rms=f"{factor * sp['rms'] * 1e9:.6f} nm")
                # the point: the keys that differ from the base (Si, vacuum), dotted
                points.append({k2: v for k2, v in _flatten(scn).items() if flat_base.get(k2, object()) != v})
    return {"name": "paper-c" + ("-quick" if quick else ""),
            "description": "Paper C: colloidal-probe pull-off on Si and SiO2, 35 % RH and vacuum, per spot",
            "base": base, "keep_runs": True, "scheduler": "synchronous",
            "outputs": ["pull_off_force", "converged"], "points": points}


def gather(spec, outdir):
    """One row per point: ``substrate``, ``state`` ("35 % RH" | "vacuum"), ``spot``, ``rms``
    (m, of the window), ``pull_off_force`` (N), ``capillary_force``, ``solid_solid_force``,
    ``water_solid_force`` at pull-off (humid), ``contact_area`` at pull-off (m^2), ``film1``,
    ``film2`` (m), ``converged``, ``elapsed`` (s), ``status``."""
    import json

    import pandas as pd

    from tribobem.scenario.schema import parse_scenario
    from tribobem.sweep import load_sweep, read_points

    spec = load_sweep(spec)
    outdir = Path(outdir)
    records = read_points(outdir)
    rows = []
    for h, o in spec.tasks():
        sc = parse_scenario(spec.scenario_for(o))
        name = sc.name or ""
        substrate = name.split()[0]
        state = "35 % RH" if sc.humidity is not None else "vacuum"
        spot = int(name.rsplit("spot", 1)[-1]) if "spot" in name else 0
        rec = records.get(h) or {}
        row = {"substrate": substrate, "state": state, "spot": spot, "rms": float(sc.body1.roughness.rms),
               "status": rec.get("status", "missing"), "elapsed": rec.get("elapsed")}
        path = outdir / "runs" / h / "summary.json"
        summ = json.loads(path.read_text(encoding="utf-8")) if row["status"] == "ok" and path.exists() else None
        if summ:
            po = summ.get("pull_off_force")
            if isinstance(po, list):  # humid: one per RH (one RH here)
                st = summ["steps"][0]
                row.update(pull_off_force=po[0], capillary_force=st.get("capillary_force"),
                           solid_solid_force=st.get("solid_solid_force"),
                           water_solid_force=st.get("water_solid_force"), contact_area=st.get("contact_area"),
                           wetted_area=st.get("wetted_area"), film1=st.get("film_thickness_1"),
                           film2=st.get("film_thickness_2"), converged=bool(st.get("converged")))
            else:
                row.update(pull_off_force=po, converged=bool(summ.get("converged")))
            row["warnings"] = " | ".join(w.split(":")[0] for w in summ.get("warnings") or [])
        rows.append(row)
    return pd.DataFrame(rows)


def summary_table(table):
    """Mean and sample standard deviation (ddof = 1) of the pull-off per substrate and state
    (N), the number of spots, and the smooth-probe DMT and JKR references -2 pi R dgamma and
    -1.5 pi R dgamma."""
    import pandas as pd

    ok = table[table["status"] == "ok"]
    rows = []
    for (sub, state), g in ok.groupby(["substrate", "state"], sort=False):
        f = g["pull_off_force"].to_numpy(dtype=float)
        rows.append({"substrate": sub, "state": state, "n_spots": len(f), "mean": float(np.mean(f)),
                     "std": float(np.std(f, ddof=1)) if len(f) > 1 else 0.0, "min": float(np.min(f)),
                     "max": float(np.max(f)), "mean_rms": float(g["rms"].mean()),
                     "dmt": -2 * math.pi * RADIUS * DGAMMA, "jkr": -1.5 * math.pi * RADIUS * DGAMMA})
    return pd.DataFrame(rows)


def plot_study(table, path) -> Path:
    """Paper C Fig. 5 style: per substrate and state, the spots (points) and their mean +- one
    standard deviation (bars)."""
    import io

    from matplotlib.figure import Figure

    from tribobem.output.atomic import atomic_write_bytes

    summ = summary_table(table)
    fig = Figure(figsize=(7.5, 4.4), layout="constrained")
    ax = fig.add_subplot()
    colors = {"35 % RH": "#2b7bba", "vacuum": "#d62728"}
    xt, xl = [], []
    for i, sub in enumerate(SUBSTRATES):
        for j, state in enumerate(("35 % RH", "vacuum")):
            x = 2.2 * i + j
            g = table[(table["substrate"] == sub) & (table["state"] == state) & (table["status"] == "ok")]
            if g.empty:
                continue
            f = -1e9 * g["pull_off_force"].to_numpy(dtype=float)
            ax.plot(np.full(f.size, x) + np.linspace(-0.12, 0.12, f.size), f, "o", ms=4, color=colors[state],
                    alpha=0.5)
            s = summ[(summ["substrate"] == sub) & (summ["state"] == state)].iloc[0]
            ax.errorbar([x + 0.3], [-1e9 * s["mean"]], yerr=[1e9 * s["std"]], fmt="s", ms=7, capsize=5,
                        color=colors[state])
            xt.append(x + 0.1)
            xl.append(f"{sub}\n{state}")
    ax.set_xticks(xt, xl)
    ax.set_ylabel("pull-off force |F| (nN)")
    ax.set_title(f"Paper C: SiO2 probe R = {RADIUS * 1e6:g} um on the Park scan scaled to rms 0.46 nm (Si), "
                 "0.74 nm (SiO2)", fontsize=9)
    ax.set_ylim(bottom=0)
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=110)
    return atomic_write_bytes(path, buf.getvalue())
