"""The ``tribobem`` command line (Typer).

Commands: ``demo``, ``run SCENARIO.toml``, ``sweep SWEEP.toml``, ``design DESIGN.toml``, ``validate``, ``info TOPOGRAPHY``,
``plot RESULT``, ``compare-loop RESULT LOOP.csv``; ``tribobem --version``.
Errors in the user's input (bad scenario keys, units, ranges, unreadable files, grids too
large for memory) print one red line and exit with code 2, never a traceback.  Help is plain
text (every boolean option shows as a flag, ``--quiet / --no-quiet``); tables printed to a
pipe or a file are never truncated (see :func:`_stdout`).
"""

from __future__ import annotations

import json
import os
import signal
import sys
import threading
import tomllib
import warnings
from contextlib import contextmanager
from importlib import resources
from pathlib import Path
from typing import Optional

import typer
from rich.console import Console
from rich.markup import escape
from rich.table import Table

from .errors import ConvergenceWarning, InputError, MemoryBudgetError, ResultWarning, TopographyError

app = typer.Typer(
    name="tribobem",
    help="FFT-accelerated boundary-element contact mechanics: adhesive, frictional contact of rough surfaces.",
    no_args_is_help=True,
    add_completion=False,
    pretty_exceptions_enable=False,
    # Plain click help: Typer's Rich panels print a "<bool>" type beside every flag, which
    # reads as if the flag took a value; the plain form shows "-q, --quiet / --no-quiet".
    rich_markup_mode=None,
)

#: Exit code of input errors (bad scenario, unreadable file, grid too large).
EXIT_INPUT = 2
#: Exit code of ``validate`` when a case fails.
EXIT_FAILED = 1
#: Exit code after Ctrl-C (SIGINT): 128 + 2, as a shell reports an interrupted command.
EXIT_INTERRUPTED = 130


def package_version() -> str:
    """The installed package version (the distribution's metadata, else ``tribobem.__version__``)."""
    try:
        from importlib.metadata import PackageNotFoundError, version

        return version("tribobem")
    except (ImportError, PackageNotFoundError):  # pragma: no cover - run from a source tree
        from ._version import __version__

        return __version__


def _print_version(value: bool) -> None:
    if value:
        from ._solver_version import SOLVER_VERSION

        _stdout().print(f"tribobem {package_version()} (solver version {SOLVER_VERSION})")
        raise typer.Exit()


@app.callback()
def _main(
    version: bool = typer.Option(False, "--version", callback=_print_version, is_eager=True,
                                 help="Print the package version and the solver version, and exit."),
):
    """FFT-accelerated boundary-element contact mechanics: adhesive, frictional contact of rough surfaces."""


#: Console width when stdout is not a terminal (a pipe, a file, a CI log): Rich would fall back to
#: 80 columns (or $COLUMNS) and cut table cells with an ellipsis; a table is only as wide as its
#: content, so a wide console prints every cell whole.
PIPE_WIDTH = 10_000


def _stdout() -> Console:
    """The stdout console: the terminal's width on a terminal, :data:`PIPE_WIDTH` otherwise."""
    console = Console(highlight=False, soft_wrap=True)
    if not console.is_terminal:
        console = Console(highlight=False, soft_wrap=True, width=PIPE_WIDTH)
    return console


def _stderr() -> Console:
    return Console(stderr=True, highlight=False, soft_wrap=True)


@contextmanager
def _user_errors(source: Path | str | None = None):
    """Turn input errors into one red line on stderr and exit code 2.

    ``source``: the file the command read (a scenario, a sweep or design file), named at the
    end of the line unless the message already names it."""
    try:
        yield
    except typer.Exit:
        raise
    except (InputError, TopographyError, MemoryBudgetError, FileNotFoundError, tomllib.TOMLDecodeError,
            NotImplementedError, PermissionError, IsADirectoryError) as exc:
        text = str(exc) if not isinstance(exc, FileNotFoundError) or not exc.filename else f"{exc.strerror}: {exc.filename}"
        text = " ".join(str(text).split())
        if source is not None and str(source) not in text:
            text = f"{text} ({source})"
        _stderr().print(f"[bold red]error:[/bold red] [red]{escape(text)}[/red]")
        raise typer.Exit(EXIT_INPUT) from None


@contextmanager
def _interrupts(outdir: Path, what: str):
    """Ctrl-C: one line on stderr that says what the result folder holds, and exit code 130.

    The files of a result folder are written to temporary files and moved into place
    together (:func:`tribobem.output.atomic.staged`), so the folder holds either its previous
    complete outputs (or none) or the new complete ones; which one is read off summary.json
    (a new one is a new file: ``os.replace``)."""
    from .output.atomic import file_state

    summary = Path(outdir) / "summary.json"
    before = file_state(summary)
    # A Ctrl-C that lands in a weakref callback or a __del__ is printed and dropped by Python
    # ("Exception ignored in ..."), and the run would go on as if never interrupted: record every
    # SIGINT, keep such a drop quiet, and treat the run as interrupted when it returns.
    seen: list = []

    def on_sigint(signum, frame):
        seen.append(signum)
        raise KeyboardInterrupt

    def unraisable(info, previous=sys.unraisablehook):
        if not isinstance(info.exc_value, KeyboardInterrupt):
            previous(info)

    restore = None
    if threading.current_thread() is threading.main_thread():
        restore = (signal.signal(signal.SIGINT, on_sigint), sys.unraisablehook)
        sys.unraisablehook = unraisable
    try:
        yield
        if seen:
            raise KeyboardInterrupt
    except KeyboardInterrupt:
        after = file_state(summary)
        if after is not None and after != before:
            state = f"outputs in {outdir} are the new complete ones (written before the interrupt)"
        elif before is not None:
            state = f"outputs in {outdir} are the previous complete ones"
        else:
            state = f"outputs in {outdir} were not written"
        _stderr().print(f"[bold yellow]interrupted:[/bold yellow] {escape(what)} stopped by Ctrl-C; {escape(state)}")
        raise typer.Exit(EXIT_INTERRUPTED) from None
    finally:
        if restore is not None:
            signal.signal(signal.SIGINT, restore[0])
            sys.unraisablehook = restore[1]


def _warn_nonconverged(summary: dict, quiet: bool) -> None:
    if not summary.get("converged"):
        bad = sum(1 for s in summary.get("steps", []) if not s.get("converged"))
        _stderr().print(f"[bold yellow]warning:[/bold yellow] {bad} of {len(summary.get('steps', []))} step(s) did "
                        "not converge; see summary.json and the report")


#: Header label and dimension of each step key a run kind's step table may show
#: (:attr:`tribobem.runs.kind.RunKind.columns`).
_STEP_COLUMN_LABELS = {
    "rh": ("RH", "dimensionless"), "normal_force": ("F", "force"), "approach": ("\u03b4", "length"),
    "tangential_force_x": ("F_x", "force"), "displacement_x": ("\u03b4_x", "length"),
    "contact_area": ("A_c", "area"), "adhesive_area": ("A_adh", "area"), "stick_ratio": ("A_st/A_c", "dimensionless"),
    "max_pressure": ("p_max", "pressure"), "capillary_force": ("F_cap", "force"),
    "solid_solid_force": ("F_ss", "force"), "water_solid_force": ("F_ws", "force"), "wetted_area": ("A_men", "area"),
    "island_count": ("islands", "dimensionless"),
    "plastic_area": ("A_pl", "area"),
}


def _step_table_columns(summary: dict) -> tuple:
    """(key, label, dimension) of the step table's columns: those the run kind declares for a run
    with or without ``[humidity]`` (:meth:`~tribobem.runs.kind.RunKind.step_columns`); a kind
    this version does not know (a result folder of another version): the normal-load columns."""
    from .output.run_kind import run_view
    from .runs import KINDS
    from .runs.kind import NORMAL_COLUMNS

    view = run_view(summary)
    kind = KINDS.get(view.kind)
    keys = kind.step_columns(view.humid) if kind is not None else NORMAL_COLUMNS
    if any("plastic_area" in s for s in summary.get("steps", [])):
        keys = tuple(keys) + ("plastic_area",)  # a hardness cap: the plastic nodes of each state
    return tuple((key, *_STEP_COLUMN_LABELS[key]) for key in keys)


def _print_summary(summary: dict, outdir: Path | None, console: Console) -> None:
    from .output.run_kind import run_view
    from .units import display_unit, format_quantity

    steps = summary.get("steps", [])
    view = run_view(summary)
    table = Table(title=f"tribobem {summary.get('kind')} run", show_lines=False, pad_edge=False)
    cols = _step_table_columns(summary)
    scales = {}
    for key, label, dim in cols:
        vals = [s.get(key) for s in steps if s.get(key) is not None]
        scales[key] = display_unit(vals, dim)
    table.add_column("#", justify="right")
    table.add_column("branch", justify="left")
    for key, label, dim in cols:
        table.add_column(f"{label} ({scales[key][1]})" if scales[key][1] else label, justify="right")
    # Round-off (e.g. a tangential force of 1e-22 N at F_x = 0) prints as 0.
    tiny = {key: 1e-9 * max((abs(s.get(key)) for s in steps if isinstance(s.get(key), (int, float))), default=0.0)
            for key, _, _ in cols}
    table.add_column("iter", justify="right")
    table.add_column("ok", justify="center")
    # At most 30 rows on the terminal; a cut says how many rows it hides (all are in summary.json).
    hidden = max(len(steps) - 30, 0)
    show = steps if not hidden else steps[:15] + [None] + steps[-15:]
    for s in show:
        if s is None:
            table.add_row("...", f"[dim]{hidden} hidden[/dim]", *(["..."] * len(cols)), "", "")
            continue
        cells = []
        for key, _, _ in cols:
            v = s.get(key)
            if isinstance(v, (int, float)) and abs(v) <= tiny[key]:
                v = 0.0
            cells.append("-" if v is None else f"{v / scales[key][0]:.4g}")
        branch = {"loading": "load", "unloading": "unload"}.get(s.get("branch"), str(s.get("branch", "")))
        table.add_row(str(s.get("index", "")), branch, *cells, str(s.get("iterations", "")),
                      "yes" if s.get("converged") else "[red]NO[/red]")
    console.print(table)
    if hidden:
        console.print(f"{hidden} of {len(steps)} steps hidden above; summary.json and the report have every step")
    if summary.get("friction_coefficient") is not None:
        mu = summary["friction_coefficient"]
        if view.humid_friction:  # the run-level values are per RH
            _print_humid_friction(summary, console)
        elif summary.get("static_friction_force") is not None:
            console.print("gross-slip onset (static friction): "
                          f"[bold]{format_quantity(summary['static_friction_force'], 'force', 4)}"
                          f"[/bold] = {summary['static_friction_ratio']:.4f} \u03bc F0+ (\u03bc = {mu:g}); pre-sliding "
                          f"displacement {format_quantity(summary.get('presliding_displacement'), 'length', 4)}")
        elif summary.get("gross_slip") is False:
            console.print(f"no gross slip along the ramp (\u03bc = {mu:g}); the largest step keeps a stick zone "
                          "(the warning below says where gross slip sets in)")
        if not view.humid_friction:
            _print_loop(summary, console)
    if view.humid_pulloff:  # one pull-off force per RH: the run's lists, else the steps' (one per RH)
        pairs = (list(zip(summary["pull_off_force"], summary["rh"]))
                 if isinstance(summary.get("rh"), list) and isinstance(summary.get("pull_off_force"), list)
                 else [(s.get("pull_off_force"), s.get("rh")) for s in steps if s.get("rh") is not None])
        console.print("pull-off force: " + ", ".join(
            f"[bold]{format_quantity(f, 'force', 4)}[/bold] at RH {rh:g}" for f, rh in pairs))
    elif summary.get("pull_off_force") is not None:
        console.print(f"pull-off force: [bold]{format_quantity(summary['pull_off_force'], 'force', 4)}[/bold] "
                      f"at approach {format_quantity(summary.get('pull_off_approach'), 'length', 4)}")
    levels = summary.get("grid_levels")
    if isinstance(levels, dict) and levels.get("levels"):
        change = levels.get("change")
        console.print("grid levels: " + ", ".join(
            f"{lv['n']}^2 {format_quantity(lv['pull_off_force'], 'force', 4)}" for lv in levels["levels"])
            + (f"; change between the last two {100 * change:+.1f} %" if change is not None else ""))
    prob = summary.get("problem", {})
    if prob.get("tabor_parameter") is not None:
        maugis = prob.get("maugis_parameter")
        console.print(f"Tabor parameter {prob['tabor_parameter']:.3g}"
                      + (f", Maugis parameter {maugis:.3g}" if maugis is not None else ""))
    for w in summary.get("warnings") or []:
        console.print(f"[bold yellow]warning:[/bold yellow] {escape(str(w))}")
    _print_expected(summary.get("expected"), console)
    t = summary.get("timings", {})
    if t:
        console.print(f"time: {t.get('total', 0):.1f} s (solve {t.get('solve', 0):.1f} s)")
    if outdir is not None:
        report = Path(outdir) / "report.html"
        console.print(f"results in [bold]{escape(str(outdir))}[/bold]"
                      + (f"; report: [bold]{escape(str(report))}[/bold]" if report.exists() else ""))


def _print_loop(summary: dict, console: Console) -> None:
    """A hysteresis run's loop energy per cycle and K_L at Paper F's points A, B, C."""
    from .units import format_quantity

    energy = [e for e in (summary.get("dissipated_energy") or []) if isinstance(e, (int, float))]
    if energy:
        console.print("loop energy per cycle: " + ", ".join(
            f"[bold]{format_quantity(e, 'energy', 4)}[/bold]" for e in energy))
    table = [t for t in (summary.get("lateral_stiffness") or []) if isinstance(t, dict)]
    if table:
        console.print("lateral stiffness K_L (last rising branch): " + ", ".join(
            f"{t.get('point')} [bold]{_stiffness(t.get('stiffness'))}[/bold]" for t in table))
    elif summary.get("lateral_stiffness_error"):
        console.print(f"lateral stiffness K_L: not computed ({escape(str(summary['lateral_stiffness_error']))})")


def _print_humid_friction(summary: dict, console: Console) -> None:
    """One line per RH (and the dry reference first) of a humid friction run: the static friction
    force and ratio, the presliding displacement (partial_slip) or the sliding force and the last
    cycle's dissipated energy (hysteresis).  The run-level values are lists in RH order there."""
    from .units import format_quantity

    def at(key, i):
        v = summary.get(key)
        return v[i] if isinstance(v, list) and i < len(v) else None

    def line(label, get):
        parts = []
        sff = get("static_friction_force")
        if sff is not None:
            ratio = get("static_friction_ratio")
            parts.append(f"static friction [bold]{format_quantity(sff, 'force', 4)}[/bold]"
                         + (f" = {ratio:.4f} \u03bc F0+" if isinstance(ratio, (int, float)) else ""))
        else:
            parts.append("no gross slip")
        if get("presliding_displacement") is not None:
            parts.append(f"pre-sliding {format_quantity(get('presliding_displacement'), 'length', 4)}")
        if get("sliding_force") is not None:
            parts.append(f"sliding force {format_quantity(get('sliding_force'), 'force', 4)}")
        energy = get("dissipated_energy")
        if isinstance(energy, list) and energy and energy[-1] is not None:
            parts.append(f"dissipated energy (last cycle) {format_quantity(energy[-1], 'energy', 4)}")
        console.print(f"{label}: " + ", ".join(parts))

    dry = summary.get("dry") or {}
    console.print(f"humid friction (\u03bc = {summary['friction_coefficient']:g}), per RH:")
    if dry:
        line("  dry reference", dry.get)
    for i, rh in enumerate(summary["rh"]):
        line(f"  RH {100 * float(rh):.3g} %", lambda key, i=i: at(key, i))


def _print_expected(exp: dict | None, console: Console) -> None:
    """``expected: met`` / ``not met`` with each value computed against expected (the scenario's
    ``expected`` table; nothing without one)."""
    if not exp:
        return
    head = "[bold green]met[/bold green]" if exp.get("met") else "[bold red]not met[/bold red]"
    parts = []
    for r in exp.get("values") or []:
        got = "not computed" if r.get("computed") is None else f"{r['computed']:.6g}"
        err = "" if r.get("relative_error") is None else f", {100 * r['relative_error']:.2f} %"
        parts.append(f"{r['key']} = {got} against {r['expected']:.6g}{err}")
    for w in exp.get("warnings") or []:
        parts.append(f"warning {w['name']} {'raised' if w.get('present') else 'NOT raised'}")
    tol = exp.get("tolerance")
    tol_text = f" within {100 * tol:g} %" if tol is not None else ""
    console.print(f"expected{tol_text} ({escape(str(exp.get('reference') or ''))}): {head}; " + escape("; ".join(parts)))


def _run(scenario, out: Path, quiet: bool, as_json: bool, base_dir=None) -> dict:
    from .scenario import run_scenario

    with warnings.catch_warnings():
        # printed below from the summary, in every output mode: not twice
        warnings.simplefilter("ignore", ConvergenceWarning)
        warnings.simplefilter("ignore", ResultWarning)
        result = run_scenario(scenario, outdir=out, progress=not (quiet or as_json), quiet=quiet or as_json,
                              base_dir=base_dir)
    summary = result.summary
    if as_json:
        from .output.summary import jsonable

        sys.stdout.write(json.dumps(jsonable(summary), indent=2) + "\n")
    elif not quiet:
        _print_summary(summary, out, _stdout())
    else:
        _stdout().print(str(Path(out) / "report.html") if (Path(out) / "report.html").exists() else str(out))
    if quiet or as_json:
        # --quiet and --json hide the progress and the tables, never what the user must read: the
        # warnings and the expected line go to stderr (stdout stays the path, or the JSON).
        _print_notices(summary, _stderr())
    _warn_nonconverged(summary, quiet)
    return summary


def _print_notices(summary: dict, console: Console) -> None:
    """The run's warnings and its expected line (what every output mode prints)."""
    for w in summary.get("warnings") or []:
        console.print(f"[bold yellow]warning:[/bold yellow] {escape(str(w))}")
    _print_expected(summary.get("expected"), console)


# ----------------------------------------------------------------------------- demo
def demo_scenario(small: bool = False) -> tuple[dict, str]:
    """The embedded demo scenario (dict) and a one-line description of it.

    A rigid sphere (R = 1 um) brought into contact with a compliant flat (E* = 5 GPa) at zero
    external load and pulled off, with Dugdale adhesion (Maugis parameter 1.07), on a grid that
    resolves the cohesive zone (about 10 cells across at pull-off), so that the pull-off can be
    checked against Maugis-Dugdale (the scenario's ``expected``).  It needs no input files.
    (The measured Park AFM scan cannot resolve a cohesive zone: its Dugdale range is a fraction
    of a pixel; see examples/pulloff_afm_park.toml.)
    """
    text = resources.files("tribobem").joinpath("data", "demo.toml").read_text(encoding="utf-8")
    sc = tomllib.loads(text)
    where = "smooth sphere, no input files, checked against Maugis-Dugdale"
    if small:  # tests: a tiny, fast version of the same job (not resolved: it says so)
        sc["grid"]["n"] = 32
        sc["load"]["steps"] = 10
        sc["load"]["refine"] = 2
    return sc, where


@app.command()
def demo(
    out: Path = typer.Option(Path("tribobem_demo"), "--out", "-o", help="Result folder."),
    quiet: bool = typer.Option(False, "--quiet", "-q", help="No progress bar or tables; print the report path "
                                                            "and the pull-off."),
    as_json: bool = typer.Option(False, "--json", help="Print summary.json to stdout."),
    small: bool = typer.Option(False, "--small", hidden=True, help="Tiny grid (tests)."),
):
    """Run the built-in demo: an adhesive sphere pulled off a flat, checked against Maugis-Dugdale."""
    with _user_errors():
        if os.environ.get("TRIBOBEM_DEMO_SMALL"):
            small = True
        sc, where = demo_scenario(small)
        if not (quiet or as_json):
            _stdout().print("[bold]tribobem demo[/bold]: rigid sphere (R = 1 µm) on a compliant flat (E* = 5 GPa), "
                            f"Dugdale adhesion; {escape(where)}")
        with _interrupts(out, "tribobem demo"):
            summary = _run(sc, out, quiet, as_json, base_dir=Path.cwd())
        if not as_json:
            from .output.checks import pull_off_statement

            # the key result and whether the grid backs it, in one line
            _stdout().print(escape(pull_off_statement(summary)))


# ----------------------------------------------------------------------------- run
@app.command()
def run(
    scenario: Path = typer.Argument(..., help="Scenario file (TOML)."),
    out: Optional[Path] = typer.Option(None, "--out", "-o", help="Result folder (default: results/<scenario name>)."),
    quiet: bool = typer.Option(False, "--quiet/--no-quiet", "-q", help="No progress bar or tables."),
    as_json: bool = typer.Option(False, "--json/--no-json", help="Print summary.json to stdout."),
):
    """Run a scenario file and write summary.json, fields.nc, figures and report.html."""
    with _user_errors(scenario):
        if not scenario.exists():
            raise FileNotFoundError(f"scenario file {scenario} not found")
        outdir = out if out is not None else Path("results") / scenario.stem
        with _interrupts(outdir, "tribobem run"):
            _run(scenario, outdir, quiet, as_json)


# ----------------------------------------------------------------------------- sweep
@app.command()
def sweep(
    sweep_file: Path = typer.Argument(..., help="Sweep file (TOML): a base scenario and a grid of parameters."),
    out: Optional[Path] = typer.Option(None, "--out", "-o", help="Results folder (default: results/<stem>)."),
    scheduler: Optional[str] = typer.Option(None, "--scheduler", help="Dask scheduler ADDRESS, 'local' or 'synchronous'."),
    workers: Optional[int] = typer.Option(None, "--workers", help="Workers of the local cluster."),
    quiet: bool = typer.Option(False, "--quiet/--no-quiet", "-q", help="No progress bar or messages."),
    as_json: bool = typer.Option(False, "--json/--no-json", help="Print the sweep result as JSON."),
):
    """Run a scenario over a grid of parameters (Dask; resumable: finished points are kept)."""
    with _user_errors(sweep_file):
        from .sweep import sweep_command

        if not sweep_file.exists():
            raise FileNotFoundError(f"sweep file {sweep_file} not found")
        try:  # a Ctrl-C while the sweep runs: sweep_command says what is saved and returns 130
            code = sweep_command(str(sweep_file), out=str(out) if out else None, scheduler=scheduler,
                                 workers=workers, quiet=quiet, json_output=as_json)
        except KeyboardInterrupt:  # before the sweep started, or a second Ctrl-C
            _stderr().print("[bold yellow]interrupted:[/bold yellow] tribobem sweep stopped by Ctrl-C; the points "
                            "finished so far are saved; run the same command again to compute the rest")
            code = EXIT_INTERRUPTED
    if code:
        raise typer.Exit(code)


# ----------------------------------------------------------------------------- design
@app.command()
def design(
    design_file: Path = typer.Argument(..., help="Design file (TOML): a base scenario, design parameters, chain "
                                                 "options and targets."),
    out: Optional[Path] = typer.Option(None, "--out", "-o", help="Results folder (default: results/<stem>)."),
    scheduler: Optional[str] = typer.Option(None, "--scheduler", help="Dask scheduler ADDRESS, 'local' or 'synchronous'."),
    workers: Optional[int] = typer.Option(None, "--workers", help="Workers of the local cluster."),
    quiet: bool = typer.Option(False, "--quiet/--no-quiet", "-q", help="No progress bar or messages."),
    as_json: bool = typer.Option(False, "--json/--no-json", help="Print the design result and ranking as JSON."),
):
    """Rank design variants: normal, pull-off, tangential ramp (and hysteresis) per point; table and report."""
    with _user_errors(design_file):
        from .design.command import design_command

        if not design_file.exists():
            raise FileNotFoundError(f"design file {design_file} not found")
        try:  # a Ctrl-C while the points run: design_command says what is saved and returns 130
            code = design_command(str(design_file), out=str(out) if out else None, scheduler=scheduler,
                                  workers=workers, quiet=quiet, json_output=as_json)
        except KeyboardInterrupt:  # before the sweep started, or a second Ctrl-C
            _stderr().print("[bold yellow]interrupted:[/bold yellow] tribobem design stopped by Ctrl-C; the points "
                            "finished so far are saved; run the same command again to compute the rest")
            code = EXIT_INTERRUPTED
    if code:
        raise typer.Exit(code)


# ----------------------------------------------------------------------------- validate
@app.command()
def validate(
    quick: bool = typer.Option(True, "--quick/--full", help="Quick (small grids) or full validation."),
    ci: bool = typer.Option(False, "--ci/--no-ci", help="The CI gating tier instead (overrides --quick/--full): "
                                                         "the cases that protect published numbers, at a "
                                                         "resolution that fits about 5 minutes per physics on "
                                                         "2 cores."),
    physics: Optional[list[str]] = typer.Option(None, "--physics", help="Run only the cases of this physics "
                                                                         "(repeatable): normal, adhesion, "
                                                                         "tangential, ..."),
    as_json: bool = typer.Option(False, "--json/--no-json", help="Print the rows as JSON."),
    case: Optional[list[str]] = typer.Option(None, "--case", help="Run only these cases (repeatable)."),
    quiet: bool = typer.Option(False, "--quiet/--no-quiet", "-q", help="No spinner."),
):
    """Run the analytic validation cases and print a table of errors (exit 1 if any fails)."""
    import time

    with _user_errors():
        try:
            from .validation import run_validation
        except ImportError as exc:
            raise InputError("validate", f"the validation module is not available: {exc}") from None
        level = "ci" if ci else ("quick" if quick else "full")
        console = _stdout()
        t0, c0 = time.perf_counter(), time.process_time()
        kw = {"level": level, "cases": case or None, "physics": physics or None}
        if as_json or quiet:
            rows = run_validation(**kw)
        else:
            what = f"{level} validation cases" + (f" of {', '.join(physics)}" if physics else "")
            with _stderr().status(f"running the {what} ..."):
                rows = run_validation(**kw)
        wall, cpu = time.perf_counter() - t0, time.process_time() - c0
        records = [_row_dict(r) for r in rows]
        failed = [r for r in records if not r["passed"]]
        if as_json:
            from .output.summary import jsonable

            sys.stdout.write(json.dumps(jsonable({"quick": level == "quick", "level": level, "physics": physics or None,
                                                  "passed": not failed, "wall_time": wall, "cpu_time": cpu,
                                                  "rows": records}), indent=2) + "\n")
        else:
            table = Table(title=f"tribobem validation ({level}"
                                + (f": {', '.join(physics)}" if physics else "") + ")")
            for col, just in (("case", "left"), ("quantity", "left"), ("reference", "right"), ("computed", "right"),
                              ("rel. error", "right"), ("tolerance", "right"), ("", "center")):
                table.add_column(col, justify=just)
            for r in records:
                table.add_row(str(r["case"]), str(r["quantity"]), _g(r["reference"]), _g(r["computed"]),
                              _g(r["rel_error"], ".2e"), _g(r["tolerance"], ".1e"),
                              "[green]pass[/green]" if r["passed"] else "[bold red]FAIL[/bold red]")
            console.print(table)
            console.print(f"{len(records) - len(failed)} of {len(records)} checks passed"
                          + (f"; [bold red]{len(failed)} failed[/bold red]" if failed else "")
                          + f" ({wall:.0f} s, CPU {cpu:.0f} s)")
        if failed:
            raise typer.Exit(EXIT_FAILED)


def _row_dict(row) -> dict:
    if isinstance(row, dict):
        d = dict(row)
    elif hasattr(row, "_asdict"):
        d = row._asdict()
    elif hasattr(row, "__dataclass_fields__"):
        from dataclasses import asdict

        d = asdict(row)
    else:
        d = {k: getattr(row, k) for k in ("case", "quantity", "reference", "computed", "rel_error", "tolerance", "passed")}
    d["passed"] = bool(d.get("passed"))
    return d


def _g(v, fmt: str = ".5g") -> str:
    try:
        return format(float(v), fmt)
    except (TypeError, ValueError):
        return str(v)


# ----------------------------------------------------------------------------- info
@app.command()
def info(
    topography: Path = typer.Argument(..., help="Topography file (AFM, confocal, .x3p, .npy, text, ...), or "
                                                "data:NAME for a measured file shipped with tribobem "
                                                "(e.g. data:example_ps.tiff; folder: $TRIBOBEM_DATA_DIR if set)."),
    as_json: bool = typer.Option(False, "--json/--no-json", help="Print the statistics as JSON."),
    channel: Optional[str] = typer.Option(None, "--channel", help="Channel name or index."),
    detrend: str = typer.Option("height", "--detrend", help="height (the least-squares plane, the default) | "
                                                              "center (the mean only) | curvature | none"),
    unit: Optional[str] = typer.Option(None, "--unit", help="Length unit of the heights, for files that do not "
                                                              "store one (.npy, text), e.g. nm."),
    size: Optional[str] = typer.Option(None, "--size", help="Physical size of the scan, for files that do not store "
                                                              "it (.npy, text): 'L' (square) or 'LX,LY', with units, "
                                                              "e.g. '10 um' or '10 um,5 um'."),
    plot: bool = typer.Option(False, "--plot/--no-plot", help="Also write PNGs of the height map, height "
                                                               "distribution, PSD and ACF, and an HTML page of them."),
    out: Optional[Path] = typer.Option(None, "--out", "-o", help="Folder of the --plot files (default: "
                                                                 "results/topography_<file stem>; implies --plot)."),
):
    """Read a measured topography and print its size and statistics (SI after detrending)."""
    with _user_errors():
        from .data import DATA_PREFIX, topography_path
        from .units import format_quantity

        if str(topography).startswith(DATA_PREFIX):
            topography = topography_path(str(topography))
        if not topography.exists():
            raise FileNotFoundError(f"topography file {topography} not found")
        ch = int(channel) if channel is not None and channel.isdigit() else channel
        topo = _read_for_info(topography, ch, detrend, unit, _parse_size(size))
        st = topo.stats()
        g = topo.grid
        note = _correlation_note(topo, detrend, st)
        record = {
            "path": str(topography),
            "format": topo.info.get("format", ""),
            "instrument": topo.info.get("instrument", ""),
            "channel": topo.info.get("channel", ""),
            "channels": topo.info.get("channels", []),
            "grid": [g.nx, g.ny],
            "physical_size": [g.lx, g.ly],
            "pixel_size": [g.dx, g.dy],
            "unit": topo.info.get("original_unit", ""),
            "detrend": detrend,
            "filled_points": topo.info.get("filled_points", 0),
            **{k: v for k, v in st.items()},
        }
        if note:
            record["correlation_length_note"] = note
        plots = {}
        if plot or out is not None:
            from .output.topography import write_topography_plots

            outdir = out if out is not None else Path("results") / f"topography_{topography.stem}"
            plots = write_topography_plots(topo.heights, g, outdir, title=topography.name, detrend=detrend)
            record["plots"] = {k: str(v) for k, v in plots.items()}
        if as_json:
            from .output.summary import jsonable

            sys.stdout.write(json.dumps(jsonable(record), indent=2) + "\n")
            return
        table = Table(title=f"{topography.name}", show_header=False)
        table.add_column("", justify="left", style="bold")
        table.add_column("", justify="left")
        corr = st.get("correlation_length")
        rows = [
            ("format", f"{record['format']} {('(' + record['instrument'] + ')') if record['instrument'] else ''}".strip()),
            ("channel", f"{record['channel']} (of {len(record['channels'])})"),
            ("grid", f"{g.nx} x {g.ny} points"),
            ("physical size", f"{format_quantity(g.lx, 'length')} x {format_quantity(g.ly, 'length')}"),
            ("pixel size", f"{format_quantity(g.dx, 'length')} x {format_quantity(g.dy, 'length')}"),
            ("unit in file", str(record["unit"])),
            ("detrend", detrend),
            ("rms height", format_quantity(st.get("rms_height"), "length")),
            ("rms slope", f"{st.get('rms_slope', float('nan')):.4g}"),
            ("rms curvature", f"{st.get('rms_curvature', float('nan')):.4g} 1/m"),
            ("skewness", f"{st.get('skewness', float('nan')):.4g}"),
            ("kurtosis", f"{st.get('kurtosis', float('nan')):.4g}"),
            ("correlation length (ACF 10 %)", format_quantity(corr, "length") if corr == corr
             else "nan (see the note below)"),
            ("peak to valley", format_quantity(st.get("peak_to_valley"), "length")),
        ]
        if record["filled_points"]:
            rows.append(("filled points", str(record["filled_points"])))
        for a, b in rows:
            table.add_row(a, escape(b))
        console = _stdout()
        console.print(table)
        if note:
            console.print(f"[bold yellow]note:[/bold yellow] {escape(note)}")
        for name, path in plots.items():
            console.print(f"{name}: {escape(str(path))}")


def _parse_size(size: str | None) -> tuple[float, float] | None:
    """``--size``: 'L' or 'LX,LY' (lengths with units) -> (lx, ly) in m."""
    if size is None:
        return None
    from .units import to_si

    parts = [s.strip() for s in size.replace(";", ",").split(",") if s.strip()]
    if len(parts) not in (1, 2):
        raise InputError("info.size", f"give one length (square scan) or two separated by a comma, e.g. "
                                      f"'10 um' or '10 um,5 um'; got {size!r}")
    sizes = []
    for s in parts:
        if not any(c.isalpha() for c in s):
            raise InputError("info.size", f"{s!r} has no unit; write it with one, e.g. '{s} um'")
        v = to_si(s, "length", "info.size")
        if not (v > 0 and v != float("inf")):
            raise InputError("info.size", f"must be a finite length > 0, got {s!r}")
        sizes.append(v)
    return (sizes[0], sizes[-1])


def _read_for_info(path: Path, channel, detrend: str, unit: str | None, size_m: tuple[float, float] | None):
    """Read a topography for ``info``, with ``--size`` in SI and the CLI's names in the errors."""
    from .geometry import read_topography

    def read(size):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            try:
                return read_topography(path, channel=channel, detrend=detrend, unit=unit, size=size)
            except TopographyError as exc:
                if exc.field == "topography.physical_sizes":
                    raise TopographyError(exc.field, f"{str(exc).split(': ', 1)[-1].rstrip('. ')}; give the scan's size with "
                                          "--size, e.g. --size '10 um' (square) or --size '10 um,5 um'") from None
                if exc.field == "topography.unit":
                    raise TopographyError(exc.field, f"{path} does not say the length unit of its heights; give "
                                          "it with --unit, e.g. --unit nm") from None
                raise

    return read(size_m)


def _correlation_note(topo, detrend: str, stats: dict) -> str | None:
    """Why the correlation length is NaN, and which ``--detrend`` gives one (None if finite)."""
    corr = stats.get("correlation_length")
    if corr is not None and corr == corr:
        return None
    import numpy as np

    from .geometry.stats import correlation_length
    from .geometry.topography import DETREND_MODES, detrend_heights
    from .units import format_quantity

    g = topo.grid
    if not stats.get("rms_height"):
        return "correlation length nan: the surface is flat (rms height 0) after detrending"
    half = format_quantity(min(g.lx, g.ly) / 2, "length")
    # the trends --detrend {detrend} leaves in the heights
    left = {"none": "offset, tilt, curvature", "center": "tilt, curvature"}.get(detrend, "curvature")
    reason = (f"correlation length nan: the height autocorrelation does not fall below 10 % of its peak within "
              f"half the scan ({half}); with --detrend {detrend} the heights are dominated by a trend ({left}) "
              "or by wavelengths longer than the scan")
    # Stronger detrending removes more of the trend: try the modes after the current one.
    order = list(DETREND_MODES)
    later = order[order.index(detrend) + 1:] if detrend in order else order
    rms = float(stats["rms_height"])
    for mode in later:
        h = detrend_heights(topo.heights, g, mode)
        if float(np.sqrt(np.mean(h**2))) <= 1e-9 * rms:
            return f"{reason}. The heights are a pure trend: with --detrend {mode} nothing is left"
        c = correlation_length(h, g)
        if c == c:
            return f"{reason}. Change the detrending: with --detrend {mode} it is {format_quantity(c, 'length')}"
    return (f"{reason}. Change the detrending (--detrend height or curvature); here none gives one, so the "
            "scan is shorter than about two correlation lengths: use a larger scan")


# ----------------------------------------------------------------------------- plot
@app.command()
def plot(
    result: Path = typer.Argument(..., help="Result folder (with summary.json and fields.nc)."),
    quiet: bool = typer.Option(False, "--quiet/--no-quiet", "-q", help="Print nothing but errors."),
):
    """Re-make the figures and report.html of a result folder from its files."""
    with _user_errors():
        from .output import read_summary, replot
        from .runs import KINDS

        if not result.exists():
            raise FileNotFoundError(f"result folder {result} not found")
        if result.is_file():
            result = result.parent
        # the run kind's figure sets and report sections (an unknown kind: every set that applies)
        kind = KINDS.get(read_summary(result / "summary.json").get("kind")) if (result / "summary.json").is_file() else None
        with _interrupts(result, "tribobem plot"):
            files = replot(result, figure_sets=kind.figures if kind else None,
                           report_sections=kind.report_sections if kind else None)
        if not quiet:
            for name, path in files.items():
                _stdout().print(f"{name}: {escape(str(path))}")


# ----------------------------------------------------------------------------- compare-loop
@app.command("compare-loop")
def compare_loop(
    result: Path = typer.Argument(..., help="Result folder of a hysteresis run (with summary.json)."),
    measured: Path = typer.Argument(..., help="Measured loop: CSV with displacement and force columns, units in "
                                              "the header, e.g. 'displacement (um), force (mN)'."),
    out: Optional[Path] = typer.Option(None, "--out", "-o", help="Figure (PNG; default RESULT/compare_loop.png)."),
    center: bool = typer.Option(True, "--center/--no-center", help="Centre each loop's displacement range on 0 "
                                                                   "in the overlay."),
    as_json: bool = typer.Option(False, "--json/--no-json", help="Print the comparison as JSON."),
    quiet: bool = typer.Option(False, "--quiet/--no-quiet", "-q", help="Print only the figure path."),
):
    """Overlay a measured friction loop on a simulated one and compare K_L at A, B, C (Paper F).

    Both loops: Paper F Eq. 3 fitted to the pre-sliding part of the last rising branch, from its turning point.

    A, B, C: F = -0.5, 0, 0.5 x the force scale (simulated: mu F0+; measured: F* = the largest absolute force of the record).
    """
    with _user_errors():
        from .analysis.loops import compare_loops
        from .output.loops import comparison_figure
        from .units import format_quantity

        if not result.exists():
            raise FileNotFoundError(f"result folder {result} not found")
        if not measured.exists():
            raise FileNotFoundError(f"measured loop {measured} not found")
        folder = result.parent if result.is_file() else result
        figure = out if out is not None else folder / "compare_loop.png"
        cmp = compare_loops(result, measured)
        comparison_figure(cmp, figure, center=center)
        if as_json:
            from .output.summary import jsonable

            sys.stdout.write(json.dumps(jsonable(cmp.as_dict()), indent=2) + "\n")
            return
        if quiet:
            _stdout().print(str(cmp.figure))
            return
        console = _stdout()
        table = Table(title="lateral stiffness K_L (Paper F Eq. 3 fit of the last rising branch)")
        for col in ("point", "F / scale", "K_L simulated", "K_L measured", "sim / meas"):
            table.add_column(col, justify="left" if col == "point" else "right")
        for r in cmp.rows:
            ks, km = r["simulated"]["stiffness"], r["measured"]["stiffness"]
            table.add_row(r["point"], f"{r['force_ratio']:+.2f}", _stiffness(ks), _stiffness(km),
                          "-" if r["ratio"] != r["ratio"] else f"{r['ratio']:.3f}")
        console.print(table)
        for name, loop, fit in (("simulated", cmp.simulated, cmp.simulated_fit),
                                ("measured", cmp.measured, cmp.measured_fit)):
            console.print(f"{name}: scale {escape(loop.normalisation)}; fit over {fit.points} points from the turning "
                          f"point (F = {format_quantity(fit.turn_force, 'force')}, "
                          f"{'gross sliding after them' if fit.sliding else 'no gross sliding on the branch'}), "
                          f"n = {fit.n:.3f}")
        console.print(f"figure: [bold]{escape(str(cmp.figure))}[/bold]")


def _stiffness(k) -> str:
    """A stiffness (N/m) in N/m, kN/m or MN/m; '-' for NaN / None."""
    if k is None or k != k:
        return "-"
    for factor, unit in ((1e6, "MN/m"), (1e3, "kN/m"), (1.0, "N/m")):
        if abs(k) >= factor:
            break
    return f"{k / factor:.4g} {unit}"


def main() -> None:  # pragma: no cover - console entry alternative
    app()


if __name__ == "__main__":  # pragma: no cover
    app()
