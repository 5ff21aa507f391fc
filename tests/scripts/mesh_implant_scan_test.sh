#!/usr/bin/env bash
# SPDX-License-Identifier: LGPL-2.1-or-later
# scripts/mesh-implant on scan-like STL surfaces (issue 19): TKR B's STL
# exports made scan-like (meshes/gen/scanlike.py: subdivided, 0.01 mm
# noise, 3 folded vertices each, a duplicated and a missing triangle, the
# orientation reversed), written in metres and in another frame (file axes
# = our y, z, x). mesh-implant reads them with --units m and --rotation,
# reports and repairs the defects (tkr-surface), tags the groups from the
# pair's geometry and meshes; a static contact under 2000 N (the
# doc/geometry.md settings) then gives the peak pressure within 20 % of
# the block-structured tkr-b-medium.msh's (45.19 MPa, 85.67 mm^2 with the
# same parameters, measured 2026-12-02) and the contact area within 20 %.
# Arguments: tkr-surface and tkr-wear executables.
set -uo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/checks.sh"
export TKR_SURFACE=$1
wear=$2
rot=0,1,0,0,0,1,1,0,0
for part in femur insert; do
  $py "$root/meshes/gen/scanlike.py" "$cad/tkr-b-$part.stl" "$work/$part.stl" --seed 5 --duplicates 1 \
    --holes 1 --flip --units m --rotation $rot > /dev/null
done
cd "$work"
"$root/scripts/mesh-implant" --femur femur.stl --insert insert.stl --units m --rotation $rot -o knee.msh \
  > mesh.log 2>&1
echo "exit $?" >> mesh.log
grep -v "^  " mesh.log
has() { grep -q -- "$1" mesh.log; }
check "meshed" has "exit 0"
check "self-intersections reported" grep -qE "^surface femur: defect: [1-9][0-9]* pairs of intersecting" mesh.log
check "duplicates reported" has "surface tibia: defect: 1 duplicate triangles"
check "groups found on whole patches" bash -c "grep -qE '^femur: .*femur_contact 1 patches' mesh.log && grep -qE '^tibia: .*tibia_contact 1 patches' mesh.log"
check "insert swept" has "tibia (swept columns)"
static_2000n "$wear" knee.msh 45.19 85.67 "the structured mesh's"
exit $failed
