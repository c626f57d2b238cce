"""Finite-element bodies (issue 13): meshes from the parameter set (gmsh), plane-stress and
plane-strain elements and static condensation (scikit-fem), an on-disk cache by geometry
hash.

``flexibility.model = fe`` uses :func:`rvsim.fe.disc.disc_tables` for the cycloid discs and
(``flexibility.fe_carrier``) :func:`rvsim.fe.carrier.carrier_table` for the carrier and the
flange, (switch B) :func:`rvsim.fe.pin.pin_table` for the pins in their housing grooves
and (``flexibility.fe_crank``) :func:`rvsim.fe.crank.crank_table` for the crankshafts in 3-D;
the dynamic engine takes the disc's modes from :mod:`rvsim.fe.modes` (``flexibility.fe_modes``;
its Craig-Bampton model is built and verified beside them) (docs/model.md section 17).  The
submodules import gmsh and scikit-fem only when a mesh is built.
"""

from __future__ import annotations

__all__ = ["cache", "carrier", "crank", "disc", "elasticity", "mesh", "modes", "pin"]
