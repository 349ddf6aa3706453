"""The tyre interface: read_tyre returns the right family; forces, checks, mirror image, ranges.

Vendor-style MF fixtures are built here from Chrono's PAC2002 file
(``ref_Generic_Pac02Tire.tir``, projectchrono/chrono, BSD-3; see
``tests/data/ref_SOURCES.md``) the way vendors ship them: UTF-8 byte-order
mark, CRLF, ``FITTYP = 6`` / ``'MF_05'``, a keyless ``[SHAPE]`` table
(``1.00 0.00`` rows), ``!`` and ``$`` comments after values, empty values where
no number is needed, a vendor section, and lengths in mm and angles in
degrees.  Read cleanly, the tyre must give the same forces as the original
file (an independent check of the unit conversion and of every reader path).
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from tyrefit.errors import FormatError, ModelError
from tyrefit.io.tir import read_property_file, read_tyre
from tyrefit.models import mf61, pac89
from tyrefit.tyres import MFTyre, MirroredTyre, Pac89Tyre, Tyre, require_physical

DATA = Path(__file__).parent / "data"
GENERIC = DATA / "ref_Generic_Pac02Tire.tir"

#: keys converted when the vendor-style fixture is written in mm / degrees / kN (factor from SI)
_MM = {"UNLOADED_RADIUS", "WIDTH", "RIM_RADIUS", "RIM_WIDTH", "BOTTOMING_RADIUS"}
_DEG = {"ALPMIN", "ALPMAX", "CAMMIN", "CAMMAX"}


def vendor_style(text: str, *, units: bool = True, fittyp: str = "6", fmt: str = "'MF_05'") -> bytes:
    """Chrono's PAC2002 file rewritten as a vendor ships MF 5.x files."""
    out = []
    for line in text.splitlines():
        s = line.strip()
        key = s.split("=")[0].strip().upper() if "=" in s else ""
        if s.startswith("PROPERTY_FILE_FORMAT"):
            out.append(f"PROPERTY_FILE_FORMAT = {fmt}   ! declared by the vendor")
            out.append(f"FITTYP = {fittyp}  $Magic Formula version number")
            out.append("MEASURING_RIG =")  # an empty value where no number is needed
            continue
        if units and key in _MM | _DEG | {"VERTICAL_STIFFNESS", "VERTICAL_DAMPING", "FZMIN", "FZMAX", "FNOMIN",
                                          "LONGVL", "VXLOW"}:
            v = float(s.split("=")[1].split("$")[0])
            if key in _MM:
                v *= 1e3
            elif key in _DEG:
                v = math.degrees(v)
            elif key in ("VERTICAL_STIFFNESS", "VERTICAL_DAMPING"):
                v *= 1e-6  # N/m -> kN/mm, N s/m -> kN s/mm
            elif key in ("LONGVL", "VXLOW"):
                v *= 1e3  # m/s -> mm/s (Adams: speeds in LENGTH/TIME)
            else:
                v *= 1e-3  # N -> kN
            out.append(f"{key:<26} = {v!r}   ! converted for the fixture")
            continue
        if units and s.startswith("LENGTH"):
            out.append("LENGTH = 'mm'")
            continue
        if units and s.startswith("ANGLE"):
            out.append("ANGLE = 'deg'")
            continue
        if units and s.startswith("FORCE"):
            out.append("FORCE = 'kN'")
            continue
        out.append(line)
        if s == "[UNITS]":
            pass
    body = "\r\n".join(out)
    head = ("[MDI_HEADER]\r\nFILE_TYPE = 'tir'\r\nFILE_VERSION = 3.0\r\nFILE_FORMAT = 'ASCII'\r\n"
            "! vendor-style fixture built by tests/test_tyre_interface.py from Chrono's Generic_Pac02Tire.tir\r\n")
    tail = ("\r\n$---------------------------------------------------------shape\r\n[SHAPE]\r\n"
            " 1.00 0.00\r\n 1.00 0.40\r\n 1.00 0.90\r\n 0.90 1.00\r\n"
            "$---------------------------------------------------------vendor\r\n[VENDOR_DATA]\r\n"
            "RIG = 'flat-trac $ with a dollar in quotes'\r\nOPERATOR =\r\nSERIAL = 'X-12' ! after a value\r\n")
    return b"\xef\xbb\xbf" + (head + body + tail).encode()


@pytest.fixture
def vendor_file(tmp_path) -> Path:
    p = tmp_path / "vendor_mf52.tir"
    p.write_bytes(vendor_style(GENERIC.read_text()))
    return p


# --------------------------------------------------------------------------- families

@pytest.mark.parametrize("fittyp,fmt,family", [("6", "'MF_05'", "MF52"), ("5", "'MF_05'", "MF52"),
                                               ("21", "'PAC2002'", "MF52"), ("61", "'USER'", "MF61"),
                                               ("62", "''", "MF61")])
def test_fittyp_decides_the_family(tmp_path, fittyp, fmt, family):
    p = tmp_path / "t.tir"
    p.write_bytes(vendor_style(GENERIC.read_text(), units=False, fittyp=fittyp, fmt=fmt))
    if family == "MF61":  # an MF 6.1 file needs NOMPRES
        p.write_bytes(p.read_bytes().replace(b"[TIRE_CONDITIONS]", b"[OPERATING_CONDITIONS]\r\nNOMPRES = 800000"
                                             b"\r\n[TIRE_CONDITIONS]"))
    t = read_tyre(p)
    assert isinstance(t, MFTyre) and t.family == family
    assert read_property_file(p).family == family


def test_fittyp_6_is_mf52_not_mf6(tmp_path):
    pf = read_property_file(DATA / "ref_HMMWV_Pac02Tire.tir")
    assert pf.format == "PAC2002" and pf.family == "MF52"
    p = tmp_path / "f6.tir"
    p.write_bytes(b"[MODEL]\nFITTYP = 6\n[LATERAL_COEFFICIENTS]\nPCY1 = 1.3\n")
    assert read_property_file(p).format == "FITTYP 6"
    assert read_property_file(p).family == "MF52"


def test_read_tyre_families_of_reference_files():
    assert isinstance(read_tyre(DATA / "ref_adams_pac89_example.tir"), Pac89Tyre)
    assert read_tyre(DATA / "ref_HMMWV_Pac89Tire.json").family == "PAC89"
    m = read_tyre(DATA / "ref_HMMWV_Pac02Tire.tir")
    assert m.family == "MF52" and m.declared_format == "PAC2002" and m.version == "5.2"
    assert isinstance(m, Tyre) and m.combined and "mx" in m.outputs


def test_unknown_family_is_one_line_error(tmp_path):
    p = tmp_path / "x.tir"
    p.write_text("[MODEL]\nPROPERTY_FILE_FORMAT = 'SWIFT'\n[LATERAL_COEFFICIENTS]\nPCY1 = 1\n")
    with pytest.raises(FormatError, match="cannot tell the tyre model.*SWIFT"):
        read_tyre(p)


# --------------------------------------------------------------------------- vendor files

def test_vendor_style_file_reads_cleanly_and_gives_the_original_forces(vendor_file):
    raw = vendor_file.read_bytes()
    assert raw.startswith(b"\xef\xbb\xbf") and b"\r\n" in raw
    pf = read_property_file(vendor_file)
    assert pf.tables["SHAPE"]["columns"] is None and pf.tables["SHAPE"]["rows"][0] == [1.0, 0.0]
    assert pf.get("RIG", section="VENDOR_DATA") == "flat-trac $ with a dollar in quotes"
    assert pf.get("OPERATOR", section="VENDOR_DATA") is None and pf.get("SERIAL") == "X-12"
    assert pf.get("MEASURING_RIG") is None
    t, ref = read_tyre(vendor_file), read_tyre(GENERIC)
    assert t.family == ref.family == "MF52"
    assert t.unloaded_radius == pytest.approx(0.4699, rel=1e-12)
    assert t.ranges["slip_angle"] == pytest.approx(ref.ranges["slip_angle"], rel=1e-12)
    assert t.fnomin == pytest.approx(35000.0, rel=1e-12)
    fz, sa, sr, cam = 30e3, np.radians(np.linspace(-12, 12, 9)), np.linspace(-0.2, 0.2, 9), 0.02
    a, b = t.forces(fz, sa, sr, cam), ref.forces(fz, sa, sr, cam)
    for k in ("fx", "fy", "mz", "mx", "my"):
        np.testing.assert_allclose(a[k], b[k], rtol=1e-9, atol=1e-9 * np.max(np.abs(b[k])))


def test_empty_value_where_a_number_is_needed_names_the_line(tmp_path):
    p = tmp_path / "a1.tir"
    p.write_text("[MODEL]\nPROPERTY_FILE_FORMAT = 'PAC89'\n[LATERAL_COEFFICIENTS]\na0 = 1.3\na1 =\n")
    with pytest.raises(FormatError, match=r"a1.tir:5: A1 in \[LATERAL_COEFFICIENTS\] has no value"):
        read_tyre(p)


def test_duplicated_key_refused_with_both_lines(tmp_path):
    p = tmp_path / "dup.tir"
    p.write_text("[MODEL]\nPROPERTY_FILE_FORMAT = 'PAC89'\n[LATERAL_COEFFICIENTS]\na0 = 1.3\na3 = 1\n\na3 = 2\n")
    with pytest.raises(FormatError, match=r"dup.tir:7: A3 is given twice in \[LATERAL_COEFFICIENTS\] \(first at "
                                          r"line 5\)"):
        read_property_file(p)


def test_incomplete_pac89_lists_what_is_missing(tmp_path):
    p = tmp_path / "inc.tir"
    p.write_text("[MODEL]\nPROPERTY_FILE_FORMAT = 'PAC89'\n[LATERAL_COEFFICIENTS]\na0 = 1.3\na1 = -22\na2 = 1000\n"
                 "[LONGITUDINAL_COEFFICIENTS]\nb0 = 1.6\n")
    t = read_tyre(p)
    assert t.missing == [f"a{i}" for i in range(3, 14)] + [f"b{i}" for i in range(1, 11)]
    probs = t.check()
    assert probs[0] == "required coefficient a3 is missing"
    with pytest.raises(ModelError, match="a3 is missing"):
        require_physical(t, str(p))


def test_mf_file_missing_required_coefficients(tmp_path):
    t = read_tyre(DATA / "mf61_small.tir")
    assert t.family == "MF61" and t.missing == ["PKY2"]


# --------------------------------------------------------------------------- forces

def test_pac89_forces_are_the_model_functions():
    t = read_tyre(DATA / "ref_adams_pac89_example.tir")
    fz, sa, sr, cam = np.array([2e3, 4e3, 6e3]), np.radians([-4.0, 1.0, 8.0]), np.array([-0.1, 0.0, 0.05]), 0.01
    f = t.forces(fz, sa, sr, cam)
    np.testing.assert_array_equal(f["fy"], pac89.lateral_force(t.coefficients, fz, sa, cam))
    np.testing.assert_array_equal(f["fx"], pac89.longitudinal_force(t.coefficients, fz, sr))
    np.testing.assert_array_equal(f["mz"], pac89.aligning_moment(t.coefficients, fz, sa, cam))
    assert f["fy"][2] < 0 and f["fy"][0] > 0  # ISO-W: positive slip angle, negative lateral force


def test_mf_forces_are_the_evaluator_with_si_parameters():
    t = read_tyre(GENERIC)
    fz, sa, sr = np.array([20e3, 35e3]), np.radians([3.0, -6.0]), np.array([0.05, -0.08])
    f = t.forces(fz, sa, sr, 0.0)
    ref = mf61.forces(t.params, fz, slip_ratio=sr, slip_angle=sa, camber=0.0, version="5.2")
    for k in ref:
        np.testing.assert_array_equal(f[k], ref[k])


def test_off_the_ground_gives_zero_and_shapes_broadcast():
    for t in (read_tyre(DATA / "ref_adams_pac89_example.tir"), read_tyre(GENERIC)):
        f = t.forces(np.array([[0.0], [-10.0], [3000.0]]), np.radians([0.0, 5.0]))
        for k, v in f.items():
            assert v.shape == (3, 2)
            assert np.all(v[:2] == 0.0) and np.all(np.isfinite(v))
        assert np.all(f["fy"][2] != 0)


@pytest.mark.parametrize("path", [DATA / "ref_adams_pac89_example.tir", GENERIC])
def test_mirror_image(path):
    """The mirrored tyre: Fy(a, g) -> -Fy(-a, -g); PAC89's coefficient flip agrees with the generic mirror."""
    t = read_tyre(path)
    m = MirroredTyre(t)
    fz, sa, cam = 4000.0 if t.family == "PAC89" else 30e3, np.radians(np.linspace(-10, 10, 11)), np.radians(2.0)
    a, b = t.forces(fz, sa, 0.03, cam), m.forces(fz, -sa, 0.03, -cam)
    np.testing.assert_allclose(b["fy"], -a["fy"], rtol=0, atol=1e-9)
    np.testing.assert_allclose(b["fx"], a["fx"], rtol=0, atol=1e-9)
    np.testing.assert_allclose(b["mz"], -a["mz"], rtol=0, atol=1e-9)
    if isinstance(t, Pac89Tyre):
        coef = t.mirrored().forces(fz, sa, 0.03, cam)
        gen = m.forces(fz, sa, 0.03, cam)
        for k in ("fx", "fy", "mz"):
            np.testing.assert_allclose(coef[k], gen[k], rtol=1e-12, atol=1e-9)
        assert t.mirrored().tyreside == "RIGHT"


# --------------------------------------------------------------------------- checks

EXAMPLE = DATA / "ref_adams_pac89_example.tir"


@pytest.mark.parametrize("change,match", [
    ({"a0": -1.0}, "lateral model is not physical: C <= 0"),
    ({"a0": 0.0}, "C <= 0"),
    ({"a4": 0.0}, "a4 = 0"),
    ({"a3": -3000.0}, "BCD <= 0"),
    ({"a7": 2.5}, "E > 1"),
    ({"a2": 1e5}, "peak friction D/Fz > 5"),
    ({"a1": 0.0, "a2": 0.0}, "D <= 0"),
    ({"b0": -1.0}, "longitudinal model is not physical: C <= 0"),
    ({"c0": -1.0}, "aligning model is not physical: C <= 0"),
])
def test_pac89_check_finds_unphysical_models(change, match):
    t = read_tyre(EXAMPLE)
    assert t.check() == []
    t.coefficients.update(change)
    assert any(match in p for p in t.check()), t.check()
    with pytest.raises(ModelError, match="allow_unphysical=True"):
        require_physical(t)
    assert require_physical(t, allow_unphysical=True)


@pytest.mark.parametrize("change,match", [
    ({"PCY1": -1.0}, "Cy = PCY1 LCY <= 0"),
    ({"PDY1": 0.1, "PDY2": 0.5}, "mu_y = 0 or changes sign"),  # crosses zero inside 1750-78750 N
    ({"PDY1": 0.0, "PDY2": 0.0}, "mu_y = 0 or changes sign"),
    ({"PDX1": 0.1, "PDX2": 0.5}, "mu_x = 0 or changes sign"),
    ({"PKY2": 0.0}, "PKY2 = 0"),
    ({"PKY1": 0.0}, "Kya = 0"),
    ({"PCX1": 0.0}, "Cx = PCX1 LCX <= 0"),
    ({"PKX1": -5.0, "PKX2": 0.0}, "Kxk <= 0"),
    ({"PEY1": 3.0, "PEY2": 0.0}, "Ey > 1"),
    ({"QCZ1": -1.0}, "Ct = QCZ1 <= 0"),
])
def test_mf_check_finds_unphysical_models(change, match):
    t = read_tyre(GENERIC)
    assert t.check() == []
    t.params.update(change)
    assert any(match in p for p in t.check()), t.check()


def test_mf_range_edges_are_warnings_not_problems():
    """Chrono's own PAC2002 tyre has E > 1 at the far edges of its declared load range: evaluable, said."""
    t = read_tyre(DATA / "ref_HMMWV_Pac02Tire.tir")
    assert t.check() == []
    assert any("Ey > 1" in w for w in t.warnings())


def test_nominal_values_and_validity():
    t = read_tyre(GENERIC)
    assert t.nominal == {"fz": 35000.0, "pressure": 800000.0, "speed": 16.7, "unloaded_radius": 0.4699,
                         "width": 0.3175}
    v = t.validity()
    assert v["fz"] == (1750.0, 78750.0) and v["slip_ratio"] == (-1.5, 1.5)
    p = read_tyre(EXAMPLE)
    assert p.validity()["fz"] == (1000.0, 10000.0)  # no FZMIN/FZMAX, no FNOMIN: the documented fallback


# --------------------------------------------------------------------------- sim and compare take any family

MF61 = DATA / "mfeval_MagicFormula61_Paramerters.tir"


@pytest.fixture(scope="module")
def hard_mf61(tmp_path_factory) -> Path:
    """MFeval's MF 6.1 example with LMUX = 0.85: the 'hard' (lower-grip) front tyre of seed 000's scenario."""
    text = MF61.read_text()
    lines = [("LMUX = 0.85" if ln.split("=")[0].strip().upper() == "LMUX" else ln) for ln in text.splitlines()]
    p = tmp_path_factory.mktemp("mf") / "hard61.tir"
    p.write_text("\n".join(lines) + "\n")
    return p


def test_sim_braking_runs_with_mf_tyres(hard_mf61, tmp_path, capsys):
    import json

    from tyrefit.cli import main
    from tyrefit.sim.tyres import AxleTyre

    js = tmp_path / "b.json"
    assert main(["sim", "braking", "--front", str(hard_mf61), "--rear", str(MF61), "--json", str(js)]) == 0
    doc = json.loads(js.read_text())
    rows = doc["rows"]
    assert len(rows) == 12 and all(r["stopping_distance_m"] > 0 for r in rows)
    for base, low in zip(rows[::2], rows[1::2]):  # the lower-grip front stops later
        assert base["vehicle"] == "base" and low["vehicle"] == "low_wear"
        assert low["stopping_distance_m"] > base["stopping_distance_m"]
    # the axle curves are the MF 6.1 evaluator's (pure slip, both tyres of the axle)
    t = read_tyre(MF61)
    axle = AxleTyre(t, 4000.0)
    k = np.linspace(-0.3, 0.3, 61)
    ref = mf61.forces(t.params, 4000.0, slip_ratio=k, version="6.1")["fx"]
    # two tyres, the right one mirrored: Fx is unchanged by the mirror at zero slip angle and camber
    np.testing.assert_allclose(axle.fx(k), 2 * ref, rtol=2e-3, atol=2.0)


def test_sim_and_compare_refuse_unphysical_tyre_files(tmp_path, capsys):
    from tyrefit.cli import main

    bad = tmp_path / "bad.tir"
    bad.write_text(EXAMPLE.read_text().replace("a0  = 1.65", "a0  = -1.65"))
    assert main(["sim", "braking", "--front", str(bad), "--rear", str(EXAMPLE)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "not physical" in err[0] and "--allow-unphysical" in err[0]
    assert main(["compare", str(bad), str(EXAMPLE)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "C <= 0" in err[0]
    assert main(["compare", str(bad), str(EXAMPLE), "--allow-unphysical"]) == 0


def test_compare_pac89_against_mf(capsys):
    from tyrefit.cli import main

    assert main(["compare", str(EXAMPLE), str(MF61)]) == 0


@pytest.mark.parametrize("edit,match", [
    (lambda t: t.replace("a4  = 12.80", "a4  = 0.0"), "a4 = 0"),
    (lambda t: t.replace("a3  = 3036.0", "a3  = -3036.0"), "BCD <= 0"),
    (lambda t: t.replace("a1  = -34.0", "a1  = 5e8"), "peak friction"),
    (lambda t: t.replace("a0  = 1.65", "a0  = 0.0"), "C <= 0"),
    (lambda t: t.replace("a5  = 0.00501", "a5  = 0.00501\na5  = 0.1"), "given twice"),
    (lambda t: t[: t.index("[LONGITUDINAL_COEFFICIENTS]") + 40], "missing"),  # truncated mid-block
    (lambda t: t[: t.index("a2  =")], "missing"),
])
def test_sim_refuses_bad_tyre_files_in_one_line(tmp_path, capsys, edit, match):
    """Issue 15: a0 = 0, a4 = 0, a3 < 0, huge a1, duplicated keys, truncated files reached sim."""
    from tyrefit.cli import main

    text = EXAMPLE.read_text()
    bad = tmp_path / "bad.tir"
    bad.write_text(edit(text))
    assert bad.read_text() != text
    js = tmp_path / "o.json"
    assert main(["sim", "curved", "--front", str(bad), "--rear", str(EXAMPLE), "--json", str(js)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and match in err[0], err
    assert not js.exists()


@pytest.mark.parametrize("key,match", [("FNOMIN", "FNOMIN = 0 must be positive"), ("LONGVL", "LONGVL = 0 must be"),
                                       ("NOMPRES", "NOMPRES = 0 must be")])
def test_mf_nominal_values_must_be_positive(tmp_path, key, match):
    lines = [(f"{key} = 0" if ln.split("=")[0].strip().upper() == key else ln) for ln in MF61.read_text().splitlines()]
    p = tmp_path / "z.tir"
    p.write_text("\n".join(lines) + "\n")
    problems = read_tyre(p).check()
    assert any(match in q for q in problems), problems
    assert all("not finite" not in q for q in problems)  # said plainly, before any evaluation


def test_unreadable_fittyp_is_said(tmp_path):
    p = tmp_path / "f.tir"
    p.write_text("[MODEL]\nFITTYP = abc\n[LATERAL_COEFFICIENTS]\nPCY1 = 1\n")
    with pytest.raises(FormatError, match="FITTYP abc"):
        read_tyre(p)
