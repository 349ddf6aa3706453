"""``batch fit --scheduler``: bad addresses are one line and exit 2 in seconds; '' runs locally;
a scheduler neither on this machine nor TLS is warned about (issue 25).

No traffic leaves this machine: every address tried here is loopback, or refused before any
connection is made (monkeypatched ``socket.create_connection``).  The silent-peer run spends
its seconds waiting for a handshake, so it starts in the background when the module starts
and the other tests run meanwhile.
"""

from __future__ import annotations

import socket
import subprocess
import sys
import threading
import time
from pathlib import Path

import pytest

from tyrefit.cli import main
from tyrefit.errors import DataError
from tyrefit.workflows.batch import is_loopback, scheduler_address, scheduler_warning

ROOT = Path(__file__).resolve().parents[1]
DATA = ROOT / "data" / "passenger" / "passenger_205_55R16.csv"

BAD = ["tls://127.0.0.1:1", "ucx://127.0.0.1:1", "inproc://x", "file:///etc/passwd", "tcp://[::1",
       "127.0.0.1:notaport", "tcp://127.0.0.1:1", "tcp://127.0.0.1:0", "tcp://127.0.0.1:70000"]


def _silent_peer_run(out: Path, result: dict) -> None:
    """``batch fit --scheduler`` at a loopback port that accepts and never answers: result['p'], ['elapsed']."""
    srv = socket.socket()
    srv.bind(("127.0.0.1", 0))
    srv.listen(4)
    port = srv.getsockname()[1]
    try:
        t0 = time.perf_counter()
        result["p"] = subprocess.run([sys.executable, "-m", "tyrefit.cli", "batch", "fit", str(DATA), "--out",
                                      str(out), "--scheduler", f"tcp://127.0.0.1:{port}"],
                                     capture_output=True, text=True, timeout=60)
        result["elapsed"] = time.perf_counter() - t0
    finally:
        srv.close()


@pytest.fixture(scope="module", autouse=True)
def silent_peer(request, tmp_path_factory):
    """The silent-peer run, started in a thread as the module starts when its test is selected."""
    if not any(getattr(item, "function", None) is test_silent_loopback_peer_times_out_in_seconds
               for item in request.session.items):
        yield None
        return
    out, result = tmp_path_factory.mktemp("silent_peer") / "o", {}
    t = threading.Thread(target=_silent_peer_run, args=(out, result), daemon=True)
    t.start()
    yield t, out, result
    t.join()


@pytest.mark.parametrize("address", BAD)
def test_bad_scheduler_is_one_line_exit_2_quickly(tmp_path, address):
    t0 = time.perf_counter()
    p = subprocess.run([sys.executable, "-m", "tyrefit.cli", "batch", "fit", str(DATA), "--out",
                        str(tmp_path / "o"), "--scheduler", address], capture_output=True, text=True, timeout=60)
    elapsed = time.perf_counter() - t0
    assert p.returncode == 2, p.stderr
    lines = p.stderr.strip().splitlines()
    assert len(lines) == 1 and "Traceback" not in p.stderr, p.stderr
    assert "scheduler" in lines[0]
    assert elapsed < 10, elapsed
    assert not (tmp_path / "o").exists()


def test_silent_loopback_peer_times_out_in_seconds(silent_peer):
    t, _, result = silent_peer  # started with the module (_silent_peer_run)
    t.join(timeout=120)
    assert not t.is_alive() and "elapsed" in result, result
    p, elapsed = result["p"], result["elapsed"]
    assert p.returncode == 2 and "Traceback" not in p.stderr and len(p.stderr.strip().splitlines()) == 1, p.stderr
    assert elapsed < 30, elapsed  # the handshake deadline is about 7 s; a hang would run to the 60 s timeout


def test_empty_scheduler_runs_locally(tmp_path, capsys):
    assert main(["batch", "fit", str(DATA), "--out", str(tmp_path / "o"), "--scheduler", "", "--workers", "1"]) == 0
    out = capsys.readouterr().out
    assert "1 fitted" in out and "serial" in out
    assert (tmp_path / "o" / "passenger_205_55R16.tir").exists()


def test_address_parsing():
    assert scheduler_address(None) is None and scheduler_address("") is None and scheduler_address("  ") is None
    assert scheduler_address("tcp://127.0.0.1:8786") == ("tcp", "127.0.0.1", 8786)
    assert scheduler_address("localhost") == ("tcp", "localhost", 8786)
    assert scheduler_address("TLS://[::1]:9000") == ("tls", "::1", 9000)
    for bad in BAD[1:6]:
        with pytest.raises(DataError, match="^scheduler="):  # the keyword; the CLI says --scheduler
            scheduler_address(bad)


def test_warning_when_neither_loopback_nor_tls():
    assert is_loopback("127.0.0.1") and is_loopback("::1") and is_loopback("localhost") and is_loopback("127.3.2.1")
    assert not is_loopback("10.0.0.5") and not is_loopback("scheduler.example")
    assert scheduler_warning(("tcp", "127.0.0.1", 8786)) is None
    assert scheduler_warning(("tls", "10.0.0.5", 8786)) is None
    w = scheduler_warning(("tcp", "10.0.0.5", 8786))
    assert w and "pickled" in w and "TLS" in w


def test_cli_prints_the_warning_without_sending_anything(tmp_path, capsys, monkeypatch):
    tried = []

    def refuse(addr, *a, **k):
        tried.append(addr)
        raise ConnectionRefusedError(111, "Connection refused (test: nothing sent)")

    monkeypatch.setattr(socket, "create_connection", refuse)
    assert main(["batch", "fit", str(DATA), "--out", str(tmp_path / "o"), "--scheduler", "tcp://10.255.255.1:8786"]) == 2
    err = capsys.readouterr().err
    assert tried == [("10.255.255.1", 8786)]
    lines = err.strip().splitlines()
    assert len(lines) == 2 and "warning" in lines[0] and "pickled" in lines[0] and "error" in lines[1], err


@pytest.mark.parametrize("content, words", [
    (None, "cannot be read"),
    ("not json", "not JSON"),
    ('{"type": "Scheduler"}', "no 'address'"),
    ('{"address": "ucx://127.0.0.1:1"}', "UCX"),
    ('{"address": "tcp://127.0.0.1:1"}', "cannot connect"),
])
def test_scheduler_file_is_read_and_checked(tmp_path, capsys, content, words):
    """``--scheduler-file``: the address Dask's scheduler wrote, with the same checks; bad files are one line."""
    sf = tmp_path / "scheduler.json"
    if content is not None:
        sf.write_text(content)
    assert main(["batch", "fit", str(DATA), "--out", str(tmp_path / "o"), "--scheduler-file", str(sf)]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and words in err and "Traceback" not in err, err
    assert not (tmp_path / "o").exists()


def test_scheduler_and_scheduler_file_exclude_each_other(tmp_path, capsys):
    with pytest.raises(SystemExit) as e:
        main(["batch", "fit", str(DATA), "--out", str(tmp_path / "o"), "--scheduler", "tcp://127.0.0.1:1",
              "--scheduler-file", str(tmp_path / "s.json")])
    assert e.value.code == 2 and "not allowed with" in capsys.readouterr().err
