"""Fuzzing the data readers: any bytes in, only tyrefit's own errors out.

``read_data`` on CSV (unit headers), TYDEX ``.tdx`` and FSAE TTC ``.dat``
is given (1) arbitrary bytes, (2) arbitrary text and (3) valid files with
random byte-, token-, field- and line-level edits.  It must either return a
:class:`~tyrefit.io.readers.Dataset` that keeps the reader's promises
(canonical SI columns, integer runs, finite numbers) or raise a
:class:`~tyrefit.errors.TyrefitError`; anything else is a bug.  Example
counts come from the hypothesis profile (tests/conftest.py, 'ci': 200 per
test, the slower mutation tests half of that).
"""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest
from fuzz_helpers import WHITESPACE, FUZZ, FUZZ_FEW, FUZZ_HALF, mutated, only_tyrefit_errors, sweep_table, table_csv, write
from hypothesis import example, given
from hypothesis import strategies as st

from tyrefit.errors import TyrefitError
from tyrefit.io.readers import Dataset, read_data

# --------------------------------------------------------------------------- valid seed files


def _csv_slip_angle() -> bytes:
    rows = ["# synthetic: fuzz seed", "run,fz [kN],slip_angle [deg],camber [deg],fy [N],mz [N*m]"]
    for r, fz in enumerate((3.0, 5.0), 1):
        for sa in np.linspace(-10, 10, 9):
            rows.append(f"{r},{fz},{sa:.3f},0,{-900 * fz * np.sin(1.4 * np.arctan(0.2 * sa)):.2f},{-3 * sa:.2f}")
    return ("\n".join(rows) + "\n").encode()


def _csv_static() -> bytes:
    rows = ["lateral_displacement [mm];fy [kN];fz [kN];pressure [bar]"]
    for fz in (20.0, 30.0):
        for d in np.linspace(0, 60, 8):
            rows.append(f"{d:.1f};{0.7 * fz * np.tanh(d / 20):.3f};{fz - 0.01 * d:.3f};8")
    return ("\n".join(rows) + "\n").encode()


def _csv_patch() -> bytes:
    rows = ["load [kg]\tlength [mm]\twidth [mm]\tpressure [kPa]"]
    for m in (1000, 2000, 3000):
        rows.append(f"{m}\t{150 + m / 20:.0f}\t{220}\t800")
    return ("\n".join(rows) + "\n").encode()


def _csv_vertical() -> bytes:
    rows = ["vertical_displacement [mm],fz [N]"]
    for z in list(np.linspace(0, 30, 7)) + list(np.linspace(30, 0, 7)):
        rows.append(f"{z:.2f},{250 * z:.1f}")
    return ("\n".join(rows) + "\n").encode()


def _csv_slip_ratio() -> bytes:
    rows = ["fz [N],slip_ratio [%],fx [N],speed [km/h]"]
    for fz in (4000.0, 6000.0):
        for k in np.linspace(-20, 20, 11):
            rows.append(f"{fz},{k:.2f},{fz * np.sin(1.6 * np.arctan(0.15 * k)):.1f},60")
    return ("\n".join(rows) + "\n").encode()


def _tdx() -> bytes:
    out = ["**HEADER", f"{'RELEASE':<10}{'TYDEX release':<30}1.3", "**CONSTANTS",
           f"{'INFLPRES':<10}{'inflation pressure':<30}{'kPa':<10}{'220':<10}", "**MEASURCHANNELS"]
    for code, desc, unit in (("SLIPANGL", "slip angle", "deg"), ("FZW", "vertical force", "N"),
                             ("FYW", "lateral force", "N")):
        out.append(f"{code:<10}{desc:<30}{unit:<10}{'1':<10}{'0':<10}{'0':<10}")
    out.append("**MEASURDATA")
    for fz in (3000.0, 5000.0):
        for sa in np.linspace(-10, 10, 8):
            out.append(f"{sa:10.4f}{fz:10.1f}{-0.9 * fz * np.sin(1.4 * np.arctan(0.2 * sa)):10.1f}")
    out.append("**END")
    return ("\n".join(out) + "\n").encode()


def _ttc(sweeps: int = 1) -> bytes:
    lines = ["Run 8: synthetic TTC-style record (fuzz seed)", "ET\tV\tSA\tIA\tP\tFX\tFY\tFZ\tMZ\tSL",
             "s\tkph\tdeg\tdeg\tkPa\tN\tN\tN\tN-m\tnone"]
    t = 0.0
    sa_cycle = list(np.linspace(0, -12, 15)) + list(np.linspace(-12, 12, 30)) + list(np.linspace(12, 0, 15))
    for fz in (-1100.0, -660.0):
        for _ in range(sweeps):
            for sa in sa_cycle:
                fy = fz * 2.4 * np.sin(1.4 * np.arctan(0.25 * sa))  # SAE: positive SA, negative FY
                lines.append("\t".join(f"{v:.3f}" for v in (t, 40.0, sa, 0.0, 83.0, 0.0, fy, fz, 0.0, 0.0)))
                t += 0.05
    return ("\n".join(lines) + "\n").encode()


CSV_SEEDS = {"slip_angle": _csv_slip_angle(), "static": _csv_static(), "patch": _csv_patch(),
             "vertical": _csv_vertical(), "slip_ratio": _csv_slip_ratio()}
TDX = _tdx()
TTC = _ttc()


# --------------------------------------------------------------------------- oracle


def _check_dataset(ds: Dataset) -> None:
    """What a returned Dataset promises."""
    assert isinstance(ds, Dataset)
    assert isinstance(ds.df, pd.DataFrame) and len(ds.df) > 0
    assert "run" in ds.df and pd.api.types.is_integer_dtype(ds.df["run"])
    for c in ("fz", "fy", "fx", "slip_angle", "slip_ratio", "camber"):
        if c in ds.df and ds.df[c].dtype != object:
            assert np.all(np.isfinite(ds.df[c].to_numpy(float))), c


def _read(path, **kw) -> None:
    try:
        ds = read_data(path, **kw)
    except TyrefitError:
        return
    _check_dataset(ds)


# --------------------------------------------------------------------------- the seeds are valid


@pytest.mark.parametrize("kind", sorted(CSV_SEEDS))
def test_csv_seeds_read(kind):
    ds = read_data(write(f"seed_{kind}.csv", CSV_SEEDS[kind]))
    assert ds.kind == kind
    _check_dataset(ds)


def test_tdx_and_ttc_seeds_read():
    ds = read_data(write("seed.tdx", TDX))
    assert ds.kind == "slip_angle" and ds.meta["format"] == "tdx"
    _check_dataset(ds)
    ds = read_data(write("seed.dat", _ttc(sweeps=2)), convention="sae")
    assert ds.kind == "slip_angle" and ds.meta["format"] == "ttc" and ds.n_runs >= 2
    _check_dataset(ds)


# --------------------------------------------------------------------------- arbitrary input


@FUZZ
@given(data=st.binary(max_size=4096), suffix=st.sampled_from([".csv", ".tdx", ".dat", ".txt"]))
@example(data=b"", suffix=".csv")
@example(data=b"\x00\x01\x02", suffix=".dat")
@example(data=b"PK\x03\x04rest", suffix=".csv")
def test_arbitrary_bytes_raise_only_tyrefit_errors(data, suffix):
    _read(write(f"bytes{suffix}", data))


@FUZZ
@given(text=st.text(max_size=2000), suffix=st.sampled_from([".csv", ".tdx", ".dat"]))
@example(text='fz [N],fy [N],slip_angle [deg]\n"1\n2",3,4\n', suffix=".csv")
@example(text="fz [N]\n" + "x" * 140000 + "\n", suffix=".csv")
@example(text="a\n" * 4, suffix=".dat")
def test_arbitrary_text_raises_only_tyrefit_errors(text, suffix):
    _read(write(f"text{suffix}", text.encode("utf-8", "surrogatepass")))


@FUZZ
@given(header=st.lists(st.text(max_size=20), min_size=1, max_size=6),
       rows=st.lists(st.lists(st.one_of(st.floats().map(repr), st.text(max_size=6)), min_size=1, max_size=6),
                     max_size=12))
def test_random_tables_raise_only_tyrefit_errors(header, rows):
    lines = [",".join(h.replace("\n", " ") for h in header)]
    lines += [",".join(c.replace("\n", " ") for c in r) for r in rows]
    _read(write("table.csv", ("\n".join(lines) + "\n").encode("utf-8", "surrogatepass")))


# --------------------------------------------------------------------------- mutated valid files


@pytest.mark.parametrize("kind", sorted(CSV_SEEDS))
def test_mutated_csv_raises_only_tyrefit_errors(kind):
    @FUZZ_HALF
    @given(data=mutated(CSV_SEEDS[kind]))
    def check(data):
        _read(write(f"mut_{kind}.csv", data))

    check()


@FUZZ_HALF
@given(data=mutated(TDX))
def test_mutated_tydex_raises_only_tyrefit_errors(data):
    _read(write("mut.tdx", data))


@FUZZ_HALF
@given(data=mutated(TTC), convention=st.sampled_from(["sae", "iso"]))
def test_mutated_ttc_raises_only_tyrefit_errors(data, convention):
    _read(write("mut.dat", data), convention=convention)


@FUZZ_HALF
@given(data=mutated(CSV_SEEDS["slip_angle"]), kind=st.sampled_from(
    ["static", "slip_angle", "slip_ratio", "patch", "vertical", "braking", "utqg", "emission"]))
def test_forced_kind_raises_only_tyrefit_errors(data, kind):
    _read(write("kind.csv", data), kind=kind)


def test_oracle_catches_foreign_exceptions():
    """The oracle itself must fail on a non-tyrefit exception (guards against a test that cannot fail)."""
    def bad_reader(path):
        raise KeyError("not ours")

    with pytest.raises(KeyError):
        only_tyrefit_errors(bad_reader, "x")
    only_tyrefit_errors(lambda p: (_ for _ in ()).throw(TyrefitError("ours")), "x")


# --------------------------------------------------------------------------- issue 15: the input checks


@FUZZ
@given(name=st.sampled_from(["fz", "slip angle", "FY", "camber"]), pad=WHITESPACE, pad2=WHITESPACE,
       unit=st.sampled_from(["N", "kN", "deg", None]))
def test_header_parsing_is_linear_and_ignores_padding(name, pad, pad2, unit):
    """Any whitespace around and inside a header parses like the plain header (no regex backtracking)."""
    from tyrefit.nomenclature import parse_header

    plain = parse_header(f"{name} [{unit}]" if unit else name)
    padded = parse_header(f"{pad}{name}{pad2}[{pad}{unit}{pad2}]{pad}" if unit else f"{pad}{name}{pad2}")
    assert padded == plain


@FUZZ_FEW
@given(scale=st.floats(1e-4, 0.2), seed=st.integers(0, 100))
def test_loads_in_kn_labelled_newtons_are_refused(scale, seed):
    arr = sweep_table(seed=seed)
    arr[:, 3] *= scale
    with pytest.raises(TyrefitError, match="kN"):
        read_data(write("kn.csv", table_csv(arr)))


@FUZZ_FEW
@given(flip=st.sets(st.integers(0, 2), min_size=1, max_size=3), seed=st.integers(0, 100))
def test_sign_flipped_sweeps_are_refused(flip, seed):
    arr = sweep_table(seed=seed)
    for r in flip:
        arr[arr[:, 0] == r, 2] *= -1
    with pytest.raises(TyrefitError, match="opposite sign" if len(flip) < 3 else "reversed in every sweep"):
        read_data(write("flip.csv", table_csv(arr)))


@FUZZ_FEW
@given(run=st.integers(0, 2), value=st.sampled_from([0.0, 1234.5, -50.0]), seed=st.integers(0, 100))
def test_stuck_force_channel_is_refused(run, value, seed):
    arr = sweep_table(seed=seed)
    arr[arr[:, 0] == run, 2] = value
    with pytest.raises(TyrefitError, match="constant"):
        read_data(write("stuck.csv", table_csv(arr)))


@FUZZ_FEW
@given(k=st.integers(1, 5), fz=st.floats(-200.0, 0.0), seed=st.integers(0, 100))
def test_warm_up_samples_without_load_are_dropped_and_counted(k, fz, seed):
    arr = sweep_table(seed=seed)
    warm = np.array([(0, 0.0, 1.0, fz)] * k)
    ds = read_data(write("warm.csv", table_csv(np.vstack([warm, arr]))))
    assert len(ds.df) == len(arr) and (ds.df["fz"] > 0).all()
    assert sum(ds.meta["dropped"].values()) == k


@FUZZ_FEW
@given(seed=st.sampled_from(sorted(CSV_SEEDS)), bom=st.sampled_from([b"\xef\xbb\xbf", b""]))
def test_a_bom_changes_nothing(seed, bom):
    plain = read_data(write("plain.csv", CSV_SEEDS[seed]))
    with_bom = read_data(write("bom.csv", bom + CSV_SEEDS[seed]))
    pd.testing.assert_frame_equal(plain.df, with_bom.df)


def test_tdx_and_ttc_with_bom_read_like_without():
    for name, raw, conv in (("b.tdx", TDX, "iso"), ("b.dat", TTC, "sae")):
        a = read_data(write(name, raw), convention=conv)
        b = read_data(write(name, b"\xef\xbb\xbf" + raw), convention=conv)
        pd.testing.assert_frame_equal(a.df, b.df)


def test_fifo_and_device_inputs_are_refused(tmp_path):
    import os

    fifo = tmp_path / "p.csv"
    os.mkfifo(fifo)
    with pytest.raises(TyrefitError, match="FIFO"):
        read_data(fifo)
    with pytest.raises(TyrefitError, match="device"):
        read_data("/dev/zero")
