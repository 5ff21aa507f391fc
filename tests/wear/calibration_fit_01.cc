// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.
//
// The numerics of Problem = calibration (doc/calibration.md) against
// independent answers: Student's t quantiles against tables (9 digits);
// the run-in's integral against its closed form; MassCurve interpolates
// and extends linearly; the fit recovers k, run-in factor and length
// exactly (1e-6) from points computed with them on an analytic M(tau)
// = 30 tau^0.9 (a rate that falls as the insert conforms), and refuses
// entries the points cannot separate.

#include <tkr/base/exceptions.h>
#include <tkr/problems/calibration_fit.h>

#include <cmath>

#include "../tests.h"

int
main(int argc, char **argv)
{
  using namespace TKR::Problems::Calibration;
  dealii::Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  initlog();

  // Tables (e.g. Abramowitz & Stegun 26.10; scipy.stats.t.ppf).
  const std::vector<std::tuple<double, unsigned int, double>> table = {
    {0.975, 1, 12.7062047362},
    {0.975, 2, 4.30265272975},
    {0.975, 5, 2.57058183661},
    {0.975, 30, 2.04227245630},
    {0.95, 10, 1.81246112281},
    {0.995, 3, 5.84090930976}};
  for (const auto &[p, dof, t] : table)
    deallog << "t(" << p << ", " << dof << ") relative error below 1e-9: "
            << (std::abs(student_t_quantile(p, dof) / t - 1) < 1e-9 ? "yes" :
                                                                      "no")
            << std::endl;
  deallog << "t(0.025, 4) = -t(0.975, 4): "
          << (student_t_quantile(0.025, 4) == -student_t_quantile(0.975, 4) ?
                "yes" :
                "no")
          << std::endl;

  // The run-in 3 -> 1 at 1e6: 2e6 effective cycles by 1e6, then + c.
  deallog << "run-in integral to 1e6, 2e6, 5e5: "
          << run_in_integral(3, 1e6, 1e6) / 1e6 << " "
          << run_in_integral(3, 1e6, 2e6) / 1e6 << " "
          << run_in_integral(3, 1e6, 5e5) / 1e6 << " (2 3 1.25)" << std::endl;

  // M(tau) = 30 tau^0.9 on 41 points of tau = k c, k = 2e-7, c to 2e6.
  std::vector<double> tau, mass;
  for (unsigned int i = 0; i <= 400; ++i)
    {
      tau.push_back(2e-7 * 5e3 * i);
      mass.push_back(30 * std::pow(tau.back(), 0.9));
    }
  const MassCurve curve(tau, mass);
  deallog << "M between points, beyond the end: " << curve(0.5e-3) << " "
          << curve(0.4 + 1e-3) - curve(0.4) << " = "
          << curve(0.4) - curve(0.4 - 1e-3) << std::endl;

  // Points of k = 3e-7, run-in 2.5 -> 1 at 4e5, on the same curve.
  const auto predict = [&](const std::vector<double>               &x,
                           const TKR::Problems::Calibration::Point &p) {
    return curve(x[0] * run_in_integral(x[1], x[2], p.cycles));
  };
  std::vector<TKR::Problems::Calibration::Point> points;
  for (const double c : {1e5, 2.5e5, 5e5, 7.5e5, 1e6, 1.25e6})
    {
      points.push_back({0, 0, c, 0});
      points.back().mass = predict({3e-7, 2.5, 4e5}, points.back());
    }
  const FitResult fitted =
    fit(points, predict, {2e-7, 2, 1e6}, {"k", "factor", "length"});
  deallog << "fitted k, factor, length: relative errors below 1e-6: "
          << (std::abs(fitted.x[0] / 3e-7 - 1) < 1e-6 &&
                  std::abs(fitted.x[1] / 2.5 - 1) < 1e-6 &&
                  std::abs(fitted.x[2] / 4e5 - 1) < 1e-6 ?
                "yes" :
                "no")
          << std::endl;

  // k and a second factor on the rate that multiplies it: not separable.
  const auto twice = [&](const std::vector<double>               &x,
                         const TKR::Problems::Calibration::Point &p) {
    return curve(x[0] * x[1] * p.cycles);
  };
  try
    {
      fit(points, twice, {2e-7, 1}, {"k", "scale"});
      deallog << "k x scale: not refused" << std::endl;
    }
  catch (const TKR::ExcInputError &exc)
    {
      const std::string what = exc.what();
      deallog << "k x scale refused: "
              << (what.find("<k>, <scale>") != std::string::npos &&
                      what.find("singular") != std::string::npos ?
                    "naming both" :
                    what)
              << std::endl;
    }
}
