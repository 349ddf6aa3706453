"""Diagnosis: where a PAC89 model fails, which physical effect is missing, and the error falling as it is added.

>>> from tyrefit.diagnose import diagnose          # doctest: +SKIP
>>> dg = diagnose(dataset, rated_load=6000.0)      # doctest: +SKIP
>>> dg.accepted, dg.noise_floor                    # doctest: +SKIP
>>> dg.report("reports/diagnose")                  # doctest: +SKIP
"""

from .._callable import callable_package
from .data import SweepData, prepare
from .engine import Candidate, Settings, Step, diagnose
from .result import Diagnosis

__all__ = ["diagnose", "Diagnosis", "Settings", "Step", "Candidate", "SweepData", "prepare"]


def workflow(data, *, start=None, rated_load=None, convention: str = "iso", seed: int = 0) -> Diagnosis:
    """What the start model misses, effect by effect, with held-out evidence (``tyrefit diagnose`` as a function).

    ``data``: a slip-angle record (path or Dataset).  Returns :class:`Diagnosis` (``accepted``, ``steps``,
    ``summary()``, ``report(dir)``).
    """
    from ..io.readers import read_data

    ds = data if hasattr(data, "df") else read_data(data, convention=convention)
    return diagnose(ds, start=list(start or []), rated_load=rated_load, seed=int(seed))


callable_package(__name__, workflow)
