"""A small mutation run: do the tests notice when the code is wrong?

Usage (from the repository root; minutes on one core)::

    nice python -m benchmarks.mutation --sample 40 --seed 15 [--root DIR] [--named] [--json OUT]

``--sample`` is the total: round(sample / number of target files) mutants per file (at least 1).
Issue 25's run is ``--sample 264 --seed 15``: 12 mutants in each of the 22 modules of
:data:`TARGETS` (``fitting/mf.py`` and the four modules split from it count as five), about 50
minutes on one core.  A file's 12 are the same in any run that gives it 12.

How it works
------------
The repository (``tyrefit/``, ``tests/``, ``data/``, ``pyproject.toml``) is
copied once to a scratch directory.  Each mutant rewrites one source file there
and runs the test files that exercise it (``pytest -x -q``, the fast tier) with
``PYTHONPATH`` pointing at the copy, so ``import tyrefit`` finds the mutant (the
runner checks this before starting).  A mutant is *killed* when the tests fail
or exceed their time limit (3x the unmutated run + 20 s), *survives* when they
pass.  The score is killed / (killed + survived).

Mutation operators (AST, one change per mutant; after Offutt et al., "An
experimental determination of sufficient mutant operators", ACM TOSEM 5 (1996)):

* arithmetic: ``+`` <-> ``-``, ``*`` <-> ``/``, ``**`` -> ``*``;
* a term deleted: ``a + b`` -> ``a``, ``a - b`` -> ``a``, ``a * b`` -> ``a``;
* comparison: ``<`` <-> ``<=``, ``>`` <-> ``>=``, ``==`` <-> ``!=``;
* boolean: ``and`` <-> ``or``, ``not x`` -> ``x``;
* unary minus dropped: ``-x`` -> ``x``;
* number constants: ``0`` <-> ``1``, others ``c`` -> ``2 c``.

Sites are enumerated per file in a fixed order and sampled per file with a
seed derived from ``--seed`` and the file's path, so that an unchanged file
gives the same mutants in any checkout: runs before and after new tests can be
compared mutant by mutant.

``--named`` also runs the hand-written mutants of issues 15 and 25
(:data:`NAMED`): mutations that survived the suite when the issue was written.
``--only FRAGMENT[,FRAGMENT]`` runs just the named mutants whose name contains
one of the fragments (add ``--sample 0`` to skip the sampled ones).  A named
mutant whose text is no longer in the code (exactly once) stops the run
(:class:`StaleMutant`, exit status 1 with the list) instead of leaving the
score: keep :data:`NAMED` in step with the code.
"""

from __future__ import annotations

import argparse
import ast
import hashlib
import json
import os
import random
import shutil
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass, field
from pathlib import Path

#: modules mutated, and the test files run against each (the fast tier of each file)
TARGETS = {
    "tyrefit/models/pac89.py": ["tests/test_pac89.py", "tests/test_mutants_session12.py", "tests/test_fitting.py",
                                "tests/test_mutations.py"],
    "tyrefit/models/slip.py": ["tests/test_slip.py", "tests/test_mutants_session13.py"],
    "tyrefit/fitting/engine.py": ["tests/test_mutants_sampled_fit.py", "tests/test_mutants_session12.py",
                                  "tests/test_mutants_session13.py", "tests/test_fitting.py",
                                  "tests/test_robust_fit.py", "tests/test_mutations.py", "tests/test_fit_params.py"],
    "tyrefit/fitting/initial.py": ["tests/test_mutants_sampled_fit.py", "tests/test_mutants_session13.py",
                                   "tests/test_fitting.py", "tests/test_robust_fit.py"],
    "tyrefit/io/tir.py": ["tests/test_mutants_sampled_io.py", "tests/test_mutants_session12.py", "tests/test_tir.py",
                          "tests/test_tir_no_model.py", "tests/test_mutations.py", "tests/test_mutants_session13.py"],
    "tyrefit/io/readers.py": ["tests/test_mutants_sampled_io.py", "tests/test_io_csv.py", "tests/test_io_errors.py",
                              "tests/test_io_load_programme.py", "tests/test_mutants_session13.py"],
    "tyrefit/io/segment.py": ["tests/test_mutants_sampled_io.py", "tests/test_mutants_session12.py",
                              "tests/test_io_csv.py", "tests/test_io_ttc.py", "tests/test_inspect.py",
                              "tests/test_mutants_session13.py"],
    # issue 25's modules (the quick files that import each, fastest first: -x stops at the first failure;
    # tests/test_mutants_sampled_*.py kill the sampled mutants of --sample 216 --seed 15 that survived the rest,
    # tests/test_mutants_session13.py those of the fresh draw --sample 264 --seed 16)
    "tyrefit/fitting/core.py": ["tests/test_mutants_sampled_fit.py", "tests/test_mutants_fresh_core_stats.py",
                                "tests/test_mutants_session13.py", "tests/test_fitting_core.py",
                                "tests/test_diagnose_speed.py", "tests/test_mutants_issue25.py",
                                "tests/test_fitting.py"],
    "tyrefit/fitting/mf.py": ["tests/test_mutants_sampled_fit.py", "tests/test_mutants_session12.py",
                              "tests/test_mutants_issue25.py", "tests/test_mutants_session13.py",
                              "tests/test_fit_params.py", "tests/test_fit_mf_speed.py", "tests/test_fit_mf.py"],
    # fitting/mf.py's jobs split out (issue 27): the same test files as mf.py
    "tyrefit/fitting/mf_identify.py": ["tests/test_mutants_sampled_fit.py", "tests/test_mutants_session12.py",
                                       "tests/test_mutants_issue25.py", "tests/test_mutants_session13.py",
                                       "tests/test_fit_params.py", "tests/test_fit_mf_speed.py",
                                       "tests/test_fit_mf.py"],
    "tyrefit/fitting/mf_contract.py": ["tests/test_mutants_sampled_fit.py", "tests/test_mutants_session12.py",
                                       "tests/test_mutants_issue25.py", "tests/test_mutants_session13.py",
                                       "tests/test_fit_params.py", "tests/test_fit_mf_speed.py",
                                       "tests/test_fit_mf.py"],
    "tyrefit/fitting/mf_eval.py": ["tests/test_mutants_sampled_fit.py", "tests/test_mutants_session12.py",
                                   "tests/test_mutants_issue25.py", "tests/test_mutants_session13.py",
                                   "tests/test_fit_params.py", "tests/test_fit_mf_speed.py", "tests/test_fit_mf.py"],
    "tyrefit/fitting/mf_initial.py": ["tests/test_mutants_sampled_fit.py", "tests/test_mutants_session12.py",
                                      "tests/test_mutants_issue25.py", "tests/test_mutants_session13.py",
                                      "tests/test_fit_params.py", "tests/test_fit_mf_speed.py",
                                      "tests/test_fit_mf.py"],
    "tyrefit/sim/allocator.py": ["tests/test_mutants_sampled_rig.py", "tests/test_sim_allocator.py",
                                 "tests/test_mutants_issue25.py"],
    "tyrefit/io/pac89_tir.py": ["tests/test_mutants_sampled_io.py", "tests/test_pac89_tir_units.py",
                                "tests/test_tir.py", "tests/test_fuzz_tyre_files.py",
                                "tests/test_mutants_session13.py"],
    "tyrefit/rig/patch.py": ["tests/test_mutants_sampled_rig.py", "tests/test_rig_patch.py",
                             "tests/test_rig_vertical.py", "tests/test_mutants_issue25.py",
                             "tests/test_mutants_session13.py"],
    "tyrefit/models/mf61.py": ["tests/test_mutants_sampled_fit.py", "tests/test_mf61_model.py",
                               "tests/test_mf_parts.py", "tests/test_mf52_61keys.py", "tests/test_mf_tir_write.py",
                               "tests/test_mutants_issue25.py", "tests/test_mf_use_mode.py"],
    "tyrefit/diagnose/engine.py": ["tests/test_mutants_sampled_diag.py", "tests/test_mutants_session12.py",
                                   "tests/test_mutants_engine_fresh.py", "tests/test_mutants_session13.py",
                                   "tests/test_diagnose_speed.py", "tests/test_mutants_issue25.py",
                                   "tests/test_diagnose_camber_evidence.py", "tests/test_diagnose.py"],
    "tyrefit/diagnose/stats.py": ["tests/test_mutants_sampled_diag.py", "tests/test_mutants_session12.py",
                                  "tests/test_mutants_fresh_core_stats.py", "tests/test_mutants_session13.py",
                                  "tests/test_diagnose_speed.py", "tests/test_mutants_issue25.py",
                                  "tests/test_diagnose.py", "tests/test_diagnose_noise_verdict.py"],
    "tyrefit/io/ttc.py": ["tests/test_mutants_sampled_io.py", "tests/test_io_ttc_lines.py", "tests/test_io_ttc.py",
                          "tests/test_ttc_field.py", "tests/test_mutants_session13.py"],
    "tyrefit/io/outputs.py": ["tests/test_mutants_sampled_io.py", "tests/test_outputs.py",
                              "tests/test_outputs_folder_names.py", "tests/test_outputs_names.py",
                              "tests/test_mutants_session13.py"],
    "tyrefit/rig/conversion.py": ["tests/test_mutants_sampled_rig.py", "tests/test_rig_conversion.py",
                                  "tests/test_mutants_issue25.py", "tests/test_mutants_session13.py"],
}

#: the mutations issue 15 found surviving: (name, file, old text, new text, tests)
NAMED = [
    ("sweep weighting 1/n dropped from the default cost", "tyrefit/fitting/problem.py",
     "        self.weights = self.data.sweep_weights()",
     "        self.weights = np.ones(self.y.size)",
     ["tests/test_fitting.py", "tests/test_mutations.py"]),
    ("speed effect's stiffness term deleted", "tyrefit/effects/catalogue.py",
     "    coef[\"a3\"] = coef[\"a3\"] * relative_factor(x.speed, x.speed_ref, v[\"speed_ky\"])\n",
     "",
     ["tests/test_effects.py", "tests/test_mutations.py"]),
    ("a12 left out of mirrored()", "tyrefit/tyres/pac89.py",
     "for k in (\"a9\", \"a10\", \"a12\", \"a13\"",
     "for k in (\"a9\", \"a10\", \"a13\"",
     ["tests/test_tir.py", "tests/test_compare.py", "tests/test_mutations.py"]),
    ("89.5 deg slip clamp moved to 30 deg", "tyrefit/models/pac89.py",
     "X_LIMIT_DEG = 89.5",
     "X_LIMIT_DEG = 30.0",
     ["tests/test_pac89.py", "tests/test_mutations.py"]),
    ("scenarios' treadwear exponent silently replaced by HPwizard's 0.15", "tyrefit/sim/scenarios.py",
     None, None,  # filled by _named_scenarios (the code under test changed with its fix)
     ["tests/test_sim_scenarios.py", "tests/test_mutations.py"]),
]

#: the mutations issue 25 found surviving the quick suite (each killed by tests/test_mutants_issue25.py)
NAMED += [
    ("l1 cost stops after the first continuation step", "tyrefit/fitting/core.py",
     "        for frac in L1_STEPS:\n", "        for frac in L1_STEPS[:1]:\n",
     ["tests/test_fitting_core.py", "tests/test_mutants_issue25.py"]),
    ("MF stage constraint penalty weight 0", "tyrefit/fitting/mf.py",
     "self.pen_w = 10.0 * math.sqrt(", "self.pen_w = 0.0 * math.sqrt(",
     ["tests/test_mutants_issue25.py"]),
    ("allocator's rear-force clip removed", "tyrefit/sim/allocator.py",
     "        fx_r = np.minimum(np.maximum(fx_r, self.rear.lower), self.rear.upper)\n", "",
     ["tests/test_sim_allocator.py", "tests/test_mutants_issue25.py"]),
    ("torque feed-forward without the slip term of dw_ref/dt", "tyrefit/sim/allocator.py",
     "dw_ref = (1.0 + lam) * vdot / p.wheel_radius", "dw_ref = vdot / p.wheel_radius",
     ["tests/test_sim_allocator.py", "tests/test_mutants_issue25.py"]),
    ("breakpoint interval at Delta SSE = s, not s / dof", "tyrefit/rig/patch.py",
     "s * (1.0 + 1.0 / dof)", "s * (1.0 + 1.0)",
     ["tests/test_rig_patch.py", "tests/test_mutants_issue25.py"]),
    ("linear pressure law's sign flipped", "tyrefit/rig/patch.py",
     "return self.ref + self.m * (p - p_ref)", "return self.ref - self.m * (p - p_ref)",
     ["tests/test_rig_patch.py", "tests/test_mutants_issue25.py"]),
    ("My without VXLOW does not follow the rolling speed's sign", "tyrefit/models/mf61.py",
     "        my = my * np.sign(vr)\n", "        my = my\n",
     ["tests/test_mf61_model.py", "tests/test_mutants_issue25.py"]),
    ("level-out confirmation guard switched off", "tyrefit/diagnose/engine.py",
     "    if np.isfinite(ev[\"delta_levelout\"]) and ev[\"delta_levelout\"] < 0:\n", "    if False:\n",
     ["tests/test_diagnose.py", "tests/test_mutants_issue25.py"]),
    ("score-test p-value without the +1 (can be 0)", "tyrefit/diagnose/stats.py",
     "    p = (1.0 + np.count_nonzero(Tb >= T * (1 - 1e-9))) / (n_boot + 1.0)",
     "    p = (0.0 + np.count_nonzero(Tb >= T * (1 - 1e-9))) / (n_boot + 1.0)",
     ["tests/test_mutants_issue25.py"]),
    ("screening p-value without the +1 (can be 0)", "tyrefit/diagnose/stats.py",
     "    p_obs = (1.0 + np.sum(Tb >= T[:, None] * (1 - 1e-9), axis=1)) / (B + 1.0)",
     "    p_obs = (0.0 + np.sum(Tb >= T[:, None] * (1 - 1e-9), axis=1)) / (B + 1.0)",
     ["tests/test_mutants_issue25.py"]),
    ("relaxation_length() without the factor n", "tyrefit/rig/conversion.py",
     "return self.n * np.asarray(length, float) * (1.0 + self.b * np.abs(u))",
     "return np.asarray(length, float) * (1.0 + self.b * np.abs(u))",
     ["tests/test_rig_conversion.py", "tests/test_mutants_issue25.py"]),
]

#: sampled mutants of ``--sample 216 --seed 15`` (code of bce2202) that the quick suite lets live, and why that
#: is harmless: (file, a fragment of the mutant's changed line as ast.unparse writes it, kind, why).  Kinds:
#: 'equivalent' (no input reachable through tyrefit behaves differently), 'tie' (differs only where two
#: computed floats are exactly equal), 'harmless' (differs, but in no result a user sees).  The run prints
#: the reason under each surviving mutant that matches, and leaves the equivalent ones out of
#: ``adjusted_score``.
KNOWN_SURVIVORS = [
    ("tyrefit/models/pac89.py", "f.E) - f.Sv", "equivalent",
     "PAC89's longitudinal Sv is 0 x Fz (longitudinal_factors): x - 0 = x + 0"),
    ("tyrefit/fitting/engine.py", "if spec.name != 'lateral' and 'a4' in why", "equivalent",
     "the block never changes c0: c0 = dict(c_init) already, its conditions rule out a3/a4 from initial= or "
     "fixed=, and 'a4' in why arises only for the lateral part (need_loads under p == 'lateral')"),
    ("tyrefit/fitting/engine.py", "if (s, i) == ('b7', 'b8') or ('b6' in self.vary", "harmless",
     "with b6 fitted (>= 4 loads) the D and BCD end-load laws are dropped as well; they are inactive for "
     "physical sweeps (longitudinal example: same coefficients to 1e-6)"),
    ("tyrefit/fitting/engine.py", "* _RAD_TO_DEG if self.d.camber.size else 1", "equivalent",
     "d.camber holds one value per point and a part is fitted only with sweeps of >= 4 points: never empty"),
    ("tyrefit/fitting/engine.py", "'a3': (2e-09, np.inf)", "harmless",
     "a guard floor on the peak cornering stiffness a3 (N/deg): rig values are ~1e3 (lateral example: 2461)"),
    ("tyrefit/fitting/initial.py", "if nl >= 2 and np.ptp(fzk) >= 0:", "equivalent",
     "nl >= 2 distinct load levels give ptp > 0; no caller passes n_levels"),
    ("tyrefit/fitting/initial.py", "if C > 1.0 and B * x_m > 0:", "equivalent",
     "C > 1 only on Eq. 2's falling branch, where y_a < 0.98 D gives C >= 1.127"),
    ("tyrefit/fitting/initial.py", "if C > 1.0 + 2e-06 and B * x_m > 0:", "equivalent",
     "C > 1 only on Eq. 2's falling branch, where y_a < 0.98 D gives C >= 1.127"),
    ("tyrefit/io/tir.py", "{62: '6.2', 122: '6.1'}", "equivalent",
     "FITTYP 61 makes the family MF61, whose default is '6.1'"),
    ("tyrefit/io/tir.py", "entries.get(req, 1) is None", "equivalent", "neither default (0 or 1) is None"),
    ("tyrefit/io/readers.py", "f = d['fy']", "equivalent",
     "lateral_slope centres the slip angle per run, so the per-run mean force drops out of sum(a f)"),
    ("tyrefit/io/readers.py", "'static': ('fy', 0)}", "equivalent",
     "the expected sign of a static push is never read (the sign check skips static data)"),
    ("tyrefit/io/segment.py", "np.where(ok, idx, 0)", "equivalent",
     "digits stay distinct among on-level samples; off-level samples never lie in a steady stretch"),
    ("tyrefit/io/segment.py", "direction = 1 if imax >= imin", "equivalent",
     "imax == imin means a zero range, never >= the positive threshold"),
    ("tyrefit/io/segment.py", "Counter(label[(run <= 0) & (label != '')])", "equivalent",
     "samples of a kept sweep carry no drop label"),
    ("tyrefit/fitting/core.py", "small = z < 1.0", "tie",
     "Huber's rho and rho' are continuous at z = 1; only rho'' at exactly z = 1 differs"),
    ("tyrefit/fitting/core.py", "if rel <= tol or dx < tol:", "tie", "a cost fall of exactly tol x the cost"),
    ("tyrefit/fitting/mf_contract.py", "if est is None and est.empty", "equivalent",
     "est is never None; a column-less est fails at its has_peak lookup after the ceiling either way"),
    ("tyrefit/fitting/mf.py", "if x - grp[-1] >= tol:", "tie",
     "condition means exactly one tolerance apart (0.5 deg, 5 kPa, 2 km/h)"),
    ("tyrefit/fitting/mf.py", "1000.0 / np.max(self.w)", "harmless",
     "the residual of a non-finite model row is a large constant either way (w <= 1): the step is refused"),
    ("tyrefit/fitting/mf_contract.py", "g('PDY2', 1) * dfz", "equivalent",
     "p is always the complete neutral() set plus the stage's values: the default is never used"),
    ("tyrefit/rig/patch.py", "xs0 = float(max(x[i], 1e-06))", "harmless",
     "a start-value guard; x[i] (the load nearest 63 % of the widest) is far above both"),
    ("tyrefit/rig/patch.py", "min=2e-09, meaning='load scale of the rise'", "harmless",
     "a bound at 1e-9 N on a load scale of ~1e4 N"),
    ("tyrefit/rig/patch.py", "xs0 = float(max(x[i], 2e-06 * np.max(x)))", "harmless",
     "a start-value guard; x[i] is far above both"),
    ("tyrefit/rig/patch.py", "'o', color=c, ms=8)", "harmless", "marker size of the measured points in a plot"),
    ("tyrefit/diagnose/engine.py", "tot = sum(var.values()) or 0", "harmless",
     "a guard for a misfit surface of exactly zero variance, which the check never fits (ratio > 1.3 first)"),
    ("tyrefit/diagnose/engine.py", "new[i] > new[chosen] or new[i] <= new[chosen]", "equivalent",
     "sets: where new[i] == new[chosen], new[i] <= new[chosen] holds as well"),
    ("tyrefit/diagnose/stats.py", "np.sign(slope and 1.0)", "equivalent",
     "the start (B, D) becomes (-B, -D): the same Magic Formula curve, the same SSR"),
    ("tyrefit/diagnose/stats.py", "np.sum(Tb > T[:, None] * (1 - 1e-09), axis=1)) / (n_boot + 1.0)", "tie",
     "a bootstrap statistic exactly equal to T (1 - 1e-9); the W = +-1 draws (T* = T) count either way"),
    ("tyrefit/io/outputs.py", "_RANDOM = 16", "harmless",
     "side-file names keep 8 more bytes of room: shorter temporary names, never seen"),
    ("tyrefit/io/outputs.py", "mask = os.umask(1)", "equivalent",
     "the mask is read and set back: umask(1) returns the same old mask"),
    ("tyrefit/rig/conversion.py", "max=20.0, unit='1/deg'", "harmless",
     "a bound on K at 10 per degree; tyres have 0.05-0.5"),
    # the same seed on the code of 069d4bd (fitting/mf.py split, diagnose's end check reworked): new sites
    ("tyrefit/fitting/mf_initial.py", "'RBY1': 20.0", "harmless", "a start value of the combined Fy stage"),
    ("tyrefit/fitting/mf_eval.py", "if self.pure == 'kappa' or self.channel == 'mx':", "harmless",
     "Mx's analytic Jacobian left out: finite differences instead (speed only)"),
    ("tyrefit/fitting/mf.py", "np.isfinite(pts['fy'].to_numpy(float)).sum() >= 10:", "harmless",
     "the Mz0 start estimate also with exactly 10 points (a start value)"),
    ("tyrefit/fitting/mf_initial.py", "if 'PPX3' not in why else 1,", "harmless",
     "the start of a PPX3 the data cannot identify: held at its neutral 0 (base takes init only for fitted "
     "or core names)"),
    ("tyrefit/fitting/mf_contract.py", "g('RBY1', 1) + g('RBY4', 0)", "equivalent",
     "p is always the complete neutral() set plus the stage's values: the default is never used"),
    ("tyrefit/diagnose/stats.py", "rcond=2e-10, hermitian=True) @ sk)", "harmless",
     "the pseudo-inverse's cut-off at 2e-10 instead of 1e-10 of the largest singular value"),
    ("tyrefit/diagnose/engine.py", "if ratio < MISFIT_RATIO or eng.G < 6:", "tie",
     "a held-out RMSE of exactly MISFIT_RATIO x the noise floor"),
    # the same seed on the code of d316ab8 (fit_pac89 bounds=, fit_mf initial=): new sites
    ("tyrefit/fitting/engine.py", "hi = max(self.hi, 0.002)", "harmless",
     "a floor on the largest load [kN] behind the b5/c5 bounds; rig loads are hundreds of times larger"),
    ("tyrefit/fitting/engine.py", "'a4': (0.002,", "harmless", "a4's lower bound at 2e-3 kN instead of 1e-3 kN"),
    ("tyrefit/fitting/engine.py", "C, E_law = (spec.core[1], spec.curvature)", "harmless",
     "the multi-start's extra starts vary a1 instead of C; the Eq. 2-4 start is among them and the lowest cost wins"),
    ("tyrefit/fitting/mf_contract.py", "np.sign(float(base.get('PKY1', -1.0))) / np.sign(A)", "equivalent",
     "A is the grid of +-2, 3, 4 deg, never 0: dividing by sign(A) = +-1 is multiplying by it"),
    ("tyrefit/fitting/mf_contract.py", "np.sign(float(base.get('PKY1', 1.0)))", "equivalent",
     "the default is never used: every _Problem base is fit_mf's p, mf61.neutral() (which has PKY1) plus the "
     "stage's values, and _contract_grid is called only from _Problem"),
    ("tyrefit/fitting/mf.py", "if last[0] is None and (not np.array_equal(last[0], th))", "equivalent",
     "the cache is always current: r_start = residual(th0) fills it before solve, and SciPy's trf (1.17) asks "
     "for J only at the point it has just evaluated (trf.py: fun then jac at x0; jac after accepting x_new)"),
    ("tyrefit/fitting/mf_initial.py", "np.geomspace(0.6, 20.0, 60)", "harmless", "the lower end of PKY2's start grid"),
    ("tyrefit/fitting/mf_contract.py", "math.pi - phase + 0 / fz", "equivalent",
     "0 / fz = 0 * fz = 0 on the positive loads"),
    # the same seed on the code of 8140e13 (diagnose's speed work: lm_normal_batch, sequential screening)
    ("tyrefit/fitting/core.py", "if rel < tol or dx <= tol:", "tie", "a step of exactly tol x the parameter scale"),
    ("tyrefit/fitting/core.py", "np.maximum(old_cost, 2e-300)", "harmless",
     "the guard against a zero cost in the relative fall: differs only for a cost below 2e-300"),
    ("tyrefit/diagnose/stats.py", "if Tb.shape[1] <= n_boot and decided(T, Tb, alpha):", "equivalent",
     "Tb reaches n_boot draws only after the last block, where the loop ends whether it breaks or not"),
    ("tyrefit/diagnose/stats.py", "np.floor(alpha * (B + 1))) - 2, 1)]", "harmless",
     "the critical value's order statistic moves only where alpha (draws + 1) < 3 (never at 499+ draws and "
     "alpha >= 0.01), and only the detectable size it reports"),
    ("tyrefit/diagnose/stats.py", "np.count_nonzero(min_boot <= p_obs.min())", "tie",
     "a draw's min-p within 1e-9 (relative) of the observed one"),
    ("tyrefit/diagnose/stats.py", "np.searchsorted(min_boot, p_obs, side='right')", "tie",
     "a draw's min-p within 1e-9 (relative) of a candidate's own p-value"),
    ("tyrefit/diagnose/engine.py", "evaluated[i][1].rmse_heldout <= evaluated[best[f]][1].rmse_heldout", "tie",
     "two variants of one family with bitwise-equal held-out RMSE"),
    ("tyrefit/diagnose/engine.py", "(lv[d.level_index[f]] - np.mean(lv)) * np.ptp(lv)", "equivalent",
     "scales a group's directions by ptp(lv)^2 > 0: the score statistic, its draws and the stopping point are "
     "invariant to a column's scale (the end check's JSON byte-identical on 9 records, helper-20)"),
    # the same seed on the code of 8d66ef5 (engine.py's dead fallback gone: its sample redrawn)
    ("tyrefit/fitting/engine.py", "np.abs(d.y))), 2e-12)", "harmless",
     "the robust cost's noise scale when the data show no noise (pooled floor 0): 1e-3 x the largest |F| "
     "either way unless every |F| is below 2e-9 N, data with no tyre force in them"),
    # the same seed on the code of bb25c64 (engine.py and mf.py changed by 2be0732, one problem class; engine.py
    # by bed5945, point_scatter): new sites
    ("tyrefit/fitting/engine.py", "if cost in ('l1', *ROBUST_LOSSES) or len(theta):", "harmless",
     "an l2 fit is solved once more (l2, default tol) from its polished minimum: the cost moves by 2e-11 "
     "(relative), coefficients by <= 5e-5 (relative, well inside their standard errors), nfev by 3 (lateral "
     "example); a robust fit with nothing varied solves an empty problem (0 evaluations, same coefficients)"),
    ("tyrefit/fitting/engine.py", "if best is None or obj <= best[0]:", "tie",
     "two starts ending at bitwise-equal l2 objectives: the later one is polished instead"),
    ("tyrefit/fitting/mf.py", "if not obj <= obj0:", "tie",
     "a joint polish ending at a cost bitwise equal to its start's is kept instead of dropped"),
    ("tyrefit/fitting/mf_initial.py", "np.geomspace(0.3, 20.0, 120)", "harmless",
     "a finer grid (120 instead of 60 values) for the PKY2 start of the Fy0 stage: a start value"),
    ("tyrefit/fitting/mf.py", "np.round(np.median(sp), 4)", "harmless",
     "LONGVL, the reference speed, written to 1e-4 instead of 1e-2 m/s; the speed terms are fitted against "
     "whichever reference is written with them"),
    ("tyrefit/fitting/mf_contract.py", "(g('PDX1', 0) + g('PDX2', 0)", "equivalent",
     "p is always the complete neutral() set plus the stage's values: the default is never used"),
    ("tyrefit/fitting/mf_contract.py", "g('RBX3', 1) * gamma ** 2", "equivalent",
     "p is always the complete neutral() set plus the stage's values: the default is never used"),
    ("tyrefit/fitting/mf_eval.py", "p0[k] is not v or p0[k] != v", "equivalent",
     "the fallback after a TypeError is never reached: fit_mf's mapping and every stage's values are floats "
     "(float() on neutral(), nominal, initial=, fixed=, theta), so p.items() - p0.items() never fails "
     "(never entered in tests/test_fit_mf.py, test_fit_params.py, test_fit_mf_speed.py, "
     "test_mutants_sampled_fit.py)"),
    # the same seed on the code of 8b5c2bc (diagnose's speed-up, issue 24 build item 8: stats.py, core.py,
    # pac89.py, engine.py changed): new sites
    ("tyrefit/diagnose/stats.py", "np.linalg.pinv(X[tr], rcond=2e-10).T", "harmless",
     "the held-out null's per-fold pseudo-inverse cut at 2e-10 instead of 1e-10 of the largest singular value "
     "(the unit columns of a model's Jacobian: well-conditioned directions are far above both)"),
    ("tyrefit/fitting/core.py", "0.0, M) - held[:, None, :] * eye", "equivalent",
     "a held parameter's row and column are zeroed and its right-hand side is 0: a pivot of -1 instead of +1 "
     "gives the same h = 0 there and leaves the free parameters' system untouched"),
    ("tyrefit/fitting/core.py", "if lam > 20000000000.0:", "harmless",
     "lm_normal gives up at a damping of 2e10 instead of 1e10: at most one more trial step, of ~1e-10 of a "
     "parameter's scale, which ends the fit as converged either way"),
    ("tyrefit/diagnose/engine.py", "if mf['odd_share'] > 0.5 else", "tie",
     "a misfit whose odd and even parts in slip have exactly equal mean squares (odd share exactly 0.5)"),
    # --sample 60 --seed 15 over fitting/mf.py and the four modules split from it (issue 27, code of 4b45581; 12
    # per file, the draw of the full run): the survivors tests/test_mutants_session12.py does not kill
    ("tyrefit/fitting/mf.py", "if secondary or want:", "harmless",
     "the runaway check (a term > 1000 x the largest measured value) run on every stage, not only Mx and My: "
     "only _drop_unfit reads it, for the moment channels (force stages' facts are never read); on the bundled "
     "TTC-style pair the Mz stages' largest term is 2.5 x the largest |Mz| (QCZ1), 400 x below the threshold; "
     "one more Jacobian per stage"),
    ("tyrefit/fitting/mf.py", "'RBY1': (0.0, 1000.0)", "harmless",
     "RBY1's upper bound at 1000 instead of 500: published sets 5-26 and the fits' starts 5-20, far from either"),
    ("tyrefit/fitting/mf.py", "if prob.y.size else 1", "equivalent",
     "_runaway runs only on a stage fitted on >= 10 points (every sweep keeps points in the polish problem): "
     "prob.y is never empty"),
    ("tyrefit/fitting/mf.py", "r0 = nominal.get('UNLOADED_RADIUS', 0.6)", "equivalent",
     "fit_mf's nominal always holds UNLOADED_RADIUS (its set starts from mf61.neutral(), which has it; tyre_info "
     "and fixed= only replace it), and _joint_polish is called from fit_mf only"),
    ("tyrefit/fitting/mf.py", "if 'fy' in pts or np.isfinite(pts['fy']", "harmless",
     "the Mz0 start estimate (_initial_mz) also made when the Mz0 sweeps carry 10 or fewer finite Fy (every MFData "
     "has an fy column): start values only (QDZ1 from the trail, 0.02 m when fewer than 5 points give one; "
     "typical QBZ1, QCZ1, QEZ1)"),
    ("tyrefit/fitting/mf.py", "(1.0 if cost != 'l2' else 1.0)", "equivalent", "both branches are 1.0"),
    ("tyrefit/fitting/mf.py", "self.base.get(k, 1)", "harmless",
     "_Problem.theta's start for a varied coefficient neither the start nor fit_mf's set holds (LMUV without its "
     "estimate, MF 5.2's PHY3: not in mf61.neutral()) at 1 instead of 0, a start value: an MF 5.2 Fy0 fit with "
     "PHY3 varied (cambers 0, 2, 4 deg) ends at PHY3 0.0333115 and the same objective to 1e-12 either way"),
    ("tyrefit/fitting/mf_identify.py", "initial=0.0) <= 0.25 * _DEG:", "tie",
     "the largest |camber| of the sweeps exactly 0.25 deg"),
    ("tyrefit/fitting/mf_contract.py", "kmax / S.ravel()", "equivalent", "S is +-1: kmax / S = kmax * S exactly"),
    ("tyrefit/fitting/mf_contract.py", "p0 = float(nominal.get('NOMPRES', 1)) or 1.0", "equivalent",
     "_grid's nominal is fit_mf's, which always holds NOMPRES (_nominal sets it): the default is never used"),
    ("tyrefit/fitting/mf_eval.py", "p0[k] is not v and p0[k] == v", "equivalent",
     "the fallback after a TypeError is never reached (see the 'p0[k] is not v or p0[k] != v' entry)"),
    ("tyrefit/fitting/mf_initial.py", "p0 = nominal.get('NOMPRES', 0.0) or 0", "harmless",
     "differs only when NOMPRES is 0 (fixed= NOMPRES 0, or pressures below 50 Pa, which round to 0), where the "
     "model's own dpi = (p - NOMPRES)/NOMPRES is undefined too; the mutant's infinite dpi drops out of the start "
     "regression (its ptp is nan)"),
    ("tyrefit/fitting/mf_initial.py", "pts[force].to_numpy(float) * pts['fz']", "harmless",
     "_orientation regresses F Fz instead of F / Fz on the slip near zero: Fz > 0 only reweights the points, the "
     "slope's sign (all it is for) is the same whenever the sweeps agree on the data's orientation"),
    ("tyrefit/fitting/mf_initial.py", "near = np.abs(x) <= 2", "harmless",
     "_orientation on every point (|alpha| <= 2 rad, or 2 / _DEG) instead of those within 2 deg: a Magic Formula "
     "Fy keeps the sign of alpha, so the whole sweep's slope has the near-zero sign (published set, one-sided "
     "sweeps to 12-45 deg at 0.5-2 FNOMIN: the same sign)"),
    ("tyrefit/fitting/mf_initial.py", "'QSX7': 1.0, 'QSX8'", "harmless",
     "an Mx multi-start value: the Mx stage starts from the variable projection instead whenever one of its linear "
     "coefficients is varied (QSX1 always is unless held by vary= or fixed=)"),
    ("tyrefit/fitting/mf_initial.py", "RCX1=1.0, REX1=1.0)", "harmless",
     "the high-B start of the combined Fx stage at REX1 = +1 (its bound, moved inside) instead of -1: one of three "
     "starts, the lowest cost wins"),
    ("tyrefit/fitting/mf_initial.py", "RBX1=6.0, RBX2=10.0", "harmless",
     "the low-B start of the combined Fx stage with RBX2 10 instead of 5: a start value"),
    ("tyrefit/fitting/mf_initial.py", "('RVY1', 0.04)", "harmless",
     "the combined Fy starts' RVY1 0.04 instead of 0.02 (a typical magnitude off the flat point 0): a start value"),
    # a fresh draw, --sample 264 --seed 16 on the code of 34d42b1: the survivors tests/test_mutants_session13.py
    # leaves (equivalent, ties, and the harmless: tolerances, caps, counters, start values, cosmetic)
    ("tyrefit/fitting/initial.py", "np.median(np.diff(z))) if len(z) > 1 else 1", "equivalent",
     "with <= 1 folded point len(v) // 15 = 0 sets the window to 3 whatever dz, and _smooth returns < 3 points "
     "as they are"),
    ("tyrefit/fitting/initial.py", "if C >= 1.0 + 1e-06 and B * x_m > 0:", "equivalent",
     "C > 1 only on Eq. 2's falling branch, where y_a < 0.98 D gives C >= 1.127"),
    ("tyrefit/fitting/core.py", "d[d < 0] = 1.0", "equivalent",
     "diag(A) holds squared column norms (>= 0); a zero one is an all-zero column, decoupled from the rest: solve "
     "fails and lstsq gives the same step (0 for that parameter; to rounding)"),
    ("tyrefit/models/mf61.py", "b.lmuy_p = A_MU * b.lmuy_s / (1.0 - (A_MU - 1.0)", "equivalent",
     "A_MU = 1 (module docstring): (A_MU - 1) lmuy_s = 0 either way"),
    ("tyrefit/diagnose/stats.py", "rng: np.random.Generator, n_boot: int=3998)", "equivalent",
     "score_test_groups' only caller (engine._omnibus) passes Settings.n_boot: the default is never used"),
    ("tyrefit/io/ttc.py", "[''] * (len(names_raw) + len(units_raw))", "equivalent",
     "extra empty units past the channels are never read (map_headers and the column loop take len(names))"),
    ("tyrefit/fitting/mf_eval.py", "if self.pure == 'alpha' and self.channel != 'fx':", "equivalent",
     "only Fx0 is pure 'alpha' (channel fx): on the plain path (mf_parts.FAST = False) it goes through forces() at "
     "alpha = 0, where G_xa = 1 exactly - the same Fx, slower (test_mutants_session12 checks both paths)"),
    ("tyrefit/rig/conversion.py", "if isinstance(o, float) or not math.isfinite(o):", "equivalent",
     "json.dumps calls default= only for what it cannot serialise: numpy scalars (handled first); Python floats, "
     "NaN included, never reach it (RIG.json's fields hold nothing else)"),
    ("tyrefit/io/segment.py", "if direction >= 0 and v >= x[imax]:", "tie",
     "a later slope-change candidate exactly equal to the running maximum; the cuts are the first centre crossing "
     "between turning points either way"),
    ("tyrefit/fitting/mf.py", "if best is None or obj <= best[0]:", "tie", "two starts of exactly the same cost"),
    ("tyrefit/fitting/mf_contract.py", "else bool(worst > -G_TOL)})", "tie", "a worst value of exactly -G_TOL"),
    ("tyrefit/rig/conversion.py", "np.where(np.abs(u) <= 1e-12, 1.0 / self.n", "tie",
     "|u| of exactly 1e-12, where f(u) = 1/n to 1e-24 either way"),
    ("tyrefit/fitting/engine.py", "nfev_total = 1", "harmless", "the part's model-evaluation count, one too many"),
    ("tyrefit/fitting/engine.py", "abs(s_['C'] - c_best) > 0.05]", "harmless",
     "the 'another minimum' note's threshold 0.05 in C instead of 5 % of C (0.065-0.08 for C = 1.3-1.65)"),
    ("tyrefit/fitting/initial.py", "if k <= 1 or len(y) <= 3:", "harmless",
     "start-value smoothing of a 3-point folded sweep (a 4-point sweep with one point at zero slip)"),
    ("tyrefit/fitting/initial.py", "np.geomspace(0.2 * fzk.min(), 40.0 * fzk.max(), 300)", "harmless",
     "the a4 start grid to 40 x instead of 20 x the largest load (300 nodes; a start value)"),
    ("tyrefit/io/readers.py", "round(x / _DEG, 6) for x in _group_levels(cond['camber']", "harmless",
     "camber levels of the data summary to 6 decimals of a degree instead of 3"),
    ("tyrefit/io/segment.py", "tol['fz'] = max(tol['fz'], 0.1 * fz_med)", "harmless",
     "load set-point tolerance 10 % instead of 5 % of the median load: closer levels merge, their sweeps are "
     "still cut at the slip cycles and kept"),
    ("tyrefit/io/segment.py", "cuts.append(int(e0 + cross[0] - 1)", "harmless",
     "a cycle cut 2 samples before its centre crossing: 2 samples near zero slip go to the neighbouring cycle of "
     "the same set point, every sample is kept"),
    ("tyrefit/fitting/core.py", "def at_bound(self, rel: float=2e-06)", "harmless",
     "'at its bound' within 2e-6 instead of 1e-6 of the bound"),
    ("tyrefit/fitting/mf.py", "'QSX7': (-2.0, 0.5, 0.5, 2.0)", "harmless",
     "the Mx start grid without its QSX7 = -0.5 node (-2, 0.5, 2 remain; start values)"),
    ("tyrefit/fitting/mf.py", "r = np.where(np.isfinite(r), r, 2000.0)", "harmless",
     "the residual of a non-finite model row is a large constant either way: the step is refused"),
    ("tyrefit/fitting/mf.py", "self.nfev += 0 + len(self.linear) - len(self.fixed)", "harmless",
     "the stage's evaluation count, one short per variable-projection call"),
    ("tyrefit/fitting/mf.py", "t[j] = t[j] + h if t[j] <= ub[j] else t[j] - h", "harmless",
     "a finite-difference step of ~1e-8 may cross an upper bound by less than itself"),
    ("tyrefit/fitting/mf_contract.py", "np.exp(np.clip(g('PKX3', 0) * dfz, -50, 50)) / (1 + g('PPX1'", "harmless",
     "K_x divided instead of multiplied by its pressure factor: the same sign, so K_x > 0 holds or breaks alike "
     "(only the 0.1 margin band scales, by a factor near 1 over a rig's pressures)"),
    ("tyrefit/fitting/mf_contract.py", "np.clip(g('PKX3', 0) * dfz, -100, 50)", "harmless",
     "exp(-50) = 2e-22 or smaller: K_x ~ 0 below the margin either way"),
    ("tyrefit/fitting/mf_eval.py", "if p.keys() == p0.keys():", "harmless",
     "the fast path's diff given up: the plain evaluation, the same values, slower"),
    ("tyrefit/fitting/mf_eval.py", "out = [k for k, _ in p.items()]", "harmless",
     "every name taken as changed: all coefficients rebuilt (or the plain path), the same values, slower"),
    ("tyrefit/fitting/mf_initial.py", "dpi = np.where(np.isfinite(pr), (pr - p0) / p0, 1)", "harmless",
     "start regression: sweeps without a pressure taken at 2 x NOMPRES instead of NOMPRES (start values)"),
    ("tyrefit/fitting/mf_initial.py", "if ok.sum() >= 5 else 0.04", "harmless",
     "the Mz0 start trail 0.04 instead of 0.02 m when < 5 points measure it (a start value)"),
    ("tyrefit/fitting/mf_initial.py", "np.ptp(vs[ok]) <= 0.002:", "harmless",
     "the LMUV start needs a slip-speed spread of 0.002 instead of 0.001 (a start value)"),
    ("tyrefit/fitting/mf_initial.py", "PPX3=float(c_mu[2] * mu0)", "harmless",
     "the PPX3 start multiplied instead of divided by mu0 ~ 1 (a start value; PPX3 is fitted)"),
    ("tyrefit/fitting/mf_initial.py", "PPX1=float(c_k[2] / max(c_k[1], 1.0))", "harmless",
     "the PPX1 start divided by the wrong regression coefficient (a start value; PPX1 is fitted)"),
    ("tyrefit/sim/allocator.py", "over_f = np.maximum(fx_f - self.front.upper, 1)", "harmless",
     "a constant added to the objective and a 1 N dead band at the front limit; fx_f is clipped to the limits "
     "after the search"),
    ("tyrefit/sim/allocator.py", "self._penalty * (over_f * 2 + over_r ** 2)", "harmless",
     "a linear instead of quadratic penalty beyond the front limit: the search stops at the limit instead of "
     "~fx / 1e4 beyond it, and fx_f is clipped to the limits after the search"),
    ("tyrefit/sim/allocator.py", "{'searches': 0, 'evaluations': 1}", "harmless",
     "the allocator's evaluation counter starts at 1 (a statistic in the scenario details)"),
    ("tyrefit/rig/patch.py", "if abs(f.pressure - p) <= 0.02 * f.pressure:", "harmless",
     "a pressure within 2 % instead of 1 % of a measured one takes that fit instead of the pressure law"),
    ("tyrefit/diagnose/engine.py", "for b in flagged_bins[:6]", "harmless",
     "the end check names up to 6 slip ranges instead of 3"),
    ("tyrefit/io/ttc.py", "found {lines[1][:120]!r}", "harmless",
     "the refused names line quoted to 120 characters instead of 60"),
    ("tyrefit/rig/conversion.py", "pars.add('n', 1.0, min=0.05, max=100.0", "harmless",
     "a bound on the relaxation-length ratio n at 100 instead of 50; calibrations give ~1-3"),
    ("tyrefit/rig/conversion.py", "p.add('E', 0.0, min=-20.0, max=1.0", "harmless",
     "the dynamic curves' curvature bound at -20 instead of -10; fitted E lie in -3..1"),
]

_OPS = {ast.Add: ast.Sub, ast.Sub: ast.Add, ast.Mult: ast.Div, ast.Div: ast.Mult, ast.Pow: ast.Mult}
_CMP = {ast.Lt: ast.LtE, ast.LtE: ast.Lt, ast.Gt: ast.GtE, ast.GtE: ast.Gt, ast.Eq: ast.NotEq, ast.NotEq: ast.Eq}


@dataclass
class Mutant:
    file: str
    site: int
    what: str
    line: int
    source: str = field(repr=False, default="")
    tests: list = field(default_factory=list)
    outcome: str = ""
    seconds: float = 0.0
    changed: str = ""  # the mutant's first changed line (unparsed), what KNOWN_SURVIVORS match
    known: tuple = ()  # (kind, why) of a matching KNOWN_SURVIVORS entry


def _docstring_ids(tree) -> set:
    ids = set()
    for node in ast.walk(tree):
        if isinstance(node, (ast.Module, ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef)) and node.body:
            first = node.body[0]
            if isinstance(first, ast.Expr) and isinstance(first.value, ast.Constant):
                ids.add(id(first.value))
    return ids


def _sites(tree) -> list[tuple[ast.AST, str, str]]:
    """(node, kind, description) of every mutable place, in a fixed (walk) order."""
    out = []
    skip = _docstring_ids(tree)
    for node in ast.walk(tree):
        if isinstance(node, ast.BinOp) and type(node.op) in _OPS:
            out.append((node, "op", f"{type(node.op).__name__} -> {_OPS[type(node.op)].__name__}"))
            if isinstance(node.op, (ast.Add, ast.Sub, ast.Mult)):
                out.append((node, "drop", f"{type(node.op).__name__}: right term deleted"))
        elif isinstance(node, ast.Compare) and len(node.ops) == 1 and type(node.ops[0]) in _CMP:
            out.append((node, "cmp", f"{type(node.ops[0]).__name__} -> {_CMP[type(node.ops[0])].__name__}"))
        elif isinstance(node, ast.BoolOp):
            out.append((node, "bool", f"{type(node.op).__name__} swapped"))
        elif isinstance(node, ast.UnaryOp) and isinstance(node.op, (ast.USub, ast.Not)):
            out.append((node, "unary", f"{type(node.op).__name__} dropped"))
        elif (isinstance(node, ast.Constant) and isinstance(node.value, (int, float))
              and not isinstance(node.value, bool) and id(node) not in skip):
            out.append((node, "const", f"constant {node.value!r} changed"))
    return out


class _Apply(ast.NodeTransformer):
    def __init__(self, target, kind):
        self.target, self.kind = target, kind

    def visit(self, node):
        node = self.generic_visit(node)
        if node is not self.target:
            return node
        k = self.kind
        if k == "op":
            node.op = _OPS[type(node.op)]()
        elif k == "drop":
            return node.left
        elif k == "cmp":
            node.ops = [_CMP[type(node.ops[0])]()]
        elif k == "bool":
            node.op = ast.Or() if isinstance(node.op, ast.And) else ast.And()
        elif k == "unary":
            return node.operand
        elif k == "const":
            v = node.value
            node.value = 1 if v == 0 else (0 if v == 1 else v * 2)
        return node


def mutants_of(root: Path, rel: str, k: int, seed: int) -> list[Mutant]:
    """A seeded sample of ``k`` mutants of file ``rel`` (the same for the same file contents' sites)."""
    text = (root / rel).read_text()
    tree = ast.parse(text)
    sites = _sites(tree)
    rng = random.Random(int(hashlib.sha256(f"{seed}:{rel}".encode()).hexdigest()[:12], 16))
    chosen = sorted(rng.sample(range(len(sites)), min(k, len(sites))))
    return [_mutant(text, rel, i) for i in chosen]


def _mutant(text: str, rel: str, i: int, original: list[str] | None = None) -> Mutant:
    """Sampled mutant number ``i`` (site index) of file ``rel`` whose source is ``text``."""
    t2 = ast.parse(text)
    node, kind, what = _sites(t2)[i]
    line = getattr(node, "lineno", 0)
    src = ast.unparse(ast.fix_missing_locations(_Apply(node, kind).visit(t2)))
    original = original if original is not None else ast.unparse(ast.parse(text)).splitlines()
    changed = next((b for a, b in zip(original, src.splitlines()) if a != b), "").strip()
    return Mutant(rel, i, what, line, src, TARGETS[rel], changed=changed)


def rerun_mutants(root: Path, rows: list[dict]) -> list[Mutant]:
    """The sampled mutants that survived a previous run (its JSON ``rows``), rebuilt from the code at ``root``.

    Raises
    ------
    StaleMutant
        A file changed since that run (its site no longer is the same mutation on the same line).
    """
    out, stale = [], []
    for r in rows:
        if r["outcome"] != "survived" or r["site"] < 0:
            continue
        m = _mutant((Path(root) / r["file"]).read_text(), r["file"], r["site"])
        if (m.what, m.line) != (r["what"], r["line"]):
            stale.append(f"{r['file']} site {r['site']}: was {r['what']} at line {r['line']}, now {m.what} at {m.line}")
        out.append(m)
    if stale:
        raise StaleMutant("the code changed since that run (rerun the full sample instead):\n  " + "\n  ".join(stale))
    return out


def known_survivor(m: Mutant) -> tuple:
    """(kind, why) of the :data:`KNOWN_SURVIVORS` entry matching a sampled mutant, or ()."""
    for f, fragment, kind, why in KNOWN_SURVIVORS:
        if f == m.file and m.changed and fragment in m.changed:
            return kind, why
    return ()


def _named_scenarios(root: Path):
    """The scenarios mutant: whatever exponent the code computes, use HPwizard's 0.15 instead."""
    text = (root / "tyrefit/sim/scenarios.py").read_text()
    for old, new in (("        fit = traction_from_data(data_path(\"sim\", \"braking_utqg.csv\")).fit\n",
                      "        raise OSError('bundled table unreadable')\n"),):
        if old in text:
            return old, new
    return None, None


class StaleMutant(SystemExit):
    """A named mutant whose text is not (exactly once) in the code: keep :data:`NAMED` in step with it."""


def named_mutants(root: Path, only=None) -> list[Mutant]:
    """The named mutants (those whose name contains one of ``only``, default all).

    Raises
    ------
    StaleMutant
        A selected mutant's text no longer matches the code (it would silently leave the score).
    """
    out, stale = [], []
    for name, rel, old, new, tests in NAMED:
        if only and not any(s.lower() in name.lower() for s in only):
            continue
        if old is None:
            old, new = _named_scenarios(root)
        text = (root / rel).read_text()
        if old is None or text.count(old) != 1:
            stale.append(f"{name} ({rel}: its text {'is not' if old is None or old not in text else 'is more than once'}"
                         " in the code)")
            continue
        line = text[: text.index(old)].count("\n") + 1
        out.append(Mutant(rel, -1, name, line, text.replace(old, new, 1), tests))
    if stale:
        raise StaleMutant("named mutants that no longer match the code (update benchmarks/mutation.py NAMED):\n  "
                          + "\n  ".join(stale))
    if only and not out:
        raise SystemExit(f"no named mutant matches {', '.join(only)}")
    return out


def _run_tests(work: Path, tests: list[str], timeout: float) -> tuple[str, float]:
    tests = [t for t in tests if (work / t).exists()]
    env = dict(os.environ, PYTHONPATH=str(work), PYTHONDONTWRITEBYTECODE="1", MPLBACKEND="Agg")
    t0 = time.perf_counter()
    try:
        r = subprocess.run([sys.executable, "-m", "pytest", "-x", "-q", "-p", "no:cacheprovider", "-m", "not slow",
                            *tests], cwd=work, env=env, capture_output=True, timeout=timeout)
    except subprocess.TimeoutExpired:
        return "killed (timeout)", time.perf_counter() - t0
    dt = time.perf_counter() - t0
    if r.returncode == 0:
        return "survived", dt
    if r.returncode == 5:  # no tests collected
        return "no tests", dt
    return "killed", dt


def _copy(root: Path, work: Path) -> None:
    for name in ("tyrefit", "tests", "data", "benchmarks"):
        if (root / name).exists():
            shutil.copytree(root / name, work / name, ignore=shutil.ignore_patterns("__pycache__", "*.pyc"))
    for name in ("pyproject.toml", "conftest.py"):
        if (root / name).exists():
            shutil.copy2(root / name, work / name)


def run(root: Path, sample: int, seed: int, named: bool, files=None, log=print, only=None, rerun=None) -> dict:
    """Score the sampled mutants (``sample`` > 0) and, with ``named`` or ``only``, the named ones.

    ``rerun``: the rows of a previous run's JSON; only its surviving sampled mutants are run (``sample`` and
    ``files`` are ignored) and the result scores that run's whole sample, those outcomes replaced (named
    mutants keep their previous outcomes).  A surviving sampled mutant that matches
    :data:`KNOWN_SURVIVORS` carries its reason; ``adjusted_score`` leaves the ones shown equivalent out.
    """
    root = Path(root).resolve()
    files = files or list(TARGETS)
    per_file = max(1, round(sample / len(files)))
    if rerun is not None:
        mutants = rerun_mutants(root, rerun)
    else:
        mutants = [m for rel in files for m in mutants_of(root, rel, per_file, seed)] if sample > 0 else []
    if named or only:
        mutants += named_mutants(root, only)
    with tempfile.TemporaryDirectory(prefix="tyrefit-mut-") as tmp:
        work = Path(tmp)
        _copy(root, work)
        env = dict(os.environ, PYTHONPATH=str(work))
        where = subprocess.run([sys.executable, "-c", "import tyrefit; print(tyrefit.__file__)"], cwd=work, env=env,
                               capture_output=True, text=True).stdout.strip()
        if not where.startswith(str(work)):
            raise SystemExit(f"mutants would not be imported: tyrefit resolves to {where}")
        base = {}
        for m in mutants:
            key = tuple(m.tests)
            if key not in base:
                outcome, dt = _run_tests(work, m.tests, timeout=3600)
                if outcome != "survived":
                    raise SystemExit(f"the unmutated tests {m.tests} do not pass ({outcome}); fix them first")
                base[key] = dt
                log(f"baseline {', '.join(m.tests)}: {dt:.1f} s")
        for m in mutants:
            if m.outcome:
                log(f"{m.file}:{m.line} {m.what}: {m.outcome}")
                continue
            path = work / m.file
            original = path.read_text()
            path.write_text(m.source)
            try:
                m.outcome, m.seconds = _run_tests(work, m.tests, timeout=3 * base[tuple(m.tests)] + 20)
            finally:
                path.write_text(original)
            log(f"{m.file}:{m.line} [{m.site}] {m.what}: {m.outcome} ({m.seconds:.1f} s)")
    for m in mutants:
        if m.outcome == "survived" and m.site >= 0:
            m.known = known_survivor(m)
    rows = [{"file": m.file, "line": m.line, "site": m.site, "what": m.what, "outcome": m.outcome,
             "seconds": round(m.seconds, 2), "changed": m.changed,
             **({"known": m.known[0], "why": m.known[1]} if m.known else {})} for m in mutants]
    if rerun is not None:  # the previous run's rows, the rerun ones replaced: the score of the whole sample
        new = {(r["file"], r["site"]): r for r in rows if r["site"] >= 0}
        rows = [new.get((r["file"], r["site"]), r) if r["site"] >= 0 else r for r in rerun]
    return {"root": str(root), "seed": seed, "sample": sample, "files": files, **score(rows), "rows": rows}


def score(rows: list[dict]) -> dict:
    """Killed / counted over ``rows`` (all, and the sampled ones alone), and the sampled score without the
    survivors :data:`KNOWN_SURVIVORS` shows equivalent (``adjusted_score``)."""
    counted = [r for r in rows if r["outcome"].startswith(("killed", "survived"))]
    killed = sum(r["outcome"].startswith("killed") for r in counted)
    sampled = [r for r in counted if r["site"] >= 0]
    k_s = sum(r["outcome"].startswith("killed") for r in sampled)
    equivalent = sum(1 for r in sampled if r["outcome"] == "survived" and r.get("known") == "equivalent")
    return {"score": killed / len(counted) if counted else float("nan"), "killed": killed, "mutants": len(counted),
            "sampled_score": k_s / len(sampled) if sampled else float("nan"), "sampled_killed": k_s,
            "sampled_mutants": len(sampled), "equivalent": equivalent,
            "adjusted_score": k_s / (len(sampled) - equivalent) if len(sampled) > equivalent else float("nan")}


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--root", default=".", help="repository to mutate (default: here)")
    ap.add_argument("--sample", type=int, default=40, help="mutants sampled over the target files")
    ap.add_argument("--seed", type=int, default=15)
    ap.add_argument("--named", action="store_true", help="also run the named mutants (issues 15 and 25)")
    ap.add_argument("--only", default="", help="comma-separated name fragments: run just the named mutants whose "
                    "name contains one (with --sample 0, nothing else)")
    ap.add_argument("--files", default="", help="comma-separated subset of the target files")
    ap.add_argument("--json", default="", help="write the rows here")
    ap.add_argument("--rerun", default="", help="a previous run's --json: run only its surviving sampled mutants "
                    "and score the whole sample (the previous outcomes of the others)")
    a = ap.parse_args(argv)
    files = [f for f in a.files.split(",") if f] or None
    only = [s for s in a.only.split(",") if s] or None
    rerun = json.loads(Path(a.rerun).read_text())["rows"] if a.rerun else None
    res = run(Path(a.root), a.sample, a.seed, a.named, files, only=only, rerun=rerun)
    print(f"mutation score {res['score']:.3f} ({res['killed']}/{res['mutants']} killed); sampled mutants "
          f"{res['sampled_score']:.3f} ({res['sampled_killed']}/{res['sampled_mutants']}); without the "
          f"{res['equivalent']} shown equivalent {res['adjusted_score']:.3f}")
    for r in res["rows"]:
        if r["outcome"] == "survived":
            print(f"  survived: {r['file']}:{r['line']} {r['what']}: {r['changed'][:70]}"
                  + (f"\n      {r['known']}: {r['why']}" if "known" in r else ""))
    if a.json:
        Path(a.json).write_text(json.dumps(res, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
