// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#include <tkr/wear/cross_shear.h>
#include <tkr/wear/cross_shear_laws.h>

#include <filesystem>

namespace TKR::Wear
{
  void
  CrossShearLaw::analyse_cycle(const CycleSliding &sliding)
  {
    ratio.clear();
    for (const auto &node : cycle_cross_shear(sliding))
      ratio.push_back(node.ratio);
  }

  ArchardCrossShearWear::ArchardCrossShearWear(
    const CrossShearTable &k_per_metre)
    : k_per_metre(k_per_metre)
  {}

  std::string
  ArchardCrossShearWear::law_description() const
  {
    return "Archard, k(cross-shear" +
           std::string(k_per_metre.depends_on_pressure() ? ", pressure" : "") +
           ") in mm^3/(N m) from <" +
           std::filesystem::path(k_per_metre.file()).filename().string() + ">";
  }

  double
  ArchardCrossShearWear::interval_depth(const CycleSliding &sliding,
                                        const unsigned int  i,
                                        const unsigned int  j) const
  {
    const IntervalSliding &interval = sliding.interval(i);
    const double           pa       = interval.pressure_start[j];
    const double           pb       = interval.pressure_end[j];
    // k in mm^3/(N mm) = mm^2/N: the table's mm^3/(N m) x 1e-3.
    return 0.5e-3 *
           (k_per_metre.value(ratio[j], pa) * pa *
              interval.slip_start[j].norm() +
            k_per_metre.value(ratio[j], pb) * pb * interval.slip_end[j].norm());
  }

  AreaWear::AreaWear(const CrossShearTable &c)
    : c(c)
  {}

  std::string
  AreaWear::law_description() const
  {
    return "contact area, C(cross-shear) from <" +
           std::filesystem::path(c.file()).filename().string() + ">";
  }

  double
  AreaWear::interval_depth(const CycleSliding &sliding,
                           const unsigned int  i,
                           const unsigned int  j) const
  {
    return c.value(ratio[j]) * sliding.interval(i).slip_distance(j);
  }
} // namespace TKR::Wear
