#!/usr/bin/env python3
# SPDX-License-Identifier: LGPL-2.1-or-later
"""The result files of tkr-wear: the names of their keys and columns, and
their readers.

The program's result schema (`tkr-wear --print-schema`, kept as
python/result_schema.json) is the type, unit and meaning of every key of
summary.json, status.json and study.json and of every column of
wear_history.csv, steps.csv, wear_map.csv, wear_map_faces.csv and
study.csv; doc/output.md ("Result files") documents the same (the ctest
`tests/output_schema`, tests/scripts/check_output_schema.py, fails when
they differ). This module loads it, so a script reads a key by a name
that the program writes.

Scripts find it by their own path, nothing is installed:

    sys.path.insert(0, os.path.join(ROOT, "python"))
    import tkr_results

Reading (every failure is a ResultError: one line naming the file, and
the key, column or line; never an empty value):

    summary = tkr_results.read_summary(path)     # summary.json
    summary["mass_loss_mg"]                      # type-checked value
    summary.get("mean_cross_shear")              # None when absent
    status = tkr_results.read_json(path)         # status.json, study.json
    rows = tkr_results.read_rows(path, ("step", "ap_position_mm"))
    table = tkr_results.read_table(path, ("cycles", "mass_mg"))

Checking a run's files against the schema (every key and column present
is documented, with its type, for the problem or protocol that wrote it):

    problems = tkr_results.check_file(path)      # [] when all is right

An uncaught ResultError ends a program that imported this module with its
one line on stderr and exit code 1, without a traceback (sys.excepthook).

Command line (exit 1 with one line `tkr_results: error: ...`):

    python3 python/tkr_results.py get FILE KEY   print one value of a JSON
                                                 file (strings as they are,
                                                 the rest as JSON)
    python3 python/tkr_results.py check PATH...  check the result files
                                                 (a directory: every result
                                                 file under it)
"""
import csv
import json
import math
import os
import re
import sys

# --------------------------------------------------------------------------
# The schema: the program's (`tkr-wear --print-schema`, C++
# ResultSchema), kept as python/result_schema.json (tests/output_schema
# fails when the two differ and says how to renew it). Nothing below
# names a key or column by hand.

SCHEMA_FILE = os.path.join(os.path.dirname(os.path.abspath(__file__)), "result_schema.json")


def load_schema(path=SCHEMA_FILE):
    """{file name: [field, ...]} of the schema at @p path (a field: a dict
    with name, type, unit, written_by, fields, trace, study, timing,
    meaning)."""
    with open(path) as f:
        return json.load(f)["files"]


SCHEMA = load_schema()

WEAR, CONTACT, ELASTICITY = "wear", "contact", "elasticity"
PROBLEMS = (WEAR, CONTACT, ELASTICITY)

# JSON types of the keys: a JSON string, an integer, a number (integer or
# not; null when the run computed no finite value), true/false, a list of
# objects, an object.
TYPES = ("string", "integer", "number", "boolean", "list", "object")

# summary.json: key -> (type, the problems that write it), in the order of
# the schema.
SUMMARY_KEYS = {f["name"]: (f["type"], tuple(f["written_by"])) for f in SCHEMA["summary.json"]}

# The fields of the objects of the summary's lists (all numbers).
SUMMARY_RECORDS = {f["name"]: tuple(f["fields"]) for f in SCHEMA["summary.json"] if f["fields"]}

# wear_history.csv's columns of every run, in the order written (wall_time_s
# is left out under Output/Testing); an activity mix writes the
# WEAR_HISTORY_ACTIVITY_COLUMNS of each activity before wall_time_s.
WEAR_HISTORY_COLUMNS = tuple(f["name"] for f in SCHEMA["wear_history.csv"] if "NAME" not in f["name"])
WEAR_HISTORY_ACTIVITY_COLUMNS = tuple(f["name"] for f in SCHEMA["wear_history.csv"] if "NAME" in f["name"])

# steps.csv: column -> the gait protocols (Gait/Control) that write it.
PROTOCOLS = tuple(sorted({w for f in SCHEMA["steps.csv"] for w in f["written_by"]}))
STEPS_COLUMNS = {f["name"]: tuple(f["written_by"]) or PROTOCOLS for f in SCHEMA["steps.csv"]}

WEAR_MAP_COLUMNS = tuple(f["name"] for f in SCHEMA["wear_map.csv"])
WEAR_MAP_FACES_COLUMNS = tuple(f["name"] for f in SCHEMA["wear_map_faces.csv"])

# The results of a case's summary.json that study.csv and study.json list.
STUDY_RESULT_KEYS = tuple(
    f["name"] for f in sorted((f for f in SCHEMA["summary.json"] if f["study"]), key=lambda f: f["study"])
)
# study.csv: `case`, the study's inputs (named by their entry path), then
# these (wall_time_s is left out under Output/Testing).
STUDY_CSV_COLUMNS = tuple(f["name"] for f in SCHEMA["study.csv"])

# study.json, the objects of its list `cases`, a case's status.json: key -> type.
STUDY_JSON_KEYS = {f["name"]: f["type"] for f in SCHEMA["study.json"]}
STUDY_CASE_KEYS = {f["name"]: f["type"] for f in SCHEMA["study.json cases"]}
STATUS_JSON_KEYS = {f["name"]: f["type"] for f in SCHEMA["status.json"]}
CALIBRATION_JSON_KEYS = {f["name"]: f["type"] for f in SCHEMA["calibration.json"]}
OPTIMISATION_JSON_KEYS = {f["name"]: f["type"] for f in SCHEMA["optimisation.json"]}

# The solver's traces: iteration and solve counts say how the solver got
# there, not what it computed; compared files leave them out
# (tests/scripts/without_traces.py).
TRACES = tuple(sorted({f["name"] for fields in SCHEMA.values() for f in fields if f["trace"]}))

# The JSON files by name: their keys and types.
JSON_FILES = {
    "summary.json": {key: kind for key, (kind, _) in SUMMARY_KEYS.items()},
    "status.json": STATUS_JSON_KEYS,
    "calibration.json": CALIBRATION_JSON_KEYS,
    "optimisation.json": OPTIMISATION_JSON_KEYS,
    "study.json": STUDY_JSON_KEYS,
}
CSV_FILES = {
    "wear_history.csv": tuple(f["name"] for f in SCHEMA["wear_history.csv"]),
    "steps.csv": tuple(STEPS_COLUMNS),
    "wear_map.csv": WEAR_MAP_COLUMNS,
    "wear_map_faces.csv": WEAR_MAP_FACES_COLUMNS,
    "study.csv": STUDY_CSV_COLUMNS,
}


# The placeholder of an activity's name in the keys and columns of an
# activity mix (activity_NAME_mass_loss_mg, NAME_mass_mg).
ACTIVITY_NAME = "NAME"


def schema_name(name, known):
    """@p name as the schema @p known (keys or columns) names it: a fixed
    name as it is; an activity mix's (activity_walking_mass_loss_mg,
    stair_ascent_mass_loss_mg) as its template with NAME for the activity
    (the template with the longest fixed end that fits); else @p name."""
    if name in known:
        return name
    templates = sorted(
        (t for t in known if ACTIVITY_NAME in t),
        key=lambda t: len(t.split(ACTIVITY_NAME)[1]),
        reverse=True,
    )
    for template in templates:
        prefix, suffix = template.split(ACTIVITY_NAME)
        middle = name[len(prefix) : len(name) - len(suffix)]
        if (
            len(name) > len(prefix) + len(suffix)
            and name.startswith(prefix)
            and name.endswith(suffix)
            and re.fullmatch(r"[a-z0-9_]+", middle)
        ):
            return template
    return name


class ResultError(Exception):
    """A result file that cannot be read as documented: the message is one
    line, `FILE[:LINE]: what`."""


def _excepthook(kind, value, traceback, default=sys.excepthook):
    """An uncaught ResultError: its line on stderr (exit code 1, as for any
    uncaught exception), without a traceback; anything else as usual."""
    if issubclass(kind, ResultError):
        program = (
            os.path.basename(sys.argv[0]) if sys.argv and sys.argv[0] not in ("", "-", "-c") else "python3"
        )
        print(f"{program}: error: {value}", file=sys.stderr)
    else:
        default(kind, value, traceback)


# A script (or a python3 heredoc of a test) that does not catch ResultError
# still ends with one line naming the file and the key.
sys.excepthook = _excepthook


# --------------------------------------------------------------------------
# JSON files


def is_type(value, kind):
    """Whether a JSON value (as json.load gives it) has the schema's type."""
    if kind == "string":
        return isinstance(value, str)
    if kind == "integer":
        return isinstance(value, int) and not isinstance(value, bool)
    if kind == "number":
        return value is None or (isinstance(value, (int, float)) and not isinstance(value, bool))
    if kind == "boolean":
        return isinstance(value, bool)
    if kind == "list":
        return isinstance(value, list)
    if kind == "object":
        return isinstance(value, dict)
    raise ValueError("unknown type " + kind)


def load_json_object(path):
    """The JSON object in @p path as a dict; ResultError if the file is
    missing, unreadable or not a JSON object."""
    try:
        with open(path) as f:
            data = json.load(f)
    except FileNotFoundError:
        raise ResultError(f"{path}: no such file")
    except (OSError, UnicodeDecodeError) as e:
        raise ResultError(f"{path}: cannot read ({e})")
    except ValueError as e:
        raise ResultError(f"{path}: not valid JSON ({e})")
    if not isinstance(data, dict):
        raise ResultError(f"{path}: not a JSON object")
    return data


class Result:
    """The keys of one JSON result file, read by their documented names.

    result[key] is the value, checked against the schema's type; a key that
    is not documented, absent, null where a number is wanted, or of another
    type raises ResultError naming the file and the key. get(key, default)
    gives @p default when the key is absent (for keys that a run writes only
    sometimes)."""

    def __init__(self, path, data, keys):
        self.path = path
        self.data = data
        self.keys = keys

    def __contains__(self, key):
        return key in self.data

    def __iter__(self):
        return iter(self.data)

    def items(self):
        return self.data.items()

    def __getitem__(self, key):
        kind = self.keys.get(schema_name(key, self.keys))
        if kind is None:
            raise ResultError(
                f"{self.path}: {key} is not a documented key of "
                f"{os.path.basename(self.path)} (doc/output.md)"
            )
        if key not in self.data:
            raise ResultError(f"{self.path}: missing key {key}")
        value = self.data[key]
        if kind == "number" and value is None:
            raise ResultError(f"{self.path}: {key} is null (the run computed no finite value)")
        if not is_type(value, kind):
            raise ResultError(f"{self.path}: {key} is {json.dumps(value)}, not of type {kind}")
        return value

    def get(self, key, default=None):
        if schema_name(key, self.keys) in self.keys and key not in self.data:
            return default
        return self[key]


def keys_of(path):
    """The documented keys and types of the JSON file @p path (by name;
    summary.json for any other name, e.g. a stored reference
    one_cycle.summary.json)."""
    name = os.path.basename(path)
    for known, keys in JSON_FILES.items():
        if name == known or name.endswith("." + known):
            return keys
    return JSON_FILES["summary.json"]


def read_json(path):
    """summary.json, status.json or study.json as a Result."""
    return Result(path, load_json_object(path), keys_of(path))


def read_summary(path):
    """A run's summary.json as a Result (doc/output.md, `summary.json`)."""
    return Result(path, load_json_object(path), JSON_FILES["summary.json"])


def check_summary_data(data, path="summary.json"):
    """The differences between summary.json's content @p data and the
    schema: keys not documented, values of another type, keys that the
    run's problem does not write, records with other fields."""
    problems = []
    problem = data.get("problem")
    for key, value in data.items():
        if schema_name(key, SUMMARY_KEYS) not in SUMMARY_KEYS:
            problems.append(f"{path}: key {key} is not documented in doc/output.md")
            continue
        kind, writers = SUMMARY_KEYS[schema_name(key, SUMMARY_KEYS)]
        if not is_type(value, kind):
            problems.append(f"{path}: {key} is {json.dumps(value)}, not of type {kind}")
        if problem in PROBLEMS and problem not in writers:
            problems.append(f"{path}: {key} is not documented for Problem = {problem}")
        if key in SUMMARY_RECORDS and isinstance(value, list):
            fields = set(SUMMARY_RECORDS[key])
            for record in value:
                if not isinstance(record, dict) or set(record) != fields:
                    problems.append(
                        f"{path}: {key} has the record {json.dumps(record)}, not "
                        f"the fields {', '.join(SUMMARY_RECORDS[key])}"
                    )
                    break
    return problems


def check_json_data(data, keys, path):
    """Keys of @p data not in @p keys (key -> type) or of another type."""
    problems = []
    for key, value in data.items():
        if key not in keys:
            problems.append(f"{path}: key {key} is not documented in doc/output.md")
        elif not is_type(value, keys[key]):
            problems.append(f"{path}: {key} is {json.dumps(value)}, not of type {keys[key]}")
    return problems


# --------------------------------------------------------------------------
# CSV files

# Key of the file line numbers of the rows in a table of read_table().
LINE = "#line"


def data_lines(path):
    """[(line number, line)] of @p path without '#' lines and blank lines."""
    try:
        with open(path, newline="") as f:
            return [
                (n, line)
                for n, line in enumerate(f, start=1)
                if line.strip() and not line.lstrip().startswith("#")
            ]
    except FileNotFoundError:
        raise ResultError(f"{path}: no such file")
    except (OSError, UnicodeDecodeError) as e:
        raise ResultError(f"{path}: cannot read ({e})")


def missing_columns_error(path, header, missing):
    shown = ",".join(header)
    shown = shown if len(shown) <= 100 else shown[:97] + "..."
    return ResultError(
        f"{path}: missing column{'s' if len(missing) > 1 else ''} "
        f"{', '.join(missing)} (header line: {shown})"
    )


def read_header(path):
    """The column names of the CSV file @p path (blanks around them
    stripped)."""
    lines = data_lines(path)
    if not lines:
        raise ResultError(f"{path}: empty file (no header line)")
    return [name.strip() for name in next(csv.reader([lines[0][1]]))]


def read_table(path, required, optional=(), text_columns=()):
    """Read a CSV file with a header line into {column name: list}.

    Columns are found by name (surrounding blanks ignored); the ones in
    `required` must exist, the ones in `optional` are read when present,
    all others are ignored. Values are converted to float (to str for
    `text_columns`); a value that is not a finite number is an error.
    Lines starting with '#' and blank lines are skipped. table[LINE] holds
    the line number of each row, for messages.
    """
    lines = data_lines(path)
    if not lines:
        raise ResultError(f"{path}: empty file (no header line)")
    rows = list(csv.reader(line for _, line in lines))
    header = [name.strip() for name in rows[0]]
    missing = [c for c in required if c not in header]
    if missing:
        raise missing_columns_error(path, header, missing)
    wanted = [c for c in list(required) + list(optional) if c in header]
    index = {c: header.index(c) for c in wanted}
    table = {c: [] for c in wanted}
    table[LINE] = []
    for (line_number, _), row in zip(lines[1:], rows[1:]):
        table[LINE].append(line_number)
        if len(row) < len(header):
            raise ResultError(f"{path}:{line_number}: {len(row)} fields, the header has {len(header)}")
        for c in wanted:
            text = row[index[c]].strip()
            if c in text_columns:
                table[c].append(text)
                continue
            try:
                value = float(text)
            except ValueError:
                value = math.nan
            if not math.isfinite(value):
                raise ResultError(f"{path}:{line_number}: column {c}: '{text}' is not a finite number")
            table[c].append(value)
    if len(rows) < 2:
        raise ResultError(f"{path}: no data rows after the header")
    return table


def read_rows(path, required=()):
    """The rows of a CSV file as dicts {column: text} (as csv.DictReader,
    '#' lines and blank lines skipped); the columns in @p required must be
    in the header, and every row must have a field for each column."""
    lines = data_lines(path)
    if not lines:
        raise ResultError(f"{path}: empty file (no header line)")
    rows = list(csv.reader(line for _, line in lines))
    header = [name.strip() for name in rows[0]]
    missing = [c for c in required if c not in header]
    if missing:
        raise missing_columns_error(path, header, missing)
    result = []
    for (line_number, _), row in zip(lines[1:], rows[1:]):
        if len(row) < len(header):
            raise ResultError(f"{path}:{line_number}: {len(row)} fields, the header has {len(header)}")
        result.append(dict(zip(header, row)))
    return result


def number(row, column, path="CSV file"):
    """float(row[column]) of a row of read_rows(); ResultError if the
    column is absent or the value is not a finite number."""
    if column not in row:
        raise ResultError(f"{path}: missing column {column}")
    try:
        value = float(row[column])
    except ValueError:
        value = math.nan
    if not math.isfinite(value):
        raise ResultError(f"{path}: column {column}: '{row[column]}' is not a finite number")
    return value


def check_header(header, name, path):
    """Columns of @p header that the schema of the file @p name does not
    document, or a steps.csv that mixes the protocols' columns."""
    if name == "study.csv":
        # the study's inputs (entry paths) lie between case and status
        if header[:1] != ["case"] or "status" not in header:
            return [f"{path}: a study.csv starts with case and has a status column"]
        header = ["case"] + header[header.index("status") :]
    columns = CSV_FILES[name]
    problems = [
        f"{path}: column {c} is not documented in doc/output.md"
        for c in header
        if schema_name(c, columns) not in columns
    ]
    if name == "steps.csv":
        protocols = [p for p in PROTOCOLS if all(p in STEPS_COLUMNS.get(c, PROTOCOLS) for c in header)]
        if not protocols and not problems:
            problems.append(f"{path}: the columns are not those of one protocol (force or displacement)")
    return problems


# --------------------------------------------------------------------------
# Checks of whole files


def file_kind(path):
    """The documented file that @p path is (by its name, also as a stored
    reference NAME.summary.json), or None."""
    name = os.path.basename(path)
    for known in list(JSON_FILES) + list(CSV_FILES):
        if name == known or name.endswith("." + known):
            return known
    # an activity's of a mix: steps_NAME.csv, wear_map_NAME.csv
    for known in ("steps.csv", "wear_map.csv"):
        stem = known[: -len(".csv")]
        if re.fullmatch(re.escape(stem) + r"_[a-z0-9_]+\.csv", name) and name != "wear_map_faces.csv":
            return known
    return None


def check_file(path):
    """The differences between the result file @p path and the schema
    (a list of one-line messages, empty when it agrees)."""
    kind = file_kind(path)
    if kind is None:
        raise ResultError(f"{path}: not a result file of doc/output.md")
    if kind in CSV_FILES:
        return check_header(read_header(path), kind, path)
    data = load_json_object(path)
    if kind == "summary.json":
        return check_summary_data(data, path)
    problems = check_json_data(data, JSON_FILES[kind], path)
    if kind == "study.json":
        for case in data.get("cases", []) if isinstance(data.get("cases"), list) else []:
            if not isinstance(case, dict):
                problems.append(f"{path}: a case is {json.dumps(case)}, not an object")
                continue
            problems += check_json_data(case, STUDY_CASE_KEYS, f"{path}: case {case.get('case')}")
    return problems


def result_files(paths):
    """The result files among @p paths (directories searched recursively
    for the files of the schema, also as stored references NAME.FILE)."""
    files = []
    for path in paths:
        if os.path.isdir(path):
            for directory, _, names in sorted(os.walk(path)):
                files += [os.path.join(directory, n) for n in sorted(names) if file_kind(n)]
        else:
            files.append(path)
    return files


# --------------------------------------------------------------------------
# Command line


def format_value(value):
    return value if isinstance(value, str) else json.dumps(value)


def main(arguments):
    usage = "usage: tkr_results.py get FILE KEY | check PATH..."
    if arguments[:1] in (["-h"], ["--help"]):
        print(__doc__)
        return 0
    if len(arguments) == 3 and arguments[0] == "get":
        print(format_value(read_json(arguments[1])[arguments[2]]))
        return 0
    if len(arguments) >= 2 and arguments[0] == "check":
        files = result_files(arguments[1:])
        if not files:
            raise ResultError(f"no result files in {' '.join(arguments[1:])}")
        problems = [p for f in files for p in check_file(f)]
        for problem in problems:
            print(problem)
        print(f"tkr_results: {len(files)} result files, {len(problems)} differences from doc/output.md")
        return 1 if problems else 0
    raise ResultError(usage)


if __name__ == "__main__":
    try:
        sys.exit(main(sys.argv[1:]))
    except ResultError as e:
        print(f"tkr_results: error: {e}", file=sys.stderr)
        sys.exit(1)
