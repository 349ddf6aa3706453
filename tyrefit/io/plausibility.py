"""Is the tyre in the file mirrored?  Sign checks a fit cannot make for itself.

A channel whose sign is flipped (a camber column negated by a rig's set-up, an aligning
moment logged with the wrong sign, a drive/brake Fx inverted) gives a model that fits the
data well and is wrong: tyrefit would write a tyre whose camber thrust pushes away from the
lean, whose pneumatic trail is negative, or that brakes when it drives.  These checks look at
the data in ISO-W (after the reader's sign conversion), where a normal tyre has

* **camber thrust** with the sign of the cornering stiffness: dFy/dgamma and dFy/dalpha both
  negative (a tyre pushes towards the side it leans to, as it pushes against its slip angle);
* **pneumatic trail** t = -(dMz/dalpha) / (dFy/dalpha) positive near zero slip: the aligning
  moment turns the wheel back towards zero slip (checked per load level; "mirrored" when the
  trail is negative at more than half of them);
* **Fx rising with slip ratio** near zero: a driving (positive) slip ratio gives a positive Fx.

Each check measures, near zero slip, per sweep, and reports only a clear contradiction (many
sweeps agreeing, an effect well above the sweeps' scatter).  :func:`mirrored_findings` returns
the findings; :func:`check_mirrored` refuses them (one line) unless they are allowed
(``--allow-mirrored``), and then returns them as warnings.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pandas as pd

from ..errors import ValueRangeError, option
from .levels import group_levels

__all__ = ["Finding", "mirrored_findings", "check_mirrored", "camber_thrust", "pneumatic_trail", "fx_slip_slope"]

_DEG = np.pi / 180.0
#: the slip range taken as "near zero" for the slopes [rad] and [-]
SMALL_ALPHA = 2.5 * _DEG
SMALL_KAPPA = 0.04
#: a camber thrust counts when the sweeps' intercepts change with camber by at least this share of Fz per
#: degree, with a t statistic over 4
MIN_CAMBER_MU_PER_DEG = 0.004


@dataclass
class Finding:
    check: str       # 'camber_thrust', 'pneumatic_trail', 'fx_slip'
    message: str


def _line(x: np.ndarray, y: np.ndarray) -> tuple[float, float, float] | None:
    """(intercept, slope, slope standard error) of a least-squares line, or None."""
    if x.size < 3 or np.ptp(x) <= 0:
        return None
    xm, ym = x.mean(), y.mean()
    sxx = float(((x - xm) ** 2).sum())
    b = float(((x - xm) * (y - ym)).sum() / sxx)
    a = float(ym - b * xm)
    r = y - a - b * x
    se = float(np.sqrt(max((r ** 2).sum(), 0.0) / max(x.size - 2, 1) / sxx))
    return a, b, se


def _per_sweep(df: pd.DataFrame, var: str, chans: tuple[str, ...], small: float, min_span: float) -> pd.DataFrame:
    """Per sweep near zero ``var``: intercept and slope of each channel, median fz and camber."""
    rows = []
    for run, g in df.groupby("run", sort=True):
        x = g[var].to_numpy(float)
        sel = np.abs(x) <= small
        if sel.sum() < 4 or np.ptp(x[sel]) < min_span:
            continue
        row = {"run": run, "fz": float(g["fz"].median()) if "fz" in g else np.nan,
               "camber": float(g["camber"].median()) if "camber" in g else 0.0}
        ok = True
        for c in chans:
            fit = _line(x[sel], g[c].to_numpy(float)[sel])
            if fit is None:
                ok = False
                break
            row[f"{c}_0"], row[f"{c}_slope"], row[f"{c}_se"] = fit
        if ok:
            rows.append(row)
    return pd.DataFrame(rows)


def _numeric(df: pd.DataFrame, cols) -> bool:
    return all(c in df and pd.api.types.is_numeric_dtype(df[c]) for c in cols)


def camber_thrust(df: pd.DataFrame) -> dict | None:
    """Camber thrust near zero slip: dFy0/dgamma per unit load [1/rad], its t statistic, the cornering
    slope's sign, and the thrust at 3 deg and the median load [N]; None when the data cannot tell."""
    if not _numeric(df, ("run", "fz", "fy", "slip_angle", "camber")):
        return None
    if np.ptp(df["camber"].to_numpy(float)) < 1.0 * _DEG:
        return None
    s = _per_sweep(df, "slip_angle", ("fy",), SMALL_ALPHA, 1.0 * _DEG)
    if len(s) < 4 or s["camber"].nunique() < 2 or (s["fz"] <= 0).any():
        return None
    mu0 = (s["fy_0"] / s["fz"]).to_numpy(float)
    g = s["camber"].to_numpy(float)
    fit = _line(g, mu0)
    if fit is None:
        return None
    _, slope, se = fit
    ca = float(np.median(s["fy_slope"]))
    fz = float(np.median(s["fz"]))
    return {"slope": slope, "t": slope / se if se > 0 else np.inf, "cornering_sign": np.sign(ca),
            "thrust_3deg_N": slope * 3 * _DEG * fz, "fz_N": fz, "sweeps": len(s)}


def pneumatic_trail(df: pd.DataFrame) -> dict | None:
    """Pneumatic trail near zero slip per load level [m]: {'levels': [(fz, trail), ...]}; None if not measurable."""
    if not _numeric(df, ("run", "fz", "fy", "mz", "slip_angle")):
        return None
    s = _per_sweep(df, "slip_angle", ("fy", "mz"), SMALL_ALPHA, 1.0 * _DEG)
    if s.empty:
        return None
    s = s[np.abs(s["fy_slope"]) > 4 * s["fy_se"]]  # a clear cornering stiffness
    if s.empty:
        return None
    s = s.assign(trail=-s["mz_slope"] / s["fy_slope"]).sort_values("fz")
    fz = s["fz"].to_numpy(float)
    _, level = group_levels(fz, 100.0, 0.05, relative_to="value")  # loads within 100 N or 5 %
    level = np.where(level < 0, max(int(level.max()), 0), level)  # an unrecorded load: the last level, as before
    levels = [(float(np.median(fz[level == k])), float(np.median(s["trail"].to_numpy(float)[level == k])))
              for k in range(int(level.max()) + 1)]
    return {"levels": levels, "sweeps": len(s)}


def fx_slip_slope(df: pd.DataFrame) -> dict | None:
    """Slope of Fx against slip ratio near zero per sweep: share of clearly negative ones; None if not measurable."""
    if not _numeric(df, ("run", "fx", "slip_ratio")):
        return None
    s = _per_sweep(df, "slip_ratio", ("fx",), SMALL_KAPPA, 0.01)
    if s.empty:
        return None
    clear = s[np.abs(s["fx_slope"]) > 4 * s["fx_se"]]
    if clear.empty:
        return None
    neg = int((clear["fx_slope"] < 0).sum())
    return {"negative": neg, "clear": len(clear), "median_slope": float(np.median(clear["fx_slope"]))}


def mirrored_findings(ds) -> list[Finding]:
    """Sign contradictions of a :class:`~tyrefit.io.readers.Dataset` (ISO-W) that say the tyre is mirrored."""
    df, src = ds.df, ds.source
    conv = getattr(ds, "convention", "iso") or "iso"
    out: list[Finding] = []
    if ds.kind in ("slip_angle", "slip_ratio"):
        c = camber_thrust(df)
        if c is not None and c["cornering_sign"] != 0 and np.sign(c["slope"]) != c["cornering_sign"] \
                and abs(c["slope"]) * _DEG >= MIN_CAMBER_MU_PER_DEG and abs(c["t"]) > 4:
            out.append(Finding("camber_thrust", (
                f"{src}: camber thrust of the wrong sign: {c['thrust_3deg_N']:+.0f} N at {c['fz_N']:.0f} N and "
                f"+3 deg camber (zero slip angle, {c['sweeps']} sweeps), pushing away from the lean; in ISO-W "
                f"(this file read as {conv}) a positive camber gives a lateral force of the cornering stiffness's "
                "sign (negative): is the camber column negated, or the file's convention another?")))
        t = pneumatic_trail(df)
        if t is not None and t["levels"]:
            neg = [(fz, tr) for fz, tr in t["levels"] if tr < 0]
            if len(neg) * 2 > len(t["levels"]):
                shown = ", ".join(f"{tr * 1e3:+.1f} mm at {fz:.0f} N" for fz, tr in neg[:4])
                out.append(Finding("pneumatic_trail", (
                    f"{src}: negative pneumatic trail -Mz/Fy near zero slip at {len(neg)} of {len(t['levels'])} "
                    f"load levels ({shown}): the aligning moment turns the wheel away from zero slip; in ISO-W "
                    f"(this file read as {conv}) a normal tyre's trail is positive: is the Mz channel negated?")))
        x = fx_slip_slope(df)
        if x is not None and x["negative"] * 2 > x["clear"]:
            out.append(Finding("fx_slip", (
                f"{src}: Fx falls with slip ratio near zero in {x['negative']} of {x['clear']} sweeps (median "
                f"{x['median_slope'] / 1e3:.4g} kN per unit slip): in ISO-W a driving (positive) slip ratio gives "
                "a positive Fx: is the Fx or the slip-ratio channel negated?")))
    return out


def check_mirrored(ds, allow: bool = False) -> list[str]:
    """Refuse a mirrored tyre (one line, :class:`ValueRangeError`) unless ``allow``; return the findings'
    messages (warnings when allowed, else an empty list)."""
    found = mirrored_findings(ds)
    if found and not allow:
        raise ValueRangeError("; ".join(f.message for f in found)
                              + f" (pass {option('allow_mirrored', flag=True)} if the "
                              f"tyre really is so; a sign convention is fixed with {option('convention')})")
    return [f.message for f in found]
