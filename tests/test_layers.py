"""The package's layering, as a contract: every import of tyrefit's own modules, at module level or
inside a function, points down (or sideways within a layer), and no two components import each other.

The layers, lowest first (:data:`LAYERS`)::

    errors, version, nomenclature
    models                                  (the equations)
    tyre file formats                       (text <-> coefficient dicts; the output transaction)
    tyres                                   (tyre objects)
    io                                      (rig records, tyre readers, reports' HTML builder)
    fitting core                            (parameters and the least-squares solver)
    effects                                 (the catalogue of physical effects)
    fitting, rig                            (fitting problems, static-rig conversion)
    diagnose, compare, sim
    workflows, synthetic, api               (data files to results; generators and validation)
    commands, cli

The same layering is written as import-linter contracts in ``pyproject.toml`` (``[tool.importlinter]``),
which the last two tests run.  The ``ast`` checks here add what those contracts do not say: no two
components import each other (an acyclic-components check), and the count of imports written inside
functions, which hide a dependency from a reader, is ratcheted down.
:func:`test_function_level_imports_do_not_grow` ratchets their number down.
"""

from __future__ import annotations

import ast
from collections import defaultdict
from pathlib import Path

PKG = Path(__file__).resolve().parents[1] / "tyrefit"

#: lowest first; a module belongs to the longest prefix that names it
LAYERS: list[list[str]] = [
    ["tyrefit.errors", "tyrefit._version", "tyrefit.nomenclature", "tyrefit._callable"],
    ["tyrefit.models"],
    ["tyrefit.io.property_file", "tyrefit.io.outputs", "tyrefit.io.inputs", "tyrefit.io.pac89_tir",
     "tyrefit.io.chrono_doc", "tyrefit.io.mf_tir"],
    ["tyrefit.tyres"],
    ["tyrefit.io", "tyrefit.datasets"],
    ["tyrefit.fitting.core", "tyrefit.fitting._blas"],
    ["tyrefit.effects"],
    ["tyrefit.fitting", "tyrefit.rig"],
    ["tyrefit.diagnose", "tyrefit.compare", "tyrefit.sim"],
    ["tyrefit.workflows", "tyrefit.synthetic", "tyrefit.api"],
    ["tyrefit.commands", "tyrefit.cli"],
    ["tyrefit"],  # the package's __init__: lazy exports of the API
]

#: function-level imports of tyrefit's own modules (this checker counts each module named): 218 before the
#: contract was written, 146 after hoisting those that point to a lower layer, 144 after the rig split
#: (rig/pipeline.py's io.readers, rig/report.py's rig.static), 141 with commands/diagnose.py's at module level, 138 with diagnose's workflow in workflows/diagnose.py,
#: 136 with commands/fit.py's io.facets at module level, 106 with the sim scenario parsers in cli.py (commands/sim.py
#: off the start-up path) and cli.py's, commands/sim.py's and sim/api.py's at module level, 65 with every command's,
#: 55 with api.py's and compare's, 47 with sim's, 25 with synthetic's, 11 with effects', fitting's (mf_data, mf_result),
#: tyres.contract's and the workflows' (what is left: 5 in files under mutation testing, 6 in diagnose/),
#: 5 with diagnose's, 0 with fitting/engine.py's and io/readers.py's: only optional dependencies
#: (dask, the report's pandas) are imported inside functions now; never raise it
FUNCTION_LEVEL_MAX = 0


def _component(module: str) -> str:
    best = ""
    for layer in LAYERS:
        for prefix in layer:
            if (module == prefix or module.startswith(prefix + ".")) and len(prefix) > len(best):
                best = prefix
    return best


def _layer(component: str) -> int:
    return next(i for i, layer in enumerate(LAYERS) if component in layer)


def _imports(root: Path = PKG):
    """(importer, imported, line, inside a function) for every import of a tyrefit module under ``root``."""
    out = []
    for f in sorted(root.rglob("*.py")):
        rel = f.relative_to(root.parent).with_suffix("")
        if {"data", "pipelines"} & set(rel.parts):
            continue
        parts = list(rel.parts)
        is_pkg = parts[-1] == "__init__"
        module = ".".join(parts[:-1] if is_pkg else parts)
        package = module if is_pkg else module.rpartition(".")[0]
        tree = ast.parse(f.read_text(encoding="utf-8"))
        stack = [(tree, False)]
        while stack:
            node, in_func = stack.pop()
            for child in ast.iter_child_nodes(node):
                func = in_func or isinstance(child, (ast.FunctionDef, ast.AsyncFunctionDef, ast.Lambda))
                if isinstance(child, ast.ImportFrom):
                    if child.level:
                        base = package.split(".")[: len(package.split(".")) - child.level + 1]
                        target = ".".join(base + ([child.module] if child.module else []))
                    else:
                        target = child.module or ""
                    names = [target + "." + a.name for a in child.names]
                    for t in ([target] if child.module else []) + names:
                        if t.startswith("tyrefit") and (t == target or _is_module(t, root)):
                            out.append((module, t, child.lineno, in_func))
                elif isinstance(child, ast.Import):
                    for a in child.names:
                        if a.name.startswith("tyrefit"):
                            out.append((module, a.name, child.lineno, in_func))
                stack.append((child, func))
    return out


def _is_module(name: str, root: Path = PKG) -> bool:
    p = root.parent.joinpath(*name.split("."))
    return p.with_suffix(".py").is_file() or (p / "__init__.py").is_file()


def test_every_import_points_down_the_layers():
    bad = []
    for src, dst, line, in_func in _imports():
        cs, cd = _component(src), _component(dst)
        if cd == "tyrefit" and dst != "tyrefit":
            continue
        if _layer(cd) > _layer(cs):
            bad.append(f"{src}:{line} imports {dst} ({cs} is below {cd}){' inside a function' if in_func else ''}")
    assert not bad, "imports against the layers:\n" + "\n".join(bad)


def test_no_two_components_import_each_other():
    edges = defaultdict(set)
    for src, dst, _, _ in _imports():
        cs, cd = _component(src), _component(dst)
        if cs != cd:
            edges[cs].add(cd)
    cycles = sorted(f"{a} <-> {b}" for a in edges for b in edges[a] if a < b and a in edges.get(b, ()))
    assert not cycles, "components importing each other: " + ", ".join(cycles)


def test_function_level_imports_do_not_grow():
    n = sum(1 for *_, in_func in _imports() if in_func)
    assert n <= FUNCTION_LEVEL_MAX, f"{n} function-level imports of tyrefit modules (at most {FUNCTION_LEVEL_MAX})"


def test_the_contract_sees_a_violation(tmp_path):
    """The checker itself: an upward import planted inside a function of a low module is reported."""
    import shutil

    copy = tmp_path / "tyrefit"
    shutil.copytree(PKG, copy, ignore=shutil.ignore_patterns("data", "pipelines", "__pycache__"))
    f = copy / "models" / "pac89.py"
    f.write_text(f.read_text() + "\n\ndef _planted():\n    from ..sim import api  # noqa\n")
    found = [x for x in _imports(copy) if x[0] == "tyrefit.models.pac89" and x[1].startswith("tyrefit.sim")]
    assert found and found[0][3] and _layer(_component(found[0][1])) > _layer(_component(found[0][0]))


# --- the same layering through import-linter (pyproject.toml's [tool.importlinter] contracts) -----------------
def _lint_imports(root: Path, cwd: Path):
    """Run ``lint-imports`` on the package under ``root`` with the contracts of ``cwd/pyproject.toml``."""
    import os
    import subprocess
    import sys

    import pytest

    pytest.importorskip("importlinter", reason="import-linter is a test extra: pip install -e '.[test]'")
    exe = Path(sys.executable).parent / "lint-imports"
    cmd = [str(exe)] if exe.exists() else [sys.executable, "-c", "from importlinter.cli import lint_imports_command as c; c()"]
    env = dict(os.environ, PYTHONPATH=str(root), PYTHONDONTWRITEBYTECODE="1")
    return subprocess.run(cmd + ["--no-cache"], cwd=cwd, env=env, capture_output=True, text=True, timeout=300)


def test_import_linter_contracts_are_kept():
    p = _lint_imports(PKG.parent, PKG.parent)
    assert p.returncode == 0, p.stdout[-3000:] + p.stderr[-2000:]
    assert "3 kept, 0 broken" in p.stdout


def test_import_linter_sees_a_violation(tmp_path):
    """An upward import planted in a copy of the package breaks the layers contract; one from a file format
    module to the tyre classes breaks the format contract."""
    import shutil

    shutil.copytree(PKG, tmp_path / "tyrefit", ignore=shutil.ignore_patterns("data", "pipelines", "__pycache__"))
    shutil.copy(PKG.parent / "pyproject.toml", tmp_path / "pyproject.toml")
    f = tmp_path / "tyrefit" / "models" / "slip.py"
    f.write_text(f.read_text() + "\n\ndef _planted():\n    from ..sim import api  # noqa\n")
    g = tmp_path / "tyrefit" / "io" / "pac89_tir.py"
    g.write_text(g.read_text() + "\nfrom ..tyres import base as _planted  # noqa\n")
    p = _lint_imports(tmp_path, tmp_path)
    assert p.returncode == 1, p.stdout[-3000:]
    assert "tyrefit's layers BROKEN" in p.stdout and "tyre file formats below the tyre classes BROKEN" in p.stdout
    assert "tyrefit.models.slip -> tyrefit.sim.api" in p.stdout
