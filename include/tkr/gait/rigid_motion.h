// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#ifndef tkr_gait_rigid_motion_h
#define tkr_gait_rigid_motion_h

#include <deal.II/base/point.h>
#include <deal.II/base/symmetric_tensor.h>
#include <deal.II/base/tensor.h>

namespace TKR::Gait
{
  /**
   * A rigid motion x = R X + t (mm), e.g. the femur's flexion in a gait
   * step (GaitLoads::femur_motion()).
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
  };
} // namespace TKR::Gait

#endif
