"""benchmarks/adhesive_loop.py on a small grid: every inner solve of the coupling loop is counted
under one kind, each step ends with a normal solve at the run's tolerance and a final-pass
tangential solve, and the counted coupling passes match the steps' own."""

import importlib.util
from pathlib import Path

SCRIPT = Path(__file__).resolve().parents[2] / "benchmarks" / "adhesive_loop.py"


def _module():
    spec = importlib.util.spec_from_file_location("adhesive_loop_benchmark", SCRIPT)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def test_small_loop_profile(capsys):
    r = _module().main(["--n", "32", "--cycles", "1", "--steps", "8", "--json"])
    capsys.readouterr()
    solves = r["solves"]
    assert r["normal_method"] == "polonsky_keer"  # auto with adhesion
    # the start and every step: one final-pass tangential solve each
    assert solves["tangential, final pass"]["solves"] == r["steps"]
    # every step's last normal solve is at the run's tolerance
    assert solves["normal, run tolerance"]["solves"] >= r["steps"]
    # one normal solve per coupling pass, plus the finishing solves of passes accepted at an
    # inexact tolerance
    normal = solves["normal, run tolerance"]["solves"] + solves["normal, inexact pass"]["solves"]
    assert normal >= round(r["passes_per_step"] * r["steps"])
    assert len(r["loop_energies_J"]) == 1 and r["loop_energies_J"][0] > 0
