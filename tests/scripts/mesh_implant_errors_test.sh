#!/usr/bin/env bash
# SPDX-License-Identifier: LGPL-2.1-or-later
# scripts/mesh-implant never ends in a Python traceback (issue 19 item 4):
# a missing file, an unknown file type, an unreadable STL, an unreadable
# STEP (a gmsh exception), a bad --rotation, STL surfaces on which the
# tagging finds no contact triangle and an open sheet (a defect tkr-surface
# cannot repair) each end with exit code 1
# and one "error:" line that names the problem. Needs Debian's
# python3-gmsh and python3-numpy.
set -uo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/checks.sh"
echo "solid nothing" > "$work/bad.stl"
echo "not a step file" > "$work/bad.step"
echo "x" > "$work/bad.xyz"
stl() { # stl NAME "x y z x y z x y z" ...: an ASCII STL of the given triangles
  local name=$1
  shift
  {
    echo "solid $name"
    for t in "$@"; do
      read -r -a v <<< "$t"
      printf 'facet normal 0 0 0\nouter loop\nvertex %s %s %s\nvertex %s %s %s\nvertex %s %s %s\nendloop\nendfacet\n' "${v[@]}"
    done
    echo "endsolid $name"
  } > "$work/$name.stl"
}
stl sheet "0 0 0 60 0 0 60 40 0" "0 0 0 60 40 0 0 40 0"
fails() { # fails FRAGMENT ARGS...: exit 1, FRAGMENT on the last line, no traceback
  local fragment=$1
  shift
  "$root/scripts/mesh-implant" "$@" -o "$work/x.msh" > "$work/out.log" 2>&1
  local code=$?
  tail -1 "$work/out.log"
  [ "$code" -eq 1 ] && tail -1 "$work/out.log" | grep -q -- "$fragment" &&
    ! grep -q "Traceback" "$work/out.log"
}
check "missing file" fails "error: --femur $work/none.stl: no such file" \
  --femur "$work/none.stl" --insert "$cad/tkr-a-insert.stl"
check "unknown file type" fails "unknown file type" --femur "$work/bad.xyz" --insert "$cad/tkr-a-insert.stl"
check "unreadable STL" fails "is not a readable STL file" --femur "$work/bad.stl" --insert "$cad/tkr-a-insert.stl"
check "unreadable STEP (a gmsh exception)" fails "error: gmsh: Could not read file" \
  --femur "$cad/tkr-a-femur.step" --insert "$work/bad.step"
check "bad --rotation" fails "needs nine numbers" --femur "$cad/tkr-a-femur.stl" \
  --insert "$cad/tkr-a-insert.stl" --rotation 1,0,0
check "tagging that finds nothing" fails "error: tagging the surfaces: no triangle of the femur was found for femur_contact" \
  --femur "$cad/tkr-a-femur.stl" --insert "$cad/tkr-a-insert.stl" --contact-distance 0
check "an open sheet that cannot bound a body (a defect tkr-surface cannot repair)" fails \
  "could not be made valid (the surface encloses no volume" --femur "$cad/tkr-a-femur.stl" --insert "$work/sheet.stl"
exit $failed
