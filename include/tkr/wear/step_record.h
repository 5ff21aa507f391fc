// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#ifndef tkr_wear_step_record_h
#define tkr_wear_step_record_h

#include <deal.II/base/point.h>
#include <deal.II/base/tensor.h>

#include <tkr/contact/contact_state.h>
#include <tkr/gait/rigid_motion.h>
#include <tkr/gait/tibia_pose.h>
#include <tkr/mortar/mortar_coupling.h>

#include <boost/serialization/vector.hpp>

#include <mpi.h>

#include <vector>

namespace TKR::Wear
{
  /**
   * What one gait step leaves for the wear computation, per slave
   * (`tibia_contact`) node: contact pressure (0 where not in contact), the
   * femur material point it touches (in the femur's reference
   * configuration), its displacement and its normal.
   */
  struct StepRecord
  {
    Gait::RigidMotion                 femur_motion;
    std::vector<double>               pressure;
    std::vector<dealii::Point<3>>     femur_point;
    std::vector<dealii::Tensor<1, 3>> displacement;
    std::vector<dealii::Tensor<1, 3>> normal;

    template <class Archive>
    void
    serialize(Archive &archive, const unsigned int)
    {
      archive &femur_motion &pressure &femur_point &displacement &normal;
    }
  };

  /**
   * The record of a contact solve: pressures of the active nodes, the
   * tibia's displacement (elastic plus @p tibia_translation, its pose), and
   * as femur material point the mortar projection of each node mapped back
   * through the femur's motion. The coupling is in the tibia's frame: the
   * femur was moved by @p femur_motion and then by -@p tibia_translation.
   */
  StepRecord
  make_step_record(const Mortar::MortarCoupling &coupling,
                   const Contact::ContactState  &state,
                   const Gait::RigidMotion      &femur_motion,
                   const dealii::Tensor<1, 3>   &tibia_translation);

  /** What one gait step did (for the screen and steps.csv). */
  struct StepReport
  {
    /** The gait's inputs: percent of the cycle, flexion (deg), forces. */
    double percent = 0, flexion = 0, axial_force = 0;
    double ap_force = 0, ie_torque = 0;
    /** Active nodes at the end, Newton iterations summed over the pose
     * updates, pose updates. */
    unsigned int active_nodes = 0, newton_iterations = 0, pose_updates = 0;
    /** The tibia's rigid translation (pose) in this step, mm. */
    dealii::Tensor<1, 3> tibia_pose;
    /** The tibia's rotation about +z (IE, deg). */
    double ie_rotation = 0;
    /** Peak pressure (MPa), contact force (N) and area (mm^2). */
    double max_pressure = 0, contact_force = 0, contact_area = 0;
    /** The contact solves and the pose iteration converged. */
    bool converged = false;
    /** The pose iteration reached its tolerance. */
    bool   pose_converged = false;
    double wall_time      = 0;

    template <class Archive>
    void
    serialize(Archive &archive, const unsigned int)
    {
      archive &percent &flexion &axial_force &ap_force &ie_torque;
      archive &active_nodes &newton_iterations         &pose_updates;
      archive &tibia_pose                              &ie_rotation;
      archive &max_pressure &contact_force             &contact_area;
      archive &converged &pose_converged               &wall_time;
    }
  };

  /**
   * Where a gait step ended, for the warm start of the same step in the
   * next extrapolation block: the tibia's pose and restraint forces, and
   * the active set.
   */
  struct StepStart
  {
    Gait::PoseState   pose;
    std::vector<bool> active;
    /** The face clearances of the step's last solve, for the coupling
     *  window of the next one (Mortar::CouplingWindow; not checkpointed:
     *  it changes the cost, not the result). */
    std::vector<double> face_clearance;

    template <class Archive>
    void
    serialize(Archive &archive, const unsigned int)
    {
      archive &pose &active &face_clearance;
    }
  };

  /**
   * Give every rank of @p communicator the records, reports and end states
   * of all steps: each step's are taken from the one rank that lists it in
   * @p own_steps (the root of the step group that solved it; the others
   * list none).
   */
  void
  gather_steps(const std::vector<unsigned int> &own_steps,
               std::vector<StepRecord>         &records,
               std::vector<StepReport>         &reports,
               std::vector<StepStart>          &starts,
               const MPI_Comm                   communicator);
} // namespace TKR::Wear

#endif
