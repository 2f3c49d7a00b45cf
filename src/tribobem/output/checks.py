"""Sanity and resolution checks of a run's results: numbers the grid cannot back get a warning.

Each check looks at the solved states (not at the inputs), so it holds for any geometry:

* ``edge``: on a free-boundary grid the contact or the cohesive zone touches the domain edge
  (the zero-padded operator then truncates the load: enlarge the domain);
* ``cohesive_zone``: with Dugdale adhesion, the cohesive zone around the contact is narrower
  than :data:`MIN_COHESIVE_CELLS` cells (its width estimated as adhesive area over the outer
  perimeter, exact for a thin ring), or narrower than one cell (no cohesive node next to a
  contact): pull-off and adhesive forces are then set by the grid (lattice trapping);
* ``full_contact``: the contact covers more than :data:`FULL_CONTACT` of the domain;
* ``large_contact``: a sphere whose contact radius exceeds :data:`MAX_A_OVER_R` of its radius
  (the half-space, small-slope model no longer holds).

:func:`result_warnings` returns one message per check that fires (the worst case over the
states), for summary.json ``warnings``, the report's banner and the CLI.
"""

from __future__ import annotations

import math
from typing import Sequence

import numpy as np

__all__ = ["result_warnings", "MIN_COHESIVE_CELLS", "FULL_CONTACT", "MAX_A_OVER_R"]

#: Fewest cells across the cohesive zone for resolved adhesive forces (Maugis-Dugdale pull-off
#: is ~5 % high at ~4 cells, within 1 % at ~8).
MIN_COHESIVE_CELLS = 3.0
#: Contact fraction above which the domain is too small for the contact.
FULL_CONTACT = 0.9
#: Largest contact radius over sphere radius for the half-space model.
MAX_A_OVER_R = 0.1


def _perimeter_cells(mask: np.ndarray) -> int:
    """Number of cell edges between the mask and its complement (inside the grid)."""
    m = mask.astype(np.int8)
    return int(np.abs(np.diff(m, axis=0)).sum() + np.abs(np.diff(m, axis=1)).sum())


def _touches_edge(mask: np.ndarray) -> bool:
    return bool(mask[0, :].any() or mask[-1, :].any() or mask[:, 0].any() or mask[:, -1].any())


def cohesive_cells(res) -> float:
    """Estimated width of the cohesive zone in cells: adhesive area / outer perimeter / dx
    (for a ring from a to c: (c^2 - a^2)/(2c), i.e. c - a for a thin ring).

    inf without cohesive nodes and without contact; 0 with contact but no cohesive node.
    """
    adh = np.asarray(res.adhesive, bool)
    con = np.asarray(res.contact, bool)
    if not adh.any():
        return 0.0 if con.any() else math.inf
    outer = _perimeter_cells(adh | con)
    if outer == 0:
        return math.inf
    dx = math.sqrt(res.grid.cell_area)
    # Counting cell edges measures a boundary in the Manhattan metric: 4/pi times its length on
    # average over orientations, so the edge count is scaled back by pi/4.
    length = outer * dx * math.pi / 4.0
    width = (np.count_nonzero(adh) * res.grid.cell_area) / length
    return width / dx


def result_warnings(results: Sequence, *, periodic: bool, interaction=None, radius: float | None = None) -> list[str]:
    """Warnings for states the grid cannot back (see the module docstring).

    Parameters
    ----------
    results : sequence of NormalResult
        The solved states of a run (any order).
    periodic : bool
        The grid is periodic (no edge check).
    interaction : Interaction, optional
        The stress law outside contact (Dugdale: cohesive-zone check).
    radius : float, optional
        Composite sphere radius (m), for the contact-size check.
    """
    out: list[str] = []
    res = [r for r in results if r is not None]
    if not res:
        return out
    if not periodic:
        touching = [r for r in res if _touches_edge(np.asarray(r.contact, bool) | np.asarray(r.adhesive, bool))]
        if touching:
            out.append(f"edge: the contact or the cohesive zone touches the edge of the free-boundary domain in "
                       f"{len(touching)} of {len(res)} saved state(s): the domain truncates it; enlarge grid.size")
    if interaction is not None and getattr(interaction, "h0", None):
        widths = [cohesive_cells(r) for r in res if np.asarray(r.contact, bool).any()]
        widths = [w for w in widths if math.isfinite(w)]
        if widths:
            w = min(widths)
            if w < MIN_COHESIVE_CELLS:
                what = "narrower than one cell (no cohesive node beside the contact)" if w == 0 else f"about {w:.1f} cells wide"
                out.append(f"cohesive_zone: the cohesive zone is {what} (fewer than {MIN_COHESIVE_CELLS:g}): "
                           "adhesive and pull-off forces are set by the grid, not resolved; refine grid.n or "
                           "shrink the domain")
    frac = max(float(np.mean(np.asarray(r.contact, bool))) for r in res)
    if frac > FULL_CONTACT:
        out.append(f"full_contact: the contact covers {100 * frac:.0f} % of the domain: the domain is too small "
                   "for this load (free boundary: enlarge grid.size; periodic: the cell is nearly in full contact)")
    if radius:
        a = max(math.sqrt(np.count_nonzero(np.asarray(r.contact, bool)) * r.grid.cell_area / math.pi) for r in res)
        if a > MAX_A_OVER_R * radius:
            out.append(f"large_contact: contact radius {a:.3g} m is {a / radius:.2f} of the sphere radius "
                       f"{radius:.3g} m (> {MAX_A_OVER_R:g}): the half-space, small-slope model does not hold")
    return out
