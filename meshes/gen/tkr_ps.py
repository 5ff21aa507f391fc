# SPDX-License-Identifier: LGPL-2.1-or-later
"""TKR variant C: a posterior-stabilised (PS) knee, made from the parametric
TKR of tkr.py (doc/geometry.md, "TKR C").

Femoral component: the J-curve sweep of tkr.py (two condyles, an anterior
bridge, the intercondylar notch open behind theta_notch) whose notch is the
intercondylar box: its walls are the condyles' inner faces (x = +-x_in), and
a cam -- a cylinder along x of radius cam_radius -- joins the posterior
condyles across the box.  Its axis lies at the inset cam_eta from the
J-curve at theta = cam_theta, so that it lies between the condyles' inner
walls (its end discs on them) near their posterior tips.

Insert: the dished insert of tkr.py with larger dish radii than A (lower
sagittal and frontal conformity) and a central tibial post between the
dishes: a prism along x (half width post_half_width) whose sagittal section
has a vertical posterior face at y = post_back, a top at z = post_top and
an anterior face vertical at y = post_front up to z = post_chamfer, then
chamfered to (post_front_top, post_top); it rises from post_base (inside
the insert) into the femur's box.  (All four sides of the post are
vertical where they meet the dishes and the plateau: the insert is then a
height field with steps along vertical walls, which insert_sweep.py
meshes as columns; an anterior face inclined down to the articular
surface would not be.)

With the femur rotated about the distal-arc centre (the flexion axis) and
lowered onto the dishes (clearance_report()), the post stays clear of the
box walls, the cam and the bridge up to 60 deg of flexion; the cam meets
the post's posterior face beyond that (cam_engagement()).
"""
import math

import numpy as np

import tkr

DEG = math.pi / 180.0

# the shell and the dishes (same keys as tkr.VARIANTS)
VARIANT = dict(
    width=72.0,
    depth=48.0,
    r_corner=12.0,
    t_min=8.0,
    plateau=5.0,
    x_c=21.0,
    y_dish=-1.0,
    R_ts=80.0,
    R_tf=36.0,
    R_d=40.0,
    R_p=20.0,
    R_a=24.0,
    th_fa=-75.0,
    th_0=-20.0,
    th_1=20.0,
    th_2=110.0,
    th_notch=-55.0,
    L_flange=20.0,
    R_f=24.0,
    w_condyle=11.0,
    r_edge=4.0,
    alpha_edge=40.0,
    t_fem=8.0,
    gap=1e-3,
)
# the posterior stabilisation
PS = dict(
    post_half_width=7.0,
    post_back=7.0,
    post_front=17.0,
    post_front_top=14.0,
    post_chamfer=21.0,
    post_top=27.0,
    post_base=9.0,
    cam_theta=105.0,
    cam_eta=4.5,
    cam_radius=3.0,
)


class Geometry(tkr.Geometry):
    """tkr.Geometry of variant C plus the post and the cam."""

    def __init__(self):
        super().__init__("c", VARIANT)
        for k, v in PS.items():
            setattr(self, k, v)
        self.ps = dict(PS)
        s = self.s_of_theta(self.cam_theta)
        Q, n, _ = self.curve(np.array([s]))
        self.cam_centre = Q[0] - self.cam_eta * n[0]  # (y, z) at 0 deg
        assert self.cam_eta + self.cam_radius < self.t_fem  # inside the component
        assert self.post_half_width < self.x_in

    # ------------------------------------------------------------ post
    def post_polygon(self):
        """Sagittal section of the post, (y, z), counter-clockwise."""
        return np.array(
            [
                [self.post_back, self.post_base],
                [self.post_front, self.post_base],
                [self.post_front, self.post_chamfer],
                [self.post_front_top, self.post_top],
                [self.post_back, self.post_top],
            ]
        )

    def post_distance(self, P):
        """Signed distance of points P (n x 3) from the post solid (negative
        inside)."""
        poly = self.post_polygon()
        yz = P[:, 1:]
        # signed distance to the convex polygon: max over the edges' half planes
        # outside, exact distance to the polygon where outside
        d_edges = []
        inside = np.ones(len(P), bool)
        for i in range(len(poly)):
            a, b = poly[i], poly[(i + 1) % len(poly)]
            e = b - a
            nrm = np.array([e[1], -e[0]]) / np.linalg.norm(e)  # outward (ccw polygon)
            side = (yz - a) @ nrm
            inside &= side <= 0
            t = np.clip(((yz - a) @ e) / (e @ e), 0, 1)
            d_edges.append(np.linalg.norm(yz - (a + t[:, None] * e), axis=1))
        d_yz = np.min(d_edges, axis=0)
        d_yz = np.where(inside, -d_yz, d_yz)
        d_x = np.abs(P[:, 0]) - self.post_half_width
        outside = np.hypot(np.maximum(d_yz, 0), np.maximum(d_x, 0))
        return np.where((d_yz <= 0) & (d_x <= 0), np.maximum(d_yz, d_x), outside)

    # ------------------------------------------------------------ femur samples
    def femur_features(self, step=0.25):
        """Points (femur frame, 0 deg) on the surfaces that could meet the
        post: the box walls (the condyles' inner faces, x = +-x_in, from the
        articular side to the fixation side, behind theta_notch), the cam's
        cylinder and the notch's front wall (the bridge's posterior face).
        Returns {name: points (n x 3)}."""
        out = {}
        s = np.arange(self.s_notch, self.S[4], step)
        w = np.linspace(0.0, 1.0, 17)
        walls = []
        for x in (-self.x_in, self.x_in):
            S, W = np.meshgrid(s, w, indexing="ij")
            walls.append(self.femur_point(np.full(S.shape, x), S, W).reshape(-1, 3))
        out["box walls"] = np.concatenate(walls)
        ang = np.linspace(0, 2 * math.pi, 73)[:-1]
        xs = np.arange(-self.x_in, self.x_in + 1e-9, step)
        X, A = np.meshgrid(xs, ang, indexing="ij")
        cam = np.stack(
            [
                X,
                self.cam_centre[0] + self.cam_radius * np.cos(A),
                self.cam_centre[1] + self.cam_radius * np.sin(A),
            ],
            axis=-1,
        )
        out["cam"] = cam.reshape(-1, 3)
        xs = np.arange(-self.x_in, self.x_in + 1e-9, step)
        X, W = np.meshgrid(xs, w, indexing="ij")
        out["notch front wall"] = self.femur_point(X, np.full(X.shape, self.s_notch), W).reshape(-1, 3)
        return out

    def flex(self, P, phi_deg, drop=0.0):
        """Points of the femur frame after the rigid flexion rotation about
        the distal-arc centre (as tkr.Geometry.femur_lower_surface) and a
        drop along -z."""
        phi = phi_deg * DEG
        c, sn = math.cos(phi), math.sin(phi)
        d = P[:, 1:] - self.C_d
        out = P.copy()
        out[:, 1] = self.C_d[0] + c * d[:, 0] - sn * d[:, 1]
        out[:, 2] = self.C_d[1] + sn * d[:, 0] + c * d[:, 1] - drop
        return out


# ---------------------------------------------------------------- checks
def touch_drop(g, phi, step=0.25):
    """How far the femur, rotated by phi, must be lowered until its condyles
    touch the dishes (the gap at the touch point of tkr.clearance_report)."""
    xs = np.arange(-g.A, g.A + 1e-9, step)
    ys = np.arange(-g.B, g.B + 1e-9, step)
    X, Y = np.meshgrid(xs, ys, indexing="ij")
    inside = g.outline_sd(np.stack([X, Y], -1)) < 0
    gap = np.where(inside, g.femur_lower_surface(X, Y, phi) - g.tibia_top(X, Y), np.inf)
    return float(gap.min()) - g.gap


def clearance_report(g, flexions=(0, 10, 20, 30, 40, 50, 60)):
    """The dish/condyle contact check of tkr.clearance_report (without the
    post), then the clearance of the post from the box walls, the cam and
    the notch's front wall, the femur rotated about the distal-arc centre
    and lowered onto the dishes.  Negative = the post penetrates."""
    lines = clearance_lines_dishes(g, flexions)
    feats = g.femur_features()
    for phi in flexions:
        drop = touch_drop(g, phi)
        parts = []
        for name, P in feats.items():
            d = g.post_distance(g.flex(P, phi, drop))
            parts.append("%s %.2f" % (name, d.min()))
        lines.append("flexion %4.0f deg: post clearance (mm) from the %s" % (phi, "; ".join(parts)))
    return lines


def clearance_lines_dishes(g, flexions):
    """tkr.clearance_report on geometry g (it takes a variant name)."""
    saved = tkr.Geometry
    try:
        tkr.Geometry = lambda variant: g
        return tkr.clearance_report("c", flexions)
    finally:
        tkr.Geometry = saved


def cam_engagement(g, step=2.0, tol=0.1, top=120.0):
    """The flexion angle (deg, within tol) at which the cam first touches
    the post: a scan in steps of `step` deg, then bisection; None if not
    up to `top` deg."""
    cam = g.femur_features()["cam"]

    def clear(phi):
        return g.post_distance(g.flex(cam, phi, touch_drop(g, phi))).min()

    lo = 0.0
    while lo + step <= top and clear(lo + step) > 0.0:
        lo += step
    if lo + step > top:
        return None
    hi = lo + step
    while hi - lo > tol:
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if clear(mid) > 0.0 else (lo, mid)
    return hi


def cam_over_insert(g, phi):
    """Smallest vertical clearance of the cam above the insert's articular
    surface (dishes and plateau, the post left out) at flexion phi."""
    cam = g.flex(g.femur_features()["cam"], phi, touch_drop(g, phi))
    inside = g.outline_sd(cam[:, :2]) < 0
    if not np.any(inside):
        return np.inf
    return float(np.min(cam[inside, 2] - g.tibia_top(cam[inside, 0], cam[inside, 1])))


# ---------------------------------------------------------------- CAD
def build_occ(g, which=("femur", "tibia")):
    """The CAD solids of C in the current gmsh model: tkr.build_occ plus the
    cam (femur) and the post (insert), fused.  Returns {name: [tags]}."""
    import gmsh

    occ = gmsh.model.occ
    res = tkr.build_occ(g, which)
    if "femur" in which:
        yc, zc = g.cam_centre
        cam = occ.addCylinder(-g.x_in, yc, zc, 2 * g.x_in, 0, 0, g.cam_radius)
        out, _ = occ.fuse([(3, t) for t in res["femur"]], [(3, cam)])
        occ.synchronize()
        res["femur"] = [t for d, t in out if d == 3]
    if "tibia" in which:
        w = g.post_half_width
        pts = [occ.addPoint(-w, y, z) for y, z in g.post_polygon()]
        lines = [occ.addLine(pts[i], pts[(i + 1) % len(pts)]) for i in range(len(pts))]
        face = occ.addPlaneSurface([occ.addCurveLoop(lines)])
        post = [dt for dt in occ.extrude([(2, face)], 2 * w, 0, 0) if dt[0] == 3]
        out, _ = occ.fuse([(3, t) for t in res["tibia"]], post)
        occ.synchronize()
        res["tibia"] = [t for d, t in out if d == 3]
    return res


def cad_volumes(g):
    import gmsh

    gmsh.initialize(["gmsh", "-v", "0"])
    try:
        gmsh.model.add("c")
        tags = build_occ(g)
        return {k: sum(gmsh.model.occ.getMass(3, t) for t in v) for k, v in tags.items()}
    finally:
        gmsh.finalize()


def face_sizes_for_deviation(deviation, h_max, samples=12):
    """{face: triangle size} of the current model for a chordal deviation:
    sqrt(8 deviation R) with R the smallest principal radius of curvature
    found on the face (sampled on its parameter domain), at most h_max."""
    import gmsh

    sizes = {}
    for _, s in gmsh.model.getEntities(2):
        lo, hi = gmsh.model.getParametrizationBounds(2, s)
        u = np.linspace(lo[0], hi[0], samples)
        v = np.linspace(lo[1], hi[1], samples)
        U, V = np.meshgrid(u, v, indexing="ij")
        uv = np.column_stack([U.ravel(), V.ravel()]).ravel()
        kmax, kmin, _, _ = gmsh.model.getPrincipalCurvatures(s, uv)
        k = float(np.max(np.abs(np.concatenate([kmax, kmin]))))
        sizes[s] = h_max if k < 1e-9 else min(h_max, math.sqrt(8.0 * deviation / k))
    return sizes


def chordal_stl(path, deviation=0.3, h_max=12.0):
    """Write the current model's surface as a binary STL faceted the way
    CAD exporters do it (triangle sizes from a chordal tolerance, long
    triangles on flat faces) and return the largest measured distance of
    the facets (centroids, edge midpoints) from the CAD faces."""
    import gmsh

    sizes = face_sizes_for_deviation(deviation, h_max)

    def size(dim, tag, x, y, z):
        if dim == 2:
            return sizes.get(tag, h_max)
        if dim == 1:
            return min([sizes[f] for f in gmsh.model.getAdjacencies(1, tag)[0]] or [h_max])
        return min(
            [
                sizes[f]
                for c in gmsh.model.getAdjacencies(0, tag)[0]
                for f in gmsh.model.getAdjacencies(1, c)[0]
            ]
            or [h_max]
        )

    gmsh.model.mesh.setSizeCallback(size)
    gmsh.option.setNumber("Mesh.MeshSizeFromPoints", 0)
    gmsh.option.setNumber("Mesh.MeshSizeFromCurvature", 0)
    gmsh.option.setNumber("Mesh.MeshSizeExtendFromBoundary", 0)
    gmsh.option.setNumber("Mesh.MeshSizeMax", h_max)
    gmsh.option.setNumber("Mesh.Algorithm", 6)
    try:
        gmsh.model.mesh.generate(2)
    finally:
        gmsh.model.mesh.removeSizeCallback()
    tags, coords, _ = gmsh.model.mesh.getNodes()
    X = np.zeros((int(tags.max()) + 1, 3))
    X[tags.astype(np.int64)] = coords.reshape(-1, 3)
    worst = 0.0
    for _, s in gmsh.model.getEntities(2):
        for et, _, nt in zip(*gmsh.model.mesh.getElements(2, s)):
            T = X[np.array(nt, np.int64).reshape(-1, 3)]
            P = np.concatenate(
                [
                    T.mean(axis=1),
                    0.5 * (T[:, 0] + T[:, 1]),
                    0.5 * (T[:, 1] + T[:, 2]),
                    0.5 * (T[:, 2] + T[:, 0]),
                ]
            )
            q, _ = gmsh.model.getClosestPoint(2, s, P.reshape(-1))
            worst = max(worst, float(np.linalg.norm(np.array(q).reshape(-1, 3) - P, axis=1).max()))
    gmsh.option.setNumber("Mesh.Binary", 1)
    gmsh.write(path)
    return worst


def export_cad(outdir, deviation=0.25):
    """tkr-c-femur.step/.stl and tkr-c-insert.step/.stl in outdir; returns
    [(file, chordal deviation of the STL or None)]."""
    import os

    import gmsh

    g = Geometry()
    out = []
    for name, fname in (("femur", "femur"), ("tibia", "insert")):
        gmsh.initialize(["gmsh", "-v", "0"])
        try:
            gmsh.model.add(name)
            build_occ(g, (name,))
            base = os.path.join(outdir, "tkr-c-%s" % fname)
            gmsh.write(base + ".step")
            out.append((base + ".step", None))
            out.append((base + ".stl", chordal_stl(base + ".stl", deviation)))
        finally:
            gmsh.finalize()
    return out


# ---------------------------------------------------------------- mesh
def femur_contact_without_cam(step):
    """The face ids (in scripts/mesh-implant's numbering of the STEP file)
    of femur_contact by mesh-implant's rule, less the cam's cylinder (the
    cam does not reach the post below 60 deg of flexion, cam_engagement(),
    and its 3 mm radius folds a coarse contact layer)."""
    import argparse
    import contextlib
    import io
    import tempfile

    import gmsh
    import mesh_implant

    g = Geometry()
    args = argparse.Namespace(
        units="mm",
        rotation=None,
        feature_angle=40.0,
        size=8.0,
        femur_contact_faces=None,
        femur_fixation_faces=None,
        tibia_contact_faces=None,
        tibia_inferior_faces=None,
    )
    gmsh.initialize(["gmsh", "-v", "0"])
    try:
        with tempfile.TemporaryDirectory() as tmp, contextlib.redirect_stdout(io.StringIO()):
            part = mesh_implant.Part("femur", step, args, tmp)
        ids = []
        for s in part.contact:
            lo = np.array(gmsh.model.getBoundingBox(2, s))
            c = np.array(gmsh.model.occ.getCenterOfMass(2, s))
            cam = (
                gmsh.model.getType(2, s) == "Cylinder"
                and lo[0] >= -g.x_in - 1e-6
                and lo[3] <= g.x_in + 1e-6
                and np.linalg.norm(c[1:] - g.cam_centre) < g.cam_radius
            )
            if not cam:
                ids.append(s)
    finally:
        gmsh.finalize()
    return sorted(ids)


COARSE = [
    # the whole component with a contact layer, as when tkr-c-coarse.msh was
    # made (mesh-implant's default is now the articular shell)
    "--femur-mesh",
    "layer",
    "--contact-size",
    "5",
    "--size",
    "12",
    "--layers",
    "1",
    "--layer-thickness",
    "1.0",
    "--sweep-size",
    "3",
    "--sweep-cells",
    "4",
]


def make_coarse(path, cad_dir):
    """tkr-c-coarse.msh: scripts/mesh-implant with COARSE on
    tkr-c-{femur,insert}.step in cad_dir, the cam left out of femur_contact
    (femur_contact_without_cam).  Returns the text of mesh-implant's report
    and the .prm fragment."""
    import os
    import shutil
    import tempfile

    import mesh_implant

    femur = os.path.join(cad_dir, "tkr-c-femur.step")
    insert = os.path.join(cad_dir, "tkr-c-insert.step")

    def rel(p):
        return os.path.join("meshes/tkr/cad", os.path.basename(p))

    argv = (
        ["--femur", rel(femur), "--insert", rel(insert)]
        + COARSE
        + ["--femur-contact-faces", ",".join(map(str, femur_contact_without_cam(femur)))]
    )
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, "tkr-c-coarse.msh")
        cwd = os.getcwd()
        os.chdir(os.path.dirname(os.path.dirname(os.path.dirname(cad_dir))))
        try:
            mesh_implant.main(argv + ["-o", out])
        finally:
            os.chdir(cwd)
        shutil.move(out, path)
        with open(os.path.join(tmp, "tkr-c-coarse-report.txt")) as f:
            text = f.read()
        with open(os.path.join(tmp, "tkr-c-coarse.prm")) as f:
            prm = f.read()
    # the exact flexion axis (the distal-arc centre, moved with the femur)
    # instead of mesh-implant's estimate, which the coarse facets bias
    import re

    g = Geometry()
    dz = float(re.search(r"femur moved along z by ([-+0-9.]+) mm", text).group(1))
    prm = re.sub(
        r"set Flexion axis point = .*",
        "set Flexion axis point = 0, %.3f, %.3f\n  # (replaced by tkr_ps.make_coarse: the "
        "distal-arc centre of the CAD, moved by %+.4f mm with the femur)" % (g.C_d[0], g.C_d[1] + dz, dz),
        prm,
    )
    return text.replace(tmp + "/", ""), prm.replace(tmp + "/", "meshes/tkr/")


def geometry_report(mesh_report=None, mesh_check=None):
    """Text of meshes/tkr/tkr-c-report.txt: parameters, derived dimensions,
    flexion axis, CAD volumes, the clearances over 0-60 deg, and the coarse
    mesh (mesh-implant's report, check_msh's result)."""
    g = Geometry()
    vols = cad_volumes(g)
    fem = g.femur_point(
        np.linspace(-g.x_out, g.x_out, 5)[:, None], np.linspace(0, g.S[4], 2000)[None, :], 0.0
    ).reshape(-1, 3)
    L = [
        "TKR variant C (posterior-stabilised): geometry report (generated by meshes/gen/tkr_ps.py; mm)",
        "",
        "parameters (shell and dishes, as tkr.py):",
    ]
    L += ["  %-16s %g" % kv for kv in VARIANT.items()]
    L += ["parameters (post and cam):"] + ["  %-16s %g" % kv for kv in PS.items()]
    L += [
        "",
        "derived:",
        "  insert: width %.1f (x), depth %.1f (y), height %.1f at the plateau, %.1f at the post top; "
        "minimum thickness %.1f at the dish bottoms (+-%.1f, %.1f, %.1f)"
        % (2 * g.A, 2 * g.B, g.H, g.post_top, g.t_min, g.x_c, g.y_dish, g.t_min),
        "  insert conformity: sagittal R_d/R_ts = %.2f (A 0.80), frontal R_f/R_tf = %.2f (A 0.93)"
        % (g.R_d / g.R_ts, g.R_f / g.R_tf),
        "  post: x -%.1f..%.1f (width %.1f), posterior face y = %.1f (vertical), anterior face y = %.1f "
        "(vertical) up to z = %.1f, chamfered to (y %.1f, z %.1f), top z = %.1f (%.1f above the plateau)"
        % (
            g.post_half_width,
            g.post_half_width,
            2 * g.post_half_width,
            g.post_back,
            g.post_front,
            g.post_chamfer,
            g.post_front_top,
            g.post_top,
            g.post_top,
            g.post_top - g.H,
        ),
        "  femoral component: width %.1f, AP extent %.1f (y %.1f..%.1f), height %.1f (z %.1f..%.1f); "
        "condyle width %.1f, condyle spacing %.1f"
        % (
            2 * g.x_out,
            np.ptp(fem[:, 1]),
            fem[:, 1].min(),
            fem[:, 1].max(),
            np.ptp(fem[:, 2]),
            fem[:, 2].min(),
            fem[:, 2].max(),
            2 * g.w_condyle,
            2 * g.x_c,
        ),
        "  intercondylar box: walls x = +-%.1f (width %.1f, %.1f mm from each side of the post), "
        "open behind theta = %.0f deg, no roof (the post never reaches the bone side)"
        % (g.x_in, 2 * g.x_in, g.x_in - g.post_half_width, g.th_notch),
        "  cam: cylinder along x between the box walls, radius %.1f, axis at (y, z) = (%.2f, %.2f) "
        "(inset %.1f from the J-curve at theta = %.0f deg)"
        % (g.cam_radius, g.cam_centre[0], g.cam_centre[1], g.cam_eta, g.cam_theta),
        "  J-curve: distal arc R_d centre (%.3f, %.3f); posterior arc R_p centre (%.3f, %.3f); "
        "anterior arc R_a centre (%.3f, %.3f)" % (g.C_d[0], g.C_d[1], g.C_p[0], g.C_p[1], g.C_a[0], g.C_a[1]),
        "  flexion axis point (parallel to x): (0, %.3f, %.3f), the distal-arc centre" % (g.C_d[0], g.C_d[1]),
        "  initial position (0 deg): lowest condyle points (+-%.1f, %.1f, %.4f), gap %.4g mm above "
        "the dish bottoms" % (g.x_c, g.y_dish, g.t_min + g.gap, g.gap),
        "  CAD volumes (OpenCASCADE): femur %.3f mm^3, insert %.3f mm^3" % (vols["femur"], vols["tibia"]),
        "",
        "exact-geometry contact check (femur rotated about the distal-arc centre, then lowered "
        "to touch the dishes):",
    ]
    L += ["  " + s for s in clearance_report(g)]
    L += [
        "  cam over the insert's dishes and plateau (vertical, mm): "
        + ", ".join("%.0f deg %.2f" % (p, cam_over_insert(g, p)) for p in (0, 20, 40, 60)),
        "  the cam meets the post's posterior face at %.1f deg of flexion" % cam_engagement(g),
    ]
    if mesh_report:
        L += [
            "",
            "meshes/tkr/tkr-c-coarse.msh: scripts/mesh-implant %s on the STEP files, with "
            "--femur-contact-faces leaving the cam out of femur_contact "
            "(tkr_ps.femur_contact_without_cam); its report:" % " ".join(COARSE),
        ]
        L += ["  " + s for s in mesh_report.splitlines()]
    if mesh_check:
        L += ["", "meshes/gen/check_msh.py:"] + ["  " + s for s in mesh_check.splitlines()]
    return "\n".join(L) + "\n"


def main(argv):
    """tkr_ps.py [cad] [mesh]: export the CAD files and/or make the coarse
    mesh and its report (scripts/generate-meshes tkr-c does both)."""
    import os
    import subprocess
    import sys

    here = os.path.dirname(os.path.abspath(__file__))
    meshes = os.path.dirname(here)
    cad_dir = os.path.join(meshes, "tkr", "cad")
    if not argv or "cad" in argv:
        for f, dev in export_cad(cad_dir):
            print(
                "made  %s (%.2f MB)%s"
                % (
                    os.path.relpath(f, meshes),
                    os.path.getsize(f) / 1e6,
                    "" if dev is None else ", chordal deviation %.3f mm" % dev,
                )
            )
    if not argv or "mesh" in argv:
        path = os.path.join(meshes, "tkr", "tkr-c-coarse.msh")
        text, prm = make_coarse(path, cad_dir)
        with open(os.path.join(meshes, "tkr", "tkr-c-coarse.prm"), "w") as f:
            f.write(prm)
        check = subprocess.run(
            [sys.executable, os.path.join(here, "check_msh.py"), path], capture_output=True, text=True
        )
        with open(os.path.join(meshes, "tkr", "tkr-c-report.txt"), "w") as f:
            f.write(geometry_report(text, check.stdout.replace(meshes + "/", "meshes/")))
        print("wrote tkr/tkr-c-coarse.msh, tkr/tkr-c-report.txt")
        return check.returncode
    return 0


if __name__ == "__main__":
    import sys

    sys.path.insert(0, __import__("os").path.dirname(__import__("os").path.abspath(__file__)))
    sys.exit(main(sys.argv[1:]))
