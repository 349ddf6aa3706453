"""Outputs that name a folder or a dangling link (issue 25): ``--json out/`` (trailing slash) or an
existing folder is refused, never a file named ``out``; a dangling symlink as output needs ``--force``."""

from __future__ import annotations

import os
from pathlib import Path

import pytest

from tyrefit.cli import main
from tyrefit.errors import OutputError, OutputExistsError
from tyrefit.io.outputs import check_output

ROOT = Path(__file__).resolve().parents[1]
DATA = str(ROOT / "data" / "passenger" / "passenger_205_55R16.csv")


@pytest.mark.parametrize("spelling", ["out/", "out//"])
def test_json_with_trailing_slash_is_refused(tmp_path, spelling, capsys, monkeypatch):
    monkeypatch.chdir(tmp_path)
    assert main(["inspect", DATA, "--json", spelling]) == 2
    err = capsys.readouterr().err
    assert "folder" in err and len(err.strip().splitlines()) == 1
    assert not (tmp_path / "out").exists()
    with pytest.raises(OutputError, match="folder"):
        check_output(spelling)


def test_json_naming_an_existing_folder_is_refused(tmp_path, capsys):
    (tmp_path / "out").mkdir()
    assert main(["inspect", DATA, "--json", str(tmp_path / "out")]) == 2
    assert "folder" in capsys.readouterr().err
    assert os.listdir(tmp_path / "out") == []


def test_dangling_symlink_output_needs_force(tmp_path, capsys):
    link = tmp_path / "out.json"
    link.symlink_to(tmp_path / "nowhere.json")
    with pytest.raises(OutputExistsError, match="force=True"):
        check_output(link)
    assert main(["inspect", DATA, "--json", str(link)]) == 2
    assert "--force" in capsys.readouterr().err and link.is_symlink() and not link.exists()
    check_output(link, force=True)
