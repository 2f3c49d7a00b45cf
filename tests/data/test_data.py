"""The measured topographies shipped with tribobem (tribobem.data), the one setting that finds them
(TRIBOBEM_DATA_DIR), scenario paths "data:NAME", and the installed package's independence of the
repository's studies (issue 18 item 4, issue 22 item 1)."""

from __future__ import annotations

import json
import os
import re
import shutil
import subprocess
import sys
import tomllib
from pathlib import Path

import pytest
from typer.testing import CliRunner

from tribobem.cli import app
from tribobem.data import DATA_ENV, TOPOGRAPHIES, topography_dir, topography_path
from tribobem.errors import InputError
from tribobem.scenario import build_problem, parse_scenario

ROOT = Path(__file__).resolve().parents[2]
runner = CliRunner()


def _scenario(path: str) -> dict:
    return {
        "kind": "normal",
        "grid": {"n": 16, "periodic": False},
        "body1": {"E": "3 GPa", "nu": 0.35, "roughness": {"kind": "file", "path": path, "detrend": "center"}},
        "body2": {"rigid": True, "shape": {"kind": "sphere", "radius": "10 um"}},
        "load": {"force": "1 uN"},
    }


def test_the_four_files_ship_with_their_origin_and_licence(monkeypatch):
    monkeypatch.delenv(DATA_ENV, raising=False)
    folder = topography_dir()
    assert folder == Path(__import__("tribobem").__file__).resolve().parent / "data" / "topographies"
    for name in TOPOGRAPHIES:
        p = topography_path(name)
        assert p == folder / name and p.is_file() and p.stat().st_size > 100_000
    notice = (folder / "README.md").read_text()
    assert "SurfaceTopography" in notice and "MIT" in notice and "Permission is hereby granted" in notice
    for name in TOPOGRAPHIES:
        assert name in notice
    # package data: installed by `pip install .` (CI installs non-editable)
    with open(ROOT / "pyproject.toml", "rb") as fh:
        package_data = tomllib.load(fh)["tool"]["setuptools"]["package-data"]["tribobem"]
    assert "data/topographies/*" in package_data


def test_data_dir_setting_replaces_the_folder(monkeypatch, tmp_path):
    monkeypatch.setenv(DATA_ENV, str(tmp_path))
    assert topography_dir() == tmp_path
    with pytest.raises(InputError, match=DATA_ENV) as err:
        topography_path("example_ps.tiff")  # nothing else is searched
    assert str(tmp_path) in str(err.value) and err.value.field == "path"
    assert topography_path("example_ps.tiff", must_exist=False) == tmp_path / "example_ps.tiff"
    monkeypatch.delenv(DATA_ENV)
    shutil.copyfile(topography_path("di-3.di"), tmp_path / "mine.di")
    monkeypatch.setenv(DATA_ENV, str(tmp_path))
    assert topography_path("data:mine.di") == tmp_path / "mine.di"


@pytest.mark.parametrize("name", ["", "data:", "../example_ps.tiff", "/etc/passwd", "a/../../b"])
def test_data_names_stay_inside_the_folder(name):
    with pytest.raises(InputError, match="data folder"):
        topography_path(name)


def test_scenario_names_a_shipped_file(monkeypatch, tmp_path):
    monkeypatch.delenv(DATA_ENV, raising=False)
    prob = build_problem(parse_scenario(_scenario("data:example_ps.tiff")), base_dir=tmp_path)
    assert prob.grid.lx == pytest.approx(1e-6)  # the size of the Park scan
    # a data: name that is not there: one InputError naming the key and the folder
    with pytest.raises(InputError, match=r"body1\.roughness\.path: data:nope\.tiff: no file") as err:
        build_problem(parse_scenario(_scenario("data:nope.tiff")), base_dir=tmp_path)
    assert str(topography_dir()) in str(err.value) and "example_ps.tiff" in str(err.value)
    # the setting applies to scenarios as well
    monkeypatch.setenv(DATA_ENV, str(tmp_path))
    with pytest.raises(InputError, match=DATA_ENV):
        build_problem(parse_scenario(_scenario("data:example_ps.tiff")), base_dir=tmp_path)


def test_info_reads_a_shipped_file(monkeypatch):
    monkeypatch.delenv(DATA_ENV, raising=False)
    r = runner.invoke(app, ["info", "data:example_ps.tiff", "--json"], catch_exceptions=False)
    assert r.exit_code == 0, r.output
    d = json.loads(r.stdout)
    assert d["grid"] == [512, 512] and d["rms_height"] == pytest.approx(3.933e-9, rel=0.01)
    r = runner.invoke(app, ["info", "data:nope.tiff"], catch_exceptions=False)
    out = r.output.strip()
    assert r.exit_code == 2 and len(out.splitlines()) == 1 and out.startswith("error:") and "nope.tiff" in out


def _text_files():
    for folder in ("src", "tests", "examples", "benchmarks", "studies", "docs", ".ci"):
        for p in (ROOT / folder).rglob("*"):
            generated = any(part in ("_build", "api") for part in p.relative_to(ROOT).parts[:2]) and folder == "docs"
            if p.is_file() and p.suffix in (".py", ".toml", ".md", ".txt", ".cfg", "") and "egg-info" not in str(p) \
                    and not generated:
                yield p
    yield ROOT / "README.md"
    yield ROOT / "CHANGELOG.md"
    yield ROOT / "pyproject.toml"


def test_no_file_refers_to_a_sibling_data_folder():
    """The data are found through tribobem.data, never by a path guess next to the repository."""
    pattern = re.compile(r"\.\./(\.\./)?" + "shared" + r"|[\"']" + "shared" + r"[\"']\s*/|" + "shared" + "/data")
    bad = []
    for p in _text_files():
        try:
            text = p.read_text(encoding="utf-8")
        except (UnicodeDecodeError, OSError):
            continue
        bad += [f"{p.relative_to(ROOT)}:{i}" for i, line in enumerate(text.splitlines(), 1) if pattern.search(line)]
    assert not bad, bad


def test_installed_package_never_imports_the_studies(tmp_path):
    """`tribobem validate` (every physics module, with its computations and references) imports
    without the repository's `studies` package: run from a folder outside the repository."""
    code = ("import sys, tribobem, tribobem.validation as v, tribobem.validation.paper_e, "
            "tribobem.validation.studies, tribobem.validation.bisinusoidal, tribobem.validation.paper_e_model; "
            "assert v.PHYSICS_CASES['studies'] and v.PHYSICS_CASES['paper_e']; "
            "assert not [m for m in sys.modules if m == 'studies' or m.startswith(('studies.', 'tribobem.studies'))]")
    env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
    r = subprocess.run([sys.executable, "-c", code], cwd=tmp_path, env=env, capture_output=True, text=True, timeout=120)
    assert r.returncode == 0, r.stderr
    for p in (ROOT / "src" / "tribobem").rglob("*.py"):
        assert not re.search(r"^\s*(from|import) (tribobem\.)?studies\b|from \.+studies\b", p.read_text(), re.M), p
