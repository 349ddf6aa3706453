"""``tyrefit compare A.tir B.tir [--data DATA] [--report DIR] [--json OUT.json]``.

Compares two tyre files (any family :func:`tyrefit.tyres.read_tyre` reads) load by load --
cornering stiffness, peak friction coefficient, slip angle at the peak, mean
|dmu|/mu_peak over 0-12 deg -- and every other channel both tyres carry (Fx, Mz, Mx; the
skipped ones named with the reason) and, with ``--data``, each against measured slip-angle
or slip-ratio sweeps (:func:`tyrefit.compare.tyres.compare_tyres`).  JSON keys as in
``shared/DESIGN.md``, plus ``channels`` and ``channels_skipped``.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np

from ..io.outputs import write_text
from .outputs import check_outputs
from ..compare.tyres import compare_tyres
from ..io.readers import read_data
from ..io.report import Report
from ..io.tir import read_tyre  # every family (PAC89, MF 5.2, MF 6.1/6.2) behind the Tyre interface
from ..tyres.base import require_physical  # unphysical over the declared range: refused unless allowed

__all__ = ["run"]


def _json_default(o):
    if hasattr(o, "item"):
        return o.item()
    if isinstance(o, float) and not math.isfinite(o):
        return None
    return str(o)


def _clean(o):
    """Replace NaN/inf by None (strict JSON)."""
    if isinstance(o, float):
        return o if math.isfinite(o) else None
    if isinstance(o, dict):
        return {k: _clean(v) for k, v in o.items()}
    if isinstance(o, (list, tuple)):
        return [_clean(v) for v in o]
    if hasattr(o, "item"):
        return _clean(o.item())
    return o


def _g(v, fmt=".4g") -> str:
    return "-" if v is None or (isinstance(v, float) and not math.isfinite(v)) else format(v, fmt)


def _channel_line(ch: str, rows: list, names) -> str:
    """One console line per compared channel: its key numbers a / b at the first and last load, worst score."""
    first, last = rows[0], rows[-1]

    def ab(row, key, fmt=".4g"):
        return f"{_g(row[key][0], fmt)} / {_g(row[key][1], fmt)}"

    if ch == "fx":
        score = max((r["mean_abs_dmu_over_peak"] for r in rows), default=float("nan"))
        txt = "; ".join(f"Fz {r['fz'] / 1e3:.3g} kN: slip stiffness {ab(r, 'slip_stiffness')} N, peak mu_x "
                        f"{ab(r, 'peak_mu', '.3f')} at kappa {ab(r, 'slip_at_peak', '.3f')}" for r in (first, last))
        txt += f"; worst mean |dmu_x|/mu_peak {100 * score:.2f} %"
    elif ch == "mz":
        score = max((r["mean_abs_diff_over_peak"] for r in rows), default=float("nan"))
        txt = "; ".join(f"Fz {r['fz'] / 1e3:.3g} kN: peak Mz {ab(r, 'peak_mz')} N·m at "
                        f"{ab(r, 'slip_at_peak_deg', '.1f')} deg, trail {ab(r, 'pneumatic_trail_at_zero', '.4f')} m" for r in (first, last))
        txt += f"; worst mean |dMz|/Mz_peak {100 * score:.2f} %"
    else:
        score = max((r["mean_abs_diff_over_range"] for r in rows), default=float("nan"))
        txt = "; ".join(f"Fz {r['fz'] / 1e3:.3g} kN: Mx {_g(r['mx_range'][0][0])}..{_g(r['mx_range'][0][1])} / "
                        f"{_g(r['mx_range'][1][0])}..{_g(r['mx_range'][1][1])} N·m" for r in (first, last))
        txt += f"; worst mean |dMx|/range {100 * score:.2f} %"
    d = [r["data"] for r in rows if "data" in r]
    if d:
        n = np.array([x["points"] for x in d], float)
        rm = np.array([x["rmse"] for x in d], float)
        tot = np.sqrt((n[:, None] * rm ** 2).sum(0) / n.sum())
        txt += f"; vs data RMSE {tot[0]:.4g} / {tot[1]:.4g} {d[0]['unit']}"
    return txt


def run(args) -> int:
    """Entry point of ``tyrefit compare``."""
    check_outputs(args)
    ta = read_tyre(args.tyre_a)
    tb = read_tyre(args.tyre_b)
    for t in (ta, tb):  # how a file that does not declare its family was read (no [MODEL] section)
        for note in t.file_notes:
            print(f"warning: {note}")

    for path, tyre in ((args.tyre_a, ta), (args.tyre_b, tb)):
        require_physical(tyre, str(path), allow_unphysical=getattr(args, "allow_unphysical", False))
    data = None
    if args.data:
        data = read_data(args.data, convention=args.convention or "iso")
    na, nb = Path(args.tyre_a).stem, Path(args.tyre_b).stem
    if na == nb:
        na, nb = str(args.tyre_a), str(args.tyre_b)
    cmp = compare_tyres(ta, tb, data, names=(na, nb))
    doc = _clean(cmp.to_json())
    doc["files"] = [str(args.tyre_a), str(args.tyre_b)]
    if args.json:
        write_text(args.json, json.dumps(doc, indent=2, default=_json_default, allow_nan=False) + "\n",
                   force=args.force)
    if args.report:
        r = Report(f"tyrefit compare: {na} vs {nb}",
                   f"tyrefit compare {args.tyre_a} {args.tyre_b}" + (f" --data {args.data}" if args.data else ""))
        cmp.report_section(r, title="Load by load")
        r.json_block(doc, "JSON")
        r.save(args.report, force=args.force)
    s = cmp.summary()
    print(f"{na} vs {nb}: {len(cmp.loads)} loads; worst mean |dmu|/mu_peak {100 * s['worst_mean_abs_dmu_over_peak']:.2f} % "
          f"(agreement >= {s['min_agreement_pct']:.1f} %)")
    if "rmse_N" in s:
        print(f"  vs data: lateral RMSE {s['rmse_N'][0]:.4g} N / {s['rmse_N'][1]:.4g} N, within-sweep noise floor "
              f"{s['noise_floor_N']:.4g} N (the definitions of fit and diagnose)")
    for lc in cmp.loads:
        line = (f"  {lc.conditions}: C_alpha {lc.cornering_stiffness[0]:.4g} / {lc.cornering_stiffness[1]:.4g} N/rad, "
                f"peak mu {lc.peak_text(0)} / {lc.peak_text(1)}, mean |dmu|/mu_peak "
                f"{100 * lc.mean_abs_dmu_over_peak:.2f} %")
        if lc.data is not None:
            v = lc.data["mean_abs_dmu_over_peak_vs_data"]
            line += f"; vs data {100 * v[0]:.2f} % / {100 * v[1]:.2f} %"
        print(line)
    for ch, rows in cmp.channels.items():
        if ch == "fy":
            continue
        print(f"  {ch}: " + _channel_line(ch, rows, cmp.names))
    for n in cmp.notes:
        print(f"  note: {n}")
    if args.json:
        print(f"wrote {args.json}")
    if args.report:
        print(f"wrote {Path(args.report) / 'index.html'}")
    return 0
