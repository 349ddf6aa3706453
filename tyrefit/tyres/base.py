"""The tyre interface every model family sits behind.

A :class:`Tyre` answers one question -- the forces and moments at a load,
slip angle, slip ratio, camber, pressure and speed -- in SI and ISO-W, and
says where that answer can be trusted (nominal values, validity ranges,
:meth:`Tyre.check`).  ``fit``, ``eval``, ``compare`` and ``sim`` use only this
interface, so a PAC89 tyre fitted here, a vendor's MF 5.2 / PAC2002 file and
an MF 6.1 / 6.2 file are interchangeable wherever a tyre is needed.

Design choices
--------------
* **An abstract base class, not a Protocol.**  The shared behaviour (the
  convenience curves ``fx``/``fy``/``mz``, the mirror image, ``check_physical``,
  the default validity ranges) lives here once; a family implements
  :meth:`Tyre.forces` and :meth:`Tyre.check`.
* **One call, every output.**  :meth:`Tyre.forces` broadcasts its inputs
  (NumPy rules) and returns a dict of arrays ``fx``, ``fy``, ``mz`` and, where
  the model defines them, ``mx`` and ``my``.  Combined slip is applied where
  the model has it (:attr:`Tyre.combined`); PAC89 has none, so its Fx depends
  on the slip ratio alone and Fy, Mz on the slip angle alone.
* **No load, no force.**  Points with ``fz <= 0`` (the wheel off the ground)
  give zero forces and moments, as a simulator does; the formulas themselves
  are undefined there (PAC89's B = BCD / (C D) is 0/0 at Fz = 0).
* **Checks list, they do not raise.**  :meth:`Tyre.check` returns every problem
  found over the declared range as a sentence; commands refuse a tyre with
  problems unless ``--allow-unphysical`` (:func:`require_physical`).
"""

from __future__ import annotations

import abc
import math
from collections.abc import Sequence
from typing import Any

import numpy as np

from ..errors import ModelError, ValueRangeError, option

__all__ = ["Tyre", "MirroredTyre", "FAMILIES", "require_physical", "broadcast_inputs"]

#: model families behind the interface
FAMILIES = ("PAC89", "MF52", "MF61")

#: fallbacks of the validity ranges when neither the file nor the fit declares one (SI)
_DEFAULT_SLIP_ANGLE = (-math.radians(15.0), math.radians(15.0))
_DEFAULT_SLIP_RATIO = (-1.0, 1.0)
_DEFAULT_CAMBER = (0.0, 0.0)


def broadcast_inputs(fz, slip_angle=0.0, slip_ratio=0.0, camber=0.0, pressure=None, speed=None,
                     *, nominal_pressure=None, nominal_speed=None) -> dict[str, np.ndarray]:
    """Float arrays of the operating point, broadcast to one shape.

    ``pressure`` and ``speed`` default to the nominal values (NaN when there is none).
    """
    p = nominal_pressure if pressure is None else pressure
    v = nominal_speed if speed is None else speed
    arrs = np.broadcast_arrays(*(np.asarray(x if x is not None else np.nan, dtype=float)
                                 for x in (fz, slip_angle, slip_ratio, camber, p, v)))
    return dict(zip(("fz", "slip_angle", "slip_ratio", "camber", "pressure", "speed"), arrs))


class Tyre(abc.ABC):
    """A tyre model: forces and moments in SI and ISO-W, with its nominal values and validity ranges.

    Subclasses set the attributes below and implement :meth:`forces` and
    :meth:`check`.

    Attributes
    ----------
    family : str
        'PAC89', 'MF52' or 'MF61' (MF 6.2 files are evaluated as 6.1).
    name : str
    fnomin : float or None
        nominal (rated) load [N].
    unloaded_radius, width : float or None
        [m].
    nominal_pressure : float or None
        [Pa] (None: the model has no pressure dependence).
    nominal_speed : float or None
        [m/s] (the file's LONGVL).
    ranges : dict
        declared validity ranges (min, max) in SI: ``fz`` [N], ``slip_angle``
        [rad], ``slip_ratio`` [-], ``camber`` [rad], ``pressure`` [Pa].
    combined : bool
        whether :meth:`forces` applies combined slip.
    inputs : tuple of str
        the operating-point inputs the model responds to (PAC89: no pressure or speed).
    outputs : tuple of str
        the keys :meth:`forces` returns.
    """

    family: str = ""
    name: str = "tyre"
    combined: bool = False
    outputs: tuple[str, ...] = ("fx", "fy", "mz")
    #: the operating-point inputs the model responds to
    inputs: tuple[str, ...] = ("fz", "slip_angle", "slip_ratio", "camber")

    # Subclasses that are dataclasses define these as fields; the defaults keep the ABC usable.
    fnomin: float | None = None
    unloaded_radius: float | None = None
    width: float | None = None
    nominal_pressure: float | None = None
    nominal_speed: float | None = None
    tyreside: str = "LEFT"
    #: what the reader had to assume about the file it came from (e.g. a missing ``[MODEL]`` section)
    file_notes: Sequence[str] = ()

    # -- evaluation -----------------------------------------------------------------
    @abc.abstractmethod
    def forces(self, fz, slip_angle=0.0, slip_ratio=0.0, camber=0.0, pressure=None,
               speed=None) -> dict[str, np.ndarray]:
        """Forces and moments at the given operating points (NumPy broadcasting).

        Parameters
        ----------
        fz : array_like
            normal load [N], positive in compression.
        slip_angle : array_like
            ISO-W slip angle [rad] (a positive angle gives a negative lateral force).
        slip_ratio : array_like
            longitudinal slip ratio [-] (positive when driving).
        camber : array_like
            inclination angle [rad], ISO-W.
        pressure : array_like, optional
            inflation pressure [Pa]; default the nominal pressure.
        speed : array_like, optional
            forward speed [m/s]; default the nominal speed.

        Returns
        -------
        dict of ndarray
            ``fx``, ``fy`` [N], ``mz`` [N*m] and, where the model has them,
            ``mx``, ``my`` [N*m]; ISO-W; zero where ``fz <= 0``; NaN for a part
            the tyre does not model (see :attr:`has_longitudinal` and siblings).
        """

    @abc.abstractmethod
    def check(self, n: int = 41) -> list[str]:
        """Problems of the model over its declared ranges (empty when physical).

        Looks for what makes a tyre unusable or its forces meaningless: shape
        factor C <= 0, peak D <= 0, curvature E > 1, a stiffness that is zero
        or undefined (PAC89's a4 = 0, MF's PKY2 = 0), non-finite forces, and
        required coefficients that the file does not give.
        """

    def warnings(self, n: int = 41) -> list[str]:
        """Questionable but evaluable features over the declared ranges (reported, never refused)."""
        return []

    # -- convenience curves (pure slip) ---------------------------------------------
    def fx(self, fz, slip_ratio, camber=0.0):
        """Longitudinal force [N] at load [N] and slip ratio [-] (no slip angle)."""
        return self.forces(fz, slip_ratio=slip_ratio, camber=camber)["fx"]

    def fy(self, fz, slip_angle, camber=0.0):
        """Lateral force [N] (ISO-W) at load [N], slip angle [rad], camber [rad] (no slip ratio)."""
        return self.forces(fz, slip_angle=slip_angle, camber=camber)["fy"]

    def mz(self, fz, slip_angle, camber=0.0):
        """Aligning moment [N*m] (ISO-W) at load [N], slip angle [rad], camber [rad]."""
        return self.forces(fz, slip_angle=slip_angle, camber=camber)["mz"]

    @property
    def has_lateral(self) -> bool:
        """Whether the model gives a lateral force."""
        return True

    @property
    def has_longitudinal(self) -> bool:
        """Whether the model gives a longitudinal force."""
        return True

    @property
    def has_aligning(self) -> bool:
        """Whether the model gives an aligning moment."""
        return True

    def mirrored(self) -> "Tyre":
        """The same tyre mounted on the other side (see :class:`MirroredTyre`)."""
        return MirroredTyre(self)

    def on_road(self, friction: float) -> "Tyre":
        """The same tyre on a road whose friction is ``friction`` x that of the surface it was tested on.

        The peak forces scale and the slip stiffnesses do not: the friction scaling factors of the
        Magic Formula (Pacejka 2012, Sec. 4.3.2, lambda_mu_x and lambda_mu_y), and for PAC89 the peak
        factor D alone (B = BCD / (C D) absorbs it).  A test rig's abrasive belt grips more than a road
        does; FSAE teams commonly scale belt-rig data by about 0.6-0.7 for a dry track, a number best
        measured on the car (a skid pad's lateral limit against the tyre model's).
        """
        raise ModelError(f"{self.name}: a {self.family} tyre has no road-friction scaling")

    @staticmethod
    def _check_friction(friction: float) -> float:
        f = float(friction)
        if not (math.isfinite(f) and 0.05 <= f <= 1.5):
            raise ValueRangeError(f"road friction {friction!r}: a factor on the test surface's friction, from 0.05 "
                                  "to 1.5 (1 = the surface the tyre was tested on)")
        return f

    # -- nominal values and ranges ----------------------------------------------------
    @property
    def nominal(self) -> dict[str, float | None]:
        """Nominal values: ``fz`` [N], ``pressure`` [Pa], ``speed`` [m/s], ``unloaded_radius``, ``width`` [m]."""
        return {"fz": self.fnomin, "pressure": self.nominal_pressure, "speed": self.nominal_speed,
                "unloaded_radius": self.unloaded_radius, "width": self.width}

    def validity(self) -> dict[str, tuple[float, float]]:
        """Validity ranges in SI, the declared ones where given, else documented fallbacks.

        ``fz``: declared, else 0.2-2 x FNOMIN, else 1-10 kN; ``slip_angle``
        +/-15 deg; ``slip_ratio`` +/-1; ``camber`` 0; ``pressure`` the nominal one.
        """
        r = dict(getattr(self, "ranges", {}) or {})
        out: dict[str, tuple[float, float]] = {}
        fz = r.get("fz")
        if fz is None or not (fz[1] > 0):
            fz = (0.2 * self.fnomin, 2.0 * self.fnomin) if self.fnomin else (1000.0, 10000.0)
        out["fz"] = (max(float(fz[0]), 1e-3 * float(fz[1]), 1.0), float(fz[1]))
        out["slip_angle"] = tuple(map(float, r.get("slip_angle", _DEFAULT_SLIP_ANGLE)))
        out["slip_ratio"] = tuple(map(float, r.get("slip_ratio", _DEFAULT_SLIP_RATIO)))
        out["camber"] = tuple(map(float, r.get("camber", _DEFAULT_CAMBER)))
        if "pressure" in r:
            out["pressure"] = tuple(map(float, r["pressure"]))
        elif self.nominal_pressure:
            out["pressure"] = (float(self.nominal_pressure),) * 2
        return out

    def check_physical(self, fz_range: tuple[float, float] | None = None, n: int = 41) -> None:
        """Raise :class:`~tyrefit.errors.ModelError` naming the first problem of :meth:`check`."""
        problems = self._check_range(fz_range, n) if fz_range is not None else self.check(n)
        if problems:
            more = f" (and {len(problems) - 1} more)" if len(problems) > 1 else ""
            raise ModelError(f"{problems[0]}{more}")

    def _check_range(self, fz_range, n):  # pragma: no cover - overridden where a load range is supported
        return self.check(n)

    def grid(self, n: int = 41) -> dict[str, np.ndarray]:
        """An (fz x slip_angle x slip_ratio x camber) grid over :meth:`validity` for checks."""
        v = self.validity()
        fz = np.linspace(*v["fz"], n)
        sa = np.linspace(*v["slip_angle"], 21)
        sr = np.linspace(*v["slip_ratio"], 21)
        cam = np.unique(np.linspace(*v["camber"], 5))
        return {"fz": fz[:, None, None, None], "slip_angle": sa[None, :, None, None],
                "slip_ratio": sr[None, None, :, None], "camber": cam[None, None, None, :]}

    def _finite_problems(self, n: int) -> list[str]:
        """'forces not finite' problems over :meth:`grid` (pure and combined slip)."""
        g = self.grid(n)
        with np.errstate(all="ignore"):
            pure_y = self.forces(g["fz"], slip_angle=g["slip_angle"], camber=g["camber"])
            pure_x = self.forces(g["fz"], slip_ratio=g["slip_ratio"], camber=g["camber"])
            both = self.forces(g["fz"], slip_angle=g["slip_angle"], slip_ratio=g["slip_ratio"],
                               camber=g["camber"]) if self.combined else {}
        out = []
        has = {"fx": self.has_longitudinal, "fy": self.has_lateral, "mz": self.has_aligning,
               "mx": getattr(self, "has_overturning", True), "my": getattr(self, "has_rolling", True)}
        for label, res in (("pure lateral slip", pure_y), ("pure longitudinal slip", pure_x),
                           ("combined slip", both)):
            for k, val in res.items():
                if not has.get(k, True):
                    continue
                val = np.asarray(val)
                if not np.all(np.isfinite(val)):
                    idx = np.unravel_index(int(np.argmin(np.isfinite(val))), val.shape)
                    fz_bad = float(np.broadcast_to(g["fz"], val.shape)[idx])
                    out.append(f"{k} is not finite in {label} at Fz = {fz_bad:.0f} N")
        return out

    def describe(self) -> dict[str, Any]:
        """Plain summary for JSON and reports."""
        return {"family": self.family, "name": self.name, "nominal": self.nominal,
                "ranges": {k: list(v) for k, v in self.validity().items()}, "combined": self.combined,
                "outputs": list(self.outputs)}


class MirroredTyre(Tyre):
    """A tyre mounted on the other side of the vehicle: the mirror image about the wheel plane.

    With the slip angle and camber mirrored, lateral force, overturning and
    aligning moment change sign; Fx and My do not:
    ``F'(fz, a, k, g) = S F(fz, -a, k, -g)`` with S = diag(+, -, -, -, +) on
    (fx, fy, mz, mx, my).  Exact for every model family (conicity and ply-steer
    offsets flip, as on a real axle).
    """

    def __init__(self, tyre: Tyre) -> None:
        self.tyre = tyre
        self.family = tyre.family
        self.name = tyre.name
        self.combined = tyre.combined
        self.outputs = tyre.outputs
        self.inputs = tyre.inputs
        for k in ("fnomin", "unloaded_radius", "width", "nominal_pressure", "nominal_speed"):
            setattr(self, k, getattr(tyre, k))
        side = str(getattr(tyre, "tyreside", "LEFT")).upper()
        self.tyreside = "RIGHT" if side == "LEFT" else "LEFT"
        self.ranges = dict(getattr(tyre, "ranges", {}) or {})
        if "camber" in self.ranges:
            lo, hi = self.ranges["camber"]
            self.ranges["camber"] = (-hi, -lo)

    def forces(self, fz, slip_angle=0.0, slip_ratio=0.0, camber=0.0, pressure=None, speed=None):
        f = self.tyre.forces(fz, -np.asarray(slip_angle, float), slip_ratio, -np.asarray(camber, float),
                             pressure, speed)
        return {k: (-v if k in ("fy", "mz", "mx") else v) for k, v in f.items()}

    def check(self, n: int = 41) -> list[str]:
        return self.tyre.check(n)

    @property
    def has_lateral(self) -> bool:
        return self.tyre.has_lateral

    @property
    def has_longitudinal(self) -> bool:
        return self.tyre.has_longitudinal

    @property
    def has_aligning(self) -> bool:
        return self.tyre.has_aligning

    def mirrored(self) -> Tyre:
        return self.tyre

    def on_road(self, friction: float) -> Tyre:
        return MirroredTyre(self.tyre.on_road(friction))


def require_physical(tyre: Tyre, source: str = "", allow_unphysical: bool = False) -> list[str]:
    """Refuse ``tyre`` with :class:`~tyrefit.errors.ModelError` if :meth:`Tyre.check` finds problems.

    With ``allow_unphysical`` the problems are returned instead (for a warning).
    """
    problems = tyre.check()
    if problems and not allow_unphysical:
        where = f"{source}: " if source else ""
        more = f"; and {len(problems) - 1} more" if len(problems) > 1 else ""
        raise ModelError(f"{where}the tyre is not physical over its declared range: {problems[0]}{more} "
                         f"({option('allow_unphysical', flag=True)} evaluates it anyway)")
    return problems

