"""Validation of the two-scale solve (``[two_scale]``): closed forms and whole-burl solves.

``two_scale_smooth``
    A stiff interface (its mean gap changes by 1e-5 of the approach) on a rounded burl is the
    smooth rounded punch: Sneddon's approach and contact radius
    (:func:`tribobem.analytic.punch.rounded_punch`), to the grid's own error.
``two_scale_layer``
    A linear interface law g = g0 - p/k is a uniform compliant (Winkler) layer: on a periodic
    sinusoidal macro gap in full contact the nominal pressure is exactly one harmonic,
    P1 = A / (2/(E* q) + 1/k), and delta = A - g0 + P0/k.
``two_scale_partial_slip``
    The small rough burl's tangential ramp (mu = 0.2) against whole-burl ramps of the coupled
    dissimilar pair (:data:`WHOLE_BURL_SLIP`): static friction within 3 %, the tangential
    displacement at 0.5 and 0.9 of it within 10 % (or the realisations' scatter).  The quick
    tier compares 20 nm cells on both sides, the gate 10 nm.
``two_scale_hysteresis``
    The small rough burl's friction loop (F* = 0.8 mu F, Masing's rule in every macro cell)
    against whole-burl loops of the coupled pair (:data:`WHOLE_BURL_LOOP`): the loop energy and
    K_L at A, B, C within 10 % (or the realisations' scatter); the interface's own frictional work
    equal to the loop energy; and Masing's loop of one window against the window's own coupled
    loop (energy within 10 %).
``two_scale_humid``
    The small rough burl at RH 0.5 (Si and SiO2 films, meniscus forces): windows solved with
    their menisci give the humid interface laws (the window slides at mu times its repulsive
    pressure); against whole-burl humid ramps (:data:`WHOLE_BURL_HUMID`): F0+ and static friction
    within 3 %, the meniscus force within 5 %, the displacements at 0.5 and 0.9 F_s within 10 %.
``two_scale_pulloff``
    The small rough burl's capillary pull-off at RH 0.5 from its validation force (windows
    loaded and unloaded with their menisci give the tensile law, the burl unloads under
    displacement control) against whole-burl pull-offs at the same cells
    (:data:`WHOLE_BURL_PULLOFF`): within 10 % or the realisations' scatter.  The quick tier
    compares 20 nm cells, the gate 10 nm.
``two_scale_whole_burl``
    A rough SiC burl on a Si wafer (Gaussian roughness 1.5 nm rms, 50 nm correlation length,
    about 53 MPa over the flat top) solved whole at 10 nm cells (:data:`WHOLE_BURLS`: four
    roughness realisations each, computed once by ``python -m studies.two_scale --whole``)
    against the two-scale solve with windows at the same 10 nm cells: the approach of the mean
    planes within 3 % of the rms roughness or the realisations' scatter (whichever is larger),
    and the real contact area within 5 % or the scatter.  The quick tier solves the small burl
    at 20 nm cells on both sides (the whole grid is then 512^2, seconds).
"""

from __future__ import annotations

import math
import time

import numpy as np

from ..analytic.punch import rounded_punch
from ..elasticity import free_boundary_operator, periodic_operator
from ..geometry.rough import gaussian_surface
from ..geometry.shapes import burl
from ..grid import Grid
from ..materials import ContactPair, Material
from ..two_scale.laws import NormalInterfaceLaw
from ..two_scale.macro import radial_pressure_profile, solve_interface_normal
from ..two_scale.micro import MicroWindows, interface_law
from ..two_scale.tangential import interface_loop, interface_slip_law, solve_interface_tangential, window_loop_check
from .common import ValidationRow, _row

__all__ = ["CASES", "BURLS", "WHOLE_BURLS", "WHOLE_BURL_SLIP", "WHOLE_BURL_LOOP", "WHOLE_BURL_HUMID",
           "WHOLE_BURL_PULLOFF", "DUGDALE", "PAIR", "RMS", "CORRELATION", "MU", "two_scale_burl", "two_scale_burl_slip",
           "two_scale_burl_loop", "two_scale_burl_humid", "two_scale_burl_pulloff"]

#: The validation pair: Si wafer (body 1, rough) and SiC burl (body 2).
PAIR = ContactPair(Material(130e9, 0.28), Material(410e9, 0.14))
#: The wafer's roughness: rms (m) and correlation length (m) of a Gaussian surface.
RMS, CORRELATION = 1.5e-9, 50e-9

#: The validation burls (SI): flat-top radius, edge radius, force, grid side and whole-grid cells
#: (10 nm cells).
BURLS = {
    "small": {"radius": 3e-6, "edge_radius": 20e-6, "force": 1.5e-3, "size": 10.24e-6, "n": 1024},
    "large": {"radius": 6e-6, "edge_radius": 40e-6, "force": 6.0e-3, "size": 20.48e-6, "n": 2048},
}

#: Whole-burl solves at 10 nm cells, roughness seeds 100-103 (``python -m studies.two_scale
#: --whole``, 2026-12-02: 3.5-4.4 s of CPU per 1024^2 solve, 23-26 s per 2048^2): the approach of
#: the mean planes (m) and the real contact area (m^2), one value per realisation.
WHOLE_BURLS: dict = {
    "small": {"approach": [-9.25048e-10, -9.12428e-10, -9.94445e-10, -9.64812e-10],
              "contact_area": [3.402e-13, 3.348e-13, 3.314e-13, 3.303e-13]},
    "large": {"approach": [1.405635e-09, 1.389945e-09, 1.416646e-09, 1.394816e-09],
              "contact_area": [1.3456e-12, 1.3145e-12, 1.3201e-12, 1.3304e-12]},
}

#: The small burl's nominal pressure profile solved whole at 10 nm cells (1024^2, seeds 100-103,
#: 2026-12-02): the cumulative force F(r)/F inside radius r, in rings of :data:`PROFILE_RING`
#: (r = 0.16, 0.32, ... 3.52 um), the mean over the realisations (their spread: 0.014 at most).
PROFILE_RING = 0.16e-6
WHOLE_BURL_PROFILE = [0.0021, 0.008, 0.016, 0.0281, 0.0434, 0.0625, 0.0923, 0.1212, 0.1525, 0.1918, 0.2324,
                      0.2819, 0.3366, 0.3998, 0.4723, 0.5436, 0.6372, 0.753, 0.8844, 0.9889, 1.0, 1.0]

#: The whole small burl at 20 nm cells (512^2, seed 100): the quick tier's reference, which the
#: quick tier recomputes (a second), so that it needs nothing committed.
QUICK_N = 512

#: Dugdale adhesion of the adhesive pull-off study (``[adhesion]``): 50 mJ/m^2, z0 0.3 nm
#: (sigma0 = 171 MPa, h0 = 0.29 nm).
DUGDALE = {"model": "dugdale", "work_of_adhesion": 0.05, "z0": 0.3e-9}

#: Friction coefficient of the partial-slip validation.
MU = 0.2

#: Whole-burl humid ramps of the small burl at RH 0.5 (``kind = "partial_slip"`` with ``[humidity]
#: rh = 0.5``, Si and SiO2 films, meniscus forces without van der Waals, mu = 0.2, ``tangential_forces
#: = "auto"``; ``python -m studies.two_scale --whole-humid``, 2026-12-02): static friction (N), the
#: repulsive force F0+ and the meniscus force (N) at zero tangential load, the tangential
#: displacement (m) at 0.5 and 0.9 of the static friction, per roughness seed.  "n512": 20 nm cells
#: (35-38 s of CPU each), "n1024": 10 nm cells.
WHOLE_BURL_HUMID: dict = {
    "n512": {"seeds": [100, 101], "static_friction_force": [7.112339832e-04, 7.103736603e-04],
             "repulsive_force": [3.561264229e-03, 3.555182607e-03],
             "capillary_force": [-2.059556923e-03, -2.053905527e-03], "d50": [7.380935420e-10, 7.387992569e-10],
             "d90": [1.480073261e-09, 1.489881283e-09]},
    # 10 nm cells: 207 s of CPU each
    "n1024": {"seeds": [100, 101], "static_friction_force": [6.749238770e-04, 6.728526522e-04],
              "repulsive_force": [3.378950507e-03, 3.369601677e-03],
              "capillary_force": [-1.878476790e-03, -1.869001283e-03], "d50": [7.054696040e-10, 7.062056167e-10],
              "d90": [1.423374100e-09, 1.429257396e-09]},
}

#: Whole-burl pull-offs of the small burl from its validation force (``kind = "pulloff"``, ``load.preload
#: = 1.5 mN``, 40 unloading steps, refine 4; ``python -m studies.two_scale --whole-pulloff``,
#: 2026-12-03): the pull-off force (N) per roughness seed.  At RH 0.5 (Si and SiO2 films, meniscus
#: forces without van der Waals): "n512" (20 nm cells, 64-74 s of CPU each), "n1024" (10 nm, 399 s);
#: at 40 nm cells (256^2) the same burl pulls off at -0.902 mN: the whole burl's capillary pull-off
#: is not converged in the cell (-0.902 / -0.640 / -0.465 mN at 40 / 20 / 10 nm).  With Dugdale
#: adhesion (:data:`DUGDALE`, dry, 20 nm cells): -6.8427e-8 N for all four seeds, exactly sigma0
#: times one cell's area: the whole burl's Dugdale pull-off is a count of one cell there.
WHOLE_BURL_PULLOFF: dict = {
    "n512": {"seeds": [100, 101], "pull_off_force": [-6.683345045e-04, -6.121722223e-04]},
    "n1024": {"seeds": [100], "pull_off_force": [-4.648696922e-04]},
    "dugdale_n512": {"seeds": [100, 101, 102, 103], "pull_off_force": [-6.842669857e-08] * 4},
}

#: The friction loops of the hysteresis validation: F* = 0.8 mu F, 24 steps per cycle.
LOOP_AMPLITUDE, LOOP_STEPS = 0.8, 24

#: Whole-burl friction loops of the small burl (``kind = "hysteresis"``, force path 0 -> +F* -> -F*
#: -> +F*, F* = 0.8 mu F0+, 24 steps, mu = 0.2, the coupled dissimilar pair; ``python -m
#: studies.two_scale --whole-loop``, 2026-12-02): the loop energy (J) and K_L at A, B, C (N/m), per
#: roughness seed.  "n512": 20 nm cells (23 s of CPU), "n1024": 10 nm cells.
WHOLE_BURL_LOOP: dict = {
    "n512": {"seeds": [100], "dissipated_energy": [4.9106528e-14],
             "A": [439490.24], "B": [403036.67], "C": [342973.32]},
    # 10 nm cells: 131-139 s of CPU per loop
    "n1024": {"seeds": [100, 101], "dissipated_energy": [4.7874815e-14, 5.0740654e-14],
              "A": [438213.35, 436829.20], "B": [402064.44, 399366.79], "C": [343251.84, 338311.74]},
}

#: Whole-burl partial-slip ramps of the small burl (``kind = "partial_slip"``, ``tangential_forces =
#: "auto"``, mu = 0.2, the coupled dissimilar pair; ``python -m studies.two_scale --whole-slip``):
#: static friction (N), its ratio to mu F0+, and the tangential displacement (m) at 0.5 and 0.9
#: of the static friction, per roughness seed.  "n512": 20 nm cells (18 s of CPU each), "n1024":
#: 10 nm cells.
WHOLE_BURL_SLIP: dict = {
    "n512": {"seeds": [100], "static_friction_force": [2.986553314e-04], "static_friction_ratio": [0.99551777],
             "d50": [3.686585161e-10], "d90": [7.790328245e-10]},
    # 87-102 s of CPU and 3.0 GB per ramp (2026-12-02)
    "n1024": {"seeds": [100, 101], "static_friction_force": [2.992036173e-04, 2.988737150e-04],
              "static_friction_ratio": [0.99734539, 0.99624572], "d50": [3.689565196e-10, 3.693524299e-10],
              "d90": [7.858565667e-10, 8.001176401e-10]},
}


def cumulative_force(pressure, grid) -> list:
    """F(r) / F: the fraction of the force inside radius r about the grid's centre, in rings of
    :data:`PROFILE_RING` out to 3.52 um (the small burl's contact and a margin)."""
    prof = radial_pressure_profile(pressure, grid.dx, grid.dy, PROFILE_RING, 22 * PROFILE_RING)
    r = np.array(prof["radius"])
    ring = np.pi * ((r + PROFILE_RING / 2) ** 2 - (r - PROFILE_RING / 2) ** 2)
    f = np.cumsum(np.nan_to_num(np.array(prof["pressure"])) * ring)
    return (f / f[-1]).tolist()


def two_scale_burl(name: str, *, window: float = 1e-6, window_n: int | None = None, realisations: int = 4,
                   macro_n: int = 128, cells_factor: int = 1, seed0: int = 0, pressures: int = 32) -> dict:
    """The two-scale solve of validation burl ``name``.

    Parameters
    ----------
    name : str
        A key of :data:`BURLS`.
    window : float
        Window side (m).
    window_n : int, optional
        Window cells; default: the whole grid's cells (10 nm) times ``cells_factor``.
    realisations, macro_n : int
        Roughness realisations of the windows; macro cells per side.
    pressures : int
        Tabulated pressures, from 1e-3 to 20 times the mean pressure over the flat top.
    cells_factor : int
        Window cells finer than the whole grid's by this factor (when ``window_n`` is None).
    seed0 : int
        Seed of the first realisation.

    Returns
    -------
    dict
        ``approach`` (m, of the mean planes), ``contact_area`` (m^2, real), ``nominal_area``,
        ``max_pressure``, ``converged``, ``cpu_s``, the settings.
    """
    b = BURLS[name]
    if window_n is None:
        window_n = int(round(window / (b["size"] / b["n"]))) * cells_factor
    t = time.process_time()
    wgrid = Grid(window_n, window_n, window, window, periodic=True)
    gaps = []
    for k in range(realisations):
        z = gaussian_surface(wgrid, RMS, CORRELATION, seed=seed0 + k)
        gaps.append(z.max() - z)
    mean_p = b["force"] / (math.pi * b["radius"] ** 2)
    law = interface_law(MicroWindows(wgrid, PAIR, gaps), np.geomspace(1e-3 * mean_p, 20 * mean_p, pressures), cache=False)
    grid = Grid(macro_n, macro_n, b["size"], b["size"])
    res = solve_interface_normal(free_boundary_operator(grid, PAIR), burl(grid, b["radius"], b["edge_radius"]), law,
                                 b["force"], tol=1e-9)
    return {"approach": res.approach, "contact_area": res.real_contact_area, "nominal_area": res.nominal_area,
            "force_profile": cumulative_force(res.pressure, grid),
            "max_pressure": res.max_pressure, "converged": bool(res.converged and law.converged),
            "beyond_table": res.beyond_table, "cpu_s": time.process_time() - t, "window": window,
            "window_n": window_n, "realisations": realisations, "macro_n": macro_n, "pressures": pressures}


def _tangential_burl(name, window, window_n, realisations, macro_n, seed0):
    """The small rough burl's macro normal state and its windows' slip law (mu = :data:`MU`)."""
    b = BURLS[name]
    if window_n is None:
        window_n = int(round(window / (b["size"] / b["n"])))
    wgrid = Grid(window_n, window_n, window, window, periodic=True)
    gaps = []
    for k in range(realisations):
        z = gaussian_surface(wgrid, RMS, CORRELATION, seed=seed0 + k)
        gaps.append(z.max() - z)
    windows = MicroWindows(wgrid, PAIR, gaps)
    mean_p = b["force"] / (math.pi * b["radius"] ** 2)
    law = interface_law(windows, np.geomspace(1e-3 * mean_p, 20 * mean_p, 32), cache=False)
    slip_law = interface_slip_law(windows, np.geomspace(1e-2 * mean_p, 20 * mean_p, 12), MU, cache=False)
    grid = Grid(macro_n, macro_n, b["size"], b["size"])
    op = free_boundary_operator(grid, PAIR, components=("x", "y", "z"))
    res = solve_interface_normal(op.normal, burl(grid, b["radius"], b["edge_radius"]), law, b["force"], tol=1e-9)
    ok = bool(res.converged and law.converged and slip_law.converged)
    return op, res, law, slip_law, ok, window_n


def two_scale_burl_slip(name: str = "small", *, window: float = 1e-6, window_n: int | None = None,
                        realisations: int = 4, macro_n: int = 128, seed0: int = 0) -> dict:
    """The two-scale tangential ramp of validation burl ``name`` at mu = :data:`MU`.

    Returns
    -------
    dict
        ``static_friction_force`` (N, mu F), ``d50`` and ``d90`` (m: the tangential displacement at
        0.5 and 0.9 of it), ``converged``, ``cpu_s``.
    """
    t = time.process_time()
    op, res, law, slip_law, ok, window_n = _tangential_burl(name, window, window_n, realisations, macro_n, seed0)
    static = MU * res.force
    out, prev = {}, None
    for key, frac in (("d50", 0.5), ("d90", 0.9)):
        r = solve_interface_tangential(op, res.pressure, slip_law, frac * static, initial_shear=prev, tol=1e-9)
        prev = r.shear
        out[key] = r.displacement
        ok = ok and r.converged
    return {"static_friction_force": static, **out, "converged": ok, "cpu_s": time.process_time() - t,
            "window_n": window_n, "realisations": realisations, "macro_n": macro_n}


def two_scale_burl_loop(name: str = "small", *, window: float = 1e-6, window_n: int | None = None,
                        realisations: int = 4, macro_n: int = 128, seed0: int = 0,
                        amplitude: float = LOOP_AMPLITUDE, steps: int = LOOP_STEPS) -> dict:
    """The two-scale friction loop of validation burl ``name`` (F* = ``amplitude`` mu F, one
    cycle of ``steps`` steps, Masing's rule in every macro cell).

    Returns
    -------
    dict
        ``dissipated_energy`` (J), ``dissipation_work`` (J, the interface's own work),
        ``lateral_stiffness`` ({"A", "B", "C"}: N/m), ``converged``, ``cpu_s``.
    """
    from ..runs.loop_stiffness import stiffness_table
    from ..solvers.hysteresis import cycle_path, loop_energies

    t = time.process_time()
    op, res, law, slip_law, ok, window_n = _tangential_burl(name, window, window_n, realisations, macro_n, seed0)
    path = cycle_path(amplitude * MU * res.force, 1, steps, "force")
    loop = interface_loop(op, res.pressure, slip_law, path.values, path.turning, path.cycle, tol=1e-9)
    rows = [{"tangential_force_x": 0.0, "tangential_force_y": 0.0, "displacement_x": 0.0, "displacement_y": 0.0,
             "branch": "start", "cycle": 0, "gross_slip": False}]
    rows += [{"tangential_force_x": st.force, "tangential_force_y": 0.0, "displacement_x": st.displacement,
              "displacement_y": 0.0, "branch": br, "cycle": int(c), "gross_slip": False}
             for st, c, br in zip(loop.states, path.cycle, path.branch)]
    table, _ = stiffness_table(rows, MU, res.force, None)
    energy = loop_energies([r["tangential_force_x"] for r in rows], [r["displacement_x"] for r in rows],
                           [r["cycle"] for r in rows])[0]
    return {"dissipated_energy": energy, "dissipation_work": loop.dissipation[0],
            "lateral_stiffness": {r["point"]: r["stiffness"] for r in table},
            "converged": bool(ok and all(st.converged for st in loop.states)), "cpu_s": time.process_time() - t,
            "window_n": window_n, "realisations": realisations, "macro_n": macro_n}


def _slip_rows(quick: bool) -> list[ValidationRow]:
    case = "two_scale_partial_slip"
    key = "n512" if quick or "n1024" not in WHOLE_BURL_SLIP else "n1024"
    ref = WHOLE_BURL_SLIP[key]
    ts = two_scale_burl_slip("small", window_n=50 if key == "n512" else 100)
    rows = []
    fs = float(np.mean(ref["static_friction_force"]))
    rows.append(_row(case, f"small burl, {key}: static friction (N)", fs, ts["static_friction_force"],
                     max(0.03, float(np.ptp(ref["static_friction_force"])) / 2 / fs)))
    for q, label in (("d50", "0.5"), ("d90", "0.9")):
        d = float(np.mean(ref[q]))
        rows.append(_row(case, f"small burl, {key}: tangential displacement at {label} F_s (m)", d, ts[q],
                         max(0.10, float(np.ptp(ref[q])) / 2 / d)))
    return rows


def _loop_rows(quick: bool) -> list[ValidationRow]:
    case = "two_scale_hysteresis"
    key = "n512" if quick else "n1024"
    ref = WHOLE_BURL_LOOP[key]
    ts = two_scale_burl_loop("small", window_n=50 if key == "n512" else 100)
    rows = []
    e = float(np.mean(ref["dissipated_energy"]))
    rows.append(_row(case, f"small burl, {key}: loop energy (J)", e, ts["dissipated_energy"],
                     max(0.10, float(np.ptp(ref["dissipated_energy"])) / 2 / e)))
    # the interface's own frictional work closes the energy balance of the Masing loop
    rows.append(_row(case, "small burl: interface work sum(closed integral tau ds) dA = loop energy (J)",
                     ts["dissipated_energy"], ts["dissipation_work"], 1e-6))
    for point in ("A", "B", "C"):
        k = float(np.mean(ref[point]))
        rows.append(_row(case, f"small burl, {key}: K_L at {point} (N/m)", k, ts["lateral_stiffness"][point],
                         max(0.10, float(np.ptp(ref[point])) / 2 / k)))
    # Masing's rule against one window's own loop (the coupled pair, at the mean pressure over the top)
    n = 50 if quick else 100
    wgrid = Grid(n, n, 1e-6, 1e-6, periodic=True)
    z = gaussian_surface(wgrid, RMS, CORRELATION, seed=0)
    b = BURLS["small"]
    chk = window_loop_check(wgrid, PAIR, z.max() - z, b["force"] / (math.pi * b["radius"] ** 2), MU,
                            amplitude=LOOP_AMPLITUDE, steps=2 * LOOP_STEPS)
    rows.append(_row(case, "one window: Masing's loop energy against its coupled loop (J)", chk["energy"],
                     chk["masing_energy"], 0.10))
    return rows


def two_scale_burl_humid(name: str = "small", *, window: float = 1e-6, window_n: int | None = None,
                         realisations: int = 4, macro_n: int = 128, rh: float = 0.5) -> dict:
    """The two-scale humid ramp of validation burl ``name`` at ``rh`` from a scenario (the films and
    the capillary model are the scenario's, as a user runs it)."""
    from ..scenario import parse_scenario, run_scenario

    b = BURLS[name]
    if window_n is None:
        window_n = int(round(window / (b["size"] / b["n"])))
    sc = {"kind": "partial_slip", "grid": {"n": macro_n, "size": b["size"]},
          "body1": {"E": PAIR.body1.E, "nu": PAIR.body1.nu, "film": {"isotherm": "Si"},
                    "roughness": {"kind": "gaussian", "rms": RMS, "correlation_length": CORRELATION}},
          "body2": {"E": PAIR.body2.E, "nu": PAIR.body2.nu, "film": {"isotherm": "SiO2"},
                    "shape": {"kind": "burl", "radius": b["radius"], "edge_radius": b["edge_radius"]}},
          "load": {"force": b["force"]}, "friction": {"coefficient": MU, "tangential_forces": [0.0]},
          "humidity": {"rh": rh, "van_der_waals": False},
          "two_scale": {"window": window, "window_n": window_n, "realisations": realisations, "cache": False}}
    t = time.process_time()
    # the static friction and F0+ first; then the ramp at 0.5 and 0.9 of it
    first = run_scenario(parse_scenario(sc), outdir=None, progress=False, warn=False).summary
    fs = first["static_friction_force"]
    sc["friction"]["tangential_forces"] = [0.0, 0.5 * fs, 0.9 * fs]
    s = run_scenario(parse_scenario(sc), outdir=None, progress=False, warn=False).summary
    d = [r["displacement_x"] for r in s["steps"]]
    return {"static_friction_force": fs, "repulsive_force": s["repulsive_force"], "capillary_force": s["capillary_force"],
            "d50": d[1] - d[0], "d90": d[2] - d[0], "converged": bool(first["converged"] and s["converged"]),
            "cpu_s": time.process_time() - t}


def _humid_rows(quick: bool) -> list[ValidationRow]:
    case = "two_scale_humid"
    key = "n512" if quick or "n1024" not in WHOLE_BURL_HUMID else "n1024"
    ref = WHOLE_BURL_HUMID[key]
    ts = two_scale_burl_humid("small", window_n=50 if key == "n512" else 100)
    rows = []
    for q, label, tol in (("repulsive_force", "repulsive force F0+ at RH 0.5 (N)", 0.03),
                          ("capillary_force", "meniscus force at RH 0.5 (N)", 0.05),
                          ("static_friction_force", "static friction at RH 0.5 (N)", 0.03),
                          ("d50", "tangential displacement at 0.5 F_s, RH 0.5 (m)", 0.10),
                          ("d90", "tangential displacement at 0.9 F_s, RH 0.5 (m)", 0.10)):
        v = float(np.mean(ref[q]))
        rows.append(_row(case, f"small burl, {key}: {label}", v, ts[q], max(tol, float(np.ptp(ref[q])) / 2 / abs(v))))
    return rows


def two_scale_burl_pulloff(name: str = "small", *, window: float = 1e-6, window_n: int | None = None,
                           realisations: int = 4, macro_n: int = 128, rh: float | None = 0.5) -> dict:
    """The two-scale pull-off of validation burl ``name`` from its force, at ``rh`` (Si and SiO2
    films, meniscus forces) or, with ``rh`` None, dry with :data:`DUGDALE`, from a scenario."""
    from ..scenario import parse_scenario, run_scenario

    b = BURLS[name]
    if window_n is None:
        window_n = int(round(window / (b["size"] / b["n"])))
    sc = {"kind": "pulloff", "grid": {"n": macro_n, "size": b["size"]},
          "body1": {"E": PAIR.body1.E, "nu": PAIR.body1.nu,
                    "roughness": {"kind": "gaussian", "rms": RMS, "correlation_length": CORRELATION}},
          "body2": {"E": PAIR.body2.E, "nu": PAIR.body2.nu,
                    "shape": {"kind": "burl", "radius": b["radius"], "edge_radius": b["edge_radius"]}},
          "load": {"preload": b["force"], "refine": 4},
          "two_scale": {"window": window, "window_n": window_n, "realisations": realisations, "cache": False}}
    if rh is None:
        sc["adhesion"] = dict(DUGDALE)
    else:
        sc["body1"]["film"] = {"isotherm": "Si"}
        sc["body2"]["film"] = {"isotherm": "SiO2"}
        sc["humidity"] = {"rh": rh, "van_der_waals": False}
    t = time.process_time()
    s = run_scenario(parse_scenario(sc), outdir=None, progress=False, warn=False).summary
    force = s["pull_off_force"][0] if rh is not None else s["pull_off_force"]
    return {"pull_off_force": float(force), "strength": s["two_scale"]["strength"], "converged": bool(s["converged"]),
            "warnings": s["warnings"], "cpu_s": time.process_time() - t}


def _pulloff_rows(quick: bool) -> list[ValidationRow]:
    case = "two_scale_pulloff"
    key = "n512" if quick else "n1024"
    ref = WHOLE_BURL_PULLOFF[key]
    ts = two_scale_burl_pulloff("small", window_n=50 if key == "n512" else 100)
    v = float(np.mean(ref["pull_off_force"]))
    spread = float(np.ptp(ref["pull_off_force"])) / 2 / abs(v)
    return [_row(case, f"small burl, {key}: capillary pull-off force at RH 0.5 (N)", v, ts["pull_off_force"],
                 max(0.10, spread))]


def _smooth_rows(quick: bool) -> list[ValidationRow]:
    case = "two_scale_smooth"
    pair = ContactPair(Material(100e9, 0.3), Material.rigid())
    E = pair.effective_modulus
    n = 96 if quick else 192
    bb, Re = 1e-6, 5e-6
    grid = Grid(n, n, 4e-6, 4e-6)
    ps = np.geomspace(1e3, 1e11, 64)
    law = NormalInterfaceLaw(ps, 1e-9 - 1e-14 * np.log(ps / 1e3), 1e-9 + 1e-14, np.full(64, 0.1), ps,
                             np.zeros(64), np.zeros(64))
    ref = rounded_punch(contact_radius=1.3 * bb, flat_radius=bb, edge_radius=Re, E_star=E)
    res = solve_interface_normal(free_boundary_operator(grid, pair), burl(grid, bb, Re), law, float(ref.force), tol=1e-9)
    tol = grid.dx / (2 * ref.contact_radius)  # the contact edge is known to half a cell (as validation.burl)
    return [_row(case, "approach vs Sneddon (mean planes less the 1 nm layer)", ref.approach, res.approach + 1e-9, tol),
            _row(case, "contact radius vs Sneddon", ref.contact_radius, math.sqrt(res.nominal_area / math.pi), tol)]


def _layer_rows(quick: bool) -> list[ValidationRow]:
    case = "two_scale_layer"
    pair = ContactPair(Material(100e9, 0.3), Material.rigid())
    E = pair.effective_modulus
    n, lam, A, P0, g0, k = (32 if quick else 64), 10e-6, 2e-9, 2e8, 20e-9, 1e17
    grid = Grid(n, n, lam, lam, periodic=True)
    x = (np.arange(n) + 0.5) * grid.dx
    X = np.broadcast_to(x[:, None], grid.shape)
    q = 2 * math.pi / lam
    h = A * (1 - np.cos(q * X))
    ps = np.geomspace(1e6, 1e9, 256)
    law = NormalInterfaceLaw(ps, g0 - ps / k, g0, np.full(256, 0.1), ps, np.zeros(256), np.zeros(256))
    res = solve_interface_normal(periodic_operator(grid, pair), h, law, P0 * lam * lam, tol=1e-10)
    P1 = A / (2 / (E * q) + 1 / k)
    P1_num = float(2 * np.mean(res.pressure * np.cos(q * X)))
    return [_row(case, "pressure harmonic P1 = A/(2/(E* q) + 1/k) (Pa)", P1, P1_num, 2e-3),
            _row(case, "approach A - g0 + P0/k (m)", A - g0 + P0 / k, res.approach, 1e-3, scale=A)]


def _whole_burl_rows(quick: bool) -> list[ValidationRow]:
    case = "two_scale_whole_burl"
    rows = []
    if quick or not WHOLE_BURLS:
        from ..solvers.normal import solve_normal  # the quick reference, solved here

        b = BURLS["small"]
        grid = Grid(QUICK_N, QUICK_N, b["size"], b["size"])
        H = burl(grid, b["radius"], b["edge_radius"]) - gaussian_surface(grid, RMS, CORRELATION, seed=100)
        offset = -float(H.min())
        whole = solve_normal(free_boundary_operator(grid, PAIR), H + offset, force=b["force"], tol=1e-8)
        ts = two_scale_burl("small", window_n=int(round(1e-6 / grid.dx)))
        # the approach is judged against the rms roughness (its zero, the mean planes' touch, is arbitrary)
        rows.append(_row(case, "small burl, 20 nm cells: approach of the mean planes (m; error / rms)",
                         whole.approach - offset, ts["approach"], 0.03, scale=RMS))
        # the nominal pressure profile: the largest difference of the cumulative force F(r)/F (measured 2.2 %)
        prof = np.array(cumulative_force(whole.pressure, grid))
        dev = np.abs(np.array(ts["force_profile"]) - prof)
        k = int(np.argmax(dev))
        rows.append(_row(case, f"small burl, 20 nm cells: pressure profile, F(r)/F at r = {(k + 1) * PROFILE_RING * 1e6:.2f} "
                         "um (largest difference)", float(prof[k]), float(ts["force_profile"][k]), 0.05,
                         scale=1.0))
        # at 20 nm cells (50-cell windows) the windows' contact fraction is 6 % low (measured; 3 % at 10 nm)
        rows.append(_row(case, "small burl, 20 nm cells: real contact area (m^2)", whole.contact_area,
                         ts["contact_area"], 0.10))
        return rows
    for name, ref in WHOLE_BURLS.items():
        ts = two_scale_burl(name)
        if name == "small":
            dev = np.abs(np.array(ts["force_profile"]) - np.array(WHOLE_BURL_PROFILE))
            k = int(np.argmax(dev))
            rows.append(_row(case, f"small burl: pressure profile, F(r)/F at r = {(k + 1) * PROFILE_RING * 1e6:.2f} um "
                             "(largest difference)", WHOLE_BURL_PROFILE[k], float(ts["force_profile"][k]), 0.05,
                             scale=1.0))
        a_ref = float(np.mean(ref["approach"]))
        a_tol = max(0.03, float(np.ptp(ref["approach"])) / 2 / RMS)
        rows.append(_row(case, f"{name} burl: approach of the mean planes (m; error / rms)", a_ref, ts["approach"],
                         a_tol, scale=RMS))
        area = float(np.mean(ref["contact_area"]))
        spread = float(np.ptp(ref["contact_area"])) / 2 / area
        rows.append(_row(case, f"{name} burl: real contact area (m^2)", area, ts["contact_area"], max(0.05, spread)))
    return rows


CASES = {
    "two_scale_smooth": _smooth_rows,
    "two_scale_layer": _layer_rows,
    "two_scale_whole_burl": _whole_burl_rows,
    "two_scale_partial_slip": _slip_rows,
    "two_scale_hysteresis": _loop_rows,
    "two_scale_humid": _humid_rows,
    "two_scale_pulloff": _pulloff_rows,
}
