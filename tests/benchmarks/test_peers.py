"""benchmarks/peers.py without the peers: its problems and a tiny run of tribobem's modes."""

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

SCRIPT = Path(__file__).resolve().parents[2] / "benchmarks" / "peers.py"
sys.path.insert(0, str(SCRIPT.parent))

import peers  # noqa: E402


def test_the_problems_are_what_the_docs_say():
    n = 128
    free = peers.problem("free", n)
    per = peers.problem("periodic", n)
    assert free["gap"].min() == 0.0 and not free["periodic"] and free["nu"] == 0.0
    assert per["periodic"] and per["nu"] == 0.3
    assert abs(per["force"] - 0.01 / (1 - 0.09)) < 1e-15 and free["force"] == 2e-4
    # the rough part's rms slope (the crown removed): 0.05 and 1
    x = (np.arange(n) + 0.5) / n - 0.5
    crown = (x[:, None] ** 2 + x[None, :] ** 2) / (2 * peers.CROWN_RADIUS)
    z = -(free["gap"] - crown)
    assert abs(peers.rms_slope(z - z.mean(), 1.0 / n) - 0.05) < 1e-12
    assert abs(peers.rms_slope(-per["gap"], 1.0 / n) - 1.0) < 1e-12


@pytest.mark.slow  # three subprocesses, 9-13 s
def test_a_tiny_run_gives_the_table(tmp_path):
    out = tmp_path / "rows.json"
    proc = subprocess.run([sys.executable, str(SCRIPT), "--problem", "free", "--n", "64",
                           "--codes", "tribobem", "--json", str(out)], capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0, proc.stderr
    rows = json.loads(out.read_text())
    assert {(r["problem"], r["mode"]) for r in rows} == {("free", m) for m in ("whole", "default", "fast")}
    for r in rows:
        assert "error" not in r and r["converged"] and r["bytes_per_node"] > 0
    assert len({r["contact_nodes"] for r in rows}) == 1  # every mode: the same contact nodes
    assert "| free | 64 | tribobem | fast |" in proc.stdout
