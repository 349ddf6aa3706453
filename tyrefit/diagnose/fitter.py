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
from ..fitting.core import Parameters, Sweeps, lm_normal, solve
from ..models import pac89
from .data import SweepData

__all__ = ["ModelSpec", "FitOut", "fit", "initial_guess"]

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
        h = self._steps(x0, 1e-6)
        coef = _coefficients(self._columns(x0, h), self.effects, inputs)
        p0 = {c: np.broadcast_to(np.asarray(v, dtype=float), (k + 1, n))[0] for c, v in coef.items()}
        f0, Jc = pac89.lateral_jacobian(p0, inputs.fz, inputs.slip_angle, inputs.camber)
        J = np.zeros((n, k))
        for i, c in enumerate(pac89.LATERAL):
            v = np.asarray(coef[c], dtype=float)
            if v.ndim == 0:
                continue
            v = np.broadcast_to(v, (k + 1, v.shape[-1]))
            dv = (v[1:] - v[0]) / h[:, None]
            nz = np.flatnonzero(np.any(dv != 0.0, axis=1))
            if len(nz):
                J[:, nz] += Jc[:, i][:, None] * dv[nz].T
        return f0, J


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


def _problem(spec: ModelSpec, data: SweepData, idx):
    """(residual, residual-and-Jacobian, points) of ``spec`` on the points ``idx`` of ``data``."""
    inputs = data.inputs if idx is None else data.inputs.take(idx)
    y = data.fy if idx is None else data.fy[idx]

    def both(t):
        f0, J = spec.jacobian(t, inputs)
        return f0 - y, J

    def fun(t):
        return spec.predict(t, inputs) - y

    return fun, both, inputs, y


def fit(spec: ModelSpec, data: SweepData, idx=None, x0=None, max_nfev: int = 200, tol: float = 1e-9) -> FitOut:
    """Least-squares fit of ``spec`` to ``data`` (points ``idx``), starting at ``x0``.

    One :func:`tyrefit.fitting.core.solve` (``'lm-normal'`` back end, ``'l2'``
    cost on Fy in N, all points weighted alike).  ``tol`` is the relative cost
    reduction below which the fit stops.  Returns the fit on the chosen
    points; raises :class:`FitError` if the model cannot be evaluated
    (non-finite) at the start.
    """
    fun, both, _, _ = _problem(spec, data, idx)
    x = _start(spec, x0)
    try:
        sol = solve(fun, spec.parameters(x), fun_jac=both, method="lm-normal", max_nfev=max_nfev, tol=tol,
                    stderr=False, what="diagnosis refit")
    except FitError:
        raise FitError("the model is not finite at the start values; check the data units (fz [N], slip [rad])") \
            from None
    return _fitout(spec, sol)


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
    """Fit from the data-based initial guess, trying a few curvature/shape starts (the core's multi-start)."""
    g = initial_guess(data)
    starts = [_start(spec, spec.start(dict(g, a0=a0, a7=a7))) for a0, a7 in ((1.4, -0.3), (1.2, 0.3), (1.7, -1.0))]
    fun, both, _, _ = _problem(spec, data, None)
    try:
        sol = solve(fun, spec.parameters(starts[0]), fun_jac=both, method="lm-normal", max_nfev=200, tol=1e-9,
                    starts=starts, stderr=False, what="PAC89 start model")
    except FitError:
        raise FitError("PAC89 start model could not be fitted to these data") from None
    return _fitout(spec, sol)
