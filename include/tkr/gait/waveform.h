// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#ifndef tkr_gait_waveform_h
#define tkr_gait_waveform_h

#include <map>
#include <string>
#include <vector>

namespace TKR::Gait
{
  /**
   * Gait waveforms: a CSV table of channels over the cycle, read by column
   * name. The first line that is neither empty nor a '#' comment is the
   * header naming the columns; one of them is `percent_cycle`, the others
   * are channels (e.g. flexion_deg, axial_force_N). A protocol names the
   * channels it needs (any order; columns it does not need are ignored, so
   * a lab can keep its machine's other channels in the file). Rows give
   * the percent of the cycle, increasing from 0; they must cover the
   * whole cycle: the last row at 100 % (equal to the row at 0 %: the cycle
   * is periodic) or closer to 100 % than the table's largest row spacing,
   * in which case the values between the last row and 100 % blend into the
   * first row. Values are interpolated linearly and periodically.
   */
  class Waveform
  {
  public:
    /**
     * Read @p filename and keep the columns @p channels. ExcInputError
     * with file and line on bad input, naming the missing column or the
     * range of the cycle that the rows do not cover. Each channel named
     * in @p scales is multiplied by its factor (`Gait/Channel scales`; a
     * name that is not a channel is refused).
     */
    Waveform(const std::string                   &filename,
             std::vector<std::string>             channels,
             const std::map<std::string, double> &scales = {});

    /**
     * The values of the channels (in the order of the constructor) at
     * @p percent of the cycle (any real; taken modulo 100).
     */
    std::vector<double>
    at(const double percent) const;

    /** The channels, as given to the constructor. */
    const std::vector<std::string> &
    channels() const
    {
      return channel_names;
    }

    /** Number of table rows (a row at 100 % not counted). */
    unsigned int
    n_rows() const
    {
      return percents.size();
    }

    /** The file it was read from. */
    const std::string &
    file() const
    {
      return filename;
    }

  private:
    /** Refuse a table that does not cover the whole cycle. */
    void
    check_coverage() const;

    const std::string              filename;
    const std::vector<std::string> channel_names;
    std::vector<double>            percents;
    /** Per row, the values of the channels. */
    std::vector<std::vector<double>> rows;
  };
} // namespace TKR::Gait

#endif
