# SPDX-License-Identifier: LGPL-2.1-or-later
"""The femoral component as its articular shell (`--femur-mesh shell`, the
default of scripts/mesh-implant's `--method auto`; doc/geometry.md, issue 50
item 1).

Why: the femoral component is CoCr (E about 200 GPa), some 200 times stiffer
than the UHMWPE insert.  What it contributes to the contact, the pressures
and the wear is the shape of its articular surface, not its volume.  Its
volume (box, pegs, side walls and the sharp, unfilleted CAD edges where the
condyles meet them) is what made meshing real implants fail: the contact
layer (contact_layer.py) needs a direction at every articular node that
slides inside the neighbouring faces, and a tetrahedral core.  The shell
looks at nothing but the articular surface:

1. The articular triangles (femur_contact): on a STEP file those of the
   boundary triangulation the contact layer would have had (sizes from
   contact_layer.SizeField), so that `--femur-mesh shell` and `layer` share
   their articular surface; if gmsh cannot triangulate a face elsewhere,
   only the articular faces are triangulated (triangulate_faces()).  On an
   STL they are the tagged, remeshed triangles
   (mesh_implant.prepare_surfaces()).
2. Every triangle becomes three kite-shaped quadrangles (edge midpoints and
   the centroid, as contact_layer splits its prisms), the new nodes put on
   the CAD faces and curves, or on the repaired surface and its smooth
   moving-least-squares fit (contact_layer.boundary_projector()).
3. Every node of the articular surface gets a column along its inward
   normal: the quadrangles' area-weighted normals at the node, smoothed
   with a Gaussian of width `smoothing` over the nodes of the same
   connected patch whose normals are within 90 degrees (a crease between
   articular faces turns the columns over a few millimetres instead of at
   one node).  Neighbouring faces play no part.
4. The columns are `thickness` deep, but at most half the radius of
   curvature of the convex side (where the columns converge: the cam of a
   posterior-stabilised femur, a rounded rim), and neighbours differ by
   at most a factor of 1.4.  Columns of hexahedra whose scaled corner
   Jacobian falls below `quality_target` (and below 0.9 times that of the
   same cell in the limit of a shallow column: the columns' convergence
   is the cause, not the kite or the columns' tilt against it) are thinned
   by 0.7 again, down to `min_fraction` of that depth (a crease between
   articular faces, which the smoothing turns into a tight curve, may need
   that).
5. Cells still below `trim_quality` that touch the border of the articular
   patch (a sharp rim, a sliver of a triangle) have their triangles left out
   of the shell, ring by ring (reported: what was trimmed and where).
6. `layers` cell layers, thinnest at the surface (thickness ratio `ratio`).
   The outer quadrangles are femur_contact, the inner ones femur_fixation
   (clamped by tkr-wear and moved rigidly with the femur, as the whole
   component's fixation faces were), the side walls have no group
   (traction free).

Compared with the whole component on TKR A, B and C (doc/geometry.md,
"The femur as its articular shell") the wear results change by much less
than the 1 % the issue allows.
"""
import numpy as np
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components
from scipy.spatial import cKDTree

import blockmesh
import contact_layer

import gmsh


class ShellError(RuntimeError):
    """The shell could not be made (the message names an option)."""


# --------------------------------------------------------------- surface
class visible_only:
    """Context manager: gmsh meshes only the faces `faces` of the current
    model (and their curves and points): the articular faces of a STEP file
    are triangulated without touching the rest of the component."""

    def __init__(self, faces):
        self.faces = [(2, int(s)) for s in faces]

    def __enter__(self):
        self.all = gmsh.model.getEntities()
        gmsh.model.setVisibility(self.all, 0)
        gmsh.model.setVisibility(self.faces, 1, recursive=True)
        gmsh.option.setNumber("Mesh.MeshOnlyVisible", 1)
        return self

    def __exit__(self, *exc):
        gmsh.option.setNumber("Mesh.MeshOnlyVisible", 0)
        gmsh.model.setVisibility(self.all, 1)
        return False


def triangulate_faces(faces, outward, size_field, size):
    """Triangulate only the faces `faces` of the current (OpenCASCADE) gmsh
    model, sizes from size_field (a contact_layer.SizeField, as
    contact_layer.triangulate_boundary()).  outward: {face: (K x 6) points
    on the face and the outward unit normal there} (the face table's, from
    the body's coarse volume mesh): each face's triangles are turned to
    agree with the normals of the ones nearest those points (a face's mean
    normal would not do: a cam's cylinder has almost none).  Returns X,
    tris, face, curve_edges as contact_layer.triangulate_boundary() (no
    CAD entity per node)."""
    gmsh.model.mesh.clear()
    with visible_only(faces):
        X = contact_layer.generate_surfaces(size_field, size)
    tris, face = [], []
    for s in faces:
        tri = []
        for et, _, nt in zip(*gmsh.model.mesh.getElements(2, s)):
            if et != 2:
                raise ShellError("articular face %d has elements of type %d" % (s, et))
            tri.append(np.array(nt, np.int64).reshape(-1, 3))
        if not tri:
            raise ShellError("gmsh made no triangles on articular face %d" % s)
        tri = np.concatenate(tri)
        P = X[tri]
        nt = np.cross(P[:, 1] - P[:, 0], P[:, 2] - P[:, 0])
        nt /= np.maximum(np.linalg.norm(nt, axis=1), 1e-300)[:, None]
        ref = np.asarray(outward[s]).reshape(-1, 6)
        _, near = cKDTree(P.mean(axis=1)).query(ref[:, :3])
        if np.einsum("ij,ij->i", nt[near], ref[:, 3:]).sum() < 0:
            tri = tri[:, ::-1]
        tris.append(tri)
        face.append(np.full(len(tri), s))
    tris, face = np.concatenate(tris), np.concatenate(face)
    boundary = gmsh.model.getBoundary([(2, s) for s in faces], combined=False, oriented=False)
    used, renum, curve_edges = contact_layer.renumber_used(len(X), tris, [abs(c) for _, c in boundary])
    return X[used], renum[tris], face, curve_edges


def check_orientation(tris):
    """Raise ShellError unless every edge shared by two triangles is run
    through in opposite directions by them (one consistent side)."""
    E = np.concatenate([tris[:, [0, 1]], tris[:, [1, 2]], tris[:, [2, 0]]])
    key = E[:, 0] * (E.max() + 1) + E[:, 1]
    if len(np.unique(key)) < len(key):
        raise ShellError(
            "the articular triangles are not oriented consistently (two run through the same edge "
            "the same way): the faces of the articular surface disagree on their outward side"
        )


def kites(X, tris, face, curve_edges, project):
    """Each triangle (outward) split into three kite-shaped quadrangles by
    its edge midpoints and centroid: (nodes, quads (Q x 4, outward), owner
    (Q: the triangle of each quadrangle)); only the nodes the triangles use,
    the new ones projected (project(kind, tag, points): onto face `tag`
    (kind 2) or curve `tag` (kind 1))."""
    used = np.unique(tris)
    renum = -np.ones(len(X), np.int64)
    renum[used] = np.arange(len(used))
    tris = renum[tris]
    curve_edges = {
        frozenset(renum[list(e)].tolist()): c for e, c in curve_edges.items() if (renum[list(e)] >= 0).all()
    }
    nodes = list(X[used])
    mid, on = {}, {}
    quads, owner = [], []
    for t, (a, b, c) in enumerate(tris):
        g = len(nodes)
        nodes.append((nodes[a] + nodes[b] + nodes[c]) / 3.0)
        on[g] = (2, face[t])
        m = {}
        for u, v in ((a, b), (b, c), (c, a)):
            k = (min(u, v), max(u, v))
            if k not in mid:
                mid[k] = len(nodes)
                nodes.append(0.5 * (nodes[u] + nodes[v]))
                cv = curve_edges.get(frozenset(k))
                on[mid[k]] = (1, cv) if cv is not None else (2, face[t])
            m[(u, v)] = mid[k]
        quads += [[a, m[(a, b)], g, m[(c, a)]], [b, m[(b, c)], g, m[(a, b)]], [c, m[(c, a)], g, m[(b, c)]]]
        owner += [t] * 3
    nodes = np.array(nodes)
    by_target = {}
    for v, e in on.items():
        by_target.setdefault(e, []).append(v)
    for (kind, tag), vs in by_target.items():
        nodes[vs] = project(kind, tag, nodes[vs])
    return nodes, np.array(quads, np.int64), np.array(owner, np.int64)


def quad_normals(nodes, quads):
    """Area vectors (twice the area times the unit normal) of quadrangles."""
    P = nodes[quads]
    return 0.5 * np.cross(P[:, 2] - P[:, 0], P[:, 3] - P[:, 1])


def quad_edges(quads):
    """The unique edges (E x 2, sorted node pairs) of quadrangles."""
    E = np.concatenate([quads[:, [i, (i + 1) % 4]] for i in range(4)])
    return np.unique(np.sort(E, axis=1), axis=0)


def directions(nodes, quads, smoothing):
    """Unit outward normal at every node: the area-weighted normals of its
    quadrangles, smoothed with Gaussian weights exp(-(r / smoothing)^2) over
    the nodes within 2 smoothing of the same connected patch whose normals
    are within 90 degrees of its own (step 3 of the module docstring)."""
    N = np.zeros_like(nodes)
    a = quad_normals(nodes, quads)
    for i in range(4):
        np.add.at(N, quads[:, i], a)
    N /= np.maximum(np.linalg.norm(N, axis=1), 1e-300)[:, None]
    if smoothing <= 0:
        return N
    E = quad_edges(quads)
    graph = coo_matrix((np.ones(len(E)), (E[:, 0], E[:, 1])), shape=(len(nodes), len(nodes)))
    comp = connected_components(graph, directed=False)[1]
    tree = cKDTree(nodes)
    D = tree.sparse_distance_matrix(tree, 2.0 * smoothing, output_type="coo_matrix")
    i, j, r = D.row, D.col, D.data
    keep = (comp[i] == comp[j]) & (np.einsum("ij,ij->i", N[i], N[j]) > 0)
    i, j, r = i[keep], j[keep], r[keep]
    w = np.exp(-((r / smoothing) ** 2))
    S = N.copy()  # the node itself (distance 0 is not stored)
    np.add.at(S, i, w[:, None] * N[j])
    return S / np.maximum(np.linalg.norm(S, axis=1), 1e-300)[:, None]


def convex_curvature(nodes, quads, normals):
    """At every node, the largest curvature (1/mm) along its edges on the
    convex side, (n_a - n_b) . (x_a - x_b) / |x_a - x_b|^2 > 0: where inward
    columns converge, meeting at depth 1/curvature; 0 where none does."""
    E = quad_edges(quads)
    d = nodes[E[:, 0]] - nodes[E[:, 1]]
    k = np.einsum("ij,ij->i", normals[E[:, 0]] - normals[E[:, 1]], d) / np.maximum((d * d).sum(1), 1e-300)
    out = np.zeros(len(nodes))
    np.maximum.at(out, E[:, 0], k)
    np.maximum.at(out, E[:, 1], k)
    return out


def cap_neighbours(depth, edges, factor=1.4):
    """No column more than `factor` times as deep as a neighbour (a thinned
    column next to full ones makes wedges)."""
    for _ in range(200):
        low = depth.copy()
        np.minimum.at(low, edges[:, 0], depth[edges[:, 1]])
        np.minimum.at(low, edges[:, 1], depth[edges[:, 0]])
        capped = np.minimum(depth, factor * low)
        if np.array_equal(capped, depth):
            break
        depth = capped
    return depth


def fractions(layers, ratio):
    """Depth fractions 0 .. 1 of the layer levels, the thinnest layer at the
    surface, each next one `ratio` times thicker."""
    w = ratio ** np.arange(layers)
    return np.concatenate([[0.0], np.cumsum(w) / w.sum()])


def extrude(nodes, quads, normals, depth, frac):
    """Nodes ((layers + 1) N x 3: level k of node i is k N + i) and
    hexahedra (layers Q x 8, level by level) of the columns; each
    hexahedron's first face is the outer one (reversed, so that the
    hexahedron turns positively: levels go inward)."""
    N = len(nodes)
    P = np.concatenate([nodes - (f * depth)[:, None] * normals for f in frac])
    q = quads[:, ::-1]
    hexes = np.concatenate([np.hstack([k * N + q, (k + 1) * N + q]) for k in range(len(frac) - 1)])
    return P, hexes


def quality(P, hexes):
    """Smallest scaled corner Jacobian of each hexahedron (negative: turned
    inside out)."""
    with np.errstate(invalid="ignore", divide="ignore"):
        q = blockmesh.corner_jacobians(P, hexes).min(axis=1)
    return np.where(np.isnan(q), -1.0, q)


def limit_quality(nodes, quads, normals, frac):
    """The quality the first-layer cells tend to as the columns get
    shallow (depth 1e-3 mm): what thinning can reach (the kite's shape and
    the columns' tilt against it stay)."""
    P, hexes = extrude(nodes, quads, normals, np.full(len(nodes), 1e-3), frac[:2])
    return quality(P, hexes)


class Shell:
    """The result of build(): nodes, hexes, surfaces ({femur_contact,
    femur_fixation: quads}) and what had to give way (thinned: columns
    thinner than asked; trimmed: triangles left out, their area and the
    lowest one's centre; min_depth)."""


def build(
    nodes,
    quads,
    thickness,
    layers,
    ratio,
    smoothing=None,
    quality_target=0.25,
    min_fraction=0.2,
):
    """Steps 3, 4 and 6 of the module docstring on one kite surface (nodes,
    quads outward); mesh_shell() trims (step 5) and calls this again.
    Returns a Shell (not yet oriented and tagged: finish()) and the
    smallest quality of the cells under each quad."""
    smoothing = 0.5 * thickness if smoothing is None else smoothing
    frac = fractions(layers, ratio)
    normals = directions(nodes, quads, smoothing)
    edges = quad_edges(quads)
    kappa = convex_curvature(nodes, quads, normals)
    with np.errstate(divide="ignore"):
        depth = np.clip(np.where(kappa > 0, 0.5 / kappa, thickness), 0.05 * thickness, thickness)
    depth = cap_neighbours(depth, edges)
    floor = min_fraction * depth
    reachable = limit_quality(nodes, quads, normals, frac)
    for _ in range(40):
        P, hexes = extrude(nodes, quads, normals, depth, frac)
        q = quality(P, hexes)
        q_cell = q.reshape(layers, -1).min(axis=0)  # per quad, over its column of cells
        bad = (q_cell < quality_target) & (q_cell < 0.9 * reachable)
        cols = np.unique(quads[bad])
        cols = cols[depth[cols] > floor[cols] * (1 + 1e-9)]
        if not len(cols):
            break
        depth[cols] = np.maximum(0.7 * depth[cols], floor[cols])
        depth = np.maximum(cap_neighbours(depth, edges), np.minimum(floor, depth))
    shell = Shell()
    shell.nodes, shell.hexes = P, hexes
    shell.quads = quads
    shell.thinned = int(np.sum(depth < thickness * (1 - 1e-9)))
    shell.min_depth = float(depth.min())
    shell.n_surface = len(nodes)
    return shell, q_cell


def finish(shell, layers):
    """Orient the hexahedra and tag the outer and inner quadrangles."""
    N, Q = shell.n_surface, len(shell.quads)
    q = quality(shell.nodes, shell.hexes)
    if np.any(q <= 0):
        i = int(np.argmin(q))
        raise ShellError(
            "%d hexahedra of the femoral shell are inverted, e.g. at (%.1f, %.1f, %.1f); try a smaller "
            "--shell-thickness or a smaller --contact-size"
            % ((int(np.sum(q <= 0)),) + tuple(shell.nodes[shell.hexes[i]].mean(axis=0)))
        )
    shell.hexes = blockmesh.orient_hexes(shell.nodes, shell.hexes)
    outer = shell.quads
    inner = layers * N + shell.quads
    shell.surfaces = {
        "femur_contact": blockmesh.orient_quads_outward(shell.nodes, shell.hexes[:Q], outer),
        "femur_fixation": blockmesh.orient_quads_outward(shell.nodes, shell.hexes[(layers - 1) * Q :], inner),
    }
    return shell


def border_triangles(tris):
    """The triangles with an edge on the border of the surface (an edge of
    one triangle only)."""
    E = np.sort(np.concatenate([tris[:, [0, 1]], tris[:, [1, 2]], tris[:, [2, 0]]]), axis=1)
    _, inv, count = np.unique(E, axis=0, return_inverse=True, return_counts=True)
    on = (count[inv] == 1).reshape(3, -1).any(axis=0)
    return np.flatnonzero(on)


def mesh_shell(
    X,
    tris,
    face,
    curve_edges,
    project,
    thickness,
    layers,
    ratio,
    notes,
    smoothing=None,
    trim_quality=0.15,
    max_rings=4,
):
    """The shell under the articular triangles (X, tris outward, face,
    curve_edges as contact_layer.triangulate_boundary(); project as
    contact_layer.boundary_projector()): steps 2-6 of the module docstring.
    notes: a list that gets a line on what had to give way.  Returns
    (nodes, hexes, surfaces) for blockmesh.write_msh."""
    if layers < 1 or thickness <= 0 or ratio <= 0:
        raise ShellError("--shell-layers must be at least 1, --shell-thickness and --shell-ratio positive")
    check_orientation(tris)
    keep = np.ones(len(tris), bool)
    area = 0.5 * np.linalg.norm(
        np.cross(X[tris][:, 1] - X[tris][:, 0], X[tris][:, 2] - X[tris][:, 0]), axis=1
    )
    trimmed = []
    for ring in range(max_rings + 1):
        idx = np.flatnonzero(keep)
        nodes, quads, owner = kites(X, tris[idx], face[idx], curve_edges, project)
        shell, q_cell = build(nodes, quads, thickness, layers, ratio, smoothing)
        bad = np.unique(owner[q_cell < trim_quality])
        if not len(bad) or ring == max_rings:
            break
        border = np.intersect1d(bad, border_triangles(tris[idx]))
        if not len(border):
            break
        keep[idx[border]] = False
        trimmed.append(idx[border])
    shell = finish(shell, layers)
    shell.trimmed = np.concatenate(trimmed) if trimmed else np.zeros(0, np.int64)
    if len(shell.trimmed):
        c = X[tris[shell.trimmed]].mean(axis=1)
        low = c[np.argmin(c[:, 2])]
        notes.append(
            "trimmed %d articular triangles (%.1f mm^2 of %.1f) at the border of the articular surface "
            "where the shell's cells stayed below a scaled Jacobian of %g (a sharp rim), the lowest "
            "at (%.1f, %.1f, %.1f)"
            % ((len(shell.trimmed), area[shell.trimmed].sum(), area.sum(), trim_quality) + tuple(low))
        )
    if shell.thinned:
        notes.append(
            "%d of %d shell columns thinner than %g mm (curvature or cell shape), the thinnest %.2f mm"
            % (shell.thinned, shell.n_surface, thickness, shell.min_depth)
        )
    return shell.nodes, shell.hexes, shell.surfaces
