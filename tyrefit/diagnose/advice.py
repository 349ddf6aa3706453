"""Experiment-design advice: which extra test would decide what these data leave open.

For every effect family the diagnosis could not settle, one entry says

* ``status``: ``untestable`` (the data cannot carry the family at all, e.g.
  shifts from one-sided sweeps, load laws from one load), ``ambiguous``
  (significant, but two families or variants explain it equally well, or the
  held-out evidence could not confirm it) or ``not detected`` (testable, not
  significant);
* ``why`` in words and ``test``: the extra test that would decide it, with
  levels computed from the data (which loads, cambers, pressures; both slip
  signs; a repeated sweep);
* ``detectable``: the smallest effect the present data detect with 80 %
  power at the 5 % level, per parameter, in the parameter's own unit and as
  the largest change of lateral force [N] the start model cannot mimic
  (:func:`~tyrefit.diagnose.stats.detectable_size`, from the score test of
  the last screening round, with its min-p critical value).

``needs_model`` names the tyre model that can carry a family PAC89 cannot
(pressure, speed: MF 6.1, ``--model mf61``).  Slip-ratio sweeps in the data
(drive/brake and combined slip) are not part of the lateral diagnosis; when
there are combined ones, an entry of family ``combined_slip`` with status
``beyond PAC89`` says so: PAC89 has no combined-slip terms, MF 6.1 has
(G_xa, G_yk, S_Vyk; ``tyrefit fit FILE --model mf61``).
"""

from __future__ import annotations

import numpy as np

from ..effects import EFFECTS, FAMILIES
from .stats import detectable_size

__all__ = ["MF61", "PEAK_SEARCH_DEG", "build_advice", "level_curve", "measured_peak", "needs_model", "peak_reach",
           "pushes"]

_DEG = np.pi / 180.0
#: the words for an effect PAC89 cannot carry and MF 6.1 can (the model ladder)
MF61 = "needs MF 6.1 (`--model mf61`)"


def needs_model(effect_id: str) -> str | None:
    """``MF61`` for an effect PAC89 has no input for and MF 6.1 carries (pressure, speed), else None."""
    return MF61 if EFFECTS[effect_id].extra.get("needs_model") == "mf61" else None


def _kn(x) -> str:
    return f"{x / 1e3:.1f} kN"


#: slip range [deg] searched for the fitted force peak
PEAK_SEARCH_DEG = 30.0


def level_curve(spec, theta, data, k: int, slip) -> tuple[np.ndarray, float, float]:
    """|Fy| [N] of the model at load level ``k`` over slip angles ``slip`` [rad] (>= 0).

    Evaluated on the slip side the level's sweeps reach further, at the level's median camber, pressure and
    speed.  Returns |Fy|, that side (+1 or -1) and the level's reach on it [rad].
    """
    x = data.inputs
    m = np.asarray(data.level_index["fz"]) == k
    sa = x.slip_angle[m]
    up, down = max(float(sa.max()), 0.0), max(float(-sa.min()), 0.0)
    side = 1.0 if up >= down else -1.0
    n = len(slip)

    def med(v):
        return None if v is None else np.full(n, float(np.median(v[m])))

    inp = x._replace(fz=np.full(n, float(data.levels["fz"][k])), slip_angle=side * np.asarray(slip),
                     camber=med(x.camber), pressure=med(x.pressure), speed=med(x.speed))
    return np.abs(spec.predict(theta, inp)), side, max(up, down)


#: bin width [deg] of |slip| in which the measured force is averaged to find a sweep's own peak
_PEAK_BIN_DEG = 0.5


def measured_peak(slip, force, min_reach_deg: float = 3.0) -> dict | None:
    """Where one side of a measured sweep peaks, from the data alone (no model).

    |F| is averaged in :data:`_PEAK_BIN_DEG` bins of |slip|; the sweep *peaked* when its largest bin
    mean lies inside the sweep (at most 85 % of its reach) and the force at the sweep's end has fallen
    below it by more than both 2 % of the peak and three standard errors of the two bin means (the
    scatter within the bins).  ``None`` for a side that reaches less than ``min_reach_deg``.

    Returns ``{"peaked", "peak_deg", "reach_deg", "drop"}`` (``drop``: fall from the peak to the end,
    as a fraction of the peak).
    """
    a = np.degrees(np.abs(np.asarray(slip, float)))
    f = np.abs(np.asarray(force, float))
    reach = float(a.max()) if a.size else 0.0
    if reach < min_reach_deg or a.size < 10:
        return None
    b = np.floor(a / _PEAK_BIN_DEG).astype(int)
    keys = np.unique(b)
    mean = np.array([f[b == k].mean() for k in keys])
    n = np.array([np.count_nonzero(b == k) for k in keys])
    var = np.array([f[b == k].var(ddof=1) if c > 1 else np.nan for k, c in zip(keys, n)])
    sd = np.sqrt(np.nanmedian(var)) if np.any(np.isfinite(var)) else 0.0
    se = sd / np.sqrt(n)
    j = int(np.argmax(mean))
    centre = (keys + 0.5) * _PEAK_BIN_DEG
    drop = mean[j] - mean[-1]
    peaked = bool(centre[j] <= 0.85 * reach and drop > max(0.02 * mean[j], 3.0 * np.hypot(se[j], se[-1])))
    return {"peaked": peaked, "peak_deg": float(centre[j]), "reach_deg": reach,
            "drop": float(drop / mean[j]) if mean[j] > 0 else 0.0}


def _measured_level_peak(data, k: int) -> dict:
    """The measured sweeps of load level ``k``: did most of their sides peak, and where (median)."""
    m = np.asarray(data.level_index["fz"]) == k
    sa, fy, sw = data.inputs.slip_angle[m], np.asarray(data.fy)[m], np.asarray(data.sweep)[m]
    sides = []
    for g in np.unique(sw):
        for sign in (1.0, -1.0):
            on = (sw == g) & (np.sign(sa) == sign)
            r = measured_peak(sa[on], fy[on])
            if r is not None:
                sides.append(r)
    peaked = [r for r in sides if r["peaked"]]
    ok = bool(sides) and 2 * len(peaked) > len(sides)
    return {"data_peaked": ok, "data_peak_deg": float(np.median([r["peak_deg"] for r in peaked])) if ok else None,
            "data_drop": float(np.median([r["drop"] for r in peaked])) if ok else None}


def peak_reach(spec, theta, data) -> list[dict]:
    """Per load level: where the measured sweeps peak, and the fitted model's peak against the sweeps' reach.

    The data decide first (:func:`measured_peak`): a level whose measured sweeps rise to a force peak and
    fall past it has its peak *measured* (``data_peaked``, ``data_peak_deg``), whatever the model does.
    Only where the data have not peaked is the fitted model asked: it is evaluated by :func:`level_curve` on
    0..:data:`PEAK_SEARCH_DEG` deg, and ``peak_deg`` is None when it still rises at the end of that range (a
    curve with no peak, as a brush model's).  ``reached``: the level's peak is in the data, measured or
    within the sweeps' reach.  A level short of its peak carries the peak force only as an extrapolation
    of the curve's shape, so there friction level and curvature are not measured apart.  Where the data
    peaked and the model's peak lies well beyond it (``model_misses_peak``), the miss is the model's.
    """
    grid = np.linspace(0.0, PEAK_SEARCH_DEG, 601) * _DEG
    out = []
    for k, fz in enumerate(np.asarray(data.levels["fz"], dtype=float)):
        if not np.any(np.asarray(data.level_index["fz"]) == k):
            continue
        f, _, reach = level_curve(spec, theta, data, k, grid)
        j = int(np.argmax(f))
        peak = None if j >= len(grid) - 1 else float(grid[j] / _DEG)
        meas = _measured_level_peak(data, k)
        model_ok = peak is not None and peak <= reach / _DEG
        out.append({"fz_N": float(fz), "peak_deg": peak, "reach_deg": float(reach / _DEG),
                    "reached": meas["data_peaked"] or model_ok, **meas,
                    "model_misses_peak": bool(meas["data_peaked"] and not model_ok)})
    return out


def _short_of_peak(peaks) -> tuple[list[dict], str]:
    """The load levels whose sweeps stop before the fitted peak, and a sentence saying so."""
    short = [p for p in peaks or [] if not p["reached"]]
    if not short:
        return [], ""
    where = ", ".join(_kn(p["fz_N"]) for p in short)
    at = "; ".join(f"{_kn(p['fz_N'])}: " + (f"peak at ~{p['peak_deg']:.0f} deg" if p["peak_deg"] is not None
                                             else f"no peak below {PEAK_SEARCH_DEG:.0f} deg")
                   + f", sweeps to {p['reach_deg']:.0f} deg" for p in short)
    return short, f"the sweeps at {where} stop before the fitted force peak ({at})"


def _test(family: str, d, cands, status: str, peaks=None) -> str:
    """The extra test that would decide ``family`` on data ``d`` (SweepData)."""
    s = d.summary
    fz = np.asarray(s.fz_levels, dtype=float)
    reach = s.slip_extent / _DEG
    lo, hi = fz.min(), fz.max()
    static = getattr(d, "static_pushes", False)  # static-rig pushes: one way each, slip converted with Eq. 1
    short, _ = _short_of_peak(peaks)
    if family in ("load_friction", "curvature_load") and len(fz) >= 2 and short:
        if all(p["peak_deg"] is not None for p in short):
            far = (f"to {'a converted slip' if static else '|slip|'} >= "
                   f"{min(1.3 * max(p['peak_deg'] for p in short), PEAK_SEARCH_DEG):.0f} deg")
        else:
            far = f"the fitted curve still rises at {PEAK_SEARCH_DEG:.0f} deg: as far as the rig and the tyre allow"
        what = "pushes carried past the static peak force" if static else "sweeps past the force peak"
        return (f"{what} ({far}) at {', '.join(_kn(p['fz_N']) for p in short)}: where the peak "
                "is measured, the peak force (friction) and the approach to it (curvature) are measured apart")
    if family == "load_friction":
        if len(fz) < 3:
            want = [0.5 * lo, 1.5 * lo] if len(fz) == 1 else [0.5 * (lo + hi), 1.3 * hi]
            return ("slip sweeps through the peak (|slip| >= 5 deg) at >= 3 loads: add loads at "
                    + " and ".join(_kn(v) for v in want))
        if reach < 5:
            return f"sweeps through the peak: extend the slip range to |slip| >= 8 deg (now {reach:.1f} deg)"
        if status == "ambiguous":
            return ("a sweep at a load between the tested ones and a repeat of the highest-load sweep: a smooth fall "
                    "of friction with load and a knee above the rated load differ between the levels")
        return ("repeat the sweeps at the lowest and the highest load: k repeats shrink the detectable size about "
                "1/sqrt(k)")
    if family == "curvature_load":
        if len(fz) < 2:
            return f"the same sweep at a second load (e.g. {_kn(1.6 * lo)}) reaching |slip| >= 8 deg"
        if reach < 6:
            return f"extend the sweeps past the peak to |slip| >= 8-10 deg (now {reach:.1f} deg) at >= 2 loads"
        return "sweeps past the peak (|slip| >= 10 deg) repeated at the lowest and the highest load"
    if family == "overload":
        r = s.rated_load
        if r is None:
            return "give the tyre's rated load (--rated-load NEWTONS, from its load index)"
        above = fz[fz > 1.02 * r]
        if len(above) == 0:
            return f"sweeps at 1.2 and 1.4 x the rated load ({_kn(1.2 * r)}, {_kn(1.4 * r)})"
        if len(above) == 1:
            extra = 0.5 * (r + above[0]) if above[0] > 1.25 * r else 1.15 * above[0]
            return (f"a second load above the rated load {_kn(r)} (e.g. {_kn(extra)}): with one level above it a "
                    "knee at the rating cannot be held out and checked, nor told from a smooth friction fall")
        return (f"a sweep just above the rated load ({_kn(1.1 * r)}) and a repeat of the highest-load sweep: "
                "they place the knee")
    if family == "camber":
        c = np.degrees(np.asarray(s.camber_levels, dtype=float))
        if len(c) < 3:
            return "the same sweeps at >= 3 camber angles, e.g. -4, 0, +4 deg (2 give thrust and shift only)"
        return "repeat the sweeps at the outer camber angles"
    if family == "offsets":
        if s.slip_reach < 1.0 * _DEG:
            both = ("pushes to both sides of the centred tyre (converted slip, e.g." if static
                    else "sweeps through zero in both slip directions (e.g.")
            return (f"{both} -{max(reach, 6):.0f} to +{max(reach, 6):.0f} deg): with one "
                    f"{'push direction' if static else 'slip sign'} a shift of the curve cannot be told from its "
                    "shape near zero; ply steer from conicity needs both mounting sides")
        if len(fz) < 2:
            return "the sweep through zero at a second load (load-dependent shifts); both mounting sides for ply steer"
        return "repeat the sweeps through zero (both directions) and test the tyre mounted the other way round"
    if family == "pressure":
        p = np.asarray(s.pressure_levels, dtype=float)
        p0 = float(np.median(p)) if len(p) else None
        return ("the same sweeps at a second inflation pressure"
                + (f" (e.g. {0.8 * p0 / 1e3:.0f} and {1.2 * p0 / 1e3:.0f} kPa)" if p0 else " (e.g. -20 % and +20 %)"))
    if family == "speed":
        if static:
            return "a dynamic-rig test at two speeds (e.g. 40 and 100 km/h): a static push does not roll"
        return "the same sweeps at a second speed (e.g. 40 and 100 km/h)"
    return "more sweeps"


def pushes(text: str) -> str:
    """``text`` with sweeps called pushes (static-rig data converted with Eq. 1: one push per load)."""
    return text.replace("sweeps", "pushes").replace("sweep", "push")


def _detectable(c, data) -> list[dict] | None:
    info = getattr(c, "info", None)
    if not info or not np.isfinite(getattr(c, "critical", np.nan)):
        return None
    byname = {p.name: p for p in EFFECTS[c.effect].params}
    sizes = detectable_size(info["fisher"], info["var"], c.critical)
    jmax = np.asarray(info["jmax"], dtype=float)
    params = [byname[n] for n in info.get("names", [])]
    out = []
    for p, b, jm in zip(params, sizes, jmax):
        out.append({"parameter": p.name, "unit": p.unit, "value": float(b) if np.isfinite(b) else None,
                    "force_N": float(b * jm) if np.isfinite(b) else None, "meaning": p.meaning})
    return out


def _rival_entry(r: dict, peaks) -> dict:
    """The advice entry of a rival family (see :func:`tyrefit.diagnose.engine._rivals`)."""
    acc, riv = r["accepted"], r["rival"]
    fa, fr = EFFECTS[acc].family, EFFECTS[riv].family
    why = (f"{riv} alone brings {100 * r['share']:.0f} % of the held-out improvement {acc} brought (held-out RMSE "
           f"{r['rmse_heldout_rival']:.1f} against {r['rmse_heldout_accepted']:.1f} N, round {r['round']}); it was not "
           f"added once {acc} was in, nor is {acc} confirmed on top of it ({r['accepted_over_rival']}): these data "
           f"cannot tell {fr} from {fa}; {acc} predicted the held-out sweeps better and was added")
    _, short = _short_of_peak(peaks)
    if short and {fa, fr} == {"load_friction", "curvature_load"}:
        why += (f"; {short}: there the peak force is an extrapolation of the curve's shape, so a fall of friction "
                "with load and a change of curvature with load bend the measured part of the curves alike")
    return {"effect": riv, "family": fr, "status": "ambiguous", "why": why, "rival_of": acc,
            "share": r["share"]}


def build_advice(data, cands: dict, accepted: list[str], settings, level: float | None = None,
                 rivals: list[dict] | None = None, peaks: list[dict] | None = None) -> list[dict]:
    """Advice entries (see the module docstring), one per effect family not settled by the diagnosis.

    ``level`` is the screening's level (default ``settings.alpha``): the detectable sizes are at it.
    ``rivals`` (from the engine): families that explain nearly what an accepted effect explains and were
    not accepted; each is reported ``ambiguous`` with the accepted one.  ``peaks``
    (:func:`peak_reach`): whether each load's sweeps pass the fitted force peak, for the tests named.
    """
    level = settings.alpha if level is None else level
    rival_of = {EFFECTS[r["rival"]].family: r for r in sorted(rivals or [], key=lambda r: r["share"])}
    acc_fams = {EFFECTS[a].family for a in accepted}
    start_fams = {c.family for c in cands.values() if c.status == "in start model"}
    out = []
    for fam, ids in FAMILIES.items():
        cs = [cands[i] for i in ids]
        statuses = {c.status for c in cs}
        entry = None
        if fam in rival_of and fam not in acc_fams | start_fams:
            entry = _rival_entry(rival_of[fam], peaks)
        elif fam in acc_fams | start_fams:
            tied = [c for c in cs if c.status == "variant not distinguishable"]
            r = data.summary.rated_load
            above = [f for f in data.summary.fz_levels if r is not None and f > 1.02 * r]
            if fam == "overload" and len(above) == 1 and fam in acc_fams:
                chosen = next(a for a in accepted if EFFECTS[a].family == fam)
                entry = {"effect": chosen, "family": fam, "status": "ambiguous",
                         "why": (f"accepted on one load level above the rated load ({above[0] / 1e3:.1f} kN): the "
                                 "sweeps below the rating do not follow that one, but no held-out level checks a "
                                 "knee at the rating against another law (or a fault of that one sweep)")}
            elif tied:
                chosen = next(a for a in accepted if EFFECTS[a].family == fam)
                entry = {"effect": chosen, "family": fam, "status": "ambiguous",
                         "why": (f"variants {', '.join([chosen] + [c.effect for c in tied])} fit the held-out sweeps "
                                 f"within the practical margin; the simplest ({chosen}) was added")}
        elif statuses == {"not testable with these data"}:
            c = cs[0]
            why = c.reason
            if len(data.summary.fz_levels) == 1 and fam in ("load_friction", "curvature_load", "offsets"):
                why += ("; with one load a law in load is a constant, which the base coefficients (a2, a7, the "
                        "shifts' constant parts) already are: the family cannot be told apart from them")
            if fam == "offsets" and getattr(data, "static_pushes", False):
                why = (f"static pushes go one way from the centred tyre (converted slip "
                       f"{round(data.summary.slip_min / _DEG, 1) + 0.0:.1f} to {data.summary.slip_max / _DEG:.1f} deg): a shift needs both sides")
            entry = {"effect": c.effect, "family": fam, "status": "untestable", "why": why}
        else:
            unconf = [c for c in cs if c.status in ("significant but not confirmed", "confirmed, not added")]
            if unconf:
                c = unconf[0]
                entry = {"effect": c.effect, "family": fam, "status": "ambiguous",
                         "why": f"significant in the score test but not added: {c.reason}"}
            else:
                tested = sorted((c for c in cs if c.status == "not significant"),
                                key=lambda c: len(EFFECTS[c.effect].params))
                if tested:
                    c = tested[0]
                    entry = {"effect": c.effect, "family": fam, "status": "not detected",
                             "why": c.reason}
        if entry is None:
            continue
        entry["test"] = _test(fam, data, cands, entry["status"], peaks)
        if getattr(data, "static_pushes", False):
            entry["why"], entry["test"] = pushes(entry["why"]), pushes(entry["test"])
        entry["detectable"] = _detectable(cands[entry["effect"]], data) if entry["status"] != "untestable" else None
        entry["power"] = 0.8
        entry["level"] = level
        entry["needs_model"] = needs_model(entry["effect"])
        out.append(entry)
    sr = getattr(data, "slip_ratio_sweeps", None)
    if sr and sr.get("combined_sweeps"):
        ang = ", ".join(f"{a / _DEG:g}" for a in sr["slip_angles"])
        out.append({"effect": "combined_slip", "family": "combined_slip", "status": "beyond PAC89",
                    "why": (f"{sr['combined_sweeps']} combined-slip sweeps (slip ratio swept at slip angle {ang} deg) "
                            "are in the data: the lateral force falls and the aligning moment changes under drive "
                            "and brake slip, which PAC89 (pure slip only) cannot carry"),
                    "test": ("fit the file with --model mf61: the combined-slip weighting functions G_xa, G_yk and "
                             "S_Vyk (Pacejka 2012, 4.E50-4.E67) are fitted from these sweeps"),
                    "detectable": None, "power": 0.8, "level": level, "needs_model": MF61})
    return out


def advice_lines(advice: list[dict]) -> list[str]:
    """One line per entry for the terminal and the report."""
    lines = []
    for a in advice:
        det = ""
        if a.get("detectable"):
            parts = [f"{d['parameter']} {d['value']:.3g} {d['unit']} (~{d['force_N']:.0f} N)"
                     for d in a["detectable"] if d["value"] is not None]
            if parts:
                det = f"; smallest detectable (80 % power, {100 * a['level']:g} % level): " + ", ".join(parts)
        lines.append(f"{a['family']} [{a['status']}]: {a['why']}; to decide: {a['test']}{det}"
                     + (f"; {a['needs_model']}" if a.get("needs_model") else ""))
    return lines
