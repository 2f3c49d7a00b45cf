"""Polonsky-Keer's alternating edge nodes held out of the contact (``solvers.normal.FREEZE_AFTER``).

A node at the edge of an adhesive contact can alternate at every iteration between entering (it
overlaps while out) and leaving (its pressure falls below the Dugdale floor while in); each change
restarts the CG.  The solver holds such a node out after its second re-entry and checks its exact
gap before convergence.  The references: the plain iteration (``FREEZE_AFTER = None``) on the same
solves, taken from the coupled steps of an adhesive friction loop (where the alternation occurs),
and the loop's energies.
"""

from __future__ import annotations

import json

import numpy as np
import pytest

import tribobem.solvers.coupling as coupling
import tribobem.solvers.normal as normal
from tribobem.scenario import run_scenario


def _loop_scenario(n=64, steps=8):
    """The adhesive friction loop of benchmarks/adhesive_loop.py on a coarse grid: a rigid ball
    (R = 40 um) on a 100 GPa / 0.25 half-space, Dugdale 40 mJ/m^2, F = 8 uN, mu = 0.25."""
    return {
        "kind": "hysteresis",
        "grid": {"n": n, "size": "0.6 um", "periodic": False},
        "body1": {"E": "100 GPa", "nu": 0.25},
        "body2": {"rigid": True, "shape": {"kind": "sphere", "radius": "40 um"}},
        "adhesion": {"model": "dugdale", "work_of_adhesion": "40 mJ/m^2", "z0": "0.2 nm"},
        "load": {"force": "8 uN"},
        "friction": {"coefficient": 0.25,
                     "path": {"control": "force", "cycles": 1, "steps": steps, "amplitude": 0.95}},
        "output": {"fields": "none", "figures": False, "report": False},
    }


@pytest.fixture(scope="module")
def frozen_solves(tmp_path_factory):
    """The normal solves of the loop that froze nodes (arguments and result), and the loop's
    summary."""
    captured = []
    solve = normal.solve_normal

    def spy(*args, **kw):
        res = solve(*args, **kw)
        if res.info["counters"]["frozen"] and len(captured) < 4:
            captured.append((args, dict(kw), res))
        return res

    mp = pytest.MonkeyPatch()
    mp.setattr(coupling, "solve_normal", spy)
    out = tmp_path_factory.mktemp("loop")
    try:
        run_scenario(_loop_scenario(), outdir=out, quiet=True, progress=False)
    finally:
        mp.undo()
    with open(out / "summary.json", encoding="utf-8") as fh:
        return captured, json.load(fh)


def test_alternating_nodes_are_frozen_on_the_loop(frozen_solves):
    captured, _ = frozen_solves
    assert captured, "no solve of the 64^2 loop froze a node (the alternation this guards against)"


def test_frozen_solve_reaches_the_plain_iterations_equilibrium(frozen_solves, monkeypatch):
    """Each solve that froze nodes, solved again by the plain iteration: the same cohesive zone,
    contact nodes that differ at most by the frozen ones (which sit at the floor with zero gap
    either way), the same force, approach and pressure to the solve's tolerance (x 100), and no
    more iterations."""
    captured, _ = frozen_solves
    monkeypatch.setattr(normal, "FREEZE_AFTER", None)
    for args, kw, frozen in captured:
        plain = normal.solve_normal(*args, **kw)
        assert frozen.converged and plain.converged
        assert plain.info["counters"]["frozen"] == 0
        tol = kw.get("tol", 1e-10)
        assert int(np.count_nonzero(frozen.contact != plain.contact)) <= frozen.info["counters"]["frozen"]
        assert np.array_equal(frozen.adhesive | frozen.contact, plain.adhesive | plain.contact)
        scale = np.abs(plain.pressure).sum()
        assert np.abs(frozen.pressure - plain.pressure).sum() < 100 * tol * scale
        assert abs(frozen.force - plain.force) < 100 * tol * abs(plain.repulsive_force)
        assert abs(frozen.approach - plain.approach) < 100 * tol * 1e-9
        assert frozen.iterations <= plain.iterations


def test_loop_energy_and_areas_unchanged_by_freezing(frozen_solves, tmp_path, monkeypatch):
    """The whole loop with the plain iteration: the same loop energy to 1e-6 and the same
    contact, cohesive and stick areas at every step."""
    _, summary = frozen_solves
    monkeypatch.setattr(normal, "FREEZE_AFTER", None)
    run_scenario(_loop_scenario(), outdir=tmp_path, quiet=True, progress=False)
    with open(tmp_path / "summary.json", encoding="utf-8") as fh:
        plain = json.load(fh)
    assert summary["dissipated_energy"] == pytest.approx(plain["dissipated_energy"], rel=1e-6)
    for a, b in zip(summary["steps"], plain["steps"], strict=True):
        for key in ("contact_area", "adhesive_area", "stick_area"):
            assert a[key] == b[key], key
