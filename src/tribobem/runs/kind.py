"""What a run kind declares: the scenario sections and keys it uses, and its own rules.

Every ``runs/<kind>.py`` module defines ``KIND = RunKind(...)``.  The scenario schema asks the
kind, never a list of special cases:

* :meth:`RunKind.unused` -- each section or key the scenario *gives* (present in the file or
  dict, whatever its value) that the kind does not read is an error naming it, e.g.
  ``humidity: kind = 'partial_slip' does not use [humidity]``.  A scenario that runs never
  carries a value the run silently ignores.
* :attr:`RunKind.check` -- the kind's consistency rules (which load keys go together, what a
  path needs, ...).  They raise :class:`~tribobem.errors.InputError` naming the key.

Nothing here imports :mod:`tribobem.scenario` (the schema imports the registry); the rules get
the validated :class:`~tribobem.scenario.schema.Scenario` as an argument.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Callable, Mapping, Optional, Union

from ..errors import InputError

__all__ = ["SECTIONS", "BODY_KEYS", "COMMON", "NORMAL_COLUMNS", "TANGENTIAL_COLUMNS", "CAPILLARY_COLUMNS", "RunKind",
           "RunOutput", "fail"]

#: A section whose every key the kind reads.
ALL = "*"

#: The scenario sections (tables) in file order; ``kind``, ``name``, ``description`` and
#: ``expected`` are top-level metadata that every kind accepts.
SECTIONS = ("grid", "body1", "body2", "load", "adhesion", "friction", "humidity", "two_scale", "solver", "output")

#: The body keys every kind reads (the films' keys ``film`` and ``hamaker`` belong to the
#: capillary kinds); ``texture`` and ``waviness`` add to the body's topography like
#: ``roughness``, so every kind that builds a gap reads them.
BODY_KEYS = frozenset({"E", "nu", "rigid", "name", "roughness", "shape", "texture", "waviness"})

#: The sections every kind reads in full, or with these keys.
COMMON: dict[str, Union[str, frozenset]] = {
    "grid": ALL,
    "body1": BODY_KEYS,
    "body2": BODY_KEYS,
    "adhesion": ALL,
    "solver": frozenset({"tolerance", "max_iterations", "backend", "kernel"}),
    "output": ALL,
}


@dataclass
class RunOutput:
    """What a runner returns: the states it computed and the numbers for summary.json.

    Attributes
    ----------
    rows : list of dict
        summary.json ``steps``: scalars per step (SI units), each with a ``branch``.
    results : list
        The states whose fields go to fields.nc (:class:`~tribobem.results.NormalResult`).
    labels : list of str
        A label per entry of ``results``.
    indices : list of int
        The index in ``rows`` of each entry of ``results`` (-1: not a row, e.g. a refined onset).
    run : dict
        Run-level values for summary.json (SI units).
    curve : LoadCurve, optional
        The force-approach curve, for its jumps (normal and pull-off runs).
    tangential : list, optional
        :class:`~tribobem.results.TangentialResult` per entry of ``results`` (tangential kinds).
    warnings : list of str
        Messages for summary.json ``warnings`` and the report's banner.
    cycle_fields : dict
        name -> (maps per cycle, attributes): fields.nc variables on (cycle, x, y).
    step_fields : dict
        name -> (maps per result, attributes): fields.nc variables on (step, x, y).
    step_coords : dict
        name -> (values per result, attributes): fields.nc coordinates on step.
    representative : int, optional
        The entry of ``results`` that ``output.fields = "last"`` keeps (default: pull-off, onset
        or the largest load).
    """

    rows: list
    results: list
    labels: list
    indices: list
    run: dict
    curve: Any = None
    tangential: Optional[list] = None
    warnings: list = field(default_factory=list)
    cycle_fields: dict = field(default_factory=dict)
    step_fields: dict = field(default_factory=dict)
    step_coords: dict = field(default_factory=dict)
    representative: Optional[int] = None

    def __post_init__(self):
        n = len(self.results)
        if len(self.labels) != n or len(self.indices) != n:
            raise ValueError(f"a runner returned {n} results with {len(self.labels)} labels and "
                             f"{len(self.indices)} indices (they must be aligned one-to-one)")
        if self.tangential and len(self.tangential) != n:
            raise ValueError(f"a runner returned {len(self.tangential)} tangential results for {n} results "
                             "(they must be aligned one-to-one)")

#: summary.json step keys of every kind, with their dimension (what ``expected`` may state).
COMMON_RESULTS = {
    "normal_force": "force", "approach": "length", "contact_area": "area", "adhesive_area": "area",
    "repulsive_force": "force", "adhesive_force": "force", "max_pressure": "pressure", "mean_gap": "length",
}
#: Step keys of the tangential kinds.
TANGENTIAL_STEPS = {
    "tangential_force_x": "force", "tangential_force_y": "force", "displacement_x": "length",
    "displacement_y": "length", "stick_area": "area", "slip_area": "area", "stick_ratio": "dimensionless",
}
#: Step keys of the RH steps (kind capillary, humid pull-off).
CAPILLARY_STEPS = {
    "capillary_force": "force", "solid_solid_force": "force", "water_solid_force": "force", "wetted_area": "area",
}


#: The CLI step table's columns (summary.json step keys, in order, after ``#`` and ``branch``)
#: of the normal-load kinds: force, approach, areas, peak pressure.
NORMAL_COLUMNS = ("normal_force", "approach", "contact_area", "adhesive_area", "max_pressure")
#: ... of the tangential kinds: the friction columns replace the approach and the cohesive area.
TANGENTIAL_COLUMNS = ("normal_force", "tangential_force_x", "displacement_x", "contact_area", "stick_ratio",
                      "max_pressure")
#: ... of the RH steps (kind capillary, humid pull-off): one row per RH with the adhesive force
#: components and the meniscus.
CAPILLARY_COLUMNS = ("rh", "normal_force", "capillary_force", "solid_solid_force", "water_solid_force",
                     "contact_area", "wetted_area", "island_count")


def fail(key: str, message: str):
    """Raise the :class:`~tribobem.errors.InputError` of a kind's rule on scenario key ``key``
    (dotted from the top, e.g. ``"load.force"``).

    Parameters
    ----------
    key : str
        The dotted scenario key the rule is about.
    message : str
        What is wrong and what to give instead.

    Raises
    ------
    InputError
        Always.
    """
    raise InputError(key, message)


def _keys(value) -> Union[str, frozenset]:
    return value if value == ALL else frozenset(value)


@dataclass(frozen=True)
class RunKind:
    """A run kind: its runner, the scenario sections and keys it reads, its rules.

    Parameters
    ----------
    name : str
        The scenario's ``kind``.
    run : callable
        ``run(pb, bar, settings=None) -> RunOutput``: the runner (:mod:`tribobem.runs`;
        ``settings``: the run's :class:`~tribobem.runs.settings.SolverSettings`).
    uses : mapping
        Section -> the keys of that section the kind reads (an iterable of names) or
        :data:`ALL`, on top of :data:`COMMON`.  A section missing from both is not read at all.
    check : callable, optional
        ``check(scenario)``: the kind's consistency rules; raises
        :class:`~tribobem.errors.InputError` (:func:`fail`) naming the key.
    hints : mapping, optional
        ``"section"`` or ``"section.key"`` -> why the kind does not read it and what to give
        instead, appended to the generic message.
    summary : str
        One line on what the kind computes (the CLI and the docs list it).
    figures : tuple of str
        The figure sets of its result folder (:data:`tribobem.output.figures.FIGURE_SETS`).
    report_sections : tuple of str
        Its own sections of report.html (:data:`tribobem.output.report.REPORT_SECTIONS`).
    results : mapping
        The summary.json keys it produces beyond :data:`COMMON_RESULTS` (run-level values and
        its own step keys) -> dimension: what a scenario's ``expected`` table may state.
    columns : tuple of str
        The step keys of the CLI's step table (``tribobem run``), in order
        (:data:`NORMAL_COLUMNS`, :data:`TANGENTIAL_COLUMNS`, :data:`CAPILLARY_COLUMNS`); every
        step row of the kind has them (None where a step has no value).
    humid_columns : tuple of str, optional
        The step table's columns when the run uses ``[humidity]`` (its steps are RH steps);
        None: :attr:`columns` either way.
    """

    name: str
    run: Callable[..., "RunOutput"]
    uses: Mapping[str, Any] = field(default_factory=dict)
    check: Optional[Callable[[Any], None]] = None
    hints: Mapping[str, str] = field(default_factory=dict)
    summary: str = ""
    figures: tuple = ("maps",)
    report_sections: tuple = ()
    results: Mapping[str, str] = field(default_factory=dict)
    columns: tuple = NORMAL_COLUMNS
    humid_columns: Optional[tuple] = None

    def step_columns(self, humid: bool = False) -> tuple:
        """The CLI step table's columns (step keys) of a run of this kind.

        Parameters
        ----------
        humid : bool
            Whether the run used ``[humidity]``.

        Returns
        -------
        tuple of str
            :attr:`humid_columns` for a humid run when declared, else :attr:`columns`.
        """
        return self.humid_columns if humid and self.humid_columns is not None else self.columns

    def result_keys(self) -> dict[str, str]:
        """Every summary.json key (run level or step) this kind produces -> its dimension."""
        return {**COMMON_RESULTS, **dict(self.results)}

    def reads(self) -> dict[str, Union[str, frozenset]]:
        """Section -> the keys this kind reads (:data:`ALL`: every key); absent: not read."""
        out = dict(COMMON)
        for section, keys in self.uses.items():
            if section not in SECTIONS:
                raise ValueError(f"run kind {self.name!r} declares an unknown section {section!r}")
            keys = _keys(keys)
            base = out.get(section)
            if keys == ALL or base == ALL:
                out[section] = ALL
            else:
                out[section] = (base or frozenset()) | keys
        return out

    def unused(self, scenario, registry: Mapping[str, "RunKind"] = ()) -> list[tuple[str, str]]:
        """``(key, message)`` for each section or key ``scenario`` gives that this kind does not
        read (in file order); ``registry`` (kind -> RunKind) names the kinds that do read it.

        Parameters
        ----------
        scenario : Scenario
            The validated scenario (its ``model_fields_set`` says what the file gave).
        registry : mapping, optional
            Kind name -> RunKind, to name the kinds that read an ignored section or key.

        Returns
        -------
        list of (str, str)
            ``(key, message)`` pairs; empty when the scenario gives nothing this kind ignores.
        """
        reads = self.reads()
        others = {k: kd.reads() for k, kd in dict(registry).items()}

        def readers(section, key=None):
            return [k for k, r in others.items()
                    if section in r and (key is None or r[section] == ALL or key in r[section])]

        problems = []
        for section in SECTIONS:
            if section not in scenario.model_fields_set:
                continue
            keys = reads.get(section)
            if keys is None:
                problems.append((section, self._message(f"[{section}]", section, readers(section))))
            elif keys != ALL:
                given = getattr(scenario, section)
                for key in type(given).model_fields:  # declared order
                    if key in given.model_fields_set and key not in keys:
                        dotted = f"{section}.{key}"
                        problems.append((dotted, self._message("it", dotted, readers(section, key))))
        return problems

    def _message(self, what: str, key: str, by: list[str]) -> str:
        text = f"kind = {self.name!r} does not use {what}"
        # a body key's hint may be given once for both bodies as "body.<key>"
        hint = self.hints.get(key) or self.hints.get(key.replace("body1.", "body.").replace("body2.", "body."))
        if by:
            text += f" (used by kind {', '.join(repr(k) for k in by)})"
        if hint:
            text += f"; {hint}"
        return text


# ----------------------------------------------------------------------------- rules shared by kinds
def refuse_normcg(sc, why: str) -> None:
    """Refuse ``[solver] method = "normcg"`` where the run's normal solves cannot use it (instead
    of ignoring it silently).

    Parameters
    ----------
    sc : Scenario
        The validated scenario.
    why : str
        Which solves of the run stay with Polonsky-Keer, for the message.

    Raises
    ------
    InputError
        On ``solver.method``.
    """
    if sc.solver.method == "normcg":
        fail("solver.method", f"normcg is not available here: {why}; leave method out (Polonsky-Keer)")


def require_elastic_body(sc):
    """At least one elastic body: two rigid bodies carry no force at a prescribed load."""
    if sc.body1.rigid and sc.body2.rigid:
        fail("body2.rigid", "both bodies are rigid; give at least one a finite E (two rigid bodies are "
                            "allowed only for kind = \"capillary\" at a prescribed load.approach)")


def require_friction(sc):
    """The ``[friction]`` section with its coefficient (the tangential kinds need mu)."""
    fr = sc.friction
    if fr is None or fr.coefficient is None:
        fail("friction.coefficient", f"required for kind = {sc.kind!r}: the friction coefficient "
                                     "mu >= 0 (0: frictionless), in a [friction] section")
    return fr


def require_humidity(sc):
    """``[humidity] rh``: the relative humidities of a capillary run."""
    hum = sc.humidity
    if hum is None or not hum.rh:
        fail("humidity.rh", f"required for kind = {sc.kind!r}: the relative humidities, fractions in "
                            "(0, 1], e.g. rh = [0.3, 0.5, 0.7, 0.9]")
    return hum


def positive_normal_load(sc):
    """Without adhesion a prescribed normal force must be compressive (> 0 N)."""
    load = sc.load
    if sc.adhesion.enabled:
        return
    if load.force is not None and load.force <= 0:
        fail("load.force", f"must be > 0 N without adhesion, got {load.force:g} N "
                           "(a tensile load needs [adhesion])")
    if load.forces is not None and min(load.forces) <= 0:
        fail("load.forces", "every force must be > 0 N without adhesion "
                            f"(got {min(load.forces):g} N; a tensile load needs [adhesion])")
