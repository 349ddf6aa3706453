"""Static tyre test rig (STTR) to rolling-tyre model: the pipeline of Komana, Els and Becker.

Komana, Els and Becker ("Cost efficient tyre testing, modelling and validation
for PBS assessments") build a Pacejka '89 tyre from two days of static tests
instead of five days of field tests:

1. contact patch L(Fz, p), W, A (:mod:`tyrefit.rig.patch`);
2. vertical stiffness with hysteresis (:mod:`tyrefit.rig.vertical`);
3. static lateral push: lateral stiffness, mu = Fy/Fz with the falling Fz,
   static peak and sliding level (:mod:`tyrefit.rig.static`);
4. Eq. 1, lateral displacement to slip angle, calibrated once on a tyre
   tested on both rigs (:mod:`tyrefit.rig.conversion`);
5. the PAC89 fit of the converted data (:func:`tyrefit.fitting.fit_pac89`).

:func:`prepare_static_fit` (:mod:`tyrefit.rig.pipeline`) does steps 1-4 and
hands a slip-angle data set to the fit; the pipeline's figures and report
section are :mod:`tyrefit.rig.report`::

    inp = prepare_static_fit(read_data("STTR.csv"), read_data("PATCH.csv"),
                             rig=RigCalibration.from_json("RIG.json"))
    result = fit_pac89(inp.data, cost="l1", tyre_info=inp.tyre_info)
"""

from __future__ import annotations

from .conversion import UNCALIBRATED, RigCalibration, RigRangeWarning, calibrate, eq1_slip_angle
from .patch import PatchModel, fit_patch
from .pipeline import StaticFitInput, prepare_static_fit
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
