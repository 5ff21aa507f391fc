// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#ifndef tkr_gait_rigid_motion_h
#define tkr_gait_rigid_motion_h

#include <deal.II/base/numbers.h>
#include <deal.II/base/point.h>
#include <deal.II/base/symmetric_tensor.h>
#include <deal.II/base/tensor.h>

#include <cmath>

namespace TKR::Gait
{
  /**
   * A rigid motion x = R X + t (mm), e.g. the femur's flexion in a gait
   * step (GaitLoads::femur_motion()). R is a finite rotation: nothing here
   * is linearised.
   */
  struct RigidMotion
  {
    dealii::Tensor<2, 3> rotation = dealii::unit_symmetric_tensor<3>();
    dealii::Tensor<1, 3> translation;

    dealii::Point<3>
    operator()(const dealii::Point<3> &X) const
    {
      return dealii::Point<3>(rotation * X + translation);
    }

    /** The inverse motion applied to @p x. */
    dealii::Point<3>
    inverse(const dealii::Point<3> &x) const
    {
      return dealii::Point<3>(transpose(rotation) * (x - translation));
    }

    /** For Utilities::pack() and checkpoints. */
    template <class Archive>
    void
    serialize(Archive &archive, const unsigned int)
    {
      archive &rotation &translation;
    }

    /**
     * The rotation by @p degrees (right-handed) about the line through
     * @p point along the coordinate axis @p axis (0: x, 1: y, 2: z).
     */
    static RigidMotion
    rotation_about(const unsigned int      axis,
                   const double            degrees,
                   const dealii::Point<3> &point)
    {
      const double       theta = degrees * dealii::numbers::PI / 180.;
      const unsigned int i = (axis + 1) % 3, j = (axis + 2) % 3;
      RigidMotion        motion;
      motion.rotation[i][i] = std::cos(theta);
      motion.rotation[i][j] = -std::sin(theta);
      motion.rotation[j][i] = std::sin(theta);
      motion.rotation[j][j] = std::cos(theta);
      motion.translation    = point - motion.rotation * point;
      return motion;
    }
  };

  /**
   * The femur's rigid motion in the tibia's frame (DESIGN.md section 10):
   * with the femur moved by F and the tibia by T (both rigid, in the
   * simulator's frame), a femur point X is at T^{-1}(F(X)) in the frame in
   * which the tibia's mesh lies. Contact and wear see only this motion:
   * the coupling places the femur's vertices there, and the slip of a
   * tibia node between two steps is the change of this motion at the
   * femur point it touches, minus the change of its elastic displacement.
   * Kept as the pair (F, T) and composed at every use, never linearised:
   * a protocol may prescribe or solve any finite tibial rotation.
   */
  struct RelativeMotion
  {
    /** The femur's motion F (e.g. the flexion). */
    RigidMotion femur;
    /** The tibia's motion T (its pose). */
    RigidMotion tibia;

    /** T^{-1}(F(X)): where the femur point @p X is in the tibia's frame. */
    dealii::Point<3>
    operator()(const dealii::Point<3> &X) const
    {
      return tibia.inverse(femur(X));
    }

    /** F^{-1}(T(x)): the femur point at @p x of the tibia's frame. */
    dealii::Point<3>
    inverse(const dealii::Point<3> &x) const
    {
      return femur.inverse(tibia(x));
    }

    /**
     * R_T^T R_F: the rotation of the femur in the tibia's frame, which
     * turns the femur's (co-rotated) displacement into that frame.
     */
    dealii::Tensor<2, 3>
    rotation() const
    {
      return transpose(tibia.rotation) * femur.rotation;
    }

    template <class Archive>
    void
    serialize(Archive &archive, const unsigned int)
    {
      archive &femur &tibia;
    }
  };
} // namespace TKR::Gait

#endif
