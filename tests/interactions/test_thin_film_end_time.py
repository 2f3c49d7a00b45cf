"""Thin-film levelling in a scenario has an end: ``[humidity] film_time``.

Paper B's thin-film equation without the disjoining pressure has no steady state (the films
drain off the peaks for as long as one integrates), so a scenario with ``levelling =
"thin_film"`` and ``disjoining = false`` must say when to take the films (``film_time``, a
physical time) and is refused without it.  With it, the run integrates to that time, shows the
time reached as a progress phase per film (1/1000 of the end time) and records it per step
(``film_time_1`` in s, ``film_time_tau_slow_1`` in units of tau_slow); a step limit reached
first is a non-convergence with a warning.  ``disjoining = true`` still runs to its steady state.

The tiny cell (16^2, 0.5 um, rms 0.2 nm, 1.05 nm SiO2 film at RH 0.5): tau_slow = 1.43 ms;
100 us (0.07 tau_slow) takes 290 time steps, about 2 s.
"""

from __future__ import annotations

import numpy as np
import pytest

import tribobem.runs.capillary as capillary_run
from tribobem.interactions.films import film_thickness, levelling_time
from tribobem.interactions.isotherms import isotherm_from_spec
from tribobem.interactions.water import Water
from tribobem.runs.capillary import FILM_PROGRESS_STEPS, films_at
from tribobem.scenario import run_scenario
from tribobem.scenario.build import build_problem
from tribobem.scenario.schema import ScenarioError, parse_scenario

END = 1e-4  # s


def _scenario(**humidity):
    return {
        "kind": "capillary", "name": "thin film to an end time",
        "grid": {"n": 16, "size": "0.5 um", "periodic": True},
        "body1": {"E": "70 GPa", "nu": 0.17, "film": {"isotherm": "SiO2"},
                  "roughness": {"kind": "gaussian", "rms": "0.2 nm", "seed": 1, "correlation_length": "0.1 um"}},
        "body2": {"rigid": True},
        "load": {"force": "0.1 uN"},
        "humidity": {"rh": [0.5], "van_der_waals": False, "levelling": "thin_film", **humidity},
        "output": {"fields": "none", "figures": False, "report": False},
    }


def test_open_ended_thin_film_is_refused_naming_the_key():
    with pytest.raises(ScenarioError) as exc:
        parse_scenario(_scenario())
    msg = dict(exc.value.errors)["humidity.film_time"]
    assert "no steady state" in msg and "drain off the peaks" in msg
    assert "give film_time" in msg and "disjoining = true" in msg
    # the end time belongs to the thin-film levelling only
    with pytest.raises(ScenarioError) as exc:
        parse_scenario({**_scenario(film_time="1 ms"), "humidity": {"rh": [0.5], "film_time": "1 ms"}})
    assert "levelling = 'thin_film'" in dict(exc.value.errors)["humidity.film_time"]
    with pytest.raises(ScenarioError) as exc:
        parse_scenario(_scenario(film_time="-1 ms"))
    assert "humidity.film_time" in dict(exc.value.errors)
    # the well-posed forms parse: with the end time, or with the disjoining pressure
    assert parse_scenario(_scenario(film_time="100 us")).humidity.film_time == pytest.approx(END, rel=1e-12)
    assert parse_scenario(_scenario(disjoining=True)).humidity.film_time is None


class _Bar:
    """A progress handler that records its phases and calls."""

    def __init__(self):
        self.phases, self.calls = [], []

    def phase(self, description, total):
        self.phases.append((description, total))

    def __call__(self, done, total):
        self.calls.append((len(self.phases), done, total))


def test_films_run_to_the_end_time_with_progress():
    pb = build_problem(parse_scenario(_scenario(film_time="100 us")))
    hs = pb.humidity
    bar = _Bar()
    f1, f2 = films_at(pb, 0.5, bar=bar)
    # the film the library gives for that end time, bit for bit
    ref = film_thickness(hs.surface1, pb.grid, hs.isotherm1, 0.5, hs.water, mode="thin_film", time=END)
    assert np.array_equal(f1.thickness, ref.thickness)
    assert f1.converged and f1.time == pytest.approx(END, rel=1e-12) and "integrated to t = 0.0001 s" in f1.message
    # tau_slow of the cell's longest wavelength (its side) about the isotherm's film
    sio2 = isotherm_from_spec("SiO2")
    tau = levelling_time(0.5e-6, float(sio2.thickness(0.5)), Water())
    assert f1.levelling_time == pytest.approx(tau, rel=1e-12)
    assert 1e-3 < tau < 2e-3  # 1.43 ms
    # one phase, for the wet body only (body 2 is dry), named with the end time in s and tau_slow
    assert bar.phases == [(f"RH 0.5, film 1: levelling to 0.0001 s = {END / tau:.3g} tau_slow", FILM_PROGRESS_STEPS)]
    done = [d for _, d, _ in bar.calls]
    assert done == sorted(set(done)) and done[-1] == FILM_PROGRESS_STEPS  # advancing, to the end time
    assert len(done) > 10
    assert f2.time == 0.0 and f2.mean_thickness == 0.0


def test_run_records_the_time_reached():
    r = run_scenario(_scenario(film_time="100 us"), progress=False, quiet=True)
    assert r.summary["converged"] is True
    assert r.summary["problem"]["humidity"]["film_time"] == pytest.approx(END, rel=1e-12)
    step = r.summary["steps"][0]
    tau = levelling_time(0.5e-6, float(isotherm_from_spec("SiO2").thickness(0.5)), Water())
    assert step["film_time_1"] == pytest.approx(END, rel=1e-12)
    assert step["film_time_tau_slow_1"] == pytest.approx(END / tau, rel=1e-12)
    assert step["film_time_2"] == 0.0 and step["film_time_tau_slow_2"] == 0.0  # the dry rigid flat
    assert not any("film on body" in w for w in r.summary["warnings"])


def test_step_limit_before_the_end_time_is_a_warning(monkeypatch):
    def few_steps(*args, **kw):
        return film_thickness(*args, max_iterations=5, **kw)

    monkeypatch.setattr(capillary_run, "film_thickness", few_steps)
    r = run_scenario(_scenario(film_time="100 us"), progress=False, quiet=True)
    assert r.summary["converged"] is False
    step = r.summary["steps"][0]
    assert step["converged"] is False and step["film_iterations_1"] == 5
    assert 0.0 < step["film_time_1"] < END
    notes = [w for w in r.summary["warnings"] if "film on body1" in w]
    assert len(notes) == 1
    assert "stopped after max_iterations = 5 time steps" in notes[0] and "before the end time 0.0001 s" in notes[0]
    assert "not of humidity.film_time = 0.0001 s" in notes[0]


def test_disjoining_pressure_still_runs_to_its_steady_state():
    pb = build_problem(parse_scenario(_scenario(disjoining=True)))
    hs = pb.humidity
    assert hs.film_time is None and pb.info["humidity"]["film_time"] is None
    f1, _ = films_at(pb, 0.5, bar=_Bar())
    ref = film_thickness(hs.surface1, pb.grid, hs.isotherm1, 0.5, hs.water, mode="thin_film", disjoining=True)
    assert f1.converged and "steady" in f1.message
    assert np.array_equal(f1.thickness, ref.thickness)
