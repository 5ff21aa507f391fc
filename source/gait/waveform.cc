// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#include <deal.II/base/utilities.h>

#include <tkr/base/exceptions.h>
#include <tkr/gait/waveform.h>

#include <algorithm>
#include <cmath>
#include <fstream>

namespace TKR::Gait
{
  using namespace dealii;

  Waveform::Waveform(const std::string       &filename,
                     std::vector<std::string> channels)
    : filename(filename)
    , channel_names(std::move(channels))
  {
    std::ifstream in(filename);
    AssertThrow(in.good(),
                ExcInputError("Cannot open the waveform file <" + filename +
                              ">: it does not exist or is not readable."));
    std::string               line;
    unsigned int              line_number = 0;
    std::vector<unsigned int> columns;
    unsigned int              n_columns = 0;
    std::vector<double>       last_row;
    while (std::getline(in, line))
      {
        ++line_number;
        const std::string trimmed = Utilities::trim(line);
        if (trimmed.empty() || trimmed[0] == '#')
          continue;
        const auto        fields = Utilities::split_string_list(trimmed, ',');
        const std::string where  = "Line <" + std::to_string(line_number) +
                                  "> of the waveform file <" + filename + ">: ";
        if (columns.empty())
          {
            columns   = find_columns(trimmed, line_number);
            n_columns = fields.size();
            continue;
          }
        AssertThrow(fields.size() == n_columns,
                    ExcInputError(where + "expected " +
                                  std::to_string(n_columns) +
                                  " comma-separated values (one per column "
                                  "of the header), found " +
                                  std::to_string(fields.size()) + "."));
        std::vector<double> values;
        try
          {
            values = Utilities::string_to_double(fields);
          }
        catch (...)
          {
            AssertThrow(false,
                        ExcInputError(where + "a value is not a number."));
          }
        const double percent = values[columns[0]];
        AssertThrow(percents.empty() ? percent == 0. :
                                       percent > percents.back(),
                    ExcInputError(where + (percents.empty() ?
                                             "the first row must be at 0 %." :
                                             "percentages must increase.")));
        AssertThrow(percent <= 100.,
                    ExcInputError(where + "percent above 100."));
        std::vector<double> row;
        for (unsigned int c = 1; c < columns.size(); ++c)
          row.push_back(values[columns[c]]);
        percents.push_back(percent);
        rows.push_back(row);
      }
    AssertThrow(!columns.empty(),
                ExcInputError("The waveform file <" + filename +
                              "> has no header line naming its columns."));
    AssertThrow(rows.size() >= 2,
                ExcInputError("The waveform file <" + filename +
                              "> needs at least two rows of data."));
    if (percents.back() == 100.)
      {
        AssertThrow(rows.back() == rows.front(),
                    ExcInputError("The waveform file <" + filename +
                                  ">: the row at 100 % must repeat the row "
                                  "at 0 % (the cycle is periodic)."));
        percents.pop_back();
        rows.pop_back();
        return;
      }
    check_coverage();
  }

  std::vector<unsigned int>
  Waveform::find_columns(const std::string &header,
                         const unsigned int line) const
  {
    const auto names   = Utilities::split_string_list(header, ',');
    bool       numbers = true;
    try
      {
        Utilities::string_to_double(names);
      }
    catch (...)
      {
        numbers = false;
      }
    AssertThrow(!numbers,
                ExcInputError("Line <" + std::to_string(line) +
                              "> of the waveform file <" + filename +
                              ">: the first line that is not a comment must "
                              "be a header naming the columns (percent_cycle "
                              "and the protocol's channels, e.g. "
                              "percent_cycle,flexion_deg,axial_force_N,"
                              "ap_force_N,ie_torque_Nm), not numbers."));
    std::vector<unsigned int> columns;
    std::vector<std::string>  wanted = {"percent_cycle"};
    wanted.insert(wanted.end(), channel_names.begin(), channel_names.end());
    for (const auto &name : wanted)
      {
        const auto  it = std::find(names.begin(), names.end(), name);
        std::string list;
        for (const auto &n : names)
          list += (list.empty() ? "" : ", ") + n;
        AssertThrow(it != names.end(),
                    ExcInputError("Line <" + std::to_string(line) +
                                  "> of the waveform file <" + filename +
                                  ">: the header (" + list +
                                  ") has no column named " + name +
                                  "; the columns are found by their names "
                                  "in the first line that is not a comment "
                                  "(doc/gait.md)."));
        columns.push_back(it - names.begin());
      }
    return columns;
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
