"""A tyre is finished when it is constructed: no code outside the tyre classes sets its attributes.

Design data, static-rig stiffnesses, names and header lines go in through the constructor or
:func:`dataclasses.replace` (:func:`tyrefit.tyres.size.with_design`,
:meth:`tyrefit.rig.pipeline.StaticFitInput.with_static_design`, :meth:`FitResult.with_tyre`), so a result's
statistics, contract and report always describe the tyre it holds.  The check is on the source (``ast``):
an assignment to ``tyre.<x>`` / ``<...>.tyre.<x>``, an augmented one, ``setattr(tyre, ...)`` or an in-place
list method on ``tyre.header`` anywhere in the package outside ``tyrefit/tyres/`` fails it.
"""

from __future__ import annotations

import ast
from pathlib import Path

PKG = Path(__file__).resolve().parents[1] / "tyrefit"
_LIST_METHODS = {"append", "extend", "insert", "remove", "pop", "clear", "sort", "reverse"}


def _is_tyre(node: ast.AST) -> bool:
    """``tyre`` (any name ending in 'tyre') or ``<expr>.tyre``."""
    if isinstance(node, ast.Name):
        return node.id.endswith("tyre")
    return isinstance(node, ast.Attribute) and node.attr == "tyre"


def mutations(tree: ast.AST) -> list[tuple[int, str]]:
    out = []
    for node in ast.walk(tree):
        targets = []
        if isinstance(node, ast.Assign):
            targets = node.targets
        elif isinstance(node, (ast.AugAssign, ast.AnnAssign)):
            targets = [node.target]
        for t in targets:
            for el in (t.elts if isinstance(t, ast.Tuple) else [t]):
                base = el.value if isinstance(el, ast.Subscript) else el
                if isinstance(base, ast.Attribute) and _is_tyre(base.value):
                    out.append((node.lineno, ast.unparse(el)))
        if isinstance(node, ast.Call):
            f = node.func
            if isinstance(f, ast.Name) and f.id == "setattr" and node.args and _is_tyre(node.args[0]):
                out.append((node.lineno, ast.unparse(node)))
            if (isinstance(f, ast.Attribute) and f.attr in _LIST_METHODS and isinstance(f.value, ast.Attribute)
                    and _is_tyre(f.value.value)):
                out.append((node.lineno, ast.unparse(node)))
    return out


def test_the_checker_sees_each_kind_of_mutation():
    src = ("tyre.fnomin = 1.0\nres.tyre.name = 'x'\nres.tyre.header.append('y')\nsetattr(tyre, 'a', 1)\n"
           "front_tyre.coefficients['a0'] += 1\nt = replace(tyre, fnomin=1.0)\nself.tyre_x = 2\n")
    found = sorted(line for line, _ in mutations(ast.parse(src)))
    assert found == [1, 2, 3, 4, 5]


def test_no_tyre_is_changed_after_construction_outside_the_tyre_classes():
    bad = []
    for f in sorted(PKG.rglob("*.py")):
        rel = f.relative_to(PKG.parent)
        if rel.parts[1] in ("tyres", "data", "pipelines"):
            continue
        bad += [f"{rel}:{line}: {what}" for line, what in mutations(ast.parse(f.read_text()))]
    for f in sorted((PKG.parent / "pipelines").glob("*.py")):
        bad += [f"{f.name}:{line}: {what}" for line, what in mutations(ast.parse(f.read_text()))]
    assert not bad, "tyres changed after construction:\n" + "\n".join(bad)
