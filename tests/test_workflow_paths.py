"""One fit workflow: ``tyrefit fit``, ``tyrefit batch fit`` and ``tf.fit`` write the same tyre file.

The same record and options, design data included (a per-file size and rated load from a batch
manifest), must give byte-identical ``.tir`` files from the three paths (lines carrying a date
aside).  Before the workflow moved into :mod:`tyrefit.workflows.fit`, the batch path fitted without
the size and rated load (no dimensions, FNOMIN or estimates), so these tests fail on it.
"""

from __future__ import annotations

import re
import shutil
from pathlib import Path

import pytest

import tyrefit as tf
from tyrefit.cli import main
from tyrefit.errors import DataError
from tyrefit.workflows.batch import batch_fit, read_manifest

DATA = Path(__file__).resolve().parents[1] / "data"
_DATE = re.compile(r"\b(19|20)\d\d-\d\d-\d\d\b")


def _text(path: Path) -> list[str]:
    return [ln for ln in path.read_text().splitlines() if not _DATE.search(ln)]


CASES = [
    # (bundled record, convention, model, size, rated load [N])
    ("truck/tyre_a_dynamic.csv", "iso", "pac89", "385/65R22.5", 41678.0),
    ("ttc_mf61/cornering.dat", "sae", "mf61", "16x7.5-10", 1100.0),
]


@pytest.mark.parametrize("rel, conv, model, size, load", CASES, ids=["pac89-truck", "mf61-ttc"])
def test_fit_batch_and_api_write_the_same_tyre(tmp_path, rel, conv, model, size, load, capsys):
    db = tmp_path / "db"
    db.mkdir()
    src = db / Path(rel).name
    shutil.copy(DATA / rel, src)
    # 1. the command line
    cli = tmp_path / "cli.tir"
    assert main(["fit", str(src), "--model", model, "--convention", conv, "--size", size,
                 "--rated-load", f"{load:g}", "--out", str(cli)]) == 0
    # 2. a batch with a manifest giving this file's size and rated load (in kN: the unit is read)
    (db / "tyres.csv").write_text(f"file,size,rated_load [kN]\n{src.name},{size},{load / 1e3:g}\n")
    res = batch_fit(str(src), tmp_path / "batch", workers=1, progress=False, model=model, convention=conv,
                    manifest=db / "tyres.csv")
    assert res.n_ok == 1, res.failed
    # 3. the Python API
    api = tmp_path / "api.tir"
    r = tf.fit(str(src), model=model, convention=conv, size=size, rated_load=load)
    if model == "pac89":
        r.tyre.to_tir(api)
    else:
        r.write_tir(api)
    a, b, c = _text(cli), _text(tmp_path / "batch" / f"{src.stem}.tir"), _text(api)
    assert a == b == c
    # and the design data are really in it (not three equal files without them)
    joined = "\n".join(a)
    assert "ESTIMATED" in joined and (f"{load:g}" in joined.replace(" ", "") or "FNOMIN" in joined)


def test_batch_without_manifest_is_the_fit_without_options(tmp_path):
    src = tmp_path / "tyre_a_dynamic.csv"
    shutil.copy(DATA / "truck/tyre_a_dynamic.csv", src)
    assert main(["fit", str(src), "--out", str(tmp_path / "cli.tir")]) == 0
    res = batch_fit(str(src), tmp_path / "batch", workers=1, progress=False)
    assert res.n_ok == 1
    assert _text(tmp_path / "cli.tir") == _text(tmp_path / "batch" / "tyre_a_dynamic.tir")


def test_manifest_changes_refit_the_tyre(tmp_path):
    """The size and load are in each tyre's fingerprint: changing them refits, keeping them skips."""
    src = tmp_path / "db" / "t.csv"
    src.parent.mkdir()
    shutil.copy(DATA / "truck/tyre_a_dynamic.csv", src)
    man = tmp_path / "db" / "m.csv"
    man.write_text("file,rated_load [N]\nt.csv,41678\n")
    out = tmp_path / "out"
    assert batch_fit(str(src), out, workers=1, progress=False, manifest=man).n_ok == 1
    assert batch_fit(str(src), out, workers=1, progress=False, manifest=man).n_skipped == 1
    man.write_text("file,rated_load [N]\nt.csv,40000\n")
    assert batch_fit(str(src), out, workers=1, progress=False, manifest=man).n_ok == 1
    assert "40000" in (out / "t.tir").read_text().replace(" ", "")


@pytest.mark.parametrize("text, match", [
    ("file,size\nnot_there.csv,385/65R22.5\n", r"line 2: 'not_there.csv' is none of the batch's data files"),
    ("file,rated_load\nt.csv,41678\n", r"needs its unit in the header"),
    ("file,rated_load [m]\nt.csv,41678\n", r"rated_load \[m\]"),
    ("file,rated_load [N]\nt.csv,-5\n", r"line 2: .*rated"),
    ("file,size\nt.csv,banana\n", r"line 2: "),
    ("file,colour\nt.csv,red\n", r"needs 'file' and 'size'"),
    ("file,size,tread\nt.csv,385/65R22.5,x\n", r"unknown column"),
    ("file,size\nt.csv,385/65R22.5\nt.csv,385/65R22.5\n", r"line 3: 't.csv' has a row already"),
    ("", r"empty"),
])
def test_bad_manifest_is_one_line(tmp_path, text, match):
    src = tmp_path / "t.csv"
    src.write_text("x\n")
    man = tmp_path / "m.csv"
    man.write_text(text)
    with pytest.raises(DataError, match=match) as e:
        read_manifest(man, [src])
    assert "\n" not in str(e.value)


def test_a_relative_path_gives_the_same_file(tmp_path, monkeypatch):
    """``tyrefit fit db/a.csv`` from the data's parent and a batch of the folder write the same bytes."""
    db = tmp_path / "db"
    db.mkdir()
    shutil.copy(DATA / "truck/tyre_a_dynamic.csv", db / "a.csv")
    monkeypatch.chdir(tmp_path)
    assert main(["fit", "db/a.csv", "--out", "cli.tir"]) == 0
    assert batch_fit("db", tmp_path / "batch", workers=1, progress=False).n_ok == 1
    assert (tmp_path / "cli.tir").read_bytes() == (tmp_path / "batch" / "a.tir").read_bytes()
