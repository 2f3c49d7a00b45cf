"""The ``tribobem sweep SWEEP.toml`` command: options, exit code, the Ctrl-C message."""

from __future__ import annotations

import json
import os
import sys
from pathlib import Path

from ..output.atomic import file_state
from .cache import read_points
from .execute import run_sweep
from .spec import SweepSpec

__all__ = ["sweep_command", "default_outdir", "interrupted_message"]


def default_outdir(path: str | os.PathLike) -> Path:
    """The default results folder of a sweep file.

    Parameters
    ----------
    path : path
        The sweep file.

    Returns
    -------
    Path
        ``results/<sweep file stem>``, relative to the current folder (like ``tribobem run``).
    """
    return Path("results") / Path(path).stem


def sweep_command(path, out=None, scheduler=None, workers=None, quiet=False, json_output=False) -> int:
    """Entry point for ``tribobem sweep SWEEP.toml`` (the CLI wires its options to these).

    Parameters
    ----------
    path : str
        The sweep file.
    out : str, optional
        Results folder (default ``results/<stem>`` in the current folder, as for ``tribobem run``).
    scheduler : str, optional
        ``ADDRESS`` of a Dask scheduler, "local" (default) or "synchronous"; default from
        the sweep file's ``scheduler`` key.
    workers : int, optional
        Local cluster size; default from the sweep file's ``workers`` key, else min(2, cpus).
    quiet : bool
        No progress bar and no messages.
    json_output : bool
        Print the :class:`SweepResult` as JSON on stdout.

    Returns
    -------
    int
        Exit code: 0 when every point succeeded, 1 when some failed, 130 when interrupted
        (Ctrl-C; the finished points are kept).
    """
    spec = SweepSpec.from_file(path)
    outdir = Path(out) if out else default_outdir(path)
    before = [file_state(outdir / name) for name in ("results.nc", "results.csv")]
    try:
        res = run_sweep(spec, outdir, scheduler=scheduler or spec.scheduler, n_workers=workers or spec.workers,
                        progress=not quiet and not json_output, quiet=quiet or json_output)
    except KeyboardInterrupt:
        print(interrupted_message(spec, outdir, before), file=sys.stderr, flush=True)
        return 130
    if json_output:
        print(json.dumps(res.as_dict(), indent=1))
    return res.exit_code


def interrupted_message(spec: SweepSpec, outdir: Path, before: list) -> str:
    """The one line ``tribobem sweep`` prints on Ctrl-C.

    Parameters
    ----------
    spec : SweepSpec
        The interrupted sweep.
    outdir : Path
        Its results folder.
    before : list
        The :func:`~tribobem.output.atomic.file_state` of results.nc and results.csv when the
        sweep started.

    Returns
    -------
    str
        How many points are saved (each point record is whole: written atomically, as soon as
        the point finished) and what became of results.nc / results.csv.
    """
    records = read_points(outdir)
    saved = sum(1 for h, _ in spec.tasks() if records.get(h, {}).get("status") == "ok")
    after = [file_state(outdir / name) for name in ("results.nc", "results.csv")]
    if after != before and None not in after:
        results = "results.nc and results.csv are the new complete ones"
    elif None in before:
        results = "results.nc and results.csv were not written"
    else:
        results = "results.nc and results.csv are the previous complete ones, not updated"
    rest = "run the same command again to compute the rest" if saved < len(spec) else "all points are done"
    return f"interrupted: {saved} of {len(spec)} points are saved in {outdir} ({results}); {rest}"
