"""The tribobem command line (Typer), driven through typer.testing.CliRunner."""

import json
import os
from pathlib import Path

import pytest
from typer.testing import CliRunner

from tribobem.cli import app

from tribobem.data import topography_path

REPO = Path(__file__).resolve().parents[1]
#: The measured Park AFM scan shipped with tribobem (tribobem.data; no skip: it is always there).
PARK = topography_path("example_ps.tiff")
EXAMPLES = sorted((REPO / "examples").glob("*.toml"))

runner = CliRunner()


def invoke(*args):
    return runner.invoke(app, [str(a) for a in args], catch_exceptions=False)


def _one_line_error(result):
    out = result.output.strip()
    assert result.exit_code == 2, out
    assert "Traceback" not in out
    assert len(out.splitlines()) == 1, out
    assert out.startswith("error:") or out.startswith("memory:"), out
    return out


def test_help_lists_the_commands():
    r = invoke("--help")
    assert r.exit_code == 0
    for cmd in ("demo", "run", "sweep", "validate", "info", "plot"):
        assert cmd in r.output


def test_demo_small(tmp_path):
    out = tmp_path / "demo"
    r = invoke("demo", "--small", "--out", out, "--quiet")
    assert r.exit_code == 0, r.output
    assert (out / "report.html").is_file() and (out / "summary.json").is_file() and (out / "fields.nc").is_file()
    assert str(out / "report.html") in r.output
    s = json.loads((out / "summary.json").read_text())
    assert s["kind"] == "pulloff" and s["pull_off_force"] is not None and s["pull_off_force"] <= 0
    assert s["inputs"]["grid"]["n"] == 32
    # the key result and its resolution in one line: the tiny grid does not resolve the zone
    line = [x for x in r.output.splitlines() if x.startswith("pull-off")]
    assert len(line) == 1 and "Maugis-Dugdale" in line[0] and "NOT resolved" in line[0]


def test_demo_needs_no_input_files():
    import tribobem.cli as cli

    sc, where = cli.demo_scenario()
    assert "roughness" not in sc["body1"] and "roughness" not in sc["body2"]
    from tribobem.scenario import parse_scenario

    parsed = parse_scenario(sc)
    assert parsed.kind == "pulloff" and parsed.load.preload is None
    assert parsed.expected.values["pull_off_force"] == pytest.approx(-0.25e-6, rel=1e-3)


def test_demo_is_resolved_and_meets_maugis_dugdale(tmp_path):
    """The full demo (128^2, ~5 s of solving): no resolution warning, pull-off within its stated
    3 % of Maugis-Dugdale, and the line says so."""
    out = tmp_path / "demo"
    r = invoke("demo", "--out", out, "--quiet")
    assert r.exit_code == 0, r.output
    s = json.loads((out / "summary.json").read_text())
    assert s["warnings"] == [] and s["expected"]["met"]
    assert s["cohesive_zone_cells"] > 8
    assert "cohesive zone" in r.output and ": resolved)" in r.output
    # the softened Dugdale law (the default) has one equilibrium per state: no band of edge
    # equilibria to report, and the pull-off is Maugis-Dugdale's to 1 % (+0.2 % measured; the
    # step law's +2.0 % lay inside its own 3.2 % band)
    assert "cohesive_edge" not in s and "grid band" not in r.output
    assert abs(s["expected"]["values"][0]["relative_error"]) < 0.01
    assert s["problem"]["softening_width"] > 0


def _write(tmp_path, text, name="s.toml"):
    p = tmp_path / name
    p.write_text(text)
    return p


GOOD = """
kind = "normal"
[grid]
n = 16
size = "0.5 um"
[body1]
E = "130 GPa"
nu = 0.28
[body2]
rigid = true
shape = { kind = "sphere", radius = "10 um" }
[load]
forces = ["1 uN", "2 uN"]
[output]
figures = false
"""


def test_run_json_and_outputs(tmp_path):
    p = _write(tmp_path, GOOD)
    out = tmp_path / "res"
    r = runner.invoke(app, ["run", str(p), "--out", str(out), "--json"])
    assert r.exit_code == 0, r.output
    s = json.loads(r.stdout)
    assert s["kind"] == "normal" and len(s["steps"]) == 2 and s["converged"] is True
    assert (out / "summary.json").is_file() and (out / "fields.nc").is_file()


def test_run_prints_a_table(tmp_path):
    p = _write(tmp_path, GOOD)
    r = invoke("run", p, "--out", tmp_path / "res2")
    assert r.exit_code == 0, r.output
    assert "tribobem normal run" in r.output and "report" in r.output


@pytest.mark.parametrize(
    "text, words",
    [
        (GOOD.replace('n = 16', 'n = 16\ncolour = "red"'), ["grid.colour", "unknown key", "allowed keys"]),
        (GOOD.replace('forces = ["1 uN", "2 uN"]', 'force = "3 nm"'), ["load.force", "expected a force (N)", "3 nm"]),
        (GOOD.replace("nu = 0.28", "nu = 0.8"), ["body1.nu", "(-1, 0.5]"]),
        (GOOD.replace('kind = "normal"', 'kind = "capillary"').replace(
            'forces = ["1 uN", "2 uN"]', 'force = "1 uN"\n[humidity]\nrh = [1.5]'),
         ["humidity.rh[0]", "(0, 1]"]),
        ("kind = \n", ["not valid TOML"]),
        (GOOD.replace("n = 16", "n = 131072"), ["GiB"]),
    ],
)
def test_bad_scenarios_exit_2_with_one_line(tmp_path, text, words):
    p = _write(tmp_path, text)
    msg = _one_line_error(runner.invoke(app, ["run", str(p), "--out", str(tmp_path / "res")]))
    for w in words:
        assert w in msg, msg


def test_missing_files_exit_2(tmp_path):
    assert "not found" in _one_line_error(runner.invoke(app, ["run", str(tmp_path / "nope.toml")]))
    assert "not found" in _one_line_error(runner.invoke(app, ["info", str(tmp_path / "nope.tiff")]))
    assert "not found" in _one_line_error(runner.invoke(app, ["plot", str(tmp_path / "nope")]))
    assert "not found" in _one_line_error(runner.invoke(app, ["sweep", str(tmp_path / "nope.toml")]))
    p = _write(tmp_path, GOOD.replace('[body2]', '[body2]\nroughness = { kind = "file", path = "missing.tiff" }'))
    assert "missing.tiff" in _one_line_error(runner.invoke(app, ["run", str(p), "--out", str(tmp_path / "r")]))


def test_unreadable_topography_exits_2(tmp_path):
    bad = tmp_path / "bad.tiff"
    bad.write_bytes(b"\x00not an image")
    msg = _one_line_error(runner.invoke(app, ["info", str(bad)]))
    assert "bad.tiff" in msg


def test_info_on_the_park_scan():
    r = invoke("info", PARK, "--json")
    assert r.exit_code == 0, r.output
    d = json.loads(r.stdout)
    assert d["grid"] == [512, 512]
    assert d["physical_size"][0] == pytest.approx(1e-6)
    assert d["rms_height"] == pytest.approx(3.933e-9, rel=0.01)  # tribobem/data/topographies/README.md
    assert d["rms_slope"] == pytest.approx(0.385, rel=0.05)
    for key in ("skewness", "kurtosis", "correlation_length", "unit"):
        assert key in d
    r = invoke("info", PARK)
    assert r.exit_code == 0 and "rms height" in r.output and "correlation length" in r.output


def test_plot_remakes_the_report(tmp_path):
    p = _write(tmp_path, GOOD.replace("figures = false", "figures = true"))
    out = tmp_path / "res"
    assert invoke("run", p, "--out", out, "--quiet").exit_code == 0
    (out / "report.html").unlink()
    r = invoke("plot", out)
    assert r.exit_code == 0, r.output
    assert (out / "report.html").is_file() and "pressure" in r.output


class _Row:
    def __init__(self, case, passed):
        self.case, self.quantity, self.reference, self.computed = case, "a", 1.0, 1.0 if passed else 1.5
        self.rel_error, self.tolerance, self.passed = (0.0 if passed else 0.5), 0.01, passed


@pytest.fixture
def fake_validation(monkeypatch):
    import sys
    import types

    mod = types.ModuleType("tribobem.validation")
    state = {"rows": [_Row("hertz", True)]}
    def run_validation(quick=True, cases=None, progress=None, *, level=None, physics=None):
        state["calls"].append({"level": level, "cases": cases, "physics": physics})
        return state["rows"]

    mod.run_validation = run_validation
    state["calls"] = []
    monkeypatch.setitem(sys.modules, "tribobem.validation", mod)
    return state


def test_validate_table_json_and_exit_codes(fake_validation):
    r = invoke("validate", "--quick")
    assert r.exit_code == 0 and "hertz" in r.output and "pass" in r.output
    r = runner.invoke(app, ["validate", "--json"])
    assert r.exit_code == 0 and json.loads(r.stdout)["rows"][0]["case"] == "hertz"
    fake_validation["rows"].append(_Row("jkr", False))
    r = invoke("validate", "--full")
    assert r.exit_code == 1 and "FAIL" in r.output
    assert fake_validation["calls"][-1] == {"level": "full", "cases": None, "physics": None}


def test_validate_ci_tier_by_physics(fake_validation, monkeypatch):
    import sys
    import time

    r = invoke("validate", "--ci", "--physics", "adhesion", "--physics", "studies", "--case", "guduru")
    assert r.exit_code == 0 and "tribobem validation (ci: adhesion, studies)" in r.output
    assert fake_validation["calls"][-1] == {"level": "ci", "cases": ["guduru"], "physics": ["adhesion", "studies"]}
    # the reported times are those of the validation run: let the fake burn 0.2 s of CPU
    mod = sys.modules["tribobem.validation"]
    fake = mod.run_validation

    def busy(**kw):
        c0 = time.process_time()
        while time.process_time() - c0 < 0.2:
            pass
        return fake(**kw)

    monkeypatch.setattr(mod, "run_validation", busy)
    d = json.loads(runner.invoke(app, ["validate", "--ci", "--json"]).stdout)
    assert d["level"] == "ci" and d["passed"]
    assert 0.2 <= d["cpu_time"] < 5 and 0.1 < d["wall_time"] < 5


#: Examples whose run takes minutes: their CLI run is a slow test (test_examples.SLOW holds their
#: expectation checks); and the materials examples, whose CLI path is the other examples' (their
#: expectations are checked by test_examples in the default run: the default run's time budget).
SLOW_EXAMPLES = {"pulloff_afm_park_levels", "normal_yielding_rough", "normal_coated_paper_c", "stresses_paper_d_ball"}


@pytest.mark.parametrize("example", [pytest.param(e, marks=[pytest.mark.slow] if e.stem in SLOW_EXAMPLES else [])
                                     for e in EXAMPLES], ids=[e.stem for e in EXAMPLES])
def test_every_example_runs(example):
    from tribobem.scenario import run_scenario

    r = run_scenario(example, outdir=None, progress=False)
    assert r.converged, r.summary["warnings"]
    assert r.steps


def test_examples_exist():
    names = {e.stem for e in EXAMPLES}
    assert {"hertz_free_boundary", "rough_periodic", "afm_park_normal", "pulloff_sphere"} <= names


# --------------------------------------------------------------------------------------
# CLI polish (issue 9 item 5): --version, info on .npy, nan correlation length, piped
# tables, boolean flags
# --------------------------------------------------------------------------------------

def _cli(*args, env=None):
    """Run the CLI in a subprocess (stdout is a pipe, not a terminal)."""
    import subprocess
    import sys

    return subprocess.run([sys.executable, "-m", "tribobem.cli", *map(str, args)], capture_output=True, text=True,
                          env={**os.environ, **(env or {})}, timeout=300)


def test_version_prints_package_and_solver_version():
    from importlib.metadata import version

    from tribobem._solver_version import SOLVER_VERSION

    r = invoke("--version")
    assert r.exit_code == 0
    assert r.output.strip() == f"tribobem {version('tribobem')} (solver version {SOLVER_VERSION})"
    p = _cli("--version")
    assert p.returncode == 0 and p.stdout.strip() == r.output.strip()


def _npy(tmp_path, heights, name="h.npy"):
    import numpy as np

    path = tmp_path / name
    np.save(path, np.asarray(heights, dtype=float))
    return path


def test_info_reads_npy_with_size_and_unit(tmp_path):
    import numpy as np

    rng = np.random.default_rng(3)
    h = rng.normal(size=(64, 32))                      # in nm
    path = _npy(tmp_path, h)
    # --detrend center: the mean only, so that the rms is numpy's std (the default removes the plane)
    r = invoke("info", path, "--size", "10 um,5 um", "--unit", "nm", "--detrend", "center", "--json")
    assert r.exit_code == 0, r.output
    d = json.loads(r.stdout)
    assert d["grid"] == [64, 32]
    assert d["physical_size"] == pytest.approx([10e-6, 5e-6], rel=1e-12)
    assert d["pixel_size"] == pytest.approx([10e-6 / 64, 5e-6 / 32], rel=1e-12)
    assert d["rms_height"] == pytest.approx(np.std(h) * 1e-9, rel=1e-9)   # mean removed ("center")
    # one length: a square scan; the size in another unit than the heights
    d = json.loads(invoke("info", path, "--size", "0.002 mm", "--unit", "um", "--detrend", "center",
                          "--json").stdout)
    assert d["physical_size"] == pytest.approx([2e-6, 2e-6], rel=1e-12)
    assert d["rms_height"] == pytest.approx(np.std(h) * 1e-6, rel=1e-9)
    # what is missing is named with the option that gives it
    assert "--size" in _one_line_error(runner.invoke(app, ["info", str(path), "--unit", "nm"]))
    assert "--unit" in _one_line_error(runner.invoke(app, ["info", str(path), "--size", "10 um"]))
    assert "no unit" in _one_line_error(runner.invoke(app, ["info", str(path), "--size", "10", "--unit", "nm"]))
    assert "info.size" in _one_line_error(runner.invoke(app, ["info", str(path), "--size", "1 um,2 um,3 um",
                                                              "--unit", "nm"]))


def test_nan_correlation_length_comes_with_reason_and_detrend_hint(tmp_path):
    import numpy as np

    from tribobem.geometry.stats import correlation_length
    from tribobem.grid import Grid

    # short-correlated roughness (rms 1 nm) on a tilt of 100 nm over the scan: with the mean
    # removed only (--detrend center), the tilt dominates the autocorrelation, which never falls
    # below 10 % (the default, the plane, removes the tilt)
    rng = np.random.default_rng(0)
    n, L = 128, 1e-6
    rough = rng.normal(size=(n, n))
    rough = (rough + np.roll(rough, 1, 0) + np.roll(rough, 1, 1) + np.roll(rough, 1, (0, 1))) / 2.0
    x = np.arange(n) / n
    h = rough + 100.0 * x[:, None] + 0.0 * x[None, :]    # nm
    path = _npy(tmp_path, h)
    args = ("info", path, "--size", "1 um", "--unit", "nm", "--detrend", "center")
    d = json.loads(invoke(*args, "--json").stdout)
    assert d["correlation_length"] is None
    note = d["correlation_length_note"]
    assert "10 %" in note and "half the scan" in note and "trend" in note and "--detrend height" in note
    # the hint's value is the correlation length with that detrending
    d2 = json.loads(invoke(*args, "--json", "--detrend", "height").stdout)
    plane = d2["correlation_length"]
    assert plane is not None and "correlation_length_note" not in d2
    from tribobem.units import format_quantity

    assert format_quantity(plane, "length") in note
    g = Grid(n, n, L, L)
    hp = (rough - rough.mean()) * 1e-9
    assert plane == pytest.approx(correlation_length(hp - hp.mean(), g), rel=0.05)  # the roughness' own
    r = invoke(*args)
    assert r.exit_code == 0 and "nan (see the note below)" in r.output and "note:" in r.output
    # a finite correlation length has no note; a flat surface says so
    assert "correlation_length_note" not in json.loads(invoke("info", path, "--size", "1 um", "--unit", "nm",
                                                              "--detrend", "curvature", "--json").stdout)
    flat = _npy(tmp_path, np.zeros((16, 16)), "flat.npy")
    d = json.loads(invoke("info", flat, "--size", "1 um", "--unit", "nm", "--json").stdout)
    assert "flat" in d["correlation_length_note"]


def test_tables_are_not_truncated_when_stdout_is_not_a_terminal(fake_validation, tmp_path):
    long_quantity = "a quantity whose description is much longer than any terminal " * 3
    row = _Row("hertz", True)
    row.quantity = long_quantity.strip()
    fake_validation["rows"][:] = [row]
    r = invoke("validate")
    assert r.exit_code == 0
    assert row.quantity in r.output and "\u2026" not in r.output   # whole, on one line, no ellipsis
    # a real pipe with a narrow $COLUMNS: every row of the info table whole
    import numpy as np

    path = _npy(tmp_path, np.random.default_rng(1).normal(size=(32, 32)))
    p = _cli("info", path, "--size", "1 um", "--unit", "nm", env={"COLUMNS": "30"})
    assert p.returncode == 0, p.stderr
    lines = [line for line in p.stdout.splitlines() if "pixel size" in line]
    assert len(lines) == 1 and "31.25 nm x 31.25 nm" in lines[0]


def test_boolean_options_are_flags_shown_as_flags():
    """Every boolean option of every command (but the demo's, declared with it) is a
    --flag/--no-flag pair; no help shows a value type beside a flag."""
    import inspect

    checked = 0
    for info in app.registered_commands:
        name = info.name or info.callback.__name__.replace("_", "-")
        text = runner.invoke(app, [name, "--help"]).output
        assert "<bool>" not in text and "BOOLEAN" not in text, (name, text)
        if name == "demo":
            continue
        for param in inspect.signature(info.callback).parameters.values():
            if param.annotation in (bool, "bool"):
                decls = param.default.param_decls
                assert "/" in decls[0], f"{name} {decls}: a boolean option must be a --flag/--no-flag pair"
                long_names = [d.strip() for d in decls[0].split("/")]
                assert " / ".join(long_names) in text, (name, long_names)
                checked += 1
    assert checked >= 12
    assert "--quick / --full" in invoke("validate", "--help").output


def test_boolean_flags_are_accepted_with_their_negative(tmp_path):
    p = _write(tmp_path, GOOD)
    r = runner.invoke(app, ["run", str(p), "--out", str(tmp_path / "a"), "--json", "--no-json", "--quiet"])
    assert r.exit_code == 0, r.output
    assert not r.stdout.lstrip().startswith("{")       # --no-json after --json: no JSON
    r = runner.invoke(app, ["run", str(p), "--out", str(tmp_path / "b"), "--no-quiet"])
    assert r.exit_code == 0 and "tribobem normal run" in r.output
    r = runner.invoke(app, ["run", str(p), "--out", str(tmp_path / "c"), "--quiet", "true"])
    assert r.exit_code == 2                            # a flag takes no value


def test_run_says_how_many_rows_it_hides_and_whether_expected_was_met(tmp_path):
    """A step table longer than 30 rows says how many it hides (the pull-off example has 34
    steps), and ``run`` prints whether the scenario's ``expected`` was met, with the values."""
    example = Path(__file__).resolve().parents[1] / "examples" / "pulloff_sphere.toml"
    r = invoke("run", str(example), "-o", str(tmp_path / "ps"))
    assert r.exit_code == 0, r.output
    n = len(json.loads((tmp_path / "ps" / "summary.json").read_text())["steps"])
    assert n > 30
    assert f"{n - 30} hidden" in r.output and f"{n - 30} of {n} steps hidden above" in r.output
    line = next(ln for ln in r.output.splitlines() if ln.startswith("expected"))
    assert "within 3 %" in line and ": met;" in line and "pull_off_force = " in line and " against -2.5e-07" in line


# --------------------------------------------------------------------------------------
# info on measured scans: the plane removed by default, correlation lengths, --plot
# --------------------------------------------------------------------------------------

def _tilted_npy(tmp_path, n=64):
    """Roughness (rms ~1 nm, in nm) with no plane in it, on a tilt of ~60 nm over a 1 um scan."""
    import numpy as np

    from tribobem.geometry import detrend_heights
    from tribobem.grid import Grid

    g = Grid(n, n, 1e-6, 1e-6)
    rough = detrend_heights(np.random.default_rng(4).normal(size=g.shape), g, "height")
    x = (np.arange(n) + 0.5) / n
    return _npy(tmp_path, rough + 50.0 * x[:, None] - 30.0 * x[None, :] + 7.0, "tilted.npy"), rough


def test_info_default_detrend_is_the_plane(tmp_path):
    import numpy as np

    path, rough = _tilted_npy(tmp_path)
    d = json.loads(invoke("info", path, "--size", "1 um", "--unit", "nm", "--json").stdout)
    assert d["detrend"] == "height"
    assert d["rms_height"] == pytest.approx(1e-9 * np.sqrt(np.mean(rough**2)), rel=1e-6)
    assert "correlation_length_note" not in d and d["correlation_length"] is not None
    c = json.loads(invoke("info", path, "--size", "1 um", "--unit", "nm", "--detrend", "center", "--json").stdout)
    assert c["rms_height"] > 10 * d["rms_height"]   # the tilt, kept by "center"
    r = invoke("info", path, "--size", "1 um", "--unit", "nm")
    assert r.exit_code == 0
    (row,) = [line for line in r.output.splitlines() if " detrend " in line]
    assert "height" in row


#: tribobem/data/topographies/README.md, plane removed: rms height (m), correlation length (m).
SHIPPED_PLANE = {
    "example_ps.tiff": (3.933e-9, 40.00e-9),
    "di-3.di": (35.22e-9, 1.511e-6),
    "spot_1-1000nm.ibw": (9.552e-9, 945.2e-9),
    "plu-1.plu": (18.28e-9, 185.9e-6),
}


@pytest.mark.parametrize("name", sorted(SHIPPED_PLANE))
def test_info_gives_a_correlation_length_on_each_shipped_file(name):
    rms, corr = SHIPPED_PLANE[name]
    d = json.loads(invoke("info", f"data:{name}", "--json").stdout)
    assert d["rms_height"] == pytest.approx(rms, rel=0.005)
    assert d["correlation_length"] == pytest.approx(corr, rel=0.005)
    assert "correlation_length_note" not in d
    assert d["correlation_length"] < 0.5 * min(d["physical_size"])


def test_info_plot_writes_four_pngs_and_a_self_contained_page(tmp_path, monkeypatch):
    import re

    path, _ = _tilted_npy(tmp_path, n=48)
    out = tmp_path / "plots"
    r = invoke("info", path, "--size", "1 um", "--unit", "nm", "--plot", "--out", out)
    assert r.exit_code == 0, r.output
    names = ("height_map.png", "height_distribution.png", "psd.png", "acf.png")
    for name in names:
        p = out / name
        assert p.is_file() and p.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" and p.stat().st_size > 10_000
        assert str(p) in r.output          # the paths are printed
    page = (out / "topography.html").read_text(encoding="utf-8")
    assert str(out / "topography.html") in r.output
    assert len(re.findall(r"<img [^>]*src='data:image/png;base64,", page)) == 4
    assert "http://" not in page and "https://" not in page
    # --json lists them; without --out they go to results/topography_<stem>
    monkeypatch.chdir(tmp_path)
    d = json.loads(invoke("info", path, "--size", "1 um", "--unit", "nm", "--plot", "--json").stdout)
    assert set(d["plots"]) == {"height_map", "height_distribution", "psd", "acf", "html"}
    assert Path(d["plots"]["html"]) == Path("results") / "topography_tilted" / "topography.html"
    assert (tmp_path / "results" / "topography_tilted" / "psd.png").is_file()
