// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

// The condensed solver's store of compliance columns K^{-1} e_c: computed
// in batches through the factorisation, kept per node until the stiffness
// changes (the master body's while its block of K does not), shared
// between step groups at a stiffness update (prefetch()).

#include <deal.II/base/timer.h>

#include <tkr/base/exceptions.h>
#include <tkr/base/mpi.h>
#include <tkr/contact/condensed_solver.h>

#include <algorithm>
#include <cmath>
#include <cstring>

namespace TKR::Contact
{
  using namespace dealii;

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
    last_zone_values.clear();
    last_gathered.reset();
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
    // The weights are zero away from their surface or body: only the
    // others are added (the same sums).
    std::vector<std::pair<int, double>> weights;
    for (unsigned int m = 0; m < n_observations; ++m)
      {
        const Epetra_MultiVector &w = observation_weights[m].trilinos_vector();
        weights.clear();
        for (int i = 0; i < X.MyLength(); ++i)
          if (w[0][i] != 0.)
            weights.emplace_back(i, w[0][i]);
        for (int c = 0; c < X.NumVectors(); ++c)
          for (const auto &[i, weight] : weights)
            values[c * n_observations + m] += weight * X[c][i];
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
        // (X is overwritten: no zeros first)
        Epetra_MultiVector X(direct_solver.row_map(), n_columns, false);
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
            const unsigned int n_own   = n_own_values(node);
            const unsigned int n_other = surface_dofs.size() - n_own;
            double             own_max = 0, other_max = 0;
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
  // turn) and sent by it. (At the first setup nobody wants a node: the
  // flags' gather, a few kB, is all it costs.)
  std::vector<std::vector<unsigned int>>
  CondensedActiveSetSolver::prefetch_plan(
    const MPI_Comm             peers,
    std::vector<unsigned int> &to_compute) const
  {
    const unsigned int n_nodes = node_columns.size();
    const unsigned int n_peers = Utilities::MPI::n_mpi_processes(peers);
    const unsigned int me      = Utilities::MPI::this_mpi_process(peers);
    // per node: whether this peer wants it, then whether it holds it
    std::vector<int> local(2 * n_nodes, 0);
    for (const unsigned int node : last_stiffness_nodes)
      local[node] = 1;
    for (unsigned int node = 0; node < expected_nodes.size(); ++node)
      if (expected_nodes[node])
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
    return sent;
  }

  void
  CondensedActiveSetSolver::prefetch(const MPI_Comm peers)
  {
    std::vector<unsigned int>                    to_compute;
    const std::vector<std::vector<unsigned int>> sent =
      prefetch_plan(peers, to_compute);
    if (!to_compute.empty())
      compute_columns(to_compute);
    if (Utilities::MPI::n_mpi_processes(peers) > 1)
      exchange_columns(sent, peers);
    expected_nodes.clear();
  }

  void
  CondensedActiveSetSolver::expect(const std::vector<unsigned int> &slave_nodes)
  {
    const auto                    operator_B = mortar_operator();
    const Mortar::MortarOperator &B          = *operator_B;
    expected_nodes.resize(node_columns.size(), false);
    for (const unsigned int i : slave_nodes)
      for (auto e = B.begin(i); e != B.end(i); ++e)
        expected_nodes[e->column / 3] = true;
  }

  // The columns travel in rounds of a few nodes per peer, to bound the
  // buffers.
  void
  CondensedActiveSetSolver::exchange_columns(
    const std::vector<std::vector<unsigned int>> &sent,
    const MPI_Comm                                peers)
  {
    const unsigned int n_peers = Utilities::MPI::n_mpi_processes(peers);
    const unsigned int me      = Utilities::MPI::this_mpi_process(peers);
    std::vector<int>   offsets;
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
                const unsigned int node  = sent[p][k];
                const unsigned int n_own = n_own_values(node);
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
        {
          used_nodes[e->column / 3] = true;
          if (node_columns[e->column / 3][e->column % 3].surface.empty())
            needed.push_back(e->column / 3);
        }
    std::sort(needed.begin(), needed.end());
    needed.erase(std::unique(needed.begin(), needed.end()), needed.end());
    if (!needed.empty())
      compute_columns(needed);
  }
} // namespace TKR::Contact
