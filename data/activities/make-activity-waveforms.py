#!/usr/bin/env python3
# SPDX-License-Identifier: LGPL-2.1-or-later
"""Write data/activities/stair-ascent.csv and deep-knee-bend.csv.

EXAMPLE force-control waveforms for activities other than walking, in the
columns of data/iso14243-1.csv (percent_cycle, flexion_deg, axial_force_N,
ap_force_N, ie_torque_Nm; AP force > 0 pushes the tibia anteriorly, IE
torque > 0 rotates the tibia internally). They are RECONSTRUCTIONS around a
few published numbers, NOT a standard and NOT measured time courses: only
the numbers marked "SOURCE" below were read in a publication (full
citations in README.md); every other key point is marked "ASSUMPTION".

Sources read (abstracts only; the figures with the time courses were not
accessible):
  [K10] Kutzner et al. 2010, J Biomech 43:2164-2173 (abstract).
  [P09] "Hip and knee flexion of lead and trail limbs during ascent of a
        step of different heights by normal adults", Physiotherapy 2009
        (abstract).
  [B14] Bergmann et al. 2014, PLoS ONE 9(1):e86035 (abstract).
  [KA]  Kingston & Acker, J Appl Biomech 36(6):444 (abstract).

Usage: make-activity-waveforms.py [output directory]  (default: the
directory of this script). Pure Python 3, no third-party modules; reads
../iso14243-1.csv (the repository's ISO 14243-1 reconstruction) for the
AP force and IE torque shapes of the stair ascent.
"""
import math
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
ISO_CSV = os.path.join(HERE, os.pardir, "iso14243-1.csv")

# ASSUMPTION: body mass 75 kg, g = 9.81 m/s^2, so 1 BW = 735.75 N. The
# sources give forces in % BW; rescale a whole file with `Gait/Channel
# scales` (axial_force_N: m / 75) for another body mass.
BODY_MASS_KG = 75.0
BW_N = BODY_MASS_KG * 9.81

# ASSUMPTION: the swing load of the ISO 14243-1 reconstruction
# (data/iso14243-1.csv, 167.6 N from 60 % on) keeps the femur on the insert
# whenever the leg is unloaded.
SWING_LOAD_N = 167.6

# Simulator limit: our implant meshes may not handle flexion above ~90-100
# deg (the femur leaves the insert), so every flexion value is capped here.
FLEXION_CAP_DEG = 90.0

# ---------------------------------------------------------------- stair ascent
# SOURCE [K10]: "Average peak resultant forces, in percent of body weight,
# were highest during stair descending (346% BW), followed by stair
# ascending (316% BW), ..." -> peak axial force 3.16 BW. [K10] also: shear
# forces about 10-20 times smaller than the axial force and the resultant
# "almost vertical" on the plateau, so axial force ~ resultant force
# (sqrt(1 + 1/10^2) = 1.005).
STAIR_PEAK_BW = 3.16
# SOURCE [P09]: maximum knee flexion of the LEAD limb ascending a 20.3 cm
# step, 90.5 deg (trail limb 57.6 deg); capped to FLEXION_CAP_DEG.
STAIR_PEAK_FLEXION_DEG = min(90.5, FLEXION_CAP_DEG)

# ASSUMPTION: the time course. Stance 0..65 % (foot contact on the step at
# 0 %), swing 65..100 %; no stance/swing ratio was read in a source. Flexion
# at foot contact 60 deg (between [P09]'s trail 57.6 and lead 90.5 deg),
# near-extension (5 deg) late in stance, swing peak [P09] at 83 %.
STAIR_FLEXION = [
    (0, 60.0),  # ASSUMPTION: foot contact on the step
    (8, 50.0),  # ASSUMPTION
    (15, 42.0),  # ASSUMPTION
    (25, 28.0),  # ASSUMPTION
    (35, 15.0),  # ASSUMPTION
    (45, 7.0),  # ASSUMPTION
    (55, 5.0),  # ASSUMPTION: near extension late in stance
    (60, 8.0),  # ASSUMPTION
    (65, 20.0),  # ASSUMPTION: toe off
    (72, 50.0),  # ASSUMPTION
    (78, 76.0),  # ASSUMPTION
    (83, STAIR_PEAK_FLEXION_DEG),  # SOURCE [P09] value, capped; timing ASSUMED
    (88, 86.0),  # ASSUMPTION
    (94, 70.0),  # ASSUMPTION
    (100, 60.0),  # = 0 % (periodic)
]
# Axial force in BW. Only the maximum is published ([K10]); the two-peaked
# stance shape (weight acceptance, push-up) and all other values are an
# ASSUMPTION.
STAIR_AXIAL_BW = [
    (0, SWING_LOAD_N / BW_N),  # ASSUMPTION: swing load at foot contact
    (5, 1.2),  # ASSUMPTION
    (10, 2.6),  # ASSUMPTION
    (15, STAIR_PEAK_BW),  # SOURCE [K10] 316 % BW; timing ASSUMED
    (20, 2.9),  # ASSUMPTION
    (30, 2.2),  # ASSUMPTION: mid-stance trough
    (40, 2.6),  # ASSUMPTION
    (47, 2.9),  # ASSUMPTION: second (push-up) peak, below the first
    (55, 2.0),  # ASSUMPTION
    (61, 0.8),  # ASSUMPTION
    (65, SWING_LOAD_N / BW_N),  # ASSUMPTION: toe off, swing load
    (100, SWING_LOAD_N / BW_N),  # = 0 % (periodic)
]
# AP force and IE torque: no source gives them for stair ascent.
# ASSUMPTION: the ISO 14243-1 reconstruction's channels at the same percent
# (their stance also ends by 65 %; both shapes are themselves partly
# assumed, see scripts/make-iso-waveform), scaled:
# - AP: so that its largest magnitude is 1/15 of the stair peak axial force
#   ([K10]: shear 10-20 times smaller than the axial force; 15 = midpoint).
# - IE: unscaled (peak 6 N m). [B14]: "The peak torque around the implant
#   stem during walking was 10.5 Nm, which was higher than during all other
#   activities"; so a stair torque no larger than the walking one.
STAIR_AP_PEAK_FRACTION_OF_AXIAL = 1.0 / 15.0  # ASSUMPTION within [K10]'s 1/20..1/10
STAIR_IE_SCALE = 1.0  # ASSUMPTION (bounded by [B14])

# -------------------------------------------------------------- deep knee bend
# SOURCE [K10]: knee bending, average peak resultant force 253 % BW.
KNEE_BEND_PEAK_BW = 2.53
# SOURCE [K10]: two legged stance, average peak resultant force 107 % BW.
# ASSUMPTION: this is the load standing upright (0 deg) at the start and end
# of the knee bend.
STANDING_BW = 1.07
# The flexion depth of [K10]'s knee bend was not read. Squats in the Grand
# Challenge data reach ~120 deg ([KA]), more than the simulator's limit, so
# the bend is CAPPED: a "deep knee bend to 90 deg".
KNEE_BEND_MAX_FLEXION_DEG = FLEXION_CAP_DEG


def knee_bend_flexion(p):
    """ASSUMPTION: raised cosine, 0 deg at 0 and 100 %, maximum at 50 %."""
    return 0.5 * KNEE_BEND_MAX_FLEXION_DEG * (1.0 - math.cos(2.0 * math.pi * p / 100.0))


def knee_bend_axial_bw(flexion):
    """ASSUMPTION: linear in flexion, STANDING_BW at 0 deg to the [K10] peak
    at the deepest (capped) flexion; the same going down and up."""
    return STANDING_BW + (KNEE_BEND_PEAK_BW - STANDING_BW) * flexion / KNEE_BEND_MAX_FLEXION_DEG


# ASSUMPTION: no source read gives AP force or IE torque for a knee bend:
# both are zero (the simulator's restraints alone position the tibia).
KNEE_BEND_AP_N = 0.0
KNEE_BEND_IE_NM = 0.0


def monotone_cubic(points, x):
    """Fritsch-Carlson monotone piecewise cubic Hermite interpolation (as in
    scripts/make-iso-waveform): no overshoot beyond the key points."""
    xs = [p[0] for p in points]
    ys = [p[1] for p in points]
    n = len(xs)
    d = [(ys[i + 1] - ys[i]) / (xs[i + 1] - xs[i]) for i in range(n - 1)]
    m = [d[0]] + [0.0 if d[i - 1] * d[i] <= 0 else (d[i - 1] + d[i]) / 2 for i in range(1, n - 1)] + [d[-1]]
    for i in range(n - 1):
        if d[i] == 0:
            m[i] = m[i + 1] = 0.0
            continue
        a, b = m[i] / d[i], m[i + 1] / d[i]
        s = a * a + b * b
        if s > 9:
            t = 3 / s**0.5
            m[i], m[i + 1] = t * a * d[i], t * b * d[i]
    for i in range(n - 1):
        if xs[i] <= x <= xs[i + 1]:
            h = xs[i + 1] - xs[i]
            t = (x - xs[i]) / h
            return (
                (2 * t**3 - 3 * t**2 + 1) * ys[i]
                + (t**3 - 2 * t**2 + t) * h * m[i]
                + (-2 * t**3 + 3 * t**2) * ys[i + 1]
                + (t**3 - t**2) * h * m[i + 1]
            )
    raise ValueError(x)


def read_iso(path):
    """Rows of data/iso14243-1.csv by percent: {percent: (ap_N, ie_Nm)}."""
    rows, header = {}, None
    with open(path) as f:
        for line in f:
            line = line.strip()
            if not line or line.startswith("#"):
                continue
            cells = line.split(",")
            if header is None:
                header = cells
                continue
            r = dict(zip(header, (float(c) for c in cells)))
            rows[int(round(r["percent_cycle"]))] = (r["ap_force_N"], r["ie_torque_Nm"])
    return rows


STAIR_HEADER = """\
# Stair ascent, force control: a RECONSTRUCTION for an EXAMPLE, not a
# standard and not a measured time course. Written by
# data/activities/make-activity-waveforms.py (key points and sources
# there; citations in data/activities/README.md).
# Body mass ASSUMPTION 75 kg (1 BW = 735.75 N); rescale with Gait/Channel
# scales.
# SOURCES: peak axial force 3.16 BW = {peak:.1f} N at 15 % (Kutzner et al.
#   2010, J Biomech 43:2164, abstract: stair ascending 316 % BW average
#   peak resultant force; resultant almost vertical, shear 10-20x smaller);
#   peak flexion 90 deg (Physiotherapy 2009, step ascent abstract: lead
#   knee 90.5 deg for a 20.3 cm step; capped at 90 deg for the simulator).
# ASSUMPTION: the whole time course (stance 0-65 %, swing 65-100 %, flexion
#   60 deg at foot contact, two stance force peaks, swing load 167.6 N as in
#   data/iso14243-1.csv); AP force = the ISO 14243-1 reconstruction's AP
#   force scaled to a peak of 1/15 of the peak axial force; IE torque = the
#   ISO 14243-1 reconstruction's, unscaled (Bergmann et al. 2014 PLoS ONE:
#   walking has the largest stem torque of all activities).
# Signs: AP force > 0 pushes the tibia anteriorly (+y); IE torque > 0
# rotates the tibia internally.
percent_cycle,flexion_deg,axial_force_N,ap_force_N,ie_torque_Nm
"""

KNEE_BEND_HEADER = """\
# Deep knee bend CAPPED AT 90 DEG ("deep knee bend to 90 deg"), force
# control: a RECONSTRUCTION for an EXAMPLE, not a standard and not a
# measured time course. Written by
# data/activities/make-activity-waveforms.py (key points and sources
# there; citations in data/activities/README.md).
# Body mass ASSUMPTION 75 kg (1 BW = 735.75 N); rescale with Gait/Channel
# scales.
# SOURCES: peak axial force 2.53 BW = {peak:.1f} N (Kutzner et al. 2010,
#   J Biomech 43:2164, abstract: knee bending 253 % BW average peak
#   resultant force); standing load 1.07 BW = {stand:.1f} N (same abstract:
#   two legged stance 107 % BW). Squats can reach ~120 deg (Kingston &
#   Acker, J Appl Biomech 36(6):444, abstract); our implant meshes allow
#   ~90-100 deg, so flexion is CAPPED at 90 deg.
# ASSUMPTION: flexion a raised cosine 0 -> 90 deg (50 %) -> 0 deg; axial
#   force linear in flexion from 1.07 BW to 2.53 BW (the source peak placed
#   at the capped depth); AP force 0 and IE torque 0 (no source read).
# Signs: AP force > 0 pushes the tibia anteriorly (+y); IE torque > 0
# rotates the tibia internally.
percent_cycle,flexion_deg,axial_force_N,ap_force_N,ie_torque_Nm
"""


def stair_rows(iso):
    ap_iso_max = max(abs(ap) for ap, _ in iso.values())
    ap_scale = STAIR_AP_PEAK_FRACTION_OF_AXIAL * STAIR_PEAK_BW * BW_N / ap_iso_max
    for p in range(0, 101):
        f = min(monotone_cubic(STAIR_FLEXION, p), FLEXION_CAP_DEG)
        a = monotone_cubic(STAIR_AXIAL_BW, p) * BW_N
        ap, ie = iso[p]
        yield p, f, a, ap_scale * ap, STAIR_IE_SCALE * ie


def knee_bend_rows():
    for p in range(0, 101):
        f = min(knee_bend_flexion(p), FLEXION_CAP_DEG)
        a = knee_bend_axial_bw(f) * BW_N
        yield p, f, a, KNEE_BEND_AP_N, KNEE_BEND_IE_NM


def write(path, header, rows):
    with open(path, "w") as out:
        out.write(header)
        for p, f, a, ap, ie in rows:
            out.write(f"{p},{f:.2f},{a:.1f},{ap + 0.0:.1f},{ie + 0.0:.3f}\n")


def main(outdir):
    iso = read_iso(ISO_CSV)
    write(
        os.path.join(outdir, "stair-ascent.csv"),
        STAIR_HEADER.format(peak=STAIR_PEAK_BW * BW_N),
        stair_rows(iso),
    )
    write(
        os.path.join(outdir, "deep-knee-bend.csv"),
        KNEE_BEND_HEADER.format(peak=KNEE_BEND_PEAK_BW * BW_N, stand=STANDING_BW * BW_N),
        knee_bend_rows(),
    )


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else HERE)
