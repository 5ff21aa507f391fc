// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#include <deal.II/base/timer.h>

#include <tkr/base/exceptions.h>
#include <tkr/output/checkpoint.h>
#include <tkr/output/wear_output.h>
#include <tkr/problems/wear_problem.h>
#include <tkr/wear/sliding.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <iomanip>
#include <limits>
#include <sstream>

namespace TKR::Problems
{
  using namespace dealii;

  WearProblem::WearProblem(const Parameters::AllParameters &parameters,
                           const MPI_Comm                   mpi_communicator,
                           const bool                       resume)
    : resume(resume)
    , groups(mpi_communicator, parameters.gait.step_groups)
    , model(parameters, mpi_communicator, groups.communicator)
    , cycle(model, groups)
    , motion(model.geometry(), groups.communicator, model.timer())
    , law(Wear::create_wear_law(parameters.wear))
  {}

  void
  WearProblem::start()
  {
    const auto &parameters = model.parameters();
    const auto &directory  = parameters.output.directory;
    if (!resume)
      {
        state.cycles_per_block = parameters.wear.cycles_per_extrapolation_step;
        state.history.push_back(Wear::BlockResult());
        return;
      }
    state = Output::read_checkpoint(directory,
                                    model.triangulation().n_vertices(),
                                    cycle.n_steps(),
                                    parameters,
                                    model.world());
    model.geometry().set_vertex_displacements(state.displacement,
                                              state.stiffness_displacement);
    model.geometry().set_wear_depth(state.depth);
    cycle.set_step_starts(state.step_starts);
    if (state.stiffness_block > 1)
      cycle.setup_solver();
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

  // The wear law over the cycle's sliding gives each tibia_contact node's
  // depth; the block's statistics come from the step reports.
  void
  WearProblem::compute_wear()
  {
    const auto              &reports = cycle.get_reports();
    const Wear::CycleSliding sliding(cycle.get_records());
    cycle_wear    = law->cycle_wear(sliding);
    cross_shear   = Wear::cycle_cross_shear(sliding);
    peak_pressure = max_contact_area = 0;
    unsigned int n_newton = 0, n_solves = 0, n_converged = 0;
    for (const auto &r : reports)
      {
        n_newton += r.newton_iterations;
        n_solves += r.pose_updates + 1;
        n_converged += r.converged;
        state.pose_fallbacks += r.pose_fallbacks;
        peak_pressure    = std::max(peak_pressure, r.max_pressure);
        max_contact_area = std::max(max_contact_area, r.contact_area);
      }
    state.contact_solves += n_solves;
    state.newton_iterations += n_newton;
    state.steps += reports.size();
    state.converged    = state.converged && n_converged == reports.size();
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
    const auto &protocol = cycle.get_protocol();
    const auto &reports  = cycle.get_reports();
    unbalanced_steps.clear();
    for (unsigned int s = 0; s < reports.size(); ++s)
      {
        const double balance    = protocol.load_balance(reports[s]);
        const bool   unbalanced = reports[s].converged && !(balance <= 1.);
        if (unbalanced)
          unbalanced_steps.push_back(s);
        if (!reports[s].converged || unbalanced)
          state.failed_steps.push_back({state.block + 1,
                                        s,
                                        reports[s].pose_residual,
                                        reports[s].contact_converged,
                                        balance});
      }
    if (unbalanced_steps.empty())
      return;
    state.converged = false;
    model.pcout() << "Warning: block " << state.block + 1 << ": "
                  << unbalanced_steps.size()
                  << " converged step(s) fail the load balance ("
                  << protocol.load_balance_text() << "), e.g. step "
                  << unbalanced_steps[0] << " by "
                  << protocol.load_balance(reports[unbalanced_steps[0]])
                  << " times what the tolerances allow. The run will exit "
                     "with 1."
                  << std::endl;
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
    const auto  &reports    = cycle.get_reports();
    const double cycles     = law->effective_cycles(0, wear.cycles);
    const auto   measures =
      Wear::measure_wear(cycle_wear.depth,
                         model.geometry().worn_surface_measures().area,
                         wear.wear_area_threshold,
                         cycles);
    const double mass = parameters.materials.tibia.density * measures.volume;
    unsigned int n_newton = 0, n_solves = 0, n_converged = 0;
    for (const auto &r : reports)
      {
        n_newton += r.newton_iterations;
        n_solves += r.pose_updates + 1;
        n_converged += r.converged;
      }
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
                  << " cycles without geometry update: " << mass * cycles
                  << " mg" << std::endl
                  << "  steps: " << reports.size()
                  << ", converged: " << n_converged;
    if (!parameters.output.testing)
      model.pcout() << ", contact solves: " << n_solves
                    << ", Newton iterations per step: "
                    << double(n_newton) / reports.size();
    model.pcout() << std::endl
                  << "  load balance ("
                  << cycle.get_protocol().load_balance_text()
                  << ") in every converged step: "
                  << (unbalanced_steps.empty() ? "yes" : "no") << std::endl;
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
    const auto  measures = model.geometry().worn_surface_measures();
    const auto &surface  = model.geometry().worn_surface().nodes();
    block_areas          = measures.area;
    block_medial         = medial_nodes();
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
              (block_medial[j] ? state.volume_medial : state.volume_lateral) +=
                effective * cycle_wear.depth[j] * measures.area[j];
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

  double
  WearProblem::mean_cross_shear(const std::vector<bool> &select,
                                const bool               value) const
  {
    double weighted = 0, weight = 0;
    if (block_areas.size() != cross_shear.size())
      return 0.;
    for (unsigned int j = 0; j < cross_shear.size(); ++j)
      {
        if (!select.empty() && select[j] != value)
          continue;
        const double w = cross_shear[j].work * block_areas[j];
        weighted += w * cross_shear[j].ratio;
        weight += w;
      }
    return weight > 0 ? weighted / weight : 0.;
  }

  std::vector<bool>
  WearProblem::medial_nodes() const
  {
    const auto &surface = model.geometry().worn_surface().nodes();
    const auto &x       = model.geometry().vertex_positions();
    double      lo = std::numeric_limits<double>::max(), hi = -lo;
    for (const auto &node : surface)
      {
        lo = std::min(lo, x[node.vertex][0]);
        hi = std::max(hi, x[node.vertex][0]);
      }
    std::vector<bool> medial;
    for (const auto &node : surface)
      medial.push_back((x[node.vertex][0] - 0.5 * (lo + hi)) *
                         model.parameters().gait.medial_direction >
                       0);
    return medial;
  }

  Wear::SideResult
  WearProblem::side_result(const std::vector<double> &node_depth,
                           const bool                 on_medial,
                           const double               volume) const
  {
    std::vector<double> depth = node_depth;
    for (unsigned int j = 0; j < depth.size(); ++j)
      if (block_medial[j] != on_medial)
        depth[j] = 0;
    const auto measures =
      Wear::measure_wear(depth,
                         block_areas,
                         model.parameters().wear.wear_area_threshold);
    return {volume,
            measures.max_depth,
            measures.worn_percent(),
            mean_cross_shear(block_medial, on_medial)};
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
    const auto measures =
      Wear::measure_wear(node_depth,
                         block_areas,
                         parameters.wear.wear_area_threshold);
    const double wall_time = state.wall_time + model.wall_time();
    state.history.push_back(
      {state.block,
       state.cycles,
       state.volume,
       parameters.materials.tibia.density * state.volume,
       measures.max_depth,
       measures.worn_percent(),
       peak_pressure,
       max_contact_area,
       wall_time,
       side_result(node_depth, true, state.volume_medial),
       side_result(node_depth, false, state.volume_lateral)});
    Output::write_wear_history(output.directory,
                               state.history,
                               output.testing,
                               model.world());
    report_progress(block_wall_time);
    if (output.vtu_interval > 0 && groups.index == 0)
      output_worn_tibia();
    write_checkpoint_if_due();
  }

  void
  WearProblem::report_progress(const double block_wall_time) const
  {
    const auto        &parameters = model.parameters();
    const auto        &last       = state.history.back();
    const unsigned int n_blocks =
      state.block + std::ceil((parameters.wear.cycles - state.cycles) /
                                state.cycles_per_block -
                              1e-9);
    std::ostringstream line;
    line << "Block " << std::setw(4) << state.block << "/" << n_blocks << ": "
         << std::setw(9) << state.cycles << " cycles, mass loss " << last.mass
         << " mg, max depth " << 1e3 * last.max_depth << " um, wear area "
         << last.wear_area_percent << " %";
    if (!parameters.output.testing)
      {
        const double remaining = (n_blocks - state.block) * block_wall_time;
        line << ", " << std::fixed << std::setprecision(1) << block_wall_time
             << " s/block, ETA " << std::setprecision(0) << remaining / 60.
             << " min";
      }
    say_progress(line.str());
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
      {"cross_shear",
       per_vertex([&](const unsigned int j) { return cross_shear[j].ratio; })}};
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
    TimerOutput::Scope scope(model.timer(), "checkpoint");
    state.displacement           = model.geometry().vertex_displacements();
    state.stiffness_displacement = model.geometry().vertex_displacements(true);
    state.depth                  = model.geometry().wear_depth();
    state.step_starts            = cycle.get_step_starts();
    Output::write_checkpoint(output.directory,
                             state,
                             model.parameters(),
                             model.world());
    model.pcout() << "  checkpoint written after block " << state.block
                  << std::endl;
  }

  void
  WearProblem::output_results()
  {
    const auto &parameters = model.parameters();
    const auto &output     = parameters.output;
    Output::write_steps_csv(output.directory,
                            cycle.get_reports(),
                            cycle.get_protocol(),
                            model.world());
    if (output.vtu_interval > 0)
      cycle.output_steps(cycle_wear);
    std::vector<double> ratio;
    for (const auto &cs : cross_shear)
      ratio.push_back(cs.ratio);
    Output::write_wear_map(output.directory,
                           model.geometry().worn_surface(),
                           model.geometry(),
                           ratio,
                           model.world());

    const auto &last    = state.history.back();
    auto       &summary = model.summary();
    summary.set("cycles", state.cycles);
    summary.set("blocks", state.block);
    summary.set("mass_loss_mg", last.mass);
    summary.set("volume_loss_mm3", last.volume);
    summary.set("max_wear_depth_mm", last.max_depth);
    summary.set("wear_area_percent", last.wear_area_percent);
    summary.set("wear_area_threshold_mm", parameters.wear.wear_area_threshold);
    if (!cross_shear.empty()) // a resumed run computes a cycle
      summary.set("mean_cross_shear", mean_cross_shear());
    for (const auto &[side, result] :
         {std::pair{"medial", last.medial}, std::pair{"lateral", last.lateral}})
      {
        const std::string prefix(side);
        summary.set(prefix + "_volume_loss_mm3", result.volume);
        summary.set(prefix + "_mass_loss_mg",
                    parameters.materials.tibia.density * result.volume);
        summary.set(prefix + "_max_wear_depth_mm", result.max_depth);
        summary.set(prefix + "_wear_area_percent", result.wear_area_percent);
        summary.set(prefix + "_mean_cross_shear", result.mean_cross_shear);
      }
    summary.set("max_pressure_MPa", state.max_pressure);
    summary.set("steps", static_cast<unsigned long long>(state.steps));
    summary.set("contact_solves",
                static_cast<unsigned long long>(state.contact_solves));
    summary.set("mean_newton_iterations",
                double(state.newton_iterations) / state.contact_solves);
    summary.set("pose_fallbacks",
                static_cast<unsigned long long>(state.pose_fallbacks));
    summary.set("cycles_per_extrapolation_step", state.cycles_per_block);
    summary.set("first_cycle_mass_loss_mg_per_million_cycles",
                1e6 * state.first_cycle_mass);
    summary.set("linear_extrapolation_mass_loss_mg",
                state.first_cycle_mass *
                  law->effective_cycles(0, parameters.wear.cycles));
    if (const auto &run_in = law->get_run_in(); !run_in.empty())
      {
        // The run-in factor's points, for mass_loss.png (scripts/plot-wear).
        std::vector<Output::Summary::Record> points;
        for (const auto &[cycles, factor] : run_in.points())
          points.push_back({{"cycles", cycles}, {"factor", factor}});
        summary.set("run_in_factor", points);
      }
    summary.set("stiffness_update_interval",
                parameters.wear.stiffness_update_interval);
    summary.set("step_groups", groups.n_groups);
    std::vector<Output::Summary::Record> failed;
    for (const auto &f : state.failed_steps)
      failed.push_back({{"block", f.block},
                        {"step", f.step},
                        {"pose_residual_mm", f.pose_residual},
                        {"contact_converged", f.contact_converged ? 1. : 0.},
                        {"load_balance", f.load_balance}});
    summary.set("unconverged_steps", failed);
    if (output.plots)
      {
        // The summary is written by finish(); the plots read it.
        summary.write(output.directory, model.world());
        const std::string error =
          Output::make_plots(output.directory,
                             output.measured_mass_loss_file,
                             model.world());
        if (!error.empty())
          model.pcout() << "Warning: no plots: " << error << std::endl;
      }
  }

  bool
  WearProblem::run()
  {
    const auto &parameters = model.parameters();
    const auto &wear       = parameters.wear;
    model.start("knee-simulator wear test");
#ifdef TKR_TEST_HOOKS
    // Test only (cli/one_rank_error, scripts/study; CMake option
    // TKR_TEST_HOOKS): an input error raised on one rank of the run alone,
    // as a rank-local failure would be, while the others go on into the
    // set-up.
    if (const char *rank = std::getenv("TKR_TEST_ERROR_ON_RANK"))
      AssertThrow(std::to_string(
                    Utilities::MPI::this_mpi_process(model.world())) != rank,
                  ExcInputError("TKR_TEST_ERROR_ON_RANK: an error raised on "
                                "rank " +
                                std::string(rank) + " alone."));
#endif
    AssertThrow(parameters.mesh.fe_degree == 1,
                ExcInputError(
                  "Problem = wear needs Finite element degree = 1."));
    model.make_grid();
    model.distribute_dofs();
    cycle.setup();
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
            cycle.setup_solver();
            state.stiffness_block = block;
          }
        const bool first = (block == 1);
        const bool last  = state.cycles + state.cycles_per_block >= wear.cycles;
        if (first)
          model.pcout() << "Gait cycle, " << cycle.n_steps()
                        << " steps:" << std::endl;
        cycle.solve(first, last, first);
        compute_wear();
        extrapolate();
        finish_block(block_timer.wall_time());
      }
    if (parameters.contact_solver.coupling_window > 0 &&
        !parameters.output.testing)
      model.pcout() << "Coupling window: "
                    << Utilities::MPI::sum(groups.is_group_root ?
                                             cycle.n_window_misses() :
                                             0u,
                                           model.world())
                    << " contact solves repeated on the whole search distance"
                    << std::endl;
    output_results();
    const bool converged = model.finish(state.converged);
    if (!converged)
      report_failure();
    return converged;
  }

  // The last line of the screen and of progress.log.
  void
  WearProblem::report_failure() const
  {
    std::ostringstream line;
    line << "tkr-wear: " << state.failed_steps.size()
         << " gait step(s) over the blocks did not converge or failed their "
            "load balance (summary.json lists them as unconverged_steps, "
            "the first in block "
         << (state.failed_steps.empty() ? 0 : state.failed_steps[0].block)
         << ", step "
         << (state.failed_steps.empty() ? 0 : state.failed_steps[0].step)
         << "): these results are not converged, exit code 1.";
    say_progress(line.str());
  }

  void
  WearProblem::say_progress(const std::string &line) const
  {
    model.pcout() << line << std::endl;
    if (Utilities::MPI::this_mpi_process(model.world()) == 0)
      {
        std::ofstream log(model.parameters().output.directory + "/progress.log",
                          std::ios::app);
        log << line << std::endl;
      }
  }
} // namespace TKR::Problems
