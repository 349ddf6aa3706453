"""Evaluating a Magic Formula 6.1 tyre: vectorised vs a plain per-point loop.

The tyre is MFeval's MF 6.1 example (``tests/data/mfeval_MagicFormula61_Paramerters.tir``);
the points are 1,000,000 random combined-slip operating points inside its ranges
(load 500-12000 N, slip ratio +-0.3, slip angle +-12 deg, camber +-0.1 rad,
pressure 200-360 kPa, speed 3-30 m/s).  The measurement is one call of
:func:`tyrefit.models.mf61.forces` on all of them; the baseline is the same
function called once per point in a Python loop.  The loop is timed on the
first ``LOOP_POINTS`` points and scaled linearly to the full count (it is
linear in the number of points; timing it on 1M points would take minutes) -
the notes say so.  ``TYREFIT_BENCH_FULL=1`` times the loop on 10x more points.

When the ``tyrefit eval`` command is present, a second row times the command
end to end (CSV in, CSV out) on the same points against the same scaled loop.
"""

from __future__ import annotations

import tempfile
from pathlib import Path

import numpy as np

from . import best_of, full, measurement

POINTS = 1_000_000
LOOP_POINTS = 2_000
TIR = Path(__file__).resolve().parent.parent / "tests" / "data" / "mfeval_MagicFormula61_Paramerters.tir"


def _tir_values(path: Path) -> dict:
    """The coefficients of a .tir through tyrefit's own reader."""
    from tyrefit.io.tir import read_tyre

    return dict(read_tyre(path).params)


def points(n: int, seed: int = 0) -> dict[str, np.ndarray]:
    """``n`` random combined-slip operating points (SI)."""
    rng = np.random.default_rng(seed)
    return {"fz": rng.uniform(500.0, 12000.0, n), "slip_ratio": rng.uniform(-0.3, 0.3, n),
            "slip_angle": np.radians(rng.uniform(-12.0, 12.0, n)), "camber": rng.uniform(-0.1, 0.1, n),
            "pressure": rng.uniform(200e3, 360e3, n), "speed": rng.uniform(3.0, 30.0, n)}


def run() -> dict:
    from tyrefit.models import mf61

    p = _tir_values(TIR)
    x = points(POINTS)
    n_loop = LOOP_POINTS * (10 if full() else 1)

    def vectorised():
        return mf61.forces(p, x["fz"], x["slip_ratio"], x["slip_angle"], x["camber"], x["pressure"], x["speed"])

    def loop():
        out = np.empty((n_loop, 5))
        for i in range(n_loop):
            r = mf61.forces(p, x["fz"][i], x["slip_ratio"][i], x["slip_angle"][i], x["camber"][i],
                            x["pressure"][i], x["speed"][i])
            out[i] = (r["fx"], r["fy"], r["mz"], r["mx"], r["my"])
        return out

    t_vec, r = best_of(vectorised, repeat=3)
    t_loop, r_loop = best_of(loop, repeat=1)
    t_loop_scaled = t_loop * POINTS / n_loop
    same = all(np.allclose(r[ch][:n_loop], r_loop[:, j], rtol=1e-12, atol=1e-9)
               for j, ch in enumerate(("fx", "fy", "mz", "mx", "my")))
    rows = [measurement(f"mf61.forces, {POINTS:,} points vectorised", t_vec,
                        f"per-point Python loop over mf61.forces ({n_loop:,} points timed, scaled x{POINTS // n_loop})",
                        t_loop_scaled, points=POINTS, loop_points=n_loop, loop_seconds_measured=t_loop,
                        loop_equals_vectorised=bool(same),
                        points_per_second=POINTS / t_vec)]
    info = {"tyre": str(TIR.name), "points": POINTS}

    try:  # the eval command (another engineer's work) - timed end to end when it exists
        import contextlib
        import io

        import pandas as pd

        from tyrefit.cli import main as cli_main

        with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(io.StringIO()):
            try:
                probe = cli_main(["eval", "--help"])
            except SystemExit as exc:
                probe = exc.code
        if probe not in (0, None):
            raise ImportError("no 'tyrefit eval' command in this tree")
        with tempfile.TemporaryDirectory() as tmp:
            tmp = Path(tmp)
            table = pd.DataFrame({"fz [N]": x["fz"], "slip_ratio [-]": x["slip_ratio"],
                                  "slip_angle [rad]": x["slip_angle"], "camber [rad]": x["camber"],
                                  "pressure [Pa]": x["pressure"], "speed [m/s]": x["speed"]})
            table.to_csv(tmp / "points.csv", index=False)

            def cli():
                return cli_main(["eval", str(TIR), "--points", str(tmp / "points.csv"), "--out",
                                 str(tmp / "forces.csv"), "--force"])

            code = cli()
            if code == 0:
                t_cli, _ = best_of(cli, repeat=1)
                rows.append(measurement(f"tyrefit eval CLI, {POINTS:,} points (CSV in, CSV out)", t_cli,
                                        "same scaled per-point loop (model only, no I/O)", t_loop_scaled,
                                        points=POINTS))
            else:
                info["eval_cli"] = f"tyrefit eval exited {code}; not timed"
    except (ImportError, SystemExit) as exc:  # pragma: no cover - depends on the eval command's presence
        info["eval_cli"] = f"not timed: {exc.__class__.__name__}: {exc}"
    return {"measurements": rows, "info": info}


if __name__ == "__main__":  # pragma: no cover
    import json

    print(json.dumps(run(), indent=1, default=str))
