// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#ifndef tkr_wear_archard_h
#define tkr_wear_archard_h

#include <deal.II/base/point.h>
#include <deal.II/base/tensor.h>

#include <tkr/contact/active_set_solver.h>
#include <tkr/mortar/mortar_coupling.h>

#include <vector>

namespace TKR::Wear
{
  /** A rigid motion x = R X + t of the femur (mm). */
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
  };

  /**
   * What one gait step leaves for the wear computation, per slave
   * (`tibia_contact`) node: contact pressure (0 where not in contact), the
   * femur material point it touches (in the femur's reference
   * configuration), its displacement and its normal.
   */
  struct StepRecord
  {
    RigidMotion                       femur_motion;
    std::vector<double>               pressure;
    std::vector<dealii::Point<3>>     femur_point;
    std::vector<dealii::Tensor<1, 3>> displacement;
    std::vector<dealii::Tensor<1, 3>> normal;
  };

  /**
   * The record of a contact solve: pressures of the active nodes, and as
   * femur material point the mortar projection of each node mapped back
   * through the femur's motion.
   */
  StepRecord
  make_step_record(const Mortar::MortarCoupling &coupling,
                   const Contact::ContactState  &state,
                   const RigidMotion            &femur_motion);

  /**
   * The wear depth (mm) of every node over the interval from step @p a to
   * step @p b (the trapezoidal rule of cycle_wear_depth()); @p slip (if
   * given) gets each node's slip over the interval (mm; the mean of the
   * slips from the points touched at both ends, or the one where the node
   * touched, zero where it touched at neither).
   */
  std::vector<double>
  interval_wear_depth(const StepRecord    &a,
                      const StepRecord    &b,
                      const double         k,
                      std::vector<double> *slip = nullptr);

  /**
   * Archard's law dh/dt = k p |v_t| integrated over one periodic cycle of
   * steps with the trapezoidal rule. Between steps i and i+1 (the last step
   * followed by the first) the femur point that node j touches at step i
   * moves by M_{i+1}(X) - M_i(X) while the node moves by
   * u_{i+1} - u_i; the tangential part of the difference is the slip s.
   * The depth increment is k (p_i s(X_i) + p_{i+1} s(X_{i+1})) / 2.
   *
   * @p k in mm^3/(N mm) (the `.prm` value in mm^3/(N m) times 1e-3), the
   * result in mm per node; @p slip (if given) gets the slip distance of
   * every node over the whole cycle (mm, pressure-independent: summed where
   * the node is in contact at either end of the interval).
   */
  std::vector<double>
  cycle_wear_depth(const std::vector<StepRecord> &steps,
                   const double                   k,
                   std::vector<double>           *slip = nullptr);

  /** Worn volume (mm^3): sum of nodal depth times D_jj. */
  double
  worn_volume(const std::vector<double>    &depth,
              const Mortar::MortarCoupling &coupling);
} // namespace TKR::Wear

#endif
