"""The one fitting core: parameters, sweeps of data, and one least-squares solver.

Every fit in tyrefit (the PAC89 fit of ``tyrefit fit``, the staged Magic
Formula fit, diagnosis refits, the brush, slip-law and rig fits) states its
problem in these three pieces and calls :func:`solve`:

* :class:`Parameter` / :class:`Parameters`: name, value, bounds, ``vary``,
  standard error, unit and typical scale, like :class:`lmfit.Parameters`
  (and convertible to and from them: :meth:`Parameters.to_lmfit`,
  :meth:`Parameters.from_lmfit`).  A parameter with ``vary=False`` is not an
  unknown of the solver at all, so it is held *exactly*.
* :class:`Sweeps`: the measured points of a fit: the fitted quantity ``y``,
  the sweep each point belongs to, the operating conditions (load, slip,
  camber, pressure, speed ...) and the per-point cost weights (by default
  ``1/n_s``, each sweep counting once whatever its sampling density).
* :func:`solve`: bounded :func:`scipy.optimize.least_squares` (trust-region
  reflective) with x-scaling, an analytic or finite-difference Jacobian,
  the cost as an option, multi-start, and one :class:`Solution` with values,
  standard errors from the Jacobian, cost, RMSE and the residual variance.

Design choices
--------------
Why our own parameter container and not :class:`lmfit.Parameters` itself:
diagnosis builds thousands of small problems, and an ``lmfit.Parameters``
carries an expression interpreter per instance (about 1 ms to create and to
copy); tyrefit needs no constraint expressions.  The fields and names are
lmfit's (``value``, ``min``, ``max``, ``vary``, ``stderr``, ``valuesdict``),
and :class:`~tyrefit.fitting.result.FitResult` still exposes lmfit objects.

The cost is an option of the one solver.  With weights w_i and residuals r_i
(model - data, in whatever quantity the caller fits):

* ``'l2'``: sum w_i r_i^2 (least squares);
* ``'l1'``: sum w_i |r_i|, Komana, Els and Becker's Eq. 5, reached by a
  pseudo-Huber (soft l1) continuation from the start (normally the l2
  solution): its scale shrinks 0.3, 0.03, 0.003 x the median weighted
  residual, so the smooth problem converges to the l1 minimum;
* ``'huber'``, ``'soft_l1'``: outlier-resistant, sum w_i s_i^2 rho((r_i/s_i)^2)
  with a per-point scale s_i (``scale=``; e.g. 1.345 x each sweep's noise);
  with a scalar scale and unit weights this is SciPy's own ``loss=`` with
  ``f_scale``; ``'cauchy'`` and ``'arctan'`` likewise.

Which caller uses which cost, and why:

* PAC89 fit (:mod:`tyrefit.fitting.engine`): r = F/Fz residual (mu), w = 1/n_s;
  ``l2`` by default, ``l1`` / ``huber`` / ``soft_l1`` on request
  (``tyrefit fit --cost``).  mu removes the load scale and 1/n_s keeps a
  densely sampled sweep from dominating: the model's *shape* over the whole
  test matrix is what the tyre file must carry (Komana et al., section 4.3).
* Magic Formula stages (:mod:`tyrefit.fitting.mf`): the same (force over load,
  moments over load x radius, w = 1/n_s) plus penalty rows for the physical
  constraints (weight 1).
* Diagnosis (:mod:`tyrefit.diagnose.fitter`): r in N, w = 1, ``l2``: the
  screening statistics, the bootstrap noise model and the held-out RMSE are
  all in N per point, so the fit must minimise exactly the point-wise sum
  of squares those statistics assume (a 1/n_s or 1/Fz weighting would make
  the fitted model no longer the least-squares model they test).
* Brush, slip-law and rig fits: unweighted ``l2`` on their own residuals
  (force over load, friction, width, length), SciPy's soft l1 with a fixed
  scale in the rig calibration (stick-slip scatter).

Standard errors are the Gauss-Newton ones at the solution,
cov = s^2 (J^T J)^+ (the pseudo-inverse taken with the columns of J scaled to
unit norm, so that parameters of very different size do not fool its cut-off) with s^2 = sum w r^2 / (N - p) of the *least-squares*
weighting sqrt(w) r, whatever the cost (for l1 and the robust costs this is
the least-squares approximation at their solution), over the data rows only
(penalty rows excluded).

Two back ends sit behind :func:`solve`: SciPy's ``'trf'`` (or ``'dogbox'``)
for every fit, and ``'lm-normal'``, a box-constrained Levenberg-Marquardt on
the p x p normal equations, for the many small warm-started refits of a
diagnosis (p <= ~20, N up to a few thousand, starts close to the optimum),
where forming J^T J is far cheaper than the SVD/QR that ``trf`` does per
iteration.  Both take the same parameters, weights and scales and give the
same :class:`Solution`.
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Callable, Iterable, Mapping, Sequence
from dataclasses import dataclass, field

import numpy as np
import pandas as pd
from scipy.optimize import least_squares

from ..errors import FitError

__all__ = ["Parameter", "Parameters", "Sweeps", "Solution", "solve", "objective", "covariance", "COSTS",
           "ROBUST_LOSSES", "interior", "huber", "soft_l1", "lm_normal", "lm_normal_batch"]


# ------------------------------------------------------------------------------ parameters
@dataclass
class Parameter:
    """One fitted (or held) quantity.

    Attributes
    ----------
    name : str
    value : float
    min, max : float
        Hard bounds (``-inf`` / ``inf`` for none).
    vary : bool
        False: held exactly at ``value`` (not an unknown of the solver).
    stderr : float or None
        Standard error after a fit (None before, or when held).
    unit : str
        Unit of the value, e.g. ``'N'``, ``'1/kN'`` (PAC89 units for PAC89 coefficients).
    scale : float or None
        Typical magnitude, for solver scaling and finite-difference steps
        (None: max(|value|, 1)).
    meaning : str
        One line for reports.
    """

    name: str
    value: float = 0.0
    min: float = -np.inf
    max: float = np.inf
    vary: bool = True
    stderr: float | None = None
    unit: str = ""
    scale: float | None = None
    meaning: str = ""

    def __post_init__(self):
        self.value = float(self.value)
        self.min = -np.inf if self.min is None else float(self.min)
        self.max = np.inf if self.max is None else float(self.max)
        if self.min > self.max:
            raise ValueError(f"parameter {self.name}: min {self.min:g} > max {self.max:g}")

    @property
    def typical(self) -> float:
        """The scale used by the solver: ``scale`` or max(|value|, 1)."""
        return float(self.scale) if self.scale else max(abs(self.value), 1.0)

    @property
    def bounds(self) -> tuple[float, float]:
        return self.min, self.max

    def at_bound(self, rel: float = 1e-6) -> str | None:
        """``'lower'`` / ``'upper'`` when the value sits on that bound (within ``rel``), else None."""
        for b, side in ((self.min, "lower"), (self.max, "upper")):
            if np.isfinite(b) and abs(self.value - b) <= rel * max(1.0, abs(b)):
                return side
        return None


class Parameters(dict):
    """Ordered mapping name -> :class:`Parameter` (insertion order is the solver's order).

    Examples
    --------
    >>> p = Parameters()
    >>> _ = p.add("mu", 1.0, min=0.05, max=3.0, unit="-")
    >>> _ = p.add("k", 20.0, min=1e-6, vary=False)
    >>> p.free(), p.valuesdict()
    (['mu'], {'mu': 1.0, 'k': 20.0})
    """

    def add(self, name: str, value: float = 0.0, *, min: float = -np.inf, max: float = np.inf,  # noqa: A002
            vary: bool = True, unit: str = "", scale: float | None = None, meaning: str = "") -> Parameter:
        """Add (or replace) a parameter and return it."""
        p = Parameter(name, value, min, max, vary, None, unit, scale, meaning)
        self[name] = p
        return p

    @classmethod
    def from_values(cls, values: Mapping[str, float], *, bounds: Mapping[str, tuple[float, float]] | None = None,
                    vary: Iterable[str] | None = None, scale: Mapping[str, float] | None = None) -> "Parameters":
        """Parameters from a name -> value mapping; ``vary`` names the free ones (default: all)."""
        bounds, scale = bounds or {}, scale or {}
        free = None if vary is None else set(vary)
        out = cls()
        for k, v in values.items():
            lo, hi = bounds.get(k, (-np.inf, np.inf))
            out.add(k, float(v), min=lo, max=hi, vary=free is None or k in free, scale=scale.get(k))
        return out

    @classmethod
    def from_lmfit(cls, params) -> "Parameters":
        """Copy of an :class:`lmfit.Parameters` (expressions are evaluated to values and held)."""
        out = cls()
        for k, p in params.items():
            q = out.add(k, float(p.value), min=p.min, max=p.max, vary=bool(p.vary) and not p.expr)
            q.stderr = None if p.stderr is None else float(p.stderr)
        return out

    def to_lmfit(self):
        """The same parameters as :class:`lmfit.Parameters` (values, bounds, vary, stderr)."""
        import lmfit

        out = lmfit.Parameters()
        for k, p in self.items():
            out.add(k, value=p.value, min=p.min, max=p.max, vary=p.vary)
            out[k].stderr = p.stderr
        return out

    def copy(self) -> "Parameters":
        out = Parameters()
        for k, p in self.items():
            out[k] = Parameter(p.name, p.value, p.min, p.max, p.vary, p.stderr, p.unit, p.scale, p.meaning)
        return out

    def free(self) -> list[str]:
        """Names of the varying parameters, in order."""
        return [k for k, p in self.items() if p.vary]

    def valuesdict(self) -> dict[str, float]:
        """name -> value of every parameter (lmfit's name)."""
        return {k: p.value for k, p in self.items()}

    def vector(self) -> np.ndarray:
        """Values of the free parameters."""
        return np.array([p.value for p in self.values() if p.vary], dtype=float)

    def bounds_arrays(self) -> tuple[np.ndarray, np.ndarray]:
        """(lower, upper) of the free parameters."""
        free = [p for p in self.values() if p.vary]
        return (np.array([p.min for p in free], dtype=float), np.array([p.max for p in free], dtype=float))

    def scales(self) -> np.ndarray:
        """Typical magnitudes of the free parameters (see :attr:`Parameter.typical`)."""
        return np.array([p.typical for p in self.values() if p.vary], dtype=float)

    def values_of(self, x: Sequence[float]) -> dict[str, float]:
        """name -> value with the free parameters set from the vector ``x`` (held ones as they are)."""
        out = self.valuesdict()
        out.update(zip(self.free(), (float(v) for v in x)))
        return out

    def set_vector(self, x: Sequence[float], stderr: Sequence[float] | None = None) -> None:
        """Set the free parameters' values (and standard errors) from vectors."""
        for j, k in enumerate(self.free()):
            self[k].value = float(x[j])
            if stderr is not None:
                self[k].stderr = float(stderr[j])


# ------------------------------------------------------------------------------ the data
@dataclass
class Sweeps:
    """The measured points of one fit, grouped in sweeps.

    Attributes
    ----------
    y : ndarray (N,)
        The fitted quantity (force [N], moment [N*m], mu [-], width [m] ...).
    sweep : ndarray (N,)
        Sweep id of each point (any labels; a sweep is one slip sweep at one
        steady condition, the unit of weighting, resampling and hold-out).
    x : dict of str -> ndarray (N,)
        Operating conditions and inputs of each point, SI (``fz`` [N],
        ``slip_angle`` [rad], ``slip_ratio`` [-], ``camber`` [rad],
        ``pressure`` [Pa], ``speed`` [m/s] ...).
    weights : ndarray (N,) or None
        Cost weight w_i of each point (cost = sum w_i rho(r_i)); None:
        ``1/n_s`` (each sweep counts once; see :meth:`sweep_weights`).
    levels : dict of str -> ndarray
        Condition levels (set points) of a factor, when known.
    """

    y: np.ndarray
    sweep: np.ndarray
    x: dict[str, np.ndarray] = field(default_factory=dict)
    weights: np.ndarray | None = None
    levels: dict[str, np.ndarray] = field(default_factory=dict)

    def __post_init__(self):
        self.y = np.asarray(self.y, dtype=float)
        self.sweep = np.asarray(self.sweep)
        if self.sweep.shape != self.y.shape:
            raise ValueError(f"sweep ids ({self.sweep.shape}) and y ({self.y.shape}) differ in shape")
        for k, v in self.x.items():
            if np.ndim(v) and np.shape(v) != self.y.shape:
                raise ValueError(f"condition {k!r} has shape {np.shape(v)}, y has {self.y.shape}")

    @classmethod
    def from_frame(cls, df: pd.DataFrame, y: str, x: Iterable[str] = (), sweep: str = "run",
                   weights: str | np.ndarray | None = "sweep") -> "Sweeps":
        """Sweeps from a DataFrame: column ``y``, conditions ``x`` (those present), sweep ids from ``sweep``.

        ``weights``: ``'sweep'`` (1/n_s, default), ``'point'`` (1 each) or an array.
        """
        sw = df[sweep].to_numpy() if sweep in df else np.zeros(len(df), dtype=int)
        cond = {c: df[c].to_numpy(float) for c in x if c in df}
        out = cls(df[y].to_numpy(float), sw, cond)
        if isinstance(weights, str):
            out.weights = out.sweep_weights() if weights == "sweep" else np.ones(out.n)
        elif weights is not None:
            out.weights = np.asarray(weights, dtype=float)
        return out

    @property
    def n(self) -> int:
        return int(self.y.size)

    @property
    def n_sweeps(self) -> int:
        return int(np.unique(self.sweep).size) if self.n else 0

    @property
    def n_per_sweep(self) -> np.ndarray:
        """Number of points of each point's sweep (N,)."""
        _, inv, cnt = np.unique(self.sweep, return_inverse=True, return_counts=True)
        return cnt[inv.reshape(-1)].astype(float)

    def sweep_weights(self) -> np.ndarray:
        """1/n_s per point: every sweep weighs alike in the cost, however densely it was sampled."""
        return 1.0 / self.n_per_sweep

    @property
    def w(self) -> np.ndarray:
        """The cost weights in use (``weights``, or 1/n_s)."""
        return self.sweep_weights() if self.weights is None else self.weights

    def take(self, idx) -> "Sweeps":
        """The points ``idx`` (index array or mask); weights are recomputed when they were the default."""
        return Sweeps(self.y[idx], self.sweep[idx], {k: (np.asarray(v)[idx] if np.ndim(v) else v)
                                                    for k, v in self.x.items()},
                      None if self.weights is None else self.weights[idx], dict(self.levels))


# ------------------------------------------------------------------------------ robust losses
def huber(z):
    """Huber's loss on z = (r/s)^2 with its derivatives in z (rows: rho, rho', rho'')."""
    out = np.empty((3, z.size))
    small = z <= 1.0
    sz = np.sqrt(np.where(small, 1.0, z))
    out[0] = np.where(small, z, 2.0 * sz - 1.0)
    out[1] = np.where(small, 1.0, 1.0 / sz)
    out[2] = np.where(small, 0.0, -0.5 / (sz * np.where(small, 1.0, z)))
    return out


def soft_l1(z):
    """Pseudo-Huber (soft l1) loss 2 (sqrt(1 + z) - 1) with its derivatives in z."""
    t = 1.0 + z
    return np.vstack([2.0 * (np.sqrt(t) - 1.0), t**-0.5, -0.5 * t**-1.5])


#: robust costs with a per-point scale: rho of z = (r / s)^2 (SciPy's definitions)
ROBUST_LOSSES = {"huber": huber, "soft_l1": soft_l1}
#: every cost :func:`solve` accepts
COSTS = ("l2", "l1", "huber", "soft_l1", "cauchy", "arctan")
_SCIPY_LOSS = {"l2": "linear", "huber": "huber", "soft_l1": "soft_l1", "cauchy": "cauchy", "arctan": "arctan"}
#: the pseudo-Huber scales of the l1 continuation, as fractions of the median weighted residual at the start
L1_STEPS = (0.3, 0.03, 0.003)


def interior(x, lb, ub, rel: float = 1e-9) -> np.ndarray:
    """Project ``x`` strictly inside [lb, ub] (by rel x max(1, |bound|)); a degenerate box gives its middle."""
    x = np.asarray(x, dtype=float).copy()
    for j in range(x.size):
        a, b = lb[j], ub[j]
        ea = rel * max(1.0, abs(a)) if np.isfinite(a) else 0.0
        eb = rel * max(1.0, abs(b)) if np.isfinite(b) else 0.0
        if np.isfinite(a) and np.isfinite(b) and b - a <= ea + eb:
            x[j] = 0.5 * (a + b)
        else:
            x[j] = min(max(x[j], a + ea), b - eb)
    return x


# ------------------------------------------------------------------------------ the result
@dataclass
class Solution:
    """What :func:`solve` returns.

    Attributes
    ----------
    params : Parameters
        All parameters with the fitted values and standard errors (held ones unchanged).
    x : ndarray
        Fitted values of the free parameters (solver order: ``names``).
    names : list of str
    stderr : dict
        Standard error of each free parameter (NaN when the Jacobian is singular).
    cov : ndarray
        Covariance of ``x`` (Gauss-Newton, least-squares weighting).
    cost : float
        The objective at ``x`` under the cost used: sum w r^2 (l2), sum w |r| (l1),
        sum w s^2 rho((r/s)^2) (robust).
    rmse : float
        sqrt(mean r^2) over the data rows, unweighted, in the residual's unit.
    s2 : float
        Residual variance sum w r^2 / (N - p) (the noise estimate behind ``stderr``).
    resid : ndarray
        Unweighted residual r (model - data) at ``x``, data rows and any extra rows.
    nfev : int
        Residual evaluations, all starts and continuation steps included.
    success : bool
    message : str
    starts : list of dict
        One row per start: ``start``, ``cost``, ``nfev``.
    """

    params: Parameters
    x: np.ndarray
    names: list[str]
    stderr: dict[str, float]
    cov: np.ndarray
    cost: float
    rmse: float
    s2: float
    resid: np.ndarray
    nfev: int
    success: bool
    message: str = ""
    starts: list[dict] = field(default_factory=list)
    jac: np.ndarray | None = field(default=None, repr=False)

    @property
    def values(self) -> dict[str, float]:
        """name -> value of every parameter."""
        return self.params.valuesdict()

    @property
    def correl(self) -> pd.DataFrame:
        """Correlation matrix of the free parameters."""
        sd = np.sqrt(np.clip(np.diag(self.cov), 0, None)) if self.cov.size else np.zeros(0)
        with np.errstate(invalid="ignore", divide="ignore"):
            c = self.cov / np.outer(sd, sd)
        return pd.DataFrame(c, index=self.names, columns=self.names)

    def at_bound(self, rel: float = 1e-6) -> dict[str, str]:
        """Free parameters that ended on a bound: name -> 'lower' / 'upper'."""
        out = {}
        for k in self.names:
            side = self.params[k].at_bound(rel)
            if side:
                out[k] = side
        return out


# ------------------------------------------------------------------------------ the solver
class _Cached:
    """The caller's residual, remembering its last few evaluations (the start check, SciPy's first call and
    the final statistics then share them)."""

    def __init__(self, fun, size: int = 3):
        self.fun, self.size, self.memo = fun, size, []

    def __call__(self, x):
        key = np.asarray(x, dtype=float).tobytes()
        for k, v in self.memo:
            if k == key:
                return v
        v = np.asarray(self.fun(np.array(x, dtype=float)), dtype=float)
        self.memo.append((key, v))
        if len(self.memo) > self.size:
            self.memo.pop(0)
        return v


class _Weighted:
    """The caller's residual r(x) (and Jacobian) as the solver sees it: m * r with m per the cost."""

    def __init__(self, residual, jac, m, nonfinite, big):
        self.residual, self.user_jac, self.m = residual, jac, m
        self.nonfinite, self.big = nonfinite, big
        self.nfev = 0

    def __call__(self, x):
        self.nfev += 1
        f = self.m * np.asarray(self.residual(x), dtype=float)
        if self.nonfinite == "penalise":
            f = np.where(np.isfinite(f), f, self.big)
        return f

    def jac(self, x):
        J = np.asarray(self.user_jac(x), dtype=float)
        return J * self.m[:, None] if np.ndim(self.m) else J * self.m


def _multiplier(cost: str, w: np.ndarray | None, scale) -> tuple[np.ndarray | float, object, float]:
    """Residual multiplier, SciPy loss and f_scale for a cost (see the module docstring)."""
    if cost == "l1":
        return (1.0 if w is None else w), "soft_l1", 1.0
    if cost == "l2":
        return (1.0 if w is None else np.sqrt(w)), "linear", 1.0
    if np.ndim(scale) == 0 and w is None:  # SciPy's own loss with a scalar scale
        return 1.0, _SCIPY_LOSS[cost], float(scale if scale is not None else 1.0)
    if cost not in ROBUST_LOSSES:
        raise ValueError(f"cost {cost!r} takes a scalar scale and no weights")
    s = np.asarray(scale, dtype=float) * np.ones(1)
    rho = ROBUST_LOSSES[cost]
    ww = 1.0 if w is None else w

    def loss(z):
        return rho(z) * (s**2 * ww)

    return 1.0 / s, loss, 1.0


def solve(residual: Callable[[np.ndarray], np.ndarray], params: Parameters, *,
          jac: Callable[[np.ndarray], np.ndarray] | str | None = None,
          fun_jac: Callable[[np.ndarray], tuple[np.ndarray, np.ndarray]] | None = None,
          data: Sweeps | None = None, weights: np.ndarray | None = None, n_data: int | None = None,
          cost: str = "l2", scale: float | np.ndarray | None = None,
          method: str = "trf", x_scale: str | float | np.ndarray = "jac",
          starts: Sequence[Mapping[str, float] | np.ndarray] | None = None,
          tol: float = 1e-8, ftol: float | None = None, xtol: float | None = None, gtol: float | None = None,
          max_nfev: int | None = None, nonfinite: str = "raise",
          stderr: bool = True, what: str = "fit") -> Solution:
    """Fit the free parameters of ``params`` by (weighted, bounded, possibly robust) least squares.

    Parameters
    ----------
    residual : callable
        ``residual(x) -> r``: model minus data at the free values ``x`` (in the
        order of ``params.free()``; ``params.values_of(x)`` gives every value).
        It may return extra rows after the first ``n_data`` (penalties); they
        take weight 1 unless ``weights`` covers them.
    params : Parameters
        Start values, bounds, ``vary`` and scales.
    jac : callable or {'2-point', '3-point'} or None
        ``jac(x) -> dr/dx`` (N, p) of the *unweighted* residual, or a finite-
        difference scheme (default ``'2-point'``).
    fun_jac : callable, optional
        ``fun_jac(x) -> (r, J)`` in one call (what ``'lm-normal'`` uses when given).
    data : Sweeps, optional
        Supplies the weights (``data.w``) when ``weights`` is None.
    weights : ndarray, optional
        Cost weight w_i per residual row (default: ``data.w``, else 1).
    n_data : int, optional
        Rows of ``r`` that are data (RMSE, s^2, standard errors, the l1 scale);
        default all.
    cost : {'l2', 'l1', 'huber', 'soft_l1', 'cauchy', 'arctan'}
        See the module docstring.
    scale : float or ndarray, optional
        Robust costs: the residual scale s (scalar, or per row).
    method : {'trf', 'dogbox', 'lm-normal'}
        SciPy's trust-region reflective (default) or dogbox, or the normal-
        equation Levenberg-Marquardt for small warm-started refits (``l2`` only).
    x_scale : 'jac', float, ndarray or 'params'
        SciPy's x_scale; ``'params'`` uses each parameter's typical scale.
        ``'lm-normal'`` always uses the parameters' typical scales.
    starts : sequence of mappings or vectors, optional
        Multi-start: each is solved from (mappings fill in the free names they
        carry over ``params``' values) and the lowest cost wins; starts at
        which the residual is not finite are skipped.  Default: ``params``' values.
    tol : float
        ftol = xtol = gtol (SciPy); relative cost change (``'lm-normal'``).
    ftol, xtol, gtol : float, optional
        SciPy's tolerances one by one (default ``tol``).
    max_nfev : int, optional
        Evaluation limit per solve (default SciPy's: 100 p; 200 for ``'lm-normal'``).
    nonfinite : {'raise', 'penalise'}
        A non-finite residual at the start raises :class:`FitError`; with
        ``'penalise'`` non-finite rows become 1e3 x the largest row multiplier
        during the solve (a model that cannot be evaluated is far off).
    stderr : bool
        Compute standard errors (one more Jacobian).
    what : str
        Name of the fit, for error messages.

    Returns
    -------
    Solution

    Raises
    ------
    FitError
        The residual is not finite at every start.
    """
    if cost not in COSTS:
        raise ValueError(f"cost {cost!r} is not one of {', '.join(COSTS)}")
    names = params.free()
    lb, ub = params.bounds_arrays()
    typical = params.scales()
    x_start = params.vector()
    if weights is None and data is not None:
        weights = data.w
    w = None if weights is None else np.asarray(weights, dtype=float)
    if starts is None:
        starts = [x_start]
    residual = _Cached(residual)
    if not names:  # nothing varies: evaluate only
        r = np.asarray(residual(x_start), dtype=float)
        return _solution(params, names, x_start, r, None, w, n_data, cost, scale, 1, True, "nothing to fit",
                         [], stderr=False)
    if method == "lm-normal" and cost != "l2":
        raise ValueError("method 'lm-normal' solves the l2 cost only")
    if jac is None:
        jac = "2-point"
    tols = (tol if ftol is None else ftol, tol if xtol is None else xtol, tol if gtol is None else gtol)
    log, best = [], None
    nfev = 0
    for si, st in enumerate(starts):
        if isinstance(st, Mapping):
            x0 = np.array([float(st.get(k, params[k].value)) for k in names])
        else:
            x0 = np.asarray(st, dtype=float)
        x, n, ok, msg, fails, J_fd = _solve_one(residual, jac, fun_jac, x0, lb, ub, typical, w, n_data, cost, scale,
                                          method, x_scale, tols, max_nfev, nonfinite)
        nfev += n
        if fails:
            log.append({"start": si, "cost": float("inf"), "nfev": n})
            continue
        r = np.asarray(residual(x), dtype=float)
        c = objective(r, w, cost, scale)
        log.append({"start": si, "cost": c, "nfev": n})
        if best is None or c < best[0]:
            best = (c, x, r, ok, msg, J_fd)
    if best is None:
        raise FitError(f"{what}: the model is not finite at the start values; check the data (units, signs, a flat "
                       "or zero channel?)")
    _, x, r, ok, msg, J = best
    if stderr and J is None:
        J = _unweighted_jac(residual, jac, fun_jac, x, lb, ub, typical, r)
    return _solution(params, names, x, r, J, w, n_data, cost, scale, nfev, ok, msg, log, stderr=stderr)


def _solve_one(residual, jac, fun_jac, x0, lb, ub, typical, w, n_data, cost, scale, method, x_scale, tol,
               max_nfev, nonfinite):
    """One start: (x, nfev, success, message, failed_at_start, SciPy's FD Jacobian of r at x or None).

    ``nfev`` counts residual evaluations as SciPy does (without those of a
    finite-difference Jacobian).
    """
    r0 = np.asarray(residual(x0), dtype=float)
    n_rows = r0.size
    if not np.all(np.isfinite(r0)) and nonfinite == "raise":
        return x0, 1, False, "not finite at the start", True, None
    ww = None if w is None else _pad(w, n_rows)
    if method == "lm-normal":
        x0 = np.clip(x0, lb, ub)
        if fun_jac is None:
            def fun_jac(t):
                return np.asarray(residual(t), dtype=float), np.asarray(jac(t), dtype=float)
        m = 1.0 if ww is None else np.sqrt(ww)
        if ww is None:
            fj, fr = fun_jac, residual
        else:
            def fj(t):
                rr, JJ = fun_jac(t)
                return m * rr, JJ * m[:, None]

            def fr(t):
                return m * residual(t)
        x, n, ok = lm_normal(fj, fr, x0, lb, ub, typical, max_nfev or 200, tol[0])
        return x, n, ok, "", False, None
    xs = typical if isinstance(x_scale, str) and x_scale == "params" else x_scale
    if cost == "l1":
        m = 1.0 if ww is None else ww
        fr = _Weighted(residual, jac if callable(jac) else None, m, nonfinite, 0.0)
        x = interior(x0, lb, ub)
        f0 = fr(x)
        rows = f0[:n_data] if n_data else f0
        s0 = float(np.median(np.abs(rows))) or 1e-9
        ok, msg, nfev = True, "", 0
        fr.big = 1e3 * float(np.max(np.abs(m))) if np.ndim(m) else 1e3 * m
        for frac in L1_STEPS:
            res = _lsq(fr, jac, x, lb, ub, xs, "soft_l1", frac * s0, method, tol, max_nfev)
            x, ok, msg, nfev = res.x, bool(res.success), str(res.message), nfev + int(res.nfev)
        return x, nfev, ok, msg, False, None
    m, loss, f_scale = _multiplier(cost, ww, scale)
    big = 1e3 * (float(np.max(m)) if np.ndim(m) else float(m))
    fr = _Weighted(residual, jac if callable(jac) else None, m, nonfinite, big)
    res = _lsq(fr, jac, interior(x0, lb, ub), lb, ub, xs, loss, f_scale, method, tol, max_nfev)
    J = None
    if not callable(jac) and loss == "linear":  # SciPy's FD Jacobian of m r at x: keep it (lmfit does)
        J = res.jac / m[:, None] if np.ndim(m) else res.jac / m
    return res.x, int(res.nfev), bool(res.success), str(res.message), False, J


def _pad(w, n_rows):
    w = np.asarray(w, dtype=float)
    if w.size == n_rows:
        return w
    if w.size > n_rows:
        raise ValueError(f"{w.size} weights for {n_rows} residual rows")
    return np.concatenate([w, np.ones(n_rows - w.size)])


def _lsq(fr: _Weighted, jac, x0, lb, ub, x_scale, loss, f_scale, method, tol, max_nfev):
    """One SciPy solve; ``tol`` is (ftol, xtol, gtol)."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        return least_squares(fr, x0, jac=fr.jac if callable(jac) else jac, bounds=(lb, ub), method=method,
                             x_scale=x_scale, loss=loss, f_scale=f_scale, ftol=tol[0], xtol=tol[1], gtol=tol[2],
                             max_nfev=max_nfev)


def objective(r, w, cost: str = "l2", scale=None) -> float:
    """The cost of residuals ``r`` with weights ``w`` (None: 1) under ``cost`` (see the module docstring)."""
    ww = None if w is None else _pad(w, r.size)
    if cost == "l2":
        return float(np.sum(r * r if ww is None else ww * r * r))
    if cost == "l1":
        return float(np.sum(np.abs(r) if ww is None else ww * np.abs(r)))
    s = 1.0 if scale is None else np.asarray(scale, dtype=float)
    z = (r / s) ** 2
    if cost in ROBUST_LOSSES:
        rho = ROBUST_LOSSES[cost](np.atleast_1d(z))[0]
    elif cost == "cauchy":
        rho = np.log1p(z)
    else:
        rho = np.arctan(z)
    return float(np.sum(rho * s**2 * (1.0 if ww is None else ww)))


def _unweighted_jac(residual, jac, fun_jac, x, lb, ub, typical, r):
    if fun_jac is not None:
        return np.asarray(fun_jac(x)[1], dtype=float)
    if callable(jac):
        return np.asarray(jac(x), dtype=float)
    # forward differences inside the box (SciPy's 2-point step)
    J = np.empty((r.size, x.size))
    eps = math.sqrt(np.finfo(float).eps)
    for j in range(x.size):
        h = eps * max(abs(x[j]), 1.0)
        t = x.copy()
        t[j] = x[j] + h if x[j] + h <= ub[j] else x[j] - h
        J[:, j] = (np.asarray(residual(t), dtype=float) - r) / (t[j] - x[j])
    return J


def covariance(J: np.ndarray, r: np.ndarray, w: np.ndarray | None = None, n_data: int | None = None
               ) -> tuple[np.ndarray, float]:
    """Gauss-Newton covariance of the parameters and the residual variance s^2.

    cov = s^2 (J_w^T J_w)^+ with J_w = sqrt(w) J and s^2 = sum w r^2 / (N - p)
    over the first ``n_data`` rows (the least-squares weighting, whatever the
    cost).  The pseudo-inverse is taken with the columns of J_w scaled to unit
    norm, so that its cut-off sees the problem's conditioning and not the
    parameters' units (a stiffness of 4e7 N/m beside a friction of 1).

    Parameters
    ----------
    J : ndarray (N, p)
        Jacobian of the unweighted residual.
    r : ndarray (N,)
        Unweighted residual.
    w : ndarray, optional
        Cost weights (default 1).
    n_data : int, optional
        Data rows (default all).
    """
    n = r.size if n_data is None else int(n_data)
    rd = r[:n]
    wd = np.ones(n) if w is None else _pad(w, r.size)[:n]
    p = J.shape[1]
    s2 = float(np.sum(wd * rd * rd)) / max(1, n - p)
    cov = np.full((p, p), np.nan)
    if p:
        Jw = J[:n] * np.sqrt(wd)[:, None]
        d = np.linalg.norm(Jw, axis=0)
        d = np.where(d > 0, d, 1.0)
        try:
            Js = Jw / d
            cov = np.linalg.pinv(Js.T @ Js) / np.outer(d, d) * s2
        except np.linalg.LinAlgError:  # pragma: no cover
            pass
    return cov, s2


def _solution(params, names, x, r, J, w, n_data, cost, scale, nfev, ok, msg, log, *, stderr) -> Solution:
    n = r.size if n_data is None else int(n_data)
    rd = r[:n]
    p = len(names)
    if stderr and J is not None and p:
        cov, s2 = covariance(J, r, w, n_data)
    else:
        wd = np.ones(n) if w is None else _pad(w, r.size)[:n]
        cov, s2 = np.full((p, p), np.nan), float(np.sum(wd * rd * rd)) / max(1, n - p)
    sd = np.sqrt(np.clip(np.diag(cov), 0, None)) if p else np.zeros(0)
    out = params.copy()
    out.set_vector(x, sd if stderr else None)
    return Solution(params=out, x=np.asarray(x, dtype=float), names=list(names),
                    stderr=dict(zip(names, sd.tolist())), cov=cov, cost=objective(r, w, cost, scale),
                    rmse=float(np.sqrt(np.mean(rd * rd))) if n else float("nan"), s2=s2, resid=r, nfev=int(nfev),
                    success=bool(ok), message=msg, starts=log, jac=J)


# ------------------------------------------------------------------------------ lm-normal
def lm_normal(jac, fun, x, lower, upper, scale, max_nfev: int, tol: float = 1e-9):
    """Box-constrained Levenberg-Marquardt on the scaled normal equations (the ``'lm-normal'`` back end).

    The problems are small (P <= ~20 parameters) and start close to the
    optimum, so solving the P x P normal equations with Marquardt's diagonal
    damping is far cheaper than an SVD of the N x P Jacobian per iteration.
    Parameters at a bound whose descent direction points out of the box are
    held there for the step (active set); the others are clipped to the box.
    Converges when an accepted step lowers the cost by less than ``tol``
    relatively or moves no parameter by more than ``tol`` of its scale.

    Parameters
    ----------
    jac : callable
        ``jac(x) -> (r, J)``.
    fun : callable
        ``fun(x) -> r``.

    Returns
    -------
    x, evaluations, converged
    """
    r, J = jac(x)
    cost = float(r @ r)
    lam, nu = 1e-3, 2.0
    nfev = 1
    converged = False
    span = 1e-12 * scale
    lo, hi = lower + span, upper - span  # at a bound within these
    scale_rows = np.broadcast_to(scale, np.shape(J)).copy()  # J * scale as one same-shape product
    while nfev < max_nfev:
        Js = J * scale_rows
        g = Js.T @ r
        active = ((x <= lo) & (g > 0)) | ((x >= hi) & (g < 0))
        free = ~active
        A = Js[:, free].T @ Js[:, free]
        d = np.diag(A).copy()
        d[d <= 0] = 1.0
        h = np.zeros_like(x)
        try:
            h[free] = -np.linalg.solve(A + lam * np.diag(d), g[free])
        except np.linalg.LinAlgError:
            h[free] = -np.linalg.lstsq(A + lam * np.diag(d), g[free], rcond=None)[0]
        x_new = np.minimum(np.maximum(x + h * scale, lower), upper)  # clipped into the box
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
            if rel < tol or dx < tol:
                converged = True
                break
            r, J = jac(x)  # (not at the converged point: nothing reads it there)
            # Nielsen's damping update: shrink a lot when the linear model was good
            lam = max(lam * max(1.0 / 3.0, 1.0 - (2.0 * rho - 1.0) ** 3), 1e-12)
            nu = 2.0
        else:
            lam *= nu
            nu *= 2.0
            if lam > 1e10:
                converged = True  # no downhill step left: a (possibly bounded) minimum
                break
    return x, nfev, converged


def lm_normal_batch(jac, fun, x, w, lower, upper, scale, max_nfev: int, tol: float = 1e-9):
    """:func:`lm_normal` on F problems at once that share their points and differ in their weights.

    Problem f minimises sum_n w[f, n] r_f(x_f)[n]^2 (weights 0 or 1 leave
    points out: the folds of a cross-validation).  Every problem takes the
    steps :func:`lm_normal` would take on its own (same damping, active set,
    acceptance and convergence rules), but each iteration evaluates the
    model and its Jacobian for all unfinished problems in one call, so the
    per-call overhead of the model is paid once per iteration, not F times.

    Parameters
    ----------
    jac : callable
        ``jac(X, rows) -> (R, J)``: residuals (len(rows), N) and Jacobians
        (len(rows), N, P) of the problems ``rows`` at their parameters ``X``.
    fun : callable or None
        ``fun(X, rows) -> R``.  None: the trial points are evaluated with
        ``jac``, and an accepted step's Jacobian is the one made there (fewer
        model calls when most steps are accepted and ``jac`` costs little more
        than ``fun``; the same steps, as ``jac``'s R is ``fun``'s).
    x : ndarray (F, P)
        Start of each problem.
    w : ndarray (F, N)
        Weight of every point in every problem.
    lower, upper, scale : ndarray (P,)

    Returns
    -------
    X (F, P), R (F, N) residuals at X (every point, weighted or not), evaluations (F,), converged (F,)
    """
    x = np.array(x, dtype=float)
    F, P = x.shape
    w = np.asarray(w, dtype=float)
    rows = np.arange(F)
    r, J = jac(x, rows)
    r, J = np.array(r, dtype=float), np.array(J, dtype=float)
    cost = np.sum(w * r * r, axis=1)
    lam, nu = np.full(F, 1e-3), np.full(F, 2.0)
    nfev = np.ones(F, dtype=int)
    done = np.zeros(F, dtype=bool)
    converged = np.zeros(F, dtype=bool)
    span = 1e-12 * scale
    lo, hi = lower + span, upper - span  # at a bound within these
    left_out = w == 0
    eye = np.eye(P, dtype=bool)
    # scale and weights spread to J's shape: the products below as same-shape ones (no short broadcast loops)
    scale_all = np.broadcast_to(scale, J.shape).copy()
    w_all = np.broadcast_to(w[:, :, None], J.shape).copy()
    while True:
        act = np.flatnonzero(~done & (nfev < max_nfev))
        if not act.size:
            break
        every = act.size == F  # all problems still running: their arrays as they are, no copies
        Ja, ra, wa, xa = (J, r, w, x) if every else (J[act], r[act], w[act], x[act])
        Js = Ja * scale_all[:act.size]
        Jw = Js * (w_all if every else w_all[act])
        JwT = Jw.transpose(0, 2, 1)
        g = (JwT @ ra[:, :, None])[:, :, 0]
        A = JwT @ Js
        held = ((xa <= lo) & (g > 0)) | ((xa >= hi) & (g < 0))
        d = np.diagonal(A, axis1=1, axis2=2).copy()
        d[d <= 0] = 1.0
        M = A + ((lam if every else lam[act])[:, None] * d)[:, None, :] * eye
        gf = g
        if held.any():
            # a held parameter: its row and column out of the system, a unit pivot in their place (h = 0 there)
            M = np.where(held[:, :, None] | held[:, None, :], 0.0, M) + held[:, None, :] * eye
            gf = np.where(held, 0.0, g)
        try:
            h = -np.linalg.solve(M, gf[:, :, None])[:, :, 0]
        except np.linalg.LinAlgError:
            h = -np.stack([np.linalg.lstsq(M[i], gf[i], rcond=None)[0] for i in range(len(act))])
        x_new = np.minimum(np.maximum(xa + h * scale, lower), upper)  # clipped into the box
        h = (x_new - xa) / scale
        predicted = -(2.0 * np.sum(h * g, axis=1) + np.sum(h * (A @ h[:, :, None])[:, :, 0], axis=1))
        if fun is None:
            r_new, J_new = jac(x_new, act)
            r_new = np.asarray(r_new, dtype=float)
        else:
            r_new = np.asarray(fun(x_new, act), dtype=float)
        nfev[act] += 1
        if np.isfinite(r_new).all():
            cost_new = np.sum(wa * r_new * r_new, axis=1)
        else:  # left-out points count for nothing, finite or not
            out = left_out if every else left_out[act]
            fin = np.all(np.isfinite(r_new) | out, axis=1)
            rw = np.where(out, 0.0, r_new)
            cost_new = np.where(fin, np.sum(wa * rw * rw, axis=1), np.inf)
        better = cost_new < cost[act]
        # accepted steps (vectorised over the problems; the same rules as lm_normal)
        ia = act[better]
        upd = ia[:0]
        if ia.size:
            old_cost, new_cost, pred = cost[ia], cost_new[better], predicted[better]
            rel = (old_cost - new_cost) / np.maximum(old_cost, 1e-300)
            rho = np.where(pred > 0, (old_cost - new_cost) / np.where(pred > 0, pred, 1.0), 0.0)
            dx = np.max(np.abs(h[better]), axis=1)
            x[ia], cost[ia], r[ia] = x_new[better], new_cost, r_new[better]
            stop = (rel < tol) | (dx < tol)
            converged[ia[stop]] = done[ia[stop]] = True
            go = ~stop
            upd = ia[go]
            lam[upd] = np.maximum(lam[upd] * np.maximum(1.0 / 3.0, 1.0 - (2.0 * rho[go] - 1.0) ** 3), 1e-12)
            nu[upd] = 2.0
        if ia.size < act.size:  # refused steps: more damping
            ir = act[~better]
            lam[ir] *= nu[ir]
            nu[ir] *= 2.0
            give_up = ir[lam[ir] > 1e10]
            converged[give_up] = done[give_up] = True
        if upd.size and fun is None:
            J[upd] = J_new[np.flatnonzero(better)[go]]
        elif upd.size:
            rr, JJ = jac(x[upd], upd)
            r[upd], J[upd] = rr, JJ
    return x, r, nfev, converged
