#!/usr/bin/env bash
# SPDX-License-Identifier: LGPL-2.1-or-later
# scripts/mesh-implant on a scan-like posterior-stabilised implant (issue
# 19): TKR C's STEP files triangulated like the STL exports of A and B and
# made scan-like (meshes/gen/scanlike.py, seed 3: 0.01 mm noise, 3 folded
# vertices each, one of them on the insert's base rim, a duplicated and a
# missing triangle, reversed). The femur's 4 mm remesh loses the cam (3 mm
# radius, 1.5 mm under the posterior condyles) and is redone with 3 mm
# triangles; the insert is swept with its post (a sliver under 1 mm^2 that
# the remeshing leaves at the post's foot counts as wall). A static contact
# under 2000 N (the doc/geometry.md settings) then gives the peak pressure and the
# contact area within 20 % of those of meshes/tkr/tkr-c-implant-auto.msh,
# the STEP files' mesh (33.21 MPa, 107.57 mm^2 with the same parameters,
# measured 2026-12-03). Arguments: tkr-surface and tkr-wear executables.
set -uo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/checks.sh"
export TKR_SURFACE=$1
wear=$2
for part in femur insert; do
  $py "$root/meshes/gen/scanlike.py" "$cad/tkr-c-$part.step" "$work/$part.stl" --seed 3 --duplicates 1 \
    --holes 1 --flip > /dev/null
done
cd "$work"
"$root/scripts/mesh-implant" --femur femur.stl --insert insert.stl -o knee.msh > mesh.log 2>&1
echo "exit $?" >> mesh.log
grep -v "^  " mesh.log
has() { grep -q -- "$1" mesh.log; }
check "meshed" has "exit 0"
check "no traceback" bash -c "! grep -q Traceback mesh.log"
check "the femur's 4 mm remesh found unfaithful, redone with 3 mm" \
  has "surface femur: the remeshed surface strays .* remeshing with edges of 3 mm"
check "insert swept with its post" bash -c "grep -q 'tibia (swept columns)' mesh.log \
  && grep -q 'the post .* swept as a raised feature' mesh.log"
static_2000n "$wear" knee.msh 33.21 107.57 "the STEP mesh's"
exit $failed
