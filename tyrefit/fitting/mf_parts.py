"""The Magic Formula model evaluated by parts, for the fit's residuals and Jacobians.

:func:`tyrefit.models.mf61.forces` builds the coefficient mapping (``coefficients``, ~350 keys) and every
part of the model at each call.  A fit evaluates the model tens of thousands of times with a few
coefficients changed, so here

* the coefficient mapping and the slip/load quantities of (4.E1)-(4.E8) (``_basic``) are built once for a
  set of points, and a call changes only the varied entries (:class:`Forces`, ``coefficients``);
* the parts of Fx, Fy and Mz are kept (:meth:`Forces.state`), and a change of one coefficient recomputes only
  the parts that depend on it (:meth:`Forces.update`): a finite-difference column of an Mz0 coefficient
  re-evaluates the trail and residual torque, not Fx0, Fy0 and the combined-slip weights;
* Mx and Mz have analytic Jacobians in their own coefficients (:func:`mx_jacobian`, MF 6.1 form of 4.E69 with
  the manual's terms; :func:`mz_jacobian`, 4.E31-4.E47 and 4.E71-4.E78).

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


def mx_jacobian(c, b, fy, names) -> dict[str, np.ndarray]:
    """d Mx / d theta for the MF 6.1 Mx (``mf61._mx``): {name: column} for the names it covers ({} for MF 5.2).

    Mx = R0 Fz LMX [QSX1 LVMX - QSX2 g (1 + PPMX1 dpi) + QSX3 Fy/Fz0 + QSX4 A S + QSX10 T g]
         + R0 LMX [Fy (QSX13 + QSX14 |g|) - Fz QSX12 g |g|]
    with A = cos(QSX5 w), w = atan((QSX6 Fz/Fz0)^2), S = sin(u), u = QSX7 g + QSX8 atan(QSX9 Fy/Fz0),
    T = atan(QSX11 Fz/Fz0).
    """
    if b.v52:
        return {}
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
    shape = np.shape(fz)
    return {n: np.broadcast_to(np.asarray(col[n], dtype=float), shape) for n in names if n in col}


def mz_jacobian(c, b, fyp, fy_prime, kxk, fx, fy, names) -> dict[str, np.ndarray]:
    """d Mz / d theta (MF 6.1, ``mf61._mz_parts`` and ``mf61._mz``) for the aligning coefficients among ``names``.

    Mz = -t Fy' + Mzr + s Fx (4.E71) with the other channels held (the Mz stages vary only the trail, the
    residual torque and s).  t = cos(C_t atan(B_t x - E_t (B_t x - atan(B_t x)))) D_t cos(alpha') LFZO
    (4.E73), x = alpha_t,eq (A54); E_t = min(E0 (1 + (QEZ4 + QEZ5 g) 2/pi atan(B_t C_t alpha_t)), 1) (4.E44);
    Mzr = D_r cos(atan(B_r alpha_r,eq)) (4.E75); s (4.E76).  Returns {name: column} for the names it covers
    (QBZ*, QCZ1, QDZ*, QEZ*, QHZ*, PPZ*, SSZ*); {} for MF 5.2.
    """
    if b.v52:
        return {}
    eps = mf61.EPSILON
    fz, dfz, dpi, fz0p = b.fz, b.dfz, b.dpi, b.fz0p
    g = gs = b.gamma
    r0, red, lfzo = c["UNLOADED_RADIUS"], b.red, c["LFZO"]
    kya = fyp["kya"]
    kyap = kya + eps * mf61._sgn(kya)
    ar = b.astar + fyp["shy"] + fyp["svy"] / kyap
    sht = c["QHZ1"] + c["QHZ2"] * dfz + (c["QHZ3"] + c["QHZ4"] * dfz) * gs
    b1 = c["QBZ1"] + c["QBZ2"] * dfz + c["QBZ3"] * dfz ** 2
    b2 = 1.0 + c["QBZ4"] * g + c["QBZ5"] * np.abs(g)
    bk = c["LKY"] / b.lmuy_s
    bt = b1 * b2 * bk
    ct = c["QCZ1"]
    d0 = fz * (r0 / fz0p) * c["LTR"]
    d1 = c["QDZ1"] + c["QDZ2"] * dfz
    d2 = 1.0 - c["PPZ1"] * dpi
    d3 = 1.0 + c["QDZ3"] * g + c["QDZ4"] * g ** 2
    dt0 = d0 * d1 * d2
    dt = dt0 * d3
    at = b.astar + sht
    e0 = c["QEZ1"] + c["QEZ2"] * dfz + c["QEZ3"] * dfz ** 2
    eg = c["QEZ4"] + c["QEZ5"] * gs
    earg = bt * ct * at
    a_e = np.arctan(earg)
    e1 = 1.0 + eg * (2.0 / np.pi) * a_e
    free = (e0 * e1) < 1.0                       # E_t <= 1: no derivative where it is limited
    et = np.minimum(e0 * e1, 1.0)
    de = np.where(free, 1.0, 0.0)
    de_darg = de * e0 * eg * (2.0 / np.pi) / (1.0 + earg ** 2)   # d E_t / d (B_t C_t alpha_t)
    kk = (kxk / kyap) ** 2 * b.kappa ** 2
    tan_t = np.tan(at)
    q = np.sqrt(tan_t ** 2 + kk)
    x = np.arctan(q) * np.sign(at)
    with np.errstate(invalid="ignore", divide="ignore"):
        dx_dat = np.where(q > 0, np.sign(at) * tan_t * (1.0 + tan_t ** 2) / (q * (1.0 + q ** 2)), 1.0)
    q_r = np.sqrt(np.tan(ar) ** 2 + kk)
    ar_eq = np.arctan(q_r) * np.sign(ar)
    u = bt * x
    v = u - et * (u - np.arctan(u))
    w = np.arctan(v)
    kt = b.cos_ap * lfzo * red
    dt_dv = -np.sin(ct * w) * ct / (1.0 + v ** 2) * dt * kt
    dv_du = 1.0 - et * (1.0 - 1.0 / (1.0 + u ** 2))
    dv_de = -(u - np.arctan(u))
    # dMz/d(intermediate) with dMz/dt = -Fy'
    m_t = -fy_prime
    m_dt = m_t * np.cos(ct * w) * kt                                     # through D_t
    m_bt = m_t * dt_dv * (dv_du * x + dv_de * de_darg * ct * at)         # through B_t (the argument and E_t)
    m_ct = m_t * (-np.sin(ct * w) * w * dt * kt + dt_dv * dv_de * de_darg * bt * at)
    m_at = m_t * dt_dv * (dv_du * bt * dx_dat + dv_de * de_darg * bt * ct)
    m_et = m_t * dt_dv * dv_de * de
    br = c["QBZ9"] * c["LKY"] / b.lmuy_s + c["QBZ10"] * fyp["by"] * fyp["cy"]
    dr = (fz * r0 * ((c["QDZ6"] + c["QDZ7"] * dfz) * c["LRES"]
                     + ((c["QDZ8"] + c["QDZ9"] * dfz) * (1.0 + c["PPZ2"] * dpi)
                        + (c["QDZ10"] + c["QDZ11"] * dfz) * np.abs(gs)) * gs * c["LKZC"])
          * b.lmuy_s * np.cos(b.alpha))
    m_dr = np.cos(np.arctan(br * ar_eq)) * red                           # C_r = 1
    m_br = -dr * np.sin(np.arctan(br * ar_eq)) * ar_eq / (1.0 + (br * ar_eq) ** 2) * red
    rr = fz * r0 * b.lmuy_s * np.cos(b.alpha)
    rg = rr * gs * c["LKZC"]
    rs = r0 * c["LS"] * fx
    cols = {
        "QBZ1": m_bt * b2 * bk, "QBZ2": m_bt * dfz * b2 * bk, "QBZ3": m_bt * dfz ** 2 * b2 * bk,
        "QBZ4": m_bt * b1 * g * bk, "QBZ5": m_bt * b1 * np.abs(g) * bk,
        "QCZ1": m_ct,
        "QDZ1": m_dt * d0 * d2 * d3, "QDZ2": m_dt * d0 * dfz * d2 * d3, "PPZ1": -m_dt * d0 * d1 * dpi * d3,
        "QDZ3": m_dt * dt0 * g, "QDZ4": m_dt * dt0 * g ** 2,
        "QEZ1": m_et * e1, "QEZ2": m_et * dfz * e1, "QEZ3": m_et * dfz ** 2 * e1,
        "QEZ4": m_et * e0 * (2.0 / np.pi) * a_e, "QEZ5": m_et * e0 * (2.0 / np.pi) * a_e * gs,
        "QHZ1": m_at, "QHZ2": m_at * dfz, "QHZ3": m_at * gs, "QHZ4": m_at * dfz * gs,
        "QDZ6": m_dr * rr * c["LRES"], "QDZ7": m_dr * rr * dfz * c["LRES"],
        "QDZ8": m_dr * rg * (1.0 + c["PPZ2"] * dpi), "QDZ9": m_dr * rg * dfz * (1.0 + c["PPZ2"] * dpi),
        "PPZ2": m_dr * rg * (c["QDZ8"] + c["QDZ9"] * dfz) * dpi,
        "QDZ10": m_dr * rg * np.abs(gs), "QDZ11": m_dr * rg * dfz * np.abs(gs),
        "QBZ9": m_br * c["LKY"] / b.lmuy_s, "QBZ10": m_br * fyp["by"] * fyp["cy"],
        "SSZ1": rs, "SSZ2": rs * fy / c["FNOMIN"], "SSZ3": rs * g, "SSZ4": rs * dfz * g,
    }
    shape = np.shape(fz)
    return {n: np.broadcast_to(np.asarray(cols[n], dtype=float), shape) for n in names if n in cols}
