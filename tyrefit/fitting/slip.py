"""Fit the slippage laws of Ghasemi et al. (2021) to slip-ratio and rolling-radius data.

* :func:`fit_friction_slip` fits ``mu = mu_p (1 - exp(-k s))`` (Ghasemi et al.,
  Eq. 8) to friction-slip points by least squares and derives the
  characteristic slip and friction (Eq. 15-17);
* :func:`fit_rolling_radius` fits the rolling radius against wheel torque
  (Eq. 18-19) and returns the longitudinal elasticity factor (Eq. 20);
* :func:`analyse_slip` runs both on a tidy slip-ratio table (one fit per
  load level) -- what ``tyrefit slip`` reports.

Containers carry their own ``plot(ax=None)`` and ``as_dict()``.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import pandas as pd
from ..errors import ColumnError, DataError, FitError
from ..models import slip as sl
from .core import Parameters, solve

__all__ = ["SlipFit", "RadiusFit", "SlipAnalysis", "fit_friction_slip", "fit_rolling_radius",
           "analyse_slip", "load_groups"]


@dataclass
class SlipFit:
    """Result of fitting Eq. 8 to friction-slip points.

    Attributes
    ----------
    mu_peak, k : float
        Fitted peak friction coefficient [-] and slip factor [-].
    mu_peak_stderr, k_stderr : float
        Standard errors from the Jacobian at the optimum.
    nu_c : float
        Characteristic curvature used [-].
    characteristic_slip, characteristic_mu : float
        Eq. 16 and Eq. 17 at the fitted values.
    rmse : float
        Root-mean-square residual of mu [-].
    n : int
        Number of points.
    fz : float or None
        Mean load of the points [N].
    slip, mu : ndarray
        The data fitted.
    """

    mu_peak: float
    k: float
    mu_peak_stderr: float
    k_stderr: float
    nu_c: float
    characteristic_slip: float
    characteristic_mu: float
    rmse: float
    n: int
    fz: float | None = None
    slip: np.ndarray = field(default_factory=lambda: np.zeros(0), repr=False)
    mu: np.ndarray = field(default_factory=lambda: np.zeros(0), repr=False)

    def predict(self, s):
        """mu(s) of the fitted law."""
        return sl.friction(s, self.mu_peak, self.k)

    def as_dict(self) -> dict:
        """The ``tyrefit slip --json`` keys (DESIGN) plus errors, rmse and point count."""
        d = {}
        if self.fz is not None:
            d["fz"] = round(float(self.fz), 1)
        d.update({
            "mu_peak": float(self.mu_peak),
            "k": float(self.k),
            "characteristic_curvature": float(self.nu_c),
            "characteristic_slip": float(self.characteristic_slip),
            "characteristic_mu": float(self.characteristic_mu),
            "mu_peak_stderr": float(self.mu_peak_stderr),
            "k_stderr": float(self.k_stderr),
            "rmse_mu": float(self.rmse),
            "n_points": int(self.n),
        })
        return d

    def plot(self, ax=None, label: str | None = None):
        """Data and fitted law, with the characteristic point (Ghasemi et al. 2021, Fig. 3); returns the Axes."""
        from matplotlib.figure import Figure

        if ax is None:
            ax = Figure().subplots()
        line = ax.plot(self.slip, self.mu, ".", ms=3, alpha=0.6)[0]
        lo, hi = (min(0.0, float(np.min(self.slip))), max(0.0, float(np.max(self.slip)))) if self.n else (0, 1)
        s = np.linspace(lo, hi, 300)
        lab = label or (f"Fz = {self.fz / 1e3:.2f} kN" if self.fz is not None else "fit")
        ax.plot(s, self.predict(s), "-", color=line.get_color(),
                label=f"{lab}: mu_p={self.mu_peak:.3f}, k={self.k:.1f}")
        for sign in (1, -1):
            if (sign > 0 and hi > 0) or (sign < 0 and lo < 0):
                ax.plot(sign * self.characteristic_slip, sign * self.characteristic_mu, "o", mfc="none",
                        color=line.get_color())
        ax.set_xlabel("slip s [-]")
        ax.set_ylabel("friction coefficient Fx/Fz [-]")
        ax.legend(fontsize=8)
        return ax


def fit_friction_slip(slip, mu, *, nu_c: float = sl.NU_C, fz: float | None = None) -> SlipFit:
    """Fit ``mu = mu_p (1 - exp(-k s))`` (Eq. 8) to points ``(slip, mu)``.

    Braking points (s < 0) are fitted with the odd extension of Eq. 8.

    Parameters
    ----------
    slip : array_like
        Slip [-].
    mu : array_like
        Friction coefficient Fx/Fz [-].
    nu_c : float
        Characteristic curvature [-] for Eq. 16-17 (default -2).
    fz : float, optional
        Load of the points [N] (reported only).

    Raises
    ------
    DataError
        Fewer than 4 finite points, or no slip beyond 0.005.
    FitError
        The least-squares fit did not converge.
    """
    s = np.asarray(slip, float)
    m = np.asarray(mu, float)
    ok = np.isfinite(s) & np.isfinite(m)
    s, m = s[ok], m[ok]
    if s.size < 4:
        raise DataError(f"friction-slip fit needs at least 4 points, got {s.size}")
    if np.max(np.abs(s)) < 5e-3:
        raise DataError(f"slip spans only +/-{np.max(np.abs(s)):.3g}; Eq. 8 needs slips beyond 0.005")
    # start: mu_p from the largest friction, k from the slope near the origin
    mu_p0 = max(float(np.max(np.abs(m))), 1e-3)
    small = np.abs(s) <= np.quantile(np.abs(s), 0.3)
    if np.count_nonzero(small & (s != 0)) >= 2:
        slope = float(np.sum(s[small] * m[small]) / np.sum(s[small] ** 2))
    else:
        slope = mu_p0 / np.median(np.abs(s[s != 0]))
    k0 = float(np.clip(abs(slope) / mu_p0, 0.5, 500.0))

    def resid(x):
        return sl.friction(s, x[0], x[1]) - m

    def jac(x):
        e = np.exp(-x[1] * np.abs(s))
        return np.column_stack([np.sign(s) * (1 - e), np.abs(s) * x[0] * e * np.sign(s)])

    pars = Parameters()
    pars.add("mu_peak", mu_p0, min=1e-6, max=10.0, unit="-", meaning="peak friction coefficient")
    pars.add("k", k0, min=1e-6, max=1e4, unit="-", meaning="slip stiffness coefficient of Eq. 8")
    # three starts of k (the exponential's rate): the one fitting core picks the lowest cost
    best = solve(resid, pars, jac=jac, starts=[[mu_p0, kk] for kk in (k0, 3 * k0, k0 / 3)],
                 what="friction-slip fit")
    if not best.success:  # pragma: no cover - trf always reports success on this smooth problem
        raise FitError(f"friction-slip fit did not converge: {best.message}")
    mu_p, k = (float(v) for v in best.x)
    err = np.array([best.stderr["mu_peak"], best.stderr["k"]])
    return SlipFit(mu_p, k, float(err[0]), float(err[1]), nu_c,
                   float(sl.characteristic_slip(mu_p, k, nu_c)), float(sl.characteristic_mu(mu_p, k, nu_c)),
                   best.rmse, int(s.size), fz, s, m)


@dataclass
class RadiusFit:
    """Rolling radius against wheel torque (Ghasemi et al. 2021, Eq. 18-20).

    ``r0`` is the free-rolling radius: from Eq. 20's kinematic form
    ``r = r0 (1 - s)`` by least squares when the slip is known, otherwise the
    zero-torque intercept of the small-torque fit.  ``lambda_0`` is the
    elasticity factor at small torque, from ``r0 - r = lambda_0 T + lambda_1 T^2``
    fitted over the lower half of the torque range (Eq. 19 with the first
    term of the nonlinear f of Eq. 18); ``lambda_w`` is Eq. 20 at each point.
    """

    r0: float
    lambda_0: float
    lambda_1: float
    rmse: float
    n: int
    torque: np.ndarray = field(repr=False)
    radius: np.ndarray = field(repr=False)
    slip: np.ndarray | None = field(default=None, repr=False)
    torque_fit_max: float = float("nan")

    @property
    def lambda_w(self) -> np.ndarray:
        """Eq. 20 at each data point [m/(N m)] (NaN at zero torque)."""
        return sl.elasticity_factor(self.r0, radius=self.radius, torque=self.torque)

    def slip_from_radius(self) -> np.ndarray:
        """Slip implied by the radius, ``s = (r0 - r) / r0`` (Eq. 20, second form)."""
        return (self.r0 - self.radius) / self.r0

    def as_dict(self) -> dict:
        d = {"r0": float(self.r0), "elasticity_factor": float(self.lambda_0),
             "elasticity_factor_quadratic": float(self.lambda_1), "rmse_m": float(self.rmse), "n_points": self.n,
             "r0_from": "slip (Eq. 20)" if self.slip is not None else "small-torque intercept"}
        lw = self.lambda_w
        big = np.abs(self.torque) > 0.2 * np.max(np.abs(self.torque))
        if np.any(big & np.isfinite(lw)):
            d["elasticity_factor_range"] = [float(np.nanmin(lw[big])), float(np.nanmax(lw[big]))]
        if self.slip is not None:
            d["slip_from_radius_rmse"] = float(np.sqrt(np.mean((self.slip_from_radius() - self.slip) ** 2)))
        return d

    def plot(self, ax=None):
        """Radius against torque with the small-torque law (Ghasemi et al. 2021, Fig. 6); returns the Axes."""
        from matplotlib.figure import Figure

        if ax is None:
            ax = Figure().subplots()
        ax.plot(self.torque, self.radius * 1e3, ".", ms=3, label="data")
        t = np.linspace(min(0, self.torque.min()), self.torque_fit_max, 200)
        ax.plot(t, (self.r0 - self.lambda_0 * t - self.lambda_1 * t**2) * 1e3, "-",
                label=f"r0 = {self.r0 * 1e3:.1f} mm, lambda_w(0) = {self.lambda_0 * 1e6:.3g} mm/kNm")
        ax.set_xlabel("wheel torque T [N m]")
        ax.set_ylabel("rolling radius r [mm]")
        ax.legend(fontsize=8)
        return ax


def fit_rolling_radius(torque, radius, slip=None) -> RadiusFit:
    """Free-rolling radius and elasticity factor from rolling radius [m] against torque [N m] (Eq. 18-20).

    Parameters
    ----------
    torque : array_like
        Wheel torque [N m].
    radius : array_like
        Instantaneous (kinematic) rolling radius v/omega [m].
    slip : array_like, optional
        Slip [-] at the same points; gives r0 from ``r = r0 (1 - s)`` (Eq. 20).

    Raises
    ------
    DataError
        Fewer than 3 points (in the lower half of the torque range) or no torque variation.
    """
    t = np.asarray(torque, float)
    r = np.asarray(radius, float)
    s = None if slip is None else np.asarray(slip, float)
    ok = np.isfinite(t) & np.isfinite(r) & (np.ones_like(t, bool) if s is None else np.isfinite(s))
    t, r = t[ok], r[ok]
    s = None if s is None else s[ok]
    if t.size < 3 or np.ptp(t) <= 0:
        raise DataError(f"rolling-radius fit needs at least 3 points with varying torque, got {t.size}")
    tmax = 0.5 * float(np.max(np.abs(t)))
    low = np.abs(t) <= tmax
    if np.count_nonzero(low) < 3:
        raise DataError("rolling-radius fit needs at least 3 points in the lower half of the torque range")
    if s is not None:
        one = 1.0 - s
        r0 = float(np.sum(r * one) / np.sum(one**2))  # Ghasemi et al., Eq. 20: r = r0 (1 - s)
        X = np.column_stack([t[low], t[low] ** 2])
        (l0, l1), *_ = np.linalg.lstsq(X, r0 - r[low], rcond=None)
        res = r[low] - (r0 - X @ np.array([l0, l1]))
    else:
        X = np.column_stack([np.ones(np.count_nonzero(low)), -t[low], -t[low] ** 2])
        (r0, l0, l1), *_ = np.linalg.lstsq(X, r[low], rcond=None)  # Eq. 19 with lambda_w = l0 + l1 T
        res = r[low] - X @ np.array([r0, l0, l1])
    return RadiusFit(float(r0), float(l0), float(l1), float(np.sqrt(np.mean(res**2))), int(t.size), t, r, s, tmax)


@dataclass
class SlipAnalysis:
    """Everything ``tyrefit slip`` reports: one :class:`SlipFit` per load, and the radius fit."""

    fits: list[SlipFit]
    radius: RadiusFit | None = None
    nu_c: float = sl.NU_C
    source: str = ""

    def as_dict(self) -> dict:
        """DESIGN's JSON: the keys of one fit, or ``{"loads": [...]}`` for several loads."""
        if len(self.fits) == 1:
            d = self.fits[0].as_dict()
        elif self.fits:
            d = {"characteristic_curvature": float(self.nu_c), "loads": [f.as_dict() for f in self.fits]}
        else:
            d = {"characteristic_curvature": float(self.nu_c)}
        if self.radius is not None:
            d["rolling_radius"] = self.radius.as_dict()
        return d

    def plot_friction(self, ax=None):
        """mu(s) for every load with the characteristic points; returns the Axes."""
        from matplotlib.figure import Figure

        if ax is None:
            ax = Figure().subplots()
        for f in self.fits:
            f.plot(ax)
        return ax

    def plot_curvature(self, ax=None):
        """Curvature of the fitted laws and the characteristic curvature (Ghasemi et al. 2021, Fig. 5)."""
        from matplotlib.figure import Figure

        if ax is None:
            ax = Figure().subplots()
        smax = max(float(np.max(np.abs(f.slip))) for f in self.fits)
        s = np.linspace(0, smax, 300)
        for f in self.fits:
            lab = f"Fz = {f.fz / 1e3:.2f} kN" if f.fz is not None else "fit"
            line = ax.plot(s, sl.curvature(s, f.mu_peak, f.k), label=lab)[0]
            ax.axvline(f.characteristic_slip, color=line.get_color(), ls=":", lw=1)
        ax.axhline(self.nu_c, color="k", ls="--", lw=1, label=f"nu_c = {self.nu_c:g}")
        lo = min(self.nu_c * 3, min(float(sl.curvature(0.0, f.mu_peak, f.k)) for f in self.fits))
        ax.set_ylim(max(lo, self.nu_c * 20), 0.5)
        ax.set_xlabel("slip s [-]")
        ax.set_ylabel("curvature d2mu/ds2 [-]")
        ax.legend(fontsize=8)
        return ax

    def plot_mobility(self, ax=None, modified: bool = True):
        """Mobility-agility index against slip (Ghasemi et al. 2021, Fig. 7-8); returns the Axes."""
        from matplotlib.figure import Figure

        if ax is None:
            ax = Figure().subplots()
        smax = max(float(np.max(np.abs(f.slip))) for f in self.fits)
        s = np.linspace(0, smax, 400)
        for f in self.fits:
            lab = f"Fz = {f.fz / 1e3:.2f} kN" if f.fz is not None else "fit"
            if modified:
                y = sl.modified_mobility_agility_index(s, f.mu_peak, f.k, self.nu_c)
            else:
                y = sl.mobility_agility_index(s, f.mu_peak, f.k)
            ax.plot(s, y, label=lab)
        ax.set_xlabel("slip s [-]")
        ax.set_ylabel("modified WMAI [-]" if modified else "WMAI [-]")
        ax.legend(fontsize=8)
        return ax


def load_groups(df: pd.DataFrame, rtol: float = 0.05, atol: float = 100.0) -> list[tuple[float, pd.DataFrame]]:
    """Split a slip-ratio table by load level: runs whose mean load (``load`` set point, else ``fz``)
    lie within max(100 N, 5 %) of each other form one group.  Returns ``[(mean load [N], rows), ...]``."""
    col = "load" if "load" in df else "fz"
    key = df["run"] if "run" in df else pd.Series(0, index=df.index)
    means = df.groupby(key)[col].mean().sort_values()
    groups: list[list] = []
    for run, v in means.items():
        if groups and abs(v - groups[-1][-1][1]) <= max(atol, rtol * abs(v)):
            groups[-1].append((run, v))
        else:
            groups.append([(run, v)])
    out = []
    for g in groups:
        runs = [r for r, _ in g]
        rows = df[key.isin(runs)]
        out.append((float(rows["fz"].mean()), rows))
    return out


def analyse_slip(df: pd.DataFrame, *, nu_c: float = sl.NU_C, source: str = "") -> SlipAnalysis:
    """Fit the slippage laws of Ghasemi et al. (2021) to a tidy slip-ratio table.

    Parameters
    ----------
    df : DataFrame
        Canonical SI columns: ``slip_ratio``, ``fx``, ``fz`` (and ``run``,
        ``load``) for the friction law; ``torque`` and ``rolling_radius`` for
        Eq. 19-20 when present.
    nu_c : float
        Characteristic curvature [-].
    source : str
        Name of the data (for messages).

    Raises
    ------
    ColumnError
        Neither friction (slip_ratio, fx, fz) nor radius (torque, rolling_radius) columns.
    """
    where = f"{source}: " if source else ""
    has_mu = all(c in df for c in ("slip_ratio", "fx", "fz"))
    has_r = all(c in df for c in ("torque", "rolling_radius"))
    if not has_mu and not has_r:
        raise ColumnError(f"{where}slip analysis needs 'slip_ratio', 'fx' and 'fz' (friction-slip law) or "
                          f"'torque' and 'rolling_radius' (Eq. 19-20); found {', '.join(map(str, df.columns))}")
    fits = []
    if has_mu:
        for fz, rows in load_groups(df):
            if np.any(rows["fz"].to_numpy() <= 0):
                raise DataError(f"{where}loads must be positive to form mu = Fx/Fz")
            mu = rows["fx"].to_numpy(float) / rows["fz"].to_numpy(float)
            try:
                fits.append(fit_friction_slip(rows["slip_ratio"].to_numpy(float), mu, nu_c=nu_c, fz=fz))
            except DataError as exc:
                raise DataError(f"{where}load {fz:.0f} N: {exc}") from None
    radius = None
    if has_r:
        radius = fit_rolling_radius(df["torque"].to_numpy(float), df["rolling_radius"].to_numpy(float),
                                    df["slip_ratio"].to_numpy(float) if "slip_ratio" in df else None)
    return SlipAnalysis(fits, radius, nu_c, source)
