// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

// Newton's method on the pose equations of a gait step (PoseNewton): the
// iteration, its search direction and its line search. The equations and
// the globalisation are in doc/gait.md, "The pose Newton"; the Newton
// steps come from a PoseDerivatives (the condensed active set's analytic
// ones, or FiniteDifferencePose).

#include <deal.II/lac/vector.h>

#include <tkr/base/exceptions.h>
#include <tkr/contact/pose_newton.h>

#include <algorithm>
#include <cmath>

namespace TKR::Contact
{
  using namespace dealii;

  namespace
  {
    /** The line search's (strong Wolfe) curvature constant. */
    constexpr double line_search_eta = 0.5;
    /** Contact solutions per line search, at most. */
    constexpr unsigned int max_line_search_steps = 8;
    /**
     * The smallest cosine of the Newton direction with S^-1 r (in the
     * metric), and of a damped one.
     */
    constexpr double min_cosine = 1e-2, damped_cosine = 0.5;
    /** The first and the largest Levenberg-Marquardt damping. */
    constexpr double min_damping = 1. / 64, max_damping = 1e6;
    /** The largest change of the pose per Newton iteration (mm). */
    constexpr double max_pose_step = 2.;
  } // namespace

  PoseNewton::PoseNewton(PoseSystem &system, PoseDerivatives &derivatives)
    : system(system)
    , derivatives(derivatives)
    , stiffness(derivatives.metric())
    , rows(system.residual_rows())
  {
    AssertDimension(rows.size(), system.n_unknowns());
  }

  double
  PoseNewton::largest(const Point &point)
  {
    double r_max = 0;
    for (const double r : point.residual)
      r_max = std::max(r_max, std::abs(r));
    return r_max;
  }

  // The merit's gradient is -M S^-1 r (M the metric): with M = G^-1 the
  // gradient of the step's potential energy V(q) (the elastic energy and
  // the work of the loads and springs at the contact solution of q), so
  // that the slope of V along dq is known at every trial pose without V
  // itself.
  double
  PoseNewton::slope(const Point &point, const std::vector<double> &dq) const
  {
    const unsigned int m = rows.size();
    Vector<double>     displacement(m), force(m);
    for (unsigned int k = 0; k < m; ++k)
      displacement(k) = point.residual[k] / rows[k].second;
    stiffness.vmult(force, displacement);
    double sum = 0;
    for (unsigned int k = 0; k < m; ++k)
      sum -= dq[k] * force(k);
    return sum;
  }

  // The search direction (doc/gait.md, "Globalisation"): the Newton step
  // if it is gradient related in the metric M, i.e. its cosine with the
  // steepest descent direction d = S^-1 r in M,
  //   -phi'(0) / (|dq|_M |d|_M),  phi'(0) = -dq . M d,
  // is at least min_cosine; else the Newton step damped (Levenberg-
  // Marquardt) by mu = 1/64, 1/16, ... until the cosine is at least
  // damped_cosine (the Newton model has just failed there, so the step
  // leans towards d: fewer solves than min_cosine on the cases that
  // damp, doc/gait.md). Damping turns dq continuously from the Newton
  // step to d, which descends (M is positive definite). Only if no damping
  // up to max_damping gives such a direction is d itself taken (counted as
  // a fallback).
  std::vector<double>
  PoseNewton::search_direction(Point &point, PoseStatistics &statistics)
  {
    const unsigned int m = rows.size();
    Vector<double>     descent(m);
    for (unsigned int k = 0; k < m; ++k)
      descent(k) = point.residual[k] / rows[k].second;
    Vector<double> force(m);
    stiffness.vmult(force, descent);
    const double descent_norm =
      std::sqrt(std::max(0., stiffness.matrix_norm_square(descent)));
    const auto cosine = [&](const std::vector<double> &dq) {
      const Vector<double> x(dq.begin(), dq.end());
      const double         norm =
        std::sqrt(std::max(0., stiffness.matrix_norm_square(x)));
      return norm > 0 && descent_norm > 0 ?
               (x * force) / (norm * descent_norm) :
               0.;
    };

    std::vector<double> dq(m);
    double              regularisation = 0;
    if (!derivatives.newton_step(point, 0., dq))
      {
        ++statistics.n_regularised;
        regularisation = 1;
        AssertThrow(derivatives.newton_step(point, regularisation, dq),
                    ExcMessage("The Newton matrix of the pose is singular."));
      }
    // The Newton step is tested against min_cosine, a damped one against
    // damped_cosine.
    double target = min_cosine;
    for (double mu = min_damping; !(cosine(dq) >= target); mu *= 4)
      {
        if (mu > max_damping)
          {
            ++statistics.n_descent_fallbacks;
            dq.assign(descent.begin(), descent.end());
            break;
          }
        if (derivatives.newton_step(point, regularisation + mu, dq))
          for (double &v : dq)
            v *= 1 + mu;
        target = damped_cosine;
      }
    return dq;
  }

  // The line search of one pose step: the bracket [low, high] of the step
  // has phi'(low) < 0 (its solution kept) and phi'(high) > eta |phi'(0)|
  // or no contact solution there; regula falsi on phi' where both ends
  // have a slope, else halving, never closer than a tenth of the bracket
  // to an end.
  PoseNewton::Step
  PoseNewton::line_search(const Point               &start,
                          const std::vector<double> &dq,
                          PoseStatistics            &statistics)
  {
    const double slope_0   = slope(start, dq);
    const double alpha_max = std::min(1., max_pose_step / system.step_size(dq));
    double       low = 0, slope_low = slope_0;
    double       high = alpha_max, slope_high = 0;
    bool         has_high = false;
    Step         lowest;
    double       alpha = alpha_max;
    for (unsigned int n = 0; n < max_line_search_steps; ++n)
      {
        Step trial;
        trial.point.q = start.q;
        for (unsigned int k = 0; k < dq.size(); ++k)
          trial.point.q[k] += alpha * dq[k];
        trial.point.state = start.state;
        const bool solved = derivatives.solve(trial.point, true) &&
                            trial.point.statistics.converged;
        const double s = solved ? slope(trial.point, dq) : 0.;
        if (solved && (std::abs(s) <= line_search_eta * std::abs(slope_0) ||
                       (s < 0 && alpha == alpha_max)))
          {
            trial.outcome = Step::accepted;
            return trial;
          }
        if (solved && s < 0)
          {
            low            = alpha;
            slope_low      = s;
            lowest         = std::move(trial);
            lowest.outcome = Step::lowered;
          }
        else
          {
            high       = alpha;
            slope_high = s;
            has_high   = solved;
          }
        const double width = high - low;
        alpha = has_high ? low - slope_low * width / (slope_high - slope_low) :
                           0.5 * (low + high);
        alpha = std::clamp(alpha, low + 0.1 * width, high - 0.1 * width);
        ++statistics.n_step_cuts;
      }
    return lowest;
  }

  // The iteration (doc/gait.md, "The pose Newton"): the contact solution
  // at the starting pose (enough for a warm step whose pose still holds);
  // then, at the contact solution of the current pose, the Newton step
  // (search_direction()) and a line search along it in the merit, whose
  // slope along dq is
  //   phi'(alpha) = -dq . M S^-1 r(q + alpha dq).
  // With M = G^-1 the merit is the step's potential energy V(q): convex
  // for small rotations, its gradient continuous (the contact force is,
  // item 2 of issue 33). The line search looks for |phi'(alpha)| <= eta
  // |phi'(0)| (the strong Wolfe condition), from the full step (at most
  // max_pose_step) by regula falsi on phi' (increasing in alpha): every
  // accepted step lowers V, and a Newton direction that lies across a
  // change of the active set (where the merit |r|^2 has a kink and its
  // one-sided Newton directions point against each other) still lowers V.
  // A Newton direction that is not gradient related (follower loads and
  // the finite rotation make the Newton matrix differ from V's Hessian) is
  // damped until it is (search_direction()). The iteration ends when every
  // |r_p| <= tolerance; a step that finds no contact solution near its
  // start ends it, not converged.
  ContactStatistics
  PoseNewton::solve(std::vector<double> &q,
                    const double         tolerance,
                    const unsigned int   max_iterations,
                    ContactState        &state,
                    PoseStatistics      &statistics)
  {
    statistics                    = PoseStatistics();
    derivatives.n_solves          = 0;
    derivatives.newton_iterations = 0;
    Point point;
    point.q     = q;
    point.state = state;
    derivatives.solve(point, false);
    bool stuck = false;
    while (!(point.statistics.converged && largest(point) <= tolerance) &&
           statistics.n_iterations < max_iterations && !stuck)
      {
        ++statistics.n_iterations;
        const std::vector<double> dq   = search_direction(point, statistics);
        Step                      step = line_search(point, dq, statistics);
        if (step.outcome == Step::stuck)
          {
            // No contact solution, or no descent, near the start: the
            // solve ends, not converged, at the last point.
            stuck = true;
            system.couple(point.q);
            continue;
          }
        point = std::move(step.point);
        if (step.outcome == Step::lowered)
          {
            // The bracket's lower end lowers the merit: taken, counted.
            ++statistics.n_stalled_steps;
            system.couple(point.q);
          }
      }
    q                   = point.q;
    state               = point.state;
    statistics.residual = largest(point);
    statistics.converged =
      point.statistics.converged && statistics.residual <= tolerance;
    if (statistics.converged && derivatives.newton_step_is_cheap())
      {
        PoseStatistics            ignored;
        const std::vector<double> dq = search_direction(point, ignored);
        statistics.refined           = q;
        for (unsigned int k = 0; k < q.size(); ++k)
          statistics.refined[k] += dq[k];
      }
    statistics.n_solves      = derivatives.n_solves;
    ContactStatistics result = point.statistics;
    result.newton_iterations = derivatives.newton_iterations;
    return result;
  }
} // namespace TKR::Contact
