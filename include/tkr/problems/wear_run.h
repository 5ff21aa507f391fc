// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#ifndef tkr_problems_wear_run_h
#define tkr_problems_wear_run_h

#include <tkr/base/mpi.h>
#include <tkr/geometry/mesh_motion.h>
#include <tkr/output/progress.h>
#include <tkr/output/vtu_output.h>
#include <tkr/problems/gait_cycle.h>
#include <tkr/problems/two_body_model.h>
#include <tkr/wear/run_result.h>
#include <tkr/wear/surface_sides.h>
#include <tkr/wear/wear_law.h>
#include <tkr/wear/wear_state.h>

#include <memory>
#include <string>
#include <vector>

namespace TKR::Problems
{
  /**
   * What a wear run works on, shared by the block loop (WearProblem) and
   * the classes that report (WearReport), write (WearFiles) and checkpoint
   * (WearCheckpoint) it: the model, the activities with one gait cycle
   * each (`Gait/Activities`, doc/gait.md "Activity mixes"; without a mix
   * the run's gait alone), the wear law, the state a checkpoint keeps and
   * the wear of the last block's cycle; and what follows from them alone:
   * the activities' step starts, their share of the wear, the run's
   * result.
   */
  struct WearRun
  {
    WearRun(const Parameters::AllParameters &parameters,
            const MPI_Comm                   mpi_communicator);

    /** Steps of one cycle of every activity. */
    unsigned int
    n_steps() const;

    /** Every activity's step starts, one activity after the other. */
    std::vector<Gait::StepStart>
    step_starts() const;

    /** Start the activities' cycles from @p starts (as step_starts()). */
    void
    set_step_starts(const std::vector<Gait::StepStart> &starts);

    /** Whether the run is an activity mix. */
    bool
    is_mix() const
    {
      return !model.parameters().mix.empty();
    }

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
     * The run's result (doc/output.md): what summary.json and
     * wear_history.csv are written from and what a study reads.
     */
    Wear::RunResult
    result() const;

    const StepGroups groups;
    TwoBodyModel     model;
    /** The activities: the mix, or the run's gait alone. */
    const std::vector<Parameters::Activity> activities;
    /** One gait cycle per activity; cycle is the first. */
    std::vector<std::unique_ptr<GaitCycle>> cycles;
    GaitCycle                              &cycle;
    std::unique_ptr<Wear::WearLaw>          law;
    Wear::WearRunState                      state;
    /** The wear of the last block's cycle (of a mix: mixed). */
    Wear::CycleWear cycle_wear;
    /** Each activity's wear of the last block's cycle. */
    std::vector<Wear::CycleWear> activity_wear;
    /**
     * The nodal areas of the worn surface on which the last block's cycle
     * was solved (before the block's wear moved it: the block's volume and
     * wear area are measured on them) and its medial and lateral nodes.
     */
    Wear::SurfaceSides sides;
  };

  /**
   * The screen and progress.log of a wear run: the statistics of each
   * block's steps (into the run's state), the load balance of every
   * converged step (a step that fails it makes the run fail, loudly), the
   * report of the first cycle, a progress line per block and the failed
   * steps at the end.
   */
  class WearReport
  {
  public:
    explicit WearReport(WearRun &run);

    /**
     * Count the steps of the cycles just solved into the run's state,
     * check their load balance and, after the first, report the cycle.
     */
    void
    add_cycles();

    /** The progress line of the block (screen and progress.log). */
    void
    block(const double block_wall_time) const;

    /** The failed steps, after a run that did not converge. */
    void
    failure() const;

    /** The block's largest pressure (MPa) and contact area (mm^2). */
    double peak_pressure = 0, max_contact_area = 0;

  private:
    /**
     * The protocol's load balance of every converged step of the cycle;
     * a step that fails it makes the run fail, with a warning.
     */
    void
    check_load_balance();

    /** The screen report of the first cycle (on the unworn insert). */
    void
    first_cycle();

    /** The first-cycle report's lines of each activity of a mix. */
    void
    activities() const;

    WearRun &run;
    /** The progress lines (screen and progress.log). */
    Output::Progress progress;
    /** The converged steps of the last cycle that failed the balance. */
    std::vector<unsigned int> unbalanced_steps;
  };

  /**
   * The files of a wear run: per block a row of wear_history.csv and the
   * worn tibia (worn.pvd, each step group a share of its cells); at the end
   * steps.csv and the step VTU files of the last cycle, the wear maps,
   * summary.json and the plots.
   */
  class WearFiles
  {
  public:
    explicit WearFiles(WearRun &run);

    /**
     * The block's row of the history (with @p report's block statistics)
     * and its files.
     */
    void
    block(const WearReport &report);

    /** The files of the run's end. */
    void
    finish();

  private:
    /**
     * The worn tibia's VTU files of the block (collective: each step group
     * writes a share of the cells).
     */
    void
    worn_tibia();

    WearRun                           &run;
    std::unique_ptr<Output::VtuSeries> worn_series;
  };

  /**
   * The checkpoint of a wear run (checkpoint.h5, written atomically, with
   * the parameters that determine the state): read at a resume, written
   * every `Checkpoint interval` blocks and at a stop signal.
   */
  class WearCheckpoint
  {
  public:
    explicit WearCheckpoint(WearRun &run);

    /** Take the run's state from the checkpoint and say so. */
    void
    resume();

    /** Write one, if one is due after this block. */
    void
    write_if_due();

    /**
     * A stop @p signal ended the cycle of the next block: write the
     * checkpoint of the last block done (its step starts @p starts, from
     * before the cycle) and raise ExcStopped saying what was kept.
     */
    void
    stop(const std::string &signal, const std::vector<Gait::StepStart> &starts);

  private:
    /** checkpoint.h5 of the state after the last block done. */
    void
    write();

    WearRun &run;
  };
} // namespace TKR::Problems

#endif
