// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.
//
// WearFiles: the files of a wear run, per block and at its end.

#include <deal.II/base/timer.h>

#include <tkr/output/wear_output.h>
#include <tkr/problems/wear_run.h>

namespace TKR::Problems
{
  using namespace dealii;

  WearFiles::WearFiles(WearRun &run)
    : run(run)
  {}

  void
  WearFiles::block(const WearReport &report)
  {
    const auto         &parameters = run.model.parameters();
    const auto         &output     = parameters.output;
    const auto         &surface = run.model.geometry().worn_surface().nodes();
    const auto         &depth   = run.model.geometry().wear_depth();
    std::vector<double> node_depth(surface.size());
    for (unsigned int j = 0; j < surface.size(); ++j)
      node_depth[j] = depth[surface[j].vertex];
    const double threshold = parameters.wear.wear_area_threshold;
    const auto   measures =
      Wear::measure_wear(node_depth, run.sides.areas(), threshold);
    const auto side = [&](const bool medial, const double volume) {
      return run.sides.side_result(node_depth,
                                   medial,
                                   volume,
                                   threshold,
                                   run.cycle_wear.cross_shear);
    };
    const double wall_time = run.state.wall_time + run.model.wall_time();
    run.state.history.push_back(
      {run.state.block,
       run.state.cycles,
       run.state.volume,
       parameters.materials.tibia.density * run.state.volume,
       measures.max_depth,
       measures.worn_percent(),
       report.peak_pressure,
       report.max_contact_area,
       wall_time,
       side(true, run.state.volume_medial),
       side(false, run.state.volume_lateral),
       run.activity_results()});
    {
      TimerOutput::Scope scope(run.model.timer(), "output");
      Output::write_wear_history(output.directory,
                                 run.state.history,
                                 run.activity_names(),
                                 output.testing,
                                 run.model.world());
      // The worn tibia every Output/Worn VTU interval blocks and at the end.
      const unsigned int every = output.worn_vtu_interval;
      if (every > 0 && (run.state.block % every == 0 ||
                        run.state.cycles >= parameters.wear.cycles))
        worn_tibia();
    }
  }

  // The tibia in its worn geometry with the accumulated depth, the wear
  // rate, the slip of the block's cycle, the pressure at its largest load
  // and the law's own fields, per vertex.
  void
  WearFiles::worn_tibia()
  {
    const auto &output = run.model.parameters().output;
    if (!worn_series)
      worn_series = std::make_unique<Output::VtuSeries>(output.directory,
                                                        "worn",
                                                        run.model.world());
    const auto        &surface    = run.model.geometry().worn_surface().nodes();
    const unsigned int n_vertices = run.model.triangulation().n_vertices();
    const auto &peak = run.cycle.get_records()[run.cycle.peak_load_step()];
    const auto  per_vertex = [&](const auto &node_value) {
      std::vector<double> values(n_vertices, 0.);
      for (unsigned int j = 0; j < surface.size(); ++j)
        values[surface[j].vertex] = node_value(j);
      return values;
    };
    Output::WornTibiaFields fields = {
      {"wear_depth_mm", run.model.geometry().wear_depth()},
      {"wear_rate_um_per_Mcycles", per_vertex([&](const unsigned int j) {
         return 1e9 * run.cycle_wear.depth[j];
       })},
      {"peak_load_pressure_MPa",
       per_vertex([&](const unsigned int j) { return peak.pressure[j]; })},
      {"cycle_slip_mm", per_vertex([&](const unsigned int j) {
         return run.cycle_wear.slip[j];
       })},
      {"cross_shear", per_vertex([&](const unsigned int j) {
         return run.cycle_wear.cross_shear[j].ratio;
       })}};
    for (unsigned int a = 0; a < run.state.activity_depth.size(); ++a)
      fields.emplace_back("wear_depth_mm_" + run.activities[a].slug,
                          run.state.activity_depth[a]);
    for (const auto &[name, values] : run.cycle_wear.fields)
      fields.emplace_back(name,
                          per_vertex(
                            [&, &values = values](const unsigned int j) {
                              return values[j];
                            }));
    // (each step group a share of the cells)
    Output::write_worn_tibia(run.groups.index,
                             run.groups.n_groups,
                             run.model.geometry(),
                             fields,
                             *worn_series,
                             run.state.block,
                             run.state.cycles);
  }

  void
  WearFiles::finish()
  {
    const auto &parameters = run.model.parameters();
    const auto &output     = parameters.output;
    const bool  mix        = run.is_mix();
    for (unsigned int a = 0; a < run.cycles.size(); ++a)
      {
        Output::write_steps_csv(output.directory,
                                run.cycles[a]->get_reports(),
                                run.cycles[a]->get_protocol(),
                                run.model.world(),
                                mix ? run.activities[a].slug : "");
        if (output.vtu_interval > 0 && a < run.activity_wear.size())
          run.cycles[a]->output_steps(run.activity_wear[a]);
      }
    const auto ratios = [](const Wear::CycleWear &wear) {
      std::vector<double> ratio;
      for (const auto &cs : wear.cross_shear)
        ratio.push_back(cs.ratio);
      return ratio;
    };
    Output::write_wear_map(output.directory,
                           run.model.geometry().worn_surface(),
                           run.model.geometry(),
                           ratios(run.cycle_wear),
                           run.model.world());
    for (unsigned int a = 0; mix && a < run.activities.size(); ++a)
      Output::write_wear_map(output.directory,
                             run.model.geometry().worn_surface(),
                             run.model.geometry(),
                             a < run.activity_wear.size() ?
                               ratios(run.activity_wear[a]) :
                               std::vector<double>(),
                             run.model.world(),
                             run.activities[a].slug,
                             &run.state.activity_depth[a]);
    Output::write_run_result(run.result(), run.model.summary());
    if (output.plots)
      {
        // The summary is written by finish(); the plots read it.
        run.model.summary().write(output.directory, run.model.world());
        const std::string error =
          Output::make_plots(output.directory,
                             output.measured_mass_loss_file,
                             run.model.world());
        if (!error.empty())
          run.model.pcout() << "Warning: no plots: " << error << std::endl;
      }
  }
} // namespace TKR::Problems
