#!/usr/bin/env bash
# SPDX-License-Identifier: LGPL-2.1-or-later
# scripts/mesh-implant on the STEP files of TKR A (default options) estimates
# the flexion axis within 0.5 mm of the generator's (0, -2, 53) and writes a
# parameter file next to the mesh that holds it; the estimator also finds
# the axis of the block-structured coarse mesh. Exit code 0 only when every
# check passed. Needs Debian's python3-gmsh and python3-numpy.
set -uo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/checks.sh"
check "mesh-implant on the STEP files" \
  "$root/scripts/mesh-implant" --femur "$cad/tkr-a-femur.step" \
  --insert "$cad/tkr-a-insert.step" -o "$work/knee.msh"
check "the estimate on its output within 0.5 mm of (y, z) = (-2, 53)" \
  "$py" "$root/meshes/gen/flexion_axis.py" "$work/knee.msh" --expect=-2,53
axis_in_prm() { # the Flexion axis point of knee.prm within 0.5 mm of (0, -2, 53)
  awk -F'[=,]' '/^  set Flexion axis point =/ { found = 1
      d = sqrt(($3 + 2) ^ 2 + ($4 - 53) ^ 2); if ($2 + 0 != 0 || d > 0.5) bad = 1 }
    END { exit !(found && !bad) }' "$work/knee.prm"
}
check "knee.prm written next to the mesh with the axis" axis_in_prm
check "knee.prm names the mesh" grep -q "set File = $work/knee.msh" "$work/knee.prm"
check "the estimate on tkr-a-coarse.msh within 0.5 mm of (-2, 53.001)" \
  "$py" "$root/meshes/gen/flexion_axis.py" "$root/meshes/tkr/tkr-a-coarse.msh" --expect=-2,53.001
exit $failed
