// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#ifndef tkr_wear_archard_h
#define tkr_wear_archard_h

#include <tkr/mortar/mortar_coupling.h>
#include <tkr/wear/step_record.h>

#include <vector>

namespace TKR::Wear
{
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
