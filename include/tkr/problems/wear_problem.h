// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#ifndef tkr_problems_wear_problem_h
#define tkr_problems_wear_problem_h

#include <tkr/base/mpi.h>
#include <tkr/problems/gait_cycle.h>
#include <tkr/problems/two_body_model.h>

#include <vector>

namespace TKR::Problems
{
  /**
   * `Problem = wear`: the ISO 14243-1 gait cycle (GaitCycle) on the two-body
   * model and the Archard wear of that cycle (DESIGN.md sections 2, 4.6).
   *
   * Where the long run plugs in (DESIGN.md 4.7): the loop over
   * extrapolation blocks goes around GaitCycle::solve() and
   * compute_wear() in run(); the extrapolated depth moves the tibia
   * through the model's Wear::WornGeometry, and checkpoints save that
   * geometry with the block counter.
   */
  class WearProblem
  {
  public:
    WearProblem(const Parameters::AllParameters &parameters,
                const MPI_Comm                   mpi_communicator);

    /** Run; returns true if every contact solve converged. */
    bool
    run();

    /** Wear depth per tibia_contact node after the cycle (mm). */
    const std::vector<double> &
    get_wear_depth() const
    {
      return wear_depth;
    }

  private:
    /** The Archard wear of the cycle, its report and summary entries. */
    void
    compute_wear();
    void
    output_results();

    const StepGroups    groups;
    TwoBodyModel        model;
    GaitCycle           cycle;
    std::vector<double> wear_depth, slip;
  };
} // namespace TKR::Problems

#endif
