"""Brush tyre models: the original camber brush and the width-aware 2N-strip model.

Two models of Zhang, Zhu, Zhou, Chen and Liu (*Estimation of road adhesion coefficient
based on camber brush model*, World Electr. Veh. J. 15 (2024) 263):

* the **original camber brush model** (:func:`brush_forces`): one brush the
  width of the tread, a contact half-length ``a`` and an effective radius
  ``R_e`` from the mean line load, a length-direction pressure distribution
  with concavity factor lambda_x (Eq. 14-16), combined slip (Eq. 26-29) and
  the parabolic camber deflection of the bristles (Eq. 18-22);
* the **improved camber brush model** (:func:`camber_brush_forces`): the
  contact patch narrows with camber (Eq. 1), the pressure across the width
  has a concavity factor lambda_y and a bias factor Delta_y that shifts the
  load to the side the tyre leans to (Eq. 2-10, 24), and the tyre is cut
  into 2N strips across the width, each a brush with its own load, half
  length, effective radius and length-direction pressure distribution
  (Eq. 11-16, 23-30).  With no bias and no camber it is symmetric across
  the width.

All functions are pure and vectorised: SI in and out, ISO-W signs (positive
slip angle -> negative Fy; a positive inclination leans the wheel top to
-y and its camber thrust is negative, as in :mod:`tyrefit.models.pac89`),
NumPy broadcasting over load, slip, camber, pressure and friction; the strips
live on a trailing axis.

Conventions and choices (each stated where it is used)
-------------------------------------------------------
* Bristle deflection and theoretical slip follow Pacejka's brush model:
  sigma_x = (omega R_e - V_x) / (omega R_e), sigma_y = -V_y / (omega R_e)
  (Zhang et al. 2024, Eq. 26), F = K sigma in the linear range with K = 2 a^2 k.
* Zhang et al. write the power laws with raw coefficients (``a1 Q^a2 / P^a3``);
  here every power law is normalised at a reference point, e.g.
  ``a = a_ref (q / q_ref)^a2 (p / p_ref)^-a3`` (the same law; the paper's
  ``a1`` is ``a_ref q_ref^-a2 p_ref^a3``), and the linear laws of lambda use
  ``dfz = fz / fz_ref - 1`` and ``dp = p / p_ref - 1`` (the paper's
  ``q_y3`` is ``q_y3 - q_y1 - q_y2`` here), which keeps fitted values O(1).
* Strip half-length and effective radius are functions of the strip's line
  load q [N/m] (Eq. 11), not of its load (Eq. 25, 27): with the load, every
  strip would shrink to nothing as N grows; with the line load the model
  converges as N grows (tested).
* Strip loads integrate the width distribution exactly over each strip
  (Eq. 23 is its midpoint rule), so they sum to Fz for every N.
* Eq. 22/29 print the camber term of the adhesion zone as
  ``(2 - 3 u_c + u_c^2)/4``; integrating Eq. 19 gives ``(2 - 3 u_c + u_c^3)/4``
  (which is 1 at u_c = -1, as the linear limit Eq. 20 needs); the cube is used.
* The slip point solves Eq. 21 with the camber deflection included (Eq. 18),
  with the combined-slip vector of Eq. 26; the sliding zone pushes along the
  bristle deflection at the slip point (Eq. 29 uses phi_x / phi, and the
  same for y, which the paper's Fy line drops).
* The bias factor gives the pressure centroid at y = -Delta_y (derived from
  Eq. 6-8: the first moment of eta_y is -Delta_y/b); positive inclination
  (top to -y) gives Delta_y > 0 (Eq. 24), so the load moves to -y, the side
  the tyre leans to.
* Physical ranges: |B_y| <= 1 (otherwise Eq. 6 gives negative pressure at the
  light shoulder: the patch lifts there) and -0.2 < lambda_x < 3 (where
  eta_x(u)/(1-u) is monotonic and the slip point is unique); the model clips
  B_y and lambda_x to these ranges and :meth:`BrushParams.check` says so.

References
----------
Zhang, Zhu, Zhou, Chen, Liu (2024), World Electr. Veh. J. 15, 263 (Eq. numbers above).
Pacejka, *Tire and Vehicle Dynamics*, 3rd ed., ch. 3 (brush model, Fiala's
parabolic-pressure limit used in the tests).
"""

from __future__ import annotations

from dataclasses import asdict, dataclass, fields, replace
from typing import NamedTuple

import numpy as np

__all__ = [
    "BrushParams",
    "DEFAULT_PARAMS",
    "StripState",
    "BrushForces",
    "contact_half_width",
    "width_concavity",
    "width_bias",
    "width_pressure_shape",
    "length_pressure_shape",
    "length_pressure_moment",
    "length_concavity",
    "half_length",
    "effective_radius",
    "strip_states",
    "original_state",
    "slip_point",
    "brush_kernel",
    "kinematic_slip",
    "brush_forces",
    "camber_brush_forces",
    "camber_brush_lateral_force",
    "camber_stiffness",
    "cornering_stiffness",
    "free_rolling_radius",
    "contact_length",
    "LAMBDA_X_RANGE",
]

#: lambda_x range where the slip point of a brush is unique (see module notes)
LAMBDA_X_RANGE = (-0.199, 2.999)
_TINY = 1e-12
#: points of the scan that brackets the slip point
_SCAN = 33


@dataclass(frozen=True)
class BrushParams:
    """Parameters of the camber brush models (SI; the notation of Zhang et al. 2024).

    The defaults describe a plausible 205/55R16 passenger tyre at its rated
    load 4821 N and 240 kPa (Zhang et al. 2024, §2.2) -- they are *illustrative values
    chosen by tyrefit*, not the paper's (it does not print its fitted
    coefficients).

    Attributes
    ----------
    fz_ref : float
        Reference load [N] of the normalised laws.
    p_ref : float
        Reference inflation pressure [Pa].
    b0 : float
        Contact half-width without camber [m] (Eq. 1).
    b1, b2, b3 : float
        Width loss with camber: ``2b = 2 b0 - b1 (fz/fz_ref)^b2 (p/p_ref)^-b3 |gamma|``,
        b1 [m/rad] (Eq. 1).
    qy1, qy2, qy3 : float
        Width concavity ``lambda_y = qy1 dfz + qy2 dp + qy3`` [-] (Eq. 9, 24).
    qy4, qy5 : float
        Width bias ``Delta_y = sign(gamma) qy4 |gamma|^qy5`` [m], gamma in rad
        (Eq. 10, 24; the paper's q_y7, q_y8).
    a_ref : float
        Contact half-length [m] at the reference line load ``q_ref = fz_ref / (2 b0)``
        and pressure (Eq. 11, 27).
    a2, a3 : float
        Exponents of the half-length on line load and pressure (Eq. 11).
    qx1, qx2, qx3 : float
        Length concavity ``lambda_x = qx1 (q/q_ref - 1) + qx2 dp + qx3`` (Eq. 15, 28).
    r_ref : float
        Effective radius [m] at the reference line load and pressure (Eq. 25).
    c2, c3 : float
        ``R_e = r_ref (p/p_ref)^c2 (q/q_ref)^-c3`` (Eq. 25).
    kx, ky : float
        Tread (bristle) stiffness per unit contact area [N/m^3], longitudinal
        and lateral; a strip of width w has ``k = kx w`` per unit length.
    """

    fz_ref: float = 4821.0
    p_ref: float = 240e3
    b0: float = 0.075
    b1: float = 0.15
    b2: float = -0.5
    b3: float = -0.3
    qy1: float = 0.8
    qy2: float = -0.6
    qy3: float = 0.6
    qy4: float = 0.10
    qy5: float = 1.0
    a_ref: float = 0.070
    a2: float = 0.7
    a3: float = 0.5
    qx1: float = 0.5
    qx2: float = -0.3
    qx3: float = 0.3
    r_ref: float = 0.305
    c2: float = 0.01
    c3: float = 0.02
    kx: float = 5.5e7
    ky: float = 4.0e7

    @property
    def q_ref(self) -> float:
        """Reference line load [N/m]: the rated load spread over the unloaded width."""
        return self.fz_ref / (2.0 * self.b0)

    def replace(self, **changes) -> "BrushParams":
        """A copy with some values changed."""
        return replace(self, **changes)

    def as_dict(self) -> dict[str, float]:
        return asdict(self)

    @classmethod
    def names(cls) -> tuple[str, ...]:
        return tuple(f.name for f in fields(cls))

    def check(self, fz, pressure, camber) -> list[str]:
        """Problems of these parameters over the given conditions (empty if none).

        Checks that the contact width stays positive, that |B_y| <= 1 (no
        negative pressure across the width), that lambda_y >= -1 and that
        lambda_x stays in :data:`LAMBDA_X_RANGE`.
        """
        fz, pressure, camber = np.broadcast_arrays(*(np.asarray(x, float) for x in (fz, pressure, camber)))
        out = []
        b = contact_half_width(self, fz, pressure, camber)
        if np.any(b <= 0):
            out.append(f"contact width <= 0 (min {2 * b.min() * 1e3:.1f} mm): b1 too large for the camber range")
        lam_y = width_concavity(self, fz, pressure)
        if np.any(lam_y < -1):
            out.append(f"lambda_y = {lam_y.min():.3g} < -1 gives negative pressure at mid-width")
        with np.errstate(divide="ignore", invalid="ignore"):
            B = _bias_coefficient(lam_y, width_bias(self, camber), b)
        if np.any(np.abs(B) > 1):
            out.append(f"|B_y| = {np.nanmax(np.abs(B)):.3g} > 1: the light shoulder would carry negative pressure "
                       "(clipped to 1)")
        _, _, _, qload, _ = _strip_geometry(self, fz, pressure, camber, 8)
        lam_x = length_concavity(self, qload, pressure[..., None])
        if np.any(lam_x < LAMBDA_X_RANGE[0]) or np.any(lam_x > LAMBDA_X_RANGE[1]):
            out.append(f"lambda_x in [{lam_x.min():.3g}, {lam_x.max():.3g}] leaves {LAMBDA_X_RANGE} (clipped)")
        return out


DEFAULT_PARAMS = BrushParams()


# --- geometry and pressure (Eq. 1-16) --------------------------------------------------
def contact_half_width(p: BrushParams, fz, pressure, camber):
    """Contact half-width b [m] (Zhang et al. 2024, Eq. 1).

    ``2b = 2 b0 - b1 (fz/fz_ref)^b2 (p/p_ref)^-b3 |gamma|``; the width narrows as the
    tyre leans, whichever way.
    """
    fz = np.asarray(fz, float)
    shrink = p.b1 * (fz / p.fz_ref) ** p.b2 * (np.asarray(pressure, float) / p.p_ref) ** (-p.b3)
    return p.b0 - 0.5 * shrink * np.abs(camber)  # Zhang et al., Eq. 1


def width_concavity(p: BrushParams, fz, pressure):
    """Width-direction concavity factor lambda_y [-] (Eq. 9, 24): grows with load, falls with pressure."""
    dfz = np.asarray(fz, float) / p.fz_ref - 1.0
    dp = np.asarray(pressure, float) / p.p_ref - 1.0
    return p.qy1 * dfz + p.qy2 * dp + p.qy3  # Zhang et al., Eq. 9 / 24


def width_bias(p: BrushParams, camber):
    """Width-direction bias factor Delta_y [m] (Eq. 10, 24): the pressure centroid lies at y = -Delta_y."""
    g = np.asarray(camber, float)
    return np.sign(g) * p.qy4 * np.abs(g) ** p.qy5  # Zhang et al., Eq. 24


def _bias_coefficient(lam_y, delta_y, b):
    """B_y of Eq. 8 (unclipped)."""
    return 7.0 * (5.0 + lam_y) / (7.0 + 3.0 * lam_y) * delta_y / b  # Zhang et al., Eq. 8


def width_pressure_shape(v, lambda_y, bias_b=0.0):
    """Width-direction pressure shape eta_y(v) [-] (Eq. 6-7), mean 1 over v in [-1, 1].

    Parameters
    ----------
    v : array_like
        Relative width coordinate y/b [-] (Eq. 4).
    lambda_y : array_like
        Concavity factor [-].
    bias_b : array_like
        B_y of Eq. 8 [-] (clipped to [-1, 1]).
    """
    v = np.asarray(v, float)
    A = 15.0 / (2.0 * (5.0 + lambda_y))  # Zhang et al., Eq. 7
    B = np.clip(bias_b, -1.0, 1.0)
    return A * (1 - v**2) * (1 + lambda_y * v**2) * (1 - B * v)  # Zhang et al., Eq. 6


def _width_shape_integral(v, lam, B):
    """Antiderivative of eta_y (Eq. 6) in v, zero at v = 0."""
    A = 15.0 / (2.0 * (5.0 + lam))
    return A * (v + (lam - 1) * v**3 / 3 - lam * v**5 / 5
                - B * (v**2 / 2 + (lam - 1) * v**4 / 4 - lam * v**6 / 6))


def length_pressure_shape(u, lambda_x):
    """Length-direction pressure shape eta_x(u) [-] (Eq. 14, 16), integral 2 over u in [-1, 1]."""
    u = np.asarray(u, float)
    A = 15.0 / (2.0 * (5.0 + lambda_x))  # Zhang et al., Eq. 16
    return A * (1 - u**2) * (1 + lambda_x * u**2)  # Zhang et al., Eq. 14


def length_pressure_moment(u, lambda_x):
    """m0(u) = integral of eta_x from -1 to u (Eq. 28; the load share behind u, times 2)."""
    u = np.asarray(u, float)
    A = 15.0 / (2.0 * (5.0 + lambda_x))

    def prim(t):
        return t + (lambda_x - 1) * t**3 / 3 - lambda_x * t**5 / 5

    return A * (prim(u) - prim(-1.0))  # Zhang et al., Eq. 28 (m0)


def length_concavity(p: BrushParams, line_load, pressure):
    """Length-direction concavity factor lambda_x [-] of a strip with line load q [N/m] (Eq. 15, 28)."""
    dq = np.asarray(line_load, float) / p.q_ref - 1.0
    dp = np.asarray(pressure, float) / p.p_ref - 1.0
    return p.qx1 * dq + p.qx2 * dp + p.qx3  # Zhang et al., Eq. 15 / 28


def half_length(p: BrushParams, line_load, pressure):
    """Contact half-length a [m] at line load q [N/m] (Eq. 11, 27): ``a_ref (q/q_ref)^a2 (p/p_ref)^-a3``."""
    q = np.maximum(np.asarray(line_load, float), _TINY)
    return p.a_ref * (q / p.q_ref) ** p.a2 * (np.asarray(pressure, float) / p.p_ref) ** (-p.a3)  # Eq. 11


def effective_radius(p: BrushParams, line_load, pressure):
    """Effective rolling radius R_e [m] at line load q [N/m] (Eq. 25): ``r_ref (p/p_ref)^c2 (q/q_ref)^-c3``."""
    q = np.maximum(np.asarray(line_load, float), _TINY)
    return p.r_ref * (np.asarray(pressure, float) / p.p_ref) ** p.c2 * (q / p.q_ref) ** (-p.c3)  # Eq. 25


# --- strips --------------------------------------------------------------------------
class StripState(NamedTuple):
    """Per-strip quantities (strips on the last axis).

    ``y`` centre [m], ``width`` [m], ``fz`` load [N], ``line_load`` [N/m],
    ``a`` half-length [m], ``re`` effective radius [m], ``lambda_x`` [-],
    ``kx``, ``ky`` bristle stiffness per unit length [N/m^2].
    """

    y: np.ndarray
    width: np.ndarray
    fz: np.ndarray
    line_load: np.ndarray
    a: np.ndarray
    re: np.ndarray
    lambda_x: np.ndarray
    kx: np.ndarray
    ky: np.ndarray


def _strip_geometry(p, fz, pressure, camber, n):
    fz = np.asarray(fz, float)[..., None]
    pressure = np.asarray(pressure, float)[..., None]
    camber = np.asarray(camber, float)[..., None]
    b = contact_half_width(p, fz, pressure, camber)
    lam_y = width_concavity(p, fz, pressure)
    B = np.clip(_bias_coefficient(lam_y, width_bias(p, camber), b), -1.0, 1.0)
    edges = np.linspace(-1.0, 1.0, 2 * n + 1)
    share = 0.5 * np.diff(_width_shape_integral(edges, lam_y, B), axis=-1)  # Eq. 23, integrated exactly
    fz_i = fz * share
    w = b / n
    v_mid = 0.5 * (edges[1:] + edges[:-1])
    q = fz_i / w
    return v_mid * b, w, fz_i, q, b


def strip_states(p: BrushParams, fz, pressure, camber, n: int = 10) -> StripState:
    """The 2N strips of the improved model (Eq. 23-28).

    Parameters
    ----------
    p : BrushParams
    fz : array_like
        Tyre load [N].
    pressure : array_like
        Inflation pressure [Pa].
    camber : array_like
        Inclination angle [rad], ISO-W.
    n : int
        Half the number of strips (2N strips across the width).
    """
    y, w, fz_i, q, _ = _strip_geometry(p, fz, pressure, camber, n)
    pressure = np.asarray(pressure, float)[..., None]
    a = half_length(p, q, pressure)
    re = effective_radius(p, q, pressure)
    lam_x = length_concavity(p, q, pressure)
    w = np.broadcast_to(w, fz_i.shape)
    return StripState(np.broadcast_to(y, fz_i.shape), w, fz_i, q, a, re, lam_x, p.kx * w, p.ky * w)


def original_state(p: BrushParams, fz, pressure) -> StripState:
    """The original camber brush model as a single strip (width 2 b0, uniform across the width).

    Half-length, effective radius and lambda_x come from the mean line load
    ``fz / (2 b0)``; camber changes neither the width nor the loads.
    """
    fz = np.asarray(fz, float)[..., None]
    pressure = np.asarray(pressure, float)[..., None]
    w = 2.0 * p.b0 + 0.0 * fz
    q = fz / w
    return StripState(0.0 * fz, w, fz, q, half_length(p, q, pressure), effective_radius(p, q, pressure),
                      length_concavity(p, q, pressure), p.kx * w, p.ky * w)


# --- the brush kernel (Eq. 17-22, 26-29) ------------------------------------------------
def _h_and_dh(u, A, lam, phx, phy, psi):
    g = A * (1 + u) * (1 + lam * u**2)
    dg = A * (1 + 2 * lam * u + 3 * lam * u**2)
    ey = phy - (1 + u) * psi
    m = np.sqrt(phx**2 + ey**2)
    dm = -psi * ey / np.maximum(m, _TINY)
    return g - m, dg - dm


def slip_point(phi_x, phi_y, psi, lambda_x, iterations: int = 16):
    """Relative slip-point coordinate u_c in [-1, 1] (Eq. 21 with Eq. 18-19, 26, 28).

    The bristle that enters at the leading edge (u = 1) sticks while its
    force per length stays below the friction limit,
    ``|phi - (1+u) psi e_y| < A (1+u)(1+lambda_x u^2)`` (Eq. 21 divided by
    ``mu Fz (1-u) / (2a)``), with ``phi = (Kx sx, Ky sy)/(mu Fz)`` (Eq. 26) and
    ``psi = 3/2 K_ygamma sin(gamma) / (mu Fz)`` the camber deflection (Eq. 19-20).
    u_c is the first point, from the leading edge, where it reaches the limit:
    -1 for pure adhesion, 1 for full sliding.

    Solved by a scan of 33 points for the bracket, then Newton steps kept
    inside the bracket (vectorised; a few iterations reach machine precision
    in the smooth cases).  A rare thin dip of h below zero between two scan
    points (lambda_x near 2 with camber) can be missed.
    """
    phi_x, phi_y, psi, lambda_x = np.broadcast_arrays(*(np.asarray(x, float) for x in (phi_x, phi_y, psi, lambda_x)))
    lam = np.clip(lambda_x, *LAMBDA_X_RANGE)
    A = 15.0 / (2.0 * (5.0 + lam))
    grid = np.linspace(-1.0, 1.0, _SCAN)
    hg, _ = _h_and_dh(grid, A[..., None], lam[..., None], phi_x[..., None], phi_y[..., None], psi[..., None])
    nonpos = hg <= 0.0
    # last grid index with h <= 0 (always >= 0: h(-1) = -|phi| <= 0)
    last = grid.size - 1 - np.argmax(nonpos[..., ::-1], axis=-1)
    full = last == grid.size - 1
    # h = 0 exactly at the bracket's low end: that is the slip point (pure camber: u_c = -1)
    at_lo = np.take_along_axis(hg, last[..., None], axis=-1)[..., 0] == 0.0
    j = np.minimum(last, grid.size - 2)
    lo = grid[j]
    hi = lo + (grid[1] - grid[0])
    hlo = np.take_along_axis(hg, j[..., None], axis=-1)[..., 0]
    hhi = np.take_along_axis(hg, (j + 1)[..., None], axis=-1)[..., 0]
    lo0 = lo
    # safeguarded Newton: h(lo) <= 0 < h(hi); a Newton step that leaves the
    # bracket is replaced by the false-position point of the bracket (which
    # also lands on a root at the bracket's end, where bisection would crawl)
    u = np.where(hhi - hlo > 0, lo - hlo * (hi - lo) / np.where(hhi - hlo > 0, hhi - hlo, 1.0), 0.5 * (lo + hi))
    used_fp = np.zeros(u.shape, bool)
    for _ in range(iterations):
        h, dh = _h_and_dh(u, A, lam, phi_x, phi_y, psi)
        neg = h <= 0.0
        lo = np.where(neg, u, lo)
        hlo = np.where(neg, h, hlo)
        hi = np.where(neg, hi, u)
        hhi = np.where(neg, hhi, h)
        with np.errstate(divide="ignore", invalid="ignore"):
            step = u - h / dh
            fp = lo - hlo * (hi - lo) / (hhi - hlo)
        ok = (dh > 0) & (step >= lo) & (step <= hi)
        okfp = np.isfinite(fp) & (fp >= lo) & (fp <= hi) & ~used_fp
        new = np.where(ok, step, np.where(okfp, fp, 0.5 * (lo + hi)))
        used_fp = ~ok & okfp  # never two false-position steps in a row (they can stall on one side)
        done = np.all(np.abs(new - u) < 1e-14)
        u = new
        if done:
            break
    uc = np.where(at_lo, lo0, u)
    return np.where(full, 1.0, uc)


class BrushForces(NamedTuple):
    """Forces of a brush model [N] (ISO-W), with the per-strip values and slip points."""

    fx: np.ndarray
    fy: np.ndarray
    fx_strips: np.ndarray
    fy_strips: np.ndarray
    slip_point: np.ndarray
    strips: StripState


def brush_kernel(fz, a, re, kx, ky, lambda_x, sigma_x, sigma_y, camber, mu):
    """Forces of one brush (one strip) under combined slip and camber (Eq. 17-22, 26-29).

    Parameters
    ----------
    fz : array_like
        Strip load [N].
    a : array_like
        Contact half-length [m].
    re : array_like
        Effective radius [m] (the camber parabola of Eq. 19).
    kx, ky : array_like
        Bristle stiffness per unit length [N/m^2].
    lambda_x : array_like
        Length-direction concavity factor [-].
    sigma_x, sigma_y : array_like
        Theoretical slips [-] (Eq. 26), signed so that F = K sigma in the linear range.
    camber : array_like
        Inclination [rad], ISO-W.
    mu : array_like
        Friction (road adhesion) coefficient [-].

    Returns
    -------
    fx, fy, u_c : ndarray
        Forces [N] (ISO-W) and the slip point.

    Notes
    -----
    Adhesion zone (u_c < u <= 1) and sliding zone (-1 <= u < u_c), Eq. 22, 29::

        Fx = (1-u_c)^2/4 Kx sx + mu Fz m0(u_c)/2 n_x
        Fy = (1-u_c)^2/4 Ky sy - (2 - 3 u_c + u_c^3)/4 K_yg sin(gamma) + mu Fz m0(u_c)/2 n_y

    with K = 2 a^2 k (Eq. 20), K_yg = 2 a^3 k_y / (3 R_e) (Eq. 20) and n the
    unit direction of the bristle deflection at the slip point.
    """
    fz = np.asarray(fz, float)
    Kx = 2.0 * a**2 * kx
    Ky = 2.0 * a**2 * ky
    Kyg = 2.0 * a**3 * ky / (3.0 * re)  # Zhang et al., Eq. 20
    sg = np.sin(camber)
    mufz = np.maximum(mu * fz, _TINY)
    phx = Kx * sigma_x / mufz  # Zhang et al., Eq. 26
    phy = Ky * sigma_y / mufz
    psi = 1.5 * Kyg * sg / mufz  # camber deflection, Eq. 19 in the units of Eq. 21
    lam = np.clip(lambda_x, *LAMBDA_X_RANGE)
    uc = slip_point(phx, phy, psi, lam)
    ey = phy - (1 + uc) * psi
    norm = np.sqrt(phx**2 + ey**2)
    nx = np.where(norm > _TINY, phx / np.maximum(norm, _TINY), 0.0)
    ny = np.where(norm > _TINY, ey / np.maximum(norm, _TINY), 0.0)
    slide = 0.5 * mu * fz * length_pressure_moment(uc, lam)
    adh = 0.25 * (1 - uc) ** 2
    fx = adh * Kx * sigma_x + slide * nx  # Zhang et al., Eq. 29
    fy = adh * Ky * sigma_y - 0.25 * (2 - 3 * uc + uc**3) * Kyg * sg + slide * ny  # Eq. 22, 29 (u_c^3, see notes)
    return fx, fy, uc


def kinematic_slip(vx, vy, omega, re):
    """Theoretical slips (Eq. 26): ``sx = (omega Re - Vx)/(omega Re)``, ``sy = -Vy/(omega Re)``.

    ``vx``, ``vy`` [m/s] wheel-centre velocity in the wheel frame, ``omega``
    [rad/s], ``re`` [m].  The rolling speed is floored at 1 mm/s (a locked
    wheel slides fully).
    """
    vr = np.maximum(np.asarray(omega, float) * re, 1e-3)
    return (vr - vx) / vr, -np.asarray(vy, float) / vr


def _sum_forces(st: StripState, vx, vy, omega, camber, mu) -> BrushForces:
    vx = np.asarray(vx, float)[..., None]
    vy = np.asarray(vy, float)[..., None]
    omega = np.asarray(omega, float)[..., None]
    sx, sy = kinematic_slip(vx, vy, omega, st.re)
    fx, fy, uc = brush_kernel(st.fz, st.a, st.re, st.kx, st.ky, st.lambda_x, sx, sy,
                              np.asarray(camber, float)[..., None], np.asarray(mu, float)[..., None])
    return BrushForces(fx.sum(-1), fy.sum(-1), fx, fy, uc, st)  # Zhang et al., Eq. 30


def free_rolling_radius(st: StripState):
    """Free-rolling radius [m] of a set of strips: the stiffness-weighted harmonic mean of R_e.

    At this radius the linear longitudinal strip forces sum to zero at zero
    slip (``sum Kx_i (1 - R0/Re_i) = 0``); a rig defines its slip ratio on it.
    """
    Kx = 2.0 * st.a**2 * st.kx
    return Kx.sum(-1) / (Kx / st.re).sum(-1)


def _rig_kinematics(st, slip_ratio, slip_angle):
    """Wheel kinematics for a rig slip ratio and slip angle (V_x = 1 m/s)."""
    r0 = free_rolling_radius(st)
    slip_ratio = np.asarray(slip_ratio, float)
    omega = (1.0 + slip_ratio) / r0
    return np.ones_like(omega), np.tan(slip_angle) + 0.0 * omega, omega


def brush_forces(p: BrushParams, fz, slip_ratio=0.0, slip_angle=0.0, camber=0.0, pressure=None, mu=1.0,
                 *, vx=None, vy=None, omega=None) -> BrushForces:
    """Original camber brush model: Fx, Fy [N] (ISO-W) of the whole tread as one brush.

    Parameters
    ----------
    p : BrushParams
    fz : array_like
        Load [N].
    slip_ratio : array_like
        Longitudinal slip ratio kappa [-] on the free-rolling radius (positive driving).
    slip_angle : array_like
        Slip angle [rad], ISO-W.
    camber : array_like
        Inclination [rad], ISO-W.
    pressure : array_like, optional
        Inflation pressure [Pa]; default ``p.p_ref``.
    mu : array_like
        Road adhesion coefficient [-].
    vx, vy, omega : array_like, optional
        Instead of slip ratio and angle: wheel-centre velocity in the wheel
        frame [m/s] and wheel spin [rad/s] (as in a vehicle model, Eq. 26).
    """
    pressure = p.p_ref if pressure is None else pressure
    fz, slip_ratio, slip_angle, camber, pressure, mu = np.broadcast_arrays(
        *(np.asarray(x, float) for x in (fz, slip_ratio, slip_angle, camber, pressure, mu)))
    st = original_state(p, fz, pressure)
    if omega is None:
        vx, vy, omega = _rig_kinematics(st, slip_ratio, slip_angle)
    return _sum_forces(st, vx, vy, omega, camber, mu)


def camber_brush_forces(p: BrushParams, fz, slip_ratio=0.0, slip_angle=0.0, camber=0.0, pressure=None,
                        mu=1.0, *, n: int = 10, vx=None, vy=None, omega=None) -> BrushForces:
    """Improved camber brush model (2N strips across the width): Fx, Fy [N] (ISO-W).

    Same arguments as :func:`brush_forces`, plus ``n`` (2N strips).  Each
    strip has its own load, half-length, effective radius and length
    pressure distribution (Eq. 23-28) and its own slip (Eq. 26: the strips
    share the wheel spin but not the radius); the forces are summed (Eq. 30).
    A rig slip ratio is taken on the free-rolling radius of the strips
    (:func:`free_rolling_radius`).
    """
    pressure = p.p_ref if pressure is None else pressure
    fz, slip_ratio, slip_angle, camber, pressure, mu = np.broadcast_arrays(
        *(np.asarray(x, float) for x in (fz, slip_ratio, slip_angle, camber, pressure, mu)))
    st = strip_states(p, fz, pressure, camber, n)
    if omega is None:
        vx, vy, omega = _rig_kinematics(st, slip_ratio, slip_angle)
    return _sum_forces(st, vx, vy, omega, camber, mu)


def camber_brush_lateral_force(fz, slip_angle, camber, pressure=None, mu: float = 1.0,
                               params: BrushParams = DEFAULT_PARAMS, n: int = 10):
    """Lateral force Fy [N] (ISO-W) of the improved camber brush model at zero slip ratio.

    The physical explanation of the ``camber`` effect: a leaning tyre bends
    its bristles along a parabola (Eq. 19, camber thrust towards the lean)
    and moves its load to the leaning shoulder (Eq. 1-10, 24), which changes
    the strips' lengths and radii and so the camber stiffness and where the
    patch starts to slide.  Use it to generate Fy(alpha, gamma, Fz) test data.

    Parameters
    ----------
    fz : array_like
        Load [N].
    slip_angle : array_like
        Slip angle [rad], ISO-W.
    camber : array_like
        Inclination [rad], ISO-W.
    pressure : array_like, optional
        Inflation pressure [Pa]; default the parameters' reference.
    mu : float
        Friction coefficient [-].
    params : BrushParams
    n : int
        2N strips.
    """
    return camber_brush_forces(params, fz, 0.0, slip_angle, camber, pressure, mu, n=n).fy


def cornering_stiffness(st: StripState):
    """Sum of the strips' cornering stiffness ``K_y = 2 a^2 k_y`` [N/rad] (Eq. 20)."""
    return (2.0 * st.a**2 * st.ky).sum(-1)


def camber_stiffness(st: StripState):
    """Sum of the strips' camber stiffness ``K_yg = 2 a^3 k_y / (3 R_e)`` [N/rad] (Eq. 20)."""
    return (2.0 * st.a**3 * st.ky / (3.0 * st.re)).sum(-1)


def contact_length(p: BrushParams, fz, pressure, camber, n: int = 10):
    """Contact-patch length [m] of the improved model: twice the longest strip half-length."""
    return 2.0 * strip_states(p, fz, pressure, camber, n).a.max(-1)
