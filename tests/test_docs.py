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

    page = _scenario_keys().blocks_to_directives((DOCS / "guide" / "scenarios.md").read_text())
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


# ----------------------------------------------------------------------------- offline site, true pages
def _scenario_keys():
    sys.path.insert(0, str(DOCS / "_ext"))
    try:
        import scenario_keys
    finally:
        sys.path.remove(str(DOCS / "_ext"))
    return scenario_keys


def _conf() -> dict:
    namespace = {"__file__": str(DOCS / "conf.py")}
    path = list(sys.path)
    try:
        exec(compile((DOCS / "conf.py").read_text(encoding="utf-8"), str(DOCS / "conf.py"), "exec"), namespace)
    finally:
        sys.path[:] = path
    return namespace


#: the display equations of the theory pages
THEORY_MATHS = [m.group(1).strip() for page in sorted((DOCS / "theory").glob("*.md"))
                for m in re.finditer(r"^\$\$\n(.*?)\n\$\$$", page.read_text(encoding="utf-8"), re.S | re.M)]


@pytest.fixture(scope="module")
def maths_site(tmp_path_factory):
    """A one-page site holding the theory pages' equations, built with the documentation's
    maths settings (its maths extensions, MathJax options and MyST dollar maths)."""
    conf = _conf()
    settings = {k: v for k, v in conf.items() if k.startswith("mathjax") or k == "myst_enable_extensions"}
    settings["extensions"] = ["myst_parser"] + [e for e in conf["extensions"] if "math" in e]
    root = tmp_path_factory.mktemp("maths_site")
    (root / "src").mkdir()
    (root / "src" / "conf.py").write_text("".join(f"{k} = {v!r}\n" for k, v in settings.items()))
    (root / "src" / "index.md").write_text("# Equations\n\n" + "".join(f"$$\n{m}\n$$\n\n" for m in THEORY_MATHS))
    r = subprocess.run([sys.executable, "-m", "sphinx", "-q", "-W", "-b", "html", str(root / "src"), str(root / "out")],
                       capture_output=True, text=True, timeout=300)
    assert r.returncode == 0, r.stdout + r.stderr
    return root / "out" / "index.html"


def test_the_site_serves_mathjax_itself(maths_site):
    """The pages load MathJax from the site (a relative path to a file the build copied there,
    with its fonts), not from a CDN, and load nothing else from outside."""
    assert THEORY_MATHS, "no display equation found on the theory pages"
    html = maths_site.read_text(encoding="utf-8")
    scripts = re.findall(r'<script[^>]*\bsrc="([^"]+)"', html)
    mathjax = [s for s in scripts if "mathjax" in s.lower() or "tex-" in s]
    assert len(mathjax) == 1, scripts
    assert not re.match(r"^(https?:)?//", mathjax[0]), mathjax[0]
    script = maths_site.parent / mathjax[0]
    assert script.is_file() and script.stat().st_size > 500_000, script  # MathJax itself, not a stub
    fonts = script.parent / "output" / "chtml" / "fonts" / "woff-v2"
    assert len(list(fonts.glob("*.woff"))) >= 20, fonts  # the CHTML output's TeX fonts, loaded relative to it
    remote = [u for u in re.findall(r'<(?:script|link)[^>]*\b(?:src|href)="([^"]+)"', html)
              if re.match(r"^(https?:)?//", u)]
    assert not remote, remote


CHROMIUM = next((shutil.which(b) for b in ("chromium", "chromium-browser", "google-chrome") if shutil.which(b)), None)


@pytest.mark.skipif(CHROMIUM is None, reason="needs a headless Chromium (Debian: apt-get install chromium)")
def test_equations_are_typeset_without_a_network(maths_site):
    """Opened in a browser whose every connection outside the machine fails, each theory
    equation is typeset by MathJax (no raw TeX left, no MathJax error)."""
    argv = [CHROMIUM, "--headless", "--no-sandbox", "--disable-gpu", "--proxy-server=127.0.0.1:9",
            "--proxy-bypass-list=<-loopback>", "--virtual-time-budget=15000", "--dump-dom", maths_site.as_uri()]
    dom = subprocess.run(argv, capture_output=True, text=True, timeout=120).stdout
    assert "<h1" in dom, dom[-2000:]
    assert dom.count("<mjx-container") == len(THEORY_MATHS), dom[-2000:]
    assert "<mjx-merror" not in dom and "\\frac" not in dom


#: phrases of a test suite's state, which belongs in CHANGELOG.md, not on a theory page
TEST_STATUS = re.compile(r"slow test|\btest_\w+|\bpytest\b|\btests/|does not pass|still fails|known to fail|"
                         r"the test's|\bxfail|not gated", re.I)


@pytest.mark.parametrize("page", sorted((DOCS / "theory").glob("*.md")), ids=lambda p: p.name)
def test_theory_pages_state_limits_not_test_status(page):
    hits = [f"{page.name}:{i}: {line.strip()}" for i, line in enumerate(page.read_text(encoding="utf-8").splitlines(), 1)
            if TEST_STATUS.search(line)]
    assert not hits, "\n".join(hits)


def test_the_limit_behind_a_failing_slow_test_is_on_its_page_and_its_status_in_the_changelog():
    adhesion = (DOCS / "theory" / "adhesion.md").read_text(encoding="utf-8")
    for number in ("5.7 %", "7.3 %", "1248^2", "2.6 %", "6.1 % and 4.3 %"):
        assert number in adhesion, number
    assert "test_maugis_dugdale_curve_points[5.0]" in (ROOT / "CHANGELOG.md").read_text(encoding="utf-8")


def test_committed_key_tables_equal_what_the_schema_generates():
    """The scenario page's key tables are committed as markdown (readable on GitHub) and are
    what the schema and the run-kind registry generate now: after a schema change, run
    ``python docs/_ext/scenario_keys.py``."""
    sk = _scenario_keys()
    for page in sk.PAGES:
        text = (DOCS / page).read_text(encoding="utf-8")
        assert len(list(sk.BLOCK.finditer(text))) >= (25 if page.endswith("scenarios.md") else 1), page
        assert not sk.stale_blocks(text), f"{page}: stale {sk.stale_blocks(text)}; run python docs/_ext/scenario_keys.py"
        assert sk.update_page(text) == text, f"{page}: a bare directive fence; run python docs/_ext/scenario_keys.py"


def test_a_stale_key_table_is_named_and_the_build_renders_the_directive():
    sk = _scenario_keys()
    text = (DOCS / "guide" / "scenarios.md").read_text(encoding="utf-8")
    row = next(line for line in text.splitlines() if line.startswith("| `preload` | force (N)"))
    assert row.startswith("| `preload` | force (N), > 0 | none |") and row.endswith("| pulloff |"), row
    stale = text.replace(row, row.replace("force (N), > 0", "force (N)"))
    assert sk.stale_blocks(stale) == ["scenario-keys LoadSpec"]
    assert sk.update_page(stale) == text
    built = sk.blocks_to_directives(text)  # what Sphinx parses (source-read)
    assert "| `preload` |" not in built and "<!-- scenario-keys" not in built
    assert "```{scenario-keys} PathSpec\n:section: friction\n```\n" in built
    assert "```{scenario-keys} Scenario\n:no-docstring:\n```\n" in built
    assert "```{scenario-reads}\n```\n" in built and "```{expected-keys}\n```\n" in built


def test_markdown_cells_keep_code_and_pipes():
    sk = _scenario_keys()
    assert sk.rst_to_markdown("see :func:`~tribobem.data.topography_path` and ``\"3 %\"``") == \
        'see `tribobem.data.topography_path` and `"3 %"`'
    assert sk.markdown_table(["key", "type"], [["``slip``", '"total" | "incremental"']]) == \
        ["| key | type |", "|---|---|", '| `slip` | "total" \\| "incremental" |']


#: pages the README lists whose generated table is on the built site only (the README says so)
BUILT_SITE_ONLY: set = set()
GENERATED_FENCE = re.compile(r"^```\{(scenario-keys|scenario-kinds|scenario-reads|expected-keys)\}", re.M)


def test_the_pages_the_readme_lists_read_as_markdown():
    """README.md says its documentation pages are readable as markdown on GitHub: none shows a
    bare generated-table directive, except a page the README names as built-site only."""
    readme = (ROOT / "README.md").read_text(encoding="utf-8")
    section = readme[readme.index("readable as markdown"):readme.index("## How to cite")]
    pages = {t.split("#")[0] for t in LINK.findall(section) if t.endswith(".md") or ".md#" in t}
    assert "docs/guide/scenarios.md" in pages and len(pages) >= 10, pages
    for page in sorted(pages):
        bare = GENERATED_FENCE.findall((ROOT / page).read_text(encoding="utf-8"))
        if page in BUILT_SITE_ONLY and bare:
            head = readme[readme.index("readable as markdown"):readme.index("| page | what |")]
            assert page in head and "built site only" in head, page
        else:
            assert not bare, f"{page}: bare {bare} directives show as code on GitHub"


@pytest.mark.parametrize("stale", [False, True], ids=["current", "stale"])
def test_the_build_renders_a_committed_key_table_and_fails_on_a_stale_one(tmp_path, stale):
    sk = _scenario_keys()
    text = (DOCS / "guide" / "scenarios.md").read_text(encoding="utf-8")
    block = next(m.group(0) for m in sk.BLOCK.finditer(text) if m.group("spec") == " LoadSpec")
    if stale:
        block = block.replace("| `preload` | force (N), > 0 |", "| `preload` | force (N) |")
    (tmp_path / "src").mkdir()
    (tmp_path / "src" / "conf.py").write_text(f"import sys\nsys.path.insert(0, {str(DOCS / '_ext')!r})\n"
                                              "extensions = ['myst_parser', 'scenario_keys']\n")
    (tmp_path / "src" / "index.md").write_text("# Load\n\n" + block)
    r = subprocess.run([sys.executable, "-m", "sphinx", "-q", "-W", "-b", "html", str(tmp_path / "src"),
                        str(tmp_path / "out")], capture_output=True, text=True, timeout=300)
    if stale:
        assert r.returncode != 0
        assert "the generated table 'scenario-keys LoadSpec' is stale" in r.stderr, r.stderr
        assert "python docs/_ext/scenario_keys.py" in r.stderr
    else:
        assert r.returncode == 0, r.stdout + r.stderr
        html = (tmp_path / "out" / "index.html").read_text(encoding="utf-8")
        assert html.count('<table class="scenario-keys') == 1  # the directive's list table, not the markdown
        assert "pulloff" in html and "preload" in html
