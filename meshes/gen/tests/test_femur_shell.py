# SPDX-License-Identifier: LGPL-2.1-or-later
"""femur_shell (the femoral component as its articular shell) on surfaces
known in closed form:

- the curved face of a half cylinder (radius R = 20 mm, an OpenCASCADE
  model, as a STEP file gives it), triangulated by triangulate_faces() and
  projected onto the CAD face: every hexahedron valid, the articular nodes
  on the cylinder, the fixation nodes on the coaxial cylinder of radius
  R - THICKNESS, the first cell layer as thin as the grading says;
- a spherical cap of radius 2 mm (smaller than the 3 mm asked): the columns
  thinned to at most half the radius, not through the centre;
- a concave trough (the inside of a cylinder, columns diverging): the full
  thickness everywhere.
"""
import math

import numpy as np
import pytest

import blockmesh
import contact_layer
import femur_shell
import gmsh
import mesh_implant

R, LENGTH = 20.0, 30.0
THICKNESS, LAYERS, RATIO = 3.0, 3, 1.5  # mesh-implant's defaults (--shell-*)


def radius_about_x(P):
    return np.hypot(P[:, 1], P[:, 2])


@pytest.fixture(scope="module")
def half_cylinder():
    """The shell under the curved face of the half cylinder |x| < LENGTH/2,
    y^2 + z^2 < R^2, z < 0 (the face is its outside, facing down as a
    femur's condyles do); returns (nodes, hexes, surfaces, notes)."""
    gmsh.initialize(["gmsh", "-v", "0"])
    try:
        gmsh.model.add("half-cylinder")
        cyl = gmsh.model.occ.addCylinder(-LENGTH / 2, 0, 0, LENGTH, 0, 0, R)
        box = gmsh.model.occ.addBox(-LENGTH, -2 * R, -2 * R, 2 * LENGTH, 4 * R, 2 * R)
        out, _ = gmsh.model.occ.intersect([(3, cyl)], [(3, box)])
        gmsh.model.occ.synchronize()
        vol = out[0][1]
        curved = [
            abs(s)
            for _, s in gmsh.model.getBoundary(out, oriented=False)
            if gmsh.model.getType(2, abs(s)) == "Cylinder"
        ]
        assert len(curved) == 1
        mesh_implant.generate_plain(3, 10.0)
        rows, _, _ = mesh_implant.face_table(vol)
        gmsh.model.mesh.clear()
        field = contact_layer.SizeField(np.array([[0.0, 0.0, -R]]), None, 2.0, 2.0, 10.0, 0.0)
        X, tris, face, curve_edges = femur_shell.triangulate_faces(
            curved, {s: rows[s]["outward"] for s in curved}, field, 2.0
        )
        notes = []
        nodes, hexes, surfaces = femur_shell.mesh_shell(
            X, tris, face, curve_edges, contact_layer.cad_projector(), THICKNESS, LAYERS, RATIO, notes
        )
        return nodes, hexes, surfaces, notes
    finally:
        gmsh.finalize()


def test_half_cylinder_cells_valid(half_cylinder):
    nodes, hexes, surfaces, notes = half_cylinder
    q = blockmesh.corner_jacobians(nodes, hexes).min(axis=1)
    assert q.min() > 0.3, q.min()
    assert notes == []  # nothing thinned or trimmed: R is 6.7 times the depth
    assert len(hexes) == LAYERS * len(surfaces["femur_contact"])


def test_half_cylinder_thickness(half_cylinder):
    nodes, _, surfaces, _ = half_cylinder
    outer = nodes[np.unique(surfaces["femur_contact"])]
    inner = nodes[np.unique(surfaces["femur_fixation"])]
    assert np.allclose(radius_about_x(outer), R, atol=1e-6)
    assert (outer[:, 2] <= 1e-6).all()
    # the columns are normal to the cylinder (smoothed normals of a
    # cylinder stay radial; at the straight borders they tilt slightly)
    assert np.allclose(radius_about_x(inner), R - THICKNESS, atol=0.01)


def test_half_cylinder_orientation_and_grading(half_cylinder):
    nodes, hexes, surfaces, _ = half_cylinder
    P = nodes[surfaces["femur_contact"]]
    n = np.cross(P[:, 2] - P[:, 0], P[:, 3] - P[:, 1])
    c = P.mean(axis=1)
    radial = np.column_stack([np.zeros(len(c)), c[:, 1], c[:, 2]])
    assert (np.einsum("ij,ij->i", n, radial) > 0).all()  # femur_contact faces outward
    P = nodes[surfaces["femur_fixation"]]
    n = np.cross(P[:, 2] - P[:, 0], P[:, 3] - P[:, 1])
    c = P.mean(axis=1)
    radial = np.column_stack([np.zeros(len(c)), c[:, 1], c[:, 2]])
    assert (np.einsum("ij,ij->i", n, radial) < 0).all()  # femur_fixation faces the axis
    # first layer: THICKNESS / (1 + RATIO + RATIO^2) deep
    first = THICKNESS / sum(RATIO**k for k in range(LAYERS))
    r = np.sort(np.unique(np.round(radius_about_x(nodes), 3)))
    assert abs((R - first) - r[r < R - 1e-3].max()) < 0.01


def spherical_cap(radius, rings=8, per_ring=24, polar=60.0, outward=True):
    """Triangles of a spherical cap about -z (nodes on the sphere),
    oriented with the normal away from the centre (outward=True: a convex
    articular surface) or towards it (a trough)."""
    from scipy.spatial import Delaunay

    pts = [[0.0, 0.0, -radius]]
    for i in range(1, rings + 1):
        t = math.radians(polar) * i / rings
        for j in range(per_ring):
            f = 2 * math.pi * (j + 0.5 * (i % 2)) / per_ring
            pts.append(
                [
                    radius * math.sin(t) * math.cos(f),
                    radius * math.sin(t) * math.sin(f),
                    -radius * math.cos(t),
                ]
            )
    pts = np.array(pts)
    tri = Delaunay(pts[:, :2]).simplices
    P = pts[tri]
    away = np.einsum("ij,ij->i", np.cross(P[:, 1] - P[:, 0], P[:, 2] - P[:, 0]), P.mean(axis=1)) > 0
    tri = np.where((away == outward)[:, None], tri, tri[:, ::-1])
    return pts, tri


def shell_on_sphere(radius, outward):
    X, T = spherical_cap(radius, outward=outward)

    def on_sphere(kind, tag, P):
        return radius * P / np.linalg.norm(P, axis=1)[:, None]

    notes = []
    out = femur_shell.mesh_shell(X, T, np.zeros(len(T), int), {}, on_sphere, THICKNESS, LAYERS, RATIO, notes)
    return out + (notes,)


def test_small_radius_thinned():
    radius = 2.0
    nodes, hexes, surfaces, notes = shell_on_sphere(radius, True)
    assert blockmesh.corner_jacobians(nodes, hexes).min() > 0.1
    inner = np.linalg.norm(nodes[np.unique(surfaces["femur_fixation"])], axis=1)
    assert inner.min() >= 0.45 * radius  # at most half the radius deep (and a bit of tilt)
    assert inner.max() <= radius - 0.05 * THICKNESS + 1e-9
    assert any("thinner than 3 mm" in n for n in notes)


def test_concave_full_thickness():
    radius = 20.0
    nodes, hexes, surfaces, notes = shell_on_sphere(radius, False)
    assert blockmesh.corner_jacobians(nodes, hexes).min() > 0.2
    inner = np.linalg.norm(nodes[np.unique(surfaces["femur_fixation"])], axis=1)
    assert np.allclose(inner, radius + THICKNESS, atol=0.01)  # the columns diverge: nothing thinned
    assert not any("thinner" in n for n in notes)
