"""benchmarks/gpu.py, the GPU table, without a GPU: its dry run (NumPy on both sides) runs each
case it is given and finds the two runs identical; without CuPy it says so and exits 0."""

import importlib.util
import json
from pathlib import Path

import pytest

from tribobem.elasticity import cupy_available

SCRIPT = Path(__file__).resolve().parents[1] / "benchmarks" / "gpu.py"


def _module():
    spec = importlib.util.spec_from_file_location("gpu_benchmark", SCRIPT)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def test_dry_run_table(tmp_path, capsys):
    out = tmp_path / "gpu.json"
    assert _module().main(["--dry-run", "--cases", "normal_normcg", "burl", "--json", str(out)]) == 0
    data = json.loads(out.read_text())
    assert [r["case"] for r in data["rows"]] == ["normal_normcg", "burl"]
    for r in data["rows"]:
        assert r["contact_nodes"] > 0 and r["contact_nodes_differ"] == 0 and r["max_rel_diff"] == 0.0
    assert "| burl | 256 |" in capsys.readouterr().out


@pytest.mark.skipif(cupy_available(), reason="a GPU is present: the script would measure")
def test_without_a_gpu_it_says_so(capsys):
    assert _module().main(["--cases", "normal_normcg"]) == 0
    assert "CuPy with a CUDA device is not available" in capsys.readouterr().out
