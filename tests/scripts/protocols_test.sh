#!/usr/bin/env bash
# SPDX-License-Identifier: LGPL-2.1-or-later
# protocols_test.sh TKR_WEAR ROOT [PROTOCOL...]
# Every gait protocol runs (issue 52: no protocol is named here): the
# coarse one-cycle job (ROOT/prm/one-cycle.prm) with 20 steps per cycle
# under every registered protocol with its example entries
# (tkr-wear --list-models, tkr-wear --model-example PROTOCOL: e.g. the ISO
# 14243-3 waveform for displacement control). Each run must exit 0 with
# every step converged, its result files must agree with doc/output.md
# (python/tkr_results.py check) and pass tests/scripts/check_wear_physics.py
# (mass = density x volume, the sides add up, the depth map holds the
# volume).
set -u
exe=$1
root=$2
shift 2
protocols=("$@")
if [ "${#protocols[@]}" -eq 0 ]; then
  mapfile -t protocols < <("$exe" --list-models | sed -n 's/^gait protocol: \([^ ]*\).*/\1/p')
  [ "${#protocols[@]}" -ge 1 ] || { echo "FAIL: tkr-wear --list-models lists no gait protocol"; exit 1; }
fi
echo "protocols: ${protocols[*]}"
status=0
for protocol in "${protocols[@]}"; do
  dir=$protocol
  rm -rf "$dir"
  if ! "$exe" --model-example "$protocol" > "$dir.model.prm"; then
    echo "FAIL: tkr-wear --model-example $protocol"
    status=1
    continue
  fi
  {
    echo "include $root/prm/one-cycle.prm"
    echo "include $(pwd)/$dir.model.prm"
    echo "subsection Gait"
    echo "  set Steps per cycle = 20"
    echo "end"
    echo "subsection Output"
    echo "  set Directory = $dir"
    echo "  set VTU interval = 0"
    echo "  set Plots = false"
    echo "  set Testing = true"
    echo "end"
  } > "$dir.prm"
  if ! "$exe" "$dir.prm" > "$dir.log" 2>&1; then
    echo "FAIL: $protocol exited with an error:"
    tail -5 "$dir.log"
    status=1
    continue
  fi
  converged=$(python3 "$root/python/tkr_results.py" get "$dir/summary.json" converged)
  mass=$(python3 "$root/python/tkr_results.py" get "$dir/summary.json" mass_loss_mg)
  if [ "$converged" = true ]; then
    echo "ok: $protocol: every step converged, $mass mg"
  else
    echo "FAIL: $protocol: not every step converged"
    status=1
  fi
  python3 "$root/python/tkr_results.py" check "$dir" || status=1
  python3 "$root/tests/scripts/check_wear_physics.py" "$dir" || status=1
done
exit $status
