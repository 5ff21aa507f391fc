#!/usr/bin/env bash
# SPDX-License-Identifier: LGPL-2.1-or-later
# Time one Hertz sphere contact solve per mesh size and break the time into
# mortar coupling, sparsity set-up, assembly, AMG set-up, CG and residual
# (TimerOutput), with the active-set iterations. Results go to the screen
# and to benchmarks/results/hertz-contact-<date>.txt; doc/performance.md
# records them.
#   benchmarks/hertz-contact.sh [BUILD_DIR] [RANKS]
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-$root/build/release}
ranks=${2:-1}
[ "$(id -u)" -eq 0 ] && export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
mkdir -p "$root/benchmarks/results"
out="$root/benchmarks/results/hertz-contact-$(date +%Y%m%d-%H%M).txt"
cd "$root"
{
  echo "machine: $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | xargs)"
  echo "build: $build, MPI ranks: $ranks"
  for mesh in coarse medium fine; do
    prm=$(mktemp --suffix=.prm)
    sed "s/sphere-medium/sphere-$mesh/; s|output/hertz-sphere|output/bench-sphere-$mesh|" \
      prm/hertz-sphere.prm > "$prm"
    echo "=== sphere-$mesh"
    /usr/bin/time -f "wall %e s, max RSS %M kB" \
      mpirun -np "$ranks" "$build/tkr-wear" "$prm" 2>&1 |
      grep -E "Degrees|Mortar coupling:|iteration|converged in|ratio|Total wall|mortar coupling|setup system|assemble system|AMG setup|CG solve|residual|wall .* s, max RSS"
    rm -f "$prm"
  done
} | tee "$out"
