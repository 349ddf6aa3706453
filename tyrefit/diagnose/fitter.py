"""A lean least-squares fitter for PAC89 plus effects (many fast refits).

Diagnosis refits the model hundreds of times (candidates x hold-out folds),
so this fitter is built for speed: the Jacobian is PAC89's analytic one with
respect to a0..a13 chained with the derivative of the point-wise coefficients
with respect to the parameters (all parameter steps evaluated at once as
``(P+1, 1)`` columns broadcast against the points), a box-constrained Levenberg-Marquardt
on the small normal equations does the rest, and refits start from the
previous solution.  The cost is ordinary
least squares on the lateral force in N.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..effects import BASE, Effect, ModelInputs, get_effect
from ..effects import coefficients as _coefficients
from ..effects import lateral_force as _model
from ..models import pac89
from ..errors import FitError
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


def fit(spec: ModelSpec, data: SweepData, idx=None, x0=None, max_nfev: int = 200, tol: float = 1e-9) -> FitOut:
    """Least-squares fit of ``spec`` to ``data`` (points ``idx``), starting at ``x0``.

    ``tol`` is the relative cost reduction below which the fit stops.
    Returns the fit on the chosen points; raises :class:`FitError` if the model
    cannot be evaluated (non-finite) at the start.
    """
    inputs = data.inputs if idx is None else data.inputs.take(idx)
    y = data.fy if idx is None else data.fy[idx]
    x = spec.start(None) if x0 is None else np.clip(np.asarray(x0, float), spec.lower, spec.upper)
    x = np.where(x <= spec.lower, spec.lower + 1e-9 * spec.scale, x)
    x = np.where(x >= spec.upper, spec.upper - 1e-9 * spec.scale, x)
    def both(t):
        f0, J = spec.jacobian(t, inputs)
        return f0 - y, J

    def fun(t):
        return spec.predict(t, inputs) - y

    r0 = fun(x)
    if not np.all(np.isfinite(r0)):
        raise FitError("the model is not finite at the start values; check the data units (fz [N], slip [rad])")
    theta, nfev, ok = _levenberg_marquardt(both, fun, x, spec.lower, spec.upper, spec.scale, max_nfev, tol)
    r = spec.predict(theta, inputs) - y
    return FitOut(theta=theta, resid=r, rmse=float(np.sqrt(np.mean(r**2))), nfev=nfev,
                  success=ok and bool(np.all(np.isfinite(r))), values=spec.values(theta))


def _levenberg_marquardt(jac, fun, x, lower, upper, scale, max_nfev: int, tol: float = 1e-9):
    """Box-constrained Levenberg-Marquardt on the scaled normal equations.

    The problems are small (P <= ~20 parameters) and start close to the
    optimum, so solving the P x P normal equations with Marquardt's diagonal
    damping is far cheaper than an SVD of the N x P Jacobian per iteration.
    Parameters at a bound whose descent direction points out of the box are
    held there for the step (active set); the others are clipped to the box.
    Converges when an accepted step lowers the cost by less than ``tol``
    relatively or moves no parameter by more than ``tol`` of its scale.
    Returns (theta, evaluations, converged).
    """
    r, J = jac(x)
    cost = float(r @ r)
    lam, nu = 1e-3, 2.0
    nfev = 1
    converged = False
    span = 1e-12 * scale
    while nfev < max_nfev:
        Js = J * scale
        g = Js.T @ r
        active = ((x <= lower + span) & (g > 0)) | ((x >= upper - span) & (g < 0))
        free = ~active
        A = Js[:, free].T @ Js[:, free]
        d = np.diag(A).copy()
        d[d <= 0] = 1.0
        h = np.zeros_like(x)
        try:
            h[free] = -np.linalg.solve(A + lam * np.diag(d), g[free])
        except np.linalg.LinAlgError:
            h[free] = -np.linalg.lstsq(A + lam * np.diag(d), g[free], rcond=None)[0]
        x_new = np.clip(x + h * scale, lower, upper)
        h = (x_new - x) / scale
        predicted = -(2.0 * h @ g + h @ (Js.T @ (Js @ h)))
        r_new = fun(x_new)
        nfev += 1
        cost_new = float(r_new @ r_new) if np.all(np.isfinite(r_new)) else np.inf
        if cost_new < cost:
            rel = (cost - cost_new) / max(cost, 1e-300)
            rho = (cost - cost_new) / predicted if predicted > 0 else 0.0
            dx = np.max(np.abs(h))
            x, cost = x_new, cost_new
            r, J = jac(x)
            # Nielsen's damping update: shrink a lot when the linear model was good
            lam = max(lam * max(1.0 / 3.0, 1.0 - (2.0 * rho - 1.0) ** 3), 1e-12)
            nu = 2.0
            if rel < tol or dx < tol:
                converged = True
                break
        else:
            lam *= nu
            nu *= 2.0
            if lam > 1e10:
                converged = True  # no downhill step left: a (possibly bounded) minimum
                break
    return x, nfev, converged


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
    """Fit from the data-based initial guess, trying a few curvature/shape starts."""
    g = initial_guess(data)
    best = None
    for a0, a7 in ((1.4, -0.3), (1.2, 0.3), (1.7, -1.0)):
        g.update(a0=a0, a7=a7)
        try:
            out = fit(spec, data, x0=spec.start(g))
        except FitError:
            continue
        if best is None or out.rmse < best.rmse:
            best = out
    if best is None:
        raise FitError("PAC89 start model could not be fitted to these data")
    return best
