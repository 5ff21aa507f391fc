# SPDX-License-Identifier: LGPL-2.1-or-later
"""One body of scripts/mesh-implant as hexahedra with a layer of
shape-regular hexahedra under its articular faces (`--method layer`, and
the femoral component of `--method auto`; doc/geometry.md).

Tetrahedra split into hexahedra (`--method split`) scatter the nodal contact
pressures: their hexahedra are warped and their faces on the articular
surface are irregular.  Here the articular faces get a layer of prisms,
every prism is split into three hexahedra, and only the rest of the body is
filled with tetrahedra split into four hexahedra each:

1. gmsh triangulates the boundary of the body (Frontal-Delaunay).  The
   size is `contact_size` on the articular faces where they are within
   `refine_distance` of the other body's articular faces, and grows to
   `size` over `grading` mm away from there (SizeField); narrow faces
   (fillet strips) are meshed no coarser than twice their width.
2. The articular ("contact") triangles are extruded inward in `layers`
   prism layers of total depth `thickness` (graded by `ratio`, the thinnest
   at the surface).  A node inside the articular faces moves along the
   inward normal (at a crease between two articular faces along the
   direction that is `thickness` deep below both); a node on the edge of
   the articular faces moves inside the neighbouring non-articular face(s),
   so that the layer's side walls lie on them and the body keeps its shape.
3. The rest of the body (the "core") is bounded by the layer's inner
   surface and the non-articular triangles, whose nodes on the edge of the
   articular faces moved with the layer; the nodes near that edge follow
   (inverse-distance weighted, fading out over four times the move), so
   the triangles there keep their shape.  gmsh fills the core with
   Delaunay tetrahedra without new boundary nodes.
4. Every prism is split into three hexahedra and every tetrahedron into
   four, by the midpoints of the edges and the centroids of the triangles
   (and of the tetrahedra), the same points on both sides of every shared
   triangle, so the mesh is conforming and has no pyramids.  On the
   articular surface each triangle becomes three kite-shaped quadrangles
   (angles of 60-120 degrees on a good triangle).  New nodes on the body's
   boundary are projected onto the CAD faces and edges (STEP input; on an
   STL the triangulated surface is the geometry), except where that would
   make a hexahedron's scaled corner Jacobian fall below 0.02 (then they
   stay on the straight edges and faces).

The kites are fine on the master side (the femoral component): its
surface only has to be faceted finely.  On the slave side (the insert,
where the pressures are read) their three kinds of nodes see different
stencils and the nodal pressures of a conforming contact scatter by some
30 %; inserts that allow it are therefore swept (insert_sweep.py).
"""
import math
import os
import sys

import numpy as np

import blockmesh

import gmsh

CONTACT_GROUPS = ("femur_contact", "tibia_contact")


# ------------------------------------------------------------------ surface
class SizeField:
    """Mesh size for gmsh's size callback: contact_size on the articular
    faces and where they are within refine_distance of the other body's
    articular faces (other: sample points; None: everywhere), growing
    linearly to `size` over `grading` mm away from both.  Distances are
    looked up on a lattice (spacing `cell` mm) of exact point distances."""

    def __init__(self, own, other, contact_size, size, grading, refine_distance, caps=None, cell=1.5):
        self.h0, self.h1, self.grading, self.reach = contact_size, size, grading, refine_distance
        self.caps = caps or {}
        lo = own.min(axis=0) - grading - cell
        hi = own.max(axis=0) + grading + cell
        self.lo, self.cell = lo, cell
        n = np.ceil((hi - lo) / cell).astype(int) + 1
        g = np.stack(np.meshgrid(*[lo[i] + cell * np.arange(n[i]) for i in range(3)], indexing="ij"), -1)
        self.d_own = self._distance(g.reshape(-1, 3), own).reshape(n)
        self.d_other = None if other is None else self._distance(g.reshape(-1, 3), other).reshape(n)
        self.n = n

    @staticmethod
    def _distance(X, P, chunk=4000):
        out = np.empty(len(X))
        for i in range(0, len(X), chunk):
            x = X[i : i + chunk]
            d2 = (x * x).sum(1)[:, None] - 2 * x @ P.T + (P * P).sum(1)[None, :]
            out[i : i + chunk] = np.sqrt(np.maximum(d2.min(axis=1), 0.0))
        return out

    def __call__(self, dim, tag, x, y, z):
        i = np.clip(np.round((np.array([x, y, z]) - self.lo) / self.cell).astype(int), 0, self.n - 1)
        i = tuple(i)

        def grow(d):
            return self.h0 + (self.h1 - self.h0) * min(1.0, max(0.0, d) / self.grading)

        h = grow(self.d_own[i])
        if self.d_other is not None:
            h = max(h, grow(self.d_other[i] - self.reach))
        return min(h, max(self.h0, self.caps.get((dim, tag), h)))


def width_caps():
    """{(dim, tag): size} that keeps the triangles of narrow faces (fillet
    strips) from becoming needles: a face's size is at most twice its width
    2 area / perimeter (but not below the contact size: SizeField), a
    curve's and a point's at most that of their faces (OpenCASCADE models;
    {} otherwise)."""
    caps = {}
    try:
        for _, s in gmsh.model.getEntities(2):
            area = gmsh.model.occ.getMass(2, s)
            perimeter = sum(
                gmsh.model.occ.getMass(1, abs(c)) for _, c in gmsh.model.getBoundary([(2, s)], oriented=False)
            )
            caps[(2, s)] = 4.0 * area / perimeter
    except Exception:  # not an OpenCASCADE model (STL)
        return {}
    for dim in (1, 0):
        for _, e in gmsh.model.getEntities(dim):
            up = gmsh.model.getAdjacencies(dim, e)[0]
            vals = [caps[(dim + 1, u)] for u in up if (dim + 1, u) in caps]
            if vals:
                caps[(dim, e)] = min(vals)
    return caps


def surface_mesh_options(size_field, size):
    """gmsh's options for a triangulation of the boundary (Frontal-Delaunay)
    whose sizes come from size_field (a SizeField, as gmsh's size callback)
    alone, at most `size`, without subdivision; the callback stays set until
    gmsh.model.mesh.removeSizeCallback()."""
    gmsh.model.mesh.setSizeCallback(size_field)
    gmsh.option.setNumber("Mesh.MeshSizeExtendFromBoundary", 0)
    gmsh.option.setNumber("Mesh.MeshSizeFromPoints", 0)
    gmsh.option.setNumber("Mesh.MeshSizeFromCurvature", 0)
    gmsh.option.setNumber("Mesh.MeshSizeMax", size)
    gmsh.option.setNumber("Mesh.MeshSizeMin", 0.0)
    gmsh.option.setNumber("Mesh.Algorithm", 6)
    gmsh.option.setNumber("Mesh.SubdivisionAlgorithm", 0)


def generate_surfaces(size_field, size):
    """Triangulate the visible surfaces of the current gmsh model with
    surface_mesh_options() (the size callback removed after); returns the
    node coordinates indexed by gmsh's node tag (rows of unused tags zero)."""
    surface_mesh_options(size_field, size)
    try:
        gmsh.model.mesh.generate(2)
    finally:
        gmsh.model.mesh.removeSizeCallback()
    tags, coords, _ = gmsh.model.mesh.getNodes()
    X = np.zeros((int(tags.max()) + 1, 3))
    X[tags.astype(np.int64)] = coords.reshape(-1, 3)
    return X


def renumber_used(n, tris, curves):
    """The nodes that the triangles `tris` use (of gmsh's node tags below n),
    numbered from 0: returns used (their tags, increasing), renum (tag ->
    number, -1 if unused) and curve_edges ({frozenset of two numbers:
    curve} for the line elements of the gmsh curves `curves` between used
    nodes)."""
    used = np.unique(tris)
    renum = -np.ones(n, np.int64)
    renum[used] = np.arange(len(used))
    curve_edges = {}
    for c in curves:
        for et, _, nt in zip(*gmsh.model.mesh.getElements(1, c)):
            for a, b in np.array(nt, np.int64).reshape(-1, 2):
                if renum[a] >= 0 and renum[b] >= 0:
                    curve_edges[frozenset((renum[a], renum[b]))] = c
    return used, renum, curve_edges


def triangulate_boundary(vol, groups, size_field, size):
    """Triangulate the boundary of volume `vol` of the current gmsh model
    (Frontal-Delaunay, sizes from size_field, a SizeField).
    Returns X (nodes, N x 3), tris (M x 3, outward), face (M, CAD face of each
    triangle), ent (N x 2: dim and tag of the CAD entity of each node) and
    curve_edges ({frozenset of two nodes: CAD curve} for the mesh edges on
    CAD curves)."""
    X = generate_surfaces(size_field, size)
    n = len(X)
    ent = np.zeros((n, 2), np.int64)
    for dim in (0, 1, 2):
        for _, e in gmsh.model.getEntities(dim):
            nt, _, _ = gmsh.model.mesh.getNodes(dim, e)
            ent[nt.astype(np.int64)] = (dim, e)
    tris, face = [], []
    for _, s in gmsh.model.getBoundary([(3, vol)], oriented=False):
        s = abs(s)
        for et, _, nt in zip(*gmsh.model.mesh.getElements(2, s)):
            if et != 2:
                raise RuntimeError("surface %d has elements of type %d" % (s, et))
            tri = np.array(nt, np.int64).reshape(-1, 3)
            tris.append(tri)
            face.append(np.full(len(tri), s))
    tris, face = np.concatenate(tris), np.concatenate(face)
    used, renum, curve_edges = renumber_used(n, tris, [c for _, c in gmsh.model.getEntities(1)])
    X, ent, tris = X[used], ent[used], renum[tris]
    return X, orient_outward(X, tris), face, ent, curve_edges


def orient_outward(X, tris):
    """Orient the triangles of a closed surface consistently (breadth-first
    over shared edges), outward (positive enclosed volume)."""
    tris = tris.copy()
    edges = {}
    for t, (a, b, c) in enumerate(tris):
        for e in ((a, b), (b, c), (c, a)):
            edges.setdefault(frozenset(e), []).append(t)
    if any(len(v) != 2 for v in edges.values()):
        raise RuntimeError("the boundary triangulation is not a closed manifold surface")
    done = np.zeros(len(tris), bool)
    for start in range(len(tris)):
        if done[start]:
            continue
        done[start] = True
        queue = [start]
        while queue:
            t = queue.pop()
            a, b, c = tris[t]
            for p, q in ((a, b), (b, c), (c, a)):
                for u in edges[frozenset((p, q))]:
                    if u == t or done[u]:
                        continue
                    tu = list(tris[u])
                    i = tu.index(p)
                    if tu[(i + 1) % 3] == q:  # same direction: flip
                        tris[u] = tris[u][::-1]
                    done[u] = True
                    queue.append(u)
    P = X[tris]
    if np.einsum("ij,ij->i", P[:, 0], np.cross(P[:, 1], P[:, 2])).sum() < 0:
        tris = tris[:, ::-1]
    return tris


def triangle_normals(X, tris):
    P = X[tris]
    n = np.cross(P[:, 1] - P[:, 0], P[:, 2] - P[:, 0])
    return n / np.linalg.norm(n, axis=1)[:, None]


def face_normals_at_nodes(X, tris, face):
    """{node: {face: unit outward normal of that face at the node}}, the
    angle-weighted mean of the normals of the face's triangles around it."""
    nrm = triangle_normals(X, tris)
    out = {}
    for t, tri in enumerate(tris):
        for i in range(3):
            a, b, c = tri[i], tri[(i + 1) % 3], tri[(i + 2) % 3]
            u, v = X[b] - X[a], X[c] - X[a]
            ang = math.acos(max(-1.0, min(1.0, np.dot(u, v) / (np.linalg.norm(u) * np.linalg.norm(v)))))
            d = out.setdefault(a, {})
            d[face[t]] = d.get(face[t], 0.0) + ang * nrm[t]
    for d in out.values():
        for s in d:
            d[s] = d[s] / np.linalg.norm(d[s])
    return out


def layer_direction(contact_normals, other_normals):
    """Direction d of a node's layer nodes: d . (-n) = 1 for the outward
    normals n of the articular faces at the node (minimum norm), and
    d . m = 0 for the normals m of the non-articular faces there (the node
    slides inside them).  None if no such direction exists."""
    A = -np.array(contact_normals)
    if other_normals:
        M = np.array(other_normals)
        _, sv, vt = np.linalg.svd(M)
        rank = int(np.sum(sv > 1e-6))
        if rank >= 3:
            return None
        basis = vt[rank:].T  # 3 x (3 - rank)
    else:
        basis = np.eye(3)
    y, *_ = np.linalg.lstsq(A @ basis, np.ones(len(A)), rcond=None)
    d = basis @ y
    if np.min(A @ d) < 0.3:  # cannot go (enough) below every face
        return None
    return d


# ------------------------------------------------------------------ layer
class LayeredBody:
    """Nodes, prisms of the articular layer and the surface of the core of
    one body, before the core is meshed and everything is split into
    hexahedra (build_layer() fills it)."""


def build_layer(X, tris, face, ent, groups, layers, thickness, ratio, project):
    """Steps 2 and 3 of the module docstring.  project(kind, tag, points)
    moves points onto a CAD face (kind 2) or edge (kind 1) or returns them
    unchanged.  Returns a LayeredBody with
      nodes          all nodes so far (surface, layer)
      prisms         (P x 6): bottom triangle (outer) then top (inner) nodes
      core_tris      (K x 3) closed surface of the core, outward of the core
      boundary_tris  (B x 3) with boundary_face (B): triangles on the body's
                     boundary (articular and moved non-articular ones)
      band           list of (a, b, face): boundary edges of the layer's side
                     walls on face `face` (a, b node ids, one pair per layer
                     level, levels 0..layers)
      node_ent       (N x 2) CAD entity of each node on the boundary
                     ((-1, -1) inside)."""
    is_c = np.array([groups.get(s) in CONTACT_GROUPS for s in face])
    nrm = face_normals_at_nodes(X, tris, face)
    c_nodes = np.unique(tris[is_c])
    c_faces = set(face[is_c].tolist())
    # fractions of the depth at the layer levels, thinnest at the surface
    w = ratio ** np.arange(layers)
    frac = np.concatenate([[0.0], np.cumsum(w) / w.sum()])
    # direction and CAD entity of every articular node's column
    direction, target = {}, {}
    bad = []
    for a in c_nodes:
        cn = [v for s, v in nrm[a].items() if s in c_faces]
        on = [(s, v) for s, v in nrm[a].items() if s not in c_faces]
        d = layer_direction(cn, [v for _, v in on])
        if d is None:
            # a corner of several non-articular faces that admits no
            # direction inside all of them: straight in along the mean
            # articular normal, on no face (allowed at a few nodes)
            bad.append(X[a])
            m = np.mean(cn, axis=0)
            d, on = -m / np.dot(m, m), []
        direction[a] = d
        if len(on) == 1:
            target[a] = (2, on[0][0])
        elif len(on) >= 2:
            curve = common_curve(ent[a], [s for s, _ in on])
            target[a] = (1, curve) if curve is not None else (2, on[0][0])
        else:
            target[a] = (-1, -1)
    if len(bad) > max(2, 0.002 * len(c_nodes)):
        raise RuntimeError(
            "%d nodes of the articular faces have no direction into the body "
            "(a sharp edge next to them?), e.g. at %s; give the articular surface as its own "
            "STL (--femur-contact-stl, --insert-contact-stl) or try another --patch-angle"
            % (len(bad), bad[0])
        )
    level = {(a, 0): a for a in c_nodes}
    for k in range(1, layers + 1):
        for i, a in enumerate(c_nodes):
            level[(a, k)] = len(X) + i * layers + k - 1
    prisms = np.array(
        [
            [level[(v, k)] for v in tri] + [level[(v, k + 1)] for v in tri]
            for tri in tris[is_c]
            for k in range(layers)
        ],
        np.int64,
    )
    # the columns, thinned where a prism folds or degenerates (concave or
    # thin places): the nodes of such prisms get 0.7 of their depth, again
    # until every prism is fine
    depth = np.full(len(c_nodes), float(thickness))
    column = -np.ones(len(X) + layers * len(c_nodes), np.int64)
    column[c_nodes] = np.arange(len(c_nodes))
    column[len(X) :] = np.repeat(np.arange(len(c_nodes)), layers)
    # straight: columns whose layer nodes stay where their direction puts
    # them instead of going onto their neighbouring face; projected onto a
    # face that curves away, or onto the finer surface, they can move by
    # more than a thinned layer's depth and fold prisms at any depth
    straight = np.zeros(len(c_nodes), bool)
    directions = np.array([direction[a] for a in c_nodes])
    groups_of = {e: np.array([target[a] == e for a in c_nodes]) for e in set(target.values()) if e[0] > 0}
    cols = column[prisms[:, :3]]

    def folded_with(P):
        # NaN quality (a column of zero length) counts as folded
        return ~(prism_quality(np.concatenate([X, P.reshape(-1, 3)]), prisms) >= 0.05)

    for _ in range(12):
        U = X[c_nodes][:, None, :] + depth[:, None, None] * frac[None, 1:, None] * directions[:, None, :]
        P = U.copy()
        for e, m in groups_of.items():
            m = m & ~straight
            if m.any():
                P[m] = project(e[0], e[1], U[m].reshape(-1, 3)).reshape(P[m].shape)
        folded = folded_with(P)
        if np.any(folded):
            back = np.unique(cols[folded & ~folded_with(U)])
            back = back[~straight[back]]
            if len(back):
                straight[back] = True
                P[back] = U[back]
                folded = folded_with(P)
        nodes = np.concatenate([X, P.reshape(-1, 3)])
        if not np.any(folded):
            break
        depth[np.unique(column[prisms[folded]])] *= 0.7
        # no column more than 1.4 times as deep as a neighbour: a thinned
        # column next to full ones makes wedges that fold in turn
        for _ in range(50):
            lowest = np.full(len(depth), np.inf)
            for i in range(3):
                np.minimum.at(lowest, cols[:, i], depth[cols].min(axis=1))
            capped = np.minimum(depth, 1.4 * lowest)
            if np.array_equal(capped, depth):
                break
            depth = capped
    else:
        raise RuntimeError(
            "%d prisms of the contact layer stay folded, e.g. at %s; try a smaller "
            "--layer-thickness" % (int(folded.sum()), nodes[prisms[folded][0]].mean(axis=0))
        )
    body = LayeredBody()
    body.thinned = int(np.sum(depth < thickness))
    body.off_face = int(straight.sum())
    body.straight_in = len(bad)
    body.nodes = nodes
    body.node_ent = np.concatenate([ent, np.repeat(np.array([target[a] for a in c_nodes]), layers, axis=0)])
    body.prisms = prisms
    inner = np.array([[level[(v, layers)] for v in tri] for tri in tris[is_c]], np.int64)
    moved = np.arange(len(body.nodes))
    for a in c_nodes:
        moved[a] = level[(a, layers)]
    body.moved = moved
    other = moved[tris[~is_c]]
    body.core_tris = np.concatenate([inner, other])
    body.boundary_tris = np.concatenate([tris[is_c], other])
    body.boundary_face = np.concatenate([face[is_c], face[~is_c]])
    # the layer's side walls: articular triangle edges whose other triangle
    # is non-articular
    owner = {}
    for t, tri in enumerate(tris):
        for i in range(3):
            owner.setdefault(frozenset((tri[i], tri[(i + 1) % 3])), []).append(t)
    band = []
    for e, ts in owner.items():
        if is_c[ts[0]] != is_c[ts[1]]:
            a, b = sorted(e)
            s = face[ts[1]] if is_c[ts[0]] else face[ts[0]]
            band.append(
                ([level[(a, k)] for k in range(layers + 1)], [level[(b, k)] for k in range(layers + 1)], s)
            )
    body.band = band
    body.layers = layers
    morph_next_to_layer(body, tris[~is_c], c_nodes, project)
    return body


def prism_quality(nodes, prisms):
    """Smallest scaled corner Jacobian of the three straight hexahedra of
    every prism, positive when it is not folded (NaN when a column has
    zero length)."""
    X = nodes
    b, t = prisms[:, :3], prisms[:, 3:]
    q = np.full(len(prisms), np.inf)
    for i in range(3):
        v, nx, pv = i, (i + 1) % 3, (i + 2) % 3
        pts = np.stack(
            [
                X[b[:, v]],
                0.5 * (X[b[:, v]] + X[b[:, nx]]),
                X[b].mean(axis=1),
                0.5 * (X[b[:, v]] + X[b[:, pv]]),
                X[t[:, v]],
                0.5 * (X[t[:, v]] + X[t[:, nx]]),
                X[t].mean(axis=1),
                0.5 * (X[t[:, v]] + X[t[:, pv]]),
            ],
            axis=1,
        )
        n = len(prisms)
        with np.errstate(invalid="ignore", divide="ignore"):
            jac = blockmesh.corner_jacobians(pts.reshape(-1, 3), np.arange(8 * n).reshape(n, 8))
        q = np.minimum(q, np.min(-jac, axis=1))
    return q


def common_curve(entity, faces):
    """The CAD curve at a CAD point (or the curve itself) that bounds all the
    given faces, or None."""
    dim, tag = int(entity[0]), int(entity[1])
    if dim == 1:
        cands = [tag]
    elif dim == 0:
        cands = list(gmsh.model.getAdjacencies(0, tag)[0])
    else:
        return None
    for c in cands:
        up = set(gmsh.model.getAdjacencies(1, c)[0].tolist())
        if set(faces) <= up:
            return c
    return None


def morph_next_to_layer(body, tris, c_nodes, project, reach=4.0):
    """Move the nodes of the non-articular faces near the edge of the
    articular faces along with the layer: the nodes on that edge moved by
    u_a (inside their face) to the layer's bottom; a node at distance r from
    the edge moves by the inverse-distance (Shepard) mean of the nearby u_a
    times max(0, 1 - r / (reach |u|)), and back onto its CAD face (curve)
    (points stay).  Without this the triangles next to the edge would lose
    the layer's depth and could fold over."""
    X = body.nodes
    edge = np.array(sorted(set(np.unique(tris).tolist()) & set(c_nodes.tolist())), np.int64)
    if len(edge) == 0:
        return
    u = X[body.moved[edge]] - X[edge]
    umax = np.linalg.norm(u, axis=1).max()
    free = np.setdiff1d(np.unique(tris), edge)
    free = free[body.node_ent[free][:, 0] >= 1]  # not on CAD points
    r = np.linalg.norm(X[free][:, None, :] - X[edge][None, :, :], axis=2)
    near = r.min(axis=1) < reach * umax
    free, r = free[near], r[near]
    w = 1.0 / np.maximum(r, 1e-9) ** 4
    uf = (w @ u) / w.sum(axis=1)[:, None]
    fall = np.maximum(0.0, 1.0 - r.min(axis=1) / (reach * np.linalg.norm(uf, axis=1) + 1e-12))
    P = X[free] + fall[:, None] * uf
    ent = body.node_ent[free]
    for e in set(map(tuple, ent.tolist())):
        m = np.all(ent == e, axis=1)
        P[m] = project(e[0], e[1], P[m])
    X[free] = P


# ------------------------------------------------------------------ core
def in_child(fn, *args):
    """fn(*args) in a forked process, its result returned (pickled through
    a pipe), its exception raised again (a plain Exception, as gmsh's, or
    RuntimeError).  gmsh 4.8 stays locked ("I'm busy! Ask me that later...",
    every later mesh generation silently empty) after an exception inside
    generate(): a mesher that may fail runs in a child."""
    import pickle

    sys.stdout.flush()
    sys.stderr.flush()
    r, w = os.pipe()
    pid = os.fork()
    if pid == 0:
        os.close(r)
        try:
            res = ("ok", fn(*args))
        except BaseException as e:  # noqa: B902 (everything goes back to the parent)
            res = ("error", type(e).__name__, str(e))
        with os.fdopen(w, "wb") as f:
            f.write(pickle.dumps(res))
        os._exit(0)
    os.close(w)
    with os.fdopen(r, "rb") as f:
        data = f.read()
    _, status = os.waitpid(pid, 0)
    if not data:
        raise RuntimeError("the tetrahedral mesher died (wait status %d)" % status)
    res = pickle.loads(data)
    if res[0] == "error":
        raise (Exception if res[1] == "Exception" else RuntimeError)(res[2])
    return res[1]


def core_tets(X, T, size):
    """gmsh's Delaunay tetrahedra inside the closed surface (X, T; tags
    1..len(X)) in a new model: (tets, inner node tags, their coordinates,
    surface node tags, their coordinates)."""
    gmsh.model.add("core")
    s = gmsh.model.addDiscreteEntity(2)
    gmsh.model.mesh.addNodes(2, s, np.arange(1, len(X) + 1), X.reshape(-1))
    gmsh.model.mesh.addElementsByType(s, 2, [], T.reshape(-1))
    loop = gmsh.model.geo.addSurfaceLoop([s])
    v = gmsh.model.geo.addVolume([loop])
    gmsh.model.geo.synchronize()
    gmsh.model.mesh.generate(3)
    tets = []
    for et, _, nt in zip(*gmsh.model.mesh.getElements(3, v)):
        if et != 4:
            raise RuntimeError("the core has elements of type %d" % et)
        tets.append(np.array(nt, np.int64).reshape(-1, 4))
    if not tets:
        raise RuntimeError("gmsh made no tetrahedra in the core")
    inner, coords, _ = gmsh.model.mesh.getNodes(3, v)
    on_surface, xs, _ = gmsh.model.mesh.getNodes(2, s)
    return np.concatenate(tets), inner, coords, on_surface, xs


def mesh_core(body, size):
    """Step 3: Delaunay tetrahedra in the core (a new gmsh model in a
    child process: in_child()), with no new node on its boundary.  Appends
    the new nodes to body.nodes and returns the tetrahedra (T x 4)."""
    used = np.unique(body.core_tris)
    local = -np.ones(len(body.nodes), np.int64)
    local[used] = np.arange(1, len(used) + 1)  # gmsh wants dense tags
    gmsh.option.setNumber("Mesh.MeshSizeExtendFromBoundary", 1)
    gmsh.option.setNumber("Mesh.MeshSizeMax", size)
    gmsh.option.setNumber("Mesh.Algorithm3D", 1)
    gmsh.option.setNumber("Mesh.SubdivisionAlgorithm", 0)
    tets, inner, coords, on_surface, xs = in_child(core_tets, body.nodes[used], local[body.core_tris], size)
    if len(on_surface) != len(used) or not np.allclose(
        xs.reshape(-1, 3)[np.argsort(on_surface)], body.nodes[used]
    ):
        raise RuntimeError(
            "tetrahedral meshing of the core added %d boundary nodes" % (len(on_surface) - len(used))
        )
    renum = {i + 1: int(v) for i, v in enumerate(used)}
    n = len(body.nodes)
    for i, t in enumerate(inner):
        renum[int(t)] = n + i
    missing = set(np.unique(tets).tolist()) - set(renum)
    if missing:
        raise RuntimeError("core: %d nodes of the tetrahedra are unknown" % len(missing))
    body.nodes = np.concatenate([body.nodes, coords.reshape(-1, 3)])
    body.node_ent = np.concatenate([body.node_ent, -np.ones((len(inner), 2), np.int64)])
    return np.vectorize(renum.get)(tets)


# ------------------------------------------------------------------ hexahedra
class Splitter:
    """New nodes of the split: edge midpoints and triangle (tetrahedron)
    centroids, one per edge (triangle) whichever element asks first."""

    def __init__(self, nodes):
        self.nodes = list(nodes)
        self.mid = {}
        self.cen = {}

    def _add(self, p):
        self.nodes.append(p)
        return len(self.nodes) - 1

    def edge(self, a, b):
        k = (a, b) if a < b else (b, a)
        if k not in self.mid:
            self.mid[k] = self._add(0.5 * (self.nodes[a] + self.nodes[b]))
        return self.mid[k]

    def tri(self, a, b, c):
        k = tuple(sorted((a, b, c)))
        if k not in self.cen:
            self.cen[k] = self._add((self.nodes[a] + self.nodes[b] + self.nodes[c]) / 3.0)
        return self.cen[k]

    def centre(self, tet):
        return self._add(sum(self.nodes[v] for v in tet) / 4.0)


def split_into_hexes(body, tets, groups, curve_edges, project):
    """Step 4: prisms into three, tetrahedra into four hexahedra; boundary
    quadrangles by group.  Returns (nodes, hexes, surfaces) as
    blockmesh.write_msh wants them (oriented)."""
    sp = Splitter(body.nodes)
    from_prisms, from_tets = [], []
    for p in body.prisms:
        bot, top = p[:3], p[3:]
        for i in range(3):
            v, nx, pv = i, (i + 1) % 3, (i + 2) % 3
            from_prisms.append(
                [
                    bot[v],
                    sp.edge(bot[v], bot[nx]),
                    sp.tri(*bot),
                    sp.edge(bot[v], bot[pv]),
                    top[v],
                    sp.edge(top[v], top[nx]),
                    sp.tri(*top),
                    sp.edge(top[v], top[pv]),
                ]
            )
    X = body.nodes
    vol = np.einsum(
        "ij,ij->i",
        X[tets[:, 1]] - X[tets[:, 0]],
        np.cross(X[tets[:, 2]] - X[tets[:, 0]], X[tets[:, 3]] - X[tets[:, 0]]),
    )
    tets = np.where((vol < 0)[:, None], tets[:, [0, 2, 1, 3]], tets)  # gmsh's turn both ways
    for t in tets:
        c = sp.centre(t)
        for i in range(4):
            v = t[i]
            p, q, r = [t[j] for j in ((1, 2, 3), (2, 0, 3), (0, 1, 3), (1, 0, 2))[i]]  # (v p q r) even
            from_tets.append(
                [
                    v,
                    sp.edge(v, p),
                    sp.tri(v, p, q),
                    sp.edge(v, q),
                    sp.edge(v, r),
                    sp.tri(v, p, r),
                    c,
                    sp.tri(v, q, r),
                ]
            )
    quads = {}
    # boundary triangles: three quadrangles each
    on_face = {}  # new boundary node -> (kind, tag)
    for tri, s in zip(body.boundary_tris, body.boundary_face):
        a, b, c = tri
        g = sp.tri(a, b, c)
        on_face[g] = (2, s)
        m = {}
        for u, v in ((a, b), (b, c), (c, a)):
            m[(u, v)] = sp.edge(u, v)
            cv = curve_edges.get(frozenset((u, v)))
            on_face.setdefault(m[(u, v)], (1, cv) if cv is not None else (2, s))
        group = groups.get(s)
        if group:
            quads.setdefault(group, []).extend(
                [[a, m[(a, b)], g, m[(c, a)]], [b, m[(b, c)], g, m[(a, b)]], [c, m[(c, a)], g, m[(b, c)]]]
            )
    # the layer's side walls: two quadrangles per prism side
    for lo, hi, s in body.band:
        for k in range(body.layers):
            m0, m1 = sp.edge(lo[k], hi[k]), sp.edge(lo[k + 1], hi[k + 1])
            on_face.setdefault(m1, (2, s))
            group = groups.get(s)
            if group:
                quads.setdefault(group, []).extend([[lo[k], m0, m1, lo[k + 1]], [m0, hi[k], hi[k + 1], m1]])
    straight = np.array(sp.nodes)
    # every hexahedron of a kind must turn the same way (a folded one would
    # turn the other way, and reordering it would hide an overlap)
    hexes = []
    for kind, h in (("prism", from_prisms), ("tetrahedron", from_tets)):
        h = np.array(h, np.int64).reshape(-1, 8)
        sign = np.sign(centre_jacobians(straight, h))
        if len(np.unique(sign)) > 1:
            raise RuntimeError(
                "%d hexahedra of a %s are inverted" % (min(np.sum(sign > 0), np.sum(sign < 0)), kind)
            )
        hexes.append(h if len(h) == 0 or sign[0] > 0 else h[:, [0, 3, 2, 1, 4, 7, 6, 5]])
    hexes = blockmesh.orient_hexes(straight, np.concatenate(hexes))
    nodes = straight.copy()
    by_target = {}
    for v, e in on_face.items():
        by_target.setdefault(e, []).append(v)
    for (kind, tag), vs in by_target.items():
        nodes[vs] = project(kind, tag, nodes[vs])
    body.n_straight = keep_valid(straight, nodes, hexes, np.array(sorted(on_face), np.int64))
    surfaces = {
        g: blockmesh.orient_quads_outward(nodes, hexes, np.array(q, np.int64)) for g, q in quads.items()
    }
    return nodes, hexes, surfaces


def centre_jacobians(nodes, hexes):
    """Jacobian determinants of trilinear hexahedra at their centres."""
    x = nodes[hexes]
    a = x[:, 1] + x[:, 2] + x[:, 5] + x[:, 6] - x[:, 0] - x[:, 3] - x[:, 4] - x[:, 7]
    b = x[:, 2] + x[:, 3] + x[:, 6] + x[:, 7] - x[:, 0] - x[:, 1] - x[:, 4] - x[:, 5]
    c = x[:, 4] + x[:, 5] + x[:, 6] + x[:, 7] - x[:, 0] - x[:, 1] - x[:, 2] - x[:, 3]
    return np.einsum("ij,ij->i", a, np.cross(b, c))


def keep_valid(straight, nodes, hexes, moved, min_quality=0.02):
    """Where moving the new boundary nodes onto the CAD made a hexahedron's
    scaled corner Jacobian fall below min_quality (thin tetrahedra at a
    curved face), put that hexahedron's moved nodes back on the straight
    edges and faces.  Changes nodes in place; returns how many nodes went
    back."""
    is_moved = np.zeros(len(nodes), bool)
    is_moved[moved] = True
    back = 0
    for _ in range(20):
        q = blockmesh.corner_jacobians(nodes, hexes).min(axis=1)
        bad = q < min_quality
        if not np.any(bad):
            break
        vs = np.unique(hexes[bad])
        vs = vs[is_moved[vs]]
        if len(vs) == 0:
            break
        nodes[vs] = straight[vs]
        is_moved[vs] = False
        back += len(vs)
    return back


def contact_layer_quality(nodes, hexes, surfaces):
    """{group: (number of hexahedra with a face in the group, their minimum
    scaled corner Jacobian)} for the articular groups."""
    return {g: v[:2] for g, v in contact_cells(nodes, hexes, surfaces).items()}


def contact_cells(nodes, hexes, surfaces):
    """{group: (number of hexahedra with a face in the group, their minimum
    scaled corner Jacobian, the centre of the worst one)} for the articular
    groups (the contact cells, whose quality mesh-implant checks)."""
    faces = {}
    for h, conn in enumerate(hexes):
        for f in blockmesh.HEX_FACES:
            faces[frozenset(conn[list(f)].tolist())] = h
    out = {}
    for g, q in surfaces.items():
        if g not in CONTACT_GROUPS:
            continue
        hs = np.unique([faces[frozenset(x.tolist())] for x in q])
        jac = blockmesh.corner_jacobians(nodes, hexes[hs]).min(axis=1)
        worst = hs[np.argmin(jac)]
        out[g] = (len(hs), float(jac.min()), nodes[hexes[worst]].mean(axis=0))
    return out


def mesh_body(
    vol, groups, size_field, size, layers, thickness, ratio, cad, notes, fine_faces=None, smooth=None
):
    """Steps 1-4 for volume `vol` of the current gmsh model (its faces
    classified into `groups`; sizes from size_field, a SizeField; cad: new
    boundary nodes go onto the OpenCASCADE faces, else onto the boundary
    triangulation; notes: a list that gets a line on what had to give way;
    fine_faces: {face: triangles (T x 3 x 3)}, a finer surface that new
    boundary nodes on faces go onto instead, and then, on the faces in
    smooth ({face: project(points)}), onto a smooth surface).  Returns
    (nodes, hexes, surfaces)."""
    X, tris, face, ent, curve_edges = triangulate_boundary(vol, groups, size_field, size)
    project = boundary_projector(X, tris, face, curve_edges, cad, fine_faces, smooth)
    body = build_layer(X, tris, face, ent, groups, layers, thickness, ratio, project)
    tets = mesh_core(body, size)
    out = split_into_hexes(body, tets, groups, curve_edges, project)
    if body.thinned:
        notes.append("%d layer columns thinned (folds)" % body.thinned)
    if body.off_face:
        notes.append("%d layer columns left straight, off their neighbouring face (folds)" % body.off_face)
    if body.straight_in:
        notes.append("%d layer columns straight in at corners of several faces" % body.straight_in)
    if body.n_straight:
        notes.append("%d new boundary nodes left on straight edges (inverted otherwise)" % body.n_straight)
    return out


def boundary_projector(X, tris, face, curve_edges, cad, fine_faces=None, smooth=None):
    """project(kind, tag, points) for the new boundary nodes of a split:
    onto the OpenCASCADE faces and curves (cad), else onto the boundary
    triangulation (X, tris, face, curve_edges); with fine_faces ({face:
    triangles (T x 3 x 3)}) points on faces go onto that finer surface
    instead, and on the faces in smooth ({face: project(points)}) then onto
    a smooth surface (mesh_body())."""
    project = cad_projector() if cad else mesh_projector(X, tris, face, curve_edges)
    if fine_faces is None:
        return project
    on_fine, on_mesh, smooth = surface_projector(fine_faces), project, smooth or {}

    def project_fine(kind, tag, P):
        if kind != 2:
            return on_mesh(kind, tag, P)
        P = on_fine(kind, tag, P)
        if tag in smooth and len(P):
            P = smooth[tag](P.reshape(-1, 3)).reshape(P.shape)
        return P

    return project_fine


def closest_on_triangles(P, T):
    """Closest points to the points P (n x 3) on the triangles T (m x 3 x 3)."""
    out = np.empty_like(P)
    a, b, c = T[:, 0], T[:, 1], T[:, 2]
    ab, ac = b - a, c - a
    n = np.cross(ab, ac)
    nn = np.maximum((n * n).sum(1), 1e-300)
    for i, p in enumerate(P):
        # projection onto each plane, then clamped to the triangle through
        # its barycentric coordinates, else the closest point on an edge
        q = p - ((p - a) * n).sum(1)[:, None] * n / nn[:, None]
        w2 = (np.cross(ab, q - a) * n).sum(1) / nn
        w1 = (np.cross(q - a, ac) * n).sum(1) / nn
        inside = (w1 >= 0) & (w2 >= 0) & (w1 + w2 <= 1)
        best = np.where(inside[:, None], q, np.inf)
        for u, v in ((a, b), (b, c), (c, a)):
            e = v - u
            t = np.clip(((p - u) * e).sum(1) / np.maximum((e * e).sum(1), 1e-300), 0, 1)
            r = u + t[:, None] * e
            closer = ((r - p) ** 2).sum(1) < ((best - p) ** 2).sum(1)
            best = np.where(closer[:, None], r, best)
        out[i] = best[np.argmin(((best - p) ** 2).sum(1))]
    return out


def mesh_projector(X, tris, face, curve_edges):
    """project(kind, tag, points) onto the triangles of face `tag` (kind 2)
    or the segments of curve `tag` (kind 1) of the boundary triangulation:
    for an STL, whose triangulation is its geometry."""
    by_face = {s: X[tris[face == s]] for s in np.unique(face)}
    by_curve = {}
    for e, c in curve_edges.items():
        by_curve.setdefault(c, []).append(X[sorted(e)])

    def project(kind, tag, P):
        P = np.asarray(P, float)
        if tag is None or len(P) == 0 or kind not in (1, 2):
            return P
        if kind == 2:
            return closest_on_triangles(P, by_face[tag])
        S = np.array(by_curve[tag])
        return closest_on_triangles(P, np.stack([S[:, 0], S[:, 1], S[:, 1]], axis=1))

    return project


def surface_projector(by_face, candidates=16):
    """project(kind, tag, points) onto the closest of the triangles
    by_face[tag] (T x 3 x 3; among the `candidates` nearest by centroid) for
    faces (kind 2); other points stay: for surfaces tagged per patch (no
    curves), projected onto their finer repaired surface."""
    from scipy.spatial import cKDTree

    trees = {s: cKDTree(T.mean(axis=1)) for s, T in by_face.items() if len(T)}

    def project(kind, tag, P):
        P = np.asarray(P, float)
        if kind != 2 or tag not in trees or len(P) == 0:
            return P
        T = by_face[tag]
        _, idx = trees[tag].query(P.reshape(-1, 3), k=min(candidates, len(T)))
        idx = idx.reshape(len(idx), -1)
        out = np.array([closest_on_triangles(p[None], T[i])[0] for p, i in zip(P.reshape(-1, 3), idx)])
        return out.reshape(P.shape)

    return project


def cad_projector():
    """project(kind, tag, points) onto the entities of the current gmsh
    model (closest point)."""

    def project(kind, tag, P):
        P = np.asarray(P, float)
        if tag is None or len(P) == 0:
            return P
        out, _ = gmsh.model.getClosestPoint(kind, int(tag), P.reshape(-1))
        return np.array(out).reshape(P.shape)

    return project
