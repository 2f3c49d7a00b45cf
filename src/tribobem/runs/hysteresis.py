"""Run kind ``hysteresis``: tangential force or displacement cycles (Papers E and F).

``[load] force`` is the normal force; ``[friction] path = {control, amplitude | stroke, cycles,
steps}`` the tangential path (:func:`~tribobem.solvers.hysteresis.cycle_path`).  Rows: the file-contract
step keys plus ``cycle``, ``branch``, ``force_ratio`` (F_x / (mu F0+ at F_x = 0)); the first
row is the start (Paper E point A, F_x = 0, one-shot solve).  Run level: ``dissipated_energy``
(loop area per cycle, J), ``dissipation_work`` (sum of q . ds per cycle, J: the same energy from
the tractions), ``static_friction_force`` (first step without stick on the first loading branch),
``presliding_displacement``, ``sliding_force`` (displacement paths in gross sliding),
``lateral_stiffness`` (points A, B, C: F_x/(mu F0+) = -0.5, 0, 0.5 on the last branch from -F*
to +F*; beside the fit, the slopes of the geometry's analytic reference, named by
``lateral_stiffness_reference``: :func:`tribobem.analytic.tangential_axisymmetric.lateral_reference`),
``loop_change`` (between the last two loops: max |dF_x| / mu F0+ on displacement paths, max
|d delta_x| / loop width on force paths).  The run-level values take F_x and delta_x along
the load direction (``friction.direction``; the x components for direction 0).
"""

from __future__ import annotations

import numpy as np

from ..analysis.loops import STIFFNESS_POINTS
from ..analytic.tangential_axisymmetric import lateral_reference, reference_geometry
from ..analytic.mindlin import mindlin_compliance_k
from ..analytic.tangential_axisymmetric import sphere_partial_slip
from ..errors import InputError
from ..solvers.hysteresis import hysteresis_loop, loop_energies
from .common import scenario_errors
from .humid_friction import meniscus_fields, run_per_rh
from .kind import (ALL, CAPILLARY_STEPS, TANGENTIAL_STEPS, RunKind, RunOutput, fail, positive_normal_load,
                   require_elastic_body, require_friction, require_humidity)
from .kind import TANGENTIAL_COLUMNS
from .settings import SolverSettings
from .loop_stiffness import _along, kept_states, lateral_stiffness_fit, stiffness_table
from .two_scale import check_two_scale_tangential, run_hysteresis as run_two_scale

__all__ = ["run", "check", "KIND", "lateral_stiffness_fit", "STIFFNESS_POINTS"]



@scenario_errors  # the solvers' error keys -> scenario keys (runs.common.SCENARIO_KEYS)
def run(pb, bar, settings: SolverSettings | None = None) -> RunOutput:
    """Run a ``hysteresis`` scenario on its built :class:`~tribobem.scenario.build.Problem`.

    With ``[humidity]``: one loop per RH under the capillary model, after a dry reference
    (:mod:`tribobem.runs.humid_friction`).

    Parameters
    ----------
    pb : Problem
        The built scenario (grid, elastic operator, gap in m, loads in N or m, interaction,
        solver settings).
    bar : progress handler
        ``bar.phase(description, total)`` starts a phase, ``bar(done, total)`` reports its
        progress (the CLI's progress bar, or a no-op).
    settings : SolverSettings, optional
        The run's solver settings (:mod:`tribobem.runs.settings`; default: built from
        ``pb.scenario``).

    Returns
    -------
    RunOutput
        One step per point of the cyclic path, with the loop's run-level values (energies in J,
        lateral stiffness in N/m) and the states for fields.nc.
    """
    if settings is None:
        settings = SolverSettings.from_scenario(pb.scenario)
    if pb.two_scale is not None:  # [two_scale]: micro windows, then the macro loop (Masing's rule)
        return run_two_scale(pb, bar, settings)
    if pb.humidity is not None:
        return run_per_rh(pb, bar, _run_one, "hysteresis", settings)
    return _run_one(pb, bar, pb.interaction, None, "", settings)[0]


def _run_one(pb, bar, interaction, initial, label: str, settings: SolverSettings):
    """One loop with the stress law ``interaction`` and the run's ``settings``; returns the
    RunOutput and its start (F_x = 0, the next RH's warm start)."""
    sc = pb.scenario
    fr, load = sc.friction, sc.load
    path = fr.path
    mu = float(fr.coefficient)
    model = interaction if getattr(interaction, "self_consistent", False) else None

    solver_kw = settings.coupled_kw()
    n_steps = max(path.steps // 4, 4) + path.cycles * 2 * (path.steps // 2)
    bar.phase(f"{label}: hysteresis steps" if label else "hysteresis steps", n_steps)
    res = hysteresis_loop(pb.operator, pb.gap, normal_force=load.force, friction_coefficient=mu, control=path.control,
                          amplitude=path.amplitude if path.amplitude is not None else 0.999, stroke=path.stroke,
                          cycles=path.cycles, steps=path.steps, direction=fr.direction, interaction=interaction,
                          moving_gap=pb.shifted_gap if pb.upper_moves_visibly else None, progress=bar,
                          initial=initial, **solver_kw)
    e = res.direction
    f0p = res.start.normal.repulsive_force

    def row(r, cycle, branch):
        d = r.scalars()
        d.update(cycle=int(cycle), branch=branch)
        ft = r.tangential.force_x * e[0] + r.tangential.force_y * e[1]
        d["force_ratio"] = ft / (mu * f0p) if mu > 0 and f0p > 0 else float("nan")
        return d

    rows = [row(res.start, 0, "start")]
    rows += [row(r, c, b) for r, c, b in zip(res.steps, res.path.cycle, res.path.branch)]
    # the loop along the load direction (direction 90: the y components, not F_x = 0)
    F = [_along(r, e)[0] for r in rows]
    D = [_along(r, e)[1] for r in rows]
    C = [r["cycle"] for r in rows]
    run_level = {"friction_coefficient": mu, "control": path.control, "repulsive_force": f0p,
                 "adhesive_force": res.start.normal.adhesive_force,
                 "peak_force": res.peak_force if path.control == "force" else None,
                 "dissipated_energy": loop_energies(F, D, C),
                 "dissipation_work": [float(w.sum()) * pb.grid.cell_area for w in res.dissipation[1:]],
                 "failed_steps": [int(i) + 1 for i in res.failed],
                 # cells [i0, i1, j0, j1] of the window the last step was solved on (solvers/window.py:
                 # exact, checked each step), or None: the whole grid
                 "solve_window": (list(res.steps[-1].normal.info["window"])
                                  if res.steps and "window" in res.steps[-1].normal.info else None)}
    # Gross-slip onset on the first loading branch.
    load_rows = [r for r in rows if r["branch"] in ("start", "loading")]
    onset = next((r for r in load_rows if r["stick_area"] == 0.0 and r["branch"] == "loading"), None)
    if onset is not None:
        run_level["static_friction_force"] = _along(onset, e)[0]
        run_level["static_friction_ratio"] = onset["force_ratio"]
        run_level["presliding_displacement"] = _along(onset, e)[1] - _along(rows[0], e)[1]
    if res.offsets and np.any(res.offsets):
        run_level["counterface_offset_max"] = float(np.max(np.hypot(*np.array(res.offsets).T)))
    if path.control == "displacement":
        gross = [abs(_along(r, e)[0]) for r in rows if r.get("gross_slip")]
        run_level["sliding_force"] = float(np.mean(gross)) if gross else None
    # Change between the last two loops: max |dF_x| / (mu F0+) on displacement paths, max
    # |d delta_x| / (loop width in delta_x) on force paths (the prescribed quantity does not change).
    last = [i for i, r in enumerate(rows) if r["cycle"] == path.cycles]
    prev = [i for i, r in enumerate(rows) if r["cycle"] == path.cycles - 1 and r["cycle"] >= 1]
    if last and prev and len(last) == len(prev):
        if path.control == "displacement":
            dF = max(abs(F[i] - F[j]) for i, j in zip(last, prev))
            run_level["loop_change"] = dF / (mu * f0p) if mu > 0 else None
        else:
            dd = max(abs(D[i] - D[j]) for i, j in zip(last, prev))
            width = max(D[i] for i in last) - min(D[i] for i in last)
            run_level["loop_change"] = dd / width if width > 0 else None
    # Lateral stiffness (Paper F) on the last branch from -F* to +F*.
    # The K_L reference matches the geometry (tribobem.analytic.tangential_axisymmetric.lateral_reference): a sphere
    # keeps Mindlin-Deresiewicz at its smooth Hertz radius at F0+, also when rough or dissimilar
    # (Paper F's smooth-ball comparison; rough contacts have a much smaller real area); a smooth
    # uncoupled burl gets the rounded punch of Ciavarella-Jaeger; other cases none.
    inputs = sc.model_dump(mode="json")
    b1, b2 = pb.pair.body1, pb.pair.body2
    try:
        if reference_geometry(inputs)[0] == "sphere":
            k_comp = mindlin_compliance_k(b1.E, b1.nu, b2.E, b2.nu)
            radius = (3.0 * f0p * pb.info["radius"] / (4.0 * pb.pair.effective_modulus)) ** (1.0 / 3.0)
            reference, ref_note = sphere_partial_slip(force=f0p, mu=mu, k=k_comp, contact_radius=radius), ""
        else:
            reference, ref_note = lateral_reference(inputs, f0p, mu)
    except InputError as exc:  # mu = 0, no compressive force
        reference, ref_note = None, f"no analytic reference: {exc}"
    run_level["lateral_stiffness_reference"] = reference.name if reference is not None else None
    if reference is None:
        run_level["lateral_stiffness_reference_note"] = ref_note
    try:
        table, fit = stiffness_table(rows, mu, f0p, reference, e)
        run_level["lateral_stiffness"] = table
        run_level["lateral_stiffness_fit"] = fit
    except (InputError, RuntimeError, ValueError) as exc:
        run_level["lateral_stiffness"] = []
        run_level["lateral_stiffness_error"] = str(exc)
    # Fields: the start and each turning point (Paper E A, D, H, L ...) and the step after (A', D', H').
    keep = kept_states(res.path.turning, len(rows))
    all_states = [res.start] + res.steps
    kept = [all_states[i] for i in keep]
    results = [s.normal for s in kept]
    tangential = [s.tangential for s in kept]
    labels = [f"{rows[i]['branch']} {rows[i]['cycle']} step {i}" for i in keep]
    cycle_fields = {}
    if len(res.dissipation) > 1:
        cycle_fields = {
            "dissipation": (res.dissipation[1:], {"units": "J m-2", "long_name": "frictional dissipation per cycle "
                                                  "(sum of -q . ds over the cycle's steps)"}),
            "accumulated_slip": (res.accumulated_slip[1:], {"units": "m", "long_name": "accumulated slip length per "
                                                            "cycle (sum of |ds|)"}),
        }
    if res.start.capillary is not None:
        run_level["capillary_force"] = res.start.capillary.capillary_force
    out = RunOutput(rows=rows, results=results, tangential=tangential, labels=labels, indices=keep,
                    run=run_level, cycle_fields=cycle_fields, step_fields=meniscus_fields(kept, model))
    return out, res.start


def check(sc) -> None:
    """Kind ``hysteresis``: mu, ``friction.path`` and one normal force held during the cycles;
    incremental slip (the loop follows the history); mu > 0 on a force-controlled path.

    Parameters
    ----------
    sc : Scenario
        The validated scenario (called by the schema after the per-section checks).

    Raises
    ------
    InputError
        Through :func:`~tribobem.runs.kind.fail`, naming the offending scenario key.
    """
    require_elastic_body(sc)
    fr, load = require_friction(sc), sc.load
    if sc.humidity is not None:
        require_humidity(sc)
    if fr.path is None:
        fail("friction.path", "required for kind = 'hysteresis': e.g. { control = \"force\", "
             "amplitude = 0.999, cycles = 3, steps = 80 } or { control = \"displacement\", "
             "stroke = \"3 um\", cycles = 4, steps = 80 }")
    if "slip" in fr.model_fields_set and fr.slip == "total":
        fail("friction.slip", "a hysteresis loop follows the load history: slip must be 'incremental' "
                              "(or left out); the total criterion has no history")
    if fr.path.control == "force" and fr.coefficient == 0:
        fail("friction.coefficient", "must be > 0 for a force-controlled path: its amplitude is a "
                                     "fraction of mu F0+ (got 0)")
    if load.force is None:
        fail("load.force", "required for kind = 'hysteresis': the normal force held during the "
                           "tangential cycles (> 0 N without adhesion)")
    positive_normal_load(sc)
    if sc.two_scale is not None:
        # what the two-scale loop supports: a force path along x, dry, non-adhesive
        if fr.path.control != "force":
            fail("friction.path.control", "a two-scale loop is force-controlled (control = 'force')")
        check_two_scale_tangential(sc, "loop")


_ONE_FORCE = "kind = 'hysteresis' takes one normal force, load.force (held during the tangential cycles)"
_PATH = "its tangential loading is friction.path"

KIND = RunKind(
    name="hysteresis", run=run, check=check,
    summary="friction hysteresis: tangential force or displacement cycles at one normal force",
    figures=("hysteresis", "friction", "humid_friction", "two_scale", "maps"),
    report_sections=("humid_friction", "hysteresis"),
    columns=TANGENTIAL_COLUMNS, humid_columns=("rh",) + TANGENTIAL_COLUMNS,
    results={"static_friction_force": "force", "static_friction_ratio": "dimensionless",
             "presliding_displacement": "length", **TANGENTIAL_STEPS, **CAPILLARY_STEPS},
    uses={"load": ("force",), "friction": ("coefficient", "direction", "slip", "path"),
          "humidity": ALL, "body1": ("film", "hamaker", "hardness", "layer"),
          "body2": ("film", "hamaker", "hardness", "layer"), "solver": ("method",),
          "two_scale": ALL},
    hints={"load.forces": _ONE_FORCE, "load.approach": _ONE_FORCE, "load.approaches": _ONE_FORCE,
           "friction.tangential_forces": _PATH, "friction.tangential_displacements": _PATH},
)
