"""The aligning moment's trail model (tyrefit.effects.channels.trail_moment) and its diagnosis.

Three kinds of check:

* fixed points against :mod:`tyrefit.models.mf61` (the MF 6.1 evaluator checked against MFeval's
  published values in tests/test_mf61*.py), every trail and residual-torque term switched on: the
  trail model with MF's coefficients and MF's own Fy0 at zero camber is MF 6.1's pure-slip Mz;
* a truth of another form: Pacejka's brush model with a parabolic pressure distribution (Pacejka,
  *Tire and Vehicle Dynamics*, 3rd ed. 2012, Sec. 3.2.2, Eq. 3.34-3.38 for Fy and Mz, written out
  here, not taken from the package), whose trail is a polynomial in the sliding fraction, not a
  cosine: nothing that is not there is named;
* the diagnosis names camber on Mz where MF 6.1's camber acts on the trail, and does not where it
  does not.
"""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

from tyrefit.diagnose.channels import channel_data, diagnose_channel
from tyrefit.effects.base import ModelInputs
from tyrefit.effects.channels import TRAIL_COEFFICIENT, trail_moment
from tyrefit.models import mf61
from tyrefit.synthetic.ttc_drivebrake import published_mf61


def _mf_truth() -> dict:
    """MFeval's MF 6.1 tyre with the side force's shifts and camber shifts zeroed (so MF's residual torque
    is centred at zero slip, SHf = 0, Eq. 4.E38), Br a constant (QBZ10 = 0) and no Fx at zero slip ratio
    (PVX1-2, PHX1-2: MF adds s Fx to Mz, Eq. 4.E71): the terms the trail model has no counterpart for;
    every trail and residual-torque coefficient kept."""
    p = published_mf61()
    for k in ("PHY1", "PHY2", "PHY3", "PVY1", "PVY2", "PVY3", "PVY4", "PKY6", "PKY7", "QBZ10", "QDZ10", "QDZ11",
              "PPZ2", "PVX1", "PVX2", "PHX1", "PHX2"):
        p[k] = 0.0
    return p


def _mapped(p: dict) -> dict:
    """The trail model's coefficients of the MF tyre ``p`` with Fz_ref = FNOMIN (lengths = R0 x QDZ)."""
    r0 = p["UNLOADED_RADIUS"]
    c = {k: v.neutral for k, v in TRAIL_COEFFICIENT.items()}
    c.update(mz_Ct=p["QCZ1"], mz_Dt=r0 * p["QDZ1"], mz_Dt_fz=r0 * p["QDZ2"], mz_Bt=p["QBZ1"], mz_Bt_fz=p["QBZ2"],
             mz_Bt_fz2=p["QBZ3"], mz_Et=p["QEZ1"], mz_Et_fz=p["QEZ2"], mz_Et_fz2=p["QEZ3"], mz_Et_asym=p["QEZ4"],
             mz_Et_camber=p["QEZ5"], mz_SHt=p["QHZ1"], mz_SHt_fz=p["QHZ2"], mz_SHt_camber=p["QHZ3"],
             mz_SHt_camber_fz=p["QHZ4"], mz_Bt_camber=p["QBZ4"], mz_Bt_abs_camber=p["QBZ5"],
             mz_Dt_abs_camber=p["QDZ3"], mz_Dt_camber2=p["QDZ4"], mz_Dr=r0 * p["QDZ6"], mz_Dr_fz=r0 * p["QDZ7"],
             mz_Dr_camber=r0 * p["QDZ8"], mz_Dr_camber_fz=r0 * p["QDZ9"], mz_Br=p["QBZ9"])
    return c


def test_trail_model_is_mf61_pure_slip_mz_at_fixed_points():
    """Loads 0.5-1.5 FNOMIN, slip -12..12 deg, camber 0-4 deg (one sign: MF 6.1's paper has QDZ3 gamma,
    the book |gamma|), nominal pressure: the trail model with MF's coefficients and MF's Fy0(gamma = 0)
    gives MF 6.1's Mz to 1e-6 of its scale."""
    p = _mf_truth()
    fz, a, g = np.meshgrid([3376.0, 6752.0, 10128.0], np.radians(np.linspace(-12, 12, 25)), np.radians([0.0, 2.0, 4.0]))
    fz, a, g = fz.ravel(), a.ravel(), g.ravel()
    truth = mf61.forces(p, fz, 0.0, a, g)["mz"]
    fy0 = mf61.forces(p, fz, 0.0, a, 0.0)["fy"]
    x = ModelInputs(fz=fz, slip_angle=a, camber=g, fz_ref=p["FNOMIN"], side_force=fy0)
    got = trail_moment(_mapped(p), x)
    assert np.max(np.abs(got - truth)) < 1e-6 * np.max(np.abs(truth))  # MF's epsilon guards aside
    # every group of terms matters at these points (the comparison would see a wrong sign in any)
    for k in ("mz_SHt_camber", "mz_Dt_abs_camber", "mz_Bt_camber", "mz_Et_asym", "mz_Dr_camber", "mz_Et_fz2"):
        c = _mapped(p)
        c[k] = -c[k]
        assert np.max(np.abs(trail_moment(c, x) - truth)) > 1e-3 * np.max(np.abs(truth)), k


def test_trail_model_pressure_is_mf61s_ppz1():
    """MF 6.1 shortens the trail with pressure by (1 - PPZ1 dpi) (Eq. 4.E42): the mz_pressure effect with
    mz_p_trail = -PPZ1 gives MF's Mz at 220 and 300 kPa (Fy0 at each pressure from MF)."""
    from tyrefit.diagnose.channels import predict
    from tyrefit.effects.channels import CHANNEL_EFFECTS

    p = _mf_truth()
    fz = np.full(25, 6752.0)
    a = np.radians(np.linspace(-12, 12, 25))
    eff = CHANNEL_EFFECTS["mz"]["mz_pressure"]
    for pr in (220e3, 300e3):
        truth = mf61.forces(p, fz, 0.0, a, 0.0, pressure=np.full(25, pr))
        x = ModelInputs(fz=fz, slip_angle=a, camber=np.zeros(25), pressure=np.full(25, pr), pressure_ref=p["NOMPRES"],
                        fz_ref=p["FNOMIN"], side_force=truth["fy"])
        got = predict("mz", {**_mapped(p), "mz_p_trail": -p["PPZ1"]}, [eff], x)
        assert np.max(np.abs(got - truth["mz"])) < 1e-6 * np.max(np.abs(truth["mz"]))
        plain = predict("mz", _mapped(p), [], x)
        assert np.max(np.abs(plain - truth["mz"])) > 0.05 * np.max(np.abs(truth["mz"]))


def _brush(fz, alpha, mu=1.0, a0=0.08, fz0=4000.0, cpy=4.7e6):
    """Pacejka's brush model, parabolic pressure (Pacejka 2012, Eq. 3.34-3.38), ISO-W signs.

    Half contact length a = a0 sqrt(Fz / Fz0); theta = 2 cpy a^2 / (3 mu Fz); sigma = tan(alpha);
    lam = theta |sigma| (<= 1 in partial sliding):
    Fy = -mu Fz sgn(sigma) (3 lam - 3 lam^2 + lam^3),  Mz = mu Fz a sgn(sigma) lam (1 - lam)^3;
    full sliding (lam > 1): Fy = -mu Fz sgn(sigma), Mz = 0.
    """
    a = a0 * np.sqrt(fz / fz0)
    theta = 2.0 * cpy * a * a / (3.0 * mu * fz)
    s = np.tan(alpha)
    lam = np.minimum(theta * np.abs(s), 1.0)
    fy = -mu * fz * np.sign(s) * (3 * lam - 3 * lam ** 2 + lam ** 3)
    mz = mu * fz * a * np.sign(s) * lam * (1 - lam) ** 3
    return fy, mz


def _brush_record(cambers=(0.0,), loads=(2000.0, 4000.0, 6000.0), seed=0, rho=0.0):
    rng = np.random.default_rng(seed)
    rows = []
    a = np.radians(np.linspace(-12, 12, 41))
    run = 0
    for g in cambers:
        for fz in loads:
            fy, mz = _brush(np.full_like(a, fz), a)
            for y in (fy, mz):
                sd = 0.01 * np.max(np.abs(y))
                e = np.empty(len(a))
                e[0] = rng.normal()
                for i in range(1, len(a)):
                    e[i] = rho * e[i - 1] + np.sqrt(1 - rho * rho) * rng.normal()
                y += sd * e
            rows.append(pd.DataFrame({"run": run, "fz": fz, "slip_angle": a, "camber": np.radians(g), "fy": fy,
                                      "mz": mz}))
            run += 1
    return pd.concat(rows, ignore_index=True)


@pytest.mark.parametrize("cambers,rho", [((0.0,), 0.0), ((0.0, 2.0, 4.0), 0.0), ((0.0, 3.0), 0.8)])
def test_brush_tyre_gets_no_invented_names(cambers, rho):
    """A brush tyre has no camber, conicity, ply steer or side asymmetry in Mz: none is named, under
    independent noise or AR(1) noise at rho 0.8, with camber levels in the record (whose Mz does not change
    with camber).  The trail model's cosine is not the brush's polynomial, so load laws may be named
    (measured: held-out RMSE 1.75-2.48 N*m of 23.7 N*m RMS, verdict "structure remains" or "undecided")."""
    dg = diagnose_channel(channel_data(_brush_record(cambers=cambers, rho=rho), "mz"))
    fams = {c["family"] for c in dg.candidates if c["effect"] in dg.accepted}
    assert not fams & {"mz_camber", "mz_offsets", "mz_asymmetry", "mz_pressure"}, dg.accepted
    # the cosine trail follows the brush's moment to about a tenth of its RMS; the rest is a form it has no
    # term for (the brush's trail stays at zero once the whole patch slides), which is not called noise
    assert dg.steps[-1].rmse_heldout < 0.15 * np.sqrt(np.mean(dg.data.y ** 2))
    assert dg.unexplained["verdict"] != "nothing"


def test_reference_side_force_is_the_least_cambered_sweep_at_the_same_load():
    """The trail multiplies the side force of slip alone (Eq. 4.E31, Fy0 at zero camber): a sweep at 4 deg
    takes the 0-deg sweep's smoothed Fy at its own slip angles; the 0-deg sweep keeps its own."""
    a = np.radians(np.linspace(-10, 10, 41))
    rows = []
    for run, (fz, g, shift) in enumerate([(3000.0, 0.0, 0.0), (3000.0, 4.0, 500.0), (6000.0, 0.0, 0.0),
                                          (6000.0, 4.0, 900.0)]):
        fy = -fz * np.sin(1.3 * np.arctan(10 * a)) - shift
        rows.append(pd.DataFrame({"run": run, "fz": fz, "slip_angle": a, "camber": np.radians(g), "fy": fy,
                                  "mz": 30 * np.sin(6 * a)}))
    cd = channel_data(pd.concat(rows, ignore_index=True), "mz")
    sf = cd.inputs.side_force
    for fz in (3000.0, 6000.0):
        zero = (cd.inputs.fz == fz) & (cd.inputs.camber == 0)
        four = (cd.inputs.fz == fz) & (cd.inputs.camber > 0)
        expect = -fz * np.sin(1.3 * np.arctan(10 * cd.slip[four]))
        assert np.max(np.abs(sf[four] - expect)) < 1e-3 * fz
        assert np.max(np.abs(sf[zero] + fz * np.sin(1.3 * np.arctan(10 * cd.slip[zero])))) < 1e-3 * fz


def test_mz_without_fy_is_reported_in_words():
    df = pd.DataFrame({"run": np.repeat([0, 1], 30), "fz": np.repeat([3000.0, 6000.0], 30),
                       "slip_angle": np.tile(np.radians(np.linspace(-10, 10, 30)), 2),
                       "mz": np.tile(40 * np.sin(np.radians(np.linspace(-10, 10, 30)) * 6), 2)})
    why = channel_data(df, "mz")
    assert isinstance(why, str) and "side force" in why and "no finite fy" in why


@pytest.mark.parametrize("layout", ["2loads_2cambers", "3loads_3cambers"])
def test_mz_camber_on_the_trail_is_named_and_not_invented(layout):
    """MF 6.1's camber acts on the trail (QHZ3 shift, QBZ4-5, QDZ3-4, QEZ5) and the residual torque
    (QDZ8-11): on those sweeps the Mz diagnosis names camber; on the same tyre without its camber terms
    it does not (benchmarks/diagnose_channels.py cases, 1 % noise on Mz and on Fy)."""
    from benchmarks.diagnose_channels import run_case

    row = run_case(("mz", "camber", layout, "iid", 1000))
    assert "mz_camber" in row["named"], row["accepted"]
    plain = run_case(("mz", "plain", layout, "iid", 1000))
    assert "mz_camber" not in plain["named"], plain["accepted"]


def test_a_family_made_redundant_by_a_later_one_is_dropped():
    """4 loads x cambers 0 and 3 deg x 2 pressures of the camber-only MF 6.1 tyre: with half the sweeps
    cambered, the camber moment and trail shift first pass for a residual torque and trail shift
    (mz_offsets, accepted in the first round); once camber is accepted, offsets no longer lower the
    held-out error and are dropped (backward elimination), so the tyre is not described as conical."""
    from benchmarks.diagnose_channels import run_case

    row = run_case(("mz", "camber", "4loads_2cambers_2pressures", "iid", 1000))
    assert "mz_camber" in row["named"]
    assert "mz_offsets" not in row["named"], row["accepted"]


def test_camber_is_not_invented_under_strongly_correlated_noise():
    """2 loads x cambers 0 and 3 deg of the MF 6.1 tyre without camber terms, AR(1) noise at rho 0.9 on Mz and
    Fy: the richest model's residuals read a lag-one correlation of 0.41, and the F test corrected with it
    passed a camber moment (p = 0.0017).  The F test takes the bias-corrected noise model's correlation (0.88)
    when it is the larger, and camber is not named."""
    from benchmarks.diagnose_channels import run_case

    row = run_case(("mz", "plain", "2loads_2cambers", "ar1_09", 1001))
    assert "mz_camber" not in row["named"], row["accepted"]


@pytest.mark.parametrize("fy,why", [(0.0, "zero throughout"), (np.inf, "no finite fy"), ("n/a", "no finite fy")])
def test_mz_with_an_unusable_side_force_is_reported_in_words(fy, why):
    """A side force of zeros (an unconnected channel), infinities or text cannot carry a trail: the Mz channel
    is reported absent with the reason, not diagnosed as if the trail were zero."""
    from tyrefit.diagnose.channels import diagnose_channels

    a = np.radians(np.linspace(-10, 10, 30))
    df = pd.DataFrame({"run": np.repeat([0, 1], 30), "fz": np.repeat([3000.0, 6000.0], 30),
                       "slip_angle": np.tile(a, 2), "mz": np.tile(40 * np.sin(a * 6), 2), "fy": fy})
    out, absent = diagnose_channels(df)
    assert "mz" not in out and why in absent["mz"]
