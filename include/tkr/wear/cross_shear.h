// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#ifndef tkr_wear_cross_shear_h
#define tkr_wear_cross_shear_h

#include <deal.II/base/tensor.h>

#include <tkr/wear/sliding.h>

#include <string>
#include <vector>

namespace TKR::Wear
{
  /**
   * The cross-shear of one node's sliding over a gait cycle (doc/wear.md,
   * "Cross-shear"), the quadratic-work form: every slip increment s_k
   * under the pressure p_k does the frictional work w_k = mu p_k |s_k| per
   * unit area, and its part along a unit direction e is w_k cos^2 of the
   * angle between s_k and e, i.e. e . T e with the work tensor
   * T = sum_k p_k s_k (x) s_k / |s_k| (mu cancels). The principal
   * molecular orientation is the direction of most work, the eigenvector
   * of T's largest eigenvalue lambda_1 (a closed form, no search), and the
   * cross-shear ratio is the work perpendicular to it in the surface over
   * the total, lambda_2 / (lambda_1 + lambda_2): 0 for sliding along one
   * line, at most 1/2.
   */
  /**
   * How the cross-shear ratio is defined (`Wear/Cross-shear definition`,
   * doc/wear.md "Cross-shear"): work_tensor, the quadratic (sin^2)
   * projection above, the PMO in closed form, ratio in [0, 1/2];
   * abs_sin, the frictional work across the PMO by the |sin| of each
   * increment's angle to it, the PMO the direction of most work by |cos|
   * (found by an exact sweep over the angles where the projections change
   * sign), ratio in [0, 1/sqrt(2)]. Sliding along one line gives 0 in
   * both; a narrow ellipse of aspect e about e^2 log(1/e) and e.
   */
  enum class CrossShearDefinition
  {
    work_tensor,
    abs_sin
  };

  /** "work tensor" or "abs sin" (the entry's values). */
  CrossShearDefinition
  cross_shear_definition(const std::string &name);

  /** The largest ratio of @p definition (1/2, 1/sqrt(2)). */
  double
  largest_cross_shear(const CrossShearDefinition definition);

  struct CrossShear
  {
    /** The ratio of the definition (work_tensor: lambda_2 / (lambda_1 +
     *  lambda_2), in [0, 1/2]); 0 without sliding. */
    double ratio = 0;
    /** The principal molecular orientation (unit; its largest component
     *  positive); zero without sliding. */
    dealii::Tensor<1, 3> orientation;
    /** The frictional work per unit area over mu: sum_k p_k |s_k| (MPa mm).
     */
    double work = 0;
  };

  /** The cross-shear of the slip increments @p slips (mm) under the
   *  pressures @p pressures (MPa), by @p definition. */
  CrossShear
  cross_shear(
    const std::vector<dealii::Tensor<1, 3>> &slips,
    const std::vector<double>               &pressures,
    const CrossShearDefinition definition = CrossShearDefinition::work_tensor);

  /**
   * The cross-shear of every `tibia_contact` node over the cycle
   * @p sliding: each end of each interval where the node touches adds its
   * slip vector with half its pressure (the trapezoidal rule of Archard's
   * law, so that `work` times k is the Archard depth of the cycle).
   */
  std::vector<CrossShear>
  cycle_cross_shear(
    const CycleSliding        &sliding,
    const CrossShearDefinition definition = CrossShearDefinition::work_tensor);
} // namespace TKR::Wear

#endif
