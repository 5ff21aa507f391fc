#!/usr/bin/env python3
# SPDX-License-Identifier: LGPL-2.1-or-later
"""Physical statements about the files of a wear run (issue 35 item 6).

    check_wear_physics.py RESULTS_DIR [--density RHO] [--rate-band B]
                          [--map-band B] [--same-as OTHER_DIR]
                          [--same-tolerance R]

Reads summary.json, wear_history.csv, wear_map.csv and wear_map_faces.csv
of RESULTS_DIR by their documented names (python/tkr_results.py,
doc/output.md) and prints one line per statement, "ok: ..." or
"FAILED: ...", with the numbers and the band; exit code 1 if one fails.
Unlike a comparison with stored files, a re-blessed output cannot make a
wrong answer pass these. Always checked (doc/wear.md, "One block",
"Output"):

* mass = density x volume: the summary's (the insert and both sides) and
  every history row's (band: the files' printed digits, RELATIVE_ROUNDING);
* the sides add up: medial + lateral volume and worn area = the insert's,
  the insert's largest depth = the larger side's (summary and every row);
* the summary is the last history row (mass, volume, depth, area);
* the gait protocol's own results (e.g. force control's range of the AP
  position over the cycle) are the extremes of their steps.csv columns;
* wear accumulates: volume, mass and largest depth (also of each side)
  never decrease from block to block, the worn areas are within 0..100 %;
* the extrapolation: the first block's mass is the first cycle's mass per
  million cycles times its effective cycles (the block's cycles, or the
  integral of the run-in factor over them: doc/wear.md "Run-in"), and the
  linear extrapolation is that rate times the effective cycles of the run;
* the wear map: the largest nodal depth of wear_map.csv is the summary's,
  and sum_j depth_j A_j, A_j the nodal areas (integral of the bilinear shape
  function over the faces of wear_map_faces.csv, 2x2 Gauss points as the
  program's D_jj), lies between its value on the unworn surface (the nodes
  moved back by their depth along the worn surface's normals) and on the
  worn one, within --map-band of the volume: the volume of a block is its
  depth times the nodal areas of the geometry its cycle was solved on,
  which is between the two. The band (default 1 %) covers the rebuilt
  unworn surface: it is moved back along the worn surface's normals, not
  the ones the wear moved it along, which differ by the slope of the wear
  profile (depth / cell size: 0.4 / 3.7 on the one-cycle runs), an error
  of second order in that slope: 0.1 to 0.2 % of the volume on the
  one-block runs.

With --rate-band B (for Archard's law, whose worn volume per cycle is k x
normal load x sliding distance and so changes only as far as the wear moves
the contact: not for the area law, whose rate grows with the contact area):
every block's mass per effective million cycles within B of the first
cycle's. With --same-as OTHER_DIR: the wear (summary and every history
row: volume, mass, depth, worn area, peak pressure, contact area, both
sides) equals OTHER_DIR's within a relative --same-tolerance (default 1e-6,
the tolerance to which the suite compares runs of the same discrete problem,
tests/scripts/compare-files.sh): 1 against 2 ranks, a left against a right
knee, a run-in factor of 1 against none.
"""
import argparse
import math
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "python"))
import tkr_results  # noqa: E402

# The CSV files are written with 10 significant digits, summary.json with
# 12: a relation between printed numbers holds to a few units of 5e-10
# relative.
RELATIVE_ROUNDING = 1e-8

# UHMWPE (Materials/Tibia density's default, doc/wear.md), mg/mm^3.
DENSITY = 0.935

SIDES = ("medial", "lateral")

# The history columns that two runs of the same wear problem share: all but
# the block's number, the wall time and the mean cross-shear (a ratio of
# small eigenvalues: it differs by 1.2e-6 relative between mirrored runs,
# tests/app/CMakeLists.txt).
SAME_COLUMNS = tuple(
    c
    for c in tkr_results.WEAR_HISTORY_COLUMNS
    if c not in ("block", "wall_time_s") and not c.endswith("mean_cross_shear")
)
# The gait protocols' own results in summary.json (doc/output.md) and the
# steps.csv column of the last cycle each is the range or the largest
# magnitude of.
PROTOCOL_RESULTS = (
    ("ap_position_range_mm", "ap_position_mm", "range"),
    ("ie_rotation_range_deg", "ie_rotation_deg", "range"),
    ("max_ap_reaction_N", "ap_reaction_N", "largest magnitude"),
    ("max_ie_reaction_Nm", "ie_reaction_Nm", "largest magnitude"),
)
SAME_KEYS = (
    "cycles",
    "blocks",
    "mass_loss_mg",
    "volume_loss_mm3",
    "max_wear_depth_mm",
    "wear_area_percent",
    "medial_mass_loss_mg",
    "medial_volume_loss_mm3",
    "medial_max_wear_depth_mm",
    "medial_wear_area_percent",
    "lateral_mass_loss_mg",
    "lateral_volume_loss_mm3",
    "lateral_max_wear_depth_mm",
    "lateral_wear_area_percent",
    "max_pressure_MPa",
    "first_cycle_mass_loss_mg_per_million_cycles",
    "linear_extrapolation_mass_loss_mg",
)


class Statement:
    """One checked statement: whether it holds and its one-line text."""

    def __init__(self, passed, text):
        self.passed = bool(passed)
        self.text = text

    def line(self):
        return ("ok: " if self.passed else "FAILED: ") + self.text


def relative_difference(a, b):
    """|a - b| over the larger magnitude (0 when both are 0)."""
    scale = max(abs(a), abs(b))
    return abs(a - b) / scale if scale > 0 else 0.0


def worst(pairs):
    """(largest relative difference, its label) of [(label, a, b)]."""
    result = (0.0, "-")
    for label, a, b in pairs:
        difference = relative_difference(a, b)
        if difference > result[0]:
            result = (difference, label)
    return result


def rows(table):
    """A table of tkr_results.read_table() as a list of {column: value}."""
    columns = [c for c in table if c != tkr_results.LINE]
    return [{c: table[c][i] for c in columns} for i in range(len(table[tkr_results.LINE]))]


# --------------------------------------------------------------------------
# The run-in factor


def factor_integral(points, a, b):
    """The integral of the run-in factor from cycle @p a to @p b: piecewise
    linear between @p points [(cycles, factor)], constant beyond the first
    and the last (doc/wear.md, "Run-in"); b - a without points."""
    if not points:
        return b - a
    points = sorted(points)

    def primitive(n):
        # integral from points[0][0] to n (negative below it)
        c0, f0 = points[0]
        if n <= c0:
            return (n - c0) * f0
        total = 0.0
        for (ca, fa), (cb, fb) in zip(points, points[1:]):
            if n <= ca:
                break
            end = min(n, cb)
            f_end = fa + (fb - fa) * (end - ca) / (cb - ca) if cb > ca else fb
            total += (end - ca) * (fa + f_end) / 2
        c_last, f_last = points[-1]
        if n > c_last:
            total += (n - c_last) * f_last
        return total

    return primitive(b) - primitive(a)


def run_in_points(summary):
    """[(cycles, factor)] of the summary's run_in_factor (empty without)."""
    return [(p["cycles"], p["factor"]) for p in summary.get("run_in_factor", [])]


# --------------------------------------------------------------------------
# Statements on one run


def check_density(summary, history, density):
    """mass = density x volume: the summary's (insert, sides), every row's."""
    pairs = [("summary", summary["mass_loss_mg"], density * summary["volume_loss_mm3"])]
    for side in SIDES:
        pairs.append(
            (
                f"summary {side}",
                summary[f"{side}_mass_loss_mg"],
                density * summary[f"{side}_volume_loss_mm3"],
            )
        )
    for row in rows(history):
        pairs.append((f"block {row['block']:g}", row["mass_mg"], density * row["volume_mm3"]))
    difference, where = worst(pairs)
    return Statement(
        difference <= RELATIVE_ROUNDING,
        f"mass = {density:g} mg/mm^3 x volume in the summary (insert, medial, lateral) and in all "
        f"{len(history['block'])} history rows: largest relative difference {difference:.2e} "
        f"({where}), band {RELATIVE_ROUNDING:g} (printed digits)",
    )


def check_sides(summary, history):
    """medial + lateral = insert (volume, worn area); depth = larger side's."""
    pairs = []
    for label, total, parts, depth, side_depths in [
        (
            "summary",
            (summary["volume_loss_mm3"], summary["wear_area_percent"]),
            [(summary[f"{s}_volume_loss_mm3"], summary[f"{s}_wear_area_percent"]) for s in SIDES],
            summary["max_wear_depth_mm"],
            [summary[f"{s}_max_wear_depth_mm"] for s in SIDES],
        )
    ] + [
        (
            f"block {row['block']:g}",
            (row["volume_mm3"], row["wear_area_percent"]),
            [(row[f"{s}_volume_mm3"], row[f"{s}_wear_area_percent"]) for s in SIDES],
            row["max_depth_mm"],
            [row[f"{s}_max_depth_mm"] for s in SIDES],
        )
        for row in rows(history)
    ]:
        pairs.append((f"{label} volume", total[0], sum(p[0] for p in parts)))
        pairs.append((f"{label} worn area", total[1], sum(p[1] for p in parts)))
        pairs.append((f"{label} depth", depth, max(side_depths)))
    difference, where = worst(pairs)
    return Statement(
        difference <= RELATIVE_ROUNDING,
        f"medial + lateral = insert (volume, worn area; depth = the larger side's) in the summary and "
        f"every row: largest relative difference {difference:.2e} ({where}), band {RELATIVE_ROUNDING:g}",
    )


def check_summary_is_last_row(summary, history):
    """The summary's wear is the last block's."""
    last = rows(history)[-1]
    pairs = [
        ("cycles", summary["cycles"], last["cycles"]),
        ("blocks", summary["blocks"], last["block"]),
        ("mass", summary["mass_loss_mg"], last["mass_mg"]),
        ("volume", summary["volume_loss_mm3"], last["volume_mm3"]),
        ("depth", summary["max_wear_depth_mm"], last["max_depth_mm"]),
        ("worn area", summary["wear_area_percent"], last["wear_area_percent"]),
    ]
    difference, where = worst(pairs)
    return Statement(
        difference <= RELATIVE_ROUNDING,
        f"summary = last history row (block {last['block']:g}: cycles, mass, volume, depth, worn area): "
        f"largest relative difference {difference:.2e} ({where}), band {RELATIVE_ROUNDING:g}",
    )


def check_accumulation(history):
    """Volume, mass and depth never decrease (each law's depth increments
    are >= 0, so every node's accumulated depth grows); worn areas within
    0..100 %. The worn area is not required to grow: it is a share of the
    nodal areas of each block's geometry, which the wear changes."""
    columns = ["cycles", "volume_mm3", "mass_mg", "max_depth_mm"] + [
        f"{s}_{c}" for s in SIDES for c in ("volume_mm3", "max_depth_mm")
    ]
    table = rows(history)
    decrease, where = 0.0, "-"
    for before, after in zip(table, table[1:]):
        for c in columns:
            # a fall beyond the printed digits of the larger value
            fall = (before[c] - after[c]) / max(abs(before[c]), abs(after[c]), 1e-300)
            if fall > decrease:
                decrease, where = fall, f"{c} from block {before['block']:g} to {after['block']:g}"
    areas = [row[f"{p}wear_area_percent"] for row in table for p in ("", "medial_", "lateral_")]
    in_range = all(0 <= a <= 100 for a in areas)
    return Statement(
        decrease <= RELATIVE_ROUNDING and in_range,
        f"wear accumulates over {len(table) - 1} blocks (cycles, volume, mass, largest depth; per side): "
        f"largest relative decrease {decrease:.2e} ({where}), band {RELATIVE_ROUNDING:g}; worn areas "
        f"{min(areas):g} .. {max(areas):g} %, band 0 .. 100 %",
    )


def check_extrapolation(summary, history):
    """First block = first cycle's rate x its effective cycles; the linear
    extrapolation = that rate x the run's effective cycles."""
    points = run_in_points(summary)
    rate = summary["first_cycle_mass_loss_mg_per_million_cycles"]
    table = rows(history)
    first = table[1]
    block = factor_integral(points, table[0]["cycles"], first["cycles"]) / 1e6
    run = factor_integral(points, 0.0, summary["cycles"]) / 1e6
    predicted_block = rate * block
    predicted_linear = rate * run
    difference_block = relative_difference(first["mass_mg"] - table[0]["mass_mg"], predicted_block)
    difference_linear = relative_difference(summary["linear_extrapolation_mass_loss_mg"], predicted_linear)
    factor = " (run-in integrated)" if points else ""
    return Statement(
        max(difference_block, difference_linear) <= RELATIVE_ROUNDING,
        f"block 1 = first cycle {rate:.6g} mg/Mcycles x {block:.6g} Mcycles{factor} = {predicted_block:.6g} "
        f"mg (history {first['mass_mg']:.6g}, relative difference {difference_block:.2e}); linear "
        f"extrapolation x {run:.6g} Mcycles = {predicted_linear:.6g} mg (summary "
        f"{summary['linear_extrapolation_mass_loss_mg']:.6g}, {difference_linear:.2e}); band "
        f"{RELATIVE_ROUNDING:g}",
    )


def check_rate_band(summary, history, band):
    """Archard: every block's mass per effective million cycles within
    @p band of the first cycle's."""
    points = run_in_points(summary)
    rate = summary["first_cycle_mass_loss_mg_per_million_cycles"]
    table = rows(history)
    ratios = []
    for before, after in zip(table, table[1:]):
        cycles = factor_integral(points, before["cycles"], after["cycles"]) / 1e6
        if cycles > 0:
            ratios.append((after["block"], (after["mass_mg"] - before["mass_mg"]) / cycles / rate))
    lowest = min(ratios, key=lambda r: r[1])
    highest = max(ratios, key=lambda r: r[1])
    passed = rate > 0 and all(abs(r - 1) <= band for _, r in ratios)
    return Statement(
        passed,
        f"Archard: the blocks' mass per effective Mcycle over the first cycle's ({rate:.6g} mg) "
        f"{lowest[1]:.4f} (block {lowest[0]:g}) .. {highest[1]:.4f} (block {highest[0]:g}) at a final "
        f"depth of {table[-1]['max_depth_mm']:.4g} mm, band 1 +- {band:g}",
    )


def nodal_areas(positions, faces):
    """D_j = integral of the bilinear shape function of node j over the
    quadrilaterals @p faces (node indices in cyclic order), 2x2 Gauss
    points; and the area-weighted nodal normals (unit, the faces' side)."""
    areas = [0.0] * len(positions)
    normals = [[0.0, 0.0, 0.0] for _ in positions]
    g = (0.5 - 0.5 / math.sqrt(3), 0.5 + 0.5 / math.sqrt(3))
    for face in faces:
        p = [positions[n] for n in face]
        for xi in g:
            for eta in g:
                shape = ((1 - xi) * (1 - eta), xi * (1 - eta), xi * eta, (1 - xi) * eta)
                d_xi = (-(1 - eta), 1 - eta, eta, -eta)
                d_eta = (-(1 - xi), -xi, xi, 1 - xi)
                a = [sum(d_xi[k] * p[k][i] for k in range(4)) for i in range(3)]
                b = [sum(d_eta[k] * p[k][i] for k in range(4)) for i in range(3)]
                cross = (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])
                weight = 0.25 * math.sqrt(sum(c * c for c in cross))
                for k, node in enumerate(face):
                    areas[node] += shape[k] * weight
                    for i in range(3):
                        normals[node][i] += 0.25 * shape[k] * cross[i]
    for n in normals:
        length = math.sqrt(sum(c * c for c in n)) or 1.0
        n[:] = [c / length for c in n]
    return areas, normals


def map_volumes(positions, depths, faces):
    """(sum d_j A_j on the worn surface, on the unworn one): the unworn
    surface is the worn one with every node moved back out of the tibia by
    its depth along its normal (outward: the articular surface faces the
    femur above it, +z, whichever way the faces are numbered)."""
    areas, normals = nodal_areas(positions, faces)
    mean_z = sum(a * n[2] for a, n in zip(areas, normals))
    outward = 1.0 if mean_z > 0 else -1.0
    unworn = [[x[i] + outward * d * n[i] for i in range(3)] for x, d, n in zip(positions, depths, normals)]
    unworn_areas, _ = nodal_areas(unworn, faces)
    worn_volume = sum(d * a for d, a in zip(depths, areas))
    unworn_volume = sum(d * a for d, a in zip(depths, unworn_areas))
    return worn_volume, unworn_volume


def check_wear_map(summary, wear_map, faces, band):
    """The map's largest depth is the summary's; the volume lies between
    sum d A on the unworn and on the worn surface (within @p band)."""
    positions = list(zip(wear_map["x"], wear_map["y"], wear_map["z"]))
    depths = wear_map["depth_mm"]
    face_nodes = [tuple(int(face[c]) for c in ("n0", "n1", "n2", "n3")) for face in rows(faces)]
    worn, unworn = map_volumes(positions, depths, face_nodes)
    volume = summary["volume_loss_mm3"]
    low, high = min(worn, unworn), max(worn, unworn)
    inside = low - band * volume <= volume <= high + band * volume
    depth_difference = relative_difference(max(depths), summary["max_wear_depth_mm"])
    return Statement(
        inside and depth_difference <= RELATIVE_ROUNDING and volume > 0,
        f"wear map ({len(depths)} nodes): sum depth x nodal area {unworn:.6g} mm^3 (unworn surface) .. "
        f"{worn:.6g} (worn) against the volume {volume:.6g} (ratios {unworn / volume:.4f} .. "
        f"{worn / volume:.4f}), band the interval +- {band:g}; largest depth {max(depths):.6g} mm = "
        f"summary's to {depth_difference:.1e}, band {RELATIVE_ROUNDING:g}",
    )


def check_same(summary, history, other_summary, other_history, tolerance, other_name):
    """The wear of two runs of the same problem agrees within @p tolerance."""
    pairs = [(f"summary {key}", summary[key], other_summary[key]) for key in SAME_KEYS]
    table, other = rows(history), rows(other_history)
    if len(table) != len(other):
        return Statement(False, f"same wear as {other_name}: {len(table)} against {len(other)} history rows")
    for row, other_row in zip(table, other):
        pairs += [(f"block {row['block']:g} {c}", row[c], other_row[c]) for c in SAME_COLUMNS]
    # numbers that should be zero (block 0) agree absolutely
    pairs = [(label, a, b) for label, a, b in pairs if abs(a - b) > 1e-12]
    difference, where = worst(pairs)
    return Statement(
        difference <= tolerance,
        f"same wear as {other_name} ({len(SAME_KEYS)} summary keys, {len(SAME_COLUMNS)} columns of "
        f"{len(table)} rows): largest relative difference {difference:.2e} ({where}), band {tolerance:g} "
        f"(the solvers' agreement, compare-files.sh)",
    )


# --------------------------------------------------------------------------
# Reading a run


def check_protocol_results(summary, steps):
    """The protocol's own results are the extremes of its steps.csv columns."""
    pairs = []
    for key, column, kind in PROTOCOL_RESULTS:
        if key in summary:
            values = steps[column]
            extreme = max(values) - min(values) if kind == "range" else max(abs(v) for v in values)
            pairs.append((key, summary[key], extreme))
    difference, where = worst(pairs)
    return Statement(
        difference <= RELATIVE_ROUNDING,
        f"the protocol's results ({', '.join(p[0] for p in pairs)}) = the range or largest magnitude of "
        f"their steps.csv columns over {len(steps['step'])} steps: largest relative difference "
        f"{difference:.2e} ({where}), band {RELATIVE_ROUNDING:g}",
    )


def read_run(directory, with_map=True):
    """(summary, history, wear map, faces) of a wear run's directory."""
    summary = tkr_results.read_summary(os.path.join(directory, "summary.json"))
    if summary["problem"] != "wear":
        raise tkr_results.ResultError(f"{directory}/summary.json: problem is {summary['problem']}, not wear")
    history = tkr_results.read_table(
        os.path.join(directory, "wear_history.csv"),
        [c for c in tkr_results.WEAR_HISTORY_COLUMNS if c != "wall_time_s"],
    )
    wear_map = faces = None
    if with_map:
        wear_map = tkr_results.read_table(
            os.path.join(directory, "wear_map.csv"), ("x", "y", "z", "depth_mm")
        )
        faces = tkr_results.read_table(
            os.path.join(directory, "wear_map_faces.csv"), tkr_results.WEAR_MAP_FACES_COLUMNS
        )
    return summary, history, wear_map, faces


def statements(directory, density=DENSITY, rate_band=None, map_band=0.01, same_as=None, same_tolerance=1e-6):
    """Every statement on the run in @p directory (see the module's text)."""
    summary, history, wear_map, faces = read_run(directory)
    if len(history["block"]) < 2:
        raise tkr_results.ResultError(f"{directory}/wear_history.csv: no block after block 0")
    result = [
        check_density(summary, history, density),
        check_sides(summary, history),
        check_summary_is_last_row(summary, history),
        check_accumulation(history),
        check_extrapolation(summary, history),
        check_wear_map(summary, wear_map, faces, map_band),
    ]
    if any(key in summary for key, _, _ in PROTOCOL_RESULTS):
        steps = tkr_results.read_table(
            os.path.join(directory, "steps.csv"), ("step",), [column for _, column, _ in PROTOCOL_RESULTS]
        )
        result.append(check_protocol_results(summary, steps))
    if rate_band is not None:
        result.append(check_rate_band(summary, history, rate_band))
    if same_as:
        other_summary, other_history, _, _ = read_run(same_as, with_map=False)
        result.append(
            check_same(
                summary, history, other_summary, other_history, same_tolerance, os.path.normpath(same_as)
            )
        )
    return result


def main(arguments):
    parser = argparse.ArgumentParser(
        description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    parser.add_argument("results", help="the run's output directory")
    parser.add_argument("--density", type=float, default=DENSITY, help="the insert's density, mg/mm^3")
    parser.add_argument("--rate-band", type=float, help="Archard: blocks' rate within 1 +- this")
    parser.add_argument("--map-band", type=float, default=0.01, help="the wear map's volume band")
    parser.add_argument("--same-as", help="another run's directory with the same wear")
    parser.add_argument("--same-tolerance", type=float, default=1e-6)
    args = parser.parse_args(arguments)
    print(f"check_wear_physics: {os.path.normpath(args.results)}")
    result = statements(
        args.results, args.density, args.rate_band, args.map_band, args.same_as, args.same_tolerance
    )
    for statement in result:
        print(statement.line())
    failed = sum(not s.passed for s in result)
    print(f"check_wear_physics: {len(result)} statements, {failed} failed")
    return 1 if failed else 0


if __name__ == "__main__":
    try:
        sys.exit(main(sys.argv[1:]))
    except tkr_results.ResultError as e:
        print(f"FAILED: {e}")
        sys.exit(1)
