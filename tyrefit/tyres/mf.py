"""Magic Formula tyres (MF 5.2 / PAC2002 and MF 6.1 / 6.2) behind the tyre interface.

:class:`MFTyre` holds a property file's parameters under their ``.tir``
spelling in upper case (``PCY1``, ``LMUY``, ``FNOMIN``), dimensional values
converted to SI by the reader (:func:`tyrefit.io.tir.mf_from_property_file`),
and evaluates them with the MF 6.1 / 5.2 equations of
:mod:`tyrefit.models.mf61` (pure and combined slip, camber, pressure, Mx, My).
MF 6.2 files are evaluated as 6.1; turn slip is out of scope.

:meth:`MFTyre.check` looks at the Magic Formula factors themselves over the
declared ranges -- the MF analogues of PAC89's C > 0, D > 0, a4 != 0, E <= 1 --
with the equations of Pacejka, *Tire and Vehicle Dynamics*, 3rd ed. (2012),
section 4.3.2 (numbers (4.E11)-(4.E25)), then that the evaluated forces are
finite on a grid over the ranges.

Which parts a file models
-------------------------
A property file says which forces and moments its tyre computes in
``USE_MODE`` ([MODEL]); tyrefit honours its last digit, which means the same in
both families of files:

* MSC Adams PAC2002 / MF 5.2 files (the comment block MSC ships in them, e.g.
  Goodyear's MF-Tool 5.0 export in ``tests/data/vendor_feda_335_65R22_5_40psi.tir``):
  0 Fz only, no Magic Formula; 1 Fx, My only; 2 Fy, Mx, Mz only; 3 uncombined;
  4 combined; +10 with relaxation; x -1 mirrored characteristics.
* TNO MF-Tyre 6.x (TNO's ``dteval`` help text, (C) 1996-2013 TNO Automotive;
  FunctionBay RecurDyn's MF-Tyre property-file page): the same 0-5 in the last
  digit (5 = combined + turn slip), tens = dynamics (0 steady state, 1/2
  relaxation, 3 rigid ring), hundreds = road contact (MFeval's example file
  has 124).

So the last digit 1 removes Fy, Mz and Mx; 2 removes Fx and My; 0 removes all;
3 evaluates uncombined (Fx, My at alpha = 0; Fy, Mz, Mx at kappa = 0); 4 and 5
combined (turn slip is out of scope: 5 is 4 at zero turn slip).  Tens,
hundreds and the sign (relaxation, road contact, mirroring) concern a
simulator's dynamics, not the steady-state forces, and are not applied; a
negative USE_MODE is said in :meth:`MFTyre.warnings`.  A file without USE_MODE
computes every part.  MFeval ignores the file's USE_MODE (it takes its own
``useMode`` argument) and evaluates every coefficient block.

tyrefit's own writer (:mod:`tyrefit.io.mf_tir`) also writes a machine-readable
comment ``$ TYREFIT_NOT_FITTED = fx, mz, ...`` naming the channels that had
no data (``fx``, ``fy``, ``mz``, ``mx``, ``my`` and ``combined``); those parts
are absent here too (NaN; ``combined`` not fitted -> uncombined evaluation,
which is what the neutral combined-slip weights G = 1 give anyway).  A part
that is absent gives NaN in :meth:`MFTyre.forces`, is not checked, and
``sim`` refuses a tyre without the part it needs.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np

from ..errors import ModelError
from .base import Tyre

from ..models import mf61 as _mf61
from ..io.mf_tir import write_mf_tir

__all__ = ["MFTyre", "REQUIRED_MF", "USE_MODE_OUTPUTS", "NOT_FITTED_KEY", "parse_not_fitted"]

#: channels computed for each last digit of USE_MODE (see the module notes for the sources)
USE_MODE_OUTPUTS: dict[int, tuple[str, ...]] = {
    0: (), 1: ("fx", "my"), 2: ("fy", "mz", "mx"), 3: ("fx", "fy", "mz", "mx", "my"),
    4: ("fx", "fy", "mz", "mx", "my"), 5: ("fx", "fy", "mz", "mx", "my"),
}

#: the comment key tyrefit's writer uses for the channels fitted without data (``$ TYREFIT_NOT_FITTED = fx, mz``)
NOT_FITTED_KEY = "TYREFIT_NOT_FITTED"
_NOT_FITTED_NAMES = frozenset(["fx", "fy", "mz", "mx", "my", "combined"])
_PART_CHANNEL = {"longitudinal": "fx", "lateral": "fy", "aligning": "mz"}


def parse_not_fitted(comments) -> frozenset[str]:
    """Channels named in a ``TYREFIT_NOT_FITTED = ...`` comment line (empty when there is none)."""
    out: set[str] = set()
    for line in comments or ():
        text = str(line).strip()
        if not text.upper().startswith(NOT_FITTED_KEY):
            continue
        rest = text[len(NOT_FITTED_KEY):].lstrip()
        if not rest.startswith("="):
            continue
        out.update(w for w in (x.strip().lower() for x in rest[1:].replace(";", ",").split(","))
                   if w in _NOT_FITTED_NAMES)
    return frozenset(out)

#: coefficients without which a part of an MF tyre cannot be evaluated (the others default to 0, L* to 1)
REQUIRED_MF: dict[str, tuple[str, ...]] = {
    "general": ("FNOMIN", "UNLOADED_RADIUS", "LONGVL"),
    "longitudinal": ("PCX1", "PDX1", "PKX1"),
    "lateral": ("PCY1", "PDY1", "PKY1", "PKY2"),
    "aligning": ("QBZ1", "QCZ1", "QDZ1"),
}


@dataclass(eq=False)
class MFTyre(Tyre):
    """A Magic Formula 5.2 or 6.1/6.2 tyre read from a property file.

    Attributes
    ----------
    params : dict
        upper-case ``.tir`` key -> value; dimensional values in SI.
    family : str
        'MF52' or 'MF61'.
    version : str
        '5.2', '6.1' or '6.2' (6.2 is evaluated as 6.1).
    declared_format : str
        the file's ``PROPERTY_FILE_FORMAT`` (or FITTYP) as declared.
    ranges : dict
        declared validity ranges (SI) from the ``[*_RANGE]`` sections.
    tables : dict
        the file's curve and shape tables, as read.
    """

    params: dict[str, float] = field(default_factory=dict)
    family: str = "MF61"
    version: str = "6.1"
    declared_format: str = ""
    name: str = "MF tyre"
    tyreside: str = "LEFT"
    fnomin: float | None = None
    unloaded_radius: float | None = None
    width: float | None = None
    nominal_pressure: float | None = None
    nominal_speed: float | None = None
    ranges: dict[str, tuple[float, float]] = field(default_factory=dict)
    header: list[str] = field(default_factory=list)
    tables: dict[str, Any] = field(default_factory=dict)
    source: str = ""
    #: channels declared not fitted (``TYREFIT_NOT_FITTED`` comment); None: read from ``header``
    not_fitted: frozenset | None = None
    #: what the reader had to assume about the file (a missing ``[MODEL]`` section); not written back
    file_notes: list[str] = field(default_factory=list)

    combined = True
    outputs = ("fx", "fy", "mz", "mx", "my")

    def __post_init__(self) -> None:
        self.params = {str(k).upper(): float(v) for k, v in dict(self.params).items()}
        if self.family not in ("MF52", "MF61"):
            raise ModelError(f"MF family must be 'MF52' or 'MF61', got {self.family!r}")
        self.not_fitted = frozenset(parse_not_fitted(self.header) if self.not_fitted is None
                                    else (str(x).lower() for x in self.not_fitted))
        um = self.use_mode
        digit = None if um is None else abs(um) % 10
        self._computed = frozenset(USE_MODE_OUTPUTS.get(digit, USE_MODE_OUTPUTS[4])) - self.not_fitted
        # USE_MODE 3 (uncombined), or no combined-slip data: each slip alone
        self.combined = digit != 3 and "combined" not in self.not_fitted
        # MF 5.2 has no pressure terms (unless the file carries MF 6.1 ones, applied as MFeval does:
        # tyrefit.models.mf61 notes); both respond to speed (LMUV, low-speed reductions, My)
        self.inputs = ("fz", "slip_angle", "slip_ratio", "camber", "speed") + (
            ("pressure",) if self.family == "MF61" or self._pressure_52 else ())

    # -- the Tyre interface ---------------------------------------------------------
    def forces(self, fz, slip_angle=0.0, slip_ratio=0.0, camber=0.0, pressure=None, speed=None):
        """Fx, Fy, Mz, Mx, My (SI, ISO-W), combined slip (see :mod:`tyrefit.models.mf61`).

        ``pressure`` defaults to the file's INFLPRES (else NOMPRES); ``speed``
        to LONGVL.  Points with ``fz <= 0`` give zeros; a part the file does
        not model (all its coefficients zero or absent) gives NaN.
        """
        p0 = self.params.get("INFLPRES", self.nominal_pressure)
        v0 = self.nominal_speed
        fz, sa, sr, cam = np.broadcast_arrays(*(np.asarray(x, dtype=float)
                                                for x in (fz, slip_angle, slip_ratio, camber)))
        pr = np.broadcast_to(np.asarray(p0 if pressure is None else pressure, dtype=float), fz.shape) \
            if (pressure is not None or p0 is not None) else None
        vv = np.broadcast_to(np.asarray(v0 if speed is None else speed, dtype=float), fz.shape) \
            if (speed is not None or v0 is not None) else None
        on = fz > 0
        fzs = np.where(on, fz, self.fnomin or 1.0)
        with np.errstate(all="ignore"):
            out = _mf61.forces(self.params, fzs, slip_ratio=sr, slip_angle=sa, camber=cam, pressure=pr, speed=vv,
                               version=self.family)
            if not self.combined:  # USE_MODE 3: Fx, My at alpha = 0; Fy, Mz, Mx at kappa = 0
                zero = np.zeros_like(fzs)
                ox = _mf61.forces(self.params, fzs, slip_ratio=sr, slip_angle=zero, camber=cam, pressure=pr,
                                  speed=vv, version=self.family)
                oy = _mf61.forces(self.params, fzs, slip_ratio=zero, slip_angle=sa, camber=cam, pressure=pr,
                                  speed=vv, version=self.family)
                out = {k: (ox if k in ("fx", "my") else oy)[k] for k in out}
        has = {"fx": self.has_longitudinal, "fy": self.has_lateral, "mz": self.has_aligning,
               "mx": self.has_overturning, "my": self.has_rolling}
        return {k: (np.where(on, np.broadcast_to(np.asarray(v, dtype=float), fz.shape), 0.0) if has.get(k, True)
                    else np.full(fz.shape, np.nan))  # a part the file does not model: NaN, as Pac89Tyre
                for k, v in out.items() if k in ("fx", "fy", "mz", "mx", "my")}

    @property
    def _pressure_52(self) -> bool:
        """An MF 5.2 file with MF 6.1 pressure terms and NOMPRES (evaluated with them, as MFeval)."""
        return self.family == "MF52" and _mf61._pressure_52(self.params)

    @property
    def use_mode(self) -> int | None:
        """The file's ``USE_MODE`` as an integer (None when absent or not an integer)."""
        v = self.params.get("USE_MODE")
        if v is None or not np.isfinite(v) or v != int(v):
            return None
        return int(v)

    def _has(self, part: str) -> bool:
        """The file models ``part``: USE_MODE computes it, it is not declared not fitted,
        and one of its required coefficients is given and non-zero.

        Fitting houses write the parts they did not fit as zeros (Stackpole's
        TTC PAC2002 files, ``USE_MODE = 2``: 'Fy, Mx, Mz only', every Fx
        coefficient 0); such a part is absent, not unphysical.
        """
        return _PART_CHANNEL[part] in self._computed and any(self.params.get(k, 0.0) != 0.0
                                                             for k in REQUIRED_MF[part])

    @property
    def has_overturning(self) -> bool:
        """Mx is computed (USE_MODE, not declared not fitted) and the lateral part exists."""
        return "mx" in self._computed and self.has_lateral

    @property
    def has_rolling(self) -> bool:
        """My is computed (USE_MODE, not declared not fitted)."""
        return "my" in self._computed

    @property
    def has_lateral(self) -> bool:
        return self._has("lateral")

    @property
    def has_longitudinal(self) -> bool:
        return self._has("longitudinal")

    @property
    def has_aligning(self) -> bool:
        return self._has("aligning")

    @property
    def missing(self) -> list[str]:
        """Required coefficients the file does not give (a part absent altogether is not listed)."""
        out = [k for k in REQUIRED_MF["general"] if k not in self.params]
        parts = [p for p in ("longitudinal", "lateral", "aligning") if self._has(p)]
        if not parts:
            parts = ["longitudinal", "lateral"]
        for part in parts:
            out += [k for k in REQUIRED_MF[part] if k not in self.params]
        if self.family == "MF61" and "NOMPRES" not in self.params:  # dpi = (p - NOMPRES)/NOMPRES (4.E2b)
            out.append("NOMPRES")
        return out

    # -- checks ---------------------------------------------------------------------
    def factors(self, fz, camber=0.0, pressure=None) -> dict[str, np.ndarray]:
        """Pure-slip Magic Formula factors at load [N], camber [rad], pressure [Pa].

        Cx, mux (Dx/Fz), Ex (for kappa > 0 and < 0), Kxk; Cy, muy, Ey (alpha > 0
        and < 0), Kya; Ct, Et bounds for Mz.  Pacejka (2012) (4.E11)-(4.E25),
        (4.E40)-(4.E44); MF 5.2 where it differs (no pressure terms,
        Kya = PKY1 Fz0 sin(2 atan(Fz/(PKY2 Fz0))) (1 - PKY3 |gamma|)).
        """
        p = self.params

        def g(k, d=0.0):
            return p.get(k, d)

        def s(k):  # scaling factors default to 1
            return p.get(k, 1.0)

        fz = np.asarray(fz, dtype=float)
        gam = np.asarray(camber, dtype=float)
        fz0 = g("FNOMIN", 1.0) * s("LFZO")  # (4.E1)
        dfz = (fz - fz0) / fz0  # (4.E2a)
        if (self.family == "MF61" or self._pressure_52) and g("NOMPRES") > 0:
            pr = self.params.get("INFLPRES", g("NOMPRES")) if pressure is None else pressure
            dpi = (np.asarray(pr, dtype=float) - g("NOMPRES")) / g("NOMPRES")  # (4.E2b)
        else:
            dpi = 0.0 * fz
        mf61 = self.family == "MF61"
        out = {}
        out["Cx"] = g("PCX1") * s("LCX") + 0 * fz  # (4.E11)
        out["mux"] = ((g("PDX1") + g("PDX2") * dfz) * (1 + g("PPX3") * dpi + g("PPX4") * dpi**2)
                      * (1 - g("PDX3") * gam**2) * s("LMUX"))  # (4.E13)
        ex = (g("PEX1") + g("PEX2") * dfz + g("PEX3") * dfz**2) * s("LEX")  # (4.E14)
        out["Ex+"], out["Ex-"] = ex * (1 - g("PEX4")), ex * (1 + g("PEX4"))
        out["Kxk"] = (fz * (g("PKX1") + g("PKX2") * dfz) * np.exp(g("PKX3") * dfz)
                      * (1 + g("PPX1") * dpi + g("PPX2") * dpi**2) * s("LKX"))  # (4.E15)
        out["Cy"] = g("PCY1") * s("LCY") + 0 * fz  # (4.E21)
        out["muy"] = ((g("PDY1") + g("PDY2") * dfz) * (1 + g("PPY3") * dpi + g("PPY4") * dpi**2)
                      * (1 - g("PDY3") * gam**2) * s("LMUY"))  # (4.E23)
        ey0 = (g("PEY1") + g("PEY2") * dfz) * s("LEY")
        ecam = 1 + g("PEY5") * gam**2  # PEY5 = 0 in a plain MF 5.2 file
        shift = g("PEY3") + g("PEY4") * gam
        out["Ey+"], out["Ey-"] = ey0 * (ecam - shift), ey0 * (ecam + shift)  # (4.E24)
        if mf61:
            den = (g("PKY2") + g("PKY5") * gam**2) * (1 + g("PPY2") * dpi) * fz0
            with np.errstate(divide="ignore", invalid="ignore"):
                out["Kya"] = (g("PKY1") * fz0 * (1 + g("PPY1") * dpi) * (1 - g("PKY3") * np.abs(gam))
                              * np.sin(g("PKY4", 2.0) * np.arctan(fz / den)) * s("LKY"))  # (4.E25)
        else:  # MF 5.2 (with PKY5, PPY1, PPY2 when the file carries them, as MFeval)
            with np.errstate(divide="ignore", invalid="ignore"):
                out["Kya"] = (g("PKY1") * fz0 * (1 + g("PPY1") * dpi)
                              * np.sin(g("PKY4", 2.0) * np.arctan(fz / ((g("PKY2") + g("PKY5") * gam**2)
                                                                       * (1 + g("PPY2") * dpi) * fz0)))
                              * (1 - g("PKY3") * np.abs(gam)) * s("LKY"))
        out["Ct"] = g("QCZ1") + 0 * fz  # (4.E41)
        et = g("QEZ1") + g("QEZ2") * dfz + g("QEZ3") * dfz**2  # (4.E44), atan term bounded by +/-1
        bound = np.abs(g("QEZ4") + g("QEZ5") * gam)
        out["Et_max"] = np.maximum(et * (1 + bound), et * (1 - bound))
        return out

    def on_road(self, friction: float) -> "MFTyre":
        """This tyre on a road of ``friction`` x the test surface's friction (:meth:`Tyre.on_road`):
        LMUX and LMUY, the friction scaling factors of (4.E13) and (4.E23), multiplied by ``friction``
        (Pacejka 2012, Sec. 4.3.2); the slip stiffnesses (4.E15, 4.E25) do not carry them."""
        f = self._check_friction(friction)
        p = dict(self.params)
        for k in ("LMUX", "LMUY"):
            p[k] = float(p.get(k, 1.0)) * f
        return replace(self, params=p, name=self.name if f == 1.0 else f"{self.name} (road friction x{f:g})")

    def check(self, n: int = 41) -> list[str]:
        """Problems that make the tyre unusable (empty when physical).

        Conditions (Pacejka 2012, 4.E11-4.E25, 4.E41-4.E44), over the declared
        load, camber and pressure ranges: Cx = PCX1 LCX > 0, Cy = PCY1 LCY > 0,
        Ct = QCZ1 > 0, mu_x and mu_y non-zero and of one sign, PKY2 != 0
        (D = mu Fz may be negative: B = K / (C D) takes its sign, so the
        slope and the peak |D| are unchanged -- MF-Tool 5.0 files such as
        Goodyear's 335/65R22.5 in Project Chrono have PDY1 < 0 with PKY1 < 0); at the nominal point
        (FNOMIN, zero camber, nominal pressure): Ex <= 1 and Ey <= 1 for both
        slip signs, Kxk > 0, Kya != 0, Et <= 1; every required coefficient
        given (:attr:`missing`); then finite forces on a grid over the ranges
        (pure and combined slip).  E > 1 or a lost stiffness towards the edges
        of the declared range only (common in vendor files, whose ranges
        reach far beyond the measured loads) is reported by :meth:`warnings`.
        """
        problems = [f"required coefficient {k} is missing" for k in self.missing]
        positive = ["FNOMIN", "UNLOADED_RADIUS", "LONGVL"] + (["NOMPRES"] if self.family == "MF61" else [])
        problems += [f"{k} = {self.params[k]:g} must be positive (the MF equations divide by it)"
                     for k in positive if k in self.params and not self.params[k] > 0]
        if problems:
            return problems
        problems += self._factor_problems(n, hard=True)
        if not problems:
            problems += self._finite_problems(n)
        return problems

    def warnings(self, n: int = 41) -> list[str]:
        """Questionable but evaluable: E > 1, Kxk <= 0, Kya = 0 or changing sign, or mu > 5 inside the range;
        MF 6.1-only coefficients in an MF 5.2 file, which the 5.2 equations do not use."""
        out = self._factor_problems(n, hard=False)
        raw = self.params.get("USE_MODE")
        if raw is not None and self.use_mode is None:
            out.append(f"USE_MODE = {raw:g} is not an integer; every part is evaluated, combined")
        elif self.use_mode is not None:
            if abs(self.use_mode) % 10 not in USE_MODE_OUTPUTS:
                out.append(f"USE_MODE = {self.use_mode}: last digit {abs(self.use_mode) % 10} is not 0-5; "
                           "every part is evaluated, combined")
            if self.use_mode < 0:
                out.append(f"USE_MODE = {self.use_mode} < 0 asks Adams to mirror the tyre characteristics; tyrefit "
                           "evaluates the coefficients as written")
        if self.family == "MF52":
            applied = [k for k in _mf61.APPLIED_61_IN_52 if self.params.get(k, 0.0) != 0.0]
            if "NOMPRES" not in self.params or not self.params["NOMPRES"] > 0:
                applied = [k for k in applied if not k.startswith("PP")]
            unused = [k for k in _MF61_ONLY if self.params.get(k, 0.0) != 0.0 and k not in applied]
            if applied:
                out.append("MF 5.2 file with MF 6.1-only coefficients, applied as MFeval's FITTYP 6 path does (a "
                           f"strict MF 5.2 evaluator drops them): {', '.join(applied)}")
            if unused:
                out.append("MF 6.1-only coefficients not used in an MF 5.2 file (MFeval's FITTYP 6 path keeps the 5.2 "
                           f"camber stiffness and My; pressure terms need NOMPRES): {', '.join(unused)}")
        return out

    def _factor_problems(self, n: int, hard: bool) -> list[str]:
        v = self.validity()
        lo, hi = v["fz"]
        if hard:
            fz0 = self.fnomin or 0.5 * (lo + hi)
            fz_grid = np.linspace(lo, hi, n)[:, None, None]
            nominal = np.array([[[fz0]]])
        else:
            fz_grid = np.linspace(lo, hi, n)[:, None, None]
            nominal = fz_grid
        cam = np.unique(np.linspace(*v["camber"], 5))[None, :, None]
        pr = np.unique(np.asarray(v.get("pressure", (np.nan, np.nan)), float))[None, None, :]
        pr = None if np.all(np.isnan(pr)) else pr
        with np.errstate(all="ignore"):
            f = self.factors(fz_grid, cam, pr)
            f0 = self.factors(nominal, 0.0 * cam[:, :1] if hard else cam, None if hard else pr)
        span = f"(checked Fz {lo:.0f}-{hi:.0f} N)"
        at0 = " at the nominal load" if hard else ""
        everywhere, nominal_tests = [], []
        if self.has_longitudinal:
            everywhere += [("longitudinal", "Cx = PCX1 LCX <= 0", ~(f["Cx"] > 0)),
                           ("longitudinal", "mu_x = 0 or changes sign (PDX1, PDX2)", _not_one_sign(f["mux"]))]
            nominal_tests += [("longitudinal", "Ex > 1 (PEX1..PEX4)", ~((f0["Ex+"] <= 1) & (f0["Ex-"] <= 1))),
                              ("longitudinal", "Kxk <= 0 (PKX1..PKX3)", ~(f0["Kxk"] > 0))]
            if not hard:
                nominal_tests.append(("longitudinal", "mu_x > 5", f0["mux"] > 5))
        if self.has_lateral:
            ky = f0["Kya"]
            everywhere += [("lateral", "Cy = PCY1 LCY <= 0", ~(f["Cy"] > 0)),
                           ("lateral", "mu_y = 0 or changes sign (PDY1, PDY2)", _not_one_sign(f["muy"]))]
            nominal_tests += [("lateral", "Ey > 1 (PEY1..PEY5)", ~((f0["Ey+"] <= 1) & (f0["Ey-"] <= 1))),
                              ("lateral", "Kya = 0 or undefined (PKY1, PKY2)", ~(np.abs(ky) > 0))]
            if not hard:
                nominal_tests.append(("lateral", "mu_y > 5", f0["muy"] > 5))
        if self.has_aligning:
            everywhere.append(("aligning", "Ct = QCZ1 <= 0", ~(f["Ct"] > 0)))
            nominal_tests.append(("aligning", "Et > 1 (QEZ1..QEZ5)", ~(f0["Et_max"] <= 1)))
        problems = []
        if hard and self.has_lateral and self.params.get("PKY2", 0.0) == 0.0 and "PKY2" not in self.missing:
            problems.append("lateral model is not physical: PKY2 = 0 (Kya = PKY1 Fz0 sin(PKY4 atan(Fz/(PKY2 "
                            "Fz0))) is undefined)")
        if not hard and self.has_lateral:
            ky = f0["Kya"]
            if np.all(np.isfinite(ky)) and np.any(ky > 0) and np.any(ky < 0):
                problems.append(f"lateral: the cornering stiffness Kya changes sign inside the declared range {span}")
        tests = [(*t, fz_grid) for t in (everywhere if hard else [])] + [(*t, nominal) for t in nominal_tests]
        for part, what, bad, src in tests:
            bad = np.asarray(bad)
            if np.any(bad):
                b = np.broadcast_to(bad, np.broadcast_shapes(bad.shape, src.shape))
                row = int(np.argmax(np.any(b.reshape(b.shape[0], -1), axis=1)))
                where = f"Fz = {src[row, 0, 0]:.0f} N"
                label = "is not physical" if hard else "is questionable"
                problems.append(f"{part} model {label}: {what} at {where}{at0 if src is nominal else ''} {span}")
        return problems

    def coefficient_table(self) -> list[dict]:
        return [{"name": k, "value": v} for k, v in self.params.items()]

    def to_tir(self, path, force: bool = False):
        """Write the tyre as an MF 6.1 (``FITTYP = 61``) property file, every coefficient, the ranges it declares.

        A fitted tyre (``tyrefit.fit(...).tyre``) is written as ``fit`` writes it (the physical-validity
        contract checked, the fit's header); any other is written from its parameters and ranges after the
        reader's own check (:meth:`check`), so a file tyrefit writes is one its ``eval`` reads.
        """
        from pathlib import Path


        res = getattr(self, "_result", None)
        if res is not None:
            return res.write_tir(path, force=force)
        problems = self.check()
        if problems:
            raise ModelError(f"{self.name}: not written, the tyre is not physical over its declared range: "
                             f"{problems[0]}")
        write_mf_tir(self.params, path, ranges=self.ranges or None, header=tuple(self.header or ()),
                     force=force, version="5.2" if self.family == "MF52" else "6.1")
        return Path(path)

    def to_json(self, path, force: bool = False):
        """Chrono's JSON is a PAC89 format; a Magic Formula tyre is exchanged as its ``.tir`` (:meth:`to_tir`)."""
        raise ModelError(f"{self.name}: Chrono's JSON (Pac89Tire) holds a PAC89 tyre; write this Magic Formula tyre "
                         "with to_tir(path), which Chrono's Pac02Tire and MF readers load")


#: coefficients of MF 6.1 that tyrefit's MF 5.2 evaluation does not read (checked by changing each one; teasit's
#: 'v52' FSAE export carries PPX1..PPY5, PKY5..PKY7, PEY5 with FITTYP = 6)
_MF61_ONLY = ("PPX1", "PPX2", "PPX3", "PPX4", "PPY1", "PPY2", "PPY3", "PPY4", "PPY5", "PPZ1", "PPZ2", "PPMX1",
              "PKY5", "PKY6", "PKY7", "PEY5", "QDZ10", "QDZ11", "RBX3", "RBY4", "QSX4", "QSX5", "QSX6", "QSX7",
              "QSX8", "QSX9", "QSX10", "QSX11", "QSX12", "QSX13", "QSX14", "QSY5", "QSY6", "QSY7", "QSY8")


def _not_one_sign(mu: np.ndarray) -> np.ndarray:
    """True where the friction factor is zero, not finite, or of the other sign than at most points.

    The Magic Formula's peak is |D| = |mu| Fz whatever the sign of D (B = K / (C D)
    follows it), so only a zero or a sign change inside the range breaks the curve.
    """
    mu = np.asarray(mu, dtype=float)
    sign = 1.0 if np.sum(mu > 0) >= np.sum(mu < 0) else -1.0
    return ~(sign * mu > 0)
