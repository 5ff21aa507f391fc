// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#include <deal.II/lac/lapack_full_matrix.h>
#include <deal.II/lac/vector.h>

#include <tkr/base/exceptions.h>
#include <tkr/contact/finite_difference_pose.h>

#include <algorithm>
#include <cmath>

namespace TKR::Contact
{
  using namespace dealii;

  FiniteDifferencePose::FiniteDifferencePose(ContactSolver    &solver,
                                             PoseSystem       &system,
                                             const Mapping<3> &mapping,
                                             const double      initial_distance)
    : solver(solver)
    , system(system)
    , mapping(mapping)
    , initial_distance(initial_distance)
  {}

  bool
  FiniteDifferencePose::solve(Point &point, const bool couple)
  {
    if (couple && !system.couple(point.q))
      return false;
    point.statistics = solver.solve(mapping,
                                    system.load_coefficients(point.q),
                                    initial_distance,
                                    point.state);
    point.residual.clear();
    for (const auto &[index, scale] : system.residual_rows())
      point.residual.push_back(scale * solver.observation(index));
    point.data.reset();
    ++n_solves;
    newton_iterations += point.statistics.newton_iterations;
    return true;
  }

  FullMatrix<double>
  FiniteDifferencePose::jacobian(const Point &point)
  {
    const auto         rows = system.residual_rows();
    const unsigned int m    = rows.size();
    FullMatrix<double> J(m, m);
    for (unsigned int k = 0; k < m; ++k)
      {
        const double h = 1e-3 / rows[k].second;
        Point        moved;
        moved.q = point.q;
        moved.q[k] += h;
        moved.state = point.state;
        if (solve(moved, true) && moved.statistics.converged)
          for (unsigned int p = 0; p < m; ++p)
            J(p, k) = (moved.residual[p] - point.residual[p]) / h;
        else
          J(k, k) = -rows[k].second;
      }
    return J;
  }

  // (J - mu S) dq = -r, dq scaled by 1 + mu; LU with partial pivoting. A
  // singular matrix, or a pose change beyond any motion of a step, is a
  // failure.
  bool
  FiniteDifferencePose::newton_step(Point               &point,
                                    const double         damping,
                                    std::vector<double> &dq)
  {
    if (!point.data)
      {
        auto data    = std::make_shared<Jacobian>();
        data->matrix = jacobian(point);
        point.data   = data;
      }
    const auto        &J = dynamic_cast<const Jacobian &>(*point.data).matrix;
    const auto         rows = system.residual_rows();
    const unsigned int m    = rows.size();
    LAPACKFullMatrix<double> matrix(m, m);
    Vector<double>           x(m);
    for (unsigned int p = 0; p < m; ++p)
      {
        for (unsigned int k = 0; k < m; ++k)
          matrix(p, k) = J(p, k);
        matrix(p, p) -= damping * rows[p].second;
        x(p) = -point.residual[p];
      }
    try
      {
        matrix.compute_lu_factorization();
        matrix.solve(x);
      }
    catch (const ExceptionBase &)
      {
        return false;
      }
    dq.assign(x.begin(), x.end());
    return std::all_of(dq.begin(),
                       dq.end(),
                       [](const double v) { return std::isfinite(v); }) &&
           system.step_size(dq) < 1e3;
  }

  FullMatrix<double>
  FiniteDifferencePose::metric() const
  {
    const auto         rows = system.residual_rows();
    FullMatrix<double> metric(rows.size(), rows.size());
    for (unsigned int p = 0; p < rows.size(); ++p)
      metric(p, p) = rows[p].second * rows[p].second;
    return metric;
  }
} // namespace TKR::Contact
