"""Outputs of the hysteresis kind (Papers E and F): the loop figure with Paper E's points, the
lateral stiffness figure at Paper F's points, the last cycle's dissipation maps, the stick/slip
maps at the turning points, and the report's "Friction hysteresis" section.  One tiny real run
(examples/hysteresis_mindlin.toml at n = 24, 8 steps per cycle) and synthetic summaries."""

import copy
import tomllib
from pathlib import Path

import numpy as np
import pytest

from tribobem.output import make_figures, render_report, replot
from tribobem.output.figures import loop_map_steps, mindlin_reference, turning_point_letters
from tribobem.output.run_kind import run_view

EXAMPLE = Path(__file__).resolve().parents[2] / "examples" / "hysteresis_mindlin.toml"
HYSTERESIS_FIGURES = ("hysteresis_loop", "lateral_stiffness", "dissipation_cycle1", "stickslip_loop")


def _png(path):
    path = Path(path)
    return path.is_file() and path.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" and path.stat().st_size > 5000


@pytest.fixture(scope="module")
def tiny(tmp_path_factory):
    from tribobem.scenario import run_scenario

    sc = tomllib.loads(EXAMPLE.read_text())
    sc["grid"]["n"] = 24
    sc["friction"]["path"]["steps"] = 8
    out = tmp_path_factory.mktemp("hy")
    res = run_scenario(sc, outdir=out, progress=False, quiet=True)
    return res, out


def _rows(branches_cycles):
    """Summary rows with the given (branch, cycle) per step and a zig-zag force."""
    rows = []
    for i, (b, c) in enumerate(branches_cycles):
        rows.append({"branch": b, "cycle": c, "tangential_force_x": float(np.sin(i)), "displacement_x": 1e-9 * i,
                     "stick_ratio": 0.5, "normal_force": 1.0, "converged": True})
    return rows


def _path(cycles, m=3, m0=2):
    bc = [("start", 0)] + [("loading", 0)] * m0
    for c in range(1, cycles + 1):
        bc += [("unloading", c)] * m + [("reloading", c)] * m
    return _rows(bc)


# ----------------------------------------------------------------------------- naming
def test_paper_e_letters():
    rows = _path(2)  # start 0, loading 1-2, unloading 3-5, reloading 6-8, unloading 9-11, reloading 12-14
    letters = turning_point_letters(rows)
    assert letters == {0: "A", 1: "A'", 2: "D", 3: "D'", 5: "H", 6: "H'", 8: "L", 9: "L'", 11: "P", 12: "P'",
                       14: "T"}
    # past X the turning points are numbered
    many = turning_point_letters(_path(5, m=2))
    assert "X" in many.values() and "TP7" in many.values() and "TP7'" in many.values()
    assert turning_point_letters([]) == {}


def test_hysteresis_is_the_kind_not_the_rows():
    assert run_view({"kind": "hysteresis"}).hysteresis
    # rows with a cycle do not make a run a hysteresis run: summary.json's kind does
    assert not run_view({"steps": [{"cycle": 0}]}).hysteresis
    assert not run_view({"kind": "partial_slip", "steps": [{"branch": "loading"}]}).hysteresis
    assert not run_view(None).hysteresis


def test_loop_maps_at_most_six(tiny):
    res, _ = tiny
    ds, summary = res.fields, res.summary
    picks = loop_map_steps(ds, summary)
    # one cycle: the saved states are exactly A, D, D', H, H', L
    assert [name for _, name in picks] == ["A", "D", "D'", "H", "H'", "L"]
    assert [int(ds["summary_step"].values[i]) for i, _ in picks] == [0, 4, 5, 8, 9, 12]
    # three cycles' worth of saved states: A, D, D' and the last three
    import xarray as xr

    rows = _path(3, m=4, m0=4)
    keep = [0] + [i for i, n in turning_point_letters(rows).items() if n not in ("A", "A'")]
    fake = xr.Dataset(coords={"step": np.arange(len(keep)), "summary_step": ("step", np.array(keep)),
                              "tangential_force_x": ("step", np.ones(len(keep)))})
    fake["shear_x"] = ("step", np.zeros(len(keep)))
    names = [n for _, n in loop_map_steps(fake, {"kind": "hysteresis", "steps": rows})]
    assert names == ["A", "D", "D'", "X", "X'", "TP7"]


# ----------------------------------------------------------------------------- the real run
def test_real_run_draws_the_hysteresis_figures(tiny):
    res, out = tiny
    for name in HYSTERESIS_FIGURES:
        assert name in res.files, name
        assert res.files[name] == out / f"{name}.png" and _png(out / f"{name}.png"), name
    # the stick/slip maps are one multi-panel figure, no per-step maps
    assert not list(out.glob("stickslip_step*.png"))
    assert "stick_ratio" in res.files and "force_curve" not in res.files
    names = [k for k in res.files if k not in ("fields", "report", "summary")]
    assert names.index("hysteresis_loop") == 0


def test_mindlin_reference_of_identical_bodies(tiny):
    res, _ = tiny
    s = res.summary
    ref = mindlin_reference(s)
    assert ref is not None
    assert ref["peak"] == pytest.approx(s["peak_force"])
    # the loop area is the Mindlin-Deresiewicz energy within the coarse grid's error
    assert s["dissipated_energy"][0] == pytest.approx(ref["energy"], rel=0.1)
    # dissimilar bodies (a rigid ball on nu = 0.3): coupled, no overlay; rough bodies neither
    rigid = copy.deepcopy(s)
    rigid["inputs"]["body2"]["rigid"] = True
    assert mindlin_reference(rigid) is None
    rough = copy.deepcopy(s)
    rough["inputs"]["body1"]["roughness"] = {"kind": "gaussian"}
    assert mindlin_reference(rough) is None
    # a rigid ball on an incompressible flat has no coupling: the overlay applies
    inc = copy.deepcopy(rigid)
    inc["inputs"]["body1"]["nu"] = 0.5
    assert mindlin_reference(inc) is not None


def test_report_has_the_hysteresis_section(tiny):
    res, out = tiny
    html = (out / "report.html").read_text()
    assert "<h2>Friction hysteresis</h2>" in html
    assert "<h2>Friction</h2>" not in html  # folded into the hysteresis section
    sec = html.split("<h2>Friction hysteresis</h2>")[1].split("<h2>")[0]
    for name in HYSTERESIS_FIGURES:  # embedded once, in the section
        assert html.count(f"alt='{name}'") == 1 and f"alt='{name}'" in sec, name
    figs = [k for k in res.files if k not in ("fields", "report", "summary")]
    assert html.count("<img") == len(figs)
    assert "peak force F*" in sec and "0.8 \u03bc F\u2080\u207a" in sec
    # energy per cycle: loop area, traction work and the Mindlin-Deresiewicz energy
    energy = sec.split("Dissipated energy per cycle")[1].split("</table>")[0]
    assert "loop area" in energy and "traction work" in energy and "Mindlin-Deresiewicz W" in energy
    assert energy.count("<tr>") == 1 + len(res.summary["dissipated_energy"])
    # lateral stiffness table: A, B, C with the three stiffnesses and their ratio
    stiff = sec.split("Lateral stiffness (Paper F)")[1].split("</table>")[0]
    for col in ("K_L fit (Eq. 3)", "K_L Mindlin-Deresiewicz", "K_L virgin (Paper F Eq. 6)",
                "fit / Mindlin-Deresiewicz"):
        assert f"<th>{col}</th>" in stiff
    for point in ("A", "B", "C"):
        assert f"<tr><td>{point}</td>" in stiff
    assert "N/\u00b5m" in stiff
    t = res.summary["lateral_stiffness"][0]
    assert f"{t['stiffness'] / t['mindlin_stiffness']:.4f}" in stiff
    assert "Stick and slip at Paper E's points" in sec


def test_figures_from_the_files(tiny, tmp_path):
    from tribobem.output import read_fields, read_summary
    from tribobem.output.figures import hysteresis_figures, loop_stickslip_figure

    _, out = tiny
    ds, summary = read_fields(out), read_summary(out / "summary.json")
    figs = hysteresis_figures(ds, summary, tmp_path)
    assert set(figs) == {"hysteresis_loop", "lateral_stiffness", "dissipation_cycle1"}
    assert all(_png(p) for p in figs.values())
    picks = loop_map_steps(ds, summary)
    assert [n for _, n in picks] == ["A", "D", "D'", "H", "H'", "L"]
    assert _png(loop_stickslip_figure(ds, picks, tmp_path / "maps.png", mu=0.3))


def test_replot_without_fields(tiny, tmp_path):
    import shutil

    _, out = tiny
    shutil.copy(out / "summary.json", tmp_path / "summary.json")
    files = replot(tmp_path)  # no fields.nc: the loop and the stiffness only
    assert {"hysteresis_loop", "lateral_stiffness"} <= set(files)
    assert not any(k.startswith(("dissipation", "stickslip")) for k in files)
    assert "Friction hysteresis" in (tmp_path / "report.html").read_text()


# ----------------------------------------------------------------------------- other kinds, partial data
def test_other_kinds_draw_none_of_them(tmp_path):
    from .test_outputs_tangential import _fields, synthetic_run

    grid, normals, tangentials, summary = synthetic_run(n=16, ratios=(0.0, 0.6, 1.0))
    figs = make_figures(_fields(grid, normals, tangentials), summary, tmp_path)
    assert "stickslip_step0" in figs  # the partial_slip maps, one per step
    assert not any(k.startswith(("hysteresis", "lateral", "dissipation", "stickslip_loop")) for k in figs)
    assert not list(tmp_path.glob("hysteresis*.png")) and not list(tmp_path.glob("dissipation*.png"))
    assert "Friction hysteresis" not in render_report(summary, figs)
    rows = [n.scalars() for n in normals[:2]]
    rows[1]["normal_force"] *= 2
    figs = make_figures(None, {"kind": "normal", "steps": rows}, tmp_path / "n")
    assert not any(k.startswith(("hysteresis", "lateral", "dissipation")) for k in figs)
    assert "Friction hysteresis" not in render_report({"kind": "normal", "converged": True, "steps": rows})


def test_partial_hysteresis_summary(tmp_path):
    # rows without the run-level tables: the loop only, and a report without the tables
    rows = _path(1, m=4, m0=4)
    s = {"kind": "hysteresis", "converged": True, "steps": rows, "friction_coefficient": 0.3,
         "lateral_stiffness": [], "lateral_stiffness_error": "need at least 4 points on the branch to fit, got 3"}
    figs = make_figures(None, s, tmp_path)
    assert "hysteresis_loop" in figs and _png(figs["hysteresis_loop"])
    assert "lateral_stiffness" not in figs and "stickslip_loop" not in figs
    html = render_report(s, figs)
    assert "<h2>Friction hysteresis</h2>" in html and "Lateral stiffness not computed" in html
    assert "Dissipated energy per cycle" not in html
    # junk rows: nothing drawn, no error
    assert "hysteresis_loop" not in make_figures(None, {"kind": "hysteresis", "steps": [{"cycle": 0}]},
                                                 tmp_path / "j")
