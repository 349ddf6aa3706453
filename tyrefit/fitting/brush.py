"""Fit the camber brush models (Zhang et al. 2024) to contact-patch, pressure and force data.

The paper builds its model in stages, and so does this module:

1. contact width against load, pressure and camber (Eq. 1):
   :func:`fit_contact_width` (columns ``width``, ``fz`` or ``load``,
   ``pressure``, ``camber``);
2. pressure across the width: concavity and bias of one measured profile
   (Eq. 6-8, :func:`fit_width_profile`) and their laws in load, pressure
   and camber (Eq. 9-10, :func:`fit_width_laws`);
3. contact length against line load and pressure (Eq. 11, 27):
   :func:`fit_contact_length` (columns ``length``, ``fz``/``load``,
   ``pressure`` and optionally ``camber``), given the width laws;
4. tread stiffness, length-direction concavity and friction from force
   sweeps (Eq. 17-30): :func:`fit_brush_forces` (columns ``fz``,
   ``slip_angle`` and/or ``slip_ratio``, ``fy`` and/or ``fx``, optionally
   ``camber``, ``pressure``), for either model.

:func:`calibrate_original` fits the original model to the zero-camber forces
of an improved model: the "same tyre" described by the simpler model, used
by the adhesion estimator to compare the two (Zhang et al. 2024, Fig. 16-17).

Fits state their parameters (value, bounds, vary) as
:class:`tyrefit.fitting.core.Parameters`, are solved by the one fitting core
(:func:`tyrefit.fitting.core.solve`: bounded least squares, finite-difference
Jacobian, unit x-scale, as lmfit's ``least_squares`` method did before) and
return :class:`BrushFitResult` with the fitted
:class:`~tyrefit.models.brush.BrushParams`.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import pandas as pd

from ..errors import ColumnError, DataError, FitError
from ..models import brush as bm
from .core import Parameters, Solution, solve

__all__ = [
    "BrushFitResult",
    "BOUNDS",
    "fit_contact_width",
    "fit_width_profile",
    "fit_width_laws",
    "fit_contact_length",
    "fit_brush_forces",
    "calibrate_original",
]

#: bounds of the fitted parameters (SI)
BOUNDS: dict[str, tuple[float, float]] = {
    "b0": (0.01, 0.5), "b1": (0.0, 5.0), "b2": (-5.0, 5.0), "b3": (-5.0, 5.0),
    "qy1": (-20, 20), "qy2": (-20, 20), "qy3": (-0.99, 20), "qy4": (0.0, 2.0), "qy5": (0.2, 4.0),
    "a_ref": (0.005, 0.5), "a2": (0.05, 2.0), "a3": (-2.0, 2.0),
    "qx1": (-5, 5), "qx2": (-5, 5), "qx3": (-0.19, 2.9),
    "r_ref": (0.05, 2.0), "c2": (-1.0, 1.0), "c3": (-1.0, 1.0),
    "kx": (1e5, 1e10), "ky": (1e5, 1e10), "mu": (0.05, 3.0),
}


@dataclass
class BrushFitResult:
    """Outcome of a brush-model fit.

    Attributes
    ----------
    params : BrushParams
        Fitted parameters (the others as given).
    mu : float or None
        Fitted friction coefficient (force fits).
    varied : tuple of str
        Names that were fitted.
    rmse : dict
        Root-mean-square residual of each fitted quantity (SI units).
    solution : Solution
        The fitting core's result (values, standard errors, cost), None for linear fits.
    what : str
        Which fit.
    """

    params: bm.BrushParams
    mu: float | None
    varied: tuple[str, ...]
    rmse: dict[str, float]
    solution: Solution | None = field(default=None, repr=False)
    what: str = ""

    def values(self) -> dict[str, float]:
        """The fitted values and their standard errors (nonlinear fits)."""
        out = {}
        if self.solution is not None:
            for k in self.varied:
                p = self.solution.params[k]
                out[k] = p.value
                out[k + "_stderr"] = p.stderr if p.stderr is not None else float("nan")
        return out

    def report(self) -> str:
        lines = [f"{self.what}: " + ", ".join(f"{k} = {v:.6g}" for k, v in self.values().items()
                                             if not k.endswith("_stderr"))]
        lines.append("rmse: " + ", ".join(f"{k} = {v:.4g}" for k, v in self.rmse.items()))
        return "\n".join(lines)


def _parameters(base: bm.BrushParams, vary, mu: float | None = None) -> Parameters:
    pars = Parameters()
    for name in vary:
        lo, hi = BOUNDS[name]
        val = mu if name == "mu" else getattr(base, name)
        pars.add(name, value=float(np.clip(val, lo + 1e-12 * abs(lo), hi)), min=lo, max=hi)
    return pars


def _apply(base: bm.BrushParams, vals: dict) -> tuple[bm.BrushParams, float | None]:
    vals = dict(vals)
    mu = vals.pop("mu", None)
    return base.replace(**vals), mu


def _minimize(fun, pars: Parameters, what: str) -> Solution:
    """Solve with the fitting core; ``fun`` takes name -> value (every parameter)."""
    try:
        res = solve(lambda x: fun(pars.values_of(x)), pars, x_scale=1.0, max_nfev=4000 * (len(pars.free()) + 1),
                    what=what)
    except (ValueError, FloatingPointError) as exc:
        raise FitError(f"{what}: fit failed ({exc})") from None
    if not np.all(np.isfinite(res.resid)):
        raise FitError(f"{what}: residuals are not finite at the solution")
    return res


def _load(df: pd.DataFrame, where: str) -> np.ndarray:
    if "fz" in df:
        return df["fz"].to_numpy(float)
    if "load" in df:
        return df["load"].to_numpy(float)
    raise ColumnError(f"{where}: needs 'fz' or 'load'")


def _need(df, cols, where):
    miss = [c for c in cols if c not in df]
    if miss:
        raise ColumnError(f"{where}: missing column(s) {', '.join(repr(c) for c in miss)}; "
                          f"found {', '.join(map(str, df.columns))}")


def _col(df, name, default):
    return df[name].to_numpy(float) if name in df else np.full(len(df), float(default))


# --- 1. contact width -----------------------------------------------------------------------
def fit_contact_width(df: pd.DataFrame, base: bm.BrushParams = bm.DEFAULT_PARAMS,
                      vary=("b0", "b1", "b2", "b3")) -> BrushFitResult:
    """Fit Eq. 1, ``2b = 2 b0 - b1 (fz/fz_ref)^b2 (p/p_ref)^-b3 |gamma|``, to contact widths.

    Parameters
    ----------
    df : DataFrame
        ``width`` [m], ``fz`` or ``load`` [N], ``camber`` [rad], ``pressure`` [Pa]
        (defaults to ``base.p_ref`` when absent).
    """
    where = "contact-width fit"
    _need(df, ["width", "camber"], where)
    fz = _load(df, where)
    cam = df["camber"].to_numpy(float)
    pr = _col(df, "pressure", base.p_ref)
    w = df["width"].to_numpy(float)
    if np.count_nonzero(np.abs(cam) > np.deg2rad(0.5)) < 2:
        raise DataError(f"{where}: needs widths at two or more non-zero cambers (Eq. 1's camber term)")
    if np.ptp(fz) <= 0.05 * np.mean(fz):
        vary = tuple(v for v in vary if v != "b2")
    if np.ptp(pr) <= 0.05 * np.mean(pr):
        vary = tuple(v for v in vary if v != "b3")
    pars = _parameters(base, vary)

    def resid(pp):
        p, _ = _apply(base, pp)
        return 2 * bm.contact_half_width(p, fz, pr, cam) - w

    res = _minimize(resid, pars, where)
    p, _ = _apply(base, res.values)
    return BrushFitResult(p, None, tuple(vary), {"width": float(res.rmse)}, res, where)


# --- 2. width pressure ---------------------------------------------------------------------
def fit_width_profile(v, pressure) -> tuple[float, float, float]:
    """Concavity lambda_y and bias B_y of one pressure profile across the width (Eq. 6-8).

    Parameters
    ----------
    v : array_like
        Relative width position y/b in [-1, 1].
    pressure : array_like
        Pressure (or path sum, any unit) at those positions.

    Returns
    -------
    lambda_y, B_y, delta_over_b : float
        Concavity factor, bias coefficient of Eq. 6 and the centroid shift
        Delta_y/b it implies (Eq. 8: ``Delta_y/b = B_y (7 + 3 lambda) / (7 (5 + lambda))``).
    """
    v = np.asarray(v, float)
    q = np.asarray(pressure, float)
    if v.size < 4:
        raise DataError(f"width-profile fit needs at least 4 points, got {v.size}")
    if np.any(np.abs(v) > 1):
        raise DataError("width-profile positions must be relative, |y/b| <= 1")
    scale0 = float(np.mean(q) / np.mean(bm.width_pressure_shape(v, 0.0, 0.0)))
    pars = Parameters()
    pars.add("scale", scale0, min=0)
    pars.add("lam", 0.5, min=-0.99, max=20)
    pars.add("B", 0.0, min=-1, max=1)

    def resid(pp):
        return pp["scale"] * bm.width_pressure_shape(v, pp["lam"], pp["B"]) - q

    res = _minimize(resid, pars, "width-profile fit")
    lam, B = res.values["lam"], res.values["B"]
    return float(lam), float(B), float(B * (7 + 3 * lam) / (7 * (5 + lam)))


def fit_width_laws(table: pd.DataFrame, base: bm.BrushParams = bm.DEFAULT_PARAMS) -> BrushFitResult:
    """Fit the laws of lambda_y (Eq. 9) and Delta_y (Eq. 10, 24) to fitted profiles.

    Parameters
    ----------
    table : DataFrame
        One row per profile: ``fz`` [N], ``pressure`` [Pa], ``camber`` [rad],
        ``lambda_y`` [-], ``delta_y`` [m] (e.g. ``delta_over_b * b`` from
        :func:`fit_width_profile`).
    """
    where = "width-pressure laws"
    _need(table, ["fz", "pressure", "camber", "lambda_y", "delta_y"], where)
    fz = table["fz"].to_numpy(float)
    pr = table["pressure"].to_numpy(float)
    g = table["camber"].to_numpy(float)
    lam = table["lambda_y"].to_numpy(float)
    dy = table["delta_y"].to_numpy(float)
    # Eq. 9 is linear in qy1..qy3
    X = np.column_stack([fz / base.fz_ref - 1, pr / base.p_ref - 1, np.ones_like(fz)])
    (q1, q2, q3), *_ = np.linalg.lstsq(X, lam, rcond=None)
    # Eq. 10: Delta = sign(g) qy4 |g|^qy5, a straight line in logs over the cambered profiles
    m = (np.abs(g) > np.deg2rad(0.5)) & (np.sign(dy) == np.sign(g)) & (dy != 0)
    if np.count_nonzero(m) >= 2 and np.ptp(np.log(np.abs(g[m]))) > 0:
        q5, lq4 = np.polyfit(np.log(np.abs(g[m])), np.log(np.abs(dy[m])), 1)
        q4 = float(np.exp(lq4))
    elif np.count_nonzero(m) >= 1:
        q5 = 1.0
        q4 = float(np.mean(np.abs(dy[m]) / np.abs(g[m])))
    else:
        raise DataError(f"{where}: no cambered profile with a bias to the leaning side")
    p = base.replace(qy1=float(q1), qy2=float(q2), qy3=float(q3), qy4=q4, qy5=float(q5))
    rl = lam - X @ np.array([q1, q2, q3])
    rd = dy - bm.width_bias(p, g)
    return BrushFitResult(p, None, ("qy1", "qy2", "qy3", "qy4", "qy5"),
                          {"lambda_y": float(np.sqrt(np.mean(rl**2))), "delta_y": float(np.sqrt(np.mean(rd**2)))},
                          None, where)


# --- 3. contact length ---------------------------------------------------------------------
def fit_contact_length(df: pd.DataFrame, base: bm.BrushParams = bm.DEFAULT_PARAMS, n: int = 10,
                       vary=("a_ref", "a2", "a3")) -> BrushFitResult:
    """Fit the half-length law (Eq. 11) to contact-patch lengths: length = 2 max_i a(q_i).

    The width laws of ``base`` (Eq. 1, 9, 10) give the strips' line loads.

    Parameters
    ----------
    df : DataFrame
        ``length`` [m], ``fz`` or ``load`` [N], optionally ``pressure`` [Pa] and ``camber`` [rad].
    """
    where = "contact-length fit"
    _need(df, ["length"], where)
    fz = _load(df, where)
    pr = _col(df, "pressure", base.p_ref)
    cam = _col(df, "camber", 0.0)
    L = df["length"].to_numpy(float)
    if np.ptp(pr) <= 0.05 * np.mean(pr):
        vary = tuple(v for v in vary if v != "a3")
    if np.ptp(fz) <= 0.05 * np.mean(fz):
        vary = tuple(v for v in vary if v != "a2")
    pars = _parameters(base, vary)

    def resid(pp):
        p, _ = _apply(base, pp)
        return bm.contact_length(p, fz, pr, cam, n) - L

    res = _minimize(resid, pars, where)
    p, _ = _apply(base, res.values)
    return BrushFitResult(p, None, tuple(vary), {"length": float(res.rmse)}, res, where)


# --- 4. forces -----------------------------------------------------------------------------
def _predict(model, p, fz, kappa, alpha, gam, pr, mu, n):
    if model == "improved":
        return bm.camber_brush_forces(p, fz, kappa, alpha, gam, pr, mu, n=n)
    return bm.brush_forces(p, fz, kappa, alpha, gam, pr, mu)


def fit_brush_forces(df: pd.DataFrame, base: bm.BrushParams = bm.DEFAULT_PARAMS, *, model: str = "improved",
                     vary=("kx", "ky", "qx3", "mu"), mu: float = 1.0, n: int = 10) -> BrushFitResult:
    """Fit brush parameters (and mu) to force sweeps.

    Parameters
    ----------
    df : DataFrame
        ``fz`` [N] and at least one of (``slip_angle`` [rad], ``fy`` [N]) or
        (``slip_ratio`` [-], ``fx`` [N]); optionally ``camber`` [rad],
        ``pressure`` [Pa].  Missing slips are zero; a force that is missing is
        not fitted.
    base : BrushParams
        Start values and the parameters that are not fitted (geometry).
    model : {'improved', 'original'}
    vary : sequence of str
        Names to fit (fields of BrushParams, and ``'mu'``).
    mu : float
        Friction coefficient (start value when fitted).
    n : int
        2N strips of the improved model.

    Notes
    -----
    Residuals are force over load, so loads weigh alike.
    """
    where = "brush force fit"
    if model not in ("improved", "original"):
        raise ValueError(f"model must be 'improved' or 'original', got {model!r}")
    fz = _load(df, where)
    has_y = "fy" in df
    has_x = "fx" in df
    if not (has_x or has_y):
        raise ColumnError(f"{where}: needs 'fy' (with 'slip_angle') or 'fx' (with 'slip_ratio')")
    kappa = _col(df, "slip_ratio", 0.0)
    alpha = _col(df, "slip_angle", 0.0)
    gam = _col(df, "camber", 0.0)
    pr = _col(df, "pressure", base.p_ref)
    fx_d = df["fx"].to_numpy(float) if has_x else None
    fy_d = df["fy"].to_numpy(float) if has_y else None
    if len(df) < len(vary) + 1:
        raise DataError(f"{where}: {len(df)} points for {len(vary)} parameters")
    pars = _parameters(base, vary, mu)

    def resid(pp):
        p, m = _apply(base, pp)
        f = _predict(model, p, fz, kappa, alpha, gam, pr, mu if m is None else m, n)
        parts = []
        if has_x:
            parts.append((f.fx - fx_d) / fz)
        if has_y:
            parts.append((f.fy - fy_d) / fz)
        return np.concatenate(parts)

    res = _minimize(resid, pars, where)
    p, m = _apply(base, res.values)
    f = _predict(model, p, fz, kappa, alpha, gam, pr, mu if m is None else m, n)
    rmse = {}
    if has_x:
        rmse["fx"] = float(np.sqrt(np.mean((f.fx - fx_d) ** 2)))
    if has_y:
        rmse["fy"] = float(np.sqrt(np.mean((f.fy - fy_d) ** 2)))
    return BrushFitResult(p, mu if m is None else m, tuple(vary), rmse, res, f"{where} ({model} model)")


def calibrate_original(improved: bm.BrushParams = bm.DEFAULT_PARAMS, *, n: int = 8,
                       loads=(2500.0, 3500.0, 4500.0, 5500.0, 6500.0), mus=(0.3, 0.6, 1.0),
                       pressure: float | None = None,
                       vary=("a_ref", "a2", "r_ref", "c3", "kx", "ky", "qx1", "qx3")) -> BrushFitResult:
    """The original camber brush model fitted to the zero-camber forces of an improved model.

    Both models see the same wheel kinematics (``V_x = 1``, ``V_y = tan(alpha)``,
    ``omega = (1 + kappa) / R0`` with R0 the improved tyre's free-rolling radius
    at each load), pure and combined slip up to kappa = +/-0.25 and
    alpha = +/-10 deg, on roads of mu = 0.3, 0.6 and 1.  Without camber the two models then describe the
    same tyre; with camber they differ by what the original model leaves out
    (width loss, load bias, strip radii): Zhang et al. 2024, Fig. 17.
    """
    pressure = improved.p_ref if pressure is None else pressure
    kap = np.linspace(-0.25, 0.25, 21)
    alp = np.deg2rad(np.linspace(-10, 10, 11))
    K, A = np.meshgrid(kap, alp[::2], indexing="ij")
    grid_k = np.concatenate([kap, 0 * alp, K.ravel()])
    grid_a = np.concatenate([0 * kap, alp, A.ravel()])
    mus = np.asarray(mus, float)
    fz = np.repeat(np.tile(np.asarray(loads, float), mus.size), grid_k.size)
    mu = np.repeat(mus, len(loads) * grid_k.size)
    kk = np.tile(grid_k, len(loads) * mus.size)
    aa = np.tile(grid_a, len(loads) * mus.size)
    st = bm.strip_states(improved, fz, pressure, 0.0, n)
    r0 = bm.free_rolling_radius(st)
    vx = np.ones_like(fz)
    vy = np.tan(aa)
    om = (1 + kk) / r0
    ref = bm.camber_brush_forces(improved, fz, 0, 0, 0.0, pressure, mu, n=n, vx=vx, vy=vy, omega=om)
    pars = _parameters(improved, vary)

    def resid(pp):
        p, _ = _apply(improved, pp)
        f = bm.brush_forces(p, fz, 0, 0, 0.0, pressure, mu, vx=vx, vy=vy, omega=om)
        return np.concatenate([(f.fx - ref.fx) / fz, (f.fy - ref.fy) / fz])

    res = _minimize(resid, pars, "original-model calibration")
    p, _ = _apply(improved, res.values)
    f = bm.brush_forces(p, fz, 0, 0, 0.0, pressure, mu, vx=vx, vy=vy, omega=om)
    return BrushFitResult(p, None, tuple(vary), {"fx": float(np.sqrt(np.mean((f.fx - ref.fx) ** 2))),
                                                 "fy": float(np.sqrt(np.mean((f.fy - ref.fy) ** 2)))},
                          res, "original model calibrated on the improved model without camber")
