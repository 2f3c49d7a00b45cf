"""What a user reads: warnings and the expected line in every output mode, the result checks
from Python, the grid band only where it means something, the automatic tangential ramp, the
hysteresis summary line and the one-line refusals (memory, RH in per cent)."""

import json
import re
import types
import warnings

import numpy as np
import pytest
from rich.console import Console
from typer.testing import CliRunner

from tribobem import Grid
from tribobem.cli import _print_summary, app
from tribobem.errors import (RESULT_WARNINGS, FullContactWarning, MemoryBudgetError, ResultWarning,
                             result_warning_category)
from tribobem.output.checks import CHECKS, cohesive_edge_band, cohesive_edge_nodes, pull_off_statement
from tribobem.scenario import run_scenario

runner = CliRunner()

#: 1 N (a force given without a unit) on a 16^2 free-boundary sphere: p_max of hundreds of GPa,
#: the contact fills the domain and touches its edge.
OVERLOADED = """
kind = "normal"
expected = { reference = "the run must say that the domain is too small", warnings = ["full_contact", "edge"] }
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
force = 1
[output]
figures = false
"""


def _write(tmp_path, text, name="s.toml"):
    p = tmp_path / name
    p.write_text(text)
    return p


def test_quiet_and_json_runs_keep_the_warnings_and_the_expected_line(tmp_path):
    p = _write(tmp_path, OVERLOADED)
    r = runner.invoke(app, ["run", str(p), "--out", str(tmp_path / "q"), "--quiet"])
    assert r.exit_code == 0, r.output
    # stdout is the report path alone (scripts read it); what the user must read is on stderr
    assert r.stdout.strip() == str(tmp_path / "q" / "report.html")
    err = r.stderr
    assert re.search(r"^warning: full_contact: the contact covers \d+ % of the domain", err, re.M), err
    assert re.search(r"^warning: edge: ", err, re.M), err
    line = next(ln for ln in err.splitlines() if ln.startswith("expected"))
    assert ": met;" in line and "warning full_contact raised" in line and "warning edge raised" in line
    # --json: stdout stays one JSON document, the same lines on stderr
    r = runner.invoke(app, ["run", str(p), "--out", str(tmp_path / "j"), "--json"])
    assert r.exit_code == 0, r.output
    s = json.loads(r.stdout)
    assert any(w.startswith("full_contact:") for w in s["warnings"])
    assert "warning: full_contact:" in r.stderr and "expected" in r.stderr


def test_run_result_carries_the_warnings_and_python_warns_one_category_per_check(tmp_path):
    sc = _write(tmp_path, OVERLOADED)
    with pytest.warns(FullContactWarning, match=r"^full_contact: the contact covers") as record:
        res = run_scenario(sc, outdir=None, progress=False)
    assert any(w.startswith("full_contact:") for w in res.warnings)
    assert res.warnings == res.summary["warnings"]
    cats = {w.category for w in record if issubclass(w.category, ResultWarning)}
    assert {RESULT_WARNINGS["full_contact"], RESULT_WARNINGS["edge"]} <= cats
    # one category per check, each a ResultWarning named after it
    assert set(RESULT_WARNINGS) == set(CHECKS)
    for name, cls in RESULT_WARNINGS.items():
        assert issubclass(cls, ResultWarning) and cls.check == name
        assert result_warning_category(f"{name}: x") is cls
    assert result_warning_category("RH 0.4: a note") is ResultWarning
    # a script can make them errors
    with warnings.catch_warnings():
        warnings.simplefilter("error", ResultWarning)
        with pytest.raises(RESULT_WARNINGS["edge"], match="^edge: the contact"):
            run_scenario(sc, outdir=None, progress=False)


# ----------------------------------------------------------------------------- the grid band
def _state(gap, contact, adhesive, n, dx=1e-9, adhesive_force=-1.0):
    grid = types.SimpleNamespace(dx=dx, dy=dx, cell_area=dx * dx, nx=n, ny=n)
    return types.SimpleNamespace(gap=gap, contact=contact, adhesive=adhesive, grid=grid,
                                 adhesive_force=adhesive_force, pressure=np.where(adhesive, -1.0, 0.0))


def test_band_counts_only_the_dugdale_zone_edge_not_free_or_meniscus_nodes():
    """A flat top whose gaps all lie just beyond h0: only the free nodes next to the zone or the
    contact are two-way (before: every free node of the top), and a tensile node far beyond the
    range (a meniscus) is not in Dugdale's zone."""
    n, h0, sigma0, C = 32, 1.0e-9, 1.0e8, 5e-18  # sigma0 C = 0.5 nm
    gap = np.full((n, n), 1.1e-9)                # free, within sigma0 C of h0 everywhere
    contact = np.zeros((n, n), bool)
    contact[15:17, 15:17] = True
    gap[contact] = 0.0
    adhesive = np.zeros((n, n), bool)
    adhesive[14:18, 14:18] = True
    adhesive &= ~contact
    gap[adhesive] = 0.9e-9                       # zone nodes, two-way (g > h0 - sigma0 C)
    adhesive[0:4, 0:4] = True                    # a meniscus: tensile, gap 5 h0
    gap[0:4, 0:4] = 5e-9
    st = _state(gap, contact, adhesive, n)
    nodes, force = cohesive_edge_nodes(st, h0, sigma0, C)
    zone = 16 - 4  # the 4 x 4 block less its contact
    ring = 4 * 4   # the free 4-neighbours of the block: 4 per side
    assert nodes == zone + ring, nodes
    assert force == pytest.approx(nodes * sigma0 * 1e-18)


def test_band_is_not_resolved_below_a_cell_and_never_a_percentage_above_the_force():
    from tribobem.interactions.dugdale import DugdaleAdhesion

    ad = DugdaleAdhesion(work_of_adhesion=0.1, z0=0.3e-9)
    n = 16
    gap = np.full((n, n), 10 * ad.h0)
    contact = np.zeros((n, n), bool)
    contact[7:9, 7:9] = True
    gap[contact] = 0.0
    adhesive = np.zeros((n, n), bool)
    adhesive[6, 7] = True  # one cohesive node beside a 2x2 contact: the zone is below a cell
    gap[6, 7] = 0.5 * ad.h0
    st = _state(gap, contact, adhesive, n, dx=4e-9, adhesive_force=-ad.sigma0 * 16e-18)
    band = cohesive_edge_band([st], ad, 50e9)
    assert band["resolved"] is False and band["fraction"] is None
    assert "narrower than one cell" in band["reason"]
    text = pull_off_statement({"pull_off_force": -1e-8, "cohesive_edge": band, "warnings": []})
    assert "grid band not resolved" in text and "%" not in text


def test_capillary_runs_have_no_grid_band(tmp_path):
    """The capillary example's menisci made the band 24167 % of the adhesive force: runs with
    [humidity] have no band, and no cohesive_edge warning."""
    from pathlib import Path

    import tomllib

    sc = tomllib.loads((Path(__file__).resolve().parents[1] / "examples" / "capillary_rough_sio2.toml").read_text())
    sc["grid"]["n"] = 32
    sc.pop("expected", None)
    sc.setdefault("output", {})["figures"] = False
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ResultWarning)
        res = run_scenario(sc, outdir=tmp_path / "cap", progress=False, base_dir=Path.cwd())
    assert "cohesive_edge" not in res.summary
    assert not any(w.startswith("cohesive_edge") for w in res.warnings)
    assert "grid band" not in (tmp_path / "cap" / "report.html").read_text()


# ----------------------------------------------------------------------------- tangential "auto"
RAMP = """
kind = "partial_slip"
[grid]
n = 32
size = "0.32 um"
[body1]
E = "130 GPa"
nu = 0.3
[body2]
rigid = true
shape = { kind = "sphere", radius = "10 um" }
[load]
force = "10 uN"
[friction]
coefficient = 0.2
tangential_forces = TF
[output]
figures = false
report = false
"""


def test_partial_slip_auto_ramps_to_gross_slip_with_the_listed_ramps_onset(tmp_path):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ResultWarning)
        auto = run_scenario(_write(tmp_path, RAMP.replace("TF", '"auto"'), "a.toml"), progress=False).summary
        listed = run_scenario(_write(tmp_path, RAMP.replace("TF", '{ start = "0 uN", stop = "2.4 uN", num = 13 }'),
                                     "b.toml"), progress=False).summary
    f0p = auto["repulsive_force"]
    top = auto["tangential_forces_auto"][-1]
    assert top == pytest.approx(1.2 * 0.2 * f0p, rel=1e-12) and len(auto["tangential_forces_auto"]) == 13
    assert auto["gross_slip"] is True
    # the onset is bracketed to 1e-3 mu F0+ on both ramps
    assert auto["static_friction_ratio"] == pytest.approx(listed["static_friction_ratio"], abs=2e-3)
    assert 0.8 < auto["static_friction_ratio"] <= 1.0


def test_a_ramp_short_of_gross_slip_says_where_it_sets_in(tmp_path):
    p = _write(tmp_path, RAMP.replace("TF", '["0 uN", "0.5 uN", "1 uN"]'))
    r = runner.invoke(app, ["run", str(p), "--out", str(tmp_path / "r"), "--quiet"])
    assert r.exit_code == 0, r.output
    s = json.loads((tmp_path / "r" / "summary.json").read_text())
    assert s["gross_slip"] is False
    assert s["gross_slip_force_estimate"] == pytest.approx(0.2 * s["repulsive_force"], rel=1e-12)
    line = next(ln for ln in r.stderr.splitlines() if ln.startswith("warning: ramp:"))
    assert "no gross slip up to F_t = 1 µN" in line and "mu F0+ = 2 µN" in line and '"auto"' in line


def test_auto_ramp_is_refused_with_a_normal_load_path(tmp_path):
    text = RAMP.replace("TF", '"auto"').replace('force = "10 uN"', 'forces = ["5 uN", "10 uN"]')
    text = text.replace('coefficient = 0.2', 'coefficient = 0.2\nslip = "incremental"')
    r = runner.invoke(app, ["run", str(_write(tmp_path, text)), "--out", str(tmp_path / "r")])
    assert r.exit_code == 2
    assert r.output.startswith("error: friction.tangential_forces") and "load.forces" in r.output


# ----------------------------------------------------------------------------- summary lines, refusals
def test_hysteresis_summary_prints_loop_energy_and_lateral_stiffness():
    summary = {"kind": "hysteresis", "converged": True, "friction_coefficient": 0.3,
               "steps": [{"index": 0, "branch": "start", "normal_force": 1e-6, "tangential_force_x": 0.0,
                          "converged": True}],
               "dissipated_energy": [1.25e-15, 1.5e-15],
               "lateral_stiffness": [{"point": "A", "stiffness": 2.5e5}, {"point": "B", "stiffness": 1.5e5},
                                     {"point": "C", "stiffness": 9.0e4}]}
    console = Console(record=True, width=200)
    _print_summary(summary, None, console)
    text = console.export_text()
    assert "loop energy per cycle: 1.25 fJ, 1.5 fJ" in text
    assert "K_L (last rising branch): A 250 kN/m, B 150 kN/m, C 90 kN/m" in text


def test_memory_refusal_reads_like_every_other_error(tmp_path):
    text = OVERLOADED.replace("n = 16", "n = 131072")
    p = _write(tmp_path, text)
    r = runner.invoke(app, ["run", str(p), "--out", str(tmp_path / "m")])
    assert r.exit_code == 2
    out = r.output.strip()
    assert len(out.splitlines()) == 1 and out.startswith("error: grid.n: a 131072 x 131072 grid (free boundary)")
    assert out.endswith(f"({p})") and "periodic grid" not in out
    fit = int(re.search(r"about (\d+) x \1 fits here", out).group(1))
    Grid.square(fit, 1e-6).check_memory()            # what it suggests fits
    with pytest.raises(MemoryBudgetError):
        Grid.square(int(1.1 * fit) + 8, 1e-6).check_memory()


@pytest.mark.parametrize("value", ["40", "[0.3, 70]"])
def test_rh_in_per_cent_is_refused_with_the_fraction(tmp_path, value):
    text = OVERLOADED.replace('kind = "normal"', 'kind = "capillary"').replace("force = 1", 'force = "1 uN"')
    text = text.replace('expected = { reference = "the run must say that the domain is too small", '
                        'warnings = ["full_contact", "edge"] }', "")
    text += f"[humidity]\nrh = {value}\n"
    r = runner.invoke(app, ["run", str(_write(tmp_path, text)), "--out", str(tmp_path / "rh")])
    assert r.exit_code == 2
    assert "not per cent" in r.output and ("write 0.4" in r.output or "write 0.7" in r.output)


def test_scenario_physical_size_of_a_scan_is_in_metres_whatever_the_heights_unit(tmp_path):
    """A .npy scan with heights in nm and physical_size = 1 um: the scan spans 1 um (it was read
    as 1e-6 nm, i.e. 1e-15 m, and the resampling failed)."""
    from tribobem.scenario import load_scenario
    from tribobem.scenario.build import build_problem

    h = np.random.default_rng(0).normal(size=(32, 32))
    np.save(tmp_path / "h.npy", h)
    sc = {"kind": "normal", "grid": {"n": 32, "size": "1 um"},
          "body1": {"E": "70 GPa", "nu": 0.3, "roughness": {"kind": "file", "path": str(tmp_path / "h.npy"),
                                                            "unit": "nm", "physical_size": ["1 um", "0.5 um"],
                                                            "detrend": "center"}},
          "body2": {"rigid": True}, "load": {"force": "1 uN"}}
    s, base = load_scenario(sc)
    with pytest.raises(Exception, match="resample|outside"):  # 1 um x 0.5 um does not cover the 1 um grid
        build_problem(s, base)
    sc["body1"]["roughness"]["physical_size"] = ["1 um", "1 um"]
    s, base = load_scenario(sc)
    pb = build_problem(s, base)
    f = pb.info["files"]["body1.roughness"]
    assert f["scan_size"] == pytest.approx([1e-6, 1e-6], rel=1e-12)
    assert pb.info["roughness"]["body1"]["rms_height"] == pytest.approx(1e-9 * h.std(), rel=1e-9)
