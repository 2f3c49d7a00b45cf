"""What the figures and reports print must be readable: forces with SI prefixes and solver noise
as 0, font sizes the report can show, point names off the tick labels, the profile through the
contact, the jump rows of the step table named, a design ranking table that fits a 1280 px window."""

from __future__ import annotations

import html
import re

import numpy as np
import pytest
import xarray as xr

import tribobem.output.figures as figures
from tribobem.output.plotting import MIN_FONT, legible, profile_row, step_title
from tribobem.output.report import render_report
from tribobem.units import format_quantity, format_value


# --------------------------------------------------------------------------- helpers
def _capture(monkeypatch):
    """Make the figure modules' save_png keep the Figure (drawn at its final sizes) instead of writing it."""
    got = []

    def keep(fig, path):
        legible(fig)
        fig.draw_without_rendering()
        got.append(fig)
        return path

    for family in (figures.maps, figures.load_curve, figures.stickslip, figures.hysteresis, figures.humid_maps):
        monkeypatch.setattr(family, "save_png", keep)
    return got


def _fields(pressure, normal_force, labels, dx=1e-9):
    """A fields dataset of grid-shaped pressure maps (Pa, (step, nx, ny)) on cells of dx (m)."""
    p = np.asarray(pressure, dtype=float)
    ns, nx, ny = p.shape
    x = (np.arange(nx) - (nx - 1) / 2) * dx
    y = (np.arange(ny) - (ny - 1) / 2) * dx
    gap = np.where(p > 0, 0.0, 1e-9) * np.ones_like(p)
    return xr.Dataset(
        {"pressure": (("step", "x", "y"), p), "gap": (("step", "x", "y"), gap),
         "initial_gap": (("x", "y"), np.add.outer(x**2, y**2) / 2e-6)},
        coords={"step": np.arange(ns), "x": x, "y": y, "label": ("step", list(labels)),
                "normal_force": ("step", np.asarray(normal_force, dtype=float))})


def _prandtl_summary(cycles=4, n=6, fmax=5.2e-3, stroke=3.37e-6, k_ratio=12.0):
    """A displacement-controlled rectangular friction loop (elastic-perfectly-plastic, Coulomb
    force fmax in N, stroke in m): four cycles, so that the turning points D, H, L ... share the
    loop's corners and their names ("H, P, X, TP8") sit at the ends of the range."""
    half = stroke / 2
    k = k_ratio * fmax / half
    path = [("start", 0, 0.0)] + [("loading", 0, half * (i + 1) / n) for i in range(n)]
    for c in range(1, cycles + 1):
        path += [("unloading", c, half - half * (i + 1) / n) for i in range(2 * n)]
        path += [("reloading", c, -half + half * (i + 1) / n) for i in range(2 * n)]
    rows, f, d0 = [], 0.0, 0.0
    for i, (b, c, d) in enumerate(path):
        f = float(np.clip(f + k * (d - d0), -fmax, fmax))
        d0 = d
        rows.append({"index": i, "cycle": c, "branch": b, "tangential_force_x": f, "displacement_x": d,
                     "stick_ratio": 1.0 if abs(f) < fmax else 0.0, "converged": True, "normal_force": 0.05,
                     "repulsive_force": 0.05})
    return {"kind": "hysteresis", "friction_coefficient": 0.104, "repulsive_force": 0.05, "steps": rows,
            "inputs": {"friction": {"coefficient": 0.104, "path": {"control": "displacement", "stroke": stroke}}}}


def _overlap(a, b) -> bool:
    return a.x0 < b.x1 and b.x0 < a.x1 and a.y0 < b.y1 and b.y0 < a.y1


# --------------------------------------------------------------------------- titles
def test_format_value_rounds_before_choosing_the_prefix_and_zeroes_solver_noise():
    assert format_quantity(9.9999999e-7, "force", 3) == "1 µN"  # titles printed "1e+03 nN"
    assert format_value(9.9999999e-7, "force", 3) == "1 µN"
    assert format_value(1e-6, "force", 3) == "1 µN"
    assert format_value(1e-6, "force", 3, ascii_only=True) == "1 uN"
    assert format_value(999.96e-9, "force", 4) == "1 µN"
    assert format_value(-2.54934e-7, "force", 4) == "-254.9 nN"
    # noise against the run's force scale prints as 0; a value above ZERO_FRACTION stays
    assert format_value(-4e-16, "force", 3, scale=1e-6) == "0 N"
    assert format_value(-4.2753e-13, "force", 4, scale=[2.549e-7, -4.2753e-13]) == "0 N"  # demo, zero load
    assert format_value(-3e-12, "force", 3, scale=2.5e-7) == "-3 pN"  # 1.2e-5 of the scale: kept
    assert format_value(-4e-16, "force", 3) == "-400 aN"  # no scale: nothing zeroed


def test_step_title_prefixes_and_zero_load_state():
    p = np.zeros((2, 8, 8))
    p[:, 3:5, 3:5] = 1e8  # 4 cells of 1 nm^2 at 100 MPa: F+ = 4e-10 N per step
    ds = _fields(p, [-4.2753e-13, -2.549e-7], ["preload", "pull-off"])
    assert step_title(ds, 0) == "preload, F = 0 N"
    assert step_title(ds, 1) == "pull-off, F = -255 nN"
    ds1 = _fields(p[:1], [9.9999999e-7], ["state"])
    assert step_title(ds1, 0) == "state, F = 1 µN"


# --------------------------------------------------------------------------- profile
def test_profile_row_goes_through_the_maximum_pressure():
    y = (np.arange(12) - 5.5) * 1e-9
    p = np.zeros((16, 12))
    p[3, 9] = 2e6  # off-centre maximum
    p[8, 6] = 1e6
    assert profile_row(p, y) == (9, "maximum pressure")
    # equal maxima: the row nearest y = 0
    p[3, 4] = 2e6
    assert profile_row(p, y) == (4, "maximum pressure")
    # held by adhesive stress only (no compressive node): the largest |p|
    q = np.zeros((16, 12))
    q[10, 2] = -5e7
    q[1, 7] = -1e7
    assert profile_row(q, y) == (2, "maximum |pressure|")
    assert profile_row(np.zeros((16, 12)), y) == (5, "centre line")  # y[5] = -0.5 nm, nearest to 0


def test_profile_figure_draws_and_names_the_row_through_the_contact(monkeypatch):
    got = _capture(monkeypatch)
    p = np.zeros((1, 16, 12))
    p[0, 2:5, 8:11] = 3e7
    p[0, 3, 9] = 9e7  # the contact of a rough spot, off the centre line (y index 9: y = 3.5 nm)
    ds = _fields(p, [5e-11], ["state"])
    figures.profile_figure(ds, 0, "unused.png")
    fig = got[0]
    ax, ax2 = fig.axes[0], fig.axes[1]
    title = ax.get_title()
    assert "y = 3.5 nm" in title and "maximum pressure" in title, title
    drawn = ax2.get_lines()[0].get_ydata()  # pressure p in MPa
    np.testing.assert_allclose(drawn, p[0, :, 9] / 1e6, rtol=1e-12)
    assert drawn.max() == pytest.approx(90.0, rel=1e-12)


# --------------------------------------------------------------------------- font sizes
def _texts_of(fig):
    ticks, legends = [], []
    for ax in fig.axes:
        ticks += [t for t in ax.get_xticklabels() + ax.get_yticklabels() if t.get_text()]
        for child in ax.child_axes:
            ticks += [t for t in child.get_xticklabels() + child.get_yticklabels() if t.get_text()]
        if ax.get_legend() is not None:
            legends += list(ax.get_legend().get_texts())
    for leg in fig.legends:
        legends += list(leg.get_texts())
    return ticks, legends


def test_tick_labels_and_legends_are_at_least_10_pt(monkeypatch):
    got = _capture(monkeypatch)
    figures.hysteresis_loop_figure(_prandtl_summary(), "unused.png")
    steps = [{"approach": d, "normal_force": f, "branch": b}
             for d, f, b in ((0.0, 0.0, "loading"), (1e-9, 2e-7, "loading"), (0.5e-9, 1e-7, "unloading"),
                             (-0.5e-9, -3e-8, "unloading"))]
    figures.force_curve_figure({"kind": "pulloff", "steps": steps, "pull_off_force": -3e-8,
                                "pull_off_approach": -0.5e-9}, "unused.png")
    p = np.zeros((1, 16, 12))
    p[0, 6:9, 4:7] = 1e7
    figures.profile_figure(_fields(p, [1e-10], ["state"]), 0, "unused.png")
    assert len(got) == 3
    for fig in got:
        ticks, legends = _texts_of(fig)
        assert ticks and legends
        assert min(t.get_fontsize() for t in ticks) >= MIN_FONT == 10.0
        assert min(t.get_fontsize() for t in legends) >= 10.0


def test_legible_keeps_larger_sizes_and_insets_at_8_pt():
    from matplotlib.figure import Figure

    fig = Figure()
    ax = fig.add_subplot()
    ax.plot([0, 1], [0, 1], label="a")
    ax.legend(fontsize=7)
    ax.set_title("t", fontsize=14)
    ins = ax.inset_axes([0.1, 0.5, 0.4, 0.4])
    ins.plot([0, 1], [1, 0])
    ins.tick_params(labelsize=6)
    legible(fig)
    fig.draw_without_rendering()
    assert ax.get_legend().get_texts()[0].get_fontsize() == 10.0
    assert ax.title.get_fontsize() == 14.0
    assert min(t.get_fontsize() for t in ins.get_xticklabels()) == 8.0
    assert min(t.get_fontsize() for t in ax.get_xticklabels()) == 10.0


# --------------------------------------------------------------------------- loop letters
def test_loop_point_names_stay_off_the_tick_labels(monkeypatch):
    got = _capture(monkeypatch)
    figures.hysteresis_loop_figure(_prandtl_summary(), "unused.png")
    fig = got[0]
    names = {}
    for ax in fig.axes:
        names[ax] = [t for t in ax.texts if type(t).__name__ == "Annotation"]
    loop = fig.axes[0]
    labels = [t.get_text() for t in names[loop]]
    assert "H, P, X, TP8" in labels and "D, L, T, TP7, TP9" in labels, labels
    ticks = []
    for ax in fig.axes:
        ticks += [t.get_window_extent() for t in ax.get_xticklabels() + ax.get_yticklabels() if t.get_text()]
        for child in ax.child_axes:  # the F_x / (mu F0+) axis on the right
            ticks += [t.get_window_extent() for t in child.get_yticklabels() if t.get_text()]
    assert len(ticks) > 20
    checked = 0
    for ax, texts in names.items():
        frame = ax.get_window_extent()
        for t in texts:
            bb = (t.get_bbox_patch() or t).get_window_extent()
            assert not any(_overlap(bb, tb) for tb in ticks), t.get_text()
            # inside the frame (within 0.5 px)
            assert bb.x0 >= frame.x0 - 0.5 and bb.x1 <= frame.x1 + 0.5, (t.get_text(), bb, frame)
            assert bb.y0 >= frame.y0 - 0.5 and bb.y1 <= frame.y1 + 0.5, (t.get_text(), bb, frame)
            checked += 1
    assert checked >= 20  # 6 names on the loop, 2 x 10 on the stick-ratio panel


# --------------------------------------------------------------------------- report
def _demo_like_summary():
    """The demo's path (summary.json values): loading under displacement control with a jump-in
    at step 3; the end of the loading (step 9) and the zero-load start of the unloading (step 10)
    at one approach; the refined pull-off (24) at the approach of step 23; the jump-off at 28."""
    rows = [(-9.7428e-10, 0.0), (-7.6447e-10, 0.0), (-5.5467e-10, 0.0), (-3.4486e-10, -2.4510e-07),
            (-1.3506e-10, -2.3528e-07), (9.1397e-10, -7.6440e-09), (9.1397e-10, -4.2753e-13),
            (-3.0387e-10, -2.4721e-07), (-4.2566e-10, -2.4979e-07), (-4.2566e-10, -2.5493e-07),
            (-9.1280e-10, 0.0)]
    branch = ["loading"] * 6 + ["unloading"] * 5
    steps = [{"index": i, "approach": d, "normal_force": f, "branch": b, "repulsive_force": max(f, 0.0) + 3.6e-7,
              "converged": True} for i, ((d, f), b) in enumerate(zip(rows, branch))]
    return {"kind": "pulloff", "steps": steps,
            "jumps": [{"index": 3, "branch": "loading", "kind": "jump-in", "approach": -3.4486e-10, "force": -2.451e-07},
                      {"index": 10, "branch": "unloading", "kind": "jump-off", "approach": -9.128e-10, "force": 0.0}]}


def _step_rows(page):
    table = page[page.index("<h2>Steps"):]
    table = table[:table.index("</table>")]
    rows = {}
    for m in re.finditer(r"<tr( class='marked')?><td>(\d+)</td>(.*?)</tr>", table):
        cells = re.findall(r"<td[^>]*>(.*?)</td>", m.group(3))
        rows[int(m.group(2))] = (bool(m.group(1)), [html.unescape(c) for c in cells])
    return rows


def test_report_labels_jump_rows_and_repeated_approaches():
    page = render_report(_demo_like_summary())
    rows = _step_rows(page)
    assert len(rows) == 11
    notes = {i: cells[-1] for i, (_, cells) in rows.items()}
    assert notes[3] == "jump-in" and notes[10] == "jump-off"
    assert notes[6] == "same \u03b4 as 5" and notes[9] == "same \u03b4 as 8"
    assert {i for i, n in notes.items() if n} == {3, 6, 9, 10}
    assert {i for i, (marked, _) in rows.items() if marked} == {3, 6, 9, 10}
    assert "<th class='l'>note</th>" in page
    assert "a second equilibrium at the approach of step k" in html.unescape(page)
    # the zero-load state: 0 N in the table and as the max normal force, not -427.5 fN
    assert rows[6][1][1] == "0 N"
    assert "fN" not in page
    assert re.search(r"max normal force</th><td class='l'>0 N<", page)


def test_report_without_jumps_or_repeats_has_no_note_column():
    steps = [{"approach": 1e-9 * i, "normal_force": 1e-6 * i, "branch": "loading"} for i in range(4)]
    page = render_report({"kind": "normal", "steps": steps})
    assert ">note<" not in page and "marked" not in page.split("</style>")[1]


# --------------------------------------------------------------------------- design table
def _design_rows():
    from tribobem.design import DesignSpec

    design = DesignSpec.from_dict({
        "name": "burl", "base": {"name": "b", "grid": {"n": 16, "size": "1.6 um"},
                                 "body1": {"E": "130 GPa", "nu": 0.28},
                                 "body2": {"E": "410 GPa", "nu": 0.14,
                                           "shape": {"kind": "burl", "radius": "0.3 um", "edge_radius": "10 um"}},
                                 "load": {"force": "2 uN"}, "friction": {"coefficient": 0.3}},
        "parameters": {"body2.shape.radius": ["0.2 um", "0.3 um", "0.4 um"],
                       "body1.texture.kind": ["dimples", "grooves"], "humidity.rh": [0.3, 0.7]},
        "targets": {"static_friction_force": {"min": "15 uN"}}})
    rows = []
    for i, (r, t, h) in enumerate((r, t, h) for r in ("0.2 um", "0.3 um", "0.4 um") for t in ("dimples", "grooves")
                                  for h in (0.3, 0.7)):
        rows.append({"rank": i + 1, "hash": f"{i:016x}", "status": "ok", "message": "",
                     "point": {"body2.shape.radius": r, "body1.texture.kind": t, "humidity.rh": h},
                     "targets_met": 1, "n_targets": 1, "distance": 0.1 * i, "met": {"static_friction_force": True},
                     "exceeds_hardness": False, "n_warnings": 2, "warnings": [],
                     "static_friction_force": 1.73e-5 + 1e-6 * i, "static_friction_ratio": 0.9962,
                     "presliding_displacement": 6.217e-10, "lateral_stiffness_A": 39780.0 + 100 * i,
                     "lateral_stiffness_B": 36609.0, "lateral_stiffness_C": 31530.0,
                     "pull_off_force": -4.221e-5, "contact_area": 1e-14 if i > 6 else 5e-15,
                     "max_pressure": 6.976e8, "repulsive_force": 2e-6, "capillary_force": None,
                     "peak_pressure": 2.046e9})
    return design, rows


def test_design_ranking_table_fits_a_1280_px_window():
    from tribobem.design.report import render_design_report

    design, rows = _design_rows()
    page = render_design_report(design, rows)
    table = page[page.index("<h2>Ranking</h2>"):]
    table = table[:table.index("</table>")]
    assert "table.rank th{white-space:normal" in page  # the headers wrap
    head, units, *body = re.findall(r"<tr[^>]*>(.*?)</tr>", table)
    heads = [re.sub(r"<[^>]+>", "", html.unescape(h).replace("&shy;", "")) for h in re.findall(r"<th[^>]*>(.*?)</th>", head)]
    unit_cells = [html.unescape(u) for u in re.findall(r"<th[^>]*>(.*?)</th>", units)]
    assert len(body) == 12 and len(unit_cells) == len(heads)
    # a column per parameter, the values alone; units once per column, in the second header row
    assert heads[1:4] == ["body2.shape.radius", "body1.texture.kind", "humidity.rh"]
    assert "F_cap" not in heads  # no point has a value: left out
    col = {h: i for i, h in enumerate(heads)}
    assert unit_cells[col["F_s"]] == "\u00b5N" and unit_cells[col["K_L A"]] == "kN/m"
    assert unit_cells[col["A_real"]] == "nm\u00b2" and unit_cells[col["p_peak"]] == "GPa"
    cells = [[html.unescape(re.sub(r"<[^>]+>", "", c)) for c in re.findall(r"<td[^>]*>(.*?)</td>", r)] for r in body]
    assert cells[0][col["F_s"]] == "17.3" and cells[0][col["K_L A"]] == "39.78"
    assert cells[11][col["A_real"]] == "10000"  # no exponent
    assert not any("=" in c or "\u00b5N" in c or "N/m" in c for r in cells for c in r)
    # width: the widest cell of each column (a header by its longest unbreakable word), in
    # characters; at the table's 0.74 x 16 px font (about 6.5 px per character, plus 6 px of
    # padding per column) 140 characters are 1030 px, inside the page's 1100 px column
    width = sum(max([len(w) for w in re.split(r"[ .]", h) if w] + [len(r[i]) for r in cells])
                for i, h in enumerate(heads))
    assert width <= 140, width


def test_wide_figures_are_shown_wide_in_the_report(tmp_path):
    from matplotlib.figure import Figure

    from tribobem.output.plotting import DPI, save_png
    from tribobem.output.report import _width_class

    widths = {}
    for name, w in (("one", 6.4), ("mid", 8.0), ("two", 9.2)):  # a map, a wider figure, gap + roughness maps
        fig = Figure(figsize=(w, 4.2))
        fig.add_subplot().plot([0, 1], [0, 1])
        widths[name] = save_png(fig, tmp_path / f"{name}.png")
    assert round(6.4 * DPI) == 704 and _width_class(widths["one"]) == ""  # 520 px: 0.74 of its pixels
    assert _width_class(widths["mid"]) == "mid"  # 880 px: at 700 px, 0.8
    assert _width_class(widths["two"]) == "wide"  # 1012 px: at 520 px only 0.51
    page = render_report({"kind": "normal", "steps": []}, figures={"topography": widths["two"], "pressure": widths["one"]})
    assert "<figure class='wide'><img alt='topography'" in page and "<figure><img alt='pressure'" in page


def test_spread_labels_separates_a_cluster():
    from matplotlib.figure import Figure

    from tribobem.output.plotting import spread_labels

    fig = Figure(figsize=(5.6, 4.4), layout="constrained")
    ax = fig.add_subplot()
    pts = [(5000.0, 36.6), (5000.0, 36.0), (5000.0, 35.2), (5050.0, 34.9), (10000.0, 68.0)]  # labels overlap unspread
    ax.plot(*zip(*pts), "o")
    names = [ax.annotate(f"#{k}", p, textcoords="offset points", xytext=(4, 4), fontsize=7) for k, p in enumerate(pts)]
    spread_labels(ax, names)
    fig.draw_without_rendering()
    boxes = [t.get_window_extent() for t in names]
    frame = ax.get_window_extent()
    for i in range(len(boxes)):
        assert names[i].get_fontsize() == 10.0
        assert frame.x0 - 0.5 <= boxes[i].x0 and boxes[i].x1 <= frame.x1 + 0.5
        assert frame.y0 - 0.5 <= boxes[i].y0 and boxes[i].y1 <= frame.y1 + 0.5
        for j in range(i):
            assert not _overlap(boxes[i], boxes[j]), (names[i].get_text(), names[j].get_text())


def test_stickslip_title_at_zero_tangential_force_prints_zero(monkeypatch, tmp_path):
    """The first state of an automatic ramp is solved at F_x = 0: its round-off (1e-22 N, with a
    y component of the same size) printed "F_x = -9.54e-05 aN" and "|F_t|/(mu F0+)"."""
    import warnings

    from tribobem.errors import ResultWarning
    from tribobem.scenario import run_scenario

    sc = {"kind": "partial_slip", "grid": {"n": 24, "size": "0.32 um"}, "body1": {"E": "130 GPa", "nu": 0.3},
          "body2": {"rigid": True, "shape": {"kind": "sphere", "radius": "10 um"}}, "load": {"force": "10 uN"},
          "friction": {"coefficient": 0.2, "tangential_forces": ["0 uN", "1 uN"]},
          "output": {"figures": False, "report": False}}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ResultWarning)
        res = run_scenario(sc, progress=False)
    ds = res.fields.copy(deep=True)
    # the round-off of the example's step 0 (64^2: F_x = -9.54e-23 N), with a y part of its size
    ds["tangential_force_x"].values[0] = -9.54e-23
    ds["tangential_force_y"].values[0] = 3.1e-23
    got = _capture(monkeypatch)
    figures.stickslip_figure(ds, 0, tmp_path / "s.png", mu=0.2)
    title = got[-1].axes[0].get_title()
    assert "$F_x$ = 0 N" in title and r"$F_x/(\mu F_0^+)$ = 0.000" in title and "|F_t|" not in title
