"""Global PAC89 fit: all sweeps at once, on the friction coefficient.

:func:`fit_pac89` fits the lateral coefficients ``a0``..``a13`` to slip-angle
sweeps, ``b0``..``b10`` to slip-ratio sweeps and ``c0``..``c17`` to the
aligning moment when ``mz`` is measured, following Komana, Els and Becker
(section 4.3): Eq. 2-4 initial estimates per sweep
(:mod:`tyrefit.fitting.initial`), then one least-squares problem over every
point on the friction coefficient mu = F / Fz.

The problem
-----------
Residual of point i in sweep s:  r_i = (F_model(p; Fz_i, x_i, gamma_i) - F_i) / Fz_i,
with the *measured* Fz_i (static-rig loads fall during a push).  Costs:

* ``cost='l2'`` (default): sum_s (1/n_s) sum_i r_i^2, ordinary least squares
  with each sweep weighted by 1/n_s so that densely sampled sweeps do not
  dominate (mu already removes the load scale);
* ``cost='l1'``: sum_s (1/n_s) sum_i |r_i|, Komana et al. Eq. 5
  (Cost = sum sqrt((Y - y)^2)), solved as a smooth pseudo-Huber problem
  (``soft_l1`` loss) whose scale is shrunk in two continuation steps from
  the l2 solution, so it converges to the l1 minimum.

Solver: the one fitting core, :func:`tyrefit.fitting.core.solve` (SciPy's
trust-region reflective ``least_squares``) with the analytic Jacobian of
:mod:`tyrefit.models.pac89` for all points at once; the cost (l2, Eq. 5 l1,
Huber, soft l1) and the 1/n_s sweep weights are the core's options.
The coefficients are held as :class:`lmfit.Parameters` (value, bounds,
``vary``, standard error, correlations) in the result.

Physical constraints, exact over the fitted load range [Fz_lo, Fz_hi]:

* C > 0: bounds on ``a0`` / ``b0``;
* D > 0: D/Fz = a1 Fz + a2 is linear in Fz, so it is positive over the range
  iff it is at both ends; when a1 and a2 both vary they are re-parametrised
  as the peak friction (D/Fz) at Fz_lo and Fz_hi, each bounded below by
  mu = 0.02 (an affine change of variables); when only one varies its bounds
  follow from the other's fixed value.  Same for BCD/Fz = b3 Fz + b4 > 0;
* E <= 1: E = a6 Fz + a7 is linear, handled the same way (E at both ends
  <= 1).  The longitudinal E = b6 Fz^2 + b7 Fz + b8 is checked after the fit
  and refitted with b6 = 0 (linear, exact) if it breaks E <= 1.

Staged, multi-start fitting so that a poor start cannot strand the fit:
stage 1 fits C, the D law and the BCD law with E held; stage 2 frees all
fitted coefficients.  Four starts spread along the C-E valley (the Eq. 2-4
estimates, typical C with E = 0, high C with E = 0.8, low C with E lowered
by 1; see :func:`_starts`) are all run; the lowest cost wins.  (An early
exit once the noise floor was reached was tried and removed: on the PAC89
example set it stopped in the higher of two minima.)

Identifiability: a coefficient the data cannot determine is held at its
neutral value (0, or the Eq. 2-4 estimate for a4) and listed in
``FitResult.not_identifiable`` with the reason; it is never fitted to noise.
The rules (:func:`identifiability`) need, for

* load laws: a1, a4 >= 2 load levels; a6 >= 3 (E is the weakest-determined
  factor); b1 >= 2; b3, b7 >= 3; b5, b6 >= 4; c1 >= 2; c3, c8 >= 3; c5, c7 >= 4;
* camber: a5, c6, c10 >= 2 levels of |gamma|; a11, c15 >= 2 camber levels;
  a8, c11 also both slip signs (a horizontal camber shift is told from a
  vertical one only by the saturated ends); c14 also >= 3 load levels;
* shifts: a10, a13, b10, c13, c17 need both slip signs reaching at least half
  the largest |slip|; a9, a12, b9, c12, c16 also >= 2 load levels;
* curvature: with no sweep reaching its peak E is held at 0 (a6, a7 / b6-b8).

References
----------
Komana, Els, Becker, *Cost efficient tyre testing, modelling and validation for PBS assessments*, Sec. 4.3, Eq. 2-5.
"""

from __future__ import annotations

import functools
import math
import time
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, field

import numpy as np
import pandas as pd

from ..errors import DataError, FitError, close_matches, option
from ..io.readers import derive_runs, read_data
from ..models import pac89
from . import initial as ini
from ._blas import single_threaded_blas
from .core import covariance, huber, interior, soft_l1
from .problem import SweepProblem
from .result import FitResult

__all__ = ["fit_pac89", "PartData", "identifiability", "prepare_data", "point_scatter", "PARTS"]

_RAD_TO_DEG = 180.0 / math.pi
MU_MIN, MU_MAX = 0.02, 6.0


@dataclass(frozen=True)
class PartSpec:
    """What one part of PAC89 (lateral, longitudinal, aligning) fits to."""

    name: str
    names: tuple[str, ...]
    force: str
    slip: str
    x_scale: float  # SI slip -> PAC89 units
    core: tuple[str, ...]  # stage-1 coefficients (C, D law, BCD law)
    curvature: tuple[str, ...]

    def jacobian(self, p, d: "PartData", names):
        if self.name == "lateral":
            return pac89.lateral_jacobian(p, d.fz, d.slip, d.camber, names)
        if self.name == "longitudinal":
            return pac89.longitudinal_jacobian(p, d.fz, d.slip, names)
        return pac89.aligning_jacobian(p, d.fz, d.slip, d.camber, names)

    def model(self, p, fz, slip, camber=0.0):
        if self.name == "lateral":
            return pac89.lateral_force(p, fz, slip, camber)
        if self.name == "longitudinal":
            return pac89.longitudinal_force(p, fz, slip)
        return pac89.aligning_moment(p, fz, slip, camber)


PARTS: dict[str, PartSpec] = {
    "lateral": PartSpec("lateral", pac89.LATERAL, "fy", "slip_angle", _RAD_TO_DEG,
                        ("a0", "a1", "a2", "a3", "a4"), ("a6", "a7")),
    "longitudinal": PartSpec("longitudinal", pac89.LONGITUDINAL, "fx", "slip_ratio", 100.0,
                             ("b0", "b1", "b2", "b3", "b4", "b5"), ("b6", "b7", "b8")),
    "aligning": PartSpec("aligning", pac89.ALIGNING, "mz", "slip_angle", _RAD_TO_DEG,
                         ("c0", "c1", "c2", "c3", "c4", "c5"), ("c7", "c8", "c9")),
}

#: neutral values of the coefficients that are not fitted (everything else 0)
#: linear laws value(Fz) = s Fz + i constrained at both ends of the load range:
#: (slope, intercept, lower bound, upper bound) in PAC89 units (Fz in kN)
_LINEAR_LAWS = {
    "lateral": [("a1", "a2", MU_MIN * 1e3, MU_MAX * 1e3), ("a6", "a7", -30.0, 1.0)],
    "longitudinal": [("b1", "b2", MU_MIN * 1e3, MU_MAX * 1e3), ("b3", "b4", 1e-6, np.inf), ("b7", "b8", -30.0, 1.0)],
    "aligning": [],
}


@dataclass
class PartData:
    """Arrays of one part's points (SI, ISO-W) and their sweep structure."""

    part: PartSpec
    df: pd.DataFrame
    fz: np.ndarray
    slip: np.ndarray
    camber: np.ndarray
    y: np.ndarray  # measured force or moment
    run: np.ndarray
    n_per_run: np.ndarray  # n of the sweep of each point
    info: dict = field(default_factory=dict)
    screening: dict = field(default_factory=dict)  # samples left out before the fit (see screen_sweeps)

    @functools.cached_property
    def norm(self) -> np.ndarray:
        """Load each point's residual is divided by [N]: the measured Fz, never below half its sweep's median.

        mu = F/Fz with the *measured* load (static-rig loads fall during a push), but a
        lift-off or glitched sample with a near-zero load would blow its mu residual up
        without bound; the sweep's median load is the set point the sweep was run at.
        """
        return np.maximum(self.fz, 0.5 * _sweep_median(self.fz, self.run))

    @property
    def n(self) -> int:
        return len(self.y)

    @property
    def fz_range(self) -> tuple[float, float]:
        return float(self.fz.min()), float(self.fz.max())


# ----------------------------------------------------------------------------------- data
def _frame(data) -> tuple[pd.DataFrame, dict]:
    """DataFrame and description of ``data`` (Dataset, DataFrame or path)."""
    info = {"source": "", "kind": ""}
    if isinstance(data, pd.DataFrame):
        df = data
    elif hasattr(data, "df"):
        df = data.df
        info["source"] = str(getattr(data, "source", "") or "")
        info["kind"] = str(getattr(data, "kind", "") or "")
    else:
        ds = read_data(data)
        df, info["source"], info["kind"] = ds.df, ds.source, ds.kind
    if "fz" not in df:
        raise DataError(f"{info['source'] or 'data'}: no 'fz' column; fitting needs the normal load of every point")
    df = df.copy()
    if "run" not in df:
        df["run"] = _derive_runs(df)
    if "camber" not in df:
        df["camber"] = 0.0
    df["camber"] = df["camber"].fillna(0.0)
    return df, info


def _derive_runs(df: pd.DataFrame) -> np.ndarray:
    kind = "slip_angle" if "slip_angle" in df else "slip_ratio"
    return np.asarray(derive_runs(df, kind)[0], int)


def _varies(g: pd.Series, tol: float) -> bool:
    v = g.to_numpy(float)
    v = v[np.isfinite(v)]
    return v.size > 0 and float(np.ptp(v)) >= tol


def prepare_data(data, *, screen: bool = True) -> tuple[dict[str, PartData], dict]:
    """Split ``data`` into lateral, longitudinal and aligning point sets.

    A sweep (``run``) is lateral when its slip angle varies by >= 0.5 deg and
    its slip ratio (if any) varies by less than 0.05 (rig noise of +-0.01 is
    common); longitudinal when its slip ratio varies by >= 0.01 while the slip
    angle varies by less than 0.5 deg and stays within 0.5 deg of zero.
    Other sweeps (combined slip, or longitudinal at a slip angle) are left out:
    PAC89 has pure-slip curves only.
    A run whose load is not held (its 5-95 % load range exceeds half its
    median load: a rig's warm-up or load ramp) is left out with a note.
    Points with NaN in the needed columns or Fz <= 0 are dropped.  With
    ``screen`` (default), lift-off samples and spikes are left out and counted
    (:func:`screen_sweeps`; the counts are in ``PartData.screening``).
    """
    df, info = _frame(data)
    if info.get("kind") == "static" or ("lateral_displacement" in df and "slip_angle" not in df):
        raise DataError(f"{info['source'] or 'data'}: static-rig data (lateral displacement) must first be turned "
                        "into slip angles with tyrefit.rig.prepare_static_fit (Komana et al. Eq. 1, needs the "
                        f"contact-patch length); the fit does this with {option('patch', 'PATCH.csv')}")
    parts: dict[str, PartData] = {}
    dropped, ramps = [], []
    lat_runs, lon_runs = [], []
    for run, g in df.groupby("run", sort=True):
        fzr = g["fz"].to_numpy(float)
        fzr = fzr[np.isfinite(fzr)]
        if fzr.size and np.median(fzr) > 0 and \
                np.subtract(*np.percentile(fzr, [95, 5])) > 0.5 * np.median(fzr):
            ramps.append(int(run))  # the load is not held (a rig's warm-up or load ramp): not a sweep
            continue
        sa_var = "slip_angle" in g and _varies(g["slip_angle"], math.radians(0.5))
        sr_var = "slip_ratio" in g and _varies(g["slip_ratio"], 0.01)
        # a slip-angle sweep may carry slip-ratio noise (FSAE TTC: +-0.01); only a slip ratio that
        # moves by 0.05 or more during a slip-angle sweep makes it combined slip
        sr_big = "slip_ratio" in g and _varies(g["slip_ratio"], 0.05)
        if sa_var and not sr_big and "fy" in g:
            lat_runs.append(run)
        elif sr_var and not sa_var and "fx" in g:
            sa = g["slip_angle"].to_numpy(float) if "slip_angle" in g else np.zeros(len(g))
            if np.all(~np.isfinite(sa)) or abs(np.nanmedian(sa)) < math.radians(0.5):
                lon_runs.append(run)
            else:
                dropped.append(int(run))
        elif sa_var or sr_var:
            dropped.append(int(run))
    if ramps:
        info.setdefault("notes", []).append(
            f"{len(ramps)} run(s) whose load is not held (5-95 % range above half the median: a warm-up or load "
            f"ramp) left out (runs {ramps[:8]}{'...' if len(ramps) > 8 else ''})")
    if dropped:
        info.setdefault("notes", []).append(
            f"{len(dropped)} combined-slip sweep(s) left out (runs {dropped[:8]}{'...' if len(dropped) > 8 else ''}): "
            "PAC89 has pure-slip curves only")
    for name, runs, cols in (("lateral", lat_runs, ("fy", "slip_angle")),
                             ("longitudinal", lon_runs, ("fx", "slip_ratio")),
                             ("aligning", lat_runs, ("mz", "slip_angle"))):
        if not runs or any(c not in df for c in cols):
            continue
        sub = df[df["run"].isin(runs)]
        ok = np.isfinite(sub["fz"].to_numpy(float)) & (sub["fz"].to_numpy(float) > 0)
        for c in cols:
            ok &= np.isfinite(sub[c].to_numpy(float))
        sub = sub[ok]
        spec = PARTS[name]
        screening = {}
        if screen:
            keep, screening = screen_sweeps(sub, spec.force, spec.slip)
            sub = sub[keep]
        counts = sub.groupby("run")["run"].transform("size").to_numpy()
        sub = sub[counts >= 4]
        if len(sub) < 10:
            continue
        if not np.any(np.abs(sub[cols[0]].to_numpy(float)) > 1e-9 * np.abs(sub["fz"].to_numpy(float)).max()):
            info.setdefault("notes", []).append(  # a rig without that channel often writes zeros
                f"{name}: '{cols[0]}' is zero throughout the sweeps; the {name} part is not fitted")
            continue
        counts = sub.groupby("run")["run"].transform("size").to_numpy()
        parts[name] = PartData(spec, sub, sub["fz"].to_numpy(float), sub[spec.slip].to_numpy(float),
                               sub["camber"].to_numpy(float), sub[spec.force].to_numpy(float),
                               sub["run"].to_numpy(), counts.astype(float), screening=screening)
    if not parts:
        what = info["source"] or "data"
        raise DataError(f"{what}: nothing to fit: need sweeps of slip_angle with fy (and fz), or of slip_ratio "
                        "with fx, each with at least 4 points and a slip span of 0.5 deg / 0.01")
    return parts, info


# ------------------------------------------------------------------------------ screening
#: a sample whose load is below this fraction of its sweep's median load is a lift-off or a glitch
LOAD_FLOOR = 0.1
#: a spike departs from the 5-point running median of its sweep by more than SPIKE_K robust sigmas ...
SPIKE_K = 8.0
#: ... and by more than this fraction of the sweep's peak |F| (so that a noise-free sweep flags nothing)
SPIKE_MIN = 0.15
#: a load spike departs from the running median of the sweep's load by more than this fraction of it
LOAD_SPIKE = 0.25


def _sweep_median(values: np.ndarray, run: np.ndarray) -> np.ndarray:
    """Median of ``values`` over each point's sweep, one value per point."""
    return pd.Series(np.asarray(values, float)).groupby(np.asarray(run)).transform("median").to_numpy()


def _running_median(v: np.ndarray, group: np.ndarray, width: int = 5) -> np.ndarray:
    """Running median of ``v`` within contiguous groups (codes ``group``, sorted), mirrored at group ends.

    Vectorised over all groups at once (``scipy.ndimage.median_filter(mode='mirror')``
    per group gives the same values).
    """
    n = len(v)
    i = np.arange(n)
    bounds = np.flatnonzero(np.r_[True, group[1:] != group[:-1], True])
    sizes = np.diff(bounds)
    lo = np.repeat(bounds[:-1], sizes)
    hi = np.repeat(bounds[1:] - 1, sizes)
    h = width // 2
    j = i[:, None] + np.arange(-h, h + 1)[None, :]
    j = np.where(j < lo[:, None], 2 * lo[:, None] - j, j)
    j = np.where(j > hi[:, None], 2 * hi[:, None] - j, j)
    j = np.clip(j, lo[:, None], hi[:, None])
    return np.median(v[j], axis=1)


def _mad_sigma(e: np.ndarray, group: np.ndarray) -> np.ndarray:
    """1.4826 x the median absolute deviation of ``e`` within each group, one value per point."""
    dev = np.abs(e - _sweep_median(e, group))
    return 1.4826 * _sweep_median(dev, group)


def _restored(x: np.ndarray, y: np.ndarray, group: np.ndarray, flagged: np.ndarray, thr: np.ndarray) -> np.ndarray:
    """Flagged samples that lie on their sweep once the flagged ones are taken out (Hampel's second pass).

    On the steep part of a curve a spike in the window shifts the running
    median of its good neighbours by a slip step, which can exceed the
    threshold there.  The running median of each sweep's unflagged samples,
    interpolated in slip at the flagged ones, is the curve without the
    spikes: a flagged sample within ``thr`` of it is restored.
    """
    back = np.zeros(len(y), dtype=bool)
    for g in np.unique(group[flagged]):
        idx = np.flatnonzero(group == g)
        clean = idx[~flagged[idx]]
        if len(clean) < 5:
            continue
        o = clean[np.argsort(x[clean], kind="stable")]
        xc, mc = x[o], _running_median(y[o], np.zeros(len(o), dtype=int))
        xc, first = np.unique(xc, return_index=True)
        fl = idx[flagged[idx]]
        inside = (x[fl] >= xc[0]) & (x[fl] <= xc[-1])  # beyond the clean samples: no curve to compare with
        m2 = np.interp(x[fl], xc, mc[first])
        back[fl] = inside & (np.abs(y[fl] - m2) <= thr[fl])
    return back


def screen_sweeps(df: pd.DataFrame, force: str, slip: str) -> tuple[np.ndarray, dict]:
    """Samples to keep, and what was left out: lift-off samples, load spikes, force spikes.

    Per sweep (``run``):

    * **lift-off**: Fz below ``LOAD_FLOOR`` (10 %) of the sweep's median load; the
      mu residual of such a sample divides by almost nothing;
    * **load spike**: in record order, Fz departs from its 5-point running median by
      more than max(``LOAD_SPIKE`` x the median load, ``SPIKE_K`` robust sigmas);
    * **force spike**: in slip order, F departs from its 5-point running median by
      more than max(``SPIKE_K`` robust sigmas, ``SPIKE_MIN`` x the sweep's peak |F|),
      and still does from the running median of the sweep without the flagged
      samples (a good neighbour of a spike on the steep part is given back).

    The robust sigma is 1.4826 x the median absolute deviation of the departures
    (Hampel's identifier, as in Pearson, "Outliers in process modeling and
    identification", IEEE TCST 10 (2002) 55-63).  A running median of 5 passes
    a smooth curve and up to two adjacent spikes untouched, so a clean sweep
    flags nothing; sweeps of fewer than 5 samples are only checked for lift-off.

    Returns
    -------
    keep : ndarray of bool
    report : dict
        ``low_load``, ``load_spikes``, ``force_spikes`` (counts), ``runs`` (sweeps
        touched), ``index`` (row labels left out), ``n`` (samples screened).
    """
    n = len(df)
    if n == 0:
        return np.ones(0, bool), {"low_load": 0, "load_spikes": 0, "force_spikes": 0, "runs": [], "index": [], "n": 0}
    run = df["run"].to_numpy()
    code = pd.factorize(run, sort=True)[0]
    fz = df["fz"].to_numpy(float)
    y = df[force].to_numpy(float)
    x = df[slip].to_numpy(float)
    med = _sweep_median(fz, code)
    size = np.bincount(code)[code]
    low = fz < LOAD_FLOOR * med
    long_ = size >= 5
    # loads, in record order within each sweep
    o = np.argsort(code, kind="stable")
    dz = np.empty(n)
    dz[o] = fz[o] - _running_median(fz[o], code[o])
    lspike = long_ & ~low & (np.abs(dz) > np.maximum(LOAD_SPIKE * med, SPIKE_K * _mad_sigma(dz, code)))
    # forces, in slip order within each sweep
    o = np.lexsort((x, code))
    m = np.empty(n)
    m[o] = _running_median(y[o], code[o])
    d = y - m
    peak = pd.Series(np.abs(m)).groupby(code).transform("max").to_numpy()
    thr = np.maximum(SPIKE_K * _mad_sigma(d, code), SPIKE_MIN * peak)
    fspike = long_ & ~low & ~lspike & (np.abs(d) > thr)
    fspike &= ~_restored(x, y, code, fspike, thr)
    out = low | lspike | fspike
    runs = pd.unique(run[out]).tolist()
    report = {"low_load": int(low.sum()), "load_spikes": int(lspike.sum()), "force_spikes": int(fspike.sum()),
              "runs": sorted((int(r) if isinstance(r, (int, np.integer)) else r for r in runs), key=str),
              "index": df.index[out].tolist(), "n": n}
    return ~out, report


def screening_message(part: str, rep: Mapping) -> str | None:
    """One line saying what :func:`screen_sweeps` left out of ``part``, or None."""
    bits = []
    if rep.get("low_load"):
        bits.append(f"{rep['low_load']} lift-off sample(s) (Fz below {LOAD_FLOOR:.0%} of the sweep's median load)")
    if rep.get("load_spikes"):
        bits.append(f"{rep['load_spikes']} load spike(s) (Fz off its running median by > {LOAD_SPIKE:.0%})")
    if rep.get("force_spikes"):
        bits.append(f"{rep['force_spikes']} force spike(s) (off the sweep's running median by > {SPIKE_K:g} robust "
                    f"sigma and > {SPIKE_MIN:.0%} of its peak)")
    if not bits:
        return None
    runs = rep.get("runs", [])
    return (f"{part}: left out of the fit: {', '.join(bits)}, in {len(runs)} sweep(s) "
            f"(runs {runs[:8]}{'...' if len(runs) > 8 else ''})")


# ------------------------------------------------------------------------- identifiability
def _levels(values: np.ndarray, tol: float) -> int:
    v = np.sort(np.asarray(values, float))
    if v.size == 0:
        return 0
    return int(1 + np.sum(np.diff(v) > tol))


def identifiability(d: PartData) -> tuple[dict[str, str], dict]:
    """Coefficients of ``d.part`` that the data cannot determine, with the reason.

    Returns ``(not_identifiable, facts)``; see the module docstring for the rules.
    """
    _, inv = np.unique(d.run, return_inverse=True)
    cnt = np.bincount(inv)
    runs = pd.DataFrame({"fz": np.bincount(inv, d.fz) / cnt, "camber": np.bincount(inv, d.camber) / cnt})
    n_l = int(ini.load_levels(runs["fz"].to_numpy()).max() + 1) if len(runs) else 0
    cam_tol = math.radians(0.25)
    n_c = _levels(runs["camber"].to_numpy(), cam_tol)
    n_ac = _levels(np.abs(runs["camber"].to_numpy()), cam_tol)
    x = d.slip * d.part.x_scale
    xmax = float(np.max(np.abs(x)))
    pos, neg = int(np.sum(x > 0.5 * xmax)), int(np.sum(x < -0.5 * xmax))
    both = pos >= 3 and neg >= 3
    peak = getattr(d, "_any_peak", True)
    facts = {"load_levels": n_l, "camber_levels": n_c, "abs_camber_levels": n_ac, "both_signs": both,
             "points_pos": pos, "points_neg": neg, "slip_max": xmax, "any_peak": bool(peak)}
    why: dict[str, str] = {}

    def need_loads(names, k):
        for nm in names:
            if n_l < k:
                why[nm] = f"needs >= {k} load levels (data: {n_l})"

    def need_both(names, extra=""):
        for nm in names:
            if not both:
                why.setdefault(nm, "needs both slip signs reaching half the largest |slip| "
                                   f"(data: {pos} points above, {neg} below){extra}")

    def need_camber(names, k=2, absolute=False):
        have = n_ac if absolute else n_c
        for nm in names:
            if have < k or (absolute and np.max(np.abs(runs["camber"])) < cam_tol):
                why.setdefault(nm, f"needs >= {k} {'|camber|' if absolute else 'camber'} levels (data: {have})")

    p = d.part.name
    if p == "lateral":
        need_loads(["a1", "a4"], 2)
        need_loads(["a6"], 3)
        need_camber(["a5"], absolute=True)
        need_camber(["a8", "a11"])
        need_both(["a8"])
        need_both(["a10", "a13"])
        need_both(["a9", "a12"])
        need_loads(["a9", "a12"], 2)
        if not peak:
            for nm in ("a6", "a7"):
                why.setdefault(nm, "no sweep reaches its peak: curvature E held at 0")
    elif p == "longitudinal":
        need_loads(["b1"], 2)
        need_loads(["b3", "b7"], 3)
        need_loads(["b5", "b6"], 4)
        need_both(["b9", "b10"])
        need_loads(["b9"], 2)
        if not peak:
            for nm in ("b6", "b7", "b8"):
                why.setdefault(nm, "no sweep reaches its peak: curvature E held at 0")
    else:
        need_loads(["c1"], 2)
        need_loads(["c3", "c8"], 3)
        need_loads(["c5", "c7"], 4)
        need_camber(["c6", "c10"], absolute=True)
        need_camber(["c11", "c14", "c15"])
        need_loads(["c14"], 3)
        need_both(["c11", "c12", "c13", "c16", "c17"])
        need_loads(["c12", "c16"], 2)
    return why, facts


# ------------------------------------------------------------------------------ point scatter
def point_scatter(d: PartData) -> tuple[float, pd.Series]:
    """Measurement-noise estimate [N or N*m] from neighbouring points along each sweep.

    Within a sweep sorted by slip, each interior point is compared with the
    straight line through its two neighbours, e_i = y_i - (w1 y_{i-1} + w2 y_{i+1})
    (linear-interpolation weights), which removes any locally linear trend;
    for independent noise of standard deviation sigma, var(e_i) =
    sigma^2 (1 + w1^2 + w2^2), so e_i / sqrt(1 + w1^2 + w2^2) estimates sigma.
    A robust scale (1.4826 x median absolute deviation) per sweep is used, so
    the curvature at the peak and outliers do not inflate it.  With repeated
    (up/down) sweeps the neighbours alternate between branches, so hysteresis
    counts as noise: the floor is what no single-valued steady-state curve can
    go below.  Returns the pooled value (root mean square over sweeps, weighted
    by points) and the per-sweep values.
    """
    out = {}
    for run, g in d.df.groupby("run", sort=True):
        x = g[d.part.slip].to_numpy(float)
        y = g[d.part.force].to_numpy(float)
        o = np.argsort(x, kind="stable")
        x, y = x[o], y[o]
        if len(x) < 5:
            continue
        x0, x1, x2 = x[:-2], x[1:-1], x[2:]
        span = x2 - x0
        ok = span > 0
        w1 = np.where(ok, (x2 - x1) / np.where(ok, span, 1.0), 0.5)
        w2 = 1.0 - w1
        e = (y[1:-1] - (w1 * y[:-2] + w2 * y[2:])) / np.sqrt(1.0 + w1**2 + w2**2)
        out[run] = 1.4826 * float(np.median(np.abs(e - np.median(e))))
    s = pd.Series(out, dtype=float)
    if s.empty:
        return float("nan"), s
    n = d.df.groupby("run").size().reindex(s.index).to_numpy(float)
    return float(np.sqrt(np.sum(n * s.to_numpy() ** 2) / np.sum(n))), s


# ------------------------------------------------------------------------------ the problem
class _Problem(SweepProblem):
    """One PAC89 part on its sweeps: an affine parametrisation theta -> coefficients, box bounds on theta."""

    method = "trf"  # dogbox was faster on some problems but took 2400 evaluations on others
    tol = 1e-9

    def __init__(self, d: PartData, base: dict[str, float], vary: Sequence[str], cost: str,
                 bounds: Mapping[str, tuple[float, float]] | None = None):
        super().__init__(d.y, d.run, cost)  # each sweep counts once: weights 1/n_s
        self.d = d
        self.spec = d.part
        self.what = self.spec.name
        self.names = self.spec.names
        #: the caller's bounds (fit_pac89's ``bounds``), intersected with the physical ones
        self.user_bounds = {k: v for k, v in (bounds or {}).items() if k in self.names}
        self.base = {k: float(base.get(k, 0.0)) for k in self.names}
        self.vary = [k for k in self.names if k in set(vary)]
        lo, hi = d.fz_range
        self.lo, self.hi = lo * 1e-3, hi * 1e-3
        self.inv_fz = 1.0 / d.norm
        if cost in ROBUST_LOSSES:  # robust costs: per-point scale of the mu residual
            self.robust_scale = robust_scale(d)
        self._build()

    # -- parametrisation ---------------------------------------------------------
    def _direct_bounds(self, k: str) -> tuple[float, float]:
        b = self.base
        gmax = float(np.max(np.abs(self.d.camber))) * _RAD_TO_DEG if self.d.camber.size else 0.0
        hi = max(self.hi, 1e-3)
        table = {
            "a0": (0.3, 3.0), "b0": (0.3, 3.0), "c0": (0.3, 5.0),
            "a3": (1e-9, np.inf), "a4": (1e-3, 1e5),
            "a5": (-1.0, 0.99 / gmax if gmax > 0 else 1.0),
            "b5": (-2.0 / hi, 10.0 / hi), "c5": (-2.0 / hi, 10.0 / hi),
            "c6": (-1.0, 0.99 / gmax if gmax > 0 else 1.0), "c10": (-1.0, 0.99 / gmax if gmax > 0 else 1.0),
        }
        lo_b, hi_b = table.get(k, (-np.inf, np.inf))
        # linear laws with one member fixed: bounds from the fixed one, at both load ends
        for s, i, L, U in self._laws():
            if k not in (s, i):
                continue
            other = i if k == s else s
            if other in self.vary:
                continue
            ends = np.array([self.lo, self.hi])
            if k == i:  # value = s0 Fz + i
                lo_b = max(lo_b, float(np.max(L - b[s] * ends)))
                hi_b = min(hi_b, float(np.min(U - b[s] * ends)))
            else:  # value = s Fz + i0
                lo_b = max(lo_b, float(np.max((L - b[i]) / ends)))
                hi_b = min(hi_b, float(np.min((U - b[i]) / ends)))
        if k in self.user_bounds:
            ulo, uhi = self.user_bounds[k]
            if max(lo_b, ulo) > min(hi_b, uhi):
                raise DataError(f"the bounds given for {k}, [{ulo:g}, {uhi:g}], are outside its physical range "
                                f"[{lo_b:g}, {hi_b:g}] on these data")
            lo_b, hi_b = max(lo_b, ulo), min(hi_b, uhi)
        return lo_b, hi_b

    def _laws(self):
        laws = []
        for s, i, L, U in _LINEAR_LAWS[self.spec.name]:
            if (s, i) == ("b7", "b8") and ("b6" in self.vary or self.base.get("b6", 0.0) != 0.0):
                continue  # quadratic E: checked after the fit
            laws.append((s, i, L, U))
        return laws

    def _build(self) -> None:
        nv = len(self.vary)
        idx = {k: j for j, k in enumerate(self.names)}
        # a law with a bounded member (fit_pac89's ``bounds``) is fitted in its coefficients, each in its box
        pairs = [(s, i, L, U) for s, i, L, U in self._laws()
                 if s in self.vary and i in self.vary and self.hi - self.lo > 1e-9
                 and s not in self.user_bounds and i not in self.user_bounds]
        paired = {k for s, i, _, _ in pairs for k in (s, i)}
        theta_names, lb, ub, cols = [], [], [], []
        self.offset = np.array([self.base[k] for k in self.names])
        for k in self.vary:
            if k in paired:
                continue
            col = np.zeros(len(self.names))
            col[idx[k]] = 1.0
            self.offset[idx[k]] = 0.0
            a, b = self._direct_bounds(k)
            theta_names.append(k), lb.append(a), ub.append(b), cols.append(col)
        for s, i, L, U in pairs:
            dz = self.hi - self.lo
            for end, (cs, ci) in (("lo", (-1.0 / dz, self.hi / dz)), ("hi", (1.0 / dz, -self.lo / dz))):
                col = np.zeros(len(self.names))
                col[idx[s]], col[idx[i]] = cs, ci
                theta_names.append(f"{s}{i}@{end}"), lb.append(L), ub.append(U), cols.append(col)
            self.offset[idx[s]] = self.offset[idx[i]] = 0.0
        self.theta_names = theta_names
        self.T = np.array(cols).T if cols else np.zeros((len(self.names), 0))
        self.lb, self.ub = np.array(lb, float), np.array(ub, float)
        self.used = [k for j, k in enumerate(self.names) if np.any(self.T[j] != 0)]
        self.used_idx = [idx[k] for k in self.used]
        self.pairs = pairs
        assert len(theta_names) == nv

    def theta_of(self, coeffs: Mapping[str, float]) -> np.ndarray:
        c = np.array([float(coeffs.get(k, self.base[k])) for k in self.names])
        th, *_ = np.linalg.lstsq(self.T, c - self.offset, rcond=None)
        return interior(th, self.lb, self.ub)

    def coeffs_of(self, theta: np.ndarray) -> dict[str, float]:
        c = self.offset + self.T @ theta
        return dict(zip(self.names, c.tolist()))

    # -- residuals --------------------------------------------------------------
    def rows(self, theta):
        """Residual on mu = (F_model - F) / load of every point (unweighted; the core applies 1/n_s)."""
        p = self.coeffs_of(theta)
        y = self.spec.model(p, self.d.fz, self.d.slip, self.d.camber)
        return (y - self.d.y) * self.inv_fz

    def jac(self, theta):
        """d residual / d theta (the analytic PAC89 Jacobian through the affine parametrisation)."""
        p = self.coeffs_of(theta)
        _, J = self.spec.jacobian(p, self.d, self.used)
        J = J * self.inv_fz[:, None]
        return J @ self.T[self.used_idx, :]


#: the outlier-resistant costs: rho of z = (r / s)^2, r the mu residual, s = HUBER_K x the sweep's noise
ROBUST_LOSSES = {"huber": huber, "soft_l1": soft_l1}
#: Huber's tuning constant: 95 % efficiency at Gaussian noise (Huber, Robust Statistics, 1981)
HUBER_K = 1.345
COSTS = ("l2", "l1", "soft_l1", "huber")


def robust_scale(d: PartData) -> np.ndarray:
    """Per-point scale s_i of the mu residual for the robust costs: ``HUBER_K`` x the sweep's noise / load.

    The noise of each sweep is :func:`point_scatter`'s (neighbouring points, median
    absolute deviation: spikes do not inflate it); sweeps too short for it take
    the pooled value.  Below s the cost is least squares, above it grows linearly.
    """
    pooled, per = point_scatter(d)
    sig = pd.Series(d.run).map(per).to_numpy(float)
    if not np.isfinite(pooled) or pooled <= 0:
        pooled = max(1e-3 * float(np.max(np.abs(d.y))), 1e-12)
    sig = np.where(np.isfinite(sig) & (sig > 0), sig, pooled)
    return HUBER_K * sig / d.norm


#: coefficients whose value 0 switches their term off (load slopes, camber terms, shifts);
#: the others (C, D, BCD, E core: a0, a2, a3, a4, a7, ...) have no neutral value
NEUTRAL = frozenset(["a1", "a5", "a6", "a8", "a9", "a10", "a11", "a12", "a13",
                     "b1", "b3", "b5", "b6", "b7", "b9", "b10",
                     "c1", "c3", "c5", "c6", "c7", "c8", "c10", "c11", "c12", "c13", "c14", "c15", "c16", "c17"])


# ------------------------------------------------------------------------------ one part
@dataclass
class PartFit:
    """Result of fitting one part (internal; gathered into FitResult)."""

    name: str
    coefficients: dict[str, float]
    varied: list[str]
    not_identifiable: dict[str, str]
    stderr: dict[str, float]
    correl: pd.DataFrame
    initial: dict[str, float]
    estimates: pd.DataFrame
    facts: dict
    objective: float
    nfev: int
    seconds: float
    starts: list[dict]
    notes: list[str]
    data: PartData
    point_scatter: float
    noise_per_run: pd.Series
    bounds: dict[str, tuple[float, float]]
    constraints: list[str]
    #: what the user must see: spikes left out, RMSE far above the noise floor, degenerate sweeps
    warnings: list[str] = field(default_factory=list)
    #: coefficients (or 'a1a2@lo'-style end values of a constrained law) that ended at a bound
    at_bound: list[str] = field(default_factory=list)


def _starts(spec: PartSpec, c0: dict[str, float]) -> list[dict[str, float]]:
    """Start points of the multi-start, spread along the C-E valley.

    Over a limited slip range a higher shape factor C with a higher curvature
    E gives nearly the same curve as a lower C with a lower E, so the cost has
    separate minima along that valley (seen on the PAC89 example set: C 1.35 /
    E 0.27 and C 1.73 / E 0.87, the second lower).  The starts are: the
    Eq. 2-4 estimates; the typical shape (C = 1.3 lateral, 1.65 longitudinal)
    with E = 0; a high-C, high-E start; a low-C, low-E start.
    """
    if spec.name == "aligning":
        alt = dict(c0, c0=2.0, c9=0.0)
        return [c0, alt]
    C, E_law = spec.core[0], spec.curvature
    e_int = E_law[-1]
    zero_e = {k: 0.0 for k in E_law}
    typ = dict(c0, **{C: ini.TYPICAL_C[spec.name]}, **zero_e)
    high = dict(c0, **{C: float(min(max(1.3 * c0[C], 1.6), 2.2))}, **zero_e)
    high[e_int] = 0.8
    low = dict(c0, **{C: float(max(0.85 * c0[C], 1.05))})
    low[e_int] = c0[e_int] - 1.0
    return [c0, typ, high, low]


def _fit_part(d: PartData, *, cost: str, vary: Iterable[str] | None, fixed: Mapping[str, float],
              initial: Mapping[str, float], notes: list[str],
              bounds: Mapping[str, tuple[float, float]] | None = None) -> PartFit:
    t0 = time.perf_counter()
    spec = d.part
    # Eq. 2-4 estimates
    if spec.name == "aligning":
        est = pd.DataFrame()
        c_init = ini.aligning_initial(d.df, spec.x_scale)
        d._any_peak = True
    else:
        est = ini.estimate_sweeps(d.df, spec.slip, spec.force, x_scale=spec.x_scale, part=spec.name)
        d._any_peak = bool(est["has_peak"].any()) if len(est) else False
        fn = ini.lateral_initial if spec.name == "lateral" else ini.longitudinal_initial
        c_init = fn(est)
    why, facts = identifiability(d)
    c0 = dict(c_init)
    c0.update({k: float(v) for k, v in initial.items() if k in spec.names})
    # what varies
    if vary is None:
        want = [k for k in spec.names if k not in why]
    else:
        want = [k for k in spec.names if k in set(vary)]
    held_by_rule = [k for k in want if k in why and (vary is not None)]
    if held_by_rule:
        notes.append(f"{spec.name}: {', '.join(held_by_rule)} asked to vary but not identifiable from these data; held")
    want = [k for k in want if k not in why and k not in fixed]
    # values of the coefficients that do not vary: fixed, else neutral (0) where a neutral value
    # exists (load slopes, camber terms, shifts), else the Eq. 2-4 estimate (C, D, BCD, E core)
    for k in spec.names:
        if k in fixed:
            c0[k] = float(fixed[k])
        elif k not in want and k in NEUTRAL and k not in initial:
            c0[k] = 0.0
    if spec.name == "lateral" and "a4" in why and "a4" not in fixed and "a4" not in initial:
        # one load: BCD law's curvature held so the cornering coefficient 2 a3/a4 falls gently with load
        c0["a4"] = c_init["a4"]
        if "a3" not in fixed and "a3" not in initial:  # a held or given a3 stays what the caller said
            c0["a3"] = c_init["a3"]
    if not d._any_peak and spec.name != "aligning":
        notes.append(f"{spec.name}: no sweep reaches its peak inside the tested slip range; D and C are "
                     "extrapolated (Eq. 2-4 fallback, see tyrefit.fitting.initial)")

    best = None
    starts_log = []
    nfev_total = 0
    nf_floor, nf_runs = point_scatter(d)
    core = [k for k in spec.core if k in want]
    for si, start in enumerate(_starts(spec, c0)):
        start = {k: (c0[k] if k in fixed or k not in want else v) for k, v in start.items()}
        # stage 1: C, D law, BCD law; E and the rest held
        p1 = _Problem(d, start, core, "l2", bounds)
        th1, n1 = p1.solve(p1.theta_of(start), tol=1e-5)  # only a start for stage 2
        c1 = dict(start, **p1.coeffs_of(th1)) if core else dict(start)
        # stage 2: everything that varies
        p2 = _Problem(d, c1, want, "l2", bounds)
        th2, n2 = p2.solve(p2.theta_of(c1), tol=1e-6)  # coarse: the best is polished below
        obj = p2.objective(th2)
        nfev_total += n1 + n2
        cs = p2.coeffs_of(th2)
        starts_log.append({"start": si, "objective_l2": obj, "nfev": n1 + n2,
                           "C": cs[spec.core[0]], "E": cs[spec.curvature[-1]]})
        if best is None or obj < best[0]:
            best = (obj, p2, th2)
    _, prob, theta = best
    if len(theta):
        theta, n_pol = prob.solve(theta, tol=1e-9)
        nfev_total += n_pol
        best = (prob.objective(theta), prob, theta)
    # distinct minima of nearly the same cost: C and E are only weakly determined by these data
    C_key = spec.core[0]
    c_best = prob.coeffs_of(theta)[C_key]
    rivals = [s_ for s_ in starts_log if s_["objective_l2"] <= best[0] * 1.02
              and abs(s_["C"] - c_best) > 0.05 * abs(c_best)]
    if rivals and C_key in want:
        r_ = min(rivals, key=lambda s_: s_["objective_l2"])
        notes.append(f"{spec.name}: another minimum within {100 * (r_['objective_l2'] / best[0] - 1):.2f} % of the "
                     f"cost has C = {r_['C']:.3g}, E = {r_['E']:.3g} (best: C = {c_best:.3g}); over the tested slip "
                     "range the two shapes nearly coincide, so C and E are weakly determined (their standard errors "
                     "are local)")
    if cost in ("l1", *ROBUST_LOSSES) and len(theta):
        # from the l2 solution: Komana et al.'s Eq. 5 (sum of absolute errors, which the core reaches by
        # pseudo-Huber continuation), or Huber / soft-l1 on the mu residual scaled by each sweep's noise
        pc = _Problem(d, prob.coeffs_of(theta), want, cost, bounds)
        th, n = pc.solve(pc.theta_of(prob.coeffs_of(theta)))
        nfev_total += n
        prob, theta = pc, th
    coeffs = prob.coeffs_of(theta) if len(theta) else dict(prob.base)
    # longitudinal: quadratic E must stay <= 1 over the load range, else refit with b6 = 0
    if spec.name == "longitudinal" and "b6" in want:
        fzk = np.linspace(prob.lo, prob.hi, 50)
        E = coeffs["b6"] * fzk**2 + coeffs["b7"] * fzk + coeffs["b8"]
        if np.any(E > 1.0):
            notes.append("longitudinal: E > 1 inside the load range with b6 free; refitted with b6 = 0 "
                         "(linear E law, constrained exactly)")
            want2 = [k for k in want if k != "b6"]
            c_re = dict(coeffs, b6=0.0)
            p3 = _Problem(d, c_re, want2, "l2", bounds)
            th3, n3 = p3.solve(p3.theta_of(c_re))
            nfev_total += n3
            prob, theta, want = p3, th3, want2
            coeffs = prob.coeffs_of(theta)
    at_bound = []
    for j, tn in enumerate(prob.theta_names):
        for bound, side in ((prob.lb[j], "lower"), (prob.ub[j], "upper")):
            if np.isfinite(bound) and abs(theta[j] - bound) <= 1e-6 * max(1.0, abs(bound)):
                at_bound.append(tn)
                what = (f"{tn.split('@')[0]} at Fz = {prob.lo if tn.endswith('lo') else prob.hi:.3g} kN"
                        if "@" in tn else tn)
                given = tn in prob.user_bounds and bound == prob.user_bounds[tn][0 if side == "lower" else 1]
                notes.append(f"{spec.name}: {what} ended at its {side} bound {bound:g} " + (
                    "(the bound given: the data want a value beyond it)" if given else
                    "(constraint active: the data want a value the physical limits exclude, or the model misses an "
                    "effect)"))
    stderr, correl = _uncertainty(prob, theta)
    bounds = {k: prob._direct_bounds(k) for k in want if k not in {x for s, i, _, _ in prob.pairs for x in (s, i)}}
    constraints = []
    for s, i, L, U in prob.pairs:
        law = "D/Fz" if (s, i) in (("a1", "a2"), ("b1", "b2")) else ("BCD/Fz" if s == "b3" else "E")
        constraints.append(f"{law} = {s} Fz + {i} bounded to [{L:g}, {U:g}] at Fz = {prob.lo:.3g} and "
                           f"{prob.hi:.3g} kN (fitted as its end values)")
    warns = []
    for s, i, L, U in prob._laws():
        if s in want and i in want and (s in prob.user_bounds or i in prob.user_bounds):
            # bounds given on a member: the law is fitted in its own coefficients, its ends are only checked
            ends = [coeffs[s] * fz + coeffs[i] for fz in (prob.lo, prob.hi)]
            held = all(L <= e <= U for e in ends)
            constraints.append(f"{s} Fz + {i} not constrained to [{L:g}, {U:g}] during the fit (bounds given on "
                               f"{s if s in prob.user_bounds else i}); checked after it: "
                               + ("holds" if held else "BROKEN"))
            if not held:
                warns.append(f"{spec.name}: {s} Fz + {i} = {ends[0]:.4g} .. {ends[1]:.4g} at Fz = {prob.lo:.3g} .. "
                             f"{prob.hi:.3g} kN is outside [{L:g}, {U:g}] with the bounds given: not a physical "
                             "tyre there")
    return PartFit(name=spec.name, coefficients=coeffs, varied=list(want), not_identifiable=why, stderr=stderr,
                   correl=correl, initial=c_init, estimates=est, facts=facts, objective=prob.objective(theta),
                   nfev=nfev_total, seconds=time.perf_counter() - t0, starts=starts_log, notes=notes, data=d,
                   point_scatter=nf_floor, noise_per_run=nf_runs, bounds=bounds, constraints=constraints,
                   warnings=_part_warnings(d, coeffs, nf_floor) + warns, at_bound=at_bound)


#: sweeps with fewer points than this (median) are too short to be slip sweeps
SHORT_SWEEP = 8


def _part_warnings(d: PartData, coeffs: Mapping[str, float], floor: float) -> list[str]:
    """Warnings of one fitted part: samples left out (lift-off, spikes), degenerate (too short) sweeps."""
    out = []
    msg = screening_message(d.part.name, d.screening)
    if msg:
        out.append(msg)
    # (an RMSE far above the noise floor is warned about by FitResult: tyrefit.fitting.result._fit_warnings)
    per = np.median(d.n_per_run) if d.n else 0
    n_runs = len(np.unique(d.run))
    if per < SHORT_SWEEP:
        out.append(f"{d.part.name}: {n_runs} sweeps of a median {per:.0f} points: too short to be slip sweeps "
                   "(is the run column a sample or block counter?); the per-sweep start estimates and the 1/n sweep "
                   "weighting assume sweeps across the slip range")
    return out


def _uncertainty(prob: _Problem, theta) -> tuple[dict[str, float], pd.DataFrame]:
    """Standard errors and correlations of the varied coefficients (Gauss-Newton, at the solution).

    cov(theta) = s^2 (J^T J)^+ with s^2 = sum r^2 / (N - p) of the mu residuals
    weighted sqrt(1/n_s) (:func:`tyrefit.fitting.core.covariance`), mapped to the
    coefficients through the affine parametrisation.  For the l1 and robust
    costs this is the least-squares approximation at their solution.
    """
    names = prob.vary
    if not len(theta):
        return {}, pd.DataFrame()
    cov_t, _ = covariance(prob.jac(theta), prob.rows(theta), prob.weights)
    idx = [prob.names.index(k) for k in names]
    Tm = prob.T[idx, :]
    cov = Tm @ cov_t @ Tm.T
    sd = np.sqrt(np.clip(np.diag(cov), 0, None))
    with np.errstate(invalid="ignore", divide="ignore"):
        corr = cov / np.outer(sd, sd)
    return dict(zip(names, sd.tolist())), pd.DataFrame(corr, index=names, columns=names)


# ------------------------------------------------------------------------------ public API
def fit_pac89(data, *, cost: str = "l2", vary: Sequence[str] | None = None,
              fixed: Mapping[str, float] | None = None, initial=None, tyre_info=None, screen: bool = True,
              bounds: Mapping[str, tuple[float, float]] | None = None):
    """Fit PAC89 coefficients to tyre test data.

    Parameters
    ----------
    data : Dataset, pandas.DataFrame or path
        canonical columns (SI, ISO-W): ``fz`` [N], ``fy`` [N] with ``slip_angle``
        [rad] (and optional ``camber`` [rad], ``mz`` [N*m]) and/or ``fx`` [N]
        with ``slip_ratio`` [-]; ``run`` identifies sweeps (derived if absent).
    cost : {'l2', 'l1', 'soft_l1', 'huber'}
        ordinary least squares (default), the sum of absolute errors of
        Komana et al. Eq. 5, or an outlier-resistant loss (Huber; soft l1 =
        pseudo-Huber) whose scale is 1.345 x each sweep's noise floor; all on
        mu = F/Fz with each sweep weighted 1/n.  Whatever the cost, lift-off
        samples and spikes are left out first (:func:`screen_sweeps`) and
        counted in the warnings.
    vary : sequence of str, optional
        coefficients to fit (e.g. ``['a0', 'a2', 'a3', 'a4', 'a7']``); the
        others are held at ``fixed`` / ``initial`` / neutral values.  Parts
        with no name in ``vary`` are not fitted.  Default: every coefficient
        the data can identify.  Names the data cannot identify are held even
        when listed (and reported).
    fixed : mapping, optional
        coefficients held at these values.
    initial : mapping or lmfit.Parameters, optional
        start values overriding the Eq. 2-4 estimates.
    bounds : mapping name -> (min, max), optional
        bounds on coefficients, intersected with the physical ones (C > 0, ...).  A bounded member of a
        linear law (a1/a2, a6/a7, b1/b2, b3/b4, b7/b8) is fitted in its own coefficient: the law's ends
        (D > 0, E <= 1 over the load range) are then checked after the fit, with a warning if broken.
    tyre_info : mapping or Pac89Tyre, optional
        design data for the tyre file: ``unloaded_radius``, ``width`` [m],
        ``fnomin`` [N], ``lateral_stiffness``, ``vertical_stiffness`` [N/m],
        ``name``, ``tyreside``, ``rolling_resistance``, ``header`` (extra lines).
    screen : bool
        leave lift-off samples and spikes out before fitting (default; see
        :func:`screen_sweeps`; what was left out is in ``FitResult.warnings``
        and ``FitResult.screening``).  ``False`` fits every sample.

    Returns
    -------
    FitResult

    Raises
    ------
    DataError
        nothing fittable in the data; ``cost`` not one of COSTS; unknown names;
        the data's force rises the wrong way with slip (sign convention).
    FitError
        the fit produced a non-finite result, or a curve that turns over.
    """
    t0 = time.perf_counter()
    if cost not in COSTS:
        raise DataError(f"cost {cost!r} is not known; accepted: 'l2' (least squares), 'l1' (Komana et al. Eq. 5), "
                        "'soft_l1' or 'huber' (outlier-resistant, on mu scaled by each sweep's noise)")
    fixed = {str(k).lower(): float(v) for k, v in (fixed or {}).items()}
    if initial is not None and hasattr(initial, "valuesdict"):
        initial = initial.valuesdict()
    initial = {str(k).lower(): float(v) for k, v in (initial or {}).items()}
    if vary is not None:
        vary = [str(k).lower() for k in vary]
    bounds = {str(k).lower(): (float(lo), float(hi)) for k, (lo, hi) in (bounds or {}).items()}
    for k, (lo, hi) in bounds.items():
        if not lo <= hi:
            raise DataError(f"bounds: {k} min {lo:g} > max {hi:g}")
    for label, names in (("vary", vary or []), ("fixed", fixed), ("initial", initial), ("bounds", bounds)):
        bad = [k for k in names if k not in pac89.ALL]
        if bad:
            raise DataError(f"{label}: {', '.join(bad)} not a PAC89 coefficient; accepted a0..a13, b0..b10, c0..c17"
                            + close_matches(bad[0], pac89.ALL))
    parts, info = prepare_data(data, screen=screen)
    _check_data_orientation(parts, info)
    notes = list(info.get("notes", []))
    fits = {}
    for name, d in parts.items():
        if vary is not None and not any(k in d.part.names for k in vary):
            continue
        with single_threaded_blas():
            pf = _fit_part(d, cost=cost, vary=vary, fixed=fixed, initial=initial, notes=notes, bounds=bounds)
        if not all(np.isfinite(v) for v in pf.coefficients.values()):
            raise FitError(f"{name} fit did not converge to finite coefficients; check the data (units, signs)")
        fits[name] = pf
    if not fits:
        raise DataError(f"vary={vary}: none of these coefficients belongs to a part present in the data "
                        f"(parts: {', '.join(parts)})")
    _check_orientation(fits)
    return FitResult.from_parts(fits, info=info, cost=cost, notes=notes, tyre_info=tyre_info, fixed=fixed,
                                initial=initial, seconds=time.perf_counter() - t0, bounds=bounds)


#: ISO-W: a positive slip angle gives a negative lateral force, a positive slip ratio a positive Fx
_EXPECTED_SIGN = {"lateral": -1.0, "longitudinal": 1.0}
_SIGN_HINT = {"lateral": "in ISO-W (tyrefit's convention) a positive slip angle gives a negative lateral force. "
                         f"If the file uses the SAE convention (FSAE TTC), pass {option('convention', 'sae')}",
              "longitudinal": "in ISO-W a positive (driving) slip ratio gives a positive longitudinal force; "
                              "check the sign of the slip ratio or Fx channel"}


#: the near-linear slip range of any tyre (3 deg, 3 %) and the least span a sweep must cover in it
_LINEAR_SLIP = {"lateral": (math.radians(3.0), math.radians(1.0)), "longitudinal": (0.03, 0.01)}


def _sweep_slope_signs(d: PartData) -> dict:
    """Sign of dmu/dslip of each sweep that covers the near-linear range around zero slip.

    Only points within 3 deg (3 % slip ratio) of zero count, where every tyre's
    force is steep and monotone; a sweep needs 5 of them spanning 1 deg (1 %),
    and the straight line must explain half their variance (|correlation| >= 0.7).
    Other sweeps (short, off-centre, flat) are left out.
    """
    mu = d.y / d.norm
    lim, span = _LINEAR_SLIP[d.part.name]
    out = {}
    for run, idx in pd.Series(np.arange(d.n)).groupby(d.run, sort=True).indices.items():
        x, y = d.slip[idx], mu[idx]
        inner = np.abs(x) <= lim
        x, y = x[inner], y[inner]
        if len(x) < 5 or np.ptp(x) < span or np.ptp(y) <= 0:
            continue
        c = float(np.corrcoef(x, y)[0, 1])
        if abs(c) >= 0.7:
            out[run] = math.copysign(1.0, c)
    return out


def _check_data_orientation(parts: dict[str, PartData], info: dict) -> None:
    """Refuse data whose force rises the wrong way with slip (a sign-flipped channel or another convention).

    Tested on the data before fitting, because a flexible curve fits reversed data
    well (a shape factor C near 3 turns the curve over within a fraction of a
    degree): the fit statistics cannot reveal it.  All sweeps reversed: one
    error naming the convention; some sweeps reversed: one error naming them.
    """
    src = info.get("source", "") or "data"
    for name, want in _EXPECTED_SIGN.items():
        d = parts.get(name)
        if d is None:
            continue
        signs = _sweep_slope_signs(d)
        rev = [int(r) if isinstance(r, (int, np.integer)) else r for r, sg in signs.items() if sg != want]
        if not rev:
            continue
        force = "lateral force" if name == "lateral" else "longitudinal force"
        slip = "slip angle" if name == "lateral" else "slip ratio"
        if len(rev) * 2 > len(signs):
            raise DataError(f"{src}: the {force} {'rises' if want < 0 else 'falls'} with {slip} in "
                            f"{len(rev)} of {len(signs)} sweeps; {_SIGN_HINT[name]}")
        raise DataError(f"{src}: sweeps of opposite sign: in runs {rev[:8]}{'...' if len(rev) > 8 else ''} the "
                        f"{force} {'rises' if want < 0 else 'falls'} with {slip}, in the other {len(signs) - len(rev)} "
                        "sweeps it does not; a sign-flipped channel or mixed conventions")


def _check_orientation(fits: dict[str, PartFit]) -> None:
    """The fitted curve must not turn over: at the outer half of the slip range F keeps the ISO-W sign.

    With C > 2 the PAC89 curve changes sign past its peak; a fit of reversed or
    corrupted data can end there with a good R^2.  Checked at camber 0 over the
    fitted load range.
    """
    for name, want in _EXPECTED_SIGN.items():
        pf = fits.get(name)
        if pf is None:
            continue
        d = pf.data
        xmax = float(np.max(np.abs(d.slip)))
        x = np.concatenate([np.linspace(-xmax, -0.5 * xmax, 9), np.linspace(0.5 * xmax, xmax, 9)])
        for fz in np.linspace(*d.fz_range, 5):
            f = d.part.model(pf.coefficients, np.full_like(x, fz), x, 0.0)
            if np.mean(np.sign(f) == want * np.sign(x)) < 0.5:
                C = pf.coefficients[d.part.core[0]]
                raise FitError(f"{d.info.get('source', '') or 'data'}: the fitted {name} curve turns over (its force "
                               f"has the wrong sign beyond half the slip range at Fz = {fz:.0f} N; C = {C:.3g}): "
                               "the data do not look like a tyre's force (sign convention, units, channel mix-up?)")
