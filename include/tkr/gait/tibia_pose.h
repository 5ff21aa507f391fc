// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#ifndef tkr_gait_tibia_pose_h
#define tkr_gait_tibia_pose_h

#include <deal.II/base/conditional_ostream.h>
#include <deal.II/base/tensor.h>

#include <deal.II/dofs/dof_handler.h>

#include <deal.II/lac/affine_constraints.h>

#include <tkr/elasticity/linear_elasticity.h>
#include <tkr/gait/gait_loads.h>
#include <tkr/gait/protocol.h>
#include <tkr/parameters/parameters.h>

#include <array>
#include <functional>
#include <map>
#include <vector>

namespace TKR::Gait
{
  /** The rigid part of the tibia's displacement on its inferior surface. */
  struct InferiorMotion
  {
    /** Mean displacement (mm). */
    dealii::Tensor<1, 3> mean;
    /** Best-fitting rotation about +z (deg). */
    double rotation_z = 0;
  };

  /**
   * Where the pose iteration of a step stands: the tibia's rigid motion
   * (its pose: the translation of the inferior surface's centroid, mm, in
   * the simulator's frame, and the rotation about the vertical (IE) axis
   * through that centroid, deg, positive about +z) and the two-rate
   * restraints' excess force (N, along the simulator's y) and torque (N mm,
   * about z). A step starts from zero (cold) or from the converged state
   * of the same step of the previous cycle (warm).
   */
  struct PoseState
  {
    dealii::Tensor<1, 3> translation;
    double               rotation         = 0;
    double               restraint_force  = 0;
    double               restraint_torque = 0;

    template <class Archive>
    void
    serialize(Archive &archive, const unsigned int)
    {
      archive &translation &rotation &restraint_force &restraint_torque;
    }
  };

  /**
   * The load-controlled kinematics of the tibia in a gait step (DESIGN.md
   * section 2): the insert has no displacement condition, its tray may be
   * rigid (tray constraints), it is loaded by the gait's forces and held
   * by the restraint springs.
   *
   * Under load control the tibia moves by millimetres and degrees (AP and
   * ML sliding in the dishes, rising and sinking with the femur, internal-
   * external rotation), which a small-displacement contact model,
   * linearised at the reference position, cannot follow. So the tibia's
   * reference position carries a rigid motion (its pose: a translation
   * and a rotation about the vertical axis through the inferior centroid,
   * finite, in the relative motion of the femur): after a contact solve,
   * the mean displacement of its inferior surface and its best-fitting
   * rotation are what the pose must take up: the step's pose equations
   * (each protocol's pose_equations(), solved by the gait driver's pose
   * Newton until they are below the pose tolerance). The loads and the springs
   * act in the tibia's frame: the AP force of the simulator's frame is turned
   * into it, the springs act on pose plus displacement (the pose part is a
   * traction).
   */
  class TibiaPose
  {
  public:
    TibiaPose(const Parameters::Gait &parameters, const GaitLoads &gait_loads);

    /**
     * The rigid tibial tray (`Tibial tray = rigid`): constraints that let
     * the inferior surface translate, rotate about z (IE) and ab/adduct
     * (about y), but not tilt in the sagittal plane. With @p hold_ap_ie
     * the tray's AP translation (y) and IE rotation (about z) are held at
     * the pose as well (displacement control: the simulator prescribes
     * them). Returns the number of inferior nodes tied to the tray.
     */
    unsigned int
    add_tray_constraints(const dealii::DoFHandler<3>       &dof_handler,
                         dealii::AffineConstraints<double> &constraints,
                         const bool hold_ap_ie = false) const;

    /**
     * Loads of a step on the tibia in @p pose: the gait's tractions, the
     * restraint springs acting on pose plus displacement (the pose part is
     * a traction), the restraints' excess force and torque, and the axial
     * stabilisation spring. The springs are the same in every step
     * (springs()); the tractions are linear_combination() of load_basis()
     * with load_coefficients().
     */
    Elasticity::BoundaryLoads
    loads(const GaitState &gait, const PoseState &pose) const;

    /** The springs of every step's loads() (no tractions). */
    Elasticity::BoundaryLoads
    springs() const;

    /**
     * Eight tractions of which every step's are a combination (in the
     * tibia's frame): a unit axial force, AP force (y) and torque about z
     * (GaitLoads::traction_basis()), the spring tractions -S(x) e_d of a
     * unit pose translation in x, y, z, a unit force along x distributed
     * like the AP force (the part of the AP force that the tibia's rotation
     * turns into its x direction), and the spring traction of a pose
     * rotation of one degree about the IE axis.
     */
    std::vector<Elasticity::BoundaryLoads>
    load_basis() const;

    /**
     * Indices in load_basis() of its unit forces along x, y, z (N) and of
     * its unit torque about z (N mm): the generalized forces that the pose
     * unknowns x, y, z and theta work against.
     */
    enum UnitForce : unsigned int
    {
      axial_force = 0,
      ap_force    = 1,
      ie_torque   = 2,
      ml_force    = 6
    };

    /** The coefficients of the tractions of loads() on load_basis(). */
    std::vector<double>
    load_coefficients(const GaitState &gait, const PoseState &pose) const;

    /**
     * The tibia's rigid motion in @p pose (simulator frame): the rotation
     * by the pose's IE angle about the vertical axis through the inferior
     * centroid, then the translation.
     */
    RigidMotion
    motion(const PoseState &pose) const;


    /**
     * The inferior motion as four linear functionals of the displacement
     * (tractions on `tibia_inferior` whose work is the mean displacement
     * in x, y, z and the best-fitting rotation about z in degrees).
     */
    std::array<Elasticity::BoundaryLoads, 4>
    motion_functionals() const;

    /**
     * motion_functionals() as a protocol's observations, named
     * inferior_mean_displacement_x/y/z and inferior_rotation_z_deg.
     */
    std::vector<std::pair<std::string, Elasticity::BoundaryLoads>>
    motion_observations() const;

    /**
     * |F_z + F_axial| over its bound, for a step whose contact resultant on
     * the tibia is @p contact_resultant under the axial force
     * @p axial_force: the contact alone carries the axial force; the axial
     * stabilisation spring, whose force is below its stiffness times the
     * pose tolerance once the pose has converged, and the contact solver's
     * tolerance (@p relative_allowance times the axial force) bound the
     * difference.
     */
    double
    axial_balance(const double                axial_force,
                  const dealii::Tensor<1, 3> &contact_resultant,
                  const double                relative_allowance) const;

    /** The inferior motion from the observations of motion_observations(). */
    static InferiorMotion
    inferior_motion(const Observations &observations);

  private:
    /** Refuse a tibia_inferior surface that is not flat enough. */
    void
    check_tray_flatness(
      const std::map<unsigned int,
                     std::array<dealii::types::global_dof_index, 3>> &nodes,
      const std::vector<dealii::Point<3>> &vertices) const;

    const Parameters::Gait parameters;
    const GaitLoads       &gait_loads;
  };
} // namespace TKR::Gait

#endif
