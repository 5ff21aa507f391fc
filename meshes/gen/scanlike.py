#!/usr/bin/env python3
"""Scan-like STL test inputs for mesh-implant (issue 19): an implant body's
clean STL export turned into what users bring.

    scanlike.py IN.stl|IN.step OUT.stl [--seed S] [--subdivide K] [--noise MM]
                [--folds N] [--duplicates N] [--holes N] [--flip]
                [--units mm|m] [--rotation R11,...,R33]

A STEP input is first triangulated with edges of at most 1.5 mm (the
options of the STL exports of TKR A and B: a scanner sees the shape, not an
exporter's facets).  In this order: each triangle split into four K times (a fine, scanner-like
triangulation of the export's long CAD triangles); every vertex moved by
Gaussian noise of standard deviation MM along random directions (a scan's
measurement noise); N vertices (seeded, among vertices with at least five
neighbours) pushed past a neighbour along the surface so that their
triangles fold over their neighbours (self-intersections); N triangles
written twice; N triangles left out (holes); the whole orientation reversed
(--flip); the coordinates turned (x_file = R^T x_ours, i.e. the inverse of
mesh-implant's --rotation R) and written in metres (--units m).  Nothing is
tuned to one file: the same options make the inputs of TKR A, B and C.
"""
import argparse
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from mesh_implant import parse_rotation, read_stl, write_stl_binary  # noqa: E402


def indexed(tris):
    """Points and triangles (indices) of a soup, identical points merged."""
    pts, inv = np.unique(np.round(tris.reshape(-1, 3), 9), axis=0, return_inverse=True)
    return pts, inv.reshape(-1, 3)


def subdivide(pts, tri):
    """Each triangle into four at its edge midpoints."""
    edges = np.sort(np.concatenate([tri[:, [0, 1]], tri[:, [1, 2]], tri[:, [2, 0]]]), axis=1)
    uniq, inv = np.unique(edges, axis=0, return_inverse=True)
    mids = 0.5 * (pts[uniq[:, 0]] + pts[uniq[:, 1]])
    m = len(pts) + inv.reshape(3, -1).T  # midpoints of edges 01, 12, 20
    a, b, c = tri.T
    new = np.concatenate(
        [
            np.stack([a, m[:, 0], m[:, 2]], 1),
            np.stack([m[:, 0], b, m[:, 1]], 1),
            np.stack([m[:, 2], m[:, 1], c], 1),
            np.stack([m[:, 0], m[:, 1], m[:, 2]], 1),
        ]
    )
    return np.concatenate([pts, mids]), new


def fold(pts, tri, count, rng):
    """Push `count` vertices past a neighbour: their fans fold over."""
    nbrs = [set() for _ in range(len(pts))]
    for t in tri:
        for i in range(3):
            nbrs[t[i]].update((t[(i + 1) % 3], t[(i + 2) % 3]))
    candidates = [v for v in range(len(pts)) if len(nbrs[v]) >= 5]
    moved = []
    for v in rng.choice(candidates, size=count, replace=False):
        w = sorted(nbrs[v])[rng.integers(len(nbrs[v]))]
        pts[v] = pts[v] + 1.6 * (pts[w] - pts[v])
        moved.append(pts[v].copy())
    return moved


def triangulate_step(path, size=1.5):
    """The surface of a STEP file as triangles of at most `size` mm, 12 per
    full turn on curved faces (what a scanner sees of the shape: the
    options of tkr.export_cad's STL exports of TKR A and B)."""
    import gmsh

    gmsh.initialize(["gmsh", "-v", "0"])
    try:
        gmsh.model.occ.importShapes(path)
        gmsh.model.occ.synchronize()
        gmsh.option.setNumber("Mesh.MeshSizeMax", size)
        gmsh.option.setNumber("Mesh.MeshSizeFromCurvature", 12)
        gmsh.model.mesh.generate(2)
        X, T = surface_mesh(gmsh)
        return X[T]
    finally:
        gmsh.finalize()


def surface_mesh(gmsh):
    """The current gmsh model's nodes (indexed by tag) and its 3-node
    triangles as node indices."""
    tags, coords, _ = gmsh.model.mesh.getNodes()
    X = np.zeros((int(tags.max()) + 1, 3))
    X[tags.astype(np.int64)] = coords.reshape(-1, 3)
    tris = []
    for _, s in gmsh.model.getEntities(2):
        for et, _, nt in zip(*gmsh.model.mesh.getElements(2, s)):
            if et == 2:
                tris.append(np.array(nt, np.int64).reshape(-1, 3))
    return X, np.concatenate(tris)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("input")
    ap.add_argument("output")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--subdivide", type=int, default=1)
    ap.add_argument("--noise", type=float, default=0.01, help="mm")
    ap.add_argument("--folds", type=int, default=3)
    ap.add_argument("--duplicates", type=int, default=0)
    ap.add_argument("--holes", type=int, default=0)
    ap.add_argument("--flip", action="store_true")
    ap.add_argument("--units", choices=("mm", "m"), default="mm")
    ap.add_argument("--rotation", type=parse_rotation)
    a = ap.parse_args(argv)
    rng = np.random.default_rng(a.seed)
    pts, tri = indexed(
        read_stl(a.input) if not a.input.lower().endswith((".step", ".stp")) else triangulate_step(a.input)
    )
    for _ in range(a.subdivide):
        pts, tri = subdivide(pts, tri)
    pts = pts + a.noise * rng.standard_normal(pts.shape)
    moved = fold(pts, tri, a.folds, rng)
    soup = pts[tri]
    if a.duplicates:
        soup = np.concatenate([soup, soup[rng.choice(len(soup), a.duplicates, replace=False)]])
    if a.holes:
        soup = np.delete(soup, rng.choice(len(soup), a.holes, replace=False), axis=0)
    if a.flip:
        soup = soup[:, ::-1]
    if a.rotation is not None:
        soup = soup @ np.asarray(a.rotation)  # x_file = R^T x_ours
    if a.units == "m":
        soup = soup / 1000.0
    write_stl_binary(a.output, soup)
    print(
        "%s: %d triangles; folded vertices at %s"
        % (a.output, len(soup), ", ".join("(%.2f, %.2f, %.2f)" % tuple(p) for p in moved))
    )


if __name__ == "__main__":
    main()
