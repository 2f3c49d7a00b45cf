"""Sphinx extension: the scenario-key tables of the user guide, generated at build time.

The tables are read from the pydantic models of :mod:`tribobem.scenario.schema` (key, type and
unit, default, description) and from the run-kind registry :data:`tribobem.runs.KINDS` (which
kind reads which key, :meth:`tribobem.runs.kind.RunKind.reads`), so they cannot go stale.

A page may keep a table as committed markdown between two marks (``<!-- scenario-keys LoadSpec
-->`` ... ``<!-- /scenario-keys -->``), so that it also reads as markdown on GitHub.  The build
checks each such block against what the schema generates now (a stale block is a warning, an
error under ``-W``) and renders the directive in its place.  ``python docs/_ext/scenario_keys.py
[--check] [PAGE ...]`` rewrites the blocks of the pages (paths relative to docs/; default the
scenario page) and turns a bare directive fence into a block; ``--check`` only reports.

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


# ----------------------------------------------------------------------------- table contents
class TableContent(typing.NamedTuple):
    """One generated table: its header, rows (reStructuredText cells), column widths (%), and
    the reStructuredText prose that follows it."""

    header: list[str]
    rows: list[list[str]]
    widths: list[int] | None
    prose: str = ""


def keys_content(name: str, options: dict | None = None) -> TableContent:
    """``scenario-keys MODEL``: the keys of a model of :mod:`tribobem.scenario.schema`."""
    from tribobem.scenario import schema

    options = options or {}
    model = getattr(schema, name, None)
    if not (isinstance(model, type) and issubclass(model, BaseModel)):
        raise ValueError(f"scenario-keys: {name!r} is not a model of tribobem.scenario.schema")
    section = options.get("section", SECTION_OF.get(name))
    header = ["key", "type (unit)", "default", "description"]
    widths = [14, 22, 12, 52]
    if section:
        header.append("read by")
        widths = [13, 20, 10, 44, 13]
    prose = "" if "no-docstring" in options else split_tables(_docstring(model))[0]
    return TableContent(header, model_rows(model, section), widths, prose)


def kinds_content() -> TableContent:
    """``scenario-kinds``: one row per run kind."""
    from tribobem.runs import KINDS
    from tribobem.runs.kind import COMMON

    rows = []
    for name, kind in KINDS.items():
        own = [s for s in kind.reads() if s not in COMMON or kind.reads()[s] != COMMON[s]]
        rows.append([f"``{name}``", kind.summary, ", ".join(f"``[{s}]``" for s in own),
                     ", ".join(kind.figures), ", ".join(kind.report_sections) or "-"])
    return TableContent(["kind", "what it computes", "its own sections or keys", "figure sets",
                         "report sections"], rows, [12, 40, 20, 16, 12])


def reads_content() -> TableContent:
    """``scenario-reads``: section by kind, the keys each kind reads."""
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
    return TableContent(["section"] + [f"``{k}``" for k in KINDS], rows, None)


def expected_content() -> TableContent:
    """``expected-keys``: the summary keys an ``expected`` table may state."""
    from tribobem.runs import KINDS
    from tribobem.scenario.schema import EXPECTED_KEYS

    rows = []
    for key, dim in EXPECTED_KEYS.items():
        by = [k for k, kind in KINDS.items() if key in kind.result_keys()]
        rows.append([f"``{key}``", dim, ", ".join(by) if len(by) < len(KINDS) else "every kind"])
    return TableContent(["key", "dimension", "produced by"], rows, [30, 20, 50])


#: directive name -> (takes a model name, content function)
CONTENT = {
    "scenario-keys": keys_content,
    "scenario-kinds": kinds_content,
    "scenario-reads": reads_content,
    "expected-keys": expected_content,
}


def content(directive: str, argument: str = "", options: dict | None = None) -> TableContent:
    fn = CONTENT[directive]
    return fn(argument, options) if directive == "scenario-keys" else fn()


# ----------------------------------------------------------------------------- Sphinx directives
class _Base(Directive):
    name = ""

    def run(self):
        try:
            table = content(self.name, self.arguments[0] if self.arguments else "", self.options)
        except ValueError as exc:
            raise self.error(str(exc)) from None
        rst = list_table(table.header, table.rows, table.widths)
        if table.prose:
            rst += [""] + table.prose.splitlines() + [""]
        return self._parse(rst)

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
    name = "scenario-keys"
    required_arguments = 1
    option_spec = {"section": directives.unchanged, "no-docstring": directives.flag}


class ScenarioKinds(_Base):
    name = "scenario-kinds"


class ScenarioReads(_Base):
    name = "scenario-reads"


class ExpectedKeys(_Base):
    name = "expected-keys"


# ----------------------------------------------------------------------------- committed markdown
# A page keeps each generated table as markdown between two marks, so that it reads on GitHub:
#
#     <!-- scenario-keys PathSpec :section: friction -->
#     | key | ... |
#     <!-- /scenario-keys -->
#
# The build checks every such block against what the schema generates now (a stale one is a
# warning, an error under -W) and renders the directive in its place (list tables with links
# into the API reference).  ``python docs/_ext/scenario_keys.py [PAGE ...]`` rewrites the
# blocks of the pages (default: the scenario page), and turns a directive fence into a block.
_NAMES = "|".join(re.escape(n) for n in CONTENT)
BLOCK = re.compile(r"^<!-- (?P<name>" + _NAMES + r")(?P<spec>(?: [^\n]*?)?) -->\n.*?^<!-- /(?P=name) -->\n",
                   re.S | re.M)
FENCE = re.compile(r"^```\{(?P<name>" + _NAMES + r")\}(?P<arg>[^\n]*)\n(?P<opts>(?::[\w-]+:[^\n]*\n)*)```[ \t]*\n",
                   re.M)
PAGES = ["guide/scenarios.md", "guide/kinds.md"]


def parse_spec(spec: str) -> tuple[str, dict]:
    """``"PathSpec :section: friction"`` -> ``("PathSpec", {"section": "friction"})``."""
    argument, *opts = re.split(r"\s+(?=:[\w-]+:)", spec.strip())
    if argument.startswith(":"):
        argument, opts = "", [argument] + opts
    options = {}
    for opt in opts:
        m = re.match(r":([\w-]+):\s*(.*)$", opt.strip())
        options[m.group(1)] = m.group(2).strip() or None
    return argument, options


def rst_to_markdown(text: str) -> str:
    """The inline reStructuredText of the docstrings as markdown: roles and literals become code
    spans (``:func:`~a.b``` -> `` `a.b` ``, ````x```` -> `` `x` ``); paragraphs and ``*`` lists
    are the same in both."""

    def role(m):
        target = m.group(1).lstrip("~")
        if "<" in target and target.endswith(">"):
            target = target[:target.index("<")].strip()
        return _code(target)

    text = re.sub(r":(?:py:)?[a-z]+:`([^`]+)`", role, text)
    return re.sub(r"``(.+?)``", lambda m: _code(m.group(1)), text, flags=re.S)


def _code(text: str) -> str:
    text = " ".join(text.split())
    return f"`` {text} ``" if "`" in text else f"`{text}`"


def markdown_table(header: list[str], rows: list[list[str]]) -> list[str]:
    def cell(text):
        text = rst_to_markdown(" ".join(str(text).split())).replace("|", "\\|")
        return text or " "

    out = ["| " + " | ".join(cell(h) for h in header) + " |", "|" + "---|" * len(header)]
    out += ["| " + " | ".join(cell(c) for c in row) + " |" for row in rows]
    return out


def markdown_block(name: str, spec: str = "") -> str:
    """The committed form of one generated table: marks, the markdown table, the prose."""
    argument, options = parse_spec(spec)
    table = content(name, argument, options)
    lines = [f"<!-- {name}{' ' + spec.strip() if spec.strip() else ''} -->", ""]
    lines += markdown_table(table.header, table.rows)
    if table.prose:
        lines += [""] + rst_to_markdown(table.prose).splitlines()
    lines += ["", f"<!-- /{name} -->"]
    return "\n".join(lines) + "\n"


def _fence_spec(m) -> str:
    parts = [m.group("arg").strip()] + [line.strip() for line in m.group("opts").splitlines()]
    return " ".join(p for p in parts if p)


def update_page(text: str) -> str:
    """The page with every generated block rewritten from the schema (and every directive fence
    turned into a block)."""
    text = FENCE.sub(lambda m: markdown_block(m.group("name"), _fence_spec(m)), text)
    return BLOCK.sub(lambda m: markdown_block(m.group("name"), m.group("spec")), text)


def stale_blocks(text: str) -> list[str]:
    """The marks (``"scenario-keys LoadSpec"``) of the blocks that differ from what the schema
    generates now."""
    return [f"{m.group('name')}{m.group('spec')}" for m in BLOCK.finditer(text)
            if m.group(0) != markdown_block(m.group("name"), m.group("spec"))]


def blocks_to_directives(text: str) -> str:
    """The page as the build renders it: each committed block replaced by its directive."""

    def fence(m):
        argument, options = parse_spec(m.group("spec"))
        opts = "".join(f":{k}:{' ' + v if v else ''}\n" for k, v in options.items())
        return f"```{{{m.group('name')}}}{' ' + argument if argument else ''}\n{opts}```\n"

    return BLOCK.sub(fence, text)


def _source_read(app, docname, source):
    from sphinx.util import logging

    text = source[0]
    if "<!-- " not in text:
        return
    for mark in stale_blocks(text):
        logging.getLogger(__name__).warning(
            f"the generated table '{mark}' is stale (the schema or the run kinds changed): "
            f"run python docs/_ext/scenario_keys.py {docname}.md", location=docname)
    source[0] = blocks_to_directives(text)


def setup(app):
    app.add_directive("scenario-keys", ScenarioKeys)
    app.add_directive("scenario-kinds", ScenarioKinds)
    app.add_directive("scenario-reads", ScenarioReads)
    app.add_directive("expected-keys", ExpectedKeys)
    app.connect("source-read", _source_read)
    return {"version": "1", "parallel_read_safe": True, "parallel_write_safe": True}


def main(argv: list[str] | None = None) -> int:
    """``python docs/_ext/scenario_keys.py [--check] [PAGE ...]``: rewrite the generated tables
    of the pages (relative to docs/; default the scenario page); ``--check`` only says which
    are stale (exit 1)."""
    import sys
    from pathlib import Path

    args = sys.argv[1:] if argv is None else argv
    check = "--check" in args
    pages = [a for a in args if a != "--check"] or PAGES
    docs = Path(__file__).resolve().parents[1]
    status = 0
    for page in pages:
        path = Path(page) if Path(page).is_absolute() or Path(page).exists() else docs / page
        text = path.read_text(encoding="utf-8")
        new = update_page(text)
        if new != text:
            if check:
                print(f"{path}: stale generated tables: {', '.join(stale_blocks(text)) or 'directive fences'}")
                status = 1
            else:
                path.write_text(new, encoding="utf-8")
                print(f"{path}: generated tables rewritten")
    return status


__all__ = ["setup", "type_text", "default_text", "split_tables", "model_rows", "update_page", "stale_blocks",
           "markdown_block", "blocks_to_directives", "main"]

if __name__ == "__main__":
    raise SystemExit(main())
