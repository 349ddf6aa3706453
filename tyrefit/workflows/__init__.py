"""Workflows: data files to finished results, the one code path behind the Python API and the command line.

:mod:`tyrefit.workflows.fit` fits a tyre from rig records (PAC89 from dynamic or static-rig tests,
Magic Formula 5.2/6.1 from several records); ``tf.fit``, ``tyrefit fit`` and ``tyrefit batch fit`` all
call it, so the same data and options give the same tyre file.
"""
