"""tyrefit: tyre test-rig measurements to tyre models engineers can trust.

Read rig data (CSV with unit headers, TYDEX, FSAE TTC), turn static-rig tests
into slip-angle curves, fit Pacejka '89 and Magic Formula 5.2/6.1, export
``.tir`` and Chrono JSON, diagnose what the model misses, and drive vehicle
simulations with the result.

The Python API (:mod:`tyrefit.api`)::

    import tyrefit as tf
    ds  = tf.read_data(tf.datasets.path("truck/tyre_a_dynamic.csv"))
    res = tf.fit(ds, model="pac89", cost="l1", size="385/65R22.5", rated_load=41678)
    res.tyre.to_tir("a.tir")

The names are imported on first use, so ``import tyrefit`` stays cheap for the command line.
"""

from ._version import __version__

__all__ = ["read_data", "read_tyre", "fit", "diagnose", "compare", "simulate", "datasets", "__version__"]


def __getattr__(name: str):
    import importlib

    if name in ("read_data", "read_tyre", "fit", "simulate"):
        return getattr(importlib.import_module("tyrefit.api"), name)
    if name in ("datasets", "errors", "compare", "diagnose"):  # compare, diagnose: callable packages
        return importlib.import_module(f"tyrefit.{name}")
    raise AttributeError(f"module 'tyrefit' has no attribute {name!r}")


def __dir__():
    return sorted(list(globals()) + __all__)
