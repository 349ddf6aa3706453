"""tyrefit: tyre test-rig measurements to tyre models engineers can trust.

Read rig data (CSV with unit headers, TYDEX, FSAE TTC), turn static-rig tests
into slip-angle curves, fit Pacejka '89, export ``.tir`` and Chrono JSON,
diagnose what the model misses, and drive vehicle simulations with the result.
"""

__version__ = "0.1.0"
