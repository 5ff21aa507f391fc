#!/usr/bin/env bash
# SPDX-License-Identifier: LGPL-2.1-or-later
# The pose and contact Newton across a change of the active set (issue 33):
# TKR C's chordal STL export (up to 12 mm triangles, a PS cam and post)
# through scripts/mesh-implant with the defaults, then ten steps of one ISO
# 14243-1 cycle from rest with the default pose Newton (the pose and the
# contact solved together, analytic derivatives) and with the Newton on the
# pose alone, its derivatives by finite differences (the independent
# answer). With a backtracking line search
# on |r|^2 the Newton stalled where a node's activation lay across its step
# (steps at 58 % and 67-75 % of 100: 40 Newton steps each between 5 and 6
# active nodes, not converged; doc/gait.md); its line search in the step's
# potential energy converges. Checks: both runs converge every step, and
# the coupled poses (AP translation, IE rotation) agree with the others
# within 0.05 mm and 0.1 deg, the first-cycle mass loss within 0.1 %.
# Arguments: tkr-surface and tkr-wear executables.
set -uo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/checks.sh"
export TKR_SURFACE=$1
wear=$2
cd "$work"
check "mesh-implant on the chordal TKR C STL with the defaults" \
  "$root/scripts/mesh-implant" --femur "$cad/tkr-c-femur.stl" --insert "$cad/tkr-c-insert.stl" -o knee.msh
for solver in coupled fd; do
  derivatives=$([ $solver = coupled ] && echo analytic || echo finite differences)
  printf 'include %s\ninclude %s\nsubsection Gait\n  set Steps per cycle = 10\n  set Pose derivatives = %s\nend
subsection Wear\n  set Cycles = 1\n  set Cycles per extrapolation step = 1\nend
subsection Output\n  set Directory = %s\n  set VTU interval = 0\nend\n' \
    "$root/prm/one-cycle.prm" knee.prm "$derivatives" "$solver" > "$solver.prm"
  "$wear" "$solver.prm" > "$solver.log" 2>&1
  grep "^  step" "$solver.log" | sed 's/, [0-9.]* s$//'
  check "$solver: every step converged" test "$($py "$root/python/tkr_results.py" get "$solver/summary.json" unconverged_steps)" = "[]"
done
agree() {
  $py - "$root/python" <<'PY'
import sys
sys.path.insert(0, sys.argv[1])
import tkr_results as r
rows = {s: r.read_rows(s + "/steps.csv", ("step", "ap_position_mm", "ie_rotation_deg")) for s in ("coupled", "fd")}
bad = 0
for a, b in zip(rows["coupled"], rows["fd"]):
    dy = abs(r.number(a, "ap_position_mm") - r.number(b, "ap_position_mm"))
    dt = abs(r.number(a, "ie_rotation_deg") - r.number(b, "ie_rotation_deg"))
    print("step %s: |dy| %.4f mm, |dtheta| %.4f deg" % (a["step"], dy, dt))
    bad |= dy > 0.05 or dt > 0.1
m = [r.read_summary(s + "/summary.json")["first_cycle_mass_loss_mg_per_million_cycles"] for s in ("coupled", "fd")]
print("mass loss coupled %.6g, finite differences %.6g mg per 1e6 cycles" % tuple(m))
sys.exit(bad or abs(m[0] / m[1] - 1) > 1e-3)
PY
}
check "coupled poses and mass loss agree with the finite-difference Newton" agree
exit $failed
