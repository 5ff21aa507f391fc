// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#include <deal.II/base/timer.h>

#include <tkr/base/mpi.h>
#include <tkr/contact/active_set_solver.h>

#include <iomanip>

namespace TKR::Contact
{
  using namespace dealii;

  ActiveSetSolver::ActiveSetSolver(Elasticity::LinearElasticity    &elasticity,
                                   const Mortar::MortarCoupling    &coupling,
                                   const Parameters::ContactSolver &parameters,
                                   const double   slave_youngs_modulus,
                                   const MPI_Comm mpi_communicator,
                                   const ConditionalOStream &pcout,
                                   TimerOutput              &timer,
                                   const bool                testing)
    : ContactSolver(elasticity,
                    coupling,
                    parameters,
                    slave_youngs_modulus,
                    mpi_communicator,
                    pcout,
                    timer)
    , testing(testing)
  {}

  void
  ActiveSetSolver::make_constraints(
    const Mortar::MortarOperator &B,
    const std::vector<bool>      &active,
    AffineConstraints<double>    &constraints) const
  {
    constraints.clear();
    const auto &nodes = coupling.slave_nodes();
    const auto &dofs  = B.surface_dofs();
    for (unsigned int j = 0; j < nodes.size(); ++j)
      {
        if (!active[j])
          continue;
        const Tensor<1, 3> &n = nodes[j].normal;
        unsigned int        d = 0;
        for (unsigned int e = 1; e < 3; ++e)
          if (std::abs(n[e]) > std::abs(n[d]))
            d = e;
        const unsigned int pivot_column = 3 * j + d;
        const auto         dof          = dofs[pivot_column];
        if (dirichlet.is_constrained(dof))
          continue;
        double pivot = 0;
        for (auto e = B.begin(j); e != B.end(j); ++e)
          if (e->column == pivot_column)
            pivot = e->value;
        constraints.add_line(dof);
        for (auto e = B.begin(j); e != B.end(j); ++e)
          if (e->column != pivot_column)
            constraints.add_entry(dof, dofs[e->column], -e->value / pivot);
        constraints.set_inhomogeneity(dof, nodes[j].weighted_gap / pivot);
      }
    constraints.merge(dirichlet,
                      AffineConstraints<double>::no_conflicts_allowed,
                      /*allow_different_local_lines=*/true);
    constraints.close();
  }

  std::vector<double>
  ActiveSetSolver::gather(const Mortar::MortarOperator        &B,
                          const TrilinosWrappers::MPI::Vector &vector) const
  {
    const auto         &dofs = B.surface_dofs();
    std::vector<double> values(dofs.size(), 0.);
    const IndexSet     &owned = vector.locally_owned_elements();
    for (unsigned int i = 0; i < dofs.size(); ++i)
      if (owned.is_element(dofs[i]))
        values[i] = vector[dofs[i]];
    sum_over_ranks(values, mpi_communicator);
    return values;
  }

  ContactStatistics
  ActiveSetSolver::solve(const Mapping<3>                &mapping,
                         const Elasticity::BoundaryLoads &loads,
                         const double                     initial_distance,
                         ContactState                    &state)
  {
    const auto                  &nodes   = coupling.slave_nodes();
    const unsigned int           n_slave = nodes.size();
    const Mortar::MortarOperator B(coupling);

    // The sparsity pattern holds the couplings of every node that may
    // become active, so that the matrix can be reused when the set changes.
    // The constraint lines that can change are those of the covered slave
    // nodes; only the cells that hold one are assembled again in each
    // Newton step (LinearElasticity::assemble_changing_cells()). The
    // multipliers need the residual only at the slave DoFs.
    AffineConstraints<double> all_covered_constraints;
    IndexSet changing_dofs(elasticity.get_dof_handler().n_dofs());
    IndexSet slave_dofs(elasticity.get_dof_handler().n_dofs());
    {
      std::vector<bool> all_covered(n_slave);
      for (unsigned int j = 0; j < n_slave; ++j)
        all_covered[j] = nodes[j].covered;
      make_constraints(B, all_covered, all_covered_constraints);
      elasticity.setup_system(all_covered_constraints);
      const auto &dofs = B.surface_dofs();
      for (unsigned int j = 0; j < n_slave; ++j)
        for (unsigned int d = 0; d < 3; ++d)
          {
            slave_dofs.add_index(dofs[3 * j + d]);
            if (nodes[j].covered && !dirichlet.is_constrained(dofs[3 * j + d]))
              changing_dofs.add_index(dofs[3 * j + d]);
          }
      slave_dofs.compress();
      changing_dofs.compress();
    }

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
        make_constraints(B, state.active, constraints);
        if (iteration == 1)
          elasticity.assemble_fixed_cells(mapping,
                                          constraints,
                                          loads,
                                          changing_dofs,
                                          all_covered_constraints);
        else
          elasticity.assemble_changing_cells(mapping, constraints, loads);
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
        statistics.cg_iterations += linear.iterations;
        statistics.relative_residual = linear.relative_residual;
        statistics.newton_iterations = iteration;

        elasticity.compute_residual(mapping, loads, slave_dofs, residual);
        const std::vector<double> r = gather(B, residual);
        const std::vector<double> u = gather(B, elasticity.get_solution());

        // Multipliers lambda_j = r_j . n_j / D_jj and gaps after
        // deformation. Every slave node's displacement is kept (the wear's
        // slip needs it also where the node is out of reach of the master).
        for (unsigned int j = 0; j < n_slave; ++j)
          {
            Tensor<1, 3> r_j;
            for (unsigned int e = 0; e < 3; ++e)
              {
                r_j[e]                   = r[3 * j + e];
                state.displacement[j][e] = u[3 * j + e];
              }
            if (!nodes[j].covered)
              continue;
            state.pressure[j] = r_j * nodes[j].normal / nodes[j].D;
            state.gap[j]      = B.gap(j, u.data());
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

    observe_solution();
    add_contact_results(coupling, state, statistics);
    return statistics;
  }
} // namespace TKR::Contact
