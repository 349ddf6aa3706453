"""Real vendor property files and the layouts real tools export, read and evaluated as a user would.

Each test is named for the real-world case that once failed (see ``tests/data/vendor_SOURCES.md``
for the files).  Physics is checked with physics: the ISO-W sign of Fy and Mz at a small positive
slip angle, |F|/Fz of a road tyre, Fx growing with the slip ratio.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from tyrefit.errors import FormatError
from tyrefit.io.tir import read_property_file, read_tyre

DATA = Path(__file__).parent / "data"
FEDA = DATA / "vendor_feda_335_65R22_5_40psi.tir"
GENERIC = DATA / "ref_Generic_Pac02Tire.tir"


def _sound_road_tyre(t, fz):
    """Fy < 0 and Mz > 0 at +2 deg (ISO-W), 0.3 < |Fy|/Fz and |Fx|/Fz < 2, Fx rising with slip ratio."""
    f = t.forces(fz, slip_angle=np.radians(2.0))
    assert f["fy"] < 0 and f["mz"] > 0, f
    peak_y = np.max(np.abs(t.forces(fz, slip_angle=np.radians(np.linspace(0, 15, 31)))["fy"])) / fz
    fx = t.forces(fz, slip_ratio=np.array([0.0, 0.01, 0.02, 0.04]))["fx"]
    assert np.all(np.diff(fx) > 0), fx
    peak_x = np.max(np.abs(t.forces(fz, slip_ratio=np.linspace(0, 0.5, 51))["fx"])) / fz
    assert 0.3 < peak_y < 2.0 and 0.3 < peak_x < 2.0, (peak_y, peak_x)


def test_goodyear_mf05_with_negative_pdy1_is_not_refused():
    """MF-Tool 5.0 writes D = mu Fz < 0 with PKY1 < 0 (B = K/(C D) > 0): a normal tyre, not an unphysical one."""
    t = read_tyre(FEDA)
    assert t.family == "MF52" and t.params["PDY1"] < 0
    assert t.check() == [], t.check()
    _sound_road_tyre(t, 16929.0)
    # the magnitude is the file's: |Fy| peak / Fz at FNOMIN near |PDY1| (PDY3 camber term off at zero camber)
    fy = t.forces(16929.0, slip_angle=np.radians(np.linspace(0, 15, 151)))["fy"]
    assert np.max(np.abs(fy)) / 16929.0 == pytest.approx(0.70977, rel=0.05)


def test_mf_check_refuses_friction_that_changes_sign_inside_the_range():
    t = read_tyre(FEDA)
    t.params["PDY2"] = 2.0  # mu_y = -0.71 + 2 dfz crosses zero inside FZMIN..FZMAX
    assert any("mu_y = 0 or changes sign" in p for p in t.check())


def test_reads_pac2002_with_contact_model_text_under_a_commented_section(tmp_path):
    """Project Chrono's MAN 5t file (data/vehicle/MAN_5t/tire/MAN_5t_pacejka.tir) ends with a commented-out
    ``![CONTACT_COEFFICIENTS]`` header and ``CONTACT_MODEL = '3D_ENVELOPING'``, which lands in
    [ALIGNING_COEFFICIENTS]: a quoted setting, not a malformed coefficient."""
    tail = ("$-----------------------------------------------contact patch parameters\n"
            "! 3D contact can be switched on by deleting the comment ! character\n"
            "! When no further coefficients are specified, default values will be taken\n"
            "![CONTACT_COEFFICIENTS]\nCONTACT_MODEL            = '3D_ENVELOPING'\n\n")
    p = tmp_path / "man5t_like.tir"
    p.write_text(GENERIC.read_text() + tail)
    t = read_tyre(p)
    assert t.check() == []
    assert read_property_file(p).get("CONTACT_MODEL", section="ALIGNING_COEFFICIENTS") == "3D_ENVELOPING"
    # an unquoted word where a coefficient belongs is still refused, naming the line
    bad = tmp_path / "bad.tir"
    bad.write_text(GENERIC.read_text().replace("QBZ1                       = 5.8978", "QBZ1 = five", 1))
    with pytest.raises(FormatError, match=r"bad.tir:\d+: QBZ1 = 'five' .* is not a number"):
        read_property_file(bad)


#: the layout of teasit's magic-formula-tyre-library exports (doc/examples/fsae-ttc-data/fsaettc_obfuscated.tir):
#: every optional entry written with an empty value
_EMPTY_OPTIONALS = """[MDI_HEADER]
FILE_TYPE                    = 'tir'
FILE_VERSION                 = 3
[UNITS]
LENGTH                       = 'meter'
FORCE                        = 'newton'
ANGLE                        = 'radians'
[MODEL]
FITTYP                       = 61
LONGVL                       = 10
VXLOW                        = 1
ROAD_INCREMENT               =
[DIMENSION]
UNLOADED_RADIUS              = 0.2025
WIDTH                        =
RIM_RADIUS                   =
[OPERATING_CONDITIONS]
INFLPRES                     =
NOMPRES                      = 97000
[INERTIA]
MASS                         =
[VERTICAL]
FNOMIN                       = 2750
VERTICAL_STIFFNESS           =
[VERTICAL_FORCE_RANGE]
FZMIN                        =
FZMAX                        =
[SLIP_ANGLE_RANGE]
ALPMIN                       =
ALPMAX                       =
[LONGITUDINAL_COEFFICIENTS]
PCX1                         = 1.5
PDX1                         = 1.1004
PDX2                         = -0.36199
PKX1                         = 16.405
PKX3                         = -0.51846
[LATERAL_COEFFICIENTS]
PCY1                         = 1.5
PDY1                         = 1.0798
PDY2                         = -0.12631
PEY1                         = 0.63909
PKY1                         = -18.9867
PKY2                         = 1.6262
PKY4                         = 2
[ALIGNING_COEFFICIENTS]
QBZ1                         = 10
QCZ1                         = 1.1
QDZ1                         = 0.12
"""


def test_reads_mf61_export_with_empty_optional_values(tmp_path):
    p = tmp_path / "fsaettc_like.tir"
    p.write_text(_EMPTY_OPTIONALS)
    t = read_tyre(p)
    assert t.family == "MF61" and t.check() == []
    assert "WIDTH" not in t.params and "fz" not in t.ranges  # empty means not given
    assert t.forces(2750.0, pressure=None)["fy"] == pytest.approx(0.0, abs=2750 * 0.06)  # offsets only
    _sound_road_tyre(t, 2750.0)


@pytest.mark.parametrize("edit,match", [
    (("FNOMIN                       = 2750", "FNOMIN                       ="), r":\d+: FNOMIN has no value"),
    (("PDY2                         = -0.12631", "PDY2                         ="),
     r":\d+: PDY2 in \[LATERAL_COEFFICIENTS\] has no value"),
])
def test_mf61_export_with_an_empty_required_value_names_the_line(tmp_path, edit, match):
    p = tmp_path / "empty_required.tir"
    p.write_text(_EMPTY_OPTIONALS.replace(*edit))
    with pytest.raises(FormatError, match=match):
        read_tyre(p)


def test_inspect_and_eval_of_the_goodyear_file(tmp_path, capsys):
    from tyrefit.cli import main

    assert main(["inspect", str(FEDA)]) == 0
    out = capsys.readouterr().out
    assert "family MF52" in out and "not physical" not in out
    pts = tmp_path / "p.csv"
    pts.write_text("fz [kN],slip_angle [deg],slip_ratio [%]\n16.929,2,0\n16.929,0,5\n")
    assert main(["eval", str(FEDA), "--points", str(pts), "--out", str(tmp_path / "f.csv")]) == 0
    import pandas as pd

    f = pd.read_csv(tmp_path / "f.csv")
    assert f["fy [N]"][0] < 0 and f["fx [N]"][1] > 0


# --------------------------------------------------------------------------- eval's output CSV

def test_eval_csv_is_round_trip_exact_and_matches_pandas_text():
    """csv_text writes what pandas' round-trip default writes (shortest repr, NaN empty, ints as ints)."""
    import io

    import pandas as pd

    from tyrefit.commands.eval import csv_text

    rng = np.random.default_rng(3)
    x = rng.normal(0.0, 3000.0, 500) * 10.0 ** rng.integers(-12, 12, 500)
    x[[3, 7]] = np.nan
    df = pd.DataFrame({"fz [N]": rng.integers(100, 9000, 500), "odd, name \"q\"": x, "flag": x > 0,
                       "fy [N]": -x / 3.0})
    text = csv_text(df)
    lines = text.splitlines()
    assert lines[0] == 'fz [N],"odd, name ""q""",flag,fy [N]' and len(lines) == 501
    assert lines[4].split(",")[-3:-1] == ["", "False"]  # NaN empty (row 3), bool as pandas writes it
    back = pd.read_csv(io.StringIO(text))
    assert back["fz [N]"].dtype.kind == "i"
    np.testing.assert_array_equal(back["odd, name \"q\""].to_numpy(), x)  # bit-exact, NaN kept
    np.testing.assert_array_equal(back["fy [N]"].to_numpy(), -x / 3.0)
    assert back["flag"].dtype == bool
    y = x.copy()
    y[5] = np.inf
    back = pd.read_csv(io.StringIO(csv_text(pd.DataFrame({"a": y, "b": y}))))
    assert back["a"].iloc[5] == np.inf and np.isnan(back["b"].iloc[3])
    assert len(pd.read_csv(io.StringIO(csv_text(pd.DataFrame({"a": y}))))) == 500  # no blank line for NaN
    assert csv_text(df.head(0)) == df.head(0).to_csv(index=False, lineterminator="\n")
    df["note"] = "a,b"  # a text column: pandas writes it (quoted)
    assert csv_text(df) == df.to_csv(index=False, lineterminator="\n")


def test_compare_with_a_file_that_leaves_its_load_range_empty(tmp_path):
    """teasit's FSAE export (no FZMIN/FZMAX, FNOMIN 2750 N) against MFeval's 6.1 example (FZMIN = 0): loads
    were 0-18 kN, a row at Fz = 0 gave NaN and 'worst nan %'.  Now the overlap with 0.2-2 x FNOMIN."""
    import json

    from tyrefit.cli import main

    p = tmp_path / "fsaettc_like.tir"
    p.write_text(_EMPTY_OPTIONALS)
    out = tmp_path / "c.json"
    assert main(["compare", str(p), str(DATA / "mfeval_MagicFormula61_Paramerters.tir"), "--json", str(out)]) == 0
    loads = json.loads(out.read_text())["loads"]
    fz = [row["fz"] for row in loads]
    assert min(fz) == pytest.approx(550.0) and max(fz) == pytest.approx(5500.0)
    assert all(np.isfinite(row["mean_abs_dmu_over_peak"]) for row in loads)
    from tyrefit.compare.tyres import _default_loads

    mfeval = read_tyre(DATA / "mfeval_MagicFormula61_Paramerters.tir")
    assert _default_loads(mfeval, mfeval)[0][0] == pytest.approx(0.05 * 18000.0)  # FZMIN = 0 is not a load


def _man5t_like(tmp_path, name, **replace):
    text = GENERIC.read_text()
    for old, new in replace.items():
        text = text.replace(old, new)
    p = tmp_path / name
    p.write_text(text)
    return p


def test_pac2002_use_mode_2_with_zeroed_fx_block_is_lateral_only(tmp_path, capsys):
    """Stackpole's TTC PAC2002 fits ship USE_MODE = 2 ('Fy, Mx, Mz only') with every Fx coefficient 0: eval refused
    the file as unphysical (Cx = 0, mu_x = 0).  The part is absent: eval leaves fx empty, Fy and Mz as before."""
    import re

    from tyrefit.cli import main

    text = GENERIC.read_text().replace("USE_MODE                   = 4", "USE_MODE                   = 2")
    head, rest = text.split("[LONGITUDINAL_COEFFICIENTS]", 1)
    block, tail = rest.split("$---", 1)
    block = re.sub(r"(?m)^([A-Z0-9]+)(\s*=\s*)(\S+)", r"\g<1>\g<2>0", block)
    p = tmp_path / "stackpole_like.tir"
    p.write_text(head + "[LONGITUDINAL_COEFFICIENTS]" + block + "$---" + tail)
    t, full = read_tyre(p), read_tyre(GENERIC)
    assert not t.has_longitudinal and t.has_lateral and t.check() == []
    f, g = t.forces(30000.0, slip_angle=0.05), full.forces(30000.0, slip_angle=0.05)
    assert np.isnan(f["fx"]) and f["fy"] == g["fy"] and f["fy"] < 0
    pts = tmp_path / "p.csv"
    pts.write_text("fz [N],slip_angle [deg]\n30000,3\n")
    assert main(["eval", str(p), "--points", str(pts), "--out", str(tmp_path / "f.csv")]) == 0
    assert "no longitudinal model" in capsys.readouterr().out
    assert (tmp_path / "f.csv").read_text().splitlines()[1].split(",")[2] == ""  # fx [N] empty


def test_fittyp_52_reads_as_mf52(tmp_path):
    p = _man5t_like(tmp_path, "fittyp52.tir", **{"PROPERTY_FILE_FORMAT       = 'PAC2002'": "FITTYP    =52"})
    t = read_tyre(p)
    assert t.family == "MF52" and read_property_file(p).format == "FITTYP 52"
    assert t.forces(30000.0, slip_angle=0.05)["fy"] == read_tyre(GENERIC).forces(30000.0, slip_angle=0.05)["fy"]


# --------------------------------------------------------------------------- records in the layouts users bring

def _vw_drivebrake(with_warmup: bool, zero_mz: bool = False):
    """A drive/brake record in SAE signs (FZ < 0) whose truth is Project Chrono's generic PAC2002 truck tyre, seeded."""
    import pandas as pd

    t = read_tyre(GENERIC)
    rng = np.random.default_rng(7)
    rows = []
    for fz in (15000.0, 30000.0, 45000.0):
        k = np.concatenate([np.linspace(0, -0.25, 60), np.linspace(-0.25, 0.25, 120), np.linspace(0.25, 0, 60)])
        fzm = fz * (1 + 0.01 * rng.standard_normal(k.size))
        f = t.forces(fzm, slip_ratio=k)
        rows.append(pd.DataFrame({"SL [-]": k, "SA [deg]": 0.0, "FZ [N]": -fzm,
                                  "FX [N]": f["fx"] + 0.015 * fz * rng.standard_normal(k.size),
                                  "FY [N]": rng.normal(0, 100, k.size), "MZ [N*m]": 0.0 if zero_mz else -f["mz"]}))
    if with_warmup:  # a TTC-style warm-up: load ramped from 50 N while the slip angle creeps by 0.5 deg
        rows.insert(0, pd.DataFrame({"SL [-]": 0.0, "SA [deg]": np.linspace(0, 0.5, 200),
                                     "FZ [N]": -np.linspace(50, 30000, 200), "FX [N]": rng.normal(0, 30, 200),
                                     "FY [N]": rng.normal(0, 30, 200), "MZ [N*m]": 0.0}))
    return pd.concat(rows, ignore_index=True)


def test_fit_drive_brake_record_with_a_load_ramp_warm_up(tmp_path, capsys):
    """The warm-up (load 50 N -> 30 kN, slip angle 0 -> 0.5 deg, Mz 0) was taken as a lateral and an aligning sweep;
    the aligning start had D = 0 and scipy raised 'Residuals are not finite' as a traceback."""
    from tyrefit.cli import main

    p = tmp_path / "drivebrake_sae.csv"
    _vw_drivebrake(with_warmup=True).to_csv(p, index=False)
    out = tmp_path / "t.tir"
    assert main(["fit", str(p), "--convention", "sae", "--out", str(out)]) == 0
    text = capsys.readouterr().out
    assert "load is not held" in text and "longitudinal RMSE" in text and "lateral RMSE" not in text
    t = read_tyre(out)
    assert not t.has_lateral and t.has_longitudinal
    fx = t.forces(30000.0, slip_ratio=np.array([-0.05, 0.05]))["fx"]
    ref = read_tyre(GENERIC).forces(30000.0, slip_ratio=np.array([-0.05, 0.05]))["fx"]
    np.testing.assert_allclose(fx, ref, rtol=0.05)


def test_fit_with_an_mz_channel_of_zeros_fits_the_rest(tmp_path, capsys):
    import pandas as pd

    from tyrefit.cli import main

    t = read_tyre(GENERIC)
    rng = np.random.default_rng(5)
    rows = []
    for run, fz in enumerate((15000.0, 30000.0, 45000.0)):
        a = np.linspace(-12, 12, 81)
        rows.append(pd.DataFrame({"fz [N]": fz, "slip_angle [deg]": a, "mz [N*m]": 0.0,
                                  "fy [N]": t.forces(fz, slip_angle=np.radians(a))["fy"] + rng.normal(0, 150, a.size)}))
    p = tmp_path / "no_mz.csv"
    pd.concat(rows).to_csv(p, index=False)
    assert main(["fit", str(p), "--out", str(tmp_path / "t.tir")]) == 0
    assert "'mz' is zero throughout" in capsys.readouterr().out
    assert read_tyre(tmp_path / "t.tir").has_lateral


def test_mf_fit_does_not_fit_an_mz_channel_of_zeros(tmp_path):
    """A rig without an Mz transducer writes MZ = 0: fit --model mf61 fitted Mz0 to it (QDZ1 ~ 1e-13, 'R2 nan')."""
    import pandas as pd

    from tyrefit.fitting.mf import fit_mf

    t = read_tyre(DATA / "mfeval_MagicFormula61_Paramerters.tir")
    rng = np.random.default_rng(11)
    rows = []
    for fz in (3000.0, 6000.0, 9000.0):
        a = np.linspace(-12, 12, 61)
        rows.append(pd.DataFrame({"fz": fz, "slip_angle": np.radians(a), "mz": 0.0,
                                  "fy": t.forces(fz, slip_angle=np.radians(a))["fy"] + rng.normal(0, 60, a.size)}))
    res = fit_mf(pd.concat(rows, ignore_index=True), model="mf61")
    assert [str(s).lower() for s in res.stages] == ["fy0"], res.stages
    assert any("'mz' is zero throughout" in n for n in res.notes)


def test_pac89_forces_at_a_subnormal_load_are_zero_not_nan():
    """Found by the fuzz test: Fz = 5e-324 N gave NaN (kN units: D underflows to 0, B = 0/0)."""
    t = read_tyre(DATA / "ref_adams_pac89_example.tir")
    f = t.forces(np.array([5e-324, 0.0, 1e-3]), slip_angle=0.05, slip_ratio=0.05)
    assert all(np.all(np.isfinite(v)) for v in f.values()), f
    assert f["fy"][0] == 0.0 and f["fx"][0] == 0.0  # (at 1 mN the model's constant offsets a12/a13 remain)


def test_mf52_file_with_mf61_only_coefficients_applied_as_mfeval(tmp_path):
    """teasit's 'v52' FSAE export (FITTYP = 6) carries PPX1..PPY5, PKY5, PEY5.  MFeval's FITTYP 6 path applies
    them (19 % of peak Fx at that file's INFLPRES 80 kPa vs NOMPRES 98 kPa); tyrefit follows MFeval (checked
    against MFeval's solver in test_mf52_61keys.py).  Each key MFeval applies changes the forces here; each it
    does not read (the 5.2 camber stiffness, the 5.2 My) changes nothing; the warnings say which is which."""
    from tyrefit.models.mf61 import APPLIED_61_IN_52, UNUSED_61_IN_52

    t = read_tyre(GENERIC)
    assert not any("6.1-only" in w for w in t.warnings())
    t.params["NOMPRES"] = 250000.0
    pt = dict(slip_angle=0.05, slip_ratio=0.05, camber=0.03, pressure=200000.0)
    g = t.forces(30000.0, **pt)
    # (QSX4-QSX11 act in pairs, checked below; PPMX1 through QSX2, which this file has as 0)
    pairs = tuple(f"QSX{i}" for i in range(4, 12))
    alone = [k for k in APPLIED_61_IN_52 if k not in pairs + ("PPMX1",)]
    for k in alone + list(UNUSED_61_IN_52):
        t2 = read_tyre(GENERIC)
        t2.params.update(NOMPRES=250000.0, **{k: t2.params.get(k, 0.0) + 0.37})
        f = t2.forces(30000.0, **pt)
        changed = any(abs(f[c] - g[c]) > 1e-9 * max(1.0, abs(g[c])) for c in f)
        assert changed == (k in APPLIED_61_IN_52), k
    t2 = read_tyre(GENERIC)
    t2.params.update(QSX4=0.1, QSX7=0.5, QSX10=0.05, QSX11=2.0)
    assert abs(t2.forces(30000.0, **pt)["mx"] - t.forces(30000.0, **pt)["mx"]) > 1.0
    t.params.update(PPX1=-4.4, PKY5=83.0, PKY6=-1.0)
    w = " ".join(t.warnings())
    assert "applied as MFeval" in w and "PPX1, PKY5" in w and "not used" in w and "PKY6" in w


def test_goodyear_mf05_matches_mfeval():
    """The Goodyear MF-Tool 5.0 file (PDY1 < 0) evaluated by MFeval 4.0's solver (see vendor_SOURCES.md):
    Fx, Fy, Mz within 0.1 % of peak, pure and combined slip and camber, inside the file's ranges."""
    import pandas as pd

    ref = pd.read_csv(DATA / "vendor_feda_mfeval_reference.csv")
    t = read_tyre(FEDA)
    f = t.forces(ref["fz [N]"].to_numpy(), slip_angle=ref["slip_angle [rad]"].to_numpy(),
                 slip_ratio=ref["slip_ratio [-]"].to_numpy(), camber=ref["camber [rad]"].to_numpy(),
                 speed=ref["speed [m/s]"].to_numpy())
    for ch, col in (("fx", "fx [N]"), ("fy", "fy [N]"), ("mz", "mz [N*m]")):
        r = ref[col].to_numpy()
        assert np.max(np.abs(f[ch] - r)) <= 1e-3 * np.max(np.abs(r)), ch
    assert np.max(np.abs(ref["fy [N]"])) > 10000 and ref["camber [rad]"].max() > 0 and \
        ((ref["slip_ratio [-]"] != 0) & (ref["slip_angle [rad]"] != 0)).any()
