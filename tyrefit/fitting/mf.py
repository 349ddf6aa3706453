"""Staged Magic Formula 6.1 (and 5.2) fit of one tyre to one or more rig records.

:func:`fit_mf` fits a complete MF 6.1 parameter set, evaluated by
:func:`tyrefit.models.mf61.forces`, to every record given (a cornering and a
drive/brake record of the same tyre, say), in the stages a tyre laboratory
uses, each on the sweeps that carry its information:

========  =====================================  ====================================
stage     sweeps                                  coefficients (MF 6.1 names)
========  =====================================  ====================================
Fx0       slip-ratio sweeps at slip angle ~ 0     PCX1, PDX*, PEX*, PKX*, PHX*, PVX*, PPX*, LMUV
Fy0       slip-angle sweeps at slip ratio ~ 0     PCY1, PDY*, PEY*, PKY*, PHY*, PVY*, PPY*, LMUV
Mz0       slip-angle sweeps at slip ratio ~ 0     QBZ*, QCZ1, QDZ*, QEZ*, QHZ*, PPZ*
Fx        combined sweeps (kappa at alpha != 0)   RBX*, RCX1, REX*, RHX1
Fy        combined sweeps                         RBY*, RCY1, REY*, RHY*, RVY*
Mz        combined sweeps                         SSZ*
joint     every sweep: Fx, Fy and Mz together      every coefficient of the six stages above
Mx        every sweep with mx                     QSX1-QSX14, PPMX1
My        slip-ratio sweeps with my               QSY1-QSY8
========  =====================================  ====================================

The *joint* polish (:func:`_joint_polish`) is the last step of the force
stages: the stages hold the earlier stages' coefficients, so the noise of the
pure-slip estimates propagates into the later channels (combined Mz through
alpha_eq, 4.E77-4.E78); every fitted Fx/Fy/Mz coefficient then moves at once,
from the staged values, for a few iterations.

Mx is linear in QSX1-QSX4, QSX10, QSX12-QSX14: its start is a variable
projection (:class:`_Projection`, Golub & Pereyra 1973): a coarse grid over
the nonlinear QSX5-QSX9, QSX11 (and PPMX1), the linear ones solved exactly at
every grid point, the best refined in the nonlinear ones only.  From generic
starts the joint problem stopped in a local minimum (5.9 % of peak Mx on
generated data, 2.7 x the generating set's cost), because the near-linear sine
term trades off against QSX2 and QSX3.

A channel with no signal above its noise floor (:func:`channel_signal`) is
not fitted and says so.

The multi-start runs on up to 60 points per sweep (every k-th point) and the
winner is polished on up to 250 per sweep, so a 100 Hz record costs no more
than a 20 Hz one; the statistics use every point.

Each stage holds the coefficients of the stages before it (Mz0 needs the
Fy0 cornering stiffness and shape, combined slip needs the pure-slip
curves), which is why the order is fixed.  Every stage is a small bounded
least-squares problem solved by the one fitting core
(:func:`tyrefit.fitting.core.solve`: SciPy's trust-region reflective
``least_squares``, the cost and the 1/n_s sweep weights as its options) on the
friction coefficient, as the PAC89 fit
(:mod:`tyrefit.fitting.engine`): residual ``r_i = w_s (F_model - F_i) / Fz_i``
with the *measured* load, camber, pressure and speed of every point, and
``w_s = 1/sqrt(n_s)`` per sweep (l2) so densely sampled sweeps do not
dominate; ``cost='l1'`` is Komana et al. Eq. 5 (sum |r| with w_s = 1/n_s),
reached from the l2 solution by a pseudo-Huber continuation.  Moments are
divided by ``Fz R0`` instead of ``Fz``.

Jacobian
--------
Analytic where the channel is a closed form in the stage's coefficients: Mx
(QSX*, PPMX1) and Mz in the aligning coefficients (QBZ*, QCZ1, QDZ*, QEZ*,
QHZ*, PPZ*, SSZ*; MF 6.1), :mod:`tyrefit.fitting.mf_parts`.  Elsewhere forward
differences, one evaluation of the stage's own channel per varied coefficient
(a stage varies 4-27 coefficients; the model is vectorised over all points),
with the step ``sqrt(eps) * max(|theta|, typical size)`` per coefficient.  The
coefficient mapping is built once per stage and only the varied entries
change; the parts of the model a stage does not vary (the pure-slip forces
of the combined stages, Fy0 of the Mz0 stage) are evaluated once, and a
column of the joint polish recomputes only the parts its coefficient enters
(:class:`tyrefit.fitting.mf_eval._Eval`, :class:`tyrefit.fitting.mf_parts.Forces`).
The stages are what makes the fit fast: the plain alternative (all coefficients at once, see
``benchmarks/bench_fit_mf.py``) evaluates every channel of the whole model
for every one of ~100 coefficients per Jacobian.

The jobs around the stages
--------------------------
Each in its own module, all imported here (none imports this one):

* which coefficients the data determine, the others held with the reason
  (:func:`identifiability`): :mod:`tyrefit.fitting.mf_identify`;
* the tyre contract held as penalty rows over the declared range (peak
  friction, curvature, slip stiffness, combined-slip weights, the one-lobe
  SV_yk, the friction ceiling; Pacejka 2012 4.E11-4.E66) and checked after
  the fit: :mod:`tyrefit.fitting.mf_contract`;
* one channel of the model at a stage's points, evaluated by parts:
  :mod:`tyrefit.fitting.mf_eval`;
* start values (Komana et al. Eq. 2-4 per sweep mapped to the coefficients)
  and the multi-start: :mod:`tyrefit.fitting.mf_initial`;
* the data (sweeps, kinds, levels, channel signal): :mod:`tyrefit.fitting.mf_data`;
  the stages' coefficient lists: :mod:`tyrefit.fitting.mf_stages`; the
  result and the tyre file: :mod:`tyrefit.fitting.mf_result`.

This module holds the stage's least-squares problem (:class:`_Problem`: the
bounds, the penalty rows, the Jacobian), the variable projection, the
nominal values, one stage (:func:`_fit_stage`: multi-start, polish, the holds
of coefficients whose standard error exceeds their size), the joint polish
and :func:`fit_mf`.

Effects (``fit --effects ... --model mf61``)
--------------------------------------------
:data:`EFFECT_COEFFICIENTS` maps the diagnose effect ids
(:mod:`tyrefit.effects.catalogue`) to the MF 6.1 lateral coefficients that
carry them; the Fy0 stage then varies the start model
(:data:`START_FY0`: PCY1, PDY1, PKY1, PKY2, PEY1) plus those, so the
diagnose waterfall continues in the exported tyre.  diagnose's ``speed``
(friction and cornering stiffness against travel speed) maps to LMUV, which
carries the friction part (through the slip speed); MF 6.1 has no speed term
on the cornering stiffness.  LMUV, shared with the Fx0 stage, is fitted with
``--effects`` only when a speed effect is asked for, so the start model's
tyre carries no speed law.

References
----------
Pacejka, *Tire and Vehicle Dynamics*, 3rd ed. (2012), sections 4.3.2-4.3.4
and the equations 4.E1-4.E78; Besselink, Schmeitz, Pacejka, "An improved
Magic Formula/Swift tyre model that can handle inflation pressure changes",
VSD 48 (2010) (the PP* terms).  Komana, Els, Becker, *Cost efficient tyre testing...*, Eq. 2-5.
"""

from __future__ import annotations

import math
import time
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field

import numpy as np
import pandas as pd

from ..errors import DataError, FitError, option
from ..models import mf61
from . import mf_parts
from ._blas import single_threaded_blas
from .core import Parameters, covariance, solve
from .problem import SweepProblem
from .mf_result import FitResultMF, _noise_floor
from .mf_stages import (FX0, FXC, FY0, FYC, MX, MX_LINEAR, MY, MZ0, MZC, SPEED_FRICTION, STAGES,  # noqa: F401
                        _ONLY_61, _STAGE, Stage)
from .mf_data import (_CHANNELS, FREE_ROLLING_FX, SIGNAL_RATIO, MFData, _as_frame, _classify,  # noqa: F401
                      _free_rolling, _levels, _span, channel_signal, condition_levels, prepare_mf_data)
from .mf_effects import (_EFFECT_NOTES, _FAMILY_DEFAULT, EFFECT_COEFFICIENTS, START_FY0,  # noqa: F401
                         _in_catalogue, effect_coefficients)
from .mf_identify import COMBINED_SHIFTS, NO_PEAK, SHAPE_DEFAULTS, identifiability  # noqa: F401
from .mf_eval import _Eval, _mf61
from .mf_contract import (MU_CAP, MU_CAP_FACTOR, SVYK_LOBE, MuCeiling, _check_constraints,  # noqa: F401
                          _contract_grid, _contract_terms, _factors, _grid, _mu_ceiling)
from .mf_initial import _TYPICAL, _initial_mz, _initial_pure, _orientation, _starts

__all__ = ["fit_mf", "prepare_mf_data", "identifiability", "MFData", "FitResultMF", "STAGES",
           "EFFECT_COEFFICIENTS", "START_FY0", "effect_coefficients"]

_DEG = math.pi / 180.0
_MODELS = {"mf61": "6.1", "mf52": "5.2"}


# ----------------------------------------------------------------------------- the problem
_BOUNDS = {"PCX1": (0.3, 3.0), "PCY1": (0.3, 3.0), "QCZ1": (0.3, 5.0), "RCX1": (0.05, 3.0), "RCY1": (0.05, 3.0),
           "PEX1": (-30.0, 1.0), "PEY1": (-30.0, 1.0), "REX1": (-30.0, 1.0), "REY1": (-30.0, 1.0),
           "PDX1": (0.02, 6.0), "PDY1": (0.02, 6.0), "PKY4": (0.3, 5.0), "PKY2": (0.05, 50.0),
           "RBX1": (0.0, 500.0), "RBY1": (0.0, 500.0), "QBZ1": (0.0, 200.0), "PKX1": (0.0, 500.0),
           "PEX4": (-1.0, 1.0), "PEY3": (-1.0, 1.0),
           # friction falls with slip speed (4.E7); 2 halves mu at Vs = LONGVL/2, beyond any rubber on a dry road
           "LMUV": (0.0, 2.0),
           # DVy_kappa cos(atan(RVY4 alpha)) (4.E67): the kappa-induced side force fades with the slip angle, to half
           # at 1.73/|RVY4| rad.  Published sets |RVY4| <= ~100 (MFeval's MF 6.1 example -97.05: half at 1.0 deg);
           # sweeps at alpha = 0 and >= 3 deg do not measure how fast it fades in between once the factor there is
           # within the noise, and unbounded it can run off to a step at alpha = 0 (|RVY4| of order 1e10).
           # 200 (half at 0.5 deg) is twice the published ones; at the bound it is a note (_bound_warnings)
           "RVY4": (-200.0, 200.0),
           # Mx (6.1 manual form): the sine term QSX4 sin(QSX8 atan(QSX9 Fy/Fz0)) is linear in Fy for small QSX9,
           # one column with QSX3 Fy/Fz0, and the pair ran away together (QSX3, QSX4 5000 x the measured Mx,
           # cancelling; 3 loads x 2 cambers of MFeval's set): bounded at ~10-20 x the published magnitudes (MFeval's
           # MF 6.1 example QSX3 1.62, QSX4 11.4, QSX8 4.5, |QSX9| 0.033; QSX2 -9.9); at +-50 for QSX4 the fit of
           # that set's own Mx (2 loads, cambers 0/3 deg) ended on the bound at 1.27 x the noise floor
           # The camber terms QSX2 g and QSX10 atan(QSX11 Fz/Fz0) g are left wide: with two cambers the data take
           # a saturated atan (a load-independent camber term, QSX2 178 against QSX10 114, QSX11 892 on the bundled
           # TTC-style pair: 1.82 N*m; bounded at +-200/+-20/+-50: 5.1 N*m), benign since both are linear in g;
           # a term that really runs away is caught by _runaway
           "QSX3": (-50.0, 50.0), "QSX4": (-200.0, 200.0), "QSX8": (-50.0, 50.0),
           "QSX9": (-5.0, 5.0), "QSX5": (-10.0, 10.0), "QSX6": (-50.0, 50.0), "QSX7": (-10.0, 10.0),
           "QSX2": (-1e3, 1e3), "QSX10": (-1e3, 1e3), "QSX11": (-1e4, 1e4),
           "QSX12": (-20.0, 20.0), "QSX13": (-20.0, 20.0), "QSX14": (-20.0, 20.0)}
#: a coefficient at this bound is the data's own answer, said in the notes, not a warning (_bound_warnings)
_QUIET_BOUNDS = {("LMUV", "lower"), ("RVY4", "lower"), ("RVY4", "upper")}


def _typical_step(name: str) -> float:
    if name.startswith(("PK", "RB", "QB")):
        return 1.0
    return 0.1


class _Problem(SweepProblem):
    """One Magic Formula stage on its sweeps: the varied coefficients as theta, the tyre contract as penalty rows."""

    def __init__(self, stage: Stage, pts: pd.DataFrame, base: dict[str, float], vary: Sequence[str],
                 nominal: Mapping[str, float], version: str, cost: str, scale: float, pkysign: float,
                 mu_cap=None, env: Mapping | None = None):
        super().__init__(pts[stage.channel].to_numpy(float), pts["run"].to_numpy(), cost)  # weights 1/n_s
        self.stage = stage
        self.what = f"MF stage {stage.name}"
        self.base = dict(base)
        self.vary = self.theta_names = list(vary)
        self.eval = _Eval(pts, stage, nominal, version)
        self.n_data = self.y.size  # the contract's penalty rows follow the data rows
        self.n_sweeps = len(np.unique(self.data.sweep))
        self.inv = 1.0 / (self.eval.fz * scale)  # force over load, moment over load x radius
        self.mult = np.sqrt(self.weights) if cost == "l2" else self.weights  # the row multiplier the cost implies
        self.w = self.mult * self.inv  # weighted residual = w (y - data) (the variable projection uses it)
        self.lb = np.array([_BOUNDS.get(k, (-np.inf, np.inf))[0] for k in self.vary], float)
        self.ub = np.array([_BOUNDS.get(k, (-np.inf, np.inf))[1] for k in self.vary], float)
        if stage.name == "Fy0" and "PKY1" in self.vary:  # the data's orientation (ISO-W: PKY1 < 0)
            if pkysign < 0:
                self.ub[self.vary.index("PKY1")] = -1e-3
            else:
                self.lb[self.vary.index("PKY1")] = 1e-3
        steps = mu_cap.steps() if mu_cap is not None and stage.name in ("Fx0", "Fy0") else ()
        self.grid = _grid(pts, nominal, env, steps)
        if mu_cap is not None and stage.name in ("Fx0", "Fy0"):
            self.grid = (*self.grid, mu_cap(self.grid[0]))
        self.cgrid = _contract_grid(stage, pts, nominal, version, self.base)
        self.pen_w = 10.0 * math.sqrt(max(1, self.n_sweeps)) * (1.0 if cost == "l2" else 1.0)
        self.nfev = 0

    def params(self, theta) -> dict[str, float]:
        p = dict(self.base)
        p.update(zip(self.vary, (float(t) for t in theta)))
        return p

    def penalties(self, p) -> np.ndarray:
        terms = _factors(p, self.stage.name, *self.grid) + _contract_terms(p, self.stage.name, self.cgrid)
        out = [np.maximum(0.0, m - np.asarray(v, float)) for _, v, m in terms]
        return self.pen_w * np.concatenate(out) if out else np.zeros(0)

    def data_residual(self, p) -> np.ndarray:
        """The data rows of :meth:`mu_residual` at the parameter set ``p``."""
        self.nfev += 1
        y = self.eval(p, changed=self.vary)
        r = self.inv * (y - self.y)
        bad = ~np.isfinite(r)
        if bad.any():
            r = np.where(bad, 1e3 * np.max(self.w) / self.mult, r)
        return r

    def mu_residual(self, theta) -> np.ndarray:
        """Unweighted residual (model - data) over load (x radius for moments), then the penalty rows.

        A non-finite model value is a large residual: 1e3 x the largest row weight once weighted.
        """
        p = self.params(theta)
        out = np.concatenate([self.data_residual(p), self.penalties(p)])
        self._last = (np.array(theta, float), out.copy())  # the solver asks for the Jacobian where it evaluated last
        return out

    def residual(self, theta) -> np.ndarray:
        """Weighted residual as the solver sees it (data rows x the cost's multiplier, penalties as they are)."""
        r = self.mu_residual(theta)
        r[: self.y.size] *= self.mult
        return r

    def jac(self, theta, r0=None):
        """Jacobian of :meth:`mu_residual`: analytic columns where the model has them (:meth:`_Eval.jacobian`),
        forward differences for the others (steps of each coefficient's typical size)."""
        theta = np.asarray(theta, float)
        last = getattr(self, "_last", None)
        if r0 is None and mf_parts.FAST and last is not None and np.array_equal(last[0], theta):
            r0 = last[1].copy()
        if r0 is None:
            r0 = self.mu_residual(theta)
        J = np.empty((r0.size, theta.size))
        eps = math.sqrt(np.finfo(float).eps)
        # analytic columns (Mx, Mz in their own coefficients) for the data rows; the penalty rows (Mz0: E_t and the
        # aligning rule) by forward differences of the penalties alone
        # penalty rows that are all zero (every constraint holds) have a zero derivative: a forward step of
        # sqrt(eps) does not reach a boundary the solution sits away from
        n = self.y.size
        pen0 = r0[n:]
        active = bool(np.any(pen0))
        cols = self.eval.jacobian(self.params(theta), self.vary)
        for j in range(theta.size):
            h = eps * max(abs(theta[j]), _typical_step(self.vary[j]))
            t = theta.copy()
            t[j] = t[j] + h if t[j] + h <= self.ub[j] else t[j] - h
            q = self.params(t)
            if self.vary[j] in cols:  # rows the residual replaced (non-finite model) do not move
                dy = self.inv * cols[self.vary[j]]
                J[:n, j] = np.where(np.isfinite(dy), dy, 0.0)
            else:
                J[:n, j] = (self.data_residual(q) - r0[:n]) / (t[j] - theta[j])
            J[n:, j] = (self.penalties(q) - pen0) / (t[j] - theta[j]) if active else 0.0
        return J

    rows = mu_residual

    def inside(self, theta) -> np.ndarray:
        return _inside(theta, self.lb, self.ub)

    def max_nfev(self, n_free: int) -> int:
        return 100

    def theta(self, p: Mapping[str, float]) -> np.ndarray:
        return _inside(np.array([float(p.get(k, self.base.get(k, 0.0))) for k in self.vary]), self.lb, self.ub)


def _inside(x, lb, ub):
    x = np.asarray(x, float).copy()
    for j in range(x.size):
        a, b = lb[j], ub[j]
        ea = 1e-9 * max(1.0, abs(a)) if np.isfinite(a) else 0.0
        eb = 1e-9 * max(1.0, abs(b)) if np.isfinite(b) else 0.0
        x[j] = min(max(x[j], a + ea), b - eb)
    return x


# ----------------------------------------------------------------- the variable projection
#: coefficients that enter a stage's channel linearly, and a coarse grid of the others for the variable
#: projection start (:class:`_Projection`).  MF 6.1 Mx (tyrefit.models.mf61._mx):
#: Mx/(R0 Fz) = QSX1 - QSX2 g (1 + PPMX1 dpi) + QSX3 Fy/Fz0 + QSX4 cos(QSX5 atan((QSX6 Fz/Fz0)^2))
#: sin(QSX7 g + QSX8 atan(QSX9 Fy/Fz0)) + QSX10 atan(QSX11 Fz/Fz0) g + (Fy/Fz)(QSX13 + QSX14 |g|) - QSX12 g|g|.
#: The grid uses the model's symmetries: cos is even (QSX5, QSX6 > 0), flipping QSX4, QSX7, QSX8 together
#: leaves the sine term unchanged (QSX8 > 0), QSX10 absorbs the sign of QSX11 (QSX11 > 0).  Over a rig's
#: range (camber <= 0.1 rad, |Fy/Fz0| <= 3) the grid spans sine arguments from nearly linear to past pi/2.
_LINEAR = {"Mx": ("QSX1", "QSX2", "QSX3", "QSX4", "QSX10", "QSX12", "QSX13", "QSX14")}
_GRID = {"Mx": {"QSX5": (0.2, 0.6, 1.2), "QSX6": (0.5, 1.0, 2.0), "QSX7": (-2.0, -0.5, 0.5, 2.0),
                "QSX8": (1.0, 4.0), "QSX9": (-0.3, -0.03, 0.03, 0.3), "QSX11": (0.3, 1.0, 3.0)}}
#: points per sweep for the grid of the variable projection
_GRID_POINTS = 15
#: evaluations per nonlinear coefficient of each refinement of the projection's best grid points; the stage's
#: polish follows on more points (60 had 7400 projections, 9 s of the FSAE pair's 11 s Mx stage)
_PROJECTION_NFEV = 20


class _Projection:
    """Variable projection (Golub & Pereyra 1973) of a stage whose channel is linear in some coefficients.

    For fixed nonlinear coefficients q the weighted residual ``w (y(q, b) - y_data)`` is affine in the
    linear ones b, so b is a linear least-squares solution and the cost a function of q alone.  The
    columns are taken from the model itself (the channel at b_k = 1 minus the channel at b = 0), so
    nothing of the model is transcribed; columns that do not move with q are evaluated once.  A grid over
    q picks the starts; the best few are refined by :func:`least_squares` in q only.  This removes the
    local minima that the joint problem has where a linear and a nonlinear term trade off (Mx: QSX2/QSX3
    against the near-linear sine term QSX4 sin(QSX7 g + QSX8 atan(QSX9 Fy/Fz0))).
    """

    def __init__(self, prob: "_Problem", linear: Sequence[str], nonlinear: Sequence[str], base: Mapping[str, float]):
        self.prob, self.linear, self.nonlinear = prob, list(linear), list(nonlinear)
        self.base = dict(base)
        self.w = prob.w
        self.nfev = 0
        q0 = {k: float(self.base.get(k, 0.0)) for k in self.nonlinear}
        q1 = {k: 1.1 * v + 0.1 for k, v in q0.items()}
        self.y0_fixed, self.fixed = None, {}
        q2 = {k: -0.7 * v - 0.3 for k, v in q0.items()}
        (y0a, ca), (y0b, cb), (y0c, cc) = self._columns(q0), self._columns(q1), self._columns(q2)

        def same(a, b, c):
            return np.allclose(a, b, rtol=1e-12, atol=1e-15) and np.allclose(a, c, rtol=1e-12, atol=1e-15)

        if same(y0a, y0b, y0c):
            self.y0_fixed = y0a
        # a column y(b_k = 1) - y(b = 0) that does not move with q is evaluated once
        self.fixed = {k: ca[k] for k in self.linear if same(ca[k], cb[k], cc[k])}

    def _columns(self, q: Mapping[str, float]) -> tuple[np.ndarray, dict[str, np.ndarray]]:
        p = dict(self.base, **q, **{k: 0.0 for k in self.linear})
        ev = self.prob.eval
        y0 = self.y0_fixed if self.y0_fixed is not None else ev(p)
        cols = {k: self.fixed[k] if k in self.fixed else ev(dict(p, **{k: 1.0})) - y0 for k in self.linear}
        self.nfev += 1 + len(self.linear) - len(self.fixed)
        return y0, cols

    def solve_linear(self, q: Mapping[str, float]) -> tuple[np.ndarray, dict[str, float]]:
        """(weighted residual, linear coefficients) at nonlinear coefficients ``q``."""
        y0, cols = self._columns(q)
        X = np.column_stack([cols[k] for k in self.linear]) * self.w[:, None]
        rhs = self.w * (self.prob.y - y0)
        ok = np.all(np.isfinite(X), axis=1) & np.isfinite(rhs)
        if ok.sum() <= X.shape[1]:
            return np.full(rhs.size, 1e3 * np.max(self.w)), {k: 0.0 for k in self.linear}
        beta, *_ = np.linalg.lstsq(X[ok], rhs[ok], rcond=None)
        r = np.where(ok, X @ beta - rhs, 1e3 * np.max(self.w))
        return r, dict(zip(self.linear, beta.tolist()))

    def best(self, grid: Mapping[str, Sequence[float]], n_refine: int = 3) -> dict[str, float]:
        """Grid over the nonlinear coefficients, the ``n_refine`` best refined; the winner with its b."""
        import itertools

        names = [k for k in self.nonlinear if k in grid]
        rows = []
        for vals in itertools.product(*(grid[k] for k in names)):
            q = {k: float(self.base.get(k, 0.0)) for k in self.nonlinear}
            q.update(zip(names, vals))
            r, _ = self.solve_linear(q)
            rows.append((float(r @ r), q))
        rows.sort(key=lambda t: t[0])
        picked: list = []
        for c, q in rows:  # distinct costs only (the symmetric twins of a point cost the same)
            if all(abs(c - c2) > 1e-9 * max(c, 1e-30) for c2, _ in picked):
                picked.append((c, q))
            if len(picked) >= n_refine:
                break
        if not self.nonlinear:
            return dict(self.solve_linear({})[1])
        best = None
        for _, q in picked:
            th0 = np.array([q[k] for k in self.nonlinear])
            pars = Parameters()
            for k, v in zip(self.nonlinear, th0):
                pars.add(k, float(v))
            sol = solve(lambda th: self.solve_linear(dict(zip(self.nonlinear, th)))[0], pars, x_scale="jac",
                        max_nfev=_PROJECTION_NFEV * len(th0), ftol=1e-10, xtol=1e-10, gtol=1e-8, stderr=False,
                        what="variable projection")
            if best is None or sol.cost < best[0]:
                best = (sol.cost, sol.x)
        q = dict(zip(self.nonlinear, best[1].tolist()))
        _, beta = self.solve_linear(q)
        return {**q, **beta}


# -------------------------------------------------------------------------- nominal values
def _nominal(data: MFData, tyre_info: Mapping | None, base: Mapping[str, float]) -> dict[str, float]:
    sw = data.sweeps
    info = dict(tyre_info or {})
    out = {}
    lv = condition_levels(sw)
    if info.get("fnomin"):
        out["FNOMIN"] = float(info["fnomin"])
    else:  # the middle load level, rounded: the data's own nominal load
        out["FNOMIN"] = float(np.round(np.median(lv["fz"]), -1)) if lv["fz"] else float(base.get("FNOMIN", 4000.0))
    pr = lv["pressure"]
    out["NOMPRES"] = float(info.get("nompres") or (np.round(np.median(pr), -2) if pr else base.get("NOMPRES", 2e5)))
    out["INFLPRES"] = out["NOMPRES"]
    sp = lv["speed"]
    if sp:
        out["LONGVL"] = float(np.round(np.median(sp), 2))
    if info.get("unloaded_radius"):
        out["UNLOADED_RADIUS"] = float(info["unloaded_radius"])
    if info.get("width"):
        out["WIDTH"] = float(info["width"])
    return out


# ----------------------------------------------------------------------------- one stage
@dataclass
class StageFit:
    """Result of one stage (internal; gathered into :class:`FitResultMF`)."""

    name: str
    channel: str
    varied: list[str]
    held: dict[str, str]
    initial: dict[str, float]
    facts: dict
    objective: float
    nfev: int
    seconds: float
    starts: list[dict]
    estimates: pd.DataFrame
    stderr: dict[str, float]
    constraints: list[dict]
    n_points: int
    n_sweeps: int


def _fit_stage(stage: Stage, data: MFData, p: dict[str, float], *, vary_only: Sequence[str] | None,
               nominal: Mapping[str, float], version: str, cost: str, notes: list[str],
               multistart: bool = True, hold: Sequence[str] = (), given: Sequence[str] = ()) -> StageFit | None:
    t0 = time.perf_counter()
    pts = data.subset(stage.sweeps, stage.channel)
    runs = pts["run"].unique()
    sw = data.sweeps[data.sweeps["run"].isin(runs)]
    if len(pts) < 10 or not len(sw):
        return None
    if stage.name == "Mz*" and not (sw["kind"] == "combined").any():
        return None
    est = pd.DataFrame()
    any_peak = True
    init: dict[str, float] = {}
    if stage.name in ("Fx0", "Fy0"):
        why0, _ = identifiability(stage, pts, sw, version=version)
        init, est, any_peak = _initial_pure(stage, pts, nominal, why0)
    elif stage.name == "Mz0":
        if "fy" in pts and np.isfinite(pts["fy"].to_numpy(float)).sum() > 10:
            init = _initial_mz(pts, nominal)
    elif stage.name in ("Fx", "Fy"):
        init = {k: _TYPICAL[k] for k in ("RBX1", "RBX2", "RCX1", "RBY1", "RBY2", "RCY1") if k in stage.names}
    cap = None
    if stage.name in ("Fx0", "Fy0"):
        cap = _mu_ceiling(pts, est, stage.channel)
    if stage.name == "Mz*":  # the joint polish varies what the Mz0 and Mz stages found identifiable
        why, facts = {}, {"points": int(len(pts)), "sweeps": int(len(sw))}
    else:
        peak_runs = est.loc[est["has_peak"].astype(bool), "run"].tolist() \
            if stage.name in ("Fx0", "Fy0") and len(est) and "has_peak" in est else None
        why, facts = identifiability(stage, pts, sw, any_peak=any_peak, version=version, peak_runs=peak_runs)
    if cap is not None:
        facts["mu_ceiling"] = cap
    held_to = {"mu_cap": cap, "env": data.envelope()}  # the constraints' ceiling and the grid they hold over
    names = [k for k in stage.names if k in _known_names()]
    want = [k for k in names if k not in why]
    if vary_only is not None:
        asked_held = [k for k in vary_only if k in names and k in why]
        if asked_held:
            notes.append(f"{stage.name}: {', '.join(asked_held)} asked for but not identifiable from these data; "
                         "held")
        want = [k for k in want if k in set(vary_only)]
    want = [k for k in want if k not in hold]  # held by the caller without a note (LMUV outside --effects speed)
    base = dict(p)
    for k in names:
        if k in given:  # the caller's start or held value (fit_mf's initial, fixed), not the stage's estimate
            continue
        if k in init and (k in want or k in stage.core):
            base[k] = init[k]
        if why.get(k, "").startswith(NO_PEAK):
            base[k] = SHAPE_DEFAULTS.get(k, 0.0)
    if not want:
        return StageFit(stage.name, stage.channel, [], why, init, facts, float("nan"), 0, 0.0, [], est, {}, [],
                        len(pts), len(sw))
    scale = nominal.get("UNLOADED_RADIUS", 0.3) if stage.moment else 1.0
    pkysign = base.get("PKY1", -1.0)
    core = [k for k in stage.core if k in want]
    starts = _starts(stage, base) if multistart and stage.name != "Mz*" else [base]
    secondary = stage.name in ("Mx", "My")  # the moments a vehicle model barely uses: a cheaper search
    lin = [k for k in _LINEAR.get(stage.name, ()) if k in want]
    if lin and multistart:
        # variable projection: a grid over the nonlinear coefficients, the linear ones solved exactly
        pg = _Problem(stage, _thin(pts, _GRID_POINTS), base, want, nominal, version, "l2", scale, pkysign, **held_to)
        proj = _Projection(pg, lin, [k for k in want if k not in lin], base)
        starts = [dict(base, **proj.best(_GRID[stage.name]))]
        core = []
        nfev_proj = proj.nfev
    else:
        nfev_proj = 0
    if set(given) & set(want) and starts[0] != base:  # the caller's start values are a start of their own
        starts = [base] + starts
    log, best = [], None
    nfev = nfev_proj
    # the multi-start runs on at most _START_POINTS points per sweep; the winner is polished on all points
    pts_s = _thin(pts, _START_POINTS // 2 if secondary else _START_POINTS)
    for si, st in enumerate(starts):
        c = {k: (v if k in want else base.get(k, v)) for k, v in st.items()}
        if core and len(core) < len(want):
            p1 = _Problem(stage, pts_s, c, core, nominal, version, "l2", scale, pkysign, **held_to)
            c.update(p1.params(p1.solve(p1.theta(c), tol=1e-5)[0]))
            nfev += p1.nfev
        p2 = _Problem(stage, pts_s, c, want, nominal, version, "l2", scale, pkysign, **held_to)
        th = p2.solve(p2.theta(c), tol=1e-6)[0]
        obj = p2.objective(th)
        nfev += p2.nfev
        log.append({"start": si, "objective_l2": obj})
        if best is None or obj < best[0]:
            best = (obj, p2, th)
    _, prob_s, th = best
    pts_p = _thin(pts, _POLISH_POINTS)
    prob = _Problem(stage, pts_p, prob_s.params(th), want, nominal, version, "l2", scale, pkysign, **held_to) \
        if len(pts_s) < len(pts_p) else prob_s
    n_before = prob.nfev
    th = prob.solve(th, tol=1e-10, max_nfev=_SECONDARY_NFEV if secondary else _POLISH_NFEV)[0]
    nfev += prob.nfev - n_before
    if cost == "l1":  # Komana et al. Eq. 5: the core's pseudo-Huber continuation from the l2 solution
        pl1 = _Problem(stage, pts_p, prob.params(th), want, nominal, version, "l1", scale, pkysign, **held_to)
        th1 = pl1.solve(pl1.theta(prob.params(th)))[0]
        nfev += pl1.nfev
        prob, th = pl1, th1
    stderr = _stderr(prob, th, len(pts_p))
    # a coefficient the data do not determine (standard error >= its size) is held at its neutral value and the
    # rest refitted, one at a time, the worst first, as long as the hold costs no more than the noise explains
    # (a likelihood-ratio test at 5 %: the weighted SSE rises by < 3.84 s^2).  Two collinear terms (QSX3 against
    # the near-linear QSX4 sine of Fy) both have standard errors above their size while together they carry the
    # channel: holding the sine term of MFeval's Mx left 12 x the noise floor; that hold is refused and said
    kept: dict[str, str] = {}
    for _ in range(_MAX_HOLDS):
        weak = {k: v for k, v in _not_identified(prob, th, stderr).items() if k not in kept} \
            if stage.name != "Mz*" else {}
        if not weak:
            break
        k = max(weak, key=lambda n: weak[n][0] / max(abs(weak[n][1]), 1e-300))
        se, v, n0 = weak[k]
        q = prob.params(th)
        q[k] = n0
        rest = [n for n in want if n != k]
        trial = _Problem(stage, pts_p, q, rest, nominal, version, prob.cost, scale, pkysign, **held_to)
        th1 = trial.solve(trial.theta(q), tol=1e-8, max_nfev=_HOLD_NFEV)[0] if rest else np.zeros(0)
        nfev += trial.nfev
        sse0, s2 = _weighted_sse(prob, th)
        sse1, _ = _weighted_sse(trial, th1)
        if not (sse1 - sse0 < _LR_CHI2 * s2):
            kept[k] = f"{k} = {v:.4g} +- {se:.3g}"
            continue
        why[k] = f"not identified: standard error {se:.3g} >= |value| {abs(v):.3g}; held at its neutral value {n0:g}"
        want, prob, th = rest, trial, th1
        stderr = _stderr(prob, th, len(pts_p)) if want else {}
        if not want:
            break
    if kept:
        notes.append(f"{stage.name}: kept though each one's standard error exceeds its size (holding any raises the "
                     f"error beyond the noise, a likelihood-ratio test at 5 %: they are determined together): "
                     + ", ".join(kept.values()))
    fitted = prob.params(th)
    p.update({k: fitted[k] for k in names if k in fitted})
    facts["r2"] = _r2(stage, pts, fitted, nominal, version)
    if secondary and want:
        facts["runaway"] = _runaway(prob, th)
    cons = _check_constraints(stage, fitted, prob.grid, prob.cgrid)
    for c in cons:
        if not c["holds"]:
            notes.append(f"{stage.name}: constraint {c['constraint']} broken on the grid of the fitted range "
                         f"(worst {c['worst']:.3g})")
    return StageFit(stage.name, stage.channel, want, why, init, facts, prob.objective(th), nfev,
                    time.perf_counter() - t0, log, est, stderr, cons, len(pts), len(sw))


def _r2(stage: Stage, pts: pd.DataFrame, p: Mapping[str, float], nominal, version: str) -> float:
    """R^2 of the stage's channel on every one of its points (1 - SS_res / SS_tot, unweighted, N or N*m)."""
    y = pts[stage.channel].to_numpy(float)
    res = _Eval(pts, stage, nominal, version)(p) - y
    ok = np.isfinite(res) & np.isfinite(y)
    sst = float(np.sum((y[ok] - y[ok].mean()) ** 2))
    return 1.0 - float(np.sum(res[ok] ** 2)) / sst if sst > 0 and ok.sum() > 2 else float("nan")


#: a term whose contribution reaches this many times the channel's largest measured value cancels another.
#: Published sets do carry terms that nearly cancel: MFeval's MF 6.1 example refitted to its own Mx reaches
#: 22 x (QSX4's sine of Fy against the linear QSX3 Fy); the runaway seen on a real record was ~1e8 x
RUNAWAY_FACTOR = 1000.0


def _runaway(prob: "_Problem", th) -> dict[str, float]:
    """Coefficients whose term is larger than :data:`RUNAWAY_FACTOR` x the largest measured value.

    The contribution of coefficient k is |dy/dtheta_k theta_k| (its term itself where y is linear in it,
    to first order elsewhere); two such terms of opposite sign cancel on the data and leave the model
    anywhere in between (QSX4 = -2.2e9 against QSX2 = 3.6e5 on a real cornering record).  Returns
    name -> contribution / largest |y|.
    """
    r0 = prob.mu_residual(th)
    J = prob.jac(th, r0)[: prob.y.size]
    peak = float(np.nanmax(np.abs(prob.y * prob.inv))) if prob.y.size else 0.0
    if not peak > 0:
        return {}
    size = np.nanmax(np.abs(J * np.asarray(th, float)[None, :]), axis=0) / peak
    return {k: float(v) for k, v in zip(prob.vary, size) if v > RUNAWAY_FACTOR}


def _drop_unfit(data: "MFData", p: dict[str, float], fits: dict, notes: list[str]) -> None:
    """Declare a moment channel not fitted when its fit is worse than a constant or its terms run away.

    Mx and My (and Mz) stages whose R^2 on their points is <= 0, or whose terms cancel
    (:func:`_runaway`), are reset to the neutral coefficients and their stage to nothing varied: the file
    declares the channel not fitted (``TYREFIT_NOT_FITTED``, header) instead of carrying a curve that is
    worse than no curve.  Force channels are never dropped here: Fx and Fy are what a simulator runs on.
    """
    neutral = _mf61().neutral()
    for ch, names in (("mx", ("Mx",)), ("my", ("My",)), ("mz", ("Mz0", "Mz", "Mz*"))):
        st = [n for n in names if n in fits and fits[n].varied]
        if not st:
            continue
        last = fits[st[-1]]
        r2 = last.facts.get("r2", float("nan"))
        run = {k: v for n in st for k, v in fits[n].facts.get("runaway", {}).items()}
        if not (r2 <= 0 or run):
            continue
        why = (f"worse than a constant (R2 {r2:.2f} on its sweeps)" if r2 <= 0 else
               "coefficients that run away to cancel each other (" +
               ", ".join(f"{k} term {v:.0f} x the largest measured |{ch}|" for k, v in sorted(run.items())) + ")")
        dropped = set()
        for n in names:
            if n in fits:
                for k in fits[n].varied:
                    p[k] = float(neutral.get(k, 0.0))
                    fits[n].held[k] = f"{ch.upper()} not fitted: {why}; held at its neutral value"
                dropped.update(fits[n].varied)
                fits[n].varied = []
        if "joint" in fits:  # the polish moved them too; they are neutral now
            fits["joint"].varied = [k for k in fits["joint"].varied if k not in dropped]
        notes.append(f"{ch.upper()} not written as fitted: {why}; the file declares it not fitted "
                     f"(neutral coefficients)")


#: at most this many coefficients of one stage are tried for a hold for their standard error (one per refit)
_MAX_HOLDS = 8
#: evaluations of the refit that tries a hold (it starts at the solution, one coefficient moved)
_HOLD_NFEV = 12
#: chi-square (1 dof) at 5 %: a hold whose weighted SSE rises by more than this many s^2 is refused
_LR_CHI2 = 3.84


def _weighted_sse(prob: "_Problem", th) -> tuple[float, float]:
    """(sum of w r^2 over the data rows, its per-degree-of-freedom variance s^2) of ``prob`` at ``th``."""
    r = prob.mu_residual(th)[: prob.y.size]
    sse = float(np.sum(prob.weights * np.where(np.isfinite(r), r, 0.0) ** 2))
    return sse, sse / max(1, prob.y.size - len(prob.vary))


def _not_identified(prob: "_Problem", th, stderr: Mapping[str, float]) -> dict[str, tuple[float, float, float]]:
    """Varied coefficients whose standard error is at least their own size: name -> (stderr, value, neutral).

    Such a value is the noise's, not the tyre's (PEY5 = 2670 +- 2797 on a real record): it is held at the
    neutral value of :func:`tyrefit.models.mf61.neutral` (PKY1 with the data's orientation).
    """
    neutral = _mf61().neutral()
    out = {}
    se_all = np.array([stderr.get(k, float("nan")) for k in prob.vary], float)
    if not np.isfinite(se_all).any():  # no covariance at all (singular at the solution): nothing to say
        return out
    for k, v, lo, hi in zip(prob.vary, th, prob.lb, prob.ub):
        if any(np.isfinite(b) and abs(v - b) <= 1e-6 * max(1.0, abs(b)) for b in (lo, hi)):
            continue  # held by its bound: a constrained fit, said by _bound_warnings, its error means nothing
        se = stderr.get(k, float("nan"))
        se = se if np.isfinite(se) else math.inf  # a direction the data do not see at all
        if se > 0 and se >= abs(v):
            n0 = float(neutral.get(k, 0.0))
            if k == "PKY1":
                n0 = math.copysign(abs(n0), v)
            out[k] = (float(se), float(v), n0)
    return out


def _bounds_of(name: str, p: Mapping[str, float]) -> tuple[float, float]:
    """The bounds a stage and the joint polish give coefficient ``name`` (PKY1: the data's orientation)."""
    lo, hi = _BOUNDS.get(name, (-np.inf, np.inf))
    if name == "PKY1":
        lo, hi = (lo, -1e-3) if p.get("PKY1", -1.0) < 0 else (1e-3, hi)
    return lo, hi


def _bound_warnings(p: Mapping[str, float], fits: Mapping[str, StageFit], notes: list[str] | None = None) -> list[str]:
    """Fitted coefficients that end at a bound in the final set (after every stage and the joint polish).

    A coefficient held there by its bound is a constrained fit: its standard error means nothing and the
    shape it sets may be wrong (as :func:`tyrefit.fitting.result._fit_warnings` says for PAC89).  LMUV at 0
    (its lower bound) is the data's own answer when friction does not fall with slip speed, RVY4 at +-200
    when the kappa-induced side force is within the noise at the combined sweeps' slip angles
    (:data:`_QUIET_BOUNDS`): said in ``notes`` (when given) in those words, not as a warning.
    """
    last: dict[str, str] = {}
    for name, f in fits.items():  # stage order: the last stage that varied a coefficient set its value
        for k in f.varied:
            last[k] = name
    out = []
    for k, stage in last.items():
        lo, hi = _bounds_of(k, p)
        v = float(p[k])
        for b, side in ((lo, "lower"), (hi, "upper")):
            if np.isfinite(b) and abs(v - b) <= 1e-6 * max(1.0, abs(b)):
                if (k, side) in _QUIET_BOUNDS and notes is not None:
                    notes.append(_bound_note(k, b, side, stage, fits))
                    continue
                out.append(f"{k} = {v:.4g} is at its {side} bound {b:g} (stage {stage}): the fit is constrained "
                           "there, its standard error means nothing and the shape it sets may be wrong")
    return out


def _bound_note(k: str, b: float, side: str, stage: str, fits: Mapping[str, StageFit]) -> str:
    """The note for a coefficient of :data:`_QUIET_BOUNDS` at its bound ``b``."""
    if k == "RVY4":
        lv = fits["Fy"].facts.get("levels", {}) if "Fy" in fits else {}
        nz = sorted({round(abs(a) / _DEG, 1) for a in lv.get("slip_angle", []) if abs(a) >= 0.5 * _DEG})
        f = 1.0 / math.sqrt(1.0 + (b * nz[0] * _DEG) ** 2) if nz else float("nan")
        return (f"RVY4 = {b:g} (stage {stage}), its {side} bound: the kappa-induced side force DVy_kappa "
                f"cos(atan(RVY4 alpha)) (4.E67) is within the noise at the combined sweeps' slip angles "
                f"({', '.join(f'{a:g}' for a in nz) or 'none'} deg; cos(atan(RVY4 alpha)) = {f:.2g} at "
                f"{nz[0] if nz else 0:g} deg here): how fast it fades between alpha = 0 and there is not measured "
                f"(published sets |RVY4| <= ~100)")
    return (f"{k} = {b:g} (stage {stage}), its lower bound: these data show no fall of friction with slip speed "
            "between their speeds (a rise, which MF 6.1 cannot carry, would end here too)")


#: stages whose coefficients the joint polish varies, and the channels it fits
_JOINT_STAGES = ("Fx0", "Fy0", "Mz0", "Fx", "Fy", "Mz")
_JOINT_CHANNELS = (("fx", ("longitudinal", "combined")), ("fy", ("lateral", "combined", "longitudinal")),
                   ("mz", ("lateral", "longitudinal", "combined")))
_JOINT_NFEV = 8
#: the parts of the model (mf_parts.group) whose coefficients enter each stage's constraint factors (_factors)
_PENALTY_GROUPS = {"Fx0": ("fx0", "basic"), "Fy0": ("fy0", "basic"), "Fx": ("gxa", "basic"), "Fy": ("gyk", "basic"),
                   # E_t (QEZ) and the aligning rule (Mz0 through the trail and Fy0, 4.E31-4.E47)
                   "Mz0": ("mz0", "fy0", "basic")}
#: points of the joint polish in all (every k-th point of each sweep; between 60 and 250 per sweep)
_JOINT_POINTS = 20000


def _joint_polish(data: MFData, p: dict[str, float], fits: Mapping[str, StageFit], *, nominal: Mapping[str, float],
                  version: str, notes: list[str]) -> StageFit | None:
    """A last least-squares polish of every force and aligning coefficient the stages fitted, on all sweeps.

    The stages fit each channel on its own sweeps with the earlier stages held, so the pure-slip
    estimates' noise propagates: combined Mz goes through alpha_eq = sqrt(alpha^2 + (K_x/K_y)^2 kappa^2)
    (Pacejka 2012, 4.E77-4.E78), which is steep near kappa = 0, and a 1-2 % error of K_x/K_y there is
    ~1 % of peak Mz.  The combined and Mz sweeps also carry information on the pure-slip coefficients;
    this polish lets every fitted Fx/Fy/Mz coefficient move at once (from the staged values, so no
    multi-start), on the residuals of Fx (drive/brake and combined), Fy (every sweep: as the Fy and Fy0 stages) and Mz
    (all), each weighted as in its stage, with the constraint penalties of the Fx0, Fy0, Mz0, Fx and Fy
    stages.  It lowers the combined-Mz error that the staged K_x/K_y leaves (above), and the Fx and Fy
    errors with it.
    """
    t0 = time.perf_counter()
    vary = list(dict.fromkeys(k for st in _JOINT_STAGES if st in fits for k in fits[st].varied))
    if len(vary) < 2 or not any(st in fits and fits[st].varied for st in ("Mz0", "Fx", "Fy", "Mz")):
        return None
    mf = _mf61()
    # as many points per sweep as the stage polish where the record is small, fewer on a long record
    n_sw = max(1, int(data.df["run"].nunique()))
    d = _thin(data.df, int(np.clip(_JOINT_POINTS / n_sw, _START_POINTS, _POLISH_POINTS)))
    kind = d["kind"].to_numpy()
    kap = np.where(kind == "lateral", 0.0, d["slip_ratio"].to_numpy(float))
    alp = np.where(kind == "longitudinal", 0.0, d["slip_angle"].to_numpy(float))
    pr, sp = d["pressure"].to_numpy(float), d["speed"].to_numpy(float)
    pr = np.where(np.isfinite(pr), pr, nominal.get("NOMPRES", np.nan)) if np.isfinite(pr).any() else None
    sp = np.where(np.isfinite(sp), sp, nominal.get("LONGVL", np.nan)) if np.isfinite(sp).any() else None
    fz, gam = d["fz"].to_numpy(float), d["camber"].to_numpy(float)
    r0 = nominal.get("UNLOADED_RADIUS", 0.3)
    blocks = []
    for c, kinds in _JOINT_CHANNELS:
        if c not in d or not any(st in fits and fits[st].channel == c and fits[st].varied for st in _JOINT_STAGES):
            continue
        y = d[c].to_numpy(float)
        m = np.isin(kind, kinds) & np.isfinite(y)
        if m.sum() < 10:
            continue
        runs = d["run"].to_numpy()[m]
        _, inv, cnt = np.unique(runs, return_inverse=True, return_counts=True)
        w = 1.0 / np.sqrt(cnt[inv]) / (fz[m] * (r0 if c == "mz" else 1.0))
        blocks.append((c, m, y[m], w))
    pens = [_Problem(_STAGE[st], data.subset(_STAGE[st].sweeps, _STAGE[st].channel), p, [], nominal, version, "l2",
                     1.0, p.get("PKY1", -1.0), mu_cap=fits[st].facts.get("mu_ceiling"), env=data.envelope())
            for st in ("Fx0", "Fy0", "Mz0", "Fx", "Fy") if st in fits and fits[st].varied]
    lb = np.array([_bounds_of(k, p)[0] for k in vary], float)
    ub = np.array([_bounds_of(k, p)[1] for k in vary], float)
    kw = {"version": version}
    nfev = [0]

    fast = mf_parts.FAST and mf is mf61
    if fast:  # Fx, Fy, Mz by parts: the mapping built once, a Jacobian column recomputes what its coefficient moves
        model = mf_parts.Forces(version, fz, kap, alp, gam, pr, sp)
        model.bind(p)
        groups = [mf_parts.group(k, model.v52) for k in vary]
    last: list = [None, None, None]  # theta, residual, state of the last evaluation

    def residual(th):
        q = dict(p, **dict(zip(vary, th.tolist())))
        nfev[0] += 1
        if fast:
            c, b = model.coefficients(zip(vary, th.tolist()))
            st = model.state(c, b)
            out = {ch: model.out(st, ch) for ch, *_ in blocks}
        else:
            out = mf.forces(q, fz, slip_ratio=kap, slip_angle=alp, camber=gam, pressure=pr, speed=sp, **kw)
        parts = [w * (np.asarray(out[c], float)[m] - y) for c, m, y, w in blocks]
        parts += [pb.penalties(q) for pb in pens]
        r = np.concatenate(parts)
        r = np.where(np.isfinite(r), r, 1e3)
        if fast:
            last[:] = [np.array(th, float), r.copy(), (c, b, st)]
        return r

    def jac_fast(th):
        if last[0] is None or not np.array_equal(last[0], th):
            residual(th)
        rr, (c, b, st) = last[1], last[2]
        J = np.zeros((rr.size, th.size))
        eps = math.sqrt(np.finfo(float).eps)
        pen0 = [pb.penalties(dict(p, **dict(zip(vary, th.tolist())))) for pb in pens]
        nfev[0] += th.size  # one (partial) evaluation per column, as the forward differences counted
        # the aligning coefficients (trail, residual torque, s) move Mz alone: analytic columns (mf_parts.mz_jacobian)
        mz_cols = mf_parts.mz_jacobian(c, b, st["fyp"], st["fy_prime"], st["kxk"], st["fx"], st["fy"],
                                       [k for k, g in zip(vary, groups) if g in ("mz0", "ssz")])
        for j in range(th.size):
            if vary[j] in mz_cols:
                i0 = 0
                for ch, m, y, w in blocks:
                    n = int(m.sum())
                    if ch == "mz":
                        col = w * mz_cols[vary[j]][m]
                        J[i0:i0 + n, j] = np.where(np.isfinite(col), col, 0.0)
                    i0 += n
                continue  # the penalties (Fx0, Fy0, Fx, Fy factors) do not hold aligning coefficients
            h = eps * max(abs(th[j]), _typical_step(vary[j]))
            t = th[j] + h if th[j] + h <= ub[j] else th[j] - h
            cj = dict(c)
            cj[vary[j]] = float(t)
            bj = model.basic(cj) if groups[j] == "basic" else b
            sj = model.update(st, cj, bj, groups[j])
            touched = mf_parts.TOUCHES[groups[j]]
            i0 = 0
            for ch, m, y, w in blocks:
                n = int(m.sum())
                if ch in touched:
                    rj = w * (model.out(sj, ch)[m] - y)
                    J[i0:i0 + n, j] = (np.where(np.isfinite(rj), rj, 1e3) - rr[i0:i0 + n]) / (t - th[j])
                i0 += n
            qj = dict(p, **dict(zip(vary, th.tolist())))
            qj[vary[j]] = float(t)
            for pb, r0 in zip(pens, pen0):
                if groups[j] not in _PENALTY_GROUPS[pb.stage.name]:  # a factor the coefficient does not enter
                    i0 += r0.size
                    continue
                rj = pb.penalties(qj)
                J[i0:i0 + rj.size, j] = (np.where(np.isfinite(rj), rj, 1e3) - np.where(np.isfinite(r0), r0, 1e3)) \
                    / (t - th[j])
                i0 += rj.size
        return J

    def jac(th):
        if fast:
            return jac_fast(th)
        rr = residual(th)
        J = np.empty((rr.size, th.size))
        eps = math.sqrt(np.finfo(float).eps)
        for j in range(th.size):
            h = eps * max(abs(th[j]), _typical_step(vary[j]))
            t = th.copy()
            t[j] = t[j] + h if t[j] + h <= ub[j] else t[j] - h
            J[:, j] = (residual(t) - rr) / (t[j] - th[j])
        return J

    th0 = _inside(np.array([p[k] for k in vary]), lb, ub)
    r_start = residual(th0)
    pars = Parameters()
    for k, v, lo, hi in zip(vary, th0, lb, ub):
        pars.add(k, float(v), min=lo, max=hi)
    # the one fitting core; the 1/sqrt(n_s) sweep weights are already in each block's rows (w), so unit weights
    sol = solve(residual, pars, jac=jac, x_scale="jac", tol=1e-10, max_nfev=_JOINT_NFEV, stderr=False,
                what="MF joint polish")
    obj0, obj = float(r_start @ r_start), float(sol.cost)
    if not obj < obj0:
        return None
    q = dict(zip(vary, sol.x.tolist()))
    p.update(q)
    cons = [c for pb in pens for c in _check_constraints(pb.stage, p, pb.grid, pb.cgrid)]
    for c in cons:
        if not c["holds"]:
            notes.append(f"joint polish: constraint {c['constraint']} broken on the grid of the fitted range "
                         f"(worst {c['worst']:.3g})")
    facts = {"points": int(sum(m.sum() for _, m, _, _ in blocks)), "objective_before": obj0,
             "channels": [c for c, *_ in blocks]}
    return StageFit("joint", "+".join(c for c, *_ in blocks), vary, {}, {}, facts, obj, nfev[0],
                    time.perf_counter() - t0, [], pd.DataFrame(), {}, cons, facts["points"],
                    int(d["run"].nunique()))


#: points per sweep (every k-th) for the multi-start and for the polish; a 100 Hz rig record has ~1000 per
#: sweep, which add noise averaging but no information on the curve; the statistics use every point
_START_POINTS = 60
_POLISH_POINTS = 250
#: evaluations of a stage's polish; a force stage that has not converged by then crawls along a flat
#: direction (the combined Fy stage held to G <= 1 on data whose generating tyre has G_yk 1.03: 400 iterations,
#: 6.7 s of the FSAE pair's 40 s, for the same RMSE to 0.1 %); the moments' variable-projection start needs more
_POLISH_NFEV = 120
_SECONDARY_NFEV = 100


def _thin(pts: pd.DataFrame, per_sweep: int) -> pd.DataFrame:
    """Every k-th point of each sweep so that no sweep has more than about ``per_sweep`` points."""
    g = pts.groupby("run", sort=False)
    n = g["run"].transform("size").to_numpy()
    step = np.maximum(1, np.ceil(n / per_sweep)).astype(int)
    keep = (g.cumcount().to_numpy() % step) == 0
    return pts[keep] if not keep.all() else pts


def _stderr(prob: _Problem, th, n: int) -> dict[str, float]:
    """Standard errors at the solution; infinite for a coefficient the data do not move at all.

    The covariance's pseudo-inverse gives a zero column (a term multiplied by a coefficient held at 0, say
    QSX5 inside QSX4 cos(QSX5 ...) with QSX4 = 0) a zero variance; it is an unmeasured direction.
    """
    try:  # least-squares weighting (1/n_s) at the solution, whatever the cost: tyrefit.fitting.core.covariance
        J = prob.jac(th)
        cov, _ = covariance(J, prob.mu_residual(th), prob.weights, n_data=n)
        se = np.sqrt(np.clip(np.diag(cov), 0, None))
        norm = np.linalg.norm(J[:n] * np.sqrt(prob.weights[:n])[:, None], axis=0)
        se = np.where(norm > 1e-12 * max(float(norm.max(initial=0.0)), 1e-300), se, np.inf)
        return dict(zip(prob.vary, se.tolist()))
    except (np.linalg.LinAlgError, ValueError):  # pragma: no cover
        return {k: float("nan") for k in prob.vary}


_KNOWN: set | None = None


def _known_names() -> set:
    global _KNOWN
    if _KNOWN is None:
        mf = _mf61()
        _KNOWN = {k for table in (mf.COEFFICIENTS, getattr(mf, "COEFFICIENTS_52", {}))
                  for names in table.values() for k in names} | set(SPEED_FRICTION)
    return _KNOWN


#: the stage whose fitted curve a stage is evaluated on (Pacejka 2012: combined slip weights the pure-slip
#: forces, 4.E50/4.E58; the trail and residual torque use Fy0's stiffness and shift, 4.E34-4.E47; Mx uses Fy)
_PREREQUISITE = {"Fx": "Fx0", "Fy": "Fy0", "Mz0": "Fy0", "Mz": "Mz0", "Mx": "Fy0"}
_PREREQUISITE_WHY = {"Fx0": "no slip-ratio sweeps at zero slip angle with Fx",
                     "Fy0": "no slip-angle sweeps at zero slip ratio with Fy",
                     "Mz0": "no slip-angle sweeps at zero slip ratio with Mz"}


# ------------------------------------------------------------------------------ public API
def fit_mf(data, *, model: str = "mf61", cost: str = "l2", vary: Sequence[str] | None = None,
           effects: Sequence[str] | None = None, fixed: Mapping[str, float] | None = None,
           tyre_info: Mapping | None = None, convention: str = "iso", stages: Sequence[str] | None = None,
           multistart: bool = True, initial: Mapping[str, float] | None = None) -> "FitResultMF":
    """Fit a Magic Formula 6.1 (or 5.2) tyre to one or more rig records.

    Parameters
    ----------
    data : Dataset, DataFrame, path, or a sequence of them
        the records of one tyre (SI, ISO-W canonical columns).
    model : {'mf61', 'mf52'}
    cost : {'l2', 'l1'}
        least squares, or Komana et al. Eq. 5 (sum of absolute mu errors).
    vary : sequence of str, optional
        coefficients that may vary (others held at neutral/initial values).
    effects : sequence of str, optional
        diagnose effect ids: the Fy0 stage varies :data:`START_FY0` plus
        their coefficients (:data:`EFFECT_COEFFICIENTS`) only.
    fixed : mapping, optional
        coefficients held at these values (also FNOMIN, NOMPRES, ... ).
    tyre_info : mapping, optional
        ``fnomin`` [N], ``nompres`` [Pa], ``unloaded_radius``, ``width`` [m], ``name``.
    stages : sequence of str, optional
        stages to run (default all, see :data:`STAGES`).
    initial : mapping, optional
        start values of coefficients, instead of the stages' estimates: the first start of their
        stage's multi-start (the lowest cost wins).

    Returns
    -------
    FitResultMF
    """
    t0 = time.perf_counter()
    if model not in _MODELS:
        raise DataError(f"{option('model', repr(model))}: a Magic Formula fit takes mf61 or mf52")
    if cost not in ("l1", "l2"):
        raise DataError(f"cost {cost!r} is not known; accepted: 'l1' (Komana et al. Eq. 5) or 'l2' (least squares)")
    version = _MODELS[model]
    mf = _mf61()
    data = data if isinstance(data, MFData) else prepare_mf_data(data, convention=convention)
    notes = list(data.notes)
    p = {k.upper(): float(v) for k, v in mf.neutral().items()}
    p.update(_nominal(data, tyre_info, p))
    start = {str(k).upper(): float(v) for k, v in (initial or {}).items()}
    p.update(start)
    for k, v in (fixed or {}).items():
        p[str(k).upper()] = float(v)
    nominal = {k: p[k] for k in ("FNOMIN", "NOMPRES", "LONGVL", "UNLOADED_RADIUS") if k in p}
    fixed_names = {str(k).upper() for k in (fixed or {})}
    eff_vary = None
    if effects is not None:  # [] is diagnose's start model alone
        eff_vary, en = effect_coefficients(list(effects))
        notes += en
    vary_set = {str(k).upper() for k in vary} if vary is not None else None
    fits: dict[str, StageFit] = {}
    quiet: dict[str, str] = {}
    with single_threaded_blas():
        for st in STAGES:
            if stages is not None and st.name not in stages:
                continue
            if st.channel not in quiet:
                quiet[st.channel] = channel_signal(data, st.channel)[2]
                if quiet[st.channel]:
                    notes.append(quiet[st.channel])
            if quiet[st.channel]:
                continue
            pre = _PREREQUISITE.get(st.name)
            if pre and (stages is None or pre in stages) and not (pre in fits and fits[pre].varied):
                # each stage holds the ones before it: on a neutral placeholder curve it would fit nonsense (a
                # drive/brake record alone: combined Fy on a neutral Fy0, 725 N RMSE, R2 0.46)
                notes.append(f"{st.name} not fitted: it is evaluated on the {pre} stage's curve, which these data do "
                             f"not give ({_PREREQUISITE_WHY[pre]})")
                continue
            only = None
            if st.name == "Mz*":
                if not all(k in fits and fits[k].varied for k in ("Mz0", "Mz")):
                    continue
                only = fits["Mz0"].varied + fits["Mz"].varied
            if st.name == "Fy0" and eff_vary is not None:
                only = list(eff_vary)
            # LMUV is shared by Fx and Fy: with --effects it is fitted only when a speed effect is asked for; the
            # Fy0 stage holds the value the Fx0 stage fitted (each stage holds the stages before it: Fx0 was fitted
            # with it), the joint polish moves it with both channels
            hold = [k for k in SPEED_FRICTION if k not in eff_vary] if eff_vary is not None else []
            if st.name == "Fy0" and "Fx0" in fits:
                hold += [k for k in SPEED_FRICTION if k in fits["Fx0"].varied and k not in hold]
            if vary_set is not None:
                only = [k for k in (only if only is not None else st.names) if k in vary_set]
            if fixed_names:
                only = [k for k in (only if only is not None else st.names) if k not in fixed_names]
            if st.name == "Mx" and cost == "l2" and (stages is None or "joint" in stages):
                # before the moments that use the final Fy: every force/Mz coefficient polished together
                jf = _joint_polish(data, p, fits, nominal=nominal, version=version, notes=notes)
                if jf is not None:
                    fits["joint"] = jf
            sf = _fit_stage(st, data, p, vary_only=only, nominal=nominal, version=version, cost=cost, notes=notes,
                            multistart=multistart, hold=hold, given=[*start, *fixed_names])
            if sf is None:
                continue
            fits[st.name] = sf
    _drop_unfit(data, p, fits, notes)
    if not fits:
        raise DataError(f"{', '.join(data.sources)}: no stage could be fitted (need slip-angle sweeps with fy or "
                        "slip-ratio sweeps with fx)")
    if not all(np.isfinite(v) for v in p.values() if isinstance(v, float)):
        raise FitError("the Magic Formula fit produced non-finite coefficients; check the data (units, signs)")
    if "Fy0" in fits and fits["Fy0"].varied:
        _check_orientation(data, p, version)
    warns = _bound_warnings(p, fits, notes)
    return FitResultMF.build(p, fits, data, model=model, version=version, cost=cost, notes=notes,
                             tyre_info=dict(tyre_info or {}), seconds=time.perf_counter() - t0, effects=effects,
                             warnings=warns)


def _check_orientation(data: MFData, p, version) -> None:
    pts = data.subset(("lateral",), "fy")
    if len(pts) < 10:
        return
    if _orientation(pts, "slip_angle", "fy") < 0:
        raise DataError(f"{', '.join(data.sources)}: the lateral force rises with slip angle; in ISO-W (tyrefit's "
                        "convention) a positive slip angle gives a negative lateral force. If the file uses the SAE "
                        f"convention (FSAE TTC), pass {option('convention', 'sae')}")
