"""Study scripts (examples/studies/*.py) never overwrite the published data (issue 9 item 4).

Every script writes into a folder given by ``--out`` whose default lies under results/
(ignored by git); a script that has published files in docs/ writes them only with an explicit
``--publish`` (and refuses ``--publish --quick``).  The quick runs of the scripts (in the
other tests/studies/test_studies_*.py files) check that docs/ is left untouched.
"""

from __future__ import annotations

import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
SCRIPTS = sorted((ROOT / "examples" / "studies").glob("*.py"))


def _load(script: Path):
    import importlib.util

    spec = importlib.util.spec_from_file_location(f"example_{script.stem}", script)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def _help(script: Path, capsys, monkeypatch) -> str:
    monkeypatch.setenv("COLUMNS", "200")
    with pytest.raises(SystemExit) as exc:
        _load(script).main(["--help"])
    assert exc.value.code == 0
    return " ".join(capsys.readouterr().out.split())


@pytest.mark.parametrize("script", SCRIPTS, ids=[s.stem for s in SCRIPTS])
def test_outputs_go_to_out_and_docs_only_with_publish(script, capsys, monkeypatch):
    text = _help(script, capsys, monkeypatch)
    m = re.search(r"--out OUT (.*?)(?= --|$)", text)
    assert m, f"{script.name}: no --out option"
    assert re.search(r"default:? results/\w+", m.group(1)), f"{script.name}: --out default not under results/"
    source = script.read_text()
    if re.search(r"[\"']docs[\"']", source):   # the script knows the published folder
        assert "--publish" in text, f"{script.name} writes docs/ without a --publish option"


@pytest.mark.parametrize("name", ["afm_pulloff", "rough_ball_study"])
def test_publish_is_refused_for_quick_runs(name, capsys):
    with pytest.raises(SystemExit) as exc:
        _load(ROOT / "examples" / "studies" / f"{name}.py").main(["--quick", "--publish", "--out", "unused"])
    assert exc.value.code == 2 and "not with --quick" in capsys.readouterr().err
