"""Writing MF 6.1 property files (tyrefit.io.mf_tir)."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest

from tyrefit.errors import ModelError, OutputExistsError
from tyrefit.io.mf_tir import SECTIONS, TURNSLIP, format_mf_tir, write_mf_tir
from tyrefit.models import mf61

from test_mf61_model import _read_tir_values

DATA = Path(__file__).parent / "data"


def _parse(text: str) -> tuple[list[str], dict[str, dict[str, str]]]:
    """Sections in order and their key -> raw value text (an independent, strict reader)."""
    order, sections, current = [], {}, None
    for line in text.splitlines():
        if line.startswith("$") or not line.strip():
            continue
        if line.startswith("["):
            current = line.strip()[1:-1]
            order.append(current)
            sections[current] = {}
            continue
        assert "=" in line, line
        key, rest = line.split("=", 1)
        value = rest.split("$", 1)[0].strip()
        assert key.strip() not in sections[current], f"duplicate {key} in [{current}]"
        sections[current][key.strip()] = value
    return order, sections


def _flat(sections) -> dict:
    out = {}
    for name, sec in sections.items():
        for k, v in sec.items():
            try:
                out[k] = float(v)
            except ValueError:
                out[k] = v.strip("'")
    return out


def _mfeval_example() -> dict:
    return _read_tir_values(DATA / "mfeval_MagicFormula61_Paramerters.tir")


def test_layout_every_coefficient_once_in_its_section(tmp_path):
    path = write_mf_tir(_mfeval_example(), tmp_path / "t.tir")
    order, sections = _parse(path.read_text())
    assert order == ["MDI_HEADER", "UNITS"] + SECTIONS
    for section, names in mf61.COEFFICIENTS.items():
        assert set(names) <= set(sections[section]), section
    assert sections["MODEL"]["FITTYP"] == "61"
    assert set(TURNSLIP) == set(sections["TURNSLIP_COEFFICIENTS"])
    assert sections["UNITS"] == {"LENGTH": "'meter'", "FORCE": "'newton'", "ANGLE": "'radians'",
                                 "MASS": "'kg'", "TIME": "'second'"}


def test_round_trip_gives_identical_forces(tmp_path):
    p = _mfeval_example()
    path = write_mf_tir(p, tmp_path / "t.tir")
    q = _flat(_parse(path.read_text())[1])
    a = np.radians(np.linspace(-15, 15, 13))
    k = np.linspace(-0.4, 0.4, 9)[:, None]
    args = (np.array([2000.0, 6752.0, 9000.0])[:, None, None], k, a, 0.05, 300000.0, 12.0)
    r0, r1 = mf61.forces(p, *args), mf61.forces(q, *args)
    for ch in r0:
        np.testing.assert_array_equal(r0[ch], r1[ch])
    for key, v in p.items():
        if isinstance(v, float) and key in q and key != "MASS":
            assert q[key] == v, key


def test_comments_never_run_into_values(tmp_path):
    p = dict(mf61.neutral(), PKY1=-1.2345678901234567e-13, QSX1=123456789012.34567, WIDTH=0.1 + 0.2)
    text = format_mf_tir(p, header=["source: a file with $ and 'quotes' and\nnew lines", "RMSE Fy 25.3 N"])
    for line in text.splitlines():
        if line.startswith("$") or line.startswith("[") or not line.strip():
            continue
        key, rest = line.split("=", 1)
        value = rest.split("$", 1)[0]
        assert re.fullmatch(r"\s*('[^'$]*'|[-+0-9.eE]+)\s*", value), line
        if "$" in rest:
            assert rest.split("$", 1)[0].endswith("  "), line
    assert "$ source: a file with $ and 'quotes' and new lines" in text
    q = _flat(_parse(text)[1])
    assert q["PKY1"] == -1.2345678901234567e-13 and q["QSX1"] == 123456789012.34567 and q["WIDTH"] == 0.1 + 0.2


def test_neutral_fill_and_not_fitted_declared(tmp_path):
    fitted = {"FNOMIN": 3000.0, "NOMPRES": 180000.0, "LONGVL": 11.1, "UNLOADED_RADIUS": 0.26,
              "PCX1": 1.5, "PDX1": 1.3, "PKX1": 30.0, "PCY1": 1.4, "PDY1": 1.2, "PKY1": -25.0, "PKY2": 2.0,
              "PKY4": 2.0}
    text = format_mf_tir(fitted, not_fitted=["mz0", "mz", "mx", "my", "fx", "fy"],
                         ranges={"fz": (200.0, 4500.0), "camber": (-0.07, 0.07), "pressure": (150e3, 220e3),
                                 "slip_angle": (-0.21, 0.21), "slip_ratio": (-0.3, 0.3)})
    q = _flat(_parse(text)[1])
    assert (q["FZMIN"], q["FZMAX"], q["CAMMIN"], q["CAMMAX"]) == (200.0, 4500.0, -0.07, 0.07)
    assert (q["PRESMIN"], q["PRESMAX"], q["KPUMIN"], q["ALPMAX"]) == (150e3, 220e3, -0.3, 0.21)
    assert "NOT FITTED: pure-slip Mz" in text and "NOT FITTED: rolling resistance My" in text
    assert "DEFAULTS [STRUCTURAL]: all: neutral / generic values, not from data" in text
    assert re.search(r"DEFAULTS \[LATERAL_COEFFICIENTS\]: PDY2, ", text)
    # neutral parts are not zeros that give NaN: the file evaluates finite everywhere; the part without data
    # (pure-slip Mz: QDZ1 = 0, no trail, no residual torque) gives no moment rather than a generic curve
    a = np.radians(np.linspace(-20, 20, 21))
    r = mf61.forces(q, np.array([300.0, 3000.0, 4500.0])[:, None], 0.1, a, 0.05, 200e3, 3.0)
    assert all(np.isfinite(v).all() for v in r.values())
    assert np.abs(r["fy"]).max() > 100 and np.abs(r["mz"]).max() == 0.0
    # declared for Adams (USE_MODE 3: Fx and Fy fitted, no combined slip) and for tyrefit's reader
    assert q["USE_MODE"] == 3 and "$ TYREFIT_NOT_FITTED = mz, mx, my, combined" in text


def test_bad_values_refused_before_writing(tmp_path):
    target = tmp_path / "t.tir"
    for bad, match in (({"PKY1": float("nan")}, "PKY1 = nan is not finite"),
                       ({"PDX1": "abc"}, "PDX1 = 'abc' is not a number"),
                       ({"FNOMIN": 0.0}, "FNOMIN = 0.0 must be positive"),
                       ({"TYRESIDE": "UP"}, "TYRESIDE")):
        with pytest.raises(ModelError, match=match):
            write_mf_tir(dict(mf61.neutral(), **bad), target)
        assert not target.exists()
        assert list(tmp_path.iterdir()) == []


def test_existing_file_kept_unless_force(tmp_path):
    target = tmp_path / "t.tir"
    target.write_text("keep me")
    with pytest.raises(OutputExistsError):
        write_mf_tir(mf61.neutral(), target)
    assert target.read_text() == "keep me"
    write_mf_tir(mf61.neutral(), target, force=True)
    assert "FITTYP" in target.read_text()


def test_round_trip_through_the_project_reader(tmp_path):
    """write_mf_tir -> tyrefit.io.tir.read_tyre -> MFTyre.forces: identical forces and moments."""
    from tyrefit.io.tir import read_tyre

    p = _mfeval_example()
    path = write_mf_tir(p, tmp_path / "t.tir", header=["round trip"], not_fitted=["my"])
    tyre = read_tyre(path)
    assert tyre.family == "MF61"
    a = np.radians(np.linspace(-15, 15, 13))
    k = np.linspace(-0.4, 0.4, 9)[:, None]
    fz = np.array([2000.0, 6752.0, 9000.0])[:, None, None]
    got = tyre.forces(fz, slip_angle=a, slip_ratio=k, camber=0.05, pressure=300000.0, speed=12.0)
    want = mf61.forces(p, fz, k, a, 0.05, 300000.0, 12.0)
    for ch in ("fx", "fy", "mz", "mx"):
        np.testing.assert_array_equal(got[ch], want[ch])
    # My was declared not fitted: absent when read back (NaN), the file's own USE_MODE kept
    assert np.isnan(got["my"]).all() and not tyre.has_rolling and tyre.use_mode == p.get("USE_MODE", 4)


def test_mf52_file_round_trip(tmp_path):
    """version='5.2' writes FITTYP = 6 without the 6.1-only keys; read back it is evaluated by the
    5.2 equations (here and through the project reader) with identical forces."""
    from tyrefit.io.mf_tir import ONLY_61
    from tyrefit.io.tir import read_tyre

    p = _read_tir_values(DATA / "mfeval_MagicFormula52_Paramerters.tir")
    path = write_mf_tir(p, tmp_path / "t52.tir", version="5.2")
    order, sections = _parse(path.read_text())
    assert sections["MODEL"]["FITTYP"] == "6"
    q = _flat(sections)
    assert not ONLY_61 & set(q) and {"LGAX", "LGAY", "LGAZ", "PHY3"} <= set(q)
    a = np.radians(np.linspace(-12, 12, 9))
    k = np.linspace(-0.3, 0.3, 7)[:, None]
    want = mf61.forces(p, 8000.0, k, a, 0.04)
    got = mf61.forces(q, 8000.0, k, a, 0.04)
    tyre = read_tyre(path)
    assert tyre.family == "MF52"
    via_reader = tyre.forces(8000.0, slip_angle=a, slip_ratio=k, camber=0.04)
    for ch in want:
        np.testing.assert_array_equal(got[ch], want[ch])
        np.testing.assert_array_equal(via_reader[ch], want[ch])


def test_lmuv_written_in_scaling_section_neutral_zero_and_read_back(tmp_path):
    """LMUV (friction decay with slip speed, 4.E7) is a scaling factor whose neutral value is 0, not 1: written
    in [SCALING_COEFFICIENTS] (0 when not given, and the header says so), a fitted value read back as the
    same float and evaluated the same by the project reader, at a speed away from LONGVL."""
    from tyrefit.io.tir import read_tyre

    text = format_mf_tir(mf61.neutral())
    _, sections = _parse(text)
    assert sections["SCALING_COEFFICIENTS"]["LMUV"] == "0"
    assert "LMUV 0: no friction decay with slip speed" in text
    p = dict(_mfeval_example(), LMUV=0.2718281828459045)
    path = write_mf_tir(p, tmp_path / "t.tir")
    _, sections = _parse(path.read_text())
    assert float(sections["SCALING_COEFFICIENTS"]["LMUV"]) == p["LMUV"]
    head = re.sub(r"\n\$ {4,}", " ", path.read_text())  # header continuation lines joined
    assert not any("DEFAULTS [SCALING_COEFFICIENTS]" in ln and "LMUV" in ln for ln in head.splitlines())
    tyre = read_tyre(path)
    assert tyre.params["LMUV"] == p["LMUV"]
    k = np.linspace(-0.4, 0.4, 9)[:, None]
    a = np.radians(np.linspace(-12, 12, 7))
    got = tyre.forces(6752.0, slip_angle=a, slip_ratio=k, camber=0.0, pressure=260000.0, speed=30.0)
    want = mf61.forces(p, 6752.0, k, a, 0.0, 260000.0, 30.0)
    slow = mf61.forces(dict(p, LMUV=0.0), 6752.0, k, a, 0.0, 260000.0, 30.0)
    for ch in ("fx", "fy", "mz"):
        np.testing.assert_array_equal(got[ch], want[ch])
    assert np.max(np.abs(want["fx"] - slow["fx"])) > 0.05 * np.max(np.abs(slow["fx"]))  # LMUV acts at 30 m/s
