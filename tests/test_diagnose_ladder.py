"""``diagnose --base mf61`` (tyrefit.workflows.ladder): what the Magic Formula tyre of ``fit --model mf61`` misses.

Truth: MFeval's published MF 6.1 tyre (tyrefit.models.mf61) with a grip loss above a rated load that
MF 6.1 cannot carry - a power-law knee on LMUY per load level, not the correction form the ladder
tests - and the same tyre without it.
"""

from __future__ import annotations

import json
import subprocess
import sys

import numpy as np
import pandas as pd
import pytest

from tyrefit.workflows.ladder import diagnose_mf
from tyrefit.io.readers import Dataset
from tyrefit.synthetic.ttc_drivebrake import make_sweeps, published_mf61

RATED = 6000.0


def _record(knee: bool, seed: int = 11) -> Dataset:
    p = published_mf61()
    frames, run = [], 0
    for k, fz in enumerate((3000.0, 4500.0, 6000.0, 7500.0, 9000.0)):
        q = dict(p)
        if knee and fz > RATED:
            q["LMUY"] = 1.0 - 0.9 * ((fz - RATED) / RATED) ** 1.5
        df = make_sweeps(q, seed=seed + k, noise=0.005, loads=[fz], cambers_deg=(0.0,), pressures=(260e3,),
                         slip_angles_deg=(0.0,), n_points=61, combined=False, pure=True)
        df = df[df.groupby("run")["slip_ratio"].transform(np.ptp) == 0].copy()
        df["run"] = run
        run += 1
        frames.append(df)
    df = pd.concat(frames, ignore_index=True)
    return Dataset(df[["run", "fz", "slip_angle", "slip_ratio", "camber", "pressure", "speed", "fy", "mz"]],
                   kind="slip_angle", source="synthetic knee record")


@pytest.fixture(scope="module")
def knee():
    return diagnose_mf([_record(True)], rated_load=RATED)


def test_a_knee_above_the_rated_load_is_named_beyond_mf61(knee):
    fy = knee.channels["fy"]
    assert "overload" in fy.accepted
    steps = fy.steps
    assert [s["added"] for s in steps] == [None, "friction law re-adjusted", "overload"]
    assert steps[-1]["rmse"] < 0.6 * steps[0]["rmse"]  # the knee was most of the tyre's error
    assert steps[-1]["rmse_heldout"] < 0.8 * steps[1]["rmse_heldout"]  # and it predicts held-out sweeps
    assert {c["effect"]: c["status"] for c in fy.candidates}["overload"] == "accepted"
    # the correction takes grip away above the rating: theta > 0 on the direction -max(Fz - Fr, 0) / Fr
    assert next(c for c in fy.candidates if c["effect"] == "overload")["theta"] > 0


def test_without_a_knee_nothing_beyond_mf61_is_named():
    lg = diagnose_mf([_record(False)], rated_load=RATED)
    assert "overload" not in lg.channels["fy"].accepted
    assert lg.channels["fy"].unexplained["verdict"] in ("nothing", "undecided")


def test_held_terms_are_reported_by_channel(knee):
    held = knee.held
    # one camber level and one pressure: the fit holds the camber and pressure terms with that reason
    ppy = {k: v for k, v in held.get("fy", {}).items() if k.startswith("PPY")}
    assert ppy and all("pressure" in v for v in ppy.values())
    assert all(k.startswith("PP") for k in held.get("fy", {}) if "pressure" in held["fy"][k])
    d = knee.to_dict()
    for key in ("start", "accepted", "noise_floor", "steps", "candidates"):
        assert key in d  # the diagnose --json contract keys
    assert d["start"] == ["mf61"]


def test_cli_base_mf61(tmp_path):
    from tyrefit.datasets import path

    out = tmp_path / "d.json"
    proc = subprocess.run([sys.executable, "-m", "tyrefit.cli", "diagnose", str(path("ttc_mf61/cornering.dat")),
                           str(path("ttc_mf61/drivebrake.dat")), "--convention", "sae", "--base", "mf61",
                           "--json", str(out), "--report", str(tmp_path / "rep")],
                          capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0, proc.stderr
    d = json.loads(out.read_text())
    assert set(d["channels"]) == {"fy", "mz", "fx"}
    assert (tmp_path / "rep" / "index.html").stat().st_size > 10000
    bad = subprocess.run([sys.executable, "-m", "tyrefit.cli", "diagnose", str(path("ttc_mf61/cornering.dat")),
                          "--convention", "sae", "--base", "mf61", "--start", "camber", "--json",
                          str(tmp_path / "e.json")], capture_output=True, text=True, timeout=120)
    assert bad.returncode == 2 and "Traceback" not in bad.stderr and "--start" in bad.stderr
