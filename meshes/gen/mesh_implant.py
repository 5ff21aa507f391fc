#!/usr/bin/env python3
"""mesh-implant: tagged hexahedral two-body mesh from a femoral component and a
tibial insert given as STEP (or IGES/BREP) files or closed STL surfaces.

    scripts/mesh-implant --femur FEMUR.step --insert INSERT.stl -o knee.msh

Each body is meshed on its own; the two never share nodes.  --method:

  auto (default)   the insert swept from its articular surface: structured
                   columns under an O-grid of square cells (--sweep-size)
                   in plan, from the flat seat up to the top, a height
                   field over its outline, whatever the walls do (draft,
                   rounded rims, a locking recess: approximated, the volume
                   reported; a post kept if it sweeps fit for contact, else
                   left out where the femur never comes within
                   --contact-distance of it over -5..60 deg of flexion, else
                   refused; insert_sweep.py); if it has no flat seat or no
                   top, as "layer".  The femoral component as its articular
                   shell (--femur-mesh below).
  layer            a layer of prisms under the articular faces (--layers,
                   --layer-thickness, --layer-ratio) and tetrahedra inside,
                   each prism split into three hexahedra, each tetrahedron
                   into four (contact_layer.py); on a repaired STL surface
                   a layer that fails is tried again at half the depth,
                   then the body is meshed as "split" (reported).  The articular faces get
                   --contact-size where they are within --refine-distance of
                   the other body's articular faces.
  split            tetrahedra everywhere (refined towards the articular
                   faces), each split into four hexahedra by gmsh
                   (Mesh.SubdivisionAlgorithm = 2): the method before issue
                   18; its nodal contact pressures scatter.

--femur-mesh: shell (the default of auto; femur_shell.py): the femoral
component as hexahedra extruded inward from its articular surface
(femur_contact) only, --shell-thickness deep (thinner where the surface's
radius of curvature is smaller) in --shell-layers layers graded by
--shell-ratio, along the surface's own smoothed normals; the inner face is
femur_fixation (clamped by tkr-wear), the side walls are traction free.
The box, the pegs, the side walls and their sharp edges play no part
(CoCr is some 200 times stiffer than UHMWPE: the femur contributes the
shape of its articular surface).  layer and split (the defaults of those
--method values) mesh the whole component as above.

No impractical mesh is written (issue 50): more than --max-dofs Q1
displacement DoFs (default 200,000) or a hexahedron with a face on
femur_contact or tibia_contact of scaled corner Jacobian below
--min-contact-quality (default 0.1) ends mesh-implant with one error line
naming the body, the numbers, where the worst cell is and the options that
would help; nothing is written.

STL surfaces (both inputs STL; --surface remesh, the default; doc/geometry.md
"STL surfaces as they come"): each surface, in mm and our frame, is checked,
repaired and remeshed with edges of --surface-size by tkr-surface (CGAL;
apps/surface.cc: defects counted and located, soup repair, holes filled,
orientation, self-intersections removed locally or by an alpha wrap); its
triangles are tagged from the pair's geometry (surface_tags.py: femur_contact
= what faces and comes within --contact-distance of the insert as the femur
flexes -5..60 deg about its estimated axis, tibia_contact = the insert's
upward triangles near it, tibia_inferior = its downward triangles (n_z <
-0.3) below three quarters of the articular zone's height (a rounded rim's
lower half, a locking recess's floor; of those the mesh's tibia_inferior
keeps the seat only, the quadrangles within 0.05 mm of the plane through the
lowest ones: the rigid tray needs it flat), femur_fixation by the normal rule
below), or from --femur-contact-stl/--insert-contact-stl patches; the
surface is remeshed again (--contact-size on the contact triangles, --size/2
elsewhere; for the femur, and the insert with --method layer, smaller, down
to 0.56 --contact-size, while the result strays from the repaired surface by
more than half --layer-thickness or folds),
split into smooth patches at --patch-angle, each patch given the group most
of it has (contact if a quarter of its area is; a patch that joins contact
and the other group, or has 5-25 % contact, split again at half the angle,
twice; a patch whose rules still disagree, such as base and walls joined by
a rounded rim, keeps its triangles' groups), and the articular nodes put on
a moving-least-squares surface
through the input's vertices (--smooth-radius).  --surface as-is: the STL goes straight to gmsh
as below.

The hexahedra are about half the requested tetrahedron/triangle sizes.
CAD faces (and STL faces with --surface as-is) are assigned to the physical
groups of DESIGN.md section 3 by the rules below (printed in a table;
override with --*-faces using the face ids of that table):

  insert (tibia)   tibia_inferior: faces with mean outward normal n_z < -0.9
                                   and centroid within 5 % of the height of the
                                   lowest point;
                   tibia_contact:  faces with mean outward normal n_z > 0.3;
                   other faces (sides) untagged = traction free.
  femur            untagged:       faces with |n_x| > 0.8 (medial/lateral sides,
                                   notch walls) and proximal end faces (n_z >
                                   0.5, centroid in the top 15 % of the height);
                   femur_contact:  faces whose outward normal points away from
                                   the centre c of the femur's bounding box
                                   (mean of n . (p - c)/|p - c| > 0);
                   femur_fixation: the others (they face the bone).

Positioning: the inputs must already use the project's axes (x medial-lateral,
y anterior-posterior, z axial, femur above the insert).  With --offset the
femur is translated by the given vector and nothing else.  Otherwise it is
moved along z only, so that the smallest vertical distance between its
articular surface and the insert's articular surface (both meshes) is --gap.

Flexion axis: estimated from the distal arcs of the condyles
(flexion_axis.py) and written, with the mesh file, into KNEE.prm next to
KNEE.msh, a ready-to-run parameter file of the wear run (check the axis and
the medial side, which is a guess).  KNEE-report.txt next to KNEE.msh
repeats the options, the method and counts of each body, the smallest scaled
corner Jacobian of the hexahedra on each articular surface (the "contact
layer"), the gap and the axis.

Units: STEP/IGES files declare their unit and OpenCASCADE converts them to mm.
STL has no unit: --units mm (default) or m says what its numbers are.
"""
import argparse
import math
import os
import struct
import sys
import tempfile

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)

import blockmesh  # noqa: E402
import contact_layer  # noqa: E402
import femur_shell  # noqa: E402
import insert_sweep  # noqa: E402
import gmsh_hexes  # noqa: E402
import flexion_axis  # noqa: E402

import gmsh  # noqa: E402


# ------------------------------------------------------------------ input
def read_stl(path):
    """Triangles (n, 3, 3) of an ASCII or binary STL file."""
    with open(path, "rb") as f:
        data = f.read()
    if len(data) >= 84:
        n = struct.unpack("<I", data[80:84])[0]
        if 84 + 50 * n == len(data):
            rec = np.frombuffer(
                data[84:], dtype=np.dtype([("n", "<f4", 3), ("v", "<f4", (3, 3)), ("a", "<u2")]), count=n
            )
            return rec["v"].astype(float)
    vals = []
    for line in data.decode("ascii", "replace").splitlines():
        s = line.split()
        if s and s[0] == "vertex":
            vals.append([float(t) for t in s[1:4]])
    if not vals or len(vals) % 3:
        raise SystemExit("error: %s is not a readable STL file" % path)
    return np.array(vals).reshape(-1, 3, 3)


def read_stl_in_frame(path, units, rotation):
    """The triangles of an STL file in mm and in our frame (x_ours = R x_file)."""
    tris = read_stl(path)
    if units == "m":
        tris = tris * 1000.0
    if rotation is not None:
        tris = tris @ np.asarray(rotation).T
    return tris


def write_stl_binary(path, tris):
    with open(path, "wb") as f:
        f.write(b"mesh-implant".ljust(80, b" "))
        f.write(struct.pack("<I", len(tris)))
        for t in tris:
            nrm = np.cross(t[1] - t[0], t[2] - t[0])
            ln = np.linalg.norm(nrm)
            nrm = nrm / ln if ln > 0 else nrm
            f.write(struct.pack("<12fH", *nrm, *t.reshape(-1), 0))


CAD_EXTENSIONS = (".step", ".stp", ".iges", ".igs", ".brep")

# Known gmsh failures on users' surfaces and what to try (mesh-implant says
# them instead of a traceback).
GMSH_HINTS = (
    (
        "Wrong topology of boundary mesh for parametrization",
        "the surface could not be split into faces that gmsh can parametrise (typical of decimated or "
        "scanned STL surfaces): try --feature-angle 60 or 89, or repair and remesh the surface first",
    ),
    ("intersect", "the surface intersects itself: remove the self-intersections before meshing"),
    ("Could not read file", "the file could not be read as the format its name says: export it again"),
    (
        "overlapping facets",
        "the tetrahedral mesher met overlapping facets: try another --contact-size or " "--method split",
    ),
)


def gmsh_failure(exc):
    """One line for a gmsh exception: what gmsh said and what to try."""
    text = str(exc).strip() or type(exc).__name__
    for key, hint in GMSH_HINTS:
        if key in text:
            return "error: gmsh: %s; %s" % (text, hint)
    return (
        "error: gmsh: %s; try --method split, other sizes, or check the input surfaces "
        "(closed, not self-intersecting)" % text
    )


def import_cad(path, rotation):
    """Import a STEP/IGES/BREP file into the current gmsh model, turned by
    `rotation` (x_ours = R x_file) if given."""
    shapes = gmsh.model.occ.importShapes(path)
    if rotation is not None:
        a = np.zeros((3, 4))
        a[:, :3] = rotation
        gmsh.model.occ.affineTransform(shapes, list(a.reshape(-1)))
    gmsh.model.occ.synchronize()
    return shapes


def load_geometry(path, units, feature_angle, tmpdir, rotation=None):
    """Load one body into the current (empty) gmsh model, turned by the
    3x3 matrix `rotation` (x_ours = R x_file) if given; return its volume
    tag and, for an STL, its triangles."""
    ext = os.path.splitext(path)[1].lower()
    if ext in CAD_EXTENSIONS:
        import_cad(path, rotation)
        vols = gmsh.model.getEntities(3)
        if not vols:
            raise SystemExit("error: %s contains no solid" % path)
        if len(vols) > 1:
            out, _ = gmsh.model.occ.fuse(vols[:1], vols[1:])
            gmsh.model.occ.synchronize()
            vols = [dt for dt in out if dt[0] == 3]
            if len(vols) != 1:
                raise SystemExit("error: %s holds %d disjoint solids" % (path, len(vols)))
        return vols[0][1], None
    if ext == ".stl":
        tris = read_stl_in_frame(path, units, rotation)
        tmp = os.path.join(tmpdir, "in-%d.stl" % len(os.listdir(tmpdir)))
        write_stl_binary(tmp, tris)
        gmsh.merge(tmp)
        gmsh.model.mesh.removeDuplicateNodes()
        gmsh.model.mesh.classifySurfaces(feature_angle * math.pi / 180, True, True, math.pi)
        gmsh.model.mesh.createGeometry()
        surfs = [t for _, t in gmsh.model.getEntities(2)]
        loop = gmsh.model.geo.addSurfaceLoop(surfs)
        vol = gmsh.model.geo.addVolume([loop])
        gmsh.model.geo.synchronize()
        return vol, tris
    raise SystemExit("error: unknown file type %s (use .step/.stp/.iges/.brep/.stl)" % path)


# ---------------------------------------------------- surface repair (CGAL)
def surface_tool():
    """The tkr-surface executable (apps/surface.cc): $TKR_SURFACE, the build
    trees of this checkout, or the PATH."""
    import glob
    import shutil

    root = os.path.dirname(os.path.dirname(HERE))
    for c in (
        [os.environ.get("TKR_SURFACE", "")]
        + [os.path.join(root, "build", "release", "tkr-surface")]
        + sorted(glob.glob(os.path.join(root, "build", "*", "tkr-surface")))
        + [shutil.which("tkr-surface")]
    ):
        if c and os.path.isfile(c) and os.access(c, os.X_OK):
            return c
    raise SystemExit(
        "error: tkr-surface (the surface check and repair of STL inputs, apps/surface.cc) is not "
        "built: build tkr-wear (scripts/run-tests or cmake and make in build/release), set "
        "TKR_SURFACE to its path, or give --surface as-is to mesh the STL triangles as they are"
    )


def run_surface_tool(role, cmd, shown, log):
    """tkr-surface with its lines printed and logged as "surface ROLE: ...";
    a failure ends mesh-implant with one message."""
    import subprocess

    res = subprocess.run([surface_tool()] + cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    lines = res.stdout.splitlines()
    for path, name in shown.items():
        lines = [ln.replace(path, name) for ln in lines]
    for ln in lines:
        print("surface %s: %s" % (role, ln))
    log += ["surface %s: %s" % (role, ln) for ln in lines]
    if res.returncode != 0:
        last = lines[-1] if lines else "tkr-surface exited with %d" % res.returncode
        raise SystemExit(
            "error: the surface of the %s could not be made valid (%s); try another "
            "--surface-size or --contact-size, or repair it in a CAD tool"
            % (role, last.replace("error: ", ""))
        )


def prepare_surfaces(args, tmpdir, log):
    """--surface remesh (both inputs STL): each surface, in mm and our
    frame, checked, repaired and remeshed with edges of --surface-size by
    tkr-surface; its triangles tagged from the pair's geometry
    (surface_tags.py) or from the --*-contact-stl patches; then remeshed
    again with --contact-size on the contact triangles and max(--contact-size,
    --size/2) elsewhere, the tags carried over (nearest triangle) and made
    uniform per smooth patch, the articular corners put on the smooth
    surface.  Sets args.tagged = {role: (triangles, labels, patch of each
    triangle, repaired triangles, their patches, SmoothSurface)}."""
    import surface_tags
    from scipy.spatial import cKDTree

    paths = {"femur": args.femur, "tibia": args.insert}
    clean, final, smooth = {}, {}, {}
    for role, p in paths.items():
        raw = os.path.join(tmpdir, "%s-frame.stl" % role)
        given = read_stl_in_frame(p, args.units, args.rotation)
        write_stl_binary(raw, given)
        edge = np.median(np.linalg.norm(given - np.roll(given, 1, axis=1), axis=2))
        smooth[role] = surface_tags.SmoothSurface(given, max(args.smooth_radius, 2.5 * edge))
        clean[role] = os.path.join(tmpdir, "%s-clean.stl" % role)
        run_surface_tool(
            role,
            [
                raw,
                clean[role],
                "--size",
                str(args.surface_size),
                "--feature-angle",
                str(args.feature_angle),
                "--wrap-alpha",
                str(0.5 * args.surface_size),
            ],
            {raw: p},
            log,
        )
    tris = {role: read_stl(clean[role]) for role in paths}
    patches = [
        None if q is None else read_stl_in_frame(q, args.units, args.rotation)
        for q in (args.femur_contact_stl, args.insert_contact_stl)
    ]
    try:
        labels = dict(
            zip(
                ("femur", "tibia"),
                surface_tags.tag_pair(
                    tris["femur"],
                    tris["tibia"],
                    args.contact_distance,
                    *patches,
                    patch_tol=max(0.5, args.surface_size)
                )[:2],
            )
        )
    except ValueError as e:
        raise SystemExit(
            "error: tagging the surfaces: %s; check the frame (--rotation, femur resting on the "
            "insert), widen --contact-distance, or give --femur-contact-stl/--insert-contact-stl" % e
        )
    args.tagged = {}
    for role in paths:
        contact = os.path.join(tmpdir, "%s-contact.stl" % role)
        write_stl_binary(contact, tris[role][labels[role] == surface_tags.CONTACT])
        final[role] = os.path.join(tmpdir, "%s-final.stl" % role)
        # the remeshed surface of a body that gets a contact layer (the
        # femur; the insert with --method layer) must follow the repaired
        # one: within half the layer's depth within two triangle sizes of the
        # contact triangles (a feature it loses, such as a cam 1.5 mm under
        # the condyles' surface, is crossed by the layer) and without
        # triangles turned against it (folds); else again with smaller
        # triangles (elsewhere down to --contact-size, then both by 0.75),
        # and if none is faithful the repaired surface as it is.  A swept
        # insert takes its heights from the repaired surface.
        layered = role == "femur" or args.method == "layer"
        sizes = [(max(args.contact_size, 0.5 * args.size), args.contact_size)]
        if layered:
            if sizes[0][0] > args.contact_size:
                sizes.append((args.contact_size, args.contact_size))
            sizes += [(f * sizes[-1][0], f * sizes[-1][1]) for f in (0.75, 0.5625)]
        for attempt, (size, csize) in enumerate(sizes):
            run_surface_tool(
                role,
                [
                    clean[role],
                    final[role],
                    "--size",
                    "%g" % size,
                    "--contact-size",
                    "%g" % csize,
                    "--near",
                    contact,
                    "--near-distance",
                    str(0.5 * args.surface_size),
                    "--feature-angle",
                    str(args.feature_angle),
                    "--wrap-alpha",
                    str(0.5 * args.surface_size),
                ],
                {clean[role]: "the repaired surface", contact: "its contact triangles"},
                log,
            )
            T = read_stl(final[role])
            fault = (
                surface_tags.unfaithful(
                    T,
                    tris[role],
                    0.5 * args.layer_thickness,
                    layer=tris[role][labels[role] == surface_tags.CONTACT],
                    reach=2.0 * size,
                )
                if layered
                else None
            )
            if fault is None:
                break
            line = "surface %s: the remeshed surface %s" % (role, fault)
            if attempt + 1 < len(sizes):
                line += (
                    "; remeshing with edges of %g mm (%g mm on the contact triangles)" % sizes[attempt + 1]
                )
            print(line)
            log.append(line)
        else:
            # a closed, manifold surface always has a faithful remesh: the
            # repaired one itself (--surface-size triangles, more cells)
            line = (
                "surface %s: no remesh down to %g mm triangles is faithful (%s); the repaired surface "
                "(--surface-size %g mm) is meshed as it is (a larger --layer-thickness or a smaller "
                "--contact-size may allow fewer cells)" % (role, sizes[-1][1], fault, args.surface_size)
            )
            print(line)
            log.append(line)
            T = tris[role].copy()
            write_stl_binary(final[role], T)
        _, nearest = cKDTree(tris[role].mean(axis=1)).query(T.mean(axis=1))
        a = 0.5 * np.linalg.norm(np.cross(T[:, 1] - T[:, 0], T[:, 2] - T[:, 0]), axis=1)
        patch = surface_tags.patches(T, args.patch_angle, 2.0 * args.contact_size**2)
        uniform = surface_tags.group_patches(
            T, labels[role][nearest], patch, a, args.patch_angle, 2.0 * args.contact_size**2
        )
        patch = surface_tags.split_mixed(T, patch, uniform)
        # the articular triangles' corners onto the smooth surface through
        # the given vertices (SmoothSurface)
        pts, inv = np.unique(np.round(T.reshape(-1, 3), 9), axis=0, return_inverse=True)
        inv = inv.reshape(-1, 3)
        on = np.unique(inv[uniform == surface_tags.CONTACT])
        skipped = smooth[role].too_far
        pts[on] = smooth[role].project(pts[on])
        skipped = smooth[role].too_far - skipped
        if skipped > 0.2 * len(on):
            # the input's facets cut the articular curvature by more than
            # the smooth surface may correct (a coarse chordal export: 34 %
            # and 47 % of TKR C's; a few rim nodes elsewhere, 6 % at most)
            line = (
                "warning: %d of the %d articular nodes of the %s lie more than %g mm off the smooth "
                "surface through the input's vertices and stay on its facets: the input is too coarse "
                "for contact pressures (expect them off by tens of per cent); export the STL with a "
                "finer chordal tolerance (a few micrometres)"
                % (skipped, len(on), role, smooth[role].max_move)
            )
            print(line)
            log.append(line)
        T = pts[inv]
        # each triangle of the repaired surface belongs to the patch of the
        # remeshed triangle most parallel to it among the 8 nearest (the
        # nearest alone may lie across a sharp edge): new boundary nodes go
        # onto their own patch
        _, cand = cKDTree(T.mean(axis=1)).query(tris[role].mean(axis=1), k=8)
        _, n_fine = surface_tags.normals(tris[role])
        _, n_final = surface_tags.normals(T)
        best = np.argmax(np.einsum("ikj,ij->ik", n_final[cand], n_fine), axis=1)
        args.tagged[role] = (
            T,
            uniform,
            patch,
            tris[role],
            patch[cand[np.arange(len(cand)), best]],
            smooth[role],
        )
        line = "%s: %d smooth patches (--patch-angle %g deg)" % (role, patch.max() + 1, args.patch_angle)
        for code, name in [(surface_tags.UNTAGGED, "untagged")] + sorted(surface_tags.NAMES[role].items()):
            m = uniform == code
            line += "; %s %d patches, %.1f mm2" % (name, len(np.unique(patch[m])), a[m].sum())
        print(line)
        log.append(line)


def load_tagged(tris, labels, patch, role):
    """The current gmsh model from tagged triangles: one discrete surface per
    smooth patch, one discrete curve per pair of neighbouring patches (their
    common edges), one discrete point per node where three or more patches
    meet, and the volume they bound.  Returns (volume, {surface: group name
    or None}, {patch: surface})."""
    import surface_tags

    pts, T, E, ta, tb = surface_tags.shared_edges(tris)
    pa, pb = patch[ta], patch[tb]
    border = pa != pb
    edges, pairs = E[border], np.sort(np.stack([pa, pb], axis=1)[border], axis=1)
    around = [set() for _ in range(len(pts))]
    for tri, k in zip(T, patch):
        for v in tri:
            around[v].add(int(k))
    owner = np.zeros(len(pts), bool)

    def own(nodes):
        nodes = np.unique(nodes)
        nodes = nodes[~owner[nodes]]
        owner[nodes] = True
        return nodes

    point_of = {}
    for v in np.unique(edges):
        if len(around[v]) >= 3:
            point_of[int(v)] = gmsh.model.addDiscreteEntity(0)
            gmsh.model.mesh.addNodes(0, point_of[int(v)], [v + 1], pts[v])
            owner[v] = True
    curves_of = {}
    for pair in np.unique(pairs, axis=0):
        m = (pairs == pair).all(axis=1)
        ends = [point_of[int(v)] for v in np.unique(edges[m]) if int(v) in point_of]
        c = gmsh.model.addDiscreteEntity(1, -1, ends)
        nodes = own(edges[m])
        if len(nodes):
            gmsh.model.mesh.addNodes(1, c, nodes + 1, pts[nodes].reshape(-1))
        gmsh.model.mesh.addElementsByType(c, 1, [], (edges[m] + 1).reshape(-1))
        for k in pair:
            curves_of.setdefault(int(k), []).append(c)
    groups, surfs, surface_of = {}, [], {}
    for k in np.unique(patch):
        m = patch == k
        s = gmsh.model.addDiscreteEntity(2, -1, curves_of.get(int(k), []))
        nodes = own(T[m])
        if len(nodes):
            gmsh.model.mesh.addNodes(2, s, nodes + 1, pts[nodes].reshape(-1))
        groups[s] = surface_tags.NAMES[role].get(int(labels[m][0]))
        surfs.append((s, m))
        surface_of[int(k)] = s
    for s, m in surfs:
        gmsh.model.mesh.addElementsByType(s, 2, [], (T[m] + 1).reshape(-1))
    loop = gmsh.model.geo.addSurfaceLoop([s for s, _ in surfs])
    vol = gmsh.model.geo.addVolume([loop])
    gmsh.model.geo.synchronize()
    return vol, groups, surface_of


# --------------------------------------------------------- face statistics
def face_table(vol):
    """Per boundary face of volume `vol` of the current tetrahedral mesh:
    area, centroid, area-weighted mean outward unit normal, and the mean of
    n . (p - c)/|p - c| for c = centre of the bounding box."""
    _, _, ntags = gmsh.model.mesh.getElements(3, vol)
    etypes, _, _ = gmsh.model.mesh.getElements(3, vol)
    tets = None
    for t, nt in zip(etypes, ntags):
        if t == 4:
            tets = np.array(nt, dtype=np.int64).reshape(-1, 4)
    if tets is None:
        raise SystemExit("error: tetrahedral meshing failed")
    opp = {}
    for tet in tets:
        for i in range(4):
            f = tuple(sorted(np.delete(tet, i).tolist()))
            opp[f] = tet[i]
    tags, coords, _ = gmsh.model.mesh.getNodes()
    X = np.zeros((int(tags.max()) + 1, 3))
    X[tags.astype(np.int64)] = coords.reshape(-1, 3)
    bb = gmsh.model.getBoundingBox(3, vol)
    lo, hi = np.array(bb[:3]), np.array(bb[3:])
    centre = 0.5 * (lo + hi)
    rows = {}
    for _, s in gmsh.model.getBoundary([(3, vol)], oriented=False):
        s = abs(s)
        et, _, nt = gmsh.model.mesh.getElements(2, s)
        tri = None
        for t, n in zip(et, nt):
            if t == 2:
                tri = np.array(n, dtype=np.int64).reshape(-1, 3)
        if tri is None:
            continue
        area, cen, nrm, away = 0.0, np.zeros(3), np.zeros(3), 0.0
        samples = []
        for t in tri:
            p = X[t]
            n = 0.5 * np.cross(p[1] - p[0], p[2] - p[0])
            o = opp.get(tuple(sorted(t.tolist())))
            if o is not None and np.dot(n, X[o] - p[0]) > 0:
                n = -n
            a = np.linalg.norm(n)
            if a == 0:
                continue
            m = p.mean(axis=0)
            samples.append(np.concatenate([m, n / a]))
            area += a
            cen += a * m
            nrm += n
            d = m - centre
            away += np.dot(n, d) / (np.linalg.norm(d) + 1e-12)
        if area == 0:
            continue
        rows[s] = dict(
            area=area,
            centroid=cen / area,
            normal=nrm / np.linalg.norm(nrm) if np.linalg.norm(nrm) > 0 else nrm,
            away=away / area,
            outward=np.array(samples),  # centroid and outward unit normal of each triangle
        )
    return rows, lo, hi


def face_table_stl(vol, tris):
    """Like face_table, from the classified STL triangles (no volume mesh);
    outward orientation from the STL file (made consistent by the sign of the
    enclosed volume)."""
    signed = np.einsum("ij,ij->i", tris[:, 0], np.cross(tris[:, 1], tris[:, 2])).sum() / 6.0
    orient = {}
    for t in tris:
        n = np.cross(t[1] - t[0], t[2] - t[0])
        key = tuple(sorted(tuple(np.round(p, 5)) for p in t))
        orient[key] = n if signed > 0 else -n
    tags, coords, _ = gmsh.model.mesh.getNodes()
    X = np.zeros((int(tags.max()) + 1, 3))
    X[tags.astype(np.int64)] = coords.reshape(-1, 3)
    lo = tris.reshape(-1, 3).min(axis=0)
    hi = tris.reshape(-1, 3).max(axis=0)
    centre = 0.5 * (lo + hi)
    rows = {}
    for _, s in gmsh.model.getBoundary([(3, vol)], oriented=False):
        s = abs(s)
        et, _, nt = gmsh.model.mesh.getElements(2, s)
        area, cen, nrm, away = 0.0, np.zeros(3), np.zeros(3), 0.0
        for t, n in zip(et, nt):
            if t != 2:
                continue
            for tri in np.array(n, dtype=np.int64).reshape(-1, 3):
                p = X[tri]
                nn = 0.5 * np.cross(p[1] - p[0], p[2] - p[0])
                ref = orient.get(tuple(sorted(tuple(np.round(q, 5)) for q in p)))
                if ref is not None and np.dot(ref, nn) < 0:
                    nn = -nn
                a = np.linalg.norm(nn)
                if a == 0:
                    continue
                m = p.mean(axis=0)
                d = m - centre
                area += a
                cen += a * m
                nrm += nn
                away += np.dot(nn, d) / (np.linalg.norm(d) + 1e-12)
        if area > 0:
            rows[s] = dict(
                area=area,
                centroid=cen / area,
                normal=nrm / max(np.linalg.norm(nrm), 1e-300),
                away=away / area,
            )
    return rows, lo, hi


def classify(role, rows, lo, hi):
    H = hi[2] - lo[2]
    groups = {}
    for s, r in rows.items():
        n, c = r["normal"], r["centroid"]
        g = None
        if role == "tibia":
            if n[2] < -0.9 and c[2] < lo[2] + 0.05 * H:
                g = "tibia_inferior"
            elif n[2] > 0.3:
                g = "tibia_contact"
        else:
            if abs(n[0]) > 0.8:
                g = None
            elif n[2] > 0.5 and c[2] > lo[2] + 0.85 * H:
                g = None
            elif r["away"] > 0:
                g = "femur_contact"
            else:
                g = "femur_fixation"
        groups[s] = g
    return groups


def print_table(role, path, rows, groups):
    print("%s (%s): faces" % (role, path))
    print("   face    area mm2        centroid x y z            mean normal        group")
    for s in sorted(rows):
        r = rows[s]
        print(
            "  %5d %10.1f   %8.2f %8.2f %8.2f   %6.3f %6.3f %6.3f   %s"
            % (s, r["area"], *r["centroid"], *r["normal"], groups.get(s) or "-")
        )


# ----------------------------------------------------------------- meshing
def generate_plain(dim, size_max):
    """Mesh the current model up to dimension `dim` with elements of at most
    `size_max` mm and no subdivision (the passes that classify faces or
    sample surfaces)."""
    gmsh.option.setNumber("Mesh.MeshSizeMax", size_max)
    gmsh.option.setNumber("Mesh.MeshSizeMin", 0.0)
    gmsh.option.setNumber("Mesh.SubdivisionAlgorithm", 0)
    gmsh.model.mesh.generate(dim)


class Part:
    """One body loaded into its own gmsh model (named after its role), with
    its faces classified into groups."""

    def __init__(self, role, path, args, tmpdir):
        self.role, self.path = role, path
        gmsh.model.add(role)
        self.method, self.notes, self.fine_faces, self.smooth = None, [], None, {}
        if role in getattr(args, "tagged", {}):
            # repaired, remeshed and tagged per triangle (prepare_surfaces)
            T, labels, patch, fine, fine_patch, smooth = args.tagged[role]
            self.vol, self.groups, surface_of = load_tagged(T, labels, patch, role)
            self.cad, self.tris = False, T
            self.fine_faces = {s: fine[fine_patch == k] for k, s in surface_of.items()}
            self.smooth = {
                s: smooth.project for s, g in self.groups.items() if g in contact_layer.CONTACT_GROUPS
            }
            self.contact = [s for s, g in self.groups.items() if g in contact_layer.CONTACT_GROUPS]
            return
        shown = path
        self.vol, self.tris = load_geometry(path, args.units, args.feature_angle, tmpdir, args.rotation)
        self.cad = self.tris is None
        if not self.cad:
            # STL: classify from the file's own triangles
            rows, lo, hi = face_table_stl(self.vol, self.tris)
        else:
            # pass 1: coarse tetrahedra to classify the faces
            generate_plain(3, 2.0 * args.size)
            rows, lo, hi = face_table(self.vol)
            gmsh.model.mesh.clear()
        # (an STL's discrete surfaces keep their triangles: clearing them
        # would delete the geometry)
        groups = classify(role, rows, lo, hi)
        names = (
            ("femur_contact", "femur_fixation") if role == "femur" else ("tibia_contact", "tibia_inferior")
        )
        for g in names:
            override = getattr(args, g + "_faces")
            if override:
                ids = [int(t) for t in override.split(",") if t.strip()]
                for s in list(groups):
                    if groups[s] == g:
                        groups[s] = None
                for s in ids:
                    if s not in rows:
                        raise SystemExit("error: %s has no face %d" % (shown, s))
                    groups[s] = g
        print_table(role, shown, rows, groups)
        for g in names:
            if not any(v == g for v in groups.values()):
                raise SystemExit(
                    "error: no face of %s was assigned to %s; use --%s-faces"
                    % (shown, g, g.replace("_", "-"))
                )
        self.groups = groups
        self.rows = rows
        self.contact = [s for s, g in groups.items() if g in contact_layer.CONTACT_GROUPS]

    def articular_points(self, spacing):
        """Points on the articular faces, about `spacing` mm apart."""
        gmsh.model.setCurrent(self.role)
        if self.cad:
            generate_plain(2, spacing)
        pts = [gmsh.model.mesh.getNodes(2, s, includeBoundary=True)[1].reshape(-1, 3) for s in self.contact]
        if self.cad:
            gmsh.model.mesh.clear()
        return np.concatenate(pts)

    def surface_triangles(self, spacing):
        """The body's boundary as outward triangles (T x 3 x 3): a repaired
        STL surface's (--surface-size; the one remeshed for the mesh is
        coarser, 3-4 mm), an STL's own, a CAD body's triangulated at
        `spacing` mm."""
        if self.fine_faces is not None:
            return np.concatenate(list(self.fine_faces.values()))
        if not self.cad:
            T = self.tris
            if np.einsum("ij,ij->i", T[:, 0], np.cross(T[:, 1], T[:, 2])).sum() < 0:
                T = T[:, ::-1]
            return T
        gmsh.model.setCurrent(self.role)
        generate_plain(2, spacing)
        faces = insert_sweep.boundary_triangles(self.vol)
        gmsh.model.mesh.clear()
        return np.concatenate([insert_sweep.outward(P, n) for P, n in faces.values()])

    def mesh(self, args, near):
        """Pass 2: the hexahedral mesh (nodes, hexes, surfaces).  near:
        points on the other body's articular faces (for the sizes)."""
        gmsh.model.setCurrent(self.role)
        if self.role == "tibia" and args.method == "auto":
            # structured columns under a plan grid (insert_sweep.py); a post
            # the sweep cannot mesh is left out where the femur (its surface
            # in self.femur, set by main()) never reaches it
            try:
                if self.cad:
                    generate_plain(2, args.sweep_size)
                fine = self.fine_faces
                smooth = next(iter(self.smooth.values()), None)
                import surface_tags

                femur = getattr(self, "femur", None)
                log = []
                out = insert_sweep.mesh_insert(
                    self.vol,
                    self.groups,
                    args.sweep_size,
                    args.sweep_cells,
                    args.sweep_top_cell,
                    self.cad,
                    fine,
                    smooth,
                    clearance=None if femur is None else lambda P, ins: surface_tags.approach(femur, ins, P),
                    contact_distance=args.contact_distance,
                    log=log,
                )
                self.method = "swept columns"
                self.log = log
                return out
            except insert_sweep.Refused as e:
                raise SystemExit("error: %s" % e)
            except insert_sweep.NotSweepable as e:
                print("note: the insert cannot be swept (%s); it gets a contact layer instead" % e)
                self.notes.append("not swept: %s" % e)
                if self.cad:
                    gmsh.model.mesh.clear()
        # a layer of prisms under the articular faces, tetrahedra elsewhere,
        # all split into hexahedra (contact_layer.py)
        own = self.articular_points(1.5)
        gmsh.model.setCurrent(self.role)
        field = contact_layer.SizeField(
            own,
            near if args.refine_distance > 0 else None,
            args.contact_size,
            args.size,
            args.grading_distance,
            args.refine_distance,
            contact_layer.width_caps() if self.cad else {},
        )
        if self.role == "femur" and args.femur_mesh == "shell":
            self.method = "articular shell"
            return self.shell(args, field)
        self.method = "contact layer"
        return contact_layer.mesh_body(
            self.vol,
            self.groups,
            field,
            args.size,
            args.layers,
            args.layer_thickness,
            args.layer_ratio,
            self.cad,
            self.notes,
            self.fine_faces,
            self.smooth,
        )

    def shell(self, args, field):
        """--femur-mesh shell: hexahedra extruded inward from the articular
        faces only (femur_shell.py), on the triangles the contact layer
        would have had there (the boundary triangulated as for the layer, in
        a child process: gmsh stays locked after a failure; if that fails,
        on a face away from the articular surface, only the articular faces
        are triangulated, turned outward by the face table: then nothing but
        them is needed)."""
        if self.cad:
            try:
                X, tris, face, _, curve_edges = contact_layer.in_child(
                    contact_layer.triangulate_boundary, self.vol, self.groups, field, args.size
                )
            except Exception as e:
                note = (
                    "the femur's boundary could not be triangulated (%s); its articular faces were, alone"
                    % str(e).strip()
                )
                print("note: " + note)
                self.notes.append(note)
                X, tris, face, curve_edges = femur_shell.triangulate_faces(
                    self.contact, {s: self.rows[s]["outward"] for s in self.contact}, field, args.size
                )
            project = contact_layer.cad_projector()
        else:
            X, tris, face, _, curve_edges = contact_layer.triangulate_boundary(
                self.vol, self.groups, field, args.size
            )
            project = contact_layer.boundary_projector(
                X, tris, face, curve_edges, False, self.fine_faces, self.smooth
            )
        on = np.isin(face, self.contact)
        tris, face = tris[on], face[on]
        return femur_shell.mesh_shell(
            X,
            tris,
            face,
            curve_edges,
            project,
            args.shell_thickness,
            args.shell_layers,
            args.shell_ratio,
            self.notes,
        )


def mesh_part_robust(part, args, tmpdir, near):
    """Part.mesh(); where the contact layer of a repaired STL surface fails
    (its prisms fold, its nodes find no direction, or its side walls cross
    a nearby face: a scan's rounded edges next to the articular faces give
    the layer's border small faces to slide in), the body is meshed again
    with a layer of half the depth, then by --method split with
    straight-sided subdivision (reported).  Returns (nodes, hexes,
    surfaces) and the method in words."""
    import copy

    notes = []
    again = copy.copy(args)
    if part.role == "femur" and args.femur_mesh == "shell":
        # the shell depends on nothing but the articular surface: where its
        # cells turn inside out it is made again at half the thickness; no
        # fall back to split tetrahedra (their cells are unfit for contact)
        for attempt in range(2):
            try:
                out = part.mesh(again, near)
                return out, "; ".join([part.method] + notes + part.notes)
            except femur_shell.ShellError as e:
                if attempt:
                    raise SystemExit("error: the femur's articular shell: %s" % e)
                note = "note: the articular shell of the femur failed (%s); meshing it again with " % e
                note += "--shell-thickness %g" % (0.5 * args.shell_thickness)
            print(note)
            notes.append(note.replace("note: ", ""))
            part.notes = []
            again.shell_thickness = 0.5 * args.shell_thickness
    for thickness in (0.5 * args.layer_thickness, None):
        try:
            out = part.mesh(again, near)
            return out, "; ".join([part.method] + notes + part.notes)
        except Exception as e:
            if part.cad or part.role not in getattr(args, "tagged", {}) or args.method == "split":
                raise
            why = gmsh_failure(e).replace("error: gmsh: ", "gmsh: ") if type(e) is Exception else str(e)
        note = "note: the contact layer of the %s failed (%s); meshing it again %s" % (
            part.role,
            why,
            "with --layer-thickness %g" % thickness
            if thickness
            else "by --method split (tetrahedra split into hexahedra, straight-sided)",
        )
        print(note)
        notes.append(note.replace("note: ", ""))
        part.notes = []
        again.layer_thickness = thickness
    gmsh.model.setCurrent(part.role)
    return mesh_body(part.role, part.path, args, tmpdir, linear=True, part=part), "; ".join(
        ["split tetrahedra"] + notes
    )


def mesh_body(role, path, args, tmpdir, linear=False, part=None):
    """--method split: tetrahedra refined towards the articular faces, each
    split into four hexahedra by gmsh (in `part`'s model if given)."""
    part = part or Part(role, path, args, tmpdir)
    vol, groups = part.vol, part.groups
    # pass 2: graded tetrahedra, split into hexahedra
    contact = [s for s, g in groups.items() if g in ("femur_contact", "tibia_contact")]
    f = gmsh.model.mesh.field.add("Distance")
    gmsh.model.mesh.field.setNumbers(f, "SurfacesList", contact)
    t = gmsh.model.mesh.field.add("Threshold")
    gmsh.model.mesh.field.setNumber(t, "InField", f)
    gmsh.model.mesh.field.setNumber(t, "SizeMin", args.contact_size)
    gmsh.model.mesh.field.setNumber(t, "SizeMax", args.size)
    gmsh.model.mesh.field.setNumber(t, "DistMin", 0.5 * args.contact_size)
    gmsh.model.mesh.field.setNumber(t, "DistMax", args.grading_distance)
    gmsh.model.mesh.field.setAsBackgroundMesh(t)
    gmsh.option.setNumber("Mesh.MeshSizeExtendFromBoundary", 0)
    gmsh.option.setNumber("Mesh.MeshSizeFromPoints", 0)
    gmsh.option.setNumber("Mesh.MeshSizeFromCurvature", 0)
    gmsh.option.setNumber("Mesh.MeshSizeMax", args.size)
    gmsh.option.setNumber("Mesh.SubdivisionAlgorithm", 2)
    gmsh.option.setNumber("Mesh.SecondOrderLinear", 1 if linear else 0)
    gmsh.model.mesh.generate(3)
    # extract hexahedra and tagged quadrangles
    return gmsh_hexes.extract(vol, groups, path)


def mesh_body_robust(role, path, args, tmpdir):
    """Subdivision places the new boundary nodes on the curved geometry; where
    that inverts a hexahedron, mesh again with straight-sided subdivision
    (Mesh.SecondOrderLinear = 1: the boundary is then the tetrahedral mesh's
    polyhedral surface)."""
    try:
        return mesh_body(role, path, args, tmpdir)
    except RuntimeError as e:
        print("note: %s: %s; meshing again with straight-sided subdivision" % (role, e))
        gmsh.model.remove()
        return mesh_body(role, path, args, tmpdir, linear=True)


def facing(nodes, quads, sign):
    """Quads whose outward normal has sign(n_z) == sign."""
    p = nodes[quads]
    n = np.cross(p[:, 2] - p[:, 0], p[:, 3] - p[:, 1])
    return quads[np.sign(n[:, 2]) == sign]


def seat_only(tib, tol=0.05):
    """The insert's tibia_inferior quadrangles that lie on its seat: those
    facing down whose nodes are all within tol mm of the plane fitted to
    the lowest ones (within tol of the lowest node); what bears on the tray.
    The rest of the underside that the tags found (a locking recess's floor,
    the lower half of a rounded rim) stays traction free: tkr-wear's rigid
    tray needs a flat tibia_inferior.  Returns (body, number of quadrangles
    left out, the seat's area in mm^2)."""
    nodes, hexes, surfaces = tib
    q = surfaces.get("tibia_inferior")
    if q is None or not len(q):
        return tib, 0, 0.0
    P = nodes[q]
    n = np.cross(P[:, 2] - P[:, 0], P[:, 3] - P[:, 1])
    down = n[:, 2] < -0.9 * np.linalg.norm(n, axis=1)
    low = down & (P[..., 2] <= P[..., 2].min() + tol).all(axis=1)
    if not np.any(low):
        return tib, 0, 0.0
    # z = a x + b y + c through the lowest quadrangles' nodes
    X = P[low].reshape(-1, 3)
    a, b, c = np.linalg.lstsq(np.c_[X[:, :2], np.ones(len(X))], X[:, 2], rcond=None)[0]
    seat = down & (np.abs(P[..., 2] - a * P[..., 0] - b * P[..., 1] - c) <= tol).all(axis=1)
    surfaces = dict(surfaces, tibia_inferior=q[seat])
    area = 0.5 * np.linalg.norm(n[seat], axis=1).sum()
    return (nodes, hexes, surfaces), int(np.count_nonzero(~seat)), float(area)


def min_vertical_gap(fem, tib):
    fn, _, fs = fem
    tn, _, ts = tib
    fq = facing(fn, fs["femur_contact"], -1)
    tq = facing(tn, ts["tibia_contact"], +1)
    g1 = blockmesh.vertical_gap(tn[np.unique(tq)], fn, fq)  # z_f - z_t at tibia nodes
    g2 = -blockmesh.vertical_gap(fn[np.unique(fq)], tn, tq)  # z_f - z_t at femur nodes
    g = np.concatenate([g1, g2])
    g = g[~np.isnan(g)]
    if len(g) == 0:
        raise SystemExit(
            "error: the articular surfaces do not overlap in the x-y plane; "
            "position the parts (--offset) or check the axes"
        )
    return float(g.min())


def refuse_impractical(bodies, methods, args):
    """No impractical mesh is written (issue 50 item 3): more than
    --max-dofs Q1 displacement DoFs (default 200,000: a wear run of 100
    blocks on 2 ranks takes hours beyond that), or a contact cell (a
    hexahedron with a face on femur_contact or tibia_contact) of scaled
    corner Jacobian below --min-contact-quality (default 0.1: the nodal
    pressures of such cells scatter by tens of per cent, doc/geometry.md
    "Contact layers") end mesh-implant with one line naming the body, the
    numbers, where the worst cell is and the options that would help."""
    causes = []
    vertices = {b: len(bodies[b][0]) for b in bodies}
    dofs = 3 * sum(vertices.values())
    femur, insert = methods["femur"], methods["tibia"]
    if dofs > args.max_dofs:
        helps = ["a larger --contact-size (now %g) or --size (now %g)" % (args.contact_size, args.size)]
        if femur.startswith("articular shell"):
            helps.append("fewer --shell-layers (now %d)" % args.shell_layers)
        else:
            helps.append("--femur-mesh shell")
        if insert.startswith("swept"):
            helps.append("a larger --sweep-size (now %g) or fewer --sweep-cells" % args.sweep_size)
        causes.append(
            "the mesh has %d Q1 DoFs (femur %d, insert %d), more than --max-dofs %d: try %s"
            % (dofs, 3 * vertices["femur"], 3 * vertices["tibia"], args.max_dofs, ", ".join(helps))
        )
    for body, group in (("femur", "femur_contact"), ("tibia", "tibia_contact")):
        n, q, where = contact_layer.contact_cells(*bodies[body])[group]
        if q >= args.min_contact_quality:
            continue
        method = methods[body]
        if body == "femur":
            helps = (
                "a smaller --shell-thickness (now %g) or another --contact-size" % args.shell_thickness
                if method.startswith("articular shell")
                else "--femur-mesh shell"
            )
        elif method.startswith("swept"):
            helps = "another --sweep-size or --sweep-top-cell"
        elif method.startswith("contact layer"):
            helps = "another --layer-thickness or --contact-size"
        else:
            helps = "--method auto"
        causes.append(
            "the %s's contact cells (%s, %d on %s) reach a scaled corner Jacobian of %.3f at "
            "(%.1f, %.1f, %.1f), below --min-contact-quality %g: try %s"
            % (
                "insert" if body == "tibia" else body,
                method.split(";")[0],
                n,
                group,
                q,
                *where,
                args.min_contact_quality,
                helps,
            )
        )
    if causes:
        raise SystemExit(
            "error: no mesh written: %s (or move the limits deliberately with --max-dofs N and "
            "--min-contact-quality Q)" % "; and ".join(causes)
        )


def parse_rotation(text):
    """--rotation: nine numbers, the rows of R (x_ours = R x_file), which
    must be a rotation (orthonormal to 1e-4, determinant +1)."""
    try:
        r = np.array([float(t) for t in text.split(",")])
    except ValueError:
        raise SystemExit("error: --rotation needs nine numbers R11,R12,...,R33 (got %r)" % text)
    if r.shape != (9,):
        raise SystemExit("error: --rotation needs nine numbers R11,R12,...,R33 (got %d)" % r.size)
    r = r.reshape(3, 3)
    err = np.abs(r @ r.T - np.eye(3)).max()
    if err > 1e-4 or np.linalg.det(r) < 0:
        raise SystemExit(
            "error: --rotation is not a rotation (R R^T differs from I by %.2g, det %.4g): "
            "give the rows as unit vectors, orthogonal, right-handed" % (err, np.linalg.det(r))
        )
    return r


def bounding_box(role, path, args):
    """Lower and upper corner of a body in our frame (units and rotation
    applied); a CAD file is read in a scratch gmsh model."""
    if os.path.splitext(path)[1].lower() == ".stl":
        p = read_stl_in_frame(path, args.units, args.rotation).reshape(-1, 3)
        return p.min(axis=0), p.max(axis=0)
    gmsh.model.add("probe-" + role)
    try:
        import_cad(path, args.rotation)
        box = np.array(gmsh.model.getBoundingBox(-1, -1))
    finally:
        gmsh.model.remove()
    return box[:3], box[3:]


def check_frame(args):
    """Our axes: x medial-lateral, y anterior-posterior, z axial (femur
    above the insert). Refuse, with what was found, an insert that is not
    thinnest along z, a femur not above the insert, or bodies that do not
    overlap in plan (then the articular faces cannot face each other)."""
    flo, fhi = bounding_box("femur", args.femur, args)
    tlo, thi = bounding_box("tibia", args.insert, args)
    ext = thi - tlo
    hint = (
        "our axes are x medial-lateral, y anterior-posterior, z axial with the femur above the "
        "insert: turn the input with --rotation R11,...,R33 (rows: our x, y, z axes in the file's "
        "frame) or in your CAD tool"
    )
    print(
        "insert: %.1f x %.1f x %.1f mm (x, y, z); femur z %.1f .. %.1f, insert z %.1f .. %.1f"
        % (ext[0], ext[1], ext[2], flo[2], fhi[2], tlo[2], thi[2])
    )
    if ext[2] >= min(ext[0], ext[1]):
        raise SystemExit(
            "error: the insert is %.1f x %.1f x %.1f mm along x, y, z, not thinnest along z "
            "(its thickness); %s" % (ext[0], ext[1], ext[2], hint)
        )
    if 0.5 * (flo[2] + fhi[2]) <= 0.5 * (tlo[2] + thi[2]):
        raise SystemExit(
            "error: the femur (z %.1f .. %.1f mm) is not above the insert (z %.1f .. %.1f mm); %s"
            % (flo[2], fhi[2], tlo[2], thi[2], hint)
        )
    overlap = np.minimum(fhi[:2], thi[:2]) - np.maximum(flo[:2], tlo[:2])
    if (overlap <= 0.5 * ext[:2]).any():
        raise SystemExit(
            "error: in plan the femur (x %.1f .. %.1f, y %.1f .. %.1f mm) covers less than half "
            "of the insert (x %.1f .. %.1f, y %.1f .. %.1f mm): the articular surfaces do not "
            "face each other; %s" % (flo[0], fhi[0], flo[1], fhi[1], tlo[0], thi[0], tlo[1], thi[1], hint)
        )


def main(argv=None):
    ap = argparse.ArgumentParser(
        prog="mesh-implant", description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    ap.add_argument("--femur", required=True, help="femoral component (.step/.stp/.iges/.brep/.stl)")
    ap.add_argument("--insert", required=True, help="tibial insert (.step/.stp/.iges/.brep/.stl)")
    ap.add_argument("-o", "--output", required=True, help="output .msh (ASCII 4.1)")
    ap.add_argument("--units", choices=("mm", "m"), default="mm", help="unit of STL coordinates (default mm)")
    ap.add_argument(
        "--rotation",
        type=parse_rotation,
        help="R11,R12,R13,R21,...,R33: turn both inputs by this rotation, x_ours = R x_file "
        "(the rows are our x (medial-lateral), y (anterior-posterior), z (axial, towards "
        "the femur) axes written in the file's frame)",
    )
    ap.add_argument(
        "--method",
        choices=("auto", "layer", "split"),
        default="auto",
        help="auto (default): swept insert where possible, contact layer otherwise; "
        "layer: contact layer on both bodies; split: tetrahedra split into hexahedra",
    )
    ap.add_argument(
        "--femur-mesh",
        choices=("shell", "layer", "split"),
        help="the femoral component: shell (default with --method auto): hexahedra extruded inward "
        "from its articular surface only (--shell-*), the inner face clamped as femur_fixation; "
        "layer: the whole component, a contact layer and a tetrahedral core (default with --method "
        "layer); split: the whole component as tetrahedra split into hexahedra (default with --method split)",
    )
    ap.add_argument(
        "--shell-thickness",
        type=float,
        default=3.0,
        help="shell: depth of the femoral shell under its articular surface, mm (thinner where the "
        "surface's radius of curvature is smaller)",
    )
    ap.add_argument("--shell-layers", type=int, default=3, help="shell: cell layers through the shell")
    ap.add_argument(
        "--shell-ratio",
        type=float,
        default=1.5,
        help="shell: thickness ratio of consecutive cell layers (thinnest at the surface)",
    )
    ap.add_argument(
        "--max-dofs",
        type=int,
        default=200000,
        help="refuse (write nothing) a mesh of more Q1 displacement DoFs than this",
    )
    ap.add_argument(
        "--min-contact-quality",
        type=float,
        default=0.1,
        help="refuse (write nothing) a mesh with a contact cell (a hexahedron with a face on "
        "femur_contact or tibia_contact) of smaller scaled corner Jacobian",
    )
    ap.add_argument(
        "--size",
        type=float,
        default=8.0,
        help="tetrahedron size away from the articular faces, mm (hexahedra are about half)",
    )
    ap.add_argument(
        "--contact-size",
        type=float,
        help="triangle/tetrahedron size at the articular faces, mm " "(default 3; 4 with --method split)",
    )
    ap.add_argument(
        "--grading-distance",
        type=float,
        default=10.0,
        help="distance over which the size grows from --contact-size to --size, mm",
    )
    ap.add_argument(
        "--refine-distance",
        type=float,
        default=10.0,
        help="layer: --contact-size where the articular faces are within this distance "
        "(mm) of the other body's articular faces (in the input position), growing "
        "to --size beyond; 0: on all articular faces",
    )
    ap.add_argument("--layers", type=int, default=2, help="layer: number of cell layers")
    ap.add_argument("--layer-thickness", type=float, default=1.5, help="layer: total depth, mm")
    ap.add_argument(
        "--layer-ratio",
        type=float,
        default=1.3,
        help="layer: thickness ratio of consecutive layers (thinnest at the surface)",
    )
    ap.add_argument(
        "--sweep-size", type=float, default=2.0, help="auto, swept insert: plan size of the cells, mm"
    )
    ap.add_argument(
        "--sweep-cells", type=int, default=6, help="auto, swept insert: cells through the insert's thickness"
    )
    ap.add_argument(
        "--sweep-top-cell",
        type=float,
        default=1.0,
        help="auto, swept insert: thickness of the cells at the articular surface "
        "where the insert is thinnest, mm",
    )
    ap.add_argument(
        "--surface",
        choices=("remesh", "as-is"),
        default="remesh",
        help="STL: remesh (default): check, repair and remesh each STL surface with tkr-surface "
        "(CGAL) before meshing; as-is: mesh the STL triangles as they are",
    )
    ap.add_argument(
        "--surface-size",
        type=float,
        default=1.0,
        help="STL, remesh: edge length of the repaired surface, which is the geometry the mesh "
        "follows and is tagged on, mm",
    )
    ap.add_argument(
        "--contact-distance",
        type=float,
        default=3.0,
        help="STL, remesh: the contact groups are the triangles that come within this distance "
        "(mm) of the other body over the flexion range; auto: a post of the insert that the sweep "
        "cannot mesh is left out if the femur stays farther than this from it (else refused)",
    )
    ap.add_argument(
        "--smooth-radius",
        type=float,
        default=3.0,
        help="STL, remesh: radius (mm; at least 2.5 edges of the input) of the smooth surface "
        "fitted through the input's vertices that the articular nodes are put on",
    )
    ap.add_argument(
        "--patch-angle",
        type=float,
        default=30.0,
        help="STL, remesh: dihedral angle (deg) above which an edge of the remeshed surface "
        "separates two patches; a group is given to whole patches",
    )
    ap.add_argument(
        "--femur-contact-stl",
        help="STL, remesh: the femur's articular surface as its own STL "
        "(same units and frame), instead of the proximity rule",
    )
    ap.add_argument("--insert-contact-stl", help="STL, remesh: the insert's articular surface as its own STL")
    ap.add_argument(
        "--feature-angle", type=float, default=40.0, help="STL: angle (deg) between facets that splits faces"
    )
    ap.add_argument(
        "--offset",
        help="DX,DY,DZ: translate the femur by this (mm) instead of " "moving it along z to touch the insert",
    )
    ap.add_argument("--gap", type=float, default=1e-3, help="initial gap when touching (mm)")
    for g in ("femur_contact", "femur_fixation", "tibia_contact", "tibia_inferior"):
        ap.add_argument(
            "--" + g.replace("_", "-") + "-faces",
            dest=g + "_faces",
            help="comma-separated face ids (see the table) for %s, replacing the rule" % g,
        )
    args = ap.parse_args(argv)
    stl_remesh = args.surface == "remesh" and all(
        p.lower().endswith(".stl") for p in (args.femur, args.insert)
    )
    faces = [
        g
        for g in ("femur_contact", "femur_fixation", "tibia_contact", "tibia_inferior")
        if getattr(args, g + "_faces")
    ]
    if stl_remesh and faces:
        raise SystemExit(
            "error: --%s-faces names faces of the CAD table; with STL input give the contact "
            "patch as --femur-contact-stl/--insert-contact-stl, or mesh the STL as it is with "
            "--surface as-is" % faces[0].replace("_", "-")
        )
    for option, path in (("--femur", args.femur), ("--insert", args.insert)):
        if not os.path.isfile(path):
            raise SystemExit("error: %s %s: no such file" % (option, path))
        if os.path.splitext(path)[1].lower() not in CAD_EXTENSIONS + (".stl",):
            raise SystemExit(
                "error: %s %s: unknown file type (use .step/.stp/.iges/.igs/.brep or .stl)" % (option, path)
            )
    if args.contact_size is None:
        args.contact_size = 4.0 if args.method == "split" else 3.0
    if args.femur_mesh is None:
        args.femur_mesh = {"auto": "shell", "layer": "layer", "split": "split"}[args.method]

    inputs = (args.femur, args.insert)
    gmsh.initialize(["gmsh", "-v", "1"])
    try:
        with tempfile.TemporaryDirectory() as tmpdir:
            check_frame(args)
            surface_log, methods, sweep_log = [], {}, []
            if stl_remesh:
                prepare_surfaces(args, tmpdir, surface_log)
            if args.method == "split" and args.femur_mesh == "split":
                fem = mesh_body_robust("femur", args.femur, args, tmpdir)
                tib = mesh_body_robust("tibia", args.insert, args, tmpdir)
                methods = {"femur": "split tetrahedra", "tibia": "split tetrahedra"}
            else:
                parts = [Part("femur", args.femur, args, tmpdir), Part("tibia", args.insert, args, tmpdir)]
                near = [p.articular_points(1.5) for p in parts]
                if args.method == "auto":
                    parts[1].femur = parts[0].surface_triangles(1.5)  # a post's clearance (insert_sweep)
                if args.femur_mesh == "split":
                    gmsh.model.setCurrent("femur")
                    fem = mesh_body("femur", args.femur, args, tmpdir, linear=True, part=parts[0])
                    methods["femur"] = "split tetrahedra (straight-sided)"
                else:
                    fem, methods["femur"] = mesh_part_robust(parts[0], args, tmpdir, near[1])
                if args.method == "split":
                    gmsh.model.setCurrent("tibia")
                    tib = mesh_body("tibia", args.insert, args, tmpdir, linear=True, part=parts[1])
                    methods["tibia"] = "split tetrahedra (straight-sided)"
                else:
                    tib, methods["tibia"] = mesh_part_robust(parts[1], args, tmpdir, near[0])
                sweep_log = getattr(parts[1], "log", [])
    finally:
        gmsh.finalize()
    report = (
        [
            "mesh-implant report (meshes/gen/mesh_implant.py)",
            "",
            "femur:  %s" % inputs[0],
            "insert: %s" % inputs[1],
            "options: "
            + " ".join(
                "--%s %s" % (k.replace("_", "-"), v)
                for k, v in sorted(vars(args).items())
                if v is not None and k not in ("femur", "insert", "output", "tagged")
            ),
            "",
        ]
        + surface_log
        + [""] * bool(surface_log)
        + sweep_log
    )

    def say(line):
        print(line)
        report.append(line)

    tib, off_seat, seat_area = seat_only(tib)
    if off_seat:
        say(
            "tibia_inferior: the seat only (%.1f mm^2), %d quadrangles of the underside off it "
            "(a recess's floor, a rounded rim) left traction free" % (seat_area, off_seat)
        )
    fn = fem[0].copy()
    if args.offset:
        d = np.array([float(t) for t in args.offset.split(",")])
        if d.shape != (3,):
            raise SystemExit("error: --offset needs DX,DY,DZ")
        fn += d
        fem = (fn, fem[1], fem[2])
        say("femur translated by (%g, %g, %g) mm" % tuple(d))
    else:
        g0 = min_vertical_gap(fem, tib)
        fn[:, 2] += args.gap - g0
        fem = (fn, fem[1], fem[2])
        say("femur moved along z by %+.4f mm to an initial gap of %g mm" % (args.gap - g0, args.gap))
        if args.gap - g0 > 0.5:
            # More than facets explain (tkr-wear's Gait/Largest initial overlap, 0.5 mm): the
            # input bodies intersect, e.g. the femur's box in the insert's post.
            say(
                "warning: the femur was lifted by %.2f mm off the insert: the input bodies intersect "
                "by more than their facets explain (0.5 mm); check the assembly (doc/robustness.md)"
                % (args.gap - g0)
            )
    say("smallest vertical gap between the articular surfaces: %.4f mm" % min_vertical_gap(fem, tib))
    refuse_impractical({"femur": fem, "tibia": tib}, methods, args)
    blockmesh.write_msh(args.output, {"femur": fem, "tibia": tib}, "mesh-implant")
    s = blockmesh.summary({"femur": fem, "tibia": tib})
    for b in ("femur", "tibia"):
        say(
            "%s (%s): %d vertices, %d hexahedra, volume %.1f mm^3, min scaled corner Jacobian %.3f, quads %s"
            % (
                b,
                methods[b],
                s[b]["vertices"],
                s[b]["hexahedra"],
                s[b]["volume"],
                s[b]["min_quality"],
                s[b]["quads"],
            )
        )
    # The quality where the bodies touch: the hexahedra with a face on an
    # articular surface.
    for body in (fem, tib):
        for g, (n, q) in contact_layer.contact_layer_quality(*body).items():
            say("contact layer %s: %d hexahedra, min scaled corner Jacobian %.3f" % (g, n, q))
    say(
        "wrote %s (%d Q1 displacement DoFs)"
        % (args.output, 3 * (s["femur"]["vertices"] + s["tibia"]["vertices"]))
    )
    # The flexion axis, which the CAD does not state: estimated from the
    # distal arcs of the condyles, written with the mesh into a parameter file.
    rep = os.path.splitext(args.output)[0] + "-report.txt"
    try:
        axis = flexion_axis.estimate(fn[np.unique(fem[2]["femur_contact"])])
    except ValueError as e:
        say("warning: no flexion axis estimate (%s); set Gait/Flexion axis point yourself" % e)
        axis = None
    if axis is not None:
        say(flexion_axis.describe(axis))
        prm = os.path.splitext(args.output)[0] + ".prm"
        tibia_x = tib[0][np.unique(tib[2]["tibia_contact"]), 0]
        with open(prm, "w") as f:
            f.write(flexion_axis.prm_fragment(args.output, axis, float(np.ptp(tibia_x))))
        say("wrote %s (a parameter file for the wear run: check the flexion axis and the medial side)" % prm)
    with open(rep, "w") as f:
        f.write("\n".join(report) + "\n")
    print("wrote %s" % rep)
    return 0


def run(argv=None):
    """main() with every failure as one message and exit 1, never a
    traceback (SystemExit messages pass through)."""
    try:
        return main(argv)
    except SystemExit:
        raise
    except KeyboardInterrupt:
        raise SystemExit("error: interrupted")
    except Exception as exc:  # gmsh raises plain Exception
        if type(exc) is Exception:
            raise SystemExit(gmsh_failure(exc))
        if isinstance(exc, RuntimeError) and " --" in str(exc):
            raise SystemExit("error: %s" % exc)  # the mesher's own refusal, naming the option to change
        raise SystemExit(
            "error: %s: %s (an internal error of mesh-implant; please report it with the "
            "command line)" % (type(exc).__name__, exc)
        )


if __name__ == "__main__":
    sys.exit(run())
