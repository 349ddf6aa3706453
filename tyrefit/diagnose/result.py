"""The :class:`Diagnosis` container: what was found, with the evidence and views."""

from __future__ import annotations

import json
import os
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import pandas as pd

from ..effects import EFFECTS, get_effect, resolve_pac89
from ..io.outputs import write_text
from .advice import advice_lines, needs_model
from .data import SweepData
from .report import write_report
from .steps import Candidate, Settings, Step
from .views import plot_even_odd, plot_residual_maps, plot_waterfall, signature_view

__all__ = ["Diagnosis"]


@dataclass
class Diagnosis:
    """Result of :func:`tyrefit.diagnose.diagnose`.

    Attributes
    ----------
    data : SweepData
        The prepared sweeps.
    start : list of str
        Effects in the start model.
    accepted : list of str
        Effects added, in order (empty when the data show nothing beyond the start model).
    steps : list of Step
        Start model, then one step per accepted effect (fit, held-out residuals).
    candidates : dict
        Effect id -> :class:`Candidate` evidence, one per catalogue effect.
    noise_floor : float
        Within-sweep noise [N].
    unexplained : dict
        Final check for structure still unexplained (``summary``, ``where``, ``p_value``).
    export : dict
        The final model refitted with only what a PAC89 ``.tir`` can hold
        (``effects``, ``rmse`` [N], ``coefficients`` a0..a13).
    peaks : list of dict
        Per load level, the final model's force peak against the sweeps' reach
        (:func:`~tyrefit.diagnose.advice.peak_reach`).
    channels : dict
        ``'mz'`` / ``'fx'`` -> :class:`~tyrefit.diagnose.channels.ChannelDiagnosis` of the other channels
        the record carries (empty when they were not diagnosed); ``channels_absent`` says why one is missing.
    """

    data: SweepData
    start: list[str]
    accepted: list[str]
    steps: list[Step]
    candidates: dict[str, Candidate]
    noise_floor: float
    noise_floor_per_sweep: np.ndarray
    settings: Settings
    seed: int
    unexplained: dict = field(default_factory=dict)
    export: dict = field(default_factory=dict)
    seconds: float = float("nan")
    advice: list = field(default_factory=list)
    screening: dict = field(default_factory=dict)
    peaks: list = field(default_factory=list)
    channels: dict = field(default_factory=dict)
    channels_absent: dict = field(default_factory=dict)

    # -- summaries -------------------------------------------------------------------
    @property
    def final(self) -> Step:
        return self.steps[-1]

    @property
    def effects(self) -> list[str]:
        """Effects of the final model."""
        return list(self.final.effects)

    def pac89(self) -> tuple[list[str], list[str]]:
        """PAC89 coefficients to vary for the final model's effects, and notes (see resolve_pac89)."""
        return resolve_pac89(self.effects)

    def tir_coefficients(self) -> dict[str, float]:
        """PAC89 a0..a13 for a ``.tir``: the final model refitted with only what PAC89 can hold."""
        return dict(self.export.get("coefficients", {}))

    def cell_table(self, step: Step | int = -1) -> pd.DataFrame:
        """RMSE and bias [N] per condition cell (load x camber x pressure x speed) for a step."""
        st = self.steps[step] if isinstance(step, int) else step
        d = self.data
        r = st.fit.resid
        df = pd.DataFrame({"cell": d.cell, "fz": d.levels["fz"][d.level_index["fz"]],
                           "camber": d.levels["camber"][d.level_index["camber"]], "r": r})
        keys = ["fz", "camber"]
        for f in ("pressure", "speed"):
            if f in d.levels:
                df[f] = d.levels[f][d.level_index[f]]
                keys.append(f)
        g = df.groupby(keys)
        out = pd.DataFrame({"points": g.size(), "rmse_N": g["r"].apply(lambda v: float(np.sqrt(np.mean(v**2)))),
                            "bias_N": g["r"].mean()}).reset_index()
        out.insert(0, "fz_kN", out.pop("fz") / 1e3)
        out.insert(1, "camber_deg", np.degrees(out.pop("camber")))
        if "pressure" in out:
            out.insert(2, "pressure_kPa", out.pop("pressure") / 1e3)
        if "speed" in out:
            out.insert(3, "speed_kmh", out.pop("speed") * 3.6)
        return out

    def to_dict(self) -> dict:
        """JSON-ready dict with the keys of the DESIGN contract (and more)."""
        vary, notes = self.pac89()
        d = self.data
        return {
            "start": list(self.start),
            "accepted": list(self.accepted),
            "noise_floor": float(self.noise_floor),
            "steps": [{"effects": s.effects, "rmse": float(s.rmse), "rmse_heldout": float(s.rmse_heldout),
                       "rmse_levelout": _num(s.rmse_levelout), "rmse_extrapolated": _num(s.rmse_extrapolated),
                       "added": s.added} for s in self.steps],
            "candidates": [self.candidates[e].to_dict() for e in EFFECTS],
            "unexplained": {k: v for k, v in self.unexplained.items() if k in ("summary", "where", "p_value",
                                                                               "structure_found", "directions",
                                                                               "misfit", "omnibus_groups",
                                                                               "verdict", "noise_model",
                                                                               "repeat_noise")},
            "pac89": {"vary": vary, "notes": notes, "effects": self.export.get("effects", []),
                      "rmse": _num(self.export.get("rmse")), "coefficients": self.tir_coefficients()},
            "parameters": {k: float(v) for k, v in self.final.fit.values.items()},
            "data": {"source": d.source, "points": d.n, "points_raw": d.n_raw, "sweeps": d.n_sweeps,
                     "conditions": {"fz": list(map(float, d.levels["fz"])),
                                    "camber_deg": [float(np.degrees(c)) for c in d.levels["camber"]],
                                    **({"pressure": list(map(float, d.levels["pressure"]))}
                                       if "pressure" in d.levels else {}),
                                    **({"speed": list(map(float, d.levels["speed"]))} if "speed" in d.levels else {})},
                     "rated_load": d.inputs.rated_load, "notes": list(d.notes),
                     # per load: the final model's force peak [deg] against the sweeps' reach [deg]
                     "peak_reach": [dict(p) for p in self.peaks]},
            "advice": [dict(a) for a in self.advice],
            **({"channels": {"fy": self.lateral_channel(), **{k: v.to_dict() for k, v in self.channels.items()}},
                "channels_not_diagnosed": dict(self.channels_absent)} if self.channels else {}),
            "screening": dict(self.screening),
            "needs_model": {e: m for e in self.accepted if (m := needs_model(e))},
            "settings": dict(self.settings.__dict__),
            "seed": self.seed,
            "seconds": float(self.seconds),
        }

    def lateral_channel(self) -> dict:
        """The lateral diagnosis in the layout of a ``channels`` entry (N)."""
        return {"unit": "N", "start": list(self.start), "accepted": list(self.accepted),
                "noise_floor": float(self.noise_floor),
                "steps": [{"effects": s.effects, "rmse": float(s.rmse), "rmse_heldout": float(s.rmse_heldout),
                           "added": s.added} for s in self.steps],
                "unexplained": {k: v for k, v in self.unexplained.items() if k in ("summary", "structure_found",
                                                                                   "verdict")}}

    def to_json(self, path: str | os.PathLike | None = None, force: bool = False) -> str:
        """The diagnosis as JSON text; also written atomically to ``path`` when given."""
        return json_text(self.to_dict(), path, force)

    def report(self, directory: str | os.PathLike, force: bool = False) -> Path:
        """Write the HTML report ``directory/index.html`` (plus CSV tables); return its path."""
        return write_report(self, directory, force=force)

    def summary(self) -> str:
        """A few lines for the terminal."""
        lines = ["start model: base PAC89" + (" + " + ", ".join(self.start) if self.start else ""),
                 f"noise floor (within-sweep): {self.noise_floor:.1f} N"]
        for s in self.steps:
            lines.append(f"  {'+ ' + s.added if s.added else 'start':<28} RMSE {s.rmse:8.1f} N   "
                         f"held-out {s.rmse_heldout:8.1f} N")
        lines.append("accepted: " + (", ".join(f"{a} ({m})" if (m := needs_model(a)) else a for a in self.accepted)
                                     if self.accepted else "nothing beyond the start model"))
        lines.append(self.unexplained.get("summary", ""))
        for ch in self.channels.values():
            lines.append(ch.summary())
        for ch, why in self.channels_absent.items():
            lines.append(f"{ch}: not diagnosed ({why})")
        if self.advice:
            lines.append("advice (what these data leave open, and the test that would decide it):")
            lines += ["  " + t for t in advice_lines(self.advice)]
        return "\n".join(lines)

    def family_of(self, effect_id: str) -> str:
        return get_effect(effect_id).family

    # -- views (see tyrefit.diagnose.views) -------------------------------------------
    def plot_waterfall(self, ax=None):
        """RMSE and held-out RMSE [N] per step against the noise floor; returns the Axes."""
        return plot_waterfall(self, ax=ax)

    def plot_residual_maps(self, fig=None):
        """Residual maps over slip and load, faceted by camber and pressure, start vs final; returns the Figure."""
        return plot_residual_maps(self, fig=fig)

    def plot_even_odd(self, ax=None):
        """Even and odd residual parts per sweep, start vs final; returns the Axes."""
        return plot_even_odd(self, ax=ax)

    def plot_signature(self, effect_id: str, ax=None):
        """Signature view of an accepted effect (data, model without and with it); returns the Axes."""
        if effect_id not in self.accepted:
            raise KeyError(f"{effect_id!r} was not accepted; accepted: {', '.join(self.accepted) or 'none'}")
        return get_effect(effect_id).plot_signature(signature_view(self, effect_id), ax=ax)


def json_text(data: dict, path: str | os.PathLike | None = None, force: bool = False) -> str:
    """``data`` as indented JSON text; also written atomically to ``path`` when given."""
    text = json.dumps(data, indent=2) + "\n"
    if path is not None:
        write_text(path, text, force=force)
    return text


def _num(x):
    return None if x is None or not np.isfinite(x) else float(x)
