"""Safe outputs: nothing already on disk is lost.

Every file tyrefit writes goes through :func:`atomic_write` (or
:func:`output_dir` for report folders): the content is written to a temporary
file beside the target and renamed over it only when complete, so a failing
run never leaves a partial file and never touches an existing one.  An
existing output is replaced only when ``force=True``.
"""

from __future__ import annotations

import contextlib
import os
import shutil
import tempfile
from collections.abc import Iterator
from pathlib import Path

from ..errors import OutputExistsError

def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


__all__ = ["check_output", "check_outputs", "atomic_write", "write_text", "write_bytes", "staged_dir"]


def check_output(path: str | os.PathLike, force: bool = False) -> Path:
    """Raise :class:`OutputExistsError` if ``path`` exists and ``force`` is false.

    Call this *before* doing any work, so the user learns at once.
    """
    p = Path(path)
    if p.exists() and not force:
        raise OutputExistsError(f"{p}: output exists; pass --force to replace it")
    return p


def check_outputs(args, files=("out", "json"), reports=("report",)) -> None:
    """Check a command's outputs before it does any work.

    ``files`` name ``args`` attributes holding output files, ``reports``
    attributes holding report folders (their ``index.html`` is checked);
    attributes that are missing or None are skipped.  Honours ``args.force``.
    """
    force = bool(getattr(args, "force", False))
    for name in files:
        if getattr(args, name, None):
            check_output(getattr(args, name), force)
    for name in reports:
        if getattr(args, name, None):
            check_output(Path(getattr(args, name)) / "index.html", force)


@contextlib.contextmanager
def atomic_write(path: str | os.PathLike, mode: str = "w", force: bool = False, **kw) -> Iterator:
    """Open a temporary file beside ``path``; rename it over ``path`` on success.

    On any exception the temporary file is removed and ``path`` is untouched.
    """
    p = check_output(path, force)
    p.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(prefix=f".{p.name}.", suffix=".tmp", dir=p.parent)
    try:
        with os.fdopen(fd, mode, **kw) as fh:
            yield fh
        os.chmod(tmp, 0o666 & ~_umask())  # mkstemp makes 0600; give the usual mode of a new file
        os.replace(tmp, p)
    except BaseException:
        with contextlib.suppress(OSError):
            os.unlink(tmp)
        raise


def write_text(path: str | os.PathLike, text: str, force: bool = False) -> Path:
    """Write ``text`` atomically (UTF-8, LF)."""
    with atomic_write(path, "w", force=force, encoding="utf-8", newline="\n") as fh:
        fh.write(text)
    return Path(path)


def write_bytes(path: str | os.PathLike, data: bytes, force: bool = False) -> Path:
    """Write ``data`` atomically."""
    with atomic_write(path, "wb", force=force) as fh:
        fh.write(data)
    return Path(path)


@contextlib.contextmanager
def staged_dir(path: str | os.PathLike, force: bool = False) -> Iterator[Path]:
    """Build a report folder in a temporary sibling; swap it in on success.

    An existing folder is an error unless ``force``; with ``force`` it is
    replaced only after the new one is complete.
    """
    p = Path(path)
    if p.exists() and any(p.iterdir()) and not force:
        raise OutputExistsError(f"{p}: report folder exists and is not empty; pass --force to replace it")
    p.parent.mkdir(parents=True, exist_ok=True)
    tmp = Path(tempfile.mkdtemp(prefix=f".{p.name}.", dir=p.parent))
    try:
        yield tmp
        if p.exists():
            old = Path(tempfile.mkdtemp(prefix=f".{p.name}.old.", dir=p.parent))
            os.replace(p, old / "x")
            os.replace(tmp, p)
            shutil.rmtree(old, ignore_errors=True)
        else:
            os.replace(tmp, p)
    except BaseException:
        shutil.rmtree(tmp, ignore_errors=True)
        raise
