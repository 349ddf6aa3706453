"""Safe outputs: nothing already on disk is lost."""

import pytest

from tyrefit.errors import OutputExistsError
from tyrefit.io.outputs import atomic_write, check_output, staged_dir, write_text


def test_write_text_creates_and_refuses_to_replace(tmp_path):
    p = tmp_path / "out.txt"
    write_text(p, "first")
    with pytest.raises(OutputExistsError, match="force=True"):
        write_text(p, "second")
    assert p.read_text() == "first"
    write_text(p, "second", force=True)
    assert p.read_text() == "second"


def test_failure_inside_atomic_write_leaves_existing_file_and_no_temp(tmp_path):
    p = tmp_path / "out.txt"
    p.write_text("precious")
    with pytest.raises(RuntimeError):
        with atomic_write(p, "w", force=True) as fh:
            fh.write("partial")
            raise RuntimeError("boom")
    assert p.read_text() == "precious"
    assert sorted(x.name for x in tmp_path.iterdir()) == ["out.txt"]


def test_check_output_is_a_file_exists_error(tmp_path):
    p = tmp_path / "x"
    p.write_text("")
    with pytest.raises(FileExistsError):
        check_output(p)
    assert check_output(tmp_path / "new") == tmp_path / "new"


def test_staged_dir_swaps_in_only_on_success(tmp_path):
    d = tmp_path / "report"
    with staged_dir(d) as tmp:
        (tmp / "index.html").write_text("v1")
    assert (d / "index.html").read_text() == "v1"
    with pytest.raises(OutputExistsError):
        with staged_dir(d):
            pass
    with pytest.raises(ValueError):
        with staged_dir(d, force=True) as tmp:
            (tmp / "index.html").write_text("v2")
            raise ValueError("failed run")
    assert (d / "index.html").read_text() == "v1"
    with staged_dir(d, force=True) as tmp:
        (tmp / "index.html").write_text("v2")
    assert (d / "index.html").read_text() == "v2"
    assert sorted(x.name for x in tmp_path.iterdir()) == ["report"]


def test_written_files_get_the_usual_mode(tmp_path):
    import os

    p = write_text(tmp_path / "mode.txt", "x")
    mask = os.umask(0)
    os.umask(mask)
    assert p.stat().st_mode & 0o777 == 0o666 & ~mask


# --------------------------------------------------------------------------- one output layer (issue 15)

import errno
import os
import subprocess
import sys

from tyrefit.errors import OutputError
from tyrefit.io.outputs import MANIFEST, check_report_dir, output_run, read_manifest


def test_run_commits_every_output_together_or_none(tmp_path):
    tir, js = tmp_path / "t.tir", tmp_path / "t.json"
    tir.write_text("earlier tyre")
    with pytest.raises(RuntimeError):
        with output_run(force=True):
            write_text(tir, "new tyre", force=True)
            assert tir.read_text() == "earlier tyre"  # staged, not in place yet
            write_text(js, "{}")
            raise RuntimeError("the report failed")
    assert tir.read_text() == "earlier tyre" and not js.exists()
    assert sorted(p.name for p in tmp_path.iterdir()) == ["t.tir"]  # no temporaries left
    with output_run(force=True):
        write_text(tir, "new tyre", force=True)
        write_text(js, "{}")
    assert tir.read_text() == "new tyre" and js.read_text() == "{}"


def test_failed_commit_restores_what_it_had_replaced(tmp_path, monkeypatch):
    a, b = tmp_path / "a.txt", tmp_path / "b.txt"
    a.write_text("old a")
    b.write_text("old b")
    real = os.replace
    calls = []

    def flaky(src, dst):
        calls.append(dst)
        if str(dst).endswith("b.txt"):
            raise OSError(errno.ENOSPC, "No space left on device")
        return real(src, dst)
    monkeypatch.setattr(os, "replace", flaky)
    with pytest.raises(OutputError, match=r"b\.txt: cannot write \(no space left"):
        with output_run(force=True):
            write_text(a, "new a", force=True)
            write_text(b, "new b", force=True)
    monkeypatch.setattr(os, "replace", real)
    assert a.read_text() == "old a" and b.read_text() == "old b"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a.txt", "b.txt"]


def test_an_output_may_never_be_an_input(tmp_path):
    data = tmp_path / "d.csv"
    data.write_text("x")
    link = tmp_path / "hard.json"
    os.link(data, link)
    sym = tmp_path / "sym.json"
    sym.symlink_to(data)
    for target in (data, link, sym, tmp_path / "sub" / ".." / "d.csv"):
        with pytest.raises(OutputError, match="is an input"):
            with output_run(inputs=[data], force=True):
                write_text(target, "overwritten", force=True)
    assert data.read_text() == "x"


def test_the_same_file_twice_in_one_run_is_refused(tmp_path):
    with pytest.raises(OutputError, match="written twice"):
        with output_run():
            write_text(tmp_path / "a.tir", "1")
            write_text(tmp_path / "." / "a.tir", "2")
    assert not (tmp_path / "a.tir").exists()


def test_report_folder_keeps_files_tyrefit_did_not_write(tmp_path):
    d = tmp_path / "report"
    d.mkdir()
    (d / "notes.txt").write_text("mine")
    with pytest.raises(OutputExistsError, match="not empty.*did not write"):
        check_report_dir(d)
    with output_run(reports=[d], force=True):
        write_text(d / "index.html", "v1", force=True)
    assert (d / "notes.txt").read_text() == "mine" and read_manifest(d) == {"index.html"}
    with output_run(reports=[d], force=True):  # its own file is replaced
        write_text(d / "index.html", "v2", force=True)
    assert (d / "index.html").read_text() == "v2"
    with pytest.raises(OutputExistsError, match="not written by tyrefit"):
        with output_run(reports=[d], force=True):
            write_text(d / "notes.txt", "replaced", force=True)
    assert (d / "notes.txt").read_text() == "mine"
    with pytest.raises(OutputExistsError, match="not written by tyrefit"):
        with staged_dir(d, force=True) as tmp:  # a folder merged in: same rule
            (tmp / "notes.txt").write_text("replaced")
    assert (d / "notes.txt").read_text() == "mine"


def test_staged_dir_merge_refuses_a_foreign_file(tmp_path):
    d = tmp_path / "report"
    d.mkdir()
    (d / "index.html").write_text("my own page")
    with pytest.raises(OutputExistsError, match="not written by tyrefit"):
        with staged_dir(d, force=True) as tmp:
            (tmp / "index.html").write_text("tyrefit's page")
    assert (d / "index.html").read_text() == "my own page"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["report"]
    assert MANIFEST not in {p.name for p in d.iterdir()}


@pytest.mark.parametrize("setup,target,match", [
    (lambda d: (d / "f").write_text("x"), "f/out.tir", "is a file"),
    (lambda d: (d / "o.tir").mkdir(), "o.tir", "is a folder"),
])
def test_os_level_refusals_name_the_path(tmp_path, setup, target, match):
    setup(tmp_path)
    with pytest.raises(OutputError, match=match):
        write_text(tmp_path / target, "x", force=True)


def test_file_too_large_is_one_line_and_keeps_the_old_file(tmp_path):
    """RLIMIT_FSIZE makes write() fail with EFBIG ('File too large'), like a full disk."""
    p = tmp_path / "out.tir"
    p.write_text("old")
    code = ("import resource, sys\n"
            "resource.setrlimit(resource.RLIMIT_FSIZE, (10, 10))\n"
            "from tyrefit.io.outputs import write_text, output_run\n"
            "from tyrefit.errors import OutputError\n"
            "try:\n"
            "    with output_run(force=True):\n"
            f"        write_text({str(p)!r}, 'x' * 100000, force=True)\n"
            "except OutputError as e:\n"
            "    print(e)\n")
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=60)
    assert "out.tir: cannot write (file too large" in r.stdout, r.stderr
    assert p.read_text() == "old" and sorted(x.name for x in tmp_path.iterdir()) == ["out.tir"]


def test_a_symbolic_link_named_as_output_is_replaced_not_written_through(tmp_path):
    precious = tmp_path / "precious.txt"
    precious.write_text("keep")
    link = tmp_path / "link.tir"
    link.symlink_to(precious)
    with output_run(force=True):
        write_text(link, "new tyre", force=True)
    assert precious.read_text() == "keep" and not link.is_symlink() and link.read_text() == "new tyre"


@pytest.mark.parametrize("target", ["/dev/null", "/dev/stdout"])
def test_devices_and_pipes_are_never_outputs(target):
    with pytest.raises(OutputError, match="regular files only"):
        write_text(target, "x", force=True)
