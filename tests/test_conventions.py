"""Issue 12: one meaning per name across the package.

``_DEG`` (and ``DEG``) is pi/180, degrees -> radians, in every module that
defines it (it once meant 180/pi in some); the inverse has names of its own
(``_RAD2DEG``, ``_RAD_TO_DEG``) and is 180/pi.
"""

from __future__ import annotations

import ast
import importlib
import math
import re
from pathlib import Path

import tyrefit

ROOT = Path(tyrefit.__file__).resolve().parent
TO_RAD = re.compile(r"^_?DEG$")
TO_DEG = re.compile(r"^_?RAD_?(2|TO_)DEG$")


def _module_constants():
    """(module, name) of every module-level assignment to a name of either pattern."""
    for p in sorted(ROOT.rglob("*.py")):
        parts = ("tyrefit",) + p.relative_to(ROOT).with_suffix("").parts
        mod = ".".join(parts[:-1] if parts[-1] == "__init__" else parts)
        for node in ast.parse(p.read_text(encoding="utf-8")).body:
            targets = node.targets if isinstance(node, ast.Assign) else \
                [node.target] if isinstance(node, ast.AnnAssign) else []
            for t in targets:
                if isinstance(t, ast.Name) and (TO_RAD.match(t.id) or TO_DEG.match(t.id)):
                    yield mod, t.id


def test_deg_means_degrees_to_radians_everywhere():
    found = list(_module_constants())
    assert len(found) >= 15, found  # the scan sees the package's constants
    wrong = []
    for mod, name in found:
        value = getattr(importlib.import_module(mod), name)
        want = math.pi / 180.0 if TO_RAD.match(name) else 180.0 / math.pi
        if not math.isclose(float(value), want, rel_tol=1e-15):
            wrong.append(f"{mod}.{name} = {value!r} (expected {want!r})")
    assert not wrong, "; ".join(wrong)
