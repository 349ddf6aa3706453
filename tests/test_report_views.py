"""The fit report's views show every condition level of the data, each panel titled with its true conditions.

Checked from the figure objects themselves (axes titles, the model lines'
data), on a generated FSAE-style record of 3 pressures x 3 cambers x 5 loads
(45 sweeps, :func:`tyrefit.synthetic.ttc.make_record` with its own seeded
programme) and on drive/brake sweeps at 2 pressures x 2 cambers x 3 loads.
"""

from __future__ import annotations

import math
import re

import numpy as np
import pandas as pd
import pytest

from tyrefit.io.facets import channel_levels, facet_sweeps, format_condition
from tyrefit.models import pac89
from tyrefit.synthetic.pac89_example import EXAMPLE

PROGRAMME = {"loads_N": [1100.0, 660.0, 220.0, 1550.0, 880.0], "cambers_deg": [0.0, 2.0, 4.0],
             "pressures_kPa": [82.7, 68.9, 96.5], "speeds_kmh": [40.0], "sweep_amplitude_deg": 9.75}


@pytest.fixture(scope="module")
def fsae45():
    """The 45-sweep record (segmented), its set points per run, and the fit."""
    from tyrefit.fitting import fit_pac89
    from tyrefit.io.readers import Dataset  # noqa: F401 - the reader path is exercised by the CLI tests
    from tyrefit.io.segment import segment_record
    from tyrefit.synthetic.ttc import make_record

    rec, truth = make_record(seed=7, rate=10.0, programme=PROGRAMME)
    df, meta = segment_record(rec, "slip_angle", "fsae45")
    assert meta["n_sweeps"] == 45
    res = fit_pac89(df[["run", "fz", "fy", "mz", "slip_angle", "camber", "pressure", "speed"]])
    return df, truth, res


def _panels(figs):
    return [ax for fig in figs for ax in fig.axes if ax.get_visible() and ax.get_title()]


def _model_lines(ax):
    return {int(ln.get_gid().split()[-1]): ln for ln in ax.get_lines() if (ln.get_gid() or "").startswith("model run")}


@pytest.mark.parametrize("part", ["lateral", "aligning"])
def test_every_sweep_of_the_45_is_drawn_once_under_its_true_conditions(fsae45, part):
    df, truth, res = fsae45
    figs = res.facet_figures(part)
    panels = _panels(figs)
    assert len(panels) == 9  # 3 pressures x 3 cambers, nothing dropped, nothing repeated
    seen = []
    sweep_mean = df.groupby("run")[["pressure", "camber", "fz"]].mean()
    titles = set()
    for ax in panels:
        t = ax.get_title()
        titles.add(t)
        m = re.fullmatch(r"pressure (\d+) kPa, camber (-?\d+\.\d)°", t)
        assert m, t
        p_kpa, cam = float(m.group(1)), float(m.group(2))
        lines = _model_lines(ax)
        assert len(lines) == 5  # the five loads
        for run, ln in lines.items():
            seen.append(run)
            # the set points the generator used for this sweep (segmentation keeps the record order)
            assert abs(truth[run]["camber_deg"] - cam) < 0.15
            # the title shows the measured level (the tyre warms: up to +1.5 kPa over the set point)
            assert abs(sweep_mean.loc[run, "pressure"] / 1e3 - p_kpa) <= 1.5
            assert abs(truth[run]["pressure_kpa"] - p_kpa) <= 2.5
            # the line is the model at this sweep's own mean load and camber
            x = np.radians(ln.get_xdata())
            fz, gam = sweep_mean.loc[run, "fz"], sweep_mean.loc[run, "camber"]
            want = (res.tyre.fy(fz, x, gam) if part == "lateral" else res.tyre.mz(fz, x, gam))
            np.testing.assert_allclose(ln.get_ydata(), want, rtol=1e-9, atol=1e-9)
            assert ln.get_label() == f"{fz / 1e3:.2f} kN"
    assert sorted(seen) == list(range(45))
    assert len(titles) == 9
    for fig in figs:
        sup = fig._suptitle.get_text()
        assert "PAC89" in sup and "pressure not in the model" in sup and "speed 40 km/h" in sup


def test_report_header_and_warnings_say_what_the_tyre_lacks(fsae45):
    _, _, res = fsae45
    text = "\n".join(res.model_lines())
    assert "longitudinal Fx (b0-b10): NOT FITTED" in text
    assert re.search(r"pressure: not in the model .* 3 levels \(70, 84, 98 kPa\)", text)
    assert any(w.startswith("pressure: not in the model") for w in res.warnings)
    assert any("NOT FITTED" in h for h in res.tyre.header)
    tab = res.sweeps_table()
    assert "pressure [kPa]" in tab and tab["pressure [kPa]"].between(60, 110).all()


def test_many_levels_are_paginated_not_dropped():
    """5 pressures x 2 cambers with at most 2 rows per page: 3 pages, every panel present."""
    rows = []
    run = 0
    for p in (180e3, 200e3, 220e3, 240e3, 260e3):
        for c in (-0.0314, 0.0314):
            for fz in (2000.0, 4000.0):
                a = np.radians(np.linspace(-8, 8, 30))
                rows.append(pd.DataFrame({"run": run, "fz": fz, "slip_angle": a, "camber": c, "pressure": p,
                                          "fy": pac89.lateral_force(EXAMPLE, fz, a, c)}))
                run += 1
    df = pd.concat(rows, ignore_index=True)
    from tyrefit.io.facets import pages

    facets, info = facet_sweeps(df, ("pressure", "speed", "camber"))
    assert info["varying"] == ["pressure", "camber"]
    assert [f.title for f in facets[:2]] == ["pressure 180 kPa, camber -1.8°", "pressure 180 kPa, camber 1.8°"]
    pg = pages(facets, max_rows=2)
    assert [len(p) for p in pg] == [4, 4, 2]
    assert sorted(r for f in facets for r in f.runs) == list(range(run))


def test_drive_brake_sweeps_all_drawn():
    """Slip-ratio sweeps at 2 pressures x 2 cambers x 3 loads: 4 panels, 12 sweeps."""
    from tyrefit.fitting import fit_pac89

    rng = np.random.default_rng(3)
    rows, run = [], 0
    for p in (83e3, 97e3):
        for c in (0.0, math.radians(2.0)):
            for fz in (700.0, 1100.0, 1500.0):
                s = np.linspace(-0.2, 0.2, 60)
                fx = pac89.longitudinal_force(EXAMPLE, fz, s) + rng.normal(0, 5, s.size)
                rows.append(pd.DataFrame({"run": run, "fz": fz + rng.normal(0, 3, s.size), "slip_ratio": s,
                                          "camber": c, "pressure": p, "fx": fx}))
                run += 1
    res = fit_pac89(pd.concat(rows, ignore_index=True))
    panels = _panels(res.facet_figures("longitudinal"))
    assert sorted(ax.get_title() for ax in panels) == sorted(
        f"pressure {p} kPa, camber {c}°" for p in (83, 97) for c in ("0.0", "2.0"))
    assert sorted(r for ax in panels for r in _model_lines(ax)) == list(range(12))


def test_levels_and_labels():
    lv, idx = channel_levels(np.r_[[2e5] * 3, [2.3e5] * 3, [2.6e5] * 3] + np.tile([0, 300, -300], 3), "pressure")
    np.testing.assert_allclose(lv, [2e5, 2.3e5, 2.6e5])  # the top level too (it sits in the last bin)
    assert list(idx) == [0, 0, 0, 1, 1, 1, 2, 2, 2]
    assert format_condition("camber", math.radians(-0.000451)) == "camber 0.0°"
    assert format_condition("pressure", 83450.0) == "pressure 83 kPa"
    assert format_condition("speed", 40 / 3.6) == "speed 40 km/h"


# ------------------------------------------------------------------------------ CLI: --by, noise floor, warnings
@pytest.fixture(scope="module")
def fsae45_file(tmp_path_factory):
    from tyrefit.synthetic.ttc import format_ttc, make_record

    rec, _ = make_record(seed=7, rate=10.0, programme=PROGRAMME)
    p = tmp_path_factory.mktemp("fsae") / "fsae45.dat"
    p.write_text(format_ttc(rec))
    return p


def test_fit_by_pressure_writes_one_tyre_per_level_and_beats_the_merged_fit(fsae45_file, tmp_path, capsys):
    from tyrefit.cli import main
    from tyrefit.io.tir import read_tyre

    assert main(["fit", str(fsae45_file), "--convention", "sae", "--out", str(tmp_path / "m.tir")]) == 0
    merged_out = capsys.readouterr().out
    assert "merged: 3 pressure levels (70, 84, 98 kPa) fitted as one tyre" in merged_out
    merged_rmse = float(re.search(r"lateral RMSE ([\d.]+) N", merged_out).group(1))
    assert main(["fit", str(fsae45_file), "--convention", "sae", "--out", str(tmp_path / "t.tir"),
                 "--by", "pressure", "--report", str(tmp_path / "rep")]) == 0
    out = capsys.readouterr().out
    table = pd.read_csv(tmp_path / "t_by_pressure.csv")
    assert list(table["level"]) == ["pressure 70 kPa", "pressure 84 kPa", "pressure 98 kPa"]
    assert list(table["sweeps"]) == [15, 15, 15]
    # the synthetic tyre's grip and stiffness change with pressure: one tyre per level fits better
    assert (table["RMSE [N]"] < 0.85 * merged_rmse).all()
    for f in table["file"]:
        t = read_tyre(tmp_path / f)
        assert any("one tyre per pressure level" in h for h in t.header)
        assert (tmp_path / "rep" / f.split("_", 1)[1].removesuffix(".tir") / "index.html").exists()
    assert "merged:" not in out


def test_fit_by_a_single_level_is_a_clear_error(fsae45_file, tmp_path, capsys):
    from tyrefit.cli import main

    assert main(["fit", str(fsae45_file), "--convention", "sae", "--out", str(tmp_path / "t.tir"),
                 "--by", "speed"]) == 2
    err = capsys.readouterr().err
    assert "one speed level (speed 40 km/h)" in err and "Traceback" not in err
    assert not list(tmp_path.iterdir())


@pytest.mark.slow
def test_diagnose_suggests_a_complete_export_that_keeps_its_promise(fsae45_file, tmp_path, capsys, monkeypatch):
    """Run the command the diagnose report suggests, as written: it must run (SAE file: --convention sae),
    give the RMSE the report promises, and report the same noise floor as diagnose."""
    import json
    import shlex

    from tyrefit.cli import main

    monkeypatch.chdir(tmp_path)
    assert main(["diagnose", str(fsae45_file), "--convention", "sae", "--json", "d.json", "--report", "dg"]) == 0
    capsys.readouterr()
    floor = json.load(open("d.json"))["noise_floor"]
    html = (tmp_path / "dg" / "index.html").read_text()
    import html as _html

    cmd = _html.unescape(re.search(r"To export: (tyrefit fit .*? --out tyre\.tir)", html).group(1))
    promised = float(re.search(r"--out tyre\.tir - it gives lateral RMSE ([\d.]+) N", _html.unescape(html)).group(1))
    argv = shlex.split(cmd)
    assert argv[:2] == ["tyrefit", "fit"] and "--convention" in argv and argv[argv.index("--convention") + 1] == "sae"
    assert main(argv[1:]) == 0
    out = capsys.readouterr().out
    m = re.search(r"lateral RMSE ([\d.]+) N \(R² [\d.]+, noise floor ([\d.]+) N\)", out)
    rmse, shown_floor = float(m.group(1)), float(m.group(2))
    assert rmse == pytest.approx(promised, abs=0.05 + 1e-4 * promised)  # the report prints 0.1 N
    assert shown_floor == pytest.approx(floor, rel=0.001)  # printed to 4 significant digits
    assert (tmp_path / "tyre.tir").exists()


def test_fit_noise_floor_is_diagnose_definition(fsae45):
    """The number itself, without printing: fit's floor equals diagnose's function on diagnose's sampling."""
    from tyrefit.diagnose.data import prepare
    from tyrefit.diagnose.stats import noise_floor

    df, _, res = fsae45
    sd = prepare(df[["run", "fz", "fy", "slip_angle", "camber", "pressure", "speed"]])
    want, _ = noise_floor(sd.inputs.slip_angle, sd.fy, sd.sweep, fz=sd.inputs.fz)
    assert res.stats["lateral"]["noise_floor"] == pytest.approx(want, rel=1e-9)
    assert res.stats["lateral"]["point_scatter"] != pytest.approx(want, rel=1e-3)  # the other estimate, named apart


def test_inspect_drive_brake_record_read_as_sae_does_not_ask_for_sae(tmp_path, capsys):
    """A drive/brake record (slip angle held per sweep) read with --convention sae: no sign complaint."""
    from tyrefit.cli import main

    rng = np.random.default_rng(5)
    rows = []
    for run, (sa, fz) in enumerate([(0.0, 700.0), (0.0, 1100.0), (-3.0, 700.0), (-3.0, 1100.0), (3.0, 900.0)]):
        s = np.linspace(-0.15, 0.15, 80)
        fx = pac89.longitudinal_force(EXAMPLE, fz, s)
        # SAE signs; Fy changes with slip ratio while the rig's slip angle creeps with it (compliance), so the
        # within-sweep slope of Fy against slip angle is that creep, not the cornering stiffness
        fy = 300.0 * sa + 200.0 * s / 0.15 + rng.normal(0, 10, s.size)
        rows.append(pd.DataFrame({"run": run, "SA [deg]": sa + 0.3 * s / 0.15 + rng.normal(0, 0.02, s.size),
                                  "SL [-]": s,
                                  "FZ [N]": -fz, "FX [N]": fx, "FY [N]": fy}))
    p = tmp_path / "db.csv"
    pd.concat(rows).rename(columns={"SA [deg]": "slip_angle [deg]", "SL [-]": "slip_ratio [-]", "FZ [N]": "fz [N]",
                                    "FX [N]": "fx [N]", "FY [N]": "fy [N]"}).to_csv(p, index=False)
    assert main(["inspect", str(p), "--convention", "sae"]) == 0
    out = capsys.readouterr().out
    assert "slip_ratio test" in out and "(--convention sae)?" not in out and "not ISO-W" not in out


def test_signature_legend_labels_are_rounded():
    """The diagnose signature legend read 'data -0.000451 deg' for the zero-camber level."""
    from tyrefit.effects.signatures import _group_label

    lv = [math.radians(-0.000451), math.radians(2.0), math.radians(4.0)]
    assert [_group_label("camber", v, lv) for v in lv] == ["camber 0.0°", "camber 2.0°", "camber 4.0°"]
    assert _group_label("fz", 1111.2, [1111.2]) == "1.11 kN"
    assert _group_label("pressure", 200.4e3, [200.4e3, 200.9e3]) != _group_label("pressure", 200.9e3,
                                                                                   [200.4e3, 200.9e3])


def test_fit_warnings_reach_the_tir_and_the_chrono_json(fsae45, tmp_path):
    """A fit that stays above its noise floor and merges pressures says so in the .tir header and the JSON."""
    import json

    from tyrefit.io.tir import read_tyre

    from tyrefit.tyres.size import parse_size, with_design

    _, _, res = fsae45
    assert any("x the within-sweep noise floor" in w for w in res.warnings)  # 3 pressures in one PAC89 tyre
    res = res.with_tyre(with_design(res.tyre, parse_size("205/55R16"), 1500.0)[0])  # design data Chrono's JSON needs
    res.tyre.to_tir(tmp_path / "t.tir")
    res.tyre.to_chrono_json(tmp_path / "t.json")
    header = read_tyre(tmp_path / "t.tir").header
    notes = json.loads((tmp_path / "t.json").read_text())["Notes"]
    for w in res.warnings:
        assert any(w in h for h in header) and any(w in n for n in notes)
    d = res.to_dict()
    assert d["warnings"] == res.warnings and d["stats"]["lateral"]["noise_floor"] == res.noise_floor


def test_a_coefficient_at_its_bound_is_flagged_not_fitted():
    """Slip-ratio sweeps with no peak drive the shape factor b0 to its bound: status and warning say so."""
    from tyrefit.fitting import fit_pac89
    from tyrefit.fitting.result import _at_bound

    assert _at_bound(0.3, 0.3, 2.0) == "lower" and _at_bound(1.0, 0.3, 2.0) is None
    rng = np.random.default_rng(2)
    rows = []
    for run, fz in enumerate((2000.0, 4000.0, 6000.0)):
        s = np.linspace(-0.3, 0.3, 80)
        fx = 25.0 * fz * s + rng.normal(0, 15, s.size)  # a straight line: no peak, no curvature
        rows.append(pd.DataFrame({"run": run, "fz": fz, "slip_ratio": s, "fx": fx}))
    res = fit_pac89(pd.concat(rows, ignore_index=True))
    flagged = res.coefficients[res.coefficients["status"].str.startswith("at its")]
    assert "b0" in set(flagged["name"])
    for r in flagged.itertuples():
        assert any(w.startswith(f"{r.part}: {r.name} = ") and "bound" in w for w in res.warnings)
    assert not res.coefficients[res.coefficients["status"] == "fitted"]["name"].isin(flagged["name"]).any()


def test_compare_reports_fits_rmse_and_noise_floor(fsae45):
    """compare --data scores a fitted tyre with the RMSE and noise floor that fit reported for it."""
    from tyrefit.compare.tyres import compare_tyres
    from tyrefit.io.readers import Dataset

    df, _, res = fsae45
    data = Dataset(df[["run", "fz", "fy", "mz", "slip_angle", "camber", "pressure", "speed"]], kind="slip_angle",
                   source="fsae45")
    s = compare_tyres(res.tyre, res.tyre, data).summary()
    assert s["rmse_N"][0] == pytest.approx(res.stats["lateral"]["rmse"], rel=1e-9)
    assert s["noise_floor_N"] == pytest.approx(res.stats["lateral"]["noise_floor"], rel=1e-12)


def test_diagnose_views_show_every_pressure_and_camber(fsae45):
    """The diagnose report's panels: every (camber, pressure) pair, titled in display units."""
    from tyrefit.diagnose import views
    from tyrefit.diagnose.data import prepare

    df, _, _ = fsae45
    sd = prepare(df[["run", "fz", "fy", "slip_angle", "camber", "pressure", "speed"]])
    fc = views.facets(sd)
    titles = [views._facet_title(sd, c, p) for c, p in fc]
    got = [re.fullmatch(r"camber (-?\d+\.\d)°, pressure (\d+) kPa", t).groups() for t in titles]
    assert [c for c, _ in got] == ["0.0", "2.0", "4.0"] * 3
    np.testing.assert_allclose([float(p) for _, p in got], np.repeat([70.2, 83.5, 98.0], 3), atol=1.0)


def test_drive_brake_sweeps_left_out_of_the_fit_are_drawn_too():
    """Combined-slip sweeps (slip angle held at -3 deg) are not fitted by PAC89 but still drawn, titled."""
    from tyrefit.fitting import fit_pac89
    from tyrefit.fitting.result import unfitted_figures

    rows, run = [], 0
    for sa in (0.0, -3.0):
        for c in (0.0, 2.0):
            for fz in (700.0, 1500.0):
                s = np.linspace(-0.2, 0.2, 60)
                rows.append(pd.DataFrame({"run": run, "fz": fz, "slip_ratio": s, "slip_angle": math.radians(sa),
                                          "camber": math.radians(c), "fx": pac89.longitudinal_force(EXAMPLE, fz, s)
                                          * (1 - 0.1 * abs(sa) / 3)}))
                run += 1
    df = pd.concat(rows, ignore_index=True)
    res = fit_pac89(df)
    fitted = set(res._parts["longitudinal"].data.df["run"])
    left = sorted(set(range(run)) - fitted)
    assert left == [4, 5, 6, 7]  # the -3 deg sweeps
    figs = unfitted_figures(df, left)
    panels = _panels(figs)
    assert sorted(ax.get_title() for ax in panels) == ["camber 0.0°", "camber 2.0°"]
    assert "slip angle -3.0°" in figs[0]._suptitle.get_text()  # common to every panel: said once, on top
    drawn = sorted(int(ln.get_gid().split()[-1]) for ax in panels for ln in ax.get_lines())
    assert drawn == left
    assert "4 sweeps NOT FITTED" in figs[0]._suptitle.get_text()


def test_a_report_folder_given_as_a_relative_path_is_written(tmp_path, monkeypatch):
    """`tyrefit diagnose ... --report rep` (relative) failed: files of the staged folder were staged twice."""
    from tyrefit.io.outputs import output_run, staged_dir, write_text

    monkeypatch.chdir(tmp_path)
    with output_run([], ["rep"]):
        with staged_dir("rep") as tmp:
            for name in ("index.html", "cells.csv", "candidates.csv"):
                write_text(tmp / name, name)
    assert sorted(p.name for p in (tmp_path / "rep").iterdir() if not p.name.startswith(".")) == [
        "candidates.csv", "cells.csv", "index.html"]
    assert not [p for p in tmp_path.iterdir() if p.name.startswith(".rep.")]  # no staging folder left behind


def test_a_sweep_without_a_pressure_value_is_drawn_and_said():
    rows = []
    a = np.radians(np.linspace(-8, 8, 30))
    for run, p in enumerate([200e3, 200e3, 240e3, np.nan]):
        rows.append(pd.DataFrame({"run": run, "fz": 3000.0 + 500 * run, "slip_angle": a, "pressure": p,
                                  "fy": pac89.lateral_force(EXAMPLE, 3000.0, a)}))
    facets, info = facet_sweeps(pd.concat(rows, ignore_index=True), ("pressure", "speed", "camber"))
    assert [f.title for f in facets] == ["pressure not recorded", "pressure 200 kPa", "pressure 240 kPa"]
    assert sorted(r for f in facets for r in f.runs) == [0, 1, 2, 3]
