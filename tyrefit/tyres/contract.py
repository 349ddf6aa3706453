"""The physical-validity contract of a Magic Formula tyre, over the whole envelope it declares.

A tyre file is a promise to a simulator: Adams, CarMaker or Chrono will
evaluate it anywhere inside the ranges it declares (``FZMIN..FZMAX``,
``KPUMIN..KPUMAX``, ``ALPMIN..ALPMAX``, ``CAMMIN..CAMMAX``,
``PRESMIN..PRESMAX``), not only where the rig measured.  :func:`violations`
checks, on a grid of that envelope, the rules every tyre tyrefit writes must
keep (the fit holds them as constraints, :mod:`tyrefit.fitting.mf`; the writer
refuses a tyre that breaks them):

``E <= 1``
    every curvature factor of the Magic Formula -- pure slip E_x (4.E14, both
    slip signs), E_y (4.E24, both signs), the trail's E_t (4.E44, with the
    atan term at its bound +-1), combined slip E_xa (4.E56) and E_yk (4.E64).
    With E > 1 the curve ``sin(C atan(Bx - E(Bx - atan Bx)))`` folds back
    (the force reverses at large slip); solvers that clip E to 1 and those
    that do not then give different tyres.
``mu > 0`` and, where a ceiling is given, ``mu <= ceiling``
    the peak friction mu_x (4.E13), mu_y (4.E23) at each grid load; the
    ceiling (the fit passes 1.15 x the largest |F|/Fz the data show through
    the peak) keeps a shape that never peaks inside the data from carrying
    a friction the tyre never showed.
``0 <= G <= 1``
    the combined-slip weighting functions G_xa (4.E51) and G_yk (4.E59) over
    the declared slip-angle x slip-ratio range: combined slip may only take
    force away, |Fx(kappa, alpha)| <= |Fx(kappa, 0)| and |Fy(alpha, kappa) -
    SV_yk| <= |Fy(alpha, 0)|.  A shift S_Hxa (RHX1) or S_Hyk (RHY1, RHY2)
    larger than the smallest slip makes G exceed 1 between 0 and twice the
    shift (4.E52, 4.E60: G is normalised at the shift, not at zero slip).
aligning
    the aligning moment turns the wheel back towards the direction of travel
    between 2 and 4 deg of slip angle at every load and pressure of the range
    (camber nearest 0): ``Mz Fy < 0``, a positive pneumatic trail (4.E31-4.E36).

References: Pacejka, *Tire and Vehicle Dynamics*, 3rd ed. (2012), 4.3.2
(4.E1-4.E78); Besselink, Schmeitz, Pacejka, VSD 48 (2010).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from ..models import mf61 as _mf61
from .mf import MFTyre

__all__ = ["Violation", "violations", "check_tyre", "envelope", "slip_grid", "ALIGN_DEG"]

_DEG = math.pi / 180.0
#: tolerance of 0 <= G <= 1: a fit that holds the rule as a penalty ends within 1e-6 of it
G_TOL = 1e-4
#: tolerance of E <= 1: a fit whose curvature ends on its bound carries E = 1 + rounding (solvers clip E to 1)
E_TOL = 1e-3
#: slip angles [deg] at which the aligning moment must align the wheel
ALIGN_DEG = (2.0, 3.0, 4.0)


@dataclass(frozen=True)
class Violation:
    """One broken rule: ``rule`` id, ``channel``, the worst value found, where, and a sentence."""

    rule: str
    channel: str
    worst: float
    where: str
    message: str

    def __str__(self) -> str:
        return self.message


def envelope(params: Mapping, ranges: Mapping | None = None) -> dict[str, tuple[float, float]]:
    """The declared envelope in SI: ``fz``, ``slip_ratio``, ``slip_angle``, ``camber``, ``pressure``.

    ``ranges`` (keys as :meth:`tyrefit.tyres.base.Tyre.validity`) win over the file keys ``FZMIN``
    .. ``PRESMAX`` in ``params``; absent ranges take 0.2-2 FNOMIN, +-1, +-15 deg, 0 and NOMPRES.
    """
    p = {str(k).upper(): v for k, v in params.items()}
    r = dict(ranges or {})
    fn = float(p.get("FNOMIN", 4000.0))

    def pick(name, lo, hi, default):
        if name in r:
            return tuple(map(float, r[name]))
        if lo in p and hi in p:
            return float(p[lo]), float(p[hi])
        return default

    out = {"fz": pick("fz", "FZMIN", "FZMAX", (0.2 * fn, 2.0 * fn)),
           "slip_ratio": pick("slip_ratio", "KPUMIN", "KPUMAX", (-1.0, 1.0)),
           "slip_angle": pick("slip_angle", "ALPMIN", "ALPMAX", (-15 * _DEG, 15 * _DEG)),
           "camber": pick("camber", "CAMMIN", "CAMMAX", (0.0, 0.0))}
    nom = float(p.get("NOMPRES", 0.0) or 0.0)
    out["pressure"] = pick("pressure", "PRESMIN", "PRESMAX", (nom, nom))
    lo, hi = out["fz"]
    out["fz"] = (max(lo, 1e-3 * hi, 1.0), hi)
    return out


def slip_grid(lo: float, hi: float, n: int, small: float) -> np.ndarray:
    """n points over [lo, hi] plus the small slips near zero where shifts act (inside the range only)."""
    pts = np.concatenate([np.linspace(lo, hi, n), small * np.array([-1.0, -0.3, -0.1, 0.1, 0.3, 1.0])])
    return np.unique(pts[(pts >= lo) & (pts <= hi)])


def violations(params: Mapping, ranges: Mapping | None = None, *, version: str | None = None,
               mu_ceiling: Mapping[str, tuple] | None = None, channels=("fx", "fy", "mz"),
               n_fz: int = 9) -> list[Violation]:
    """Rules of the contract (module notes) broken anywhere on a grid of the declared envelope.

    Parameters
    ----------
    params : mapping
        the parameter set (``.tir`` keys, SI), as :func:`tyrefit.models.mf61.forces` takes it.
    ranges : mapping, optional
        the envelope (:func:`envelope`); default the file keys in ``params``.
    version : {'6.1', '5.2'}, optional
        default from FITTYP.
    mu_ceiling : mapping, optional
        ``{'x': ..., 'y': ...}``: the largest peak friction allowed, a function of the load [N] or
        ``(fz, mu_max)`` arrays (interpolated in load, held beyond the ends).
    channels : iterable of str
        the channels the tyre carries (``fx``: Ex, mu_x, G_xa; ``fy``: Ey, mu_y, G_yk; ``mz``:
        Et and aligning).
    n_fz : int
        grid loads over FZMIN..FZMAX.

    Returns
    -------
    list of :class:`Violation` (empty when the tyre keeps the contract).
    """
    p = {str(k).upper(): v for k, v in params.items()}
    env = envelope(p, ranges)
    v = _mf61.resolve_version(p, version)
    c = _mf61.coefficients(p)
    fz = np.linspace(*env["fz"], n_fz)
    cam = np.unique(np.linspace(*env["camber"], 3))
    pr = np.unique(np.linspace(*env["pressure"], 3)) if env["pressure"][1] > 0 else np.array([np.nan])
    F, G, P = (a.ravel() for a in np.meshgrid(fz, cam, pr, indexing="ij"))
    press = None if np.all(np.isnan(P)) else P
    fz0 = float(c["FNOMIN"]) * float(c["LFZO"])
    dfz = (F - fz0) / fz0
    out: list[Violation] = []
    chans = set(channels)

    def at(mask, arrays) -> str:
        i = int(np.argmax(mask))
        parts = [f"Fz = {arrays[0][i]:.0f} N"]
        if len(arrays) > 1 and cam.size > 1:
            parts.append(f"camber {arrays[1][i] / _DEG:.2g} deg")
        if len(arrays) > 2 and arrays[2] is not None and pr.size > 1:
            parts.append(f"pressure {arrays[2][i] / 1e3:.0f} kPa")
        if len(arrays) > 3:
            parts += [s for s in arrays[3:] if isinstance(s, str)]
        return ", ".join(parts)

    def add(rule, channel, bad, value, where, text):
        bad = np.asarray(bad, bool)
        if bad.any():
            worst = float(np.max(np.where(bad, value, -np.inf)))
            out.append(Violation(rule, channel, worst, where(bad),
                                 f"{channel}: {text} (worst {worst:.4g}) at {where(bad)}"))

    _, b = _mf61._prepare(p, v, F, 0.0 * F, 0.0 * F, G, press, None)
    if "fx" in chans:
        ex = (c["PEX1"] + c["PEX2"] * dfz + c["PEX3"] * dfz ** 2) * c["LEX"]
        for sgn in (1.0, -1.0):
            e = ex * (1.0 - c["PEX4"] * sgn)
            add("E<=1", "Fx", e > 1.0 + E_TOL, e, lambda m: at(m, (F, G, P)),
                f"pure-slip curvature E_x > 1 (PEX1..PEX4, 4.E14) for {'drive' if sgn > 0 else 'brake'}")
        _mu_rules(add, "x", "Fx", "PDX1, PDX2", _mux(c, b), F, G, P, at, mu_ceiling)
        exa = c["REX1"] + c["REX2"] * dfz
        add("E<=1", "Fx", exa > 1.0 + E_TOL, exa, lambda m: at(m, (F, G, P)),
            "combined-slip curvature E_xa > 1 (REX1, REX2, 4.E56)")
    if "fy" in chans:
        ey0 = (c["PEY1"] + c["PEY2"] * dfz) * c["LEY"]
        for sgn in (1.0, -1.0):
            e = ey0 * (1.0 + c["PEY5"] * G ** 2 - (c["PEY3"] + c["PEY4"] * G) * sgn)
            add("E<=1", "Fy", e > 1.0 + E_TOL, e, lambda m: at(m, (F, G, P)),
                f"pure-slip curvature E_y > 1 (PEY1..PEY5, 4.E24) for {'positive' if sgn > 0 else 'negative'} slip")
        muy = np.abs(_mf61._fy0_parts(c, b)["muy"])
        _mu_rules(add, "y", "Fy", "PDY1, PDY2", muy, F, G, P, at, mu_ceiling)
        eyk = c["REY1"] + c["REY2"] * dfz
        add("E<=1", "Fy", eyk > 1.0 + E_TOL, eyk, lambda m: at(m, (F, G, P)),
            "combined-slip curvature E_yk > 1 (REY1, REY2, 4.E64)")
    if "mz" in chans:
        et = c["QEZ1"] + c["QEZ2"] * dfz + c["QEZ3"] * dfz ** 2
        bound = np.abs(c["QEZ4"] + c["QEZ5"] * G)
        etm = np.maximum(et * (1.0 + bound), et * (1.0 - bound))
        add("E<=1", "Mz", etm > 1.0 + E_TOL, etm, lambda m: at(m, (F, G, P)),
            "trail curvature E_t > 1 (QEZ1..QEZ5, 4.E44)")
    if "fx" in chans or "fy" in chans:
        out += _combined(p, v, c, env, fz, cam, chans)
    if "mz" in chans and "fy" in chans:
        def forces(F, A, G, P):
            return _mf61.forces(p, F, slip_ratio=0.0 * F, slip_angle=A, camber=G, pressure=P, version=v)

        out += _aligning(forces, env, fz, cam, pr, float(p.get("UNLOADED_RADIUS", 0.3)))
    return out


def check_tyre(tyre) -> list[str]:
    """Every problem of a tyre tyrefit reads: its reader's check, then the contract over its declared envelope.

    Magic Formula tyres (:class:`tyrefit.tyres.mf.MFTyre`): :func:`violations` for the parts the file
    models.  Other families (PAC89, Chrono JSON): the reader's check (C > 0, D > 0, E <= 1 over the load
    range) and the aligning rule through the tyre's own forces.
    """
    problems = list(tyre.check())
    env = tyre.validity()
    if isinstance(tyre, MFTyre):
        chans = [c for c, has in (("fx", tyre.has_longitudinal), ("fy", tyre.has_lateral),
                                  ("mz", tyre.has_aligning)) if has]
        return problems + [str(x) for x in violations(tyre.params, env, version=tyre.version, channels=chans)]
    if getattr(tyre, "has_lateral", True) and getattr(tyre, "has_aligning", False):
        fz = np.linspace(*env["fz"], 9)
        cam = np.unique(np.linspace(*env["camber"], 3))
        pr = np.array([np.nan])

        def forces(F, A, G, P):
            return tyre.forces(F, slip_angle=A, camber=G)

        problems += [str(x) for x in _aligning(forces, env, fz, cam, pr, float(tyre.unloaded_radius or 0.3))]
    return problems


def _mux(c, b):
    """mu_x (4.E13) with the pressure and camber factors."""
    dfz, dpi = b.dfz, b.dpi
    return np.abs((c["PDX1"] + c["PDX2"] * dfz) * (1 + c["PPX3"] * dpi + c["PPX4"] * dpi ** 2)
                  * (1 - c["PDX3"] * b.gamma ** 2) * c["LMUX"])


def _mu_rules(add, axis, channel, coefs, mu, F, G, P, at, ceiling):
    add("mu>0", channel, ~(mu > 1e-6), -mu, lambda m: at(m, (F, G, P)),
        f"peak friction mu_{axis} <= 0 ({coefs})")
    if ceiling and ceiling.get(axis) is not None:
        if callable(ceiling[axis]):
            cap = np.asarray(ceiling[axis](F), float)
        else:
            lf, lm = (np.asarray(a, float) for a in ceiling[axis])
            o = np.argsort(lf)
            cap = np.interp(F, lf[o], lm[o])
        add("mu<=ceiling", channel, mu > cap * (1 + 1e-6), mu / cap, lambda m: at(m, (F, G, P)),
            f"peak friction mu_{axis} above 1.15 x the largest |F|/Fz the data show through the peak "
            f"({coefs}; ratio to that ceiling)")


def _combined(p, v, c, env, fz, cam, chans) -> list[Violation]:
    """0 <= G_xa, G_yk <= 1 over the declared slip-angle x slip-ratio range (4.E51, 4.E59)."""
    al = slip_grid(*env["slip_angle"], 13, 1.0 * _DEG)
    ka = slip_grid(*env["slip_ratio"], 13, 0.02)
    F, G, A, K = (a.ravel() for a in np.meshgrid(fz, cam, al, ka, indexing="ij"))
    _, b = _mf61._prepare(p, v, F, K, A, G, None, None)
    out = []
    checks = []
    if "fx" in chans:
        checks.append(("Fx", "G_xa", _mf61._gxa(c, b), "RBX*, RCX1, REX*, RHX1; |Fx(kappa, alpha)| > "
                       "|Fx(kappa, 0)|: combined slip adds longitudinal force"))
    if "fy" in chans:
        gyk, _ = _mf61._gyk(c, b, np.ones_like(F))
        checks.append(("Fy", "G_yk", gyk, "RBY*, RCY1, REY*, RHY*; |Fy(alpha, kappa) - SV_yk| > |Fy(alpha, 0)|: "
                       "combined slip adds lateral force"))
    for ch, name, g, what in checks:
        g = np.asarray(g, float)
        bad_hi = ~np.isfinite(g) | (g > 1.0 + G_TOL)
        bad_lo = g < -G_TOL
        for bad, rule, val, text in ((bad_hi, "G<=1", g, f"combined-slip weight {name} > 1 ({what})"),
                                     (bad_lo, "G>=0", -g, f"combined-slip weight {name} < 0 (the force reverses "
                                      "with the other slip)")):
            if bad.any():
                i = int(np.argmax(bad))
                where = (f"Fz = {F[i]:.0f} N, slip angle {A[i] / _DEG:.3g} deg, slip ratio {K[i]:.3g}"
                         + (f", camber {G[i] / _DEG:.2g} deg" if cam.size > 1 else ""))
                worst = float(np.nanmax(np.where(bad, np.nan_to_num(val, nan=np.inf), -np.inf)))
                out.append(Violation(rule, ch, worst, where, f"{ch}: {text} (worst {worst:.4g}) at {where}"))
    return out


def _aligning(forces, env, fz, cam, pr, r0: float) -> list[Violation]:
    """Mz Fy < 0 (positive pneumatic trail) at 2-4 deg of slip angle, both signs, every load and pressure."""
    lo, hi = env["slip_angle"]
    angles = [a * _DEG for a in ALIGN_DEG] + [-a * _DEG for a in ALIGN_DEG]
    angles = [a for a in angles if lo - 1e-9 <= a <= hi + 1e-9]
    if not angles:
        return []
    g0 = float(cam[np.argmin(np.abs(cam))])
    F, P, A = (a.ravel() for a in np.meshgrid(fz, pr, np.array(angles), indexing="ij"))
    press = None if np.all(np.isnan(P)) else P
    f = forces(F, A, np.full_like(F, g0), press)
    fy, mz = np.asarray(f["fy"], float), np.asarray(f["mz"], float)
    val = mz * np.sign(fy) / (F * r0)  # > 0: Mz pushes the slip angle up (de-aligning)
    bad = ~np.isfinite(val) | (val >= 0.0)
    if not bad.any():
        return []
    i = int(np.argmax(bad))
    where = (f"Fz = {F[i]:.0f} N, slip angle {A[i] / _DEG:.3g} deg"
             + (f", pressure {P[i] / 1e3:.0f} kPa" if pr.size > 1 and press is not None else "")
             + (f", camber {g0 / _DEG:.2g} deg" if abs(g0) > 0 else ""))
    worst = float(np.nanmax(np.where(bad, val, -np.inf)))
    return [Violation("aligning", "Mz", worst, where,
                      f"Mz: the aligning moment does not align the wheel (Mz of the sign of Fy: a negative "
                      f"pneumatic trail, QDZ1-QDZ4, or a residual torque against it, QDZ6-QDZ11) at {where} "
                      f"(Mz {mz[i]:.3g} N*m, Fy {fy[i]:.4g} N)")]
