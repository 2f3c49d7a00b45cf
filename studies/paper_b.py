"""Paper B section 4.2: capillary adhesion of a rough SiO2 surface against a rigid dry flat
against relative humidity, as a resumable sweep of ``capillary`` runs.

The interface (Paper B 4.2): an elastic SiO2 half-space (E = 64 GPa, nu = 0.17, the
thesis' Fig. 3.9 values) carrying a Gaussian rough surface (exponential ACF, Hu and Tonder;
:func:`tribobem.geometry.gaussian_surface`, whose correlation length is the lag where the ACF
falls to 10 %) on a periodic 10 x 10 um cell of 256^2 nodes, rms 5 nm, L_ac / L = 0.02, 0.05,
0.1 (L_ac = 0.2, 0.5, 1 um), pressed with F0 = 500 uN against a rigid, dry flat.  Only the
rough body adsorbs water (the shipped SiO2 isotherm, levelled to its equilibrium on the
undeformed surface, open system).  RH steps 0.1 ... 0.95 and 0.99.

Choices the paper leaves open (stated here and in the README):

* solid-solid adhesion: Dugdale with dgamma = 88 mJ/m^2 (Paper C's 2 gamma_SiO2, the thesis'
  own SiO2 value) and z0 = 0.3 nm (mid of the thesis' 0.2-0.4 nm), so sigma0 = 301 MPa and
  h0 = 0.29 nm.  On 39 nm cells this cohesive zone is not resolved (the gap changes by far more
  than h0 per cell; the run says so): F_ss is the grid's estimate, as in Paper B's own
  256^2 runs;
* Hamaker constants: SiO2 6.5e-20 J for both solids (the flat's material is not given),
  water 3.7e-20 J (defaults); critical distance 0.84 nm; contact angles 0;
* "uniform" films (Fig. 18) are compared with our default "equilibrium" levelling, not with
  Paper B's thin-film integration without disjoining pressure (which has no end state).

Fig. 18 with four levellings (:func:`film_levelling_comparison`, issue 21 item 3; L_ac/L =
0.05, 256^2, 500 uN; measured 2026-11-26 on the shared 2-core machine: 331 s CPU for the 12 RH of
the thin film, 5.5-6.4 s for each of the others, every film and state converged).  F_cap in uN;
"thin film" is the thin-film equation *with* the disjoining pressure (closed system) integrated
to its steady state, and uniform against it (|F_uniform| / |F| - 1):

======  =========  =========  ===========  ==================  ====================
RH      uniform    thin film  equilibrium  closed equilibrium  uniform / thin film
======  =========  =========  ===========  ==================  ====================
0.1     -27.7      -27.7      -27.7        -27.7               +0.00 %
0.2     -58.1      -57.7      -57.7        -57.7               +0.58 %
0.3     -82.9      -82.6      -82.6        -82.6               +0.30 %
0.4     -89.5      -89.5      -89.5        -89.5               +0.00 %
0.5     -90.3      -90.3      -90.3        -90.3               +0.00 %
0.6     -96.3      -96.2      -96.2        -96.2               +0.11 %
0.7     -119.7     -119.6     -119.6       -119.6              +0.06 %
0.8     -199.0     -198.5     -198.5       -198.5              +0.23 %
0.85    -319.5     -318.5     -318.5       -318.5              +0.31 %
0.9     -720.6     -721.9     -723.3       -721.9              -0.18 %
0.95    -685.3     -685.6     -685.6       -685.6              -0.03 %
0.99    -136.0     -136.0     -136.0       -136.0              +0.00 %
======  =========  =========  ===========  ==================  ====================

The thin film ends on the closed equilibrium (to the grid's Nyquist pressure mode, 4e-4 of the
mean thickness at RH 0.9), and its F_cap is the closed equilibrium's to 0.006 %.  Paper B's
finding (uniform more F_cap at low RH, less at higher RH, the same above 90 %) is *not*
reproduced in size: the signs follow it loosely (uniform 0-0.6 % more up to 0.85, 0.2-0.4 % less
at 0.9, equal at 0.95 and 0.99), but the differences are below 1 %, because every levelled film
with the disjoining pressure is nearly uniform on 39 nm cells (its healing length is 0.6-7 nm).
Paper B's levelling is the thin-film equation *without* disjoining pressure
(``levelling = "thin_film"``), whose films drain off the peaks into the valleys; on this surface
its pseudo-spectral integration does not finish (about 40 % of the nodes dry and the flux is not
positivity-preserving; see ``film_thickness`` Notes), so that curve is missing.

Cases (one sweep point each, labelled by the scenario ``name``): the three L_ac at 500 uN
(Fig. 13), rms 7.5 and 10 nm (the L_ac/L = 0.02 surface scaled, Fig. 16), three more
realisations of it (seeds 2-4, Fig. 15), 5000 uN on the three L_ac (Fig. 17c), uniform films on
the three L_ac (Fig. 18).  ``quick=True`` shrinks everything for a test (module constants).
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

__all__ = ["RH", "LAC_RATIOS", "base_scenario", "sweep_spec", "gather", "findings", "plot_study",
           "peak", "FINDINGS", "FIG18_LEVELLINGS", "film_levelling_comparison"]

#: Paper B 4.2 geometry and loads.
SIZE = 10e-6
N = 256
RMS = 5e-9
LAC_RATIOS = (0.02, 0.05, 0.1)
F0 = 500e-6
F0_HIGH = 5000e-6
#: Our choices for what Paper B does not give (module docstring).
DGAMMA = 0.088
Z0 = 0.3e-9
#: The RH steps (the peak region is sampled densely).
RH = (0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.85, 0.9, 0.95, 0.99)
#: Quick mode (tests): a 32^2 cell of 1.25 um (the same 39 nm cells), the force scaled by the area.
QUICK_N = 32
QUICK_SIZE = 1.25e-6
QUICK_RH = (0.5, 0.9, 0.99)

#: Paper B's findings, in the order of :func:`findings` (key, text).
FINDINGS = (
    ("rise_fall", "F_cap rises with RH, peaks near 90 % RH and falls towards 0 at 100 % (Fig. 13)"),
    ("lac_peak_rh", "longer L_ac moves the peak to lower RH (Fig. 13d)"),
    ("lac_peak_height", "longer L_ac raises the peak (Fig. 13d)"),
    ("rms", "lower rms gives a higher peak at lower RH (rms 5 / 7.5 / 10 nm, Fig. 16)"),
    ("realisations", "four realisations of the same statistics lie in a narrow band (Fig. 15)"),
    ("high_load", "at 5000 uN F_cap falls monotonically with RH (Fig. 17c)"),
    ("uniform", "uniform films give more F_cap at low RH, less at higher RH, the same above 90 % (Fig. 18)"),
    ("minor", "F_ss and F_ws are much smaller than F_cap and nearly flat in RH (Fig. 13a-c)"),
    ("merge", "islands merge into one meniscus near 90 % RH (Fig. 12)"),
)


def base_scenario(quick: bool = False) -> dict:
    """The base ``capillary`` scenario (L_ac/L = 0.02, rms 5 nm, seed 1, 500 uN)."""
    size = QUICK_SIZE if quick else SIZE
    n = QUICK_N if quick else N
    force = F0 * (size / SIZE) ** 2
    return {
        "kind": "capillary",
        "name": "lac 0.02",
        "description": "Paper B 4.2: rough elastic SiO2 against a rigid dry flat, F_cap against RH",
        "grid": {"n": n, "size": f"{size * 1e6:.6g} um", "periodic": True},
        "body1": {"name": "rough SiO2", "E": "64 GPa", "nu": 0.17,
                  "roughness": {"kind": "gaussian", "rms": f"{RMS * 1e9:g} nm",
                                "correlation_length": f"{LAC_RATIOS[0] * SIZE * 1e6:.6g} um", "seed": 1},
                  "film": {"isotherm": "SiO2"}, "hamaker": "6.5e-20 J"},
        "body2": {"name": "rigid dry flat", "rigid": True, "hamaker": "6.5e-20 J"},
        "load": {"force": f"{force * 1e6:.8g} uN"},
        "adhesion": {"model": "dugdale", "work_of_adhesion": f"{DGAMMA * 1e3:g} mJ/m^2", "z0": f"{Z0 * 1e9:g} nm"},
        "humidity": {"rh": list(QUICK_RH if quick else RH), "levelling": "equilibrium", "film_system": "open"},
        "output": {"fields": "last", "figures": False, "report": False},
    }


#: Fig. 18 comparison (:func:`film_levelling_comparison`): label -> ``[humidity]`` overrides.
#: "closed equilibrium" is the steady state of the thin-film equation *with* the disjoining
#: pressure, which "thin_film disjoining" integrates to it in time
#: (``film_thickness(mode="thin_film", disjoining=True)``, closed system); "thin_film" is the
#: scenario's ``levelling = "thin_film"``, Paper B's form without the disjoining pressure.
FIG18_LEVELLINGS = {
    "uniform": {"levelling": "uniform"},
    "thin_film disjoining": {"levelling": "thin_film", "film_system": "closed", "disjoining": True},
    "equilibrium": {"levelling": "equilibrium", "film_system": "open"},
    "closed equilibrium": {"levelling": "equilibrium", "film_system": "closed"},
    "thin_film": {"levelling": "thin_film"},
}


def film_levelling_comparison(levellings=("uniform", "thin_film disjoining", "equilibrium", "closed equilibrium"),
                              lac_ratio: float = 0.05, rh=RH, quick: bool = False, progress=None) -> list[dict]:
    """Paper B Fig. 18: F_cap against RH for differently levelled films on one surface.

    Runs one ``capillary`` scenario per levelling (:data:`FIG18_LEVELLINGS`) on the base
    surface of the study with ``L_ac / L = lac_ratio`` (500 uN, 256^2, rms 5 nm, seed 1).

    Parameters
    ----------
    levellings : sequence of str
        Keys of :data:`FIG18_LEVELLINGS`.  ``"thin_film disjoining"``: the thin-film equation
        (Paper B Eq. 8) with the disjoining pressure, closed system, integrated to its steady
        state (``[humidity] disjoining = true``).  ``"thin_film"`` (Paper B's Eq. 8 without
        disjoining pressure, integrated to 100 tau_slow) is not in the default: on this surface
        its films dry the peaks and the pseudo-spectral integration does not finish (module
        docstring).
    lac_ratio : float
        Correlation length over the cell side.
    rh : sequence of float
        Relative humidities (fractions).
    quick : bool
        The 32^2 test cell of :func:`base_scenario`.
    progress : callable, optional
        ``progress(label, rh, capillary_force)`` after every run.

    Returns
    -------
    list of dict
        One row per (levelling, RH): ``levelling``, ``rh``, ``capillary_force`` (N, < 0
        tensile), ``film_thickness`` (m, mean film), ``converged`` (the capillary solve and,
        for ``"thin_film disjoining"``, the film's integration to its steady state),
        ``elapsed`` (s of the run, wall clock, over its RH steps), ``cpu`` (s of CPU,
        ``time.process_time``, over its RH steps).
    """
    import time

    from tribobem.scenario.run import run_scenario

    rows = []
    for label in levellings:
        sc = base_scenario(quick)
        sc["name"] = f"fig18 {label} lac {lac_ratio:g}"
        # absolute L_ac of the full study, also in quick mode (as in the sweep)
        sc["body1"]["roughness"]["correlation_length"] = f"{lac_ratio * SIZE * 1e6:.6g} um"
        sc["humidity"] = {**sc["humidity"], "rh": [float(r) for r in rh], **FIG18_LEVELLINGS[label]}
        if "film_system" not in FIG18_LEVELLINGS[label]:
            sc["humidity"].pop("film_system", None)
        t0, c0 = time.perf_counter(), time.process_time()
        res = run_scenario(sc, progress=False, quiet=True)
        elapsed, cpu = time.perf_counter() - t0, time.process_time() - c0
        # a step's ``converged`` covers the capillary state and both films (for the thin film:
        # its integration reached the steady state)
        for st in res.summary["steps"]:
            rows.append({"levelling": label, "rh": st["rh"], "capillary_force": st["capillary_force"],
                         "film_thickness": st.get("film_thickness_1"), "converged": bool(st.get("converged")),
                         "elapsed": elapsed, "cpu": cpu})
            if progress is not None:
                progress(label, st["rh"], st["capillary_force"])
    return rows


def _cases(quick: bool) -> list[dict]:
    """Sweep points: dotted overrides of :func:`base_scenario`, each with its ``name``."""
    size = QUICK_SIZE if quick else SIZE
    f_high = F0_HIGH * (size / SIZE) ** 2
    lac = {r: f"{r * SIZE * 1e6:.6g} um" for r in LAC_RATIOS}  # absolute L_ac of the full study
    pts = []
    for r in LAC_RATIOS:
        pts.append({"name": f"lac {r:g}", "body1.roughness.correlation_length": lac[r]})
    if quick:
        pts.append({"name": "uniform lac 0.02", "humidity.levelling": "uniform"})
        pts.append({"name": "load 5000 uN lac 0.02", "load.force": f"{f_high * 1e6:.8g} uN"})
        return pts
    for rms in (7.5, 10.0):
        pts.append({"name": f"rms {rms:g} nm", "body1.roughness.rms": f"{rms:g} nm"})
    for seed in (2, 3, 4):
        pts.append({"name": f"seed {seed}", "body1.roughness.seed": seed})
    for r in LAC_RATIOS:
        pts.append({"name": f"load 5000 uN lac {r:g}", "body1.roughness.correlation_length": lac[r],
                    "load.force": f"{f_high * 1e6:.8g} uN"})
    for r in LAC_RATIOS:
        pts.append({"name": f"uniform lac {r:g}", "body1.roughness.correlation_length": lac[r],
                    "humidity.levelling": "uniform"})
    return pts


def sweep_spec(quick: bool = False) -> dict:
    """The study's sweep (a dict for :func:`tribobem.sweep.run_sweep`; the full one is also
    ``examples/studies/paper_b.toml``)."""
    return {"name": "paper-b" + ("-quick" if quick else ""),
            "description": "Paper B 4.2: F_cap against RH on rough SiO2 (L_ac, rms, realisations, load, films)",
            "base": base_scenario(quick), "keep_runs": True, "scheduler": "synchronous",
            "outputs": ["peak_capillary_force", "peak_capillary_rh", "converged"],
            "points": _cases(quick)}


def _read_json(path: Path):
    import json

    try:
        return json.loads(path.read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return None


def gather(spec, outdir):
    """One row per (case, RH) of a finished (or partial) sweep.

    Parameters
    ----------
    spec : dict, path or SweepSpec
        The sweep (:func:`sweep_spec` or ``examples/studies/paper_b.toml``).
    outdir : path
        Its results folder (``points/``, ``runs/<hash>/summary.json``).

    Returns
    -------
    pandas.DataFrame
        Columns ``case``, ``lac_ratio`` (L_ac / L of the full study's cell), ``rms`` (m),
        ``seed``, ``force`` (N, the applied load), ``levelling``, ``n``, ``size`` (m), ``rh``,
        ``capillary_force``, ``solid_solid_force``, ``water_solid_force``, ``adhesive_total``
        (their sum), ``repulsive_force`` (N), ``wetted_fraction`` and ``contact_fraction`` (of
        the nominal area), ``island_count``, ``kelvin_radius`` (m), ``film_thickness`` (m,
        mean film on the rough body), ``outer_iterations``, ``iterations``, ``converged``,
        ``elapsed`` (s per point), ``status``.  Points without a successful record give one
        row with NaN results.
    """
    import pandas as pd

    from tribobem.scenario.schema import parse_scenario
    from tribobem.sweep import load_sweep, read_points

    spec = load_sweep(spec)
    outdir = Path(outdir)
    records = read_points(outdir)
    rows = []
    for h, o in spec.tasks():
        sc = parse_scenario(spec.scenario_for(o))
        lx, ly = sc.grid.lengths
        info = {"case": sc.name, "lac_ratio": round(sc.body1.roughness.correlation_length / SIZE, 6),
                "rms": float(sc.body1.roughness.rms), "seed": sc.body1.roughness.seed,
                "force": float(sc.load.force), "levelling": sc.humidity.levelling, "n": sc.grid.shape[0],
                "size": lx}
        rec = records.get(h) or {}
        status = rec.get("status", "missing")
        summ = _read_json(outdir / "runs" / h / "summary.json") if status == "ok" else None
        if not summ:
            rows.append({**info, "rh": math.nan, "status": status})
            continue
        area = lx * ly
        for st in summ.get("steps", []):
            cap, ss, ws = (st.get(k) for k in ("capillary_force", "solid_solid_force", "water_solid_force"))
            rows.append({**info, "rh": st.get("rh"), "capillary_force": cap, "solid_solid_force": ss,
                         "water_solid_force": ws, "adhesive_total": cap + ss + ws,
                         "repulsive_force": st.get("repulsive_force"),
                         "wetted_fraction": st.get("wetted_area") / area,
                         "contact_fraction": st.get("contact_area") / area,
                         "island_count": st.get("island_count"), "kelvin_radius": st.get("kelvin_radius"),
                         "film_thickness": st.get("film_thickness_1"),
                         "outer_iterations": st.get("outer_iterations"), "iterations": st.get("iterations"),
                         "converged": bool(st.get("converged")), "elapsed": rec.get("elapsed"), "status": status})
    cols = ["case", "lac_ratio", "rms", "seed", "force", "levelling", "n", "size", "rh", "capillary_force",
            "solid_solid_force", "water_solid_force", "adhesive_total", "repulsive_force", "wetted_fraction",
            "contact_fraction", "island_count", "kelvin_radius", "film_thickness", "outer_iterations", "iterations",
            "converged", "elapsed", "status"]
    # every column even when nothing has run yet (a partial sweep gathers NaN)
    return pd.DataFrame(rows).reindex(columns=cols)


def peak(curves, case: str) -> tuple[float, float]:
    """(RH, F_cap) of the most tensile capillary force of ``case`` (NaN when missing)."""
    c = curves[(curves["case"] == case) & np.isfinite(curves["rh"].astype(float))]
    if c.empty:
        return math.nan, math.nan
    i = int(np.argmin(c["capillary_force"].to_numpy(dtype=float)))
    return float(c["rh"].iloc[i]), float(c["capillary_force"].iloc[i])


def _curve(curves, case):
    c = curves[(curves["case"] == case) & np.isfinite(curves["rh"].astype(float))].sort_values("rh")
    return c["rh"].to_numpy(dtype=float), c["capillary_force"].to_numpy(dtype=float), c


def _uN(f) -> str:
    return f"{f * 1e6:.4g} uN"


def findings(curves) -> list[dict]:
    """Paper B's findings (:data:`FINDINGS`) against ours: a list of ``{"key", "paper", "ours",
    "verdict"}`` with ``verdict`` one of "reproduced", "partly", "not reproduced", "missing".

    The rules (on F_cap < 0, tensile; "higher peak" = more tensile):

    * rise_fall: the peak is at an interior RH in [0.8, 0.97] for every L_ac at 500 uN and
      |F_cap(0.99)| < 0.5 |F_cap(peak)|;
    * lac_peak_rh / lac_peak_height: the peak RH does not increase and |peak| increases with
      L_ac (0.02 -> 0.05 -> 0.1);
    * rms: |peak| decreases and the peak RH does not decrease from rms 5 to 7.5 to 10 nm;
    * realisations: reproduced when the spread (max - min) of F_cap over the four seeds is below
      20 % of their mean |F_cap| at every RH >= 0.5 (Paper B: "a quite narrow band"); partly when
      only the peaks agree (same RH, within 5 %) while the curves spread more on the way up;
    * high_load: F_cap at 5000 uN does not become more tensile with RH by more than 2 % of its
      largest magnitude, for each L_ac;
    * uniform: uniform more tensile than levelled at RH <= 0.5, less at 0.7-0.85, within 5 %
      at RH >= 0.9, for each L_ac;
    * minor: max |F_ss| + max |F_ws| < 0.2 max |F_cap| and each varies over RH by less than
      10 % of max |F_cap| (``ours`` gives the numbers);
    * merge: for every L_ac at 500 uN, the first RH at which at most 3 active islands remain and
      the meniscus covers more than half of the non-contact area (the merging RH) lies in
      [0.85, 0.95].
    """
    out = []

    def add(key, ours, verdict):
        out.append({"key": key, "paper": dict(FINDINGS)[key], "ours": ours, "verdict": verdict})

    lacs = [f"lac {r:g}" for r in LAC_RATIOS]
    pk = {c: peak(curves, c) for c in set(curves["case"])}
    have = [c for c in lacs if c in pk and math.isfinite(pk[c][0])]
    # rise and fall
    if have:
        parts, ok = [], True
        for c in have:
            rh, f, d = _curve(curves, c)
            rpk, fpk = pk[c]
            f99 = float(f[-1]) if rh[-1] >= 0.985 else math.nan
            interior = 0 < int(np.argmin(f)) < len(f) - 1
            good = interior and 0.8 <= rpk <= 0.97 and (math.isfinite(f99) and abs(f99) < 0.5 * abs(fpk))
            ok &= good
            parts.append(f"{c}: peak {_uN(fpk)} at RH {rpk:g}, {_uN(f99)} at 0.99")
        add("rise_fall", "; ".join(parts), "reproduced" if ok else "not reproduced")
    else:
        add("rise_fall", "no data", "missing")
    if len(have) == 3:
        rpk = [pk[c][0] for c in have]
        fpk = [abs(pk[c][1]) for c in have]
        txt = ", ".join(f"L_ac/L {r:g}: RH {a:g}, {_uN(-b)}" for r, a, b in zip(LAC_RATIOS, rpk, fpk))
        rh_ok = rpk[0] >= rpk[1] >= rpk[2] and rpk[0] > rpk[2]
        add("lac_peak_rh", txt, "reproduced" if rh_ok else ("partly" if rpk[0] >= rpk[2] else "not reproduced"))
        h_ok = fpk[0] < fpk[1] < fpk[2]
        add("lac_peak_height", txt, "reproduced" if h_ok else ("partly" if fpk[0] < fpk[2] else "not reproduced"))
    else:
        add("lac_peak_rh", "no data", "missing")
        add("lac_peak_height", "no data", "missing")
    rms_cases = [c for c in ("lac 0.02", "rms 7.5 nm", "rms 10 nm") if c in pk and math.isfinite(pk[c][0])]
    if len(rms_cases) == 3:
        rpk = [pk[c][0] for c in rms_cases]
        fpk = [abs(pk[c][1]) for c in rms_cases]
        txt = ", ".join(f"rms {r:g} nm: RH {a:g}, {_uN(-b)}" for r, a, b in zip((5, 7.5, 10), rpk, fpk))
        h_ok, r_ok = fpk[0] > fpk[1] > fpk[2], rpk[0] <= rpk[1] <= rpk[2]
        add("rms", txt, "reproduced" if h_ok and r_ok else ("partly" if h_ok or r_ok else "not reproduced"))
    else:
        add("rms", "no data", "missing")
    seeds = [c for c in ("lac 0.02", "seed 2", "seed 3", "seed 4") if c in pk and math.isfinite(pk[c][0])]
    if len(seeds) == 4:
        worst, where = 0.0, math.nan
        for rh in sorted(set(curves["rh"].dropna())):
            if rh < 0.5:
                continue
            vals = [float(curves[(curves["case"] == c) & (curves["rh"] == rh)]["capillary_force"].iloc[0]) for c in seeds]
            spread = (max(vals) - min(vals)) / abs(np.mean(vals))
            if spread > worst:
                worst, where = spread, rh
        pks = ", ".join(f"{_uN(pk[c][1])} at {pk[c][0]:g}" for c in seeds)
        pk_f = [pk[c][1] for c in seeds]
        peaks_agree = (len({pk[c][0] for c in seeds}) == 1
                       and (max(pk_f) - min(pk_f)) <= 0.05 * abs(float(np.mean(pk_f))))
        add("realisations", f"peaks {pks}; largest spread {100 * worst:.3g} % of the mean (RH {where:g})",
            "reproduced" if worst < 0.2 else ("partly" if peaks_agree else "not reproduced"))
    else:
        add("realisations", "no data", "missing")
    high = [f"load 5000 uN lac {r:g}" for r in LAC_RATIOS]
    high = [c for c in high if c in pk and math.isfinite(pk[c][0])]
    if high:
        parts, n_ok = [], 0
        for c in high:
            rh, f, _ = _curve(curves, c)
            a = np.abs(f)
            # largest gain of |F_cap| over its smallest value at a lower RH (0 for a monotone fall)
            rise = float(np.max(a[1:] - np.minimum.accumulate(a)[:-1])) if a.size > 1 else 0.0
            mono = rise <= 0.02 * float(np.max(a))
            n_ok += mono
            parts.append(f"{c[len('load 5000 uN '):]}: {_uN(f[0])} at RH {rh[0]:g} -> peak {_uN(pk[c][1])} at "
                         f"{pk[c][0]:g} -> {_uN(f[-1])} at {rh[-1]:g}")
        add("high_load", "; ".join(parts), "reproduced" if n_ok == len(high) else ("partly" if n_ok else "not reproduced"))
    else:
        add("high_load", "no data", "missing")
    uni = [(f"lac {r:g}", f"uniform lac {r:g}") for r in LAC_RATIOS]
    uni = [(a, b) for a, b in uni if a in pk and b in pk and math.isfinite(pk[a][0]) and math.isfinite(pk[b][0])]
    if uni:
        parts, score = [], []
        for a, b in uni:
            ra, fa, _ = _curve(curves, a)
            rb, fb, _ = _curve(curves, b)
            common = np.intersect1d(ra, rb)
            fa_c = np.array([fa[ra == r][0] for r in common])
            fb_c = np.array([fb[rb == r][0] for r in common])
            rel = (np.abs(fb_c) - np.abs(fa_c)) / np.maximum(np.abs(fa_c), 1e-300)
            low = rel[common <= 0.5]
            mid = rel[(common >= 0.7) & (common <= 0.85)]
            top = rel[common >= 0.9]
            c1 = low.size > 0 and bool(np.all(low > 0))
            c2 = mid.size > 0 and bool(np.all(mid < 0))
            c3 = top.size > 0 and bool(np.all(np.abs(top) < 0.05))
            score.append(c1 + c2 + c3)
            parts.append(f"{a}: uniform/levelled - 1 = " + ", ".join(f"{100 * v:+.2g} % at {r:g}" for r, v in zip(common, rel)))
        verdict = "reproduced" if all(s == 3 for s in score) else ("partly" if any(score) else "not reproduced")
        add("uniform", "; ".join(parts), verdict)
    else:
        add("uniform", "no data", "missing")
    base = curves[curves["case"].isin(have) & np.isfinite(curves["rh"].astype(float))]
    if not base.empty:
        big = float(np.max(np.abs(base["capillary_force"])))
        ss, ws = base["solid_solid_force"].astype(float), base["water_solid_force"].astype(float)
        small = float(np.max(np.abs(ss)) + np.max(np.abs(ws)))
        var_ss = float(np.max([np.ptp(base[base["case"] == c]["solid_solid_force"]) for c in have]))
        var_ws = float(np.max([np.ptp(base[base["case"] == c]["water_solid_force"]) for c in have]))
        ok = small < 0.2 * big and max(var_ss, var_ws) < 0.1 * big
        add("minor", f"max |F_ss| {_uN(float(np.max(np.abs(ss))))} (varies by {_uN(var_ss)} over RH), max |F_ws| "
                     f"{_uN(float(np.max(np.abs(ws))))} (varies by {_uN(var_ws)}), against max |F_cap| {_uN(big)}",
            "reproduced" if ok else "not reproduced")
        parts, ok = [], True
        for c in have:
            d = base[base["case"] == c].sort_values("rh")
            frac = d["wetted_fraction"] / np.maximum(1 - d["contact_fraction"], 1e-12)
            merged = d[(d["island_count"] <= 3) & (frac > 0.5)]
            rm = float(merged["rh"].iloc[0]) if not merged.empty else math.nan
            at90 = d[np.isclose(d["rh"].astype(float), 0.9)]
            extra = ""
            if not at90.empty:
                r90 = at90.iloc[0]
                extra = (f" (at RH 0.9: {int(r90['island_count'])} active islands, meniscus "
                         f"{100 * r90['wetted_fraction'] / max(1 - r90['contact_fraction'], 1e-12):.3g} % of the "
                         "non-contact area)")
            ok &= math.isfinite(rm) and 0.85 <= rm <= 0.95
            parts.append(f"{c}: merged at RH {rm:g}{extra}")
        add("merge", "; ".join(parts), "reproduced" if ok else "not reproduced")
    else:
        add("minor", "no data", "missing")
        add("merge", "no data", "missing")
    order = [k for k, _ in FINDINGS]
    return sorted(out, key=lambda d: order.index(d["key"]))


def plot_study(curves, path, title: str | None = None) -> Path:
    """Six panels: F_cap against RH for the three L_ac (Fig. 13d), the components of L_ac/L =
    0.02 (Fig. 13a), rms (Fig. 16), realisations (Fig. 15), 5000 uN (Fig. 17c) and uniform vs
    levelled films (Fig. 18)."""
    from matplotlib.figure import Figure

    from tribobem.output.atomic import atomic_write_bytes

    fig = Figure(figsize=(14, 8.4), layout="constrained")
    axes = fig.subplots(2, 3)
    colors = {0.02: "#1b9e77", 0.05: "#d95f02", 0.1: "#7570b3"}

    def line(ax, case, **kw):
        rh, f, _ = _curve(curves, case)
        if rh.size:
            ax.plot(100 * rh, 1e6 * f, marker=kw.pop("marker", "o"), ms=3.5, **kw)

    ax = axes[0, 0]
    for r in LAC_RATIOS:
        line(ax, f"lac {r:g}", color=colors[r], label=f"L$_{{ac}}$/L = {r:g}")
    ax.set_title("F$_{cap}$ vs RH, 500 \u00b5N (Paper B Fig. 13d)", fontsize=10)
    ax = axes[0, 1]
    rh, f, d = _curve(curves, "lac 0.02")
    if rh.size:
        for key, lab, col in (("capillary_force", "F$_{cap}$", "#2b7bba"), ("solid_solid_force", "F$_{ss}$", "#f4a261"),
                              ("water_solid_force", "F$_{ws}$", "#2a9d8f"), ("adhesive_total", "total", "k")):
            ax.plot(100 * rh, 1e6 * d[key].to_numpy(dtype=float), marker="o", ms=3.5, color=col, label=lab)
    ax.set_title("components, L$_{ac}$/L = 0.02 (Fig. 13a)", fontsize=10)
    ax = axes[0, 2]
    for case, lab, col in (("lac 0.02", "rms 5 nm", "#1b9e77"), ("rms 7.5 nm", "rms 7.5 nm", "#e7298a"),
                           ("rms 10 nm", "rms 10 nm", "#66a61e")):
        line(ax, case, color=col, label=lab)
    ax.set_title("rms, L$_{ac}$/L = 0.02 (Fig. 16)", fontsize=10)
    ax = axes[1, 0]
    for case, col in (("lac 0.02", "#1b9e77"), ("seed 2", "#a6761d"), ("seed 3", "#666666"), ("seed 4", "#e6ab02")):
        line(ax, case, color=col, label="seed 1" if case == "lac 0.02" else case)
    ax.set_title("four realisations (Fig. 15)", fontsize=10)
    ax = axes[1, 1]
    for r in LAC_RATIOS:
        line(ax, f"lac {r:g}", color=colors[r], alpha=0.35, label=f"{r:g}, 500 \u00b5N")
        line(ax, f"load 5000 uN lac {r:g}", color=colors[r], marker="s", label=f"{r:g}, 5000 \u00b5N")
    ax.set_title("5000 \u00b5N against 500 \u00b5N (Fig. 17)", fontsize=10)
    ax = axes[1, 2]
    for r in LAC_RATIOS:
        line(ax, f"lac {r:g}", color=colors[r], label=f"{r:g} equilibrium films")
        line(ax, f"uniform lac {r:g}", color=colors[r], ls="--", marker="x", label=f"{r:g} uniform films")
    ax.set_title("uniform vs levelled films (Fig. 18)", fontsize=10)
    for ax in axes.flat:
        ax.axhline(0.0, color="0.6", lw=0.6)
        ax.set_xlabel("RH (%)")
        ax.set_ylabel("force (\u00b5N), < 0 tensile")
        if any(not ln.get_label().startswith("_") for ln in ax.get_lines()):
            ax.legend(fontsize=7)
    if title:
        fig.suptitle(title, fontsize=11)
    import io

    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=110)
    return atomic_write_bytes(path, buf.getvalue())
