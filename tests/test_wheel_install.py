"""A wheel built from the package tree installs into a fresh venv, with no network, and runs ``tyrefit demo``
in an empty folder outside the repository (issue 27, packaging).

How it installs with no network: pip is given only local sources, never a remote index.

* the local wheel stores this machine's pip is configured with (``pip config list``: ``find-links``
  folders and ``file://`` indexes, e.g. ``/opt/wheels`` and ``file:///opt/pypi/simple``), with pip's
  own configuration switched off so that no remote index is consulted;
* a wheelhouse of the pure-Python runtime dependencies of tyrefit as they are installed in the
  environment running this test, written back into wheels from the files their ``RECORD`` lists (checked
  against its hashes).  That covers a dependency the local stores lack (lmfit, on this machine).

The fresh venv has no access to the running environment or to the repository: the demo runs with a
minimal environment (``env -i``-like) in an empty folder, so a package file missing from the wheel, a
dependency missing from ``pyproject.toml`` or a path into the source tree fails here.  Skipped, with the
reason, only where that offline install is not possible (no venv/ensurepip, or a build or runtime
dependency that no local source has).
"""

from __future__ import annotations

import base64
import hashlib
import os
import re
import shutil
import subprocess
import sys
import tomllib
import zipfile
from importlib import metadata
from pathlib import Path

import pytest

from tyrefit.commands.demo import STEPS

ROOT = Path(__file__).resolve().parents[1]
# what a wheel build reads: the package (whose data/ and pipelines/ are links to the repository's folders)
TREE = ["pyproject.toml", "README.md", "LICENSE", "MANIFEST.in", "setup.py", "setup.cfg",
        "tyrefit", "data", "pipelines"]
_IGNORE = shutil.ignore_patterns("__pycache__", "*.pyc", "*.egg-info", "build", "dist", ".pytest_cache")
_SKIPPED_META = {"INSTALLER", "REQUESTED", "RECORD", "direct_url.json"}


def _copy_tree(dest: Path) -> Path:
    """The files a wheel is built from, copied (symlinks kept as links) into ``dest``; not a git archive."""
    dest.mkdir(parents=True)
    for name in TREE:
        src = ROOT / name
        if src.is_symlink() or src.is_file():
            shutil.copy2(src, dest / name, follow_symlinks=False)
        elif src.is_dir():
            shutil.copytree(src, dest / name, symlinks=True, ignore=_IGNORE)
    return dest


def local_sources() -> tuple[list[str], list[str]]:
    """(index URLs, find-links folders) that this machine's pip is configured with and that are on local disk."""
    try:
        out = subprocess.run([sys.executable, "-m", "pip", "config", "list"], capture_output=True, text=True,
                             timeout=60).stdout
    except (OSError, subprocess.SubprocessError):
        out = ""
    indexes, links = [], []
    for line in out.splitlines():
        m = re.match(r"^[^=]*\.(index-url|extra-index-url|find-links)='(.*)'$", line.strip())
        if not m:
            continue
        for value in m.group(2).split():
            path = value[len("file://"):] if value.startswith("file://") else value
            if "://" in path or not Path(path).exists():
                continue  # a remote source: never used here
            if m.group(1) == "find-links":
                links.append(path)
            else:
                indexes.append("file://" + path)
    return list(dict.fromkeys(indexes)), list(dict.fromkeys(links))


def _requirement_names(requirements: list[str]) -> list[str]:
    names = []
    for req in requirements:
        try:
            from packaging.requirements import Requirement

            r = Requirement(req)
            if r.marker is not None and not r.marker.evaluate({"extra": ""}):
                continue
            names.append(r.name)
        except ImportError:  # no packaging: the name alone (a dependency too many is harmless)
            names.append(re.match(r"\s*([A-Za-z0-9._-]+)", req).group(1))
        except Exception:
            continue
    return names


def _repack(dist: metadata.Distribution, dest: Path) -> Path | None:
    """Write an installed pure-Python distribution back into a wheel in ``dest``.

    The wheel holds the files its ``RECORD`` lists inside site-packages (compiled caches, the installer's
    own files and console scripts left out: pip writes scripts again from ``entry_points.txt``); None if the
    distribution is not pure Python, is an editable install, or a file differs from its recorded hash.
    """
    wheel = dist.read_text("WHEEL") or ""
    tags = [line.split(":", 1)[1].strip() for line in wheel.splitlines() if line.startswith("Tag:")]
    if "Root-Is-Purelib: true" not in wheel or not tags or not all(t.endswith("-none-any") for t in tags):
        return None
    if dist.read_text("direct_url.json") or not dist.files:
        return None
    pythons = ".".join(dict.fromkeys(t.split("-")[0] for t in tags))
    name = re.sub(r"[-_.]+", "_", dist.metadata["Name"]).lower()
    target = dest / f"{name}-{dist.version}-{pythons}-none-any.whl"
    entries = []
    for f in dist.files:
        rel = str(f).replace("\\", "/")
        if rel.startswith("..") or "__pycache__/" in rel or rel.endswith(".pyc"):
            continue
        if ".dist-info/" in rel and rel.split(".dist-info/", 1)[1] in _SKIPPED_META:
            continue
        data = Path(f.locate()).read_bytes()
        digest = base64.urlsafe_b64encode(hashlib.sha256(data).digest()).rstrip(b"=").decode()
        if f.hash is None or f.hash.mode != "sha256" or digest != f.hash.value:
            return None  # changed since it was installed (or unrecorded): not the released file
        entries.append((rel, data, digest))
    dist_info = next(rel.split("/")[0] for rel, _, _ in entries if rel.endswith(".dist-info/METADATA"))
    record = [f"{rel},sha256={digest},{len(data)}" for rel, data, digest in entries] + [f"{dist_info}/RECORD,,"]
    with zipfile.ZipFile(target, "w", zipfile.ZIP_DEFLATED) as zf:
        for rel, data, _ in entries:
            zf.writestr(rel, data)
        zf.writestr(f"{dist_info}/RECORD", "\n".join(record) + "\n")
    return target


def repack_runtime_dependencies(pyproject: Path, dest: Path) -> list[Path]:
    """The pure-Python runtime dependencies of ``pyproject`` (and theirs), as installed here, as wheels in ``dest``."""
    dest.mkdir(parents=True, exist_ok=True)
    todo = _requirement_names(tomllib.loads(pyproject.read_text())["project"].get("dependencies", []))
    seen, wheels = set(), []
    while todo:
        key = re.sub(r"[-_.]+", "-", todo.pop()).lower()
        if key in seen:
            continue
        seen.add(key)
        try:
            dist = metadata.distribution(key)
        except metadata.PackageNotFoundError:
            continue
        w = _repack(dist, dest)
        if w is not None:
            wheels.append(w)
        todo.extend(_requirement_names(dist.requires or []))
    return wheels


def pip_offline_args(wheelhouse: Path) -> list[str]:
    """pip options that reach local files only: the machine's local stores and ``wheelhouse``."""
    indexes, links = local_sources()
    args = ["--index-url", indexes[0]] + [a for i in indexes[1:] for a in ("--extra-index-url", i)] if indexes \
        else ["--no-index"]
    for d in [*links, str(wheelhouse)]:
        args += ["--find-links", d]
    return args


def pip_env() -> dict[str, str]:
    """The environment for pip: its configuration files and PIP_* variables off (they may name a remote index),
    no PYTHON* variables (a PYTHONPATH into the source tree would pass for an installed tyrefit)."""
    env = {k: v for k, v in os.environ.items() if not k.startswith(("PIP_", "PYTHON"))}
    env.update(PIP_CONFIG_FILE=os.devnull, PIP_DISABLE_PIP_VERSION_CHECK="1", PIP_NO_INPUT="1")
    return env


def clean_env(venv: Path, home: Path) -> dict[str, str]:
    """A minimal environment (as ``env -i``) with the venv first on PATH: nothing points at the repository."""
    env = {"PATH": f"{venv / 'bin'}:/usr/bin:/bin", "HOME": str(home), "LANG": "C.UTF-8"}
    env.update({k: v for k, v in os.environ.items() if k.startswith("OPENBLAS_")})  # this machine's BLAS settings
    return env


# run in the fresh venv: the top-level modules imported anywhere in the installed tyrefit that it cannot find
_IMPORTS_FOUND = """
import ast, importlib.util, pathlib, sys, tyrefit
names = set()
for f in pathlib.Path(tyrefit.__file__).parent.rglob("*.py"):
    for n in ast.walk(ast.parse(f.read_bytes())):
        if isinstance(n, ast.Import):
            names |= {a.name.split(".")[0] for a in n.names}
        elif isinstance(n, ast.ImportFrom) and n.level == 0 and n.module:
            names.add(n.module.split(".")[0])
print(" ".join(sorted(m for m in names - set(sys.stdlib_module_names) if importlib.util.find_spec(m) is None)))
"""


def _unavailable(result: subprocess.CompletedProcess) -> str | None:
    """pip's reason when a distribution is in no local source (offline install impossible here), else None."""
    m = re.search(r"No matching distribution found for (\S+)", result.stdout + result.stderr)
    return m.group(1) if m else None


@pytest.mark.slow
def test_wheel_installs_offline_and_runs_the_demo_outside_the_repository(tmp_path):
    tree = _copy_tree(tmp_path / "src")
    wheelhouse = tmp_path / "wheelhouse"
    repack_runtime_dependencies(tree / "pyproject.toml", wheelhouse)
    offline = pip_offline_args(wheelhouse)

    # the wheel, in pip's isolated build environment, its backend from the local sources
    dist = tmp_path / "dist"
    built = subprocess.run([sys.executable, "-m", "pip", "wheel", "--no-deps", *offline, "-w", str(dist), str(tree)],
                           capture_output=True, text=True, env=pip_env(), timeout=900)
    if built.returncode and _unavailable(built):
        pytest.skip(f"offline build impossible here: no local source has {_unavailable(built)}")
    assert built.returncode == 0, built.stdout[-3000:] + built.stderr[-3000:]
    (wheel,) = dist.glob("tyrefit-*.whl")
    names = zipfile.ZipFile(wheel).namelist()
    data_files = [p.relative_to(tree / "data").as_posix() for p in (tree / "data").rglob("*") if p.is_file()]
    not_packed = [f for f in data_files if f"tyrefit/data/{f}" not in names]
    assert data_files and not not_packed, f"bundled data missing from the wheel: {not_packed[:10]}"
    assert any(n.startswith("tyrefit/pipelines/") for n in names), "the demo's pipelines are not in the wheel"
    assert "tyrefit/py.typed" in names
    assert any(n.endswith(".dist-info/licenses/LICENSE") for n in names)

    # a fresh venv, the wheel and its declared dependencies from local files only
    venv = tmp_path / "venv"
    made = subprocess.run([sys.executable, "-m", "venv", str(venv)], capture_output=True, text=True, env=pip_env(),
                          timeout=300)
    if made.returncode or not (venv / "bin" / "python").exists():
        pytest.skip(f"no venv with pip here: {made.stderr.strip()[-300:]}")
    installed = subprocess.run([str(venv / "bin" / "python"), "-m", "pip", "install", *offline, str(wheel)],
                               capture_output=True, text=True, env=pip_env(), timeout=900)
    if installed.returncode and _unavailable(installed):
        pytest.skip(f"offline install impossible here: no local source has {_unavailable(installed)}")
    assert installed.returncode == 0, installed.stdout[-3000:] + installed.stderr[-3000:]

    # an empty folder outside the repository, a minimal environment
    run, home = tmp_path / "run", tmp_path / "home"
    run.mkdir()
    home.mkdir()
    env = clean_env(venv, home)
    where = subprocess.run(["python", "-c", "import tyrefit as tf; print(tf.__file__); print(tf.datasets.names()[0])"],
                           cwd=run, env=env, capture_output=True, text=True, timeout=300)
    assert where.returncode == 0, where.stderr
    assert Path(where.stdout.splitlines()[0]).resolve().is_relative_to(venv.resolve()), where.stdout
    # every third-party module the installed package imports (lazy imports too) is installed, but for the extras
    missing = subprocess.run(["python", "-c", _IMPORTS_FOUND], cwd=run, env=env, capture_output=True, text=True,
                             timeout=300)
    assert missing.returncode == 0, missing.stderr
    optional, project = set(), tomllib.loads((tree / "pyproject.toml").read_text())["project"]
    for reqs in project.get("optional-dependencies", {}).values():
        for req in reqs:
            m = re.match(r"\s*([A-Za-z0-9._-]+)\s*(?:\[([^\]]*)\])?", req)
            optional |= {m.group(1).lower(), *(e.strip().lower() for e in (m.group(2) or "").split(",") if e.strip())}
    assert set(missing.stdout.split()) <= optional, f"imported but not installed: {missing.stdout.split()}"
    assert subprocess.run(["tyrefit", "--help"], cwd=run, env=env, capture_output=True, timeout=300).returncode == 0

    demo = subprocess.run(["tyrefit", "demo", "--out", "demo"], cwd=run, env=env, capture_output=True, text=True,
                          timeout=1800)
    assert demo.returncode == 0, demo.stdout[-3000:] + demo.stderr[-3000:]
    index = run / "demo" / "index.html"
    assert f"[demo] wrote {Path('demo') / 'index.html'}" in demo.stdout or f"[demo] wrote {index}" in demo.stdout, \
        demo.stdout[-1000:]
    assert index.is_file()
    tyres = sorted((run / "demo").rglob("*.tir"))
    assert tyres, "the demo wrote no .tir"
    for step, _, _ in STEPS:
        assert (run / "demo" / step / "index.html").is_file(), step
    assert str(ROOT) not in index.read_text(), "the demo report names the source tree"
