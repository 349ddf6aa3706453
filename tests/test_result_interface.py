"""One result type for every family (issue 27): PAC89 and MF fits answer the same calls, lmfit included."""

from __future__ import annotations

import lmfit
import pytest

import tyrefit as tf
from tyrefit.errors import FitError
from tyrefit.fitting.result_base import TyreFitResult


@pytest.fixture(scope="module")
def results():
    pac = tf.fit(tf.datasets.path("truck/tyre_a_dynamic.csv"))
    corner = tf.read_data(tf.datasets.path("ttc_mf61/cornering.dat"), convention="sae")
    mf = tf.fit(corner, model="mf61")
    return {"pac89": pac, "mf61": mf}


@pytest.mark.parametrize("family", ["pac89", "mf61"])
def test_every_family_is_one_result_type(results, family, tmp_path):
    r = results[family]
    assert isinstance(r, TyreFitResult)
    assert r.contract() == []
    frame = r.to_frame()
    assert len(frame) > 100
    assert "<table" in r._repr_html_() and r.summary()
    assert r.rmse > 0 and set(r.to_dict())
    out = r.write_tir(tmp_path / "t.tir")
    assert tf.read_tyre(out).family.startswith("PAC89" if family == "pac89" else "MF")


@pytest.mark.parametrize("family", ["pac89", "mf61"])
def test_fit_report_is_lmfits(results, family):
    r = results[family]
    p = r.lmfit_params()
    assert isinstance(p, lmfit.Parameters)
    varied = [k for k, v in p.items() if v.vary]
    assert varied and all(p[k].stderr is not None and p[k].stderr > 0 for k in varied)
    text = r.fit_report(show_correl=False)
    assert "[[Variables]]" in text and "[[Fit Statistics]]" in text
    assert all(f"{k}:" in text for k in varied) and "+/-" in text
    if family == "mf61":
        assert set(varied) <= set(r.fitted) and "PDY1" in varied and "FNOMIN" not in p


def test_write_tir_refuses_a_tyre_that_breaks_the_contract(results, tmp_path):
    import copy

    r = copy.deepcopy(results["pac89"])
    r.tyre.coefficients["a0"] = -1.3  # C < 0: no tyre
    assert r.contract()
    with pytest.raises(FitError, match="not physical"):
        r.write_tir(tmp_path / "bad.tir")
    assert not (tmp_path / "bad.tir").exists()


def test_the_command_line_does_not_import_lmfit(tmp_path):
    """lmfit is imported when a caller asks for lmfit objects, not by ``tyrefit fit`` (+0.6 s per call)."""
    import subprocess
    import sys

    code = ("import sys; from tyrefit.cli import main; "
            f"rc = main(['fit', {str(tf.datasets.path('truck/tyre_a_dynamic.csv'))!r}, '--out', "
            f"{str(tmp_path / 't.tir')!r}]); print(rc, 'lmfit' in sys.modules)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120).stdout
    assert out.strip().splitlines()[-1] == "0 False"


def test_pac89_lmfit_params_carry_the_correlations(results):
    p = results["pac89"].lmfit_params()
    varied = [k for k, v in p.items() if v.vary]
    assert all(isinstance(p[k].correl, dict) and p[k].correl for k in varied)
    assert abs(p["a3"].correl["a4"]) <= 1.0
