"""Measured topographies (the four example files), Topography operations, errors, the gap."""

import numpy as np
import pytest

from tribobem.errors import InputError, TopographyError
from tribobem.geometry import (
    Topography,
    combine_gap,
    detrend_heights,
    gap_from_bodies,
    read_topography,
    rms_height,
    rms_slope,
    sphere,
    unit_to_metres,
    validate_heights,
)
from tribobem.grid import Grid

from .conftest import TOPOGRAPHY_FILES, TOPOGRAPHY_PLANE

UNITS = {"example_ps.tiff": "µm", "di-3.di": "nm", "spot_1-1000nm.ibw": "m", "plu-1.plu": "µm"}


@pytest.fixture(scope="module")
def measured(topography_dir):
    """Each example file read once with only the mean removed (detrend center: the README's
    first rms column)."""
    return {name: read_topography(topography_dir / name, detrend="center") for name in TOPOGRAPHY_FILES}


# ----------------------------------------------------------------------------- the example files
@pytest.mark.parametrize("name", sorted(TOPOGRAPHY_FILES))
def test_read_measured_file(measured, name):
    shape, size, rms, slope = TOPOGRAPHY_FILES[name]
    t = measured[name]
    assert t.grid.shape == shape and t.heights.shape == shape
    assert t.grid.lx == pytest.approx(size[0], rel=1e-3) and t.grid.ly == pytest.approx(size[1], rel=1e-3)
    assert not t.grid.periodic
    assert rms_height(t.heights) == pytest.approx(rms, rel=0.005)
    assert rms_slope(t.heights, t.grid) == pytest.approx(slope, rel=0.02)
    assert abs(t.heights.mean()) < 1e-10 * rms
    assert t.info["original_unit"] == UNITS[name]
    assert t.info["unit_factor"] == pytest.approx(unit_to_metres(UNITS[name]))
    assert t.source.endswith(name) and t.info["filled_points"] == 0
    s = t.stats()
    assert s["rms_height"] == pytest.approx(rms, rel=0.005) and s["rms_slope"] == pytest.approx(slope, rel=0.02)


def test_ibw_channels(topography_dir, measured):
    t = measured["spot_1-1000nm.ibw"]
    assert t.info["channel"] == "HeightTrace" and t.info["channel_index"] == 0
    assert len(t.info["channels"]) == 8
    r = read_topography(topography_dir / "spot_1-1000nm.ibw", channel="heightretrace")
    assert r.info["channel"] == "HeightRetrace"
    assert r.info["channel_index"] == read_topography(topography_dir / "spot_1-1000nm.ibw", channel=1).info["channel_index"]
    assert not np.array_equal(r.heights, t.heights)
    with pytest.raises(TopographyError, match="HeightTrace") as e:
        read_topography(topography_dir / "spot_1-1000nm.ibw", channel="Deflection")
    assert e.value.field == "topography.channel"
    with pytest.raises(TopographyError, match="out of range"):
        read_topography(topography_dir / "spot_1-1000nm.ibw", channel=8)


def test_non_height_channel(topography_dir):
    with pytest.raises(TopographyError, match="not a height channel") as e:
        read_topography(topography_dir / "di-3.di", channel="Phase")
    assert e.value.field == "topography.channel"


def test_detrend_modes_on_file(topography_dir, measured):
    path = topography_dir / "di-3.di"
    center = measured["di-3.di"]
    tilt = read_topography(path, detrend="height")
    curv = read_topography(path, detrend="curvature")
    raw = read_topography(path, detrend="none")
    assert rms_height(curv.heights) <= rms_height(tilt.heights) <= rms_height(center.heights)
    assert np.allclose(raw.heights - raw.heights.mean(), center.heights, rtol=0, atol=1e-15)
    assert np.allclose(raw.detrended("height").heights, tilt.heights, rtol=0, atol=1e-15)
    with pytest.raises(InputError, match="topography.detrend"):
        read_topography(path, detrend="quartic")


def test_resample_measured(measured):
    t = measured["plu-1.plu"]
    g = Grid(96, 96, 0.9e-3, 0.9e-3)
    r = t.resample(g)
    assert r.grid == g and r.heights.shape == (96, 96)
    assert np.all(np.isfinite(r.heights))
    assert r.heights.max() <= t.heights.max() and r.heights.min() >= t.heights.min()


# ----------------------------------------------------------------------------- errors
def test_missing_file(tmp_path):
    with pytest.raises(TopographyError, match="not found") as e:
        read_topography(tmp_path / "nope.di")
    assert e.value.field == "topography.path"


def test_empty_file(tmp_path):
    p = tmp_path / "empty.txt"
    p.write_bytes(b"")
    with pytest.raises(TopographyError, match="empty") as e:
        read_topography(p)
    assert e.value.field == "topography.path" and "empty.txt" in str(e.value)


def test_garbage_file(tmp_path):
    p = tmp_path / "garbage.dat"
    p.write_bytes(np.random.default_rng(0).integers(0, 256, 2000, dtype=np.uint8).tobytes())
    with pytest.raises(TopographyError, match="cannot read") as e:
        read_topography(p)
    assert "garbage.dat" in str(e.value) and len(str(e.value)) < 800


def test_line_scan_rejected(tmp_path):
    p = tmp_path / "line.txt"
    p.write_text("0 1\n1 2\n2 1.5\n3 0.2\n")
    with pytest.raises(TopographyError, match="line scan") as e:
        read_topography(p, unit="nm")
    assert e.value.field == "topography.grid"


@pytest.fixture
def npy_with_nan(tmp_path):
    h = np.random.default_rng(1).standard_normal((20, 16))
    h[3:6, 4:7] = np.nan
    p = tmp_path / "holes.npy"
    np.save(p, h)
    return p


def test_npy_needs_sizes_and_unit(npy_with_nan):
    with pytest.raises(TopographyError, match="physical_sizes"):
        read_topography(npy_with_nan)
    with pytest.raises(TopographyError, match="unit=") as e:
        read_topography(npy_with_nan, physical_sizes=(2.0, 1.6))
    assert e.value.field == "topography.unit"


def test_undefined_data_filled(npy_with_nan):
    t = read_topography(npy_with_nan, physical_sizes=(2.0, 1.6), unit="nm")
    assert t.info["filled_points"] == 9 and np.all(np.isfinite(t.heights))
    assert t.grid.lx == pytest.approx(2e-9) and t.grid.ly == pytest.approx(1.6e-9)


def test_undefined_data_not_filled(npy_with_nan):
    with pytest.raises(TopographyError, match="9 undefined") as e:
        read_topography(npy_with_nan, physical_sizes=(2.0, 1.6), unit="nm", fill="none")
    assert e.value.field == "topography.heights"


def test_nan_heights_rejected():
    g = Grid(4, 3, 1.0, 1.0)
    h = np.zeros(g.shape)
    h[0, 0], h[1, 2] = np.nan, np.inf
    with pytest.raises(InputError, match="2 of 12") as e:
        validate_heights(h, "body1.topography")
    assert e.value.field == "body1.topography"
    with pytest.raises(InputError, match="2 of 12"):
        Topography(h, g)
    with pytest.raises(InputError, match="2D"):
        validate_heights(np.zeros(5))
    with pytest.raises(InputError, match="does not match"):
        validate_heights(np.zeros((3, 4)), grid=g)


def test_units():
    assert unit_to_metres("µm") == 1e-6 and unit_to_metres("\u03bcm") == 1e-6
    assert unit_to_metres("nm") == 1e-9 and unit_to_metres("mm") == 1e-3 and unit_to_metres("m") == 1.0
    assert unit_to_metres("inch") == pytest.approx(0.0254)
    with pytest.raises(InputError, match="topography.unit"):
        unit_to_metres("kg")


# ----------------------------------------------------------------------------- operations
@pytest.fixture
def plane():
    g = Grid(20, 10, 2e-6, 1e-6)
    X, Y = g.meshgrid()
    return Topography(1e-3 * X + 2e-3 * Y + 5e-9, g, "", {"channel": "synthetic"})


def test_window_and_crop(plane):
    w = plane.window(2, 3, 10, 5)
    assert w.grid.shape == (10, 5) and w.grid.lx == pytest.approx(1e-6) and w.grid.ly == pytest.approx(0.5e-6)
    assert np.array_equal(w.heights, plane.heights[2:12, 3:8])
    c = plane.crop(0.2e-6, 0.3e-6, 1.0e-6, 0.5e-6)
    assert np.array_equal(c.heights, w.heights) and c.grid == w.grid
    assert c.info["channel"] == "synthetic" and c.info["history"] == ["window(2, 3, 10, 5)"]
    with pytest.raises(InputError, match="topography.window.x"):
        plane.window(15, 0, 10, 5)
    with pytest.raises(InputError, match="topography.crop"):
        plane.crop(1.5e-6, 0, 1e-6, 0.5e-6)


def test_resample_identity_and_plane(plane):
    same = plane.resample(plane.grid)
    assert np.allclose(same.heights, plane.heights, rtol=1e-14, atol=0)
    fine = Grid(40, 20, 1.6e-6, 0.8e-6)  # a centred sub-window, twice as fine
    r = plane.resample(fine, offset=(0.1e-6, -0.05e-6))
    X, Y = fine.meshgrid()
    expected = 1e-3 * (X + 0.1e-6) + 2e-3 * (Y - 0.05e-6) + 5e-9
    assert np.allclose(r.heights, expected, rtol=0, atol=1e-12 * 5e-9 + 1e-21)
    with pytest.raises(InputError, match="outside"):
        plane.resample(Grid(10, 10, 3e-6, 1e-6))


def test_detrended(plane):
    rough = plane.heights + 1e-10 * np.cos(2 * np.pi * plane.grid.meshgrid()[0] / 0.5e-6)
    t = Topography(rough, plane.grid)
    d = t.detrended("height")
    assert rms_height(d.heights) == pytest.approx(1e-10 / np.sqrt(2), rel=1e-2)
    q = detrend_heights(sphere(plane.grid, 1e-3), plane.grid, "curvature")
    assert np.abs(q).max() < 1e-20
    assert np.array_equal(t.detrended("none").heights, t.heights)


def test_combine_gap():
    g = Grid(8, 8, 1e-6, 1e-6)
    upper = sphere(g, 1e-4)
    lower = np.random.default_rng(0).standard_normal(g.shape) * 1e-9
    gap = combine_gap(lower, upper)
    assert np.array_equal(gap, upper - lower)
    assert np.array_equal(combine_gap(Topography(lower, g), upper), gap)
    assert np.array_equal(gap_from_bodies(g, upper_shape=upper, lower_roughness=lower), gap)
    assert np.array_equal(gap_from_bodies(g, upper_shape=upper, upper_roughness=-lower), gap)
    assert not gap_from_bodies(g).any()
    with pytest.raises(InputError, match="differ in shape"):
        combine_gap(np.zeros((8, 8)), np.zeros((8, 4)))
    with pytest.raises(InputError, match="gap.upper_shape"):
        gap_from_bodies(g, upper_shape=np.zeros((4, 4)))


# ----------------------------------------------------------------------------- default detrend: the plane
def _tilted_scan(tmp_path, n=(48, 40), size=(2e-6, 1.6e-6)):
    """A rough surface (rms ~1 nm) orthogonal to every plane, plus a tilt of ~100 nm over the scan,
    saved as .npy in m. Returns (path, untilted heights, grid)."""
    g = Grid(n[0], n[1], size[0], size[1])
    rough = 1e-9 * np.random.default_rng(7).standard_normal(g.shape)
    rough = detrend_heights(rough, g, "height")   # no plane left in it: the plane fit leaves it as is
    X, Y = g.meshgrid()
    h = rough + 0.05 * X - 0.02 * Y + 3e-8
    path = tmp_path / "tilted.npy"
    np.save(path, h)
    return path, rough, g


def test_read_default_detrend_is_the_plane(tmp_path):
    path, rough, g = _tilted_scan(tmp_path)
    t = read_topography(path, physical_sizes=(g.lx, g.ly), unit="m")
    assert t.info["detrend"] == "height" and t.info["history"][-1] == "detrend(height)"
    assert rms_height(t.heights) == pytest.approx(rms_height(rough), rel=1e-6)
    assert np.allclose(t.heights, rough, rtol=0, atol=1e-6 * rms_height(rough))
    # "center" is still there, and keeps the tilt: rms about 30 x larger
    c = read_topography(path, physical_sizes=(g.lx, g.ly), unit="m", detrend="center")
    assert rms_height(c.heights) > 20 * rms_height(rough)


def test_scenario_file_roughness_default_detrend_is_the_plane(tmp_path):
    from tribobem.scenario import build_problem, parse_scenario
    from tribobem.scenario.schema import FileRoughness

    assert FileRoughness.model_fields["detrend"].default == "height"
    path, rough, g = _tilted_scan(tmp_path, n=(32, 32), size=(1e-6, 1e-6))
    sc = {
        "kind": "normal",
        "grid": {"n": 32, "periodic": False},
        "body1": {"E": "3 GPa", "nu": 0.35,
                  "roughness": {"kind": "file", "path": path.name, "unit": "m", "physical_size": ["1 um", "1 um"]}},
        "body2": {"rigid": True, "shape": {"kind": "sphere", "radius": "10 um"}},
        "load": {"force": "1 uN"},
    }
    prob = build_problem(parse_scenario(sc), base_dir=tmp_path)
    assert prob.grid.shape == (32, 32) and prob.grid.lx == pytest.approx(1e-6)
    assert rms_height(prob.roughness1) == pytest.approx(rms_height(rough), rel=1e-6)
    sc["body1"]["roughness"]["detrend"] = "center"
    # only the mean removed: the tilt (+-25 nm over the 1 um scan) stays, rms about 16 x larger
    assert rms_height(build_problem(parse_scenario(sc), base_dir=tmp_path).roughness1) > 10 * rms_height(rough)


@pytest.mark.parametrize("name", sorted(TOPOGRAPHY_PLANE))
def test_shipped_files_plane_detrended(topography_dir, name):
    """With the plane removed (the default), every shipped scan has a finite correlation length
    (the radial ACF falls below 10 % within half the scan), where only the mean removed left
    three of them (di-3, spot_1-1000nm, plu-1) tilt-dominated, without one."""
    from tribobem.geometry.stats import acf, correlation_length

    rms, slope, corr = TOPOGRAPHY_PLANE[name]
    t = read_topography(topography_dir / name)
    s = t.stats()
    assert s["rms_height"] == pytest.approx(rms, rel=0.005)
    assert s["rms_slope"] == pytest.approx(slope, rel=0.02)
    assert s["correlation_length"] == pytest.approx(corr, rel=0.005)
    assert s["correlation_length"] < 0.5 * min(t.grid.lx, t.grid.ly)
    # the definition: the normalised ACF is above 10 % before it and below just after it
    r, R = acf(t.heights, t.grid)
    rho = R / R[0]
    assert np.all(rho[r < s["correlation_length"]] > 0.1)
    assert rho[np.searchsorted(r, s["correlation_length"])] < 0.1
    if name != "example_ps.tiff":  # that scan is flattened already: the mean alone leaves no tilt
        assert np.isnan(correlation_length(read_topography(topography_dir / name, detrend="center").heights,
                                           t.grid))
