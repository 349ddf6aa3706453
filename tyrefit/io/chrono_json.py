"""Project Chrono's PAC89 tyre JSON (``Template: Pac89Tire``): read into and written from the tyre classes.

The layout, what Chrono's ``Pac89Tire::Create`` reads unconditionally and how
parts without a model are written are in :mod:`tyrefit.io.chrono_doc`, which
holds the document as plain data and knows no tyre class; this module reads it
into a :class:`~tyrefit.tyres.pac89.Pac89Tyre`.
"""

from __future__ import annotations

import os

from ..tyres.pac89 import Pac89Tyre
from .chrono_doc import REQUIRED_DESIGN, chrono_dict, chrono_fields, write_chrono_json  # noqa: F401  (public here)

__all__ = ["read_chrono_json", "write_chrono_json", "chrono_dict"]


def read_chrono_json(path: str | os.PathLike) -> Pac89Tyre:
    """Read Chrono's PAC89 JSON into a :class:`Pac89Tyre`."""
    return Pac89Tyre(**chrono_fields(path))
