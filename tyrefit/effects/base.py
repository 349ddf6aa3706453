"""Building blocks of the effect catalogue: parameters, physics cards, data summaries.

An :class:`Effect` is a named extension of the Pacejka '89 lateral-force model.
Its parameters have *neutral* values that give back the previous model bit for
bit (the PyBaMM "option with a neutral submodel" pattern); it says which data
make it testable, how it maps to a PAC89 ``.tir`` and what it means physically.
The effects themselves live in :mod:`tyrefit.effects.catalogue`.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from typing import NamedTuple

import numpy as np

from ..fitting.core import Parameter
from .signatures import plot as _plot_signature

__all__ = ["Param", "PhysicsCard", "DataSummary", "ModelInputs", "Effect"]


@dataclass(frozen=True)
class Param:
    """One parameter of an effect: its catalogue definition.

    The fit-time state (value, vary, standard error) is the fitting core's
    :class:`~tyrefit.fitting.core.Parameter`, made by :meth:`parameter`.

    Attributes
    ----------
    name : str
        A PAC89 coefficient name (``a1``, ``a5``...) when the effect *is* that
        coefficient, otherwise an effect parameter (``overload_mu``).
    neutral : float
        Value that switches the effect off exactly.
    bounds : (float, float)
        Hard bounds used by the fitter.
    plausible : (float, float)
        Range seen on real tyres (for warnings and reports).
    unit : str
        Unit of the parameter (PAC89 units for PAC89 coefficients).
    scale : float
        Typical magnitude (optimiser scaling and finite-difference steps).
    meaning : str
        One line for reports.
    """

    name: str
    neutral: float
    bounds: tuple[float, float]
    plausible: tuple[float, float]
    unit: str
    scale: float
    meaning: str

    def parameter(self, value: float | None = None) -> Parameter:
        """This definition as the fitting core's :class:`~tyrefit.fitting.core.Parameter` at ``value`` (default neutral)."""
        return Parameter(self.name, self.neutral if value is None else float(value), self.bounds[0], self.bounds[1],
                         True, None, self.unit, self.scale, self.meaning)


@dataclass(frozen=True)
class PhysicsCard:
    """What an effect is, in the words an engineer uses.

    ``what`` happens in the tyre, its ``size`` on real tyres, the ``test`` that
    reveals it, what it changes in the ``vehicle``, and the ``sources``
    (seed papers, model modules) that explain it.
    """

    what: str
    size: str
    test: str
    vehicle: str
    sources: tuple[str, ...] = ()

    def as_rows(self) -> list[dict[str, str]]:
        """Rows for a report table."""
        return [
            {"": "what happens in the tyre", "card": self.what},
            {"": "typical size", "card": self.size},
            {"": "test that reveals it", "card": self.test},
            {"": "what it changes in the vehicle", "card": self.vehicle},
            {"": "sources", "card": "; ".join(self.sources)},
        ]


@dataclass(frozen=True)
class DataSummary:
    """What a data set covers: the condition levels an effect needs to be testable.

    All values SI: ``fz_levels`` [N], ``camber_levels`` [rad],
    ``pressure_levels`` [Pa], ``speed_levels`` [m/s], ``slip_min``/``slip_max``
    [rad]; ``rated_load`` [N] or None when unknown.
    """

    fz_levels: tuple[float, ...]
    camber_levels: tuple[float, ...] = (0.0,)
    pressure_levels: tuple[float, ...] = ()
    speed_levels: tuple[float, ...] = ()
    slip_min: float = 0.0
    slip_max: float = 0.0
    rated_load: float | None = None
    n_sweeps: int = 0

    @property
    def slip_reach(self) -> float:
        """Smaller of the two slip extents [rad] (how far both sides reach)."""
        return min(-self.slip_min, self.slip_max)

    @property
    def slip_extent(self) -> float:
        """Larger of the two slip extents [rad]."""
        return max(-self.slip_min, self.slip_max)


class ModelInputs(NamedTuple):
    """Operating conditions of each point, SI, plus the reference values effects need.

    ``pressure`` [Pa] and ``speed`` [m/s] may be None when the data have no
    such column (effects that need them are then not testable).
    ``rated_load`` [N], ``pressure_ref`` [Pa], ``speed_ref`` [m/s] are the
    points where the pressure/speed/overload terms are zero; ``fz_ref`` [N]
    is the reference load of the curved friction law (the middle load level).
    ``side_force`` [N] is the measured lateral force of each point, where a
    channel's model needs it (the aligning moment's trail times Fy), and
    ``side_force_zero`` [rad] the slip angle at which that side force crosses
    zero in the point's sweep (where the residual torque is centred); None
    otherwise.
    """

    fz: np.ndarray
    slip_angle: np.ndarray
    camber: np.ndarray
    pressure: np.ndarray | None = None
    speed: np.ndarray | None = None
    rated_load: float | None = None
    pressure_ref: float | None = None
    speed_ref: float | None = None
    fz_ref: float | None = None
    side_force: np.ndarray | None = None
    side_force_zero: np.ndarray | None = None

    def take(self, idx) -> "ModelInputs":
        """The inputs at the points ``idx`` (index array or boolean mask)."""
        def t(a):
            return None if a is None else np.asarray(a)[idx]
        return self._replace(fz=t(self.fz), slip_angle=t(self.slip_angle), camber=t(self.camber),
                             pressure=t(self.pressure), speed=t(self.speed),
                             side_force=t(self.side_force), side_force_zero=t(self.side_force_zero))


#: ``apply(coef, values, inputs)``: modify the PAC89 coefficient mapping in place
ApplyFn = Callable[[dict, Mapping[str, object], ModelInputs], None]
#: ``testable(summary)``: None when the data can test the effect, else the reason they cannot
TestableFn = Callable[[DataSummary], "str | None"]


@dataclass(frozen=True)
class Effect:
    """A named extension of the PAC89 lateral-force model.

    Attributes
    ----------
    id : str
        Registry key; starts with the family name (``camber_thrust``).
    family : str
        ``load_friction``, ``overload``, ``camber``, ``offsets``, ``pressure``...
    title : str
        Short human name.
    params : tuple of Param
        Parameters with neutral values, bounds and plausible ranges.
    needs : str
        The data it needs to be testable, in words.
    testable : callable
        ``testable(summary) -> None | reason``.
    apply : callable or None
        Modifies PAC89 coefficient arrays point by point (see
        :func:`tyrefit.effects.model.coefficients`); None when the parameters
        *are* PAC89 coefficients.
    pac89 : tuple of str
        PAC89 coefficients that represent the effect exactly (empty if none).
    pac89_approx : tuple of str
        PAC89 coefficients that can absorb part of the effect when it is not
        representable exactly.
    pac89_note : str
        How the effect reaches a ``.tir``, or what to do instead.
    card : PhysicsCard
    signature : str
        Which signature view shows it (see :mod:`tyrefit.effects.signatures`).
    refinement : bool
        A higher-order form of its family's law (a third-order friction law, a
        bent curvature law): it may refine the family once the family has won
        on its other variants, but never names a family by itself - with more
        terms it can mimic another family's law (a knee at the rated load).
    """

    id: str
    family: str
    title: str
    params: tuple[Param, ...]
    needs: str
    testable: TestableFn
    card: PhysicsCard
    signature: str
    apply: ApplyFn | None = None
    pac89: tuple[str, ...] = ()
    pac89_approx: tuple[str, ...] = ()
    pac89_note: str = ""
    requires_rated_load: bool = False
    extra: dict = field(default_factory=dict)
    refinement: bool = False

    @property
    def param_names(self) -> tuple[str, ...]:
        return tuple(p.name for p in self.params)

    @property
    def neutral(self) -> dict[str, float]:
        """Parameter name -> neutral value."""
        return {p.name: p.neutral for p in self.params}

    @property
    def representable(self) -> bool:
        """True when PAC89 represents the effect exactly."""
        return bool(self.pac89) and set(self.pac89) == set(self.param_names)

    def why_not_testable(self, summary: DataSummary) -> str | None:
        """None if ``summary``'s data can test the effect, else the reason."""
        return self.testable(summary)

    def plot_signature(self, view, ax=None):
        """Draw this effect's signature view (see :func:`tyrefit.effects.signatures.plot`)."""
        return _plot_signature(self, view, ax=ax)
