"""The HTML report of ``tyrefit diagnose --base mf61``: the MF tyre's error per channel, what it holds neutral,
the corrections beyond MF 6.1 and what is left."""

from __future__ import annotations

import os
from pathlib import Path
from types import SimpleNamespace

import numpy as np
from matplotlib.figure import Figure

from ..io.outputs import staged_dir, write_text
from ..io.report import Report
from . import views
from .channel_report import _NAMES, _SLIP, _waterfall

__all__ = ["build_report", "write_report"]

_SLIP_FY = ("slip angle [deg]", 180.0 / np.pi)


def _waterfalls(lg) -> Figure:
    chans = list(lg.channels)
    fig = Figure(figsize=(4.6 * max(len(chans), 1), 3.9), layout="constrained")
    axes = np.atleast_1d(fig.subplots(1, max(len(chans), 1)))
    for ax, ch in zip(axes, chans):
        c = lg.channels[ch]
        labels = [f"{lg.model.upper()}\ntyre"] + [f"+\n{s['added']}" for s in c.steps[1:]]
        _waterfall(ax, labels, [s["rmse"] for s in c.steps], [s["rmse_heldout"] for s in c.steps], c.noise_floor,
                   c.data.unit, _NAMES[ch])
    return fig


def _residual_maps(c) -> Figure:
    shim = SimpleNamespace(data=c.data.sweeps, steps=[SimpleNamespace(fit=SimpleNamespace(resid=c.resid), added=None)])
    label, factor = _SLIP.get(c.channel, _SLIP_FY)
    fig = views.plot_residual_maps(shim, steps=(0,), slip_label=label, slip_factor=factor, unit=c.data.unit)
    fig.suptitle(f"{_NAMES[c.channel]}: residual of the final model", fontsize=12)
    return fig


def build_report(lg) -> Report:
    r = Report(f"tyrefit diagnose --base {lg.model} — what the Magic Formula tyre still misses")
    r.p(f"Base: the {lg.model.upper()} tyre that `tyrefit fit --model {lg.model}` writes from these records (the same "
        "code and options). For every channel the records carry: the coefficients the fit held at their neutral "
        "values (the data cannot identify them: the tyre may carry the effect, the data cannot show it), "
        "corrections for effects MF 6.1 cannot carry, tested on held-out sweeps with the tyre held as fitted, "
        "and the verdict on what is left. The MF tyre is not refitted per fold: its held-out error is its error.")
    r.h2("1. Error per channel")
    r.figure(_waterfalls(lg), "RMSE of the exported MF tyre per channel, then with each accepted correction (not in "
                              "the .tir); the dashed line is the channel's within-sweep noise floor.")
    for ch, why in lg.channels_absent.items():
        r.p(f"{_NAMES[ch]}: not diagnosed - {why}.")
    for i, (ch, c) in enumerate(lg.channels.items(), start=2):
        r.h2(f"{i}. {_NAMES[ch][0].upper()}{_NAMES[ch][1:]}")
        r.p(c.unexplained.get("summary", ""), cls="warn" if c.unexplained.get("structure_found") else "note")
        held = lg.held.get(ch, {})
        if held:
            r.table([{"coefficient": k, "why it was held neutral": v} for k, v in sorted(held.items())],
                    caption="MF 6.1 terms of this channel the fit held neutral: the test that would identify "
                            "each is in its reason")
        r.table([{"correction (beyond MF 6.1)": x["effect"], "status": x["status"],
                  f"held-out gain [{c.data.unit}]": x.get("delta_heldout", "–"),
                  "sweeps improved": x.get("sweeps_improved", "–"), "p (held-out sweeps)": x.get("p_value", "–"),
                  "why": x.get("reason", "")} for x in c.candidates], digits=3)
        for x in c.candidates:
            if x["status"] == "accepted":
                r.p(f"{x['effect']} ({x['title']}): {x['physics']}")
        r.figure(_residual_maps(c), "Mean residual (model - data) of the final model over slip and load, faceted by "
                                    "camber and pressure.")
    other = {k: v for k, v in lg.held.items() if k not in lg.channels}
    if other:
        r.h2(f"{len(lg.channels) + 2}. Other held terms")
        r.table([{"part": part, "coefficient": k, "why": v} for part, d in sorted(other.items())
                 for k, v in sorted(d.items())])
    r.json_block(lg.to_dict(), "diagnosis JSON")
    return r


def write_report(lg, directory: str | os.PathLike, force: bool = False) -> Path:
    report = build_report(lg)
    with staged_dir(directory, force=force) as tmp:
        write_text(tmp / "index.html", report.html(), force=True)
    return Path(directory) / "index.html"
