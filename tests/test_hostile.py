"""The hostile-input corpus (tests/hostile): every case exits 0 with a checked result or 2 with one line.

The default tier runs the fast subset (cases marked ``fast``: the issue's
data-loss and hang cases among them); the slow tier runs the whole corpus
(``pytest -m slow tests/test_hostile.py``; or ``python -m tests.hostile`` for
the table).  Each case runs the installed ``tyrefit`` as a subprocess with a
timeout and hashes every file that existed before the run.  The fast subset's
cases run two at a time (each in its own folder, process and timeout; the
commands spend much of their time starting Python), and each case's verdict
is still its own test.
"""

from __future__ import annotations

from concurrent.futures import ThreadPoolExecutor

import pytest

from hostile import all_cases, run_case

CASES = all_cases()
FAST = [c for c in CASES if c.fast]


def _judge(case, o=None):
    o = run_case(case) if o is None else o
    assert o.verdict == "pass", (f"{case.name}: {o.verdict} ({o.why}); exit {o.code}, {o.seconds:.1f} s; "
                                 f"actual: {o.actual}; stderr: {o.stderr[-600:]}")


@pytest.fixture(scope="module")
def fast_outcomes(request):
    """The fast cases this session selected, started two at a time: {name: future of run_case's Outcome}."""
    wanted = {item.callspec.params["case"].name for item in request.session.items
              if getattr(item, "function", None) is test_fast_subset and hasattr(item, "callspec")}
    with ThreadPoolExecutor(max_workers=2) as pool:
        return {c.name: pool.submit(run_case, c) for c in FAST if c.name in wanted}


@pytest.mark.parametrize("case", FAST, ids=lambda c: c.name)
def test_fast_subset(case, fast_outcomes):
    _judge(case, fast_outcomes[case.name].result())


@pytest.mark.slow
@pytest.mark.parametrize("case", [c for c in CASES if not c.fast], ids=lambda c: c.name)
def test_full_corpus(case):
    _judge(case)


def test_corpus_covers_every_command_with_enough_cases():
    commands = {c.command.split()[0] for c in CASES}
    assert {"fit", "diagnose", "compare", "sim", "slip", "traction", "rig", "batch", "inspect", "demo"} <= commands
    assert len(CASES) >= 150
    assert sum(c.expect == "ok" for c in CASES) >= 30  # legitimate inputs too, each with a checked result


def test_judge_catches_lost_data_and_wrong_results(tmp_path):
    """The judge itself bites: a case that destroys its input, one that accepts garbage, one that hangs."""
    from hostile import Case

    lost = run_case(Case("overwrite", "inspect", ["inspect", "{d}/d.csv", "--json", "{d}/d.csv", "--force"],
                         {"d.csv": "x\n"}, "ok"), base=tmp_path)
    assert lost.verdict != "pass"
    wrong = run_case(Case("accepts", "inspect", ["inspect", "{data}/sim/hard_front.tir"], {}, "error", "x"),
                     base=tmp_path)
    assert wrong.verdict == "WRONG"
    hang = run_case(Case("slow", "sim", ["sim", "curved"], {}, "ok", timeout=0.5), base=tmp_path)
    assert hang.hang and hang.verdict == "HANG"
