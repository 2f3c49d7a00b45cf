"""Run kind ``capillary``: one load held while the relative humidity steps (Papers B and C).

For every RH of ``[humidity] rh`` (in the order given):

1. each body's adsorbed water film is levelled on its *undeformed* topography (thesis;
   :func:`~tribobem.interactions.films.film_thickness`, mode ``humidity.levelling``);
2. the contact is solved self-consistently with the meniscus islands
   (:func:`~tribobem.solvers.capillary.solve_capillary`: Paper B Fig. 6, an outer fixed point
   on the active islands around the normal solver), at the scenario's ``load.force`` or
   ``load.approach``, warm-started from the previous RH.

Each RH is one summary.json step with the file-contract keys ``rh``, ``capillary_force``,
``solid_solid_force``, ``water_solid_force``, ``normal_force`` (the total), ``repulsive_force``,
``contact_area``, ``wetted_area`` (meniscus area outside contact), ``island_count`` (active
islands), ``kelvin_radius``, ``film_thickness_1`` / ``_2`` (mean films), ``outer_iterations``
and ``converged`` (the contact, its island fixed point and both films), plus the normal
solver's scalars, ``capillary_pressure`` (the applied one, Pa, with Paper C's contribution
coefficient), ``contribution_coefficient``, ``adhesive_force_total`` (F_cap + F_ss + F_ws) and
the films' iterations.  Run level: ``peak_capillary_force`` (the most tensile F_cap) and
``peak_capillary_rh``.  fields.nc gets, per RH, the film thicknesses, the meniscus mask and the
island labels (runner key ``step_fields``).

Thin-film levelling (``levelling = "thin_film"``) integrates each film in time, to
``humidity.film_time`` (required without the disjoining pressure, whose films drain off the peaks
without end) or to its steady state: each film is then a progress phase of its own over the
physical time reached, and the steps record that time (``film_time_1`` / ``_2`` in s,
``film_time_tau_slow_1`` / ``_2`` in units of tau_slow); a film whose step limit came before its
end time is not converged, with a warning.

Flagged, not silent: a film whose mean thickness (both films together) reaches the relief of
the gap (its peak-to-valley) buries the roughness, and the island rule then wets the whole
non-contact area; the step carries ``films_exceed_relief = true`` and a warning says so.
"""

from __future__ import annotations

import math
import warnings

import numpy as np

from ..errors import ConvergenceWarning
from ..interactions.films import film_thickness
from ..interactions.menisci import contribution_coefficient
from ..solvers.capillary import solve_capillary
from .common import approach_below_full_contact, scenario_errors
from .kind import ALL, CAPILLARY_STEPS, RunKind, RunOutput, fail, require_elastic_body, require_humidity
from .kind import CAPILLARY_COLUMNS
from .settings import FILM_TOLERANCE_FLOOR, SolverSettings

__all__ = ["run", "check", "KIND", "films_at"]

#: fields.nc variables a capillary step adds: name -> (dtype, attributes).
STEP_FIELDS = {
    "film_thickness_1": (float, {"units": "m", "long_name": "adsorbed water film on body 1 (levelled, before contact)"}),
    "film_thickness_2": (float, {"units": "m", "long_name": "adsorbed water film on body 2 (levelled, before contact)"}),
    "meniscus": (np.int8, {"units": "1", "flag_values": "0 1",
                           "long_name": "meniscus mask: nodes of active islands outside contact (carry dP_cap)"}),
    "island_labels": (np.int32, {"units": "1", "long_name": "meniscus island label (0: above the cut height; "
                                                             "active and dry cross-cut islands)"}),
    "island_active": (np.int8, {"units": "1", "flag_values": "0 1",
                                "long_name": "1 on nodes of islands that hold a seed (contact, wetted or d_cr)"}),
}


#: Resolution of a thin-film levelling's progress phase: the time reached in 1/1000 of the end time.
FILM_PROGRESS_STEPS = 1000


def _film_progress(bar, rh: float, body: int):
    """A ``time_progress(t, t_end, tau_slow)`` of the thin-film levelling that shows the time
    reached on ``bar``: a phase of its own, opened at the first time step (when tau_slow is
    known) and named with the end time in s and in tau_slow, advanced in 1/1000 of the end time."""
    state = {"shown": -1}

    def report(t, t_end, tau_slow):
        if state["shown"] < 0:
            ratio = f" = {t_end / tau_slow:.3g} tau_slow" if tau_slow > 0 else ""
            # short: a progress line is about 80 characters wide off a wide terminal
            bar.phase(f"RH {rh:g}, film {body}: levelling to {t_end:.3g} s{ratio}", FILM_PROGRESS_STEPS)
            state["shown"] = 0
        done = min(FILM_PROGRESS_STEPS, int(FILM_PROGRESS_STEPS * t / t_end)) if t_end > 0 else FILM_PROGRESS_STEPS
        if done > state["shown"]:
            state["shown"] = done
            bar(done, FILM_PROGRESS_STEPS)

    return report


def films_at(pb, rh: float, tol: float = 1e-10, bar=None, *, humidity=None, grid=None):
    """Both bodies' levelled films at ``rh`` (:class:`~tribobem.interactions.films.FilmResult`).

    Computed on each body's undeformed topography (``pb.humidity.surface1/2``) before contact,
    as in the thesis; a dry body gets a zero film.  Thin-film levelling integrates to
    ``humidity.film_time`` when given (the form without disjoining pressure has no steady state,
    the scenario refuses it without that end time), else to its steady state.

    Parameters
    ----------
    pb : Problem
        The built scenario with ``[humidity]`` (``pb.humidity``: surfaces, isotherms, water).
    rh : float
        Relative humidity (0..1).
    tol : float
        Tolerance of the film levelling (floored at
        :data:`~tribobem.runs.settings.FILM_TOLERANCE_FLOOR`, below which it would not converge;
        a run passes its settings' ``film_tolerance``, already floored).
    bar : progress handler, optional
        Thin-film levelling: each wet body's integration is a phase of ``bar``
        (``bar.phase``, ``bar(done, total)``) advancing with the physical time reached, in
        1/1000 of the end time (:data:`FILM_PROGRESS_STEPS`).  None: nothing shown.
    humidity, grid : optional
        Other surfaces than the problem's: a humidity setup and its grid (a two-scale run's
        micro windows); default ``pb.humidity`` and ``pb.grid``.

    Returns
    -------
    (FilmResult, FilmResult)
        The films of body 1 and body 2 (thickness in m per node; ``time`` reached and
        ``levelling_time`` tau_slow in s for thin-film levelling).
    """
    hs = pb.humidity if humidity is None else humidity
    grid = pb.grid if grid is None else grid
    out = []
    for body, (surface, iso) in enumerate(((hs.surface1, hs.isotherm1), (hs.surface2, hs.isotherm2)), 1):
        kw = {}
        if hs.levelling == "thin_film":
            kw["time"] = hs.film_time
            if bar is not None:
                kw["time_progress"] = _film_progress(bar, rh, body)
        out.append(film_thickness(surface, grid, iso, rh, hs.water, mode=hs.levelling,
                                  system=None if hs.levelling == "uniform" else hs.system,
                                  disjoining=hs.disjoining, tol=max(tol, FILM_TOLERANCE_FLOOR), **kw))
    return out[0], out[1]


def capillary_options(pb, rh: float, settings: SolverSettings | None = None, *, humidity=None,
                      periodic: bool | None = None) -> dict:
    """The keyword arguments of :func:`~tribobem.solvers.capillary.solve_capillary` at ``rh``
    (all but the load, the films, the warm start and the tolerances).

    Parameters
    ----------
    pb : Problem
        The built scenario with ``[humidity]``.
    rh : float
        Relative humidity (0..1).
    settings : SolverSettings, optional
        The run's solver settings: its ``normal_method`` (default: built from ``pb.scenario``).
    humidity, periodic : optional
        Another humidity setup and periodicity than the problem's (a two-scale run's periodic
        micro windows); default ``pb.humidity`` and ``pb.grid.periodic``.

    Returns
    -------
    dict
        Kelvin radius (m), capillary pressure (Pa), contribution coefficient, adhesion law,
        Hamaker constants (J), contact angles (rad), critical distance and cutoff (m), periodicity,
        the normal solver (``[solver] method``; auto is Polonsky-Keer with ``[humidity]``).
    """
    hs = pb.humidity if humidity is None else humidity
    water = hs.water
    return {
        "kelvin_radius": water.kelvin_radius(rh),
        "capillary_pressure": water.capillary_pressure(rh),
        "contribution": contribution_coefficient(rh, hs.contribution),
        "adhesion": pb.interaction,
        "hamaker": (hs.hamaker1, hs.hamaker2),
        "water_hamaker": hs.water_hamaker,
        "van_der_waals": hs.van_der_waals,
        "contact_angles": hs.contact_angles,
        "critical_distance": hs.critical_distance,
        "cutoff": hs.cutoff,
        "periodic": pb.grid.periodic if periodic is None else bool(periodic),
        "normal_method": (settings or SolverSettings.from_scenario(pb.scenario)).normal_method,
    }


def capillary_row(state, rh: float, f1, f2, opts: dict, relief: float) -> dict:
    """A summary.json step of one RH (module docstring) from a solved capillary state.

    Parameters
    ----------
    state : CapillaryResult
        The solved state at this RH.
    rh : float
        Relative humidity (0..1).
    f1, f2 : FilmResult
        The films of body 1 and body 2.
    opts : dict
        The solver options of :func:`capillary_options` at this RH.
    relief : float
        Peak-to-valley of the initial gap (m): films at least this thick together bury the
        roughness, so the step is flagged ``films_exceed_relief``.

    Returns
    -------
    dict
        The step's scalars: forces in N, areas in m^2, radius and film thicknesses in m, pressure
        in Pa, counts, ``converged`` (state and both films); with thin-film levelling also
        ``film_time_1`` / ``_2`` (the physical time reached, s) and ``film_time_tau_slow_1`` /
        ``_2`` (the same in units of the film's tau_slow, the relaxation time of its slowest
        mode; 0 for a dry body).
    """
    row = state.normal.scalars()
    c = float(opts["contribution"])
    adh_total = state.capillary_force + state.solid_solid_force + state.water_solid_force
    films = f1.mean_thickness + f2.mean_thickness
    row.update({
        "rh": float(rh),
        "normal_force": float(state.total_force),
        "capillary_force": float(state.capillary_force),
        "solid_solid_force": float(state.solid_solid_force),
        "water_solid_force": float(state.water_solid_force),
        "adhesive_force_total": float(adh_total),
        "repulsive_force": float(state.repulsive_force),
        "contact_area": float(state.contact_area),
        "wetted_area": float(state.wetted_area),
        "island_count": int(state.island_count),
        "kelvin_radius": float(opts["kelvin_radius"]),
        "capillary_pressure": float(opts["capillary_pressure"]) * c,
        "contribution_coefficient": c,
        "film_thickness_1": float(f1.mean_thickness),
        "film_thickness_2": float(f2.mean_thickness),
        "film_iterations_1": int(f1.iterations),
        "film_iterations_2": int(f2.iterations),
        "outer_iterations": int(state.outer_iterations),
        "films_exceed_relief": bool(films > 0 and films >= relief),
        "converged": bool(state.converged and f1.converged and f2.converged),
    })
    if "thin_film" in (f1.mode, f2.mode):
        # how far the thin-film integration went: in s and in units of the slowest mode's
        # relaxation time (a dry body: 0, it has no film to level)
        for i, f in ((1, f1), (2, f2)):
            row[f"film_time_{i}"] = float(f.time)
            row[f"film_time_tau_slow_{i}"] = float(f.time / f.levelling_time) if f.levelling_time > 0 else 0.0
    return row


def step_maps(state, f1, f2) -> dict:
    """The per-RH maps of :data:`STEP_FIELDS` of one solved state.

    Parameters
    ----------
    state : CapillaryResult
        The solved state (its islands and contact mask).
    f1, f2 : FilmResult
        The films of body 1 and body 2.

    Returns
    -------
    dict
        Name -> array of ``grid.shape`` in the dtype of :data:`STEP_FIELDS`: film thicknesses (m),
        meniscus mask (active island, not in contact), island labels and active mask.
    """
    isl = state.islands
    contact = np.asarray(state.normal.contact, dtype=bool)
    active = np.asarray(isl.active, dtype=bool)
    maps = {
        "film_thickness_1": f1.thickness,
        "film_thickness_2": f2.thickness,
        "meniscus": active & ~contact,
        "island_labels": isl.labels,
        "island_active": active,
    }
    return {k: np.asarray(v).astype(STEP_FIELDS[k][0]) for k, v in maps.items()}


def step_fields(maps: dict) -> dict:
    """:attr:`~tribobem.runs.kind.RunOutput.step_fields` of a run of RH steps: its per-RH maps of
    :data:`STEP_FIELDS` with their attributes (the humid pull-off shares them, and takes them
    from here rather than reading the table).

    Parameters
    ----------
    maps : dict
        Name -> list of maps, one per RH (:func:`step_maps`); a name missing gets none.

    Returns
    -------
    dict
        Name -> (list of maps, attributes), in the order of :data:`STEP_FIELDS`.
    """
    return {name: (maps.get(name, []), attrs) for name, (_dtype, attrs) in STEP_FIELDS.items()}


def _film_notes(rh, f1, f2, film_time=None) -> list[str]:
    notes = []
    for i, f in ((1, f1), (2, f2)):
        if f.converged:
            continue
        note = f"RH {rh:g}, film on body{i}: {f.message}"
        if f.mode == "thin_film" and film_time is not None and f.time < film_time * (1.0 - 1e-12):
            # the step limit ended the integration first: the films are not those of the end time asked for
            note += (f"; its film is that of t = {f.time:.4g} s, not of humidity.film_time = {film_time:.4g} s "
                     "(give a shorter film_time)")
        notes.append(note)
    return notes


@scenario_errors  # the solvers' error keys -> scenario keys (runs.common.SCENARIO_KEYS)
def run(pb, bar, settings: SolverSettings | None = None) -> RunOutput:
    """Run a ``capillary`` scenario on its built :class:`~tribobem.scenario.build.Problem`.

    Returns its :class:`~tribobem.runs.kind.RunOutput`, with ``step_fields`` (per-RH maps
    aligned with ``results``) and ``representative`` (the index of the RH with the most tensile
    capillary force, the state ``output.fields = "last"`` keeps).

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
    """
    sc, load, hs = pb.scenario, pb.scenario.load, pb.humidity
    approach_below_full_contact(pb)
    if settings is None:
        settings = SolverSettings.from_scenario(sc)
    relief = float(np.ptp(pb.gap))
    n = len(hs.rh)
    # Thin-film levelling can dominate the run (minutes per film): each film is then a phase of
    # its own, advancing with the physical time reached, and each RH's contact solve another.
    thin = hs.levelling == "thin_film"
    if not thin:
        bar.phase("RH steps", n)
    rows, results, labels, notes = [], [], [], []
    maps: dict[str, list] = {}
    prev = None
    for k, rh in enumerate(hs.rh):
        with warnings.catch_warnings():
            # Non-convergence is flagged per step (converged = false) and gathered below.
            warnings.simplefilter("ignore", ConvergenceWarning)
            f1, f2 = films_at(pb, rh, settings.film_tolerance, bar=bar if thin else None)
            if thin:
                bar.phase(f"RH {rh:g} ({k + 1} of {n}): contact with menisci", 1)
            opts = capillary_options(pb, rh, settings)
            loadkw = {"normal_force": load.force} if load.force is not None else {"approach": load.approach}
            state = solve_capillary(pb.operator, pb.gap, **loadkw, film1=f1.thickness, film2=f2.thickness,
                                    initial=prev, grid=pb.grid, **settings.path_kw(), **opts)
        row = capillary_row(state, rh, f1, f2, opts, relief)
        rows.append(row)
        results.append(state.normal)
        labels.append(f"RH {rh:g}")
        for name, m in step_maps(state, f1, f2).items():
            maps.setdefault(name, []).append(m)
        notes += _film_notes(rh, f1, f2, hs.film_time if thin else None)
        if pb.operator is None and math.isnan(row["normal_force"]) and not any("indeterminate" in m for m in notes):
            notes.append("both bodies rigid and touching: the contact reaction is indeterminate, so the normal, "
                         "repulsive and contact forces are NaN; the capillary, solid-solid and water-solid forces "
                         "are exact")
        if not state.converged:
            notes.append(f"RH {rh:g}: {state.message}")
        if row["films_exceed_relief"]:
            notes.append(f"RH {rh:g}: the films (mean e1 + e2 = {row['film_thickness_1'] + row['film_thickness_2']:.3g} m) "
                         f"reach the relief of the gap ({relief:.3g} m peak to valley): the water buries the "
                         "roughness and the meniscus covers the whole non-contact area")
        prev = state if state.converged else prev
        if thin:
            bar(1, 1)
        else:
            bar(k + 1, n)
    fcap = np.array([r["capillary_force"] for r in rows], dtype=float)
    ipk = int(np.nanargmin(fcap)) if np.any(np.isfinite(fcap)) else 0
    run_level = {"peak_capillary_force": float(fcap[ipk]), "peak_capillary_rh": float(rows[ipk]["rh"]),
                 "load_control": "force" if load.force is not None else "approach"}
    return RunOutput(rows=rows, results=results, labels=labels, indices=list(range(n)), run=run_level,
                     warnings=notes, representative=ipk,
                     step_coords={"rh": ([r["rh"] for r in rows], {"units": "1", "long_name": "relative humidity"}),
                                  "capillary_pressure": ([r["capillary_pressure"] for r in rows],
                                                         {"units": "Pa", "long_name": "applied capillary pressure"})},
                     step_fields=step_fields(maps))


def check(sc) -> None:
    """Kind ``capillary``: ``[humidity] rh`` and one load, held at every RH (``force`` or
    ``approach``).

    Parameters
    ----------
    sc : Scenario
        The validated scenario (called by the schema after the per-section checks).

    Raises
    ------
    InputError
        Through :func:`~tribobem.runs.kind.fail`, naming the offending scenario key.
    """
    require_humidity(sc)
    if sc.load.approach is None:
        # two rigid bodies at a prescribed approach: the meniscus force of rigid bodies (Paper B
        # 4.1) is well defined; at a prescribed force the contact reaction is not
        require_elastic_body(sc)
    given = sc.load.given
    if given not in (["force"], ["approach"]):
        fail("load.force" if not given else f"load.{given[1]}",
             "kind = 'capillary' takes one load, held at every RH: force (N) or approach (m)"
             + (f" (got {', '.join(given)})" if given else ""))


KIND = RunKind(
    name="capillary", run=run, check=check,
    summary="capillary adhesion from adsorbed water films and menisci at one load, RH by RH",
    figures=("capillary", "maps"), report_sections=("capillary",),
    columns=CAPILLARY_COLUMNS,
    results={"peak_capillary_force": "force", "peak_capillary_rh": "dimensionless", **CAPILLARY_STEPS},
    uses={"load": ("force", "approach"), "humidity": ALL, "body1": ("film", "hamaker", "hardness", "layer"),
          "body2": ("film", "hamaker", "hardness", "layer"), "solver": ("method",)},
    hints={"friction": "kind = 'capillary' is frictionless; leave [friction] out",
           "load.forces": "kind = 'capillary' takes one load, held at every RH: force (N) or approach (m)",
           "load.approaches": "kind = 'capillary' takes one load, held at every RH: force (N) or approach (m)",
           "load.preload": "a capillary run takes load.force or load.approach"},
)
