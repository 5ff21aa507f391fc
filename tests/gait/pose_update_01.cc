// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.
//
// The update rule of the pose iteration (PoseUpdate) on functions with
// known roots, iterated like ForceControl::solve_pose() (at most 40 solves,
// tolerance 0.001 on every component):
// 1. a smooth, coupled, linear correction: the relaxed step converges and
//    the bracket never engages;
// 2. a pose component whose "position reached" falls steeply over a small
//    range of the pose, as where a contact node enters the active set: from
//    -3.597 to -3.616 mm (TKR B, block 60, step 39, doc/results.md) over
//    0.0004 mm (slope -47.5; on TKR B 0.004 mm, which the relaxed step
//    handles alone, but there the other components were coupled to it),
//    flat outside; the other five components smooth. The relaxed step alone
//    cycles for all 40 solves; with the safeguard the root -3.60973 mm is
//    found (23 solves);
// 3. a correction that jumps over its root (no pose meets the tolerance):
//    NOT converged with both rules (the safeguard does not make a step
//    without an equilibrium converged).

#include <tkr/gait/pose_update.h>

#include <cmath>
#include <functional>

#include "../tests.h"

using TKR::Gait::PoseUpdate;
using PoseVector = PoseUpdate::Vector;

namespace
{
  struct Outcome
  {
    unsigned int solves    = 0;
    bool         converged = false;
    bool         bracketed = false;
    PoseVector   q;
    double       residual = 0;
  };

  Outcome
  iterate(const std::function<PoseVector(const PoseVector &)> &correction,
          const bool                                           safeguard)
  {
    PoseUpdate update(safeguard);
    Outcome    outcome;
    PoseVector q;
    for (;;)
      {
        const PoseVector d = correction(q);
        ++outcome.solves;
        outcome.residual = 0;
        for (unsigned int i = 0; i < PoseUpdate::n; ++i)
          outcome.residual = std::max(outcome.residual, std::abs(d[i]));
        outcome.converged = outcome.residual <= 1e-3;
        if (outcome.converged || outcome.solves >= PoseUpdate::max_solves)
          break;
        q = update.next(q, d, d);
      }
    outcome.q         = q;
    outcome.bracketed = update.bracketed_ever();
    return outcome;
  }

  void
  print(const std::string &name, const Outcome &o)
  {
    deallog << name << ": " << o.solves << " solves, "
            << (o.converged ? "converged" : "NOT converged")
            << (o.bracketed ? ", bracketed" : "") << ", residual "
            << (o.converged ? std::string("<= 0.001") :
                              std::to_string(o.residual))
            << ", q[1] = " << o.q[1] << std::endl;
  }

  // Smooth parts: each component relaxes towards its root, weakly coupled.
  PoseVector
  smooth(const PoseVector &q)
  {
    const PoseVector root({0.3, -1.2, -0.05, 2.0, 40., -300.});
    PoseVector       d;
    for (unsigned int i = 0; i < PoseUpdate::n; ++i)
      d[i] =
        0.8 * (root[i] - q[i]) + 0.05 * (root[(i + 1) % 6] - q[(i + 1) % 6]);
    return d;
  }

  // The AP position reached on TKR B, block 60, step 39 (doc/results.md).
  double
  reached(const double y)
  {
    const double y0 = -3.610, width = 0.0004;
    if (y <= y0)
      return -3.597;
    if (y >= y0 + width)
      return -3.616;
    return -3.597 - 0.019 * (y - y0) / width;
  }
} // namespace

int
main()
{
  initlog();
  deallog << std::setprecision(6);

  print("smooth, relaxed", iterate(smooth, false));
  print("smooth, safeguarded", iterate(smooth, true));

  const auto window = [](const PoseVector &q) {
    PoseVector d = smooth(q);
    d[1]         = reached(q[1]) - q[1];
    return d;
  };
  const Outcome cycling = iterate(window, false);
  print("steep window, relaxed", cycling);
  const Outcome found = iterate(window, true);
  print("steep window, safeguarded", found);
  const double root = (-3.597 - 47.5 * 3.610) / 48.5;
  deallog << "root " << root << ", safeguarded |q[1] - root| < 3e-5: "
          << (std::abs(found.q[1] - root) < 3e-5 ? "yes" : "NO") << std::endl;

  const auto jump = [](const PoseVector &q) {
    PoseVector d = smooth(q);
    d[1]         = (q[1] < -1. ? -0.98 : -1.02) - q[1];
    return d;
  };
  print("jump, relaxed", iterate(jump, false));
  const Outcome jumped = iterate(jump, true);
  print("jump, safeguarded", jumped);
}
