"""Tyre property files: PAC89 read/write exactness, MF 5.x / PAC2002 / MF 6.x reading."""

import math
import re
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from tyrefit.errors import FormatError, ModelError, OutputExistsError
from tyrefit.io.tir import coefficients_for_export, format_tir, read_property_file, read_tir, read_tyre, write_tir
from tyrefit.models import pac89
from tyrefit.tyres.pac89 import Pac89Tyre

DATA = Path(__file__).parent / "data"
EXAMPLE = DATA / "ref_adams_pac89_example.tir"


def test_reads_reference_pac89():
    t = read_tir(EXAMPLE)
    c = t.coefficients
    assert (c["a0"], c["a3"], c["a13"]) == (1.65, 3036.0, 6.26206)
    assert (c["b0"], c["b10"], c["c17"]) == (1.67272, -0.176, -3.336941)
    assert t.unloaded_radius == pytest.approx(0.326)
    assert t.width == pytest.approx(0.245)
    assert t.lateral_stiffness == pytest.approx(190e3)
    assert t.tyreside == "LEFT"
    assert len([k for k in pac89.ALL if k in c]) == 43


def test_reference_read_write_read_exact(tmp_path):
    ta = read_tir(EXAMPLE)
    tb = read_tir(write_tir(ta, tmp_path / "b.tir"))
    assert tb == ta
    assert tb.coefficients == ta.coefficients


def test_write_read_write_read_exact(tmp_path):
    t1 = read_tir(EXAMPLE)
    t1.ranges = {"fz": (2013.7, 8000.1), "slip_angle": (-0.2094395102, 0.21), "camber": (-0.07, 0.0698),
                 "slip_ratio": (-0.3, 0.3)}
    t1.fnomin = 4000.0
    t1.vertical_stiffness = 209651.123456789
    t1.lateral_stiffness = 1.0 / 3.0 * 1e6
    t1.header = ["first line", "second: with = and $ signs"]
    p1 = write_tir(t1, tmp_path / "one.tir")
    t2 = read_tir(p1)
    p2 = write_tir(t2, tmp_path / "two.tir")
    t3 = read_tir(p2)
    assert p1.read_text() == p2.read_text()  # the file is a fixed point after one write
    assert t3 == t2  # read -> write -> read is exact
    assert t3.coefficients == t1.coefficients  # coefficients are written with repr: exact from the start
    assert t3.header == t1.header  # section rulers are layout, not header lines
    for k, (lo, hi) in t1.ranges.items():  # SI values converted to mm / deg: 15 significant digits
        assert t2.ranges[k] == pytest.approx((lo, hi), rel=1e-14)
    assert t2.vertical_stiffness == pytest.approx(t1.vertical_stiffness, rel=1e-14)


@settings(max_examples=60, deadline=None)
@given(values=st.lists(st.floats(allow_nan=False, allow_infinity=False, width=64, min_value=-1e12, max_value=1e12),
                       min_size=43, max_size=43))
def test_any_coefficients_round_trip_exactly(values, tmp_path_factory):
    t = Pac89Tyre(coefficients=dict(zip(pac89.ALL, values)), unloaded_radius=0.3135, width=0.205)
    d = tmp_path_factory.mktemp("rt")
    back = read_tir(write_tir(t, d / "x.tir", check=False))
    assert back.coefficients == coefficients_for_export(t)[0]  # a part without a model: its neutral block
    again = read_tir(write_tir(back, d / "y.tir", check=False))
    assert again.coefficients == back.coefficients


def test_write_refuses_existing_and_unphysical(tmp_path):
    t = read_tir(EXAMPLE)
    p = write_tir(t, tmp_path / "a.tir")
    with pytest.raises(OutputExistsError):
        write_tir(t, p)
    write_tir(t, p, force=True)
    bad = Pac89Tyre(coefficients=dict(t.coefficients, a7=1.5), ranges={"fz": (2000.0, 8000.0)})
    with pytest.raises(ModelError, match="E > 1"):
        write_tir(bad, tmp_path / "bad.tir")
    assert not (tmp_path / "bad.tir").exists()


def test_crlf_and_case_insensitive(tmp_path):
    text = EXAMPLE.read_text().replace("a3  = 3036.0", "A3  = 3036.0").replace("\n", "\r\n")
    p = tmp_path / "crlf.tir"
    p.write_bytes(text.encode())
    assert read_tir(p).coefficients == read_tir(EXAMPLE).coefficients


@pytest.mark.parametrize("name", ["ref_HMMWV_Pac02Tire.tir", "ref_Generic_Pac02Tire.tir"])
def test_reads_pac2002_files(name):
    pf = read_property_file(DATA / name)
    assert pf.format == "PAC2002"
    for sec in ("UNITS", "MODEL", "DIMENSION", "VERTICAL", "LATERAL_COEFFICIENTS", "LONGITUDINAL_COEFFICIENTS",
                "ALIGNING_COEFFICIENTS", "SCALING_COEFFICIENTS"):
        assert sec in pf.sections
    assert pf.get("FNOMIN") == 35000
    assert pf.get("PCY1", section="LATERAL_COEFFICIENTS") == pytest.approx(1.5874)
    assert pf.unit_factor("LENGTH") == 1.0 and pf.unit_factor("ANGLE") == 1.0
    assert pf.n_parameters > 150
    with pytest.raises(FormatError, match="PAC89 file is needed"):
        read_tir(DATA / name)


def test_hmmwv_pac02_is_crlf():
    raw = (DATA / "ref_HMMWV_Pac02Tire.tir").read_bytes()
    assert b"\r\n" in raw


def test_reads_mf61_style_with_curve_table_and_vendor_section():
    pf = read_property_file(DATA / "mf61_small.tir")
    assert pf.format == "MF61"
    assert pf.tables["DEFLECTION_LOAD_CURVE"]["columns"] == ["pen", "fz"]
    assert pf.tables["DEFLECTION_LOAD_CURVE"]["rows"][-1] == [0.02, 4400.0]
    assert pf.get("TEST_RIG", section="VENDOR_SPECIFIC") == "flat track"
    assert pf.get("SERIAL") == "ABC-123"
    assert pf.get("PDY1") == 1.0  # Fortran D exponent
    assert pf.get("PKY1") == -15.3
    assert pf.unit_factor("ANGLE") == 1.0
    assert any("MF-Tyre 6.1" in c for c in pf.comments)


def test_mf61_crlf_same_as_lf(tmp_path):
    p = tmp_path / "crlf.tir"
    p.write_bytes((DATA / "mf61_small.tir").read_bytes().replace(b"\n", b"\r\n"))
    a, b = read_property_file(DATA / "mf61_small.tir"), read_property_file(p)
    assert a.sections == b.sections and a.tables == b.tables


@pytest.mark.parametrize("content,match", [(b"", "empty"), (b"\x00\x01\x02binary", "binary"),
                                           (b"A = 1\n", "before any"), (b"$ only a comment\n", "no \\[SECTION\\]")])
def test_bad_files(tmp_path, content, match):
    p = tmp_path / "bad.tir"
    p.write_bytes(content)
    with pytest.raises(FormatError, match=match):
        read_property_file(p)


def test_read_tyre_dispatches_on_suffix():
    assert read_tyre(EXAMPLE).coefficients["a0"] == 1.65
    assert read_tyre(DATA / "ref_HMMWV_Pac89Tire.json").coefficients["a0"] == pytest.approx(1.49975356208205)


def test_format_writes_ranges_in_file_units():
    t = Pac89Tyre(coefficients={"a0": 1.3}, ranges={"slip_angle": (-math.radians(12), math.radians(12)),
                                                     "fz": (1000.0, 5000.0)})
    text = format_tir(t)
    assert "ALPMAX               = 12.0" in text
    assert "FZMIN                = 1000.0" in text
    assert "PROPERTY_FILE_FORMAT = 'PAC89'" in text
    assert np.isclose(float(text.split("ALPMIN")[1].split("=")[1].split()[0]), -12.0)


# --------------------------------------------------------------------------- hostile and malformed files

def test_parser_is_linear_on_long_runs_of_spaces(tmp_path):
    """Runs of spaces in comment rulers took the old regex-based parser quadratic time.

    The old ``^[$!]\\s*[-=_]{4,}\\s*[A-Za-z_ ]*$`` ruler pattern needed 69 s for a 150 KB file
    of five such lines (measured at commit 2025cc3); this 800 KB file did not finish in 30 s there (about
    20 min by the quadratic rate).  A separate process with a generous timeout bounds it; the parse itself
    takes about 10 ms.
    """
    import subprocess
    import sys

    p = tmp_path / "hostile.tir"
    lines = ["[MODEL]", "PROPERTY_FILE_FORMAT = 'PAC89'"] + ["$---- " + " " * 120_000 + "1" for _ in range(5)]
    lines += ["[LATERAL_COEFFICIENTS]", "a0 = " + " " * 100_000 + "1.3", "a1" + " " * 50_000 + "= -22",
              "[" + " " * 50_000 + "X"]
    p.write_text("\n".join(lines) + "\n")
    code = ("import sys\nfrom tyrefit.io.tir import read_property_file\nfrom tyrefit.errors import FormatError\n"
            "try:\n    read_property_file(sys.argv[1])\nexcept FormatError as e:\n    print(e)\n")
    res = subprocess.run([sys.executable, "-c", code, str(p)], capture_output=True, text=True, timeout=60)
    assert res.returncode == 0, res.stderr
    assert "cannot read section header" in res.stdout  # the last line is reported, after all the others parsed


@pytest.mark.parametrize("text,match", [
    ("[MODEL]\nPROPERTY_FILE_FORMAT = 'PAC89'\n[LATERAL_COEFFICIENTS]\na1 =\n", r":4: A1 in \[LATERAL_COEFFICIENTS\] "
                                                                             "has no value"),
    ("[MODEL]\nPROPERTY_FILE_FORMAT = 'PAC89'\n[LATERAL_COEFFICIENTS]\na0 = 1.3 $ ok\na0 = 1.4\n", "given twice"),
    ("[MODEL]\nPROPERTY_FILE_FORMAT = 'PAC89'\n[LATERAL_COEFFICIENTS]\na0 = one\n", "not a number"),
    ("[MODEL]\nPROPERTY_FILE_FORMAT = 'PAC89'\n[DIMENSION]\nWIDTH =\n", r":4: WIDTH in \[DIMENSION\] has no value"),
    ("[SHAPE]\n1.0 0.0\n1.0 0.5 0.3\n", "has 3 values"),
    ("[MODEL\nFITTYP = 61\n", "section header"),
    ("[MODEL]\nPROPERTY_FILE_FORMAT = 'PAC89'\n[LATERAL_COEFFICIENTS]\na0 1.3\n", "expected KEY = value"),
    ("[VERTICAL_FORCE_RANGE]\nFZMIN = 9000\nFZMAX = 1000\n[MODEL]\nFITTYP = 61\n", "above FZMAX"),
])
def test_malformed_files_exit_2_with_one_line(tmp_path, capsys, text, match):
    from tyrefit.cli import main

    p = tmp_path / "bad.tir"
    p.write_text(text)
    for argv in (["inspect", str(p)], ["eval", str(p), "--points", str(p), "--out", str(tmp_path / "o.csv")]):
        assert main(argv) == 2
        err = capsys.readouterr().err.strip().splitlines()
        assert len(err) == 1 and re.search(match, err[0]), err
    assert not (tmp_path / "o.csv").exists()


def test_inspect_incomplete_pac89_exit_2_lists_missing(tmp_path, capsys):
    from tyrefit.cli import main

    p = tmp_path / "inc.tir"
    p.write_text("[MODEL]\nPROPERTY_FILE_FORMAT = 'PAC89'\n[LATERAL_COEFFICIENTS]\na0 = 1.3\na1 = -22\n")
    assert main(["inspect", str(p)]) == 2
    cap = capsys.readouterr()
    err = cap.err.strip().splitlines()
    assert len(err) == 1 and "incomplete PAC89 tyre: missing a2, a3, a4" in err[0] and "a13" in err[0]
    assert "MISSING: a2" in cap.out and "family PAC89" in cap.out


@pytest.mark.parametrize("name,fmt,family", [("ref_HMMWV_Pac02Tire.tir", "PAC2002", "MF52"),
                                             ("mfeval_MagicFormula52_Paramerters.tir", "FITTYP 6", "MF52"),
                                             ("mfeval_MagicFormula61_Paramerters.tir", "MF61", "MF61"),
                                             ("ref_adams_pac89_example.tir", "PAC89", "PAC89"),
                                             ("ref_HMMWV_Pac89Tire.json", "PAC89", "PAC89")])
def test_inspect_json_declared_format_and_family(tmp_path, name, fmt, family):
    import json

    from tyrefit.cli import main

    out = tmp_path / "i.json"
    assert main(["inspect", str(DATA / name), "--json", str(out)]) == 0
    doc = json.loads(out.read_text())
    assert doc["kind"] == "tyre" and doc["format"] == fmt and doc["family"] == family
    assert doc["missing"] == [] and doc["problems"] == []
    if family == "PAC89":
        note = doc["chrono_limits"]  # every difference of ChPac89Tire::Advance that the Pac89Tyre docstring lists
        for said in ("clamps camber to +/-3 deg", "slip ratio to +/-1", "Fx*Fy/k_lat to Mz", "Mx = -Fz*Fy/k_lat",
                     "mu/0.8", "+/-89.5 deg"):
            assert said in note, said


def test_devices_and_folders_are_refused_not_read(tmp_path):
    from tyrefit.errors import TyrefitError

    (tmp_path / "folder.json").mkdir()
    for bad in ("/dev/zero", tmp_path, tmp_path / "folder.json"):  # .json goes to the Chrono reader
        with pytest.raises(TyrefitError, match="not a regular file|is a folder"):
            read_tyre(bad)
