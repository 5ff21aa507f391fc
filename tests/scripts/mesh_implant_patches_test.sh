#!/usr/bin/env bash
# SPDX-License-Identifier: LGPL-2.1-or-later
# scripts/mesh-implant with the contact patches given as their own STL
# files (issue 19 item 2, --femur-contact-stl / --insert-contact-stl, the
# way published implant data often comes): the patches are the triangles of
# TKR A's STL exports that face the other body (femur: the condyles, |x| >
# 11 mm, with n_z < -0.3; insert: n_z > 0.3 in its top half). With --contact-distance 0 the rule from the
# pair's geometry finds nothing (scripts/mesh_implant_errors), so a mesh
# proves that the patches were used. The groups go to whole smooth patches
# of the remeshed surface (a patch is contact if a quarter of it is given;
# the contact layer needs the group borders at sharp edges): femur_contact
# covers the given patch (the whole J-shaped condyle surfaces, 5,673 mm^2,
# of which the patch is the part facing down), tibia_contact is the
# insert's patch within 10 %. Argument: the tkr-surface executable.
set -uo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/checks.sh"
export TKR_SURFACE=$1
cd "$work" || exit 1
$py - "$root/meshes/gen" "$cad" <<'PY' > patches.log
import sys
import numpy as np
sys.path.insert(0, sys.argv[1])
import mesh_implant
for part, keep in (("femur", lambda n, c, z: (n[:, 2] < -0.3) & (np.abs(c[:, 0]) > 11)),
                   ("insert", lambda n, c, z: (n[:, 2] > 0.3) & (c[:, 2] > z.mean()))):
    T = mesh_implant.read_stl("%s/tkr-a-%s.stl" % (sys.argv[2], part))
    n = np.cross(T[:, 1] - T[:, 0], T[:, 2] - T[:, 0])
    area = 0.5 * np.linalg.norm(n, axis=1)
    m = keep(n / (2 * area[:, None]), T.mean(axis=1), T[:, :, 2])
    mesh_implant.write_stl_binary("%s-contact.stl" % part, T[m])
    print("%s %.1f" % (part, area[m].sum()))
PY
cat patches.log
"$root/scripts/mesh-implant" --femur "$cad/tkr-a-femur.stl" --insert "$cad/tkr-a-insert.stl" \
  --femur-contact-stl femur-contact.stl --insert-contact-stl insert-contact.stl --contact-distance 0 \
  -o knee.msh > mesh.log 2>&1
echo "exit $?" >> mesh.log
grep -v "^  \|^surface" mesh.log
check "meshed with the given patches (the rule alone finds nothing)" grep -q "exit 0" mesh.log
check "check_msh.py accepts the mesh" "$py" "$root/meshes/gen/check_msh.py" --quiet knee.msh
area() { # area ROLE GROUP: the area mesh-implant reports for GROUP
  sed -n "s/^$1: .*; $2 [0-9]* patches, \([0-9.]*\) mm2.*/\1/p" mesh.log
}
within() { $py -c "import sys; a, b = map(float, sys.argv[1:]); print(a, b); sys.exit(abs(a / b - 1) > 0.1)" "$@"; }
covers() { $py -c "import sys; a, b = map(float, sys.argv[1:]); print(a, b); sys.exit(a < 0.95 * b)" "$@"; }
check "femur_contact covers the given patch" covers "$(area femur femur_contact)" \
  "$(sed -n 's/^femur //p' patches.log)"
check "tibia_contact: the given patch's area within 10 %" within "$(area tibia tibia_contact)" \
  "$(sed -n 's/^insert //p' patches.log)"
exit $failed
