"""Run kinds: one module per kind, one registry line per kind.

Each ``runs/<kind>.py`` defines ``KIND``, a :class:`~tribobem.runs.kind.RunKind`: its runner,
the scenario sections and keys it reads, its consistency rules.  The scenario schema takes its
list of kinds from :data:`KINDS` and asks the kind which sections it reads and whether a
scenario is consistent; it has no per-kind branch.

A runner is called as ``runner(pb, bar, settings=...)`` with the built
:class:`~tribobem.scenario.build.Problem`, a progress handler (``bar.phase(description,
total)``, ``bar(done, total)``) and the run's solver settings
(:class:`~tribobem.runs.settings.SolverSettings`, built once by the caller; a runner called
without them builds them from ``pb.scenario``), and returns a
:class:`~tribobem.runs.kind.RunOutput` (steps, states for fields.nc, run-level values, warnings).

A new kind is a new module here defining ``run(pb, bar, settings=None)`` and ``KIND`` and ONE
line in :data:`KINDS` (a kind whose steps go through the coupling loop, or whose path picks its
own normal solver, is also named in :mod:`tribobem.runs.settings`).  Nothing in this package
imports :mod:`tribobem.scenario` (the schema imports the registry).
"""

from __future__ import annotations

from importlib import import_module
from typing import Callable

from ..errors import InputError
from .kind import RunKind, RunOutput

__all__ = ["KINDS", "RUNNERS", "RunKind", "RunOutput", "Runner", "get_runner", "get_kind", "available_kinds",
           "NotImplementedKindError"]

#: ``runner(pb: Problem, bar, settings: SolverSettings | None = None) -> RunOutput``
Runner = Callable[..., RunOutput]


class NotImplementedKindError(InputError):
    """A scenario kind the schema accepts but this version cannot run (no runner).

    Parameters
    ----------
    field : str
        The scenario key the error is about (``kind``).
    message : str
        Why, with the available kinds; also kept as ``reason``.
    """

    def __init__(self, field: str, message: str):
        self.reason = message
        super().__init__(field, message)


def _kind(module: str) -> RunKind:
    return import_module(f"{__name__}.{module}").KIND


#: kind -> its declaration, one line per kind.
KINDS: dict[str, RunKind] = {
    "normal": _kind("normal"),
    "pulloff": _kind("pulloff"),
    "partial_slip": _kind("partial_slip"),
    "hysteresis": _kind("hysteresis"),
    "capillary": _kind("capillary"),
    # a new kind: its module runs/<kind>.py with KIND = RunKind(...) and one line here
}

#: kind -> runner (``KINDS[kind].run``).
RUNNERS: dict[str, Runner] = {name: kind.run for name, kind in KINDS.items()}


def available_kinds() -> tuple[str, ...]:
    """The kinds that have a runner, in registry order.

    Returns
    -------
    tuple of str
    """
    return tuple(KINDS)


def get_kind(kind: str) -> RunKind:
    """The declaration of ``kind`` (a :class:`NotImplementedKindError` names the available ones).

    Parameters
    ----------
    kind : str
        The scenario's ``kind``.

    Returns
    -------
    RunKind

    Raises
    ------
    NotImplementedKindError
        When ``kind`` has no runner.
    """
    get_runner(kind)
    return KINDS[kind]


def get_runner(kind: str) -> Runner:
    """The runner of ``kind``.

    Parameters
    ----------
    kind : str
        The scenario's ``kind``.

    Returns
    -------
    Runner
        ``runner(pb, bar, settings=None) -> RunOutput``.

    Raises
    ------
    NotImplementedKindError
        (an :class:`~tribobem.errors.InputError` on field ``kind``) when ``kind`` has no
        runner; the message lists the available kinds.
    """
    try:
        return RUNNERS[kind]
    except (KeyError, TypeError):
        raise NotImplementedKindError(
            "kind", f"{kind!r} runs are not implemented yet in this version "
                    f"(available: {', '.join(RUNNERS)})") from None
