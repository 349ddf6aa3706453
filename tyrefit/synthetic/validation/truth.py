"""Truth tyres for the diagnose validation, written independently of the effect catalogue.

**Synthetic.**  Nothing here is a measurement, and nothing here calls
:mod:`tyrefit.effects` or :mod:`tyrefit.models.pac89`: the curve and every law
below are written afresh, in forms the diagnose catalogue does *not* contain,
so that a diagnosis scored on these data cannot win by refitting the very
function that generated them (the cases of
:mod:`tyrefit.synthetic.hidden` take their truths from the catalogue's own
``effects.lateral_force``, and their base is exactly the start model).

The tyre
--------
A passenger-car tyre of about 205/55 R16 (load index 91: rated load 615 kg =
6031 N, rounded to :data:`RATED_LOAD` = 6000 N), on dry asphalt, 220 kPa.

Base curve: an exponential saturation of the *normalised slip*
(the brush-model idea that the force depends on slip through
``phi = K_alpha tan(alpha) / (mu Fz)``; Pacejka, *Tire and Vehicle Dynamics*,
3rd ed., Sec. 3.2.2, theoretical slip and its saturation at ``mu Fz``), with
a sliding fall-off after the peak, as rubber friction falls from its static
to its sliding value::

    Fy = -sgn(alpha) mu Fz [1 - exp(-|phi| - q phi^2)] [1 - d phi^2 / (phi_d^2 + phi^2)]
         with phi = K_alpha tan(alpha) / (mu Fz)

The first bracket has slope 1 at phi = 0 (so dFy/dalpha = -K_alpha at zero
slip) and tends to 1; the second tends to 1 - d (sliding / peak friction).
This is *not* the Magic Formula: the start model (PAC89,
``D sin(C atan(B x - E (B x - atan B x)))``) can only approximate it; how
closely is measured by :func:`tyrefit.synthetic.validation.runner.base_fit`
and reported with the rates (a null whose base the start model cannot
represent would not be a null).

Cornering stiffness (a tanh saturation in load, not PAC89's
``a3 sin(2 atan(Fz / a4))``)::

    K_alpha = K_max tanh(Fz / F_k),   K_max = 140 kN/rad, F_k = 9 kN

gives 31, 58, 99 kN/rad at 2, 4, 8 kN: a cornering-stiffness coefficient of
15 -> 12 /rad, typical of passenger tyres (205/55R16 tyres are around
60-80 kN/rad at 4 kN).  Friction mu = 1.0 (dry asphalt), q = 0.5, d = 0.10,
phi_d = 2.5.

These base values were chosen, among realistic ones, so that the start model
can follow the null tyre closely (measured with
:func:`~tyrefit.synthetic.validation.runner.base_fit`: the best start-model
fit of the noise-free null leaves 4.9 N RMS = 0.12 sigma on every layout,
about 0.1 % of the peak force, against 1.1-6.1 sigma for the effects).  An exponential
stiffness saturation ``K_max (1 - exp(-Fz / F_k))`` was tried first and left
0.58 sigma: a systematic misfit that large is itself detectable structure, so
its "nulls" would not have been nulls.

Effects (each a form outside the catalogue; the catalogue forms it must be told
apart from are in brackets)
------------------------------------------------------------------------------
``load_friction_power``  mu = mu0 (Fz / Fz0)^(-n), n = 0.12 (8 % less grip per doubling of
                         load; degressive friction, [a1: mu linear in Fz, times 1 + q dfz^2 (+ r dfz^3)])
``load_friction_tanh``   mu = mu0 (1 - m tanh((Fz - Fz0) / F_m)), m = 0.15, F_m = 4 kN
``curvature``            the saturation sharpness changes with load: q = q0 (Fz / Fz0)^(-k), k = -1.0
                         (q 0.25 at 2 kN, 1.0 at 8 kN: the curve bends over sooner at high load), the curve rescaled so its
                         peak stays mu Fz times the null's: shape only (the rescaling moves the
                         cornering stiffness by about 1 % over 2-8 kN) [a6: E linear in Fz, + c dfz^2]
``overload``             a smooth knee of grip past the rated load:
                         mu *= 1 - c w ln(1 + exp((Fz - F_r) / w)) / F_r, c = 0.5, w = 480 N
                         (-8 % at 6.8 kN, -16 % at 8 kN; Komana et al., Sec. 4.2, describe grip
                         falling above the rated load) [a hinge, linear past F_r, rounded by a
                         quadratic blend over +-10 % of F_r or a fitted width: not a softplus]
``offsets``              ply steer as a slip-angle offset alpha_ps = 0.15 deg, conicity as a
                         force offset F_c = c_c Fz, c_c = -0.012 (48 N at 4 kN): typical
                         uniformity values (conicity and ply-steer forces of 50-150 N at the
                         test load) [a9-a13 shifts in PAC89's own form]
``camber``               saturating camber thrust that fades as the patch slides:
                         F_gamma = -C_g Fz g_s tanh(gamma / g_s) (1 - (F0 / mu Fz)^2),
                         C_g = 1.0 /rad (about 70 N/deg at 4 kN), g_s = 5 deg [a5, a8, a11;
                         the camber brush model]
``asym_curvature``       the saturation sharpness differs between the slip sides, q (1 + s sgn(phi)), s = 0.5,
                         each side rescaled to the null's peak: shape only, no shift (side differences of
                         3-6 % of the force at 3-8 deg) [MF 6.1 PEY3; diagnose family ``asymmetry``, which
                         must not be named ``offsets``]
``camber_shift``         a slip offset growing with camber, alpha += k gamma, k = 0.05 (0.2 deg at 4 deg of
                         camber) [a8 gamma: the camber family, not ``offsets``]
``pressure``             K_alpha *= (p / p0)^0.35, mu *= (p / p0)^-0.10, p0 = 220 kPa
                         (stiffness rises and grip falls slightly with inflation; MF 6.1 uses
                         polynomials in dp instead) [PPY1/PPY3-style linear terms]

The sign of the curvature law was chosen so that the catalogue *can* name
it: fitted to the noise-free ``load6`` truth, start + ``curvature_load``
leaves 0.32 sigma (start 0.77), the next family 0.75.  With k = +1 (rounder
at high load) no single family explains it (``overload_stiffness`` 0.66,
``curvature_load`` 0.81, start 0.93 sigma): inside a -12..12 deg sweep a
rounder high-load curve is indistinguishable from grip falling with load, so
"right family" would not be a fair score
(:func:`~tyrefit.synthetic.validation.runner.oracle` measures this for every
effect and layout).

Signs are ISO-W: a positive slip angle gives a negative lateral force, and a
positive inclination angle pushes the same way.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace

import numpy as np

__all__ = ["TruthTyre", "EFFECT_FAMILY", "EFFECTS", "RATED_LOAD", "FZ0", "P0", "lateral_force"]

_DEG = np.pi / 180.0

#: rated load of the simulated tyre [N] (load index 91: 615 kg)
RATED_LOAD = 6000.0
#: nominal load [N] (reference of the load laws)
FZ0 = 4000.0
#: reference inflation pressure [Pa]
P0 = 220e3

#: validation effect -> diagnose family it must be reported as
EFFECT_FAMILY: dict[str, str] = {
    "load_friction_power": "load_friction",
    "load_friction_tanh": "load_friction",
    "curvature": "curvature_load",
    "overload": "overload",
    "offsets": "offsets",
    "camber": "camber",
    "pressure": "pressure",
    "asym_curvature": "asymmetry",
    "camber_shift": "camber",
}
EFFECTS = tuple(EFFECT_FAMILY)


@dataclass(frozen=True)
class TruthTyre:
    """Parameters of the truth tyre (SI).  The defaults are the neutral (null) tyre.

    Attributes
    ----------
    mu0 : friction coefficient at ``FZ0`` [-]
    k_max : cornering-stiffness ceiling [N/rad]
    f_k : load scale of the cornering stiffness [N]
    q0 : saturation sharpness at ``FZ0`` [-]
    d : fall from peak to sliding friction [-]
    phi_d : normalised slip at which half of ``d`` is lost [-]
    n_pow : load exponent of friction (``load_friction_power``) [-]
    m_tanh, f_m : depth [-] and load scale [N] of the tanh friction law
    k_curv : load exponent of the sharpness (``curvature``) [-]
    c_over, w_over : depth [-] and width [N] of the overload knee
    alpha_ps : ply-steer slip offset [rad]
    c_con : conicity force per unit load [-]
    c_gamma : camber stiffness per unit load [1/rad]
    g_s : camber saturation angle [rad]
    kp_k, kp_mu : pressure exponents of stiffness and friction [-]
    s_asym : relative change of the saturation sharpness between the slip sides (``asym_curvature``) [-]
    k_gs : slip offset per unit camber (``camber_shift``) [rad/rad]
    rated_load : [N]
    """

    mu0: float = 1.0
    k_max: float = 140e3
    f_k: float = 9000.0
    q0: float = 0.5
    d: float = 0.10
    phi_d: float = 2.5
    n_pow: float = 0.0
    m_tanh: float = 0.0
    f_m: float = 4000.0
    k_curv: float = 0.0
    c_over: float = 0.0
    w_over: float = 480.0
    alpha_ps: float = 0.0
    c_con: float = 0.0
    c_gamma: float = 0.0
    g_s: float = 5.0 * _DEG
    kp_k: float = 0.0
    kp_mu: float = 0.0
    s_asym: float = 0.0
    k_gs: float = 0.0
    rated_load: float = RATED_LOAD
    effects: tuple[str, ...] = field(default=())

    @classmethod
    def with_effects(cls, effects=(), **over) -> "TruthTyre":
        """The null tyre plus ``effects`` (names of :data:`EFFECTS`) at their default sizes."""
        t = cls(**over)
        vals: dict[str, float] = {}
        for e in effects:
            if e not in EFFECT_SIZES:
                raise ValueError(f"unknown validation effect {e!r}; known: {', '.join(EFFECTS)}")
            vals.update(EFFECT_SIZES[e])
        return replace(t, **vals, effects=tuple(effects))

    # --- laws -------------------------------------------------------------------------
    def friction(self, fz, pressure=None):
        """Peak friction coefficient mu(Fz, p) [-] (null: constant ``mu0``)."""
        fz = np.asarray(fz, dtype=float)
        mu = self.mu0 * (fz / FZ0) ** (-self.n_pow)  # power law in load
        mu = mu * (1.0 - self.m_tanh * np.tanh((fz - FZ0) / self.f_m))  # tanh law in load
        if self.c_over:
            x = (fz - self.rated_load) / self.w_over
            soft = self.w_over * np.logaddexp(0.0, x)  # softplus: a smooth knee at the rated load
            mu = mu * (1.0 - self.c_over * soft / self.rated_load)
        if pressure is not None and self.kp_mu:
            mu = mu * (np.asarray(pressure, dtype=float) / P0) ** (-self.kp_mu)
        return mu

    def cornering_stiffness(self, fz, pressure=None):
        """K_alpha(Fz, p) = -dFy/dalpha at zero slip [N/rad]."""
        fz = np.asarray(fz, dtype=float)
        k = self.k_max * np.tanh(fz / self.f_k)  # saturating with load (not PAC89's sin(2 atan))
        if pressure is not None and self.kp_k:
            k = k * (np.asarray(pressure, dtype=float) / P0) ** self.kp_k
        return k

    def sharpness(self, fz):
        """Saturation sharpness q(Fz) [-]."""
        return self.q0 * (np.asarray(fz, dtype=float) / FZ0) ** (-self.k_curv)

    def _shape(self, phi, q):
        """Normalised force |Fy| / (mu Fz) at normalised slip ``phi`` >= 0 and sharpness ``q``."""
        sat = 1.0 - np.exp(-phi - q * phi * phi)
        slide = 1.0 - self.d * phi * phi / (self.phi_d**2 + phi * phi)
        return sat * slide

    def _shape_peak(self, q):
        """Peak of :meth:`_shape` over phi for each sharpness ``q`` (grid search to ~1e-6)."""
        q = np.atleast_1d(np.asarray(q, dtype=float))
        uq, inv = np.unique(np.round(q, 12), return_inverse=True)
        grid = np.linspace(0.0, 12.0, 2401)
        peaks = np.array([np.max(self._shape(grid, x)) for x in uq])
        return peaks[inv.ravel()].reshape(q.shape)

    def lateral_force(self, fz, slip_angle, camber=0.0, pressure=None):
        """Lateral force Fy [N], ISO-W, of this truth tyre.

        Parameters
        ----------
        fz : array_like
            Vertical load [N] (> 0).
        slip_angle : array_like
            Slip angle [rad].
        camber : array_like
            Inclination angle [rad].
        pressure : array_like, optional
            Inflation pressure [Pa].
        """
        fz = np.asarray(fz, dtype=float)
        a = np.asarray(slip_angle, dtype=float) + self.alpha_ps  # ply steer: a slip-angle offset
        if self.k_gs:
            a = a + self.k_gs * np.asarray(camber, dtype=float)  # a shift that grows with camber
        mu = self.friction(fz, pressure)
        k = self.cornering_stiffness(fz, pressure)
        peak = mu * fz
        phi = k * np.tan(a) / peak  # normalised (theoretical) slip, Pacejka Sec. 3.2.2
        q = self.sharpness(fz)
        if self.s_asym:
            # the curve saturates sooner on the positive slip side than on the negative: shape only, the peak
            # of each side stays mu Fz times the null's (rescaled as for ``curvature``)
            q = q * (1.0 + self.s_asym * np.sign(phi))
        f0 = -np.sign(phi) * peak * self._shape(np.abs(phi), q)
        if self.s_asym:
            f0 = f0 * (self._shape_peak(np.full(1, self.q0))[0] / self._shape_peak(q))
        if self.k_curv:
            # curvature only: the peak stays at the null tyre's, the shape around it changes with load
            f0 = f0 * (self._shape_peak(np.full(1, self.q0))[0] / self._shape_peak(q))
        fy = f0 - self.c_con * fz  # conicity: a force offset growing with load
        if self.c_gamma:
            g = np.asarray(camber, dtype=float)
            fade = np.clip(1.0 - (f0 / peak) ** 2, 0.0, 1.0)  # camber thrust fades as the patch slides
            fy = fy - self.c_gamma * fz * self.g_s * np.tanh(g / self.g_s) * fade
        return fy


#: effect -> parameter values (typical passenger-tyre sizes, see the module docstring)
EFFECT_SIZES: dict[str, dict[str, float]] = {
    "load_friction_power": {"n_pow": 0.12},
    "load_friction_tanh": {"m_tanh": 0.15},
    "curvature": {"k_curv": -1.0},
    "overload": {"c_over": 0.5},
    "offsets": {"alpha_ps": 0.15 * _DEG, "c_con": -0.012},
    "camber": {"c_gamma": 1.0},
    "pressure": {"kp_k": 0.35, "kp_mu": 0.10},
    "asym_curvature": {"s_asym": 0.5},
    "camber_shift": {"k_gs": 0.05},
}


def lateral_force(effects, fz, slip_angle, camber=0.0, pressure=None, **over):
    """Fy [N] of the null tyre plus ``effects`` at their default sizes (see :class:`TruthTyre`)."""
    return TruthTyre.with_effects(effects, **over).lateral_force(fz, slip_angle, camber, pressure)
