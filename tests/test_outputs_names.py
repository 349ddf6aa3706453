"""Output names at the file system's limits (issue 25): legal names of 241-255 bytes keep legal
temporary and backup names."""

from __future__ import annotations

import os
from pathlib import Path

import pytest

from tyrefit.cli import main
from tyrefit.io.outputs import side_name, write_text

ROOT = Path(__file__).resolve().parents[1]
DATA = str(ROOT / "data" / "passenger" / "passenger_205_55R16.csv")


@pytest.mark.parametrize("nbytes", [241, 248, 255])
def test_long_output_names_written_and_replaced(tmp_path, nbytes, capsys):
    name = "a" * (nbytes - 5) + ".json"
    assert len(name.encode()) == nbytes
    out = tmp_path / name
    assert main(["inspect", DATA, "--json", str(out)]) == 0, capsys.readouterr().err
    first = out.read_text()
    assert main(["inspect", DATA, "--json", str(out), "--force"]) == 0, capsys.readouterr().err  # backup name
    assert out.read_text() == first
    assert sorted(os.listdir(tmp_path)) == [name]  # no temporary or backup left


def test_long_multibyte_name_and_report_folder(tmp_path, capsys):
    name = "é" * 125 + ".json"  # 255 bytes, 130 characters
    assert len(name.encode()) == 255
    out = tmp_path / name
    write_text(out, "x")
    write_text(out, "y", force=True)
    assert out.read_text() == "y" and os.listdir(tmp_path) == [name]


def test_side_name_fits_name_max(tmp_path):
    for name in ("a" * 255, "é" * 127, "b" * 10):
        s = side_name(name, tmp_path, suffix=".12345.bak")
        assert len(os.fsencode(s)) <= 255 and s.startswith(".") and s.endswith(".12345.bak")
        s.encode("utf-8")  # a cut never splits a character
        t = side_name(name, tmp_path, suffix=".", extra=12)
        assert len(os.fsencode(t)) + 12 <= 255
    assert side_name("short.json", tmp_path, suffix=".tmp") == ".short.json.tmp"
