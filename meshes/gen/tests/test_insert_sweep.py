# SPDX-License-Identifier: LGPL-2.1-or-later
"""insert_sweep.mesh_insert() on an insert whose geometry is known in
closed form: the box 40 x 30 x 10 mm (x, y, z; base at z = 0) with a
cylindrical trough along x cut into its top, radius R = 30 mm, DEPTH = 3 mm
deep at y = 0 (an OpenCASCADE model, as a STEP file gives it).

The top is the height field z(y) = ZC - sqrt(R^2 - y^2) for |y| < HALF_WIDTH,
else 10 mm, with ZC = 10 + R - DEPTH and HALF_WIDTH = sqrt(R^2 - (R -
DEPTH)^2); the volume is the box's less L times the circular segment's area
R^2 acos((R - DEPTH) / R) - (R - DEPTH) HALF_WIDTH.
"""
import functools
import math

import numpy as np
import pytest

import blockmesh
import gmsh
import insert_sweep

L, W, H = 40.0, 30.0, 10.0
R, DEPTH = 30.0, 3.0
ZC = H + R - DEPTH
HALF_WIDTH = math.sqrt(R**2 - (R - DEPTH) ** 2)
SIZE, CELLS, TOP_CELL = 2.0, 6, 1.0  # mesh-implant's defaults (--sweep-*)


def top_height(y):
    trough = ZC - np.sqrt(np.maximum(R**2 - y**2, 0.0))
    return np.where(np.abs(y) < HALF_WIDTH, trough, H)


@functools.lru_cache(maxsize=None)
def sweep(size):
    """(nodes, hexes, surfaces) of the insert swept with plan cells of about
    `size` mm; the trough's face is tibia_contact, the base tibia_inferior,
    the other faces have no group."""
    gmsh.initialize(["gmsh", "-v", "0"])
    try:
        gmsh.model.add("insert")
        block = gmsh.model.occ.addBox(-L / 2, -W / 2, 0.0, L, W, H)
        cylinder = gmsh.model.occ.addCylinder(-L / 2 - 1.0, 0.0, ZC, L + 2.0, 0.0, 0.0, R)
        out, _ = gmsh.model.occ.cut([(3, block)], [(3, cylinder)])
        gmsh.model.occ.synchronize()
        groups = {}
        for _, s in gmsh.model.getBoundary(out, oriented=False):
            if gmsh.model.getType(2, abs(s)) == "Cylinder":
                groups[abs(s)] = "tibia_contact"
            elif gmsh.model.getBoundingBox(2, abs(s))[5] < 1e-3:
                groups[abs(s)] = "tibia_inferior"
        assert sorted(groups.values()) == ["tibia_contact", "tibia_inferior"]
        gmsh.option.setNumber("Mesh.MeshSizeMax", size)
        gmsh.option.setNumber("Mesh.MeshSizeMin", 0.0)
        gmsh.model.mesh.generate(2)
        return insert_sweep.mesh_insert(out[0][1], groups, size, CELLS, TOP_CELL, True)
    finally:
        gmsh.finalize()


def columns(nodes):
    """The node indices per plan point, bottom to top (one row each)."""
    _, column = np.unique(np.round(nodes[:, :2], 6), axis=0, return_inverse=True)
    return np.lexsort((nodes[:, 2], column.ravel())).reshape(-1, CELLS + 1)


def test_columns_stand_on_the_base_and_end_on_the_top():
    nodes, hexes, surfaces = sweep(SIZE)
    z = nodes[columns(nodes), 2]
    assert len(hexes) == CELLS * len(surfaces["tibia_inferior"])
    assert np.all(np.diff(z, axis=1) > 0)
    assert np.abs(z[:, 0]).max() < 1e-12  # every foot on the base
    # every top node on the analytic top (vertical Newton projection onto
    # the CAD face), to round-off
    top = columns(nodes)[:, -1]
    assert np.allclose(nodes[top, 2], top_height(nodes[top, 1]), rtol=0, atol=1e-9)
    # graded so that the top cell is TOP_CELL thick where the insert is thinnest
    thinnest = np.argmin(z[:, -1] - z[:, 0])
    assert z[thinnest, -1] - z[thinnest, -2] == pytest.approx(TOP_CELL, abs=1e-6)


def test_base_and_contact_groups():
    nodes, hexes, surfaces = sweep(SIZE)
    base = nodes[surfaces["tibia_inferior"]]
    diagonals = np.cross(base[:, 2] - base[:, 0], base[:, 3] - base[:, 1])
    assert 0.5 * np.linalg.norm(diagonals, axis=1).sum() == pytest.approx(L * W, rel=1e-12)
    assert np.all(diagonals[:, 2] < 0)  # facing down (outward)
    # a top quadrangle is tibia_contact when its centre is above the trough
    contact = nodes[surfaces["tibia_contact"]].mean(axis=1)
    assert np.all(np.abs(contact[:, 1]) < HALF_WIDTH)
    above = np.abs(base.mean(axis=1)[:, 1]) < HALF_WIDTH
    assert len(contact) == above.sum()


def test_volume_converges_to_the_exact_one():
    """The hexahedra's volume against the exact one.  The mesh's top
    interpolates the exact heights at its nodes, so the error is of second
    order in the plan size (the trough's curvature; the rims of the trough,
    not aligned with the grid, cut an h-wide strip by O(h)): it must fall
    by more than 3 when the size halves from 4 to 2 mm (measured: 44.0 and
    8.8 mm^3, 0.45 % and 0.09 % of the exact volume), and be under 0.2 % at
    2 mm."""
    segment = R**2 * math.acos((R - DEPTH) / R) - (R - DEPTH) * HALF_WIDTH
    exact = L * W * H - L * segment
    error = {}
    for size in (2 * SIZE, SIZE):
        nodes, hexes, _ = sweep(size)
        error[size] = blockmesh.hex_volumes(nodes, hexes).sum() - exact
    assert abs(error[SIZE]) < abs(error[2 * SIZE]) / 3
    assert abs(error[SIZE]) < 0.002 * exact
