"""The demo runs every pipeline, links every report, and reports a failing step without hiding it."""

import json
from pathlib import Path

import pytest

from tyrefit.cli import main
from tyrefit.commands.demo import STEPS, run_demo


def _pipelines(tmp_path):
    d = tmp_path / "pipelines"
    d.mkdir()
    (d / "good.py").write_text(
        "from pathlib import Path\n"
        "def main(out):\n"
        "    out = Path(out); out.mkdir(parents=True, exist_ok=True)\n"
        "    (out / 'index.html').write_text('<html>good</html>')\n"
        "    return {'headline': 'all good', 'value': 3}\n")
    (d / "paths.py").write_text(  # a step that records the path of a file it wrote (as sim --json does)
        "import json\nfrom pathlib import Path\n"
        "def main(out):\n"
        "    out = Path(out); out.mkdir(parents=True, exist_ok=True)\n"
        "    (out / 't.tir').write_text('x')\n"
        "    (out / 'r.json').write_text(json.dumps({'file': str(out / 't.tir')}))\n"
        "    return {'headline': 'paths'}\n")
    (d / "bad.py").write_text("def main(out):\n    raise ValueError('no data for this step')\n")
    return d


def test_demo_links_reports_and_shows_failed_steps(tmp_path):
    steps = [("good", "good.py", "a step that works"), ("bad", "bad.py", "a step that fails")]
    records, index = run_demo(tmp_path / "demo", steps=steps, pipelines=_pipelines(tmp_path))
    assert [r["status"] for r in records] == ["ok", "failed"]
    assert (tmp_path / "demo" / "bad" / "log.txt").is_file()
    html = index.read_text()
    assert '<a href="good/index.html">good</a>' in html
    assert "ValueError: no data for this step" in html
    summary = json.loads((tmp_path / "demo" / "demo.json").read_text())
    assert summary[0]["numbers"] == {"value": 3}


def test_demo_json_names_the_final_folder_not_the_staging_one(tmp_path):
    out = tmp_path / "demo"
    run_demo(out, steps=[("paths", "paths.py", "records a path")], pipelines=_pipelines(tmp_path))
    recorded = Path(json.loads((out / "paths" / "r.json").read_text())["file"])
    assert recorded == out / "paths" / "t.tir" and recorded.is_file()


def test_demo_refuses_to_replace_a_report_without_force(tmp_path, capsys):
    out = tmp_path / "demo"
    out.mkdir()
    (out / "index.html").write_text("keep me")
    assert main(["demo", "--out", str(out)]) == 2
    assert (out / "index.html").read_text() == "keep me"
    assert len(capsys.readouterr().err.strip().splitlines()) == 1


def test_every_demo_step_has_a_pipeline():
    from tyrefit.io.datasets import data_dir

    for _, script, _ in STEPS:
        assert (data_dir().parent / "pipelines" / script).is_file(), script


@pytest.mark.slow
def test_full_demo_on_bundled_data(tmp_path):
    from tyrefit.io.tir import read_tyre
    from tyrefit.tyres.contract import check_tyre

    records, index = run_demo(tmp_path / "demo")
    assert all(r["status"] == "ok" for r in records), [r["headline"] for r in records]
    for r in records:
        assert (tmp_path / "demo" / r["link"]).is_file()
    # every tyre the demo writes keeps the physical-validity contract over the range it declares
    tyres = sorted((tmp_path / "demo").rglob("*.tir"))
    assert tyres
    for f in tyres:
        assert check_tyre(read_tyre(f)) == [], f
