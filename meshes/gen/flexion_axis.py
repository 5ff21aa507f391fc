#!/usr/bin/env python3
"""Estimate the flexion axis of a femoral component from its femur_contact
surface: in the sagittal (y-z) plane through the lowest point of each
condyle, the surface's nodes within 1.5 mm of that plane (the lowest of
them in 1 mm bins of y) trace the J-curve;
a least-squares circle through the part of it within DEPTH mm of the
condyle's lowest point is the distal arc, whose centre the femur rotates
about (the flexion axis, parallel to x). The two condyles are the nodes on
either side of the middle of the surface's x range.

    meshes/gen/flexion_axis.py MESH.msh [--depth 2]

prints the estimate; scripts/mesh-implant calls estimate() and writes it
into the .prm fragment next to the mesh. Measured: 0.09 mm from the
generator's axis on the mesh-implant output of TKR A (0.000 mm on its
block-structured meshes), but 0.9-1.9 mm on TKR B, whose distal arc is
short (the window then reaches into the neighbouring arcs): check the
printed radii and rms, and the report of your CAD if it has one.
"""
import argparse
import sys

import numpy as np


def fit_circle(y, z):
    """Least-squares circle through (y, z) (Kasa's algebraic fit):
    centre (yc, zc), radius, rms distance of the points from the circle."""
    A = np.column_stack([y, z, np.ones_like(y)])
    b = -(y * y + z * z)
    (d, e, f), *_ = np.linalg.lstsq(A, b, rcond=None)
    yc, zc = -d / 2, -e / 2
    r = np.sqrt(yc * yc + zc * zc - f)
    rms = np.sqrt(np.mean((np.hypot(y - yc, z - zc) - r) ** 2))
    return yc, zc, r, rms


def condyle_arc(points, depth, band=1.5):
    """The distal arc of one condyle from its femur_contact nodes: those
    within @p band mm in x of the condyle's lowest node and within @p depth
    mm above it.  Their heights are first freed of the frontal (x) shape of
    the condyle: a parabola in x fitted to the nodes within 3 mm in y of
    the lowest one; then a circle is fitted to (y, z) of all of them.  (On
    unstructured meshes, whose nodes do not lie on the apex line, the
    frontal shape would otherwise lift the off-apex nodes and flatten the
    arc.)"""
    apex = points[np.argmin(points[:, 2])]
    near = points[(np.abs(points[:, 0] - apex[0]) <= band) & (points[:, 2] <= apex[2] + depth)]
    x, y, z = near[:, 0] - apex[0], near[:, 1], near[:, 2]
    middle = np.abs(y - apex[1]) <= 3.0
    if middle.sum() >= 4 and np.ptp(x[middle]) > 0.2 * band:
        (c, b, k), *_ = np.linalg.lstsq(
            np.column_stack([np.ones(middle.sum()), x[middle], x[middle] ** 2]),
            z[middle] - (y[middle] - apex[1]) ** 2 / 1e9,
            rcond=None,
        )
        if k > 0:
            z = z - b * x - k * x**2
    if len(y) < 5:
        raise ValueError("fewer than 5 nodes within %g mm of the lowest point" % depth)
    return fit_circle(y, z) + (int(len(y)),)


def estimate(nodes, depth=2.0):
    """nodes: femur_contact node coordinates (N x 3). Returns a dict with
    the axis point (0, yc, zc) and each condyle's arc."""
    x = nodes[:, 0]
    middle = 0.5 * (x.min() + x.max())
    arcs = {}
    for name, side in (("-x", x < middle), ("+x", x >= middle)):
        yc, zc, r, rms, n = condyle_arc(nodes[side], depth)
        arcs[name] = dict(
            centre=(yc, zc), radius=r, rms=rms, points=n, lowest_z=float(nodes[side][:, 2].min())
        )
    yc = np.mean([a["centre"][0] for a in arcs.values()])
    zc = np.mean([a["centre"][1] for a in arcs.values()])
    return dict(point=(0.0, float(yc), float(zc)), condyles=arcs)


def describe(result):
    lines = []
    for name, a in result["condyles"].items():
        lines.append(
            "  condyle at %s: distal arc centre (y, z) = (%.3f, %.3f) mm, radius %.2f mm, "
            "%d profile points, rms %.3f mm"
            % (name, a["centre"][0], a["centre"][1], a["radius"], a["points"], a["rms"])
        )
    lines.append("  flexion axis estimate: through (%.3f, %.3f, %.3f), parallel to x" % result["point"])
    lines += disagreement(result)
    return "\n".join(lines)


def disagreement(result, limit=2.0):
    """Lines on how far the two condyles' distal arcs disagree: the distance
    of their centres and the difference of their radii, and a warning where
    the centres are more than `limit` mm apart (tkr-wear warns with the
    same limit when the axis it is given is that far from a condyle's
    centre). A real component may have condyles of different sagittal
    radii: then no single axis is the centre of both, and about the mean
    one condyle rises against the other as the femur flexes."""
    arcs = list(result["condyles"].values())
    if len(arcs) != 2:
        return []
    poor = [name for name, a in result["condyles"].items() if a["rms"] > 0.1]
    if poor:
        # (the fit window reaching into the next arc or across a box: no
        # centre to compare; tkr-wear does not judge such an arc either)
        return [
            "  the condyles' distal arcs are not compared: the profile at %s is no circle within 0.1 mm"
            % poor[0]
        ]
    (y0, z0), (y1, z1) = arcs[0]["centre"], arcs[1]["centre"]
    apart = float(np.hypot(y1 - y0, z1 - z0))
    lines = [
        "  the condyles' distal arcs: centres %.2f mm apart (y %+.2f, z %+.2f mm), radii differ by %.2f mm"
        % (apart, y1 - y0, z1 - z0, arcs[1]["radius"] - arcs[0]["radius"])
    ]
    if apart > limit:
        lines.append(
            "  warning: the condyles' distal arcs are centred %.1f mm apart: no single axis is the "
            "centre of both, and the estimate (their mean) is %.1f mm from each. Use the component's "
            'design axis if its maker states one (doc/gait.md, "The flexion axis").' % (apart, 0.5 * apart)
        )
    return lines


def prm_fragment(mesh_path, result, insert_width):
    """A ready-to-run parameter file for the wear run on @p mesh_path, with
    the estimated flexion axis."""
    import os

    stem = os.path.splitext(os.path.basename(mesh_path))[0]
    condyles = result["condyles"]
    lines = [
        "# Written by mesh-implant for %s: the entries of a tkr-wear parameter" % mesh_path,
        "# file that depend on the implant; everything else keeps its default",
        "# (tkr-wear --print-parameters). Run it from the directory you ran",
        "# mesh-implant in:  mpirun -np 2 tkr-wear %s.prm" % stem,
        "set Problem = wear",
        "",
        "subsection Mesh",
        "  set File = %s" % mesh_path,
        "end",
        "",
        "subsection Gait",
        "  # Estimated from femur_contact (meshes/gen/flexion_axis.py): the centre",
        "  # of the distal arc of each condyle in the sagittal plane,",
    ]
    for name, a in condyles.items():
        lines.append(
            "  #   condyle at %s: (y, z) = (%.3f, %.3f), radius %.2f mm, rms %.3f mm"
            % (name, a["centre"][0], a["centre"][1], a["radius"], a["rms"])
        )
    lines += [
        "  # averaged. Check it against your CAD: a wrong axis moves the femur",
        "  # into or away from the insert as it flexes.",
    ]
    lines += ["  #" + line[1:] for line in disagreement(result)]
    lines += [
        "  set Flexion axis point = %.3f, %.3f, %.3f" % result["point"],
        "  # A GUESS: which side of x is medial depends on the knee (left or",
        "  # right) and cannot be read from the geometry. Confirm it.",
        "  set Medial side = +x",
        "  # The insert is %.1f mm wide in x (tkr-wear measures it itself; the" % insert_width,
        "  # axial load line is offset medially by 0.07 of it).",
        "end",
        "",
        "subsection Contact solver",
        "  set Initial contact distance = 0.05",
        "end",
        "",
        "subsection Output",
        "  set Directory = output/%s" % stem,
        "end",
    ]
    return "\n".join(lines) + "\n"


def read_group_nodes(path, group):
    """Coordinates of the nodes of a physical group of a .msh file."""
    import gmsh

    gmsh.initialize(["gmsh", "-v", "0"])
    try:
        gmsh.open(path)
        for dim, tag in gmsh.model.getPhysicalGroups(2):
            if gmsh.model.getPhysicalName(dim, tag) == group:
                _, coords = gmsh.model.mesh.getNodesForPhysicalGroup(dim, tag)
                return np.asarray(coords).reshape(-1, 3)
    finally:
        gmsh.finalize()
    raise SystemExit("error: %s has no physical group %s" % (path, group))


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("mesh")
    ap.add_argument(
        "--depth",
        type=float,
        default=2.0,
        help="height (mm) above the lowest point of the profile used for the fit",
    )
    ap.add_argument("--expect", help="Y,Z: exit 1 unless the estimate is within --tolerance of it")
    ap.add_argument("--tolerance", type=float, default=0.5)
    ap.add_argument("--prm", help="also write the parameter file of prm_fragment() here")
    args = ap.parse_args(argv)
    result = estimate(read_group_nodes(args.mesh, "femur_contact"), args.depth)
    print(describe(result))
    if args.prm:
        tibia = read_group_nodes(args.mesh, "tibia_contact")
        with open(args.prm, "w") as f:
            f.write(prm_fragment(args.mesh, result, float(np.ptp(tibia[:, 0]))))
        print("  wrote %s" % args.prm)
    if args.expect:
        y, z = (float(t) for t in args.expect.split(","))
        distance = np.hypot(result["point"][1] - y, result["point"][2] - z)
        print(
            "  distance from (%g, %g): %.3f mm (tolerance %g): %s"
            % (y, z, distance, args.tolerance, "ok" if distance <= args.tolerance else "FAILED")
        )
        return 0 if distance <= args.tolerance else 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
