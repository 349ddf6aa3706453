"""Packages that are also the API function of their name (``tf.compare(...)``, ``tf.diagnose(...)``)."""

from __future__ import annotations

import sys
import types
from collections.abc import Callable


def callable_package(name: str, workflow: Callable) -> None:
    """Make the package ``name`` callable as ``workflow``.

    Python binds a subpackage to its parent's attribute of the same name as soon as anything imports it,
    so ``tyrefit.compare`` cannot be both the package and a function; the package is made callable instead
    of renamed (every ``tyrefit.compare.*`` import stays as it is).
    """

    class _Workflow(types.ModuleType):
        __doc__ = workflow.__doc__

        def __call__(self, *args, **kwargs):
            return workflow(*args, **kwargs)

    sys.modules[name].__class__ = _Workflow
