// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#ifndef tkr_wear_activity_mix_h
#define tkr_wear_activity_mix_h

#include <tkr/wear/wear_law.h>

#include <vector>

namespace TKR::Wear
{
  /**
   * The wear of one cycle of an activity mix (`Gait/Activities`): the
   * activities' cycles @p wear weighted by their @p shares (which add up
   * to 1), node by node: the depth, the slip and the law's fields are the
   * share-weighted sums; the cross-shear's work is the share-weighted sum
   * of the works, its ratio the work-weighted mean of the ratios and its
   * orientation that of the activity with the most work at the node. The
   * intervals are the activities' own and are not mixed (empty). A mix of
   * one activity with share 1 is that activity's wear.
   */
  CycleWear
  mix_cycle_wear(const std::vector<CycleWear> &wear,
                 const std::vector<double>    &shares);
} // namespace TKR::Wear

#endif
