#!/usr/bin/env bash
# SPDX-License-Identifier: LGPL-2.1-or-later
# scripts/mesh-implant on a scan-like pair with rounded rims and a locking
# recess (issue 33 item 3): TKR B's STEP files through meshes/gen/rounded.py
# (the insert's top rim, base rim and recess edges rounded, 1.1-1.5 mm, a
# 3 mm recess cut into its base; both bodies triangulated irregularly, 30-55k
# triangles, 0.005 mm noise; closed and manifold). With the defaults
# mesh-implant must mesh it (before: "ValueError: need at least one array to
# concatenate", an internal error), tag the insert's underside from the
# geometry, give the wear run only the seat as tibia_inferior (within 15 %
# of the area of the input's flat triangles within 0.05 mm of its lowest
# point: the quadrangles whose centres lie over the seat, less those that
# ramp up to the recess's floor, 1654 vs 1768 mm^2 on 2026-12-06; its nodes
# within 0.07 mm in z: the rigid tray's flatness tolerance; the recess's
# floor and the rounded base rim do not bear on the tray) and put no quadrangle facing
# down into tibia_contact. The insert is swept, the columns inside the
# recess standing on its floor. Then the mesh goes through a gait cycle of
# 10 steps (large load changes per step) of ISO 14243-1 from rest with the
# defaults and the parameter file mesh-implant wrote: every step must
# converge (ISO 14243-3 too, but in the benchmark: CI's time).
# A and C, whole cycles and the rest of the robustness set:
# benchmarks/robustness.sh, doc/robustness.md. Arguments: tkr-surface,
# tkr-wear.
set -uo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/checks.sh"
export TKR_SURFACE=$1
wear=$2
$py "$root/meshes/gen/rounded.py" "$cad/tkr-b-femur.step" "$work/femur.stl" --seed 2 --size 1.1 2> /dev/null
$py "$root/meshes/gen/rounded.py" "$cad/tkr-b-insert.step" "$work/insert.stl" --seed 1 --rim 1.5 2> /dev/null
check "closed and manifold (tkr-surface finds no defect)" bash -c "\"$1\" $work/insert.stl $work/i.stl | grep -q 'defects: none' \
  && \"$1\" $work/femur.stl $work/f.stl | grep -q 'defects: none'"
cd "$work"
"$root/scripts/mesh-implant" --femur femur.stl --insert insert.stl -o knee.msh > mesh.log 2>&1
echo "exit $?" >> mesh.log
grep -v "^  \|^surface" mesh.log
has() { grep -q -- "$1" mesh.log; }
check "meshed" has "exit 0"
check "no traceback, no internal error" bash -c "! grep -q 'Traceback\|internal error' mesh.log"
check "valid two-body mesh" $py "$root/meshes/gen/check_msh.py" --quiet knee.msh
tags() {
  $py - "$root/meshes/gen" <<'PY'
import sys
import numpy as np
sys.path.insert(0, sys.argv[1])
import check_msh
from mesh_implant import read_stl
names, phys, nodes, blocks = check_msh.read_msh("knee.msh")
ids = {v: k[1] for k, v in names.items()}
X = {t: np.array(p) for t, p in nodes.items()}
def quads(group):
    return [np.array([X[n] for n in el[1][:4]]) for dim, ent, et, els in blocks if dim == 2
            and ids[group] in phys.get((2, ent), []) for el in els]
def area_normal(Q):
    n = 0.5 * np.cross(Q[2] - Q[0], Q[3] - Q[1])
    return np.linalg.norm(n), n / np.linalg.norm(n)
inferior = sum(area_normal(Q)[0] for Q in quads("tibia_inferior"))
down = [a for a, n in map(area_normal, quads("tibia_contact")) if n[2] < -0.3]
T = read_stl("insert.stl")
n = np.cross(T[:, 1] - T[:, 0], T[:, 2] - T[:, 0])
a = 0.5 * np.linalg.norm(n, axis=1)
z = T[..., 2]
under = a[(n[:, 2] < -0.3 * 2 * a) & (T.mean(axis=1)[:, 2] < z.min() + 0.5 * np.ptp(z))].sum()
seat = a[(n[:, 2] < -0.9 * 2 * a) & (T[..., 2] < z.min() + 0.05).all(axis=1)].sum()
P = np.concatenate(quads("tibia_inferior"))
off = np.ptp(P[:, 2])
print("tibia_inferior %.1f mm2, input seat %.1f mm2 (%+.1f %%), input underside %.1f mm2; its nodes within "
      "%.3f mm in z; tibia_contact quads facing down: %d" % (inferior, seat, 100 * (inferior / seat - 1), under, off,
                                                             len(down)))
sys.exit(not 0.85 <= inferior / seat <= 1.15 or off > 0.07 or len(down) > 0)
PY
}
check "tibia_inferior is the underside, tibia_contact faces up" tags
cat "$work/check.log"
check "insert swept, its columns standing on the recess floor" bash -c "grep -q 'tibia (swept columns)' mesh.log \
  && grep -q 'of the base lie above it (a recess' mesh.log"
printf 'include %s\ninclude knee.prm\nsubsection Gait\n  set Steps per cycle = 10\n  set Waveform file = %s\nend
subsection Wear\n  set Cycles = 1\n  set Cycles per extrapolation step = 1\nend
subsection Output\n  set Directory = iso1\n  set VTU interval = 0\nend\n' "$root/prm/one-cycle.prm" \
  "$root/data/iso14243-1.csv" > iso1.prm
"$wear" iso1.prm > iso1.log 2>&1
grep "^  step" iso1.log | sed 's/, [0-9.]* s$//'
check "ISO 14243-1, 10 steps: every step converged" \
  test "$($py "$root/python/tkr_results.py" get iso1/summary.json unconverged_steps)" = "[]"
exit $failed
