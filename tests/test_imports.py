"""Every tyrefit module imports on its own in a fresh interpreter (no import cycles, no missing names).

An import cycle shows only when the cycle's *second* module is imported first,
so each module is imported in its own ``python -c "import tyrefit.x"``
process.  To keep the cost to a few seconds, one process imports a batch of
modules, each in a fresh copy of the interpreter state: it forks per module
(POSIX), so every child starts from an interpreter that has imported only
numpy, scipy, pandas and the standard library, never another tyrefit module.
"""

from __future__ import annotations

import os
import pkgutil
import subprocess
import sys

import pytest

import tyrefit


def _modules() -> list[str]:
    out = ["tyrefit"]
    for m in pkgutil.walk_packages(tyrefit.__path__, "tyrefit."):
        out.append(m.name)
    return sorted(out)


MODULES = _modules()

_CHILD = r"""
import importlib, os, sys, traceback
import numpy, scipy.optimize, pandas  # the third-party base every child shares (not tyrefit)
assert not any(k == "tyrefit" or k.startswith("tyrefit.") for k in sys.modules)
failed = []
for name in sys.argv[1:]:
    pid = os.fork()
    if pid == 0:
        try:
            importlib.import_module(name)
        except BaseException:
            sys.stderr.write(f"--- import {name} failed:\n{traceback.format_exc()}\n")
            os._exit(1)
        os._exit(0)
    _, status = os.waitpid(pid, 0)
    if status != 0:
        failed.append(name)
print("FAILED:" + ",".join(failed))
sys.exit(1 if failed else 0)
"""


def test_module_list_is_complete():
    assert "tyrefit.fitting.core" in MODULES and "tyrefit.diagnose.fitter" in MODULES
    assert len(MODULES) > 100


@pytest.mark.skipif(not hasattr(os, "fork"), reason="the batched check forks per module (POSIX)")
def test_every_module_imports_alone_in_a_fresh_process():
    r = subprocess.run([sys.executable, "-c", _CHILD, *MODULES], capture_output=True, text=True, timeout=600)
    assert r.returncode == 0, r.stdout[-2000:] + r.stderr[-6000:]


@pytest.mark.parametrize("name", ["tyrefit.fitting.core", "tyrefit.diagnose.fitter", "tyrefit.rig.conversion",
                                  "tyrefit.fitting.mf", "tyrefit.cli"])
def test_key_modules_import_with_plain_python_c(name):
    """The check exactly as the issue states it, ``python -c "import tyrefit.<m>"``, for the fitting core's users."""
    r = subprocess.run([sys.executable, "-c", f"import {name}"], capture_output=True, text=True, timeout=120)
    assert r.returncode == 0, r.stderr[-3000:]
