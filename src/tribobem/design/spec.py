"""The design file: base scenario, design parameters, chain options and targets.

A design file (TOML) is a sweep file (:mod:`tribobem.sweep`) with two more tables::

    name = "burl_design"
    scenario = "base.toml"            # or an inline [base] scenario table

    [parameters]                      # dotted scenario keys -> values (cartesian product)
    "body2.shape.radius" = ["5 um", "10 um"]
    "humidity.rh" = ["dry", 0.5]      # "dry": the point runs without [humidity]

    [chain]                           # what each point runs (all optional)
    tangential_forces = "auto"        # or a list / {start, stop, num} (N)
    hysteresis = true                 # or false, or {amplitude, cycles, steps}

    [targets]                         # what the ranking compares (never recomputes a point)
    static_friction_force = { min = "2 uN" }
    pull_off_force = { max = "1 uN" } # on |pull-off force| (the magnitude)
    lateral_stiffness_B = { min = "5000 N/m" }
    hardness = "5 GPa"                # peak pressure of the chain <= hardness

:class:`DesignSpec` reads and checks it; :meth:`DesignSpec.sweep` turns it into the
:class:`~tribobem.sweep.SweepSpec` that :func:`~tribobem.sweep.run_sweep` runs, whose point
hashes cover the base scenario, the point, the chain options, the point's effective solver
options and the solver version, but not the targets (changing a target re-ranks the finished
points without recomputing them).
"""

from __future__ import annotations

import math
import os
import tomllib
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path

from ..errors import InputError
from ..sweep import SweepSpec, point_hash, solver_options
from ..units import to_si

__all__ = ["DesignSpec", "DesignSweep", "Target", "ChainOptions", "load_design", "DESIGN_KEYS", "TARGET_COLUMNS",
           "DESIGN_VERSION"]

#: Version of the design chain; part of every point hash (bump it when the chain computes
#: something else, so old points are recomputed).
DESIGN_VERSION = 3  # 2: a humid point's contact area, pressures and forces are its humid state;
#                    3: the automatic ramp's superseded first pass leaves no warning

#: Top-level keys of a design file.
DESIGN_KEYS = {"name", "description", "scenario", "base", "parameters", "points", "chain", "targets",
               "scheduler", "workers"}

#: Design-table columns a target may name -> their dimension (:data:`tribobem.units.DIMENSIONS`).
TARGET_COLUMNS = {
    "static_friction_force": "force",
    "static_friction_ratio": "dimensionless",
    "presliding_displacement": "length",
    "lateral_stiffness_A": "stiffness",
    "lateral_stiffness_B": "stiffness",
    "lateral_stiffness_C": "stiffness",
    "pull_off_force": "force",
    "contact_area": "area",
    "max_pressure": "pressure",
    "peak_pressure": "pressure",
    "repulsive_force": "force",
}
#: Target aliases: ``lateral_stiffness`` is the stiffness at Paper F's point B (F_x = 0).
_ALIASES = {"lateral_stiffness": "lateral_stiffness_B"}
#: Columns whose targets compare the magnitude (pull-off forces are negative numbers).
MAGNITUDE_COLUMNS = {"pull_off_force"}

_CHAIN_KEYS = {"tangential_forces", "auto_factor", "auto_steps", "hysteresis", "pulloff"}
_HYSTERESIS_KEYS = {"control", "amplitude", "stroke", "cycles", "steps"}


@dataclass(frozen=True)
class Target:
    """One target of the ranking.

    Attributes
    ----------
    column : str
        The design-table column (:data:`TARGET_COLUMNS`), or ``"hardness"``: the chain's peak
        pressure must not exceed ``max``.
    min, max : float or None
        Bounds in SI units (N, m, m^2, Pa, N/m); None: no bound on that side.  For
        ``pull_off_force`` they bound the magnitude ``|pull-off force|``.
    """

    column: str
    min: float | None = None
    max: float | None = None

    @property
    def value_column(self) -> str:
        """The table column the target reads (``peak_pressure`` for ``hardness``)."""
        return "peak_pressure" if self.column == "hardness" else self.column

    @property
    def magnitude(self) -> bool:
        """Whether the bounds apply to the magnitude of the value."""
        return self.column in MAGNITUDE_COLUMNS

    @property
    def dimension(self) -> str:
        """The dimension of the bounds."""
        return TARGET_COLUMNS[self.value_column]

    def label(self) -> str:
        """A readable statement, e.g. ``"static_friction_force >= 2 µN"``."""
        from ..units import format_quantity

        name = f"|{self.column}|" if self.magnitude else self.column
        if self.column == "hardness":
            return f"peak pressure <= hardness {format_quantity(self.max, 'pressure', 3)}"
        parts = []
        if self.min is not None:
            parts.append(f">= {format_quantity(self.min, self.dimension, 3)}")
        if self.max is not None:
            parts.append(f"<= {format_quantity(self.max, self.dimension, 3)}")
        return f"{name} " + " and ".join(parts)

    def evaluate(self, value) -> tuple[bool, float, float]:
        """Whether ``value`` meets the target, how far it misses, and by how much it passes.

        Parameters
        ----------
        value : float or None
            The table value (SI; NaN or None: not computed).

        Returns
        -------
        met : bool
            True when every bound holds.
        distance : float
            0 when met, else the relative shortfall ``|value - bound| / |bound|`` summed over
            the bounds it misses (1 for a missing value or a zero bound).
        margin : float
            The smallest relative margin by which the bounds hold (negative when missed; NaN
            for a missing value).
        """
        if value is None or not math.isfinite(float(value)):
            return False, 1.0, math.nan
        v = abs(float(value)) if self.magnitude else float(value)
        distance, margins = 0.0, []
        for bound, sign in ((self.min, 1.0), (self.max, -1.0)):
            if bound is None:
                continue
            scale = abs(bound) if bound != 0 else 1.0
            m = sign * (v - bound) / scale
            margins.append(m)
            if m < 0:
                distance += -m if bound != 0 else 1.0
        met = all(m >= 0 for m in margins)
        return met, distance, min(margins) if margins else math.nan


@dataclass
class ChainOptions:
    """What each design point runs after the normal contact at the clamp load.

    Attributes
    ----------
    tangential_forces : "auto" or list of float
        The tangential ramp of the partial-slip stage (N): "auto" ramps to
        ``auto_factor x mu x clamp load`` in ``auto_steps`` steps, and once more to
        ``auto_factor x mu x F0+`` (F0+ the repulsive force at zero tangential load, which
        adhesion and menisci raise above the clamp load) when that first ramp ends before
        gross slip.
    auto_factor : float
        Head room of the automatic ramp over the friction bound (default 1.2).
    auto_steps : int
        Steps of the automatic ramp (default 13, zero included).
    hysteresis : dict or None
        ``friction.path`` of the hysteresis stage (``{control, amplitude, cycles, steps}``;
        default a force-controlled loop to 0.95 mu F0+, 1 cycle, 16 steps); None: no
        hysteresis stage (no lateral stiffness).
    pulloff : bool
        Run the pull-off stage (from the clamp load as preload).
    """

    tangential_forces: object = "auto"
    auto_factor: float = 1.2
    auto_steps: int = 13
    hysteresis: dict | None = field(default_factory=lambda: {"control": "force", "amplitude": 0.95, "cycles": 1,
                                                              "steps": 16})
    pulloff: bool = True

    @classmethod
    def from_dict(cls, data: Mapping | None) -> ChainOptions:
        """Read the ``[chain]`` table.

        Parameters
        ----------
        data : mapping or None
            The table (forces as numbers in N or unit strings).

        Returns
        -------
        ChainOptions

        Raises
        ------
        InputError
            An unknown key or a bad value, named ``chain.<key>``.
        """
        data = dict(data or {})
        unknown = sorted(set(data) - _CHAIN_KEYS)
        if unknown:
            raise InputError(f"chain.{unknown[0]}", f"unknown key; allowed: {', '.join(sorted(_CHAIN_KEYS))}")
        out = cls()
        tf = data.get("tangential_forces", "auto")
        if tf != "auto":
            if isinstance(tf, Mapping):
                if set(tf) != {"start", "stop", "num"}:
                    raise InputError("chain.tangential_forces", "a range table needs exactly start, stop, num")
                num = tf["num"]
                if not isinstance(num, int) or num < 2:
                    raise InputError("chain.tangential_forces.num", f"must be an integer >= 2, got {num!r}")
                a = to_si(tf["start"], "force", "chain.tangential_forces.start")
                b = to_si(tf["stop"], "force", "chain.tangential_forces.stop")
                tf = [a + (b - a) * i / (num - 1) for i in range(num)]
            elif isinstance(tf, (list, tuple)) and tf:
                tf = [to_si(v, "force", f"chain.tangential_forces[{i}]") for i, v in enumerate(tf)]
            else:
                raise InputError("chain.tangential_forces", f"must be \"auto\", a list of forces or "
                                 f"{{start, stop, num}}, got {tf!r}")
        out.tangential_forces = tf
        fac = data.get("auto_factor", out.auto_factor)
        if isinstance(fac, bool) or not isinstance(fac, (int, float)) or not fac > 1.0:
            raise InputError("chain.auto_factor", f"must be a number > 1, got {fac!r}")
        out.auto_factor = float(fac)
        steps = data.get("auto_steps", out.auto_steps)
        if isinstance(steps, bool) or not isinstance(steps, int) or steps < 3:
            raise InputError("chain.auto_steps", f"must be an integer >= 3, got {steps!r}")
        out.auto_steps = steps
        hyst = data.get("hysteresis", True)
        if hyst is False:
            out.hysteresis = None
        elif isinstance(hyst, Mapping):
            unknown = sorted(set(hyst) - _HYSTERESIS_KEYS)
            if unknown:
                raise InputError(f"chain.hysteresis.{unknown[0]}",
                                 f"unknown key; allowed: {', '.join(sorted(_HYSTERESIS_KEYS))}")
            path = dict(hyst)
            if path.get("control", "force") == "force":
                path = {**out.hysteresis, **path}
            out.hysteresis = path
        elif hyst is not True:
            raise InputError("chain.hysteresis", f"must be true, false or a table {{amplitude, cycles, steps}}, "
                             f"got {hyst!r}")
        pull = data.get("pulloff", True)
        if not isinstance(pull, bool):
            raise InputError("chain.pulloff", f"must be true or false, got {pull!r}")
        out.pulloff = pull
        return out

    def as_dict(self) -> dict:
        """Plain JSON types (forces in N): what the point hashes cover."""
        return {"tangential_forces": self.tangential_forces, "auto_factor": self.auto_factor,
                "auto_steps": self.auto_steps, "hysteresis": self.hysteresis, "pulloff": self.pulloff}


def _parse_targets(data: Mapping | None) -> list[Target]:
    out = []
    for key, spec in dict(data or {}).items():
        column = _ALIASES.get(key, key)
        if column == "hardness":
            if isinstance(spec, Mapping):
                raise InputError("targets.hardness", "give the hardness as one pressure, e.g. \"5 GPa\"")
            h = to_si(spec, "pressure", "targets.hardness")
            if not h > 0:
                raise InputError("targets.hardness", f"must be > 0, got {spec!r}")
            out.append(Target("hardness", None, h))
            continue
        if column not in TARGET_COLUMNS:
            raise InputError(f"targets.{key}", f"unknown target; allowed: hardness, lateral_stiffness, "
                             f"{', '.join(sorted(TARGET_COLUMNS))}")
        if not isinstance(spec, Mapping) or not spec or set(spec) - {"min", "max"}:
            raise InputError(f"targets.{key}", "must be a table with min and/or max, e.g. { min = \"2 uN\" }")
        dim = TARGET_COLUMNS[column]
        lo = to_si(spec["min"], dim, f"targets.{key}.min") if "min" in spec else None
        hi = to_si(spec["max"], dim, f"targets.{key}.max") if "max" in spec else None
        if lo is not None and hi is not None and lo > hi:
            raise InputError(f"targets.{key}", f"min {spec['min']!r} is above max {spec['max']!r}")
        out.append(Target(column, lo, hi))
    return out


@dataclass
class DesignSweep(SweepSpec):
    """The sweep of a design study: a :class:`~tribobem.sweep.SweepSpec` whose point hashes
    also cover the chain options (:attr:`chain`) and :data:`DESIGN_VERSION`.

    Attributes
    ----------
    chain : dict
        :meth:`ChainOptions.as_dict` (forces in N).
    """

    chain: dict = field(default_factory=dict)

    def tasks(self, runner: str | None = None) -> list[tuple[str, dict]]:
        """``(hash, overrides)`` of every point, in sweep order.

        Parameters
        ----------
        runner : str, optional
            The runner name (default :attr:`runner`).

        Returns
        -------
        list of (str, dict)
            As :meth:`SweepSpec.tasks`, with the chain options and the design version in
            every hash besides the base, the overrides, the point's effective scenario solver
            options and the solver version.
        """
        runner = runner or self.runner
        keyed = {"design_version": DESIGN_VERSION, "scenario": self.base, "chain": self.chain}
        return [(point_hash(runner, keyed, o, solver_options("scenario", self.base, o)), o) for o in self.overrides()]


@dataclass
class DesignSpec:
    """A parsed design file.

    Attributes
    ----------
    base : dict
        The base scenario (units as written).
    parameters : dict
        Dotted scenario key -> list of values (their cartesian product is the design grid).
    points : list of dict
        Explicit override dicts (combined with the product of ``parameters``).
    chain : ChainOptions
        What each point runs.
    targets : list of Target
        What the ranking compares.
    name, description : str
        Label and free text.
    scenario_path, source : Path or None
        The base scenario file (its folder resolves relative paths) and the design file.
    scheduler : str or None
        Default Dask scheduler; the command line overrides it.
    workers : int or None
        Default local cluster size.
    """

    base: dict
    parameters: dict = field(default_factory=dict)
    points: list = field(default_factory=list)
    chain: ChainOptions = field(default_factory=ChainOptions)
    targets: list = field(default_factory=list)
    name: str = "design"
    description: str = ""
    scenario_path: Path | None = None
    source: Path | None = None
    scheduler: str | None = None
    workers: int | None = None

    @classmethod
    def from_dict(cls, data: Mapping, source: str | os.PathLike | None = None) -> DesignSpec:
        """Build a design spec from a parsed design file.

        Parameters
        ----------
        data : mapping
            The parsed TOML table.
        source : path, optional
            The design file (relative paths resolve against its folder; its stem is the
            default name).

        Returns
        -------
        DesignSpec

        Raises
        ------
        InputError
            An unknown key, a bad chain option or target, or any error of the sweep spec
            (:meth:`tribobem.sweep.SweepSpec.from_dict`: no base scenario, a key that names no
            scenario section, nothing to vary, ...).
        """
        unknown = sorted(set(data) - DESIGN_KEYS)
        if unknown:
            raise InputError(f"design.{unknown[0]}", f"unknown key; allowed: {', '.join(sorted(DESIGN_KEYS))}")
        if "base" not in data and "scenario" not in data:
            raise InputError("design.scenario", "missing: give scenario = \"file.toml\" or an inline [base] table")
        sweep_part = {k: data[k] for k in ("name", "description", "scenario", "base", "parameters", "points",
                                           "scheduler", "workers") if k in data}
        try:  # the sweep file's checks and scenario loading
            sw = SweepSpec.from_dict(sweep_part, source=source)
        except InputError as exc:
            if not exc.field.startswith("sweep."):
                raise
            raise InputError("design." + exc.field[len("sweep."):], exc.reason) from None
        return cls(base=sw.base, parameters=sw.parameters, points=sw.points,
                   chain=ChainOptions.from_dict(data.get("chain")), targets=_parse_targets(data.get("targets")),
                   name=sw.name if ("name" in data or source is not None) else "design",
                   description=sw.description, scenario_path=sw.scenario_path, source=sw.source,
                   scheduler=sw.scheduler, workers=sw.workers)

    @classmethod
    def from_file(cls, path: str | os.PathLike) -> DesignSpec:
        """Read a design TOML file.

        Parameters
        ----------
        path : path
            The design file.

        Returns
        -------
        DesignSpec

        Raises
        ------
        InputError
            The file is missing or not valid TOML, or see :meth:`from_dict`.
        """
        path = Path(path)
        if not path.is_file():
            raise InputError("design", f"design file not found: {path}")
        try:
            data = tomllib.loads(path.read_text(encoding="utf-8"))
        except tomllib.TOMLDecodeError as exc:
            raise InputError("design", f"{path} is not valid TOML: {exc}") from None
        return cls.from_dict(data, source=path)

    @property
    def base_dir(self) -> str | None:
        """Folder for the relative paths of the scenario (its own file's, else the design file's)."""
        if self.scenario_path is not None:
            return str(self.scenario_path.parent)
        return str(self.source.parent) if self.source is not None else None

    def sweep(self) -> DesignSweep:
        """The sweep that runs the design points.

        Returns
        -------
        DesignSweep
            Base scenario, parameters and points of the design; no ``outputs`` (every scalar
            of the chain is kept).
        """
        return DesignSweep(base=self.base, parameters=self.parameters, points=self.points, name=self.name,
                           description=self.description, scenario_path=self.scenario_path, source=self.source,
                           scheduler=self.scheduler, workers=self.workers, chain=self.chain.as_dict())


def load_design(path_or_spec) -> DesignSpec:
    """A :class:`DesignSpec` from a path, a parsed dict or a spec.

    Parameters
    ----------
    path_or_spec : DesignSpec, mapping or path
        A spec (returned as it is), a parsed design file (relative paths resolve against the
        current folder) or the path of a design TOML file.

    Returns
    -------
    DesignSpec
    """
    if isinstance(path_or_spec, DesignSpec):
        return path_or_spec
    if isinstance(path_or_spec, Mapping):
        return DesignSpec.from_dict(path_or_spec)
    return DesignSpec.from_file(path_or_spec)
