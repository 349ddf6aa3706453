"""``tyrefit fit``: files in, .tir / JSON / report out; static and --effects paths."""

import math
import sys
import types

import numpy as np
import pytest

from tyrefit.cli import main
from tyrefit.io.chrono_json import read_chrono_json
from tyrefit.io.tir import read_tir
from tyrefit.models import pac89
from tyrefit.synthetic.pac89_example import EXAMPLE, _write_csv, lateral_sweeps, longitudinal_sweeps


@pytest.fixture(scope="module")
def lateral_csv(tmp_path_factory):
    d = tmp_path_factory.mktemp("lat")
    df = lateral_sweeps(cambers_deg=(-4.0, 0.0, 4.0))
    return _write_csv(df, d / "lateral.csv", "test data")


def test_fit_writes_tir_json_and_report(lateral_csv, tmp_path, capsys):
    out, js, rep = tmp_path / "t.tir", tmp_path / "t.json", tmp_path / "rep"
    assert main(["fit", str(lateral_csv), "--out", str(out), "--json", str(js), "--report", str(rep),
                 "--size", "245/45R17", "--rated-load", "4000"]) == 0
    text = capsys.readouterr().out
    assert "RMSE" in text and str(out) in text
    t = read_tir(out)
    assert t.coefficients["a3"] > 0
    sa = np.radians(np.linspace(-12, 12, 97))
    for fz in (2000.0, 8000.0):
        ft = pac89.lateral_force(EXAMPLE, fz, sa, 0.0)
        assert np.max(np.abs(t.fy(fz, sa) - ft)) < 0.005 * np.max(np.abs(ft))
    assert t.ranges["camber"] == pytest.approx((-math.radians(4), math.radians(4)))
    assert read_chrono_json(js).coefficients == t.coefficients
    html = (rep / "index.html").read_text()
    assert "data:image/png;base64" in html and "t.tir" in html and "Coefficients" in html
    assert (rep / "sweeps.csv").exists()


def test_existing_output_needs_force(lateral_csv, tmp_path, capsys):
    out = tmp_path / "t.tir"
    out.write_text("keep me")
    assert main(["fit", str(lateral_csv), "--out", str(out)]) == 2
    assert "--force" in capsys.readouterr().err
    assert out.read_text() == "keep me"
    assert main(["fit", str(lateral_csv), "--out", str(out), "--force"]) == 0
    assert read_tir(out).coefficients["a3"] > 0


def test_l1_cost_flag(lateral_csv, tmp_path):
    out = tmp_path / "l1.tir"
    assert main(["fit", str(lateral_csv), "--out", str(out), "--cost", "l1"]) == 0
    assert any("Eq. 5" in h for h in read_tir(out).header)


def test_out_must_be_tir(lateral_csv, tmp_path, capsys):
    assert main(["fit", str(lateral_csv), "--out", str(tmp_path / "t.txt")]) == 2
    assert ".tir" in capsys.readouterr().err


def test_slip_ratio_and_combined_file(tmp_path):
    lon = longitudinal_sweeps()
    p = _write_csv(lon, tmp_path / "lon.csv", "test")
    assert main(["fit", str(p), "--out", str(tmp_path / "lon.tir")]) == 0
    t = read_tir(tmp_path / "lon.tir")
    assert t.has_longitudinal and t.ranges["slip_ratio"] == pytest.approx((-0.3, 0.3))
    lat = lateral_sweeps(loads=(3000.0, 6000.0), cambers_deg=(0.0,)).drop(columns="mz")
    lat["slip_ratio"] = 0.0
    lat["fx"] = 0.0  # every cell filled: each sweep measures both forces
    lon["run"] += 100
    lon["camber"] = 0.0
    lon["fy"] = 0.0
    both = _write_csv(__import__("pandas").concat([lat, lon], ignore_index=True), tmp_path / "both.csv", "test")
    assert main(["fit", str(both), "--out", str(tmp_path / "both.tir")]) == 0
    t2 = read_tir(tmp_path / "both.tir")
    assert t2.has_longitudinal and t2.coefficients["a3"] > 0


def test_sae_file_with_convention_flag(tmp_path):
    df = lateral_sweeps(loads=(3000.0, 6000.0), cambers_deg=(0.0,)).drop(columns="mz")
    sae = df.assign(fz=-df["fz"], fy=-df["fy"], slip_angle=-df["slip_angle"])  # half turn about x
    p = _write_csv(sae, tmp_path / "sae.csv", "test")
    assert main(["fit", str(p), "--out", str(tmp_path / "a.tir")]) == 2
    assert main(["fit", str(p), "--out", str(tmp_path / "a.tir"), "--convention", "sae"]) == 0
    assert read_tir(tmp_path / "a.tir").coefficients["a3"] > 0


def test_effects_with_monkeypatched_resolver(lateral_csv, tmp_path, monkeypatch, capsys):
    fake = types.ModuleType("tyrefit.effects")

    def resolve_pac89(ids):
        vary = ["a0", "a2", "a3", "a4", "a7"]
        if "camber" in ids:
            vary += ["a5", "a8", "a11"]
        return vary, [f"{i}: test note" for i in ids]

    fake.resolve_pac89 = resolve_pac89
    fake.EFFECTS = {}  # no catalogue entries: every requested effect is carried
    import tyrefit
    import tyrefit.workflows.fit

    monkeypatch.setitem(sys.modules, "tyrefit.effects", fake)
    monkeypatch.setattr(tyrefit, "effects", fake, raising=False)
    monkeypatch.setattr(tyrefit.workflows.fit, "resolve_pac89", resolve_pac89)  # imported there at module level
    out, rep = tmp_path / "e.tir", tmp_path / "rep"
    assert main(["fit", str(lateral_csv), "--effects", "camber", "--out", str(out), "--report", str(rep)]) == 0
    text = capsys.readouterr().out
    assert "start model RMSE" in text
    t = read_tir(out)
    assert t.coefficients["a11"] != 0.0 and t.coefficients["a1"] == 0.0  # camber terms fitted, load slope held
    html = (rep / "index.html").read_text()
    assert "Start model and start model + effects" in html and "camber: test note" in html


def test_effects_lower_the_error(lateral_csv, monkeypatch):
    from tyrefit.commands.fit import fit_file

    fake = types.ModuleType("tyrefit.effects")
    fake.resolve_pac89 = lambda ids: (["a0", "a2", "a3", "a4", "a7"] + (["a5", "a8", "a11"] if ids else []), [])
    fake.EFFECTS = {}
    import tyrefit
    import tyrefit.workflows.fit

    monkeypatch.setitem(sys.modules, "tyrefit.effects", fake)
    monkeypatch.setattr(tyrefit, "effects", fake, raising=False)
    monkeypatch.setattr(tyrefit.workflows.fit, "resolve_pac89", fake.resolve_pac89)  # imported there at module level
    args = types.SimpleNamespace(data=str(lateral_csv), convention="iso", cost="l2", effects="camber",
                                 patch=None, rig=None, vertical=None, static_part="peak", rated_load=None)
    result, extras = fit_file(args)
    assert result.rmse < 0.75 * extras["start"].rmse


def test_static_needs_patch(tmp_path, capsys):
    p = tmp_path / "s.csv"
    rows = ["run,lateral_displacement [mm],fy [N],fz [N]"]
    rows += [f"1,{d},{-40.0 * d},{40000 - 10 * d}" for d in range(0, 60)]
    p.write_text("\n".join(rows) + "\n")
    assert main(["fit", str(p), "--out", str(tmp_path / "s.tir")]) == 2
    assert "--patch PATCH.csv for Eq. 1" in capsys.readouterr().err


def test_static_with_patch_on_bundled_truck(tmp_path):
    from tyrefit.io.datasets import data_path

    # bundled with the package: missing data is a failure, not a skip
    static, patch = data_path("truck", "tyre_a_static.csv"), data_path("truck", "tyre_a_patch.csv")
    vertical = data_path("truck", "tyre_a_vertical.csv")
    out = tmp_path / "s.tir"
    assert main(["fit", str(static), "--patch", str(patch), "--vertical", str(vertical), "--out", str(out)]) == 0
    t = read_tir(out)
    assert t.lateral_stiffness and t.lateral_stiffness > 0
    assert t.vertical_stiffness and t.vertical_stiffness > 0
    assert t.fnomin and t.coefficients["a3"] > 0
    assert any("Eq. 1" in h for h in t.header)


# ------------------------------------------------------------- fit --effects with the real effect catalogue
@pytest.fixture(scope="module")
def passenger_effects(tmp_path_factory):
    """``tyrefit fit`` on the bundled passenger tyre with real catalogue effects (truth in its truth.json)."""
    import contextlib
    import io
    import json

    from tyrefit.io.datasets import data_path

    d = tmp_path_factory.mktemp("passenger_effects")
    out, rep, js = d / "p.tir", d / "rep", d / "p.json"
    buf = io.StringIO()
    with contextlib.redirect_stdout(buf):
        rc = main(["fit", str(data_path("passenger", "passenger_205_55R16.csv")), "--effects",
                   "camber,offsets_constant,load_friction", "--out", str(out), "--report", str(rep),
                   "--json", str(js), "--size", "205/55R16", "--rated-load", "6031"])
    truth = json.loads(data_path("passenger", "truth.json").read_text())["pac89_and_effects"]
    return rc, buf.getvalue(), out, rep, js, truth


def test_effects_real_catalogue_recovers_the_effects_coefficients(passenger_effects):
    """The data hold camber, constant offsets and load-dependent friction (and pressure, which PAC89 lacks):
    the catalogue's PAC89 terms for the three named effects come back close to the generator's values."""
    rc, text, out, _, _, truth = passenger_effects
    assert rc == 0
    c = read_tir(out).coefficients
    for k, rel in (("a5", 0.15), ("a8", 0.1), ("a10", 0.1), ("a11", 0.05), ("a13", 0.05), ("a1", 0.2)):
        assert c[k] == pytest.approx(truth[k], rel=rel), k
    assert c["a9"] == 0.0 and c["a12"] == 0.0          # offsets_constant: no load-dependent shifts


def test_effects_real_catalogue_lowers_the_error_and_reports_both_models(passenger_effects):
    rc, text, _, rep, js, _ = passenger_effects
    line = next(x for x in text.splitlines() if x.strip().startswith("start model RMSE"))
    start, final = (float(v) for v in
                    __import__("re").findall(r"RMSE ([\d.]+) N -> with .*: ([\d.]+) N", line)[0])
    assert final < 0.6 * start                        # measured 273 N -> 136 N with camber and offsets alone
    html = (rep / "index.html").read_text()
    assert "Start model and start model + effects" in html and "start + camber, offsets_constant" in html
    # pressure is in the data and not in the model: the RMSE stays above the floor, and the fit says so
    assert "x the within-sweep noise floor" in text


def test_effects_unknown_id_is_a_one_line_error(lateral_csv, tmp_path, capsys):
    assert main(["fit", str(lateral_csv), "--effects", "cambre", "--out", str(tmp_path / "x.tir")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "unknown effect 'cambre'" in err[0] and "camber" in err[0]
    assert not (tmp_path / "x.tir").exists()


def test_effects_not_in_pac89_say_so(lateral_csv, tmp_path, capsys):
    """'pressure' has no PAC89 terms: the fit runs, and a note says what to do instead."""
    assert main(["fit", str(lateral_csv), "--effects", "pressure", "--out", str(tmp_path / "p.tir")]) == 0
    out = capsys.readouterr().out
    assert "note: pressure:" in out and "PAC89" in out
