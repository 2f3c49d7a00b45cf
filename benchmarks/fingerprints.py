"""Bitwise fingerprints of the numbers tribobem produces: the baseline a pure refactor is compared against.

A refactor that claims "no behaviour change" must give the same numbers to the last bit.  This
script runs

* every scenario of ``examples/*.toml`` (``tribobem.run_scenario(path, outdir=None,
  progress=False, warn=False)``),
* the sweeps of ``examples/studies/*.toml`` that run in well under a minute
  (:data:`STUDY_SWEEPS`; the others take from minutes to hours, or need a generated input
  file, see below), in this process with no Dask (``scheduler="synchronous"``),
* every case of the quick validation tier (``tribobem validate --quick``: the rows of
  ``tribobem.validation.run_validation(level="quick")``, one task per case),

and records every number they give, encoded exactly:

* a float (Python or NumPy) as ``float.hex()`` of its float64 value (so ``-0.0``, the NaN and
  every last bit count), an int as an int, a bool as a bool, None as None;
* a string as ``"str:<text>"``, a warning message (any string under a ``warnings`` key) and any
  string longer than 200 characters as ``"sha256:<digest>"`` of its UTF-8 text, so that a
  changed message shows too;  the repository's absolute path in a string is replaced by
  ``<repo>`` first (the baseline worktree and the refactor's worktree differ there);
* a field array of ``result.fields`` (an xarray Dataset: every data variable and every
  coordinate) as ``"sha256:<digest>"`` of the raw bytes of a C-contiguous float64 copy, with
  its shape, dtype and the float64 sum of its finite values (the sum tells a round-off change
  from a large one when the digest differs);  object coordinates (the step labels) as the
  sha256 of their strings.

Keys: ``examples/<stem>/<dotted summary key>`` (lists by index: ``steps.3.approach``),
``examples/<stem>/fields/<name>[.shape|.dtype|.sum]``, ``examples/<stem>/fields.attrs.<name>``,
``studies/<stem>/<point as JSON>/<output>`` and ``validation/<case>/<quantity>.<field>``
(``computed``, ``reference``, ``rel_error``, ``tolerance``, ``passed``; a repeated
case + quantity gets ``#2``, ``#3``, ...).  A task that raises records
``<task>/error`` (the exception type and the sha256 of its message).

Not recorded (not results, or not reproducible by construction):

* summary keys ``timings``, ``created``, ``versions`` and, at any depth, ``time``,
  ``elapsed``, ``wall_time``, ``cpu_time``, ``started``, ``finished``, ``host``, ``pid``
  (wall-clock times, dates, the machine); the dataset attribute ``tribobem_version``;
* sweep records' ``hash`` (it includes ``SOLVER_VERSION``, which a refactor may bump on
  purpose; the point's overrides are the key instead) and the sweeps' ``elapsed``/host fields;
* the studies sweeps not in :data:`STUDY_SWEEPS`: ``bisinusoidal_pulloff.toml`` (625 points
  at 256^2, hours), ``paper_b.toml`` (256^2 capillary RH sweeps, tens of minutes),
  ``rough_ball_slip.toml`` (29 points, 53 min) and its base scenario
  ``rough_ball_slip_base.toml`` (needs ``results/rough_ball_slip_flat.npy``, written by the
  study script).

Determinism: two ``--compare`` runs of the baseline's commit, one with ``--jobs 2`` in another
task order and one with ``--jobs 1`` (every task in one process, after the others' caches), gave
all 11500 fingerprints identical (benchmarks/README.md, "Result fingerprints"), so nothing is
excluded as non-deterministic.  The numbers may depend on the machine (its core count sets the
FFT threads; the NumPy/SciPy builds), so compare on the machine that recorded the baseline.

Usage::

    python benchmarks/fingerprints.py --out benchmarks/fingerprints/baseline.json
    python benchmarks/fingerprints.py --compare benchmarks/fingerprints/baseline.json
    python benchmarks/fingerprints.py --compare baseline.json --only examples --match 'examples/hertz*'

``--compare`` recomputes the tasks of the file (restricted by ``--only``/``--match``), prints
every key whose value differs (old, new, and the relative difference for floats), keys only in
one of the two, and a final line ``N of M fingerprints identical``; exit status 1 if any
differs.
"""

from __future__ import annotations

import argparse
import fnmatch
import hashlib
import json
import math
import os
import subprocess
import sys
import tempfile
import time
import traceback
import warnings
from concurrent.futures import ProcessPoolExecutor, as_completed
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

#: The sweeps of examples/studies/ small enough to fingerprint (seconds each, measured).
STUDY_SWEEPS = ("bisinusoidal_quick.toml", "sphere_pulloff_sweep.toml")

#: Keys skipped at any depth of a summary or record: times, dates, the machine.
SKIP_KEYS = frozenset({"timings", "created", "versions", "time", "elapsed", "wall_time", "cpu_time",
                       "started", "finished", "host", "pid"})

#: Dataset attributes skipped (the package version is not a result).
SKIP_ATTRS = frozenset({"tribobem_version"})

#: Strings longer than this are recorded by their sha256.
MAX_STRING = 200

GROUPS = ("examples", "studies", "validation")


# ----------------------------------------------------------------------------- encoding
def _sha256(data: bytes) -> str:
    return "sha256:" + hashlib.sha256(data).hexdigest()


def _normalise_text(text: str, roots=()) -> str:
    for r in roots:
        if r:
            text = text.replace(r, "<repo>")
    return text


def encode_scalar(value, *, digest: bool = False, roots=()):
    """The exact, JSON-safe encoding of one scalar.

    Parameters
    ----------
    value : bool, int, float, str, None or a NumPy scalar
        The value.  Anything else is encoded as its ``str()``.
    digest : bool
        Encode a string as its sha256 (warnings) instead of its text.
    roots : sequence of str
        Absolute paths replaced by ``<repo>`` in strings before they are encoded.

    Returns
    -------
    bool, int, str or None
        A bool or an int unchanged, a float as ``float.hex()`` of its float64, a string as
        ``"str:..."`` or ``"sha256:..."``.
    """
    import numpy as np

    if value is None:
        return None
    if isinstance(value, (bool, np.bool_)):
        return bool(value)
    if isinstance(value, (int, np.integer)):
        return int(value)
    if isinstance(value, (float, np.floating)):
        return float(value).hex()
    text = _normalise_text(value if isinstance(value, str) else str(value), roots)
    if digest or len(text) > MAX_STRING:
        return _sha256(text.encode("utf-8"))
    return "str:" + text


def flatten(obj, prefix: str = "", *, roots=(), digest: bool = False, out: dict | None = None) -> dict:
    """Flatten nested dicts and lists into ``{dotted key: encoded value}``.

    Dict keys are joined with ``.``, list items by their index; keys in :data:`SKIP_KEYS` are
    left out at any depth; strings under a ``warnings`` key are recorded by their sha256.
    NumPy arrays of up to 10000 items are flattened like lists, larger ones recorded by the
    sha256 of their float64 bytes (``.sha256``) and their shape.

    Parameters
    ----------
    obj : dict, list, tuple, array or scalar
        The value to flatten.
    prefix : str
        The key of ``obj`` itself ("" at the top).
    roots : sequence of str
        Absolute paths replaced by ``<repo>`` in strings.
    digest : bool
        Record strings by their sha256 (set below a ``warnings`` key).
    out : dict, optional
        The dict to fill (a new one by default).

    Returns
    -------
    dict
        ``out``.
    """
    import numpy as np

    out = {} if out is None else out

    def key(k):
        return f"{prefix}.{k}" if prefix else str(k)

    if isinstance(obj, dict):
        for k, v in obj.items():
            if str(k) in SKIP_KEYS:
                continue
            flatten(v, key(k), roots=roots, digest=digest or str(k) == "warnings", out=out)
    elif isinstance(obj, (list, tuple)):
        if not obj:
            out[prefix] = "str:[]"
        for i, v in enumerate(obj):
            flatten(v, key(i), roots=roots, digest=digest, out=out)
    elif isinstance(obj, np.ndarray) and obj.dtype != object and obj.ndim > 0:
        if obj.size <= 10000:
            flatten(obj.tolist(), prefix, roots=roots, digest=digest, out=out)
        else:
            out[key("sha256")] = array_digest(obj)
            out[key("shape")] = "str:" + repr(tuple(obj.shape))
    elif isinstance(obj, np.ndarray):
        flatten(obj.tolist(), prefix, roots=roots, digest=digest, out=out)
    else:
        out[prefix] = encode_scalar(obj, digest=digest, roots=roots)
    return out


def array_digest(values) -> str:
    """sha256 of the raw bytes of a C-contiguous float64 copy of an array."""
    import numpy as np

    return _sha256(np.ascontiguousarray(np.asarray(values, dtype=np.float64)).tobytes())


def fields_fingerprints(ds, prefix: str, roots=()) -> dict:
    """Fingerprints of an xarray Dataset: data variables, coordinates and attributes.

    Parameters
    ----------
    ds : xarray.Dataset or None
        ``RunResult.fields``.
    prefix : str
        Key prefix, e.g. ``"examples/hertz_free_boundary"``.
    roots : sequence of str
        Absolute paths replaced by ``<repo>`` in strings.

    Returns
    -------
    dict
        ``<prefix>/fields/<name>`` (sha256), ``.shape``, ``.dtype``, ``.sum`` (float64 sum of
        the finite values), and ``<prefix>/fields.attrs.<name>``.
    """
    import numpy as np

    out: dict = {}
    if ds is None:
        out[f"{prefix}/fields"] = None
        return out
    names = [("", n) for n in ds.data_vars] + [("coord:", n) for n in ds.coords]
    for tag, name in names:
        values = np.asarray(ds[name].values)
        k = f"{prefix}/fields/{tag}{name}"
        if values.dtype == object or values.dtype.kind in "USO":
            text = "\x1f".join(_normalise_text(str(v), roots) for v in values.ravel())
            out[k] = _sha256(text.encode("utf-8"))
        else:
            out[k] = array_digest(values)
            finite = np.asarray(values, dtype=np.float64)
            out[k + ".sum"] = float(np.sum(finite[np.isfinite(finite)])).hex()
        out[k + ".shape"] = "str:" + repr(tuple(values.shape))
        out[k + ".dtype"] = "str:" + str(values.dtype)
    attrs = {k: v for k, v in ds.attrs.items() if k not in SKIP_ATTRS}
    flatten(attrs, f"{prefix}/fields.attrs", roots=roots, out=out)
    return out


# ----------------------------------------------------------------------------- tasks
def _roots() -> tuple[str, ...]:
    import tribobem

    pkg_root = str(Path(tribobem.__file__).resolve().parents[2])
    return tuple(sorted({pkg_root, str(ROOT)}, key=len, reverse=True))


def example_entries(path: Path, name: str) -> dict:
    """Fingerprints of one example scenario (summary and fields)."""
    import tribobem

    roots = _roots()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        result = tribobem.run_scenario(str(path), outdir=None, progress=False, warn=False)
    out = {f"{name}/{k}": v for k, v in flatten(result.summary, roots=roots).items()}
    out.update(fields_fingerprints(result.fields, name, roots))
    return out


def study_entries(path: Path, name: str) -> dict:
    """Fingerprints of one small sweep: every point's status and outputs, keyed by its overrides."""
    from tribobem.sweep import run_sweep
    from tribobem.sweep.cache import read_points

    roots = _roots()
    with tempfile.TemporaryDirectory(prefix="tribobem-fingerprints-") as tmp:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            run_sweep(str(path), tmp, scheduler="synchronous", progress=False, quiet=True, gather_results=False)
        records = read_points(tmp)
    out: dict = {}
    for rec in records.values():
        point = json.dumps(rec.get("point"), sort_keys=True, separators=(",", ":"))
        body = {"status": rec.get("status"), "outputs": rec.get("outputs"), "converged": rec.get("converged"),
                "error": rec.get("error")}
        for k, v in flatten(body, roots=roots).items():
            out[f"{name}/{point}/{k}"] = v
    return out


def validation_entries(case: str, name: str) -> dict:
    """Fingerprints of one quick validation case: every row's numbers."""
    from dataclasses import asdict, is_dataclass

    from tribobem.validation import run_validation

    roots = _roots()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        rows = run_validation(level="quick", cases=[case])
    out: dict = {}
    seen: dict[str, int] = {}
    for row in rows:
        d = asdict(row) if is_dataclass(row) else (row._asdict() if hasattr(row, "_asdict") else dict(row))
        base = f"{name}/{d.get('case')}/{d.get('quantity')}"
        seen[base] = seen.get(base, 0) + 1
        if seen[base] > 1:
            base += f"#{seen[base]}"
        for field_name, v in d.items():
            if field_name in ("case", "quantity"):
                continue
            out[f"{base}.{field_name}"] = encode_scalar(v, roots=roots) if not isinstance(v, (dict, list)) else \
                _sha256(json.dumps(v, sort_keys=True, default=str).encode())
    return out


def run_task(task: tuple[str, str, str]) -> tuple[str, dict, float]:
    """Run one task in a worker process.

    Parameters
    ----------
    task : (group, name, argument)
        ``("examples", "examples/<stem>", path)``, ``("studies", "studies/<stem>", path)`` or
        ``("validation", "validation/<case>", case)``.

    Returns
    -------
    (name, entries, seconds)
    """
    group, name, arg = task
    t0 = time.perf_counter()
    try:
        if group == "examples":
            entries = example_entries(Path(arg), name)
        elif group == "studies":
            entries = study_entries(Path(arg), name)
        else:
            entries = validation_entries(arg, name)
    except Exception as exc:  # a failing task is a fingerprint too (and must stay failing)
        traceback.print_exc(file=sys.stderr)
        entries = {f"{name}/error": f"str:{type(exc).__name__} " + _sha256(str(exc).encode())}
    return name, entries, time.perf_counter() - t0


def all_tasks(only: list[str] | None = None, match: list[str] | None = None) -> list[tuple[str, str, str]]:
    """The tasks, in the order examples, studies, validation (each sorted by name).

    Parameters
    ----------
    only : list of str, optional
        Groups to keep (:data:`GROUPS`).
    match : list of str, optional
        fnmatch patterns on the task names (``examples/hertz*``); any may match.
    """
    groups = only or list(GROUPS)
    tasks = []
    if "examples" in groups:
        tasks += [("examples", f"examples/{p.stem}", str(p)) for p in sorted((ROOT / "examples").glob("*.toml"))]
    if "studies" in groups:
        tasks += [("studies", f"studies/{Path(s).stem}", str(ROOT / "examples" / "studies" / s)) for s in STUDY_SWEEPS]
    if "validation" in groups:
        from tribobem.validation import CASES

        tasks += [("validation", f"validation/{c}", c) for c in CASES]
    if match:
        tasks = [t for t in tasks if any(fnmatch.fnmatchcase(t[1], m) for m in match)]
    return tasks


def compute(tasks, jobs: int = 2, order: dict | None = None) -> tuple[dict, dict]:
    """Run the tasks in ``jobs`` worker processes.

    Parameters
    ----------
    tasks : list of tasks (:func:`all_tasks`)
    jobs : int
        Worker processes (1: in this process).
    order : dict, optional
        Task name -> seconds of an earlier run: the longest start first.

    Returns
    -------
    (entries, seconds)
        All fingerprints (sorted by key) and each task's wall time.
    """
    if order:
        tasks = sorted(tasks, key=lambda t: -order.get(t[1], 1e9))
    entries: dict = {}
    seconds: dict = {}
    n = len(tasks)

    def done(k, name, ent, dt):
        entries.update(ent)
        seconds[name] = round(dt, 2)
        print(f"[{k}/{n}] {name}: {dt:.1f} s, {len(ent)} fingerprints", file=sys.stderr, flush=True)

    if jobs <= 1:
        for k, t in enumerate(tasks, 1):
            done(k, *run_task(t))
    else:
        import multiprocessing as mp

        # fork: the workers inherit sys.path/PYTHONPATH and need not re-import this file as __main__
        with ProcessPoolExecutor(max_workers=jobs, mp_context=mp.get_context("fork")) as pool:
            futures = [pool.submit(run_task, t) for t in tasks]
            for k, fut in enumerate(as_completed(futures), 1):
                done(k, *fut.result())
    return dict(sorted(entries.items())), dict(sorted(seconds.items()))


# ----------------------------------------------------------------------------- comparison
def _as_float(v):
    if isinstance(v, str) and not v.startswith(("str:", "sha256:")):
        try:
            return float.fromhex(v)
        except ValueError:
            return None
    return None


def _show(v) -> str:
    f = _as_float(v)
    if f is not None:
        return repr(f)
    return json.dumps(v)


def compare(old: dict, new: dict) -> tuple[list[str], int, int]:
    """Compare two fingerprint dicts.

    Parameters
    ----------
    old, new : dict
        ``{key: encoded value}``.

    Returns
    -------
    (lines, n_identical, n_total)
        One line per differing key (``key: old -> new (rel. diff ...)``, or ``only in old`` /
        ``only in new``), the number of identical keys and the number of keys in either dict.
    """
    lines = []
    keys = sorted(set(old) | set(new))
    same = 0
    for k in keys:
        if k not in new:
            lines.append(f"{k}: only in old ({_show(old[k])})")
            continue
        if k not in old:
            lines.append(f"{k}: only in new ({_show(new[k])})")
            continue
        a, b = old[k], new[k]
        if a == b and type(a) is type(b):
            same += 1
            continue
        fa, fb = _as_float(a), _as_float(b)
        if fa is not None and fb is not None:
            if math.isfinite(fa) and math.isfinite(fb):
                scale = max(abs(fa), abs(fb))
                rel = abs(fb - fa) / scale if scale > 0 else 0.0
                lines.append(f"{k}: {fa!r} -> {fb!r} (rel. diff {rel:.3g})")
            else:
                lines.append(f"{k}: {fa!r} -> {fb!r}")
        else:
            lines.append(f"{k}: {_show(a)} -> {_show(b)}")
    return lines, same, len(keys)


def _describe() -> str:
    import tribobem

    where = Path(tribobem.__file__).resolve().parent
    try:
        return subprocess.run(["git", "describe", "--always", "--dirty", "--tags"], cwd=where, capture_output=True,
                              text=True, check=True).stdout.strip()
    except (OSError, subprocess.CalledProcessError):
        return "unknown"


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    what = ap.add_mutually_exclusive_group()
    what.add_argument("--out", type=Path, help="write the fingerprints to this JSON file")
    what.add_argument("--compare", type=Path, help="recompute and compare with this JSON file (exit 1 if any differs)")
    ap.add_argument("--only", choices=GROUPS, action="append",
                    help="only this group of tasks (repeatable; default: all)")
    ap.add_argument("--match", action="append", help="only the tasks whose name matches this fnmatch pattern "
                                                     "(repeatable), e.g. 'examples/hertz*' or 'validation/md_*'")
    ap.add_argument("--jobs", type=int, default=2, help="worker processes (default 2; 1: in this process)")
    ap.add_argument("--list", action="store_true", help="list the task names and exit")
    args = ap.parse_args(argv)

    tasks = all_tasks(args.only, args.match)
    if args.list:
        print("\n".join(t[1] for t in tasks))
        return 0
    if not (args.out or args.compare):
        ap.error("one of --out, --compare or --list is required")
    old = None
    if args.compare:
        old = json.loads(args.compare.read_text())
        names = {t[1] for t in tasks}
        # the old file's tasks restricted to the selection (a task's keys start with its name + "/")
        recorded = set(old.get("seconds", {})) or {k.split("/", 2)[0] + "/" + k.split("/", 2)[1] for k in old["entries"]}
        tasks = [t for t in tasks if t[1] in recorded]
        missing = sorted(n for n in recorded if n in names and n not in {t[1] for t in tasks})
        assert not missing, missing
    t0 = time.perf_counter()
    entries, seconds = compute(tasks, args.jobs, order=(old or {}).get("seconds"))
    total = time.perf_counter() - t0
    print(f"{len(tasks)} tasks, {len(entries)} fingerprints, {total:.0f} s (jobs {args.jobs})", file=sys.stderr)
    if args.out:
        args.out.parent.mkdir(parents=True, exist_ok=True)
        doc = {"commit": _describe(), "created": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime()),
               "jobs": args.jobs, "total_seconds": round(total, 1), "cpu_count": os.cpu_count(),
               "seconds": seconds, "entries": entries}
        args.out.write_text(json.dumps(doc, indent=1) + "\n")
        print(f"wrote {args.out}", file=sys.stderr)
        return 0
    prefixes = tuple(t[1] + "/" for t in tasks)
    old_entries = {k: v for k, v in old["entries"].items() if k.startswith(prefixes)}
    lines, same, n = compare(old_entries, entries)
    print(f"compared {_describe()} with {args.compare} (recorded at {old.get('commit')})")
    for line in lines:
        print(line)
    print(f"{same} of {n} fingerprints identical")
    return 0 if same == n else 1


if __name__ == "__main__":
    sys.exit(main())
