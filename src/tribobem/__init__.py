"""tribobem: FFT-accelerated boundary element method for the adhesive, frictional contact of
rough surfaces.

Data flows one way: inputs -> geometry -> operator -> solver -> result -> outputs.
"""

from .errors import ConvergenceError, ConvergenceWarning, InputError, TribobemError
from .grid import Grid
from .materials import ContactPair, Material, effective_modulus

__version__ = "0.1.0"

__all__ = [
    "Grid", "Material", "ContactPair", "effective_modulus",
    "TribobemError", "InputError", "ConvergenceError", "ConvergenceWarning",
    "__version__",
]
