#!/usr/bin/env bash
# SPDX-License-Identifier: LGPL-2.1-or-later
# resume_converged_test.sh TKR_WEAR PRM CHECKPOINT
# Copy CHECKPOINT into PRM's output directory 'results' (in the current
# directory), resume the run with `tkr-wear --resume` and require exit code
# 0, the resume line, no "NOT CONVERGED" step and an empty list of
# unconverged steps in summary.json.
set -u
exe=$1
prm=$2
checkpoint=$3
results=$(cd "$(dirname "$0")/../.." && pwd)/python/tkr_results.py
rm -rf results
mkdir -p results
cp "$checkpoint" results/checkpoint.h5
"$exe" --resume "$prm" > resumed.log 2>&1
code=$?
grep -E "Resumed from|^Block|steps:" resumed.log
if [ "$code" -ne 0 ]; then
  echo "FAIL: the resumed run exited with $code:"
  tail -5 resumed.log
  exit 1
fi
if grep -q "NOT CONVERGED" resumed.log; then
  echo "FAIL: steps did not converge:"
  grep "NOT CONVERGED" resumed.log
  exit 1
fi
unconverged=$(python3 "$results" get results/summary.json unconverged_steps) || exit 1
[ "$unconverged" = "[]" ] ||
  { echo "FAIL: summary.json lists unconverged steps"; exit 1; }
echo "ok: every step of the resumed blocks converged"
