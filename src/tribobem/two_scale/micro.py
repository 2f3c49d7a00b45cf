"""Micro scale: the normal law of a rough interface from periodic windows.

Each window is a periodic cell of the two bodies' combined roughness (and of the textures whose
period divides it) at asperity resolution.  It is pressed through a ladder of nominal pressures
p_k under force control, warm-started step to step (:func:`tribobem.solvers.normal_paths.
force_curve`), and gives at each p_k the mean gap of its mean planes (the window's mean gap:
the q = 0 displacement of a periodic cell is zero, so the window carries only its own,
micro-scale elasticity; the macro operator carries the rest), the real contact fraction and
the largest local pressure.  The realisations are averaged into a
:class:`~tribobem.two_scale.laws.NormalInterfaceLaw`.

Tables are cached on disk, keyed by a SHA-256 of everything that sets them (the window's gap
array, grid, the two materials, the interaction, the pressures, the solver tolerance and
:data:`tribobem._solver_version.SOLVER_VERSION`), so that reruns and design variants that share
roughness, materials and loads reuse them.  The windows are independent: they run through Dask
(``scheduler``: ``"synchronous"``, ``"threads"``, ``"processes"`` or the address of a
``dask.distributed`` scheduler).
"""

from __future__ import annotations

import hashlib
import json
import os
import socket
import time
import warnings
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from .._solver_version import SOLVER_VERSION
from ..elasticity.operators import periodic_operator
from ..errors import ConvergenceWarning, InputError
from ..grid import Grid
from ..materials import ContactPair
from ..solvers.normal_paths import force_curve
from .laws import NormalInterfaceLaw

__all__ = ["MicroWindows", "window_table", "interface_law", "compute_tables", "table_key", "default_cache_dir",
           "TABLE_VERSION"]

#: The format of a cached table (part of its key): bumped when a table gains or changes a column.
TABLE_VERSION = 1


@dataclass
class MicroWindows:
    """The micro windows of a two-scale run (built from ``[two_scale]`` and the bodies).

    Attributes
    ----------
    grid : Grid
        The periodic window grid (m).
    pair : ContactPair
        The two bodies' materials.
    gaps : list of ndarray
        One initial gap per realisation (m, minimum 0): the combined roughness (and short
        textures) of the two bodies.
    interaction : Interaction or None
        The stress law outside contact (None: dry, non-adhesive).
    info : dict
        How the windows were made (window size, cells, seeds, which textures went to the
        windows), for the summary.
    surfaces : list of (ndarray, ndarray), optional
        Per realisation, the two bodies' own surfaces in the window (m, positive out of each
        body): what their water films rest on.
    capillary : list of dict, optional
        Per realisation, its menisci at one RH (``film1``, ``film2``, ``options``:
        :func:`window_table`); None: dry.
    humidity : list, optional
        Per realisation, the humidity setup of its surfaces (a scenario with ``[humidity]``),
        from which a run makes :attr:`capillary` at its RH.
    """

    grid: Grid
    pair: ContactPair
    gaps: list
    interaction: Any = None
    info: dict = field(default_factory=dict)
    surfaces: list | None = None
    capillary: list | None = None
    humidity: list | None = None

    def capillary_of(self, k: int):
        """Realisation ``k``'s menisci (``film1``, ``film2``, ``options``) or None (dry)."""
        return None if self.capillary is None else self.capillary[k]

    def capillary_key(self, k: int) -> dict:
        """What sets realisation ``k``'s menisci, for the cache key (empty when dry)."""
        c = self.capillary_of(k)
        if c is None:
            return {}
        h = hashlib.sha256()
        for f in (c["film1"], c["film2"]):
            h.update(np.ascontiguousarray(np.broadcast_to(f, self.grid.shape), dtype=np.float64).tobytes())
        opts = {key: repr(v) for key, v in sorted(c["options"].items())}
        return {"capillary": h.hexdigest() + json.dumps(opts, sort_keys=True)}


def default_cache_dir() -> Path:
    """Where tables are cached: ``$TRIBOBEM_CACHE/two_scale`` or ``~/.cache/tribobem/two_scale``."""
    root = os.environ.get("TRIBOBEM_CACHE")
    base = Path(root) if root else Path(os.environ.get("XDG_CACHE_HOME", Path.home() / ".cache")) / "tribobem"
    return base / "two_scale"


def table_key(grid: Grid, pair: ContactPair, gap: np.ndarray, interaction, pressures, tol: float,
               max_iterations: int, **extra) -> str:
    """The cache key of a window's table: SHA-256 of its gap, grid, materials, stress law,
    pressures, solver settings, solver and table versions, and ``extra`` (e.g. mu, fractions)."""
    h = hashlib.sha256()
    h.update(np.ascontiguousarray(gap, dtype=np.float64).tobytes())
    meta = {"grid": [grid.nx, grid.ny, grid.lx, grid.ly], "pair": repr(pair), "interaction": repr(interaction),
            "pressures": [float(p).hex() for p in pressures], "tol": tol, "max_iterations": max_iterations,
            "solver_version": SOLVER_VERSION, "table_version": TABLE_VERSION,
            **{k: (v if not isinstance(v, (list, tuple, np.ndarray)) else [float(x).hex() for x in v])
               for k, v in extra.items()}}
    h.update(json.dumps(meta, sort_keys=True).encode())
    return h.hexdigest()


def window_states(op, gap: np.ndarray, pressures, *, interaction=None, capillary=None, tol: float = 1e-8,
                  max_iterations: int = 10000) -> tuple[list, list]:
    """A window pressed through a ladder of nominal pressures, warm-started step to step.

    Dry (or with a plain stress law): :func:`tribobem.solvers.normal_paths.force_curve`.  With
    ``capillary`` (the window's films and the capillary model's options at one RH): the
    self-consistent meniscus state at each pressure (:func:`tribobem.solvers.capillary.
    solve_capillary`), each from the one before.

    Returns
    -------
    (list of NormalResult, list of dict)
        The states, and per state ``converged``, ``iterations`` and, with menisci,
        ``repulsive_force``, ``capillary_force`` (N) and ``wetted_area`` (m^2).
    """
    grid = op.grid
    area = grid.lx * grid.ly
    forces = [float(p) * area for p in pressures]
    if capillary is None:
        curve = force_curve(op, gap, forces, interaction=interaction, unload=False, tol=tol,
                            max_iterations=max_iterations, keep_fields=True)
        steps = list(curve.steps)
        if len(steps) != len(forces):
            raise InputError("two_scale.pressures", f"the window solved {len(steps)} of {len(forces)} pressures")
        return list(curve.results), [{"converged": bool(s["converged"]), "iterations": int(s["iterations"])}
                                     for s in steps]
    from ..solvers.capillary import solve_capillary

    states, extra, prev = [], [], None
    for f in forces:
        r = solve_capillary(op, gap, normal_force=f, film1=capillary["film1"], film2=capillary["film2"], tol=tol,
                            max_iterations=max_iterations, initial=prev, **capillary["options"])
        prev = r
        states.append(r.normal)
        extra.append({"converged": bool(r.converged), "iterations": int(r.normal.iterations),
                      "repulsive_force": float(r.repulsive_force), "capillary_force": float(r.capillary_force),
                      "wetted_area": float(r.wetted_area)})
    return states, extra


def window_table(grid: Grid, pair: ContactPair, gap: np.ndarray, pressures, *, interaction=None, capillary=None,
                 tol: float = 1e-8, max_iterations: int = 10000) -> dict:
    """One window's table: mean gap, contact fraction and peak pressure at each pressure.

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
    interaction : Interaction, optional
        Stress law outside contact.
    capillary : dict, optional
        Menisci at one RH: ``film1``, ``film2`` (m, the films on the window's two surfaces) and
        ``options`` (the remaining keyword arguments of :func:`tribobem.solvers.capillary.
        solve_capillary`: Kelvin radius, capillary pressure, ...).
    tol, max_iterations : float, int
        Normal solver settings of every step.

    Returns
    -------
    dict
        ``gaps`` (m), ``touch_gap`` (m: the mean gap at first touch), ``contact_fractions``,
        ``max_pressures`` (Pa), ``patch_cells`` (the largest contact patch's equivalent
        diameter in cells), ``converged`` and ``iterations`` (per pressure); with menisci also
        ``repulsive_pressures`` and ``capillary_pressures`` (Pa: the window's mean repulsive
        and meniscus pressures, the latter negative) and ``wetted_fractions``.
    """
    op = periodic_operator(grid, pair)
    area = grid.lx * grid.ly
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ConvergenceWarning)  # carried in ``converged``
        states, extra = window_states(op, gap, pressures, interaction=interaction, capillary=capillary, tol=tol,
                                      max_iterations=max_iterations)
    out = {
        "patch_cells": [_largest_patch_cells(np.asarray(r.contact)) for r in states],
        "gaps": [float(r.mean_gap) for r in states],
        "touch_gap": float(np.mean(gap)),
        "contact_fractions": [float(r.contact_area) / area for r in states],
        "max_pressures": [float(r.max_pressure) for r in states],
        "converged": [e["converged"] for e in extra],
        "iterations": [e["iterations"] for e in extra],
    }
    if capillary is not None:
        out["repulsive_pressures"] = [e["repulsive_force"] / area for e in extra]
        out["capillary_pressures"] = [e["capillary_force"] / area for e in extra]
        out["wetted_fractions"] = [e["wetted_area"] / area for e in extra]
    return out


def _largest_patch_cells(contact: np.ndarray) -> float:
    """Equivalent diameter (cells) of the largest contact patch, 2 sqrt(n / pi) of its n cells
    (patches are 4-connected; a patch across the periodic edge counts as two)."""
    from scipy import ndimage

    labels, count = ndimage.label(contact)
    if count == 0:
        return 0.0
    largest = int(np.bincount(labels.ravel())[1:].max())
    return float(2.0 * np.sqrt(largest / np.pi))


#: A lock on a table older than this (s) is taken for a killed computation's and ignored.
STALE_LOCK = 3600.0


def _holder_gone(lock: Path) -> bool:
    """Whether the lock's holder was a process on this machine that no longer runs (a killed run
    leaves its lock behind; one on another machine of a cluster is judged by its age alone)."""
    try:
        host, pid = lock.read_text().split()
        pid = int(pid)
    except (OSError, ValueError):
        return False  # being written just now, or not ours to judge
    if host != socket.gethostname():
        return False
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return True
    except PermissionError:
        return False
    return False


def _read_table(path: Path) -> dict | None:
    try:
        table = json.loads(path.read_text())
    except (OSError, ValueError):
        return None  # absent, or unreadable (e.g. written by a killed run): recompute
    table["cached"] = True
    return table


def _cached_call(fn, kwargs: dict, key: str, cache_dir: str | None) -> dict:
    """``fn(**kwargs)`` (a table as a dict), read from or written to ``cache_dir/<key>.json``
    (None: no cache).

    While one process computes a table it holds ``<key>.lock``; another process that needs the
    same table (the points of a design study on the workers of one machine or of a cluster that
    shares the cache folder) waits for it instead of computing it twice.
    """
    path = Path(cache_dir) / f"{key}.json" if cache_dir is not None else None
    lock = None
    if path is not None:
        table = _read_table(path)
        if table is not None:
            return table
        path.parent.mkdir(parents=True, exist_ok=True)
        lock = path.with_suffix(".lock")
        while True:
            try:
                fd = os.open(lock, os.O_CREAT | os.O_EXCL | os.O_WRONLY)
                os.write(fd, f"{socket.gethostname()} {os.getpid()}".encode())
                os.close(fd)
            except FileExistsError:
                pass
            else:
                # ours; but another process may have written the table and released the lock
                # between our first look and now
                table = _read_table(path)
                if table is None:
                    break  # compute it
                lock.unlink(missing_ok=True)
                return table
            # another process holds the lock: wait for its table (or take over a stale lock)
            try:
                stale = time.time() - lock.stat().st_mtime > STALE_LOCK or _holder_gone(lock)
            except FileNotFoundError:
                continue  # released just now
            if stale:
                lock.unlink(missing_ok=True)
                continue
            time.sleep(0.5)
            table = _read_table(path)
            if table is not None:
                return table
    try:
        table = fn(**kwargs)
        if path is not None:
            tmp = path.with_suffix(f".tmp{os.getpid()}")
            tmp.write_text(json.dumps(table))
            os.replace(tmp, path)  # atomic: a reader sees the whole table or none
    finally:
        if lock is not None:
            lock.unlink(missing_ok=True)
    table["cached"] = False
    return table


def compute_tables(tasks: list, cache: bool, cache_dir, scheduler: str) -> list:
    """Run the window tasks ``(fn, kwargs, key)`` through the cache and Dask (module docstring).

    Parameters
    ----------
    tasks : list of (callable, dict, str)
        The table function, its keyword arguments and the cache key of each window.
    cache : bool
        Use the cache.
    cache_dir : path or None
        Default :func:`default_cache_dir`.
    scheduler : str
        ``"synchronous"``, ``"threads"``, ``"processes"`` or a Dask scheduler address.

    Returns
    -------
    list of dict
        The tables, in task order, each with ``cached`` (bool).
    """
    where = (str(cache_dir) if cache_dir is not None else str(default_cache_dir())) if cache else None
    if scheduler == "synchronous" or len(tasks) == 1:
        return [_cached_call(fn, kw, key, where) for fn, kw, key in tasks]
    import dask

    delayed = [dask.delayed(_cached_call)(fn, kw, key, where) for fn, kw, key in tasks]
    if scheduler in ("threads", "processes"):
        return list(dask.compute(*delayed, scheduler=scheduler))
    from dask.distributed import Client  # an address: a running dask.distributed scheduler

    with Client(scheduler) as client:
        return list(dask.compute(*delayed, scheduler=client))


def interface_law(windows: MicroWindows, pressures, *, tol: float = 1e-8, max_iterations: int = 10000,
                  scheduler: str = "synchronous", cache: bool = True, cache_dir=None) -> NormalInterfaceLaw:
    """The normal interface law of ``windows`` at ``pressures`` (averaged over the realisations).

    Parameters
    ----------
    windows : MicroWindows
        The windows (one gap per realisation).
    pressures : sequence of float
        Nominal pressures (Pa), increasing, > 0.
    tol, max_iterations : float, int
        Normal solver settings of the window solves.
    scheduler : str
        ``"synchronous"``, ``"threads"``, ``"processes"`` or a Dask scheduler address.
    cache : bool
        Read and write the tables in ``cache_dir``.
    cache_dir : path, optional
        Default :func:`default_cache_dir`.

    Returns
    -------
    NormalInterfaceLaw
        With ``info``: the windows' provenance, ``cached`` (how many tables were read from the
        cache), ``iterations`` (total), ``not_converged`` (how many micro solves did not).
    """
    pressures = np.asarray(pressures, dtype=float)
    if pressures.ndim != 1 or pressures.size < 3 or not np.all(np.diff(pressures) > 0) or pressures[0] <= 0:
        raise InputError("two_scale.pressures", "the table needs at least 3 increasing positive pressures")
    tasks = [(window_table, {"grid": windows.grid, "pair": windows.pair, "gap": g, "pressures": pressures,
                             "interaction": windows.interaction, "capillary": windows.capillary_of(k), "tol": tol,
                             "max_iterations": max_iterations},
              table_key(windows.grid, windows.pair, g, windows.interaction, pressures, tol, max_iterations,
                        **windows.capillary_key(k)))
             for k, g in enumerate(windows.gaps)]
    tables = compute_tables(tasks, cache, cache_dir, scheduler)
    info = dict(windows.info)
    info["capillary"] = windows.capillary is not None
    info.update({"cached": int(sum(t.get("cached", False) for t in tables)),
                 "iterations": int(sum(sum(t["iterations"]) for t in tables)),
                 "not_converged": int(sum(len(t["converged"]) - sum(t["converged"]) for t in tables)),
                 "solves": int(sum(len(t["converged"]) for t in tables))})
    gaps = np.mean([t["gaps"] for t in tables], axis=0)
    flat = np.flatnonzero(np.diff(gaps) >= 0)
    if flat.size:
        # the windows' mean gap stopped decreasing: they are (nearly) in full contact, where the
        # interface has no compliance left and the law cannot be inverted
        k = int(flat[0]) + 1
        frac = float(np.mean([t["contact_fractions"][k] for t in tables]))
        raise InputError("two_scale.max_pressure", f"the windows' mean gap stops decreasing at {pressures[k]:.4g} Pa "
                         f"(real contact fraction {frac:.3g}): the windows are in full contact there and the interface "
                         "law cannot be inverted; give a smaller max_pressure, or windows that hold more of the "
                         "roughness (a larger two_scale.window)")
    return NormalInterfaceLaw.from_realisations(pressures, tables, info)
