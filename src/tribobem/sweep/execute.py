"""Running a sweep: the points without a record, in this process or on Dask.

:func:`run_sweep` reads the finished points of a results folder, runs the others
(:func:`~tribobem.sweep.point.run_point`) in this process (``"synchronous"``), on a
``LocalCluster`` of worker processes, or on an existing Dask scheduler, writes every record
as soon as its point finishes, shows its progress (a live bar on a terminal, one line per finished
point off one), and gathers the results at the end.  A
Ctrl-C stops it with every finished point saved (the worker processes of a local cluster
ignore SIGINT, so only this process handles it).
"""

from __future__ import annotations

import json
import os
import signal
import sys
import threading
import time
from collections.abc import Callable, Mapping
from contextlib import contextmanager
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from rich.console import Console
from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn, TimeElapsedColumn, TimeRemainingColumn

from .. import _solver_version
from ..errors import InputError
from ..output.atomic import atomic_write_text
from .cache import _clean_stale_tmp, pending, read_points, write_record
from .point import failed_record, run_point
from .results import gather, write_results
from .spec import load_sweep
from .values import _jsonable

__all__ = ["SweepResult", "run_sweep"]


@dataclass
class SweepResult:
    """What :func:`run_sweep` did.

    Attributes
    ----------
    outdir : Path
        The results folder.
    n_points : int
        Points in the sweep.
    n_done_before : int
        Points with a successful record before this run (skipped).
    n_run : int
        Points computed in this run.
    n_ok, n_failed : int
        Points with a successful / failed record after this run.
    wall_time : float
        Seconds this run took.
    results_nc, results_csv : Path or None
        The gathered files.
    dataset : xarray.Dataset or None
        What :func:`~tribobem.sweep.results.gather` made of the records.
    failed : dict
        hash -> error message of the failed points.
    """

    outdir: Path
    n_points: int
    n_done_before: int
    n_run: int
    n_ok: int
    n_failed: int
    wall_time: float
    results_nc: Path | None = None
    results_csv: Path | None = None
    dataset: Any = None
    failed: dict = field(default_factory=dict)

    @property
    def complete(self) -> bool:
        """True when every point of the sweep has a successful record."""
        return self.n_ok == self.n_points

    @property
    def exit_code(self) -> int:
        """0 when every point succeeded, 1 otherwise (for the CLI)."""
        return 0 if self.complete else 1

    def as_dict(self) -> dict:
        """The result as plain JSON types (paths as strings, ``wall_time`` in s, no dataset)."""
        return {"outdir": str(self.outdir), "n_points": self.n_points, "n_done_before": self.n_done_before,
                "n_run": self.n_run, "n_ok": self.n_ok, "n_failed": self.n_failed,
                "wall_time": self.wall_time,
                "results_nc": str(self.results_nc) if self.results_nc else None,
                "results_csv": str(self.results_csv) if self.results_csv else None,
                "failed": dict(self.failed)}


class _Progress:
    """Progress of the points of a sweep: a live Rich bar on a terminal, else one line each.

    Off a terminal (stderr redirected to a file or a pipe, Rich's ``Console.is_terminal``
    false) a live bar draws nothing until it stops, so a log would show the start line and
    then nothing until the end; there every finished point gets its own flushed line instead:
    ``point 3 of 4 done: x = 1, y = 10 (12.3 s)``.

    Parameters
    ----------
    enabled : bool
        Show progress at all (False: nothing, as under ``--quiet``).
    total : int
        Points to run this time.
    label : str
        The bar's label (the sweep's name).
    offset : int
        Points already done before this run (the line numbers count on from it).
    n_points : int, optional
        Points in the sweep (default ``offset + total``).
    console : rich.console.Console, optional
        Where the progress goes (default: a console on stderr, beside the other messages).
    """

    def __init__(self, enabled: bool, total: int, label: str, offset: int = 0, n_points: int | None = None,
                 console: Console | None = None):
        self.bar = None
        self.lines = False
        self.done = offset
        self.n_points = n_points if n_points is not None else offset + total
        if not (enabled and total):
            return
        console = console if console is not None else Console(stderr=True)
        if not console.is_terminal and not console.is_jupyter:  # a notebook draws Rich's bar itself
            self.lines = True
            self.file = console.file
            return
        try:
            self.bar = Progress(TextColumn("[bold]{task.description}"), BarColumn(), MofNCompleteColumn(),
                                TimeElapsedColumn(), TimeRemainingColumn(), transient=False, console=console)
            self.task = self.bar.add_task(label, total=total)
            self.bar.start()
        except Exception:  # pragma: no cover - a console Rich cannot drive: one line per point
            self.bar = None
            self.lines = True
            self.file = console.file

    @property
    def shows_failures(self) -> bool:
        """True when a failed point's error is part of the progress output (line mode)."""
        return self.lines

    def advance(self, rec: Mapping | None = None):
        """One point finished (``rec``: its record, for the line off a terminal)."""
        self.done += 1
        if self.bar is not None:
            self.bar.advance(self.task)
        elif self.lines:
            rec = rec or {}
            point = rec.get("point") or {}
            params = ", ".join(f"{k} = {v}" for k, v in point.items()) if isinstance(point, Mapping) else str(point)
            el = rec.get("elapsed")
            took = f" ({el:.1f} s)" if isinstance(el, (int, float)) else ""
            ok = rec.get("status", "ok") == "ok"
            line = (f"point {self.done} of {self.n_points} {'done' if ok else 'failed'}: {params or '(base)'}{took}" +
                    ("" if ok else f": {rec.get('error')}"))
            print(line, file=self.file, flush=True)

    def close(self):
        if self.bar is not None:
            self.bar.stop()


def _say(msg: str, quiet: bool) -> None:
    if not quiet:
        print(msg, file=sys.stderr, flush=True)


def run_sweep(
    spec,
    outdir: str | os.PathLike,
    scheduler=None,
    n_workers: int | None = None,
    progress: bool = True,
    func: Callable[[dict], Mapping] | None = None,
    *,
    quiet: bool | None = None,
    retry_failed: bool = True,
    gather_results: bool = True,
    max_points: int | None = None,
) -> SweepResult:
    """Run every point of a sweep that has no successful record in ``outdir``.

    Parameters
    ----------
    spec : SweepSpec, path or dict
        The sweep (a path is read with :meth:`~tribobem.sweep.SweepSpec.from_file`).
    outdir : path
        Results folder: ``points/<hash>.json`` per point, ``results.nc``, ``results.csv``,
        ``sweep.json`` (the spec echoed).
    scheduler : None, "synchronous", "local", address or distributed.Client
        None / "local": a ``LocalCluster`` of ``n_workers`` single-threaded worker
        processes, closed at the end.  An address (``"tcp://host:8786"``): an existing
        scheduler.  "synchronous": in this process, no Dask (tests, debugging).
    n_workers : int, optional
        Local cluster size (default ``min(2, cpu count)``).
    progress : bool
        Show progress on stderr: a live bar on a terminal, else one line per finished point.
    func : callable, optional
        ``func(point) -> dict of scalars`` replaces the spec's runner (library use; the
        point is the dict of overrides as written in the spec).
    quiet : bool, optional
        No messages (default: ``not progress``).
    retry_failed : bool
        Run the points whose record says "failed" again (default).
    gather_results : bool
        Write ``results.nc`` / ``results.csv`` at the end.
    max_points : int, optional
        Run at most this many of the missing points (the rest stay missing).

    Returns
    -------
    SweepResult
        Counts of the points, the gathered files and dataset, the failures, the wall time (s).

    Raises
    ------
    KeyboardInterrupt
        On Ctrl-C, after the local cluster (if any) is closed; every finished point is saved.
    """
    t0 = time.perf_counter()
    spec = load_sweep(spec)
    quiet = (not progress) if quiet is None else quiet
    outdir = Path(outdir)
    (outdir / "points").mkdir(parents=True, exist_ok=True)
    if func is not None:
        runner = "callable:" + getattr(func, "__module__", "?") + ":" + getattr(func, "__qualname__", repr(func))
    else:
        runner = spec.runner
    tasks = spec.tasks(runner)
    atomic_write_text(outdir / "sweep.json", json.dumps(_jsonable({
        "name": spec.name, "description": spec.description, "runner": runner,
        "source": str(spec.source) if spec.source else None,
        "scenario": str(spec.scenario_path) if spec.scenario_path else None,
        "base": spec.base, "parameters": spec.parameters, "points": spec.points,
        "outputs": spec.outputs, "is_grid": spec.is_grid, "n_points": len(tasks),
        "solver_version": _solver_version.SOLVER_VERSION,
        "hashes": [h for h, _ in tasks],
    }), indent=1) + "\n")

    _clean_stale_tmp(outdir)
    records = read_points(outdir)
    done, todo = pending(tasks, records, retry_failed, max_points)
    _say(f"sweep {spec.name!r}: {len(done)} of {len(tasks)} points done, running {len(todo)}", quiet)

    base_task = {"outputs": spec.outputs}
    if func is not None:
        base_task.update(mode="callable", func=func)
    elif spec.function:
        base_task.update(mode="function", function=spec.function, base=spec.base)
    else:
        base_task.update(mode="scenario", base=spec.base,
                         base_dir=str(spec.scenario_path.parent) if spec.scenario_path else
                         (str(spec.source.parent) if spec.source else None))

    def make_task(h, o):
        t = dict(base_task, hash=h, point=o)
        if t["mode"] == "scenario" and spec.keep_runs:
            t["run_dir"] = str((outdir / "runs" / h).resolve())
        return t

    n_run = 0
    bar = _Progress(progress and not quiet, len(todo), spec.name, offset=len(done), n_points=len(tasks))

    def finish(rec):
        nonlocal n_run
        write_record(outdir, rec)
        records[rec["hash"]] = rec
        n_run += 1
        bar.advance(rec)
        if rec["status"] != "ok":
            _say(f"point {rec['hash']} {rec.get('point')} failed: {rec.get('error')}",
                 quiet or bar.bar is not None or bar.shows_failures)

    try:
        if not todo:
            pass
        elif scheduler == "synchronous" or scheduler == "sync":
            for h, o in todo:
                finish(run_point(make_task(h, o)))
        else:
            _run_distributed(todo, make_task, finish, scheduler, n_workers, quiet)
    finally:
        bar.close()

    nc = csv_path = ds = None
    if gather_results:
        nc, csv_path = write_results(spec, outdir, records, runner)
        ds = gather(spec, outdir, records, runner)
    final = [records.get(h) for h, _ in tasks]
    n_ok = sum(1 for r in final if r and r.get("status") == "ok")
    failed = {h: r.get("error") for (h, _), r in zip(tasks, final) if r and r.get("status") == "failed"}
    res = SweepResult(outdir=outdir, n_points=len(tasks), n_done_before=len(done), n_run=n_run, n_ok=n_ok,
                      n_failed=len(failed), wall_time=time.perf_counter() - t0, results_nc=nc,
                      results_csv=csv_path, dataset=ds, failed=failed)
    _say(f"sweep {spec.name!r}: {n_ok} of {len(tasks)} ok, {len(failed)} failed, "
         f"{len(tasks) - n_ok - len(failed)} missing ({res.wall_time:.1f} s)" +
         (f"; results in {nc}" if nc else ""), quiet)
    return res


@contextmanager
def _sigint_ignored():
    """Ignore SIGINT in this process while a local cluster starts its worker processes.

    The workers inherit the ignored signal, so a Ctrl-C at the terminal, which goes to the
    whole process group, is handled by this process alone: it stops the cluster and says what
    is saved, instead of every worker printing a traceback.  (A Ctrl-C during these seconds
    is lost; the next one works.)  Outside the main thread nothing changes."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    try:
        old = signal.signal(signal.SIGINT, signal.SIG_IGN)
    except (ValueError, OSError):  # pragma: no cover - no signals here
        yield
        return
    try:
        yield
    finally:
        signal.signal(signal.SIGINT, old if old is not None else signal.SIG_DFL)


def _run_distributed(todo, make_task, finish, scheduler, n_workers, quiet):
    """Run the points ``todo`` on Dask and call ``finish(record)`` for each as it completes."""
    # Deferred: distributed is heavy to import and a synchronous sweep does without it.
    from distributed import Client, LocalCluster, as_completed

    cluster = None
    own_client = True
    if isinstance(scheduler, Client):
        client, own_client = scheduler, False
    elif scheduler in (None, "local", "processes"):
        n = n_workers or min(2, os.cpu_count() or 1)
        with _sigint_ignored():  # the worker processes never see a Ctrl-C
            cluster = LocalCluster(n_workers=n, threads_per_worker=1, processes=True, dashboard_address=":0",
                                   silence_logs=50)
        client = Client(cluster)
        _say(f"local Dask cluster: {n} worker process(es)", quiet)
    elif isinstance(scheduler, str):
        client = Client(scheduler)
        _say(f"Dask scheduler {scheduler}", quiet)
    else:
        raise InputError("scheduler", f"must be None, 'synchronous', 'local', an address or a Client, got {scheduler!r}")
    futures = {}
    try:
        for h, o in todo:
            fut = client.submit(run_point, make_task(h, o), pure=False, key=f"point-{h}-{os.getpid()}-{time.time_ns()}")
            futures[fut] = (h, o)
        for fut in as_completed(list(futures)):
            h, o = futures.pop(fut)
            try:
                rec = fut.result()
            except (KeyboardInterrupt, SystemExit):
                raise
            except Exception as exc:  # the worker died, or the task could not run
                rec = failed_record(h, o, exc)
            finish(rec)
    finally:
        for fut in futures:
            fut.cancel()
        if own_client:
            client.close()
        if cluster is not None:
            cluster.close()
