"""Sweep point hashes are the keys of existing sweep folders: pinned here, so that a
refactoring that changes them (and makes every resumed sweep recompute all its points) fails."""

from __future__ import annotations

import json

import numpy as np

import tribobem._solver_version as sv
from tribobem.sweep import SweepSpec, point_hash, read_points, run_sweep

#: A function sweep whose hashes depend on nothing but the spec and the solver version
#: (``dict`` has no keyword defaults, so no solver options enter them).
FUNCTION_SPEC = {"function": "builtins:dict", "base": {"a": "1 nm"}, "parameters": {"x": [1, 2.5, "3 um"]}}
#: Its hashes at solver version 5, as every version of tribobem.sweep has made them.
FUNCTION_HASHES = ["53054dc539e825e4", "544cb5500fb29322", "d7b7142fef0beabb"]


def test_point_hash_is_pinned():
    base = {"kind": "normal", "grid": {"n": 8, "size": "10 um"}}
    point = {"load.force": "1 mN", "x": np.float64(0.5), "k": (1, 2)}
    solver = {"tolerance": 1e-10, "max_iterations": 500}
    assert point_hash("scenario", base, point, solver, solver_version=7) == "bd85d10c3d576452"
    assert point_hash("function:pkg.mod:f", {"n": 32}, {"x": 1}, solver_version=1) == "a43a79919333c9a4"


def test_spec_point_hashes_are_pinned(monkeypatch):
    monkeypatch.setattr(sv, "SOLVER_VERSION", 5)
    assert [h for h, _ in SweepSpec.from_dict(FUNCTION_SPEC).tasks()] == FUNCTION_HASHES


def test_an_existing_sweep_folder_is_resumed_from_its_records(tmp_path, monkeypatch):
    """Records written under the pinned hashes (by an earlier version) are reused, not recomputed."""
    monkeypatch.setattr(sv, "SOLVER_VERSION", 5)
    points = tmp_path / "points"
    points.mkdir()
    for i, (h, x) in enumerate(zip(FUNCTION_HASHES, [1, 2.5, "3 um"])):
        rec = {"version": 1, "solver_version": 5, "hash": h, "point": {"x": x}, "status": "ok",
               "outputs": {"a": 100.0 + i, "x": 200.0 + i}, "error": None, "elapsed": 0.5}
        (points / f"{h}.json").write_text(json.dumps(rec, indent=1, sort_keys=True) + "\n")
    assert sorted(read_points(tmp_path)) == sorted(FUNCTION_HASHES)
    res = run_sweep(FUNCTION_SPEC, tmp_path, scheduler="synchronous", progress=False)
    assert (res.n_done_before, res.n_run, res.n_ok) == (3, 0, 3)
    # the gathered values are the records' (a recomputed point would give a = 1e-9 m)
    assert res.dataset["a"].values.tolist() == [100.0, 101.0, 102.0]
    assert res.dataset["hash"].values.tolist() == FUNCTION_HASHES
