"""Paper A section 6: the bisinusoidal pull-off study (Tables 1-2) and its fit
``F = a E*^beta R_c^(1+beta) dgamma^(1-beta) k^b``.

The computation (:func:`bisinusoidal_cell`, :func:`bisinusoidal_gap`,
:func:`bisinusoidal_pull_off`, the sweep point :func:`pull_off_point`; geometry, gap and
pull-off procedure documented there) lives in the package, :mod:`tribobem.validation.bisinusoidal`,
because the validation case ``bisinusoidal_resolution`` uses it; it is re-exported here.  This
module adds Paper A's tables and the least-squares fit of the computed table.

Units: SI throughout (J/m^2, m, Pa, N).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Mapping

import numpy as np

from tribobem.errors import InputError
from tribobem.validation.bisinusoidal import (
    DEFAULT_N,
    DEFAULT_Z0,
    PAPER_A_S,
    bisinusoidal_cell,
    bisinusoidal_gap,
    bisinusoidal_pull_off,
    pull_off_point,
)

__all__ = [
    "PAPER_A_TABLE1",
    "PAPER_A_FIT",
    "DEFAULT_Z0",
    "DEFAULT_N",
    "PAPER_A_S",
    "bisinusoidal_cell",
    "bisinusoidal_gap",
    "bisinusoidal_pull_off",
    "pull_off_point",
    "fit_pull_off",
    "PullOffFit",
]

#: Paper A Table 1: the 625 combinations (SI units), S = 5 nm.
PAPER_A_TABLE1 = {
    "dgamma": [0.030, 0.040, 0.050, 0.060, 0.070],          # J/m^2
    "R_c": [100e-6, 200e-6, 300e-6, 400e-6, 500e-6],        # m
    "E_star": [80e9, 90e9, 100e9, 110e9, 120e9],            # Pa
    "k": [0.1, 0.3, 0.5, 0.7, 0.9],
}
#: Paper A Table 2: F = a E*^beta R_c^(1+beta) dgamma^(1-beta) k^b.
PAPER_A_FIT = {"a": 10.39, "b": 0.041, "beta": 0.0}


# --------------------------------------------------------------------------------------
# The fit F = a E*^beta R_c^(1+beta) dgamma^(1-beta) k^b
# --------------------------------------------------------------------------------------

@dataclass
class PullOffFit:
    """Least-squares fit (in log space) of ``F = a E*^beta R_c^(1+beta) dgamma^(1-beta) k^b``.

    ``a, b, beta`` are the free fit (``a`` in SI units: N / (Pa^beta m^(1+beta)
    (J/m^2)^(1-beta)), dimensionless when beta = 0); ``a0, b0`` the fit with beta fixed at 0.
    ``r2`` / ``r2_beta0``: coefficient of determination of ln F; ``rms_rel`` /
    ``rms_rel_beta0``: rms relative error of F; ``max_rel``: the largest.  Unpacks as
    ``a, b, beta = fit``.
    """

    a: float
    b: float
    beta: float
    r2: float
    rms_rel: float
    max_rel: float
    a0: float
    b0: float
    r2_beta0: float
    rms_rel_beta0: float
    max_rel_beta0: float
    n: int
    stderr: dict = field(default_factory=dict)

    def __iter__(self):
        return iter((self.a, self.b, self.beta))

    def predict(self, dgamma, R_c, E_star, k, beta0: bool = False):
        """Fitted |F| (N)."""
        if beta0:
            return self.a0 * np.asarray(R_c) * np.asarray(dgamma) * np.asarray(k) ** self.b0
        return (self.a * np.asarray(E_star) ** self.beta * np.asarray(R_c) ** (1 + self.beta)
                * np.asarray(dgamma) ** (1 - self.beta) * np.asarray(k) ** self.b)

    def as_dict(self) -> dict:
        return {k: getattr(self, k) for k in ("a", "b", "beta", "r2", "rms_rel", "max_rel", "a0", "b0",
                                              "r2_beta0", "rms_rel_beta0", "max_rel_beta0", "n")} | {
            "stderr": dict(self.stderr)}


def _column(table, *names):
    for name in names:
        try:
            col = table[name]
        except (KeyError, IndexError, TypeError, ValueError):
            continue
        return np.asarray(col, dtype=float).ravel()
    raise InputError("table", f"needs a column {names[0]!r} (or one of {', '.join(names[1:])})")


def fit_pull_off(table: Mapping) -> PullOffFit:
    """Fit Paper A Eq. 35 to computed pull-off forces.

    Parameters
    ----------
    table : mapping, DataFrame or xarray.Dataset
        Columns (or coordinates) ``dgamma`` (J/m^2), ``R_c`` (m), ``E_star`` (Pa), ``k`` and the force:
        ``F`` / ``pull_off`` (magnitude) or ``pull_off_force`` (sign ignored), in N.
        Rows with a non-finite or zero force are dropped.

    Returns
    -------
    PullOffFit
        ``a, b, beta = fit_pull_off(table)``; the beta = 0 fit and R^2 as attributes.

    Notes
    -----
    ``ln(F / (R_c dgamma)) = ln a + beta ln(E* R_c / dgamma) + b ln k`` is linear in
    ``(ln a, beta, b)``: solved with :func:`scipy.optimize.least_squares` (linear loss),
    which equals ordinary least squares in log space (the paper used a genetic algorithm
    on the same model).
    """
    from scipy.optimize import least_squares

    if hasattr(table, "to_dataframe"):  # an xarray Dataset (e.g. the sweep's results.nc)
        table = table.to_dataframe().reset_index()
    dg = _column(table, "dgamma", "work_of_adhesion")
    R = _column(table, "R_c", "R", "radius")
    E = _column(table, "E_star", "E", "effective_modulus")
    k = _column(table, "k")
    F = np.abs(_column(table, "F", "pull_off", "pull_off_force"))
    ok = np.isfinite(F) & (F > 0) & np.isfinite(dg) & np.isfinite(R) & np.isfinite(E) & np.isfinite(k)
    dg, R, E, k, F = dg[ok], R[ok], E[ok], k[ok], F[ok]
    if len(F) < 3:
        raise InputError("table", f"needs at least 3 rows with a finite pull-off force, got {len(F)}")
    y = np.log(F / (R * dg))
    lnF = np.log(F)
    X = np.column_stack([np.ones_like(y), np.log(E * R / dg), np.log(k)])

    def r2(pred_lnF):
        ss_res = float(np.sum((lnF - pred_lnF) ** 2))
        ss_tot = float(np.sum((lnF - lnF.mean()) ** 2))
        return 1.0 - ss_res / ss_tot if ss_tot > 0 else float("nan")

    def rel(pred_lnF):
        e = np.exp(pred_lnF - lnF) - 1.0
        return float(np.sqrt(np.mean(e**2))), float(np.max(np.abs(e)))

    def solve(cols):
        A = X[:, cols]
        x0 = np.linalg.lstsq(A, y, rcond=None)[0]
        sol = least_squares(lambda c: A @ c - y, x0, method="lm")
        c = sol.x
        resid = A @ c - y
        dof = max(len(y) - len(cols), 1)
        cov = np.linalg.pinv(A.T @ A) * float(resid @ resid) / dof
        return c, np.sqrt(np.diag(cov)), A @ c + np.log(R * dg)

    c, se, pred = solve([0, 1, 2])
    c0, se0, pred0 = solve([0, 2])
    rms, mx = rel(pred)
    rms0, mx0 = rel(pred0)
    a, beta, b = math.exp(c[0]), float(c[1]), float(c[2])
    return PullOffFit(
        a=a, b=b, beta=beta, r2=r2(pred), rms_rel=rms, max_rel=mx,
        a0=math.exp(c0[0]), b0=float(c0[1]), r2_beta0=r2(pred0), rms_rel_beta0=rms0, max_rel_beta0=mx0,
        n=int(len(F)),
        stderr={"ln_a": float(se[0]), "beta": float(se[1]), "b": float(se[2]),
                "ln_a0": float(se0[0]), "b0": float(se0[1])},
    )
