#!/usr/bin/env bash
# SPDX-License-Identifier: LGPL-2.1-or-later
# scripts/mesh-implant's femur as its articular shell and its limits
# (issue 50 items 1 and 3), on the STEP files of TKR C (posterior-stabilised:
# its 3 mm cam folds the whole component's contact layer):
# - with the defaults the femur is the articular shell (femur_contact
#   outside, femur_fixation inside, nothing else tagged), its contact cells
#   have a scaled corner Jacobian of at least 0.15, the mesh has at most
#   200,000 DoFs, passes check_msh.py and the femur sits 0.001 mm above
#   the insert on the meshes;
# - the whole component (--femur-mesh layer, contact cells 0.061 at the
#   cam) with --max-dofs 50000 is refused: exit 1, one "error:" line naming
#   both causes (the DoFs of each body, the worst cell and where it is) and
#   the options that help, no .msh or .prm written, no traceback.
# Needs Debian's python3-gmsh and python3-numpy.
set -uo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/checks.sh"
check "mesh-implant on the TKR C STEP files with the defaults" \
  "$root/scripts/mesh-implant" --femur "$cad/tkr-c-femur.step" \
  --insert "$cad/tkr-c-insert.step" -o "$work/knee.msh"
report=$work/knee-report.txt
check "the femur is the articular shell" grep -q "^femur (articular shell" "$report"
quality() { # quality GROUP MIN: the report's contact cells of GROUP have a scaled Jacobian >= MIN
  awk -v g="$1" -v min="$2" '$1 == "contact" && $3 == g":" { found = 1; if ($NF + 0 < min) bad = 1 }
    END { exit !(found && !bad) }' "$report"
}
check "femur_contact cells with scaled Jacobian >= 0.15" quality femur_contact 0.15
check "tibia_contact cells with scaled Jacobian >= 0.1" quality tibia_contact 0.1
dofs_at_most() { # the DoFs the report names are at most $1
  local n
  n=$(sed -n 's/^wrote .* (\([0-9]*\) Q1 displacement DoFs)$/\1/p' "$report")
  echo "DoFs: $n"
  [ -n "$n" ] && [ "$n" -le "$1" ]
}
check "at most 200,000 DoFs" dofs_at_most 200000
check "femur_contact and femur_fixation quadrangles, as many" \
  grep -qE "^femur \(articular shell.*quads \{'femur_contact': ([0-9]+), 'femur_fixation': \1\}" "$report"
check "the femur placed on the meshes 0.001 mm above the insert" \
  grep -q "^smallest vertical gap between the articular surfaces: 0.0010 mm" "$report"
check "check_msh.py accepts the mesh" "$py" "$root/meshes/gen/check_msh.py" --quiet "$work/knee.msh"
refused() {
  "$root/scripts/mesh-implant" --femur "$cad/tkr-c-femur.step" --insert "$cad/tkr-c-insert.step" \
    --femur-mesh layer --max-dofs 50000 -o "$work/whole.msh" > "$work/whole.log" 2>&1
  local code=$?
  tail -1 "$work/whole.log"
  [ "$code" -eq 1 ] && [ "$(grep -c "^error:" "$work/whole.log")" -eq 1 ] &&
    tail -1 "$work/whole.log" | grep -q "^error: no mesh written: the mesh has [0-9]* Q1 DoFs (femur [0-9]*, insert [0-9]*), more than --max-dofs 50000: try .*--femur-mesh shell" &&
    tail -1 "$work/whole.log" | grep -q "the femur's contact cells (contact layer, [0-9]* on femur_contact) reach a scaled corner Jacobian of 0.0[0-9]* at (.*), below --min-contact-quality 0.1: try --femur-mesh shell" &&
    ! grep -q "Traceback" "$work/whole.log" && [ ! -e "$work/whole.msh" ] && [ ! -e "$work/whole.prm" ]
}
check "the whole femur with --max-dofs 50000 refused, both causes named, nothing written" refused
exit $failed
