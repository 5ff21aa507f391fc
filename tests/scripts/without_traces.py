#!/usr/bin/env python3
# SPDX-License-Identifier: LGPL-2.1-or-later
"""Copy a result file without the solver's traces, for compare-files.sh.

    without_traces.py IN OUT

The iteration and solve counts of a run (JSON keys or CSV columns named in
tkr_results.TRACES, "a trace" in doc/output.md) say how the solver got
there, not what it computed, so a better solver must not change a test's
compared files. Other files are copied.
"""
import csv
import json
import os
import shutil
import sys

# The readers of the result files (doc/output.md, "Result files").
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "python"))
import tkr_results  # noqa: E402

TRACES = set(tkr_results.TRACES)


def main(source, target):
    if source.endswith(".json"):
        data = tkr_results.load_json_object(source)
        with open(target, "w") as f:
            json.dump({k: v for k, v in data.items() if k not in TRACES}, f, indent=2)
    elif source.endswith(".csv"):
        with open(source, newline="") as f:
            rows = list(csv.reader(f))
        keep = [i for i, name in enumerate(rows[0] if rows else []) if name not in TRACES]
        with open(target, "w", newline="") as f:
            csv.writer(f, lineterminator="\n").writerows(
                [row[i] for i in keep if i < len(row)] for row in rows
            )
    else:
        shutil.copyfile(source, target)


if __name__ == "__main__":
    try:
        main(sys.argv[1], sys.argv[2])
    except tkr_results.ResultError as e:
        sys.exit(f"without_traces: error: {e}")
