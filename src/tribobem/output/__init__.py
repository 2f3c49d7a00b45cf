"""Outputs of a run: summary.json, fields.nc, PNG figures and a self-contained report.html.

Every file is written atomically (a temporary file in the same folder, fsync, then
``os.replace``; :mod:`tribobem.output.atomic`), and the files of one result folder are moved
into place together (:func:`~tribobem.output.atomic.staged`), so an interrupted run leaves
the folder's previous complete files (or none), never a half-written or a mixed result.
"""

from pathlib import Path

from .atomic import staged
from .fields import build_fields, read_fields, representative_step, write_fields
from .figures import FIGURE_NAMES, make_figures
from .report import render_report, write_report
from .summary import REQUIRED_KEYS, STEP_KEYS, read_summary, versions, write_summary

__all__ = [
    "build_fields", "write_fields", "read_fields", "representative_step",
    "make_figures", "FIGURE_NAMES",
    "render_report", "write_report",
    "write_summary", "read_summary", "versions", "STEP_KEYS", "REQUIRED_KEYS",
    "write_outputs", "replot",
]


def write_outputs(outdir, summary: dict, ds=None, *, figures: bool = True, report: bool = True,
                  figure_sets=None, report_sections=None) -> dict:
    """Write fields.nc (if ``ds``), the figures, report.html and summary.json into ``outdir``,
    all moved into place together at the end (:func:`~tribobem.output.atomic.staged`).

    Parameters
    ----------
    outdir : path-like
        The result folder (created).
    summary : dict
        The run summary.
    ds : xarray.Dataset, optional
        The fields.
    figures, report : bool
        Whether to draw the figures and write report.html.
    figure_sets, report_sections : sequence of str, optional
        The run kind's figure sets and report sections (:data:`~tribobem.output.figures.FIGURE_SETS`,
        :data:`~tribobem.output.report.REPORT_SECTIONS`); default: all, each drawing what applies.

    Returns
    -------
    dict
        Name -> Path of every file written ("summary", "fields", "report", figure names).
    """
    outdir = Path(outdir)
    outdir.mkdir(parents=True, exist_ok=True)
    files = {}
    with staged():
        if ds is not None:
            files["fields"] = write_fields(ds, outdir / "fields.nc")
        figs = make_figures(ds, summary, outdir, sets=figure_sets) if figures else {}
        files.update(figs)
        if report:
            files["report"] = write_report(outdir, summary, figs, sections=report_sections)
        files["summary"] = write_summary(outdir / "summary.json", summary)
    return files


def replot(result_dir, figure_sets=None, report_sections=None) -> dict:
    """Re-make the figures and report.html of a result folder from its summary.json and
    fields.nc (fields.nc optional: without it only the figures drawn from the summary).

    Parameters
    ----------
    result_dir : path-like
        The result folder.
    figure_sets, report_sections : sequence of str, optional
        The run kind's (see :func:`write_outputs`); default: all, each drawing what applies.

    Returns
    -------
    dict
        Name -> Path of the files written (figures and "report").
    """
    result_dir = Path(result_dir)
    if not result_dir.is_dir():
        raise FileNotFoundError(f"result folder {result_dir} not found")
    summary = read_summary(result_dir / "summary.json")
    ds = read_fields(result_dir / "fields.nc") if (result_dir / "fields.nc").exists() else None

    with staged():
        figs = make_figures(ds, summary, result_dir, sets=figure_sets)
        files = dict(figs)
        files["report"] = write_report(result_dir, summary, figs, sections=report_sections)
    return files
