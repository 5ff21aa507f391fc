// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#include <deal.II/base/timer.h>

#include <tkr/base/mpi.h>
#include <tkr/contact/active_set_solver.h>

#include <algorithm>
#include <iomanip>
#include <limits>

namespace TKR::Contact
{
  using namespace dealii;

  unsigned int
  ContactState::n_active() const
  {
    return std::count(active.begin(), active.end(), true);
  }

  std::vector<types::global_dof_index>
  surface_dof_indices(const Mortar::MortarCoupling &coupling)
  {
    std::vector<types::global_dof_index> dofs;
    for (const auto *surface :
         {&coupling.slave_surface(), &coupling.master_surface()})
      for (const auto &node : surface->nodes())
        dofs.insert(dofs.end(), node.dofs.begin(), node.dofs.end());
    return dofs;
  }

  double
  apply_mortar_operator(const Mortar::MortarCoupling &coupling,
                        const unsigned int            j,
                        const double                 *slave_values,
                        const double                 *master_values)
  {
    const auto  &node = coupling.slave_nodes()[j];
    Tensor<1, 3> v_master;
    for (const auto &[k, M] : node.M)
      for (unsigned int e = 0; e < 3; ++e)
        v_master[e] += M * master_values[3 * k + e];
    double result = -node.master_normal * v_master;
    for (unsigned int e = 0; e < 3; ++e)
      result += node.D * node.normal[e] * slave_values[3 * j + e];
    return result;
  }

  std::vector<bool>
  nodes_near_closest(const Mortar::MortarCoupling &coupling,
                     const double                  distance)
  {
    const auto &nodes   = coupling.slave_nodes();
    double      min_gap = std::numeric_limits<double>::max();
    for (const auto &node : nodes)
      if (node.covered)
        min_gap = std::min(min_gap, node.weighted_gap / node.D);
    const double      threshold = std::max(min_gap, 0.) + distance;
    std::vector<bool> near(nodes.size(), false);
    for (unsigned int j = 0; j < nodes.size(); ++j)
      near[j] =
        nodes[j].covered && nodes[j].weighted_gap <= threshold * nodes[j].D;
    return near;
  }

  void
  start_state(const Mortar::MortarCoupling &coupling,
              const double                  initial_distance,
              ContactState                 &state)
  {
    const auto        &nodes   = coupling.slave_nodes();
    const unsigned int n_slave = nodes.size();
    if (state.active.size() != n_slave || state.n_active() == 0)
      state.active = nodes_near_closest(coupling, initial_distance);
    else
      // A warm start from another geometry: only covered nodes may be
      // active.
      for (unsigned int j = 0; j < n_slave; ++j)
        state.active[j] = state.active[j] && nodes[j].covered;
    state.pressure.assign(n_slave, 0.);
    state.gap.assign(n_slave, std::numeric_limits<double>::quiet_NaN());
    state.displacement.assign(n_slave, Tensor<1, 3>());
  }

  ActiveSetUpdate::ActiveSetUpdate(const ConditionalOStream &pcout,
                                   const double slave_youngs_modulus)
    : pcout(pcout)
    , slave_youngs_modulus(slave_youngs_modulus)
  {}

  unsigned int
  ActiveSetUpdate::next_set(const Mortar::MortarCoupling &coupling,
                            const ContactState           &state,
                            std::vector<bool>            &next,
                            std::vector<double>          &violation) const
  {
    const auto        &nodes   = coupling.slave_nodes();
    const unsigned int n_slave = nodes.size();
    next.assign(n_slave, false);
    violation.assign(n_slave, 0.);
    unsigned int n_changed = 0;
    for (unsigned int j = 0; j < n_slave; ++j)
      if (nodes[j].covered)
        {
          const double lambda = state.pressure[j], gap = state.gap[j];
          const double c = slave_youngs_modulus / std::sqrt(nodes[j].D);
          next[j]        = (lambda - c * gap > 0);
          // How far the node is from satisfying its present status.
          violation[j] =
            state.active[j] ? std::max(0., -lambda) : std::max(0., -c * gap);
        }
    for (unsigned int j = 0; j < n_slave; ++j)
      n_changed += (next[j] != state.active[j]);
    return n_changed;
  }

  unsigned int
  ActiveSetUpdate::count_changes(const Mortar::MortarCoupling &coupling,
                                 const ContactState           &state) const
  {
    std::vector<bool>   next;
    std::vector<double> violation;
    return next_set(coupling, state, next, violation);
  }

  unsigned int
  ActiveSetUpdate::update(const Mortar::MortarCoupling &coupling,
                          ContactState                 &state)
  {
    std::vector<bool>   next;
    std::vector<double> violation;
    const unsigned int  n_changed = next_set(coupling, state, next, violation);
    if (n_changed == 0)
      return 0;

    history.push_back(state.active);
    if (std::find(history.begin(), history.end(), next) != history.end())
      {
        if (!damped)
          pcout << "    the active set cycles: damped updates from now on"
                << std::endl;
        damped = true;
      }
    if (damped)
      {
        const unsigned int worst =
          std::max_element(violation.begin(), violation.end()) -
          violation.begin();
        next        = state.active;
        next[worst] = !next[worst];
      }
    state.active = next;
    return n_changed;
  }

  void
  add_contact_results(const Mortar::MortarCoupling &coupling,
                      const ContactState           &state,
                      ContactStatistics            &statistics)
  {
    const auto &nodes = coupling.slave_nodes();
    for (unsigned int j = 0; j < nodes.size(); ++j)
      if (state.active[j])
        {
          ++statistics.n_active;
          statistics.contact_area += nodes[j].D;
          statistics.contact_force -=
            state.pressure[j] * nodes[j].D * nodes[j].normal;
          statistics.max_pressure =
            std::max(statistics.max_pressure, state.pressure[j]);
        }
  }

  ActiveSetSolver::ActiveSetSolver(Elasticity::LinearElasticity    &elasticity,
                                   const Mortar::MortarCoupling    &coupling,
                                   const Parameters::ContactSolver &parameters,
                                   const double   slave_youngs_modulus,
                                   const MPI_Comm mpi_communicator,
                                   const ConditionalOStream &pcout,
                                   TimerOutput              &timer,
                                   const bool                testing)
    : elasticity(elasticity)
    , coupling(coupling)
    , parameters(parameters)
    , slave_youngs_modulus(slave_youngs_modulus)
    , mpi_communicator(mpi_communicator)
    , pcout(pcout)
    , timer(timer)
    , testing(testing)
  {}

  void
  ActiveSetSolver::setup(const AffineConstraints<double> &dirichlet_constraints)
  {
    dirichlet.clear();
    dirichlet.copy_from(dirichlet_constraints);

    surface_dofs = surface_dof_indices(coupling);

    // The sparsity pattern must hold the couplings of every node that may
    // become active, so that the matrix can be reused when the set changes.
    std::vector<bool> all_covered(coupling.slave_nodes().size());
    for (unsigned int j = 0; j < all_covered.size(); ++j)
      all_covered[j] = coupling.slave_nodes()[j].covered;
    AffineConstraints<double> constraints;
    make_constraints(all_covered, constraints);
    elasticity.setup_system(constraints);
  }

  // The mortar condition of node j, n_j . (sum_k M_jk u_k - D_jj u_j) = -g_j,
  // solved for the component d in which n_j is largest:
  // u_jd = sum_{e != d} (-n_je/n_jd) u_je
  //        + sum_k sum_e M_jk n_je / (D_jj n_jd) u_ke + g_j / (D_jj n_jd).
  void
  ActiveSetSolver::make_constraints(
    const std::vector<bool>   &active,
    AffineConstraints<double> &constraints) const
  {
    constraints.clear();
    const auto &nodes        = coupling.slave_nodes();
    const auto &slave_nodes  = coupling.slave_surface().nodes();
    const auto &master_nodes = coupling.master_surface().nodes();
    for (unsigned int j = 0; j < nodes.size(); ++j)
      {
        if (!active[j])
          continue;
        const auto        &node = nodes[j];
        const auto        &dofs = slave_nodes[j].dofs;
        const Tensor<1, 3> n    = node.normal;
        unsigned int       d    = 0;
        for (unsigned int e = 1; e < 3; ++e)
          if (std::abs(n[e]) > std::abs(n[d]))
            d = e;
        if (dirichlet.is_constrained(dofs[d]))
          continue;
        const double scale = 1. / (node.D * n[d]);
        constraints.add_line(dofs[d]);
        for (unsigned int e = 0; e < 3; ++e)
          if (e != d)
            constraints.add_entry(dofs[d], dofs[e], -n[e] / n[d]);
        const Tensor<1, 3> n_master = node.master_normal;
        for (const auto &[k, M] : node.M)
          for (unsigned int e = 0; e < 3; ++e)
            if (M * n_master[e] != 0.)
              constraints.add_entry(dofs[d],
                                    master_nodes[k].dofs[e],
                                    M * n_master[e] * scale);
        constraints.set_inhomogeneity(dofs[d], node.weighted_gap * scale);
      }
    constraints.merge(dirichlet,
                      AffineConstraints<double>::no_conflicts_allowed,
                      /*allow_different_local_lines=*/true);
    constraints.close();
  }

  std::vector<double>
  ActiveSetSolver::gather(const TrilinosWrappers::MPI::Vector &vector) const
  {
    std::vector<double> values(surface_dofs.size(), 0.);
    const IndexSet     &owned = vector.locally_owned_elements();
    for (unsigned int i = 0; i < surface_dofs.size(); ++i)
      if (owned.is_element(surface_dofs[i]))
        values[i] = vector[surface_dofs[i]];
    sum_over_ranks(values, mpi_communicator);
    return values;
  }

  ContactStatistics
  ActiveSetSolver::solve(const Mapping<3>                &mapping,
                         const Elasticity::BoundaryLoads &loads,
                         const double                     initial_distance,
                         ContactState                    &state)
  {
    const auto        &nodes        = coupling.slave_nodes();
    const unsigned int n_slave      = nodes.size();
    const unsigned int master_start = 3 * n_slave;

    start_state(coupling, initial_distance, state);

    ContactStatistics         statistics;
    ActiveSetUpdate           active_set_update(pcout, slave_youngs_modulus);
    AffineConstraints<double> constraints;
    TrilinosWrappers::MPI::Vector residual;
    unsigned int                  n_expansions           = 0;
    bool                          rebuild_preconditioner = true;
    double                        expansion_distance     = initial_distance;

    for (unsigned int iteration = 1; iteration <= parameters.max_iterations;
         ++iteration)
      {
        Timer iteration_timer;
        make_constraints(state.active, constraints);
        elasticity.assemble_system(mapping, constraints, loads);
        const bool fresh_preconditioner = rebuild_preconditioner;
        // The AMG hierarchy of the first iteration stays a good
        // preconditioner while only some constraint rows change: it is
        // rebuilt only when that stops being true (see below).
        if (rebuild_preconditioner)
          {
            elasticity.setup_preconditioner(mapping);
            rebuild_preconditioner = false;
          }
        const auto linear = elasticity.solve(constraints);
        statistics.linear_iterations += linear.iterations;
        statistics.relative_residual = linear.relative_residual;
        statistics.newton_iterations = iteration;

        elasticity.compute_residual(mapping, loads, residual);
        const std::vector<double> r = gather(residual);
        const std::vector<double> u = gather(elasticity.get_solution());

        // Multipliers lambda_j = r_j . n_j / D_jj and gaps after
        // deformation.
        for (unsigned int j = 0; j < n_slave; ++j)
          {
            const auto  &node = nodes[j];
            Tensor<1, 3> r_j, u_j;
            for (unsigned int e = 0; e < 3; ++e)
              {
                r_j[e] = r[3 * j + e];
                u_j[e] = u[3 * j + e];
              }
            // Every slave node's displacement (the wear's slip needs it
            // also where the node is out of reach of the master).
            state.displacement[j] = u_j;
            if (!node.covered)
              continue;
            state.pressure[j] = r_j * node.normal / node.D;
            state.gap[j] =
              (node.weighted_gap -
               apply_mortar_operator(coupling, j, u.data(), &u[master_start])) /
              node.D;
          }

        const unsigned int n_active = state.n_active();
        const unsigned int n_changed =
          active_set_update.count_changes(coupling, state);
        pcout << "    active set iteration " << std::setw(2) << iteration
              << ": " << std::setw(6) << n_active << " active, " << std::setw(5)
              << n_changed << " changed";
        if (!testing)
          pcout << ", CG " << linear.iterations << " it., residual "
                << std::scientific << std::setprecision(1)
                << linear.relative_residual << std::defaultfloat
                << std::setprecision(6) << ", " << std::fixed
                << std::setprecision(2) << iteration_timer.wall_time() << " s"
                << std::defaultfloat << std::setprecision(6);
        pcout << std::endl;

        if (!linear.converged && !fresh_preconditioner)
          {
            // A reused hierarchy may no longer fit: retry with a new one.
            rebuild_preconditioner = true;
            continue;
          }
        if (!linear.converged)
          {
            // Typically a body held only by contact whose active set cannot
            // hold it (singular system): add the nodes near the closest one,
            // within a growing distance, and try again.
            if (n_expansions < 4)
              {
                expansion_distance *= 4;
                ++n_expansions;
                const auto near =
                  nodes_near_closest(coupling, expansion_distance);
                for (unsigned int j = 0; j < n_slave; ++j)
                  state.active[j] = state.active[j] || near[j];
                pcout << "    the linear solver failed (singular?): active set "
                         "widened to the nodes within "
                      << expansion_distance << " mm of the closest"
                      << std::endl;
                active_set_update.clear_history();
                rebuild_preconditioner = true;
                continue;
              }
            pcout << "    the linear solver did not converge" << std::endl;
            break;
          }
        if (n_changed == 0)
          {
            statistics.converged =
              linear.relative_residual <= parameters.tolerance;
            break;
          }
        active_set_update.update(coupling, state);
      }

    add_contact_results(coupling, state, statistics);
    return statistics;
  }
} // namespace TKR::Contact
