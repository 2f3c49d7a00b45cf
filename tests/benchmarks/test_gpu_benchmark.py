"""The GPU paths without a GPU: benchmarks/gpu.py's dry run (NumPy on both sides) runs each case
it is given and finds the two runs identical, and without CuPy it says so and exits 0; a
scenario's backend = "cupy" on a small grid runs on NumPy and says so."""

import importlib.util
import json
from pathlib import Path

import pytest

from tribobem.elasticity import cupy_available

SCRIPT = Path(__file__).resolve().parents[2] / "benchmarks" / "gpu.py"


def _module():
    spec = importlib.util.spec_from_file_location("gpu_benchmark", SCRIPT)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def test_dry_run_table(tmp_path, capsys, monkeypatch):
    monkeypatch.setenv("TRIBOBEM_CUPY_MIN_NODES", "0")  # the script sets it: restored after the test
    out = tmp_path / "gpu.json"
    assert _module().main(["--dry-run", "--cases", "normal_normcg", "burl", "--json", str(out)]) == 0
    data = json.loads(out.read_text())
    assert [r["case"] for r in data["rows"]] == ["normal_normcg", "burl"]
    for r in data["rows"]:
        assert r["contact_nodes"] > 0 and r["contact_nodes_differ"] == 0 and r["max_rel_diff"] == 0.0
    assert "| burl | 256 |" in capsys.readouterr().out


@pytest.mark.skipif(cupy_available(), reason="a GPU is present: the script would measure")
def test_without_a_gpu_it_says_so(capsys, monkeypatch):
    monkeypatch.setenv("TRIBOBEM_CUPY_MIN_NODES", "0")
    assert _module().main(["--cases", "normal_normcg"]) == 0
    assert "CuPy with a CUDA device is not available" in capsys.readouterr().out


def _hertz(n: int) -> dict:
    return {"kind": "normal", "grid": {"n": n, "size": "1.2 um", "periodic": False},
            "body1": {"E": "130 GPa", "nu": 0.28}, "body2": {"rigid": True, "shape": {"kind": "sphere", "radius": "10 um"}},
            "load": {"force": "200 uN"}, "solver": {"backend": "cupy"}}


def test_small_grids_requested_on_cupy_run_on_numpy(monkeypatch):
    """Below CUPY_MIN_NODES a scenario's backend = "cupy" runs on NumPy (faster there than a GPU,
    benchmarks/gpu.py's hertz rows), and says so; TRIBOBEM_CUPY_MIN_NODES moves the limit."""
    from tribobem.scenario import build_problem, parse_scenario
    from tribobem.scenario.build import CUPY_MIN_NODES

    assert 64 * 64 < CUPY_MIN_NODES
    monkeypatch.delenv("TRIBOBEM_CUPY_MIN_NODES", raising=False)
    pb = build_problem(parse_scenario(_hertz(64)))
    assert pb.operator.backend.name == "numpy"
    assert pb.info["backend"].startswith("numpy (cupy requested")


@pytest.mark.skipif(cupy_available(), reason="CuPy is present: the limit would not raise")
def test_above_the_limit_cupy_is_still_required(monkeypatch):
    from tribobem.errors import InputError
    from tribobem.scenario import build_problem, parse_scenario

    monkeypatch.setenv("TRIBOBEM_CUPY_MIN_NODES", "0")
    with pytest.raises(InputError, match="CuPy with a working CUDA device is not available") as exc:
        build_problem(parse_scenario(_hertz(64)))
    assert exc.value.field == "solver.backend"


def test_save_then_against(tmp_path, capsys, monkeypatch):
    """The GPU and CPU sides on different machines: --save writes the runs (a failing case is
    recorded with its error and the table goes on), --against runs the CPU side and compares
    with the saved contact masks and results."""
    monkeypatch.setenv("TRIBOBEM_CUPY_MIN_NODES", "0")
    mod = _module()
    real_run = mod.run

    def run(sc, backend, base_dir):
        if sc.get("name", "").startswith("Hertz"):
            raise RuntimeError("planted failure")
        return real_run(sc, backend, base_dir)

    monkeypatch.setattr(mod, "run", run)
    saved = tmp_path / "gpu"
    assert mod.main(["--dry-run", "--save", str(saved), "--cases", "hertz", "burl_ramp"]) == 0
    data = json.loads((saved / "gpu_rows.json").read_text())
    assert [r["case"] for r in data["rows"]] == ["hertz", "burl_ramp"]
    assert data["rows"][0]["error"] == "RuntimeError: planted failure"
    assert data["rows"][1]["contact_nodes"] > 0 and "timings" in data["rows"][1]
    monkeypatch.setattr(mod, "run", real_run)
    out = tmp_path / "table.json"
    assert mod.main(["--against", str(saved), "--cases", "hertz", "burl_ramp", "--json", str(out)]) == 0
    rows = json.loads(out.read_text())["rows"]
    assert "error" in rows[0] and "cpu_s" not in rows[0]
    assert rows[1]["contact_nodes_differ"] == 0 and rows[1]["max_rel_diff"] == 0.0
    text = capsys.readouterr().out
    assert "| hertz | 64 | failed: RuntimeError: planted failure |" in text
