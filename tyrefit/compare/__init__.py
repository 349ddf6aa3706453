"""Comparing tyre models: with each other and with data (:mod:`.tyres`), and the
camber brush model against PAC89 (:mod:`.brush`)."""

from .._callable import callable_package
from ..io.readers import read_data
from ..io.tir import read_tyre
from ..tyres.base import Tyre, require_physical
from .tyres import Comparison, LoadComparison, binned_curve, compare_tyres, data_metrics, model_metrics

__all__ = ["Comparison", "LoadComparison", "compare_tyres", "model_metrics", "data_metrics", "binned_curve"]


def workflow(a, b, data=None, *, convention: str = "iso", names=None, allow_unphysical: bool = False) -> Comparison:
    """Two tyres on the quantities engineers read, channel by channel (``tyrefit compare`` as a function).

    ``a``, ``b``: tyres or tyre files (refused, unless ``allow_unphysical``, when not physical over their
    declared range); ``data``: an optional record (path or Dataset) both are scored against.
    """
    tyres = []
    for t in (a, b):
        tyre = t if isinstance(t, Tyre) else read_tyre(t)
        require_physical(tyre, str(getattr(tyre, "name", t)), allow_unphysical=allow_unphysical)
        tyres.append(tyre)
    ds = None if data is None else (data if hasattr(data, "df") else read_data(data, convention=convention))
    nm = tuple(names) if names else tuple(str(getattr(t, "name", f"tyre {i}")) for i, t in enumerate(tyres, 1))
    return compare_tyres(tyres[0], tyres[1], ds, names=nm)


callable_package(__name__, workflow)
