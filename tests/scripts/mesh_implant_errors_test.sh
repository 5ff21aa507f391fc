#!/usr/bin/env bash
# SPDX-License-Identifier: LGPL-2.1-or-later
# scripts/mesh-implant never ends in a Python traceback (issue 19 item 4):
# a missing file, an unknown file type, an unreadable STL, an unreadable
# STEP (a gmsh exception), a bad --rotation and STL surfaces on which the
# tagging finds no contact triangle each end with exit code 1
# and one "error:" line that names the problem. Needs Debian's
# python3-gmsh and python3-numpy.
set -uo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/checks.sh"
echo "solid nothing" > "$work/bad.stl"
echo "not a step file" > "$work/bad.step"
echo "x" > "$work/bad.xyz"
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
exit $failed
