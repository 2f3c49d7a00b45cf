"""Outputs of the tangential kinds (partial_slip, hysteresis) from synthetic results: the
fields.nc variables, the stick/slip figures, the report's friction table and warning banner."""

import base64

import numpy as np
import pytest

from tribobem.grid import Grid
from tribobem.output import make_figures, read_fields, render_report, write_fields, write_outputs
from tribobem.output.fields import build_fields
from tribobem.results import CoupledResult, NormalResult, TangentialResult

MU = 0.3
RATIOS = (0.0, 0.3, 0.6, 0.9, 1.0)  # F_x/(mu P); the last one is gross slip


def synthetic_run(n=32, size=2e-6, ratios=RATIOS, mu=MU, force=1e-5, adhesive=True, radius=0.35):
    """A Hertz-like circular contact (radius ``radius`` times size) with a Dugdale ring outside it, and the
    Cattaneo-Mindlin traction for each F_x/(mu P) in ``ratios``: a stick core of radius
    c = a (1 - ratio)^(1/3), a slip annulus where |q| = mu p, shear along +x, slip along -x.

    Returns (grid, normal results, tangential results, summary)."""
    grid = Grid.square(n, size)
    x, y = np.meshgrid(grid.x, grid.y, indexing="ij")
    r = np.hypot(x, y)
    a = radius * size
    inside = r < a
    p = np.where(inside, np.sqrt(np.clip(1 - (r / a) ** 2, 0, None)), 0.0)
    p *= force / (p.sum() * grid.cell_area)  # the compressive part carries `force`
    ring = (r >= a) & (r < 1.2 * a) if adhesive else np.zeros_like(inside)
    sigma0 = 0.05 * p.max()
    pressure = np.where(ring, -sigma0, p)
    p0 = p.max()
    normals, tangentials, rows = [], [], []
    for k, ratio in enumerate(ratios):
        c = a * (1.0 - ratio) ** (1.0 / 3.0)
        stick = inside & (r < c)
        qx = mu * p0 / a * (np.sqrt(np.clip(a**2 - r**2, 0, None)) - np.sqrt(np.clip(c**2 - r**2, 0, None)))
        qx = np.where(inside, qx, 0.0)
        shear = np.stack([qx, np.zeros_like(qx)])
        slip = np.zeros_like(shear)
        slip[0] = np.where(inside & ~stick, -1e-9 * (r / a) * ratio, 0.0)
        delta = 40e-9 * (1.0 - (1.0 - min(ratio, 1.0)) ** (2.0 / 3.0))
        nres = NormalResult(grid=grid, pressure=pressure, gap=np.where(inside, 0.0, 1e-9 * (r / a) ** 2),
                            displacement=np.zeros_like(p), contact=inside, adhesive=ring,
                            force=float(pressure.sum() * grid.cell_area), approach=5e-9, iterations=10 + k,
                            residual_history=np.array([1e-3, 1e-11]), converged=True, time=0.01)
        tres = TangentialResult(grid=grid, shear=shear, slip=slip, relative_displacement=slip.copy(),
                                contact=inside, stick=stick, force_x=float(qx.sum() * grid.cell_area), force_y=0.0,
                                displacement_x=delta, displacement_y=0.0, friction_coefficient=mu, mode="total",
                                control="force", iterations=20 + k, residual_history=np.array([1e-2, 1e-12]),
                                converged=True, gross_slip=not stick.any(), time=0.02)
        normals.append(nres)
        tangentials.append(tres)
        rows.append(CoupledResult(nres, tres, coupling_iterations=3, coupling_history=np.array([1e-2, 1e-9]),
                                  converged=True).scalars())
    onset = next(i for i, t in enumerate(tangentials) if not t.stick.any())
    f0 = normals[0].repulsive_force
    summary = {
        "kind": "partial_slip", "converged": True, "inputs": {"name": "synthetic partial slip"},
        "versions": {"tribobem": "test"}, "timings": {"solve": 1.0}, "steps": rows,
        "friction_coefficient": mu,
        "static_friction_force": tangentials[onset].force_x,
        "static_friction_ratio": tangentials[onset].force_x / (mu * f0),
        "presliding_displacement": tangentials[onset].displacement_x - tangentials[0].displacement_x,
        "gross_slip": True,
        "warnings": ["the tangential ramp went past the gross-slip onset: the last step slides"],
    }
    return grid, normals, tangentials, summary


def _fields(grid, normals, tangentials):
    return build_fields(grid, normals, [f"F_x {i}" for i in range(len(normals))],
                        initial_gap=np.zeros(grid.shape), tangential=tangentials)


@pytest.fixture(scope="module")
def run():
    return synthetic_run()


def _png(path):
    return path.is_file() and path.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" and path.stat().st_size > 5000


def test_fields_have_the_tangential_variables(run):
    grid, normals, tangentials, _ = run
    tangentials = list(tangentials)
    tangentials[1] = None  # a step without a tangential solution
    ds = _fields(grid, normals, tangentials)
    for name, unit in (("shear_x", "Pa"), ("shear_y", "Pa"), ("slip_x", "m"), ("slip_y", "m"), ("stick", "1")):
        assert ds[name].dims == ("step", "x", "y") and ds[name].attrs["units"] == unit
    assert ds["stick"].dtype == np.int8
    for name, unit in (("tangential_force_x", "N"), ("tangential_force_y", "N"), ("displacement_x", "m"),
                       ("displacement_y", "m"), ("stick_ratio", "1")):
        assert name in ds.coords and ds[name].dims == ("step",) and ds[name].attrs["units"] == unit
    t = tangentials[2]
    np.testing.assert_array_equal(ds["shear_x"].values[2], t.shear[0])
    np.testing.assert_array_equal(ds["slip_x"].values[2], t.slip[0])
    np.testing.assert_array_equal(ds["stick"].values[2], t.stick.astype(np.int8))
    assert ds["tangential_force_x"].values[2] == pytest.approx(t.force_x)
    assert ds["displacement_x"].values[2] == pytest.approx(t.displacement_x)
    assert ds["stick_ratio"].values[2] == pytest.approx(t.stick_ratio)
    assert 0 < ds["stick_ratio"].values[2] < 1
    # the missing step: NaN fields and scalars, no stick
    assert np.isnan(ds["shear_x"].values[1]).all() and np.isnan(ds["tangential_force_x"].values[1])
    assert not ds["stick"].values[1].any()
    assert ds.attrs["friction_coefficient"] == MU and ds["slip_x"].attrs["slip_mode"] == "total"
    # the force is the traction times the cell area
    assert ds["shear_x"].values[3].sum() * grid.cell_area == pytest.approx(ds["tangential_force_x"].values[3])


def test_fields_without_tangential_are_unchanged(run):
    grid, normals, _, _ = run
    ds = build_fields(grid, normals, ["a"] * len(normals), initial_gap=np.zeros(grid.shape))
    assert "shear_x" not in ds and "stick" not in ds and "stick_ratio" not in ds.coords
    with pytest.raises(ValueError, match="one entry"):
        build_fields(grid, normals, ["a"] * len(normals), initial_gap=np.zeros(grid.shape), tangential=[None])


def test_fields_round_trip(run, tmp_path):
    grid, normals, tangentials, _ = run
    ds = _fields(grid, normals, [None] + list(tangentials[1:]))
    back = read_fields(write_fields(ds, tmp_path / "fields.nc"))
    for name in ("shear_x", "shear_y", "slip_x", "slip_y", "stick"):
        np.testing.assert_array_equal(back[name].values, ds[name].values)
        assert back[name].attrs["units"] == ds[name].attrs["units"]
    assert back["stick"].dtype == np.int8
    for name in ("tangential_force_x", "tangential_force_y", "displacement_x", "displacement_y", "stick_ratio"):
        np.testing.assert_array_equal(back[name].values, ds[name].values)  # NaN in step 0 included
        assert name in back.coords
    assert back.attrs["friction_coefficient"] == MU


def test_figures_for_a_partial_slip_run(run, tmp_path):
    grid, normals, tangentials, summary = run
    ds = _fields(grid, normals, tangentials)
    figs = make_figures(ds, summary, tmp_path)
    # first step (F_x = 0), the last with stick (ratio 0.9, step 3) and one half-way between
    assert [k for k in figs if k.startswith("stickslip_")] == ["stickslip_step0", "stickslip_step2", "stickslip_step3"]
    assert "stick_ratio" in figs and "stick_normal" not in figs
    assert "force_curve" not in figs  # constant normal force: nothing to show
    assert {"pressure", "contact", "profile", "topography"} <= set(figs)
    for name, path in figs.items():
        assert path == tmp_path / f"{name}.png" and _png(path), name
    assert list(figs)[:2] == ["stick_ratio", "stickslip_step0"]


def test_figures_skip_tangential_ones_for_a_normal_run(run, tmp_path):
    grid, normals, _, _ = run
    ds = build_fields(grid, normals[:2], ["loading 0", "loading 1"], initial_gap=np.zeros(grid.shape))
    rows = [n.scalars() for n in normals[:2]]
    rows[1]["normal_force"] *= 2
    figs = make_figures(ds, {"kind": "normal", "steps": rows}, tmp_path)
    assert not any(k.startswith("stick") for k in figs)
    assert not list(tmp_path.glob("stick*.png"))
    assert "force_curve" in figs


def test_tangential_figures_tolerate_missing_keys(run, tmp_path):
    grid, normals, tangentials, summary = run
    # no mu anywhere, no run-level onset: stick_ratio is drawn against F_x itself
    bare = {"kind": "partial_slip", "steps": [{k: v for k, v in r.items() if k not in ("repulsive_force",)}
                                                for r in summary["steps"]]}
    figs = make_figures(None, bare, tmp_path)
    assert "stick_ratio" in figs and _png(figs["stick_ratio"])
    # rows without the tangential keys, or junk, give no tangential figure and no error
    for steps in ([{"normal_force": 1.0}], [{"tangential_force_x": None, "stick_ratio": "x"}] * 3, []):
        assert not any(k.startswith("stick") for k in make_figures(None, {"steps": steps}, tmp_path / "x"))
    # a dataset whose tangential steps never stick still gets maps (the last step instead)
    ds = _fields(grid, normals[-1:], tangentials[-1:])
    assert list(make_figures(ds, {}, tmp_path / "y")) == ["stickslip_step0", "pressure", "contact", "profile",
                                                         "topography"]


def test_branches_are_drawn_as_separate_lines(run, tmp_path):
    from tribobem.output.figures import _segments

    _, _, _, summary = run
    rows = [dict(r, branch="loading") for r in summary["steps"]]
    rows += [dict(r, branch="unloading", tangential_force_x=-r["tangential_force_x"]) for r in summary["steps"][::-1]]
    segs = _segments(rows)
    assert [b for b, _ in segs] == ["loading", "unloading"]
    assert segs[1][1][0] == segs[0][1][-1]  # connected
    s = dict(summary, steps=rows, kind="hysteresis")
    assert _png(make_figures(None, s, tmp_path)["stick_ratio"])


def test_normal_load_path_figure(tmp_path):
    forces = np.linspace(1e-6, 1e-5, 6)
    rows = [{"normal_force": f, "approach": 1e-9 * (f / 1e-6) ** (2 / 3), "tangential_force_x": 0.0,
             "tangential_force_y": 0.0, "stick_ratio": 0.6 + 0.02 * i, "stick_radius_ratio": 0.77 + 0.01 * i,
             "repulsive_force": f, "converged": True} for i, f in enumerate(forces)]
    figs = make_figures(None, {"kind": "partial_slip", "friction_coefficient": 0.2, "steps": rows}, tmp_path)
    assert "stick_normal" in figs and _png(figs["stick_normal"])
    assert "stick_ratio" not in figs and "force_curve" in figs


def test_report_shows_figures_friction_table_and_warnings(run, tmp_path):
    grid, normals, tangentials, summary = run
    files = write_outputs(tmp_path, summary, _fields(grid, normals, tangentials))
    html = (tmp_path / "report.html").read_text()
    figs = [k for k in files if k not in ("fields", "report", "summary")]
    assert html.count("<img") == len(figs) == html.count("data:image/png;base64,")
    for name in ("stick_ratio", "stickslip_step0", "stickslip_step3"):
        assert f"alt='{name}'" in html
    first = html.split("alt='stick_ratio' src='data:image/png;base64,")[1].split("'")[0]
    assert base64.b64decode(first)[:4] == b"\x89PNG"
    assert "Stick/slip map of step 3" in html and "Stick ratio A_stick" in html
    # friction table, in the report's units
    assert "<h2>Friction</h2>" in html
    assert "friction coefficient \u03bc</th><td class='l'>0.3<" in html
    assert "static friction force" in html and "\u00b5N" in html
    assert "presliding displacement</th><td class='l'>40 nm<" in html
    assert "gross slip reached</th><td class='l'>yes<" in html
    # warning banner, before the key results
    assert "class='warnings'" in html and "went past the gross-slip onset" in html
    assert html.index("class='warnings'") < html.index("Key results")
    # step table with the tangential columns
    head = html.split("<h2>Steps")[1].split("</tr>")[0]
    for col in ("F\u2093", "\u03b4\u2093", "stick ratio", "coupl. iter.", "tang. iter."):
        assert f"<th>{col}</th>" in head


def test_report_of_a_normal_run_has_no_friction_table_nor_banner():
    html = render_report({"kind": "normal", "converged": True, "steps": [{"normal_force": 1e-6, "converged": True}],
                          "warnings": []})
    assert "Friction" not in html and "class='warnings'" not in html and "stick ratio" not in html
