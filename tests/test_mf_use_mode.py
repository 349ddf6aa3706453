"""Which parts a Magic Formula file models (USE_MODE, TYREFIT_NOT_FITTED) and where its design data come from.

USE_MODE's last digit is read as MSC's PAC2002 files and TNO's ``dteval`` define it
(0 Fz only, 1 Fx/My only, 2 Fy/Mx/Mz only, 3 uncombined, 4 combined, 5 combined +
turn slip; see :mod:`tyrefit.tyres.mf`).  The writer's not-fitted parts must give no
force in every reader -- tyrefit's (absent: NaN), and one that ignores USE_MODE,
as MFeval does (zero, finite) -- and ``sim`` must refuse a tyre without Fx.
"""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest

from tyrefit.cli import main
from tyrefit.io.tir import read_tyre
from tyrefit.models import mf61
from tyrefit.tyres.mf import parse_not_fitted

DATA = Path(__file__).parent / "data"
GENERIC = DATA / "ref_Generic_Pac02Tire.tir"
MFEVAL61 = DATA / "mfeval_MagicFormula61_Paramerters.tir"


def _with_use_mode(tmp_path, src: Path, value) -> Path:
    text = src.read_text()
    text, n = re.subn(r"(?mi)^USE_MODE\s*=.*$", "" if value is None else f"USE_MODE = {value}", text)
    assert n == 1
    p = tmp_path / f"{src.stem}_{value}.tir"
    p.write_text(text)
    return p


FZ, SA, SR = 30000.0, np.radians(4.0), np.array([-0.1, 0.05, 0.1])


def _forces(tyre):
    return tyre.forces(FZ, slip_angle=SA, slip_ratio=SR, camber=0.02)


@pytest.mark.parametrize("mode, present", [(0, ()), (1, ("fx", "my")), (2, ("fy", "mz", "mx")),
                                           (12, ("fy", "mz", "mx")), (-2, ("fy", "mz", "mx")),
                                           (4, ("fx", "fy", "mz", "mx", "my")),
                                           (124, ("fx", "fy", "mz", "mx", "my")),
                                           (5, ("fx", "fy", "mz", "mx", "my"))])
def test_use_mode_last_digit_selects_the_parts(tmp_path, mode, present):
    ref = _forces(read_tyre(_with_use_mode(tmp_path, GENERIC, None)))
    tyre = read_tyre(_with_use_mode(tmp_path, GENERIC, mode))
    got = _forces(tyre)
    assert tyre.use_mode == mode and tyre.combined
    for ch in ("fx", "fy", "mz", "mx", "my"):
        if ch in present:
            np.testing.assert_array_equal(got[ch], ref[ch])
        else:
            assert np.isnan(got[ch]).all(), (mode, ch)
    assert tyre.has_longitudinal == ("fx" in present) and tyre.has_lateral == ("fy" in present)
    assert tyre.has_aligning == ("mz" in present)
    assert tyre.check() == []
    assert any("mirror" in w for w in tyre.warnings()) == (mode < 0)


def test_use_mode_3_is_uncombined(tmp_path):
    ref = read_tyre(_with_use_mode(tmp_path, GENERIC, 4))
    tyre = read_tyre(_with_use_mode(tmp_path, GENERIC, 3))
    assert not tyre.combined
    got = _forces(tyre)
    fx_pure = ref.forces(FZ, slip_angle=0.0, slip_ratio=SR, camber=0.02)
    fy_pure = ref.forces(FZ, slip_angle=SA, slip_ratio=0.0 * SR, camber=0.02)
    for ch in ("fx", "my"):
        np.testing.assert_array_equal(got[ch], fx_pure[ch])
    for ch in ("fy", "mz", "mx"):
        np.testing.assert_array_equal(got[ch], fy_pure[ch])
    # and that differs from the combined evaluation (the test could fail)
    comb = _forces(ref)
    assert np.all(np.abs(got["fx"] - comb["fx"]) > 50.0) and np.all(np.abs(got["fy"] - comb["fy"]) > 50.0)


@pytest.mark.parametrize("name", sorted(p.name for p in DATA.glob("*.tir")))
def test_vendor_files_read_as_before(tmp_path, name):
    """Every shipped file with a USE_MODE (4, 14, 124) gives the forces it gives without one."""
    src = DATA / name
    if not re.search(r"(?mi)^USE_MODE\s*=", src.read_text(errors="replace")):
        pytest.skip("no USE_MODE")
    tyre, plain = read_tyre(src), read_tyre(_with_use_mode(tmp_path, src, None))
    assert tyre.use_mode in (4, 14, 124)
    fz = 0.8 * (tyre.fnomin or 4000.0)
    a, b = (t.forces(fz, slip_angle=np.radians([-6.0, 3.0]), slip_ratio=[-0.05, 0.08], camber=0.01)
            for t in (tyre, plain))
    for ch in a:
        np.testing.assert_array_equal(a[ch], b[ch])
    assert tyre.has_longitudinal and tyre.has_lateral and tyre.combined


def test_not_fitted_marker_parsing():
    assert parse_not_fitted(["x", "TYREFIT_NOT_FITTED = fx, mx, combined"]) == {"fx", "mx", "combined"}
    assert parse_not_fitted(["NOT FITTED: pure-slip Fx (PCX1, ...)", "TYREFIT_NOT_FITTED: fx"]) == set()
    assert parse_not_fitted(["tyrefit_not_fitted = FY; bogus"]) == {"fy"}


# ---------------------------------------------------------------- a lateral-only fit, end to end
def _lateral_csv(path: Path, *, loaded_radius: bool = False) -> Path:
    """Slip-angle sweeps of MFeval's MF 6.1 example at 3 loads, 2 cambers (Fy, Mz with 0.5 % noise)."""
    p = {k.upper(): v for k, v in read_tyre(MFEVAL61).params.items()}
    rng = np.random.default_rng(3)
    rows = []
    for fz in (2500.0, 4500.0, 6500.0):
        for cam in (0.0, 3.0):
            a = np.radians(np.linspace(-12, 12, 61))
            f = mf61.forces(p, fz, 0.0, a, np.radians(cam), p["NOMPRES"], 16.6)
            fy = f["fy"] + 0.005 * np.max(np.abs(f["fy"])) * rng.standard_normal(a.size)
            mz = f["mz"] + 0.005 * np.max(np.abs(f["mz"])) * rng.standard_normal(a.size)
            rl = p["UNLOADED_RADIUS"] - fz / p["VERTICAL_STIFFNESS"] + 2e-4 * rng.standard_normal(a.size)
            for i in range(a.size):
                rows.append(f"{fz:.1f},{np.degrees(a[i]):.4f},{cam},{fy[i]:.3f},{mz[i]:.4f}"
                            + (f",{rl[i] * 1e3:.3f}" if loaded_radius else ""))
    head = "fz [N],slip_angle [deg],camber [deg],fy [N],mz [N*m]" + (",loaded_radius [mm]" if loaded_radius else "")
    path.write_text(head + "\n" + "\n".join(rows) + "\n")
    return path


@pytest.fixture(scope="module")
def lateral_fit(tmp_path_factory):
    d = tmp_path_factory.mktemp("lat")
    csv = _lateral_csv(d / "lateral.csv")
    out = d / "lat.tir"
    assert main(["fit", str(csv), "--model", "mf61", "--out", str(out)]) == 0
    return csv, out


def test_lateral_only_fit_models_no_fx_anywhere(lateral_fit, tmp_path, capsys):
    csv, out = lateral_fit
    text = out.read_text()
    q = {k.upper(): v for k, v in read_tyre(out).params.items()}
    # for Adams: Fy, Mx, Mz only; for tyrefit: the channels without data, machine-readable
    assert q["USE_MODE"] == 2
    assert re.search(r"(?m)^\$ TYREFIT_NOT_FITTED = fx, mx, my, combined$", text)
    tyre = read_tyre(out)
    assert not tyre.has_longitudinal and tyre.has_lateral and tyre.has_aligning
    f = tyre.forces(3800.0, slip_angle=0.05, slip_ratio=0.1)
    assert np.isnan(f["fx"]) and np.isfinite(f["fy"]) and abs(f["fy"]) > 1000
    # a reader that ignores USE_MODE (MFeval) evaluates the same equations: Fx is zero and finite, not a generic curve
    g = mf61.forces(q, np.array([500.0, 3800.0, 8000.0])[:, None], np.linspace(-1, 1, 11), 0.05, 0.0)
    assert np.all(g["fx"] == 0.0) and all(np.isfinite(v).all() for v in g.values())
    assert q["PKX1"] == 0.0 and q["PKX2"] == 0.0 and q["PDX1"] != 0.0 and q["PCX1"] != 0.0
    # sim braking needs Fx: a clear one-line refusal
    capsys.readouterr()
    assert main(["sim", "braking", "--front", str(out), "--rear", str(out)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "no longitudinal model" in err[0]
    # eval leaves fx empty and says why
    pts = tmp_path / "p.csv"
    pts.write_text("fz [N],slip_angle [deg],slip_ratio [-]\n3800,3,0.1\n")
    assert main(["eval", str(out), "--points", str(pts), "--out", str(tmp_path / "f.csv")]) == 0
    assert "no longitudinal model" in capsys.readouterr().out
    row = dict(zip(*(line.split(",") for line in (tmp_path / "f.csv").read_text().splitlines()[:2])))
    assert row["fx [N]"] == "" and float(row["fy [N]"]) < 0


def test_placeholders_are_declared_without_size(lateral_fit):
    _, out = lateral_fit
    head = " ".join(read_tyre(out).header)  # header lines are wrapped at 100 characters
    assert re.search(r"PLACEHOLDER \[DIMENSION\][^$]*UNLOADED_RADIUS 0\.3135", head)
    assert re.search(r"PLACEHOLDER \[OPERATING_CONDITIONS\][^$]*INFLPRES 220000", head)
    assert "no pressure column: NOMPRES = INFLPRES 220 kPa is a placeholder" in head
    assert "PLACEHOLDER [INERTIA]" in head and "MASS 9.3" in head


def test_size_rated_load_and_loaded_radius_replace_placeholders(tmp_path, capsys):
    csv = _lateral_csv(tmp_path / "lat_rl.csv", loaded_radius=True)
    out = tmp_path / "s.tir"
    assert main(["fit", str(csv), "--model", "mf61", "--out", str(out), "--size", "255/55R18",
                 "--rated-load", "5000"]) == 0
    printed = capsys.readouterr().out
    tyre = read_tyre(out)
    p, head = tyre.params, " ".join(tyre.header)
    truth = read_tyre(MFEVAL61).params
    # the loaded-radius channel gives R0 and c_z (the data win over the size's design radius 0.3892 m)
    assert p["UNLOADED_RADIUS"] == pytest.approx(truth["UNLOADED_RADIUS"], abs=5e-4)
    assert p["VERTICAL_STIFFNESS"] == pytest.approx(truth["VERTICAL_STIFFNESS"], rel=0.03)
    assert "FROM THE DATA" in head
    # the size gives width, aspect ratio and rim radius; the rated load FNOMIN; mass etc. are estimates
    assert (p["WIDTH"], p["ASPECT_RATIO"], p["RIM_RADIUS"]) == pytest.approx((0.255, 0.55, 0.2286))
    assert p["FNOMIN"] == 5000.0 and p["MASS"] == pytest.approx(0.015 * 5000 / 9.80665)
    assert "mass 7.65 kg ESTIMATED" in head
    dim = re.search(r"PLACEHOLDER \[DIMENSION\][^:]*:([^$]*?)PLACEHOLDER", head).group(1)
    assert "RIM_WIDTH" in dim and not re.search(r"\b(UNLOADED_RADIUS|WIDTH|ASPECT_RATIO)\b", dim)
    assert "UNLOADED_RADIUS" not in printed.split("PLACEHOLDERS")[-1]


# ---------------------------------------------------------------- fit --json: what Chrono needs, named
def test_fit_json_names_exactly_the_flags_chrono_still_needs(tmp_path, capsys):
    """Chrono's Pac89Tire::Create reads Mass, Inertia and the Design Parameters (radius, width, stiffnesses,
    damping) without defaults; fit names the flags that give the missing ones, one line, nothing written."""
    data = str(Path(__file__).parents[1] / "data" / "truck" / "tyre_a_dynamic.csv")
    out, js = tmp_path / "a.tir", tmp_path / "a.json"
    assert main(["fit", data, "--out", str(out), "--json", str(js)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "--size" in err[0] and "--rated-load" in err[0] and "Mass" in err[0]
    assert main(["fit", data, "--out", str(out), "--json", str(js), "--size", "385/65R22.5"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    # the size gives radius, width, mass and inertia: only the stiffness flags are asked for
    assert len(err) == 1 and "--size" not in err[0] and "--rated-load" in err[0] and "Mass" not in err[0]
    assert "Vertical Stiffness" in err[0]
    assert not out.exists() and not js.exists()


# ---------------------------------------------------------------- sim braking with one tyre on both axles (qa bug 5)
def test_sim_braking_takes_the_same_tyre_on_both_axles(tmp_path, capsys):
    """The most ordinary car has one tyre all round: its stopping distances, not a refusal.  The base and the
    low-wear vehicle then carry the same tyres (k = 1) and stop alike; a front tyre softer than the rear is
    still refused (seed 000's comparison is hard front / soft rear)."""
    import json

    sim = Path(__file__).parents[1] / "data" / "sim"
    soft, hard = str(sim / "soft_rear.tir"), str(sim / "hard_front.tir")
    js = tmp_path / "b.json"
    assert main(["sim", "braking", "--front", soft, "--rear", soft, "--json", str(js)]) == 0
    rows = json.loads(js.read_text())["rows"]
    dist = {(r["condition"], r["initial_speed_kmh"], r["vehicle"]): r["stopping_distance_m"] for r in rows}
    assert len(dist) == 12 and all(d > 0 for d in dist.values())
    for (c, v, veh), d in dist.items():
        assert d == pytest.approx(dist[(c, v, "base")], rel=1e-9)
    # physics: the stop from 120 km/h at eta = 1 takes at least v^2 / (2 mu_max g) with mu_max <= 1.3
    assert dist[(1.0, 120.0, "base")] > (120 / 3.6) ** 2 / (2 * 1.3 * 9.81)
    capsys.readouterr()
    assert main(["sim", "braking", "--front", soft, "--rear", hard, "--json", str(tmp_path / "c.json")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "must be the harder one" in err[0]


# ---------------------------------------------------------------- a closed stdout pipe (qa bug 8)
@pytest.mark.parametrize("model", ["pac89", "mf61"])
def test_closed_stdout_pipe_still_writes_the_tyre(tmp_path, model):
    """``tyrefit fit ... | head -1``: the reader goes away before tyrefit has printed; the tyre file must still
    be committed, with exit 0 and no traceback (it was lost: the BrokenPipeError aborted the staged run)."""
    import subprocess
    import sys

    csv = _lateral_csv(tmp_path / "lat.csv")
    out = tmp_path / "t.tir"
    code = "import sys; from tyrefit.cli import main; sys.exit(main(sys.argv[1:]))"
    proc = subprocess.Popen([sys.executable, "-c", code, "fit", str(csv), "--model", model, "--out", str(out)],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    proc.stdout.close()  # the reader is gone before the first line
    err = proc.stderr.read().decode()
    assert proc.wait(timeout=300) == 0, err
    assert "Traceback" not in err and "Broken pipe" not in err, err
    assert out.exists() and read_tyre(out).has_lateral


def test_batch_mf_fit_says_where_design_values_come_from(tmp_path):
    """batch fit --model mf61 writes the same origins as fit: R0 and c_z from a loaded-radius channel, the rest
    declared PLACEHOLDER (the batch has no --size)."""
    src = tmp_path / "data"
    src.mkdir()
    _lateral_csv(src / "a.csv", loaded_radius=True)
    out = tmp_path / "out"
    assert main(["batch", "fit", str(src), "--out", str(out), "--model", "mf61", "--workers", "1"]) == 0
    tyre = read_tyre(out / "a.tir")
    head = " ".join(tyre.header)
    truth = read_tyre(MFEVAL61).params
    assert tyre.params["UNLOADED_RADIUS"] == pytest.approx(truth["UNLOADED_RADIUS"], abs=5e-4)
    assert "FROM THE DATA" in head and re.search(r"PLACEHOLDER \[DIMENSION\][^$]*\bWIDTH 0\.205", head)
    assert not tyre.has_longitudinal


def test_inspect_reports_use_mode_and_not_fitted(lateral_fit, tmp_path, capsys):
    import json

    _, out = lateral_fit
    js = tmp_path / "i.json"
    assert main(["inspect", str(out), "--json", str(js)]) == 0
    text = capsys.readouterr().out
    assert "model parts: lateral, aligning (pure slip only); USE_MODE 2; not fitted: combined, fx, mx, my" in text
    d = json.loads(js.read_text())
    assert d["use_mode"] == 2 and d["parts"] == ["lateral", "aligning"] and "fx" in d["not_fitted"]
