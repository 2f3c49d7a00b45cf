"""Running a design study (:func:`run_design`) and the ``tribobem design FILE.toml`` command."""

from __future__ import annotations

import json
import sys
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from ..output.atomic import file_state, staged
from ..sweep import read_points, run_sweep
from ..sweep.command import default_outdir
from .chain import DesignPointRunner
from .report import write_design_report
from .spec import DesignSpec, load_design
from .table import design_table, rank_rows, write_table

__all__ = ["DesignResult", "run_design", "design_command"]

#: The files a design study writes besides the sweep's ``points/`` and ``design/`` records.
DESIGN_FILES = ("design.nc", "design.csv", "design_report.html")


@dataclass
class DesignResult:
    """What :func:`run_design` did.

    Attributes
    ----------
    outdir : Path
        The design folder.
    sweep : SweepResult
        The sweep's counts (points run, reused, failed; wall time in s).
    rows : list of dict
        The ranked design table (:func:`tribobem.design.table.rank_rows`), in sweep order.
    design_nc, design_csv, report : Path or None
        The files written.
    """

    outdir: Path
    sweep: Any
    rows: list = field(default_factory=list)
    design_nc: Path | None = None
    design_csv: Path | None = None
    report: Path | None = None

    @property
    def ranking(self) -> list[dict]:
        """The rows, best first."""
        return sorted(self.rows, key=lambda r: r["rank"])

    @property
    def exit_code(self) -> int:
        """0 when every point succeeded, 1 otherwise."""
        if self.sweep is not None:
            return self.sweep.exit_code
        return 0 if all(r["status"] == "ok" for r in self.rows) else 1

    def as_dict(self) -> dict:
        """Plain JSON types: the sweep's counts, the files, and the ranking (rank, point,
        status, targets met, distance, the SI values)."""
        from ..sweep.values import _jsonable

        keys = ("rank", "hash", "point", "status", "message", "targets_met", "n_targets", "distance",
                "static_friction_force", "static_friction_ratio", "presliding_displacement", "lateral_stiffness_A",
                "lateral_stiffness_B", "lateral_stiffness_C", "pull_off_force", "contact_area", "max_pressure",
                "peak_pressure", "repulsive_force", "capillary_force", "exceeds_hardness", "n_warnings")
        counts = self.sweep.as_dict() if self.sweep is not None else {"outdir": str(self.outdir)}
        return _jsonable({**counts, "design_nc": str(self.design_nc) if self.design_nc else None,
                          "design_csv": str(self.design_csv) if self.design_csv else None,
                          "report": str(self.report) if self.report else None,
                          "ranking": [{k: r.get(k) for k in keys} for r in self.ranking]})


def tabulate(design: DesignSpec, outdir, result=None) -> DesignResult:
    """Rank the finished points of a design folder and write the table and the report.

    Parameters
    ----------
    design : DesignSpec
        The design (its targets are read now: changed targets re-rank without recomputing).
    outdir : path
        The design folder.
    result : SweepResult, optional
        What the sweep did this time (for the report).

    Returns
    -------
    DesignResult
    """
    outdir = Path(outdir)
    sweep = design.sweep()
    tasks = sweep.tasks(_runner_name())
    rows = rank_rows(design_table(design, tasks, outdir, read_points(outdir)), design.targets)
    attrs = {"design": design.name, "description": design.description,
             "targets": json.dumps([t.label() for t in design.targets]),
             "chain": json.dumps(design.chain.as_dict())}
    with staged():  # the table and the report move into place together
        nc, csv_path = write_table(rows, outdir, attrs)
        report = write_design_report(outdir, design, rows, result)
    return DesignResult(outdir=outdir, sweep=result, rows=rows, design_nc=nc, design_csv=csv_path, report=report)


def _runner_name() -> str:
    """The runner name :func:`tribobem.sweep.run_sweep` gives :class:`DesignPointRunner`."""
    return f"callable:{DesignPointRunner.__module__}:{DesignPointRunner.__qualname__}"


def run_design(design, outdir, scheduler=None, n_workers: int | None = None, progress: bool = True,
               quiet: bool | None = None) -> DesignResult:
    """Run every design point without a successful record, then rank and report.

    Parameters
    ----------
    design : DesignSpec, mapping or path
        The design (:func:`~tribobem.design.spec.load_design`).
    outdir : path
        The design folder: ``points/<hash>.json`` (the sweep's records), ``design/<hash>.json``
        (each point's full result), ``sweep.json``, ``design.nc``, ``design.csv``,
        ``design_report.html``.
    scheduler : None, "synchronous", "local", address or distributed.Client
        As for :func:`tribobem.sweep.run_sweep` (default: the design file's, else a local
        cluster).
    n_workers : int, optional
        Local cluster size (default: the design file's, else min(2, cpus)).
    progress : bool
        Show progress on stderr: a live bar on a terminal, else one line per finished point.
    quiet : bool, optional
        No messages (default ``not progress``).

    Returns
    -------
    DesignResult

    Raises
    ------
    KeyboardInterrupt
        On Ctrl-C (every finished point is saved; the table and report are not updated).
    """
    design = load_design(design)
    outdir = Path(outdir)
    sweep = design.sweep()
    tasks = sweep.tasks(_runner_name())
    runner = DesignPointRunner(design.base, design.chain.as_dict(), tasks, outdir, design.base_dir)
    res = run_sweep(sweep, outdir, scheduler=scheduler or design.scheduler, n_workers=n_workers or design.workers,
                    progress=progress, func=runner, quiet=quiet, gather_results=False)
    out = tabulate(design, outdir, res)
    if not (quiet if quiet is not None else not progress):
        best = out.ranking[0] if out.rows else None
        line = f"design {design.name!r}: table {out.design_csv}, report {out.report}"
        if best is not None and best["status"] == "ok":
            line += (f"; best: {', '.join(f'{k} = {v}' for k, v in best['point'].items())} "
                     f"({best['targets_met']}/{best['n_targets']} targets met)")
        print(line, file=sys.stderr, flush=True)
    return out


def design_command(path, out=None, scheduler=None, workers=None, quiet=False, json_output=False) -> int:
    """Entry point for ``tribobem design DESIGN.toml`` (the CLI wires its options to these).

    Parameters
    ----------
    path : str
        The design file.
    out : str, optional
        Design folder (default ``results/<stem>`` in the current folder).
    scheduler : str, optional
        ``ADDRESS`` of a Dask scheduler, "local" (default) or "synchronous".
    workers : int, optional
        Local cluster size.
    quiet : bool
        No progress bar and no messages.
    json_output : bool
        Print the :class:`DesignResult` as JSON on stdout.

    Returns
    -------
    int
        0 when every point succeeded, 1 when some failed, 130 when interrupted (the finished
        points are kept; the same command computes the rest).
    """
    design = DesignSpec.from_file(path)
    outdir = Path(out) if out else default_outdir(path)
    before = [file_state(outdir / name) for name in DESIGN_FILES]
    try:
        res = run_design(design, outdir, scheduler=scheduler, n_workers=workers,
                         progress=not quiet and not json_output, quiet=quiet or json_output)
    except KeyboardInterrupt:
        records = read_points(outdir)
        tasks = design.sweep().tasks(_runner_name())
        saved = sum(1 for h, _ in tasks if records.get(h, {}).get("status") == "ok")
        after = [file_state(outdir / name) for name in DESIGN_FILES]
        files = ("the design table and report are the previous ones, not updated" if None not in before and
                 after == before else "the design table and report were not written" if None in after else
                 "the design table and report are the new ones")
        print(f"interrupted: {saved} of {len(tasks)} design points are saved in {outdir} ({files}); run the same "
              "command again to compute the rest", file=sys.stderr, flush=True)
        return 130
    if json_output:
        print(json.dumps(res.as_dict(), indent=1))
    return res.exit_code
