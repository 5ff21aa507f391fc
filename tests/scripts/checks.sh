# SPDX-License-Identifier: LGPL-2.1-or-later
# Shared by the tests/scripts/*_test.sh checks; source it. Sets root (the
# sources), work (a temporary folder removed on exit), py (Debian's python3
# with gmsh and numpy), cad (the bundled CAD files), failed (0), and
# check DESCRIPTION COMMAND...: runs the command, prints ok or FAILED with
# its output, and sets failed=1 on failure.
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
failed=0
py=/usr/bin/python3
cad=$root/meshes/tkr/cad
check() {
  local what=$1
  shift
  if "$@" > "$work/check.log" 2>&1; then
    echo "ok: $what"
  else
    echo "FAILED: $what"
    cat "$work/check.log"
    failed=1
  fi
}

# static_2000n WEAR MESH PEAK AREA WHAT: the static contact under 2000 N of
# prm/static-2000n.prm on MESH (in the current folder, output in static/);
# checks that it converged and that its peak pressure (MPa) and contact area
# (mm^2) are within 20 % of PEAK and AREA, those of WHAT.
static_2000n() {
  printf 'include %s\nsubsection Mesh\n  set File = %s\nend\nsubsection Output\n  set Directory = static\nend\n' \
    "$root/prm/static-2000n.prm" "$2" > static.prm
  "$1" static.prm > static.log 2>&1 || tail -20 static.log
  grep -i "converged\|contact area\|max pressure" static.log
  value() { sed -n "s/^ *$1: *\([0-9.]*\).*/\1/p" static.log; }
  within() { $py -c "import sys; a, b = float(sys.argv[1]), float(sys.argv[2]); print(a, b, a / b - 1); sys.exit(abs(a / b - 1) > 0.2)" "$@"; }
  check "contact converged" grep -q "Contact converged" static.log
  check "peak pressure within 20 % of $5" within "$(value 'max pressure')" "$3"
  check "contact area within 20 % of $5" within "$(value 'contact area')" "$4"
}
