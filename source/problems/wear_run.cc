// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.
//
// WearRun: what a wear run works on, its activities (`Gait/Activities`,
// doc/gait.md "Activity mixes": one GaitCycle per activity, their step
// starts, their share of the wear) and its result.

#include <tkr/base/exceptions.h>
#include <tkr/problems/wear_run.h>

#include <algorithm>

namespace TKR::Problems
{
  using namespace dealii;

  namespace
  {
    /** One gait cycle per activity. */
    std::vector<std::unique_ptr<GaitCycle>>
    make_cycles(TwoBodyModel                            &model,
                const StepGroups                        &groups,
                const std::vector<Parameters::Activity> &activities)
    {
      std::vector<std::unique_ptr<GaitCycle>> cycles;
      for (const auto &activity : activities)
        cycles.push_back(std::make_unique<GaitCycle>(model,
                                                     groups,
                                                     activity.gait,
                                                     activity.slug));
      return cycles;
    }
  } // namespace

  WearRun::WearRun(const Parameters::AllParameters &parameters,
                   const MPI_Comm                   mpi_communicator)
    : groups(mpi_communicator, parameters.gait.step_groups)
    , model(parameters, mpi_communicator, groups.communicator)
    , activities(parameters.activities())
    , cycles(make_cycles(model, groups, activities))
    , cycle(*cycles[0])
    , law(Wear::create_wear_law(parameters.wear))
  {}

  unsigned int
  WearRun::n_steps() const
  {
    unsigned int n = 0;
    for (const auto &c : cycles)
      n += c->n_steps();
    return n;
  }

  std::vector<Gait::StepStart>
  WearRun::step_starts() const
  {
    std::vector<Gait::StepStart> starts;
    for (const auto &c : cycles)
      starts.insert(starts.end(),
                    c->get_step_starts().begin(),
                    c->get_step_starts().end());
    return starts;
  }

  void
  WearRun::set_step_starts(const std::vector<Gait::StepStart> &starts)
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

  // Each activity's share of the block's wear, as the mix's is added.
  void
  WearRun::add_activity_wear(const double               effective,
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
  WearRun::activity_names() const
  {
    std::vector<std::string> names;
    if (is_mix())
      for (const auto &activity : activities)
        names.push_back(activity.slug);
    return names;
  }

  std::vector<Wear::ActivityResult>
  WearRun::activity_results() const
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

  Wear::RunResult
  WearRun::result() const
  {
    const auto     &parameters = model.parameters();
    Wear::RunResult result;
    result.history             = state.history;
    result.cycles              = state.cycles;
    result.blocks              = state.block;
    result.density             = parameters.materials.tibia.density;
    result.wear_area_threshold = parameters.wear.wear_area_threshold;
    // A run resumed at its end computes no cycle.
    result.has_cross_shear  = !cycle_wear.cross_shear.empty();
    result.mean_cross_shear = sides.mean_cross_shear(cycle_wear.cross_shear);
    if (result.has_cross_shear)
      for (unsigned int a = 0; a < cycles.size(); ++a)
        for (const auto &[name, value] :
             cycles[a]->get_protocol().cycle_results(cycles[a]->get_reports()))
          result.protocol_results.emplace_back(
            !is_mix() ? name : "activity_" + activities[a].slug + "_" + name,
            value);
    result.activity_names = activity_names();
    for (unsigned int a = 0; a < result.activity_names.size(); ++a)
      result.activity_shares.push_back(activities[a].share);
    result.max_pressure      = state.max_pressure;
    result.steps             = state.steps;
    result.contact_solves    = state.contact_solves;
    result.newton_iterations = state.newton_iterations;
    result.pose_fallbacks    = state.pose_fallbacks;
    result.cut_back_steps    = state.cut_back_steps;
    result.sub_steps         = state.sub_steps;
    result.cycles_per_block  = state.cycles_per_block;
    result.first_cycle_mass  = state.first_cycle_mass;
    result.linear_extrapolation_mass =
      state.first_cycle_mass * law->effective_cycles(0, parameters.wear.cycles);
    if (const auto &run_in = law->get_run_in(); !run_in.empty())
      result.run_in = run_in.points();
    result.stiffness_update_interval =
      parameters.wear.stiffness_update_interval;
    result.step_groups  = groups.n_groups;
    result.failed_steps = state.failed_steps;
    result.converged    = state.converged;
    return result;
  }
} // namespace TKR::Problems
