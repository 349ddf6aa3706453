"""Fitting PAC89 to tyre test data.

:func:`fit_pac89` runs the procedure of Komana, Els and Becker (*Cost efficient tyre testing,
modelling and validation for PBS assessments*, section 4.3):
Eq. 2-4 initial estimates per sweep (:mod:`tyrefit.fitting.initial`), then a
global fit on the friction coefficient (:mod:`tyrefit.fitting.engine`), and
returns a :class:`FitResult` (:mod:`tyrefit.fitting.result`).
"""

from .engine import fit_pac89, identifiability, noise_floor, prepare_data
from .initial import estimate_sweep, estimate_sweeps
from .result import FitResult

#: the point-to-point scatter the fit weights by (neighbour differences, hysteresis counted as noise):
#: what ``tyrefit.fitting.noise_floor`` has always named here.  The within-sweep noise floor models are
#: judged against is :func:`tyrefit.fitting.noise.noise_floor`.
point_scatter = noise_floor

__all__ = ["fit_pac89", "FitResult", "estimate_sweep", "estimate_sweeps", "identifiability", "noise_floor",
           "point_scatter", "prepare_data"]
