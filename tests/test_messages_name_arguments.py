"""Library messages name the function argument; the command line (errors.cli_style) reads it as the flag."""

from __future__ import annotations

import pytest

from tyrefit.effects.catalogue import _overload
from tyrefit.errors import ModelError, cli_style
from tyrefit.io.chrono_doc import _flags_for
from tyrefit.workflows.batch import scheduler_warning


class _Summary:
    rated_load = None
    fz_levels = (1000.0, 2000.0)


@pytest.mark.parametrize("style, expect, absent", [("api", "rated_load=NEWTONS", "--rated-load"),
                                                   ("cli", "--rated-load NEWTONS", "rated_load=")])
def test_rule_reason_and_warning_follow_the_caller(style, expect, absent):
    if style == "cli":
        with cli_style():
            reason, warn = _overload(_Summary()), scheduler_warning(("tcp", "10.0.0.5", 8786))
    else:
        reason, warn = _overload(_Summary()), scheduler_warning(("tcp", "10.0.0.5", 8786))
    assert expect in reason and absent not in reason
    assert warn.startswith("--scheduler tcp://10.0.0.5:8786" if style == "cli" else "scheduler=tcp://10.0.0.5:8786")


def test_chrono_error_names_the_fit_arguments():
    err = ModelError("needs Width; " + _flags_for(["Width", "Vertical Stiffness"]))
    assert "size=SIZE" in str(err) and "rated_load=NEWTONS" in str(err) and "vertical=VERTICAL.csv" in str(err)
    assert "--" not in str(err)
    with cli_style():
        assert "--size SIZE" in str(err) and "--rated-load NEWTONS" in str(err) and "--vertical VERTICAL.csv" in str(err)
