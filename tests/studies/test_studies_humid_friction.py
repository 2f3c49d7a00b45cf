"""The humid-friction study (studies.humid_friction) in its quick mode: 32^2 cells, two RH, a
short loop.  It runs, resumes from its records without recomputing a point, and its table
carries one row per RH plus the dry case, each with every output of the study."""

from __future__ import annotations

import math

import numpy as np
import pytest

from studies import humid_friction as hf


def test_kelvin_radius_and_persson_rh():
    # r_k = gamma V / (R T ln RH): -5.06 nm at 90 % RH (water, 295 K)
    assert hf.kelvin_radius(0.9) == pytest.approx(-5.064e-9, rel=1e-3)
    rh = hf.persson_rh(5e-9)
    assert 2 * abs(hf.kelvin_radius(rh)) == pytest.approx(3 * 5e-9, rel=1e-12)
    assert 0.92 < rh < 0.94


def test_full_sweep_is_the_documented_study(tmp_path):
    from tribobem.scenario.schema import parse_scenario
    from tribobem.sweep import load_sweep

    flat = tmp_path / "flat.npy"
    np.save(flat, np.zeros((4, 4)))  # parsing reads no heights
    spec = load_sweep(hf.sweep_spec(flat))
    kinds = {}
    for _, o in spec.tasks():
        sc = parse_scenario(spec.scenario_for(o))
        kinds[sc.kind] = sc
    assert set(kinds) == {"partial_slip", "hysteresis", "capillary"}
    sc = kinds["hysteresis"]
    assert sc.grid.shape == (256, 256) and sc.grid.lengths[0] == pytest.approx(5e-6) and not sc.grid.periodic
    assert sc.body1.E == 64e9 and sc.body1.nu == 0.17 and sc.body2.rigid
    assert sc.body2.shape.radius == pytest.approx(100e-6) and sc.load.force == pytest.approx(10e-6)
    assert sc.friction.path.cycles == 3 and sc.friction.path.steps == 40
    assert len(sc.humidity.rh) >= 8 and sc.body1.film is not None and sc.body2.film is not None


@pytest.fixture(scope="module")
def quick(tmp_path_factory):
    out = tmp_path_factory.mktemp("humid_friction")
    spec, res = hf.run_study(out, quick=True)
    assert res.n_ok == 3 and res.n_run == 3, res.failed
    return spec, out


def test_quick_study_resumes_without_recomputing(quick):
    spec, out = quick
    records = sorted((out / "points").glob("*.json"))
    stamps = [p.stat().st_mtime_ns for p in records]
    _, res = hf.run_study(out, quick=True)
    assert (res.n_done_before, res.n_run, res.n_ok) == (3, 0, 3)
    assert [p.stat().st_mtime_ns for p in sorted((out / "points").glob("*.json"))] == stamps


def test_quick_table_one_value_per_rh_and_dry(quick, tmp_path):
    spec, out = quick
    table = hf.gather(spec, out)
    assert list(table["case"]) == ["dry"] + ["humid"] * len(hf.QUICK["rh"])
    assert list(table["rh"].iloc[1:]) == list(hf.QUICK["rh"]) and math.isnan(table["rh"].iloc[0])
    for col in ("static_friction_force", "presliding_displacement", "stiffness_A", "stiffness_B", "stiffness_C",
                "dissipated_energy", "capillary_force", "repulsive_force"):
        v = table[col].to_numpy(float)
        assert np.isfinite(v).all(), col
    # the dry case has no meniscus; every humid state is pulled in (F_cap < 0, F0+ > F0)
    h = table[table["case"] == "humid"]
    assert table["capillary_force"].iloc[0] == 0.0
    assert (h["capillary_force"] < 0).all() and (h["repulsive_force"] > hf.FORCE).all()
    assert (h["capillary_kind_force"] < 0).all()
    # the loop: positive energies and stiffnesses
    assert (table["dissipated_energy"] > 0).all()
    assert (table[["stiffness_A", "stiffness_B", "stiffness_C"]].to_numpy(float) > 0).all()
    f = hf.findings(table)
    assert {x["key"] for x in f} == {"cap_rise_fall", "cap_vs_kind", "persson_friction", "persson_area",
                                     "humid_above_dry"}
    assert all(x["verdict"] in {"agrees", "partly", "disagrees", "missing data"} for x in f)
    md = hf.markdown_table(table)
    assert md.count("\n") == 1 + len(table)
    png = hf.plot_study(table, tmp_path / "h.png")
    assert png.stat().st_size > 10_000
