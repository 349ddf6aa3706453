"""Fitting PAC89 to tyre test data.

:func:`fit_pac89` runs the procedure of Komana, Els and Becker (*Cost efficient tyre testing,
modelling and validation for PBS assessments*, section 4.3):
Eq. 2-4 initial estimates per sweep (:mod:`tyrefit.fitting.initial`), then a
global fit on the friction coefficient (:mod:`tyrefit.fitting.engine`), and
returns a :class:`FitResult` (:mod:`tyrefit.fitting.result`).
"""

from .engine import fit_pac89, identifiability, point_scatter, prepare_data
from .initial import estimate_sweep, estimate_sweeps
from .noise import noise_floor
from .result import FitResult

# noise_floor: the within-sweep noise floor models are judged against (a smooth curve per sweep, pooled);
# point_scatter: the point-to-point scatter the robust costs scale by (neighbour differences, hysteresis
# counted as noise): a different quantity, reported beside the floor as the fit's point scatter.

__all__ = ["fit_pac89", "FitResult", "estimate_sweep", "estimate_sweeps", "identifiability", "noise_floor",
           "point_scatter", "prepare_data"]
