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


# ------------------------------------------------------------- issue 50
def rectangle_wire(x0, y0, z, dx, dy):
    """A wire around the rectangle [x0, x0 + dx] x [y0, y0 + dy] at height z,
    and its plane surface (to remove once lofted)."""
    r = gmsh.model.occ.addRectangle(x0, y0, z, dx, dy)
    gmsh.model.occ.synchronize()
    curves = [abs(c) for _, c in gmsh.model.getBoundary([(2, r)], oriented=True)]
    return gmsh.model.occ.addWire(curves), r


def frustum(lo, hi, z0, z1):
    """The solid ruled between the rectangles lo and hi ((x0, y0, dx, dy))
    at heights z0 and z1."""
    w0, r0 = rectangle_wire(*lo[:2], z0, *lo[2:])
    w1, r1 = rectangle_wire(*hi[:2], z1, *hi[2:])
    out = gmsh.model.occ.addThruSections([w0, w1], makeSolid=True, makeRuled=True)
    gmsh.model.occ.remove([(2, r0), (2, r1)])
    return [dt for dt in out if dt[0] == 3]


def sweep_model(build, size=SIZE, **kwargs):
    """mesh_insert() on the OpenCASCADE solid that build() makes in a new
    model, its faces grouped as mesh-implant's rule does for CAD (n_z >
    0.3: tibia_contact; n_z < -0.9 at the lowest point: tibia_inferior).
    Returns (nodes, hexes, surfaces, report lines, the solid's volume)."""
    gmsh.initialize(["gmsh", "-v", "0"])
    try:
        gmsh.model.add("insert")
        vol = build()
        gmsh.model.occ.synchronize()
        groups = {}
        for _, s in gmsh.model.getBoundary([(3, vol)], oriented=False):
            s = abs(s)
            box = gmsh.model.getBoundingBox(2, s)
            uv = gmsh.model.getParametrization(2, s, [(box[0] + box[3]) / 2, (box[1] + box[4]) / 2, box[5]])
            n = gmsh.model.getNormal(s, uv)
            if box[5] < 1e-6:
                groups[s] = "tibia_inferior"
            elif abs(n[2]) > 0.3 and box[2] > 1e-6:
                groups[s] = "tibia_contact"
        gmsh.option.setNumber("Mesh.MeshSizeMax", size)
        gmsh.option.setNumber("Mesh.MeshSizeMin", 0.0)
        gmsh.model.mesh.generate(2)
        log = []
        out = insert_sweep.mesh_insert(vol, groups, size, CELLS, TOP_CELL, True, log=log, **kwargs)
        return out + (log, gmsh.model.occ.getMass(3, vol))
    finally:
        gmsh.finalize()


def drafted(draft):
    """The trough box of sweep() with side walls drafted by `draft` deg
    (outward normals above the horizontal: +, the seat wider than the top):
    ruled from the box's outline at the top to the outline offset by
    H tan(draft) at the seat."""

    def build():
        d = H * math.tan(math.radians(draft))
        body = frustum((-L / 2 - d, -W / 2 - d, L + 2 * d, W + 2 * d), (-L / 2, -W / 2, L, W), 0.0, H)
        cylinder = gmsh.model.occ.addCylinder(-L / 2 - 10.0, 0.0, ZC, L + 20.0, 0.0, 0.0, R)
        out, _ = gmsh.model.occ.cut(body, [(3, cylinder)])
        return out[0][1]

    return build


@pytest.mark.parametrize("draft", [15.0, -15.0])
def test_drafted_walls(draft):
    """Walls drafted either way (issue 50): the columns stand on the seat
    plane under the top's outline, every foot at z = 0, every top node on
    the exact top; the outline follows the top's edge, which the trough
    moves along the drafted end walls: x_end(y) = L/2 + (H - top(y))
    tan(draft), so the swept volume is the integral of 2 x_end(y) top(y)
    over |y| < W/2 (the mesh within 0.5 % of it: 0.25-0.31 % measured, the
    chords of the outline and its rounded corners); tibia_inferior is the
    seat only (under an overhanging top the feet beyond the seat carry no
    tray); the report gives the draft and both volumes."""
    nodes, hexes, surfaces, log, solid = sweep_model(drafted(draft))
    tan = math.tan(math.radians(draft))
    z = nodes[columns(nodes), 2]
    assert np.all(np.diff(z, axis=1) > 0)
    assert np.abs(z[:, 0]).max() < 1e-12
    top = columns(nodes)[:, -1]
    inner = np.abs(nodes[top, 0]) < L / 2 - 1.0
    assert np.allclose(nodes[top[inner], 2], top_height(nodes[top[inner], 1]), rtol=0, atol=1e-9)
    # (on the outline: a node just beyond the top's edge (the smoothing)
    # takes the height of the trough's face at its boundary)
    assert np.allclose(nodes[top, 2], top_height(nodes[top, 1]), rtol=0, atol=0.02)
    # the footprint: |y| <= W/2 and |x| <= x_end(y) (on the outline to the
    # chords of the top's 2 mm triangles, the smoothing over 0.5 mm)
    x_end = L / 2 + (H - top_height(nodes[:, 1])) * tan
    assert np.all(np.abs(nodes[:, 1]) <= W / 2 + 1e-6)
    assert np.all(np.abs(nodes[:, 0]) <= x_end + 0.05)
    y = np.linspace(-W / 2, W / 2, 200001)
    f = 2 * (L / 2 + (H - top_height(y)) * tan) * top_height(y)
    swept = float(np.sum(0.5 * (f[1:] + f[:-1]) * np.diff(y)))
    volume = blockmesh.hex_volumes(nodes, hexes).sum()
    assert volume == pytest.approx(swept, rel=5e-3)
    # tibia_inferior: under the seat only
    base = nodes[surfaces["tibia_inferior"]]
    seat = (L + 2 * H * tan, W + 2 * H * tan)
    centres = base.mean(axis=1)
    assert np.all(np.abs(centres[:, 0]) < seat[0] / 2) and np.all(np.abs(centres[:, 1]) < seat[1] / 2)
    area = 0.5 * np.linalg.norm(np.cross(base[:, 2] - base[:, 0], base[:, 3] - base[:, 1]), axis=1).sum()
    if draft > 0:  # the whole footprint
        g = 2 * (L / 2 + (H - top_height(y)) * tan)
        assert area == pytest.approx(np.sum(0.5 * (g[1:] + g[:-1]) * np.diff(y)), rel=5e-3)  # chords, corners
    else:  # the quadrangles whose centres are over the seat: its area to half a cell along its outline
        assert abs(area - seat[0] * seat[1]) < (seat[0] + seat[1]) * SIZE
    line = [s for s in log if s.startswith("insert: swept from its articular surface")]
    assert len(line) == 1
    assert "draft %+.1f deg" % draft in line[0]
    assert "meshed volume %.1f mm^3, input %.1f mm^3" % (volume, solid) in line[0]


def with_post(post_draft):
    """A box 60 x 40 x 10 mm with the trough of sweep() at y = -8 and a post
    on the plateau behind it: a frustum on the rectangle |x| < 5, 8 < y <
    16 from z = 9 (inside the box) up to 20, its walls drafted by post_draft deg (the top
    narrower)."""

    def build():
        occ = gmsh.model.occ
        box = occ.addBox(-30.0, -20.0, 0.0, 60.0, 40.0, H)
        cylinder = occ.addCylinder(-40.0, -8.0, ZC, 80.0, 0.0, 0.0, R)
        out, _ = occ.cut([(3, box)], [(3, cylinder)])
        t = 11.0 * math.tan(math.radians(post_draft))
        post = frustum(
            (-5.0, 8.0, 10.0, 8.0), (-5.0 + t, 8.0 + t, 10.0 - 2 * t, 8.0 - 2 * t), H - 1.0, H + 10.0
        )
        out, _ = occ.fuse(out, post)
        return [t for d, t in out if d == 3][0]

    return build


def test_post_kept_or_left_out():
    """A post with vertical walls is swept as a raised feature; the same
    post with walls drafted by 15 deg cannot be, and is left out when the
    femur stays farther than the contact distance from it (the columns
    under it end on the plateau around it, z = 10, interpolated), refused
    (Refused, naming --contact-distance) when it comes nearer or when
    there is no femur to tell."""
    nodes, hexes, surfaces, log, _ = sweep_model(with_post(0.0))
    assert nodes[:, 2].max() == pytest.approx(H + 10.0)
    assert any("swept as a raised feature" in s for s in log)

    far = lambda P, ins: (np.full(len(P), 12.5), np.zeros(len(P)))  # noqa: E731
    nodes, hexes, surfaces, log, solid = sweep_model(with_post(15.0), clearance=far)
    assert nodes[:, 2].max() < H + 1e-6  # no post
    under = (np.abs(nodes[:, 0]) < 5.0) & (nodes[:, 1] > 8.0) & (nodes[:, 1] < 16.0)
    top = columns(nodes)[:, -1]
    assert np.abs(nodes[top[under[top]], 2] - H).max() < 0.05
    note = [s for s in log if "left out" in s]
    assert len(note) == 1 and "no closer than 12.50 mm" in note[0] and "draft +15.0 deg" in note[0]
    assert blockmesh.hex_volumes(nodes, hexes).sum() < solid

    near = lambda P, ins: (np.full(len(P), 1.0), np.full(len(P), 30.0))  # noqa: E731
    with pytest.raises(insert_sweep.Refused, match="within 1.00 mm of it at 30 deg.*--contact-distance 3 mm"):
        sweep_model(with_post(15.0), clearance=near)
    with pytest.raises(insert_sweep.Refused, match="no femur"):
        sweep_model(with_post(15.0))
