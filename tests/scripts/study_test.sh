#!/usr/bin/env bash
# SPDX-License-Identifier: LGPL-2.1-or-later
# study_test.sh TKR_WEAR MPIEXEC [TKR_WEAR_TEST]
# Problem = study (doc/studies.md) on the inputs in tests/scripts/study/:
# 1. the 2 x 2 grid (grid.prm) on 2 ranks (two groups of one rank, one
#    queue; and one group of two ranks) and on 1 rank: the same study.csv
#    (to 1e-9 relative);
# 2. each case's case.prm run alone with tkr-wear: summary.json, steps.csv
#    and wear_history.csv equal the study's case to 1e-9 relative; the
#    physics of the inputs: doubling k doubles the mass loss (ratio in
#    [1.9, 2.1]), Channel scales axial_force_N: 0.9 scales the axial force
#    of every step by 0.9 (against data/iso14243-1.csv) and Femur AP
#    offset = 0.5 moves the tibia posteriorly by more than 0 and less than
#    0.5 mm in every step (case-0000 against itself without the offset);
# 3. the grid on 1 rank killed (SIGKILL) while case-0001 runs (after its
#    first checkpoint), resumed with --resume on 2 ranks: the finished case
#    skipped, the interrupted one resumed from its checkpoint, study.csv and
#    every case's files equal the uninterrupted run's (1e-9);
# 4. a cases file with a good case, a value the parameter checks refuse
#    and a contact solver that cannot converge, on 2 ranks: exit code 1,
#    the good case done, the others failed with their reasons;
# 4b. the results each case of 3. kept in its status.json (the run's
#    Wear::RunResult, read in-process) equal its summary.json; with
#    mass_loss_mg taken out of case-0000's, --resume lists that case as
#    failed with a reason that names the key, and exits with 1;
# 5. a path the base file does not have: one message with the study file's
#    line, the case, the entry and the value; exit code 1;
# 6. design variants (generator.prm): meshes/gen/tkr_variant.py meshes
#    each case; R_ts = 55 reproduces the bundled TKR A mesh byte for byte
#    and its flexion axis, R_ts = 70 runs and wears differently.
# 7. an error raised on one rank of a 2-rank case (TKR_TEST_ERROR_ON_RANK,
#    only in tkr-wear-test, the third argument): after 30 s
#    that rank says so and ends the study instead of the other rank waiting
#    forever.
set -u
exe=$1
mpiexec=$2
test_exe=${3:-}
here=$(cd "$(dirname "$0")" && pwd)
data=$here/study
# the readers of the result files (doc/output.md); import tkr_results
# in a python3 heredoc started with "$python_dir" as its first argument
python_dir=$(cd "$here/../../python" && pwd)
results="$python_dir/tkr_results.py"
work=$(pwd)/study_test
rm -rf "$work"
mkdir -p "$work"
cd "$work" || exit 1
fail() {
  echo "study_test: $*"
  exit 1
}
compare() { # DIR REFERENCE_DIR FILE...
  "$here/compare-files.sh" --relative 1e-9 "$@" || fail "$1 differs from $2"
}
cases="case-0000 case-0001 case-0002 case-0003"

# 1.
"$mpiexec" -np 2 "$exe" "$data/grid.prm" > grid2.log 2>&1 ||
  { cat grid2.log; fail "the grid on 2 ranks failed"; }
cat grid2.log
mv grid grid2
"$exe" "$data/grid.prm" > grid1.log 2>&1 ||
  { cat grid1.log; fail "the grid on 1 rank failed"; }
mv grid grid1
compare grid2 grid1 study.csv
printf 'include %s\nsubsection Study\n  set Ranks per case = 2\nend\n' "$data/grid.prm" > pairs.prm
"$mpiexec" -np 2 "$exe" pairs.prm > pairs.log 2>&1 ||
  { cat pairs.log; fail "the grid with 2 ranks per case failed"; }
grep "1 group(s) of 2 rank(s)" pairs.log || fail "not one group of 2 ranks"
compare grid grid1 study.csv
echo "study_test: 1. the grid on 2 ranks (1 or 2 ranks per case) = on 1 rank (study.csv, 1e-9)"

# 2.
for c in $cases; do
  cp "grid2/$c/case.prm" "single-$c.prm"
  printf 'subsection Output\n  set Directory = single/%s\nend\n' "$c" >> "single-$c.prm"
  "$exe" "single-$c.prm" > "single-$c.log" 2>&1 ||
    { tail -5 "single-$c.log"; fail "$c alone failed"; }
  compare "grid2/$c" "single/$c" summary.json steps.csv wear_history.csv
done
echo "study_test: 2. every case of the study = its case.prm run alone (summary.json, steps.csv, wear_history.csv, 1e-9)"
cp grid2/case-0000/case.prm plain.prm
printf 'subsection Gait\n  set Femur AP offset = 0\nend\n' >> plain.prm
printf 'subsection Output\n  set Directory = plain\nend\n' >> plain.prm
"$exe" plain.prm > plain.log 2>&1 || fail "case-0000 without the femur offset failed"
python3 - "$python_dir" "$here/../../data/iso14243-1.csv" << 'EOF'
import csv, sys
sys.path.insert(0, sys.argv.pop(1))
import tkr_results
def summary(c):
    return tkr_results.read_summary("grid2/%s/summary.json" % c)
def steps(d):
    return tkr_results.read_rows(d + "/steps.csv", ("percent", "axial_force_N", "ap_position_mm"))
ratio = [summary(b)["mass_loss_mg"] / summary(a)["mass_loss_mg"]
         for a, b in (("case-0000", "case-0002"), ("case-0001", "case-0003"))]
print("study_test: mass loss k = 2e-7 / k = 1e-7: %.4f, %.4f" % tuple(ratio))
ok = all(1.9 <= r <= 2.1 for r in ratio)
study, plain = steps("grid2/case-0000"), steps("plain")
table = {float(r["percent_cycle"]): float(r["axial_force_N"])
         for r in csv.DictReader(l for l in open(sys.argv[1])
                                 if not l.startswith("#"))}
scale = max(abs(float(s["axial_force_N"]) / table[float(s["percent"])] - 0.9)
            for s in study)
print("study_test: axial force / base axial force - 0.9: max %.2g" % scale)
ok = ok and scale < 1e-9
shift = [float(p["ap_position_mm"]) - float(s["ap_position_mm"])
         for s, p in zip(study, plain)]
print("study_test: tibia moved posteriorly by the femur AP offset 0.5 mm "
      "(case-0000 against itself without the offset): "
      "%.3f to %.3f mm" % (min(shift), max(shift)))
ok = ok and all(0 < d < 0.5 for d in shift)
sys.exit(0 if ok else 1)
EOF
[ $? -eq 0 ] || fail "the inputs' physics"

# 3.
rm -rf grid
"$exe" "$data/grid.prm" > interrupted.log 2>&1 &
pid=$!
for _ in $(seq 1 3000); do
  [ -f grid/case-0001/checkpoint.h5 ] && { kill -9 "$pid"; break; }
  kill -0 "$pid" 2> /dev/null || break
  sleep 0.02
done
wait "$pid" 2> /dev/null
[ $? -eq 137 ] || fail "the study was not killed while case-0001 ran"
[ -f grid/case-0001/status.json ] && fail "case-0001 finished before the kill"
"$mpiexec" -np 2 "$exe" --resume "$data/grid.prm" > resumed.log 2>&1 ||
  { cat resumed.log; fail "the resumed study failed"; }
grep -q "resumed" resumed.log || fail "the study did not say it resumed"
[ "$(python3 "$results" get grid/case-0001/status.json resumed)" = true ] ||
  fail "case-0001 did not resume from its checkpoint"
[ "$(python3 "$results" get grid/case-0000/status.json resumed)" = false ] ||
  fail "case-0000 was run again"
compare grid grid1 study.csv
for c in $cases; do
  compare "grid/$c" "grid1/$c" summary.json steps.csv wear_history.csv
done
echo "study_test: 3. killed during case-0001, resumed on 2 ranks (case-0000 kept, case-0001 from its checkpoint): the uninterrupted results (1e-9)"

# 4.
"$mpiexec" -np 2 "$exe" "$data/fail.prm" > fail.log 2>&1
status=$?
cat fail.log | grep -v "^---\|^Primary\|^mpirun\|^  Process\|^  Exit\|^the job\|^$\|abort"
[ $status -ne 0 ] || fail "a study with failed cases exited with 0"
python3 - "$python_dir" << 'EOF' || fail "4. the failed cases"
import sys
sys.path.insert(0, sys.argv[1])
import tkr_results
rows = {r["case"]: r for r in tkr_results.read_rows("fail/study.csv", ("case", "status", "mass_loss_mg", "reason"))}
ok = (rows["case-0000"]["status"] == "done"
      and float(rows["case-0000"]["mass_loss_mg"]) > 0
      and rows["case-0001"]["status"] == "failed"
      and "Poisson's ratio" in rows["case-0001"]["reason"]
      and "0.7" in rows["case-0001"]["reason"]
      and rows["case-0002"]["status"] == "failed"
      and "did not converge" in rows["case-0002"]["reason"])
sys.exit(0 if ok else 1)
EOF
echo "study_test: 4. one failed input and one failed solve recorded with their reasons, the good case done, exit code $status"

# 4b. The table is written from the results each case kept in its
# status.json (in-process, Wear::RunResult): they equal its summary.json;
# a done case that lacks one of them is listed as failed, naming the key.
python3 - "$python_dir" << 'EOF' || fail "4b. status.json results against summary.json"
import json, sys
sys.path.insert(0, sys.argv[1])
import tkr_results
status = tkr_results.load_json_object("grid/case-0000/status.json")
summary = tkr_results.load_json_object("grid/case-0000/summary.json")
kept = status["results"]
bad = [k for k, v in kept.items() if summary.get(k) != v]
print("study_test: %d results kept in status.json, %d differ from summary.json" % (len(kept), len(bad)))
del status["results"]["mass_loss_mg"]
with open("grid/case-0000/status.json", "w") as f:
    json.dump(status, f, indent=2)
sys.exit(1 if bad or not kept else 0)
EOF
if "$exe" --resume "$data/grid.prm" > missing.log 2>&1; then
  fail "4b. a case without its mass_loss_mg was listed as done"
fi
python3 - "$python_dir" << 'EOF' || fail "4b. the missing result"
import sys
sys.path.insert(0, sys.argv[1])
import tkr_results
rows = {r["case"]: r for r in tkr_results.read_rows("grid/study.csv", ("case", "status", "reason"))}
row = rows["case-0000"]
print("study_test: case-0000 %s: %s" % (row["status"], row["reason"]))
sys.exit(0 if row["status"] == "failed" and "has no result mass_loss_mg" in row["reason"] else 1)
EOF
echo "study_test: 4b. the table from the results kept in status.json; a missing one fails its case by name"

# 5.
if "$exe" "$data/wrong.prm" > wrong.log 2>&1; then
  fail "a wrong entry path was accepted"
fi
cat wrong.log
grep -q "wrong.prm:4: case-0000 sets <Wear/Wear coeficient> = <1e-7>" wrong.log ||
  fail "5. unexpected message"
echo "study_test: 5. a wrong path refused with file:line, case, entry and value"
# 6.
"$mpiexec" -np 2 "$exe" "$data/generator.prm" > generator.log 2>&1 ||
  { cat generator.log; fail "6. the design variants failed"; }
cat generator.log
cmp -s generator/case-0000/mesh.msh "$here/../../meshes/tkr/tkr-a-coarse.msh" ||
  fail "6. R_ts = 55 did not reproduce meshes/tkr/tkr-a-coarse.msh"
grep -q "Flexion axis point = 0, -2, 53.001" generator/case-0000/mesh.prm ||
  fail "6. the flexion axis of TKR A"
python3 - "$python_dir" << 'EOF'
import sys
sys.path.insert(0, sys.argv[1])
import tkr_results
rows = {r["case"]: r for r in tkr_results.read_rows("generator/study.csv", ("case", "status", "mass_loss_mg"))}
a, b = (float(rows[c]["mass_loss_mg"]) for c in ("case-0000", "case-0001"))
print("study_test: mass loss R_ts = 55: %.4f mg, R_ts = 70: %.4f mg" % (a, b))
sys.exit(0 if rows["case-0001"]["status"] == "done" and a != b else 1)
EOF
[ $? -eq 0 ] || fail "6. the variants' results"
echo "study_test: 6. design variants meshed per case by meshes/gen/tkr_variant.py (R_ts = 55 gives the bundled TKR A mesh and flexion axis)"
# 7.
if [ -n "$test_exe" ]; then
  printf 'include %s\nsubsection Output\n  set Directory = one_rank\nend\n' \
    "$work/pairs.prm" > one_rank.prm
  TKR_TEST_ERROR_ON_RANK=1 timeout 200 "$mpiexec" -np 2 "$test_exe" one_rank.prm > one_rank.log 2>&1
  status=$?
  cat one_rank.log
  [ $status -ne 124 ] || fail "7. a one-rank error in a case hung the study"
  [ $status -ne 0 ] || fail "7. a one-rank error in a case: exit code 0"
  grep -q "tkr-wear: case-0000: error on rank 1 that the other ranks of its group did not raise within 30 s; ending the study (--resume continues it): TKR_TEST_ERROR_ON_RANK" one_rank.log ||
    fail "7. unexpected message"
  echo "study_test: 7. an error on one rank of a 2-rank case ends the study with one message (exit code $status)"
else
  echo "study_test: 7. skipped (no tkr-wear-test given)"
fi
echo "study_test: passed"
