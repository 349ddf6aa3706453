"""A validation of ``tyrefit diagnose`` that is not circular: its truths are not the catalogue's own forms.

**Synthetic.**  :mod:`.truth` writes a truth tyre and its effects in forms the
diagnose catalogue does not contain (no call into :mod:`tyrefit.effects` or
:mod:`tyrefit.models.pac89`); :mod:`.cases` samples it on rig layouts (one
sweep per load, load x camber x pressure grids, one-sided sweeps) with three
noise models; :mod:`.runner` diagnoses each case, scores it and tabulates the
rates with confidence intervals, cached per case.

Run ``python -m tyrefit.synthetic.validation --help``.
"""

from .cases import LAYOUTS, NOISE_MODELS, SIGMA, Case, make_case
from .runner import base_fit, markdown, plan_cases, rates, run, run_case
from .truth import EFFECT_FAMILY, EFFECTS, RATED_LOAD, TruthTyre

__all__ = ["LAYOUTS", "NOISE_MODELS", "SIGMA", "Case", "make_case", "base_fit", "markdown", "plan_cases", "rates",
           "run", "run_case", "EFFECT_FAMILY", "EFFECTS", "RATED_LOAD", "TruthTyre"]
