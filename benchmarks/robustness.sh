#!/usr/bin/env bash
# SPDX-License-Identifier: LGPL-2.1-or-later
# Issue 33 item 4: the robustness set. Inputs made from our own designs to
# look like what users bring, each meshed with the defaults and run through
# one ISO 14243-1 and one ISO 14243-3 cycle from rest (1 rank each, default
# tolerances); with --long, the coarsest mesh also through the whole
# 5e6-cycle test of both protocols. Prints one line per run and exits 1 if
# any input fails to mesh or any step is unconverged.
#
#   rounded-a/b/c  meshes/gen/rounded.py pairs (30-55k irregular triangles,
#                  closed and manifold, 0.005 mm noise): the insert's top,
#                  side and base rims rounded (0.75-1.5 mm), a 3 mm locking
#                  recess under it; C keeps the box and cam of its
#                  posterior-stabilised femur
#   rim3-b         the same with 3 mm rims on the insert and the femur's
#                  sharp edges rounded by 1 mm
#   split-c        rounded-c meshed with --method split (tetrahedra split
#                  into hexahedra: poor contact cells)
#   coarse-a/b/c   the project's coarse meshes (5-10 active nodes at the
#                  168 N swing load)
#   axis-y+2 ...   coarse A with the flexion axis point moved by +-2 mm in
#                  AP (y) and in height (z)
#
#   benchmarks/robustness.sh [--long] [--jobs N] [WORKDIR]
# Needs the Release build in build/release (tkr-wear, tkr-surface). About
# 30 min on 2 cores with --jobs 2 (--long: 5e6 cycles add some 10 min);
# doc/robustness.md has the last results.
set -uo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
long=0 jobs=2
while [ $# -gt 0 ]; do
  case $1 in
    --long) long=1 ;;
    --jobs) jobs=$2; shift ;;
    *) break ;;
  esac
  shift
done
work=${1:-$(mktemp -d)}
mkdir -p "$work" && cd "$work" && work=$PWD || exit 1
wear=$root/build/release/tkr-wear
[ -x "$wear" ] || { echo "no $wear: build Release first" >&2; exit 1; }
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
echo "robustness set in $work"
failed=0

# rounded DESIGN NAME INSERT-OPTIONS FEMUR-OPTIONS MESH-IMPLANT-OPTIONS
rounded() {
  local design=$1 name=$2 insert=$3 femur=$4 mesh=$5 part opts
  for part in femur insert; do
    opts=$insert
    [ $part = femur ] && opts=$femur
    # shellcheck disable=SC2086
    /usr/bin/python3 "$root/meshes/gen/rounded.py" "$root/meshes/tkr/cad/tkr-$design-$part.step" \
      "$name-$part.stl" $opts > "$name-$part.log" 2>&1 ||
      { echo "$name: rounded.py failed on the $part: $(tail -1 "$name-$part.log")"; return 1; }
  done
  # shellcheck disable=SC2086
  "$root/scripts/mesh-implant" --femur "$name-femur.stl" --insert "$name-insert.stl" $mesh \
    -o "$name.msh" > "$name-mesh.log" 2>&1 ||
    { echo "$name: mesh-implant failed: $(tail -1 "$name-mesh.log")"; return 1; }
}

# cycle NAME PROTOCOL INCLUDE [GAIT-ENTRY]: one cycle from rest; prints a line
cycle() {
  local name=$1 proto=$2 include=$3 extra=${4:-} run=$1-$2 ctl=force start code
  [ "$proto" = 3 ] && ctl=displacement
  printf '%s\n' "include $root/prm/one-cycle.prm" "include $include" "subsection Gait" \
    "  set Control = $ctl" "  set Waveform file = $root/data/iso14243-$proto.csv" "$extra" "end" \
    "subsection Wear" "  set Cycles = 1" "  set Cycles per extrapolation step = 1" "end" \
    "subsection Output" "  set Directory = $run" "  set VTU interval = 0" "end" > "$run.prm"
  start=$(date +%s)
  "$wear" "$run.prm" > "$run.log" 2>&1
  code=$?
  report "$run" $code $(($(date +%s) - start))
}

# report RUN EXIT SECONDS: one line from RUN/summary.json and RUN.log
report() {
  local run=$1 code=$2 seconds=$3
  if [ ! -f "$run/summary.json" ]; then
    echo "$run: exit $code, no summary.json: $(tail -1 "$run.log")"
    return 1
  fi
  /usr/bin/python3 - "$root/python" "$run" "$code" "$seconds" << 'EOF'
import re, sys
sys.path.insert(0, sys.argv.pop(1))
import tkr_results
run, code, seconds = sys.argv[1], int(sys.argv[2]), sys.argv[3]
s = tkr_results.read_summary(run + "/summary.json")
active = [int(a) for a in re.findall(r"^ +step +\d+ .*?(\d+) active", open(run + ".log").read(), re.M)]
# a pose Newton step off the Newton direction is a fallback: none is allowed here (issue 33)
ok = code == 0 and s["converged"] and not s["unconverged_steps"] and s.get("pose_fallbacks", 0) == 0
print("%-12s exit %d, %d DoFs, contact cells %.2f/%.2f (tibia/femur), %d/%d steps converged%s, %d solves,"
      " %d pose fallbacks, active %s, %s, %s s%s"
      % (run + ":", code, s["dofs"], s["contact_cell_quality_tibia"], s["contact_cell_quality_femur"],
         s["steps"] - len(s["unconverged_steps"]), s["steps"],
         "" if not s["unconverged_steps"] else " (unconverged: %s)" % s["unconverged_steps"][:10],
         s["contact_solves"], s.get("pose_fallbacks", -1),
         "%d-%d" % (min(active), max(active)) if active else "?",
         "%.4f mg/1e6 cycles" % s["first_cycle_mass_loss_mg_per_million_cycles"] if s["blocks"] == 1
         else "%.4f mg after %g cycles" % (s["mass_loss_mg"], s["cycles"]), seconds, "" if ok else "  FAILED"))
sys.exit(0 if ok else 1)
EOF
}

# meshes (sequential: gmsh and tkr-surface use both cores)
cases=()
fem="--seed 2 --size 1.1"
for d in a b c; do
  rounded $d rounded-$d "--seed 1 --rim 1.5" "$fem" "" && cases+=("rounded-$d rounded-$d.prm")
done
rounded b rim3-b "--seed 3 --rim 3" "$fem --femur-rim 1" "" && cases+=("rim3-b rim3-b.prm")
rounded c split-c "--seed 1 --rim 1.5" "$fem" "--method split" && cases+=("split-c split-c.prm")
[ ${#cases[@]} = 5 ] || failed=1
for d in a b c; do
  printf 'set Problem = wear\nsubsection Mesh\n  set File = %s\nend\n' "$root/meshes/tkr/tkr-$d-coarse.msh" \
    > coarse-$d.prm
  # B's flexion axis (prm/study-designs.csv); C's coarse mesh comes with its own
  [ $d = b ] && printf 'subsection Gait\n  set Flexion axis point = 0, -1, 44.001\nend\n' >> coarse-b.prm
  [ $d = c ] && cp "$root/meshes/tkr/tkr-c-coarse.prm" coarse-c.prm &&
    sed -i "s|meshes/tkr/|$root/meshes/tkr/|" coarse-c.prm
  cases+=("coarse-$d coarse-$d.prm")
done
for shift in y+2:0,0,53.001 y-2:0,-4,53.001 z+2:0,-2,55.001 z-2:0,-2,51.001; do
  cp coarse-a.prm "axis-${shift%%:*}.prm"
  cases+=("axis-${shift%%:*} axis-${shift%%:*}.prm set Flexion axis point = ${shift#*:}")
done

# the cycles, $jobs at a time
running=0
for c in "${cases[@]}"; do
  read -r name include extra <<< "$c"
  for proto in 1 3; do
    cycle "$name" $proto "$PWD/$include" "$extra" > "$name-$proto.line" &
    running=$((running + 1))
    if [ $running -ge "$jobs" ]; then
      wait -n
      running=$((running - 1))
    fi
  done
done
wait
for c in "${cases[@]}"; do
  for proto in 1 3; do
    cat "${c%% *}-$proto.line"
    grep -q FAILED "${c%% *}-$proto.line" && failed=1
  done
done

# the coarsest mesh through the whole test (5e6 cycles, 100 blocks), 2 ranks
if [ $long = 1 ]; then
  for proto in 1 3; do
    printf 'include %s\nsubsection Output\n  set Directory = %s\n  set VTU interval = 0\nend\n' \
      "$root/prm/iso14243-$proto-coarse.prm" "$work/long-$proto" > long-$proto.prm
    start=$(date +%s)
    (cd "$root" && mpirun -np 2 "$wear" "$work/long-$proto.prm") > long-$proto.log 2>&1
    report long-$proto $? $(($(date +%s) - start)) || failed=1
  done
fi
exit $failed
