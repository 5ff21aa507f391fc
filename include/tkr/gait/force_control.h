// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#ifndef tkr_gait_force_control_h
#define tkr_gait_force_control_h

#include <tkr/gait/gait_loads.h>
#include <tkr/gait/protocol.h>
#include <tkr/gait/tibia_pose.h>
#include <tkr/gait/waveform.h>

namespace TKR::Gait
{
  /**
   * ISO 14243-1 force control (`Gait/Control = force`, DESIGN.md section
   * 2): the femur is rotated by the flexion angle about the flexion axis;
   * the tibia has no displacement condition, it is loaded on its inferior
   * surface by the axial force (with its medial offset), the AP force and
   * the IE torque of the waveform and held by the AP and IE restraints
   * (GaitLoads). Its pose is the tibia's rigid translation with the
   * two-rate restraints' excess force and torque (which follow from the
   * translation and rotation), its equations the mean displacement and
   * rotation of the inferior surface (pose_equations(), solved by the gait
   * driver's pose Newton); TibiaPose holds the tray's kinematics and loads
   * that both protocols share.
   *
   * The waveform's channels: flexion_deg, axial_force_N, ap_force_N,
   * ie_torque_Nm (with percent_cycle; data/iso14243-1.csv).
   */
  class ForceControl : public Protocol
  {
  public:
    /** @p restraints: the entries of `Gait/Force control`. */
    ForceControl(const Parameters::Gait &parameters,
                 const Restraints       &restraints,
                 const InferiorSurface  &surface);

    std::string
    name() const override
    {
      return "force";
    }

    std::string
    description() const override
    {
      return "ISO 14243-1 force control";
    }

    std::string
    setup_text() const override;

    void
    add_constraints(const dealii::DoFHandler<3>       &dof_handler,
                    dealii::AffineConstraints<double> &constraints,
                    const dealii::ConditionalOStream  &pcout) const override;

    const Waveform &
    waveform() const override
    {
      return table;
    }

    Elasticity::BoundaryLoads
    springs() const override;

    std::vector<Elasticity::BoundaryLoads>
    load_basis() const override;

    std::vector<std::pair<std::string, Elasticity::BoundaryLoads>>
    observations() const override;

    StepInput
    input(const double percent) const override;

    Pose
    rest_pose(const StepInput &input, const double lift) const override;

    RelativeMotion
    motion(const StepInput &input, const Pose &pose) const override;

    std::vector<double>
    load_coefficients(const StepInput &input, const Pose &pose) const override;

    /**
     * The translation and the IE rotation; the restraints' excess force
     * and torque follow from them; the inferior surface's mean
     * displacement and rotation (at the rim) vanish at equilibrium.
     */
    PoseEquations
    pose_equations() const override;

    void
    report(const Pose         &pose,
           const Observations &last,
           StepReport         &report) const override;

    /**
     * TibiaPose::axial_balance(): the contact alone carries the axial force
     * (the restraints act in the tray's plane).
     */
    double
    load_balance(const StepReport &report) const override;

    std::string
    load_balance_text() const override
    {
      return "axial force carried by the contact";
    }

    std::vector<std::pair<std::string, double>>
    cycle_results(const std::vector<StepReport> &reports) const override;

    std::vector<std::string>
    input_columns() const override;

    std::vector<std::string>
    pose_columns() const override;

    std::string
    input_text(const StepReport &report) const override;

    std::string
    pose_text(const StepReport &report) const override;

    /** The gait state (flexion, forces) of @p input. */
    static GaitState
    gait_state(const StepInput &input);

    /** The pose state of an opaque @p pose (rest if it is empty). */
    static PoseState
    pose_state(const Pose &pose);

    /** The opaque pose of @p state. */
    static Pose
    to_pose(const PoseState &state);

    /** The inferior motion from the observations (by name). */
    static InferiorMotion
    inferior_motion(const Observations &observations);

  private:
    const Parameters::Gait parameters;
    const Waveform         table;
    const GaitLoads        gait_loads;
    const TibiaPose        tibia_pose;
  };
} // namespace TKR::Gait

#endif
