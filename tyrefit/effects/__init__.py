"""Named physical effects that extend the Pacejka '89 lateral-force model.

>>> from tyrefit.effects import EFFECTS, resolve_pac89
>>> sorted({e.family for e in EFFECTS.values()})[:3]
['camber', 'curvature_load', 'load_friction']

See :mod:`tyrefit.effects.catalogue` for the registry and the physics cards,
:mod:`tyrefit.effects.model` for the extended model and
:mod:`tyrefit.effects.signatures` for the signature views.
"""

from .base import DataSummary, Effect, ModelInputs, Param, PhysicsCard
from .catalogue import BASE, BASE_NAMES, EFFECTS, FAMILIES, get_effect, parse_effects, resolve_pac89
from .model import coefficients, lateral_force, overload_factor, relative_factor

__all__ = [
    "BASE", "BASE_NAMES", "EFFECTS", "FAMILIES", "DataSummary", "Effect", "ModelInputs", "Param",
    "PhysicsCard", "coefficients", "get_effect", "lateral_force", "overload_factor", "parse_effects",
    "relative_factor", "resolve_pac89",
]
