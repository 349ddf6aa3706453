"""Safe outputs: nothing already on disk is lost."""

import pytest

from tyrefit.errors import OutputExistsError
from tyrefit.io.outputs import atomic_write, check_output, staged_dir, write_text


def test_write_text_creates_and_refuses_to_replace(tmp_path):
    p = tmp_path / "out.txt"
    write_text(p, "first")
    with pytest.raises(OutputExistsError, match="--force"):
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
