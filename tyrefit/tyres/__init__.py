"""Tyre models behind one interface (:class:`~tyrefit.tyres.base.Tyre`): PAC89, MF 5.2, MF 6.1/6.2.

Read any tyre file with :func:`tyrefit.io.tir.read_tyre` (PAC89 / MF ``.tir``
and Chrono PAC89 JSON); it returns the right family.
"""

from .base import FAMILIES, MirroredTyre, Tyre, require_physical
from .mf import MFTyre
from .pac89 import Pac89Tyre
from .size import TyreSize, parse_size

__all__ = ["Tyre", "MirroredTyre", "Pac89Tyre", "MFTyre", "FAMILIES", "require_physical", "TyreSize", "parse_size"]
