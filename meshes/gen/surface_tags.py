#!/usr/bin/env python3
"""Physical groups per triangle from the geometry of the pair (issue 19):
for a femoral component and a tibial insert given as closed, outward
triangulated surfaces in our frame (x medial-lateral, y anterior, z
proximal; tkr-surface's output), without any CAD faces.

  femur_contact   the femur's triangles that face the insert (n_z < -0.3 in
                  the turned pose) and come within
                  DISTANCE mm of it somewhere over the flexion range: the
                  femur turned about its flexion axis (estimated from the
                  distal arcs of the condyles, flexion_axis.py) by -5 to 60
                  degrees in 5-degree steps (ISO 14243-1 reaches 58) and
                  lowered along z until it touches the insert;
  tibia_contact   the insert's triangles facing up (n_z > 0.3) that come
                  within DISTANCE mm of the femur in one of those poses;
  tibia_inferior  the insert's triangles facing down (n_z < -0.3) lower than
                  three quarters of the height of the articular zone (the
                  tibia_contact triangles) above its lowest point;
  femur_fixation  the femur's other triangles that face the bone: outward
                  normal towards the centre of the femur's bounding box,
                  except the medial/lateral sides (|n_x| > 0.8) and the
                  proximal ends (n_z > 0.5 in the top 15 % of the height),
                  which stay untagged (traction free), as the peg sides
                  facing away from the centre do.

A contact patch given as its own STL file (published implant data often
comes so) replaces the rule for that body: the triangles within TOL mm of
the patch are the contact group.
"""
import numpy as np
from scipy.spatial import cKDTree

import flexion_axis

UNTAGGED, CONTACT, OTHER = 0, 1, 2
NAMES = {
    "femur": {CONTACT: "femur_contact", OTHER: "femur_fixation"},
    "tibia": {CONTACT: "tibia_contact", OTHER: "tibia_inferior"},
}
FLEXION = np.arange(-5.0, 60.1, 5.0)


def normals(tris):
    """Centroids and outward unit normals of triangles (T x 3 x 3)."""
    n = np.cross(tris[:, 1] - tris[:, 0], tris[:, 2] - tris[:, 0])
    return tris.mean(axis=1), n / np.maximum(np.linalg.norm(n, axis=1), 1e-300)[:, None]


def samples(tris):
    """Points on the triangles: corners, edge midpoints and centroids."""
    return np.concatenate(
        [tris.reshape(-1, 3), 0.5 * (tris + np.roll(tris, 1, axis=1)).reshape(-1, 3), tris.mean(axis=1)]
    )


def turned(P, angle, point):
    """Points P turned by `angle` degrees about the x axis through `point`."""
    a = np.radians(angle)
    c, s = np.cos(a), np.sin(a)
    Q = P - point
    return np.column_stack([Q[:, 0], c * Q[:, 1] - s * Q[:, 2], s * Q[:, 1] + c * Q[:, 2]]) + point


def flexion_point(fem_tris):
    """The flexion axis point (x = 0) from the femur's downward triangles."""
    c, n = normals(fem_tris)
    pts = fem_tris[n[:, 2] < -0.3].reshape(-1, 3)
    if len(pts) < 10:
        raise ValueError("the femur has no triangles facing down (towards the insert)")
    return np.array(flexion_axis.estimate(pts)["point"])


def lowered_poses(fc, fn, ic, up, point):
    """The femur's poses of proximity() and approach(): for each flexion of
    FLEXION, the femur triangles' centres fc (normals fn) turned about the
    axis through `point`, which of them face down, and the lift (mm) that
    lowers the femur onto the insert's upward triangles (centres ic[up])
    where they face each other in plan (within 1.5 mm); a pose without such
    a pair is left out.  Yields (angle, turned centres, down, lift)."""
    ins_plan = cKDTree(ic[up][:, :2])
    for angle in FLEXION:
        c = turned(fc, angle, point)
        down = turned(fn, angle, np.zeros(3))[:, 2] < -0.3
        d, i = ins_plan.query(c[down][:, :2])
        close = d < 1.5
        if close.any():
            yield angle, c, down, (c[down][close, 2] - ic[up][i[close], 2]).min()


def proximity(fem_tris, ins_tris, distance, point):
    """Boolean masks: femur triangles facing and within `distance` of the
    insert, insert triangles within `distance` of the femur, over the
    flexion poses (see the module's head)."""
    fc, fn = normals(fem_tris)
    ic, inn = normals(ins_tris)
    fs = np.concatenate([fem_tris.reshape(-1, 3), fc])
    up = inn[:, 2] > 0.3
    ins_tree = cKDTree(np.concatenate([ins_tris.reshape(-1, 3), ic]))
    fem_near, ins_near = np.zeros(len(fc), bool), np.zeros(len(ic), bool)
    for angle, c, down, lift in lowered_poses(fc, fn, ic, up, point):
        c[:, 2] -= lift
        d, _ = ins_tree.query(c, distance_upper_bound=distance)
        fem_near |= (d < distance) & down
        s = turned(fs, angle, point)
        s[:, 2] -= lift
        d, _ = cKDTree(s).query(ic[up], distance_upper_bound=distance)
        ins_near[np.flatnonzero(up)[d < distance]] = True
    return fem_near, ins_near


def approach(fem_tris, ins_tris, points, point=None, exact=10.0):
    """How near the femur comes to given points on the insert over the
    poses of proximity() (turned about its flexion axis through `point`,
    estimated if None, by FLEXION, and lowered onto the insert's upward
    triangles): the smallest distance of each point from the femur's
    triangles in any pose (from their samples() where those are farther
    than `exact` mm), and the flexion (deg) of that pose.  A part of the
    insert all of whose points stay farther than the contact distance is
    no tibia_contact in any pose, whatever it faces: insert_sweep.py leaves
    a post that it cannot mesh out only then."""
    from scipy.spatial import cKDTree

    import contact_layer

    if point is None:
        point = flexion_point(fem_tris)
    fc, fn = normals(fem_tris)
    ic, inn = normals(ins_tris)
    up = inn[:, 2] > 0.3
    fs = samples(fem_tris)
    points = np.asarray(points, float).reshape(-1, 3)
    best, at = np.full(len(points), np.inf), np.full(len(points), np.nan)
    for angle, _, _, lift in lowered_poses(fc, fn, ic, up, point):
        s = turned(fs, angle, point)
        s[:, 2] -= lift
        d, _ = cKDTree(s).query(points)
        near = d < exact
        if near.any():
            # the distance to the femur's triangles, not to their samples
            F = turned(fem_tris.reshape(-1, 3), angle, point).reshape(-1, 3, 3)
            F[..., 2] -= lift
            _, k = cKDTree(F.mean(axis=1)).query(points[near], k=min(16, len(F)))
            q = np.array(
                [contact_layer.closest_on_triangles(p[None], F[i])[0] for p, i in zip(points[near], k)]
            )
            d[near] = np.minimum(d[near], np.linalg.norm(q - points[near], axis=1))
        nearer = d < best
        best[nearer], at[nearer] = d[nearer], angle
    return best, at


def near_patch(tris, patch, tol):
    """Triangles whose centroid is within tol of the patch surface (sampled)."""
    d, _ = cKDTree(samples(patch)).query(tris.mean(axis=1))
    return d < tol


def tag_femur(tris, contact):
    c, n = normals(tris)
    lo, hi = tris.reshape(-1, 3).min(axis=0), tris.reshape(-1, 3).max(axis=0)
    centre = 0.5 * (lo + hi)
    labels = np.full(len(tris), UNTAGGED)
    inward = np.einsum("ij,ij->i", n, centre - c) > 0
    side = np.abs(n[:, 0]) > 0.8
    end = (n[:, 2] > 0.5) & (c[:, 2] > lo[2] + 0.85 * (hi[2] - lo[2]))
    labels[inward & ~side & ~end] = OTHER
    labels[contact] = CONTACT
    return labels


def tag_insert(tris, contact):
    """tibia_inferior: the triangles facing down (n_z < -0.3) below three
    quarters of the height of the articular zone's lowest point (the
    contact triangles) above the insert's lowest point: a flat base, its
    rounded rim's lower half, a locking recess's floor and mouth, whatever
    the smooth patches are (a scan's rounded rim joins them all)."""
    c, n = normals(tris)
    lo = tris.reshape(-1, 3).min(axis=0)
    labels = np.full(len(tris), UNTAGGED)
    if contact.any():
        reach = lo[2] + 0.75 * (tris[contact][..., 2].min() - lo[2])
    else:
        reach = lo[2] + 0.05 * (tris[..., 2].max() - lo[2])
    labels[(n[:, 2] < -0.3) & (c[:, 2] < reach)] = OTHER
    labels[contact] = CONTACT
    return labels


def shared_edges(tris):
    """Points (identical ones merged) and triangles (indices) of a closed
    triangulated surface, its edges (node pairs) and the two triangles of
    each edge."""
    pts, inv = np.unique(np.round(tris.reshape(-1, 3), 9), axis=0, return_inverse=True)
    T = inv.reshape(-1, 3)
    E = np.sort(np.concatenate([T[:, [0, 1]], T[:, [1, 2]], T[:, [2, 0]]]), axis=1)
    owner = np.tile(np.arange(len(T)), 3)
    order = np.lexsort((E[:, 1], E[:, 0]))
    E, owner = E[order], owner[order]
    same = np.flatnonzero((E[1:] == E[:-1]).all(axis=1))
    return pts, T, E[same], owner[same], owner[same + 1]


def patches(tris, angle, min_area):
    """Smooth patches: connected components of the triangles across edges
    whose dihedral angle is below `angle` (deg); a patch smaller than
    min_area (mm2; the strips that remeshing leaves along sharp rims) joins
    the neighbour whose mean normal is closest to its own, if they differ
    by less than 60 degrees (a strip on a rim between two faces at 90
    degrees); a small face at a sharp edge all round (the end of TKR C's cam
    where it stands out of the femur's bone side) stays a patch of its own:
    joined to a contact patch, it would fold that patch's layer.  Returns
    the patch index of each triangle (0, 1, ...)."""
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components

    _, T, _, a, b = shared_edges(tris)
    _, n = normals(tris)
    smooth = np.einsum("ij,ij->i", n[a], n[b]) > np.cos(np.radians(angle))
    graph = coo_matrix((np.ones(smooth.sum()), (a[smooth], b[smooth])), shape=(len(T), len(T)))
    patch = connected_components(graph, directed=False)[1]
    area = 0.5 * np.linalg.norm(np.cross(tris[:, 1] - tris[:, 0], tris[:, 2] - tris[:, 0]), axis=1)
    alone = set()
    while True:
        sizes = np.bincount(patch, weights=area)
        small = [k for k in np.argsort(sizes) if 0 < sizes[k] < min_area and k not in alone]
        if not small:
            break
        k = small[0]
        pa, pb = patch[a], patch[b]
        border = np.unique(np.concatenate([pb[pa == k], pa[pb == k]]))
        border = border[border != k]
        mean = [(area[patch == j, None] * n[patch == j]).sum(axis=0) for j in np.append(border, k)]
        mean = [v / max(np.linalg.norm(v), 1e-300) for v in mean]
        cos = np.array([np.dot(v, mean[-1]) for v in mean[:-1]])
        if not len(border) or cos.max() < 0.5:
            alone.add(k)
            continue
        patch[patch == k] = border[cos.argmax()]
    return np.unique(patch, return_inverse=True)[1]


def unfaithful(T, ref, tolerance, layer=None, reach=0.0):
    """None if the triangles T follow the reference surface ref (both T x 3
    x 3): every vertex of ref (within `reach` of the triangles `layer`, if
    given) within `tolerance` of T, and no triangle of T facing away
    (normal more than 90 degrees) from all of the 8 reference triangles
    nearest its centre (a fold); else what is wrong, and where, in words."""
    from scipy.spatial import cKDTree
    import contact_layer

    P = np.unique(np.round(ref.reshape(-1, 3), 9), axis=0)
    if layer is not None and len(layer):
        # only where the contact layer is (the triangles `layer`, within
        # `reach`): a rounded proximal edge cut by coarse triangles harms no layer
        d, _ = cKDTree(layer.reshape(-1, 3)).query(P)
        P = P[d < reach]
    d = np.zeros(0)
    if len(P):
        Q = contact_layer.surface_projector({0: T})(2, 0, P)
        d = np.linalg.norm(P - Q, axis=1)
    if len(d) and d.max() > tolerance:
        return "strays %.2f mm from the repaired surface at (%.1f, %.1f, %.1f) (more than %g mm)" % (
            (d.max(),) + tuple(P[np.argmax(d)]) + (tolerance,)
        )
    c, n = normals(T)
    rc, rn = normals(ref)
    _, i = cKDTree(rc).query(c, k=8)
    turned = np.einsum("ij,ikj->ik", n, rn[i]).max(axis=1) < 0
    if turned.any():
        return "has %d triangles turned against the repaired surface, e.g. at (%.1f, %.1f, %.1f)" % (
            (turned.sum(),) + tuple(c[np.argmax(turned)])
        )
    return None


def by_patch(labels, patch, area, contact_fraction=0.25, mixed=0.8):
    """Labels made uniform on each patch: CONTACT where at least
    contact_fraction of the patch's area is CONTACT, else the label with the
    largest area, unless that has less than `mixed` of the area: then the
    patch joins faces that its rules tell apart (an insert's base and side
    walls joined by a rim rounded in the repair of a fold) and each triangle
    keeps its own label (CONTACT ones the largest other label); split_mixed()
    then makes patches of them."""
    out = np.empty_like(labels)
    for k in np.unique(patch):
        m = patch == k
        a = np.array([area[m & (labels == c)].sum() for c in (UNTAGGED, CONTACT, OTHER)])
        if a[CONTACT] >= contact_fraction * a.sum():
            out[m] = CONTACT
            continue
        best = (UNTAGGED, OTHER)[int(a[OTHER] > a[UNTAGGED])]
        if a[best] >= mixed * a.sum():
            out[m] = best
        else:
            out[m] = np.where(labels[m] == CONTACT, best, labels[m])
    return out


def group_patches(
    tris, labels, patch, area, angle, min_area, levels=2, significant=0.05, contact_fraction=0.25
):
    """Labels made uniform per patch (by_patch()), except on a patch that
    joins the articular surface to the other group's (both with at least
    `significant` of its area and min_area mm2: a scan's rounded rims join
    an insert's top, sides and base, or a femur's condyles and bone side,
    in one smooth surface) or whose contact part is significant but under
    contact_fraction (condyles joined to the sides: by_patch() would drop
    it): such a patch is split into smooth patches at half the angle
    (`levels` times), so that the groups meet at its sharpest creases (the
    contact layer needs an edge at its border), and at the end keeps its
    triangles' labels (both groups) or follows by_patch() (contact and
    untagged only: a strip of a wall next to a contact patch stays
    untagged)."""
    out = np.empty_like(labels)
    for k in np.unique(patch):
        m = patch == k
        a = np.array([area[m & (labels == c)].sum() for c in (UNTAGGED, CONTACT, OTHER)])
        sig = max(significant * a.sum(), min_area)
        both = a[CONTACT] >= sig and a[OTHER] >= sig
        if not both and not sig <= a[CONTACT] < contact_fraction * a.sum():
            out[m] = by_patch(labels[m], np.zeros(m.sum(), int), area[m], contact_fraction)
        elif levels > 0:
            sub = patches(tris[m], 0.5 * angle, min_area)
            out[m] = group_patches(
                tris[m],
                labels[m],
                sub,
                area[m],
                0.5 * angle,
                min_area,
                levels - 1,
                significant,
                contact_fraction,
            )
        elif both:
            out[m] = labels[m]
        else:
            out[m] = by_patch(labels[m], np.zeros(m.sum(), int), area[m], contact_fraction)
    return out


def split_mixed(tris, patch, labels):
    """Patches made of one label each: the connected components of the
    triangles across edges whose two triangles share patch and label."""
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components

    _, T, _, a, b = shared_edges(tris)
    same = (patch[a] == patch[b]) & (labels[a] == labels[b])
    graph = coo_matrix((np.ones(same.sum()), (a[same], b[same])), shape=(len(T), len(T)))
    return connected_components(graph, directed=False)[1]


def tag_pair(fem_tris, ins_tris, distance, femur_patch=None, insert_patch=None, patch_tol=0.5):
    """Labels (UNTAGGED, CONTACT, OTHER) per triangle of each body and the
    flexion axis point used.  Raises ValueError naming what found nothing."""
    point = flexion_point(fem_tris)
    fem_near, ins_near = proximity(fem_tris, ins_tris, distance, point)
    if femur_patch is not None:
        fem_near = near_patch(fem_tris, femur_patch, patch_tol)
    if insert_patch is not None:
        ins_near = near_patch(ins_tris, insert_patch, patch_tol)
    fem, ins = tag_femur(fem_tris, fem_near), tag_insert(ins_tris, ins_near)
    for role, labels in (("femur", fem), ("tibia", ins)):
        for code, name in NAMES[role].items():
            if not (labels == code).any():
                raise ValueError("no triangle of the %s was found for %s" % (role, name))
    return fem, ins, point


class SmoothSurface:
    """A smooth surface through the vertices of a triangulated one (moving
    least squares): project(X) moves each point along the local normal onto
    the quadratic height function w(u, v) fitted, with Gaussian weights of
    width `radius`, to the vertices within `radius` (at least 12) whose
    normals are within 30 degrees of the nearest vertex's.  A CAD export's
    vertices lie on the exact surface but its facets cut the curvature (a
    1.5 mm tessellation doubles the peak contact pressure under 2000 N):
    the quadric restores it, to about radius^4 / (8 R^3) on a sphere of
    radius R (0.001 mm for 3 mm on R = 20 mm), and averages a scan's
    noise.  A point whose neighbours lie to one side (their mean more than
    radius/2 away in the tangent plane: a rim, where the fit would
    extrapolate) or whose move would exceed max_move (mm) stays."""

    def __init__(self, tris, radius, max_move=0.15):
        self.max_move = max_move
        self.too_far = 0  # points that stayed because their move exceeded max_move
        pts, inv = np.unique(np.round(tris.reshape(-1, 3), 9), axis=0, return_inverse=True)
        n = np.cross(tris[:, 1] - tris[:, 0], tris[:, 2] - tris[:, 0])
        N = np.zeros_like(pts)
        np.add.at(N, inv.reshape(-1, 3), n[:, None, :])
        self.P, self.N = pts, N / np.maximum(np.linalg.norm(N, axis=1), 1e-300)[:, None]
        self.tree, self.radius = cKDTree(pts), radius

    def project(self, X):
        X = np.asarray(X, float).reshape(-1, 3)
        out = X.copy()
        _, nearest = self.tree.query(X)
        for i, x in enumerate(X):
            n0 = self.N[nearest[i]]
            idx = np.array(self.tree.query_ball_point(x, self.radius))
            if len(idx) < 12:
                idx = self.tree.query(x, k=12)[1]
            idx = idx[self.N[idx] @ n0 > np.cos(np.radians(30.0))]
            if len(idx) < 6:
                continue
            e1 = np.cross(n0, [1.0, 0.0, 0.0] if abs(n0[0]) < 0.9 else [0.0, 1.0, 0.0])
            e1 /= np.linalg.norm(e1)
            e2 = np.cross(n0, e1)
            D = self.P[idx] - x
            u, v, w = D @ e1, D @ e2, D @ n0
            if np.hypot(u.mean(), v.mean()) > 0.5 * self.radius:
                continue  # all neighbours to one side (a rim): no extrapolation
            wt = np.sqrt(np.exp(-(u * u + v * v) / self.radius**2))
            A = np.column_stack([np.ones_like(u), u, v, u * u, u * v, v * v]) * wt[:, None]
            coef, *_ = np.linalg.lstsq(A, w * wt, rcond=None)
            if abs(coef[0]) <= self.max_move:
                out[i] = x + coef[0] * n0
            else:
                self.too_far += 1
        return out
