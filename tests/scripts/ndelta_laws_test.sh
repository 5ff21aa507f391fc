#!/usr/bin/env bash
# SPDX-License-Identifier: LGPL-2.1-or-later
# ndelta_laws_test.sh TKR_WEAR ROOT [LAW...]
# Each wear law converges in the extrapolation step (issue 20 item 4): the
# coarse one-cycle job (ROOT/prm/one-cycle.prm) over 5e5 cycles in blocks of
# n_Delta and n_Delta / 2, under every registered law with its example
# inputs (tkr-wear --list-models, tkr-wear --model-example LAW: e.g. the
# EXAMPLE tables of ROOT/data/wear; issue 52: no law is named here) and
# the default law with the example run-in (3 falling to 1 at 1e6 cycles,
# across the whole run: LAW run-in). The two masses of a law must agree
# within 1 % and every solve must converge, and each run's files must pass
# tests/scripts/check_wear_physics.py. n_Delta is 2.5e5, for a law whose
# rate changes with the wear (trait rate-changes-with-wear) 1e5: the area
# law's rate grows with the contact area, which wear enlarges, so a block
# that keeps the rate of its first cycle lags (1e6 cycles in blocks of 2.5e5 and 1.25e5: 1.4 %
# apart, 2e6 in 1e6 and 5e5: 10 %; the 5e6-cycle job in 5e4 and 2.5e4:
# 0.15 %, doc/results.md). The run-in is integrated exactly over each block;
# the factor at a block's start instead would give 1.375e6 and 1.3125e6
# effective cycles (exact: 1.25e6), masses 5 % apart.
set -u
exe=$1
root=$2
shift 2
laws=("$@")
if [ "${#laws[@]}" -eq 0 ]; then
  mapfile -t laws < <("$exe" --list-models | sed -n 's/^wear law: \([^ ]*\).*/\1/p')
  [ "${#laws[@]}" -ge 1 ] || { echo "FAIL: tkr-wear --list-models lists no wear law"; exit 1; }
  laws+=(run-in)
fi
echo "laws: ${laws[*]}"
status=0
# changing LAW: whether the law's rate changes with the wear
changing() {
  [ "$1" != run-in ] && "$exe" --list-models | grep -q "^wear law: $1 (.*rate-changes-with-wear"
}
# mass SUMMARY: its mass_loss_mg, or NOT-CONVERGED (python/tkr_results.py)
mass() {
  if [ "$(python3 "$root/python/tkr_results.py" get "$1" converged)" = true ]; then
    python3 "$root/python/tkr_results.py" get "$1" mass_loss_mg
  else
    echo NOT-CONVERGED
  fi
}
for law in "${laws[@]}"; do
  masses=()
  steps="2.5e5 1.25e5"
  changing "$law" && steps="1e5 5e4"
  for n in $steps; do
    dir=$law-$n
    rm -rf "$dir"
    if [ "$law" = run-in ]; then
      printf 'subsection Wear\n  set Run-in file = %s\nend\n' \
        "$root/data/wear/example-run-in.csv" > "$dir.model.prm"
    elif ! "$exe" --model-example "$law" > "$dir.model.prm"; then
      echo "FAIL: tkr-wear --model-example $law"
      status=1
      continue
    fi
    {
      echo "include $root/prm/one-cycle.prm"
      echo "include $(pwd)/$dir.model.prm"
      echo "subsection Wear"
      echo "  set Cycles = 5e5"
      echo "  set Cycles per extrapolation step = $n"
      echo "end"
      echo "subsection Output"
      echo "  set Directory = $dir"
      echo "  set VTU interval = 0"
      echo "  set Plots = false"
      echo "  set Testing = true"
      echo "end"
    } > "$dir.prm"
    if ! "$exe" "$dir.prm" > "$dir.log" 2>&1; then
      echo "FAIL: $law with n_Delta $n exited with an error:"
      tail -5 "$dir.log"
      status=1
      continue
    fi
    masses+=("$(mass "$dir/summary.json")")
    # The run's physical statements (tests/scripts/check_wear_physics.py):
    # mass = density x volume, the sides add up, wear accumulates, block 1
    # = the first cycle's rate x its effective cycles (the run-in's integral),
    # the depth map holds the volume; for Archard (with a cross-shear table
    # or a run-in too) every block's rate per effective cycle within 10 %
    # of the first cycle's (tests/app/CMakeLists.txt: the geometry changes
    # load x sliding by about depth / contact half-width). Not for a law
    # whose rate changes with the wear (e.g. with the contact area,
    # doc/wear.md).
    band=(--rate-band 0.1)
    changing "$law" && band=()
    python3 "$root/tests/scripts/check_wear_physics.py" "$dir" ${band[@]+"${band[@]}"} || status=1
  done
  [ "${#masses[@]}" -eq 2 ] || continue
  python3 - "$law" $steps "${masses[@]}" <<'PY' || status=1
import sys
law, n_a, n_b, a, b = sys.argv[1:6]
if "NOT-CONVERGED" in (a, b):
    sys.exit(f"FAIL: {law}: a run did not converge")
a, b = float(a), float(b)
difference = abs(a - b) / b
print(f"{law}: n_Delta {n_a} {a:.6f} mg, {n_b} {b:.6f} mg, difference "
      f"{100 * difference:.4f} %")
if not a > 0 or difference > 0.01:
    sys.exit(f"FAIL: {law}: the two masses differ by more than 1 %")
PY
done
[ "$status" -eq 0 ] && echo "ok: ${laws[*]} within 1 % between n_Delta and n_Delta / 2"
exit "$status"
