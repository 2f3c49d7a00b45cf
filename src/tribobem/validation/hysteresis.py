"""Validation of friction hysteresis (Papers E and F).

Cases
-----
``mindlin_deresiewicz``
    Two identical steel bodies (no coupling), sphere R = 10 mm, P = 10 N, mu = 0.3, free
    boundary over +-1.5a, one cycle 0 -> +Q* -> -Q* -> +Q* at Q* = 0.8 mu P with the incremental
    slip criterion.  Against Mindlin-Deresiewicz (with the corrected Eq. 2.27c): the
    largest displacement error over the loading, unloading and reloading branches relative to
    the branch amplitude delta* (3%), the loop energy (loop area, 5%), the stick radius at mid
    unloading and mid reloading against the counter-slip radius
    c'/a = (1 - (Q* -+ Q)/(2 mu P))^(1/3) (3%), and the lateral stiffness at Paper F's points A,
    B, C (Q/(mu P) = -0.5, 0, 0.5 on the branch from -Q*) from the fit of Paper F Eq. 3 against
    the slope of the exact branch K0 (1 - (Q* + Q)/(2 mu P))^(1/3), K0 = 8a/k (5%).
    Quick: 64^2, 24 steps per cycle; full: 128^2, 48 steps.
"""

from __future__ import annotations

import math
import warnings

import numpy as np

from ..analytic import mindlin as md
from ..errors import ConvergenceWarning
from ..runs.hysteresis import STIFFNESS_POINTS, lateral_stiffness_fit
from ..solvers.hysteresis import hysteresis_loop, loop_energies
from .common import _row
from .tangential import _mindlin_k, cattaneo_problem

__all__ = ["CASES", "mindlin_deresiewicz_delta"]


def mindlin_deresiewicz_delta(Q, branch: str, Q_star: float, mu: float, P: float, a: float, k: float):
    """Mindlin-Deresiewicz tangential displacement (m) on a branch (corrected Eq. 2.27c).

    Parameters
    ----------
    Q : float or array_like
        Tangential force (N).
    branch : {"loading", "unloading", "reloading"}
        The virgin curve (Cattaneo-Mindlin), the branch from +Q* or the branch from -Q*.
    Q_star : float
        Turning-point amplitude (N); not used on the loading branch.
    mu : float
        Friction coefficient.
    P : float
        Normal force (N).
    a : float
        Contact radius (m).
    k : float
        Tangential compliance (1/Pa), see
        :func:`~tribobem.analytic.mindlin.mindlin_compliance_k`.

    Returns
    -------
    float or ndarray
        Tangential displacement (m), shape of ``Q``.
    """
    if branch == "loading":
        return md.cattaneo_mindlin_displacement(Q, P=P, a=a, mu=mu, k=k)
    if branch == "unloading":
        return md.mindlin_unloading_displacement(Q, Q_star, P=P, a=a, mu=mu, k=k)
    return md.mindlin_reloading_displacement(Q, Q_star, P=P, a=a, mu=mu, k=k)


def _md_rows(quick: bool) -> list:

    n, steps = (64, 24) if quick else (128, 48)
    P, mu, amp = 10.0, 0.3, 0.8
    grid, gap, op, pair, a = cattaneo_problem(n)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ConvergenceWarning)
        run = hysteresis_loop(op, gap, normal_force=P, friction_coefficient=mu, amplitude=amp, cycles=1, steps=steps,
                              tangential_tol=1e-8)

    k = _mindlin_k(pair)
    Qs = run.peak_force  # = amp mu F0+ (F0+ = P without adhesion)
    F = np.array([s.tangential.force_x for s in run.steps])
    D = np.array([s.tangential.displacement_x for s in run.steps])
    br = run.path.branch
    dstar = float(mindlin_deresiewicz_delta(Qs, "loading", Qs, mu, P, a, k))
    case = f"mindlin_deresiewicz {n}^2, Q* = {amp:g} mu P"
    rows = []
    for name in ("loading", "unloading", "reloading"):
        sel = br == name
        ref = mindlin_deresiewicz_delta(F[sel], name, Qs, mu, P, a, k)
        err = np.abs(D[sel] - ref)
        i = int(np.argmax(err))
        rows.append(_row(case, f"delta on the {name} branch (largest error, relative to delta*)",
                         float(ref[i]), float(D[sel][i]), 0.03, scale=dstar))
    W = md.mindlin_loop_energy(Qs, P=P, a=a, mu=mu, k=k)
    E = loop_energies(np.concatenate([[0.0], F]), np.concatenate([[0.0], D]), np.concatenate([[0], run.path.cycle]))
    rows.append(_row(case, "loop energy (loop area)", W, E[0], 0.05))
    # Stick radius mid-branch: the counter-slip radius c'.
    for name in ("unloading", "reloading"):
        idx = np.flatnonzero(br == name)
        j = idx[np.argmin(np.abs(F[idx]))]  # the step nearest Q = 0
        ratio_fn = md.mindlin_unloading_stick_ratio if name == "unloading" else md.mindlin_reloading_stick_ratio
        c_ref = a * float(ratio_fn(F[j], Qs, P=P, mu=mu))
        c_num = math.sqrt(run.steps[j].tangential.stick_area / math.pi)
        rows.append(_row(case, f"stick radius on the {name} branch at Q = {F[j] / (mu * P):+.3f} mu P", c_ref, c_num, 0.03))
    # Lateral stiffness at A, B, C on the reloading branch (fit from the turning point -Q*).
    idx = np.flatnonzero(br == "reloading")
    t = idx[0] - 1
    Fb = np.concatenate([[0.0], F[idx] - F[t]])
    Db = np.concatenate([[0.0], D[idx] - D[t]])
    _, K = lateral_stiffness_fit(Fb, Db)
    for point, ratio in STIFFNESS_POINTS.items():
        Qp = ratio * mu * P
        dd = float(np.interp(Qp - F[t], Fb, Db))
        k_md = float(md.mindlin_reloading_stiffness(Qp, Qs, P=P, a=a, mu=mu, k=k))
        rows.append(_row(case, f"lateral stiffness at {point} (Q = {ratio:+g} mu P), fit vs exact branch slope",
                         k_md, float(K(dd)), 0.05))
    return rows


#: name -> rows(quick)
CASES = {"mindlin_deresiewicz": _md_rows}
