"""Finite-element bodies (issue 13): meshes from the parameter set (gmsh), plane-stress
elements and static condensation (scikit-fem), an on-disk cache by geometry hash.

``flexibility.model = fe`` uses :func:`rvsim.fe.disc.disc_tables` for the cycloid discs
(docs/model.md section 17).  :mod:`rvsim.fe.modes` (the disc's modes and Craig-Bampton
model), :mod:`rvsim.fe.crank` (the crankshaft in 3-D) and :mod:`rvsim.fe.carrier` (the
carrier plate) are computed and verified but not used by the engines yet.  The submodules
import gmsh and scikit-fem only when a mesh is built.
"""

from __future__ import annotations

__all__ = ["cache", "carrier", "crank", "disc", "elasticity", "mesh", "modes"]
