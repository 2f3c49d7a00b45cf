"""Outputs of humid friction runs (kinds partial_slip and hysteresis with [humidity]): the figure
set ``humid_friction`` (values against RH with the dry reference, the curve or loops per RH),
the per-RH stick/slip maps with the meniscus edge, and the report's "Humid friction" section
(the dry row, then one row per RH); a dry run gets none of it.  Small real runs (32 x 32, two
RHs, a few steps)."""

import copy
import io
import shutil

import numpy as np
import pytest

from tribobem.output import make_figures, render_report, replot
from tribobem.output.figures import meniscus_mask
from tribobem.output.humid import per_rh, rh_groups, rh_summary
from tribobem.output.run_kind import run_view
from tribobem.units import format_quantity

RHS = (0.3, 0.7)
HUMID_FIGURES = ("humid_friction_rh", "humid_friction_curve")

BASE = {
    "name": "humid friction test",
    "grid": {"n": 32, "size": "0.3 um"},
    "body1": {"E": "130 GPa", "nu": 0.28, "film": {"isotherm": "Si"}},
    "body2": {"rigid": True, "shape": {"kind": "sphere", "radius": "1 um"}, "film": {"isotherm": "SiO2"}},
    "load": {"force": "1 uN"},
    "humidity": {"rh": list(RHS), "van_der_waals": False},
}


def _png(path):
    return path.is_file() and path.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" and path.stat().st_size > 5000


def _run(tmp_path_factory, name, scenario):
    from tribobem.scenario import run_scenario

    out = tmp_path_factory.mktemp(name)
    res = run_scenario(scenario, outdir=out, progress=False, quiet=True)
    return res, out


def _partial_slip(humid=True):
    sc = copy.deepcopy(BASE)
    sc["kind"] = "partial_slip"
    sc["friction"] = {"coefficient": 0.3, "slip": "total",
                      "tangential_forces": {"start": "0 uN", "stop": "1.5 uN", "num": 6}}
    if not humid:
        del sc["humidity"]
    return sc


@pytest.fixture(scope="module")
def slip(tmp_path_factory):
    return _run(tmp_path_factory, "ps", _partial_slip())


@pytest.fixture(scope="module")
def loop(tmp_path_factory):
    sc = copy.deepcopy(BASE)
    sc["kind"] = "hysteresis"
    sc["friction"] = {"coefficient": 0.3, "path": {"control": "force", "amplitude": 0.9, "cycles": 2, "steps": 12}}
    return _run(tmp_path_factory, "hy", sc)


def _section(html):
    assert html.count("<h2>Humid friction</h2>") == 1
    return html.split("<h2>Humid friction</h2>")[1].split("<h2>")[0]


def _table(sec):
    return sec.split("Per RH against the dry reference")[1].split("</table>")[0]


# ----------------------------------------------------------------------------- partial_slip
def test_partial_slip_report_has_one_row_per_rh_and_dry(slip):
    res, out = slip
    s = res.summary
    assert run_view(s).humid_friction and len(s["static_friction_force"]) == len(RHS)
    html = (out / "report.html").read_text()
    sec = _section(html)
    table = _table(sec)
    # the dry reference first, then one row per RH in run order
    assert table.count("<tr class='dry'>") == 1 and table.count("<tr class='rh'>") == len(RHS)
    assert table.index("<tr class='dry'>") < table.index("<tr class='rh'>")
    assert [r.split("</td>")[0].split(">")[-1] for r in table.split("<tr class='rh'>")[1:]] == ["RH 30 %", "RH 70 %"]
    for v in s["static_friction_force"]:
        if v is not None:
            assert format_quantity(v, "force", 4) in table
    assert format_quantity(s["dry"]["static_friction_force"], "force", 4) in table.split("<tr class='rh'>")[0]
    for col in ("static friction F_s", "presliding displacement", "F_cap", "A meniscus", "islands"):
        assert col in table
    # the friction section defers to the humid one: its per-RH lists have no scalar to show
    assert "<h2>Friction</h2>" not in html
    assert "humidity" not in html.split("<h2>Humid friction</h2>")[0].lower().split("key results")[1]


def test_partial_slip_figures(slip):
    res, out = slip
    for name in (*HUMID_FIGURES, "stickslip_rh"):
        assert _png(out / f"{name}.png"), name
    # the ramps per RH replace the one line through every RH; no per-step map of a mixed set
    assert not (out / "stick_ratio.png").exists()
    assert not list(out.glob("stickslip_step*.png"))
    html = (out / "report.html").read_text()
    sec = _section(html)
    for name in (*HUMID_FIGURES, "stickslip_rh"):
        assert html.count(f"alt='{name}'") == 1 and f"alt='{name}'" in sec, name
    assert "meniscus edge" in sec


def test_meniscus_outline_on_the_maps(slip):
    from matplotlib.figure import Figure

    from tribobem.output import read_fields
    from tribobem.output.figures import _stickslip_axes
    from tribobem.output.figures import humid_stickslip_steps

    _, out = slip
    ds = read_fields(out)
    assert "meniscus" in ds and "rh" in ds.coords
    picks = humid_stickslip_steps(ds)
    assert [rh for _, rh in picks] == list(RHS)  # one map per RH, in run order
    i = picks[0][0]
    wet = meniscus_mask(ds, i)
    men = np.asarray(ds["meniscus"].values[i]).astype(bool)
    contact = np.asarray(ds["contact"].values[i]).astype(bool)
    assert men.any() and np.array_equal(wet, men | contact)
    ax = Figure().add_subplot()
    labels = [h.get_label() for h in _stickslip_axes(ax, ds, i, mu=0.3)]
    assert "meniscus edge" in labels
    # a dry dataset has no meniscus: no outline, no legend entry
    dry = ds.drop_vars("meniscus")
    assert meniscus_mask(dry, i) is None
    ax = Figure().add_subplot()
    assert "meniscus edge" not in [h.get_label() for h in _stickslip_axes(ax, dry, i, mu=0.3)]


def test_per_rh_helpers(slip):
    res, _ = slip
    s = res.summary
    groups = rh_groups(s)
    assert [g[0] for g in groups] == list(RHS)
    assert sum(len(g[2]) for g in groups) == len(s["steps"]) and groups[1][1] == len(groups[0][2])
    assert per_rh(s, "static_friction_force") == s["static_friction_force"]
    assert per_rh(s, "friction_coefficient") == [0.3, 0.3]  # a shared value stays scalar in the summary
    sub, offset = rh_summary(s, -1)
    assert sub["rh"] == RHS[-1] and offset == groups[1][1] and sub["steps"] == groups[1][2]
    assert sub["static_friction_force"] == s["static_friction_force"][-1]
    assert "dry" not in sub and not run_view(sub).humid_friction
    # run-wide lists stay whole even when as long as the RH list
    two = {**s, "warnings": ["w1", "w2"]}
    assert rh_summary(two, 0)[0]["warnings"] == ["w1", "w2"]


def test_replot_from_the_files(slip, tmp_path):
    _, out = slip
    for name in ("summary.json", "fields.nc"):
        shutil.copy(out / name, tmp_path / name)
    files = replot(tmp_path)
    assert {*HUMID_FIGURES, "stickslip_rh"} <= set(files)
    assert "<h2>Humid friction</h2>" in (tmp_path / "report.html").read_text()


def test_cli_prints_one_line_per_rh(slip):
    from rich.console import Console

    from tribobem.cli import _print_summary

    res, _ = slip
    buf = io.StringIO()
    _print_summary(res.summary, None, Console(file=buf, width=200))
    text = buf.getvalue()
    assert "dry" in text and "RH 30 %" in text and "RH 70 %" in text
    assert format_quantity(res.summary["static_friction_force"][0], "force", 4) in text


# ----------------------------------------------------------------------------- hysteresis
def test_hysteresis_report_and_figures(loop):
    res, out = loop
    s = res.summary
    html = (out / "report.html").read_text()
    sec = _section(html)
    table = _table(sec)
    assert table.count("<tr class='dry'>") == 1 and table.count("<tr class='rh'>") == len(RHS)
    for col in ("dissipated energy (last cycle)", "K_L at A", "K_L at B", "K_L at C", "static friction"):
        assert col in table
    last = [v for v in s["dissipated_energy"][0] if v is not None][-1]
    assert format_quantity(last, "energy", 4) in table
    assert format_quantity(s["dry"]["dissipated_energy"][-1], "energy", 4) in table.split("<tr class='rh'>")[0]
    # the detailed hysteresis section shows the last RH (whose per-cycle maps fields.nc keeps)
    assert "<h2>Friction hysteresis at RH 70 %</h2>" in html
    assert html.index("<h2>Humid friction</h2>") < html.index("<h2>Friction hysteresis at RH 70 %</h2>")
    for name in (*HUMID_FIGURES, "hysteresis_loop", "lateral_stiffness", "stickslip_loop"):
        assert _png(out / f"{name}.png"), name
        assert html.count(f"alt='{name}'") == 1, name
    for name in HUMID_FIGURES:
        assert f"alt='{name}'" in sec
    assert not (out / "stick_ratio.png").exists()


def test_hysteresis_loop_maps_of_the_last_rh(loop):
    from tribobem.output import read_fields
    from tribobem.output.figures import loop_map_steps

    res, out = loop
    ds = read_fields(out)
    sub, offset = rh_summary(res.summary, -1)
    picks = loop_map_steps(ds, sub, offset)
    assert picks and [n for _, n in picks][:3] == ["A", "D", "D'"]
    rh = np.asarray(ds["rh"].values)
    assert all(rh[i] == RHS[-1] for i, _ in picks)


# ----------------------------------------------------------------------------- dry runs
def test_dry_run_has_no_humid_outputs(tmp_path_factory):
    res, out = _run(tmp_path_factory, "dry", _partial_slip(humid=False))
    s = res.summary
    assert "rh" not in s and not run_view(s).humid_friction
    html = (out / "report.html").read_text()
    assert "Humid friction" not in html and "<h2>Friction</h2>" in html
    assert not any((out / f"{n}.png").exists() for n in (*HUMID_FIGURES, "stickslip_rh"))
    assert list(out.glob("stickslip_step*.png"))  # the dry maps, one per shown step, as before
    assert make_figures(None, s, tmp_path_factory.mktemp("none"), sets=("humid_friction",)) == {}
    from tribobem.output.report import humid_friction_section

    assert humid_friction_section(s, {"x": out / "stick_ratio.png"}) == ([], {"x": out / "stick_ratio.png"})
    assert "Humid friction" not in render_report(s, sections=("friction", "humid_friction"))
