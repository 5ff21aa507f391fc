// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#include <deal.II/base/symmetric_tensor.h>

#include <tkr/wear/cross_shear.h>

#include <algorithm>
#include <cmath>

namespace TKR::Wear
{
  using namespace dealii;

  CrossShearDefinition
  cross_shear_definition(const std::string &name)
  {
    return name == "abs sin" ? CrossShearDefinition::abs_sin :
                               CrossShearDefinition::work_tensor;
  }

  double
  largest_cross_shear(const CrossShearDefinition definition)
  {
    return definition == CrossShearDefinition::abs_sin ? std::sqrt(0.5) : 0.5;
  }

  namespace
  {
    /**
     * The angle phi in [0, pi) that maximises f(phi) = sum_k w_k |cos(
     * theta_k - phi)|. Between the angles where a term changes sign
     * (theta_k +- pi/2) f = A cos phi + B sin phi with A, B sums over the
     * terms with their signs there; its largest value on such an interval
     * is at an end or at atan2(B, A). Sweeping the sorted sign changes
     * updates A and B term by term: O(n log n), exact.
     */
    double
    most_work_angle(const std::vector<double> &theta,
                    const std::vector<double> &w)
    {
      const unsigned int n = theta.size();
      // The sign change of each term (in [0, pi)) and the sign before it.
      std::vector<std::pair<double, unsigned int>> changes;
      double                                       A = 0, B = 0;
      std::vector<double>                          sign(n);
      for (unsigned int k = 0; k < n; ++k)
        {
          const bool first_half = theta[k] < M_PI / 2;
          sign[k]               = first_half ? 1. : -1.;
          changes.emplace_back(theta[k] + (first_half ? 1 : -1) * M_PI / 2, k);
          A += sign[k] * w[k] * std::cos(theta[k]);
          B += sign[k] * w[k] * std::sin(theta[k]);
        }
      std::sort(changes.begin(), changes.end());
      double best = -1, best_phi = 0, start = 0;
      for (unsigned int c = 0; c <= n; ++c)
        {
          const double end  = c < n ? changes[c].first : M_PI;
          double       peak = std::atan2(B, A);
          if (peak < start)
            peak += 2 * M_PI * std::ceil((start - peak) / (2 * M_PI));
          for (const double phi : {start, end, peak})
            if (phi >= start && phi <= end &&
                A * std::cos(phi) + B * std::sin(phi) > best)
              {
                best     = A * std::cos(phi) + B * std::sin(phi);
                best_phi = phi;
              }
          if (c == n)
            break;
          const unsigned int k = changes[c].second;
          A -= 2 * sign[k] * w[k] * std::cos(theta[k]);
          B -= 2 * sign[k] * w[k] * std::sin(theta[k]);
          sign[k] = -sign[k];
          start   = end;
        }
      return best_phi;
    }

    /**
     * The |sin| definition: the increments' angles in the plane of T's
     * two principal directions @p e1, @p e2, the PMO by most_work_angle(),
     * the ratio sum_k w_k |sin(theta_k - phi)| / W into @p out.
     */
    void
    abs_sin_cross_shear(const std::vector<Tensor<1, 3>> &slips,
                        const std::vector<double>       &pressures,
                        const Tensor<1, 3>              &e1,
                        const Tensor<1, 3>              &e2,
                        CrossShear                      &out)
    {
      std::vector<double> theta, w;
      for (unsigned int k = 0; k < slips.size(); ++k)
        {
          const double s = slips[k].norm();
          if (s <= 0 || pressures[k] <= 0)
            continue;
          double angle = std::atan2(slips[k] * e2, slips[k] * e1);
          if (angle < 0)
            angle += M_PI;
          theta.push_back(std::min(angle, std::nextafter(M_PI, 0.)));
          w.push_back(pressures[k] * s);
        }
      const double phi    = most_work_angle(theta, w);
      double       across = 0;
      for (unsigned int k = 0; k < theta.size(); ++k)
        across += w[k] * std::abs(std::sin(theta[k] - phi));
      out.ratio       = across / out.work;
      out.orientation = std::cos(phi) * e1 + std::sin(phi) * e2;
    }
  } // namespace

  CrossShear
  cross_shear(const std::vector<Tensor<1, 3>> &slips,
              const std::vector<double>       &pressures,
              const CrossShearDefinition       definition)
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
    if (definition == CrossShearDefinition::abs_sin)
      abs_sin_cross_shear(slips,
                          pressures,
                          eigen[0].second,
                          eigen[1].second,
                          out);
    unsigned int largest = 0;
    for (unsigned int d = 1; d < 3; ++d)
      if (std::abs(out.orientation[d]) > std::abs(out.orientation[largest]))
        largest = d;
    if (out.orientation[largest] < 0)
      out.orientation *= -1.;
    return out;
  }

  std::vector<CrossShear>
  cycle_cross_shear(const CycleSliding        &sliding,
                    const CrossShearDefinition definition)
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
        out[j] = cross_shear(slips, pressures, definition);
      }
    return out;
  }
} // namespace TKR::Wear
