// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#include <tkr/wear/surface_sides.h>
#include <tkr/wear/wear_law.h>

#include <algorithm>
#include <limits>

namespace TKR::Wear
{
  SurfaceSides::SurfaceSides(const std::vector<double> &x,
                             const int                  medial_direction,
                             std::vector<double>        areas)
    : nodal_areas(std::move(areas))
  {
    double lo = std::numeric_limits<double>::max(), hi = -lo;
    for (const double xj : x)
      {
        lo = std::min(lo, xj);
        hi = std::max(hi, xj);
      }
    for (const double xj : x)
      is_medial.push_back((xj - 0.5 * (lo + hi)) * medial_direction > 0);
  }

  // The mean of the ratio weighted by w_j = W_j A_j, the node's frictional
  // work per unit area over mu times its area: the nodes that slide most
  // under load, where the insert wears, count most.
  double
  SurfaceSides::mean_cross_shear(const std::vector<CrossShear> &cross_shear,
                                 const int                      side) const
  {
    double weighted = 0, weight = 0;
    if (nodal_areas.size() != cross_shear.size())
      return 0.;
    for (unsigned int j = 0; j < cross_shear.size(); ++j)
      {
        if (side >= 0 && is_medial[j] != (side == 1))
          continue;
        const double w = cross_shear[j].work * nodal_areas[j];
        weighted += w * cross_shear[j].ratio;
        weight += w;
      }
    return weight > 0 ? weighted / weight : 0.;
  }

  SideResult
  SurfaceSides::side_result(const std::vector<double>     &node_depth,
                            const bool                     on_medial,
                            const double                   volume,
                            const double                   threshold,
                            const std::vector<CrossShear> &cross_shear) const
  {
    std::vector<double> depth = node_depth;
    for (unsigned int j = 0; j < depth.size(); ++j)
      if (is_medial[j] != on_medial)
        depth[j] = 0;
    const auto measures = measure_wear(depth, nodal_areas, threshold);
    return {volume,
            measures.max_depth,
            measures.worn_percent(),
            mean_cross_shear(cross_shear, on_medial ? 1 : 0)};
  }
} // namespace TKR::Wear
