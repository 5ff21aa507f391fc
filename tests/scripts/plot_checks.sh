# SPDX-License-Identifier: LGPL-2.1-or-later
# Shared by the tests of the plotting scripts (plot_wear_test.sh,
# plot_optimisation_test.sh); source it. Sets n_passed and n_failed (0) and
# defines check DESCRIPTION COMMAND... (counts a pass or a failure),
# is_png FILE and one_line_error STDERR_FILE EXIT_CODE PATTERN.
n_passed=0
n_failed=0

check() { # check DESCRIPTION COMMAND...: count a pass or a failure
  local what=$1
  shift
  if "$@"; then
    n_passed=$((n_passed + 1))
  else
    n_failed=$((n_failed + 1))
    echo "FAILED: $what" >&2
  fi
}

# is_png FILE: PNG signature, an IHDR of at least 300 x 300 pixels, > 10 kB
is_png() {
  local file=$1
  [[ -f "$file" ]] || { echo "  $file: missing" >&2; return 1; }
  local signature size
  signature=$(head -c 16 "$file" | od -An -tx1 | tr -d ' \n')
  [[ "$signature" == 89504e470d0a1a0a0000000d49484452 ]] ||
    { echo "  $file: not a PNG (starts with $signature)" >&2; return 1; }
  local b
  read -r -a b < <(od -An -tu1 -j16 -N8 "$file")
  local width=$(((b[0] << 24) | (b[1] << 16) | (b[2] << 8) | b[3]))
  local height=$(((b[4] << 24) | (b[5] << 16) | (b[6] << 8) | b[7]))
  size=$(wc -c <"$file")
  echo "  $(basename "$file"): ${width} x ${height} pixels, $size bytes"
  ((width >= 300 && height >= 300 && size > 10000)) ||
    { echo "  $file: too small" >&2; return 1; }
}

one_line_error() { # one_line_error STDERR_FILE EXIT_CODE PATTERN
  local lines
  lines=$(wc -l <"$1")
  [[ $2 -eq 1 && $lines -eq 1 ]] && grep -q -- "$3" "$1" &&
    ! grep -q Traceback "$1" ||
    {
      echo "  exit code $2, $lines lines of stderr:" >&2
      cat "$1" >&2
      return 1
    }
}
