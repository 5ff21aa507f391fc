// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#ifndef tkr_wear_run_result_h
#define tkr_wear_run_result_h

#include <tkr/base/result_schema.h>
#include <tkr/wear/wear_state.h>

#include <string>
#include <utility>
#include <vector>

namespace TKR::Wear
{
  /**
   * The result of a wear run (`Problem = wear`), the one record that
   * summary.json, wear_history.csv and a study's table (study.csv,
   * study.json) are written from. Its results are declared in one table
   * (run_result.cc) in the ResultSchema (`tkr-wear --print-schema`,
   * doc/output.md); named_values() and the columns below are that table.
   */
  struct RunResult
  {
    /** One row per block (wear_history.csv), the last is the run's end. */
    std::vector<BlockResult> history;
    /** Cycles run, blocks. */
    double       cycles = 0;
    unsigned int blocks = 0;
    /** The insert's density (mg/mm^3), for the sides' mass. */
    double density = 0;
    /** `Wear/Wear area threshold` (mm). */
    double wear_area_threshold = 0;
    /** The work-weighted mean cross-shear of the last computed cycle; a
     *  run resumed at its end computes none (has_cross_shear false). */
    bool   has_cross_shear  = false;
    double mean_cross_shear = 0;
    /** The protocol's own results of the last computed cycle
     *  (Gait::Protocol::cycle_results(); none if no cycle was computed). */
    std::vector<std::pair<std::string, double>> protocol_results;
    /** The largest contact pressure of all steps (MPa). */
    double max_pressure = 0;
    /** Step solves and the solver's effort over all blocks. */
    unsigned long long steps = 0, contact_solves = 0, newton_iterations = 0,
                       pose_fallbacks = 0;
    /** Steps whose pose converged only in sub-steps (a cut-back), and the
     *  sub-steps they took. */
    unsigned long long cut_back_steps = 0, sub_steps = 0;
    /** The last block's n_Delta (cycles). */
    double cycles_per_block = 0;
    /** The first cycle's mass loss (mg) and its linear extrapolation to
     *  `Wear/Cycles` with the run-in (mg). */
    double first_cycle_mass = 0, linear_extrapolation_mass = 0;
    /** The run-in factor's points (cycles, factor); empty without one. */
    std::vector<std::pair<double, double>> run_in;
    /** `Wear/Stiffness update interval`, the step groups. */
    unsigned int stiffness_update_interval = 0, step_groups = 1;
    /** The steps that did not converge or failed their load balance. */
    std::vector<FailedStep> failed_steps;
    /** Every step converged and balanced. */
    bool converged = true;
    /**
     * The activities of a mix (empty without one): their slugs and shares,
     * in the order of BlockResult::activities.
     */
    std::vector<std::string> activity_names;
    std::vector<double>      activity_shares;

    /**
     * The scalar results, named as in summary.json and in the order of
     * that file (doc/output.md): the run's end, each side's, each
     * activity's of a mix (activity_NAME_...), the solver's counts, the
     * first cycle's.
     */
    std::vector<std::pair<std::string, double>>
    named_values() const;
  };

  /**
   * wear_history.csv's columns of a block, in their order (the checkpoint
   * stores the rows in the same order): the block's own (the wall time is
   * ResultField::timing, written last), each side's (`SIDE_...`) and each
   * activity's of a mix (`NAME_...`).
   */
  const std::vector<ResultColumn<BlockResult>> &
  block_columns();
  const std::vector<ResultColumn<SideResult>> &
  side_columns();
  const std::vector<ResultColumn<ActivityResult>> &
  activity_columns();

  /** The fields of a step that did not converge (summary.json's
   *  `unconverged_steps`, the checkpoint). */
  const std::vector<ResultColumn<FailedStep>> &
  failed_step_columns();
} // namespace TKR::Wear

#endif
