// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

// The analytic derivatives of a gait step's pose equations at a contact
// solution of the condensed active set (CondensedActiveSetSolver::
// pose_derivatives(), for PoseNewton): the multipliers of the active set
// and the pose linearised together, from the compliance columns. The
// equations are in doc/gait.md, "The pose Newton".

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
  std::shared_ptr<CondensedActiveSetSolver::PoseData>
  CondensedActiveSetSolver::make_pose_data(const PoseSystem          &system,
                                           const std::vector<double> &q)
  {
    TimerOutput::Scope scope(timer, "contact zone");
    auto               data = std::make_shared<PoseData>();
    data->coefficients      = system.load_coefficients(q);
    combine_basis(data->coefficients, data->u0, data->u0_observations);
    data->zone = make_zone(Mortar::MortarOperator(coupling), data->u0);
    data->z.resize(coupling.slave_nodes().size());
    return data;
  }

  // The active set iteration of solve() on the zone of @p data, its
  // columns z_i kept there for the Newton matrix; the active set of the
  // point's state (if it has one) is the start.
  void
  CondensedActiveSetSolver::solve_at_pose(const PoseSystem &system,
                                          const double      initial_distance,
                                          PoseData         &data,
                                          PoseDerivatives::Point &point)
  {
    const auto                    operator_B = mortar_operator();
    const Mortar::MortarOperator &B          = *operator_B;
    ContactStatistics             statistics = iterate(B,
                                           data.zone,
                                           data.z,
                                           data.u0,
                                           data.u0_observations,
                                           initial_distance,
                                           point.state);
    statistics.relative_residual             = basis_residual;
    statistics.converged =
      statistics.converged && basis_residual <= parameters.tolerance;
    last_rhs.clear();
    last_coefficients = data.coefficients;
    data.active       = point.state.active;
    point.residual.clear();
    for (const auto &[index, scale] : system.residual_rows())
      point.residual.push_back(scale * observed[index]);
    point.statistics = statistics;
  }

  // How u_0 and its observations change with the pose through the loads
  // (central differences of the load coefficients: exact for the linear
  // ones, the mean slope at a restraint's kink), and the velocity fields of
  // the master's points.
  CondensedActiveSetSolver::PoseSensitivities
  CondensedActiveSetSolver::pose_sensitivities(const PoseSystem &system,
                                               const std::vector<double> &q,
                                               const PoseData &data) const
  {
    const unsigned int m      = system.n_unknowns();
    const unsigned int n_zone = data.zone.values.size();
    PoseSensitivities  d;
    d.u0.assign(m, std::vector<double>(n_zone, 0.));
    d.observations.assign(m,
                          std::vector<double>(data.u0_observations.size(), 0.));
    for (unsigned int k = 0; k < m; ++k)
      {
        const double        h    = 1e-6 * std::max(1., std::abs(q[k]));
        std::vector<double> plus = q, minus = q;
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
              d.u0[k][v] += dc * column.surface[data.zone.values[v]];
            for (unsigned int o = 0; o < column.observations.size(); ++o)
              d.observations[k][o] += dc * column.observations[o];
          }
        d.velocity.push_back(system.master_velocity(q, k));
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
                                               const std::vector<double> &q,
                                               PoseData                  &data)
  {
    const auto                   &nodes      = coupling.slave_nodes();
    const auto                    operator_B = mortar_operator();
    const Mortar::MortarOperator &B          = *operator_B;
    std::vector<unsigned int>     active;
    for (unsigned int j = 0; j < nodes.size(); ++j)
      if (data.active[j])
        active.push_back(j);
    ensure_columns(B, active);

    TimerOutput::Scope      scope(timer, "condensed Newton step");
    const Zone             &zone = data.zone;
    const unsigned int      m    = system.n_unknowns();
    const unsigned int      n_A  = active.size();
    const auto              rows = system.residual_rows();
    const PoseSensitivities d    = pose_sensitivities(system, q, data);
    AssertDimension(rows.size(), m);
    for (const unsigned int i : active)
      if (data.z[i].surface.empty())
        data.z[i] = zone_column(B, zone, i);

    PoseNewtonSystem newton;
    newton.n_active               = n_A;
    LAPACKFullMatrix<double> &J   = newton.matrix;
    Vector<double>           &rhs = newton.rhs;
    J.reinit(n_A + m, n_A + m);
    rhs.reinit(n_A + m);
    const std::vector<double> delassus = zone.delassus(active, data.z);
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
          J(n_A + p, b) = -scale * data.z[active[b]].observations[index];
        for (unsigned int k = 0; k < m; ++k)
          J(n_A + p, n_A + k) = scale * d.observations[k][index];
        rhs(n_A + p) = -scale * data.u0_observations[index];
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

  /**
   * The analytic pose derivatives (pose_derivatives()): each contact
   * solution keeps its zone and columns (PoseData), its Newton system is
   * assembled once, when the first Newton step there needs it.
   */
  class CondensedActiveSetSolver::AnalyticPose : public PoseDerivatives
  {
  public:
    AnalyticPose(CondensedActiveSetSolver &solver,
                 PoseSystem               &system,
                 const double              initial_distance)
      : solver(solver)
      , system(system)
      , initial_distance(initial_distance)
    {}

    bool
    solve(Point &point, const bool couple) override
    {
      if (couple && !system.couple(point.q))
        return false;
      auto data = solver.make_pose_data(system, point.q);
      solver.solve_at_pose(system, initial_distance, *data, point);
      point.data = data;
      ++n_solves;
      newton_iterations += point.statistics.newton_iterations;
      return true;
    }

    bool
    newton_step(Point               &point,
                const double         damping,
                std::vector<double> &dq) override
    {
      auto &data = dynamic_cast<PoseData &>(*point.data);
      if (!data.newton)
        data.newton = std::make_unique<PoseNewtonSystem>(
          solver.pose_newton_system(system, point.q, data));
      return solve_newton_system(system, *data.newton, damping, dq);
    }

    bool
    newton_step_is_cheap() const override
    {
      return true;
    }

    FullMatrix<double>
    metric() const override
    {
      return solver.rigid_stiffness(system);
    }

  private:
    CondensedActiveSetSolver &solver;
    PoseSystem               &system;
    const double              initial_distance;
  };

  std::unique_ptr<PoseDerivatives>
  CondensedActiveSetSolver::pose_derivatives(PoseSystem  &system,
                                             const double initial_distance)
  {
    return std::make_unique<AnalyticPose>(*this, system, initial_distance);
  }
} // namespace TKR::Contact
