"""Finite-element bodies (issue 13): meshes from the parameter set (gmsh), plane-stress and
plane-strain elements and static condensation (scikit-fem), an on-disk cache by geometry
hash.

``flexibility.model = fe`` uses :func:`rvsim.fe.disc.disc_tables` for the cycloid discs and
(``flexibility.fe_carrier``) :func:`rvsim.fe.carrier.carrier_table` for the carrier and the
flange and (switch B) :func:`rvsim.fe.pin.pin_table` for the pins in their housing grooves
(docs/model.md section 17).  :mod:`rvsim.fe.modes` (the disc's modes and
Craig-Bampton model) and :mod:`rvsim.fe.crank` (the crankshaft in 3-D) are computed and
verified but not used by the engines yet.  The submodules
import gmsh and scikit-fem only when a mesh is built.
"""

from __future__ import annotations

__all__ = ["cache", "carrier", "crank", "disc", "elasticity", "mesh", "modes", "pin"]
