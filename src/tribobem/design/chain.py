"""One design point: a fixed chain of existing run kinds on the same geometry.

Each point's scenario (the base with the point's overrides) is run as

1. ``normal`` at the clamp load (``load.force``): real contact area, max pressure, F0+;
2. ``pulloff`` from the clamp load as preload (``load.preload``): the pull-off force (0 N,
   without running it, when the point has neither adhesion nor humidity; a ``[two_scale]`` point
   unloads its windows' tensile law);
3. ``partial_slip``: a tangential ramp to gross slip (``friction.tangential_forces``): static
   friction force and ratio, pre-sliding displacement;
4. optionally ``hysteresis`` (``friction.path``): the lateral stiffness at Paper F's points
   A, B, C.

Every stage is a scenario dict made from the point's scenario with ``kind`` changed and the
sections and keys the kind does not read (:meth:`tribobem.runs.RunKind.reads`) left out, run
by :func:`tribobem.scenario.run_scenario` without an output folder.  With ``[humidity]``
(one RH per point; ``humidity.rh = "dry"`` leaves humidity and the films out) the humid kinds
return run-level lists in RH order, of which the point takes element 0.  The normal stage of a
humid point is dry (kind ``normal`` has no menisci), so its contact area, max pressure,
repulsive force F0+ and capillary force are those of the humid ramp's first state: the clamp
load at zero tangential load with the menisci of the point's RH (the chain's ramps start at
F_t = 0).  A dry point takes them from the normal stage (capillary force 0 N).

:class:`DesignPointRunner` is the callable :func:`tribobem.sweep.run_sweep` runs on each point
(``func``): it returns the point's scalars (the sweep's record) and writes the point's full
result, warnings and per-stage messages included, to ``OUTDIR/design/<hash>.json``.
"""

from __future__ import annotations

import copy
import json
import math
import time
from collections.abc import Mapping
from pathlib import Path

from ..errors import InputError
from ..output.atomic import atomic_write_text
from ..runs import KINDS
from ..runs.kind import ALL, SECTIONS
from ..scenario.schema import adhesion_model
from ..sweep.values import _canonical, _jsonable, apply_overrides
from ..units import to_si

__all__ = ["DesignPointRunner", "DesignPointError", "run_chain", "stage_scenario", "point_scenario",
           "STAGES", "VALUE_KEYS", "read_detail"]

#: The stages of the chain, in order -> the run kind each runs.
STAGES = {"normal": "normal", "pulloff": "pulloff", "ramp": "partial_slip", "hysteresis": "hysteresis"}

#: Scalars of a design point (SI units) -> (dimension, description).
VALUE_KEYS = {
    "static_friction_force": ("force", "tangential force at the gross-slip onset of the ramp (N)"),
    "static_friction_ratio": ("dimensionless", "static friction force / (mu F0+) at the onset"),
    "presliding_displacement": ("length", "tangential displacement from zero load to the onset (m)"),
    "lateral_stiffness_A": ("stiffness", "lateral stiffness K_L at Paper F's point A, F_x = -0.5 mu F0+ (N/m)"),
    "lateral_stiffness_B": ("stiffness", "lateral stiffness K_L at Paper F's point B, F_x = 0 (N/m)"),
    "lateral_stiffness_C": ("stiffness", "lateral stiffness K_L at Paper F's point C, F_x = 0.5 mu F0+ (N/m)"),
    "pull_off_force": ("force", "pull-off force from the clamp load (N, negative: tensile)"),
    "contact_area": ("area", "real contact area at the clamp load and zero tangential load (m^2; humid: "
                             "with the menisci, the humid ramp's first state)"),
    "max_pressure": ("pressure", "max contact pressure at the clamp load and zero tangential load (Pa; humid: "
                                 "with the menisci)"),
    "peak_pressure": ("pressure", "max contact pressure over every state of the chain (Pa)"),
    "repulsive_force": ("force", "repulsive (compressive) force F0+ at the clamp load and zero tangential load "
                                 "(N; humid: clamp load plus what the menisci pull)"),
    "capillary_force": ("force", "meniscus (Laplace) force at the clamp load and zero tangential load (N, "
                                 "negative: tensile; 0 for a dry point)"),
    "clamp_load": ("force", "the normal (clamp) load (N)"),
    "friction_coefficient": ("dimensionless", "local friction coefficient mu"),
    "ramp_max_force": ("force", "the last tangential force of the ramp (N)"),
}

#: Where a design point's full result goes, relative to the design folder.
DETAIL_DIR = "design"

#: Values of ``humidity.rh`` that mean "no humidity" for a design point.
_DRY = ("dry", "none")


class DesignPointError(RuntimeError):
    """A stage of a design point failed (the message names the stages and their errors)."""


def _first(value):
    """Element 0 of a per-RH list (one RH per design point), else the value."""
    if isinstance(value, (list, tuple)):
        return value[0] if value else None
    return value


def _num(value) -> float:
    v = _first(value)
    try:
        v = float(v)
    except (TypeError, ValueError):
        return math.nan
    return v if math.isfinite(v) else math.nan


def point_scenario(base: Mapping, overrides: Mapping) -> tuple[dict, list[str]]:
    """The scenario of one design point, ready to be split into stages.

    Parameters
    ----------
    base : mapping
        The base scenario (units as written).
    overrides : mapping
        The point's dotted overrides.

    Returns
    -------
    scenario : dict
        The base with the overrides set; ``humidity.rh = "dry"`` removes ``[humidity]`` and
        the bodies' films; a random roughness without a ``seed`` gets seed 0, so that every
        stage sees the same geometry.
    notes : list of str
        What was changed (reported with the point's warnings).

    Raises
    ------
    InputError
        ``humidity.rh`` with more than one RH (a design point takes one; vary it as a
        parameter instead), or a body that is not a table.
    """
    sc = apply_overrides(base, overrides)
    notes = []
    hum = sc.get("humidity")
    if isinstance(hum, Mapping):
        rh = hum.get("rh")
        if isinstance(rh, str) and rh.strip().lower() in _DRY:
            sc.pop("humidity")
            for body in ("body1", "body2"):
                if isinstance(sc.get(body), dict):
                    sc[body].pop("film", None)
                    sc[body].pop("hamaker", None)
        elif isinstance(rh, (list, tuple)) and len(rh) != 1:
            raise InputError("humidity.rh", f"a design point takes one RH, got {rh!r}: give humidity.rh as a "
                                            "design parameter (a list of single values, \"dry\" for none)")
    for body in ("body1", "body2"):
        b = sc.get(body)
        if b is None:
            continue
        if not isinstance(b, dict):
            raise InputError(body, "must be a table")
        rough = b.get("roughness")
        if isinstance(rough, dict) and rough.get("kind") in ("gaussian", "self_affine") and rough.get("seed") is None:
            rough["seed"] = 0
            notes.append(f"design: {body}.roughness has no seed; seed 0 is used so that every stage of the chain "
                         "sees the same surface")
    return sc, notes


def stage_scenario(scenario: Mapping, kind: str, load: Mapping | None = None, friction: Mapping | None = None) -> dict:
    """A stage's scenario: ``kind`` set, what the kind does not read left out.

    Parameters
    ----------
    scenario : mapping
        The point's scenario (:func:`point_scenario`).
    kind : str
        The run kind of the stage (a key of :data:`tribobem.runs.KINDS`).
    load, friction : mapping, optional
        Keys set in ``[load]`` / ``[friction]`` after the unread ones are left out.

    Returns
    -------
    dict
        A scenario the kind accepts: every section the kind does not read is removed, every
        section it reads in part keeps only the keys it reads, ``expected`` is dropped, and
        ``[output]`` asks for no fields, figures or report.
    """
    sc = copy.deepcopy(dict(scenario))
    sc["kind"] = kind
    sc.pop("expected", None)
    reads = KINDS[kind].reads()
    for section in SECTIONS:
        if section not in sc:
            continue
        keys = reads.get(section)
        if keys is None:
            sc.pop(section)
        elif keys != ALL and isinstance(sc[section], dict):
            sc[section] = {k: v for k, v in sc[section].items() if k in keys}
    for section, extra in (("load", load), ("friction", friction)):
        if extra:
            sc.setdefault(section, {})
            sc[section].update(copy.deepcopy(dict(extra)))
    sc["output"] = {"fields": "none", "figures": False, "report": False}
    return sc


def _run(scenario: dict, base_dir):
    from ..scenario import run_scenario  # deferred: solvers and outputs load on the worker

    kw = {"outdir": None, "progress": False, "quiet": True, "warn": False}  # warnings: the design's table
    if base_dir:
        kw["base_dir"] = base_dir
    return run_scenario(scenario, **kw).summary


def _rows_max(summary: Mapping, key: str = "max_pressure") -> float:
    vals = [_num(r.get(key)) for r in summary.get("steps") or [] if isinstance(r, Mapping)]
    vals = [v for v in vals if not math.isnan(v)]
    return max(vals) if vals else math.nan


def _zero_load_row(summary: Mapping, forces) -> Mapping | None:
    """The ramp's row at zero tangential load, or None.

    The solved tangential force of that state is zero only to round-off (1e-23 N, not 0.0),
    so the row is found by its place: the first row of a ramp whose first requested force is
    0, or the ``zero_force`` row a ramp reports when its first force already slides.
    """
    rows = [r for r in summary.get("steps") or [] if isinstance(r, Mapping)]
    if not rows:
        return None
    if rows[0].get("branch") == "zero_force":
        return rows[0]
    if forces and float(forces[0]) == 0.0 and rows[0].get("branch") == "ramp":
        return rows[0]
    return None


def run_chain(scenario: Mapping, chain: Mapping, base_dir=None) -> dict:
    """Run the chain of one design point.

    Parameters
    ----------
    scenario : mapping
        The point's scenario (:func:`point_scenario`); ``load.force`` is the clamp load and
        ``friction.coefficient`` the local friction coefficient.
    chain : mapping
        :meth:`~tribobem.design.spec.ChainOptions.as_dict` (forces in N).
    base_dir : path, optional
        Folder for the scenario's relative paths.

    Returns
    -------
    dict
        ``values`` (:data:`VALUE_KEYS` -> float, SI; NaN where not computed), ``flags``
        (``gross_slip``: the ramp reached gross slip), ``warnings`` (every warning of every
        stage, each once, with the stages that gave it), ``stages`` (stage -> ``status`` "ok" |
        "failed" | "skipped", ``message``, ``elapsed`` in s, ``converged``).
    """
    values = {k: math.nan for k in VALUE_KEYS}
    stages: dict = {}
    warns: dict[str, list[str]] = {}
    load = scenario.get("load") or {}
    if "force" not in load:
        raise InputError("load.force", "a design point needs the clamp load as load.force (e.g. \"10 uN\")")
    clamp = to_si(load["force"], "force", "load.force")
    values["clamp_load"] = clamp
    fr = scenario.get("friction") or {}
    mu = fr.get("coefficient")
    if mu is None:
        raise InputError("friction.coefficient", "a design point needs the friction coefficient (the ramp and the "
                                                 "hysteresis loop use it)")
    mu = float(mu)
    values["friction_coefficient"] = mu
    humid = "humidity" in scenario
    summaries: dict = {}

    def stage(name, sc):
        t0 = time.perf_counter()
        try:
            s = _run(sc, base_dir)
        except Exception as exc:  # the stage failed: recorded, the chain goes on
            stages[name] = {"status": "failed", "message": f"{type(exc).__name__}: {exc}",
                            "elapsed": time.perf_counter() - t0, "converged": None}
            return None
        stages[name] = {"status": "ok", "message": "", "elapsed": time.perf_counter() - t0,
                        "converged": bool(s.get("converged"))}
        for w in s.get("warnings") or []:
            warns.setdefault(str(w), []).append(name)
        if not s.get("converged"):
            warns.setdefault("did not converge (some step stopped before its tolerance)", []).append(name)
        summaries[name] = s
        return s

    # 1. normal contact at the clamp load
    s = stage("normal", stage_scenario(scenario, "normal", load={"force": load["force"]}))
    if s is None:  # the geometry or the scenario itself is bad: the other kinds would fail alike
        for name in ("pulloff", "ramp", "hysteresis"):
            stages[name] = {"status": "skipped", "message": "the normal stage failed", "elapsed": 0.0,
                            "converged": None}
    else:
        last = (s.get("steps") or [{}])[-1]
        f0p_normal = _num(last.get("repulsive_force"))
        if not humid:  # a humid point takes these from the humid ramp (below): this stage is dry
            values["contact_area"] = _num(last.get("contact_area"))
            values["max_pressure"] = _num(last.get("max_pressure"))
            values["repulsive_force"] = f0p_normal
            values["capillary_force"] = 0.0

        # 2. pull-off from the clamp load
        adh = scenario.get("adhesion") or {}
        sticky = humid or adhesion_model(adh) != "none"  # any registered stress law but none
        if chain.get("pulloff", True) and not sticky:
            values["pull_off_force"] = 0.0
            stages["pulloff"] = {"status": "skipped", "message": "no adhesion and no humidity: pull-off force 0 N",
                                 "elapsed": 0.0, "converged": None}
        elif chain.get("pulloff", True):
            lp = {k: v for k, v in load.items() if k != "force"}
            lp["preload"] = load["force"]
            s = stage("pulloff", stage_scenario(scenario, "pulloff", load=lp))
            if s is not None:
                values["pull_off_force"] = _num(s.get("pull_off_force"))
        else:
            stages["pulloff"] = {"status": "skipped", "message": "chain.pulloff = false", "elapsed": 0.0,
                                 "converged": None}

        # 3. tangential ramp to gross slip
        f0p = f0p_normal if not math.isnan(f0p_normal) else clamp
        tf = chain.get("tangential_forces", "auto")
        auto = tf == "auto"
        if auto:
            n = int(chain.get("auto_steps", 13))
            top = float(chain.get("auto_factor", 1.2)) * mu * max(clamp, f0p)
            tf = [top * i / (n - 1) for i in range(n)]
        elif humid and (not tf or float(tf[0]) != 0.0):
            # The humid state at zero tangential load is the ramp's first row; the ramp solves
            # that state anyway (the origin of the pre-sliding displacement), so this costs nothing.
            tf = [0.0, *tf]
        before_ramp = {w: list(st) for w, st in warns.items()}
        s = stage("ramp", stage_scenario(scenario, "partial_slip", load={"force": load["force"]},
                                         friction={"tangential_forces": tf}))
        if s is not None and auto and _first(s.get("static_friction_force")) is None and mu > 0:
            # adhesion or menisci carry F0+ above the clamp load: once more to factor x mu x F0+
            f0p_ramp = _num(s.get("repulsive_force"))
            if not math.isnan(f0p_ramp) and f0p_ramp > max(clamp, f0p):
                top = float(chain.get("auto_factor", 1.2)) * mu * f0p_ramp
                tf_first, tf = tf, [top * i / (n - 1) for i in range(n)]
                first = {w: list(st) for w, st in warns.items()}
                warns.clear()
                warns.update(before_ramp)  # the first pass's notes (e.g. "no gross slip") are superseded
                s2 = stage("ramp", stage_scenario(scenario, "partial_slip", load={"force": load["force"]},
                                                  friction={"tangential_forces": tf}))
                if s2 is None:  # keep the first pass, its forces and its notes
                    warns.clear()
                    warns.update(first)
                    tf = tf_first
                s = s2 if s2 is not None else s
        if s is not None:
            values["ramp_max_force"] = float(tf[-1]) if tf else math.nan
            for k in ("static_friction_force", "static_friction_ratio", "presliding_displacement"):
                values[k] = _num(s.get(k))
            if math.isnan(values["static_friction_force"]):
                warns.setdefault(f"design: the ramp ended at {tf[-1]:.4g} N before gross slip: no static friction "
                                 "force (give chain.tangential_forces up to above mu F0+)", []).append("ramp")
            if humid:
                row = _zero_load_row(s, tf)
                if row is not None:
                    for k in ("contact_area", "max_pressure", "repulsive_force", "capillary_force"):
                        values[k] = _num(row.get(k))
                else:
                    warns.setdefault("design: the humid ramp has no state at zero tangential load: contact_area, "
                                     "max_pressure, repulsive_force and capillary_force are not computed",
                                     []).append("ramp")

        # 4. hysteresis loop (lateral stiffness)
        path = chain.get("hysteresis")
        if path:
            s = stage("hysteresis", stage_scenario(scenario, "hysteresis", load={"force": load["force"]},
                                                   friction={"path": path}))
            if s is not None:
                table = s.get("lateral_stiffness") or []
                if table and isinstance(table[0], list):  # humid: one table per RH
                    table = table[0]
                for row in table or []:
                    if isinstance(row, Mapping) and row.get("point") in ("A", "B", "C"):
                        values[f"lateral_stiffness_{row['point']}"] = _num(row.get("stiffness"))
                if s.get("lateral_stiffness_error"):
                    warns.setdefault(f"design: lateral stiffness not fitted: {s['lateral_stiffness_error']}",
                                     []).append("hysteresis")
        else:
            stages["hysteresis"] = {"status": "skipped", "message": "chain.hysteresis = false", "elapsed": 0.0,
                                    "converged": None}

    peaks = [_rows_max(s) for s in summaries.values()]
    peaks = [p for p in peaks if not math.isnan(p)]
    values["peak_pressure"] = max(peaks) if peaks else math.nan
    gross = summaries.get("ramp", {}).get("gross_slip")
    return {"values": values, "flags": {"gross_slip": bool(_first(gross)) if gross is not None else None},
            "warnings": [f"{w} [{', '.join(dict.fromkeys(st))}]" for w, st in warns.items()], "stages": stages}


def read_detail(outdir, h: str) -> dict | None:
    """The full result of one design point (``OUTDIR/design/<hash>.json``), or None.

    Parameters
    ----------
    outdir : path
        The design folder.
    h : str
        The point's hash.

    Returns
    -------
    dict or None
        What :class:`DesignPointRunner` wrote: ``values`` (SI), ``warnings``, ``stages``,
        ``flags``, ``notes``; None when the file is missing or unreadable (a point run on a
        worker without the design folder, or never run).
    """
    path = Path(outdir) / DETAIL_DIR / f"{h}.json"
    try:
        data = json.loads(path.read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return None
    return data if isinstance(data, dict) and data.get("hash") == h else None


class DesignPointRunner:
    """The callable :func:`tribobem.sweep.run_sweep` runs on every design point.

    Picklable (plain attributes), so it runs on Dask workers.  Its name in the sweep's
    records and hashes is ``callable:tribobem.design.chain:DesignPointRunner``.

    Parameters
    ----------
    base : dict
        The base scenario (units as written).
    chain : dict
        :meth:`~tribobem.design.spec.ChainOptions.as_dict`.
    tasks : list of (str, dict)
        ``(hash, overrides)`` of every point (:meth:`~tribobem.design.spec.DesignSweep.tasks`),
        to name each point's detail file.
    outdir : path
        The design folder; each point writes ``OUTDIR/design/<hash>.json`` (on a remote
        cluster the folder must be shared with the workers, else the detail files are lost and
        the table has no warnings text for those points).
    base_dir : str, optional
        Folder for the scenario's relative paths.
    """

    def __init__(self, base: Mapping, chain: Mapping, tasks, outdir, base_dir: str | None = None):
        self.__qualname__ = type(self).__qualname__  # the sweep names its runner by it
        self.base = dict(base)
        self.chain = dict(chain)
        self.hashes = {_canonical(o): h for h, o in tasks}
        self.outdir = str(Path(outdir).resolve())
        self.base_dir = base_dir

    def __call__(self, point: Mapping) -> dict:
        """Run one point.

        Parameters
        ----------
        point : mapping
            The point's dotted overrides (units as written).

        Returns
        -------
        dict
            The point's scalars (SI): :data:`VALUE_KEYS`, ``n_warnings``, ``gross_slip`` and
            ``exceeds_hardness`` is left to the table (targets are not part of a point).

        Raises
        ------
        InputError
            The point's scenario is not a valid design point (no clamp load or friction
            coefficient, several RHs).
        DesignPointError
            A stage failed; the message names each failed stage and its error (the other
            stages' numbers are kept in the detail file).
        """
        h = self.hashes.get(_canonical(dict(point)))
        scenario, notes = point_scenario(self.base, point)
        detail = run_chain(scenario, self.chain, self.base_dir)
        detail["warnings"] = notes + detail["warnings"]
        failed = {k: v["message"] for k, v in detail["stages"].items() if v["status"] == "failed"}
        if h is not None:
            atomic_write_text(Path(self.outdir) / DETAIL_DIR / f"{h}.json",
                              json.dumps(_jsonable({"hash": h, "point": dict(point), **detail}), indent=1) + "\n")
        if failed:
            raise DesignPointError("; ".join(f"stage {k} failed: {m}" for k, m in failed.items()))
        out = dict(detail["values"])
        out["n_warnings"] = len(detail["warnings"])
        out["gross_slip"] = detail["flags"]["gross_slip"]
        return out
