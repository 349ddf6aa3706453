"""Every bad-input class of issue 2 raises a tyrefit error naming file, column/row and what is accepted."""

import pytest

from tyrefit.errors import (ColumnError, DataError, FormatError, TyrefitError, UnitError, ValueRangeError)
from tyrefit.io.readers import check_fittable, read_data

GOOD_HEADER = "slip_angle [deg],fy [N],fz [N]"


def write(tmp_path, text, name="bad.csv", mode="w"):
    p = tmp_path / name
    if mode == "wb":
        p.write_bytes(text)
    else:
        p.write_text(text)
    return p


def sweep_rows(fz=3000, n=11):
    return "".join(f"{a},{-80 * a},{fz}\n" for a in range(-(n // 2), n - n // 2))


# (class, file text, regex) for the CSV reader
CASES = {
    "empty": (FormatError, "", r"bad\.csv: file is empty"),
    "blank": (FormatError, "\n  \n", r"file is empty"),
    "only comments": (FormatError, "# nothing\n", r"no header line"),
    "no data rows": (DataError, "# c\n" + GOOD_HEADER + "\n", r"no data rows after the header \(line 2\)"),
    "missing column": (ColumnError, "slip_angle [deg],fy [N]\n1,2\n",
                       r"cannot tell what test this is .*'slip_angle \[deg\]', 'fy \[N\]'.*slip_angle: slip_angle, fy, fz"),
    "unknown unit": (UnitError, "slip_angle [deg],fy [N],fz [kgf/cm2]\n1,2,3\n",
                     r"column 'fz \[kgf/cm2\]': unknown unit \[kgf/cm2\]; accepted: .*\[N\]"),
    "unit of wrong quantity": (UnitError, "slip_angle [N],fy [N],fz [N]\n1,2,3\n",
                               r"column 'slip_angle \[N\]'.*'slip_angle' is a angle; accepted: \[rad\], \[deg\]"),
    "no unit": (UnitError, "slip_angle,fy [N],fz [N]\n1,2,3\n",
                r"column 'slip_angle' has no unit; write it as 'slip_angle \[unit\]' with one of \[rad\], \[deg\]"),
    "same quantity twice (units)": (ColumnError, "slip_angle [deg],fy [N],fz [N],fz [kN]\n1,2,3,4\n",
                                    r"same quantity is given twice: 'fz \[N\]' and 'fz \[kN\]' are both 'fz'"),
    "same quantity twice (alias)": (ColumnError, "SA [deg],slip_angle [deg],fy [N],fz [N]\n1,1,2,3\n",
                                    r"'SA \[deg\]' and 'slip_angle \[deg\]' are both 'slip_angle'"),
    "non-numeric": (ValueRangeError, GOOD_HEADER + "\n1,2,3000\n2,abc,3000\n",
                    r"line 3, column 'fy \[N\]': non-numeric value 'abc'; a number is needed"),
    "empty cell": (ValueRangeError, GOOD_HEADER + "\n1,,3000\n", r"line 2, column 'fy \[N\]': an empty cell"),
    "ragged row": (FormatError, GOOD_HEADER + "\n1,2\n", r"line 2 has 2 cells, the header has 3"),
    "nan": (ValueRangeError, GOOD_HEADER + "\n1,2,3000\n2,nan,3000\n",
            r"line 3, column 'fy \[N\]': value nan is not a finite number; NaN, inf and empty cells are not accepted"),
    "inf": (ValueRangeError, GOOD_HEADER + "\n1,2,inf\n",
            r"line 2, column 'fz \[N\]': value inf is not a finite number"),
    "zero load": (ValueRangeError, GOOD_HEADER + "\n1,2,0\n",
                  r"line 2, column 'fz \[N\]': zero or negative load, 0 N; accepted 0 < fz <= 200 kN"),
    "negative load": (ValueRangeError, GOOD_HEADER + "\n1,2,3000\n1,2,3000\n1,2,-5\n",
                      r"line 4, column 'fz \[N\]': zero or negative load, -5 N; accepted 0 < fz <= 200 kN"),
    "implausible load": (ValueRangeError, "slip_angle [deg],fy [N],fz [kN]\n1,2,250\n",
                         r"implausibly large load, 250 kN = 250000 N; accepted 0 < fz <= 200 kN"),
    "implausible load [kg]": (ValueRangeError, "lateral_displacement [mm],fy [N],fz [N],load [kg]\n1,2,3000,30000\n",
                              r"column 'load \[kg\]': implausibly large load, 30000 kg = 294200 N; accepted 0 < load <= 200 kN"),
    "slip angle beyond 90": (ValueRangeError, GOOD_HEADER + "\n95,2,3000\n",
                             r"line 2, column 'slip_angle \[deg\]': out of range, 95 deg; accepted \|slip_angle\| <= 90 deg"),
    "slip angle in rad beyond 90": (ValueRangeError, "slip_angle [rad],fy [N],fz [N]\n-2,2,3000\n",
                                    r"out of range, -2 rad = -114.6 deg; accepted \|slip_angle\| <= 90 deg"),
    "camber beyond 30": (ValueRangeError, GOOD_HEADER + ",camber [deg]\n1,2,3000,35\n",
                         r"column 'camber \[deg\]': out of range, 35 deg; accepted \|camber\| <= 30 deg"),
    "pressure beyond 20 bar": (ValueRangeError, GOOD_HEADER + ",pressure [psi]\n1,2,3000,400\n",
                               r"column 'pressure \[psi\]': out of range, 400 psi = 27.58 bar; accepted 0 < pressure <= 20 bar"),
    "slip ratio beyond 100 %": (ValueRangeError, "slip_ratio [%],fx [N],fz [N]\n150,2,3000\n",
                                r"column 'slip_ratio \[%\]': out of range, 150 % = 1.5 -; accepted \|slip_ratio\| <= 1"),
    "run ids not integers": (ValueRangeError, "run," + GOOD_HEADER + "\n1.5,1,2,3000\n",
                             r"line 2, column 'run': run ids must be integers"),
}


@pytest.mark.parametrize("case", sorted(CASES))
def test_bad_csv(tmp_path, case):
    cls, text, pattern = CASES[case]
    with pytest.raises(cls, match=pattern) as info:
        read_data(write(tmp_path, text))
    msg = str(info.value)
    assert "\n" not in msg and msg.startswith(str(tmp_path / "bad.csv"))


@pytest.mark.parametrize("data, what", [
    (b"\x00\x01\x02\x03binary\xff" * 20, r"binary content \(NUL bytes\)"),
    (b"PK\x03\x04" + bytes(range(256)), r"binary content \(a ZIP/Excel workbook; save it as CSV\)"),
    (b"MATLAB 5.0 MAT-file, Platform: GLNXA64" + bytes(200), r"a MATLAB \.mat file"),
    (bytes(range(1, 32)) * 40, r"binary content \(\d+ control bytes"),
])
def test_binary_content(tmp_path, data, what):
    with pytest.raises(FormatError, match=what + r".*tyrefit reads text tables"):
        read_data(write(tmp_path, data, "b.dat", mode="wb"))


def test_tir_handed_in_as_data(tmp_path):
    tir = "[MODEL]\nPROPERTY_FILE_FORMAT = 'PAC89'\n[LATERAL_COEFFICIENTS]\na0 = 1.3\n"
    for name in ("tyre.tir", "tyre.csv"):
        with pytest.raises(FormatError, match=r"this is a tyre property file \(\.tir\), not measurement data; "
                                              r"use it with compare/sim"):
            read_data(write(tmp_path, tir, name))


def test_chrono_json_handed_in_as_data(tmp_path):
    with pytest.raises(FormatError, match=r"tyre property file \(Chrono JSON\).*use it with compare/sim"):
        read_data(write(tmp_path, '{"Template": "Pac89Tire", "Lateral Coefficients": {}}', "t.json"))


def test_missing_file_and_folder(tmp_path):
    with pytest.raises(FormatError, match=r"nope\.csv: no such file"):
        read_data(tmp_path / "nope.csv")
    with pytest.raises(FormatError, match=r"is a folder"):
        read_data(tmp_path)


def test_unknown_convention_and_kind(tmp_path):
    p = write(tmp_path, GOOD_HEADER + "\n1,2,3000\n")
    with pytest.raises(DataError, match=r"unknown sign convention 'saw'; accepted: 'iso', 'sae'"):
        read_data(p, convention="saw")
    with pytest.raises(DataError, match=r"unknown data kind 'slipangle'.*did you mean 'slip_angle'"):
        read_data(p, kind="slipangle")


# --------------------------------------------------------------------------- fit checks


def test_static_without_patch(tmp_path):
    text = "lateral_displacement [mm],fy [N],fz [N]\n" + "".join(f"{d},{20 * d},{5000 - d}\n" for d in range(20))
    ds = read_data(write(tmp_path, text))
    with pytest.raises(DataError, match=r"bad\.csv: a static-rig .* needs contact-patch data .*Eq\. 1.*"
                                        r"patch=PATCH\.csv with 'length \[mm\]'"):
        check_fittable(ds)


def test_patch_at_one_load_only(tmp_path):
    text = "lateral_displacement [mm],fy [N],fz [N]\n" + "".join(f"{d},{20 * d},{5000 - d}\n" for d in range(20))
    ds = read_data(write(tmp_path, text))
    patch = write(tmp_path, "load [kg],length [mm]\n500,120\n", "patch.csv")
    with pytest.raises(DataError, match=r"patch\.csv: contact-patch length at 1 load only; at least 2"):
        check_fittable(ds, patch=patch)


def test_too_few_points(tmp_path):
    ds = read_data(write(tmp_path, GOOD_HEADER + "\n" + sweep_rows(n=6)))
    with pytest.raises(DataError, match=r"too few points to fit: 6; at least 10 are needed"):
        check_fittable(ds)


def test_too_few_sweeps(tmp_path):
    ds = read_data(write(tmp_path, GOOD_HEADER + "\n" + sweep_rows()))
    with pytest.raises(DataError, match=r"too few sweeps to fit: 1; at least 2 are needed"):
        check_fittable(ds, min_sweeps=2)


def test_sweep_without_slip_variation(tmp_path):
    flat = "".join(f"0.1,{-8 + k},5000\n" for k in range(11))
    ds = read_data(write(tmp_path, GOOD_HEADER + "\n" + sweep_rows() + flat))
    assert ds.n_runs == 2
    with pytest.raises(DataError, match=r"sweep 1 \(fz 5000 N, 11 points\) has no slip_angle variation "
                                        r"\(span 0 deg\); each sweep needs at least 0\.5 deg"):
        check_fittable(ds)


def test_table_kinds_are_not_fittable(tmp_path):
    ds = read_data(write(tmp_path, "tyre,treadwear\nA,300\n"))
    with pytest.raises(DataError, match=r"a utqg table cannot be fitted"):
        check_fittable(ds)


def test_all_errors_are_value_errors_and_tyrefit_errors():
    for cls in (FormatError, ColumnError, UnitError, ValueRangeError, DataError):
        assert issubclass(cls, TyrefitError) and issubclass(cls, ValueError)
