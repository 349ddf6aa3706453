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


def workflow(data, *, start=None, rated_load=None, convention: str = "iso", seed: int = 0,
             channels: bool = True) -> Diagnosis:
    """What the start model misses, effect by effect, with held-out evidence (``tyrefit diagnose`` as a function).

    ``data``: a slip-angle record (path or Dataset), or several records of one tyre (a cornering and a
    drive/brake record).  With ``channels`` (default) the aligning moment and the drive/brake force are
    diagnosed too where the records carry them (:mod:`tyrefit.diagnose.channels`).  Returns
    :class:`Diagnosis` (``accepted``, ``steps``, ``channels``, ``summary()``, ``report(dir)``).
    """
    from ..io.readers import read_data

    items = list(data) if isinstance(data, (list, tuple)) else [data]
    ds = combine_records([d if hasattr(d, "df") else read_data(d, convention=convention) for d in items])
    dg = diagnose(ds, start=list(start or []), rated_load=rated_load, seed=int(seed))
    if channels:
        dg.channels, dg.channels_absent = diagnose_channels(ds, rated_load=rated_load, seed=int(seed))
    return dg


callable_package(__name__, workflow)
