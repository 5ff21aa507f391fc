// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#include <tkr/wear/archard.h>

#include <memory>
#include <sstream>

namespace TKR::Wear
{
  ArchardWear::ArchardWear(const double k_per_metre)
    : k_per_metre(k_per_metre)
    , k(1e-3 * k_per_metre)
  {}

  std::string
  ArchardWear::law_description() const
  {
    std::ostringstream text;
    text << "Archard, k = " << k_per_metre << " mm^3/(N m)";
    return text.str();
  }

  namespace
  {
    ModelEntries
    archard_entries()
    {
      return {"Archard",
              [](dealii::ParameterHandler &prm) {
                prm.declare_entry("Wear coefficient",
                                  "2e-7",
                                  dealii::Patterns::Double(0),
                                  "Archard wear coefficient k in "
                                  "mm^3/(N m) (Wear law = archard).");
              },
              [](const dealii::ParameterHandler &prm) -> std::any {
                return ArchardParameters{prm.get_double("Wear coefficient")};
              },
              {},
              {"Wear coefficient"},
              "Wear coefficient"};
    }

    [[maybe_unused]] const bool registered = WearLaws::add(
      {"archard",
       "Archard's law with the constant Wear coefficient k, depth rate k p "
       "|v_t| (the reference paper's model)",
       archard_entries(),
       [](const Parameters::Wear &,
          const std::any &own) -> std::unique_ptr<WearLaw> {
         return std::make_unique<ArchardWear>(
           std::any_cast<const ArchardParameters &>(own).wear_coefficient);
       }});
  } // namespace

  double
  ArchardWear::interval_depth(const CycleSliding &sliding,
                              const unsigned int  i,
                              const unsigned int  j) const
  {
    const IntervalSliding &interval = sliding.interval(i);
    return 0.5 * k *
           (interval.pressure_start[j] * interval.slip_start[j].norm() +
            interval.pressure_end[j] * interval.slip_end[j].norm());
  }
} // namespace TKR::Wear
