#!/usr/bin/env bash
# SPDX-License-Identifier: LGPL-2.1-or-later
# optimisation_test.sh TKR_WEAR MPIEXEC
# Problem = optimisation (doc/optimisation.md) on tests/scripts/optimisation/:
# 1. COBYLA on the test function with a constraint finds the known optimum
#    (ML spring stiffness 9, wear coefficient 1.99526e-7, mass 1.01) within
#    1e-4 of the range, on 2 ranks; optimisation.json as doc/output.md says;
# 2. BOBYQA (no constraint) finds u = 0.3: 11 and 1.99526e-7, mass 1;
# 3. --resume replays the method: an optimisation stopped after 10
#    evaluations and resumed reads those 10 back and ends where a whole run
#    ends;
# 4. wear runs, 2 ranks: the failed evaluations (non-integer steps per
#    cycle) are failed, never the best; every done evaluation's objective
#    is its summary.json's; best.prm runs the best design again with the
#    same volume (1e-9);
# 5. bad inputs refused before any run, exit 1, naming the entry: an
#    unknown path, empty bounds, an objective that is not a result, a start
#    outside the bounds, BOBYQA with constraints, an initial design that
#    leaves the method nothing, bad scenarios, a verification mesh without
#    a generator, an unknown verification entry;
# 6. the initial design (a Latin hypercube: one point per third of the
#    range) runs in parallel, one rank per run; with two scenarios each
#    evaluation's objective is the weighted sum of its runs' volumes and
#    its constraint the worst pressure (and with Combine = worst case the
#    larger volume); the verification's numbers are those of its runs.
set -u
exe=$1
mpiexec=$2
here=$(cd "$(dirname "$0")" && pwd)
data=$here/optimisation
python=/usr/bin/python3
results=$here/../../python/tkr_results.py
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work" || exit 1
failures=0
check() { # check NAME COMMAND...: run COMMAND, report ok/FAILED
  name=$1
  shift
  if "$@"; then echo "ok: $name"; else echo "FAILED: $name"; failures=$((failures + 1)); fi
}
near() { # near DIR PATH VALUE TOLERANCE: best_inputs[PATH] within TOL (relative)
  "$python" - "$@" <<'PY'
import json, sys
directory, path, value, tolerance = sys.argv[1], sys.argv[2], float(sys.argv[3]), float(sys.argv[4])
got = json.load(open(directory + "/optimisation.json"))["best_inputs"][path]
print("%s: %.9g, known %.9g" % (path, got, value))
sys.exit(0 if abs(got - value) <= tolerance * abs(value) else 1)
PY
}
best() { # best DIR VALUE TOLERANCE: best_objective within TOL (absolute)
  "$python" - "$@" <<'PY'
import json, sys
r = json.load(open(sys.argv[1] + "/optimisation.json"))
print("best objective %.12g after %d evaluations (%s)" % (r["best_objective"], r["evaluations"], r["stop_reason"]))
sys.exit(0 if r["feasible"] and abs(r["best_objective"] - float(sys.argv[2])) <= float(sys.argv[3]) else 1)
PY
}

# 1. COBYLA with a constraint, 2 ranks.
$mpiexec -np 2 "$exe" "$data/quadratic.prm" > cobyla.log 2>&1
check "cobyla: exit 0" test $? -eq 0
check "cobyla: ML spring stiffness 9" near quadratic "Gait/ML spring stiffness" 9 2e-4
check "cobyla: wear coefficient 1.99526e-7" near quadratic "Wear/Archard/Wear coefficient" 1.99526231497e-7 2e-4
check "cobyla: mass 1.01, feasible" best quadratic 1.01 1e-6
check "cobyla: optimisation.json as doc/output.md says" \
  "$python" "$results" check quadratic/optimisation.json

# 2. BOBYQA, bounds only.
sed -e 's/^  set Constraints.*$/  set Method = bobyqa/' -e 's/Directory = quadratic/Directory = bobyqa/' \
  -e 's|= base.prm|= '"$data"'/base.prm|' "$data/quadratic.prm" > bobyqa.prm
"$exe" bobyqa.prm > bobyqa.log 2>&1
check "bobyqa: exit 0" test $? -eq 0
check "bobyqa: ML spring stiffness 11" near bobyqa "Gait/ML spring stiffness" 11 2e-4
check "bobyqa: mass 1" best bobyqa 1 1e-8

# 2b. COBYLA from the best of an initial design of 8 points, 2 ranks.
sed -e 's/^  set Test function.*$/&\n  set Initial design = 8/' -e 's/Directory = quadratic/Directory = design/' \
  -e 's|= base.prm|= '"$data"'/base.prm|' "$data/quadratic.prm" > design.prm
$mpiexec -np 2 "$exe" design.prm > design.log 2>&1
check "design: exit 0" test $? -eq 0
check "design: 9 evaluations before the method" grep -q "^eval-0008:" design.log
check "design: ML spring stiffness 9" near design "Gait/ML spring stiffness" 9 2e-4
check "design: mass 1.01, feasible" best design 1.01 1e-6

# 3. Stopped after 10 evaluations, resumed.
sed -e 's/Maximum evaluations = 200/Maximum evaluations = 10/' -e 's/Directory = quadratic/Directory = resumed/' \
  -e 's|= base.prm|= '"$data"'/base.prm|' "$data/quadratic.prm" > first.prm
sed -e 's/Directory = quadratic/Directory = resumed/' -e 's|= base.prm|= '"$data"'/base.prm|' \
  "$data/quadratic.prm" > resumed.prm
"$exe" first.prm > first.log 2>&1
"$exe" --resume resumed.prm > resumed.log 2>&1
check "resume: exit 0" test $? -eq 0
check "resume: 10 evaluations read back" test "$(grep -c 'read back' resumed.log)" -eq 10
check "resume: the same optimum as a whole run" \
  cmp <(grep -v '"stop_reason"' quadratic/optimisation.json) <(grep -v '"stop_reason"' resumed/optimisation.json)

# 4. Wear runs on 2 ranks, with failed evaluations.
$mpiexec -np 2 "$exe" "$data/wear.prm" > wear.log 2>&1
check "wear: exit 0" test $? -eq 0
check "wear: 4 evaluations, some failed on the integer entry" \
  "$python" - <<'PY'
import csv, json, sys
rows = list(csv.DictReader(open("wear/optimisation.csv")))
failed = [r for r in rows if r["status"] == "failed"]
done = [r for r in rows if r["status"] == "done"]
ok = len(rows) == 4 and failed and all("Steps per cycle" in r["reason"] for r in failed)
for r in done:
    s = json.load(open("wear/%s/summary.json" % r["evaluation"]))
    ok = ok and float(r["volume_loss_mm3"]) == float("%.12g" % s["volume_loss_mm3"])
best = json.load(open("wear/optimisation.json"))
least = min(done, key=lambda r: float(r["volume_loss_mm3"]))
ok = ok and best["best_evaluation"] == least["evaluation"] and best["failed_evaluations"] == len(failed)
print("%d done, %d failed; best %s" % (len(done), len(failed), best["best_evaluation"]))
sys.exit(0 if ok else 1)
PY
"$exe" wear/best.prm > best.log 2>&1
check "wear: best.prm runs" test $? -eq 0
check "wear: best.prm gives the best volume" "$python" - <<'PY'
import json, sys
best = json.load(open("wear/optimisation.json"))["best_objective"]
again = json.load(open("wear/best/summary.json"))["volume_loss_mm3"]
print("best %.12g, again %.12g" % (best, again))
sys.exit(0 if abs(again - best) <= 1e-9 * abs(best) else 1)
PY

# 6. The initial design in parallel (2 ranks, one per run), two scenarios
#    (weights 0.25 and 0.75) and the verification with other entries.
$mpiexec -np 2 "$exe" "$data/parallel.prm" > parallel.log 2>&1
check "parallel: exit 0" test $? -eq 0
check "parallel: the initial design, the scenarios, the verification" \
  "$python" - <<'PY'
import csv, json, sys
rows = list(csv.DictReader(open("parallel/optimisation.csv")))
result = json.load(open("parallel/optimisation.json"))
ok = len(rows) == 6
# eval-0001..0003: one point of the Latin hypercube in each third of 5 .. 25
thirds = sorted(int(3 * (float(r["Gait/ML spring stiffness"]) - 5) / 20) for r in rows[1:4])
ok = ok and thirds == [0, 1, 2]
weights = {"light": 0.25, "heavy": 0.75}
def combined(directory):
    runs = {s: json.load(open("%s/%s/summary.json" % (directory, s))) for s in weights}
    volume = sum(w * runs[s]["volume_loss_mm3"] for s, w in weights.items())
    pressure = max(r["max_pressure_MPa"] for r in runs.values())
    return volume, pressure, runs
for r in rows:
    volume, pressure, runs = combined("parallel/" + r["evaluation"])
    ok = ok and abs(float(r["volume_loss_mm3"]) - volume) <= 1e-9 * volume
    ok = ok and abs(float(r["max_pressure_MPa"]) - pressure) <= 1e-9 * pressure
    ok = ok and all(abs(float(r["volume_loss_mm3@" + s]) - runs[s]["volume_loss_mm3"]) <= 1e-9 * volume for s in weights)
    # the runs of the initial design and the scenarios went one rank each
    ok = ok and all("MPI ranks: 1 in 1" in open("parallel/%s/%s/log.txt" % (r["evaluation"], s)).read() for s in weights)
start, _, _ = combined("parallel/verify-start")
best, best_pressure, runs = combined("parallel/verify-best")
ok = ok and abs(result["verification_start_objective"] - start) <= 1e-9 * start
ok = ok and abs(result["verification_best_objective"] - best) <= 1e-9 * best
ok = ok and result["verification_status"] == "done" and result["verification_best_feasible"]
ok = ok and result["scenario_weights"] == weights
print("%d evaluations; LHS thirds %s; verification start %.9g best %.9g" % (len(rows), thirds, start, best))
sys.exit(0 if ok else 1)
PY
check "parallel: the verification ran with 24 steps per cycle" \
  grep -q "Steps per cycle *= 24" parallel/verify-best/light/case.prm
check "parallel: optimisation.json as doc/output.md says" \
  "$python" "$results" check parallel/optimisation.json
check "parallel: the plots" test -s parallel/optimisation_convergence.png -a -s parallel/optimisation_wear_maps.png
# Stopped (SIGTERM to the ranks) during the initial design's runs: exit 3,
# the table so far written, and --resume ends where the whole run ends.
sed -e 's/Directory = parallel/Directory = stopped/' -e 's|= base.prm|= '"$data"'/base.prm|' \
  -e 's|: light.prm|: '"$data"'/light.prm|' -e 's|: heavy.prm|: '"$data"'/heavy.prm|' \
  "$data/parallel.prm" > stopped.prm
$mpiexec -np 2 "$exe" stopped.prm > stopped.log 2>&1 &
pid=$!
for _ in $(seq 600); do grep -q "Degrees of freedom" stopped/eval-0000/light/log.txt 2>/dev/null && break; sleep 0.1; done
pkill -TERM -P $pid -x tkr-wear
wait $pid
check "stopped during the initial design: exit 3" test $? -eq 3
check "... the message" grep -q "Stopped by SIGTERM.*tkr-wear --resume stopped.prm continues the optimisation" stopped.log
$mpiexec -np 2 "$exe" --resume stopped.prm > stopped-resume.log 2>&1
check "... resumed: exit 0" test $? -eq 0
check "... the whole run's optimum" \
  cmp <(grep -v '"stop_reason"' parallel/optimisation.json) <(grep -v '"stop_reason"' stopped/optimisation.json)

sed -e 's/Initial design *= 3/Initial design = 1/' -e 's/Maximum evaluations *= 6/Maximum evaluations = 3/' \
  -e 's/^  set Verification.*$/  set Combine scenarios = worst case/' -e 's/Directory = parallel/Directory = worst/' \
  -e 's|= base.prm|= '"$data"'/base.prm|' -e 's|: light.prm|: '"$data"'/light.prm|' \
  -e 's|: heavy.prm|: '"$data"'/heavy.prm|' "$data/parallel.prm" > worst.prm
$mpiexec -np 2 "$exe" worst.prm > worst.log 2>&1
check "worst case: exit 0" test $? -eq 0
check "worst case: the objective is the larger scenario's" "$python" - <<'PY'
import csv, sys
rows = list(csv.DictReader(open("worst/optimisation.csv")))
ok = len(rows) == 3 and all(
    float(r["volume_loss_mm3"]) == max(float(r["volume_loss_mm3@light"]), float(r["volume_loss_mm3@heavy"])) for r in rows)
sys.exit(0 if ok else 1)
PY

# 5. Bad inputs: refused with the entry named, before any run.
refused() { # refused NAME SED-EXPRESSION MESSAGE
  sed -e "$2" -e 's|= base.prm|= '"$data"'/base.prm|' -e 's/Directory = quadratic/Directory = bad/' \
    "$data/quadratic.prm" > bad.prm
  rm -rf bad
  "$exe" bad.prm > bad.log 2>&1
  local status=$?
  if [ $status -eq 1 ] && grep -q "$3" bad.log && [ ! -d bad/eval-0000 ]; then
    echo "ok: refused: $1"
  else
    echo "FAILED: refused: $1 (exit $status)"
    cat bad.log
    failures=$((failures + 1))
  fi
}
refused "unknown path" 's|Gait/ML spring stiffness = 5|Gait/No such entry = 5|' \
  "Optimisation/Variables (.*bad.prm:[0-9]*).*<Gait/No such entry> is not an entry"
refused "empty bounds" 's|= 5 .. 25|= 25 .. 5|' \
  "Optimisation/Variables (.*bad.prm:[0-9]*): Gait/ML spring stiffness: the bounds 25 .. 5 are empty"
refused "objective not a result" 's|minimise mass_loss_mg|minimise mass_los_mg|' \
  "Optimisation/Objective (.*bad.prm:[0-9]*): <mass_los_mg> is not"
refused "start outside the bounds" 's|= 5 .. 25|= 12 .. 25|' \
  "lies outside 12 .. 25 (an infeasible start)"
refused "bobyqa with constraints" 's|Test function = quadratic|Method = bobyqa|' \
  "Optimisation/Method (.*bad.prm:[0-9]*): bobyqa takes bounds only"
refused "initial design too large" 's|Test function = quadratic|Initial design = 199|' \
  "Optimisation/Initial design (.*bad.prm:[0-9]*) = 199: the start and the initial design leave no evaluation"
refused "scenario file missing" 's|Test function = quadratic|Scenarios = a: 1: no-such.prm|' \
  "Optimisation/Scenarios (.*bad.prm:[0-9]*): a: the file <.*no-such.prm> does not exist"
refused "scenario not NAME: WEIGHT: FILE" 's|Test function = quadratic|Scenarios = a: base.prm|' \
  "Optimisation/Scenarios (.*bad.prm:[0-9]*): <a: .*base.prm> is not NAME: WEIGHT: FILE"
refused "verification mesh without a generator" \
  's|Test function = quadratic|Verification mesh generator arguments = --resolution medium|' \
  "Optimisation/Verification mesh generator arguments (.*bad.prm:[0-9]*): there is no Mesh generator"
refused "verification entry unknown" 's|Test function = quadratic|Verification entries = Mesh/Fil = x.msh|' \
  "<Mesh/Fil> is not an entry"

echo "$failures failure(s)"
exit $((failures > 0))
