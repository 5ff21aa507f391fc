// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#include <tkr/base/exceptions.h>
#include <tkr/problems/calibration_fit.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace TKR::Problems::Calibration
{
  using namespace dealii;

  MassCurve::MassCurve(const std::vector<double> &tau,
                       const std::vector<double> &mass)
    : taus(tau)
    , masses(mass)
  {
    AssertThrow(taus.size() == masses.size() && taus.size() >= 2,
                ExcMessage("MassCurve: a run of at least one block"));
    for (unsigned int i = 1; i < taus.size(); ++i)
      AssertThrow(taus[i] > taus[i - 1],
                  ExcMessage("MassCurve: tau must increase"));
  }

  double
  MassCurve::operator()(const double tau) const
  {
    // The segment that holds tau; the first or the last beyond the ends.
    const auto   after = std::upper_bound(taus.begin(), taus.end(), tau);
    unsigned int i     = std::clamp<long>(after - taus.begin(),
                                      1,
                                      static_cast<long>(taus.size()) - 1);
    const double slope = (masses[i] - masses[i - 1]) / (taus[i] - taus[i - 1]);
    return masses[i - 1] + slope * (tau - taus[i - 1]);
  }

  double
  run_in_integral(const double factor, const double length, const double cycles)
  {
    if (cycles >= length)
      return cycles + (factor - 1.) * length / 2.;
    return factor * cycles + (1. - factor) * cycles * cycles / (2. * length);
  }

  namespace
  {
    using Matrix = std::vector<std::vector<double>>;

    /** Residuals predict(exp(y)) - mass. */
    std::vector<double>
    residuals(const std::vector<Point>  &points,
              const Prediction          &predict,
              const std::vector<double> &y)
    {
      std::vector<double> x(y.size());
      for (unsigned int i = 0; i < y.size(); ++i)
        x[i] = std::exp(y[i]);
      std::vector<double> r;
      for (const Point &point : points)
        r.push_back(predict(x, point) - point.mass);
      return r;
    }

    double
    sum_of_squares(const std::vector<double> &r)
    {
      double sum = 0;
      for (const double v : r)
        sum += v * v;
      return sum;
    }

    /** The Jacobian of residuals() in y (central differences). */
    Matrix
    jacobian(const std::vector<Point>  &points,
             const Prediction          &predict,
             const std::vector<double> &y)
    {
      const double h = 1e-6;
      Matrix       J(points.size(), std::vector<double>(y.size()));
      for (unsigned int k = 0; k < y.size(); ++k)
        {
          std::vector<double> plus = y, minus = y;
          plus[k] += h;
          minus[k] -= h;
          const std::vector<double> rp = residuals(points, predict, plus),
                                    rm = residuals(points, predict, minus);
          for (unsigned int j = 0; j < points.size(); ++j)
            J[j][k] = (rp[j] - rm[j]) / (2 * h);
        }
      return J;
    }

    /**
     * The Cholesky factor L (A = L L^T) of the small symmetric matrix
     * @p A scaled to a unit diagonal, and the smallest pivot squared
     * (0 if not positive definite): a measure of how independent the
     * columns of J are, whatever the parameters' scales.
     */
    std::pair<Matrix, double>
    scaled_cholesky(const Matrix &A)
    {
      const unsigned int n = A.size();
      Matrix             L(n, std::vector<double>(n, 0.));
      double             smallest = 1;
      for (unsigned int i = 0; i < n; ++i)
        for (unsigned int j = 0; j <= i; ++j)
          {
            double sum = A[i][j] / std::sqrt(A[i][i] * A[j][j]);
            for (unsigned int k = 0; k < j; ++k)
              sum -= L[i][k] * L[j][k];
            if (i == j)
              {
                smallest = std::min(smallest, std::max(sum, 0.));
                if (sum <= 0)
                  return {L, 0.};
                L[i][i] = std::sqrt(sum);
              }
            else
              L[i][j] = sum / L[j][j];
          }
      return {L, smallest};
    }

    /** J^T J and -J^T r. */
    std::pair<Matrix, std::vector<double>>
    normal_equations(const Matrix &J, const std::vector<double> &r)
    {
      const unsigned int  n = J.empty() ? 0 : J[0].size();
      Matrix              A(n, std::vector<double>(n, 0.));
      std::vector<double> g(n, 0.);
      for (unsigned int j = 0; j < J.size(); ++j)
        for (unsigned int a = 0; a < n; ++a)
          {
            g[a] -= J[j][a] * r[j];
            for (unsigned int b = 0; b < n; ++b)
              A[a][b] += J[j][a] * J[j][b];
          }
      return {A, g};
    }

    /** Solve A d = b, A symmetric positive definite (scaled Cholesky). */
    std::vector<double>
    solve(const Matrix &A, const std::vector<double> &b)
    {
      const unsigned int n = b.size();
      const Matrix       L = scaled_cholesky(A).first;
      // A = S L L^T S with S = diag(sqrt(A_ii)).
      std::vector<double> y(n);
      for (unsigned int i = 0; i < n; ++i)
        {
          y[i] = b[i] / std::sqrt(A[i][i]);
          for (unsigned int k = 0; k < i; ++k)
            y[i] -= L[i][k] * y[k];
          y[i] /= L[i][i];
        }
      for (unsigned int i = n; i-- > 0;)
        {
          for (unsigned int k = i + 1; k < n; ++k)
            y[i] -= L[k][i] * y[k];
          y[i] /= L[i][i];
        }
      for (unsigned int i = 0; i < n; ++i)
        y[i] /= std::sqrt(A[i][i]);
      return y;
    }
  } // namespace

  FitResult
  fit(const std::vector<Point>       &points,
      const Prediction               &predict,
      const std::vector<double>      &start,
      const std::vector<std::string> &names)
  {
    const unsigned int  n = start.size();
    std::vector<double> y(n);
    for (unsigned int i = 0; i < n; ++i)
      y[i] = std::log(start[i]);
    std::vector<double> r      = residuals(points, predict, y);
    double              sum    = sum_of_squares(r);
    double              lambda = 1e-3;
    FitResult           result;
    std::string         list;
    for (const std::string &name : names)
      list += (list.empty() ? "<" : ", <") + name + ">";
    for (result.iterations = 0; result.iterations < 500; ++result.iterations)
      {
        const auto [A, g] = normal_equations(jacobian(points, predict, y), r);
        Matrix damped     = A;
        for (unsigned int a = 0; a < n; ++a)
          damped[a][a] += lambda * A[a][a];
        const std::vector<double> step = solve(damped, g);
        std::vector<double>       trial(n);
        double                    largest = 0;
        for (unsigned int a = 0; a < n; ++a)
          {
            trial[a] = y[a] + step[a];
            largest  = std::max(largest, std::abs(step[a]));
          }
        const std::vector<double> r_trial = residuals(points, predict, trial);
        const double              s_trial = sum_of_squares(r_trial);
        if (s_trial <= sum)
          {
            y      = trial;
            r      = r_trial;
            sum    = s_trial;
            lambda = std::max(lambda / 10, 1e-12);
          }
        else
          lambda *= 10;
        if (largest < 1e-10 || lambda > 1e12)
          {
            result.inverse_normal_matrix = A;
            break;
          }
      }
    AssertThrow(result.iterations < 500,
                ExcInputError("Calibration: the least-squares fit of " + list +
                              " did not converge in 500 iterations."));

    // Identifiable: J^T J (in log x, scaled to a unit diagonal) not
    // singular.
    const Matrix A       = result.inverse_normal_matrix;
    bool         regular = true;
    for (unsigned int a = 0; a < n; ++a)
      regular &= A[a][a] > 0;
    AssertThrow(regular && scaled_cholesky(A).second > 1e-10,
                ExcInputError(
                  "Calibration: the measured points do not determine " + list +
                  " together (the fit's normal matrix is singular: the "
                  "mass loss changes the same way with them). Fit fewer "
                  "entries, or add points where they act differently (for "
                  "the run-in: during it and well after it)."));
    for (unsigned int a = 0; a < n; ++a)
      {
        std::vector<double> unit(n, 0.);
        unit[a] = 1;
        for (unsigned int b = 0; b < n; ++b)
          result.inverse_normal_matrix[b][a] = solve(A, unit)[b];
      }
    result.x.resize(n);
    for (unsigned int i = 0; i < n; ++i)
      result.x[i] = std::exp(y[i]);
    result.sum_of_squares = sum;
    return result;
  }

  namespace
  {
    /** The continued fraction of the incomplete beta function (Lentz). */
    double
    beta_fraction(const double a, const double b, const double x)
    {
      const double tiny = 1e-300;
      double       c = 1, d = 1 - (a + b) * x / (a + 1);
      d        = 1 / (std::abs(d) < tiny ? tiny : d);
      double h = d;
      for (unsigned int m = 1; m <= 1000; ++m)
        {
          const double m2 = 2. * m;
          for (const double aa :
               {m * (b - m) * x / ((a - 1 + m2) * (a + m2)),
                -(a + m) * (a + b + m) * x / ((a + m2) * (a + 1 + m2))})
            {
              d = 1 + aa * d;
              d = 1 / (std::abs(d) < tiny ? tiny : d);
              c = 1 + aa / c;
              c = std::abs(c) < tiny ? tiny : c;
              h *= d * c;
              if (aa < 0 && std::abs(d * c - 1) < 1e-16)
                return h;
            }
        }
      return h;
    }

    /** The regularized incomplete beta function I_x(a, b). */
    double
    incomplete_beta(const double a, const double b, const double x)
    {
      if (x <= 0 || x >= 1)
        return x <= 0 ? 0. : 1.;
      const double front =
        std::exp(std::lgamma(a + b) - std::lgamma(a) - std::lgamma(b) +
                 a * std::log(x) + b * std::log(1 - x));
      if (x < (a + 1) / (a + b + 2))
        return front * beta_fraction(a, b, x) / a;
      return 1 - front * beta_fraction(b, a, 1 - x) / b;
    }

    /** P(T <= t) for t >= 0. */
    double
    student_t_cdf(const double t, const double dof)
    {
      return 1 - 0.5 * incomplete_beta(dof / 2, 0.5, dof / (dof + t * t));
    }
  } // namespace

  double
  student_t_quantile(const double p, const unsigned int dof)
  {
    AssertThrow(p > 0 && p < 1 && dof > 0,
                ExcMessage("student_t_quantile: p in (0, 1), dof > 0"));
    if (p < 0.5)
      return -student_t_quantile(1 - p, dof);
    double low = 0, high = 1;
    while (student_t_cdf(high, dof) < p)
      high *= 2;
    for (unsigned int i = 0; i < 200 && high - low > 1e-14 * high; ++i)
      {
        const double middle                           = (low + high) / 2;
        (student_t_cdf(middle, dof) < p ? low : high) = middle;
      }
    return (low + high) / 2;
  }
} // namespace TKR::Problems::Calibration
