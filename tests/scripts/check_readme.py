#!/usr/bin/env python3
# SPDX-License-Identifier: LGPL-2.1-or-later
"""Every test that ctest knows is described in tests/README.md.

    check_readme.py BUILD_DIR README

Lists the tests of BUILD_DIR (ctest -N) and looks for each in README's
tables, written in backticks: the name without its variants (`.release`,
`.debug`, `.mpirun=N`), or its base name before the first '.', or its
folder's wildcard (`cli/*`). Prints the missing ones and fails if there are
any, so that the README cannot drift from the tests.
"""
import re
import subprocess
import sys


def test_names(build_dir):
    listing = subprocess.run(
        ["ctest", "-N"], cwd=build_dir, capture_output=True, text=True, check=True
    ).stdout
    names = set()
    for line in listing.splitlines():
        match = re.match(r"\s*Test\s+#\d+: (\S+)", line)
        if match:
            name = re.sub(r"\.mpirun=\d+", "", match.group(1))
            names.add(re.sub(r"\.(release|debug)$", "", name))
    return sorted(names)


def main(build_dir, readme):
    with open(readme) as f:
        documented = set(re.findall(r"`([^`\s]+)`", f.read()))
    names = test_names(build_dir)
    missing = [
        name
        for name in names
        if name not in documented
        and name.split(".")[0] not in documented
        and name.split("/")[0] + "/*" not in documented
    ]
    for name in missing:
        print("tests/README.md does not describe the test %s" % name)
    print("check_readme: %d tests, %d not in tests/README.md" % (len(names), len(missing)))
    return 1 if missing else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1], sys.argv[2]))
