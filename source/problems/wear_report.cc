// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.
//
// WearReport: the screen and progress.log of a wear run.

#include <tkr/base/exceptions.h>
#include <tkr/problems/wear_run.h>
#include <tkr/wear/sliding.h>

#include <algorithm>

namespace TKR::Problems
{
  using namespace dealii;

  namespace
  {
    /** What the steps of a block's cycles did, counted. */
    struct StepCounts
    {
      unsigned int steps = 0, converged = 0, solves = 0, newton = 0;
    };

    StepCounts
    count_steps(const std::vector<std::unique_ptr<GaitCycle>> &cycles)
    {
      StepCounts counts;
      for (const auto &c : cycles)
        for (const auto &r : c->get_reports())
          {
            ++counts.steps;
            counts.converged += r.converged;
            counts.solves += r.contact_solves;
            counts.newton += r.newton_iterations;
          }
      return counts;
    }
  } // namespace

  WearReport::WearReport(WearRun &run)
    : run(run)
    , progress(run.model.parameters().output.directory, run.model.world())
  {}

  // The block's statistics come from the step reports.
  void
  WearReport::add_cycles()
  {
    auto &state   = run.state;
    peak_pressure = max_contact_area = 0;
    for (const auto &c : run.cycles)
      for (const auto &r : c->get_reports())
        {
          state.pose_fallbacks += r.pose_fallbacks;
          state.cut_back_steps += r.sub_steps > 0;
          state.sub_steps += r.sub_steps;
          peak_pressure    = std::max(peak_pressure, r.max_pressure);
          max_contact_area = std::max(max_contact_area, r.contact_area);
        }
    const StepCounts counts = count_steps(run.cycles);
    state.contact_solves += counts.solves;
    state.newton_iterations += counts.newton;
    state.steps += counts.steps;
    state.converged    = state.converged && counts.converged == counts.steps;
    state.max_pressure = std::max(state.max_pressure, peak_pressure);
    check_load_balance();
    if (state.block == 0)
      first_cycle();
  }

  // A converged step out of equilibrium is a result the program cannot
  // stand behind: it is counted and named, loudly, never silent.
  void
  WearReport::check_load_balance()
  {
    unbalanced_steps.clear();
    unsigned int first = 0;
    std::string  example;
    for (const auto &c : run.cycles)
      {
        const auto &protocol = c->get_protocol();
        const auto &reports  = c->get_reports();
        for (unsigned int s = 0; s < reports.size(); ++s)
          {
            const double balance    = protocol.load_balance(reports[s]);
            const bool   unbalanced = reports[s].converged && !(balance <= 1.);
            if (unbalanced && unbalanced_steps.empty())
              example = "e.g. step " + std::to_string(first + s) + " by " +
                        format_number(balance, 6) + " times what the " +
                        "tolerances allow (" + protocol.load_balance_text() +
                        ")";
            if (unbalanced)
              unbalanced_steps.push_back(first + s);
            if (!reports[s].converged || unbalanced)
              run.state.failed_steps.push_back({run.state.block + 1,
                                                first + s,
                                                reports[s].pose_residual,
                                                reports[s].contact_converged,
                                                balance});
          }
        first += reports.size();
      }
    if (unbalanced_steps.empty())
      return;
    run.state.converged = false;
    run.model.pcout() << "Warning: block " << run.state.block + 1 << ": "
                      << unbalanced_steps.size()
                      << " converged step(s) fail the load balance, " << example
                      << ". The run will exit with 1." << std::endl;
  }

  // The first cycle (on the unworn insert) is reported in full, per
  // million cycles (at the law's rate, without the run-in factor), so that
  // regression tests compare O(1) numbers; its wear area counts the nodes
  // whose depth extrapolated linearly to the Cycles of the parameter file
  // (with the run-in) exceeds the threshold.
  void
  WearReport::first_cycle()
  {
    const auto  &parameters = run.model.parameters();
    const auto  &wear       = parameters.wear;
    const double n_cycles   = run.law->effective_cycles(0, wear.cycles);
    const auto   measures =
      Wear::measure_wear(run.cycle_wear.depth,
                         run.model.geometry().worn_surface_measures().area,
                         wear.wear_area_threshold,
                         n_cycles);
    const double mass = parameters.materials.tibia.density * measures.volume;
    const StepCounts counts = count_steps(run.cycles);
    run.model.pcout() << "Wear of the first cycle (" << run.law->description()
                      << "):" << std::endl
                      << "  volume loss:       " << 1e6 * measures.volume
                      << " mm^3 per million cycles" << std::endl
                      << "  mass loss:         " << 1e6 * mass
                      << " mg per million cycles" << std::endl
                      << "  max wear depth:    " << 1e9 * measures.max_depth
                      << " um per million cycles" << std::endl
                      << "  peak pressure:     " << peak_pressure
                      << " MPa (over the cycle)" << std::endl
                      << "  max contact area:  " << max_contact_area << " mm^2"
                      << std::endl
                      << "  wear area:         " << measures.worn_percent()
                      << " % of tibia_contact (depth x " << wear.cycles
                      << " cycles > " << wear.wear_area_threshold << " mm)"
                      << std::endl
                      << "  linear extrapolation to " << wear.cycles
                      << " cycles without geometry update: " << mass * n_cycles
                      << " mg" << std::endl
                      << "  steps: " << counts.steps
                      << ", converged: " << counts.converged;
    if (!parameters.output.testing)
      run.model.pcout() << ", contact solves: " << counts.solves
                        << ", Newton iterations per step: "
                        << double(counts.newton) / counts.steps;
    run.model.pcout() << std::endl << "  load balance (";
    for (unsigned int a = 0; a < run.cycles.size(); ++a)
      run.model.pcout() << (a > 0 ? "; " : "")
                        << run.cycles[a]->get_protocol().load_balance_text();
    run.model.pcout() << ") in every converged step: "
                      << (unbalanced_steps.empty() ? "yes" : "no") << std::endl;
    activities();
    run.state.first_cycle_mass = mass;
  }

  // Each activity's share of the mix's first cycle, and what the activity
  // alone would wear per million cycles.
  void
  WearReport::activities() const
  {
    if (!run.is_mix())
      return;
    const double density = run.model.parameters().materials.tibia.density;
    const auto  &area    = run.model.geometry().worn_surface_measures().area;
    for (unsigned int a = 0; a < run.activities.size(); ++a)
      {
        const double alone =
          1e6 * density *
          Wear::measure_wear(run.activity_wear[a].depth, area, 0.).volume;
        unsigned int n_converged = 0;
        for (const auto &r : run.cycles[a]->get_reports())
          n_converged += r.converged;
        run.model.pcout() << "  activity " << run.activities[a].name
                          << " (share " << run.activities[a].share
                          << "): " << run.activities[a].share * alone
                          << " mg per million cycles of the mix (" << alone
                          << " alone), steps: " << run.cycles[a]->n_steps()
                          << ", converged: " << n_converged << std::endl;
      }
  }

  void
  WearReport::block(const double block_wall_time) const
  {
    const unsigned int n_blocks =
      run.state.block +
      std::ceil((run.model.parameters().wear.cycles - run.state.cycles) /
                  run.state.cycles_per_block -
                1e-9);
    progress.block(run.state.block,
                   n_blocks,
                   run.state.cycles,
                   run.state.history.back(),
                   block_wall_time,
                   run.model.parameters().output.testing);
  }

  void
  WearReport::failure() const
  {
    progress.failure(run.state.failed_steps);
  }
} // namespace TKR::Problems
