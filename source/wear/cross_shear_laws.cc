// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#include <tkr/wear/cross_shear.h>
#include <tkr/wear/cross_shear_laws.h>

#include <filesystem>

namespace TKR::Wear
{
  namespace
  {
    /**
     * The entries of a law with a table of its coefficient over the
     * cross-shear: `Wear/@p subsection/Cross-shear table`, whose columns
     * are @p columns, and its Table scale (the rate entry); the table must
     * be given. Its example: the EXAMPLE table @p example of data/wear/.
     */
    ModelEntries
    table_entries(const std::string              &subsection,
                  const std::string              &columns,
                  const std::string              &example,
                  const std::vector<std::string> &traits = {})
    {
      return {
        subsection,
        [columns](dealii::ParameterHandler &prm) {
          prm.declare_entry(
            "Cross-shear table",
            "",
            dealii::Patterns::FileName(),
            "CSV file of the law's coefficient over the cross-shear ratio "
            "(columns " +
              columns +
              "); piecewise linear, constant beyond the first and last row "
              "(doc/wear.md, Cross-shear tables). The cross-shear column "
              "is a ratio from 0 to 0.5. data/wear/ has EXAMPLE tables "
              "only: no published coefficients are shipped. A relative "
              "path is taken from the directory of the parameter file that "
              "sets it, then from the working directory.");
          prm.declare_entry(
            "Table scale",
            "1",
            dealii::Patterns::Double(0),
            "A factor on the table's coefficient (1: the table as it is): "
            "what Problem = calibration fits to measured wear when the "
            "table's shape is known and its level is not "
            "(doc/calibration.md).");
        },
        [](const dealii::ParameterHandler &prm) -> std::any {
          return CrossShearLawParameters{prm.get("Cross-shear table"),
                                         prm.get_double("Table scale")};
        },
        {"Cross-shear table"},
        {"Cross-shear table"},
        "Table scale",
        [](const std::any &own) -> std::string {
          return std::any_cast<const CrossShearLawParameters &>(own)
                     .cross_shear_table.empty() ?
                   "Cross-shear table, a CSV file of its coefficient over "
                   "the cross-shear (doc/wear.md; data/wear/ has example "
                   "tables)." :
                   "";
        },
        {{"Cross-shear table", "data/wear/" + example}},
        traits};
    }

    /**
     * The table of a law's own entries @p own (CrossShearLawParameters),
     * its @p coefficient column, scaled.
     */
    template <typename Law>
    std::unique_ptr<WearLaw>
    make_table_law(const Parameters::Wear &parameters,
                   const std::any         &own,
                   const std::string      &coefficient,
                   const bool              may_have_pressure)
    {
      const auto &entries = std::any_cast<const CrossShearLawParameters &>(own);
      return std::make_unique<Law>(
        CrossShearTable(entries.cross_shear_table,
                        coefficient,
                        may_have_pressure,
                        cross_shear_definition(
                          parameters.cross_shear_definition)),
        entries.table_scale);
    }

    [[maybe_unused]] const bool archard_cs_registered = WearLaws::add(
      {"archard_cs",
       "Archard's law with k from its Cross-shear table (Wear/Archard cs) "
       "as a function of each node's cross-shear over the cycle (and of the "
       "pressure if the table has a pressure_MPa column)",
       table_entries("Archard cs",
                     "cross_shear, k_mm3_per_Nm in mm^3/(N m) and optionally "
                     "pressure_MPa",
                     "example-archard-cs.csv"),
       [](const Parameters::Wear &parameters, const std::any &own) {
         return make_table_law<ArchardCrossShearWear>(parameters,
                                                      own,
                                                      "k_mm3_per_Nm",
                                                      true);
       }});

    [[maybe_unused]] const bool area_registered = WearLaws::add(
      {"area",
       "the contact-area law, worn volume = C x contact area x sliding "
       "distance, i.e. depth rate C(cross-shear) |v_t| whatever the "
       "pressure, C from its Cross-shear table (Wear/Area)",
       table_entries("Area",
                     "cross_shear, C: dimensionless",
                     "example-area-law.csv",
                     {"rate-changes-with-wear"}),
       [](const Parameters::Wear &parameters, const std::any &own) {
         return make_table_law<AreaWear>(parameters, own, "C", false);
       }});
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
    const CrossShearTable &k_per_metre,
    const double           scale)
    : k_per_metre(k_per_metre)
    , scale(scale)
  {}

  std::string
  ArchardCrossShearWear::law_description() const
  {
    return "Archard, k(cross-shear" +
           std::string(k_per_metre.depends_on_pressure() ? ", pressure" : "") +
           ") in mm^3/(N m) from <" +
           std::filesystem::path(k_per_metre.file()).filename().string() + ">" +
           (scale == 1 ? "" : " x " + std::to_string(scale));
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
    return 0.5e-3 * scale *
           (k_per_metre.value(ratio[j], pa) * pa *
              interval.slip_start[j].norm() +
            k_per_metre.value(ratio[j], pb) * pb * interval.slip_end[j].norm());
  }

  AreaWear::AreaWear(const CrossShearTable &c, const double scale)
    : c(c)
    , scale(scale)
  {}

  std::string
  AreaWear::law_description() const
  {
    return "contact area, C(cross-shear) from <" +
           std::filesystem::path(c.file()).filename().string() + ">" +
           (scale == 1 ? "" : " x " + std::to_string(scale));
  }

  double
  AreaWear::interval_depth(const CycleSliding &sliding,
                           const unsigned int  i,
                           const unsigned int  j) const
  {
    return scale * c.value(ratio[j]) * sliding.interval(i).slip_distance(j);
  }
} // namespace TKR::Wear
