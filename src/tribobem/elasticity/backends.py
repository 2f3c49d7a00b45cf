"""The array backends by name: ``numpy``, ``cupy`` and ``strict`` (testing).

:func:`get_backend` is where a name (``[solver] backend``, or an operator's cached backend name)
becomes a :class:`~tribobem.elasticity.backend.Backend`; kept apart from :mod:`.backend` so that
the strict testing backend (:mod:`.strict`, built on :class:`~.backend.Backend`) is reachable by
name without an import cycle.
"""

from __future__ import annotations

from functools import lru_cache

from ..errors import InputError
from .backend import Backend, cupy_available
from .strict import strict_backend

__all__ = ["get_backend"]


@lru_cache(maxsize=None)
def get_backend(name: str = "numpy") -> Backend:
    """The backend called ``name`` ("numpy" or "cupy"); raises if CuPy is unusable.

    ``"strict"`` is the testing backend of :mod:`tribobem.elasticity.strict` (NumPy underneath,
    CuPy's host/device rules: a host array reaching the device array module fails without a
    GPU); scenarios do not offer it.

    Parameters
    ----------
    name : {"numpy", "cupy", "strict"}
        The backend's name, as ``[solver] backend`` spells it.

    Returns
    -------
    Backend
        The backend, cached per name (one instance, and so one set of FFT plans and work
        buffers, per process).

    Raises
    ------
    InputError
        For an unknown name, or ``"cupy"`` without CuPy or a CUDA device.
    """
    if name == "strict":
        return strict_backend()
    if name not in ("numpy", "cupy"):
        raise InputError("solver.backend", f"must be 'numpy' or 'cupy', got {name!r}")
    if name == "cupy":
        if not cupy_available():
            raise InputError("solver.backend", "CuPy with a working CUDA device is not available; install tribobem[gpu]")
    return Backend(name)
