"""Writing ``tyrefit eval``'s output CSV: :func:`tyrefit.commands.eval.csv_text` vs ``DataFrame.to_csv``.

200,000 rows of 4 input and 5 output float columns (the shape of ``eval`` at 200k
points with fz, slip angle, slip ratio, camber in, Fx, Fy, Mz, Mx, My out).  The
baseline is what ``eval`` did before, ``to_csv(float_format='%.10g')`` (10
significant digits, not round-trip), and pandas' own round-trip default
(``float_format=None``) is a second baseline.  Both texts are checked to read
back (``csv_text`` exactly).
"""

from __future__ import annotations

import io

import numpy as np
import pandas as pd

from . import best_of, measurement

ROWS = 200_000


def frame(n: int = ROWS, seed: int = 0) -> pd.DataFrame:
    rng = np.random.default_rng(seed)
    cols = {"fz [N]": rng.uniform(500.0, 12000.0, n), "slip_angle [deg]": rng.uniform(-12, 12, n),
            "slip_ratio [-]": rng.uniform(-0.3, 0.3, n), "camber [deg]": rng.uniform(-3, 3, n)}
    for k in ("fx [N]", "fy [N]", "mz [N*m]", "mx [N*m]", "my [N*m]"):
        cols[k] = rng.normal(0.0, 3000.0, n)
    return pd.DataFrame(cols)


def run() -> dict:
    from tyrefit.commands.eval import csv_text

    df = frame()
    t_new, text = best_of(lambda: csv_text(df), repeat=2)
    t_old, _ = best_of(lambda: df.to_csv(index=False, lineterminator="\n", float_format="%.10g"), repeat=2)
    t_pd, _ = best_of(lambda: df.to_csv(index=False, lineterminator="\n"), repeat=2)
    exact = bool(np.array_equal(pd.read_csv(io.StringIO(text)).to_numpy(), df.to_numpy()))
    return {"measurements": [
        measurement(f"eval CSV write, {ROWS} rows x 9 floats (csv_text)", t_new, "to_csv(float_format='%.10g')",
                    t_old, notes=f"round trip exact: {exact}"),
        measurement(f"eval CSV write, {ROWS} rows x 9 floats (csv_text)", t_new, "to_csv() (pandas round-trip "
                    "default)", t_pd),
    ]}
