#!/usr/bin/env bash
# SPDX-License-Identifier: LGPL-2.1-or-later
# Issue 19 item 5: scan-like STL inputs of TKR A, B and C (meshes/gen/scanlike.py:
# subdivided, 0.01 mm noise, 3 folded vertices, a duplicated and a missing
# triangle, reversed orientation), one set in metres and one in another frame,
# through scripts/mesh-implant, a static contact under 2000 N and (with
# --cycle) one ISO 14243-1 gait cycle on 1 rank. Prints one line per input.
# A and B start from their STL exports (1.5 mm triangles), C from its STEP
# file triangulated the same way (its STL export is chordal, up to 12 mm
# triangles 0.44 mm off the CAD faces); the last row is that chordal export
# as it is, with no scan defects; the "rounded" rows are the pairs of
# meshes/gen/rounded.py (issue 33 item 3: the insert's rims rounded, a 3 mm
# locking recess in its base, 30-55k irregular triangles, closed and manifold).
#   benchmarks/scan-inputs.sh [--cycle] [WORKDIR]   (Release build in build/release)
set -uo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
cycle=0
[ "${1:-}" = "--cycle" ] && { cycle=1; shift; }
work=${1:-$(mktemp -d)}
mkdir -p "$work" && cd "$work" || exit 1
wear=$root/build/release/tkr-wear
rot=0,1,0,0,0,1,1,0,0
# name design options-for-scanlike options-for-mesh-implant
cases=("a-mm a.stl --seed 3|" "b-mm b.stl --seed 3|" "c-mm c.step --seed 3|"
       "a-m a.stl --seed 4 --units m|--units m" "b-frame b.stl --seed 5 --rotation $rot|--rotation $rot"
       "c-chordal c.stl as-is|" "a-rounded a.step rounded|" "b-rounded b.step rounded|" "c-rounded c.step rounded|")
for c in "${cases[@]}"; do
  make=${c%%|*} mesh=${c#*|}
  read -r name design opts <<< "$make"
  for part in femur insert; do
    src=$root/meshes/tkr/cad/tkr-${design%.*}-$part.${design#*.}
    if [ "$opts" = as-is ]; then
      cp "$src" "$name-$part.stl"
    elif [ "$opts" = rounded ]; then
      # shellcheck disable=SC2046
      /usr/bin/python3 "$root/meshes/gen/rounded.py" "$src" "$name-$part.stl" \
        $([ $part = femur ] && echo "--seed 2 --size 1.1" || echo "--seed 1 --rim 1.5") > /dev/null 2>&1
    else
      # shellcheck disable=SC2086
      /usr/bin/python3 "$root/meshes/gen/scanlike.py" "$src" "$name-$part.stl" --duplicates 1 --holes 1 \
        --flip $opts > /dev/null
    fi
  done
  # shellcheck disable=SC2086
  if ! "$root/scripts/mesh-implant" --femur "$name-femur.stl" --insert "$name-insert.stl" $mesh \
      -o "$name.msh" > "$name-mesh.log" 2>&1; then
    echo "$name: mesh-implant failed: $(tail -1 "$name-mesh.log")"
    continue
  fi
  printf 'include %s\nsubsection Mesh\n  set File = %s\nend\nsubsection Output\n  set Directory = %s\nend\n' \
    "$root/prm/static-2000n.prm" "$name.msh" "$name-static" > "$name-static.prm"
  "$wear" "$name-static.prm" > "$name-static.log" 2>&1
  line="$name: $(grep -o 'wrote [^ ]* ([0-9]* Q1' "$name-mesh.log" | grep -o '[0-9]* Q1') DoFs;"
  line+=" layer $(grep 'contact layer' "$name-mesh.log" | grep -o '[0-9.]*$' | paste -sd/);"
  line+=" 2000 N: area $(sed -n 's/ *contact area: *//p' "$name-static.log"),"
  line+=" peak $(sed -n 's/ *max pressure: *//p' "$name-static.log")"
  if [ $cycle = 1 ]; then
    printf 'include %s\ninclude %s\nsubsection Output\n  set Directory = %s\n  set VTU interval = 0\nend\n' \
      "$root/prm/one-cycle.prm" "$name.prm" "$name-cycle" > "$name-cycle.prm"
    "$wear" "$name-cycle.prm" > "$name-cycle.log" 2>&1; code=$?
    get() { /usr/bin/python3 "$root/python/tkr_results.py" get "$name-cycle/summary.json" "$1"; }
    line+="; one cycle: exit $code, \"unconverged_steps\": $(get unconverged_steps), \"first_cycle_mass_loss_mg_per_million_cycles\": $(get first_cycle_mass_loss_mg_per_million_cycles)"
  fi
  echo "$line"
done
