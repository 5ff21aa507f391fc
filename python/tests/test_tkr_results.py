# SPDX-License-Identifier: LGPL-2.1-or-later
"""Unit tests of python/tkr_results.py, the readers of the result files
(ctest python/unit; alone: python3 -m pytest python/tests)."""
import json
import os
import subprocess
import sys

import pytest

PYTHON_DIR = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
ROOT = os.path.dirname(PYTHON_DIR)
sys.path.insert(0, PYTHON_DIR)
import tkr_results  # noqa: E402


def write(path, text):
    with open(path, "w") as f:
        f.write(text)
    return str(path)


def write_json(path, data):
    return write(path, json.dumps(data))


WEAR_SUMMARY = {
    "problem": "wear",
    "cycles": 5000000,
    "blocks": 1,
    "mass_loss_mg": 11.5,
    "mean_newton_iterations": None,
    "converged": True,
    "run_in_factor": [{"cycles": 0, "factor": 3}, {"cycles": 1e6, "factor": 1}],
    "unconverged_steps": [],
}


def test_summary_values_by_name(tmp_path):
    summary = tkr_results.read_summary(write_json(tmp_path / "summary.json", WEAR_SUMMARY))
    assert summary["mass_loss_mg"] == 11.5
    assert summary["cycles"] == 5000000  # a whole number is a number
    assert summary["converged"] is True
    assert summary["unconverged_steps"] == []
    assert summary.get("mean_cross_shear") is None  # documented, absent
    assert summary.get("mean_cross_shear", 0.0) == 0.0


def test_missing_key_names_file_and_key(tmp_path):
    path = write_json(tmp_path / "summary.json", WEAR_SUMMARY)
    with pytest.raises(tkr_results.ResultError) as error:
        tkr_results.read_summary(path)["max_wear_depth_mm"]
    assert str(error.value) == f"{path}: missing key max_wear_depth_mm"


def test_undocumented_key_is_refused(tmp_path):
    path = write_json(tmp_path / "summary.json", dict(WEAR_SUMMARY, mass_loss=1.0))
    with pytest.raises(tkr_results.ResultError, match="mass_loss is not a documented key of summary.json"):
        tkr_results.read_summary(path)["mass_loss"]
    with pytest.raises(tkr_results.ResultError, match="not a documented key"):
        tkr_results.read_summary(path).get("mass_loss", 0)


@pytest.mark.parametrize(
    "key, value, message",
    [
        ("mass_loss_mg", "11.5", 'mass_loss_mg is "11.5", not of type number'),
        ("blocks", 1.5, "blocks is 1.5, not of type integer"),
        ("blocks", True, "blocks is true, not of type integer"),
        ("converged", 1, "converged is 1, not of type boolean"),
        ("mass_loss_mg", None, "mass_loss_mg is null"),
    ],
)
def test_type_check(tmp_path, key, value, message):
    path = write_json(tmp_path / "summary.json", dict(WEAR_SUMMARY, **{key: value}))
    with pytest.raises(tkr_results.ResultError, match=message):
        tkr_results.read_summary(path)[key]


def test_unreadable_json(tmp_path):
    with pytest.raises(tkr_results.ResultError, match="summary.json: no such file"):
        tkr_results.read_summary(str(tmp_path / "summary.json"))
    path = write(tmp_path / "summary.json", "{")
    with pytest.raises(tkr_results.ResultError, match="not valid JSON"):
        tkr_results.read_summary(path)
    path = write(tmp_path / "summary.json", "[1]")
    with pytest.raises(tkr_results.ResultError, match="not a JSON object"):
        tkr_results.read_summary(path)


def test_status_json_by_name(tmp_path):
    status = {"case": "case-0001", "status": "done", "reason": "", "resumed": True, "wall_time_s": 1.5}
    result = tkr_results.read_json(write_json(tmp_path / "status.json", status))
    assert result["resumed"] is True
    with pytest.raises(tkr_results.ResultError, match="not a documented key of status.json"):
        result["mass_loss_mg"]


def test_check_summary(tmp_path):
    assert tkr_results.check_summary_data(WEAR_SUMMARY) == []
    problems = tkr_results.check_summary_data(
        dict(WEAR_SUMMARY, hertz_radius_mm=1.0, new_key=2, run_in_factor=[{"cycles": 0}])
    )
    assert problems == [
        'summary.json: run_in_factor has the record {"cycles": 0}, not the fields cycles, factor',
        "summary.json: hertz_radius_mm is not documented for Problem = wear",
        "summary.json: key new_key is not documented in doc/output.md",
    ]


def test_activity_mix_names(tmp_path):
    keys = tkr_results.SUMMARY_KEYS
    assert tkr_results.schema_name("mass_loss_mg", keys) == "mass_loss_mg"
    assert tkr_results.schema_name("activity_stair_ascent_mass_loss_mg", keys) == "activity_NAME_mass_loss_mg"
    # the longest fixed end wins: NAME is walking, not walking_lateral
    assert (
        tkr_results.schema_name("activity_walking_lateral_mass_loss_mg", keys)
        == "activity_NAME_lateral_mass_loss_mg"
    )
    assert tkr_results.schema_name("activity__mass_loss_mg", keys) == "activity__mass_loss_mg"
    assert tkr_results.schema_name("activity_Walk_mass_loss_mg", keys) == "activity_Walk_mass_loss_mg"
    summary = dict(WEAR_SUMMARY, activity_walking_share=0.9, activity_walking_mass_loss_mg=1.5)
    assert tkr_results.check_summary_data(summary) == []
    assert tkr_results.check_summary_data(dict(summary, activity_walking_mass=1.0)) == [
        "summary.json: key activity_walking_mass is not documented in doc/output.md"
    ]
    path = write_json(tmp_path / "summary.json", summary)
    assert tkr_results.read_summary(path)["activity_walking_mass_loss_mg"] == 1.5
    history = "block,cycles,medial_volume_mm3,walking_volume_mm3,stair_ascent_medial_volume_mm3\n"
    assert tkr_results.check_file(write(tmp_path / "wear_history.csv", history)) == []
    assert tkr_results.file_kind("steps_stair_ascent.csv") == "steps.csv"
    assert tkr_results.file_kind("wear_map_walking.csv") == "wear_map.csv"
    assert tkr_results.file_kind("wear_map_faces.csv") == "wear_map_faces.csv"


def test_read_table(tmp_path):
    path = write(tmp_path / "wear_history.csv", "# comment\n cycles , mass_mg,extra\n\n0,0,a\n5e6, 11.5,b\n")
    table = tkr_results.read_table(path, ("cycles", "mass_mg"), ("max_depth_mm",))
    assert table["cycles"] == [0.0, 5e6] and table["mass_mg"] == [0.0, 11.5]
    assert "max_depth_mm" not in table and table[tkr_results.LINE] == [4, 5]
    with pytest.raises(tkr_results.ResultError) as error:
        tkr_results.read_table(path, ("cycles", "volume_mm3"))
    assert str(error.value) == f"{path}: missing column volume_mm3 (header line: cycles,mass_mg,extra)"
    path = write(tmp_path / "bad.csv", "cycles,mass_mg\n0,nan\n")
    with pytest.raises(tkr_results.ResultError, match=r"bad.csv:2: column mass_mg: 'nan' is not a finite"):
        tkr_results.read_table(path, ("cycles", "mass_mg"))
    path = write(tmp_path / "short.csv", "cycles,mass_mg\n0\n")
    with pytest.raises(tkr_results.ResultError, match=r"short.csv:2: 1 fields, the header has 2"):
        tkr_results.read_table(path, ("cycles",))


def test_read_rows(tmp_path):
    path = write(tmp_path / "study.csv", 'case,Mesh/File,status\ncase-0000,"a,b.msh",done\n')
    rows = tkr_results.read_rows(path, ("case", "status"))
    assert rows == [{"case": "case-0000", "Mesh/File": "a,b.msh", "status": "done"}]
    with pytest.raises(tkr_results.ResultError, match="study.csv: missing column mass_loss_mg"):
        tkr_results.read_rows(path, ("mass_loss_mg",))
    assert tkr_results.number({"x": "2.5"}, "x") == 2.5
    with pytest.raises(tkr_results.ResultError, match="f.csv: column x: '' is not a finite number"):
        tkr_results.number({"x": ""}, "x", "f.csv")


def test_check_headers(tmp_path):
    force = "step,percent,flexion_deg,axial_force_N,ap_force_N,ie_torque_Nm,converged,ap_position_mm"
    assert tkr_results.check_file(write(tmp_path / "steps.csv", force + "\n")) == []
    mixed = force + ",ap_reaction_N"
    assert "not those of one protocol" in tkr_results.check_file(write(tmp_path / "steps.csv", mixed))[0]
    study = "case,Wear/Archard/Wear coefficient,status,mass_loss_mg,reason\n"
    assert tkr_results.check_file(write(tmp_path / "study.csv", study)) == []
    assert tkr_results.check_file(write(tmp_path / "wear_map.csv", "x,y,z,depth\n")) == [
        f"{tmp_path}/wear_map.csv: column depth is not documented in doc/output.md"
    ]


def test_command_line(tmp_path):
    path = write_json(tmp_path / "summary.json", WEAR_SUMMARY)
    script = os.path.join(PYTHON_DIR, "tkr_results.py")

    def run(*arguments):
        return subprocess.run([sys.executable, script] + list(arguments), capture_output=True, text=True)

    assert run("get", path, "mass_loss_mg").stdout == "11.5\n"
    assert run("get", path, "problem").stdout == "wear\n"
    assert run("get", path, "converged").stdout == "true\n"
    assert run("get", path, "unconverged_steps").stdout == "[]\n"
    missing = run("get", path, "max_wear_depth_mm")
    assert missing.returncode == 1 and missing.stdout == ""
    assert missing.stderr == f"tkr_results: error: {path}: missing key max_wear_depth_mm\n"
    assert run("check", path).returncode == 0
    assert run("check", write_json(tmp_path / "summary.json", dict(WEAR_SUMMARY, x=1))).returncode == 1


def test_doc_and_module_agree():
    sys.path.insert(0, os.path.join(ROOT, "tests", "scripts"))
    import check_output_schema

    assert check_output_schema.check_doc(os.path.join(ROOT, "doc", "output.md")) == []


def test_stored_references_agree():
    files = tkr_results.result_files([os.path.join(ROOT, "tests", "app")])
    assert any(f.endswith("one_cycle.summary.json") for f in files)
    assert [p for f in files for p in tkr_results.check_file(f)] == []


def test_uncaught_error_is_one_line(tmp_path):
    code = (
        "import sys; sys.path.insert(0, sys.argv[1]); import tkr_results; "
        "tkr_results.read_summary(sys.argv[2])"
    )
    missing = str(tmp_path / "summary.json")
    result = subprocess.run([sys.executable, "-c", code, PYTHON_DIR, missing], capture_output=True, text=True)
    assert result.returncode == 1
    assert result.stderr == f"python3: error: {missing}: no such file\n"
