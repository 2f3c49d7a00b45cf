"""Adsorbed water films on a rough surface: uniform, thin-film levelling and equilibrium.

A body whose undeformed topography is ``h_s(x, y)`` (m, heights positive outward from the
body) carries an adsorbed water film of local thickness ``e(x, y) >= 0``; its free surface is
``h_w = h_s + e``. Paper B (Sec. 2.2.1, Eqs. 6-8) and Appendix B level the film with the
thin-film (lubrication) equation::

    dh_w/dt = -(gamma / (3 eta)) div[(h_w - h_s)^3 grad(lap h_w)]          (Paper B Eq. 8, B.1)
            =  div[ M(e) grad P ],   M(e) = e^3 / (3 eta),   P = -gamma lap(h_w)

starting from the uniform film of the isotherm thickness (Eq. 6), volume conserved (Eq. 7).
The thesis integrates it with fixed-step RK4 (Appendix B) or "adaptive RK" (Paper B), gives no
end time and no stopping rule, and without a disjoining pressure the film on the peaks thins
without limit: the end state depends on when one stops. Hence three modes:

``"uniform"``
    the isotherm thickness everywhere (Paper B Fig. 18's comparison case).
``"thin_film"``
    Eq. 8 integrated in time (stiff Rosenbrock W-method, adaptive; see :func:`film_thickness`),
    optionally with the disjoining pressure in the liquid pressure,
    ``P = -gamma lap(h_w) - Pi(e)`` (``disjoining=True``): its steady state is then the closed
    equilibrium below. Without it (the thesis' form) the film on the peaks drains.
``"equilibrium"`` (default; the thesis' recommendation 2)
    the steady state directly: the liquid pressure under the free surface equals the Kelvin
    pressure,

    ``-gamma lap(h_w) - Pi(e) = (R_g T / V) ln RH``,   ``e = h_w - h_s >= 0``,

    with ``Pi(e) = -(R_g T / V) ln RH_iso(e)`` the disjoining pressure implied by the
    isotherm (:mod:`.isotherms`). ``system="open"``: RH fixes the chemical potential;
    ``system="closed"``: the mean thickness is fixed (to the isotherm thickness at RH, or
    ``mean_thickness``) and the right side is a Lagrange multiplier (the thesis' volume
    conservation, Eq. 7). Films come out thinner on peaks and thicker in valleys.

Signs. ``Pi > 0`` and ``dPi/de < 0``; ``-gamma lap(h_w) > 0`` on a peak (convex free
surface). The film equation is the stationarity condition of the convex energy
``int [gamma |grad h_w|^2 / 2 + W(e) - P_K e] dA`` with ``W' = -Pi`` (``W'' = -Pi' > 0``), so the
equilibrium film is unique and its Jacobian ``gamma k^2 - Pi'(e)`` is symmetric positive
definite. Linearised about a flat film ``e0`` on ``h_s = a cos(k x)``:
``e = e0 + e1 cos(k x)`` with ``e1 = -a gamma k^2 / (gamma k^2 + |Pi'(e0)|)`` (open and closed
systems alike, to first order in ``a``): thinner on the peak, and the film follows the surface
(``e1 -> 0``) for wavelengths much longer than the healing length
``xi = sqrt(gamma / |Pi'(e0)|)`` (about 0.6 nm on SiO2 at 30 % RH), while it levels fully
(``e1 -> -a``) for much shorter ones. On the 10 um / 256^2 surfaces of Paper B the grid
spacing (39 nm) is far longer than ``xi``: the equilibrium film there is close to uniform.

Boundaries. On a periodic grid the derivatives are pseudo-spectral (real FFTs). On a
free-boundary grid the topography is extended by even reflection (mirror images across the
four edges; a 2nx x 2ny periodic cell) and the result cropped: this is the cosine (Neumann)
expansion, zero slope of ``h_w`` and zero flux through the edges, so the film volume of the
window is conserved and no spurious periodic jump appears where the edges of a non-periodic
topography meet. It costs four times the periodic work.
"""

from __future__ import annotations

import math
import time as _time
import warnings
from dataclasses import dataclass

import numpy as np

from ..elasticity.backends import get_backend
from ..errors import ConvergenceWarning, InputError
from ..grid import Grid
from .isotherms import Isotherm, isotherm_from_spec
from .water import Water, check_rh

__all__ = ["FilmResult", "film_thickness", "levelling_time", "VISCOSITY", "MODES", "SYSTEMS"]

#: Viscosity of water in Pa s (only sets the time scale of the thin-film mode).
VISCOSITY = 1e-3

MODES = ("equilibrium", "thin_film", "uniform")
SYSTEMS = ("open", "closed")

_DEFAULT_WATER = Water()


@dataclass
class FilmResult:
    """The adsorbed water film on one body.

    Attributes
    ----------
    thickness : ndarray
        Local film thickness e >= 0 on each node (m), shape of the grid.
    water_surface : ndarray
        Height of the free water surface h_w = h_s + e (m).
    mean_thickness : float
        Mean of ``thickness`` over the grid (m) (film volume / nominal area).
    mode : str
        ``"equilibrium"``, ``"thin_film"`` or ``"uniform"``.
    system : str
        ``"open"`` (RH fixes the chemical potential) or ``"closed"`` (volume fixed).
    iterations : int
        Newton iterations (equilibrium) or accepted time steps (thin_film); 0 for uniform.
    converged : bool
        Equilibrium: residual below ``tol``. thin_film: the stopping rule was met (steady
        state, the requested ``time``, or without disjoining pressure the end time; see
        :func:`film_thickness`). False also comes with a :class:`ConvergenceWarning`.
    volume_error : float
        ``|mean_thickness - target| / target`` for the modes that fix the volume (closed,
        thin_film, uniform); NaN for the open system, whose volume is free.
    message : str
        What happened, in words (mode, stopping reason, clipping).
    rh : float
        Relative humidity (fraction).
    liquid_pressure : float
        The uniform liquid pressure -gamma lap(h_w) - Pi(e) of the solution (Pa): the Kelvin
        pressure (R_g T / V) ln RH for the open system, the Lagrange multiplier for the
        closed one; for thin_film the area mean of P at the end; for uniform -Pi(e) of the
        flat film. NaN for a dry body.
    residual : float
        Equilibrium: the largest nodal residual, in units of R_g T / V (i.e. of ln RH).
        thin_film: the last relative rate of change ``max|de/dt| tau_slow / mean(e)``.
    time : float
        thin_film: physical time reached (s); 0 otherwise.
    levelling_time : float
        thin_film: the linear relaxation time tau_slow of the longest resolved wavelength
        about the uniform film (s; :func:`levelling_time`); 0 otherwise.
    clipped : int
        thin_film: node updates where the film went negative and was set to 0 (the volume
        is then restored by rescaling). Equilibrium: dry nodes, held at the isotherm's floor
        thickness (about 3e-15 m for the shipped tables) because the Laplace pressure there
        exceeds the floor's disjoining pressure (about 1.9 GPa).
    wall_time : float
        Seconds spent.
    """

    thickness: np.ndarray
    water_surface: np.ndarray
    mean_thickness: float
    mode: str
    system: str
    iterations: int
    converged: bool
    volume_error: float
    message: str
    rh: float = math.nan
    liquid_pressure: float = math.nan
    residual: float = 0.0
    time: float = 0.0
    levelling_time: float = 0.0
    clipped: int = 0
    wall_time: float = 0.0


def levelling_time(wavelength: float, thickness: float, water: Water = _DEFAULT_WATER,
                   viscosity: float = VISCOSITY, disjoining_slope: float = 0.0) -> float:
    """Linear relaxation time of one Fourier mode of a film (s).

    A small perturbation ``cos(k x)`` of a uniform film of thickness ``e0`` under Eq. 8 with
    the pressure ``-gamma lap(h_w) - Pi(e)`` decays at the rate
    ``(e0^3 / (3 eta)) k^2 (gamma k^2 + |Pi'(e0)|)``; this returns its inverse.

    Parameters
    ----------
    wavelength : float
        2 pi / k in m.
    thickness : float
        Uniform film thickness e0 in m.
    water : Water
        Supplies gamma.
    viscosity : float
        eta in Pa s.
    disjoining_slope : float
        dPi/de at e0 in Pa/m (0 for the thesis' Eq. 8 without disjoining pressure).

    Returns
    -------
    float
        The relaxation time 1 / rate (s).
    """
    k = 2.0 * math.pi / wavelength
    rate = thickness**3 / (3.0 * viscosity) * k * k * (water.surface_tension * k * k + abs(disjoining_slope))
    return 1.0 / rate


# ----------------------------------------------------------------------------- spectral helper
class _Spectral:
    """Pseudo-spectral derivatives on the (possibly mirror-extended) grid with real FFTs."""

    def __init__(self, grid: Grid, periodic: bool):
        self.backend = get_backend("numpy")
        self.periodic = periodic
        self.n = grid.shape
        nx, ny = grid.shape
        if not periodic:
            nx, ny = 2 * nx, 2 * ny
        self.shape = (nx, ny)
        self.lx = grid.lx * (1 if periodic else 2)
        self.ly = grid.ly * (1 if periodic else 2)
        kx = 2.0 * np.pi * np.fft.fftfreq(nx, d=grid.dx)
        ky = 2.0 * np.pi * np.fft.rfftfreq(ny, d=grid.dy)
        self.k2 = kx[:, None] ** 2 + ky[None, :] ** 2
        # first derivatives: the Nyquist mode has no real derivative, set it to 0 (the
        # Laplacian keeps k^2 there)
        kxd, kyd = kx.copy(), ky.copy()
        if nx % 2 == 0:
            kxd[nx // 2] = 0.0
        if ny % 2 == 0:
            kyd[-1] = 0.0
        self.ikx = 1j * kxd[:, None]
        self.iky = 1j * kyd[None, :]
        self.k_min = 2.0 * np.pi / max(self.lx, self.ly)

    def extend(self, a: np.ndarray) -> np.ndarray:
        if self.periodic:
            return np.array(a, dtype=float)
        top = np.concatenate([a, a[:, ::-1]], axis=1)
        return np.concatenate([top, top[::-1, :]], axis=0)

    def crop(self, a: np.ndarray) -> np.ndarray:
        if self.periodic:
            return a
        return np.ascontiguousarray(a[: self.n[0], : self.n[1]])

    def rfft(self, a):
        return self.backend.rfft2(a)

    def irfft(self, a):
        return self.backend.irfft2(a, s=self.shape)


# ----------------------------------------------------------------------------- public entry
def film_thickness(
    surface,
    grid: Grid,
    isotherm,
    rh: float,
    water: Water = _DEFAULT_WATER,
    *,
    mode: str = "equilibrium",
    system: str | None = None,
    periodic: bool | None = None,
    tol: float = 1e-10,
    max_iterations: int | None = None,
    progress=None,
    mean_thickness: float | None = None,
    disjoining: bool = False,
    time: float | None = None,
    duration: float = 100.0,
    steady_tolerance: float = 1e-8,
    step_tolerance: float = 1e-4,
    viscosity: float = VISCOSITY,
    time_progress=None,
) -> FilmResult:
    """The adsorbed water film on a body's undeformed topography (module docstring).

    Parameters
    ----------
    surface : array_like
        Undeformed topography h_s of the body (m), shape ``grid.shape``, heights positive
        outward from the body's bulk (so a peak of the body is a maximum of ``surface``).
    grid : Grid
        The grid (cell sizes dx, dy in m).
    isotherm : Isotherm or spec
        The body's isotherm, or anything :func:`~.isotherms.isotherm_from_spec` accepts
        (``"SiO2"``, ``"Si"``, ``None`` for dry, a table ...). A dry body gets a zero film.
    rh : float
        Relative humidity in (0, 1].
    water : Water
        gamma, T, V.
    mode : {"equilibrium", "thin_film", "uniform"}
        See the module docstring.
    system : {"open", "closed"} or None
        Equilibrium: open (RH fixes the chemical potential; default) or closed (mean thickness
        fixed). thin_film conserves the volume: it is closed (``None`` or ``"closed"``;
        ``"open"`` is refused). Ignored by uniform.
    periodic : bool, optional
        Default ``grid.periodic``. False: mirror extension (module docstring).
    tol : float
        Equilibrium: the largest nodal residual of the film equation, in units of R_g T / V
        (i.e. an error in ln RH), at which Newton stops.
    max_iterations : int, optional
        Newton iterations (default 100) or thin-film time steps (default 50000).
    progress : callable, optional
        ``progress(iteration, value)`` after every Newton iteration (value: the residual) or
        accepted time step (value: the relative rate of change).
    mean_thickness : float, optional
        Closed system / thin_film / uniform: the mean film thickness to keep (m), i.e. the
        adsorbed volume per area V_ads / A of Paper B Eq. 6. Default: the isotherm thickness
        at ``rh``. Refused for the open system.
    disjoining : bool
        thin_film only: add the disjoining pressure to the liquid pressure
        (``P = -gamma lap h_w - Pi(e)``), so that the film relaxes to the closed equilibrium.
        False is the thesis' Eq. 8: films on peaks drain without limit.
    time : float, optional
        thin_film only: integrate to this physical time (s) and stop (converged once reached;
        not converged when ``max_iterations`` steps end first).  Without the disjoining
        pressure there is no steady state (the films drain off the peaks for as long as one
        integrates), so this is the way to say where the result is taken; a scenario must give
        it there (``[humidity] film_time``).
    duration : float
        thin_film without ``time``: the largest time in units of ``tau_slow``, the linear
        relaxation time (:func:`levelling_time`) of the longest resolved wavelength (the
        domain side; twice it on a mirrored free-boundary grid) about the uniform film.
        Default 100: that mode has decayed by e^-100 in linear theory.
    steady_tolerance : float
        thin_film without ``time``: stop (converged) once the relative rate of change
        ``max|de/dt| tau_slow / mean(e)`` (the change still to come, in units of the film
        thickness, if the slowest mode were all that was left) is below this.
    step_tolerance : float
        thin_film: local error per time step (ROS2 against its first stage), relative to the
        mean thickness.
    viscosity : float
        eta in Pa s (thin_film; only sets the time scale).
    time_progress : callable, optional
        thin_film only: ``time_progress(t, t_end, tau_slow)`` after every accepted time step:
        the physical time reached, the end time (``time``, else ``duration x tau_slow``) and the
        relaxation time ``tau_slow`` (all in s), e.g. for a progress bar over the physical time.

    Returns
    -------
    FilmResult

    Raises
    ------
    InputError
        Bad surface, grid, RH, mode, system or tolerances; RH = 1 where the film diverges
        (open equilibrium always: at the Kelvin pressure 0 a flat film is bulk water and the
        open equilibrium has no finite solution; closed / thin_film / uniform when the
        isotherm thickness at RH = 1 is infinite, as for every shipped isotherm).

    Warns
    -----
    ConvergenceWarning
        Newton or the time integration stopped before meeting its stopping rule (the result
        has ``converged=False``).

    Notes
    -----
    *Equilibrium.* Newton's method on ``F(e) = -gamma lap(h_s + e) - Pi(e) - P_K`` scaled by
    R_g T / V (so ``F`` is in units of ln RH). The Jacobian ``J = gamma k^2 + D``,
    ``D = -Pi'(e) > 0``, is SPD; each Newton step is solved by preconditioned CG in the
    symmetric scaling by ``D^-1/2`` with a block preconditioner: on nodes whose disjoining
    stiffness exceeds the largest Laplacian eigenvalue (``D >= gamma k_max^2``: the usual case,
    the film follows the isotherm locally) the scaled operator is close to the identity and
    is left alone (Jacobi); on the others (thick films, fine grids) the FFT-diagonal inverse
    ``(gamma k^2 + d)^-1``, ``d`` the harmonic mean of their ``D``, is applied. It is exact
    for a uniform ``D`` in either regime. A backtracking line search on the scaled residual
    globalises the iteration. On steep peaks the Laplace pressure squeezes the film towards
    0 where ``Pi -> +inf``: the iterates are kept at or above the isotherm's floor thickness
    (:attr:`~.isotherms.Isotherm.floor`, where ``Pi`` is about 1.9 GPa) by projection
    (projected Newton for the bound ``e >= floor``); a node held there by a Laplace pressure
    beyond ``Pi(floor)`` is reported as dry (``clipped``). Closed system: the open problem at
    an unknown chemical potential, found by an outer Newton iteration on the mean thickness
    (``d mean(e) / d P_K = mean(J^-1 1) > 0``), warm-started; the mean is kept to 1e-13.

    *thin_film.* Method of lines on the pseudo-spectral grid, advanced by the two-stage
    Rosenbrock W-method ROS2 (Verwer et al. 1999; L-stable, second order for any
    approximate Jacobian) with the frozen-mobility Jacobian ``-B C`` (``B = -div(M(e_n)
    grad .)``, ``C = dP/de = gamma k^2 [+ |Pi'(e_n)|]``): the stiff fourth-order (and, with
    the disjoining pressure, second-order) operator is implicit with the *local* mobility,
    so thick valleys and thin crests each relax at their own rate. Each stage solves
    ``(I + h B C) x = r`` by CG on ``(C + h C B C) x = C r`` (``B C`` is self-adjoint in the
    ``C`` inner product), preconditioned by ``Ct^-1 (c^-1 + h mean(M) kd^2)^-1 Ct^-1`` with
    ``c = gamma k^2 + d`` (``d`` the harmonic mean of the disjoining stiffness
    ``D = |Pi'(e_n)|``; ``kd^2`` the symbol of the spectral ``-div grad`` built from first
    derivatives, which is 0 along the Nyquist lines where ``k^2`` is not: with ``k^2`` in its
    place CG took ten times the iterations) and ``Ct^-1`` the equilibrium solver's block
    approximation of ``C^-1``: ``1 / D`` on the nodes with ``D >= gamma k_max^2``, the
    FFT-diagonal ``(gamma k^2 + d_soft)^-1`` on the others. The variable ``D`` has to be in
    the outer factors: ``B`` differentiates its variation, so at long steps ``C B C`` is far
    from ``d^2 B`` in the long waves, and the constant-coefficient inverse
    ``(c + h mean(M) kd^2 c^2)^-1`` let CG grow with the step, to its cap of 2000 a stage on
    Paper B's 256^2 surface at RH 0.9 (``stage_solve`` docstring). Without the disjoining
    pressure it is that inverse with ``c = gamma k^2``: the implicit constant-mobility
    biharmonic step of the classical IMEX schemes is the preconditioner
    here, not the time step. A constant-mobility IMEX step was tried
    first and rejected: its stabilising implicit term must use the largest mobility, and a
    mode on a film thinner than that barely relaxes at long steps (amplification ->
    1 - M/M_max), so draining films forced steps of the fastest time scale of the valleys
    and gave a crest thickness that changed with the tolerance. The step is adapted from
    the difference between ROS2 and its first stage (linearly implicit Euler). The update
    has no k = 0 component, so the volume is conserved to round-off. Where a crest drains
    to 0 the non-local pseudo-spectral flux can push it below 0 at any step length: such
    nodes are set to 0 and the volume restored by rescaling (counted in ``clipped``;
    their error is not controlled, they stay dry). Stopping rule: ``time`` if given; else
    steady state (``steady_tolerance``) or ``duration x tau_slow``. With
    ``disjoining=True`` reaching ``duration`` before the steady state is a non-convergence;
    without it there is no steady state (the peaks drain) and the film at
    ``duration x tau_slow`` (or the drained steady state, if reached first) is the
    documented result. At a steady state the residual pseudo-spectral Nyquist mode of P
    cannot relax (its first derivative is 0 on the grid): the steady film differs from the
    equilibrium film by that mode only, which vanishes as the grid is refined (3e-6 of the
    mean thickness at 1 nm cells, 8e-8 at 0.5 nm in the test case).

    Without disjoining pressure on a surface rough enough to dry its crests (rms of the
    order of the film), the time steps stay short (the dry spots' neighbourhood limits
    them): 24^2 cells, rms 1.5 nm, 1 nm film: about 2300 steps to 1e-3 tau_slow. Use
    ``time`` or a short ``duration`` there, or the equilibrium mode. On Paper B's surface
    (rms 5 nm, 1 nm film) this is the common case, not the exception: the water pools in the
    valleys and about 40 % of the nodes dry within milliseconds; at 64^2 the 50000-step
    default ends at 2e-6 tau_slow with some 1500 nodes clipped per step (so ``converged``
    is False), and 256^2 is out of reach. The pseudo-spectral flux is not
    positivity-preserving (integrated without the clipping the film reaches -11 times its
    mean on the dry ridges), so no step-size control can cure it; that would take a local,
    finite-volume flux with a positivity-preserving face mobility (issue 21 item 3).

    Cost (issue 21 item 3, CPU s, ``time.process_time``, shared 2-core machine, load 3):
    Paper B's surface (256^2, 10 um, rms 5 nm, L_ac 0.5 um), SiO2, ``disjoining=True``, to
    the steady state: 3.5 s at RH 0.5 (43 steps, 323 CG iterations) and 14 s at RH 0.9 (103
    steps, 1452 CG iterations). With the constant-coefficient preconditioner the same steps
    took 1358 and 21900 CG iterations (8.8 s and 130 s), and with BLAS inner products in the
    CG as well (:func:`_pcg`) 30-42 s at RH 0.5 and more than 300 s at RH 0.9. RH 0.99 (the
    film varies by 1.3 times its mean; some nodes are soft) is the slow case: 290 s at 256^2
    (410 steps, 42861 CG iterations), 37 s at 128^2. The result agrees with
    ``step_tolerance=1e-6`` to 3e-9 (RH 0.5) and 5e-9 (RH 0.9) of the mean thickness.
    """
    t_start = _time.perf_counter()
    if mode not in MODES:
        raise InputError("film_thickness.mode", f"must be one of {', '.join(MODES)}, got {mode!r}")
    if not isinstance(grid, Grid):
        raise InputError("grid", f"must be a tribobem.grid.Grid, got {type(grid).__name__}")
    try:
        h = np.asarray(surface, dtype=float)
    except (TypeError, ValueError):
        raise InputError("surface", "topography must be an array of heights in m") from None
    if h.shape != grid.shape:
        raise InputError("surface", f"topography shape {h.shape} does not match the grid {grid.shape}")
    if not np.all(np.isfinite(h)):
        raise InputError("surface", "topography contains NaN or inf")
    if not isinstance(water, Water):
        raise InputError("film_thickness.water", f"water must be a Water, got {type(water).__name__}")
    iso = isotherm if isinstance(isotherm, Isotherm) else isotherm_from_spec(isotherm)
    rh = check_rh(rh)
    if not np.ndim(rh) == 0:
        raise InputError("film_thickness.rh", "film_thickness takes one relative humidity at a time")
    if system is None:
        system = "closed" if mode == "thin_film" else "open"
    if system not in SYSTEMS:
        raise InputError("film_thickness.system", f"must be 'open' or 'closed', got {system!r}")
    if mode == "thin_film" and system == "open":
        raise InputError("film_thickness.system", "the thin-film equation conserves the film volume: it is a closed "
                                                 "system (use system='closed' or None)")
    if not (isinstance(tol, (int, float)) and math.isfinite(tol) and tol > 0):
        raise InputError("film_thickness.tol", f"must be a finite number > 0, got {tol!r}")
    if mean_thickness is not None:
        if mode == "equilibrium" and system == "open":
            raise InputError("film_thickness.mean_thickness",
                             "the open system's mean thickness follows from RH; use system='closed'")
        if not (isinstance(mean_thickness, (int, float)) and math.isfinite(mean_thickness) and mean_thickness > 0):
            raise InputError("film_thickness.mean_thickness", f"must be a finite number > 0 m, got {mean_thickness!r}")
    if max_iterations is not None and not (isinstance(max_iterations, (int, np.integer)) and max_iterations >= 1):
        raise InputError("film_thickness.max_iterations", f"must be an integer >= 1, got {max_iterations!r}")
    if periodic is None:
        periodic = grid.periodic
    if mode != "thin_film" and (disjoining or time is not None):
        raise InputError("film_thickness.mode", "disjoining and time apply to mode='thin_film' only")
    if time_progress is not None and not callable(time_progress):
        raise InputError("time_progress", f"must be callable as time_progress(t, t_end, tau_slow), got {time_progress!r}")

    def finish(res: FilmResult) -> FilmResult:
        res.wall_time = _time.perf_counter() - t_start
        if not res.converged:
            warnings.warn(f"film_thickness ({mode}): {res.message}", ConvergenceWarning, stacklevel=3)
        return res

    if iso.dry:
        z = np.zeros(grid.shape)
        return finish(FilmResult(z, h.copy(), 0.0, mode, system, 0, True, 0.0,
                                 f"dry body ({iso.name}): no film", rh=rh))

    if mode == "equilibrium" and system == "open" and rh == 1.0:
        raise InputError(
            "film_thickness.rh",
            "RH = 1 with an open-system equilibrium film: the Kelvin pressure is 0 and a flat film is "
            "bulk water (no finite film); use RH < 1, or a closed system with a finite mean_thickness",
        )
    target = float(mean_thickness) if mean_thickness is not None else float(iso.thickness(rh))
    if not math.isfinite(target):
        raise InputError(
            "film_thickness.rh",
            f"the {iso.name} film thickness at RH = {rh} is infinite (bulk water); use RH < 1 or give mean_thickness",
        )

    if mode == "uniform":
        e = np.full(grid.shape, target)
        p_liq = -iso.disjoining_pressure(target, water) if target > 0 else math.nan
        return finish(FilmResult(e, h + e, target, mode, system, 0, True, 0.0,
                                 f"uniform film of thickness {target:.4g} m", rh=rh,
                                 liquid_pressure=float(p_liq)))
    if target <= 0.0:
        z = np.zeros(grid.shape)
        return finish(FilmResult(z, h.copy(), 0.0, mode, system, 0, True, 0.0, "zero film at this RH", rh=rh))

    sp = _Spectral(grid, bool(periodic))
    hs = sp.extend(h)
    if mode == "equilibrium":
        res = _equilibrium(sp, hs, iso, water, rh, system, target, tol,
                           100 if max_iterations is None else int(max_iterations), progress)
    else:
        res = _thin_film(sp, hs, iso, water, target, disjoining, time, duration, steady_tolerance,
                         step_tolerance, viscosity, 50000 if max_iterations is None else int(max_iterations),
                         progress, time_progress)
    e = sp.crop(res.pop("e"))
    mean = float(e.mean())
    if mode == "equilibrium" and system == "open":
        verr = math.nan
    else:
        verr = abs(mean - target) / target
    return finish(FilmResult(e, h + e, mean, mode, system, rh=rh, volume_error=verr, **res))


# ----------------------------------------------------------------------------- equilibrium
def _dot(a, b) -> float:
    """Sum of ``a * b`` over all nodes, single-threaded (see :func:`_pcg`)."""
    return float(np.einsum("ij,ij->", a, b))


def _pcg(apply, precond, b, rtol, maxiter):
    """Preconditioned conjugate gradients for SPD ``apply``; returns (x, iterations).

    The inner products are ``einsum`` sums, not BLAS ``vdot`` / ``norm``: multithreaded BLAS
    on a grid-sized vector costs microseconds on an idle machine but milliseconds when the
    cores are shared (its threads wait for a time slice), and it was then half of the CPU
    time of the thin-film stage solves at 128^2 (issue 21 item 3).
    """
    x = np.zeros_like(b)
    r = b.copy()
    z = precond(r)
    p = z.copy()
    rz = _dot(r, z)
    bnorm = math.sqrt(_dot(b, b))
    if bnorm == 0.0:
        return x, 0
    for it in range(1, maxiter + 1):
        ap = apply(p)
        alpha = rz / _dot(p, ap)
        x += alpha * p
        r -= alpha * ap
        if math.sqrt(_dot(r, r)) <= rtol * bnorm:
            return x, it
        z = precond(r)
        rz_new = _dot(r, z)
        p = z + (rz_new / rz) * p
        rz = rz_new
    return x, maxiter


def _equilibrium(sp: _Spectral, hs, iso: Isotherm, water: Water, rh, system, target, tol, max_iter, progress):
    c = water.pressure_scale
    kk = (water.surface_tension / c) * sp.k2  # gamma k^2 / (R_g T / V), 1/m
    lap_s = sp.irfft(kk * sp.rfft(hs))  # -gamma lap(h_s) / (R_g T / V)
    floor = iso.floor
    closed = system == "closed"
    state = {"it": 0, "cg": 0}

    def residual(e, mu):
        g, d = iso._log_rh_above_floor(e)
        return lap_s + sp.irfft(kk * sp.rfft(e)) + g - mu, d

    def scaled_solve(d, free, rhs, eta):
        """(I + S K S) y = rhs on the free nodes (y = 0 on the others); returns S y."""
        # Solve J de = r in the symmetric scaling by the disjoining stiffness D = g'(e),
        # S = D^-1/2: D spans decades where films are squeezed (g' ~ 1/e) and unscaled CG
        # loses the small entries to round-off. Block preconditioner (docstring Notes): the
        # nodes whose D exceeds the largest Laplacian eigenvalue are nearly decoupled (scaled
        # operator ~ I): identity there; on the rest, where the Laplacian dominates, the
        # FFT-diagonal inverse (K + dbar)^-1 in the unscaled variables, dbar the harmonic
        # mean of their D (the weakest nodes set the low-k modes).
        sd = free / np.sqrt(d)
        stiff = d >= kk.max()
        soft = free * ~stiff
        dbar = 1.0 / float(np.mean(1.0 / d[soft > 0])) if np.any(soft > 0) else 1.0
        filt = 1.0 / (kk + dbar)
        sqd = soft * np.sqrt(d)

        def apply(y):
            return sd * sp.irfft(kk * sp.rfft(sd * y)) + y

        def precond(r):
            return np.where(stiff, r, sqd * sp.irfft(filt * sp.rfft(sqd * r)))

        y, n = _pcg(apply, precond, sd * rhs, eta, 2000)
        state["cg"] += n
        return sd * y

    def projected(f, e):
        # a node held at the floor whose residual pushes it further down is in equilibrium
        # with the bound (dry node: the Laplace pressure exceeds Pi(floor))
        return np.where((e <= floor) & (f > 0.0), 0.0, f)

    def solve_open(e, mu, budget):
        """Projected Newton for F(e) = 0, e >= floor, at fixed mu; returns (e, f, d, rmax, ok, msg)."""
        f, d = residual(e, mu)
        fp = projected(f, e)
        rmax = float(np.abs(fp).max())
        while rmax > tol:
            if budget <= 0:
                return (e, f, d, rmax, False,
                        f"no convergence in {max_iter} Newton iterations (residual {rmax:.3g} > tol {tol:.3g})")
            budget -= 1
            state["it"] += 1
            free = ((e > floor) | (f <= 0.0)).astype(float)
            eta = min(0.1, max(rmax, 1e-3 * tol))  # inexact Newton forcing term
            step = scaled_solve(d, free, -f, eta)
            # merit: the projected residual in the same scaling as the CG (the CG residual bound
            # makes the step a descent direction for it)
            w = 1.0 / np.sqrt(d)
            fnorm = float(np.linalg.norm(w * fp))
            alpha = 1.0
            for _ in range(60):
                e_try = np.maximum(e + alpha * step, floor)
                f_try, d_try = residual(e_try, mu)
                fp_try = projected(f_try, e_try)
                n_try = float(np.linalg.norm(w * fp_try))
                if n_try <= (1.0 - 1e-4 * alpha) * fnorm or float(np.abs(fp_try).max()) <= tol:
                    break
                alpha *= 0.5
            else:
                return e, f, d, rmax, False, f"line search failed at Newton iteration {state['it']} (residual {rmax:.3g})"
            e, f, d, fp = e_try, f_try, d_try, fp_try
            rmax = float(np.abs(fp).max())
            if progress is not None:
                progress(state["it"], rmax)
        return e, f, d, rmax, True, ""

    e = np.full(sp.shape, target)
    if not closed:
        mu = math.log(rh)  # P_K / (R_g T / V)
        e, f, d, rmax, ok, msg = solve_open(e, mu, max_iter)
        outer = 0
    else:
        # Closed system: the open problem at an unknown chemical potential mu, found by
        # Newton on the mean thickness, d mean(e) / d mu = mean(J^-1 1) > 0 (J is SPD), each
        # open solve warm-started. The outer loop converges quadratically; the mean is then
        # the target to round-off.
        mu = float(iso._log_rh_above_floor(np.asarray(max(target, floor)))[0])
        outer = 0
        ok, msg = True, ""
        while True:
            e, f, d, rmax, ok, msg = solve_open(e, mu, max_iter - state["it"])
            if not ok:
                break
            gap = target - float(e.mean())
            if abs(gap) <= 1e-13 * target:
                break
            if outer >= 50:
                ok, msg = False, f"the mean thickness did not converge in 50 outer iterations ({gap / target:.3g} relative)"
                break
            outer += 1
            free = ((e > floor) | (f <= 0.0)).astype(float)
            b = scaled_solve(d, free, free.copy(), 1e-12)
            dmu = gap / float(b.mean())
            e = np.maximum(e + dmu * b, floor)  # first-order predictor for the next open solve
            mu += dmu
    dry = int(np.count_nonzero((e <= floor) & (f > 0.0)))
    if ok:
        msg = f"equilibrium ({system}) after {state['it']} Newton iterations ({state['cg']} CG"
        msg += f", {outer} chemical-potential updates)" if closed else ")"
        msg += f", residual {rmax:.2e}"
    if dry:
        msg += (f"; {dry} nodes are dry (held at the isotherm floor {floor:.3g} m: the Laplace pressure "
                "there exceeds the disjoining pressure of the floor)")
    return dict(e=e, iterations=state["it"], converged=ok, message=msg, residual=rmax,
                liquid_pressure=mu * c, clipped=dry)


# ----------------------------------------------------------------------------- thin film
def _thin_film(sp: _Spectral, hs, iso: Isotherm, water: Water, target, disjoining, t_final, duration,
               steady_tol, step_tol, viscosity, max_steps, progress, time_progress=None):
    gamma = water.surface_tension
    for name, v in (("duration", duration), ("steady_tolerance", steady_tol), ("step_tolerance", step_tol),
                    ("viscosity", viscosity)):
        if not (isinstance(v, (int, float)) and math.isfinite(v) and v > 0):
            raise InputError(f"film_thickness.{name}", f"must be a finite number > 0, got {v!r}")
    if t_final is not None and not (isinstance(t_final, (int, float)) and math.isfinite(t_final) and t_final > 0):
        raise InputError("film_thickness.time", f"must be a finite time > 0 s, got {t_final!r}")
    hs_hat = sp.rfft(hs)
    k2 = sp.k2
    gk2 = gamma * k2
    ikx, iky = sp.ikx, sp.iky
    kd2 = np.abs(ikx) ** 2 + np.abs(iky) ** 2
    gk2_max = float(gk2.max())
    pscale = water.pressure_scale
    pslope = float(abs(iso.disjoining_pressure_derivative(target, water))) if disjoining else 0.0
    tau_slow = levelling_time(2.0 * np.pi / sp.k_min, target, water, viscosity, pslope)
    t_end = float(t_final) if t_final is not None else duration * tau_slow
    inv3eta = 1.0 / (3.0 * viscosity)
    floor = iso.floor
    cg_total = [0]
    # the stage solves need not be more exact than the local error they are controlled by
    cg_rtol = min(1e-6, 1e-2 * step_tol)

    def div_m_grad(m, w_hat):
        """Spectrum of div(m grad w) from the spectrum of w (zero mean: divergence form)."""
        q = ikx * sp.rfft(m * sp.irfft(ikx * w_hat)) + iky * sp.rfft(m * sp.irfft(iky * w_hat))
        q[0, 0] = 0.0
        return q

    def pressure_hat(e):
        """Spectrum of the liquid pressure P = -gamma lap(h_s + e) [- Pi(e)] and dPi/de terms."""
        p_hat = gk2 * (hs_hat + sp.rfft(e))
        if not disjoining:
            return p_hat, None
        # Pi at max(e, floor): a drained node (e = 0 after clipping) would give Pi = +inf;
        # its mobility is 0 there anyway
        g, dg = iso._log_rh(np.maximum(e, floor))
        return sp.rfft(sp.irfft(p_hat) + pscale * g), pscale * dg  # -Pi = (R_g T / V) ln RH_iso

    def f_of(e, m):
        p_hat, _ = pressure_hat(e)
        return sp.irfft(div_m_grad(m, p_hat))

    def stage_solve(m, dp, h, r):
        """Solve (I + h B C) x = r, B = -div(m grad .), C = dP/de = gamma k^2 [+ D], D = |Pi'(e)|.

        B C is self-adjoint in the C inner product (B and C symmetric, C positive definite
        on zero-mean fields), so CG runs on the SPD system A x = (C + h C B C) x = C r on the
        zero-mean fields. Preconditioner: A = C (C^-1 + h B) C, so A^-1 = C^-1 (C^-1 + h B)^-1
        C^-1, approximated as

            M^-1 = P Ct^-1 K Ct^-1 P,   K = c / (1 + h mbar kd^2 c),  c = gamma k^2 + d,

        P the projection on zero mean, d the harmonic mean of D, mbar the mean mobility, kd^2
        B's own symbol for a constant mobility (the squared first-derivative wavenumbers, 0 in
        the derivative along a Nyquist line; with k^2 there, as before issue 21, CG needed ten
        times the iterations), and Ct^-1 the equilibrium solver's block approximation of C^-1:
        1 / D on the nodes whose disjoining stiffness exceeds the largest Laplacian eigenvalue
        (D >= gamma k_max^2: there C is within a factor 2 of its diagonal D), the FFT-diagonal
        (gamma k^2 + d_s)^-1 on the others (d_s the harmonic mean of their D). The variable D
        must sit in the *outer* factors: C B C is not spectrally equivalent to d^2 B, because B
        differentiates the variation of D (|grad (D v)|^2 against d^2 |grad v|^2 for a smooth v), so the
        constant-coefficient inverse 1 / (c + h mbar kd^2 c^2) of issue 21's first version
        missed the long waves more the more h B C dominated: on Paper B's 256^2 surface at RH
        0.9 (D is 40 gamma k_max^2 there) its stage CG grew to the cap of 2000 beyond tens of
        tau_slow, 21900 iterations in all, against at most 23 a stage (1452 in all) now. For a
        uniform film M^-1 is A^-1 with C^-1 replaced by 1 / D (stiff nodes: gamma k^2 / D <= 1
        neglected) or exactly A^-1 (soft nodes); without the disjoining pressure it is the
        constant-mobility inverse 1 / (gamma k^2 + h mbar kd^2 gamma^2 k^4). Tried and not
        kept: the scaling D^-1/2 F^-1[d / (gamma k^2 + d)] F D^-1/2 for Ct^-1 on every node
        (3.3 times the iterations of this one on 0.5 nm cells, where gamma k_max^2 > D), and
        MINRES on the block system [[-C, I], [I, h B]] with constant-coefficient blocks
        (bounded too, but 1.7-3.8 times the iterations, each about 15 % cheaper).
        """
        mbar = float(m.mean())
        if dp is None:
            pre = gk2 + h * mbar * kd2 * gk2 * gk2
            pre[0, 0] = np.inf  # the zero-mean subspace

            def c_apply_hat(v_hat):
                return gk2 * v_hat

            def precond(res):
                return sp.irfft(sp.rfft(res) / pre)
        else:
            # harmonic means: K approximates (C^-1 + h B)^-1, whose C^-1 is ~ 1 / D
            d = 1.0 / float(np.mean(1.0 / dp))
            c_k = gk2 + d
            kk = c_k / (1.0 + h * mbar * kd2 * c_k)
            kk[0, 0] = 0.0  # the constants are outside the zero-mean subspace
            stiff = dp >= gk2_max
            soft = (~stiff).astype(float)
            inv_stiff = np.where(stiff, 1.0 / dp, 0.0)
            filt = 1.0 / (gk2 + (1.0 / float(np.mean(1.0 / dp[~stiff])) if np.any(~stiff) else d))

            def c_apply_hat(v_hat):
                return sp.rfft(sp.irfft(gk2 * v_hat) + dp * sp.irfft(v_hat))

            def c_inv(v):
                # block-diagonal (stiff / soft nodes) and symmetric: a valid CG preconditioner
                return inv_stiff * v + soft * sp.irfft(filt * sp.rfft(soft * v))

            def precond(res):
                z = c_inv(sp.irfft(kk * sp.rfft(c_inv(res - res.mean()))))
                return z - z.mean()

        def h_apply(v):
            cv_hat = c_apply_hat(sp.rfft(v))
            bcv_hat = -div_m_grad(m, cv_hat)
            out_hat = cv_hat + h * c_apply_hat(bcv_hat)
            out_hat[0, 0] = 0.0
            return sp.irfft(out_hat)

        rhs = sp.irfft(c_apply_hat(sp.rfft(r)))
        rhs -= rhs.mean()
        x, n = _pcg(h_apply, precond, rhs, cg_rtol, 2000)
        cg_total[0] += n
        return x - x.mean()

    # Two-stage Rosenbrock W-method ROS2 (Verwer, Spee, Blom and Hundsdorfer 1999), gamma =
    # 1 + 1/sqrt(2): L-stable, second order for any approximate Jacobian (here the frozen-
    # mobility -B C at the start of the step); its first stage alone is the linearly implicit
    # Euler step, whose difference from the ROS2 result is the local error estimate.
    gam = 1.0 + 1.0 / math.sqrt(2.0)
    e = np.full(sp.shape, target)
    t = 0.0
    m = np.maximum(e, 0.0) ** 3 * inv3eta
    f0 = f_of(e, m)
    # first step: a tenth of the relaxation time of the shortest resolved wavelength
    kmax2 = float(k2.max())
    dt = min(0.1 / (float(m.max()) * kmax2 * (gamma * kmax2 + pslope)), t_end)
    steps = 0
    clipped = 0
    rel_rate = math.inf
    converged = False
    message = ""
    volume = float(e.mean())
    dp = pressure_hat(e)[1]
    while steps < max_steps:
        dt = min(dt, t_end - t)
        h = gam * dt
        k1 = stage_solve(m, dp, h, f0)
        k2_ = stage_solve(m, dp, h, f_of(e + dt * k1, m) - 2.0 * k1)
        new = e + dt * (1.5 * k1 + 0.5 * k2_)
        est = np.abs(0.5 * dt * (k1 + k2_))
        # a drained node that stays drained (clipped back to 0 below) has no error to control
        est[(e <= 0.0) & (new <= 0.0)] = 0.0
        err = float(est.max()) / (step_tol * target)
        tiny = dt <= 1e-12 * tau_slow
        if err <= 1.0 or tiny:
            # A film cannot go negative: undershoots are clipped to 0 and the volume restored
            # by rescaling. Shorter steps would not help: the pseudo-spectral flux is
            # non-local, so on a drained node (e = 0, zero mobility) the divergence of its
            # neighbours' flux need not vanish and pushes it below 0 at any step length.
            neg = new < 0.0
            if np.any(neg):
                clipped += int(np.count_nonzero(neg))
                new = np.maximum(new, 0.0)
                new *= volume / float(new.mean())
            rate = float(np.abs(new - e).max()) / dt
            e = new
            t += dt
            steps += 1
            rel_rate = rate * tau_slow / target
            m = np.maximum(e, 0.0) ** 3 * inv3eta
            f0 = f_of(e, m)
            if disjoining:
                dp = pressure_hat(e)[1]
            if progress is not None:
                progress(steps, rel_rate)
            if time_progress is not None:
                time_progress(t, t_end, tau_slow)
            if t_final is not None:
                if t >= t_end * (1.0 - 1e-12):
                    converged = True
                    message = f"integrated to t = {t:.4g} s ({t / tau_slow:.4g} tau_slow) in {steps} steps"
                    break
            else:
                if rel_rate <= steady_tol:
                    converged = True
                    message = (f"steady after {steps} steps, t = {t / tau_slow:.4g} tau_slow "
                               f"(relative rate {rel_rate:.2e} <= {steady_tol:.2e})")
                    if not disjoining:
                        message += ("; without disjoining pressure this is the drained film (the peaks "
                                    "emptied to e = 0), not an equilibrium")
                    break
                if t >= t_end * (1.0 - 1e-12):
                    if disjoining:
                        message = (f"not steady at the end time {duration:g} tau_slow after {steps} steps "
                                   f"(relative rate {rel_rate:.2e} > {steady_tol:.2e})")
                    else:
                        converged = True
                        message = (f"stopped at the end time {duration:g} tau_slow (= {t:.4g} s) after {steps} "
                                   "steps: without disjoining pressure there is no steady state, the film on "
                                   "the peaks keeps draining")
                    break
        fac = 4.0 if err == 0.0 else min(4.0, max(0.2, 0.9 / math.sqrt(err)))
        dt *= fac
    else:
        message = (f"stopped after max_iterations = {max_steps} time steps at t = {t:.4g} s ({t / tau_slow:.4g} "
                   f"tau_slow), before the end time {t_end:.4g} s ({t_end / tau_slow:.4g} tau_slow)")
    message += f" ({cg_total[0]} CG iterations)"
    if clipped:
        message += (f"; the film went negative in {clipped} node updates (set to 0 and the volume restored "
                    "by rescaling)")
    # the mean of -gamma lap(h_w) is 0 on a periodic cell: only the disjoining part is left
    p_mean = float(np.mean(iso._log_rh(np.maximum(e, floor))[0])) * pscale if disjoining else 0.0
    return dict(e=e, iterations=steps, converged=converged, message=message, residual=rel_rate,
                liquid_pressure=p_mean, time=t, levelling_time=tau_slow, clipped=clipped)
