"""Sweeps: spec parsing, resumability, atomic point files, gathering, failures, Dask."""

from __future__ import annotations

import csv
import json
import math
import time
from pathlib import Path

import numpy as np
import pytest

from tribobem.errors import InputError
from tribobem.sweep import SweepSpec, point_hash, read_points, run_sweep, sweep_command


def _calls(folder: Path) -> list[str]:
    return sorted(p.name for p in folder.glob("*.call"))


def make_func(counter: Path, interrupt_at: int | None = None, fail_x=None, flag: Path | None = None):
    """A cheap point function that leaves a file per completed call in ``counter``.

    ``interrupt_at``: the n-th call (1-based) raises KeyboardInterrupt, as a Ctrl-C would,
    if ``flag`` exists (and removes it).  ``fail_x``: points with that x raise ValueError while ``flag``
    exists.
    """
    counter.mkdir(parents=True, exist_ok=True)

    def func(point):
        n = len(list(counter.glob("*"))) + 1
        armed = flag is not None and flag.exists()
        if armed and interrupt_at is not None and n == interrupt_at:
            flag.unlink()  # only once
            raise KeyboardInterrupt
        if armed and fail_x is not None and point["x"] == fail_x:
            raise ValueError(f"x = {fail_x} is not allowed today")
        (counter / f"x{point['x']}_y{point['y']}.call").write_text(json.dumps(point))
        return {"sum": float(point["x"]) + float(str(point["y"]).split()[0]), "flag": True}

    return func


SPEC = {"name": "toy", "function": "builtins:dict",
        "parameters": {"x": [1, 2, 3], "y": [10, 20]}, "outputs": ["sum"]}


def _no_tmp(outdir: Path):
    left = [p for p in outdir.rglob("*") if p.name.endswith(".tmp")]
    assert not left, f"temporary files left behind: {left}"


def test_spec_from_file_with_scenario_and_points(tmp_path):
    (tmp_path / "sub").mkdir()
    (tmp_path / "sub" / "base.toml").write_text('kind = "pulloff"\n[grid]\nn = 32\nsize = "1 um"\n')
    (tmp_path / "sweep.toml").write_text(
        'scenario = "sub/base.toml"\noutputs = ["pull_off_force"]\n'
        '[parameters]\n"adhesion.work_of_adhesion" = ["30 mJ/m^2", "50 mJ/m^2"]\n'
        'grid.n = [32, 64]\n'                      # unquoted dotted key: nested table, flattened
        '[[points]]\n"adhesion.z0" = "0.2 nm"\n[[points]]\nadhesion.z0 = "0.3 nm"\n')
    spec = SweepSpec.from_file(tmp_path / "sweep.toml")
    assert spec.base["grid"]["n"] == 32 and spec.scenario_path.name == "base.toml"
    assert list(spec.parameters) == ["adhesion.work_of_adhesion", "grid.n"]
    assert len(spec) == 8 and not spec.is_grid
    assert spec.overrides()[0] == {"adhesion.z0": "0.2 nm", "adhesion.work_of_adhesion": "30 mJ/m^2", "grid.n": 32}
    scen = spec.scenario_for(spec.overrides()[-1])
    assert scen["grid"] == {"n": 64, "size": "1 um"} and scen["adhesion"]["z0"] == "0.3 nm"
    assert spec.base["grid"]["n"] == 32  # the base is not modified


@pytest.mark.parametrize("data, field", [
    ({"function": "builtins:dict", "parameters": {"x": [1]}, "bogus": 1}, "sweep.bogus"),
    ({"parameters": {"x": [1]}}, "sweep.scenario"),
    ({"function": "builtins:dict", "parameters": {"x": []}}, "parameters.x"),
    ({"function": "builtins:dict", "parameters": {"x": [1, 1]}}, "parameters.x"),
    ({"base": {"kind": "normal"}, "parameters": {"nonsense.key": [1, 2]}}, "parameters.nonsense.key"),
    ({"function": "builtins:dict", "parameters": {"x": [1]}, "points": [{"x": 2}]}, "points[0].x"),
    ({"function": "nomodule", "parameters": {"x": [1]}}, "sweep.function"),
])
def test_spec_errors_name_the_field(data, field):
    with pytest.raises(InputError) as err:
        SweepSpec.from_dict(data)
    assert field in str(err.value)


def test_point_hash_is_stable_and_order_free():
    a = point_hash("scenario", {"grid": {"n": 8, "size": 1.0}}, {"x": 1, "y": "2 nm"})
    b = point_hash("scenario", {"grid": {"size": 1.0, "n": 8}}, {"y": "2 nm", "x": 1})
    assert a == b and len(a) == 16
    assert a != point_hash("scenario", {"grid": {"n": 16, "size": 1.0}}, {"x": 1, "y": "2 nm"})


def test_resume_after_interrupt_computes_only_missing_points(tmp_path, capsys):
    out, counter, flag = tmp_path / "out", tmp_path / "calls", tmp_path / "armed"
    flag.write_text("1")
    func = make_func(counter, interrupt_at=3, flag=flag)
    assert not list(out.glob("points/*")) if out.exists() else True
    with pytest.raises(KeyboardInterrupt):
        run_sweep(SPEC, out, scheduler="synchronous", func=func, progress=False)
    assert len(read_points(out)) == 2 and len(_calls(counter)) == 2  # finished points kept
    _no_tmp(out)
    first = set(_calls(counter))
    for f in counter.glob("*.call"):
        f.unlink()
    res = run_sweep(SPEC, out, scheduler="synchronous", func=func, progress=True, quiet=False)
    assert "2 of 6 points done, running 4" in capsys.readouterr().err
    assert (res.n_done_before, res.n_run, res.n_ok, res.n_failed) == (2, 4, 6, 0)
    assert not (first & set(_calls(counter))) and len(_calls(counter)) == 4  # each point once
    res = run_sweep(SPEC, out, scheduler="synchronous", func=func, progress=False)
    assert res.n_run == 0 and res.complete and res.exit_code == 0
    _no_tmp(out)


def test_results_files_full_grid(tmp_path):
    import xarray as xr

    spec = SweepSpec.from_dict({"function": "builtins:dict", "outputs": ["E", "n"],
                                "parameters": {"E": ["80 GPa", "120 GPa"], "n": [8, 16, 32]}})
    t0 = time.perf_counter()
    res = run_sweep(spec, tmp_path, scheduler="synchronous", progress=False)
    wall = time.perf_counter() - t0
    assert res.complete and res.n_run == 6
    with xr.open_dataset(tmp_path / "results.nc") as ds:
        assert ds["out.E"].dims == ("E", "n") and ds["out.E"].shape == (2, 3)  # echoed inputs renamed
        assert ds.coords["E"].values.tolist() == [8e10, 1.2e11]  # SI coordinates
        assert ds.coords["E"].attrs["units"] == "kilogram / meter / second ** 2"
        assert float(ds["out.E"].sel(E=1.2e11, n=16)) == 1.2e11  # the function got SI floats
        assert float(ds["out.n"].sel(E=8e10, n=32)) == 32
        assert (ds["status"].values == "ok").all() and ds.attrs["n_ok"] == 6
    rows = list(csv.DictReader((tmp_path / "results.csv").open()))
    assert [r["n"] for r in rows] == ["8", "16", "32"] * 2
    assert [r["E"] for r in rows] == ["80 GPa"] * 3 + ["120 GPa"] * 3  # as written in the spec
    assert {r["status"] for r in rows} == {"ok"} and float(rows[4]["n"]) == 16.0
    # each point's run time (s): measured, so > 0, and the six together within the sweep's wall time
    elapsed = [float(r["elapsed"]) for r in rows]
    assert all(0 < e < wall for e in elapsed) and sum(elapsed) <= wall
    manifest = json.loads((tmp_path / "sweep.json").read_text())
    assert manifest["n_points"] == 6 and manifest["is_grid"]
    _no_tmp(tmp_path)


def test_failed_point_is_recorded_and_retried(tmp_path):
    import xarray as xr

    out, counter, flag = tmp_path / "out", tmp_path / "calls", tmp_path / "armed"
    flag.write_text("1")
    func = make_func(counter, fail_x=2, flag=flag)
    res = run_sweep(SPEC, out, scheduler="synchronous", func=func, progress=False)
    assert (res.n_ok, res.n_failed, res.exit_code) == (4, 2, 1)
    recs = [r for r in read_points(out).values() if r["status"] == "failed"]
    assert len(recs) == 2 and all("x = 2 is not allowed today" in r["error"] for r in recs)
    assert all(r["point"]["x"] == 2 and "Traceback" in r["traceback"] for r in recs)
    rows = list(csv.DictReader((out / "results.csv").open()))
    failed_rows = [r for r in rows if r["status"] == "failed"]
    assert len(failed_rows) == 2 and failed_rows[0]["sum"] == "" and "ValueError" in failed_rows[0]["error"]
    with xr.open_dataset(out / "results.nc") as ds:
        assert ds["sum"].dims == ("point",) or ds["sum"].dims == ("x", "y")
        assert math.isnan(float(ds["sum"].sel(x=2, y=10)))
        assert float(ds["sum"].sel(x=3, y=20)) == 23.0
    flag.unlink()
    n_before = len(_calls(counter))
    res = run_sweep(SPEC, out, scheduler="synchronous", func=func, progress=False)
    assert (res.n_done_before, res.n_run, res.n_ok, res.n_failed) == (4, 2, 6, 0)
    assert len(_calls(counter)) == n_before + 2
    _no_tmp(out)


def test_partial_run_then_restart(tmp_path):
    """A sweep stopped after some points (as by a kill) resumes with the rest."""
    counter = tmp_path / "calls"
    func = make_func(counter)
    res = run_sweep(SPEC, tmp_path / "o", scheduler="synchronous", func=func, progress=False, max_points=4)
    assert res.n_run == 4 and res.n_ok == 4
    rows = list(csv.DictReader((tmp_path / "o" / "results.csv").open()))
    assert sum(r["status"] == "missing" for r in rows) == 2
    res = run_sweep(SPEC, tmp_path / "o", scheduler="synchronous", func=func, progress=False)
    assert res.n_run == 2 and res.complete and len(_calls(counter)) == 6


def test_explicit_points_give_a_point_dimension(tmp_path):
    spec = SweepSpec.from_dict({"function": "builtins:dict",
                                "points": [{"a": 1, "b": "5 nm"}, {"a": 2, "b": "7 nm"}, {"a": 3, "b": "1 um"}]})
    res = run_sweep(spec, tmp_path, scheduler="synchronous", progress=False)
    ds = res.dataset
    assert ds["out.a"].dims == ("point",) and ds.sizes["point"] == 3
    assert ds.coords["b"].values.tolist() == pytest.approx([5e-9, 7e-9, 1e-6])


def test_sweep_command(tmp_path, capsys, monkeypatch):
    monkeypatch.chdir(tmp_path)
    f = tmp_path / "s.toml"
    f.write_text('function = "builtins:dict"\nscheduler = "synchronous"\n[base]\nc = 1\n[parameters]\nx = [1, 2]\n')
    assert sweep_command(str(f), quiet=True) == 0
    assert (tmp_path / "results" / "s" / "results.nc").is_file()
    assert sweep_command(str(f), out=str(tmp_path / "o2"), json_output=True) == 0
    report = json.loads(capsys.readouterr().out)
    assert report["n_ok"] == 2 and report["n_run"] == 2


def test_local_cluster_one_worker(tmp_path):
    pytest.importorskip("distributed")
    counter = tmp_path / "calls"
    func = make_func(counter)
    t0 = time.perf_counter()
    res = run_sweep(SPEC, tmp_path / "o", n_workers=1, func=func, progress=False)
    assert res.complete and res.n_run == 6 and len(_calls(counter)) == 6
    recs = read_points(tmp_path / "o")
    assert {r["outputs"]["sum"] for r in recs.values()} == {11.0, 21.0, 12.0, 22.0, 13.0, 23.0}
    assert time.perf_counter() - t0 < 60
    _no_tmp(tmp_path / "o")


def test_scenario_sweep_through_run_scenario(tmp_path):
    """The default runner: each point is the base scenario with its dotted keys set."""
    # the default runner; our own module: an ImportError here is a failure, not a skip
    from tribobem.scenario import run_scenario  # noqa: F401
    (tmp_path / "base.toml").write_text(
        'kind = "normal"\n[grid]\nn = 32\nsize = "0.25 um"\nperiodic = false\n'
        '[body1]\nE = "130 GPa"\nnu = 0.28\n[body2]\nrigid = true\n'
        'shape = { kind = "sphere", radius = "10 um" }\n[load]\nforce = "1 uN"\n[solver]\ntolerance = 1e-8\n')
    (tmp_path / "sweep.toml").write_text(
        'scenario = "base.toml"\noutputs = ["contact_area", "normal_force", "converged", "nonexistent"]\n'
        '[parameters]\n"load.force" = ["1 uN", "2 uN"]\n"body1.E" = ["100 GPa", "200 GPa"]\n')
    res = run_sweep(tmp_path / "sweep.toml", tmp_path / "out", scheduler="synchronous", progress=False)
    assert res.complete, res.failed
    ds = res.dataset
    assert ds["contact_area"].dims == ("load.force", "body1.E")
    area = ds["contact_area"].values
    assert (area > 0).all() and area[1, 0] > area[0, 0] and area[0, 0] > area[0, 1]  # Hertz trends
    assert float(ds["normal_force"].sel({"load.force": 2e-6, "body1.E": 1e11})) == pytest.approx(2e-6, rel=1e-6)
    assert (ds["converged"].values == 1).all() and np.isnan(ds["nonexistent"].values).all()


def test_stale_temporary_files_of_a_killed_sweep_are_removed(tmp_path):
    import os

    out = tmp_path / "o"
    (out / "points").mkdir(parents=True)
    stale = out / "points" / ".abc.json.x1.tmp"
    stale.write_text("{half a reco")
    os.utime(stale, (time.time() - 3600, time.time() - 3600))
    fresh = out / ".results.nc.x2.tmp"  # a write in progress (young): left alone
    fresh.write_text("")
    res = run_sweep(SPEC, out, scheduler="synchronous", func=make_func(tmp_path / "c"), progress=False)
    assert res.complete and not stale.exists() and fresh.exists()


def test_a_range_table_in_a_point_stays_a_value():
    from tribobem.sweep import apply_overrides, flatten

    flat = flatten({"friction": {"tangential_forces": {"start": "0 uN", "stop": "1 uN", "num": 3}, "coefficient": 0.2}})
    assert flat == {"friction.tangential_forces": {"start": "0 uN", "stop": "1 uN", "num": 3},
                    "friction.coefficient": 0.2}
    base = {"friction": {"coefficient": 0.1}}
    assert apply_overrides(base, flat)["friction"]["tangential_forces"]["num"] == 3


# --------------------------------------------------------------------------------------
# The hash covers the solver version and the solver options (issue 9 item 5)
# --------------------------------------------------------------------------------------

def test_point_hash_covers_solver_version_and_options(monkeypatch):
    import tribobem._solver_version as sv
    from tribobem.sweep import solver_options

    base, point = {"grid": {"n": 8}}, {"x": 1}
    h = point_hash("scenario", base, point, {"tolerance": 1e-10})
    assert h == point_hash("scenario", base, point, {"tolerance": 1e-10}, solver_version=sv.SOLVER_VERSION)
    assert h != point_hash("scenario", base, point, {"tolerance": 1e-10}, solver_version=sv.SOLVER_VERSION + 1)
    assert h != point_hash("scenario", base, point, {"tolerance": 1e-9})
    monkeypatch.setattr(sv, "SOLVER_VERSION", sv.SOLVER_VERSION + 1)  # read at call time
    assert h != point_hash("scenario", base, point, {"tolerance": 1e-10})
    # scenario runner: the schema's [solver] defaults, overridden by the base and the point
    from tribobem.scenario.schema import SolverSpec

    opts = solver_options("scenario", {"solver": {"tolerance": 1e-8}}, {"solver.max_iterations": 50})
    assert set(opts) == set(SolverSpec.model_fields)
    assert opts["tolerance"] == 1e-8 and opts["max_iterations"] == 50
    assert opts["kernel"] == SolverSpec().kernel and opts["backend"] == SolverSpec().backend
    # function runner: the function's plain keyword defaults that the base and point leave unset
    opts = solver_options("function:tribobem.validation.bisinusoidal:pull_off_point", {"n": 32, "tol": 1e-6}, {})
    assert opts["max_iterations"] == 20000 and opts["kernel"] == "spectral"
    assert "tol" not in opts and "n" not in opts and "dgamma" not in opts  # given, or no default


def test_scenario_points_recompute_when_a_solver_default_changes(monkeypatch):
    import tribobem.sweep.cache as sweep  # the point hashes look the solver defaults up there

    spec = SweepSpec.from_dict({"base": {"kind": "normal", "grid": {"n": 8}}, "parameters": {"grid.n": [8, 16]}})
    before = [h for h, _ in spec.tasks()]
    defaults = sweep._scenario_solver_defaults()
    assert [h for h, _ in spec.tasks()] == before  # stable
    monkeypatch.setattr(sweep, "_scenario_solver_defaults", lambda: {**defaults, "tolerance": defaults["tolerance"] / 10})
    after = [h for h, _ in spec.tasks()]
    assert not set(after) & set(before)
    # a tolerance written in the base is already the effective option: a changed default does not matter
    spec = SweepSpec.from_dict({"base": {"kind": "normal", "solver": {"tolerance": 1e-7}}, "parameters": {"grid.n": [8]}})
    h_new = spec.tasks()[0][0]
    monkeypatch.setattr(sweep, "_scenario_solver_defaults", lambda: defaults)
    assert spec.tasks()[0][0] == h_new


def _point_module(folder: Path, tol: float) -> None:
    """A module ``sweeppoint`` with ``point(x, tol=...)``: returns x and the tolerance used and
    leaves one file per call (to count the computed points)."""
    (folder / "sweeppoint.py").write_text(
        "from pathlib import Path\n"
        f"CALLS = Path({str(folder / 'calls')!r})\n"
        f"def point(x, tol={tol!r}):\n"
        "    CALLS.mkdir(exist_ok=True)\n"
        "    (CALLS / f'{len(list(CALLS.iterdir()))}').write_text(str(x))\n"
        "    return {'x': x, 'tol': tol}\n")


def test_sweep_recomputes_after_a_solver_change_and_only_then(tmp_path, monkeypatch):
    """The CLI sweep of a function: a restart computes nothing; a changed default tolerance of
    the function, or a bumped solver version, recomputes every point."""
    import importlib
    import sys

    from typer.testing import CliRunner

    import tribobem._solver_version as sv
    from tribobem.cli import app

    mod_dir = tmp_path / "mod"
    mod_dir.mkdir()
    _point_module(mod_dir, 1e-9)
    monkeypatch.syspath_prepend(str(mod_dir))
    sys.modules.pop("sweeppoint", None)
    (tmp_path / "s.toml").write_text('function = "sweeppoint:point"\noutputs = ["x", "tol"]\n'
                                     '[parameters]\nx = [1, 2, 3]\n')
    out = tmp_path / "out"
    calls = mod_dir / "calls"

    def sweep():
        r = CliRunner().invoke(app, ["sweep", str(tmp_path / "s.toml"), "--out", str(out), "--scheduler",
                                     "synchronous", "--json"])
        assert r.exit_code == 0, r.output
        return json.loads(r.stdout)

    assert sweep()["n_run"] == 3 and len(list(calls.iterdir())) == 3
    rec = next(iter(read_points(out).values()))
    assert rec["solver_version"] == sv.SOLVER_VERSION
    assert json.loads((out / "sweep.json").read_text())["solver_version"] == sv.SOLVER_VERSION
    assert sweep()["n_run"] == 0 and len(list(calls.iterdir())) == 3    # resumed: nothing to do
    _point_module(mod_dir, 1e-11)                                       # a new default tolerance
    importlib.reload(importlib.import_module("sweeppoint"))
    res = sweep()
    assert res["n_run"] == 3 and res["n_done_before"] == 0 and len(list(calls.iterdir())) == 6
    with open(out / "results.csv") as fh:
        assert {float(r["tol"]) for r in csv.DictReader(fh)} == {1e-11}  # gathered: the new points only
    assert sweep()["n_run"] == 0
    monkeypatch.setattr(sv, "SOLVER_VERSION", sv.SOLVER_VERSION + 1)   # results of the solver changed
    assert sweep()["n_run"] == 3 and len(list(calls.iterdir())) == 9
    sys.modules.pop("sweeppoint", None)


_LINE = r"point (\d+) of (\d+) (done|failed): x = (\d), y = (\d+) \((\d+\.\d) s\)(: .*)?"


def _progress_lines(err: str) -> list[tuple]:
    import re

    return [re.fullmatch(_LINE, ln).groups() for ln in err.splitlines() if re.fullmatch(_LINE, ln)]


def test_progress_off_a_terminal_is_one_line_per_finished_point(tmp_path, capsys):
    out, counter, flag = tmp_path / "out", tmp_path / "calls", tmp_path / "armed"
    flag.write_text("1")
    func = make_func(counter, fail_x=2, flag=flag)
    order = [(o["x"], o["y"]) for _, o in SweepSpec.from_dict(SPEC).tasks()]
    res = run_sweep(SPEC, out, scheduler="synchronous", func=func, progress=True, quiet=False)
    assert res.n_failed == 2
    err = capsys.readouterr().err  # captured: not a terminal, so no live bar
    lines = _progress_lines(err)
    assert [(int(a), int(b)) for a, b, *_ in lines] == [(k, 6) for k in range(1, 7)]  # one per point, in order
    assert [(int(x), int(y)) for *_, x, y, _, _ in lines] == order
    assert [st for _, _, st, *_ in lines] == ["done", "done", "failed", "failed", "done", "done"]
    assert lines[2][6] == ": ValueError: x = 2 is not allowed today"
    assert "points done, running 6" in err and err.count("not allowed today") == 2  # no second failure message
    # a rerun numbers on from the points already done
    flag.unlink()
    run_sweep(SPEC, out, scheduler="synchronous", func=func, progress=True, quiet=False)
    lines = _progress_lines(capsys.readouterr().err)
    assert [(int(a), st, int(x), int(y)) for a, _, st, x, y, *_ in lines] == [(5, "done", 2, 10), (6, "done", 2, 20)]


def test_progress_quiet_prints_nothing_and_a_terminal_gets_the_bar(tmp_path, capsys):
    import io

    from rich.console import Console

    from tribobem.sweep.execute import _Progress

    run_sweep(SPEC, tmp_path / "q", scheduler="synchronous", func=make_func(tmp_path / "c"), progress=True,
              quiet=True)
    assert capsys.readouterr().err == ""
    f = tmp_path / "s.toml"
    f.write_text('function = "builtins:dict"\nscheduler = "synchronous"\n[base]\nc = 1\n[parameters]\nx = [1, 2]\n')
    assert sweep_command(str(f), out=str(tmp_path / "o"), quiet=True) == 0
    assert capsys.readouterr().err == ""
    assert sweep_command(str(f), out=str(tmp_path / "o2")) == 0
    err = capsys.readouterr().err
    assert "point 1 of 2 done: x = 1 (" in err and "point 2 of 2 done: x = 2 (" in err
    term = _Progress(True, 3, "t", console=Console(file=io.StringIO(), force_terminal=True))
    try:
        assert term.bar is not None and not term.lines
    finally:
        term.close()
    buf = io.StringIO()
    log = _Progress(True, 2, "t", offset=1, n_points=3, console=Console(file=buf, force_terminal=False))
    assert log.bar is None and log.lines
    log.advance({"status": "ok", "point": {"a": "1 um"}, "elapsed": 12.34})
    assert buf.getvalue() == "point 2 of 3 done: a = 1 um (12.3 s)\n"
