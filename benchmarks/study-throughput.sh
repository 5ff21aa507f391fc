#!/usr/bin/env bash
# SPDX-License-Identifier: LGPL-2.1-or-later
# benchmarks/study-throughput.sh [RUNS]
# The throughput of Problem = study (doc/studies.md, "Scale"): 8 coarse
# cases (prm/one-cycle.prm, one gait cycle on TKR A coarse, 10,017 DoFs,
# with 8 Latin-hypercube samples of k and the insert's modulus) as one
# study on 2 ranks (Ranks per case = 1) against the same 8 cases one after
# another, each on 1 rank and each on 2 ranks (2 step groups). Wall time
# of the whole processes, the two commands in turn (A B A B ...), medians
# of RUNS pairs (default 3) and the median of the pairs' ratios; every
# case of the study compared
# with its run alone (summary.json, steps.csv, 1e-9 relative).
# Run from the repository root after the Release build; about 15 minutes.
set -eu
runs=${1:-3}
root=$(pwd)
exe=$root/build/release/tkr-wear
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
work=$(mktemp -d)
cd "$work"
cat > study.prm <<PRM
set Problem = study
subsection Study
  set Base parameter file = $root/prm/one-cycle.prm
  set Grid = Output/Plots = false; Output/VTU interval = 0
  set Sampling = latin hypercube
  set Samples = 8
  set Seed = 8
  set Distributions = Wear/Archard/Wear coefficient *= uniform(0.8, 1.2); \\
                      Materials/Tibia/Young's modulus *= uniform(0.8, 1.2)
end
subsection Output
  set Directory = study
  set Plots = false
end
PRM
mpirun -np 2 "$exe" study.prm > first.log 2>&1
for i in 0 1 2 3 4 5 6 7; do
  c=case-000$i
  cp study/$c/case.prm alone-$c.prm
  printf 'subsection Output\n  set Directory = alone/%s\nend\n' $c >> alone-$c.prm
done
# paired RUNS 'COMMAND A' 'COMMAND B': wall seconds of A and B in turn
paired() {
  local i start end
  for ((i = 0; i < $1; i++)); do
    for which in A B; do
      local cmd=$2
      [ $which = B ] && cmd=$3
      start=$(date +%s.%N)
      bash -c "$cmd" > /dev/null 2>&1
      end=$(date +%s.%N)
      echo "$which $start $end"
    done
  done | python3 -c '
import statistics, sys
t = {"A": [], "B": []}
for line in sys.stdin:
    which, start, end = line.split()
    t[which].append(float(end) - float(start))
print("A: median %.1f s (%s)" % (statistics.median(t["A"]), ", ".join("%.1f" % x for x in t["A"])))
print("B: median %.1f s (%s)" % (statistics.median(t["B"]), ", ".join("%.1f" % x for x in t["B"])))
print("A/B: median of the pairs %.3f" % statistics.median(a / b for a, b in zip(t["A"], t["B"])))'
}
cat > sequential-1.sh <<'SH'
for f in alone-case-000*.prm; do "$1" "$f" > /dev/null 2>&1 || exit 1; done
SH
cat > sequential-2.sh <<'SH'
for f in alone-case-000*.prm; do mpirun -np 2 "$1" "$f" > /dev/null 2>&1 || exit 1; done
SH
echo "== study of 8 cases on 2 ranks (Ranks per case = 1) vs the 8 cases one after another on 1 rank each"
paired "$runs" "mpirun -np 2 $exe study.prm" "bash sequential-1.sh $exe"
echo "== the same study vs the 8 cases one after another on 2 ranks each (2 step groups)"
paired "$runs" "mpirun -np 2 $exe study.prm" "bash sequential-2.sh $exe"
echo "== every case of the study = its run alone (1e-9)"
bash sequential-1.sh "$exe"
for i in 0 1 2 3 4 5 6 7; do
  "$root/tests/scripts/compare-files.sh" --relative 1e-9 study/case-000$i alone/case-000$i steps.csv
done
python3 - "$root/python" << 'PY'
import sys
sys.path.insert(0, sys.argv[1])
import tkr_results
worst = 0.0
for i in range(8):
    a = tkr_results.read_summary("study/case-000%d/summary.json" % i)
    b = tkr_results.read_summary("alone/case-000%d/summary.json" % i)
    for key, value in a.items():
        if "time" in key or not isinstance(value, (int, float)):
            continue
        worst = max(worst, abs(value - b[key]) / max(abs(value), 1e-300))
print("summary.json (all numbers but timings): largest relative difference %.3g" % worst)
assert worst <= 1e-9
PY
for f in study/case-000*/status.json; do
  echo "${f#study/}:  \"wall_time_s\": $(python3 "$root/python/tkr_results.py" get "$f" wall_time_s)"
done
echo "work directory: $work"
