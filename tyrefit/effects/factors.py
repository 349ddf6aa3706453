"""Load, pressure and speed factors of the effect modifiers (pure numpy; shared by
:mod:`tyrefit.effects.catalogue` and :mod:`tyrefit.effects.model`)."""

from __future__ import annotations

import numpy as np

__all__ = ["overload_factor", "relative_factor", "KNEE_HALF_WIDTH"]


#: half-width of the rounded knee of :func:`overload_factor`, as a share of the rated load
KNEE_HALF_WIDTH = 0.1


def overload_factor(fz, rated_load: float, k, half_width=KNEE_HALF_WIDTH):
    """Multiplier 1 - k max(0, Fz - Fr)/Fr on a factor above the rated load Fr.

    Parameters
    ----------
    fz : array_like
        Normal load [N].
    rated_load : float
        Rated (maximum) load of the tyre Fr [N].
    k : array_like
        Fractional loss per rated load of overload [-]; 0 is neutral.
    half_width : array_like, optional
        Half-width of the rounded knee as a share of Fr [-] (default
        :data:`KNEE_HALF_WIDTH`); the ``overload_knee`` effect fits it.

    Notes
    -----
    A hinge at the rated load: grip is unchanged below Fr and falls linearly
    above it, the behaviour Komana et al. (Sec. 4.2) report for a
    truck tyre above its 4250 kg rating.  The knee is rounded over
    Fr (1 +- :data:`KNEE_HALF_WIDTH`) by a quadratic blend (the C1 hinge
    ``(x + w)^2 / 4w`` for ``|x| < w``): the contact patch does not change
    shape at one exact load, and a rated load is a nominal value (load index
    steps are 3-4 % apart; the patch starts to cave in gradually).  A sharp
    hinge left 0.76 sigma of a smooth knee on one-sweep-per-load data with a
    level at the rated load, where a curved friction law then explained the
    data better than the overload it was.  Exactly 1.0 when ``k == 0``, and
    at loads below Fr (1 - w).  How wide the knee is depends on the tyre (how
    gradually the patch caves in), so ``overload_knee`` fits ``half_width``.
    """
    x = np.asarray(fz, dtype=float) - rated_load
    w = np.asarray(half_width, dtype=float) * rated_load
    h = np.where(x <= -w, 0.0, np.where(x >= w, x, (x + w) ** 2 / (4.0 * w)))  # C1 hinge: a rounded knee
    return 1.0 - k * h / rated_load


def relative_factor(value, reference: float, k):
    """Multiplier 1 + k (v - v_ref)/v_ref (pressure or speed sensitivity).

    ``k`` is the relative change of the factor per relative change of the
    condition (an elasticity at the reference), as MF 6.1's PPY1/PPY3 are per
    dpi = (p - p0)/p0.  Exactly 1.0 when ``k == 0``.
    """
    return 1.0 + k * (np.asarray(value, dtype=float) - reference) / reference
