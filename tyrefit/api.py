"""The Python API: the workflows of the command line as functions of data and keyword options.

``import tyrefit as tf`` exports these (``tyrefit/__init__.py``)::

    ds  = tf.read_data(tf.datasets.path("truck/tyre_a_dynamic.csv"))
    res = tf.fit(ds, model="pac89", cost="l1", size="385/65R22.5", rated_load=41678)
    res.summary(); res.plot(); res.to_frame(); res.tyre.to_tir("a.tir"); res.tyre.to_json("a.json")
    mf  = tf.fit([corner, drive_brake], model="mf61")          # several records, one tyre
    dg  = tf.diagnose(ds, start=["load_friction"], rated_load=6031)
    cmp = tf.compare(tyre_a, tyre_b, data=ds)
    sim = tf.simulate("ramp", front=mf.tyre, rear=mf.tyre, vehicle="fsae")

:func:`fit` is the workflow :func:`tyrefit.workflows.fit.fit` that ``tyrefit fit`` and ``tyrefit batch fit``
also run, so the same data and options give the same tyre file.
"""

from __future__ import annotations

import os
from collections.abc import Sequence

from .compare import workflow as _compare
from .errors import DataError
from .io.readers import read_data as _read_data
from .io.tir import read_tyre as _read_tyre
from .sim.api import simulate as _simulate
from .workflows.diagnose import diagnose as _diagnose
from .workflows.fit import fit as _fit

__all__ = ["read_data", "read_tyre", "fit", "diagnose", "compare", "simulate"]

_MODELS = ("pac89", "mf52", "mf61")


def read_data(path, convention: str = "iso", kind: str | None = None):
    """Read a rig record (CSV with unit headers, TYDEX ``.tdx``, FSAE TTC ``.dat``) into SI and ISO-W signs.

    ``convention``: the file's sign convention, 'iso' or 'sae' (FSAE TTC: Fz negative).
    """
    if convention not in ("iso", "sae"):
        raise DataError(f"convention={convention!r}: 'iso' or 'sae'")
    return (_read_data(path, convention=convention) if kind is None
            else _read_data(path, convention=convention, kind=kind))


def read_tyre(path):
    """Read any tyre file tyrefit reads (PAC89 ``.tir``, MF 5.x/PAC2002, MF 6.1/6.2, Chrono JSON)."""
    return _read_tyre(path)


def _path(x) -> str | None:
    return None if x is None else os.fspath(x)


def fit(data, *, model: str = "pac89", cost: str = "l2", effects: Sequence[str] | str | None = None,
        size: str | None = None, rated_load: float | None = None, patch=None, rig=None, vertical=None,
        static_part: str = "peak", convention: str = "iso", allow_mirrored: bool = False, params=None):
    """Fit a tyre to rig data: ``tyrefit fit`` as a function.

    Parameters
    ----------
    data : path, Dataset, or a sequence of them
        one record (PAC89) or several records of one tyre (a cornering and a drive/brake record; MF only).
    model : {'pac89', 'mf52', 'mf61'}
    cost : {'l2', 'l1', 'soft_l1', 'huber'}
        'l1' is Komana et al.'s Eq. 5 (sum of absolute friction errors).
    effects : list of str, optional
        diagnose effect ids fitted on top of the start model.
    size, rated_load : optional
        tyre size ('385/65R22.5') and rated load [N]: dimensions, FNOMIN and estimates.
    patch, rig, vertical : path, optional
        contact-patch data, rig calibration and vertical-stiffness test (static-rig data, PAC89).
    static_part : {'peak', 'sliding'}
    convention : {'iso', 'sae'}
    params : lmfit.Parameters, optional
        coefficients as lmfit users set them (names of the family: ``a0``..``c17`` for PAC89, ``PCY1``,
        ``PDY1``, ... for MF); the others are fitted as without ``params``:

        * ``value``: the start value of a varied coefficient (the fit's first start; its multi-start
          still runs and the lowest cost wins);
        * ``vary=False``: held at ``value``;
        * ``min`` / ``max``: bounds, intersected with the physical ones (PAC89; refused for MF);
        * ``expr``: evaluated at the values given and *held* at that value (not a constraint during the
          fit; the result's notes say so).

        Names not of the family raise :class:`~tyrefit.errors.DataError`.  ``res.lmfit_params()`` shows
        the held coefficients with ``vary=False`` and the bounds given; ``res.fit_report()`` is lmfit's
        report.  Example::

            p = lmfit.Parameters()
            p.add("a0", value=1.3, vary=False)     # C held
            p.add("a2", value=1100, max=1200)      # start value and an upper bound
            res = tf.fit(ds, model="pac89", params=p)
            print(res.fit_report())

    Returns
    -------
    :class:`tyrefit.fitting.FitResult` (PAC89) or :class:`tyrefit.fitting.mf_result.FitResultMF`; both have
    ``tyre`` (``to_tir``, ``forces``), ``summary()``, ``plot(ax=None)``, ``to_frame()``, ``report(dir)``,
    ``_repr_html_``.
    """
    return _fit(data, model=model, cost=cost, effects=effects, size=size, rated_load=rated_load,
                patch=_path(patch), rig=_path(rig), vertical=_path(vertical), static_part=static_part,
                convention=convention, allow_mirrored=allow_mirrored, params=params)


def diagnose(data, *, start: Sequence[str] | None = None, rated_load: float | None = None,
             convention: str = "iso", seed: int = 0, channels: bool = True, base: str = "pac89",
             patch=None, rig=None, vertical=None, static_part: str = "peak"):
    """What the model misses, effect by effect (``tyrefit diagnose``: :func:`tyrefit.workflows.diagnose.diagnose`).

    ``data`` is one record or several of one tyre (cornering and drive/brake).  ``base='pac89'`` grows PAC89 on
    Fy and, with ``channels``, diagnoses Mz and Fx where the records carry them; ``base='mf61'`` / ``'mf52'``
    diagnoses the Magic Formula tyre ``fit --model`` writes.  ``patch``, ``rig``, ``vertical``, ``static_part``
    convert static-rig pushes as :func:`fit` does.
    """
    return _diagnose(data, start=start or (), rated_load=rated_load, convention=convention, seed=seed, base=base,
                     channels=channels, patch=_path(patch), rig=_path(rig), vertical=_path(vertical),
                     static_part=static_part)


def compare(a, b, data=None, *, convention: str = "iso", names: Sequence[str] | None = None,
            allow_unphysical: bool = False):
    """Two tyres on the quantities engineers read, channel by channel (:func:`tyrefit.compare.workflow`)."""
    return _compare(a, b, data, convention=convention, names=names, allow_unphysical=allow_unphysical)


def simulate(scenario: str, front=None, rear=None, vehicle="ev", **options):
    """A vehicle scenario with the given tyres on a vehicle (preset name, file or spec): ``tyrefit sim``."""
    return _simulate(scenario, front=front, rear=rear, vehicle=vehicle, **options)
