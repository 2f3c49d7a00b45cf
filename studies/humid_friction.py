"""Humid friction of a smooth ball on a rough SiO2 flat against relative humidity: static
friction, pre-sliding, lateral stiffness at Paper F's points A/B/C, loop energy and the capillary
force, each beside the dry (Dugdale) case.

The geometry joins Paper D section 3.2 and Paper B section 4.2: a rigid smooth ball (R = 100 um,
F0 = 10 uN, mu = 0.2, as Paper D) on an elastic SiO2 flat (E = 64 GPa, nu = 0.17) carrying a
Gaussian rough surface of Paper B's statistics (exponential ACF, rms 5 nm, L_ac / L = 0.05 of
its 10 um cell, i.e. L_ac = 0.5 um), water films on both bodies (the SiO2 isotherm), solid-solid
adhesion Dugdale dgamma = 88 mJ/m^2, z0 = 0.3 nm (:mod:`studies.paper_b`'s choice).  The flat is
generated once on 10 x 10 um (:func:`studies.rough_slip.flat_surface`, L_ac given, rms 5 nm over
the whole flat) and only its central window is solved (``crop``, free boundary, the flat's own
cells: no resampling).

The study is a resumable sweep of three points over one base scenario (:func:`sweep_spec`):

* ``partial_slip``: a tangential force ramp (0 ... 20 uN in 0.5 uN steps, ``slip = "total"``,
  ends at gross slip, the onset bisected to 1e-3 mu F0+) -> static friction force and ratio,
  pre-sliding displacement, the capillary force of the zero-tangential-load state;
* ``hysteresis``: a force-controlled loop, amplitude 0.9 mu F0+, 3 cycles x 40 steps ->
  lateral stiffness at A, B, C (F_x / (mu F0+) = -0.5, 0, 0.5 on the last reloading branch,
  Paper F Eq. 3 fit) and the dissipated energy per cycle;
* ``capillary``: the tool's own ``capillary`` kind on the same surface and load (no friction) ->
  F_cap, wetted area, islands: the normal-only reference of the zero-load state.

The two friction points run every RH of :data:`RH` in one run each (warm-started RH to RH) after
a dry reference run with the same Dugdale law (``dry`` of summary.json): that dry run is the
"dry" row of every table.  A killed study resumes at the point level (``points/<hash>.json``;
finished points are never recomputed).

Resolution (full study): the flat on 512^2 cells over 10 um, the central 5 x 5 um solved on
256^2 cells of 19.5 nm.  What that resolves: the asperities (L_ac = 0.5 um = 26 cells); the
meniscus (its rim, where the gap reaches 2 |r_k| plus the films, lies at r ~ sqrt(2 R 2|r_k|) =
1.1 um at RH 0.7, 1.4 um at 0.9, 2.0 um at 0.95 from the ball's centre, inside the 2.5 um
half-window; :func:`gather` reports whether the capillary run's meniscus touches the window's
edge per RH).  What it does not: the contact spots (at F0 = 10 uN the largest spot is ~1-3
cells across and the stick zone 1 cell: the runs warn; static friction and stick are the grid's
estimate of many one-cell spots) and the Dugdale cohesive zone (h0 = 0.29 nm, crossed within a
cell, as in Paper B's 39 nm cells).  Read the numbers as trends with RH, not as converged values.

Persson (2008) predicts that friction and contact area peak where the Kelvin bridge height
2 |r_k| is about 3 h_rms (:func:`persson_rh`; 0.93 for h_rms = 5 nm); Paper B that F_cap rises
and then falls with RH.  :func:`findings` states where our curves agree; no parameter is tuned
to them.

Results of the full study (measured 2026-11-26; ``python -m studies.humid_friction --out
/tmp/humid_study``, 339 s on one core: partial slip 53 s, hysteresis 279 s, capillary 7 s).
F_s: static friction force, delta_s: pre-sliding displacement at the onset, K: lateral
stiffness (kN/m) at A, B, C of the last reloading branch, W: dissipated energy of the third
cycle, F_cap: capillary force of the zero-tangential-load state (friction run / the
``capillary`` kind alone), F0+: repulsive force there, A_c: contact area there (not stored for
the dry run).  The dry row is the dry reference run (Dugdale only, F_ss = -0.46 uN)::

    | RH   | 2|r_k|/h | F_s uN| F_s/muF0+ | delta_s nm | K_A | K_B | K_C | W fJ | F_cap uN fric / cap | F0+ uN | A_c um^2 |
    | dry  |  -     |  2.08  | 0.992 | 0.643 |  6.93 |  5.19 |  3.16 | 0.872 |    0   /    0   | 10.5 |   -     |
    | 0.1  | 0.093  |  2.91  | 0.991 | 0.777 |  8.89 |  6.71 |  4.12 | 1.42  |  -2.98 /  -2.98 | 14.6 | 0.0061  |
    | 0.2  | 0.133  |  3.79  | 0.991 | 0.892 | 10.8  |  8.20 |  5.33 | 1.76  |  -7.43 /  -7.68 | 18.8 | 0.0099  |
    | 0.3  | 0.177  |  5.05  | 0.989 | 0.998 | 13.9  | 10.4  |  6.57 | 2.66  | -13.8  / -13.8  | 25.3 | 0.0122  |
    | 0.4  | 0.233  |  5.16  | 0.989 | 0.995 | 14.1  | 10.6  |  6.62 | 2.88  | -14.8  / -14.9  | 26.1 | 0.0134  |
    | 0.5  | 0.308  |  5.08  | 0.989 | 0.984 | 14.1  | 10.5  |  6.56 | 2.85  | -14.3  / -14.3  | 25.8 | 0.0126  |
    | 0.6  | 0.418  |  4.99  | 0.989 | 0.977 | 13.9  | 10.3  |  6.43 | 2.81  | -13.8  / -13.8  | 25.3 | 0.0118  |
    | 0.7  | 0.598  |  5.27  | 0.988 | 0.992 | 14.4  | 10.9  |  6.77 | 2.98  | -15.5  / -15.5  | 26.7 | 0.0134  |
    | 0.8  | 0.956  |  5.85  | 0.988 | 1.02  | 15.7  | 11.9  |  7.40 | 3.36  | -18.7  / -18.7  | 29.6 | 0.0145  |
    | 0.9  | 2.03   | 11.5   | 0.981 | 1.28  | 23.5  | 18.9  | 13.1  | 6.78  | -46.7  / -46.8  | 58.8 | 0.0248  |
    | 0.95 | 4.16   | 16.9   | 0.973 | 1.42  | 28.9  | 23.8  | 16.8  | 10.6  | -73.6  / -73.7  | 86.7 | 0.0336  |

What the curves say (findings, not targets):

* F_cap rises from 0.1 to 0.3, stays at -14 to -16 uN from 0.3 to 0.7 (25-51 separate islands,
  their Laplace pressure falling as their area grows), rises again as the islands merge (6 at
  0.8, one meniscus around the ball at 0.9 and 0.95) and approaches the smooth sphere's
  4 pi gamma R = 91 uN.  It has not fallen by RH 0.95: Paper B's fall (a flat on a flat, where
  the wetted area is bounded and F_cap ~ dP A falls with dP) is not this geometry's; a ball's
  meniscus keeps growing towards 4 pi gamma R.  Paper B's fall lies between 0.95 and 0.99, which
  this window cannot hold (the rim at 0.99 lies near r = 6.5 um).  Agrees with Paper B in the
  rise (and its island merging near 0.9), not in the fall.
* The zero-load F_cap of the friction runs equals the ``capillary`` kind's within 1 % except
  at RH 0.2 (3.3 %; 0.96 % at 0.4, 0 at five RHs): the friction run is warm-started from the
  previous RH's state, the capillary kind from its own, and the island fixed point lands on a
  nearby state.
* Static friction follows mu F0+ (F_s / (mu F0+) = 0.97-0.99 throughout): the menisci act as
  extra normal load (F_s / F_s,dry = 1.4 ... 8.1 against F0+ / F0+,dry = 1.4 ... 8.3).  It
  rises monotonically with RH to the last sampled RH; so does the contact area.  Persson's peak
  (RH 0.93, 2|r_k| = 3 h_rms) is not seen: friction and area still rise at 0.95 (partly: a
  curve still rising through the predicted RH, no peak).
* K_B grows as F0+^0.72 (4.6x for 8.3x the load; Mindlin's smooth ball: F0+^(1/3)), the loop
  energy by 12x; the pre-sliding displacement by 2.2x.

Resolution caveats (the runs warn): the contact spots are 1-1.4 cells across and the stick zone
one cell, so F_s / (mu F0+) near 1 and delta_s are grid-limited (the ratio below 1 is a few
one-cell spots slipping late); the Dugdale zone is unresolved; the meniscus at RH 0.95 reaches
2.45 um from the centre, 2 cells inside the 2.5 um half-window (not touching it).
"""

from __future__ import annotations

import json
import math
import os
from pathlib import Path

import numpy as np

__all__ = ["RADIUS", "E_FLAT", "NU_FLAT", "FORCE", "FRICTION", "DGAMMA", "Z0", "RMS", "CORRELATION_LENGTH",
           "FLAT_SIZE", "FLAT_N", "WINDOW", "N", "RH", "QUICK", "kelvin_radius", "persson_rh", "write_flat",
           "base_scenario", "sweep_spec", "run_study", "gather", "findings", "plot_study", "main"]

#: Paper D 3.2: rigid ball, F0, mu; Paper B 4.2 / Fig. 3.9: SiO2 flat.
RADIUS = 100e-6
E_FLAT = 64e9
NU_FLAT = 0.17
FORCE = 10e-6
FRICTION = 0.2
#: Solid-solid Dugdale law of studies.paper_b (Paper C's 2 gamma_SiO2, z0 mid of 0.2-0.4 nm).
DGAMMA = 0.088
Z0 = 0.3e-9
#: Paper B surface statistics: rms 5 nm, L_ac / L = 0.05 of the 10 um cell.
RMS = 5e-9
CORRELATION_LENGTH = 0.5e-6
FLAT_SIZE = 10e-6
SEED = 1
#: Full study: the flat on 512^2 (19.5 nm cells), the central 5 um solved on 256^2.
FLAT_N = 512
WINDOW = 5e-6
N = 256
RH = (0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 0.95)
#: Tangential ramp (N): far past mu F0+ of the wettest state (the ramp ends at gross slip).
RAMP = (0.0, 20e-6, 41)
CYCLES, STEPS, AMPLITUDE = 3, 40, 0.9
#: Quick mode (tests): the flat on 64^2 over 2.5 um (39 nm cells), 1.25 um solved on 32^2,
#: two RH, one short loop.
QUICK = {"flat_n": 64, "flat_size": 2.5e-6, "window": 1.25e-6, "n": 32, "rh": (0.5, 0.9),
         "ramp": (0.0, 20e-6, 21), "cycles": 1, "steps": 12}

#: Water at 295 K (defaults): surface tension (N/m), molar volume (m^3/mol).
GAMMA_WATER = 0.0725
MOLAR_VOLUME = 18.05e-6
GAS_CONSTANT = 8.314462618
TEMPERATURE = 295.0


def kelvin_radius(rh: float) -> float:
    """Kelvin radius r_k = gamma V / (R_g T ln RH) (m, negative for RH < 1)."""
    return GAMMA_WATER * MOLAR_VOLUME / (GAS_CONSTANT * TEMPERATURE * math.log(rh))


def persson_rh(h_rms: float = RMS, ratio: float = 3.0) -> float:
    """The RH at which the Kelvin bridge height 2 |r_k| equals ``ratio`` x ``h_rms`` (m)
    (Persson 2008: friction and contact area peak near it)."""
    return math.exp(-GAMMA_WATER * MOLAR_VOLUME / (GAS_CONSTANT * TEMPERATURE * 0.5 * ratio * h_rms))


def _cfg(quick: bool) -> dict:
    if quick:
        return dict(QUICK)
    return {"flat_n": FLAT_N, "flat_size": FLAT_SIZE, "window": WINDOW, "n": N, "rh": RH, "ramp": RAMP,
            "cycles": CYCLES, "steps": STEPS}


def write_flat(path: str | os.PathLike, quick: bool = False) -> dict:
    """Write the study's flat (:func:`studies.rough_slip.flat_surface` with Paper B's L_ac and
    rms over the whole flat) to ``path`` (``.npy``, m) with its info (``.json``), unless a flat
    with the same info is there already.  Returns the info."""
    from .rough_slip import write_flat as _write

    c = _cfg(quick)
    path = Path(path)
    want = {"n": c["flat_n"], "size": c["flat_size"], "seed": SEED, "rms": RMS, "correlation_length": CORRELATION_LENGTH}
    meta = path.with_suffix(".json")
    if path.is_file() and meta.is_file():
        try:
            have = json.loads(meta.read_text(encoding="utf-8"))
            if all(math.isclose(float(have[k]), float(v), rel_tol=1e-12) for k, v in want.items()):
                return have
        except (OSError, ValueError, KeyError):
            pass
    return _write(path, n=c["flat_n"], size=c["flat_size"], seed=SEED, rms=RMS,
                  correlation_length=CORRELATION_LENGTH)


def base_scenario(flat: str | os.PathLike, quick: bool = False) -> dict:
    """The base scenario (kind ``capillary``, no friction): the ball on the central window of
    the flat at ``flat`` (an absolute path keeps the sweep's hashes independent of the working
    folder), films on both bodies, Dugdale adhesion, every RH."""
    c = _cfg(quick)
    x0 = 0.5 * (c["flat_size"] - c["window"])
    um = f"{c['window'] * 1e6:.6g} um"
    return {
        "kind": "capillary",
        "name": "humid friction" + (" (quick)" if quick else ""),
        "description": "smooth rigid ball (R = 100 um) on a rough SiO2 flat (rms 5 nm, L_ac 0.5 um), films on both",
        "grid": {"n": c["n"], "size": um},
        "body1": {"name": "rough SiO2 flat", "E": f"{E_FLAT / 1e9:g} GPa", "nu": NU_FLAT,
                  "roughness": {"kind": "array", "path": str(Path(flat).resolve()),
                                "size": f"{c['flat_size'] * 1e6:.6g} um",
                                "crop": {"x0": f"{x0 * 1e6:.6g} um", "y0": f"{x0 * 1e6:.6g} um", "lx": um, "ly": um}},
                  "film": {"isotherm": "SiO2"}},
        "body2": {"name": "rigid SiO2 ball", "rigid": True,
                  "shape": {"kind": "sphere", "radius": f"{RADIUS * 1e6:g} um"}, "film": {"isotherm": "SiO2"}},
        "load": {"force": f"{FORCE * 1e6:g} uN"},
        "adhesion": {"model": "dugdale", "work_of_adhesion": f"{DGAMMA * 1e3:g} mJ/m^2", "z0": f"{Z0 * 1e9:g} nm"},
        "humidity": {"rh": [float(r) for r in c["rh"]]},
        "output": {"fields": "none", "figures": False, "report": False},
    }


def sweep_spec(flat: str | os.PathLike, quick: bool = False) -> dict:
    """The study's sweep: points ``partial_slip``, ``hysteresis`` and ``capillary`` (module
    docstring) over :func:`base_scenario`."""
    c = _cfg(quick)
    f0, f1, num = c["ramp"]
    ramp = {"start": f"{f0 * 1e6:g} uN", "stop": f"{f1 * 1e6:g} uN", "num": int(num)}
    return {
        "name": "humid-friction" + ("-quick" if quick else ""),
        "description": "humid friction of a smooth ball on a rough SiO2 flat against RH, beside the dry case",
        "base": base_scenario(flat, quick), "keep_runs": True, "scheduler": "synchronous",
        "outputs": ["converged"],
        "points": [
            {"name": "partial_slip", "kind": "partial_slip", "friction.coefficient": FRICTION,
             "friction.tangential_forces": ramp, "friction.slip": "total"},
            {"name": "hysteresis", "kind": "hysteresis", "friction.coefficient": FRICTION,
             "friction.path": {"control": "force", "amplitude": AMPLITUDE, "cycles": c["cycles"],
                               "steps": c["steps"]}},
            # the capillary run keeps its meniscus maps: gather checks them against the window's edge
            {"name": "capillary", "output.fields": "all"},
        ],
    }


def run_study(outdir, quick: bool = False, progress: bool = False, max_points: int | None = None):
    """Write the flat (once) and run the sweep into ``outdir`` (resumable).

    Returns
    -------
    (spec dict, tribobem.sweep.SweepResult)
    """
    from tribobem.sweep import run_sweep

    outdir = Path(outdir)
    outdir.mkdir(parents=True, exist_ok=True)
    flat = outdir / "humid_friction_flat.npy"
    write_flat(flat, quick)
    spec = sweep_spec(flat, quick)
    res = run_sweep(spec, outdir, scheduler="synchronous", progress=progress, max_points=max_points)
    return spec, res


# ----------------------------------------------------------------------------- gathering

def _read_json(path: Path):
    try:
        return json.loads(path.read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return None


def _num(v) -> float:
    try:
        return math.nan if v is None else float(v)
    except (TypeError, ValueError):
        return math.nan


def _stiff(table) -> dict:
    """{"A": K, "B": K, "C": K} (N/m) of a lateral-stiffness table (list of dicts)."""
    out = {"A": math.nan, "B": math.nan, "C": math.nan}
    for d in table or []:
        if isinstance(d, dict) and d.get("point") in out:
            out[d["point"]] = _num(d.get("stiffness"))
    return out


def _edge_touch(fields: Path) -> dict:
    """rh -> (meniscus or contact touches the window's edge, their largest distance from the
    window's centre in m) of a capillary run's fields.nc."""
    if not fields.is_file():
        return {}
    import xarray as xr

    out = {}
    with xr.open_dataset(fields) as ds:
        if "meniscus" not in ds or "rh" not in ds.coords:
            return {}
        x, y = ds["x"].values, ds["y"].values
        X, Y = np.meshgrid(x - 0.5 * (x[0] + x[-1]), y - 0.5 * (y[0] + y[-1]), indexing="ij")
        for k in range(ds.sizes["step"]):
            # the meniscus and the contact, not p != 0: the films' van der Waals terms act everywhere
            m = ds["meniscus"].isel(step=k).values != 0
            if "contact" in ds:
                m |= ds["contact"].isel(step=k).values != 0
            edge = bool(m[0].any() or m[-1].any() or m[:, 0].any() or m[:, -1].any())
            ext = float(np.sqrt(X[m] ** 2 + Y[m] ** 2).max()) if m.any() else 0.0
            out[round(float(ds["rh"].values[k]), 6)] = (edge, ext)
    return out


COLUMNS = ["case", "rh", "static_friction_force", "static_friction_ratio", "presliding_displacement",
           "onset_repulsive_force", "stiffness_A", "stiffness_B", "stiffness_C", "dissipated_energy",
           "dissipated_energy_cycles", "sliding_force", "capillary_force", "repulsive_force",
           "contact_area", "wetted_area", "loop_capillary_force", "capillary_kind_force",
           "capillary_kind_repulsive_force", "capillary_kind_contact_area", "capillary_kind_wetted_area",
           "capillary_kind_islands", "meniscus_extent", "meniscus_at_edge", "kelvin_radius", "bridge_over_rms"]


def gather(spec, outdir):
    """One row for the dry case and one per RH of a finished (or partial) study.

    Parameters
    ----------
    spec : dict, path or SweepSpec
        The sweep (:func:`sweep_spec`).
    outdir : path
        Its results folder (``points/``, ``runs/<hash>/``).

    Returns
    -------
    pandas.DataFrame
        ``case`` ("dry" or "humid"), ``rh`` (NaN for dry); from the partial-slip run:
        ``static_friction_force`` (N), ``static_friction_ratio`` (F_s / (mu F0+ at F_x = 0)),
        ``presliding_displacement`` (m), ``onset_repulsive_force`` (N), ``capillary_force``
        and ``repulsive_force`` (N, the zero-tangential-load state; dry: capillary 0),
        ``contact_area`` and ``wetted_area`` (m^2, at F_x = 0); from the loop:
        ``stiffness_A/B/C`` (N/m), ``dissipated_energy`` (J, last cycle),
        ``dissipated_energy_cycles`` (J, every cycle, ";"-joined), ``sliding_force`` (N),
        ``loop_capillary_force`` (N); from the ``capillary`` kind: ``capillary_kind_force``,
        ``capillary_kind_repulsive_force`` (N), ``capillary_kind_contact_area``,
        ``capillary_kind_wetted_area`` (m^2), ``capillary_kind_islands``, ``meniscus_extent`` (m,
        from the window's centre), ``meniscus_at_edge``; ``kelvin_radius`` (m) and
        ``bridge_over_rms`` (2 |r_k| / h_rms).  Missing results are NaN.
    """
    import pandas as pd

    from tribobem.sweep import load_sweep, read_points

    spec = load_sweep(spec)
    outdir = Path(outdir)
    records = read_points(outdir)
    runs, fields = {}, {}
    rhs = list(spec.base.get("humidity", {}).get("rh", []))
    for h, o in spec.tasks():
        rec = records.get(h) or {}
        name = o.get("name")
        if rec.get("status") == "ok":
            runs[name] = _read_json(outdir / "runs" / h / "summary.json") or {}
            fields[name] = outdir / "runs" / h / "fields.nc"
    rows = {"dry": {"case": "dry", "rh": math.nan, "capillary_force": 0.0, "loop_capillary_force": 0.0,
                    "capillary_kind_force": 0.0}}
    for rh in rhs:
        rk = kelvin_radius(rh)
        rows[rh] = {"case": "humid", "rh": float(rh), "kelvin_radius": rk, "bridge_over_rms": 2 * abs(rk) / RMS}
    ps = runs.get("partial_slip")
    if ps:
        dry = ps.get("dry") or {}
        for k in ("static_friction_force", "static_friction_ratio", "presliding_displacement", "onset_repulsive_force",
                  "repulsive_force"):
            rows["dry"][k] = _num(dry.get(k))
        for i, rh in enumerate(ps.get("rh", [])):
            r = rows.setdefault(rh, {"case": "humid", "rh": rh})
            for k in ("static_friction_force", "static_friction_ratio", "presliding_displacement",
                      "onset_repulsive_force", "capillary_force", "repulsive_force"):
                v = ps.get(k)
                r[k] = _num(v[i] if isinstance(v, list) else v)
        # areas of the F_x = 0 state: the first step of each RH (and the dry run has none in steps)
        seen = set()
        for st in ps.get("steps", []):
            rh = st.get("rh")
            if rh in rows and rh not in seen:
                seen.add(rh)
                rows[rh]["contact_area"] = _num(st.get("contact_area"))
                rows[rh]["wetted_area"] = _num(st.get("wetted_area"))
    hy = runs.get("hysteresis")
    if hy:
        dry = hy.get("dry") or {}

        def loop_values(r, stiff, energy, sliding):
            for p, v in _stiff(stiff).items():
                r[f"stiffness_{p}"] = v
            e = [_num(x) for x in (energy or [])]
            r["dissipated_energy"] = e[-1] if e else math.nan
            r["dissipated_energy_cycles"] = ";".join(f"{x:.6g}" for x in e)
            r["sliding_force"] = _num(sliding)

        loop_values(rows["dry"], dry.get("lateral_stiffness"), dry.get("dissipated_energy"), dry.get("sliding_force"))
        for i, rh in enumerate(hy.get("rh", [])):
            r = rows.setdefault(rh, {"case": "humid", "rh": rh})

            def at(key):
                v = hy.get(key)
                return v[i] if isinstance(v, list) else v

            loop_values(r, at("lateral_stiffness"), at("dissipated_energy"), at("sliding_force"))
            r["loop_capillary_force"] = _num(at("capillary_force"))
    cp = runs.get("capillary")
    if cp:
        edge = _edge_touch(fields["capillary"])
        for st in cp.get("steps", []):
            rh = st.get("rh")
            if rh not in rows:
                continue
            r = rows[rh]
            r["capillary_kind_force"] = _num(st.get("capillary_force"))
            r["capillary_kind_repulsive_force"] = _num(st.get("repulsive_force"))
            r["capillary_kind_contact_area"] = _num(st.get("contact_area"))
            r["capillary_kind_wetted_area"] = _num(st.get("wetted_area"))
            r["capillary_kind_islands"] = _num(st.get("island_count"))
            e = edge.get(round(float(rh), 6))
            if e is not None:
                r["meniscus_at_edge"], r["meniscus_extent"] = bool(e[0]), e[1]
    df = pd.DataFrame([rows["dry"]] + [rows[k] for k in rows if k != "dry"]).reindex(columns=COLUMNS)
    nx = spec.base["grid"]["n"]
    df.attrs.update(n=nx, window=_window(spec.base), points_ok=sorted(runs))
    return df


def _window(base) -> float:
    from tribobem.units import si_value

    return float(si_value(base["grid"]["size"]))


# ----------------------------------------------------------------------------- findings

def findings(table) -> list[dict]:
    """Where our curves agree with Paper B and Persson (2008): a list of ``{"key", "expected",
    "ours", "verdict"}``, ``verdict`` one of "agrees", "partly", "disagrees", "missing data".

    * ``cap_rise_fall`` (Paper B): |F_cap| (partial-slip zero-load state) has an interior
      maximum over RH;
    * ``cap_vs_kind``: the zero-load F_cap of the friction run against the ``capillary`` kind's
      (same surface, load, films): within 5 % at every RH ("partly": within 25 %);
    * ``persson_friction`` / ``persson_area``: the static friction force / the contact area at
      F_x = 0 peak at the RH nearest :func:`persson_rh` (within one RH step: "agrees"; an interior
      peak elsewhere: "partly"; a monotone curve: "disagrees");
    * ``humid_above_dry``: static friction above the dry value at every RH.
    """
    out = []
    h = table[table["case"] == "humid"].sort_values("rh")
    dry = table[table["case"] == "dry"]
    rh = h["rh"].to_numpy(float)
    prh = persson_rh()

    def add(key, expected, ours, verdict):
        out.append({"key": key, "expected": expected, "ours": ours, "verdict": verdict})

    def peak_of(col):
        v = h[col].to_numpy(float)
        if v.size == 0 or not np.isfinite(v).any():
            return None
        i = int(np.nanargmax(v))
        return i, v

    p = peak_of("capillary_force") if "capillary_force" in h else None
    if p is not None:
        v = -p[1]  # tensile = negative: the most tensile is the largest -F_cap
        i = int(np.nanargmax(v))
        interior = 0 < i < len(v) - 1
        add("cap_rise_fall", "Paper B: F_cap rises with RH, peaks and falls towards RH 1",
            f"|F_cap| peaks at RH {rh[i]:g} ({v[i] * 1e6:.3g} uN); at RH {rh[-1]:g}: {v[-1] * 1e6:.3g} uN",
            "agrees" if interior else ("partly" if i == len(v) - 1 and len(v) > 1 and v[-1] > v[0] else "disagrees"))
    else:
        add("cap_rise_fall", "Paper B: F_cap rises with RH, peaks and falls towards RH 1", "no data", "missing data")
    a, b = h["capillary_force"].to_numpy(float), h["capillary_kind_force"].to_numpy(float)
    ok = np.isfinite(a) & np.isfinite(b) & (np.abs(b) > 0)
    if ok.any():
        rel = np.abs(a[ok] - b[ok]) / np.abs(b[ok])
        add("cap_vs_kind", "zero-load F_cap of the friction run equals the capillary kind's",
            "largest difference " + f"{100 * rel.max():.3g} % (RH {rh[ok][int(np.argmax(rel))]:g})",
            "agrees" if rel.max() < 0.05 else ("partly" if rel.max() < 0.25 else "disagrees"))
    else:
        add("cap_vs_kind", "zero-load F_cap of the friction run equals the capillary kind's", "no data", "missing data")
    for key, col, what in (("persson_friction", "static_friction_force", "static friction"),
                           ("persson_area", "contact_area", "contact area at F_x = 0")):
        p = peak_of(col)
        exp = f"Persson 2008: {what} peaks where 2|r_k| ~ 3 h_rms (RH {prh:.3f})"
        if p is None:
            add(key, exp, "no data", "missing data")
            continue
        i, v = p
        near = int(np.argmin(np.abs(rh - prh)))
        interior = 0 < i < len(v) - 1
        # a peak at the wettest RH sampled is no peak: at most "partly" (a curve still rising)
        verdict = ("agrees" if interior and abs(i - near) <= 1 else
                   "partly" if interior or (i == len(v) - 1 and abs(i - near) <= 1) else "disagrees")
        add(key, exp, f"peak at RH {rh[i]:g} ({v[i]:.4g}); nearest sampled RH to {prh:.3f} is {rh[near]:g}", verdict)
    if not dry.empty and np.isfinite(dry["static_friction_force"].to_numpy(float)).all():
        d = float(dry["static_friction_force"].iloc[0])
        f = h["static_friction_force"].to_numpy(float)
        add("humid_above_dry", "menisci add normal load: static friction above the dry value",
            f"F_s / F_s,dry from {np.nanmin(f) / d:.3g} to {np.nanmax(f) / d:.3g}",
            "agrees" if np.all(f > d) else ("partly" if np.any(f > d) else "disagrees"))
    else:
        add("humid_above_dry", "menisci add normal load: static friction above the dry value", "no data",
            "missing data")
    return out


def markdown_table(table) -> str:
    """The study's table against RH (dry first) in markdown, SI values in readable units."""
    head = ("| RH | 2\\|r_k\\|/h_rms | F_s (uN) | F_s/(mu F0+) | delta_s (nm) | K_A | K_B | K_C (kN/m) | W_cycle (fJ) "
            "| F_cap friction (uN) | F_cap capillary kind (uN) | F0+ (uN) | A_c (um^2) |")
    lines = [head, "|" + "---|" * 13]

    def f(v, s=1.0, spec=".3g"):
        v = _num(v)
        return "-" if not math.isfinite(v) else format(v / s, spec)

    for r in table.itertuples():
        lab = "dry" if r.case == "dry" else f"{r.rh:g}"
        lines.append(f"| {lab} | {f(r.bridge_over_rms)} | {f(r.static_friction_force, 1e-6)} | "
                     f"{f(r.static_friction_ratio, 1, '.3f')} | {f(r.presliding_displacement, 1e-9)} | "
                     f"{f(r.stiffness_A, 1e3)} | {f(r.stiffness_B, 1e3)} | {f(r.stiffness_C, 1e3)} | "
                     f"{f(r.dissipated_energy, 1e-15)} | {f(r.capillary_force, 1e-6)} | "
                     f"{f(r.capillary_kind_force, 1e-6)} | {f(r.repulsive_force, 1e-6)} | "
                     f"{f(r.contact_area, 1e-12, '.3g')} |")
    return "\n".join(lines)


# ----------------------------------------------------------------------------- figure

def plot_study(table, path, title: str | None = None) -> Path:
    """Six panels against RH, the dry value as a dashed line in each: static friction, pre-sliding
    displacement, K_L at A/B/C, dissipated energy per cycle, F_cap (friction run and capillary
    kind), contact area at F_x = 0; the Persson RH marked."""
    import io

    from matplotlib.figure import Figure

    from tribobem.output.atomic import atomic_write_bytes

    h = table[table["case"] == "humid"].sort_values("rh")
    d = table[table["case"] == "dry"]
    dry = d.iloc[0] if not d.empty else None
    rh = 100 * h["rh"].to_numpy(float)
    fig = Figure(figsize=(14, 8.4), layout="constrained")
    axes = fig.subplots(2, 3)
    prh = 100 * persson_rh()

    def panel(ax, cols, scale, ylabel, title_):
        for col, lab, c in cols:
            ax.plot(rh, h[col].to_numpy(float) / scale, "o-", color=c, ms=4, label=lab)
            if dry is not None and math.isfinite(_num(dry[col])):
                ax.axhline(_num(dry[col]) / scale, color=c, ls="--", lw=1, label=f"{lab} dry")
        ax.axvline(prh, color="0.5", ls=":", lw=1, label="2|r_k| = 3 h_rms")
        ax.set_xlabel("RH (%)")
        ax.set_ylabel(ylabel)
        ax.set_title(title_, fontsize=10)
        ax.legend(fontsize=7)
        ax.grid(alpha=0.3)

    panel(axes[0, 0], [("static_friction_force", "F_s", "C0")], 1e-6, "static friction (uN)",
          "static friction force")
    panel(axes[0, 1], [("presliding_displacement", "delta_s", "C1")], 1e-9, "pre-sliding displacement (nm)",
          "pre-sliding displacement at the onset")
    panel(axes[0, 2], [("stiffness_A", "A", "C0"), ("stiffness_B", "B", "C1"), ("stiffness_C", "C", "C2")], 1e3,
          "K_L (kN/m)", "lateral stiffness (last reloading branch)")
    panel(axes[1, 0], [("dissipated_energy", "last cycle", "C3")], 1e-15, "dissipated energy (fJ)",
          "dissipated energy per cycle")
    panel(axes[1, 1], [("capillary_force", "friction run, F_x = 0", "C0"),
                       ("capillary_kind_force", "capillary kind", "C3")], 1e-6, "F_cap (uN), < 0 tensile",
          "capillary force of the zero-load state")
    panel(axes[1, 2], [("contact_area", "A_c", "C2")], 1e-12, "contact area (um^2)", "contact area at F_x = 0")
    if title is None:
        a = table.attrs
        title = (f"Rigid ball R = 100 um on rough SiO2 (rms 5 nm, L_ac 0.5 um), F0 = 10 uN, mu = 0.2; "
                 f"{a.get('n', '?')}^2 cells on {a.get('window', float('nan')) * 1e6:g} um")
    fig.suptitle(title, fontsize=10)
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=110)
    return atomic_write_bytes(path, buf.getvalue())


# ----------------------------------------------------------------------------- entry

def main(argv=None) -> int:
    """``python -m studies.humid_friction [--out DIR] [--quick] [--no-run] [--max-points K]``:
    run (resumable), gather ``<out>/humid_friction.csv``, ``humid_friction_findings.csv``,
    ``humid_friction.md`` (the table) and ``humid_friction.png``."""
    import argparse
    import time

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", type=Path, default=None,
                    help="results folder (default results/humid_friction, results/humid_friction_quick with --quick)")
    ap.add_argument("--quick", action="store_true", help="32^2 cells, two RH, one short loop (a test of the machinery)")
    ap.add_argument("--no-run", action="store_true", help="only gather what is there")
    ap.add_argument("--max-points", type=int, default=None, help="run at most this many missing points")
    ap.add_argument("--quiet", action="store_true")
    args = ap.parse_args(argv)
    out = args.out or Path("results") / ("humid_friction_quick" if args.quick else "humid_friction")
    out.mkdir(parents=True, exist_ok=True)
    flat = out / "humid_friction_flat.npy"
    t0 = time.perf_counter()
    if args.no_run:
        write_flat(flat, args.quick)
        spec = sweep_spec(flat, args.quick)
    else:
        spec, res = run_study(out, args.quick, progress=not args.quiet, max_points=args.max_points)
        if not args.quiet:
            print(f"sweep: {res.n_ok} of {res.n_points} points ok ({res.n_run} run now), {res.n_failed} failed "
                  f"({time.perf_counter() - t0:.0f} s)")
    table = gather(spec, out)
    table.to_csv(out / "humid_friction.csv", index=False)
    import pandas as pd

    fnd = findings(table)
    pd.DataFrame(fnd).to_csv(out / "humid_friction_findings.csv", index=False)
    md = markdown_table(table)
    (out / "humid_friction.md").write_text(md + "\n", encoding="utf-8")
    plot_study(table, out / "humid_friction.png")
    if not args.quiet:
        print(md)
        for f in fnd:
            print(f"[{f['verdict']}] {f['expected']}\n    ours: {f['ours']}")
        print(f"Persson RH (2|r_k| = 3 h_rms): {persson_rh():.4f}")
        print(f"wrote {out / 'humid_friction.csv'}, {out / 'humid_friction.md'}, {out / 'humid_friction.png'}")
    return 0


if __name__ == "__main__":
    import sys

    sys.exit(main())
