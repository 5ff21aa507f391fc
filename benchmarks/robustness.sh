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
#   sharp-a, draft-out-b, draft-in-b, asym-a, overlap-a, decimated-c,
#   real-like      meshes/gen/cadlike.py pairs (issue 50 item 7): what a
#                  real implant's CAD export has: sharp unfilleted femur
#                  edges, insert walls with 15 deg draft both ways,
#                  condyles of distal radii 30 and 36 mm, 0.05 mm of
#                  overlap, decimated exports with long thin facets;
#                  real-like has them all (on C, posterior-stabilised)
#
#   benchmarks/robustness.sh [--long] [--jobs N] [--only NAME,...]
#                            [--protocols 1,3] [--timeout S] [--reuse]
#                            [--report] [WORKDIR]
# --only runs the named inputs only (e.g. --only sharp-a,asym-a; --long's
# runs are named long); --protocols the named ISO 14243 parts only;
# --timeout stops a tkr-wear run after S seconds; --reuse keeps the
# meshes already in WORKDIR (NAME.msh and NAME.prm) instead of making them
# again; --report only prints the lines of the runs found in
# WORKDIR (their exit codes unknown: taken as 0 where summary.json exists).
# Needs the Release build in build/release (tkr-wear, tkr-surface), or
# TKR_BUILD set to another build directory. About 30 min on 2 cores with
# --jobs 2 for the scan-like set (--long: 5e6 cycles add some 10 min); the
# cadlike inputs add 1.5-6 min each to make and mesh and 4-16 min a cycle;
# doc/robustness.md has the last results.
set -uo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
long=0 jobs=2 only='' timeout='' reuse=0 protocols='1 3' report_only=0
while [ $# -gt 0 ]; do
  case $1 in
    --long) long=1 ;;
    --jobs) jobs=$2; shift ;;
    --only) only=,$2,; shift ;;
    --timeout) timeout=$2; shift ;;
    --reuse) reuse=1 ;;
    --protocols) protocols=${2//,/ }; shift ;;
    --report) report_only=1 reuse=1 ;;
    *) break ;;
  esac
  shift
done
work=${1:-$(mktemp -d)}
mkdir -p "$work" && cd "$work" && work=$PWD || exit 1
build=${TKR_BUILD:-$root/build/release}
wear=$build/tkr-wear
[ -x "$wear" ] || { echo "no $wear: build Release first" >&2; exit 1; }
export TKR_SURFACE=${TKR_SURFACE:-$build/tkr-surface}
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
echo "robustness set in $work"
failed=0

# want NAME: whether NAME is to be run (no --only, or named in it)
want() { [ -z "$only" ] || [[ $only == *,$1,* ]]; }

# rounded DESIGN NAME INSERT-OPTIONS FEMUR-OPTIONS MESH-IMPLANT-OPTIONS
rounded() {
  local design=$1 name=$2 insert=$3 femur=$4 mesh=$5 part opts
  [ $reuse = 1 ] && [ -f "$name.msh" ] && [ -f "$name.prm" ] && return 0
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

# cadlike NAME: a meshes/gen/cadlike.py pair meshed by mesh-implant with the
# defaults (NAME.txt: what the pair has; NAME-mesh.log: mesh-implant's report)
cadlike() {
  local name=$1
  [ $reuse = 1 ] && [ -f "$name.msh" ] && [ -f "$name.prm" ] && return 0
  /usr/bin/python3 "$root/meshes/gen/cadlike.py" "$name" -o . > "$name-gen.log" 2>&1 ||
    { echo "$name: cadlike.py failed: $(tail -1 "$name-gen.log")"; return 1; }
  "$root/scripts/mesh-implant" --femur "$name-femur.stl" --insert "$name-insert.stl" -o "$name.msh" \
    > "$name-mesh.log" 2>&1 ||
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
  ${timeout:+timeout "$timeout"} "$wear" "$run.prm" > "$run.log" 2>&1
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
  want rounded-$d || continue
  rounded $d rounded-$d "--seed 1 --rim 1.5" "$fem" "" && cases+=("rounded-$d rounded-$d.prm") || failed=1
done
if want rim3-b; then
  rounded b rim3-b "--seed 3 --rim 3" "$fem --femur-rim 1" "" && cases+=("rim3-b rim3-b.prm") || failed=1
fi
if want split-c; then
  rounded c split-c "--seed 1 --rim 1.5" "$fem" "--method split" && cases+=("split-c split-c.prm") || failed=1
fi
for name in sharp-a draft-out-b draft-in-b asym-a overlap-a decimated-c real-like; do
  want $name || continue
  cadlike $name && cases+=("$name $name.prm") || failed=1
done
for d in a b c; do
  printf 'set Problem = wear\nsubsection Mesh\n  set File = %s\nend\n' "$root/meshes/tkr/tkr-$d-coarse.msh" \
    > coarse-$d.prm
  # B's flexion axis (prm/study-designs.csv); C's coarse mesh comes with its own
  [ $d = b ] && printf 'subsection Gait\n  set Flexion axis point = 0, -1, 44.001\nend\n' >> coarse-b.prm
  [ $d = c ] && cp "$root/meshes/tkr/tkr-c-coarse.prm" coarse-c.prm &&
    sed -i "s|meshes/tkr/|$root/meshes/tkr/|" coarse-c.prm
  want coarse-$d && cases+=("coarse-$d coarse-$d.prm")
done
for shift in y+2:0,0,53.001 y-2:0,-4,53.001 z+2:0,-2,55.001 z-2:0,-2,51.001; do
  want "axis-${shift%%:*}" || continue
  cp coarse-a.prm "axis-${shift%%:*}.prm"
  cases+=("axis-${shift%%:*} axis-${shift%%:*}.prm set Flexion axis point = ${shift#*:}")
done

# the cycles, $jobs at a time
running=0
for c in "${cases[@]}"; do
  [ $report_only = 1 ] && break
  read -r name include extra <<< "$c"
  for proto in $protocols; do
    cycle "$name" "$proto" "$PWD/$include" "$extra" > "$name-$proto.line" &
    running=$((running + 1))
    if [ $running -ge "$jobs" ]; then
      wait -n
      running=$((running - 1))
    fi
  done
done
wait
for c in "${cases[@]}"; do
  for proto in $protocols; do
    [ $report_only = 1 ] && { report "${c%% *}-$proto" 0 "?" > "${c%% *}-$proto.line"; }
    cat "${c%% *}-$proto.line"
    grep -q FAILED "${c%% *}-$proto.line" && failed=1
  done
done

# the coarsest mesh through the whole test (5e6 cycles, 100 blocks), 2 ranks
if [ $long = 1 ] && want long; then
  for proto in 1 3; do
    printf 'include %s\nsubsection Output\n  set Directory = %s\n  set VTU interval = 0\nend\n' \
      "$root/prm/iso14243-$proto-coarse.prm" "$work/long-$proto" > long-$proto.prm
    start=$(date +%s)
    (cd "$root" && mpirun -np 2 "$wear" "$work/long-$proto.prm") > long-$proto.log 2>&1
    report long-$proto $? $(($(date +%s) - start)) || failed=1
  done
fi
exit $failed
