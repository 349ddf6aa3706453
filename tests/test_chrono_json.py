"""Chrono PAC89 JSON: read the reference file, write -> read round trip."""

import json
import math
from pathlib import Path

import numpy as np
import pytest

from tyrefit.errors import FormatError, ModelError
from tyrefit.io.chrono_json import chrono_dict, read_chrono_json, write_chrono_json
from tyrefit.io.tir import read_tir
from tyrefit.models import pac89

DATA = Path(__file__).parent / "data"


def test_reads_reference_json():
    t = read_chrono_json(DATA / "ref_HMMWV_Pac89Tire.json")
    assert t.name == "HMMWV Pac89 Tire"
    assert t.coefficients["a2"] == pytest.approx(812.449795340733)
    assert t.coefficients["b8"] == pytest.approx(-1.15310023217878)
    assert t.coefficients["c9"] == pytest.approx(-1.3329)
    assert t.unloaded_radius == 0.464 and t.width == 0.318
    assert t.lateral_stiffness == 261065.0
    assert t.vertical_curve[0] == (0.0, 0.0) and t.vertical_curve[-1] == (0.10, 53140.0)
    assert t.rolling_resistance == 0.015


def test_round_trip(tmp_path):
    t = read_chrono_json(DATA / "ref_HMMWV_Pac89Tire.json")
    p = write_chrono_json(t, tmp_path / "t.json")
    back = read_chrono_json(p)
    assert back.coefficients == t.coefficients
    assert back.vertical_curve == t.vertical_curve
    assert (back.unloaded_radius, back.width, back.lateral_stiffness, back.vertical_stiffness) == \
        (t.unloaded_radius, t.width, t.lateral_stiffness, t.vertical_stiffness)
    doc = json.loads(p.read_text())
    assert doc["Template"] == "Pac89Tire"
    assert set(doc["Lateral Coefficients"]) == set(pac89.LATERAL)


def test_tir_to_json_to_tir_values(tmp_path):
    t = read_tir(DATA / "ref_adams_pac89_example.tir")
    with pytest.raises(ModelError, match="needs Vertical Stiffness, Vertical Damping, Mass, Inertia"):
        write_chrono_json(t, tmp_path / "x.json")
    assert not (tmp_path / "x.json").exists()
    t.vertical_stiffness, t.vertical_damping, t.mass, t.inertia = 250e3, 3000.0, 10.0, (0.6, 1.1, 0.6)
    back = read_chrono_json(write_chrono_json(t, tmp_path / "x.json"))
    assert back.coefficients == t.coefficients
    assert chrono_dict(t)["Design Parameters"]["Unloaded Radius"] == pytest.approx(0.326)


def test_not_a_chrono_file(tmp_path):
    p = tmp_path / "x.json"
    p.write_text('{"a": 1}')
    with pytest.raises(FormatError, match="Lateral Coefficients"):
        read_chrono_json(p)
    p.write_text("{not json")
    with pytest.raises(FormatError, match="not a Chrono"):
        read_chrono_json(p)


# --------------------------------------------------------------------------- what Chrono reads

#: keys Pac89Tire::Create reads unconditionally (projectchrono/chrono @ 17a9098167,
#: src/chrono_vehicle/wheeled_vehicle/tire/Pac89Tire.cpp)
CHRONO_TOP = ("Name", "Mass", "Inertia")
CHRONO_DESIGN = ("Unloaded Radius", "Width", "Lateral Stiffness", "Vertical Stiffness", "Vertical Damping",
                 "Rolling Resistance")
CHRONO_BLOCKS = {"Lateral Coefficients": pac89.LATERAL, "Longitudinal Coefficients": pac89.LONGITUDINAL,
                 "Aligning Coefficients": pac89.ALIGNING}


def chrono_has_every_key(doc: dict) -> None:
    for k in CHRONO_TOP:
        assert k in doc, k
    assert len(doc["Inertia"]) == 3 and all(isinstance(v, float) for v in doc["Inertia"])
    for k in CHRONO_DESIGN:
        assert isinstance(doc["Design Parameters"][k], float), k
    for block, names in CHRONO_BLOCKS.items():
        assert set(doc[block]) == set(names), block


def chrono_advance(doc: dict, fz_n: float, alpha_rad: float, kappa: float, gamma_rad: float, mu=0.8):
    """ChPac89Tire::Advance (projectchrono/chrono @ 05a1a976a6, ChPac89Tire.cpp) for one contact state.

    A transcription in plain Python (math module), independent of tyrefit.models.pac89:
    Fz in kN, alpha and gamma in degrees, kappa in percent; kappa clamped to +/-1, gamma to
    +/-3 deg, X1 to +/-89.5 deg; Mz += Fx * Fy / k_lat; returns Chrono's (Fx, Fy, Mz, Mx)
    before its SAE -> ISO flip.
    """
    a, b, c = (doc[k] for k in CHRONO_BLOCKS)
    A = [a[f"a{i}"] for i in range(14)]
    B = [b[f"b{i}"] for i in range(11)]
    C = [c[f"c{i}"] for i in range(18)]
    fz = fz_n / 1000.0
    kap = max(-1.0, min(1.0, kappa)) * 100.0
    alp = math.degrees(alpha_rad)
    gam = max(-3.0, min(3.0, math.degrees(gamma_rad)))
    scale = mu / doc["Coefficient of Friction"]

    def mf(D, Cc, Bb, E, x, sv):
        return D * math.sin(Cc * math.atan(Bb * x - E * (Bb * x - math.atan(Bb * x)))) + sv

    Cx, Dx = B[0], B[1] * fz**2 + B[2] * fz
    BCDx = (B[3] * fz**2 + B[4] * fz) * math.exp(-B[5] * fz)
    fx = scale * mf(Dx, Cx, BCDx / (Cx * Dx), B[6] * fz**2 + B[7] * fz + B[8], kap + B[9] * fz + B[10], 0.0)
    Cy, Dy = A[0], A[1] * fz**2 + A[2] * fz
    BCDy = A[3] * math.sin(math.atan(fz / A[4]) * 2.0) * (1.0 - A[5] * abs(gam))
    x1 = max(-89.5, min(89.5, alp + A[9] * fz + A[10] + A[8] * gam))
    fy = scale * mf(Dy, Cy, BCDy / (Cy * Dy), A[6] * fz + A[7], x1, 0.0) + A[11] * fz * gam + A[12] * fz + A[13]
    Cz, Dz = C[0], C[1] * fz**2 + C[2] * fz
    BCDz = (C[3] * fz**2 + C[4] * fz) * (1 - C[6] * abs(gam)) * math.exp(-C[5] * fz)
    x1 = max(-89.5, min(89.5, alp + C[11] * gam + C[12] * fz + C[13]))
    Ez = (C[7] * fz**2 + C[8] * fz + C[9]) * (1.0 - C[10] * abs(gam))
    svz = (C[14] * fz**2 + C[15] * fz) * gam + C[16] * fz + C[17]
    mz = scale * mf(Dz, Cz, BCDz / (Cz * Dz), Ez, x1, 0.0) + svz
    deflection = fy / doc["Design Parameters"]["Lateral Stiffness"]
    return fx, fy, mz + fx * deflection, -(fz * 1000) * deflection


def test_hmmwv_json_keeps_every_key_chrono_reads(tmp_path):
    """Chrono's own HMMWV file lost Mass, Inertia and Vertical Damping through tyrefit before."""
    t = read_chrono_json(DATA / "ref_HMMWV_Pac89Tire.json")
    assert (t.mass, t.inertia, t.vertical_damping) == (37.6, (3.84, 6.69, 3.84), 3483.932502)
    doc = json.loads(write_chrono_json(t, tmp_path / "h.json").read_text())
    chrono_has_every_key(doc)
    assert doc["Mass"] == 37.6 and doc["Design Parameters"]["Vertical Damping"] == 3483.932502


def test_chrono_advance_transcription_agrees_with_the_model():
    """Inside Chrono's limits the transcription and tyrefit.models.pac89 agree (Mz without Fx*Fy/k_lat)."""
    t = read_chrono_json(DATA / "ref_HMMWV_Pac89Tire.json")
    doc = json.loads(json.dumps(chrono_dict(t)))
    for fz, al, ga in ((3000.0, 0.05, 0.01), (8000.0, -0.2, -0.03), (5000.0, 0.0, 0.0)):
        fx, fy, mz, mx = chrono_advance(doc, fz, al, 0.0, ga)
        # our ISO-W outputs are Chrono's SAE values with fy, mz negated (ChPac89Tire: force (Fx, -Fy), moment -Mz)
        assert -fy == pytest.approx(float(pac89.lateral_force(t.coefficients, fz, al, ga)), rel=1e-12, abs=1e-9)
        assert fx == pytest.approx(float(pac89.longitudinal_force(t.coefficients, fz, 0.0)), rel=1e-12, abs=1e-9)
        assert -(mz - fx * fy / doc["Design Parameters"]["Lateral Stiffness"]) == pytest.approx(
            float(pac89.aligning_moment(t.coefficients, fz, al, ga)), rel=1e-12, abs=1e-9)


def test_bom_json_reads(tmp_path):
    p = tmp_path / "bom.json"
    p.write_bytes(b"\xef\xbb\xbf" + (DATA / "ref_HMMWV_Pac89Tire.json").read_bytes())
    assert read_chrono_json(p).coefficients == read_chrono_json(DATA / "ref_HMMWV_Pac89Tire.json").coefficients


# --------------------------------------------------------------------------- fit --json: Chrono loads it

@pytest.fixture(scope="module")
def fitted_files(tmp_path_factory):
    """`tyrefit fit --size --rated-load --json` on lateral-only data and on lateral + longitudinal data."""
    import pandas as pd

    from tyrefit.cli import main
    from tyrefit.synthetic.pac89_example import _write_csv, lateral_sweeps, longitudinal_sweeps

    d = tmp_path_factory.mktemp("fitjson")
    lat = lateral_sweeps(loads=(2000.0, 4000.0, 6000.0), cambers_deg=(-2.0, 0.0, 2.0))
    lon = longitudinal_sweeps(loads=(2000.0, 4000.0, 6000.0)).assign(run=lambda x: x["run"] + lat["run"].max() + 1,
                                                                     camber=0.0, fy=0.0, mz=0.0)
    both = pd.concat([lat.assign(slip_ratio=0.0, fx=0.0), lon], ignore_index=True)
    out = {}
    for name, df in (("lateral", lat), ("both", both)):
        csv = _write_csv(df, d / f"{name}.csv", "test data")
        tir, js = d / f"{name}.tir", d / f"{name}.json"
        assert main(["fit", str(csv), "--out", str(tir), "--json", str(js), "--size", "245/45R17",
                     "--rated-load", "4000"]) == 0
        out[name] = (tir, js)
    return out


@pytest.mark.parametrize("which", ["lateral", "both"])
def test_fit_json_has_every_key_and_finite_forces_in_chronos_equations(fitted_files, which):
    tir, js = fitted_files[which]
    doc = json.loads(js.read_text())
    chrono_has_every_key(doc)
    d = doc["Design Parameters"]
    assert d["Unloaded Radius"] == pytest.approx(0.2159 + 0.245 * 0.45) and d["Width"] == pytest.approx(0.245)
    assert doc["Mass"] > 0 and d["Vertical Damping"] > 0 and d["Lateral Stiffness"] > 0
    assert any("ESTIMATED" in n for n in doc["Notes"])
    t = read_tir(tir)
    assert t.fnomin == 4000.0 and t.aspect_ratio == pytest.approx(0.45) and t.vertical_damping > 0
    assert any("ESTIMATED" in h for h in t.header)
    lo, hi = t.ranges["fz"]
    a_lo, a_hi = t.ranges["slip_angle"]
    worst = 0.0
    for fz in np.linspace(lo, hi, 7):
        for al in np.linspace(a_lo, a_hi, 15):
            for ka in np.linspace(-0.3, 0.3, 9):
                for ga in np.radians([-2.0, 0.0, 2.0]):
                    out = chrono_advance(doc, fz, al, ka, ga)
                    assert all(math.isfinite(v) for v in out), (fz, al, ka, ga, out)
                    worst = max(worst, abs(out[1]))
    assert worst > 1000.0  # a real lateral force, not a neutral block
    if which == "lateral":  # Fx and Mz not fitted: neutral, zero and finite, said so
        assert any(n.startswith("longitudinal") and "NOT FITTED" in n for n in doc["Notes"])
        assert chrono_advance(doc, 4000.0, 0.1, 0.1, 0.0)[0] == 0.0
    else:
        assert abs(chrono_advance(doc, 4000.0, 0.0, 0.1, 0.0)[0]) > 1000.0


def test_fit_json_without_size_is_refused_before_writing(tmp_path, capsys):
    from tyrefit.cli import main
    from tyrefit.synthetic.pac89_example import _write_csv, lateral_sweeps

    csv = _write_csv(lateral_sweeps(loads=(2000.0, 4000.0, 6000.0), cambers_deg=(0.0,)), tmp_path / "l.csv", "t")
    out, js = tmp_path / "t.tir", tmp_path / "t.json"
    assert main(["fit", str(csv), "--out", str(out), "--json", str(js)]) == 2
    assert "--size" in capsys.readouterr().err
    assert not out.exists() and not js.exists()


@pytest.mark.parametrize("flags,match", [(["--rated-load", "nan"], "positive, finite"),
                                         (["--rated-load", "-5"], "positive, finite"),
                                         (["--size", "big"], "not a tyre size"),
                                         (["--size", "999/10R5"], "not a tyre")])
def test_fit_bad_size_or_load_flags(tmp_path, capsys, flags, match):
    from tyrefit.cli import main
    from tyrefit.synthetic.pac89_example import _write_csv, lateral_sweeps

    csv = _write_csv(lateral_sweeps(loads=(2000.0, 4000.0, 6000.0), cambers_deg=(0.0,)), tmp_path / "l.csv", "t")
    assert main(["fit", str(csv), "--out", str(tmp_path / "t.tir"), *flags]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and match in err[0]


def test_json_block_missing_a_coefficient_is_incomplete(tmp_path):
    doc = json.loads(json.dumps(chrono_dict(read_chrono_json(DATA / "ref_HMMWV_Pac89Tire.json"))))
    del doc["Lateral Coefficients"]["a5"], doc["Aligning Coefficients"]["c17"]
    p = tmp_path / "m.json"
    p.write_text(json.dumps(doc))
    t = read_chrono_json(p)
    assert t.missing == ["a5", "c17"]
    assert t.check()[0] == "required coefficient a5 is missing"
