"""The documentation cannot drift from the code: its code blocks run, its links exist.

* Every ```python block of README.md and of the user guide (docs/guide/*.md) runs, in a
  temporary folder holding a copy of the repository's examples/.
* Every ```console block runs its ``$ `` lines there (``tribobem ...`` commands, or ``python -c``
  one-liners that prepare an input); the output lines a block shows must appear in what the
  command printed.  Every ```bash block is checked line by line: ``tribobem`` lines run, install
  and build lines (pip, python -m pytest / sphinx) are the only others allowed.
* A block whose preceding line is ``<!-- docs-test: slow -->`` runs only under ``-m slow`` (each
  of the others is a few seconds).  Blocks meant as illustrations use another language
  (```toml, ```text), never python or console.
* README.md and every page of docs/ (and CHANGELOG.md) link only to files that exist, and no
  page refers to a folder outside the repository.
"""

from __future__ import annotations

import os
import re
import shlex
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
DOCS = ROOT / "docs"
GUIDE_PAGES = sorted((DOCS / "guide").glob("*.md"))
RUN_PAGES = [ROOT / "README.md"] + GUIDE_PAGES
ALL_PAGES = ([ROOT / "README.md", ROOT / "CHANGELOG.md"]
             + sorted(p for p in DOCS.rglob("*.md") if "_build" not in p.parts and "api" not in p.parts))

SLOW_MARK = "<!-- docs-test: slow -->"
FENCE = re.compile(r"^```(\w+)[^\n]*\n(.*?)^```\s*$", re.S | re.M)
#: bash lines that install or build rather than use tribobem (not run here: the environment
#: already has them, and the test suite must not run itself)
SETUP = re.compile(r"^(pip install|python -m pytest|python -m sphinx)\b")


def _blocks(page: Path):
    text = page.read_text(encoding="utf-8")
    for m in FENCE.finditer(text):
        lang, body = m.group(1), m.group(2)
        before = text[:m.start()].rstrip().splitlines()
        slow = bool(before) and before[-1].strip() == SLOW_MARK
        line = text[:m.start()].count("\n") + 1
        yield lang, body, slow, f"{page.relative_to(ROOT)}:{line}"


def _params(langs):
    out = []
    for page in RUN_PAGES:
        for lang, body, slow, where in _blocks(page):
            if lang in langs:
                marks = [pytest.mark.slow] if slow else []
                out.append(pytest.param(body, where, id=where, marks=marks))
    return out


@pytest.fixture
def workdir(tmp_path, monkeypatch):
    shutil.copytree(ROOT / "examples", tmp_path / "examples")
    monkeypatch.chdir(tmp_path)
    monkeypatch.setenv("MPLBACKEND", "Agg")
    return tmp_path


@pytest.mark.parametrize("body, where", _params({"python"}))
def test_python_block_runs(body, where, workdir):
    code = compile(body, where, "exec")
    exec(code, {"__name__": "__docs__"})


def _argv(command: str) -> list[str]:
    """``tribobem ...`` runs the installed command; ``python ...`` this interpreter."""
    argv = shlex.split(command)
    if argv[0] == "tribobem":
        exe = shutil.which("tribobem")
        assert exe, "the tribobem command is not installed (pip install .)"
        return [exe] + argv[1:]
    if argv[0] == "python":
        return [sys.executable] + argv[1:]
    raise AssertionError(f"a console block may run only tribobem or python: {command!r}")


def _run(command: str, cwd: Path, where: str) -> str:
    env = {**os.environ, "MPLBACKEND": "Agg", "COLUMNS": "200"}
    argv = _argv(command)
    r = subprocess.run(argv, cwd=cwd, env=env, capture_output=True, text=True, timeout=600)
    out = r.stdout + r.stderr
    assert r.returncode == 0, f"{where}: `{command}` exited {r.returncode}:\n{out[-3000:]}"
    return out


@pytest.mark.parametrize("body, where", _params({"console"}))
def test_console_block_runs(body, where, workdir):
    commands, expected = [], {}
    for line in body.splitlines():
        if line.startswith("$ "):
            commands.append(line[2:].strip())
            expected[len(commands) - 1] = []
        elif line.strip() and commands:
            expected[len(commands) - 1].append(line.strip())
    assert commands, f"{where}: a console block without a $ command"
    for i, command in enumerate(commands):
        out = " ".join(_run(command, workdir, where).split())
        for shown in expected[i]:
            assert " ".join(shown.split()) in out, f"{where}: `{command}` did not print {shown!r}:\n{out[-3000:]}"


@pytest.mark.parametrize("body, where", _params({"bash", "sh", "shell"}))
def test_bash_block_runs(body, where, workdir):
    for raw in body.splitlines():
        line = raw.split(" #")[0].strip() if not raw.lstrip().startswith("#") else ""
        if not line:
            continue
        if SETUP.match(line):
            continue
        assert line.startswith("tribobem"), f"{where}: a bash block may hold tribobem commands and install/build " \
                                             f"lines only (or use ```text for an illustration): {line!r}"
        _run(line, workdir, where)


def test_every_guide_page_and_the_readme_have_runnable_blocks():
    """The collection above is not empty by accident (a renamed fence would skip everything)."""
    langs = [lang for page in RUN_PAGES for lang, *_ in _blocks(page)]
    assert langs.count("python") >= 4 and langs.count("console") >= 4, langs


# ----------------------------------------------------------------------------- links
LINK = re.compile(r"!?\[[^\]]*\]\(([^)\s]+)(?:\s+\"[^\"]*\")?\)")
INCLUDE = re.compile(r"^```\{(?:include|literalinclude)\}\s+(\S+)", re.M)


def _targets(page: Path):
    text = page.read_text(encoding="utf-8")
    text_wo_code = re.sub(r"^```(?!\{).*?^```", "", text, flags=re.S | re.M)
    for m in LINK.finditer(text_wo_code):
        yield m.group(1)
    for m in INCLUDE.finditer(text):
        yield m.group(1)


@pytest.mark.parametrize("page", ALL_PAGES, ids=lambda p: str(p.relative_to(ROOT)))
def test_relative_links_and_images_exist(page):
    missing = []
    for target in _targets(page):
        if re.match(r"^[a-z]+:", target) or target.startswith("#"):
            continue  # external (https:, mailto:) or an anchor on the same page
        path = target.split("#")[0]
        if not (page.parent / path).exists():
            missing.append(target)
    assert not missing, f"{page.relative_to(ROOT)}: links to missing files {missing}"


@pytest.mark.parametrize("page", ALL_PAGES + sorted((DOCS / "_ext").glob("*.py")) + [DOCS / "conf.py"],
                         ids=lambda p: str(p.relative_to(ROOT)))
def test_docs_never_reference_a_folder_outside_the_repository(page):
    text = page.read_text(encoding="utf-8")
    assert not re.search(r"\.\./" + "shared|" + "shared" + "/(data|seed)", text), page


def test_generated_key_tables_cover_every_scenario_section():
    """The scenario page asks the build for a key table of every section model of the schema."""
    from tribobem.scenario import schema

    page = (DOCS / "guide" / "scenarios.md").read_text()
    wanted = ["GridSpec", "BodySpec", "LoadSpec", "AdhesionSpec", "FrictionSpec", "PathSpec", "HumiditySpec",
              "SolverSpec", "OutputSpec", "ExpectedSpec", "FilmSpec", "TextureSpec", "WavinessSpec", "CropSpec"]
    wanted += [m.__name__ for m in (schema.GaussianRoughness, schema.SelfAffineRoughness, schema.FileRoughness,
                                    schema.ArrayRoughness, schema.SphereShape, schema.CylinderShape,
                                    schema.WavySphereShape, schema.BisinusoidalShape, schema.BurlShape)]
    missing = [m for m in wanted if f"{{scenario-keys}} {m}" not in page]
    assert not missing, missing


def test_key_table_rows_come_from_the_models():
    """The docs extension reads type, unit, default and the readers from the schema and registry."""
    sys.path.insert(0, str(DOCS / "_ext"))
    try:
        import scenario_keys as sk
    finally:
        sys.path.remove(str(DOCS / "_ext"))
    from tribobem.scenario import schema

    rows = {r[0]: r for r in sk.model_rows(schema.LoadSpec, "load")}
    assert rows["``preload``"][1] == "force (N), > 0" and rows["``preload``"][4] == "pulloff"
    assert rows["``steps``"][2] == "40"
    rows = {r[0]: r for r in sk.model_rows(schema.HumiditySpec, "humidity")}
    assert rows["``temperature``"][1].startswith("temperature (K)") and rows["``temperature``"][2] == "295"
    assert "meniscus" in rows["``critical_distance``"][3]
