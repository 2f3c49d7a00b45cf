"""Solvers: constrained conjugate gradients for normal (and adhesive) contact, the tangential
(partial-slip) solver, the normal-tangential coupling loop, load paths.

Error keys: a solver's :class:`~tribobem.errors.InputError` names its own argument, as
``"<function>.<argument>"`` (``solve_tangential.method``, ``pull_off.preload``; the two normal
solvers share ``solve_normal.*``, NormCG being one of ``solve_normal``'s methods), or the bare
argument (``gap``, ``pressure``) where no scenario key stands for it.  The solvers know no
scenario keys: the scenario runners translate (:data:`tribobem.runs.common.SCENARIO_KEYS`).
"""

from .capillary import solve_capillary
from .coupling import solve_coupled
from .normal import solve_normal
from .normal_cg import solve_normal_cg
from .normal_paths import normal_path
from .tangential_paths import tangential_ramp
from .tangential import GrossSlipError, solve_tangential

__all__ = ["solve_normal", "solve_normal_cg", "solve_tangential", "solve_coupled", "tangential_ramp", "normal_path",
           "GrossSlipError", "solve_capillary"]
