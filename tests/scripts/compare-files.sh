#!/usr/bin/env bash
# SPDX-License-Identifier: LGPL-2.1-or-later
# compare-files.sh [--relative R] RESULTS_DIR REFERENCE_PREFIX FILE...
# Compare each FILE written into RESULTS_DIR by a test run with the stored
# REFERENCE_PREFIX.FILE (or REFERENCE_PREFIX/FILE if REFERENCE_PREFIX is a
# directory: the files of another run) by numdiff, with a relative
# tolerance of 1e-6 (and
# an absolute one of 1e-12 for numbers that should be zero). Unlike the
# screen comparison of deal.II's tests (absolute 1e-6), this sees the small
# numbers of summary.json and the CSV files (a wear volume of 1e-5 mm^3).
# The solver's traces (iteration and solve counts) are left out on both
# sides (without_traces.py). Each file the run wrote must also agree with
# the schema of doc/output.md: no key or column that is not documented
# there (python/tkr_results.py check).
set -u
here=$(cd "$(dirname "$0")" && pwd)
rel=1e-6
if [ "${1:-}" = "--relative" ]; then
  rel=$2
  shift 2
fi
dir=$1
prefix=$2
shift 2
status=0
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
for file in "$@"; do
  reference="$prefix.$file"
  [ -d "$prefix" ] && reference="$prefix/$file"
  if [ ! -f "$dir/$file" ]; then
    echo "compare-files: the run did not write $dir/$file"
    status=1
    continue
  fi
  if ! python3 "$here/../../python/tkr_results.py" check "$dir/$file" > "$tmp/schema.txt"; then
    echo "compare-files: $dir/$file does not agree with doc/output.md:"
    cat "$tmp/schema.txt"
    status=1
  fi
  if ! python3 "$here/without_traces.py" "$dir/$file" "$tmp/run.${file##*.}" ||
    ! python3 "$here/without_traces.py" "$reference" "$tmp/reference.${file##*.}"; then
    echo "compare-files: $file or $reference cannot be read"
    status=1
    continue
  fi
  if ! numdiff -q -a 1e-12 -r "$rel" -s ' \t\n=,:;<>[](){}^"' \
      "$tmp/run.${file##*.}" "$tmp/reference.${file##*.}" >/dev/null; then
    echo "compare-files: $file differs from $reference:"
    numdiff -a 1e-12 -r "$rel" -s ' \t\n=,:;<>[](){}^"' "$tmp/run.${file##*.}" \
      "$tmp/reference.${file##*.}" | head -40
    status=1
  else
    echo "compare-files: $file ok"
  fi
done
exit $status
