// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#include <deal.II/base/utilities.h>

#include <tkr/base/csv_table.h>
#include <tkr/base/exceptions.h>
#include <tkr/gait/waveform.h>

#include <algorithm>
#include <cmath>

namespace TKR::Gait
{
  using namespace dealii;

  Waveform::Waveform(const std::string                   &filename,
                     std::vector<std::string>             channels,
                     const std::map<std::string, double> &scales)
    : filename(filename)
    , channel_names(std::move(channels))
  {
    std::vector<double> factor(channel_names.size(), 1.);
    for (const auto &[name, value] : scales)
      {
        const auto it =
          std::find(channel_names.begin(), channel_names.end(), name);
        std::string known;
        for (const std::string &channel : channel_names)
          known += (known.empty() ? "" : ", ") + channel;
        AssertThrow(it != channel_names.end(),
                    ExcInputError("Gait/Channel scales names <" + name +
                                  ">, which is not a channel of this "
                                  "protocol (" +
                                  known + ")."));
        factor[it - channel_names.begin()] = value;
      }
    std::vector<std::string> columns = {"percent_cycle"};
    columns.insert(columns.end(), channel_names.begin(), channel_names.end());
    const CsvTable table(filename,
                         "waveform file",
                         columns,
                         {},
                         "percent_cycle and the protocol's channels, e.g. "
                         "percent_cycle,flexion_deg,axial_force_N,"
                         "ap_force_N,ie_torque_Nm",
                         "doc/gait.md");
    for (unsigned int r = 0; r < table.n_rows(); ++r)
      {
        const double percent = table(r, "percent_cycle");
        AssertThrow(
          percents.empty() ? percent == 0. : percent > percents.back(),
          ExcInputError(table.where(r) + (percents.empty() ?
                                            "the first row must be at 0 %." :
                                            "percentages must increase.")));
        AssertThrow(percent <= 100.,
                    ExcInputError(table.where(r) + "percent above 100."));
        percents.push_back(percent);
        rows.emplace_back(table.row(r).begin() + 1, table.row(r).end());
        for (unsigned int c = 0; c < factor.size(); ++c)
          rows.back()[c] *= factor[c];
      }
    AssertThrow(rows.size() >= 2,
                ExcInputError(table.name() +
                              " needs at least two rows of data."));
    if (percents.back() == 100.)
      {
        AssertThrow(rows.back() == rows.front(),
                    ExcInputError(table.name() +
                                  ": the row at 100 % must repeat the row "
                                  "at 0 % (the cycle is periodic)."));
        percents.pop_back();
        rows.pop_back();
        return;
      }
    check_coverage();
  }

  // Rows up to 99 % every 1 % cover the cycle (the last interval blends
  // into 0 %); rows that stop at 50 % do not.
  void
  Waveform::check_coverage() const
  {
    double spacing = 0;
    for (unsigned int i = 1; i < percents.size(); ++i)
      spacing = std::max(spacing, percents[i] - percents[i - 1]);
    AssertThrow(100. - percents.back() <= spacing,
                ExcInputError(
                  "The waveform file <" + filename + "> covers 0 to " +
                  format_number(percents.back()) +
                  " % of the cycle only: its rows must reach 100 % (the "
                  "row at 100 % repeating the one at 0 %) or come closer "
                  "to it than the table's row spacing (" +
                  format_number(spacing) + " %)."));
  }

  std::vector<double>
  Waveform::at(const double percent) const
  {
    const double p = percent - 100. * std::floor(percent / 100.);
    unsigned int i = 0;
    while (i + 1 < percents.size() && percents[i + 1] <= p)
      ++i;
    const auto  &a         = rows[i];
    const auto  &b         = rows[(i + 1) % rows.size()];
    const double b_percent = (i + 1 < rows.size() ? percents[i + 1] : 100.);
    const double s         = (p - percents[i]) / (b_percent - percents[i]);
    std::vector<double> values(a.size());
    for (unsigned int c = 0; c < a.size(); ++c)
      values[c] = (1 - s) * a[c] + s * b[c];
    return values;
  }
} // namespace TKR::Gait
