"""PAC89 fit: ``tyrefit.fitting.fit_pac89`` vs plain ``scipy.optimize.least_squares`` with finite differences.

Data (synthetic, nothing here is a measurement): the PAC89 example coefficient
set evaluated by :mod:`tyrefit.synthetic.pac89_example` at Fz 2, 4, 6, 8 kN x
camber -4, -2, 0, 2, 4 deg, slip -12..12 deg, 1 % Gaussian noise of each
sweep's peak; about 3 000 and 30 000 points (finer slip steps), and 300 000 with
``TYREFIT_BENCH_FULL=1``.

Baseline, measured in the same run on the same data and the same model:
``scipy.optimize.least_squares`` with its default 2-point finite-difference
Jacobian (default ``trf`` method, no bounds, no scaling) on the same residual
(mu = Fy/Fz, each sweep weighted 1/n) of :func:`tyrefit.models.pac89.lateral_force`,
over the same 14 coefficients a0..a13, from the same Eq. 2-4 start
(:mod:`tyrefit.fitting.initial`).  Both run with OpenBLAS on one thread
(:func:`tyrefit.fitting._blas.single_threaded_blas`), so that the ratio
measures the method (analytic Jacobian, staging, multi-start), not BLAS
threading on a shared machine.

Measurements per size:

* ``fit_pac89`` end to end (Eq. 2-4 estimates, staged multi-start fit,
  statistics, FitResult) vs the plain FD solve;
* the core solve alone (one :func:`tyrefit.fitting.core.solve` call, SciPy's
  ``least_squares``, from the same start with tyrefit's analytic Jacobian, same
  settings otherwise) vs the same call with ``jac='2-point'`` - the Jacobian's share.

* robustness (3k only): plain FD ``least_squares`` from three textbook
  starting points (no Eq. 2-4 estimates) vs ``fit_pac89(initial=...)`` from
  the same points; a start succeeds when the worst error against the
  generating curves is below 1 % of peak.

Each row records both RMSEs [N] of Fy over all points and the worst error
against the generating curves [% of peak].  ``python -m benchmarks.bench_fit``
prints the dict.
"""

from __future__ import annotations

import math

import numpy as np
from scipy.optimize import least_squares

from . import best_of, full, measurement

SIZES = {"3k": 0.16, "30k": 0.016}  # slip step [deg] -> 20 sweeps x (24 / step + 1) points
FULL_SIZES = {**SIZES, "300k": 0.0016}  # with TYREFIT_BENCH_FULL=1


def _data(step):
    from tyrefit.synthetic.pac89_example import lateral_sweeps

    return lateral_sweeps(slip_deg=np.arange(-12.0, 12.0 + 1e-9, step)).drop(columns="mz")


def _worst_pct(coeffs) -> float:
    from tyrefit.models import pac89
    from tyrefit.synthetic.pac89_example import EXAMPLE

    sa = np.radians(np.linspace(-12, 12, 241))
    worst = 0.0
    for fz in np.linspace(2000, 8000, 7):
        for g in np.radians([-4.0, -2.0, 0.0, 2.0, 4.0]):
            t = pac89.lateral_force(EXAMPLE, fz, sa, g)
            worst = max(worst, float(np.max(np.abs(pac89.lateral_force(coeffs, fz, sa, g) - t)) / np.max(np.abs(t))))
    return 100 * worst


def _rmse(coeffs, df) -> float:
    from tyrefit.models import pac89

    fy = pac89.lateral_force(coeffs, df["fz"].to_numpy(), df["slip_angle"].to_numpy(), df["camber"].to_numpy())
    return float(np.sqrt(np.mean((fy - df["fy"].to_numpy()) ** 2)))


def _plain_fd(df, start):
    """What a user would write: least_squares, default FD Jacobian, on the same residual and model."""
    from tyrefit.models import pac89

    names = pac89.LATERAL
    fz, sa, cam, fy = (df[c].to_numpy(float) for c in ("fz", "slip_angle", "camber", "fy"))
    n = df.groupby("run")["run"].transform("size").to_numpy(float)
    w = 1.0 / np.sqrt(n) / fz

    def resid(x):
        return w * (pac89.lateral_force(dict(zip(names, x)), fz, sa, cam) - fy)

    r = least_squares(resid, np.array([start[k] for k in names]))
    return dict(zip(names, r.x)), r


#: textbook starting points a user without Eq. 2-4 estimates might try (rest 0)
GENERIC_STARTS = [dict(a0=1.3, a2=1000.0, a3=1000.0, a4=10.0, a7=0.0),
                  dict(a0=1.5, a2=1000.0, a3=2000.0, a4=5.0, a7=-1.0),
                  dict(a0=1.0, a2=800.0, a3=500.0, a4=20.0, a7=0.5)]


def _robustness(df, fit_pac89, single_threaded_blas) -> dict:
    """Plain FD least_squares from textbook starts vs fit_pac89(initial=...) from the same starts.

    A start "succeeds" when the fit's worst error against the generating curves is below 1 % of peak.
    """
    import time

    t_fd = t_fit = 0.0
    ok_fd = ok_fit = 0
    rm_fd, rm_fit = [], []
    for st in GENERIC_STARTS:
        start = {f"a{i}": 0.0 for i in range(14)}
        start.update(st)
        with single_threaded_blas():
            t0 = time.perf_counter()
            c, _ = _plain_fd(df, start)
            t_fd += time.perf_counter() - t0
        t0 = time.perf_counter()
        res = fit_pac89(df, initial=st)
        t_fit += time.perf_counter() - t0
        ok_fd += _worst_pct(c) < 1.0
        ok_fit += _worst_pct(res.values) < 1.0
        rm_fd.append(_rmse(c, df))
        rm_fit.append(_rmse(res.values, df))
    return measurement(f"fit_pac89 from {len(GENERIC_STARTS)} textbook starts, {len(df)} points", t_fit,
                       "plain FD least_squares from the same starts", t_fd, points=len(df),
                       succeeded=ok_fit, baseline_succeeded=ok_fd, rmse_N=rm_fit, baseline_rmse_N=rm_fd)


def run() -> dict:
    from tyrefit.fitting import fit_pac89
    from tyrefit.fitting._blas import single_threaded_blas
    from tyrefit.fitting.core import solve
    from tyrefit.fitting.engine import _Problem, prepare_data

    out, info = [], {"sizes": {}}
    fit_pac89(_data(0.5))  # warm-up: imports, caches
    repeat = 3 if full() else 1
    for label, step in (FULL_SIZES if full() else SIZES).items():
        df = _data(step)
        npts = len(df)
        t_fit, res = best_of(lambda: fit_pac89(df), repeat=repeat)
        start = dict(res.initial)
        start.update({k: 0.0 for k in ("a5", "a8", "a9", "a10", "a11", "a12", "a13")})
        with single_threaded_blas():
            t_fd, (c_fd, r_fd) = best_of(lambda: _plain_fd(df, start), repeat=repeat)
        rm_fit, rm_fd = _rmse(res.values, df), _rmse(c_fd, df)
        out.append(measurement(f"fit_pac89, {npts} points, 14 coefficients (end to end)", t_fit,
                               "scipy least_squares, 2-point FD Jacobian, same residual/model/start", t_fd,
                               points=npts, rmse_N=rm_fit, baseline_rmse_N=rm_fd, nfev=res.stats["lateral"]["nfev"],
                               baseline_nfev=int(r_fd.nfev), worst_pct_of_peak=_worst_pct(res.values),
                               baseline_worst_pct_of_peak=_worst_pct(c_fd),
                               baseline_status=str(r_fd.message)))
        # the Jacobian's share: one solve from the same start, analytic vs FD
        parts, _ = prepare_data(df)
        prob = _Problem(parts["lateral"], start, list(res.coefficients.query("part == 'lateral' and varied")["name"]),
                        "l2")
        pars = prob.parameters(prob.theta_of(start))
        kw = dict(weights=prob.weights, method="trf", x_scale="jac", tol=1e-10, stderr=False)
        with single_threaded_blas():
            t_an, r_an = best_of(lambda: solve(prob.residual, pars, jac=prob.jac, **kw), repeat=repeat)
            t_2p, r_2p = best_of(lambda: solve(prob.residual, pars, jac="2-point", **kw), repeat=repeat)
        out.append(measurement(f"one core solve (least_squares), analytic Jacobian, {npts} points", t_an,
                               "same solve, jac='2-point'", t_2p, points=npts,
                               rmse_N=_rmse(prob.coeffs_of(r_an.x), df), baseline_rmse_N=_rmse(prob.coeffs_of(r_2p.x), df),
                               nfev=int(r_an.nfev), baseline_nfev=int(r_2p.nfev)))
        if label == "3k":
            out.append(_robustness(df, fit_pac89, single_threaded_blas))
        info["sizes"][label] = {"points": npts, "fit_seconds": t_fit, "fd_seconds": t_fd,
                                "ratio_fd_over_fit": t_fd / t_fit if t_fit > 0 else math.nan,
                                "rmse_fit_N": rm_fit, "rmse_fd_N": rm_fd}
    return {"measurements": out, "info": info}


if __name__ == "__main__":  # pragma: no cover
    import json

    print(json.dumps(run(), indent=2, default=float))
