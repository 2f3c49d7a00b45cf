"""report.html: a self-contained page (figures embedded as base64 PNG) with the key scalars,
the step table, the inputs, the versions and the convergence status."""

from __future__ import annotations

import base64
import datetime as _dt
import html
import json
from pathlib import Path

from ..units import format_quantity
from .summary import atomic_write_text, jsonable

__all__ = ["render_report", "write_report"]

_CAPTIONS = {
    "force_curve": "Force-approach curve: loading and unloading branches, pull-off and jumps marked.",
    "pressure": "Pressure map (positive compressive; tensile adhesive stresses in blue when present).",
    "contact": "Contact map: contact (g = 0), cohesive zone (adhesive stress outside contact), free.",
    "profile": "Gap and pressure along the centre line.",
    "pressure_pulloff": "Pressure map at pull-off.",
    "contact_pulloff": "Contact map at pull-off.",
    "topography": "Initial gap and roughness of the bodies.",
}

# key -> (label, dimension) of the run-level scalars shown in the table
_RUN_SCALARS = (
    ("pull_off_force", "pull-off force", "force"),
    ("pull_off_approach", "approach at pull-off", "length"),
    ("hysteresis_energy", "energy lost over the load cycle", "energy"),
)
_PROBLEM_SCALARS = (
    ("effective_modulus", "effective modulus E*", "pressure"),
    ("radius", "sphere radius R", "length"),
    ("sigma0", "Dugdale stress \u03c3\u2080", "pressure"),
    ("h0", "Dugdale range h\u2080", "length"),
    ("tabor_parameter", "Tabor parameter \u03bc_T", "dimensionless"),
    ("maugis_parameter", "Maugis parameter \u03bb", "dimensionless"),
)
_STEP_COLUMNS = (
    ("branch", "branch", None),
    ("normal_force", "F", "force"),
    ("approach", "\u03b4", "length"),
    ("contact_area", "A contact", "area"),
    ("adhesive_area", "A adhesive", "area"),
    ("repulsive_force", "F\u207a", "force"),
    ("adhesive_force", "F\u207b", "force"),
    ("max_pressure", "p max", "pressure"),
    ("mean_gap", "mean gap", "length"),
    ("iterations", "iter.", None),
    ("residual", "residual", None),
    ("converged", "conv.", None),
)

_CSS = """
body{font-family:system-ui,-apple-system,Segoe UI,Helvetica,Arial,sans-serif;margin:2em auto;max-width:1100px;
color:#222;padding:0 1em}
h1{font-size:1.6em;margin-bottom:.2em}h2{font-size:1.2em;border-bottom:1px solid #ddd;padding-bottom:.2em;margin-top:1.6em}
table{border-collapse:collapse;font-size:.88em}td,th{border:1px solid #ddd;padding:3px 8px;text-align:right}
th{background:#f4f4f4}td.l,th.l{text-align:left}
.ok{background:#e6f4ea;border:1px solid #34a853;padding:.6em 1em;border-radius:4px}
.warn{background:#fdecea;border:2px solid #d93025;padding:.6em 1em;border-radius:4px;font-weight:600}
.note{background:#fff8e1;border:1px solid #f9a825;padding:.4em 1em;border-radius:4px;margin:.4em 0}
figure{display:inline-block;margin:.5em;vertical-align:top;max-width:520px}figure img{max-width:100%}
figcaption{font-size:.85em;color:#555}pre{background:#f7f7f7;padding:1em;overflow:auto;font-size:.8em;max-height:30em}
.muted{color:#777;font-size:.85em}
"""


def _fmt(value, dim) -> str:
    if value is None:
        return "n/a"
    if isinstance(value, bool):
        return "yes" if value else "NO"
    if dim is None:
        if isinstance(value, float):
            return f"{value:.3g}"
        return str(value)
    if dim == "dimensionless":
        return f"{float(value):.4g}"
    return format_quantity(value, dim, 4)


def _img(path: Path) -> str:
    data = base64.b64encode(Path(path).read_bytes()).decode("ascii")
    return f"data:image/png;base64,{data}"


def render_report(summary: dict, figures: dict | None = None) -> str:
    """The HTML text of the report.

    Parameters
    ----------
    summary : dict
        The run summary (as written to summary.json).
    figures : dict, optional
        Figure name -> PNG path; embedded in that order.
    """
    s = jsonable(summary)
    e = html.escape
    title = s.get("inputs", {}).get("name") or f"tribobem {s.get('kind', '')} run"
    parts = [f"<!DOCTYPE html><html lang='en'><head><meta charset='utf-8'><title>{e(title)}</title>"
             f"<style>{_CSS}</style></head><body>"]
    parts.append(f"<h1>{e(title)}</h1>")
    desc = s.get("inputs", {}).get("description")
    if desc:
        parts.append(f"<p>{e(desc)}</p>")
    created = s.get("created") or _dt.datetime.now().isoformat(timespec="seconds")
    parts.append(f"<p class='muted'>kind: <b>{e(str(s.get('kind')))}</b> &middot; {e(created)} &middot; "
                 f"tribobem {e(str(s.get('versions', {}).get('tribobem', '')))}</p>")

    steps = s.get("steps", [])
    n_bad = sum(1 for st in steps if not st.get("converged", True))
    if s.get("converged"):
        parts.append(f"<p class='ok'>Converged: all {len(steps)} step(s) reached the solver tolerance.</p>")
    else:
        parts.append(f"<p class='warn'>WARNING: not converged. {n_bad} of {len(steps)} step(s) did not reach the "
                     "solver tolerance; their results are unreliable. Raise solver.max_iterations, loosen "
                     "solver.tolerance, or refine the load steps.</p>")
    for w in s.get("warnings", []) or []:
        parts.append(f"<p class='note'>{e(str(w))}</p>")

    # key scalars
    rows = []
    for key, label, dim in _RUN_SCALARS:
        if s.get(key) is not None:
            rows.append((label, _fmt(s[key], dim)))
    prob = s.get("problem", {}) or {}
    for key, label, dim in _PROBLEM_SCALARS:
        if prob.get(key) is not None:
            rows.append((label, _fmt(prob[key], dim)))
    g = prob.get("grid")
    if g:
        rows.append(("grid", f"{g['nx']} x {g['ny']} cells, {format_quantity(g['lx'], 'length')} x "
                             f"{format_quantity(g['ly'], 'length')}, {'periodic' if g.get('periodic') else 'free boundary'}"))
    if steps:
        last = max(steps, key=lambda st: st.get("normal_force") or float("-inf"))
        rows.append(("max normal force", _fmt(last.get("normal_force"), "force")))
        rows.append(("contact area at max force", _fmt(last.get("contact_area"), "area")))
        rows.append(("max pressure", _fmt(max((st.get("max_pressure") or 0) for st in steps), "pressure")))
    for body, st in (prob.get("roughness") or {}).items():
        if "rms_height" in st:
            rows.append((f"{body} roughness", f"rms {format_quantity(st['rms_height'], 'length')}, rms slope "
                                              f"{st.get('rms_slope', float('nan')):.3g}"))
    t = s.get("timings", {})
    if t:
        rows.append(("time", ", ".join(f"{k} {v:.2f} s" for k, v in t.items() if isinstance(v, (int, float)))))
    parts.append("<h2>Key results</h2><table>")
    parts += [f"<tr><th class='l'>{e(a)}</th><td class='l'>{e(b)}</td></tr>" for a, b in rows]
    parts.append("</table>")

    if figures:
        parts.append("<h2>Figures</h2>")
        for name, path in figures.items():
            if path is None or not Path(path).exists():
                continue
            parts.append(f"<figure><img alt='{e(name)}' src='{_img(path)}'><figcaption>"
                         f"{e(_CAPTIONS.get(name, name))}</figcaption></figure>")

    if steps:
        parts.append(f"<h2>Steps ({len(steps)})</h2><table><tr><th>#</th>"
                     + "".join(f"<th>{e(c[1])}</th>" for c in _STEP_COLUMNS) + "</tr>")
        show = steps if len(steps) <= 200 else steps[:100] + steps[-100:]
        for i, st in enumerate(show):
            idx = i if len(steps) <= 200 or i < 100 else len(steps) - 200 + i
            cells = "".join(f"<td>{e(_fmt(st.get(k), d))}</td>" for k, _, d in _STEP_COLUMNS)
            parts.append(f"<tr><td>{idx}</td>{cells}</tr>")
        parts.append("</table>")
    if s.get("jumps"):
        parts.append("<h2>Jumps</h2><ul>")
        for j in s["jumps"]:
            parts.append(f"<li>{e(str(j.get('kind')))} on the {e(str(j.get('branch')))} branch at "
                         f"\u03b4 = {e(_fmt(j.get('approach'), 'length'))}, F = {e(_fmt(j.get('force'), 'force'))}</li>")
        parts.append("</ul>")

    parts.append("<h2>Inputs (SI units)</h2><pre>" + e(json.dumps(s.get("inputs", {}), indent=2)) + "</pre>")
    notes = prob.get("notes") or []
    files = prob.get("files") or {}
    if files or notes:
        parts.append("<h2>Topography files</h2><pre>" + e(json.dumps({"files": files, "notes": notes}, indent=2)) + "</pre>")
    parts.append("<h2>Versions</h2><table>")
    parts += [f"<tr><th class='l'>{e(k)}</th><td class='l'>{e(str(v))}</td></tr>" for k, v in s.get("versions", {}).items()]
    parts.append("</table></body></html>\n")
    return "".join(parts)


def write_report(outdir, summary: dict, figures: dict | None = None, name: str = "report.html") -> Path:
    """Render the report and write it atomically to ``outdir/name``."""
    path = Path(outdir) / name
    return atomic_write_text(path, render_report(summary, figures))
