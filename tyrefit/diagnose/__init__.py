"""Diagnosis: where a PAC89 model fails, which physical effect is missing, and the error falling as it is added.

>>> from tyrefit.diagnose import diagnose          # doctest: +SKIP
>>> dg = diagnose(dataset, rated_load=6000.0)      # doctest: +SKIP
>>> dg.accepted, dg.noise_floor                    # doctest: +SKIP
>>> dg.report("reports/diagnose")                  # doctest: +SKIP
"""

import sys as _sys
import types as _types

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


class _Workflow(_types.ModuleType):
    """``tyrefit.diagnose`` is this package and, called, :func:`workflow` (``tf.diagnose(data, start=...)``).

    Python binds the subpackage to the name ``diagnose`` of ``tyrefit`` as soon as anything imports it, so the
    package itself is made callable rather than renamed (every ``tyrefit.diagnose.*`` import stays as it is).
    """

    def __call__(self, *args, **kwargs):
        return workflow(*args, **kwargs)


_sys.modules[__name__].__class__ = _Workflow
