// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#include <deal.II/base/numbers.h>

#include <tkr/base/exceptions.h>
#include <tkr/gait/displacement_control.h>
#include <tkr/mesh/mesh.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <iomanip>
#include <iostream>
#include <limits>
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
         {"ap_displacement_mm", "", "mm", {}, "input: the prescribed AP displacement of the tray"},
         {"ie_rotation_deg", "", "deg", {}, "force control: the tibia's solved IE rotation (pose); displacement control: the prescribed IE rotation (input)"}},
        // pose
        {{"ap_reaction_N", "", "N", {}, "the AP force that held the tray (on the tibia, positive anterior)"},
         {"ie_reaction_Nm", "", "N m", {}, "the IE torque that held the tray (positive internal)"},
         {"ml_position_mm", "", "mm", {}, "the tray's solved x (medial-lateral) position"},
         {"axial_position_mm", "", "mm", {}, "the tray's solved z (axial) position"}},
        // the cycle's results
        {{"max_ap_reaction_N", "number", "N", {}, "displacement control's own result: the largest magnitude of the AP force that held the tray (`steps.csv` `ap_reaction_N`) over the last computed cycle; absent under force control and when a resumed run computed no cycle"},
         {"max_ie_reaction_Nm", "number", "N m", {}, "displacement control's: the largest magnitude of the IE torque that held the tray (`ie_reaction_Nm`) over the last computed cycle; absent as `max_ap_reaction_N`"}}};
      // clang-format on
      return results;
    }

    /** The waveform's channels. */
    const std::vector<std::string> channels = names(own_results().inputs);

    [[maybe_unused]] const bool declared =
      declare_results("displacement", own_results());

    /** The pose's numbers: the tray's x and z (mm). */
    constexpr unsigned int pose_size = 2;

    /** The signs' entries (`Gait/Displacement control`). */
    void
    declare_signs(ParameterHandler &prm)
    {
      prm.declare_entry("AP displacement sign",
                        "1",
                        Patterns::Selection("1|-1"),
                        "Multiplies the tabulated AP displacement: +1 keeps "
                        "the table's convention (positive = the tibia moved "
                        "anteriorly, +y, mm).");
      prm.declare_entry("IE rotation sign",
                        "1",
                        Patterns::Selection("1|-1"),
                        "Multiplies the tabulated IE rotation: +1 keeps the "
                        "table's convention (positive = internal rotation of "
                        "the tibia, deg, about the vertical axis through the "
                        "centroid of tibia_inferior).");
    }

    [[maybe_unused]] const bool registered = Protocols::add(
      {"displacement",
       "ISO 14243-3 displacement control (flexion, the tibial tray's AP "
       "displacement and IE rotation prescribed, the axial force applied; "
       "the tray's axial and medial-lateral position solved, no restraint "
       "springs; the AP force and IE torque that hold the tray reported per "
       "step; needs Tibial tray = rigid; signs in Gait/Displacement "
       "control)",
       {"Displacement control",
        declare_signs,
        [](const ParameterHandler &prm) -> std::any {
          return DisplacementSigns{prm.get_double("AP displacement sign"),
                                   prm.get_double("IE rotation sign")};
        },
        {},
        {"AP displacement sign", "IE rotation sign"},
        {},
        {},
        {},
        {},
        {{"Waveform file", "data/iso14243-3.csv"}}},
       [](const Parameters::Gait &parameters,
          const std::any         &own,
          const InferiorSurface  &surface) -> std::unique_ptr<Protocol> {
         return std::make_unique<DisplacementControl>(
           parameters,
           std::any_cast<const DisplacementSigns &>(own),
           surface);
       }});
  } // namespace

  DisplacementControl::DisplacementControl(const Parameters::Gait  &parameters,
                                           const DisplacementSigns &signs,
                                           const InferiorSurface   &surface)
    : parameters(parameters)
    , signs(signs)
    , table(parameters.waveform_file, channels, parameters.channel_scales)
    , gait_loads(parameters, Restraints(), surface)
    , tibia_pose(parameters, gait_loads)
  {
    AssertThrow(parameters.rigid_tray,
                ExcInputError(
                  "Gait/Control = displacement prescribes the AP translation "
                  "and the IE rotation of the tibial tray, which needs "
                  "Gait/Tibial tray = rigid (it is free)."));
  }

  std::string
  DisplacementControl::setup_text() const
  {
    const auto        &surface = gait_loads.inferior_surface();
    std::ostringstream text;
    text << "Tibia inferior surface: " << surface.area << " mm^2, insert width "
         << surface.width
         << " mm; AP and IE prescribed, axial and ML position solved";
    return text.str();
  }

  void
  DisplacementControl::add_constraints(const DoFHandler<3>       &dof_handler,
                                       AffineConstraints<double> &constraints,
                                       const ConditionalOStream  &pcout) const
  {
    const unsigned int n_tied =
      tibia_pose.add_tray_constraints(dof_handler, constraints, true);
    pcout << "Tibial tray: rigid (no sagittal tilt), AP and IE held, " << n_tied
          << " inferior nodes tied to 3 DoFs" << std::endl;
  }

  // Along z and along the tray's x nothing but the contact holds the tibia:
  // the stabilisation spring acts on the displacement relative to the pose
  // in both, and vanishes as the pose converges.
  Elasticity::BoundaryLoads
  DisplacementControl::springs() const
  {
    Elasticity::BoundaryLoads loads = tibia_pose.springs();
    loads.springs[Mesh::BoundaryIds::tibia_inferior][0][0] =
      parameters.axial_stabilisation_spring / gait_loads.inferior_area();
    return loads;
  }

  std::vector<Elasticity::BoundaryLoads>
  DisplacementControl::load_basis() const
  {
    return tibia_pose.load_basis();
  }

  std::vector<std::pair<std::string, Elasticity::BoundaryLoads>>
  DisplacementControl::observations() const
  {
    return tibia_pose.motion_observations();
  }

  StepInput
  DisplacementControl::input(const double percent) const
  {
    return waveform_input(table, percent);
  }

  GaitState
  DisplacementControl::gait_state(const StepInput &input) const
  {
    AssertDimension(input.values.size(), 4);
    GaitState state;
    state.percent     = input.percent;
    state.flexion     = input.values[0];
    state.axial_force = input.values[1];
    return state;
  }

  // The table's AP displacement is along +y (anterior) and its IE rotation
  // internal, i.e. about -z if medial is +x; the pose adds the tray's x
  // and z.
  PoseState
  DisplacementControl::pose_state(const StepInput &input,
                                  const Pose      &pose) const
  {
    AssertDimension(input.values.size(), 4);
    PoseState state;
    state.translation[1] =
      signs.ap_displacement_sign * input.values[2] - parameters.femur_ap_offset;
    state.rotation =
      -parameters.medial_direction * signs.ie_rotation_sign * input.values[3];
    if (!pose.empty())
      {
        AssertDimension(pose.values.size(), pose_size);
        state.translation[0] = pose.values[0];
        state.translation[2] = pose.values[1];
      }
    return state;
  }

  Pose
  DisplacementControl::rest_pose(const StepInput &, const double lift) const
  {
    return Pose{{0., lift}};
  }

  RelativeMotion
  DisplacementControl::motion(const StepInput &input, const Pose &pose) const
  {
    RelativeMotion motion;
    motion.femur = gait_loads.femur_motion(gait_state(input));
    motion.tibia = tibia_pose.motion(pose_state(input, pose));
    return motion;
  }

  std::vector<double>
  DisplacementControl::load_coefficients(const StepInput &input,
                                         const Pose      &pose) const
  {
    return tibia_pose.load_coefficients(gait_state(input),
                                        pose_state(input, pose));
  }

  // The tray's x and z (pose values 0 and 1) against the inferior
  // surface's mean x and z displacement. Along x nothing but the contact
  // (and the weak ML spring) holds the tray; the contact force is
  // continuous in the pose since the mortar coupling's edge rule and basis
  // blend (Mortar::MortarCoupling), which is what the Newton needs here.
  PoseEquations
  DisplacementControl::pose_equations() const
  {
    const auto    names = tibia_pose.motion_observations();
    PoseEquations equations;
    equations.unknowns  = {0, 1};
    equations.forces    = {TibiaPose::ml_force, TibiaPose::axial_force};
    equations.residuals = {{names[0].first, 1.}, {names[2].first, 1.}};
    return equations;
  }

  // Nothing but the contact and the tray acts on the tibia along the
  // tray's y and about the IE axis (the axial force and the stabilisation
  // springs act along z and x, the ML spring's uniform traction has no
  // moment about the centroid): the reactions are minus the contact's
  // force along y and its moment about the vertical axis through the
  // inferior centroid.
  std::pair<double, double>
  DisplacementControl::reactions(const StepReport &report) const
  {
    const Tensor<1, 3> c        = gait_loads.inferior_centroid();
    const double       moment_z = report.contact_moment[2] -
                            cross_product_3d(c, report.contact_resultant)[2];
    return {-report.contact_resultant[1],
            parameters.medial_direction * moment_z * 1e-3};
  }

  void
  DisplacementControl::report(const Pose         &pose,
                              const Observations &last,
                              StepReport         &report) const
  {
    const PoseState state      = pose_state(report.input, pose);
    const auto [force, torque] = reactions(report);
    report.pose                = pose;
    report.pose_values         = {force,
                                  torque,
                                  state.translation[0] +
                                    TibiaPose::inferior_motion(last).mean[0],
                                  state.translation[2] +
                                    TibiaPose::inferior_motion(last).mean[2]};
  }

  double
  DisplacementControl::load_balance(const StepReport &report) const
  {
    // 0.1 % of the axial force: a jump in z's correction at fixed x where a
    // slave node's coverage changes (doc/gait.md).
    return tibia_pose.axial_balance(gait_state(report.input).axial_force,
                                    report.contact_resultant,
                                    1e-3);
  }

  // The largest AP force and IE torque that held the tray over the cycle
  // (pose_values), what a displacement-controlled simulator measures.
  std::vector<std::pair<std::string, double>>
  DisplacementControl::cycle_results(
    const std::vector<StepReport> &reports) const
  {
    double ap = 0, ie = 0;
    for (const StepReport &report : reports)
      {
        ap = std::max(ap, std::abs(report.pose_values.at(0)));
        ie = std::max(ie, std::abs(report.pose_values.at(1)));
      }
    const auto &cycle = own_results().cycle;
    return {{cycle[0].name, ap}, {cycle[1].name, ie}};
  }

  std::vector<std::string>
  DisplacementControl::input_columns() const
  {
    return channels;
  }

  std::vector<std::string>
  DisplacementControl::pose_columns() const
  {
    return names(own_results().pose);
  }

  std::string
  DisplacementControl::input_text(const StepReport &report) const
  {
    std::ostringstream text;
    text << std::fixed << std::setprecision(1) << "flexion " << std::setw(5)
         << report.input.values[0] << " deg, axial " << std::setw(6)
         << std::setprecision(0) << report.input.values[1] << " N";
    return text.str();
  }

  std::string
  DisplacementControl::pose_text(const StepReport &report) const
  {
    AssertDimension(report.pose_values.size(), 4);
    std::ostringstream text;
    text << std::fixed << std::setprecision(2) << "tibia y " << std::setw(5)
         << pose_state(report.input, report.pose).translation[1] << " z "
         << std::setw(5) << report.pose_values[3] << " mm, reactions "
         << std::setprecision(0) << std::setw(4) << report.pose_values[0]
         << " N " << std::setprecision(2) << std::setw(5)
         << report.pose_values[1] << " N m";
    return text.str();
  }
} // namespace TKR::Gait
