#!/usr/bin/env bash
# SPDX-License-Identifier: LGPL-2.1-or-later
# activity_mix_test.sh TKR_WEAR MPIEXEC
# Activity mixes (Gait/Activities, doc/gait.md) on tests/scripts/activity_mix/
# (coarse TKR A, 4-step gait, 4 blocks), 2 ranks:
# 1. a mix of one activity with share 1 is the run without a mix: the
#    columns of wear_history.csv they share and summary.json's mass, digit
#    for digit;
# 2. a mix of the main gait (0.3) and an activity file that sets the same
#    gait (0.7) wears as the main gait alone (1e-9), and each activity's
#    mass is its share of it;
# 3. walking 0.8 + stair ascent 0.2 (the shipped example waveform):
#    converged; the activities' masses add up to the run's, each
#    activity's sides to its volume, the activities' wear maps to the
#    run's (1e-9); the stair ascent wears more per cycle than walking
#    (a larger peak force); the mix's mass lies between the single
#    activities' runs;
# 4. the mix stopped after 2 blocks and resumed (--resume) gives the whole
#    mix's wear_history.csv; a resume with other shares is refused;
# 5. refusals: shares that do not add up to 1, a missing waveform, an
#    activity file that sets a Wear entry, a malformed list, a repeated
#    name.
set -u
exe=$1
mpiexec=$2
here=$(cd "$(dirname "$0")" && pwd)
data=$here/activity_mix
work=$(mktemp -d)
trap '[ -n "${KEEP:-}" ] || rm -rf "$work"' EXIT
cd "$work" || exit 1
failures=0
check() { # check NAME COMMAND...
  name=$1
  shift
  if "$@"; then echo "ok: $name"; else echo "FAILED: $name"; failures=$((failures + 1)); fi
}
case_prm() { # case_prm NAME ACTIVITIES [EXTRA]: NAME.prm, output in NAME/
  printf 'include %s\nsubsection Gait\n  set Activities = %s\nend\nsubsection Output\n  set Directory = %s\nend\n%s\n' \
    "$data/base.prm" "$2" "$1" "${3:-}" > "$1.prm"
}
run() { # run NAME: 2 ranks, log in NAME.log, returns the exit code
  "$mpiexec" --oversubscribe -np 2 "$exe" "$1.prm" > "$1.log" 2>&1
}
value() { # value FILE KEY: a number of summary.json
  python3 -c "import json,sys; print(json.load(open(sys.argv[1]))[sys.argv[2]])" "$1" "$2"
}
close() { # close A B TOL: |A - B| <= TOL max(|A|, |B|)
  python3 -c "import sys; a, b, t = map(float, sys.argv[1:]); sys.exit(abs(a - b) > t * max(abs(a), abs(b)))" "$1" "$2" "$3"
}

# 1. One activity with share 1 = no mix.
case_prm single ""
case_prm one "walking: 1"
run single
check "run without a mix" test $? -eq 0
run one
check "mix of one activity, share 1" test $? -eq 0
cut -d, -f1-16 single/wear_history.csv > single.csv
cut -d, -f1-16 one/wear_history.csv > one.csv
check "... wear_history.csv = the run without a mix (16 columns, every digit)" cmp -s single.csv one.csv
check "... its activity columns" grep -q "walking_volume_mm3,walking_mass_mg,walking_max_depth_mm" one/wear_history.csv
check "... summary mass_loss_mg" test "$(value single/summary.json mass_loss_mg)" = "$(value one/summary.json mass_loss_mg)"
check "... activity_walking_mass_loss_mg = mass_loss_mg" test "$(value one/summary.json activity_walking_mass_loss_mg)" = "$(value one/summary.json mass_loss_mg)"

# 2. The same gait twice, 0.3 and 0.7.
case_prm twice "walking: 0.3; walking again: 0.7: $data/same-gait.prm"
run twice
check "the same gait twice (0.3 + 0.7)" test $? -eq 0
m=$(value single/summary.json mass_loss_mg)
check "... mass = the single run's (1e-9)" close "$(value twice/summary.json mass_loss_mg)" "$m" 1e-9
check "... walking's mass = 0.3 of it (1e-9)" close "$(value twice/summary.json activity_walking_mass_loss_mg)" "$(python3 -c "print(0.3 * $m)")" 1e-9
check "... walking again's = 0.7 of it (1e-9)" close "$(value twice/summary.json activity_walking_again_mass_loss_mg)" "$(python3 -c "print(0.7 * $m)")" 1e-9

# 3. Walking and stair ascent.
case_prm stair-alone "stair ascent: 1: $data/stair.prm"
case_prm mix "walking: 0.8; stair ascent: 0.2: $data/stair.prm"
run stair-alone
check "stair ascent alone" test $? -eq 0
run mix
check "walking 0.8 + stair ascent 0.2: converged" test $? -eq 0
grep "activity .*(share" mix.log
python3 - "$work" <<'PY'
import csv, json, sys
work = sys.argv[1]
s = json.load(open(f"{work}/mix/summary.json"))
walk, stair = "activity_walking_", "activity_stair_ascent_"
errors = []
def close(a, b, tol=1e-9):
    return abs(a - b) <= tol * max(abs(a), abs(b), 1e-300)
if not close(s[walk + "mass_loss_mg"] + s[stair + "mass_loss_mg"], s["mass_loss_mg"]):
    errors.append("activities' masses do not add up to the run's")
for a in (walk, stair):
    if not close(s[a + "medial_mass_loss_mg"] + s[a + "lateral_mass_loss_mg"], s[a + "mass_loss_mg"]):
        errors.append(a + " sides do not add up")
rows = {}
for name in ("wear_map", "wear_map_walking", "wear_map_stair_ascent"):
    rows[name] = [float(r["depth_mm"]) for r in csv.DictReader(open(f"{work}/mix/{name}.csv"))]
for j, d in enumerate(rows["wear_map"]):
    if not abs(rows["wear_map_walking"][j] + rows["wear_map_stair_ascent"][j] - d) <= 1e-9 * max(rows["wear_map"]):
        errors.append(f"wear maps do not add up at node {j}")
        break
one = json.load(open(f"{work}/one/summary.json"))["mass_loss_mg"]
alone = json.load(open(f"{work}/stair-alone/summary.json"))["mass_loss_mg"]
mix = s["mass_loss_mg"]
print(f"mass: walking alone {one:.6g}, stair ascent alone {alone:.6g}, mix {mix:.6g} "
      f"(walking {s[walk + 'mass_loss_mg']:.6g}, stair {s[stair + 'mass_loss_mg']:.6g})")
if not alone > one:
    errors.append("stair ascent alone does not wear more than walking")
if not min(one, alone) < mix < max(one, alone):
    errors.append("the mix's mass is not between the single activities'")
for e in errors:
    print("error:", e)
sys.exit(1 if errors else 0)
PY
check "... masses, sides and maps add up; mix between the single activities" test $? -eq 0
check "... steps_walking.csv and steps_stair_ascent.csv" test -s mix/steps_walking.csv -a -s mix/steps_stair_ascent.csv

# 4. Stopped after 2 blocks, resumed.
case_prm half "walking: 0.8; stair ascent: 0.2: $data/stair.prm" "subsection Wear
  set Cycles = 5e5
end"
sed -i 's/Directory = half/Directory = resumed/' half.prm
case_prm resumed "walking: 0.8; stair ascent: 0.2: $data/stair.prm"
run half
check "the mix for 2 blocks" test $? -eq 0
"$mpiexec" --oversubscribe -np 2 "$exe" --resume resumed.prm > resume.log 2>&1
check "... resumed to 4 blocks: exit 0" test $? -eq 0
check "... the whole mix's wear_history.csv" cmp -s resumed/wear_history.csv mix/wear_history.csv
case_prm other-shares "walking: 0.7; stair ascent: 0.3: $data/stair.prm"
sed -i 's/Directory = other-shares/Directory = resumed/' other-shares.prm
"$mpiexec" --oversubscribe -np 2 "$exe" --resume other-shares.prm > other.log 2>&1
check "... a resume with other shares is refused" test $? -ne 0
check "... naming the share" grep -q "Gait/Activities/stair_ascent/Share = 0.2, but the parameter file sets 0.3" other.log

# 5. Refusals (before any solve).
refused() { # refused NAME ACTIVITIES PATTERN
  case_prm "$1" "$2"
  run "$1"
  local code=$?
  check "refused: $1 (exit 1)" test $code -eq 1
  check "... says: $3" grep -q "$3" "$1.log"
}
refused shares "walking: 0.8; stair ascent: 0.1: $data/stair.prm" "the shares 0.8 + 0.1 add up to 0.9, not 1"
refused waveform "walking: 0.8; stair ascent: 0.2: $data/no-waveform.prm" "the waveform file <.*no-such-waveform.csv> of the activity <stair ascent> does not exist"
refused foreign "walking: 0.8; stair ascent: 0.2: $data/foreign.prm" "sets Wear/Cycles"
refused malformed "walking 1" "is not NAME: SHARE"
refused repeated "walking: 0.5; Walking: 0.5" "two activities are named"

if [ $failures -gt 0 ]; then
  echo "$failures check(s) FAILED"
  exit 1
fi
echo "all activity-mix checks passed"
