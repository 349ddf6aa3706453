"""``eval`` writes in chunks (bounded memory) and the file is the same byte for byte at any chunk size
(issue 25)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import tyrefit.commands.eval as ev
from tyrefit.cli import main

DATA = Path(__file__).resolve().parent / "data"
TYRES = ["mfeval_MagicFormula61_Paramerters.tir", "ref_HMMWV_Pac02Tire.tir", "ref_adams_pac89_example.tir",
         "ref_HMMWV_Pac89Tire.json"]


@pytest.fixture(scope="module")
def points(tmp_path_factory):
    rng = np.random.default_rng(7)
    n = 2503
    p = tmp_path_factory.mktemp("pts") / "p.csv"
    cols = [rng.uniform(500, 9000, n), rng.uniform(-15, 15, n), rng.uniform(-0.3, 0.3, n), rng.uniform(-4, 4, n)]
    cols[0][5] = -100.0  # a wheel off the ground
    with open(p, "w") as f:
        f.write("fz [N],slip_angle [deg],slip_ratio [-],camber [deg],label [-]\n")
        for i in range(n):
            f.write(f"{cols[0][i]:.6g},{cols[1][i]:.6g},{cols[2][i]:.5g},{cols[3][i]:.4g},{i % 3}\n")
    return p


@pytest.mark.parametrize("tyre", TYRES)
def test_chunked_output_is_byte_identical(tmp_path, points, tyre, monkeypatch, capsys):
    outs = []
    for chunk in (10**9, 1000, 7, 1):
        if chunk == 1:
            continue  # 2503 one-row frames: slow and adds nothing over 7
        monkeypatch.setattr(ev, "CHUNK", chunk)
        o = tmp_path / f"f{chunk}.csv"
        assert main(["eval", str(DATA / tyre), "--points", str(points), "--out", str(o), "--allow-unphysical"]) == 0
        outs.append(o.read_bytes())
    assert outs[0].count(b"\n") == 2504
    assert all(o == outs[0] for o in outs[1:])
    text = capsys.readouterr().out
    assert "2503 points" in text


def test_write_forces_default_chunk_is_used(monkeypatch, tmp_path, points):
    calls = []
    real = ev._forces

    def counting(tyre, si):
        calls.append(len(si["fz"]))
        return real(tyre, si)

    monkeypatch.setattr(ev, "_forces", counting)
    monkeypatch.setattr(ev, "CHUNK", 1000)
    assert main(["eval", str(DATA / TYRES[0]), "--points", str(points), "--out", str(tmp_path / "o.csv"),
                 "--allow-unphysical"]) == 0
    assert calls == [1000, 1000, 503]


def test_empty_points_file_writes_the_header(tmp_path, capsys):
    p = tmp_path / "e.csv"
    p.write_text("fz [N],slip_angle [deg]\n")
    rc = main(["eval", str(DATA / TYRES[0]), "--points", str(p), "--out", str(tmp_path / "o.csv"),
               "--allow-unphysical"])
    capsys.readouterr()
    if rc == 0:
        assert (tmp_path / "o.csv").read_text().splitlines()[0].startswith("fz [N],slip_angle [deg]")


def test_plain_file_streams_and_odd_files_are_read_whole_with_the_same_bytes(tmp_path, points, monkeypatch):
    """A plain numeric CSV never goes through read_points (bounded memory); a file with a comment, a blank
    line or a quoted header is read whole; both write the same bytes."""
    tyre = str(DATA / TYRES[1])
    whole = []
    real = ev.read_points
    monkeypatch.setattr(ev, "read_points", lambda p: (whole.append(p), real(p))[1])
    monkeypatch.setattr(ev, "CHUNK", 500)
    assert main(["eval", tyre, "--points", str(points), "--out", str(tmp_path / "a.csv"), "--allow-unphysical"]) == 0
    assert whole == []
    lines = points.read_text().splitlines()
    odd = tmp_path / "odd.csv"
    odd.write_text("# a comment\n" + lines[0] + "\n" + "\n".join(lines[1:1000]) + "\n\n" + "\n".join(lines[1000:]) + "\n")
    assert main(["eval", tyre, "--points", str(odd), "--out", str(tmp_path / "b.csv"), "--allow-unphysical"]) == 0
    assert whole == [str(odd)]
    assert (tmp_path / "a.csv").read_bytes() == (tmp_path / "b.csv").read_bytes()


def test_bad_value_late_in_a_streamed_file_names_its_line_and_writes_nothing(tmp_path, points, monkeypatch, capsys):
    monkeypatch.setattr(ev, "CHUNK", 500)
    lines = points.read_text().splitlines()
    cells = lines[2000].split(",")
    cells[1] = "120"  # a slip angle beyond 90 deg, in the fifth chunk
    lines[2000] = ",".join(cells)
    bad = tmp_path / "bad.csv"
    bad.write_text("\n".join(lines) + "\n")
    out = tmp_path / "o.csv"
    assert main(["eval", str(DATA / TYRES[0]), "--points", str(bad), "--out", str(out), "--allow-unphysical"]) == 2
    err = capsys.readouterr().err
    assert "line 2001" in err and "slip_angle" in err and len(err.strip().splitlines()) == 1
    assert not out.exists() and sorted(p.name for p in tmp_path.iterdir()) == ["bad.csv"]
