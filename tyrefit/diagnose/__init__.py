"""Diagnosis: where a PAC89 model fails, which physical effect is missing, and the error falling as it is added.

>>> from tyrefit.diagnose import diagnose          # doctest: +SKIP
>>> dg = diagnose(dataset, rated_load=6000.0)      # doctest: +SKIP
>>> dg.accepted, dg.noise_floor                    # doctest: +SKIP
>>> dg.report("reports/diagnose")                  # doctest: +SKIP
"""

from .data import SweepData, prepare
from .engine import Candidate, Settings, Step, diagnose
from .result import Diagnosis

__all__ = ["diagnose", "Diagnosis", "Settings", "Step", "Candidate", "SweepData", "prepare"]
