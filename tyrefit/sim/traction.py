"""Treadwear versus traction, stopping distances and the hard tyre's emission factor.

Pham et al. 2025 (Sec. 3.1 and 4.1):

* stopping distance with aerodynamic drag and rolling resistance (Eq. 15-16,
  after HPwizard)::

      d = ln(1 + K v0^2 / (mu + f_r)) / (2 g K),   K = rho C_D A / (2 m g)  [s^2/m^2]

* its inverse, the tyre's peak friction from a measured stopping distance
  (Eq. 41)::

      mu = K v0^2 / (exp(2 g K d) - 1) - f_r

* the treadwear-traction power law fitted on UTQG treadwear grades and Tire
  Rack stopping distances (Eq. 42), mu = a TW^-b; HPwizard's law is
  a = 2.25, b = 0.15;
* wear is proportional to 1/TW, so a hard tyre of peak friction mu_h emits
  k = TW_s / TW_h = (mu_h / mu_s)^(1/b) times what the soft tyre emits (Eq. 43);
* the vehicle's peak friction with different tyres front and rear (Eq. 17)
  and its peak lateral acceleration (Eq. 18).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import DataError, FitError
from ..fitting.core import Parameters, solve
from ..io.readers import read_data
from ..nomenclature import G0

__all__ = [
    "HPWIZARD",
    "K_TYPICAL",
    "F_R_TYPICAL",
    "drag_constant",
    "stopping_distance",
    "mu_from_stopping_distance",
    "TractionFit",
    "fit_treadwear_traction",
    "emission_ratio",
    "vehicle_peak_friction",
    "peak_lateral_acceleration",
    "TractionTable",
    "traction_from_data",
]

#: HPwizard's treadwear-traction law mu = a TW^-b (Pham et al. 2025, ref. [37])
HPWIZARD = {"a": 2.25, "b": 0.15}
#: HPwizard's typical K = rho C_D A / (2 m g) [s^2/m^2] and rolling resistance f_r [-]
K_TYPICAL = 6.58e-5
F_R_TYPICAL = 0.013


def drag_constant(drag: float, mass: float, g: float = G0) -> float:
    """K = C_d / (m g) [s^2/m^2] for a drag force C_d v^2 (C_d = rho C_D A / 2 [kg/m]) (Eq. 16)."""
    return drag / (mass * g)


def stopping_distance(v0, mu, K: float = K_TYPICAL, f_r: float = F_R_TYPICAL, g: float = G0):
    """Stopping distance [m] from speed ``v0`` [m/s] at peak friction ``mu`` (Pham et al. 2025, Eq. 15).

    ``K`` = 0 gives the drag-free limit v0^2 / (2 g (mu + f_r)).
    """
    v0 = np.asarray(v0, dtype=float)
    mu = np.asarray(mu, dtype=float)
    if K == 0:
        return v0**2 / (2.0 * g * (mu + f_r))
    return np.log1p(K * v0**2 / (mu + f_r)) / (2.0 * g * K)          # Eq. 15


def mu_from_stopping_distance(d, v0, K: float = K_TYPICAL, f_r: float = F_R_TYPICAL, g: float = G0):
    """Peak friction coefficient from a stopping distance ``d`` [m] from ``v0`` [m/s] (Pham et al. 2025, Eq. 41)."""
    d = np.asarray(d, dtype=float)
    v0 = np.asarray(v0, dtype=float)
    if K == 0:
        return v0**2 / (2.0 * g * d) - f_r
    return K * v0**2 / np.expm1(2.0 * g * K * d) - f_r                # Eq. 41


def emission_ratio(mu_hard, mu_soft, b: float = HPWIZARD["b"]):
    """k = TW_s / TW_h = (mu_h / mu_s)^(1/b): hard-tyre emission as a share of the soft tyre's (Eq. 43)."""
    return (np.asarray(mu_hard, float) / np.asarray(mu_soft, float)) ** (1.0 / b)


def vehicle_peak_friction(mu_front, mu_rear, lf: float, lr: float):
    """Vehicle peak friction with static axle loads: (l_r mu_f + l_f mu_r) / (l_f + l_r) (Eq. 17)."""
    return (lr * np.asarray(mu_front, float) + lf * np.asarray(mu_rear, float)) / (lf + lr)


def peak_lateral_acceleration(mu_y_front, mu_y_rear, g: float = G0):
    """a_y,max ~ g min(mu_y,f, mu_y,r) [m/s^2] (Eq. 18)."""
    return g * np.minimum(mu_y_front, mu_y_rear)


@dataclass(frozen=True)
class TractionFit:
    """mu = a TW^-b fitted to (treadwear, mu) pairs (Pham et al. 2025, Eq. 42)."""

    a: float
    b: float
    a_stderr: float
    b_stderr: float
    r2: float
    rmse: float
    treadwear: np.ndarray
    mu: np.ndarray

    def predict(self, treadwear):
        """mu at UTQG treadwear ``treadwear``."""
        return self.a * np.asarray(treadwear, float) ** (-self.b)

    def treadwear_for(self, mu):
        """Treadwear grade whose fitted mu is ``mu`` (inverse of Eq. 42)."""
        return (np.asarray(mu, float) / self.a) ** (-1.0 / self.b)

    def k(self, mu_hard, mu_soft) -> float:
        """Hard-tyre emission factor with this fit's exponent (Eq. 43)."""
        return float(emission_ratio(mu_hard, mu_soft, self.b))

    def to_dict(self) -> dict:
        return {"a": self.a, "b": self.b, "a_stderr": self.a_stderr, "b_stderr": self.b_stderr,
                "r2": self.r2, "rmse": self.rmse, "n_tyres": int(self.treadwear.size),
                "hpwizard": dict(HPWIZARD)}

    def plot(self, ax=None):
        """Data, this fit and HPwizard's law over the treadwear range."""
        from matplotlib.figure import Figure

        if ax is None:
            ax = Figure(figsize=(6, 4)).subplots()
        ax.plot(self.treadwear, self.mu, "o", label="tyres (Eq. 41 from stopping distance)")
        tw = np.linspace(min(100.0, self.treadwear.min()), max(900.0, self.treadwear.max()), 300)
        ax.plot(tw, self.predict(tw), "-", label=f"fit: mu = {self.a:.3g} TW^-{self.b:.3g}")
        ax.plot(tw, HPWIZARD["a"] * tw ** -HPWIZARD["b"], "--",
                label=f"HPwizard: mu = {HPWIZARD['a']} TW^-{HPWIZARD['b']}")
        ax.set_xlabel("UTQG treadwear [-]")
        ax.set_ylabel("peak friction coefficient mu [-]")
        ax.legend()
        return ax


def fit_treadwear_traction(treadwear, mu) -> TractionFit:
    """Fit mu = a TW^-b by least squares on mu (Pham et al. 2025, Eq. 42).

    The start comes from the straight line ln mu = ln a - b ln TW; the final
    fit is nonlinear least squares on mu itself (the fitting core,
    :func:`tyrefit.fitting.core.solve`), with standard errors from its Jacobian.
    """
    tw = np.asarray(treadwear, dtype=float).ravel()
    mu = np.asarray(mu, dtype=float).ravel()
    if tw.size != mu.size:
        raise DataError(f"treadwear and mu differ in length ({tw.size} vs {mu.size})")
    if tw.size < 3:
        raise DataError(f"the treadwear-traction fit needs at least 3 tyres, got {tw.size}")
    if np.any(tw <= 0):
        raise DataError(f"treadwear grades must be positive; found {tw[tw <= 0][0]:g}")
    if np.any(mu <= 0):
        raise DataError(f"friction coefficients must be positive; found {mu[mu <= 0][0]:.4g} "
                        "(a stopping distance too long for its speed?)")
    if np.ptp(tw) <= 0:
        raise DataError("all tyres have the same treadwear grade; the fit needs a range")
    slope, intercept = np.polyfit(np.log(tw), np.log(mu), 1)
    p0 = (float(np.exp(intercept)), float(-slope))
    pars = Parameters()
    pars.add("a", p0[0], meaning="friction at TW = 1")
    pars.add("b", p0[1], meaning="exponent of the treadwear grade")
    try:
        sol = solve(lambda v: v[0] * tw ** (-v[1]) - mu, pars, x_scale=1.0, max_nfev=10000,
                    what="treadwear-traction fit")
    except (FitError, ValueError) as exc:  # pragma: no cover - well-posed for positive data
        raise FitError(f"treadwear-traction fit did not converge: {exc}") from None
    popt = sol.x
    err = np.array([sol.stderr["a"], sol.stderr["b"]])
    pred = popt[0] * tw ** (-popt[1])
    ss_res = float(np.sum((mu - pred) ** 2))
    ss_tot = float(np.sum((mu - mu.mean()) ** 2))
    return TractionFit(a=float(popt[0]), b=float(popt[1]), a_stderr=float(err[0]), b_stderr=float(err[1]),
                       r2=1.0 - ss_res / ss_tot if ss_tot > 0 else float("nan"),
                       rmse=float(np.sqrt(ss_res / tw.size)), treadwear=tw, mu=mu)


@dataclass(frozen=True)
class TractionTable:
    """Tyres of a braking/UTQG table with their friction (Eq. 41) and the Eq. 42 fit."""

    names: list
    treadwear: np.ndarray
    stopping_distance: np.ndarray
    initial_speed: np.ndarray
    mu: np.ndarray
    fit: TractionFit
    K: float
    f_r: float
    source: str = ""

    def rows(self) -> list[dict]:
        return [{"name": str(n), "treadwear": float(t), "stopping_distance_m": float(d),
                 "initial_speed_mps": float(v), "mu": float(m), "mu_fit": float(self.fit.predict(t))}
                for n, t, d, v, m in zip(self.names, self.treadwear, self.stopping_distance,
                                         self.initial_speed, self.mu)]


def traction_from_data(data, K: float = K_TYPICAL, f_r: float = F_R_TYPICAL) -> TractionTable:
    """From a braking table (``treadwear``, ``stopping_distance``, ``initial_speed``) to the Eq. 42 fit.

    Parameters
    ----------
    data : path, Dataset or DataFrame
        With canonical SI columns ``treadwear`` [-], ``stopping_distance`` [m],
        ``initial_speed`` [m/s] and optionally ``name``.
    K, f_r : float
        Drag constant [s^2/m^2] and rolling resistance of Eq. 41 (HPwizard's typical values).
    """
    import pandas as pd

    source = ""
    if isinstance(data, (str, bytes)) or hasattr(data, "__fspath__"):
        source = str(data)
        data = read_data(data, kind="braking")
    df = getattr(data, "df", data)
    source = source or getattr(data, "source", "")
    if not isinstance(df, pd.DataFrame):
        raise DataError("traction data must be a file, a Dataset or a DataFrame")
    missing = [c for c in ("treadwear", "stopping_distance", "initial_speed") if c not in df]
    if missing:
        raise DataError(f"{source or 'traction data'}: missing column(s) {', '.join(missing)}; a braking table "
                        "needs 'treadwear [-]', 'stopping_distance [m|ft]' and 'initial_speed [km/h|mph|m/s]'")
    d = df["stopping_distance"].to_numpy(float)
    v0 = df["initial_speed"].to_numpy(float)
    tw = df["treadwear"].to_numpy(float)
    names = list(df["name"]) if "name" in df else [f"tyre {i + 1}" for i in range(len(df))]
    mu = mu_from_stopping_distance(d, v0, K=K, f_r=f_r)
    bad = ~(mu > 0)
    if bad.any():
        i = int(np.flatnonzero(bad)[0])
        raise DataError(f"{source or 'traction data'}: tyre {names[i]!r}: stopping distance {d[i]:.4g} m from "
                        f"{v0[i]:.4g} m/s gives mu = {mu[i]:.4g} <= 0; check the units of the distance and speed")
    return TractionTable(names=names, treadwear=tw, stopping_distance=d, initial_speed=v0, mu=mu,
                         fit=fit_treadwear_traction(tw, mu), K=K, f_r=f_r, source=source)
