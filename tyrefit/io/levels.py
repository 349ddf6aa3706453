"""Set-point levels of a measured condition: the one grouping function of the package.

A rig record holds sweeps at set points of load, camber, pressure, speed (and,
in combined-slip tests, slip angle); the value each sweep measures scatters
about its set point.  :func:`group_levels` groups such values into levels and
says which level each value belongs to.  The views, fits and checks that need
levels call it with the tolerance their job needs:

* :func:`tyrefit.io.facets.channel_levels`: ``method="peaks"`` with segmentation's step tolerance;
* :func:`tyrefit.fitting.mf_data.condition_levels` and :func:`tyrefit.fitting.mf_figures.sweep_levels`:
  gap, loads within 100 N or 4 % of the largest load;
* :func:`tyrefit.effects.signatures.plot`: gap, ``relative_to="range"`` (5 % of the span);
* :func:`tyrefit.io.plausibility.pneumatic_trail`: gap, ``relative_to="value"`` (100 N or 5 % of the load).

Two clusterings
---------------
* **gap** (default): the values are sorted and a new level starts where the
  step to the previous value exceeds ``max(atol, rtol * scale)``.  ``scale``
  is the largest magnitude (``relative_to="max"``: one tolerance for all the
  values), the span max - min (``"range"``), or the upper value of each step
  (``"value"``: a tolerance that grows with the value).  A level is the mean
  of its values.  Gap clustering chains: values 1, 2, 3 with a tolerance of
  1.5 are one level.
* **peaks**: the anchored clustering of segmentation
  (:func:`tyrefit.io.segment._levels`): peaks of a histogram with bins of
  half the tolerance; a level is the median of the values within the
  tolerance of its peak, and each value belongs to its nearest level.  Ramps
  between set points do not chain levels together.

A value that is not finite (a condition not recorded for that sweep) belongs
to no level: its index is -1.

The copies inside the mutation-testing targets (``fitting/initial.py``
``load_levels``, ``fitting/engine.py`` ``_levels``, ``io/readers.py``
``_group_levels``, ``io/segment.py`` ``_levels``) are left as they are; on
finite values they equal ``group_levels(v, abs_tol, rel_tol)[1]``,
``len(group_levels(v, tol)[0])``, ``group_levels(v, atol, rtol,
relative_to="value")[0]`` and ``group_levels(v, tol, method="peaks")[0]``
(``tests/test_levels.py`` checks it).
"""

from __future__ import annotations

import numpy as np

from .segment import _levels as _histogram_peaks

__all__ = ["group_levels"]

_RELATIVE_TO = ("max", "range", "value")
_METHODS = ("gap", "peaks")


def group_levels(values, atol: float = 0.0, rtol: float = 0.0, *, relative_to: str = "max",
                 method: str = "gap") -> tuple[np.ndarray, np.ndarray]:
    """Group measured values of one condition into set-point levels.

    Parameters
    ----------
    values : array_like
        one value per sweep (or per point) [SI]; NaN where not recorded.
    atol : float
        absolute tolerance [SI].
    rtol : float
        relative tolerance; the tolerance is ``max(atol, rtol * scale)``.
    relative_to : {'max', 'range', 'value'}
        ``scale`` of ``rtol``: the largest ``|value|``, the span max - min, or
        (``method="gap"`` only) the upper value of each step.
    method : {'gap', 'peaks'}
        gap clustering of the sorted values, or segmentation's histogram peaks
        (see the module docstring).

    Returns
    -------
    levels : ndarray
        the levels, ascending [SI] (empty when no value is finite).
    index : ndarray of int
        level of each value (position in ``levels``); -1 where the value is not finite.
    """
    if relative_to not in _RELATIVE_TO:
        raise ValueError(f"relative_to={relative_to!r}: one of {', '.join(_RELATIVE_TO)}")
    if method not in _METHODS:
        raise ValueError(f"method={method!r}: one of {', '.join(_METHODS)}")
    if method == "peaks" and relative_to == "value":
        raise ValueError("relative_to='value' is a gap tolerance; method='peaks' takes 'max' or 'range'")
    v = np.asarray(values, float).ravel()
    index = np.full(v.size, -1, int)
    ok = np.isfinite(v)
    x = v[ok]
    if x.size == 0:
        return np.zeros(0), index
    if method == "peaks":
        scale = float(np.max(np.abs(x))) if relative_to == "max" else float(np.max(x) - np.min(x))
        tol = float(max(atol, rtol * scale))
        lv = np.asarray(_histogram_peaks(x, tol, 1), float)
        if lv.size == 0:  # pragma: no cover - the histogram always has a peak for finite values
            lv = np.array([float(np.median(x))])
        index[ok] = np.argmin(np.abs(x[:, None] - lv[None, :]), axis=1)
        return lv, index
    order = np.argsort(x, kind="stable")
    s = x[order]
    if relative_to == "value":
        step = np.diff(s) > np.maximum(atol, rtol * np.abs(s[1:]))
    else:
        scale = float(np.max(np.abs(s))) if relative_to == "max" else float(s[-1] - s[0])
        step = np.diff(s) > max(atol, rtol * scale)
    group = np.empty(s.size, int)
    group[order] = np.r_[0, np.cumsum(step)]
    index[ok] = group
    levels = np.array([np.mean(g) for g in np.split(s, np.flatnonzero(step) + 1)], float)
    return levels, index
