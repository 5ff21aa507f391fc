// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#ifndef tkr_problems_calibration_fit_h
#define tkr_problems_calibration_fit_h

#include <functional>
#include <string>
#include <vector>

/**
 * The numerics of `Problem = calibration` (doc/calibration.md): the mass
 * loss of a wear run as a function of its wear "time", the run-in model,
 * the least-squares fit and its confidence interval.
 */
namespace TKR::Problems::Calibration
{
  /**
   * A wear run's mass loss m as a function of tau = k F(c), the wear
   * coefficient (or 1 for a law without one) times the effective cycles
   * (the run-in factor integrated from 0 to c). For a law linear in k the
   * worn geometry, hence the rate dm/dtau, depends on tau only: a run at
   * another k or run-in follows the same curve, m(c) = M(k' F'(c)). Linear
   * between the run's blocks, extended beyond its end with the last
   * block's slope.
   */
  class MassCurve
  {
  public:
    /** From the run's blocks: @p tau (increasing, from 0) and @p mass. */
    MassCurve(const std::vector<double> &tau, const std::vector<double> &mass);

    double
    operator()(const double tau) const;

    /** The run's last tau (beyond it, the curve is extrapolated). */
    double
    end() const
    {
      return taus.back();
    }

  private:
    std::vector<double> taus, masses;
  };

  /**
   * The run-in of the fit: the factor falls linearly from @p factor at 0
   * cycles to 1 at @p length and stays 1. Its integral from 0 to
   * @p cycles (the effective cycles).
   */
  double
  run_in_integral(const double factor,
                  const double length,
                  const double cycles);

  /** One measured point: its design (index), specimen (index), cycles and
   *  mass loss (mg). */
  struct Point
  {
    unsigned int design = 0, specimen = 0;
    double       cycles = 0, mass = 0;
  };

  /**
   * The model's prediction of the mass loss of @p point with the
   * parameters @p x (the fitted quantities, in the order of the fit).
   */
  using Prediction =
    std::function<double(const std::vector<double> &x, const Point &point)>;

  /** The result of fit(). */
  struct FitResult
  {
    std::vector<double> x;
    /** Sum of squared residuals (mg^2) and the Levenberg-Marquardt
     *  iterations. */
    double       sum_of_squares = 0;
    unsigned int iterations     = 0;
    /** (J^T J)^-1 at x (the parameters' covariance over sigma^2). */
    std::vector<std::vector<double>> inverse_normal_matrix;
  };

  /**
   * Least squares of predict(x, point) - point.mass over @p points,
   * the parameters positive (the fit runs in log x), from @p start
   * (Levenberg-Marquardt, central-difference Jacobian). ExcInputError
   * naming @p names if the data do not determine them (J^T J singular to
   * 1e-10 of its largest eigenvalue) or the iteration does not converge.
   */
  FitResult
  fit(const std::vector<Point>       &points,
      const Prediction               &predict,
      const std::vector<double>      &start,
      const std::vector<std::string> &names);

  /**
   * The quantile of Student's t distribution with @p dof degrees of
   * freedom at @p p in (0, 1) (the regularized incomplete beta function
   * by its continued fraction, inverted by bisection: about 1e-12).
   */
  double
  student_t_quantile(const double p, const unsigned int dof);
} // namespace TKR::Problems::Calibration

#endif
