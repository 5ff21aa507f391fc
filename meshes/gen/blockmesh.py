"""Block-structured hexahedral meshes of two contacting bodies, written by gmsh.

Every body is a union of logically structured blocks: a block is an array of
node coordinates X[i, j, k, 0:3] (an analytic map of a graded index grid), and
the names of the physical surfaces its six logical faces belong to.  Blocks of
one body are glued by merging coincident nodes (the maps are evaluated with the
same formulas on shared faces, so shared nodes agree to round-off).  The two
bodies are never merged: their nodes stay distinct even where they touch.

The result is handed to gmsh as discrete entities (one volume per body, one
surface per physical surface) and written by gmsh as ASCII msh 4.1.
"""
import math

import numpy as np

# logical faces of a block: name -> (axis, side)
FACES = {"imin": (0, 0), "imax": (0, 1), "jmin": (1, 0), "jmax": (1, 1), "kmin": (2, 0), "kmax": (2, 1)}
# local corner order of a gmsh hexahedron in (i, j, k) offsets
HEX_CORNERS = ((0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0), (0, 0, 1), (1, 0, 1), (1, 1, 1), (0, 1, 1))


# --------------------------------------------------------------------------
# one-dimensional grids
# --------------------------------------------------------------------------
def geometric(n, length, ratio):
    """n cells on [0, length], each cell `ratio` times the previous one."""
    if abs(ratio - 1.0) < 1e-12:
        return np.linspace(0.0, length, n + 1)
    w = ratio ** np.arange(n)
    return np.concatenate([[0.0], np.cumsum(w)]) / w.sum() * length


def first_cell_ratio(n, length, h0):
    """Growth ratio r such that n cells starting with size h0 fill `length`."""
    if n * h0 >= length:
        return 1.0
    lo, hi = 1.0, 10.0
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if h0 * (mid**n - 1) / (mid - 1) > length:
            hi = mid
        else:
            lo = mid
    return 0.5 * (lo + hi)


def graded(n, length, h0):
    """n cells on [0, length], first cell about h0, geometric growth."""
    return geometric(n, length, first_cell_ratio(n, length, h0))


def grid1d(breaks, size, min_cells=1, samples=400):
    """Nodes on [breaks[0], breaks[-1]] that contain every break point and whose
    spacing follows the size function `size(s)` (mm).  In each interval the
    number of cells is round(int 1/size ds) (at least min_cells) and the
    nodes equidistribute int 1/size ds."""
    out = [float(breaks[0])]
    for a, b in zip(breaks[:-1], breaks[1:]):
        s = np.linspace(a, b, samples + 1)
        f = 1.0 / np.array([size(t) for t in s])
        cum = np.concatenate([[0.0], np.cumsum(0.5 * (f[1:] + f[:-1]) * np.diff(s))])
        n = max(min_cells, int(round(cum[-1])))
        targets = np.linspace(0.0, cum[-1], n + 1)[1:]
        pts = np.interp(targets, cum, s)
        pts[-1] = b
        out.extend(pts.tolist())
    return np.array(out)


def size_near(points, h_fine, h_coarse, half_width, growth):
    """Size function: h_fine within half_width of any of `points`, growing
    linearly (slope `growth`) outside, capped at h_coarse."""
    pts = np.atleast_1d(points)

    def f(s):
        d = max(0.0, float(np.min(np.abs(pts - s))) - half_width)
        return min(h_coarse, h_fine + growth * d)

    return f


# --------------------------------------------------------------------------
# bodies
# --------------------------------------------------------------------------
class Block:
    def __init__(self, X, faces=None, cell_mask=None):
        X = np.asarray(X, dtype=float)
        assert X.ndim == 4 and X.shape[3] == 3, X.shape
        self.X = X
        self.faces = dict(faces or {})
        for f in self.faces:
            assert f in FACES, f
        self.cell_mask = cell_mask


class Body:
    """A union of blocks with a physical volume name."""

    def __init__(self, name):
        self.name = name
        self.blocks = []

    def add(self, X, faces=None, cell_mask=None):
        self.blocks.append(Block(X, faces, cell_mask))

    def assemble(self, tol=1e-7):
        """Return nodes (N,3), hexes (M,8) (0-based, gmsh order, positive
        Jacobian), and {surface name: quads (K,4)} with outward orientation."""
        coords, hexes, faces = [], [], []
        offset = 0
        for b in self.blocks:
            X = b.X
            ni, nj, nk = X.shape[:3]
            idx = np.arange(ni * nj * nk).reshape(ni, nj, nk) + offset
            coords.append(X.reshape(-1, 3))
            mask = b.cell_mask if b.cell_mask is not None else np.ones((ni - 1, nj - 1, nk - 1), bool)
            cells = []
            for di, dj, dk in HEX_CORNERS:
                cells.append(idx[di : ni - 1 + di, dj : nj - 1 + dj, dk : nk - 1 + dk])
            cells = np.stack(cells, axis=-1)  # (ni-1, nj-1, nk-1, 8)
            hexes.append(cells[mask])
            for fname, group in b.faces.items():
                if group is None:
                    continue
                axis, side = FACES[fname]
                sl = [slice(None)] * 3
                sl[axis] = 0 if side == 0 else -1
                fidx = idx[tuple(sl)]  # 2D array of node ids on the face
                # which cells are adjacent to the face (respect the mask)
                csl = [slice(None)] * 3
                csl[axis] = 0 if side == 0 else -1
                cmask = mask[tuple(csl)]
                a, c = fidx.shape
                q = np.stack([fidx[:-1, :-1], fidx[1:, :-1], fidx[1:, 1:], fidx[:-1, 1:]], axis=-1)
                faces.append((group, q[cmask]))
            offset += ni * nj * nk
        coords = np.concatenate(coords)
        # merge coincident nodes
        key = np.round(coords / tol).astype(np.int64)
        _, first, inverse = np.unique(key, axis=0, return_index=True, return_inverse=True)
        inverse = inverse.reshape(-1)
        nodes = coords[first]
        hexes = inverse[np.concatenate(hexes)]
        used = np.unique(hexes)
        renum = -np.ones(len(nodes), np.int64)
        renum[used] = np.arange(len(used))
        nodes = nodes[used]
        hexes = renum[hexes]
        check_no_near_duplicates(nodes, 1e3 * tol)
        hexes = orient_hexes(nodes, hexes)
        surfaces = {}
        for group, q in faces:
            q = renum[inverse[q]]
            surfaces.setdefault(group, []).append(q)
        surfaces = {g: np.concatenate(v) for g, v in surfaces.items()}
        surfaces = {g: orient_quads_outward(nodes, hexes, q) for g, q in surfaces.items()}
        return nodes, hexes, surfaces


def check_no_near_duplicates(nodes, dist):
    """Fail if two distinct nodes are closer than dist (a missed merge)."""
    key = np.floor(nodes / dist).astype(np.int64)
    order = np.lexsort(key.T[::-1])
    k = key[order]
    same = np.all(k[1:] == k[:-1], axis=1)
    if np.any(same):
        i = order[1:][same][0]
        raise RuntimeError("nodes closer than %g mm near %s" % (dist, nodes[i]))


def corner_jacobians(nodes, hexes):
    x = nodes[hexes]  # (M, 8, 3)
    nb = ((1, 3, 4), (2, 0, 5), (3, 1, 6), (0, 2, 7), (7, 5, 0), (4, 6, 1), (5, 7, 2), (6, 4, 3))
    dets = []
    for c, (i, j, k) in enumerate(nb):
        e1, e2, e3 = x[:, i] - x[:, c], x[:, j] - x[:, c], x[:, k] - x[:, c]
        d = np.einsum("ij,ij->i", e1, np.cross(e2, e3))
        n = np.linalg.norm(e1, axis=1) * np.linalg.norm(e2, axis=1) * np.linalg.norm(e3, axis=1)
        dets.append(d / n)
    return np.stack(dets, axis=1)


def orient_hexes(nodes, hexes):
    x = nodes[hexes]
    # Jacobian at the centre
    a = x[:, 1] + x[:, 2] + x[:, 5] + x[:, 6] - x[:, 0] - x[:, 3] - x[:, 4] - x[:, 7]
    b = x[:, 2] + x[:, 3] + x[:, 6] + x[:, 7] - x[:, 0] - x[:, 1] - x[:, 4] - x[:, 5]
    c = x[:, 4] + x[:, 5] + x[:, 6] + x[:, 7] - x[:, 0] - x[:, 1] - x[:, 2] - x[:, 3]
    d = np.einsum("ij,ij->i", a, np.cross(b, c))
    flip = d < 0
    hexes = hexes.copy()
    hexes[flip] = hexes[flip][:, [0, 3, 2, 1, 4, 7, 6, 5]]
    q = corner_jacobians(nodes, hexes)
    if np.any(q <= 0):
        bad = np.argwhere(q <= 0)[0][0]
        raise RuntimeError(
            "%d hexahedra with non-positive corner Jacobian, e.g. at %s"
            % (int(np.sum(np.any(q <= 0, axis=1))), nodes[hexes[bad]].mean(axis=0))
        )
    return hexes


HEX_FACES = ((0, 3, 2, 1), (0, 1, 5, 4), (0, 4, 7, 3), (1, 2, 6, 5), (2, 3, 7, 6), (4, 5, 6, 7))


def orient_quads_outward(nodes, hexes, quads):
    """Order each boundary quad so that its normal points out of its hex."""
    owner = {}
    for h, conn in enumerate(hexes):
        for f in HEX_FACES:
            owner.setdefault(frozenset(conn[list(f)].tolist()), []).append(h)
    out = quads.copy()
    for n, q in enumerate(quads):
        hs = owner.get(frozenset(q.tolist()))
        if hs is None or len(hs) != 1:
            raise RuntimeError("tagged quad %s is not a boundary face" % (nodes[q].mean(axis=0),))
        centre = nodes[hexes[hs[0]]].mean(axis=0)
        p = nodes[q]
        normal = np.cross(p[2] - p[0], p[3] - p[1])
        if np.dot(normal, p.mean(axis=0) - centre) < 0:
            out[n] = q[::-1]
    return out


def hex_volumes(nodes, hexes):
    """Exact volumes of trilinear hexahedra (2x2x2 Gauss)."""
    x = nodes[hexes]
    g = 0.5 / math.sqrt(3.0)
    vol = np.zeros(len(hexes))
    corners = np.array(HEX_CORNERS, float)
    for a in (0.5 - g, 0.5 + g):
        for b in (0.5 - g, 0.5 + g):
            for c in (0.5 - g, 0.5 + g):
                p = np.array([a, b, c])
                f = np.where(corners == 1, p, 1 - p)  # (8,3)
                s = np.where(corners == 1, 1.0, -1.0)
                da = s[:, 0] * f[:, 1] * f[:, 2]
                db = f[:, 0] * s[:, 1] * f[:, 2]
                dc = f[:, 0] * f[:, 1] * s[:, 2]
                ja = np.einsum("k,mkd->md", da, x)
                jb = np.einsum("k,mkd->md", db, x)
                jc = np.einsum("k,mkd->md", dc, x)
                vol += np.einsum("ij,ij->i", ja, np.cross(jb, jc)) / 8.0
    return vol


# --------------------------------------------------------------------------
# output
# --------------------------------------------------------------------------
BODY_SURFACES = {"femur": ("femur_contact", "femur_fixation"), "tibia": ("tibia_contact", "tibia_inferior")}


def write_msh(path, bodies, title="tkr-wear"):
    """bodies: {'femur': (nodes, hexes, surfaces), 'tibia': (...)}.
    Writes ASCII msh 4.1 through the gmsh API."""
    import gmsh

    gmsh.initialize(["gmsh", "-v", "2"])
    try:
        gmsh.model.add(title)
        node_offset = 0
        elem_offset = 0
        vtag = {}
        for name in ("tibia", "femur"):
            nodes, hexes, surfaces = bodies[name]
            t = gmsh.model.addDiscreteEntity(3)
            vtag[name] = t
            tags = np.arange(1, len(nodes) + 1) + node_offset
            gmsh.model.mesh.addNodes(3, t, tags, nodes.reshape(-1))
            etags = np.arange(1, len(hexes) + 1) + elem_offset
            gmsh.model.mesh.addElementsByType(t, 5, etags, (hexes + 1 + node_offset).reshape(-1))
            elem_offset += len(hexes)
            p = gmsh.model.addPhysicalGroup(3, [t])
            gmsh.model.setPhysicalName(3, p, name)
            for sname in BODY_SURFACES[name]:
                q = surfaces[sname]
                s = gmsh.model.addDiscreteEntity(2)
                etags = np.arange(1, len(q) + 1) + elem_offset
                gmsh.model.mesh.addElementsByType(s, 3, etags, (q + 1 + node_offset).reshape(-1))
                elem_offset += len(q)
                p = gmsh.model.addPhysicalGroup(2, [s])
                gmsh.model.setPhysicalName(2, p, sname)
            node_offset += len(nodes)
        gmsh.option.setNumber("Mesh.MshFileVersion", 4.1)
        gmsh.option.setNumber("Mesh.Binary", 0)
        gmsh.option.setNumber("Mesh.SaveAll", 0)
        gmsh.write(path)
    finally:
        gmsh.finalize()


def summary(bodies):
    out = {}
    for name, (nodes, hexes, surfaces) in bodies.items():
        q = corner_jacobians(nodes, hexes)
        out[name] = dict(
            vertices=len(nodes),
            hexahedra=len(hexes),
            volume=float(hex_volumes(nodes, hexes).sum()),
            min_quality=float(q.min()),
            quads={k: len(v) for k, v in surfaces.items()},
        )
    return out


def vertical_gap(points, nodes, quads, cell=2.0):
    """For each point, the signed vertical distance z_surface - z_point to the
    piecewise-bilinear surface `quads` (split into 4 triangles about the quad
    centre) directly above/below it; nan where the surface does not cover the
    point.  Used to report the discrete initial gap / overlap of the bodies."""
    P = nodes[quads]  # (K,4,3)
    c = P.mean(axis=1)
    tris = []
    for i in range(4):
        tris.append(np.stack([P[:, i], P[:, (i + 1) % 4], c], axis=1))
    T = np.concatenate(tris)  # (4K,3,3)
    lo = T[:, :, :2].min(axis=1)
    hi = T[:, :, :2].max(axis=1)
    buckets = {}
    for t in range(len(T)):
        for bx in range(int(math.floor(lo[t, 0] / cell)), int(math.floor(hi[t, 0] / cell)) + 1):
            for by in range(int(math.floor(lo[t, 1] / cell)), int(math.floor(hi[t, 1] / cell)) + 1):
                buckets.setdefault((bx, by), []).append(t)
    out = np.full(len(points), np.nan)
    for n, p in enumerate(points):
        cand = buckets.get((int(math.floor(p[0] / cell)), int(math.floor(p[1] / cell))), [])
        best = np.nan
        for t in cand:
            a, b, cc = T[t]
            d = (b[1] - cc[1]) * (a[0] - cc[0]) + (cc[0] - b[0]) * (a[1] - cc[1])
            if abs(d) < 1e-14:
                continue
            l1 = ((b[1] - cc[1]) * (p[0] - cc[0]) + (cc[0] - b[0]) * (p[1] - cc[1])) / d
            l2 = ((cc[1] - a[1]) * (p[0] - cc[0]) + (a[0] - cc[0]) * (p[1] - cc[1])) / d
            l3 = 1 - l1 - l2
            if min(l1, l2, l3) >= -1e-12:
                z = l1 * a[2] + l2 * b[2] + l3 * cc[2]
                g = z - p[2]
                if np.isnan(best) or abs(g) < abs(best):
                    best = g
        out[n] = best
    return out
