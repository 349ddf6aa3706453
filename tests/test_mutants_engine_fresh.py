"""diagnose/engine.py: tests for a fresh sample of mutants that survived the quick suite.

``python -m benchmarks.mutation --sample 216 --seed 15`` of ``tyrefit/diagnose/engine.py`` (sites in
brackets; each docstring names the mutant it kills).  Each test states behaviour a user sees - a refusal,
a verdict, a named place in the summary - on small hand-built residuals of a synthetic rig layout, not
the mutated text.
"""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest

from tyrefit.diagnose.data import prepare
from tyrefit.diagnose.engine import (MISFIT_RATIO, MISFIT_SHARE, Settings, _Engine, _misfit, _misfit_text, _unexplained,
                                   diagnose)
from tyrefit.errors import DataError
from tyrefit.synthetic.hidden import make_case, rig_grid


@pytest.fixture(scope="module")
def rig():
    """The default synthetic rig layout: one -12..12 deg sweep per load (5) x camber (3) x pressure (2)."""
    case = make_case((), "iid", seed=5)
    data = prepare(case.data)
    eng = _Engine(data, Settings(), 0)
    x = data.inputs
    ext = np.max(np.abs(x.slip_angle))
    u = np.clip(x.slip_angle / ext, -1, 1)
    return SimpleNamespace(case=case, data=data, eng=eng, u=u)


@pytest.fixture(scope="module")
def rig9():
    """A small rig layout: one -12..12 deg sweep (25 points) per load (3) x camber (-3, 0, +3 deg)."""
    grid = rig_grid(loads=(3000.0, 5000.0, 7000.0), cambers_deg=(-3.0, 0.0, 3.0), pressures=(220e3,),
                    points_per_sweep=25)
    data = prepare(make_case((), "iid", seed=5, grid=grid).data)
    x = data.inputs
    u = np.clip(x.slip_angle / np.max(np.abs(x.slip_angle)), -1, 1)
    return SimpleNamespace(data=data, eng=_Engine(data, Settings(), 0), u=u)


def _step(r, rmse_heldout, J):
    """The final step of a diagnosis, reduced to what the end check reads: residuals, held-out RMSE, Jacobian."""
    return SimpleNamespace(fit=SimpleNamespace(resid=np.asarray(r, float), theta=None), rmse_heldout=rmse_heldout,
                           spec=SimpleNamespace(jacobian=lambda theta, x: (None, J)))


def _level_z(data, f):
    """The level of factor ``f`` of each point, scaled to [-1, 1]."""
    lv = np.asarray(data.levels[f], float)
    v = lv[data.level_index[f]]
    return (v - 0.5 * (lv.min() + lv.max())) / (0.5 * np.ptp(lv))


def test_a_record_with_a_zero_noise_floor_is_refused_with_a_data_error(rig):
    """engine.py [609] ``_diagnose`` (``floor <= 0`` -> ``floor < 0``), --sample 216 --seed 15 site 100.

    Every decision of the diagnosis is measured against the within-sweep noise floor (the practical
    margin is ``Settings.margin`` x the floor; the end check divides by it).  A record whose Fy sweeps
    leave no noise at all - a dead Fy channel recorded as zeros - has a floor of exactly 0 and cannot
    be diagnosed: it is refused with a DataError (the CLI's one-line error, exit 2).  The mutant lets
    the floor of 0 through and the end check fails with a ZeroDivisionError traceback.
    """
    df = rig.case.data.copy()
    df["fy"] = 0.0
    with pytest.raises(DataError, match="noise floor"):
        diagnose(df, rated_load=rig.case.rated_load)


def test_a_misfit_even_in_camber_is_predicted_by_the_surface_and_put_down_to_camber(rig9):
    """engine.py [909] ``_condition_terms`` (``len(lv) >= 3`` -> ``> 3``), --sample 216 --seed 15 site 121.

    The misfit check's smooth surface has, per condition factor, the terms z and z^2 (``_condition_terms``:
    "z in [-1, 1] per factor, z^2, pair products"); a z^2 term needs 3 levels to be estimated, and the
    rig's usual camber programme (-3, 0, +3 deg) has exactly 3.  A residual that is the same at -3 and at
    +3 deg and different at 0 (a cornering stiffness that falls with the camber's magnitude, whatever its
    sign) is then a systematic misfit that other sweeps predict, and the check puts it down to camber.
    Without z^2 for 3 levels (the mutant) the surface has only the camber slope, which is blind to an
    even pattern: the misfit is called unpredictable (correlated noise) and camber is not named.
    """
    d, eng, u = rig9.data, rig9.eng, rig9.u
    assert len(d.levels["camber"]) == 3 and eng.G >= 6
    zc = _level_z(d, "camber")
    even = zc**2 - np.mean(zc**2)                       # +1/3 at +-3 deg, -2/3 at 0 deg
    noise = 10.0 * np.random.default_rng(1).standard_normal(d.n)
    r = noise + 40.0 * even * np.tanh(4.0 * u)         # stiffness change, odd in slip
    floor = 10.0
    mf = _misfit(eng, _step(r, 2.0 * floor, None), floor, u, None)
    assert mf["ratio"] > MISFIT_RATIO and mf["checked"]
    assert mf["systematic"] and mf["predictable_share"] >= MISFIT_SHARE
    assert next(iter(mf["components"])) == "camber" and mf["components"]["camber"] > 0.5
    assert mf["odd_share"] > 0.5                        # the curve's shape, not a shift


def test_the_end_check_finds_a_slip_curve_error_that_changes_sign_with_load(rig):
    """engine.py [1052] ``_unexplained`` (``P[:, :5] * z[:, None]`` -> ``P[:, :5]``), --sample 216 --seed 15 site 422.

    The end check's omnibus score test looks for smooth residual directions in slip (Legendre orders
    0-4 and 5-9) "and orders 0-4 times each condition (load, camber, pressure, speed), one group each"
    (``_unexplained``).  A residual slope at small slip that grows with load - a load law of the
    cornering stiffness the model lacks - is positive at high loads and negative at low ones: its mean
    over the loads is zero, so the slip-shape groups cannot see it, only the 'slip x load' group can.
    The check must find it (verdict 'structure', that group's p-value at the bootstrap's floor).  The
    mutant's 'slip x load' group has lost its load factor (it repeats the slip-shape group): the same
    residuals pass for noise.
    """
    d, u = rig.data, rig.u
    eng = _Engine(d, Settings(), 0)                     # its own bootstrap stream
    zf = _level_z(d, "fz")
    noise = 10.0 * np.random.default_rng(2).standard_normal(d.n)
    r = noise + 6.0 * zf * np.tanh(3.0 * u)
    J = np.polynomial.legendre.legvander(u, 2)          # the model follows the slip curve common to all loads
    floor = 10.0
    un = _unexplained(eng, _step(r, 1.1 * floor, J), floor, Settings())
    g = un["omnibus_groups"]
    assert set(g) >= {"slip shape (orders 0-4)", "slip x load", "slip x camber", "slip x pressure"}
    assert g["slip x load"]["p_value"] < 0.01
    assert un["verdict"] == "structure" and un["structure_found"]
    assert un["summary"].startswith("structure remains (omnibus score test p = ")
    # the same record without the load law: nothing found
    eng0 = _Engine(d, Settings(), 0)
    un0 = _unexplained(eng0, _step(noise, 1.1 * floor, J), floor, Settings())
    assert un0["verdict"] == "noise" and not un0["structure_found"]


def test_the_end_check_names_the_cell_far_above_the_overall_rmse(rig):
    """engine.py [1083] ``_unexplained`` (``np.mean(r ** 2)`` -> ``np.mean(r * 2)``), --sample 216 --seed 15 site 429.

    The end check says where the residual is largest: the condition cells whose RMSE stands well above
    the overall RMSE of the residuals (1.5 x), each "(RMSE x N, k x the overall y N)".  One of 30 cells
    with four times the noise of the others (3.3 x the overall RMSE; the others 0.8 x) is named, alone,
    with its RMSE over the overall RMSE; the mutant's "overall" is the square root of twice the mean
    residual (near 0, or NaN when the mean is negative), so it names every cell or none.
    """
    d, eng = rig.data, rig.eng
    rng = np.random.default_rng(3)
    bad = d.cell == d.cell[np.argmax(d.inputs.fz)]
    r = np.where(bad, 40.0, 10.0) * rng.standard_normal(d.n)
    r -= r.mean()
    overall = np.sqrt(np.mean(r**2))
    rmse_bad = np.sqrt(np.mean(r[bad] ** 2))
    floor = 10.0
    un = _unexplained(eng, _step(r, 1.1 * floor, np.ones((d.n, 1))), floor, Settings())
    cells = [w for w in un["where"] if w.startswith("cells ")]
    assert len(cells) == 1
    assert cells[0].count("Fz ") == 1
    fz = np.median(d.inputs.fz[bad])
    assert cells[0].startswith(f"cells Fz {fz / 1e3:.1f} kN")
    assert f"(RMSE {rmse_bad:.0f} N, {rmse_bad / overall:.1f} x the overall {overall:.0f} N)" in cells[0]


def test_the_end_check_names_a_slip_range_of_five_points():
    """engine.py [1073] ``_unexplained`` (a slip bin needs ``m.sum() >= 5`` points, not 6), --sample 216
    --seed 15 site 157.

    The end check names the slip ranges (8 equal bins; "a bin needs at least 5 points", its docstring)
    whose mean residual lies beyond 3 standard errors.  Five sweeps reach -12 deg with one point each and
    otherwise run from -8.5 to 12 deg: the -12 to -9 deg bin holds exactly 5 points, where the model is
    63 N off; it must be named.
    """
    import pandas as pd

    slip = np.radians(np.r_[-12.0, np.linspace(-8.5, 12.0, 40)])
    loads = (2000.0, 3500.0, 5000.0, 6500.0, 8000.0)
    df = pd.DataFrame({"run": np.repeat(np.arange(5), slip.size), "slip_angle": np.tile(slip, 5),
                       "fz": np.repeat(loads, slip.size), "camber": 0.0})
    df["fy"] = -df["fz"] * np.sin(1.4 * np.arctan(8.0 * df["slip_angle"]))
    d = prepare(df)
    eng = _Engine(d, Settings(), 0)
    rng = np.random.default_rng(4)
    r = 5.0 * rng.standard_normal(d.n) + np.where(d.inputs.slip_angle < np.radians(-10.0), 63.0, 0.0)
    floor = 5.0
    un = _unexplained(eng, _step(r, 1.1 * floor, np.ones((d.n, 1))), floor, Settings())
    assert any(w.startswith("slip ranges -12.0 to -9.0 deg") for w in un["where"]), un["where"]


@pytest.mark.parametrize("loads", [(3000.0, 6000.0), (5000.0,)], ids=["two sweeps", "one sweep"])
def test_a_record_of_fewer_than_three_sweeps_is_diagnosed_and_its_end_check_is_undecided(loads):
    """engine.py [981] ``_unexplained`` (``q = max(1, G // 3)`` -> ``max(0, ...)``), --sample 216 --seed 15 site 130.

    The end check's omnibus test uses "at most G/3 directions per group (G sweeps)" (``_unexplained``),
    but never fewer than one; with fewer than 3 sweeps it still runs and the end check says so: verdict
    'undecided', "cannot be checked: only G sweeps, too few to tell structure from noise".  One or two
    sweeps (one per load) are a legal record that ``diagnose`` takes.  The mutant gives every group
    G // 3 = 0 directions there, and the noise-model bootstrap of the empty groups fails with a
    ValueError traceback instead of a diagnosis.
    """
    grid = rig_grid(loads=loads, cambers_deg=(0.0,), pressures=(220e3,), points_per_sweep=25)
    case = make_case((), "iid", seed=5, grid=grid)
    dg = diagnose(case.data, rated_load=case.rated_load)
    un = dg.unexplained
    G = len(loads)
    assert un["verdict"] == "undecided" and not un["structure_found"]
    assert un["summary"].startswith(f"cannot be checked: only {G} sweeps, too few to tell structure from noise")
    assert all(g["directions"] >= 1 and 0 <= g["p_value"] <= 1 for g in un["omnibus_groups"].values())


@pytest.mark.parametrize("factor, words", [("fz", "changing with load"),
                                           ("pressure", "changing with inflation pressure")])
def test_a_misfit_that_grows_with_one_condition_is_put_down_to_that_condition(rig, factor, words):
    """engine.py [836] ``_condition_terms`` (``z = (level - mid) / half`` -> ``(level + mid) / half``),
    --sample 216 --seed 15 site 219.

    The misfit check's surface has, per condition factor, terms in "z in [-1, 1] per factor, z^2, pair
    products" (``_condition_terms``), and the summary says how much of the fitted surface belongs to
    each condition group (``_CONDITION_WORDS``: "changing with load", "... with inflation pressure").  A
    cornering-stiffness error that grows steadily with load (or with pressure) on the default rig (5
    loads, 3 cambers, 2 pressures) is a systematic misfit that other sweeps predict, and it is put down
    to that condition, first and for most of the surface.  The mutant's z is shifted off [-1, 1] (by
    2 x mid / half: +5 for the loads, +22 for the pressures): the load pattern is then put down to
    'combinations of the conditions' and pressure, and the ridge fit of the badly scaled pressure
    columns predicts almost none of a pressure misfit (called not systematic).
    """
    d, eng, u = rig.data, rig.eng, rig.u
    z = _level_z(d, factor)
    r = 10.0 * np.random.default_rng(1).standard_normal(d.n) + 40.0 * z * np.tanh(4.0 * u)
    floor = 10.0
    mf = _misfit(eng, _step(r, 2.0 * floor, None), floor, u, None)
    assert mf["checked"] and mf["systematic"] and mf["predictable_share"] >= MISFIT_SHARE
    first, share = next(iter(mf["components"].items()))
    assert first == factor and share > 0.5, mf["components"]
    text, _ = _misfit_text(mf, None)
    assert text.startswith("systematic misfit not explained by any catalogue effect: the model's curve shape")
    parts = text.split(" odd in slip; ", 1)[1]
    assert parts.split("; ")[0].split(" % ", 1)[1].startswith(words), text


def test_weaker_families_wait_until_the_strongest_is_refitted():
    """engine.py [600] ``_diagnose`` (``gain >= 0.25 * top`` -> ``gain >= 0.25 / top``), --sample 216 --seed 15
    site 422.

    Each round refits "the strongest families first: those within a factor 4 of the largest predicted
    error reduction ... the other families only if none of these is confirmed" (the comment in
    ``diagnose``).  A tyre with camber thrust and a fall of friction with load, diagnosed for one step
    (``max_steps=1``): camber's predicted gain is more than 4 x any other family's, camber is confirmed
    and accepted, and the significant load families (load_friction, overload) are left "significant, not
    refitted" (no held-out numbers).  The mutant's threshold is 0.25 / top, i.e. every family of the
    batch: they are refitted too and reported confirmed or not confirmed.
    """
    grid = rig_grid(points_per_sweep=25)
    case = make_case(["camber", "load_friction"], "iid", seed=5, grid=grid)
    dg = diagnose(case.data, rated_load=case.rated_load, max_steps=1)
    assert dg.accepted == ["camber"]
    sig = [c for c in dg.candidates.values() if c.round == 1 and c.p_adjusted < 0.05]
    gain: dict[str, float] = {}
    for c in sorted(sig, key=lambda c: -c.predicted_dssr):
        gain.setdefault(c.family, c.predicted_dssr)
    top = max(gain, key=gain.get)
    assert top == "camber"
    weak = {f for f, g in gain.items() if g < 0.25 * gain[top]}
    assert {"load_friction", "overload"} <= weak
    for c in sig:
        if c.family in weak:
            assert c.status == "significant, not refitted", (c.effect, c.status, c.reason)
            assert np.isnan(c.rmse_heldout)
        else:
            assert c.status != "significant, not refitted" and np.isfinite(c.rmse_heldout), (c.effect, c.status)
