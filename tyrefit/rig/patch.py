"""Contact-patch models: length, width and area against load and pressure.

Komana, Els and Becker (Sec. 4.1, Fig. 2) find that the contact
patch of a truck tyre grows in two stages.  Up to the *shoulder load* the
elliptical patch grows faster in width than in length; once it reaches the
tyre shoulders the width stops and only the length grows.  Hence

* length and area: two-gradient piecewise-linear in the load with a
  breakpoint, the shoulder load (:func:`two_gradient`, fitted by
  :func:`fit_two_gradient`);
* width: an exponential rise to the shoulder width (:func:`exp_rise`);
* a higher inflation pressure gives a smaller patch: each parameter follows a
  pressure law across the tested pressures (power law for gradients,
  breakpoints and widths, linear for intercepts; :class:`PatchModel`).

The length L(Fz, p) is what Eq. 1 needs to turn a static lateral
displacement into a slip angle (:mod:`tyrefit.rig.conversion`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
import pandas as pd
from scipy.optimize import minimize_scalar

from ..errors import ColumnError, DataError, FitError
from ..fitting.core import Parameters, solve
from ..nomenclature import G0

__all__ = [
    "two_gradient",
    "exp_rise",
    "TwoGradientFit",
    "ExpRiseFit",
    "PatchFit",
    "PatchModel",
    "fit_two_gradient",
    "fit_exp_rise",
    "fit_patch",
]


# ----------------------------------------------------------------------------- pure model functions
def two_gradient(x, y0, k1, k2, xb):
    """Two-gradient piecewise-linear function (Komana et al., Sec. 4.1, Fig. 2 and 3).

    Parameters
    ----------
    x : array_like
        abscissa (load [N] or deflection [m]).
    y0 : float
        value at x = 0.
    k1, k2 : float
        gradients below and above the breakpoint.
    xb : float
        breakpoint (same unit as ``x``).

    Returns
    -------
    ndarray
        y0 + k1 min(x, xb) + k2 max(x - xb, 0): continuous at ``xb``.
    """
    x = np.asarray(x, float)
    return y0 + k1 * np.minimum(x, xb) + k2 * np.maximum(x - xb, 0.0)


def exp_rise(x, y_max, x_scale):
    """Exponential rise to an asymptote: y_max (1 - exp(-x / x_scale)).

    The contact-patch width against load, saturating at the shoulder width
    (Komana et al., Sec. 4.1: "an exponential trend with an asymptote at the
    shoulder width").
    """
    return y_max * (1.0 - np.exp(-np.asarray(x, float) / x_scale))


# ----------------------------------------------------------------------------- fits
@dataclass
class TwoGradientFit:
    """A fitted :func:`two_gradient` curve.

    Attributes
    ----------
    y0, k1, k2, breakpoint : float
        parameters (units of the data).
    breakpoint_interval : (float, float)
        profile-likelihood ~68 % interval of the breakpoint.
    rmse : float
        root-mean-square residual.
    n : int
        points fitted.
    """

    y0: float
    k1: float
    k2: float
    breakpoint: float
    breakpoint_interval: tuple[float, float]
    rmse: float
    n: int

    def __call__(self, x):
        return two_gradient(x, self.y0, self.k1, self.k2, self.breakpoint)

    def slope(self, x):
        """Gradient at ``x`` (k1 below the breakpoint, k2 above)."""
        return np.where(np.asarray(x, float) <= self.breakpoint, self.k1, self.k2)

    def to_dict(self) -> dict:
        return {"y0": self.y0, "k1": self.k1, "k2": self.k2, "breakpoint": self.breakpoint,
                "breakpoint_interval": list(self.breakpoint_interval), "rmse": self.rmse, "n": self.n}


def _lsq_at(x, y, xb):
    A = np.column_stack([np.ones_like(x), np.minimum(x, xb), np.maximum(x - xb, 0.0)])
    coef, *_ = np.linalg.lstsq(A, y, rcond=None)
    r = y - A @ coef
    return coef, float(r @ r)


def _profile_sse(x, y, grid):
    """Residual sum of squares of the linear fit at every trial breakpoint (batched normal equations)."""
    G = grid[:, None]
    A = np.stack([np.ones((grid.size, x.size)), np.minimum(x, G), np.maximum(x - G, 0.0)], axis=-1)
    AtA = np.einsum("gni,gnj->gij", A, A)
    Aty = np.einsum("gni,n->gi", A, y)
    try:
        coef = np.linalg.solve(AtA, Aty[..., None])[..., 0]
    except np.linalg.LinAlgError:  # a singular trial (all points on one side): fall back
        return np.array([_lsq_at(x, y, g)[1] for g in grid])
    r = y[None, :] - np.einsum("gni,gi->gn", A, coef)
    return np.einsum("gn,gn->g", r, r)


def fit_two_gradient(x, y, *, min_side: int = 2, what: str = "data") -> TwoGradientFit:
    """Fit a two-gradient piecewise-linear curve with a free breakpoint.

    For each trial breakpoint the intercept and both gradients are a linear
    least-squares problem, so the breakpoint is found by profiling: a grid
    search of the residual sum of squares between the ``min_side``-th smallest
    and largest ``x``, then a bounded scalar refinement.

    Parameters
    ----------
    x, y : array_like
        abscissa and ordinate (e.g. load [N] and length [m]).
    min_side : int
        distinct ``x`` values required on each side of the breakpoint.
    what : str
        name used in error messages.

    Returns
    -------
    TwoGradientFit

    Raises
    ------
    DataError
        fewer than ``2 * min_side + 1`` distinct abscissae.
    """
    x = np.asarray(x, float)
    y = np.asarray(y, float)
    ok = np.isfinite(x) & np.isfinite(y)
    x, y = x[ok], y[ok]
    xs = np.unique(x)
    if xs.size < 2 * min_side + 1:
        raise DataError(f"{what}: a two-gradient fit needs at least {2 * min_side + 1} distinct loads, "
                        f"found {xs.size}")
    lo, hi = xs[min_side - 1], xs[-min_side]
    grid = np.linspace(lo, hi, 400)
    sse = _profile_sse(x, y, grid)
    i = int(np.argmin(sse))
    a, b = grid[max(i - 1, 0)], grid[min(i + 1, grid.size - 1)]
    res = minimize_scalar(lambda g: _lsq_at(x, y, g)[1], bounds=(a, b), method="bounded",
                          options={"xatol": 1e-9 * max(abs(hi), 1.0)})
    xb = float(res.x) if res.fun <= sse[i] else float(grid[i])
    coef, s = _lsq_at(x, y, xb)
    dof = max(x.size - 4, 1)
    # profile-likelihood interval: SSE within (1 + 1/dof) of the minimum (Delta chi^2 = 1)
    inside = grid[sse <= s * (1.0 + 1.0 / dof)]
    interval = (float(min(inside.min(), xb)), float(max(inside.max(), xb))) if inside.size else (xb, xb)
    return TwoGradientFit(float(coef[0]), float(coef[1]), float(coef[2]), xb, interval,
                          math.sqrt(s / x.size), int(x.size))


@dataclass
class ExpRiseFit:
    """A fitted :func:`exp_rise` curve (width against load)."""

    y_max: float
    x_scale: float
    rmse: float
    n: int

    def __call__(self, x):
        return exp_rise(x, self.y_max, self.x_scale)

    def saturation_load(self, fraction: float = 0.99) -> float:
        """Load at which the width reaches ``fraction`` of the shoulder width."""
        return -self.x_scale * math.log(1.0 - fraction)

    def to_dict(self) -> dict:
        return {"y_max": self.y_max, "x_scale": self.x_scale, "rmse": self.rmse, "n": self.n}


def fit_exp_rise(x, y, *, what: str = "data") -> ExpRiseFit:
    """Fit y = y_max (1 - exp(-x / x_scale)) by nonlinear least squares."""
    x = np.asarray(x, float)
    y = np.asarray(y, float)
    ok = np.isfinite(x) & np.isfinite(y)
    x, y = x[ok], y[ok]
    if np.unique(x).size < 3:
        raise DataError(f"{what}: the width law needs at least 3 distinct loads, found {np.unique(x).size}")
    ymax0 = float(np.max(y))
    # initial scale from the point closest to 63 % of the maximum
    i = int(np.argmin(np.abs(y - 0.63 * ymax0)))
    xs0 = float(max(x[i], 1e-6 * np.max(x)))
    pars = Parameters()
    pars.add("y_max", ymax0, min=0.0, meaning="saturation value")
    pars.add("x_scale", xs0, min=1e-9, meaning="load scale of the rise")
    try:
        sol = solve(lambda v: exp_rise(x, *v) - y, pars, x_scale=1.0, max_nfev=5000, stderr=False, what=what)
    except FitError as exc:  # pragma: no cover - not finite on pathological data
        raise DataError(f"{what}: the exponential width law did not converge ({exc})") from None
    ym, xs = sol.x
    r = y - exp_rise(x, ym, xs)
    return ExpRiseFit(float(ym), float(xs), float(np.sqrt(np.mean(r**2))), int(x.size))


# ----------------------------------------------------------------------------- per-pressure and model
@dataclass
class PatchFit:
    """Contact-patch fits at one inflation pressure.

    Attributes
    ----------
    pressure : float
        [Pa].
    length, area : TwoGradientFit or None
        length [m] and area [m2] against load [N].
    width : ExpRiseFit or None
        width [m] against load [N].
    loads : ndarray
        loads tested [N].
    """

    pressure: float
    length: TwoGradientFit | None
    area: TwoGradientFit | None
    width: ExpRiseFit | None
    loads: np.ndarray

    @property
    def shoulder_load(self) -> float:
        """The shoulder load [N]: the breakpoint of the length law (NaN without length data)."""
        return self.length.breakpoint if self.length is not None else float("nan")


# parameters carried across pressures and how: power law (positive) or linear
_LAW = {"length": {"y0": "linear", "k1": "power", "k2": "power", "breakpoint": "power"},
        "area": {"y0": "linear", "k1": "power", "k2": "power", "breakpoint": "power"},
        "width": {"y_max": "power", "x_scale": "power"}}


@dataclass
class PressureLaw:
    """theta(p) = theta_ref (p / p_ref)^m (power) or theta_ref + m (p - p_ref) (linear)."""

    kind: str
    ref: float
    m: float

    def __call__(self, p, p_ref):
        p = np.asarray(p, float)
        if self.kind == "power":
            return self.ref * (p / p_ref) ** self.m
        return self.ref + self.m * (p - p_ref)


def _fit_law(kind: str, p: np.ndarray, v: np.ndarray, p_ref: float) -> PressureLaw:
    if p.size < 2:
        return PressureLaw(kind, float(v[0]), 0.0)
    if kind == "power" and np.all(v > 0):
        m, c = np.polyfit(np.log(p / p_ref), np.log(v), 1)
        return PressureLaw("power", float(np.exp(c)), float(m))
    m, c = np.polyfit(p - p_ref, v, 1)
    return PressureLaw("linear", float(c), float(m))


@dataclass
class PatchModel:
    """Contact patch against load and pressure, fitted per pressure plus a pressure law.

    At a tested pressure (within 1 %) the fit of that pressure is used; at
    other pressures the parameters come from the pressure law fitted across
    the tested pressures.

    Attributes
    ----------
    fits : list of PatchFit
        one per tested pressure, by increasing pressure.
    p_ref : float
        reference pressure of the laws [Pa] (the middle tested pressure).
    laws : dict
        ``{'length': {'k1': PressureLaw, ...}, 'area': ..., 'width': ...}``.
    source : str
    """

    fits: list[PatchFit]
    p_ref: float
    laws: dict[str, dict[str, PressureLaw]] = field(default_factory=dict)
    source: str = ""

    # -- evaluation -------------------------------------------------------------------
    @property
    def pressures(self) -> np.ndarray:
        return np.array([f.pressure for f in self.fits])

    def _fit_at(self, pressure):
        if len(self.fits) == 1:  # one pressure tested: no pressure law, used as it is
            return self.fits[0]
        if pressure is None:
            pressure = self.p_ref
        p = float(pressure)
        for f in self.fits:
            if abs(f.pressure - p) <= 0.01 * f.pressure:
                return f
        return p

    def _params(self, what: str, pressure) -> dict[str, float] | None:
        f = self._fit_at(pressure)
        if isinstance(f, PatchFit):
            sub = getattr(f, what)
            if sub is None:
                return None
            return {k: getattr(sub, k) for k in _LAW[what]}
        laws = self.laws.get(what)
        if not laws:
            return None
        return {k: float(law(f, self.p_ref)) for k, law in laws.items()}

    def _need(self, what, pressure):
        prm = self._params(what, pressure)
        if prm is None:
            raise ColumnError(f"{self.source or 'patch data'}: no contact-patch {what} data; add a "
                              f"'{what} [{'cm2' if what == 'area' else 'mm'}]' column")
        return prm

    def length(self, fz, pressure=None):
        """Contact-patch length [m] at load ``fz`` [N] and ``pressure`` [Pa]."""
        q = self._need("length", pressure)
        return two_gradient(fz, q["y0"], q["k1"], q["k2"], q["breakpoint"])

    def area(self, fz, pressure=None):
        """Contact-patch area [m2] at load ``fz`` [N] and ``pressure`` [Pa]."""
        q = self._need("area", pressure)
        return two_gradient(fz, q["y0"], q["k1"], q["k2"], q["breakpoint"])

    def width(self, fz, pressure=None):
        """Contact-patch width [m] at load ``fz`` [N] and ``pressure`` [Pa]."""
        q = self._need("width", pressure)
        return exp_rise(fz, q["y_max"], q["x_scale"])

    def shoulder_load(self, pressure=None) -> float:
        """Shoulder load [N] (breakpoint of the length law) at ``pressure`` [Pa]."""
        return float(self._need("length", pressure)["breakpoint"])

    def has(self, what: str) -> bool:
        return any(getattr(f, what) is not None for f in self.fits)

    def load_range(self) -> tuple[float, float]:
        loads = np.concatenate([f.loads for f in self.fits])
        return float(loads.min()), float(loads.max())

    # -- reporting --------------------------------------------------------------------
    def table(self) -> pd.DataFrame:
        """One row per pressure: breakpoints [kg], gradients, shoulder width [mm], rmse."""
        rows = []
        for f in self.fits:
            r = {"pressure [bar]": f.pressure / 1e5}
            if f.length is not None:
                r.update({"length breakpoint [kg]": f.length.breakpoint / G0,
                          "68% interval [kg]": "%.0f-%.0f" % tuple(np.array(f.length.breakpoint_interval) / G0),
                          "L0 [mm]": 1e3 * f.length.y0,
                          "dL/dF below [mm/t]": 1e3 * f.length.k1 * G0 * 1e3,
                          "dL/dF above [mm/t]": 1e3 * f.length.k2 * G0 * 1e3,
                          "length rmse [mm]": 1e3 * f.length.rmse})
            if f.area is not None:
                r.update({"area breakpoint [kg]": f.area.breakpoint / G0,
                          "dA/dF below [cm2/t]": 1e4 * f.area.k1 * G0 * 1e3,
                          "dA/dF above [cm2/t]": 1e4 * f.area.k2 * G0 * 1e3,
                          "area rmse [cm2]": 1e4 * f.area.rmse})
            if f.width is not None:
                r.update({"shoulder width [mm]": 1e3 * f.width.y_max,
                          "width at 99% [kg]": f.width.saturation_load() / G0,
                          "width rmse [mm]": 1e3 * f.width.rmse})
            rows.append(r)
        return pd.DataFrame(rows)

    def laws_table(self) -> pd.DataFrame:
        rows = []
        for what, laws in self.laws.items():
            for k, law in laws.items():
                rows.append({"quantity": what, "parameter": k, "law": law.kind,
                             "value at p_ref": law.ref,
                             "exponent / slope": law.m})
        return pd.DataFrame(rows)

    def to_dict(self) -> dict:
        return {"p_ref": self.p_ref, "source": self.source,
                "fits": [{"pressure": f.pressure,
                          "length": f.length.to_dict() if f.length else None,
                          "area": f.area.to_dict() if f.area else None,
                          "width": f.width.to_dict() if f.width else None} for f in self.fits],
                "laws": {w: {k: {"kind": v.kind, "ref": v.ref, "m": v.m} for k, v in d.items()}
                         for w, d in self.laws.items()}}

    def plot(self, data: pd.DataFrame | None = None, axes=None):
        """Length, width and area against load per pressure (Komana et al., Fig. 2).

        Parameters
        ----------
        data : DataFrame, optional
            the patch data (canonical SI columns) to draw as points.
        axes : sequence of 3 Axes, optional

        Returns
        -------
        ndarray of Axes
        """
        import matplotlib
        from matplotlib.figure import Figure

        if axes is None:
            axes = Figure(figsize=(13, 3.8)).subplots(1, 3)
        lo, hi = self.load_range()
        F = np.linspace(0.0, hi * 1.02, 300)
        colors = matplotlib.rcParams["axes.prop_cycle"].by_key()["color"]
        for j, f in enumerate(self.fits):
            c = colors[j % len(colors)]
            lab = f"{f.pressure / 1e5:.1f} bar"
            for ax, what, scale, unit in zip(axes, ("length", "width", "area"), (1e3, 1e3, 1e4),
                                             ("mm", "mm", "cm²")):
                sub = getattr(f, what)
                if sub is None:
                    continue
                ax.plot(F / G0, scale * sub(F), color=c, lw=1.5, label=lab)
                if what != "width":
                    ax.axvline(sub.breakpoint / G0, color=c, ls=":", lw=1)
                if data is not None and what in data:
                    d = data[np.isclose(data["pressure"], f.pressure, rtol=0.01)] if "pressure" in data else data
                    lc = "load" if "load" in d else "fz"
                    ax.plot(d[lc] / G0, scale * d[what], "o", color=c, ms=4)
                ax.set_xlabel("load [kg]")
                ax.set_ylabel(f"contact-patch {what} [{unit}]")
        for ax in axes:
            ax.grid(alpha=0.3)
        axes[0].legend(title="pressure", fontsize=8)
        return axes


def _patch_frame(patch) -> tuple[pd.DataFrame, str]:
    df = getattr(patch, "df", patch)
    src = getattr(patch, "source", "") or "patch data"
    if not isinstance(df, pd.DataFrame):
        raise DataError(f"{src}: expected a Dataset or DataFrame of contact-patch data")
    return df, src


def fit_patch(patch) -> PatchModel:
    """Fit the contact-patch model of Komana, Els and Becker (Sec. 4.1) to patch data.

    Parameters
    ----------
    patch : Dataset or DataFrame
        canonical columns ``load`` or ``fz`` [N], ``length`` [m] (needed),
        optionally ``width`` [m], ``area`` [m2], ``pressure`` [Pa].

    Returns
    -------
    PatchModel

    Raises
    ------
    ColumnError
        no ``length`` or no load column.
    DataError
        too few loads per pressure for the two-gradient law (5 needed).
    """
    df, src = _patch_frame(patch)
    lc = "load" if "load" in df else ("fz" if "fz" in df else None)
    if lc is None:
        raise ColumnError(f"{src}: contact-patch data need a load column, 'load [kg]' or 'fz [N]'")
    if "length" not in df:
        raise ColumnError(f"{src}: contact-patch data without 'length'; Eq. 1 needs the patch length: "
                          "add 'length [mm]'")
    if "pressure" in df:
        groups = [(float(p), g) for p, g in df.groupby(df["pressure"].round(-3))]
    else:
        groups = [(float("nan"), df)]
    fits = []
    for p, g in groups:
        F = g[lc].to_numpy(float)
        where = f"{src} at {p / 1e5:.2f} bar" if p == p else src
        length = fit_two_gradient(F, g["length"], what=f"{where}, length")
        area = fit_two_gradient(F, g["area"], what=f"{where}, area") if "area" in g else None
        width = fit_exp_rise(F, g["width"], what=f"{where}, width") if "width" in g else None
        pressure = float(g["pressure"].mean()) if "pressure" in g else float("nan")
        fits.append(PatchFit(pressure, length, area, width, np.unique(F)))
    fits.sort(key=lambda f: f.pressure)
    ps = np.array([f.pressure for f in fits])
    p_ref = float(ps[len(ps) // 2]) if np.all(np.isfinite(ps)) else float("nan")
    laws: dict[str, dict[str, PressureLaw]] = {}
    if len(fits) > 1:
        for what, params in _LAW.items():
            subs = [getattr(f, what) for f in fits]
            if any(s is None for s in subs):
                continue
            laws[what] = {k: _fit_law(kind, ps, np.array([getattr(s, k) for s in subs]), p_ref)
                          for k, kind in params.items()}
    return PatchModel(fits, p_ref, laws, src)
