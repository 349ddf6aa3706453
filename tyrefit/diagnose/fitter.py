"""A lean least-squares fitter for PAC89 plus effects (many fast refits).

Diagnosis refits the model hundreds of times (candidates x hold-out folds),
so this fitter is built for speed: the Jacobian is PAC89's analytic one with
respect to a0..a13 chained with the derivative of the point-wise coefficients
with respect to the parameters (all parameter steps evaluated at once as
``(P+1, 1)`` columns broadcast against the points), and refits start from the
previous solution.

The problem is stated in the one fitting core (:mod:`tyrefit.fitting.core`):
the parameters are core :class:`~tyrefit.fitting.core.Parameters` made from
the effects' catalogue definitions (neutral value, bounds, scale, unit), and
every fit is one :func:`tyrefit.fitting.core.solve` with its ``'lm-normal'``
back end (box-constrained Levenberg-Marquardt on the small normal equations:
P <= ~20 parameters, warm starts).  The cost is the core's ``'l2'`` on the
lateral force in N with every point weighted alike, not the PAC89 fit's mu
residual with 1/n_s sweep weights: the diagnosis statistics (screening
score, bootstrap noise model, held-out RMSE) are all point-wise in N, so the
fitted model must be the ordinary least-squares one they assume.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..effects import BASE, Effect, ModelInputs, get_effect
from ..effects import coefficients as _coefficients
from ..effects import lateral_force as _model
from ..errors import FitError
from ..fitting.core import Parameters, Sweeps, lm_normal, lm_normal_batch, solve
from ..models import pac89
from .data import SweepData

__all__ = ["ModelSpec", "FitOut", "fit", "fit_folds", "initial_guess"]

_DEG = np.pi / 180.0


class ModelSpec:
    """Start model plus effects, as a parameter vector with bounds and scales.

    Parameters
    ----------
    effects : sequence of str or Effect
        Effects in the model (base PAC89 is always in).
    fixed : mapping, optional
        Parameters held at a value (not fitted), e.g. ``a4`` for single-load data.
    """

    def __init__(self, effects=(), fixed: dict | None = None):
        self.effects: tuple[Effect, ...] = tuple(e if isinstance(e, Effect) else get_effect(e) for e in effects)
        self.fixed = dict(fixed or {})
        params, seen = [], set()
        for p in list(BASE) + [p for e in self.effects for p in e.params]:
            if p.name not in seen and p.name not in self.fixed:
                params.append(p)
                seen.add(p.name)
        self.params = tuple(params)
        self.names = [p.name for p in params]
        self.lower = np.array([p.bounds[0] for p in params])
        self.upper = np.array([p.bounds[1] for p in params])
        self.scale = np.array([p.scale for p in params])

    def parameters(self, theta=None) -> Parameters:
        """The fitting core's parameters at ``theta`` (default: neutral values); fixed ones held (vary=False)."""
        out = Parameters()
        for j, p in enumerate(self.params):
            out[p.name] = p.parameter(p.neutral if theta is None else theta[j])
        for k, v in self.fixed.items():
            out.add(k, float(v), vary=False)
        return out

    @property
    def ids(self) -> list[str]:
        return [e.id for e in self.effects]

    def with_effect(self, effect: Effect | str) -> "ModelSpec":
        """This model plus ``effect``; a same-family variant whose parameters it contains is replaced."""
        e = effect if isinstance(effect, Effect) else get_effect(effect)
        keep = [m for m in self.effects
                if not (m.family == e.family and set(m.param_names) <= set(e.param_names))]
        return ModelSpec(keep + [e], self.fixed)

    def values(self, theta) -> dict:
        """Parameter name -> value (fixed ones included)."""
        v = dict(self.fixed)
        v.update(zip(self.names, theta))
        return v

    def start(self, previous: dict | None) -> np.ndarray:
        """Start vector: previous values where known, neutral values elsewhere."""
        prev = previous or {}
        x = np.array([prev.get(p.name, p.neutral) for p in self.params], dtype=float)
        return np.clip(x, self.lower + 1e-12 * self.scale, self.upper - 1e-12 * self.scale)

    def predict(self, theta, inputs: ModelInputs) -> np.ndarray:
        """Lateral force [N] (ISO-W) at ``inputs``."""
        return _model(self.values(theta), self.effects, inputs)

    def _columns(self, x0: np.ndarray, h: np.ndarray) -> dict:
        """Values with every parameter as a (P+1, 1) column: row 0 at x0, row j+1 stepped in parameter j."""
        k = len(x0)
        vals = {n: np.full((k + 1, 1), v, dtype=float) for n, v in self.fixed.items()}
        for j, n in enumerate(self.names):
            col = np.full((k + 1, 1), x0[j])
            col[j + 1, 0] += h[j]
            vals[n] = col
        return vals

    def _steps(self, x0: np.ndarray, rel_step: float) -> np.ndarray:
        h = rel_step * np.maximum(np.abs(x0), self.scale)
        return np.where(x0 + h > self.upper, -h, h)

    def jacobian(self, theta, inputs: ModelInputs, method: str = "chain"):
        """Model value and Jacobian with respect to the parameters.

        Parameters
        ----------
        theta : array_like
            Parameter vector of this spec.
        inputs : ModelInputs
        method : {'chain', 'fd'}
            ``'chain'`` (default): the analytic PAC89 Jacobian with respect to
            the coefficients a0..a13 (:func:`tyrefit.models.pac89.lateral_jacobian`)
            times the derivative of the point-wise coefficients with respect to
            the parameters (effects are algebraic in their parameters, so the
            latter is a cheap difference of :func:`tyrefit.effects.coefficients`).
            ``'fd'``: forward differences of the whole model, all parameter
            steps evaluated in one broadcast call (for checking).

        Returns
        -------
        f0 : ndarray (N,)
            Lateral force [N] at ``theta``.
        J : ndarray (N, P)
            d f / d theta.
        """
        x0 = np.asarray(theta, dtype=float)
        n = len(inputs.fz)
        k = len(x0)
        if method == "fd":
            h = self._steps(x0, 1e-7)
            F = np.broadcast_to(_model(self._columns(x0, h), self.effects, inputs), (k + 1, n))
            return F[0], ((F[1:] - F[0]) / h[:, None]).T
        f0, J = self.jacobian_batch(x0[None, :], inputs)
        return f0[0], J[0]

    def jacobian_batch(self, X: np.ndarray, inputs: ModelInputs):
        """:meth:`jacobian` (``'chain'``) of F parameter sets at once: (F, n) forces and (F, n, P) Jacobians.

        The coefficients and their parameter derivatives are made per set, as :meth:`jacobian` makes them;
        PAC89's analytic Jacobian then runs once, every set's coefficients a (F, 1) column (or (F, n) where
        they vary from point to point) broadcast against the n points of ``inputs``, so one model call
        serves all F sets (one set: its coefficients as numbers, or (n,) arrays).  Each set's rows are
        computed as they would be alone.
        """
        X = np.atleast_2d(np.asarray(X, dtype=float))
        F, k = X.shape
        H = self._steps(X, 1e-6)  # (F, k)
        # every set's parameter columns stacked: row f (k+1) + 0 at X[f], row f (k+1) + j + 1 stepped in j
        C = np.repeat(X[:, None, :], k + 1, axis=1)  # (F, k+1, k)
        C[:, np.arange(1, k + 1), np.arange(k)] += H
        C = C.reshape(F * (k + 1), k)
        vals = {name: np.full((F * (k + 1), 1), v, dtype=float) for name, v in self.fixed.items()}
        vals.update({name: C[:, j:j + 1] for j, name in enumerate(self.names)})
        coef = _coefficients(vals, self.effects, inputs)
        varied, p0, dvs = [], {}, []
        for c in pac89.LATERAL:
            v = coef[c]
            if not (isinstance(v, np.ndarray) and v.ndim == 2):
                p0[c] = v  # no parameter reaches it: a scalar, or fixed values at the points
                continue
            v3 = v.reshape(F, k + 1, -1)
            varied.append(c)
            # each set's value: (F, 1), or (F, n) when it varies from point to point; one set: a number or (n,)
            p0[c] = v3[:, 0, :] if F > 1 else (v3[0, 0, 0] if v3.shape[2] == 1 else v3[0, 0])
            dvs.append((v3[:, 1:, :] - v3[:, :1, :]) / H[:, :, None])  # (F, k, 1 or n)
        f0, Jc = pac89.lateral_jacobian(p0, inputs.fz, inputs.slip_angle, inputs.camber, names=varied)
        if F == 1:
            f0, Jc = f0[None], Jc[None]
        point = [i for i, dv in enumerate(dvs) if dv.shape[2] > 1]
        zero = np.zeros((F, k))
        M = np.stack([zero if i in point else dv[:, :, 0] for i, dv in enumerate(dvs)], axis=1)  # (F, varied, k)
        if not point:
            return f0, Jc @ M
        Jt = np.zeros((F, k, Jc.shape[1]))  # the point-wise terms summed parameter by parameter (rows of n)
        for i in point:
            Jt += dvs[i] * Jc[:, None, :, i]
        Jt += (Jc @ M).transpose(0, 2, 1)
        return f0, np.ascontiguousarray(Jt.transpose(0, 2, 1))


@dataclass
class FitOut:
    """Result of one refit: parameter vector, residuals (model - data) [N], RMSE [N]."""

    theta: np.ndarray
    resid: np.ndarray
    rmse: float
    nfev: int
    success: bool
    values: dict


def _start(spec: ModelSpec, x0) -> np.ndarray:
    """``x0`` clipped into the box and moved 1e-9 of a scale off a bound."""
    x = spec.start(None) if x0 is None else np.clip(np.asarray(x0, float), spec.lower, spec.upper)
    x = np.where(x <= spec.lower, spec.lower + 1e-9 * spec.scale, x)
    return np.where(x >= spec.upper, spec.upper - 1e-9 * spec.scale, x)


def _problem(spec: ModelSpec, data: SweepData, idx, known=None):
    """(residual, residual-and-Jacobian, points) of ``spec`` on the points ``idx`` of ``data``.

    ``known``: (theta, f, J) of the model on these points at one theta, already made: served from there.
    """
    inputs = data.inputs if idx is None else data.inputs.take(idx)
    y = data.fy if idx is None else data.fy[idx]

    def both(t):
        if known is not None and np.array_equal(t, known[0]):
            return known[1] - y, known[2]
        f0, J = spec.jacobian(t, inputs)
        return f0 - y, J

    def fun(t):
        if known is not None and np.array_equal(t, known[0]):
            return known[1] - y  # the Jacobian's model value is the prediction's, bit for bit
        return spec.predict(t, inputs) - y

    return fun, both, inputs, y


def fit(spec: ModelSpec, data: SweepData, idx=None, x0=None, max_nfev: int = 200, tol: float = 1e-9,
        at_start=None) -> FitOut:
    """Least-squares fit of ``spec`` to ``data`` (points ``idx``), starting at ``x0``.

    One :func:`tyrefit.fitting.core.solve` (``'lm-normal'`` back end, ``'l2'``
    cost on Fy in N, all points weighted alike).  ``tol`` is the relative cost
    reduction below which the fit stops.  ``at_start``: (f, J) of
    :meth:`ModelSpec.jacobian` at ``x0`` on all points, when already made (the
    fit's first evaluation).  Returns the fit on the chosen points; raises
    :class:`FitError` if the model cannot be evaluated (non-finite) at the start.
    """
    x = _start(spec, x0)
    known = (x, *at_start) if at_start is not None and idx is None else None
    fun, both, _, _ = _problem(spec, data, idx, known)
    try:
        sol = solve(fun, spec.parameters(x), fun_jac=both, method="lm-normal", max_nfev=max_nfev, tol=tol,
                    stderr=False, what="diagnosis refit")
    except FitError:
        raise FitError("the model is not finite at the start values; check the data units (fz [N], slip [rad])") \
            from None
    return _fitout(spec, sol)


#: records of at most this many points refit their folds together (:func:`fit_folds`); larger ones one by one,
#: where the model calls are long enough that batching them saves nothing (294 points: 2 x faster together;
#: 1470: 1.2 x slower; the bundled passenger and TTC records: 1.5-1.8 x slower)
BATCH_MAX_POINTS = 800


def fit_folds(spec: ModelSpec, data: SweepData, tests, x0, max_nfev: int = 200, tol: float = 1e-9):
    """Refits of ``spec`` each leaving out one set of points, all at once (cross-validation folds).

    Each refit is the one :func:`fit` makes on the points outside ``tests[f]`` starting at ``x0``: the same
    box-constrained Levenberg-Marquardt steps (:func:`tyrefit.fitting.core.lm_normal_batch`), with the model
    and its Jacobian evaluated for every unfinished fold in one call (records of up to
    :data:`BATCH_MAX_POINTS` points; larger ones call :func:`fit` fold by fold).

    Parameters
    ----------
    tests : sequence of bool arrays (N,)
        The held-out points of each fold.
    x0 : array_like (P,)
        Start of every refit (the fit on all points).

    Returns
    -------
    thetas : ndarray (F, P)
    resid : ndarray (F, N)
        Model minus data [N] at every point with fold f's parameters: the held-out residuals are
        ``resid[f][tests[f]]``.
    """
    n = data.n
    F = len(tests)
    if F == 0:
        return np.zeros((0, len(spec.names))), np.zeros((0, n))
    if n > BATCH_MAX_POINTS:  # large records: the per-call overhead the batch saves is small, its arrays are not
        X = np.array([fit(spec, data, idx=np.flatnonzero(~np.asarray(t, dtype=bool)), x0=x0, max_nfev=max_nfev,
                          tol=tol).theta for t in tests])
        return X, np.array([spec.predict(x, data.inputs) - data.fy for x in X])
    w = ~np.asarray(tests, dtype=bool)
    jac = _batch_problem(spec, data)
    x = np.repeat(_start(spec, x0)[None, :], F, axis=0)
    X, R, _, _ = lm_normal_batch(jac, None, x, w.astype(float), spec.lower, spec.upper, spec.scale, max_nfev, tol)
    return X, R


def _batch_problem(spec: ModelSpec, data: SweepData):
    """Residuals and Jacobians of parameter sets (F, P) on every point, for :func:`lm_normal_batch`."""

    def jac(X, rows):
        if len(X) > 1 and (X == X[0]).all():  # one start shared by every problem: one evaluation serves all
            f0, J = spec.jacobian_batch(X[:1], data.inputs)
            f0, J = np.repeat(f0, len(X), axis=0), np.repeat(J, len(X), axis=0)
        else:
            f0, J = spec.jacobian_batch(X, data.inputs)
        return f0 - data.fy, J

    return jac


def _fitout(spec: ModelSpec, sol) -> FitOut:
    r = sol.resid
    return FitOut(theta=sol.x, resid=r, rmse=float(np.sqrt(np.mean(r**2))), nfev=sol.nfev,
                  success=sol.success and bool(np.all(np.isfinite(r))), values=spec.values(sol.x))


#: the normal-equation Levenberg-Marquardt now lives in the fitting core (kept under its old name)
_levenberg_marquardt = lm_normal


def sweeps_of(data: SweepData) -> Sweeps:
    """The diagnosis points as the fitting core's :class:`~tyrefit.fitting.core.Sweeps` (Fy [N], unit weights)."""
    x = data.inputs
    cond = {"fz": x.fz, "slip_angle": x.slip_angle, "camber": x.camber}
    if x.pressure is not None:
        cond["pressure"] = x.pressure
    if x.speed is not None:
        cond["speed"] = x.speed
    return Sweeps(data.fy, data.sweep, cond, np.ones(data.n), {k: np.asarray(v) for k, v in data.levels.items()})


def initial_guess(data: SweepData) -> dict:
    """Start values of the base PAC89 parameters from the sweeps.

    Peak friction from the largest |Fy|/Fz of each load level (a2 = 1000 mu),
    cornering stiffness from the slope within +/-1.5 deg of zero slip per load
    level, a3 and a4 from BCD(Fz) = a3 sin(2 atan(Fz/a4)) by a grid over a4
    with a3 linear; C and E at typical values.
    """
    x = data.inputs
    fzk = x.fz * 1e-3
    lv = data.level_index["fz"]
    levels = data.levels["fz"] * 1e-3
    mus, stiff, loads = [], [], []
    for k in range(len(levels)):
        m = lv == k
        a, y, z = x.slip_angle[m], data.fy[m], fzk[m]
        if m.sum() < 5:
            continue
        mus.append(np.quantile(np.abs(y) / (z * 1e3), 0.98))
        c = np.abs(a) <= 1.5 * _DEG
        if c.sum() < 4 or np.ptp(a[c]) == 0:
            c = np.abs(a) <= 3.0 * _DEG
        if c.sum() >= 4 and np.ptp(a[c]) > 0:
            slope = np.polyfit(a[c] / _DEG, y[c], 1)[0]
            stiff.append(-slope)
            loads.append(levels[k])
    mu = float(np.median(mus)) if mus else 1.0
    loads, stiff = np.array(loads), np.array(stiff)
    ok = stiff > 0
    loads, stiff = loads[ok], stiff[ok]
    if len(loads) >= 2:
        best = (np.inf, 1500.0, 10.0)
        for a4 in np.geomspace(0.3 * loads.min(), 30 * loads.max(), 80):
            s = np.sin(2 * np.arctan(loads / a4))
            a3 = float(s @ stiff / (s @ s))
            err = float(np.sum((a3 * s - stiff) ** 2))
            if err < best[0]:
                best = (err, a3, a4)
        a3, a4 = best[1], best[2]
    elif len(loads) == 1:
        a4 = 2.0 * loads[0]
        a3 = stiff[0] / np.sin(2 * np.arctan(0.5))
    else:
        a4 = 2.0 * float(np.median(fzk))
        a3 = 20.0 * mu * 1e3 * float(np.median(fzk)) / 10.0
    return {"a0": 1.4, "a2": 1000.0 * mu, "a3": float(a3), "a4": float(a4), "a7": -0.3}


def fit_start(spec: ModelSpec, data: SweepData) -> FitOut:
    """Fit from the data-based initial guess, trying a few curvature/shape starts, all at once.

    Three starts (C, E) = (1.4, -0.3), (1.2, 0.3), (1.7, -1.0) with the data-based peak and stiffness
    (:func:`initial_guess`) run together (:func:`tyrefit.fitting.core.lm_normal_batch`, every point
    weighted alike); the fit with the lowest sum of squares is kept.
    """
    g = initial_guess(data)
    starts = np.array([_start(spec, spec.start(dict(g, a0=a0, a7=a7)))
                       for a0, a7 in ((1.4, -0.3), (1.2, 0.3), (1.7, -1.0))])
    n, S = data.n, len(starts)
    jac = _batch_problem(spec, data)
    X, R, nfev, ok = lm_normal_batch(jac, None, starts, np.ones((S, n)), spec.lower, spec.upper, spec.scale, 200,
                                     1e-9)
    sse = np.where(np.all(np.isfinite(R), axis=1), np.sum(R * R, axis=1), np.inf)
    b = int(np.argmin(sse))
    if not np.isfinite(sse[b]):
        raise FitError("PAC89 start model could not be fitted to these data")
    r = R[b]
    return FitOut(theta=X[b], resid=r, rmse=float(np.sqrt(np.mean(r**2))), nfev=int(np.sum(nfev)),
                  success=bool(ok[b]), values=spec.values(X[b]))
