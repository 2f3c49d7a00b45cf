"""``[two_scale]`` from a scenario file: the run, its summary, and the errors that name a key."""

import copy
import math

import numpy as np
import pytest

from tribobem.elasticity import free_boundary_operator
from tribobem.errors import InputError
from tribobem.geometry.rough import gaussian_surface
from tribobem.geometry.shapes import burl
from tribobem.grid import Grid
from tribobem.materials import ContactPair, Material
from tribobem.scenario import parse_scenario, run_scenario
from tribobem.solvers.normal import solve_normal

BASE = {
    "kind": "normal",
    "grid": {"n": 64, "size": "10.24 um"},
    "body1": {"E": "130 GPa", "nu": 0.28,
              "roughness": {"kind": "gaussian", "rms": "1.5 nm", "correlation_length": "50 nm", "seed": 1}},
    "body2": {"E": "410 GPa", "nu": 0.14, "shape": {"kind": "burl", "radius": "3 um", "edge_radius": "20 um"}},
    "load": {"force": "1.5 mN"},
    "two_scale": {"window": "1 um", "window_n": 50, "realisations": 4, "cache": False},
}


def _override(d, changes):
    """``d`` with dotted keys set (a None value removes the key)."""
    for dotted, value in changes.items():
        *path, last = dotted.split(".")
        node = d
        for p in path:
            node = node.setdefault(p, {})
        if value is None:
            node.pop(last, None)
        else:
            node[last] = value
    return d


def scenario(**changes):
    return _override(copy.deepcopy(BASE), changes)


def whole_burl(n=512, seed=100):
    """The same burl on one grid of 20 nm cells, roughness included (the reference)."""
    pair = ContactPair(Material(130e9, 0.28), Material(410e9, 0.14))
    grid = Grid(n, n, 10.24e-6, 10.24e-6)
    topo = gaussian_surface(grid, 1.5e-9, 50e-9, seed=seed)
    H = burl(grid, 3e-6, 20e-6) - topo
    offset = -H.min()
    res = solve_normal(free_boundary_operator(grid, pair), H + offset, force=1.5e-3, tol=1e-8)
    return res.approach - offset, res.contact_area  # approach of the mean planes, real area


def test_two_scale_normal_run_matches_the_whole_burl():
    result = run_scenario(parse_scenario(scenario()), outdir=None, progress=False, warn=False)
    s = result.summary
    step = s["steps"][0]
    assert s["converged"] and step["converged"]
    assert step["normal_force"] == pytest.approx(1.5e-3, rel=1e-10)
    approach_whole, area_whole = whole_burl()
    # measured: -0.6909 vs -0.6808 nm (0.7 % of the 1.5 nm rms), real area -6.3 % at these 50-cell windows
    # (the 100-cell windows of a 10 nm whole grid give -3.2 %); a law without the windows' own elasticity, or
    # the table's gaps off by one cell of rms, misses by far more
    assert abs(step["approach"] - approach_whole) < 0.05 * 1.5e-9
    assert step["contact_area"] == pytest.approx(area_whole, rel=0.10)
    assert step["nominal_contact_area"] > math.pi * (3e-6) ** 2 * 0.9
    assert step["max_pressure"] > step["max_nominal_pressure"]
    ts = s["two_scale"]
    assert ts["law"]["realisations"] == 4 and ts["law"]["converged"]
    assert ts["law"]["pressures"][0] < 1.5e-3 / (math.pi * 9e-12) < ts["law"]["pressures"][-1]
    assert s["problem"]["two_scale"]["window_n"] == 50
    # the only warnings: 50 nm correlation length over 20 nm cells, and asperity contacts under 3 cells
    # across (as coarse as the whole grid here)
    assert [w.split(":")[0] for w in s["warnings"]] == ["two_scale.window_n"] * 2
    assert s["two_scale"]["window_patch_cells"] < 3


TOML = """
kind = "normal"
[grid]
n = 64
size = "10.24 um"
[body1]
E = "130 GPa"
nu = 0.28
roughness = { kind = "gaussian", rms = "1.5 nm", correlation_length = "50 nm", seed = 1 }
[body2]
E = "410 GPa"
nu = 0.14
shape = { kind = "burl", radius = "3 um", edge_radius = "20 um" }
[load]
forces = ["0.5 mN", "1.5 mN"]
[two_scale]
window = "1 um"
window_n = 50
realisations = 2
"""


def test_two_scale_runs_from_the_cli_and_writes_the_maps(tmp_path, monkeypatch):
    import xarray as xr
    from typer.testing import CliRunner

    from tribobem.cli import app

    monkeypatch.setenv("TRIBOBEM_CACHE", str(tmp_path / "cache"))
    path = tmp_path / "burl.toml"
    path.write_text(TOML)
    out = tmp_path / "out"
    r = CliRunner().invoke(app, ["run", str(path), "--out", str(out), "--quiet"])
    assert r.exit_code == 0, r.output
    with xr.open_dataset(out / "fields.nc") as ds:
        p = ds["pressure"].values
    assert p.shape[-2:] == (64, 64) and np.nanmax(p) > 0
    assert (out / "report.html").exists() and (out / "interface_law.png").exists()
    report = (out / "report.html").read_text()
    assert "two-scale" in report and "scale separation" in report
    # the rerun reads both windows' tables from the cache
    assert len(list((tmp_path / "cache" / "two_scale").glob("*.json"))) == 2
    r = CliRunner().invoke(app, ["run", str(path), "--out", str(tmp_path / "again"), "--json"])
    assert r.exit_code == 0, r.output


@pytest.mark.parametrize("changes, key", [
    ({"two_scale.window": "0.2 um"}, "two_scale.window"),
    ({"body1.roughness": {"kind": "none"}}, "two_scale"),
    ({"load.force": None, "load.approach": "2 nm"}, "load.approach"),
    ({"adhesion": {"model": "dugdale", "work_of_adhesion": "0.1 J/m^2", "z0": "0.3 nm"}}, "adhesion.model"),
    ({"kind": "pulloff", "load": {"preload": "1 mN", "control": "force"},
      "adhesion": {"model": "dugdale", "work_of_adhesion": "0.1 J/m^2", "z0": "0.3 nm"}}, "load.control"),
    ({"kind": "pulloff", "load": {"preload": "1 mN"}}, "adhesion.model"),
])
def test_bad_two_scale_scenarios_name_the_key(changes, key):
    with pytest.raises(InputError) as err:
        sc = parse_scenario(scenario(**changes))
        run_scenario(sc, outdir=None, progress=False, warn=False)
    assert key in str(err.value)


def test_a_table_short_of_the_macro_pressures_is_a_warning():
    sc = parse_scenario(scenario(**{"two_scale.max_pressure": "30 MPa", "two_scale.min_pressure": "0.1 MPa"}))
    s = run_scenario(sc, outdir=None, progress=False, warn=False).summary
    assert any("two_scale.max_pressure" in w for w in s["warnings"])


# both tiers under -m slow: CI's validation gate runs the two_scale physics itself (the quick
# tier took 44 s of the default run)
@pytest.mark.slow
@pytest.mark.parametrize("quick", [True, False])
def test_the_two_scale_validation_cases_pass(quick):
    from tribobem.validation import PHYSICS_CASES, run_validation

    rows = run_validation(quick=quick, cases=PHYSICS_CASES["two_scale"])
    assert {r.case for r in rows} == set(PHYSICS_CASES["two_scale"])
    failed = [r for r in rows if not r.passed]
    assert not failed, failed


def test_a_texture_that_does_not_tile_the_window_and_a_coarse_macro_grid():
    tex = {"kind": "dimples", "pitch": "0.3 um", "size": "0.15 um", "depth": "2 nm"}
    with pytest.raises(InputError, match="two_scale.window"):
        run_scenario(parse_scenario(scenario(**{"body1.texture": tex})), outdir=None, progress=False, warn=False)
    # a texture that tiles the window goes to the windows (and is resolved by their cells)
    tex["pitch"], tex["size"] = "0.25 um", "0.125 um"
    s = run_scenario(parse_scenario(scenario(**{"body1.texture": tex})), outdir=None, progress=False,
                     warn=False).summary
    assert s["problem"]["two_scale"]["window_textures"] == ["body1.texture"]
    # 16 macro cells of 640 nm against an edge zone of 0.49 um
    s = run_scenario(parse_scenario(scenario(**{"grid.n": 16})), outdir=None, progress=False, warn=False).summary
    assert any(w.startswith("grid.n: the macro cells") for w in s["warnings"])


def slip_scenario(**changes):
    d = scenario(**{"kind": "partial_slip", "friction": {"coefficient": 0.2, "tangential_forces": "auto"},
                    "two_scale.window_n": 32, "two_scale.realisations": 2, "grid.n": 48})
    return _override(d, changes)


def test_two_scale_partial_slip_ramps_to_the_static_friction(tmp_path):
    from tribobem.output.figures.sets import two_scale_figures

    s = run_scenario(parse_scenario(slip_scenario()), outdir=None, progress=False, warn=False).summary
    figures = two_scale_figures(None, s, tmp_path)  # the normal and the tangential interface laws
    assert set(figures) == {"interface_law", "slip_law"} and all(f.stat().st_size > 10_000 for f in figures.values())
    steps = s["steps"]
    fx = [st["tangential_force_x"] for st in steps]
    dx = [st["displacement_x"] for st in steps]
    assert s["converged"] and len(steps) == 12
    assert s["static_friction_force"] == pytest.approx(0.2 * 1.5e-3, rel=1e-9)  # mu F: every window slides at mu p
    assert np.all(np.diff(fx) > 0) and np.all(np.diff(dx) > 0)
    assert steps[0]["stick_ratio"] == 1.0 and steps[-1]["stick_ratio"] < 0.3
    assert 0 < s["displacement_at_half_static_friction"] < s["displacement_at_0p9_static_friction"]
    assert s["two_scale"]["slip_law"]["realisations"] == 2
    # beyond the static friction: not solved, and said
    s = run_scenario(parse_scenario(slip_scenario(**{"friction.tangential_forces": ["0.1 mN", "0.4 mN"]})),
                     outdir=None, progress=False, warn=False).summary
    assert len(s["steps"]) == 1 and s["gross_slip"]
    assert any("slides as a whole" in w for w in s["warnings"])


@pytest.mark.parametrize("changes, key", [
    ({"friction.tangential_forces": None, "friction.tangential_displacements": ["1 nm"]},
     "friction.tangential_displacements"),
    ({"friction.direction": 30}, "friction.direction"),
])
def test_unsupported_two_scale_ramps_name_the_key(changes, key):
    with pytest.raises(InputError) as err:
        run_scenario(parse_scenario(slip_scenario(**changes)), outdir=None, progress=False, warn=False)
    assert key in str(err.value)


def loop_scenario(**changes):
    d = scenario(**{"kind": "hysteresis", "grid.n": 128,
                    "friction": {"coefficient": 0.2,
                                 "path": {"control": "force", "amplitude": 0.8, "cycles": 1, "steps": 24}}})
    return _override(d, changes)


def test_two_scale_loop_matches_the_whole_burl_loop():
    from tribobem.validation.two_scale import WHOLE_BURL_LOOP

    result = run_scenario(parse_scenario(loop_scenario()), outdir=None, progress=False, warn=False)
    s = result.summary
    ref = WHOLE_BURL_LOOP["n512"]  # the whole burl's loop at the windows' 20 nm cells, the coupled pair
    assert s["converged"] and len(s["steps"]) == 31
    # measured: +1.9 % (seed 1 windows), K_L -1.4 / -2.5 / -3.9 %; a slip law without the Masing factor 2
    # halves the loop, one without the windows' elasticity misses K_L by far more
    assert s["dissipated_energy"][0] == pytest.approx(ref["dissipated_energy"][0], rel=0.10)
    assert s["dissipation_work"][0] == pytest.approx(s["dissipated_energy"][0], rel=1e-6)
    k = {r["point"]: r["stiffness"] for r in s["lateral_stiffness"]}
    for point in "ABC":
        assert k[point] == pytest.approx(ref[point][0], rel=0.10)
    assert s["two_scale"]["unloading_rule"] == "Masing"
    # the stick maps of the kept states (start, D, D', H, H', L) follow the branches: right after a
    # turn the windows stick again (Masing: the branch's own stick fraction), at a turn most slip
    stuck = [np.count_nonzero(t.stick) / np.count_nonzero(t.contact) for t in result.tangential]
    assert stuck[0] == 1.0 and stuck[2] > 0.9 and stuck[4] > 0.9
    assert max(stuck[1], stuck[3], stuck[5]) < 0.2
    # the loop closes: back at +F* at the first turn's displacement
    assert s["steps"][-1]["displacement_x"] == pytest.approx(s["steps"][6]["displacement_x"], rel=1e-6)


@pytest.mark.parametrize("changes, key", [
    ({"friction.path": {"control": "displacement", "stroke": "1 nm", "cycles": 1, "steps": 24}},
     "friction.path.control"),
    ({"friction.path.amplitude": 0.999}, "friction.path.amplitude"),
])
def test_unsupported_two_scale_loops_name_the_key(changes, key):
    changes = {"two_scale.window_n": 32, "two_scale.realisations": 1, "grid.n": 32, **changes}
    with pytest.raises(InputError) as err:
        run_scenario(parse_scenario(loop_scenario(**changes)), outdir=None, progress=False, warn=False)
    assert key in str(err.value)


def _scan_file(tmp_path, n=512, seed=100):
    """The validation roughness (seed 100) written as a scan file (npy, heights in m)."""
    grid = Grid(n, n, 10.24e-6, 10.24e-6)
    path = tmp_path / "scan.npy"
    np.save(path, gaussian_surface(grid, 1.5e-9, 50e-9, seed=seed))
    return path


def _measured(path, **changes):
    rough = {"kind": "file", "path": str(path), "physical_size": ["10.24 um", "10.24 um"], "unit": "m",
             "detrend": "none"}
    return scenario(**{"body1.roughness": rough, "grid.n": 128, "two_scale.realisations": 16, **changes})


def test_windows_cut_from_a_measured_scan_match_the_whole_burl_on_that_scan(tmp_path):
    path = _scan_file(tmp_path)
    s = run_scenario(parse_scenario(_measured(path)), outdir=None, progress=False, warn=False).summary
    step = s["steps"][0]
    approach_whole, area_whole = whole_burl()  # the same surface on the whole grid
    files = s["problem"]["files"]["body1.roughness"]
    assert files["windows"] == 100 and s["problem"]["two_scale"]["realisations"] == 16
    # the wavelengths above the window (here 0.16 nm of the 1.5 nm rms) go to the macro grid
    assert files["macro_rms"] < 0.2 * files["scan_rms"]
    # measured: real area -2.1 %, approach of the mean planes 0.037 nm (2.5 % of the rms) from the whole burl
    assert step["contact_area"] == pytest.approx(area_whole, rel=0.05)
    approach = step["approach"] + s["problem"]["two_scale"]["macro_gap_shift"]
    assert abs(approach - approach_whole) < 0.04 * 1.5e-9
    assert s["problem"]["two_scale"]["measured"] == ["body1"]


def test_measured_windows_errors_and_warnings_name_the_key(tmp_path):
    path = _scan_file(tmp_path, n=128)
    with pytest.raises(InputError) as err:
        run_scenario(parse_scenario(_measured(path, **{"two_scale.window": "12 um", "two_scale.window_n": 64})),
                     outdir=None, progress=False, warn=False)
    assert "two_scale.window" in str(err.value)
    s = run_scenario(parse_scenario(_measured(path, **{"two_scale.window": "4 um", "two_scale.window_n": 50,
                                                       "two_scale.realisations": 8})),
                     outdir=None, progress=False, warn=False).summary
    assert any(w.startswith("two_scale.realisations") and "4 window(s)" in w for w in s["warnings"])
    assert s["problem"]["two_scale"]["realisations"] == 4


HUMID = {"body1.film": {"isotherm": "Si"}, "body2.film": {"isotherm": "SiO2"},
         "humidity": {"rh": 0.5, "van_der_waals": False}}


def test_a_humid_two_scale_ramp_matches_the_whole_burl_at_rh_0p5():
    from tribobem.validation.two_scale import WHOLE_BURL_HUMID

    d = slip_scenario(**{"two_scale.window_n": 50, "two_scale.realisations": 4, "grid.n": 128, **HUMID})
    s = run_scenario(parse_scenario(d), outdir=None, progress=False, warn=False).summary
    ref = WHOLE_BURL_HUMID["n512"]  # the whole burl at the windows' 20 nm cells, RH 0.5, seed 100
    assert s["converged"] and s["rh"] == 0.5
    # the menisci pull the burl on: F0+ = F + |F_cap| (measured -0.5 %, -0.9 %), and every window slides
    # at mu times its repulsive pressure, so the burl at mu F0+ (measured -0.4 %); a dry law gives mu F,
    # 58 % low
    assert s["repulsive_force"] == pytest.approx(ref["repulsive_force"][0], rel=0.03)
    assert s["capillary_force"] == pytest.approx(ref["capillary_force"][0], rel=0.05)
    assert s["static_friction_force"] == pytest.approx(0.2 * s["repulsive_force"], rel=1e-9)
    assert s["static_friction_force"] == pytest.approx(ref["static_friction_force"][0], rel=0.03)
    # measured -1.2 % and +0.1 %
    assert s["displacement_at_half_static_friction"] == pytest.approx(ref["d50"][0], rel=0.10)
    assert s["displacement_at_0p9_static_friction"] == pytest.approx(ref["d90"][0], rel=0.10)
    assert s["steps"][0]["capillary_force"] == s["capillary_force"] and s["wetted_area"] > 0


def test_a_humid_two_scale_run_takes_one_rh():
    d = slip_scenario(**{**HUMID, "humidity": {"rh": [0.3, 0.7], "van_der_waals": False}})
    with pytest.raises(InputError) as err:
        run_scenario(parse_scenario(d), outdir=None, progress=False, warn=False)
    assert "humidity.rh" in str(err.value)


def pulloff_scenario(**changes):
    d = copy.deepcopy(BASE)
    d["kind"] = "pulloff"
    d["load"] = {"preload": "1.5 mN", "refine": 4}
    return _override(d, changes)


def test_a_humid_two_scale_pulloff_matches_the_whole_burl_at_rh_0p5(tmp_path):
    from tribobem.validation.two_scale import WHOLE_BURL_PULLOFF

    d = pulloff_scenario(**HUMID)
    r = run_scenario(parse_scenario(d), outdir=tmp_path / "out", progress=False, warn=False)
    s = r.summary
    ref = WHOLE_BURL_PULLOFF["n512"]  # the whole burl at the windows' 20 nm cells, RH 0.5, seeds 100-101
    assert s["converged"] and s["kind"] == "pulloff"
    (force,) = s["pull_off_force"]
    # measured -3.5 % against the seeds' mean (their spread is +-4.4 %); a law without the windows'
    # tensile branch has no pull-off at all
    assert force == pytest.approx(float(np.mean(ref["pull_off_force"])), rel=0.10)
    ts = s["two_scale"]
    # the most tensile nominal stress of the burl is within the windows' strength
    assert 0 < -ts["pull_off_stress"] <= ts["strength"] * (1 + 1e-9)
    steps = s["steps"]
    assert steps[0]["normal_force"] == pytest.approx(1.5e-3, rel=1e-5)  # the preload
    assert min(x["normal_force"] for x in steps) == force
    # the burl separates: the last state carries almost nothing
    assert abs(steps[-1]["normal_force"]) <= 1e-2 * abs(force)
    # the menisci hold the burl at the preload (as the humid ramp's F_cap) and at pull-off
    assert steps[0]["capillary_force"] < 0 and steps[0]["wetted_area"] > 0
    assert (tmp_path / "out" / "fields.nc").exists()


def test_a_two_scale_pulloff_needs_a_preload_and_one_rh():
    d = pulloff_scenario(**HUMID, **{"load.preload": None})
    with pytest.raises(InputError) as err:
        parse_scenario(d)
    assert "load.preload" in str(err.value)
    d = pulloff_scenario(**{**HUMID, "humidity": {"rh": [0.3, 0.7], "van_der_waals": False}})
    with pytest.raises(InputError) as err:
        parse_scenario(d)
    assert "humidity.rh" in str(err.value)
