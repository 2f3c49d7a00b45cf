"""Window versus whole (issue 20 item 4, the thesis' first recommendation): when does a
2-10 um window of a rough surface represent the contact of a whole burl?

Answer (one surface realisation, numbers below; findings, not targets):

* **Contact area and mean gap: a window of 5 um (5 roll-off wavelengths) or more represents
  the burl; 2 um does not.**  At 30 nm cells the 5 and 10 um windows give the real contact
  fraction of the whole solution over the same cells within 4 % and the mean gap within 5 %, at
  the centre and at the edge, free or periodic alike; the 2 um windows (2 roll-off wavelengths)
  miss it by -7 to -20 % (area) and +8 to +13 % (gap).  The boundary matters less than the size:
  free and periodic differ by at most 7 points.
* **Static friction coefficient F_s/F_N: 5 um or more represents it (within 3 %), 2 um within
  10 %.**  With Coulomb friction and adhesion F_s ~ mu F0+ (F0+ = F + adhesive force, F_s/
  (mu F0+) = 0.94-0.98 everywhere), so F_s/F_N carries the local adhesive-to-compressive ratio,
  which a window at its local nominal pressure reproduces.
* **Pre-sliding displacement: no window represents the burl.**  Every window under-predicts
  it, by 28-83 % (burl 3.26 nm; free windows 0.60 -> 2.34 nm as they grow from 2 to 10 um,
  periodic cells 0.54 -> 1.37 nm).  The burl's pre-sliding is set by its own tangential
  compliance (the whole contact's size, Mindlin-like), which a window lacks: a free window has
  the compliance of a patch of its own size, a periodic cell none at the macroscopic scale (its
  q = 0 mode carries no displacement), so the periodic cell is the worse estimate and neither
  converges with window size up to 10 um.
* **Dugdale pull-off: no window represents the burl; the pull-off stress is not an intensive
  quantity here.**  The whole burl lets go at -2.46 uN (7.8 kPa over pi b^2); every window at
  -0.6 to -5.9 uN, i.e. the same few first-touch asperities whatever the window's area, so the
  stress a window predicts falls as 1/A (2 um: 100-180x the burl's, 5 um: 12-25x, 10 um: -21 %
  at the centre, +280 % at the edge).  These forces are one to ten cells of the Dugdale stress
  sigma0 dx^2 = 0.62 uN (the 10 um centre windows' -0.6158 uN is one cell): the cohesive zone
  is 0.2-0.6 cells wide (the runs warn), so the values are grid-set; the conclusion that the
  pull-off of this non-sticky interface (rms 2 nm on Si; on a trial map the unloading from the
  clamp load retraced the loading, see Set-up) is not extensive does not hang on them.
* **Capillary pull-off at RH 0.5: extensive, converging with window size, and the whole
  burl's within the windows' range.**  The windows' capillary stress is 19-38 MPa at 2 um (centre and edge differ by
  2x), 22-25 MPa at 5 um and 27-29 MPa at 10 um (free and periodic within 4 %): the menisci
  fill the area, so the stress is intensive and the 10 um windows agree with each other.  The
  whole burl's capillary pull-off, computed by the study with ``[solver] method = "normcg"``
  (``whole_capillary_method`` in :data:`FULL`; Polonsky-Keer did not finish at 384^2), is 25.8
  MPa on the study's 384^2 map (1 of its 19 unloading states did not converge: flagged, and the
  pull-off taken over the others), and 25.4 MPa on the full 768^2 map, computed apart (52 min
  of CPU): grid-converged to 1.5 % (documentation, Studies).

Full study (measured 2026-11-26, ``python -m studies.burl_windows --out /tmp/burl_windows``,
on a shared 2-core machine: whole burl 98 s wall (768^2 normal 9.9 s, 384^2 normal 1.6 s,
pull-off 0.5 s, tangential ramp 86 s), 60 window points about 110 s of CPU; with the whole
burl's capillary pull-off, 2026-11-27: 4 min 11 s wall in all, whole burl 163 s, windows 86 s).  p_nom: the nominal
pressure of the 60 nm solve over the window (the 30 nm solve gives 32 MPa instead of 42 for the
2 um centre window, within 6 % elsewhere); A_r/A and mean gap: window / whole over the same
cells; sigma_po = -F_po / A (whole: over pi b^2); sigma_cap: capillary pull-off stress at
RH 0.5; delta_s: pre-sliding displacement; in brackets window / whole - 1 (markdown)::

    | window | pos.   | bound.   | p_nom MPa | A_r/A 30 nm: win / whole   | A_r/A 60 nm: win / whole   | mean gap nm 30 nm    |
    |--------|--------|----------|-----------|----------------------------|----------------------------|----------------------|
    | whole  | -      | free     | 50.0      | 0.0614 over pi b^2         | 0.0683 over pi b^2         | -                    |
    | 2 um   | centre | free     | 42.2      | 0.0301 / 0.0363 (-17 %)    | 0.0433 / 0.0467 (-7 %)     | 3.73 / 3.29 (+13 %)  |
    | 2 um   | centre | periodic | 42.2      | 0.0292 / 0.0363 (-20 %)    | 0.0433 / 0.0467 (-7 %)     | 3.67 / 3.29 (+11 %)  |
    | 2 um   | edge   | free     | 26.0      | 0.0432 / 0.0503 (-14 %)    | 0.0493 / 0.0562 (-12 %)    | 2.84 / 2.63 (+8 %)   |
    | 2 um   | edge   | periodic | 26.0      | 0.0466 / 0.0503 (-7 %)     | 0.0519 / 0.0562 (-8 %)     | 2.84 / 2.63 (+8 %)   |
    | 5 um   | centre | free     | 36.8      | 0.0484 / 0.0484 (+0 %)     | 0.0539 / 0.0530 (+2 %)     | 3.27 / 3.22 (+1 %)   |
    | 5 um   | centre | periodic | 36.8      | 0.0486 / 0.0484 (+0 %)     | 0.0529 / 0.0530 (-0 %)     | 3.24 / 3.22 (+0 %)   |
    | 5 um   | edge   | free     | 57.0      | 0.0691 / 0.0720 (-4 %)     | 0.0804 / 0.0812 (-1 %)     | 2.85 / 2.75 (+4 %)   |
    | 5 um   | edge   | periodic | 57.0      | 0.0717 / 0.0720 (-0 %)     | 0.0833 / 0.0812 (+3 %)     | 2.72 / 2.75 (-1 %)   |
    | 10 um  | centre | free     | 39.7      | 0.0529 / 0.0538 (-2 %)     | 0.0589 / 0.0600 (-2 %)     | 2.92 / 2.88 (+1 %)   |
    | 10 um  | centre | periodic | 39.7      | 0.0539 / 0.0538 (+0 %)     | 0.0607 / 0.0600 (+1 %)     | 2.88 / 2.88 (+0 %)   |
    | 10 um  | edge   | free     | 42.1      | 0.0563 / 0.0565 (-0 %)     | 0.0627 / 0.0632 (-1 %)     | 2.81 / 2.94 (-4 %)   |
    | 10 um  | edge   | periodic | 42.1      | 0.0569 / 0.0565 (+1 %)     | 0.0636 / 0.0632 (+1 %)     | 2.79 / 2.94 (-5 %)   |

    | window | pos.   | bound.   | F_po uN | sigma_po kPa        | sigma_cap MPa | F_s/F_N        | delta_s nm   |
    |--------|--------|----------|---------|---------------------|---------------|----------------|--------------|
    | whole  | -      | free     | 2.46    | 7.84                | 25.8          | 0.2180         | 3.26         |
    | 2 um   | centre | free     | 5.86    | 1.41e+03 (+17856 %) | 19.4          | 0.1963 (-10 %) | 0.60 (-82 %) |
    | 2 um   | centre | periodic | 5.16    | 1.24e+03 (+15707 %) | 20.1          | 0.2012 (-8 %)  | 0.62 (-81 %) |
    | 2 um   | edge   | free     | 3.14    | 753 (+9508 %)       | 38.4          | 0.2304 (+6 %)  | 0.68 (-79 %) |
    | 2 um   | edge   | periodic | 3.13    | 753 (+9504 %)       | 37.2          | 0.2284 (+5 %)  | 0.54 (-83 %) |
    | 5 um   | centre | free     | 4.93    | 194 (+2374 %)       | 22.1          | 0.2174 (-0 %)  | 1.30 (-60 %) |
    | 5 um   | centre | periodic | 4.93    | 194 (+2374 %)       | 22.9          | 0.2177 (-0 %)  | 0.91 (-72 %) |
    | 5 um   | edge   | free     | 2.41    | 94.8 (+1109 %)      | 25.1          | 0.2166 (-1 %)  | 1.87 (-43 %) |
    | 5 um   | edge   | periodic | 2.42    | 95.4 (+1117 %)      | 24.8          | 0.2170 (-1 %)  | 1.30 (-60 %) |
    | 10 um  | centre | free     | 0.62    | 6.21 (-21 %)        | 27.0          | 0.2154 (-1 %)  | 1.80 (-45 %) |
    | 10 um  | centre | periodic | 0.62    | 6.21 (-21 %)        | 28.0          | 0.2229 (+2 %)  | 1.32 (-59 %) |
    | 10 um  | edge   | free     | 2.96    | 29.8 (+280 %)       | 28.3          | 0.2243 (+3 %)  | 2.34 (-28 %) |
    | 10 um  | edge   | periodic | 2.97    | 29.9 (+282 %)       | 29.0          | 0.2221 (+2 %)  | 1.37 (-58 %) |

Resolution.  Roughness: short cut-off 0.3 um = 10 cells at 30 nm, 5 at 60 nm; roll-off 1 um =
33 / 17 cells; rms slope 0.016.  Contact spots of the whole burl: 501 spots, mean equivalent
diameter 6.7 cells (largest 20) at 30 nm; 505 spots, 3.6 cells (largest 10) at 60 nm, where the
contact fraction is 11 % higher (0.0683 against 0.0614 over the top): the 60 nm values of
every kind carry that offset, window and whole alike, which is why the comparisons pair
values of one cell size.  The Dugdale cohesive zone is not resolved at either cell size
(0.2-0.8 cells; h0 = 0.29 nm is crossed within a cell), so adhesive forces are grid-set; the
stick zone of the whole burl's ramp is at most 2 cells across (the run warns), so its F_s and
delta_s are the grid's estimate.  One surface realisation: the 2 um scatter (centre against
edge) is partly statistical, and another seed would move it.

What is weak: one realisation; the 60 nm map for the kinds (spots 3.6 cells); adhesive forces
grid-set; the whole-burl capillary reference has one unconverged unloading state; the windows
are pressed by a flat, so the crown's 1 nm sag and the pressure gradient across an edge window
are absent from them (probably why the 10 um edge window's mean gap is 4-5 % low, the only
10 um quantity off by more than 3 % apart from pre-sliding and pull-off).

Set-up
------
Body 2 is a rigid burl (``shape = { kind = "burl" }``: flat top of radius b = 10 um, edge
rounding R = 20 um, crown 50 mm, i.e. 1 nm of sag at the top's edge), body 1 an elastic Si
wafer (E = 130 GPa, nu = 0.28) with a self-affine rough top (Persson PSD, H = 0.8, rms 2 nm,
roll-off 1 um, short cut-off 0.3 um, one realisation, :func:`surface`).  Dugdale adhesion
dgamma = 50 mJ/m^2, z0 = 0.3 nm; Coulomb friction mu = 0.2; the capillary pull-off at RH 0.5
with SiO2 water films on both bodies (native oxide).  The clamp force is 15.7 mN: 50 MPa of
mean pressure over the top (pi b^2).

The surface is generated once on the whole grid and every window is cut from that map at the
same cell size (``roughness = { kind = "array", crop = ... }``, no resampling).  Windows of 2,
5 and 10 um (even cell counts) sit at the burl's centre and at its edge (the window's outer
side on the top's rim r = b, centred on the x axis).  Each window is loaded at the nominal
pressure the whole solve gives there (the mean traction over the window's cells in the
whole-burl solution, tensile Dugdale stress included), pressed by a rigid flat, and solved
twice: (a) free boundary (the crop alone on a half-space, the flat ending at the window's edge,
like a rough flat punch) and (b) a periodic cell of the same crop (the crop is not periodic:
its opposite edges do not match).

Two cell sizes.  The normal solves (contact fraction, mean gap) run on the 30 nm map (whole
burl 768^2 cells, 23 um); every kind, whole and windows alike, runs on the same map coarsened
2 x 2 (block means: 384^2 cells of 60 nm), where the whole burl's pull-off and tangential ramp
fit the budget.  Per window and per whole burl the kinds are ``normal`` (real contact fraction,
mean gap), ``pulloff`` (Dugdale; ``[humidity] rh = 0.5`` for the capillary pull-off) and
``partial_slip`` (a force ramp at the nominal load to gross slip, the onset bisected to 1e-3
mu F0+: static friction, pre-sliding displacement).  The whole burl's capillary pull-off is
left out of the full study (see the answer above); the quick mode keeps it.

The pull-offs start from zero external load (the bodies brought into contact and let go), not
from the clamp load: on a trial realisation of the whole burl (384^2, another seed) the start
at the 15.7 mN preload cost 420 s of CPU (``solve_at_force`` spent its 60 solves without
reaching the preload within 0.1 %, and two unloading steps stalled at 2,300 Polonsky-Keer
iterations) and gave the same pull-off force, -1.8475 uN to all digits printed, as the zero-load
start (1.5 s): at these parameters the unloading retraces the loading (no adhesion hysteresis),
so the preload does not matter.

What is compared (:func:`gather`):

* contact fraction A_r/A and mean gap of a window against the whole solution restricted to the
  window's cells (a local comparison, at each cell size);
* pull-off stress sigma = -F_pull-off / A: a window's A is its area, the burl's A = pi b^2
  (what a window scaled up to the burl would predict);
* static friction coefficient F_s / F_N (gross-slip onset over the normal load) and the
  pre-sliding displacement (rigid shift from F_t = 0 to the onset).

Every run is a resumable sweep point (``OUT/whole/points``, ``OUT/windows/points``, runs kept
under ``runs/<hash>/``): a killed study recomputes only its missing points.  The windows' loads
are read from the whole normal solves, so the whole burl runs first.

``python -m studies.burl_windows --out DIR [--quick]`` writes ``burl_windows.csv`` (one row per
window size, position and boundary), ``burl_windows_whole.csv`` (the whole-burl values),
``burl_windows.md`` and ``burl_windows.png``.
"""

from __future__ import annotations

import json
import math
import os
from pathlib import Path

import numpy as np

__all__ = ["E_WAFER", "NU_WAFER", "BURL_RADIUS", "EDGE_RADIUS", "CROWN", "RMS", "HURST", "ROLLOFF",
           "SHORT_CUTOFF", "SEED", "DGAMMA", "Z0", "PRESSURE", "FRICTION", "RH", "FULL", "QUICK",
           "config", "surface", "write_surfaces", "window_cells", "whole_spec", "window_locals",
           "window_spec", "run_study", "gather", "markdown_table", "plot_study", "main"]

#: The wafer (body 1, elastic, rough) and the rigid burl (body 2).
E_WAFER = 130e9
NU_WAFER = 0.28
BURL_RADIUS = 10e-6
EDGE_RADIUS = 20e-6
CROWN = 50e-3
#: The wafer's top: self-affine (Persson PSD), one realisation.
RMS = 2e-9
HURST = 0.8
ROLLOFF = 1e-6
SHORT_CUTOFF = 0.3e-6
SEED = 20
#: Dugdale adhesion, friction, humidity.
DGAMMA = 0.05
Z0 = 0.3e-9
FRICTION = 0.2
RH = 0.5
#: Mean pressure over the burl's top (Pa): the clamp force is PRESSURE * pi b^2.
PRESSURE = 50e6
#: The tangential ramp, in units of mu F_N: it ends at gross slip and the onset is bisected to
#: 1e-3 mu F0+ (runs.partial_slip), so only the bracket matters, not the step.
RAMP = (0.0, 0.5, 0.8, 0.95, 1.05, 1.15, 1.3, 1.6, 2.0, 3.0)

#: The full study.  Two cell sizes: the normal solves (contact fraction, mean gap) on the whole
#: map of ``n``^2 cells of ``dx``; every kind (normal, pull-off, friction, capillary pull-off) on
#: that map coarsened by ``coarse`` (block means), whole burl and windows alike.
FULL = {"n": 768, "dx": 30e-9, "radius": BURL_RADIUS, "edge_radius": EDGE_RADIUS, "crown": CROWN,
        "rolloff": ROLLOFF, "short_cutoff": SHORT_CUTOFF, "windows": (2e-6, 5e-6, 10e-6),
        "capillary_windows": (2e-6, 5e-6, 10e-6), "whole_capillary": True, "whole_capillary_method": "normcg",
        "coarse": 2, "steps": 16, "refine": 3}
#: Quick mode (tests, < 30 s): a 2 um burl on 96^2 cells of 50 nm (48^2 of 100 nm), windows of 1
#: and 1.6 um.
QUICK = {"n": 96, "dx": 50e-9, "radius": 2e-6, "edge_radius": 10e-6, "crown": CROWN,
         "rolloff": 1e-6, "short_cutoff": 0.6e-6, "windows": (1.0e-6, 1.6e-6),
         "capillary_windows": (1.0e-6,), "whole_capillary": True, "coarse": 2, "steps": 8, "refine": 2}

POSITIONS = ("centre", "edge")
BOUNDARIES = ("free", "periodic")
#: Water at 295 K: surface tension (N/m) for the Kelvin radius in the header.
GAMMA_WATER = 0.0725


def config(quick: bool = False) -> dict:
    """The study's sizes: :data:`QUICK` or :data:`FULL` (a copy)."""
    return dict(QUICK if quick else FULL)


def force_of(cfg: dict) -> float:
    """The clamp force (N): :data:`PRESSURE` over the burl's top, pi b^2."""
    return PRESSURE * math.pi * cfg["radius"] ** 2


# ----------------------------------------------------------------------------- the surface

def surface(cfg: dict):
    """The wafer's rough top on the whole grid (``cfg["n"]``^2 cells of ``cfg["dx"]``).

    Returns
    -------
    heights : ndarray (n, n)
        m, zero mean, rms :data:`RMS` (body 1's topography, positive toward the burl).
    info : dict
        ``n``, ``dx``, ``size``, ``seed``, ``rms``, ``hurst``, ``rolloff``, ``short_cutoff``,
        ``rms_slope`` (forward differences on this grid).
    """
    from tribobem.geometry import rms_slope, self_affine_surface
    from tribobem.grid import Grid

    n, dx = int(cfg["n"]), float(cfg["dx"])
    grid = Grid.square(n, n * dx, periodic=False)
    h = self_affine_surface(grid, HURST, rms_height=RMS, rolloff_wavelength=cfg["rolloff"],
                            short_cutoff=cfg["short_cutoff"], seed=SEED)
    info = {"n": n, "dx": dx, "size": n * dx, "seed": SEED, "rms": RMS, "hurst": HURST,
            "rolloff": float(cfg["rolloff"]), "short_cutoff": float(cfg["short_cutoff"]),
            "rms_slope": float(rms_slope(h, grid))}
    return h, info


def coarsen(h: np.ndarray, k: int) -> np.ndarray:
    """Block means of ``k x k`` cells (the same surface seen by cells k times larger)."""
    n0, n1 = h.shape
    return h[: n0 - n0 % k, : n1 - n1 % k].reshape(n0 // k, k, n1 // k, k).mean(axis=(1, 3))


def _save(path: Path, array: np.ndarray, info: dict) -> None:
    tmp = path.with_name("." + path.name + ".tmp.npy")
    np.save(tmp, array)
    os.replace(tmp, path)
    path.with_suffix(".json").write_text(json.dumps(info, indent=1) + "\n", encoding="utf-8")


def write_surfaces(outdir, cfg: dict) -> dict:
    """Write the whole map (``surface.npy``) and its coarsened copy (``surface_coarse.npy``)
    with their info (``.json``) into ``outdir``, unless maps with the same info are there.

    Returns
    -------
    dict
        ``fine`` and ``coarse``: absolute paths (absolute: the sweep hashes then do not depend on
        the working folder); ``info``: the fine map's info.
    """
    outdir = Path(outdir)
    outdir.mkdir(parents=True, exist_ok=True)
    fine, coarse = outdir / "surface.npy", outdir / "surface_coarse.npy"
    want = {"n": int(cfg["n"]), "dx": float(cfg["dx"]), "seed": SEED, "rms": RMS, "hurst": HURST,
            "rolloff": float(cfg["rolloff"]), "short_cutoff": float(cfg["short_cutoff"])}
    info = None
    if fine.is_file() and coarse.is_file() and fine.with_suffix(".json").is_file():
        try:
            have = json.loads(fine.with_suffix(".json").read_text(encoding="utf-8"))
            if all(math.isclose(float(have[k]), float(v), rel_tol=1e-12) for k, v in want.items()):
                info = have
        except (OSError, ValueError, KeyError):
            info = None
    if info is None:
        h, info = surface(cfg)
        _save(fine, h, info)
        k = int(cfg["coarse"])
        _save(coarse, coarsen(h, k), dict(info, n=int(cfg["n"]) // k, dx=float(cfg["dx"]) * k, coarsened_from=str(fine)))
    return {"fine": str(fine.resolve()), "coarse": str(coarse.resolve()), "info": info}


# ----------------------------------------------------------------------------- windows

def window_cells(cfg: dict, size: float, position: str, coarse: bool = False) -> tuple[int, int, int]:
    """Cell range of a window on the whole grid: ``(ix0, iy0, m)``, the window being cells
    ``[ix0, ix0 + m) x [iy0, iy0 + m)``.

    ``m`` is the even cell count nearest ``size``; ``"centre"``: centred on the burl's axis (the
    grid's centre); ``"edge"``: its outer side (+x) on the top's rim r = b (to the nearest cell),
    centred in y.  ``coarse``: on the coarsened grid.
    """
    k = int(cfg["coarse"]) if coarse else 1
    n, dx = int(cfg["n"]) // k, float(cfg["dx"]) * k
    m = 2 * max(1, int(round(size / (2 * dx))))
    c = n // 2
    if position == "centre":
        ix0 = c - m // 2
    elif position == "edge":
        ix0 = c + int(round(cfg["radius"] / dx)) - m
    else:
        raise ValueError(f"position must be 'centre' or 'edge', got {position!r}")
    iy0 = c - m // 2
    if ix0 < 0 or ix0 + m > n:
        raise ValueError(f"a {size:g} m window at the {position} does not fit the whole grid")
    return ix0, iy0, m


def _base(paths: dict, cfg: dict) -> dict:
    """What every run shares: the wafer with the coarse whole map, a rigid flat body 2, Dugdale."""
    size = int(cfg["n"]) * float(cfg["dx"])
    return {
        "kind": "normal",
        "grid": {"n": int(cfg["n"]) // int(cfg["coarse"]), "size": size, "periodic": False},
        "body1": {"name": "Si wafer", "E": E_WAFER, "nu": NU_WAFER,
                  "roughness": {"kind": "array", "path": paths["coarse"], "size": size}},
        "body2": {"name": "rigid burl", "rigid": True},
        "adhesion": {"model": "dugdale", "work_of_adhesion": DGAMMA, "z0": Z0},
        "output": {"fields": "none", "figures": False, "report": False},
    }


def _kind_points(prefix: str, force: float, cfg: dict, kinds) -> list[dict]:
    """Points of the ``kinds`` (``normal``, ``pulloff``, ``friction``, ``capillary``) at normal
    force ``force`` (N; the pull-offs start from zero external load, see the module docstring)."""
    f = float(f"{force:.6g}")  # six digits: the point hashes do not hang on the last bits
    mu_f = FRICTION * f
    po = {"kind": "pulloff", "load.loading": False, "load.steps": int(cfg["steps"]), "load.refine": int(cfg["refine"])}
    table = {
        "normal": {"kind": "normal", "load.force": f, "output.fields": "last"},
        "pulloff": dict(po),
        "friction": {"kind": "partial_slip", "load.force": f, "friction.coefficient": FRICTION,
                     "friction.slip": "total",
                     "friction.tangential_forces": [float(f"{mu_f * r:.6g}") for r in RAMP]},
        "capillary": dict(po, **{"humidity.rh": [RH], "body1.film.isotherm": "SiO2", "body2.film.isotherm": "SiO2"}),
    }
    return [dict(table[k], name=f"{prefix}/{k}") for k in kinds]


def whole_spec(paths: dict, cfg: dict, quick: bool = False) -> dict:
    """The whole burl's sweep: the normal solve on the fine map (``whole_fine``), and every
    kind on the coarse map (``whole``); their fields give the windows' loads."""
    shape = {"body2.shape.kind": "burl", "body2.shape.radius": float(cfg["radius"]),
             "body2.shape.edge_radius": float(cfg["edge_radius"]), "body2.shape.crown": float(cfg["crown"])}
    force = force_of(cfg)
    fine = {"grid.n": int(cfg["n"]), "body1.roughness.path": paths["fine"]}
    pts = [dict(p, **shape, **fine) for p in _kind_points("whole_fine", force, cfg, ["normal"])]
    kinds = ["normal", "pulloff", "friction"] + (["capillary"] if cfg.get("whole_capillary", True) else [])
    pts += [dict(p, **shape) for p in _kind_points("whole", force, cfg, kinds)]
    if cfg.get("whole_capillary_method"):
        # the whole burl's humid pull-off: Polonsky-Keer does not finish on the full map (384^2),
        # NormCG does (142 s of CPU); the windows keep the default solver
        for p in pts:
            if p["name"].endswith("/capillary"):
                p["solver.method"] = cfg["whole_capillary_method"]
    return {"name": "burl-windows-whole" + ("-quick" if quick else ""),
            "description": "a rigid burl on a rough Si wafer: the whole contact",
            "base": _base(paths, cfg), "keep_runs": True, "scheduler": "synchronous",
            "outputs": ["converged"], "points": pts}


def window_locals(fields_path, cfg: dict, coarse: bool = False) -> dict:
    """What the whole solution says over each window: ``{(size, position): {...}}`` with
    ``nominal_pressure`` (Pa, mean traction over its cells, tensile included),
    ``contact_fraction`` (cells with gap = 0), ``mean_gap`` (m), ``adhesive_fraction`` (cells in
    the Dugdale zone), ``window_rms`` (rms of the crop, m), the cell range (``ix0``, ``iy0``,
    ``cells``) and the window's side ``length`` (m).  ``coarse``: ``fields_path`` is a solution
    on the coarse map."""
    import xarray as xr

    with xr.open_dataset(fields_path) as ds:
        p = ds["pressure"].isel(step=-1).values
        g = ds["gap"].isel(step=-1).values
        c = ds["contact"].isel(step=-1).values != 0
        a = ds["adhesive"].isel(step=-1).values != 0
        h = ds["roughness_body1"].values if "roughness_body1" in ds else None
    k = int(cfg["coarse"]) if coarse else 1
    dx = float(cfg["dx"]) * k
    out = {}
    for size in cfg["windows"]:
        for pos in POSITIONS:
            ix0, iy0, m = window_cells(cfg, size, pos, coarse)
            sl = (slice(ix0, ix0 + m), slice(iy0, iy0 + m))
            out[(float(size), pos)] = {
                "ix0": ix0, "iy0": iy0, "cells": m, "length": m * dx,
                "nominal_pressure": float(p[sl].mean()), "contact_fraction": float(c[sl].mean()),
                "mean_gap": float(g[sl].mean()), "adhesive_fraction": float(a[sl].mean()),
                "window_rms": float(np.std(h[sl])) if h is not None else math.nan}
    return out


def _prefix(size: float, pos: str, bound: str) -> str:
    return f"w{size * 1e6:g}um-{pos}-{bound}"


def window_spec(paths: dict, cfg: dict, local_fine: dict, local_coarse: dict, quick: bool = False) -> dict:
    """The windows' sweep: per window size, position and boundary, the normal solve on the fine
    map and every kind on the coarse map, each at the nominal load the whole solve of that map
    gives over the window (``local_*``: :func:`window_locals`)."""
    pts = []
    for size in cfg["windows"]:
        for pos in POSITIONS:
            for bound in BOUNDARIES:
                for coarse in (False, True):
                    k = int(cfg["coarse"]) if coarse else 1
                    d = float(cfg["dx"]) * k
                    ix0, iy0, m = window_cells(cfg, size, pos, coarse)
                    loc = (local_coarse if coarse else local_fine)[(float(size), pos)]
                    lw = m * d
                    force = loc["nominal_pressure"] * lw * lw
                    if not force > 0:
                        continue  # a window in tension has no nominal load to hold (not the case here)
                    over = {"grid.n": m, "grid.size": lw, "grid.periodic": bound == "periodic",
                            "body1.roughness.path": paths["coarse" if coarse else "fine"],
                            "body1.roughness.crop.x0": ix0 * d, "body1.roughness.crop.y0": iy0 * d,
                            "body1.roughness.crop.lx": lw, "body1.roughness.crop.ly": lw}
                    if coarse:
                        kinds = ["normal", "pulloff", "friction"]
                        if any(math.isclose(size, s) for s in cfg["capillary_windows"]):
                            kinds.append("capillary")
                        prefix = _prefix(size, pos, bound)
                    else:
                        kinds, prefix = ["normal"], _prefix(size, pos, bound) + "-fine"
                    pts += [dict(p, **over) for p in _kind_points(prefix, force, cfg, kinds)]
    return {"name": "burl-windows" + ("-quick" if quick else ""),
            "description": "windows of the burl's rough contact at its nominal pressure, free and periodic",
            "base": _base(paths, cfg), "keep_runs": True, "scheduler": "synchronous", "outputs": ["converged"],
            "points": pts}


def _run_dirs(spec, outdir: Path) -> dict:
    """point name -> (record or None, run folder) of a sweep."""
    from tribobem.sweep import load_sweep, read_points

    spec = load_sweep(spec)
    records = read_points(outdir) if (Path(outdir) / "points").is_dir() else {}
    return {o["name"]: (records.get(h), Path(outdir) / "runs" / h) for h, o in spec.tasks()}


def _fields_of(runs: dict, name: str):
    rec, run = runs.get(name, (None, None))
    if rec and rec.get("status") == "ok" and (run / "fields.nc").is_file():
        return run / "fields.nc"
    return None


def run_study(outdir, quick: bool = False, progress: bool = False, max_points: int | None = None):
    """Write the maps (once), run the whole burl, then the windows (both resumable).

    Returns
    -------
    (whole spec dict, window spec dict or None, [SweepResult, SweepResult or None])
        The window sweep needs both whole normal solves; without them (``max_points`` stopped
        the first sweep early, or they failed) the windows are not run.
    """
    from tribobem.sweep import run_sweep

    outdir = Path(outdir)
    cfg = config(quick)
    paths = write_surfaces(outdir, cfg)
    ws = whole_spec(paths, cfg, quick)
    r1 = run_sweep(ws, outdir / "whole", scheduler="synchronous", progress=progress, max_points=max_points)
    runs = _run_dirs(ws, outdir / "whole")
    ff, fc = _fields_of(runs, "whole_fine/normal"), _fields_of(runs, "whole/normal")
    left = None if max_points is None else max_points - r1.n_run
    if ff is None or fc is None or (left is not None and left <= 0):
        return ws, None, [r1, None]
    wsp = window_spec(paths, cfg, window_locals(ff, cfg), window_locals(fc, cfg, coarse=True), quick)
    r2 = run_sweep(wsp, outdir / "windows", scheduler="synchronous", progress=progress, max_points=left)
    return ws, wsp, [r1, r2]


# ----------------------------------------------------------------------------- gathering

def _read_json(path: Path):
    try:
        return json.loads(path.read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return None


def _num(v) -> float:
    if isinstance(v, list):
        v = v[0] if v else None
    try:
        return math.nan if v is None else float(v)
    except (TypeError, ValueError):
        return math.nan


def _summary(runs: dict, name: str) -> dict:
    rec, run = runs.get(name, (None, None))
    if not rec or rec.get("status") != "ok":
        return {}
    return _read_json(run / "summary.json") or {}


def _field_stats(fields_path) -> dict:
    """Contact fraction (gap = 0), mean gap (m) and mean traction (Pa) of a run's last state."""
    out = {"contact_fraction": math.nan, "mean_gap": math.nan, "mean_pressure": math.nan}
    if fields_path is None:
        return out
    import xarray as xr

    with xr.open_dataset(fields_path) as ds:
        out["contact_fraction"] = float((ds["contact"].isel(step=-1).values != 0).mean())
        out["mean_gap"] = float(ds["gap"].isel(step=-1).values.mean())
        out["mean_pressure"] = float(ds["pressure"].isel(step=-1).values.mean())
    return out


def _spots(fields_path, dx: float) -> dict:
    """Contact spots of a run's last state: count, mean and largest equivalent diameter (cells)."""
    import xarray as xr
    from scipy import ndimage

    with xr.open_dataset(fields_path) as ds:
        c = ds["contact"].isel(step=-1).values != 0
    lab, n = ndimage.label(c)
    if n == 0:
        return {"spots": 0, "spot_diameter_cells": math.nan, "largest_spot_cells": math.nan}
    areas = np.bincount(lab.ravel())[1:]
    d = np.sqrt(4 * areas / math.pi)
    return {"spots": int(n), "spot_diameter_cells": float(d.mean()), "largest_spot_cells": float(d.max())}


def _kind_values(runs: dict, prefix: str, area: float, force: float) -> dict:
    """Pull-off stresses, friction values and run facts of the points under ``prefix``."""
    po, cap, fr = (_summary(runs, f"{prefix}/{k}") for k in ("pulloff", "capillary", "friction"))
    fs = _num(fr.get("static_friction_force"))
    out = {"pull_off_force": _num(po.get("pull_off_force")), "capillary_pull_off_force": _num(cap.get("pull_off_force")),
           "static_friction_force": fs, "presliding_displacement": _num(fr.get("presliding_displacement")),
           "repulsive_force": _num(fr.get("repulsive_force")), "adhesive_force": _num(fr.get("adhesive_force")),
           "static_friction_ratio": _num(fr.get("static_friction_ratio"))}
    out["pull_off_stress"] = -out["pull_off_force"] / area
    out["capillary_pull_off_stress"] = -out["capillary_pull_off_force"] / area
    out["friction_coefficient_static"] = fs / force if force > 0 else math.nan
    conv = [s.get("converged") for s in (po, cap, fr) if s]
    out["converged_all"] = bool(all(conv)) if conv else None
    out["n_warnings"] = sum(len(s.get("warnings") or []) for s in (po, cap, fr))
    out["cohesive_zone_cells"] = _num(po.get("cohesive_zone_cells"))
    return out


#: Quantities compared window against whole: (column, reference column, label).
COMPARED = (("contact_fraction_fine", "whole_contact_fraction_fine", "A_r/A (fine)"),
            ("mean_gap_fine", "whole_mean_gap_fine", "mean gap (fine)"),
            ("contact_fraction", "whole_contact_fraction", "A_r/A"),
            ("mean_gap", "whole_mean_gap", "mean gap"),
            ("pull_off_stress", "whole_pull_off_stress", "pull-off stress"),
            ("capillary_pull_off_stress", "whole_capillary_pull_off_stress", "capillary pull-off stress"),
            ("friction_coefficient_static", "whole_friction_coefficient_static", "F_s/F_N"),
            ("presliding_displacement", "whole_presliding_displacement", "pre-sliding displacement"))


def gather(outdir, quick: bool = False):
    """The study's tables from a finished (or partial) run folder.

    Returns
    -------
    table : pandas.DataFrame
        One row per window size, position and boundary: ``size`` (nominal, m), ``length`` (m, the
        even cell count's side on the coarse map), ``cells_fine``, ``cells``, ``position``,
        ``boundary``, ``window_rms`` (m), ``nominal_pressure`` (Pa, from the whole solve on the
        coarse map; ``nominal_pressure_fine`` on the fine one); the window's
        ``contact_fraction``, ``mean_gap`` (coarse map; ``*_fine``: fine map), ``pull_off_stress``,
        ``capillary_pull_off_stress`` (Pa, tensile positive: -F/A), ``static_friction_force``
        (N), ``friction_coefficient_static`` (F_s / F_N), ``presliding_displacement`` (m),
        ``repulsive_force``, ``adhesive_force`` (N, at F_t = 0); ``whole_*`` the whole burl's
        counterpart (local over the window's cells for contact fraction and mean gap; for the
        rest the whole burl's value, the stresses over pi b^2) and ``err_*`` = window / whole - 1.
    whole : pandas.DataFrame
        One row: the whole burl (force, mean pressure over pi b^2, contact fraction over the
        top at both cell sizes, the kinds' values, resolution facts and point run times).
    """
    import pandas as pd

    outdir = Path(outdir)
    cfg = config(quick)
    paths = write_surfaces(outdir, cfg)
    ws = whole_spec(paths, cfg, quick)
    wr = _run_dirs(ws, outdir / "whole")
    ff, fc = _fields_of(wr, "whole_fine/normal"), _fields_of(wr, "whole/normal")
    dxf, k = float(cfg["dx"]), int(cfg["coarse"])
    dxc = dxf * k
    top = math.pi * cfg["radius"] ** 2
    force = float(f"{force_of(cfg):.6g}")
    w = {"force": force, "mean_pressure": force / top, "radius": cfg["radius"], "dx_fine": dxf, "dx": dxc,
         "n_fine": int(cfg["n"]), "n": int(cfg["n"]) // k, "rms": RMS, "rms_slope": paths["info"]["rms_slope"],
         "short_cutoff_cells_fine": cfg["short_cutoff"] / dxf, "short_cutoff_cells": cfg["short_cutoff"] / dxc,
         "rolloff_cells": cfg["rolloff"] / dxc}
    w.update(_kind_values(wr, "whole", top, force))
    for tag, fp, d in (("_fine", ff, dxf), ("", fc, dxc)):
        if fp is None:
            continue
        import xarray as xr

        with xr.open_dataset(fp) as ds:
            x, y = ds["x"].values, ds["y"].values
            c = ds["contact"].isel(step=-1).values != 0
        X, Y = np.meshgrid(x, y, indexing="ij")
        w[f"contact_fraction_top{tag}"] = float(c[np.hypot(X, Y) <= cfg["radius"]].sum() * d * d / top)
        w.update({f"{kk}{tag}": v for kk, v in _spots(fp, d).items()})
    for name, (rec, _) in wr.items():
        w[f"elapsed_{name.replace('/', '_')}"] = _num((rec or {}).get("elapsed"))
    whole = pd.DataFrame([w])

    lf = window_locals(ff, cfg) if ff is not None else {}
    lc = window_locals(fc, cfg, coarse=True) if fc is not None else {}
    rows = []
    wr2 = {}
    if lf and lc:
        wsp = window_spec(paths, cfg, lf, lc, quick)
        wr2 = _run_dirs(wsp, outdir / "windows")
    for size in cfg["windows"]:
        for pos in POSITIONS:
            for bound in BOUNDARIES:
                key = (float(size), pos)
                f_, c_ = lf.get(key, {}), lc.get(key, {})
                prefix = _prefix(size, pos, bound)
                length = c_.get("length", math.nan)
                p_nom = c_.get("nominal_pressure", math.nan)
                fw = float(f"{p_nom * length * length:.6g}") if math.isfinite(p_nom) else math.nan
                r = {"size": float(size), "position": pos, "boundary": bound, "length": length,
                     "cells": c_.get("cells"), "cells_fine": f_.get("cells"),
                     "window_rms": f_.get("window_rms", math.nan), "nominal_pressure": p_nom,
                     "nominal_pressure_fine": f_.get("nominal_pressure", math.nan), "window_force": fw}
                sf = _field_stats(_fields_of(wr2, f"{prefix}-fine/normal"))
                sc = _field_stats(_fields_of(wr2, f"{prefix}/normal"))
                r.update(contact_fraction_fine=sf["contact_fraction"], mean_gap_fine=sf["mean_gap"],
                         contact_fraction=sc["contact_fraction"], mean_gap=sc["mean_gap"])
                r.update(_kind_values(wr2, prefix, length * length if math.isfinite(length) else math.nan, fw))
                r.update(whole_contact_fraction_fine=f_.get("contact_fraction", math.nan),
                         whole_mean_gap_fine=f_.get("mean_gap", math.nan),
                         whole_contact_fraction=c_.get("contact_fraction", math.nan),
                         whole_mean_gap=c_.get("mean_gap", math.nan),
                         whole_pull_off_stress=w["pull_off_stress"],
                         whole_capillary_pull_off_stress=w["capillary_pull_off_stress"],
                         whole_friction_coefficient_static=w["friction_coefficient_static"],
                         whole_presliding_displacement=w["presliding_displacement"])
                for col, ref, _ in COMPARED:
                    a, b = _num(r.get(col)), _num(r.get(ref))
                    r[f"err_{col}"] = a / b - 1.0 if (math.isfinite(a) and math.isfinite(b) and b != 0) else math.nan
                r["elapsed"] = sum(_num((wr2.get(f"{prefix}/{kk}", (None,))[0] or {}).get("elapsed")) or 0.0
                                   for kk in ("normal", "pulloff", "friction", "capillary")
                                   if wr2.get(f"{prefix}/{kk}", (None,))[0])
                rows.append(r)
    table = pd.DataFrame(rows)
    table.attrs.update(cfg=cfg)
    return table, whole


# ----------------------------------------------------------------------------- reporting

def markdown_table(table, whole) -> str:
    """The window-versus-whole table (markdown): per window the value and, in brackets, its
    relative error against the whole burl (``+12 %``)."""

    def f(v, scale=1.0, spec=".3g"):
        v = _num(v)
        return "-" if not math.isfinite(v) else format(v / scale, spec)

    def e(v):
        v = _num(v)
        return "" if not math.isfinite(v) else f" ({100 * v:+.0f} %)"

    wr = whole.iloc[0]
    head = ("| window | position | boundary | p_nom (MPa) | A_r/A fine | A_r/A | mean gap (nm) | "
            "pull-off (kPa) | capillary pull-off (kPa) | F_s/F_N | pre-sliding (nm) |")
    lines = [head, "|" + "---|" * 11,
             f"| whole burl | - | free | {f(wr['mean_pressure'], 1e6)} | {f(wr.get('contact_fraction_top_fine'))} | "
             f"{f(wr.get('contact_fraction_top'))} | - | {f(wr['pull_off_stress'], 1e3)} | "
             f"{f(wr['capillary_pull_off_stress'], 1e3)} | {f(wr['friction_coefficient_static'], 1, '.4f')} | "
             f"{f(wr['presliding_displacement'], 1e-9)} |"]
    for r in table.itertuples():
        lines.append(
            f"| {r.size * 1e6:g} um | {r.position} | {r.boundary} | {f(r.nominal_pressure, 1e6)} | "
            f"{f(r.contact_fraction_fine)} vs {f(r.whole_contact_fraction_fine)}{e(r.err_contact_fraction_fine)} | "
            f"{f(r.contact_fraction)} vs {f(r.whole_contact_fraction)}{e(r.err_contact_fraction)} | "
            f"{f(r.mean_gap, 1e-9)} vs {f(r.whole_mean_gap, 1e-9)}{e(r.err_mean_gap)} | "
            f"{f(r.pull_off_stress, 1e3)}{e(r.err_pull_off_stress)} | "
            f"{f(r.capillary_pull_off_stress, 1e3)}{e(r.err_capillary_pull_off_stress)} | "
            f"{f(r.friction_coefficient_static, 1, '.4f')}{e(r.err_friction_coefficient_static)} | "
            f"{f(r.presliding_displacement, 1e-9)}{e(r.err_presliding_displacement)} |")
    return "\n".join(lines)


def plot_study(table, whole, fields_path, path, title: str | None = None) -> Path:
    """Eight panels: (a) the whole burl's contact pressure with the windows drawn on it; against
    the window size, one line per position (colour) and boundary (solid free, dashed periodic):
    (b) contact fraction and (c) mean gap relative to the whole solution over the window (fine
    map), (d) the same on the coarse map, (e) pull-off stress and (f) capillary pull-off stress
    beside the whole burl's (black line), (g) F_s/F_N relative to the whole burl's, (h)
    pre-sliding displacement beside the whole burl's."""
    import io

    from matplotlib.figure import Figure
    from matplotlib.patches import Rectangle

    from tribobem.output.atomic import atomic_write_bytes

    cfg = table.attrs.get("cfg") or FULL
    wr = whole.iloc[0]
    fig = Figure(figsize=(17, 8.2), layout="constrained")
    ax = fig.subplots(2, 4)
    a0 = ax[0, 0]
    if fields_path is not None:
        import xarray as xr

        with xr.open_dataset(fields_path) as ds:
            p = ds["pressure"].isel(step=-1).values
            x, y = ds["x"].values, ds["y"].values
        ext = [x[0] * 1e6, x[-1] * 1e6, y[0] * 1e6, y[-1] * 1e6]
        im = a0.imshow(p.T / 1e6, origin="lower", extent=ext, cmap="magma", vmin=-200, vmax=1000)
        fig.colorbar(im, ax=a0, label="pressure (MPa)", shrink=0.8)
        dx = float(x[1] - x[0])
        n = len(x)
        for size in cfg["windows"]:
            for pos, col in zip(POSITIONS, ("C0", "C3")):
                k = round(dx / float(cfg["dx"]))
                ix0, iy0, m = window_cells(cfg, size, pos, coarse=k > 1)
                x0 = (ix0 - n / 2) * dx * 1e6
                y0 = (iy0 - n / 2) * dx * 1e6
                a0.add_patch(Rectangle((x0, y0), m * dx * 1e6, m * dx * 1e6, fill=False, ec=col, lw=1))
        lim = 1.15 * cfg["radius"] * 1e6
        a0.set_xlim(-lim, lim)
        a0.set_ylim(-lim, lim)
        a0.set_xlabel("x (um)")
        a0.set_ylabel("y (um)")
    a0.set_title("(a) whole burl: pressure, windows (blue centre, red edge)", fontsize=9)
    style = {("centre", "free"): ("C0", "-", "o"), ("centre", "periodic"): ("C0", "--", "s"),
             ("edge", "free"): ("C3", "-", "o"), ("edge", "periodic"): ("C3", "--", "s")}

    def lines(a, col, scale=1.0, rel=False, ref=None, log=False):
        for (pos, bound), (c, ls, mk) in style.items():
            t = table[(table["position"] == pos) & (table["boundary"] == bound)].sort_values("size")
            v = t[col].to_numpy(float) / scale
            if rel:
                v = 100 * v
            a.plot(t["size"].to_numpy(float) * 1e6, v, ls=ls, marker=mk, color=c, ms=4, label=f"{pos}, {bound}")
        if rel:
            a.axhline(0, color="k", lw=0.8)
        if ref is not None and math.isfinite(_num(ref)):
            a.axhline(_num(ref) / scale, color="k", lw=1.2, label="whole burl")
        vals = table[col].to_numpy(float)
        vals = vals[np.isfinite(vals)]
        if log and vals.size and np.all(vals > 0):
            a.set_yscale("log")
        elif log and vals.size and np.any(vals != 0):
            a.set_yscale("symlog", linthresh=float(np.min(np.abs(vals[vals != 0]))))
        a.set_xscale("log")
        a.set_xticks([s * 1e6 for s in cfg["windows"]], [f"{s * 1e6:g}" for s in cfg["windows"]])
        a.set_xticks([], minor=True)
        a.set_xlabel("window side (um)")
        a.grid(alpha=0.3, which="both")
        a.legend(fontsize=7)

    lines(ax[0, 1], "err_contact_fraction_fine", rel=True)
    ax[0, 1].set_ylabel("window / whole - 1 (%)")
    ax[0, 1].set_title(f"(b) contact fraction vs whole, {cfg['dx'] * 1e9:g} nm cells", fontsize=9)
    lines(ax[0, 2], "err_mean_gap_fine", rel=True)
    ax[0, 2].set_ylabel("window / whole - 1 (%)")
    ax[0, 2].set_title(f"(c) mean gap vs whole, {cfg['dx'] * 1e9:g} nm cells", fontsize=9)
    lines(ax[0, 3], "err_contact_fraction", rel=True)
    ax[0, 3].set_ylabel("window / whole - 1 (%)")
    ax[0, 3].set_title(f"(d) contact fraction vs whole, {cfg['dx'] * cfg['coarse'] * 1e9:g} nm cells", fontsize=9)
    lines(ax[1, 0], "pull_off_stress", scale=1e3, ref=wr["pull_off_stress"], log=True)
    ax[1, 0].set_ylabel("-F_pull-off / A (kPa)")
    ax[1, 0].set_title("(e) Dugdale pull-off stress (whole: over pi b^2)", fontsize=9)
    lines(ax[1, 1], "capillary_pull_off_stress", scale=1e3, ref=wr["capillary_pull_off_stress"], log=True)
    ax[1, 1].set_ylabel("-F_pull-off / A (kPa)")
    ax[1, 1].set_title(f"(f) capillary pull-off stress, RH {RH:g}", fontsize=9)
    lines(ax[1, 2], "err_friction_coefficient_static", rel=True)
    ax[1, 2].set_ylabel("window / whole - 1 (%)")
    ax[1, 2].set_title("(g) static friction F_s/F_N vs the whole burl's", fontsize=9)
    lines(ax[1, 3], "presliding_displacement", scale=1e-9, ref=wr["presliding_displacement"], log=True)
    ax[1, 3].set_ylabel("pre-sliding displacement (nm)")
    ax[1, 3].set_title("(h) pre-sliding displacement (whole burl: black)", fontsize=9)
    if title is None:
        title = (f"Window vs whole: rigid burl (b = {cfg['radius'] * 1e6:g} um) on a rough Si wafer (rms "
                 f"{RMS * 1e9:g} nm), {PRESSURE / 1e6:g} MPa mean, Dugdale {DGAMMA * 1e3:g} mJ/m^2, mu = {FRICTION:g}; "
                 f"whole {cfg['n']}^2 x {cfg['dx'] * 1e9:g} nm and {cfg['n'] // cfg['coarse']}^2 x "
                 f"{cfg['dx'] * cfg['coarse'] * 1e9:g} nm")
    fig.suptitle(title, fontsize=10)
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=100)
    return atomic_write_bytes(path, buf.getvalue())


# ----------------------------------------------------------------------------- entry

def main(argv=None) -> int:
    """``python -m studies.burl_windows [--out DIR] [--quick] [--no-run] [--max-points K]``:
    run (resumable), then write ``burl_windows.csv``, ``burl_windows_whole.csv``,
    ``burl_windows.md`` and ``burl_windows.png`` into the results folder."""
    import argparse
    import time

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", type=Path, default=None,
                    help="results folder (default results/burl_windows, results/burl_windows_quick with --quick)")
    ap.add_argument("--quick", action="store_true", help="a 2 um burl on 48^2 cells (a test of the machinery)")
    ap.add_argument("--no-run", action="store_true", help="only gather what is there")
    ap.add_argument("--max-points", type=int, default=None, help="run at most this many missing points")
    ap.add_argument("--quiet", action="store_true")
    args = ap.parse_args(argv)
    out = args.out or Path("results") / ("burl_windows_quick" if args.quick else "burl_windows")
    out.mkdir(parents=True, exist_ok=True)
    t0 = time.perf_counter()
    if not args.no_run:
        _, _, res = run_study(out, args.quick, progress=not args.quiet, max_points=args.max_points)
        if not args.quiet:
            for r in res:
                if r is not None:
                    print(f"sweep {r.outdir.name}: {r.n_ok} of {r.n_points} points ok ({r.n_run} run now), "
                          f"{r.n_failed} failed")
            print(f"({time.perf_counter() - t0:.0f} s)")
    table, whole = gather(out, args.quick)
    table.to_csv(out / "burl_windows.csv", index=False)
    whole.to_csv(out / "burl_windows_whole.csv", index=False)
    md = markdown_table(table, whole)
    (out / "burl_windows.md").write_text(md + "\n", encoding="utf-8")
    cfg = config(args.quick)
    runs = _run_dirs(whole_spec(write_surfaces(out, cfg), cfg, args.quick), out / "whole")
    plot_study(table, whole, _fields_of(runs, "whole_fine/normal"), out / "burl_windows.png")
    if not args.quiet:
        print(md)
        print(f"wrote {out / 'burl_windows.csv'}, {out / 'burl_windows_whole.csv'}, {out / 'burl_windows.md'}, "
              f"{out / 'burl_windows.png'}")
    return 0


if __name__ == "__main__":
    import sys

    sys.exit(main())
