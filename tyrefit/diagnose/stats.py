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
* :func:`holm` - Holm's step-down correction across the effects screened.
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
from scipy.interpolate import BSpline

__all__ = ["ScoreTest", "score_test", "GroupScoreTest", "score_test_groups", "residualise", "holm", "noise_floor",
           "sweep_folds", "level_folds", "cluster_bootstrap_prob", "cluster_sums", "crossval_surface"]

_DEG = np.pi / 180.0


def residualise(X: np.ndarray, J: np.ndarray) -> np.ndarray:
    """X minus its least-squares projection on the columns of J.

    Uses the small normal equations (column-scaled, pseudo-inverse) rather
    than a QR of the tall matrix: far faster on a busy multi-threaded BLAS.
    """
    norms = np.linalg.norm(J, axis=0)
    Js = J / np.where(norms > 0, norms, 1.0)
    A = Js.T @ Js
    return X - Js @ (np.linalg.pinv(A, rcond=1e-12, hermitian=True) @ (Js.T @ X))


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
    for X in groups:
        Jt = residualise(X, J_model)
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
    best = None
    for lam in ridge:
        pred = np.empty(len(r))
        for f in range(len(folds)):
            tr = pf != f
            A = B[tr].T @ B[tr]
            pen = lam * max(np.trace(A) / k, 1e-300)
            pred[~tr] = B[~tr] @ np.linalg.solve(A + pen * np.eye(k), B[tr].T @ r[tr])
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


def _bspline_basis(x: np.ndarray, spacing: float) -> np.ndarray:
    lo, hi = x.min(), x.max()
    n_int = int(max(0, np.floor((hi - lo) / spacing) - 1))
    interior = np.linspace(lo, hi, n_int + 2)[1:-1] if n_int > 0 else np.array([])
    t = np.r_[[lo] * 4, interior, [hi] * 4]
    return BSpline.design_matrix(x, t, 3).toarray()


def _magic_formula_ssr(x: np.ndarray, y: np.ndarray) -> tuple[float, int]:
    """SSR and dof of one Magic Formula (B, C, D, E, Sh, Sv) through a sparse sweep.

    A sweep of ~25 points cannot feed a 1.5 deg knot spline and still leave
    degrees of freedom for the noise; a single Magic Formula is the smooth curve
    with the fewest parameters that follows a tyre's force curve through its
    peak (Pacejka, Tyre and Vehicle Dynamics, Ch. 4).
    """
    from scipy.optimize import least_squares

    n = len(x)
    if n < 10:
        return 0.0, 0
    i = np.argsort(x)
    x, y = x[i], y[i]
    lin = np.abs(x - x[np.argmin(np.abs(x))]) <= max(np.ptp(x) / 8, 1e-9)
    slope = np.polyfit(x[lin], y[lin], 1)[0] if lin.sum() >= 2 else (y[-1] - y[0]) / np.ptp(x)
    d0 = max(np.abs(y).max(), 1e-9) * np.sign(slope or 1.0)
    c0 = 1.4
    p0 = np.array([slope / (c0 * d0), c0, d0, 0.0, 0.0, 0.0])

    def res(p):
        B, C, D, E, sh, sv = p
        bx = B * (x + sh)
        return D * np.sin(C * np.arctan(bx - E * (bx - np.arctan(bx)))) + sv - y

    lo = [-np.inf, 0.1, -np.inf, -10.0, -np.ptp(x) / 4, -np.inf]
    hi = [np.inf, 2.5, np.inf, 1.0, np.ptp(x) / 4, np.inf]
    p0 = np.clip(p0, np.array(lo) + 1e-9, np.array(hi) - 1e-9)
    try:
        sol = least_squares(res, p0, bounds=(lo, hi), x_scale="jac", max_nfev=400)
    except (ValueError, np.linalg.LinAlgError):
        return 0.0, 0
    r = sol.fun
    return float(r @ r), n - 6


def _spline_ssr(x: np.ndarray, y: np.ndarray, spacing: float, load=None) -> tuple[float, int]:
    """SSR and degrees of freedom of a cubic least-squares spline through (x, y).

    With ``load``, a coarser spline times the relative load deviation is added,
    so that point-to-point jitter of the measured load (which the model
    explains) is not counted as noise.
    """
    if np.ptp(x) <= 0:
        return 0.0, 0
    B = _bspline_basis(x, spacing)
    if load is not None:
        dz = (load - load.mean()) / max(abs(load.mean()), 1e-9)
        if np.ptp(dz) > 1e-6:
            B = np.hstack([B, _bspline_basis(x, 4 * spacing) * dz[:, None]])
    if len(x) - B.shape[1] < max(6, len(x) // 4):  # sparse sweep (1 deg steps): too little left for noise
        return _magic_formula_ssr(x, y)
    coef, _, rank, _ = np.linalg.lstsq(B, y, rcond=None)
    r = y - B @ coef
    return float(r @ r), int(len(x) - rank)


def noise_floor(slip_angle, fy, sweep, spacing_deg: float = 1.5, fz=None) -> tuple[float, np.ndarray]:
    """Within-sweep noise [N]: pooled RMSE of a smooth curve through each sweep.

    Parameters
    ----------
    slip_angle : array_like
        [rad].
    fy : array_like
        [N].
    sweep : array_like of int
    spacing_deg : float
        Knot spacing [deg] of the cubic spline in slip angle; the Magic
        Formula curve is smooth on this scale.
    fz : array_like, optional
        Measured load [N]; a coarse spline times its relative deviation within
        the sweep absorbs the load jitter the model explains.

    Returns
    -------
    floor : float
        sqrt(sum SSR / sum dof) over the sweeps [N].
    per_sweep : ndarray
        The same per sweep [N] (NaN where a sweep is too short).

    Notes
    -----
    This is the error no global model can beat *within* a sweep; slow drifts
    and sweep-to-sweep offsets are absorbed by the per-sweep curves, so a
    global model's RMSE can stay above it when the rig has such noise.
    """
    a = np.asarray(slip_angle, dtype=float)
    y = np.asarray(fy, dtype=float)
    z = None if fz is None else np.asarray(fz, dtype=float)
    sw = np.asarray(sweep)
    G = int(sw.max()) + 1
    per = np.full(G, np.nan)
    ssr_tot, dof_tot = 0.0, 0
    for g in range(G):
        m = sw == g
        if m.sum() < 10:
            continue
        o = np.argsort(a[m], kind="stable")
        ssr, dof = _spline_ssr(a[m][o], y[m][o], spacing_deg * _DEG, None if z is None else z[m][o])
        if dof > 0:
            per[g] = np.sqrt(ssr / dof)
            ssr_tot += ssr
            dof_tot += dof
    floor = float(np.sqrt(ssr_tot / dof_tot)) if dof_tot > 0 else float("nan")
    return floor, per


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
