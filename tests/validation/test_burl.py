"""Burl shape, textures and waviness: geometry, scenario keys and their errors, a run with a burl,
a texture and roughness together (issue 20 items 1 and 6)."""

from __future__ import annotations

import copy
import math
import warnings

import numpy as np
import pytest

from tribobem import ConvergenceWarning
from tribobem.errors import InputError
from tribobem.geometry import burl, dimples, grooves, pillars, sphere, texture, waviness
from tribobem.grid import Grid
from tribobem.runs.kind import BODY_KEYS
from tribobem.runs import KINDS
from tribobem.scenario import parse_scenario, run_scenario
from tribobem.scenario.build import build_problem
from tribobem.scenario.schema import ScenarioError


# ----------------------------------------------------------------------------- geometry
def test_burl_profile_flat_top_rounded_edge_and_crown():
    g = Grid.square(64, 8e-6)
    b, R, Rc = 2e-6, 10e-6, 1e-3
    r = g.radius() if hasattr(g, "radius") else np.hypot(*g.meshgrid())
    h = burl(g, b, R)
    assert np.all(h[r <= b] == 0.0)
    out = r > b
    assert np.allclose(h[out], (r[out] - b) ** 2 / (2 * R), rtol=1e-14, atol=0)
    # the shape convention of the sphere: heights >= 0, positive away from the interface
    assert h.min() == 0.0 and np.all(h >= 0)
    hc = burl(g, b, R, crown=Rc)
    assert np.allclose(hc - h, sphere(g, Rc), rtol=1e-14, atol=0)
    with pytest.raises(InputError, match="shape.edge_radius"):
        burl(g, b, 0.0)


def test_textures_signs_sizes_and_periodicity():
    p, s, d = 1e-6, 0.5e-6, 10e-9
    g = Grid.square(128, 4 * p, periodic=True)  # 32 cells per pitch
    hp = pillars(g, p, s, d)
    hd = dimples(g, p, s, d)
    assert set(np.unique(hp)) == {0.0, d} and set(np.unique(hd)) == {-d, 0.0}
    assert np.array_equal(hp > 0, hd < 0)
    # 16 features, each a disc of diameter s (not radius s): area within the sampling bound
    frac = np.count_nonzero(hp) / hp.size
    assert frac == pytest.approx(math.pi * s * s / (4 * p * p), rel=0.1)
    # periodic with the pitch: shifting by one pitch (32 cells) changes nothing
    assert np.array_equal(np.roll(hp, 32, axis=0), hp) and np.array_equal(np.roll(hp, 32, axis=1), hp)
    # grooves along x at angle 0: constant in x, width s out of every pitch
    hg = grooves(g, p, s, d)
    assert np.all(hg == hg[:1, :])
    assert np.count_nonzero(hg[0]) / g.ny == pytest.approx(s / p, abs=1 / 32)
    hg90 = grooves(g, p, s, d, angle=90.0)
    assert np.array_equal(hg90, hg.T)


def test_texture_finer_than_three_cells_is_refused_naming_the_key():
    g = Grid.square(64, 4e-6)  # dx = 62.5 nm: 3 cells = 187.5 nm
    with pytest.raises(InputError, match=r"body1\.texture\.size"):
        texture(g, "pillars", 1e-6, 0.15e-6, 1e-9, key="body1.texture")
    with pytest.raises(InputError, match=r"body1\.texture\.pitch"):
        texture(g, "dimples", 1e-6, 0.9e-6, 1e-9, key="body1.texture")
    texture(g, "grooves", 1e-6, 0.2e-6, 1e-9)  # 3.2 cells: fine


def test_waviness_is_a_cosine_along_its_angle():
    g = Grid.square(64, 10e-6, periodic=True)
    h = waviness(g, 5e-9, 5e-6)
    X, _ = g.meshgrid()
    assert np.allclose(h, 5e-9 * np.cos(2 * np.pi * X / 5e-6), rtol=0, atol=1e-22)
    assert np.allclose(waviness(g, 5e-9, 5e-6, angle=90.0), h.T, rtol=0, atol=1e-22)
    with pytest.raises(InputError, match="waviness.wavelength"):
        waviness(g, 5e-9, 0.2e-6)


# ----------------------------------------------------------------------------- scenario
BASE = {
    "kind": "normal",
    "grid": {"n": 64, "size": "8 um"},
    "body1": {"E": "130 GPa", "nu": 0.28,
              "roughness": {"kind": "gaussian", "rms": "0.5 nm", "correlation_length": "0.5 um", "seed": 3},
              "texture": {"kind": "dimples", "pitch": "1.5 um", "size": "0.6 um", "depth": "20 nm"},
              "waviness": {"amplitude": "2 nm", "wavelength": "8 um"}},
    "body2": {"rigid": True, "shape": {"kind": "burl", "radius": "2 um", "edge_radius": "50 um", "crown": "5 mm"}},
    "load": {"force": "2 mN"},
    "output": {"figures": False, "report": False},
}


def _with(path, value):
    d = copy.deepcopy(BASE)
    node = d
    for k in path[:-1]:
        node = node[k]
    if value is None:
        node.pop(path[-1])
    else:
        node[path[-1]] = value
    return d


def test_every_kind_reads_the_new_body_keys():
    assert {"texture", "waviness"} <= BODY_KEYS
    for kind in KINDS.values():
        reads = kind.reads()
        assert {"texture", "waviness"} <= set(reads["body1"]) and {"texture", "waviness"} <= set(reads["body2"])


@pytest.mark.parametrize("path, value, key", [
    (("body1", "texture", "foo"), 1, "body1.texture.foo"),
    (("body1", "texture", "size"), "2 N", "body1.texture.size"),
    (("body1", "texture", "depth"), "-5 nm", "body1.texture.depth"),
    (("body1", "texture", "pitch"), 0, "body1.texture.pitch"),
    (("body1", "texture", "kind"), "bumps", "body1.texture.kind"),
    (("body1", "texture", "size"), "1.5 um", "body1.texture.size"),       # not smaller than the pitch
    (("body1", "texture", "size"), "0.1 um", "body1.texture.size"),       # 0.8 cells
    (("body1", "texture", "pitch"), "0.7 um", "body1.texture.pitch"),     # gap of 0.8 cells
    (("body1", "texture", "angle"), "3 nm", "body1.texture.angle"),
    (("body1", "waviness", "amplitude"), "-1 nm", "body1.waviness.amplitude"),
    (("body1", "waviness", "wavelength"), "0.2 um", "body1.waviness.wavelength"),
    (("body1", "waviness", "phase"), 0, "body1.waviness.phase"),
    (("body2", "shape", "edge_radius"), None, "body2.shape.edge_radius"),
    (("body2", "shape", "crown"), "-1 mm", "body2.shape.crown"),
    (("body2", "shape", "radius"), "5 um", "body2.shape.radius"),         # wider than half the domain
])
def test_schema_errors_name_the_key(path, value, key):
    with pytest.raises(ScenarioError) as info:
        parse_scenario(_with(path, value))
    assert any(f == key for f, _ in info.value.errors), info.value.errors


def test_a_grid_sized_by_a_file_is_checked_when_built(tmp_path):
    # without grid.size the schema cannot check the cells; build_problem does, naming the key
    np.save(tmp_path / "h.npy", np.zeros((64, 64)))
    d = _with(("grid", "size"), None)
    d["body1"]["roughness"] = {"kind": "array", "path": str(tmp_path / "h.npy"), "size": "8 um"}
    d["body1"]["texture"]["size"] = "0.1 um"
    sc = parse_scenario(d)
    with pytest.raises(InputError, match=r"body1\.texture\.size"):
        build_problem(sc, tmp_path)


def test_gap_adds_shape_texture_waviness_and_roughness():
    sc = parse_scenario(BASE)
    pb = build_problem(sc)
    g = pb.grid
    plain = build_problem(parse_scenario(_with(("body1", "texture"), None)))
    tex = dimples(g, 1.5e-6, 0.6e-6, 20e-9)
    wav = waviness(g, 2e-9, 8e-6)
    assert np.allclose(pb.roughness1 - plain.roughness1, tex, rtol=0, atol=1e-18)
    shape = burl(g, 2e-6, 50e-6, crown=5e-3)
    assert np.allclose(pb.shape2, shape, rtol=0, atol=0)
    expect = shape - pb.roughness1
    assert np.allclose(pb.gap, expect - expect.min(), rtol=0, atol=1e-18)
    # the roughness statistics are those of the roughness proper, not of the texture
    assert pb.info["roughness"]["body1"]["rms_height"] == pytest.approx(0.5e-9, rel=0.35)
    nowav = build_problem(parse_scenario(_with(("body1", "waviness"), None)))
    assert np.allclose(pb.roughness1 - nowav.roughness1, wav, rtol=0, atol=1e-18)


def test_scenario_with_burl_texture_and_roughness_runs():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ConvergenceWarning)
        r = run_scenario(BASE, outdir=None, progress=False)
    assert r.converged
    step = r.summary["steps"][-1]
    assert step["normal_force"] == pytest.approx(2e-3, rel=1e-6)
    # the dimples cut holes out of the burl's contact: less than the crowned top's area
    assert 0 < step["contact_area"] < math.pi * (2e-6) ** 2


def test_pulloff_kind_with_a_flat_burl_meets_kendall():
    # the validation's quick Kendall problem (d/b = 0.1, 3 cells on d) through a scenario file
    from tribobem.analytic.punch import kendall_pull_off
    from tribobem.validation.burl import kendall_problem

    grid, _, gap, adh, E = kendall_problem(0.1, 3.0)
    edge_radius = grid.dx**2 / (40.0 * adh.h0)
    sc = {"kind": "pulloff", "grid": {"n": grid.nx, "size": grid.lx},
          "body1": {"E": 0.75e9, "nu": 0.5}, "body2": {"rigid": True, "shape": {
              "kind": "burl", "radius": 1e-6, "edge_radius": edge_radius}},
          "adhesion": {"work_of_adhesion": adh.work_of_adhesion, "z0": adh.z0},
          "load": {"steps": 16, "refine": 6}, "solver": {"tolerance": 1e-9},
          "output": {"figures": False, "report": False, "fields": "none"}}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ConvergenceWarning)
        r = run_scenario(sc, outdir=None, progress=False)
    ref = kendall_pull_off(1e-6, adh.work_of_adhesion, E)
    assert r.summary["pull_off_force"] == pytest.approx(ref, rel=0.1)  # tolerance d/b (validation.burl)
