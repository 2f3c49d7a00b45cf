"""Boxes of a free-boundary grid: the :class:`Window` a step is solved on, and the box around
a set of nodes (its sides fast FFT lengths).  Used by the windowed coupled steps
(:mod:`.window`) and the candidate-set normal solves (:mod:`.candidates`); no solver imports
here, so that both can use it.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from ..elasticity.operators import ConvolutionOperator, free_boundary_operator
from ..grid import Grid
from ..interactions.base import NoInteraction
from ..results import CoupledResult

__all__ = ["Window"]

#: Margin around the support of the tractions (fraction of its extent per side, plus MIN_MARGIN
#: cells); small, because the check after each step grows the window when it is needed (a cell
#: or two of the cohesive zone's edge moves over a hysteresis loop at a fixed normal force).
MARGIN = 0.02
MIN_MARGIN = 2
#: Use a window only when its padded transform is below this fraction of the whole grid's.
MAX_FRACTION = 0.7


def _fast_even(m: int, n: int) -> int:
    """The smallest m' >= m (<= n) whose 2m' is 5-smooth (a fast FFT length)."""
    k = m
    while k < n:
        v = 2 * k
        for f in (2, 3, 5):
            while v % f == 0:
                v //= f
        if v == 1:
            return k
        k += 1
    return n


@dataclasses.dataclass(frozen=True)
class Window:
    """Rows ``i0:i1`` and columns ``j0:j1`` of a free-boundary grid.

    Attributes
    ----------
    i0, i1 : int
        First and one-past-last row (node indices along x) of the window.
    j0, j1 : int
        First and one-past-last column (node indices along y).
    """

    i0: int
    i1: int
    j0: int
    j1: int

    @property
    def shape(self) -> tuple[int, int]:
        """The window's size in nodes, (i1 - i0, j1 - j0)."""
        return (self.i1 - self.i0, self.j1 - self.j0)

    def slice(self, a):
        """The window's part of a grid-shaped (or (k, nx, ny)) array, a contiguous copy.

        Parameters
        ----------
        a : array_like or None
            Field of shape (..., nx, ny) on the whole grid (any unit).

        Returns
        -------
        ndarray or None
            Its (..., i1 - i0, j1 - j0) part, C-contiguous (what the solvers' FFTs want); None
            for None.
        """
        if a is None:
            return None
        return np.ascontiguousarray(np.asarray(a)[..., self.i0:self.i1, self.j0:self.j1])

    def operator(self, operator: ConvolutionOperator) -> ConvolutionOperator:
        """The free-boundary operator of the window's grid (same cells, same materials).

        Cached on ``operator`` per window shape (the operator is translation invariant): the
        same object step after step, so that what the solvers cache on it (the tangential
        view, its box and preconditioner spectra, work arrays) is made once, not every step.

        Parameters
        ----------
        operator : ConvolutionOperator
            The whole grid's free-boundary operator.

        Returns
        -------
        ConvolutionOperator
            The free-boundary operator of an (i1 - i0) x (j1 - j0) grid with the same cell size
            (m), materials, components and backend (at most four window shapes are kept).
        """
        cache = operator.cache.window_operators
        m1, m2 = self.shape
        op = cache.get((m1, m2))
        if op is None:
            g = operator.grid
            sub = Grid(m1, m2, m1 * g.dx, m2 * g.dy, False)
            if len(cache) >= 4:
                cache.pop(next(iter(cache)))
            op = cache[(m1, m2)] = free_boundary_operator(sub, operator.pair, operator.components, operator.backend)
        return op

    # -- results ----------------------------------------------------------------------
    def _slice_fields(self, res, grid):
        full = res.grid.shape
        changes = {"grid": grid}
        for f in dataclasses.fields(res):
            v = getattr(res, f.name)
            if isinstance(v, np.ndarray) and v.ndim >= 2 and v.shape[-2:] == full:
                changes[f.name] = self.slice(v)
        return dataclasses.replace(res, **changes)

    def slice_result(self, res: CoupledResult, operator: ConvolutionOperator) -> CoupledResult:
        """A whole-grid step restricted to the window (a warm start of the next windowed step).

        Parameters
        ----------
        res : CoupledResult
            A state on the whole grid.
        operator : ConvolutionOperator
            The whole grid's operator (gives the window's grid).

        Returns
        -------
        CoupledResult
            ``res`` with every grid-shaped field sliced to the window and the window's grid; the
            coupling contraction estimate is carried over.
        """
        grid = self.operator(operator).grid
        out = dataclasses.replace(res, normal=self._slice_fields(res.normal, grid),
                                  tangential=self._slice_fields(res.tangential, grid))
        out._contraction = getattr(res, "_contraction", None)
        return out

    def embed(self, res: CoupledResult, operator: ConvolutionOperator, gap, reference, interaction):
        """The whole-grid result of a windowed step, and the nodes outside the window that violate it.

        Tractions and masks are the window's (zero / False outside); the displacements, the gap,
        the relative displacement and the slip outside the window come from one convolution of
        the window's tractions with the whole grid's operator (inside they are the window's own).

        Parameters
        ----------
        res : CoupledResult
            The step solved on the window's grid.
        operator : ConvolutionOperator
            The whole grid's 3x3 free-boundary operator.
        gap : array_like
            Initial gap h (m) on the whole grid.
        reference : array_like, shape (2, nx, ny), or None
            Previous step's relative displacement (m) on the whole grid (incremental slip);
            None: total slip.
        interaction : Interaction or None
            The stress law outside contact; None: none (only closed nodes violate).

        Returns
        -------
        (CoupledResult, ndarray of bool)
            The result on the whole grid, and the nodes outside the window that are closed
            (gap <= 0) or within the stress law's range: if any, the window was too small.
        """
        nr, tr = res.normal, res.tangential
        n_shape = operator.grid.shape
        sl = (slice(self.i0, self.i1), slice(self.j0, self.j1))
        xp = operator.xp

        def pad(a, fill=0.0, dtype=float):
            a = np.asarray(a)
            out = np.full(a.shape[:-2] + n_shape, fill, dtype=dtype)
            out[(...,) + sl] = a
            return out

        outside = np.ones(n_shape, dtype=bool)
        outside[sl] = False
        if not math.isfinite(float(nr.approach)):
            # no contact under force control: the gap outside cannot be checked (whole grid)
            return res, outside
        p = pad(nr.pressure)
        q = pad(tr.shear)
        u = operator.backend.to_numpy(operator.apply(xp.asarray(np.stack([q[0], q[1], p]))))
        # u[2] is K_zx q_x + K_zy q_y + K_zz p; the normal result's displacement is K_zz p alone
        # (the shear-induced part enters its gap, solve_coupled), and its gap is h + u_z - delta.
        uzz = operator.backend.to_numpy(operator.normal.apply(xp.asarray(p)))
        gap_full = np.asarray(gap, dtype=float) + u[2] - nr.approach
        g_out = gap_full[outside]
        cap = res.capillary
        if getattr(interaction, "self_consistent", False):
            # A capillary model: a node outside violates when it closes, lies in the Dugdale
            # range or belongs to an ACTIVE meniscus of the whole grid (an island the window cut
            # would miss part of its stress).  The whole grid's islands are kept on the result.
            g_chk = gap_full.copy()
            g_chk[sl] = nr.gap
            contact_full = pad(nr.contact, False, bool)
            support, islands = interaction.stress_support(g_chk, contact_full)
            bad_out = (g_out <= 0.0) | support[outside]
            if cap is not None:
                cap = dataclasses.replace(cap, islands=islands)
        else:
            law = interaction if interaction is not None else NoInteraction()
            bad_out = (g_out <= 0.0) | (np.asarray(law.outside_stress(g_out, np)) != 0.0)
        violation = np.zeros(n_shape, dtype=bool)
        violation[outside] = bad_out
        gap_full[sl] = nr.gap
        uzz[sl] = nr.displacement
        normal = dataclasses.replace(
            nr, grid=operator.grid, pressure=p, gap=gap_full, displacement=uzz,
            contact=pad(nr.contact, False, bool), adhesive=pad(nr.adhesive, False, bool),
            info={**nr.info, "window": (self.i0, self.i1, self.j0, self.j1)})
        rel = np.stack([u[0] - tr.displacement_x, u[1] - tr.displacement_y])
        rel[(...,) + sl] = tr.relative_displacement
        slip = rel - np.asarray(reference) if reference is not None else rel.copy()
        slip[(...,) + sl] = tr.slip
        tang = dataclasses.replace(
            tr, grid=operator.grid, shear=q, slip=slip, relative_displacement=rel,
            contact=pad(tr.contact, False, bool), stick=pad(tr.stick, False, bool),
            info={**tr.info, "window": (self.i0, self.i1, self.j0, self.j1)})
        if cap is not None:
            cap = dataclasses.replace(cap, normal=normal)
        out = dataclasses.replace(res, normal=normal, tangential=tang, capillary=cap)
        out._contraction = getattr(res, "_contraction", None)
        return out, violation


def _window_around(mask, shape, margin: float = MARGIN) -> Window | None:
    """The box around the True nodes of ``mask`` with the margin, its padded transform fast;
    None when it would not be clearly smaller than the whole grid's."""
    return _window_of_extent(np.asarray(mask.any(axis=1)), np.asarray(mask.any(axis=0)), shape, margin)


def _window_of_extent(rows, cols, shape, margin: float = MARGIN) -> Window | None:
    """:func:`_window_around` from the rows and the columns (host bool vectors) that hold a
    True node."""
    nx, ny = shape
    ii = np.flatnonzero(rows)
    jj = np.flatnonzero(cols)
    if ii.size == 0:
        return None

    def axis(lo, hi, n):
        ext = hi - lo + 1
        pad = int(math.ceil(margin * ext)) + MIN_MARGIN
        m = _fast_even(min(ext + 2 * pad, n), n)
        a = max(0, min((lo + hi + 1) // 2 - m // 2, n - m))
        return a, a + m

    i0, i1 = axis(int(ii[0]), int(ii[-1]), nx)
    j0, j1 = axis(int(jj[0]), int(jj[-1]), ny)
    w = Window(i0, i1, j0, j1)
    if (i1 - i0) * (j1 - j0) > MAX_FRACTION * nx * ny:
        return None
    return w
