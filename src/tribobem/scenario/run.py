"""Run a scenario: parse -> build -> solve -> outputs.

The solving step belongs to the run kind: :func:`run_scenario` looks the kind's runner up in
the registry :data:`tribobem.runs.RUNNERS` (one module per kind in :mod:`tribobem.runs`:
``normal``, ``pulloff``, ...) and turns what the runner returns into summary.json, fields.nc,
figures and the report.  A kind the schema accepts but that has no runner raises
:class:`NotImplementedKindError` (the scenario itself is valid).
"""

from __future__ import annotations

import datetime as _dt
import os
import time
import tomllib
import warnings
from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable

import numpy as np

from ..errors import ConvergenceWarning, InputError, result_warning_category
from ..runs import KINDS as RUN_KINDS
from ..runs import NotImplementedKindError, get_runner
from ..runs.settings import SolverSettings
from .build import Problem, build_problem
from .schema import EXPECTED_KEYS, Scenario, parse_scenario
from ..output import write_outputs
from ..output.atomic import staged, pause_hook
from ..output.checks import cohesive_edge_band, compare_expected, result_warnings
from ..output.fields import build_fields
from ..output.summary import versions, write_summary
from ..output.stresses import add_stress_fields

__all__ = ["RunResult", "NotImplementedKindError", "load_scenario", "read_scenario_file", "run_scenario"]


@dataclass
class RunResult:
    """The outcome of :func:`run_scenario`.

    Attributes
    ----------
    summary : dict
        summary.json content (file-contract keys).
    fields : xarray.Dataset or None
        fields.nc content (dims step, x, y).
    outdir : Path or None
        Where the files were written (None: nothing written).
    files : dict
        Name -> Path of the files written.
    problem : Problem
    results : list of NormalResult
        The solutions stored in ``fields`` (one per step there).
    curve : LoadCurve or None
        The force-approach curve of list / pull-off runs.
    tangential : list of TangentialResult
        Tangential kinds: the tangential solutions aligned one-to-one with ``results``
        (empty for the normal kinds).
    """

    summary: dict
    fields: object
    outdir: Path | None
    files: dict = field(default_factory=dict)
    problem: Problem | None = None
    results: list = field(default_factory=list)
    curve: object = None
    tangential: list = field(default_factory=list)

    @property
    def converged(self) -> bool:
        """Whether every step of the run converged (summary.json's ``converged``)."""
        return bool(self.summary.get("converged"))

    @property
    def warnings(self) -> list[str]:
        """The run's warnings (summary.json ``warnings``): one ``"check: message"`` line per
        result check that fired (:mod:`tribobem.output.checks`), and the input's and the
        runner's notes.  Empty when nothing needs the user's attention.  The same lines are
        issued as Python warnings (:class:`~tribobem.errors.ResultWarning` subclasses)."""
        return list(self.summary.get("warnings") or [])

    @property
    def steps(self) -> list:
        """The summary.json step rows (one dict per step; empty when there are none)."""
        return self.summary.get("steps", [])

    @property
    def report(self) -> Path | None:
        """Path of report.html, or None when no report was written."""
        return self.files.get("report")


# ----------------------------------------------------------------------------- loading
def _has_topography(body) -> bool:
    """Whether a body carries a topography map worth writing (roughness, texture or waviness)."""
    return body.roughness.kind != "none" or body.texture is not None or body.waviness is not None


def read_scenario_file(path) -> dict:
    """Read a TOML scenario file into a dict.

    Parameters
    ----------
    path : str or Path
        The scenario file.

    Returns
    -------
    dict
        The parsed TOML, not yet validated (the schema does that).

    Raises
    ------
    FileNotFoundError
        If the file does not exist.
    InputError
        If it is a folder, or not valid TOML (with the line and column).
    """
    path = Path(path)
    if not path.exists():
        raise FileNotFoundError(f"scenario file {path} not found")
    if path.is_dir():
        raise InputError("scenario", f"{path} is a folder, not a scenario file")
    try:
        with open(path, "rb") as fh:
            return tomllib.load(fh)
    except tomllib.TOMLDecodeError as exc:
        raise InputError("scenario", f"{path} is not valid TOML: {exc}") from None
    except UnicodeDecodeError as exc:
        raise InputError("scenario", f"{path} is not a UTF-8 text file: {exc}") from None


def load_scenario(scenario, base_dir=None) -> tuple[Scenario, Path]:
    """A validated scenario and the folder its relative paths refer to.

    Parameters
    ----------
    scenario : dict, Scenario, str or Path
        A dict (as from TOML), a :class:`Scenario`, or the path of a TOML file.
    base_dir : path-like, optional
        Overrides the folder relative paths are resolved against (default: the scenario
        file's folder, or the current directory for dicts).

    Returns
    -------
    (Scenario, Path)
    """
    source = None
    if isinstance(scenario, (str, Path)):
        path = Path(scenario)
        data = read_scenario_file(path)
        source = str(path)
        base = Path(base_dir) if base_dir is not None else path.resolve().parent
    else:
        data = scenario
        base = Path(base_dir) if base_dir is not None else Path.cwd()
    return parse_scenario(data, source), base


# ----------------------------------------------------------------------------- progress
class _RichProgress:
    """A Rich progress bar on stderr, fed by ``progress(done, total)`` callbacks."""

    def __init__(self):
        from rich.console import Console
        from rich.progress import (BarColumn, MofNCompleteColumn, Progress, SpinnerColumn, TextColumn,
                                   TimeElapsedColumn, TimeRemainingColumn)

        # the time left is Rich's estimate from the rate so far (long levelling runs say how long)
        self.progress = Progress(SpinnerColumn(), TextColumn("{task.description}"), BarColumn(),
                                 MofNCompleteColumn(), TimeElapsedColumn(), TimeRemainingColumn(),
                                 console=Console(stderr=True), transient=False)
        self.task = None

    def __enter__(self):
        self.progress.__enter__()
        return self

    def __exit__(self, *exc):
        return self.progress.__exit__(*exc)

    def phase(self, description: str, total: int | None):
        if self.task is not None:
            self.progress.update(self.task, completed=self.progress.tasks[-1].total or 0)
        self.task = self.progress.add_task(description, total=total)

    def __call__(self, done: int, total: int):
        if self.task is None:
            self.phase("solving", total)
        self.progress.update(self.task, completed=done, total=total)

    def finish(self):
        if self.task is not None:
            t = self.progress.tasks[-1]
            self.progress.update(self.task, completed=t.total if t.total is not None else t.completed)


class _Callback:
    """Wraps a user callable ``progress(done, total)`` into the phase protocol."""

    def __init__(self, fn: Callable[[int, int], None] | None):
        self.fn = fn

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        return False

    def phase(self, description, total):
        pass

    def __call__(self, done, total):
        if self.fn is not None:
            self.fn(done, total)

    def finish(self):
        pass


class _PauseHook:
    """Tests only (``TRIBOBEM_TEST_PAUSE=solve[@N]=SECONDS``, see :mod:`tribobem.output.atomic`):
    the progress handler, paused after the first step of a solve so that a test can send a
    real SIGINT while the run is demonstrably solving."""

    def __init__(self, bar):
        self.bar, self.first = bar, True

    def __getattr__(self, name):
        return getattr(self.bar, name)

    def __call__(self, done, total):
        self.bar(done, total)
        if self.first:
            self.first = False

            pause_hook("solve")


def _progress_handler(progress, quiet: bool):
    if callable(progress):
        return _Callback(progress)
    if progress and not quiet:
        return _RichProgress()
    return _Callback(None)


def run_scenario(scenario, outdir=None, progress=True, quiet: bool = False, base_dir=None,
                 warn: bool = True) -> RunResult:
    """Run a scenario and (optionally) write its result folder.

    Parameters
    ----------
    scenario : dict, Scenario, str or Path
        The scenario, or the path of its TOML file (relative file paths inside it are
        resolved against the file's folder).
    outdir : path-like, optional
        Result folder: summary.json, fields.nc, figures (PNG) and report.html are written
        there (atomically).  None: nothing is written.
    progress : bool or callable
        True: a Rich progress bar on stderr (unless ``quiet``); a callable is called as
        ``progress(done, total)``; False: nothing.
    quiet : bool
        Suppress the progress bar.
    base_dir : path-like, optional
        Folder for relative paths (default: the scenario file's folder / the current one).
    warn : bool
        Issue the run's warnings (summary.json ``warnings``, :attr:`RunResult.warnings`) as
        Python warnings too, one :class:`~tribobem.errors.ResultWarning` subclass per result
        check (default).  False for callers that show them their own way (sweeps, designs).

    Returns
    -------
    RunResult

    Raises
    ------
    InputError (incl. ScenarioError, NotImplementedKindError), TopographyError,
    MemoryBudgetError, FileNotFoundError
    """
    t0 = time.perf_counter()
    sc, base = load_scenario(scenario, base_dir)
    try:
        runner = get_runner(sc.kind)
    except NotImplementedKindError as exc:
        raise NotImplementedKindError(exc.field, f"{exc.reason}; the scenario itself is valid") from None
    pb = build_problem(sc, base)
    # The effective solver settings, once: every solve of the run takes them, summary.json
    # records them (runs/settings.py).
    settings = SolverSettings.from_scenario(sc)
    t_build = time.perf_counter()

    with _progress_handler(progress, quiet) as bar:
        out = runner(pb, _PauseHook(bar) if os.environ.get("TRIBOBEM_TEST_PAUSE") else bar, settings=settings)
        bar.finish()
    t_solve = time.perf_counter()

    rows = out.rows
    for i, r in enumerate(rows):
        r["index"] = i
    converged = bool(rows) and all(bool(r.get("converged")) for r in rows)
    warns = list(pb.warnings) + list(out.warnings)

    # Numbers the grid cannot back (edge contact, unresolved cohesive zone, ...): on the states
    # the runner returned (before any fields selection).
    # The grid's band of Dugdale equilibria (output/checks.py, cohesive_edge): reported on every
    # Dugdale run without menisci (water's tension is not a two-valued law), warned above
    # MAX_EDGE_FORCE or where the zone is not resolved.
    band_defined = pb.humidity is None
    warns += result_warnings(out.results, periodic=pb.grid.periodic, interaction=pb.interaction,
                             radius=pb.info.get("radius"), tangential=out.tangential,
                             files=pb.info.get("files"), gross_slip=out.run.get("gross_slip"),
                             effective_modulus=pb.info.get("effective_modulus"), grid_band=band_defined,
                             pair=pb.pair)
    edge_band = (cohesive_edge_band(out.results, pb.interaction, pb.info.get("effective_modulus"), pair=pb.pair)
                 if band_defined else None)
    # The same lines as Python warnings, one category per check (errors.RESULT_WARNINGS), so that
    # a script sees them without reading the summary.
    for w in warns if warn else ():
        warnings.warn(str(w), result_warning_category(w), stacklevel=2)
    if not converged:
        bad = [i for i, r in enumerate(rows) if not r.get("converged")]
        where = ", ".join(str(i) for i in bad[:10]) + (", ..." if len(bad) > 10 else "")
        msg = (f"{len(bad)} of {len(rows)} step(s) did not converge (steps {where}; tolerance "
               f"{sc.solver.tolerance:g}, max_iterations {sc.solver.max_iterations}); the run went on from "
               "their state; see summary.json steps")
        warns.append(msg)
        warnings.warn(msg, ConvergenceWarning, stacklevel=2)
    curve = out.curve


    summary = {
        "kind": sc.kind,
        "converged": converged,
        "inputs": sc.model_dump(mode="json"),
        "versions": versions(),
        "timings": {"build": t_build - t0, "solve": t_solve - t_build},
        "steps": rows,
        **out.run,
        "jumps": [dict(j) for j in curve.jumps] if curve is not None else [],
        # what [solver] method = "auto" stood for, where the run's solves take a method (also
        # under "solver"; kept here, where summaries always had it)
        "problem": {**pb.info, **({"normal_method": settings.normal_method} if settings.normal_method is not None else {})},
        "solver": settings.summary(),
        **({"cohesive_edge": edge_band} if edge_band is not None else {}),
        "warnings": warns,
        "created": _dt.datetime.now().isoformat(timespec="seconds"),
    }

    # fields
    keep = sc.output.fields
    results, labels, indices = out.results, out.labels, out.indices  # aligned (RunOutput checks it)
    tangential = list(out.tangential or [])
    sel = list(range(len(results)))  # the runner's results kept in fields.nc
    if keep == "last" and len(results) > 1:
        # The state a user looks for: the runner's representative one (e.g. the RH of the peak
        # capillary force), the pull-off, the gross-slip onset, else the largest load.
        named = [name for name in ("pull-off", "onset") if name in labels]
        if out.representative is not None:
            sel = [int(out.representative)]
        elif named:
            sel = [labels.index(named[0])]
        else:
            sel = [int(np.nanargmax([r.force for r in results]))]
        results, labels, indices = [results[i] for i in sel], [labels[i] for i in sel], [indices[i] for i in sel]
        tangential = [tangential[i] for i in sel] if tangential else []
    elif keep == "none":
        results, labels, indices, tangential, sel = [], [], [], [], []

    attrs = {"title": sc.name or f"tribobem {sc.kind} run", "kind": sc.kind,
             "tribobem_version": summary["versions"]["tribobem"],
             "effective_modulus": pb.info.get("effective_modulus"), "operator": pb.info.get("operator")}
    ds = build_fields(pb.grid, results, labels, initial_gap=pb.gap,
                      roughness1=pb.roughness1 if _has_topography(sc.body1) else None,
                      roughness2=pb.roughness2 if _has_topography(sc.body2) else None,
                      summary_steps=indices, attrs=attrs,
                      **({"tangential": tangential} if tangential else {}))
    for name, (maps, attrs_v) in out.cycle_fields.items():
        # Per-cycle maps of a run (e.g. frictional dissipation, accumulated slip): dims (cycle, x, y).
        ds[name] = (("cycle", "x", "y"), np.stack([np.asarray(m, dtype=float) for m in maps]), attrs_v)
    for name, (maps, attrs_v) in out.step_fields.items():
        # Per-step maps of a run (e.g. the films and meniscus islands of each RH of a capillary
        # run), aligned with its results: dims (step, x, y), selected with them.
        if sel:
            ds[name] = (("step", "x", "y"), np.stack([np.asarray(maps[i]) for i in sel]), attrs_v)
    for name, (values, attrs_v) in out.step_coords.items():
        # Per-step scalars of a run as coordinates (e.g. the RH of each capillary step).
        ds = ds.assign_coords({name: ("step", np.asarray([values[i] for i in sel], dtype=float), attrs_v)})
    if "cycle" in ds.dims:
        ds = ds.assign_coords(cycle=np.arange(1, ds.sizes["cycle"] + 1, dtype=np.int32))
    if sc.output.stresses and pb.pair is not None and results:
        # the bodies' stresses below the surface for the saved states (output/stresses.py)
        add_stress_fields(ds, summary, results, tangential or None, pb.grid, pb.pair,
                          depths=sc.output.stress_depths, summary_steps=indices)
    if sc.expected is not None:
        # The scenario's stated expectation beside the computed value (metadata: no effect on the
        # run; after the stresses, which it may name).
        summary["expected"] = compare_expected(summary, sc.expected.model_dump(),
                                               dimensions={**RUN_KINDS[sc.kind].result_keys(), **EXPECTED_KEYS})

    files = {}
    out_path = None
    if outdir is not None:

        out_path = Path(outdir)
        t_out = time.perf_counter()
        summary["timings"]["output"] = 0.0
        summary["timings"]["total"] = t_out - t0
        # Every file goes to a temporary file first and all move into place together at the
        # end: a Ctrl-C leaves the folder's previous complete files (or none), never a mix.
        with staged():
            kind = RUN_KINDS[sc.kind]
            files = write_outputs(out_path, summary, ds if keep != "none" else None,
                                  figures=sc.output.figures, report=sc.output.report,
                                  figure_sets=kind.figures, report_sections=kind.report_sections)
            summary["timings"]["output"] = time.perf_counter() - t_out
            summary["timings"]["total"] = time.perf_counter() - t0
            files["summary"] = write_summary(out_path / "summary.json", summary)
    else:
        summary["timings"]["total"] = time.perf_counter() - t0
    return RunResult(summary=summary, fields=ds, outdir=out_path, files=files, problem=pb,
                     results=results, curve=curve, tangential=tangential)
