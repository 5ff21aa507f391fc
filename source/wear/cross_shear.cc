// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#include <deal.II/base/symmetric_tensor.h>

#include <tkr/wear/cross_shear.h>

#include <algorithm>
#include <cmath>

namespace TKR::Wear
{
  using namespace dealii;

  CrossShear
  cross_shear(const std::vector<Tensor<1, 3>> &slips,
              const std::vector<double>       &pressures)
  {
    SymmetricTensor<2, 3> work_tensor;
    CrossShear            out;
    for (unsigned int k = 0; k < slips.size(); ++k)
      {
        const double s = slips[k].norm();
        if (s <= 0 || pressures[k] <= 0)
          continue;
        out.work += pressures[k] * s;
        work_tensor +=
          (pressures[k] / s) * symmetrize(outer_product(slips[k], slips[k]));
      }
    if (out.work <= 0)
      return out;
    // eigenvalues in descending order
    const auto   eigen   = eigenvectors(work_tensor);
    const double lambda1 = eigen[0].first;
    const double lambda2 = std::max(eigen[1].first, 0.);
    out.ratio            = lambda2 / (lambda1 + lambda2);
    out.orientation      = eigen[0].second;
    unsigned int largest = 0;
    for (unsigned int d = 1; d < 3; ++d)
      if (std::abs(out.orientation[d]) > std::abs(out.orientation[largest]))
        largest = d;
    if (out.orientation[largest] < 0)
      out.orientation *= -1.;
    return out;
  }

  std::vector<CrossShear>
  cycle_cross_shear(const CycleSliding &sliding)
  {
    std::vector<CrossShear> out(sliding.n_nodes());
    for (unsigned int j = 0; j < sliding.n_nodes(); ++j)
      {
        std::vector<Tensor<1, 3>> slips;
        std::vector<double>       pressures;
        for (unsigned int i = 0; i < sliding.n_intervals(); ++i)
          {
            const IntervalSliding &interval = sliding.interval(i);
            slips.push_back(interval.slip_start[j]);
            pressures.push_back(0.5 * interval.pressure_start[j]);
            slips.push_back(interval.slip_end[j]);
            pressures.push_back(0.5 * interval.pressure_end[j]);
          }
        out[j] = cross_shear(slips, pressures);
      }
    return out;
  }
} // namespace TKR::Wear
