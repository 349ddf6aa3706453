"""The static-rig pipeline: static tests of one tyre to a slip-angle data set for the PAC89 fit.

:func:`prepare_static_fit` runs steps 1-4 of the pipeline (contact patch, vertical stiffness, static
lateral push, Komana et al. Eq. 1) and returns a :class:`StaticFitInput`: the converted data, the
design data the tyre file needs (lateral and vertical stiffness, FNOMIN, the vertical curve, the
header lines) and the coefficients the static test itself fixes (:attr:`StaticFitInput.anchors`).
Its figures and report section are :mod:`tyrefit.rig.report`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace

import numpy as np
import pandas as pd

from . import report as _report
from ..errors import DataError
from ..io.readers import Dataset
from ..nomenclature import G0
from .conversion import UNCALIBRATED, RigCalibration, displacement_to_slip
from .patch import PatchModel, fit_patch
from .static import PARTS, StaticAnalysis, analyse_static
from .vertical import VerticalModel, fit_vertical

__all__ = ["prepare_static_fit", "StaticFitInput"]


def _dataset(df: pd.DataFrame, kind: str, source: str, meta: dict):
    return Dataset(df=df, kind=kind, source=source, convention="iso", meta=meta)



@dataclass
class StaticFitInput:
    """Static-rig data turned into a slip-angle data set, with everything the tyre file needs.

    Attributes
    ----------
    data : Dataset
        kind ``'slip_angle'``; columns ``run``, ``fz`` (measured) [N], ``fy``
        [N] and ``slip_angle`` [rad] in ISO-W (positive slip angle, negative
        ``fy``), ``pressure`` [Pa] and ``load`` (the push's set point) [N]
        where known: the samples of the chosen part.
    converted : DataFrame
        every static sample with ``u`` (= Delta y / L), ``length`` [m],
        ``slip_angle`` [rad], ``mu`` and ``part`` ('rising' / 'sliding').
    lateral_stiffness : float
        LATERAL_STIFFNESS at ``fnomin`` [N/m] (stage one of the static push).
    vertical_stiffness : float or None
        VERTICAL_STIFFNESS at ``fnomin`` [N/m] (None without vertical data).
    vertical_curve : list of (deflection [m], force [N]) or None
        Chrono ``Vertical Curve Data``.
    fnomin : float
        nominal load [N].
    notes : list of str
        what was assumed, and every range warning.
    part : str
        'peak' or 'sliding'.
    patch, static, vertical, rig
        the fitted models behind the numbers.
    """

    data: object
    converted: pd.DataFrame
    lateral_stiffness: float
    vertical_stiffness: float | None
    vertical_curve: list | None
    fnomin: float
    notes: list[str]
    part: str
    patch: PatchModel
    static: StaticAnalysis
    vertical: VerticalModel | None
    rig: RigCalibration
    pressure: float
    warnings: list[str] = field(default_factory=list)

    @property
    def anchors(self) -> dict[str, float]:
        """PAC89 coefficients the static test itself fixes, for ``part='peak'`` (else empty).

        The rising part ends at the static peak, so on its own it cannot tell
        a low, early peak from a high, late one.  What the converted data lack
        the static test measured directly, and Komana et al. read it off the
        same curve (Sec. 4.3): the peak D and the sliding asymptote y_a.  So

        * ``a0`` = C from Eq. 2, C = 1 + (1 - (2/pi) asin(y_a / D)), the median
          over the loads with a sliding plateau;
        * ``a1``, ``a2``: the PAC89 peak law D/Fz = (a1 Fz + a2) / 1000 (Fz in kN)
          fitted by least squares to the static peaks mu at the measured load
          at each peak (``a2`` alone, a1 = 0, with one load).

        The fit (``fit_pac89(..., fixed=inp.anchors)``) then finds the
        cornering-stiffness law (and whatever else the data identify) from
        the converted slip angles.
        """
        if self.part != "peak":
            return {}
        out: dict[str, float] = {}
        runs = self.static.runs
        c = np.array([r.shape_factor for r in runs])
        c = c[np.isfinite(c)]
        if c.size:
            out["a0"] = float(np.median(c))
        fzk = np.array([r.peak_fz for r in runs]) * 1e-3
        mu = np.array([r.max_mu for r in runs])
        if np.unique(np.round(fzk, 1)).size >= 2:
            slope, icpt = np.polyfit(fzk, mu, 1)
            out["a1"], out["a2"] = 1000.0 * float(slope), 1000.0 * float(icpt)
        elif fzk.size:
            out["a1"], out["a2"] = 0.0, 1000.0 * float(mu.mean())
        return out

    @property
    def fit_kwargs(self) -> dict:
        """Keyword arguments for :func:`tyrefit.fitting.fit_pac89`: ``tyre_info`` and ``fixed`` (the anchors)."""
        kw: dict = {"tyre_info": self.tyre_info}
        if self.anchors:
            kw["fixed"] = dict(self.anchors)
        return kw

    @property
    def tyre_info(self) -> dict:
        """Design data for :func:`tyrefit.fitting.fit_pac89` (``tyre_info=``) and the tyre file."""
        info = {"lateral_stiffness": self.lateral_stiffness, "fnomin": self.fnomin,
                "header": self.header_lines()}
        if self.vertical_stiffness is not None:
            info["vertical_stiffness"] = self.vertical_stiffness
        if self.vertical_curve:
            info["vertical_curve"] = self.vertical_curve
        return info

    def header_lines(self) -> list[str]:
        """Lines for the tyre file header: where the slip angles came from."""
        src = self.static.source or "static data"
        lines = [f"static-rig (STTR) data {src}, part '{self.part}', converted by Komana et al. Eq. 1 "
                 f"with the contact-patch length from {self.patch.source or 'patch data'}",
                 self.rig.summary(),
                 f"LATERAL_STIFFNESS from the static push at {self.fnomin / G0:.0f} kg"]
        if self.vertical is not None:
            lines.append(f"VERTICAL_STIFFNESS: mean of loading and unloading tangents at {self.fnomin / G0:.0f} kg "
                         f"({self.vertical.source})")
        if self.anchors:
            lines.append("held from the static test (peak part): " + ", ".join(
                f"{k} = {v:.5g}" for k, v in self.anchors.items()) + " (a0: Eq. 2 from the sliding level; "
                "a1, a2: static peaks)")
        lines += [f"range warning: {w}" for w in self.warnings]
        return lines

    def with_static_design(self, tyre):
        """A copy of a :class:`Pac89Tyre` with the static tests' lateral and vertical stiffness, vertical curve
        and FNOMIN (``tyre`` itself is not changed)."""
        design = {"lateral_stiffness": self.lateral_stiffness, "fnomin": self.fnomin}
        if self.vertical_stiffness is not None:
            design["vertical_stiffness"] = self.vertical_stiffness
        if self.vertical_curve:
            design["vertical_curve"] = list(self.vertical_curve)
        return replace(tyre, header=list(tyre.header), **design)

    # -- report --------------------------------------------------------------------------
    def plot_converted(self, ax=None, model=None):
        """Friction coefficient against converted slip angle per load; samples not used in grey.

        ``model`` (a :class:`Pac89Tyre` or a list of ``(label, tyre)``) is drawn at each run's mean load
        (:func:`tyrefit.rig.report.plot_converted`).
        """
        return _report.plot_converted(self, ax, model)

    def report_section(self, report, model=None) -> None:
        """Append the static-rig pipeline to a :class:`tyrefit.io.report.Report`
        (:func:`tyrefit.rig.report.report_section`).  ``model``: optional fitted tyre(s) to overlay."""
        _report.report_section(self, report, model)


def _frame(x):
    return getattr(x, "df", x), (getattr(x, "source", "") or "")


def prepare_static_fit(static_ds, patch_ds, *, rig: RigCalibration | None = None, part: str = "peak",
                       vertical_ds=None, rated_load: float | None = None) -> StaticFitInput:
    """Turn a static-rig lateral test into slip-angle data for the PAC89 fit.

    Parameters
    ----------
    static_ds : Dataset or DataFrame
        static lateral test (kind 'static'): ``run``, ``lateral_displacement``
        [m], ``fy`` [N] (same sign as the displacement), ``fz`` [N] measured,
        optional ``load`` [N], ``pressure`` [Pa].
    patch_ds : Dataset, DataFrame or PatchModel
        contact-patch data of the same tyre (length needed).
    rig : RigCalibration, optional
        Eq. 1 calibration from :func:`calibrate` / ``tyrefit rig calibrate``;
        None: f = 1.
    part : {'peak', 'sliding'}
        which part of each push feeds the fit (:mod:`tyrefit.rig.static`).
    vertical_ds : Dataset or DataFrame, optional
        vertical-stiffness test: VERTICAL_STIFFNESS and the Chrono curve.
    rated_load : float, optional
        FNOMIN [N]; default: the patch's shoulder load at the test pressure
        (Komana et al.: the tyre's maximum load at that pressure is reached when
        the patch becomes rectangular).

    Returns
    -------
    StaticFitInput

    Warns
    -----
    RigRangeWarning
        the data leave the calibrated range of ``rig``.
    """
    if part not in PARTS:
        raise DataError(f"unknown static part {part!r}; accepted: " + ", ".join(repr(p) for p in PARTS))
    ssrc = _frame(static_ds)[1]
    kind = getattr(static_ds, "kind", "static")
    if kind != "static":
        raise DataError(f"{ssrc or 'data'}: is a {kind} test; the static-rig pipeline needs a static lateral push "
                        "('lateral_displacement', 'fy', 'fz')")
    patch = patch_ds if isinstance(patch_ds, PatchModel) else fit_patch(patch_ds)
    static = analyse_static(static_ds)
    rig = rig or UNCALIBRATED
    notes: list[str] = []
    df = static.df
    pressure = df["pressure"].to_numpy(float) if "pressure" in df else None
    if pressure is None:
        p_test = patch.p_ref if len(patch.fits) > 1 else patch.fits[0].pressure
        notes.append(f"{ssrc or 'static data'} has no pressure column: patch length taken at "
                     f"{p_test / 1e5:.2f} bar" if np.isfinite(p_test) else
                     "no pressure in the static or patch data: the patch fit is used as it is")
    else:
        p_test = float(np.median(pressure))
    if np.isfinite(p_test) and len(patch.fits) > 1:
        tested = patch.pressures
        if np.min(np.abs(tested - p_test)) > 0.01 * p_test:
            notes.append(f"static test at {p_test / 1e5:.2f} bar, patch tested at "
                         + ", ".join(f"{p / 1e5:.2f}" for p in tested) + " bar: patch length from the pressure law")
    alpha, u = displacement_to_slip(df["lateral_displacement"].to_numpy(float), df["fz"].to_numpy(float), patch,
                                    pressure, rig)
    converted = df.copy()
    converted["length"] = np.abs(df["lateral_displacement"].to_numpy(float) / np.where(u == 0, np.nan, u))
    converted["u"] = u
    converted["slip_angle"] = alpha
    if not rig.calibrated:
        notes.append("Eq. 1 uncalibrated (f = 1): the relaxation length is taken equal to the patch length; "
                     "real tyres have several patch half-lengths, so slip angles are overstated and the cornering "
                     "stiffness understated. Calibrate once with 'tyrefit rig calibrate'.")
    sel = converted[converted["part"] == "rising"] if part == "peak" else converted
    # Eq. 1 maps displacement to slip with the displacement's sign; ISO-W: positive slip <-> negative fy
    out = pd.DataFrame({"run": sel["run"].to_numpy(int), "fz": sel["fz"].to_numpy(float),
                        "fy": -sel["fy"].to_numpy(float), "slip_angle": sel["slip_angle"].to_numpy(float)})
    if "pressure" in sel:
        out["pressure"] = sel["pressure"].to_numpy(float)
    # each push's load set point (the file's, else the load at zero displacement, as analyse_static takes
    # it): the measured load wanders along a push (by 8 % on the bundled truck pushes), and diagnosis and
    # MF fits take their load levels from the set point when there is one
    set_load = {rr.run: rr.load for rr in static.runs}
    out["load"] = (sel["load"].to_numpy(float) if "load" in sel and sel["load"].notna().all()
                   else sel["run"].map(set_load).to_numpy(float))
    warn_msgs = rig.warn(sel["u"].to_numpy(float), sel["fz"].to_numpy(float),
                         None if pressure is None else sel["pressure"].to_numpy(float),
                         where=ssrc or "static data")
    notes += [f"range warning: {m}" for m in warn_msgs]
    for rr in static.runs:
        notes += rr.notes
    # design data at the nominal load
    fnomin = float(rated_load) if rated_load is not None else patch.shoulder_load(p_test if np.isfinite(p_test)
                                                                                 else None)
    if rated_load is None:
        notes.append(f"FNOMIN = {fnomin / G0:.0f} kg: the patch's shoulder load at {p_test / 1e5:.2f} bar "
                     "(Komana et al.: the maximum load at a pressure is reached when the patch becomes rectangular); "
                     "give the rated load to override")
    lat = static.lateral_stiffness(fnomin)
    vertical = vstiff = vcurve = None
    vdf = None
    if vertical_ds is not None:
        vertical = vertical_ds if isinstance(vertical_ds, VerticalModel) else fit_vertical(vertical_ds)
        vdf = None if isinstance(vertical_ds, VerticalModel) else _frame(vertical_ds)[0]
        pv = p_test if np.isfinite(p_test) else None
        vstiff = vertical.vertical_stiffness(fnomin, pv)
        vcurve = vertical.curve(pv)
        notes += vertical.notes
    meta = {"converted_from": ssrc, "equation": "Komana et al. Eq. 1", "part": part,
            "rig": rig.to_dict(), "patch_source": patch.source}
    data = _dataset(out, "slip_angle", f"{ssrc or 'static data'} (Eq. 1, part '{part}')", meta)
    res = StaticFitInput(data=data, converted=converted, lateral_stiffness=lat, vertical_stiffness=vstiff,
                         vertical_curve=vcurve, fnomin=fnomin, notes=notes, part=part, patch=patch, static=static,
                         vertical=vertical, rig=rig, pressure=p_test, warnings=warn_msgs)
    res._patch_df = None if isinstance(patch_ds, PatchModel) else _frame(patch_ds)[0]
    res._vertical_df = vdf
    if not math.isfinite(lat):  # pragma: no cover - analyse_static guards this
        raise DataError(f"{ssrc}: lateral stiffness could not be computed")
    return res
