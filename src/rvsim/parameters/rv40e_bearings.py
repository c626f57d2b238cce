"""RV-40E with rolling bearings instead of the paper's bushings (docs/parameters.md).

Needle roller bearings run directly on the crank eccentrics and in the disc holes (no rings),
tapered roller bearings carry the cranks in the carrier and the flange.  Sizes are estimates
from the reducer's geometry (no drawings are public); docs/parameters.md lists each with its
reasoning.  The paper's clearances K-O add their radial play to the bearings' (both zero
here), so the L36 factors K-O act on this set as on the paper's.  This module holds the
frictionless base; the built-in set adds the friction of a greased reducer
(parameters/friction_values.py, applied in parameters/_io.py).
"""

from __future__ import annotations

import dataclasses

from ._types import Bearings
from .rv40e import RV40E

__all__ = ["RV40E_ROLLING"]

RV40E_ROLLING = dataclasses.replace(
    RV40E, name="RV-40E-bearings",
    citation=RV40E.citation + "; rolling bearings estimated (docs/parameters.md)",
    bearings=Bearings(arm_needles=True, support_rollers=True))
