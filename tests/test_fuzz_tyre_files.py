"""Fuzzing the tyre-file readers and writer/reader round trips.

``read_property_file`` / ``read_tir`` (any MF/PAC ``.tir``) and
``read_chrono_json`` are given arbitrary bytes and mutated valid files: they
must return or raise a :class:`~tyrefit.errors.TyrefitError`, nothing else.
Generated PAC89 parameter sets must survive ``write_tir -> read_tir`` and
``write_chrono_json -> read_chrono_json`` exactly (coefficients bit for bit;
values the ``.tir`` converts to mm, N/mm or degrees to the 15 significant
digits it writes them with).  Example counts come from the hypothesis profile
(tests/conftest.py, 'ci': 200 per test).
"""

from __future__ import annotations

import json
import math

import pytest
from fuzz_helpers import FUZZ, mutated, write
from hypothesis import example, given
from hypothesis import strategies as st

from tyrefit.errors import FormatError, TyrefitError
from tyrefit.io.chrono_json import chrono_dict, read_chrono_json, write_chrono_json
from tyrefit.io.tir import coefficients_for_export, format_tir, read_property_file, read_tir, read_tyre, write_tir
from tyrefit.models import pac89
from tyrefit.tyres.pac89 import Pac89Tyre

# --------------------------------------------------------------------------- valid seeds

#: the Pacejka '89 example set (Adams/Tire documentation via Project Chrono, see shared/reference)
EXAMPLE = dict(zip(pac89.ALL, [
    1.65, -34.0, 1250.0, 3036.0, 12.80, 0.00501, -0.02103, 0.77394, 0.0022890, 0.013442, 0.003709, 19.1656,
    1.21356, 6.26206,
    1.67272, -9.46, 1490.0, 30.0, 176.0, 0.08860, 0.00402, -0.06150, 0.20, 0.02990, -0.176,
    2.34, 1.4950, 6.416654, -3.57403, -0.087737, 0.098410, 0.0027699, -0.0001151, 0.10, -1.3329, 0.025501,
    -0.02357, 0.03027, -0.0647, 0.0211329, 0.89469, -0.099443, -3.336941]))

SEED_TYRE = Pac89Tyre(coefficients=EXAMPLE, unloaded_radius=0.326, width=0.245, fnomin=4000.0,
                      lateral_stiffness=190e3, vertical_stiffness=250e3, rolling_resistance=0.01,
                      ranges={"fz": (1000.0, 8000.0), "slip_angle": (-0.2, 0.2)}, name="fuzz seed",
                      mass=9.0, inertia=(0.5, 0.9, 0.5), vertical_damping=500.0)
TIR = format_tir(SEED_TYRE).encode()
JSON = (json.dumps(chrono_dict(SEED_TYRE), indent=2) + "\n").encode()
#: an MF-style property file with a curve table, CRLF and both comment styles
MF = (b"[MDI_HEADER]\r\nFILE_TYPE = 'tir'\r\n$ comment\r\n[MODEL]\r\nPROPERTY_FILE_FORMAT = 'PAC2002'\r\n"
      b"FITTYP = 6 ! inline\r\n[UNITS]\r\nLENGTH = 'meter'\r\nFORCE = 'newton'\r\n[DIMENSION]\r\n"
      b"UNLOADED_RADIUS = 0.3135\r\n[DEFLECTION_LOAD_CURVE]\r\n{pen fz}\r\n0.000 0.0\r\n0.005 1500.0\r\n"
      b"0.010 3200.5\r\n[LATERAL_COEFFICIENTS]\r\nPCY1 = 1.3\r\nPDY1 = 1.0D0\r\n")


def test_seeds_are_valid():
    back = read_tir(write("seed.tir", TIR))
    assert back.coefficients == SEED_TYRE.coefficients and back.width == SEED_TYRE.width
    assert back.ranges["slip_angle"] == pytest.approx(SEED_TYRE.ranges["slip_angle"], rel=1e-15)
    assert read_chrono_json(write("seed.json", JSON)).coefficients == SEED_TYRE.coefficients
    pf = read_property_file(write("mf.tir", MF))
    assert pf.format == "PAC2002" and pf.tables["DEFLECTION_LOAD_CURVE"]["rows"][2] == [0.010, 3200.5]


# --------------------------------------------------------------------------- oracle


def _read_tir_all(path) -> None:
    """Every .tir entry point; only tyrefit errors may escape."""
    for fn in (read_property_file, read_tir, read_tyre):
        try:
            r = fn(path)
        except TyrefitError:
            continue
        if isinstance(r, Pac89Tyre):
            assert set(r.coefficients) == set(pac89.ALL)
            assert all(isinstance(v, float) for v in r.coefficients.values())
            _ = r.check(n=5), r.validity(), r.missing  # the checks must not raise either
        elif hasattr(r, "params"):  # an MF tyre: its checks must not raise either
            _ = r.missing, r.check(n=5), r.warnings(n=5), r.validity()
        else:
            _ = r.format, r.family, r.n_parameters  # properties must not raise either


def _read_json(path) -> None:
    try:
        t = read_chrono_json(path)
    except TyrefitError:
        return
    assert set(t.coefficients) == set(pac89.ALL)
    assert all(isinstance(v, float) for v in t.coefficients.values())


# --------------------------------------------------------------------------- arbitrary and mutated input


@FUZZ
@given(data=st.binary(max_size=4096))
@example(data=b"")
@example(data=b"[MODEL]\nPROPERTY_FILE_FORMAT = 'PAC89'\n[LATERAL_COEFFICIENTS]\na0 = " + b"9" * 400 + b"\n")
@example(data=b"[UNITS]\nLENGTH = 'parsec'\n[MODEL]\nPROPERTY_FILE_FORMAT='PAC89'\na1=1\n")
def test_tir_arbitrary_bytes(data):
    _read_tir_all(write("bytes.tir", data))


@FUZZ
@given(text=st.text(max_size=2000))
def test_tir_arbitrary_text(text):
    _read_tir_all(write("text.tir", text.encode("utf-8", "surrogatepass")))


@FUZZ
@given(data=mutated(TIR))
def test_tir_mutated(data):
    _read_tir_all(write("mut.tir", data))


@FUZZ
@given(data=mutated(MF))
def test_mf_tir_mutated(data):
    _read_tir_all(write("mut_mf.tir", data))


@FUZZ
@given(data=st.binary(max_size=2048))
@example(data=b"")
@example(data=b'{"Lateral Coefficients": {"a0": ' + b"9" * 400 + b"}}")
@example(data=b'{"Lateral Coefficients": {}, "Design Parameters": []}')
@example(data=b'{"Lateral Coefficients": {}, "Design Parameters": {"Vertical Curve Data": [[1, 2, 3]]}}')
@example(data=b'{"Lateral Coefficients": {}, "Design Parameters": {"Vertical Curve Data": 5}}')
@example(data=b'{"Lateral Coefficients": {}, "Design Parameters": {"Unloaded Radius": 1e400}}')
@example(data=b'{"Lateral Coefficients": {"a0": ' + b"9" * 5000 + b"}}")  # beyond int() digit limit
@example(data=b"[" * 100_000 + b"]" * 100_000)  # deeper than the recursion limit
def test_json_arbitrary_bytes(data):
    _read_json(write("bytes.json", data))


_json_values = st.recursive(
    st.none() | st.booleans() | st.integers() | st.floats() | st.text(max_size=8),
    lambda inner: st.lists(inner, max_size=4) | st.dictionaries(st.text(max_size=8), inner, max_size=4),
    max_leaves=12)


@FUZZ
@given(doc=st.dictionaries(
    st.sampled_from(["Name", "Lateral Coefficients", "Longitudinal Coefficients", "Aligning Coefficients",
                     "Design Parameters", "Type", "Template"]),
    st.one_of(_json_values, st.dictionaries(
        st.sampled_from(list(pac89.ALL) + ["Unloaded Radius", "Width", "Vertical Curve Data", "Lateral Stiffness",
                                           "Vertical Stiffness", "Rolling Resistance", "A0"]),
        _json_values, max_size=6)),
    max_size=6))
def test_json_structured_garbage(doc):
    _read_json(write("doc.json", json.dumps(doc).encode()))


@FUZZ
@given(data=mutated(JSON))
def test_json_mutated(data):
    _read_json(write("mut.json", data))


# --------------------------------------------------------------------------- round trips

_coef = st.floats(allow_nan=False, allow_infinity=False)
_pos = st.floats(min_value=1e-3, max_value=1e4, allow_nan=False)
_name = st.text(st.characters(blacklist_categories=("Cc", "Cs", "Zl", "Zp"), blacklist_characters="'"),
                min_size=1, max_size=30).filter(lambda s: s.strip() == s and s)


@st.composite
def tyres(draw) -> Pac89Tyre:
    coeffs = {k: draw(_coef) for k in pac89.ALL}
    opt = lambda s: draw(st.one_of(st.none(), s))  # noqa: E731
    ranges = {}
    for key, lo, hi in (("fz", 0.0, 1e6), ("slip_angle", -1.5, 1.5), ("camber", -0.5, 0.5), ("slip_ratio", -1, 1)):
        if draw(st.booleans()):
            a, b = sorted(draw(st.lists(st.floats(lo, hi), min_size=2, max_size=2)))
            ranges[key] = (a, b)
    return Pac89Tyre(coefficients=coeffs, unloaded_radius=opt(_pos), width=opt(_pos), fnomin=opt(_pos),
                     lateral_stiffness=opt(_pos), vertical_stiffness=opt(_pos), rolling_resistance=draw(_coef),
                     ranges=ranges, name=draw(_name), tyreside=draw(st.sampled_from(["LEFT", "RIGHT"])),
                     header=draw(st.lists(st.text(max_size=40), max_size=3)))


def _close(a, b, rel=1e-14):
    """Equal to the 15 significant digits the .tir keeps for values it converts (mm, N/mm, deg)."""
    if a is None or b is None:
        return a is b
    return a == b or math.isclose(a, b, rel_tol=rel, abs_tol=0.0)


@FUZZ
@given(tyre=tyres())
def test_tir_round_trip(tyre):
    path = write("rt.tir", b"")
    write_tir(tyre, path, force=True, check=False)
    back = read_tir(path)
    # bit for bit (repr floats); a part without a model is written as its finite neutral block
    assert back.coefficients == coefficients_for_export(tyre)[0]
    for f in ("unloaded_radius", "width", "lateral_stiffness", "vertical_stiffness"):  # mm, N/mm in the file
        assert _close(getattr(back, f), getattr(tyre, f)), f
    assert back.fnomin == tyre.fnomin and back.rolling_resistance == tyre.rolling_resistance
    assert back.name == tyre.name and back.tyreside == tyre.tyreside
    assert set(back.ranges) == set(tyre.ranges)
    for k, (a, b) in tyre.ranges.items():  # angles written in degrees
        assert _close(back.ranges[k][0], a) and _close(back.ranges[k][1], b), k


@FUZZ
@given(tyre=tyres(), curve=st.one_of(st.none(), st.lists(st.tuples(_coef, _coef), min_size=1, max_size=5)))
def test_chrono_json_round_trip_is_exact(tyre, curve):
    tyre.vertical_curve = curve
    path = write("rt.json", b"")
    needed = (tyre.unloaded_radius, tyre.width, tyre.lateral_stiffness, tyre.vertical_stiffness)
    if any(v is None for v in needed):  # Chrono reads these unconditionally: refused, file untouched
        with pytest.raises(TyrefitError, match="Chrono's Pac89Tire JSON needs"):
            write_chrono_json(tyre, path, force=True)
        return
    tyre.mass, tyre.inertia, tyre.vertical_damping = 20.0, (1.0, 2.0, 1.0), 1000.0
    write_chrono_json(tyre, path, force=True)
    back = read_chrono_json(path)
    assert back.coefficients == coefficients_for_export(tyre)[0]
    assert (back.mass, back.inertia, back.vertical_damping) == (20.0, (1.0, 2.0, 1.0), 1000.0)
    for f in ("unloaded_radius", "width", "lateral_stiffness", "vertical_stiffness", "rolling_resistance", "name"):
        assert getattr(back, f) == getattr(tyre, f), f
    assert back.vertical_curve == curve


@pytest.mark.parametrize("name", ["it's", "a'$b", 'say "hi"', "a $ b ! c", "two\nlines", "cr\rlf", "sep\u2028x", "tab\there"])
def test_awkward_names_give_a_readable_tir(name):
    """Names the .tir quoting cannot hold must still give a file that reads back (name may be cleaned)."""
    tyre = Pac89Tyre(coefficients=EXAMPLE, name=name)
    path = write("name.tir", b"")
    try:
        write_tir(tyre, path, force=True, check=False)
    except TyrefitError:
        return
    back = read_tir(path)
    assert back.coefficients == tyre.coefficients


def test_write_tir_refuses_unphysical_model():
    bad = Pac89Tyre(coefficients={**EXAMPLE, "a0": -1.0})
    with pytest.raises(TyrefitError, match="C <= 0"):
        write_tir(bad, write("bad.tir", b""), force=True)


def test_non_pac89_tir_is_a_format_error():
    with pytest.raises(FormatError, match="PAC2002"):
        read_tir(write("mf2.tir", MF))


# --------------------------------------------------------------------------- the tyre interface on any point

from pathlib import Path as _Path  # noqa: E402

_DATA = _Path(__file__).parent / "data"
_TYRES = {name: read_tyre(_DATA / name) for name in ("ref_adams_pac89_example.tir", "ref_Generic_Pac02Tire.tir",
                                                      "mfeval_MagicFormula61_Paramerters.tir")}


@FUZZ
@given(name=st.sampled_from(sorted(_TYRES)),
       fz=st.floats(-1e3, 1e5), alpha=st.floats(-1.5, 1.5), kappa=st.floats(-1.0, 3.0), gamma=st.floats(-0.3, 0.3))
def test_forces_are_finite_and_mirror_twice_is_identity(name, fz, alpha, kappa, gamma):
    """Any in-domain point: finite forces (zero off the ground); the mirror of the mirror is the tyre."""
    t = _TYRES[name]
    f = t.forces(fz, alpha, kappa, gamma)
    for k, v in f.items():
        assert v.shape == () and math.isfinite(float(v)), (k, v)
        if fz <= 0:
            assert float(v) == 0.0
    back = t.mirrored().mirrored().forces(fz, alpha, kappa, gamma)
    for k in f:
        assert float(back[k]) == pytest.approx(float(f[k]), rel=1e-12, abs=1e-9)
