// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.
//
// The two cross-shear definitions (doc/wear.md, "Cross-shear"; issue 36
// item 3) on slip increments whose answers are known:
// - a narrow ellipse of aspect e (2000 chords, uniform pressure): the
//   work-tensor ratio equals lambda_2 / (lambda_1 + lambda_2) summed here
//   independently (1e-12), the |sin| ratio equals sum |dy| / sum |ds| (the
//   PMO along the long axis, 1e-12); as e falls the |sin| ratio goes like
//   e (ratio / e -> 1) and the work-tensor one like e^2 log(1/e);
// - where they agree: sliding back and forth along a line, 0 for both;
// - their largest values: two perpendicular strokes of equal work, 1/2
//   and 1/sqrt(2); a circle 1/2 and 2/pi (1e-6);
// - the |sin| PMO search against a brute-force scan of 200000 angles on
//   random increments: the sweep's PMO carries at least the scan's work
//   (1e-14) and the ratios agree to 1e-7 (the scan, refined by golden
//   section, finds a smooth maximum's angle to about sqrt(epsilon));
// - a table whose cross-shear column is the other definition's refused.

#include <deal.II/base/tensor.h>

#include <tkr/base/exceptions.h>
#include <tkr/wear/cross_shear.h>
#include <tkr/wear/tables.h>

#include <cmath>
#include <fstream>
#include <random>

#include "../tests.h"

namespace
{
  using namespace dealii;
  using namespace TKR::Wear;

  Tensor<1, 3>
  vec(const double x, const double y)
  {
    Tensor<1, 3> v;
    v[0] = x;
    v[1] = y;
    return v;
  }

  double
  ratio(const std::vector<Tensor<1, 3>> &slips,
        const CrossShearDefinition       definition)
  {
    return cross_shear(slips, std::vector<double>(slips.size(), 1.), definition)
      .ratio;
  }

  /** The work along the direction at @p phi: sum |s_k . e|. */
  double
  along(const std::vector<Tensor<1, 3>> &slips, const double phi)
  {
    double sum = 0;
    for (const auto &s : slips)
      sum += std::abs(s[0] * std::cos(phi) + s[1] * std::sin(phi));
    return sum;
  }

  /** The best angle of a scan, refined by golden section: (along, ratio). */
  std::pair<double, double>
  brute_force_abs_sin(const std::vector<Tensor<1, 3>> &slips)
  {
    const auto along = [&](const double phi) { return ::along(slips, phi); };
    const unsigned int n    = 200000;
    double             best = 0;
    for (unsigned int i = 1; i < n; ++i)
      if (along(M_PI * i / n) > along(best))
        best = M_PI * i / n;
    double a = best - M_PI / n, b = best + M_PI / n;
    for (unsigned int i = 0; i < 100; ++i)
      {
        const double c                = b - (b - a) / 1.618033988749895,
                     d                = a + (b - a) / 1.618033988749895;
        (along(c) > along(d) ? b : a) = (along(c) > along(d) ? d : c);
      }
    const double phi    = (a + b) / 2;
    double       across = 0, work = 0;
    for (const auto &s : slips)
      {
        across += std::abs(-s[0] * std::sin(phi) + s[1] * std::cos(phi));
        work += s.norm();
      }
    return {along(phi), across / work};
  }
} // namespace

int
main(int argc, char **argv)
{
  Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  initlog();
  const auto tensor = CrossShearDefinition::work_tensor;
  const auto abs    = CrossShearDefinition::abs_sin;

  for (const double e : {0.3, 0.1, 0.03, 0.01})
    {
      std::vector<Tensor<1, 3>> slips;
      double                    xx = 0, yy = 0, xy = 0, across = 0, work = 0;
      for (unsigned int k = 0; k < 2000; ++k)
        {
          const double t0 = 2 * M_PI * k / 2000, t1 = 2 * M_PI * (k + 1) / 2000;
          slips.push_back(vec(std::cos(t1) - std::cos(t0),
                              e * (std::sin(t1) - std::sin(t0))));
          const Tensor<1, 3> &s = slips.back();
          xx += s[0] * s[0] / s.norm();
          yy += s[1] * s[1] / s.norm();
          xy += s[0] * s[1] / s.norm();
          across += std::abs(s[1]);
          work += s.norm();
        }
      const double mean = (xx + yy) / 2,
                   half = std::sqrt((xx - yy) * (xx - yy) / 4 + xy * xy);
      const double tensor_ratio = (mean - half) / (xx + yy);
      deallog << "ellipse e = " << e << ": work tensor " << ratio(slips, tensor)
              << " (= summed here: "
              << (std::abs(ratio(slips, tensor) / tensor_ratio - 1) < 1e-12 ?
                    "yes" :
                    "no")
              << "), / (e^2 log(1/e)) " << std::setprecision(4)
              << ratio(slips, tensor) / (e * e * std::log(1 / e))
              << "; abs sin " << ratio(slips, abs) << " (= sum|dy|/sum|ds|: "
              << (std::abs(ratio(slips, abs) / (across / work) - 1) < 1e-12 ?
                    "yes" :
                    "no")
              << "), / e " << ratio(slips, abs) / e << std::endl;
    }

  const std::vector<Tensor<1, 3>> line = {vec(1, 0.2), vec(-1, -0.2)};
  deallog << "back and forth along a line, both 0 (1e-12): "
          << (ratio(line, tensor) < 1e-12 && ratio(line, abs) < 1e-12 ? "yes" :
                                                                        "no")
          << std::endl;
  const std::vector<Tensor<1, 3>> cross = {vec(1, 0), vec(0, 1)};
  deallog << "two perpendicular strokes: " << ratio(cross, tensor) << " "
          << ratio(cross, abs) << " (1/sqrt(2) = " << std::sqrt(0.5) << ")"
          << std::endl;
  std::vector<Tensor<1, 3>> circle;
  for (unsigned int k = 0; k < 3600; ++k)
    circle.push_back(vec(std::cos(2 * M_PI * (k + 0.5) / 3600),
                         std::sin(2 * M_PI * (k + 0.5) / 3600)));
  deallog << "circle: " << ratio(circle, tensor) << ", abs sin - 2/pi below "
          << "1e-6: "
          << (std::abs(ratio(circle, abs) - 2 / M_PI) < 1e-6 ? "yes" : "no")
          << std::endl;

  std::mt19937                           random(36);
  std::uniform_real_distribution<double> uniform(-1, 1);
  double                                 largest  = 0;
  bool                                   at_least = true;
  for (unsigned int set = 0; set < 10; ++set)
    {
      std::vector<Tensor<1, 3>> slips;
      for (unsigned int k = 0; k < 50; ++k)
        slips.push_back(vec(uniform(random), 0.5 * uniform(random)));
      const CrossShear cs =
        cross_shear(slips, std::vector<double>(50, 1.), abs);
      const auto [scan_along, scan_ratio] = brute_force_abs_sin(slips);
      largest = std::max(largest, std::abs(cs.ratio - scan_ratio));
      at_least &=
        along(slips, std::atan2(cs.orientation[1], cs.orientation[0])) >=
        scan_along * (1 - 1e-14);
    }
  // The scan finds a smooth maximum's angle to about sqrt(machine epsilon).
  deallog << "abs sin of 10 random sets: the sweep's PMO has at least the "
          << "scan's work along it: " << (at_least ? "yes" : "no")
          << "; the ratios agree to 1e-7: " << (largest < 1e-7 ? "yes" : "no")
          << std::endl;

  std::ofstream("work-tensor.csv") << "cross_shear,C\n0,1e-9\n0.5,2e-9\n";
  std::ofstream("abs-sin.csv") << "cross_shear_abs_sin,C\n0,1e-9\n0.7,2e-9\n";
  for (const auto &[file, definition] : {std::make_pair("work-tensor.csv", abs),
                                         std::make_pair("abs-sin.csv", tensor)})
    try
      {
        CrossShearTable(file, "C", false, definition);
        deallog << file << " read with the other definition" << std::endl;
      }
    catch (const TKR::ExcInputError &exc)
      {
        const std::string what = exc.what();
        deallog << file << " refused with the other definition: "
                << (what.find("was fitted with the") != std::string::npos ?
                      "yes" :
                      what)
                << std::endl;
      }
  deallog << "each with its own: "
          << CrossShearTable("work-tensor.csv", "C", false, tensor).value(0.25)
          << " " << CrossShearTable("abs-sin.csv", "C", false, abs).value(0.35)
          << std::endl;
}
