"""Elasticity: body models, influence coefficients, convolution operators, array backends."""

from .backend import Backend, cupy_available
from .backends import get_backend
from .bodies import BODY_MODELS, BodyModel, HalfSpace, body_model, body_model_of, register_body_model
from .influence import composite_coefficients, lattice_coefficients, point_kernel, single_body_coefficients
from .operators import ConvolutionOperator, free_boundary_operator, make_operator, periodic_operator

__all__ = [
    "Backend", "get_backend", "cupy_available",
    "BODY_MODELS", "BodyModel", "HalfSpace", "body_model", "body_model_of", "register_body_model",
    "composite_coefficients", "lattice_coefficients", "single_body_coefficients", "point_kernel",
    "ConvolutionOperator", "free_boundary_operator", "periodic_operator", "make_operator",
]
