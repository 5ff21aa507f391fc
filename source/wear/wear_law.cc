// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#include <tkr/base/exceptions.h>
#include <tkr/wear/wear_law.h>

#include <algorithm>
#include <filesystem>

namespace TKR::Wear
{
  void
  WearLaw::analyse_cycle(const CycleSliding &, const std::vector<CrossShear> &)
  {}

  std::string
  WearLaw::description() const
  {
    return law_description() +
           (run_in.empty() ?
              "" :
              ", run-in factor of <" +
                std::filesystem::path(run_in_file).filename().string() + ">");
  }

  double
  WearLaw::effective_cycles(const double first_cycle,
                            const double n_cycles) const
  {
    return run_in.empty() ?
             n_cycles :
             run_in.integral(first_cycle, first_cycle + n_cycles);
  }

  void
  WearLaw::set_run_in(const PiecewiseLinear &factor, const std::string &file)
  {
    run_in      = factor;
    run_in_file = file;
  }

  NodeFields
  WearLaw::node_fields() const
  {
    return {};
  }

  CycleWear
  WearLaw::cycle_wear(const CycleSliding &sliding)
  {
    CycleWear wear;
    wear.cross_shear = cycle_cross_shear(sliding, cross_shear_definition);
    analyse_cycle(sliding, wear.cross_shear);
    const unsigned int n_nodes = sliding.n_nodes();
    wear.depth.assign(n_nodes, 0.);
    wear.slip.assign(n_nodes, 0.);
    for (unsigned int i = 0; i < sliding.n_intervals(); ++i)
      {
        std::vector<double> depth(n_nodes), slip(n_nodes);
        for (unsigned int j = 0; j < n_nodes; ++j)
          {
            depth[j] = interval_depth(sliding, i, j);
            slip[j]  = sliding.interval(i).slip_distance(j);
            wear.depth[j] += depth[j];
            wear.slip[j] += slip[j];
          }
        wear.interval_depth.push_back(std::move(depth));
        wear.interval_slip.push_back(std::move(slip));
      }
    wear.fields = node_fields();
    return wear;
  }

  std::unique_ptr<WearLaw>
  create_wear_law(const Parameters::Wear &parameters)
  {
    WearLaws::kind().check(parameters.law, parameters.laws);
    std::unique_ptr<WearLaw> law =
      WearLaws::get(parameters.law)
        .create(parameters, parameters.laws.of(parameters.law));
    if (!parameters.run_in_file.empty())
      law->set_run_in(read_run_in(parameters.run_in_file),
                      parameters.run_in_file);
    law->set_cross_shear_definition(
      cross_shear_definition(parameters.cross_shear_definition));
    return law;
  }

  WearMeasures
  measure_wear(const std::vector<double> &depth,
               const std::vector<double> &nodal_area,
               const double               threshold,
               const double               depth_scale)
  {
    AssertDimension(depth.size(), nodal_area.size());
    WearMeasures measures;
    for (unsigned int j = 0; j < depth.size(); ++j)
      {
        measures.volume += depth[j] * nodal_area[j];
        measures.max_depth = std::max(measures.max_depth, depth[j]);
        measures.area += nodal_area[j];
        if (depth[j] * depth_scale > threshold)
          measures.worn_area += nodal_area[j];
      }
    return measures;
  }
} // namespace TKR::Wear
