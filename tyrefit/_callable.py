"""Packages that are also the API function of their name (``tf.compare(...)``, ``tf.diagnose(...)``)."""

from __future__ import annotations

import importlib
import sys
import types
from collections.abc import Callable


def callable_package(name: str, workflow: Callable | str) -> None:
    """Make the package ``name`` callable as ``workflow``.

    Python binds a subpackage to its parent's attribute of the same name as soon as anything imports it,
    so ``tyrefit.compare`` cannot be both the package and a function; the package is made callable instead
    of renamed (every ``tyrefit.compare.*`` import stays as it is).  ``workflow`` may be named as
    ``'module:function'`` when it lives in a higher layer than the package (``tyrefit.diagnose`` is called
    as :func:`tyrefit.workflows.diagnose.diagnose`, which uses the package); it is resolved at the first call,
    like an entry point.
    """

    def target() -> Callable:
        if callable(workflow):
            return workflow
        module, _, attr = workflow.partition(":")
        return getattr(importlib.import_module(module), attr)

    class _Workflow(types.ModuleType):
        __doc__ = workflow.__doc__ if callable(workflow) else f"Callable as :func:`{workflow.replace(':', '.')}`."

        def __call__(self, *args, **kwargs):
            return target()(*args, **kwargs)

    sys.modules[name].__class__ = _Workflow
