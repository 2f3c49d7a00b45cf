"""The registry of stress laws: what ``[adhesion] model = NAME`` stands for.

Each law is one :class:`StressLaw`: its name (the ``model`` tag of the scenario's
``[adhesion]`` table), the pydantic model of that table (its *spec*, a subclass of
:class:`tribobem.scenario.schema.AdhesionSpec` whose ``model`` field is ``Literal[NAME]``), the
law's class (an :class:`~tribobem.interactions.base.Interaction`, whose declared capabilities
-- ``windowable``, ``summary_info``, ``result_checks``, ``report_rows``, see
:mod:`tribobem.interactions.base` -- tell the solvers, checks and report what it allows) and
its builder, ``(spec, context) -> Interaction or None``.

The schema validates ``[adhesion]`` with the spec of the law its ``model`` names
(:func:`tribobem.scenario.schema.parse_scenario`), and the problem builder calls the builder
(:func:`tribobem.scenario.build.build_problem`).  A new law is thus its module here (the law
and its builder), its spec class beside the others in :mod:`tribobem.scenario.schema` and one
:func:`register_law` line there; nothing else names it.

The built-in laws ``none`` and ``dugdale`` are registered by :mod:`tribobem.scenario.schema`,
where their specs live (importing :mod:`tribobem` imports it).
"""

from __future__ import annotations

import typing
from dataclasses import dataclass
from typing import Any, Callable

__all__ = ["StressLaw", "LawContext", "LAWS", "register_law", "unregister_law", "get_law", "law_names",
           "one_of", "report_rows"]


@dataclass(frozen=True)
class LawContext:
    """What a law's builder may read of the problem besides its own ``[adhesion]`` keys.

    Attributes
    ----------
    grid : Grid
        The solver grid (m).
    effective_modulus : float or None
        Composite modulus E* of the pair (Pa); None when both bodies are rigid.
    """

    grid: Any
    effective_modulus: float | None = None


@dataclass(frozen=True)
class StressLaw:
    """One registered stress law.

    Attributes
    ----------
    name : str
        The ``[adhesion] model`` tag.
    spec : type
        The pydantic model of its ``[adhesion]`` table (``model: Literal[name]``).
    law : type
        The law's class; its declared capabilities (class attributes such as
        ``report_rows``) are read from here where no instance exists (the report).
    build : callable
        ``build(spec, context)`` -> the law (an Interaction), or None for no stress law.
    """

    name: str
    spec: type
    law: type
    build: Callable[[Any, LawContext], Any]


#: Name -> law, in registration order (the order error messages and the report list them).
LAWS: dict[str, StressLaw] = {}


def _tags(spec: type) -> tuple:
    field = getattr(spec, "model_fields", {}).get("model")
    ann = getattr(field, "annotation", None)
    return typing.get_args(ann) if typing.get_origin(ann) is typing.Literal else ()


def register_law(name: str, spec: type, law: type, build: Callable[[Any, LawContext], Any] | None = None) -> StressLaw:
    """Register a stress law under ``[adhesion] model = name``.

    Parameters
    ----------
    name : str
        The tag; must not be registered yet.
    spec : type
        The pydantic model of its ``[adhesion]`` table; its ``model`` field must be
        ``Literal[name]``.
    law : type
        The law's class (an Interaction).
    build : callable, optional
        ``(spec, context) -> Interaction or None``; default ``law.from_spec``.

    Returns
    -------
    StressLaw
        The registered entry.

    Raises
    ------
    ValueError
        When the name is taken or the spec's ``model`` field is not ``Literal[name]``.
    """
    if name in LAWS:
        raise ValueError(f"stress law {name!r} is registered already")
    if _tags(spec) != (name,):
        raise ValueError(f"the spec of stress law {name!r} must declare model: Literal[{name!r}], "
                         f"got {_tags(spec) or 'no such field'}")
    entry = StressLaw(name, spec, law, build if build is not None else law.from_spec)
    LAWS[name] = entry
    return entry


def unregister_law(name: str) -> None:
    """Remove a registered law (tests that register their own).

    Parameters
    ----------
    name : str
        The tag; absent names are ignored.
    """
    LAWS.pop(name, None)


def law_names() -> tuple[str, ...]:
    """The registered tags, in registration order."""
    return tuple(LAWS)


def one_of(names=None) -> str:
    """``'none', 'dugdale' or 'x'``: the tags as a choice, as the schema's messages list them.

    Parameters
    ----------
    names : iterable of str, optional
        Default: the registered tags.

    Returns
    -------
    str
    """
    quoted = [repr(n) for n in (LAWS if names is None else names)]
    return quoted[0] if len(quoted) == 1 else ", ".join(quoted[:-1]) + " or " + quoted[-1]


def get_law(name: str) -> StressLaw:
    """The registered law of a tag.

    Parameters
    ----------
    name : str

    Returns
    -------
    StressLaw

    Raises
    ------
    KeyError
        Naming the registered tags, when ``name`` is not one of them.
    """
    try:
        return LAWS[name]
    except KeyError:
        raise KeyError(f"unknown stress law {name!r}; registered: {one_of()}") from None


def report_rows() -> tuple[tuple[str, str, str], ...]:
    """``(key, label, dimension)`` of every registered law's report rows (first law first; a key
    two laws declare is listed once)."""
    out, seen = [], set()
    for entry in LAWS.values():
        for row in getattr(entry.law, "report_rows", ()) or ():
            if row[0] not in seen:
                seen.add(row[0])
                out.append(tuple(row))
    return tuple(out)
