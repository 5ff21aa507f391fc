// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#include <deal.II/base/timer.h>

#include <deal.II/lac/lapack_full_matrix.h>

#include <tkr/base/exceptions.h>
#include <tkr/base/mpi.h>
#include <tkr/contact/condensed_solver.h>

#include <algorithm>
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
    elasticity.assemble_system(mapping, dirichlet, loads);
    // The part of the right-hand side that comes from inhomogeneous
    // Dirichlet values (assemble_rhs() leaves it out).
    dirichlet_rhs = elasticity.get_system_rhs();
    elasticity.assemble_rhs(mapping, dirichlet, loads);
    dirichlet_rhs -= elasticity.get_system_rhs();
    {
      TimerOutput::Scope scope(timer, "direct factorisation");
      direct_solver.factorize(elasticity.get_system_matrix());
    }

    surface_dofs    = Mortar::surface_dof_indices(coupling);
    n_slave_values  = 3 * coupling.slave_surface().nodes().size();
    n_master_values = surface_dofs.size() - n_slave_values;
    clear_columns();
  }

  void
  CondensedActiveSetSolver::clear_columns()
  {
    slave_columns.assign(coupling.slave_surface().nodes().size(), Column());
    slave_column_loads.assign(slave_columns.size(), Tensor<1, 3>());
    master_columns.assign(coupling.master_surface().nodes().size(), {});
    n_stored_columns = 0;
  }

  unsigned int
  CondensedActiveSetSolver::add_observation(
    const TrilinosWrappers::MPI::Vector &weights)
  {
    const unsigned int index = ContactSolver::add_observation(weights);
    clear_columns();
    return index;
  }

  std::vector<double>
  CondensedActiveSetSolver::observe(const Epetra_MultiVector &X) const
  {
    const unsigned int  n_observations = observation_weights.size();
    std::vector<double> values(X.NumVectors() * n_observations, 0.);
    for (unsigned int m = 0; m < n_observations; ++m)
      {
        const Epetra_MultiVector &w = observation_weights[m].trilinos_vector();
        for (int c = 0; c < X.NumVectors(); ++c)
          for (int i = 0; i < X.MyLength(); ++i)
            values[c * n_observations + m] += w[0][i] * X[c][i];
      }
    sum_over_ranks(values, mpi_communicator);
    return values;
  }

  // A unit load on a constrained DoF acts on the DoFs it depends on (the
  // transpose of the constraint), which is what assembling it would do.
  void
  CondensedActiveSetSolver::add_load(Epetra_MultiVector           &B,
                                     const unsigned int            c,
                                     const types::global_dof_index dof,
                                     const double                  value) const
  {
    if (const auto *entries = dirichlet.get_constraint_entries(dof))
      {
        for (const auto &[k, weight] : *entries)
          add_load(B, c, k, weight * value);
        return;
      }
    const int local = B.Map().LID(static_cast<int>(dof));
    if (local >= 0)
      B[c][local] += value;
  }

  // Each rank adds the values it owns (for a constrained DoF the weighted
  // values of the DoFs it depends on); one sum gives all ranks all values.
  std::vector<double>
  CondensedActiveSetSolver::read_surface(const Epetra_MultiVector &X,
                                         const bool distributed) const
  {
    const unsigned int  n = surface_dofs.size();
    std::vector<double> values(X.NumVectors() * n, 0.);
    const auto          add = [&](const types::global_dof_index dof,
                         const double                  weight,
                         const unsigned int            i) {
      const int local = X.Map().LID(static_cast<int>(dof));
      if (local >= 0)
        for (int c = 0; c < X.NumVectors(); ++c)
          values[c * n + i] += weight * X[c][local];
    };
    for (unsigned int i = 0; i < n; ++i)
      if (distributed)
        add(surface_dofs[i], 1., i);
      else if (const auto *entries =
                 dirichlet.get_constraint_entries(surface_dofs[i]))
        for (const auto &[k, weight] : *entries)
          add(k, weight, i);
      else if (!dirichlet.is_constrained(surface_dofs[i]))
        add(surface_dofs[i], 1., i);
    sum_over_ranks(values, mpi_communicator);
    return values;
  }

  // The columns are solved in batches (the factors are applied to many
  // right-hand sides at once); of each only the surface values and the
  // observations are kept.
  void
  CondensedActiveSetSolver::compute_columns(
    const Mortar::MortarOperator    &B,
    const std::vector<unsigned int> &slave,
    const std::vector<unsigned int> &master)
  {
    TimerOutput::Scope scope(timer, "compliance columns");
    const auto        &master_nodes = coupling.master_surface().nodes();
    // (slave node, 3) or (master node, direction).
    std::vector<std::pair<unsigned int, unsigned int>> loads;
    for (const unsigned int j : slave)
      loads.emplace_back(j, 3);
    for (const unsigned int k : master)
      for (unsigned int d = 0; d < 3; ++d)
        loads.emplace_back(k, d);
    const unsigned int batch = 128, n = surface_dofs.size();
    for (unsigned int start = 0; start < loads.size(); start += batch)
      {
        const unsigned int n_columns =
          std::min<unsigned int>(batch, loads.size() - start);
        Epetra_MultiVector rhs(direct_solver.row_map(), n_columns);
        Epetra_MultiVector X(direct_solver.row_map(), n_columns);
        for (unsigned int c = 0; c < n_columns; ++c)
          {
            const auto [node, d] = loads[start + c];
            if (d == 3)
              {
                for (auto e = B.begin(node); e != B.end(node); ++e)
                  if (e->column < n_slave_values)
                    add_load(rhs, c, surface_dofs[e->column], e->value);
              }
            else
              add_load(rhs, c, master_nodes[node].dofs[d], 1.);
          }
        direct_solver.solve(X, rhs);
        const std::vector<double> values         = read_surface(X, false);
        const std::vector<double> observations   = observe(X);
        const unsigned int        n_observations = observation_weights.size();
        for (unsigned int c = 0; c < n_columns; ++c)
          {
            const auto [node, d] = loads[start + c];
            const double *column = &values[c * n];
            // The other body's part must vanish (K does not couple them).
            const bool    is_slave = (d == 3);
            const double *own   = is_slave ? column : column + n_slave_values;
            const double *other = is_slave ? column + n_slave_values : column;
            const unsigned int n_own =
              is_slave ? n_slave_values : n_master_values;
            const unsigned int n_other =
              is_slave ? n_master_values : n_slave_values;
            double own_max = 0, other_max = 0;
            for (unsigned int i = 0; i < n_own; ++i)
              own_max = std::max(own_max, std::abs(own[i]));
            for (unsigned int i = 0; i < n_other; ++i)
              other_max = std::max(other_max, std::abs(other[i]));
            AssertThrow(other_max <= 1e-12 * own_max,
                        ExcInputError(
                          "The condensed active set needs bodies that touch "
                          "only through contact, but the stiffness matrix "
                          "couples the tibia_contact and femur_contact "
                          "surfaces. Use Contact solver/Solver = active "
                          "set."));
            Column &stored =
              is_slave ? slave_columns[node] : master_columns[node][d];
            stored.surface.assign(own, own + n_own);
            stored.observations.assign(observations.begin() +
                                         c * n_observations,
                                       observations.begin() +
                                         (c + 1) * n_observations);
          }
        n_stored_columns += n_columns;
      }
    for (const unsigned int j : slave)
      for (auto e = B.begin(j); e != B.end(j); ++e)
        if (e->column < n_slave_values)
          slave_column_loads[j][e->column - 3 * j] = e->value;
  }

  // z_i = K^{-1} B_i^T: the slave part is one stored column, the master
  // part sum_c B_ic K^{-1} e_c over the master entries of row i.
  CondensedActiveSetSolver::Column
  CondensedActiveSetSolver::compliance(const Mortar::MortarOperator &B,
                                       const unsigned int            i) const
  {
    const unsigned int n_observations = observation_weights.size();
    Column             z;
    z.surface.assign(surface_dofs.size(), 0.);
    z.observations = slave_columns[i].observations;
    std::copy(slave_columns[i].surface.begin(),
              slave_columns[i].surface.end(),
              z.surface.begin());
    for (auto e = B.begin(i); e != B.end(i); ++e)
      if (e->column >= n_slave_values)
        {
          const unsigned int c = e->column - n_slave_values;
          const Column      &m = master_columns[c / 3][c % 3];
          for (unsigned int r = 0; r < n_master_values; ++r)
            z.surface[n_slave_values + r] += e->value * m.surface[r];
          for (unsigned int o = 0; o < n_observations; ++o)
            z.observations[o] += e->value * m.observations[o];
        }
    return z;
  }

  // The Newton iteration on the multipliers. Per iteration: the columns the
  // active set needs, z_i = K^{-1} B_i^T at the surface for every active
  // node i, the dense matrix W_AA = B_A z_A, its Cholesky solve for
  // lambda_A, then the surface displacement u = u_0 - sum_i lambda_i z_i
  // gives the gaps of all nodes and the next active set.
  ContactStatistics
  CondensedActiveSetSolver::solve(const Mapping<3>                &mapping,
                                  const Elasticity::BoundaryLoads &loads,
                                  const double  initial_distance,
                                  ContactState &state)
  {
    const auto        &nodes   = coupling.slave_nodes();
    const unsigned int n_slave = nodes.size();
    Assert(direct_solver.is_factorized(),
           ExcMessage("Call setup() before solve()."));
    const Mortar::MortarOperator B(coupling);

    // u_0 = K^{-1} f.
    elasticity.assemble_rhs(mapping, dirichlet, loads);
    TrilinosWrappers::MPI::Vector f = elasticity.get_system_rhs();
    f += dirichlet_rhs;
    TrilinosWrappers::MPI::Vector u0(f);
    ContactStatistics             statistics;
    {
      TimerOutput::Scope scope(timer, "direct solve");
      direct_solver.solve(u0.trilinos_vector(), f.trilinos_vector());
      // The accuracy of the factorisation; the rest is dense algebra on
      // its columns.
      TrilinosWrappers::MPI::Vector residual(f);
      statistics.relative_residual =
        elasticity.get_system_matrix().residual(residual, u0, f) /
        std::max(f.l2_norm(), std::numeric_limits<double>::min());
    }
    const std::vector<double> u0_observations = observe(u0.trilinos_vector());
    dirichlet.distribute(u0);
    const std::vector<double> u0_surface =
      read_surface(u0.trilinos_vector(), true);

    start_state(coupling, initial_distance, state);

    ActiveSetUpdate     active_set_update(pcout, slave_youngs_modulus);
    const unsigned int  n_columns_before = n_stored_columns;
    std::vector<double> u_surface;
    // z_i for the nodes needed so far in this solve (the geometry, and so
    // B, is fixed within it).
    std::vector<Column> z(n_slave);

    for (unsigned int iteration = 1; iteration <= parameters.max_iterations;
         ++iteration)
      {
        statistics.newton_iterations = iteration;
        std::vector<unsigned int> active;
        for (unsigned int j = 0; j < n_slave; ++j)
          if (state.active[j])
            active.push_back(j);

        // The columns this active set needs.
        std::vector<unsigned int> slave_needed, master_needed;
        for (const unsigned int i : active)
          {
            Tensor<1, 3> load;
            for (auto e = B.begin(i); e != B.end(i); ++e)
              if (e->column < n_slave_values)
                load[e->column - 3 * i] = e->value;
            if (slave_columns[i].surface.empty() ||
                (slave_column_loads[i] - load).norm() > 1e-12 * load.norm())
              slave_needed.push_back(i);
            for (auto e = B.begin(i); e != B.end(i); ++e)
              if (e->column >= n_slave_values &&
                  master_columns[(e->column - n_slave_values) / 3][0]
                    .surface.empty())
                master_needed.push_back((e->column - n_slave_values) / 3);
          }
        std::sort(master_needed.begin(), master_needed.end());
        master_needed.erase(std::unique(master_needed.begin(),
                                        master_needed.end()),
                            master_needed.end());
        if (!slave_needed.empty() || !master_needed.empty())
          compute_columns(B, slave_needed, master_needed);

        const unsigned int n_active = active.size();
        Vector<double>     lambda(n_active);
        {
          TimerOutput::Scope scope(timer, "condensed Newton step");
          for (const unsigned int i : active)
            if (z[i].surface.empty())
              z[i] = compliance(B, i);

          // W_AA lambda_A = -g_0,A with g_0 = g - B u_0.
          LAPACKFullMatrix<double> W(n_active, n_active);
          for (unsigned int a = 0; a < n_active; ++a)
            {
              const unsigned int j = active[a];
              lambda(a) =
                -(nodes[j].weighted_gap - B.apply_row(j, u0_surface.data()));
              for (unsigned int b = 0; b < n_active; ++b)
                W(a, b) = B.apply_row(j, z[active[b]].surface.data());
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

          // Surface displacement, pressures and gaps.
          u_surface = u0_surface;
          for (unsigned int a = 0; a < n_active; ++a)
            {
              const auto &z_i = z[active[a]].surface;
              for (unsigned int r = 0; r < u_surface.size(); ++r)
                u_surface[r] -= lambda(a) * z_i[r];
            }
          std::fill(state.pressure.begin(), state.pressure.end(), 0.);
          for (unsigned int a = 0; a < n_active; ++a)
            state.pressure[active[a]] = lambda(a);
          for (unsigned int j = 0; j < n_slave; ++j)
            if (nodes[j].covered)
              state.gap[j] = B.gap(j, u_surface.data());
        }

        const unsigned int n_changed =
          active_set_update.count_changes(coupling, state);
        pcout << "    active set iteration " << std::setw(2) << iteration
              << ": " << std::setw(6) << n_active << " active, " << std::setw(5)
              << n_changed << " changed" << std::endl;
        if (n_changed == 0)
          {
            statistics.converged = true;
            break;
          }
        active_set_update.update(coupling, state);
      }

    statistics.converged = statistics.converged &&
                           statistics.relative_residual <= parameters.tolerance;
    for (unsigned int j = 0; j < n_slave; ++j)
      for (unsigned int e = 0; e < 3; ++e)
        state.displacement[j][e] = u_surface[3 * j + e];
    // The observed functionals: w . u = w . u_0 - sum_i lambda_i w . z_i
    // (over the nodes that carry a multiplier: those of the last Newton
    // step, whose z_i are known).
    observed = u0_observations;
    for (unsigned int j = 0; j < n_slave; ++j)
      if (state.pressure[j] != 0.)
        for (unsigned int m = 0; m < observed.size(); ++m)
          observed[m] -= state.pressure[j] * z[j].observations[m];
    last_rhs                    = f;
    last_state                  = state;
    statistics.computed_columns = n_stored_columns - n_columns_before;
    add_contact_results(coupling, state, statistics);
    return statistics;
  }

  void
  CondensedActiveSetSolver::compute_solution()
  {
    TimerOutput::Scope            scope(timer, "direct solve");
    const Mortar::MortarOperator  B(coupling);
    TrilinosWrappers::MPI::Vector f = last_rhs;
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
    elasticity.set_solution(u);
  }
} // namespace TKR::Contact
