// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#include <tkr/gait/pose_update.h>

#include <algorithm>
#include <cmath>

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

  bool
  PoseUpdate::stalled() const
  {
    if (norms.size() <= 4)
      return false;
    const auto recent = norms.end() - 4;
    return *std::min_element(recent, norms.end()) >=
           0.9 * *std::min_element(norms.begin(), recent);
  }

  PoseUpdate::Vector
  PoseUpdate::next(const Vector &q, const Vector &d, const Vector &r)
  {
    const double relaxation = relaxed_relaxation(r);
    norms.push_back(r.norm());
    for (unsigned int i = 0; i < n; ++i)
      brackets[i].add(q[i], d[i]);

    // A bracket much narrower than the correction asked for inside it no
    // longer holds the root (the other components moved it, or d jumps
    // there): back to the relaxed step.
    if (active < n && (!brackets[active].encloses() ||
                       brackets[active].width() < 1e-3 * std::abs(d[active])))
      {
        brackets[active].forget_signs();
        active = n;
      }
    // Once the relaxed step stalls, bracket the component with the largest
    // residual among those that alternate and enclose a root.
    if (safeguard && active == n && stalled())
      for (unsigned int i = 0; i < n; ++i)
        if (brackets[i].oscillates() && brackets[i].encloses() &&
            (active == n || std::abs(r[i]) > std::abs(r[active])))
          active = i;

    Vector result = q + relaxation * d;
    if (active < n)
      {
        ever           = true;
        result[active] = brackets[active].false_position();
      }
    return result;
  }

  bool
  PoseUpdate::bracketed_ever() const
  {
    return ever;
  }
} // namespace TKR::Gait
