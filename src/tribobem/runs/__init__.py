"""Run kinds: one module per kind, one registry ``kind -> runner`` (SPEC 12).

A runner is called as ``runner(pb, bar)`` with the built
:class:`~tribobem.scenario.build.Problem` and a progress handler (``bar.phase(description,
total)``, ``bar(done, total)``), and returns a dict with the keys

``rows``
    summary.json steps (dicts of scalars, each with a ``branch``);
``results``
    the results whose fields go to fields.nc (NormalResult);
``labels``, ``indices``
    a label per result and its index in ``rows`` (-1: not a row);
``curve``
    a LoadCurve or None;
``run``
    run-level scalars for summary.json;
``tangential`` (optional)
    a list of :class:`~tribobem.results.TangentialResult`, one per entry of ``results``;
``warnings`` (optional)
    messages for summary.json ``warnings`` and the report's banner.

A new kind is a new module here with a ``run(pb, bar)`` function and ONE line in
:data:`RUNNERS`.  The scenario schema (:mod:`tribobem.scenario.schema`) lists the kinds it
accepts; a kind runs exactly when it has a runner here.  Nothing in this package imports
:mod:`tribobem.scenario` at import time (the schema imports the registry).
"""

from __future__ import annotations

from importlib import import_module
from typing import Callable

from ..errors import InputError

__all__ = ["RUNNERS", "Runner", "get_runner", "available_kinds", "NotImplementedKindError"]

#: ``runner(pb: Problem, bar) -> dict``
Runner = Callable[..., dict]


class NotImplementedKindError(InputError):
    """A scenario kind the schema accepts but this version cannot run (no runner)."""

    def __init__(self, field: str, message: str):
        self.reason = message
        super().__init__(field, message)


def _runner(module: str) -> Runner:
    return import_module(f"{__name__}.{module}").run


#: kind -> runner, one line per kind.
RUNNERS: dict[str, Runner] = {
    "normal": _runner("normal"),
    "pulloff": _runner("pulloff"),
    "partial_slip": _runner("partial_slip"),
    "hysteresis": _runner("hysteresis"),
    "capillary": _runner("capillary"),
    # a new kind: its module runs/<kind>.py and one line here
}


def available_kinds() -> tuple[str, ...]:
    """The kinds that have a runner, in registry order."""
    return tuple(RUNNERS)


def get_runner(kind: str) -> Runner:
    """The runner of ``kind``.

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
