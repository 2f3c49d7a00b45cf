"""Solvers: constrained conjugate gradients for normal (and adhesive) contact, load paths."""

from .normal import solve_normal

__all__ = ["solve_normal"]
