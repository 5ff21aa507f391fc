#!/usr/bin/env python3
# SPDX-License-Identifier: LGPL-2.1-or-later
"""CAD-like STL input pairs (issue 50, item 7): what a real implant's CAD
export has and the scan-like pairs of rounded.py lack, made from the
parametric TKR of tkr.py and tkr_ps.py with OpenCASCADE (gmsh).

    cadlike.py [NAME ...] [-o DIR] [--coarse] [--list]

writes DIR/NAME-femur.stl, DIR/NAME-insert.stl and DIR/NAME.txt (what was
made and what was measured on the STL files) for each named input of
INPUTS (all of them without a name).  An input combines these features:

sharp
    The femur without the edge fillets of tkr.py's frontal section (r_edge,
    alpha_edge): each condyle's articular arc (frontal radius R_f) runs out
    to the side walls and to the box walls (the condyles' inner faces; the
    box of the posterior-stabilised C) and meets them in a sharp CAD edge
    (the arc's slope there is asin(w_condyle / R_f), 27 deg on A, so the
    normals turn by 63 deg across the edge; 50 deg with tkr.py's fillet).
    This is where mesh-implant's femur contact layer found nodes "with no
    direction into the body" on the real implant.
draft DEG
    The insert's side walls inclined: the outward normals DEG below the
    horizontal (DEG > 0: the top wider than the base, an undercut, as on
    the real implant, whose wall normals had n_z = -0.28, 16 deg; DEG < 0:
    the base wider than the top).  The top outline (and so the articular
    surface) is tkr.py's; the base is offset by -H tan(DEG).  A surface is
    ruled between the two outlines (planes and cones).
asym (R_MEDIAL, R_LATERAL)
    Condyles with different distal radii whose lowest points lie at the
    same height, so that both touch the insert: the distal arcs' centres
    are R_LATERAL - R_MEDIAL apart in height (the real implant: 30.0 mm at
    z 36.0 and 36.1 mm at z 42.2).  Each condyle gets its own J-curve
    (tkr.Geometry with its own R_d, th_0 and y_dish) that keeps the
    design's anterior flange and anterior arc (centre C_a and radius R_a):
    its distal arc is tangent to that arc, with its lowest point at the
    design's height, where th_0' solves (R_d' - R_a)(1 - cos th_0') =
    (R_d - R_a)(1 - cos th_0); the smaller the radius, the further anterior
    the lowest point (on C: medial 2.2 mm, lateral 0.7 mm anterior of the
    design's).  The bridged part (anterior of theta_notch), and so its
    clearance from C's post, is the design's; the condyles differ behind
    it (a first version that kept the medial th_0 moved the anterior arc
    3.4 mm back, into C's post).  The insert's dishes follow:
    each dish bottom under its condyle's lowest point, its sagittal radius
    scaled to keep the design's conformity R_d / R_ts.  Medial is +x
    (tkr-wear's default Medial side).
overlap MM
    The femur lowered by MM into the insert (tkr.py's gap = -MM): the
    assembly as exported, not touching but interpenetrating.
decimate (N_FEMUR, N_INSERT)
    The CAD exported with a fine chordal tolerance (triangle sizes from
    the faces' curvature, tkr_ps.face_sizes_for_deviation: about 10 times
    the triangles wanted) and decimated by quadric error (decimate():
    edges collapsed onto one of their end vertices, so every vertex stays
    on the CAD surface) to N_FEMUR and N_INSERT triangles: large triangles
    on flat faces and long thin ones across curved regions of one
    curvature direction (the femur's fixation faces, the cam, the cones of
    the insert's corners), as decimated CAD exports have them.

Without decimate, a surface is the chordal export itself (tolerance
CHORDAL mm).  Every output is checked closed and manifold (every edge in
two triangles of opposite orientation) and oriented outward; what a
feature should be is measured on the STL files (features(), the .txt
report) and tested (meshes/gen/tests/test_cadlike.py).  --coarse makes
the same inputs with a coarser export and decimation (for the tests).
"""
import argparse
import heapq
import math
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import tkr  # noqa: E402
import tkr_ps  # noqa: E402
from mesh_implant import read_stl, write_stl_binary  # noqa: E402
from rounded import orient_outward  # noqa: E402
from scanlike import indexed, surface_mesh  # noqa: E402

DEG = math.pi / 180.0

# the real implant of issue 50: distal radii 30.0 and 36.1 mm, wall normals 16 deg down, 24k and 43k
# triangles; the inputs combine its features one at a time on the design that shows each best
INPUTS = {
    "sharp-a": dict(design="a", sharp=True),
    "draft-out-b": dict(design="b", draft=15.0),
    "draft-in-b": dict(design="b", draft=-15.0),
    "asym-a": dict(design="a", asym=(30.0, 36.0)),
    "overlap-a": dict(design="a", overlap=0.05),
    "decimated-c": dict(design="c", decimate=(43000, 24000)),
    "real-like": dict(
        design="c", sharp=True, draft=16.0, asym=(30.0, 36.0), overlap=0.05, decimate=(43000, 24000)
    ),
}
CHORDAL = 0.01  # mm: the export of the inputs that are not decimated
CHORDAL_FINE = 0.001  # mm: the export that is decimated
H_MAX_FINE = 3.0  # mm: its longest edge (some 5-10 times the triangles wanted)
H_MAX = 12.0  # mm: the longest triangle edge of an export (flat faces)
# --coarse: for the tests (the same features, fewer triangles)
COARSE = dict(chordal=0.05, chordal_fine=0.01, h_max_fine=6.0, decimate_scale=0.2)


def design_params(design):
    """The tkr.Geometry parameters of a design (and the post/cam of C, or None)."""
    if design == "c":
        return dict(tkr_ps.VARIANT), dict(tkr_ps.PS)
    return dict(tkr.VARIANTS[design]), None


class Pair:
    """The geometry of one input: the femur's condyles (one tkr.Geometry per
    side, medial +x), the insert's dishes and walls."""

    def __init__(self, design, sharp=False, draft=0.0, asym=None, overlap=0.0, decimate=None):
        self.design, self.sharp, self.draft, self.asym = design, sharp, draft, asym
        self.overlap, self.decimate = overlap, decimate
        p, self.ps = design_params(design)
        self.p = p
        if overlap:
            p["gap"] = -overlap
        if sharp:
            p["r_edge"] = 0.0  # tkr.Geometry then has u1 = w_condyle: the arc runs out to the walls
        self.side = {}
        if asym is None:
            g = tkr.Geometry(design, p)
            self.side = {+1: g, -1: g}
        else:
            # both distal arcs tangent to the design's anterior arc (so the flange, the bridge and
            # their clearance from C's post are the design's), their lowest points at its height
            base = tkr.Geometry(design, p)
            rise = (base.R_d - base.R_a) * (1.0 - math.cos(base.th["th_0"]))
            for side, r_d in ((+1, asym[0]), (-1, asym[1])):
                th0 = -math.acos(1.0 - rise / (r_d - base.R_a))
                y = base.C_a[0] + (r_d - base.R_a) * math.sin(th0)
                self.side[side] = tkr.Geometry(design, dict(p, R_d=r_d, th_0=th0 / DEG, y_dish=y))
                assert np.allclose(self.side[side].C_a, base.C_a) and th0 > base.th["th_notch"]
        g = self.side[+1]
        self.H = g.H
        self.name = design

    def dish(self, side):
        """(x, y, R_ts, R_tf) of the dish under one condyle: its bottom under
        the condyle's lowest point, the design's conformity R_d / R_ts."""
        g = self.side[side]
        r_ts = self.p["R_ts"] * g.R_d / self.p["R_d"]
        return side * g.x_c, g.y_dish, r_ts, g.R_tf

    def lowest(self, side):
        """(x, y, z) of a condyle's lowest point (theta = 0, middle of its frontal arc)."""
        g = self.side[side]
        return np.array([side * g.x_c, g.C_d[0], g.C_d[1] - g.R_d])

    def outline(self, z):
        """(half width, half depth, corner radius) of the insert's outline at height z."""
        g = self.side[+1]
        d = -(self.H - z) * math.tan(self.draft * DEG)
        return g.A + d, g.B + d, g.r_corner + d


# ---------------------------------------------------------------- CAD
def profile_wire(g, s0, side=None):
    """The frontal section at arc length s0 as a plane surface (OCC tag):
    tkr's section with its fillets, or (r_edge 0) each condyle's articular
    arc straight into the side walls.  side None: both condyles and the
    bridge, else one condyle."""
    import gmsh

    if g.r_edge > 0:
        return tkr._occ_profile_wire(g, s0, side is None, side)
    occ = gmsh.model.occ
    Q, n, _ = g.curve(np.array([s0]))
    Q, n = Q[0], n[0]

    def P(x, eta):
        pt = Q - eta * n
        return occ.addPoint(x, pt[0], pt[1])

    de, t = g.delta_edge, g.t_fem
    curves = []
    chain = []  # condyle arcs, -x to +x
    for sign in (-1, +1) if side is None else (side,):
        a, b = sign * g.x_c - g.w_condyle, sign * g.x_c + g.w_condyle
        chain.append((P(a, de), P(sign * g.x_c, g.R_f), P(b, de)))
    for i, (pa, pc, pb) in enumerate(chain):
        if i:
            curves.append(occ.addLine(chain[i - 1][2], pa))  # the bridge
        curves.append(occ.addCircleArc(pa, pc, pb))
    x0, x1 = (-g.x_out, g.x_out) if side is None else (side * g.x_c - g.w_condyle, side * g.x_c + g.w_condyle)
    p1, p0 = P(x1, t), P(x0, t)
    curves += [occ.addLine(chain[-1][2], p1), occ.addLine(p1, p0), occ.addLine(p0, chain[0][0])]
    return occ.addPlaneSurface([occ.addCurveLoop(curves)])


def build_femur(pair):
    """The femur solid in the current gmsh model (tag): the bridged part
    (flange, anterior arc up to theta_notch) swept along the common
    J-curve, each condyle behind it along its own; C's cam fused in."""
    import gmsh

    occ = gmsh.model.occ
    g = pair.side[+1]
    S = g.S
    vols = []
    for s0, s1 in ((S[0], S[1]), (S[1], g.s_notch)):
        vols += tkr._occ_sweep(g, profile_wire(g, s0), s0, s1)
    for side, gs in pair.side.items():
        S = gs.S
        for s0, s1 in ((gs.s_notch, S[2]), (S[2], S[3]), (S[3], S[4])):
            vols += tkr._occ_sweep(gs, profile_wire(gs, s0, side), s0, s1)
    occ.synchronize()
    out, _ = occ.fuse(vols[:1], vols[1:])
    occ.synchronize()
    vol = [t for d, t in out if d == 3]
    assert len(vol) == 1, "the femur's sweeps did not fuse into one solid"
    if pair.ps is not None:
        # the cam between the box walls, its axis the mean of the two condyles' (tkr_ps.Geometry)
        centres = []
        for gs in pair.side.values():
            Q, n, _ = gs.curve(np.array([gs.s_of_theta(pair.ps["cam_theta"])]))
            centres.append(Q[0] - pair.ps["cam_eta"] * n[0])
        yc, zc = pair.cam_axis = np.mean(centres, axis=0)
        r, x_in = pair.ps["cam_radius"], g.x_in
        # its end discs on the box walls reach past the condyles' posterior tips (tkr_ps: 64 %
        # inside); the fraction inside is reported
        pair.cam_inside = {}
        for sign in (-1, 1):
            disc = occ.addCylinder(sign * x_in, yc, zc, sign * 0.2, 0, 0, r)
            common, _ = occ.intersect([(3, disc)], [(3, vol[0])], removeObject=True, removeTool=False)
            inside = sum(occ.getMass(d, t) for d, t in common if d == 3)
            occ.remove(common, recursive=True)
            pair.cam_inside[sign] = inside / (math.pi * r * r * 0.2)
        cam = occ.addCylinder(-x_in, yc, zc, 2 * x_in, 0, 0, r)
        out, _ = occ.fuse([(3, vol[0])], [(3, cam)])
        occ.synchronize()
        vol = [t for d, t in out if d == 3]
    return vol[0]


def rounded_rectangle(a, b, r, z):
    """A closed wire (OCC tag) of the rounded rectangle |x| <= a, |y| <= b
    with corner radius r at height z: 4 lines and 4 quarter circles, so
    that two of them loft into planes and cones."""
    import gmsh

    occ = gmsh.model.occ
    pts, curves = [], []
    for cx, cy, a0 in (
        (a - r, b - r, 0.0),
        (-a + r, b - r, 90.0),
        (-a + r, -b + r, 180.0),
        (a - r, -b + r, 270.0),
    ):
        c = occ.addPoint(cx, cy, z)
        p = [
            occ.addPoint(cx + r * math.cos((a0 + d) * DEG), cy + r * math.sin((a0 + d) * DEG), z)
            for d in (0, 90)
        ]
        pts.append((p[0], c, p[1]))
    for i, (p0, c, p1) in enumerate(pts):
        curves.append(occ.addCircleArc(p0, c, p1))
        curves.append(occ.addLine(p1, pts[(i + 1) % 4][0]))
    return occ.addWire(curves)


def build_insert(pair):
    """The insert solid in the current gmsh model (tag): the prism between
    the base outline and tkr.py's top outline (ruled: walls with the
    pair's draft), the two dishes (tori) cut, C's post fused."""
    import gmsh

    occ = gmsh.model.occ
    H = pair.H
    if pair.draft:
        wires = [rounded_rectangle(*pair.outline(z), z) for z in (0.0, H)]
        prism = [dt for dt in occ.addThruSections(wires, makeSolid=True, makeRuled=True) if dt[0] == 3]
    else:
        a, b, r = pair.outline(H)
        rect = occ.addRectangle(-a, -b, 0, 2 * a, 2 * b, roundedRadius=r)
        prism = [dt for dt in occ.extrude([(2, rect)], 0, 0, H) if dt[0] == 3]
    tori = []
    for side in (-1, +1):
        x, y, r_ts, r_tf = pair.dish(side)
        tori.append(tkr.occ_dish(x, y, pair.side[side].t_min + r_ts, r_ts, r_tf))
    out, _ = occ.cut(prism, tori)
    occ.synchronize()
    vol = [t for d, t in out if d == 3]
    if pair.ps is not None:
        w = pair.ps["post_half_width"]
        poly = tkr_ps.Geometry.post_polygon(argparse.Namespace(**pair.ps))
        pts = [occ.addPoint(-w, y, z) for y, z in poly]
        lines = [occ.addLine(pts[i], pts[(i + 1) % len(pts)]) for i in range(len(pts))]
        face = occ.addPlaneSurface([occ.addCurveLoop(lines)])
        post = [dt for dt in occ.extrude([(2, face)], 2 * w, 0, 0) if dt[0] == 3]
        out, _ = occ.fuse([(3, vol[0])], post)
        occ.synchronize()
        vol = [t for d, t in out if d == 3]
    assert len(vol) == 1, "the insert is not one solid"
    return vol[0]


def interference(pair):
    """Where the CAD solids of the femur and the insert overlap:
    [(volume mm^3, centre of mass)] of their common parts (OpenCASCADE).
    With an overlap, one part under each condyle; anything else (C's post
    against the bridge or the cam) is a wrong assembly."""
    import gmsh

    gmsh.initialize(["gmsh", "-v", "0"])
    try:
        gmsh.model.add("both")
        f, i = build_femur(pair), build_insert(pair)
        out, _ = gmsh.model.occ.intersect([(3, f)], [(3, i)])
        gmsh.model.occ.synchronize()
        return [
            (gmsh.model.occ.getMass(d, t), np.array(gmsh.model.occ.getCenterOfMass(d, t)))
            for d, t in out
            if d == 3
        ]
    finally:
        gmsh.finalize()


def chordal_triangles(deviation, h_max=H_MAX):
    """The current model's surface triangulated as a CAD exporter does it
    (tkr_ps.chordal_stl: sizes sqrt(8 deviation R) from each face's
    smallest radius of curvature, at most h_max): points and triangles."""
    import gmsh

    sizes = tkr_ps.face_sizes_for_deviation(deviation, h_max)

    def size(dim, tag, x, y, z):
        if dim == 2:
            return sizes.get(tag, h_max)
        faces = gmsh.model.getAdjacencies(1, tag)[0] if dim == 1 else []
        if dim == 0:
            faces = [
                f for c in gmsh.model.getAdjacencies(0, tag)[0] for f in gmsh.model.getAdjacencies(1, c)[0]
            ]
        return min([sizes[f] for f in faces] or [h_max])

    gmsh.model.mesh.setSizeCallback(size)
    for k, v in (("MeshSizeFromPoints", 0), ("MeshSizeFromCurvature", 0), ("MeshSizeExtendFromBoundary", 0)):
        gmsh.option.setNumber("Mesh." + k, v)
    gmsh.option.setNumber("Mesh.MeshSizeMax", h_max)
    gmsh.option.setNumber("Mesh.Algorithm", 6)
    try:
        gmsh.model.mesh.generate(2)
    finally:
        gmsh.model.mesh.removeSizeCallback()
    X, T = surface_mesh(gmsh)
    return indexed(X[T])


# ---------------------------------------------------------------- decimation
def decimate(X, T, target, max_turn=60.0, max_aspect=100.0):
    """Quadric-error decimation (Garland and Heckbert 1997) of a closed,
    manifold, outward oriented surface down to `target` triangles, by
    half-edge collapses: a vertex a is moved onto a neighbour b (so every
    remaining vertex is one of the input's, on the CAD surface), at the
    cost x_b^T Q_a x_b, Q_a the area-weighted plane quadrics accumulated on
    a.  Nothing favours well-shaped triangles: across a region curved in
    one direction only the collapses along the straight direction cost
    nothing, so the triangles there grow long and thin, as decimated CAD
    exports have them; creases (sharp edges) cost and stay.  A collapse is
    refused where it would make the surface non-manifold (the link
    condition: a and b share exactly the two vertices opposite their edge),
    turn a triangle's normal by more than max_turn deg or make one longer
    than max_aspect times its height (long, but not degenerate).  Returns
    points and triangles (unused points dropped)."""
    X = np.asarray(X, float)
    T = np.array(T, np.int64)
    Xh = np.column_stack([X, np.ones(len(X))])
    nrm = np.cross(X[T[:, 1]] - X[T[:, 0]], X[T[:, 2]] - X[T[:, 0]])
    area = 0.5 * np.linalg.norm(nrm, axis=1)
    nrm = nrm / np.maximum(2 * area, 1e-300)[:, None]
    plane = np.column_stack([nrm, -np.einsum("ij,ij->i", nrm, X[T[:, 0]])])
    K = area[:, None, None] * plane[:, :, None] * plane[:, None, :]
    Q = np.zeros((len(X), 4, 4))
    for k in range(3):
        np.add.at(Q, T[:, k], K)
    vf = [set() for _ in range(len(X))]
    for i, t in enumerate(T.tolist()):
        for v in t:
            vf[v].add(i)
    alive = np.ones(len(T), bool)
    count = len(T)
    stamp = np.zeros(len(X), np.int64)
    cos_turn = math.cos(max_turn * DEG)

    def neighbours(v):
        return {u for f in vf[v] for u in T[f]} - {v}

    def cost(a, b):
        return float(Xh[b] @ Q[a] @ Xh[b])

    heap = []
    E = np.unique(np.sort(np.concatenate([T[:, [0, 1]], T[:, [1, 2]], T[:, [2, 0]]]), axis=1), axis=0)
    for a, b in ((E[:, 0], E[:, 1]), (E[:, 1], E[:, 0])):
        c = np.einsum("ij,ijk,ik->i", Xh[b], Q[a], Xh[b])
        heap += list(zip(c.tolist(), a.tolist(), b.tolist(), [0] * len(a)))
    heapq.heapify(heap)

    def valid(a, b):
        shared = [f for f in vf[a] if b in T[f]]
        if len(shared) != 2:
            return False
        opposite = {u for f in shared for u in T[f]} - {a, b}
        if neighbours(a) & neighbours(b) != opposite:
            return False
        for f in vf[a]:
            if f in shared:
                continue
            P = X[T[f]]
            old = np.cross(P[1] - P[0], P[2] - P[0])
            P = np.where((T[f] == a)[:, None], X[b], P)
            new = np.cross(P[1] - P[0], P[2] - P[0])
            ln, lo = np.linalg.norm(new), np.linalg.norm(old)
            e2 = max(np.sum((P - np.roll(P, 1, axis=0)) ** 2, axis=1))
            if e2 > max_aspect * ln or new @ old < cos_turn * ln * lo:
                return False
        return True

    while count > target and heap:
        c, a, b, s = heapq.heappop(heap)
        if s != stamp[a] or not vf[a] or not vf[b] or not valid(a, b):
            continue
        shared = [f for f in vf[a] if b in T[f]]
        for f in shared:
            alive[f] = False
            for v in T[f]:
                vf[v].discard(f)
        count -= 2
        for f in vf[a]:
            T[f][T[f] == a] = b
            vf[b].add(f)
        vf[a] = set()
        Q[b] += Q[a]
        stamp[b] += 1
        # b's quadric changed (its old entries are stale by their stamp); the
        # edges at b are offered again (a refused one may be valid now)
        for u in neighbours(b):
            heapq.heappush(heap, (cost(u, b), u, b, stamp[u]))
            heapq.heappush(heap, (cost(b, u), b, u, stamp[b]))
    T = T[alive]
    used, T = np.unique(T, return_inverse=True)
    return X[used], T.reshape(-1, 3)


# ---------------------------------------------------------------- measures
def check_closed(X, T):
    """Raises (SystemExit) unless the triangles form a closed, manifold
    surface; returns them oriented outward (rounded.orient_outward)."""
    return orient_outward(X, T)


def aspect(X, T):
    """Per triangle: longest edge / (2 area / longest edge), i.e. the
    longest edge over the height onto it (1.15 for an equilateral one)."""
    P = X[T]
    e = np.linalg.norm(P - np.roll(P, 1, axis=1), axis=2).max(axis=1)
    a2 = np.linalg.norm(np.cross(P[:, 1] - P[:, 0], P[:, 2] - P[:, 0]), axis=1)
    return e * e / np.maximum(a2, 1e-300)


def normals(X, T):
    n = np.cross(X[T[:, 1]] - X[T[:, 0]], X[T[:, 2]] - X[T[:, 0]])
    return n / np.maximum(np.linalg.norm(n, axis=1), 1e-300)[:, None]


def wall_draft(pair, X, T, tol=0.01):
    """Angles (deg) of the outward normals below the horizontal of the
    insert's flat outer wall triangles: all three vertices within tol mm of
    the outline at their height, on its straight sides (not in the corners,
    whose cones a triangle spans as a chord, tilted by up to 1.5 deg), 0.5
    mm clear of the base and the top."""
    P = X[T]
    z = P[..., 2]
    a, b, r = pair.outline(z)
    q = np.abs(P[..., :2]) - np.stack([a - r, b - r], axis=-1)
    sd = np.linalg.norm(np.maximum(q, 0), axis=-1) + np.minimum(q.max(axis=-1), 0) - r
    sel = (np.abs(sd) < tol).all(axis=1) & (q.min(axis=-1) < 1e-6).all(axis=1)
    sel &= (z.min(axis=1) > 0.5) & (z.max(axis=1) < pair.H - 0.5)
    n = normals(X, T)[sel]
    return np.degrees(np.arcsin(np.clip(-n[:, 2], -1, 1)))


def arc_fit(y, z, drop):
    """Least-squares circle (centre yc, zc, radius R) in the sagittal plane
    through points that lie at the distance R - drop_i from the centre (a
    surface of revolution about an axis parallel to x, sampled off its
    middle plane: the femur's condyle, the insert's dish): returns (R, yc,
    zc, rms).  Started from the algebraic fit of the points lowered by
    their drop."""
    import flexion_axis
    from scipy.optimize import least_squares

    yc, zc, r, _ = flexion_axis.fit_circle(y, z - drop)

    def res(c):
        return np.hypot(y - c[0], z - c[1]) + drop - c[2]

    sol = least_squares(res, [yc, zc, r], xtol=1e-12, ftol=1e-12)
    yc, zc, r = sol.x
    return float(r), float(yc), float(zc), float(np.sqrt(np.mean(res(sol.x) ** 2)))


def sagittal_arc(X, T, xc, r_frontal, facing, window=0.8, band=3.0):
    """The sagittal arc of a surface of revolution about an axis parallel
    to x (a condyle's distal arc: facing -1, its vertices on triangles
    facing down; a dish: facing +1) measured on an STL: the vertices within
    `band` mm of x = xc and within `window` mm (after the frontal drop)
    above the lowest, fitted by arc_fit with the frontal drop r_frontal -
    sqrt(r_frontal^2 - u^2) at u = x - xc: (R, yc, zc, rms, vertices); the
    lowest point of the arc is zc - R."""
    on = np.zeros(len(X), bool)
    on[T[facing * normals(X, T)[:, 2] > 0.3].ravel()] = True
    u = X[:, 0] - xc
    sel = on & (np.abs(u) < band)
    drop = r_frontal - np.sqrt(np.maximum(r_frontal**2 - u**2, 0.0))
    zlow = (X[:, 2] - drop)[sel].min()
    sel &= X[:, 2] - drop < zlow + window
    r, yc, zc, rms = arc_fit(X[sel, 1], X[sel, 2], drop[sel])
    return r, yc, zc, rms, int(sel.sum())


def faceted_overlap(pair, Xf, Tf, Xi, Ti, radius=4.0):
    """Largest vertical overlap (mm, > 0: the femur below the insert) of
    the femur's vertices within `radius` mm in plan of a condyle's lowest
    point over the insert's faceted top, per side."""
    ni = normals(Xi, Ti)
    top = Ti[ni[:, 2] > 0.2]
    P = Xi[top]
    out = {}
    for side in (-1, 1):
        low = pair.lowest(side)
        sel = np.hypot(Xf[:, 0] - low[0], Xf[:, 1] - low[1]) < radius
        best = -np.inf
        near = (np.abs(P[:, :, :2].mean(axis=1) - low[:2]) < radius + H_MAX).all(axis=1)
        A, B, C = P[near, 0], P[near, 1], P[near, 2]
        det = (B[:, 0] - A[:, 0]) * (C[:, 1] - A[:, 1]) - (C[:, 0] - A[:, 0]) * (B[:, 1] - A[:, 1])
        for x, y, zf in Xf[sel]:
            l1 = ((B[:, 0] - x) * (C[:, 1] - y) - (C[:, 0] - x) * (B[:, 1] - y)) / det
            l2 = ((C[:, 0] - x) * (A[:, 1] - y) - (A[:, 0] - x) * (C[:, 1] - y)) / det
            l3 = 1 - l1 - l2
            hit = (l1 >= -1e-9) & (l2 >= -1e-9) & (l3 >= -1e-9)
            if hit.any():
                zi = (l1 * A[:, 2] + l2 * B[:, 2] + l3 * C[:, 2])[hit].max()
                best = max(best, zi - zf)
        out[side] = float(best)
    return out


def sharp_edge_turn(X, T, x_edge, z_max):
    """Largest turn (deg) of the normals across the femur's edges whose
    both vertices lie within 0.01 mm of |x| = x_edge and below z_max: the
    articular face against the side wall."""
    n = normals(X, T)
    E = np.concatenate([T[:, [0, 1]], T[:, [1, 2]], T[:, [2, 0]]])
    key = np.sort(E, axis=1)
    owner = np.tile(np.arange(len(T)), 3)
    order = np.lexsort(key.T[::-1])
    key, owner = key[order], owner[order]
    pair = owner.reshape(-1, 2)  # closed manifold: each edge twice
    k = key[::2]
    on = (np.abs(np.abs(X[k[:, 0], 0]) - x_edge) < 0.01) & (np.abs(np.abs(X[k[:, 1], 0]) - x_edge) < 0.01)
    on &= np.maximum(X[k[:, 0], 2], X[k[:, 1], 2]) < z_max
    if not on.any():
        return 0.0
    c = np.einsum("ij,ij->i", n[pair[on, 0]], n[pair[on, 1]])
    return float(np.degrees(np.arccos(np.clip(c, -1, 1))).max())


def features(pair, femur, insert):
    """What the STL pair has, measured on it: a dict and report lines."""
    Xf, Tf = indexed(read_stl(femur))
    Xi, Ti = indexed(read_stl(insert))
    Tf, Ti = check_closed(Xf, Tf), check_closed(Xi, Ti)
    g = pair.side[+1]
    f = dict(triangles=(len(Tf), len(Ti)))
    lines = [
        "femur %s: %d triangles; insert %s: %d triangles; both closed, manifold, outward"
        % (os.path.basename(femur), len(Tf), os.path.basename(insert), len(Ti))
    ]
    for name, X, T in (("femur", Xf, Tf), ("insert", Xi, Ti)):
        q = aspect(X, T)
        f[name + "_aspect"] = q
        lines.append(
            "%s triangles: longest edge over height median %.1f, 90 %% %.1f, max %.0f; %.1f %% above 10"
            % (name, np.median(q), np.percentile(q, 90), q.max(), 100 * np.mean(q > 10))
        )
    if getattr(pair, "cam_inside", None):
        lines.append(
            "cam: radius %g, axis (y, z) (%.3f, %.3f), the mean of the two condyles' (theta %g, inset %g); "
            "its end discs %.0f %% (+x) and %.0f %% (-x) inside the condyles"
            % (
                (pair.ps["cam_radius"],)
                + tuple(pair.cam_axis)
                + (
                    pair.ps["cam_theta"],
                    pair.ps["cam_eta"],
                    100 * pair.cam_inside[1],
                    100 * pair.cam_inside[-1],
                )
            )
        )
    f["edge_turn"] = sharp_edge_turn(Xf, Tf, g.x_out, pair.lowest(1)[2] + 6.0)
    lines.append(
        "femur: normals turn by up to %.1f deg across the condyles' outer edges (|x| = %.1f, "
        "distal 6 mm)" % (f["edge_turn"], g.x_out)
    )
    f["arcs"], f["dishes"], f["overlap"] = {}, {}, {}
    for side in (1, -1):
        gs = pair.side[side]
        # the distal arc only (B's is short): within 90 % of its rise at its nearer end
        rise = gs.R_d * (1 - math.cos(min(-gs.th["th_0"], gs.th["th_1"])))
        r, yc, zc, rms, n = sagittal_arc(Xf, Tf, side * gs.x_c, gs.R_f, -1, window=min(0.8, 0.9 * rise))
        f["arcs"][side] = (r, yc, zc)
        lines.append(
            "condyle %s (%s): distal arc radius %.3f mm, centre (y, z) (%.3f, %.3f), rms %.4f mm, "
            "%d vertices (CAD: %.3f at (%.3f, %.3f))"
            % (
                ("+x" if side > 0 else "-x", "medial" if side > 0 else "lateral", r, yc, zc, rms, n, gs.R_d)
                + tuple(gs.C_d)
            )
        )
        x, y, r_ts, r_tf = pair.dish(side)
        rd, ycd, zcd, rmsd, nd = sagittal_arc(Xi, Ti, x, r_tf, +1)
        f["dishes"][side] = (rd, ycd, zcd)
        f["overlap"][side] = (zcd - rd) - (zc - r)
        lines.append(
            "dish %s: sagittal radius %.3f mm, bottom (y, z) (%.3f, %.3f), rms %.4f mm, %d vertices "
            "(CAD: %.3f at (%.3f, %.3f)); the condyle's lowest point %.4f mm below it"
            % ("+x" if side > 0 else "-x", rd, ycd, zcd - rd, rmsd, nd, r_ts, y, gs.t_min, f["overlap"][side])
        )
    w = wall_draft(pair, Xi, Ti)
    f["draft"] = w
    lines.append(
        "insert walls: outward normals %.3f to %.3f deg below the horizontal (%d flat wall triangles)"
        % (w.min(), w.max(), len(w))
        if len(w)
        else "insert walls: none found"
    )
    f["faceted_overlap"] = faceted_overlap(pair, Xf, Tf, Xi, Ti)
    lines.append(
        "the femur's vertices below the insert's faceted top by up to %.4f mm (+x), %.4f mm (-x)"
        % (f["faceted_overlap"][1], f["faceted_overlap"][-1])
    )
    return f, lines


# ---------------------------------------------------------------- main
def make(name, outdir, coarse=False):
    """Write outdir/name-femur.stl, name-insert.stl and name.txt; returns
    (pair, femur path, insert path)."""
    import gmsh

    spec = INPUTS[name]
    pair = Pair(**spec)
    chordal = COARSE["chordal"] if coarse else CHORDAL
    fine = COARSE["chordal_fine"] if coarse else CHORDAL_FINE
    lines = ["%s: %s" % (name, ", ".join("%s %s" % kv for kv in spec.items()))]
    paths = []
    for k, (part, build) in enumerate((("femur", build_femur), ("insert", build_insert))):
        gmsh.initialize(["gmsh", "-v", "0"])
        try:
            gmsh.model.add(part)
            build(pair)
            if pair.decimate:
                X, T = chordal_triangles(fine, COARSE["h_max_fine"] if coarse else H_MAX_FINE)
            else:
                X, T = chordal_triangles(chordal)
        finally:
            gmsh.finalize()
        T = check_closed(X, T)
        made = "chordal export %g mm: %d triangles" % (fine if pair.decimate else chordal, len(T))
        if pair.decimate:
            target = pair.decimate[k] * (COARSE["decimate_scale"] if coarse else 1.0)
            X, T = decimate(X, T, int(target))
            T = check_closed(X, T)
            made += ", decimated to %d" % len(T)
        path = os.path.join(outdir, "%s-%s.stl" % (name, part))
        write_stl_binary(path, X[T])
        paths.append(path)
        lines.append("%s: %s" % (part, made))
    common = interference(pair)
    lines.append(
        "CAD solids in common: %s"
        % ("; ".join("%.3f mm^3 at (%.1f, %.1f, %.2f)" % ((v,) + tuple(c)) for v, c in common) or "none")
    )
    f, more = features(pair, *paths)
    with open(os.path.join(outdir, name + ".txt"), "w") as out:
        out.write("\n".join(lines + more) + "\n")
    print("\n".join(lines + more))
    return pair, paths[0], paths[1]


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("names", nargs="*", help="inputs to make (default: all)")
    ap.add_argument("-o", "--outdir", default=".")
    ap.add_argument("--coarse", action="store_true", help="coarser export and decimation (tests)")
    ap.add_argument("--list", action="store_true", help="list the inputs and stop")
    a = ap.parse_args(argv)
    if a.list:
        for k, v in INPUTS.items():
            print("%-12s %s" % (k, ", ".join("%s %s" % kv for kv in v.items())))
        return 0
    for name in a.names or INPUTS:
        if name not in INPUTS:
            raise SystemExit("error: no input %r (known: %s)" % (name, ", ".join(INPUTS)))
        make(name, a.outdir, a.coarse)
    return 0


if __name__ == "__main__":
    sys.exit(main())
