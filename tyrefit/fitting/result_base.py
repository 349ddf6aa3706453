"""What every tyre fit returns: one interface for PAC89 and Magic Formula 5.2 / 6.1 fits.

:class:`TyreFitResult` is the type ``tf.fit`` returns for every family; a notebook or a script uses
the same calls whatever the model:

* ``tyre`` (the fitted :class:`~tyrefit.tyres.base.Tyre`), ``rmse``, ``stats`` (per part or channel:
  ``rmse``, ``r2``, ``noise_floor``, ...), ``warnings``, ``notes``, ``not_identifiable``;
* ``summary()``, ``plot(ax=None)`` (on pyplot, one panel per condition level), ``to_frame()`` (every
  point with the model beside it), ``to_dict()``, ``to_html()`` / ``_repr_html_()``,
  ``report(directory)``;
* ``contract()`` (what the tyre breaks of the physical-validity rules over the ranges its file would
  declare; empty when it keeps them), ``require_valid()`` and ``write_tir(path)``, which refuses a
  tyre that breaks them;
* ``lmfit_params()`` and ``fit_report()``: the fitted coefficients as :class:`lmfit.Parameters`
  (value, bounds, ``vary``, ``stderr``) and lmfit's own report of them.  lmfit is imported only here,
  when asked: the solver is tyrefit's own (:mod:`tyrefit.fitting.core`).
"""

from __future__ import annotations

import abc
import os
from pathlib import Path

from ..errors import FitError

__all__ = ["TyreFitResult"]


class TyreFitResult(abc.ABC):
    """The result of fitting a tyre model to rig data (every family); see the module docstring.

    Every subclass has the attributes ``tyre`` (the fitted :class:`~tyrefit.tyres.base.Tyre`), ``stats``,
    ``warnings``, ``notes`` and ``not_identifiable`` (a field or a property: not declared here, so that
    dataclass subclasses keep them as fields).
    """

    @property
    @abc.abstractmethod
    def rmse(self) -> float:
        """The headline RMSE [N]: lateral force where the fit has it, else longitudinal."""

    @abc.abstractmethod
    def summary(self) -> str:
        """Plain-text summary: fit quality per part or channel, holds, warnings."""

    @abc.abstractmethod
    def plot(self, ax=None):
        """Model over data on pyplot (or on ``ax``), one panel per condition level; returns the Axes."""

    @abc.abstractmethod
    def to_frame(self):
        """Every fitted point with its conditions, the measurement and the model (a DataFrame)."""

    @abc.abstractmethod
    def to_dict(self) -> dict:
        """JSON-ready summary."""

    @abc.abstractmethod
    def to_html(self) -> str:
        """HTML fragment (statistics and coefficients, no figures)."""

    def _repr_html_(self) -> str:
        return self.to_html()

    @abc.abstractmethod
    def report(self, directory: str | os.PathLike, force: bool = False, title: str | None = None) -> Path:
        """Write the self-contained HTML report to ``directory``; return its path."""

    @abc.abstractmethod
    def contract(self) -> list:
        """The physical-validity rules the tyre breaks over the ranges its file declares (empty: none)."""

    def require_valid(self) -> None:
        """Raise :class:`~tyrefit.errors.FitError` when :meth:`contract` finds a problem."""
        problems = [str(v) for v in self.contract()]
        if problems:
            more = f" (and {len(problems) - 1} more)" if len(problems) > 1 else ""
            raise FitError(f"the fitted tyre is not physical over the range it would declare: {problems[0]}{more}")

    @abc.abstractmethod
    def write_tir(self, path: str | os.PathLike, *, force: bool = False) -> Path:
        """Write the tyre's property file after :meth:`require_valid`; return the path."""

    @abc.abstractmethod
    def lmfit_params(self):
        """The coefficients as :class:`lmfit.Parameters`: value, bounds, ``vary`` (fitted or held), ``stderr``."""

    def fit_report(self, **kwargs) -> str:
        """lmfit's report of the coefficients (:func:`lmfit.fit_report`), after the fit's statistics.

        ``kwargs`` go to :func:`lmfit.fit_report` (``show_correl``, ``min_correl``, ``sort_pars``).
        """
        import lmfit

        lines = ["[[Fit Statistics]]"]
        for name, s in getattr(self, "stats", {}).items():
            if not s.get("fitted", True):
                continue
            unit = s.get("unit", "")
            lines.append(f"    {name + ':':<14} RMSE {s['rmse']:.6g} {unit}, R2 {s['r2']:.6g}, noise floor "
                         f"{s['noise_floor']:.6g} {unit}")
        return "\n".join(lines) + "\n" + lmfit.fit_report(self.lmfit_params(), **kwargs)
