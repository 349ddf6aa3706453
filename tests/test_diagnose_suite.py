"""The hidden-effect suite: right family first, nothing in null data, held-out error near the noise.

The default tier runs a fast subset (one case per family spread over the three
noise models, one null case per noise model); the full suite (4 seeds per
family and noise model, 20 null seeds per noise model) is ``@pytest.mark.slow``.
``python -m tyrefit.synthetic.hidden [--full]`` prints the same rates.
"""

import numpy as np
import pytest

from tyrefit.diagnose import diagnose
from tyrefit.synthetic.hidden import EFFECT_SIZES, NOISE_MODELS, make_case, run_suite, score_case, suite_cases

FAST = [(("load_friction",), "iid"), (("curvature_load",), "ar1"), (("overload",), "offsets"),
        (("camber",), "ar1"), (("offsets",), "offsets"), (("pressure",), "iid"), (("speed",), "ar1"),
        (("camber", "pressure"), "offsets"), ((), "iid"), ((), "offsets"), ((), "ar1")]


@pytest.mark.parametrize("truth,noise", FAST, ids=[f"{'+'.join(t) or 'null'}-{n}" for t, n in FAST])
def test_fast_subset(truth, noise):
    case = make_case(truth, noise, seed=31)
    row = score_case(case, diagnose(case.data, rated_load=case.rated_load, seed=31))
    if truth:
        assert row["right_first"], row
        assert row["all_found"], row
        assert row["ratio_to_true_noise"] <= 1.3, row
    else:
        assert row["null_clean"], row


def test_suite_definition_covers_every_family_and_noise_model():
    cases = suite_cases(full=True)
    truths = {t for t, _, _ in cases}
    for fam in EFFECT_SIZES:
        assert (fam,) in truths
    assert ("camber", "pressure") in truths and () in truths
    assert {n for _, n, _ in cases} == set(NOISE_MODELS)
    assert sum(1 for t, n, _ in cases if not t and n == "ar1") == 20


def test_noise_models_have_the_stated_total_sd():
    for noise in NOISE_MODELS:
        sds = [np.std(make_case((), noise, seed=s, sigma=40.0).data["fy"]
                      - make_case((), noise, seed=s, sigma=1e-9).data["fy"]) for s in range(6)]
        assert np.mean(sds) == pytest.approx(40.0, rel=0.12), noise


@pytest.mark.slow
def test_full_suite_rates():
    res = run_suite(full=True, verbose=False)
    assert res["right_first_rate"] >= 0.9
    for noise, rate in res["null_clean_rate"].items():
        assert rate >= 0.9, noise
    assert res["heldout_ok_rate"] >= 0.9
