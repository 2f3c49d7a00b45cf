"""Result checks: each warning fires on a state that should trigger it, and not on one that
should not (issue 9 item 1, the part the tangential kinds need)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from tribobem import DugdaleAdhesion, Grid
from tribobem.output.checks import cohesive_cells, result_warnings
from tribobem.results import NormalResult


def state(n=64, contact_r=10, adhesive_r=None, center=(32, 32), size=1e-6):
    g = Grid.square(n, size)
    i, j = np.meshgrid(np.arange(n), np.arange(n), indexing="ij")
    r = np.hypot(i + 0.5 - center[0], j + 0.5 - center[1])
    contact = r < contact_r
    adhesive = (r < adhesive_r) & ~contact if adhesive_r else np.zeros_like(contact)
    p = np.where(contact, 1e6, np.where(adhesive, -1e5, 0.0))
    z = np.zeros((n, n))
    return NormalResult(grid=g, pressure=p, gap=z, displacement=z, contact=contact, adhesive=adhesive, force=1.0,
                        approach=0.0, iterations=1, residual_history=np.array([0.0]), converged=True, time=0.0)


ADH = DugdaleAdhesion(0.05, 0.3e-9)


def test_cohesive_width_estimate_of_a_ring():
    # ring from 10 to 16 cells: width 6 cells (area / outer perimeter slightly less for a ring)
    w = cohesive_cells(state(contact_r=10, adhesive_r=16))
    assert 4.0 < w < 7.0


def test_no_warning_for_a_resolved_centred_contact():
    assert result_warnings([state(contact_r=10, adhesive_r=18)], periodic=False, interaction=ADH, radius=1e-3) == []


def test_edge_contact_warns_on_free_boundary_only():
    s = state(contact_r=10, center=(5, 32))
    assert any(w.startswith("edge:") for w in result_warnings([s], periodic=False))
    assert not any(w.startswith("edge:") for w in result_warnings([s], periodic=True))


@pytest.mark.parametrize("adhesive_r, text", [(11.5, "cells wide"), (None, "narrower than one cell")])
def test_unresolved_cohesive_zone_warns(adhesive_r, text):
    ws = result_warnings([state(contact_r=10, adhesive_r=adhesive_r)], periodic=False, interaction=ADH)
    assert any(w.startswith("cohesive_zone:") and text in w for w in ws)
    # without adhesion the check does not apply
    assert not any(w.startswith("cohesive_zone:") for w in result_warnings([state(contact_r=10)], periodic=False))


def test_full_contact_and_large_contact_warn():
    s = state(contact_r=60)  # covers ~ all of a 64^2 domain
    ws = result_warnings([s], periodic=True)
    assert any(w.startswith("full_contact:") for w in ws)
    # contact radius ~ 10 cells x 15.6 nm = 0.16 um against R = 1 um: a/R = 0.16 > 0.1
    ws = result_warnings([state(contact_r=10)], periodic=False, radius=1e-6)
    assert any(w.startswith("large_contact:") for w in ws)
    assert not any(w.startswith("large_contact:") for w in result_warnings([state(contact_r=10)], periodic=False,
                                                                            radius=1e-4))


def test_the_demo_states_its_unresolved_cohesive_zone():
    # The built-in demo's cohesive range is a fraction of a cell (issue 9): it must now say so.
    from tribobem.cli import demo_scenario
    from tribobem.scenario import run_scenario

    sc, _ = demo_scenario(small=True)
    s = run_scenario(sc, progress=False).summary
    assert any(w.startswith("cohesive_zone:") for w in s["warnings"])
