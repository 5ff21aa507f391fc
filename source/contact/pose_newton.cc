// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

// The contact problem and the rigid pose of the tibial tray in one
// semismooth Newton iteration (CondensedActiveSetSolver::solve_with_pose()).
// The equations and the globalisation are in doc/gait.md, "Pose and
// contact in one Newton".

#include <deal.II/base/timer.h>

#include <deal.II/lac/full_matrix.h>
#include <deal.II/lac/lapack_full_matrix.h>

#include <tkr/base/exceptions.h>
#include <tkr/contact/condensed_solver.h>

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
     * The smallest cosine of the Newton direction with S^-1 r (in K), and
     * of a damped one.
     */
    constexpr double min_cosine = 1e-2, damped_cosine = 0.5;
    /** The first and the largest Levenberg-Marquardt damping. */
    constexpr double min_damping = 1. / 64, max_damping = 1e6;
    /** The largest change of the pose per Newton iteration (mm). */
    constexpr double max_pose_step = 2.;
  } // namespace

  void
  CondensedActiveSetSolver::combine_basis(
    const std::vector<double> &c,
    std::vector<double>       &u0,
    std::vector<double>       &u0_observations) const
  {
    AssertThrow(!basis_columns.empty() && c.size() + 1 == basis_columns.size(),
                ExcMessage("Call set_load_basis() with as many loads as "
                           "coefficients before this solve()."));
    u0              = basis_columns.back().surface;
    u0_observations = basis_columns.back().observations;
    for (unsigned int b = 0; b < c.size(); ++b)
      {
        const Column &column = basis_columns[b];
        for (unsigned int r = 0; r < u0.size(); ++r)
          u0[r] += c[b] * column.surface[r];
        for (unsigned int o = 0; o < u0_observations.size(); ++o)
          u0_observations[o] += c[b] * column.observations[o];
      }
  }

  // The coupling of q is the current one: u_0(q) on all surface values and
  // on the zone of the coupling.
  CondensedActiveSetSolver::PosePoint
  CondensedActiveSetSolver::make_pose_point(const PoseSystem          &system,
                                            const std::vector<double> &q)
  {
    TimerOutput::Scope scope(timer, "contact zone");
    PosePoint          point;
    point.q            = q;
    point.coefficients = system.load_coefficients(q);
    combine_basis(point.coefficients, point.u0, point.u0_observations);
    point.zone = make_zone(Mortar::MortarOperator(coupling), point.u0);
    point.z.resize(coupling.slave_nodes().size());
    return point;
  }

  // The active set iteration of solve() on the point's zone, its columns
  // z_i kept in the point for the Newton matrix; the active set of @p state
  // (if it has one) is the start.
  ContactStatistics
  CondensedActiveSetSolver::solve_at_pose(const PoseSystem &system,
                                          const double      initial_distance,
                                          PosePoint        &point,
                                          ContactState     &state)
  {
    const Mortar::MortarOperator B          = mortar_operator();
    ContactStatistics            statistics = iterate(B,
                                           point.zone,
                                           point.z,
                                           point.u0,
                                           point.u0_observations,
                                           initial_distance,
                                           state);
    statistics.relative_residual            = basis_residual;
    statistics.converged =
      statistics.converged && basis_residual <= parameters.tolerance;
    last_rhs.clear();
    last_coefficients = point.coefficients;
    point.active      = state.active;
    point.residual.clear();
    for (const auto &[index, scale] : system.residual_rows())
      point.residual.push_back(scale * observed[index]);
    return statistics;
  }

  // How u_0 and its observations change with the pose through the loads
  // (central differences of the load coefficients: exact for the linear
  // ones, the mean slope at a restraint's kink), and the velocity fields of
  // the master's points.
  CondensedActiveSetSolver::PoseDerivatives
  CondensedActiveSetSolver::pose_derivatives(const PoseSystem &system,
                                             const PosePoint  &point) const
  {
    const unsigned int m      = system.n_unknowns();
    const unsigned int n_zone = point.zone.values.size();
    PoseDerivatives    d;
    d.u0.assign(m, std::vector<double>(n_zone, 0.));
    d.observations.assign(m,
                          std::vector<double>(point.u0_observations.size(),
                                              0.));
    for (unsigned int k = 0; k < m; ++k)
      {
        const double        h    = 1e-6 * std::max(1., std::abs(point.q[k]));
        std::vector<double> plus = point.q, minus = point.q;
        plus[k] += h;
        minus[k] -= h;
        const std::vector<double> cp = system.load_coefficients(plus);
        const std::vector<double> cm = system.load_coefficients(minus);
        for (unsigned int b = 0; b < cp.size(); ++b)
          {
            const double dc = (cp[b] - cm[b]) / (2 * h);
            if (dc == 0.)
              continue;
            const Column &column = basis_columns[b];
            for (unsigned int v = 0; v < n_zone; ++v)
              d.u0[k][v] += dc * column.surface[point.zone.values[v]];
            for (unsigned int o = 0; o < column.observations.size(); ++o)
              d.observations[k][o] += dc * column.observations[o];
          }
        d.velocity.push_back(system.master_velocity(point.q, k));
      }
    return d;
  }

  // The Newton matrix of the active set A at the contact solution of the
  // pose q, for the unknowns lambda_A (the new multipliers) and the change
  // dq of the pose:
  //   [ W_AA / D     H_A / D ] [lambda_A]   [ -(g_A - B_A u_0) / D ]
  //   [ -S Z_A^T     S R     ] [   dq   ] = [ -S w . u_0           ]
  // W_AA = B_A K^{-1} B_A^T (the Delassus operator), H_jk = G_jk -
  // B_j du_0/dq_k with G_jk = gamma_j . dp_j/dq_k the change of the
  // weighted gap when the master point p_j moves with the pose (gamma_j the
  // coupling's gap gradient), Z_A the observations of the columns z_i,
  // R = d(w . u_0)/dq the pose's own effect on the observations through the
  // loads, S the residual's scales. The gap rows are divided by D_jj (mm).
  // If no active node holds some pose unknown the matrix is singular: the
  // pose rows then get the fixed-point model dr_p/dq_p = -s_p (the pose
  // moves by the displacement it observes).
  CondensedActiveSetSolver::PoseNewtonSystem
  CondensedActiveSetSolver::pose_newton_system(const PoseSystem &system,
                                               PosePoint        &point)
  {
    const auto                  &nodes = coupling.slave_nodes();
    const Mortar::MortarOperator B     = mortar_operator();
    std::vector<unsigned int>    active;
    for (unsigned int j = 0; j < nodes.size(); ++j)
      if (point.active[j])
        active.push_back(j);
    ensure_columns(B, active);

    TimerOutput::Scope    scope(timer, "condensed Newton step");
    const Zone           &zone = point.zone;
    const unsigned int    m    = system.n_unknowns();
    const unsigned int    n_A  = active.size();
    const auto            rows = system.residual_rows();
    const PoseDerivatives d    = pose_derivatives(system, point);
    AssertDimension(rows.size(), m);
    for (const unsigned int i : active)
      if (point.z[i].surface.empty())
        point.z[i] = zone_column(B, zone, i);

    PoseNewtonSystem newton;
    newton.n_active               = n_A;
    LAPACKFullMatrix<double> &J   = newton.matrix;
    Vector<double>           &rhs = newton.rhs;
    J.reinit(n_A + m, n_A + m);
    rhs.reinit(n_A + m);
    const std::vector<double> delassus = zone.delassus(active, point.z);
    for (unsigned int a = 0; a < n_A; ++a)
      {
        const auto &node = nodes[active[a]];
        for (unsigned int b = 0; b < n_A; ++b)
          J(a, b) = delassus[a * n_A + b] / node.D;
        for (unsigned int k = 0; k < m; ++k)
          {
            const Tensor<1, 3> v =
              d.velocity[k].first * node.master_point + d.velocity[k].second;
            J(a, n_A + k) =
              (node.gap_gradient * v - zone.apply(active[a], d.u0[k])) / node.D;
          }
        rhs(a) = -(node.weighted_gap - zone.apply(active[a], zone.u0)) / node.D;
      }
    for (unsigned int p = 0; p < m; ++p)
      {
        const auto [index, scale] = rows[p];
        for (unsigned int b = 0; b < n_A; ++b)
          J(n_A + p, b) = -scale * point.z[active[b]].observations[index];
        for (unsigned int k = 0; k < m; ++k)
          J(n_A + p, n_A + k) = scale * d.observations[k][index];
        rhs(n_A + p) = -scale * point.u0_observations[index];
      }

    return newton;
  }

  // LU with partial pivoting; a singular matrix, or a pose change beyond
  // any motion of a step (a nearly singular one), is a failure.
  bool
  CondensedActiveSetSolver::solve_newton_system(const PoseSystem       &system,
                                                const PoseNewtonSystem &newton,
                                                const double            damping,
                                                std::vector<double>    &dq)
  {
    const auto               rows     = system.residual_rows();
    const unsigned int       n_active = newton.n_active;
    LAPACKFullMatrix<double> matrix(newton.matrix);
    for (unsigned int p = 0; p < rows.size(); ++p)
      matrix(n_active + p, n_active + p) -= damping * rows[p].second;
    Vector<double> x(newton.rhs);
    try
      {
        matrix.compute_lu_factorization();
        matrix.solve(x);
      }
    catch (const ExceptionBase &)
      {
        return false;
      }
    for (unsigned int k = 0; k < dq.size(); ++k)
      dq[k] = x(n_active + k);
    return std::all_of(x.begin(),
                       x.end(),
                       [](const double v) { return std::isfinite(v); }) &&
           system.step_size(dq) < 1e3;
  }

  // G^-1 of the force columns' observations (PoseSystem::force_columns()):
  // G^-1 S^-1 r is the unbalanced generalized force of a pose residual r.
  FullMatrix<double>
  CondensedActiveSetSolver::rigid_stiffness(const PoseSystem &system) const
  {
    const auto         rows    = system.residual_rows();
    const auto         columns = system.force_columns();
    const unsigned int m       = rows.size();
    FullMatrix<double> G(m, m);
    for (unsigned int p = 0; p < m; ++p)
      for (unsigned int k = 0; k < m; ++k)
        {
          AssertIndexRange(columns[k], basis_columns.size() - 1);
          G(p, k) = basis_columns[columns[k]].observations[rows[p].first];
        }
    FullMatrix<double> stiffness(m, m);
    stiffness.invert(G);
    return stiffness;
  }

  // The search direction (doc/gait.md, "Globalisation"): the Newton step
  // if it is gradient related in V, i.e. its cosine with the steepest
  // descent direction d = S^-1 r in the stiffness metric,
  //   -phi'(0) / (|dq|_K |d|_K),  phi'(0) = -dq . K d,
  // is at least min_cosine; else the Newton step damped (Levenberg-
  // Marquardt) by mu = 1/64, 1/16, ... until the cosine is at least
  // damped_cosine (the Newton model has just failed there, so the step
  // leans towards d: fewer solves than min_cosine on the cases that
  // damp, doc/gait.md). Damping turns dq continuously from the Newton
  // step to d, which descends (K is positive definite). Only if no damping
  // up to max_damping gives such a direction is d itself taken (counted as
  // a fallback).
  std::vector<double>
  CondensedActiveSetSolver::pose_search_direction(
    const PoseSystem         &system,
    PosePoint                &point,
    const FullMatrix<double> &stiffness,
    PoseStatistics           &statistics)
  {
    const auto         rows = system.residual_rows();
    const unsigned int m    = rows.size();
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

    const PoseNewtonSystem newton = pose_newton_system(system, point);
    std::vector<double>    dq(m);
    double                 regularisation = 0;
    if (!solve_newton_system(system, newton, 0., dq))
      {
        ++statistics.n_regularised;
        regularisation = 1;
        AssertThrow(solve_newton_system(system, newton, regularisation, dq),
                    ExcMessage("The Newton matrix of the contact and the "
                               "pose is singular."));
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
        if (solve_newton_system(system, newton, regularisation + mu, dq))
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
  CondensedActiveSetSolver::PoseStep
  CondensedActiveSetSolver::pose_line_search(
    PoseSystem                &system,
    const PosePoint           &start,
    const ContactState        &start_state,
    const std::vector<double> &dq,
    const std::function<double(const PosePoint &, const std::vector<double> &)>
                   &slope,
    const double    initial_distance,
    unsigned int   &newton_iterations,
    PoseStatistics &pose_statistics)
  {
    const double slope_0   = slope(start, dq);
    const double alpha_max = std::min(1., max_pose_step / system.step_size(dq));
    double       low = 0, slope_low = slope_0;
    double       high = alpha_max, slope_high = 0;
    bool         has_high = false;
    PoseStep     lowest;
    double       alpha = alpha_max;
    for (unsigned int n = 0; n < max_line_search_steps; ++n)
      {
        std::vector<double> q_trial(start.q.size());
        for (unsigned int k = 0; k < q_trial.size(); ++k)
          q_trial[k] = start.q[k] + alpha * dq[k];
        PoseStep trial;
        trial.state = start_state;
        bool solved = system.couple(q_trial);
        if (solved)
          {
            trial.point = make_pose_point(system, q_trial);
            trial.statistics =
              solve_at_pose(system, initial_distance, trial.point, trial.state);
            newton_iterations += trial.statistics.newton_iterations;
            ++pose_statistics.n_solves;
            solved = trial.statistics.converged;
          }
        const double s = solved ? slope(trial.point, dq) : 0.;
        if (solved && (std::abs(s) <= line_search_eta * std::abs(slope_0) ||
                       (s < 0 && alpha == alpha_max)))
          {
            trial.outcome = PoseStep::accepted;
            return trial;
          }
        if (solved && s < 0)
          {
            low            = alpha;
            slope_low      = s;
            lowest         = std::move(trial);
            lowest.outcome = PoseStep::lowered;
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
        ++pose_statistics.n_step_cuts;
      }
    return lowest;
  }

  // The iteration (doc/gait.md, "Pose and contact in one Newton"): the
  // contact solution at the starting pose (enough for a warm step whose
  // pose still holds); then, at the contact solution (lambda, q) of the
  // current pose, the Newton step of multipliers and pose together
  // (pose_search_direction()), and a line search along its pose part dq
  // in the step's potential energy V(q) (the elastic energy and the work
  // of the loads and springs at the contact solution of q). V is convex
  // for small rotations, its gradient is continuous (the contact force is,
  // item 2 of issue 33) and equals -G^-1 S^-1 r, so the slope of V along
  // dq is known at every trial pose without V itself:
  //   phi'(alpha) = -dq . G^-1 S^-1 r(q + alpha dq).
  // The line search looks for |phi'(alpha)| <= eta |phi'(0)| (the strong
  // Wolfe condition), from the full step (at most max_pose_step) by
  // regula falsi on phi' (increasing in alpha): every accepted step
  // lowers V, and a Newton direction that lies across a change of the
  // active set (where the merit |r|^2 has a kink and its one-sided Newton
  // directions point against each other) still lowers V. A Newton
  // direction that is not gradient related in V (follower loads and the
  // finite rotation make the Newton matrix differ from V's Hessian) is
  // damped until it is (pose_search_direction()). The iteration ends when every
  // |r_p| <= tolerance; a step that finds no contact solution near its start
  // ends it, not converged.
  ContactStatistics
  CondensedActiveSetSolver::solve_with_pose(PoseSystem          &system,
                                            std::vector<double> &q,
                                            const double         tolerance,
                                            const unsigned int   max_iterations,
                                            const double    initial_distance,
                                            ContactState   &state,
                                            PoseStatistics &pose_statistics)
  {
    const auto               rows      = system.residual_rows();
    const FullMatrix<double> stiffness = rigid_stiffness(system);
    const auto               force     = [&](const PosePoint &p) {
      Vector<double> displacement(rows.size()), f(rows.size());
      for (unsigned int k = 0; k < rows.size(); ++k)
        displacement(k) = p.residual[k] / rows[k].second;
      stiffness.vmult(f, displacement);
      return f;
    };
    const auto slope = [&](const PosePoint &p, const std::vector<double> &d) {
      const Vector<double> f   = force(p);
      double               sum = 0;
      for (unsigned int k = 0; k < d.size(); ++k)
        sum -= d[k] * f(k);
      return sum;
    };
    const auto largest = [](const PosePoint &p) {
      double r_max = 0;
      for (const double r : p.residual)
        r_max = std::max(r_max, std::abs(r));
      return r_max;
    };
    pose_statistics         = PoseStatistics();
    PosePoint         point = make_pose_point(system, q);
    ContactStatistics statistics =
      solve_at_pose(system, initial_distance, point, state);
    pose_statistics.n_solves       = 1;
    unsigned int newton_iterations = statistics.newton_iterations;
    bool         stuck             = false;
    while (!(statistics.converged && largest(point) <= tolerance) &&
           pose_statistics.n_iterations < max_iterations && !stuck)
      {
        ++pose_statistics.n_iterations;
        const std::vector<double> dq =
          pose_search_direction(system, point, stiffness, pose_statistics);
        PoseStep step = pose_line_search(system,
                                         point,
                                         state,
                                         dq,
                                         slope,
                                         initial_distance,
                                         newton_iterations,
                                         pose_statistics);
        if (step.outcome == PoseStep::stuck)
          {
            // No contact solution, or no descent, near the start: the
            // solve ends, not converged, at the last point.
            stuck = true;
            system.couple(point.q);
            continue;
          }
        point      = std::move(step.point);
        state      = std::move(step.state);
        statistics = step.statistics;
        if (step.outcome == PoseStep::lowered)
          {
            // The bracket's lower end lowers V: taken, counted.
            ++pose_statistics.n_stalled_steps;
            system.couple(point.q);
          }
      }
    q                        = point.q;
    pose_statistics.residual = largest(point);
    pose_statistics.converged =
      statistics.converged && pose_statistics.residual <= tolerance;
    if (pose_statistics.converged)
      {
        PoseStatistics            ignored;
        const std::vector<double> dq =
          pose_search_direction(system, point, stiffness, ignored);
        pose_statistics.refined = q;
        for (unsigned int k = 0; k < q.size(); ++k)
          pose_statistics.refined[k] += dq[k];
      }
    statistics.newton_iterations = newton_iterations;
    return statistics;
  }
} // namespace TKR::Contact
