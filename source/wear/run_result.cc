// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.
//
// The results of a wear run: one table per record, each line a result's
// name, type, unit, meaning and how it is read. summary.json's keys,
// wear_history.csv's columns, the checkpoint's history and the schema
// (ResultSchema, `tkr-wear --print-schema`) all come from these tables: a
// new result is one line here.

#include <tkr/wear/run_result.h>

#include <optional>

namespace TKR::Wear
{
  namespace
  {
    const std::vector<std::string> wear = {"wear"};

    /** A scalar of summary.json: its field and how a run's value is read
     *  (none: the key is absent). */
    template <typename... Arguments>
    struct Value
    {
      ResultField field;
      std::function<std::optional<double>(const RunResult &, Arguments...)>
        value;
    };

    const BlockResult &
    last(const RunResult &r)
    {
      static const BlockResult none;
      return r.history.empty() ? none : r.history.back();
    }

    // summary.json: the run's end.
    const std::vector<Value<>> &
    run_values()
    {
      // clang-format off
      static const std::vector<Value<>> table = {
        {{"cycles", "number", "cycles", wear, "load cycles at the end of the run (`Wear/Cycles`)"},
         [](const RunResult &r) { return r.cycles; }},
        {{"blocks", "integer", "-", wear, "extrapolation blocks run (doc/wear.md)"},
         [](const RunResult &r) { return r.blocks; }},
        {{"mass_loss_mg", "number", "mg", wear, "the insert's mass loss: worn volume times the insert's density", {}, false, 1},
         [](const RunResult &r) { return last(r).mass; }},
        {{"volume_loss_mm3", "number", "mm^3", wear, "the insert's worn volume", {}, false, 2},
         [](const RunResult &r) { return last(r).volume; }},
        {{"max_wear_depth_mm", "number", "mm", wear, "the largest accumulated wear depth at a node of `tibia_contact`", {}, false, 4},
         [](const RunResult &r) { return last(r).max_depth; }},
        {{"wear_area_percent", "number", "%", wear, "the part of `tibia_contact`'s area worn deeper than `wear_area_threshold_mm`", {}, false, 3},
         [](const RunResult &r) { return last(r).wear_area_percent; }},
        {{"wear_area_threshold_mm", "number", "mm", wear, "`Wear/Wear area threshold`: the depth that counts as worn"},
         [](const RunResult &r) { return r.wear_area_threshold; }},
        {{"mean_cross_shear", "number", "-", wear, "the work-weighted mean cross-shear ratio of the last computed cycle (doc/wear.md, \"Cross-shear\"); absent when a resumed run computed no cycle"},
         [](const RunResult &r) { return r.has_cross_shear ? std::optional(r.mean_cross_shear) : std::nullopt; }}};
      // clang-format on
      return table;
    }

    // summary.json: each side (SIDE: medial, lateral).
    const std::vector<Value<const SideResult &>> &
    side_values()
    {
      // clang-format off
      static const std::vector<Value<const SideResult &>> table = {
        {{"SIDE_volume_loss_mm3", "number", "mm^3", wear, "`volume_loss_mm3` of the SIDE side (`Gait/Medial side`, doc/wear.md \"Output\"); the two sides add up to the insert"},
         [](const RunResult &, const SideResult &s) { return s.volume; }},
        {{"SIDE_mass_loss_mg", "number", "mg", wear, "the SIDE side's mass loss", {}, false, 5},
         [](const RunResult &r, const SideResult &s) { return r.density * s.volume; }},
        {{"SIDE_max_wear_depth_mm", "number", "mm", wear, "the SIDE side's largest depth"},
         [](const RunResult &, const SideResult &s) { return s.max_depth; }},
        {{"SIDE_wear_area_percent", "number", "%", wear, "the SIDE side's worn area, in percent of the whole articular surface"},
         [](const RunResult &, const SideResult &s) { return s.wear_area_percent; }},
        {{"SIDE_mean_cross_shear", "number", "-", wear, "the SIDE side's mean cross-shear (last computed cycle)"},
         [](const RunResult &, const SideResult &s) { return s.mean_cross_shear; }}};
      // clang-format on
      return table;
    }

    // summary.json: each activity of a mix (NAME: its name).
    const std::vector<Value<unsigned int>> &
    activity_values()
    {
      // clang-format off
      static const std::vector<Value<unsigned int>> table = {
        {{"activity_NAME_share", "number", "-", wear, "per activity of a mix (`Gait/Activities`, doc/gait.md \"Activity mixes\"; NAME its name in small letters, spaces and `-` as `_`): its share of the cycles; absent without a mix"},
         [](const RunResult &r, unsigned int a) { return r.activity_shares[a]; }},
        {{"activity_NAME_mass_loss_mg", "number", "mg", wear, "the activity's part of the mass loss (its cycles' wear times its share, summed over the blocks); the activities add up to `mass_loss_mg`"},
         [](const RunResult &r, unsigned int a) { return last(r).activities[a].mass; }},
        {{"activity_NAME_volume_loss_mm3", "number", "mm^3", wear, "the activity's part of the volume loss"},
         [](const RunResult &r, unsigned int a) { return last(r).activities[a].volume; }},
        {{"activity_NAME_max_wear_depth_mm", "number", "mm", wear, "the largest depth of the activity's part of the wear"},
         [](const RunResult &r, unsigned int a) { return last(r).activities[a].max_depth; }},
        {{"activity_NAME_medial_mass_loss_mg", "number", "mg", wear, "the activity's part of the medial side's mass loss"},
         [](const RunResult &r, unsigned int a) { return r.density * last(r).activities[a].medial_volume; }},
        {{"activity_NAME_lateral_mass_loss_mg", "number", "mg", wear, "the activity's part of the lateral side's mass loss"},
         [](const RunResult &r, unsigned int a) { return r.density * last(r).activities[a].lateral_volume; }}};
      // clang-format on
      return table;
    }

    // summary.json: after the protocol's own results (Gait::Protocol).
    const std::vector<Value<>> &
    solver_values()
    {
      // clang-format off
      static const std::vector<Value<>> table = {
        {{"max_pressure_MPa", "number", "MPa", wear, "the largest nodal contact pressure: of the static solve (contact), of every step computed (wear)", {}, false, 7},
         [](const RunResult &r) { return r.max_pressure; }},
        {{"steps", "integer", "-", wear, "gait steps computed (every computed cycle's steps)"},
         [](const RunResult &r) { return r.steps; }},
        {{"contact_solves", "integer", "-", wear, "contact solves of all steps (a trace)", {}, true, 8},
         [](const RunResult &r) { return r.contact_solves; }},
        {{"mean_newton_iterations", "number", "-", wear, "active-set iterations per contact solve (a trace)", {}, true},
         [](const RunResult &r) { return double(r.newton_iterations) / r.contact_solves; }},
        {{"pose_fallbacks", "integer", "-", wear, "steps of the pose Newton off the Newton direction (doc/gait.md)"},
         [](const RunResult &r) { return r.pose_fallbacks; }},
        {{"cut_back_steps", "integer", "-", wear, "steps whose pose converged only through sub-steps from the step before (a cut-back, doc/gait.md)"},
         [](const RunResult &r) { return r.cut_back_steps; }},
        {{"sub_steps", "integer", "-", wear, "the sub-steps those cut-backs solved"},
         [](const RunResult &r) { return r.sub_steps; }},
        {{"cycles_per_extrapolation_step", "number", "cycles", wear, "the cycles of one block, n_Delta (`Wear/Cycles per extrapolation step`)"},
         [](const RunResult &r) { return r.cycles_per_block; }},
        {{"first_cycle_mass_loss_mg_per_million_cycles", "number", "mg", wear, "the first computed cycle's mass loss times 1e6"},
         [](const RunResult &r) { return 1e6 * r.first_cycle_mass; }},
        {{"linear_extrapolation_mass_loss_mg", "number", "mg", wear, "the first cycle's mass loss extrapolated linearly to `Wear/Cycles` (with a run-in, over the effective cycles): the prediction without the worn geometry, for comparison"},
         [](const RunResult &r) { return r.linear_extrapolation_mass; }},
        {{"stiffness_update_interval", "integer", "-", wear, "`Wear/Stiffness update interval`"},
         [](const RunResult &r) { return r.stiffness_update_interval; }},
        {{"step_groups", "integer", "-", wear, "the step groups the steps of a cycle were split into (`Gait/Step groups`)"},
         [](const RunResult &r) { return r.step_groups; }}};
      // clang-format on
      return table;
    }

    // The positions of the wear run's results in their files (the
    // protocols' own results go between 22 and 25, the contact problem's
    // from 60: ResultSchema).
    [[maybe_unused]] const bool declared =
      ResultSchema::declare("summary.json", 20, fields_of(run_values())) &&
      ResultSchema::declare("summary.json", 21, fields_of(side_values())) &&
      ResultSchema::declare("summary.json", 22, fields_of(activity_values())) &&
      ResultSchema::declare("summary.json", 25, fields_of(solver_values())) &&
      ResultSchema::declare(
        "summary.json",
        26,
        {{"run_in_factor",
          "list",
          "-",
          wear,
          "the run-in factor's points, objects with the fields `cycles` and `factor`; only with a `Wear/Run-in file` (drawn on `mass_loss.png`)",
          {"cycles", "factor"}},
         {"unconverged_steps",
          "list",
          "-",
          wear,
          "the steps that did not converge or failed the load balance, objects with the fields `block`, `step`, `pose_residual_mm` (mm), `contact_converged` (1 or 0) and `load_balance`; `[]` when every step converged",
          [] {
            std::vector<std::string> names;
            for (const auto &column : failed_step_columns())
              names.push_back(column.field.name);
            return names;
          }()}}) &&
      ResultSchema::declare("wear_history.csv",
                            10,
                            fields_of(block_columns())) &&
      ResultSchema::declare("wear_history.csv",
                            20,
                            fields_of(side_columns())) &&
      ResultSchema::declare("wear_history.csv",
                            30,
                            fields_of(activity_columns())) &&
      ResultSchema::declare("wear_history.csv",
                            40,
                            fields_of(block_columns(), true));
  } // namespace

  const std::vector<ResultColumn<BlockResult>> &
  block_columns()
  {
    // clang-format off
    static const std::vector<ResultColumn<BlockResult>> table = {
      member_column<BlockResult>({"block", "", "-", {}, "the block (0 = the start)"},
       &BlockResult::block),
      member_column<BlockResult>({"cycles", "", "cycles", {}, "load cycles at the end of the block"},
       &BlockResult::cycles),
      member_column<BlockResult>({"volume_mm3", "", "mm^3", {}, "accumulated worn volume"},
       &BlockResult::volume),
      member_column<BlockResult>({"mass_mg", "", "mg", {}, "accumulated mass loss"},
       &BlockResult::mass),
      member_column<BlockResult>({"max_depth_mm", "", "mm", {}, "largest accumulated depth"},
       &BlockResult::max_depth),
      member_column<BlockResult>({"wear_area_percent", "", "%", {}, "worn area (deeper than `Wear/Wear area threshold`) in percent of `tibia_contact`"},
       &BlockResult::wear_area_percent),
      member_column<BlockResult>({"peak_pressure_MPa", "", "MPa", {}, "the largest nodal pressure of the block's cycle"},
       &BlockResult::peak_pressure),
      member_column<BlockResult>({"max_contact_area_mm2", "", "mm^2", {}, "the largest contact area of the block's cycle"},
       &BlockResult::max_contact_area),
      member_column<BlockResult>({"wall_time_s", "", "s", {}, "wall time at the end of the block; absent under `Output/Testing = true`", {}, false, false, true},
       &BlockResult::wall_time)};
    // clang-format on
    return table;
  }

  const std::vector<ResultColumn<SideResult>> &
  side_columns()
  {
    // clang-format off
    static const std::vector<ResultColumn<SideResult>> table = {
      member_column<SideResult>({"SIDE_volume_mm3", "", "mm^3", {}, "the SIDE side's accumulated volume (doc/wear.md, \"Output\")"},
       &SideResult::volume),
      member_column<SideResult>({"SIDE_max_depth_mm", "", "mm", {}, "the SIDE side's largest depth"},
       &SideResult::max_depth),
      member_column<SideResult>({"SIDE_wear_area_percent", "", "%", {}, "the SIDE side's worn area, in percent of the whole surface"},
       &SideResult::wear_area_percent),
      member_column<SideResult>({"SIDE_mean_cross_shear", "", "-", {}, "the SIDE side's mean cross-shear of the block's cycle (work x area weighted)"},
       &SideResult::mean_cross_shear)};
    // clang-format on
    return table;
  }

  const std::vector<ResultColumn<ActivityResult>> &
  activity_columns()
  {
    // clang-format off
    static const std::vector<ResultColumn<ActivityResult>> table = {
      member_column<ActivityResult>({"NAME_volume_mm3", "", "mm^3", {}, "per activity of a mix, in the order of `Gait/Activities` (NAME as in `summary.json`'s `activity_NAME_...`): its accumulated part of the volume; absent without a mix"},
       &ActivityResult::volume),
      member_column<ActivityResult>({"NAME_mass_mg", "", "mg", {}, "the activity's accumulated part of the mass loss"},
       &ActivityResult::mass),
      member_column<ActivityResult>({"NAME_max_depth_mm", "", "mm", {}, "the largest depth of the activity's part"},
       &ActivityResult::max_depth),
      member_column<ActivityResult>({"NAME_medial_volume_mm3", "", "mm^3", {}, "the activity's part of the medial side's volume"},
       &ActivityResult::medial_volume),
      member_column<ActivityResult>({"NAME_lateral_volume_mm3", "", "mm^3", {}, "the activity's part of the lateral side's volume"},
       &ActivityResult::lateral_volume)};
    // clang-format on
    return table;
  }

  const std::vector<ResultColumn<FailedStep>> &
  failed_step_columns()
  {
    // clang-format off
    static const std::vector<ResultColumn<FailedStep>> table = {
      member_column<FailedStep>({"block", "", "-", {}, "the block (1, 2, ...)"},
       &FailedStep::block),
      member_column<FailedStep>({"step", "", "-", {}, "the step of its cycle"},
       &FailedStep::step),
      member_column<FailedStep>({"pose_residual_mm", "", "mm", {}, "the pose solve's last residual"},
       &FailedStep::pose_residual),
      member_column<FailedStep>({"contact_converged", "", "-", {}, "1 if the contact solves converged, else 0"},
       &FailedStep::contact_converged),
      member_column<FailedStep>({"load_balance", "", "-", {}, "the protocol's load balance (at most 1 when balanced)"},
       &FailedStep::load_balance)};
    // clang-format on
    return table;
  }

  std::vector<std::pair<std::string, double>>
  RunResult::named_values() const
  {
    std::vector<std::pair<std::string, double>> values;
    const auto add = [&values](const std::string          &name,
                               const std::optional<double> value) {
      if (value)
        values.emplace_back(name, *value);
    };
    for (const auto &v : run_values())
      add(v.field.name, v.value(*this));
    for (const auto &[side, result] :
         {std::pair{"medial", last(*this).medial},
          std::pair{"lateral", last(*this).lateral}})
      for (const auto &v : side_values())
        add(with_name(v.field.name, side), v.value(*this, result));
    for (unsigned int a = 0;
         a < activity_names.size() && a < last(*this).activities.size();
         ++a)
      for (const auto &v : activity_values())
        add(with_name(v.field.name, activity_names[a]), v.value(*this, a));
    values.insert(values.end(),
                  protocol_results.begin(),
                  protocol_results.end());
    for (const auto &v : solver_values())
      add(v.field.name, v.value(*this));
    return values;
  }
} // namespace TKR::Wear
