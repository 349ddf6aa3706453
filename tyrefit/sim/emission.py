"""Tyre-wear particle emission as a quadratic in longitudinal force (Pham et al. 2025, Eq. 14).

Pham et al. take the number of particles a tyre emits as N(F_x) = a F_x^2 +
b F_x + c, fitted by least squares to particle counts measured in traction
and braking (Foitzik et al. 2018) under the constraint that N is never
negative; the fit's minimum lies at a non-zero force.  A low-wear ("hard")
tyre emits a fixed fraction k of the soft tyre's particles at every force,
N_h = k N_s (Eq. 43 gives k from the treadwear-traction law).

Forces here are per tyre; :meth:`QuadraticEmission.axle` gives the same law
for an axle of n tyres sharing the axle force equally, which is what the
allocator works with.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np
from scipy.optimize import minimize_scalar, nnls

from ..errors import DataError

__all__ = ["QuadraticEmission", "EmissionFit", "fit_emission", "DEFAULT_EMISSION"]


@dataclass(frozen=True)
class QuadraticEmission:
    """N(F) = a F^2 + b F + c particles per second, F [N] (Pham et al. 2025, Eq. 14).

    Attributes
    ----------
    a : float
        [(#/s)/N^2], >= 0.
    b : float
        [(#/s)/N].
    c : float
        [#/s].
    source : str
        Where the coefficients come from (a fit, or "default").
    """

    a: float
    b: float
    c: float
    source: str = ""

    def rate(self, fx):
        """Particles per second at longitudinal force ``fx`` [N]."""
        fx = np.asarray(fx, dtype=float)
        return (self.a * fx + self.b) * fx + self.c            # Eq. 14

    __call__ = rate

    @property
    def force_at_minimum(self) -> float:
        """Force of least emission, -b / (2 a) [N]."""
        return -self.b / (2.0 * self.a) if self.a > 0 else float("nan")

    @property
    def minimum(self) -> float:
        """Least emission, c - b^2 / (4 a) [#/s] (>= 0 for a fit of :func:`fit_emission`)."""
        return self.c - self.b**2 / (4.0 * self.a) if self.a > 0 else self.c

    def axle(self, n_tyres: int = 2) -> "QuadraticEmission":
        """The law for an axle force shared by ``n_tyres``: n N(F/n) = (a/n) F^2 + b F + n c."""
        return replace(self, a=self.a / n_tyres, b=self.b, c=self.c * n_tyres,
                       source=f"{self.source} (axle of {n_tyres})")

    def scaled(self, k: float) -> "QuadraticEmission":
        """k times this law (the hard tyre, N_h = k N_s)."""
        return replace(self, a=k * self.a, b=k * self.b, c=k * self.c, source=f"{k:.4g} x {self.source}")

    def to_dict(self) -> dict:
        return {"a": self.a, "b": self.b, "c": self.c, "force_at_minimum_N": self.force_at_minimum,
                "minimum": self.minimum, "source": self.source}


@dataclass(frozen=True)
class EmissionFit:
    """Result of :func:`fit_emission`."""

    model: QuadraticEmission
    r2: float
    rmse: float
    n_points: int
    constrained: bool
    weights: str
    fx: np.ndarray
    particles: np.ndarray

    def to_dict(self) -> dict:
        return {**self.model.to_dict(), "r2": self.r2, "rmse": self.rmse, "n_points": self.n_points,
                "constraint_active": self.constrained, "weights": self.weights}

    def plot(self, ax=None):
        """Data and fitted quadratic (braking and traction points coloured apart)."""
        from matplotlib.figure import Figure

        if ax is None:
            ax = Figure(figsize=(6, 4)).subplots()
        brake = self.fx < 0
        ax.plot(self.fx[brake], self.particles[brake], "o", ms=4, label="braking")
        ax.plot(self.fx[~brake], self.particles[~brake], "o", ms=4, label="traction")
        f = np.linspace(self.fx.min(), self.fx.max(), 300)
        ax.plot(f, self.model.rate(f), "k-", label=f"fit, min at {self.model.force_at_minimum:.0f} N")
        ax.set_xlabel("longitudinal force per tyre [N]")
        ax.set_ylabel("particles [#/s]")
        ax.legend()
        return ax


def fit_emission(fx, particles, weights: str = "absolute") -> EmissionFit:
    """Fit N = a F^2 + b F + c with N >= 0 for every F (constrained least squares, Eq. 14).

    Parameters
    ----------
    fx : array_like
        Longitudinal force per tyre [N].
    particles : array_like
        Particle emission [#/s] (any count rate; the unit carries through).
    weights : {'absolute', 'relative'}
        'absolute' (default) is ordinary least squares, Pham et al.'s choice;
        'relative' minimises the sum of squared *relative* residuals
        ((N_model - N)/N)^2, for counts with multiplicative scatter and no
        zero counts.

    Returns
    -------
    EmissionFit

    Notes
    -----
    N >= 0 everywhere means a >= 0 and c >= b^2 / (4 a).  Writing N = a (F - F0)^2
    + m with a, m >= 0 covers exactly those quadratics; for a fixed F0 the fit of
    (a, m) is a non-negative least-squares problem (``scipy.optimize.nnls``), and
    F0 is found by a bounded scalar search.  When the unconstrained fit already
    satisfies the constraint it is returned as is.
    """
    f = np.asarray(fx, dtype=float).ravel()
    y = np.asarray(particles, dtype=float).ravel()
    if f.size != y.size:
        raise DataError(f"fx and particles differ in length ({f.size} vs {y.size})")
    ok = np.isfinite(f) & np.isfinite(y)
    f, y = f[ok], y[ok]
    if f.size < 4:
        raise DataError(f"an emission fit needs at least 4 points with finite force and particles, got {f.size}")
    if np.any(y < 0):
        raise DataError(f"particle counts must be >= 0; found {y[y < 0][0]:.4g}")
    if np.ptp(f) <= 0:
        raise DataError("all forces are equal; the emission fit needs a range of forces")
    if weights not in ("relative", "absolute"):
        raise DataError(f"weights must be 'relative' or 'absolute', got {weights!r}")
    if weights == "relative":
        w = 1.0 / np.maximum(y, 1e-6 * max(np.max(y), 1e-300))
    else:
        w = np.ones_like(y)

    A = np.column_stack([f**2, f, np.ones_like(f)])
    coef, *_ = np.linalg.lstsq(A * w[:, None], y * w, rcond=None)
    a, b, c = coef
    constrained = not (a > 0 and c - b * b / (4 * a) >= 0)
    if constrained:
        def profile(f0):
            M = np.column_stack([(f - f0) ** 2, np.ones_like(f)]) * w[:, None]
            sol, res = nnls(M, y * w)
            return res**2, sol

        span = np.ptp(f)
        grid = np.linspace(f.min() - span, f.max() + span, 401)
        vals = np.array([profile(g)[0] for g in grid])
        i = int(np.argmin(vals))
        lo, hi = grid[max(i - 1, 0)], grid[min(i + 1, grid.size - 1)]
        opt = minimize_scalar(lambda g: profile(g)[0], bounds=(lo, hi), method="bounded",
                              options={"xatol": 1e-6 * span})
        f0 = opt.x if opt.fun <= vals[i] else grid[i]
        (aa, m) = profile(f0)[1]
        a, b, c = aa, -2.0 * aa * f0, aa * f0**2 + m
    model = QuadraticEmission(float(a), float(b), float(c),
                              source=f"constrained least-squares fit ({weights} residuals) to {f.size} points")
    pred = model.rate(f)
    ss_res = float(np.sum((y - pred) ** 2))
    ss_tot = float(np.sum((y - y.mean()) ** 2))
    return EmissionFit(model=model, r2=1.0 - ss_res / ss_tot if ss_tot > 0 else float("nan"),
                       rmse=float(np.sqrt(ss_res / f.size)), n_points=int(f.size), constrained=bool(constrained),
                       weights=weights, fx=f, particles=y)


#: DEFAULT emission law per tyre [#/s], force per tyre [N]: the constrained least-squares
#: fit of the bundled SYNTHETIC ``data/sim/emission.csv`` (truth a = 0.012, minimum 0 at
#: F0 = 500 N), rounded; the constraint is active, so the minimum (about 0) lies at 500 N.
#: Pham et al.'s own coefficients (a fit to Foitzik et al.'s counts) are not used.
#: ``tests/test_sim_emission.py`` checks these against a refit of the bundled file.
DEFAULT_EMISSION = QuadraticEmission(a=0.01249, b=-12.48, c=3117.6,
                                     source="DEFAULT (fit to tyrefit's synthetic emission.csv)")
