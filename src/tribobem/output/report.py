"""report.html: a self-contained page (figures embedded as base64 PNG) with the key scalars,
the step table, the inputs, the versions and the convergence status; for hysteresis runs a
"Friction hysteresis" section (loop, energy per cycle, lateral stiffness at Paper F's points,
dissipation and stick/slip maps); for humid friction runs a "Humid friction" section (one row per
RH after the dry reference, the figures against RH and per RH)."""

from __future__ import annotations

import base64
import datetime as _dt
import html
import json
import math
from pathlib import Path

from ..interactions.registry import report_rows as law_report_rows
from ..units import ZERO_FRACTION, format_quantity, format_value
from .atomic import staged_source
from ..analytic.friction_loops import kl_reference, kl_reference_values, loop_reference
from .atomic import atomic_write_text
from .humid import per_rh, rh_groups, rh_label, rh_summary, zero_load_row
from .run_kind import run_view
from .summary import jsonable

__all__ = ["render_report", "write_report"]

_CAPTIONS = {
    "force_curve": "Force-approach curve: loading and unloading branches, pull-off and jumps marked.",
    "pressure": "Pressure map (positive compressive; tensile adhesive stresses in blue when present).",
    "contact": "Contact map: contact (g = 0), cohesive zone (adhesive stress outside contact), free.",
    "profile": ("Gap and pressure along the line y = const through the largest pressure (the title gives its y; "
                "the centre line when there is no pressure)."),
    "pressure_pulloff": "Pressure map at pull-off.",
    "contact_pulloff": "Contact map at pull-off.",
    "plastic": ("Permanent (plastic) surface displacement after the most loaded state (a hardness cap): the "
                "flattening the later states see; outlined, the nodes at p = H in that state."),
    "subsurface": ("Von Mises stress below the surface of each elastic body: the section through its largest value, "
                   "and the plane maxima against depth (homogeneous half-spaces; residual stresses of plastic states "
                   "not included)."),
    "topography": "Initial gap and roughness of the bodies.",
    "stick_ratio": ("Stick ratio A_stick / A_c (compressive contact) and tangential displacement \u03b4\u2093 of "
                    "body 2 against F\u2093 / (\u03bc F\u2080\u207a), F\u2080\u207a the repulsive force of each "
                    "step; gross-slip onset (dashed) and presliding displacement (dotted) marked."),
    "stick_normal": ("Stick ratio (and stick-radius ratio c/a when computed) along the normal-load path: "
                     "slip from the normal load alone (frictional Poisson coupling)."),
    "hysteresis_loop": ("Friction hysteresis loop: tangential force F\u2093 against the displacement \u03b4\u2093 of "
                        "body 2, one colour per cycle (cycle 0, the initial loading, dashed). Paper E's points: A "
                        "(start, F\u2093 = 0), A' (the step after it), the turning points D, H, L ... (filled) and the "
                        "steps right after them D', H' ... (open). Grey band: the analytic loop of the geometry (a "
                        "sphere: Mindlin-Deresiewicz; a burl: the rounded punch of Ciavarella-Jaeger), drawn for "
                        "smooth bodies without normal-tangential coupling. Below: stick ratio A_stick / A_c "
                        "along the path."),
    "lateral_stiffness": ("Lateral stiffness K_L at Paper F's points A, B, C (F\u2093 / (\u03bc F\u2080\u207a) = "
                          "-0.5, 0, 0.5 on the last branch from -F* to +F*; not Paper E's point A): fit of the "
                          "simulated branch (Paper F Eq. 3; thin line: the fitted K_L along the branch), the exact "
                          "slope of the geometry's analytic branch from the same turning point and its virgin-curve "
                          "slope (a sphere: Mindlin-Deresiewicz and Paper F Eq. 6; a burl: the rounded punch of "
                          "Ciavarella-Jaeger; none for other geometries)."),
    "capillary_forces": ("Adhesive force components against RH (Paper B Fig. 13): capillary F_cap = dP_cap x the "
                         "meniscus area outside contact, solid-solid F_ss (Dugdale zone), water-solid F_ws (van der "
                         "Waals across water and across the air gap between the films) and their sum; crosses: RH "
                         "steps that did not converge. Right: meniscus and contact areas (% of the nominal area) and "
                         "the number of active meniscus islands."),
    "pulloff_rh": ("Humid pull-off against RH (the most tensile force of a quasi-static unloading with the menisci "
                   "recomputed at every step) and the capillary force at pull-off; right: the unloading curves."),
    "meniscus": ("Meniscus islands at chosen RH (Paper B Fig. 12): contact, Dugdale zone, meniscus (islands of "
                 "g < S = 2|r_k| + e1 + e2 that hold a seed: contact, wetted or a film-to-film gap below d_cr; they "
                 "carry dP_cap), dry cross-cuts (below S without a seed: no pressure) and free nodes."),
    "films": ("Adsorbed water film thickness of each body that carries one, levelled on its undeformed topography "
              "before contact, at the RH of the meniscus maps."),
    "humid_friction_rh": ("Humid friction against RH (one ramp or loop per RH, in the order given, each "
                          "warm-started from the previous RH's zero-load state). Partial slip: static friction "
                          "force (gross-slip onset; grey squares: \u03bc F\u2080\u207a at the onset, the most the "
                          "contact carries) and presliding displacement. Hysteresis: lateral stiffness K_L at Paper "
                          "F's points A, B, C, dissipated energy (loop area) of the last cycle, and the static "
                          "friction and sliding forces when reached. Dashed: the dry reference run (Dugdale "
                          "adhesion alone if the scenario has it, no meniscus). Last panel: the capillary force of "
                          "the state at F\u2093 = 0 (< 0: tensile)."),
    "humid_friction_curve": ("Tangential force F\u2093 against the displacement \u03b4\u2093 of body 2, one curve per "
                             "RH (colour: RH). Partial slip: stars mark the gross-slip onset; below, the stick "
                             "ratio against F\u2093 / (\u03bc F\u2080\u207a) (dotted: each RH's onset). "
                             "Hysteresis: the loops, cycle 0 (the initial loading) dashed; below, the stick ratio "
                             "along each loop. The dry reference keeps no steps; its static friction force, when "
                             "reached, is the grey dashed line."),
    "stickslip_rh": ("Stick/slip maps, one per RH (at most four): the kept state of each ramp half-way to its last "
                     "state that still sticks. Compressive contact that sticks (blue) or slips (red), "
                     "tensile zone p < 0 where no shear acts (pale amber: here the meniscus under the Laplace "
                     "pressure), no contact (grey); teal line: the meniscus edge (outer edge of the wetted region); "
                     "arrows: tangential traction q on body 1, on a common scale across the maps."),
    "stickslip_loop": ("Stick/slip maps at Paper E's points (A: start; D, H, L ...: turning points; D', H' ...: "
                       "the step right after them): compressive contact that sticks (blue) or slips (red), no "
                       "contact (grey); arrows: tangential traction q on body 1, on a common scale."),
}
_STICKSLIP_CAPTION = ("Stick/slip map of step {k}: compressive contact that sticks (blue) or slips (red), "
                      "tensile zone p < 0 where no shear acts (pale amber), no contact (grey); arrows: "
                      "tangential traction q on body 1, on a common scale across the maps.")

# key -> (label, dimension) of the run-level scalars shown in the table
_RUN_SCALARS = (
    ("pull_off_force", "pull-off force", "force"),
    ("pull_off_approach", "approach at pull-off", "length"),
    ("hysteresis_energy", "energy lost over the load cycle", "energy"),
    ("peak_capillary_force", "peak capillary force F_cap (most tensile)", "force"),
    ("peak_capillary_rh", "RH at the peak capillary force", "dimensionless"),
)
# (the stress laws' own rows follow them: each law's ``report_rows``, interactions/registry.py)
_PROBLEM_SCALARS = (
    ("effective_modulus", "effective modulus E*", "pressure"),
    ("radius", "sphere radius R", "length"),
    ("hardness", "hardness H (pressure cap of the softer surface)", "pressure"),
)
# run-level scalars of the tangential kinds (partial_slip, hysteresis)
_FRICTION_SCALARS = (
    ("friction_coefficient", "friction coefficient \u03bc", "dimensionless"),
    ("static_friction_force", "static friction force (gross-slip onset)", "force"),
    ("static_friction_ratio", "static friction ratio F\u2093 / (\u03bc F\u2080\u207a) at onset", "dimensionless"),
    ("presliding_displacement", "presliding displacement", "length"),
    ("sliding_force", "sliding force (gross-sliding plateau)", "force"),
    ("gross_slip", "gross slip reached", "yesno"),
)
# (key, header, dimension, optional): optional columns appear only when a step has the key
_STEP_COLUMNS = (
    ("branch", "branch", None, True),
    ("cycle", "cycle", None, True),
    ("normal_force", "F", "force", False),
    ("approach", "\u03b4", "length", False),
    ("rh", "RH", "dimensionless", True),
    ("pull_off_force", "F pull-off", "force", True),
    ("capillary_force", "F_cap", "force", True),
    ("solid_solid_force", "F_ss", "force", True),
    ("water_solid_force", "F_ws", "force", True),
    ("wetted_area", "A meniscus", "area", True),
    ("island_count", "islands", None, True),
    ("kelvin_radius", "r_k", "length", True),
    ("film_thickness_1", "e1 (mean)", "length", True),
    ("film_thickness_2", "e2 (mean)", "length", True),
    ("outer_iterations", "outer it.", None, True),
    ("tangential_force_x", "F\u2093", "force", True),
    ("displacement_x", "\u03b4\u2093", "length", True),
    ("stick_ratio", "stick ratio", "dimensionless", True),
    ("stick_radius_ratio", "c / a", "dimensionless", True),
    ("contact_area", "A contact", "area", False),
    ("adhesive_area", "A adhesive", "area", False),
    ("repulsive_force", "F\u207a", "force", False),
    ("adhesive_force", "F\u207b", "force", False),
    ("max_pressure", "p max", "pressure", False),
    ("plastic_area", "A plastic (p = H)", "area", True),
    ("max_plastic_displacement", "plastic depth max", "length", True),
    ("mean_gap", "mean gap", "length", False),
    ("iterations", "iter.", None, False),
    ("coupling_iterations", "coupl. iter.", None, True),
    ("tangential_iterations", "tang. iter.", None, True),
    ("residual", "residual", None, False),
    ("converged", "conv.", None, False),
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
.warnings{background:#fff4dc;border:2px solid #f0a30a;border-left:10px solid #f0a30a;padding:.5em 1em;
border-radius:4px;margin:.8em 0}.warnings b{color:#8a5300}.warnings ul{margin:.3em 0 .1em 1.2em;padding:0}
figure{display:inline-block;margin:.5em;vertical-align:top;max-width:520px}figure img{max-width:100%}
figure.wide{display:block;max-width:100%}figure.mid{max-width:700px}h3{font-size:1.02em;margin:1.2em 0 .4em}
figcaption{font-size:.85em;color:#555}pre{background:#f7f7f7;padding:1em;overflow:auto;font-size:.8em;max-height:30em}
.muted{color:#777;font-size:.85em}.scroll{overflow-x:auto;max-width:100%}.steps{font-size:.8em}\
.steps td{white-space:nowrap;padding:2px 5px}.steps th{padding:2px 5px}
table{max-width:100%}td.l{overflow-wrap:anywhere}tr.dry td{background:#f3f3f3;font-style:italic}
table.humid td{white-space:nowrap}.met{color:#1e7e34;font-weight:600}.unmet{color:#d93025;font-weight:600}
tr.marked td{background:#fff8e1}td.stepnote{font-style:italic}
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
    if dim == "yesno":
        return "yes" if value else "no"
    if dim == "dimensionless":
        return f"{float(value):.4g}"
    return format_value(value, dim, 4)  # rounded before the unit is chosen: 1 µN, not 1e+03 nN


def _force_scale(steps) -> float:
    """The run's force scale (N): the largest |F|, F+ or |F-| of its steps."""
    return max((abs(float(st[k])) for st in steps for k in ("normal_force", "repulsive_force", "adhesive_force")
                if isinstance(st.get(k), (int, float)) and not isinstance(st.get(k), bool)
                and math.isfinite(float(st[k]))), default=0.0)


def _step_notes(steps) -> dict:
    """Step position -> what is special about it: the state a jump of the force-approach curve
    lands on ("jump-in", "jump-off"), or a second state at the approach of the step before it
    (another equilibrium of the same approach, reached from another start: the end of the
    loading and the start of the unloading, or a refinement's re-solve)."""
    notes = {}
    for i in range(1, len(steps)):
        a, b = steps[i - 1].get("approach"), steps[i].get("approach")
        fa, fb = steps[i - 1].get("normal_force"), steps[i].get("normal_force")
        if all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in (a, b, fa, fb)) \
                and abs(a - b) <= 1e-9 * max(abs(a), abs(b), 1e-30) and fa != fb:
            notes[i] = f"same \u03b4 as {i - 1}"
    return notes


def _caption(name: str) -> str:
    if name.startswith("dissipation_cycle"):
        return (f"Cycle {name[len('dissipation_cycle'):]}: frictional dissipation per area (sum over the cycle's "
                "steps of -q \u00b7 \u0394s, J/m\u00b2) and accumulated slip (sum of |\u0394s|), on the nodes "
                "that carried compressive contact.")
    if name.startswith("stickslip_step"):
        return _STICKSLIP_CAPTION.format(k=name[len("stickslip_step"):])
    if name.startswith("stickslip_field"):
        return _STICKSLIP_CAPTION.format(k=f"{name[len('stickslip_field'):]} of fields.nc")
    if name.startswith("stickslip_") and name not in _CAPTIONS:
        # a state that is not a summary.json step (the refined gross-slip onset): by its label
        return _STICKSLIP_CAPTION.replace("step {k}", "the {k} state").format(k=name[len("stickslip_"):])
    return _CAPTIONS.get(name, name)


def _img(path: Path) -> str:
    data = base64.b64encode(staged_source(path).read_bytes()).decode("ascii")  # written in this batch
    return f"data:image/png;base64,{data}"


def _figure_html(name: str, path, cls: str = "", caption: str | None = None) -> str:
    e = html.escape
    c = f" class='{cls}'" if cls else ""
    text = _caption(name) if caption is None else caption
    return f"<figure{c}><img alt='{e(name)}' src='{_img(path)}'><figcaption>{e(text)}</figcaption></figure>"


def _width_class(path) -> str:
    """The figure class that shows a PNG at 0.7 of its pixels or more: "" (520 px wide) for a
    one-panel figure, "mid" (700 px) or "wide" (the page) for a wider one (a topography with the
    roughness maps beside the gap), whose labels would otherwise shrink below readable."""
    with open(staged_source(path), "rb") as f:
        head = f.read(24)  # PNG signature and IHDR: width at bytes 16-20
    width = int.from_bytes(head[16:20], "big") if head[12:16] == b"IHDR" else 0
    if width * 0.7 <= 520:
        return ""
    return "mid" if width * 0.7 <= 700 else "wide"


def _is_hysteresis_figure(name: str) -> bool:
    return name in ("hysteresis_loop", "lateral_stiffness", "stickslip_loop") or name.startswith("dissipation_cycle")


def _stiffness(value) -> str:
    """A stiffness (N/m) in N/\u00b5m, N/mm or N/m."""
    try:
        v = float(value)
    except (TypeError, ValueError):
        return "n/a"
    if not math.isfinite(v):
        return "n/a"
    for label, f in (("N/\u00b5m", 1e6), ("N/mm", 1e3), ("N/m", 1.0)):
        if abs(v) >= f:
            return f"{v / f:.4g} {label}"
    return f"{v:.4g} N/m"


def _num(v):
    try:
        f = float(v)
    except (TypeError, ValueError):
        return None
    return f if math.isfinite(f) else None


def _friction_rows(s: dict) -> list:
    """(label, formatted value) of the run-level friction values the summary holds."""
    # a humid run's per-RH lists are tabulated by the humid_friction section, not here
    return [(label, _fmt(s[key], dim)) for key, label, dim in _FRICTION_SCALARS
            if s.get(key) is not None and not isinstance(s[key], (list, tuple, dict))]


def _hysteresis_section(s: dict, figures: dict) -> list:
    """The "Friction hysteresis" section: the run's friction scalars, the loop figure, the
    energy per cycle, the lateral stiffness at Paper F's points, and the maps.  ``s`` may be one
    RH of a humid run (:func:`~tribobem.output.humid.rh_summary`, a scalar ``rh``): the heading
    and the map caption say so."""
    e = html.escape
    rh = _num(s.get("rh"))
    if rh is None:
        parts = ["<h2>Friction hysteresis</h2>"]
    else:
        parts = [f"<h2>Friction hysteresis at {e(rh_label(rh))}</h2><p class='muted'>The loop of the last RH, "
                 "whose per-cycle dissipation maps fields.nc keeps; every RH against the dry reference: "
                 "section Humid friction.</p>"]
    mu = _num(s.get("friction_coefficient"))
    f0p = _num(s.get("repulsive_force"))
    mup = mu * f0p if mu and f0p else None
    rows = []
    if s.get("control"):
        rows.append(("control", f"{s['control']} (Papers E, F: cycles 0 \u2192 +F* \u2192 -F* \u2192 +F* ...)"
                     if s["control"] == "force" else f"{s['control']} (stroke cycles, gross sliding allowed)"))
    if f0p is not None:
        rows.append(("repulsive force F\u2080\u207a (at F\u2093 = 0)", _fmt(f0p, "force")))
    peak = _num(s.get("peak_force"))
    if peak is not None:
        extra = f" = {peak / mup:.4g} \u03bc F\u2080\u207a" if mup else ""
        rows.append(("peak force F*", _fmt(peak, "force") + extra))
    rows += _friction_rows(s)
    if s.get("static_friction_force") is None:
        rows.append(("static friction force", "not reached (the stick zone never vanished on the initial loading)"))
    lc = _num(s.get("loop_change"))
    if lc is not None:
        rows.append(("loop change between the last two cycles, max |\u0394F\u2093| / (\u03bc F\u2080\u207a)",
                     f"{lc:.3g}"))
    failed = s.get("failed_steps") or []
    rows.append(("steps that did not converge", ", ".join(str(i) for i in failed) if failed else "none"))
    parts.append("<table>")
    parts += [f"<tr><th class='l'>{e(a)}</th><td class='l'>{e(b)}</td></tr>" for a, b in rows]
    parts.append("</table>")
    if "hysteresis_loop" in figures:
        parts.append(_figure_html("hysteresis_loop", figures["hysteresis_loop"], "mid"))

    # energy per cycle
    area = list(s.get("dissipated_energy") or [])
    work = list(s.get("dissipation_work") or [])
    if area or work:
        ref = loop_reference(s)  # the geometry's analytic loop (a sphere: Mindlin-Deresiewicz), or None
        parts.append("<h3>Dissipated energy per cycle</h3><table><tr><th>cycle</th>"
                     "<th>loop area \u222e F\u2093 d\u03b4\u2093</th><th>traction work \u2211 -q \u00b7 \u0394s</th>"
                     "<th>work / area</th>" + (f"<th>{e(ref['name'])} W</th><th>area / W</th>" if ref else "")
                     + "</tr>")
        for k in range(max(len(area), len(work))):
            a = _num(area[k]) if k < len(area) else None
            w = _num(work[k]) if k < len(work) else None
            ratio = f"{w / a:.4f}" if a and w is not None else "n/a"
            cells = [str(k + 1), _fmt(a, "energy"), _fmt(w, "energy"), ratio]
            if ref:
                cells += [_fmt(ref["energy"], "energy"), f"{a / ref['energy']:.4f}" if a is not None else "n/a"]
            parts.append("<tr>" + "".join(f"<td>{e(c)}</td>" for c in cells) + "</tr>")
        parts.append("</table>")
        if ref and "model" in ref:
            parts.append(f"<p class='muted'>{e(ref['name'])}: W = 4 F* \u03b4(F*) - 8 \u222b\u2080^F* \u03b4 dF "
                         "between the Masing branches of the virgin curve \u03b4(F) = (\u03bc E* k / 4) [d(P) - "
                         "d(P - F/\u03bc)], d the approach of the frictionless normal solution, P = F\u2080\u207a, "
                         "k = \u2211 (2 - \u03bd)/G.</p>")
        elif ref:
            parts.append("<p class='muted'>Mindlin-Deresiewicz: W = (9 \u03bc\u00b2 P\u00b2 k / (10 a)) "
                         "[1 - (1 - r)^(5/3) - (5 r / 6)(1 + (1 - r)^(2/3))], r = F* / (\u03bc P), P = F\u2080\u207a, "
                         "a from the "
                         f"compressive contact area at the start ({e(_fmt(ref['radius'], 'length'))}), k = \u2211 "
                         "(2 - \u03bd)/G.</p>")

    # lateral stiffness (Paper F)
    table = [t for t in (s.get("lateral_stiffness") or []) if isinstance(t, dict)]
    if table:
        # the analytic reference of the run's geometry (Mindlin-Deresiewicz for a sphere, the rounded
        # punch of Ciavarella-Jaeger for a burl), or none: a sphere's law applied to a punch misleads
        ref_name, ref_note = kl_reference(s)
        virgin = "K_L virgin (Paper F Eq. 6)" if ref_name == "Mindlin-Deresiewicz" else f"K_L virgin, {ref_name}"
        parts.append("<h3>Lateral stiffness (Paper F)</h3><table><tr><th>point</th>"
                     "<th>F\u2093 / (\u03bc F\u2080\u207a)</th><th>F\u2093</th><th>\u03b4\u2093</th>"
                     "<th>K_L fit (Eq. 3)</th>"
                     + (f"<th>K_L {e(ref_name)}</th><th>{e(virgin)}</th><th>fit / {e(ref_name)}</th>" if ref_name else "")
                     + "</tr>")
        for t in table:
            k = _num(t.get("stiffness"))
            md, vir = kl_reference_values(t)
            md, vir = (md if math.isfinite(md) else None), (vir if math.isfinite(vir) else None)
            ratio = f"{k / md:.4f}" if k is not None and md else "n/a"
            fr = _num(t.get("force_ratio"))
            cells = [str(t.get("point", "")), f"{fr:+.2f}" if fr is not None else "n/a",
                     _fmt(t.get("tangential_force"), "force"), _fmt(t.get("displacement"), "length"), _stiffness(k)]
            if ref_name:
                cells += [_stiffness(md), _stiffness(vir), ratio]
            parts.append("<tr>" + "".join(f"<td>{e(c)}</td>" for c in cells) + "</tr>")
        parts.append("</table>")
        if not ref_name:
            parts.append(f"<p class='note'>K_L: {e(ref_note)}.</p>")
        fit = s.get("lateral_stiffness_fit") or {}
        if all(_num(fit.get(x)) is not None for x in ("c1", "c2", "n")):
            parts.append(f"<p class='muted'>Fit F\u2093 - F_turn = c\u2081 (1 - (1 - c\u2082 \u03b4)^n) on the last "
                         f"branch from -F* (\u03b4 from its turning point): c\u2081 = {e(_fmt(fit['c1'], 'force'))}, "
                         f"c\u2082 = {float(fit['c2']):.4g} 1/m, n = {float(fit['n']):.4g} (Mindlin: n = 1.5). "
                         "Points A, B, C are Paper F's, not Paper E's.</p>")
    elif s.get("lateral_stiffness_error"):
        parts.append(f"<p class='note'>Lateral stiffness not computed: {e(str(s['lateral_stiffness_error']))}</p>")
    if "lateral_stiffness" in figures:
        parts.append(_figure_html("lateral_stiffness", figures["lateral_stiffness"]))
    for name, path in figures.items():
        if name.startswith("dissipation_cycle"):
            parts.append(_figure_html(name, path, "wide"))
    if "stickslip_loop" in figures:
        parts.append("<h3>Stick and slip at Paper E's points</h3>")
        cap = None
        if rh is not None:
            cap = (_caption("stickslip_loop") + " Pale amber: the tensile zone, here the meniscus under the Laplace "
                   "pressure; teal line: the meniscus edge (outer edge of the wetted region).")
        parts.append(_figure_html("stickslip_loop", figures["stickslip_loop"], "wide", cap))
    return parts


_CAPILLARY_FIGURES = ("capillary_forces", "pulloff_rh", "meniscus", "films")


def _humidity_rows(hum: dict) -> list:
    """(label, text) of the humidity inputs (``problem.humidity`` of summary.json): water, films,
    Hamaker constants and meniscus settings."""
    return [
        ("water", f"T = {hum.get('temperature', float('nan')):.4g} K, γ = "
                  f"{format_quantity(hum.get('surface_tension'), 'surface_tension', 4)}, V = "
                  f"{hum.get('molar_volume', float('nan')) * 1e6:.4g} cm³/mol"),
        ("films (isotherms)", f"body 1: {hum.get('isotherm1')}, body 2: {hum.get('isotherm2')}; levelling "
                              f"{hum.get('levelling')} ({hum.get('film_system')} system"
                              f"{', with the disjoining pressure' if hum.get('disjoining') else ''}), "
                              "on the undeformed topographies"),
        ("Hamaker constants", f"body 1 {hum.get('hamaker1', float('nan')):.3g} J, "
                              f"body 2 {hum.get('hamaker2', float('nan')):.3g} J, "
                              f"water {hum.get('water_hamaker', float('nan')):.3g} J; van der Waals "
                              f"{'on' if hum.get('van_der_waals') else 'off'}, cut-off "
                              f"{format_quantity(hum.get('cutoff'), 'length', 3)}"),
        ("meniscus", f"contact angles {', '.join(f'{a:g}' for a in hum.get('contact_angles_deg') or [])} deg, "
                     f"critical distance d_cr = {format_quantity(hum.get('critical_distance'), 'length', 3)}, "
                     f"contribution coefficient: {hum.get('contribution')}"),
    ]


def _capillary_section(s: dict, hum: dict, figures: dict) -> list:
    """The "Capillary adhesion" section: water, films and meniscus settings, the humid pull-off per
    RH, and the capillary figures (force components, pull-off, meniscus and film maps)."""
    e = html.escape
    parts = ["<h2>Capillary adhesion</h2>"]
    rows = _humidity_rows(hum)
    if isinstance(s.get("pull_off_force"), list):
        steps = s.get("steps") or []
        # the run's lists in RH order where it has them (a two-scale pull-off), else one step per RH
        pairs = (list(zip(s["rh"], s["pull_off_force"])) if isinstance(s.get("rh"), list)
                 else [(st.get("rh"), st.get("pull_off_force")) for st in steps if st.get("rh") is not None])
        rows.append(("pull-off force per RH", "; ".join(
            f"RH {100 * float(rh):.3g} %: {_fmt(f, 'force')}" for rh, f in pairs)))
        rows.append(("unloading starts from", f"{_fmt(s.get('preload'), 'force')} ({s.get('preload_source', '')})"))
    parts.append("<table>")
    parts += [f"<tr><th class='l'>{e(a)}</th><td class='l'>{e(b)}</td></tr>" for a, b in rows]
    parts.append("</table>")
    for name in _CAPILLARY_FIGURES:
        if name in figures:
            # every capillary figure at the page's width: the two-panel ones keep readable legends
            parts.append(_figure_html(name, figures[name], "wide"))
    return parts


def _expected_section(s: dict) -> list:
    """Computed against expected (the scenario's ``expected`` table, summary.json ``expected``):
    met or not met, each value with its relative error against the tolerance, and each warning
    the scenario expects.  Nothing without an ``expected`` table."""
    exp = s.get("expected")
    if not exp:
        return []
    e = html.escape
    met = bool(exp.get("met"))
    tol = exp.get("tolerance")
    parts = [f"<h2>Computed against expected</h2><p>Reference: {e(str(exp.get('reference') or ''))}"
             + (f"; tolerance {100 * tol:g} %" if tol is not None else "")
             + f": <span class='{'met' if met else 'unmet'}'>{'met' if met else 'NOT met'}</span></p>"]
    rows = []
    for r in exp.get("values") or []:
        d = r.get("dimension") or "dimensionless"  # the kind's declared dimension of the key
        err = r.get("relative_error")
        rows.append((r.get("key"), r.get("where") or "", _fmt(r.get("expected"), d),
                     "not computed" if r.get("computed") is None else _fmt(r.get("computed"), d),
                     "" if err is None else f"{100 * err:.2f} %", "yes" if r.get("within") else "NO"))
    for w in exp.get("warnings") or []:
        rows.append((f"warning {w.get('name')}", "warnings", "raised", "raised" if w.get("present") else "not raised",
                     "", "yes" if w.get("present") else "NO"))
    parts.append("<table><tr><th class='l'>key</th><th class='l'>where</th><th>expected</th><th>computed</th>"
                 "<th>relative error</th><th>within</th></tr>")
    parts += ["<tr>" + "".join(f"<td{' class=l' if i < 2 else ''}>{e(str(c))}</td>" for i, c in enumerate(row))
              + "</tr>" for row in rows]
    parts.append("</table>")
    return parts


_HUMID_FIGURES = ("humid_friction_rh", "humid_friction_curve", "stickslip_rh")
_NOT_REACHED = "not reached"


def _humid_cell(value, dim) -> str:
    """A table cell of the humid friction table: ``dim`` "stiffness" in N/m units, "text" as
    is, else :func:`_fmt`."""
    if dim == "stiffness":
        return _stiffness(value) if value is not None else "n/a"
    if dim == "text":
        return str(value)
    return _fmt(value, dim)


def _last_of(values):
    """The last finite entry of a per-cycle list, or None."""
    if isinstance(values, (list, tuple)):
        return next((v for v in reversed(values) if _num(v) is not None), None)
    return _num(values)


def _k_at(table, point):
    return next((t.get("stiffness") for t in table or [] if isinstance(t, dict) and t.get("point") == point), None)


def _humid_table(s: dict) -> tuple[list, list]:
    """(columns [(header, dimension)], rows [(is_dry, [values])]) of the humid friction table:
    the dry reference first, then one row per RH in run order."""
    hyst = run_view(s).hysteresis
    rhs = list(s.get("rh") or [])
    dry = s.get("dry") or {}
    groups = rh_groups(s)
    aligned = len(groups) == len(rhs)
    zero = [zero_load_row(g[2]) or {} if aligned else {} for g in groups] if aligned else [{}] * len(rhs)

    def run_or_zero(key, row_key=None):
        vals = per_rh(s, key)
        return [v if v is not None else z.get(row_key or key) for v, z in zip(vals, zero)]

    f0p = run_or_zero("repulsive_force")
    cap = run_or_zero("capillary_force")
    steps = []
    for g in (groups if aligned else [None] * len(rhs)):
        if g is None:
            steps.append(None)
            continue
        bad = sum(1 for r in g[2] if not r.get("converged", True))
        steps.append(f"{len(g[2])}" + (f" ({bad} not converged)" if bad else ""))
    wet = [z.get("wetted_area") for z in zero]
    islands = [z.get("island_count") for z in zero]
    dash = "\u2014"  # not applicable to the dry reference: no water
    if hyst:
        cols = [("", "text"), ("F\u2080\u207a (F\u2093 = 0)", "force"), ("peak force F*", "force"),
                ("static friction", "force"), ("sliding force", "force"),
                ("dissipated energy (last cycle)", "energy"), ("K_L at A", "stiffness"), ("K_L at B", "stiffness"),
                ("K_L at C", "stiffness"), ("F_cap (F\u2093 = 0)", "force"), ("A meniscus", "area"),
                ("islands", None), ("steps", "text")]
        tables = per_rh(s, "lateral_stiffness")
        peak = per_rh(s, "peak_force")
        sff, sld = per_rh(s, "static_friction_force"), per_rh(s, "sliding_force")
        energy = per_rh(s, "dissipated_energy")
        rows = [(True, ["dry", dry.get("repulsive_force"), dry.get("peak_force"),
                        dry.get("static_friction_force") if dry.get("static_friction_force") is not None
                        else _NOT_REACHED, dry.get("sliding_force"), _last_of(dry.get("dissipated_energy")),
                        *(_k_at(dry.get("lateral_stiffness"), p) for p in "ABC"), dash, dash, dash, dash])]
        for i, rh in enumerate(rhs):
            rows.append((False, [rh_label(rh), f0p[i], peak[i], sff[i] if sff[i] is not None else _NOT_REACHED,
                                 sld[i], _last_of(energy[i]), *(_k_at(tables[i], p) for p in "ABC"), cap[i], wet[i],
                                 islands[i], steps[i]]))
    else:
        cols = [("", "text"), ("static friction F_s", "force"), ("F_s / (\u03bc F\u2080\u207a) at onset", "dimensionless"),
                ("presliding displacement", "length"), ("F\u2080\u207a (F\u2093 = 0)", "force"),
                ("F_cap (F\u2093 = 0)", "force"), ("A meniscus", "area"), ("islands", None),
                ("Kelvin radius r_k", "length"), ("film e1", "length"), ("film e2", "length"),
                ("stick ratio at F\u2093 = 0", "dimensionless"), ("steps", "text")]
        sff = per_rh(s, "static_friction_force")
        ratio, pre = per_rh(s, "static_friction_ratio"), per_rh(s, "presliding_displacement")
        stick0 = run_or_zero("zero_force_stick_ratio", "stick_ratio")
        rows = [(True, ["dry", dry.get("static_friction_force") if dry.get("static_friction_force")
                        is not None else _NOT_REACHED, dry.get("static_friction_ratio"),
                        dry.get("presliding_displacement"), dry.get("repulsive_force"), dash, dash, dash, dash, dash,
                        dash, dry.get("zero_force_stick_ratio"), dash])]
        for i, rh in enumerate(rhs):
            z = zero[i]
            rows.append((False, [rh_label(rh), sff[i] if sff[i] is not None else _NOT_REACHED, ratio[i], pre[i],
                                 f0p[i], cap[i], wet[i], islands[i], z.get("kelvin_radius"), z.get("film_thickness_1"),
                                 z.get("film_thickness_2"), stick0[i], steps[i]]))
    return cols, rows


def humid_friction_section(s: dict, figures: dict) -> tuple[list, dict]:
    """Report section ``humid_friction`` (kinds partial_slip and hysteresis with ``[humidity]``):
    the humidity inputs, one table row per RH after the dry reference (static friction,
    presliding displacement or the loop's energy and lateral stiffness, F0+, the capillary force
    and the meniscus of the zero-load state), and the humid figures.  Nothing for a dry run.

    Parameters
    ----------
    s : dict
        The run summary (summary.json, JSON-ready).
    figures : dict
        Figure name -> PNG path, the figures not yet placed.

    Returns
    -------
    (list of str, dict)
        The HTML parts and the figures left for the general list.
    """
    view = run_view(s)
    if not view.humid_friction:
        return [], figures
    e = html.escape
    hyst = view.hysteresis
    rhs = list(s.get("rh") or [])
    parts = ["<h2>Humid friction</h2>"]
    what = "loop" if hyst else "ramp"
    parts.append(f"<p>One {what} per RH, in the order given ({e(', '.join(rh_label(v) for v in rhs))}), each "
                 f"warm-started from the previous RH's state at F\u2093 = 0, after a dry reference {what} (the "
                 "scenario without [humidity]: Dugdale adhesion alone, if any). The menisci are recomputed at every "
                 "step; shear acts only where the contact is compressive, never in a meniscus.</p>")
    settings = []
    mu = _num(s.get("friction_coefficient"))
    if mu is not None:
        settings.append(("friction coefficient \u03bc", f"{mu:.4g}"))
    hum = (s.get("problem") or {}).get("humidity")
    if hum:
        settings += _humidity_rows(hum)
    if settings:
        parts.append("<table>")
        parts += [f"<tr><th class='l'>{e(a)}</th><td class='l'>{e(b)}</td></tr>" for a, b in settings]
        parts.append("</table>")
    cols, rows = _humid_table(s)
    # a column empty in every row (the sliding force of a force-controlled loop) says nothing
    keep = [k for k in range(len(cols)) if k == 0 or any(vals[k] is not None for _, vals in rows)]
    cols = [cols[k] for k in keep]
    rows = [(d, [vals[k] for k in keep]) for d, vals in rows]
    parts.append("<h3>Per RH against the dry reference</h3><div class='scroll'><table class='humid'><tr>"
                 + "".join(f"<th>{e(h) if h else 'RH'}</th>" for h, _ in cols) + "</tr>")
    for is_dry, values in rows:
        cells = "".join(f"<td{' class=l' if k == 0 else ''}>{e(_humid_cell(v, d))}</td>"
                        for k, (v, (_, d)) in enumerate(zip(values, cols)))
        parts.append(f"<tr class='{'dry' if is_dry else 'rh'}'>{cells}</tr>")
    parts.append("</table></div>")
    parts.append("<p class='muted'>F\u2080\u207a: the repulsive (compressive) part of the normal force; the "
                 "meniscus pulls the bodies together, so F\u2080\u207a = F + |F_adhesive| and \u03bc F\u2080\u207a, "
                 "not \u03bc F, bounds the tangential force. F_cap, A meniscus, islands"
                 + (", r_k and the films" if not hyst else "") + " are those of the state at F\u2093 = 0 (F_cap "
                 "< 0: tensile). " + ("K_L at Paper F's points A, B, C (F\u2093 / (\u03bc F\u2080\u207a) = -0.5, 0, "
                                      "0.5 on the last branch from -F* to +F*)." if hyst else "") + "</p>")
    for name, cls in (("humid_friction_rh", "wide"), ("humid_friction_curve", "mid"), ("stickslip_rh", "wide")):
        if name in figures:
            parts.append(_figure_html(name, figures[name], cls))
    return parts, {k: v for k, v in figures.items() if k not in _HUMID_FIGURES}


def friction_section(s: dict, figures: dict) -> tuple[list, dict]:
    """Report section ``friction``: the run-level friction values of a partial-slip run (a
    hysteresis run has its own section; a humid run's values, lists per RH, are section
    ``humid_friction``'s).  Returns (HTML parts, the figures left to place)."""
    fric = _friction_rows(s)
    view = run_view(s)
    if not fric or view.hysteresis or view.humid_friction:
        return [], figures
    e = html.escape
    parts = ["<h2>Friction</h2><table>"]
    parts += [f"<tr><th class='l'>{e(a)}</th><td class='l'>{e(b)}</td></tr>" for a, b in fric]
    parts.append("</table>")
    return parts, figures


def hysteresis_section(s: dict, figures: dict) -> tuple[list, dict]:
    """Report section ``hysteresis``: loop energies, static friction, lateral stiffness at A, B,
    C against Mindlin-Deresiewicz, with the loop figures.  Returns (HTML parts, the figures left)."""
    view = run_view(s)
    if not view.hysteresis:
        return [], figures
    if view.humid_friction:
        # the run-level values are lists per RH (section humid_friction): the detail of the last
        # RH, the one whose per-cycle maps fields.nc keeps and the hysteresis figures show
        s, _ = rh_summary(s, -1)
    parts = _hysteresis_section(s, figures)
    return parts, {k: v for k, v in figures.items() if not _is_hysteresis_figure(k)}


def capillary_section(s: dict, figures: dict) -> tuple[list, dict]:
    """Report section ``capillary``: the humidity inputs and the forces against RH, with the
    capillary figures (runs with ``[humidity]``).  Returns (HTML parts, the figures left)."""
    hum = (s.get("problem") or {}).get("humidity")
    if not hum:
        return [], figures
    parts = _capillary_section(s, hum, figures)
    return parts, {k: v for k, v in figures.items() if k not in _CAPILLARY_FIGURES}


#: The report sections a run kind names (:attr:`tribobem.runs.kind.RunKind.report_sections`):
#: name -> ``(summary, figures) -> (HTML parts, figures left for the general list)``, each
#: showing only what applies.
REPORT_SECTIONS = {"friction": friction_section, "hysteresis": hysteresis_section, "capillary": capillary_section,
                   "humid_friction": humid_friction_section}


def render_report(summary: dict, figures: dict | None = None, sections=None) -> str:
    """The HTML text of the report.

    Parameters
    ----------
    summary : dict
        The run summary (as written to summary.json).
    figures : dict, optional
        Figure name -> PNG path; embedded in that order.
    sections : sequence of str, optional
        The kind's own sections (keys of :data:`REPORT_SECTIONS`), placed after the key
        results; default: every section (each shows only what the summary holds).

    Returns
    -------
    str
        A self-contained HTML document (inline CSS, PNGs embedded as data URIs), so the report
        can be moved or mailed without its folder.
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

    warns = [str(w) for w in (s.get("warnings") or []) if w]
    if warns:  # prominently, before anything else
        parts.append(f"<div class='warnings' role='alert'><b>\u26a0 {len(warns)} warning(s)</b><ul>"
                     + "".join(f"<li>{e(w)}</li>" for w in warns) + "</ul></div>")

    steps = s.get("steps", [])
    n_bad = sum(1 for st in steps if not st.get("converged", True))
    if s.get("converged"):
        parts.append(f"<p class='ok'>Converged: all {len(steps)} step(s) reached the solver tolerance.</p>")
    else:
        parts.append(f"<p class='warn'>WARNING: not converged. {n_bad} of {len(steps)} step(s) did not reach the "
                     "solver tolerance; their results are unreliable. Raise solver.max_iterations, loosen "
                     "solver.tolerance, or refine the load steps.</p>")

    # key scalars
    rows = []
    for key, label, dim in _RUN_SCALARS:
        if s.get(key) is not None and not isinstance(s[key], list):  # a humid pull-off's list: its own section
            rows.append((label, _fmt(s[key], dim)))
    band = s.get("cohesive_edge")
    if isinstance(band, dict) and band.get("fraction") is None and band.get("resolved") is False:
        # too coarse for the band to mean anything: say so rather than print a number
        rows.append(("grid band of the Dugdale equilibria",
                     f"not resolved: {band.get('reason') or 'the cohesive zone is below a cell'}; the adhesive "
                     "forces are set by a few cells"))
    elif isinstance(band, dict) and band.get("fraction") is not None:
        # the grid's band of Dugdale equilibria (output/checks.py, cohesive_edge)
        rows.append(("grid band of the Dugdale equilibria",
                     f"{band.get('nodes')} cohesive-zone edge nodes consistent in and out of the zone, "
                     f"{_fmt(band.get('force'), 'force')}: adhesive forces set by the grid to about "
                     f"\u00b1{100 * float(band['fraction']):.1f} %"
                     + (", loop energies several times that" if s.get("dissipated_energy") else "")))
    prob = s.get("problem", {}) or {}
    for key, label, dim in _PROBLEM_SCALARS + law_report_rows():
        if prob.get(key) is not None:
            rows.append((label, _fmt(prob[key], dim)))
    lay = prob.get("layer")
    if lay:  # a coated body: E* above is the pair of substrates
        rows.append((f"body{lay['body']} coating", f"{_fmt(lay['thickness'], 'length')} layer, E "
                     f"{_fmt(lay['E'], 'pressure')}, nu {lay['nu']:g}, bonded to the body (E* above: the substrates')"))
    g = prob.get("grid")
    if g:
        rows.append(("grid", f"{g['nx']} x {g['ny']} cells, {format_quantity(g['lx'], 'length')} x "
                             f"{format_quantity(g['ly'], 'length')}, {'periodic' if g.get('periodic') else 'free boundary'}"))
    if steps:
        last = max(steps, key=lambda st: st.get("normal_force") or float("-inf"))
        # a state solved at zero load (-4e-13 N of a 2.5e-7 N run) reads 0 N, not -427.5 fN
        rows.append(("max normal force", format_value(last.get("normal_force"), "force", 4,
                                                      scale=_force_scale(steps))))
        rows.append(("contact area at max force", _fmt(last.get("contact_area"), "area")))
        rows.append(("max pressure", _fmt(max((st.get("max_pressure") or 0) for st in steps), "pressure")))
    for body, st in ((s.get("subsurface") or {}).get("bodies") or {}).items():
        # [output] stresses: the largest von Mises stress below the surface, and where
        rows.append((f"{body} subsurface stress",
                     f"von Mises up to {_fmt(st['max_von_mises'], 'pressure')} at depth "
                     f"{_fmt(st['max_von_mises_depth'], 'length')} (state {st['max_von_mises_state']}); max shear "
                     f"{_fmt(st['max_shear'], 'pressure')} at {_fmt(st['max_shear_depth'], 'length')}; largest tensile "
                     f"principal stress {_fmt(st['max_tensile_principal'], 'pressure')}"))
    for body, st in (prob.get("roughness") or {}).items():
        if "rms_height" in st:
            rows.append((f"{body} roughness", f"rms {format_quantity(st['rms_height'], 'length')}, rms slope "
                                              f"{st.get('rms_slope', float('nan')):.3g}"))
    ts = prob.get("two_scale")
    if ts:  # [two_scale]: the windows hold the roughness, the grid above is the macro grid
        run_ts = s.get("two_scale") or {}
        law = run_ts.get("law") or {}
        rows.append(("two-scale", f"{ts['realisations']} periodic window(s) of {format_quantity(ts['window'], 'length')} "
                                  f"({ts['window_n']}^2 cells of {format_quantity(ts['window_dx'], 'length')}), "
                                  f"{len(law.get('pressures', []))} tabulated pressures; macro cells "
                                  f"{format_quantity(ts['macro_dx'], 'length')}; contact area = real area "
                                  "(the windows' contact fraction), max pressure = the windows' largest"))
        if s.get("rh") is not None and s.get("capillary_force") is not None:  # the windows' menisci at one RH
            rows.append(("menisci", f"RH {s['rh']:g}: meniscus force {format_quantity(s['capillary_force'], 'force')}, "
                                    f"repulsive force F0+ {format_quantity(s['repulsive_force'], 'force')}, wetted area "
                                    f"{format_quantity(s['wetted_area'], 'area')} (the windows' menisci, summed over "
                                    "the macro contact)"))
        if run_ts.get("window_over_pressure_length") is not None:
            rows.append(("scale separation", f"window / (p / |grad p|) = {run_ts['window_over_pressure_length']:.2f} "
                                             f"(median over the contact; "
                                             f"{format_quantity(run_ts['pressure_length_edge'], 'length')} at its edge)"))
    solver = [f"normal solver {prob['normal_method']}"] if prob.get("normal_method") and not ts else []
    if ts:
        if s.get("kind") == "pulloff":
            solver.append("micro windows: loading and unloading under displacement control; macro: Newton with "
                          "MINRES on the tensile interface law, unloading under displacement control")
        else:
            solver.append("micro windows: Polonsky-Keer force path; macro: projected Newton with the interface law")
    solve = s.get("solve") or {}
    if solve.get("precision"):
        solver.append(f"{solve['precision']} precision")
    cand = solve.get("candidates")
    if cand:
        i0, i1, j0, j1 = cand["box"]
        solver.append(f"candidate-set solve: a box of {i1 - i0} x {j1 - j0} nodes ({100 * cand['box_fraction']:.1f} % of "
                      f"the grid), {cand['rounds']} round(s), every node outside it verified open (margin "
                      f"{format_quantity(cand['verified_margin'], 'length')})")
    if prob.get("backend"):
        solver.append(f"backend {prob['backend']}" + (f", FFT engine {prob['fft']}" if prob.get("fft") else ""))
    if solver:  # what [solver] method = "auto" and backend stood for
        rows.append(("solver", "; ".join(solver)))
    t = s.get("timings", {})
    if t:
        # the report is written before the outputs are complete: their time and the total are
        # in summary.json (written last), not here
        done = {k: v for k, v in t.items() if isinstance(v, (int, float)) and k not in ("output", "total")}
        rows.append(("time", ", ".join(f"{k} {v:.2f} s" for k, v in done.items())
                     + " (output and total time: summary.json)"))
    parts.append("<h2>Key results</h2><table>")
    parts += [f"<tr><th class='l'>{e(a)}</th><td class='l'>{e(b)}</td></tr>" for a, b in rows]
    parts.append("</table>")

    parts += _expected_section(s)

    figures = {k: v for k, v in (figures or {}).items() if v is not None and staged_source(v).exists()}
    names = tuple(REPORT_SECTIONS) if sections is None else tuple(sections)
    unknown = [n for n in names if n not in REPORT_SECTIONS]
    if unknown:
        raise ValueError(f"unknown report section(s) {unknown}; known: {', '.join(REPORT_SECTIONS)}")
    for name in names:
        # each section shows what applies and the figures it placed leave the general list
        html_parts, figures = REPORT_SECTIONS[name](s, figures)
        parts += html_parts

    if figures:
        parts.append("<h2>Figures</h2>")
        for name, path in figures.items():
            parts.append(_figure_html(name, path, _width_class(path)))

    if steps:
        cols = [(k, h, d) for k, h, d, optional in _STEP_COLUMNS
                if not optional or any(st.get(k) is not None for st in steps)]
        notes = _step_notes(steps)
        for j in s.get("jumps") or []:  # the state a jump lands on
            if isinstance(j.get("index"), int) and 0 <= j["index"] < len(steps):
                notes[j["index"]] = "; ".join(filter(None, (str(j.get("kind") or "jump"), notes.get(j["index"]))))
        parts.append(f"<h2>Steps ({len(steps)})</h2><div class='scroll'><table class='steps'><tr><th>#</th>"
                     + "".join(f"<th>{e(c[1])}</th>" for c in cols) + ("<th class='l'>note</th>" if notes else "")
                     + "</tr>")
        show = steps if len(steps) <= 200 else steps[:100] + steps[-100:]
        # round-off (a tangential force of 1e-22 N at F_x = 0) prints as 0: below 1e-9 of the
        # column's largest magnitude, far below any solver tolerance
        tiny = {k: 1e-9 * max((abs(st.get(k)) for st in steps if isinstance(st.get(k), (int, float))
                               and not isinstance(st.get(k), bool)), default=0.0) for k, _, _ in cols}
        # the net normal force: solver noise below ZERO_FRACTION of the run's forces (units.format_value)
        tiny["normal_force"] = max(tiny.get("normal_force", 0.0), ZERO_FRACTION * _force_scale(steps))

        def cell(st, k, d):
            v = st.get(k)
            if isinstance(v, (int, float)) and not isinstance(v, bool) and abs(v) <= tiny[k]:
                v = 0.0
            return _fmt(v, d)

        for i, st in enumerate(show):
            idx = i if len(steps) <= 200 or i < 100 else len(steps) - 200 + i
            if len(steps) > 200 and i == 100:  # say what the cut hides
                parts.append(f"<tr><td>...</td><td colspan='{len(cols)}' class='l'>{len(steps) - 200} steps hidden "
                             "(summary.json has every step)</td></tr>")
            cells = "".join(f"<td>{e(cell(st, k, d))}</td>" for k, _, d in cols)
            if notes:
                cells += f"<td class='l stepnote'>{e(notes.get(idx, ''))}</td>"
            tr = "<tr class='marked'>" if idx in notes else "<tr>"
            parts.append(f"{tr}<td>{idx}</td>{cells}</tr>")
        parts.append("</table></div>")
        said = []
        if any("jump" in n for n in notes.values()):
            said.append("jump-in, jump-off: the state a jump of the force-approach curve lands on")
        if any("same" in n for n in notes.values()):
            said.append("\u201csame \u03b4 as k\u201d: a second equilibrium at the approach of step k, with another "
                        "force: the adhesive contact has several states at one approach, and this one was reached "
                        "from another start (the end of the loading and the start of the unloading, or the "
                        "refinement around the pull-off re-solving a point of the curve)")
        if said:
            parts.append(f"<p class='muted'>note: {e('; '.join(said))}.</p>")
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


def write_report(outdir, summary: dict, figures: dict | None = None, name: str = "report.html",
                 sections=None) -> Path:
    """Render the report (:func:`render_report`) and write it atomically to ``outdir/name``.

    Atomic (a temporary file renamed into place) so that a reader never sees a half-written
    report.

    Parameters
    ----------
    outdir : str or Path
        The result folder.
    summary : dict
        The run summary (as written to summary.json).
    figures : dict, optional
        Figure name -> PNG path.
    name : str
        File name of the report.
    sections : sequence of str, optional
        As for :func:`render_report`.

    Returns
    -------
    pathlib.Path
        The report's path.
    """
    path = Path(outdir) / name
    return atomic_write_text(path, render_report(summary, figures, sections))
