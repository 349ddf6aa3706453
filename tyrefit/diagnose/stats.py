"""Statistics that respect the sweep structure of tyre data.

Residuals along a slip sweep are correlated (rig drift, temperature, per-sweep
offsets), so tests that treat points as independent find "effects" in pure
noise.  Everything here treats the *sweep* as the independent unit:

* :func:`score_test` - a score (Lagrange-multiplier) test of an effect's
  parameters at their neutral values, with the score summed per sweep and its
  null distribution from a wild cluster (Rademacher, per sweep) bootstrap of
  the score (Kline & Santos 2012, "A score based approach to wild bootstrap
  inference").  It needs only the fit of the model without the effect, so
  every catalogue effect can be screened for the cost of one Jacobian.
* :func:`score_test_groups` - the same for several groups of directions at
  once (min-p over the groups, calibrated by the same sweep flips), used by the
  final check for unexplained structure.
* :func:`crossval_surface` - how much of a residual a smooth surface over slip
  and conditions, fitted to other sweeps, predicts on held-out sweeps
  (systematic misfit against noise correlated within a sweep).
* :func:`screen_candidates` - every candidate of a round screened at once,
  min-p adjusted over the same draws; its null from sweep flips (>=
  :data:`MIN_FLIP_SWEEPS` sweeps) or from a parametric bootstrap of an AR(1) +
  sweep-offset noise model (:func:`estimate_noise`, :func:`simulate_noise`)
  estimated from the residuals, bias-corrected and re-estimated per draw
  (few sweeps: a one-sweep-per-load rig programme has 5-7);
* :func:`heldout_gain_null` - the held-out gain a candidate that is not there
  gets from noise alone (the second gate with few sweeps);
* :func:`detectable_size` - the smallest effect the score test detects with a
  given power (experiment-design advice);
* :func:`holm` - Holm's step-down correction (kept for callers; the engine uses min-p).
* :func:`noise_floor` - the within-sweep noise: RMSE a separate smooth curve
  through every sweep leaves.
* :func:`sweep_folds`, :func:`level_folds` - hold-out folds of whole sweeps and
  whole load / camber / pressure levels.
* :func:`cluster_bootstrap_prob` - how often a per-sweep improvement survives
  resampling the sweeps.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.special import bdtr, bdtrc

from ..fitting.noise import _bspline_basis, noise_floor  # noqa: F401  (diagnose's within-sweep floor)

__all__ = ["ScoreTest", "score_test", "GroupScoreTest", "score_test_groups", "residualise", "holm", "noise_floor",
           "SweepLayout", "NoiseModel", "estimate_noise", "simulate_noise", "repeat_noise", "Screen", "screen_candidates",
           "heldout_gain_null", "HeldoutNull", "detectable_size", "draw_blocks", "decided", "corrected_noise",
           "projection_basis", "MIN_FLIP_SWEEPS",
           "sweep_folds", "level_folds", "cluster_bootstrap_prob", "cluster_sums", "crossval_surface"]

_DEG = np.pi / 180.0


def residualise(X: np.ndarray, J: np.ndarray) -> np.ndarray:
    """X minus its least-squares projection on the columns of J.

    Uses the small normal equations (column-scaled, pseudo-inverse) rather
    than a QR of the tall matrix: far faster on a busy multi-threaded BLAS.
    """
    return _residualiser(J)(X)


def _residualiser(J: np.ndarray):
    """:func:`residualise` against one J for any number of X: the scaled J and its pseudo-inverse made once."""
    norms = np.linalg.norm(J, axis=0)
    Js = J / np.where(norms > 0, norms, 1.0)
    A = Js.T @ Js
    Ap = np.linalg.pinv(A, rcond=1e-12, hermitian=True)

    def off(X: np.ndarray) -> np.ndarray:
        return X - Js @ (Ap @ (Js.T @ X))

    return off


def cluster_sums(values: np.ndarray, cluster: np.ndarray, n_clusters: int) -> np.ndarray:
    """Sum rows of ``values`` (N, q) within each cluster -> (G, q)."""
    values = np.asarray(values, dtype=float)
    if values.ndim == 1:
        values = values[:, None]
    out = np.zeros((n_clusters, values.shape[1]))
    np.add.at(out, cluster, values)
    return out


@dataclass
class ScoreTest:
    """Result of a cluster-robust score test.

    ``statistic`` = s' V^-1 s with s the score and V the sum of per-sweep
    score outer products; ``p_value`` from the wild cluster score bootstrap;
    ``df`` the number of parameters tested; ``predicted_dssr`` the reduction
    of the residual sum of squares [N^2] a refit would give to first order
    (used to rank candidates); ``n_clusters`` sweeps.
    """

    statistic: float
    p_value: float
    df: int
    predicted_dssr: float
    n_clusters: int


def score_test(J_model: np.ndarray, J_new: np.ndarray, resid: np.ndarray, cluster: np.ndarray,
               n_clusters: int, rng: np.random.Generator, n_boot: int = 1999) -> ScoreTest:
    """Score test of new parameters (columns ``J_new``) at their neutral values.

    Parameters
    ----------
    J_model : ndarray (N, P)
        Jacobian of the fitted model with respect to its own parameters.
    J_new : ndarray (N, q)
        Jacobian with respect to the tested parameters, at their neutral values.
    resid : ndarray (N,)
        Residuals (data - model or model - data; the statistic is even) [N].
    cluster : ndarray of int (N,)
        Sweep of each point.
    n_clusters : int
    rng : numpy Generator
    n_boot : int
        Bootstrap draws; the smallest attainable p-value is 1/(n_boot+1).

    Notes
    -----
    The tested directions are first made orthogonal to the model's own
    (J_new - Q Q' J_new with Q an orthonormal basis of J_model), so the
    score does not depend on the fitted parameters to first order.  With
    per-sweep scores S_g = J~_g' r_g, s = sum_g S_g, V = sum_g S_g S_g' and
    T = s' V^+ s.  Under the null the S_g are independent with mean zero,
    so flipping their signs at random (w_g = +/-1, which leaves V unchanged)
    gives the null distribution of T: p = (1 + #{T* >= T}) / (n_boot + 1).
    """
    Jt = residualise(J_new, J_model)
    r = np.asarray(resid, dtype=float)
    S = cluster_sums(Jt * r[:, None], cluster, n_clusters)
    s = S.sum(axis=0)
    V = S.T @ S
    Vp = np.linalg.pinv(V, rcond=1e-10, hermitian=True)
    T = float(s @ Vp @ s)
    W = rng.choice(np.array([-1.0, 1.0]), size=(n_boot, n_clusters))
    Sb = W @ S
    Tb = np.einsum("bi,ij,bj->b", Sb, Vp, Sb)
    p = (1.0 + np.count_nonzero(Tb >= T * (1 - 1e-9))) / (n_boot + 1.0)
    info = Jt.T @ Jt
    dssr = float(s @ np.linalg.pinv(info, rcond=1e-12, hermitian=True) @ s)
    return ScoreTest(statistic=T, p_value=float(p), df=int(J_new.shape[1]), predicted_dssr=dssr,
                     n_clusters=int(n_clusters))



@dataclass
class GroupScoreTest:
    """Result of :func:`score_test_groups`.

    ``p_value`` of the min-p combination over the groups; ``p_groups`` the
    bootstrap p-value of each group alone; ``statistics`` and ``dfs`` per group.
    """

    p_value: float
    p_groups: list[float]
    statistics: list[float]
    dfs: list[int]


def score_test_groups(J_model: np.ndarray, groups: list[np.ndarray], resid: np.ndarray, cluster: np.ndarray,
                      n_clusters: int, rng: np.random.Generator, n_boot: int = 1999) -> GroupScoreTest:
    """Cluster score tests of several groups of directions, combined by min-p.

    Each group is tested as in :func:`score_test`; every bootstrap draw flips
    the same sweeps for all groups, so the smallest group p-value has its
    null distribution from the same draws (Westfall-Young min-p): the
    combined test holds its level however many groups there are and however
    they overlap, while each group keeps few enough directions for the
    number of sweeps.

    Parameters
    ----------
    J_model : ndarray (N, P)
    groups : list of ndarray (N, q_k)
        Directions of each group (residual structure to look for).
    resid, cluster, n_clusters, rng, n_boot
        As in :func:`score_test`.
    """
    r = np.asarray(resid, dtype=float)
    W = rng.choice(np.array([-1.0, 1.0]), size=(n_boot, n_clusters))
    T, Tb, dfs = [], [], []
    off = _residualiser(J_model)
    for X in groups:
        Jt = off(X)
        S = cluster_sums(Jt * r[:, None], cluster, n_clusters)
        Vp = np.linalg.pinv(S.T @ S, rcond=1e-10, hermitian=True)
        s = S.sum(axis=0)
        T.append(float(s @ Vp @ s))
        Sb = W @ S
        Tb.append(np.einsum("bi,ij,bj->b", Sb, Vp, Sb))
        dfs.append(int(X.shape[1]))
    Tb = np.array(Tb)  # (K, n_boot)
    T = np.array(T)
    p_obs = (1.0 + np.sum(Tb >= T[:, None] * (1 - 1e-9), axis=1)) / (n_boot + 1.0)
    # p-value of every bootstrap draw within its group (rank among the draws), then min over groups
    ranks = np.argsort(np.argsort(-Tb, axis=1, kind="stable"), axis=1)
    p_boot = (1.0 + ranks) / (n_boot + 1.0)
    min_boot = p_boot.min(axis=0)
    p = (1.0 + np.count_nonzero(min_boot <= p_obs.min() * (1 + 1e-9))) / (n_boot + 1.0)
    return GroupScoreTest(p_value=float(p), p_groups=[float(v) for v in p_obs], statistics=[float(v) for v in T],
                          dfs=dfs)


def crossval_surface(B: np.ndarray, resid: np.ndarray, folds: list[np.ndarray], sweep: np.ndarray,
                     ridge=(1e-3, 1e-1, 1.0)) -> dict:
    """How much of a residual other sweeps predict: a smooth surface fitted on training sweeps.

    Parameters
    ----------
    B : ndarray (N, k)
        Basis of the surface (smooth in slip angle, polynomial in the conditions).
    resid : ndarray (N,)
        Residual of the final model [N].
    folds : list of ndarray
        Test sweeps of each fold (whole sweeps held out).
    sweep : ndarray of int (N,)
        Sweep of each point.
    ridge : sequence of float
        Ridge penalties, relative to the mean diagonal of B'B; the one with the
        lowest held-out error is used.

    Returns
    -------
    dict
        ``mse`` [N^2] of the residual, ``mse_cv`` [N^2] of the residual minus
        the held-out predictions, ``share`` = 1 - mse_cv/mse (the part of the
        residual variance other sweeps predict; negative when the surface only
        fits noise), ``predictable_rmse`` = sqrt(max(0, mse - mse_cv)) [N],
        ``ridge`` (the penalty used), ``coef`` (the surface fitted to all
        sweeps with it) and ``fitted`` (its values at the points) [N].

    Notes
    -----
    Noise correlated along a sweep (rig drift, per-sweep offsets, AR noise)
    is as large on held-out sweeps as it is unpredictable from the others, so
    the share is about zero or negative; a misfit of the model that is a
    smooth function of slip and conditions carries over to held-out sweeps
    and gives a clearly positive share.
    """
    r = np.asarray(resid, dtype=float)
    G = int(np.max(sweep)) + 1
    fold_of = np.empty(G, dtype=int)
    for k, f in enumerate(folds):
        fold_of[f] = k
    pf = fold_of[sweep]
    k = B.shape[1]
    # each fold's Gram matrix and moment, made once for every ridge value
    grams = []
    for f in range(len(folds)):
        tr = pf != f
        grams.append((tr, B[tr].T @ B[tr], B[tr].T @ r[tr]))
    best = None
    for lam in ridge:
        pred = np.empty(len(r))
        for tr, A, b in grams:
            pen = lam * max(np.trace(A) / k, 1e-300)
            pred[~tr] = B[~tr] @ np.linalg.solve(A + pen * np.eye(k), b)
        mse_cv = float(np.mean((r - pred) ** 2))
        if best is None or mse_cv < best[1]:
            best = (lam, mse_cv)
    lam, mse_cv = best
    A = B.T @ B
    coef = np.linalg.solve(A + lam * max(np.trace(A) / k, 1e-300) * np.eye(k), B.T @ r)
    mse = float(np.mean(r**2))
    return {"mse": mse, "mse_cv": mse_cv, "share": 1.0 - mse_cv / mse if mse > 0 else 0.0,
            "predictable_rmse": float(np.sqrt(max(0.0, mse - mse_cv))), "ridge": lam, "coef": coef,
            "fitted": B @ coef}

def holm(p_values) -> np.ndarray:
    """Holm step-down adjusted p-values (family-wise error control)."""
    p = np.asarray(p_values, dtype=float)
    m = len(p)
    if m == 0:
        return p
    order = np.argsort(p)
    adj = np.empty(m)
    running = 0.0
    for rank, i in enumerate(order):
        running = max(running, min(1.0, (m - rank) * p[i]))
        adj[i] = running
    return adj


def repeat_noise(slip_angle, resid, sweep, cell) -> dict | None:
    """The record's noise measured between repeated sweeps: the model's error cancels, the noise does not.

    Two sweeps of one condition cell (same load, camber, pressure, speed) share every systematic error of
    the model, so the difference of their residuals at the same slip angle is noise alone, whatever its
    structure (AR along the sweep, an offset per sweep, drift): for each point of a sweep the residual of
    the next repeat at the nearest slip angle on the same side is subtracted (no interpolation, which
    would average the noise), and sd = sqrt(mean(diff^2) / 2) is the point-wise noise standard deviation
    a model with nothing missing leaves on held-out sweeps.

    Returns ``{"sd_N", "pairs", "cells", "points"}``, or None when no cell has two sweeps whose slip
    ranges overlap.
    """
    a = np.asarray(slip_angle, float)
    r = np.asarray(resid, float)
    sw = np.asarray(sweep)
    cl = np.asarray(cell)
    diffs, pairs, cells = [], 0, set()
    for c in np.unique(cl):
        groups = [g for g in np.unique(sw[cl == c]) if np.count_nonzero(sw == g) >= 10]
        for g, h in zip(groups[:-1], groups[1:]):
            mg, mh = sw == g, sw == h
            ag, ah, rg, rh = a[mg], a[mh], r[mg], r[mh]
            spacing = np.median(np.diff(np.sort(ah))) if ah.size > 1 else 0.0
            got = False
            for side in (1.0, -1.0):
                og, oh = np.sign(ag) == side, np.sign(ah) == side
                if og.sum() < 5 or oh.sum() < 5:
                    continue
                xs, order = ah[oh], np.argsort(ah[oh])
                xs, ys = xs[order], rh[oh][order]
                j = np.clip(np.searchsorted(xs, ag[og]), 1, len(xs) - 1)
                near = np.where(np.abs(xs[j - 1] - ag[og]) <= np.abs(xs[j] - ag[og]), j - 1, j)
                ok = np.abs(xs[near] - ag[og]) <= max(2.0 * spacing, 1e-12)
                if ok.sum() >= 5:
                    diffs.append(rg[og][ok] - ys[near][ok])
                    got = True
            if got:
                pairs += 1
                cells.add(int(c))
    if not diffs:
        return None
    dd = np.concatenate(diffs)
    return {"sd_N": float(np.sqrt(np.mean(dd * dd) / 2.0)), "pairs": pairs, "cells": len(cells),
            "points": int(dd.size)}


def sweep_folds(sweep_cells: np.ndarray, k: int, rng: np.random.Generator) -> list[np.ndarray]:
    """Assign whole sweeps to ``k`` folds, spreading each condition cell over the folds.

    Returns the list of test-sweep index arrays.
    """
    G = len(sweep_cells)
    k = int(min(k, G))
    perm = rng.permutation(G)
    order = perm[np.argsort(sweep_cells[perm], kind="stable")]
    fold = np.empty(G, dtype=int)
    start = int(rng.integers(k))
    fold[order] = (np.arange(G) + start) % k
    return [np.flatnonzero(fold == f) for f in range(k)]


def level_folds(sweep_levels: dict[str, np.ndarray], levels: dict[str, np.ndarray],
                max_per_factor: int = 2) -> list[tuple[str, np.ndarray]]:
    """Leave-one-level-out folds for the *interior* levels of factors with >= 3 levels.

    Interior levels only, so the held-out level is interpolated, never
    extrapolated; at most ``max_per_factor`` levels (the most central) per factor.

    Returns (label, test-sweep indices) pairs.
    """
    out = []
    for f, lv in levels.items():
        n = len(lv)
        if n < 3:
            continue
        interior = list(range(1, n - 1))
        interior.sort(key=lambda i: abs(i - (n - 1) / 2))
        for i in interior[:max_per_factor]:
            test = np.flatnonzero(sweep_levels[f] == i)
            if 0 < len(test) < len(sweep_levels[f]):
                out.append((f"{f} level {i}", test))
    return out


def cluster_bootstrap_prob(d: np.ndarray, rng: np.random.Generator, n_boot: int = 999) -> float:
    """Share of sweep-bootstrap resamples in which sum(d) > 0 (d: per-sweep improvement)."""
    d = np.asarray(d, dtype=float)
    if len(d) == 0:
        return float("nan")
    idx = rng.integers(0, len(d), size=(n_boot, len(d)))
    return float(np.mean(d[idx].sum(axis=1) > 0))


# --------------------------------------------------------------------------------------------------------
# Screening all candidates at once: the sweep-flip (many sweeps) or the noise-model bootstrap (few sweeps)
# --------------------------------------------------------------------------------------------------------
#: with this many sweeps or more the screening uses sweep flips (no noise model): 2^11 sign patterns leave
#: ample resolution for a min-p over a dozen candidates at 5 %, and the per-sweep score variance is estimated
#: from >= 12 sweeps; with fewer, the AR(1) + sweep-offset noise-model bootstrap
MIN_FLIP_SWEEPS = 12


class SweepLayout:
    """Points of each sweep in record order, padded: the frame AR noise lives in.

    ``index[g, i]`` is the point at position ``i`` of sweep ``g`` (-1 past its end).
    """

    def __init__(self, sweep: np.ndarray, n_sweeps: int):
        sweep = np.asarray(sweep)
        self.G = int(n_sweeps)
        self.N = len(sweep)
        self.sweep = sweep
        self.n = np.bincount(sweep, minlength=self.G)
        self.n_max = int(self.n.max())
        order = np.argsort(sweep, kind="stable")
        pos = np.arange(self.N) - np.repeat(np.r_[0, np.cumsum(self.n)[:-1]], self.n)
        self.index = np.full((self.G, self.n_max), -1, dtype=int)
        self.index[sweep[order], pos] = order
        self.mask = self.index >= 0
        # f_g = (1/n) sum_ij rho^|i-j| needs these lag counts: (n - h) pairs at lag h
        self.lag_counts = np.clip(self.n[:, None] - np.arange(self.n_max)[None, :], 0, None).astype(float)
        self._slot = np.empty(self.N, dtype=int)  # each point's place in the flattened (G, n_max) frame
        self._slot[self.index[self.mask]] = np.flatnonzero(self.mask.ravel())
        self._take = np.where(self.mask, self.index, 0).ravel()
        #: every sweep has n_max points and the points are stored sweep by sweep in order: the frame is a reshape
        self.full = bool(self.mask.all())
        self.whole = self.full and bool(np.array_equal(self._slot, np.arange(self.N)))

    def padded(self, x: np.ndarray) -> np.ndarray:
        """(..., N) -> (..., G, n_max), zero past the end of each sweep (a view of ``x`` when :attr:`whole`)."""
        shape = x.shape[:-1] + (self.G, self.n_max)
        if self.whole:
            return x.reshape(shape)
        out = np.take(x, self._take, axis=-1).reshape(shape)
        return out if self.full else np.where(self.mask, out, 0.0)

    def unpad(self, xp: np.ndarray) -> np.ndarray:
        """(..., G, n_max) -> (..., N) (a view of ``xp`` when :attr:`whole`)."""
        flat = xp.reshape(xp.shape[:-2] + (-1,))
        return flat if self.whole else np.take(flat, self._slot, axis=-1)


@dataclass
class NoiseModel:
    """Noise of a rig record: AR(1) along each sweep plus a random offset per sweep.

    ``sd`` [N] stationary standard deviation of the AR(1) part of each sweep
    (G,), ``rho`` its lag-one correlation between neighbouring points, ``tau``
    [N] the standard deviation of the per-sweep offsets (drift between sweeps).
    Arrays carry a leading axis when several models are estimated at once.
    """

    sd: np.ndarray
    rho: np.ndarray
    tau: np.ndarray

    def to_dict(self) -> dict:
        return {"sd_N": float(np.sqrt(np.mean(np.asarray(self.sd) ** 2))), "rho": float(np.asarray(self.rho).ravel()[0]),
                "tau_N": float(np.asarray(self.tau).ravel()[0])}


def _ar_f(layout: SweepLayout, rho: np.ndarray) -> np.ndarray:
    """f_g(rho) = (1/n_g) sum_ij rho^|i-j| (variance of a sweep sum / n_g sigma^2) -> (B, G)."""
    rho = np.atleast_1d(np.asarray(rho, dtype=float))[:, None]
    n = layout.n[None, :].astype(float)
    if np.all(np.abs(1.0 - rho) > 1e-2):
        # sum_(h=1)^(n-1) (n - h) rho^h = rho (n (1 - rho) - (1 - rho^n)) / (1 - rho)^2, without the (B, H) powers
        lagged = rho * (n * (1.0 - rho) - (1.0 - rho**n)) / (1.0 - rho) ** 2
        return 1.0 + 2.0 * lagged / n
    h = np.arange(layout.n_max)[None, :]
    powh = np.where(h == 0, 1.0, rho ** np.maximum(h, 1))  # (B, H)
    w = np.where(h == 0, 1.0, 2.0) * powh
    return (w @ layout.lag_counts.T) / layout.n[None, :]


def estimate_noise(resid: np.ndarray, layout: SweepLayout, dof_within: float = 0.0,
                   dof_between: float = 0.0) -> NoiseModel:
    """Estimate the AR(1) + sweep-offset noise from residuals (rows of ``resid`` estimated separately).

    Parameters
    ----------
    resid : ndarray (N,) or (B, N)
        Residuals [N] of a model that explains the systematic part (here: the
        model with every candidate effect added, so a missing effect does not
        pass for correlated noise).
    layout : SweepLayout
    dof_within, dof_between : float
        Parameters of that model spent within sweeps and on sweep means
        (degrees-of-freedom corrections of the variances).

    Notes
    -----
    Method of moments, per row: the lag-one autocorrelation of the
    within-sweep deviations, corrected for the demeaning bias (1 + 3 rho)/n
    (Marriott & Pope 1954), gives rho; the within-sweep sum of squares of
    sweep g has expectation sd_g^2 (n_g - f_g) with f_g = (1/n_g) sum_ij
    rho^|i-j|, which gives sd_g; the mean square of the sweep means has
    expectation tau^2 + sd_g^2 f_g / n_g, which gives tau (>= 0).
    """
    r = np.atleast_2d(resid)
    rp = layout.padded(r)  # (B, G, H)
    n = layout.n.astype(float)
    m = rp.sum(axis=-1) / n  # sweep means (B, G)
    d = rp - m[..., None]
    if not layout.full:
        d = np.where(layout.mask, d, 0.0)  # zero past the end of a sweep: no lag product reaches there
    # sums along each sweep without (B, G, H) temporaries
    ss = np.einsum("...h,...h->...", d, d)  # (B, G)
    lag1 = np.einsum("...h,...h->...", d[..., 1:], d[..., :-1])
    rho = np.sum(lag1, axis=-1) / np.maximum(np.sum(ss, axis=-1), 1e-300)
    rho = np.clip(rho + (1.0 + 3.0 * rho) / max(np.mean(n), 2.0), -0.5, 0.97)
    f = _ar_f(layout, rho)  # (B, G)
    N, G = layout.N, layout.G
    cw = (N - G) / max(N - G - dof_within, 1.0)
    sd2 = cw * ss / np.maximum(n[None, :] - f, 1.0)
    cb = G / max(G - dof_between, 1.0)
    tau2 = np.maximum(0.0, cb * np.mean(m * m, axis=-1) - np.mean(sd2 * f / n[None, :], axis=-1))
    return NoiseModel(sd=np.sqrt(sd2), rho=rho, tau=np.sqrt(tau2))


def simulate_noise(model: NoiseModel, layout: SweepLayout, n_draws: int, rng: np.random.Generator) -> np.ndarray:
    """Draws (n_draws, N) of AR(1) + sweep-offset noise from one estimated model."""
    sd = np.asarray(model.sd, dtype=float).reshape(-1)[-layout.G:]
    rho = float(np.asarray(model.rho).ravel()[0])
    tau = float(np.asarray(model.tau).ravel()[0])
    # the AR(1) recursion e_i = rho e_(i-1) + c z_i runs in place on the draws (no (B, G, H) temporaries:
    # at a thousand draws their allocation cost more than the arithmetic)
    e = rng.standard_normal((n_draws, layout.G, layout.n_max))
    c = np.sqrt(max(1.0 - rho * rho, 0.0))
    for i in range(1, layout.n_max):
        zi = e[..., i]
        zi *= c
        zi += rho * e[..., i - 1]
    e *= sd[None, :, None]
    e += tau * rng.standard_normal((n_draws, layout.G))[..., None]
    return layout.unpad(e)


@dataclass
class Screen:
    """Joint screening of every candidate effect in one round.

    ``statistic``, ``p_value`` (each candidate alone), ``p_adjusted``
    (family-wise: single-step min-p over all candidates, the same draws for
    every candidate), ``predicted_dssr`` [N^2] (first-order gain of a refit),
    ``critical`` (statistic each candidate must reach to pass at ``alpha``
    after the adjustment), ``method`` ("sweep flips" or "noise-model
    bootstrap"), ``noise`` (the estimated NoiseModel, noise-model bootstrap
    only), ``info`` (per candidate: Fisher information and score variance of
    its parameters, for the smallest detectable effect), ``draws`` (bootstrap
    draws the p-values rest on).
    """

    statistic: np.ndarray
    p_value: np.ndarray
    p_adjusted: np.ndarray
    predicted_dssr: np.ndarray
    df: np.ndarray
    critical: np.ndarray
    method: str
    n_clusters: int
    noise: NoiseModel | None = None
    info: list = None
    draws: int = 0


def _minp_adjust(T: np.ndarray, Tb: np.ndarray, alpha: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Per-candidate and min-p adjusted p-values from observed T (K,) and draws Tb (K, B); critical T at alpha."""
    p_obs, p_adj, min_boot = _minp(T, Tb)
    return p_obs, p_adj, _critical(Tb, min_boot, alpha)


def _minp(T: np.ndarray, Tb: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """:func:`_minp_adjust` without the critical values: p-values, adjusted p-values, sorted min-p of the draws."""
    K, B = Tb.shape
    p_obs = (1.0 + np.sum(Tb >= T[:, None] * (1 - 1e-9), axis=1)) / (B + 1.0)
    # each draw's rank within its candidate (0 = largest; ties in draw order): the inverse of the stable sort
    order = np.argsort(-Tb, axis=1, kind="stable")
    ranks = np.empty((K, B), dtype=np.intp)
    ranks[np.arange(K)[:, None], order] = np.arange(B)
    p_boot = (1.0 + ranks) / (B + 1.0)
    min_boot = np.sort(p_boot.min(axis=0))
    p_adj = (1.0 + np.searchsorted(min_boot, p_obs * (1 + 1e-9), side="right")) / (B + 1.0)
    return p_obs, np.maximum(p_adj, p_obs), min_boot


def _critical(Tb: np.ndarray, min_boot: np.ndarray, alpha: float) -> np.ndarray:
    """Critical T per candidate: its draws' quantile at the largest p whose adjusted p is below alpha."""
    K, B = Tb.shape
    c = min_boot[max(int(np.floor(alpha * (B + 1))) - 2, 0)] if B else 0.0
    return np.quantile(Tb, 1.0 - c, axis=1) if c > 0 else np.full(K, np.inf)


#: cumulative draws after which a noise-model screening may stop (then ``n_boot``)
DRAW_STEPS = (499, 999)
#: a screening stops early when, for every candidate, a binomial count of exceedances as far from alpha as the
#: one drawn has at most this probability if the candidate's exact p-value were alpha
DECIDED_RISK = 1e-4


def draw_blocks(n_boot: int) -> list[int]:
    """Sizes of the blocks of bootstrap draws: up to :data:`DRAW_STEPS` draws in all, then up to ``n_boot``."""
    ends = [t for t in DRAW_STEPS if t < n_boot] + [n_boot]
    return [b - a for a, b in zip([0] + ends[:-1], ends) if b > a]


def decided(T: np.ndarray, Tb: np.ndarray, alpha: float, risk: float = DECIDED_RISK) -> bool:
    """Whether every candidate's min-p adjusted p-value is settled against ``alpha`` by the ``B`` draws so far.

    The adjusted p-value (1 + c) / (B + 1) counts c draws whose smallest p-value is at most the candidate's;
    c is binomial (B, p) with p the exact adjusted p-value.  A candidate is settled when c is incompatible
    with p = alpha: P(C <= c) < ``risk`` (clearly below alpha) or P(C >= c) < ``risk`` (clearly above).
    """
    return _settled(_minp(T, Tb)[1], Tb.shape[1], alpha, risk)


def _settled(padj: np.ndarray, B: int, alpha: float, risk: float = DECIDED_RISK) -> bool:
    """:func:`decided` from the adjusted p-values ``padj`` of ``B`` draws."""
    c = np.rint(padj * (B + 1.0) - 1.0)
    below = bdtr(c, B, alpha) < risk
    above = (c >= 1) & (bdtrc(np.maximum(c - 1.0, 0.0), B, alpha) < risk)
    return bool(np.all(below | above))


def _pinv_quadratic(s: np.ndarray, V: np.ndarray, rcond: float) -> np.ndarray:
    """s_b' pinv(V_b) s_b for a stack of symmetric V (B, q, q) and s (B, q), as ``np.linalg.pinv(V, rcond,
    hermitian=True)`` would give it: eigenvalues at or below rcond x the largest |eigenvalue| count as 0."""
    if V.shape[-1] == 1:
        v = V[:, 0, 0]
        return np.divide(s[:, 0] ** 2, v, out=np.zeros_like(v), where=v != 0)
    w, U = np.linalg.eigh(V)
    cut = rcond * np.max(np.abs(w), axis=1, keepdims=True)
    inv = np.divide(1.0, w, out=np.zeros_like(w), where=np.abs(w) > cut)
    proj = (U.transpose(0, 2, 1) @ s[:, :, None])[:, :, 0]  # U' s
    return np.sum(inv * proj * proj, axis=1)


def _pinv_each(mats: list, rcond: float) -> list:
    """``np.linalg.pinv(m, rcond, hermitian=True)`` of every symmetric matrix in ``mats``, one call per size."""
    out = [None] * len(mats)
    for size in {m.shape[0] for m in mats}:
        idx = [i for i, m in enumerate(mats) if m.shape[0] == size]
        stacked = np.linalg.pinv(np.stack([mats[i] for i in idx]), rcond=rcond, hermitian=True)
        for i, m in zip(idx, stacked):
            out[i] = m
    return out


def projection_basis(A: np.ndarray, layout) -> tuple[np.ndarray, float, float]:
    """Orthonormal basis Q of the columns of ``A`` and the degrees of freedom they take within and between sweeps.

    The between-sweep part is Q's content in the sweep-mean space (what a model's directions spend of the
    sweep offsets), the within-sweep part the rest of its rank.
    """
    U, sv, _ = np.linalg.svd(A / np.maximum(np.linalg.norm(A, axis=0), 1e-300), full_matrices=False)
    Q = U[:, sv > 1e-8 * sv[0]]
    dof_b = float(np.sum((cluster_sums(Q, layout.sweep, layout.G) / np.sqrt(layout.n)[:, None]) ** 2))
    return Q, Q.shape[1] - dof_b, dof_b


def corrected_noise(resid: np.ndarray, Q: np.ndarray, dof_within: float, dof_between: float, layout: SweepLayout,
                    rng: np.random.Generator, n_pilot: int = 199) -> tuple[NoiseModel, NoiseModel]:
    """The noise model of ``resid`` projected off the orthonormal directions ``Q``, and its bias-corrected version.

    :func:`estimate_noise` of the projected residuals (``dof_within``, ``dof_between``: what the directions
    spend, :func:`projection_basis`), then a bootstrap bias correction (Efron & Tibshirani 1993, Sec. 10.3):
    the projection on a model's smooth directions removes slow noise, so rho, sd and tau come out low;
    ``n_pilot`` draws from the estimate, re-estimated the same way, show the bias each parameter is moved by.
    Returns (estimate, corrected).
    """
    def proj(x):
        return x - (x @ Q) @ Q.T

    obs = estimate_noise(proj(resid), layout, dof_within, dof_between)
    pilot = estimate_noise(proj(simulate_noise(obs, layout, n_pilot, rng)), layout, dof_within, dof_between)
    corrected = NoiseModel(
        sd=np.asarray(obs.sd) * np.asarray(obs.sd) / np.maximum(np.mean(pilot.sd, axis=0), 1e-300),
        rho=np.clip(2.0 * np.asarray(obs.rho) - np.mean(pilot.rho), -0.5, 0.97),
        tau=np.maximum(0.0, 2.0 * np.asarray(obs.tau) - np.mean(pilot.tau)))
    return obs, corrected


def screen_candidates(J_model: np.ndarray, J_new: list[np.ndarray], resid: np.ndarray, layout: SweepLayout,
                      rng: np.random.Generator, n_boot: int = 999, alpha: float = 0.05,
                      method: str = "auto", min_flip_sweeps: int | None = None,
                      in_alternative: list[bool] | None = None) -> Screen:
    """Score tests of every candidate's parameters at their neutral values, adjusted for testing them all.

    Parameters
    ----------
    J_model : ndarray (N, P)
        Jacobian of the fitted model.
    J_new : list of ndarray (N, q_k)
        Jacobian of each candidate's new parameters at their neutral values.
    resid : ndarray (N,)
        Residuals of the fitted model [N].
    layout : SweepLayout
    rng : Generator
    n_boot : int
        Bootstrap draws (the noise model: at most; see Notes).
    alpha : float
        Family-wise level: the critical values, and when the noise-model draws may stop.
    method : {'auto', 'flip', 'noise'}
        ``'flip'``: wild cluster score bootstrap, Rademacher signs per sweep
        (Kline & Santos 2012) - free of any noise model, but its null has only
        2^G distinct draws and a sweep-robust variance, so it needs many sweeps;
        ``'noise'``: parametric bootstrap from an AR(1) + sweep-offset noise
        model estimated from the residuals of the model with every candidate
        added, re-estimated in every draw; ``'auto'``: flips with
        ``min_flip_sweeps`` sweeps or more, else the noise model.
    in_alternative : list of bool, optional
        Which candidates' directions join the model whose residuals the noise
        model is estimated from (default: all).  The diagnosis leaves out its
        refinements (higher-order load laws): with 5-7 sweeps every further
        load-law direction spends one of the few between-sweep degrees of
        freedom that carry the sweep-offset part of the noise, and with the
        cubic friction and bent curvature directions in, the offset noise of
        one-sided 6-sweep nulls came out low (false alarms in 7.5 % of 200
        records with them, 4.0 % without).

    Notes
    -----
    Every candidate's directions are made orthogonal to the model's
    (J~ = J_new - P J_new), its score is s = J~' r and its statistic
    T = s' V^-1 s with V the variance of s: the sum of per-sweep score outer
    products (flips) or J~' Sigma J~ with Sigma the estimated noise
    covariance (noise model).  In each draw the same noise (or the same
    flips) feeds every candidate, so the smallest per-candidate p-value has
    its null distribution from the same draws: single-step min-p
    (Westfall & Young 1993), which holds the family-wise level however
    strongly the candidates' directions overlap, and loses far less power
    than Holm when they do (load_friction, overload and curvature_load all
    act on the peak).

    The noise model of 5-7 sweeps is itself uncertain (its correlation from
    ~300 points of AR(1) noise with rho 0.8 has a standard error of about
    0.05), and the studentised bootstrap only partly absorbs that: drawing
    from the estimate, a nominal 5 % test rejected 6.7 % of 1000 null data
    sets of one -12..12 deg sweep at each of 6 loads with AR(1) noise
    (5.0 % when drawing from the true noise model).  None of these did
    better on the same 1000 sets: a REML estimate of the noise (6.4 %), one
    pooled sd (6.5 %), the bias correction on the long-run-variance scale
    (7.1 %), drawing each bootstrap sample's noise model from the estimate's
    spread (7.0 %), a fast double bootstrap (7.9 %), a full double bootstrap
    of the borderline results (6.9 %).  The diagnosis therefore screens at
    :attr:`~tyrefit.diagnose.steps.Settings.alpha_noise`, half its level.

    The sweep-offset variance tau^2 is what a candidate's between-sweep
    content (a constant force or slip shift, a law in load on one-sided
    sweeps) is weighed against, and with 5-7 sweeps it rests on the few
    sweep means a model leaves free; the model with every candidate spends
    2.2 of 6 of them on two-sided sweeps, nearly all on the shifts' constant
    and load-linear force offsets.  With an exactly representable null tyre
    (a plain Magic Formula) and sweep-offset noise (offset sd 0.5 sigma), one
    sweep at each of 6 loads, the first-round screening drawing its noise
    with that model's tau rejected 4.0 % of 600 null records at a nominal
    2.5 % (6.3 % at 5 %), the excess all in the shifts family.  The draws
    now take tau from the start model's residuals (restricted under the
    null, which has all 6 sweep means; Davidson & MacKinnon 1999: a
    bootstrap's data-generating process should be estimated under the null)
    when that is the larger, while every statistic is still studentised with
    the tau of the model with every candidate: 2.0 % at 2.5 % (4.3 % at 5 %)
    on the same 600 records.  Estimating the studentising tau under the null
    as well (per family) held the level too, but took all power from a pure
    force offset growing with load (conicity, 24-96 N: found in 0 of 20 data
    sets with independent noise, against 20 of 20): with 6 sweep means the
    restricted tau absorbs the trend it is to judge.  sd and rho stay those
    of the model with every candidate: a within-sweep effect left in the
    residuals would pass for correlated noise and take the power (the reason
    the noise is estimated from that model at all).

    The noise-model draws come in blocks (499, then 999, then ``n_boot`` in
    all) and stop once no candidate's decision at ``alpha`` can change
    (:func:`decided`: a sequential Monte Carlo test after Besag & Clifford,
    Biometrika 78 (1991) 301-304): a round where nothing is near the level
    needs 499 draws, not 1999.  The p-values then have the resolution
    1 / (draws + 1).
    """
    G = layout.G
    r = np.asarray(resid, dtype=float)
    off = _residualiser(J_model)
    Jt = [off(X) for X in J_new]
    jmax = [np.max(np.abs(X), axis=0) for X in Jt]  # largest force change the model cannot mimic [N/unit]
    q = np.array([X.shape[1] for X in Jt])
    K = len(Jt)
    allJ = np.hstack(Jt) if K else np.zeros((layout.N, 0))
    s_obs = allJ.T @ r
    sl = np.r_[0, np.cumsum(q)]
    fisher = [X.T @ X for X in Jt]
    info_p = _pinv_each(fisher, 1e-12)
    dssr = np.array([float(s_obs[sl[k]:sl[k + 1]] @ info_p[k] @ s_obs[sl[k]:sl[k + 1]]) for k in range(K)])
    if method == "auto":
        method = "flip" if G >= (min_flip_sweeps or MIN_FLIP_SWEEPS) else "noise"
    if method == "flip":
        W = rng.choice(np.array([-1.0, 1.0]), size=(n_boot, G))
        S = cluster_sums(allJ * r[:, None], layout.sweep, G)  # (G, sum q)
        Sb = W @ S
        T, Tb = np.empty(K), np.empty((K, n_boot))
        var = [S[:, sl[k]:sl[k + 1]].T @ S[:, sl[k]:sl[k + 1]] for k in range(K)]
        for k, Vp in enumerate(_pinv_each(var, 1e-10)):
            sk = S[:, sl[k]:sl[k + 1]].sum(axis=0)
            T[k] = float(sk @ Vp @ sk)
            sbk = Sb[:, sl[k]:sl[k + 1]]
            Tb[k] = np.einsum("bi,ij,bj->b", sbk, Vp, sbk)
        p, padj, crit = _minp_adjust(T, Tb, alpha)
        return Screen(T, p, padj, dssr, q, crit, "sweep flips", G, None,
                      [{"fisher": f, "var": v, "jmax": m} for f, v, m in zip(fisher, var, jmax)], n_boot)
    # --- noise-model bootstrap -----------------------------------------------------------------
    # the alternative: model plus every candidate direction (orthonormal basis); the noise is estimated
    # from its residuals so an effect that is there does not pass for correlated noise
    keep = [True] * K if in_alternative is None else list(in_alternative)
    Q, dof_w, dof_b = projection_basis(np.hstack([J_model] + [X for X, k in zip(Jt, keep) if k]), layout)
    # variance of every candidate's score under a noise model: J~' Sigma J~ with Sigma_g = sd_g^2 rho^|i-j|
    # + tau^2, from lagged cross-products of J~ within each sweep
    Jp = np.moveaxis(np.ascontiguousarray(layout.padded(allJ.T)), 0, -1)  # (G, H, sum q)
    H = layout.n_max
    pairs = [(sl[k] + i, sl[k] + j) for k in range(K) for i in range(q[k]) for j in range(q[k])]
    ia = np.array([a for a, _ in pairs], dtype=int)
    ib = np.array([b for _, b in pairs], dtype=int)
    # pair (i, j) at lag h: sum_t J_i[t] J_j[t+h] + sum_t J_j[t] J_i[t+h], the second sum being pair (j, i)'s first
    pair_at = np.r_[0, np.cumsum(q * q)]
    swap = np.array([pair_at[k] + j * q[k] + i for k in range(K) for i in range(q[k]) for j in range(q[k])],
                    dtype=int)
    lag = np.empty((G, H, len(pairs)))
    Ja, Jb = Jp[:, :, ia], Jp[:, :, ib]
    for h in range(H):
        x = np.sum(Ja[:, :H - h] * Jb[:, h:], axis=1)
        lag[:, h, :] = x + x[:, swap] if h > 0 else x
    colsum = Jp.sum(axis=1)  # (G, sum q)
    off = np.sum(colsum[:, ia] * colsum[:, ib], axis=0)  # (pairs,)

    def alt_resid(x):
        p = (x @ Q) @ Q.T
        return np.subtract(x, p, out=p)

    noise_obs, noise = corrected_noise(r, Q, dof_w, dof_b, layout, rng)
    # the draws' sweep offsets: the larger of that tau and the start model's own (restricted under the null,
    # from all the sweep means), see Notes; the statistics stay studentised with the full model's tau
    Q0, dw0, db0 = projection_basis(J_model, layout)
    tau0 = estimate_noise(r - (r @ Q0) @ Q0.T, layout, dw0, db0).tau
    draw_model = NoiseModel(sd=noise.sd, rho=noise.rho, tau=np.maximum(np.asarray(noise.tau), tau0))

    def variances(nm: NoiseModel) -> np.ndarray:
        rho = np.atleast_1d(nm.rho)
        powh = np.ones((len(rho), H))  # rho^h (B, H), as running products
        if H > 1:
            powh[:, 1:] = rho[:, None]
            np.cumprod(powh, axis=1, out=powh)
        w = (np.atleast_2d(nm.sd) ** 2)[:, :, None] * powh[:, None, :]  # (B, G, H)
        B = w.shape[0]
        return w.reshape(B, -1) @ lag.reshape(-1, lag.shape[-1]) + (np.atleast_1d(nm.tau) ** 2)[:, None] * off[None, :]

    Vobs = variances(noise_obs)[0]
    var = [Vobs[pair_at[k]:pair_at[k + 1]].reshape(q[k], q[k]) for k in range(K)]
    var_p = _pinv_each(var, 1e-10)
    T = np.array([float(s_obs[sl[k]:sl[k + 1]] @ var_p[k] @ s_obs[sl[k]:sl[k + 1]]) for k in range(K)])
    # the draws in blocks (sequential Monte Carlo, after Besag & Clifford 1991): stop once every candidate's
    # adjusted p-value is clear of alpha by far more than its Monte Carlo error, at most n_boot draws
    blocks = []
    for size in draw_blocks(n_boot):
        e = simulate_noise(draw_model, layout, size, rng)
        nb = estimate_noise(alt_resid(e), layout, dof_w, dof_b)
        sb = e @ allJ  # scores of the draws (J~ is orthogonal to the model's directions)
        Vb = variances(nb)
        blk = np.empty((K, size))
        for k in range(K):
            Vbk = Vb[:, pair_at[k]:pair_at[k + 1]].reshape(-1, q[k], q[k])
            blk[k] = _pinv_quadratic(sb[:, sl[k]:sl[k + 1]], Vbk, 1e-10)
        blocks.append(blk)
        Tb = np.hstack(blocks)
        p, padj, min_boot = _minp(T, Tb)
        if Tb.shape[1] < n_boot and _settled(padj, Tb.shape[1], alpha):
            break
    crit = _critical(Tb, min_boot, alpha)
    return Screen(T, p, padj, dssr, q, crit, "noise-model bootstrap", G, noise,
                  [{"fisher": f, "var": v, "jmax": m} for f, v, m in zip(fisher, var, jmax)], Tb.shape[1])


def detectable_size(fisher: np.ndarray, var: np.ndarray, critical: float, power: float = 0.8) -> np.ndarray:
    """Smallest parameter change the score test detects with ``power``, each parameter alone.

    With parameter change b, the score has mean I b (I = J~'J~) and variance
    V, so T = s'V^-1 s is noncentral chi-square with noncentrality
    b' I V^-1 I b.  For one parameter at a time the test rejects with
    probability ``power`` when sqrt(ncp) = sqrt(critical) + z_power
    (one-degree-of-freedom normal approximation).  Returns |b| per parameter
    (inf where the data carry no information on it).
    """
    from scipy.stats import norm

    I = np.atleast_2d(fisher)
    V = np.atleast_2d(var)
    need = np.sqrt(max(critical, 0.0)) + norm.ppf(power)
    out = np.full(I.shape[0], np.inf)
    for j in range(I.shape[0]):
        v = V[j, j]
        if v > 0 and I[j, j] > 0:
            out[j] = need * np.sqrt(v) / I[j, j]
    return out


def heldout_gain_null(J_model: np.ndarray, J_new: np.ndarray, noise: NoiseModel, layout: SweepLayout,
                      point_fold: np.ndarray, inside: np.ndarray, rng: np.random.Generator,
                      n_draws: int = 999) -> np.ndarray:
    """Null distribution of the held-out gain of adding ``J_new`` when the data are pure noise.

    The model is linearised at the current fit: for noise e the out-of-fold
    residual of fold f is e_test - X_test (X_train' X_train)^+ X_train' e_train
    with X the model's (or the model plus the candidate's) Jacobian, so the
    held-out gain sum_inside(oof_0^2 - oof_1^2) of a candidate that is not
    there is a quadratic form in e, simulated from the noise model
    (:class:`HeldoutNull`, which a diagnosis round keeps to test each of its
    candidates on the same draws).

    Parameters
    ----------
    J_model, J_new : ndarray (N, P), (N, q)
    noise : NoiseModel
    layout : SweepLayout
    point_fold : ndarray of int (N,)
        Fold of each point (whole sweeps).
    inside : ndarray of bool (N,)
        Points whose held-out prediction counts (sweeps inside the training levels).
    rng : Generator
    n_draws : int

    Returns
    -------
    ndarray (n_draws,)
        Held-out gains [N^2] under the null.
    """
    return HeldoutNull(J_model, noise, layout, point_fold, rng, n_draws).gain(J_new, inside)


def _unit_columns(X: np.ndarray) -> np.ndarray:
    return X / np.maximum(np.linalg.norm(X, axis=0), 1e-300)


class HeldoutNull:
    """Noise draws and the current model's out-of-fold errors on them, for the held-out gain of any candidate.

    The draws (from the noise model) and the current model's part of the
    held-out sums of squares are the same for every candidate of a round, so
    they are made once; :meth:`gain` adds a candidate's directions.  The
    out-of-fold prediction of fold f is (e_train pinv(X_train)') X_test', two
    thin products (B x n_train x P, then B x P x n_test) instead of the
    n_test x n_train hat matrix; the first for every fold at once, as e Z with
    Z (N, folds x P) holding each fold's pinv(X_train)' at its training points
    and zeros elsewhere (no copies of the draws' training columns).
    """

    def __init__(self, J_model: np.ndarray, noise: NoiseModel, layout: SweepLayout, point_fold: np.ndarray,
                 rng: np.random.Generator, n_draws: int = 999):
        self.e = simulate_noise(noise, layout, n_draws, rng)  # (B, N)
        self.noise = noise
        self.X0 = _unit_columns(J_model)
        self.point_fold = np.asarray(point_fold)
        self.folds = [(self.point_fold == f, self.point_fold != f) for f in np.unique(self.point_fold)]
        self._base: dict = {}

    def _sse(self, X: np.ndarray, inside: np.ndarray) -> np.ndarray:
        """Per draw: the sum over held-out points ``inside`` of the squared out-of-fold error of model X."""
        out = np.zeros(self.e.shape[0])
        used = [(te_all & inside, tr) for te_all, tr in self.folds if (te_all & inside).any()]
        P = X.shape[1]
        Z = np.zeros((X.shape[0], len(used) * P))
        for i, (_, tr) in enumerate(used):
            Z[tr, i * P:(i + 1) * P] = np.linalg.pinv(X[tr], rcond=1e-10).T
        coef = self.e @ Z  # (B, folds x P): each fold's fit to the noise
        for i, (te, _) in enumerate(used):
            oof = self.e[:, te] - coef[:, i * P:(i + 1) * P] @ X[te].T
            out += np.einsum("bi,bi->b", oof, oof)
        return out

    def gain(self, J_new: np.ndarray, inside: np.ndarray) -> np.ndarray:
        """Held-out gains [N^2] (B,) of adding the directions ``J_new`` (N, q) to the model, under the null."""
        inside = np.asarray(inside, dtype=bool)
        key = inside.tobytes()
        if key not in self._base:
            self._base[key] = self._sse(self.X0, inside)
        return self._base[key] - self._sse(np.hstack([self.X0, _unit_columns(J_new)]), inside)
