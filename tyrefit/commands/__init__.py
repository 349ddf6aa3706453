"""Command implementations: ``run(args) -> int`` for each ``tyrefit`` subcommand.

They only wire library calls together; argument parsing lives in
:mod:`tyrefit.cli`.
"""
