"""Longitudinal slippage characteristics of a wheel (Ghasemi et al. 2021).

Ghasemi, Vantsevich, Gorsich, Goryca, Singh, Moradi, *Physics based
single-wheel module slippage assessment for autonomous control design*
(GVSETS 2021).  Pure, vectorised functions, SI units:

* friction-slip law ``mu = mu_p (1 - exp(-k s))`` (Eq. 8) and its curvature
  ``nu = -k^2 mu_p exp(-k s)`` (Eq. 15);
* the characteristic slip ``s_c = ln(k^2 mu_p / -nu_c) / k`` where the
  curvature reaches ``nu_c`` (Eq. 16; ``nu_c = -2`` by default, the value of the
  paper's Fig. 5) and the characteristic friction ``mu_c = mu_p + nu_c / k^2``
  (Eq. 17): beyond s_c the curve is quasi-linear and the wheel is about to
  lose mobility, so s_c is a slip limit for traction control;
* slip (Eq. 7), slip rate (Eq. 9), its critical-condition forms (Eq. 11-14);
* rolling radius and wheel torque: ``r = r0 - lambda_w T`` (Eq. 19), the
  longitudinal elasticity factor ``lambda_w = (r0 - r)/T = r0 s / T``
  (Eq. 20) and its rate (Eq. 21); the slip-tracking torque rate (Eq. 22-23);
* wheel mobility index (Eq. 24), its modified form (Eq. 25) and the
  mobility-agility indices (Eq. 26-27).

Slip s here is the paper's slippage ``s = 1 - v_x / (r0 omega)`` (positive in
traction); for the small slips of a tyre test it is close to the slip ratio
of DESIGN (``kappa = r0 omega / v_x - 1 = s / (1 - s)``).  Friction laws apply to
``|s|`` with the sign of s (braking is the mirror image of traction).
"""

from __future__ import annotations

import numpy as np

__all__ = [
    "NU_C",
    "friction",
    "friction_slope",
    "curvature",
    "characteristic_slip",
    "characteristic_mu",
    "slippage",
    "slip_rate",
    "critical_slip_rate",
    "critical_slip",
    "rolling_radius",
    "elasticity_factor",
    "elasticity_factor_rate",
    "slip_tracking_torque_rate",
    "mobility_index",
    "modified_mobility_index",
    "mobility_agility_index",
    "modified_mobility_agility_index",
]

#: default characteristic curvature (Ghasemi et al. 2021, Fig. 5)
NU_C = -2.0


def friction(s, mu_peak, k):
    """Friction coefficient ``mu = mu_p (1 - exp(-k |s|)) sign(s)`` (Ghasemi et al., Eq. 8).

    Parameters
    ----------
    s : array_like
        Slippage [-].
    mu_peak : array_like
        Peak (asymptotic) friction coefficient mu_p [-].
    k : array_like
        Slip stiffness factor [-] (the initial slope is mu_p k).
    """
    s = np.asarray(s, float)
    return np.sign(s) * mu_peak * (1.0 - np.exp(-k * np.abs(s)))  # Ghasemi et al., Eq. 8


def friction_slope(s, mu_peak, k):
    """d mu / d s = mu_p k exp(-k |s|) [-] (derivative of Eq. 8)."""
    return mu_peak * k * np.exp(-k * np.abs(np.asarray(s, float)))


def curvature(s, mu_peak, k):
    """Curvature ``nu = d^2 mu / d s^2 = -k^2 mu_p exp(-k s)`` for s >= 0 (Ghasemi et al., Eq. 15)."""
    s = np.asarray(s, float)
    return -np.sign(s + (s == 0)) * k**2 * mu_peak * np.exp(-k * np.abs(s))  # Eq. 15 (odd extension)


def characteristic_slip(mu_peak, k, nu_c: float = NU_C):
    """Characteristic slip s_c [-] (Ghasemi et al., Eq. 16): where the curvature reaches ``nu_c``.

    ``s_c = ln(k^2 mu_p / -nu_c) / k``.  Beyond s_c the friction-slip curve is
    quasi-linear and more slip buys little traction; use it as the slip
    limit of a traction or braking controller.  Where ``k^2 mu_p <= -nu_c``
    the curve is already that flat at s = 0 and s_c = 0.

    Parameters
    ----------
    mu_peak : array_like
        Peak friction coefficient [-].
    k : array_like
        Slip stiffness factor [-].
    nu_c : float
        Characteristic curvature [-], negative (default -2).
    """
    if np.any(np.asarray(nu_c) >= 0):
        raise ValueError(f"characteristic curvature nu_c must be negative, got {nu_c}")
    k = np.asarray(k, float)
    sc = np.log(k**2 * np.asarray(mu_peak, float) / -nu_c) / k  # Ghasemi et al., Eq. 16
    return np.maximum(sc, 0.0)


def characteristic_mu(mu_peak, k, nu_c: float = NU_C):
    """Characteristic friction mu_c = mu(s_c) [-] (Ghasemi et al., Eq. 17: ``mu_p + nu_c / k^2``).

    The largest friction the wheel should use before it loses mobility.
    Equals Eq. 17 wherever s_c > 0 (and 0 where s_c = 0).
    """
    return friction(characteristic_slip(mu_peak, k, nu_c), mu_peak, k)


def slippage(vx, omega, r0):
    """Slippage ``s = 1 - v_x / (r0 omega)`` [-] (Ghasemi et al., Eq. 7); v_x [m/s], omega [rad/s], r0 [m]."""
    return 1.0 - np.asarray(vx, float) / (np.asarray(r0, float) * np.asarray(omega, float))


def slip_rate(omega, omega_dot, vx, vx_dot, r0):
    """Slip rate ``ds/dt = (omega_dot v_x - omega v_x_dot) / (r0 omega^2)`` [1/s] (Eq. 9)."""
    omega = np.asarray(omega, float)
    return (omega_dot * vx - omega * vx_dot) / (r0 * omega**2)  # Ghasemi et al., Eq. 9


def critical_slip_rate(omega, omega_dot, vx, r0):
    """Slip rate at the critical condition (quasi-steady v_x): ``omega_dot v_x / (r0 omega^2)`` (Eq. 11)."""
    omega = np.asarray(omega, float)
    return omega_dot * vx / (r0 * omega**2)  # Ghasemi et al., Eq. 11


def critical_slip(omega, vx, r0):
    """Slip at the critical condition, ``s = 1 - kappa / omega`` with ``kappa = v_x / r0`` (Eq. 13-14).

    Shows that near the traction limit the wheel speed runs away with
    growing slip: omega = kappa / (1 - s).
    """
    kappa = np.asarray(vx, float) / r0  # Ghasemi et al., Eq. 13
    return 1.0 - kappa / np.asarray(omega, float)  # Ghasemi et al., Eq. 14


def rolling_radius(torque, r0, lambda_w):
    """Instantaneous rolling radius ``r = r0 - lambda_w T`` [m] (Ghasemi et al., Eq. 19).

    ``torque`` [N m], ``r0`` free-rolling radius [m], ``lambda_w``
    longitudinal elasticity factor [m/(N m)] (may itself depend on T, Eq. 18).
    """
    return r0 - lambda_w * np.asarray(torque, float)  # Ghasemi et al., Eq. 19


def elasticity_factor(r0, radius=None, torque=None, slip=None):
    """Longitudinal elasticity factor lambda_w [m/(N m)] (Ghasemi et al., Eq. 20).

    ``lambda_w = (r0 - r) / T``, or ``r0 s / T`` when the slip is given
    instead of the radius.  Undefined (NaN) at zero torque.
    """
    torque = np.asarray(torque, float)
    num = (r0 - np.asarray(radius, float)) if slip is None else r0 * np.asarray(slip, float)
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(torque != 0, num / np.where(torque != 0, torque, 1.0), np.nan)  # Eq. 20


def elasticity_factor_rate(r0, slip_rate_, lambda_w, torque, torque_rate):
    """d lambda_w / dt from ``r0 s_dot = lambda_w T_dot + T lambda_w_dot`` (Ghasemi et al., Eq. 21)."""
    torque = np.asarray(torque, float)
    return (r0 * slip_rate_ - lambda_w * torque_rate) / torque  # Eq. 21


def slip_tracking_torque_rate(r0, lambda_w, lambda_w_rate, torque, s_ref, s_ref_rate, gain):
    """Wheel-torque rate that makes the slip error decay as ``e_dot + K e = 0`` (Eq. 22-23).

    ``T_dot = (-lambda_w_dot T - K lambda_w T + r0 (s_ref_dot + K s_ref)) / lambda_w``.
    """
    return (-lambda_w_rate * torque - gain * lambda_w * torque
            + r0 * (s_ref_rate + gain * s_ref)) / lambda_w  # Ghasemi et al., Eq. 23


def mobility_index(mu, mu_peak):
    """Wheel mobility index ``1 - mu / mu_p`` [-] (Ghasemi et al., Eq. 24): 0 at the peak, 1 at rest."""
    return 1.0 - np.asarray(mu, float) / mu_peak  # Eq. 24


def modified_mobility_index(s, mu_peak, k, nu_c: float = NU_C):
    """Modified wheel mobility index (Ghasemi et al., Eq. 25).

    ``1 - mu(s) / mu_c`` for ``|s| <= s_c``, 0 beyond: mobility is used up at
    the characteristic slip, not at the peak.
    """
    s = np.abs(np.asarray(s, float))
    sc = characteristic_slip(mu_peak, k, nu_c)
    muc = characteristic_mu(mu_peak, k, nu_c)
    mu = friction(s, mu_peak, k)
    with np.errstate(divide="ignore", invalid="ignore"):
        val = 1.0 - mu / muc
    return np.where(s <= sc, val, 0.0)  # Eq. 25


def mobility_agility_index(s, mu_peak, k):
    """Wheel mobility-agility index ``mu (1 - mu / mu_p)`` [-] (Ghasemi et al., Eq. 26).

    Largest (mu_p / 4) where mu = mu_p / 2: enough traction with mobility in reserve.
    """
    mu = friction(np.abs(np.asarray(s, float)), mu_peak, k)
    return mu * (1.0 - mu / mu_peak)  # Eq. 26


def modified_mobility_agility_index(s, mu_peak, k, nu_c: float = NU_C):
    """Modified wheel mobility-agility index (Ghasemi et al., Eq. 27): ``mu (1 - mu/mu_c)`` for |s| <= s_c, else 0."""
    s = np.abs(np.asarray(s, float))
    mu = friction(s, mu_peak, k)
    return mu * modified_mobility_index(s, mu_peak, k, nu_c)  # Eq. 27
