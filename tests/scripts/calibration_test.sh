#!/usr/bin/env bash
# SPDX-License-Identifier: LGPL-2.1-or-later
# calibration_test.sh TKR_WEAR MPIEXEC
# Problem = calibration (doc/calibration.md) on tests/scripts/calibration/:
# 1. two designs (coarse TKR A and B, 4-step gait), synthetic "measured"
#    data from runs with k = 3e-7 and a run-in 2.5 -> 1 at 4e5 cycles,
#    three specimens each (factors 0.96, 1.01, 1.03, +-1 % noise;
#    make_synthetic.py), on 2 ranks: one shared k, run-in factor and
#    length recovered, each within its interval and the interval holding
#    the true value; 2 wear runs per design, verified; calibration.json's
#    keys and types those of doc/output.md;
# 2. calibrated.prm runs and gives the mass of the last calibration run
#    of design A (relative 1e-9);
# 3. one specimen: the interval from the residuals holds the true values;
# 4. the run-in length fitted without weighings during the run-in:
#    refused with one message before any run, exit 1;
# 5. data that say they are illustrative: the output says so;
# 6. a cross-shear table's scale (archard_cs, a constant table of 2e-7 on
#    design A's data of k = 3e-7): Table scale 1.5 within 1 % and inside
#    its interval, calibrated.prm = the last run (1e-9).
set -u
exe=$1
mpiexec=$2
here=$(cd "$(dirname "$0")" && pwd)
data=$here/calibration
python=/usr/bin/python3
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work" || exit 1
failures=0
check() { # check NAME COMMAND...: run COMMAND, report ok/FAILED
  name=$1
  shift
  if "$@"; then echo "ok: $name"; else echo "FAILED: $name"; failures=$((failures + 1)); fi
}
truth() { # truth DIR [KEY]: the fit holds the known values (only KEY's)
  "$python" - "$@" <<'PY'
import json, sys
r = json.load(open(sys.argv[1] + "/calibration.json"))
true = {"wear_coefficient": 3e-7, "run_in_factor": 2.5, "run_in_length": 4e5, "table_scale": 1.5}
good = r["verified"]
for key, value in r["fitted"].items():
    if len(sys.argv) > 2 and key != sys.argv[2]:
        print("%s: %.6g in [%.6g, %.6g] (not checked)" % (key, value, r["lower"][key], r["upper"][key]))
        continue
    inside = r["lower"][key] <= true[key] <= r["upper"][key]
    error = abs(value / true[key] - 1)
    print("%s: %.6g in [%.6g, %.6g] (true %.6g, error %.2f %%)%s"
          % (key, value, r["lower"][key], r["upper"][key], true[key], 100 * error,
             "" if inside and error < 0.03 else " <- WRONG"))
    good = good and inside and error < 0.03
print("interval from:", r["interval_from"], "; runs per design:", r["runs_per_design"])
sys.exit(0 if good else 1)
PY
}

# 1. Two designs on 2 ranks.
$mpiexec -np 2 "$exe" "$data/two-designs.prm" > two.log 2>&1
check "two designs: exit 0" test $? -eq 0
check "two designs: k, run-in factor and length recovered" truth two-designs
check "two designs: 2 runs per design, intervals from the 6 specimens" \
  grep -q '"runs_per_design": 2,' two-designs/calibration.json
grep -q "over the 6 specimens" two-designs/calibration.json || { echo "FAILED: not the specimens' interval"; failures=$((failures + 1)); }
check "two designs: calibration.json as doc/output.md says" \
  "$python" "$here/../../python/tkr_results.py" check two-designs/calibration.json

# 2. calibrated.prm runs the first design at the fitted values.
"$exe" two-designs/calibrated.prm > calibrated.log 2>&1
check "calibrated.prm runs" test $? -eq 0
mass_of() { tail -1 "$1" | cut -d, -f4; }
same_mass() { # same_mass A.csv B.csv: the last mass agrees to 1e-9
  "$python" -c "
import sys; a, b = float('$(mass_of "$1")'), float('$(mass_of "$2")')
print('calibrated.prm', a, 'mg; last run', b, 'mg'); sys.exit(abs(a / b - 1) > 1e-9)"
}
check "calibrated.prm = the last calibration run of design A" \
  same_mass two-designs/calibrated/wear_history.csv two-designs/run-2/tkr-a/wear_history.csv

# 3. One specimen: the interval from the residuals.
"$exe" "$data/one-specimen.prm" > one.log 2>&1
check "one specimen: exit 0" test $? -eq 0
check "one specimen: true values within the residuals' interval" truth one-specimen
check "one specimen: interval from the residuals" grep -q "on the residuals" one-specimen/calibration.json

# 4. No weighing during the run-in.
"$exe" "$data/late.prm" > late.log 2>&1
code=$?
cat late.log
check "run-in length without weighings during it: exit 1" test $code -eq 1
check "... one message naming the missing weighings" grep -q "needs weighings during the run-in" late.log
check "... before any run" test ! -e late/run-1

# 5. Illustrative data.
"$exe" "$data/illustrative.prm" > illustrative.log 2>&1
check "illustrative data: exit 0" test $? -eq 0
check "illustrative data: said on the screen" grep -q "ILLUSTRATIVE" illustrative.log
check "illustrative data: in calibration.json" grep -q '"illustrative_data": true' illustrative/calibration.json
check "illustrative data: in calibrated-entries.prm" grep -q "ILLUSTRATIVE" illustrative/calibrated-entries.prm
check "calibration.png drawn" test -s illustrative/calibration.png
grep -A4 "^Calibration of" illustrative.log

# 6. A cross-shear table's scale.
"$exe" "$data/table-scale.prm" > table.log 2>&1
check "table scale: exit 0" test $? -eq 0
check "table scale: 1.5 recovered" truth table-scale table_scale
check "table scale: in calibrated-entries.prm" grep -q "set Table scale = 1.50" table-scale/calibrated-entries.prm
"$exe" table-scale/calibrated.prm > table-calibrated.log 2>&1
check "table scale: calibrated.prm = the last run" \
  same_mass table-scale/calibrated/wear_history.csv table-scale/run-2/tkr-a-cs/wear_history.csv

if [ "$failures" -ne 0 ]; then
  echo "$failures check(s) failed; logs:"
  tail -20 two.log one.log
  exit 1
fi
echo "all calibration checks passed"
