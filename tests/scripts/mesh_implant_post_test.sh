#!/usr/bin/env bash
# SPDX-License-Identifier: LGPL-2.1-or-later
# scripts/mesh-implant on the STEP files of TKR C (posterior-stabilised,
# meshes/gen/tkr_ps.py) with default options: the insert with its tibial post
# is swept into columns (not the contact-layer fallback), the mesh passes
# check_msh.py, and the insert's articular hexahedra have a scaled corner
# Jacobian of at least 0.3. Exit code 0 only when every check passed. Needs
# Debian's python3-gmsh and python3-numpy.
set -uo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/checks.sh"
check "mesh-implant on the TKR C STEP files" \
  "$root/scripts/mesh-implant" --femur "$cad/tkr-c-femur.step" \
  --insert "$cad/tkr-c-insert.step" -o "$work/knee.msh"
check "the insert is swept" grep -q "^tibia (swept columns)" "$work/knee-report.txt"
layer_quality() { # the tibia_contact layer's min scaled corner Jacobian >= 0.3
  awk '/^contact layer tibia_contact:/ { found = 1; if ($NF + 0 < 0.3) bad = 1 }
    END { exit !(found && !bad) }' "$work/knee-report.txt"
}
check "tibia_contact hexahedra with scaled Jacobian >= 0.3" layer_quality
check "check_msh.py accepts the mesh" "$py" "$root/meshes/gen/check_msh.py" --quiet "$work/knee.msh"
exit $failed
