// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#ifndef tkr_gait_step_report_h
#define tkr_gait_step_report_h

#include <deal.II/base/tensor.h>

#include <boost/serialization/vector.hpp>

#include <vector>

namespace TKR::Gait
{
  /**
   * The inputs of one gait step: where it is in the cycle and the values
   * of the protocol's input channels there (Protocol::input_columns(),
   * e.g. flexion, axial force, AP force and IE torque under force
   * control).
   */
  struct StepInput
  {
    /** Percent of the cycle, [0, 100). */
    double percent = 0;
    /** The protocol's input channels at that instant. */
    std::vector<double> values;

    template <class Archive>
    void
    serialize(Archive &archive, const unsigned int)
    {
      archive &percent &values;
    }
  };

  /**
   * Where the pose solve of a step stands, opaque to everyone but its
   * protocol (e.g. the tibia's translation and the restraints' excess
   * force and torque under force control): what a warm start continues
   * from and a checkpoint keeps. Empty: no pose yet.
   */
  struct Pose
  {
    std::vector<double> values;

    bool
    empty() const
    {
      return values.empty();
    }

    template <class Archive>
    void
    serialize(Archive &archive, const unsigned int)
    {
      archive &values;
    }
  };

  /** What one gait step did (for the screen and steps.csv). */
  struct StepReport
  {
    /** The step's inputs (percent of the cycle, the protocol's channels). */
    StepInput input;
    /** The pose the step ended in. */
    Pose pose;
    /** The protocol's numbers of the pose (Protocol::pose_columns()). */
    std::vector<double> pose_values;
    /** Active nodes at the end, active set iterations summed over the
     * contact solves, pose updates (Newton steps of the pose), contact
     * solves. */
    unsigned int active_nodes = 0, newton_iterations = 0, pose_updates = 0,
                 contact_solves = 0;
    /** Peak pressure (MPa), contact force (N) and area (mm^2). */
    double max_pressure = 0, contact_force = 0, contact_area = 0;
    /** The resultant of the contact forces on the tibia (N). */
    dealii::Tensor<1, 3> contact_resultant;
    /** Its moment about the origin of the tibia's frame (N mm). */
    dealii::Tensor<1, 3> contact_moment;
    /** The contact solves and the pose solve converged. */
    bool converged = false;
    /** The pose solve reached its tolerance. */
    bool pose_converged = false;
    /** The pose solve's last residual (mm). */
    double pose_residual = 0;
    /** Pose Newton steps off the Newton direction (PoseSolve). */
    unsigned int pose_fallbacks = 0;
    /** Sub-steps of the step's cut-back (PoseSolve; 0: none). */
    unsigned int sub_steps = 0;
    /** Every contact solve of the step converged. */
    bool   contact_converged = false;
    double wall_time         = 0;

    template <class Archive>
    void
    serialize(Archive &archive, const unsigned int)
    {
      archive &input &pose                      &pose_values;
      archive &active_nodes &newton_iterations  &pose_updates;
      archive &max_pressure &contact_force      &contact_area;
      archive &contact_resultant                &contact_moment;
      archive &converged &pose_converged        &wall_time;
      archive &pose_residual &contact_converged &pose_fallbacks;
      archive &sub_steps                        &contact_solves;
    }
  };

  /**
   * Where a gait step ended, for the warm start of the same step in the
   * next extrapolation block: its pose and the active set.
   */
  struct StepStart
  {
    Pose              pose;
    std::vector<bool> active;
    /** The pose the step ended in one block before `pose` (empty: none). */
    Pose previous;
    /** The face clearances of the step's last solve, for the coupling
     *  window of the next one (Mortar::CouplingWindow; not checkpointed:
     *  it changes the cost, not the result). */
    std::vector<double> face_clearance;

    /** No end state yet (the step starts from rest). */
    bool
    empty() const
    {
      return active.empty();
    }

    /**
     * The start of the step's next solve: `pose` moved on by its change
     * over the last block (linear extrapolation over the blocks: the wear of
     * a block moves the pose by nearly the same amount as the block
     * before's), or `pose` itself without a previous one.
     */
    Pose
    predicted_pose() const
    {
      Pose predicted = pose;
      if (previous.values.size() == pose.values.size())
        for (unsigned int k = 0; k < pose.values.size(); ++k)
          predicted.values[k] += pose.values[k] - previous.values[k];
      return predicted;
    }

    template <class Archive>
    void
    serialize(Archive &archive, const unsigned int)
    {
      archive &pose &active &previous &face_clearance;
    }
  };
} // namespace TKR::Gait

#endif
