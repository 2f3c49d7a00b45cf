"""The sweep file: parsing, validation and the points it defines.

A sweep file (TOML) names what to run (a scenario file, an inline ``[base]`` scenario or a
library function) and what to vary (``[parameters]`` lists, whose cartesian product is the
grid, and/or explicit ``[[points]]``); :class:`SweepSpec` holds it, checks it and expands it
into the points, each a dict of dotted overrides of the base (see :mod:`tribobem.sweep`).
"""

from __future__ import annotations

import itertools
import os
import tomllib
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path

from ..errors import InputError
from .cache import point_tasks
from .values import _canonical, apply_overrides, flatten

__all__ = ["SweepSpec", "load_sweep", "SPEC_KEYS", "SCENARIO_SECTIONS"]

#: Top-level keys of a sweep file.
SPEC_KEYS = {"name", "description", "scenario", "base", "function", "parameters", "points",
             "outputs", "keep_runs", "scheduler", "workers"}
#: Top-level sections of a scenario (file-contract); a dotted key must start with one of these
#: or with a key of the base scenario.
SCENARIO_SECTIONS = {"kind", "name", "title", "description", "grid", "body1", "body2", "load",
                     "adhesion", "friction", "humidity", "solver", "output", "path"}


@dataclass
class SweepSpec:
    """A parsed sweep file.

    Attributes
    ----------
    base : dict
        Base scenario (scenario runner) or fixed keyword arguments (function runner).
    parameters : dict[str, list]
        Dotted key -> values; the sweep is their cartesian product (in file order, the last
        key varying fastest).
    points : list[dict]
        Explicit override dicts; combined with the product of ``parameters`` when both are
        given (every point for every parameter combination).
    outputs : list[str]
        Scalars to gather: run-level keys of the summary, else the last step's.  Empty:
        every scalar the runs return.
    function : str or None
        ``"package.module:callable"``; the callable takes the merged keyword arguments
        (base plus point, unit strings converted to SI floats) and returns a dict of
        scalars (or one float, gathered as ``value``).  None: run scenarios.
    name : str
        Name of the sweep (progress messages, the results' ``sweep`` attribute); default the
        sweep file's stem.
    description : str
        Free text.
    scenario_path : Path or None
        Where the base scenario came from (its folder resolves relative paths).
    source : Path or None
        The sweep file.
    keep_runs : bool
        Scenario runner: keep each run's results folder under ``OUTDIR/runs/<hash>/``.
    scheduler : str or None
        Default Dask scheduler of the sweep file (an address, ``"local"`` or
        ``"synchronous"``); the command line overrides it.
    workers : int or None
        Default local cluster size (>= 1); the command line overrides it.
    """

    base: dict = field(default_factory=dict)
    parameters: dict = field(default_factory=dict)
    points: list = field(default_factory=list)
    outputs: list = field(default_factory=list)
    function: str | None = None
    name: str = "sweep"
    description: str = ""
    scenario_path: Path | None = None
    source: Path | None = None
    keep_runs: bool = False
    scheduler: str | None = None
    workers: int | None = None

    def __post_init__(self):
        self.base = dict(self.base or {})
        self.parameters = {str(k): list(v) if isinstance(v, (list, tuple)) else v
                           for k, v in _flatten_parameters(self.parameters or {}).items()}
        self.points = [flatten(dict(p)) for p in (self.points or [])]
        self.outputs = list(self.outputs or [])
        self.validate()

    # -- construction ------------------------------------------------------------------
    @classmethod
    def from_dict(cls, data: Mapping, source: str | os.PathLike | None = None) -> SweepSpec:
        """Build a spec from a parsed sweep file.

        Parameters
        ----------
        data : mapping
            The parsed TOML table (values carry their units: numbers or quantity strings).
        source : path, optional
            The sweep file: relative paths (``scenario = "base.toml"``) resolve against its
            folder (default: the current folder) and its stem is the default ``name``.

        Returns
        -------
        SweepSpec

        Raises
        ------
        InputError
            An unknown key, a missing or doubly given runner, an unreadable scenario file, or
            any error of :meth:`validate`.
        """
        unknown = sorted(set(data) - SPEC_KEYS)
        if unknown:
            raise InputError(f"sweep.{unknown[0]}", f"unknown key; allowed: {', '.join(sorted(SPEC_KEYS))}")
        src = Path(source).resolve() if source is not None else None
        folder = src.parent if src is not None else Path.cwd()
        given = [k for k in ("scenario", "base", "function") if k in data]
        if "scenario" in data and "base" in data:
            raise InputError("sweep.scenario", "give either scenario = \"file.toml\" or an inline [base] table, not both")
        if not given:
            raise InputError("sweep.scenario", "missing: give scenario = \"file.toml\", an inline [base] table, "
                             "or function = \"module:callable\"")
        base, scen_path = {}, None
        if "scenario" in data:
            if "function" in data:
                raise InputError("sweep.function", "a function sweep takes its fixed arguments from [base], not scenario")
            scen = data["scenario"]
            if isinstance(scen, Mapping):
                base = dict(scen)
            else:
                scen_path = (folder / str(scen)).resolve()
                if not scen_path.is_file():
                    raise InputError("sweep.scenario", f"scenario file not found: {scen_path}")
                try:
                    base = tomllib.loads(scen_path.read_text(encoding="utf-8"))
                except tomllib.TOMLDecodeError as exc:
                    raise InputError("sweep.scenario", f"{scen_path} is not valid TOML: {exc}") from None
        elif "base" in data:
            if not isinstance(data["base"], Mapping):
                raise InputError("sweep.base", "must be a table")
            base = dict(data["base"])
        outputs = data.get("outputs", [])
        if isinstance(outputs, str):
            outputs = [outputs]
        return cls(
            base=base,
            parameters=data.get("parameters", {}),
            points=data.get("points", []),
            outputs=outputs,
            function=data.get("function"),
            name=str(data.get("name", src.stem if src is not None else "sweep")),
            description=str(data.get("description", "")),
            scenario_path=scen_path,
            source=src,
            keep_runs=bool(data.get("keep_runs", False)),
            scheduler=data.get("scheduler"),
            workers=data.get("workers"),
        )

    @classmethod
    def from_file(cls, path: str | os.PathLike) -> SweepSpec:
        """Read a sweep TOML file.

        Parameters
        ----------
        path : path
            The sweep file.

        Returns
        -------
        SweepSpec

        Raises
        ------
        InputError
            The file is missing or not valid TOML, or see :meth:`from_dict`.
        """
        path = Path(path)
        if not path.is_file():
            raise InputError("sweep", f"sweep file not found: {path}")
        try:
            data = tomllib.loads(path.read_text(encoding="utf-8"))
        except tomllib.TOMLDecodeError as exc:
            raise InputError("sweep", f"{path} is not valid TOML: {exc}") from None
        return cls.from_dict(data, source=path)

    # -- checks --------------------------------------------------------------------------
    def validate(self) -> None:
        """Check the spec (called on construction).

        Raises
        ------
        InputError
            A malformed function name or outputs list, an empty or repeated parameter value,
            nothing to sweep, a key both in ``[parameters]`` and a point, a key that names no
            scenario section, a bad ``workers``, or two identical points.
        """
        if self.function is not None:
            if not isinstance(self.function, str) or ":" not in self.function:
                raise InputError("sweep.function", f"must be 'package.module:callable', got {self.function!r}")
        if not isinstance(self.outputs, list) or not all(isinstance(o, str) for o in self.outputs):
            raise InputError("sweep.outputs", "must be a list of names")
        for key, values in self.parameters.items():
            if not isinstance(values, list) or not values:
                raise InputError(f"parameters.{key}", "must be a non-empty list of values")
            seen = [_canonical(v) for v in values]
            if len(set(seen)) != len(seen):
                raise InputError(f"parameters.{key}", "has a repeated value")
        if not self.parameters and not self.points:
            raise InputError("sweep.parameters", "nothing to sweep: give [parameters] lists and/or [[points]]")
        for i, p in enumerate(self.points):
            if not isinstance(p, dict):
                raise InputError(f"points[{i}]", "must be a table of overrides")
            clash = sorted(set(p) & set(self.parameters))
            if clash:
                raise InputError(f"points[{i}].{clash[0]}", "is also swept in [parameters]; give it in one place")
        if self.function is None:
            known = SCENARIO_SECTIONS | set(self.base)
            for key in list(self.parameters) + [k for p in self.points for k in p]:
                if key.split(".")[0] not in known:
                    raise InputError(f"parameters.{key}", f"does not name a scenario key; top-level sections: "
                                     f"{', '.join(sorted(SCENARIO_SECTIONS))}")
        if self.workers is not None and (not isinstance(self.workers, int) or self.workers < 1):
            raise InputError("sweep.workers", f"must be an integer >= 1, got {self.workers!r}")
        hashes = [h for h, _ in self.tasks()]
        if len(set(hashes)) != len(hashes):
            raise InputError("sweep.points", "two points are identical (same overrides)")

    # -- the points ----------------------------------------------------------------------
    @property
    def is_grid(self) -> bool:
        """True when the points are the full cartesian product of ``parameters``."""
        return bool(self.parameters) and not self.points

    @property
    def runner(self) -> str:
        """``"function:<module:callable>"`` for a function sweep, else ``"scenario"``."""
        return f"function:{self.function}" if self.function else "scenario"

    def overrides(self) -> list[dict]:
        """Every point's overrides, in sweep order.

        Returns
        -------
        list of dict
            Dotted key -> value (units as written in the sweep file): the cartesian product
            of ``parameters`` (last key fastest), for each explicit point in turn.
        """
        keys = list(self.parameters)
        combos = [dict(zip(keys, vals)) for vals in itertools.product(*self.parameters.values())] if keys else [{}]
        if not self.points:
            return combos
        return [{**pt, **combo} for pt in self.points for combo in combos]

    def tasks(self, runner: str | None = None) -> list[tuple[str, dict]]:
        """``(hash, overrides)`` of every point, in sweep order.

        Parameters
        ----------
        runner : str, optional
            As for :func:`~tribobem.sweep.cache.point_hash` (default :attr:`runner`; a
            callable given to :func:`~tribobem.sweep.run_sweep` has its own).

        Returns
        -------
        list of (str, dict)
            The hash includes the point's effective solver options and the solver version
            (:func:`~tribobem.sweep.cache.point_tasks`); the overrides carry their units as
            written in the sweep file.
        """
        runner = runner or self.runner
        return point_tasks(runner, self.base, self.overrides())

    def __len__(self) -> int:
        return len(self.overrides())

    def swept_keys(self) -> list[str]:
        """Every key that some point overrides.

        Returns
        -------
        list of str
            Dotted keys, in first-seen order.
        """
        keys: list[str] = []
        for o in self.overrides():
            for k in o:
                if k not in keys:
                    keys.append(k)
        return keys

    def scenario_for(self, overrides: Mapping) -> dict:
        """The full scenario (or keyword arguments) of one point.

        Parameters
        ----------
        overrides : mapping
            The point's dotted overrides (units as written).

        Returns
        -------
        dict
            A deep copy of the base with the overrides set.
        """
        return apply_overrides(self.base, overrides)


def _flatten_parameters(params: Mapping) -> dict:
    """``[parameters]`` tables to dotted keys (every nested table is a section here: the
    values of a parameter are its list)."""
    out = {}
    for key, value in params.items():
        if isinstance(value, Mapping):
            for k, v in _flatten_parameters(value).items():
                out[f"{key}.{k}"] = v
        else:
            out[str(key)] = value
    return out


def load_sweep(path_or_spec) -> SweepSpec:
    """A :class:`SweepSpec` from a path, a dict or a spec.

    Parameters
    ----------
    path_or_spec : SweepSpec, mapping or path
        A spec (returned as it is), a parsed sweep file (relative paths resolve against the
        current folder) or the path of a sweep TOML file.

    Returns
    -------
    SweepSpec
    """
    if isinstance(path_or_spec, SweepSpec):
        return path_or_spec
    if isinstance(path_or_spec, Mapping):
        return SweepSpec.from_dict(path_or_spec)
    return SweepSpec.from_file(path_or_spec)
