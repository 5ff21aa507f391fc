// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#include <deal.II/base/timer.h>

#include <tkr/base/exceptions.h>
#include <tkr/output/checkpoint.h>
#include <tkr/output/wear_output.h>
#include <tkr/problems/wear_problem.h>
#include <tkr/wear/activity_mix.h>
#include <tkr/wear/run_result.h>
#include <tkr/wear/sliding.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <limits>
#include <sstream>

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
            counts.solves += r.pose_updates + 1;
            counts.newton += r.newton_iterations;
          }
      return counts;
    }

    /** The shares of @p activities. */
    std::vector<double>
    shares(const std::vector<Parameters::Activity> &activities)
    {
      std::vector<double> values;
      for (const auto &activity : activities)
        values.push_back(activity.share);
      return values;
    }
  } // namespace

  WearProblem::WearProblem(const Parameters::AllParameters &parameters,
                           const MPI_Comm                   mpi_communicator,
                           const bool                       resume)
    : resume(resume)
    , groups(mpi_communicator, parameters.gait.step_groups)
    , model(parameters, mpi_communicator, groups.communicator)
    , activities(parameters.activities())
    , cycles(make_cycles(model, groups, activities))
    , cycle(*cycles[0])
    , motion(model.geometry(), groups.communicator, model.timer())
    , law(Wear::create_wear_law(parameters.wear))
    , progress(parameters.output.directory, model.world())
  {}

  void
  WearProblem::start()
  {
    const auto &parameters = model.parameters();
    const auto &directory  = parameters.output.directory;
    if (!resume)
      {
        state.cycles_per_block = parameters.wear.cycles_per_extrapolation_step;
        if (!parameters.mix.empty())
          {
            state.activity_depth.assign(
              activities.size(),
              std::vector<double>(model.triangulation().n_vertices(), 0.));
            state.activity_volume.assign(activities.size(), {});
          }
        state.history.push_back(Wear::BlockResult());
        state.history.back().activities = activity_results();
        return;
      }
    state = Output::read_checkpoint(directory,
                                    model.triangulation().n_vertices(),
                                    n_steps(),
                                    parameters,
                                    model.world());
    model.geometry().set_vertex_displacements(state.displacement,
                                              state.stiffness_displacement);
    model.geometry().set_wear_depth(state.depth);
    AssertThrow(state.activity_volume.size() ==
                  (parameters.mix.empty() ? 0 : activities.size()),
                ExcInternalError());
    set_step_starts(state.step_starts);
    if (state.stiffness_block > 1)
      for (auto &c : cycles)
        c->setup_solver();
    const bool extrapolated =
      !state.step_starts.empty() &&
      std::all_of(state.step_starts.begin(),
                  state.step_starts.end(),
                  [](const Gait::StepStart &s) { return !s.previous.empty(); });
    model.pcout() << "Resumed from <" << Output::checkpoint_file(directory)
                  << ">: block " << state.block << ", " << state.cycles
                  << " cycles"
                  << (extrapolated ? ", warm starts extrapolated from the "
                                     "poses of the last two blocks" :
                                     "")
                  << std::endl;
  }

  // The wear law over each activity's cycle sliding gives each
  // tibia_contact node's depth (of a mix: weighted by the shares); the
  // block's statistics come from the step reports.
  void
  WearProblem::compute_wear()
  {
    activity_wear.clear();
    for (const auto &c : cycles)
      activity_wear.push_back(
        law->cycle_wear(Wear::CycleSliding(c->get_records())));
    cycle_wear    = Wear::mix_cycle_wear(activity_wear, shares(activities));
    peak_pressure = max_contact_area = 0;
    for (const auto &c : cycles)
      for (const auto &r : c->get_reports())
        {
          state.pose_fallbacks += r.pose_fallbacks;
          state.cut_back_steps += r.sub_steps > 0;
          state.sub_steps += r.sub_steps;
          peak_pressure    = std::max(peak_pressure, r.max_pressure);
          max_contact_area = std::max(max_contact_area, r.contact_area);
        }
    const StepCounts counts = count_steps(cycles);
    state.contact_solves += counts.solves;
    state.newton_iterations += counts.newton;
    state.steps += counts.steps;
    state.converged    = state.converged && counts.converged == counts.steps;
    state.max_pressure = std::max(state.max_pressure, peak_pressure);
    check_load_balance();
    if (state.block == 0)
      report_first_cycle();
  }

  // A converged step out of equilibrium is a result the program cannot
  // stand behind: it is counted and named, loudly, never silent.
  void
  WearProblem::check_load_balance()
  {
    unbalanced_steps.clear();
    unsigned int first = 0;
    std::string  example;
    for (const auto &c : cycles)
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
              state.failed_steps.push_back({state.block + 1,
                                            first + s,
                                            reports[s].pose_residual,
                                            reports[s].contact_converged,
                                            balance});
          }
        first += reports.size();
      }
    if (unbalanced_steps.empty())
      return;
    state.converged = false;
    model.pcout() << "Warning: block " << state.block + 1 << ": "
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
  WearProblem::report_first_cycle()
  {
    const auto  &parameters = model.parameters();
    const auto  &wear       = parameters.wear;
    const double n_cycles   = law->effective_cycles(0, wear.cycles);
    const auto   measures =
      Wear::measure_wear(cycle_wear.depth,
                         model.geometry().worn_surface_measures().area,
                         wear.wear_area_threshold,
                         n_cycles);
    const double mass = parameters.materials.tibia.density * measures.volume;
    const StepCounts counts = count_steps(cycles);
    model.pcout() << "Wear of the first cycle (" << law->description()
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
      model.pcout() << ", contact solves: " << counts.solves
                    << ", Newton iterations per step: "
                    << double(counts.newton) / counts.steps;
    model.pcout() << std::endl << "  load balance (";
    for (unsigned int a = 0; a < cycles.size(); ++a)
      model.pcout() << (a > 0 ? "; " : "")
                    << cycles[a]->get_protocol().load_balance_text();
    model.pcout() << ") in every converged step: "
                  << (unbalanced_steps.empty() ? "yes" : "no") << std::endl;
    report_activities();
    state.first_cycle_mass = mass;
  }

  // The law turns the block of n cycles into a number of cycles at the
  // computed cycle's rate (n, unless the rate depends on the cycle count);
  // the depth grows by that many times the cycle's depth at every
  // tibia_contact node; the node moves inward along the worn surface's
  // nodal normal (Geometry::WornGeometry::worn_surface_measures()) by the
  // new depth, and MeshMotion extends that into the tibia.
  double
  WearProblem::extrapolate()
  {
    const auto &parameters = model.parameters();
    const auto &wear       = parameters.wear;
    // The surface the cycle wore (moving it updates the geometry's).
    const auto          measures = model.geometry().worn_surface_measures();
    const auto         &surface  = model.geometry().worn_surface().nodes();
    const auto         &x        = model.geometry().vertex_positions();
    std::vector<double> medial_lateral;
    for (const auto &node : surface)
      medial_lateral.push_back(x[node.vertex][0]);
    sides = Wear::SurfaceSides(medial_lateral,
                               parameters.gait.medial_direction,
                               measures.area);
    const std::vector<Tensor<1, 3>> displacement =
      model.geometry().vertex_displacements();
    for (;;)
      {
        const double n =
          std::min(state.cycles_per_block, wear.cycles - state.cycles);
        const double effective = law->effective_cycles(state.cycles, n);
        std::vector<Tensor<1, 3>> target = displacement;
        std::vector<double> increment(model.triangulation().n_vertices(), 0.);
        for (unsigned int j = 0; j < surface.size(); ++j)
          {
            const unsigned int v = surface[j].vertex;
            increment[v]         = effective * cycle_wear.depth[j];
            target[v] -= increment[v] * measures.normal[j];
          }
        const auto moved      = motion.extend(target);
        const auto distortion = motion.distortion(moved);
        if (distortion.min_ratio >= wear.distortion_limit)
          {
            model.geometry().set_vertex_displacements(moved);
            model.geometry().add_wear_depth(increment);
            state.volume +=
              effective *
              Wear::measure_wear(cycle_wear.depth, measures.area, 0.).volume;
            for (unsigned int j = 0; j < surface.size(); ++j)
              (sides.medial()[j] ? state.volume_medial :
                                   state.volume_lateral) +=
                effective * cycle_wear.depth[j] * measures.area[j];
            add_activity_wear(effective, measures.area);
            state.cycles += n;
            ++state.block;
            return n;
          }
        const std::string message =
          distortion_message(n, distortion, increment);
        AssertThrow(wear.halve_step_on_distortion && n > 1,
                    ExcInputError(message +
                                  " Reduce Wear/Cycles per extrapolation "
                                  "step, set Halve step on distortion = "
                                  "true, or refine the mesh where the "
                                  "insert wears."));
        state.cycles_per_block = 0.5 * n;
        model.pcout() << "Warning: " << message
                      << " Halving the cycles per block to "
                      << state.cycles_per_block << " and retrying."
                      << std::endl;
      }
  }

  std::string
  WearProblem::distortion_message(const double                n,
                                  const Geometry::Distortion &distortion,
                                  const std::vector<double>  &increment) const
  {
    double depth = 0;
    for (const unsigned int v : distortion.vertices)
      depth = std::max(depth, model.geometry().wear_depth()[v] + increment[v]);
    const Point<3>    &x = distortion.centre;
    std::ostringstream message;
    message << "Block " << state.block + 1 << " (" << n << " cycles from cycle "
            << state.cycles << "): the worn geometry would distort tibia cell "
            << distortion.cell << " (centre " << x[0] << ", " << x[1] << ", "
            << x[2] << "), where the wear depth reaches " << depth
            << " mm: its smallest Jacobian would drop to "
            << distortion.min_ratio
            << " of the unworn cell's, below the Distortion limit of "
            << model.parameters().wear.distortion_limit << ".";
    return message.str();
  }

  void
  WearProblem::finish_block(const double block_wall_time)
  {
    const auto         &parameters = model.parameters();
    const auto         &output     = parameters.output;
    const auto         &surface    = model.geometry().worn_surface().nodes();
    const auto         &depth      = model.geometry().wear_depth();
    std::vector<double> node_depth(surface.size());
    for (unsigned int j = 0; j < surface.size(); ++j)
      node_depth[j] = depth[surface[j].vertex];
    const double threshold = parameters.wear.wear_area_threshold;
    const auto   measures =
      Wear::measure_wear(node_depth, sides.areas(), threshold);
    const auto side = [&](const bool medial, const double volume) {
      return sides.side_result(node_depth,
                               medial,
                               volume,
                               threshold,
                               cycle_wear.cross_shear);
    };
    const double wall_time = state.wall_time + model.wall_time();
    state.history.push_back({state.block,
                             state.cycles,
                             state.volume,
                             parameters.materials.tibia.density * state.volume,
                             measures.max_depth,
                             measures.worn_percent(),
                             peak_pressure,
                             max_contact_area,
                             wall_time,
                             side(true, state.volume_medial),
                             side(false, state.volume_lateral),
                             activity_results()});
    {
      TimerOutput::Scope scope(model.timer(), "output");
      Output::write_wear_history(output.directory,
                                 state.history,
                                 activity_names(),
                                 output.testing,
                                 model.world());
      report_progress(block_wall_time);
      if (output.vtu_interval > 0 && groups.index == 0)
        output_worn_tibia();
    }
    write_checkpoint_if_due();
  }

  void
  WearProblem::report_progress(const double block_wall_time) const
  {
    const unsigned int n_blocks =
      state.block + std::ceil((model.parameters().wear.cycles - state.cycles) /
                                state.cycles_per_block -
                              1e-9);
    progress.block(state.block,
                   n_blocks,
                   state.cycles,
                   state.history.back(),
                   block_wall_time,
                   model.parameters().output.testing);
  }

  // The tibia in its worn geometry with the accumulated depth, the wear
  // rate, the slip of the block's cycle, the pressure at its largest load
  // and the law's own fields, per vertex.
  void
  WearProblem::output_worn_tibia()
  {
    const auto &output = model.parameters().output;
    if (!worn_series)
      worn_series = std::make_unique<Output::VtuSeries>(output.directory,
                                                        "worn",
                                                        groups.communicator);
    const auto        &surface    = model.geometry().worn_surface().nodes();
    const unsigned int n_vertices = model.triangulation().n_vertices();
    const auto        &peak       = cycle.get_records()[cycle.peak_load_step()];
    const auto         per_vertex = [&](const auto &node_value) {
      std::vector<double> values(n_vertices, 0.);
      for (unsigned int j = 0; j < surface.size(); ++j)
        values[surface[j].vertex] = node_value(j);
      return values;
    };
    Output::WornTibiaFields fields = {
      {"wear_depth_mm", model.geometry().wear_depth()},
      {"wear_rate_um_per_Mcycles", per_vertex([&](const unsigned int j) {
         return 1e9 * cycle_wear.depth[j];
       })},
      {"peak_load_pressure_MPa",
       per_vertex([&](const unsigned int j) { return peak.pressure[j]; })},
      {"cycle_slip_mm",
       per_vertex([&](const unsigned int j) { return cycle_wear.slip[j]; })},
      {"cross_shear", per_vertex([&](const unsigned int j) {
         return cycle_wear.cross_shear[j].ratio;
       })}};
    for (unsigned int a = 0; a < state.activity_depth.size(); ++a)
      fields.emplace_back("wear_depth_mm_" + activities[a].slug,
                          state.activity_depth[a]);
    for (const auto &[name, values] : cycle_wear.fields)
      fields.emplace_back(name,
                          per_vertex(
                            [&, &values = values](const unsigned int j) {
                              return values[j];
                            }));
    Output::write_worn_tibia(model.geometry(),
                             fields,
                             *worn_series,
                             state.block,
                             state.cycles);
  }

  void
  WearProblem::write_checkpoint_if_due()
  {
    const auto &output = model.parameters().output;
    const bool  done   = state.cycles >= model.parameters().wear.cycles;
    if (output.checkpoint_interval == 0 ||
        (state.block % output.checkpoint_interval != 0 && !done))
      return;
    write_checkpoint();
  }

  void
  WearProblem::stop(const std::string                  &signal,
                    const std::vector<Gait::StepStart> &starts)
  {
    const std::string file = model.parameters().parameter_file;
    std::string       kept =
      "before block 1 was done: there is nothing to continue; run <" + file +
      "> again";
    if (state.block > 0)
      {
        set_step_starts(starts);
        write_checkpoint();
        kept = "the checkpoint <" +
               Output::checkpoint_file(model.parameters().output.directory) +
               "> holds block " + std::to_string(state.block) + " (" +
               format_number(state.cycles, 6) + " cycles); tkr-wear --resume " +
               file + " continues the run";
      }
    AssertThrow(false,
                ExcStopped("Stopped by " + signal + " during block " +
                           std::to_string(state.block + 1) + ": " + kept +
                           "."));
  }

  void
  WearProblem::write_checkpoint()
  {
    const auto        &output = model.parameters().output;
    TimerOutput::Scope scope(model.timer(), "checkpoint");
    state.displacement           = model.geometry().vertex_displacements();
    state.stiffness_displacement = model.geometry().vertex_displacements(true);
    state.depth                  = model.geometry().wear_depth();
    state.step_starts            = step_starts();
    Output::write_checkpoint(output.directory,
                             state,
                             model.parameters(),
                             model.world());
    model.pcout() << "  checkpoint written after block " << state.block
                  << std::endl;
  }

  Wear::RunResult
  WearProblem::result() const
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
          result.protocol_results.emplace_back(parameters.mix.empty() ?
                                                 name :
                                                 "activity_" +
                                                   activities[a].slug + "_" +
                                                   name,
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

  void
  WearProblem::output_results()
  {
    const auto &parameters = model.parameters();
    const auto &output     = parameters.output;
    const bool  mix        = !parameters.mix.empty();
    for (unsigned int a = 0; a < cycles.size(); ++a)
      {
        Output::write_steps_csv(output.directory,
                                cycles[a]->get_reports(),
                                cycles[a]->get_protocol(),
                                model.world(),
                                mix ? activities[a].slug : "");
        if (output.vtu_interval > 0 && a < activity_wear.size())
          cycles[a]->output_steps(activity_wear[a]);
      }
    const auto ratios = [](const Wear::CycleWear &wear) {
      std::vector<double> ratio;
      for (const auto &cs : wear.cross_shear)
        ratio.push_back(cs.ratio);
      return ratio;
    };
    Output::write_wear_map(output.directory,
                           model.geometry().worn_surface(),
                           model.geometry(),
                           ratios(cycle_wear),
                           model.world());
    for (unsigned int a = 0; mix && a < activities.size(); ++a)
      Output::write_wear_map(output.directory,
                             model.geometry().worn_surface(),
                             model.geometry(),
                             a < activity_wear.size() ?
                               ratios(activity_wear[a]) :
                               std::vector<double>(),
                             model.world(),
                             activities[a].slug,
                             &state.activity_depth[a]);
    Output::write_run_result(result(), model.summary());
    if (output.plots)
      {
        // The summary is written by finish(); the plots read it.
        model.summary().write(output.directory, model.world());
        const std::string error =
          Output::make_plots(output.directory,
                             output.measured_mass_loss_file,
                             model.world());
        if (!error.empty())
          model.pcout() << "Warning: no plots: " << error << std::endl;
      }
  }

  std::function<void(MPI_Comm)> WearProblem::start_hook;

  bool
  WearProblem::run()
  {
    const auto &parameters = model.parameters();
    const auto &wear       = parameters.wear;
    model.start("knee-simulator wear test");
    if (start_hook)
      start_hook(model.world());
    AssertThrow(parameters.mesh.fe_degree == 1,
                ExcInputError(
                  "Problem = wear needs Finite element degree = 1."));
    model.make_grid();
    model.distribute_dofs();
    for (unsigned int a = 0; a < cycles.size(); ++a)
      cycles[a]->setup(a == 0);
    motion.setup();
    start();
    model.pcout() << "Extrapolation: " << wear.cycles << " cycles in blocks of "
                  << state.cycles_per_block << ", stiffness updated "
                  << (wear.stiffness_update_interval == 0 ?
                        std::string("never") :
                        "every " +
                          std::to_string(wear.stiffness_update_interval) +
                          " block(s)")
                  << ", warm starts " << (wear.warm_start ? "on" : "off")
                  << std::endl;
    while (state.cycles < wear.cycles)
      {
        Timer              block_timer;
        const unsigned int block = state.block + 1;
        const unsigned int R     = wear.stiffness_update_interval;
        if (block > 1 && R > 0 && (block - 1) % R == 0 &&
            state.stiffness_block != block)
          {
            model.geometry().update_stiffness_geometry();
            for (auto &c : cycles)
              c->setup_solver();
            state.stiffness_block = block;
          }
        const bool first = (block == 1);
        const bool last  = state.cycles + state.cycles_per_block >= wear.cycles;
        solve_cycles(first, last);
        {
          TimerOutput::Scope scope(model.timer(), "wear");
          compute_wear();
          extrapolate();
        }
        finish_block(block_timer.wall_time());
      }
    unsigned int window_misses = 0;
    for (const auto &c : cycles)
      window_misses += groups.is_group_root ? c->n_window_misses() : 0u;
    if (parameters.contact_solver.coupling_window > 0 &&
        !parameters.output.testing)
      model.pcout() << "Coupling window: "
                    << Utilities::MPI::sum(window_misses, model.world())
                    << " contact solves repeated on the whole search distance"
                    << std::endl;
    output_results();
    const bool converged = model.finish(state.converged);
    if (!converged)
      progress.failure(state.failed_steps);
    return converged;
  }
} // namespace TKR::Problems
