"""What the whole-grid and the two-scale hysteresis runs share: the lateral stiffness K_L of a
friction loop (Paper F: the fit of its last rising branch and its slopes at the points A, B, C)
and the states a loop keeps for fields.nc."""

from __future__ import annotations

import numpy as np

from ..analysis.loops import STIFFNESS_POINTS, fit_eq3
from ..errors import InputError

__all__ = ["lateral_stiffness_fit", "stiffness_table", "kept_states"]


def kept_states(turning, n_rows: int) -> list:
    """The rows of a loop whose states go to fields.nc: the start (row 0) and each turning point
    with the step after it (Paper E's A, D, D', H, H', ...); ``turning`` flags the path's steps,
    row k + 1 is step k."""
    keep = [0]
    for i, turn in enumerate(turning):
        if turn:
            keep += [i + 1, i + 2] if i + 2 < n_rows else [i + 1]
    return sorted(set(k for k in keep if k < n_rows))


def lateral_stiffness_fit(forces, displacements):
    """Fit F = c1 (1 - (1 - c2 d)^n) (Paper F Eq. 3) to a branch measured from its turning point.

    The fit itself is :func:`tribobem.analysis.loops.fit_eq3` (bounded least squares from a grid of starts,
    so a branch cut before its plateau does not stop in a local minimum); measured loops
    (``tribobem compare-loop``) are fitted by the same function.

    Parameters
    ----------
    forces, displacements : array_like
        F - F_turn (N) and delta - delta_turn (m) along the branch (both increasing from 0).

    Returns
    -------
    (c1, c2, n) and a callable K(d) = c1 c2 n (1 - c2 d)^(n - 1) (N/m).
    """
    F = np.asarray(forces, float)
    d = np.asarray(displacements, float)
    if len(F) < 4:
        raise InputError("lateral_stiffness", f"need at least 4 points on the branch to fit, got {len(F)}")
    (c1, c2, n), _ = fit_eq3(d, F)

    def K(x):
        return c1 * c2 * n * np.clip(1.0 - c2 * np.asarray(x, float), 1e-12, None) ** (n - 1.0)

    return (c1, c2, n), K


def _along(row, e) -> tuple[float, float]:
    """(F_t, delta_t) of a step: its tangential force and displacement along the load direction e
    (x for direction 0)."""
    return (row["tangential_force_x"] * e[0] + row["tangential_force_y"] * e[1],
            row["displacement_x"] * e[0] + row["displacement_y"] * e[1])


def stiffness_table(rows, mu, f0p, reference, e=(1.0, 0.0)):
    """K_L at A, B, C on the last branch from -F* to +F* (fit from its turning point), along the
    load direction ``e``, beside the slopes of ``reference`` (an
    :class:`~tribobem.analytic.tangential_axisymmetric.AxisymmetricPartialSlip` or None)."""
    idx = [i for i, r in enumerate(rows) if r.get("branch") == "reloading"]
    if not idx:
        return [], {}
    last_cycle = max(rows[i]["cycle"] for i in idx)
    br = [i for i in idx if rows[i]["cycle"] == last_cycle]
    turn = br[0] - 1  # the turning point -F* (last step of the unloading branch)
    # Paper F fits the pre-sliding part of the branch: stop at the first step in gross slip.
    pre = []
    for i in br:
        pre.append(i)
        if rows[i].get("gross_slip"):
            break
    br = pre
    F0, d0 = _along(rows[turn], e)
    F = np.array([_along(rows[i], e)[0] for i in br]) - F0
    D = np.array([_along(rows[i], e)[1] for i in br]) - d0
    F = np.concatenate([[0.0], F])
    D = np.concatenate([[0.0], D])
    (c1, c2, n), K = lateral_stiffness_fit(F, D)

    Fstar = -F0
    table = []
    for name, ratio in STIFFNESS_POINTS.items():
        Ft = ratio * mu * f0p
        if not (-Fstar <= Ft <= Fstar):
            continue
        dd = float(np.interp(Ft - F0, F, D))
        k_fit = float(K(dd))
        row = {"point": name, "force_ratio": ratio, "tangential_force": Ft, "displacement": dd + d0,
               "stiffness": k_fit}
        if reference is not None:
            # The exact branch of the geometry's reference through the same turning point, with F0+
            # for P, and its virgin-curve slope at the same |force| (for a sphere: Paper F Eq. 6).
            try:
                k_md = float(reference.reloading_stiffness(Ft, Fstar))
                k_virgin = float(reference.virgin_stiffness(abs(Ft)))
            except InputError:  # e.g. F* beyond mu F0+ (F0+ fell along the path)
                k_md = k_virgin = float("nan")
            row.update(reference_stiffness=k_md, reference_virgin_stiffness=k_virgin)
            if reference.name == "Mindlin-Deresiewicz":  # the file-contract keys of the sphere's reference
                row.update(mindlin_stiffness=k_md, virgin_stiffness=k_virgin)
        table.append(row)
    return table, {"c1": c1, "c2": c2, "n": n}
