"""Safe outputs: nothing already on disk is lost.

One output layer serves every command.

* **Staging.**  Every file goes through :func:`atomic_write` (or
  :func:`staged_dir` for folders built in one go).  Inside an
  :func:`output_run` (the command line opens one around every command) a
  file is written to a temporary sibling and only *registered*; when the
  whole run has succeeded :meth:`OutputRun.commit` renames every staged file
  into place, and if anything fails — the fit, the report, the second of two
  outputs — :meth:`OutputRun.rollback` deletes the temporaries and every
  earlier output stays as it was.  A commit that fails half-way (a rename
  refused by the file system) restores the files it had already replaced
  from hard-linked backups.  Outside a run each write is committed at once,
  still atomically.
* **Inputs are sacred.**  A run knows its inputs; an output whose resolved
  real path *or* inode (a hard link) is an input's is refused, even with
  ``--force``, before anything is written.  Two outputs naming the same file
  (``--json`` equal to ``--out``) are refused too.
* **Report folders.**  Each folder tyrefit writes holds a manifest
  (:data:`MANIFEST`, a small JSON list of the files tyrefit wrote there).  A
  folder that is not empty is refused without ``--force``; with it, only the
  files the manifest lists are replaced: a file tyrefit did not write is
  never replaced or removed (a same-named one stops the run), and other
  files in the folder are left alone.
* **One line per OS error.**  Read-only folders, a parent that is a file,
  an output that is a folder, a full disk or ``File too large`` become an
  :class:`~tyrefit.errors.OutputError` that names the path.

Batch folders (:mod:`tyrefit.workflows.batch`) are the one deliberate
exception to run-wide staging: a batch of thousands of tyres commits each
tyre (its ``.tir`` and fingerprint) as it finishes, so an interrupted batch
keeps its finished tyres; every file is still written atomically and never
over a file the batch did not write.
"""

from __future__ import annotations

import contextlib
import errno
import json
import os
import shutil
import stat
import tempfile
from collections.abc import Iterable, Iterator
from pathlib import Path

from ..errors import OutputError, OutputExistsError, option

__all__ = ["check_output", "real_path", "atomic_write", "write_text", "write_bytes", "staged_dir",
           "output_run", "OutputRun", "current_run", "MANIFEST", "os_error_message", "read_manifest"]

#: name of the manifest tyrefit keeps in every report folder it writes
MANIFEST = ".tyrefit-manifest.json"


def _name_max(directory: str | os.PathLike) -> int:
    """The longest file name (bytes) the file system of ``directory`` takes (NAME_MAX, usually 255)."""
    try:
        return int(os.pathconf(directory, "PC_NAME_MAX"))
    except (OSError, ValueError, AttributeError):
        return 255


def side_name(name: str, directory: str | os.PathLike, *, prefix: str = ".", suffix: str = "",
              extra: int = 0) -> str:
    """``prefix + name + suffix`` for a temporary or backup file beside ``name``, with ``name`` cut
    (on a whole character) so the result, plus ``extra`` bytes a caller adds (mkstemp's random
    part), fits the file system's NAME_MAX: a legal 255-byte output name keeps a legal side file."""
    room = _name_max(directory) - len(os.fsencode(prefix + suffix)) - extra
    raw = os.fsencode(name)
    if len(raw) > room:
        raw = raw[:max(room, 1)]
        while raw and (raw[-1] & 0xC0) == 0x80:  # a cut UTF-8 sequence: drop its continuation bytes
            raw = raw[:-1]
        if raw and raw[-1] >= 0xC0:  # ... and its lead byte
            raw = raw[:-1]
    return prefix + os.fsdecode(raw) + suffix


#: characters mkstemp/mkdtemp add between prefix and suffix
_RANDOM = 8


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


_HINTS = {
    errno.EROFS: "read-only file system",
    errno.EACCES: "permission denied",
    errno.EPERM: "operation not permitted",
    errno.ENOSPC: "no space left on the device (disk full)",
    errno.EDQUOT: "disk quota exceeded",
    errno.EFBIG: "file too large for this file system or the user's file-size limit",
    errno.EISDIR: "is a folder",
    errno.ENOTDIR: "a parent in the path is a file, not a folder",
    errno.ENAMETOOLONG: "file name too long",
    errno.ENOENT: "no such folder",
    errno.EEXIST: "a file of that name exists where a folder is needed",
}


def os_error_message(exc: OSError, path: str | os.PathLike | None = None, what: str = "cannot write") -> str:
    """One line naming the path and the cause of an :class:`OSError`."""
    p = path if path is not None else (exc.filename or "")
    why = _HINTS.get(exc.errno or -1) or exc.strerror or exc.__class__.__name__
    return f"{p}: {what} ({why})"


def _oserror(exc: OSError, path, what: str = "cannot write") -> OutputError:
    err = OutputError(os_error_message(exc, path, what))
    err.errno = exc.errno
    return err


def _ident(p: Path) -> tuple[int, int] | None:
    try:
        st = p.stat()
    except OSError:
        return None
    return (st.st_dev, st.st_ino)


def real_path(p: str | os.PathLike) -> Path:
    return Path(os.path.realpath(os.fspath(p)))


def read_manifest(directory: str | os.PathLike) -> set[str]:
    """Relative paths (``/``-separated) tyrefit wrote in ``directory``; empty if there is no manifest."""
    try:
        doc = json.loads((Path(directory) / MANIFEST).read_text(encoding="utf-8"))
        return {str(x) for x in doc.get("files", [])} if isinstance(doc, dict) else set()
    except (OSError, ValueError):
        return set()


def _files_in(directory: Path) -> set[str]:
    out = set()
    for root, _dirs, files in os.walk(directory):
        for f in files:
            rel = Path(root, f).relative_to(directory).as_posix()
            if rel != MANIFEST:
                out.add(rel)
    return out


def check_output(path: str | os.PathLike, force: bool = False) -> Path:
    """Check one output file before any work; return it as a :class:`Path`.

    Raises :class:`OutputExistsError` if it exists and ``force`` is false,
    :class:`OutputError` if it names a folder, sits under a file, or is an
    input of the current run.
    """
    p = Path(path)
    if p.is_dir():
        raise OutputError(f"{p}: is a folder; give a file name for this output")
    if str(path).endswith(("/", os.sep)) or str(path) in (".", ".."):  # Path('out/') would be the file 'out'
        raise OutputError(f"{path}: names a folder (it ends with '/'); give a file name for this output, "
                          "e.g. out/result.json")
    for q in (os.path.abspath(p), os.path.realpath(p)):
        if q.startswith(("/dev/", "/proc/", "/sys/")):  # /dev/stdout, /proc/self/fd/1: not a file to rename over
            raise OutputError(f"{p}: is in {q.split('/')[1] and '/' + q.split('/')[1]}; tyrefit writes its outputs "
                              "to regular files only")
    try:
        mode = os.stat(p).st_mode
    except OSError:
        mode = None
    if mode is not None and not stat.S_ISREG(mode):  # /dev/null, /dev/stdout, a FIFO: never renamed over
        what = ("a FIFO (named pipe)" if stat.S_ISFIFO(mode) else "a device" if stat.S_ISCHR(mode) or
                stat.S_ISBLK(mode) else "a socket" if stat.S_ISSOCK(mode) else "not a regular file")
        raise OutputError(f"{p}: is {what}; tyrefit writes its outputs to regular files only")
    for parent in p.parents:
        if parent.exists():
            if not parent.is_dir():
                raise OutputError(f"{p}: cannot write ({parent} is a file, not a folder)")
            break
    run = current_run()
    if run is not None:
        run.check_not_input(p)
    if (p.exists() or p.is_symlink()) and not force:
        raise OutputExistsError(f"{p}: output exists; pass {option('force', flag=True)} to replace it")
    return p


def check_report_dir(path: str | os.PathLike, force: bool = False) -> Path:
    """Check a report folder before any work (see the module notes)."""
    p = Path(path)
    if p.exists() and not p.is_dir():
        raise OutputError(f"{p}: is a file; {option('report')} needs a folder")
    for parent in p.parents:
        if parent.exists():
            if not parent.is_dir():
                raise OutputError(f"{p}: cannot create the folder ({parent} is a file)")
            break
    if p.is_dir():
        files = _files_in(p)
        if files and not force:
            foreign = files - read_manifest(p)
            extra = (f"; it holds {len(foreign)} file{'s' if len(foreign) != 1 else ''} tyrefit did not write "
                     f"(e.g. {sorted(foreign)[0]}), which {option('force', flag=True)} keeps") if foreign else ""
            raise OutputExistsError(f"{p}: report folder exists and is not empty; pass "
                                    f"{option('force', flag=True)} to replace "
                                    f"tyrefit's own files in it{extra}")
    return p


# --------------------------------------------------------------------------- the run (transaction)

class OutputRun:
    """The outputs of one run: staged files, committed together or not at all.

    Parameters
    ----------
    inputs : iterable of path
        files the run reads; no output may be one of them.
    reports : iterable of path
        report folders (manifest rules apply to files written under them).
    force : bool
        ``--force`` was given.
    """

    def __init__(self, inputs: Iterable = (), reports: Iterable = (), force: bool = False):
        self.force = bool(force)
        self.inputs: dict[Path, str] = {}
        self.input_ids: dict[tuple[int, int], str] = {}
        for i in inputs:
            self.add_input(i)
        self.reports: set[Path] = {real_path(r) for r in reports}
        self.staged: dict[Path, Path] = {}       # real target -> temporary file
        self.shown: dict[Path, Path] = {}        # real target -> path as the user gave it
        self.tmpdirs: dict[Path, Path] = {}      # staged folder (temporary) -> real target folder
        self.created: list[Path] = []            # folders this run created (removed on rollback if empty)
        self.committed: list[Path] = []

    # -- checks ---------------------------------------------------------------
    def add_input(self, path: str | os.PathLike) -> None:
        p = Path(path)
        if not p.exists() or p.is_dir():
            return
        self.inputs[real_path(p)] = str(path)
        ident = _ident(p)
        if ident is not None:
            self.input_ids[ident] = str(path)

    def check_not_input(self, path: str | os.PathLike) -> None:
        p = Path(path)
        r = real_path(p)
        src = self.inputs.get(r)
        if src is None:
            ident = _ident(p)
            src = self.input_ids.get(ident) if ident is not None else None
        if src is not None:
            raise OutputError(f"{path}: is an input of this run ({src}); tyrefit never writes over its inputs, "
                              f"even with {option('force', flag=True)}: choose another output name")

    def _report_of(self, r: Path) -> Path | None:
        for d in self.reports:
            if d == r.parent or d in r.parents:
                return d
        return None

    def _in_tmpdir(self, p: Path) -> bool:
        a = Path(os.path.abspath(p))
        return any(t == a.parent or t in a.parents for t in self.tmpdirs)

    def check_target(self, path: Path, force: bool) -> None:
        """Refuse a target that is an input, staged twice, a folder, or a foreign file in a report folder."""
        r = real_path(path)
        if r in self.staged:
            raise OutputError(f"{path}: written twice in one run (the same file as "
                              f"{self.shown.get(r, r)}); give each output its own name")
        check_output(path, True)  # folder / parent-is-file / input
        rep = self._report_of(r)
        if rep is not None and r.exists():
            rel = r.relative_to(rep).as_posix()
            if rel not in read_manifest(rep):
                raise OutputExistsError(f"{path}: not written by tyrefit (not in {rep.name}/{MANIFEST}); it is "
                                        f"never replaced, even with {option('force', flag=True)}: move it or choose "
                                        f"another {option('report')}")
        if r.exists() and not (force or self.force):
            raise OutputExistsError(f"{path}: output exists; pass {option('force', flag=True)} to replace it")

    # -- staging ----------------------------------------------------------------
    def makedirs(self, d: Path) -> None:
        missing = []
        q = Path(os.path.abspath(d))
        while not q.exists():
            missing.append(q)
            if q.parent == q:
                break
            q = q.parent
        if q.exists() and not q.is_dir():
            raise OutputError(f"{d}: cannot create the folder ({q} is a file)")
        for m in reversed(missing):
            try:
                m.mkdir()
            except FileExistsError:
                continue
            except OSError as exc:
                raise _oserror(exc, m, "cannot create the folder") from None
            self.created.append(m)

    def stage(self, target: Path, tmp: Path) -> None:
        r = real_path(target)
        self.staged[r] = tmp
        self.shown[r] = target

    # -- end of the run -----------------------------------------------------------
    def _plan(self) -> list[tuple[Path, Path, Path]]:
        """(real target, temporary, shown path) for every file, staged folders flattened."""
        items = [(r, t, self.shown[r]) for r, t in self.staged.items()]
        for tmpdir, dest in self.tmpdirs.items():
            for rel in sorted(_files_in(tmpdir)):
                target = dest / rel
                if target.exists():
                    if rel not in read_manifest(dest):
                        raise OutputExistsError(f"{target}: not written by tyrefit (not in {dest.name}/{MANIFEST});"
                                                f" it is never replaced, even with {option('force', flag=True)}: move "
                                                "it or choose "
                                                "another output folder")
                    self.check_not_input(target)
                items.append((target, tmpdir / rel, target))
        return items

    def _manifests(self, items) -> list[tuple[Path, Path, Path]]:
        written: dict[Path, set[str]] = {}
        for r, _t, _s in items:
            rep = self._report_of(r) or next((d for d in self.tmpdirs.values() if d in r.parents), None)
            if rep is not None:
                written.setdefault(rep, set()).add(r.relative_to(rep).as_posix())
        out = []
        for rep, names in written.items():
            names = names | {n for n in read_manifest(rep) if (rep / n).exists()}
            fd, tmp = tempfile.mkstemp(prefix=f".{MANIFEST}.", suffix=".tmp", dir=rep)
            with os.fdopen(fd, "w", encoding="utf-8") as fh:
                json.dump({"written_by": "tyrefit", "files": sorted(names)}, fh, indent=1)
                fh.write("\n")
            out.append((rep / MANIFEST, Path(tmp), rep / MANIFEST))
        return out

    def commit(self) -> list[Path]:
        """Move every staged file into place; on failure restore what was replaced."""
        try:
            items = self._plan()
            for dest in self.tmpdirs.values():
                self.makedirs(dest)
            for _r, _t, shown in items:
                self.makedirs(Path(os.path.abspath(shown)).parent)
            try:
                items += self._manifests(items)
            except OSError as exc:
                raise _oserror(exc, items[0][0].parent if items else "", "cannot write the manifest") from None
        except BaseException:
            self.rollback()
            raise
        done: list[tuple[Path, Path | None]] = []
        try:
            for _r, tmp, shown in items:
                # the path as named: a symbolic link given as an output is replaced, never written through
                r = Path(os.path.abspath(shown))
                backup = None
                if r.exists() and not r.is_symlink():
                    backup = r.with_name(side_name(r.name, r.parent, suffix=f".{os.getpid()}.bak"))
                    try:
                        os.link(r, backup)
                    except OSError:
                        backup = None
                try:
                    os.chmod(tmp, 0o666 & ~_umask())  # mkstemp makes 0600; give the usual mode of a new file
                    os.replace(tmp, r)
                except OSError as exc:
                    if backup is not None:
                        with contextlib.suppress(OSError):
                            os.unlink(backup)
                    raise _oserror(exc, shown) from None
                done.append((r, backup))
        except BaseException:
            for r, backup in reversed(done):
                with contextlib.suppress(OSError):
                    if backup is not None:
                        os.replace(backup, r)
                    else:
                        os.unlink(r)
            for _r, tmp, _s in items:  # manifests and anything not yet moved
                with contextlib.suppress(OSError):
                    os.unlink(tmp)
            self.rollback()
            raise
        for _r, backup in done:
            if backup is not None:
                with contextlib.suppress(OSError):
                    os.unlink(backup)
        for tmpdir in self.tmpdirs:
            shutil.rmtree(tmpdir, ignore_errors=True)
        self.committed = [r for r, _ in done]
        self.staged.clear()
        self.tmpdirs.clear()
        return self.committed

    def rollback(self) -> None:
        """Delete every temporary file and folder; remove folders this run created if they are empty."""
        for tmp in self.staged.values():
            with contextlib.suppress(OSError):
                os.unlink(tmp)
        for tmpdir in self.tmpdirs:
            shutil.rmtree(tmpdir, ignore_errors=True)
        for d in reversed(self.created):
            with contextlib.suppress(OSError):
                d.rmdir()
        self.staged.clear()
        self.tmpdirs.clear()


_RUNS: list[OutputRun] = []


def current_run() -> OutputRun | None:
    """The innermost active :func:`output_run`, or None."""
    return _RUNS[-1] if _RUNS else None


@contextlib.contextmanager
def output_run(inputs: Iterable = (), reports: Iterable = (), force: bool = False) -> Iterator[OutputRun]:
    """Stage every output written inside the block; commit them together at its end.

    On an exception nothing is committed and the exception propagates.
    """
    run = OutputRun(inputs, reports, force)
    _RUNS.append(run)
    try:
        yield run
    except BaseException:
        _RUNS.pop()
        run.rollback()
        raise
    _RUNS.pop()
    run.commit()


# --------------------------------------------------------------------------- writing

@contextlib.contextmanager
def atomic_write(path: str | os.PathLike, mode: str = "w", force: bool = False, **kw) -> Iterator:
    """Open a temporary file beside ``path``; put it in place on success.

    Inside an :func:`output_run` the file is staged and put in place when the
    run commits; otherwise it is renamed over ``path`` at once.  On any
    exception the temporary file is removed and ``path`` is untouched.
    """
    p = Path(path)
    run = current_run()
    direct = run is None or run._in_tmpdir(p)
    if run is not None and not direct:
        run.check_target(p, force)
        run.makedirs(p.parent)
    else:
        check_output(p, force)
        try:
            p.parent.mkdir(parents=True, exist_ok=True)
        except OSError as exc:
            raise _oserror(exc, p.parent, "cannot create the folder") from None
    try:
        fd, tmp = tempfile.mkstemp(prefix=side_name(p.name, p.parent, suffix=".", extra=_RANDOM + 4),
                                   suffix=".tmp", dir=p.parent)
    except OSError as exc:
        raise _oserror(exc, p) from None
    try:
        try:
            with os.fdopen(fd, mode, **kw) as fh:
                yield fh
        except OSError as exc:
            if isinstance(exc, OutputError):
                raise
            raise _oserror(exc, p) from None
        if direct:
            os.chmod(tmp, 0o666 & ~_umask())
            try:
                os.replace(tmp, p)
            except OSError as exc:
                raise _oserror(exc, p) from None
        else:
            run.stage(p, Path(tmp))
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
    """Build an output folder in a temporary sibling; merge it in on success.

    A non-empty folder is an error unless ``force``; with ``force`` the files
    tyrefit wrote there before (its manifest) are replaced and every other
    file is kept.  Inside an :func:`output_run` the merge happens when the
    run commits.
    """
    p = Path(path)
    check_report_dir(p, force)
    run = current_run()
    own = run is None or run._in_tmpdir(p)  # alone, or inside a folder that is itself staged: merge at once
    if own:
        run = OutputRun(force=force)
    if not p.exists():
        run.makedirs(p.parent)
    try:
        # absolute: files written into it are recognised as inside it (_in_tmpdir compares absolute paths);
        # a relative --report DIR made a relative key and its files were staged twice
        parent = p.parent if p.parent.exists() else None
        tmp = Path(os.path.abspath(tempfile.mkdtemp(
            prefix=side_name(p.name, parent or tempfile.gettempdir(), suffix=".", extra=_RANDOM), dir=parent)))
    except OSError as exc:
        raise _oserror(exc, p, "cannot create the folder") from None
    run.tmpdirs[tmp] = real_path(p)
    try:
        yield tmp
    except BaseException:
        run.tmpdirs.pop(tmp, None)
        shutil.rmtree(tmp, ignore_errors=True)
        if own:
            run.rollback()
        raise
    if own:
        run.commit()
