"""The stages of the Magic Formula fit: which coefficients each stage fits, on which sweeps and channel.

Shared by the fitter (:mod:`tyrefit.fitting.mf`, which runs them in the order of
:data:`STAGES`) and its result (:mod:`tyrefit.fitting.mf_result`, which says
which stages were not fitted); it imports neither.
"""

from __future__ import annotations

from dataclasses import dataclass

__all__ = ["Stage", "STAGES", "SPEED_FRICTION", "FX0", "FY0", "MZ0", "FXC", "FYC", "MZC", "MX", "MX_LINEAR", "MY"]

#: the one speed term of the MF 6.1 (and 5.2) force equations: the scaling factor of friction decay with slip
#: speed, mu* = LMU / (1 + LMUV Vs / V0) (Pacejka 2012, 4.E7), on mu_x and mu_y alike; the Fx0 stage
#: fits it (Fy0 when Fx0 did not; tyrefit.fitting.mf.identifiability), the joint polish from both channels
SPEED_FRICTION = ("LMUV",)
FX0 = ("PCX1", "PDX1", "PDX2", "PDX3", "PEX1", "PEX2", "PEX3", "PEX4", "PKX1", "PKX2", "PKX3",
       "PHX1", "PHX2", "PVX1", "PVX2", "PPX1", "PPX2", "PPX3", "PPX4") + SPEED_FRICTION
FY0 = ("PCY1", "PDY1", "PDY2", "PDY3", "PEY1", "PEY2", "PEY3", "PEY4", "PEY5", "PKY1", "PKY2", "PKY3",
       "PKY4", "PKY5", "PKY6", "PKY7", "PHY1", "PHY2", "PHY3", "PVY1", "PVY2", "PVY3", "PVY4",
       "PPY1", "PPY2", "PPY3", "PPY4", "PPY5") + SPEED_FRICTION
MZ0 = ("QBZ1", "QBZ2", "QBZ3", "QBZ4", "QBZ5", "QBZ9", "QBZ10", "QCZ1", "QDZ1", "QDZ2", "QDZ3", "QDZ4",
       "QDZ6", "QDZ7", "QDZ8", "QDZ9", "QDZ10", "QDZ11", "QEZ1", "QEZ2", "QEZ3", "QEZ4", "QEZ5",
       "QHZ1", "QHZ2", "QHZ3", "QHZ4", "PPZ1", "PPZ2")
FXC = ("RBX1", "RBX2", "RBX3", "RCX1", "REX1", "REX2", "RHX1")
FYC = ("RBY1", "RBY2", "RBY3", "RBY4", "RCY1", "REY1", "REY2", "RHY1", "RHY2",
       "RVY1", "RVY2", "RVY3", "RVY4", "RVY5", "RVY6")
MZC = ("SSZ1", "SSZ2", "SSZ3", "SSZ4")
MX = tuple(f"QSX{i}" for i in range(1, 15)) + ("PPMX1",)
#: the Mx terms that enter linearly (fitted first; the trigonometric QSX4-QSX11 then start from them)
MX_LINEAR = ("QSX1", "QSX2", "QSX3", "QSX12", "QSX13", "QSX14", "PPMX1")
MY = ("QSY1", "QSY2", "QSY3", "QSY4", "QSY5", "QSY6", "QSY7", "QSY8")

#: MF 5.2 has no pressure terms and uses the 5.2 camber forms; these are the coefficients 6.1 added
_ONLY_61 = frozenset(["PPX1", "PPX2", "PPX3", "PPX4", "PPY1", "PPY2", "PPY3", "PPY4", "PPY5", "PPZ1", "PPZ2",
                      "PPMX1", "PKY5", "PKY6", "PKY7", "PEY5", "QDZ10", "QDZ11", "RBX3", "RBY4", "QSY7", "QSY8",
                      "QBZ6"])


@dataclass(frozen=True)
class Stage:
    """One stage of the fit: its channel, its sweeps and its coefficients."""

    name: str
    channel: str
    sweeps: tuple[str, ...]  # sweep kinds it fits: 'longitudinal', 'lateral', 'combined'
    names: tuple[str, ...]
    core: tuple[str, ...]  # coefficients of the core sub-stage of the multi-start
    pure: str | None = None  # 'alpha' -> evaluate at slip_angle = 0; 'kappa' -> at slip_ratio = 0
    moment: bool = False


STAGES: tuple[Stage, ...] = (
    Stage("Fx0", "fx", ("longitudinal",), FX0, ("PCX1", "PDX1", "PKX1", "PEX1"), pure="alpha"),
    Stage("Fy0", "fy", ("lateral",), FY0, ("PCY1", "PDY1", "PKY1", "PKY2", "PEY1"), pure="kappa"),
    Stage("Mz0", "mz", ("lateral",), MZ0, ("QBZ1", "QCZ1", "QDZ1", "QEZ1", "QDZ6"), pure="kappa", moment=True),
    Stage("Fx", "fx", ("combined",), FXC, ("RBX1", "RBX2", "RCX1")),
    Stage("Fy", "fy", ("combined", "longitudinal"), FYC, ("RBY1", "RBY2", "RCY1")),
    Stage("Mz", "mz", ("combined", "longitudinal"), MZC, ("SSZ1", "SSZ2"), moment=True),
    # combined Mz carries the errors of the pure trail and of the combined forces: a last polish of every Mz
    # coefficient on every sweep with Mz (pure and combined), from the staged values, no multi-start
    Stage("Mz*", "mz", ("lateral", "combined", "longitudinal"), MZ0 + MZC, (), moment=True),
    Stage("Mx", "mx", ("lateral", "combined", "longitudinal"), MX, MX_LINEAR, moment=True),
    Stage("My", "my", ("longitudinal", "combined"), MY, ("QSY1", "QSY2"), moment=True),
)
_STAGE = {s.name: s for s in STAGES}
