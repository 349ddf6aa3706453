"""Static tyre test rig (STTR) to rolling-tyre model: the pipeline of seed 003.

Komana, Els and Becker (seed 003) build a Pacejka '89 tyre from two days of
static tests instead of five days of field tests:

1. contact patch L(Fz, p), W, A (:mod:`tyrefit.rig.patch`);
2. vertical stiffness with hysteresis (:mod:`tyrefit.rig.vertical`);
3. static lateral push: lateral stiffness, mu = Fy/Fz with the falling Fz,
   static peak and sliding level (:mod:`tyrefit.rig.static`);
4. Eq. 1, lateral displacement to slip angle, calibrated once on a tyre
   tested on both rigs (:mod:`tyrefit.rig.conversion`);
5. the PAC89 fit of the converted data (:func:`tyrefit.fitting.fit_pac89`).

:func:`prepare_static_fit` does steps 1-4 and hands a slip-angle data set to
the fit::

    inp = prepare_static_fit(read_data("STTR.csv"), read_data("PATCH.csv"),
                             rig=RigCalibration.from_json("RIG.json"))
    result = fit_pac89(inp.data, cost="l1", tyre_info=inp.tyre_info)
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
import pandas as pd

from ..errors import DataError
from ..nomenclature import G0
from .conversion import (UNCALIBRATED, RigCalibration, RigRangeWarning, calibrate, displacement_to_slip,
                         eq1_slip_angle)
from .patch import PatchModel, fit_patch
from .static import PARTS, StaticAnalysis, analyse_static
from .vertical import VerticalModel, fit_vertical

__all__ = [
    "prepare_static_fit",
    "StaticFitInput",
    "RigCalibration",
    "RigRangeWarning",
    "UNCALIBRATED",
    "calibrate",
    "eq1_slip_angle",
    "fit_patch",
    "fit_vertical",
    "analyse_static",
    "PatchModel",
    "VerticalModel",
    "StaticAnalysis",
    "PARTS",
]


def _dataset(df: pd.DataFrame, kind: str, source: str, meta: dict):
    try:
        from ..io.readers import Dataset
    except ImportError:  # pragma: no cover - readers always present in a full install
        return df
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

    def apply_to(self, tyre):
        """Set lateral and vertical stiffness, vertical curve and FNOMIN on a :class:`Pac89Tyre`; return it."""
        tyre.lateral_stiffness = self.lateral_stiffness
        tyre.fnomin = self.fnomin
        if self.vertical_stiffness is not None:
            tyre.vertical_stiffness = self.vertical_stiffness
        if self.vertical_curve:
            tyre.vertical_curve = list(self.vertical_curve)
        return tyre

    # -- report --------------------------------------------------------------------------
    def plot_converted(self, ax=None, model=None):
        """Friction coefficient against converted slip angle per load; samples not used in grey.

        ``model`` (a :class:`Pac89Tyre` or a list of ``(label, tyre)``) is drawn at each run's mean load.
        """
        import matplotlib
        from matplotlib.figure import Figure

        if ax is None:
            ax = Figure(figsize=(7, 4.6)).subplots()
        colors = matplotlib.rcParams["axes.prop_cycle"].by_key()["color"]
        used = "rising" if self.part == "peak" else None
        models = [] if model is None else (model if isinstance(model, list) else [("model", model)])
        styles = ["-", "--", ":", "-."]
        for j, (run, g) in enumerate(self.converted.groupby("run", sort=True)):
            c = colors[j % len(colors)]
            a = np.degrees(np.abs(g["slip_angle"]))
            inuse = g["part"] == used if used else np.ones(len(g), bool)
            ax.plot(a[inuse], g["mu"][inuse], ".", ms=2.5, color=c)
            ax.plot(a[~inuse], g["mu"][~inuse], ".", ms=2.5, color="0.75")
            ax.plot([], [], "o", color=c, label=f"{g['load'].mean() / G0 if 'load' in g else g['fz'].mean() / G0:.0f} kg")
            fz = float(g["fz"].mean())
            aa = np.linspace(0, max(a.max(), 1.0), 200)
            for k, (lab, tyre) in enumerate(models):
                mu = -tyre.fy(fz, np.radians(aa)) / fz
                ax.plot(aa, mu, styles[k % 4], color=c, lw=1.3, label=lab if j == 0 else None)
        ax.set_xlabel("slip angle from Eq. 1 [deg]")
        ax.set_ylabel("friction coefficient Fy/Fz [-]")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7, ncol=2)
        return ax

    def report_section(self, report, model=None) -> None:
        """Append the static-rig pipeline to a :class:`tyrefit.io.report.Report`.

        Contact patch (seed 003 Fig. 2), vertical stiffness (Fig. 3), the static
        pushes (Fig. 5), Eq. 1 and the converted data, the part used and every
        note and range warning.  ``model``: optional fitted tyre(s) to overlay.
        """
        from matplotlib.figure import Figure

        from .static import __doc__ as static_doc

        r = report
        r.h2("Static tyre test rig (STTR) pipeline")
        r.p("Komana, Els and Becker (seed 003): contact patch -> vertical stiffness -> static lateral push -> "
            "Eq. 1 (lateral displacement to slip angle with the patch length L) -> PAC89 fit on mu = Fy/Fz.")
        for w in self.warnings:
            r.p("Range warning: " + w, cls="warn")
        r.h3("Contact patch")
        r.table(self.patch.table(), digits=4)
        if self.patch.laws:
            r.p(f"Pressure law across {len(self.patch.fits)} pressures (reference {self.patch.p_ref / 1e5:.2f} bar): "
                "power law theta_ref (p/p_ref)^m for gradients, breakpoints and widths; linear for intercepts.")
            r.table(self.patch.laws_table(), digits=4)
        fig = Figure(figsize=(13, 3.8))
        axes = fig.subplots(1, 3)
        self.patch.plot(getattr(self, "_patch_df", None), axes=axes)
        r.figure(fig, "Contact-patch length, width and area against load per pressure (cf. seed 003 Fig. 2); "
                      "dotted lines: fitted shoulder (breakpoint) loads.")
        if self.vertical is not None:
            r.h3("Vertical stiffness")
            r.table(self.vertical.table(self.patch), digits=4)
            r.p(f"VERTICAL_STIFFNESS = {self.vertical_stiffness * 1e-3:.1f} N/mm at {self.fnomin / G0:.0f} kg "
                "(mean of the loading and unloading tangents: the elastic middle of the hysteresis loop); "
                f"the Chrono JSON gets the loop's middle as a {len(self.vertical_curve or [])}-point curve.")
            fig = Figure(figsize=(6.5, 4.5))
            ax = fig.subplots()
            self.vertical.plot(getattr(self, "_vertical_df", None), ax=ax)
            r.figure(fig, "Vertical force against deflection, loading (solid) and unloading (dashed) (cf. Fig. 3).")
        r.h3("Static lateral push")
        r.table(self.static.table(), digits=4)
        r.p(f"LATERAL_STIFFNESS = {self.lateral_stiffness * 1e-3:.1f} N/mm at {self.fnomin / G0:.0f} kg "
            "(tangent at zero displacement of Fy = a + k dy + c dy^3 fitted up to half the static peak force, "
            "interpolated in load).  C from Eq. 2 uses the sliding level as the asymptote y_a.")
        fig = Figure(figsize=(12, 4.2))
        axes = fig.subplots(1, 2)
        self.static.plot(axes[0], "mu")
        self.static.plot(axes[1], "fz")
        r.figure(fig, "Left: mu = Fy/Fz with the measured load against lateral displacement; triangles: static "
                      "peaks, dashed: sliding levels (cf. Fig. 5).  Right: the measured load falls during the push.")
        r.h3("Eq. 1: displacement to slip angle")
        r.p(self.rig.summary() + ".  L is the contact-patch length at each sample's measured load and the test "
            "pressure.  n is the relaxation length in patch lengths: a rolling tyre at slip angle alpha carries "
            "its carcass deflected sideways by y with tan(alpha) = y / sigma, sigma = C_alpha / C_y.")
        fig = Figure(figsize=(6.5, 4.2))
        ax = fig.subplots()
        self.rig.plot(ax, u_max=max(1.2 * float(np.nanmax(np.abs(self.converted["u"]))), 0.1))
        r.figure(fig, "Eq. 1: slip angle against u = Delta y / L, uncalibrated (f = 1) and with the rig calibration.")
        r.h3(f"Part of the static curve used: '{self.part}'")
        doc = static_doc.split("Which part of the curve feeds the rolling-tyre fit")[1].split("Either way")[0]
        r.raw("<pre style='white-space:pre-wrap'>" + doc.strip("\n -") + "</pre>")
        n_r = int((self.converted["part"] == "rising").sum())
        r.p(f"{len(self.data.df) if hasattr(self.data, 'df') else len(self.data)} samples feed the fit "
            f"({n_r} rising, {len(self.converted) - n_r} sliding in the whole push).")
        fig = Figure(figsize=(7, 4.6))
        ax = fig.subplots()
        self.plot_converted(ax, model)
        r.figure(fig, "Converted static data: mu against the slip angle of Eq. 1 per load; grey samples are not "
                      "used with this part" + ("; lines: fitted model(s)" if model is not None else "") + ".")
        if self.notes:
            r.h3("Notes")
            r.bullets(self.notes)


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
        (seed 003: the tyre's maximum load at that pressure is reached when
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
                     "(seed 003: the maximum load at a pressure is reached when the patch becomes rectangular); "
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
