#!/usr/bin/env python3
# SPDX-License-Identifier: LGPL-2.1-or-later
"""Synthetic "measured" mass loss for the calibration tests.

make_synthetic.py WEAR_HISTORY.csv OUT.csv SEED

WEAR_HISTORY.csv is a run of tkr-a.prm (or tkr-b.prm) with the known values
k = 3e-7 mm^3/(N m) and the run-in of truth.csv (2.5 falling to 1 at 4e5
cycles). Three specimens: the run's mass at its block ends times a
specimen factor (0.96, 1.01, 1.03: the scatter between specimens) times
1 + e, e uniform in [-0.01, 0.01] per point (weighing noise; numpy's
RandomState(SEED)). The files say they are synthetic, not illustrative.
"""
import csv
import sys

import numpy as np


def main():
    history, out, seed = sys.argv[1], sys.argv[2], int(sys.argv[3])
    with open(history) as f:
        rows = [(float(r["cycles"]), float(r["mass_mg"])) for r in csv.DictReader(f)]
    rng = np.random.RandomState(seed)
    lines = [
        "# SYNTHETIC test data (tests/scripts/calibration/make_synthetic.py): a tkr-wear",
        "# run with k = 3e-7 and the run-in of truth.csv, specimen factors 0.96, 1.01,",
        "# 1.03 and +-1 % noise per point. Not a measurement.",
        "cycles,mass_mg,specimen",
    ]
    for number, factor in enumerate((0.96, 1.01, 1.03), start=1):
        for cycles, mass in rows:
            noise = 1 + rng.uniform(-0.01, 0.01)
            lines.append(f"{cycles:.0f},{mass * factor * noise:.4f},synthetic {number}")
    with open(out, "w") as f:
        f.write("\n".join(lines) + "\n")


if __name__ == "__main__":
    main()
