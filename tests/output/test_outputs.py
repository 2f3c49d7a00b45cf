"""Result folders: summary.json (9.1 keys, strict JSON), fields.nc (xarray, dims, units),
figures, report.html (embedded images), atomic writes, re-plotting."""

import base64
import json
import math
from pathlib import Path

import numpy as np
import pytest

from tribobem.output import REQUIRED_KEYS, STEP_KEYS, read_fields, read_summary, replot, write_summary
from tribobem.output.fields import write_fields
from tribobem.output.atomic import atomic_write_text
from tribobem.output.summary import jsonable
from tribobem.scenario import run_scenario

NORMAL = {
    "kind": "normal",
    "name": "outputs test",
    "grid": {"n": 24, "size": "0.5 um"},
    "body1": {"E": "130 GPa", "nu": 0.28},
    "body2": {"rigid": True, "shape": {"kind": "sphere", "radius": "10 um"}},
    "load": {"forces": ["1 uN", "2 uN"]},
    "adhesion": {"work_of_adhesion": "50 mJ/m^2", "z0": "0.3 nm"},
}
PULLOFF = {
    "kind": "pulloff",
    "grid": {"n": 24, "size": "0.4 um"},
    "body1": {"E": "5 GPa", "nu": 0.0,
              "roughness": {"kind": "gaussian", "rms": "0.2 nm", "correlation_length": "40 nm", "seed": 1}},
    "body2": {"rigid": True, "shape": {"kind": "sphere", "radius": "1 um"}},
    "adhesion": {"work_of_adhesion": "50 mJ/m^2", "z0": "0.5 nm"},
    "load": {"preload": "0.3 uN", "steps": 8, "refine": 2},
    "solver": {"tolerance": 1e-8},
}


@pytest.fixture(scope="module")
def normal_run(tmp_path_factory):
    out = tmp_path_factory.mktemp("normal")
    return run_scenario(NORMAL, outdir=out, progress=False)


@pytest.fixture(scope="module")
def pulloff_run(tmp_path_factory):
    out = tmp_path_factory.mktemp("pulloff")
    return run_scenario(PULLOFF, outdir=out, progress=False)


def _no_temp_files(folder: Path):
    return [p.name for p in Path(folder).iterdir() if p.name.startswith(".") or p.suffix == ".tmp"]


@pytest.mark.parametrize("which", ["normal_run", "pulloff_run"])
def test_summary_has_the_91_keys(which, request):
    r = request.getfixturevalue(which)
    s = json.loads((r.outdir / "summary.json").read_text())  # strict JSON (no NaN)
    assert set(REQUIRED_KEYS) <= set(s)
    assert s["kind"] == r.summary["kind"]
    assert isinstance(s["converged"], bool)
    assert {"tribobem", "numpy", "scipy", "python"} <= set(s["versions"])
    assert {"build", "solve", "output", "total"} <= set(s["timings"])
    assert s["steps"] and all(set(STEP_KEYS) <= set(step) for step in s["steps"])
    assert s["inputs"]["grid"]["n"] == 24  # the parsed scenario, SI
    assert s["inputs"]["adhesion"]["work_of_adhesion"] == pytest.approx(0.05)
    assert read_summary(r.outdir) == s


def test_pulloff_summary_has_the_run_level_scalar(pulloff_run):
    s = read_summary(pulloff_run.outdir)
    assert s["pull_off_force"] < 0
    assert s["pull_off_approach"] is not None
    assert [st["branch"] for st in s["steps"]][-1] == "unloading"


@pytest.mark.parametrize("which, nsteps", [("normal_run", 2), ("pulloff_run", 2)])
def test_fields_nc_is_readable_with_dims_and_units(which, nsteps, request):
    import xarray as xr

    r = request.getfixturevalue(which)
    with xr.open_dataset(r.outdir / "fields.nc") as ds:
        assert ds["pressure"].dims == ("step", "x", "y")
        assert ds.sizes["step"] == nsteps and ds.sizes["x"] == 24 and ds.sizes["y"] == 24
        for name, unit in (("pressure", "Pa"), ("gap", "m"), ("displacement", "m"), ("initial_gap", "m"),
                           ("x", "m"), ("y", "m")):
            assert ds[name].attrs["units"] == unit
        assert set(np.unique(ds["contact"].values)) <= {0, 1}
        assert "adhesive" in ds and "normal_force" in ds.coords and "label" in ds.coords
        assert ds["x"].values[-1] - ds["x"].values[0] == pytest.approx(ds.attrs["dx"] * 23)
        np.testing.assert_allclose(ds["pressure"].values, np.stack([res.pressure for res in r.results]))


def test_pulloff_fields_hold_preload_and_pulloff_states(pulloff_run):
    ds = read_fields(pulloff_run.outdir)
    assert list(ds["label"].values) == ["preload", "pull-off"]
    assert "roughness_body1" in ds
    assert ds["normal_force"].values[1] == pytest.approx(read_summary(pulloff_run.outdir)["pull_off_force"], rel=0.05)


@pytest.mark.parametrize("which, figures", [
    ("normal_run", ["force_curve", "pressure", "contact", "profile", "topography"]),
    ("pulloff_run", ["force_curve", "pressure", "contact", "profile", "pressure_pulloff", "contact_pulloff", "topography"]),
])
def test_figures_and_report(which, figures, request):
    r = request.getfixturevalue(which)
    for name in figures:
        png = r.outdir / f"{name}.png"
        assert png.is_file() and png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n", name
    html = (r.outdir / "report.html").read_text()
    assert html.count("data:image/png;base64,") == len(figures)
    first = html.split("data:image/png;base64,")[1].split("'")[0]
    assert base64.b64decode(first)[:4] == b"\x89PNG"
    assert "Converged" in html and "Inputs" in html and "numpy" in html
    assert "<img" in html and "src='report" not in html  # nothing external
    assert not _no_temp_files(r.outdir)


def test_nonconverged_run_shows_a_warning_in_the_report(tmp_path):
    sc = dict(NORMAL, load={"force": "1 uN"}, solver={"max_iterations": 2, "tolerance": 1e-14})
    with pytest.warns(Warning):
        r = run_scenario(sc, outdir=tmp_path, progress=False)
    assert read_summary(tmp_path)["converged"] is False
    html = (tmp_path / "report.html").read_text()
    assert "class='warn'" in html and "not converged" in html
    assert not (tmp_path / "force_curve.png").exists()  # one step: no curve
    assert r.files["report"] == tmp_path / "report.html"


def test_replot_remakes_figures_from_the_files(normal_run):
    out = normal_run.outdir
    (out / "pressure.png").unlink()
    (out / "report.html").unlink()
    files = replot(out)
    assert (out / "pressure.png").is_file() and (out / "report.html").is_file()
    assert set(files) >= {"pressure", "report", "force_curve"}


def test_output_fields_none_and_no_figures(tmp_path):
    sc = dict(NORMAL, output={"fields": "none", "figures": False, "report": True})
    run_scenario(sc, outdir=tmp_path, progress=False)
    assert not (tmp_path / "fields.nc").exists() and not list(tmp_path.glob("*.png"))
    assert (tmp_path / "summary.json").is_file() and (tmp_path / "report.html").is_file()


def test_atomic_writes_leave_no_temp_files_on_failure(tmp_path, normal_run):
    # a summary that cannot be serialised fails before the target is touched
    target = tmp_path / "summary.json"
    target.write_text("{}")
    write_summary(target, {"kind": "x", "value": float("nan")})  # NaN -> null, strict JSON
    assert json.loads(target.read_text())["value"] is None

    class Boom:
        def __init__(self):
            self.data_vars = {}

        def to_netcdf(self, path, **kw):
            Path(path).write_bytes(b"partial")
            raise OSError("disk full")

    with pytest.raises(OSError, match="disk full"):
        write_fields(Boom(), tmp_path / "fields.nc")
    assert not (tmp_path / "fields.nc").exists()
    assert not _no_temp_files(tmp_path)
    # an existing file is replaced whole
    atomic_write_text(tmp_path / "a.txt", "old")
    atomic_write_text(tmp_path / "a.txt", "new")
    assert (tmp_path / "a.txt").read_text() == "new" and not _no_temp_files(tmp_path)


def test_jsonable_handles_numpy_and_non_finite():
    out = jsonable({"a": np.float64(1.5), "b": np.int32(3), "c": np.array([1.0, np.inf]), "d": np.bool_(True),
                    "e": math.nan, "f": Path("x")})
    assert out == {"a": 1.5, "b": 3, "c": [1.0, None], "d": True, "e": None, "f": "x"}


def test_report_rounds_off_zero_hides_no_rows_silently_and_times_only_what_it_knows():
    """Round-off below 1e-9 of a column prints as 0; a table cut at 200 rows says how many it
    hides; the time row leaves output and total to summary.json (the report is written first)."""
    from tribobem.output.report import render_report

    steps = [{"index": i, "branch": "loading", "converged": True, "normal_force": 1e-6,
              "tangential_force_x": (4.171e-22 if i == 0 else 1e-7 * i)} for i in range(250)]
    html = render_report({"kind": "partial_slip", "converged": True, "steps": steps,
                          "timings": {"build": 0.5, "solve": 2.0, "output": 0.0, "total": 2.5}})
    assert "417.1 aN" not in html and "aN" not in html
    assert "50 steps hidden (summary.json has every step)" in html
    assert "build 0.50 s, solve 2.00 s (output and total time: summary.json)" in html


def test_report_has_a_computed_against_expected_section(tmp_path):
    """The scenario's expected values are in the report, met or not, in units, not only in the
    raw inputs JSON."""
    from pathlib import Path

    from tribobem.scenario import run_scenario

    example = Path(__file__).resolve().parents[2] / "examples" / "pulloff_sphere.toml"
    r = run_scenario(str(example), outdir=tmp_path / "ps", progress=False)
    html = (tmp_path / "ps" / "report.html").read_text()
    assert r.summary["expected"]["met"] and r.summary["expected"]["values"][0]["dimension"] == "force"
    sec = html[html.index("<h2>Computed against expected</h2>"):]
    assert "<span class='met'>met</span>" in sec[:600] and "pull_off_force" in sec and "-250 nN" in sec
