// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#ifndef tkr_gait_waveform_h
#define tkr_gait_waveform_h

#include <string>
#include <vector>

namespace TKR::Gait
{
  /** The load-controlled simulator inputs at one instant of the cycle. */
  struct GaitState
  {
    /** Percent of the cycle, [0, 100). */
    double percent = 0;
    /** Flexion angle in degrees. */
    double flexion = 0;
    /** Axial force in N (compressive, pushes the tibia onto the femur). */
    double axial_force = 0;
    /** AP force in N, as tabulated (sign conventions applied later). */
    double ap_force = 0;
    /** IE torque in N m, as tabulated. */
    double ie_torque = 0;
  };

  /**
   * The gait waveforms of a CSV table with the columns percent_cycle,
   * flexion_deg, axial_force_N, ap_force_N, ie_torque_Nm (a header line and
   * '#' comment lines allowed), interpolated linearly and periodically: the
   * cycle repeats, so values between the last row and 100 % blend into the
   * first row. The first row must be at 0 %, percentages must increase and
   * stay below or at 100 % (a row at 100 % must equal the one at 0 %).
   */
  class Waveform
  {
  public:
    /** Read @p filename; ExcInputError with file and line on bad input. */
    explicit Waveform(const std::string &filename);

    /** The state at @p percent of the cycle (any real; taken modulo 100). */
    GaitState
    at(const double percent) const;

    /** Number of table rows. */
    unsigned int
    n_rows() const
    {
      return rows.size();
    }

  private:
    std::vector<GaitState> rows;
  };
} // namespace TKR::Gait

#endif
