// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#ifndef tkr_problems_wear_problem_h
#define tkr_problems_wear_problem_h

#include <tkr/geometry/mesh_motion.h>
#include <tkr/problems/wear_run.h>

#include <functional>
#include <memory>
#include <vector>

namespace TKR::Problems
{
  /**
   * `Problem = wear`: the knee-simulator wear test (DESIGN.md sections 2,
   * 4.6, 4.7). Hybrid time stepping over blocks of `Cycles per
   * extrapolation step` (n_Delta) cycles until `Cycles`: per block one
   * gait cycle (GaitCycle, with the protocol of `Gait/Control`) on the
   * current worn geometry, the wear of that cycle by the law of `Wear/Wear
   * law` (Wear::WearLaw), extrapolated over the block by the law and added
   * to the accumulated depth, the tibia_contact nodes moved inward along
   * the worn surface's normal by the new depth and the motion extended
   * into the tibia (Geometry::MeshMotion); the result is the Euler vector
   * of the model's Geometry::WornGeometry. A block that would distort a
   * tibia cell beyond the `Distortion limit` is refused, or retried with
   * half the cycles. The stiffness follows the worn geometry every
   * `Stiffness update interval` blocks. Every step starts from the same
   * step of the previous block (warm start).
   *
   * This class drives the block loop only; what it works on is a WearRun,
   * reported by a WearReport (a progress line per block, also in
   * progress.log), written by WearFiles (per block a row of
   * wear_history.csv and the worn tibia, worn.pvd; at the end
   * summary.json, steps.csv and the step VTU files of the last cycle,
   * wear_map.csv, mass_loss.png and wear_map.png) and checkpointed by
   * WearCheckpoint (every `Checkpoint interval` blocks; `tkr-wear --resume
   * FILE.prm` continues from it, on any number of ranks, with the same
   * results, and refuses a parameter file that differs in those).
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

    /**
     * Called by run() on every rank before the set-up, if set. Only the
     * test executable tkr-wear-test sets it (apps/test_hooks.cc: the fault
     * injection of two tests); tkr-wear and the library never do.
     */
    static std::function<void(MPI_Comm)> start_hook;

    /**
     * The run's result (after run(); doc/output.md): what summary.json and
     * wear_history.csv are written from and what a study reads.
     */
    Wear::RunResult
    result() const
    {
      return wear_run.result();
    }

    /** Wear depth per tibia_contact node of the last block's cycle (mm; of
     *  a mix, the share-weighted sum of its activities'). */
    const std::vector<double> &
    get_wear_depth() const
    {
      return wear_run.cycle_wear.depth;
    }

  private:
    /** A fresh start (block 0) or the state of the checkpoint. */
    void
    start();

    /**
     * Solve one cycle of every activity on the current geometry; a stop
     * signal writes the checkpoint of the last block (WearCheckpoint).
     */
    void
    solve_cycles(const bool first, const bool last);

    /**
     * The wear of the cycle just solved (the wear law on the cycle's
     * sliding) and the block's statistics.
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

    /**
     * The error (or, if the block is halved, the warning) for a block of
     * @p n cycles that would distort the tibia as @p distortion says with
     * the depth @p increment.
     */
    std::string
    distortion_message(const double                n,
                       const Geometry::Distortion &distortion,
                       const std::vector<double>  &increment) const;

    const bool           resume;
    WearRun              wear_run;
    Geometry::MeshMotion motion;
    WearReport           report;
    WearFiles            files;
    WearCheckpoint       checkpoint;
  };
} // namespace TKR::Problems

#endif
