"""Project Chrono's PAC89 tyre JSON (``Template: Pac89Tire``).

Layout of ``shared/reference/chrono/HMMWV_Pac89Tire.json``: SI design
parameters, lowercase coefficients in "Lateral/Longitudinal/Aligning
Coefficients", an optional nonlinear "Vertical Curve Data" table of
(deflection [m], force [N]).  Chrono's files carry ``//`` comments, which are
stripped before parsing; a UTF-8 byte-order mark is accepted.

What Chrono reads unconditionally (projectchrono/chrono @ 17a9098167,
``src/chrono_vehicle/wheeled_vehicle/tire/Pac89Tire.cpp``, ``Pac89Tire::Create``):
``Mass``, ``Inertia`` (3 values), and in "Design Parameters" ``Unloaded Radius``,
``Width``, ``Lateral Stiffness``, ``Vertical Stiffness``, ``Vertical Damping``,
``Rolling Resistance``; each coefficient block present must give every
coefficient (a0..a13, b0..b10, c0..c17).  :func:`chrono_dict` writes all of
them or refuses (:class:`~tyrefit.errors.ModelError` naming what is missing);
a part without a model is written as its neutral block
(:data:`tyrefit.io.pac89_tir.NEUTRAL_BLOCKS`), finite in Chrono's equations, and
said "not fitted" in ``Notes`` with every estimated design value.

The document itself (reading its keys, building and writing it from a tyre)
is :mod:`tyrefit.io.chrono_doc`, which knows no tyre class; this module reads
it into a :class:`~tyrefit.tyres.pac89.Pac89Tyre`.
"""

from __future__ import annotations

import os

from ..tyres.pac89 import Pac89Tyre
from .chrono_doc import REQUIRED_DESIGN, chrono_dict, chrono_fields, write_chrono_json  # noqa: F401  (public here)

__all__ = ["read_chrono_json", "write_chrono_json", "chrono_dict"]


def read_chrono_json(path: str | os.PathLike) -> Pac89Tyre:
    """Read Chrono's PAC89 JSON into a :class:`Pac89Tyre`."""
    return Pac89Tyre(**chrono_fields(path))
