#!/usr/bin/env python3
# SPDX-License-Identifier: LGPL-2.1-or-later
"""Test inputs of insert_sweep.py (issue 50 item 2): the project's inserts
(tkr.py's A and B, tkr_ps.py's C) with the features of real ones, as a
STEP file (OpenCASCADE) or a scan-like STL.

    inserts.py VARIANT OUT.step|OUT.stl [--draft DEG] [--rim MM] [--recess MM]
               [--post-draft DEG] [--seed S] [--size MM] [--noise MM]

--draft: the side walls are ruled between the insert's outline at the top
(unchanged, so the articular surface and its rim are the design's) and
that outline offset by H tan(DEG) at the seat: the walls' outward normals
point DEG above the horizontal (+: the seat wider than the top; -: the top
wider, an overhang, as the scanned insert of issue 50 with -16 deg).
--rim: the top rim (walls to articular surface) rounded with radius MM,
the seat's edges with 0.75 MM and a recess's floor edges with 0.5 MM (as
rounded.py does; edges OpenCASCADE refuses are left sharp).  --recess: a
locking recess MM deep cut into the seat (rounded.py's slot, 55 % x 45 % of
the plan).  --post-draft (C): the post's walls drafted by DEG, its top
narrower than its foot (its anterior chamfer dropped), as a moulded post
would be; the insert_sweep's raised-feature path cannot mesh it.

An STL is triangulated like rounded.py's (sizes --size x 0.6-1.4 varying
irregularly, finer on curvature; Gaussian noise of --noise mm; closed,
manifold, outward).  The femoral components are the design's own files
(meshes/tkr/cad/).
"""
import argparse
import math
import os
import sys

import numpy as np

HERE = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, HERE)

import gmsh  # noqa: E402

import rounded  # noqa: E402
import tkr  # noqa: E402
import tkr_ps  # noqa: E402
from mesh_implant import write_stl_binary  # noqa: E402
from scanlike import indexed  # noqa: E402


def geometry(variant):
    return tkr_ps.Geometry() if variant == "c" else tkr.Geometry(variant)


def rounded_rectangle_wire(g, z, offset):
    """A wire: the insert's outline (rounded rectangle) offset by `offset`
    at height z, and the auxiliary plane surface to remove afterwards."""
    occ = gmsh.model.occ
    r = occ.addRectangle(
        -g.A - offset,
        -g.B - offset,
        z,
        2 * (g.A + offset),
        2 * (g.B + offset),
        roundedRadius=g.r_corner + offset,
    )
    occ.synchronize()
    curves = [abs(c) for _, c in gmsh.model.getBoundary([(2, r)], oriented=True)]
    return occ.addWire(curves), r


def loft(wires, aux):
    occ = gmsh.model.occ
    out = occ.addThruSections(wires, makeSolid=True, makeRuled=True)
    occ.remove([(2, s) for s in aux])
    occ.synchronize()
    return [dt for dt in out if dt[0] == 3]


def post_solid(g, draft):
    """TKR C's post (tkr_ps.py); with draft (deg) a frustum instead: its
    foot the post's section at the plateau, its walls leaning in by `draft`
    up to the post's top height, flat top."""
    occ = gmsh.model.occ
    w = g.post_half_width
    if draft is None:
        pts = [occ.addPoint(-w, y, z) for y, z in g.post_polygon()]
        lines = [occ.addLine(pts[i], pts[(i + 1) % len(pts)]) for i in range(len(pts))]
        face = occ.addPlaneSurface([occ.addCurveLoop(lines)])
        return [dt for dt in occ.extrude([(2, face)], 2 * w, 0, 0) if dt[0] == 3]
    t = (g.post_top - g.post_base) * math.tan(math.radians(draft))
    wires, aux = [], []
    for z, d in ((g.post_base, 0.0), (g.post_top, t)):
        r = occ.addRectangle(-w + d, g.post_back + d, z, 2 * (w - d), g.post_front - g.post_back - 2 * d)
        occ.synchronize()
        wires.append(occ.addWire([abs(c) for _, c in gmsh.model.getBoundary([(2, r)], oriented=True)]))
        aux.append(r)
    return loft(wires, aux)


def build(variant, draft=0.0, rim=0.0, recess=0.0, post_draft=None):
    """The insert as one OpenCASCADE volume of the current model; returns
    its tag."""
    g = geometry(variant)
    occ = gmsh.model.occ
    offset = g.H * math.tan(math.radians(draft))
    w0, r0 = rounded_rectangle_wire(g, 0.0, offset)
    w1, r1 = rounded_rectangle_wire(g, g.H, 0.0)
    prism = loft([w0, w1], [r0, r1])
    tori = [tkr.occ_dish(side * g.x_c, g.y_dish, g.z_axis, g.R_ts, g.R_tf) for side in (-1, +1)]
    body, _ = occ.cut(prism, tori)
    occ.synchronize()
    if variant == "c":
        body, _ = occ.fuse([dt for dt in body if dt[0] == 3], post_solid(g, post_draft))
        occ.synchronize()
    vol = [t for d, t in body if d == 3]
    assert len(vol) == 1
    vol = vol[0]
    lo = np.array(gmsh.model.getBoundingBox(3, vol))
    lo, hi = lo[:3], lo[3:]
    if recess > 0:
        c, ext = 0.5 * (lo + hi), hi - lo
        w, d = 0.55 * ext[0], 0.45 * ext[1]
        r = occ.addRectangle(c[0] - w / 2, c[1] - d / 2, lo[2] - 1.0, w, d, roundedRadius=0.25 * d)
        slot = [t for t in occ.extrude([(2, r)], 0, 0, recess + 1.0) if t[0] == 3]
        out, _ = occ.cut([(3, vol)], slot)
        occ.synchronize()
        vol = [t for dd, t in out if dd == 3][0]
    if rim > 0:
        info = rounded.edge_info(vol)
        outer = {
            f
            for f in set(sum((v["faces"] for v in info.values()), []))
            if gmsh.model.getBoundingBox(2, f)[2] < lo[2] + 0.01
        }
        base, floor, top = [], [], []
        for e, v in info.items():
            if len(v["faces"]) != 2 or abs(np.dot(*v["normals"])) > 0.98:
                continue  # tangent faces: nothing to round
            z = v["mid"][2]
            wall = [abs(n[2]) < 0.6 for n in v["normals"]]
            if z < lo[2] + 0.01:
                base.append(e)
            elif recess > 0 and abs(z - lo[2] - recess) < 0.01 and any(wall):
                floor.append(e)
            elif sum(wall) == 1 and z > lo[2] + 1.0 and v["faces"][wall.index(True)] in outer:
                top.append(e)
        for radius, edges in ((rim, top), (0.75 * rim, base), (0.5 * rim, floor)):
            vol = rounded.fillet_each(vol, rounded.edges_at([info[e]["mid"] for e in edges]), radius)
    return vol


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("variant", choices=("a", "b", "c"))
    ap.add_argument("output", help=".step or .stl")
    ap.add_argument("--draft", type=float, default=0.0, help="deg; +: seat wider than the top")
    ap.add_argument("--rim", type=float, default=0.0, help="radius of the rounded top rim, mm")
    ap.add_argument("--recess", type=float, default=0.0, help="depth of a locking recess, mm")
    ap.add_argument("--post-draft", type=float, help="C: the post's walls drafted by this, deg")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--size", type=float, default=0.8, help="STL: mean triangle edge, mm")
    ap.add_argument("--noise", type=float, default=0.005, help="STL: mm")
    a = ap.parse_args(argv)
    gmsh.initialize(["gmsh", "-v", "0"])
    try:
        gmsh.model.add("insert")
        vol = build(a.variant, a.draft, a.rim, a.recess, a.post_draft)
        volume = gmsh.model.occ.getMass(3, vol)
        if a.output.lower().endswith(".stl"):
            rng = np.random.default_rng(a.seed)
            X, T = rounded.triangulate(a.size, rng)
        else:
            gmsh.write(a.output)
    finally:
        gmsh.finalize()
    if a.output.lower().endswith(".stl"):
        X, T = indexed(X[T])
        T = rounded.orient_outward(X, T)
        X = X + a.noise * rng.standard_normal(X.shape)
        write_stl_binary(a.output, X[T])
        print(
            "%s: %d triangles, CAD volume %.1f mm^3, %d edges rounded"
            % (a.output, len(T), volume, rounded.ROUNDED[0])
        )
    else:
        print("%s: CAD volume %.1f mm^3, %d edges rounded" % (a.output, volume, rounded.ROUNDED[0]))
    return 0


if __name__ == "__main__":
    sys.exit(main())
