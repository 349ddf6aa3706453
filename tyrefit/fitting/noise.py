"""The within-sweep noise floor: the error no global tyre model can beat inside a sweep.

:func:`noise_floor` is tyrefit's one noise floor: ``fit`` (PAC89 and MF), ``diagnose`` and ``compare``
all compare a model's RMSE with it.  It fits a smooth curve through each sweep on its own (a cubic
least-squares spline, or one Magic Formula through a sparse sweep) and pools the residual variance
over the sweeps; :func:`thin_sweeps` and :data:`MAX_POINTS_PER_SWEEP` thin long logged sweeps evenly
along the record first, so that every command estimates it from the same points.  Callers differ
only in its parameters (knot spacing, thinning); :func:`tyrefit.fitting.result.noise_floor_of` is
the fit's parametrisation of it (knot spacing per part, any sweep labels, per-sweep values by label).

The other noise estimates of the package estimate something else and are not floors of this kind:
the fit's point scatter (:func:`tyrefit.fitting.engine.point_scatter`, neighbour differences, counts
up/down hysteresis), the spread between repeated sweeps (:func:`tyrefit.diagnose.stats.repeat_noise`)
and diagnose's AR(1) + sweep-offset noise model (:func:`tyrefit.diagnose.stats.estimate_noise`).
"""

from __future__ import annotations

import numpy as np
from scipy.interpolate import BSpline
from scipy.signal import lfilter

from ..errors import FitError
from .core import Parameters, solve

__all__ = ["noise_floor", "thin_sweeps", "MAX_POINTS_PER_SWEEP"]

#: points per sweep kept (evenly along the record) for the floor and for diagnose's fits
MAX_POINTS_PER_SWEEP = 100

_DEG = np.pi / 180.0


def _thin(idx: np.ndarray, max_points: int) -> np.ndarray:
    """``idx`` (one sweep's indices in record order) thinned evenly to at most ``max_points``."""
    if len(idx) > max_points:
        idx = idx[np.unique(np.round(np.linspace(0, len(idx) - 1, max_points)).astype(int))]
    return idx


def thin_sweeps(sweep, max_points: int = MAX_POINTS_PER_SWEEP) -> np.ndarray:
    """Sorted indices of the points kept when each sweep is thinned evenly along the record.

    Each sweep (points sharing a label of ``sweep``) longer than ``max_points`` keeps the points
    nearest ``max_points`` evenly spaced positions along its record order; shorter sweeps are kept
    whole.

    >>> thin_sweeps([0, 0, 0, 0, 0, 1, 1], max_points=3).tolist()
    [0, 2, 4, 5, 6]
    """
    sw = np.asarray(sweep)
    take = [_thin(np.flatnonzero(sw == s), max_points) for s in np.unique(sw)]
    return np.sort(np.concatenate(take)) if take else np.zeros(0, int)


def _bspline_basis(x: np.ndarray, spacing: float) -> np.ndarray:
    lo, hi = x.min(), x.max()
    n_int = int(max(0, np.floor((hi - lo) / spacing) - 1))
    interior = np.linspace(lo, hi, n_int + 2)[1:-1] if n_int > 0 else np.array([])
    t = np.r_[[lo] * 4, interior, [hi] * 4]
    return BSpline.design_matrix(x, t, 3).toarray()


def _magic_formula_ssr(x: np.ndarray, y: np.ndarray) -> tuple[float, int]:
    """SSR and dof of one Magic Formula (B, C, D, E, Sh, Sv) through a sparse sweep.

    A sweep of ~25 points cannot feed a 1.5 deg knot spline and still leave
    degrees of freedom for the noise; a single Magic Formula is the smooth curve
    with the fewest parameters that follows a tyre's force curve through its
    peak (Pacejka, Tyre and Vehicle Dynamics, Ch. 4).
    """
    n = len(x)
    if n < 10:
        return 0.0, 0
    i = np.argsort(x)
    x, y = x[i], y[i]
    lin = np.abs(x - x[np.argmin(np.abs(x))]) <= max(np.ptp(x) / 8, 1e-9)
    slope = np.polyfit(x[lin], y[lin], 1)[0] if lin.sum() >= 2 and np.ptp(x[lin]) > 0 else (y[-1] - y[0]) / np.ptp(x)
    d0 = max(np.abs(y).max(), 1e-9) * np.sign(slope or 1.0)
    c0 = 1.4
    p0 = np.array([slope / (c0 * d0), c0, d0, 0.0, 0.0, 0.0])

    def res(p):
        B, C, D, E, sh, sv = p
        bx = B * (x + sh)
        return D * np.sin(C * np.arctan(bx - E * (bx - np.arctan(bx)))) + sv - y

    lo = [-np.inf, 0.1, -np.inf, -10.0, -np.ptp(x) / 4, -np.inf]
    hi = [np.inf, 2.5, np.inf, 1.0, np.ptp(x) / 4, np.inf]
    p0 = np.clip(p0, np.array(lo) + 1e-9, np.array(hi) - 1e-9)
    params = Parameters()
    for name, v, a, b in zip(("B", "C", "D", "E", "sh", "sv"), p0, lo, hi):
        params.add(name, float(v), min=a, max=b)
    try:  # the one fitting core (same trust-region least squares, x_scale 'jac', 400 evaluations)
        sol = solve(res, params, max_nfev=400, stderr=False, what="Magic Formula through one sweep")
    except (ValueError, np.linalg.LinAlgError, FitError):
        return 0.0, 0
    r = sol.resid
    return float(r @ r), n - 6


class LagOneNoise:
    """Lag-one correlation rho of the noise in a model's residuals along the sweeps (record order).

    A model that misses something leaves a smooth misfit along each sweep, which reads as rho near
    1.  So the residuals are first cleared of what a coarse cubic spline in ``x`` follows (one spline
    function per ``points_per_function`` points of the sweep: wide knots, since the model already
    follows the curve's peak), and rho is read from what is left.  That spline also takes part of
    slow noise, so the raw value is low (and negative for independent noise); it is calibrated by
    simulation on the same points: AR(1) noise at each rho of :attr:`GRID` (``draws`` each) gives
    the mean raw value, and the observed one is read back through that curve (a parametric-bootstrap
    bias correction).  With ``upper`` the read-back goes through the curve of the draws' lower
    ``1 - upper`` quantile instead: the largest rho the observation is still consistent with, an
    upper confidence bound (few short sweeps estimate rho loosely, and a test corrected with a low
    estimate passes correlated noise for an effect).  Sweeps shorter than 20 points are not read.

    >>> import numpy as np
    >>> x = np.tile(np.linspace(-0.2, 0.2, 60), 4); sweep = np.repeat(np.arange(4), 60)
    >>> est = LagOneNoise(x, sweep)
    >>> 0.0 <= est(np.random.default_rng(1).standard_normal(240)) < 0.3
    True
    """

    GRID = np.array([0.0, 0.2, 0.4, 0.6, 0.7, 0.8, 0.85, 0.9, 0.95])

    def __init__(self, x, sweep, points_per_function: int = 5, seed: int = 0, draws: int = 24,
                 upper: float | None = None):
        x, sw = np.asarray(x, float), np.asarray(sweep)
        self.n = len(x)
        self.projections = []
        for g in np.unique(sw):
            m = np.flatnonzero(sw == g)
            if len(m) < 20 or np.ptp(x[m]) <= 0:
                continue
            B = _bspline_basis(x[m], points_per_function * np.ptp(x[m]) / len(m))
            Q, _ = np.linalg.qr(B)
            self.projections.append((m, Q))
        rng = np.random.default_rng(seed)
        curve = []
        self.upper = upper
        for rho in self.GRID:
            vals = []
            for _ in range(draws):
                e = np.zeros(self.n)
                for m, _Q in self.projections:  # AR(1) after a burn-in of 60 samples (stationary start)
                    e[m] = lfilter([np.sqrt(1.0 - rho * rho)], [1.0, -rho], rng.standard_normal(len(m) + 60))[60:]
                vals.append(self.raw(e))
            curve.append(float(np.mean(vals) if upper is None else np.quantile(vals, 1.0 - upper)))
        self.curve = np.maximum.accumulate(np.asarray(curve))  # monotone for the read-back

    def raw(self, r) -> float:
        """The uncalibrated lag-one correlation of what the coarse spline leaves of ``r``."""
        num = den = 0.0
        for m, Q in self.projections:
            e = r[m] - Q @ (Q.T @ r[m])
            num += float(np.sum(e[1:] * e[:-1]))
            den += float(np.sum(e * e))
        return num / den if den > 0 else 0.0

    def __call__(self, resid) -> float:
        """rho in [0, 0.95] of the residuals ``resid`` (calibrated)."""
        if not self.projections:
            return 0.0
        return float(np.clip(np.interp(self.raw(np.asarray(resid, float)), self.curve, self.GRID), 0.0, 0.95))


def _spline_ssr(x: np.ndarray, y: np.ndarray, spacing: float, load=None) -> tuple[float, int]:
    """SSR and degrees of freedom of a cubic least-squares spline through (x, y).

    With ``load``, a coarser spline times the relative load deviation is added,
    so that point-to-point jitter of the measured load (which the model
    explains) is not counted as noise.
    """
    if np.ptp(x) <= 0:
        return 0.0, 0
    B = _bspline_basis(x, spacing)
    if load is not None:
        dz = (load - load.mean()) / max(abs(load.mean()), 1e-9)
        if np.ptp(dz) > 1e-6:
            B = np.hstack([B, _bspline_basis(x, 4 * spacing) * dz[:, None]])
    if len(x) - B.shape[1] < max(6, len(x) // 4):  # sparse sweep (1 deg steps): too little left for noise
        return _magic_formula_ssr(x, y)
    coef, _, rank, _ = np.linalg.lstsq(B, y, rcond=None)
    r = y - B @ coef
    return float(r @ r), int(len(x) - rank)


def noise_floor(slip_angle, fy, sweep, spacing_deg: float = 1.5, fz=None,
                max_points_per_sweep: int | None = None) -> tuple[float, np.ndarray]:
    """Within-sweep noise [N]: pooled RMSE of a smooth curve through each sweep.

    What it estimates: the standard deviation of the measurement noise that is fast compared
    with the tyre's force curve, i.e. what no smooth steady-state model can follow inside one
    sweep.  A global model's RMSE against it says how much structure the model leaves.

    Method: each sweep (sorted by slip) is fitted by a cubic least-squares regression spline
    (B-spline basis with evenly spaced knots, de Boor, *A Practical Guide to Splines*, 2001,
    ch. IX and XIV), its residual variance estimated as SSR / (n - rank) (the unbiased
    error-variance estimate of linear least squares, Hastie, Tibshirani and Friedman, *The
    Elements of Statistical Learning*, 2nd ed., 2009, Eq. 3.8), and the sweeps pooled as
    sqrt(sum SSR / sum dof).  With ``fz``, a coarser spline times the relative load deviation
    (a varying-coefficient term, Hastie and Tibshirani, *Varying-coefficient models*, JRSS B 55,
    1993) absorbs the point-to-point load jitter a tyre model explains.  A sweep too sparse to
    leave degrees of freedom beside the spline (fewer than max(6, n/4)) is fitted by one Magic
    Formula instead (B, C, D, E, Sh, Sv; Pacejka, *Tyre and Vehicle Dynamics*, 3rd ed., 2012,
    ch. 4), with n - 6 degrees of freedom.  Sweeps of fewer than 10 points are left out.

    Parameters
    ----------
    slip_angle : array_like
        [rad] (or slip ratio [-], with ``spacing_deg`` in degrees of it: slip ratio x 180 / pi).
    fy : array_like
        [N] (or any force or moment channel).
    sweep : array_like of int
        Sweep id of each point, 0 .. G-1.
    spacing_deg : float
        Knot spacing [deg] of the cubic spline in slip angle; the Magic
        Formula curve is smooth on this scale.
    fz : array_like, optional
        Measured load [N]; a coarse spline times its relative deviation within
        the sweep absorbs the load jitter the model explains.
    max_points_per_sweep : int, optional
        Thin each sweep evenly along the record to at most this many points first
        (:func:`thin_sweeps`; ``fit`` and ``compare`` pass :data:`MAX_POINTS_PER_SWEEP`,
        the points diagnose keeps).  Default: every point.

    Returns
    -------
    floor : float
        sqrt(sum SSR / sum dof) over the sweeps [N].
    per_sweep : ndarray
        The same per sweep id [N] (NaN where a sweep is too short).

    Notes
    -----
    This is the error no global model can beat *within* a sweep; slow drifts
    and sweep-to-sweep offsets are absorbed by the per-sweep curves, so a
    global model's RMSE can stay above it when the rig has such noise.
    """
    a = np.asarray(slip_angle, dtype=float)
    y = np.asarray(fy, dtype=float)
    z = None if fz is None else np.asarray(fz, dtype=float)
    sw = np.asarray(sweep)
    G = int(sw.max()) + 1
    per = np.full(G, np.nan)
    ssr_tot, dof_tot = 0.0, 0
    for g in range(G):
        m = np.flatnonzero(sw == g)
        if max_points_per_sweep is not None:
            m = _thin(m, max_points_per_sweep)
        if len(m) < 10:
            continue
        o = np.argsort(a[m], kind="stable")
        ssr, dof = _spline_ssr(a[m][o], y[m][o], spacing_deg * _DEG, None if z is None else z[m][o])
        if dof > 0:
            per[g] = np.sqrt(ssr / dof)
            ssr_tot += ssr
            dof_tot += dof
    floor = float(np.sqrt(ssr_tot / dof_tot)) if dof_tot > 0 else float("nan")
    return floor, per
