// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#include <tkr/wear/cross_shear.h>
#include <tkr/wear/cross_shear_laws.h>

#include <filesystem>

namespace TKR::Wear
{
  namespace
  {
    /** The laws with a coefficient over the cross-shear need its table. */
    std::string
    table_missing(const Parameters::Wear &parameters)
    {
      return parameters.cross_shear_table.empty() ?
               "Wear/Wear law = " + parameters.law +
                 " needs Wear/Cross-shear table, a CSV file of its "
                 "coefficient over the cross-shear (doc/wear.md; data/wear/ "
                 "has example tables)." :
               "";
    }

    /** Their input file: the table, guarded by a checkpoint. */
    WearLawPlugin::Files
    table_file(const Parameters::Wear &parameters)
    {
      return {{"Cross-shear table", parameters.cross_shear_table}};
    }

    [[maybe_unused]] const bool archard_cs_registered = WearLaws::add(
      {"archard_cs",
       "Archard's law with k from the Cross-shear table as a function of "
       "each node's cross-shear over the cycle (and of the pressure if the "
       "table has a pressure_MPa column)",
       table_missing,
       [](const Parameters::Wear &parameters) -> std::unique_ptr<WearLaw> {
         return std::make_unique<ArchardCrossShearWear>(
           CrossShearTable(parameters.cross_shear_table, "k_mm3_per_Nm", true));
       },
       table_file});

    [[maybe_unused]] const bool area_registered = WearLaws::add(
      {"area",
       "the contact-area law, worn volume = C x contact area x sliding "
       "distance, i.e. depth rate C(cross-shear) |v_t| whatever the "
       "pressure, C from the Cross-shear table",
       table_missing,
       [](const Parameters::Wear &parameters) -> std::unique_ptr<WearLaw> {
         return std::make_unique<AreaWear>(
           CrossShearTable(parameters.cross_shear_table, "C", false));
       },
       table_file});
  } // namespace

  void
  CrossShearLaw::analyse_cycle(const CycleSliding &,
                               const std::vector<CrossShear> &cross_shear)
  {
    ratio.clear();
    for (const auto &node : cross_shear)
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
