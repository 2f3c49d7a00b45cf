"""Sphinx extension: the scenario-key tables of the user guide, generated at build time.

The tables are read from the pydantic models of :mod:`tribobem.scenario.schema` (key, type and
unit, default, description) and from the run-kind registry :data:`tribobem.runs.KINDS` (which
kind reads which key, :meth:`tribobem.runs.kind.RunKind.reads`), so they cannot go stale.

Directives (usable from MyST pages as ```` ```{scenario-keys} LoadSpec ```` fences):

``scenario-keys MODEL``
    A table of the model's keys (``MODEL`` a class name of :mod:`tribobem.scenario.schema`),
    then the model's docstring.  Options: ``:section:`` the scenario section whose readers
    fill the "read by" column (default: the model's own section, if it is one);
    ``:no-docstring:`` leaves the docstring out.
``scenario-kinds``
    One row per run kind: what it computes, the sections it reads, its figure sets and report
    sections.
``scenario-reads``
    Section by kind: the keys each kind reads of each section.
``expected-keys``
    The summary keys a scenario's ``expected`` table may state, with their dimension and the
    kinds that produce them.
"""

from __future__ import annotations

import inspect
import re
import typing

from docutils import nodes
from docutils.parsers.rst import Directive, directives
from docutils.parsers.rst import Parser as RSTParser
from docutils.utils import new_document
from pydantic import BaseModel
from pydantic_core import PydanticUndefined

#: Model -> the scenario section it is (the "read by" column).
SECTION_OF = {
    "GridSpec": "grid", "BodySpec": "body1", "LoadSpec": "load", "AdhesionSpec": "adhesion",
    "FrictionSpec": "friction", "HumiditySpec": "humidity", "SolverSpec": "solver", "OutputSpec": "output",
}


# ----------------------------------------------------------------------------- model introspection
def _closure(fn) -> dict:
    try:
        return dict(inspect.getclosurevars(fn).nonlocals)
    except (TypeError, ValueError):
        return {}


def _range(v: dict, unit: str = "") -> str:
    parts = []
    for key, op in (("gt", ">"), ("ge", ">="), ("lt", "<"), ("le", "<=")):
        if v.get(key) is not None:
            parts.append(f"{op} {v[key]:g}")
    return ", ".join(parts)


def _validator_text(meta) -> str | None:
    """Type text of one of the schema's ``Annotated[..., BeforeValidator(validate)]`` helpers."""
    fn = getattr(meta, "func", None)
    if fn is None:
        return None
    v = _closure(fn)
    if "one" in v:  # QuantityList: the dimension and range live in its per-item helper
        v = {**_closure(v["one"]), **v}
        unit = v.get("unit", "")
        rng = _range(v)
        return (f"list of {v['dimension']} ({unit or '-'})" + (f", each {rng}" if rng else "")
                + ", or {start, stop, num}")
    if "dimension" in v:  # Quantity / Number
        dim, unit = v["dimension"], v.get("unit", "")
        rng = _range(v)
        head = "number" if dim == "dimensionless" else f"{dim} ({unit})"
        return head + (f", {rng}" if rng else "")
    if "angle_units" in v:
        return "angle (deg)"
    if fn.__name__ == "validate" and ("ge" in v or "le" in v):  # Int
        rng = _range(v)
        return "integer" + (f", {rng}" if rng else "")
    if fn.__name__ == "<lambda>":
        return None
    return None


def type_text(annotation) -> str:
    """A short, readable description of a field's annotation."""
    origin = typing.get_origin(annotation)
    args = typing.get_args(annotation)
    if origin is typing.Union or (origin is not None and getattr(origin, "__name__", "") == "UnionType"):
        inner = [a for a in args if a is not type(None)]
        if all(isinstance(a, type) and issubclass(a, BaseModel) for a in inner) and len(inner) > 1:
            kinds = []
            for a in inner:
                kind = a.model_fields.get("kind")
                if kind is not None and typing.get_origin(kind.annotation) is typing.Literal:
                    kinds.extend(typing.get_args(kind.annotation))
            return "table: kind = " + " | ".join(f'"{k}"' for k in kinds)
        return " or ".join(type_text(a) for a in inner)
    if origin is typing.Annotated:
        base, *meta = args
        for m in meta:
            text = _validator_text(m)
            if text:
                return text
        inner = type_text(base)
        for m in meta:  # list lengths (Field(min_length=..., max_length=...))
            lo = getattr(m, "min_length", None)
            for c in getattr(m, "metadata", []) or []:
                lo = getattr(c, "min_length", lo)
            hi = None
            for c in getattr(m, "metadata", []) or []:
                hi = getattr(c, "max_length", hi)
            if lo is not None and lo == hi:
                return f"{inner} ({lo} values)"
        return inner
    if origin is typing.Literal:
        return " | ".join(f'"{a}"' if isinstance(a, str) else repr(a) for a in args)
    if origin in (list, tuple):
        return "list of " + (type_text(args[0]) if args else "values")
    if origin is dict:
        return "table"
    if isinstance(annotation, type):
        if issubclass(annotation, BaseModel):
            return f"table ({annotation.__name__})"
        if annotation is bool:
            return "true | false"
        return {"str": "string", "float": "number", "int": "integer"}.get(annotation.__name__, annotation.__name__)
    text = str(annotation)
    return text.replace("typing.", "")


def field_type_text(field) -> str:
    """Type text of a pydantic field (whose top-level ``Annotated`` metadata pydantic moved into
    ``field.metadata``)."""
    for m in field.metadata:
        text = _validator_text(m)
        if text:
            return text
    return type_text(field.annotation)


def _fmt_value(v) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, float):
        return f"{v:g}"
    if isinstance(v, str):
        return f'"{v}"'
    if isinstance(v, (list, tuple)):
        return "[" + ", ".join(_fmt_value(x) for x in v) + "]"
    if isinstance(v, BaseModel):
        kind = getattr(v, "kind", None)
        return f'kind = "{kind}"' if kind is not None else "{}"
    return str(v)


def default_text(field) -> str:
    if field.default is PydanticUndefined and field.default_factory is None:
        return "required"
    value = field.default_factory() if field.default_factory is not None else field.default
    if value is None:
        return "none"
    return _fmt_value(value)


def _docstring(model) -> str:
    return inspect.cleandoc(model.__doc__ or "")


_TABLE_RULE = re.compile(r"^\s*=+(\s+=+)+\s*$")


def split_tables(doc: str) -> tuple[str, dict[str, str]]:
    """The docstring without its simple key tables, and key -> meaning from those tables."""
    lines = doc.splitlines()
    meanings: dict[str, str] = {}
    keep: list[str] = []
    i = 0
    while i < len(lines):
        if _TABLE_RULE.match(lines[i]):
            rule = lines[i]
            cols = [m.start() for m in re.finditer(r"=+", rule)]
            j = i + 3  # rule, header, rule
            key = None
            while j < len(lines) and not _TABLE_RULE.match(lines[j]):
                row = lines[j]
                first = row[cols[0]:cols[1]].strip() if len(cols) > 1 else row.strip()
                last = row[cols[-1]:].strip()
                if first:
                    key = first
                    meanings[key] = last
                elif key is not None and last:
                    meanings[key] += " " + last
                j += 1
            i = j + 1
            continue
        keep.append(lines[i])
        i += 1
    return "\n".join(keep).strip(), meanings


_ABBREV = ("e.g.", "i.e.", "Eq.", "Eqs.", "Fig.", "Figs.", "cf.", "vs.")


def _segments(doc: str) -> list[str]:
    flat = " ".join(doc.split())
    for i, abbrev in enumerate(_ABBREV):
        flat = flat.replace(abbrev, f"\x00{i}\x00")
    parts, depth, start = [], 0, 0
    for i, ch in enumerate(flat):
        depth += (ch in "([{") - (ch in ")]}")
        if ch in ".;" and depth <= 0 and (i + 1 == len(flat) or flat[i + 1] == " "):
            parts.append(flat[start:i + 1])
            start = i + 1
    parts.append(flat[start:])
    out = []
    for part in parts:
        for i, abbrev in enumerate(_ABBREV):
            part = part.replace(f"\x00{i}\x00", abbrev)
        out.append(part.strip().lstrip("* ").rstrip(";"))
    return [p for p in out if p]


def sentence_about(doc: str, key: str, keys=()) -> str:
    """The sentence (or clause) of ``doc`` that is about ``key``: one that starts with it, else
    the one naming it that names the fewest other keys (an enumeration of every key says least)."""
    lit = f"``{key}``"
    best, best_score = "", None
    for seg in _segments(doc):
        if lit not in seg:
            continue
        if seg.startswith(lit) or re.match(r"^[\w ]{0,20}: " + re.escape(lit), seg):
            return seg
        others = sum(f"``{k}``" in seg for k in keys if k != key)
        if best_score is None or others < best_score:
            best, best_score = seg, others
    return best if best_score is not None and best_score < 3 else ""


def model_rows(model, section: str | None) -> list[list[str]]:
    from tribobem.runs import KINDS

    doc = _docstring(model)
    prose, meanings = split_tables(doc)
    rows = []
    for key, field in model.model_fields.items():
        if model.__name__ == "ExpectedSpec" and key == "values":
            continue
        text = meanings.get(key) or sentence_about(prose, key, model.model_fields)
        row = [f"``{key}``", field_type_text(field), default_text(field), text]
        if section is not None:
            readers = [k for k, kind in KINDS.items()
                       if section in kind.reads() and (kind.reads()[section] == "*" or key in kind.reads()[section])]
            row.append(", ".join(readers) if len(readers) < len(KINDS) else "every kind")
        rows.append(row)
    return rows


# ----------------------------------------------------------------------------- rendering
def list_table(header: list[str], rows: list[list[str]], widths: list[int] | None = None,
               classes: str = "scenario-keys") -> list[str]:
    out = [".. list-table::", "   :header-rows: 1", f"   :class: {classes}"]
    if widths:
        out.append("   :widths: " + " ".join(str(w) for w in widths))
    out.append("")
    for row in [header] + rows:
        first = True
        for cell in row:
            cell = " ".join(str(cell).split()) or " "
            if cell[0] in "-*+":
                cell = "\\" + cell  # a cell that starts like a bullet would break the list table
            out.append(("   * - " if first else "     - ") + cell)
            first = False
    out.append("")
    return out


class _Base(Directive):
    def _parse(self, rst: list[str]) -> list[nodes.Node]:
        # The generated text is reStructuredText (docstrings, list tables) whatever the page's
        # own markup (MyST pages parse nested content as markdown): parse it as RST here.
        document = new_document(self.state.document.current_source or "scenario_keys", self.state.document.settings)
        document.settings.env = self.state.document.settings.env
        RSTParser().parse("\n".join(rst), document)
        if rst and rst[0].startswith(".. list-table::") and not list(document.findall(nodes.table)):
            # a malformed cell turns the whole table into text without a warning: fail the build
            raise self.error("the generated list table did not parse (a cell breaks its markup)")
        return list(document.children)


class ScenarioKeys(_Base):
    required_arguments = 1
    option_spec = {"section": directives.unchanged, "no-docstring": directives.flag}

    def run(self):
        from tribobem.scenario import schema

        name = self.arguments[0]
        model = getattr(schema, name, None)
        if not (isinstance(model, type) and issubclass(model, BaseModel)):
            raise self.error(f"scenario-keys: {name!r} is not a model of tribobem.scenario.schema")
        section = self.options.get("section", SECTION_OF.get(name))
        header = ["key", "type (unit)", "default", "description"]
        widths = [14, 22, 12, 52]
        if section:
            header.append("read by")
            widths = [13, 20, 10, 44, 13]
        rst = list_table(header, model_rows(model, section), widths)
        if "no-docstring" not in self.options:
            prose, _ = split_tables(_docstring(model))
            if prose:
                rst += [""] + prose.splitlines() + [""]
        return self._parse(rst)


class ScenarioKinds(_Base):
    def run(self):
        from tribobem.runs import KINDS
        from tribobem.runs.kind import COMMON

        rows = []
        for name, kind in KINDS.items():
            own = [s for s in kind.reads() if s not in COMMON or kind.reads()[s] != COMMON[s]]
            rows.append([f"``{name}``", kind.summary, ", ".join(f"``[{s}]``" for s in own),
                         ", ".join(kind.figures), ", ".join(kind.report_sections) or "-"])
        return self._parse(list_table(["kind", "what it computes", "its own sections or keys",
                                       "figure sets", "report sections"], rows, [12, 40, 20, 16, 12]))


class ScenarioReads(_Base):
    def run(self):
        from tribobem.runs import KINDS
        from tribobem.runs.kind import SECTIONS

        rows = []
        for section in SECTIONS:
            row = [f"``[{section}]``"]
            for kind in KINDS.values():
                keys = kind.reads().get(section)
                if keys is None:
                    row.append("-")
                elif keys == "*":
                    row.append("all")
                else:
                    row.append(", ".join(sorted(keys)))
            rows.append(row)
        return self._parse(list_table(["section"] + [f"``{k}``" for k in KINDS], rows))


class ExpectedKeys(_Base):
    def run(self):
        from tribobem.runs import KINDS
        from tribobem.scenario.schema import EXPECTED_KEYS

        rows = []
        for key, dim in EXPECTED_KEYS.items():
            by = [k for k, kind in KINDS.items() if key in kind.result_keys()]
            rows.append([f"``{key}``", dim, ", ".join(by) if len(by) < len(KINDS) else "every kind"])
        return self._parse(list_table(["key", "dimension", "produced by"], rows, [30, 20, 50]))


def setup(app):
    app.add_directive("scenario-keys", ScenarioKeys)
    app.add_directive("scenario-kinds", ScenarioKinds)
    app.add_directive("scenario-reads", ScenarioReads)
    app.add_directive("expected-keys", ExpectedKeys)
    return {"version": "1", "parallel_read_safe": True, "parallel_write_safe": True}


__all__ = ["setup", "type_text", "default_text", "split_tables", "model_rows"]
