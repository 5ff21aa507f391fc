// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#ifndef tkr_problems_wear_problem_h
#define tkr_problems_wear_problem_h

#include <tkr/base/mpi.h>
#include <tkr/geometry/mesh_motion.h>
#include <tkr/output/vtu_output.h>
#include <tkr/problems/gait_cycle.h>
#include <tkr/problems/two_body_model.h>
#include <tkr/wear/wear_state.h>

#include <memory>
#include <vector>

namespace TKR::Problems
{
  /**
   * `Problem = wear`: the ISO 14243-1 wear test (DESIGN.md sections 2, 4.6,
   * 4.7). Hybrid time stepping over blocks of `Cycles per extrapolation
   * step` (n_Delta) cycles until `Cycles`: per block one gait cycle
   * (GaitCycle) on the current worn geometry, Archard's wear of that cycle
   * times n_Delta added to the accumulated depth, the tibia_contact nodes
   * moved inward along the worn surface's normal by the new depth and the
   * motion extended into the tibia (Geometry::MeshMotion); the result is the
   * Euler vector of the model's Geometry::WornGeometry. A block that would
   * distort a tibia cell beyond the `Distortion limit` is refused, or
   * retried with half the cycles. The stiffness follows the worn geometry
   * every `Stiffness update interval` blocks. Every step starts from the
   * same step of the previous block (warm start).
   *
   * Output per block: a row of wear_history.csv, a progress line (also in
   * progress.log), the worn tibia (worn.pvd), a checkpoint every
   * `Checkpoint interval` blocks (checkpoint.h5, written atomically);
   * `tkr-wear --resume FILE.prm` continues from it, on any number of ranks,
   * with the same results. At the end: summary.json, steps.csv and the step
   * VTU files of the last cycle, wear_map.csv, mass_loss.png and
   * wear_map.png.
   */
  class WearProblem
  {
  public:
    /** With @p resume, continue from the checkpoint of the output folder. */
    WearProblem(const Parameters::AllParameters &parameters,
                const MPI_Comm                   mpi_communicator,
                const bool                       resume = false);

    /** Run; returns true if every contact solve of every block converged. */
    bool
    run();

    /** Wear depth per tibia_contact node of the last block's cycle (mm). */
    const std::vector<double> &
    get_wear_depth() const
    {
      return cycle_depth;
    }

  private:
    /** A fresh start (block 0) or the state of the checkpoint. */
    void
    start();

    /**
     * The Archard wear of the cycle just solved: depth per node, the
     * block's statistics; the report of the first cycle.
     */
    void
    compute_wear();

    /**
     * Add the wear of min(n_Delta, cycles left) cycles to the geometry,
     * halving n_Delta (if configured) while that would distort a cell
     * beyond the limit. Returns the number of cycles added.
     */
    double
    extrapolate();

    /** History row, progress line, worn tibia VTU, checkpoint. */
    void
    finish_block(const double block_wall_time);

    /** summary.json, steps.csv, step VTU files, wear map, plots. */
    void
    output_results();

    const bool           resume;
    const StepGroups     groups;
    TwoBodyModel         model;
    GaitCycle            cycle;
    Geometry::MeshMotion motion;
    Wear::WearRunState   state;
    std::vector<double>  cycle_depth, cycle_slip;
    /** The block's statistics: peak pressure, largest contact area. */
    double                             peak_pressure = 0, max_contact_area = 0;
    std::unique_ptr<Output::VtuSeries> worn_series;
  };
} // namespace TKR::Problems

#endif
