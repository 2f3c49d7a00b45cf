"""Result checks (issue 9 item 1): each warning fires on a state that should trigger it, and not
on one that should not; the measures behind them (cohesive width, gap step, patch width) against
shapes whose answer is known; computed against expected values."""

from __future__ import annotations

import math

import numpy as np
import pytest

from tribobem import DugdaleAdhesion, Grid
from tribobem.output.checks import (CHECKS, cohesive_cells, cohesive_gap_step, compare_expected, patch_width,
                                    result_warnings, scan_pixel, stick_zone_width, warning_names)
from tribobem.results import NormalResult, TangentialResult

ADH = DugdaleAdhesion(0.05, 0.3e-9)
H0 = ADH.h0


def _radius(n, center):
    i, j = np.meshgrid(np.arange(n), np.arange(n), indexing="ij")
    return np.hypot(i + 0.5 - center[0], j + 0.5 - center[1])


def state(n=64, contact_r=10, adhesive_r=None, center=(32, 32), size=1e-6, gap=None):
    """A disc of contact (radius in cells), optionally a cohesive ring to ``adhesive_r``; the gap
    rises linearly from 0 at the contact edge to h0 at the ring's edge, and by h0 per ring width
    beyond it (a resolved Maugis-Dugdale-like profile) unless ``gap`` is given."""
    g = Grid.square(n, size)
    r = _radius(n, center)
    contact = r < contact_r
    adhesive = (r < adhesive_r) & ~contact if adhesive_r else np.zeros_like(contact)
    p = np.where(contact, 1e6, np.where(adhesive, -1e5, 0.0))
    if gap is None:
        w = (adhesive_r - contact_r) if adhesive_r else 1.0
        gap = np.where(contact, 0.0, H0 * np.maximum(r - contact_r, 0.0) / w)
        if not adhesive_r:
            gap = np.where(contact, 0.0, np.maximum(gap, 1.5 * H0))
    z = np.zeros((n, n))
    return NormalResult(grid=g, pressure=p, gap=gap, displacement=z, contact=contact, adhesive=adhesive, force=1.0,
                        approach=0.0, iterations=1, residual_history=np.array([0.0]), converged=True, time=0.0)


def tangential(n=64, contact_r=20, stick_r=10, gross_slip=False, size=1e-6):
    """A contact disc with a central stick disc of radius ``stick_r`` cells (Cattaneo-like)."""
    g = Grid.square(n, size)
    r = _radius(n, (n / 2, n / 2))
    contact = r < contact_r
    stick = (r < stick_r) & contact if not gross_slip else np.zeros_like(contact)
    z2 = np.zeros((2, n, n))
    return TangentialResult(grid=g, shear=z2, slip=z2, relative_displacement=z2, contact=contact, stick=stick,
                            force_x=0.0, force_y=0.0, displacement_x=0.0, displacement_y=0.0, friction_coefficient=0.3,
                            mode="total", control="force", iterations=1, residual_history=np.array([0.0]),
                            converged=True, gross_slip=gross_slip, time=0.0)


def names(ws):
    return warning_names(ws)


# ----------------------------------------------------------------------------- measures
def test_cohesive_width_estimate_of_a_ring():
    # ring from 10 to 16 cells: width 6 cells (area / outer perimeter slightly less for a ring)
    w = cohesive_cells(state(contact_r=10, adhesive_r=16))
    assert 4.0 < w < 7.0


@pytest.mark.parametrize("diameter", [1, 2, 3, 4, 5, 7])
def test_patch_width_of_small_squares_is_exact(diameter):
    # near the 3-cell threshold the measure is exact (a finer pass on 2 x 2 sub-cells)
    m = np.zeros((40, 40), bool)
    m[5:5 + diameter, 7:7 + diameter] = True
    assert patch_width(m, 2e-9) == pytest.approx(diameter * 2e-9, rel=1e-12)


def test_patch_width_of_wide_squares_is_within_a_cell():
    m = np.zeros((40, 40), bool)
    m[5:26, 7:28] = True  # 21 cells: measured on the cells alone
    assert abs(patch_width(m, 2e-9) - 21 * 2e-9) <= 2e-9


def test_patch_width_of_discs_rings_and_empty_masks():
    r = _radius(128, (64, 64))
    for radius, below in ((3, 1.5), (5, 1.5), (12, 2.0), (30, 2.0)):
        # the cells whose centres lie within a circle of diameter D: the staircase edge cuts
        # into the inscribed disc by up to about 1.4 cells (D = 10: 8.94, the corner (4, 2) of the
        # first cell outside); from 12 cells on, measured on the cells alone (half a cell more)
        assert 2 * radius - below <= patch_width(r < radius, 1.0) <= 2 * radius
    assert patch_width(r < 5, 1.0) == pytest.approx(2 * math.hypot(4, 2), rel=1e-12)
    ring = (r >= 20) & (r < 26)  # 6 cells wide, whatever its circumference
    assert 4.5 <= patch_width(ring, 1.0) <= 7.0  # staircase: within about a cell of 6
    assert patch_width(np.zeros((8, 8), bool), 1.0) == 0.0
    # the largest patch decides: a big disc and a speck
    m = (r < 10) | (_radius(128, (110, 110)) < 1)
    assert patch_width(m, 1.0) == patch_width(r < 10, 1.0) >= 18.0


def test_gap_step_of_a_resolved_and_of_a_missing_cohesive_zone():
    resolved = state(contact_r=10, adhesive_r=18)  # gap climbs h0 over 8 cells: steps ~ h0/8
    assert cohesive_gap_step(resolved) < 0.25 * H0
    bare = state(contact_r=10)  # no cohesive node: contact next to g = 1.5 h0
    assert cohesive_gap_step(bare) == pytest.approx(1.5 * H0, rel=1e-12)


def test_scan_pixel_takes_the_coarsest_measured_file():
    files = {"body1.roughness": {"scan_grid": [512, 512], "scan_size": [1e-6, 1e-6]},
             "body2.roughness": {"scan_grid": [100, 50], "scan_size": [1e-6, 1e-6]}}
    assert scan_pixel(files) == (pytest.approx(2e-8), "body2.roughness")
    assert scan_pixel(None) is None and scan_pixel({}) is None


# ----------------------------------------------------------------------------- the checks
def test_no_warning_for_a_resolved_centred_contact():
    assert result_warnings([state(contact_r=10, adhesive_r=18)], periodic=False, interaction=ADH, radius=1e-3) == []


def test_edge_contact_warns_on_free_boundary_only():
    s = state(contact_r=10, center=(5, 32))
    assert "edge" in names(result_warnings([s], periodic=False))
    assert "edge" not in names(result_warnings([s], periodic=True))


def _humid_state(meniscus_r, n=64):
    """A contact disc (10 cells), a meniscus of uniform Laplace tension 90 MPa to ``meniscus_r``
    cells and, beyond it, a van der Waals-like tail -200 MPa (2/r)^3 (r in cells from the
    contact edge) that is nonzero on every node of the domain."""
    s = state(n=n, contact_r=10)
    r = _radius(n, (32, 32))
    tail = -2e8 * (2.0 / np.maximum(r - 10 + 2, 2.0)) ** 3
    p = np.where(s.contact, 1e8, np.where(r < meniscus_r, -9e7 + tail, tail))
    return NormalResult(grid=s.grid, pressure=p, gap=s.gap, displacement=s.displacement, contact=s.contact,
                        adhesive=~s.contact & (p < 0), force=1.0, approach=0.0, iterations=1,
                        residual_history=np.array([0.0]), converged=True, time=0.0)


def test_edge_check_ignores_a_van_der_waals_tail_but_not_a_meniscus():
    """Humid runs: every non-contact node is tensile (the 1/g^3 tail); only tension of at least
    1 % of the peak counts as cohesive zone, so a meniscus inside the domain does not warn, a
    meniscus that reaches the edge does (regression: the tail made every humid free-boundary
    run warn 'edge')."""
    inside, reaching = _humid_state(meniscus_r=20), _humid_state(meniscus_r=40)
    assert inside.adhesive[0, 0] and inside.pressure[0, 0] < 0  # the tail reaches the edge
    assert "edge" not in names(result_warnings([inside], periodic=False))
    assert "edge" in names(result_warnings([reaching], periodic=False))


@pytest.mark.parametrize("adhesive_r, text", [(11.5, "cells wide"), (None, "narrower than one cell")])
def test_unresolved_cohesive_zone_warns(adhesive_r, text):
    ws = result_warnings([state(contact_r=10, adhesive_r=adhesive_r)], periodic=False, interaction=ADH)
    assert any(w.startswith("cohesive_zone:") and text in w for w in ws)
    # without adhesion the check does not apply
    assert "cohesive_zone" not in names(result_warnings([state(contact_r=10)], periodic=False))


def test_cohesive_range_warns_where_the_gap_jumps_over_h0():
    # A cohesive ring 8 cells wide on one half of the contact only; on the other half the
    # contact borders nodes at g = 3 h0 (a steep flank).  The area/perimeter width is ~4 cells
    # (no cohesive_zone warning), but the gap crosses the whole range within one cell there.
    n = 64
    r = _radius(n, (32, 32))
    i = np.arange(n)[:, None] * np.ones(n)[None, :]
    contact = r < 10
    adhesive = (r < 18) & ~contact & (i >= 32)
    gap = np.where(contact, 0.0, np.where(adhesive, H0 * (r - 10) / 8, 3.0 * H0))
    s = state(contact_r=10, gap=gap)
    s.adhesive = adhesive
    ws = result_warnings([s], periodic=False, interaction=ADH)
    assert "cohesive_range" in names(ws) and "cohesive_zone" not in names(ws)
    assert any("3 h0" in w for w in ws if w.startswith("cohesive_range:"))
    # the resolved ring of the same width all round: no cohesive_range
    assert "cohesive_range" not in names(result_warnings([state(contact_r=10, adhesive_r=18)], periodic=False,
                                                         interaction=ADH))


def test_full_contact_and_large_contact_warn():
    s = state(contact_r=60)  # covers ~ all of a 64^2 domain
    assert "full_contact" in names(result_warnings([s], periodic=True))
    # contact radius ~ 10 cells x 15.6 nm = 0.16 um against R = 1 um: a/R = 0.16 > 0.1
    assert "large_contact" in names(result_warnings([state(contact_r=10)], periodic=False, radius=1e-6))
    assert "large_contact" not in names(result_warnings([state(contact_r=10)], periodic=False, radius=1e-4))


def test_contact_of_a_few_cells_warns():
    # 2 x 2 cells: fewer than 3 across; the warning names the state's largest patch
    assert "contact_cells" in names(result_warnings([state(contact_r=1.2)], periodic=True))
    # one state with a resolved disc and one with a speck: the speck decides
    both = [state(contact_r=10), state(contact_r=0.8)]
    assert "contact_cells" in names(result_warnings(both, periodic=True))
    assert "contact_cells" not in names(result_warnings([state(contact_r=10)], periodic=True))


def test_topography_pixels_larger_than_the_contact_warn():
    s = state(contact_r=10)  # 20 cells of 15.6 nm = 0.31 um across
    coarse = {"body1.roughness": {"scan_grid": [64, 64], "scan_size": [10e-6, 10e-6]}}  # 0.16 um pixels
    fine = {"body1.roughness": {"scan_grid": [512, 512], "scan_size": [1e-6, 1e-6]}}  # 2 nm pixels
    ws = result_warnings([s], periodic=False, files=coarse)
    assert "topography_pixels" in names(ws) and "contact_cells" not in names(ws)
    assert any("body1.roughness" in w for w in ws)
    assert result_warnings([s], periodic=False, files=fine) == []


def test_stick_zone_of_two_cells_warns_in_a_partial_slip_run():
    n = state()
    # every partial-slip state has a stick disc 2-3 cells across at most
    ramp = [tangential(stick_r=1.5), tangential(stick_r=1.0)]
    ws = result_warnings([n, n], periodic=False, tangential=ramp)
    assert "stick_zone" in names(ws) and any("at most" in w for w in ws)
    # resolved stick zones (20 cells), then the gross-slip onset (a last speck of stick) and
    # gross slip: no warning, the run says it slides
    ramp = [tangential(stick_r=10), tangential(stick_r=5), tangential(stick_r=0.8), tangential(gross_slip=True)]
    assert result_warnings([n] * 4, periodic=False, tangential=ramp, gross_slip=True) == []
    # the same resolved start, but a run that claims to end in partial slip with a 1-cell stick zone
    ramp = [tangential(stick_r=10), tangential(stick_r=0.8)]
    ws = result_warnings([n, n], periodic=False, tangential=ramp, gross_slip=False)
    assert any(w.startswith("stick_zone:") and "ends in partial slip" in w for w in ws)
    assert "stick_zone" not in names(result_warnings([n, n], periodic=False, tangential=ramp[:1] * 2,
                                                     gross_slip=False))
    dx = 1e-6 / 64
    assert 18 * dx <= stick_zone_width(tangential(stick_r=10)) <= 20 * dx  # the stick disc, not the contact


def test_warning_names_and_the_schema_agree():
    from tribobem.scenario.schema import CHECK_NAMES

    assert tuple(CHECK_NAMES) == CHECKS
    ws = ["edge: x", "cohesive_zone: y", "body1.roughness: a measured topography is not periodic", "edge: again"]
    assert warning_names(ws) == ["edge", "cohesive_zone"]


# ----------------------------------------------------------------------------- expected values
def test_compare_expected_reads_run_and_step_keys():
    summary = {"pull_off_force": -0.2574e-6, "steps": [{"index": 0, "contact_area": 1.0e-14},
                                                        {"index": 1, "contact_area": 2.0e-14}],
               "warnings": ["cohesive_zone: narrow"]}
    out = compare_expected(summary, {"values": {"pull_off_force": -0.25e-6}, "tolerance": 0.03,
                                     "reference": "Maugis-Dugdale"})
    (row,) = out["values"]
    assert row["where"] == "run" and row["relative_error"] == pytest.approx(0.0296, rel=1e-9) and row["within"]
    assert out["met"]
    out = compare_expected(summary, {"values": {"pull_off_force": -0.25e-6}, "tolerance": 0.02, "reference": "x"})
    assert not out["met"] and not out["values"][0]["within"]
    # step keys: the last step by default, or the one named
    out = compare_expected(summary, {"values": {"contact_area": 2.0e-14}, "tolerance": 0.01, "reference": "x"})
    assert out["met"] and out["values"][0]["where"] == "step 1"
    out = compare_expected(summary, {"values": {"contact_area": 2.0e-14}, "tolerance": 0.01, "step": 0,
                                     "reference": "x"})
    assert not out["met"] and out["values"][0]["computed"] == 1.0e-14
    # expected warnings: present or not
    assert compare_expected(summary, {"warnings": ["cohesive_zone"], "reference": "q"})["met"]
    assert not compare_expected(summary, {"warnings": ["edge"], "reference": "q"})["met"]
    # a key the run does not have is never met
    assert not compare_expected(summary, {"values": {"static_friction_force": 1.0}, "tolerance": 0.5,
                                          "reference": "x"})["met"]
    assert compare_expected(summary, None) is None
    assert math.isclose(out["tolerance"], 0.01)


# ----------------------------------------------------------------------------- cohesive_edge
@pytest.mark.parametrize("n, size", [(32, (1e-6, 1e-6)), (48, (1e-6, 0.5e-6))])
def test_cell_self_compliance_is_the_free_boundary_diagonal(n, size):
    """Love's centre displacement of a uniformly loaded rectangle is the diagonal of the
    free-boundary influence matrix (square and 2:1 cells)."""
    from tribobem.materials import ContactPair, Material
    from tribobem.elasticity.operators import free_boundary_operator
    from tribobem.output.checks import cell_self_compliance
    from tribobem.solvers.normal import _self_compliance

    g = Grid(n, n, size[0], size[1], False)
    op = free_boundary_operator(g, ContactPair(Material(70e9, 0.3), Material(200e9, 0.25)))
    assert cell_self_compliance(g.dx, g.dy, op.pair.effective_modulus) == pytest.approx(_self_compliance(op), rel=1e-12)


def test_cohesive_edge_band_brackets_the_maugis_dugdale_force():
    """Maugis-Dugdale sphere at F = 0, lambda = 1, cold force control: Polonsky-Keer's equilibrium
    keeps every two-way edge node in the cohesive zone, NormCG's keeps every one out; the analytic
    F0+ lies within the band's force of either (measured 0.7 and 0.9 of it at 160^2), the two
    differ by 1-2.5 bands (1.6 measured), and the band narrows with the cell (80^2 -> 160^2:
    5.2 % -> 2.4 %)."""
    from tribobem.output.checks import cell_self_compliance, cohesive_edge_band, cohesive_edge_nodes
    from tribobem.solvers.normal import solve_normal
    from tribobem.validation import maugis_dugdale_problem
    from tribobem.validation.common import PAIR as MD_PAIR
    from tribobem.validation.paper_e_model import md_state

    bands = {}
    for n in (80, 160):
        prob = maugis_dugdale_problem(1.0, n=n)
        ad, op = prob.adhesion, prob.operator
        md = md_state(ad.work_of_adhesion, radius=2.5e-6, E=MD_PAIR.body1.E, nu=MD_PAIR.body1.nu, force=0.0,
                      z0=0.3e-9)
        C = cell_self_compliance(op.grid.dx, op.grid.dy, op.pair.effective_modulus)
        F = {}
        for method in ("polonsky_keer", "normcg"):
            r = solve_normal(op, prob.gap, force=0.0, interaction=ad, tol=1e-10, method=method)
            assert r.converged, r.message
            band = cohesive_edge_band([r], ad, op.pair.effective_modulus)
            n_nodes, force = cohesive_edge_nodes(r, ad.h0, ad.sigma0, C)
            assert (band["nodes"], band["force"]) == (n_nodes, force) and n_nodes > 0
            g, zone = np.asarray(r.gap), np.asarray(r.adhesive) & ~np.asarray(r.contact)
            inside = int(np.count_nonzero(zone & (g > ad.h0 - ad.sigma0 * C)))
            if n == 160:
                assert inside == (n_nodes if method == "polonsky_keer" else 0)
            F[method] = r.repulsive_force
            if n == 160:
                assert abs(r.repulsive_force - md["repulsive_force"]) < force  # within one band
            bands[(n, method)] = band["fraction"]
        if n == 160:
            spread = F["polonsky_keer"] - F["normcg"]
            force = bands[(n, "polonsky_keer")] * abs(F["polonsky_keer"])  # at F = 0: F_adh = -F0+
            assert force < spread < 2.5 * force
    for method in ("polonsky_keer", "normcg"):
        assert bands[(160, method)] < 0.6 * bands[(80, method)]


def test_cohesive_edge_warns_on_a_coarse_grid_only():
    from tribobem.solvers.normal import solve_normal
    from tribobem.validation import maugis_dugdale_problem

    fired = {}
    for n in (48, 160):
        prob = maugis_dugdale_problem(1.0, n=n)
        r = solve_normal(prob.operator, prob.gap, force=0.0, interaction=prob.adhesion, tol=1e-10)
        w = result_warnings([r], periodic=False, interaction=prob.adhesion,
                            effective_modulus=prob.operator.pair.effective_modulus)
        fired[n] = [x for x in w if x.startswith("cohesive_edge:")]
        # without E* (or without Dugdale adhesion) there is no band to check
        assert not any(x.startswith("cohesive_edge:") for x in
                       result_warnings([r], periodic=False, interaction=prob.adhesion))
    assert len(fired[48]) == 1 and "11.7 %" in fired[48][0] and fired[160] == []
    assert "cohesive_edge" in CHECKS
