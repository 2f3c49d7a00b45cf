"""The iteration driver shared by the iterative contact solvers.

Polonsky-Keer (:mod:`.normal`), NormCG (:mod:`.normal_cg`), TangCG and the projected gradient
(:mod:`.tangential`) run the same loop::

    start
    repeat:  iterate -> residual -> history -> best / stall -> convergence test
             (-> exact recompute to confirm a convergence reached incrementally)
    -> IterationOutcome (converged, message, iterations, residual history)

A solver supplies its steps as an :class:`IterativeSolver` (its ``start``, ``iterate``,
``residual`` and, where it updates its state incrementally, ``is_exact`` and ``confirm``);
:func:`run_iterations` owns the counters, the stall detection, the history and the messages
that the results carry.  The driver costs one Python call per step and iteration and allocates
nothing per iteration.
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass

from ..errors import ConvergenceError, ConvergenceWarning

#: Both normal solvers defer a smooth change of the outside stresses (no node changes piece of
#: the law) while their relative pressure change exceeds this multiple of the change's relative
#: mismatch (benchmarks/README.md): applied at every iteration, it restarts Polonsky-Keer's CG
#: and keeps NormCG's from settling.
DEFER_RATIO = 10.0
#: Largest gain C s' (the cell's self-compliance times the law's slope) of a node's relaxed
#: outside update p + (s - p) / (1 - C s') (a law with ``outside_slope``): beyond it a node would
#: be two-valued, and the update is capped rather than amplified without bound.
RELAX_GAIN = 0.8

__all__ = ["IterationOutcome", "IterativeSolver", "dot", "relaxed_outside_update", "report_failure", "run_iterations"]


def relaxed_outside_update(p, s, slope, self_c, lower, xp, out=None):
    """The outside load's update relaxed by each node's own response (Pa).

    The fixed point p <- s(g) ignores that a node's own change of tension moves its gap by
    C dp (C the cell's self-compliance, m/Pa); solving p' = s(g + C (p' - p)) for the local
    linearisation gives p' = p + (s(g) - p) / (1 - C s'(g)), which settles a node on a
    softening piece of the law in one step instead of a geometric series of ratio C s'.
    Gains C s' above :data:`RELAX_GAIN` are capped there (the node would be two-valued).

    Parameters
    ----------
    p : array
        The current outside stresses (Pa, <= 0).
    s : array
        The law's stresses at the current gaps (Pa); overwritten when ``out`` is ``s``.
    slope : array
        The law's slope ds/dg at the current gaps (Pa/m).
    self_c : float
        The cell's self-compliance C (m/Pa).
    lower : float
        The most tensile stress the law allows (Pa, < 0); the result lies in [lower, 0].
    xp : module
        The array module.
    out : array, optional
        Where to write the result (may be ``s``).
    """
    gain = xp.clip(self_c * slope, 0.0, RELAX_GAIN)
    if out is None:
        out = xp.empty_like(s)
    xp.subtract(s, p, out=out)
    out /= 1.0 - gain
    out += p
    return xp.clip(out, lower, 0.0, out=out)


def dot(a, b) -> float:
    """Dot product of two arrays as an elementwise product and a sum.

    Parameters
    ----------
    a, b : ndarray
        Arrays of the same shape (any number of dimensions; all elements are summed).

    Returns
    -------
    float
        sum(a * b).

    Notes
    -----
    No BLAS call on purpose: on a busy machine the OpenBLAS threads of ``a @ b`` spin against
    the FFT threads, and a 10^4-element product can cost as much as a full-grid pass.
    """
    return float((a * b).sum())


class IterativeSolver:
    """The steps of an iterative solver, run by :func:`run_iterations`.

    A solver overrides :meth:`iterate` and :meth:`residual`, and the other steps where its
    defaults do not apply.  Messages are methods so that each solver keeps its own wording.
    """

    #: Appended to the stall message (None of it for solvers without instabilities).
    stall_hint = "; near an instability there may be no equilibrium"

    def start(self) -> str | None:
        """Prepare the first iteration.

        Returns
        -------
        str or None
            A message when the problem has no solution from this start (the loop then does not
            run), else None.
        """
        return None

    def iterate(self) -> str | None:
        """One iteration.

        Returns
        -------
        str or None
            A message when no equilibrium exists (the loop stops, not converged), else None.
        """
        raise NotImplementedError

    def residual(self) -> float | None:
        """The convergence measure of the last iteration (dimensionless).

        Returns
        -------
        float or None
            The residual, compared with ``tol``; None when the iteration did not measure it
            (the history then repeats its last value and no test is made).
        """
        raise NotImplementedError

    def settled(self) -> bool:
        """Whether the last iteration left the problem unchanged (e.g. no change of the contact
        set or of the element division), as convergence requires.

        Returns
        -------
        bool
        """
        return True

    def is_exact(self) -> bool:
        """Whether the residual was measured on an exactly computed state.

        Returns
        -------
        bool
            False when the state was updated incrementally: a residual below ``tol`` is then
            confirmed by :meth:`confirm`.
        """
        return True

    def confirm(self, tol: float) -> bool:
        """Recompute the state exactly after an incrementally reached ``residual < tol``.

        Parameters
        ----------
        tol : float
            The tolerance of the loop.

        Returns
        -------
        bool
            True when the exact state converges as well (the loop stops, converged); False to
            go on iterating from the exact state.
        """
        return False

    def improved(self, residual: float) -> None:
        """Called when ``residual`` is the best so far (e.g. to keep the state for a fallback).

        Parameters
        ----------
        residual : float
            The new best residual.
        """

    def stalled_message(self, residual: float, best: float, stall: int, tol: float) -> str:
        """Message of a stop for lack of progress.

        Parameters
        ----------
        residual : float
            Residual of the last iteration.
        best : float
            Best residual so far.
        stall : int
            Iterations without improvement that stopped the loop.
        tol : float
            Tolerance.

        Returns
        -------
        str
        """
        return (f"stalled: no progress in {stall} iterations (residual {residual:.3e}, best "
                f"{best:.3e}, tolerance {tol:.1e}){self.stall_hint}")

    def converged_message(self, iteration: int) -> str:
        """Message of a converged solve.

        Parameters
        ----------
        iteration : int
            The iteration that converged.

        Returns
        -------
        str
        """
        return f"converged in {iteration} iterations"

    def exhausted_message(self, max_iterations: int, history: list, tol: float) -> str:
        """Message of a solve stopped by the iteration limit.

        Parameters
        ----------
        max_iterations : int
            The limit.
        history : list of float
            Residual history.
        tol : float
            Tolerance.

        Returns
        -------
        str
        """
        if not history:
            return "not converged"
        return f"not converged after {max_iterations} iterations (residual {history[-1]:.3e}, tolerance {tol:.1e})"


@dataclass
class IterationOutcome:
    """How a loop of :func:`run_iterations` ended.

    Attributes
    ----------
    converged : bool
    message : str
        Why the loop stopped (the solver's wording, see :class:`IterativeSolver`).
    iterations : int
        Number of the last iteration run (``first - 1`` when none ran).
    history : list of float
        Residual per iteration (shared with the caller's list when one was passed).
    """

    converged: bool
    message: str
    iterations: int
    history: list


def run_iterations(solver: IterativeSolver, *, tol: float, max_iterations: int, stall: int,
                   history: list | None = None, first: int = 1) -> IterationOutcome:
    """Run an iterative solver to convergence, stall, failure or the iteration limit.

    Parameters
    ----------
    solver : IterativeSolver
        The steps (see :class:`IterativeSolver`).
    tol : float
        Convergence tolerance on ``solver.residual()`` (dimensionless).
    max_iterations : int
        Number of the last iteration allowed (iterations are numbered from ``first``).
    stall : int
        Stop, not converged, after this many iterations without improving the best residual.
    history : list of float, optional
        List the residuals are appended to (a solver continued by another one shares it).
    first : int
        Number of the first iteration (a fallback solver continues the count of the one before).

    Returns
    -------
    IterationOutcome
    """
    history = [] if history is None else history
    best, best_it = math.inf, first - 1
    it = first - 1
    converged = False
    status = solver.start()
    while status is None and it < max_iterations:
        it += 1
        status = solver.iterate()
        if status is not None:
            break
        residual = solver.residual()
        if residual is None:
            history.append(history[-1] if history else math.inf)
            continue
        history.append(residual)
        if residual < best:
            best, best_it = residual, it
            solver.improved(residual)
        elif it - best_it >= stall:
            status = solver.stalled_message(residual, best, stall, tol)
            break
        if residual < tol and solver.settled() and (solver.is_exact() or solver.confirm(tol)):
            converged = True
            status = solver.converged_message(it)
            break
    if status is None:
        status = solver.exhausted_message(max_iterations, history, tol)
    return IterationOutcome(converged, status, it, history)


def report_failure(message: str, *, strict: bool, prefix: str = "", stacklevel: int = 2) -> None:
    """Raise or warn about a solve that did not converge.

    Parameters
    ----------
    message : str
        The outcome's message.
    strict : bool
        Raise :class:`~tribobem.errors.ConvergenceError` (with ``message``) instead of warning.
    prefix : str
        Put before ``message`` in the warning.
    stacklevel : int
        ``stacklevel`` of the warning as seen from the caller of this function (2: the
        caller's caller).

    Raises
    ------
    ConvergenceError
        With ``strict``.
    """
    if strict:
        raise ConvergenceError(message)
    warnings.warn(prefix + message, ConvergenceWarning, stacklevel=stacklevel + 1)
