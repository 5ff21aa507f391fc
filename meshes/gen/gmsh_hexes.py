# SPDX-License-Identifier: LGPL-2.1-or-later
"""The hexahedral mesh gmsh made of a volume (tetrahedra split into
hexahedra, Mesh.SubdivisionAlgorithm = 2), as blockmesh.write_msh wants it;
shared by mesh_implant.py and unstructured.py."""

import numpy as np

import blockmesh

import gmsh


def extract(vol, groups, label):
    """Nodes, hexahedra and tagged quadrangles of volume `vol` of the current
    gmsh model. groups maps each boundary surface tag to its group name (or
    None: not written); label names the body in error messages. Returns
    (nodes, hexes, surfaces), renumbered to the used nodes and oriented
    (hexahedra positive, quadrangles outward)."""
    tags, coords, _ = gmsh.model.mesh.getNodes()
    X = np.zeros((int(tags.max()) + 1, 3))
    X[tags.astype(np.int64)] = coords.reshape(-1, 3)
    hexes = []
    for et, _, nt in zip(*gmsh.model.mesh.getElements(3, vol)):
        if et != 5:
            raise SystemExit("error: meshing %s left elements of type %d" % (label, et))
        hexes.append(np.array(nt, dtype=np.int64).reshape(-1, 8))
    hexes = np.concatenate(hexes)
    quads = {}
    for s, g in groups.items():
        if g is None:
            continue
        for et, _, nt in zip(*gmsh.model.mesh.getElements(2, s)):
            if et != 3:
                raise SystemExit("error: surface %d of %s has elements of type %d" % (s, label, et))
            quads.setdefault(g, []).append(np.array(nt, dtype=np.int64).reshape(-1, 4))
    used = np.unique(hexes)
    renum = -np.ones(len(X), np.int64)
    renum[used] = np.arange(len(used))
    nodes = X[used]
    hexes = blockmesh.orient_hexes(nodes, renum[hexes])
    surfaces = {
        g: blockmesh.orient_quads_outward(nodes, hexes, renum[np.concatenate(q)]) for g, q in quads.items()
    }
    return nodes, hexes, surfaces
