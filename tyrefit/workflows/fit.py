"""The fit workflow: rig records to a finished tyre, the one code path of ``tf.fit``, ``tyrefit fit`` and
``tyrefit batch fit``.

PAC89 (:func:`fit_pac89_record`)
    Dynamic-rig slip-angle and slip-ratio data (or a file with both) go straight to
    :func:`tyrefit.fitting.fit_pac89`.  Static-rig (STTR) tests are first turned into slip-angle data
    by :func:`tyrefit.rig.prepare_static_fit` (Komana et al. Eq. 1, which needs the contact-patch
    length ``patch``; ``rig`` for the calibrated f(dy/L), ``vertical`` for VERTICAL_STIFFNESS); the
    static test's shape factor C (Eq. 2) and peak-friction law are held in the fit.  With ``effects``
    the diagnose start model and the start model plus those effects
    (:func:`tyrefit.effects.resolve_pac89`) are both fitted; the tyre holds the latter.  The size and
    rated load complete the design data (:func:`tyrefit.tyres.size.with_design`).

Magic Formula 5.2 / 6.1 (:func:`fit_mf_records`)
    The records (a cornering and a drive/brake record of one tyre, say) are gathered and fitted in
    stages by :func:`tyrefit.fitting.mf.fit_mf`; the design data come from the data, the size and
    documented estimates, else template placeholders named in the header
    (:func:`tyrefit.tyres.size.complete_mf_design`).

Magic Formula design data.  A Magic Formula file carries geometry,
pressure, inertia and stiffness that force data rarely give.  Each written
value has one of four origins, said in the header and on the console:

1. **the data**: NOMPRES = INFLPRES is the middle pressure level of a
   ``pressure`` column; a ``loaded_radius`` channel (TTC's RL) gives
   UNLOADED_RADIUS and VERTICAL_STIFFNESS as the intercept and the inverse
   slope of a straight line R_l = R0 - Fz / c_z over the loaded samples (the
   linear part of MF 6.1's vertical model, Pacejka (2012) (A3.4), with
   Q_FZ2 = 0);
2. **``size``** (``385/65R22.5``): UNLOADED_RADIUS (when the data give none),
   WIDTH, ASPECT_RATIO, RIM_RADIUS; **``rated_load``**: FNOMIN;
3. **documented estimates** from the size (:func:`tyrefit.tyres.size.design_estimates`,
   the same rules as the PAC89 and Chrono writers): MASS, IXX, IYY,
   VERTICAL_STIFFNESS, LATERAL_STIFFNESS, VERTICAL_DAMPING, each line marked
   ESTIMATED;
4. otherwise **placeholders**: the 205/60R15 template of
   :func:`tyrefit.models.mf61.neutral`, listed per section under
   ``PLACEHOLDER`` in the header and summarised on the console -- never
   written silently.  UNLOADED_RADIUS enters the Mz, Mx and My equations, so
   the fitted aligning and moment coefficients belong with the radius written
   beside them.

Every record is checked for a mirrored tyre first (:func:`tyrefit.io.plausibility.check_mirrored`):
refused unless ``allow_mirrored``; the findings allowed are kept in ``result.plausibility``.

Coefficients given as ``params`` (an :class:`lmfit.Parameters`, read by :func:`read_params` without
importing lmfit, so the command line never loads it):

* ``value``: the start value of a varied coefficient (the first start of the multi-start, whose lowest
  cost wins; a coefficient the data cannot identify is held at it);
* ``vary=False``: held at ``value`` (PAC89 ``fixed``, MF ``fixed``);
* ``min`` / ``max``: bounds, intersected with the physical ones (PAC89 only; a bounded member of a
  linear load law is fitted in its own coefficient and the law's ends are checked after the fit);
  bounds on Magic Formula coefficients are refused;
* ``expr``: evaluated by lmfit at the values given and held there: an expression is not a
  constraint during the fit, and the result's notes say so.

``result.lmfit_params()`` then shows the held coefficients with ``vary=False`` and the bounds given.
"""

from __future__ import annotations

import copy
import math
import os
import re
import warnings
from collections.abc import Sequence
from dataclasses import dataclass, field, replace
from pathlib import Path

from ..errors import DataError, close_matches, option
from ..io.plausibility import check_mirrored
from ..io.readers import check_fittable, read_data
from ..tyres.size import with_design, complete_mf_design, loaded_radius_law, size_and_rated_load
from ..effects import EFFECTS, resolve_pac89
from ..fitting import fit_pac89
from ..fitting.mf import _known_names as _mf_names, fit_mf, prepare_mf_data
from ..models.pac89 import ALL as _PAC89_NAMES
from ..rig import RigCalibration, prepare_static_fit

__all__ = ["fit", "fit_pac89_record", "fit_mf_records", "read_checked", "static_input", "read_params", "ParamsGiven",
           "MODELS", "COSTS"]

MODELS = ("pac89", "mf52", "mf61")
COSTS = ("l2", "l1", "soft_l1", "huber")


def _is_dataset(x) -> bool:
    return hasattr(x, "df") and hasattr(x, "kind")


def read_checked(item, convention: str = "iso", allow_mirrored: bool = False):
    """A record read (or taken as it is) and checked for a mirrored tyre; ``(dataset, plausibility notes)``."""
    ds = item if _is_dataset(item) else read_data(os.fspath(item), convention=convention)
    return ds, check_mirrored(ds, allow=allow_mirrored)


# --------------------------------------------------------------------------- params= (lmfit Parameters)

@dataclass
class ParamsGiven:
    """What an :class:`lmfit.Parameters` given as ``params`` asks of a fit, in the family's names."""

    family: str
    #: varied coefficients with a finite value: their start values
    start: dict[str, float] = field(default_factory=dict)
    #: ``vary=False`` or an expression: held at these values
    held: dict[str, float] = field(default_factory=dict)
    #: a finite ``min`` or ``max``: (min, max)
    bounds: dict[str, tuple[float, float]] = field(default_factory=dict)
    #: name -> expression (evaluated at the values given; its value is in ``held``)
    exprs: dict[str, str] = field(default_factory=dict)

    def notes(self) -> list[str]:
        """What the fit did with them, for the result's notes."""
        out = []
        if self.start:
            out.append("params=: start values given for " + ", ".join(self.start))
        plain = [f"{k} = {v:.6g}" for k, v in self.held.items() if k not in self.exprs]
        if plain:
            out.append("params=: held (vary=False) at " + ", ".join(plain))
        for k, e in self.exprs.items():
            out.append(f"params=: {k} = {e!r} held at {self.held[k]:.6g}, its value at the values given: an "
                       "expression is evaluated once, before the fit, and is not a constraint during it")
        if self.bounds:
            out.append("params=: bounds " + ", ".join(f"{k} [{lo:g}, {hi:g}]" for k, (lo, hi) in self.bounds.items()))
        return out


_MF_COEFFICIENT = re.compile(r"[PQRS][A-Z]{1,3}\d+|L(?!ONGVL)[A-Z]+")  # as FitResultMF.lmfit_params


def _family_names(model: str) -> tuple[set, str]:
    if model == "pac89":
        return set(_PAC89_NAMES), "a PAC89 coefficient (accepted a0..a13, b0..b10, c0..c17)"
    return ({k for k in _mf_names() if _MF_COEFFICIENT.fullmatch(k)},
            "a Magic Formula coefficient (P*, Q*, R*, S* or an L* scaling factor; design data come from the "
            "data, size= and rated_load=)")


def read_params(params, model: str = "pac89") -> ParamsGiven | None:
    """``params`` (an :class:`lmfit.Parameters`, or None) as start values, holds, bounds and expressions.

    Read through the attributes lmfit's parameters have (``value``, ``vary``, ``min``, ``max``, ``expr``),
    so lmfit is not imported here.  Expressions are evaluated by lmfit (``update_constraints``) on a copy.
    """
    if params is None or isinstance(params, ParamsGiven):
        return params
    if not hasattr(params, "items") or not all(hasattr(p, "value") for _, p in params.items()):
        raise DataError(f"params=: an lmfit.Parameters (name -> Parameter with value, vary, min, max, expr); got "
                        f"{type(params).__name__}")
    params = copy.deepcopy(params)
    if hasattr(params, "update_constraints"):
        try:
            params.update_constraints()
        except Exception as e:  # lmfit's asteval: an unknown name or a bad expression
            raise DataError(f"params=: an expression could not be evaluated: {e}") from e
    family = "pac89" if model == "pac89" else "mf"
    names, what = _family_names(model)
    norm = str.lower if family == "pac89" else str.upper
    out = ParamsGiven(family)
    bad = [k for k, _ in params.items() if norm(str(k)) not in names]
    if bad:
        raise DataError(f"params=: {', '.join(map(str, bad))} not {what}" + close_matches(norm(str(bad[0])), names))
    for key, p in params.items():
        k = norm(str(key))
        expr = getattr(p, "expr", None) or None
        v = float(p.value)
        lo = -math.inf if getattr(p, "min", None) is None else float(p.min)
        hi = math.inf if getattr(p, "max", None) is None else float(p.max)
        if expr is not None or not bool(getattr(p, "vary", True)):
            if not math.isfinite(v):
                raise DataError(f"params=: {key} is held (vary=False or expr) but its value is {v:g}; give a value")
            out.held[k] = v
            if expr is not None:
                out.exprs[k] = str(expr)
        elif math.isfinite(v):
            out.start[k] = v
        if math.isfinite(lo) or math.isfinite(hi):
            if family == "mf":
                raise DataError(f"params=: bounds on MF coefficients are not supported yet: {key} [{lo:g}, {hi:g}] "
                                "(hold it with vary=False, or leave min and max at -inf and inf)")
            out.bounds[k] = (lo, hi)
    return out


def fit(data, *, model: str = "pac89", cost: str = "l2", effects: Sequence[str] | str | None = None,
        size: str | None = None, rated_load: float | None = None, patch=None, rig=None, vertical=None,
        static_part: str = "peak", convention: str = "iso", allow_mirrored: bool = False, params=None):
    """Fit a tyre to rig data; see :func:`tyrefit.api.fit` for the parameters.

    Returns the fit result with ``plausibility`` (the mirrored-tyre findings allowed), and for PAC89
    ``extras`` (``static``, ``start``, ``effects``, ``notes``, ``dataset``), for a Magic Formula fit
    ``start`` (the start-model fit when ``effects`` are given, else None).
    """
    if model not in MODELS:
        raise DataError(f"model={model!r}: one of {', '.join(MODELS)}")
    if cost not in COSTS:
        raise DataError(f"cost={cost!r}: one of {', '.join(COSTS)}")
    if convention not in ("iso", "sae"):
        raise DataError(f"convention={convention!r}: 'iso' or 'sae'")
    items = list(data) if isinstance(data, (list, tuple)) else [data]
    if not items:
        raise DataError("data: give at least one record")
    given = read_params(params, model)
    eff = _effect_ids(effects)
    if model != "pac89":
        for name, v in (("patch", patch), ("rig", rig), ("vertical", vertical)):
            if v is not None:
                raise DataError(f"{name}=: static-rig inputs are for model='pac89'; a Magic Formula fit takes "
                                "dynamic-rig slip sweeps")
        sets, plaus = [], []
        for item in items:
            ds, found = read_checked(item, convention, allow_mirrored)
            sets.append(ds)
            plaus += found
        name = Path(str(getattr(items[0], "source", items[0]))).stem
        result = fit_mf_records(sets, model=model, cost=cost, effects=eff, size=size, rated_load=rated_load,
                                name=name, params=given)
        result.plausibility = plaus
        return result
    if len(items) > 1:
        raise DataError(f"data: {len(items)} records; a PAC89 tyre is fitted to one record (several records of "
                        "one tyre need model='mf61' or 'mf52')")
    item = items[0]
    ds, plaus = read_checked(item, convention, allow_mirrored)
    name = str(getattr(item, "source", "") or "data") if _is_dataset(item) else os.fspath(item)
    result = fit_pac89_record(ds, name=name, cost=cost, effects=eff, size=size, rated_load=rated_load,
                              patch=patch, rig=rig, vertical=vertical, static_part=static_part, params=given)
    result.plausibility = plaus
    return result


def _effect_ids(effects) -> list[str]:
    if effects is None:
        return []
    parts = effects.split(",") if isinstance(effects, str) else list(effects)
    return [e.strip() for e in parts if e and e.strip()]


# --------------------------------------------------------------------------- PAC89

def static_input(ds, *, patch=None, rig=None, vertical=None, static_part: str = "peak", rated_load=None,
                 notes: list | None = None):
    """Komana et al. Eq. 1 on a static-rig test: the slip-angle data, anchors and design data to fit."""
    if not patch:
        raise DataError(f"{ds.source}: a static test needs {option('patch', 'PATCH.csv')} for Eq. 1 (contact-patch length)")
    patch_ds = read_data(os.fspath(patch), convention="iso", kind="patch")
    cal = RigCalibration.from_json(os.fspath(rig)) if rig else None
    vertical_ds = read_data(os.fspath(vertical), convention="iso", kind="vertical") if vertical else None
    kw = {"rig": cal, "part": static_part or "peak", "vertical_ds": vertical_ds}
    if rated_load is not None:
        kw["rated_load"] = rated_load
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        sfi = prepare_static_fit(ds, patch_ds, **kw)
    if notes is not None:
        notes += [f"warning: {w.message}" for w in caught]
    return sfi


def _tyre_info(sfi, rated_load, name) -> dict:
    info: dict = {"name": Path(name).stem}
    if sfi is not None:
        info.update(sfi.tyre_info)
    if rated_load is not None:
        info["fnomin"] = float(rated_load)
    return info


def fit_pac89_record(ds, *, name: str, cost: str = "l2", effects: Sequence[str] = (), size: str | None = None,
                     rated_load: float | None = None, patch=None, rig=None, vertical=None,
                     static_part: str = "peak", params=None):
    """A PAC89 tyre from one record already read (the workflow of ``tyrefit fit``, without writing).

    ``name``: the record's file name (the tyre's name and the report's titles).  ``params``: an
    :class:`lmfit.Parameters` of start values, holds, bounds and expressions (:func:`read_params`).  Returns the
    :class:`~tyrefit.fitting.result.FitResult` with ``extras``: ``static`` (the static-rig input or
    None), ``start`` (the start model's fit with ``effects``), ``effects`` (ids), ``notes``, ``dataset``.
    """
    notes: list[str] = []
    tyre_size = size_and_rated_load(size, rated_load)
    notes += [f"dropped {n} samples: {why}" for why, n in ds.meta.get("dropped", {}).items()]
    sfi = None
    if ds.kind == "static":
        sfi = static_input(ds, patch=patch, rig=rig, vertical=vertical, static_part=static_part,
                           rated_load=rated_load, notes=notes)
        data = sfi.data
    elif ds.kind in ("slip_angle", "slip_ratio"):
        if not {"slip_angle", "slip_ratio"} <= set(ds.df.columns):
            check_fittable(ds)
        # a file with both slip-angle and slip-ratio sweeps: each sweep is classified and
        # checked by tyrefit.fitting.prepare_data (combined-slip sweeps are left out, with a note)
        data = ds
    else:
        raise DataError(f"{ds.source}: a {ds.kind} table cannot be fitted to a tyre model; fit needs slip-angle, "
                        "slip-ratio or static-rig lateral tests")
    info = _tyre_info(sfi, rated_load, name)
    # static 'peak' part: C (Eq. 2) and the peak-friction law measured by the static test itself
    fixed = (sfi.anchors or None) if sfi is not None else None
    given = read_params(params, "pac89")
    kw = {}
    if given is not None:
        for k, v in given.held.items():
            if k in (fixed or {}) and fixed[k] != v:
                notes.append(f"params=: {k} held at {v:.6g} given instead of the static test's {fixed[k]:.6g}")
        fixed = {**(fixed or {}), **given.held} or None
        kw = {"initial": dict(given.start), "bounds": dict(given.bounds)}
    extras = {"static": sfi, "start": None, "effects": [], "notes": notes, "dataset": ds}
    effects = list(effects)
    if effects:
        vary0, _ = resolve_pac89([])
        vary1, enotes = resolve_pac89(effects)
        notes += list(enotes)
        # the effects choose lateral coefficients only: the longitudinal and aligning parts keep their full
        # fit (every coefficient the data identify), never silent zeros
        other = [k for k in _PAC89_NAMES if k[0] in "bc"]
        vary0, vary1 = list(vary0) + other, list(vary1) + other
        extras["start"] = fit_pac89(data, cost=cost, vary=vary0, tyre_info=info, fixed=fixed, **kw)
        extras["effects"] = effects
        # the effects' model starts from the start model's solution
        kw1 = dict(kw, initial={**kw.get("initial", {}),
                                **{k: v for k, v in extras["start"].values.items() if k.startswith("a")}})
        result = fit_pac89(data, cost=cost, vary=vary1, tyre_info=info, fixed=fixed, **kw1)
        result.notes.append(f"effects {', '.join(effects)}: start-model RMSE {extras['start'].rmse:.4g} N -> "
                            f"{result.rmse:.4g} N with the effects")
        carried, dropped = _effects_split(effects)
        result.model_label = "PAC89" + (" + " + ", ".join(carried) if carried else " start model")
        for eid, why in dropped:
            result.warnings.append(f"effect {eid} requested but NOT in the model: {why}")
        if dropped:
            result = result.with_tyre(replace(result.tyre, header=result.tyre.header + [
                f"WARNING: effect {eid} requested but NOT in the model: {why}" for eid, why in dropped]))
        extras["effects_carried"], extras["effects_dropped"] = carried, [e for e, _ in dropped]
    else:
        result = fit_pac89(data, cost=cost, tyre_info=info, fixed=fixed, **kw)
    if given is not None:
        notes += given.notes()
    tyre = sfi.with_static_design(result.tyre) if sfi is not None else result.tyre
    tyre, design_notes = with_design(tyre, tyre_size, rated_load)
    result = result.with_tyre(tyre)
    notes += [n for n in design_notes if "ESTIMATED" in n or "not estimated" in n or n.startswith("no tyre size")]
    result.notes.extend(n for n in notes if n not in result.notes)
    result.extras = extras
    return result


def _effects_split(effects):
    """(effects PAC89 carries, [(effect, why) it cannot carry]) from the effects catalogue."""
    carried, dropped = [], []
    for e in effects:
        eff = EFFECTS.get(e)
        if eff is None or eff.representable or eff.pac89 or eff.pac89_approx:
            carried.append(e + ("" if eff is None or eff.representable else " (approximated)"))
        else:
            dropped.append((e, eff.pac89_note))
    return carried, dropped


# --------------------------------------------------------------------------- Magic Formula

def fit_mf_records(sets, *, model: str = "mf61", cost: str = "l2", effects: Sequence[str] = (),
                   size: str | None = None, rated_load: float | None = None, name: str | None = None,
                   params=None):
    """One Magic Formula tyre from records already read (``tyrefit fit --model mf61|mf52``, without writing).

    ``params``: an :class:`lmfit.Parameters` of start values (``value``), holds (``vary=False``) and
    expressions (held at their value); bounds are refused (:func:`read_params`).

    Returns the :class:`~tyrefit.fitting.mf_result.FitResultMF` with ``start`` (the start model's fit
    with ``effects``, else None) and ``placeholders`` (design values from the template).
    """
    for ds in sets:
        if ds.kind not in ("slip_angle", "slip_ratio"):
            raise DataError(f"{ds.source}: a {ds.kind} table cannot be fitted to a Magic Formula tyre; it needs "
                            "slip-angle or slip-ratio sweeps from a dynamic rig")
    data = prepare_mf_data(list(sets))
    info = {"name": name or Path(str(sets[0].source)).stem}
    tyre_size = size_and_rated_load(size, rated_load)
    if rated_load is not None:
        info["fnomin"] = float(rated_load)
    measured = loaded_radius_law(sets)
    if "UNLOADED_RADIUS" in measured:
        info["unloaded_radius"] = measured["UNLOADED_RADIUS"]
    elif tyre_size is not None:
        info["unloaded_radius"] = tyre_size.unloaded_radius
    if tyre_size is not None:
        info["width"] = tyre_size.width
    effects = list(effects)
    kw = {"model": model, "cost": cost or "l2", "tyre_info": info}
    given = read_params(params, model)
    if given is not None:
        kw.update(initial=dict(given.start), fixed=dict(given.held))
    start = None
    if effects:
        start = fit_mf(data, effects=[], **kw)
        result = fit_mf(data, effects=effects, **kw)
        result.notes.append(f"effects {', '.join(effects)}: start-model Fy RMSE {start.rmse:.4g} N -> "
                            f"{result.rmse:.4g} N with the effects")
    else:
        result = fit_mf(data, **kw)
    df = result.data.df
    lines, result.placeholders = complete_mf_design(
        result.params, size=tyre_size, measured=measured, rated_load_given=bool(result.tyre_info.get("fnomin")),
        pressure_from_data="pressure" in df.columns and bool(df["pressure"].notna().any()))
    result.tyre_info["header"] = list(result.tyre_info.get("header", [])) + lines
    if measured.get("note"):
        result.notes.append(f"loaded radius: {measured['note']}")
    if given is not None:
        result.notes.extend(given.notes())
    if "UNLOADED_RADIUS" in result.placeholders:
        result.warnings.append(f"UNLOADED_RADIUS {result.params['UNLOADED_RADIUS']:g} m is a TEMPLATE value (no "
                               "credible loaded-radius channel in the data and no tyre size given): the Mz and Mx "
                               "coefficients were fitted with it; give the size for the tyre's own radius")
    result.start, result.datasets = start, list(sets)
    return result
