# SPDX-License-Identifier: LGPL-2.1-or-later
# Shared set-up for scripts/run-main-job and scripts/run-tests: install the
# Debian packages if missing, configure and build. Source it; do not run it.
set -euo pipefail

TKR_ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
# libopenblas0-pthread: installing it makes OpenBLAS the system BLAS
# (update-alternatives libblas.so.3), which CHOLMOD's supernodal
# factorisation needs to be fast (medium TKR mesh: 1.4-2.7 s instead of
# 7.6 s with the reference BLAS; doc/performance.md).
# libsuitesparse-dev (CHOLMOD) and libmumps-dev (parallel MUMPS, for the
# test contact/ipopt_mumps_01) come with libdeal.ii-dev anyway; listed
# because tkr-wear uses them directly.
# black, flake8: the Python half of the format check (scripts/indent);
# python3-pytest: the Python unit tests (ctest -R python/unit).
# libnlopt-cxx-dev: NLopt's COBYLA and BOBYQA for Problem = optimisation.
TKR_PACKAGES="libdeal.ii-dev gmsh coinor-libipopt-dev numdiff clang-format cmake g++ make pkg-config libopenblas0-pthread libsuitesparse-dev libmumps-dev python3-matplotlib python3-numpy python3-gmsh python3-scipy libcgal-dev libnlopt-cxx-dev black flake8 python3-pytest"
TKR_JOBS=${TKR_JOBS:-$(nproc)}

# OpenMPI refuses to start as root unless told that this is intended.
if [ "$(id -u)" -eq 0 ]; then
  export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
fi

tkr_install_packages() {
  local missing=()
  for p in $TKR_PACKAGES; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "ok installed" || missing+=("$p")
  done
  if [ ${#missing[@]} -gt 0 ]; then
    echo "== Installing Debian packages: ${missing[*]}"
    local sudo=""
    [ "$(id -u)" -eq 0 ] || sudo="sudo"
    $sudo apt-get update -qq
    DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq "${missing[@]}" >/dev/null
  fi
}

# tkr_build BUILD_TYPE BUILD_DIR [extra cmake arguments...]
tkr_build() {
  local type=$1 dir=$2
  shift 2
  echo "== Configuring ($type) in $dir"
  cmake -S "$TKR_ROOT" -B "$dir" -DCMAKE_BUILD_TYPE="$type" "$@" >"$dir.cmake.log" 2>&1 ||
    { cat "$dir.cmake.log"; return 1; }
  # Release also builds tkr-surface, the STL repair of scripts/mesh-implant
  # (CGAL, about 90 s to compile); the Debug build runs no script test.
  local targets="tkr-wear"
  [ "$type" = Release ] && targets="tkr-wear tkr-surface"
  echo "== Building $targets ($type)"
  # shellcheck disable=SC2086
  cmake --build "$dir" --target $targets -- -j"$TKR_JOBS"
}
