"""Tyres as the vehicle simulation sees them: one axle at its static load.

The bicycle model of Pham et al. (2025) evaluates each axle's tyre curves at the static axle
load (no load transfer, Eq. 8-9): F_x,i = eta F_z,i M_x,i(lambda_i) and
F_y,i = eta F_z,i M_y,i(alpha_i).  The curves come from any tyre behind the
:class:`~tyrefit.tyres.base.Tyre` interface (a fitted PAC89 ``.tir``, a vendor's
MF 5.2 / PAC2002 or MF 6.1 / 6.2 file, a Chrono PAC89 JSON) at that load, in
pure slip (the bicycle model of Pham et al. takes Fx from the slip ratio and Fy
from the slip angle), at the tyre's nominal pressure and speed.
:class:`AxleTyre` tabulates the axle's two tyres once (a left tyre and its
mirror image on the right, so conicity and ply-steer offsets cancel as on a
real axle) on dense slip grids and interpolates, which keeps the time loop
fast and each family's sign mapping where it lives (its model module).

Also here: the bundled default tyres of ``tyrefit sim`` (hard front, soft
rear); :func:`tyrefit.synthetic.vehicle_tyres.fit_vehicle_tyres` makes them from
the bundled synthetic data with the package's fitter.
"""

from __future__ import annotations

import math
import os
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..errors import DataError, ModelError
from ..tyres.base import Tyre, require_physical
from ..io.datasets import data_path
from ..io.tir import read_tyre

try:  # the compiled routine behind np.interp, without its Python-level checks (hot loop)
    from numpy._core.multiarray import interp as _interp
except ImportError:  # pragma: no cover - older NumPy
    try:
        from numpy.core.multiarray import interp as _interp
    except ImportError:
        _interp = np.interp

__all__ = [
    "AxleTyre",
    "load_tyre",
    "default_tyres",
    "DEFAULT_FRONT",
    "DEFAULT_REAR",
]

#: bundled default tyre files in ``data/sim/`` (front: hard low-wear, rear: soft)
DEFAULT_FRONT = "hard_front.tir"
DEFAULT_REAR = "soft_rear.tir"


def _grid(limit: float, n: int, c: float = 5.0) -> np.ndarray:
    """Symmetric grid on [-limit, limit], dense near zero (sinh spacing)."""
    u = np.linspace(-1.0, 1.0, n)
    return limit * np.sinh(c * u) / math.sinh(c)


@dataclass
class AxleTyre:
    """The tyres of one axle at a fixed (static) load, tabulated.

    Parameters
    ----------
    tyre : Tyre
        The (left) tyre, any family; the right one is its mirror image.
    fz : float
        Load per tyre [N].
    n_tyres : int
        Tyres on the axle (2: left + mirrored right).
    n_points : int
        Table size per curve.

    Notes
    -----
    Forces are axle totals for condition eta = 1; the vehicle multiplies them
    by eta (Pham et al. 2025, Eq. 8-9), which scales the curve without moving its peak.
    """

    tyre: Tyre
    fz: float
    n_tyres: int = 2
    n_points: int = 6001
    slip_ratio_grid: np.ndarray = field(init=False, repr=False)
    slip_angle_grid: np.ndarray = field(init=False, repr=False)
    fx_table: np.ndarray = field(init=False, repr=False)
    fy_table: np.ndarray = field(init=False, repr=False)
    dfx_table: np.ndarray = field(init=False, repr=False)
    dfy_table: np.ndarray = field(init=False, repr=False)

    def __post_init__(self) -> None:
        if not self.tyre.has_longitudinal:
            raise ModelError(f"tyre {self.tyre.name!r} has no longitudinal model; the vehicle simulation needs Fx: "
                             "fit it with slip-ratio data")
        if not (self.fz > 0):
            raise ModelError(f"axle load per tyre must be positive, got {self.fz!r} N")
        self.slip_ratio_grid = _grid(1.0, self.n_points)
        self.slip_angle_grid = _grid(1.2, self.n_points)
        left, right = self.tyre, self.tyre.mirrored()
        half = self.n_tyres / 2.0
        fz = float(self.fz)
        self.fx_table = half * (np.asarray(left.fx(fz, self.slip_ratio_grid))
                                + np.asarray(right.fx(fz, self.slip_ratio_grid)))
        self.fy_table = half * (np.asarray(left.fy(fz, self.slip_angle_grid))
                                + np.asarray(right.fy(fz, self.slip_angle_grid)))
        if not (np.all(np.isfinite(self.fx_table)) and np.all(np.isfinite(self.fy_table))):
            raise ModelError(f"tyre {self.tyre.name!r} gives non-finite forces at {fz:.0f} N; the simulation "
                             "cannot use it")
        i, j = int(np.argmax(self.fx_table)), int(np.argmin(self.fx_table))
        if not (i > j and self.fx_table[i] > 0 > self.fx_table[j]):
            raise ModelError(f"tyre {self.tyre.name!r} gives no usable Fx curve at the wheel load {fz:.0f} N "
                             f"(no braking peak below a driving peak){_outside(self.tyre, fz)}; the simulation "
                             "cannot use it")
        self.dfx_table = np.gradient(self.fx_table, self.slip_ratio_grid)
        self.dfy_table = np.gradient(self.fy_table, self.slip_angle_grid)
        i = int(np.argmax(self.fx_table))
        j = int(np.argmin(self.fx_table))
        self._peak_drive = (float(self.slip_ratio_grid[i]), float(self.fx_table[i]))
        self._peak_brake = (float(self.slip_ratio_grid[j]), float(self.fx_table[j]))
        # lateral: the stable branch between the two peaks (Fy falls with alpha in ISO-W), increasing in Fy
        ia, ib = int(np.argmax(self.fy_table)), int(np.argmin(self.fy_table))
        lo, hi = min(ia, ib), max(ia, ib)
        fy_b, a_b = self.fy_table[lo:hi + 1][::-1], self.slip_angle_grid[lo:hi + 1][::-1]
        keep = np.concatenate([[True], np.diff(fy_b) > 0])
        self._inv_fy, self._inv_a = fy_b[keep], a_b[keep]
        # the stable (monotone) branch between the braking and driving peaks, for inversion
        self._inv_f = self.fx_table[j:i + 1]
        self._inv_s = self.slip_ratio_grid[j:i + 1]
        if np.any(np.diff(self._inv_f) <= 0):
            keep = np.concatenate([[True], np.diff(self._inv_f) > 0])
            self._inv_f, self._inv_s = self._inv_f[keep], self._inv_s[keep]

    # -- curves (axle totals, eta = 1) -------------------------------------------
    def fx(self, slip_ratio):
        """Axle longitudinal force [N] at slip ratio [-] (driving positive)."""
        return _interp(slip_ratio, self.slip_ratio_grid, self.fx_table)

    def fy(self, slip_angle):
        """Axle lateral force [N] at ISO-W slip angle [rad] (positive angle -> negative force)."""
        return _interp(slip_angle, self.slip_angle_grid, self.fy_table)

    def slip_stiffness(self, slip_ratio):
        """dFx/d(slip ratio) [N] of the axle."""
        return _interp(slip_ratio, self.slip_ratio_grid, self.dfx_table)

    def cornering_stiffness(self, slip_angle=0.0):
        """-dFy/d(slip angle) [N/rad] of the axle (positive for a normal tyre)."""
        return -_interp(slip_angle, self.slip_angle_grid, self.dfy_table)

    @property
    def peak_drive(self) -> tuple[float, float]:
        """(slip ratio, axle force [N]) at the driving peak."""
        return self._peak_drive

    @property
    def peak_brake(self) -> tuple[float, float]:
        """(slip ratio, axle force [N]) at the braking peak (both negative)."""
        return self._peak_brake

    @property
    def mu_peak(self) -> float:
        """Peak longitudinal friction coefficient (mean of driving and braking peaks) [-]."""
        return 0.5 * (self._peak_drive[1] - self._peak_brake[1]) / (self.n_tyres * self.fz)

    @property
    def mu_y_peak(self) -> float:
        """Peak lateral friction coefficient [-]."""
        return float(np.max(np.abs(self.fy_table))) / (self.n_tyres * self.fz)

    def slip_angle_for_force(self, force):
        """ISO-W slip angle [rad] on the stable branch that gives axle lateral force ``force`` [N] (eta = 1).

        Forces beyond the peaks give the slip angle of the peak.
        """
        return _interp(force, self._inv_fy, self._inv_a)

    def slip_for_force(self, force):
        """Slip ratio on the stable branch that gives axle force ``force`` [N] (eta = 1); clipped to the peaks."""
        return _interp(force, self._inv_f, self._inv_s)

    def slip_for_mu_share(self, share: float) -> tuple[float, float]:
        """Slip ratios (braking, driving) on the rising branch where |Fx| = share x its peak (Eq. 49-50)."""
        if not 0.0 < share <= 1.0:
            raise ModelError(f"peak share must be in (0, 1], got {share!r}")
        lo = float(np.interp(share * self._peak_brake[1], self._inv_f, self._inv_s))
        hi = float(np.interp(share * self._peak_drive[1], self._inv_f, self._inv_s))
        return lo, hi


# ------------------------------------------------------------------------------ files

def _outside(tyre, fz: float) -> str:
    """', N x outside its declared load range lo-hi N' when ``fz`` is outside it, else ''."""
    try:
        lo, hi = tyre.validity()["fz"]
    except (AttributeError, KeyError, TypeError):  # pragma: no cover - every tyrefit tyre has validity()
        return ""
    if lo <= fz <= hi:
        return ""
    return f", {fz / hi if fz > hi else lo / fz:.1f} x outside its declared load range {lo:.0f}-{hi:.0f} N"


def load_tyre(path: str | os.PathLike, allow_unphysical: bool = False) -> Tyre:
    """Read any tyre file for the simulation (PAC89, MF 5.2, MF 6.1/6.2, Chrono JSON).

    It must model Fx and Fy, and be physical over its declared range
    (:meth:`~tyrefit.tyres.base.Tyre.check`) unless ``allow_unphysical``.
    """
    p = Path(path)
    if not p.exists():
        raise DataError(f"{p}: tyre file not found")
    if p.is_dir():
        raise DataError(f"{p}: is a folder; give a tyre file (.tir or Chrono .json)")
    tyre = read_tyre(p)
    require_physical(tyre, str(p), allow_unphysical=allow_unphysical)
    for part, ok, need in (("longitudinal", tyre.has_longitudinal, "slip-ratio"),
                           ("lateral", tyre.has_lateral, "slip-angle")):
        if not ok:
            raise ModelError(f"{p}: the tyre has no {part} model; the vehicle simulation needs Fx and Fy: fit it "
                             f"with {need} data")
    return tyre


def default_tyres() -> tuple[Tyre, Tyre]:
    """The bundled (front, rear) = (hard, soft) tyres of ``tyrefit sim`` (``data/sim/*.tir``).

    They are PAC89 fits of the bundled synthetic data by the package's fitter
    (:func:`tyrefit.synthetic.vehicle_tyres.fit_vehicle_tyres`); each file's header records how it was made.
    """
    return load_tyre(data_path("sim", DEFAULT_FRONT)), load_tyre(data_path("sim", DEFAULT_REAR))
