"""Diagnosis: where a PAC89 model fails, which physical effect is missing, and the error falling as it is added.

>>> from tyrefit.diagnose import diagnose          # doctest: +SKIP
>>> dg = diagnose(dataset, rated_load=6000.0)      # doctest: +SKIP
>>> dg.accepted, dg.noise_floor                    # doctest: +SKIP
>>> dg.report("reports/diagnose")                  # doctest: +SKIP
"""

from .._callable import callable_package
from .channels import ChannelDiagnosis, diagnose_channels
from .data import SweepData, combine_records, prepare
from .engine import Candidate, Settings, Step, diagnose
from .result import Diagnosis

__all__ = ["diagnose", "Diagnosis", "Settings", "Step", "Candidate", "SweepData", "prepare", "ChannelDiagnosis",
           "diagnose_channels", "combine_records"]


#: ``tf.diagnose(...)``: the workflow of ``tyrefit diagnose`` (several records, every channel, ``base='mf61'``,
#: static-rig pushes), which lives in the workflow layer above this package
callable_package(__name__, "tyrefit.workflows.diagnose:diagnose")
