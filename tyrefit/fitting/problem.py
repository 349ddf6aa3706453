"""The fitting problem every tyre fitter of the package solves: parameters theta -> residual rows on rig sweeps.

A :class:`SweepProblem` holds what the fitting core (:func:`tyrefit.fitting.core.solve`) needs and what
is the same for every model family:

* the **data** as :class:`~tyrefit.fitting.core.Sweeps` (the measured quantity and each point's sweep);
* the **weights**: each sweep counts once in the cost, however densely it was sampled
  (w_i = 1/n_s, :meth:`~tyrefit.fitting.core.Sweeps.sweep_weights`), so a densely sampled sweep
  cannot outvote the others;
* the **cost** ('l2', 'l1' = Komana et al. Eq. 5, or a robust 'soft_l1' / 'huber' with a per-point
  scale), the free parameters' names and box bounds, and how the core is called.

A model family subclasses it with its parametrisation: :meth:`rows` (unweighted residual: the data
rows, then any penalty rows), optionally an analytic :meth:`jac`, and the names and bounds of theta.
The PAC89 parts (:class:`tyrefit.fitting.engine` ``_Problem``: an affine map theta -> a0..c17 that keeps
linear load laws inside their physical range at both ends of the tested loads) and the Magic Formula
stages (:mod:`tyrefit.fitting.mf` ``_Problem``: MF 5.2/6.1 coefficients with penalty rows for the
tyre contract) are the two.  Diagnose's effect models (:mod:`tyrefit.diagnose.fitter`) use the same
core on force in N with unit weights, because their statistics (held-out sweeps, noise model) weigh
points, not sweeps.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from .core import Parameters, Sweeps, solve
from .core import objective as core_objective

__all__ = ["SweepProblem"]


class SweepProblem:
    """A weighted, bounded least-squares problem over rig sweeps (see the module notes).

    Parameters
    ----------
    y : array (N,)
        The measured quantity of every data point.
    sweep : array (N,)
        Each point's sweep (any labels).
    cost : str
        'l2', 'l1', 'soft_l1' or 'huber' (:func:`tyrefit.fitting.core.solve`).

    Subclasses set :attr:`theta_names`, :attr:`lb` and :attr:`ub` and define :meth:`rows`.
    """

    #: the core's method and the default solver settings (a subclass may change them)
    method = "trf"
    tol = 1e-8
    #: what a solver failure names
    what = "fit"
    #: analytic Jacobian of :meth:`rows` (``jac(theta) -> (rows, len(theta))``), or None for differences
    jac: Callable[[np.ndarray], np.ndarray] | None = None
    #: per-point scale of the robust costs (None: the core's default)
    robust_scale: np.ndarray | None = None
    #: the data rows of :meth:`rows` (penalty rows follow them); None: every row is a data row
    n_data: int | None = None

    def __init__(self, y, sweep, cost: str):
        self.data = Sweeps(np.asarray(y, dtype=float), np.asarray(sweep))
        self.y = self.data.y
        self.weights = self.data.sweep_weights()
        self.cost = cost
        self.theta_names: list[str] = []
        self.lb = self.ub = np.zeros(0)

    # -- what a subclass gives ---------------------------------------------------------------------------
    def rows(self, theta) -> np.ndarray:
        """Unweighted residual at ``theta``: model minus data of every data point, then any penalty rows."""
        raise NotImplementedError

    def inside(self, theta) -> np.ndarray:
        """``theta`` as the solver starts from it (a subclass may move it off its bounds)."""
        return np.asarray(theta, dtype=float)

    def max_nfev(self, n_free: int) -> int:
        """The solver's evaluation budget for ``n_free`` free parameters."""
        return 200 * (n_free + 1)

    # -- the same for every family ------------------------------------------------------------------------
    def parameters(self, theta) -> Parameters:
        """theta as the core's parameters: names, values and bounds."""
        pars = Parameters()
        for name, v, lo, hi in zip(self.theta_names, theta, self.lb, self.ub):
            pars.add(name, float(v), min=lo, max=hi)
        return pars

    def solve(self, theta0, *, cost: str | None = None, tol: float | None = None,
              max_nfev: int | None = None) -> tuple[np.ndarray, int]:
        """Solve from ``theta0`` with the fitting core; returns (theta, number of evaluations).

        ``cost`` defaults to the problem's own (an 'l1' solve may continue from an 'l2' one), ``tol`` to
        :attr:`tol`, ``max_nfev`` to :meth:`max_nfev`.
        """
        theta0 = self.inside(theta0)
        if len(theta0) == 0:
            return theta0, 0
        sol = solve(self.rows, self.parameters(theta0), jac=self.jac, weights=self.weights, n_data=self.n_data,
                    cost=cost or self.cost, scale=self.robust_scale, method=self.method, x_scale="jac",
                    max_nfev=max_nfev or self.max_nfev(len(theta0)), tol=self.tol if tol is None else tol,
                    stderr=False, what=self.what)
        return sol.x, sol.nfev

    def objective(self, theta) -> float:
        """The cost at ``theta``: sum w r^2 (l2), sum w |r| (l1), sum w s^2 rho((r/s)^2) (robust); w = 1/n_s."""
        return core_objective(self.rows(theta), self.weights, self.cost, self.robust_scale)  # penalty rows weigh 1
