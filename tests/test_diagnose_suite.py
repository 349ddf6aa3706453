"""Issue 11's rates on truths outside the effect catalogue (slow tier) and the mutation check.

The cases come from :mod:`tyrefit.synthetic.validation` (a truth tyre and
effects written without the catalogue's forms; see its docstrings).  The
slow tier asserts the issue's targets on one-sweep-per-load data (6 sweeps),
that data with >= 8 sweeps keep their rates, and that the suite *fails* when
the engine is broken on purpose (held-out evidence replaced by in-sample,
guards removed): a validation that passes a broken engine validates nothing.
``python -m tyrefit.synthetic.validation`` prints the same rates for many more
cases (the lead's table); here the counts are kept to minutes.
"""

import pytest

from tyrefit.synthetic.validation import runner as vr

pytestmark = pytest.mark.slow

#: seeds per (noise, effect) and nulls per noise model in the slow tier
N_EFFECT, N_NULL = 8, 25


def _failed(checks):
    return [f"{c['noise']} {c['family']} {c['check']}: {c['k']}/{c['n']}" for c in checks if not c["ok"]]


def test_one_sweep_per_load_meets_the_issue_targets():
    effects = [e for effs in vr.TARGET_FAMILIES.values() for e in effs]
    rows = vr.run(vr.plan_cases(["load6"], None, effects + ["null"], n_null=N_NULL, n_effect=N_EFFECT),
                  verbose=False)
    checks = vr.check_targets(rows, "load6")
    assert sum(c["check"] in ("false alarms", "right family first") for c in checks) == 3 * (1 + 4)
    assert not _failed(checks), _failed(checks)


def test_eight_sweeps_and_more_keep_their_rates():
    # 4 loads x 3 cambers x 2 pressures: the kind of grid the previous suite had (30 sweeps)
    rows = vr.run(vr.plan_cases(["grid24"], None, None, n_null=6, n_effect=2), verbose=False)
    res = vr.rates(rows)
    bad = []
    for g in res["groups"]:
        if g["effect"] == "null":
            if g["false_alarm"] > vr.TARGETS["false_alarm"]:
                bad.append(f"{g['noise']} null: {g['false_alarm']:.2f} false alarms")
        elif g["right_first"] < 0.9:  # the previous session's suite required >= 90 %
            bad.append(f"{g['noise']} {g['effect']}: right first {g['right_first']:.2f} ({g['first_families']})")
    assert not bad, bad


#: mutations the suite must catch (see runner.MUTATIONS; they patch names in tyrefit.diagnose.engine).  On the
#: engine of issue 11 several layers hold the false-alarm level: one guard removed raises the false alarms under
#: correlated noise by a few points only (measured: see the closing report), which 40 nulls cannot tell from the
#: engine's own rate; removing the screening test is caught by the false alarms, in-sample "held-out" evidence by
#: the out-of-sample check (held-out RMSE equal to the in-sample one on every case)
MUST_CATCH = ["noscreen", "insample", "insample+noconfirm+noscreen"]


@pytest.mark.parametrize("mutation", MUST_CATCH)
def test_the_suite_fails_a_broken_engine(mutation):
    n = 20
    rows = vr.run(vr.plan_cases(["load6"], ["offsets", "ar1"], ["null"], n_null=n), verbose=False, mutation=mutation)
    checks = vr.check_targets(rows, "load6")
    k = sum(bool(r.get("false_alarm", True)) for r in rows)
    # a clear failure: the whole 95 % interval of the false-alarm rate above the 5 % target, or held-out
    # evidence that is not held out
    caught = vr.wilson(k, len(rows))[0] > vr.TARGETS["false_alarm"] or any(
        not c["ok"] for c in checks if c["check"] == "held-out evidence is out of sample")
    assert caught, (f"{k}/{len(rows)} false alarms", checks)


def test_the_unmutated_engine_passes_the_out_of_sample_check():
    rows = vr.run(vr.plan_cases(["load6"], ["offsets", "ar1"], ["null"], n_null=10), verbose=False)
    c = next(c for c in vr.check_targets(rows, "load6") if c["check"] == "held-out evidence is out of sample")
    assert c["ok"], c
