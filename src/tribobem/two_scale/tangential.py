"""The tangential law of a rough interface and the macro partial-slip solve with it.

Micro: each periodic window, pressed at a tabulated nominal pressure p (its normal state from
:func:`tribobem.two_scale.micro.window_table`'s ladder), is loaded by a mean shear tau = f mu p
for a ladder of fractions f < 1 (:func:`tribobem.solvers.tangential.solve_tangential`, Coulomb
friction node by node, warm-started along f).  Its rigid tangential displacement (body 2 against
body 1) is the interface's slip s(tau; p): the periodic window carries no q = 0 displacement, so
s is the asperities' own partial slip and micro-scale elasticity, and the burl's elasticity is
the macro operator's.  The window slides as a whole at f = 1 (tau = mu p).

Macro: with the nominal pressure p(x) of the macro normal solve fixed (the macro normal-
tangential coupling of dissimilar bodies is left out; the windows keep theirs), the shear
tau(x) of the loaded cells and the rigid tangential displacement delta solve

    (G_xx tau)(x) + s(tau(x); p(x)) = delta,   sum(tau) dA = F_x,   0 <= tau < mu p,

by the projected Newton iteration of the normal macro solve (:mod:`tribobem.two_scale.macro`):
s increases with tau, so the problem is the stationarity of a convex functional.  The static
friction of the burl is sum(mu p) dA = mu F (every cell at its window's gross slip); a
tangential force above it has no solution.

Unloading and reloading (:func:`interface_loop`) follow Masing's rule in every macro cell: from
a turning point (tau_r, s_r) a branch going in the direction sgn (+1 up, -1 down) is

    s(tau) = s_r + sgn 2 s0(tau'),   tau' = sgn (tau - tau_r) / 2 >= 0,

with s0 the virgin slip law at the cell's pressure (the window's own branch, exact for an
uncoupled elastic contact at constant normal load; :func:`window_loop_check` measures it against
the coupled window).  Substituted into the macro equation, tau' solves the virgin problem at the
force F' = sgn (F - F_r)/2 and displacement delta' = sgn (delta - delta_r)/2, with each cell's
shear bounded by (f_max mu p - sgn tau_r)/2 (the cell slides backwards at -f_max mu p), where
s_r = delta_r - (G tau_r) is the cell's whole slip at the turn, gross sliding included.  So
every branch is a :func:`solve_interface_tangential` solve with per-cell limits.  The rule keeps
no older turning points (Masing without Madelung's memory): on the symmetric cycles of the
hysteresis kind a branch never passes the turn before it.
"""

from __future__ import annotations

import time
import warnings
from dataclasses import dataclass, field

import numpy as np

from ..elasticity.operators import periodic_operator
from ..errors import ConvergenceWarning, InputError
from ..solvers.tangential import GrossSlipError, solve_tangential
from .macro import _cg, _self_compliance
from .micro import compute_tables, table_key, window_states

__all__ = ["SLIP_FRACTIONS", "TangentialInterfaceLaw", "window_slip_table", "interface_slip_law",
           "InterfaceSlipResult", "solve_interface_tangential", "interface_loop", "window_loop_check"]

#: The shear fractions f = tau / (mu p) of the micro slip tables (the window slides at f = 1).
SLIP_FRACTIONS = (0.05, 0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 0.95, 0.98, 0.995)


def window_slip_table(grid, pair, gap, pressures, friction_coefficient: float, *, fractions=SLIP_FRACTIONS,
                      interaction=None, capillary=None, tol: float = 1e-8, max_iterations: int = 10000) -> dict:
    """One window's slip table: its rigid tangential displacement at tau = f mu p.

    Parameters
    ----------
    grid : Grid
        Periodic window grid (m).
    pair : ContactPair
        The materials.
    gap : ndarray
        The window's initial gap (m, minimum 0).
    pressures : sequence of float
        Nominal pressures (Pa), increasing.
    friction_coefficient : float
        mu (> 0).
    fractions : sequence of float
        f in (0, 1), increasing.
    interaction : Interaction, optional
        Stress law outside contact (normal solves).
    capillary : dict, optional
        The window's menisci at one RH (``film1``, ``film2``, ``options``: see
        :func:`tribobem.two_scale.micro.window_table`); the shear acts on the contact, whose
        capacity is mu times its repulsive force (menisci included).
    tol, max_iterations : float, int
        Normal and tangential solver settings.

    Returns
    -------
    dict
        ``slips`` (m, shape (pressures, fractions)), ``stick_ratios`` (same shape), ``converged``,
        ``capacities`` (Pa: mu times the window's mean repulsive pressure, per pressure).
    """
    op = periodic_operator(grid, pair, components=("x", "y", "z"))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ConvergenceWarning)
        states, _ = window_states(op, gap, pressures, interaction=interaction, capillary=capillary, tol=tol,
                                  max_iterations=max_iterations)
        slips = np.full((len(pressures), len(fractions)), np.nan)
        stick = np.full_like(slips, np.nan)
        ok = np.ones_like(slips, dtype=bool)
        caps = []
        for i, state in enumerate(states):
            shear = None
            capacity = friction_coefficient * float(np.sum(np.clip(state.pressure, 0, None))) * grid.dx * grid.dy
            caps.append(capacity / (grid.lx * grid.ly))
            for j, f in enumerate(fractions):
                try:
                    t = solve_tangential(op, state.pressure, state.contact, friction_coefficient=friction_coefficient,
                                         force=(f * capacity, 0.0), initial_shear=shear, tol=tol,
                                         max_iterations=max_iterations)
                except GrossSlipError:
                    ok[i, j:] = False
                    break
                slips[i, j] = t.displacement_x
                stick[i, j] = t.stick_ratio
                ok[i, j] = bool(t.converged)
                shear = t.shear
    return {"slips": slips.tolist(), "stick_ratios": stick.tolist(), "converged": ok.tolist(), "capacities": caps}


@dataclass
class TangentialInterfaceLaw:
    """Interface slip s(tau; p) (m) against mean shear tau and nominal pressure p.

    Attributes
    ----------
    pressures : ndarray, shape (m,)
        Nominal pressures (Pa), increasing.
    fractions : ndarray, shape (k,)
        Shear fractions f = tau / (mu p), increasing in (0, 1).
    slips : ndarray, shape (m, k)
        Mean over the realisations of the windows' tangential displacement (m).
    stick_ratios : ndarray, shape (m, k)
        Mean stick fraction of the windows' real contact area.
    capacities, capacity_pressures : ndarray, optional
        With menisci: the windows' sliding shear mu p_rep (Pa) at these nominal pressures (Pa);
        the fractions are of it.  None: dry, mu p.
    friction_coefficient : float
        mu.
    slip_spread : ndarray, shape (m, k)
        Standard deviation of the slip between realisations (m).
    converged : bool
    realisations : int
    """

    pressures: np.ndarray
    fractions: np.ndarray
    slips: np.ndarray
    stick_ratios: np.ndarray
    friction_coefficient: float
    slip_spread: np.ndarray
    converged: bool = True
    realisations: int = 1
    info: dict = field(default_factory=dict)
    capacities: np.ndarray | None = None
    capacity_pressures: np.ndarray | None = None

    def __post_init__(self):
        self.pressures = np.asarray(self.pressures, float)
        self.fractions = np.asarray(self.fractions, float)
        if self.capacities is not None:
            self.capacities = np.asarray(self.capacities, float)
            self.capacity_pressures = np.asarray(self.pressures if self.capacity_pressures is None
                                                 else self.capacity_pressures, float)
        self.slips = np.asarray(self.slips, float)
        if not np.all(np.isfinite(self.slips)):
            raise ValueError("the slip table has missing entries (a window slid before tau = mu p)")
        if not np.all(np.diff(self.slips, axis=1) > 0):
            raise ValueError("the slip must increase with the shear at every pressure")
        # slip per unit fraction, s(f)/f, is smooth in f and in ln p; tabulated with f = 0 added
        self._lnp = np.log(self.pressures)
        self._f = np.concatenate([[0.0], self.fractions])
        self._s = np.concatenate([np.zeros((self.pressures.size, 1)), self.slips], axis=1)
        self._st = np.concatenate([np.ones((self.pressures.size, 1)), np.asarray(self.stick_ratios, float)], axis=1)

    @property
    def max_fraction(self) -> float:
        """The largest tabulated fraction (the macro shear stays below it times mu p)."""
        return float(self.fractions[-1])

    def _row(self, p):
        """Interpolation weights in ln p (clamped to the table): rows i, i+1 and weight w."""
        x = np.clip(np.log(np.maximum(p, self.pressures[0])), self._lnp[0], self._lnp[-1])
        i = np.clip(np.searchsorted(self._lnp, x, side="right") - 1, 0, self._lnp.size - 2)
        w = (x - self._lnp[i]) / (self._lnp[i + 1] - self._lnp[i])
        return i, w

    def capacity(self, p):
        """The windows' sliding shear at nominal pressures ``p`` (Pa): mu p, or with menisci mu
        times the repulsive pressure (``capacities`` at ``capacity_pressures``, their ratio to p
        linear in ln p and held beyond the table)."""
        p = np.asarray(p, float)
        if self.capacities is None:
            return self.friction_coefficient * p
        ratio = np.interp(np.log(np.maximum(p, 1e-300)), np.log(self.capacity_pressures),
                          self.capacities / self.capacity_pressures)
        return ratio * p

    def _cell(self, tau, p):
        """Bilinear interpolation indices of (f = tau/capacity, ln p): rows i, i+1 (weight w), columns
        j, j+1 (weight u), the column width df and the capacity (mu p dry)."""
        i, w = self._row(p)
        cap = self.capacity(p)
        f = np.clip(tau / np.maximum(cap, 1e-300), 0.0, self._f[-1])
        j = np.clip(np.searchsorted(self._f, f, side="right") - 1, 0, self._f.size - 2)
        df = self._f[j + 1] - self._f[j]
        return i, w, j, (f - self._f[j]) / df, df, cap

    @staticmethod
    def _bilinear(table, i, w, j, u):
        lo = table[i, j] * (1 - u) + table[i, j + 1] * u
        hi = table[i + 1, j] * (1 - u) + table[i + 1, j + 1] * u
        return lo * (1 - w) + hi * w

    def slip(self, tau, p):
        """s(tau; p) (m) and ds/dtau (m/Pa) at shears ``tau`` (Pa) and pressures ``p`` (Pa), arrays of
        one shape; piecewise linear in f = tau/(mu p) and in ln p."""
        tau, p = np.asarray(tau, float), np.asarray(p, float)
        i, w, j, u, df, cap = self._cell(tau, p)
        s = self._bilinear(self._s, i, w, j, u)
        slope = ((self._s[i, j + 1] - self._s[i, j]) * (1 - w) + (self._s[i + 1, j + 1] - self._s[i + 1, j]) * w) / df
        return s, slope / np.maximum(cap, 1e-300)

    def stick_ratio(self, tau, p):
        """The windows' stick fraction at shears ``tau`` and pressures ``p`` (1 at tau = 0), interpolated
        like :meth:`slip`."""
        tau, p = np.asarray(tau, float), np.asarray(p, float)
        i, w, j, u, _, _ = self._cell(tau, p)
        return self._bilinear(self._st, i, w, j, u)

    def as_dict(self) -> dict:
        """The table as plain lists (SI)."""
        return {"pressures": self.pressures.tolist(), "fractions": self.fractions.tolist(),
                "slips": self.slips.tolist(), "stick_ratios": np.asarray(self.stick_ratios).tolist(),
                "slip_spread": np.asarray(self.slip_spread).tolist(), "friction_coefficient": self.friction_coefficient,
                "converged": bool(self.converged), "realisations": int(self.realisations), "info": dict(self.info),
                "capacities": None if self.capacities is None else self.capacities.tolist(),
                "capacity_pressures": None if self.capacities is None else self.capacity_pressures.tolist()}

    @classmethod
    def from_realisations(cls, pressures, fractions, friction_coefficient, tables, info=None):
        """Average per-realisation tables of :func:`window_slip_table`."""
        slips = np.array([t["slips"] for t in tables], float)
        stick = np.array([t["stick_ratios"] for t in tables], float)
        # with menisci the windows slide at mu times their repulsive pressure (dry: mu p, the default)
        caps = (np.mean([t["capacities"] for t in tables], axis=0)
                if (info or {}).get("capillary") and all(t.get("capacities") for t in tables) else None)
        return cls(pressures=np.asarray(pressures, float), fractions=np.asarray(fractions, float),
                   slips=slips.mean(axis=0), stick_ratios=stick.mean(axis=0), friction_coefficient=friction_coefficient,
                   slip_spread=slips.std(axis=0), converged=bool(all(np.all(t["converged"]) for t in tables)),
                   realisations=len(tables), info=dict(info or {}), capacities=caps)


def interface_slip_law(windows, pressures, friction_coefficient: float, *, fractions=SLIP_FRACTIONS,
                       tol: float = 1e-8, max_iterations: int = 10000, scheduler: str = "synchronous",
                       cache: bool = True, cache_dir=None) -> TangentialInterfaceLaw:
    """The tangential interface law of ``windows`` (cached, through Dask like the normal tables).

    Parameters
    ----------
    windows : MicroWindows
        The windows (one gap per realisation).
    pressures : sequence of float
        Nominal pressures (Pa) of the slip table, increasing.
    friction_coefficient : float
        mu (> 0).
    fractions : sequence of float
        Shear fractions f = tau / (mu p) in (0, 1).
    tol, max_iterations, scheduler, cache, cache_dir
        As :func:`tribobem.two_scale.micro.interface_law`.

    Returns
    -------
    TangentialInterfaceLaw
    """
    pressures = np.asarray(pressures, float)
    tasks = [(window_slip_table, {"grid": windows.grid, "pair": windows.pair, "gap": g, "pressures": pressures,
                                  "friction_coefficient": float(friction_coefficient), "fractions": tuple(fractions),
                                  "interaction": windows.interaction, "capillary": windows.capillary_of(k), "tol": tol,
                                  "max_iterations": max_iterations},
              table_key(windows.grid, windows.pair, g, windows.interaction, pressures, tol, max_iterations,
                        kind="slip", friction_coefficient=float(friction_coefficient), fractions=list(fractions),
                        **windows.capillary_key(k)))
             for k, g in enumerate(windows.gaps)]
    tables = compute_tables(tasks, cache, cache_dir, scheduler)
    info = {"capillary": windows.capillary is not None, "cached": int(sum(t.get("cached", False) for t in tables)),
            "not_converged": int(sum(int(np.size(t["converged"]) - np.sum(t["converged"])) for t in tables)),
            "solves": int(sum(np.size(t["converged"]) for t in tables))}
    return TangentialInterfaceLaw.from_realisations(pressures, fractions, float(friction_coefficient), tables, info)


@dataclass
class InterfaceSlipResult:
    """One macro partial-slip state.

    Attributes
    ----------
    shear : ndarray
        Nominal shear tau of each macro cell (Pa), along x.
    slip : ndarray
        Interface slip s(tau; p) of each cell (m).
    displacement : float
        Rigid tangential displacement delta of body 2 relative to body 1 (m).
    force : float
        Tangential force (N).
    stick_ratio : float
        Stick fraction of the real contact area (the windows' stick fraction, weighted by the
        cells' real contact area).
    newton_iterations, cg_iterations : int
    residual : float
    converged : bool
    time : float
    cell_stick : ndarray, optional
        Each cell's window stick fraction (1 at zero shear; on a Masing branch the branch's own,
        that of the virgin state at the branch's transformed shear); 0 outside the loaded cells.
    """

    shear: np.ndarray
    slip: np.ndarray
    displacement: float
    force: float
    stick_ratio: float
    newton_iterations: int
    cg_iterations: int
    residual: float
    converged: bool
    time: float = 0.0
    cell_stick: np.ndarray | None = None


def _tangential_block(operator):
    """The x-x block of a coupled operator as a compliance (positive displacement along the shear)."""
    op = operator.block("x", "x")
    c0 = _self_compliance(op)
    return op, (1.0 if c0 > 0 else -1.0), abs(c0)


def solve_interface_tangential(operator, pressure, law: TangentialInterfaceLaw, force: float, *, real_fraction=None,
                               initial_shear=None, limit=None, tol: float = 1e-9, max_newton: int = 100,
                               cg_tol: float = 1e-10, max_cg: int = 2000) -> InterfaceSlipResult:
    """The macro partial-slip state at a tangential force (module docstring).

    Parameters
    ----------
    operator : ConvolutionOperator
        The macro operator with components ("x", "y", "z") (its x-x block is used).
    pressure : ndarray
        Nominal pressure of the macro cells (Pa), from the macro normal solve.
    law : TangentialInterfaceLaw
        The interface slip law.
    force : float
        Tangential force F_x (N), 0 <= F_x < mu sum(p) dA (times the table's largest fraction).
    real_fraction : ndarray, optional
        The cells' real contact fraction (weights of the stick ratio); default uniform.
    initial_shear : ndarray, optional
        A start (the previous step of a ramp).
    limit : ndarray, optional
        Each cell's largest shear (Pa), where its window slides; default the table's largest
        fraction times mu p (a Masing branch passes its own, :func:`interface_loop`).
    tol : float
        Convergence: max |G tau + s - delta| over the loaded cells, relative to max |G tau| + max s.

    Returns
    -------
    InterfaceSlipResult

    Raises
    ------
    InputError
        ``force``: negative, or at or beyond the static friction of the table's largest fraction.
    """
    t0 = time.perf_counter()
    op, sign, c0 = _tangential_block(operator)
    p = np.asarray(pressure, float)
    dA = op.grid.dx * op.grid.dy
    loaded = p > 0
    cap = np.where(loaded, law.capacity(np.where(loaded, p, 1.0)), 0.0)
    top = law.max_fraction * cap
    if limit is not None:
        top = np.where(loaded, np.clip(np.asarray(limit, float), 0.0, top), 0.0)
        loaded = loaded & (top > 0)
    if not 0 <= force < float(top.sum()) * dA:
        raise InputError("force", f"must lie in [0, {float(top.sum()) * dA:.6g}) N (the table's largest fraction "
                         f"{law.max_fraction:g} of the static friction mu F = {float(cap.sum()) * dA:.6g} N), got {force!r}")
    if force == 0:
        return InterfaceSlipResult(np.zeros_like(p), np.zeros_like(p), 0.0, 0.0, 1.0, 0, 0, 0.0, True,
                                   time.perf_counter() - t0, cell_stick=np.where(loaded, 1.0, 0.0))

    def G(x):
        return sign * op.apply(x)

    tau = (np.where(loaded, cap, 0.0) * (force / (float(cap.sum()) * dA)) if initial_shear is None
           else np.clip(np.asarray(initial_shear, float), 0.0, top))
    # cells whose window slides (tau at the table's top): their shear is fixed and their slip is
    # whatever delta - G tau leaves, at least the table's last slip (like a contact constraint)
    sliding = loaded & (tau >= top * (1 - 1e-12))
    delta, total_cg, converged, residual = 0.0, 0, False, np.inf
    for it in range(1, max_newton + 1):
        u = G(tau)
        s, D = law.slip(np.where(loaded, tau, 0.0), np.where(loaded, p, 1.0))
        s, D = np.where(loaded, s, 0.0), np.where(loaded, D, 0.0)
        free = loaded & ~sliding
        if it > 1:
            scale = float(np.max(np.abs(u[loaded]))) + float(np.max(np.abs(s[loaded]))) + 1e-300
            residual = float(np.max(np.abs(u[free] + s[free] - delta))) / scale if free.any() else 0.0
            # a sliding cell is consistent when the slip it is left with reaches the table's top
            released = sliding & (delta - u < s - tol * scale)
            if residual <= tol and not released.any():
                converged = True
                break
            if released.any():
                sliding = sliding & ~released
                free = loaded & ~sliding
        mask = free.astype(float)
        fixed = np.where(sliding, top, 0.0)
        b = np.where(free, D * tau - s - G(fixed), 0.0)

        def apply(x, D=D, mask=mask):
            return mask * G(mask * x) + D * mask * x + (1.0 - mask) * x

        diag = np.where(free, c0 + D, 1.0)
        x, kx = _cg(apply, b, diag, np.where(free, tau, 0.0), cg_tol, max_cg)
        y, ky = _cg(apply, mask, diag, np.zeros_like(tau), cg_tol, max_cg)
        total_cg += kx + ky
        delta = (force / dA - float(fixed.sum()) - float(x[free].sum())) / float(y[free].sum())
        tau_free = np.where(free, x + delta * y, 0.0)
        # cells pushed past the top start sliding; the force is restored on the others
        over = free & (tau_free >= top)
        tau_new = np.where(sliding | over, top, np.clip(tau_free, 0.0, None))
        sliding = sliding | over
        rest = loaded & ~sliding
        if rest.any() and tau_new.sum() * dA != force:
            corr = (force / dA - float(tau_new.sum())) / float(y[rest].sum())
            tau_new = np.where(rest, np.clip(tau_new + corr * y, 0.0, top), tau_new)
            delta += corr
        tau = tau_new
    s, _ = law.slip(np.where(loaded, tau, 0.0), np.where(loaded, p, 1.0))
    s = np.where(loaded, s, 0.0)
    weight = np.where(loaded, 1.0 if real_fraction is None else np.asarray(real_fraction, float), 0.0)
    stick = law.stick_ratio(np.where(loaded, tau, 0.0), np.where(loaded, p, 1.0))
    ratio = float((stick * weight).sum() / max(weight.sum(), 1e-300))
    # delta of the free cells (where G tau + s = delta holds); all sliding: their mean
    free = loaded & ~sliding
    disp = float(delta) if free.any() else float(np.mean((G(tau) + s)[loaded]))
    return InterfaceSlipResult(shear=tau, slip=s, displacement=disp, force=float(tau.sum() * dA), stick_ratio=ratio,
                               newton_iterations=it, cg_iterations=total_cg, residual=residual, converged=converged,
                               time=time.perf_counter() - t0, cell_stick=np.where(loaded, stick, 0.0))


@dataclass
class InterfaceLoop:
    """The macro states along a cyclic tangential force path (:func:`interface_loop`).

    Attributes
    ----------
    states : list of InterfaceSlipResult
        One per path value, in physical variables (shear, whole slip delta - G tau, delta).
    forces, displacements : ndarray
        F_x (N) and delta (m) per state.
    dissipation : list of float
        Per full cycle: the interface's frictional work, sum over the cells of the closed
        integral of tau ds (J), trapezoid rule over the steps (the loop area by energy balance).
    """

    states: list
    forces: np.ndarray
    displacements: np.ndarray
    dissipation: list


def interface_loop(operator, pressure, law: TangentialInterfaceLaw, values, turning, cycles, *, real_fraction=None,
                   tol: float = 1e-9, progress=None) -> InterfaceLoop:
    """The macro friction loop along a force path, Masing's rule in every cell (module docstring).

    Parameters
    ----------
    operator : ConvolutionOperator
        The macro operator with components ("x", "y", "z").
    pressure : ndarray
        Nominal pressure of the macro cells (Pa), held along the path.
    law : TangentialInterfaceLaw
        The virgin slip law of the windows.
    values, turning, cycles : array_like
        The path's tangential forces F_x (N), its turning flags and cycle numbers
        (:func:`tribobem.solvers.hysteresis.cycle_path`).
    real_fraction : ndarray, optional
        The cells' real contact fraction (weights of the stick ratio).
    tol : float
        Each solve's tolerance.
    progress : callable, optional
        ``progress(done, total)``.

    Returns
    -------
    InterfaceLoop

    Raises
    ------
    InputError
        ``force``: a value at or beyond the table's largest fraction of mu F.
    """
    op, sign, _ = _tangential_block(operator)
    p = np.asarray(pressure, float)
    loaded = p > 0
    dA = op.grid.dx * op.grid.dy
    top = law.max_fraction * np.where(loaded, law.capacity(np.where(loaded, p, 1.0)), 0.0)
    values = np.asarray(values, float)
    # the turn a branch starts from: force, shear, displacement, direction, factor (1: virgin)
    F_r, tau_r, d_r, sgn, c = 0.0, np.zeros_like(p), 0.0, 1.0, 1.0
    states, prev = [], None
    for k, F in enumerate(values):
        Fp = sgn * (F - F_r) / c
        r = solve_interface_tangential(operator, p, law, max(Fp, 0.0), real_fraction=real_fraction,
                                       initial_shear=prev, limit=(top - sgn * tau_r) / c, tol=tol)
        prev = r.shear if Fp > 0 else None
        tau = tau_r + sgn * c * r.shear
        delta = d_r + sgn * c * r.displacement
        slip = np.where(loaded, delta - sign * op.apply(tau), 0.0)
        states.append(InterfaceSlipResult(shear=tau, slip=slip, displacement=float(delta), force=float(tau.sum() * dA),
                                          stick_ratio=r.stick_ratio, newton_iterations=r.newton_iterations,
                                          cg_iterations=r.cg_iterations, residual=r.residual, converged=r.converged,
                                          time=r.time, cell_stick=r.cell_stick))
        if turning[k]:
            F_r, tau_r, d_r, sgn, c, prev = float(F), tau, float(delta), -sgn, 2.0, None
        if progress is not None:
            progress(k + 1, len(values))
    cyc = np.asarray(cycles, int)
    dissipation = []
    for cycle in range(1, int(cyc.max()) + 1 if cyc.size else 1):
        idx = np.flatnonzero(cyc == cycle)
        if idx.size == 0:
            continue
        seq = [int(idx[0]) - 1] + idx.tolist()  # from the end of the cycle before
        w = 0.0
        for a, b in zip(seq[:-1], seq[1:]):
            sa, sb = states[a], states[b]
            w += float(np.sum(0.5 * (sa.shear + sb.shear) * (sb.slip - sa.slip))) * dA
        dissipation.append(abs(w))
    return InterfaceLoop(states=states, forces=np.array([s.force for s in states]),
                         displacements=np.array([s.displacement for s in states]), dissipation=dissipation)


def window_loop_check(grid, pair, gap, pressure: float, friction_coefficient: float, *, amplitude: float = 0.8,
                      steps: int = 24, interaction=None, tol: float = 1e-8) -> dict:
    """How well Masing's rule holds for one window: its own coupled friction loop against the
    loop Masing's rule builds from its virgin branch.

    The window (periodic, the materials' normal-tangential coupling included) is pressed at the
    nominal ``pressure`` and taken round 0 -> +F* -> -F* -> +F* (F* = ``amplitude`` mu F+, one
    cycle) by the hysteresis solver (:func:`tribobem.solvers.hysteresis.hysteresis_loop`).  Masing's
    loop from the same run's virgin branch s0: delta = delta* - 2 s0((F* - F)/2) going down,
    -delta* + 2 s0((F + F*)/2) going up.

    Returns
    -------
    dict
        ``max_deviation`` (max |delta - delta_Masing| over both branches, relative to the loop's
        width 2 delta*), ``energy`` (J, the window's loop), ``masing_energy`` (J), ``energy_ratio``,
        ``loop`` (the window's F and delta, and Masing's delta), ``converged``.
    """
    from ..solvers.hysteresis import hysteresis_loop, loop_energies

    op = periodic_operator(grid, pair, components=("x", "y", "z"))
    force = float(pressure) * grid.lx * grid.ly
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ConvergenceWarning)
        run = hysteresis_loop(op, gap, normal_force=force, friction_coefficient=friction_coefficient,
                              amplitude=amplitude, cycles=1, steps=steps, interaction=interaction, tol=tol)
    F = np.array([run.start.tangential.force_x] + [s.tangential.force_x for s in run.steps])
    d = np.array([run.start.tangential.displacement_x] + [s.tangential.displacement_x for s in run.steps])
    br = ["start"] + list(run.path.branch)
    virgin = [i for i, b in enumerate(br) if b in ("start", "loading")]
    Fv, dv = F[virgin], d[virgin] - d[0]

    def s0(x):
        return np.interp(x, Fv, dv)

    k_top = virgin[-1]
    F_top, d_top = F[k_top], d[k_top]
    pred = d.copy()
    down = [i for i, b in enumerate(br) if b == "unloading"]
    k_bot = down[-1]
    pred[down] = d_top - 2 * s0((F_top - F[down]) / 2)
    up = [i for i, b in enumerate(br) if b == "reloading"]
    d_bot_pred = pred[k_bot]
    pred[up] = d_bot_pred + 2 * s0((F[up] - F[k_bot]) / 2)
    cyc = np.array([0] + list(run.path.cycle))
    width = float(d.max() - d.min())
    e = loop_energies(F, d, cyc)[0]
    em = loop_energies(F, pred, cyc)[0]
    idx = down + up
    return {"max_deviation": float(np.max(np.abs(d[idx] - pred[idx])) / width), "energy": float(e),
            "masing_energy": float(em), "energy_ratio": float(e / em) if em > 0 else float("nan"),
            "loop": {"force": F.tolist(), "displacement": d.tolist(), "masing": pred.tolist(), "branch": br},
            "converged": bool(all(s.converged for s in run.steps))}
