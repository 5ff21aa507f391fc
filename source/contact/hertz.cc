// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#include <deal.II/base/numbers.h>

#include <tkr/contact/hertz.h>

#include <cmath>

namespace TKR::Contact::Hertz
{
  using dealii::numbers::PI;

  double
  effective_modulus(const Parameters::Material &body_1,
                    const Parameters::Material &body_2)
  {
    return 1. / ((1. - body_1.poissons_ratio * body_1.poissons_ratio) /
                   body_1.youngs_modulus +
                 (1. - body_2.poissons_ratio * body_2.poissons_ratio) /
                   body_2.youngs_modulus);
  }

  Solution
  sphere(const double F, const double R, const double E_star)
  {
    Solution solution;
    solution.a  = std::cbrt(3. * F * R / (4. * E_star));
    solution.p0 = 3. * F / (2. * PI * solution.a * solution.a);
    return solution;
  }

  Solution
  cylinder(const double F, const double L, const double R, const double E_star)
  {
    const double P = F / L;
    Solution     solution;
    solution.a  = std::sqrt(4. * P * R / (PI * E_star));
    solution.p0 = 2. * P / (PI * solution.a);
    return solution;
  }

  Solution
  fit(const std::vector<double> &r, const std::vector<double> &p)
  {
    // Least squares for p^2 = A - B r^2.
    double       s_x = 0, s_y = 0, s_xx = 0, s_xy = 0;
    unsigned int n = 0;
    for (unsigned int j = 0; j < r.size(); ++j)
      if (p[j] > 0)
        {
          const double x = r[j] * r[j], y = p[j] * p[j];
          s_x += x;
          s_y += y;
          s_xx += x * x;
          s_xy += x * y;
          ++n;
        }
    Solution     solution;
    const double denominator = n * s_xx - s_x * s_x;
    if (n < 3 || denominator <= 0)
      return solution;
    const double slope = (n * s_xy - s_x * s_y) / denominator; // -B
    const double A     = (s_y - slope * s_x) / n;
    if (A <= 0 || slope >= 0)
      return solution;
    solution.p0 = std::sqrt(A);
    solution.a  = std::sqrt(-A / slope);
    return solution;
  }
} // namespace TKR::Contact::Hertz
