"""The one cache object of an elastic operator: what the solvers derive from it once and reuse.

A :class:`~tribobem.elasticity.operators.ConvolutionOperator` and its
:class:`~tribobem.elasticity.tangential.TangentialOperator` view each carry one
:class:`OperatorCache` (``op.cache``), made with the operator.  Every piece of derived data that
used to be set on the operator's ``__dict__`` by whichever module needed it has a named slot
here, so what an operator holds (and what its memory is) can be read in one place.  The slots
are filled on first use by their owners (the module named in each slot's comment) and are never
invalidated: an operator's spectra do not change after it is made.

Nothing here changes a number: the cached objects are exactly those the solvers built before.
"""

from __future__ import annotations

import threading
from dataclasses import dataclass, field

__all__ = ["OperatorCache"]


@dataclass(eq=False)
class OperatorCache:
    """Derived data of one operator, built on first use by the module that needs it.

    Attributes
    ----------
    blocks : dict
        ``"out" + "in"`` -> the single-component block operator
        (:meth:`ConvolutionOperator.block <tribobem.elasticity.operators.ConvolutionOperator.block>`).
    tangential : TangentialOperator or None
        The tangential view of a 3x3 operator
        (:func:`~tribobem.elasticity.tangential.tangential_operator`).
    kernel_columns : KernelColumns or None
        The real-space kernel columns of a single-component operator
        (:meth:`KernelColumns.of <tribobem.elasticity.columns.KernelColumns.of>`).
    self_compliance : float or None
        Displacement of a cell under its own unit pressure (m/Pa), the diagonal of K
        (``tribobem.solvers.normal_problem._self_compliance``).
    stiffness_box_spectra : dict
        Box shape (n1, n2) -> the body model's stiffness shape on it (|q| in rad/m for the
        half-space, :meth:`~tribobem.elasticity.bodies.BodyModel.preconditioner_stiffness`), the
        settled-phase preconditioner of Polonsky-Keer's CG (``tribobem.solvers.normal._stiffness_box``).
    normcg_preconditioner : ConvolutionOperator or None
        NormCG's preconditioner, the convolution with 1/K (Pa/m)
        (:func:`tribobem.solvers.normal_cg.fft_preconditioner`).
    preconditioner_spectra : dict
        TangentialOperator: box shape (m1, m2) -> spectra (Pa/m) of TangCG's FFT preconditioner
        (:meth:`TangentialOperator.preconditioner_spectra`).
    box_spectra : dict
        TangentialOperator: transform shape (N1, N2) -> ``(N, spectra)`` of K_tt (m/Pa) on a box
        of a free-boundary grid (:meth:`TangentialOperator.box_spectra`; the latest 8 shapes).
    single_spectra : dict
        Key -> ``(spectrum, its complex64 copy)``
        (:func:`~tribobem.elasticity.backend.single_spectrum`; at most 32).
    window_operators : dict
        Window -> the operator of a sub-window of the grid (``tribobem.solvers.window``).
    exterior_displacements : dict
        Window -> the displacement its exterior tractions make on it (``tribobem.solvers.window``).
    work : threading.local
        Per-thread reusable work arrays (:func:`~tribobem.elasticity.backend.work_buffers`):
        operators are shared by the threads of a threaded Dask worker.
    """

    blocks: dict = field(default_factory=dict)
    tangential: object | None = None
    kernel_columns: object | None = None
    self_compliance: float | None = None
    stiffness_box_spectra: dict = field(default_factory=dict)
    normcg_preconditioner: object | None = None
    preconditioner_spectra: dict = field(default_factory=dict)
    box_spectra: dict = field(default_factory=dict)
    single_spectra: dict = field(default_factory=dict)
    window_operators: dict = field(default_factory=dict)
    exterior_displacements: dict = field(default_factory=dict)
    work: threading.local = field(default_factory=threading.local)

    def __repr__(self) -> str:
        filled = [k for k, v in vars(self).items() if k != "work" and v not in (None, {})]
        return f"OperatorCache({', '.join(filled) or 'empty'})"
