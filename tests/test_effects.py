"""Effect catalogue: registry, neutral values (bit for bit), PAC89 mapping, physics, testability."""

import numpy as np
import pytest

from tyrefit.effects import (BASE_NAMES, EFFECTS, FAMILIES, DataSummary, ModelInputs, coefficients, get_effect,
                             lateral_force, overload_factor, parse_effects, relative_factor, resolve_pac89)
from tyrefit.effects.signatures import SIGNATURES, SignatureView, sweep_characteristics
from tyrefit.errors import DataError
from tyrefit.models import pac89

DEG = np.pi / 180

BASE = {"a0": 1.45, "a2": 1100.0, "a3": 1500.0, "a4": 8.0, "a7": -0.3}
SIZES = {"a1": -25.0, "a5": 0.01, "a6": -0.08, "a8": 0.05, "a9": 0.02, "a10": 0.15, "a11": 15.0, "a12": 8.0,
         "a13": 60.0, "overload_mu": 0.45, "overload_ky": 0.3, "pressure_ky": 0.5, "pressure_mu": -0.3,
         "speed_mu": -0.12, "speed_ky": 0.05}


def grid(n=400, seed=0):
    rng = np.random.default_rng(seed)
    return ModelInputs(fz=rng.uniform(1500, 9000, n), slip_angle=rng.uniform(-14, 14, n) * DEG,
                       camber=rng.choice([-4.0, 0.0, 2.0, 4.0], n) * DEG, pressure=rng.choice([200e3, 230e3, 260e3], n),
                       speed=rng.choice([40 / 3.6, 100 / 3.6], n), rated_load=6000.0, pressure_ref=230e3,
                       speed_ref=100 / 3.6, fz_ref=4500.0)


def test_required_families_and_ids():
    for fam in ("load_friction", "overload", "camber", "offsets", "pressure", "curvature_load"):
        assert fam in FAMILIES
    for eid, e in EFFECTS.items():
        assert eid == e.id and eid.startswith(e.family)
    assert set(get_effect("camber").param_names) == {"a5", "a8", "a11"}
    assert set(get_effect("offsets").param_names) == {"a9", "a10", "a12", "a13"}
    assert get_effect("load_friction").param_names == ("a1",)
    assert BASE_NAMES == ("a0", "a2", "a3", "a4", "a7")


@pytest.mark.parametrize("eid", list(EFFECTS))
def test_every_effect_is_documented(eid):
    e = EFFECTS[eid]
    for field in ("what", "size", "test", "vehicle"):
        assert len(getattr(e.card, field)) > 20
    assert e.card.sources and e.needs and e.pac89_note
    assert e.signature in SIGNATURES
    for p in e.params:
        lo, hi = p.bounds
        assert lo <= p.neutral <= hi
        assert lo <= p.plausible[0] <= p.plausible[1] <= hi
        assert p.scale > 0 and p.unit and p.meaning
    if e.representable:
        assert set(e.pac89) == set(e.param_names)
    else:
        assert "not representable in PAC89" in e.pac89_note


def test_cards_cite_the_papers():
    assert "Komana et al." in get_effect("overload").card.sources[0]
    assert "4250" in get_effect("overload").card.size
    cam = " ".join(get_effect("camber").card.sources)
    assert "Zhang et al. 2024" in cam and "tyrefit.models.brush" in cam
    assert "Eq. 19" in get_effect("camber").card.what


_PREVIOUS = [(), ("load_friction", "camber"), ("pressure", "overload", "offsets"), ("speed", "curvature_load")]
# every effect on top of every previous model that does not already hold a variant of its family
_PAIRS = [(eid, prev) for eid in EFFECTS for prev in _PREVIOUS
          if all(EFFECTS[p].family != EFFECTS[eid].family for p in prev)]


@pytest.mark.parametrize("eid,previous", _PAIRS)
def test_neutral_gives_back_previous_model_bit_for_bit(eid, previous):
    e = EFFECTS[eid]
    x = grid()
    values = dict(BASE)
    for p in previous:
        values.update({n: SIZES[n] for n in EFFECTS[p].param_names})
    before = lateral_force(values, previous, x)
    with_neutral = dict(values)
    carried = {n for p in previous for n in EFFECTS[p].param_names}  # a shared term (a1) is one parameter
    with_neutral.update({n: v for n, v in e.neutral.items() if n not in carried})
    after = lateral_force(with_neutral, list(previous) + [eid], x)
    assert before.tobytes() == after.tobytes()


def test_start_model_is_pac89_exactly():
    x = grid()
    ours = lateral_force(BASE, [], x)
    ref = pac89.lateral_force({**{f"a{i}": 0.0 for i in range(14)}, **BASE}, x.fz, x.slip_angle, x.camber)
    assert ours.tobytes() == ref.tobytes()


@pytest.mark.parametrize("eid", [e for e in EFFECTS if EFFECTS[e].representable])
def test_representable_effects_are_the_pac89_coefficients(eid):
    x = grid()
    v = dict(BASE, **{n: SIZES[n] for n in EFFECTS[eid].param_names})
    ref = pac89.lateral_force({**{f"a{i}": 0.0 for i in range(14)}, **v}, x.fz, x.slip_angle, x.camber)
    np.testing.assert_array_equal(lateral_force(v, [eid], x), ref)


def test_overload_is_a_hinge_at_the_rated_load():
    x = grid()
    v = dict(BASE, overload_mu=0.45)
    below = x.fz <= 0.9 * x.rated_load  # the knee is rounded over +-10 % of the rated load
    base = lateral_force(BASE, [], x)
    ov = lateral_force(v, ["overload"], x)
    np.testing.assert_array_equal(ov[below], base[below])
    assert np.all(np.abs(ov[~below & (np.abs(x.slip_angle) > 8 * DEG)]) <
                  np.abs(base[~below & (np.abs(x.slip_angle) > 8 * DEG)]))
    # D scales by exactly the factor: compare with a2 scaled point by point
    m = overload_factor(x.fz, 6000.0, 0.45)
    ref = pac89.lateral_force({**{f"a{i}": 0.0 for i in range(14)}, **BASE, "a2": BASE["a2"] * m},
                              x.fz, x.slip_angle, x.camber)
    np.testing.assert_allclose(ov, ref, rtol=0, atol=1e-9)
    assert overload_factor(9000.0, 6000.0, 0.45) == pytest.approx(1 - 0.45 * 0.5)
    # the rounded knee: C1 at both ends of the blend, a quarter of the blend width at the rated load
    w = 600.0
    assert overload_factor(6000.0, 6000.0, 1.0) == pytest.approx(1 - (w / 4) / 6000.0)
    for f0 in (5400.0, 6600.0):
        lo, hi = overload_factor(np.array([f0 - 1e-3, f0 + 1e-3]), 6000.0, 1.0)
        d = (hi - lo) / 2e-3
        assert d == pytest.approx(0.0 if f0 < 6000 else -1 / 6000.0, abs=1e-8)


def test_overload_knee_width_moves_where_the_loss_starts():
    fr = 6000.0
    # the default rounding is the fitted variant at half-width 0.1, bit for bit
    fz = np.linspace(3000.0, 9000.0, 61)
    np.testing.assert_array_equal(overload_factor(fz, fr, 0.45), overload_factor(fz, fr, 0.45, 0.1))
    for w in (0.05, 0.3):
        m = overload_factor(fz, fr, 0.45, w)
        assert np.all(m[fz <= fr * (1 - w)] == 1.0) and np.all(m[fz > fr * (1 - w) + 1.0] < 1.0)
        above = fz >= fr * (1 + w)  # past the knee: the same straight loss whatever the width
        np.testing.assert_allclose(m[above], 1 - 0.45 * (fz[above] - fr) / fr, rtol=0, atol=1e-12)
        # C1 at both ends of the blend, w/4 of the loss at the rated load
        assert overload_factor(fr, fr, 1.0, w) == pytest.approx(1 - w / 4)
        for f0, slope in ((fr * (1 - w), 0.0), (fr * (1 + w), -1 / fr)):
            lo, hi = overload_factor(np.array([f0 - 1e-3, f0 + 1e-3]), fr, 1.0, w)
            assert (hi - lo) / 2e-3 == pytest.approx(slope, abs=1e-8)
    # the catalogue entry scales D by that factor
    x = grid()
    v = dict(BASE, overload_mu=0.45, overload_width=0.3)
    m = overload_factor(x.fz, 6000.0, 0.45, 0.3)
    ref = pac89.lateral_force({**{f"a{i}": 0.0 for i in range(14)}, **BASE, "a2": BASE["a2"] * m},
                              x.fz, x.slip_angle, x.camber)
    np.testing.assert_allclose(lateral_force(v, ["overload_knee"], x), ref, rtol=0, atol=1e-9)
    assert get_effect("overload_knee").family == "overload"


def test_cubic_friction_and_curved_curvature_laws():
    x = grid()
    dfz = (x.fz - x.fz_ref) / x.fz_ref
    zero = {f"a{i}": 0.0 for i in range(14)}
    # D (1 + q dfz^2 + r dfz^3): a2 and a1 scaled point by point
    v = dict(BASE, a1=-20.0, load_friction_q=0.1, load_friction_r=-0.2)
    m = 1 + 0.1 * dfz**2 - 0.2 * dfz**3
    ref = pac89.lateral_force({**zero, **BASE, "a1": -20.0 * m, "a2": BASE["a2"] * m}, x.fz, x.slip_angle, x.camber)
    np.testing.assert_allclose(lateral_force(v, ["load_friction_cubic"], x), ref, rtol=0, atol=1e-9)
    # r = 0 is the curved law exactly
    np.testing.assert_array_equal(lateral_force(dict(v, load_friction_r=0.0), ["load_friction_cubic"], x),
                                  lateral_force(dict(v, load_friction_r=0.0), ["load_friction_curved"], x))
    # E = a6 Fz + a7 + c dfz^2: a7 moved point by point
    v = dict(BASE, a6=-0.05, curvature_q=0.4)
    ref = pac89.lateral_force({**zero, **BASE, "a6": -0.05, "a7": BASE["a7"] + 0.4 * dfz**2},
                              x.fz, x.slip_angle, x.camber)
    np.testing.assert_allclose(lateral_force(v, ["curvature_load_curved"], x), ref, rtol=0, atol=1e-9)
    assert get_effect("curvature_load_curved").family == "curvature_load"
    # what a PAC89 .tir keeps of them: the straight laws (a1, a6), never nothing
    from tyrefit.diagnose.engine import pac89_effects
    assert pac89_effects(["load_friction_cubic", "curvature_load_curved", "overload_knee"]) == [
        "load_friction", "curvature_load"]
    assert get_effect("load_friction_cubic").family == "load_friction"


def test_pressure_scales_cornering_stiffness_and_peak():
    fz = np.full(3, 4000.0)
    p = np.array([200e3, 230e3, 260e3])
    v = dict(BASE, pressure_ky=0.5, pressure_mu=-0.3)

    def fy(a):
        x = ModelInputs(fz=fz, slip_angle=np.full(3, a), camber=np.zeros(3), pressure=p, pressure_ref=230e3)
        return lateral_force(v, ["pressure"], x)

    h = 1e-6
    stiff = -(fy(h) - fy(-h)) / (2 * h)
    np.testing.assert_allclose(stiff / stiff[1], relative_factor(p, 230e3, 0.5), rtol=1e-6)
    coef = coefficients(v, ["pressure"], ModelInputs(fz=fz, slip_angle=np.zeros(3), camber=np.zeros(3),
                                                     pressure=p, pressure_ref=230e3))
    np.testing.assert_allclose(coef["a2"] / BASE["a2"], 1 - 0.3 * (p - 230e3) / 230e3)


def test_camber_symmetries():
    a = np.linspace(-12, 12, 49) * DEG
    fz = np.full_like(a, 5000.0)
    for g in (2 * DEG, 4 * DEG):
        pos = ModelInputs(fz=fz, slip_angle=a, camber=np.full_like(a, g))
        neg = ModelInputs(fz=fz, slip_angle=-a, camber=np.full_like(a, -g))
        thrust = dict(BASE, a8=0.05, a11=15.0)
        # thrust and shift are odd in (slip, camber) together
        np.testing.assert_allclose(lateral_force(thrust, ["camber_thrust"], pos),
                                   -lateral_force(thrust, ["camber_thrust"], neg), atol=1e-9)
        # the stiffness loss a5 |gamma| is even in camber
        loss = dict(BASE, a5=0.01)
        same = ModelInputs(fz=fz, slip_angle=a, camber=np.full_like(a, -g))
        np.testing.assert_array_equal(lateral_force(loss, ["camber"], pos), lateral_force(loss, ["camber"], same))
    # camber thrust at zero slip: Sv = a11 Fz gamma (PAC89 sign) -> ISO-W -Sv, plus the shift
    x0 = ModelInputs(fz=np.array([5000.0]), slip_angle=np.zeros(1), camber=np.array([3 * DEG]))
    f = lateral_force(dict(BASE, a11=15.0), ["camber_thrust"], x0)
    assert f[0] == pytest.approx(-15.0 * 5.0 * 3.0, rel=1e-12)


def test_missing_condition_is_a_clear_error():
    x = ModelInputs(fz=np.array([4000.0]), slip_angle=np.zeros(1), camber=np.zeros(1))
    with pytest.raises(DataError, match="pressure"):
        lateral_force(dict(BASE, pressure_ky=0.1), ["pressure"], x)
    with pytest.raises(DataError, match="rated_load"):
        lateral_force(dict(BASE, overload_mu=0.1), ["overload"], x)


def test_resolve_pac89():
    vary, notes = resolve_pac89([])
    assert vary == ["a0", "a2", "a3", "a4", "a7"] and notes == []
    vary, notes = resolve_pac89(["camber", "offsets"])
    assert vary == ["a0", "a2", "a3", "a4", "a5", "a7", "a8", "a9", "a10", "a11", "a12", "a13"] and notes == []
    vary, notes = resolve_pac89(["overload"])
    assert "a1" in vary and len(notes) == 1 and "a1" in notes[0] and "knee" in notes[0]
    vary, notes = resolve_pac89(["pressure", "load_friction"])
    assert vary == ["a0", "a1", "a2", "a3", "a4", "a7"]
    assert notes[0].startswith("pressure:") and "per pressure" in notes[0] and "MF 6" in notes[0]
    with pytest.raises(DataError, match="did you mean 'camber'"):
        resolve_pac89(["cambr"])


def test_parse_effects():
    assert parse_effects("camber, pressure,camber") == ["camber", "pressure"]
    assert parse_effects(None) == [] and parse_effects("") == []
    with pytest.raises(DataError, match="unknown effect 'presure'.*did you mean 'pressure'"):
        parse_effects("presure")


def test_testability_rules():
    deg = DEG
    rich = DataSummary(fz_levels=(2e3, 4e3, 6e3, 7e3, 8e3), camber_levels=(-3 * deg, 0.0, 3 * deg),
                       pressure_levels=(2e5, 2.4e5), speed_levels=(16.7,), slip_min=-12 * deg, slip_max=12 * deg,
                       rated_load=6500.0)
    ok = {e: EFFECTS[e].why_not_testable(rich) for e in EFFECTS}
    assert all(ok[e] is None for e in EFFECTS if e not in ("speed", "load_friction_cubic"))
    assert "speed" in ok["speed"]
    assert "6 load levels" in ok["load_friction_cubic"]  # held out in turn, 5 levels must carry 4 terms
    assert EFFECTS["load_friction_cubic"].why_not_testable(
        DataSummary(fz_levels=(2e3, 3.2e3, 4.4e3, 5.6e3, 6.8e3, 8e3), slip_min=-12 * deg, slip_max=12 * deg)) is None
    poor = DataSummary(fz_levels=(4e3, 6e3), camber_levels=(0.0, 2 * deg), slip_min=0.0, slip_max=4 * deg)
    why = {e: EFFECTS[e].why_not_testable(poor) for e in EFFECTS}
    assert "3 load levels" in why["load_friction"]
    assert "rated load" in why["overload"]
    assert "3 camber levels" in why["camber"] and why["camber_thrust"] is None
    assert "both directions" in why["offsets_constant"]
    assert "pressure" in why["pressure"]
    no_over = DataSummary(fz_levels=(2e3, 4e3, 6e3), slip_min=-12 * deg, slip_max=12 * deg, rated_load=7000.0)
    assert "above the rated load" in EFFECTS["overload"].why_not_testable(no_over)
    one_over = DataSummary(fz_levels=(2e3, 4e3, 6e3, 8e3), slip_min=-12 * deg, slip_max=12 * deg, rated_load=6500.0)
    assert "2 load levels above the rated load" in EFFECTS["overload"].why_not_testable(one_over)


def test_sweep_characteristics_recover_model_values():
    a = np.linspace(-12, 12, 97) * DEG
    fz = np.full_like(a, 4000.0)
    x = ModelInputs(fz=fz, slip_angle=a, camber=np.zeros_like(a))
    v = dict(BASE, a13=50.0)
    fy = lateral_force(v, ["offsets_constant"], x)
    ch = sweep_characteristics(np.zeros_like(a, dtype=int), fz, a, fy)
    bcd = 1500.0 * np.sin(2 * np.arctan(4.0 / 8.0))  # N/deg
    assert ch["stiffness"].iloc[0] * DEG == pytest.approx(bcd, rel=0.02)
    assert ch["fy0"].iloc[0] == pytest.approx(-50.0, abs=3.0)
    assert ch["peak_mu"].iloc[0] == pytest.approx(1.1, rel=0.03)


def test_signature_plot_returns_axes():
    import matplotlib.pyplot as plt

    rng = np.random.default_rng(1)
    rows = []
    for k, (f, c) in enumerate([(f, c) for f in (3e3, 5e3) for c in (-3, 0, 3)]):
        a = np.linspace(-12, 12, 49) * DEG
        x = ModelInputs(fz=np.full_like(a, f), slip_angle=a, camber=np.full_like(a, c * DEG))
        rows.append((k, x, lateral_force(dict(BASE, a11=15.0), ["camber_thrust"], x)))
    sw = np.concatenate([np.full(49, k) for k, _, _ in rows])
    fz = np.concatenate([x.fz for _, x, _ in rows])
    al = np.concatenate([x.slip_angle for _, x, _ in rows])
    cam = np.concatenate([x.camber for _, x, _ in rows])
    fy = np.concatenate([y for _, _, y in rows])
    d = sweep_characteristics(sw, fz, al, fy + rng.normal(0, 5, len(fy)), cam)
    view = SignatureView(d, sweep_characteristics(sw, fz, al, 0 * fy, cam), sweep_characteristics(sw, fz, al, fy, cam))
    ax = get_effect("camber").plot_signature(view)
    assert ax.get_xlabel() == "camber [deg]"
    plt.close("all")


# --- camber_brush: the camber brush model's thrust (Zhang et al., Eq. 17-22) -----------------
def test_camber_brush_is_a_documented_camber_variant():
    e = get_effect("camber_brush")
    assert e.family == "camber" and e.param_names == ("camber_brush_k", "camber_brush_n")
    assert e.neutral == {"camber_brush_k": 0.0, "camber_brush_n": 0.0}
    assert not e.representable and set(e.pac89_approx) == {"a8", "a11"}
    src = " ".join(e.card.sources)
    assert "Zhang et al. 2024" in src and "17-22" in src and "tyrefit.models.brush" in src
    assert e.signature == "camber_stiffness_vs_fz"
    few = DataSummary(fz_levels=(3e3, 5e3), camber_levels=(0.0, 3 * DEG))
    assert "3 camber levels" in e.why_not_testable(few)
    one_load = DataSummary(fz_levels=(4e3,), camber_levels=(-3 * DEG, 0.0, 3 * DEG))
    assert "2 load levels" in e.why_not_testable(one_load)
    assert e.why_not_testable(DataSummary(fz_levels=(3e3, 5e3), camber_levels=(-3 * DEG, 0.0, 3 * DEG))) is None
    vary, notes = resolve_pac89(["camber_brush"])
    assert {"a8", "a11"} <= set(vary) and notes[0].startswith("camber_brush:")


def test_camber_brush_zero_slip_thrust_is_eq20_with_the_fz_power_law():
    fz = np.array([2000.0, 4000.0, 8000.0])
    g = np.array([2.0, -4.0, 6.0]) * DEG
    x = ModelInputs(fz=fz, slip_angle=np.zeros(3), camber=g)
    k, n = 8.0, 0.4
    d = lateral_force(dict(BASE, camber_brush_k=k, camber_brush_n=n), ["camber_brush"], x) - lateral_force(BASE, [], x)
    kyg = k * (fz / 1e3) ** (1.5 + n) / DEG  # N/rad
    np.testing.assert_allclose(d, -kyg * np.sin(g), rtol=1e-12)  # Zhang et al. Eq. 20: Fy = -K_yg sin(gamma)


def test_camber_brush_fades_to_nothing_where_the_patch_slides():
    from tyrefit.effects.catalogue import brush_camber_fade

    a = np.linspace(-14, 14, 113) * DEG
    fz = np.full_like(a, 5000.0)
    x = ModelInputs(fz=fz, slip_angle=a, camber=np.full_like(a, 4 * DEG))
    v = dict(BASE, camber_brush_k=10.0)
    diff = lateral_force(v, ["camber_brush"], x) - lateral_force(BASE, [], x)
    bcd = BASE["a3"] * np.sin(2 * np.arctan(5.0 / BASE["a4"]))  # N/deg
    d = BASE["a2"] * 5.0
    a_sl = np.arctan(3 * d / (bcd / DEG))  # full sliding of a parabolic-pressure brush
    beyond = np.abs(a) >= a_sl
    assert beyond.any() and np.all(np.abs(diff[beyond]) < 1e-9)
    assert np.all(np.abs(diff[np.abs(a) < a_sl]) > 0)
    # the thrust fades monotonically with |slip| from its zero-slip value
    w = brush_camber_fade(a, bcd, d)
    assert w[56] == 1.0 and np.all(np.diff(w[56:]) <= 0) and np.all(w >= 0)


def test_camber_brush_fade_is_the_brush_kernel_camber_term():
    """Against tyrefit.models.brush: Fiala's brush (parabolic pressure, lambda_x = 0) with a small camber."""
    from tyrefit.effects.catalogue import brush_camber_fade
    from tyrefit.models import brush as bm

    fz, a, re, k, mu = 4000.0, 0.07, 0.3, 4e7 * 0.15, 0.9
    ky, kyg = 2 * a**2 * k, 2 * a**3 * k / (3 * re)  # Eq. 20
    alpha = np.linspace(0, 12, 49) * DEG
    g = 1e-4
    f0 = bm.brush_kernel(fz, a, re, k, k, 0.0, 0.0, np.tan(alpha), 0.0, mu)[1]
    fg = bm.brush_kernel(fz, a, re, k, k, 0.0, 0.0, np.tan(alpha), g, mu)[1]
    share = (fg - f0) / (-kyg * np.sin(g))
    # PAC89 units: BCD [N/deg] = K_y [N/rad] * DEG, D = mu Fz
    np.testing.assert_allclose(share, brush_camber_fade(alpha, ky * DEG, mu * fz), atol=2e-3)


def test_camber_brush_reads_the_factors_after_every_scaling():
    x = grid()
    v = dict(BASE, camber_brush_k=8.0, camber_brush_n=0.3, pressure_ky=0.5, pressure_mu=-0.3)
    a = lateral_force(v, ["camber_brush", "pressure"], x)
    b = lateral_force(v, ["pressure", "camber_brush"], x)
    assert a.tobytes() == b.tobytes()


def test_camber_stiffness_characteristic_and_its_signature():
    import matplotlib.pyplot as plt

    a = np.linspace(-12, 12, 49) * DEG
    rows = []
    for k, (f, c) in enumerate([(f, c) for f in (3e3, 6e3) for c in (-3, 0, 3)]):
        x = ModelInputs(fz=np.full_like(a, f), slip_angle=a, camber=np.full_like(a, c * DEG))
        rows.append((k, x, lateral_force(dict(BASE, camber_brush_k=8.0), ["camber_brush"], x)))
    sw = np.concatenate([np.full(a.size, k) for k, _, _ in rows])
    fz, al, cam, fy = (np.concatenate(v) for v in zip(*[(x.fz, x.slip_angle, x.camber, y) for _, x, y in rows]))
    ch = sweep_characteristics(sw, fz, al, fy, cam)
    assert ch.loc[ch["camber"] == 0, "camber_stiffness"].isna().all()
    cs = ch[ch["camber"] != 0]
    # K_yg = k Fz^1.5 per degree (Eq. 20 law of the variant), from the local line through zero slip
    np.testing.assert_allclose(cs["camber_stiffness"], 8.0 * (cs["fz"] / 1e3) ** 1.5, rtol=0.02)  # fade within 1 deg
    fy0 = lateral_force(BASE, [], ModelInputs(fz=fz, slip_angle=al, camber=cam))
    base = sweep_characteristics(sw, fz, al, fy0, cam)
    ax = get_effect("camber_brush").plot_signature(SignatureView(ch, base, ch))
    assert ax.get_xlabel() == "normal load Fz [kN]" and "camber stiffness" in ax.get_ylabel()
    assert not any("0 deg" in t.get_text() and "-" not in t.get_text() for t in ax.get_legend().get_texts())
    plt.close("all")
