"""The contrast test: is what a camber or pressure term takes up really a difference between their levels?

Shared by the lateral diagnosis (:mod:`tyrefit.diagnose.engine`) and the Mz / Fx channels
(:mod:`tyrefit.diagnose.channels`): a veto behind the held-out evidence, so that a misfit common to
every sweep (a shape the model lacks) is not named camber or pressure.
"""

from __future__ import annotations

import numpy as np
from scipy import stats as sps

from .data import SweepData

__all__ = ["CAMBER_ALPHA", "MIN_CONTRAST_LOADS", "camber_evidence"]


#: level of the camber and pressure contrasts (:func:`_camber_evidence`): a conventional strict level, since the
#: contrast is a veto behind the held-out evidence, not the evidence itself
CAMBER_ALPHA = 1e-3


#: loads (and other conditions) with >= 2 levels the contrast needs: with two, "repeats from load to load" is one
#: comparison, too weak to veto the held-out evidence (a real camber thrust on 2 loads x 2 cambers gave p = 0.016)
MIN_CONTRAST_LOADS = 3


def _camber_evidence(d: SweepData, resid: np.ndarray, alpha: float, n_bins: int = 8,
                     factor: str = "camber") -> str | None:
    """None when the current model's residual differs between ``factor`` levels, else why the family is not named.

    A camber (or pressure) effect makes the sweeps at one camber differ from those at another at the same
    load; a misfit common to every sweep (a shape the model lacks) does not, though a camber term can absorb
    part of it wherever the cambers are one-sided (0 and +4 deg: a "shift for the cambered sweeps"), and a
    pressure term wherever the misfit happens to differ between the few sweeps of each pressure.  So at
    every load (and other condition) with >= 2 levels of ``factor`` the residual is averaged in ``n_bins``
    slip bins per level and its deviation from that load's mean over the levels (the contrast; k levels
    give k - 1 independent ones) is taken;
    an effect of ``factor`` repeats its contrast from load to load, noise does not.  One-way analysis of variance
    with the loads as replicates: F = between-bin variance of the load-mean contrast x n_loads over the
    across-load scatter (each load's sweeps are independent, so noise correlated along a sweep only
    enters the scatter), against F(n_cells, n_cells (n_loads - 1)).  With fewer than
    :data:`MIN_CONTRAST_LOADS` such loads the held-out evidence alone decides.
    """
    x = d.inputs
    edges = np.quantile(x.slip_angle, np.linspace(0, 1, n_bins + 1))
    b = np.clip(np.searchsorted(edges, x.slip_angle, side="right") - 1, 0, n_bins - 1)
    if factor not in d.level_index:
        return None
    cam = d.level_index[factor]
    others = [f for f in d.level_index if f != factor]
    key = np.column_stack([d.level_index[f] for f in others]) if others else np.zeros((d.n, 1), int)
    groups = {}
    for i, k in enumerate(map(tuple, key)):
        groups.setdefault(k, []).append(i)
    contrasts = []
    for idx in groups.values():
        idx = np.asarray(idx)
        levels = np.unique(cam[idx])
        if len(levels) < 2:
            continue
        pat = np.full((len(levels), n_bins), np.nan)
        for j, lv in enumerate(levels):
            m = idx[cam[idx] == lv]
            s = np.bincount(b[m], weights=resid[m], minlength=n_bins)
            c = np.bincount(b[m], minlength=n_bins)
            pat[j] = np.where(c > 0, s / np.maximum(c, 1), np.nan)
        # k levels give k - 1 independent contrasts (they sum to zero): the last level's is left out
        contrasts.append((pat - np.nanmean(pat, axis=0))[:-1].ravel())
    if len(contrasts) < MIN_CONTRAST_LOADS or len({len(c) for c in contrasts}) != 1:
        return None
    C = np.vstack(contrasts)  # loads x (camber levels x bins)
    ok = np.isfinite(C).all(axis=0)
    C = C[:, ok]
    L, n = C.shape
    if n < 2 or L < 2:
        return None
    between = float(np.sum(C.mean(axis=0) ** 2)) * L / n
    within = float(np.sum((C - C.mean(axis=0)) ** 2)) / (n * (L - 1))
    if within <= 0:
        return None
    p = float(sps.f.sf(between / within, n, n * (L - 1)))
    if p < alpha:
        return None
    return (f"the residual does not differ between {factor} levels consistently from load to load (analysis of "
            f"variance over {L} loads: p = {p:.2g} >= {alpha:g}): what the {factor} terms take up is common to "
            f"every {factor}, a shape the model lacks, not {factor}")



camber_evidence = _camber_evidence
