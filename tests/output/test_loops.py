"""Measured friction loops (tribobem.analysis.loops) and the ``compare-loop`` command.

The "measured" loops are generated from the exact Mindlin-Deresiewicz law with noise:
after gross sliding at -mu P, the reloading branch is
``delta - delta_turn = 2 delta0 [1 - (1 - (F - F_turn)/(2 mu P))^(2/3)]``, whose slope is
``K = K0 (1 - (F - F_turn)/(2 mu P))^(1/3)``, ``K0 = 8 a/k = 3 mu P/(2 delta0)``; below mu P
(force control) the branch from -F* has the same form with F_turn = -F*.  Paper F Eq. 3 holds
the branch exactly (c1 = 2 mu P, c2 = 1/(2 delta0), n = 3/2), so the fit must return the exact
slope within the noise.
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
from typer.testing import CliRunner

from tribobem.cli import app
from tribobem.errors import InputError
from tribobem.output.loops import comparison_figure
from tribobem.analysis.loops import (
    MIN_POINTS, compare_loops, fit_branch, last_branch, loop_from_summary, read_loop, stiffness_points,
    turning_points,
)

runner = CliRunner()

# A POM-like contact (Paper F, 50 mN): mu P = 5.2 mN, delta0 = 68.5 nm, stroke 3.37 um.
MU, P = 0.104, 0.05
A_HERTZ, K_COMP = 46.9e-6, 3.295e-9
DELTA0 = 3 * MU * P * K_COMP / (16 * A_HERTZ)
K0 = 8 * A_HERTZ / K_COMP
STROKE = 3.37e-6


def md_force(d, *, stroke=STROKE, cycles=4, mu=MU, P=P, delta0=DELTA0):
    """Force along a displacement path by Mindlin-Deresiewicz with memory of the last reversal
    (gross sliding at |F| = mu P); the virgin curve first."""
    d = np.asarray(d, float)
    F = np.empty_like(d)
    turn_d, turn_F, direction = 0.0, 0.0, 1
    virgin = True
    for i, x in enumerate(d):
        if i > 0:
            step = np.sign(x - d[i - 1])
            if step != 0 and step != direction:
                turn_d, turn_F, direction, virgin = d[i - 1], F[i - 1], int(step), False
        if virgin:
            r = min(abs(x) / delta0, 1.0)
            F[i] = np.sign(x) * mu * P * (1 - (1 - r) ** 1.5)
        else:
            r = min(abs(x - turn_d) / (2 * delta0), 1.0)
            F[i] = turn_F + direction * 2 * mu * P * (1 - (1 - r) ** 1.5)
            F[i] = float(np.clip(F[i], -mu * P, mu * P))
    return F


def md_path(stroke=STROKE, cycles=4, per_branch=1000):
    """0 -> +d/2 -> -d/2 -> +d/2 ... uniformly sampled (a measured record at constant speed)."""
    h = stroke / 2
    parts = [np.linspace(0, h, per_branch // 2)]
    for _ in range(cycles):
        parts += [np.linspace(h, -h, per_branch)[1:], np.linspace(-h, h, per_branch)[1:]]
    return np.concatenate(parts)


def md_slope(F, F_turn, mu=MU, P=P):
    return K0 * (1 - (F - F_turn) / (2 * mu * P)) ** (1 / 3)


def write_csv(path, d, F, header="displacement (um), force (mN)", fd=1e-6, ff=1e-3, sep=", ", comments=()):
    lines = list(comments) + [header] + [f"{a / fd:.9g}{sep}{b / ff:.9g}" for a, b in zip(d, F)]
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")
    return path


def noisy_loop(seed=1, force_noise=0.003, disp_noise=0.002, **kw):
    rng = np.random.default_rng(seed)
    d = md_path(**kw)
    F = md_force(d)
    return (d + disp_noise * DELTA0 * rng.standard_normal(d.size),
            F + force_noise * MU * P * rng.standard_normal(d.size))


def cheb_summary(steps=96, cycles=4, stroke=STROKE, direction=0.0):
    """A summary.json of a displacement-controlled hysteresis run whose steps follow the exact
    Mindlin-Deresiewicz loop at the runner's Chebyshev-cosine steps."""
    from tribobem.solvers.hysteresis import cycle_path

    path = cycle_path(stroke / 2, cycles, steps, "displacement")
    d = np.concatenate([[0.0], path.values])
    F = md_force(d)
    t = math.radians(direction)
    rows = [{"tangential_force_x": f * math.cos(t), "tangential_force_y": f * math.sin(t),
             "displacement_x": x * math.cos(t), "displacement_y": x * math.sin(t), "cycle": int(c),
             "branch": b, "converged": True}
            for f, x, c, b in zip(F, d, np.concatenate([[0], path.cycle]), ["start"] + list(path.branch))]
    return {"kind": "hysteresis", "converged": True, "friction_coefficient": MU, "repulsive_force": P,
            "inputs": {"friction": {"direction": direction}}, "steps": rows}


@pytest.fixture
def result_dir(tmp_path):
    folder = tmp_path / "sim"
    folder.mkdir()
    (folder / "summary.json").write_text(json.dumps(cheb_summary()), encoding="utf-8")
    return folder


@pytest.fixture
def measured_csv(tmp_path):
    d, F = noisy_loop()
    return write_csv(tmp_path / "measured.csv", d, F, comments=("# generated Mindlin-Deresiewicz loop, noise",))


# ----------------------------------------------------------------------------- reading
def test_read_loop_units_um_mN(measured_csv):
    loop = read_loop(measured_csv)
    d, F = noisy_loop()
    assert len(loop) == d.size
    np.testing.assert_allclose(loop.displacement, d, rtol=1e-7, atol=1e-15)
    np.testing.assert_allclose(loop.force, F, rtol=1e-7, atol=1e-12)
    assert loop.force_scale == pytest.approx(np.abs(F).max(), rel=1e-7)
    assert "max |F|" in loop.normalisation
    assert loop.units == {"displacement": "um", "force": "mN"}
    assert loop.lines[0] == 3  # comment and header lines counted


@pytest.mark.parametrize("header,sep,fd,ff", [
    ("displacement [nm];force [N]", ";", 1e-9, 1.0),
    ("time (s)\tdisplacement (µm)\tfriction force (uN)", "\t", 1e-6, 1e-6),
    ("Delta_x (micron), Fx (mN)", ",", 1e-6, 1e-3),
])
def test_read_loop_header_variants(tmp_path, header, sep, fd, ff):
    d, F = md_path(per_branch=40), None
    F = md_force(d)
    p = tmp_path / "loop.csv"
    if header.startswith("time"):
        lines = [header] + [f"{i}{sep}{a / fd:.9g}{sep}{b / ff:.9g}" for i, (a, b) in enumerate(zip(d, F))]
        p.write_text("\n".join(lines), encoding="utf-8")
    else:
        write_csv(p, d, F, header=header, fd=fd, ff=ff, sep=sep)
    loop = read_loop(p)
    np.testing.assert_allclose(loop.displacement, d, rtol=1e-7, atol=1e-15)
    np.testing.assert_allclose(loop.force, F, rtol=1e-7, atol=1e-13)


@pytest.mark.parametrize("content,line,needle", [
    ("displacement, force\n" + "1, 2\n" * 12, 1, "no unit"),
    ("displacement (um), force\n" + "1, 2\n" * 12, 1, "no unit"),
    ("displacement (furlongz), force (mN)\n" + "1, 2\n" * 12, 1, "furlongz"),
    ("displacement (mN), force (mN)\n" + "1, 2\n" * 12, 1, "not a length"),
    ("displacement (um), force (um)\n" + "1, 2\n" * 12, 1, "not a force"),
    ("displacement (um), force (mN)\n" + "1, 2\n" * 5 + "1, abc\n" + "1, 2\n" * 6, 7, "not a number"),
    ("displacement (um), force (mN)\n" + "1, 2\n" * 3 + "nan, 2\n" + "1, 2\n" * 8, 5, "NaN"),
    ("displacement (um), force (mN)\n" + "1, 2\n" * 3 + "1, inf\n" + "1, 2\n" * 8, 5, "infinite"),
    ("displacement (um), force (mN)\n" + "1, 2\n" * 3 + "1\n" + "1, 2\n" * 8, 5, "column"),
    ("# comment\n\ndisplacement (um), force (mN)\n" + "1, 2\n" * 3 + "x, 2\n", 7, "not a number"),
    ("1, 2\n" * 12, 1, "no header"),
    ("time (s), height (um)\n" + "1, 2\n" * 12, 1, "displacement column"),
    ("displacement (um) force (mN)\n" + "1 2\n" * 12, 1, "separated"),
])
def test_read_loop_errors_name_file_and_line(tmp_path, content, line, needle):
    p = tmp_path / "bad_loop.csv"
    p.write_text(content, encoding="utf-8")
    with pytest.raises(InputError) as err:
        read_loop(p)
    msg = str(err.value)
    assert "bad_loop.csv" in msg and f"line {line}" in msg and needle in msg, msg


@pytest.mark.parametrize("content,needle", [
    ("", "empty"),
    ("# only a comment\n", "empty"),
    ("displacement (um), force (mN)\n" + "1, 2\n" * (MIN_POINTS - 1), f"at least {MIN_POINTS}"),
    ("displacement (um), force (mN)\n" + "1, 2\n1, 3\n" * 8, "displacement is constant"),
])
def test_read_loop_errors_whole_file(tmp_path, content, needle):
    p = tmp_path / "short.csv"
    p.write_text(content, encoding="utf-8")
    with pytest.raises(InputError, match=needle) as err:
        read_loop(p)
    assert "short.csv" in str(err.value)


def test_read_loop_missing_and_binary(tmp_path):
    with pytest.raises(FileNotFoundError):
        read_loop(tmp_path / "nope.csv")
    p = tmp_path / "bin.csv"
    p.write_bytes(b"\xff\xfe\x00\x81garbage")
    with pytest.raises(InputError, match="UTF-8"):
        read_loop(p)


# ----------------------------------------------------------------------------- branches and the fit
def test_turning_points_ignore_noise():
    d, _ = noisy_loop(disp_noise=0.5)  # 0.5 delta0 of displacement noise: still 2 reversals per cycle
    tp = turning_points(d)
    kinds = [k for _, k in tp]
    assert kinds.count("max") == 4 and kinds.count("min") == 4, kinds
    i0, i1 = last_branch(d)
    assert d[i1] - d[i0] > 0.9 * np.ptp(d)
    assert i0 == [i for i, k in tp if k == "min"][-1]


def test_measured_md_loop_gives_exact_branch_slope(measured_csv):
    loop = read_loop(measured_csv)
    fit = fit_branch(loop)
    assert fit.sliding and fit.points >= 30
    assert fit.turn_force == pytest.approx(-MU * P, rel=0.02)
    assert fit.n == pytest.approx(1.5, rel=0.05)
    for row in stiffness_points(loop, fit):
        exact = md_slope(row["force"], -MU * P)
        assert row["stiffness"] == pytest.approx(exact, rel=0.03), row


def test_force_controlled_loop_without_sliding(tmp_path):
    """A branch from -F* to +F* (F* = 0.8 mu P) has no plateau: fitted whole; the measured scale is
    F* = max |F|, so A, B, C lie at -0.4, 0, 0.4 mu P."""
    Fs = 0.8 * MU * P
    up = np.linspace(-Fs, Fs, 400)
    r = Fs / (MU * P)
    # reloading branch from -F* and the unloading branch, two cycles
    dn = lambda Q: DELTA0 * (2 * (1 - (Fs - Q) / (2 * MU * P)) ** (2 / 3) - (1 - r) ** (2 / 3) - 1)  # noqa: E731
    dr = lambda Q: -DELTA0 * (2 * (1 - (Fs + Q) / (2 * MU * P)) ** (2 / 3) - (1 - r) ** (2 / 3) - 1)  # noqa: E731
    F = np.concatenate([up[::-1], up[1:], up[::-1][1:], up[1:]])
    d = np.concatenate([dn(up[::-1]), dr(up[1:]), dn(up[::-1][1:]), dr(up[1:])])
    rng = np.random.default_rng(3)
    F = F + 0.002 * MU * P * rng.standard_normal(F.size)
    loop = read_loop(write_csv(tmp_path / "force.csv", d, F))
    fit = fit_branch(loop)
    assert not fit.sliding
    for row in stiffness_points(loop, fit):
        assert row["force"] == pytest.approx(row["force_ratio"] * Fs, rel=0.02)
        assert row["stiffness"] == pytest.approx(md_slope(row["force"], -Fs), rel=0.03), row


def test_simulated_loop_from_summary(result_dir):
    loop = loop_from_summary(result_dir)
    assert loop.kind == "simulated" and loop.force_scale == pytest.approx(MU * P)
    assert "mu F0+" in loop.normalisation
    fit = fit_branch(loop)
    assert fit.sliding and fit.points >= 5
    assert fit.start == len(loop) - 49  # the last reloading branch: 48 steps after its turning point
    for row in stiffness_points(loop, fit):
        assert row["stiffness"] == pytest.approx(md_slope(row["force"], -MU * P), rel=0.01)


def test_simulated_loop_projects_on_the_direction(tmp_path):
    s = cheb_summary(direction=30.0)
    loop = loop_from_summary(s)
    ref = loop_from_summary(cheb_summary())
    np.testing.assert_allclose(loop.force, ref.force, atol=1e-15)
    np.testing.assert_allclose(loop.displacement, ref.displacement, atol=1e-20)


def test_too_coarse_simulated_loop_names_steps():
    with pytest.raises(InputError, match="more steps per cycle"):
        fit_branch(loop_from_summary(cheb_summary(steps=16)))


def test_not_a_hysteresis_result(tmp_path):
    (tmp_path / "summary.json").write_text(json.dumps({"kind": "normal", "steps": []}), encoding="utf-8")
    with pytest.raises(InputError, match="'normal' run"):
        loop_from_summary(tmp_path)
    with pytest.raises(InputError, match="no summary.json"):
        loop_from_summary(tmp_path / "..")


def test_compare_loops_library(result_dir, measured_csv, tmp_path):
    fig = tmp_path / "cmp.png"
    cmp = compare_loops(result_dir, measured_csv)
    assert cmp.figure is None
    assert comparison_figure(cmp, fig) == fig and cmp.figure == fig
    assert fig.is_file() and fig.stat().st_size > 10_000
    assert [r["point"] for r in cmp.rows] == ["A", "B", "C"]
    for r in cmp.rows:
        assert r["ratio"] == pytest.approx(1.0, abs=0.04), r
    d = cmp.as_dict()
    json.dumps(d)
    assert d["ratio"] == "simulated / measured"
    assert d["measured"]["fit"]["points"] >= 30


# ----------------------------------------------------------------------------- CLI
def test_cli_compare_loop_table_and_figure(result_dir, measured_csv):
    res = runner.invoke(app, ["compare-loop", str(result_dir), str(measured_csv)])
    assert res.exit_code == 0, res.output
    for word in ("K_L simulated", "K_L measured", "A", "B", "C", "mu F0+", "max |F|", "compare_loop.png"):
        assert word in res.output, word
    assert (result_dir / "compare_loop.png").is_file()


def test_cli_compare_loop_json_and_out(result_dir, measured_csv, tmp_path):
    out = tmp_path / "figs" / "overlay.png"
    out.parent.mkdir()
    res = runner.invoke(app, ["compare-loop", str(result_dir), str(measured_csv), "--json", "--out", str(out),
                              "--no-center"])
    assert res.exit_code == 0, res.output
    data = json.loads(res.stdout)
    assert out.is_file() and data["figure"] == str(out)
    pts = {p["point"]: p for p in data["points"]}
    for name, ratio in (("A", -0.5), ("B", 0.0), ("C", 0.5)):
        exact = md_slope(ratio * MU * P, -MU * P)
        assert pts[name]["simulated_stiffness"] == pytest.approx(exact, rel=0.01)
        assert pts[name]["measured_stiffness"] == pytest.approx(exact, rel=0.04)
    assert "max |F|" in data["measured"]["normalisation"]


def test_cli_compare_loop_summary_file_and_quiet(result_dir, measured_csv):
    res = runner.invoke(app, ["compare-loop", str(result_dir / "summary.json"), str(measured_csv), "-q"])
    assert res.exit_code == 0, res.output
    assert res.output.strip().endswith("compare_loop.png")


@pytest.mark.parametrize("content,needle", [
    ("displacement, force\n" + "1, 2\n" * 12, "line 1"),
    ("displacement (um), force (mN)\n" + "1, 2\n" * 4 + "1, nan\n" + "1, 2\n" * 8, "line 6"),
    ("displacement (um), force (mN)\n" + "1, 2\n" * 3, "at least"),
])
def test_cli_compare_loop_bad_file_exit_2(result_dir, tmp_path, content, needle):
    p = tmp_path / "broken.csv"
    p.write_text(content, encoding="utf-8")
    res = runner.invoke(app, ["compare-loop", str(result_dir), str(p)])
    assert res.exit_code == 2
    assert "broken.csv" in res.output and needle in res.output, res.output
    assert "Traceback" not in res.output and len(res.output.strip().splitlines()) == 1


def test_cli_compare_loop_missing_inputs_exit_2(result_dir, measured_csv, tmp_path):
    res = runner.invoke(app, ["compare-loop", str(tmp_path / "none"), str(measured_csv)])
    assert res.exit_code == 2 and "not found" in res.output
    res = runner.invoke(app, ["compare-loop", str(result_dir), str(tmp_path / "none.csv")])
    assert res.exit_code == 2 and "not found" in res.output
    (tmp_path / "normal").mkdir()
    (tmp_path / "normal" / "summary.json").write_text(json.dumps({"kind": "normal", "steps": []}))
    res = runner.invoke(app, ["compare-loop", str(tmp_path / "normal"), str(measured_csv)])
    assert res.exit_code == 2 and "hysteresis" in res.output


def test_compare_loop_on_a_real_run():
    """A solved Mindlin case (identical steel bodies, smooth, displacement control into gross
    sliding) read back from its result folder: K_L within 10 % of the exact branch slope at 32^2."""
    from tribobem.scenario import run_scenario

    R, E, nu, F0, mu = 10e-3, 210e9, 0.3, 10.0, 0.3
    Es = E / (2 * (1 - nu**2))
    a = (3 * F0 * R / (4 * Es)) ** (1 / 3)
    G = E / (2 * (1 + nu))
    k = 2 * (2 - nu) / G
    d0 = 3 * mu * F0 * k / (16 * a)
    sc = {"kind": "hysteresis", "grid": {"n": 32, "size": 3 * a}, "body1": {"E": E, "nu": nu},
          "body2": {"E": E, "nu": nu, "shape": {"kind": "sphere", "radius": R}}, "load": {"force": F0},
          "friction": {"coefficient": mu,
                       "path": {"control": "displacement", "stroke": 6 * d0, "cycles": 1, "steps": 32}}}
    r = run_scenario(sc, outdir=None, progress=False, quiet=True)
    loop = loop_from_summary(r.summary)
    fit = fit_branch(loop)
    assert fit.sliding
    K0 = 8 * a / k
    for row in stiffness_points(loop, fit):
        exact = K0 * (1 - (row["force"] + mu * F0) / (2 * mu * F0)) ** (1 / 3)
        assert row["stiffness"] == pytest.approx(exact, rel=0.10), row
