// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.
//
// WearProblem's activities (`Gait/Activities`, doc/gait.md "Activity
// mixes"): one GaitCycle per activity, their step starts, their share of
// the wear and their results.

#include <tkr/base/exceptions.h>
#include <tkr/problems/wear_problem.h>
#include <tkr/wear/sliding.h>

#include <algorithm>

namespace TKR::Problems
{
  using namespace dealii;

  unsigned int
  WearProblem::n_steps() const
  {
    unsigned int n = 0;
    for (const auto &c : cycles)
      n += c->n_steps();
    return n;
  }

  std::vector<Gait::StepStart>
  WearProblem::step_starts() const
  {
    std::vector<Gait::StepStart> starts;
    for (const auto &c : cycles)
      starts.insert(starts.end(),
                    c->get_step_starts().begin(),
                    c->get_step_starts().end());
    return starts;
  }

  void
  WearProblem::set_step_starts(const std::vector<Gait::StepStart> &starts)
  {
    unsigned int first = 0;
    for (const auto &c : cycles)
      {
        const unsigned int n = c->n_steps();
        AssertThrow(first + n <= starts.size(), ExcInternalError());
        c->set_step_starts(
          std::vector<Gait::StepStart>(starts.begin() + first,
                                       starts.begin() + first + n));
        first += n;
      }
  }

  // Each activity's share of the mix's first cycle, and what the activity
  // alone would wear per million cycles.
  void
  WearProblem::report_activities() const
  {
    if (model.parameters().mix.empty())
      return;
    const double density = model.parameters().materials.tibia.density;
    const auto  &area    = model.geometry().worn_surface_measures().area;
    for (unsigned int a = 0; a < activities.size(); ++a)
      {
        const double alone =
          1e6 * density *
          Wear::measure_wear(activity_wear[a].depth, area, 0.).volume;
        unsigned int n_converged = 0;
        for (const auto &r : cycles[a]->get_reports())
          n_converged += r.converged;
        model.pcout() << "  activity " << activities[a].name << " (share "
                      << activities[a].share
                      << "): " << activities[a].share * alone
                      << " mg per million cycles of the mix (" << alone
                      << " alone), steps: " << cycles[a]->n_steps()
                      << ", converged: " << n_converged << std::endl;
      }
  }

  // Each activity's share of the block's wear, as the mix's is added.
  void
  WearProblem::add_activity_wear(const double               effective,
                                 const std::vector<double> &area)
  {
    const auto &surface = model.geometry().worn_surface().nodes();
    for (unsigned int a = 0; a < state.activity_volume.size(); ++a)
      {
        const double scale = effective * activities[a].share;
        const auto  &depth = activity_wear[a].depth;
        auto        &total = state.activity_volume[a];
        for (unsigned int j = 0; j < surface.size(); ++j)
          {
            const double volume = scale * depth[j] * area[j];
            state.activity_depth[a][surface[j].vertex] += scale * depth[j];
            total.volume += volume;
            (sides.medial()[j] ? total.medial_volume : total.lateral_volume) +=
              volume;
          }
      }
  }

  std::vector<std::string>
  WearProblem::activity_names() const
  {
    std::vector<std::string> names;
    if (!model.parameters().mix.empty())
      for (const auto &activity : activities)
        names.push_back(activity.slug);
    return names;
  }

  std::vector<Wear::ActivityResult>
  WearProblem::activity_results() const
  {
    const auto &surface = model.geometry().worn_surface().nodes();
    std::vector<Wear::ActivityResult> results = state.activity_volume;
    for (unsigned int a = 0; a < results.size(); ++a)
      {
        results[a].mass =
          model.parameters().materials.tibia.density * results[a].volume;
        for (const auto &node : surface)
          results[a].max_depth = std::max(results[a].max_depth,
                                          state.activity_depth[a][node.vertex]);
      }
    return results;
  }

  void
  WearProblem::solve_cycles(const bool first, const bool last)
  {
    // What a checkpoint of the last block done keeps, should a stop
    // signal end this block's cycles (their steps overwrite them).
    const std::vector<Gait::StepStart> starts = step_starts();
    for (unsigned int a = 0; a < cycles.size(); ++a)
      {
        GaitCycle &c = *cycles[a];
        if (first)
          model.pcout() << (model.parameters().mix.empty() ?
                              std::string() :
                              "Activity " + activities[a].name + ", ")
                        << "Gait cycle, " << c.n_steps()
                        << " steps:" << std::endl;
        try
          {
            c.solve(first, last, first);
          }
        catch (const ExcStopped &exc)
          {
            stop(exception_message(exc), starts);
          }
      }
  }
} // namespace TKR::Problems
