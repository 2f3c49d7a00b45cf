"""Ctrl-C: a real SIGINT sent to ``tribobem run`` / ``tribobem sweep`` in a subprocess.

The subprocess is stopped at a known place by the test hook ``TRIBOBEM_TEST_PAUSE``
(:mod:`tribobem.output.atomic`): it prints ``tribobem-test: pause ...`` on stderr and sleeps
either in the solve (after its first step) or in the writing (after a file's temporary copy is
complete, before it is moved into place).  The test waits for that line, sends SIGINT and
checks the exit code (130), the one ``interrupted:`` line, that no temporary file is left and
that summary.json / fields.nc are absent or byte-identical to the previous complete ones (and
load); for sweeps, that a resumed sweep computes only the points without a whole record.
"""

from __future__ import annotations

import json
import os
import queue
import signal
import subprocess
import sys
import threading
import time
from pathlib import Path

import pytest

pytestmark = pytest.mark.skipif(sys.platform == "win32", reason="POSIX signals")

SCENARIO = """
kind = "normal"
[grid]
n = 16
size = "0.5 um"
[body1]
E = "130 GPa"
nu = 0.28
[body2]
rigid = true
shape = { kind = "sphere", radius = "10 um" }
[load]
forces = ["1 uN", "2 uN", "3 uN"]
[output]
figures = FIGURES
"""

SWEEP = """
name = "toy"
scenario = "base.toml"
outputs = ["contact_area", "max_pressure"]
[parameters]
"body1.E" = ["100 GPa", "130 GPa", "160 GPa", "190 GPa"]
"""

MARKER = "tribobem-test: pause"


def _scenario(folder: Path, figures: bool = False) -> Path:
    path = folder / "s.toml"
    path.write_text(SCENARIO.replace("FIGURES", "true" if figures else "false"))
    return path


def _tmp_files(folder: Path) -> list:
    return sorted(str(p) for p in folder.rglob("*") if p.name.endswith(".tmp"))


def _interrupt(args, cwd: Path, pause: str, group: bool = False, timeout: float = 90.0):
    """Start ``python -m tribobem.cli ARGS`` with ``TRIBOBEM_TEST_PAUSE=pause``, wait for
    the pause line on stderr, send SIGINT (to the process group with ``group``, as a terminal's
    Ctrl-C does) and return (returncode, stdout, stderr lines after the pause line)."""
    env = dict(os.environ, TRIBOBEM_TEST_PAUSE=pause, PYTHONUNBUFFERED="1")
    proc = subprocess.Popen([sys.executable, "-m", "tribobem.cli", *map(str, args)], cwd=cwd, env=env,
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            start_new_session=group)
    lines: queue.Queue = queue.Queue()

    def read():
        for line in proc.stderr:
            lines.put(line)
        lines.put(None)

    threading.Thread(target=read, daemon=True).start()
    before, deadline = [], time.monotonic() + timeout
    try:
        while True:
            line = lines.get(timeout=max(0.1, deadline - time.monotonic()))
            if line is None:
                pytest.fail(f"the process ended before the pause ({proc.wait()}): {''.join(before)}")
            before.append(line)
            if line.startswith(MARKER):
                break
        if group:
            os.killpg(proc.pid, signal.SIGINT)
        else:
            proc.send_signal(signal.SIGINT)
        out = proc.stdout.read()
        rc = proc.wait(timeout=timeout)
    except BaseException:
        proc.kill()
        proc.wait()
        raise
    after = []
    while (line := lines.get(timeout=timeout)) is not None:
        after.append(line)
    return rc, out, [ln.rstrip("\n") for ln in after if ln.strip()]


def _one_interrupted_line(lines) -> str:
    text = "\n".join(lines)
    assert "Traceback" not in text, text
    assert [ln for ln in lines if ln.startswith("interrupted:")] == lines[-1:] and len(lines) == 1, text
    return lines[0]


def _snapshot(folder: Path) -> dict:
    return {p.name: p.read_bytes() for p in folder.iterdir() if p.is_file()}


def _loads(folder: Path) -> None:
    import xarray as xr

    with open(folder / "summary.json", encoding="utf-8") as fh:
        assert json.load(fh)["kind"] == "normal"
    with xr.open_dataset(folder / "fields.nc") as ds:
        assert ds.sizes["step"] == 3


# ----------------------------------------------------------------------------- tribobem run
def test_sigint_in_the_solve_keeps_the_previous_outputs(tmp_path):
    from tribobem.scenario import run_scenario

    scen, out = _scenario(tmp_path), tmp_path / "out"
    run_scenario(scen, outdir=out, progress=False)  # the previous complete outputs
    old = _snapshot(out)
    rc, _, err = _interrupt(["run", scen, "-o", out, "-q"], tmp_path, "solve=60")
    assert rc == 130
    line = _one_interrupted_line(err)
    assert "tribobem run" in line and f"outputs in {out} are the previous complete ones" in line
    assert _snapshot(out) == old and not _tmp_files(tmp_path)
    _loads(out)


@pytest.mark.parametrize("pause, figures", [("write:*/fields.nc=60", False), ("write:*/summary.json@2=60", True)])
def test_sigint_while_writing_leaves_the_old_files_whole(tmp_path, pause, figures):
    """Paused after fields.nc's temporary file is complete (the first file written), and at
    summary.json (the last one: fields.nc, the figures and the report are complete in their
    temporary files): the folder keeps every previous file, none is mixed in."""
    from tribobem.scenario import run_scenario

    scen, out = _scenario(tmp_path, figures=figures), tmp_path / "out"
    run_scenario(scen, outdir=out, progress=False)
    old = _snapshot(out)
    assert {"summary.json", "fields.nc", "report.html"} <= set(old)
    assert any(n.endswith(".png") for n in old) == figures
    rc, _, err = _interrupt(["run", scen, "-o", out, "-q"], tmp_path, pause)
    assert rc == 130
    assert "are the previous complete ones" in _one_interrupted_line(err)
    assert _snapshot(out) == old and not _tmp_files(tmp_path)
    _loads(out)


def test_sigint_on_a_first_run_writes_nothing(tmp_path):
    scen, out = _scenario(tmp_path), tmp_path / "out"
    rc, _, err = _interrupt(["run", scen, "-o", out, "-q"], tmp_path, "write:*/summary.json=60")
    assert rc == 130
    assert f"outputs in {out} were not written" in _one_interrupted_line(err)
    assert not (out / "summary.json").exists() and not (out / "fields.nc").exists()
    assert not _tmp_files(tmp_path)


# ----------------------------------------------------------------------------- tribobem sweep
def _sweep(folder: Path) -> Path:
    _scenario(folder).rename(folder / "base.toml")
    path = folder / "sweep.toml"
    path.write_text(SWEEP)
    return path


def _records(out: Path) -> dict:
    return {p.name: p.read_bytes() for p in (out / "points").glob("*.json")}


def _resume(sweep: Path, out: Path) -> dict:
    """Run the sweep again (here, synchronously) and return its own account of it."""
    from tribobem.sweep import run_sweep

    return run_sweep(sweep, out, scheduler="synchronous", progress=False).as_dict()


@pytest.mark.parametrize("pause, saved", [("solve@3=60", 2), ("write:*/points/*.json@2=60", 1)])
def test_sweep_sigint_then_resume_computes_only_the_missing_points(tmp_path, pause, saved):
    """Interrupted in the 3rd point's solve (2 points saved), or while the 2nd point's record
    is written (1 saved: the half-written one does not count); the resumed sweep reuses the
    saved records unchanged and computes the other points only."""
    sweep, out = _sweep(tmp_path), tmp_path / "out"
    rc, _, err = _interrupt(["sweep", sweep, "-o", out, "--scheduler", "synchronous", "-q"], tmp_path, pause)
    assert rc == 130
    line = _one_interrupted_line(err)
    assert f"interrupted: {saved} of 4 points are saved in {out}" in line
    assert "results.nc and results.csv were not written" in line and "run the same command again" in line
    assert not _tmp_files(tmp_path)
    kept = _records(out)
    assert len(kept) == saved
    res = _resume(sweep, out)
    assert (res["n_done_before"], res["n_run"], res["n_ok"]) == (saved, 4 - saved, 4)
    after = _records(out)
    assert len(after) == 4 and all(after[name] == data for name, data in kept.items())  # reused as they were
    assert not _tmp_files(tmp_path)


def test_sweep_ctrl_c_on_a_local_cluster(tmp_path):
    """A terminal's Ctrl-C (SIGINT to the whole process group) while the Dask workers solve:
    the workers ignore it, the sweep stops its cluster and prints one line; the points saved
    so far are reused by the resumed sweep."""
    sweep, out = _sweep(tmp_path), tmp_path / "out"
    rc, _, err = _interrupt(["sweep", sweep, "-o", out, "--workers", "1", "-q"], tmp_path, "solve@2=60", group=True)
    assert rc == 130
    line = _one_interrupted_line(err)
    kept = _records(out)
    assert len(kept) <= 1 and f"interrupted: {len(kept)} of 4 points are saved" in line
    assert not _tmp_files(tmp_path)
    res = _resume(sweep, out)
    assert (res["n_done_before"], res["n_run"], res["n_ok"]) == (len(kept), 4 - len(kept), 4)
    assert all(_records(out)[name] == data for name, data in kept.items())


# ----------------------------------------------------------------------------- the helpers
def test_staged_writes_land_together_or_not_at_all(tmp_path):
    from tribobem.output.atomic import atomic_write_text, staged, staged_source

    a, b = tmp_path / "a.txt", tmp_path / "b.txt"
    atomic_write_text(a, "old a")
    with pytest.raises(KeyboardInterrupt):
        with staged():
            atomic_write_text(a, "new a")
            atomic_write_text(b, "new b")
            assert a.read_text() == "old a" and not b.exists()  # nothing in place yet
            assert staged_source(b).read_text() == "new b"  # but readable where it waits
            raise KeyboardInterrupt
    assert a.read_text() == "old a" and not b.exists() and not _tmp_files(tmp_path)
    with staged():
        atomic_write_text(a, "new a")
        atomic_write_text(a, "newer a")  # written twice: the last one wins
        atomic_write_text(b, "new b")
    assert a.read_text() == "newer a" and b.read_text() == "new b" and not _tmp_files(tmp_path)


def test_sigint_is_held_back_until_the_block_ends():
    from tribobem.output.atomic import sigint_deferred

    done = []
    with pytest.raises(KeyboardInterrupt):
        with sigint_deferred():
            os.kill(os.getpid(), signal.SIGINT)
            time.sleep(0.05)
            done.append(1)  # still running: the signal waits
    assert done == [1]
    assert signal.getsignal(signal.SIGINT) is signal.default_int_handler


def test_a_torn_point_record_counts_as_missing(tmp_path):
    from tribobem.sweep import read_points, run_sweep

    spec = {"name": "toy", "function": "builtins:dict", "parameters": {"x": [1, 2, 3]}, "outputs": ["x"]}
    res = run_sweep(spec, tmp_path, scheduler="synchronous", progress=False)
    assert res.n_run == 3
    victim = sorted((tmp_path / "points").glob("*.json"))[0]
    text = victim.read_text()
    victim.write_text(text[: len(text) // 2])  # cut short, as a non-atomic writer would leave it
    other = sorted((tmp_path / "points").glob("*.json"))[1]
    rec = json.loads(other.read_text())
    del rec["outputs"]  # valid JSON, but not a whole record
    other.write_text(json.dumps(rec))
    assert len(read_points(tmp_path)) == 1
    res = run_sweep(spec, tmp_path, scheduler="synchronous", progress=False)
    assert (res.n_done_before, res.n_run, res.n_ok) == (1, 2, 3)


def test_one_jsonable_for_summaries_and_sweep_hashes():
    import numpy as np

    from tribobem.output.summary import jsonable
    from tribobem.sweep.values import _jsonable

    class Odd:
        def __repr__(self):
            return "Odd()"

        def __str__(self):
            return "odd"

    value = {"a": (np.float32(1.5), np.int64(2), np.nan), "p": Path("x/y"), "o": Odd(), 3: np.array([True])}
    assert jsonable(value) == {"a": [1.5, 2, None], "p": "x/y", "o": "odd", "3": [True]}
    assert _jsonable(value) == dict(jsonable(value), o="Odd()")  # the hashes keep their repr


def test_a_ctrl_c_that_python_drops_still_interrupts(tmp_path, monkeypatch):
    """A SIGINT that lands in a __del__ (or a weakref callback) is printed and dropped by Python
    ("Exception ignored in ..."): seen once in a real run, which then exited 0 with a traceback.
    The CLI records every SIGINT, so the run still ends as interrupted (exit 130, one line) and
    the folder holds complete outputs (here the new ones, written before the run returned)."""
    from typer.testing import CliRunner

    import tribobem.cli as cli
    from tribobem.scenario import run_scenario

    class DropsCtrlC:
        def __del__(self):
            signal.raise_signal(signal.SIGINT)  # the handler's KeyboardInterrupt is dropped here

    def run_and_drop(*args, **kw):
        DropsCtrlC()  # collected at once: SIGINT inside __del__
        return run_scenario(*args, **kw)

    monkeypatch.setattr(cli, "run_scenario", run_and_drop, raising=False)
    import tribobem.scenario as scenario_pkg

    monkeypatch.setattr(scenario_pkg, "run_scenario", run_and_drop)
    sc = tmp_path / "s.toml"
    sc.write_text('[grid]\nn = 16\nsize = "0.5 um"\n[body1]\nE = "130 GPa"\nnu = 0.3\n[body2]\nrigid = true\n'
                  'shape = { kind = "sphere", radius = "10 um" }\n[load]\nforce = "1 uN"\n'
                  '[output]\nfigures = false\nreport = false\n')
    res = CliRunner().invoke(cli.app, ["run", str(sc), "-o", str(tmp_path / "out")])
    assert res.exit_code == 130, res.output
    assert "interrupted:" in res.output and "new complete ones" in res.output
    assert "Exception ignored" not in res.output
    json.loads((tmp_path / "out" / "summary.json").read_text())
    assert signal.getsignal(signal.SIGINT) is signal.default_int_handler  # restored
