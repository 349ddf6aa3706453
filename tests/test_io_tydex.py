"""TYDEX .tdx reader: fixed columns, conversion factors and offsets, constants."""

import math

import numpy as np
import pytest
from numpy.testing import assert_allclose

from tyrefit.io.datasets import data_path
from tyrefit.errors import FormatError, UnitError, ValueRangeError
from tyrefit.io.readers import condition_levels, lateral_slope, read_data
from tyrefit.models import pac89
from tyrefit.synthetic.ttc import FSAE_PAC89, make_tydex


def chan(code, desc, unit, factor="1", om="0", op="0"):
    return f"{code:<10}{desc:<30}{unit:<10}{factor:<10}{om:<10}{op:<10}"


def tdx(channels, rows, constants=()):
    out = ["**HEADER", f"{'RELEASE':<10}{'Release':<30}1.3", "**CONSTANTS", *constants, "**MEASURCHANNELS",
           *channels, "**MEASURDATA", *rows, "**END"]
    return "\n".join(out) + "\n"


def test_bundled_tydex_three_sweeps(tmp_path):
    path = data_path("ttc", "fsae_sweeps.tdx")
    assert path.read_text() == make_tydex()  # the bundled file is what the generator writes
    ds = read_data(path)
    assert ds.kind == "slip_angle" and ds.meta["format"] == "tdx" and ds.n_runs == 3
    cond = condition_levels(ds)
    assert_allclose(cond["fz"], [700, 1100, 1500], rtol=0.01)
    assert_allclose(cond["pressure"], [82.7e3])
    assert_allclose(cond["speed"], [40 / 3.6], rtol=1e-4)  # levels are rounded to 1 mm/s
    assert ds.meta["header"]["MEASID"] == "SYNTH-TTC-TDX-01"
    # FYW is written in kN with factor 0.001: the forces come back in N, matching the model to the noise
    model = pac89.lateral_force(FSAE_PAC89, ds.df["fz"], ds.df["slip_angle"])
    assert np.sqrt(np.mean((ds.df["fy"] - model) ** 2)) < 30.0
    assert lateral_slope(ds) < 0


def test_conversion_factor_and_offsets(tmp_path):
    chans = [chan("SLIPANGL", "slip angle", "deg"), chan("FZW", "load", "kN", "0.5", "10", "1"),
             chan("FYW", "lateral force", "N", "-1")]
    rows = [f"{a:10.3f}{30.0:10.3f}{100.0 * a:10.3f}" for a in range(-5, 6)]
    p = tmp_path / "f.tdx"
    p.write_text(tdx(chans, rows))
    ds = read_data(p, checks=False)  # a parsing test: 500 N at 11 kN is no tyre (check_plausible would say so)
    # value [kN] = (raw - 10) * 0.5 + 1 = 11 kN
    assert_allclose(ds.df["fz"], 11e3)
    assert_allclose(ds.df["fy"], -100.0 * np.degrees(ds.df["slip_angle"]), atol=1e-9)
    assert ds.meta["channels"]["FZW"]["factor"] == 0.5


def test_touching_fixed_width_fields(tmp_path):
    chans = [chan("SLIPANGL", "slip angle", "deg"), chan("FZW", "load", "N"), chan("FYW", "lateral", "N")]
    rows = ["%10.4f%10.3f%10.2f" % (a, 4000.0 + a, -1234567.0 / 1000 * a) for a in (-9.1234, 0.0, 9.1234)]
    rows += ["  -12.3456  4000.000-12345.678"]  # two fields touch
    p = tmp_path / "t.tdx"
    p.write_text(tdx(chans, rows))
    ds = read_data(p)
    assert_allclose(ds.df["fy"].iloc[-1], -12345.678)
    assert_allclose(ds.df["slip_angle"].iloc[-1], math.radians(-12.3456))


def test_unknown_channel_units_are_kept_raw(tmp_path):
    chans = [chan("SLIPANGL", "slip angle", "deg"), chan("FZW", "load", "N"), chan("FYW", "lateral", "N"),
             chan("TYRETEMP", "tread temperature", "degC")]
    rows = [f"{a:10.3f}{3000.0:10.3f}{-50.0 * a:10.3f}{40.0:10.3f}" for a in range(-4, 5)]
    p = tmp_path / "u.tdx"
    p.write_text(tdx(chans, rows))
    ds = read_data(p)
    assert_allclose(ds.df["tyretemp"], 40.0)
    assert ds.meta["columns"]["tyretemp"]["converted"] is False


def test_tydex_errors(tmp_path):
    chans = [chan("SLIPANGL", "slip angle", "deg"), chan("FZW", "load", "N"), chan("FYW", "lateral", "N")]
    p = tmp_path / "e.tdx"
    p.write_text("**HEADER\n**MEASURCHANNELS\n" + "\n".join(chans) + "\n**END\n")
    with pytest.raises(FormatError, match=r"no \*\*MEASURDATA block"):
        read_data(p)
    p.write_text(tdx(chans, ["     1.000  3000.000"]))
    with pytest.raises(FormatError, match=r"line \d+: 2 values in \*\*MEASURDATA, but 3 channels"):
        read_data(p)
    p.write_text(tdx(chans, [f"{1.0:10.3f}{3000.0:10.3f}  NOTAVAIL", f"{2.0:10.3f}{3000.0:10.3f}{5.0:10.3f}"]))
    with pytest.raises(ValueRangeError, match=r"column 'FYW \[N\]': value nan is not a finite number"):
        read_data(p)
    p.write_text(tdx([chan("SLIPANGL", "slip angle", "furlong"), *chans[1:]], [f"{1:10.3f}{3000:10.3f}{5:10.3f}"]))
    with pytest.raises(UnitError, match=r"unknown unit \[furlong\]"):
        read_data(p)
