"""Records to a diagnosis: ``tyrefit diagnose`` as a function (the one path of the command line and the API).

Static-rig pushes are converted to slip angles first (Komana et al. Eq. 1, the conversion of
``tyrefit fit``: :func:`tyrefit.workflows.fit.static_input`); several records of one tyre (a cornering and
a drive/brake record) are joined (:func:`tyrefit.diagnose.combine_records`).  With ``base='pac89'`` the
lateral force is diagnosed from the PAC89 start model (:func:`tyrefit.diagnose.diagnose`) and the
aligning moment and drive/brake force of the records on their own catalogues
(:func:`tyrefit.diagnose.diagnose_channels`); with ``base='mf61'`` or ``'mf52'`` the Magic Formula tyre
``tyrefit fit --model`` writes is diagnosed (:func:`tyrefit.workflows.ladder.diagnose_mf`).
"""

from __future__ import annotations

from collections.abc import Sequence

from ..diagnose import combine_records, diagnose_channels
from ..diagnose import diagnose as diagnose_lateral
from ..errors import DataError, option
from ..io.readers import read_data
from .fit import static_input
from .ladder import diagnose_mf

__all__ = ["diagnose", "diagnose_records"]

BASES = ("pac89", "mf61", "mf52")


def diagnose_records(records: Sequence, *, start=(), rated_load: float | None = None, seed: int = 0,
                     base: str = "pac89", channels: bool = True, patch=None, rig=None, vertical=None,
                     static_part: str = "peak"):
    """Diagnose records already read; returns ``(result, lead)``, ``lead`` the lateral record diagnosed.

    ``result`` is a :class:`~tyrefit.diagnose.Diagnosis` (``base='pac89'``) or a
    :class:`~tyrefit.workflows.ladder.LadderDiagnosis`.  ``patch``, ``rig``, ``vertical`` and ``static_part``
    convert one static-rig record as ``fit`` does.
    """
    records = list(records)
    if not records:
        raise DataError("data: give at least one record")
    if base not in BASES:
        raise DataError(f"{option('base', repr(base))}: one of {', '.join(BASES)}")
    names = " ".join(str(getattr(r, "source", "")) for r in records)
    if base != "pac89":
        if start:
            raise DataError(f"{option('start')} names PAC89 effects; with {option('base', base)} the start is the "
                            f"Magic Formula tyre of a fit with {option('model', base)}")
        if any(r.kind not in ("slip_angle", "slip_ratio") for r in records):
            raise DataError(f"{option('base', base)} diagnoses dynamic-rig slip sweeps (the Magic Formula tyre a "
                            f"fit with {option('model', base)} writes); static-rig pushes are diagnosed with the PAC89 "
                            f"base and {option('patch')}")
        return diagnose_mf(records, model=base, rated_load=rated_load, seed=int(seed)), records[0]
    notes: list[str] = []
    if len(records) == 1 and records[0].kind == "static":
        sfi = static_input(records[0], patch=patch, rig=rig, vertical=vertical, static_part=static_part or "peak",
                           rated_load=rated_load, notes=notes)
        notes[:0] = [f"static-rig pushes converted to slip angles with Komana et al. Eq. 1 "
                     f"({'calibrated' if sfi.rig.calibrated else 'uncalibrated, f = 1'}; part '{sfi.part}')"]
        notes += list(sfi.notes)
        ds = lead = sfi.data
    elif patch is not None or rig is not None:
        kinds = ", ".join(sorted({r.kind for r in records}))
        raise DataError(f"{names}: {option('patch')} and {option('rig')} convert static-rig pushes (one record); "
                        f"these hold {kinds} data")
    else:
        lateral = [r for r in records if r.kind == "slip_angle" and "fy" in r.df.columns]
        if not lateral:
            kinds = ", ".join(sorted({repr(r.kind) for r in records}))
            hint = ("; give the tyre's cornering record too (both records in one diagnosis) to diagnose "
                    f"Fx beside Fy and Mz, or fit drive/brake records with {option('model', 'mf61')}"
                    if any(r.kind == "slip_ratio" for r in records) else "")
            raise DataError(f"{names}: diagnose needs lateral-force slip-angle sweeps (fy against slip_angle) or "
                            f"static-rig pushes with {option('patch')}; found {kinds} data" + hint)
        ds, lead = combine_records(records), lateral[0]
    dg = diagnose_lateral(ds, start=list(start or []), rated_load=rated_load, seed=int(seed))
    if channels:
        dg.channels, dg.channels_absent = diagnose_channels(ds, rated_load=rated_load, seed=int(seed))
    dg.data.notes[:0] = notes
    return dg, lead


def diagnose(data, *, start=(), rated_load: float | None = None, convention: str = "iso", seed: int = 0,
             base: str = "pac89", channels: bool = True, patch=None, rig=None, vertical=None,
             static_part: str = "peak"):
    """``tyrefit diagnose`` as a function: ``data`` is a path or Dataset, or several of one tyre.

    Returns a :class:`~tyrefit.diagnose.Diagnosis` (``base='pac89'``) or, with ``base='mf61'`` / ``'mf52'``, a
    :class:`~tyrefit.workflows.ladder.LadderDiagnosis`; both have ``summary()``, ``to_dict()``, ``to_json()``
    and ``report(dir)``.
    """
    items = list(data) if isinstance(data, (list, tuple)) else [data]
    records = [d if hasattr(d, "df") else read_data(d, convention=convention) for d in items]
    return diagnose_records(records, start=start, rated_load=rated_load, seed=seed, base=base, channels=channels,
                            patch=patch, rig=rig, vertical=vertical, static_part=static_part)[0]
