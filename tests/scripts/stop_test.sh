#!/usr/bin/env bash
# SPDX-License-Identifier: LGPL-2.1-or-later
# stop_test.sh TKR_WEAR MPIEXEC
# A cluster's time limit (doc/cluster.md) on tests/scripts/stop/:
# 1. a wear run on 2 ranks sent SIGUSR1 (through mpirun, which forwards
#    it) after block 1: exit code 3, the message, a checkpoint of the last
#    block done although the run writes none itself; --resume on 2 ranks
#    gives the uninterrupted run's wear_history.csv (every printed digit);
# 2. SIGTERM sent to the ranks themselves (as SLURM does) after block 3:
#    the same;
# 3. a study of 8 cases on 4 ranks (4 groups of 1, oversubscribed) run
#    whole, and sent SIGUSR1 while its first cases run: exit code 3, no
#    study.csv, fewer than 8 cases done; --resume on 4 ranks: study.csv
#    equal to the whole study's (mass loss of every case, 1e-9).
set -u
exe=$1
mpiexec=$2
here=$(cd "$(dirname "$0")" && pwd)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work" || exit 1
data=$here/stop
failures=0
check() { # check NAME COMMAND...
  name=$1
  shift
  if "$@"; then echo "ok: $name"; else echo "FAILED: $name"; failures=$((failures + 1)); fi
}
mpi() { "$mpiexec" --oversubscribe "$@"; } # not in the background: $! is mpirun's
wait_for() { # wait_for FILE PATTERN: until FILE holds PATTERN (120 s at most)
  for _ in $(seq 1200); do grep -q "$2" "$1" 2>/dev/null && return 0; sleep 0.1; done
  return 1
}

# The uninterrupted run.
printf 'include %s\nsubsection Output\n  set Directory = whole\nend\n' "$data/run.prm" > whole.prm
mpi -np 2 "$exe" whole.prm > whole.log 2>&1
check "uninterrupted run" test $? -eq 0

stopped_run() { # stopped_run SIGNAL TARGET BLOCK: stop run.prm after BLOCK, resume
  rm -rf run
  "$mpiexec" --oversubscribe -np 2 "$exe" "$data/run.prm" > stop.log 2>&1 &
  local pid=$!
  wait_for run/progress.log "Block    $3/"
  # The ranks are mpirun's children (one node): only this run's ranks.
  if [ "$2" = mpirun ]; then kill -"$1" $pid; else pkill -"$1" -P $pid -x tkr-wear; fi
  wait $pid
  local code=$?
  grep "Stopped by" stop.log
  check "$1 to $2 after block $3: exit code 3" test $code -eq 3
  check "... the message" grep -q "Stopped by SIG$1 during block [0-9]*: the checkpoint" stop.log
  check "... a checkpoint" test -s run/checkpoint.h5
  mpi -np 2 "$exe" --resume "$data/run.prm" > resume.log 2>&1
  check "... resumed: exit 0" test $? -eq 0
  check "... the uninterrupted wear_history.csv" cmp -s run/wear_history.csv whole/wear_history.csv
}
stopped_run USR1 mpirun 1
stopped_run TERM ranks 3

# A study on 4 groups, whole and stopped.
printf 'include %s\nsubsection Output\n  set Directory = study-whole\nend\n' "$data/study.prm" > study-whole.prm
mpi -np 4 "$exe" study-whole.prm > study-whole.log 2>&1
check "study on 4 groups" test $? -eq 0
"$mpiexec" --oversubscribe -np 4 "$exe" "$data/study.prm" > study-stop.log 2>&1 &
pid=$!
wait_for study/case-0000/progress.log "Block    2/"
kill -USR1 $pid
wait $pid
code=$?
grep "Stopped by" study-stop.log
check "study sent SIGUSR1: exit code 3" test $code -eq 3
check "... no study.csv" test ! -e study/study.csv
done_cases=$(ls study/case-*/status.json 2>/dev/null | wc -l)
echo "cases done when stopped: $done_cases of 8"
check "... stopped before the end" test "$done_cases" -lt 8
mpi -np 4 "$exe" --resume "$data/study.prm" > study-resume.log 2>&1
check "study resumed: exit 0" test $? -eq 0
check "... study.csv = the whole study's (mass loss, 1e-9)" /usr/bin/python3 -c "
import csv, sys
a = {r['case']: float(r['mass_loss_mg']) for r in csv.DictReader(open('study/study.csv'))}
b = {r['case']: float(r['mass_loss_mg']) for r in csv.DictReader(open('study-whole/study.csv'))}
print(len(a), 'cases;', 'largest difference', max(abs(a[c] / b[c] - 1) for c in b))
sys.exit(a.keys() != b.keys() or any(abs(a[c] / b[c] - 1) > 1e-9 for c in b))"

if [ "$failures" -ne 0 ]; then
  echo "$failures check(s) failed"
  tail -n 5 whole.log stop.log resume.log study-stop.log study-resume.log
  exit 1
fi
echo "all stop checks passed"
