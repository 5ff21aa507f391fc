// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.
//
// The cases of a study (make_study_cases) against answers computed here:
// - a grid is the full factorial, the last factor fastest; `*=` and `+=`
//   act on the base value, `[i]` on one component of a vector entry, a
//   one-value factor sets the entry in every case;
// - the standard normal quantile equals tabulated values to 1e-14 and
//   inverts std::erfc to 1e-14 over (1e-12, 1 - 1e-12);
// - a Latin hypercube of n samples has exactly one sample in each of the n
//   strata of every dimension, Monte Carlo samples lie in (0, 1), the same
//   seed gives the same samples and another seed others;
// - sampled entries follow their distributions: uniform within its bounds,
//   the sample mean and standard deviation of 4000 normal LHS samples
//   within 1 % of (mean, sd), log-normal = exp(normal);
// - grid x samples: every grid point gets the same samples;
// - a path the base does not have, a component out of range and a bad
//   distribution are refused with the study file's line, case and value.

#include <tkr/base/exceptions.h>
#include <tkr/problems/study_cases.h>

#include <cmath>
#include <iostream>

#include "../tests.h"

namespace
{
  using TKR::Parameters::AllParameters;

  AllParameters
  base()
  {
    AllParameters p;
    p.problem = TKR::Parameters::ProblemType::wear;
    p.entries["Wear/Archard/Wear coefficient"]   = "2e-7";
    p.entries["Materials/Tibia/Young's modulus"] = "1000";
    p.entries["Gait/Flexion axis point"]         = "0, -2, 53.001";
    p.entries["Gait/Femur AP offset"]            = "0";
    p.entries["Output/Plots"]                    = "true";
    return p;
  }

  AllParameters
  study(const std::string &grid,
        const std::string &sampling      = "none",
        const unsigned int samples       = 0,
        const std::string &distributions = "",
        const unsigned int seed          = 1)
  {
    AllParameters s;
    s.parameter_file                = "study.prm";
    s.places["Study/Grid"]          = "study.prm:4";
    s.study.grid                    = grid;
    s.study.sampling                = sampling;
    s.study.samples                 = samples;
    s.study.distributions           = distributions;
    s.study.seed                    = seed;
    s.places["Study/Distributions"] = "study.prm:7";
    return s;
  }

  void
  expect_error(const AllParameters &s, const std::string &what)
  {
    try
      {
        TKR::Problems::make_study_cases(s, base());
        deallog << what << ": NOT refused" << std::endl;
      }
    catch (const TKR::ExcInputError &exc)
      {
        deallog << what << ": " << TKR::exception_message(exc) << std::endl;
      }
  }
} // namespace

int
main()
{
  initlog();
  using namespace TKR::Problems;

  // The grid; its wear coefficient by the entry's path before it moved
  // into Wear/Archard (set there).
  const auto grid = make_study_cases(
    study("Wear/Wear coefficient *= 0.5, 1.5; Gait/Flexion axis point[2] += "
          "-1, 0, 2; Output/Plots = false"),
    base());
  deallog << "grid cases: " << grid.size() << std::endl;
  for (const auto &c : grid)
    {
      deallog << c.name << ":";
      for (const auto &[path, value] : c.entries)
        deallog << " [" << path << " = " << value << "]";
      deallog << std::endl;
    }

  // The normal quantile.
  const double tabulated[][2] = {{0.5, 0.},
                                 {0.975, 1.959963984540054},
                                 {0.01, -2.326347874040841},
                                 {0.999, 3.090232306167814},
                                 {1e-10, -6.361340902404056}};
  double       error          = 0;
  for (const auto &t : tabulated)
    error = std::max(error, std::abs(standard_normal_quantile(t[0]) - t[1]));
  deallog << "normal quantile = tabulated to 1e-14: "
          << yes_no(error < 1e-14 * 7) << std::endl;
  double inverse_error = 0;
  for (double p = 1e-12; p < 1; p = (p < 0.5 ? p * 3 : 1 - (1 - p) / 3))
    {
      const double x = standard_normal_quantile(p);
      inverse_error =
        std::max(inverse_error,
                 std::abs(0.5 * std::erfc(-x / std::sqrt(2.)) - p) /
                   std::min(p, 1 - p));
      if (1 - p < 1e-12)
        break;
    }
  deallog << "Phi(quantile(p)) = p to 1e-14 relative: "
          << yes_no(inverse_error < 1e-14) << std::endl;

  // Latin hypercube strata, Monte Carlo range, seeds.
  const unsigned int n               = 50;
  const auto         lhs             = unit_samples(n, 3, 5, true);
  bool               one_per_stratum = true;
  for (unsigned int j = 0; j < 3; ++j)
    {
      std::vector<unsigned int> count(n, 0);
      for (unsigned int i = 0; i < n; ++i)
        ++count[static_cast<unsigned int>(lhs[i][j] * n)];
      for (const unsigned int c : count)
        one_per_stratum = one_per_stratum && (c == 1);
    }
  deallog << "Latin hypercube: one sample per stratum and dimension: "
          << yes_no(one_per_stratum) << std::endl;
  const auto mc     = unit_samples(n, 3, 5, false);
  bool       inside = true;
  for (const auto &point : mc)
    for (const double u : point)
      inside = inside && u > 0 && u < 1;
  deallog << "Monte Carlo samples in (0, 1): " << yes_no(inside) << std::endl;
  deallog << "same seed, same samples: "
          << yes_no(unit_samples(n, 3, 5, true) == lhs)
          << "; another seed, others: "
          << yes_no(unit_samples(n, 3, 6, true) != lhs) << std::endl;
  deallog << "first samples (seed 5): " << std::setprecision(12) << lhs[0][0]
          << " " << lhs[0][1] << " " << lhs[1][0] << std::endl;

  // Distributions of sampled entries.
  const auto sampled = make_study_cases(
    study("",
          "latin hypercube",
          4000,
          "Wear/Archard/Wear coefficient = normal(3, 0.5); Gait/Femur AP "
          "offset = "
          "uniform(-2, 2); Materials/Tibia/Young's modulus *= "
          "log-normal(0, 0.1)"),
    base());
  double sum = 0, sum2 = 0, ap_min = 1e9, ap_max = -1e9, ln_sum = 0;
  for (const auto &c : sampled)
    {
      const double k = std::stod(c.entries.at("Wear/Archard/Wear coefficient"));
      const double ap = std::stod(c.entries.at("Gait/Femur AP offset"));
      const double e =
        std::stod(c.entries.at("Materials/Tibia/Young's modulus"));
      sum += k;
      sum2 += k * k;
      ap_min = std::min(ap_min, ap);
      ap_max = std::max(ap_max, ap);
      ln_sum += std::log(e / 1000.);
    }
  const double mean = sum / sampled.size();
  const double sd   = std::sqrt(sum2 / sampled.size() - mean * mean);
  deallog << "normal(3, 0.5): mean within 1 %: "
          << yes_no(std::abs(mean - 3) < 0.03)
          << ", sd within 1 %: " << yes_no(std::abs(sd - 0.5) < 0.005)
          << std::endl;
  deallog << "uniform(-2, 2) within its bounds and filling them: "
          << yes_no(ap_min >= -2 && ap_max <= 2 && ap_min < -1.99 &&
                    ap_max > 1.99)
          << std::endl;
  deallog << "log-normal(0, 0.1) x 1000: mean of ln(E / 1000) near 0: "
          << yes_no(std::abs(ln_sum / sampled.size()) < 1e-3) << std::endl;

  // Grid x samples.
  const auto crossed =
    make_study_cases(study("Output/Plots = true, false",
                           "monte carlo",
                           3,
                           "Gait/Femur AP offset = uniform(-1, 1)"),
                     base());
  bool same = crossed.size() == 6;
  for (unsigned int i = 0; i < 3 && same; ++i)
    same = crossed[i].entries.at("Gait/Femur AP offset") ==
             crossed[i + 3].entries.at("Gait/Femur AP offset") &&
           crossed[i].entries.at("Output/Plots") == "true" &&
           crossed[i + 3].entries.at("Output/Plots") == "false";
  deallog << "grid x samples: 6 cases, each grid point the same samples: "
          << yes_no(same) << std::endl;

  // Errors.
  expect_error(study("Wear/Wear coeficient = 1e-7"), "unknown entry");
  expect_error(study("Gait/Flexion axis point[3] += 1"), "component");
  expect_error(study("Output/Plots *= 2"), "*= on text");
  expect_error(study("",
                     "latin hypercube",
                     4,
                     "Wear/Wear coefficient = "
                     "uniform(2, 1)"),
               "distribution");
  expect_error(study("",
                     "latin hypercube",
                     0,
                     "Wear/Wear coefficient = "
                     "uniform(1, 2)"),
               "no samples");
}
