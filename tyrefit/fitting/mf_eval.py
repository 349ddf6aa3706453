"""The Magic Formula evaluator of the staged fit: one channel of the model at a stage's points (:class:`_Eval`).

Each stage of :func:`tyrefit.fitting.mf.fit_mf` evaluates the channel it fits, hundreds of times (every
residual and every Jacobian column), at the measured load, camber, pressure and speed of every point.
:class:`_Eval` prepares those inputs once and evaluates only what the stage's coefficients change:

* the pure-slip stages through the cheaper pure-slip functions: Fx0 (Pacejka 2012, 4.E9), Fy0 (4.E19), and
  Mz0 = -t0 Fy0(gamma = 0) + Mzr0 (4.E31) with Fy0 kept while only aligning coefficients move;
* the combined-slip and moment stages vary only G_x_alpha (Fx = G_xa Fx0, 4.E50), G_y_kappa and SV_y_kappa
  (Fy = G_yk Fy0 + SV_yk, 4.E58), s (SSZ, 4.E71-4.E76), Mx or My: the pure-slip forces, the trail and the
  other channels are those of the stages before and are evaluated once (:meth:`_Eval._parts`);
* the coefficient mapping is built once per stage (:class:`tyrefit.fitting.mf_parts.Forces`) and only the
  varied entries are replaced at each call;
* analytic Jacobian columns where the channel is a closed form in the stage's coefficients (Mx in QSX*,
  PPMX1; MF 6.1 Mz in QBZ*, QCZ1, QDZ*, QEZ*, QHZ*, PPZ*, SSZ*; :mod:`tyrefit.fitting.mf_parts`).

The stages are what makes the fit fast; this is what makes a stage fast: the plain alternative evaluates
every channel of the whole model for every coefficient of every Jacobian (``benchmarks/bench_fit_mf.py``).

MF 5.2's Mz0 stage is evaluated through the combined form -t (Fy - SV_yk) + Mzr + s Fx at kappa = 0, as the
5.2 solvers (MFeval's FITTYP 6 path, which :func:`tyrefit.models.mf61.forces` follows) do.

References
----------
Pacejka, *Tire and Vehicle Dynamics*, 3rd ed. (2012), equations 4.E1-4.E78.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np
import pandas as pd

from ..models import mf61
from . import mf_parts
from .mf_stages import Stage

__all__: list[str] = []


def _mf61():
    """The Magic Formula evaluator (:mod:`tyrefit.models.mf61`), the module the stages evaluate."""
    return mf61


class _Eval:
    """Evaluate one channel of the model at a stage's points (inputs prepared once)."""

    def __init__(self, pts: pd.DataFrame, stage: Stage, nominal: Mapping[str, float], version: str):
        self.mf = _mf61()
        self.version = version
        self.channel = stage.channel
        self.pure = stage.pure
        self.fz = pts["fz"].to_numpy(float)
        self.kappa = pts["slip_ratio"].to_numpy(float).copy()
        self.alpha = pts["slip_angle"].to_numpy(float).copy()
        if stage.pure == "alpha":
            self.alpha[:] = 0.0
        elif stage.pure == "kappa":
            self.kappa[:] = 0.0
        elif "kind" in pts:  # mixed stages: pure-slip sweeps as pure slip, as they are fitted and reported
            kind = pts["kind"].to_numpy()
            self.kappa[kind == "lateral"] = 0.0
            self.alpha[kind == "longitudinal"] = 0.0
        # the Mz stages that move the pure trail re-evaluate it at every call; for MF 5.2 also the pure Mz0
        # stage: the 5.2 solvers (MFeval's FITTYP 6 path, which tyrefit's forces() follows) evaluate Mz at
        # kappa = 0 through the combined form -t (Fy - SVyk) + Mzr + s Fx, which differs from the book's pure
        # Mz0 (4.E31, -t0 Fy0(gamma = 0) + Mzr0, models.mf61.mz0) by up to 6.6 N*m of 122 on Chrono's VW
        # microbus PAC2002 file at 3 deg camber, so mz0() alone cannot fit data made by those solvers down to
        # the noise floor; the joint evaluation below uses the combined form for them
        self.joint = stage.name == "Mz*" or (stage.name == "Mz0" and version == "5.2")
        self.gamma = pts["camber"].to_numpy(float)
        pr = pts["pressure"].to_numpy(float)
        self.pressure = np.where(np.isfinite(pr), pr, nominal.get("NOMPRES", np.nan)) if np.isfinite(pr).any() \
            else None
        v = pts["speed"].to_numpy(float)
        self.speed = np.where(np.isfinite(v), v, nominal.get("LONGVL", np.nan)) if np.isfinite(v).any() else None

    def __call__(self, p: Mapping[str, float], changed: Sequence[str] | None = None) -> np.ndarray:
        """The channel at ``p``; ``changed``: the only names in which ``p`` differs between calls (the stage's
        varied coefficients): the coefficient mapping and the fixed parts are then built once
        (:mod:`tyrefit.fitting.mf_parts`)."""
        if mf_parts.FAST and self.mf is mf61:
            if self._forces is None:  # the mapping of the first call; later calls replace entries
                self._forces = mf_parts.Forces(self.version, self.fz, self.kappa, self.alpha, self.gamma,
                                               self.pressure, self.speed)
                self._forces.bind(p)
                self._p0 = dict(p)
                changed = () if changed is None else changed
            elif changed is None:  # a caller's own mapping (the variable projection): what differs from the first
                changed = self._diff(p)
            if changed is not None:
                c, b = self._forces.coefficients([(k, p[k]) for k in changed])
                return self._fast(c, b, changed)
        kw, mf = {"version": self.version}, self.mf
        if self.pure == "alpha" and self.channel == "fx":  # pure slip: the cheaper pure-slip functions
            return self.mf.fx0(p, self.fz, self.kappa, self.gamma, self.pressure, self.speed, **kw)
        if self.pure == "kappa" and self.channel == "fy":
            return self.mf.fy0(p, self.fz, self.alpha, self.gamma, self.pressure, self.speed, **kw)
        if self.pure == "kappa" and self.channel == "mz" and self.version != "5.2":
            return self.mf.mz0(p, self.fz, self.alpha, self.gamma, self.pressure, self.speed, **kw)
        if self._cache is None:
            self._cache = self._parts(*mf._prepare(p, self.version, self.fz, self.kappa, self.alpha, self.gamma,
                                                   self.pressure, self.speed)) if self._stage_functions() else {}
        if self._cache:
            return self._partial(mf.coefficients(p), self._cache["b"])
        out = self.mf.forces(p, self.fz, slip_ratio=self.kappa, slip_angle=self.alpha, camber=self.gamma,
                             pressure=self.pressure, speed=self.speed, **kw)
        return np.asarray(out[self.channel], float)

    # -- the fast path: the mapping of the first call, the varied entries replaced
    _forces = None
    _p0: dict = {}
    _pure_mz = None

    def _diff(self, p) -> list[str] | None:
        """The names in which ``p`` differs from the bound mapping (None when one is not a coefficient)."""
        p0, c0 = self._p0, self._forces.c0
        if p.keys() != p0.keys():
            return None
        try:  # the items' set difference, in C (values of a fit's mapping are floats)
            out = [k for k, _ in p.items() - p0.items()]
        except TypeError:  # an unhashable value (an array of candidates)
            out = [k for k, v in p.items() if p0[k] is not v and p0[k] != v]
        return out if all(k in c0 for k in out) else None

    def _fast(self, c, b, changed) -> np.ndarray:
        mf = self.mf
        if self.pure == "alpha" and self.channel == "fx":
            return np.asarray(mf._fx0_parts(c, b)[0])
        if self.pure == "kappa" and self.channel == "fy":
            return np.asarray(mf._fy0_parts(c, b)["fy0"])
        if self.pure == "kappa" and self.channel == "mz" and self.version != "5.2":
            # mf61.mz0 with Fy0 (and its zero-camber value) kept while only Mz coefficients change
            keep = all(mf_parts.group(k) in ("mz0", "ssz") for k in changed)
            if self._pure_mz is None or not keep:
                fyp = mf._fy0_parts(c, b)
                fy_g0 = fyp["fy0"] if not np.any(b.gstar) else mf._fy0_parts(c, b, zero_camber=True)["fy0"]
                if keep:
                    self._pure_mz = (fyp, fy_g0)
            else:
                fyp, fy_g0 = self._pure_mz
            out, _, _ = mf._mz(c, b, mf._mz_parts(c, b, fyp), fy_g0, 0.0, 0.0, fyp["fy0"])
            return np.asarray(out)
        if self._cache is None:
            self._cache = self._parts(c, b)
        return self._partial(c, b)

    def jacobian(self, p, changed) -> dict[str, np.ndarray]:
        """Analytic d(channel)/d(name) at ``p`` for the names of ``changed`` where the model has one (MF 6.1 Mx
        and Mz in their own coefficients, :mod:`tyrefit.fitting.mf_parts`): {name: column}; {} elsewhere."""
        if not (mf_parts.FAST and self.mf is mf61 and self.channel in ("mx", "mz") and self.version != "5.2"
                and self.pure in (None, "kappa")):
            return {}
        if self.pure == "kappa" and self.channel == "mx":
            return {}
        if self._forces is None or (self.pure is None and self._cache is None) \
                or (self.pure == "kappa" and self._pure_mz is None):
            self(p, changed)  # binds the mapping and the fixed parts
        c, b = self._forces.coefficients([(k, p[k]) for k in changed])
        if self.channel == "mx":
            return mf_parts.mx_jacobian(c, b, self._cache["fy"], list(changed))
        if self.pure == "kappa":  # mf61.mz0: kappa = 0, Fx = 0, Fy' = Fy0 at zero camber
            if self._pure_mz is None:
                return {}
            fyp, fy_g0 = self._pure_mz
            return mf_parts.mz_jacobian(c, b, fyp, fy_g0, 0.0, 0.0, fyp["fy0"], list(changed))
        k = self._cache
        return mf_parts.mz_jacobian(c, b, k["fyp"], k["fy_prime"], k["kxk"], k["fx"], k["fy"], list(changed))

    # -- the later stages: only the part that depends on the stage's own coefficients is re-evaluated
    _cache = None

    def _stage_functions(self) -> bool:
        need = ("_prepare", "_fx0_parts", "_fy0_parts", "_gxa", "_gyk", "_mz_parts", "_mz", "_mx", "_my",
                "coefficients")
        return all(hasattr(self.mf, n) for n in need)

    def _parts(self, c, b) -> dict:
        """Everything that the stage's coefficients do not change, from the model's own stage functions.

        The combined-slip and moment stages vary only G_x_alpha, G_y_kappa/SV_y_kappa, s (SSZ), Mx or My;
        the pure-slip forces, the trail and the other channels are those of the stages before and are
        evaluated once.  Returns {} (use :func:`forces`) when the model module has no stage functions.
        """
        mf = self.mf
        fx0, _, kxk = mf._fx0_parts(c, b)
        fyp = mf._fy0_parts(c, b)
        fx = mf._gxa(c, b) * fx0
        gyk, svyk = mf._gyk(c, b, fyp["muy"])
        fy = gyk * fyp["fy0"] + svyk
        if b.v52:
            _, svyk0 = mf._gyk(c, b, mf._fy0_parts(c, b, zero_camber=True)["muy"])
            fy_prime = fy - svyk0
        else:
            fy_prime = gyk * mf._fy0_parts(c, b, zero_camber=True)["fy0"]
        return {"b": b, "fx0": fx0, "kxk": kxk, "fyp": fyp, "fx": fx, "fy": fy, "fy_prime": fy_prime,
                "mzp": mf._mz_parts(c, b, fyp)}

    def _partial(self, c, b) -> np.ndarray:
        mf, k = self.mf, self._cache
        if self.channel == "fx":
            y = mf._gxa(c, b) * k["fx0"]                                        # (4.E50)
        elif self.channel == "fy":
            gyk, svyk = mf._gyk(c, b, k["fyp"]["muy"])
            y = gyk * k["fyp"]["fy0"] + svyk                                    # (4.E58)
        elif self.channel == "mz":
            mzp = mf._mz_parts(c, b, k["fyp"]) if self.joint else k["mzp"]  # the joint Mz polish moves Mz0 too
            y, _, _ = mf._mz(c, b, mzp, k["fy_prime"], k["kxk"], k["fx"], k["fy"])
        elif self.channel == "mx":
            y = mf._mx(c, b, k["fy"])
        else:
            y = mf._my(c, b, k["fx"], self.pressure)
        return np.broadcast_to(np.asarray(y, float), self.fz.shape)
