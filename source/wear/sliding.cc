// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#include <tkr/wear/sliding.h>

#include <algorithm>

namespace TKR::Wear
{
  using namespace dealii;

  namespace
  {
    /** Tangential slip of node j over the interval a -> b from point X. */
    Tensor<1, 3>
    slip_vector(const StepRecord   &a,
                const StepRecord   &b,
                const unsigned int  j,
                const Point<3>     &X,
                const Tensor<1, 3> &normal)
    {
      const Tensor<1, 3> relative =
        (b.motion(X) - a.motion(X)) - (b.displacement[j] - a.displacement[j]);
      return relative - (relative * normal) * normal;
    }

    IntervalSliding
    interval_sliding(const StepRecord &a, const StepRecord &b)
    {
      const unsigned int n = a.pressure.size();
      IntervalSliding    sliding;
      sliding.pressure_start = a.pressure;
      sliding.pressure_end   = b.pressure;
      sliding.slip_start.assign(n, Tensor<1, 3>());
      sliding.slip_end.assign(n, Tensor<1, 3>());
      for (unsigned int j = 0; j < n; ++j)
        {
          if (a.pressure[j] > 0)
            sliding.slip_start[j] =
              slip_vector(a, b, j, a.femur_point[j], a.normal[j]);
          if (b.pressure[j] > 0)
            sliding.slip_end[j] =
              slip_vector(a, b, j, b.femur_point[j], b.normal[j]);
        }
      return sliding;
    }
  } // namespace

  double
  IntervalSliding::slip_distance(const unsigned int j) const
  {
    const double s_a = slip_start[j].norm(), s_b = slip_end[j].norm();
    return (pressure_start[j] > 0 && pressure_end[j] > 0) ? 0.5 * (s_a + s_b) :
                                                            std::max(s_a, s_b);
  }

  CycleSliding::CycleSliding(const std::vector<StepRecord> &records)
  {
    const unsigned int n_steps = records.size();
    for (unsigned int i = 0; i < n_steps; ++i)
      intervals.push_back(
        interval_sliding(records[i], records[(i + 1) % n_steps]));
  }
} // namespace TKR::Wear
