#!/usr/bin/env bash
# SPDX-License-Identifier: LGPL-2.1-or-later
# restart_test.sh TKR_WEAR MPIEXEC PRM REFERENCE_PREFIX
# Restart equals the uninterrupted run: run PRM (a wear run with a
# checkpoint after every block, output directory 'results') in the current
# directory, kill it with SIGKILL as soon as the checkpoint after block 2
# is written, resume it with `tkr-wear --resume` on 2 ranks and compare
# wear_history.csv and steps.csv with the uninterrupted run's references
# (REFERENCE_PREFIX.<file>). Then a resume with another Wear coefficient
# must be refused with a message that names the entry.
set -u
exe=$1
mpiexec=$2
prm=$3
reference=$4
here=$(cd "$(dirname "$0")" && pwd)
rm -rf results interrupted.log resumed.log
"$exe" "$prm" > interrupted.log 2>&1 &
pid=$!
for _ in $(seq 1 3000); do
  if grep -q "checkpoint written after block 2" interrupted.log; then
    kill -9 "$pid"
    break
  fi
  if ! kill -0 "$pid" 2>/dev/null; then
    break
  fi
  sleep 0.1
done
wait "$pid" 2>/dev/null
status=$?
if [ "$status" -ne 137 ]; then
  echo "restart_test: the run was not killed after block 2 (exit status $status):"
  tail -5 interrupted.log
  exit 1
fi
echo "restart_test: killed (SIGKILL) after the checkpoint of block 2"
if ! "$mpiexec" -np 2 "$exe" --resume "$prm" > resumed.log 2>&1; then
  echo "restart_test: the resumed run failed:"
  tail -20 resumed.log
  exit 1
fi
grep "Resumed from" resumed.log || { echo "restart_test: not resumed"; exit 1; }
# The checkpoint holds the steps' poses of blocks 1 and 2: block 3 starts
# from their extrapolation, as in the uninterrupted run.
grep -q "warm starts extrapolated from the poses of the last two blocks" resumed.log ||
  { echo "restart_test: the resumed run lost the previous poses"; exit 1; }
"$here/compare-files.sh" results "$reference" wear_history.csv steps.csv

# A checkpoint locked by another process (as HDF5 locks a file it has
# open for writing): every rank stops with one message, none waits.
timeout 120 flock -x results/checkpoint.h5 \
  "$mpiexec" -np 2 "$exe" --resume "$prm" > locked.log 2>&1
grep -q "Cannot open the checkpoint <results/checkpoint.h5> with HDF5 (not an HDF5 file, not writable, or locked by another process)" locked.log ||
  { echo "restart_test: locked checkpoint, unexpected message:"; cat locked.log; exit 1; }
echo "restart_test: locked checkpoint refused:"
grep "tkr-wear: error" locked.log

# The checkpoint records the parameters that determine the wear state: a
# resume with another wear coefficient must be refused, naming the entry.
cp "$prm" changed.prm
printf 'subsection Wear\n  subsection Archard\n    set Wear coefficient = 3e-7\n  end\nend\n' >> changed.prm
if "$exe" --resume changed.prm > refused.log 2>&1; then
  echo "restart_test: --resume with another Wear coefficient was not refused"
  exit 1
fi
grep -q "was written with Wear/Archard/Wear coefficient = 2e-7, but the parameter file sets 3e-7" refused.log ||
  { echo "restart_test: unexpected message:"; cat refused.log; exit 1; }
echo "restart_test: --resume with another Wear coefficient refused:"
cat refused.log
