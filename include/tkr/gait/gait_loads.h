// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#ifndef tkr_gait_gait_loads_h
#define tkr_gait_gait_loads_h

#include <deal.II/base/point.h>
#include <deal.II/base/tensor.h>

#include <deal.II/grid/tria.h>

#include <tkr/elasticity/linear_elasticity.h>
#include <tkr/gait/rigid_motion.h>
#include <tkr/parameters/parameters.h>

namespace TKR::Gait
{
  /** The load-controlled simulator inputs at one instant of the cycle. */
  struct GaitState
  {
    /** Percent of the cycle, [0, 100). */
    double percent = 0;
    /** Flexion angle in degrees. */
    double flexion = 0;
    /** Axial force in N (compressive, pushes the tibia onto the femur). */
    double axial_force = 0;
    /** AP force in N, as tabulated (sign conventions applied later). */
    double ap_force = 0;
    /** IE torque in N m, as tabulated. */
    double ie_torque = 0;
  };

  /**
   * Area moments of the tibial inferior surface about its centroid (in the
   * x-y plane), for distributing forces, torques and springs over it, and
   * the medial-lateral width of the insert.
   */
  struct InferiorSurface
  {
    double           area = 0;
    dealii::Point<3> centroid;
    /** int (x-xc)^2, int (y-yc)^2, int r^2, int r^4 over the surface. */
    double I_xx = 0, I_yy = 0, J = 0, R4 = 0;
    /** Medial-lateral (x) extent of the tibia, mm. */
    double width = 0;
  };

  /**
   * ISO 14243-1's AP and IE restraints (two-rate springs) and the signs of
   * the tabulated AP force and IE torque: the entries of `Gait/Force
   * control` (ForceControl). Without them (the defaults here): no
   * restraint, the table's signs.
   */
  struct Restraints
  {
    /** Stiffnesses within +- the range (N/mm, N mm/deg), the range (mm,
     *  deg), the stiffnesses beyond it. */
    double ap_spring_stiffness = 0, ap_spring_range = 0,
           ap_spring_stiffness_beyond = 0;
    double ie_spring_stiffness = 0, ie_spring_range = 0,
           ie_spring_stiffness_beyond = 0;
    /** Signs applied to the tabulated AP force and IE torque. */
    double ap_force_sign = 1, ie_torque_sign = 1;
  };

  /** Measure the `tibia_inferior` surface and the tibia's width. */
  InferiorSurface
  measure_inferior_surface(const dealii::Triangulation<3> &triangulation);

  /**
   * The ISO 14243-1 loads of one gait state on the tibia, and the femur's
   * rigid flexion rotation (DESIGN.md section 2).
   *
   * Conventions (x medial-lateral, y anterior, z proximal): flexion by an
   * angle theta rotates the femur by +theta about the +x axis through the
   * flexion axis point (the femoral shaft turns from +z towards -y, the
   * posterior condyles come down). The axial force pushes the tibia along
   * +z, its line of action offset medially by `Axial load offset` x width.
   * The AP force acts along +y (anterior) times `AP force sign`. A positive
   * IE torque rotates the tibia internally (its anterior side towards
   * medial), i.e. about -z if medial is +x, times `IE torque sign`.
   *
   * All act on `tibia_inferior` as tractions: the axial force as a uniform
   * part plus a linear part carrying the offset moment, the AP force
   * uniform, the torque as a traction proportional to the distance from
   * the centroid. The restraint springs are distributed springs whose
   * stiffness against a rigid translation in y is the AP stiffness and
   * against a rigid rotation about z through the centroid the IE
   * stiffness; in x they add a by-product of the rotation spring to the ML
   * stiffness.
   */
  class GaitLoads
  {
  public:
    GaitLoads(const Parameters::Gait &parameters,
              const Restraints       &restraints,
              const InferiorSurface  &surface);

    /** The restraints and the load signs. */
    const Restraints &
    restraints() const
    {
      return restraint;
    }

    /** Tractions and springs on `tibia_inferior` for @p state. */
    Elasticity::BoundaryLoads
    loads(const GaitState &state) const;

    /**
     * The tractions on `tibia_inferior` of a unit axial force (N, along +z,
     * with its medial offset), a unit AP force (N, along +y) and a unit
     * torque about +z (N mm): every traction of the gait and of the
     * restraints is a combination of these three.
     */
    std::vector<Elasticity::BoundaryLoads>
    traction_basis() const;

    /**
     * The coefficients of the gait's tractions in @p state on
     * traction_basis(): axial force, AP force (N), torque about +z (N mm).
     */
    std::vector<double>
    resultants(const GaitState &state) const;

    /** The restraint springs on `tibia_inferior` (no tractions). */
    Elasticity::BoundaryLoads
    springs() const;

    /**
     * The two-rate restraint law's force beyond its inner, linear rate
     * (which the springs of loads() carry): the AP force (N, along +y) on
     * the tibia at an AP translation @p d (mm), zero within the AP spring
     * range, -(k_beyond - k) (|d| - range) sign(d) outside; the range is
     * measured from the restraint's neutral position, minus `Femur AP
     * offset`.
     */
    double
    ap_restraint_excess(const double d) const;

    /**
     * The same for the IE restraint: the torque about +z (N mm) at a
     * rotation @p theta about +z (deg).
     */
    double
    ie_restraint_excess(const double theta) const;

    /**
     * A traction on `tibia_inferior` with the resultant force @p force_y
     * along +y through the centroid and the torque @p torque_z about +z
     * (N, N mm), distributed as the AP force and the IE torque are.
     */
    Elasticity::BoundaryLoads::TractionField
    restraint_traction(const double force_y, const double torque_z) const;

    /** The measures of the inferior surface. */
    const InferiorSurface &
    inferior_surface() const
    {
      return surface;
    }

    /**
     * The femur's rigid flexion motion in @p state: the rotation by the
     * flexion angle about the x axis through the flexion axis point,
     * x = P + R (X - P).
     */
    RigidMotion
    femur_motion(const GaitState &state) const;

    /** Centroid of the inferior surface. */
    const dealii::Point<3> &
    inferior_centroid() const
    {
      return surface.centroid;
    }

    /** Area of the inferior surface (mm^2). */
    double
    inferior_area() const
    {
      return surface.area;
    }

    /** The prescribed resultant force (N) on the tibia. */
    dealii::Tensor<1, 3>
    force(const GaitState &state) const;

    /**
     * The prescribed resultant moment (N mm) about the centroid of the
     * inferior surface: the axial offset's moment about y and the IE
     * torque about z.
     */
    dealii::Tensor<1, 3>
    moment(const GaitState &state) const;

  private:
    const Parameters::Gait parameters;
    const Restraints       restraint;
    const InferiorSurface  surface;
  };
} // namespace TKR::Gait

#endif
