"""Wear-aware axle force allocation and the torque controller (Pham et al. 2025, Sec. 3.2-3.3).

The low-wear vehicle has hard tyres in front and soft ones at the rear (the
rear must stay soft, Eq. 21-23).  Given the driver's inputs, the allocator
predicts the forces the *base* (all-soft) vehicle would produce at the
current state, then finds front and rear longitudinal forces and a steering
correction that give the same body forces with the least tyre-wear emission:

* **base forces** (Eq. 24-28).  Lateral forces come from the soft tyre at the
  measured vx, vy, r and the driver's steering; longitudinal forces from the
  driver's demand, shared equally as the base vehicle's equal torque split
  does (:class:`EqualSplit`), within its slip limits.  :func:`base_forces_from_motion`
  is the paper's alternative, the 2x2 solve from measured accelerations.
* **no steering** (Eq. 29-30): only the total F = F_x,f + F_x,r is fixed; with
  N_s the soft tyre's axle emission and N_h = k N_s the hard one's, the best
  front force is F_f* = (2aF + b - k b) / (2a(1 + k)) (:func:`optimal_front_force`),
  projected onto the slip limits (:func:`split_no_steering`);
* **steering** (Eq. 31-34): the front lateral force at steer + d_steer fixes
  F_x,f(d_steer) and F_x,r(d_steer), and Alg. 1 (:func:`greedy_search`) finds
  the d_steer of least emission;
* **slip limits** (Eq. 49-50) keep each tyre's friction under a share of its
  peak (:class:`PeakShareSlipLimit`), or use the tyre's characteristic slip
  (Ghasemi et al. 2021) where the tyre provides one (:class:`CharacteristicSlipLimit`);
* **torque controller**: the paper solves a path-discretised optimal-control
  problem offline.  tyrefit uses a causal force-tracking controller
  (:class:`ForceTrackingController`): invert the tyre curve for the slip that
  gives the reference force, then wheel torque = r F_ref + J dw_ref/dt +
  J K (w_ref - w).  It runs at every time step like an ECU would, needs no
  solver, and tracks to within the wheel's millisecond time constant (the
  scenario reports show the tracking error).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..errors import ModelError
from .emission import QuadraticEmission
from .tyres import AxleTyre
from ..fitting.slip import fit_friction_slip

__all__ = [
    "optimal_front_force",
    "split_no_steering",
    "greedy_search",
    "steering_split",
    "base_forces_from_motion",
    "PeakShareSlipLimit",
    "CharacteristicSlipLimit",
    "CurveCharacteristicSlipLimit",
    "resolve_slip_limit",
    "AxleLimits",
    "EqualSplit",
    "WearAwareAllocator",
    "ForceTrackingController",
]


# ---------------------------------------------------------------------------- closed form (Eq. 29-30)

def optimal_front_force(total, emission_soft: QuadraticEmission, k: float):
    """Front force minimising N_s(F - F_f) + k N_s(F_f) without limits (Pham et al. 2025, Eq. 30).

    ``emission_soft`` is the soft tyre's law for the *axle* force
    (:meth:`QuadraticEmission.axle`); ``total`` = F_x,f + F_x,r [N].

    F_f* = (2 a F + b - k b) / (2 a (1 + k)).
    """
    a, b = emission_soft.a, emission_soft.b
    return (2.0 * a * np.asarray(total, float) + b - k * b) / (2.0 * a * (1.0 + k))


def split_no_steering(total, emission_soft: QuadraticEmission, k: float, front_limits, rear_limits):
    """Emission-optimal (F_x,f, F_x,r) with F_x,f + F_x,r = total inside both axles' limits.

    The cost is convex in F_x,f, so the constrained optimum is the closed form
    clipped to the feasible interval [max(lo_f, F - hi_r), min(hi_f, F - lo_r)];
    when the demand exceeds what both axles can give, both sit at their limits.
    """
    total = np.asarray(total, float)
    lo_f, hi_f = (np.asarray(v, float) for v in front_limits)
    lo_r, hi_r = (np.asarray(v, float) for v in rear_limits)
    f_opt = optimal_front_force(total, emission_soft, k)
    lo = np.maximum(lo_f, total - hi_r)
    hi = np.minimum(hi_f, total - lo_r)
    ff = np.minimum(np.maximum(f_opt, lo), np.maximum(lo, hi))
    fr = total - ff
    over = total > hi_f + hi_r
    under = total < lo_f + lo_r
    ff = np.where(over, hi_f, np.where(under, lo_f, ff))
    fr = np.where(over, hi_r, np.where(under, lo_r, fr))
    return ff, fr


# ---------------------------------------------------------------------------- Alg. 1

def greedy_search(fun, x0, step, tol: float = 1e-12, max_iter: int = 200):
    """Alg. 1 of Pham et al. (2025): greedy 1-D local search, vectorised over a batch.

    From ``x0`` evaluate ``fun`` at x + h and x - h; move to the lower of the
    two if it is lower than f(x), else halve h; stop when h < ``tol``.

    Parameters
    ----------
    fun : callable
        f(x) -> array of the same shape as ``x`` (one problem per element).
    x0, step : array_like
        Start and initial step (broadcast to one per problem).
    tol : float or array_like
        Final step size (one per problem allowed).
    max_iter : int

    Returns
    -------
    x, f, n_evaluations : ndarray, ndarray, int
    """
    x = np.array(x0, dtype=float, copy=True)
    h = np.broadcast_to(np.asarray(step, float), x.shape).copy()
    tol = np.broadcast_to(np.asarray(tol, float), x.shape)
    f = np.asarray(fun(x), float)
    n_eval = 1
    for _ in range(max_iter):
        active = (h >= tol) & (h > 0)
        if not np.any(active):
            break
        fp = np.asarray(fun(x + h), float)
        fm = np.asarray(fun(x - h), float)
        n_eval += 2
        up = active & (fp < f) & (fp <= fm)
        down = active & (fm < f) & ~up
        x = np.where(up, x + h, np.where(down, x - h, x))
        f = np.where(up, fp, np.where(down, fm, f))
        h = np.where(active & ~(up | down), 0.5 * h, h)
    return x, f, n_eval


# ---------------------------------------------------------------------------- steering (Eq. 31-34)

def steering_split(d_steer, *, steer, alpha_f, body_x, body_y, hard_front: AxleTyre, condition):
    """Front and rear longitudinal forces that reproduce the base body forces at steer + d_steer.

    With the front lateral force of the hard tyre at the corrected steering,
    F_y,f' = eta F_y,h(alpha_f - d_steer) (Eq. 31), the lateral balance of the
    front axle and the longitudinal balance (Eq. 32-33) give::

        F_x,f = (Y - F_y,f' cos s') / sin s'
        F_x,r = X - F_x,f cos s' + F_y,f' sin s'        s' = steer + d_steer

    where X and Y are the base vehicle's longitudinal body force (before drag)
    and the front axle's lateral body force.

    Returns
    -------
    fx_f, fx_r, fy_f : ndarray
    """
    s2 = steer + d_steer
    fy = condition * hard_front.fy(alpha_f - d_steer)
    sn, cs = np.sin(s2), np.cos(s2)
    sn = np.where(np.abs(sn) < 1e-12, np.copysign(1e-12, sn), sn)
    fx_f = (body_y - fy * cs) / sn
    fx_r = body_x - fx_f * cs + fy * sn
    return fx_f, fx_r, fy


def base_forces_from_motion(*, mass, dvx, dvy, vx, vy, yaw_rate, steer, drag_force, fy_f, fy_r):
    """Base vehicle's longitudinal forces from its motion (Pham et al. 2025, Eq. 26-28).

    Solves::

        [cos s  1] [F_x,f]   [m (dvx/dt - vy r) + C_d v^2 + F_y,f sin s]
        [sin s  0] [F_x,r] = [m (dvy/dt + vx r) - F_y,r - F_y,f cos s ]

    which has a unique solution when the steering angle s is not zero.
    """
    s = np.asarray(steer, float)
    rhs1 = mass * (dvx - vy * yaw_rate) + drag_force + fy_f * np.sin(s)
    rhs2 = mass * (dvy + vx * yaw_rate) - fy_r - fy_f * np.cos(s)
    fx_f = rhs2 / np.sin(s)
    fx_r = rhs1 - fx_f * np.cos(s)
    return fx_f, fx_r


# ---------------------------------------------------------------------------- slip limits (Eq. 49-50)

@dataclass(frozen=True)
class PeakShareSlipLimit:
    """Slip bounds where |mu| reaches ``share`` of its peak on the rising branch (Eq. 49-50).

    The hard tyre peaks at larger slip, so its bounds are wider, as Pham et al.
    note.  ``share`` = 0.95 is tyrefit's default (the paper's value is not
    used); with the bundled tyres it gives the effective friction that
    reproduces Table 3 of Pham et al. (2025).
    """

    share: float = 0.95

    def __call__(self, axle: AxleTyre) -> tuple[float, float]:
        return axle.slip_for_mu_share(self.share)

    def describe(self) -> str:
        return f"|mu| <= {self.share:g} x peak (Eq. 49-50)"


@dataclass(frozen=True)
class CharacteristicSlipLimit:
    """Slip bounds at the tyre's characteristic slip s_c (Ghasemi et al. 2021, Eq. 15-17).

    ``slip`` is s_c (> 0), used as +-s_c.  Bounds beyond the slip of peak force
    are moved back to the peak's slip, so the wheel stays on the stable branch.
    """

    slip: float
    source: str = "characteristic slip"

    def __call__(self, axle: AxleTyre) -> tuple[float, float]:
        if not self.slip > 0:
            raise ModelError(f"characteristic slip must be positive, got {self.slip!r}")
        lo = max(-self.slip, axle.peak_brake[0])
        hi = min(self.slip, axle.peak_drive[0])
        return lo, hi

    def describe(self) -> str:
        return f"+-{self.slip:.4g} ({self.source}, capped at the slip of peak force)"


@dataclass(frozen=True)
class CurveCharacteristicSlipLimit:
    """The characteristic slip of Ghasemi et al. (2021) computed from the axle's own Fx curve.

    Fits mu = mu_p (1 - exp(-k s)) (Ghasemi et al., Eq. 8) to the driving
    branch of the tyre's Fx/Fz curve up to its peak with
    :func:`tyrefit.fitting.slip.fit_friction_slip`, takes s_c (Eq. 16, with
    curvature ``nu_c``), converts the paper's slippage s = 1 - v/(r w) to the
    slip ratio s / (1 - s) and uses it, capped at the slip of peak force, on
    both sides (:class:`CharacteristicSlipLimit`).
    """

    nu_c: float = -2.0

    def characteristic_slip(self, axle: AxleTyre) -> float:
        lam_peak = axle.peak_drive[0]
        lam = np.linspace(0.0, lam_peak, 60)[1:]
        s = lam / (1.0 + lam)                                    # slip ratio -> slippage
        mu = axle.fx(lam) / (axle.n_tyres * axle.fz)
        sc = fit_friction_slip(s, mu, nu_c=self.nu_c, fz=axle.fz).characteristic_slip
        return float(sc / (1.0 - sc)) if sc < 1 else float("inf")

    def __call__(self, axle: AxleTyre) -> tuple[float, float]:
        return CharacteristicSlipLimit(self.characteristic_slip(axle))(axle)

    def describe(self) -> str:
        return f"characteristic slip of the tyre's own curve (Ghasemi et al. 2021, Eq. 16, nu_c = {self.nu_c:g}), capped at peak"


def resolve_slip_limit(tyre, default=None):
    """The slip limit for a tyre: its characteristic slip where it provides one, else ``default``.

    A tyre "provides" a characteristic slip through an attribute
    ``characteristic_slip`` (set, e.g., from ``tyrefit slip`` results).  The
    default is :class:`PeakShareSlipLimit` ().
    """
    sc = getattr(tyre, "characteristic_slip", None)
    if sc is not None and np.isfinite(sc) and sc > 0:
        return CharacteristicSlipLimit(float(sc), source=f"characteristic slip of {getattr(tyre, 'name', 'tyre')}")
    return default if default is not None else PeakShareSlipLimit()


@dataclass
class AxleLimits:
    """Force bounds of one axle from its slip limits: eta F(lambda_lo) <= F_x <= eta F(lambda_hi)."""

    axle: AxleTyre
    slip: tuple[float, float]
    condition: np.ndarray
    lower: np.ndarray = field(init=False)
    upper: np.ndarray = field(init=False)

    def __post_init__(self) -> None:
        self.condition = np.atleast_1d(np.asarray(self.condition, float))
        self.lower = self.condition * float(self.axle.fx(self.slip[0]))
        self.upper = self.condition * float(self.axle.fx(self.slip[1]))


# ---------------------------------------------------------------------------- allocators

@dataclass
class EqualSplit:
    """The base vehicle: equal force demand on both axles, within their slip limits."""

    front: AxleLimits
    rear: AxleLimits

    def __call__(self, i, t, x, steer_driver, force_demand):
        half = 0.5 * force_demand
        ff = np.minimum(np.maximum(half, self.front.lower), self.front.upper)
        fr = np.minimum(np.maximum(half, self.rear.lower), self.rear.upper)
        return ff, fr, np.zeros_like(ff)


@dataclass
class WearAwareAllocator:
    """The controller of Pham et al. (2025) for the low-wear vehicle (hard front, soft rear).

    Parameters
    ----------
    model : VehicleModel
        The low-wear vehicle (for kinematics and the condition eta).
    soft_front : AxleTyre
        The soft tyre at the *front* static load: the base vehicle's front axle.
    base_front, base_rear : AxleLimits
        The base vehicle's slip-limited force bounds.
    front, rear : AxleLimits
        The low-wear vehicle's bounds (hard front, soft rear).
    emission_soft : QuadraticEmission
        Soft tyre's emission for the axle force (N_h = k N_s).
    k : float
        Hard/soft emission ratio (Eq. 43).
    min_steer : float
        Below this |steer| [rad] the closed form (no steering) is used.
    search_every : int
        Run Alg. 1 every this many calls (the split is held between searches
        while the steering correction is re-solved at every call so the body
        forces keep matching the base vehicle's).
    search_force_step, search_force_tol : float
        Alg. 1's initial and final steps expressed as front-force changes [N]:
        a steering step h moves F_x,f by about C_alpha h / |sin(steer)|, so the
        steps in radians are these forces times |sin(steer)| / C_alpha.

    Notes
    -----
    Between searches, and after each, the steering correction d_steer solves
    the front lateral balance (Eq. 32) for the current front force by Newton's
    method; at a search step this reproduces Alg. 1's d_steer.
    """

    model: object
    soft_front: AxleTyre
    base_front: AxleLimits
    base_rear: AxleLimits
    front: AxleLimits
    rear: AxleLimits
    emission_soft: QuadraticEmission
    k: float
    min_steer: float = 1e-3
    search_every: int = 10
    search_force_step: float = 200.0
    search_force_tol: float = 0.2
    stats: dict = field(default_factory=lambda: {"searches": 0, "evaluations": 0})

    def __post_init__(self) -> None:
        b = self.model.n_members
        self._d_steer = np.zeros(b)
        self._fx_f = np.zeros(b)
        self._was_steering = np.zeros(b, dtype=bool)
        self._calls = 0
        self._penalty = 1e4 * self.emission_soft.a

    def emission(self, fx_f, fx_r):
        """Axle emissions of the low-wear vehicle [#/s]: k N_s(F_x,f) + N_s(F_x,r) (Eq. 30/34)."""
        return self.k * self.emission_soft.rate(fx_f) + self.emission_soft.rate(fx_r)

    def base_body_forces(self, x, steer_driver, force_demand):
        """(X, Y): base vehicle's longitudinal body force (without drag) and front lateral body force."""
        eta = self.model.condition
        half = 0.5 * force_demand
        ff = np.minimum(np.maximum(half, self.base_front.lower), self.base_front.upper)
        fr = np.minimum(np.maximum(half, self.base_rear.lower), self.base_rear.upper)
        alpha_f = self.model.slip_angle_front(x, steer_driver)
        fy = eta * self.soft_front.fy(alpha_f)                           # Eq. 24
        sn, cs = np.sin(steer_driver), np.cos(steer_driver)
        return fr + ff * cs - fy * sn, ff * sn + fy * cs, alpha_f

    def objective(self, d_steer, steer, alpha_f, body_x, body_y):
        """Emission as a function of the steering correction alone (Eq. 34), with limit penalties."""
        eta = self.model.condition
        fx_f, fx_r, _ = steering_split(d_steer, steer=steer, alpha_f=alpha_f, body_x=body_x, body_y=body_y,
                                       hard_front=self.front.axle, condition=eta)
        over_f = np.maximum(fx_f - self.front.upper, 0) + np.maximum(self.front.lower - fx_f, 0)
        over_r = np.maximum(fx_r - self.rear.upper, 0) + np.maximum(self.rear.lower - fx_r, 0)
        return self.emission(fx_f, fx_r) + self._penalty * (over_f**2 + over_r**2)

    def _newton_steer(self, d, fx_f, steer, alpha_f, body_y, iters: int = 3):
        """Solve F_x,f sin s' + F_y,h(alpha_f - d) cos s' = Y for d (Eq. 32), Newton from d."""
        eta = self.model.condition
        axle = self.front.axle
        for _ in range(iters):
            s2 = steer + d
            sn, cs = np.sin(s2), np.cos(s2)
            fy = eta * axle.fy(alpha_f - d)
            g = fx_f * sn + fy * cs - body_y
            dg = fx_f * cs + eta * axle.cornering_stiffness(alpha_f - d) * cs - fy * sn
            d = d - g / np.where(np.abs(dg) > 1e-9, dg, 1e-9)
        return d

    def __call__(self, i, t, x, steer_driver, force_demand):
        eta = self.model.condition
        body_x, body_y, alpha_f = self.base_body_forces(x, steer_driver, force_demand)
        steering = np.abs(steer_driver) >= self.min_steer
        # -- no steering: closed form on the total, F = X (+ F_y,f' sin s', negligible) ------------
        ff_free, _ = split_no_steering(body_x, self.emission_soft, self.k, (self.front.lower, self.front.upper),
                                       (self.rear.lower, self.rear.upper))
        search = steering & ((self._calls % self.search_every == 0) | ~self._was_steering)
        fx_f = np.where(steering, self._fx_f, ff_free)
        if np.any(search):
            # start Alg. 1 where the lateral balance holds with the closed-form split
            d0 = self._newton_steer(self._d_steer, ff_free, steer_driver, alpha_f, body_y)
            scale = np.abs(np.sin(steer_driver + d0)) / (eta * self.front.axle.cornering_stiffness(alpha_f - d0))
            d_opt, _, n_eval = greedy_search(
                lambda d: self.objective(d, steer_driver, alpha_f, body_x, body_y),
                np.where(search, d0, self._d_steer), np.where(search, self.search_force_step * scale, 0.0),
                tol=self.search_force_tol * scale)
            f_opt, _, _ = steering_split(d_opt, steer=steer_driver, alpha_f=alpha_f, body_x=body_x,
                                         body_y=body_y, hard_front=self.front.axle, condition=eta)
            fx_f = np.where(search, f_opt, fx_f)
            self.stats["searches"] += 1
            self.stats["evaluations"] += n_eval
        fx_f = np.minimum(np.maximum(fx_f, self.front.lower), self.front.upper)
        d = self._newton_steer(self._d_steer, fx_f, steer_driver, alpha_f, body_y)
        s2 = steer_driver + d
        fy = eta * self.front.axle.fy(alpha_f - d)
        fx_r = body_x - fx_f * np.cos(s2) + fy * np.sin(s2)
        fx_r = np.minimum(np.maximum(fx_r, self.rear.lower), self.rear.upper)
        self._d_steer, self._fx_f, self._was_steering = d, fx_f, steering
        self._calls += 1
        return fx_f, fx_r, d


# ---------------------------------------------------------------------------- torque controller

@dataclass
class ForceTrackingController:
    """Wheel torques that make each axle produce its reference longitudinal force.

    For each axle: the slip lambda_ref that gives F_ref on the stable branch of
    the tyre curve (eta F(lambda_ref) = F_ref, F_ref first clipped to the slip
    limits), the wheel speed w_ref = (v + lambda_ref max(|v|, eps)) / r, and::

        T = r F_ref + J dw_ref/dt + J K (w_ref - w)

    The first two terms are the exact steady-state feed-forward of Eq. 5, the
    last pulls the wheel onto the reference slip with rate K on top of the
    tyre's own slip stiffness.  dw_ref/dt uses the vehicle's measured
    acceleration (one step old).

    Parameters
    ----------
    model : VehicleModel
    front, rear : AxleLimits
    gain : float
        K [1/s].
    """

    model: object
    front: AxleLimits
    rear: AxleLimits
    gain: float = 100.0

    def __call__(self, x, steer, f_ref_f, f_ref_r, vdot):
        m = self.model
        p = m.params
        eta = m.condition
        vf, vr = m.wheel_speeds(x, steer)
        out = []
        for f_ref, lim, v, w in ((f_ref_f, self.front, vf, x[6]), (f_ref_r, self.rear, vr, x[7])):
            f_ref = np.minimum(np.maximum(f_ref, lim.lower), lim.upper)
            lam = np.minimum(np.maximum(lim.axle.slip_for_force(f_ref / eta), lim.slip[0]), lim.slip[1])
            den = np.maximum(np.abs(v), p.min_speed)
            w_ref = (v + lam * den) / p.wheel_radius
            dw_ref = (1.0 + lam) * vdot / p.wheel_radius
            out.append(p.wheel_radius * f_ref + p.wheel_inertia * (dw_ref + self.gain * (w_ref - w)))
        return out[0], out[1]
