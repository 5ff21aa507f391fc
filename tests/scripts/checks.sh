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
