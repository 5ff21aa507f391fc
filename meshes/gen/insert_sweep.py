# SPDX-License-Identifier: LGPL-2.1-or-later
"""The insert of scripts/mesh-implant as swept hexahedra: structured columns
under a regular quadrilateral grid (`--method auto`; doc/geometry.md).

The mortar coupling reads the contact pressure at the insert's (slave)
nodes. On kite-shaped quadrilaterals (triangles split into three, the
contact_layer method) or on tetrahedra split into hexahedra, the nodal
pressures of a conforming contact scatter by some 30 %: the nodes of
different kinds (a triangle's corners, edge midpoints and centroid) see
different stencils.  On a structured grid they do not.

What is swept (issue 50): every fixed-bearing insert's articular surface
is a height field over its footprint, pressed from above by the femur, and
the insert stands on a flat seat held by the tray.  Its side walls, rims
and recesses are what its maker chose (walls drafted either way, rounded
rims, a locking recess under the seat) and barely change the compliance
under the articular surface, so the insert is meshed from its top and its
seat alone, whatever the walls do, and the walls are approximated:

1. the seat: the tibia_inferior triangles at the lowest height that face
   straight down, at height z0 (a scanned seat within 0.1 mm);
2. the top: the triangles facing up at less than 60 degrees from the
   horizontal (n_z > T_TOP = 0.5), their largest connected part; its
   outline in plan is the footprint of the columns.  Why this outline and
   not the outline of the insert's projection: the projection's outline is
   where the walls are widest; for a seat wider than the top (draft with
   the walls' outward normals pointing up) it is the seat's edge, where the
   upper surface comes down the wall to the seat, so the columns there
   would shrink to nothing, and a locking tab at the seat would widen it
   where there is no articular height at all.  The top's outline is where
   the heights are known and the columns stand at full height; a wall
   drafted by less than 60 degrees either way is never part of it, while
   articular slopes stay far gentler than 60 degrees.  On a rounded rim
   the outline lies where the rim is 60 degrees steep (0.13 times its
   radius in from the wall).  What this adds or leaves out: the wedge of a
   drafted wall (H^2 tan(draft) / 2 per mm of outline: left out under a top
   narrower than the seat, added under an overhanging top), the outer part
   of a rounded rim, the recess's walls ramped over one cell; mesh_insert
   reports the meshed volume against the input's.  When the walls are
   vertical the top's outline is the seat's, and the seat's outline gives
   it (on CAD its curves, exactly: the meshes are those of before issue
   50);
3. the plan grid is an O-grid: a rectangle of square cells of the plan
   size h around the centroid of the footprint, and four ring blocks out to
   the footprint's outline along rays from the centroid (the outline must
   be star-shaped with respect to it; off CAD curves it is resampled along
   720 rays and smoothed over h/4, since the triangles' edges at the 60
   degree line of a rounded rim zigzag);
4. every plan node carries a column from the seat (or from a recess's
   floor, a flat face facing down above the seat and below the top; only
   the seat's quadrangles are tibia_inferior) up to the top, whose height
   is found by vertical projection onto the top's faces (Newton iterations
   with the faces' closest points and normals on CAD; on an STL the
   triangulated surface is the geometry); the columns have `cells` cells,
   graded so that the cell at the top is `top_cell` thick where the insert
   is thinnest;
5. a hole of the top whose inside rises more than RAISED above its rim is
   a raised feature, a tibial post: kept when its sides are vertical faces
   forming one axis-aligned rectangle in plan and its block of columns has
   cells fit for contact (scaled Jacobian at least POST_QUALITY, tkr-wear's
   threshold for tibia_contact cells); otherwise (drafted post walls, say)
   it is left out, the columns under it ending on the surrounding height
   field interpolated across it (a thin-plate spline through the top's
   vertices around the hole), but only if the femur stays farther than the
   contact distance from every point of the post in every pose of the
   flexion range (surface_tags.approach(): the poses in which
   surface_tags.py finds tibia_contact): a post part that is no
   tibia_contact there carries no load in that range.  If the femur comes
   closer, the insert is refused (Refused).

Every top node lies on the articular surface; the edges where two top faces
meet (the rims of the dishes) are not aligned with the grid, so the faceted
top cuts them slightly, as on the parametric meshes.
"""
import math

import numpy as np

from blockmesh import Body, corner_jacobians, graded, hex_volumes

import gmsh

T_TOP = 0.5  # the top: triangles facing up at less than 60 degrees from the horizontal
RAISED = 1.0  # mm: a hole of the top whose inside rises this much above its rim holds a raised feature
POST_QUALITY = 0.3  # a kept post's cells: at least tkr-wear's Mesh/Contact cell quality


class NotSweepable(Exception):
    """The insert has no flat seat or no top to sweep; the message says
    what.  (Inside mesh_insert also a raised feature that the sweep cannot
    mesh; it is then left out or refused.)"""


class Refused(RuntimeError):
    """The insert cannot be meshed for contact: a post that the sweep
    cannot mesh with cells fit for contact and that the femur reaches in
    the flexion range.  The message is one line that names an option."""


# ------------------------------------------------------------------ faces
def boundary_triangles(vol):
    """{face: (triangles as coordinates (T x 3 x 3), outward normals (T x 3))}
    of the current 2D mesh of the boundary of volume `vol`, outward by the
    enclosed volume."""
    tags, coords, _ = gmsh.model.mesh.getNodes()
    X = np.zeros((int(tags.max()) + 1, 3))
    X[tags.astype(np.int64)] = coords.reshape(-1, 3)
    out = {}
    for _, s in gmsh.model.getBoundary([(3, vol)], oriented=True):
        sign = 1 if s > 0 else -1
        s = abs(s)
        tri = []
        for et, _, nt in zip(*gmsh.model.mesh.getElements(2, s)):
            if et == 2:
                tri.append(np.array(nt, np.int64).reshape(-1, 3))
        if not tri:
            continue
        P = X[np.concatenate(tri)]
        n = np.cross(P[:, 1] - P[:, 0], P[:, 2] - P[:, 0])
        n = sign * n / np.linalg.norm(n, axis=1)[:, None]
        out[s] = (P, n)
    vol6 = sum(
        np.einsum(
            "ij,ij->i",
            P.mean(axis=1),
            n * 0.5 * np.linalg.norm(np.cross(P[:, 1] - P[:, 0], P[:, 2] - P[:, 0]), axis=1)[:, None],
        ).sum()
        for P, n in out.values()
    )
    if vol6 < 0:
        out = {s: (P, -n) for s, (P, n) in out.items()}
    return out


def node_normals(faces, cad):
    """{face: outward unit normals at its triangles' corners}: the CAD
    normals (STEP), else the triangles' own."""
    out = {}
    for s, (P, n) in faces.items():
        if not cad:
            out[s] = n
            continue
        pts = P.reshape(-1, 3)
        uv = gmsh.model.getParametrization(2, s, pts.reshape(-1))
        m = np.array(gmsh.model.getNormal(s, uv)).reshape(-1, 3)
        if np.sum(m * np.repeat(n, 3, axis=0)) < 0:
            m = -m
        out[s] = m
    return out


def triangle_areas(P):
    """Areas of triangles P (T x 3 x 3)."""
    return 0.5 * np.linalg.norm(np.cross(P[:, 1] - P[:, 0], P[:, 2] - P[:, 0]), axis=1)


def split_stl_faces(faces, groups, vertical=0.15):
    """STL faces come from a feature-angle split, which can join a vertical
    wall and an inclined face meeting at a shallow angle (a post's anterior
    face and its chamfer): split each such face into its near-vertical
    triangles (|n_z| < vertical; a new id, face + 1000000) and the rest.
    Returns (faces, groups) with the new ids, which keep their face's group."""
    out, grp = {}, dict(groups)
    for s, (P, n) in faces.items():
        v = np.abs(n[:, 2]) < vertical
        if np.all(v) or not np.any(v) or np.all(n[:, 2] < -0.9):
            out[s] = (P, n)
            continue
        out[s] = (P[~v], n[~v])
        out[s + 1000000] = (P[v], n[v])
        grp[s + 1000000] = groups.get(s)
    return out, grp


def outer_loop(segs):
    """The segments of the closed loop that encloses the largest area (the
    outline of a base with a recess: not the recess's own outlines)."""

    def key(q):
        return (round(float(q[0]), 6), round(float(q[1]), 6))

    nxt = {}
    for i, (a, b) in enumerate(segs):
        nxt.setdefault(key(a), []).append(i)
        nxt.setdefault(key(b), []).append(i)
    used = np.zeros(len(segs), bool)
    best, best_area = None, -1.0
    for i0 in range(len(segs)):
        if used[i0]:
            continue
        loop, p = [i0], key(segs[i0][1])
        pts = [segs[i0][0], segs[i0][1]]
        used[i0] = True
        while True:
            cand = [j for j in nxt.get(p, []) if not used[j]]
            if not cand:
                break
            i = cand[0]
            used[i] = True
            loop.append(i)
            a, b = segs[i]
            q = b if key(a) == p else a
            pts.append(q)
            p = key(q)
        pts = np.array(pts)
        area = abs(0.5 * np.sum(pts[:, 0] * np.roll(pts[:, 1], -1) - np.roll(pts[:, 0], -1) * pts[:, 1]))
        if area > best_area:
            best, best_area = loop, area
    return segs[best] if best is not None else segs


# ------------------------------------------------------------------ the top's region
def merge_vertices(P):
    """Corners of triangles P (T x 3 x 3) merged where equal to 1e-9 mm:
    (points, T x 3 indices)."""
    pts, inv = np.unique(np.round(P.reshape(-1, 3), 9), axis=0, return_inverse=True)
    return pts, inv.reshape(-1, 3)


def outward(P, n):
    """Triangles P with their corners ordered so that they turn about the
    outward normals n (boundary_triangles() gives the normals, not a
    consistent order)."""
    flip = np.einsum("ij,ij->i", np.cross(P[:, 1] - P[:, 0], P[:, 2] - P[:, 0]), n) < 0
    return np.where(flip[:, None, None], P[:, ::-1], P)


def components(T, mask):
    """Connected parts (across shared edges) of the triangles T[mask]: a
    label per triangle, -1 outside the mask."""
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components

    idx = np.flatnonzero(mask)
    E = np.sort(np.concatenate([T[idx][:, [a, b]] for a, b in ((0, 1), (1, 2), (2, 0))]), axis=1)
    owner = np.tile(np.arange(len(idx)), 3)
    order = np.lexsort((E[:, 1], E[:, 0]))
    E, owner = E[order], owner[order]
    same = np.flatnonzero((E[1:] == E[:-1]).all(axis=1))
    graph = coo_matrix((np.ones(len(same)), (owner[same], owner[same + 1])), shape=(len(idx), len(idx)))
    label = np.full(len(T), -1)
    label[idx] = connected_components(graph, directed=False)[1]
    return label


def signed_area(poly):
    """Signed area of a plan polygon (n x 2; counter-clockwise > 0)."""
    return 0.5 * float(np.sum(poly[:, 0] * np.roll(poly[:, 1], -1) - np.roll(poly[:, 0], -1) * poly[:, 1]))


def boundary_loops(pts, T, mask):
    """The closed boundary loops of the triangles T[mask], which face up
    and turn counter-clockwise in plan: [(vertex indices, signed plan
    area)]; a loop around the part is counter-clockwise (area > 0), one
    around a hole clockwise.  Where the part touches itself at a vertex the
    loop turns right as far as it can, so that loops stay simple."""
    D = np.concatenate([T[mask][:, [a, b]] for a, b in ((0, 1), (1, 2), (2, 0))])
    inner = set(map(tuple, D.tolist()))
    out = {}
    for a, b in D.tolist():
        if (b, a) not in inner:
            out.setdefault(a, []).append(b)
    used = set()
    loops = []
    for a0 in list(out):
        for b0 in out[a0]:
            if (a0, b0) in used:
                continue
            loop, a, b = [a0], a0, b0
            used.add((a, b))
            while b != a0:
                loop.append(b)
                cand = [c for c in out.get(b, []) if (b, c) not in used]
                if not cand:
                    break
                d_in = pts[b, :2] - pts[a, :2]
                turn = [
                    math.atan2(
                        d_in[0] * (pts[c, 1] - pts[b, 1]) - d_in[1] * (pts[c, 0] - pts[b, 0]),
                        d_in[0] * (pts[c, 0] - pts[b, 0]) + d_in[1] * (pts[c, 1] - pts[b, 1]),
                    )
                    for c in cand
                ]
                a, b = b, cand[int(np.argmin(turn))]
                used.add((a, b))
            loops.append((np.array(loop), signed_area(pts[loop, :2])))
    return loops


def in_polygon(XY, poly):
    """Whether plan points XY (n x 2) lie inside the polygon (m x 2; even-odd
    rule)."""
    XY = np.asarray(XY, float).reshape(-1, 2)
    a, b = poly, np.roll(poly, -1, axis=0)
    x, y = XY[:, 0:1], XY[:, 1:2]
    span = (a[None, :, 1] > y) != (b[None, :, 1] > y)
    dy = np.where(b[:, 1] != a[:, 1], b[:, 1] - a[:, 1], 1.0)
    cross = span & (x < a[None, :, 0] + (b[None, :, 0] - a[None, :, 0]) * (y - a[None, :, 1]) / dy[None, :])
    return cross.sum(axis=1) % 2 == 1


def loop_segments(poly):
    """Segments (n x 2 x 2) of a closed plan polygon."""
    return np.stack([poly, np.roll(poly, -1, axis=0)], axis=1)


def star_outline(c, segs, smooth, rays=720):
    """The outline `segs` resampled along `rays` rays from c (it must be
    star-shaped with respect to c) and smoothed: each point the Gaussian
    mean (over `smooth` mm of arc length) of its neighbours, which keeps a
    straight side straight and moves a convex one inwards, onto the top.
    Returns the segments of the new polygon."""
    t = np.linspace(0.0, 2.0 * np.pi, rays, endpoint=False)
    Q = ray_to_outline(c, c + np.column_stack([np.cos(t), np.sin(t)]), segs)
    if smooth > 0:
        width = smooth / np.mean(np.linalg.norm(Q - np.roll(Q, 1, axis=0), axis=1))  # in points
        k = np.arange(-int(math.ceil(3 * width)), int(math.ceil(3 * width)) + 1)
        w = np.exp(-0.5 * (k / max(width, 1e-9)) ** 2)
        Q = sum(wi * np.roll(Q, -ki, axis=0) for ki, wi in zip(k, w)) / w.sum()
    return loop_segments(Q)


def weighted_quantiles(v, w, q):
    """Quantiles q of values v with weights w."""
    order = np.argsort(v)
    cw = np.cumsum(w[order])
    return np.interp(np.asarray(q) * cw[-1], cw, v[order])


class Fill:
    """Heights over the holes of the top whose raised features are left
    out: per hole a thin-plate spline (scipy's RBFInterpolator) through the
    top's vertices within 2 h of the hole, outside it."""

    def __init__(self, holes, X, h):
        from scipy.interpolate import RBFInterpolator

        self.polys, self.splines = [], []
        for poly in holes:
            near = (plan_distance(X[:, :2], loop_segments(poly)) < 2.0 * h) & ~in_polygon(X[:, :2], poly)
            if near.sum() < 6:
                raise NotSweepable(
                    "too few points of the top around a hole at (%.1f, %.1f)" % tuple(poly.mean(0))
                )
            self.polys.append(poly)
            self.splines.append(RBFInterpolator(X[near, :2], X[near, 2], kernel="thin_plate_spline"))

    def which(self, XY):
        """Index of the hole each plan point lies in, -1 outside all."""
        out = np.full(len(XY), -1)
        for i, poly in enumerate(self.polys):
            out[(out < 0) & in_polygon(XY, poly)] = i
        return out

    def __call__(self, XY, which):
        z = np.empty(len(XY))
        for i, spline in enumerate(self.splines):
            m = which == i
            if np.any(m):
                z[m] = spline(XY[m])
        return z


# ------------------------------------------------------------------ top
class Top:
    """Vertical projection onto the top faces: a plan lookup in their
    triangles, refined on the CAD faces (project=True)."""

    def __init__(self, faces, top, cad, cell=2.0, fine=None, smooth=None):
        self.fine = None if fine is None else Top({0: (fine, None)}, [0], False, cell)
        self.smooth = smooth
        self.P = np.concatenate([faces[s][0] for s in top])
        self.face = np.concatenate([np.full(len(faces[s][0]), s) for s in top])
        self.cad = cad
        self.cell = cell
        lo = self.P[:, :, :2].min(axis=1)
        hi = self.P[:, :, :2].max(axis=1)
        self.buckets = {}
        for t in range(len(self.P)):
            for bx in range(int(math.floor(lo[t, 0] / cell)), int(math.floor(hi[t, 0] / cell)) + 1):
                for by in range(int(math.floor(lo[t, 1] / cell)), int(math.floor(hi[t, 1] / cell)) + 1):
                    self.buckets.setdefault((bx, by), []).append(t)

    def locate(self, p, inside=False):
        """(triangle, z) of the top triangle above plan point p (the nearest
        one if p is just outside all of them), and with inside=True whether
        p is inside it (within 1e-6 of its edges).  Of several triangles
        above p the highest (by more than 1e-6 mm; else the first): the top
        is the upper envelope (a fold repaired at a base rim leaves
        triangles facing up under it)."""
        best, best_out = None, -np.inf
        b = (int(math.floor(p[0] / self.cell)), int(math.floor(p[1] / self.cell)))
        cands = []
        for dx in (-1, 0, 1):
            for dy in (-1, 0, 1):
                cands += self.buckets.get((b[0] + dx, b[1] + dy), [])
        for t in cands:
            a, bb, c = self.P[t]
            d = (bb[1] - c[1]) * (a[0] - c[0]) + (c[0] - bb[0]) * (a[1] - c[1])
            if abs(d) < 1e-14:
                continue
            l1 = ((bb[1] - c[1]) * (p[0] - c[0]) + (c[0] - bb[0]) * (p[1] - c[1])) / d
            l2 = ((c[1] - a[1]) * (p[0] - c[0]) + (a[0] - c[0]) * (p[1] - c[1])) / d
            l3 = 1 - l1 - l2
            m = min(l1, l2, l3)
            z = l1 * a[2] + l2 * bb[2] + l3 * c[2]
            if best_out >= -1e-12:
                if m >= -1e-12 and z > best[1] + 1e-6:
                    best = (t, z)
            elif m > best_out:
                best, best_out = (t, z), m
        if best is None:
            if inside:
                return None, None, False
            raise NotSweepable("no top face above plan point (%.2f, %.2f)" % (p[0], p[1]))
        return (best[0], best[1], best_out >= -1e-6) if inside else best

    def faces(self, XY):
        """The top face above each plan point."""
        return np.array([self.face[self.locate(p)[0]] for p in XY], np.int64)

    def heights(self, XY):
        """Heights of the top above plan points XY (n x 2) and the top face
        of each."""
        z = np.empty(len(XY))
        f = np.empty(len(XY), np.int64)
        for i, p in enumerate(XY):
            t, z[i] = self.locate(p)
            f[i] = self.face[t]
            if self.fine is not None:
                z[i] = self.fine.locate(p)[1]
        if self.cad:
            for s in np.unique(f):
                m = np.where(f == s)[0]
                z[m] = self._newton(s, XY[m], z[m])
        if self.smooth is not None and len(z):
            # the point moves along the surface normal onto the smooth
            # surface; its height is taken back above XY (twice: a fixed
            # point of the slope's small shift)
            for _ in range(2):
                z = self.smooth(np.column_stack([XY, z]))[:, 2]
        return z, f

    @staticmethod
    def _newton(s, XY, z, steps=8):
        """Points of CAD face s straight above XY, starting from heights z:
        Newton iterations on the tangent plane at the closest point q of the
        current point P (the normal there is along P - q).  A point whose
        iteration does not converge within 0.05 mm of its start keeps its
        start."""
        z0 = z.copy()
        n = np.tile([0.0, 0.0, 1.0], (len(z), 1))
        for _ in range(steps):
            P = np.column_stack([XY, z])
            q, _ = gmsh.model.getClosestPoint(2, int(s), P.reshape(-1))
            q = np.array(q).reshape(-1, 3)
            d = P - q
            dist = np.linalg.norm(d, axis=1)
            far = dist > 1e-10
            n[far] = d[far] / dist[far, None]
            z = q[:, 2] - (n[:, 0] * (XY[:, 0] - q[:, 0]) + n[:, 1] * (XY[:, 1] - q[:, 1])) / n[:, 2]
        P = np.column_stack([XY, z])
        q, _ = gmsh.model.getClosestPoint(2, int(s), P.reshape(-1))
        ok = (np.linalg.norm(np.array(q).reshape(-1, 3) - P, axis=1) < 1e-7) & (np.abs(z - z0) < 0.05)
        Top.n_fallback = getattr(Top, "n_fallback", 0) + int(np.sum(~ok))
        return np.where(ok, z, z0)


# ------------------------------------------------------------------ plan
def outline_segments(base, samples=400):
    """Segments (n x 2 x 2) of the outline of the base faces (the curves
    that bound just one of them, sampled)."""
    count = {}
    for s in base:
        for _, c in gmsh.model.getBoundary([(2, s)], oriented=False):
            count[abs(c)] = count.get(abs(c), 0) + 1
    segs = []
    for c in sorted(k for k, n in count.items() if n == 1):
        lo, hi = gmsh.model.getParametrizationBounds(1, c)
        t = np.linspace(lo[0], hi[0], samples + 1)
        pts = np.array(gmsh.model.getValue(1, c, t)).reshape(-1, 3)[:, :2]
        segs.append(np.stack([pts[:-1], pts[1:]], axis=1))
    return np.concatenate(segs)


def plan_distance(P, segs):
    """Distance of plan points P (n x 2) from the outline segments."""
    A, E = segs[:, 0], segs[:, 1] - segs[:, 0]
    out = np.empty(len(P))
    for i, p in enumerate(P):
        t = np.clip(((p - A) * E).sum(1) / np.maximum((E * E).sum(1), 1e-300), 0, 1)
        out[i] = np.min(np.linalg.norm(A + t[:, None] * E - p, axis=1))
    return out


def ray_to_outline(c, P, segs):
    """Points where the rays from c through the points P meet the outline
    first (the outline must be star-shaped with respect to c)."""
    out = np.empty_like(P)
    A, B = segs[:, 0], segs[:, 1]
    E = B - A
    w = A - c
    for i, p in enumerate(P):
        d = p - c
        den = d[0] * E[:, 1] - d[1] * E[:, 0]
        ok = np.abs(den) > 1e-14
        den = np.where(ok, den, 1.0)
        t = (w[:, 0] * E[:, 1] - w[:, 1] * E[:, 0]) / den
        u = (w[:, 0] * d[1] - w[:, 1] * d[0]) / den
        hit = ok & (u >= -1e-9) & (u <= 1 + 1e-9) & (t > 1e-9)
        if not np.any(hit):
            raise NotSweepable(
                "the ray from the base centroid through (%.2f, %.2f) misses the outline" % tuple(p)
            )
        out[i] = c + np.min(t[hit]) * d
    return out


def plan_rectangle(c, segs, h):
    """Half sides (a, b) of the rectangle of the O-grid: as large as fits
    with at least two plan cells between its corners and the outline and
    one between its sides and the outline."""
    reach = [
        np.linalg.norm(ray_to_outline(c, (c + v)[None], segs)[0] - c)
        for v in ([1.0, 0], [-1.0, 0], [0, 1.0], [0, -1.0])
    ]
    A, B = min(reach[:2]), min(reach[2:])
    for lam in np.linspace(0.98, 0.3, 69):
        a, b = lam * A, lam * B
        if A - a < h or B - b < h:
            continue
        corners = c + np.array([[a, b], [-a, b], [-a, -b], [a, -b]])
        q = ray_to_outline(c, corners, segs)
        beyond = np.einsum("ij,ij->i", q - corners, corners - c) > 0
        if np.all(beyond) and np.min(np.linalg.norm(q - corners, axis=1)) >= 2 * h:
            return a, b
    raise NotSweepable("no rectangle fits inside the base outline")


def grid_line_positions(lo, hi, h, breaks=()):
    """Node positions from lo to hi, about h apart, with nodes at the given
    break points (piecewise uniform)."""
    pts = [lo] + sorted(breaks) + [hi]
    out = [np.array([lo])]
    for a, b in zip(pts[:-1], pts[1:]):
        n = max(1, int(round((b - a) / h)))
        out.append(np.linspace(a, b, n + 1)[1:])
    return np.concatenate(out)


def plan_blocks(c, segs, h, feature=None):
    """Plan node arrays (ni x nj x 2) of the O-grid: the rectangle and four
    ring blocks (first index along the rectangle side, second outward).
    feature: plan rectangle (x0, x1, y0, y1) of a raised feature, which
    must lie inside the O-grid's rectangle at least a cell from its sides;
    the rectangle then has grid lines along the feature's sides."""
    a, b = plan_rectangle(c, segs, h)
    if feature is None:
        nx = max(2, int(round(2 * a / h)))
        ny = max(2, int(round(2 * b / h)))
        x = c[0] + np.linspace(-a, a, nx + 1)
        y = c[1] + np.linspace(-b, b, ny + 1)
    else:
        x0, x1, y0, y1 = feature
        # widen the rectangle to hold the feature and a cell around it if the
        # outline leaves room (a cell between the corners and the outline)
        a2 = max(a, abs(x0 - c[0]) + h, abs(x1 - c[0]) + h)
        b2 = max(b, abs(y0 - c[1]) + h, abs(y1 - c[1]) + h)
        corners = c + np.array([[a2, b2], [-a2, b2], [-a2, -b2], [a2, -b2]])
        q = ray_to_outline(c, corners, segs)
        if (
            np.all(np.einsum("ij,ij->i", q - corners, corners - c) > 0)
            and np.min(np.linalg.norm(q - corners, axis=1)) >= h
        ):
            a, b = a2, b2
        if not (
            c[0] - a + 0.75 * h <= x0
            and x1 <= c[0] + a - 0.75 * h
            and c[1] - b + 0.75 * h <= y0
            and y1 <= c[1] + b - 0.75 * h
        ):
            raise NotSweepable(
                "the raised feature (x %.1f..%.1f, y %.1f..%.1f) does not fit inside the "
                "O-grid's rectangle (x %.1f..%.1f, y %.1f..%.1f)"
                % (x0, x1, y0, y1, c[0] - a, c[0] + a, c[1] - b, c[1] + b)
            )
        x = grid_line_positions(c[0] - a, c[0] + a, h, (x0, x1))
        y = grid_line_positions(c[1] - b, c[1] + b, h, (y0, y1))
    rect = np.stack(np.meshgrid(x, y, indexing="ij"), axis=-1)
    edges = [
        np.stack([np.full_like(y, x[-1]), y], -1),
        np.stack([np.full_like(y, x[0]), y], -1),
        np.stack([x, np.full_like(x, y[-1])], -1),
        np.stack([x, np.full_like(x, y[0])], -1),
    ]
    outs = [ray_to_outline(c, e, segs) for e in edges]
    width = max(np.max(np.linalg.norm(o - e, axis=1)) for e, o in zip(edges, outs))
    n_ring = max(1, int(math.ceil(width / h)))
    s = np.linspace(0.0, 1.0, n_ring + 1)
    ring = [e[:, None, :] + s[None, :, None] * (o - e)[:, None, :] for e, o in zip(edges, outs)]
    return [rect] + ring


def raised_feature(faces, inner, tol):
    """Plan rectangle (x0, x1, y0, y1) enclosed by the vertical faces
    `inner` (which lie inside the base's outline): the sides of a raised
    feature such as a tibial post.  They must form one axis-aligned
    rectangle, each side covered from corner to corner."""
    P = np.concatenate([faces[s][0][..., :2].reshape(-1, 2) for s in inner])
    x0, y0 = P.min(axis=0)
    x1, y1 = P.max(axis=0)
    on = [
        np.abs(P[:, 0] - x0) < tol,
        np.abs(P[:, 0] - x1) < tol,
        np.abs(P[:, 1] - y0) < tol,
        np.abs(P[:, 1] - y1) < tol,
    ]
    if not np.all(np.any(on, axis=0)):
        raise NotSweepable(
            "the vertical faces %s inside the base's outline do not form one axis-aligned "
            "rectangle in plan" % inner
        )
    for m, k, lo, hi in ((on[0], 1, y0, y1), (on[1], 1, y0, y1), (on[2], 0, x0, x1), (on[3], 0, x0, x1)):
        v = np.sort(P[m, k])
        if v[0] > lo + tol or v[-1] < hi - tol or np.max(np.diff(v)) > 0.25 * (hi - lo) + 4.0:
            raise NotSweepable("the vertical faces %s do not close the sides of a raised feature" % inner)
    return float(x0), float(x1), float(y0), float(y1)


def coons(B):
    """Transfinite interpolation of the interior of a tensor array (ni x nj)
    from its boundary rows/columns (parameters from the node indices)."""
    ni, nj = B.shape
    u = np.linspace(0, 1, ni)[:, None]
    v = np.linspace(0, 1, nj)[None, :]
    return (
        (1 - u) * B[0:1, :]
        + u * B[-1:, :]
        + (1 - v) * B[:, 0:1]
        + v * B[:, -1:]
        - ((1 - u) * (1 - v) * B[0, 0] + u * (1 - v) * B[-1, 0] + (1 - u) * v * B[0, -1] + u * v * B[-1, -1])
    )


# ------------------------------------------------------------------ seat and post
def find_seat(faces, groups, nz, flat_tol, flat_normal):
    """The seat: the tibia_inferior triangles facing down (mean n_z below
    -flat_normal) whose corners lie within flat_tol of the lowest point of
    tibia_inferior.  Returns (the faces that are seat throughout, the seat's
    triangles, its mean height z0).  Raises NotSweepable."""
    base = [s for s in faces if groups.get(s) == "tibia_inferior" and len(faces[s][0])]
    if not base:
        raise NotSweepable("the insert has no tibia_inferior face")
    z_min = min(float(faces[s][0][..., 2].min()) for s in base)
    seat = {s: (faces[s][0][..., 2] <= z_min + flat_tol).all(axis=1) & (nz[s] < -flat_normal) for s in base}
    if not any(np.any(m) for m in seat.values()):
        raise NotSweepable(
            "the tibia_inferior faces %s have no flat part facing down at their lowest point z = %.2f mm "
            "(within %g mm): no seat" % (base, z_min, flat_tol)
        )
    S = np.concatenate([faces[s][0][m] for s, m in seat.items()])
    return [s for s, m in seat.items() if np.all(m)], S, float(S[..., 2].mean())


def post_walls(faces, corner_nz, poly, z_rim, tol, cad):
    """The faces that bound a raised feature in the hole `poly` of the top
    (rim heights z_rim): vertical ones (on CAD every corner normal
    horizontal; on an STL |n_z| < 0.15, the chords of curved walls tilt, or
    a sliver under 1 mm^2 at a post's foot) at least half of whose
    triangles lie on or inside the hole in plan, above its rim's lowest
    point (not a recess's walls)."""
    segs = loop_segments(poly)
    out = []
    for s, (P, n) in faces.items():
        vertical = np.max(np.abs(corner_nz[s])) < (1e-6 if cad else 0.15)
        if not vertical and (cad or triangle_areas(P).sum() >= 1.0 or np.all(n[:, 2] > 0.02)):
            continue
        cen = P.mean(axis=1)
        near = (in_polygon(cen[:, :2], poly) | (plan_distance(cen[:, :2], segs) < tol)) & (
            cen[:, 2] > z_rim.min() - tol
        )
        if near.mean() >= 0.5:
            out.append(s)
    return out


def describe_walls(nz, area):
    """Draft of wall triangles in words: the area-weighted median of the
    angle of their outward normals above the horizontal (+: the seat wider
    than the top) and its 5-95 % range."""
    d = np.degrees(np.arcsin(np.clip(nz, -1, 1)))
    lo, med, hi = weighted_quantiles(d, area, [0.05, 0.5, 0.95])
    return (
        "draft %+.1f deg (+: outward normals up, wider below; the area-weighted median over %.0f mm^2 of "
        "walls, 5-95 %%: %+.1f..%+.1f deg)" % (med, area.sum(), lo, hi)
    )


# ------------------------------------------------------------------ body
def mesh_insert(
    vol,
    groups,
    h,
    cells,
    top_cell,
    cad,
    fine=None,
    smooth=None,
    clearance=None,
    contact_distance=3.0,
    log=None,
):
    """The swept insert (the module's steps 1-5) for volume `vol` of the
    current gmsh model, whose boundary is triangulated (any size; it locates
    the top faces).  groups: face -> group.  fine: finer triangles of the
    same surface, outward (an STL repaired by tkr-surface), as one array (T
    x 3 x 3) or per face of the model ({face: triangles}: then the seat and
    a recess's floor come from them too): the top's outline and, from its
    upward triangles, the heights of the top, then put onto smooth(points)
    (a smooth surface through the input's vertices).  clearance(points,
    insert triangles): the femur's smallest distance from each point over
    the flexion range and the flexion of it (mesh-implant:
    surface_tags.approach()); without it a post that must be left out is
    refused.  log: a list that gets the report's lines (also printed).
    Returns (nodes, hexes, surfaces).  Raises NotSweepable, Refused.

    A kept raised feature (a tibial post) is meshed as a block of vertical
    columns standing on the columns below it: the plan grid has lines along
    the feature's sides; under the feature the columns end at the articular
    surface interpolated (transfinite) from the feature's edges; above them
    the feature's columns go up to its top with cells about h high."""
    log = [] if log is None else log

    def say(line):
        print(line)
        log.append(line)

    faces = boundary_triangles(vol)
    if not cad:
        faces, groups = split_stl_faces(faces, groups)
    normals = node_normals(faces, cad)
    corner_nz = {
        s: (normals[s].reshape(-1, 3, 3)[..., 2] if cad else np.repeat(faces[s][1][:, 2:3], 3, axis=1))
        for s in faces
    }
    nz = {s: v.mean(axis=1) for s, v in corner_nz.items()}
    flat_tol, flat_normal = (1e-6, 0.9999) if cad else (0.1, 0.98)  # STL: a scanned seat within 0.1 mm
    tol = 1e-3 if cad else 0.5  # STL: chordal error of the walls
    up_tol = 0.02 if cad else 0.15  # STL: the chords of curved walls tilt
    order = list(faces)
    P_all = np.concatenate([outward(*faces[s]) for s in order])
    nz_all = np.concatenate([nz[s] for s in order])
    # the seat, a recess's floor and the top on the finer surface if there
    # is one (the model's triangles of an STL remeshed for the wear run are
    # 3-4 mm: they cut across a narrow seat between a rounded rim and a
    # recess)
    if isinstance(fine, dict):
        surf = {}
        for k, F in fine.items():
            n = np.cross(F[:, 1] - F[:, 0], F[:, 2] - F[:, 0])
            a = np.linalg.norm(n, axis=1)
            surf[k] = (F[a > 0], n[a > 0] / a[a > 0, None])
        surf_nz = {k: n[:, 2] for k, (_, n) in surf.items()}
    else:
        surf, surf_nz = faces, nz
    seat_faces, S, z0 = find_seat(surf, groups, surf_nz, flat_tol, flat_normal)
    if fine is not None:
        src = np.concatenate(list(fine.values())) if isinstance(fine, dict) else fine
        n = np.cross(src[:, 1] - src[:, 0], src[:, 2] - src[:, 0])
        a = np.linalg.norm(n, axis=1)
        src, src_nz = src[a > 0], n[a > 0, 2] / a[a > 0]
    else:
        src, src_nz = P_all, nz_all
    pts, T = merge_vertices(src)
    top = src_nz > T_TOP
    if not np.any(top):
        raise NotSweepable("no part of the insert faces up (n_z > %g)" % T_TOP)
    part = components(T, top)
    plan = 0.5 * np.abs(np.cross(src[:, 1, :2] - src[:, 0, :2], src[:, 2, :2] - src[:, 0, :2]))
    main = part == np.argmax(np.bincount(part[top], weights=plan[top]))
    loops = boundary_loops(pts, T, main)
    outer, area = max(loops, key=lambda la: la[1])
    if area <= 0:
        raise NotSweepable("the top has no outline")
    foot = pts[outer, :2]
    holes = [(pts[lp, :2], pts[lp, 2]) for lp, a in loops if a < -0.25 * h * h]
    z_top = float(pts[np.unique(T[main]), 2].min())
    reach = z0 + 0.75 * (z_top - z0)

    # a recess's floor: flat, facing down, above the seat, below the top
    floor = np.concatenate(
        [
            surf[s][0][
                (surf_nz[s] < -0.9)
                & (surf[s][0][..., 2].min(axis=1) > z0 + flat_tol)
                & (surf[s][0][..., 2].max(axis=1) < reach)
            ]
            for s in surf
        ]
    )
    if len(floor):
        say(
            "note: %d triangles (%.1f mm2) of the base lie above it (a recess, up to z = %.1f mm): the "
            "columns there stand on them" % (len(floor), triangle_areas(floor).sum(), floor[..., 2].max())
        )

    # the plan outline: the seat's where the walls are vertical (the top's
    # outline on it), else the top's
    seat_segs = outline_segments(seat_faces) if cad and seat_faces else boundary_edges_2d(S)
    if len(floor):
        seat_segs = outer_loop(seat_segs)  # a recess's outlines are no outline
    foot_segs = loop_segments(foot)
    off_seat = plan_distance(foot, seat_segs).max()  # the top's outline off the seat's
    off_top = plan_distance(seat_segs[:, 0], foot_segs).max()  # on CAD: the chords of the top's triangles
    vertical = off_seat <= tol and off_top <= (0.1 * h if cad else tol)
    if vertical:
        w = triangle_areas(S)
        c = (w[:, None] * S.mean(axis=1)[:, :2]).sum(axis=0) / w.sum()
        segs = seat_segs
    else:
        c = np.array(
            [
                np.sum((foot[:, k] + np.roll(foot[:, k], -1)) * np.cross(foot, np.roll(foot, -1, axis=0)))
                for k in (0, 1)
            ]
        ) / (6.0 * signed_area(foot))
        segs = star_outline(c, foot_segs, 0.25 * h)

    # the heights: the model's triangles facing up (per face), the finer
    # surface's if given, above `reach` (a fold repaired at the base rim
    # leaves triangles facing up there, under a node on the outline); off
    # the seat's outline only those over the top's outline (a node a hair
    # beyond it, on a concave part's chord, must not take the height of a
    # drafted wall or a rounded rim falling away there)
    up = {s: (nz[s] > up_tol) & (faces[s][0][..., 2].max(axis=1) > reach) for s in order}
    if not vertical:
        up = {s: m & in_polygon(faces[s][0].mean(axis=1)[:, :2], foot) for s, m in up.items()}
    up_faces = {s: (faces[s][0][m], faces[s][1][m]) for s, m in up.items() if np.any(m)}
    if fine is not None:
        fine = src[
            (src_nz > 0.05)
            & (src[..., 2].max(axis=1) > reach)
            & (vertical or in_polygon(src.mean(axis=1)[:, :2], foot))
        ]
    top_lookup = Top(up_faces, list(up_faces), cad, fine=fine, smooth=smooth)
    up_P = np.concatenate([up_faces[s][0] for s in up_faces])

    # raised features: holes of the top with a surface inside well above their rim
    raised = []
    for poly, z_rim in holes:
        inside = in_polygon(up_P.mean(axis=1)[:, :2], poly)
        if np.any(inside) and up_P[inside][..., 2].max() > z_rim.max() + RAISED:
            raised.append((poly, z_rim))

    def build(feature, inner, fill):
        """(nodes, hexes, surfaces, smallest scaled corner Jacobian of the
        feature's block) for a kept feature (plan rectangle, its wall faces)
        or holes left out (`fill`, a Fill or None)."""
        blocks = plan_blocks(c, segs, h, feature)
        columns = []
        for B in blocks:
            XY = B.reshape(-1, 2)
            hole = fill.which(XY) if fill is not None else np.full(len(XY), -1)
            z = np.empty(len(XY))
            if np.any(hole < 0):
                z[hole < 0] = top_lookup.heights(XY[hole < 0])[0]
            if np.any(hole >= 0):
                z[hole >= 0] = fill(XY[hole >= 0], hole[hole >= 0])
            columns.append(z.reshape(B.shape[:2]))
        upper = None
        if feature is not None:
            # the rectangle block's index range of the feature and the two heights
            # (the articular surface below, the feature's top above) on it
            rect = blocks[0]
            x0, x1, y0, y1 = feature
            i0, i1 = (int(np.argmin(np.abs(rect[:, 0, 0] - v))) for v in (x0, x1))
            j0, j1 = (int(np.argmin(np.abs(rect[0, :, 1] - v))) for v in (y0, y1))
            F = rect[i0 : i1 + 1, j0 : j1 + 1]
            eps = 10 * tol if cad else 2 * tol  # STL: off the chords of the walls, not 5 mm into a chamfer
            ix = np.zeros(F.shape[:2])
            ix[0, :], ix[-1, :] = -1, 1
            iy = np.zeros(F.shape[:2])
            iy[:, 0], iy[:, -1] = -1, 1
            out_dir = np.stack([ix, iy], -1)
            inside = F - eps * out_dir
            hi, _ = top_lookup.heights(inside.reshape(-1, 2))
            hi = hi.reshape(F.shape[:2])
            edge = np.any(out_dir != 0, axis=-1)
            lo = np.zeros(F.shape[:2])
            lo_edge, _ = top_lookup.heights((F + eps * out_dir)[edge])
            lo[edge] = lo_edge
            lo = np.where(edge, lo, coons(lo))
            if np.min(hi - lo) <= tol:
                raise NotSweepable("the raised feature does not rise above the articular surface everywhere")
            columns[0][i0 : i1 + 1, j0 : j1 + 1] = lo
            m = max(1, int(math.ceil(np.max(hi - lo) / h)))
            t = np.linspace(0.0, 1.0, m + 1)
            Z = lo[..., None] + (hi - lo)[..., None] * t
            XY = np.broadcast_to(F[..., None, :], F.shape[:2] + (m + 1, 2))
            upper = np.concatenate([XY, Z[..., None]], axis=-1)
        # the columns' feet: z0, or a recess's floor where one is above
        bottoms = [np.full(z.shape, z0) for z in columns]
        if len(floor):
            under = Top({0: (floor, None)}, [0], False)
            for B, zb in zip(blocks, bottoms):
                for idx in np.ndindex(zb.shape):
                    _, zf, inside = under.locate(B[idx], inside=True)
                    if inside:
                        zb[idx] = zf
        t_min = min(float((z - zb).min()) for z, zb in zip(columns, bottoms))
        if t_min <= 0:
            raise NotSweepable("the top touches the seat")
        sig = 1.0 - graded(cells, 1.0, min(top_cell / t_min, 1.0 / cells))[::-1]
        body = Body("tibia")
        for n, (B, z, zb) in enumerate(zip(blocks, columns, bottoms)):
            Z = zb[..., None] + (z - zb)[..., None] * sig
            XY = np.broadcast_to(B[..., None, :], B.shape[:2] + (cells + 1, 2))
            X = np.concatenate([XY, Z[..., None]], axis=-1)
            if n == 0 and upper is not None:
                # the rectangle in 3 x 3 parts; the one under the feature has no top
                for ia, ib in ((0, i0), (i0, i1), (i1, X.shape[0] - 1)):
                    for ja, jb in ((0, j0), (j0, j1), (j1, X.shape[1] - 1)):
                        if ib > ia and jb > ja:
                            below = (ia, ja) == (i0, j0)
                            body.add(
                                X[ia : ib + 1, ja : jb + 1],
                                {"kmin": "tibia_inferior", "kmax": None if below else "top"},
                            )
            else:
                body.add(X, {"kmin": "tibia_inferior", "kmax": "top"})
        quality = None
        if upper is not None:
            sides = {
                "kmax": "top",
                "imin": "inner wall",
                "imax": "inner wall",
                "jmin": "inner wall",
                "jmax": "inner wall",
            }
            body.add(upper, sides)
            post = Body("post")
            post.add(upper, sides)
            pn, ph, _ = post.assemble()
            quality = float(corner_jacobians(pn, ph).min())
        nodes, hexes, surfaces = body.assemble()
        # only the seat bears on the tray: the feet on a recess's floor, its
        # ramps and the feet beyond the seat's outline (under an overhanging
        # top) stay traction free (tkr-wear's rigid tray needs a flat
        # tibia_inferior)
        q = surfaces["tibia_inferior"]
        cen = nodes[q].mean(axis=1)
        on_seat = Top({0: (S, None)}, [0], False)
        over = np.array([on_seat.locate(p, inside=True)[2] for p in cen[:, :2]], bool)
        surfaces["tibia_inferior"] = q[(nodes[q][..., 2] == z0).all(axis=1) & over]
        # the top quadrangles take the group of the face under their centre
        # (over a hole left out: of the nearest top triangle around it)
        q = surfaces.pop("top")
        cen = nodes[q].mean(axis=1)
        hole = fill.which(cen[:, :2]) if fill is not None else np.full(len(q), -1)
        f = np.empty(len(q), np.int64)
        if np.any(hole < 0):
            f[hole < 0] = top_lookup.faces(cen[hole < 0, :2])
        if np.any(hole >= 0):
            from scipy.spatial import cKDTree

            face_of = np.concatenate([np.full(len(up_faces[s][0]), s) for s in up_faces])
            around = fill.which(up_P.mean(axis=1)[:, :2]) < 0
            _, k = cKDTree(up_P[around].mean(axis=1)).query(cen[hole >= 0])
            f[hole >= 0] = face_of[around][k]
        for g in set(groups.get(s) for s in up_faces):
            if g:
                m = np.array([groups.get(s) == g for s in f], bool)
                surfaces[g] = np.concatenate([surfaces.get(g, np.zeros((0, 4), np.int64)), q[m]])
        # the feature's sides take the group of the nearest inner vertical face
        q = surfaces.pop("inner wall", None)
        if q is not None and any(groups.get(s) for s in inner):
            cen = nodes[q].mean(axis=1)
            d = np.array(
                [[np.min(np.linalg.norm(faces[s][0].mean(axis=1) - p, axis=1)) for s in inner] for p in cen]
            )
            f = np.array(inner)[np.argmin(d, axis=1)]
            for g in set(groups.get(s) for s in inner):
                if g:
                    m = np.array([groups.get(s) == g for s in f])
                    surfaces[g] = np.concatenate([surfaces.get(g, np.zeros((0, 4), np.int64)), q[m]])
        return nodes, hexes, surfaces, quality

    # a raised feature is kept if the sweep meshes it fit for contact
    out, why = None, None
    if len(raised) == 1:
        poly, z_rim = raised[0]
        inner = post_walls(faces, corner_nz, poly, z_rim, tol, cad)
        try:
            if not inner:
                raise NotSweepable("no vertical faces bound it")
            feature = raised_feature(faces, inner, tol)
            x0, x1, y0, y1 = feature
            rim = loop_segments(np.array([[x0, y0], [x1, y0], [x1, y1], [x0, y1]]))
            if plan_distance(poly, rim).max() > max(tol, 0.1 * h):
                raise NotSweepable("its vertical faces do not bound it all round")
            out = build(feature, inner, None)
            if out[3] < POST_QUALITY:
                why = "its block of columns has cells of scaled Jacobian %.3f, below %g" % (
                    out[3],
                    POST_QUALITY,
                )
                out = None
            else:
                say(
                    "insert: the post (x %.1f..%.1f, y %.1f..%.1f mm) swept as a raised feature, smallest "
                    "scaled Jacobian of its cells %.3f" % (x0, x1, y0, y1, out[3])
                )
        except NotSweepable as e:
            why = str(e)
    elif raised:
        why = "the sweep meshes one raised feature, the top has %d" % len(raised)
    if out is None and raised:
        # left out where the femur never comes near it in the flexion range
        notes = []
        for poly, z_rim in raised:
            cen = P_all.mean(axis=1)
            mine = in_polygon(cen[:, :2], poly) & (cen[:, 2] > z_rim.min() - tol)
            walls = mine & (np.abs(nz_all) <= T_TOP)
            x0, y0 = poly.min(axis=0)
            x1, y1 = poly.max(axis=0)
            what = "the post (x %.1f..%.1f, y %.1f..%.1f mm, up to z = %.1f mm)" % (
                x0,
                x1,
                y0,
                y1,
                P_all[mine][..., 2].max(),
            )
            if why is None or "no vertical faces" in why:
                why = "its walls are not vertical: %s" % describe_walls(
                    nz_all[walls], triangle_areas(P_all[walls])
                )
            if clearance is None:
                raise Refused(
                    "%s cannot be swept with cells fit for contact (%s), and there is no femur to show that "
                    "it is never in contact: mesh the insert with --method layer" % (what, why)
                )
            import surface_tags

            pts_post = surface_tags.samples(P_all[mine])
            d, angle = clearance(pts_post, P_all)
            k = int(np.argmin(d))
            flex = "%g..%g deg of flexion" % (surface_tags.FLEXION[0], surface_tags.FLEXION[-1])
            if d[k] <= contact_distance:
                raise Refused(
                    "%s cannot be swept with cells fit for contact (%s), and the femur comes within %.2f mm "
                    "of it at %g deg of flexion (%s; --contact-distance %g mm): mesh the insert with "
                    "--method layer, or give the post vertical walls"
                    % (what, why, d[k], angle[k], flex, contact_distance)
                )
            notes.append(
                "insert: %s left out (%s): the femur comes no closer than %.2f mm to it over %s (at %g deg; "
                "tibia_contact is what comes within --contact-distance %g mm), so it carries no load there; "
                "the columns under it end on the height field around it, interpolated"
                % (what, why, d[k], flex, angle[k], contact_distance)
            )
        out = build(None, [], Fill([poly for poly, _ in raised], pts[np.unique(T[main])], h))
        for line in notes:
            say(line)
    elif out is None:
        out = build(None, [], None)
    nodes, hexes, surfaces, _ = out

    # what the sweep made of the input
    V = float(hex_volumes(nodes, hexes).sum())
    try:
        V0 = float(gmsh.model.occ.getMass(3, vol)) if cad else None
    except Exception:
        V0 = None
    if V0 is None:
        Q = src if fine is not None else P_all
        V0 = float(np.einsum("ij,ij->i", Q[:, 0], np.cross(Q[:, 1], Q[:, 2])).sum() / 6.0)
    if vertical:
        walls = "vertical walls: the columns stand on the seat's outline"
    else:
        cen = src.mean(axis=1)
        wall = np.abs(src_nz) <= T_TOP
        for poly, _ in raised:
            wall &= ~in_polygon(cen[:, :2], poly)
        if len(floor):
            wall &= ~((np.abs(src_nz) < 0.15) & (src[..., 2].max(axis=1) <= floor[..., 2].max() + flat_tol))
        walls = "walls with %s approximated as vertical on the top's outline (n_z > %g)" % (
            describe_walls(src_nz[wall], triangle_areas(src[wall])),
            T_TOP,
        )
    Q = nodes[surfaces["tibia_inferior"]]
    seat_area = 0.5 * np.linalg.norm(np.cross(Q[:, 2] - Q[:, 0], Q[:, 3] - Q[:, 1]), axis=1).sum()
    say(
        "insert: swept from its articular surface; meshed volume %.1f mm^3, input %.1f mm^3 (%+.1f %%): %s; "
        "tibia_inferior %.1f mm^2 on the input's seat of %.1f mm^2"
        % (V, V0, 100.0 * (V / V0 - 1.0), walls, seat_area, triangle_areas(S).sum())
    )
    return nodes, hexes, surfaces


def boundary_edges_2d(P):
    """Outline segments of a flat triangulated face (its boundary edges)."""
    count = {}
    for t in P[:, :, :2]:
        for i in range(3):
            a, b = tuple(np.round(t[i], 9)), tuple(np.round(t[(i + 1) % 3], 9))
            k = (a, b) if a < b else (b, a)
            count[k] = count.get(k, 0) + 1
    return np.array([[a, b] for k, n in count.items() if n == 1 for a, b in [k]])
