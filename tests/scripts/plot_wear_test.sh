#!/usr/bin/env bash
# SPDX-License-Identifier: LGPL-2.1-or-later
# Test of scripts/plot-wear on a tiny synthetic output directory (a 10 x 10
# node grid with a Gaussian wear depth, a 5-row history): the PNGs are
# written and valid (also with a run-in factor, drawn on mass_loss.png),
# and input errors give exit code 1 and one line.
# Run from anywhere: bash tests/scripts/plot_wear_test.sh. Exit code 0 only
# when every check passed. Needs python3 and Debian's python3-matplotlib
# and python3-numpy (plot-wear finds /usr/bin/python3 by itself).
set -uo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
plot="$root/scripts/plot-wear"
measured="$root/data/measured/example-gravimetric.csv"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
# n_passed, n_failed, check, is_png, one_line_error
source "$root/tests/scripts/plot_checks.sh"

echo "== plot-wear on a synthetic output directory ($work)"
python3 "$root/tests/scripts/make_synthetic_output.py" "$work/run"
"$plot" "$work/run" --measured "$measured" --title "Synthetic test case" \
  2>"$work/stderr"
status=$?
check "plot-wear exits 0 (got $status)" test $status -eq 0
check "plot-wear prints nothing on stderr" test ! -s "$work/stderr"
cat "$work/stderr" >&2
check "mass_loss.png is a PNG" is_png "$work/run/mass_loss.png"
check "wear_map.png is a PNG" is_png "$work/run/wear_map.png"
check "cross_shear_map.png is a PNG" is_png "$work/run/cross_shear_map.png"

check "--help exits 0" "$plot" --help >/dev/null

echo "== a run with a run-in (summary.json's run_in_factor)"
cp -r "$work/run" "$work/run_in"
python3 - "$root/python" "$work/run_in/summary.json" <<'EOF2'
import json, sys
sys.path.insert(0, sys.argv.pop(1))
import tkr_results
summary = tkr_results.load_json_object(sys.argv[1])
summary["run_in_factor"] = [{"cycles": 0, "factor": 3}, {"cycles": 1e6, "factor": 1}]
json.dump(summary, open(sys.argv[1], "w"))
EOF2
"$plot" "$work/run_in" 2>"$work/stderr"
status=$?
cat "$work/stderr" >&2
check "run-in: exit 0, nothing on stderr" test $status -eq 0 -a ! -s "$work/stderr"
check "run-in: mass_loss.png is a PNG" is_png "$work/run_in/mass_loss.png"
differs() { ! cmp -s "$1" "$2"; }
check "run-in: mass_loss.png differs from the run without" \
  differs "$work/run/mass_loss.png" "$work/run_in/mass_loss.png"
python3 - "$root/python" "$work/run_in/summary.json" <<'EOF2'
import json, sys
sys.path.insert(0, sys.argv.pop(1))
import tkr_results
summary = tkr_results.load_json_object(sys.argv[1])
summary["run_in_factor"] = [{"cycles": "zero"}]  # malformed on purpose
json.dump(summary, open(sys.argv[1], "w"))
EOF2
"$plot" "$work/run_in" 2>"$work/stderr"
status=$?
cat "$work/stderr"
check "malformed run_in_factor: exit 0, one warning" \
  test $status -eq 0 -a "$(grep -c "run_in_factor ignored" "$work/stderr")" -eq 1

echo "== input errors"
cp -r "$work/run" "$work/no_history"
rm "$work/no_history/wear_history.csv"
"$plot" "$work/no_history" 2>"$work/stderr"
status=$?
cat "$work/stderr"
check "missing wear_history.csv: exit 1, one line" \
  one_line_error "$work/stderr" $status "wear_history.csv: no such file"

cp -r "$work/run" "$work/no_column"
sed -i '1s/mass_mg/mass/' "$work/no_column/wear_history.csv"
"$plot" "$work/no_column" 2>"$work/stderr"
status=$?
cat "$work/stderr"
check "missing column mass_mg: exit 1, one line" \
  one_line_error "$work/stderr" $status "missing column mass_mg"

cp -r "$work/run" "$work/bad_face"
echo "0,1,2,100" >>"$work/bad_face/wear_map_faces.csv"
"$plot" "$work/bad_face" 2>"$work/stderr"
status=$?
cat "$work/stderr"
check "node index out of range: exit 1, one line" \
  one_line_error "$work/stderr" $status "must be integers in 0..99"

echo "$n_passed passed, $n_failed failed"
[[ $n_failed -eq 0 ]]
