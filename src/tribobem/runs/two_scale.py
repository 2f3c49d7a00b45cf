"""The two-scale path of a run kind (``[two_scale]``): micro windows, then the macro solve.

Not a kind of its own: the kinds that accept ``[two_scale]`` call :func:`run_normal`,
:func:`run_partial_slip` or :func:`run_hysteresis` when the built problem carries micro windows
(``pb.two_scale``).

1. The pressure range of the table: the smooth macro contact (the shapes without the
   roughness, hard contact) is solved at the largest load; the table runs from 1e-3 of its mean
   contact pressure to twice its largest pressure, ``[two_scale] pressures`` values spaced
   evenly in ln p (or between ``min_pressure`` and ``max_pressure``).
2. The micro windows give the interface law (:func:`tribobem.two_scale.micro.interface_law`:
   cached, through Dask).
3. Each load is solved at macro scale with the law (:func:`tribobem.two_scale.macro.
   solve_interface_normal`).

summary.json: the steps carry the run-level keys of a whole-grid run, with ``contact_area``
the real contact area (the law's contact fraction summed over the macro cells) and
``max_pressure`` the largest asperity pressure of the windows at the cells' nominal
pressures; ``nominal_contact_area`` and ``max_nominal_pressure`` are the macro ones, and
``approach`` is the approach of the mean planes (0: the mean planes of the undeformed
roughness touch where the macro gap is 0).  ``two_scale`` holds the table and how it was made.
"""

from __future__ import annotations

import dataclasses
import warnings

import numpy as np

from ..errors import ConvergenceWarning
from ..errors import InputError
from ..results import NormalResult, TangentialResult
from ..solvers.hysteresis import cycle_path, loop_energies
from ..solvers.normal import solve_normal
from ..two_scale.macro import pressure_length, solve_interface_normal
from ..two_scale.micro import interface_law
from ..two_scale.tangential import interface_loop, interface_slip_law, solve_interface_tangential
from .capillary import capillary_options, films_at
from .common import step_row
from .kind import RunOutput
from .loop_stiffness import kept_states, stiffness_table
from .settings import SolverSettings

__all__ = ["check_two_scale_tangential", "run_normal", "run_partial_slip", "run_hysteresis", "table_pressures", "AUTO_FRACTIONS"]

#: ``tangential_forces = "auto"`` of a two-scale partial_slip run: these fractions of the static
#: friction mu F (every window slides at its own mu p, so the burl at mu F).
AUTO_FRACTIONS = (0.0, 0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 0.95, 0.98)
#: Nominal pressures of the slip table (log-spaced over the normal table's upper range).
SLIP_PRESSURES = 12

#: A window's largest contact patch must span at least this many cells (equivalent diameter) at
#: the macro mean pressure, or the run warns (as a whole-grid run's contact_cells check does).
MIN_PATCH_CELLS = 3.0
#: The automatic table: from this fraction of the smooth contact's mean pressure ...
LOW_FRACTION = 1e-3
#: ... to this multiple of its largest pressure.
HIGH_FACTOR = 2.0


def check_two_scale_tangential(sc, what: str) -> None:
    """What a two-scale tangential run supports: along x, non-adhesive, dry or at one RH
    (``what``: "ramp" or "loop", for the messages)."""
    from .kind import fail

    fr = sc.friction
    if fr.direction != 0.0:
        fail("friction.direction", f"a two-scale {what} runs along x (direction 0)")
    if sc.humidity is not None and len(sc.humidity.rh or []) != 1:
        fail("humidity.rh", f"a two-scale {what} runs at one RH (its windows' menisci are tabulated at it); "
             f"got {list(sc.humidity.rh or [])}: run one scenario per RH (a sweep over humidity.rh)")
    if sc.adhesion.model != "none":
        fail("adhesion.model", f"a two-scale {what} takes a non-adhesive interface (the windows' Dugdale tensile "
                               "law serves the two-scale pull-off only, kind = 'pulloff'); run the whole grid")


def table_pressures(pb, settings: SolverSettings, force: float) -> tuple[np.ndarray, dict]:
    """The nominal pressures of the micro table (Pa) and how they were chosen.

    Parameters
    ----------
    pb : Problem
        The built two-scale problem (its macro operator and gap).
    settings : SolverSettings
        The run's solver settings (for the smooth solve).
    force : float
        The largest load of the run (N).

    Returns
    -------
    (ndarray, dict)
        The pressures, and ``{"smooth_mean_pressure", "smooth_max_pressure"}`` (Pa) when the
        range was automatic.
    """
    ts = pb.scenario.two_scale
    info: dict = {}
    lo, hi = ts.min_pressure, ts.max_pressure
    if lo is None or hi is None:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", ConvergenceWarning)
            # (a kind whose path picks its own normal solver, the dry pull-off: solve_normal's default)
            kw = settings.normal_kw() if settings.normal_method is not None else settings.path_kw()
            smooth = solve_normal(pb.operator, pb.gap, force=force, **kw)
        mean_p = force / max(smooth.contact_area, pb.grid.dx * pb.grid.dy)
        info = {"smooth_mean_pressure": float(mean_p), "smooth_max_pressure": float(smooth.max_pressure)}
        lo = LOW_FRACTION * mean_p if lo is None else lo
        hi = HIGH_FACTOR * float(smooth.max_pressure) if hi is None else hi
        hi = max(hi, 10.0 * lo)
    return np.geomspace(lo, hi, int(ts.pressures)), info


def _macro_result(pb, res, law=None) -> NormalResult:
    """The macro state as a NormalResult for fields.nc: nominal pressure, mean-plane separation.
    With menisci (``law.menisci``) the pressure field is the nominal repulsive pressure, what the
    windows' contacts carry (the applied nominal pressure plus the menisci's pull), so that the
    maps and their F0+ are those of the contact, as in a whole-grid humid run."""
    contact = res.pressure > 0
    pressure = res.pressure
    if law is not None and law.menisci is not None:
        pressure = law.meniscus("repulsive_pressures", res.pressure)
    return NormalResult(grid=pb.grid, pressure=pressure, gap=res.separation, displacement=res.displacement,
                        contact=contact, adhesive=np.zeros_like(contact), force=res.force, approach=res.approach,
                        iterations=res.newton_iterations, residual_history=np.array([res.residual]),
                        converged=res.converged, time=res.time, control="force",
                        info={"two_scale": True})


def _row(pb, state: NormalResult, res) -> dict:
    row = step_row(state, "loading")
    row.update({
        "contact_area": res.real_contact_area, "contact_area_compressive": res.real_contact_area,
        "nominal_contact_area": res.nominal_area, "max_pressure": res.max_pressure,
        "max_nominal_pressure": res.max_nominal_pressure, "mean_gap": float(np.mean(res.separation)),
        "cg_iterations": res.cg_iterations, "residual": res.residual,
    })
    return row


def run_normal(pb, bar, settings: SolverSettings) -> RunOutput:
    """Kind ``normal`` with ``[two_scale]``: the loads of ``[load]`` (``force`` or ``forces``).

    Parameters
    ----------
    pb : Problem
        The built problem: the macro gap and operator, and ``pb.two_scale`` (the windows).
    bar : progress handler
        ``bar.phase(description, total)`` and ``bar(done, total)``.
    settings : SolverSettings
        The run's solver settings (the tolerance of the micro and macro solves).

    Returns
    -------
    RunOutput
    """
    sc = pb.scenario
    ts = sc.two_scale
    forces = [sc.load.force] if sc.load.force is not None else list(sc.load.forces)
    pressures, range_info = table_pressures(pb, settings, max(forces))
    bar.phase("micro windows", 1)
    law = interface_law(pb.two_scale, pressures, tol=settings.tolerance, max_iterations=settings.max_iterations,
                        scheduler=ts.scheduler, cache=ts.cache)
    bar(1, 1)
    bar.phase("macro solves", len(forces))
    rows, results, messages = [], [], []
    beyond = False
    for k, force in enumerate(forces):
        res = solve_interface_normal(pb.operator, pb.gap, law, float(force), tol=max(settings.tolerance, 1e-9))
        state = _macro_result(pb, res, law)
        rows.append(_row(pb, state, res))
        results.append(state)
        beyond = beyond or res.beyond_table
        bar(k + 1, len(forces))
    info = law.info
    if info.get("not_converged"):
        messages.append(f"two_scale: {info['not_converged']} of {info['solves']} micro window solves did not converge "
                        f"(tolerance {settings.tolerance:g}); the interface law averages them as they are")
    if not law.converged and not info.get("not_converged"):
        messages.append("two_scale: a micro window solve did not converge")
    if beyond:
        messages.append(f"two_scale.max_pressure: a macro cell's nominal pressure exceeds the table's largest "
                        f"({law.pressures[-1]:.4g} Pa); the law was extrapolated there: give a larger max_pressure")
    # the windows' asperity contacts at the largest load's mean nominal pressure: resolved when the
    # largest patch spans >= 3 cells (the result check contact_cells of a whole-grid run)
    last = rows[-1]
    mean_p = float(last["normal_force"]) / max(float(last["nominal_contact_area"]), pb.grid.dx * pb.grid.dy)
    patch = law.patch_cells_at(mean_p)
    if patch is not None and patch < MIN_PATCH_CELLS:
        messages.append(f"two_scale.window_n: at the mean nominal pressure ({mean_p:.3g} Pa) the windows' largest "
                        f"contact patch is {patch:.1f} cell(s) across (< {MIN_PATCH_CELLS:g}): the asperity contacts "
                        "are not resolved, so the real contact area and the peak pressure are set by the window's "
                        "cells; refine two_scale.window_n")
    # the scale separation at the largest load: the window against the length over which the
    # nominal pressure changes (median over the contact and its edge's 5th percentile)
    lengths = pressure_length(results[-1].pressure, pb.grid.dx, pb.grid.dy)
    separation = {"pressure_length_median": lengths["median"], "pressure_length_edge": lengths["p05"],
                  "window_over_pressure_length": float(ts.window / lengths["median"])}
    run = {"two_scale": {**range_info, **separation, "mean_nominal_pressure": mean_p, "window_patch_cells": patch,
                         "law": law.as_dict(), "gap_spread_max": float(np.max(law.gap_spread))}}
    labels = [f"loading {k}" for k in range(len(rows))]
    return RunOutput(rows=rows, results=results, labels=labels, indices=list(range(len(rows))), run=run,
                     warnings=messages)


def _normal_state(pb, settings, force, windows=None):
    """The macro normal state of a two-scale tangential run, its law and run-level info."""
    pressures, range_info = table_pressures(pb, settings, force)
    ts = pb.scenario.two_scale
    law = interface_law(windows or pb.two_scale, pressures, tol=settings.tolerance,
                        max_iterations=settings.max_iterations, scheduler=ts.scheduler, cache=ts.cache)
    res = solve_interface_normal(pb.operator.normal, pb.gap, law, float(force), tol=max(settings.tolerance, 1e-9))
    return law, res, range_info


def window_menisci(pb, settings: SolverSettings) -> list | None:
    """The windows' menisci at the run's RH (``[humidity] rh``, one value): per realisation its
    two films (levelled on the window's own surfaces) and the capillary model's options, as the
    whole-grid humid kinds make them (:func:`tribobem.runs.capillary.films_at`,
    :func:`~tribobem.runs.capillary.capillary_options`); None without ``[humidity]``."""
    w = pb.two_scale
    if pb.humidity is None or w.humidity is None:
        return None
    rh = float(pb.humidity.rh[0])
    out = []
    for hs in w.humidity:
        f1, f2 = films_at(pb, rh, settings.film_tolerance, humidity=hs, grid=w.grid)
        out.append({"film1": f1.thickness, "film2": f2.thickness,
                    "options": capillary_options(pb, rh, settings, humidity=hs, periodic=w.grid.periodic)})
    return out


def _tangential_setup(pb, bar, settings):
    """The macro normal state and the windows' slip law of a two-scale tangential run."""
    sc = pb.scenario
    ts = sc.two_scale
    mu = float(sc.friction.coefficient)
    # the built windows with their menisci at the run's RH (a copy: the problem stays as built)
    windows = dataclasses.replace(pb.two_scale, capillary=window_menisci(pb, settings))
    bar.phase("micro windows (normal)", 1)
    law, res, range_info = _normal_state(pb, settings, float(sc.load.force), windows)
    bar(1, 1)
    slip_p = np.geomspace(law.pressures[0] * 10.0, law.pressures[-1], SLIP_PRESSURES)
    bar.phase("micro windows (tangential)", 1)
    try:
        slip_law = interface_slip_law(windows, slip_p, mu, tol=max(settings.tolerance, 1e-8),
                                      max_iterations=settings.max_iterations, scheduler=ts.scheduler, cache=ts.cache)
    except ValueError as exc:
        raise InputError("two_scale", f"the windows' slip table cannot be built: {exc}") from None
    bar(1, 1)
    if slip_law.capacities is not None and law.menisci is not None:
        # one repulsive pressure for the friction bound and the reported F0+: the normal table's
        # (finer in p than the slip table's own, the same windows and menisci)
        slip_law.capacity_pressures = law.pressures.copy()
        slip_law.capacities = mu * np.asarray(law.menisci["repulsive_pressures"], float)
    return law, res, range_info, slip_law


def _static_and_menisci(pb, law, res, slip_law, mu: float) -> tuple[float, dict]:
    """The burl's static friction (N: every window slides at its capacity, mu p dry, mu times its
    repulsive pressure with menisci) and, with menisci, the macro sums of the windows'
    repulsive and meniscus forces (N) and wetted area (m^2) over the loaded cells."""
    if slip_law.capacities is None:
        return mu * res.force, {}
    dA = pb.grid.dx * pb.grid.dy
    loaded = res.pressure > 0
    p = np.where(loaded, res.pressure, 0.0)
    static = float(np.sum(np.where(loaded, slip_law.capacity(np.where(loaded, p, 1.0)), 0.0))) * dA
    return static, {"repulsive_force": float(np.sum(law.meniscus("repulsive_pressures", p))) * dA,
                    "capillary_force": float(np.sum(law.meniscus("capillary_pressures", p))) * dA,
                    "wetted_area": float(np.sum(law.meniscus("wetted_fractions", p))) * dA}


def _slip_messages(slip_law) -> list:
    if slip_law.info.get("not_converged"):
        return [f"two_scale: {slip_law.info['not_converged']} of {slip_law.info['solves']} micro tangential "
                "solves did not converge"]
    return []


def _tangential_result(pb, res, slip_state, mu: float) -> TangentialResult:
    """A macro slip state as a TangentialResult for fields.nc (shear and slip along x); a cell
    sticks where most of its window's real contact sticks (the window's stick fraction >= 0.5: on
    a loop's branch, the branch's own, :attr:`~tribobem.two_scale.tangential.InterfaceSlipResult.
    cell_stick`)."""
    shear = np.zeros((2,) + pb.grid.shape)
    shear[0] = slip_state.shear
    slip = np.zeros_like(shear)
    slip[0] = slip_state.slip
    contact = res.pressure > 0
    stick = contact & (slip_state.cell_stick >= 0.5)
    return TangentialResult(grid=pb.grid, shear=shear, slip=slip, relative_displacement=slip.copy(), contact=contact,
                            stick=stick, force_x=slip_state.force, force_y=0.0,
                            displacement_x=slip_state.displacement, displacement_y=0.0, friction_coefficient=mu,
                            mode="total", control="force", iterations=slip_state.newton_iterations,
                            residual_history=np.array([slip_state.residual]), converged=slip_state.converged,
                            gross_slip=False, time=slip_state.time, info={"two_scale": True})


def run_partial_slip(pb, bar, settings: SolverSettings) -> RunOutput:
    """Kind ``partial_slip`` with ``[two_scale]``: a tangential ramp at ``load.force``.

    The macro normal state is solved once (two-scale, as :func:`run_normal`), the windows give
    the slip law at :data:`SLIP_PRESSURES` pressures, and each tangential force of
    ``friction.tangential_forces`` (``"auto"``: :data:`AUTO_FRACTIONS` of mu F) is solved at
    macro scale (:func:`tribobem.two_scale.tangential.solve_interface_tangential`).

    Parameters
    ----------
    pb : Problem
        The built two-scale problem (its operator has the x, y, z components).
    bar : progress handler
    settings : SolverSettings

    Returns
    -------
    RunOutput
        One step per tangential force below the static friction; run-level ``static_friction_force``
        (mu F), ``presliding_displacement`` (at the largest solved force) and the displacements at
        0.5 and 0.9 of the static friction (``displacement_at_half_static_friction``,
        ``displacement_at_0p9_static_friction``).
    """
    sc = pb.scenario
    fr = sc.friction
    mu = float(fr.coefficient)
    law, res, range_info, slip_law = _tangential_setup(pb, bar, settings)
    static, menisci = _static_and_menisci(pb, law, res, slip_law, mu)
    if fr.tangential_forces == "auto" or fr.tangential_forces is None:
        forces = [f * static for f in AUTO_FRACTIONS]
    else:
        forces = [float(f) for f in fr.tangential_forces]
    limit = slip_law.max_fraction * static
    solvable = [f for f in forces if 0 <= f < limit]
    state = _macro_result(pb, res, law)
    real_fraction = law.contact_fraction(res.pressure)
    rows, results, tangential, messages = [], [], [], []
    bar.phase("macro tangential steps", len(solvable))
    previous = None
    curve = []
    for k, f in enumerate(solvable):
        r = solve_interface_tangential(pb.operator, res.pressure, slip_law, f, real_fraction=real_fraction,
                                       initial_shear=previous, tol=max(settings.tolerance, 1e-9))
        previous = r.shear if f > 0 else None
        t = _tangential_result(pb, res, r, mu)
        row = _row(pb, state, res)
        row.update(t.scalars())
        row["stick_ratio"] = r.stick_ratio
        row["stick_area"] = r.stick_ratio * res.real_contact_area
        row["slip_area"] = (1.0 - r.stick_ratio) * res.real_contact_area
        row["branch"] = "ramp"
        row["converged"] = bool(res.converged and r.converged)
        row.update(menisci)
        rows.append(row)
        results.append(state)
        tangential.append(t)
        curve.append((r.force, r.displacement))
        bar(k + 1, len(solvable))
    fx = np.array([c[0] for c in curve])
    dx = np.array([c[1] for c in curve])

    def displacement_at(frac):
        target = frac * static
        if fx.size < 2 or target > fx.max():
            return None
        return float(np.interp(target, fx, dx))

    run = {"friction_coefficient": mu, "slip": "total", "direction": 0.0,
           "tangential_forces_auto": forces if fr.tangential_forces in (None, "auto") else None,
           "gross_slip": bool(len(solvable) < len(forces)),
           "static_friction_force": static, "static_friction_ratio": 1.0,
           "presliding_displacement": float(dx[-1]) if dx.size else None,
           "displacement_at_half_static_friction": displacement_at(0.5),
           "displacement_at_0p9_static_friction": displacement_at(0.9),
           "repulsive_force": res.force, "adhesive_force": 0.0, **menisci,
           "two_scale": {**range_info, "law": law.as_dict(), "slip_law": slip_law.as_dict()}}
    if menisci:
        run["rh"] = float(pb.humidity.rh[0])
    if len(solvable) < len(forces):
        messages.append(f"two_scale: {len(forces) - len(solvable)} tangential force(s) at or above "
                        f"{slip_law.max_fraction:g} mu F = {limit:.4g} N were not solved: the burl slides as a whole at "
                        f"mu F = {static:.4g} N (every window at its own mu p)")
    messages += _slip_messages(slip_law)
    labels = [f"ramp {k}" for k in range(len(rows))]
    return RunOutput(rows=rows, results=results, tangential=tangential, labels=labels,
                     indices=list(range(len(rows))), run=run, warnings=messages)


def run_hysteresis(pb, bar, settings: SolverSettings) -> RunOutput:
    """Kind ``hysteresis`` with ``[two_scale]``: a force-controlled friction loop at ``load.force``.

    The macro normal state and the slip law as :func:`run_partial_slip`; the path of
    ``friction.path`` (F* = amplitude mu F, the static friction of the two-scale burl) by
    :func:`tribobem.two_scale.tangential.interface_loop` (Masing's rule in every macro cell).
    Run level: the keys of a whole-grid loop (``dissipated_energy``, ``dissipation_work``,
    ``lateral_stiffness`` at A, B, C and its fit, ``peak_force``, ``static_friction_force``).

    Parameters
    ----------
    pb : Problem
        The built two-scale problem (operator with the x, y, z components).
    bar : progress handler
    settings : SolverSettings

    Returns
    -------
    RunOutput
    """
    sc = pb.scenario
    fr = sc.friction
    path_spec = fr.path
    mu = float(fr.coefficient)
    law, res, range_info, slip_law = _tangential_setup(pb, bar, settings)
    static, menisci = _static_and_menisci(pb, law, res, slip_law, mu)
    amplitude = float(path_spec.amplitude if path_spec.amplitude is not None else 0.999)
    if amplitude >= slip_law.max_fraction:
        raise InputError("friction.path.amplitude", f"a two-scale loop needs F* below the slip table's largest "
                         f"fraction of mu F ({slip_law.max_fraction:g}); got {amplitude:g}")
    path = cycle_path(amplitude * static, int(path_spec.cycles), int(path_spec.steps), "force")
    real_fraction = law.contact_fraction(res.pressure)
    bar.phase("macro hysteresis steps", len(path.values))
    loop = interface_loop(pb.operator, res.pressure, slip_law, path.values, path.turning, path.cycle,
                          real_fraction=real_fraction, tol=max(settings.tolerance, 1e-9), progress=bar)
    state = _macro_result(pb, res, law)
    rows, results, tangential = [], [], []
    start = solve_interface_tangential(pb.operator, res.pressure, slip_law, 0.0)
    for st, cycle, branch in [(start, 0, "start")] + list(zip(loop.states, path.cycle, path.branch)):
        t = _tangential_result(pb, res, st, mu)
        row = _row(pb, state, res)
        row.update(t.scalars())
        row.update(stick_ratio=st.stick_ratio, stick_area=st.stick_ratio * res.real_contact_area,
                   slip_area=(1.0 - st.stick_ratio) * res.real_contact_area, cycle=int(cycle), branch=branch,
                   force_ratio=st.force / static if static > 0 else float("nan"),
                   converged=bool(res.converged and st.converged), **menisci)
        rows.append(row)
        results.append(state)
        tangential.append(t)
    F = [r["tangential_force_x"] for r in rows]
    D = [r["displacement_x"] for r in rows]
    C = [r["cycle"] for r in rows]
    run = {"friction_coefficient": mu, "control": "force", "repulsive_force": res.force, "adhesive_force": 0.0,
           **menisci,
           "peak_force": amplitude * static, "dissipated_energy": loop_energies(F, D, C),
           "dissipation_work": loop.dissipation, "failed_steps": [i for i, r in enumerate(rows) if not r["converged"]],
           "static_friction_force": static, "static_friction_ratio": 1.0,
           "lateral_stiffness_reference": None,
           "lateral_stiffness_reference_note": "no analytic reference for a rough two-scale burl",
           "two_scale": {**range_info, "law": law.as_dict(), "slip_law": slip_law.as_dict(),
                         "unloading_rule": "Masing"}}
    try:
        table, fit = stiffness_table(rows, mu, res.force, None)
        run["lateral_stiffness"], run["lateral_stiffness_fit"] = table, fit
    except (InputError, RuntimeError, ValueError) as exc:
        run["lateral_stiffness"], run["lateral_stiffness_error"] = [], str(exc)
    keep = kept_states(path.turning, len(rows))
    labels = [f"{rows[i]['branch']} {rows[i]['cycle']} step {i}" for i in keep]
    return RunOutput(rows=rows, results=[results[i] for i in keep], tangential=[tangential[i] for i in keep],
                     labels=labels, indices=keep, run=run, warnings=_slip_messages(slip_law))


#: The unloading branches of a two-scale pull-off start from these fractions of the preload
#: state's largest nominal pressure (a cell's law interpolates between the two that bracket its
#: own largest pressure; below the smallest, towards the loading branch).  Dugdale: four.
UNLOADING_FRACTIONS = (1.0 / 27.0, 1.0 / 9.0, 1.0 / 3.0, 1.0)
#: With menisci two: their equilibrium menisci depend on the state, not its history (the small
#: validation burl's pull-off moves by 2e-5 from four branches to two, by 0.4 % to one).
MENISCI_UNLOADING_FRACTIONS = (1.0 / 9.0, 1.0)


def _approach_result(pb, st, law, pmax) -> NormalResult:
    """A macro state of the pull-off as a NormalResult: the net nominal pressure (negative where
    the interface pulls) and the mean-plane separation."""
    contact = law.column("contact_fractions", st.separation, pmax) > 0
    return NormalResult(grid=pb.grid, pressure=st.pressure, gap=st.separation, displacement=st.displacement,
                        contact=contact, adhesive=st.pressure < 0, force=st.force, approach=st.approach,
                        iterations=st.newton_iterations, residual_history=np.array([st.residual]),
                        converged=st.converged, time=0.0, control="displacement", info={"two_scale": True})


def run_pulloff(pb, bar, settings: SolverSettings) -> RunOutput:
    """Kind ``pulloff`` with ``[two_scale]``: load to ``load.preload``, unload to pull-off.

    The windows' normal table sets the preload state's pressures; their loading and unloading
    branches (:func:`tribobem.two_scale.tensile.tensile_interface_law`, with the run's Dugdale
    zone or its menisci at one RH) give the tensile law, with which the burl is loaded to the
    preload and unloaded under displacement control (:func:`~tribobem.two_scale.tensile.
    interface_pull_off`).  Steps: the macro states from the preload to separation; run level:
    ``pull_off_force``, ``pull_off_approach`` (lists of one with ``[humidity]``), ``preload``
    and ``two_scale`` (both tables).
    """
    from ..two_scale.tensile import interface_pull_off, tensile_interface_law

    sc = pb.scenario
    ts = sc.two_scale
    preload = float(sc.load.preload)
    windows = dataclasses.replace(pb.two_scale, capillary=window_menisci(pb, settings))
    bar.phase("micro windows (normal)", 1)
    law, res, range_info = _normal_state(pb, settings, preload, windows)
    bar(1, 1)
    top = float(res.max_nominal_pressure)
    fractions = MENISCI_UNLOADING_FRACTIONS if windows.capillary is not None else UNLOADING_FRACTIONS
    preloads = np.array([f * top for f in fractions])
    preloads = preloads[preloads >= law.pressures[0]]
    bar.phase("micro windows (loading and unloading)", 1)
    tlaw = tensile_interface_law(windows, law, preloads, tol=settings.tolerance, max_iterations=settings.max_iterations,
                                 scheduler=ts.scheduler, cache=ts.cache)
    bar(1, 1)
    bar.phase("macro unloading", None)
    po = interface_pull_off(pb.operator.normal if len(getattr(pb.operator, "components", ("z",))) > 1 else pb.operator,
                            pb.gap, tlaw, preload, res.approach, n_steps=int(sc.load.steps), refine=int(sc.load.refine),
                            tol=max(settings.tolerance, 1e-9), progress=lambda k: bar(k, None))
    dA = pb.grid.dx * pb.grid.dy
    rows = []
    humid = windows.capillary is not None
    rh = float(pb.humidity.rh[0]) if humid else None
    for k, st in enumerate(po.states):
        row = {key: po.curve[key][k] for key in po.curve}
        row["normal_force"] = row.pop("force")
        pulls = st.pressure < 0
        row.update(branch="preload" if k == 0 else "unloading", contact_area_compressive=row["contact_area"],
                   # the windows' largest asperity pressure at the compressed cells' nominal pressure
                   # (their loading table); none where no cell is compressed (the menisci outpull the contacts)
                   max_pressure=float(law.max_pressure(np.maximum(st.pressure, 0.0)).max()) if np.any(st.pressure > 0)
                   else None,
                   max_nominal_pressure=float(st.pressure.max()), adhesive_area=float(pulls.sum() * dA),
                   adhesive_force=float(st.pressure[pulls].sum() * dA), mean_gap=float(np.mean(st.separation)),
                   iterations=int(st.newton_iterations), residual=float(st.residual))
        rows.append(row)
    start = _approach_result(pb, po.preload_state, tlaw, po.pmax)
    at = _approach_result(pb, po.pull_off_state, tlaw, po.pmax)
    messages = list(po.notes)
    if not tlaw.converged:
        messages.append("two_scale: a micro window solve of the loading or unloading branches did not converge")
    if not tlaw.separated:
        messages.append("two_scale: a micro window had not separated at the top of its separation ladder; the "
                        "tensile law was cut to zero there")
    h0 = getattr(windows.interaction, "h0", None)
    if h0:
        # the windows' Dugdale zone: the gap of neighbouring window cells differs by more than the
        # law's range (the whole-grid check cohesive_range, on the windows' undeformed gaps)
        jump = max(float(np.percentile(np.abs(np.diff(g, axis=a)), 99)) for g in windows.gaps for a in (0, 1))
        if jump > h0:
            messages.append(f"two_scale.window_n: the windows' gap changes by {jump:.3g} m = {jump / h0:.2g} h0 between "
                            f"neighbouring cells (99th percentile; Dugdale range h0 = {h0:.3g} m): their cohesive zones "
                            "are not resolved, so the tensile law and the pull-off are set by the window cells; refine "
                            "two_scale.window_n")
    if tlaw.beyond_table(po.preload_state.separation):
        messages.append("two_scale.max_pressure: a macro cell is compressed beyond the table's ladder; the law "
                        "was extrapolated there")
    force, approach = float(po.force), float(po.approach)
    run = {"pull_off_force": [force] if humid else force, "pull_off_approach": [approach] if humid else approach,
           **({"rh": [rh]} if humid else {}),
           "pull_off_control": "displacement", "preload": preload, "preload_source": "load.preload",
           "two_scale": {**range_info, "law": law.as_dict(), "tensile_law": tlaw.as_dict(),
                         "strength": tlaw.strength, "pull_off_stress": force / max(float((res.pressure > 0).sum()) * dA,
                                                                                   dA),
                         "macro_time": po.time}}
    i_at = int(np.argmin([r["normal_force"] for r in rows]))
    return RunOutput(rows=rows, results=[start, at], labels=["preload", "pull-off"], indices=[0, i_at], run=run,
                     warnings=messages)
