"""design_report.html: the ranking against the targets, Pareto plots, every warning.

A self-contained page (figures embedded as base64 PNG, the run report's stylesheet) with the
targets, the ranked table, two Pareto plots (static friction force against |pull-off force|;
lateral stiffness at point B against the real contact area; the non-dominated points joined and
ringed), the failed points with their messages, and every warning of every point.
"""

from __future__ import annotations

import base64
import datetime as _dt
import html
import io
import json
import math
import os
from pathlib import Path

import numpy as np

from ..output.atomic import atomic_write_text
from ..output.plotting import DPI, new_figure, spread_labels
from ..output.report import _CSS
from ..units import display_unit

__all__ = ["pareto_front", "render_design_report", "write_design_report", "PARETO_PLOTS"]

#: The Pareto plots: (x column, y column, default sense of x, default sense of y), a sense
#: being "max" (larger is better) or "min"; x and y of ``pull_off_force`` are its magnitude.
PARETO_PLOTS = (
    ("pull_off_force", "static_friction_force", "min", "max"),
    ("contact_area", "lateral_stiffness_B", "min", "max"),
)

_DIMS = {"static_friction_force": "force", "pull_off_force": "force", "contact_area": "area",
         "lateral_stiffness_A": "stiffness", "lateral_stiffness_B": "stiffness", "lateral_stiffness_C": "stiffness",
         "max_pressure": "pressure", "peak_pressure": "pressure", "presliding_displacement": "length",
         "static_friction_ratio": "dimensionless", "repulsive_force": "force", "capillary_force": "force"}

_LABELS = {"static_friction_force": "static friction force", "pull_off_force": "|pull-off force|",
           "contact_area": "real contact area", "lateral_stiffness_B": "lateral stiffness K_L at B"}

#: The ranking table's own rules: headers wrap (at spaces and after the dots of parameter keys),
#: a smaller font, cells as narrow as their numbers; the units sit in a second header row.
_RANK_CSS = """
table.rank{font-size:.74em}table.rank th{white-space:normal;vertical-align:bottom;padding:2px 3px;\
overflow-wrap:normal;hyphens:manual}table.rank td{padding:2px 3px;white-space:nowrap}\
table.rank tr.units th{background:#fafafa;font-weight:normal;color:#555;vertical-align:top}
"""

#: Columns of the ranked table: (column, header).
_TABLE_COLUMNS = (
    ("static_friction_force", "F_s"), ("static_friction_ratio", "F_s/(\u03bc F\u2080\u207a)"),
    ("presliding_displacement", "\u03b4_pre"), ("lateral_stiffness_A", "K_L A"), ("lateral_stiffness_B", "K_L B"),
    ("lateral_stiffness_C", "K_L C"), ("pull_off_force", "pull-off"), ("contact_area", "A_real"),
    ("max_pressure", "p_max"), ("repulsive_force", "F\u2080\u207a"), ("capillary_force", "F_cap"),
    ("peak_pressure", "p_peak"),
)


def pareto_front(x, y, sense_x: str = "max", sense_y: str = "max") -> np.ndarray:
    """The non-dominated points of a two-objective comparison.

    Parameters
    ----------
    x, y : array_like
        The two objectives per point (any units; NaN: the point takes no part).
    sense_x, sense_y : {"max", "min"}
        Whether larger or smaller values are better.

    Returns
    -------
    numpy.ndarray of bool
        True for every finite point that no other finite point dominates (at least as good
        in both objectives and better in one).
    """
    x = np.asarray(x, dtype=float) * (1.0 if sense_x == "max" else -1.0)
    y = np.asarray(y, dtype=float) * (1.0 if sense_y == "max" else -1.0)
    ok = np.isfinite(x) & np.isfinite(y)
    front = np.zeros(len(x), dtype=bool)
    for i in np.flatnonzero(ok):
        dom = ok & (x >= x[i]) & (y >= y[i]) & ((x > x[i]) | (y > y[i]))
        front[i] = not dom.any()
    return front


def _sense(targets, column: str, default: str) -> str:
    """"max" or "min": from a one-sided target on the column, else the default."""
    for t in targets:
        if t.value_column == column and t.column != "hardness":
            if t.min is not None and t.max is None:
                return "max"
            if t.max is not None and t.min is None:
                return "min"
    return default


def _label(row) -> str:
    return "#" + str(row["rank"])


def _pareto_figure(rows, targets, xcol, ycol, sx, sy):
    """(PNG bytes or None, note): the Pareto plot of two columns."""
    xs = np.array([abs(r[xcol]) if xcol == "pull_off_force" else r[xcol] for r in rows], dtype=float)
    ys = np.array([abs(r[ycol]) if ycol == "pull_off_force" else r[ycol] for r in rows], dtype=float)
    ok = np.array([r["status"] == "ok" for r in rows]) & np.isfinite(xs) & np.isfinite(ys)
    if not ok.any():
        return None, f"no point has both {xcol} and {ycol}"
    sx, sy = _sense(targets, xcol, sx), _sense(targets, ycol, sy)
    front = pareto_front(np.where(ok, xs, np.nan), np.where(ok, ys, np.nan), sx, sy)
    fx, lx = _column_unit(xs[ok], xcol)  # a stiffness in kN/m, not 70000 N/m
    fy, ly = _column_unit(ys[ok], ycol)
    fig = new_figure(5.6, 4.4)
    ax = fig.add_subplot(1, 1, 1)
    met_all = np.array([r["targets_met"] == r["n_targets"] and r["n_targets"] > 0 for r in rows])
    ax.scatter(xs[ok & ~front] / fx, ys[ok & ~front] / fy, c="#8a8a8a", s=30, label="dominated", zorder=2)
    order = np.argsort(xs[front])
    ax.plot(xs[front][order] / fx, ys[front][order] / fy, "-", color="#d62728", lw=1.2, zorder=3)
    ax.scatter(xs[front] / fx, ys[front] / fy, c="#d62728", s=55, label="Pareto front", zorder=4)
    if (ok & met_all).any():
        ax.scatter(xs[ok & met_all] / fx, ys[ok & met_all] / fy, facecolors="none", edgecolors="#1e7e34", s=140,
                   linewidths=1.6, label="all targets met", zorder=5)
    ranks = [ax.annotate(_label(rows[i]), (xs[i] / fx, ys[i] / fy), textcoords="offset points", xytext=(4, 4),
                         fontsize=10, color="#333", zorder=6,  # over a neighbour's marker: on a white ground
                         bbox={"boxstyle": "round,pad=0.1", "fc": "w", "ec": "none", "alpha": 0.75})
             for i in np.flatnonzero(ok)]
    for t in targets:  # the target bounds as lines
        for col, f, line in ((xcol, fx, ax.axvline), (ycol, fy, ax.axhline)):
            if t.value_column == col and t.column != "hardness":
                for b in (t.min, t.max):
                    if b is not None:
                        line(abs(b) / f if t.magnitude else b / f, color="#1e7e34", ls=":", lw=1)
    ax.set_xlabel(f"{_LABELS.get(xcol, xcol)} ({lx})")
    ax.set_ylabel(f"{_LABELS.get(ycol, ycol)} ({ly})")
    ax.set_title(f"better: {'larger' if sx == 'max' else 'smaller'} x, {'larger' if sy == 'max' else 'smaller'} y",
                 fontsize=10)
    ax.grid(alpha=0.3)
    ax.margins(x=0.08, y=0.12)  # room for the rank labels of the extreme points
    ax.legend(fontsize=10, loc="best")
    spread_labels(ax, ranks)  # points of a cluster (equal areas) keep readable rank labels
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=DPI)
    names = ", ".join(_label(rows[i]) for i in np.flatnonzero(front))
    return buf.getvalue(), f"Pareto front: {names}"


def _missing(v) -> bool:
    return v is None or (isinstance(v, float) and math.isnan(v))


def _column_unit(values, col) -> tuple[float, str]:
    """(factor, label) shared by a column of the ranking table: SI values / factor in label.

    A stiffness (N/m) takes the force's prefixes (kN/m, MN/m).
    """
    dim = _DIMS.get(col)
    v = [abs(float(x)) for x in values if not _missing(x)]
    if dim is None or dim == "dimensionless":
        return 1.0, ""
    if dim == "stiffness":
        f, lab = display_unit(v, "force")
        return f, lab + "/m"
    return display_unit(v, dim)


def _number(v, factor: float) -> str:
    """A table cell: ``v / factor`` to 4 significant digits (no unit: the header row has it)."""
    if _missing(v):
        return "n/a"
    x = float(f"{float(v) / factor:.4g}")
    # 4 digits, and no exponent below 1e7 (10000 nm², not 1e+04)
    return f"{x:.0f}" if 1e4 <= abs(x) < 1e7 else f"{x:.4g}"


def _wrap(name: str) -> str:
    """HTML-escaped ``name`` with break opportunities after its dots (a dotted parameter key)."""
    return "<wbr>".join(html.escape(part + ".") for part in name.split(".")[:-1]) + \
        ("<wbr>" if "." in name else "") + html.escape(name.split(".")[-1])


def _ranking_table(ranked: list[dict]) -> list[str]:
    """The ranking table: a column per varied parameter, the value columns with their units in a
    header row (the cells hold numbers only), columns no point has a value in left out, headers
    wrapping, so that it fits a 1280 px window without scrolling sideways."""
    e = html.escape
    params = []
    for r in ranked:
        for k in r["point"]:
            if k not in params:
                params.append(k)
    cols = [(c, h) for c, h in _TABLE_COLUMNS if any(not _missing(r.get(c)) for r in ranked)]
    units = {c: _column_unit([r.get(c) for r in ranked], c) for c, _ in cols}
    head = (["rank"] + [_wrap(k) for k in params] + ["targets met", "distance"] + [e(h) for _, h in cols]
            + ["&gt; hardness", "warn&shy;ings", "status"])
    left = {1 + i for i in range(len(params))} | {len(head) - 1}  # text columns: aligned left
    unit_row = [""] * (1 + len(params) + 2) + [e(units[c][1]) for c, _ in cols] + ["", "", ""]
    out = ["<div class='scroll'><table class='steps rank'><thead><tr>"
           + "".join(f"<th class='l'>{h}</th>" if i in left else f"<th>{h}</th>" for i, h in enumerate(head))
           + "</tr><tr class='units'>"
           + "".join(f"<th>{u}</th>" for u in unit_row) + "</tr></thead><tbody>"]
    for r in ranked:
        met = f"{r['targets_met']} / {r['n_targets']}"
        mcls = "met" if r["n_targets"] and r["targets_met"] == r["n_targets"] else ("unmet" if r["n_targets"] else "")
        eh = r["exceeds_hardness"]
        ehs = "n/a" if eh is None else ("<span class='unmet'>YES</span>" if eh else "no")
        pcells = "".join(f"<td class='l'>{e(str(r['point'].get(k, '')))}</td>" for k in params)
        out.append(f"<tr><td>{r['rank']}</td>{pcells}<td class='{mcls}'>{met}</td><td>{r['distance']:.3g}</td>"
                   + "".join(f"<td>{e(_number(r.get(c), units[c][0]))}</td>" for c, _ in cols)
                   + f"<td>{ehs}</td><td>{r['n_warnings']}</td><td class='l'>{e(r['status'])}</td></tr>")
    out.append("</tbody></table></div>")
    return out


def _point_text(point) -> str:
    return ", ".join(f"{k} = {v}" for k, v in point.items()) or "(base)"


def render_design_report(design, rows: list[dict], result=None) -> str:
    """The design report as HTML text.

    Parameters
    ----------
    design : DesignSpec
        The design (name, targets, chain, base scenario).
    rows : list of dict
        Ranked rows (:func:`tribobem.design.table.rank_rows`).
    result : SweepResult, optional
        What the sweep did this time (points computed, wall time in s).

    Returns
    -------
    str
        A self-contained HTML page.
    """
    e = html.escape
    ranked = sorted(rows, key=lambda r: r["rank"])
    n_ok = sum(r["status"] == "ok" for r in rows)
    n_failed = sum(r["status"] == "failed" for r in rows)
    n_missing = len(rows) - n_ok - n_failed
    out = ["<!DOCTYPE html><html><head><meta charset='utf-8'>",
           f"<title>tribobem design: {e(design.name)}</title><style>{_CSS}{_RANK_CSS}</style></head><body>",
           f"<h1>Design study: {e(design.name)}</h1>"]
    if design.description:
        out.append(f"<p>{e(design.description)}</p>")
    stamp = _dt.datetime.now().strftime("%Y-%m-%d %H:%M")
    ran = (f"; this run computed {result.n_run} point(s) in {result.wall_time:.1f} s "
           f"({result.n_done_before} reused from the cache)") if result is not None else ""
    out.append(f"<p class='muted'>{len(rows)} design points: {n_ok} ok, {n_failed} failed, {n_missing} missing"
               f"{e(ran)}. Written {stamp}.</p>")
    cls = "ok" if n_ok == len(rows) else "warn"
    msg = "every point computed" if n_ok == len(rows) else \
        f"{n_failed + n_missing} point(s) without a result: see Failed points; rerun the command to retry them"
    out.append(f"<p class='{cls}'>{e(msg)}</p>")

    # targets
    out.append("<h2>Targets</h2>")
    if design.targets:
        out.append("<ul>" + "".join(f"<li>{e(t.label())}</li>" for t in design.targets) + "</ul>")
        out.append("<p class='muted'>Score: the number of targets met; ties are broken by the distance (the sum "
                   "of the relative shortfalls of the missed targets), then by the smallest relative margin of "
                   "the targets (larger first). Failed and missing points rank last.</p>")
    else:
        out.append("<p class='muted'>No [targets]: the points are listed in sweep order (rank by index).</p>")

    # ranking table
    out.append("<h2>Ranking</h2>")
    out += _ranking_table(ranked)
    out.append("<p class='muted'>F_s: static friction force (gross-slip onset of the tangential ramp); "
               "F\u2080\u207a: repulsive force at zero tangential load; \u03b4_pre: pre-sliding displacement; "
               "K_L A/B/C: lateral stiffness at Paper F's points (F_x / (\u03bc F\u2080\u207a) = -0.5, 0, 0.5 on "
               "the last branch of the hysteresis loop); pull-off: from the clamp load (negative: tensile); "
               "A_real, p_max, F\u2080\u207a and F_cap: real contact area, max contact pressure, repulsive "
               "force and meniscus force (negative: tensile) at the clamp load and zero tangential load; a dry "
               "point (no humidity) reads them from the normal-contact stage (F_cap = 0), a humid point from the "
               "first state of its humid tangential ramp (F_t = 0, the menisci of the point's RH pulling, so "
               "F\u2080\u207a exceeds the clamp load by the tensile forces); p_peak: highest pressure over every "
               "state of the chain, the one the hardness check reads.</p>")
    if design.targets:
        out.append("<h3>Targets per point</h3><div class='scroll'><table class='steps'><tr><th>rank</th>" +
                   "".join(f"<th>{e(t.label())}</th>" for t in design.targets) + "</tr>")
        for r in ranked:
            cells = "".join(f"<td class='{'met' if ok else 'unmet'}'>{'met' if ok else 'missed'}</td>"
                            for ok in r["met"].values())
            out.append(f"<tr><td>{r['rank']}</td>{cells}</tr>")
        out.append("</table></div>")

    # Pareto plots
    out.append("<h2>Pareto plots</h2>")
    for xcol, ycol, sx, sy in PARETO_PLOTS:
        png, note = _pareto_figure(rows, design.targets, xcol, ycol, sx, sy)
        if png is None:
            out.append(f"<p class='note'>{e(_LABELS.get(ycol, ycol))} against {e(_LABELS.get(xcol, xcol))}: "
                       f"{e(note)}.</p>")
            continue
        data = base64.b64encode(png).decode("ascii")
        out.append(f"<figure class='mid'><img alt='pareto {e(xcol)} {e(ycol)}' src='data:image/png;base64,{data}'>"
                   f"<figcaption>{e(_LABELS.get(ycol, ycol))} against {e(_LABELS.get(xcol, xcol))}, one marker per "
                   f"computed point (labels: rank). Red: the non-dominated points ({e(note)}); green rings: every "
                   "target met; dotted green: the target bounds.</figcaption></figure>")

    # failures
    bad = [r for r in ranked if r["status"] != "ok"]
    out.append("<h2>Failed points</h2>")
    if not bad:
        out.append("<p class='muted'>None.</p>")
    else:
        out.append("<ul>")
        for r in bad:
            stages = "; ".join(f"{k}: {v.get('status')}" + (f" ({v.get('message')})" if v.get("message") else "")
                               for k, v in (r.get("stages") or {}).items())
            out.append(f"<li><b>{e(_point_text(r['point']))}</b> [{e(r['hash'])}] {e(r['status'])}: "
                       f"{e(r['message'] or 'not computed')}" + (f"<br><span class='muted'>{e(stages)}</span>"
                                                                 if stages else "") + "</li>")
        out.append("</ul>")

    # warnings
    out.append("<h2>Warnings of every point</h2>")
    any_w = False
    for r in ranked:
        if not r["warnings"]:
            continue
        any_w = True
        out.append(f"<div class='warnings'><b>#{r['rank']} {e(_point_text(r['point']))}</b><ul>" +
                   "".join(f"<li>{e(w)}</li>" for w in r["warnings"]) + "</ul></div>")
    if not any_w:
        out.append("<p class='muted'>None.</p>")

    # inputs
    out.append("<h2>Chain and base scenario</h2>")
    out.append("<p>Each point runs: normal contact at the clamp load (load.force); pull-off from it; a tangential "
               "ramp to gross slip (partial_slip); " +
               ("a hysteresis loop (lateral stiffness)." if design.chain.hysteresis else "no hysteresis loop.") +
               "</p>")
    inputs = {"chain": design.chain.as_dict(), "parameters": design.parameters, "points": design.points,
              "base": design.base}
    out.append(f"<pre>{e(json.dumps(inputs, indent=1, default=str))}</pre>")
    out.append("</body></html>")
    return "\n".join(out)


def write_design_report(outdir: str | os.PathLike, design, rows: list[dict], result=None,
                        name: str = "design_report.html") -> Path:
    """Write the design report (atomically).

    Parameters
    ----------
    outdir : path
        The design folder.
    design : DesignSpec
        The design.
    rows : list of dict
        Ranked rows.
    result : SweepResult, optional
        What the sweep did this time.
    name : str
        File name.

    Returns
    -------
    Path
        The report.
    """
    path = Path(outdir) / name
    atomic_write_text(path, render_design_report(design, rows, result))
    return path
