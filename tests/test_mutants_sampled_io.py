"""Readers and writers: tests for the sampled mutants that survived the quick suite (issue 25's mutation run).

``nice python -m benchmarks.mutation --sample 216 --seed 15`` (12 mutants per module) left these
mutants alive; each test states documented behaviour of the file formats, not the mutated text.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from tyrefit.io.ttc import parse_ttc

ROOT = Path(__file__).resolve().parents[1]
DAT = ROOT / "data" / "ttc" / "fsae_cornering.dat"


# ------------------------------------------------------------------------------ FSAE TTC .dat (tyrefit/io/ttc.py)
@pytest.fixture(scope="module")
def ttc_lines():
    return DAT.read_text().splitlines()[:300]


def _parse(tmp_path, lines, name="t.dat"):
    p = tmp_path / name
    text = "\n".join(lines) + "\n"
    p.write_text(text)
    return parse_ttc(p, text)


def _same_table(a, b):
    assert list(a.values) == list(b.values)
    assert a.units == b.units
    for k in a.values:
        np.testing.assert_array_equal(a.values[k], b.values[k])


def test_ttc_whitespace_separated_file_reads_like_the_tab_separated_one(tmp_path, ttc_lines):
    # the docstring: tab-separated, or (no tab on the names line) whitespace-separated; units from line 3
    tabs = _parse(tmp_path, ttc_lines)
    spaces = _parse(tmp_path, [s.replace("\t", "  ") for s in ttc_lines], "s.dat")
    _same_table(tabs, spaces)
    assert spaces.units["speed"] == "kph" and spaces.units["pressure"] == "kPa"


def test_ttc_unit_with_a_space_stays_in_its_column(tmp_path, ttc_lines):
    # "deg F" is one of the units kept as written (module docstring); the info line has no tab
    lines = list(ttc_lines)
    assert "\t" not in lines[0]
    lines[2] = lines[2].replace("degC", "deg F")
    t = _parse(tmp_path, lines)
    assert t.units["tstc"] == "deg F"
    assert t.headers["tstc"] == "TSTC [deg F]"
    assert t.units["slip_ratio"] == "-" and t.units["mz"] == "N*m"


def test_ttc_trailing_tabs_on_the_header_lines_are_not_channels(tmp_path, ttc_lines):
    lines = [s + "\t" if i in (1, 2) else s for i, s in enumerate(ttc_lines)]
    _same_table(_parse(tmp_path, ttc_lines), _parse(tmp_path, lines, "trailing.dat"))


def test_ttc_units_line_shorter_than_the_names_line_leaves_the_last_channels_without_unit(tmp_path, ttc_lines):
    lines = list(ttc_lines)
    lines[2] = "\t".join(lines[2].split("\t")[:-1])  # no unit for TSTC
    t = _parse(tmp_path, lines)
    assert t.headers["tstc"] == "TSTC"
    np.testing.assert_array_equal(t.values["tstc"], _parse(tmp_path, ttc_lines, "full.dat").values["tstc"])


# ------------------------------------------------------------------------------ output names (tyrefit/io/outputs.py)
@pytest.mark.parametrize("char", ["\u00e9", "\u20ac", "\U0001f697"])  # 2-, 3- and 4-byte UTF-8
@pytest.mark.parametrize("extra", [0, 1, 2, 3, 12])
def test_a_side_file_name_is_cut_on_a_whole_character_to_fit_name_max(tmp_path, char, extra):
    from tyrefit.io.outputs import _name_max, side_name

    name = char * 300
    out = side_name(name, tmp_path, prefix=".", suffix=".tmp", extra=extra)
    room = _name_max(tmp_path) - len(".") - len(".tmp") - extra
    k = room // len(char.encode())  # the most whole characters that fit
    # whole characters only (no cut UTF-8 sequence), and not many fewer than fit (today's cut drops one
    # whole character more when the cut falls on a character boundary; harmless, the name still fits)
    assert out in ("." + char * k + ".tmp", "." + char * (k - 1) + ".tmp")
    assert len(out.encode("utf-8")) + extra <= _name_max(tmp_path)


# ------------------------------------------------------------------------ PAC89 .tir export (tyrefit/io/pac89_tir.py)
@pytest.mark.parametrize("absent", ["lateral", "longitudinal", "aligning"])
def test_a_part_without_a_model_is_exported_as_a_block_that_gives_zero_force_without_0_over_0(absent):
    # NEUTRAL_BLOCKS' contract: finite in the PAC89 equations (C = 1, D = Fz, no division by zero),
    # zero slip stiffness, so the part gives no force; never B = 0/0
    from tyrefit.io.pac89_tir import coefficients_for_export
    from tyrefit.io.tir import read_tir
    from tyrefit.models import pac89

    tyre = read_tir(ROOT / "data" / "sim" / "soft_rear.tir")
    names = {"lateral": pac89.LATERAL, "longitudinal": pac89.LONGITUDINAL, "aligning": pac89.ALIGNING}[absent]
    tyre.coefficients.update({k: 0.0 for k in names})
    c, parts = coefficients_for_export(tyre)
    assert absent in parts
    fz = np.array([500.0, 2000.0, 4000.0, 8000.0])
    slip = np.array([-0.2, -0.05, 0.0, 0.05])
    with np.errstate(divide="raise", invalid="raise"):
        out = {"lateral": lambda: pac89.lateral_force(c, fz, slip, 0.02),
               "longitudinal": lambda: pac89.longitudinal_force(c, fz, slip),
               "aligning": lambda: pac89.aligning_moment(c, fz, slip, 0.02)}[absent]()
    np.testing.assert_array_equal(out, 0.0)


# ------------------------------------------------------------------------------ Magic Formula .tir (tyrefit/io/tir.py)
MF61_TIR = ROOT / "tests" / "data" / "mfeval_MagicFormula61_Paramerters.tir"


def test_mf_file_units_convert_compound_quantities_to_si(tmp_path):
    # [UNITS] LENGTH 'cm', FORCE 'kN', TIME 'ms': a speed is cm/ms (x 10), a stiffness kN/cm (x 1e5),
    # a damping kN ms/cm (x 100), whatever the numbers were meant to be
    import re

    from tyrefit.io.tir import read_tyre

    text = MF61_TIR.read_text(encoding="latin-1")
    for kind, old, new in (("LENGTH", "meter", "cm"), ("FORCE", "newton", "kN"), ("TIME", "second", "ms")):
        text, n = re.subn(rf"(?m)^({kind}\s*=\s*)'{old}'", rf"\1'{new}'", text)
        assert n == 1
    f = tmp_path / "cm_kN_ms.tir"
    f.write_text(text, encoding="latin-1")
    si, other = read_tyre(MF61_TIR).params, read_tyre(f).params
    for key, factor in (("LONGVL", 10.0), ("VXLOW", 10.0), ("VERTICAL_STIFFNESS", 1e5), ("VERTICAL_DAMPING", 100.0),
                        ("UNLOADED_RADIUS", 0.01), ("FNOMIN", 1e3)):
        assert other[key] == pytest.approx(si[key] * factor, rel=1e-12), key


def test_mf_file_keeps_its_tyre_side():
    from tyrefit.io.tir import read_tyre

    assert read_tyre(MF61_TIR).tyreside == "RIGHT"      # TYRESIDE = 'RIGHT'
    assert read_tyre(ROOT / "tests" / "data" / "mf61_small.tir").tyreside == "LEFT"


def test_mf_file_without_tyre_side_is_left(tmp_path):
    import re

    from tyrefit.io.tir import read_tyre

    f = tmp_path / "noside.tir"
    f.write_text(re.sub(r"(?m)^TYRESIDE.*\n", "", MF61_TIR.read_text(encoding="latin-1")), encoding="latin-1")
    assert read_tyre(f).tyreside == "LEFT"


def test_a_tir_of_an_unknown_format_is_refused_naming_what_it_declares(tmp_path):
    import re

    from tyrefit.errors import FormatError
    from tyrefit.io.tir import read_tyre

    text = re.sub(r"(?m)^FITTYP.*\n", "", MF61_TIR.read_text(encoding="latin-1"))
    text = re.sub(r"(?m)^PROPERTY_FILE_FORMAT.*$", "PROPERTY_FILE_FORMAT = 'SWIFT_99'", text)
    f = tmp_path / "swift.tir"
    f.write_text(text, encoding="latin-1")
    with pytest.raises(FormatError, match="FITTYP is SWIFT_99"):
        read_tyre(f)


def test_a_tir_without_model_whose_stray_declaration_contradicts_its_coefficients_is_refused(tmp_path):
    # no [MODEL]: PROPERTY_FILE_FORMAT = 'PAC89' in another section, but Magic Formula 5.2 coefficients;
    # the file is refused (the family cannot be told), not read as either
    from tyrefit.errors import FormatError
    from tyrefit.io.tir import read_tyre

    out, skip = [], False
    for line in (ROOT / "tests" / "data" / "ref_HMMWV_Pac02Tire.tir").read_text(encoding="latin-1").splitlines(True):
        if line.strip().startswith("["):
            skip = line.strip().upper().startswith("[MODEL")
        if not skip:
            out.append(line)
    f = tmp_path / "contradicts.tir"
    f.write_text("".join(out) + "[VENDOR]\nPROPERTY_FILE_FORMAT = 'PAC89'\n", encoding="latin-1")
    with pytest.raises(FormatError, match=r"no \[MODEL\].*PAC89"):
        read_tyre(f)


# ---------------------------------------------------------------------- record segmentation (tyrefit/io/segment.py)
def _asymmetric_record(cycles=4):
    """Slip-angle cycles 0 -> +10 deg (150 samples) -> -10 deg (100) -> 0 (50) at 1000 N, 83 kPa, 40 km/h."""
    import pandas as pd

    one = np.r_[np.linspace(0.0, 10.0, 150, endpoint=False), np.linspace(10.0, -10.0, 100, endpoint=False),
                np.linspace(-10.0, 0.0, 50, endpoint=False)]
    deg = np.r_[np.zeros(40), np.tile(one, cycles), np.zeros(40)]
    n = deg.size
    return pd.DataFrame({"time": 0.01 * np.arange(n), "slip_angle": np.radians(deg), "fz": 1000.0,
                         "pressure": 83e3, "speed": 40.0 / 3.6}, index=np.arange(4, 4 + n))


def test_a_record_is_cut_where_the_slip_crosses_the_middle_of_its_range():
    # segment module docstring, step 5: pairs of extremes, the cut where the slip crosses the middle of its range
    from tyrefit.io.segment import segment_record

    out, meta = segment_record(_asymmetric_record(), "slip_angle")
    assert meta["n_sweeps"] >= 3
    step = np.radians(20.0 / 100)                        # the largest change between samples
    for r in range(1, meta["n_sweeps"]):
        first = out.loc[out["run"] == r, "slip_angle"].iloc[0]
        assert abs(first) <= step, (r, np.degrees(first))


def test_segmentation_reports_each_sweeps_samples_and_the_levels_in_their_units():
    from tyrefit.io.segment import segment_record

    out, meta = segment_record(_asymmetric_record(), "slip_angle")
    counts = out.groupby("run").size()
    assert [s["n"] for s in meta["sweeps"]] == counts.tolist()
    assert meta["levels"]["pressure"] == pytest.approx([83.0], rel=1e-6)      # kPa
    assert meta["levels"]["speed"] == pytest.approx([40.0], rel=1e-6)         # km/h
    assert meta["levels"]["fz"] == pytest.approx([1000.0], rel=1e-6)          # N



def test_a_short_dwell_before_a_sweep_of_a_10_hz_record_is_trimmed_to_the_sweeps_start():
    """segment.py [255] ``segment_record`` (the dwell's slip taken as the median of the stretch's first
    ``max(6, h)`` samples instead of ``max(3, h)``).

    The module docstring, step 4: the constant-slip dwell before the sweep starts is trimmed; the sweep
    keeps the last dwell sample as its starting point.  A 10 Hz record (0.5 s window: 5 samples) holds
    0.3 s (3 samples) at zero slip, then sweeps 0 -> +12 -> -12 -> 0 deg at 12 deg/s, twice.  The mutant's
    first six samples reach into the sweep, their median lies off the dwell by more than the 2 % band, and
    the whole dwell is kept as part of the first sweep: three points at zero slip where the data have one.
    """
    import pandas as pd

    from tyrefit.io.segment import segment_record

    one = np.r_[np.arange(0.0, 12.0, 1.2), np.arange(12.0, -12.0, -1.2), np.arange(-12.0, 1e-9, 1.2)]
    deg = np.r_[0.0, 0.0, one, one[1:], np.zeros(5)]
    df = pd.DataFrame({"time": 0.1 * np.arange(deg.size), "fz": 3000.0, "camber": 0.0,
                       "slip_angle": np.radians(deg), "fy": -3000.0 * np.sin(1.3 * np.arctan(0.2 * deg))})
    out, meta = segment_record(df, "slip_angle")
    assert meta["window"] == 5
    first = np.degrees(out.loc[out["run"] == 0, "slip_angle"].to_numpy())
    assert first[0] == 0.0 and first[1] == pytest.approx(1.2)  # one dwell sample: the sweep's start
    assert meta["dropped"]["dwell at constant slip"] == 2 + 5


# ------------------------------------------------------------------------------ readers (tyrefit/io/readers.py)
def _sweeps_dataset(pressures_kpa, loads=(3000.0, 5000.0)):
    import pandas as pd

    from tyrefit.io.readers import Dataset

    a = np.radians(np.linspace(-10.0, 10.0, 41))
    rows, run = [], 0
    for p in pressures_kpa:
        for fz in loads:
            rows.append(pd.DataFrame({"run": run, "fz": fz, "slip_angle": a, "pressure": p * 1e3,
                                      "fy": -fz * np.sin(1.3 * np.arctan(10.0 * a))}))
            run += 1
    return Dataset(pd.concat(rows, ignore_index=True), "slip_angle", "test")


def test_pressure_levels_one_psi_apart_are_two_conditions():
    # condition_levels: run means closer than 5 kPa are one pressure; 1 psi (6.9 kPa) apart are two
    from tyrefit.io.readers import condition_levels

    lv = condition_levels(_sweeps_dataset([200.0, 206.9]))
    assert lv["pressure"] == pytest.approx([200e3, 206.9e3])
    assert len(condition_levels(_sweeps_dataset([200.0, 203.0]))["pressure"]) == 1


def test_the_lateral_slope_of_sweeps_that_do_not_sweep_is_none():
    # lateral_slope: None when the data have no slip to regress on (every sweep at one slip angle)
    from tyrefit.io.readers import lateral_slope

    ds = _sweeps_dataset([200.0])
    ds.df["slip_angle"] = np.radians(1.0)
    assert lateral_slope(ds) is None
    assert lateral_slope(_sweeps_dataset([200.0])) < 0          # ISO-W: Fy falls with alpha


def test_contact_patch_data_at_one_load_with_a_few_newtons_of_scatter_are_refused():
    # require_patch: L(Fz) needs at least 2 loads; a load cell's scatter around one load is one load
    import pandas as pd

    from tyrefit.errors import DataError
    from tyrefit.io.readers import Dataset, require_patch

    static = Dataset(pd.DataFrame({"run": 0, "lateral_displacement": np.linspace(0, 0.05, 30),
                                   "fy": np.linspace(0, 9e3, 30), "fz": 4e4}), "static", "static test")
    jitter = np.array([-3.0, 1.0, 4.0, -2.0, 0.0, 2.0])
    patch = Dataset(pd.DataFrame({"fz": 4e4 + jitter, "length": 0.25 + 1e-4 * jitter}), "patch", "patch test")
    with pytest.raises(DataError, match="at 1 load only"):
        require_patch(static, patch)
    two = Dataset(pd.DataFrame({"fz": np.r_[4e4 + jitter, 6e4 + jitter], "length": 0.25}), "patch", "patch test")
    assert require_patch(static, two) is two


def test_a_clean_ttc_file_is_parsed_in_one_vectorised_pass(tmp_path, ttc_lines, monkeypatch):
    # tyrefit.io.table: the per-cell parser is the fallback for files pandas cannot read as numbers (it names
    # the bad line); a clean record must not take it (it is several times slower on 10^5-row records)
    import tyrefit.io.ttc as ttc

    def cell_by_cell(*a, **k):
        raise AssertionError("per-cell fallback used on a clean numeric file")

    monkeypatch.setattr(ttc, "parse_cells", cell_by_cell)
    t = _parse(tmp_path, ttc_lines)
    assert len(t.values["fy"]) == len(ttc_lines) - 3
