"""What the data allow: the truth's own form refitted, scored like the diagnosis.

The held-out target of the validation (held-out RMSE after the right effect
<= 1.3 x the true noise) mixes two things: how well the diagnosis' model
represents the truth, and how much six noisy sweeps can say about a sweep
that is left out.  The second is a property of the layout and the noise, not
of the engine, and it has a hard floor: a model of *exactly* the truth's
form, every shape parameter free and started at the truth, still has to be
estimated from the other sweeps, and its held-out error then carries that
estimation error on top of the held-out sweep's own noise.

:func:`truth_form_heldout` measures that floor on one case.  It refits the
:class:`~.truth.TruthTyre` (its base shape parameters and the parameters of
the case's effect) by ordinary least squares on the lateral force in N, like
the diagnosis' fitter, holds out every sweep whose load lies inside the other
sweeps' loads in turn (the diagnosis' interpolated held-out sweeps on one
sweep per load) and returns the RMSE of those predictions over the true
sigma.  The same score of the diagnosis' model set against it shows how
much of a missed target is the engine's and how much the data's.

:func:`model_scores` gives two other readings of "held out" for the diagnosed
models, fitted to all sweeps: their RMSE on an independent rerun of the same
test (new load jitter and new noise of the same model,
:func:`.cases.make_case` with ``repeat=1``; what a second rig run of the same
tyre would show, its own noise included) and their RMS distance from the
noise-free truth (a rerun's expected RMSE is sigma sqrt(1 + error^2), so the
target's 1.3 sigma is an error of 0.83 sigma).  :func:`truth_form_scores` gives
the same two for the truth's own form refitted to every sweep.

Only the one-sweep-per-load layouts (``load5``, ``load6``, ``load7``,
``onesided6``) are scored by :func:`truth_form_heldout`; on the grids the
diagnosis holds out folds of sweeps, not single levels.

**Synthetic.**  These are scores of generated cases, never of measurements.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
from scipy.optimize import least_squares

from ...diagnose.data import prepare
from .cases import Case
from .truth import EFFECT_SIZES, TruthTyre

__all__ = [
    "FREE_BASE",
    "free_parameters",
    "interior_sweeps",
    "model_scores",
    "refit_truth",
    "truth_form_heldout",
    "truth_form_scores",
]

#: base-shape parameters of the truth refitted in every case: (scale, lower, upper)
FREE_BASE: dict[str, tuple[float, float, float]] = {
    "mu0": (1.0, 0.3, 3.0),
    "k_max": (1e5, 1e4, 1e6),
    "f_k": (1e4, 500.0, 1e5),
    "q0": (0.5, 0.0, 5.0),
    "d": (0.1, 0.0, 0.9),
    "phi_d": (2.5, 0.2, 20.0),
}

#: the effects' own parameters (beyond :data:`~.truth.EFFECT_SIZES`' sizes, their scales)
_FREE_EFFECT: dict[str, tuple[float, float, float]] = {
    "n_pow": (0.1, -1.0, 1.0),
    "m_tanh": (0.1, -1.0, 1.0),
    "f_m": (4000.0, 200.0, 1e5),
    "k_curv": (1.0, -5.0, 5.0),
    "c_over": (0.5, -5.0, 5.0),
    "w_over": (480.0, 20.0, 1e4),
    "alpha_ps": (0.002, -0.05, 0.05),
    "c_con": (0.01, -0.2, 0.2),
    "c_gamma": (1.0, -10.0, 10.0),
    "g_s": (0.1, 0.005, 1.0),
    "kp_k": (0.3, -3.0, 3.0),
    "kp_mu": (0.1, -3.0, 3.0),
    "s_asym": (0.3, -0.95, 0.95),
    "k_gs": (0.05, -1.0, 1.0),
}

#: an effect's law parameters that its size does not name (the tanh law's load scale, the knee's width, ...)
_COMPANIONS = {"m_tanh": ("f_m",), "c_over": ("w_over",), "c_gamma": ("g_s",)}


_INPUTS = ("fz", "slip_angle", "camber", "pressure")


def _columns(frame) -> list[np.ndarray]:
    """The truth tyre's inputs (load, slip, camber, pressure) of a case's frame."""
    return [frame[c].to_numpy(dtype=float) for c in _INPUTS]


def _rms(err, sigma: float) -> float:
    """RMS of ``err`` (an array or a list of arrays) over ``sigma``."""
    e = np.concatenate(err) if isinstance(err, list) else np.asarray(err)
    return float(np.sqrt(np.mean(e**2)) / sigma)


def free_parameters(tyre: TruthTyre) -> dict[str, tuple[float, float, float]]:
    """Parameters refitted for ``tyre``: the base shape plus the laws of its effects."""
    out = dict(FREE_BASE)
    for e in tyre.effects:
        for name in EFFECT_SIZES[e]:
            for p in (name, *_COMPANIONS.get(name, ())):
                out[p] = _FREE_EFFECT[p]
    return out


def refit_truth(tyre: TruthTyre, fz, slip_angle, camber, pressure, fy, free=None) -> TruthTyre:
    """Least-squares refit of ``tyre``'s form to ``fy`` [N], from ``tyre``'s own values.

    ``free`` maps parameter names to (scale, lower, upper); default :func:`free_parameters`.
    """
    free = free_parameters(tyre) if free is None else free
    names = list(free)
    scale = np.array([free[k][0] for k in names])
    lo = np.array([free[k][1] for k in names]) / scale
    hi = np.array([free[k][2] for k in names]) / scale
    x0 = np.clip(np.array([getattr(tyre, k) for k in names]) / scale, lo, hi)

    def at(x):
        return replace(tyre, **{k: float(v) for k, v in zip(names, x * scale)})

    def resid(x):
        return at(x).lateral_force(fz, slip_angle, camber, pressure) - fy

    return at(least_squares(resid, x0, bounds=(lo, hi), x_scale=1.0).x)


def interior_sweeps(case: Case) -> list:
    """Runs whose load lies strictly inside the other runs' loads (the interpolated held-out sweeps).

    Raises ValueError on a layout that does not have one sweep per load.
    """
    d = case.data
    load = d.groupby("run")["fz"].mean()
    if load.round(-1).nunique() != len(load):
        raise ValueError(f"{case.layout}: the truth-form floor is defined on one sweep per load only")
    return [g for g in load.index if load.drop(g).min() < load[g] < load.drop(g).max()]


def truth_form_heldout(case: Case) -> dict:
    """Held-out RMSE / true sigma of the truth's own form on the interior sweeps, each left out in turn.

    Returns ``ratio`` (predictions against the data, as the diagnosis scores
    its own) and ``error`` (predictions against the noise-free truth: the
    estimation error alone).
    """
    d = case.data
    cols = _columns(d)
    fy, run = d["fy"].to_numpy(dtype=float), d["run"].to_numpy()
    pred_err, est_err = [], []
    for g in interior_sweeps(case):
        tr, te = run != g, run == g
        t = refit_truth(case.tyre, *(c[tr] for c in cols), fy[tr])
        p = t.lateral_force(*(c[te] for c in cols))
        pred_err.append(p - fy[te])
        est_err.append(p - case.truth_fy[te])
    return {"ratio": _rms(pred_err, case.sigma), "error": _rms(est_err, case.sigma)}


def _inputs(case: Case, like=None):
    """The diagnosis' prepared inputs and measured force of ``case``; reference values (the curved laws'
    reference load, the rated load) taken from ``like`` (inputs of the data the model was fitted to)."""
    sd = prepare(case.data, rated_load=case.rated_load)
    inp = sd.inputs
    if like is not None:
        inp = inp._replace(rated_load=like.rated_load, pressure_ref=like.pressure_ref, speed_ref=like.speed_ref,
                           fz_ref=like.fz_ref)
    return inp, sd.fy


def _truth_at(case: Case, inp) -> np.ndarray:
    return case.tyre.lateral_force(inp.fz, inp.slip_angle, inp.camber, inp.pressure)


def model_scores(steps, case: Case, rerun: Case) -> list[dict]:
    """How close diagnosis steps' fitted models are to the tyre, each as RMS / true sigma.

    ``steps`` are :class:`tyrefit.diagnose.steps.Step` objects fitted to
    ``case``; ``rerun`` is an independent rerun of the same test
    (:func:`.cases.make_case` with ``repeat=1``).  For each step:

    * ``rerun``: RMSE of its predictions on the rerun's measured force (held-out data, their noise included);
    * ``error``: RMS of its predictions against the noise-free truth at the case's own points (the model's
      distance from the tyre: a rerun's *expected* RMSE is sigma sqrt(1 + error^2)).
    """
    if (rerun.layout, rerun.noise, rerun.effect, rerun.seed) != (case.layout, case.noise, case.effect, case.seed):
        raise ValueError("the rerun must be of the same case")
    inp, _ = _inputs(case)
    rin, rfy = _inputs(rerun, like=inp)
    truth = _truth_at(case, inp)
    out = []
    for st in steps:
        pred, rpred = st.spec.predict(st.fit.theta, inp), st.spec.predict(st.fit.theta, rin)
        out.append({"rerun": _rms(rpred - rfy, case.sigma), "error": _rms(pred - truth, case.sigma)})
    return out


def truth_form_scores(case: Case, rerun: Case) -> dict:
    """:func:`model_scores` of the truth's own form refitted to every sweep of ``case`` (the floor of both)."""
    t = refit_truth(case.tyre, *_columns(case.data), case.data["fy"].to_numpy(dtype=float))
    pred, rpred = t.lateral_force(*_columns(case.data)), t.lateral_force(*_columns(rerun.data))
    return {"rerun": _rms(rpred - rerun.data["fy"].to_numpy(dtype=float), case.sigma),
            "error": _rms(pred - case.truth_fy, case.sigma)}
