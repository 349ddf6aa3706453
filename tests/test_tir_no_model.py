"""A ``.tir`` with no ``[MODEL]`` section (issue 25): ``compare`` and ``eval`` say so, naming the file
and what the family was told from; a file whose coefficients do not tell the family is refused with
the reason."""

from __future__ import annotations

from pathlib import Path

import pytest

from tyrefit.cli import main
from tyrefit.errors import FormatError
from tyrefit.io.tir import read_tyre

ROOT = Path(__file__).resolve().parents[1]
DATA = ROOT / "tests" / "data"
PAC89 = DATA / "ref_adams_pac89_example.tir"


def _strip_model(src: Path, dst: Path, extra: str = "") -> Path:
    out, skip = [], False
    for line in src.read_text(encoding="latin-1").splitlines(keepends=True):
        if line.strip().startswith("["):
            skip = line.strip().upper().startswith("[MODEL")
        if not skip:
            out.append(line)
    dst.write_text("".join(out) + extra, encoding="latin-1")
    return dst


@pytest.mark.parametrize("src, family", [("ref_adams_pac89_example.tir", "PAC89"),
                                         ("ref_HMMWV_Pac02Tire.tir", "MF52"),
                                         ("mfeval_MagicFormula61_Paramerters.tir", "MF61")])
def test_no_model_section_is_a_warning_naming_the_file(tmp_path, capsys, src, family):
    f = _strip_model(DATA / src, tmp_path / f"nomodel_{family}.tir")
    t = read_tyre(f)
    assert t.family == family
    assert main(["compare", str(f), str(PAC89), "--allow-unphysical"]) == 0
    out = capsys.readouterr().out
    line = next(x for x in out.splitlines() if "[MODEL]" in x)
    assert "warning" in line and str(f) in line and f"read as {family}" in line
    pts = tmp_path / "p.csv"
    pts.write_text("fz [N],slip_angle [deg]\n4000,2\n")
    assert main(["eval", str(f), "--points", str(pts), "--out", str(tmp_path / "o.csv"), "--allow-unphysical"]) == 0
    assert any("[MODEL]" in x and str(f) in x for x in capsys.readouterr().out.splitlines())


def test_declared_file_has_no_such_warning(capsys):
    assert main(["compare", str(PAC89), str(PAC89), "--allow-unphysical"]) == 0
    assert "[MODEL]" not in capsys.readouterr().out


def test_family_that_cannot_be_told_is_refused(tmp_path, capsys):
    f = _strip_model(DATA / "ref_HMMWV_Pac02Tire.tir", tmp_path / "mixed.tir",
                     "[EXTRA_COEFFICIENTS]\nA0 = 1.6\nA3 = 1000\n")
    with pytest.raises(FormatError, match=r"no \[MODEL\].*both PAC89"):
        read_tyre(f)
    assert main(["compare", str(f), str(PAC89)]) == 2
    err = capsys.readouterr().err
    assert "[MODEL]" in err and len(err.strip().splitlines()) == 1
