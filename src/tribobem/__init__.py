"""tribobem: FFT-accelerated boundary element method for the adhesive, frictional contact of
rough surfaces.

Data flows one way: inputs -> geometry -> operator -> solver -> result -> outputs.
"""

from .elasticity import free_boundary_operator, make_operator, periodic_operator
from .errors import (ConvergenceError, ConvergenceWarning, InputError, MemoryBudgetError, ResultWarning, TopographyError,
                     TribobemError)
from .grid import Grid
from .interactions import DugdaleAdhesion
from .materials import ContactPair, Material, effective_modulus
from .output import read_fields, read_summary
from .results import CoupledResult, LoadCurve, NormalResult, PullOff, SlipRamp, TangentialResult
from .scenario import RunResult, Scenario, ScenarioError, load_scenario, parse_scenario, run_scenario
from .solvers import GrossSlipError, normal_path, solve_coupled, solve_normal, solve_tangential, tangential_ramp
from .solvers.normal_paths import approach_curve, force_curve, pull_off, solve_at_force
from .units import to_si

from ._version import __version__

__all__ = [
    # model
    "Grid", "Material", "ContactPair", "effective_modulus", "DugdaleAdhesion",
    # operators and solvers
    "make_operator", "periodic_operator", "free_boundary_operator",
    "solve_normal", "approach_curve", "force_curve", "pull_off", "solve_at_force",
    "solve_tangential", "solve_coupled", "tangential_ramp", "normal_path",
    # results
    "NormalResult", "LoadCurve", "PullOff", "TangentialResult", "CoupledResult", "SlipRamp",
    # scenarios and outputs
    "load_scenario", "parse_scenario", "run_scenario", "Scenario", "RunResult", "read_summary", "read_fields", "to_si",
    # errors
    "TribobemError", "InputError", "TopographyError", "MemoryBudgetError", "ScenarioError",
    "ConvergenceError", "ConvergenceWarning", "ResultWarning", "GrossSlipError",
    "__version__",
]
