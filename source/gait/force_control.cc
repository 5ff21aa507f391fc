// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#include <deal.II/base/numbers.h>

#include <tkr/base/exceptions.h>
#include <tkr/gait/force_control.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <iomanip>
#include <sstream>

namespace TKR::Gait
{
  using namespace dealii;

  namespace
  {
    /** The protocol's own results (doc/output.md): its inputs (the
     *  waveform's channels), its pose, its cycle's results. */
    const ProtocolResults &
    own_results()
    {
      // clang-format off
      static const ProtocolResults results = {
        // inputs
        {{"flexion_deg", "", "deg", {}, "input: the flexion angle"},
         {"axial_force_N", "", "N", {}, "input: the axial force"},
         {"ap_force_N", "", "N", {}, "input: the AP force on the tibia"},
         {"ie_torque_Nm", "", "N m", {}, "input: the IE torque on the tibia"}},
        // pose
        {{"ap_position_mm", "", "mm", {}, "pose: the tibia's solved AP position"},
         {"ie_rotation_deg", "", "deg", {}, "force control: the tibia's solved IE rotation (pose); displacement control: the prescribed IE rotation (input)"}},
        // the cycle's results
        {{"ap_position_range_mm", "number", "mm", {}, "force control's own result (`Gait::Protocol::cycle_results()`): the range (largest minus smallest) of the tibia's AP position (`steps.csv` `ap_position_mm`) over the last computed cycle; absent under displacement control and when a resumed run computed no cycle"},
         {"ie_rotation_range_deg", "number", "deg", {}, "force control's: the range of the tibia's IE rotation (`ie_rotation_deg`) over the last computed cycle; absent as `ap_position_range_mm`"}}};
      // clang-format on
      return results;
    }

    /** The waveform's channels. */
    const std::vector<std::string> channels = names(own_results().inputs);

    [[maybe_unused]] const bool declared =
      declare_results("force", own_results());

    /** The restraints' entries (`Gait/Force control`). */
    void
    declare_restraints(ParameterHandler &prm)
    {
      prm.declare_entry("AP spring stiffness",
                        "9.3",
                        Patterns::Double(0),
                        "Anterior-posterior restraint spring, N/mm (within "
                        "the AP spring range).");
      prm.declare_entry("AP spring range",
                        "2.5",
                        Patterns::Double(0),
                        "The AP restraint has the AP spring stiffness within "
                        "+- this AP translation of the tibia (mm) and the "
                        "AP spring stiffness beyond range outside it "
                        "(ISO 14243-1:2009 two-rate law, values as commonly "
                        "cited).");
      prm.declare_entry("AP spring stiffness beyond range",
                        "44",
                        Patterns::Double(0),
                        "AP restraint stiffness beyond the AP spring range, "
                        "N/mm. Equal to the AP spring stiffness: a linear "
                        "spring.");
      prm.declare_entry("IE spring stiffness",
                        "130",
                        Patterns::Double(0),
                        "Internal-external rotation restraint spring, "
                        "N mm/deg (within the IE spring range).");
      prm.declare_entry("IE spring range",
                        "6",
                        Patterns::Double(0),
                        "The IE restraint has the IE spring stiffness within "
                        "+- this rotation of the tibia about the axial "
                        "direction (deg) and the IE spring stiffness beyond "
                        "range outside it.");
      prm.declare_entry("IE spring stiffness beyond range",
                        "360",
                        Patterns::Double(0),
                        "IE restraint stiffness beyond the IE spring range, "
                        "N mm/deg. Equal to the IE spring stiffness: a "
                        "linear spring.");
      prm.declare_entry("AP force sign",
                        "1",
                        Patterns::Selection("1|-1"),
                        "Multiplies the tabulated AP force: +1 keeps the "
                        "table's convention (positive = force on the tibia "
                        "towards anterior, +y).");
      prm.declare_entry("IE torque sign",
                        "1",
                        Patterns::Selection("1|-1"),
                        "Multiplies the tabulated IE torque: +1 keeps the "
                        "table's convention (positive = internal rotation of "
                        "the tibia).");
    }

    /** The restraints from `Gait/Force control`. */
    std::any
    parse_restraints(const ParameterHandler &prm)
    {
      Restraints r;
      r.ap_spring_stiffness = prm.get_double("AP spring stiffness");
      r.ap_spring_range     = prm.get_double("AP spring range");
      r.ap_spring_stiffness_beyond =
        prm.get_double("AP spring stiffness beyond range");
      r.ie_spring_stiffness = prm.get_double("IE spring stiffness");
      r.ie_spring_range     = prm.get_double("IE spring range");
      r.ie_spring_stiffness_beyond =
        prm.get_double("IE spring stiffness beyond range");
      r.ap_force_sign  = prm.get_double("AP force sign");
      r.ie_torque_sign = prm.get_double("IE torque sign");
      AssertThrow(r.ap_spring_stiffness_beyond >= r.ap_spring_stiffness &&
                    r.ie_spring_stiffness_beyond >= r.ie_spring_stiffness,
                  ExcInputError("Gait/Force control: a spring stiffness "
                                "beyond range must not be smaller than the "
                                "one within it."));
      return r;
    }

    [[maybe_unused]] const bool registered = Protocols::add(
      {"force",
       "ISO 14243-1 force control (flexion prescribed; axial force, AP force "
       "and IE torque applied to the tibia, held by the AP and IE "
       "restraints of Gait/Force control; the tibia's pose solved in every "
       "step)",
       {"Force control",
        declare_restraints,
        parse_restraints,
        {},
        {"AP spring stiffness",
         "AP spring range",
         "AP spring stiffness beyond range",
         "IE spring stiffness",
         "IE spring range",
         "IE spring stiffness beyond range",
         "AP force sign",
         "IE torque sign"}},
       [](const Parameters::Gait &parameters,
          const std::any         &own,
          const InferiorSurface  &surface) -> std::unique_ptr<Protocol> {
         return std::make_unique<ForceControl>(
           parameters,
           std::any_cast<const Restraints &>(own),
           surface);
       }});
  } // namespace

  ForceControl::ForceControl(const Parameters::Gait &parameters,
                             const Restraints       &restraints,
                             const InferiorSurface  &surface)
    : parameters(parameters)
    , table(parameters.waveform_file, channels, parameters.channel_scales)
    , gait_loads(parameters, restraints, surface)
    , tibia_pose(parameters, gait_loads)
  {}

  std::string
  ForceControl::setup_text() const
  {
    const auto        &surface = gait_loads.inferior_surface();
    std::ostringstream text;
    text << "Tibia inferior surface: " << surface.area << " mm^2, insert width "
         << surface.width << " mm";
    return text.str();
  }

  void
  ForceControl::add_constraints(const DoFHandler<3>       &dof_handler,
                                AffineConstraints<double> &constraints,
                                const ConditionalOStream  &pcout) const
  {
    if (!parameters.rigid_tray)
      return;
    const unsigned int n_tied =
      tibia_pose.add_tray_constraints(dof_handler, constraints);
    pcout << "Tibial tray: rigid (no sagittal tilt), " << n_tied
          << " inferior nodes tied to 5 DoFs" << std::endl;
  }

  Elasticity::BoundaryLoads
  ForceControl::springs() const
  {
    return tibia_pose.springs();
  }

  std::vector<Elasticity::BoundaryLoads>
  ForceControl::load_basis() const
  {
    return tibia_pose.load_basis();
  }

  std::vector<std::pair<std::string, Elasticity::BoundaryLoads>>
  ForceControl::observations() const
  {
    return tibia_pose.motion_observations();
  }

  StepInput
  ForceControl::input(const double percent) const
  {
    return waveform_input(table, percent);
  }

  GaitState
  ForceControl::gait_state(const StepInput &input)
  {
    AssertDimension(input.values.size(), 4);
    GaitState state;
    state.percent     = input.percent;
    state.flexion     = input.values[0];
    state.axial_force = input.values[1];
    state.ap_force    = input.values[2];
    state.ie_torque   = input.values[3];
    return state;
  }

  PoseState
  ForceControl::pose_state(const Pose &pose)
  {
    PoseState state;
    if (pose.empty())
      return state;
    AssertDimension(pose.values.size(), 6);
    for (unsigned int d = 0; d < 3; ++d)
      state.translation[d] = pose.values[d];
    state.restraint_force  = pose.values[3];
    state.restraint_torque = pose.values[4];
    state.rotation         = pose.values[5];
    return state;
  }

  Pose
  ForceControl::to_pose(const PoseState &state)
  {
    return Pose{{state.translation[0],
                 state.translation[1],
                 state.translation[2],
                 state.restraint_force,
                 state.restraint_torque,
                 state.rotation}};
  }

  InferiorMotion
  ForceControl::inferior_motion(const Observations &observations)
  {
    return TibiaPose::inferior_motion(observations);
  }

  Pose
  ForceControl::rest_pose(const StepInput &, const double lift) const
  {
    PoseState state;
    state.translation[2] = lift;
    return to_pose(state);
  }

  // The tibia's pose: a rotation about the IE axis and a translation.
  RelativeMotion
  ForceControl::motion(const StepInput &input, const Pose &pose) const
  {
    RelativeMotion motion;
    motion.femur = gait_loads.femur_motion(gait_state(input));
    motion.tibia = tibia_pose.motion(pose_state(pose));
    return motion;
  }

  std::vector<double>
  ForceControl::load_coefficients(const StepInput &input,
                                  const Pose      &pose) const
  {
    return tibia_pose.load_coefficients(gait_state(input), pose_state(pose));
  }

  // Pose values (to_pose()): translation x, y, z, restraint excess force
  // and torque, rotation. At equilibrium the inferior surface's mean
  // displacement relative to the pose vanishes, and with it the position's
  // share of the restraints: their excess is that of the pose itself.
  PoseEquations
  ForceControl::pose_equations() const
  {
    const double rim =
      0.5 * gait_loads.inferior_surface().width * numbers::PI / 180.;
    const auto    names = tibia_pose.motion_observations();
    PoseEquations equations;
    equations.unknowns  = {0, 1, 2, 5};
    equations.forces    = {TibiaPose::ml_force,
                           TibiaPose::ap_force,
                           TibiaPose::axial_force,
                           TibiaPose::ie_torque};
    equations.residuals = {{names[0].first, 1.},
                           {names[1].first, 1.},
                           {names[2].first, 1.},
                           {names[3].first, rim}};
    equations.complete  = [this](Pose &pose) {
      pose.values[3] = gait_loads.ap_restraint_excess(pose.values[1]);
      pose.values[4] = gait_loads.ie_restraint_excess(pose.values[5]);
    };
    return equations;
  }

  void
  ForceControl::report(const Pose         &pose,
                       const Observations &last,
                       StepReport         &report) const
  {
    report.pose        = pose;
    report.pose_values = {pose_state(pose).translation[1],
                          pose_state(pose).rotation +
                            inferior_motion(last).rotation_z};
  }

  double
  ForceControl::load_balance(const StepReport &report) const
  {
    return tibia_pose.axial_balance(gait_state(report.input).axial_force,
                                    report.contact_resultant,
                                    1e-6);
  }

  // The ranges of the tibia's AP position and IE rotation over the cycle
  // (pose_values), the kinematics a force-controlled simulator reports.
  std::vector<std::pair<std::string, double>>
  ForceControl::cycle_results(const std::vector<StepReport> &reports) const
  {
    std::array<double, 2> low{{0., 0.}}, high{{0., 0.}};
    for (unsigned int s = 0; s < reports.size(); ++s)
      for (unsigned int i = 0; i < 2; ++i)
        {
          const double value = reports[s].pose_values.at(i);
          low[i]             = (s == 0 ? value : std::min(low[i], value));
          high[i]            = (s == 0 ? value : std::max(high[i], value));
        }
    const auto &cycle = own_results().cycle;
    return {{cycle[0].name, high[0] - low[0]},
            {cycle[1].name, high[1] - low[1]}};
  }

  std::vector<std::string>
  ForceControl::input_columns() const
  {
    return channels;
  }

  std::vector<std::string>
  ForceControl::pose_columns() const
  {
    return names(own_results().pose);
  }

  std::string
  ForceControl::input_text(const StepReport &report) const
  {
    const GaitState    state = gait_state(report.input);
    std::ostringstream text;
    text << std::fixed << std::setprecision(1) << "flexion " << std::setw(5)
         << state.flexion << " deg, axial " << std::setw(6)
         << std::setprecision(0) << state.axial_force << " N";
    return text.str();
  }

  std::string
  ForceControl::pose_text(const StepReport &report) const
  {
    const PoseState    state = pose_state(report.pose);
    std::ostringstream text;
    text << std::fixed << std::setprecision(2) << "tibia y " << std::setw(5)
         << state.translation[1] << " z " << std::setw(5)
         << state.translation[2] << " mm";
    return text.str();
  }
} // namespace TKR::Gait
