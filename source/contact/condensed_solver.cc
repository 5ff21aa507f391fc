// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#include <deal.II/base/timer.h>

#include <deal.II/lac/lapack_full_matrix.h>

#include <tkr/base/exceptions.h>
#include <tkr/base/mpi.h>
#include <tkr/contact/condensed_solver.h>

#include <algorithm>
#include <cmath>
#include <cstring>
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
                                 coupling.master_surface().nodes().size())
      for (unsigned int node = 0; node < node_columns.size(); ++node)
        if (!node_columns[node][0].surface.empty())
          last_stiffness_nodes.push_back(node);
    clear_columns(!node_columns.empty() && fingerprint == master_block);
    master_block = fingerprint;
  }

  void
  CondensedActiveSetSolver::clear_columns(const bool keep_master)
  {
    const unsigned int n_slave_nodes = coupling.slave_surface().nodes().size();
    if (keep_master)
      std::fill(node_columns.begin(),
                node_columns.begin() + n_slave_nodes,
                std::array<Column, 3>());
    else
      node_columns.assign(n_slave_nodes +
                            coupling.master_surface().nodes().size(),
                          {});
    n_stored_columns = 0;
    for (auto &columns : node_columns)
      for (Column &column : columns)
        {
          column.observations.clear();
          n_stored_columns += !column.surface.empty();
        }
    basis_rhs.clear();
    basis_columns.clear();
  }

  // The master body's block of K is K restricted to the DoFs of the cells
  // of its material (the bodies share no DoFs); its columns vanish on the
  // slave body, so they need nothing else.
  std::uint64_t
  CondensedActiveSetSolver::master_fingerprint()
  {
    const DoFHandler<3>          &dof_handler = elasticity.get_dof_handler();
    const types::global_dof_index master_dof =
      coupling.master_surface().nodes().front().dofs[0];
    std::vector<types::global_dof_index> cell_dofs(
      dof_handler.get_fe().n_dofs_per_cell());
    types::material_id body = numbers::invalid_material_id;
    for (const auto &cell : dof_handler.active_cell_iterators())
      {
        cell->get_dof_indices(cell_dofs);
        if (std::find(cell_dofs.begin(), cell_dofs.end(), master_dof) !=
            cell_dofs.end())
          {
            body = cell->material_id();
            break;
          }
      }
    std::vector<types::global_dof_index> dofs;
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (cell->material_id() == body)
        {
          cell->get_dof_indices(cell_dofs);
          dofs.insert(dofs.end(), cell_dofs.begin(), cell_dofs.end());
        }
    std::sort(dofs.begin(), dofs.end());
    dofs.erase(std::unique(dofs.begin(), dofs.end()), dofs.end());
    master_body_dofs = IndexSet(dof_handler.n_dofs());
    master_body_dofs.add_indices(dofs.begin(), dofs.end());
    master_body_dofs = master_body_dofs & elasticity.locally_owned_dofs();

    // FNV-1a over the values' bytes
    std::uint64_t hash = 14695981039346656037ull;
    const auto    mix  = [&hash](const auto value) {
      unsigned char bytes[sizeof(value)];
      std::memcpy(bytes, &value, sizeof(value));
      for (const unsigned char b : bytes)
        hash = (hash ^ b) * 1099511628211ull;
    };
    // (Epetra's row views: deal.II's matrix iterators copy every row)
    const Epetra_CrsMatrix &K = system.matrix().trilinos_matrix();
    for (const auto row : master_body_dofs)
      {
        int     n = 0, *columns = nullptr;
        double *values = nullptr;
        K.ExtractMyRowView(K.LRID(static_cast<int>(row)), n, values, columns);
        for (int k = 0; k < n; ++k)
          {
            mix(K.ColMap().GID64(columns[k]));
            mix(values[k]);
          }
      }
    for (unsigned int i = n_slave_values; i < surface_dofs.size(); ++i)
      {
        mix(surface_dofs[i]);
        if (const auto *entries =
              dirichlet.get_constraint_entries(surface_dofs[i]))
          for (const auto &[k, weight] : *entries)
            {
              mix(k);
              mix(weight);
            }
        mix(dirichlet.is_constrained(surface_dofs[i]));
      }
    const std::vector<std::uint64_t> hashes =
      Utilities::MPI::all_gather(mpi_communicator, hash);
    for (const std::uint64_t h : hashes)
      mix(h);
    return hash;
  }

  // The columns' observations are recomputed, except those of the kept
  // master columns when the weights vanish on the master body: then they
  // are zero (the columns vanish on the slave body).
  unsigned int
  CondensedActiveSetSolver::add_observation(
    const TrilinosWrappers::MPI::Vector &weights)
  {
    const unsigned int index     = ContactSolver::add_observation(weights);
    double             on_master = 0;
    for (const auto i : master_body_dofs)
      on_master = std::max(on_master, std::abs(weights[i]));
    clear_columns(Utilities::MPI::max(on_master, mpi_communicator) == 0);
    for (auto &columns : node_columns)
      for (Column &column : columns)
        if (!column.surface.empty())
          column.observations.assign(observation_weights.size(), 0.);
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
  // right-hand sides at once); of each only its own body's surface values
  // and the observations are kept.
  void
  CondensedActiveSetSolver::compute_columns(
    const std::vector<unsigned int> &nodes)
  {
    TimerOutput::Scope scope(timer, "compliance columns");
    const unsigned int batch = 128, n = surface_dofs.size();
    const unsigned int n_observations = observation_weights.size();
    for (unsigned int start = 0; start < 3 * nodes.size(); start += batch)
      {
        const unsigned int n_columns =
          std::min<unsigned int>(batch, 3 * nodes.size() - start);
        Epetra_MultiVector rhs(direct_solver.row_map(), n_columns);
        Epetra_MultiVector X(direct_solver.row_map(), n_columns);
        for (unsigned int c = 0; c < n_columns; ++c)
          add_load(rhs,
                   c,
                   surface_dofs[3 * nodes[(start + c) / 3] + (start + c) % 3],
                   1.);
        direct_solver.solve(X, rhs);
        const std::vector<double> values       = read_surface(X, false);
        const std::vector<double> observations = observe(X);
        for (unsigned int c = 0; c < n_columns; ++c)
          {
            const unsigned int node   = nodes[(start + c) / 3];
            const double      *column = &values[c * n];
            // The other body's part must vanish (K does not couple them).
            const bool    is_slave = 3 * node < n_slave_values;
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
            Column &stored = node_columns[node][(start + c) % 3];
            stored.surface.assign(own, own + n_own);
            stored.peak = own_max;
            stored.observations.assign(observations.begin() +
                                         c * n_observations,
                                       observations.begin() +
                                         (c + 1) * n_observations);
          }
        n_stored_columns += n_columns;
      }
  }

  // Every peer lists the nodes it wants (its last stiffness's) and those it
  // holds (kept master columns); a node that a peer lacks is sent by the
  // first peer that holds it or, if none does, computed by one peer (in
  // turn) and sent by it. The columns travel in rounds of a few nodes per
  // peer, to bound the buffers.
  void
  CondensedActiveSetSolver::prefetch(const MPI_Comm peers)
  {
    const unsigned int n_nodes = node_columns.size();
    const unsigned int n_peers = Utilities::MPI::n_mpi_processes(peers);
    const unsigned int me      = Utilities::MPI::this_mpi_process(peers);
    // per node: whether this peer wants it, then whether it holds it
    std::vector<int> local(2 * n_nodes, 0);
    for (const unsigned int node : last_stiffness_nodes)
      local[node] = 1;
    for (unsigned int node = 0; node < n_nodes; ++node)
      if (!node_columns[node][0].surface.empty())
        local[n_nodes + node] = 1;
    std::vector<int>       offsets;
    const std::vector<int> all = all_gather_values(local, peers, &offsets);
    AssertThrow(offsets.back() == static_cast<int>(2 * n_nodes * n_peers),
                ExcInternalError());

    // who sends each node that some peer lacks (its list per peer)
    std::vector<std::vector<unsigned int>> sent(n_peers);
    std::vector<unsigned int>              to_compute;
    unsigned int                           turn = 0;
    for (unsigned int node = 0; node < n_nodes; ++node)
      {
        bool         wanted  = false;
        unsigned int holders = 0, holder = n_peers;
        for (unsigned int p = 0; p < n_peers; ++p)
          {
            wanted = wanted || all[2 * n_nodes * p + node] != 0;
            if (all[2 * n_nodes * p + n_nodes + node] != 0)
              {
                ++holders;
                holder = std::min(holder, p);
              }
          }
        if (holders == n_peers || (!wanted && holders == 0))
          continue;
        if (holders == 0)
          {
            holder = turn++ % n_peers;
            if (holder == me)
              to_compute.push_back(node);
          }
        sent[holder].push_back(node);
      }
    if (!to_compute.empty())
      compute_columns(to_compute);
    if (n_peers == 1)
      return;

    TimerOutput::Scope scope(timer, "compliance column exchange");
    const unsigned int n_observations = observation_weights.size();
    const unsigned int round          = 32;
    std::size_t        n_rounds       = 0;
    for (const auto &nodes : sent)
      n_rounds = std::max(n_rounds, (nodes.size() + round - 1) / round);
    for (std::size_t r = 0; r < n_rounds; ++r)
      {
        std::vector<double> packed;
        for (std::size_t k = r * round;
             k < std::min<std::size_t>((r + 1) * round, sent[me].size());
             ++k)
          for (const Column &column : node_columns[sent[me][k]])
            {
              Assert(column.observations.size() == n_observations,
                     ExcInternalError());
              packed.insert(packed.end(),
                            column.surface.begin(),
                            column.surface.end());
              packed.insert(packed.end(),
                            column.observations.begin(),
                            column.observations.end());
              packed.push_back(column.peak);
            }
        const std::vector<double> received =
          all_gather_values(packed, peers, &offsets);
        for (unsigned int p = 0; p < n_peers; ++p)
          {
            const double *value = received.data() + offsets[p];
            for (std::size_t k = r * round;
                 k < std::min<std::size_t>((r + 1) * round, sent[p].size());
                 ++k)
              {
                const unsigned int node = sent[p][k];
                const unsigned int n_own =
                  3 * node < n_slave_values ? n_slave_values : n_master_values;
                for (Column &column : node_columns[node])
                  {
                    if (p != me && column.surface.empty())
                      {
                        column.surface.assign(value, value + n_own);
                        column.observations.assign(value + n_own,
                                                   value + n_own +
                                                     n_observations);
                        column.peak = value[n_own + n_observations];
                        ++n_stored_columns;
                      }
                    value += n_own + n_observations + 1;
                  }
              }
            AssertThrow(value == received.data() + offsets[p + 1],
                        ExcInternalError());
          }
      }
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
    combine_basis(coefficients, u0, u0_observations);
    ContactStatistics statistics =
      iterate(u0, u0_observations, initial_distance, state);
    statistics.relative_residual = basis_residual;
    statistics.converged =
      statistics.converged && basis_residual <= parameters.tolerance;
    last_rhs.clear();
    last_coefficients = coefficients;
    return statistics;
  }

  // The contact zone: the surface values that the rows of covered nodes
  // reference (compact index k, surface value zone[k]), and those rows on
  // it.
  CondensedActiveSetSolver::Zone
  CondensedActiveSetSolver::make_zone(const Mortar::MortarOperator &B,
                                      const std::vector<double>    &u0) const
  {
    const auto        &nodes   = coupling.slave_nodes();
    const unsigned int n_slave = nodes.size();
    Zone               zone;
    for (unsigned int j = 0; j < n_slave; ++j)
      if (nodes[j].covered)
        for (auto e = B.begin(j); e != B.end(j); ++e)
          zone.values.push_back(e->column);
    auto &values = zone.values;
    std::sort(values.begin(), values.end());
    values.erase(std::unique(values.begin(), values.end()), values.end());
    zone.n_slave =
      std::lower_bound(values.begin(), values.end(), n_slave_values) -
      values.begin();
    zone.rows.resize(n_slave);
    for (unsigned int j = 0; j < n_slave; ++j)
      if (nodes[j].covered)
        for (auto e = B.begin(j); e != B.end(j); ++e)
          zone.rows[j].push_back(
            {static_cast<unsigned int>(
               std::lower_bound(values.begin(), values.end(), e->column) -
               values.begin()),
             e->value});
    zone.u0.resize(values.size());
    for (unsigned int k = 0; k < values.size(); ++k)
      zone.u0[k] = u0[values[k]];
    return zone;
  }

  double
  CondensedActiveSetSolver::Zone::apply(const unsigned int         j,
                                        const std::vector<double> &v) const
  {
    double result = 0;
    for (const auto &e : rows[j])
      result += e.value * v[e.column];
    return result;
  }

  // The columns of the nodes that the rows of the active nodes touch and
  // that are not stored yet.
  void
  CondensedActiveSetSolver::ensure_columns(
    const Mortar::MortarOperator    &B,
    const std::vector<unsigned int> &active)
  {
    std::vector<unsigned int> needed;
    for (const unsigned int i : active)
      for (auto e = B.begin(i); e != B.end(i); ++e)
        if (node_columns[e->column / 3][e->column % 3].surface.empty())
          needed.push_back(e->column / 3);
    std::sort(needed.begin(), needed.end());
    needed.erase(std::unique(needed.begin(), needed.end()), needed.end());
    if (!needed.empty())
      compute_columns(needed);
  }

  // z_i = sum_c B_ic K^{-1} e_c on the zone: a slave column on the zone's
  // slave values, a master one on its master values.
  CondensedActiveSetSolver::Column
  CondensedActiveSetSolver::zone_column(const Mortar::MortarOperator &B,
                                        const Zone                   &zone,
                                        const unsigned int            i) const
  {
    const unsigned int n_observations = observation_weights.size();
    const unsigned int n_zone         = zone.values.size();
    Column             z;
    z.surface.assign(n_zone, 0.);
    z.observations.assign(n_observations, 0.);
    for (auto e = B.begin(i); e != B.end(i); ++e)
      {
        const Column      &column = node_columns[e->column / 3][e->column % 3];
        const bool         is_slave = e->column < n_slave_values;
        const unsigned int first    = is_slave ? 0 : zone.n_slave;
        const unsigned int last     = is_slave ? zone.n_slave : n_zone;
        const unsigned int offset   = is_slave ? 0 : n_slave_values;
        auto [gathered, is_new]     = zone.gathered.try_emplace(e->column);
        std::vector<double> &g      = gathered->second;
        if (is_new)
          {
            g.resize(last - first);
            for (unsigned int k = first; k < last; ++k)
              g[k - first] = column.surface[zone.values[k] - offset];
          }
        double *const      target = z.surface.data() + first;
        const double       value  = e->value;
        const unsigned int n      = last - first;
        for (unsigned int k = 0; k < n; ++k)
          target[k] += value * g[k];
        for (unsigned int o = 0; o < n_observations; ++o)
          z.observations[o] += e->value * column.observations[o];
      }
    return z;
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
    const auto              &nodes    = coupling.slave_nodes();
    const unsigned int       n_active = active.size();
    Vector<double>           lambda(n_active);
    LAPACKFullMatrix<double> W(n_active, n_active);
    for (unsigned int a = 0; a < n_active; ++a)
      {
        const unsigned int j = active[a];
        lambda(a) = -(nodes[j].weighted_gap - zone.apply(j, zone.u0));
        for (unsigned int b = 0; b < n_active; ++b)
          W(a, b) = zone.apply(j, z[active[b]].surface);
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
    for (unsigned int a = 0; a < n_active; ++a)
      {
        const auto &z_i = z[active[a]].surface;
        for (unsigned int k = 0; k < u_zone.size(); ++k)
          u_zone[k] -= lambda(a) * z_i[k];
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
    const Mortar::MortarOperator B(coupling);
    std::vector<Column>          z(coupling.slave_nodes().size());
    return iterate(B,
                   make_zone(B, u0),
                   z,
                   u0,
                   u0_observations,
                   initial_distance,
                   state);
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
        {
          TimerOutput::Scope scope(timer, "condensed Newton step");
          for (const unsigned int i : active)
            if (z[i].surface.empty())
              z[i] = zone_column(B, zone, i);
          newton_step(zone, active, z, state);
        }
        const unsigned int n_changed =
          active_set_update.count_changes(coupling, state);
        pcout << "    active set iteration " << std::setw(2) << iteration
              << ": " << std::setw(6) << active.size() << " active, "
              << std::setw(5) << n_changed << " changed" << std::endl;
        if (n_changed == 0)
          {
            statistics.converged = true;
            break;
          }
        active_set_update.update(coupling, state);
      }
    finish_state(B, u0, u0_observations, state);
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
    for (unsigned int c = 0; c < y.size(); ++c)
      if (y[c] != 0.)
        {
          const Column &column = node_columns[c / 3][c % 3];
          if (c < n_slave_values)
            for (unsigned int r = 0; r < n_slave_values; ++r)
              u_slave[r] -= y[c] * column.surface[r];
          else
            master_bound += std::abs(y[c]) * column.peak;
          for (unsigned int m = 0; m < observed.size(); ++m)
            observed[m] -= y[c] * column.observations[m];
        }
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
