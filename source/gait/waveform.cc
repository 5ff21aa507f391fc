// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#include <deal.II/base/utilities.h>

#include <tkr/base/exceptions.h>
#include <tkr/gait/waveform.h>

#include <cmath>
#include <fstream>

namespace TKR::Gait
{
  using namespace dealii;

  Waveform::Waveform(const std::string &filename)
  {
    std::ifstream in(filename);
    AssertThrow(in.good(),
                ExcInputError("Cannot open the waveform file <" + filename +
                              ">: it does not exist or is not readable."));
    std::string  line;
    unsigned int line_number = 0;
    while (std::getline(in, line))
      {
        ++line_number;
        const std::string trimmed = Utilities::trim(line);
        if (trimmed.empty() || trimmed[0] == '#' ||
            trimmed.rfind("percent", 0) == 0)
          continue;
        const auto        fields = Utilities::split_string_list(trimmed, ',');
        const std::string where  = "Line <" + std::to_string(line_number) +
                                  "> of the waveform file <" + filename + ">: ";
        AssertThrow(fields.size() == 5,
                    ExcInputError(where +
                                  "expected 5 comma-separated values "
                                  "(percent, flexion, axial force, "
                                  "AP force, IE torque), found " +
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
        const GaitState row{values[0],
                            values[1],
                            values[2],
                            values[3],
                            values[4]};
        AssertThrow(rows.empty() ? row.percent == 0. :
                                   row.percent > rows.back().percent,
                    ExcInputError(where + (rows.empty() ?
                                             "the first row must be at 0 %." :
                                             "percentages must increase.")));
        AssertThrow(row.percent <= 100.,
                    ExcInputError(where + "percent above 100."));
        rows.push_back(row);
      }
    AssertThrow(rows.size() >= 2,
                ExcInputError("The waveform file <" + filename +
                              "> needs at least two rows of data."));
    if (rows.back().percent == 100.)
      {
        const GaitState &first = rows.front(), &last = rows.back();
        AssertThrow(last.flexion == first.flexion &&
                      last.axial_force == first.axial_force &&
                      last.ap_force == first.ap_force &&
                      last.ie_torque == first.ie_torque,
                    ExcInputError("The waveform file <" + filename +
                                  ">: the row at 100 % must repeat the row "
                                  "at 0 % (the cycle is periodic)."));
        rows.pop_back();
      }
  }

  GaitState
  Waveform::at(const double percent) const
  {
    const double p = percent - 100. * std::floor(percent / 100.);
    unsigned int i = 0;
    while (i + 1 < rows.size() && rows[i + 1].percent <= p)
      ++i;
    const GaitState &a         = rows[i];
    const GaitState &b         = rows[(i + 1) % rows.size()];
    const double     b_percent = (i + 1 < rows.size() ? b.percent : 100.);
    const double     s         = (p - a.percent) / (b_percent - a.percent);
    GaitState        state;
    state.percent     = p;
    state.flexion     = (1 - s) * a.flexion + s * b.flexion;
    state.axial_force = (1 - s) * a.axial_force + s * b.axial_force;
    state.ap_force    = (1 - s) * a.ap_force + s * b.ap_force;
    state.ie_torque   = (1 - s) * a.ie_torque + s * b.ie_torque;
    return state;
  }
} // namespace TKR::Gait
