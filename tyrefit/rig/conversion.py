"""Static lateral displacement to rolling slip angle: Komana et al. Eq. 1 and its calibration.

Eq. 1 of Komana, Els and Becker turns the lateral displacement Delta y of a static tyre into
the slip angle of a rolling one::

    alpha = f(u) * atan(u),     u = Delta y / L                (Komana et al., Eq. 1)

with L the contact-patch length at the measured load and pressure
(:class:`tyrefit.rig.patch.PatchModel`).  Without a calibration f = 1.

What f means physically
-----------------------
A tyre rolling at a steady slip angle alpha carries its carcass deflected
sideways under the contact patch by y, with tan(alpha) = y / sigma, where
sigma = C_alpha / C_y (cornering stiffness over lateral stiffness) is the
*relaxation length* -- the distance the tyre rolls to build up its side force
(Pacejka, *Tyre and Vehicle Dynamics*, Sec. 5.3 and 7.2).  If the static tyre
pushed by Delta y holds the same deflection as the rolling tyre that makes the
same force, then tan(alpha) = Delta y / sigma, and Eq. 1 with f = 1 says
sigma = L.  For real tyres sigma is a few patch half-lengths, so f = 1
overstates the slip angle and understates the cornering stiffness.

The calibrated form (``form = 'relaxation'``)
---------------------------------------------
::

    tan(alpha) = u / (n (1 + b u)),    i.e.    f(u) = atan(u / (n (1 + b u))) / atan(u)

* n = sigma / L at small displacement: the relaxation length in patch lengths
  (f(0) = 1/n);
* b >= 0 lets the effective relaxation length n L (1 + b u) grow with the
  displacement.

It is monotone in Delta y for every b >= 0 (d/du [u / (1 + b u)] = (1 + b u)^-2 > 0)
and bounded: alpha < 90 deg always, and alpha -> atan(1 / (n b)) for b > 0.
So outside the calibration range alpha(Delta y) neither turns back nor runs
away -- but it is an extrapolation, and :meth:`RigCalibration.check` says so.
n = 1, b = 0 is f = 1, the uncalibrated Eq. 1.

:func:`calibrate` fits n and b on a tyre tested on both rigs: it models the
rolling tyre's friction curve mu_d(alpha, Fz) from the dynamic data (a Magic
Formula per sweep, its factors interpolated in load), and chooses n and b so
that the static friction mu_s(Delta y) = Fy/Fz on the rising part of each
push equals mu_d(alpha(Delta y), Fz) at the measured load.
"""

from __future__ import annotations

import json
import math
import warnings
from dataclasses import asdict, dataclass, field
from pathlib import Path

import numpy as np
import pandas as pd

from ..errors import DataError, FitError, FormatError
from ..fitting.core import Parameters, solve
from ..io.outputs import write_text
from ..models.pac89 import magic_formula
from ..nomenclature import G0
from .patch import PatchModel, fit_patch
from .static import StaticAnalysis, analyse_static

__all__ = [
    "RigRangeWarning",
    "RigCalibration",
    "UNCALIBRATED",
    "eq1_slip_angle",
    "displacement_to_slip",
    "patch_length",
    "DynamicCurves",
    "fit_dynamic_curves",
    "calibrate",
]

_DEG = math.pi / 180.0


class RigRangeWarning(UserWarning):
    """Static data outside the range a rig calibration was fitted on."""


def eq1_slip_angle(u, n=1.0, b=0.0):
    """Slip angle [rad] from u = Delta y / L (Komana et al., Eq. 1, relaxation form of f).

    alpha = f(u) atan(u) with f(u) = atan(u / (n (1 + b |u|))) / atan(u), i.e.
    tan(alpha) = u / (n (1 + b |u|)).  Odd in u; n = 1, b = 0 gives f = 1.
    """
    u = np.asarray(u, float)
    return np.arctan(u / (n * (1.0 + b * np.abs(u))))   # Komana et al., Eq. 1 with f in relaxation form


@dataclass
class RigCalibration:
    """The calibrated f of Eq. 1 (see the module docstring).

    Attributes
    ----------
    n, b : float
        relaxation form tan(alpha) = u / (n (1 + b u)); n = 1, b = 0 is f = 1.
    n_stderr, b_stderr : float
        standard errors of the fit (NaN for the uncalibrated identity).
    u_range : (float, float)
        Delta y / L covered by the calibration data.
    fz_range : (float, float)
        loads of the calibration [N].
    pressure_range : (float, float)
        inflation pressures of the calibration [Pa].
    slip_angle_range : (float, float)
        slip angles the calibration mapped onto [rad].
    rmse_mu : float
        rms friction-coefficient residual of the calibration.
    points : int
    source : dict
        files (or names) of the static, dynamic and patch data.
    per_load : list of dict
        per static load: n fitted alone (shows whether f depends on u only).
    """

    n: float = 1.0
    b: float = 0.0
    n_stderr: float = float("nan")
    b_stderr: float = float("nan")
    u_range: tuple[float, float] = (0.0, float("inf"))
    fz_range: tuple[float, float] = (0.0, float("inf"))
    pressure_range: tuple[float, float] = (0.0, float("inf"))
    slip_angle_range: tuple[float, float] = (0.0, math.pi / 2)
    rmse_mu: float = float("nan")
    points: int = 0
    source: dict = field(default_factory=dict)
    per_load: list = field(default_factory=list)
    form: str = "relaxation"

    @property
    def calibrated(self) -> bool:
        return self.points > 0

    # -- Eq. 1 ------------------------------------------------------------------------
    def f(self, u):
        """Eq. 1 factor f(u) = alpha / atan(u) (1/n at u = 0)."""
        u = np.asarray(u, float)
        with np.errstate(invalid="ignore", divide="ignore"):
            return np.where(np.abs(u) < 1e-12, 1.0 / self.n, eq1_slip_angle(u, self.n, self.b) / np.arctan(u))

    def slip_angle(self, lateral_displacement, length):
        """Slip angle [rad] for displacement [m] and patch length [m] (Eq. 1)."""
        return eq1_slip_angle(np.asarray(lateral_displacement, float) / np.asarray(length, float), self.n, self.b)

    def relaxation_length(self, length, u=0.0):
        """Equivalent relaxation length sigma = n L (1 + b u) [m]."""
        return self.n * np.asarray(length, float) * (1.0 + self.b * np.abs(u))

    @property
    def max_slip_angle(self) -> float:
        """The bound of alpha(Delta y) as Delta y grows [rad]."""
        nb = self.n * self.b
        return math.atan(1.0 / nb) if nb > 0 else math.pi / 2

    # -- range checks -------------------------------------------------------------------
    def check(self, u=None, fz=None, pressure=None, *, where: str = "static data") -> list[str]:
        """Messages for data outside the calibrated range (empty if inside or uncalibrated).

        ``u`` is Delta y / L of the samples converted; ``fz`` [N]; ``pressure`` [Pa].
        The u range is what matters for Eq. 1 (f is a function of u); loads and
        pressures outside the calibration are reported too, since the
        relaxation length ratio may depend on them.
        """
        if not self.calibrated:
            return []
        out = []
        tol = 1.02
        if u is not None:
            u = np.abs(np.asarray(u, float))
            hi = self.u_range[1] * tol
            n_out = int(np.sum(u > hi))
            if n_out:
                out.append(f"{where}: {n_out} of {u.size} samples have Delta y/L up to {u.max():.3f}, beyond the "
                           f"calibrated range 0-{self.u_range[1]:.3f} of the rig calibration; Eq. 1 is extrapolated "
                           f"there (f stays monotone and bounded, but is not checked against dynamic data)")
        if fz is not None:
            fz = np.asarray(fz, float)
            lo, hi = self.fz_range
            if fz.min() < lo / 1.25 or fz.max() > hi * 1.25:
                out.append(f"{where}: loads {fz.min() / G0:.0f}-{fz.max() / G0:.0f} kg reach beyond the calibrated "
                           f"{lo / G0:.0f}-{hi / G0:.0f} kg (+/-25 %)")
        if pressure is not None and np.isfinite(pressure).all():
            p = np.asarray(pressure, float)
            lo, hi = self.pressure_range
            if p.min() < lo * 0.9 or p.max() > hi * 1.1:
                out.append(f"{where}: pressure {p.min() / 1e5:.2f}-{p.max() / 1e5:.2f} bar is outside the calibrated "
                           f"{lo / 1e5:.2f}-{hi / 1e5:.2f} bar (+/-10 %)")
        return out

    def warn(self, *args, **kw) -> list[str]:
        """:meth:`check`, issuing each message as a :class:`RigRangeWarning`."""
        msgs = self.check(*args, **kw)
        for m in msgs:
            warnings.warn(m, RigRangeWarning, stacklevel=3)
        return msgs

    # -- files ----------------------------------------------------------------------------
    def to_dict(self) -> dict:
        d = asdict(self)
        d = {"tyrefit": "rig calibration", "version": 1,
             "equation": "alpha = f(u) atan(u), u = lateral_displacement / patch_length (Komana et al., Eq. 1)",
             "f": "atan(u / (n (1 + b u))) / atan(u)  (relaxation form; n = 1, b = 0 is f = 1)",
             "meaning": "n = relaxation length / contact-patch length at small displacement",
             **d}
        d["valid_range"] = {"u": list(self.u_range), "fz_N": list(self.fz_range),
                            "pressure_Pa": list(self.pressure_range),
                            "slip_angle_deg": [math.degrees(a) for a in self.slip_angle_range]}
        for k in ("u_range", "fz_range", "pressure_range", "slip_angle_range"):
            d.pop(k)
        return d

    def to_json(self, path, force: bool = False) -> Path:
        """Write RIG.json (through :func:`tyrefit.io.outputs.write_text`)."""
        return write_text(path, json.dumps(self.to_dict(), indent=2, default=_jsonable) + "\n", force=force)

    @classmethod
    def from_dict(cls, d: dict, where: str = "rig calibration") -> "RigCalibration":
        if d.get("form", "relaxation") != "relaxation":
            raise FormatError(f"{where}: unknown calibration form {d.get('form')!r}; accepted: 'relaxation'")
        try:
            n, b = float(d["n"]), float(d.get("b", 0.0))
        except (KeyError, TypeError, ValueError):
            raise FormatError(f"{where}: needs numeric 'n' (and optionally 'b'); is this a file written by "
                              "'tyrefit rig calibrate'?") from None
        if not (n > 0 and b >= 0 and math.isfinite(n) and math.isfinite(b)):
            raise FormatError(f"{where}: n = {n} and b = {b} do not give a monotone, bounded Eq. 1; "
                              "accepted n > 0, b >= 0")
        vr = d.get("valid_range", {})

        def rng(key, default, scale=1.0):
            v = vr.get(key)
            return (float(v[0]) * scale, float(v[1]) * scale) if v else default

        return cls(n=n, b=b, n_stderr=float(d.get("n_stderr", float("nan"))),
                   b_stderr=float(d.get("b_stderr", float("nan"))),
                   u_range=rng("u", (0.0, float("inf"))), fz_range=rng("fz_N", (0.0, float("inf"))),
                   pressure_range=rng("pressure_Pa", (0.0, float("inf"))),
                   slip_angle_range=rng("slip_angle_deg", (0.0, math.pi / 2), _DEG),
                   rmse_mu=float(d.get("rmse_mu", float("nan"))), points=int(d.get("points", 0)),
                   source=dict(d.get("source", {})), per_load=list(d.get("per_load", [])))

    @classmethod
    def from_json(cls, path) -> "RigCalibration":
        """Read RIG.json; :class:`FormatError` if it is not a rig calibration."""
        p = Path(path)
        if not p.exists():
            raise FormatError(f"{p}: no such file (a RIG.json from 'tyrefit rig calibrate')")
        try:
            d = json.loads(p.read_text(encoding="utf-8"))
        except (UnicodeDecodeError, json.JSONDecodeError) as exc:
            raise FormatError(f"{p}: not a JSON rig calibration ({exc.__class__.__name__}: {exc})") from None
        if not isinstance(d, dict):
            raise FormatError(f"{p}: not a rig calibration (expected a JSON object)")
        return cls.from_dict(d, where=str(p))

    def summary(self) -> str:
        if not self.calibrated:
            return "Eq. 1 uncalibrated: f = 1 (relaxation length = patch length)"
        return (f"Eq. 1 calibrated: tan(alpha) = u / (n (1 + b u)), n = {self.n:.3f} +/- {self.n_stderr:.3f}, "
                f"b = {self.b:.3f} +/- {self.b_stderr:.3f}; f(0) = {1 / self.n:.3f}; valid for u = Delta y/L "
                f"<= {self.u_range[1]:.3f}, loads {self.fz_range[0] / G0:.0f}-{self.fz_range[1] / G0:.0f} kg; "
                f"rms mu residual {self.rmse_mu:.4f} over {self.points} samples")

    def plot(self, ax=None, u_max: float | None = None):
        """f(u) and alpha(u) against u = Delta y / L, with the calibrated range shaded."""
        from matplotlib.figure import Figure

        if ax is None:
            ax = Figure(figsize=(6.5, 4.2)).subplots()
        hi = u_max or (min(3 * self.u_range[1], 3.0) if self.calibrated else 1.0)
        u = np.linspace(0, hi, 300)
        ax.plot(u, np.degrees(eq1_slip_angle(u)), "k--", lw=1, label="f = 1 (uncalibrated)")
        ax.plot(u, np.degrees(self.slip_angle(u, 1.0)), "C0", lw=2, label=f"calibrated (n = {self.n:.2f}, b = {self.b:.2f})")
        if self.calibrated:
            ax.axvspan(*self.u_range, color="C0", alpha=0.1, label="calibrated range")
        ax.set_xlabel("u = Δy / L [-]")
        ax.set_ylabel("slip angle α [deg]")
        ax2 = ax.twinx()
        ax2.plot(u, self.f(u), "C1", lw=1, label="f(u)")
        ax2.set_ylabel("f(u) [-]", color="C1")
        ax2.set_ylim(0, 1.1)
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8, loc="upper left")
        return ax


#: f = 1: Eq. 1 without calibration
UNCALIBRATED = RigCalibration()


def _jsonable(o):
    if isinstance(o, (np.floating, np.integer)):
        return o.item()
    if isinstance(o, float) and not math.isfinite(o):
        return None
    return str(o)


def patch_length(patch: PatchModel, fz, pressure=None) -> np.ndarray:
    """Contact-patch length [m] at each sample's load ``fz`` [N] and pressure [Pa] (scalar, array or None)."""
    fz = np.asarray(fz, float)
    if pressure is None:
        return patch.length(fz, None)
    p = np.broadcast_to(np.asarray(pressure, float), fz.shape)
    out = np.empty(fz.shape)
    for pv in np.unique(p):
        m = p == pv
        out[m] = patch.length(fz[m], float(pv) if np.isfinite(pv) else None)
    return out


def displacement_to_slip(lateral_displacement, fz, patch: PatchModel, pressure=None,
                         rig: RigCalibration | None = None):
    """Slip angle [rad] from lateral displacement [m] at load ``fz`` [N] (Eq. 1).

    L is the patch length at the measured load and ``pressure`` [Pa]; ``rig``
    None means f = 1.  Returns ``(slip_angle, u)``.
    """
    rig = rig or UNCALIBRATED
    u = np.asarray(lateral_displacement, float) / patch_length(patch, fz, pressure)
    return eq1_slip_angle(u, rig.n, rig.b), u


# ----------------------------------------------------------------------------- dynamic reference curves
@dataclass
class DynamicCurves:
    """Per-sweep Magic-Formula fits of dynamic data, interpolated in load.

    mu(alpha) = D sin(C atan(B a - E (B a - atan B a))), a in degrees, fitted to
    mu = -Fy/Fz (ISO-W) of each sweep; K = B C D (the normalised cornering
    stiffness per degree), D, C and E are interpolated linearly in the sweep's
    mean load (held constant beyond the tested loads).
    """

    fz: np.ndarray
    D: np.ndarray
    C: np.ndarray
    K: np.ndarray
    E: np.ndarray
    rmse: np.ndarray
    max_slip: float                       # [rad]

    def mu(self, slip_angle, fz):
        """Rolling friction coefficient -Fy/Fz at ``slip_angle`` [rad] and ``fz`` [N]."""
        fz = np.asarray(fz, float)
        D = np.interp(fz, self.fz, self.D)
        C = np.interp(fz, self.fz, self.C)
        K = np.interp(fz, self.fz, self.K)
        E = np.interp(fz, self.fz, self.E)
        return magic_formula(np.degrees(slip_angle), K / (C * D), C, D, E)


def _MF_PARAMS(D0: float, K0: float) -> Parameters:  # noqa: N802 - a constructor
    """D, C, K, E of one sweep's Magic Formula on mu, with their bounds."""
    p = Parameters()
    p.add("D", D0, min=0.05, max=3.0, unit="-", meaning="peak friction")
    p.add("C", 1.4, min=0.8, max=2.0, unit="-", meaning="shape factor")
    p.add("K", K0, min=1e-4, max=10.0, unit="1/deg", meaning="cornering stiffness over load")
    p.add("E", 0.0, min=-10.0, max=1.0, unit="-", meaning="curvature factor")
    return p


def fit_dynamic_curves(dynamic) -> DynamicCurves:
    """Fit a Magic Formula to each sweep of a slip-angle data set (see :class:`DynamicCurves`)."""
    df = getattr(dynamic, "df", dynamic)
    src = getattr(dynamic, "source", "") or "dynamic data"
    for c in ("slip_angle", "fy", "fz"):
        if c not in df:
            raise DataError(f"{src}: dynamic data need '{c}'")
    rows = []
    for run, g in df.groupby("run" if "run" in df else np.zeros(len(df)), sort=True):
        a = np.degrees(g["slip_angle"].to_numpy(float))
        mu = -g["fy"].to_numpy(float) / g["fz"].to_numpy(float)
        if np.ptp(a) < 1.0 or a.size < 10:
            continue
        D0 = float(np.percentile(np.abs(mu), 98))
        small = np.abs(a) < 2.0
        K0 = float(np.polyfit(a[small], mu[small], 1)[0]) if small.sum() > 3 else D0 / 4
        K0 = max(K0, 1e-3)

        def res(q):
            D, C, K, E = q
            return magic_formula(a, K / (C * D), C, D, E) - mu

        fit = solve(res, _MF_PARAMS(D0, K0), cost="soft_l1", scale=0.02, x_scale=1.0, stderr=False,
                    what=f"{src}: Magic Formula of sweep {run}")
        rows.append((float(g["fz"].mean()), *fit.x, float(np.sqrt(np.mean(res(fit.x) ** 2))),
                     float(np.abs(g["slip_angle"]).max())))
    if not rows:
        raise DataError(f"{src}: no slip-angle sweep spans 1 deg or more; cannot describe the rolling tyre")
    rows.sort()
    r = np.array(rows)
    return DynamicCurves(r[:, 0], r[:, 1], r[:, 2], r[:, 3], r[:, 4], r[:, 5], float(r[:, 6].max()))


# ----------------------------------------------------------------------------- calibration
def _frame(x):
    return getattr(x, "df", x), (getattr(x, "source", "") or "")


def calibrate(static_ds, dynamic_ds, patch_ds, *, static_fz_tolerance: float = 0.15) -> RigCalibration:
    """Calibrate f of Eq. 1 on a tyre tested on both rigs.

    Parameters
    ----------
    static_ds : Dataset or DataFrame
        the tyre's static lateral test (kind 'static').
    dynamic_ds : Dataset or DataFrame
        its dynamic slip-angle sweeps (kind 'slip_angle', ISO-W).
    patch_ds : Dataset, DataFrame or PatchModel
        its contact-patch data (or a fitted model).
    static_fz_tolerance : float
        static samples are used if their load lies within the dynamic loads
        widened by this fraction.

    Returns
    -------
    RigCalibration

    Raises
    ------
    FitError
        no static sample overlaps the dynamic loads and slip angles.

    Notes
    -----
    Minimises, over the rising part of each static push (up to the static
    peak), sum rho(mu_s - mu_d(alpha(u; n, b), Fz)) with rho the soft-L1 loss
    (robust to stick-slip scatter), u = Delta y / L(Fz, p) and mu_d the
    dynamic reference curves (:func:`fit_dynamic_curves`).  Samples whose
    slip angle would fall beyond the dynamic sweeps are dropped and the fit
    repeated.  Also fits n alone per load, to show whether f is a function of
    u only, as Eq. 1 assumes.
    """
    ssrc = _frame(static_ds)[1]
    dsrc = _frame(dynamic_ds)[1]
    patch = patch_ds if isinstance(patch_ds, PatchModel) else fit_patch(patch_ds)
    psrc = patch.source
    sa = static_ds if isinstance(static_ds, StaticAnalysis) else analyse_static(static_ds)
    dyn = fit_dynamic_curves(dynamic_ds)
    rising = sa.select("peak")
    rising = rising[rising["mu"] > 0.0]
    lo, hi = dyn.fz.min() * (1 - static_fz_tolerance), dyn.fz.max() * (1 + static_fz_tolerance)
    use = rising[(rising["fz"] >= lo) & (rising["fz"] <= hi)]
    if len(use) < 10:
        raise FitError(f"{ssrc or 'static data'}: only {len(use)} static samples (rising part) lie within the "
                       f"dynamic loads {lo / G0:.0f}-{hi / G0:.0f} kg; the calibration needs the same tyre tested "
                       "on both rigs at overlapping loads")
    pressure = use["pressure"].to_numpy(float) if "pressure" in use else None
    fz = use["fz"].to_numpy(float)
    dy = np.abs(use["lateral_displacement"].to_numpy(float))
    u = dy / patch_length(patch, fz, pressure)
    mu_s = use["mu"].to_numpy(float)
    run = use["run"].to_numpy()
    mask = np.ones(u.size, bool)

    def residual(q, m):
        return dyn.mu(eq1_slip_angle(u[m], q[0], q[1]), fz[m]) - mu_s[m]

    q = np.array([1.0, 0.0])
    pars = Parameters()
    pars.add("n", 1.0, min=0.05, max=50.0, unit="-", meaning="Eq. 1 exponent")
    pars.add("b", 0.0, min=0.0, max=20.0, unit="-", meaning="Eq. 1 offset")
    for _ in range(3):
        fit = solve(lambda x: residual(x, mask), pars, starts=[q], cost="soft_l1", scale=0.01, x_scale=1.0,
                    what="rig calibration (Eq. 1)")
        q = fit.x
        new = eq1_slip_angle(u, *q) <= dyn.max_slip
        if np.array_equal(new, mask):
            break
        mask = new
    if mask.sum() < 10:
        raise FitError(f"{ssrc or 'static data'}: fewer than 10 static samples map inside the dynamic slip range")
    r = residual(q, mask)
    se = np.array([fit.stderr["n"], fit.stderr["b"]])  # least-squares approximation at the soft-l1 solution
    per_load = []
    for rr in sa.runs:
        m = mask & (run == rr.run)
        if m.sum() < 5:
            continue
        p1 = Parameters()
        p1.add("n", q[0], min=0.05, max=50.0)
        f1 = solve(lambda x: dyn.mu(eq1_slip_angle(u[m], x[0], 0.0), fz[m]) - mu_s[m], p1, cost="soft_l1",
                   scale=0.01, x_scale=1.0, stderr=False, what=f"rig calibration at {rr.load:.0f} N")
        per_load.append({"load_N": rr.load, "n_alone": float(f1.x[0]), "u_max": float(u[m].max()),
                         "points": int(m.sum())})
    alpha = eq1_slip_angle(u[mask], *q)
    cal = RigCalibration(
        n=float(q[0]), b=float(q[1]), n_stderr=float(se[0]), b_stderr=float(se[1]),
        u_range=(float(u[mask].min()), float(u[mask].max())),
        fz_range=(float(fz[mask].min()), float(fz[mask].max())),
        pressure_range=((float(np.min(pressure[mask])), float(np.max(pressure[mask]))) if pressure is not None
                        else (0.0, float("inf"))),
        slip_angle_range=(float(alpha.min()), float(alpha.max())),
        rmse_mu=float(np.sqrt(np.mean(r**2))), points=int(mask.sum()),
        source={"static": ssrc, "dynamic": dsrc, "patch": psrc}, per_load=per_load)
    cal._dynamic = dyn          # kept for reports (not serialised)
    cal._samples = pd.DataFrame({"run": run[mask], "u": u[mask], "fz": fz[mask], "mu_static": mu_s[mask],
                                 "slip_angle": alpha,
                                 "mu_dynamic": dyn.mu(alpha, fz[mask])})
    return cal
