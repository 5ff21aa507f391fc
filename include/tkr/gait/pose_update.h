// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#ifndef tkr_gait_pose_update_h
#define tkr_gait_pose_update_h

#include <deal.II/base/tensor.h>

#include <tkr/gait/bracket.h>

#include <array>
#include <vector>

namespace TKR::Gait
{
  /**
   * The update rule of the pose iteration (ForceControl::solve_pose(),
   * doc/gait.md "One step"), apart from the contact solves so that it can
   * be tested on functions with known roots.
   *
   * The iteration looks for a pose q (six numbers: the tibia's translation,
   * its IE rotation, the restraints' excess force and torque) at which the
   * correction d(q) that a contact solve asks for vanishes; d decreases
   * along each component (q + d is where the solve says the tibia went).
   * next() takes the relaxed step q + lambda d, with lambda the secant
   * estimate of how much of the scaled residual r one unit of step removed
   * (lambda is halved when |r| did not decrease).
   *
   * That step can cycle when d falls steeply over a small range of q, as it
   * does where a contact node enters the active set near equilibrium. The
   * safeguard keeps, per component, the latest pose with d > 0 and the
   * latest with d < 0. When the relaxed step stalls (four solves without
   * bringing |r| 10 % below the best before them), the component with the
   * largest residual among those whose d alternated in sign over the last
   * three solves and whose two poses enclose a root (the one with d > 0
   * below the one with d < 0) stops following the relaxed step: its next
   * value is the false-position point of the bracket, held within the
   * bracket's middle half, so the bracket shrinks to at most 3/4 per solve
   * and d, continuous in q, goes to zero with it. The other components keep
   * the relaxed step. A bracket that stops enclosing a root, or becomes a
   * thousand times narrower than the correction asked for inside it (the
   * other components moved the root, or d jumps), is dropped.
   */
  class PoseUpdate
  {
  public:
    static constexpr unsigned int n = 6;
    using Vector                    = dealii::Tensor<1, n>;

    /**
     * The most contact solves of one step's pose iteration, in either
     * protocol; a step that needs more ends not converged (loudly).
     */
    static constexpr unsigned int max_solves = 40;

    /**
     * With @p safeguard = false only the relaxed step (the rule before
     * issue 18; for tests that show the difference).
     */
    explicit PoseUpdate(const bool safeguard = true);

    /**
     * The next pose after a solve at @p q that asked for the correction
     * @p d, with the scaled residual @p r (whose norm the relaxation
     * watches).
     */
    Vector
    next(const Vector &q, const Vector &d, const Vector &r);

    /** Whether any component was bracketed in this iteration. */
    bool
    bracketed_ever() const;

  private:
    double
    relaxed_relaxation(const Vector &r);

    bool
    stalled() const;

    bool   safeguard;
    double lambda       = 1;
    bool   has_previous = false;
    bool   ever         = false;
    /** The bracketed component, n if none. */
    unsigned int           active = n;
    Vector                 previous_r;
    std::array<Bracket, n> brackets;
    std::vector<double>    norms;
  };
} // namespace TKR::Gait

#endif
