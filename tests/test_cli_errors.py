"""Bad input on the command line: exit 2, one line on stderr, no traceback, outputs untouched."""

import os
import subprocess
import sys
from pathlib import Path

import pytest
from test_io_errors import CASES, GOOD_HEADER

from tyrefit.cli import main
from tyrefit.errors import TyrefitError

DATA = Path(__file__).parent / "data"


def one_line_error(capsys, command="inspect"):
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.endswith("\n"), err
    assert err.startswith(f"tyrefit {command}: error: ")
    assert "Traceback" not in err
    return err


@pytest.mark.parametrize("case", sorted(CASES))
def test_inspect_bad_csv_exit_2_one_line(tmp_path, capsys, case):
    _, text, _ = CASES[case]
    p = tmp_path / "bad.csv"
    p.write_text(text)
    assert main(["inspect", str(p)]) == 2
    err = one_line_error(capsys)
    assert str(p) in err


def test_inspect_binary(tmp_path, capsys):
    p = tmp_path / "x.dat"
    p.write_bytes(bytes(range(256)) * 4)
    assert main(["inspect", str(p)]) == 2
    assert "binary content" in one_line_error(capsys)


def test_inspect_missing_file(tmp_path, capsys):
    assert main(["inspect", str(tmp_path / "none.csv")]) == 2
    assert "no such file" in one_line_error(capsys)


def _sweep_csv(tmp_path, rows):
    p = tmp_path / "sweep.csv"
    p.write_text(GOOD_HEADER + "\n" + rows)
    return p


def test_fit_tir_handed_in_as_data(tmp_path, capsys):
    out = tmp_path / "o.tir"
    assert main(["fit", str(DATA / "io_adams_pac89_example.tir"), "--out", str(out)]) == 2
    assert "this is a tyre property file (.tir), not measurement data; use it with compare/sim" in \
        one_line_error(capsys, "fit")
    assert not out.exists()


def test_fit_static_without_patch(tmp_path, capsys):
    p = tmp_path / "static.csv"
    p.write_text("lateral_displacement [mm],fy [N],fz [N]\n" + "".join(f"{d},{20 * d},{5000 - d}\n" for d in range(20)))
    assert main(["fit", str(p), "--out", str(tmp_path / "o.tir")]) == 2
    err = one_line_error(capsys, "fit")
    assert "patch" in err and str(p) in err


def test_fit_too_few_points(tmp_path, capsys):
    p = _sweep_csv(tmp_path, "".join(f"{a},{-80 * a},3000\n" for a in range(-3, 3)))
    assert main(["fit", str(p), "--out", str(tmp_path / "o.tir")]) == 2
    assert "too few points to fit: 6; at least 10 are needed" in one_line_error(capsys, "fit")


def test_fit_sweep_without_slip_variation(tmp_path, capsys):
    rows = "".join(f"{a},{-80 * a},3000\n" for a in range(-5, 6)) + "".join(f"0.1,{k},5000\n" for k in range(11))
    p = _sweep_csv(tmp_path, rows)
    assert main(["fit", str(p), "--out", str(tmp_path / "o.tir")]) == 2
    assert "sweep 1 (fz 5000 N, 11 points) has no slip_angle variation" in one_line_error(capsys, "fit")


def test_usage_error_is_one_line(capsys):
    with pytest.raises(SystemExit) as info:
        main(["inspect"])
    assert info.value.code == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "error:" in err


# --------------------------------------------------------------------------- outputs are never lost


def test_existing_json_needs_force_and_stays_untouched(tmp_path, capsys):
    out = tmp_path / "out.json"
    out.write_text("precious\n")
    assert main(["inspect", str(DATA / "io_adams_pac89_example.tir"), "--json", str(out)]) == 2
    assert "output exists; pass --force to replace it" in one_line_error(capsys)
    assert out.read_text() == "precious\n"


def test_failing_run_with_force_leaves_output_untouched(tmp_path, capsys):
    out = tmp_path / "out.json"
    out.write_text("precious\n")
    bad = tmp_path / "bad.csv"
    bad.write_text(GOOD_HEADER + "\n1,2,-3000\n")
    assert main(["inspect", str(bad), "--json", str(out), "--force"]) == 2
    one_line_error(capsys)
    assert out.read_text() == "precious\n"
    assert sorted(os.listdir(tmp_path)) == ["bad.csv", "out.json"]  # no temporary file left behind
    tir = tmp_path / "tyre.tir"
    tir.write_text("keep me\n")
    assert main(["fit", str(bad), "--out", str(tir), "--force"]) == 2
    one_line_error(capsys, "fit")
    assert tir.read_text() == "keep me\n"


def test_successful_run_with_force_replaces_output(tmp_path, capsys):
    out = tmp_path / "out.json"
    out.write_text("old\n")
    assert main(["inspect", str(DATA / "io_adams_pac89_example.tir"), "--json", str(out), "--force"]) == 0
    assert '"kind": "tyre"' in out.read_text()


def test_json_output_may_not_overwrite_the_input(tmp_path, capsys):
    p = tmp_path / "d.csv"
    p.write_text(GOOD_HEADER + "\n1,-80,3000\n")
    before = p.read_text()
    assert main(["inspect", str(p), "--json", str(p), "--force"]) == 2
    assert "is an input of this run" in one_line_error(capsys)
    assert p.read_text() == before


# --------------------------------------------------------------------------- --debug


def test_debug_raises_in_process(tmp_path):
    bad = tmp_path / "bad.csv"
    bad.write_text("")
    with pytest.raises(TyrefitError, match="file is empty"):
        main(["inspect", str(bad), "--debug"])


def test_debug_shows_traceback(tmp_path):
    bad = tmp_path / "bad.csv"
    bad.write_text("")
    cmd = [sys.executable, "-m", "tyrefit.cli", "inspect", str(bad)]
    quiet = subprocess.run(cmd, capture_output=True, text=True, timeout=120)
    loud = subprocess.run(cmd + ["--debug"], capture_output=True, text=True, timeout=120)
    assert quiet.returncode == 2 and "Traceback" not in quiet.stderr and quiet.stderr.count("\n") == 1
    assert loud.returncode != 0 and "Traceback (most recent call last)" in loud.stderr
    assert "FormatError" in loud.stderr


# --------------------------------------------------------------------------- issue 15: inputs and outputs


def _good_sweeps(path):
    from hostile import GOOD

    path.write_text(GOOD)
    return path


def test_fifo_and_devices_are_refused_at_once(tmp_path, capsys):
    fifo = tmp_path / "pipe.csv"
    os.mkfifo(fifo)
    assert main(["fit", str(fifo), "--out", str(tmp_path / "t.tir")]) == 2  # used to hang
    assert "is a FIFO" in one_line_error(capsys, "fit")
    assert main(["inspect", "/dev/zero"]) == 2  # used to fill memory (MemoryError)
    assert "character device" in one_line_error(capsys)
    assert main(["compare", str(DATA / "io_adams_pac89_example.tir"), str(fifo)]) == 2
    assert "FIFO" in one_line_error(capsys, "compare")


def test_size_limit_and_max_size_flag(tmp_path, capsys):
    d = _good_sweeps(tmp_path / "d.csv")
    assert main(["inspect", str(d), "--max-size", "0.001"]) == 2
    err = one_line_error(capsys)
    assert "over the input size limit of 0.001 MB" in err and "--max-size" in err
    assert main(["inspect", str(d), "--max-size", "1"]) == 0
    capsys.readouterr()
    for bad in ("nan", "-1", "0", "inf"):
        assert main(["inspect", str(d), "--max-size", bad]) == 2
        assert "--max-size" in one_line_error(capsys)


@pytest.mark.parametrize("argv,match", [
    (["fit", "{d}", "--rated-load", "nan", "--out", "{t}/t.tir"], "rated load must be a positive"),
    (["fit", "{d}", "--rated-load", "-5", "--out", "{t}/t.tir"], "rated load must be a positive"),
    (["fit", "{d}", "--rated-load", "1e9", "--out", "{t}/t.tir"], "at most 200 kN"),
    (["diagnose", "{d}", "--rated-load", "inf", "--json", "{t}/o.json"], "rated load"),
    (["diagnose", "{d}", "--seed", "-1", "--json", "{t}/o.json"], "seed"),
    (["sim", "adhesion", "--road-mu", "nan"], "road-mu"),
    (["sim", "adhesion", "--camber", "inf"], "camber"),
    (["batch", "fit", "{t}", "--out", "{t}/o", "--workers", "0"], "worker"),
])
def test_numeric_flags_are_finite_and_in_range(tmp_path, capsys, argv, match):
    d = _good_sweeps(tmp_path / "d.csv")
    argv = [a.format(d=d, t=tmp_path) for a in argv]
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and match in err and "Traceback" not in err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["d.csv"]


def test_fit_outputs_are_committed_together(tmp_path, capsys):
    d = _good_sweeps(tmp_path / "d.csv")
    tir = tmp_path / "t.tir"
    tir.write_text("earlier tyre\n")
    (tmp_path / "r").write_text("a file, not a folder\n")
    assert main(["fit", str(d), "--out", str(tir), "--report", str(tmp_path / "r"), "--force"]) == 2
    assert "is a file" in one_line_error(capsys, "fit")
    assert tir.read_text() == "earlier tyre\n"
    assert main(["fit", str(d), "--out", str(tir), "--json", str(tir)]) == 2
    assert "named twice" in one_line_error(capsys, "fit")
    assert main(["fit", str(d), "--out", str(tir), "--json", str(d), "--force"]) == 2
    assert "is an input" in one_line_error(capsys, "fit")
    assert d.read_text().startswith("run,")
    (tmp_path / "o.tir").mkdir()
    assert main(["fit", str(d), "--out", str(tmp_path / "o.tir"), "--force"]) == 2
    assert "is a folder" in one_line_error(capsys, "fit")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["d.csv", "o.tir", "r", "t.tir"]


def test_disk_full_is_one_line_and_keeps_the_earlier_tyre(tmp_path):
    d = _good_sweeps(tmp_path / "d.csv")
    tir = tmp_path / "t.tir"
    tir.write_text("earlier tyre\n")
    code = ("import resource, sys\nresource.setrlimit(resource.RLIMIT_FSIZE, (2000, 2000))\n"
            "from tyrefit.cli import main\nsys.exit(main(sys.argv[1:]))\n")
    r = subprocess.run([sys.executable, "-c", code, "fit", str(d), "--out", str(tir), "--force"],
                       capture_output=True, text=True, timeout=300)
    assert r.returncode == 2 and "Traceback" not in r.stderr, r.stderr
    assert r.stderr.count("\n") == 1 and "t.tir: cannot write (file too large" in r.stderr
    assert tir.read_text() == "earlier tyre\n"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["d.csv", "t.tir"]


def test_messages_name_keywords_in_python_and_flags_on_the_command_line(tmp_path, capsys):
    """One message, two spellings: ``rated_load=`` for a Python caller, ``--rated-load`` for the CLI user."""
    import tyrefit as tf
    from tyrefit.errors import DataError

    data = Path(__file__).resolve().parents[1] / "data" / "truck" / "tyre_a_dynamic.csv"
    with pytest.raises(DataError) as e:
        tf.fit(str(data), rated_load=-5.0)
    assert str(e.value).startswith("rated_load=-5.0") and "--" not in str(e.value)
    assert main(["fit", str(data), "--rated-load", "-5", "--out", str(tmp_path / "t.tir")]) == 2
    err = capsys.readouterr().err
    assert "--rated-load -5" in err and "rated_load=" not in err


def test_library_message_rendered_for_the_command_line(tmp_path, capsys):
    """A message raised deep in the library (the tyre size parser) reads as flags under the CLI."""
    data = Path(__file__).resolve().parents[1] / "data" / "truck" / "tyre_a_dynamic.csv"
    assert main(["fit", str(data), "--size", "banana", "--out", str(tmp_path / "t.tir")]) == 2
    err = capsys.readouterr().err
    assert "--size 'banana'" in err and "size=" not in err
    import tyrefit as tf
    from tyrefit.errors import DataError

    with pytest.raises(DataError, match=r"^size='banana'"):
        tf.fit(str(data), size="banana")
