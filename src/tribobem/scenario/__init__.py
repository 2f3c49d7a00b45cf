"""Scenario files: TOML -> validated model -> problem -> run (file contract 9.1).

>>> from tribobem.scenario import run_scenario
>>> result = run_scenario("examples/hertz_free_boundary.toml", outdir="results/hertz")  # doctest: +SKIP
>>> result.summary["steps"][-1]["contact_area"]                                         # doctest: +SKIP
"""

from .build import Problem, build_problem
from .run import NotImplementedKindError, RunResult, load_scenario, read_scenario_file, run_scenario
from .schema import IMPLEMENTED_KINDS, KINDS, Scenario, ScenarioError, parse_scenario

__all__ = [
    "Scenario", "ScenarioError", "parse_scenario", "load_scenario", "read_scenario_file",
    "Problem", "build_problem",
    "RunResult", "run_scenario", "NotImplementedKindError",
    "KINDS", "IMPLEMENTED_KINDS",
]
