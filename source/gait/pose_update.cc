// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#include <tkr/gait/pose_update.h>

#include <algorithm>
#include <cmath>
#include <vector>

namespace TKR::Gait
{
  PoseUpdate::PoseUpdate(const bool safeguard)
    : safeguard(safeguard)
  {}

  double
  PoseUpdate::relaxed_relaxation(const Vector &r)
  {
    if (has_previous)
      {
        if (r.norm() >= previous_r.norm())
          lambda *= 0.5;
        else
          {
            // How much of r one unit of relaxation removed along the
            // previous step: a secant slope; the Newton step is 1 / slope.
            const double slope =
              (1. - r * previous_r / previous_r.norm_square()) / lambda;
            if (slope > 0)
              lambda = std::min(1., 1. / slope);
          }
      }
    previous_r   = r;
    has_previous = true;
    return lambda;
  }

  PoseUpdate::Vector
  PoseUpdate::next(const Vector &q, const Vector &d, const Vector &r)
  {
    const double relaxation = relaxed_relaxation(r);
    // Stalled: the last three solves did not bring |r| 10 % below the best
    // before them (the relaxed step cycles or creeps).
    norms.push_back(r.norm());
    bool stalled = false;
    if (norms.size() > 3)
      {
        const auto recent = norms.end() - 3;
        stalled           = *std::min_element(recent, norms.end()) >=
                  0.9 * *std::min_element(norms.begin(), recent);
      }
    Vector result;
    for (unsigned int i = 0; i < n; ++i)
      {
        Bracket  &b    = brackets[i];
        const int sign = (d[i] > 0) - (d[i] < 0);
        if (sign > 0)
          {
            b.has_low = true;
            b.q_low   = q[i];
            b.d_low   = d[i];
          }
        else if (sign < 0)
          {
            b.has_high = true;
            b.q_high   = q[i];
            b.d_high   = d[i];
          }
        if (sign != 0 && b.last_sign != 0 && sign != b.last_sign)
          ++b.sign_changes;
        if (sign != 0)
          b.last_sign = sign;

        // A root lies between the two poses only if d > 0 below it and
        // d < 0 above it (d decreases along the component).
        const bool encloses = b.has_low && b.has_high && b.q_low < b.q_high;
        b.active =
          safeguard && encloses && b.sign_changes >= 2 && (b.active || stalled);
        if (b.active)
          {
            ever = true;
            // False position, held within the middle half of the bracket.
            const double t =
              std::clamp(b.d_low / (b.d_low - b.d_high), 0.25, 0.75);
            result[i] = b.q_low + t * (b.q_high - b.q_low);
          }
        else
          result[i] = q[i] + relaxation * d[i];
      }
    return result;
  }

  double
  PoseUpdate::relaxation() const
  {
    return lambda;
  }

  unsigned int
  PoseUpdate::n_bracketed() const
  {
    return std::count_if(brackets.begin(),
                         brackets.end(),
                         [](const Bracket &b) { return b.active; });
  }

  bool
  PoseUpdate::bracketed_ever() const
  {
    return ever;
  }
} // namespace TKR::Gait
