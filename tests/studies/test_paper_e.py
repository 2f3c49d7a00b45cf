"""Paper E section 3.2 study (friction hysteresis of an adhesive rigid ball on an elastic flat):
qualitative facts on small grids (40^2 over +-2a, a few steps per cycle)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from tribobem.errors import InputError
from studies.paper_e import (
    FORCE, FRICTION, PAPER_E_SMOOTH_REPULSIVE_FORCE, WORKS, _points, loop_metrics, loops_table, md_state,
    paper_e_loop, paper_e_problem, summary_table,
)

N = 40


@pytest.fixture(scope="module")
def loop50():
    # dgamma = 50 mJ/m^2: initial loading (4 steps) + 2 cycles of 12 steps.
    return paper_e_loop(0.05, N, steps=12, cycles=2)


@pytest.fixture(scope="module")
def ordering(loop50):
    # The initial loading (4 steps, the same for every steps <= 16) is all the ordering needs.
    short = {w: paper_e_loop(w, N, steps=4, cycles=1) for w in (0.0, 0.1)}
    return [loop_metrics(short[0.0]), loop_metrics(loop50), loop_metrics(short[0.1])]


def test_md_state_and_paper_e_repulsive_force():
    h = md_state(0.0)
    assert h["repulsive_force"] == FORCE and h["adhesive_force"] == 0.0
    assert h["contact_radius"] == h["cohesive_radius"]
    s50, s100 = md_state(0.05), md_state(0.1)
    # Maugis-Dugdale at z0 = 0.2 nm: F0+ close to Paper E's smooth 29.165 uN.
    assert math.isclose(s50["repulsive_force"], PAPER_E_SMOOTH_REPULSIVE_FORCE, rel_tol=0.03)
    for s in (s50, s100):
        assert s["cohesive_radius"] > s["contact_radius"] > h["contact_radius"]
        assert math.isclose(s["repulsive_force"] + s["adhesive_force"], FORCE, rel_tol=1e-12)
    assert s100["repulsive_force"] > s50["repulsive_force"] > FORCE
    with pytest.raises(InputError):
        md_state(-0.01)


def test_problem_domain():
    grid, gap, op, ad, md = paper_e_problem(0.05, 32)
    assert math.isclose(grid.lx, 4.0 * md["contact_radius"], rel_tol=1e-12)
    assert ad is not None and ad.work_of_adhesion == 0.05 and math.isclose(ad.z0, 0.2e-9)
    assert paper_e_problem(0.0, 16)[3] is None
    with pytest.raises(InputError):
        paper_e_problem(0.05, 4)
    with pytest.raises(InputError):
        paper_e_problem(0.05, 32, half_width=1.0)
    with pytest.raises(InputError):
        paper_e_loop(0.05, 16, peak="nope")


def test_points():
    c = np.array([0, 0, 0, 1, 1, 1, 1, 2, 2, 2, 2])
    b = np.array(["start", "loading", "loading", "unloading", "unloading", "reloading", "reloading",
                  "unloading", "unloading", "reloading", "reloading"], dtype=object)
    t = np.array([False, False, True, False, True, False, True, False, True, False, True])
    p = _points(c, b, t)
    assert p == {"A": 0, "A'": 1, "D": 2, "D'": 3, "H": 4, "H'": 5, "L": 6, "L'": 7, "H2": 8, "H2'": 9, "L2": 10}


def test_forces_and_amplitude(loop50):
    lp = loop50
    assert lp.converged.all()
    assert math.isclose(lp.repulsive_force + lp.adhesive_force, FORCE, rel_tol=1e-6)
    assert lp.adhesive_force < 0 < FORCE < lp.repulsive_force
    # F* = 0.999 x the last force with stick on the first loading, below mu F0+ of A.
    lo, hi = lp.onset_bracket
    assert lo < lp.onset_force < hi
    assert math.isclose(lp.peak_force, 0.999 * lo, rel_tol=1e-9)
    assert math.isclose(lp.amplitude, lp.peak_force / (FRICTION * lp.repulsive_force), rel_tol=1e-9)
    m = loop_metrics(lp)
    assert 0.9 < m["onset_ratio"] < 1.0 and m["onset_ratio_start"] < 1.0
    assert m["static_friction"] == pytest.approx(lp.peak_force)
    assert m["static_friction_over_mu_f0"] > 1.0  # adhesion: above mu F0
    assert 0 < m["presliding_displacement"]
    assert lp.under_resolved  # 40^2 over +-2a: about one cell across c - a


def test_stick_ratios_at_the_named_points(loop50):
    m = loop_metrics(loop50)
    assert 0.0 < m["stick_A"] < 0.5          # dissimilar bodies: slip annulus at F = 0
    assert m["stick_A1"] > m["stick_A"]      # A': part of the annulus re-sticks
    assert m["stick_D"] < 0.05               # D: (almost) full slip
    assert m["stick_D1"] > 0.8               # D': almost full stick after the reversal
    assert m["stick_H"] < 0.1 and m["stick_H1"] > 0.8


def test_loops_stationary_and_symmetric(loop50):
    m = loop_metrics(loop50)
    assert m["width_1"] > 0 and m["width_2"] > 0
    assert m["loop_change"] < 0.01
    assert m["stick_branch_asymmetry"] < 0.05
    assert m["branch_point_asymmetry"] < 0.02
    # The first loading shifts the loop toward +x (Paper E 3.2), by less than its half width.
    assert 0 < m["offset_2"] < 0.5 * m["width_2"]
    assert m["loop_energy_1"] > 0 and math.isclose(m["loop_energy_2"], m["loop_energy_1"], rel_tol=0.1)


def test_adhesion_raises_f0p_static_friction_and_presliding(ordering):
    for key in ("repulsive_force", "static_friction", "onset_force", "presliding_displacement",
                "onset_presliding_displacement"):
        v = [m[key] for m in ordering]
        assert v[0] < v[1] < v[2], key
    for m in ordering:
        # The static friction follows mu F0+, not mu F0.
        assert m["onset_over_mu_f0"] == pytest.approx(m["f0p_over_f0"], rel=0.05)


def test_literal_amplitude_is_adapted():
    # F* = 0.999 mu F0+ of A cannot be carried with adhesion (the shear lowers F0+): rerun below.
    lp = paper_e_loop(0.05, 24, steps=4, cycles=1, peak="repulsive", ramp_fractions=(0.5, 0.9))
    assert lp.amplitude_requested == 0.999
    assert math.isfinite(lp.amplitude_limit) and lp.amplitude < lp.amplitude_limit < 0.999


def test_tables(loop50):
    s = summary_table([loop50])
    assert len(s) == 1 and s.loc[0, "paper_e_repulsive_force"] == PAPER_E_SMOOTH_REPULSIVE_FORCE
    t = loops_table([loop50])
    assert len(t) == len(loop50.forces)
    assert list(t.loc[t.point != "", "point"])[:4] == ["A", "A'", "D", "D'"]
    assert set(WORKS) == {0.0, 0.05, 0.1}
