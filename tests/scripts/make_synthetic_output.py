#!/usr/bin/env python3
# SPDX-License-Identifier: LGPL-2.1-or-later
"""Write a SYNTHETIC output directory of a tkr-wear long run for
scripts/plot-wear: wear_history.csv, wear_map.csv, wear_map_faces.csv and
summary.json (formats in doc/output.md). Nothing here comes from a
simulation. Plain Python (no numpy), so any python3 runs it.

  make_synthetic_output.py DIR              tiny case for the test: a 10 x 10
                                            node grid with a Gaussian wear
                                            depth, a 5-row history
  make_synthetic_output.py DIR --insert     a kidney-shaped 70 x 50 mm
                                            surface with one elliptical wear
                                            patch per condyle (0..0.4 mm) and
                                            101 blocks of n_Delta = 5e4
                                            (the images of doc/output.md)
  --nodes NU NV                             grid of the --insert surface
"""
import argparse
import json
import math
import os
import sys

# The names of the result files' keys and columns (doc/output.md).
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "python"))
import tkr_results  # noqa: E402

DENSITY_MG_PER_MM3 = 0.935  # UHMWPE (DESIGN.md section 2)
THRESHOLD_MM = 1e-4


def grid(nu, nv, place):
    """Structured nu x nv nodes; place(u, v) with u, v in [-1, 1] gives
    (x, y, z); faces counter-clockwise, 0-based."""
    nodes = [place(-1 + 2 * i / (nu - 1), -1 + 2 * j / (nv - 1)) for j in range(nv) for i in range(nu)]
    faces = [
        (j * nu + i, j * nu + i + 1, (j + 1) * nu + i + 1, (j + 1) * nu + i)
        for j in range(nv - 1)
        for i in range(nu - 1)
    ]
    return nodes, faces


def kidney(u, v):
    """A 70 x 50 mm rounded rectangle with a posterior notch, two dished
    condyles (z only for the record: the plot looks from above)."""
    # Square -> unit disk (elliptical grid mapping), then stretched
    # radially onto the superellipse |x|^4 + |y|^4 = 1 (rounded corners).
    dx, dy = u * math.sqrt(1 - v * v / 2), v * math.sqrt(1 - u * u / 2)
    theta = math.atan2(dy, dx)
    stretch = (abs(math.cos(theta)) ** 4 + abs(math.sin(theta)) ** 4) ** -0.25
    x, y = 35 * stretch * dx, 25 * stretch * dy
    y += 9 * math.exp(-((x / 9) ** 2)) * ((1 - v) / 2) ** 3  # notch at y < 0
    z = 2 - 2.5 * sum(math.exp(-(((x - c) / 12) ** 2) - (y / 16) ** 2) for c in (-18, 18))
    return x, y, z


def patch(x, y, cx, cy, a, b, depth, power=1.2):
    """Elliptical wear patch: depth (1 - r^2)^power inside the ellipse."""
    r2 = ((x - cx) / a) ** 2 + ((y - cy) / b) ** 2
    return depth * (1 - r2) ** power if r2 < 1 else 0.0


def volume_and_area(nodes, depths, faces):
    """Worn volume (mm^3) and worn-area fraction from the projected quads
    (mean node depth times area: fine for synthetic numbers)."""
    volume = area = worn = 0.0
    for f in faces:
        p = [nodes[n] for n in f]
        a = 0.5 * abs(sum(p[k][0] * p[(k + 1) % 4][1] - p[(k + 1) % 4][0] * p[k][1] for k in range(4)))
        d = sum(depths[n] for n in f) / 4
        volume += a * d
        area += a
        worn += a if d > THRESHOLD_MM else 0.0
    return volume, 100 * worn / area


def write(directory, nodes, depths, faces, history, summary, history_columns):
    os.makedirs(directory, exist_ok=True)
    with open(os.path.join(directory, "wear_map.csv"), "w") as f:
        # a made-up cross-shear, 0 .. 0.5 across the surface
        f.write(",".join(tkr_results.WEAR_MAP_COLUMNS) + "\n")
        for (x, y, z), d in zip(nodes, depths):
            cs = 0.25 + 0.2 * math.sin(0.1 * x) * math.cos(0.1 * y)
            f.write(f"{x:.6g},{y:.6g},{z:.6g},{d:.6g},{cs:.6g}\n")
    with open(os.path.join(directory, "wear_map_faces.csv"), "w") as f:
        f.write(",".join(tkr_results.WEAR_MAP_FACES_COLUMNS) + "\n")
        for face in faces:
            f.write(",".join(map(str, face)) + "\n")
    with open(os.path.join(directory, "wear_history.csv"), "w") as f:
        f.write(",".join(history_columns) + "\n")
        for row in history:
            f.write(",".join(f"{row[c]:.6g}" for c in history_columns) + "\n")
    with open(os.path.join(directory, "summary.json"), "w") as f:
        json.dump(summary, f, indent=2)
        f.write("\n")


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("directory")
    parser.add_argument("--insert", action="store_true", help="the realistic kidney-shaped insert")
    parser.add_argument("--nodes", type=int, nargs=2, default=(71, 51), metavar=("NU", "NV"))
    arguments = parser.parse_args()

    if arguments.insert:
        nodes, faces = grid(*arguments.nodes, kidney)
        depths = [
            patch(x, y, -17.5, 1.5, 7.5, 11.0, 0.40) + patch(x, y, 18.0, -0.5, 7.0, 11.5, 0.30)
            for x, y, _ in nodes
        ]
        blocks, cycles_per_block = 100, 5e4
    else:
        nodes, faces = grid(10, 10, lambda u, v: (4.5 * u + 4.5, 4.5 * v + 4.5, 0.0))
        depths = [0.05 * math.exp(-((x - 4.5) ** 2 + (y - 4.5) ** 2) / 4) for x, y, _ in nodes]
        blocks, cycles_per_block = 4, 1.25e6

    volume, area_percent = volume_and_area(nodes, depths, faces)
    d_max = max(depths)
    history = []
    for block in range(blocks + 1):
        s = block / blocks  # wear grows linearly, as in the simulation
        history.append(
            {
                "block": block,
                "cycles": block * cycles_per_block,
                "volume_mm3": s * volume,
                "mass_mg": s * volume * DENSITY_MG_PER_MM3,
                "max_depth_mm": s * d_max,
                "wear_area_percent": area_percent if block else 0.0,
                "peak_pressure_MPa": 0.0 if block == 0 else 24.0 - 4 * s,
                "max_contact_area_mm2": 0.0 if block == 0 else 310 + 60 * s,
                "wall_time_s": 950.0 * block,
                "pose_updates": 3,
            }
        )
    # Columns in a different order than the list in doc/output.md, and one
    # extra column (pose_updates, not one of wear_history.csv): plot-wear
    # finds them by name and ignores the rest.
    columns = [
        "block",
        "cycles",
        "mass_mg",
        "volume_mm3",
        "max_depth_mm",
        "wear_area_percent",
        "peak_pressure_MPa",
        "max_contact_area_mm2",
        "pose_updates",
        "wall_time_s",
    ]
    summary = {
        "problem": "wear (SYNTHETIC, for plot-wear)",
        "cycles": blocks * cycles_per_block,
        "mass_loss_mg": volume * DENSITY_MG_PER_MM3,
        "volume_loss_mm3": volume,
        "max_wear_depth_mm": d_max,
        "wear_area_percent": area_percent,
        "wear_area_threshold_mm": THRESHOLD_MM,
        "converged": True,
    }
    extra = [c for c in columns if c not in tkr_results.WEAR_HISTORY_COLUMNS]
    assert extra == ["pose_updates"], extra
    problems = tkr_results.check_summary_data(summary)
    if problems:  # a key renamed in the schema and not here
        raise SystemExit("make_synthetic_output: " + "; ".join(problems))
    write(arguments.directory, nodes, depths, faces, history, summary, columns)


if __name__ == "__main__":
    main()
