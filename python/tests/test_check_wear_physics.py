# SPDX-License-Identifier: LGPL-2.1-or-later
"""Unit tests of tests/scripts/check_wear_physics.py, the physical statements
about a wear run's files (ctest python/unit), on small synthetic runs whose
answers are known: each statement passes on a consistent run and fails on
one that breaks it."""
import json
import math
import os
import sys

import pytest

PYTHON_DIR = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
ROOT = os.path.dirname(PYTHON_DIR)
sys.path.insert(0, PYTHON_DIR)
sys.path.insert(0, os.path.join(ROOT, "tests", "scripts"))
import check_wear_physics as physics  # noqa: E402
import tkr_results  # noqa: E402

DENSITY = physics.DENSITY


def history_table(rows):
    """A read_table()-like table from a list of {column: value}."""
    table = {c: [row[c] for row in rows] for c in rows[0]}
    table[tkr_results.LINE] = list(range(2, 2 + len(rows)))
    return table


def consistent_run(rates=(10.0, 10.0, 10.0), n=5e5, medial_share=0.6):
    """(summary, history) of an Archard run whose blocks of n cycles wear
    rates[i] mm^3 per million cycles, split medial_share : the rest."""
    rows = [{c: 0.0 for c in tkr_results.WEAR_HISTORY_COLUMNS if c != "wall_time_s"}]
    volume = depth = 0.0
    for i, rate in enumerate(rates, start=1):
        volume += rate * n / 1e6
        depth += 0.01 * rate * n / 1e6
        row = dict(rows[-1], block=i, cycles=i * n, volume_mm3=volume, mass_mg=DENSITY * volume)
        row.update(max_depth_mm=depth, wear_area_percent=20.0, peak_pressure_MPa=15.0)
        row.update(medial_volume_mm3=medial_share * volume, lateral_volume_mm3=(1 - medial_share) * volume)
        row.update(medial_max_depth_mm=depth, lateral_max_depth_mm=0.5 * depth)
        row.update(medial_wear_area_percent=12.0, lateral_wear_area_percent=8.0)
        rows.append(row)
    last = rows[-1]
    summary = {
        "problem": "wear",
        "cycles": last["cycles"],
        "blocks": len(rates),
        "mass_loss_mg": last["mass_mg"],
        "volume_loss_mm3": last["volume_mm3"],
        "max_wear_depth_mm": last["max_depth_mm"],
        "wear_area_percent": last["wear_area_percent"],
        "max_pressure_MPa": 15.0,
        "first_cycle_mass_loss_mg_per_million_cycles": DENSITY * rates[0],
        "linear_extrapolation_mass_loss_mg": DENSITY * rates[0] * last["cycles"] / 1e6,
    }
    for side in physics.SIDES:
        summary[f"{side}_volume_loss_mm3"] = last[f"{side}_volume_mm3"]
        summary[f"{side}_mass_loss_mg"] = DENSITY * last[f"{side}_volume_mm3"]
        summary[f"{side}_max_wear_depth_mm"] = last[f"{side}_max_depth_mm"]
        summary[f"{side}_wear_area_percent"] = last[f"{side}_wear_area_percent"]
    return summary, rows


def test_consistent_run_passes():
    summary, rows = consistent_run()
    history = history_table(rows)
    for statement in [
        physics.check_density(summary, history, DENSITY),
        physics.check_sides(summary, history),
        physics.check_summary_is_last_row(summary, history),
        physics.check_accumulation(history),
        physics.check_extrapolation(summary, history),
        physics.check_rate_band(summary, history, 0.1),
        physics.check_same(summary, history, summary, history, 1e-6, "itself"),
    ]:
        assert statement.passed, statement.line()
        assert statement.line().startswith("ok: ")
        assert "\n" not in statement.line()


def test_mass_not_density_times_volume_fails():
    summary, rows = consistent_run()
    rows[2]["mass_mg"] *= 1 + 1e-6
    statement = physics.check_density(summary, history_table(rows), DENSITY)
    assert not statement.passed
    assert statement.line().startswith("FAILED: ") and "block 2" in statement.line()
    # another density fails everywhere
    summary, rows = consistent_run()
    assert not physics.check_density(summary, history_table(rows), 0.94).passed


def test_sides_that_do_not_add_up_fail():
    summary, rows = consistent_run()
    rows[1]["lateral_volume_mm3"] *= 1.01
    statement = physics.check_sides(summary, history_table(rows))
    assert not statement.passed and "block 1 volume" in statement.text
    summary, rows = consistent_run()
    summary["medial_max_wear_depth_mm"] = 2 * summary["max_wear_depth_mm"]  # deeper than the insert
    assert not physics.check_sides(summary, history_table(rows)).passed


def test_summary_other_than_last_row_fails():
    summary, rows = consistent_run()
    summary["mass_loss_mg"] = rows[-2]["mass_mg"]
    assert not physics.check_summary_is_last_row(summary, history_table(rows)).passed


def test_decreasing_depth_and_area_out_of_range_fail_a_smaller_area_not():
    summary, rows = consistent_run()
    rows[3]["max_depth_mm"] = 0.5 * rows[2]["max_depth_mm"]
    statement = physics.check_accumulation(history_table(rows))
    assert not statement.passed and "max_depth_mm from block 2 to 3" in statement.text
    summary, rows = consistent_run()
    rows[3]["wear_area_percent"] = 0.999 * rows[2]["wear_area_percent"]  # nodal areas changed: allowed
    assert physics.check_accumulation(history_table(rows)).passed
    rows[1]["wear_area_percent"] = rows[2]["wear_area_percent"] = rows[3]["wear_area_percent"] = 101.0
    assert not physics.check_accumulation(history_table(rows)).passed


def test_first_block_not_first_cycle_times_cycles_fails():
    summary, rows = consistent_run()
    summary["first_cycle_mass_loss_mg_per_million_cycles"] *= 2  # n_Delta applied twice
    assert not physics.check_extrapolation(summary, history_table(rows)).passed


def test_run_in_integral():
    # 3 falling to 1 at 1e6 cycles, then 1 (data/wear/example-run-in.csv)
    points = [(0, 3), (1e6, 1)]
    assert physics.factor_integral(points, 0, 5e6) == pytest.approx(6e6, rel=1e-14)
    assert physics.factor_integral(points, 0, 2.5e5) == pytest.approx(3 * 2.5e5 - 2.5e5**2 / 1e6, rel=1e-14)
    assert physics.factor_integral(points, 2e6, 3e6) == pytest.approx(1e6, rel=1e-14)
    assert physics.factor_integral(points, 5e5, 1.5e6) == pytest.approx(1.5 * 5e5 + 5e5, rel=1e-14)
    assert physics.factor_integral([], 1e5, 3e5) == 2e5
    assert physics.factor_integral([(0, 1), (1e6, 1)], 0, 5e6) == 5e6
    # a run with that run-in: block 1 = rate x integral, not rate x cycles
    summary, rows = consistent_run(rates=(10.0,), n=2.5e5)
    summary["run_in_factor"] = [{"cycles": 0, "factor": 3}, {"cycles": 1e6, "factor": 1}]
    effective = physics.factor_integral(points, 0, 2.5e5)
    summary["first_cycle_mass_loss_mg_per_million_cycles"] = DENSITY * 10.0 * 2.5e5 / effective
    summary["linear_extrapolation_mass_loss_mg"] = summary["first_cycle_mass_loss_mg_per_million_cycles"] * (
        effective / 1e6
    )
    assert physics.check_extrapolation(summary, history_table(rows)).passed
    del summary["run_in_factor"]  # the factor forgotten
    assert not physics.check_extrapolation(summary, history_table(rows)).passed


def test_rate_band():
    summary, rows = consistent_run(rates=(10.0, 10.5, 10.9))
    assert physics.check_rate_band(summary, history_table(rows), 0.1).passed
    summary, rows = consistent_run(rates=(10.0, 20.0, 10.0))  # a block counted twice
    statement = physics.check_rate_band(summary, history_table(rows), 0.1)
    assert not statement.passed and "2.0000 (block 2)" in statement.text


def test_same_wear():
    summary, rows = consistent_run()
    other_summary, other_rows = consistent_run()
    other_rows[3]["medial_volume_mm3"] *= 1 + 1e-7
    assert physics.check_same(
        summary, history_table(rows), other_summary, history_table(other_rows), 1e-6, "B"
    ).passed
    other_rows[3]["medial_volume_mm3"] *= 1 + 1e-5
    statement = physics.check_same(
        summary, history_table(rows), other_summary, history_table(other_rows), 1e-6, "B"
    )
    assert not statement.passed and "block 3 medial_volume_mm3" in statement.text
    statement = physics.check_same(
        summary, history_table(rows), other_summary, history_table(rows[:2]), 1e-6, "B"
    )
    assert not statement.passed


def square_grid(n, size, height=lambda x, y: 0.0):
    """(n x n nodes of a size x size square, faces counter-clockwise seen
    from +z)."""
    nodes = [
        (size * i / (n - 1), size * j / (n - 1), height(size * i / (n - 1), size * j / (n - 1)))
        for j in range(n)
        for i in range(n)
    ]
    faces = [
        (j * n + i, j * n + i + 1, (j + 1) * n + i + 1, (j + 1) * n + i)
        for j in range(n - 1)
        for i in range(n - 1)
    ]
    return nodes, faces


def test_nodal_areas_of_a_flat_grid():
    nodes, faces = square_grid(3, 2.0)
    areas, normals = physics.nodal_areas(nodes, faces)
    assert sum(areas) == pytest.approx(4.0, rel=1e-14)
    assert (
        areas[0] == pytest.approx(0.25) and areas[1] == pytest.approx(0.5) and areas[4] == pytest.approx(1.0)
    )
    assert all(n == pytest.approx([0, 0, 1]) for n in normals)


def test_map_volumes_on_a_sphere():
    # A cap of a sphere of radius R - d, worn by a uniform depth d from the
    # sphere of radius R: nodal areas scale with the square of the radius.
    radius, depth = 20.0, 0.5
    worn_radius = radius - depth
    nodes, faces = square_grid(
        21, 8.0, lambda x, y: math.sqrt(worn_radius**2 - (x - 4) ** 2 - (y - 4) ** 2) - worn_radius
    )
    worn, unworn = physics.map_volumes(nodes, [depth] * len(nodes), faces)
    # the nodes on the edge of the cap have one-sided normals (as the
    # program's): the area change within 10 % of the exact one
    expected = (radius / worn_radius) ** 2
    assert unworn / worn - 1 == pytest.approx(expected - 1, rel=0.1)
    # faces numbered the other way round: the same
    reversed_faces = [tuple(reversed(f)) for f in faces]
    assert physics.map_volumes(nodes, [depth] * len(nodes), reversed_faces) == pytest.approx((worn, unworn))


def write_run(directory, summary, rows, nodes, depths, faces):
    os.makedirs(directory, exist_ok=True)
    with open(os.path.join(directory, "summary.json"), "w") as f:
        json.dump(summary, f)
    columns = [c for c in tkr_results.WEAR_HISTORY_COLUMNS if c != "wall_time_s"]
    with open(os.path.join(directory, "wear_history.csv"), "w") as f:
        f.write(",".join(columns) + "\n")
        for row in rows:
            f.write(",".join(f"{row[c]:.10g}" for c in columns) + "\n")
    with open(os.path.join(directory, "wear_map.csv"), "w") as f:
        f.write("x,y,z,depth_mm,cross_shear\n")
        for (x, y, z), d in zip(nodes, depths):
            f.write(f"{x:.10g},{y:.10g},{z:.10g},{d:.10g},0\n")
    with open(os.path.join(directory, "wear_map_faces.csv"), "w") as f:
        f.write("n0,n1,n2,n3\n")
        for face in faces:
            f.write(",".join(str(n) for n in face) + "\n")


def synthetic_directory(directory, volume_scale=1.0):
    """A flat 4 x 4 mm surface whose depth map holds the run's volume
    (times @p volume_scale): every check passes with scale 1."""
    summary, rows = consistent_run()
    nodes, faces = square_grid(5, 4.0)
    areas, _ = physics.nodal_areas(nodes, faces)
    # the middle node the deepest (the summary's depth), the others half as deep
    depth = summary["max_wear_depth_mm"]
    depths = [depth * (1.0 if i == 12 else 0.5) for i in range(len(nodes))]
    scale = summary["volume_loss_mm3"] / sum(d * a for d, a in zip(depths, areas))
    # the volume matched by the size of the surface, not the depths
    nodes = [
        (x * math.sqrt(scale * volume_scale), y * math.sqrt(scale * volume_scale), z) for x, y, z in nodes
    ]
    write_run(directory, summary, rows, nodes, depths, faces)
    return directory


def test_command_line_on_a_consistent_run(tmp_path, capsys):
    directory = synthetic_directory(str(tmp_path / "run"))
    assert physics.main([directory, "--rate-band", "0.1", "--same-as", directory]) == 0
    out = capsys.readouterr().out.splitlines()
    assert out[-1] == "check_wear_physics: 8 statements, 0 failed"
    assert all(line.startswith("ok: ") for line in out[1:-1])


def test_command_line_fails_on_a_wrong_map_volume(tmp_path, capsys):
    # the depth map holds 5 % more than the reported volume: a flat surface
    # has no area change to explain it
    directory = synthetic_directory(str(tmp_path / "run"), volume_scale=1.05)
    assert physics.main([directory]) == 1
    out = capsys.readouterr().out
    assert "FAILED: wear map" in out
    assert out.splitlines()[-1] == "check_wear_physics: 6 statements, 1 failed"


def test_missing_file_is_one_message(tmp_path):
    with pytest.raises(tkr_results.ResultError, match="summary.json: no such file"):
        physics.statements(str(tmp_path))
