"""Roads in path (curvilinear) coordinates (Pham et al. 2025, Eq. 11-13).

Sign convention (ISO 8855 vehicle axes: x forward, y left, z up)
---------------------------------------------------------------
* ``s`` [m] distance along the centre line;
* ``n`` [m] lateral offset of the centre of gravity, **positive to the left**
  of the centre line;
* ``xi`` [rad] heading error, the vehicle's x axis minus the centre line's
  tangent, **positive counter-clockwise**;
* ``kappa`` [1/m] curvature, **positive for a left turn** (centre of
  curvature on the left).

With these signs Eq. 11-13 read::

    ds/dt  = (v cos xi - u sin xi) / (1 - n kappa)
    dn/dt  = v sin xi + u cos xi
    dxi/dt = r - kappa ds/dt

with v = vx, u = vy and r the yaw rate.  Pham et al. give curvature the
opposite sign (negative for left turns) with the same equations, i.e. its n
is positive to the right; a left turn here is a right turn there, and every
result is mirror-symmetric.

Also here: the UK desirable minimum radius of horizontal curves (DMRB CD 109,
Table 2.10) that sets the curved-path scenario's radius.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import DataError

__all__ = [
    "PathGeometry",
    "straight_path",
    "curve_path",
    "curvilinear_rates",
    "uk_desirable_minimum_radius",
    "DMRB_DESIRABLE_MINIMUM_RADIUS",
]

#: DMRB CD 109 Table 2.10: design speed [km/h] -> desirable minimum radius [m] (e = 5 % superelevation)
DMRB_DESIRABLE_MINIMUM_RADIUS = {50: 180.0, 60: 255.0, 70: 360.0, 85: 510.0, 100: 720.0, 120: 1020.0}


def uk_desirable_minimum_radius(speed_kmh):
    """Desirable minimum radius [m] of a UK road for a design speed [km/h] (DMRB CD 109, Table 2.10).

    Between table speeds the radius is interpolated at constant v^2/R;
    below 50 km/h (outside the table) v^2/R is held at its 50-60 km/h value,
    about 1.07-1.09 m/s^2 (*inferred*; Pham et al.'s 30 km/h curve of about 32 m
    at half the radius matches it).
    """
    v = np.asarray(speed_kmh, dtype=float)
    spd = np.array(sorted(DMRB_DESIRABLE_MINIMUM_RADIUS), float)
    rad = np.array([DMRB_DESIRABLE_MINIMUM_RADIUS[int(k)] for k in spd])
    acc = (spd / 3.6) ** 2 / rad                          # v^2/R of each table row [m/s^2]
    a = np.interp(v, spd, acc, left=acc[1], right=acc[-1])
    return (v / 3.6) ** 2 / a


@dataclass
class PathGeometry:
    """Centre lines made of pieces of constant curvature, one per batch member.

    Attributes
    ----------
    lengths : ndarray, shape (B, K)
        Length of each piece [m].
    curvatures : ndarray, shape (B, K)
        Curvature of each piece [1/m] (positive left).
    """

    lengths: np.ndarray
    curvatures: np.ndarray

    def __post_init__(self) -> None:
        self.lengths = np.atleast_2d(np.asarray(self.lengths, float))
        self.curvatures = np.atleast_2d(np.asarray(self.curvatures, float))
        if self.lengths.shape != self.curvatures.shape:
            raise DataError("path lengths and curvatures differ in shape")
        if np.any(self.lengths <= 0):
            raise DataError("every path piece needs a positive length")
        self.ends = np.cumsum(self.lengths, axis=1)
        self.starts = self.ends - self.lengths
        # heading of the centre line at each piece start (integral of curvature)
        self.theta0 = np.cumsum(self.lengths * self.curvatures, axis=1) - self.lengths * self.curvatures

    @property
    def n_members(self) -> int:
        return self.lengths.shape[0]

    @property
    def total_length(self) -> np.ndarray:
        return self.ends[:, -1]

    def _piece(self, s):
        s = np.asarray(s, float)
        idx = np.sum(s[..., None] >= self.ends, axis=-1)
        return np.minimum(idx, self.lengths.shape[1] - 1)

    def curvature(self, s):
        """Curvature [1/m] at distance ``s`` (shape (B,), one value per member)."""
        i = self._piece(s)
        return self.curvatures[np.arange(self.n_members), i]

    def heading(self, s):
        """Centre-line heading [rad] at ``s`` (shape (B,)), zero at the start."""
        s = np.asarray(s, float)
        i = self._piece(s)
        m = np.arange(self.n_members)
        return self.theta0[m, i] + self.curvatures[m, i] * (s - self.starts[m, i])

    def xy(self, s, n=0.0, member: int = 0):
        """Global (x, y) [m] of the point at distance ``s`` and offset ``n`` for one member (arrays)."""
        s = np.atleast_1d(np.asarray(s, float))
        ss = np.linspace(0.0, max(float(s.max()), 1e-9), max(2000, int(s.max() / 0.25) + 2))

        def heading(q):
            i = np.minimum(np.searchsorted(self.ends[member], q, side="right"), self.lengths.shape[1] - 1)
            return self.theta0[member, i] + self.curvatures[member, i] * (q - self.starts[member, i])

        th = heading(ss)
        mid = heading(0.5 * (ss[1:] + ss[:-1]))                   # exact heading, midpoint rule
        x = np.concatenate([[0.0], np.cumsum(np.cos(mid) * np.diff(ss))])
        y = np.concatenate([[0.0], np.cumsum(np.sin(mid) * np.diff(ss))])
        th_s = np.interp(s, ss, th)
        n = np.broadcast_to(np.asarray(n, float), s.shape)
        return np.interp(s, ss, x) - n * np.sin(th_s), np.interp(s, ss, y) + n * np.cos(th_s)

    def smoothed_curvature(self, s, window, ramp=None):
        """Curvature filtered by two box filters in a row, of widths ``window`` and ``ramp`` [m].

        A curvature step becomes a transition of length window + ramp whose
        rate of change is kappa / window at most and builds up over ``ramp``:
        a driver's line whose lateral jerk v^3 d(kappa)/ds rises gradually to
        its peak instead of jumping.  ``ramp`` defaults to 0.3 ``window``.
        The filter keeps the integral and the first moment of the curvature.
        Both widths may be given per member (shape (B,)).
        """
        s = np.asarray(s, float)
        w1 = np.asarray(window, float)
        w2 = 0.3 * w1 if ramp is None else np.asarray(ramp, float)
        a, b = 0.5 * (w1 + w2), 0.5 * (w1 - w2)
        phi = self._integral2
        return (phi(s + a) - phi(s + b) - phi(s - b) + phi(s - a)) / (w1 * w2)

    def _integral2(self, s):
        """Second integral of curvature from 0 (zero curvature before the start and after the end)."""
        s = np.asarray(s, float)
        m = np.arange(self.n_members)
        if not hasattr(self, "_phi0"):
            th_end = self.theta0 + self.curvatures * self.lengths
            phi_end = np.cumsum(self.theta0 * self.lengths + 0.5 * self.curvatures * self.lengths**2, axis=1)
            self._phi0 = phi_end - (self.theta0 * self.lengths + 0.5 * self.curvatures * self.lengths**2)
            self._theta_end = th_end[:, -1]
            self._phi_end = phi_end[:, -1]
        sc = np.clip(s, 0.0, self.total_length)
        i = self._piece(sc)
        d = sc - self.starts[m, i]
        phi = self._phi0[m, i] + self.theta0[m, i] * d + 0.5 * self.curvatures[m, i] * d**2
        return phi + self._theta_end * np.maximum(s - self.total_length, 0.0)

    def _integral(self, s):
        """Integral of curvature from 0 to s (curvature 0 before the start and after the end)."""
        s = np.asarray(s, float)
        m = np.arange(self.n_members)
        sc = np.clip(s, 0.0, self.total_length)
        i = self._piece(sc)
        return self.theta0[m, i] + self.curvatures[m, i] * (sc - self.starts[m, i])


def straight_path(length, n_members: int = 1) -> PathGeometry:
    """A straight road of ``length`` [m] (scalar or per member)."""
    L = np.broadcast_to(np.asarray(length, float), (n_members,))
    return PathGeometry(L[:, None], np.zeros((n_members, 1)))


def curve_path(straight, radius, angle, n_members: int | None = None) -> PathGeometry:
    """Straight, circular arc (left turn), straight (the curved path of Pham et al. 2025).

    Parameters
    ----------
    straight : float or array
        Length of each straight [m].
    radius : float or array
        Arc radius [m].
    angle : float or array
        Arc angle [rad].
    """
    straight, radius, angle = np.broadcast_arrays(np.atleast_1d(np.asarray(straight, float)),
                                                  np.atleast_1d(np.asarray(radius, float)),
                                                  np.atleast_1d(np.asarray(angle, float)))
    if np.any(radius <= 0):
        raise DataError("curve radius must be positive")
    lengths = np.column_stack([straight, radius * angle, straight])
    curv = np.column_stack([np.zeros_like(radius), 1.0 / radius, np.zeros_like(radius)])
    return PathGeometry(lengths, curv)


def curvilinear_rates(n, xi, vx, vy, yaw_rate, kappa):
    """Time derivatives of (s, n, xi) in path coordinates (Pham et al. 2025, Eq. 11-13).

    Parameters
    ----------
    n : array_like
        Lateral offset [m], positive left.
    xi : array_like
        Heading error [rad], positive counter-clockwise.
    vx, vy : array_like
        Longitudinal and lateral velocity in vehicle axes [m/s].
    yaw_rate : array_like
        [rad/s], positive counter-clockwise.
    kappa : array_like
        Path curvature at s [1/m], positive for a left turn.

    Returns
    -------
    ds, dn, dxi : ndarray
    """
    c, s_ = np.cos(xi), np.sin(xi)
    ds = (vx * c - vy * s_) / (1.0 - n * kappa)          # Eq. 11
    dn = vx * s_ + vy * c                                # Eq. 12
    dxi = yaw_rate - kappa * ds                          # Eq. 13
    return ds, dn, dxi
