# SPDX-License-Identifier: LGPL-2.1-or-later
"""The insert of scripts/mesh-implant as swept hexahedra: structured columns
under a regular quadrilateral grid (`--method auto`, when the insert allows
it; doc/geometry.md).

The mortar coupling reads the contact pressure at the insert's (slave)
nodes. On kite-shaped quadrilaterals (triangles split into three, the
contact_layer method) or on tetrahedra split into hexahedra, the nodal
pressures of a conforming contact scatter by some 30 %: the nodes of
different kinds (a triangle's corners, edge midpoints and centroid) see
different stencils.  On a structured grid they do not.  Most inserts are
"2.5-dimensional": a flat base (tibia_inferior), vertical side walls and an
articular top that is a height field over the base.  Such an insert is
meshed here like the parametric ones (tkr.py):

1. the base is an O-grid in plan: a rectangle of square cells of the plan
   size h around the centroid of the base, and four ring blocks out to the
   base's outline along rays from the centroid (the outline must be
   star-shaped with respect to it);
2. every plan node carries a column from the base up to the top, whose
   height is found by vertical projection onto the CAD faces of the top
   (Newton iterations with the faces' closest points and normals; on an STL
   the triangulated surface is the geometry);
3. the columns have `cells` cells, graded so that the cell at the top is
   `top_cell` thick where the insert is thinnest.

Every top node lies on the articular surface; the edges where two top faces
meet (the rims of the dishes) are not aligned with the grid, so the faceted
top cuts them slightly, as on the parametric meshes.
"""
import math

import numpy as np

from blockmesh import Body, graded

import gmsh


class NotSweepable(Exception):
    """The insert is not a flat base with vertical walls and a height-field
    top; the message says which face breaks it."""


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


def sort_faces(faces, groups, normals, flat_tol=1e-6, flat_normal=0.9999, rim=()):
    """Base, walls and top of an insert: the base is the tibia_inferior
    faces (flat, at one height, facing down), walls are vertical faces, the
    top all others, which must face up everywhere (a height field).
    normals: node_normals(); flat_tol (mm) and flat_normal (smallest -n_z):
    how flat the base must be (a scanned base is flattened to its mean
    height within flat_tol); rim: faces of a rounded rim (split_rim()),
    counted with the base in plan.  Returns (base faces, base height,
    walls, top).  Raises NotSweepable."""
    base = [s for s in faces if groups.get(s) == "tibia_inferior"]
    if not base:
        raise NotSweepable("the insert has no tibia_inferior face")
    z = np.concatenate([faces[s][0][..., 2].ravel() for s in base])
    z0 = float(z.mean())
    if np.ptp(z) > flat_tol or any(np.min(-normals[s][:, 2]) < flat_normal for s in base):
        raise NotSweepable(
            "the base (faces %s) is not flat and horizontal (heights %.3g .. %.3g mm, "
            "within %g)" % (base, z.min(), z.max(), flat_tol)
        )

    def area(P, n):
        return triangle_areas(P)

    walls, top = [], []
    for s in faces:
        n = normals[s]
        if s in base or s in rim:
            continue
        if np.max(np.abs(n[:, 2])) < (
            1e-6 if n is not faces[s][1] else 0.15
        ):  # STL: chords of curved walls tilt
            walls.append(s)
        elif np.min(n[:, 2]) > 0.02:
            top.append(s)
        elif n is faces[s][1] and area(*faces[s]).sum() < 1.0:
            walls.append(s)  # STL: a sliver that remeshing left in a corner (a post's foot)
        else:
            raise NotSweepable(
                "face %d is neither vertical nor facing up everywhere "
                "(normals n_z from %.2f to %.2f)" % (s, n[:, 2].min(), n[:, 2].max())
            )
    base_area = sum(area(*faces[s]).sum() for s in base) + sum(
        (area(*faces[s]) * -faces[s][1][:, 2]).sum() for s in rim
    )
    plan_area = sum((area(*faces[s]) * faces[s][1][:, 2]).sum() for s in top)
    if abs(plan_area / base_area - 1) > 2e-3:
        raise NotSweepable(
            "the top faces cover %.1f mm^2 in plan, the base %.1f mm^2 (overhangs?)" % (plan_area, base_area)
        )
    return base, z0, walls, top


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


def base_reach(faces, groups):
    """The tibia_inferior face ids, the base's lowest height z_min and the
    height three quarters of the way from it to the top's lowest point
    (triangles facing up); ([], None, None) without a base or a top."""
    base = [s for s in faces if groups.get(s) == "tibia_inferior"]
    up = [P[n[:, 2] > 0.3][..., 2].min() for P, n in faces.values() if np.any(n[:, 2] > 0.3)]
    if not base or not up:
        return [], None, None
    z_min = min(float(faces[s][0][..., 2].min()) for s in base)
    return base, z_min, z_min + 0.75 * (float(min(up)) - z_min)


def split_rim(faces, groups, flat_tol, flat_normal):
    """STL: the triangles near the base that are neither flat base, nor
    vertical wall, nor facing up: a rim between base and walls rounded by
    a scan or by the repair of a fold there.  They go into faces of their
    own (new ids, face + 2000000, no group) which the sweep fills back to
    the sharp rim: the columns stand on the flat base out to the outline of
    base and rim together.  Only triangles lower than three quarters of the
    lowest height of the top above the base count.  Returns (faces, groups, rim
    face ids)."""
    base, z_min, reach = base_reach(faces, groups)
    if not base:
        return faces, groups, []
    out, grp, rim = {}, dict(groups), []
    for s, (P, n) in faces.items():
        flat = (np.abs(P[..., 2] - z_min).max(axis=1) <= flat_tol) & (-n[:, 2] >= flat_normal)
        # (a flat floor facing down above the base, a locking recess's, is no rim)
        m = (
            (P[..., 2].max(axis=1) < reach)
            & (n[:, 2] < 0.3)
            & (np.abs(n[:, 2]) >= 0.15)
            & ~flat
            & (-n[:, 2] < flat_normal)
        )
        out[s] = (P, n)
        if not np.any(m):
            continue
        if np.all(m):
            rim.append(s)  # the whole face is rim (a tibia_inferior one too: a base's rounded edge)
            grp[s] = None
            continue
        out[s] = (P[~m], n[~m])
        out[s + 2000000] = (P[m], n[m])
        grp[s + 2000000] = None
        rim.append(s + 2000000)
    return out, grp, rim


def split_recess(faces, groups, flat_tol):
    """STL: a base with a recess (a locking mechanism's pocket): the
    tibia_inferior triangles higher than flat_tol above the base's lowest
    point (the recess's floor) go into faces of their own (new ids, face +
    3000000, no group), and, if there is such a floor, faces all of whose
    triangles lie lower than three quarters of the top's lowest height and
    are vertical (the recess's walls) are left out: the columns inside the recess stand on
    its floor and ramp over one cell at its walls.  Base triangles that
    rise from the base (a rounded edge's) go into faces of their own (face
    + 4000000) that the sweep fills back like split_rim()'s.  Returns
    (faces, groups, floor face ids, rim face ids)."""
    base, z_min, reach = base_reach(faces, groups)
    if not base:
        return faces, groups, [], []
    out, grp, floor, rim = {}, dict(groups), [], []
    floor_seen = any(np.any(faces[s][0][..., 2].min(axis=1) > z_min + flat_tol) for s in base)
    for s, (P, n) in faces.items():
        if s in base:
            # the floor: wholly above the base; a rim: from the base up (a
            # rounded edge's coarse triangles, filled back like split_rim's)
            up_ = (P[..., 2].min(axis=1) > z_min + flat_tol) & (P[..., 2].max(axis=1) < reach)
            rising = ~up_ & (P[..., 2].max(axis=1) > z_min + flat_tol)
            for m, new, ids in ((up_, s + 3000000, floor), (rising, s + 4000000, rim)):
                if np.any(m):
                    out[new] = (P[m], n[m])
                    grp[new] = None
                    ids.append(new)
            keep = ~up_ & ~rising
            if np.any(keep):
                out[s] = (P[keep], n[keep])
            continue
        elif floor_seen and P[..., 2].max() < reach and np.all(np.abs(n[:, 2]) < 0.15):
            continue  # a recess's wall (below the top; no plan area)
        out[s] = (P, n)
    return out, grp, floor, rim


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
        p is inside it (within 1e-6 of its edges)."""
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
            if m > best_out:
                best, best_out = (t, l1 * a[2] + l2 * bb[2] + l3 * c[2]), m
                if m >= -1e-12:
                    break
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


# ------------------------------------------------------------------ body
def mesh_insert(vol, groups, h, cells, top_cell, cad, fine=None, smooth=None):
    """The swept insert (steps 1-3) for volume `vol` of the current gmsh
    model, whose boundary is triangulated (any size; it locates the top
    faces).  groups: face -> group.  Returns (nodes, hexes, surfaces).

    A raised feature (a tibial post) whose sides are vertical faces inside
    the base's outline, forming an axis-aligned rectangle in plan, is
    meshed as a block of vertical columns standing on the columns below it:
    the plan grid has lines along the feature's sides; under the feature
    the columns end at the articular surface interpolated (transfinite)
    from the feature's edges; above them the feature's columns go up to its
    top with cells about h high.  fine: finer triangles of the same
    surface (T x 3 x 3) whose upward ones give the heights of the top (an
    STL repaired by tkr-surface), then put onto smooth(points) (a smooth
    surface through the input's vertices).  Raises NotSweepable."""
    faces = boundary_triangles(vol)
    flat = (1e-6, 0.9999) if cad else (0.1, 0.98)  # STL: a scanned base within 0.1 mm
    rim = []
    if not cad:
        faces, groups = split_stl_faces(faces, groups)
        faces, groups, rim = split_rim(faces, groups, *flat)
        faces, groups, floor, low_rim = split_recess(faces, groups, flat[0])
        rim = rim + low_rim
        if floor:
            P = np.concatenate([faces[s][0] for s in floor])
            print(
                "note: %d triangles (%.1f mm2) of the base lie above it (a recess, up to z = %.1f mm): the "
                "columns there stand on them" % (len(P), triangle_areas(P).sum(), P[..., 2].max())
            )
            rim = rim + floor
        if rim:
            P = np.concatenate([faces[s][0] for s in rim])
            print(
                "note: %d triangles (%.1f mm2) of a rounded rim between the insert's base and walls "
                "(up to z = %.1f mm) are filled back to a sharp rim by the sweep"
                % (len(P), triangle_areas(P).sum(), P[..., 2].max())
            )
    base, z0, walls, top = sort_faces(faces, groups, node_normals(faces, cad), *flat, rim=rim)
    P = np.concatenate([faces[s][0] for s in base])
    w = triangle_areas(P)
    c = (w[:, None] * P.mean(axis=1)[:, :2]).sum(axis=0) / w.sum()
    every = (
        outline_segments(base) if cad else boundary_edges_2d(np.concatenate([P] + [faces[s][0] for s in rim]))
    )
    segs = every if cad or not floor else outer_loop(every)  # a recess's outlines are no outline
    tol = 1e-3 if cad else 0.5  # STL: chordal error of the walls
    # (a recess's walls stand on its outlines: no raised feature; on an STL
    # most of a wall's corners must be inside: a rounded top rim's nearly
    # vertical triangles lean 0.6 mm in)
    inner = [
        s
        for s in walls
        if (np.max if cad else np.median)(plan_distance(faces[s][0][..., :2].reshape(-1, 2), every)) > tol
    ]
    feature = raised_feature(faces, inner, tol) if inner else None
    if fine is not None:
        n = np.cross(fine[:, 1] - fine[:, 0], fine[:, 2] - fine[:, 0])
        fine = fine[n[:, 2] > 0.05 * np.linalg.norm(n, axis=1)]
    top_lookup = Top(faces, top, cad, fine=fine, smooth=smooth)
    blocks = plan_blocks(c, segs, h, feature)
    columns = []
    for B in blocks:
        z, f = top_lookup.heights(B.reshape(-1, 2))
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
    if not cad and floor:
        under = Top(faces, floor, False)
        for B, zb in zip(blocks, bottoms):
            for idx in np.ndindex(zb.shape):
                t, h, inside = under.locate(B[idx], inside=True)
                if inside:
                    zb[idx] = h
    t_min = min(float((z - zb).min()) for z, zb in zip(columns, bottoms))
    if t_min <= 0:
        raise NotSweepable("the top touches the base")
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
                        under = (ia, ja) == (i0, j0)
                        body.add(
                            X[ia : ib + 1, ja : jb + 1],
                            {"kmin": "tibia_inferior", "kmax": None if under else "top"},
                        )
        else:
            body.add(X, {"kmin": "tibia_inferior", "kmax": "top"})
    if upper is not None:
        body.add(
            upper,
            {
                "kmax": "top",
                "imin": "inner wall",
                "imax": "inner wall",
                "jmin": "inner wall",
                "jmax": "inner wall",
            },
        )
    nodes, hexes, surfaces = body.assemble()
    if not cad and floor:
        # only the seat bears on the tray: the feet on a recess's floor and
        # its ramps stay traction free (tkr-wear's rigid tray needs a flat
        # tibia_inferior)
        q = surfaces["tibia_inferior"]
        surfaces["tibia_inferior"] = q[(nodes[q][..., 2] == z0).all(axis=1)]
    # the top quadrangles take the group of the face under their centre
    q = surfaces.pop("top")
    cen = nodes[q].mean(axis=1)
    f = top_lookup.faces(cen[:, :2])
    for g in set(groups.get(s) for s in top):
        if g:
            m = np.array([groups.get(s) == g for s in f])
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
