"""Friction loops: a measured loop file, the last pre-sliding branch, and the comparison of a
measured loop with a simulated one by their lateral stiffness (Paper F, section 5).

A measured loop is a text table (CSV) with a displacement and a force column whose units are in
the header::

    # comments (lines starting with '#') and blank lines are skipped
    displacement (um), force (mN)
    0.000, 0.012
    0.013, 0.851
    ...

Separators: ``,``, ``;`` or a tab.  Units in ``(...)`` or ``[...]``, parsed with pint
(:mod:`tribobem.units`): ``um``, ``µm``, ``micron``, ``nm``, ``mN``, ``uN``, ``N`` ...  Other
columns (time, normal force) are ignored.  Column names: ``displacement`` (also ``disp``,
``delta``, ``x``), ``force`` (also ``friction``, ``F``, ``Fx``, ``Q``).

Lateral stiffness "the same way" for both loops (:func:`fit_branch`, :func:`stiffness_points`):

1. the branch is the LAST rising branch of the record: from a displacement minimum (turning
   point, found with a 5 % hysteresis threshold so that noise makes no reversals) to the next
   maximum (or the end of the record), spanning at least 3/4 of the displacement range;
2. its pre-sliding part: when the branch ends in gross sliding (the force over the last quarter
   of its displacement rises by less than 5 % of the branch's force change: a plateau), only
   the points before the force first reaches ``plateau_fraction`` (98 %) of the plateau are
   kept; a branch without a plateau (force control below mu P) is kept whole;
3. Paper F Eq. 3, ``F - F_turn = c1 (1 - (1 - c2 (delta - delta_turn))^n)``, is fitted from the
   turning point by :func:`tribobem.runs.hysteresis.lateral_stiffness_fit` (the runner's fit:
   same model and bounds), polished from a grid of starts (its single start can stop in a local
   minimum on a window cut before the plateau);
4. K_L = dF/d(delta) of the fit, at the displacement where the FIT reaches the force of each
   point A, B, C: F = -0.5, 0, +0.5 times the loop's force scale.

The force scale is ``mu F0+`` for a simulated loop (friction coefficient times the repulsive
normal force of its summary.json) and ``F* = max |F|`` of the record for a measured loop (its
own extremes: a measured loop has no separate normal force and friction coefficient).  For a
loop that reaches gross sliding both are the sliding force.

Why step 2: in a displacement-controlled loop most of the branch can be gross sliding (Paper
F's strokes are ~20 x the Mindlin pre-sliding distance).  Eq. 3 with ``c2 <= 1/delta_max``
cannot saturate inside the fitted range, so a fit over the whole branch bends through the
plateau and underestimates K_L severalfold.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..errors import InputError
from ..output.summary import read_summary
from ..units import UnitMismatch, convert

__all__ = [
    "MIN_POINTS", "MIN_FIT_POINTS", "Loop", "BranchFit", "LoopComparison",
    "read_loop", "loop_from_summary", "turning_points", "last_branch", "fit_branch", "stiffness_points",
    "compare_loops", "fit_eq3", "STIFFNESS_POINTS",
]

#: A measured loop needs at least this many points.
MIN_POINTS = 10
#: Paper F's points on the branch from -F* to +F*: F_x / (mu F0+) (measured loops: / max |F|).
STIFFNESS_POINTS = {"A": -0.5, "B": 0.0, "C": 0.5}
#: Points (turning point included) of the pre-sliding part needed for the Eq. 3 fit.
MIN_FIT_POINTS = 5
#: Reversals of the displacement smaller than this fraction of its range are noise.
REVERSAL_THRESHOLD = 0.05
#: The chosen branch spans at least this fraction of the displacement range.
MIN_BRANCH_SPAN = 0.75

_DISPLACEMENT_NAMES = ("displacement", "disp", "delta", "\u03b4", "x", "dx", "delta_x", "\u03b4x", "\u03b4_x", "d")
_FORCE_NAMES = ("force", "friction", "f", "fx", "f_x", "q", "ft", "f_t")
_HEADER_RE = re.compile(r"^\s*(?P<name>[^(\[]*?)\s*(?:[(\[]\s*(?P<unit>[^)\]]*?)\s*[)\]])?\s*$")


@dataclass
class Loop:
    """A friction loop: displacement and force along the sliding direction, in record order.

    Attributes
    ----------
    displacement : ndarray
        m.
    force : ndarray
        N.
    source : str
        File (or result folder) it came from.
    force_scale : float
        N: the scale of the points A, B, C (``mu F0+`` simulated, ``max |F|`` measured).
    normalisation : str
        How ``force_scale`` was obtained (printed with the comparison).
    kind : {"measured", "simulated"}
    units : dict
        Units of the file's columns (measured loops).
    lines : ndarray of int
        Line number of each point in the file (measured loops; 0 otherwise).
    """

    displacement: np.ndarray
    force: np.ndarray
    source: str
    force_scale: float
    normalisation: str
    kind: str = "measured"
    units: dict = field(default_factory=dict)
    lines: np.ndarray | None = None

    def __len__(self) -> int:
        return len(self.force)


@dataclass
class BranchFit:
    """The Paper F Eq. 3 fit of a loop's last pre-sliding branch.

    Attributes
    ----------
    start, end : int
        Indices (in the loop) of the turning point and of the last point of the branch.
    fit_end : int
        Index of the last point used in the fit (the pre-sliding part ends there).
    turn_force, turn_displacement : float
        F and delta at the turning point (N, m).
    c1, c2, n : float
        Eq. 3 parameters (N, 1/m, -).
    sliding : bool
        The branch ends in gross sliding (a force plateau).
    plateau_force : float
        F - F_turn on the plateau (N); the branch's last F - F_turn when ``sliding`` is False.
    points : int
        Points in the fit (turning point included).
    rms_residual : float
        rms of the fit residual (N).
    """

    start: int
    end: int
    fit_end: int
    turn_force: float
    turn_displacement: float
    c1: float
    c2: float
    n: float
    sliding: bool
    plateau_force: float
    points: int
    rms_residual: float

    def force(self, delta):
        """F (N) of the fit at the absolute displacement ``delta`` (m).

        Parameters
        ----------
        delta : float or array_like
            Absolute displacement (m), the loop's own coordinate.

        Returns
        -------
        float or ndarray
            F_turn + c1 (1 - (1 - c2 (delta - delta_turn))^n) (N); constant beyond saturation.
        """
        x = np.clip(1.0 - self.c2 * (np.asarray(delta, float) - self.turn_displacement), 0.0, None)
        return self.turn_force + self.c1 * (1.0 - x ** self.n)

    def stiffness_at_displacement(self, delta):
        """K_L = dF/d(delta) (N/m) of the fit at the absolute displacement ``delta`` (m).

        Parameters
        ----------
        delta : float or array_like
            Absolute displacement (m), the loop's own coordinate.

        Returns
        -------
        float or ndarray
            c1 c2 n (1 - c2 (delta - delta_turn))^(n - 1) (N/m).
        """
        x = np.clip(1.0 - self.c2 * (np.asarray(delta, float) - self.turn_displacement), 1e-12, None)
        return self.c1 * self.c2 * self.n * x ** (self.n - 1.0)

    def displacement_at(self, force: float) -> float:
        """Absolute displacement (m) where the fit reaches ``force`` (N); NaN outside the fit.

        Parameters
        ----------
        force : float
            Force (N), the loop's own coordinate.

        Returns
        -------
        float
            Displacement (m); NaN where ``force - F_turn`` is outside [0, c1).
        """
        rel = (float(force) - self.turn_force) / self.c1
        if not (0.0 <= rel < 1.0):
            return math.nan
        return self.turn_displacement + (1.0 - (1.0 - rel) ** (1.0 / self.n)) / self.c2

    def as_dict(self) -> dict:
        """The fit as a plain dict (field name -> value), for JSON output."""
        return {k: getattr(self, k) for k in ("start", "end", "fit_end", "turn_force", "turn_displacement", "c1",
                                              "c2", "n", "sliding", "plateau_force", "points", "rms_residual")}


# ----------------------------------------------------------------------------- reading
def _err(path, line, message) -> InputError:
    where = f"{path}" if line is None else f"{path}, line {line}"
    return InputError(where, message)


def _is_number(text: str) -> bool:
    try:
        float(text)
    except ValueError:
        return False
    return True


def _match(name: str, names) -> bool:
    low = name.strip().lower().replace(" ", "_")
    return low in names or any(low.startswith(n) for n in names if len(n) > 2)


def _unit_factor(path, line, column: str, unit: str | None, dimension: str, example: str) -> float:

    if unit is None or not unit.strip():
        raise _err(path, line, f"column {column!r} has no unit: write it in the header as {example}")
    try:
        factor = convert(f"1 {unit.strip()}", dimension)
    except UnitMismatch as exc:
        what = "a length" if dimension == "length" else "a force"
        raise _err(path, line, f"column {column!r}: unit {unit.strip()!r} is not {what} ({exc})") from None
    if not (math.isfinite(factor) and factor > 0):
        raise _err(path, line, f"column {column!r}: unit {unit.strip()!r} is not usable")
    return factor


def read_loop(path) -> Loop:
    """Read a measured friction loop (CSV with units in the header; see the module docstring).

    Parameters
    ----------
    path : path-like

    Returns
    -------
    Loop
        Displacement (m) and force (N) in file order; ``force_scale = max |F|``.

    Raises
    ------
    FileNotFoundError
        The file does not exist.
    InputError
        Naming the file and the line: no header, a column without a unit or with a unit that is
        not a length / a force, a missing column, a non-numeric, NaN or infinite value, fewer
        than :data:`MIN_POINTS` points, a constant displacement or force.
    """
    path = Path(path)
    if not path.exists():
        raise FileNotFoundError(f"measured loop {path} not found")
    if path.is_dir():
        raise _err(path, None, "is a folder, not a loop file (CSV)")
    try:
        text = path.read_text(encoding="utf-8-sig")
    except UnicodeDecodeError as exc:
        raise _err(path, None, f"is not a UTF-8 text file ({exc.reason} at byte {exc.start})") from None
    lines = [(i + 1, ln.strip()) for i, ln in enumerate(text.splitlines())]
    lines = [(i, ln) for i, ln in lines if ln and not ln.startswith("#")]
    if not lines:
        raise _err(path, None, "is empty: expected a header such as 'displacement (um), force (mN)' and data lines")
    hline, header = lines[0]
    sep = next((s for s in (",", ";", "\t") if s in header), None)
    if sep is None:
        raise _err(path, hline, f"header {header!r} needs two columns separated by ',', ';' or a tab, e.g. "
                                "'displacement (um), force (mN)'")
    cols = [c.strip() for c in header.split(sep)]
    parsed = []
    for c in cols:
        m = _HEADER_RE.match(c)
        parsed.append((m.group("name"), m.group("unit")) if m else (c, None))
    if _is_number(cols[0]):
        raise _err(path, hline, "has no header: the first line must name the columns with their units, e.g. "
                                "'displacement (um), force (mN)'")
    idisp = [k for k, (name, _) in enumerate(parsed) if _match(name, _DISPLACEMENT_NAMES)]
    iforce = [k for k, (name, _) in enumerate(parsed) if _match(name, _FORCE_NAMES) and k not in idisp]
    if len(idisp) != 1 or len(iforce) != 1:
        raise _err(path, hline, f"header {header!r}: need exactly one displacement column and one force column "
                                f"(e.g. 'displacement (um), force (mN)'), found columns {[p[0] for p in parsed]}")
    kd, kf = idisp[0], iforce[0]
    fd = _unit_factor(path, hline, parsed[kd][0], parsed[kd][1], "length", "'displacement (um)'")
    ff = _unit_factor(path, hline, parsed[kf][0], parsed[kf][1], "force", "'force (mN)'")
    need = max(kd, kf) + 1
    d, f, where = [], [], []
    for ln, row in lines[1:]:
        parts = [p.strip() for p in row.split(sep)]
        if len(parts) < need:
            raise _err(path, ln, f"{row!r} has {len(parts)} column(s); the header has {len(cols)}")
        vals = []
        for k, label in ((kd, "displacement"), (kf, "force")):
            try:
                v = float(parts[k])
            except ValueError:
                raise _err(path, ln, f"{label} {parts[k]!r} is not a number") from None
            if not math.isfinite(v):
                raise _err(path, ln, f"{label} is {parts[k]!r}: NaN and infinite values are not allowed")
            vals.append(v)
        d.append(vals[0] * fd)
        f.append(vals[1] * ff)
        where.append(ln)
    if len(d) < MIN_POINTS:
        raise _err(path, None, f"has {len(d)} data point(s); a loop needs at least {MIN_POINTS}")
    d, f = np.array(d), np.array(f)
    if float(np.ptp(d)) <= 0.0:
        raise _err(path, None, "the displacement is constant: not a loop")
    if float(np.ptp(f)) <= 0.0:
        raise _err(path, None, "the force is constant: not a loop")
    scale = float(np.max(np.abs(f)))
    return Loop(d, f, str(path), scale, f"F* = max |F| of the measured record = {scale:.6g} N",
                kind="measured", units={"displacement": parsed[kd][1], "force": parsed[kf][1]},
                lines=np.array(where))


def loop_from_summary(result) -> Loop:
    """The simulated loop of a hysteresis result, projected on the path direction.

    Parameters
    ----------
    result : path-like or dict
        A hysteresis run's result folder (with summary.json), the file, or the summary dict.

    Returns
    -------
    Loop
        Displacement (m) and force (N) per step, ``kind="simulated"``, with
        ``force_scale = mu F0+`` (``max |F|`` when the summary lacks mu or F0+).

    Raises
    ------
    FileNotFoundError
        No such result.
    InputError
        A folder without summary.json, a run of another kind, or fewer than
        :data:`MIN_POINTS` steps.
    """
    if isinstance(result, dict):
        summary, source = result, "summary"
    else:
        p = Path(result)
        if not p.exists():
            raise FileNotFoundError(f"result {p} not found")
        if p.is_dir() and not (p / "summary.json").is_file():
            raise InputError("result", f"{p} holds no summary.json: give the result folder of a hysteresis run")
        summary, source = read_summary(p), str(p)
    kind = summary.get("kind")
    if kind != "hysteresis":
        raise InputError("result", f"{source} is a {kind!r} run; compare-loop needs a 'hysteresis' run "
                                   "(a tangential force or displacement cycle)")
    steps = summary.get("steps") or []
    if len(steps) < MIN_POINTS:
        raise InputError("result", f"{source} has {len(steps)} step(s); a loop needs at least {MIN_POINTS}")
    direction = ((summary.get("inputs") or {}).get("friction") or {}).get("direction") or 0.0
    t = math.radians(float(direction))
    c, s = math.cos(t), math.sin(t)

    def col(key):
        return np.array([float(st.get(key) or 0.0) for st in steps])

    F = col("tangential_force_x") * c + col("tangential_force_y") * s
    D = col("displacement_x") * c + col("displacement_y") * s
    mu = summary.get("friction_coefficient")
    f0p = summary.get("repulsive_force")
    if mu and f0p and mu > 0 and f0p > 0:
        scale = float(mu) * float(f0p)
        text = f"mu F0+ = {float(mu):g} x {float(f0p):.6g} N = {scale:.6g} N (friction coefficient x repulsive force)"
    else:
        scale = float(np.max(np.abs(F)))
        text = f"F* = max |F| of the simulated loop = {scale:.6g} N"
    return Loop(D, F, source, scale, text, kind="simulated")


# ----------------------------------------------------------------------------- branches
def turning_points(displacement, threshold: float = REVERSAL_THRESHOLD) -> list[tuple[int, str]]:
    """Reversals of a displacement record: ``[(index, "min" | "max"), ...]`` between
    ``(0, "start")`` and ``(n - 1, "end")``.

    A reversal counts once the record has moved back from its running extreme by more than
    ``threshold`` times the displacement range.  Long records (400 points or more) are first
    smoothed by a running median over about n/200 points (noise and single spikes make no
    reversal); each reversal is then placed at the extreme of the raw record within that width.

    Parameters
    ----------
    displacement : array_like
        Displacement record (any unit), in record order.
    threshold : float
        Smallest reversal, as a fraction of the displacement range.

    Returns
    -------
    list of (int, str)
        ``(index, "start" | "min" | "max" | "end")`` in record order; empty for an empty record.
    """
    raw = np.asarray(displacement, float)
    n = len(raw)
    if n == 0:
        return []
    half = n // 400
    if half > 0:
        from scipy.ndimage import median_filter

        d = median_filter(raw, size=2 * half + 1, mode="nearest")
    else:
        d = raw
    thr = threshold * float(np.ptp(d))
    found = []
    lo = hi = 0
    direction = 0
    for i in range(1, n):
        if direction == 0:
            if d[i] < d[lo]:
                lo = i
            if d[i] > d[hi]:
                hi = i
            if d[i] - d[lo] > thr:
                direction = 1
                if lo > 0:
                    found.append((lo, "min"))
                hi = i
            elif d[hi] - d[i] > thr:
                direction = -1
                if hi > 0:
                    found.append((hi, "max"))
                lo = i
        elif direction > 0:
            if d[i] >= d[hi]:
                hi = i
            elif d[hi] - d[i] > thr:
                found.append((hi, "max"))
                direction, lo = -1, i
        else:
            if d[i] <= d[lo]:
                lo = i
            elif d[i] - d[lo] > thr:
                found.append((lo, "min"))
                direction, hi = 1, i
    out = [(0, "start")]
    for i, kind in found:
        a, b = max(i - half, 0), min(i + half + 1, n)
        j = a + int(np.argmin(raw[a:b]) if kind == "min" else np.argmax(raw[a:b]))
        if out[-1][0] < j < n - 1:
            out.append((j, kind))
    out.append((n - 1, "end"))
    return out


def last_branch(displacement, source: str = "loop") -> tuple[int, int]:
    """(start, end) indices of the last rising branch from a displacement minimum (turning
    point) to the next maximum, spanning at least :data:`MIN_BRANCH_SPAN` of the range.

    Parameters
    ----------
    displacement : array_like
        Displacement record, in record order.
    source : str
        Name of the record, for the error message.

    Returns
    -------
    tuple of int
        Indices of the turning point and of the branch's end.

    Raises
    ------
    InputError
        No such branch (not a full loop).
    """
    d = np.asarray(displacement, float)
    tp = turning_points(d)
    rng = float(np.ptp(d))
    best = None
    for k, (i, kind) in enumerate(tp):
        if kind != "min":
            continue
        nxt = next(((j, kj) for j, kj in tp[k + 1:] if kj in ("max", "end")), None)
        if nxt is None:
            continue
        j = nxt[0]
        if j > i and d[j] - d[i] >= MIN_BRANCH_SPAN * rng:
            best = (i, j)
    if best is None:
        raise InputError(source, "no rising branch from a displacement minimum to a maximum spanning "
                                 f"{MIN_BRANCH_SPAN:.0%} of the displacement range: not a full loop")
    return best


def _eq3(x, c1, c2, n):
    return c1 * (1.0 - np.clip(1.0 - c2 * x, 0.0, None) ** n)


def fit_eq3(x, y) -> tuple[tuple[float, float, float], float]:
    """Paper F Eq. 3 through the origin, F = c1 (1 - (1 - c2 d)^n), fitted to a branch.

    A single start near saturation ((1 - c2 d_max) small, n = 1.5) is right for a branch that
    ends at gross slip, but on a pre-sliding window cut before the plateau it can stop in a local
    minimum.  So: bounds c1 in [0.5, 10] x max F, c2 in (0, 1/d_max], n in [1, 5]; with c1
    eliminated (it enters linearly), (c2, n) is scanned on a grid, and the best grid point and the
    saturation start are refined by bounded least squares; the smaller residual wins.  The
    simulated loops (:func:`tribobem.runs.hysteresis.lateral_stiffness_fit`) and measured loops
    are fitted by this one function.

    Parameters
    ----------
    x, y : array_like
        Displacement (m) and force (N) from the turning point, both increasing from 0.

    Returns
    -------
    params : tuple of float
        (c1 (N), c2 (1/m), n (-)).
    rms : float
        rms residual of the fit (N).

    Raises
    ------
    InputError
        A branch without a positive displacement and force.
    """
    from scipy.optimize import least_squares

    x = np.asarray(x, float)
    y = np.asarray(y, float)
    dmax, fmax = float(x.max()), float(y.max())
    if not (dmax > 0 and fmax > 0):
        raise InputError("lateral_stiffness", "the branch has no rising force and displacement to fit "
                                              f"(largest displacement {dmax:.3g} m, force {fmax:.3g} N)")
    lo = np.array([0.5 * fmax, 1e-6 / dmax, 1.0])
    hi = np.array([10.0 * fmax, 1.0 / dmax, 5.0])

    def sse(p):
        r = _eq3(x, *p) - y
        return float(r @ r)

    starts = [np.array([fmax * 1.02, 0.98 / dmax, 1.5])]  # near saturation, Mindlin's exponent
    best_grid, best_val = None, math.inf
    for t in np.linspace(0.05, 1.0, 40):
        for n in np.linspace(1.0, 5.0, 33):
            g = 1.0 - np.clip(1.0 - t / dmax * x, 0.0, None) ** n
            gg = float(g @ g)
            if gg <= 0:
                continue
            c1 = float(np.clip((g @ y) / gg, lo[0], hi[0]))
            val = sse((c1, t / dmax, n))
            if val < best_val:
                best_grid, best_val = np.array([c1, t / dmax, n]), val
    if best_grid is not None:
        starts.append(best_grid)
    if not starts:
        raise InputError("lateral_stiffness", "the Paper F Eq. 3 fit failed")
    scale = np.array([fmax, 1.0 / dmax, 1.0])
    best, best_val = None, math.inf
    for p0 in starts:
        p0 = np.clip(p0, lo, hi)
        try:
            res = least_squares(lambda q: (_eq3(x, *(q * scale)) - y) / fmax, p0 / scale, bounds=(lo / scale, hi / scale),
                                x_scale="jac", max_nfev=4000)
            cand = res.x * scale
        except ValueError:
            cand = p0
        for c in (cand, p0):
            v = sse(c)
            if v < best_val:
                best, best_val = c, v
    return tuple(float(v) for v in best), float(math.sqrt(best_val / len(x)))


def fit_branch(loop: Loop, plateau_fraction: float = 0.98) -> BranchFit:
    """Fit Paper F Eq. 3 to the pre-sliding part of the loop's last rising branch (see the module
    docstring for the rules, identical for measured and simulated loops).

    Parameters
    ----------
    loop : Loop
        A measured or simulated loop.
    plateau_fraction : float
        In (0.5, 1): on a branch that ends in gross sliding, the pre-sliding part ends where
        F - F_turn first reaches this fraction of the plateau.

    Returns
    -------
    BranchFit

    Raises
    ------
    InputError
        No full rising branch, or fewer than :data:`MIN_FIT_POINTS` points before gross sliding
        (a simulated loop needs more steps per cycle; the message says how many were found),
        or ``plateau_fraction`` outside (0.5, 1).
    """
    if not (0.5 < plateau_fraction < 1.0):
        raise InputError("plateau_fraction", f"must be in (0.5, 1), got {plateau_fraction!r}")
    d, F = loop.displacement, loop.force
    i0, i1 = last_branch(d, loop.source)
    dd = d[i0:i1 + 1] - d[i0]
    dF = F[i0:i1 + 1] - F[i0]
    span = float(dd.max())
    total = float(np.max(dF))
    if not (span > 0 and total > 0):
        raise InputError(loop.source, "the last rising branch has no force increase: not a friction loop")
    tail = dd >= 0.75 * span
    sliding = False
    plateau = float(dF[-1])
    if np.count_nonzero(tail) >= 3 and np.ptp(dd[tail]) > 0:
        slope = float(np.polyfit(dd[tail], dF[tail], 1)[0])
        if slope * 0.25 * span < 0.05 * total:
            sliding = True
            plateau = float(np.median(dF[tail]))
    if sliding:
        above = np.flatnonzero(dF >= plateau_fraction * plateau)
        cut = int(above[0]) if above.size else len(dF)
    else:
        cut = len(dF)
    cut = max(cut, 1)
    if cut < MIN_FIT_POINTS:
        raise InputError(loop.source, f"only {cut} point(s) (turning point included) of the last rising branch lie "
                                      f"before gross sliding; the Eq. 3 fit needs {MIN_FIT_POINTS}: "
                                      + ("use more steps per cycle (or a smaller stroke)" if loop.kind == "simulated"
                                         else "the loop is sampled too coarsely in the pre-sliding regime"))
    x, y = dd[:cut], dF[:cut]
    (c1, c2, n), rms = fit_eq3(x, y)
    return BranchFit(int(i0), int(i1), int(i0 + cut - 1), float(F[i0]), float(d[i0]), float(c1), float(c2),
                     float(n), sliding, plateau, int(cut), rms)


def stiffness_points(loop: Loop, fit: BranchFit, points=None) -> list[dict]:
    """K_L of the fit at the points A, B, C (``F / force_scale`` = -0.5, 0, 0.5 by default).

    Parameters
    ----------
    loop : Loop
        The loop (its ``force_scale``).
    fit : BranchFit
        The Eq. 3 fit of its last rising branch (:func:`fit_branch`).
    points : mapping, optional
        Point name -> ``F / force_scale``; default :data:`STIFFNESS_POINTS`.

    Returns
    -------
    list of dict
        One row per point: ``point``, ``force_ratio``, ``force`` (N), ``displacement`` (m,
        where the fit reaches that force; NaN when the point is not on the fitted pre-sliding
        part), ``stiffness`` (N/m, NaN likewise).
    """
    points = STIFFNESS_POINTS if points is None else points
    top = fit.turn_force + float(np.max(loop.force[fit.start:fit.fit_end + 1] - fit.turn_force))
    rows = []
    for name, ratio in points.items():
        Ft = float(ratio) * loop.force_scale
        dpt = fit.displacement_at(Ft) if fit.turn_force < Ft <= top + 1e-9 * abs(top) else math.nan
        k = float(fit.stiffness_at_displacement(dpt)) if math.isfinite(dpt) else math.nan
        rows.append({"point": name, "force_ratio": float(ratio), "force": Ft, "displacement": dpt, "stiffness": k})
    return rows


# ----------------------------------------------------------------------------- comparison
@dataclass
class LoopComparison:
    """Measured and simulated loops fitted the same way (:func:`compare_loops`).

    Attributes
    ----------
    simulated, measured : Loop
        The two loops.
    simulated_fit, measured_fit : BranchFit
        Their Eq. 3 fits.
    rows : list of dict
        One per point A, B, C: ``point``, ``force_ratio``, ``simulated`` and ``measured``
        (rows of :func:`stiffness_points`) and ``ratio`` = K_sim / K_meas.
    figure : pathlib.Path or None
        The overlay figure once drawn (:func:`tribobem.output.loops.comparison_figure`).
    """

    simulated: Loop
    measured: Loop
    simulated_fit: BranchFit
    measured_fit: BranchFit
    rows: list
    #: The overlay figure once drawn (:func:`tribobem.output.loops.comparison_figure`).
    figure: Path | None = None

    def as_dict(self) -> dict:
        """The comparison as plain JSON types.

        Returns
        -------
        dict
            ``simulated`` and ``measured`` (source, points, force scale, normalisation, units,
            fit, stiffness rows), ``points`` (per point the two K_L in N/m and their ratio),
            ``ratio`` (what the ratio is) and ``figure`` (path or None).
        """
        def side(loop, fit, pts):
            return {"source": loop.source, "points_in_record": len(loop), "force_scale": loop.force_scale,
                    "normalisation": loop.normalisation, "units": loop.units, "fit": fit.as_dict(),
                    "stiffness": pts}

        return {
            "simulated": side(self.simulated, self.simulated_fit, [r["simulated"] for r in self.rows]),
            "measured": side(self.measured, self.measured_fit, [r["measured"] for r in self.rows]),
            "points": [{"point": r["point"], "force_ratio": r["force_ratio"],
                        "simulated_stiffness": r["simulated"]["stiffness"],
                        "measured_stiffness": r["measured"]["stiffness"], "ratio": r["ratio"]} for r in self.rows],
            "ratio": "simulated / measured",
            "figure": str(self.figure) if self.figure else None,
        }


def compare_loops(result, measured, plateau_fraction: float = 0.98) -> LoopComparison:
    """Compare a simulated hysteresis loop with a measured one by K_L at A, B, C.

    Parameters
    ----------
    result : path-like or dict
        Result folder of a hysteresis run (or its summary.json, or the summary dict).
    measured : path-like or Loop
        Measured loop file (:func:`read_loop`) or a loop.
    plateau_fraction : float
        The pre-sliding part of a branch ends where the force first reaches this fraction of
        its plateau (:func:`fit_branch`).

    Returns
    -------
    LoopComparison
        ``rows``: one per point with ``simulated`` and ``measured`` (see
        :func:`stiffness_points`) and ``ratio`` = K_sim / K_meas.
    """
    sim = loop_from_summary(result)
    meas = measured if isinstance(measured, Loop) else read_loop(measured)
    fs = fit_branch(sim, plateau_fraction)
    fm = fit_branch(meas, plateau_fraction)
    ps, pm = stiffness_points(sim, fs), stiffness_points(meas, fm)
    rows = []
    for a, b in zip(ps, pm):
        ratio = a["stiffness"] / b["stiffness"] if (math.isfinite(a["stiffness"]) and math.isfinite(b["stiffness"])
                                                    and b["stiffness"] != 0) else math.nan
        rows.append({"point": a["point"], "force_ratio": a["force_ratio"], "simulated": a, "measured": b,
                     "ratio": ratio})
    return LoopComparison(sim, meas, fs, fm, rows)
