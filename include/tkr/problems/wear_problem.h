// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#ifndef tkr_problems_wear_problem_h
#define tkr_problems_wear_problem_h

#include <tkr/base/mpi.h>
#include <tkr/geometry/mesh_motion.h>
#include <tkr/output/progress.h>
#include <tkr/output/vtu_output.h>
#include <tkr/problems/gait_cycle.h>
#include <tkr/problems/two_body_model.h>
#include <tkr/wear/cross_shear.h>
#include <tkr/wear/run_result.h>
#include <tkr/wear/surface_sides.h>
#include <tkr/wear/wear_law.h>
#include <tkr/wear/wear_state.h>

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
   * Output per block: a row of wear_history.csv, a progress line (also in
   * progress.log), the worn tibia (worn.pvd), a checkpoint every
   * `Checkpoint interval` blocks (checkpoint.h5, written atomically, with
   * the parameters that determine the state); `tkr-wear --resume
   * FILE.prm` continues from it, on any number of ranks, with the same
   * results, and refuses a parameter file that differs in those. At the
   * end: summary.json, steps.csv and the step VTU files of the last cycle,
   * wear_map.csv, mass_loss.png and wear_map.png.
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
    result() const;

    /** Wear depth per tibia_contact node of the last block's cycle (mm; of
     *  a mix, the share-weighted sum of its activities'). */
    const std::vector<double> &
    get_wear_depth() const
    {
      return cycle_wear.depth;
    }

  private:
    /** A fresh start (block 0) or the state of the checkpoint. */
    void
    start();

    /** Steps of one cycle of every activity. */
    unsigned int
    n_steps() const;

    /** Every activity's step starts, one activity after the other. */
    std::vector<Gait::StepStart>
    step_starts() const;

    /** Start the activities' cycles from @p starts (as step_starts()). */
    void
    set_step_starts(const std::vector<Gait::StepStart> &starts);

    /**
     * Solve one cycle of every activity on the current geometry; a stop
     * signal writes the checkpoint of the last block (stop()).
     */
    void
    solve_cycles(const bool first, const bool last);

    /** The first-cycle report's lines of each activity of a mix. */
    void
    report_activities() const;

    /** Add the block's wear of each activity of a mix to its own state. */
    void
    add_activity_wear(const double effective, const std::vector<double> &area);

    /** The slugs of the activities of a mix (empty without one). */
    std::vector<std::string>
    activity_names() const;

    /** The row's results of each activity of a mix. */
    std::vector<Wear::ActivityResult>
    activity_results() const;

    /**
     * The wear of the cycle just solved (the wear law on the cycle's
     * sliding) and the block's statistics.
     */
    void
    compute_wear();

    /**
     * The protocol's load balance of every converged step of the cycle;
     * a step that fails it makes the run fail, with a warning.
     */
    void
    check_load_balance();

    /** The screen report of the first cycle (on the unworn insert). */
    void
    report_first_cycle();

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

    /**
     * A stop @p signal ended the cycle of the next block: write the
     * checkpoint of the last block done (its step starts @p starts, from
     * before the cycle) and raise ExcStopped saying what was kept.
     */
    void
    stop(const std::string &signal, const std::vector<Gait::StepStart> &starts);

    /** checkpoint.h5 of the state after the last block done. */
    void
    write_checkpoint();

    /** History row, progress line, worn tibia VTU, checkpoint. */
    void
    finish_block(const double block_wall_time);

    /** The progress line of the block (screen and progress.log). */
    void
    report_progress(const double block_wall_time) const;

    /** The worn tibia's VTU file of the block (step group 0). */
    void
    output_worn_tibia();

    /** A checkpoint, if one is due after this block. */
    void
    write_checkpoint_if_due();

    /** summary.json, steps.csv, step VTU files, wear map, plots. */
    void
    output_results();

    const bool       resume;
    const StepGroups groups;
    TwoBodyModel     model;
    /** The activities: the mix, or the run's gait alone. */
    const std::vector<Parameters::Activity> activities;
    /** One gait cycle per activity; cycle is the first. */
    std::vector<std::unique_ptr<GaitCycle>> cycles;
    GaitCycle                              &cycle;
    Geometry::MeshMotion                    motion;
    std::unique_ptr<Wear::WearLaw>          law;
    Wear::WearRunState                      state;
    /** The wear of the last block's cycle (of a mix: mixed). */
    Wear::CycleWear cycle_wear;
    /** Each activity's wear of the last block's cycle. */
    std::vector<Wear::CycleWear> activity_wear;
    /** The progress lines (screen and progress.log). */
    Output::Progress progress;
    /**
     * The nodal areas of the worn surface on which the last block's cycle
     * was solved (before the block's wear moved it: the block's volume and
     * wear area are measured on them) and its medial and lateral nodes.
     */
    Wear::SurfaceSides sides;
    /** The converged steps of the last cycle that failed the balance. */
    std::vector<unsigned int> unbalanced_steps;
    /** The block's statistics: peak pressure, largest contact area. */
    double                             peak_pressure = 0, max_contact_area = 0;
    std::unique_ptr<Output::VtuSeries> worn_series;
  };
} // namespace TKR::Problems

#endif
