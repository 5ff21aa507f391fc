#!/usr/bin/env python3
# SPDX-License-Identifier: LGPL-2.1-or-later
"""The schema of the result files cannot drift: doc/output.md documents
exactly the keys and columns of the program's schema, which
python/tkr_results.py loads from python/result_schema.json.

    check_output_schema.py DOC [--program TKR_WEAR] [RESULT_FILE_OR_DIR...]

With --program, first compares python/result_schema.json with the output
of `TKR_WEAR --print-schema` (the C++ ResultSchema): they must be equal.
Then compares the unit and the meaning of every documented key and column
with the schema's.

Reads the tables of DOC's sections `### \\`FILE\\`` ("Result files") and
compares them with tkr_results: the files, every key and column in the
same order, the types of the JSON keys, the problems (summary.json) and
protocols (steps.csv) that write them, the fields of the summary's lists,
and the traces (tkr_results.TRACES: "a trace" in their meaning, and only
theirs). Then checks each RESULT_FILE (a directory: every result file under
it, also stored references NAME.FILE such as tests/app/one_cycle.summary.json)
against the schema (tkr_results.check_file). Prints each difference and
fails if there is any, so that a key cannot be added, renamed or dropped on
one side only.
"""
import json
import os
import re
import subprocess
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "python"))
import tkr_results  # noqa: E402


def documented_tables(doc):
    """{file name: [table, ...]} of the sections `### `FILE.json`` and
    `### `FILE.csv``; a table is a
    list of rows, a row a list of cells (header and separator left out),
    only rows whose first cell is one `name` in backticks."""
    with open(doc) as f:
        text = f.read()
    sections = {}
    for match in re.finditer(r"^### `([^`]+)`\n(.*?)(?=^#)", text + "\n#", re.M | re.S):
        tables, table = [], None
        for line in match.group(2).splitlines():
            if not line.startswith("|"):
                table = None
                continue
            if table is None:
                table = []
                tables.append(table)
                continue  # the header
            cells = [c.strip() for c in line.strip().strip("|").split(" | ")]
            name = re.fullmatch(r"`([^`]+)`", cells[0])
            if name:
                table.append([name.group(1)] + cells[1:])
        if re.search(r"\.(json|csv)$", match.group(1)):  # not the plots' sections
            sections[match.group(1)] = tables
    return sections


def words(cell):
    return tuple(w.strip() for w in cell.split(","))


def compare(what, documented, named):
    """Differences between two ordered lists of names."""
    problems = []
    for name in documented:
        if name not in named:
            problems.append(f"{what}: {name} is documented but not in tkr_results")
    for name in named:
        if name not in documented:
            problems.append(f"{what}: {name} is in tkr_results but not documented")
    if not problems and list(documented) != list(named):
        problems.append(f"{what}: documented in another order than tkr_results names them")
    return problems


def compare_attributes(what, rows, attributes, column, label):
    """Rows' @p column (a type or a list of writers) against the module's."""
    problems = []
    for row in rows:
        if row[0] in attributes and row[column] != attributes[row[0]]:
            problems.append(
                f"{what}: {row[0]}: {label} {row[column]} in doc/output.md, "
                f"{attributes[row[0]]} in tkr_results"
            )
    return problems


def check_doc(doc):
    sections = documented_tables(doc)
    problems = compare(
        "result files",
        sorted(sections),
        sorted(list(tkr_results.JSON_FILES) + list(tkr_results.CSV_FILES)),
    )
    if problems:
        return problems
    tables = {name: t for name, t in sections.items()}
    # summary.json: key | type | unit | written by | meaning
    summary = tables["summary.json"][0]
    problems += compare("summary.json", [r[0] for r in summary], list(tkr_results.SUMMARY_KEYS))
    problems += compare_attributes(
        "summary.json", summary, {k: v[0] for k, v in tkr_results.SUMMARY_KEYS.items()}, 1, "type"
    )
    writers = {r[0]: tuple(sorted(words(r[3]))) for r in summary}
    for key, (_, problems_of_key) in tkr_results.SUMMARY_KEYS.items():
        if key in writers and writers[key] != tuple(sorted(problems_of_key)):
            problems.append(
                f"summary.json: {key}: written by {', '.join(writers[key])} in doc/output.md, "
                f"{', '.join(sorted(problems_of_key))} in tkr_results"
            )
    for key, fields in tkr_results.SUMMARY_RECORDS.items():
        meaning = next((r[4] for r in summary if r[0] == key), "")
        for field in fields:
            if f"`{field}`" not in meaning:
                problems.append(f"summary.json: {key}: the field {field} is not in its meaning")
    # the CSV files: column | unit | [written by |] meaning
    for name, columns in tkr_results.CSV_FILES.items():
        problems += compare(name, [r[0] for r in tables[name][0]], list(columns))
    protocols = {r[0]: tuple(sorted(words(r[2]))) for r in tables["steps.csv"][0]}
    for column, writers_of_column in tkr_results.STEPS_COLUMNS.items():
        if column in protocols and protocols[column] != tuple(sorted(writers_of_column)):
            problems.append(
                f"steps.csv: {column}: written by {', '.join(protocols[column])} in "
                f"doc/output.md, {', '.join(sorted(writers_of_column))} in tkr_results"
            )
    # study.json (its keys, then the keys of each case), status.json,
    # calibration.json and optimisation.json:
    # key | type | meaning
    for name, keys, index in (
        ("study.json", tkr_results.STUDY_JSON_KEYS, 0),
        ("study.json cases", tkr_results.STUDY_CASE_KEYS, 1),
        ("status.json", tkr_results.STATUS_JSON_KEYS, 0),
        ("calibration.json", tkr_results.CALIBRATION_JSON_KEYS, 0),
        ("optimisation.json", tkr_results.OPTIMISATION_JSON_KEYS, 0),
    ):
        rows = tables[name.split()[0]][index] if len(tables[name.split()[0]]) > index else []
        problems += compare(name, [r[0] for r in rows], list(keys))
        problems += compare_attributes(name, rows, keys, 1, "type")
    # the traces: "a trace" in the meaning of exactly these
    for name, file_tables in tables.items():
        for table in file_tables:
            for row in table:
                said = "a trace" in row[-1]
                if said != (row[0] in tkr_results.TRACES):
                    problems.append(
                        f"{name}: {row[0]}: "
                        + ("'a trace' but not in" if said else "not 'a trace' but in")
                        + " tkr_results.TRACES"
                    )
    return problems


def check_program(program):
    """python/result_schema.json against `program --print-schema`."""
    printed = subprocess.run([program, "--print-schema"], capture_output=True, text=True, check=True).stdout
    if json.loads(printed) == json.load(open(tkr_results.SCHEMA_FILE)):
        return []
    return [
        "python/result_schema.json is not the program's schema: renew it with "
        f"`{program} --print-schema > python/result_schema.json`"
    ]


def check_text(doc):
    """The unit and the meaning of each documented key and column against
    the schema's (the tables' columns: key | type | unit | written by |
    meaning for summary.json, column | unit | [written by |] meaning for a
    CSV file, key | type | meaning for the other JSON files)."""
    problems = []
    tables = documented_tables(doc)
    files = [(name, tables[name][0]) for name in tables]
    files.append(("study.json cases", tables["study.json"][1]))
    for name, rows in files:
        fields = {f["name"]: f for f in tkr_results.SCHEMA[name]}
        for row in rows:
            field = fields.get(row[0])
            if field is None:
                continue
            unit = row[2] if name == "summary.json" else row[1] if name.endswith(".csv") else None
            if unit is not None and unit != field["unit"]:
                problems.append(
                    f"{name}: {row[0]}: unit {unit} in doc/output.md, {field['unit']} in the program"
                )
            if row[-1] != field["meaning"]:
                problems.append(
                    f"{name}: {row[0]}: the meaning in doc/output.md is not the program's:\n"
                    f"    doc:     {row[-1]}\n    program: {field['meaning']}"
                )
    return problems


def main(doc, paths):
    problems = []
    if paths[:1] == ["--program"]:
        problems += check_program(paths[1])
        paths = paths[2:]
    problems += check_doc(doc) + check_text(doc)
    files = tkr_results.result_files(paths)
    for path in files:
        problems += tkr_results.check_file(path)
    for problem in problems:
        print(problem)
    print(
        f"check_output_schema: {len(tkr_results.SUMMARY_KEYS)} summary.json keys, "
        f"{len(files)} result files checked, {len(problems)} differences"
    )
    return 1 if problems else 0


if __name__ == "__main__":
    if len(sys.argv) < 2:
        print(__doc__)
        sys.exit(2)
    try:
        sys.exit(main(sys.argv[1], sys.argv[2:]))
    except tkr_results.ResultError as e:
        print(f"check_output_schema: error: {e}")
        sys.exit(1)
