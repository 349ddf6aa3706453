"""PAC89 against numbers computed by Project Chrono's own ``ChPac89Tire`` code (issue 25).

``tests/data/chrono_pac89_reference.json`` holds Fx, Fy, Mz (and Chrono's
combined Mz and Mx) computed once by the formula code of
projectchrono/chrono @ 05a1a976a6, ``src/chrono_vehicle/wheeled_vehicle/tire/
ChPac89Tire.cpp`` lines 198-278 and 307-308 (``ChPac89Tire::Advance``), copied
into a throw-away C++ harness with Chrono's types replaced by doubles.  The
file holds only inputs, coefficients, outputs and citations (see its
``source`` and ``conventions`` entries).  Two published coefficient sets that no
one on this project wrote: Chrono's HMMWV_Pac89Tire.json and the Adams/Tire
example set (every camber and shift term nonzero).

The mapping, read from Chrono's code (the JSON states the lines): Chrono's
formula input ``m_alpha`` is tyrefit's ISO-W slip angle in degrees (two sign
flips cancel), ``m_kappa`` is 100 x the slip ratio, ``m_gamma`` the ISO-W
inclination in degrees, Fz in kN; Chrono returns ISO Fx = Fx, Fy = -Fy_pac,
Mz = -Mz_pac.  tyrefit must agree to round-off (rel 1e-9, abs 1e-6 N or N*m).
"""

import json
from pathlib import Path

import numpy as np
import pytest
from numpy.testing import assert_allclose

from tyrefit.io.chrono_json import read_chrono_json
from tyrefit.io.tir import read_tir
from tyrefit.models import pac89
from tyrefit.tyres.pac89 import Pac89Tyre

DATA = Path(__file__).parent / "data"
REF = json.loads((DATA / "chrono_pac89_reference.json").read_text())
SETS = tuple(REF["points"])
BLOCKS = ("pure_lateral", "pure_longitudinal", "combined")
RTOL, ATOL = 1e-9, 1e-6


def _block(name, block):
    s = REF["points"][name]
    b = {k: np.asarray(v, dtype=float) for k, v in s[block].items()}
    return s["coefficients"], s["lateral_stiffness_N_per_m"], b


def _inputs(b):
    """Chrono's internal inputs -> tyrefit's SI / ISO-W arguments (mapping in the JSON's conventions)."""
    return b["fz_N"], np.radians(b["alpha_deg"]), b["kappa"], np.radians(b["gamma_deg"])


@pytest.mark.parametrize("block", BLOCKS)
@pytest.mark.parametrize("name", SETS)
def test_fx_matches_chrono(name, block):
    c, _, b = _block(name, block)
    fz, _, kappa, _ = _inputs(b)
    assert_allclose(pac89.longitudinal_force(c, fz, kappa), b["Fx_pac_N"], rtol=RTOL, atol=ATOL)
    assert_allclose(b["force_x_iso_N"], b["Fx_pac_N"], rtol=0, atol=0)  # Chrono keeps Fx's sign (line 307)


@pytest.mark.parametrize("block", BLOCKS)
@pytest.mark.parametrize("name", SETS)
def test_fy_matches_chrono(name, block):
    c, _, b = _block(name, block)
    fz, sa, _, cam = _inputs(b)
    assert_allclose(pac89.lateral_force(c, fz, sa, cam), b["force_y_iso_N"], rtol=RTOL, atol=ATOL)
    assert_allclose(b["force_y_iso_N"], -b["Fy_pac_N"], rtol=0, atol=0)


@pytest.mark.parametrize("block", BLOCKS)
@pytest.mark.parametrize("name", SETS)
def test_mz_matches_chrono(name, block):
    """tyrefit's pure-slip Mz is Chrono's Mz before the Fx * deflection term (line 269), negated."""
    c, _, b = _block(name, block)
    fz, sa, _, cam = _inputs(b)
    assert_allclose(pac89.aligning_moment(c, fz, sa, cam), -b["Mz_pac_pure_Nm"], rtol=RTOL, atol=ATOL)


@pytest.mark.parametrize("name", SETS)
def test_tyre_forces_and_chrono_combined_moments(name):
    """Combined slip through the Tyre interface; Chrono's Fx * Fy / k_lat term and Mx rebuilt from its outputs.

    Chrono has no combined-slip reduction (Fx from kappa only, Fy from alpha and
    gamma only); its only combined term is Mz += Fx * Fy_pac / k_lat and
    Mx = -Fz * Fy_pac / k_lat (lines 272-278), which tyrefit leaves out
    (documented in tyrefit/tyres/pac89.py).  In ISO-W those are
    Mz_chrono = mz + fx * fy / k_lat and Mx = fz * fy / k_lat.
    """
    c, k_lat, b = _block(name, "combined")
    fz, sa, sr, cam = _inputs(b)
    out = Pac89Tyre(coefficients=c, lateral_stiffness=k_lat).forces(fz, sa, sr, cam)
    assert_allclose(out["fx"], b["force_x_iso_N"], rtol=RTOL, atol=ATOL)
    assert_allclose(out["fy"], b["force_y_iso_N"], rtol=RTOL, atol=ATOL)
    assert_allclose(out["mz"], -b["Mz_pac_pure_Nm"], rtol=RTOL, atol=ATOL)
    assert_allclose(out["mz"] + out["fx"] * out["fy"] / k_lat, b["moment_z_iso_Nm"], rtol=RTOL, atol=ATOL)
    assert_allclose(fz * out["fy"] / k_lat, b["Mx_Nm"], rtol=RTOL, atol=ATOL)
    # the cross term is not negligible at these points, so the line above is a real check of its sign
    assert np.max(np.abs(out["fx"] * out["fy"] / k_lat)) > 1.0


def test_coefficients_are_the_published_files():
    """The stored coefficient sets are the reference fixtures, as tyrefit's readers read them."""
    files = {"hmmwv_json": read_chrono_json(DATA / "ref_HMMWV_Pac89Tire.json"),
             "adams_example": read_tir(DATA / "ref_adams_pac89_example.tir")}
    assert set(files) == set(SETS)
    for name, tyre in files.items():
        s = REF["points"][name]
        assert s["coefficients"] == {k: tyre.coefficients[k] for k in pac89.ALL}
        assert s["lateral_stiffness_N_per_m"] == pytest.approx(tyre.lateral_stiffness)


def test_reference_grid_has_teeth():
    """The stored points reach the terms a mutation would hide in: both signs, camber, shifts, the clamp."""
    ad = REF["points"]["adams_example"]
    lat, lon = ad["pure_lateral"], ad["pure_longitudinal"]
    assert min(lat["alpha_deg"]) < -89.5 and max(lat["alpha_deg"]) > 89.5  # Chrono's X1 clamp active
    assert min(lat["gamma_deg"]) < 0 < max(lat["gamma_deg"]) <= REF["conventions"]["harness_settings"][
        "m_gamma_limit_deg"]
    assert min(lon["kappa"]) == -1.0 and max(lon["kappa"]) == 1.0  # inside Chrono's +/-1 clamp
    assert all(ad["coefficients"][k] != 0.0 for k in pac89.ALL)
    for name in SETS:
        for block in BLOCKS:
            assert len(REF["points"][name][block]["fz_N"]) >= 40
    assert REF["source"]["commit"] == "05a1a976a65bc09b5191476bbc808d9a1dcac415"
