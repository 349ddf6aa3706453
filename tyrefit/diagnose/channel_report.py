"""Report views of the channel diagnoses (Mz, Fx): error waterfalls, residual maps, the effects in words."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
from matplotlib.figure import Figure

from ..effects.channels import CHANNEL_EFFECTS, TRAIL_COEFFICIENT
from ..io.report import Report
from . import views
from .channels import ChannelDiagnosis, effect_sizes

__all__ = ["plot_channel_waterfall", "plot_channel_residual_maps", "add_channel_sections"]

_NAMES = {"fy": "lateral force Fy", "mz": "aligning moment Mz", "fx": "longitudinal force Fx"}
_SLIP = {"fy": ("slip angle [deg]", 180.0 / np.pi), "mz": ("slip angle [deg]", 180.0 / np.pi),
         "fx": ("slip ratio [%]", 100.0)}


def _waterfall(ax, labels, rmse, heldout, floor, unit, title):
    x = np.arange(len(rmse))
    ax.bar(x - 0.18, rmse, 0.36, label="RMSE (all sweeps)", color="#4c78a8")
    ax.bar(x + 0.18, heldout, 0.36, label="RMSE (held-out sweeps)", color="#f58518")
    ax.axhline(floor, color="k", ls="--", lw=1, label=f"noise floor {floor:.3g} {unit}")
    for i, v in enumerate(heldout):
        ax.annotate(f"{v:.3g}", (i + 0.18, v), ha="center", va="bottom", fontsize=8)
    # the panel names the channel: drop the effect ids' channel prefix and break long ids at their last '_'
    short = []
    for lab in labels:
        head, _, name = lab.rpartition("\n")
        name = name[3:] if name[:3] in ("mz_", "fx_") else name
        if len(name) > 12 and "_" in name:
            a, _, b = name.rpartition("_")
            name = f"{a}_\n{b}"
        short.append(f"{head}\n{name}" if head else name)
    ax.set_xticks(x, short, fontsize=8)
    ax.set_ylabel(f"RMSE [{unit}]", fontsize=9)
    ax.set_title(title, fontsize=10)
    ax.legend(fontsize=7)


def plot_channel_waterfall(chd: ChannelDiagnosis, ax=None):
    """RMSE and held-out RMSE from the channel's start model to its final one, against its noise floor."""
    if ax is None:
        ax = Figure(figsize=(6.5, 3.6)).subplots()
    labels = (["start\n" + ("trail x Fy" if chd.channel == "mz" else "PAC89")]
              + [f"without\n{s.added[1:]}" if s.added.startswith("-") else f"+\n{s.added}" for s in chd.steps[1:]])
    _waterfall(ax, labels, [s.rmse for s in chd.steps], [s.rmse_heldout for s in chd.steps], chd.noise_floor,
               chd.unit, _NAMES[chd.channel])
    return ax


def plot_all_waterfalls(dg, fig=None):
    """One waterfall per diagnosed channel (Fy, then Mz and Fx where present), side by side; returns the Figure."""
    chans = ["fy"] + [c for c in ("mz", "fx") if c in dg.channels]
    if fig is None:
        fig = Figure(figsize=(4.6 * len(chans), 3.9), layout="constrained")
    axes = np.atleast_1d(fig.subplots(1, len(chans)))
    for ax, ch in zip(axes, chans):
        if ch == "fy":
            labels = ["start\n" + ("+".join(dg.start) or "PAC89")] + [f"+\n{s.added}" for s in dg.steps[1:]]
            _waterfall(ax, labels, [s.rmse for s in dg.steps], [s.rmse_heldout for s in dg.steps], dg.noise_floor,
                       "N", _NAMES["fy"])
        else:
            plot_channel_waterfall(dg.channels[ch], ax=ax)
    return fig


def plot_channel_residual_maps(chd: ChannelDiagnosis, fig=None):
    """Mean residual over slip and load, faceted by camber and pressure, start vs final model; returns the Figure."""
    steps = [SimpleNamespace(fit=SimpleNamespace(resid=s.resid), added=s.added) for s in chd.steps]
    shim = SimpleNamespace(data=chd.data.sweeps, steps=steps)
    label, factor = _SLIP[chd.channel]
    fig = views.plot_residual_maps(shim, fig=fig, slip_label=label, slip_factor=factor, unit=chd.unit)
    fig.suptitle(_NAMES[chd.channel], fontsize=12)
    return fig


def add_channel_sections(r: Report, dg) -> None:
    """The report's part on every channel: waterfalls side by side, then per channel the evidence and maps."""
    if not dg.channels and not dg.channels_absent:
        return
    r.h2("8. Every channel: Fy, Mz and Fx")
    r.p("Each channel the record carries gets its own diagnosis with its own catalogue of effects "
        "(aligning moment: trail and residual torque laws in load, camber and pressure; longitudinal force: "
        "friction, stiffness, curvature and shift laws).  An effect is added when it lowers the error on "
        "held-out sweeps by a practical margin, in at least half of them, and passes a nested F test corrected "
        "for noise correlated along the sweeps.")
    r.figure(plot_all_waterfalls(dg), "Error waterfall per channel: RMSE on all sweeps and on held-out sweeps "
                                      "from the start model to the final one; the dashed line is each channel's "
                                      "within-sweep noise floor.")
    for ch, why in dg.channels_absent.items():
        r.p(f"{_NAMES[ch]}: not diagnosed - {why}.")
    for ch, chd in dg.channels.items():
        r.h2(f"8.{'12'[ch == 'fx']} {_NAMES[ch][0].upper()}{_NAMES[ch][1:]}")
        r.p(chd.unexplained.get("summary", ""), cls="warn" if chd.unexplained.get("structure_found") else "note")
        sizes = effect_sizes(chd)
        if sizes:
            r.bullets([f"{s['effect']} ({s['title']}): {s['size_rms']:.3g} {s['unit']} RMS, up to "
                       f"{s['size_max']:.3g} {s['unit']}; sets "
                       + ", ".join(f"{k} = {v:.4g}" for k, v in s["coefficients"].items())
                       + (f" ({s['pac89_note']})" if s["pac89_note"] else "") + f". {s['what']}" for s in sizes])
        else:
            r.p("Nothing accepted beyond the start model.")
        r.table([{"effect": c["effect"], "status": c["status"],
                  f"held-out gain [{chd.unit}]": c.get("delta_heldout", "–"),
                  "sweeps improved": c.get("sweeps_improved", "–"), "p (the smaller test)": c.get("p_value", "–"),
                  "why": c.get("reason", "")} for c in chd.candidates], digits=3)
        r.figure(plot_channel_residual_maps(chd), f"Mean residual of {_NAMES[ch]} (model - data) over slip and "
                                                  "load, start model above, final model below.")
        coef = chd.pac89.get("coefficients", {})
        cat = CHANNEL_EFFECTS[ch]
        if ch == "mz":
            final = chd.steps[-1]
            r.table([{"coefficient": k, "value": v, "meaning": TRAIL_COEFFICIENT[k].meaning if k in TRAIL_COEFFICIENT
                      else "see the effect above"} for k, v in final.values.items()], digits=5,
                    caption="The final trail model (Mz = -trail x Fy at zero camber + residual torque; lengths in m at "
                            f"the middle load {chd.data.inputs.fz_ref or float('nan'):.0f} N, the MF 6.1 coefficient "
                            "each one is in brackets)")
            r.table([{"coefficient": k, "value": v} for k, v in coef.items() if v != 0.0], digits=5,
                    caption="PAC89's aligning part fitted to the same sweeps with every coefficient the data identify "
                            f"(RMSE {chd.pac89.get('rmse', float('nan')):.3g} N*m against the trail model's "
                            f"{final.rmse:.3g} N*m): what a PAC89 .tir can keep of this record's Mz")
            continue
        r.table([{"coefficient": k, "value": v} for k, v in coef.items() if v != 0.0], digits=5,
                caption=f"PAC89 {'aligning' if ch == 'mz' else 'longitudinal'} coefficients with only what PAC89 "
                        f"holds ({', '.join(chd.pac89.get('effects', [])) or 'start model'}; RMSE "
                        f"{chd.pac89.get('rmse', float('nan')):.3g} {chd.unit})"
                        + ("; left out: " + ", ".join(f"{e} ({cat[e].pac89_note})" for e in chd.pac89["left_out"])
                           if chd.pac89.get("left_out") else ""))
