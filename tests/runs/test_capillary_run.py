"""Run kinds ``capillary`` and humid ``pulloff`` (file-contract, issue 8 items 5 and 9).

* Scenario keys: the file-contract capillary block parses to SI; bad values are clear errors naming
  the key (RH outside (0, 1], a non-monotone isotherm, a negative Hamaker constant, ...).
* A sphere on a stiff flat with films over RH at a prescribed approach: the capillary force of
  every RH against the sphere-flat meniscus with films (thesis Eqs. A.27-A.29, solved here by
  root finding, independent of the library), the summary keys, fields.nc and the figures.
* The humid pull-off of the same sphere: one pull-off per RH (a list in RH order) against the
  meniscus force at contact (A.29 with a = 0).
* RH = 1: an error with equilibrium films (an infinite Kelvin radius: no finite film), and with
  dry bodies a zero capillary pressure (the island carries no Laplace pressure).
* Films that reach the relief of the gap are flagged.
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
from scipy.optimize import brentq

from tribobem.errors import InputError
from tribobem.interactions.isotherms import SIO2
from tribobem.interactions.water import GAS_CONSTANT
from tribobem.scenario import parse_scenario, run_scenario
from tribobem.scenario.schema import ScenarioError

T, GAMMA, VM = 295.0, 0.0725, 18.05e-6
R = 1e-6  # sphere radius (m)

#: The file-contract capillary block (every key), on a tiny grid.
SPEC_91 = """
kind = "capillary"
[grid]
n = 16
size = "1 um"
periodic = true
[body1]
E = "64 GPa"
nu = 0.17
film = { isotherm = "SiO2" }
hamaker = "6.5e-20 J"
[body2]
rigid = true
film = { isotherm = "Si" }
hamaker = "19e-20 J"
[load]
force = "1 uN"
[humidity]
rh = [0.3, 0.5, 0.7, 0.9]
temperature = "295 K"
surface_tension = "72.5 mN/m"
molar_volume = "18.05 cm^3/mol"
levelling = "equilibrium"
film_system = "open"
contact_angles = [0.0, 0.0]
cutoff = "0.3 nm"
critical_distance = "0.84 nm"
contribution = "none"
water_hamaker = "3.7e-20 J"
van_der_waals = true
"""


def _spec91() -> dict:
    import tomllib

    return tomllib.loads(SPEC_91)


def test_spec_91_capillary_keys_parse_to_si():
    sc = parse_scenario(_spec91())
    h = sc.humidity
    assert h.rh == [0.3, 0.5, 0.7, 0.9]
    assert h.temperature == 295.0 and h.surface_tension == pytest.approx(0.0725)
    assert h.molar_volume == pytest.approx(18.05e-6) and h.cutoff == pytest.approx(0.3e-9)
    assert h.critical_distance == pytest.approx(0.84e-9) and h.water_hamaker == pytest.approx(3.7e-20)
    assert h.levelling == "equilibrium" and h.system == "open" and h.contribution == "none"
    assert sc.body1.film.isotherm == "SiO2" and sc.body1.hamaker == pytest.approx(6.5e-20)
    assert sc.body2.hamaker == pytest.approx(19e-20)
    # thin_film is a closed system by default (with the disjoining pressure: without it the
    # scenario must give film_time, see tests/interactions/test_thin_film_end_time.py)
    d = _spec91()
    d["humidity"].update(levelling="thin_film", disjoining=True)
    d["humidity"].pop("film_system")
    assert parse_scenario(d).humidity.system == "closed"


@pytest.mark.parametrize("change, field, words", [
    (lambda d: d["humidity"].update(rh=[0.5, 1.5]), "humidity.rh[1]", ["(0, 1]"]),
    (lambda d: d["humidity"].update(rh=[0.0]), "humidity.rh[0]", ["(0, 1]"]),
    (lambda d: d["humidity"].pop("rh"), "humidity.rh", ["required"]),
    (lambda d: d.pop("humidity"), "humidity.rh", ["required"]),
    (lambda d: d["body1"].update(film={"isotherm": {"rh": [0.2, 0.5, 0.8], "thickness": ["1 nm", "0.8 nm", "2 nm"]}}),
     "body1.film.isotherm.thickness", ["increasing"]),
    (lambda d: d["body1"].update(film={"isotherm": {"rh": [0.2, 0.5], "thickness": ["-1 nm", "1 nm"]}}),
     "body1.film.isotherm.thickness", [">= 0"]),
    (lambda d: d["body1"].update(film={"isotherm": "ice"}), "body1.film.isotherm", ["unknown isotherm"]),
    (lambda d: d["body2"].update(hamaker="-19e-20 J"), "body2.hamaker", ["> 0 J"]),
    (lambda d: d["humidity"].update(water_hamaker=-1e-20), "humidity.water_hamaker", ["> 0 J"]),
    (lambda d: d["humidity"].update(contact_angles=[0.0, 190.0]), "humidity.contact_angles[1]", ["[0, 180]"]),
    (lambda d: d["humidity"].update(levelling="thin_film", film_system="open"), "humidity.film_system",
     ["closed"]),
    (lambda d: d["humidity"].update(disjoining=True), "humidity.disjoining", ["levelling = 'thin_film'"]),
    (lambda d: d["humidity"].update(levelling="thin_film", film_system=None, disjoining="yes"),
     "humidity.disjoining", ["true or false"]),
    (lambda d: d["humidity"].update(critical_distance="-1 nm"), "humidity.critical_distance", [">= 0"]),
    (lambda d: d["humidity"].update(isotherm="SiO2"), "humidity.isotherm", ["unknown key"]),
    (lambda d: d["load"].update(force=None, forces=["1 uN", "2 uN"]), "load.forces", ["one load"]),
])
def test_bad_capillary_scenarios_name_the_key(change, field, words):
    d = _spec91()
    change(d)
    d["load"] = {k: v for k, v in d.get("load", {}).items() if v is not None}
    with pytest.raises(ScenarioError) as exc:
        parse_scenario(d)
    fields = [f for f, _ in exc.value.errors]
    assert field in fields, exc.value.errors
    msg = dict(exc.value.errors)[field]
    for w in words:
        assert w in msg, msg


# ----------------------------------------------------------------------------- sphere on flat
def kelvin(rh):
    return GAMMA * VM / (GAS_CONSTANT * T * math.log(rh))


def laplace(rh):
    return GAS_CONSTANT * T * math.log(rh) / VM


def sphere_flat_force(rh, t_ball, t_flat, radius=R, a=0.0):
    """Thesis Eqs. A.27-A.29 (Paper B Eqs. 17-19): the filling angle phi of the toroidal meniscus
    from 1/r2 - 1/r1 = 1/r_k (r_k < 0), then F = pi (R^2 sin^2 phi - a^2) dP_cap."""
    rk = kelvin(rh)

    def f(phi):
        r1 = (radius * (1 - math.cos(phi)) - a * a / radius - (t_ball * math.cos(phi) + t_flat)) / (1 + math.cos(phi))
        return 1.0 / (radius * math.sin(phi)) - 1.0 / r1 - 1.0 / rk

    lo = math.acos(1 - (t_ball + t_flat) / radius) * 1.0001  # r1 > 0 beyond the films' contact
    phi = brentq(f, lo, 0.5)
    return math.pi * (radius**2 * math.sin(phi) ** 2 - a * a) * laplace(rh)


def sphere_scenario(kind="capillary", rh=(0.3, 0.5, 0.7), n=64, size="0.4 um") -> dict:
    """A rigid SiO2 sphere (R = 1 um) at approach 0 (touching) on a stiff elastic flat, SiO2
    films on both, no Dugdale zone, water-solid terms off: only the meniscus pulls (Paper B 4.1)."""
    scn = {
        "kind": kind, "name": "sphere on flat with films",
        "grid": {"n": n, "size": size, "periodic": False},
        "body1": {"E": "1000 GPa", "nu": 0.2, "film": {"isotherm": "SiO2"}},
        "body2": {"rigid": True, "shape": {"kind": "sphere", "radius": "1 um"}, "film": {"isotherm": "SiO2"}},
        "load": {"approach": 0.0},
        "humidity": {"rh": list(rh), "van_der_waals": False},
        "solver": {"tolerance": 1e-9},
    }
    if kind == "pulloff":
        scn["load"] = {"steps": 16, "refine": 4}
    return scn


@pytest.fixture(scope="module")
def sphere_run(tmp_path_factory):
    out = tmp_path_factory.mktemp("capillary")
    r = run_scenario(sphere_scenario(), outdir=out, progress=False)
    return r, out


def test_sphere_flat_capillary_force_against_a27_a29(sphere_run):
    r, _ = sphere_run
    assert r.converged
    for st in r.steps:
        rh = st["rh"]
        e = SIO2.thickness(rh)
        ref = sphere_flat_force(rh, e, e)
        # Paper B 4.1 / issue 8 item 6: within 3 % for RH 0.3-0.7 (island rule vs toroidal meniscus)
        assert st["capillary_force"] == pytest.approx(ref, rel=0.03), (rh, st["capillary_force"], ref)
        # F_cap is dP_cap over the meniscus area outside contact, exactly
        assert st["capillary_force"] == pytest.approx(laplace(rh) * st["wetted_area"], rel=1e-12)
        assert st["capillary_pressure"] == pytest.approx(laplace(rh), rel=1e-12)
        assert st["kelvin_radius"] == pytest.approx(kelvin(rh), rel=1e-12)
        assert st["film_thickness_1"] == pytest.approx(e, rel=1e-6)  # a flat: the isotherm thickness
        assert st["island_count"] == 1
        # no Dugdale zone, water-solid terms off: the meniscus is all that pulls (round-off aside)
        assert abs(st["water_solid_force"]) <= 1e-12 * abs(st["capillary_force"])
        assert st["solid_solid_force"] == 0.0


def test_capillary_summary_fields_figures_report(sphere_run):
    r, out = sphere_run
    s = r.summary
    keys = ("rh", "capillary_force", "solid_solid_force", "water_solid_force", "normal_force", "repulsive_force",
            "contact_area", "wetted_area", "island_count", "kelvin_radius", "film_thickness_1", "film_thickness_2",
            "outer_iterations", "converged")
    for st in s["steps"]:
        for k in keys:
            assert k in st, k
    assert [st["rh"] for st in s["steps"]] == [0.3, 0.5, 0.7]
    fcap = [st["capillary_force"] for st in s["steps"]]
    assert s["peak_capillary_force"] == min(fcap)
    assert s["peak_capillary_rh"] == s["steps"][int(np.argmin(fcap))]["rh"]
    assert s["problem"]["humidity"]["isotherm1"] == "SiO2"
    ds = r.fields
    for name in ("film_thickness_1", "film_thickness_2", "meniscus", "island_labels", "pressure"):
        assert ds[name].dims == ("step", "x", "y")
    assert list(ds["rh"].values) == [0.3, 0.5, 0.7]
    # the meniscus mask is the wetted area of each step
    cell = r.problem.grid.cell_area
    for i, st in enumerate(s["steps"]):
        assert int(ds["meniscus"].values[i].sum()) * cell == pytest.approx(st["wetted_area"], rel=1e-12)
        assert int(ds["island_labels"].values[i].max()) >= 1
    for name in ("capillary_forces.png", "meniscus.png", "fields.nc", "report.html", "summary.json"):
        assert (out / name).is_file(), name
    html = (out / "report.html").read_text(encoding="utf-8")
    assert "Capillary adhesion" in html and "F_cap" in html


def test_fields_last_keeps_the_peak_rh():
    scn = sphere_scenario(rh=(0.3, 0.7), n=32)
    scn["output"] = {"fields": "last", "figures": False, "report": False}
    r = run_scenario(scn, progress=False)
    peak = r.summary["peak_capillary_rh"]
    assert r.fields.sizes["step"] == 1 and float(r.fields["rh"].values[0]) == peak
    assert "film_thickness_1" in r.fields


def test_humid_pulloff_per_rh_against_the_meniscus_at_contact(tmp_path):
    rh = (0.3, 0.5, 0.7)
    r = run_scenario(sphere_scenario("pulloff", rh), outdir=tmp_path, progress=False)
    s = r.summary
    assert r.converged, s["warnings"]
    po = s["pull_off_force"]
    assert isinstance(po, list) and len(po) == 3
    for f, st, h in zip(po, s["steps"], rh):
        e = SIO2.thickness(h)
        ref = sphere_flat_force(h, e, e)  # the meniscus of a sphere touching the flat (a = 0)
        assert st["rh"] == h and st["pull_off_force"] == f
        assert f == pytest.approx(ref, rel=0.03), (h, f, ref)
    curves = s["unloading_curves"]
    assert [c["rh"] for c in curves] == list(rh)
    for c, f in zip(curves, po):
        assert min(c["force"]) == pytest.approx(f, rel=1e-12)
        assert c["force"][-1] == pytest.approx(0.0, abs=1e-3 * abs(f))  # separated at the end
    assert (tmp_path / "pulloff_rh.png").is_file()
    assert "pull-off force per RH" in (tmp_path / "report.html").read_text(encoding="utf-8")


# ----------------------------------------------------------------------------- RH = 1, relief
def test_rh_one_with_equilibrium_films_is_an_error_before_any_solve():
    with pytest.raises(InputError) as exc:
        run_scenario(sphere_scenario(rh=(0.5, 1.0), n=16), progress=False)
    assert exc.value.field == "humidity.rh"
    assert "RH = 1" in str(exc.value) and "Kelvin" in str(exc.value)


def test_rh_one_with_dry_bodies_has_no_laplace_pressure():
    scn = sphere_scenario(rh=(1.0,), n=32)
    for b in ("body1", "body2"):
        scn[b].pop("film")
    r = run_scenario(scn, progress=False)
    st = r.steps[0]
    assert st["kelvin_radius"] == -math.inf or st["kelvin_radius"] is None or not math.isfinite(st["kelvin_radius"])
    assert st["capillary_pressure"] == 0.0 and st["capillary_force"] == 0.0


def test_films_that_reach_the_relief_are_flagged():
    scn = sphere_scenario(rh=(0.9,), n=32)
    scn["grid"]["periodic"] = True
    scn["grid"]["size"] = "0.5 um"
    scn["body2"] = {"rigid": True, "film": {"isotherm": "SiO2"},
                    "roughness": {"kind": "gaussian", "rms": "0.3 nm", "correlation_length": "0.1 um", "seed": 3}}
    scn["load"] = {"force": "1 uN"}
    r = run_scenario(scn, progress=False)
    st = r.steps[0]
    relief = float(np.ptp(r.problem.gap))
    assert st["film_thickness_1"] + st["film_thickness_2"] >= relief
    assert st["films_exceed_relief"] is True
    assert any("relief" in w for w in r.summary["warnings"])


def test_two_rigid_bodies_at_a_prescribed_approach_against_a27_a29(tmp_path):
    """Issue 8 item 6 allows two rigid bodies for capillary runs at a prescribed approach: the
    meniscus force of a rigid sphere touching a rigid flat, within 3 % of A.27-A.29 (RH 0.3-0.7),
    no elastic operator built, the report written."""
    scn = sphere_scenario()
    scn["body1"] = {"rigid": True, "film": {"isotherm": "SiO2"}}
    r = run_scenario(scn, outdir=tmp_path, progress=False)
    assert r.converged
    summary = json.loads((tmp_path / "summary.json").read_text())
    assert summary["problem"]["operator"].startswith("none")
    for st in r.steps:
        e = SIO2.thickness(st["rh"])
        assert st["capillary_force"] == pytest.approx(sphere_flat_force(st["rh"], e, e), rel=0.03)
        # touching rigid bodies: the contact reaction is indeterminate, said so, not a number
        assert st["contact_area"] > 0 and math.isnan(st["repulsive_force"]) and math.isnan(st["normal_force"])
    assert any("indeterminate" in w for w in summary["warnings"])
    assert (tmp_path / "report.html").exists()


@pytest.mark.parametrize("kind, load", [("capillary", {"force": "1 uN"}), ("normal", {"approach": 0.0})])
def test_two_rigid_bodies_elsewhere_are_a_scenario_error(kind, load):
    scn = sphere_scenario()
    scn["kind"], scn["load"] = kind, load
    scn["body1"] = {"rigid": True, "film": {"isotherm": "SiO2"}}
    if kind != "capillary":
        scn.pop("humidity")
        scn["body1"].pop("film")
        scn["body2"].pop("film")
    with pytest.raises(ScenarioError, match="both bodies are rigid"):
        parse_scenario(scn)


def test_humid_pulloff_with_nothing_attracting_names_humidity():
    """At RH <= 0.3 with Paper C's linear_30_60 contribution, van der Waals off and no Dugdale
    zone nothing attracts the bodies: the refusal names the humidity, not a load key the
    scenario does not have (found by the fuzz tests)."""
    from tribobem.errors import InputError
    from tribobem.scenario import run_scenario

    sc = {"kind": "pulloff", "grid": {"n": 16, "size": "0.4 um"},
          "body1": {"E": "70 GPa", "nu": 0.17, "film": {"isotherm": "SiO2"}},
          "body2": {"rigid": True, "shape": {"kind": "sphere", "radius": "0.5 um"}},
          "humidity": {"rh": [0.1], "contribution": "linear_30_60", "van_der_waals": False},
          "output": {"figures": False, "report": False}}
    with pytest.raises(InputError) as exc:
        run_scenario(sc, progress=False)
    assert exc.value.field == "humidity.rh" and "nothing attracts the bodies" in str(exc.value)


def test_capillary_approach_beyond_full_contact_of_a_periodic_cell_is_refused():
    """The same full-contact limit as kind normal (runs.common.approach_below_full_contact)."""
    import numpy as np

    from tribobem.errors import InputError
    from tribobem.scenario import build_problem, load_scenario, run_scenario

    sc = {"kind": "capillary", "grid": {"n": 16, "size": "0.25 um", "periodic": True},
          "body1": {"E": "70 GPa", "nu": 0.17, "film": {"isotherm": "SiO2"}},
          "body2": {"rigid": True, "shape": {"kind": "sphere", "radius": "5 um"}},
          "load": {"approach": "5 nm"}, "humidity": {"rh": [0.5]},
          "output": {"fields": "none", "figures": False, "report": False}}
    assert float(np.mean(build_problem(load_scenario(sc)[0]).gap)) < 5e-9
    with pytest.raises(InputError) as exc:
        run_scenario(sc, progress=False)
    assert exc.value.field == "load.approach" and "full contact of the periodic cell" in str(exc.value)


def test_thin_film_with_disjoining_pressure_ends_on_the_closed_equilibrium():
    """``disjoining = true``: the thin-film levelling of a run stops at its steady state (the
    summary's film and capillary force those of the closed equilibrium), where Paper B's form
    without it has none."""
    from tribobem.interactions.films import film_thickness
    from tribobem.scenario.build import build_problem

    base = {
        "kind": "capillary", "name": "thin film with disjoining pressure",
        "grid": {"n": 32, "size": "1.25 um", "periodic": True},
        "body1": {"E": "70 GPa", "nu": 0.17, "film": {"isotherm": "SiO2"},
                  "roughness": {"kind": "gaussian", "rms": "5 nm", "seed": 1,
                                "correlation_length": "0.5 um"}},
        "body2": {"rigid": True},
        "load": {"force": "1 uN"},
        "humidity": {"rh": [0.5], "van_der_waals": False},
        "output": {"fields": "none", "figures": False, "report": False},
    }
    runs = {}
    for label, hum in (("thin", {"levelling": "thin_film", "disjoining": True}),
                       ("closed", {"levelling": "equilibrium", "film_system": "closed"})):
        sc = {**base, "humidity": {**base["humidity"], **hum}}
        runs[label] = run_scenario(sc, progress=False, quiet=True).summary
        assert runs[label]["converged"] is True
    pb = build_problem(parse_scenario({**base, "humidity": {**base["humidity"], "levelling": "thin_film",
                                                              "disjoining": True}}))
    hs = pb.humidity
    assert hs.disjoining is True and pb.info["humidity"]["disjoining"] is True
    thin = film_thickness(hs.surface1, pb.grid, hs.isotherm1, 0.5, hs.water, mode="thin_film", disjoining=True)
    closed = film_thickness(hs.surface1, pb.grid, hs.isotherm1, 0.5, hs.water, mode="equilibrium", system="closed")
    assert thin.converged and "steady" in thin.message
    # the steady state is the closed equilibrium, up to the grid's Nyquist pressure mode
    assert abs(thin.thickness - closed.thickness).max() < 1e-3 * closed.mean_thickness
    s_thin, s_closed = runs["thin"]["steps"][0], runs["closed"]["steps"][0]
    assert s_thin["film_thickness_1"] == pytest.approx(s_closed["film_thickness_1"], rel=1e-12)
    assert s_thin["capillary_force"] == pytest.approx(s_closed["capillary_force"], rel=1e-3)
