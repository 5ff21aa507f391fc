#!/usr/bin/env bash
# SPDX-License-Identifier: LGPL-2.1-or-later
# Run tkr-wear on a parameter file that is wrong on purpose and check that it
# fails with a non-zero exit code and prints each expected message fragment.
# With TKR_RANKS=N in the environment it runs on N MPI ranks (mpirun) and
# must end within 300 s: an error raised on some ranks only must not hang
# the others.
#   expect-error.sh TKR_WEAR PRM_FILE FRAGMENT...
# A PRM_FILE that starts with -- is the command line's options instead
# (e.g. "--model-example bogus", split at spaces).
set -u
exe=$1
prm=$2
shift 2
args=("$prm")
[[ "$prm" == --* ]] && read -ra args <<< "$prm"
if [ -n "${TKR_RANKS:-}" ]; then
  output=$(timeout 300 mpirun -np "$TKR_RANKS" "$exe" "${args[@]}" 2>&1)
  code=$?
  if [ "$code" -eq 124 ]; then
    echo "$output"
    echo "FAIL: tkr-wear on $TKR_RANKS ranks did not end within 300 s (hang)"
    exit 1
  fi
else
  output=$("$exe" "${args[@]}" 2>&1)
  code=$?
fi
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
