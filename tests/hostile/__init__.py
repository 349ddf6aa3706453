"""A corpus of hostile and odd-but-legitimate inputs, run against every command.

Each :class:`Case` builds its files in a fresh folder (seeded generators, no
downloads), runs the *installed* ``tyrefit`` command line as a subprocess with
a timeout, and is judged on four counts:

* **traceback** - exit code other than 0 and 2, or ``Traceback`` on stderr;
* **hang** - the timeout expired;
* **data lost** - a file that existed before the run (in the case folder or
  the bundled data it reads) changed or disappeared, other than the outputs
  the case means to replace (``may_change``); or an error run left a new file
  behind (a partial output);
* **silently wrong** - an accepted input (exit 0) whose output fails the
  case's plausibility check (a fitted tyre against the generating curve, the
  JSON's numbers against physics), or a refused input whose one stderr line
  does not name the problem (``expect`` pattern).

Expected outcomes are ``ok`` (exit 0, check passes) or ``error`` (exit 2,
exactly one stderr line matching ``pattern``).  ``python -m tests.hostile``
runs the whole corpus and prints the table; ``tests/test_hostile.py`` runs a
fast subset in the default tier and the full corpus in the slow tier.

The synthetic lateral-force data come from a Magic Formula written out here
(Pacejka, *Tire and Vehicle Dynamics*, 3rd ed., Eq. 4.49), not from
tyrefit's own model code, so a check of a fitted tyre against them is
independent of the fitter.
"""

from __future__ import annotations

import hashlib
import json
import math
import os
import re
import resource
import stat
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
DATA = ROOT / "data"
TYREFIT = str(Path(sys.executable).parent / "tyrefit")
SEED = 20261125

# --------------------------------------------------------------------------- generators

#: truth of the generated tyre: peak mu at 4 kN, load sensitivity, shape C, curvature E, K/Fz [1/rad]
TRUTH = {"mu0": 1.05, "dmu": -0.08, "C": 1.35, "E": -0.4, "k": 18.0}
LOADS = (2000.0, 4000.0, 6000.0)


def mf_fy(alpha, fz, truth=TRUTH):
    """ISO-W lateral force [N] of the generating tyre (Pacejka 2012 Eq. 4.49 with D = mu(Fz) Fz).

    Positive slip angle gives negative force (ISO-W, DESIGN.md).
    """
    mu = truth["mu0"] * (1 + truth["dmu"] * (fz - 4000.0) / 4000.0)
    d = mu * fz
    b = truth["k"] / (truth["C"] * mu)  # B = K / (C D) with K = k Fz
    b = b * np.ones_like(np.asarray(fz, float))
    x = b * alpha
    return -d * np.sin(truth["C"] * np.arctan(x - truth["E"] * (x - np.arctan(x))))


def peak_mu(fz, truth=TRUTH):
    return truth["mu0"] * (1 + truth["dmu"] * (fz - 4000.0) / 4000.0)


def sweeps_frame(loads=LOADS, n=41, span_deg=12.0, noise=0.01, seed=SEED, camber=False):
    """Tidy table of slip-angle sweeps: run, slip_angle [deg], fy [N], fz [N] (ISO-W)."""
    rng = np.random.default_rng(seed)
    rows = []
    for r, fz in enumerate(loads):
        a = np.linspace(-span_deg, span_deg, n)
        fy = mf_fy(np.radians(a), fz) + noise * fz * rng.standard_normal(n)
        fzm = fz + 0.01 * fz * rng.standard_normal(n)
        for i in range(n):
            rows.append((r, a[i], fy[i], fzm[i]))
    return np.array(rows)


def sweeps_csv(header=("run", "slip_angle [deg]", "fy [N]", "fz [N]"), scale=(1, 1, 1, 1), delim=",", eol="\n",
               arr=None, fmt="{:.6g}", **kw) -> str:
    arr = sweeps_frame(**kw) if arr is None else arr
    lines = [delim.join(header)]
    for row in arr:
        lines.append(delim.join(fmt.format(v * s) if j else str(int(v)) for j, (v, s) in enumerate(zip(row, scale))))
    return eol.join(lines) + eol


def record_csv(n_per=600, warmup_negative=1, seed=SEED) -> str:
    """A continuous logged record (time, no run column): warm-up, three loads, two sine sweeps each."""
    rng = np.random.default_rng(seed)
    t, sa, fz = [], [], []
    dt = 0.01
    # warm-up: tyre lowered onto the belt, first sample(s) slightly negative (a transient)
    wu = np.linspace(-30.0, 0.0, 50)
    wu[warmup_negative:] = np.abs(wu[warmup_negative:]) * 0 + np.linspace(5, 60, 50 - warmup_negative)
    for v in wu:
        t.append(len(t) * dt), sa.append(0.0), fz.append(v)
    for load in LOADS:
        for k in range(n_per):
            t.append(len(t) * dt)
            sa.append(12.0 * math.sin(2 * math.pi * k / (n_per / 2)))
            fz.append(load + 0.01 * load * rng.standard_normal())
        for k in range(60):  # move to the next load: unloaded between tests
            t.append(len(t) * dt), sa.append(0.0), fz.append(20.0 + rng.standard_normal())
    sa, fz = np.array(sa), np.array(fz)
    fy = mf_fy(np.radians(sa), np.maximum(fz, 0)) + 0.01 * np.maximum(fz, 0) * rng.standard_normal(sa.size)
    lines = ["time [s],slip_angle [deg],fy [N],fz [N]"]
    lines += [f"{a:.3f},{b:.4f},{c:.2f},{d:.2f}" for a, b, c, d in zip(t, sa, fy, fz)]
    return "\n".join(lines) + "\n"


def tydex_text(arr=None) -> str:
    """A TYDEX file (fixed columns of 10; a new sweep per load) of the sweeps."""
    arr = sweeps_frame() if arr is None else arr

    def chan(code, desc, unit):
        return f"{code:<10}{desc:<30}{unit:<10}{'1':<10}{'0':<10}{'0':<10}"
    out = ["**HEADER", f"{'RELEASE':<10}{'Release':<30}1.3", "**CONSTANTS", "**MEASURCHANNELS",
           chan("SLIPANGL", "slip angle", "deg"), chan("FYW", "lateral force", "N"), chan("FZW", "load", "N"),
           "**MEASURDATA"]
    out += [f"{a:10.4f}{b:10.2f}{c:10.2f}" for _r, a, b, c in arr]
    out.append("**END")
    return "\n".join(out) + "\n"


def read_tyre(path):
    from tyrefit.io.tir import read_tir

    return read_tir(path)


def tyre_matches_truth(path, tol=0.12) -> tuple[bool, str]:
    """The fitted tyre's Fy(alpha) at the three loads against the generating curve (RMS / peak < tol)."""
    t = read_tyre(path)
    errs = []
    for fz in LOADS:
        a = np.radians(np.linspace(-12, 12, 49))
        y = mf_fy(a, fz)
        yh = np.asarray(t.fy(np.full_like(a, fz), a, 0.0), float)
        errs.append(float(np.sqrt(np.mean((yh - y) ** 2)) / (peak_mu(fz) * fz)))
    e = max(errs)
    return e < tol, f"curve error {e:.3f} of peak"


def json_has(path, *keys) -> Callable[[Path], tuple[bool, str]]:
    def check(d: Path):
        doc = json.loads((d / path).read_text())
        missing = [k for k in keys if k not in doc]
        return not missing, f"missing {missing}" if missing else "keys present"
    return check


# --------------------------------------------------------------------------- cases

@dataclass
class Case:
    """One corpus case: files to make, a command line, the expected outcome."""

    name: str
    command: str                     # the command it exercises (for the table)
    argv: list[str]                  # arguments after 'tyrefit'; {d} is the case folder, {data} the bundled data
    files: dict[str, bytes | str | Callable] = field(default_factory=dict)  # name -> content (or maker(path))
    expect: str = "error"            # 'ok' or 'error'
    pattern: str = ""                # regex the stderr line must match (error cases)
    check: Callable | None = None    # ok cases: check(folder) -> (bool, why)
    may_change: tuple[str, ...] = ()  # pre-existing files the case means to replace
    timeout: float = 120.0
    fsize: int | None = None         # RLIMIT_FSIZE for the run [bytes] (disk full / File too large)
    writes_on_error: bool = False    # a batch writes its summary even when a file fails
    fast: bool = False               # in the default test tier
    origin: str = ""                 # 'issue 15' for the issue's cases verbatim


def _w(text):
    return text


def _fifo(path: Path):
    os.mkfifo(path)


def _dir(path: Path):
    path.mkdir()


def _symlink_to(target):
    def make(path: Path):
        os.symlink(target, path)
    return make


def _fit_ok(name="t.tir"):
    def check(d):
        return tyre_matches_truth(d / name)
    return check


def _fnomin(value):
    def check(d):
        t = read_tyre(d / "t.tir")
        ok = t.fnomin is not None and abs(t.fnomin - value) < 1e-6 * value
        return ok, f"FNOMIN {t.fnomin}"
    return check


def _compare_ok(d):
    doc = json.loads((d / "c.json").read_text())
    loads = doc.get("loads", [])
    ok = bool(loads) and all(0.2 < m < 3.0 for row in loads for m in row["peak_mu"]) and all(
        k > 0 for row in loads for k in row["cornering_stiffness"])
    return ok, f"{len(loads)} loads, peak mu {[row['peak_mu'] for row in loads][:2]}"


def _braking_ok(d):
    rows = json.loads((d / "s.json").read_text())["rows"]
    bad = [r for r in rows if not (0 < r["stopping_distance_m"] < 400 and 0 < r["max_deceleration_mps2"] < 15)]
    # physics: v^2 / (2 d) <= max deceleration, and a longer distance at a higher speed
    return not bad and len(rows) >= 6, f"{len(rows)} rows, {len(bad)} implausible"


def _slip_ok(d):
    doc = json.loads((d / "s.json").read_text())
    items = doc.get("loads", [doc])
    ok = all(0.3 < x["mu_peak"] < 2.5 and 0 < x["characteristic_slip"] < 0.5 for x in items)
    return ok, f"mu_peak {[round(x['mu_peak'], 3) for x in items]}"


def _traction_ok(d):
    doc = json.loads((d / "t.json").read_text())
    return isinstance(doc, dict) and len(doc) > 0, "json written"


def _adhesion_ok(mu):
    def check(d):
        doc = json.loads((d / "a.json").read_text())
        est = doc["estimates"]
        ok = all(abs(e - mu) / mu < 0.25 for e in est)
        return ok, f"estimates {[round(e, 3) for e in est]} vs {mu}"
    return check


def _inspect_ok(kind):
    def check(d):
        doc = json.loads((d / "i.json").read_text())
        return doc.get("kind") == kind, f"kind {doc.get('kind')}"
    return check


def _exists(*names):
    def check(d):
        miss = [n for n in names if not (d / n).exists()]
        return not miss, f"missing {miss}" if miss else "written"
    return check


def _and(*checks):
    def check(d):
        whys = []
        for c in checks:
            ok, why = c(d)
            whys.append(why)
            if not ok:
                return False, "; ".join(whys)
        return True, "; ".join(whys)
    return check


def _unchanged(name, content):
    def check(d):
        p = d / name
        ok = p.exists() and p.read_bytes() == (content.encode() if isinstance(content, str) else content)
        return ok, f"{name} kept" if ok else f"{name} changed"
    return check


GOOD = sweeps_csv()
BOM = "\ufeff"


def _cases_fit() -> list[Case]:
    C = []
    ok = _fit_ok()
    add = C.append
    add(Case("fit clean sweeps", "fit", ["fit", "{d}/d.csv", "--out", "{d}/t.tir"], {"d.csv": GOOD}, "ok",
             check=ok, fast=True))
    add(Case("fit CSV with UTF-8 BOM", "fit", ["fit", "{d}/d.csv", "--out", "{d}/t.tir"], {"d.csv": BOM + GOOD},
             "ok", check=ok, origin="issue 15"))
    add(Case("fit CRLF line ends", "fit", ["fit", "{d}/d.csv", "--out", "{d}/t.tir"],
             {"d.csv": sweeps_csv(eol="\r\n")}, "ok", check=ok))
    add(Case("fit semicolon delimiter", "fit", ["fit", "{d}/d.csv", "--out", "{d}/t.tir"],
             {"d.csv": sweeps_csv(delim=";")}, "ok", check=ok))
    add(Case("fit tab delimiter", "fit", ["fit", "{d}/d.tsv", "--out", "{d}/t.tir"],
             {"d.tsv": sweeps_csv(delim="\t")}, "ok", check=ok))
    add(Case("fit loads in kN labelled [kN]", "fit", ["fit", "{d}/d.csv", "--out", "{d}/t.tir"],
             {"d.csv": sweeps_csv(header=("run", "slip_angle [deg]", "fy [kN]", "fz [kN]"),
                                  scale=(1, 1, 1e-3, 1e-3))}, "ok", check=ok))
    add(Case("fit slip in rad labelled [rad]", "fit", ["fit", "{d}/d.csv", "--out", "{d}/t.tir"],
             {"d.csv": sweeps_csv(header=("run", "slip_angle [rad]", "fy [N]", "fz [N]"),
                                  scale=(1, math.pi / 180, 1, 1))}, "ok", check=ok))
    add(Case("fit header spelling 'Slip Angle [deg]', 'FZ [N]'", "fit", ["fit", "{d}/d.csv", "--out", "{d}/t.tir"],
             {"d.csv": sweeps_csv(header=("run", "Slip Angle [deg]", "FY [N]", "FZ [N]"))}, "ok", check=ok))
    add(Case("fit comment lines and blank lines", "fit", ["fit", "{d}/d.csv", "--out", "{d}/t.tir"],
             {"d.csv": "# rig: flat-track\n\n# tyre: test\n" + GOOD.replace("\n", "\n\n", 3)}, "ok", check=ok))
    add(Case("fit TYDEX file", "fit", ["fit", "{d}/d.tdx", "--out", "{d}/t.tir"], {"d.tdx": tydex_text()}, "ok",
             check=ok))
    add(Case("fit TYDEX with BOM", "fit", ["fit", "{d}/d.tdx", "--out", "{d}/t.tir"],
             {"d.tdx": BOM + tydex_text()}, "ok", check=ok, origin="issue 15"))
    add(Case("fit bundled FSAE TTC .dat (SAE)", "fit",
             ["fit", "{data}/ttc/fsae_cornering.dat", "--convention", "sae", "--out", "{d}/t.tir"], {}, "ok",
             check=_exists("t.tir"), timeout=240))
    add(Case("fit TTC .dat with UTF-8 BOM", "fit", ["fit", "{d}/r.dat", "--convention", "sae", "--out",
             "{d}/t.tir"], {"r.dat": lambda p: p.write_bytes(b"\xef\xbb\xbf" + (DATA / "ttc/fsae_cornering.dat")
                                                              .read_bytes())}, "ok", check=_exists("t.tir"),
             timeout=240, origin="issue 15"))
    add(Case("fit record with one negative-load warm-up sample", "fit",
             ["fit", "{d}/r.csv", "--out", "{d}/t.tir"], {"r.csv": record_csv(warmup_negative=1)}, "ok",
             check=_fit_ok(), origin="issue 15", timeout=240))
    add(Case("fit record with five Fz <= 0 warm-up samples", "fit",
             ["fit", "{d}/r.csv", "--out", "{d}/t.tir"], {"r.csv": record_csv(warmup_negative=5)}, "ok",
             check=_fit_ok(), timeout=240))
    add(Case("fit loads in kN labelled [N]", "fit", ["fit", "{d}/d.csv", "--out", "{d}/t.tir"],
             {"d.csv": sweeps_csv(scale=(1, 1, 1, 1e-3))}, "error", r"kN", origin="issue 15", fast=True))
    add(Case("fit forces in kN labelled [N]", "fit", ["fit", "{d}/d.csv", "--out", "{d}/t.tir"],
             {"d.csv": sweeps_csv(scale=(1, 1, 1e-3, 1))}, "error", r"(?i)mu|friction|kN"))
    arr = sweeps_frame()
    arr0 = arr.copy()
    arr0[:, 2] = 0.0
    add(Case("fit lateral force stuck at zero", "fit", ["fit", "{d}/d.csv", "--out", "{d}/t.tir"],
             {"d.csv": sweeps_csv(arr=arr0)}, "error", r"(?i)constant|stuck", origin="issue 15", fast=True))
    arrc = arr.copy()
    arrc[:, 2] = 1234.5
    add(Case("fit lateral force stuck at a constant", "fit", ["fit", "{d}/d.csv", "--out", "{d}/t.tir"],
             {"d.csv": sweeps_csv(arr=arrc)}, "error", r"(?i)constant|stuck"))
    arrf = arr.copy()
    arrf[:, 2] *= -1
    add(Case("fit sign-flipped lateral force", "fit", ["fit", "{d}/d.csv", "--out", "{d}/t.tir"],
             {"d.csv": sweeps_csv(arr=arrf)}, "error", r"(?i)sign", origin="issue 15"))
    arrm = arr.copy()
    arrm[arrm[:, 0] == 1, 2] *= -1
    add(Case("fit sweeps of opposite sign", "fit", ["fit", "{d}/d.csv", "--out", "{d}/t.tir"],
             {"d.csv": sweeps_csv(arr=arrm)}, "error", r"(?i)opposite|sign"))
    ramp = sweeps_frame(loads=tuple(np.linspace(1500, 7000, 40)), n=15)
    ramp[:, 3] = np.linspace(1500, 7000, len(ramp))  # the load rises through the file: never held
    add(Case("fit load ramp with 40 distinct loads", "fit", ["fit", "{d}/d.csv", "--out", "{d}/t.tir"],
             {"d.csv": sweeps_csv(arr=ramp)}, "error", r"(?i)distinct|conditions|levels", origin="issue 15"))
    rng = np.random.default_rng(SEED + 7)
    tiny = np.column_stack([np.arange(20000), rng.uniform(-1, 1, 20000), rng.normal(0, 50, 20000),
                            rng.uniform(2000, 6000, 20000)])
    add(Case("fit 20,000 tiny sweeps", "fit", ["fit", "{d}/d.csv", "--out", "{d}/t.tir"],
             {"d.csv": sweeps_csv(arr=tiny)}, "error", r"(?i)sweep", origin="issue 15", timeout=180))
    long_space = "run,slip_angle [deg],fy [N],fz" + " " * 5000 + "[N]\n" + "\n".join(GOOD.splitlines()[1:40]) + "\n"
    add(Case("fit header cell with a 5000-space run (old hang)", "fit", ["fit", "{d}/d.csv", "--out", "{d}/t.tir"],
             {"d.csv": long_space}, "ok", check=_exists("t.tir"), origin="issue 15", timeout=60, fast=True))
    long_space2 = "run,slip_angle [deg],fy [N],fz" + " " * 5000 + "x\n" + "\n".join(GOOD.splitlines()[1:40]) + "\n"
    add(Case("fit header run of spaces, bad name", "fit", ["fit", "{d}/d.csv", "--out", "{d}/t.tir"],
             {"d.csv": long_space2}, "error", r"(?i)column|fz", timeout=60, fast=True))
    bracket = "run,slip_angle [deg],fy [N],fz [" + " " * 5000 + "\n" + "\n".join(GOOD.splitlines()[1:40]) + "\n"
    add(Case("fit header unclosed bracket and spaces", "fit", ["fit", "{d}/d.csv", "--out", "{d}/t.tir"],
             {"d.csv": bracket}, "error", r"(?i)column|unit|fz", timeout=60))
    lines = GOOD.splitlines()
    add(Case("fit NaN cell", "fit", ["fit", "{d}/d.csv", "--out", "{d}/t.tir"],
             {"d.csv": "\n".join(lines[:5] + ["0,1.0,nan,3000"] + lines[5:]) + "\n"}, "error", r"(?i)finite|nan"))
    add(Case("fit inf cell", "fit", ["fit", "{d}/d.csv", "--out", "{d}/t.tir"],
             {"d.csv": "\n".join(lines[:5] + ["0,1.0,inf,3000"] + lines[5:]) + "\n"}, "error", r"(?i)finite|inf"))
    add(Case("fit empty cell", "fit", ["fit", "{d}/d.csv", "--out", "{d}/t.tir"],
             {"d.csv": "\n".join(lines[:5] + ["0,1.0,,3000"] + lines[5:]) + "\n"}, "error", r"(?i)empty|finite"))
    add(Case("fit text in a number column", "fit", ["fit", "{d}/d.csv", "--out", "{d}/t.tir"],
             {"d.csv": "\n".join(lines[:5] + ["0,1.0,abc,3000"] + lines[5:]) + "\n"}, "error", r"abc|number"))
    add(Case("fit decimal comma", "fit", ["fit", "{d}/d.csv", "--out", "{d}/t.tir"],
             {"d.csv": sweeps_csv(delim=";").replace(".", ",")}, "error", r"(?i)number|decimal|comma|cell"))
    add(Case("fit ragged row", "fit", ["fit", "{d}/d.csv", "--out", "{d}/t.tir"],
             {"d.csv": "\n".join(lines[:5] + ["0,1.0,-100"] + lines[5:]) + "\n"}, "error", r"cells"))
    add(Case("fit column given twice", "fit", ["fit", "{d}/d.csv", "--out", "{d}/t.tir"],
             {"d.csv": GOOD.replace("run,", "fz [kN],", 1)}, "error", r"(?i)twice|duplicate|fz"))
    add(Case("fit missing fz column", "fit", ["fit", "{d}/d.csv", "--out", "{d}/t.tir"],
             {"d.csv": "\n".join(",".join(r.split(",")[:3]) for r in lines) + "\n"}, "error", r"(?i)fz|column"))
    add(Case("fit unknown unit [furlong]", "fit", ["fit", "{d}/d.csv", "--out", "{d}/t.tir"],
             {"d.csv": GOOD.replace("fz [N]", "fz [furlong]", 1)}, "error", r"furlong"))
    add(Case("fit unit of the wrong dimension", "fit", ["fit", "{d}/d.csv", "--out", "{d}/t.tir"],
             {"d.csv": GOOD.replace("fz [N]", "fz [deg]", 1)}, "error", r"deg"))
    add(Case("fit slip angle over 90 deg", "fit", ["fit", "{d}/d.csv", "--out", "{d}/t.tir"],
             {"d.csv": sweeps_csv(scale=(1, 10, 1, 1))}, "error", r"(?i)slip"))
    add(Case("fit SAE data without --convention sae", "fit", ["fit", "{d}/d.csv", "--out", "{d}/t.tir"],
             {"d.csv": sweeps_csv(scale=(1, -1, -1, -1))}, "error", r"(?i)convention sae"))
    add(Case("fit SAE data with --convention sae", "fit",
             ["fit", "{d}/d.csv", "--convention", "sae", "--out", "{d}/t.tir"],
             {"d.csv": sweeps_csv(scale=(1, -1, -1, -1))}, "ok", check=ok))
    add(Case("fit one sweep, 5 points", "fit", ["fit", "{d}/d.csv", "--out", "{d}/t.tir"],
             {"d.csv": "\n".join(lines[:6]) + "\n"}, "error", r"(?i)too few|points"))
    add(Case("fit all slip zero", "fit", ["fit", "{d}/d.csv", "--out", "{d}/t.tir"],
             {"d.csv": sweeps_csv(scale=(1, 0, 1, 1))}, "error", r"(?i)variation|slip"))
    add(Case("fit only a header", "fit", ["fit", "{d}/d.csv", "--out", "{d}/t.tir"],
             {"d.csv": lines[0] + "\n"}, "error", r"(?i)no data"))
    add(Case("fit only comments", "fit", ["fit", "{d}/d.csv", "--out", "{d}/t.tir"],
             {"d.csv": "# nothing\n# here\n"}, "error", r"(?i)header|comment"))
    add(Case("fit UTF-16 file", "fit", ["fit", "{d}/d.csv", "--out", "{d}/t.tir"],
             {"d.csv": lambda p: p.write_bytes(GOOD.encode("utf-16"))}, "error", r"(?i)binary|UTF-16|text"))
    add(Case("fit Latin-1 comment", "fit", ["fit", "{d}/d.csv", "--out", "{d}/t.tir"],
             {"d.csv": lambda p: p.write_bytes("# Prüfstand Müller\n".encode("latin-1") + GOOD.encode())}, "ok",
             check=ok))
    add(Case("fit a .tir given as data", "fit", ["fit", "{data}/sim/hard_front.tir", "--out", "{d}/t.tir"], {},
             "error", r"(?i)tyre property file"))
    add(Case("fit a JSON given as data", "fit", ["fit", "{d}/x.json", "--out", "{d}/t.tir"],
             {"x.json": '{"a": 1}\n'}, "error", r"(?i)json"))
    add(Case("fit a ZIP given as data", "fit", ["fit", "{d}/x.csv", "--out", "{d}/t.tir"],
             {"x.csv": lambda p: p.write_bytes(b"PK\x03\x04" + bytes(200))}, "error", r"(?i)zip|binary"))
    add(Case("fit patch data given as data", "fit", ["fit", "{data}/truck/tyre_a_patch.csv", "--out", "{d}/t.tir"],
             {}, "error", r"(?i)cannot be fitted|patch"))
    # numeric flags
    for v, pat in (("nan", "rated"), ("-5", "rated"), ("inf", "rated"), ("0", "rated"), ("1e12", "rated")):
        add(Case(f"fit --rated-load {v}", "fit", ["fit", "{d}/d.csv", "--rated-load", v, "--out", "{d}/t.tir"],
                 {"d.csv": GOOD}, "error", pat, origin="issue 15" if v in ("nan", "-5") else "",
                 fast=v == "nan"))
    add(Case("fit --rated-load 4000 (FNOMIN)", "fit",
             ["fit", "{d}/d.csv", "--rated-load", "4000", "--out", "{d}/t.tir"], {"d.csv": GOOD}, "ok",
             check=_and(ok, _fnomin(4000.0))))
    add(Case("fit --rated-load abc", "fit", ["fit", "{d}/d.csv", "--rated-load", "abc", "--out", "{d}/t.tir"],
             {"d.csv": GOOD}, "error", r"invalid float|rated"))
    add(Case("fit --max-size 0.001 on a 7 KB file", "fit",
             ["fit", "{d}/d.csv", "--max-size", "0.001", "--out", "{d}/t.tir"], {"d.csv": GOOD}, "error",
             r"--max-size", fast=True))
    add(Case("fit --max-size nan", "fit", ["fit", "{d}/d.csv", "--max-size", "nan", "--out", "{d}/t.tir"],
             {"d.csv": GOOD}, "error", r"max-size"))
    add(Case("fit --max-size 1 on a 7 KB file", "fit",
             ["fit", "{d}/d.csv", "--max-size", "1", "--out", "{d}/t.tir"], {"d.csv": GOOD}, "ok", check=ok))
    add(Case("fit --out without .tir", "fit", ["fit", "{d}/d.csv", "--out", "{d}/t.txt"], {"d.csv": GOOD},
             "error", r"\.tir"))
    add(Case("fit --effects unknown", "fit", ["fit", "{d}/d.csv", "--effects", "warp_drive", "--out", "{d}/t.tir"],
             {"d.csv": GOOD}, "error", r"(?i)warp_drive|effect"))
    # outputs
    add(Case("fit --json IN.csv --force", "fit", ["fit", "{d}/d.csv", "--out", "{d}/t.tir", "--json", "{d}/d.csv",
                                                  "--force"], {"d.csv": GOOD}, "error", r"input",
             origin="issue 15", fast=True))
    add(Case("fit --out IN.csv --force", "fit", ["fit", "{d}/d.tir", "--out", "{d}/d.tir", "--force"],
             {"d.tir": GOOD}, "error", r"(?i)input|tyre property"))
    add(Case("fit --json hard link of the input", "fit",
             ["fit", "{d}/d.csv", "--out", "{d}/t.tir", "--json", "{d}/link.json", "--force"],
             {"d.csv": GOOD, "link.json": lambda p: os.link(p.parent / "d.csv", p)}, "error", r"input"))
    add(Case("fit --json symlink to the input", "fit",
             ["fit", "{d}/d.csv", "--out", "{d}/t.tir", "--json", "{d}/sl.json", "--force"],
             {"d.csv": GOOD, "sl.json": _symlink_to("d.csv")}, "error", r"input"))
    add(Case("fit --json equal to --out", "fit", ["fit", "{d}/d.csv", "--out", "{d}/t.tir", "--json", "{d}/t.tir"],
             {"d.csv": GOOD}, "error", r"(?i)twice|same", origin="issue 15", fast=True))
    add(Case("fit --out exists, no --force", "fit", ["fit", "{d}/d.csv", "--out", "{d}/t.tir"],
             {"d.csv": GOOD, "t.tir": "old tyre\n"}, "error", r"--force"))
    add(Case("fit --out exists, --force", "fit", ["fit", "{d}/d.csv", "--out", "{d}/t.tir", "--force"],
             {"d.csv": GOOD, "t.tir": "old tyre\n"}, "ok", check=ok, may_change=("t.tir",)))
    add(Case("fit --out names a folder, --force", "fit", ["fit", "{d}/d.csv", "--out", "{d}/o.tir", "--force"],
             {"d.csv": GOOD, "o.tir": _dir}, "error", r"(?i)folder", origin="issue 15"))
    add(Case("fit --out under a parent that is a file", "fit", ["fit", "{d}/d.csv", "--out", "{d}/f/t.tir"],
             {"d.csv": GOOD, "f": "x\n"}, "error", r"(?i)is a file", origin="issue 15"))
    add(Case("fit --out in a read-only place (/proc)", "fit", ["fit", "{d}/d.csv", "--out", "/proc/t.tir"],
             {"d.csv": GOOD}, "error", r"/proc", origin="issue 15"))
    add(Case("fit --out in /sys (read-only)", "fit", ["fit", "{d}/d.csv", "--out", "/sys/t.tir"],
             {"d.csv": GOOD}, "error", r"/sys"))
    add(Case("fit disk full (File too large), --force keeps old .tir", "fit",
             ["fit", "{d}/d.csv", "--out", "{d}/t.tir", "--force"], {"d.csv": GOOD, "t.tir": "old tyre\n"},
             "error", r"(?i)too large|t\.tir", fsize=2000, origin="issue 15"))
    add(Case("fit --report naming a file", "fit", ["fit", "{d}/d.csv", "--out", "{d}/t.tir", "--report", "{d}/r"],
             {"d.csv": GOOD, "r": "notes\n"}, "error", r"(?i)is a file", origin="issue 15"))
    add(Case("fit --force: failing --report keeps the earlier out.tir", "fit",
             ["fit", "{d}/d.csv", "--out", "{d}/t.tir", "--report", "{d}/r", "--force"],
             {"d.csv": GOOD, "t.tir": "earlier tyre\n", "r": "a file\n"}, "error", r"(?i)is a file",
             origin="issue 15", fast=True))
    add(Case("fit --force: failing --json keeps the earlier out.tir", "fit",
             ["fit", "{d}/d.csv", "--out", "{d}/t.tir", "--json", "{d}/f/c.json", "--force"],
             {"d.csv": GOOD, "t.tir": "earlier tyre\n", "f": "a file\n"}, "error", r"(?i)is a file",
             origin="issue 15"))
    add(Case("fit --report folder holding a user file", "fit",
             ["fit", "{d}/d.csv", "--out", "{d}/t.tir", "--report", "{d}/r"],
             {"d.csv": GOOD, "r": _dir, "r/notes.txt": "mine\n"}, "error", r"(?i)not empty|--force"))
    add(Case("fit --report user file kept with --force", "fit",
             ["fit", "{d}/d.csv", "--out", "{d}/t.tir", "--report", "{d}/r", "--force"],
             {"d.csv": GOOD, "r": _dir, "r/notes.txt": "mine\n"}, "ok",
             check=_and(ok, _exists("r/index.html"), _unchanged("r/notes.txt", "mine\n")), origin="issue 15"))
    add(Case("fit --report user's own index.html, --force", "fit",
             ["fit", "{d}/d.csv", "--out", "{d}/t.tir", "--report", "{d}/r", "--force"],
             {"d.csv": GOOD, "r": _dir, "r/index.html": "my page\n"}, "error", r"(?i)not written by tyrefit"))
    add(Case("fit --report user's own sweeps.csv, --force", "fit",
             ["fit", "{d}/d.csv", "--out", "{d}/t.tir", "--report", "{d}/r", "--force"],
             {"d.csv": GOOD, "r": _dir, "r/sweeps.csv": "my table\n"}, "error", r"(?i)not written by tyrefit"))
    add(Case("fit --report into the data's own folder, --force", "fit",
             ["fit", "{d}/d.csv", "--out", "{d}/t.tir", "--report", "{d}", "--force"],
             {"d.csv": GOOD}, "ok", check=_and(ok, _exists("index.html"))))
    add(Case("fit --json /dev/null --force", "fit", ["fit", "{d}/d.csv", "--out", "{d}/t.tir", "--json",
                                                     "/dev/null", "--force"], {"d.csv": GOOD}, "error", r"/dev|device"))
    add(Case("fit --json /dev/stdout", "fit", ["fit", "{d}/d.csv", "--out", "{d}/t.tir", "--json", "/dev/stdout",
                                               "--force"], {"d.csv": GOOD}, "error", r"(?i)regular file|device|FIFO"))
    add(Case("fit --json names a FIFO, --force", "fit", ["fit", "{d}/d.csv", "--out", "{d}/t.tir", "--json",
                                                         "{d}/p.json", "--force"], {"d.csv": GOOD, "p.json": _fifo},
             "error", r"FIFO"))
    add(Case("fit --out a symlink to a precious file, --force", "fit",
             ["fit", "{d}/d.csv", "--out", "{d}/link.tir", "--force"],
             {"d.csv": GOOD, "precious.txt": "keep\n", "link.tir": _symlink_to("precious.txt")}, "ok",
             check=_and(_fit_ok("link.tir"), _unchanged("precious.txt", "keep\n")), may_change=("link.tir",)))
    add(Case("fit --out a dangling symlink, no --force", "fit", ["fit", "{d}/d.csv", "--out", "{d}/dl.tir"],
             {"d.csv": GOOD, "dl.tir": _symlink_to("nowhere.tir")}, "error", r"--force"))
    add(Case("fit --out file name of 300 characters", "fit", ["fit", "{d}/d.csv", "--out", "{d}/" + "t" * 300 + ".tir"],
             {"d.csv": GOOD}, "error", r"(?i)too long"))
    add(Case("fit --out with spaces and unicode", "fit", ["fit", "{d}/d.csv", "--out", "{d}/Reifen ä 1.tir"],
             {"d.csv": GOOD}, "ok", check=_fit_ok("Reifen ä 1.tir")))
    add(Case("fit --out in a new nested folder", "fit", ["fit", "{d}/d.csv", "--out", "{d}/a/b/c/t.tir"],
             {"d.csv": GOOD}, "ok", check=_fit_ok("a/b/c/t.tir")))
    add(Case("fit --report in a new nested folder", "fit", ["fit", "{d}/d.csv", "--out", "{d}/t.tir", "--report",
                                                            "{d}/x/y/r"], {"d.csv": GOOD}, "ok",
             check=_and(ok, _exists("x/y/r/index.html"))))
    add(Case("fit two data files, --json is the second", "fit",
             ["fit", "{d}/d.csv", "{d}/e.csv", "--out", "{d}/t.tir", "--json", "{d}/e.csv", "--force"],
             {"d.csv": GOOD, "e.csv": sweeps_csv(seed=SEED + 5)}, "error", r"input"))
    add(Case("fit two data files with PAC89", "fit", ["fit", "{d}/d.csv", "{d}/e.csv", "--out", "{d}/t.tir"],
             {"d.csv": GOOD, "e.csv": sweeps_csv(seed=SEED + 5)}, "error", r"(?i)several|mf61"))
    add(Case("fit --patch is a FIFO", "fit", ["fit", "{d}/d.csv", "--patch", "{d}/p.csv", "--out", "{d}/t.tir"],
             {"d.csv": GOOD, "p.csv": _fifo}, "error", r"FIFO"))
    add(Case("fit data in the out folder is not touched by --report . --force", "fit",
             ["fit", "{d}/d.csv", "--out", "{d}/t.tir", "--report", "{d}", "--force"],
             {"d.csv": GOOD, "index.html": "my own page\n"}, "error", r"(?i)not written by tyrefit"))
    return C


def _input_cases(cmd: str, argv_tail: list[str], label: str) -> list[Case]:
    """Hostile input files for a command that reads FILE (the first argument)."""
    C = []
    for name, files, arg, pat, origin in (
            ("FIFO", {"in.csv": _fifo}, "{d}/in.csv", r"FIFO", "issue 15"),
            ("/dev/zero", {}, "/dev/zero", r"device", "issue 15"),
            ("/dev/null", {}, "/dev/null", r"device", ""),
            ("a folder", {"in": _dir}, "{d}/in", r"folder", ""),
            ("a missing file", {}, "{d}/missing.csv", r"no such file", ""),
            ("an empty file", {"in.csv": ""}, "{d}/in.csv", r"(?i)empty", ""),
            ("binary bytes", {"in.csv": lambda p: p.write_bytes(bytes(range(256)) * 8)}, "{d}/in.csv",
             r"(?i)binary", ""),
            ("a symlink loop", {"in.csv": _symlink_to("in.csv")}, "{d}/in.csv", r"(?i)in\.csv", "")):
        C.append(Case(f"{label}: {name}", cmd, [*argv_tail[:1], arg, *argv_tail[1:]], files, "error", pat,
                      origin=origin, timeout=30, fast=name == "FIFO" and cmd == "fit"))
    return C


def _cases_inputs() -> list[Case]:
    C = []
    C += _input_cases("fit", ["fit", "--out", "{d}/t.tir"], "fit data")
    C += _input_cases("inspect", ["inspect"], "inspect")
    C += _input_cases("diagnose", ["diagnose", "--json", "{d}/o.json"], "diagnose data")
    C += _input_cases("slip", ["slip"], "slip data")
    C += _input_cases("traction", ["traction"], "traction data")
    C += _input_cases("compare", ["compare", "{data}/sim/hard_front.tir"], "compare tyre B")
    for name, files, arg, pat in (("FIFO", {"f.tir": _fifo}, "{d}/f.tir", r"FIFO"),
                                  ("/dev/zero", {}, "/dev/zero", r"device"),
                                  ("a data CSV", {}, "{data}/sim/soft_tyre.csv", r"(?i)tyre|tir|PAC"),
                                  ("an empty .tir", {"f.tir": ""}, "{d}/f.tir", r"(?i)empty|tir"),
                                  ("a truncated .tir", {"f.tir": lambda p: p.write_text(
                                      (DATA / "sim/hard_front.tir").read_text()[:700])}, "{d}/f.tir",
                                   r"(?i)f\.tir")):
        C.append(Case(f"sim braking --front {name}", "sim", ["sim", "braking", "--front", arg, "--json",
                                                             "{d}/s.json"], files, "error", pat, timeout=60))
    for name, files, arg, pat in (("FIFO", {"p.csv": _fifo}, "{d}/p.csv", r"FIFO"),
                                  ("/dev/zero", {}, "/dev/zero", r"device")):
        C.append(Case(f"rig calibrate --patch {name}", "rig calibrate",
                      ["rig", "calibrate", "--static", "{d}/s.csv", "--dynamic", "{data}/truck/tyre_a_dynamic.csv",
                       "--patch", arg, "--out", "{d}/rig.json"], {"s.csv": GOOD, **files}, "error", pat))
    C.append(Case("batch fit: source is a FIFO", "batch fit", ["batch", "fit", "{d}/in.csv", "--out", "{d}/o"],
                  {"in.csv": _fifo}, "error", r"FIFO"))
    return C


def _output_cases(cmd: str, argv: list[str], files: dict, label: str, json_name: str = "o.json",
                  report: bool = True, input_arg: str | None = None, ok_check=None, slow_ok: bool = False,
                  ok_timeout: float = 120.0, report_extra: tuple[str, ...] = ()) -> list[Case]:
    """Output hazards for a command with ``--json`` (and ``--report``)."""
    C = []
    j = "{d}/" + json_name
    if input_arg:
        C.append(Case(f"{label}: --json is the input, --force", cmd, [*argv, "--json", input_arg, "--force"],
                      files, "error", r"input"))
    C.append(Case(f"{label}: --json exists, no --force", cmd, [*argv, "--json", j], {**files, json_name: "{}\n"},
                  "error", r"--force"))
    C.append(Case(f"{label}: --json under a file", cmd, [*argv, "--json", "{d}/f/x.json"], {**files, "f": "x\n"},
                  "error", r"(?i)is a file"))
    C.append(Case(f"{label}: --json names a folder, --force", cmd, [*argv, "--json", "{d}/jd", "--force"],
                  {**files, "jd": _dir}, "error", r"(?i)folder"))
    C.append(Case(f"{label}: --json in /proc", cmd, [*argv, "--json", "/proc/x.json"], files, "error", r"/proc"))
    if report:
        C.append(Case(f"{label}: --report names a file", cmd, [*argv, *report_extra, "--report", "{d}/r"],
                      {**files, "r": "x\n"},
                      "error", r"(?i)is a file", origin="issue 15" if cmd in ("fit", "sim") else ""))
        C.append(Case(f"{label}: --report holds a user file, no --force", cmd,
                      [*argv, *report_extra, "--report", "{d}/r"],
                      {**files, "r": _dir, "r/mine.txt": "mine\n"}, "error", r"(?i)not empty"))
        C.append(Case(f"{label}: --report equals --json", cmd, [*argv, "--json", "{d}/same", "--report", "{d}/same"],
                      files, "error", r"(?i)twice|same"))
    if ok_check is not None:
        C.append(Case(f"{label}: --json and --report, --force over an old run", cmd,
                      [*argv, "--json", j, *(["--report", "{d}/r"] if report else []), "--force"],
                      {**files, json_name: "{}\n", **({"r": _dir, "r/mine.txt": "mine\n"} if report else {})},
                      "ok", check=_and(ok_check, *([_unchanged("r/mine.txt", "mine\n")] if report else [])),
                      may_change=(json_name,), timeout=ok_timeout))
        C.append(Case(f"{label}: file too large, old --json kept", cmd, [*argv, "--json", j, "--force"],
                      {**files, json_name: "{}\n"}, "error", r"(?i)too large", fsize=20, timeout=ok_timeout))
    return C


def _cases_commands() -> list[Case]:
    C = []
    add = C.append
    tyres = ["{data}/sim/hard_front.tir", "{data}/sim/soft_rear.tir"]
    # compare
    add(Case("compare bundled tyres", "compare", ["compare", *tyres, "--json", "{d}/c.json"], {}, "ok",
             check=_compare_ok, fast=True))
    add(Case("compare with data", "compare", ["compare", *tyres, "--data", "{d}/d.csv", "--json", "{d}/c.json"],
             {"d.csv": GOOD}, "ok", check=_compare_ok))
    # slip-ratio (drive/brake) data score the tyres' Fx since compare covers every channel (issue 23)
    add(Case("compare with slip-ratio data", "compare", ["compare", *tyres, "--data", "{data}/sim/hard_tyre.csv",
                                                         "--json", "{d}/c.json"], {}, "ok", check=_compare_ok))
    add(Case("compare .tir with CRLF", "compare", ["compare", "{d}/a.tir", tyres[1], "--json", "{d}/c.json"],
             {"a.tir": (DATA / "sim/hard_front.tir").read_text().replace("\n", "\r\n")}, "ok", check=_compare_ok))
    add(Case("compare .tir with UTF-8 BOM", "compare", ["compare", "{d}/a.tir", tyres[1], "--json", "{d}/c.json"],
             {"a.tir": BOM + (DATA / "sim/hard_front.tir").read_text()}, "ok", check=_compare_ok,
             origin="issue 15"))
    add(Case("compare --data is a FIFO", "compare", ["compare", *tyres, "--data", "{d}/p.csv"], {"p.csv": _fifo},
             "error", r"FIFO"))
    add(Case("compare --json is tyre A, --force", "compare", ["compare", "{d}/a.tir", tyres[1], "--json",
                                                              "{d}/a.tir", "--force"],
             {"a.tir": (DATA / "sim/hard_front.tir").read_text()}, "error", r"input"))
    C += _output_cases("compare", ["compare", *tyres], {}, "compare", json_name="c.json",
                       ok_check=_compare_ok)
    # sim
    add(Case("sim braking default tyres", "sim", ["sim", "braking", "--json", "{d}/s.json"], {}, "ok",
             check=_braking_ok, timeout=180))
    add(Case("sim braking --front is --json, --force", "sim",
             ["sim", "braking", "--front", "{d}/f.tir", "--json", "{d}/f.tir", "--force"],
             {"f.tir": (DATA / "sim/hard_front.tir").read_text()}, "error", r"input"))
    C += _output_cases("sim braking", ["sim", "braking"], {}, "sim braking", json_name="s.json",
                       ok_check=_braking_ok, ok_timeout=180)
    def scenario_ok(d):
        rows = json.loads((d / "s.json").read_text())["rows"]
        bad = [r for r in rows if not (-100 <= r["reduction_pct"] <= 100 and 0 <= r["max_path_difference_m"] < 5
                                       and r["emission_base"] > 0 and r["emission_low_wear"] > 0)]
        return not bad and len(rows) >= 6, f"{len(rows)} rows, {len(bad)} implausible (reduction, path, emission)"
    add(Case("sim curved default tyres", "sim", ["sim", "curved", "--json", "{d}/s.json"], {}, "ok",
             check=scenario_ok, timeout=300))
    add(Case("sim straight with the bundled tyres given explicitly", "sim",
             ["sim", "straight", "--front", tyres[0], "--rear", tyres[1], "--json", "{d}/s.json"], {}, "ok",
             check=scenario_ok, timeout=300))
    add(Case("sim curved --report names a file", "sim", ["sim", "curved", "--report", "{d}/r"], {"r": "x\n"},
             "error", r"(?i)is a file", origin="issue 15"))
    add(Case("sim straight --json exists", "sim", ["sim", "straight", "--json", "{d}/s.json"], {"s.json": "{}"},
             "error", r"--force"))
    # sim adhesion
    for v, pat in (("nan", "road-mu"), ("7", "road-mu"), ("-1", "road-mu"), ("0", "road-mu"), ("inf", "road-mu")):
        add(Case(f"sim adhesion --road-mu {v}", "sim", ["sim", "adhesion", "--road-mu", v], {}, "error", pat))
    for v in ("nan", "90", "-inf"):
        add(Case(f"sim adhesion --camber {v}", "sim", ["sim", "adhesion", "--camber", v], {}, "error", "camber"))
    add(Case("sim adhesion mu 0.5", "sim", ["sim", "adhesion", "--road-mu", "0.5", "--json", "{d}/a.json"], {},
             "ok", check=_adhesion_ok(0.5), timeout=180))
    C += _output_cases("sim adhesion", ["sim", "adhesion"], {}, "sim adhesion", json_name="a.json")
    # slip
    slip = "{data}/slip/slip_ratio.csv"
    add(Case("slip bundled data", "slip", ["slip", slip, "--json", "{d}/s.json"], {}, "ok", check=_slip_ok))
    add(Case("slip data with BOM", "slip", ["slip", "{d}/s.csv", "--json", "{d}/s.json"],
             {"s.csv": BOM + (DATA / "slip/slip_ratio.csv").read_text()}, "ok", check=_slip_ok))
    add(Case("slip given slip-angle data", "slip", ["slip", "{d}/d.csv"], {"d.csv": GOOD}, "error",
             r"(?i)slip.ratio|longitudinal"))
    C += _output_cases("slip", ["slip", slip], {}, "slip", json_name="s.json", input_arg=None, ok_check=_slip_ok)
    add(Case("slip --json is the input, --force", "slip", ["slip", "{d}/s.csv", "--json", "{d}/s.csv", "--force"],
             {"s.csv": (DATA / "slip/slip_ratio.csv").read_text()}, "error", r"input"))
    # traction
    tr = "{data}/sim/braking_utqg.csv"
    add(Case("traction bundled data", "traction", ["traction", tr, "--json", "{d}/t.json"], {}, "ok",
             check=_traction_ok))
    add(Case("traction given slip-angle data", "traction", ["traction", "{d}/d.csv"], {"d.csv": GOOD}, "error",
             r"(?i)braking|stopping"))
    add(Case("traction --json is the input, --force", "traction",
             ["traction", "{d}/b.csv", "--json", "{d}/b.csv", "--force"],
             {"b.csv": (DATA / "sim/braking_utqg.csv").read_text()}, "error", r"input"))
    C += _output_cases("traction", ["traction", tr], {}, "traction", json_name="t.json", ok_check=_traction_ok)
    # inspect
    add(Case("inspect data --json", "inspect", ["inspect", "{d}/d.csv", "--json", "{d}/i.json"], {"d.csv": GOOD},
             "ok", check=_inspect_ok("data"), fast=True))
    add(Case("inspect tyre --json", "inspect", ["inspect", "{data}/sim/hard_front.tir", "--json", "{d}/i.json"], {},
             "ok", check=_inspect_ok("tyre")))
    add(Case("inspect --json is the file, --force", "inspect", ["inspect", "{d}/d.csv", "--json", "{d}/d.csv",
                                                                "--force"], {"d.csv": GOOD}, "error", r"input"))
    C += _output_cases("inspect", ["inspect", "{d}/d.csv"], {"d.csv": GOOD}, "inspect", json_name="i.json",
                       report=False, ok_check=_inspect_ok("data"))
    add(Case("inspect particles [#/km] without speed", "inspect", ["inspect", "{d}/e.csv"],
             {"e.csv": "fx [N],particles [#/km]\n500,1e6\n1000,4e6\n2000,1.6e7\n-500,2e6\n"}, "error",
             r"(?i)per (km|distance)|#/km", origin="issue 15"))
    add(Case("inspect particles [#/s]", "inspect", ["inspect", "{d}/e.csv", "--json", "{d}/i.json"],
             {"e.csv": "fx [N],particles [#/s]\n500,1e6\n1000,4e6\n2000,1.6e7\n-500,2e6\n"}, "ok",
             check=_inspect_ok("data")))
    # diagnose
    add(Case("diagnose --rated-load nan", "diagnose", ["diagnose", "{d}/d.csv", "--rated-load", "nan", "--json",
                                                       "{d}/o.json"], {"d.csv": GOOD}, "error", "rated"))
    add(Case("diagnose --seed -1", "diagnose", ["diagnose", "{d}/d.csv", "--seed", "-1", "--json", "{d}/o.json"],
             {"d.csv": GOOD}, "error", "seed"))
    add(Case("diagnose --json is the data, --force", "diagnose", ["diagnose", "{d}/d.csv", "--json", "{d}/d.csv",
                                                                  "--force"], {"d.csv": GOOD}, "error", "input"))
    add(Case("diagnose loads in kN labelled [N]", "diagnose", ["diagnose", "{d}/d.csv", "--json", "{d}/o.json"],
             {"d.csv": sweeps_csv(scale=(1, 1, 1, 1e-3))}, "error", "kN"))
    add(Case("diagnose slip-ratio data", "diagnose", ["diagnose", slip, "--json", "{d}/o.json"], {}, "error",
             r"(?i)lateral"))
    C += _output_cases("diagnose", ["diagnose", "{d}/d.csv"], {"d.csv": GOOD}, "diagnose", json_name="o.json",
                       report_extra=("--json", "{d}/x.json"))
    add(Case("diagnose clean sweeps", "diagnose", ["diagnose", "{d}/d.csv", "--json", "{d}/o.json", "--report",
                                                   "{d}/r"], {"d.csv": GOOD}, "ok",
             check=_and(json_has("o.json", "start", "accepted", "noise_floor", "steps", "candidates"),
                        _exists("r/index.html")), timeout=300))
    # several records, every channel, and the Magic Formula base (issue 24)
    ttc = ["{data}/ttc_mf61/cornering.dat", "{data}/ttc_mf61/drivebrake.dat", "--convention", "sae"]
    add(Case("diagnose cornering + drive/brake records", "diagnose", ["diagnose", *ttc, "--json", "{d}/o.json"], {},
             "ok", check=json_has("o.json", "start", "accepted", "noise_floor", "steps", "candidates", "channels"),
             timeout=300))
    add(Case("diagnose a record and a garbage file", "diagnose", ["diagnose", "{d}/d.csv", "{d}/x.csv", "--json",
                                                                  "{d}/o.json"], {"d.csv": GOOD, "x.csv": "\x00\xff garbage\n"},
             "error", r"x\.csv"))
    add(Case("diagnose drive/brake record alone", "diagnose", ["diagnose", "{data}/ttc_mf61/drivebrake.dat",
                                                               "--convention", "sae", "--json", "{d}/o.json"], {},
             "error", r"(?i)cornering record"))
    add(Case("diagnose --base mf61", "diagnose", ["diagnose", *ttc, "--base", "mf61", "--json", "{d}/o.json",
                                                  "--report", "{d}/r"], {}, "ok",
             check=_and(json_has("o.json", "start", "accepted", "noise_floor", "steps", "candidates", "channels",
                                 "held_neutral"), _exists("r/index.html")), timeout=300))
    add(Case("diagnose --base mf61 on static pushes", "diagnose", ["diagnose", "{data}/truck/tyre_a_static.csv",
                                                                   "--base", "mf61", "--json", "{d}/o.json"], {},
             "error", r"(?i)base"))
    add(Case("diagnose --base mf61 --start", "diagnose", ["diagnose", "{d}/d.csv", "--base", "mf61", "--start",
                                                          "camber", "--json", "{d}/o.json"], {"d.csv": GOOD},
             "error", r"--start"))
    add(Case("diagnose --base unknown", "diagnose", ["diagnose", "{d}/d.csv", "--base", "pac2002", "--json",
                                                     "{d}/o.json"], {"d.csv": GOOD}, "error", r"(?i)base"))
    # edge cases of the analysis commands
    arr0, arrf = sweeps_frame(), sweeps_frame()
    arr0[:, 2] = 0.0
    arrf[:, 2] *= -1
    one = "\n".join(GOOD.splitlines()[:42]) + "\n"  # one sweep
    add(Case("diagnose one sweep", "diagnose", ["diagnose", "{d}/d.csv", "--json", "{d}/o.json"], {"d.csv": one},
             "ok", check=json_has("o.json", "start", "accepted", "noise_floor", "steps", "candidates"), timeout=300))
    add(Case("diagnose lateral force stuck at zero", "diagnose", ["diagnose", "{d}/d.csv", "--json", "{d}/o.json"],
             {"d.csv": sweeps_csv(arr=arr0)}, "error", r"(?i)constant"))
    add(Case("diagnose sign-flipped data", "diagnose", ["diagnose", "{d}/d.csv", "--json", "{d}/o.json"],
             {"d.csv": sweeps_csv(arr=arrf)}, "error", r"(?i)sign"))
    add(Case("diagnose --start unknown effect", "diagnose", ["diagnose", "{d}/d.csv", "--start", "warp",
                                                             "--json", "{d}/o.json"], {"d.csv": GOOD}, "error",
             r"(?i)warp|effect"))
    slip_text = (DATA / "slip/slip_ratio.csv").read_text()
    sl = slip_text.splitlines()
    hdr = next(i for i, ln in enumerate(sl) if ln.startswith("run,"))
    cols = sl[hdr].split(",")
    fxi = cols.index("fx [N]")

    def with_fx(f):
        body = []
        for ln in sl[hdr + 1:]:
            c = ln.split(",")
            c[fxi] = f(float(c[fxi]))
            body.append(",".join(c))
        return "\n".join(sl[:hdr + 1] + body) + "\n"
    add(Case("slip fx stuck at zero", "slip", ["slip", "{d}/s.csv"], {"s.csv": with_fx(lambda v: "0")}, "error",
             r"(?i)constant"))
    add(Case("slip fx sign-flipped", "slip", ["slip", "{d}/s.csv"], {"s.csv": with_fx(lambda v: f"{-v:g}")},
             "error", r"(?i)sign"))
    add(Case("slip fx in kN labelled [N]", "slip", ["slip", "{d}/s.csv"],
             {"s.csv": with_fx(lambda v: f"{v / 1000:g}")}, "error", r"(?i)kN"))
    add(Case("slip slip ratio in percent", "slip", ["slip", "{d}/s.csv", "--json", "{d}/s.json"],
             {"s.csv": "\n".join(sl[:hdr] + [sl[hdr].replace("slip_ratio [-]", "slip_ratio [%]")] + [
                 ",".join(f"{float(x) * 100:g}" if j == cols.index("slip_ratio [-]") else x
                          for j, x in enumerate(ln.split(","))) for ln in sl[hdr + 1:]]) + "\n"}, "ok",
             check=_slip_ok))
    add(Case("slip a single sweep", "slip", ["slip", "{d}/s.csv", "--json", "{d}/s.json"],
             {"s.csv": "\n".join(sl[:hdr + 1] + [ln for ln in sl[hdr + 1:] if ln.split(",")[0] == sl[hdr + 1]
                                                  .split(",")[0]]) + "\n"}, "ok", check=_slip_ok))
    br = (DATA / "sim/braking_utqg.csv").read_text().splitlines()
    add(Case("traction one tyre only", "traction", ["traction", "{d}/b.csv"], {"b.csv": "\n".join(br[:4]) + "\n"},
             "error", r"(?i)at least|too few|tyres"))
    add(Case("traction negative stopping distance", "traction", ["traction", "{d}/b.csv"],
             {"b.csv": "\n".join(br[:3] + [br[3].replace(",80.5,", ",-80.5,")] + br[4:]) + "\n"}, "error",
             r"(?i)stopping|range"))
    add(Case("traction with BOM", "traction", ["traction", "{d}/b.csv", "--json", "{d}/t.json"],
             {"b.csv": BOM + "\n".join(br) + "\n"}, "ok", check=_traction_ok))
    add(Case("sim adhesion camber 5 deg", "sim", ["sim", "adhesion", "--camber", "5", "--json", "{d}/a.json"], {},
             "ok", check=_adhesion_ok(0.8), timeout=240))
    add(Case("compare --data static push without patch", "compare",
             ["compare", *tyres, "--data", "{data}/truck/tyre_b_static.csv"], {}, "error", r"(?i)patch|static"))
    add(Case("compare the same tyre twice", "compare", ["compare", tyres[0], tyres[0], "--json", "{d}/c.json"], {},
             "ok", check=_compare_ok))
    # rig calibrate
    rig = ["rig", "calibrate", "--static", "{d}/s.csv", "--dynamic", "{data}/truck/tyre_a_dynamic.csv", "--patch",
           "{data}/truck/tyre_a_patch.csv"]
    add(Case("rig calibrate --out is the static file, --force", "rig calibrate", [*rig, "--out", "{d}/s.csv",
                                                                                 "--force"],
             {"s.csv": GOOD}, "error", "input"))
    add(Case("rig calibrate --out is the patch file, --force", "rig calibrate",
             [*rig, "--out", "{data}/truck/tyre_a_patch.csv", "--force"], {"s.csv": GOOD}, "error", "input"))
    add(Case("rig calibrate slip-angle data as --static", "rig calibrate", [*rig, "--out", "{d}/rig.json"],
             {"s.csv": GOOD}, "error", r"(?i)static|displacement"))
    add(Case("rig calibrate --out under a file", "rig calibrate", [*rig, "--out", "{d}/f/rig.json"],
             {"s.csv": GOOD, "f": "x"}, "error", r"(?i)is a file"))
    add(Case("rig calibrate --report names a file", "rig calibrate", [*rig, "--out", "{d}/rig.json", "--report",
                                                                      "{d}/r"], {"s.csv": GOOD, "r": "x"}, "error",
             r"(?i)is a file"))
    truck = "{data}/truck/tyre_a_"
    rig_ok = ["rig", "calibrate", "--static", truck + "static.csv", "--dynamic", truck + "dynamic.csv", "--patch",
              truck + "patch.csv"]

    def rig_json_ok(d):
        doc = json.loads((d / "rig.json").read_text())
        return doc.get("tyrefit") == "rig calibration", "rig.json written"
    add(Case("rig calibrate bundled truck tyre A", "rig calibrate", [*rig_ok, "--out", "{d}/rig.json", "--report",
                                                                     "{d}/r"], {}, "ok",
             check=_and(rig_json_ok, _exists("r/index.html")), timeout=240))
    add(Case("rig calibrate static file with BOM and CRLF", "rig calibrate",
             ["rig", "calibrate", "--static", "{d}/s.csv", "--dynamic", truck + "dynamic.csv", "--patch",
              truck + "patch.csv", "--out", "{d}/rig.json"],
             {"s.csv": BOM + (DATA / "truck/tyre_a_static.csv").read_text().replace("\n", "\r\n")}, "ok",
             check=rig_json_ok, timeout=240))
    add(Case("rig calibrate --out exists, --force over an old run keeps a user file in --report", "rig calibrate",
             [*rig_ok, "--out", "{d}/rig.json", "--report", "{d}/r", "--force"],
             {"rig.json": "{}", "r": _dir, "r/mine.txt": "mine\n"}, "ok",
             check=_and(rig_json_ok, _unchanged("r/mine.txt", "mine\n")), may_change=("rig.json",), timeout=240))
    add(Case("fit static tyre B with --patch", "fit", ["fit", "{data}/truck/tyre_b_static.csv", "--patch",
                                                       "{data}/truck/tyre_b_patch.csv", "--out", "{d}/b.tir"], {},
             "ok", check=_exists("b.tir"), timeout=240))
    add(Case("fit static test without --patch", "fit", ["fit", "{data}/truck/tyre_b_static.csv", "--out",
                                                        "{d}/b.tir"], {}, "error", r"--patch"))
    add(Case("fit static with --patch equal to --out, --force", "fit",
             ["fit", "{d}/s.csv", "--patch", "{d}/p.tir", "--out", "{d}/p.tir", "--force"],
             {"s.csv": (DATA / "truck/tyre_b_static.csv").read_text(),
              "p.tir": (DATA / "truck/tyre_b_patch.csv").read_text()}, "error", r"input"))
    # demo
    add(Case("demo --out names a file", "demo", ["demo", "--out", "{d}/f"], {"f": "x\n"}, "error", r"(?i)is a file"))
    add(Case("demo --out holds a user file, no --force", "demo", ["demo", "--out", "{d}/r"],
             {"r": _dir, "r/mine.txt": "mine\n"}, "error", r"(?i)not empty"))
    add(Case("demo --out under a file", "demo", ["demo", "--out", "{d}/f/demo"], {"f": "x\n"}, "error",
             r"(?i)is a file"))
    add(Case("demo --out in /proc", "demo", ["demo", "--out", "/proc/demo"], {}, "error", r"/proc"))
    return C


def _batch_ok(n_fitted, n_skipped=None):
    def check(d):
        s = (d / "o" / "summary.csv").read_text()
        ok_rows = s.count(",ok,")
        sk = s.count(",skipped,")
        ok = ok_rows == n_fitted and (n_skipped is None or sk == n_skipped)
        return ok, f"{ok_rows} fitted, {sk} skipped"
    return check


def _cases_batch() -> list[Case]:
    C = []
    add = C.append
    b = ["batch", "fit", "{d}/db", "--out", "{d}/o", "--workers", "1"]
    two = {"db": _dir, "db/a.csv": GOOD, "db/b.csv": sweeps_csv(seed=SEED + 1)}
    add(Case("batch fit two tyres", "batch fit", b, two, "ok", check=_and(_batch_ok(2), _fit_ok("o/a.tir")),
             timeout=240))
    add(Case("batch fit: foreign .tir not replaced", "batch fit", b, {**two, "o": _dir, "o/a.tir": "my tyre\n"},
             "error", r"(?i)not written by|--force", timeout=240, writes_on_error=True))
    add(Case("batch fit: out folder holds the user's index.html", "batch fit", b,
             {**two, "o": _dir, "o/index.html": "my page\n"}, "error", r"(?i)not written by"))
    add(Case("batch fit: out is a file", "batch fit", b, {**two, "o": "x\n"}, "error", r"(?i)not a folder"))
    add(Case("batch fit: empty folder", "batch fit", b, {"db": _dir}, "error", r"(?i)no data files"))
    add(Case("batch fit: glob matches nothing", "batch fit", ["batch", "fit", "{d}/none/*.csv", "--out", "{d}/o"],
             {}, "error", r"(?i)no (data files|such file)"))
    for v in ("0", "-1", "nan"):
        add(Case(f"batch fit --workers {v}", "batch fit", ["batch", "fit", "{d}/db", "--out", "{d}/o", "--workers",
                                                             v], two, "error", r"worker|invalid int"))
    add(Case("batch fit: one bad file among good", "batch fit", b,
             {**two, "db/c.csv": sweeps_csv(scale=(1, 1, 1, 1e-3))}, "error", r"c\.csv|c:", timeout=240,
             writes_on_error=True))
    return C


def _batch_stale_cases() -> list[Case]:
    """Staleness: the second run must refit after the source or the options changed."""
    C = []

    def prerun(argv):
        def make(path: Path):
            d = path.parent
            (d / "db").mkdir(exist_ok=True)
            (d / "db" / "a.csv").write_text(sweeps_csv(seed=SEED + 3, noise=0.01))
            subprocess.run([TYREFIT, *[a.format(d=d, data=DATA) for a in argv]], capture_output=True, timeout=240)
        return make

    base = ["batch", "fit", "{d}/db", "--out", "{d}/o", "--workers", "1"]
    def replace_old(path: Path):  # another tyre's data, with an old modification time (cp -p, mv)
        path.write_text(GOOD)
        os.utime(path, (1e9, 1e9))

    C.append(Case("batch fit: replaced source refits", "batch fit", base,
                  {"prep": prerun(base), "db/a.csv": replace_old}, "ok",
                  check=_and(_batch_ok(1, 0), _fit_ok("o/a.tir")), may_change=("db/a.csv", "a.tir", "a.fit.json"),
                  origin="issue 15", timeout=300))
    C.append(Case("batch fit: --cost l1 after l2 refits", "batch fit", [*base, "--cost", "l1"],
                  {"prep": prerun(base)}, "ok", check=_batch_ok(1, 0), origin="issue 15", timeout=300,
                  may_change=("a.tir", "a.fit.json")))
    C.append(Case("batch fit: unchanged source is up to date", "batch fit", base,
                  {"prep": prerun(base)}, "ok", check=_batch_ok(0, 1), timeout=300))
    return C


def _cases_eval() -> list[Case]:
    """``tyrefit eval`` (when the installed CLI has it)."""
    try:
        r = subprocess.run([TYREFIT, "eval", "--help"], capture_output=True, timeout=60)
    except (OSError, subprocess.TimeoutExpired):
        return []
    if r.returncode != 0:
        return []
    pts = "fz [N],slip_angle [deg]\n4000,0\n4000,2\n4000,-5\n2000,8\n"
    tyre = "{data}/sim/hard_front.tir"

    def eval_ok(d):
        import pandas as pd

        from tyrefit.io.readers import read_data  # noqa: F401 - the forces file is a CSV with unit headers

        df = pd.read_csv(d / "f.csv", comment="#")
        col = [c for c in df.columns if c.startswith("fy")][0]
        fy = df[col].to_numpy(float)
        ok = abs(fy[0]) < 0.2 * abs(fy[1]) and fy[1] < 0 < fy[2] and abs(fy[3]) < 3 * 2000
        return ok, f"fy {np.round(fy, 1).tolist()}"
    C = [Case("eval bundled tyre", "eval", ["eval", tyre, "--points", "{d}/p.csv", "--out", "{d}/f.csv"],
              {"p.csv": pts}, "ok", check=eval_ok),
         Case("eval --out is the points file, --force", "eval",
              ["eval", tyre, "--points", "{d}/p.csv", "--out", "{d}/p.csv", "--force"], {"p.csv": pts}, "error",
              "input"),
         Case("eval --out is the tyre, --force", "eval",
              ["eval", "{d}/t.tir", "--points", "{d}/p.csv", "--out", "{d}/t.tir", "--force"],
              {"p.csv": pts, "t.tir": (DATA / "sim/hard_front.tir").read_text()}, "error", "input"),
         Case("eval points FIFO", "eval", ["eval", tyre, "--points", "{d}/p.csv", "--out", "{d}/f.csv"],
              {"p.csv": _fifo}, "error", "FIFO"),
         Case("eval tyre /dev/zero", "eval", ["eval", "/dev/zero", "--points", "{d}/p.csv", "--out", "{d}/f.csv"],
              {"p.csv": pts}, "error", "device"),
         Case("eval --out exists", "eval", ["eval", tyre, "--points", "{d}/p.csv", "--out", "{d}/f.csv"],
              {"p.csv": pts, "f.csv": "old\n"}, "error", "--force"),
         Case("eval --out under a file", "eval", ["eval", tyre, "--points", "{d}/p.csv", "--out", "{d}/x/f.csv"],
              {"p.csv": pts, "x": "x"}, "error", r"(?i)is a file"),
         Case("eval tyre with BOM", "eval", ["eval", "{d}/t.tir", "--points", "{d}/p.csv", "--out", "{d}/f.csv"],
              {"p.csv": pts, "t.tir": BOM + (DATA / "sim/hard_front.tir").read_text()}, "ok", check=eval_ok)]
    return C


def _jitter(text: str, how: str) -> str:
    """A logged record with one repeated time ('repeat') or two swapped samples ('swap') mid-record."""
    lines = text.splitlines()
    i = len(lines) // 2
    if how == "repeat":
        cells = lines[i].split(",")
        cells[0] = lines[i - 1].split(",")[0]
        lines[i] = ",".join(cells)
    else:
        lines[i], lines[i + 1] = lines[i + 1], lines[i]
    return "\n".join(lines) + "\n"


def _camber_negated(path: Path):
    text = (DATA / "passenger" / "passenger_205_55R16.csv").read_text()
    rows = text.splitlines()
    k = next(i for i, r in enumerate(rows) if r and not r.startswith("#"))
    col = rows[k].split(",").index("camber [deg]")
    out = rows[:k + 1]
    for r in rows[k + 1:]:
        c = r.split(",")
        if len(c) > col and c[col]:
            c[col] = repr(-float(c[col]))
        out.append(",".join(c))
    path.write_text("\n".join(out) + "\n")


def _no_model(src: str, extra: str = ""):
    def make(path: Path):
        out, skip = [], False
        for line in (ROOT / "tests" / "data" / src).read_text(encoding="latin-1").splitlines(keepends=True):
            if line.strip().startswith("["):
                skip = line.strip().upper().startswith("[MODEL")
            if not skip:
                out.append(line)
        path.write_text("".join(out) + extra, encoding="latin-1")
    return make


def _cases_issue25() -> list[Case]:
    """Issue 25: scheduler addresses, trailing slash, long names, units, jittered records, long load
    programmes, tyre files without [MODEL], mirrored tyres."""
    C = []
    add = C.append
    b = ["batch", "fit", "{d}/db", "--out", "{d}/o", "--workers", "1", "--scheduler"]
    one = {"db": _dir, "db/a.csv": GOOD}
    for addr in ("tls://127.0.0.1:1", "ucx://127.0.0.1:1", "inproc://x", "file:///etc/passwd", "tcp://[::1",
                 "127.0.0.1:notaport", "tcp://127.0.0.1:1"):
        add(Case(f"batch fit --scheduler {addr}", "batch fit", b + [addr], one, "error", r"(?i)scheduler",
                 timeout=20, origin="issue 25", fast=addr in ("tls://127.0.0.1:1", "tcp://[::1")))
    add(Case("batch fit --scheduler '' runs locally", "batch fit", b + [""], one, "ok", check=_batch_ok(1),
             timeout=240, origin="issue 25"))
    add(Case("inspect --json with a trailing slash", "inspect", ["inspect", "{d}/d.csv", "--json", "{d}/out/"],
             {"d.csv": GOOD}, "error", r"(?i)folder", origin="issue 25", fast=True))
    long = "n" * 250 + ".json"
    add(Case("inspect --json with a 255-byte name", "inspect", ["inspect", "{d}/d.csv", "--json", "{d}/" + long],
             {"d.csv": GOOD}, "ok", check=_exists(long), origin="issue 25", fast=True))
    add(Case("inspect --json 255-byte name, --force over it", "inspect",
             ["inspect", "{d}/d.csv", "--json", "{d}/" + long, "--force"], {"d.csv": GOOD, long: "{}\n"}, "ok",
             check=_exists(long), may_change=(long,), origin="issue 25"))
    add(Case("fit units [º] and [daN]", "fit", ["fit", "{d}/d.csv", "--out", "{d}/t.tir"],
             {"d.csv": sweeps_csv(header=("run", "slip_angle [º]", "fy [daN]", "fz [daN]"), scale=(1, 1, 0.1, 0.1))},
             "ok", check=_fit_ok(), origin="issue 25", fast=True))
    add(Case("fit record with a repeated timestamp", "fit", ["fit", "{d}/r.csv", "--out", "{d}/t.tir"],
             {"r.csv": _jitter(record_csv(), "repeat")}, "ok", check=_fit_ok(), timeout=240, origin="issue 25"))
    add(Case("fit record with two swapped samples", "fit", ["fit", "{d}/r.csv", "--out", "{d}/t.tir"],
             {"r.csv": _jitter(record_csv(), "swap")}, "ok", check=_fit_ok(), timeout=240, origin="issue 25"))
    add(Case("fit 40-level load programme", "fit", ["fit", "{d}/d.csv", "--out", "{d}/t.tir"],
             {"d.csv": sweeps_csv(loads=tuple(np.linspace(1500, 7000, 40)))}, "ok", check=_exists("t.tir"),
             timeout=240, origin="issue 25"))
    add(Case("compare .tir without [MODEL]", "compare",
             ["compare", "{d}/a.tir", "{d}/b.tir", "--json", "{d}/c.json", "--allow-unphysical"],
             {"a.tir": _no_model("ref_adams_pac89_example.tir"), "b.tir": _no_model("ref_HMMWV_Pac02Tire.tir")},
             "ok", check=_exists("c.json"), origin="issue 25", fast=True))
    add(Case("compare .tir without [MODEL], family unclear", "compare", ["compare", "{d}/a.tir", "{d}/a.tir"],
             {"a.tir": _no_model("ref_HMMWV_Pac02Tire.tir", "[EXTRA]\nA0 = 1.6\nA3 = 1000\n")}, "error",
             r"\[MODEL\]", origin="issue 25"))
    add(Case("fit camber-mirrored passenger tyre", "fit", ["fit", "{d}/d.csv", "--out", "{d}/t.tir"],
             {"d.csv": _camber_negated}, "error", r"(?i)camber thrust.*--allow-mirrored", origin="issue 25",
             fast=True))
    add(Case("fit camber-mirrored, --allow-mirrored", "fit",
             ["fit", "{d}/d.csv", "--out", "{d}/t.tir", "--allow-mirrored"], {"d.csv": _camber_negated}, "ok",
             check=_exists("t.tir"), origin="issue 25"))
    # this session's inputs: the scheduler file, the batch manifest, the road friction
    sf = ["batch", "fit", "{d}/db", "--out", "{d}/o", "--workers", "1", "--scheduler-file", "{d}/s.json"]
    for label, content, pat in (("missing", None, r"(?i)scheduler-file.*cannot be read"),
                                ("not JSON", "{not json", r"(?i)not a Dask scheduler file"),
                                ("without an address", '{"type": "Scheduler"}', r"(?i)no 'address'"),
                                ("naming UCX", '{"address": "ucx://127.0.0.1:1"}', r"(?i)UCX"),
                                ("naming a closed port", '{"address": "tcp://127.0.0.1:1"}', r"(?i)cannot connect")):
        files = dict(one, **({"s.json": content} if content is not None else {}))
        add(Case(f"batch fit --scheduler-file {label}", "batch fit", sf, files, "error", pat, timeout=20,
                 origin="session 9", fast=label == "not JSON"))
    mb = ["batch", "fit", "{d}/db", "--out", "{d}/o", "--workers", "1", "--manifest", "{d}/m.csv"]
    for label, text, pat in (("naming no data file", "file,size\nnope.csv,385/65R22.5\n", r"(?i)none of the batch"),
                             ("load without a unit", "file,rated_load\na.csv,6000\n", r"(?i)unit"),
                             ("load in metres", "file,rated_load [m]\na.csv,6000\n", r"(?i)not a force"),
                             ("negative load", "file,rated_load [N]\na.csv,-6000\n", r"(?i)rated.load"),
                             ("bad size", "file,size\na.csv,banana\n", r"(?i)size"),
                             ("binary", b"\x00\x01\x02" * 50, r"(?i)manifest"),
                             ("empty", "", r"(?i)empty")):
        add(Case(f"batch fit --manifest {label}", "batch fit", mb, dict(one, **{"m.csv": text}), "error", pat,
                 origin="session 9", fast=label in ("naming no data file", "binary")))
    add(Case("batch fit --manifest with size and load", "batch fit", mb,
             dict(one, **{"m.csv": "file,size,rated_load [kN]\na.csv,205/55R16,6.0\n"}), "ok", check=_batch_ok(1),
             timeout=240, origin="session 9"))
    for rf in ("0", "nan", "9", "-0.5"):
        add(Case(f"sim ramp --road-friction {rf}", "sim", ["sim", "ramp", "--road-friction", rf, "--json", "{d}/r.json"],
                 {}, "error", r"(?i)road friction", origin="session 9", fast=rf == "nan"))
    return C


def all_cases() -> list[Case]:
    """Every case of the corpus (names are unique)."""
    cases = _cases_fit() + _cases_inputs() + _cases_commands() + _cases_batch() + _batch_stale_cases() \
        + _cases_eval() + _cases_issue25()
    names = [c.name for c in cases]
    dup = {n for n in names if names.count(n) > 1}
    assert not dup, dup
    return cases


# --------------------------------------------------------------------------- running

@dataclass
class Outcome:
    case: Case
    code: int | None
    seconds: float
    stderr: str
    verdict: str            # 'pass' or what went wrong
    actual: str             # 'ok', 'error: <line>', 'exit N', 'hang'
    why: str = ""
    traceback: bool = False
    hang: bool = False
    lost: list[str] = field(default_factory=list)
    wrong: bool = False


def _hash_tree(d: Path, extra: list[Path]) -> dict[str, str]:
    out = {}
    paths = [p for p in d.rglob("*")] + extra
    for p in paths:
        try:
            st = os.lstat(p)
        except OSError:
            continue
        if stat.S_ISLNK(st.st_mode):
            out[str(p)] = "link:" + os.readlink(p)
        elif stat.S_ISREG(st.st_mode):
            out[str(p)] = hashlib.sha256(p.read_bytes()).hexdigest()
        elif stat.S_ISDIR(st.st_mode):
            out[str(p)] = "dir"
        else:
            out[str(p)] = "special"
    return out


def _batch_own(p: Path, d: Path) -> bool:
    """Files a batch folder rewrites on every run (summary, report, status records, its own tyres)."""
    rel = os.path.relpath(p, d)
    return rel in ("o/summary.csv", "o/index.html", "o/.tyrefit-manifest.json") or rel.startswith("o/status/")


def _limit(fsize):
    def pre():
        if fsize is not None:
            resource.setrlimit(resource.RLIMIT_FSIZE, (fsize, fsize))
    return pre


def run_case(case: Case, base: Path | None = None) -> Outcome:
    """Run one case in a fresh folder and judge it."""
    d = Path(tempfile.mkdtemp(prefix="hostile-", dir=base))
    for name, content in case.files.items():
        p = d / name
        p.parent.mkdir(parents=True, exist_ok=True)
        if callable(content):
            content(p)
            if name == "prep":
                continue
        else:
            p.write_bytes(content.encode() if isinstance(content, str) else content)
    argv = [a.format(d=d, data=DATA) for a in case.argv]
    bundled = sorted(p for p in DATA.rglob("*") if p.is_file())
    before = _hash_tree(d, bundled)
    t0 = time.perf_counter()
    env = {**os.environ, "MPLBACKEND": "Agg", "PYTHONWARNINGS": "ignore"}
    try:
        r = subprocess.run([TYREFIT, *argv], capture_output=True, text=True, timeout=case.timeout,
                           preexec_fn=_limit(case.fsize), env=env, cwd=d, stdin=subprocess.DEVNULL)
        code, err, out = r.returncode, r.stderr, r.stdout
    except subprocess.TimeoutExpired:
        code, err, out = None, "", ""
    dt = time.perf_counter() - t0
    after = _hash_tree(d, bundled)
    lost = [k for k, v in before.items() if after.get(k) != v and Path(k).name not in case.may_change
            and os.path.relpath(k, d) not in case.may_change
            and not (case.command == "batch fit" and _batch_own(Path(k), d))]
    new = [k for k in after if k not in before]
    lines = [ln for ln in err.splitlines() if ln.strip() and not ln.startswith(("batch fit:", "\r"))
             and "it/s]" not in ln and "tyre/s]" not in ln and "%|" not in ln]
    o = Outcome(case, code, dt, err, "pass", "")
    if code is None:
        o.hang, o.verdict, o.actual = True, "HANG", f"hang (> {case.timeout:.0f} s)"
    elif code not in (0, 2) or "Traceback" in err:
        o.traceback, o.verdict = True, "TRACEBACK"
        o.actual = f"exit {code}: " + (err.strip().splitlines() or [""])[-1][:120]
    elif code == 0:
        o.actual = "ok"
    else:
        o.actual = "error: " + (lines[0] if lines else "(no message)")
    if lost:
        o.lost = [os.path.relpath(k, d) if k.startswith(str(d)) else k for k in lost]
        o.verdict = "DATA LOST"
        o.why = ", ".join(o.lost)
    elif o.verdict == "pass":
        if case.expect == "ok":
            if code != 0:
                o.verdict, o.why = "REFUSED", "a legitimate input was refused"
            else:
                try:
                    good, why = case.check(d) if case.check else (True, "")
                except Exception as exc:  # noqa: BLE001 - a check that cannot read the output fails
                    good, why = False, f"check failed: {exc.__class__.__name__}: {exc}"
                o.why = why
                if not good:
                    o.verdict, o.wrong = "WRONG", True
        else:
            if code == 0:
                o.verdict, o.wrong, o.why = "WRONG", True, "accepted a bad input"
            elif len(lines) != 1:
                o.verdict, o.why = "MESSAGE", f"{len(lines)} stderr lines"
            elif case.pattern and not re.search(case.pattern, lines[0]):
                o.verdict, o.why = "MESSAGE", f"message does not match {case.pattern!r}"
            elif not case.writes_on_error and new:
                leftovers = [os.path.relpath(k, d) for k in new]
                if any(not (d / x).is_dir() for x in leftovers):
                    o.verdict, o.why = "PARTIAL", "left " + ", ".join(leftovers[:3])
    _cleanup(d)
    return o


def _cleanup(d: Path):
    import shutil

    for p in d.rglob("*"):
        with_suppress_chmod(p)
    shutil.rmtree(d, ignore_errors=True)


def with_suppress_chmod(p: Path):
    try:
        if p.is_dir() and not p.is_symlink():
            os.chmod(p, 0o755)
    except OSError:
        pass


def table(outcomes: list[Outcome]) -> str:
    """Markdown table: case, command, expected, actual, verdict, seconds."""
    rows = ["| # | case | command | expected | actual | verdict | s |", "|---|---|---|---|---|---|---|"]
    for i, o in enumerate(outcomes, 1):
        act = o.actual.replace("|", "/")
        act = act if len(act) <= 150 else act[:147] + "..."
        exp = "exit 0, " + ("output checked" if o.case.check else "ok") if o.case.expect == "ok" else \
            f"exit 2, one line /{o.case.pattern}/"
        verdict = o.verdict + (f" ({o.why})" if o.why and o.verdict != "pass" else "")
        rows.append(f"| {i} | {o.case.name}{' *' if o.case.origin else ''} | {o.case.command} | {exp} | {act} | "
                    f"{verdict} | {o.seconds:.1f} |")
    return "\n".join(rows)


def summary(outcomes: list[Outcome]) -> dict[str, int]:
    return {"cases": len(outcomes),
            "commands": len({o.case.command for o in outcomes}),
            "pass": sum(o.verdict == "pass" for o in outcomes),
            "tracebacks": sum(o.traceback for o in outcomes),
            "hangs": sum(o.hang for o in outcomes),
            "data_lost": sum(bool(o.lost) for o in outcomes),
            "silently_wrong": sum(o.wrong for o in outcomes),
            "other_failures": sum(o.verdict in ("REFUSED", "MESSAGE", "PARTIAL") for o in outcomes)}
