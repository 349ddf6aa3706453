"""Road-adhesion estimation with an extended Kalman filter (Zhang et al. 2024, §4).

Zhang et al. estimate the road adhesion coefficient mu of each wheel from the
body accelerations and the yaw moment with an EKF whose measurement model
is a 7-DOF vehicle (Eq. 33-36) carrying camber brush tyres; they compare
the improved (width-aware, 2N-strip) camber brush model with the original
one on roads of mu = 0.8 and 0.3 with camber 0, 3 and 6 deg on the left
wheels and the opposite on the right.  This module reproduces that
experiment:

1. the *true* vehicle (:func:`simulate_truth`) drives on a road of known mu
   with improved-model tyres (:func:`tyrefit.models.brush.camber_brush_forces`,
   2N = 16 strips): a sinusoidal steer with slip-controlled braking whose
   slip each wheel cycles at its own frequency (as an ABS does), which keeps
   every tyre in its partly sliding range where the forces depend on mu (in
   the linear range they do not, and mu is unobservable) and makes the four
   mu separable with three measurements;
2. the measurements ``[a_x, a_y, Gamma]`` (Eq. 37), sampled at 250 Hz, get
   Gaussian noise (0.05 m/s^2, 0.05 m/s^2, 40 N m by default);
3. an EKF (:class:`AdhesionEKF`) with the parameter vector
   ``[mu_fl, mu_fr, mu_rl, mu_rr]`` as a random walk (Eq. 37-40) estimates mu,
   once with the improved model (2N = 12 strips: coarser than the truth) and
   once with the original camber brush model, whose parameters are
   calibrated on zero-camber forces of the same tyre
   (:func:`tyrefit.fitting.brush.calibrate_original`): the two agree
   without camber and differ as camber grows (the paper's Fig. 16-17).

The EKF knows the vehicle states (speeds, yaw rate, wheel spins, steer), as
in the paper; its loads come from the measured accelerations; it starts
from mu = 0.5 on both roads.  Its random walk is large at first and decays
(``q`` to ``q_final``), so that it leaves a poor start quickly and then
averages the noise.  The
Jacobian (Eq. 38-40) is ``H = D dF/dmu``: D, the derivative of the
measurement with respect to the eight tyre forces, is exact
(:func:`tyrefit.sim.vehicle7dof.measurement_matrix`); dF/dmu of each tyre is
a central difference (each tyre's force depends on its own mu only, so one
pair of batched tyre evaluations gives all four columns).

Camber signs: the inclination angle is ISO-W (positive leans the wheel top
to -y).  "Camber g on the left wheels and the opposite on the right" gives
``[+g, -g, +g, -g]`` in the order fl, fr, rl, rr: a symmetric car.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import lru_cache

import numpy as np

from ..models import brush as bm
from . import vehicle7dof as v7
from ..fitting.brush import calibrate_original

__all__ = [
    "Manoeuvre",
    "TyreModel",
    "improved_tyre",
    "original_tyre",
    "TruthRun",
    "simulate_truth",
    "AdhesionEKF",
    "AdhesionResult",
    "estimate",
    "run_experiment",
    "convergence_time",
    "camber_vector",
]


@dataclass(frozen=True)
class Manoeuvre:
    """The test drive: steer sine with slip-controlled braking.

    Attributes
    ----------
    speed : float
        Initial speed [m/s].
    duration : float
        Length of the run [s].
    steer_amplitude : float
        Road-wheel steer amplitude [rad].
    steer_frequency : float
        Steer frequency [Hz].
    brake_phi : float
        Target combined slip of the braking, as phi = Kx |sigma_x| / (mu Fz) of
        the nominal tyre at the static load on this road (1.5: half the
        contact patch slides; 3 is full sliding for a parabolic pressure).
        The slip controller (an ideal ABS) holds each wheel at the slip this
        gives; it is the test driver's input, not known to the estimator.
    brake_ramp : float
        Time to reach the brake slip [s].
    slip_modulation : float
        Relative amplitude of the slip cycling of each wheel [-] (an ABS
        cycles its wheels; different frequencies per wheel make the four mu
        separately visible in three measurements).
    slip_frequencies : tuple of float
        Cycling frequency of each wheel fl, fr, rl, rr [Hz].
    wheel_gain : float
        Bandwidth of the slip controller [1/s].
    """

    speed: float = 22.0
    duration: float = 2.0
    steer_amplitude: float = np.deg2rad(2.0)
    steer_frequency: float = 0.5
    brake_phi: float = 1.5
    brake_ramp: float = 0.15
    slip_modulation: float = 0.4
    slip_frequencies: tuple[float, float, float, float] = (2.1, 2.9, 3.7, 4.6)
    wheel_gain: float = 80.0

    def steer(self, t):
        """Front steer angle [rad] at time t [s]."""
        return self.steer_amplitude * np.sin(2 * np.pi * self.steer_frequency * np.asarray(t, float))


def camber_vector(camber) -> np.ndarray:
    """Inclination of the wheels fl, fr, rl, rr [rad] for camber on the left and the opposite on the right."""
    return np.array([camber, -camber, camber, -camber], float)


# --- tyre models ---------------------------------------------------------------------------
@dataclass(frozen=True)
class TyreModel:
    """A brush tyre model in vehicle form: forces from the wheel kinematics.

    ``kind`` is ``'improved'`` (2N strips, :func:`~tyrefit.models.brush.camber_brush_forces`)
    or ``'original'`` (:func:`~tyrefit.models.brush.brush_forces`).
    """

    params: bm.BrushParams
    kind: str = "improved"
    n: int = 8

    def forces(self, fz, vx, vy, omega, camber, mu, pressure):
        """Fx, Fy [N] (ISO-W) of each wheel; all arguments broadcast."""
        if self.kind == "improved":
            f = bm.camber_brush_forces(self.params, fz, 0.0, 0.0, camber, pressure, mu, n=self.n,
                                       vx=vx, vy=vy, omega=omega)
        else:
            f = bm.brush_forces(self.params, fz, 0.0, 0.0, camber, pressure, mu, vx=vx, vy=vy, omega=omega)
        return f.fx, f.fy

    @property
    def label(self) -> str:
        return f"improved camber brush (2N = {2 * self.n})" if self.kind == "improved" else "original camber brush"


def improved_tyre(params: bm.BrushParams = bm.DEFAULT_PARAMS, n: int = 8) -> TyreModel:
    """The improved camber brush model with 2N strips."""
    return TyreModel(params, "improved", n)


@lru_cache(maxsize=8)
def _calibrated(params: bm.BrushParams, n: int) -> bm.BrushParams:
    return calibrate_original(params, n=n).params


def original_tyre(params: bm.BrushParams = bm.DEFAULT_PARAMS, n: int = 16) -> TyreModel:
    """The original camber brush model, calibrated on the zero-camber forces of ``params`` (2N = 2n strips)."""
    return TyreModel(_calibrated(params, n), "original", 1)


# --- the true vehicle ----------------------------------------------------------------------
@dataclass
class TruthRun:
    """Record of the true vehicle at the estimator's sample times.

    ``t`` [s]; ``state`` (T, 7) in :data:`~tyrefit.sim.vehicle7dof.STATES` order;
    ``delta`` [rad]; ``fz``, ``fx``, ``fy`` (T, 4) [N]; ``y`` (T, 3) true
    measurement; ``y_meas`` with noise; ``camber`` (4,) [rad]; ``mu`` road;
    ``tyre`` the true tyre model.
    """

    t: np.ndarray
    state: np.ndarray
    delta: np.ndarray
    fz: np.ndarray
    fx: np.ndarray
    fy: np.ndarray
    y: np.ndarray
    y_meas: np.ndarray
    camber: np.ndarray
    mu: float
    vehicle: v7.VehicleParams
    noise: tuple[float, float, float]
    tyre: str = ""


def simulate_truth(road_mu: float, camber: float, *, tyre: TyreModel | None = None,
                   vehicle: v7.VehicleParams = v7.VehicleParams(), manoeuvre: Manoeuvre = Manoeuvre(),
                   dt: float = 2e-3, sample_every: int = 2, noise=(0.05, 0.05, 40.0),
                   seed: int = 1) -> TruthRun:
    """Drive the 7-DOF vehicle on a road of adhesion ``road_mu`` (explicit Euler, step ``dt``).

    Parameters
    ----------
    road_mu : float
        True road adhesion coefficient [-].
    camber : float
        Camber of the left wheels [rad]; the right wheels get the opposite.
    tyre : TyreModel, optional
        The tyres of the true vehicle; default the improved model with 2N = 16.
    vehicle, manoeuvre : optional
    dt : float
        Integration step [s].
    sample_every : int
        Record (and measure) every this many steps.
    noise : (float, float, float)
        Standard deviations of the measured a_x, a_y [m/s^2] and Gamma [N m].
    seed : int
        Seed of the measurement noise.
    """
    tyre = tyre or improved_tyre(n=8)
    vp, man = vehicle, manoeuvre
    gam = camber_vector(camber)
    mu = np.full(4, float(road_mu))
    R = vp.wheel_radius
    # nominal longitudinal stiffness at the static load -> the brake slip of the manoeuvre
    fz0 = v7.normal_loads(0.0, 0.0, vp)
    st0 = bm.original_state(tyre.params, fz0, vp.pressure)
    kx0 = 2 * st0.a[..., 0] ** 2 * st0.kx[..., 0]
    slip_target = -man.brake_phi * road_mu * fz0 / kx0
    state = np.zeros(7)
    state[0] = man.speed
    state[3:] = man.speed / R
    acc = np.zeros(3)
    n_steps = int(round(man.duration / dt))
    rec = {k: [] for k in ("t", "state", "delta", "fz", "fx", "fy", "y")}
    for i in range(n_steps + 1):
        t = i * dt
        delta = float(man.steer(t))
        fz = v7.normal_loads(acc[0], acc[1], vp)
        vxw, vyw = v7.wheel_velocities(state[0], state[1], state[2], delta, vp)
        omega = state[3:]
        fx, fy = tyre.forces(fz, vxw, vyw, omega, gam, mu, vp.pressure)
        # ideal slip controller: computed torque that drives omega to its target
        ramp = min(t / man.brake_ramp, 1.0) if man.brake_ramp > 0 else 1.0
        cycle = 1.0 + man.slip_modulation * np.sin(2 * np.pi * np.asarray(man.slip_frequencies) * t)
        omega_ref = vxw * (1.0 + ramp * cycle * slip_target) / R
        torque = fx * R - vp.wheel_inertia * man.wheel_gain * (omega - omega_ref)
        d, acc = v7.derivatives(state, fx, fy, torque, delta, vp)
        if i % sample_every == 0:
            for k, v in (("t", t), ("state", state.copy()), ("delta", delta), ("fz", fz), ("fx", fx),
                         ("fy", fy), ("y", acc.copy())):
                rec[k].append(v)
        state = state + dt * d
    out = {k: np.asarray(v) for k, v in rec.items()}
    rng = np.random.default_rng(seed)
    y_meas = out["y"] + rng.standard_normal(out["y"].shape) * np.asarray(noise)
    return TruthRun(out["t"], out["state"], out["delta"], out["fz"], out["fx"], out["fy"], out["y"], y_meas,
                    gam, float(road_mu), vp, tuple(float(x) for x in noise), tyre.label)


# --- the estimator -------------------------------------------------------------------------------
@dataclass
class AdhesionEKF:
    """Extended Kalman filter for the four adhesion coefficients (Zhang et al., Eq. 37-40, Fig. 13).

    Parameter model: random walk ``mu_k = mu_{k-1} + w``, ``w ~ N(0, Q)``.
    Measurement: ``y = h(mu, u) + v`` (Eq. 37) with ``y = [a_x, a_y, Gamma]``,
    ``v ~ N(0, R)``; ``u`` holds the vehicle states and steer.

    Attributes
    ----------
    tyre : TyreModel
        The estimator's tyre model.
    vehicle : VehicleParams
    mu0 : float
        Initial estimate.
    p0 : float
        Initial standard deviation of each mu.
    q : float
        Standard deviation of the random walk per update at the start.
    q_final : float
        ... and at the end: ``q(t) = q_final + (q - q_final) exp(-t / q_tau)``.
        A large q lets the filter leave a poor initial guess quickly; a small
        one then averages the noise (a road that changes suddenly would need
        q reset, as after a detected change).
    q_tau : float
        Time constant of that decay [s].
    r : (float, float, float)
        Measurement standard deviations (a_x, a_y [m/s^2], Gamma [N m]).
    h_rel : float
        Relative step of the central difference dF/dmu.
    bounds : (float, float)
        Estimates are kept inside these bounds.
    max_step : float or None
        Largest change of an estimate in one update (a rate limit against
        the overshoot of the linearised update far from the solution).
    """

    tyre: TyreModel
    vehicle: v7.VehicleParams = field(default_factory=v7.VehicleParams)
    mu0: float = 0.5
    p0: float = 0.3
    q: float = 3e-3
    q_final: float = 1e-4
    q_tau: float = 0.25
    r: tuple[float, float, float] = (0.05, 0.05, 40.0)
    h_rel: float = 1e-4
    bounds: tuple[float, float] = (0.05, 1.5)
    max_step: float | None = None

    def jacobian(self, mu, state, delta, camber, fz):
        """Predicted measurement h(mu) and its Jacobian H = dh/dmu (3 x 4) (Eq. 38-40)."""
        vp = self.vehicle
        vxw, vyw = v7.wheel_velocities(state[0], state[1], state[2], delta, vp)
        hstep = self.h_rel * np.maximum(mu, 1e-3)
        mus = np.stack([mu, mu + hstep, mu - hstep])  # one batched call for h and all columns of H
        fx, fy = self.tyre.forces(fz, vxw, vyw, state[3:], camber, mus, vp.pressure)
        D = v7.measurement_matrix(delta, vp)
        h = D @ np.concatenate([fx[0], fy[0]])
        dfx = (fx[1] - fx[2]) / (2 * hstep)
        dfy = (fy[1] - fy[2]) / (2 * hstep)
        H = D[:, :4] * dfx + D[:, 4:] * dfy  # Zhang et al., Eq. 39-40: each tyre depends on its own mu
        return h, H

    def run(self, truth: TruthRun) -> np.ndarray:
        """Estimates (T, 4) at the truth's sample times, from its noisy measurements."""
        n = truth.t.size
        mu = np.full(4, float(self.mu0))
        P = np.eye(4) * self.p0**2
        Rm = np.diag(np.square(self.r))
        out = np.empty((n, 4))
        t0 = truth.t[0]
        for k in range(n):
            q = self.q_final + (self.q - self.q_final) * np.exp(-(truth.t[k] - t0) / self.q_tau)
            P = P + np.eye(4) * q**2  # prediction: random walk
            y = truth.y_meas[k]
            fz = v7.normal_loads(y[0], y[1], self.vehicle)  # loads from the measured accelerations
            h, H = self.jacobian(mu, truth.state[k], truth.delta[k], truth.camber, fz)
            S = H @ P @ H.T + Rm
            K = np.linalg.solve(S, H @ P).T  # P H^T S^-1 (S and P symmetric)
            step = K @ (y - h)
            if self.max_step is not None:
                step = np.clip(step, -self.max_step, self.max_step)
            mu = np.clip(mu + step, *self.bounds)
            P = (np.eye(4) - K @ H) @ P
            P = 0.5 * (P + P.T)
            out[k] = mu
        return out


def convergence_time(t, estimates, final, tol: float) -> float:
    """First time after which every estimate stays within ``tol`` of its final value [s]."""
    bad = np.any(np.abs(estimates - final) > tol, axis=1)
    if not bad.any():
        return float(t[0])
    last = int(np.flatnonzero(bad)[-1])
    return float(t[min(last + 1, t.size - 1)])


@dataclass
class AdhesionResult:
    """Estimates of one model on one run.

    ``estimates`` are the mean estimates over the last ``final_window`` s,
    ``relative_error_pct`` = 100 (estimate - mu) / mu per wheel, ``converged_s``
    the time after which all four stay within ``tol`` (2 % of mu) of their final value.
    """

    model: str
    t: np.ndarray
    history: np.ndarray
    road_mu: float
    camber: float
    estimates: np.ndarray
    relative_error_pct: np.ndarray
    converged_s: float

    @property
    def max_abs_error_pct(self) -> float:
        return float(np.max(np.abs(self.relative_error_pct)))

    def as_dict(self) -> dict:
        return {"model": self.model, "estimates": [float(x) for x in self.estimates],
                "relative_error_pct": [float(x) for x in self.relative_error_pct],
                "converged_s": float(self.converged_s)}

    def plot(self, ax=None, title: str | None = None):
        """Estimates against time with the true mu (the paper's Fig. 14-16); returns the Axes."""
        from matplotlib.figure import Figure

        if ax is None:
            ax = Figure().subplots()
        for i, w in enumerate(v7.WHEELS):
            ax.plot(self.t, self.history[:, i], label=f"mu {w}")
        ax.axhline(self.road_mu, color="k", ls="--", lw=1, label=f"road mu = {self.road_mu:g}")
        ax.axvline(self.converged_s, color="0.5", ls=":", lw=1)
        ax.set_xlabel("time [s]")
        ax.set_ylabel("estimated adhesion coefficient [-]")
        ax.set_title(title or f"{self.model}, camber {np.rad2deg(self.camber):g} deg")
        ax.legend(fontsize=8, ncol=2)
        return ax


def estimate(truth: TruthRun, tyre: TyreModel, *, final_window: float = 0.3, tol_rel: float = 0.02,
             **ekf_options) -> AdhesionResult:
    """Run the EKF with ``tyre`` on a recorded truth and summarise it."""
    ekf = AdhesionEKF(tyre, truth.vehicle, r=truth.noise, **ekf_options)
    hist = ekf.run(truth)
    last = truth.t >= truth.t[-1] - final_window
    final = hist[last].mean(axis=0)
    err = 100.0 * (final - truth.mu) / truth.mu
    tc = convergence_time(truth.t, hist, final, tol_rel * truth.mu)
    return AdhesionResult(tyre.label, truth.t, hist, truth.mu, float(truth.camber[0]), final, err, tc)


def run_experiment(road_mu: float = 0.8, camber_deg: float = 0.0, *, params: bm.BrushParams = bm.DEFAULT_PARAMS,
                   manoeuvre: Manoeuvre = Manoeuvre(), seed: int = 1, truth_n: int = 8, estimator_n: int = 6,
                   models=("improved", "original")) -> tuple[TruthRun, dict[str, AdhesionResult]]:
    """The experiment of Zhang et al. (2024) on one road and camber: truth, then the EKF with each model.

    Returns the truth and ``{"improved": AdhesionResult, "original": AdhesionResult}``.
    """
    truth = simulate_truth(road_mu, np.deg2rad(camber_deg), tyre=improved_tyre(params, truth_n),
                           manoeuvre=manoeuvre, seed=seed)
    tyres = {"improved": improved_tyre(params, estimator_n), "original": original_tyre(params, truth_n)}
    return truth, {m: estimate(truth, tyres[m]) for m in models}
