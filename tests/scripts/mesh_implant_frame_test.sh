#!/usr/bin/env bash
# SPDX-License-Identifier: LGPL-2.1-or-later
# scripts/mesh-implant and the frame of the input (issue 19 item 3): TKR A's
# STL files written in another frame (x_file = our y, y_file = our z,
# z_file = our x) are refused with a message that says why and names
# --rotation; with --rotation 0,0,1,1,0,0,0,1,0 (the rows: our axes in the
# file's frame) they are meshed, the mesh passes check_msh.py and the
# flexion axis estimate is within 0.5 mm of the generator's (-2, 53); a
# matrix that is not a rotation, a femur below the insert, and bodies side
# by side are refused. Needs Debian's python3-gmsh and python3-numpy.
set -uo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/checks.sh"
"$py" - "$root/meshes/gen" "$cad" "$work" <<'PY'
import sys
import numpy as np
sys.path.insert(0, sys.argv[1])
import mesh_implant as mi
cad, work = sys.argv[2], sys.argv[3]
r0 = np.array([[0, 0, 1], [1, 0, 0], [0, 1, 0]], float)  # x_ours = r0 x_file
for b in ("femur", "insert"):
    t = mi.read_stl("%s/tkr-a-%s.stl" % (cad, b))
    mi.write_stl_binary("%s/%s-turned.stl" % (work, b), t @ r0)     # x_file = r0^T x_ours
    mi.write_stl_binary("%s/%s-flipped.stl" % (work, b), t * [1, 1, -1])  # femur below
    mi.write_stl_binary("%s/%s-beside.stl" % (work, b), t + ([100, 0, 0] if b == "femur" else 0))
PY
refused() { # refused FRAGMENT ARGS...: mesh-implant must exit 1 printing FRAGMENT
  local fragment=$1
  shift
  ! "$root/scripts/mesh-implant" "$@" -o "$work/x.msh" > "$work/refused.log" 2>&1 &&
    grep -q -- "$fragment" "$work/refused.log" && cat "$work/refused.log" | tail -1
}
check "turned input refused, naming --rotation" refused "not thinnest along z" \
  --femur "$work/femur-turned.stl" --insert "$work/insert-turned.stl"
check "femur below the insert refused" refused "is not above the insert" \
  --femur "$work/femur-flipped.stl" --insert "$work/insert-flipped.stl"
check "bodies side by side refused" refused "do not face each other" \
  --femur "$work/femur-beside.stl" --insert "$work/insert-beside.stl"
check "a matrix that is not a rotation refused" refused "is not a rotation" \
  --femur "$work/femur-turned.stl" --insert "$work/insert-turned.stl" --rotation 0,0,1,1,0,0,0,1,1
check "turned input meshed with --rotation" "$root/scripts/mesh-implant" \
  --femur "$work/femur-turned.stl" --insert "$work/insert-turned.stl" \
  --rotation 0,0,1,1,0,0,0,1,0 -o "$work/knee.msh"
check "check_msh.py accepts the mesh" "$py" "$root/meshes/gen/check_msh.py" --quiet "$work/knee.msh"
check "the flexion axis estimate within 0.5 mm of (y, z) = (-2, 53)" \
  "$py" "$root/meshes/gen/flexion_axis.py" "$work/knee.msh" --expect=-2,53
exit $failed
