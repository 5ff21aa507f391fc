// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#ifndef tkr_wear_surface_sides_h
#define tkr_wear_surface_sides_h

#include <tkr/wear/cross_shear.h>
#include <tkr/wear/wear_state.h>

#include <vector>

namespace TKR::Wear
{
  /**
   * The measures of one block on the worn surface's tibia_contact nodes:
   * their nodal areas before the block's wear moved them (the block's
   * volume and wear area are measured on these), which nodes are medial,
   * and the cross-shear of the block's cycle. Gives the medial and lateral
   * results and the work-weighted cross-shear means (doc/wear.md).
   */
  class SurfaceSides
  {
  public:
    SurfaceSides() = default;

    /**
     * @p x: each node's medial-lateral coordinate (mm); a node is medial
     * beyond the middle of their range towards @p medial_direction (+1 or
     * -1, `Gait/Medial side`). @p areas: the nodal areas (mm^2).
     */
    SurfaceSides(const std::vector<double> &x,
                 const int                  medial_direction,
                 std::vector<double>        areas);

    /** The nodal areas (mm^2). */
    const std::vector<double> &
    areas() const
    {
      return nodal_areas;
    }

    /** Whether each node is medial. */
    const std::vector<bool> &
    medial() const
    {
      return is_medial;
    }

    /**
     * The mean cross-shear of @p cross_shear over the nodes (of one side if
     * @p side is 1 (medial) or 0 (lateral), of all if -1), weighted by each
     * node's frictional work times its area (where the insert wears by
     * Archard's law); 0 if nothing slid or the sizes differ (a resumed run
     * before its first cycle).
     */
    double
    mean_cross_shear(const std::vector<CrossShear> &cross_shear,
                     const int                      side = -1) const;

    /**
     * One side's result: its @p volume (mm^3), the largest and the worn
     * area (depth > @p threshold, mm) of the accumulated @p node_depth
     * (mm) on that side, and its mean cross-shear.
     */
    SideResult
    side_result(const std::vector<double>     &node_depth,
                const bool                     on_medial,
                const double                   volume,
                const double                   threshold,
                const std::vector<CrossShear> &cross_shear) const;

  private:
    std::vector<double> nodal_areas;
    std::vector<bool>   is_medial;
  };
} // namespace TKR::Wear

#endif
