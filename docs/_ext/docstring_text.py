"""Sphinx extension: read tribobem's docstrings as their authors wrote them.

Two conventions of the package's docstrings that reStructuredText would misread:

* **Absolute values.**  Physics is written in plain text, with ``|x|`` for an absolute value or
  a norm; reStructuredText reads ``|x|`` as a substitution reference (an error).  Each ``|``
  outside inline literals, roles and literal blocks is escaped; no docstring of tribobem uses a
  substitution, a line block or a grid table.
* **Relative references.**  ``:mod:`.rough``` in ``tribobem.geometry.textures`` means the
  sibling module ``tribobem.geometry.rough``, as in a relative import; Sphinx would look for
  ``tribobem.geometry.textures.rough`` and then guess among every module named ``rough``.  A
  role whose target starts with one dot and names a sibling module is made absolute.
"""

from __future__ import annotations

import importlib.util
import re

_LITERAL = re.compile(r"(``.+?``|:\w+:`[^`]*`|`[^`]*`)")
_RELATIVE = re.compile(r"(:(?:py:)?(?:mod|func|class|meth|attr|data|exc|obj):`)(~?)\.(\w+)([^`]*)`")


def _escape_line(line: str) -> str:
    parts = _LITERAL.split(line)
    return "".join(p if i % 2 else re.sub(r"(?<!\\)\|", r"\\|", p) for i, p in enumerate(parts))


def _package_of(what: str, name: str, obj) -> str:
    if what == "module":
        return name if hasattr(obj, "__path__") else name.rsplit(".", 1)[0]
    module = getattr(obj, "__module__", None) or name.rsplit(".", 1)[0]
    return module.rsplit(".", 1)[0]


def _absolute(package: str, line: str) -> str:
    def repl(m):
        role, tilde, first, rest = m.groups()
        try:
            found = importlib.util.find_spec(f"{package}.{first}") is not None
        except (ImportError, ValueError):
            found = False
        if not found:
            return m.group(0)
        return f"{role}{tilde}{package}.{first}{rest}`"

    return _RELATIVE.sub(repl, line)


def process(app, what, name, obj, options, lines):
    package = _package_of(what, name, obj)
    in_block, block_indent = False, 0
    for i, line in enumerate(lines):
        indent = len(line) - len(line.lstrip())
        if in_block:
            if line.strip() and indent <= block_indent:
                in_block = False
            else:
                continue
        line = _absolute(package, line)
        if line.rstrip().endswith("::"):
            in_block, block_indent = True, indent
            head = line.rstrip()[:-2]
            lines[i] = _escape_line(head) + "::"
            continue
        lines[i] = _escape_line(line)


def setup(app):
    app.connect("autodoc-process-docstring", process)
    return {"version": "1", "parallel_read_safe": True, "parallel_write_safe": True}
