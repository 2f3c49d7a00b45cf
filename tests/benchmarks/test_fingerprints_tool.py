"""benchmarks/fingerprints.py on a tiny synthetic summary (no example is run): the flattening with
dotted keys, the exact encodings and the comparison report."""

import importlib.util
import json
from pathlib import Path

import numpy as np

SCRIPT = Path(__file__).resolve().parents[2] / "benchmarks" / "fingerprints.py"


def _module():
    spec = importlib.util.spec_from_file_location("fingerprints_tool", SCRIPT)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


SUMMARY = {
    "kind": "normal",
    "converged": True,
    "timings": {"build": 1.25, "solve": 0.5},  # skipped: wall-clock times
    "created": "2026-12-02T01:00:00",            # skipped
    "versions": {"tribobem": "0.1.0"},            # skipped
    "steps": [{"normal_force": 1e-6, "iterations": 24, "time": 0.03, "branch": "loading"},
              {"normal_force": -0.0, "iterations": np.int64(15), "time": 0.02, "branch": "loading"}],
    "problem": {"grid": {"nx": 128, "dx": np.float64(1.953125e-09)}, "file": "/repo/x/examples/a.npy"},
    "warnings": ["edge contact: 3 nodes"],
    "jumps": [],
    "curve": np.array([0.1, 0.2]),
}


def test_flatten_uses_dotted_keys_and_skips_times():
    fp = _module().flatten(SUMMARY, roots=("/repo/x",))
    assert fp["kind"] == "str:normal"
    assert fp["converged"] is True
    assert fp["steps.0.iterations"] == 24 and type(fp["steps.1.iterations"]) is int
    assert fp["problem.grid.nx"] == 128
    assert fp["curve.1"] == (0.2).hex()
    assert fp["jumps"] == "str:[]"
    assert fp["problem.file"] == "str:<repo>/examples/a.npy"  # the worktree's path does not count
    assert not [k for k in fp if k.startswith(("timings", "created", "versions")) or k.endswith(".time")]


def test_floats_are_hex_and_warnings_hashed():
    mod = _module()
    fp = mod.flatten(SUMMARY)
    assert fp["steps.0.normal_force"] == (1e-6).hex() and float.fromhex(fp["steps.0.normal_force"]) == 1e-6
    assert fp["steps.1.normal_force"] == "-0x0.0p+0"  # the sign of zero counts
    assert fp["problem.grid.dx"] == float(1.953125e-09).hex()
    w = fp["warnings.0"]
    assert w.startswith("sha256:") and "edge" not in w
    assert mod.flatten({"warnings": ["edge contact: 4 nodes"]})["warnings.0"] != w
    assert mod.encode_scalar(float("nan")) == "nan" and mod.encode_scalar(np.bool_(False)) is False
    json.dumps(fp)  # JSON-safe


def test_compare_reports_a_changed_float_only():
    mod = _module()
    old = mod.flatten(SUMMARY)
    changed = dict(SUMMARY, steps=[dict(SUMMARY["steps"][0], normal_force=np.nextafter(1e-6, 1.0)),
                                   SUMMARY["steps"][1]])
    new = mod.flatten(changed)
    lines, same, total = mod.compare(old, new)
    assert total == len(old) and same == total - 1
    assert len(lines) == 1 and lines[0].startswith("steps.0.normal_force: 1e-06 -> ")
    assert lines[0].endswith("(rel. diff 2.12e-16)")
    lines, same, total = mod.compare(old, dict(old))
    assert lines == [] and same == total


def test_compare_reports_missing_and_added_keys_and_type_changes():
    mod = _module()
    lines, same, total = mod.compare({"a": 1, "b": "str:x"}, {"a": True, "c": None})
    assert same == 0 and total == 3
    assert lines == ["a: 1 -> true", "b: only in old (\"str:x\")", "c: only in new (null)"]


def test_fields_are_digested_bitwise():
    xr = __import__("pytest").importorskip("xarray")
    mod = _module()
    p = np.arange(12.0).reshape(1, 3, 4)
    ds = xr.Dataset({"pressure": (("step", "x", "y"), p)}, coords={"label": ("step", ["loading 0"])},
                    attrs={"tribobem_version": "0.1.0", "dx": 0.5})
    fp = mod.fields_fingerprints(ds, "examples/t")
    assert fp["examples/t/fields/pressure"] == mod.array_digest(p)
    assert fp["examples/t/fields/pressure.sum"] == (66.0).hex()
    assert fp["examples/t/fields/coord:label"].startswith("sha256:")
    assert fp["examples/t/fields.attrs.dx"] == (0.5).hex() and "examples/t/fields.attrs.tribobem_version" not in fp
    p2 = p.copy()
    p2[0, 1, 1] = np.nextafter(p2[0, 1, 1], 10.0)
    ds2 = ds.copy(deep=True)
    ds2["pressure"].values[...] = p2
    assert mod.fields_fingerprints(ds2, "examples/t")["examples/t/fields/pressure"] != fp["examples/t/fields/pressure"]
