"""Values of a sweep: canonical JSON, dotted keys and overrides, quantities.

The lowest layer of :mod:`tribobem.sweep` (it imports nothing else of the package): the
canonical JSON text that point hashes and coordinate labels are made of, the dotted keys of a
sweep file (``"body2.shape.radius"``) and the overrides they apply to a base scenario.
"""

from __future__ import annotations

import copy
import json
from collections.abc import Mapping

from ..errors import InputError
from ..output.summary import jsonable

__all__ = ["flatten", "set_dotted", "apply_overrides"]


def _jsonable(value):
    """Plain JSON types (:func:`tribobem.output.summary.jsonable`: numpy scalars and arrays
    converted, non-finite floats -> None); any other object as its ``repr``, as the point
    hashes have always been made."""
    return jsonable(value, fallback=repr)


def _canonical(obj) -> str:
    """Canonical JSON text of ``obj`` (sorted keys, no spaces, ASCII): what point hashes and
    the labels of non-numeric coordinates are made of."""
    return json.dumps(_jsonable(obj), sort_keys=True, separators=(",", ":"), ensure_ascii=True)


#: Tables that are values of a scenario key, not nested sections: a range ``{start, stop, num}``.
_VALUE_TABLES = ({"start", "stop", "num"},)


def flatten(table: Mapping, prefix: str = "") -> dict:
    """Nested tables to dotted keys.

    Parameters
    ----------
    table : mapping
        Nested tables of a sweep file (a ``[[points]]`` entry, say); values carry their own
        units (numbers or quantity strings such as ``"10 um"``), which are kept as given.
    prefix : str
        Prepended to every key (``"a."`` for the table under key ``a``).

    Returns
    -------
    dict
        ``{"a": {"b": 1}}`` -> ``{"a.b": 1}``.  A range table ``{start, stop, num}`` is a
        value and stays whole; an empty table is a value too.
    """
    out = {}
    for key, value in table.items():
        name = f"{prefix}{key}"
        if isinstance(value, Mapping) and value and set(value) not in _VALUE_TABLES:
            out.update(flatten(value, name + "."))
        else:
            out[name] = value
    return out


def set_dotted(tree: dict, key: str, value) -> None:
    """Set one dotted key in nested tables, creating tables on the way.

    Parameters
    ----------
    tree : dict
        Nested tables, changed in place.
    key : str
        Dotted key: ``"a.b"`` sets ``tree["a"]["b"]``.
    value
        A deep copy of it is stored (units as given: a number or a quantity string).

    Raises
    ------
    InputError
        When a part of the key other than the last names a value, not a table.
    """
    parts = key.split(".")
    node = tree
    for i, part in enumerate(parts[:-1]):
        nxt = node.get(part)
        if nxt is None:
            nxt = node[part] = {}
        elif not isinstance(nxt, dict):
            raise InputError(key, f"cannot set it: {'.'.join(parts[:i + 1])!r} is a value ({nxt!r}), not a table")
        node = nxt
    node[parts[-1]] = copy.deepcopy(value)


def apply_overrides(base: Mapping, point: Mapping) -> dict:
    """A point's scenario (or keyword arguments): the base with the point's overrides set.

    Parameters
    ----------
    base : mapping
        Base scenario, or the fixed keyword arguments of a function; not changed.
    point : mapping
        Dotted key -> value (units as written in the sweep file).

    Returns
    -------
    dict
        A deep copy of ``base`` with every dotted key of ``point`` set (:func:`set_dotted`).
    """
    tree = copy.deepcopy(dict(base))
    for key, value in point.items():
        set_dotted(tree, key, value)
    return tree
