"""Sanity and resolution checks of a run's results: numbers the grid cannot back get a warning.

Each check looks at the solved states (not at the inputs), so it holds for any geometry.  Each
warning starts with the check's name and a colon (:data:`CHECKS`):

* ``edge``: on a free-boundary grid the contact or the cohesive zone touches the domain edge
  (the zero-padded operator then truncates the load: enlarge the domain).  The cohesive zone
  here is the set of tensile nodes whose stress is at least :data:`EDGE_TENSION_FRACTION` of the
  largest tension: a Dugdale zone or a meniscus (uniform tension) counts wherever it reaches,
  the decaying tail of a van der Waals law (1/g^3, nonzero on every node) does not;
* ``cohesive_zone``: with Dugdale adhesion, the cohesive zone around the contact is narrower
  than :data:`MIN_COHESIVE_CELLS` cells (its width estimated as adhesive area over the outer
  perimeter, exact for a thin ring), or narrower than one cell (no cohesive node next to a
  contact): pull-off and adhesive forces are then set by the grid (lattice trapping);
* ``cohesive_range``: with Dugdale adhesion, the gap changes between neighbouring cells at the
  cohesive zone by more than the Dugdale range h0 (:func:`cohesive_gap_step`): the whole range
  of the law is crossed within one cell, so the zone cannot be resolved whatever its apparent
  width (steep asperity flanks of a rough surface, a coarse grid);
* ``cohesive_edge``: with Dugdale adhesion, the nodes at the edge of the cohesive zone whose gap
  lies within one cell's own displacement under sigma0 (sigma0 x the cell's self-compliance,
  :func:`cell_self_compliance`) of the Dugdale range h0 carry at least :data:`MAX_EDGE_FORCE` of
  the adhesive force (:func:`cohesive_edge_nodes`).  Each such node is consistent on either piece
  of the law: in the zone its tension holds its gap below h0, out of it its gap opens beyond h0.
  So the grid has several equilibria that differ in these nodes; which one a solve ends on
  depends on its iteration path (Polonsky-Keer keeps them in the zone, NormCG out of it), and
  on Maugis-Dugdale spheres the adhesive forces of the two differ by 1.5-2 times the band's.  The band narrows with
  the cell (sigma0 x self-compliance is proportional to the cell size).  Every Dugdale run
  reports the band in summary.json (``cohesive_edge``: nodes, force in N, fraction of the
  adhesive force) whether or not it warns;
* ``full_contact``: the contact covers more than :data:`FULL_CONTACT` of the domain;
* ``large_contact``: a sphere whose contact radius exceeds :data:`MAX_A_OVER_R` of its radius
  (the half-space, small-slope model no longer holds);
* ``contact_cells``: the largest contact patch is fewer than :data:`MIN_CONTACT_CELLS` solver
  cells across (its inscribed diameter, :func:`patch_width`): areas, pressures and forces are set
  by a handful of cells;
* ``topography_pixels``: a measured topography whose pixels are larger than the contact: the
  largest contact patch spans fewer than :data:`MIN_CONTACT_CELLS` pixels of the scan, so the
  contact rests on heights the instrument did not resolve (the solver grid interpolates them);
* ``stick_zone``: tangential kinds: the stick zone of the partial-slip states is fewer than
  :data:`MIN_STICK_CELLS` cells across at its widest, or the run ends in partial slip with such
  a stick zone: stick ratios, the onset of gross slip and the pre-sliding displacement are then
  set by the grid.

:func:`result_warnings` returns one message per check that fires (the worst case over the
states), for summary.json ``warnings``, the report's banner and the CLI.
:func:`compare_expected` compares a run's summary with the ``expected`` value a scenario states.
"""

from __future__ import annotations

import math
from typing import Mapping, Sequence

import numpy as np
from ..interactions.base import law_result_checks
from ..units import format_quantity

__all__ = [
    "result_warnings", "warning_names", "cohesive_cells", "cohesive_gap_step", "patch_width",
    "stick_zone_width", "scan_pixel", "cell_self_compliance", "cohesive_edge_nodes", "cohesive_edge_band",
    "compare_expected", "pull_off_statement", "CHECKS",
    "MIN_COHESIVE_CELLS", "MIN_CONTACT_CELLS",
]

#: Names of the checks (the prefix of their warnings).
CHECKS = ("edge", "cohesive_zone", "cohesive_range", "cohesive_edge", "full_contact", "large_contact", "contact_cells",
          "topography_pixels", "stick_zone")

#: Fewest cells across the cohesive zone for resolved adhesive forces (Maugis-Dugdale pull-off
#: is ~5 % high at ~4 cells, within 1 % at ~8).
MIN_COHESIVE_CELLS = 3.0
#: Largest gap change between neighbouring cells at the cohesive zone, in units of h0: beyond
#: it the Dugdale range is crossed within one cell.
MAX_GAP_STEP = 1.0
#: Largest force of the cohesive zone's two-way edge nodes (:func:`cohesive_edge_nodes`), as a
#: fraction of the state's adhesive force, before the ``cohesive_edge`` warning.  The adhesive
#: forces of the grid's equilibria are uncertain by about this fraction (on Maugis-Dugdale
#: spheres the analytic force was 0.4-1.3 band from either solver's at lambda = 0.3-2, validation
#: case ``md_grid_band``), loop energies by about
#: three times it (one loop measured); 5 %: the bar of the adhesion validation.  Relative to
#: the net force the band is larger where the adhesive and repulsive parts nearly cancel
#: (lambda = 5 on 1248^2: 2.6 % of the adhesive force, 4-6 % of the net force scale).
#: Below it the fraction is still in summary.json (``cohesive_edge``) and the report.
MAX_EDGE_FORCE = 0.05
#: Contact fraction above which the domain is too small for the contact.
FULL_CONTACT = 0.9
#: Largest contact radius over sphere radius for the half-space model.
MAX_A_OVER_R = 0.1
#: Fewest cells (solver cells or scan pixels) across the largest contact patch.
MIN_CONTACT_CELLS = 3.0
#: Fewest cells across the widest stick zone of a partial-slip run.
MIN_STICK_CELLS = 3.0
#: Tension (fraction of a state's largest tension) above which a non-contact node counts as
#: part of the cohesive zone for the edge check: a long-range law's tail below it carries a
#: negligible load at the edge (1 % of the peak stress of a van der Waals 1/g^3 law is reached
#: at 4.6 times the gap of the peak).
EDGE_TENSION_FRACTION = 0.01


def _perimeter_cells(mask: np.ndarray) -> int:
    """Number of cell edges between the mask and its complement (inside the grid)."""
    m = mask.astype(np.int8)
    return int(np.abs(np.diff(m, axis=0)).sum() + np.abs(np.diff(m, axis=1)).sum())


def _edge_mask(res) -> np.ndarray:
    """Contact plus the tensile nodes that carry at least EDGE_TENSION_FRACTION of the largest
    tension (the cohesive zone or meniscus, not a van der Waals tail)."""
    contact = np.asarray(res.contact, bool)
    adh = np.asarray(res.adhesive, bool)
    if adh.any():
        p = np.asarray(res.pressure, float)
        adh = adh & (p <= EDGE_TENSION_FRACTION * float(np.min(p[adh])))
    return contact | adh


def _touches_edge(mask: np.ndarray) -> bool:
    return bool(mask[0, :].any() or mask[-1, :].any() or mask[:, 0].any() or mask[:, -1].any())


def cohesive_cells(res) -> float:
    """Estimated width of the cohesive zone in cells: adhesive area / outer perimeter / dx
    (for a ring from a to c: (c^2 - a^2)/(2c), i.e. c - a for a thin ring).

    An area-over-perimeter width works for any zone shape (rings, several contact spots),
    where a radius c - a would need a round contact.

    Parameters
    ----------
    res : NormalResult
        A solved normal state (``adhesive``, ``contact``, ``grid``).

    Returns
    -------
    float
        Width in cells (dimensionless); inf without cohesive nodes and without contact, 0
        with contact but no cohesive node.
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


def cell_self_compliance(dx: float, dy: float, effective_modulus: float | None = None, *, pair=None) -> float:
    """Displacement (m/Pa) of a cell's centre under a unit pressure on that cell alone.

    With ``pair``: its body model's (:meth:`~tribobem.elasticity.bodies.BodyModel.self_compliance`).
    Else the homogeneous half-space of modulus ``effective_modulus``, Love's uniform pressure on a
    dx x dy rectangle: w = (4 / (pi E*)) [a asinh(b / a) + b asinh(a / b)] with a = dx/2, b = dy/2
    (for a square cell 1.122 dx / E*): the zz influence coefficient at zero offset
    (:func:`~tribobem.elasticity.influence.composite_coefficients`), the diagonal of the
    free-boundary influence matrix (the periodic one's
    differs by the images and the removed mean: -1.7 % on a 64^2 cell, -0.4 % on 256^2).
    The two agree to the last bit for a half-space pair.

    Parameters
    ----------
    dx, dy : float
        Cell size (m).
    effective_modulus : float, optional
        Composite modulus E* of the pair (Pa), 1/E* = (1 - nu1^2)/E1 + (1 - nu2^2)/E2; needed
        without ``pair``.
    pair : ContactPair, optional
        The two bodies: their body model gives the self-compliance (``effective_modulus`` is then
        not used).

    Returns
    -------
    float
        m/Pa.
    """
    from ..elasticity.bodies import body_model_of, halfspace_self_compliance

    if pair is not None:
        return float(body_model_of(pair).self_compliance(pair, dx, dy))
    if effective_modulus is None:
        raise TypeError("cell_self_compliance needs effective_modulus or pair")

    return halfspace_self_compliance(dx, dy, effective_modulus)


def cohesive_edge_nodes(res, h0: float, sigma0: float, compliance: float) -> tuple[int, float]:
    """The nodes at the edge of a Dugdale cohesive zone that are consistent on either piece of
    the law, and the adhesive force they carry in it.

    A node in the zone (0 < g < h0, tension sigma0) whose gap is above h0 - sigma0 C would open
    beyond h0 without its own tension; a free node (g >= h0) next to the zone or the contact
    whose gap is below h0 + sigma0 C would close into the range under it (C: the cell's
    self-compliance, m/Pa).  Either kind could be on the other piece of the law in another
    equilibrium of the same grid.  Only Dugdale's zone counts: a tensile node whose gap is
    beyond the range (a meniscus, a long-range tail) is not in it, and a free node away from
    the zone's edge is not counted (on a flat top many such gaps lie near h0, and none of them
    borders the zone).

    Parameters
    ----------
    res : NormalResult
        A solved normal state (``gap``, ``contact``, ``adhesive``, ``grid``).
    h0 : float
        Dugdale range (m).
    sigma0 : float
        Dugdale stress (Pa).
    compliance : float
        The cell's self-compliance (m/Pa), e.g. :func:`cell_self_compliance`.

    Returns
    -------
    (int, float)
        The number of such nodes and sigma0 x their area (N).
    """
    g = np.asarray(res.gap, dtype=float)
    contact = np.asarray(res.contact, bool)
    jump = sigma0 * compliance
    zone = _dugdale_zone(res, h0, jump)
    held = zone | contact
    # 4-neighbours of the zone or the contact (no wrap: the edge nodes of a free grid have fewer)
    near = np.zeros_like(held)
    near[1:, :] |= held[:-1, :]
    near[:-1, :] |= held[1:, :]
    near[:, 1:] |= held[:, :-1]
    near[:, :-1] |= held[:, 1:]
    two_way = (zone & (g > h0 - jump)) | (~held & near & (g >= h0) & (g < h0 + jump))
    n = int(np.count_nonzero(two_way))
    return n, n * sigma0 * res.grid.cell_area


def _dugdale_zone(res, h0: float, jump: float) -> np.ndarray:
    """The Dugdale cohesive nodes of a state: tensile, out of contact, gap within the range
    (h0 plus the band ``jump``, where a two-way node may sit at convergence)."""
    g = np.asarray(res.gap, dtype=float)
    contact = np.asarray(res.contact, bool)
    return np.asarray(res.adhesive, bool) & ~contact & (g < h0 + jump)


def cohesive_gap_step(res) -> float:
    """Largest gap change (m) between two neighbouring cells at the cohesive zone of a state.

    The pairs counted are the 4-neighbour pairs with a cohesive-zone node (0 < g < h0) and the
    pairs of a contact node and a node outside the zone (g >= h0): where the zone is resolved
    the gap climbs from 0 to h0 over several cells and every such step is a fraction of h0;
    where a contact node borders a node beyond the range, the gap jumps over the whole range in
    one cell.

    Parameters
    ----------
    res : NormalResult
        A solved normal state (``gap``, ``contact``, ``adhesive``).

    Returns
    -------
    float
        The largest step (m); NaN when the state has neither kind of pair.
    """
    g = np.asarray(res.gap, float)
    con = np.asarray(res.contact, bool)
    adh = np.asarray(res.adhesive, bool)
    outside = ~(con | adh)
    worst = -np.inf
    for axis in (0, 1):
        a = [slice(None)] * 2
        b = [slice(None)] * 2
        a[axis], b[axis] = slice(1, None), slice(None, -1)
        a, b = tuple(a), tuple(b)
        pair = adh[a] | adh[b] | (con[a] & outside[b]) | (outside[a] & con[b])
        if pair.any():
            worst = max(worst, float(np.abs(g[a] - g[b])[pair].max()))
    return worst if math.isfinite(worst) else math.nan


def patch_width(mask, dx: float, dy: float | None = None) -> float:
    """Width (m) of the widest patch of ``mask``: the diameter of the largest disc inscribed in it.

    From the Euclidean distance transform on the mask sampled twice finer (each cell split in
    2 x 2): twice the largest distance of a sub-cell centre to the nearest sub-cell outside, so
    that a k x k block of cells is exactly k cells wide, a disc of D cells about D, a ring of w
    cells about w.  Patches 12 or more cells wide are measured on the cells alone (2 max(distance)
    - half a cell: within about a cell).

    Parameters
    ----------
    mask : array_like of bool
        The patches, grid-shaped.
    dx : float
        Cell size along x (m).
    dy : float, optional
        Cell size along y (m); default ``dx``.

    Returns
    -------
    float
        Width (m); 0 for an empty mask.
    """
    from scipy.ndimage import distance_transform_edt

    m = np.asarray(mask, bool)
    if not m.any():
        return 0.0
    dy = dx if dy is None else dy
    # On the cells themselves first: for a patch many cells wide that is accurate to a cell,
    # and the finer pass (four times the memory) is only needed near the 3-cell threshold.
    coarse = 2.0 * distance_transform_edt(np.pad(m, 1), sampling=(dx, dy)).max() - 0.5 * min(dx, dy)
    if coarse >= 12.0 * max(dx, dy):
        return float(coarse)
    rows, cols = np.flatnonzero(m.any(axis=1)), np.flatnonzero(m.any(axis=0))
    box = m[rows[0]:rows[-1] + 1, cols[0]:cols[-1] + 1]  # the patches only: the rest is empty
    fine = np.repeat(np.repeat(box, 2, axis=0), 2, axis=1)
    # a ring of False around it, so that a patch at the grid edge is measured inside the grid
    d = distance_transform_edt(np.pad(fine, 1), sampling=(dx / 2.0, dy / 2.0))
    return float(2.0 * d.max())


def stick_zone_width(tres) -> float:
    """Width (m) across the widest stick patch of a tangential state (:func:`patch_width`).

    Parameters
    ----------
    tres : TangentialResult
        A solved tangential state (``stick``, ``contact``, ``grid``).

    Returns
    -------
    float
        Width (m) of the widest patch of stick nodes in compressive contact; 0 without one.
    """
    g = tres.grid
    return patch_width(np.asarray(tres.stick, bool) & np.asarray(tres.contact, bool), g.dx, g.dy)


def scan_pixel(files: Mapping | None) -> tuple[float, str] | None:
    """Largest pixel (m) of the measured topographies of a problem and the body it belongs to.

    Parameters
    ----------
    files : mapping or None
        The ``problem.info["files"]`` table of :func:`tribobem.scenario.build_problem`
        (``scan_grid`` and ``scan_size`` of each measured roughness); entries without them
        are skipped.

    Returns
    -------
    tuple of (float, str) or None
        (largest pixel side in m, key of its entry); None without measured files.
    """
    best = None
    for key, f in (files or {}).items():
        try:
            (nx, ny), (lx, ly) = f["scan_grid"], f["scan_size"]
            px = max(float(lx) / int(nx), float(ly) / int(ny))
        except (KeyError, TypeError, ValueError, ZeroDivisionError):
            continue
        if best is None or px > best[0]:
            best = (px, str(key))
    return best


def cohesive_edge_band(results: Sequence, interaction, effective_modulus: float | None, *, pair=None) -> dict | None:
    """The worst state's two-way edge nodes of a Dugdale cohesive zone (:func:`cohesive_edge_nodes`).

    The band is a fraction of the state's adhesive force.  It measures
    how far the grid's equilibria can differ only where the zone is resolved: where it is
    narrower than one cell (:func:`cohesive_cells`), where the gap crosses the Dugdale range
    within one cell (:func:`cohesive_gap_step`: no node lies near h0, so the count is 0 however
    coarse the grid) or where the two-way nodes would carry more than the zone itself, the
    state is *not resolved* (``resolved`` False, ``reason`` says which) and no fraction is shown.

    Parameters
    ----------
    results : sequence of NormalResult
        The solved states of a run.
    interaction : Interaction or None
        The stress law outside contact; only a law that declares the ``cohesive_edge`` check
        (:func:`~tribobem.interactions.base.law_result_checks`: Dugdale) has the band (None
        otherwise).
    effective_modulus : float or None
        Composite modulus E* of the pair (Pa); None: no band (unless ``pair`` is given).
    pair : ContactPair, optional
        The two bodies: the cell's self-compliance is their body model's
        (:func:`cell_self_compliance`), E* theirs when ``effective_modulus`` is None.

    Returns
    -------
    dict or None
        ``nodes`` (count), ``force`` (N, sigma0 x their area), ``fraction`` (of that state's
        adhesive force; None where not resolved), ``gap_band`` (sigma0 x C, m), ``resolved``
        (bool) and ``reason`` (str or None) of the state where the fraction is largest, or of
        the first state that is not resolved; None without Dugdale adhesion, E* or a state with
        an adhesive force and a cohesive zone.
    """
    if effective_modulus is None and pair is not None:
        effective_modulus = pair.effective_modulus
    if ("cohesive_edge" not in law_result_checks(interaction)
            or not effective_modulus or effective_modulus <= 0):
        return None
    res = [r for r in results if r is not None]
    if not res:
        return None
    h0, sigma0 = interaction.h0, interaction.sigma0
    C = cell_self_compliance(res[0].grid.dx, res[0].grid.dy, effective_modulus, pair=pair)
    jump = sigma0 * C
    worst = None
    for r in res:
        f_adh = abs(float(r.adhesive_force))
        if f_adh <= 0 or not _dugdale_zone(r, h0, jump).any():
            continue
        n, f = cohesive_edge_nodes(r, h0, sigma0, C)
        reason = None
        in_contact = bool(np.asarray(r.contact, bool).any())
        width = cohesive_cells(r) if in_contact else math.inf
        step = cohesive_gap_step(r) if in_contact else math.nan
        if width < 1.0:
            reason = f"the cohesive zone is about {width:.1f} cell(s) wide (narrower than one cell)"
        elif math.isfinite(step) and step > MAX_GAP_STEP * h0:
            reason = f"the gap crosses the Dugdale range within one cell (by up to {step / h0:.2g} h0)"
        elif f > f_adh:
            reason = "the two-way nodes would carry more than the adhesive force itself"
        row = {"nodes": n, "force": f, "fraction": None if reason else f / f_adh, "gap_band": jump,
               "resolved": reason is None, "reason": reason}
        if reason is not None:
            if worst is None or worst["resolved"]:
                worst = row
        elif worst is None or (worst["resolved"] and row["fraction"] > worst["fraction"]):
            worst = row
    return worst


def _cohesive_edge_warning(res, interaction, effective_modulus, pair=None) -> str | None:
    """The ``cohesive_edge`` warning over the states (the worst one), or None."""
    band = cohesive_edge_band(res, interaction, effective_modulus, pair=pair)
    if band is None:
        return None
    if not band["resolved"]:
        return (f"cohesive_edge: the grid's band of Dugdale equilibria is not resolved in at least one saved state: "
                f"{band['reason']}, so the grid cannot say how far its adhesive and pull-off forces are from the "
                "continuous solution (they are set by a few cells); refine grid.n or shrink the domain")
    if band["fraction"] < MAX_EDGE_FORCE:
        return None
    frac, n, f, jump = band["fraction"], band["nodes"], band["force"], band["gap_band"]
    return (f"cohesive_edge: {n} node(s) at the edge of the cohesive zone have gaps within sigma0 x the cell's "
            f"self-compliance ({jump:.3g} m = {jump / interaction.h0:.2g} h0) of the Dugdale range h0, so each is "
            f"consistent both in and out of the zone; they carry {format_quantity(f, 'force')}, {100 * frac:.1f} % "
            "of the adhesive force, in at least one saved state. The grid has equilibria that differ in these "
            "nodes, and which one a solve ends on depends on its iteration path (solver.method, the load steps): "
            f"adhesive and pull-off forces are set by the grid to about +-{100 * frac:.1f} %, loop energies to a "
            "few times that; refine grid.n (the band narrows with the cell)")


def warning_names(warnings: Sequence[str]) -> list[str]:
    """The check names (:data:`CHECKS`) of a list of warnings, in order, without repeats.

    Parameters
    ----------
    warnings : sequence of str
        Warning lines ``"name: message"``; lines of other origins are ignored.

    Returns
    -------
    list of str
        The names that are in :data:`CHECKS`.
    """
    out = []
    for w in warnings or []:
        name = str(w).split(":", 1)[0].strip()
        if name in CHECKS and name not in out:
            out.append(name)
    return out


def result_warnings(results: Sequence, *, periodic: bool, interaction=None, radius: float | None = None,
                    tangential: Sequence | None = None, files: Mapping | None = None,
                    gross_slip: bool | None = None, effective_modulus: float | None = None,
                    grid_band: bool = True, pair=None) -> list[str]:
    """Warnings for states the grid cannot back (see the module docstring).

    Parameters
    ----------
    results : sequence of NormalResult
        The solved states of a run (any order).
    periodic : bool
        The grid is periodic (no edge check).
    interaction : Interaction, optional
        The stress law outside contact: the checks it declares
        (:func:`~tribobem.interactions.base.law_result_checks`; Dugdale: the cohesive-zone
        checks, which read its ``sigma0`` and ``h0``) run.
    radius : float, optional
        Composite sphere radius (m), for the contact-size check.
    tangential : sequence of TangentialResult, optional
        The tangential states of a partial-slip or hysteresis run (in path order), for the
        stick-zone check.
    files : mapping, optional
        ``problem.info["files"]``: the measured topographies (scan grid and size), for the
        pixel check.
    gross_slip : bool, optional
        The run's own verdict (summary ``gross_slip``): False when it claims that the last
        state is still in partial slip, which the stick-zone check then requires resolved.
    effective_modulus : float, optional
        Composite modulus E* of the pair (Pa), for the ``cohesive_edge`` check (skipped
        without it).
    grid_band : bool
        Run the ``cohesive_edge`` check (default).  False for runs with menisci, where the
        tension outside contact is not Dugdale's two-valued law alone.
    pair : ContactPair, optional
        The two bodies, for the ``cohesive_edge`` check: their body model's cell self-compliance
        (:func:`cell_self_compliance`) instead of the half-space's of ``effective_modulus``.

    Returns
    -------
    list of str
        One ``"name: message"`` line per check that fired (names from :data:`CHECKS`); empty
        when the grid backs every state.
    """
    out: list[str] = []
    res = [r for r in results if r is not None]
    if not res:
        return out
    grid = res[0].grid
    dx, dy = grid.dx, grid.dy
    cell = max(dx, dy)
    if not periodic:
        touching = [r for r in res if _touches_edge(_edge_mask(r))]
        if touching:
            out.append(f"edge: the contact or the cohesive zone touches the edge of the free-boundary domain in "
                       f"{len(touching)} of {len(res)} saved state(s): the domain truncates it; enlarge grid.size")
    # (a two-scale macro state's cohesive zone lives in its windows, not in the macro cells: the
    # two-scale runner checks the windows' cells itself)
    in_contact = [r for r in res if np.asarray(r.contact, bool).any()
                  and not (getattr(r, "info", None) or {}).get("two_scale")]
    declared = law_result_checks(interaction)
    h0 = interaction.h0 if declared & {"cohesive_zone", "cohesive_edge", "cohesive_range"} else None
    if h0 and "cohesive_zone" in declared:
        widths = [cohesive_cells(r) for r in in_contact]
        widths = [w for w in widths if math.isfinite(w)]
        if widths:
            w = min(widths)
            if w < MIN_COHESIVE_CELLS:
                what = "narrower than one cell (no cohesive node beside the contact)" if w == 0 else f"about {w:.1f} cells wide"
                out.append(f"cohesive_zone: the cohesive zone is {what} (fewer than {MIN_COHESIVE_CELLS:g}): "
                           "adhesive and pull-off forces are set by the grid, not resolved; refine grid.n or "
                           "shrink the domain")
    if h0 and "cohesive_edge" in declared:
        edge = _cohesive_edge_warning(res, interaction, effective_modulus, pair) if grid_band else None
        if edge:
            out.append(edge)
    if h0 and "cohesive_range" in declared:
        steps = [cohesive_gap_step(r) for r in in_contact]
        steps = [s for s in steps if math.isfinite(s)]
        if steps and max(steps) > MAX_GAP_STEP * h0:
            s = max(steps)
            out.append(f"cohesive_range: the gap changes by up to {s:.3g} m = {s / h0:.2g} h0 between neighbouring "
                       f"cells at the cohesive zone (Dugdale range h0 = {h0:.3g} m): the range of the adhesive "
                       f"law is crossed within one cell ({cell:.3g} m), so the cohesive zone cannot be resolved; "
                       "refine grid.n or shrink the domain")
    frac = max(float(np.mean(np.asarray(r.contact, bool))) for r in res)
    if frac > FULL_CONTACT:
        out.append(f"full_contact: the contact covers {100 * frac:.0f} % of the domain: the domain is too small "
                   "for this load (free boundary: enlarge grid.size; periodic: the cell is nearly in full contact)")
    if radius:
        a = max(math.sqrt(np.count_nonzero(np.asarray(r.contact, bool)) * r.grid.cell_area / math.pi) for r in res)
        if a > MAX_A_OVER_R * radius:
            out.append(f"large_contact: contact radius {a:.3g} m is {a / radius:.2f} of the sphere radius "
                       f"{radius:.3g} m (> {MAX_A_OVER_R:g}): the half-space, small-slope model does not hold")
    if in_contact:
        # the smallest of the states' largest patches: the state least backed by the grid
        width = min(patch_width(r.contact, dx, dy) for r in in_contact)
        if width < MIN_CONTACT_CELLS * cell:
            out.append(f"contact_cells: the largest contact patch is {width / cell:.1f} cell(s) across "
                       f"({width:.3g} m; fewer than {MIN_CONTACT_CELLS:g} cells of {cell:.3g} m) in at least one "
                       "saved state: its area, pressure and force are set by the grid; refine grid.n or shrink the "
                       "domain")
        px = scan_pixel(files)
        if px is not None and width < MIN_CONTACT_CELLS * px[0]:
            out.append(f"topography_pixels: the measured topography of {px[1]} has pixels of {px[0]:.3g} m, and the "
                       f"largest contact patch is {width / px[0]:.1f} pixel(s) across ({width:.3g} m; fewer than "
                       f"{MIN_CONTACT_CELLS:g}) in at least one saved state: the contact rests on heights the scan "
                       "did not resolve; use a scan with finer pixels or a larger load")
    # (a two-scale state's stick map marks where most of a window's contact sticks; its stick ratio
    # and onset come from the windows, not from the macro cells, so the rule does not apply)
    tan = [t for t in (tangential or []) if hasattr(t, "stick") and hasattr(t, "contact")
           and not (getattr(t, "info", None) or {}).get("two_scale")]
    partial = [t for t in tan if np.asarray(t.stick, bool).any() and not bool(t.gross_slip)
               and np.any(np.asarray(t.contact, bool) & ~np.asarray(t.stick, bool))]
    if partial:
        widest = max(stick_zone_width(t) for t in partial)
        # A run that claims no gross slip ends in partial slip: its last stick zone must be
        # resolved for that claim to hold.
        claims_partial = gross_slip is False and any(tan[-1] is t for t in partial)
        w_last = stick_zone_width(tan[-1]) if claims_partial else math.inf
        if widest < MIN_STICK_CELLS * cell:
            out.append(f"stick_zone: the stick zone of the partial-slip states is at most {widest / cell:.1f} cell(s) "
                       f"across (fewer than {MIN_STICK_CELLS:g}): stick ratios, the gross-slip onset and the "
                       "pre-sliding displacement are set by the grid; refine grid.n or shrink the domain")
        elif w_last < MIN_STICK_CELLS * cell:
            out.append(f"stick_zone: the run ends in partial slip with a stick zone {w_last / cell:.1f} cell(s) "
                       f"across (fewer than {MIN_STICK_CELLS:g}): the grid cannot tell it from gross slip; refine "
                       "grid.n or extend the ramp past the onset")
    return out


# ----------------------------------------------------------------------------- expected values
def _summary_value(summary: Mapping, key: str, step: int | None, rh: float | None = None):
    if step is None and key in summary and not isinstance(summary[key], (list, dict)):
        return summary[key], "run"
    if rh is not None and isinstance(summary.get(key), list) and isinstance(summary.get("rh"), list):
        # a humid run's run-level list in RH order, read at the stated RH
        rhs = summary["rh"]
        hit = [i for i, v in enumerate(rhs) if abs(float(v) - float(rh)) <= 1e-12]
        if not hit or len(summary[key]) != len(rhs):
            return None, f"RH {rh:g}"
        return summary[key][hit[0]], f"RH {rh:g}"
    steps = summary.get("steps") or []
    i = -1 if step is None else int(step)
    if not steps or not (-len(steps) <= i < len(steps)):
        return None, f"step {i}"
    return steps[i].get(key), f"step {steps[i].get('index', i)}"


def compare_expected(summary: Mapping, expected: Mapping | None, dimensions: Mapping | None = None) -> dict | None:
    """Computed against expected values (the scenario's ``expected`` metadata, in SI).

    Parameters
    ----------
    summary : mapping
        A run's summary (summary.json content): run-level keys and ``steps``.
    expected : mapping or None
        ``{"values": {key: value (SI)}, "tolerance": relative, "step": int or None,
        "warnings": [check names], "reference": str}`` as the schema's
        :class:`~tribobem.scenario.schema.ExpectedSpec` dumps it.  A key that is not a run-level
        scalar of the summary is looked up in ``steps[step]`` (default: the last step); with
        ``"rh"``, a run-level list in RH order (humid runs) is read at that RH.
    dimensions : mapping, optional
        Key -> dimension ("force", "length", ...) of the keys the run kind produces: copied to
        each row (``dimension``) so that the report shows the values in units.

    Returns
    -------
    dict or None
        ``{"reference", "tolerance", "values": [{"key", "where", "expected", "computed",
        "relative_error", "within"}], "warnings": [{"name", "present"}], "met"}``; None without
        ``expected``.  ``met`` is True when every value is within the tolerance and every
        expected warning is present.
    """
    if not expected:
        return None
    tol = expected.get("tolerance")
    rows = []
    for key, ref in (expected.get("values") or {}).items():
        got, where = _summary_value(summary, key, expected.get("step"), expected.get("rh"))
        if isinstance(got, (int, float, np.floating, np.integer)) and not isinstance(got, (bool, np.bool_)) \
                and math.isfinite(float(got)):
            got = float(got)
            err = abs(got - ref) / abs(ref) if ref != 0 else abs(got)
            within = tol is not None and err <= tol
        else:
            got, err, within = None, None, False
        rows.append({"key": key, "where": where, "expected": ref, "computed": got, "relative_error": err,
                     "within": bool(within), "dimension": (dimensions or {}).get(key)})
    present = set(warning_names(summary.get("warnings") or []))
    warns = [{"name": w, "present": w in present} for w in (expected.get("warnings") or [])]
    met = all(r["within"] for r in rows) and all(w["present"] for w in warns)
    return {"reference": expected.get("reference"), "tolerance": tol, "values": rows, "warnings": warns,
            "met": bool(met)}


def pull_off_statement(summary: Mapping) -> str:
    """One line for a pull-off run: the pull-off force, its expected value and the resolution.

    Parameters
    ----------
    summary : mapping
        A pull-off run's summary (``pull_off_force``, ``expected``, ``warnings``,
        ``cohesive_zone_cells``, ``cohesive_edge``).

    Returns
    -------
    str
        E.g. ``"pull-off -0.2549 µN (Maugis-Dugdale ... -0.25 µN, +2.0 %; cohesive zone 10.1
        cells wide, grid band +-3.2 %: resolved)"`` (the band: summary ``cohesive_edge``);
        "NOT resolved" with the names of the checks that fired.
    """
    f = summary.get("pull_off_force")
    text = f"pull-off {format_quantity(f, 'force', 4)}"
    inside = []
    exp = summary.get("expected") or {}
    for row in exp.get("values") or []:
        if row.get("key") == "pull_off_force" and row.get("relative_error") is not None:
            sign = "+" if abs(row["computed"]) >= abs(row["expected"]) else "-"
            inside.append(f"{exp.get('reference') or 'expected'}: {format_quantity(row['expected'], 'force', 4)}, "
                          f"{sign}{100 * row['relative_error']:.1f} %")
    fired = warning_names(summary.get("warnings") or [])
    cells = summary.get("cohesive_zone_cells")
    zone = f"cohesive zone {cells:.1f} cells wide" if isinstance(cells, (int, float)) else "cohesive zone"
    grid = ""
    band = summary.get("cohesive_edge")
    if isinstance(band, Mapping):
        grid = (f", grid band +-{100 * float(band['fraction']):.1f} %" if band.get("fraction") is not None
                else ", grid band not resolved")
    if fired:
        inside.append(f"{zone}{grid}: NOT resolved ({', '.join(fired)}: see the warnings)")
    else:
        inside.append(f"{zone}{grid}: resolved")
    return f"{text} ({'; '.join(inside)})"
