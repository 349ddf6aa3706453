"""The PAC89 tyre: coefficients plus the design data a simulator needs.

:class:`Pac89Tyre` is the container that ``tyrefit fit`` produces, that
``.tir`` and Chrono JSON files are read into and written from, and that the
vehicle simulation evaluates.  Every value is SI (m, N, N/m, rad) except the
coefficients, which keep PAC89's own units and spelling (``a3``, ``b10``) so
they can be grepped against a ``.tir``.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field, replace

import numpy as np

from ..errors import ModelError
from ..models import pac89

__all__ = ["Pac89Tyre"]


@dataclass
class Pac89Tyre:
    """A Pacejka '89 tyre.

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
    """

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

    def __post_init__(self) -> None:
        coeffs = {k: 0.0 for k in pac89.ALL}
        coeffs.update({str(k).lower(): float(v) for k, v in dict(self.coefficients).items()})
        self.coefficients = coeffs

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

    @property
    def has_lateral(self) -> bool:
        c = self.coefficients
        return c["a0"] != 0.0 and (c["a1"] != 0.0 or c["a2"] != 0.0)

    @property
    def has_longitudinal(self) -> bool:
        c = self.coefficients
        return c["b0"] != 0.0 and (c["b1"] != 0.0 or c["b2"] != 0.0)

    @property
    def has_aligning(self) -> bool:
        c = self.coefficients
        return c["c0"] != 0.0 and (c["c1"] != 0.0 or c["c2"] != 0.0)

    def cornering_stiffness(self, fz, camber=0.0):
        """Cornering stiffness BCD [N/rad] at load ``fz`` [N] (PAC89: a3 sin(2 atan(Fz/a4)) per degree)."""
        f = pac89.lateral_factors(self.coefficients, np.asarray(fz, float) * 1e-3, np.degrees(camber))
        return f.B * f.C * f.D * 180.0 / math.pi

    def mirrored(self) -> "Pac89Tyre":
        """The same tyre mounted on the other side: ply steer and conicity terms flip."""
        c = dict(self.coefficients)
        for k in ("a9", "a10", "a12", "a13", "c12", "c13", "c16", "c17"):
            c[k] = -c[k]
        side = "RIGHT" if self.tyreside.upper() == "LEFT" else "LEFT"
        return replace(self, coefficients=c, tyreside=side)

    # -- physical checks -----------------------------------------------------------
    def check_physical(self, fz_range: tuple[float, float] | None = None, n: int = 50) -> None:
        """Raise :class:`ModelError` unless C > 0, D > 0 and E <= 1 over the load range.

        The range defaults to the fitted ``ranges['fz']`` or 0.2-2 x FNOMIN.
        The lateral part is checked unless the tyre is longitudinal-only; the
        longitudinal part only when present.
        """
        lo, hi = fz_range or self.ranges.get("fz") or (
            (0.2 * self.fnomin, 2.0 * self.fnomin) if self.fnomin else (1000.0, 10000.0))
        fzk = np.linspace(lo, hi, n) * 1e-3
        c = self.coefficients
        parts = []
        if self.has_lateral or not self.has_longitudinal:
            parts.append(("lateral", pac89.lateral_factors(c, fzk, 0.0 * fzk)))
        if self.has_longitudinal:
            parts.append(("longitudinal", pac89.longitudinal_factors(c, fzk)))
        for part, f in parts:
            C, D, E = (np.broadcast_to(v, fzk.shape) for v in (f.C, f.D, f.E))
            for bad, what in ((C <= 0, "C <= 0"), (D <= 0, "D <= 0"), (E > 1, "E > 1")):
                if np.any(bad):
                    at = fzk[np.argmax(bad)] * 1e3
                    raise ModelError(f"{part} model is not physical: {what} at Fz = {at:.0f} N "
                                     f"(checked {lo:.0f}-{hi:.0f} N)")

    # -- files ----------------------------------------------------------------------
    @classmethod
    def from_file(cls, path) -> "Pac89Tyre":
        """Read a PAC89 ``.tir`` or a Chrono PAC89 JSON file."""
        from ..io.tir import read_tyre

        return read_tyre(path)

    def to_tir(self, path, force: bool = False):
        from ..io.tir import write_tir

        return write_tir(self, path, force=force)

    def to_chrono_json(self, path, force: bool = False):
        from ..io.chrono_json import write_chrono_json

        return write_chrono_json(self, path, force=force)

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
