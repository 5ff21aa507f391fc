#!/usr/bin/env bash
# SPDX-License-Identifier: LGPL-2.1-or-later
# Run tkr-wear on a parameter file that is wrong on purpose and check that it
# fails with a non-zero exit code and prints each expected message fragment.
#   expect-error.sh TKR_WEAR PRM_FILE FRAGMENT...
set -u
exe=$1
prm=$2
shift 2
output=$("$exe" "$prm" 2>&1)
code=$?
echo "$output"
if [ "$code" -eq 0 ]; then
  echo "FAIL: tkr-wear exited with 0 on a bad input"
  exit 1
fi
for fragment in "$@"; do
  if ! grep -qF -- "$fragment" <<<"$output"; then
    echo "FAIL: the message lacks: $fragment"
    exit 1
  fi
done
echo "OK: exit code $code and the expected message"
