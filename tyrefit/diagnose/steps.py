"""The records of a diagnosis: its decision rules (:class:`Settings`), each model on the way
(:class:`Step`) and the evidence on each effect (:class:`Candidate`); shared by
:mod:`tyrefit.diagnose.engine` and :mod:`tyrefit.diagnose.result`."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from .advice import needs_model
from .fitter import FitOut, ModelSpec

__all__ = ["Settings", "Step", "Candidate"]


@dataclass(frozen=True)
class Settings:
    """Decision rules of a diagnosis.

    alpha : family-wise level of a diagnosis: the share of data sets with
        nothing missing in which an effect may be accepted.  The screening
        with sweep flips (many sweeps) runs at ``alpha``.
    alpha_noise : level of the noise-model screening (fewer than
        :data:`~tyrefit.diagnose.stats.MIN_FLIP_SWEEPS` sweeps).  Its
        bootstrap draws from a noise model estimated from the same 5-11
        sweeps (the lag-one correlation of AR(1) noise with rho 0.8 to about
        +-0.05 from ~300 points), and the studentised bootstrap absorbs that
        uncertainty only partly: its family-wise size was measured at 1.3-1.7
        x nominal under AR(1) noise (1000 null records of one sweep at each
        of 6 loads: 1.7 % at 1 %, 6.7 % at 5 %, 12.4 % at 10 %), 0.1-0.3 x
        under independent noise.  Half of ``alpha`` keeps the diagnosis'
        false-alarm rate under ``alpha`` under either noise; the detectable
        sizes in the advice are computed at this level, so they stay honest.
        None (default): ``alpha / 2``.
    margin : practical margin, as a fraction of the noise floor, by which an
        effect must lower the held-out RMSE.
    min_boot_prob : share of sweep-bootstrap resamples in which the held-out
        improvement must stay positive (stability).
    min_folds_improved : share of sweep folds whose held-out error must fall.
    n_folds : sweep folds for cross-validation (with at most ``loso_max_sweeps``
        sweeps every sweep is its own fold).
    n_boot : bootstrap draws of the screening test.
    test : ``'auto'``, ``'flip'`` or ``'noise'``: the screening test's null
        (see :func:`~tyrefit.diagnose.stats.screen_candidates`).
    loso_max_sweeps : up to this many sweeps, hold out one sweep at a time.
    n_boot_heldout : noise-model draws of the held-out gain's null (few sweeps).
    heldout_extrapolation : count held-out sweeps beyond the training levels
        in ``rmse_heldout`` and in the evidence (default False: they are
        extrapolations, reported apart as ``rmse_extrapolated``).
    rival_share : a confirmed candidate of another family (not nested with the accepted effect) that
        alone brings at least this share of the held-out improvement (in mean square) the accepted effect
        brought is a possible rival; it is reported *ambiguous* with the accepted effect when the accepted
        effect, added on top of it, fails the confirmation guards and its family is not accepted later
        either: neither adds to the other, so these data cannot tell the two families apart (e.g. a fall
        of friction with load and a change of curvature with load when the sweeps stop before the force peak).
    batch : effect families refitted at a time, every significant variant of each (largest predicted
        gain first).
    max_steps : most effects added.
    max_points_per_sweep : longer sweeps are thinned evenly.
    """

    alpha: float = 0.05
    alpha_noise: float | None = None
    margin: float = 0.03
    min_boot_prob: float = 0.95
    min_folds_improved: float = 0.6
    n_folds: int = 5
    n_boot: int = 1999
    test: str = "auto"
    loso_max_sweeps: int = 8
    n_boot_heldout: int = 499
    heldout_extrapolation: bool = False
    rival_share: float = 0.9
    batch: int = 3
    max_steps: int = 8
    max_points_per_sweep: int = 100

    def level(self, method: str) -> float:
        """Screening level of a screen made with ``method`` (sweep flips: ``alpha``; noise model: ``alpha_noise``)."""
        if method == "sweep flips":
            return self.alpha
        return self.alpha / 2.0 if self.alpha_noise is None else self.alpha_noise


@dataclass
class Step:
    """One model on the way from the start model to the final one."""

    effects: list[str]
    added: str | None
    spec: ModelSpec
    fit: FitOut
    oof: np.ndarray
    oof_level: np.ndarray
    fold_sse: np.ndarray
    inside: np.ndarray

    @property
    def rmse(self) -> float:
        """RMSE on all points [N]."""
        return self.fit.rmse

    @property
    def rmse_heldout(self) -> float:
        """RMSE of predictions for whole held-out sweeps inside the training conditions [N].

        A sweep held out at a load (camber, pressure) level no other sweep has,
        beyond the training levels, is an extrapolation; it is left out here
        and reported as :attr:`rmse_extrapolated`.
        """
        r = self.oof[self.inside] if self.inside.any() else self.oof
        return float(np.sqrt(np.mean(r**2)))

    @property
    def rmse_heldout_all(self) -> float:
        """RMSE of predictions for every held-out sweep, the extrapolated ones included [N]."""
        return float(np.sqrt(np.mean(self.oof**2)))

    @property
    def rmse_extrapolated(self) -> float:
        """RMSE of predictions for held-out sweeps beyond the training conditions [N] (NaN if none)."""
        m = ~self.inside
        return float(np.sqrt(np.mean(self.oof[m] ** 2))) if m.any() else float("nan")

    @property
    def rmse_levelout(self) -> float:
        """RMSE of predictions for held-out interior condition levels [N] (NaN if none)."""
        m = np.isfinite(self.oof_level)
        return float(np.sqrt(np.mean(self.oof_level[m] ** 2))) if m.any() else float("nan")

    def to_dict(self) -> dict:
        return {"effects": list(self.effects), "added": self.added, "rmse": self.rmse,
                "rmse_heldout": self.rmse_heldout, "rmse_levelout": _num(self.rmse_levelout),
                "rmse_extrapolated": _num(self.rmse_extrapolated),
                "parameters": {k: float(v) for k, v in self.fit.values.items()}}


@dataclass
class Candidate:
    """The evidence on one catalogue effect."""

    effect: str
    family: str
    status: str = "not significant"
    reason: str = ""
    round: int | None = None
    statistic: float = float("nan")
    df: int = 0
    p_value: float = float("nan")
    p_adjusted: float = float("nan")
    critical: float = float("nan")
    info: dict | None = None
    predicted_dssr: float = float("nan")
    rmse_heldout: float = float("nan")
    delta_heldout: float = float("nan")
    delta_levelout: float = float("nan")
    folds_improved: float = float("nan")
    boot_prob: float = float("nan")
    p_heldout: float = float("nan")
    evidence: str = ""
    values: dict = field(default_factory=dict)

    def to_dict(self) -> dict:
        out = {"effect": self.effect, "family": self.family, "status": self.status, "reason": self.reason,
               "round": self.round, "statistic": _num(self.statistic), "df": self.df,
               "p_value": _num(self.p_value), "p_adjusted": _num(self.p_adjusted),
               "rmse_heldout": _num(self.rmse_heldout), "delta_heldout": _num(self.delta_heldout),
               "delta_levelout": _num(self.delta_levelout), "folds_improved": _num(self.folds_improved),
               "stability": _num(self.boot_prob), "p_heldout": _num(self.p_heldout),
               "heldout_evidence": self.evidence or None,
               "needs_model": needs_model(self.effect)}
        if self.values:
            out["parameters"] = {k: float(v) for k, v in self.values.items()}
        return out


def _num(x):
    return None if x is None or not np.isfinite(x) else float(x)
