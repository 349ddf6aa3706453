"""The extended lateral-force model: PAC89 plus named effects.

Effects act on PAC89 coefficients point by point: a term that scales the
friction (peak) factor D multiplies ``a1`` and ``a2`` at each point, a term
that scales the cornering stiffness BCD multiplies ``a3``; the result goes
through the public :func:`tyrefit.models.pac89.lateral_force`, so the ISO-W
<-> PAC89 sign mapping stays in one place.  With every effect parameter at its
neutral value the multipliers are exactly 1.0 and the output is bit for bit
the previous model's.

All coefficient values may be NumPy arrays that broadcast against the inputs:
a ``(P, 1)`` column per coefficient evaluates P parameter sets at once (used
by the fitter's vectorised Jacobian).
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping


from ..models import pac89
from .base import Effect, ModelInputs
from .catalogue import get_effect
from .factors import KNEE_HALF_WIDTH, overload_factor, relative_factor  # noqa: F401  (public here too)

__all__ = ["coefficients", "lateral_force", "overload_factor", "relative_factor"]


def _resolve(effects: Iterable[Effect | str]) -> list[Effect]:
    return [e if isinstance(e, Effect) else get_effect(e) for e in effects]


def coefficients(values: Mapping[str, object], effects: Iterable[Effect | str],
                 inputs: ModelInputs) -> dict[str, object]:
    """PAC89 lateral coefficients ``a0``..``a13`` after every effect's modifier.

    Parameters
    ----------
    values : mapping
        PAC89 coefficients (missing ones are 0) and effect parameters
        (missing ones take their neutral value).
    effects : iterable of Effect or id
        Effects in the model, applied in order; an effect whose ``extra``
        says ``reads_factors`` (it reads the cornering stiffness or the peak
        force, e.g. ``camber_brush``) is applied after the others.
    inputs : ModelInputs
        Operating conditions (SI) and reference values.

    Returns
    -------
    dict
        ``a0``..``a13``: scalars, or arrays broadcast against the inputs where
        an effect varies them point by point.
    """
    coef: dict[str, object] = {name: values.get(name, 0.0) for name in pac89.LATERAL}
    effs = _resolve(effects)
    # effects that read the model's factors (BCD, D) go last, so they see every scaling of a1-a5
    effs = [e for e in effs if not e.extra.get("reads_factors")] + [e for e in effs if e.extra.get("reads_factors")]
    for e in effs:
        if e.apply is not None:
            e.apply(coef, {p.name: values.get(p.name, p.neutral) for p in e.params}, inputs)
    return coef


def lateral_force(values: Mapping[str, object], effects: Iterable[Effect | str], inputs: ModelInputs):
    """Lateral force Fy [N] (ISO-W) of PAC89 plus ``effects``.

    Examples
    --------
    >>> import numpy as np
    >>> from tyrefit.effects import ModelInputs
    >>> x = ModelInputs(fz=np.array([4000.0]), slip_angle=np.radians([3.0]), camber=np.zeros(1),
    ...                 rated_load=5000.0)
    >>> p = {"a0": 1.5, "a2": 1100.0, "a3": 1500.0, "a4": 8.0, "a7": -0.5, "overload_mu": 0.3}
    >>> float(lateral_force(p, ["overload"], x)[0]) < 0   # positive slip -> negative Fy (ISO-W)
    True
    """
    coef = coefficients(values, effects, inputs)
    return pac89.lateral_force(coef, inputs.fz, inputs.slip_angle, inputs.camber)
