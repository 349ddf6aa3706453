"""FSAE TTC .dat errors name the file line of the bad row (issue 25's surviving mutation: every
message named the line before), with and without blank lines before it."""

from __future__ import annotations

from pathlib import Path

import pytest

from tyrefit.errors import DataError
from tyrefit.io.readers import read_data

DAT = Path(__file__).resolve().parents[1] / "data" / "ttc" / "fsae_cornering.dat"


def _write(tmp_path, lines, name="t.dat") -> Path:
    p = tmp_path / name
    p.write_text("\n".join(lines) + "\n")
    return p


@pytest.fixture(scope="module")
def lines():
    return DAT.read_text().splitlines()[:400]


def _cell(lines, file_line, col, value):
    out = list(lines)
    v = out[file_line - 1].split("\t")
    v[col] = value
    out[file_line - 1] = "\t".join(v)
    return out


@pytest.mark.parametrize("file_line", [4, 100, 399])
def test_non_numeric_cell_names_its_line(tmp_path, lines, file_line):
    with pytest.raises(DataError, match=rf"line {file_line}, column 'FY'"):
        read_data(_write(tmp_path, _cell(lines, file_line, 8, "abc")), convention="sae")


def test_nan_cell_names_its_line(tmp_path, lines):
    with pytest.raises(DataError, match=r"line 100, column 'FY"):
        read_data(_write(tmp_path, _cell(lines, 100, 8, "nan")), convention="sae")


def test_short_row_names_its_line(tmp_path, lines):
    out = list(lines)
    out[149] = "\t".join(out[149].split("\t")[:5])
    with pytest.raises(DataError, match=r"line 150\b"):
        read_data(_write(tmp_path, out), convention="sae")


def test_line_numbers_count_blank_lines(tmp_path, lines):
    out = lines[:50] + ["", ""] + lines[50:]  # file line 100 of `lines` is now line 102
    with pytest.raises(DataError, match=r"line 102, column 'FY'"):
        read_data(_write(tmp_path, _cell(out, 102, 8, "abc")), convention="sae")
