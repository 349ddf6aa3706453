"""The Magic Formula model evaluated by parts, for the fit's residuals and Jacobians.

:func:`tyrefit.models.mf61.forces` builds the coefficient mapping (``coefficients``, ~350 keys) and every
part of the model at each call.  A fit evaluates the model tens of thousands of times with a few
coefficients changed, so here

* the coefficient mapping and the slip/load quantities of (4.E1)-(4.E8) (``_basic``) are built once for a
  set of points, and a call changes only the varied entries (:class:`Forces`, ``coefficients``);
* the parts of Fx, Fy and Mz are kept (:meth:`Forces.state`), and a change of one coefficient recomputes only
  the parts that depend on it (:meth:`Forces.update`): a finite-difference column of an Mz0 coefficient
  re-evaluates the trail and residual torque, not Fx0, Fy0 and the combined-slip weights;
* Mx has an analytic Jacobian (:func:`mx_jacobian`; MF 6.1 form, 4.E69 with the manual's terms).

Every value is computed by the model's own stage functions in the order :func:`~tyrefit.models.mf61.forces`
uses, so the residuals are those of the plain evaluation to the last bit.

:data:`FAST` = False restores the evaluation of the branch point (a mapping per call, every part per
column); ``benchmarks/bench_fit_mf.py`` times both in one run.
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np

from ..models import mf61

#: the fast evaluation (False: the code path of the branch point, for the benchmark's baseline)
FAST = True

#: coefficients read by (4.E1)-(4.E8) (``mf61._basic``): a change rebuilds everything
_BASIC = frozenset(("FNOMIN", "LFZO", "NOMPRES", "LONGVL", "VXLOW", "LMUX", "LMUY", "LMUV", "LGAX", "LGAY",
                    "LGAZ"))
_GROUPS = (
    ("fx0", ("PCX", "PDX", "PEX", "PKX", "PHX", "PVX", "PPX"), ("LCX", "LKX", "LHX", "LVX", "LEX")),
    ("fy0", ("PCY", "PDY", "PEY", "PKY", "PHY", "PVY", "PPY"), ("LCY", "LKY", "LKYC", "LHY", "LVY", "LEY")),
    ("mz0", ("QBZ", "QCZ", "QDZ", "QEZ", "QHZ", "PPZ"), ("LTR", "LRES", "LKZC")),
    ("gxa", ("RBX", "RCX", "REX", "RHX"), ("LXAL",)),
    ("gyk", ("RBY", "RCY", "REY", "RHY", "RVY"), ("LYKA", "LVYKA")),
    ("ssz", ("SSZ",), ("LS",)),
)
#: channels each group changes
TOUCHES = {"fx0": ("fx", "mz"), "fy0": ("fy", "mz"), "mz0": ("mz",), "gxa": ("fx", "mz"), "gyk": ("fy", "mz"),
           "ssz": ("mz",), "basic": ("fx", "fy", "mz")}


@lru_cache(maxsize=None)
def group(name: str, v52: bool = False) -> str:
    """The part of the model coefficient ``name`` enters first ('basic': the shared quantities, or unknown)."""
    if name in _BASIC or (v52 and name in mf61._PRESSURE_61):  # 5.2: a pressure term switches dpi on
        return "basic"
    for g, prefixes, names in _GROUPS:
        if name.startswith(prefixes) or name in names:
            return g
    return "basic"


class Forces:
    """Fx, Fy and Mz of one set of points, by parts (see the module docstring)."""

    def __init__(self, version: str, fz, kappa, alpha, gamma, pressure, speed):
        self.version = version
        self.args = (fz, kappa, alpha, gamma, pressure, speed)
        self.shape = np.shape(fz)
        self.c0 = None
        self.b0 = None

    def bind(self, p) -> None:
        """Build the coefficient mapping and the basic quantities from ``p`` (all other calls change entries)."""
        self.c0, self.b0 = mf61._prepare(p, self.version, *self.args)
        self.v52 = self.b0.v52

    def coefficients(self, changed) -> tuple[dict, object]:
        """(c, b) with the entries ``changed`` (name -> value) replaced."""
        c = dict(self.c0)
        basic = False
        for k, v in changed:
            c[k] = float(v)
            basic = basic or group(k, self.v52) == "basic"
        return c, (self.basic(c) if basic else self.b0)

    def basic(self, c):
        fz, kappa, alpha, gamma, pressure, speed = self.args
        return mf61._basic(c, self.v52, fz, kappa, alpha, gamma, pressure, speed)

    # -- the parts, in the order of mf61.forces
    def _fx0(self, s, c, b):
        s["fx0"], _, s["kxk"] = mf61._fx0_parts(c, b)

    def _fy0(self, s, c, b):
        s["fyp"] = mf61._fy0_parts(c, b)
        if self.v52:
            s["muy0"] = mf61._fy0_parts(c, b, zero_camber=True)["muy"]
        else:
            s["fyg0"] = s["fyp"]["fy0"] if not np.any(b.gstar) else mf61._fy0_parts(c, b, zero_camber=True)["fy0"]

    def _fx(self, s, c, b):
        s["fx"] = s["gxa"] * s["fx0"]                                                  # (4.E50)

    def _fy(self, s, c, b):
        s["gyk"], svyk = mf61._gyk(c, b, s["fyp"]["muy"])
        s["fy"] = s["gyk"] * s["fyp"]["fy0"] + svyk                                    # (4.E58)
        if self.v52:
            _, svyk0 = mf61._gyk(c, b, s["muy0"])
            s["fy_prime"] = s["fy"] - svyk0
        else:
            s["fy_prime"] = s["gyk"] * s["fyg0"]                                       # (4.E74)

    def _mz(self, s, c, b):
        s["mz"], _, _ = mf61._mz(c, b, s["mzp"], s["fy_prime"], s["kxk"], s["fx"], s["fy"])

    def state(self, c, b) -> dict:
        s: dict = {}
        self._fx0(s, c, b)
        self._fy0(s, c, b)
        s["gxa"] = mf61._gxa(c, b)
        self._fx(s, c, b)
        self._fy(s, c, b)
        s["mzp"] = mf61._mz_parts(c, b, s["fyp"])
        self._mz(s, c, b)
        return s

    def update(self, s: dict, c, b, grp: str) -> dict:
        """The state ``s`` after a change of coefficients of group ``grp`` (c, b: the changed mapping)."""
        if grp == "basic":
            return self.state(c, b)
        s = dict(s)
        if grp == "fx0":
            self._fx0(s, c, b)
            self._fx(s, c, b)
        elif grp == "fy0":
            self._fy0(s, c, b)
            self._fy(s, c, b)
            s["mzp"] = mf61._mz_parts(c, b, s["fyp"])
        elif grp == "mz0":
            s["mzp"] = mf61._mz_parts(c, b, s["fyp"])
        elif grp == "gxa":
            s["gxa"] = mf61._gxa(c, b)
            self._fx(s, c, b)
        elif grp == "gyk":
            self._fy(s, c, b)
        self._mz(s, c, b)
        return s

    def out(self, s: dict, channel: str) -> np.ndarray:
        return np.broadcast_to(np.asarray(s[channel], dtype=float), self.shape)


def mx_jacobian(c, b, fy, names) -> np.ndarray | None:
    """d Mx / d theta for the MF 6.1 Mx (``mf61._mx``), one column per name; None where not analytic.

    Mx = R0 Fz LMX [QSX1 LVMX - QSX2 g (1 + PPMX1 dpi) + QSX3 Fy/Fz0 + QSX4 A S + QSX10 T g]
         + R0 LMX [Fy (QSX13 + QSX14 |g|) - Fz QSX12 g |g|]
    with A = cos(QSX5 w), w = atan((QSX6 Fz/Fz0)^2), S = sin(u), u = QSX7 g + QSX8 atan(QSX9 Fy/Fz0),
    T = atan(QSX11 Fz/Fz0).
    """
    if b.v52:
        return None
    r0, fz0, fz, g = c["UNLOADED_RADIUS"], c["FNOMIN"], b.fz, b.gamma
    lmx = c["LMX"]
    k = r0 * fz * lmx
    f, z = fy / fz0, fz / fz0
    q6z = c["QSX6"] * z
    w = np.arctan(q6z ** 2)
    a = np.cos(c["QSX5"] * w)
    at9 = np.arctan(c["QSX9"] * f)
    u = c["QSX7"] * g + c["QSX8"] * at9
    sn, cs = np.sin(u), np.cos(u)
    t = np.arctan(c["QSX11"] * z)
    q4 = c["QSX4"]
    col = {
        "QSX1": k * c["LVMX"],
        "QSX2": -k * g * (1.0 + c["PPMX1"] * b.dpi),
        "PPMX1": -k * c["QSX2"] * g * b.dpi,
        "QSX3": k * f,
        "QSX4": k * a * sn,
        "QSX5": -k * q4 * sn * np.sin(c["QSX5"] * w) * w,
        "QSX6": -k * q4 * sn * np.sin(c["QSX5"] * w) * c["QSX5"] * 2.0 * c["QSX6"] * z ** 2 / (1.0 + q6z ** 4),
        "QSX7": k * q4 * a * cs * g,
        "QSX8": k * q4 * a * cs * at9,
        "QSX9": k * q4 * a * cs * c["QSX8"] * f / (1.0 + (c["QSX9"] * f) ** 2),
        "QSX10": k * t * g,
        "QSX11": k * c["QSX10"] * g * z / (1.0 + (c["QSX11"] * z) ** 2),
        "QSX12": -r0 * lmx * fz * g * np.abs(g),
        "QSX13": r0 * lmx * fy,
        "QSX14": r0 * lmx * fy * np.abs(g),
    }
    if any(n not in col for n in names):
        return None
    shape = np.shape(fz)
    return np.column_stack([np.broadcast_to(np.asarray(col[n], dtype=float), shape) for n in names])
