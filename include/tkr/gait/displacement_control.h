// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#ifndef tkr_gait_displacement_control_h
#define tkr_gait_displacement_control_h

#include <tkr/gait/gait_loads.h>
#include <tkr/gait/protocol.h>
#include <tkr/gait/tibia_pose.h>
#include <tkr/gait/waveform.h>

#include <limits>

namespace TKR::Gait
{
  /**
   * ISO 14243-3 displacement control (`Gait/Control = displacement`,
   * doc/gait.md "Displacement control"): the femur is rotated by the
   * flexion angle about the flexion axis as under force control; the
   * tibia's tray is moved to the prescribed AP displacement (along y) and
   * IE rotation (about the vertical axis through the inferior centroid) and
   * held there (TibiaPose::add_tray_constraints() with the AP and IE DoFs
   * of the tray fixed, a finite rotation in the relative motion, so the
   * stiffness matrix is the same in every step); the axial force (with its
   * medial offset) is applied and the tray's axial and medial-lateral
   * position are solved: the tray is free along z and along its own x, with
   * no restraint springs. The AP force and the IE torque that hold the tray
   * are reported per step (the reactions: minus the contact's force along
   * the tray's y and its moment about the IE axis; nothing else acts on
   * the tibia in those directions).
   *
   * The waveform's channels: flexion_deg, axial_force_N,
   * ap_displacement_mm (the tibia, positive = anterior, times `AP
   * displacement sign`), ie_rotation_deg (the tibia, positive = internal,
   * times `IE rotation sign`), with percent_cycle (data/iso14243-3.csv).
   *
   * Its pose is the tray's translation in x and z (mm, simulator frame).
   */
  /** The entries of `Gait/Displacement control`. */
  struct DisplacementSigns
  {
    /** Signs applied to the tabulated AP displacement and IE rotation. */
    double ap_displacement_sign = 1, ie_rotation_sign = 1;
  };

  class DisplacementControl : public Protocol
  {
  public:
    /** @p signs: the entries of `Gait/Displacement control`. */
    DisplacementControl(const Parameters::Gait  &parameters,
                        const DisplacementSigns &signs,
                        const InferiorSurface   &surface);

    std::string
    name() const override
    {
      return "displacement";
    }

    std::string
    description() const override
    {
      return "ISO 14243-3 displacement control";
    }

    std::string
    setup_text() const override;

    /** The rigid tray with its AP translation and IE rotation held. */
    void
    add_constraints(const dealii::DoFHandler<3>       &dof_handler,
                    dealii::AffineConstraints<double> &constraints,
                    const dealii::ConditionalOStream  &pcout) const override;

    const Waveform &
    waveform() const override
    {
      return table;
    }

    /**
     * `ML spring stiffness` if set, and stabilisation springs along z and
     * the tray's x on the displacement relative to the pose (`Axial
     * stabilisation spring`; they vanish as the pose converges).
     */
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
     * The tray's x and z against the inferior surface's mean x and z
     * displacement (see the .cc file).
     */
    PoseEquations
    pose_equations() const override;

    void
    report(const Pose         &pose,
           const Observations &last,
           StepReport         &report) const override;

    /**
     * As under force control, the contact carries the axial force, within
     * the axial stabilisation spring times the pose tolerance plus 0.1 % of
     * the axial force (the pose may converge at a jump of the contact's
     * axial force where a slave node's coverage changes, doc/gait.md).
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

    /**
     * ap_reaction_N (the force that holds the tray, on the tibia along the
     * tray's y, positive anterior), ie_reaction_Nm (the torque that holds
     * it, positive internal), ml_position_mm and axial_position_mm (the
     * tray's x and z in the simulator's frame, solved). The AP and IE
     * positions are the inputs.
     */
    std::vector<std::string>
    pose_columns() const override;

    std::string
    input_text(const StepReport &report) const override;

    std::string
    pose_text(const StepReport &report) const override;

  private:
    /** The tibia's pose state at @p input and @p pose. */
    PoseState
    pose_state(const StepInput &input, const Pose &pose) const;

    /** The gait state of @p input (no AP force or IE torque). */
    GaitState
    gait_state(const StepInput &input) const;

    /** Updates of the relaxed step before x is bisected in its bracket. */
    static constexpr unsigned int bisection_start = 10;

    /** The AP force (N) and IE torque (N m) that hold the tray. */
    std::pair<double, double>
    reactions(const StepReport &report) const;

    const Parameters::Gait  parameters;
    const DisplacementSigns signs;
    const Waveform          table;
    /** The gait loads without restraint springs. */
    const GaitLoads gait_loads;
    const TibiaPose tibia_pose;
  };
} // namespace TKR::Gait

#endif
