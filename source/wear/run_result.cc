// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#include <tkr/base/exceptions.h>
#include <tkr/wear/run_result.h>

namespace TKR::Wear
{
  std::vector<std::pair<std::string, double>>
  RunResult::named_values() const
  {
    const BlockResult last = history.empty() ? BlockResult() : history.back();
    std::vector<std::pair<std::string, double>> values = {
      {"cycles", cycles},
      {"blocks", blocks},
      {"mass_loss_mg", last.mass},
      {"volume_loss_mm3", last.volume},
      {"max_wear_depth_mm", last.max_depth},
      {"wear_area_percent", last.wear_area_percent},
      {"wear_area_threshold_mm", wear_area_threshold}};
    if (has_cross_shear)
      values.emplace_back("mean_cross_shear", mean_cross_shear);
    for (const auto &[side, result] :
         {std::pair{"medial", last.medial}, std::pair{"lateral", last.lateral}})
      {
        const std::string prefix(side);
        values.emplace_back(prefix + "_volume_loss_mm3", result.volume);
        values.emplace_back(prefix + "_mass_loss_mg", density * result.volume);
        values.emplace_back(prefix + "_max_wear_depth_mm", result.max_depth);
        values.emplace_back(prefix + "_wear_area_percent",
                            result.wear_area_percent);
        values.emplace_back(prefix + "_mean_cross_shear",
                            result.mean_cross_shear);
      }
    for (unsigned int a = 0;
         a < activity_names.size() && a < last.activities.size();
         ++a)
      {
        const std::string     prefix = "activity_" + activity_names[a] + "_";
        const ActivityResult &result = last.activities[a];
        values.emplace_back(prefix + "share", activity_shares[a]);
        values.emplace_back(prefix + "mass_loss_mg", result.mass);
        values.emplace_back(prefix + "volume_loss_mm3", result.volume);
        values.emplace_back(prefix + "max_wear_depth_mm", result.max_depth);
        values.emplace_back(prefix + "medial_mass_loss_mg",
                            density * result.medial_volume);
        values.emplace_back(prefix + "lateral_mass_loss_mg",
                            density * result.lateral_volume);
      }
    values.insert(values.end(),
                  protocol_results.begin(),
                  protocol_results.end());
    values.insert(
      values.end(),
      {{"max_pressure_MPa", max_pressure},
       {"steps", double(steps)},
       {"contact_solves", double(contact_solves)},
       {"mean_newton_iterations", double(newton_iterations) / contact_solves},
       {"pose_fallbacks", double(pose_fallbacks)},
       {"cut_back_steps", double(cut_back_steps)},
       {"sub_steps", double(sub_steps)},
       {"cycles_per_extrapolation_step", cycles_per_block},
       {"first_cycle_mass_loss_mg_per_million_cycles", 1e6 * first_cycle_mass},
       {"linear_extrapolation_mass_loss_mg", linear_extrapolation_mass},
       {"stiffness_update_interval", stiffness_update_interval},
       {"step_groups", step_groups}});
    return values;
  }

  double
  RunResult::value(const std::string &key) const
  {
    std::string known;
    for (const auto &[name, value] : named_values())
      {
        if (name == key)
          return value;
        known += (known.empty() ? "" : ", ") + name;
      }
    AssertThrow(false,
                ExcInputError("A wear run has no result named <" + key +
                              ">; its results are: " + known + "."));
    return 0.;
  }
} // namespace TKR::Wear
