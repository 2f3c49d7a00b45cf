"""The figure sets a run kind declares (:attr:`tribobem.runs.kind.RunKind.figures`) and
:func:`make_figures`, which draws them: the one place that says which figures a result folder
gets.  Each set draws what applies to the run's kind and the sections it used
(:func:`tribobem.output.run_kind.run_view`), never guessed from the step rows' keys.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..fields import representative_step
from ..plotting import friction_coefficient as _friction_coefficient
from ..run_kind import run_view
from ..capillary import capillary_figures, capillary_step
from ..humid import humid_friction_figures, rh_summary
from .humid_maps import humid_stickslip_figure, humid_stickslip_steps
from .hysteresis import hysteresis_figures, loop_map_steps, loop_stickslip_figure
from .load_curve import force_curve_figure
from .maps import contact_figure, plastic_figure, pressure_figure, profile_figure, subsurface_figure, topography_figure
from .stickslip import _rows_with, _step_name, _step_number, stick_normal_figure, stick_ratio_figure
from .stickslip import stickslip_figure, stickslip_steps
from .two_scale import interface_law_figure, slip_law_figure

#: File stems of the figures, in report order.  ``stickslip`` stands for the stick/slip maps,
#: one per shown step, named ``stickslip_step<k>`` (k: the step's index in summary.json), or,
#: for a hysteresis run, one multi-panel ``stickslip_loop`` at Paper E's points (A, D, D' ...),
#: for a humid partial-slip run one multi-panel ``stickslip_rh`` (a map per RH);
#: ``dissipation`` for ``dissipation_cycle<k>`` (hysteresis: maps of the last cycle).
FIGURE_NAMES = ("interface_law", "hysteresis_loop", "humid_friction_rh", "humid_friction_curve", "capillary_forces", "pulloff_rh",
                "force_curve", "stick_ratio", "stick_normal",
                "stickslip", "lateral_stiffness", "dissipation", "meniscus", "films", "pressure", "contact", "profile",
                "pressure_pulloff", "contact_pulloff", "plastic", "subsurface", "topography")


def _constant_normal_force(summary: dict) -> bool:
    """True for a tangential run at a fixed normal force (the force curve says nothing)."""
    rows = _rows_with(summary, "normal_force")
    if not rows or not run_view(summary).friction:
        return False
    fn = np.array([float(r["normal_force"]) for r in rows])
    return bool(np.ptp(fn) <= 1e-6 * max(np.max(np.abs(fn)), 1e-300))


def load_curve_figures(ds, summary: dict, outdir) -> dict:
    """Figure set ``load_curve``: the force-approach curve (not for a tangential run at a fixed
    normal force, nor for RH steps: there the curve says nothing).

    Parameters
    ----------
    ds : xarray.Dataset or None
        The fields of the run (fields.nc); None: only what the summary alone gives.
    summary : dict
        The run summary (summary.json).
    outdir : path-like
        Folder of the PNG files.

    Returns
    -------
    dict
        Figure name -> Path of the PNG written; empty when the set does not apply.
    """
    if _constant_normal_force(summary) or run_view(summary).rh_steps:
        return {}
    fc = force_curve_figure(summary, Path(outdir) / "force_curve.png")
    return {"force_curve": fc} if fc is not None else {}


def friction_figures(ds, summary: dict, outdir) -> dict:
    """Figure set ``friction``: stick ratio against F_x/(mu F0+) (or against the normal force
    of a normal-load path) and the stick/slip maps of the shown steps (a hysteresis run shows
    its maps at Paper E's points instead: set ``hysteresis``).  A humid run: the stick/slip
    maps of one state per RH (``stickslip_rh``) only; its curves per RH are set
    ``humid_friction``'s.

    Parameters
    ----------
    ds : xarray.Dataset or None
        The fields of the run (fields.nc); None: only what the summary alone gives.
    summary : dict
        The run summary (summary.json).
    outdir : path-like
        Folder of the PNG files.

    Returns
    -------
    dict
        Figure name -> Path of the PNG written; empty when the set does not apply.
    """
    outdir = Path(outdir)
    out = {}
    view = run_view(summary)
    if view.humid_friction:
        # one ramp or loop per RH: the curves per RH are set humid_friction's (one line through
        # every RH tangles); the maps: one per RH (partial_slip), Paper E's points (hysteresis)
        if ds is None or view.hysteresis:
            return out
        fig = humid_stickslip_figure(ds, humid_stickslip_steps(ds), outdir / "stickslip_rh.png",
                                     mu=_friction_coefficient(summary, ds))
        return {"stickslip_rh": fig} if fig is not None else out
    for name, func in (("stick_normal", stick_normal_figure), ("stick_ratio", stick_ratio_figure)):
        try:
            fig = func(summary, outdir / f"{name}.png")
        except (KeyError, TypeError, ValueError, IndexError):  # never fail a run on a figure
            fig = None
        if fig is not None:
            out[name] = fig
            break  # a normal-load path has no F_x axis: one or the other
    if ds is None or (view.hysteresis and loop_map_steps(ds, summary)):
        return out
    maps = stickslip_steps(ds)
    if maps:
        mu = _friction_coefficient(summary, ds)
        qmax = max(float(np.nanmax(np.hypot(np.nan_to_num(ds["shear_x"].values[i]),
                                            np.nan_to_num(ds["shear_y"].values[i])))) for i in maps)
        names = set()
        for i in maps:
            k = _step_number(ds, i)
            # a summary.json step by its index; another state (the onset) by its label
            name = (f"stickslip_step{k}" if k is not None
                    else "stickslip_" + "".join(c if c.isalnum() else "_" for c in _step_name(ds, i)))
            name = name if name not in names else f"stickslip_field{i}"
            names.add(name)
            out[name] = stickslip_figure(ds, i, outdir / f"{name}.png", mu=mu, qmax=qmax or None)
    return out


def hysteresis_run_figures(ds, summary: dict, outdir) -> dict:
    """Figure set ``hysteresis``: the loop, the lateral stiffness, the last cycle's dissipation
    and the stick/slip maps at Paper E's points (:func:`hysteresis_figures`).

    Parameters
    ----------
    ds : xarray.Dataset or None
        The fields of the run (fields.nc); None: only what the summary alone gives.
    summary : dict
        The run summary (summary.json).
    outdir : path-like
        Folder of the PNG files.

    Returns
    -------
    dict
        Figure name -> Path of the PNG written; empty for a run that is not a hysteresis run.
    """
    view = run_view(summary)
    if not view.hysteresis:
        return {}
    offset, title = 0, None
    if view.humid_friction:
        # the loop of the last RH, whose per-cycle maps fields.nc keeps; every RH's loop: set
        # humid_friction
        summary, offset = rh_summary(summary, -1)
        title = f"stick and slip at Paper E's points, RH {100 * summary['rh']:.3g} %"
    out = hysteresis_figures(ds, summary, outdir)
    picks = loop_map_steps(ds, summary, offset) if ds is not None else []
    if picks:
        out["stickslip_loop"] = loop_stickslip_figure(ds, picks, Path(outdir) / "stickslip_loop.png",
                                                      mu=_friction_coefficient(summary, ds), title=title)
    return out


def humid_friction_run_figures(ds, summary: dict, outdir) -> dict:
    """Figure set ``humid_friction``: friction values against RH with the dry reference, and the
    friction curve or loops one per RH (:func:`tribobem.output.humid.humid_friction_figures`).

    Parameters
    ----------
    ds : xarray.Dataset or None
        The fields of the run (fields.nc); None: only what the summary alone gives.
    summary : dict
        The run summary (summary.json).
    outdir : path-like
        Folder of the PNG files.

    Returns
    -------
    dict
        Figure name -> Path of the PNG written; empty for a dry run.
    """
    return humid_friction_figures(ds, summary, outdir)


def capillary_run_figures(ds, summary: dict, outdir) -> dict:
    """Figure set ``capillary``: the force components against RH, the humid pull-off, the
    meniscus and film maps (:func:`tribobem.output.capillary.capillary_figures`), for RH steps.

    Parameters
    ----------
    ds : xarray.Dataset or None
        The fields of the run (fields.nc); None: only what the summary alone gives.
    summary : dict
        The run summary (summary.json).
    outdir : path-like
        Folder of the PNG files.

    Returns
    -------
    dict
        Figure name -> Path of the PNG written; empty without RH steps.
    """
    return capillary_figures(ds, summary, outdir) if run_view(summary).rh_steps else {}


def map_figures(ds, summary: dict, outdir) -> dict:
    """Figure set ``maps``: pressure, contact and profile of the representative state (a pull-off
    run: the most loaded state and the state at pull-off; RH steps: the peak capillary force),
    and the topography.

    Parameters
    ----------
    ds : xarray.Dataset or None
        The fields of the run (fields.nc); None: only what the summary alone gives.
    summary : dict
        The run summary (summary.json).
    outdir : path-like
        Folder of the PNG files.

    Returns
    -------
    dict
        Figure name -> Path of the PNG written; empty without fields.
    """
    if ds is None:
        return {}
    outdir = Path(outdir)
    out = {}
    sub = subsurface_figure(ds, outdir / "subsurface.png")  # with [output] stresses
    if sub is not None:
        out["subsurface"] = sub
    if "plastic_displacement" in ds and ds.sizes.get("step", 0):
        # a hardness cap: the flattening after the most loaded state
        f = np.asarray(ds["normal_force"].values, dtype=float)
        pl = plastic_figure(ds, int(np.nanargmax(f)) if np.any(np.isfinite(f)) else 0, outdir / "plastic.png")
        if pl is not None:
            out["plastic"] = pl
    capillary = run_view(summary).rh_steps  # the maps of a humid run: at the peak capillary force
    step = representative_step(ds)
    if capillary and step is not None and capillary_step(ds, summary) is not None:
        step = capillary_step(ds, summary)  # the maps at the peak capillary force
    if step is not None:
        labels = [str(v) for v in ds["label"].values]
        po = labels.index("pull-off") if "pull-off" in labels else None
        f = np.asarray(ds["normal_force"].values, dtype=float)
        loaded = int(np.nanargmax(f)) if np.any(np.isfinite(f)) else step
        if po is not None and loaded != po:
            # pull-off runs: maps of the most loaded state, and of the state at pull-off
            out["pressure"] = pressure_figure(ds, loaded, outdir / "pressure.png")
            out["contact"] = contact_figure(ds, loaded, outdir / "contact.png")
            out["profile"] = profile_figure(ds, po, outdir / "profile.png")
            out["pressure_pulloff"] = pressure_figure(ds, po, outdir / "pressure_pulloff.png")
            out["contact_pulloff"] = contact_figure(ds, po, outdir / "contact_pulloff.png")
        else:
            out["pressure"] = pressure_figure(ds, step, outdir / "pressure.png")
            if not capillary:  # the meniscus maps show contact, Dugdale zone and menisci instead
                out["contact"] = contact_figure(ds, step, outdir / "contact.png")
            out["profile"] = profile_figure(ds, step, outdir / "profile.png")
    out["topography"] = topography_figure(ds, outdir / "topography.png")
    return out


def two_scale_figures(ds, summary: dict, outdir) -> dict:
    """Figure set ``two_scale``: the interface laws of the micro windows, normal and (ramps and
    loops) tangential (a run with ``[two_scale]``; nothing otherwise).

    Parameters
    ----------
    ds : xarray.Dataset or None
        The fields of the run (unused: the law is in the summary).
    summary : dict
        The run summary (summary.json).
    outdir : path-like
        Folder of the PNG files.

    Returns
    -------
    dict
        Figure name -> Path of the PNG written; empty without a two-scale table.
    """
    out = {}
    f = interface_law_figure(summary, Path(outdir) / "interface_law.png")
    if f is not None:
        out["interface_law"] = f
    f = slip_law_figure(summary, Path(outdir) / "slip_law.png")
    if f is not None:  # a ramp or a loop: the windows' tangential law
        out["slip_law"] = f
    return out


#: The figure sets a run kind names (:attr:`tribobem.runs.kind.RunKind.figures`): name -> a
#: function ``(ds, summary, outdir) -> {figure name: Path}`` that draws what applies.
FIGURE_SETS = {
    "load_curve": load_curve_figures,
    "friction": friction_figures,
    "hysteresis": hysteresis_run_figures,
    "capillary": capillary_run_figures,
    "humid_friction": humid_friction_run_figures,
    "maps": map_figures,
    "two_scale": two_scale_figures,
}


def make_figures(ds, summary: dict, outdir, sets=None) -> dict:
    """Draw the figures of a run into ``outdir``.

    Parameters
    ----------
    ds : xarray.Dataset or None
        The fields (fields.nc); None: only the figures drawn from the summary.
    summary : dict
        The run summary (summary.json).
    outdir : path-like
        Folder for the PNG files (created).
    sets : sequence of str, optional
        The figure sets to draw (keys of :data:`FIGURE_SETS`), as the run kind declares them;
        default: every set (each draws only what the summary and fields hold).

    Returns
    -------
    dict
        Figure name -> Path, in :data:`FIGURE_NAMES` order.
    """
    outdir = Path(outdir)
    outdir.mkdir(parents=True, exist_ok=True)
    names = tuple(FIGURE_SETS) if sets is None else tuple(sets)
    unknown = [n for n in names if n not in FIGURE_SETS]
    if unknown:
        raise ValueError(f"unknown figure set(s) {unknown}; known: {', '.join(FIGURE_SETS)}")
    out = {}
    for name in names:
        out.update(FIGURE_SETS[name](ds, summary, outdir))
    ordered = {}
    for k in FIGURE_NAMES:
        if k in ("stickslip", "dissipation"):
            ordered.update({n: p for n, p in out.items() if n.startswith(k + "_")})
        elif k in out:
            ordered[k] = out[k]
    return ordered
