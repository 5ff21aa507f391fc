#!/usr/bin/env bash
# SPDX-License-Identifier: LGPL-2.1-or-later
# Test of scripts/plot-optimisation on a tiny synthetic optimisation output
# (5 evaluations of two variables: one failed, one infeasible; a 2-face
# wear map of the start and of the best): the three PNGs and
# optimisation_plots.txt are written with the right counts and best; the
# same without optimisation.json (columns inferred); a missing wear map
# skips that plot only; input errors give exit code 1 and one line.
# Run from anywhere: bash tests/scripts/plot_optimisation_test.sh. Exit code
# 0 only when every check passed. Needs python3 and Debian's
# python3-matplotlib and python3-numpy (the script finds /usr/bin/python3
# by itself).
set -uo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
plot="$root/scripts/plot-optimisation"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
# n_passed, n_failed, check, is_png, one_line_error
source "$root/tests/scripts/plot_checks.sh"

has_line() { # has_line FILE LINE: FILE has exactly this line
  grep -qxF -- "$2" "$1" || { echo "  $1: no line '$2'" >&2; return 1; }
}

# wear_map DIR PEAK: a 3 x 2 node map (two quadrilateral faces), depth PEAK
# at the middle nodes
wear_map() {
  mkdir -p "$1"
  cat >"$1/wear_map.csv" <<EOF
x,y,z,depth_mm,cross_shear
-10,-5,0,0,0
0,-5,0,$2,0.01
10,-5,0,0,0
-10,5,0,0.001,0
0,5,0,$2,0.02
10,5,0,0,0
EOF
  cat >"$1/wear_map_faces.csv" <<EOF
n0,n1,n2,n3
0,1,4,3
1,2,5,4
EOF
}

# Synthetic (not a run): eval-0001 infeasible (max_pressure_MPa > 14),
# eval-0002 failed, eval-0003 the best (4 of the start's 5).
run=$work/opt
mkdir -p "$run"
cat >"$run/optimisation.csv" <<'EOF'
evaluation,status,Generator/R_ts,Gait/ML spring stiffness,mass_loss_mg,max_pressure_MPa,feasible,best_objective,wall_time_s,reason
eval-0000,done,1,2,5,12,1,5,0.1,
eval-0001,done,2,2,3,15,0,5,0.1,
eval-0002,failed,2,3,,,0,5,0.1,"the mesh is distorted, run stopped"
eval-0003,done,1.5,2.5,4,13,1,4,0.1,
eval-0004,done,1.2,2.2,4.5,13.5,1,4,0.1,
EOF
cat >"$run/optimisation.json" <<'EOF'
{
  "problem": "optimisation",
  "method": "cobyla",
  "objective": "minimise mass_loss_mg",
  "constraints": "max_pressure_MPa <= 14",
  "evaluations": 5,
  "failed_evaluations": 1,
  "stop_reason": "synthetic",
  "feasible": true,
  "best_evaluation": "eval-0003",
  "best_objective": 4,
  "best_inputs": {"Generator/R_ts": 1.5, "Gait/ML spring stiffness": 2.5},
  "start_objective": 5
}
EOF
wear_map "$run/eval-0000" 0.02
wear_map "$run/eval-0003" 0.01

echo "== plot-optimisation on a synthetic optimisation ($run)"
"$plot" "$run" >"$work/stdout" 2>"$work/stderr"
status=$?
cat "$work/stdout"
cat "$work/stderr" >&2
check "exits 0 (got $status)" test $status -eq 0
check "prints nothing on stderr" test ! -s "$work/stderr"
check "optimisation_convergence.png is a PNG" is_png "$run/optimisation_convergence.png"
check "optimisation_variables.png is a PNG" is_png "$run/optimisation_variables.png"
check "optimisation_wear_maps.png is a PNG" is_png "$run/optimisation_wear_maps.png"
txt=$run/optimisation_plots.txt
check "optimisation_plots.txt written" test -s "$txt"
check "5 evaluations" has_line "$txt" "evaluations: 5"
check "4 done" has_line "$txt" "done: 4"
check "1 failed" has_line "$txt" "failed: 1"
check "3 feasible" has_line "$txt" "feasible: 3"
check "start objective 5" has_line "$txt" "start_objective: 5"
check "best eval-0003" has_line "$txt" "best_evaluation: eval-0003"
check "best objective 4" has_line "$txt" "best_objective: 4"
check "best / start 0.8" has_line "$txt" "best_over_start: 0.8"
check "best input" has_line "$txt" "best_input Gait/ML spring stiffness: 2.5 (start 2)"
check "--help exits 0" "$plot" --help >/dev/null

echo "== without optimisation.json (an interrupted run): columns inferred"
cp -r "$run" "$work/no_json"
rm "$work/no_json/optimisation.json" "$work/no_json"/*.png "$work/no_json/optimisation_plots.txt"
"$plot" "$work/no_json" >"$work/stdout" 2>"$work/stderr"
status=$?
cat "$work/stderr" >&2
check "no json: exit 0, nothing on stderr" test $status -eq 0 -a ! -s "$work/stderr"
check "no json: best eval-0003" has_line "$work/no_json/optimisation_plots.txt" "best_evaluation: eval-0003"
check "no json: variables inferred" has_line "$work/no_json/optimisation_plots.txt" \
  "variables: Generator/R_ts, Gait/ML spring stiffness"
check "no json: wear maps" is_png "$work/no_json/optimisation_wear_maps.png"

echo "== no wear map of the best: that plot skipped, not an error"
cp -r "$run" "$work/no_map"
rm "$work/no_map"/*.png "$work/no_map/eval-0003/wear_map.csv"
"$plot" "$work/no_map" >"$work/stdout" 2>"$work/stderr"
status=$?
grep wear_maps "$work/stdout"
cat "$work/stderr" >&2
check "no map: exit 0, nothing on stderr" test $status -eq 0 -a ! -s "$work/stderr"
check "no map: said on stdout" grep -q "wear_maps: skipped (eval-0003 has no wear_map.csv)" "$work/stdout"
check "no map: no optimisation_wear_maps.png" test ! -e "$work/no_map/optimisation_wear_maps.png"
check "no map: the other plots" is_png "$work/no_map/optimisation_variables.png"

echo "== input errors"
mkdir "$work/empty"
"$plot" "$work/empty" >/dev/null 2>"$work/stderr"
status=$?
cat "$work/stderr"
check "missing optimisation.csv: exit 1, one line" \
  one_line_error "$work/stderr" $status "optimisation.csv: no such file"

cp -r "$run" "$work/bad_row"
sed -i 's/^eval-0004,done,1.2,/eval-0004,done,big,/' "$work/bad_row/optimisation.csv"
"$plot" "$work/bad_row" >/dev/null 2>"$work/stderr"
status=$?
cat "$work/stderr"
check "malformed row: exit 1, one line with the file and line" \
  one_line_error "$work/stderr" $status "optimisation.csv:6: column Generator/R_ts: 'big'"

echo "$n_passed passed, $n_failed failed"
[[ $n_failed -eq 0 ]]
