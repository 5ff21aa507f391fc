#!/usr/bin/env python3
# SPDX-License-Identifier: LGPL-2.1-or-later
"""check_vtu.py RESULTS_DIR FLEXION_AXIS_POINT

Checks the content of the VTU output of a wear run (Problem = wear with
VTU interval = 1) against its steps.csv and summary.json:
  - step.pvd lists every step of steps.csv, each .pvtu and its pieces exist
    and hold the fields of the step output;
  - per step: the largest contact_pressure on the tibia equals
    max_pressure_MPa, the number of distinct nodes with active = 1 equals
    active_nodes, and the femur's 'motion' field is the rigid flexion
    rotation about the x axis through FLEXION_AXIS_POINT by flexion_deg
    (plus the femur's elastic displacement, below 0.01 mm);
  - worn.pvd (one block): the largest wear_depth_mm equals
    max_wear_depth_mm, and the largest wear rate times the block's cycles
    equals it too;
  - the worn tibia's cross_shear lies in 0 .. 0.5 and summary.json's
    mean_cross_shear between 0 and its largest value;
  - summary.json's medial and lateral volume and wear area add up to the
    insert's (1e-9), the larger of their depths is the insert's;
  - mass_loss.png, wear_map.png and cross_shear_map.png are PNG files.
Prints one line per check with O(1) numbers; exits 1 on the first failure.
Reads deal.II's zlib-compressed, base64-encoded VTU files with numpy only.
"""
import base64
import math
import os
import re
import sys
import zlib
import xml.etree.ElementTree as ET

import numpy as np

# The readers of the result files (doc/output.md, "Result files").
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "python"))
import tkr_results  # noqa: E402

TYPES = {
    "Float32": np.float32,
    "Float64": np.float64,
    "Int32": np.int32,
    "UInt8": np.uint8,
    "Int64": np.int64,
    "UInt32": np.uint32,
}


def fail(message):
    print("check_vtu: FAILED: " + message)
    sys.exit(1)


def decode(text, dtype):
    """An inline binary DataArray of a zlib-compressed VTU file (UInt32 header)."""
    text = "".join(text.split())
    first = base64.b64decode(text[:8])
    n_blocks = int(np.frombuffer(first[:4], np.uint32)[0])
    header_length = 4 * math.ceil(4 * (3 + n_blocks) / 3)
    header = np.frombuffer(base64.b64decode(text[:header_length]), np.uint32)
    sizes = header[3 : 3 + n_blocks]
    payload = base64.b64decode(text[header_length:])
    data, offset = b"", 0
    for size in sizes:
        data += zlib.decompress(payload[offset : offset + int(size)])
        offset += int(size)
    return np.frombuffer(data, dtype)


def read_vtu(path):
    """Points (n, 3) and point data {name: array (n, components)} of a .vtu."""
    root = ET.parse(path).getroot()
    if root.get("compressor") != "vtkZLibDataCompressor":
        fail(path + ": not a zlib-compressed VTU file")
    piece = root.find("UnstructuredGrid/Piece")
    points_array = piece.find("Points/DataArray")
    points = decode(points_array.text, TYPES[points_array.get("type")]).reshape(-1, 3)
    fields = {}
    for array in piece.find("PointData").findall("DataArray"):
        components = int(array.get("NumberOfComponents", "1"))
        values = decode(array.text, TYPES[array.get("type")])
        fields[array.get("Name")] = values.reshape(-1, components)
    return points, fields


def read_series(directory, name):
    """[(time, points, fields)] of NAME.pvd, all pieces joined."""
    pvd = os.path.join(directory, name + ".pvd")
    if not os.path.isfile(pvd):
        fail(pvd + " is missing")
    series = []
    for dataset in ET.parse(pvd).getroot().iter("DataSet"):
        pvtu = os.path.join(directory, dataset.get("file"))
        if not os.path.isfile(pvtu):
            fail(pvtu + " (listed in " + name + ".pvd) is missing")
        points, fields = [], {}
        for piece in ET.parse(pvtu).getroot().iter("Piece"):
            path = os.path.join(directory, piece.get("Source"))
            if not os.path.isfile(path):
                fail(path + " (listed in " + pvtu + ") is missing")
            p, f = read_vtu(path)
            points.append(p)
            for key, value in f.items():
                fields.setdefault(key, []).append(value)
        series.append(
            (float(dataset.get("timestep")), np.vstack(points), {k: np.vstack(v) for k, v in fields.items()})
        )
    return series


def close(a, b, rel):
    return abs(a - b) <= rel * max(abs(a), abs(b), 1e-30)


def main():
    if len(sys.argv) != 3:
        print(__doc__)
        sys.exit(2)
    directory = sys.argv[1]
    axis_point = np.array([float(v) for v in re.split(r"[ ,]+", sys.argv[2].strip())])
    try:
        steps = tkr_results.read_rows(
            os.path.join(directory, "steps.csv"), ("max_pressure_MPa", "active_nodes", "flexion_deg")
        )
        summary = tkr_results.read_summary(os.path.join(directory, "summary.json"))
        check(directory, axis_point, steps, summary)
    except tkr_results.ResultError as e:  # a result file not as documented
        fail(str(e))


def check(directory, axis_point, steps, summary):
    """The checks of the module's documentation on the run in @p directory
    (steps: the rows of its steps.csv, summary: its summary.json)."""
    series = read_series(directory, "step")
    times = [int(round(t)) for t, _, _ in series]
    if times != list(range(len(steps))):
        fail("step.pvd lists the steps %s, steps.csv has %d" % (times, len(steps)))
    print("step.pvd: %d steps, each with its pieces" % len(series))
    needed = {
        "displacement",
        "contact_pressure",
        "gap",
        "active",
        "motion",
        "slip_to_next_mm",
        "wear_to_next_pm",
        "material_id",
    }
    for (time, points, fields), row in zip(series, steps):
        step = int(round(time))
        missing = needed - set(fields)
        if missing:
            fail("step %d lacks the fields %s" % (step, sorted(missing)))
        tibia = fields["material_id"][:, 0] == 1
        pressure = fields["contact_pressure"][tibia, 0]
        expected = float(row["max_pressure_MPa"])
        if not close(pressure.max(), expected, 1e-5):
            fail("step %d: largest contact_pressure %g, steps.csv %g" % (step, pressure.max(), expected))
        active = points[tibia][fields["active"][tibia, 0] > 0.5]
        n_active = len({tuple(p) for p in active})
        if n_active != int(row["active_nodes"]):
            fail("step %d: %d active nodes in the VTU, steps.csv %s" % (step, n_active, row["active_nodes"]))
        theta = math.radians(float(row["flexion_deg"]))
        rotation = np.array(
            [[1, 0, 0], [0, math.cos(theta), -math.sin(theta)], [0, math.sin(theta), math.cos(theta)]]
        )
        femur = ~tibia
        X = points[femur].astype(float)
        rigid = (X - axis_point) @ rotation.T + axis_point - X
        elastic = np.abs(fields["motion"][femur] - rigid).max()
        if elastic > 0.01:
            fail("step %d: the femur's motion differs from the flexion by %g mm" % (step, elastic))
        print(
            "step %d: max pressure / steps.csv = %.6f, active nodes %d, "
            "femur motion = flexion of %.1f deg to 0.01 mm"
            % (step, pressure.max() / expected, n_active, float(row["flexion_deg"]))
        )

    worn = read_series(directory, "worn")
    if len(worn) != int(summary["blocks"]):
        fail("worn.pvd lists %d outputs, summary.json %s blocks" % (len(worn), summary["blocks"]))
    cycles, _, fields = worn[-1]
    depth = fields["wear_depth_mm"][:, 0].max()
    expected = float(summary["max_wear_depth_mm"])
    if not close(depth, expected, 1e-5):
        fail("largest wear_depth_mm %g, summary.json %g" % (depth, expected))
    if int(summary["blocks"]) == 1:
        rate = fields["wear_rate_um_per_Mcycles"][:, 0].max()
        if not close(1e-9 * rate * cycles, expected, 1e-5):
            fail(
                "largest wear rate %g um per million cycles x %g cycles "
                "differs from max_wear_depth_mm %g" % (rate, cycles, expected)
            )
    print("worn tibia: largest wear_depth_mm / summary.json = %.6f" % (depth / expected))
    cs = fields["cross_shear"][:, 0]
    if cs.min() < 0 or cs.max() > 0.5 + 1e-12:
        fail("cross_shear outside 0 .. 0.5: %g .. %g" % (cs.min(), cs.max()))
    mean = float(summary["mean_cross_shear"])
    if not 0 <= mean <= cs.max() + 1e-12:
        fail("mean_cross_shear %g of summary.json outside 0 .. %g (the " "VTU's largest)" % (mean, cs.max()))
    print("worn tibia: cross_shear within 0 .. 0.5, summary.json's mean " "within 0 .. the largest")
    # the medial and lateral sides add up to the insert
    sides = [
        {
            key: float(summary[side + "_" + key])
            for key in ("volume_loss_mm3", "max_wear_depth_mm", "wear_area_percent")
        }
        for side in ("medial", "lateral")
    ]
    for key, total in (("volume_loss_mm3", sum), ("wear_area_percent", sum), ("max_wear_depth_mm", max)):
        both = total(side[key] for side in sides)
        if not close(both, float(summary[key]), 1e-9):
            fail("medial and lateral %s give %g, the insert %s" % (key, both, summary[key]))
    print("sides: medial and lateral volume and wear area add up to the " "insert's, the larger depth is its")
    for name in ("mass_loss.png", "wear_map.png", "cross_shear_map.png"):
        with open(os.path.join(directory, name), "rb") as f:
            if f.read(8) != b"\x89PNG\r\n\x1a\n":
                fail(name + " is not a PNG file")
    print("plots: mass_loss.png, wear_map.png and cross_shear_map.png are " "PNG files")
    print("check_vtu: all checks passed")


if __name__ == "__main__":
    main()
