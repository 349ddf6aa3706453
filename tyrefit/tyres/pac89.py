"""The PAC89 tyre: coefficients plus the design data a simulator needs.

:class:`Pac89Tyre` is the container that ``tyrefit fit`` produces, that
``.tir`` and Chrono JSON files are read into and written from, and that the
vehicle simulation evaluates.  It is the PAC89 member of the
:class:`~tyrefit.tyres.base.Tyre` interface.  Every value is SI (m, N, N/m,
rad) except the coefficients, which keep PAC89's own units and spelling
(``a3``, ``b10``) so they can be grepped against a ``.tir``.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field, replace

import numpy as np

from ..io.chrono_doc import chrono_fields, write_chrono_json
from ..io.pac89_tir import read_pac89_fields, write_tir
from ..models import pac89
from .base import Tyre

__all__ = ["Pac89Tyre"]


#: coefficients a PAC89 part needs (a block present in the file must give them all)
REQUIRED = pac89.PARTS

#: Chrono's ChPac89Tire limits (projectchrono/chrono @ 05a1a976a6,
#: src/chrono_vehicle/wheeled_vehicle/tire/ChPac89Tire.cpp, ChPac89Tire::Advance)
CHRONO_LIMITS = {"camber_deg": 3.0, "slip_ratio": 1.0, "shifted_slip_angle_deg": 89.5}


@dataclass(eq=False)
class Pac89Tyre(Tyre):
    """A Pacejka '89 tyre.

    Evaluated with Chrono's ``ChPac89Tire`` equations (Adams/Tire PAC89), SI in
    and ISO-W out (:mod:`tyrefit.models.pac89`), **within Chrono's limits**.
    Chrono (projectchrono/chrono @ 05a1a976a6,
    ``src/chrono_vehicle/wheeled_vehicle/tire/ChPac89Tire.cpp``,
    ``ChPac89Tire::Advance``) also

    * clamps the camber to +/-``m_gamma_limit``, 3 deg by default
      (``ChClamp(m_gamma, -m_gamma_limit, m_gamma_limit)``);
    * clamps the longitudinal slip to +/-1 (``ChClampValue(cp_long_slip, -1, 1)``)
      and the shifted slip angle X1 to +/-89.5 deg (this clamp is also here);
    * adds ``Fx * Fy / k_lat`` to Mz and sets ``Mx = -Fz * Fy / k_lat``
      (``deflection = Fy / m_lateral_stiffness``), with k_lat the lateral stiffness;
    * scales Fx, Fy, Mz by the road's mu / 0.8 and adds a rolling-resistance My.

    :meth:`forces` does none of that: it is the PAC89 formula itself, with no
    combined slip (Fx depends on the slip ratio only, Fy and Mz on the slip
    angle and camber only).  Beyond 3 deg of camber or |kappa| = 1, and for Mz
    wherever Fx and Fy are both large, Chrono's numbers differ from these.

    Attributes
    ----------
    coefficients : dict
        ``a0``..``a13``, ``b0``..``b10``, ``c0``..``c17`` (missing ones are 0).
    unloaded_radius, width : float or None
        [m].
    fnomin : float or None
        nominal (rated) load [N].
    lateral_stiffness, vertical_stiffness : float or None
        [N/m].
    rolling_resistance : float
        rolling-resistance coefficient [-].
    ranges : dict
        fitted validity ranges in SI: ``fz`` [N], ``slip_angle`` [rad],
        ``camber`` [rad], ``slip_ratio`` [-] -> (min, max).
    header : list of str
        comment lines recorded in the file header (source data, fit statistics).
    vertical_curve : list of (deflection [m], force [N]) or None
        nonlinear vertical load curve (Chrono JSON "Vertical Curve Data").
    name : str
    tyreside : str
        'LEFT' or 'RIGHT'.
    aspect_ratio : float or None
        section height / width [-].
    vertical_damping : float or None
        [N*s/m].
    mass : float or None
        tyre mass [kg].
    inertia : tuple of 3 floats or None
        tyre moments of inertia (Ixx, Iyy, Izz) about the wheel centre [kg*m^2].
    missing : list of str
        required coefficients that the file read did not give (see :data:`REQUIRED`).
    """

    family = "PAC89"

    coefficients: dict[str, float] = field(default_factory=dict)
    unloaded_radius: float | None = None
    width: float | None = None
    fnomin: float | None = None
    lateral_stiffness: float | None = None
    vertical_stiffness: float | None = None
    rolling_resistance: float = 0.0
    ranges: dict[str, tuple[float, float]] = field(default_factory=dict)
    header: list[str] = field(default_factory=list)
    vertical_curve: list[tuple[float, float]] | None = None
    name: str = "tyrefit PAC89 tyre"
    tyreside: str = "LEFT"
    aspect_ratio: float | None = None
    vertical_damping: float | None = None
    mass: float | None = None
    inertia: tuple[float, float, float] | None = None
    missing: list[str] = field(default_factory=list)
    #: what the reader had to assume about the file (a missing ``[MODEL]`` section); not written back
    file_notes: list[str] = field(default_factory=list)

    def __post_init__(self) -> None:
        coeffs = {k: 0.0 for k in pac89.ALL}
        coeffs.update({str(k).lower(): float(v) for k, v in dict(self.coefficients).items()})
        self.coefficients = coeffs

    # -- the Tyre interface ---------------------------------------------------------
    def forces(self, fz, slip_angle=0.0, slip_ratio=0.0, camber=0.0, pressure=None, speed=None):
        """Fx, Fy [N] and Mz [N*m] in ISO-W (pure slip; see the class notes for Chrono's limits).

        ``pressure`` and ``speed`` are accepted for the interface and have no
        effect: PAC89 has neither.  Points with ``fz <= 0`` (below 1 nN) give zeros.
        """
        fz, sa, sr, cam = np.broadcast_arrays(*(np.asarray(x, dtype=float)
                                                for x in (fz, slip_angle, slip_ratio, camber)))
        # off the ground below a nanonewton: PAC89 works in kN, and for a subnormal load (5e-324 N, found by
        # the fuzz test) D = a1 Fz^2 + a2 Fz underflows to 0 and B = BCD / (C D) is 0/0
        on = fz > 1e-9
        fzs = np.where(on, fz, 1.0)  # any positive load where off the ground; zeroed below
        c = self.coefficients
        with np.errstate(all="ignore"):
            out = {"fx": pac89.longitudinal_force(c, fzs, sr),
                   "fy": pac89.lateral_force(c, fzs, sa, cam),
                   "mz": pac89.aligning_moment(c, fzs, sa, cam)}
        has = {"fx": self.has_longitudinal, "fy": self.has_lateral, "mz": self.has_aligning}
        return {k: np.where(on, np.broadcast_to(v, fz.shape), 0.0) if has[k] else np.full(fz.shape, np.nan)
                for k, v in out.items()}

    # -- evaluation (SI in, SI out, ISO-W) -----------------------------------------
    def fy(self, fz, slip_angle, camber=0.0):
        """Lateral force [N] (ISO-W) at load [N], slip angle [rad], camber [rad]."""
        return pac89.lateral_force(self.coefficients, fz, slip_angle, camber)

    def fx(self, fz, slip_ratio):
        """Longitudinal force [N] at load [N] and slip ratio [-]."""
        return pac89.longitudinal_force(self.coefficients, fz, slip_ratio)

    def mz(self, fz, slip_angle, camber=0.0):
        """Aligning moment [N*m] (ISO-W)."""
        return pac89.aligning_moment(self.coefficients, fz, slip_angle, camber)

    # A part is absent when its block is all zeros or neutral (zero slip stiffness, BCD = 0, as
    # format_tir writes a part that was not fitted); any other block is a model and is checked.
    @property
    def has_lateral(self) -> bool:
        c = self.coefficients
        return c["a3"] != 0.0 and any(c[k] != 0.0 for k in pac89.LATERAL)

    @property
    def has_longitudinal(self) -> bool:
        c = self.coefficients
        return (c["b3"] != 0.0 or c["b4"] != 0.0) and any(c[k] != 0.0 for k in pac89.LONGITUDINAL)

    @property
    def has_aligning(self) -> bool:
        c = self.coefficients
        return (c["c3"] != 0.0 or c["c4"] != 0.0) and any(c[k] != 0.0 for k in pac89.ALIGNING)

    def cornering_stiffness(self, fz, camber=0.0):
        """Cornering stiffness BCD [N/rad] at load ``fz`` [N] (PAC89: a3 sin(2 atan(Fz/a4)) per degree)."""
        f = pac89.lateral_factors(self.coefficients, np.asarray(fz, float) * 1e-3, np.degrees(camber))
        return f.B * f.C * f.D * 180.0 / math.pi

    def mirrored(self) -> "Pac89Tyre":
        """The same tyre mounted on the other side: ply steer and conicity terms flip.

        Exact at any camber: F'(a, g) = -F(-a, -g) for Fy and Mz (PAC89's E and
        BCD depend on |gamma| only).
        """
        c = dict(self.coefficients)
        for k in ("a9", "a10", "a12", "a13", "c12", "c13", "c16", "c17"):
            c[k] = -c[k]
        side = "RIGHT" if self.tyreside.upper() == "LEFT" else "LEFT"
        ranges = dict(self.ranges)
        if "camber" in ranges:
            ranges["camber"] = (-ranges["camber"][1], -ranges["camber"][0])
        return replace(self, coefficients=c, tyreside=side, ranges=ranges)

    def on_road(self, friction: float) -> "Pac89Tyre":
        """This tyre on a road of ``friction`` x the test surface's friction (:meth:`Tyre.on_road`).

        The peak factors D = a1 Fz^2 + a2 Fz, b1 Fz^2 + b2 Fz and c1 Fz^2 + c2 Fz scale; the
        stiffness BCD (a3, a4; b3, b4, b5; c3-c6) does not, so B = BCD / (C D) rises as D falls.
        """
        f = self._check_friction(friction)
        c = dict(self.coefficients)
        for k in ("a1", "a2", "b1", "b2", "c1", "c2"):
            c[k] = c[k] * f
        return replace(self, coefficients=c, name=self.name if f == 1.0 else f"{self.name} (road friction x{f:g})")

    # -- physical checks -----------------------------------------------------------
    def check(self, n: int = 41) -> list[str]:
        """Problems of the model over its declared load and camber range (empty when physical).

        Lateral part (unless the tyre is longitudinal-only): C = a0 > 0,
        D > 0, a4 != 0, BCD > 0 (a positive cornering stiffness), E <= 1,
        peak friction D/Fz <= 5.  Longitudinal part when present: C = b0 > 0,
        D > 0, BCD > 0, E <= 1.  Aligning part when present: C = c0 > 0,
        D != 0, E <= 1 (Mz's D is negative in PAC89's convention).  Then
        finite forces over the slip ranges, and every coefficient of a part
        the file gives (:attr:`missing`).  The load range is the fitted or
        declared ``ranges['fz']``, else 0.2-2 x FNOMIN, else 1-10 kN.
        """
        return self._check_range(None, n)

    def _check_range(self, fz_range, n):
        v = self.validity()
        lo, hi = fz_range or v["fz"]
        fzk = np.linspace(lo, hi, n)[:, None] * 1e-3
        gam = np.unique(np.degrees(np.linspace(*v["camber"], 5)))[None, :]
        c = self.coefficients
        problems = [f"required coefficient {k} is missing" for k in self.missing]
        span = f"(checked Fz {lo:.0f}-{hi:.0f} N)"

        with np.errstate(all="ignore"):
            parts = []
            if self.has_lateral or not self.has_longitudinal:
                if c["a4"] == 0.0:
                    problems.append("lateral: a4 = 0 (BCD = a3 sin(2 atan(Fz/a4)) is undefined)")
                parts.append(("lateral", pac89.lateral_factors(c, fzk, gam), True))
            if self.has_longitudinal:
                parts.append(("longitudinal", pac89.longitudinal_factors(c, fzk), True))
            if self.has_aligning:
                parts.append(("aligning", pac89.aligning_factors(c, fzk, gam), False))
            for part, f, positive_d in parts:
                shape = np.broadcast_shapes(np.shape(f.C), np.shape(f.D), np.shape(f.E), np.shape(f.B))
                C, D, E, B = (np.broadcast_to(x, shape) for x in (f.C, f.D, f.E, f.B))
                BCD = B * C * D
                tests = [(~(C > 0), "C <= 0"), (~(D > 0) if positive_d else ~(D != 0), "D <= 0" if positive_d
                                                                                      else "D = 0"),
                         (~(E <= 1), "E > 1")]
                if positive_d:
                    tests.append((~(BCD > 0), "BCD <= 0 (the slip stiffness is not positive)"))
                if part == "lateral":
                    tests.append((np.abs(D) / (fzk * 1e3) > 5.0, "peak friction D/Fz > 5"))
                for bad, what in tests:
                    if np.any(bad):
                        row = int(np.argmax(np.any(bad.reshape(bad.shape[0], -1), axis=1)))
                        problems.append(f"{part} model is not physical: {what} at Fz = {fzk[row, 0] * 1e3:.0f} N "
                                        f"{span}")
        if not problems:
            problems += self._finite_problems(n)
        return problems

    # -- files ----------------------------------------------------------------------
    @classmethod
    def from_file(cls, path) -> "Pac89Tyre":
        """Read a PAC89 ``.tir`` or a Chrono PAC89 JSON file.

        A tyre file of another family is refused (:class:`~tyrefit.errors.FormatError`);
        :func:`tyrefit.io.tir.read_tyre` reads every family into its own class.
        """
        return cls(**(chrono_fields(path) if str(path).lower().endswith(".json") else read_pac89_fields(path)))

    def to_tir(self, path, force: bool = False):
        """Write the Adams PAC89 ``.tir`` (:func:`tyrefit.io.tir.write_tir`)."""
        return write_tir(self, path, force=force)

    def to_chrono_json(self, path, force: bool = False):
        """Write Chrono's PAC89 JSON (:func:`tyrefit.io.chrono_json.write_chrono_json`)."""
        return write_chrono_json(self, path, force=force)

    def to_json(self, path, force: bool = False):
        """Chrono's PAC89 JSON (:meth:`to_chrono_json`), the name the Python API gives it."""
        return self.to_chrono_json(path, force=force)

    def coefficient_table(self, names=pac89.ALL) -> list[dict]:
        return [{"name": k, "value": self.coefficients[k]} for k in names]

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, Pac89Tyre):
            return NotImplemented
        return all(getattr(self, f) == getattr(other, f) for f in (
            "coefficients", "unloaded_radius", "width", "fnomin", "lateral_stiffness",
            "vertical_stiffness", "rolling_resistance", "tyreside")) and \
            {k: tuple(v) for k, v in self.ranges.items()} == {k: tuple(v) for k, v in other.ranges.items()}

    @staticmethod
    def coefficients_from(mapping: Mapping[str, float]) -> dict[str, float]:
        return {k: float(mapping.get(k, 0.0)) for k in pac89.ALL}
