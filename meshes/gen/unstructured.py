#!/usr/bin/env python3
"""Unstructured verification meshes: tetrahedra split into hexahedra, as
scripts/mesh-implant makes them, for the geometries of the patch test and the
Hertz sphere (meshes/verification/*-unstructured.msh).

    unstructured.py [NAME ...]      (NAME: patch, sphere, implant; default all)

Each body is meshed alone with gmsh's Delaunay tetrahedra and every tetrahedron
is split into four hexahedra (Mesh.SubdivisionAlgorithm = 2; new boundary nodes
lie on the CAD surfaces).  So the hexahedra are warped, their faces are
unstructured quadrilaterals of different size and orientation, and the two
contact surfaces are non-matching -- the situation of a user's own implant.

* patch-unstructured: the patch test geometry (doc/geometry.md): tibia
  [0, 20]^2 x [-10, 0], femur [0, 20]^2 x [0, 6], touching at z = 0;
  tetrahedra of 4 mm (tibia) and 3 mm (femur).
* sphere-unstructured: the Hertz sphere-on-block geometry of verification.py
  (R = 20 mm, gap 0.001 mm, block 60 x 60 x 30 mm); tetrahedra of h0 = 0.9 mm
  within 3 mm of the contact point, growing to 12 mm 25 mm away.
* tkr/tkr-a-implant.msh: scripts/mesh-implant with its default options on
  meshes/tkr/cad/tkr-a-{femur,insert}.step (the case of issue 11).

Physical groups and orientation follow DESIGN.md section 3; the files are
written and checked like all others (blockmesh.write_msh, check_msh.py).
"""
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
MESHES = os.path.dirname(HERE)
sys.path.insert(0, HERE)

import blockmesh  # noqa: E402
import gmsh_hexes  # noqa: E402
import verification  # noqa: E402

import gmsh  # noqa: E402

PATCH_L, PATCH_HT, PATCH_HF = 20.0, 10.0, 6.0
PATCH_SIZES = {"tibia": 4.0, "femur": 3.0}
SPHERE_H0, SPHERE_NEAR, SPHERE_HMAX, SPHERE_FAR = 1.0, 3.0, 12.0, 25.0


def _mesh_body(name, build, classify, size_min, size_max, point=None, near=0.0, far=1.0):
    """Mesh the volume made by build() in a new gmsh model: tetrahedra (size
    size_min within `near` of `point`, growing linearly to size_max at `far`;
    uniform size_min without a point), split into hexahedra.  classify(s) maps
    a surface tag to a group name or None.  Returns (nodes, hexes, surfaces)
    as blockmesh.write_msh wants them."""
    gmsh.model.add(name)
    vol = build()
    gmsh.model.occ.synchronize()
    groups = {}
    for _, s in gmsh.model.getBoundary([(3, vol)], oriented=False):
        groups[abs(s)] = classify(abs(s))
    if point is not None:
        p = gmsh.model.occ.addPoint(*point)
        gmsh.model.occ.synchronize()
        f = gmsh.model.mesh.field.add("Distance")
        gmsh.model.mesh.field.setNumbers(f, "PointsList", [p])
        t = gmsh.model.mesh.field.add("Threshold")
        gmsh.model.mesh.field.setNumber(t, "InField", f)
        gmsh.model.mesh.field.setNumber(t, "SizeMin", size_min)
        gmsh.model.mesh.field.setNumber(t, "SizeMax", size_max)
        gmsh.model.mesh.field.setNumber(t, "DistMin", near)
        gmsh.model.mesh.field.setNumber(t, "DistMax", far)
        gmsh.model.mesh.field.setAsBackgroundMesh(t)
        gmsh.option.setNumber("Mesh.MeshSizeExtendFromBoundary", 0)
        gmsh.option.setNumber("Mesh.MeshSizeFromPoints", 0)
        gmsh.option.setNumber("Mesh.MeshSizeFromCurvature", 0)
        gmsh.option.setNumber("Mesh.MeshSizeMin", 0.0)
    else:
        gmsh.option.setNumber("Mesh.MeshSizeMin", size_min)
    gmsh.option.setNumber("Mesh.MeshSizeMax", size_max)
    gmsh.option.setNumber("Mesh.Algorithm3D", 1)
    gmsh.option.setNumber("Mesh.SubdivisionAlgorithm", 2)
    gmsh.model.mesh.generate(3)

    nodes, hexes, surfaces = gmsh_hexes.extract(vol, groups, name)
    gmsh.model.remove()
    return nodes, hexes, surfaces


def _plane_classifier(rules):
    """Surface -> group for planar faces: rules is a list of
    (axis, value, group); a face whose bounding box is flat in `axis` at
    `value` gets `group`."""

    def classify(s):
        bb = gmsh.model.getBoundingBox(2, s)
        for axis, value, group in rules:
            if abs(bb[axis] - value) < 1e-6 and abs(bb[axis + 3] - value) < 1e-6:
                return group
        return None

    return classify


def make_patch():
    def tibia():
        return gmsh.model.occ.addBox(0, 0, -PATCH_HT, PATCH_L, PATCH_L, PATCH_HT)

    def femur():
        return gmsh.model.occ.addBox(0, 0, 0, PATCH_L, PATCH_L, PATCH_HF)

    tib = _mesh_body(
        "tibia",
        tibia,
        _plane_classifier([(2, 0.0, "tibia_contact"), (2, -PATCH_HT, "tibia_inferior")]),
        PATCH_SIZES["tibia"],
        PATCH_SIZES["tibia"],
    )
    fem = _mesh_body(
        "femur",
        femur,
        _plane_classifier([(2, 0.0, "femur_contact"), (2, PATCH_HF, "femur_fixation")]),
        PATCH_SIZES["femur"],
        PATCH_SIZES["femur"],
    )
    return {"femur": fem, "tibia": tib}


def make_sphere():
    R, gap, h_cap, r_side = verification.R, verification.GAP, verification.H_CAP, verification.R_SIDE
    W, D = verification.W, verification.D

    def tibia():
        return gmsh.model.occ.addBox(-W, -W, -D, 2 * W, 2 * W, D)

    def femur():
        occ = gmsh.model.occ
        ball = occ.addSphere(0, 0, R + gap, R)
        cylinder = occ.addCylinder(0, 0, gap - 1, 0, 0, h_cap + 2, r_side)
        out, _ = occ.intersect([(3, ball)], [(3, cylinder)])
        box = occ.addBox(-W, -W, gap - 1, 2 * W, 2 * W, h_cap + 1)
        out, _ = occ.intersect(out, [(3, box)])
        return out[0][1]

    def femur_groups(s):
        kind = gmsh.model.getType(2, s)
        if kind == "Sphere":
            return "femur_contact"
        if kind == "Plane":
            return "femur_fixation"
        return None

    tib = _mesh_body(
        "tibia",
        tibia,
        _plane_classifier([(2, 0.0, "tibia_contact"), (2, -D, "tibia_inferior")]),
        SPHERE_H0,
        SPHERE_HMAX,
        (0, 0, 0),
        SPHERE_NEAR,
        SPHERE_FAR,
    )
    fem = _mesh_body(
        "femur", femur, femur_groups, SPHERE_H0, SPHERE_HMAX, (0, 0, gap), SPHERE_NEAR, SPHERE_FAR
    )
    return {"femur": fem, "tibia": tib}


MAKERS = {"patch": make_patch, "sphere": make_sphere}


def volumes(name):
    if name == "patch":
        return {"femur": PATCH_L * PATCH_L * PATCH_HF, "tibia": PATCH_L * PATCH_L * PATCH_HT}
    return verification.make_sphere_volumes()


def write(name, path):
    gmsh.initialize(["gmsh", "-v", "1"])
    try:
        gmsh.option.setNumber("General.NumThreads", 1)
        bodies = MAKERS[name]()
    finally:
        gmsh.finalize()
    blockmesh.write_msh(path, bodies, "%s-unstructured" % name)
    return bodies


def make_implant(path=None):
    import mesh_implant

    cad = os.path.join(MESHES, "tkr", "cad")
    path = path or os.path.join(MESHES, "tkr", "tkr-a-implant.msh")
    mesh_implant.main(
        [
            "--femur",
            os.path.join(cad, "tkr-a-femur.step"),
            "--insert",
            os.path.join(cad, "tkr-a-insert.step"),
            "-o",
            path,
        ]
    )


def main(argv):
    names = [a for a in argv if not a.startswith("-")] or sorted(MAKERS) + ["implant"]
    for name in names:
        if name not in MAKERS and name != "implant":
            raise SystemExit("unstructured.py: unknown mesh %s (patch, sphere, implant)" % name)
    for name in names:
        if name == "implant":
            make_implant()
            continue
        path = os.path.join(MESHES, "verification", "%s-unstructured.msh" % name)
        bodies = write(name, path)
        s = blockmesh.summary(bodies)
        for b in ("femur", "tibia"):
            print(
                "%s %s: %d vertices, %d hexahedra, volume %.2f mm^3 (exact %.2f), "
                "min scaled corner Jacobian %.3f, quads %s"
                % (
                    name,
                    b,
                    s[b]["vertices"],
                    s[b]["hexahedra"],
                    s[b]["volume"],
                    volumes(name)[b],
                    s[b]["min_quality"],
                    s[b]["quads"],
                )
            )
        print(
            "wrote %s (%d Q1 DoFs)"
            % (os.path.relpath(path, MESHES), 3 * (s["femur"]["vertices"] + s["tibia"]["vertices"]))
        )
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
