"""What holding the disc's crank holes leaves out (issue 13, item 2; docs/model.md section 17).

The FE disc table is condensed onto the pin contact segments with both crank-hole edges held,
so the disc's elastic motion between its two holes, which the arm bushings load, is not in the
engines.  This prints its size on the RV-40E disc (default mesh): hole 1 held, a unit force
spread uniformly over hole 2's edge, hole 2's mean displacement along and across the axis
through the holes (across includes the disc turning about hole 1, a rigid motion the kernel's
disc coordinates already have; along is the stretch of the web between the holes, the one
elastic mode four hole coordinates have beyond the disc's three rigid ones).

Since 2026-11-25 the engines can condense the holes too (``flexibility.fe_disc_holes``,
rvsim.fe.disc_holes): its stretch c_ss, both hole edges free, is 8.31e-10 m/N against this
estimate's 7.9e-10 (tests/verification/test_fe_holes.py compares the two on a coarse mesh).

Usage:  python docs/validation_data/fe_disc_hole_stretch.py
"""

from __future__ import annotations

import numpy as np


def main() -> None:
    from rvsim.fe.disc import disc_body, disc_geometry
    from rvsim.fe.elasticity import edge_force
    from rvsim.parameters import RV40E

    g = disc_geometry(RV40E)
    body, _, _ = disc_body(g)
    mesh = body.mesh
    boundary = mesh.facets[:, mesh.boundary_facets()]
    on_hole = []
    for x, y, r in g["crank_holes"]:
        distance = np.hypot(mesh.p[0] - x, mesh.p[1] - y)
        on_hole.append(set(np.flatnonzero(np.abs(distance - r) < 1e-6 * r + 1e-9).tolist()))
    held = body.supported_dofs(np.array(sorted(on_hole[0])))
    edges = [(int(a), int(b)) for a, b in boundary.T if a in on_hole[1] and b in on_hole[1]]
    loads = np.column_stack([edge_force(body, edges, np.array(d)) for d in ([1.0, 0.0],
                                                                           [0.0, 1.0])])
    table = body.compliance(loads, held)
    (x1, y1, _), (x2, y2, _) = g["crank_holes"]
    axis = np.array([x2 - x1, y2 - y1]) / np.hypot(x2 - x1, y2 - y1)
    frame = np.column_stack([axis, [-axis[1], axis[0]]])
    along, across = np.diag(frame.T @ table @ frame)
    print(f"hole 2 relative to hole 1: along the axis {along:.3e} m/N (stretch of the web), "
          f"across {across:.3e} m/N (mostly turning about hole 1)")


if __name__ == "__main__":
    main()
