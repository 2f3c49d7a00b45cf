"""Run kind ``partial_slip``: tangential contact of dissimilar bodies with Coulomb friction (Paper D).

Two paths (file-contract):

* ``load.force`` with ``friction.tangential_forces`` (or ``tangential_displacements``): a
  tangential ramp at a fixed normal load, each step solved by the normal-tangential coupling
  loop; a ramp that reaches gross slip ends there (a result, not an error) and the gross-slip
  onset is bracketed to 1e-3 x mu F0+ (:func:`~tribobem.solvers.tangential_paths.tangential_ramp`);
* ``load.forces`` (with ``slip = "incremental"``): a normal-load path with friction, the
  tangential state carried step to step; tangential forces, if given, are paired with it.

Rows carry the file-contract step keys plus ``force_ratio`` (F_t / (mu F0+)), ``stick_ratio`` and
``stick_radius_ratio`` (sqrt(A_stick / A_contact)); run level: ``friction_coefficient``,
``static_friction_force``, ``static_friction_ratio``, ``presliding_displacement``,
``gross_slip`` and the onset bracket.
"""

from __future__ import annotations

import math

from ..errors import InputError
from ..units import format_quantity
from ..solvers.normal_paths import normal_path
from ..solvers.tangential_paths import stick_radius_ratio, tangential_ramp
from .common import scenario_errors
from .humid_friction import meniscus_fields, run_per_rh
from .kind import (ALL, CAPILLARY_STEPS, TANGENTIAL_STEPS, RunKind, RunOutput, fail, positive_normal_load,
                   require_elastic_body, require_friction, require_humidity)
from .kind import TANGENTIAL_COLUMNS
from .settings import SolverSettings
from .two_scale import check_two_scale_tangential, run_partial_slip as run_two_scale

__all__ = ["run", "check", "KIND"]

#: ``tangential_forces = "auto"``: steps of the ramp (zero included) and its top in units of
#: mu F0+ (head room over the friction bound; the design chain's defaults).
AUTO_STEPS = 13
AUTO_FACTOR = 1.2


def _row(res, branch: str, mu: float, e) -> dict:
    row = res.scalars()
    row["branch"] = branch
    f0p = res.normal.repulsive_force
    ft = res.tangential.force_x * e[0] + res.tangential.force_y * e[1]
    row["force_ratio"] = ft / (mu * f0p) if mu > 0 and f0p > 0 else float("nan")
    row["stick_radius_ratio"] = stick_radius_ratio(res)
    return row


@scenario_errors  # the solvers' error keys -> scenario keys (runs.common.SCENARIO_KEYS)
def run(pb, bar, settings: SolverSettings | None = None) -> RunOutput:
    """Run a ``partial_slip`` scenario on its built :class:`~tribobem.scenario.build.Problem`.

    With ``[humidity]``: one ramp per RH under the capillary model, after a dry reference
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
        One step per solved tangential (or normal-path) value, with the coupled normal and
        tangential states for fields.nc.
    """
    if settings is None:
        settings = SolverSettings.from_scenario(pb.scenario)
    if pb.two_scale is not None:  # [two_scale]: micro windows, then the macro ramp
        return run_two_scale(pb, bar, settings)
    if pb.humidity is not None:
        return run_per_rh(pb, bar, _run_one, "partial_slip", settings)
    return _run_one(pb, bar, pb.interaction, None, "", settings)[0]


def _run_one(pb, bar, interaction, initial, label: str, settings: SolverSettings):
    """One ramp (or normal-load path) with the stress law ``interaction`` and the run's
    ``settings``; returns the RunOutput and the state at zero tangential force (the next RH's
    warm start)."""
    sc = pb.scenario
    fr, load = sc.friction, sc.load
    mu = float(fr.coefficient)
    solver_kw = settings.coupled_kw()
    onset_tol = settings.onset_tolerance
    model = interaction if getattr(interaction, "self_consistent", False) else None
    theta = math.radians(fr.direction)
    e = (math.cos(theta), math.sin(theta))
    run_level: dict = {"friction_coefficient": mu, "slip": fr.slip, "direction": fr.direction}
    prefix = f"{label}: " if label else ""
    if load.forces is not None:  # check() paired it with tangential_forces only
        bar.phase(f"{prefix}normal steps", len(load.forces))
        steps = normal_path(pb.operator, pb.gap, normal_forces=load.forces, friction_coefficient=mu,
                            tangential_forces=fr.tangential_forces, direction=fr.direction,
                            interaction=interaction, slip=fr.slip, progress=bar, **solver_kw)
        rows = [_row(r, "normal_path", mu, e) for r in steps]
        out = RunOutput(rows=rows, results=[r.normal for r in steps], tangential=[r.tangential for r in steps],
                        labels=[f"normal_path {k}" for k in range(len(steps))], indices=list(range(len(steps))),
                        run=run_level, step_fields=meniscus_fields(steps, model))
        return out, (steps[0] if steps else None)

    forces = fr.tangential_forces
    displacements = fr.tangential_displacements
    if forces is None and displacements is None:
        forces = [0.0]
    if forces == "auto":
        # F0+ first (the state at F_t = 0, adhesion and menisci included), then the ramp to
        # AUTO_FACTOR x mu F0+ from that state
        bar.phase(f"{prefix}state at zero tangential force", 1)
        zero = tangential_ramp(pb.operator, pb.gap, normal_force=load.force, friction_coefficient=mu, forces=[0.0],
                               direction=fr.direction, interaction=interaction, slip=fr.slip,
                               refine_tol=onset_tol, progress=bar, initial=initial, **solver_kw)
        if zero.zero_state is None:
            raise InputError("friction.tangential_forces", f"no equilibrium at zero tangential force: {zero.message}")
        top = AUTO_FACTOR * mu * zero.zero_state.normal.repulsive_force
        forces = [top * k / (AUTO_STEPS - 1) for k in range(AUTO_STEPS)]
        initial = zero.zero_state
        run_level["tangential_forces_auto"] = forces
    n = len(forces if forces is not None else displacements)
    bar.phase(f"{prefix}tangential steps", n)
    ramp = tangential_ramp(pb.operator, pb.gap, normal_force=load.force, friction_coefficient=mu, forces=forces,
                           displacements=displacements, direction=fr.direction, interaction=interaction,
                           slip=fr.slip, refine_tol=onset_tol, progress=bar, initial=initial, **solver_kw)
    steps = list(ramp.steps)
    rows = [_row(r, "ramp", mu, e) for r in steps]
    run_level["gross_slip"] = bool(ramp.gross_slip)
    run_level["ramp_message"] = ramp.message
    if ramp.gross_slip and ramp.onset_state is not None:
        run_level["static_friction_force"] = ramp.onset
        run_level["static_friction_ratio"] = ramp.onset_ratio
        run_level["presliding_displacement"] = ramp.presliding_displacement
        run_level["onset_bracket"] = list(ramp.onset_bracket)
        run_level["onset_refinement_steps"] = ramp.refine_steps
        run_level["onset_repulsive_force"] = ramp.onset_state.normal.repulsive_force
        run_level["onset_adhesive_force"] = ramp.onset_state.normal.adhesive_force
    elif ramp.gross_slip:
        run_level["static_friction_force"] = None
        run_level["static_friction_ratio"] = None
        run_level["presliding_displacement"] = None
    if math.isfinite(ramp.max_force):
        run_level["max_tangential_force"] = ramp.max_force
    notes = []
    if ramp.zero_state is not None:
        z = ramp.zero_state
        if not ramp.gross_slip and mu > 0:
            # where the ramp would have to go: the friction bound at the state without tangential load
            est = mu * z.normal.repulsive_force
            run_level["gross_slip_force_estimate"] = est
            last = rows[-1]["tangential_force_x"] * e[0] + rows[-1]["tangential_force_y"] * e[1] if rows else 0.0
            notes.append(f"ramp: no gross slip up to F_t = {format_quantity(last, 'force', 4)}; gross slip sets in "
                         f"near mu F0+ = {format_quantity(est, 'force', 4)} (F0+ = "
                         f"{format_quantity(z.normal.repulsive_force, 'force', 4)} at zero tangential force"
                         + (", menisci included" if z.capillary is not None else "")
                         + "): extend friction.tangential_forces beyond it, or give tangential_forces = \"auto\"")
        run_level["zero_force_stick_ratio"] = z.tangential.stick_ratio
        run_level["repulsive_force"] = z.normal.repulsive_force
        run_level["adhesive_force"] = z.normal.adhesive_force
        if z.capillary is not None:
            run_level["capillary_force"] = z.capillary.capillary_force
    states = list(steps)
    labels = [f"ramp {k}" for k in range(len(steps))]
    indices = list(range(len(steps)))
    if ramp.onset_state is not None:
        # The last state with stick at the refined onset: the map a user wants to see.
        states.append(ramp.onset_state)
        labels.append("onset")
        indices.append(-1)
    if not steps:
        # Even the first value slides grossly: report it with the F_t = 0 state (the largest
        # force with an equilibrium is in max_tangential_force), not as an error.
        if ramp.zero_state is None:
            raise InputError("friction.tangential_forces", f"no step of the ramp has an equilibrium: {ramp.message}")
        z = ramp.zero_state
        rows = [_row(z, "zero_force", mu, e)]
        states, labels, indices = [z], ["zero force"], [0]
    out = RunOutput(rows=rows, results=[s.normal for s in states], tangential=[s.tangential for s in states],
                    labels=labels, indices=indices, run=run_level, step_fields=meniscus_fields(states, model),
                    warnings=notes)
    return out, ramp.zero_state


def check(sc) -> None:
    """Kind ``partial_slip``: mu; one normal force held during a tangential ramp (forces or
    displacements, at most one), or a normal-load path (``load.forces``, incremental slip) paired
    step by step with tangential forces.

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
    if len(fr.tangential_given) > 1:
        fail("friction.tangential_displacements", "give at most one of tangential_forces (force "
             "control) or tangential_displacements (displacement control)")
    if load.force is None and load.forces is None:
        fail("load.force", "required for kind = 'partial_slip': the normal force held during the "
                           "tangential ramp (or load.forces, a normal-load path)")
    if load.force is not None and load.forces is not None:
        fail("load.forces", "give one of load.force (held during the tangential ramp) or "
                            "load.forces (a normal-load path), not both")
    positive_normal_load(sc)
    if load.forces is not None:
        if fr.slip == "total" and len(load.forces) > 1:
            fail("friction.slip", "must be 'incremental' with a normal-load path (load.forces with "
                 f"{len(load.forces)} forces): the total criterion solves every step from the "
                 "undeformed state and has no history, so it cannot follow a path")
        if fr.tangential_displacements is not None:
            fail("friction.tangential_displacements", "a normal-load path (load.forces) pairs with "
                                                      "tangential_forces only")
        if fr.tangential_forces == "auto":
            fail("friction.tangential_forces", "\"auto\" is a ramp to gross slip at one normal force (load.force); "
                 "a normal-load path (load.forces) pairs with a list of tangential forces")
        for key in fr.tangential_given:
            n_t = len(getattr(fr, key))
            if n_t != len(load.forces):
                fail(f"friction.{key}", f"with load.forces the two lists are paired step by step and "
                     f"must have the same length; got {n_t} against {len(load.forces)} normal forces")
    if sc.two_scale is not None:
        # what the two-scale ramp supports: one normal force, a force ramp, dry, along x
        if load.forces is not None:
            fail("load.forces", "a two-scale partial_slip run is a tangential ramp at one normal force (load.force)")
        if fr.tangential_displacements is not None:
            fail("friction.tangential_displacements", "a two-scale ramp is force-controlled: give "
                 "friction.tangential_forces (or \"auto\")")
        if "slip" in fr.model_fields_set and fr.slip != "total":
            fail("friction.slip", "a two-scale ramp is monotonic from the undeformed state: slip = 'total'")
        check_two_scale_tangential(sc, "ramp")


_APPROACH = ("approach-controlled normal loads are not supported for kind = 'partial_slip'; give "
             "load.force (held during the tangential ramp) or load.forces (a normal-load path)")

KIND = RunKind(
    name="partial_slip", run=run, check=check,
    summary="partial slip along a tangential ramp or a normal-load path, to the gross-slip onset",
    figures=("load_curve", "friction", "humid_friction", "two_scale", "maps"), report_sections=("friction", "humid_friction"),
    columns=TANGENTIAL_COLUMNS, humid_columns=("rh",) + TANGENTIAL_COLUMNS,
    results={"static_friction_force": "force", "static_friction_ratio": "dimensionless",
             "presliding_displacement": "length", "max_tangential_force": "force",
             "zero_force_stick_ratio": "dimensionless", "gross_slip_force_estimate": "force",
             "displacement_at_half_static_friction": "length", "displacement_at_0p9_static_friction": "length",
             **TANGENTIAL_STEPS, **CAPILLARY_STEPS},
    uses={"load": ("force", "forces"),
          "friction": ("coefficient", "tangential_forces", "tangential_displacements", "direction", "slip"),
          "humidity": ALL, "body1": ("film", "hamaker", "hardness", "layer"),
          "body2": ("film", "hamaker", "hardness", "layer"), "solver": ("method",),
          "two_scale": ALL},
    hints={"friction.path": "a partial_slip ramp is friction.tangential_forces or "
                            "friction.tangential_displacements",
           "load.approach": _APPROACH, "load.approaches": _APPROACH},
)
