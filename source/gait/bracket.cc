// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#include <tkr/gait/bracket.h>

#include <algorithm>
#include <limits>

namespace TKR::Gait
{
  void
  Bracket::add(const double value, const double d)
  {
    const int sign = (d > 0) - (d < 0);
    if (sign > 0)
      {
        has_low = true;
        q_low   = value;
        d_low   = d;
      }
    else if (sign < 0)
      {
        has_high = true;
        q_high   = value;
        d_high   = d;
      }
    if (sign != 0)
      {
        signs.push_back(sign);
        if (signs.size() > 3)
          signs.erase(signs.begin());
      }
  }

  bool
  Bracket::encloses() const
  {
    return has_low && has_high && q_low < q_high;
  }

  double
  Bracket::width() const
  {
    return encloses() ? q_high - q_low :
                        std::numeric_limits<double>::infinity();
  }

  double
  Bracket::middle() const
  {
    return 0.5 * (q_low + q_high);
  }

  double
  Bracket::false_position() const
  {
    const double t = std::clamp(d_low / (d_low - d_high), 0.25, 0.75);
    return q_low + t * (q_high - q_low);
  }

  bool
  Bracket::oscillates() const
  {
    return signs.size() == 3 && signs[0] != signs[1] && signs[1] != signs[2];
  }

  void
  Bracket::forget_signs()
  {
    signs.clear();
  }
} // namespace TKR::Gait
