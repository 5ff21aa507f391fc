// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#include <deal.II/base/timer.h>

#include <deal.II/lac/lapack_full_matrix.h>

#include <tkr/contact/condensed_solver.h>

#include "term_sum.h"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <limits>

namespace TKR::Contact
{
  using namespace dealii;


  void
  CondensedActiveSetSolver::setup(
    const Mapping<3>                &mapping,
    const AffineConstraints<double> &dirichlet_constraints,
    const Elasticity::BoundaryLoads &loads)
  {
    ContactSolver::setup(mapping, dirichlet_constraints, loads);
    system.setup(dirichlet);
    system.assemble(mapping, dirichlet, loads);
    // The part of the right-hand side that comes from inhomogeneous
    // Dirichlet values (load_vector() leaves it out).
    dirichlet_rhs = system.rhs();
    dirichlet_rhs -= elasticity.load_vector(mapping, dirichlet, loads);
    {
      TimerOutput::Scope scope(timer, "direct factorisation");
      direct_solver.factorize(system.matrix());
    }

    surface_dofs    = Mortar::surface_dof_indices(coupling);
    n_slave_values  = 3 * coupling.slave_surface().nodes().size();
    n_master_values = surface_dofs.size() - n_slave_values;
    const std::uint64_t fingerprint = master_fingerprint();
    last_stiffness_nodes.clear();
    if (node_columns.size() == coupling.slave_surface().nodes().size() +
                                 coupling.master_surface().nodes().size() &&
        used_nodes.size() == node_columns.size())
      for (unsigned int node = 0; node < node_columns.size(); ++node)
        if (!node_columns[node][0].surface.empty() && used_nodes[node])
          last_stiffness_nodes.push_back(node);
    clear_columns(!node_columns.empty() && fingerprint == master_block);
    master_block = fingerprint;
    new_cycle();
  }

  void
  CondensedActiveSetSolver::new_cycle()
  {
    used_nodes.assign(node_columns.size(), false);
  }

  // u_0 = K^{-1} f with f the tractions of the loads (the springs are in
  // K) and the Dirichlet values.
  ContactStatistics
  CondensedActiveSetSolver::solve(const Mapping<3>                &mapping,
                                  const Elasticity::BoundaryLoads &loads,
                                  const double  initial_distance,
                                  ContactState &state)
  {
    Assert(direct_solver.is_factorized(),
           ExcMessage("Call setup() before solve()."));
    TrilinosWrappers::MPI::Vector f =
      elasticity.load_vector(mapping, dirichlet, loads);
    f += dirichlet_rhs;
    TrilinosWrappers::MPI::Vector u0(f);
    double                        relative_residual;
    {
      TimerOutput::Scope scope(timer, "direct solve");
      direct_solver.solve(u0.trilinos_vector(), f.trilinos_vector());
      TrilinosWrappers::MPI::Vector residual(f);
      relative_residual =
        system.matrix().residual(residual, u0, f) /
        std::max(f.l2_norm(), std::numeric_limits<double>::min());
    }
    const std::vector<double> u0_observations = observe(u0.trilinos_vector());
    dirichlet.distribute(u0);
    ContactStatistics statistics =
      iterate(read_surface(u0.trilinos_vector(), true),
              u0_observations,
              initial_distance,
              state);
    statistics.relative_residual = relative_residual;
    statistics.converged =
      statistics.converged && relative_residual <= parameters.tolerance;
    last_rhs = f;
    return statistics;
  }

  // One batch of back substitutions: the basis loads and the Dirichlet
  // values (as the last basis "load", coefficient 1).
  void
  CondensedActiveSetSolver::set_load_basis(
    const Mapping<3>                             &mapping,
    const std::vector<Elasticity::BoundaryLoads> &basis)
  {
    ContactSolver::set_load_basis(mapping, basis);
    TimerOutput::Scope scope(timer, "direct solve");
    basis_rhs.clear();
    for (const auto &load : basis)
      {
        basis_rhs.push_back(elasticity.load_vector(mapping, dirichlet, load));
      }
    basis_rhs.push_back(dirichlet_rhs);
    const unsigned int n_basis = basis_rhs.size();
    Epetra_MultiVector rhs(direct_solver.row_map(), n_basis);
    Epetra_MultiVector X(direct_solver.row_map(), n_basis);
    for (unsigned int b = 0; b < n_basis; ++b)
      *rhs(b) = *basis_rhs[b].trilinos_vector()(0);
    direct_solver.solve(X, rhs);
    basis_residual = 0;
    TrilinosWrappers::MPI::Vector u(basis_rhs[0]), residual(basis_rhs[0]);
    for (unsigned int b = 0; b < n_basis; ++b)
      {
        *u.trilinos_vector()(0) = *X(b);
        const double norm       = basis_rhs[b].l2_norm();
        if (norm > 0)
          basis_residual =
            std::max(basis_residual,
                     system.matrix().residual(residual, u, basis_rhs[b]) /
                       norm);
        dirichlet.distribute(u);
        *X(b) = *u.trilinos_vector()(0);
      }
    const std::vector<double> values         = read_surface(X, true);
    const std::vector<double> observations   = observe(X);
    const unsigned int        n              = surface_dofs.size();
    const unsigned int        n_observations = observation_weights.size();
    basis_columns.resize(n_basis);
    for (unsigned int b = 0; b < n_basis; ++b)
      {
        basis_columns[b].surface.assign(values.begin() + b * n,
                                        values.begin() + (b + 1) * n);
        basis_columns[b].observations.assign(observations.begin() +
                                               b * n_observations,
                                             observations.begin() +
                                               (b + 1) * n_observations);
      }
  }

  // u_0 = sum_i c_i K^{-1} f_i + K^{-1} f_Dirichlet from the stored
  // solutions.
  ContactStatistics
  CondensedActiveSetSolver::solve(const Mapping<3> &,
                                  const std::vector<double> &coefficients,
                                  const double               initial_distance,
                                  ContactState              &state)
  {
    std::vector<double> u0, u0_observations;
    {
      TimerOutput::Scope scope(timer, "contact zone");
      combine_basis(coefficients, u0, u0_observations);
    }
    ContactStatistics statistics =
      iterate(u0, u0_observations, initial_distance, state);
    statistics.relative_residual = basis_residual;
    statistics.converged =
      statistics.converged && basis_residual <= parameters.tolerance;
    last_rhs.clear();
    last_coefficients = coefficients;
    return statistics;
  }

  // W_AA lambda_A = -g_0,A with g_0 = g - B u_0, by Cholesky; then the
  // displacement on the zone u = u_0 - sum_i lambda_i z_i gives the
  // pressures of the active nodes and the gaps of all covered ones.
  void
  CondensedActiveSetSolver::newton_step(const Zone                      &zone,
                                        const std::vector<unsigned int> &active,
                                        const std::vector<Column>       &z,
                                        ContactState &state) const
  {
    const auto               &nodes    = coupling.slave_nodes();
    const unsigned int        n_active = active.size();
    Vector<double>            lambda(n_active);
    LAPACKFullMatrix<double>  W(n_active, n_active);
    const std::vector<double> delassus = zone.delassus(active, z);
    for (unsigned int a = 0; a < n_active; ++a)
      {
        const unsigned int j = active[a];
        lambda(a) = -(nodes[j].weighted_gap - zone.apply(j, zone.u0));
        for (unsigned int b = 0; b < n_active; ++b)
          W(a, b) = delassus[a * n_active + b];
      }
    if (n_active > 0)
      {
        // W is symmetric positive definite in exact arithmetic;
        // symmetrise the round-off before the Cholesky factorisation.
        for (unsigned int a = 0; a < n_active; ++a)
          for (unsigned int b = 0; b < a; ++b)
            W(a, b) = W(b, a) = 0.5 * (W(a, b) + W(b, a));
        W.set_property(LAPACKSupport::symmetric);
        W.compute_cholesky_factorization();
        W.solve(lambda);
      }
    std::vector<double> u_zone = zone.u0;
    {
      TermSum sum(u_zone.data(), u_zone.size());
      for (unsigned int a = 0; a < n_active; ++a)
        sum.add(-lambda(a), z[active[a]].surface.data());
    }
    std::fill(state.pressure.begin(), state.pressure.end(), 0.);
    for (unsigned int a = 0; a < n_active; ++a)
      state.pressure[active[a]] = lambda(a);
    for (unsigned int j = 0; j < nodes.size(); ++j)
      if (nodes[j].covered)
        state.gap[j] =
          (nodes[j].weighted_gap - zone.apply(j, u_zone)) / nodes[j].D;
  }

  // The Newton iteration on the multipliers, on the contact zone
  // (make_zone()). Per iteration: the columns the active set needs, z_i =
  // K^{-1} B_i^T on the zone for every active node i, the dense matrix
  // W_AA = B_A z_A, its Cholesky solve for lambda_A, then u = u_0 - sum_i
  // lambda_i z_i gives the gaps of all covered nodes and the next active
  // set (newton_step()).
  ContactStatistics
  CondensedActiveSetSolver::iterate(const std::vector<double> &u0,
                                    const std::vector<double> &u0_observations,
                                    const double               initial_distance,
                                    ContactState              &state)
  {
    const auto                    operator_B = mortar_operator();
    const Mortar::MortarOperator &B          = *operator_B;
    std::vector<Column>           z(coupling.slave_nodes().size());
    Zone                          zone;
    {
      TimerOutput::Scope scope(timer, "contact zone");
      zone = make_zone(B, u0);
    }
    return iterate(B, zone, z, u0, u0_observations, initial_distance, state);
  }

  ContactStatistics
  CondensedActiveSetSolver::iterate(const Mortar::MortarOperator &B,
                                    const Zone                   &zone,
                                    std::vector<Column>          &z,
                                    const std::vector<double>    &u0,
                                    const std::vector<double> &u0_observations,
                                    const double               initial_distance,
                                    ContactState              &state)
  {
    const unsigned int n_slave = coupling.slave_nodes().size();
    start_state(coupling, initial_distance, state);

    ContactStatistics  statistics;
    ActiveSetUpdate    active_set_update(pcout, slave_youngs_modulus);
    const unsigned int n_columns_before = n_stored_columns;
    for (unsigned int iteration = 1; iteration <= parameters.max_iterations;
         ++iteration)
      {
        statistics.newton_iterations = iteration;
        std::vector<unsigned int> active;
        for (unsigned int j = 0; j < n_slave; ++j)
          if (state.active[j])
            active.push_back(j);
        ensure_columns(B, active);
        unsigned int n_changed = 0;
        {
          TimerOutput::Scope scope(timer, "condensed Newton step");
          for (const unsigned int i : active)
            if (z[i].surface.empty())
              z[i] = zone_column(B, zone, i);
          newton_step(zone, active, z, state);
          n_changed = active_set_update.count_changes(coupling, state);
        }
        trace << "    active set iteration " << std::setw(2) << iteration
              << ": " << std::setw(6) << active.size() << " active, "
              << std::setw(5) << n_changed << " changed" << std::endl;
        if (n_changed == 0)
          {
            statistics.converged = true;
            break;
          }
        active_set_update.update(coupling, state);
      }
    {
      TimerOutput::Scope scope(timer, "contact zone");
      finish_state(B, u0, u0_observations, state);
    }
    last_state                  = state;
    statistics.computed_columns = n_stored_columns - n_columns_before;
    add_contact_results(coupling, state, statistics);
    return statistics;
  }

  // The displacement of every slave node (the wear's slip needs it also
  // away from the zone) and the observed functionals, from the nodes that
  // carry a multiplier (those of the last Newton step): u = u_0 - K^{-1} y,
  // w . u likewise, with the loads y = sum_i lambda_i B_i^T (one stored
  // column per value of y, fewer than the active rows' entries). And a
  // bound of the master nodes' displacement (a coupling window needs it)
  // without computing it: |u_m| <= sqrt(3) max_r |u_r| and max_r |u_r| <=
  // max_r |u_0,r| + sum_c |y_c| peak_c over the master values c.
  void
  CondensedActiveSetSolver::finish_state(
    const Mortar::MortarOperator &B,
    const std::vector<double>    &u0,
    const std::vector<double>    &u0_observations,
    ContactState                 &state)
  {
    const unsigned int  n_slave = coupling.slave_nodes().size();
    std::vector<double> y(u0.size(), 0.);
    for (unsigned int i = 0; i < n_slave; ++i)
      if (state.pressure[i] != 0.)
        for (auto e = B.begin(i); e != B.end(i); ++e)
          y[e->column] += state.pressure[i] * e->value;

    std::vector<double> u_slave(u0.begin(), u0.begin() + n_slave_values);
    observed            = u0_observations;
    double master_bound = 0;
    for (unsigned int r = n_slave_values; r < u0.size(); ++r)
      master_bound = std::max(master_bound, std::abs(u0[r]));
    TermSum slave_sum(u_slave.data(), n_slave_values);
    for (unsigned int c = 0; c < y.size(); ++c)
      if (y[c] != 0.)
        {
          const Column &column = node_columns[c / 3][c % 3];
          if (c < n_slave_values)
            slave_sum.add(-y[c], column.surface.data());
          else
            master_bound += std::abs(y[c]) * column.peak;
          for (unsigned int m = 0; m < observed.size(); ++m)
            observed[m] -= y[c] * column.observations[m];
        }
    slave_sum.flush();
    for (unsigned int j = 0; j < n_slave; ++j)
      for (unsigned int e = 0; e < 3; ++e)
        state.displacement[j][e] = u_slave[3 * j + e];
    state.master_displacement = std::sqrt(3.) * master_bound;
  }

  TrilinosWrappers::MPI::Vector
  CondensedActiveSetSolver::compute_solution()
  {
    TimerOutput::Scope            scope(timer, "direct solve");
    const Mortar::MortarOperator  B(coupling);
    TrilinosWrappers::MPI::Vector f;
    if (last_rhs.size() > 0)
      f = last_rhs;
    else
      {
        // The combination of the load basis of the last solve.
        f = basis_rhs.back();
        for (unsigned int b = 0; b < last_coefficients.size(); ++b)
          f.add(last_coefficients[b], basis_rhs[b]);
      }
    for (unsigned int j = 0; j < B.n_rows(); ++j)
      if (last_state.active[j])
        for (auto e = B.begin(j); e != B.end(j); ++e)
          add_load(f.trilinos_vector(),
                   0,
                   surface_dofs[e->column],
                   -last_state.pressure[j] * e->value);
    TrilinosWrappers::MPI::Vector u(f);
    direct_solver.solve(u.trilinos_vector(), f.trilinos_vector());
    dirichlet.distribute(u);
    TrilinosWrappers::MPI::Vector solution = elasticity.make_ghosted_vector();
    solution                               = u;
    return solution;
  }
} // namespace TKR::Contact
