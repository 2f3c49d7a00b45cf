"""Sphinx extension: the API reference pages, written at build time from the package itself.

One page per public module of :mod:`tribobem` (``docs/api/<module>.rst``, generated, not
tracked): a package page holds its docstring and a table of contents of its modules; a module
page documents its public names (``__all__`` where the module defines it) with autodoc and
numpydoc.  ``docs/api/toplevel.rst`` lists the names of ``import tribobem``, each linked to the
module that defines it.  Private modules (a name starting with ``_``) are left out.
"""

from __future__ import annotations

import importlib
import pkgutil
from pathlib import Path


def public_modules(package: str = "tribobem") -> list[str]:
    pkg = importlib.import_module(package)
    names = [package]
    for info in pkgutil.walk_packages(pkg.__path__, package + "."):
        if not any(part.startswith("_") for part in info.name.split(".")):
            names.append(info.name)
    return sorted(names)


def _title(text: str, char: str = "=") -> str:
    return f"{text}\n{char * len(text)}\n"


def _is_package(name: str) -> bool:
    return hasattr(importlib.import_module(name), "__path__")


def module_page(name: str, modules: list[str]) -> str:
    out = [_title(f"``{name}``"), f".. automodule:: {name}"]
    if _is_package(name):
        out.append("   :no-members:\n")
        children = [m for m in modules if m.rsplit(".", 1)[0] == name]
        if children:
            out.append(".. rubric:: Modules\n")
            out.append(".. toctree::\n   :maxdepth: 1\n")
            out += [f"   {m}" for m in children]
            out.append("")
    else:
        out.append("   :members:\n")
    return "\n".join(out) + "\n"


def toplevel_page() -> str:
    import tribobem

    rows = []
    for name in tribobem.__all__:
        if name.startswith("_"):
            continue
        obj = getattr(tribobem, name)
        module = getattr(obj, "__module__", None) or "tribobem"
        kind = "class" if isinstance(obj, type) else "func"
        if isinstance(obj, type) and issubclass(obj, BaseException):
            kind = "exc"
        doc = (getattr(obj, "__doc__", None) or "").strip().splitlines()
        first = doc[0].strip() if doc else ""
        rows.append((f":py:{kind}:`{name} <{module}.{name}>`", f"``{module}``", first))
    out = [".. list-table::", "   :header-rows: 1", "   :widths: 25 25 50", "",
           "   * - name", "     - defined in", "     - what"]
    for a, b, c in rows:
        c = c.replace("|", "\\|").replace("*", "\\*")
        out += [f"   * - {a}", f"     - {b}", f"     - {c}"]
    return "\n".join(out) + "\n"


def write_pages(app) -> None:
    folder = Path(app.srcdir) / "api"
    folder.mkdir(exist_ok=True)
    modules = [m for m in public_modules() if m != "tribobem"]
    wanted = {f"{m}.rst": module_page(m, modules) for m in modules}
    wanted["toplevel.rst"] = toplevel_page()
    for old in folder.glob("*.rst"):
        if old.name not in wanted:
            old.unlink()
    for fname, text in wanted.items():
        path = folder / fname
        if not path.exists() or path.read_text() != text:  # unchanged pages keep their mtime
            path.write_text(text)


def setup(app):
    app.connect("builder-inited", write_pages)
    return {"version": "1", "parallel_read_safe": True, "parallel_write_safe": True}
