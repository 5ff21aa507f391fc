// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#include <deal.II/base/timer.h>

#include <tkr/base/mpi.h>
#include <tkr/contact/active_set_solver.h>

#include <cmath>
#include <iomanip>

namespace TKR::Contact
{
  using namespace dealii;

  ActiveSetSolver::ActiveSetSolver(
    const Elasticity::LinearElasticity &elasticity,
    const Mortar::MortarCoupling       &coupling,
    const Parameters::ContactSolver    &parameters,
    const double                        slave_youngs_modulus,
    const MPI_Comm                      mpi_communicator,
    const ConditionalOStream           &pcout,
    TimerOutput                        &timer,
    const bool                          testing)
    : ContactSolver(elasticity,
                    coupling,
                    parameters,
                    slave_youngs_modulus,
                    mpi_communicator,
                    pcout,
                    timer,
                    testing)
    , system(elasticity)
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

  // Multipliers lambda_j = r_j . n_j / D_jj from the residual of the
  // unconstrained system (needed at the slave DoFs only) and gaps after
  // deformation. Every slave node's displacement is kept (the wear's slip
  // needs it also where the node is out of reach of the master).
  void
  ActiveSetSolver::evaluate_state(const Mapping<3>                &mapping,
                                  const Elasticity::BoundaryLoads &loads,
                                  const Mortar::MortarOperator    &B,
                                  const IndexSet                  &slave_dofs,
                                  ContactState                    &state) const
  {
    const auto                   &nodes = coupling.slave_nodes();
    TrilinosWrappers::MPI::Vector residual;
    elasticity.compute_residual(mapping,
                                loads,
                                system.solution(),
                                slave_dofs,
                                residual);
    const std::vector<double> r = gather(B, residual);
    const std::vector<double> u = gather(B, system.solution());
    state.master_displacement   = 0;
    for (unsigned int c = B.n_slave_columns(); c < B.n_columns(); c += 3)
      state.master_displacement =
        std::max(state.master_displacement,
                 std::sqrt(u[c] * u[c] + u[c + 1] * u[c + 1] +
                           u[c + 2] * u[c + 2]));
    for (unsigned int j = 0; j < nodes.size(); ++j)
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
  }

  // Inexact Newton. A Newton step whose active set changes only decides
  // the next set, from the signs of the complementarity function C_j =
  // lambda_j - c_j g_j: its linear system needs to be solved only as far
  // as these signs are certain. CG goes to ten times the Newton step
  // tolerance, then on to it (warm started); the change of C_j between the
  // two estimates the error of the first, ten times that of the second.
  // Where |C_j| does not exceed that change (a sign that may still flip),
  // and in the step that leaves the set unchanged (its solution is the
  // result), CG goes on to the Linear solver tolerance. The stopping test
  // of CG is absolute (tolerance times |f|), so the result meets the same
  // tolerance as a solve from zero.
  Elasticity::SolverStatistics
  ActiveSetSolver::solve_newton_step(
    const Mapping<3>                &mapping,
    const Elasticity::BoundaryLoads &loads,
    const Mortar::MortarOperator    &B,
    const IndexSet                  &slave_dofs,
    const AffineConstraints<double> &constraints,
    const ActiveSetUpdate           &active_set_update,
    const bool                       warm_start,
    ContactState                    &state,
    unsigned int                    &n_changed)
  {
    const auto  &nodes           = coupling.slave_nodes();
    const auto  &linear          = elasticity.get_solver_parameters();
    const double tight           = linear.tolerance;
    const double loose           = linear.newton_step_tolerance;
    const auto   complementarity = [&]() {
      std::vector<double> c(nodes.size(), 0.);
      for (unsigned int j = 0; j < nodes.size(); ++j)
        if (nodes[j].covered)
          c[j] = active_set_update.complementarity(nodes[j],
                                                   state.pressure[j],
                                                   state.gap[j]);
      return c;
    };
    const auto add = [](Elasticity::SolverStatistics       &sum,
                        const Elasticity::SolverStatistics &stage) {
      sum.iterations += stage.iterations;
      sum.relative_residual = stage.relative_residual;
      sum.converged         = stage.converged;
    };

    Elasticity::SolverStatistics statistics;
    bool                         certain = false;
    if (loose > tight)
      {
        statistics =
          system.solve(constraints, std::max(tight, 10. * loose), warm_start);
        if (statistics.converged)
          {
            evaluate_state(mapping, loads, B, slave_dofs, state);
            const std::vector<double> rough = complementarity();
            add(statistics, system.solve(constraints, loose, true));
            if (statistics.converged)
              {
                evaluate_state(mapping, loads, B, slave_dofs, state);
                const std::vector<double> c = complementarity();
                certain                     = true;
                for (unsigned int j = 0; j < nodes.size(); ++j)
                  certain =
                    certain && (!nodes[j].covered ||
                                std::abs(c[j]) > std::abs(c[j] - rough[j]));
                n_changed = active_set_update.count_changes(coupling, state);
              }
          }
        if (certain && n_changed > 0)
          return statistics;
      }
    if (loose <= tight || statistics.converged)
      add(statistics,
          system.solve(constraints, tight, loose > tight || warm_start));
    evaluate_state(mapping, loads, B, slave_dofs, state);
    n_changed = active_set_update.count_changes(coupling, state);
    return statistics;
  }

  // The sparsity pattern holds the couplings of every node that may
  // become active, so that the matrix can be reused when the set changes.
  // The constraint lines that can change are those of the covered slave
  // nodes; only the cells that hold one are assembled again in each Newton
  // step (ElasticSystem::assemble_changing_cells()). The multipliers need
  // the residual only at the slave DoFs.
  void
  ActiveSetSolver::setup_system(
    const Mortar::MortarOperator &B,
    AffineConstraints<double>    &all_covered_constraints,
    IndexSet                     &changing_dofs,
    IndexSet                     &slave_dofs)
  {
    const auto        &nodes   = coupling.slave_nodes();
    const unsigned int n_slave = nodes.size();
    std::vector<bool>  all_covered(n_slave);
    for (unsigned int j = 0; j < n_slave; ++j)
      all_covered[j] = nodes[j].covered;
    make_constraints(B, all_covered, all_covered_constraints);
    system.setup(all_covered_constraints);
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

  // The first Newton step assembles the cells that do not change with the
  // active set once (@p changing_dofs given), later ones only the others.
  // The AMG hierarchy of the first iteration stays a good preconditioner
  // while only some constraint rows change: it is rebuilt only when that
  // stops being true (@p new_preconditioner).
  void
  ActiveSetSolver::assemble_newton_system(
    const Mapping<3>                &mapping,
    const Elasticity::BoundaryLoads &loads,
    const AffineConstraints<double> &constraints,
    const IndexSet                  *changing_dofs,
    const AffineConstraints<double> &all_covered_constraints,
    const bool                       new_preconditioner)
  {
    if (changing_dofs)
      system.assemble_fixed_cells(mapping,
                                  constraints,
                                  loads,
                                  *changing_dofs,
                                  all_covered_constraints);
    else
      system.assemble_changing_cells(mapping, constraints, loads);
    if (new_preconditioner)
      system.setup_preconditioner(mapping);
  }

  // A reused AMG hierarchy may no longer fit: retry with a new one. With a
  // fresh one, the failure is typically a body held only by contact whose
  // active set cannot hold it (singular system): add the nodes near the
  // closest one, within a growing distance, and try again, at most four
  // times.
  bool
  ActiveSetSolver::recover(const bool       fresh_preconditioner,
                           unsigned int    &n_expansions,
                           double          &expansion_distance,
                           ContactState    &state,
                           ActiveSetUpdate &active_set_update) const
  {
    if (!fresh_preconditioner)
      return true;
    if (n_expansions == 4)
      {
        pcout << "    the linear solver did not converge" << std::endl;
        return false;
      }
    expansion_distance *= 4;
    ++n_expansions;
    const auto near = nodes_near_closest(coupling, expansion_distance);
    for (unsigned int j = 0; j < near.size(); ++j)
      state.active[j] = state.active[j] || near[j];
    pcout << "    the linear solver failed (singular?): active set "
             "widened to the nodes within "
          << expansion_distance << " mm of the closest" << std::endl;
    active_set_update.clear_history();
    return true;
  }

  void
  ActiveSetSolver::print_iteration(const unsigned int iteration,
                                   const unsigned int n_active,
                                   const unsigned int n_changed,
                                   const Elasticity::SolverStatistics &linear,
                                   const double wall_time) const
  {
    trace << "    active set iteration " << std::setw(2) << iteration << ": "
          << std::setw(6) << n_active << " active, " << std::setw(5)
          << n_changed << " changed, CG " << linear.iterations
          << " it., residual " << std::scientific << std::setprecision(1)
          << linear.relative_residual << std::defaultfloat
          << std::setprecision(6) << ", " << std::fixed << std::setprecision(2)
          << wall_time << " s" << std::defaultfloat << std::setprecision(6)
          << std::endl;
  }

  ContactStatistics
  ActiveSetSolver::solve(const Mapping<3>                &mapping,
                         const Elasticity::BoundaryLoads &loads,
                         const double                     initial_distance,
                         ContactState                    &state)
  {
    const Mortar::MortarOperator B(coupling);

    AffineConstraints<double> all_covered_constraints;
    IndexSet changing_dofs(elasticity.get_dof_handler().n_dofs());
    IndexSet slave_dofs(elasticity.get_dof_handler().n_dofs());
    setup_system(B, all_covered_constraints, changing_dofs, slave_dofs);

    start_state(coupling, initial_distance, state);

    ContactStatistics         statistics;
    ActiveSetUpdate           active_set_update(pcout, slave_youngs_modulus);
    AffineConstraints<double> constraints;
    unsigned int              n_expansions           = 0;
    bool                      rebuild_preconditioner = true;
    double                    expansion_distance     = initial_distance;
    // The first linear solve starts from zero (the result of a contact
    // solve does not depend on what was solved before), later ones from the
    // last Newton step's solution.
    bool warm_start = false;

    for (unsigned int iteration = 1; iteration <= parameters.max_iterations;
         ++iteration)
      {
        Timer iteration_timer;
        make_constraints(B, state.active, constraints);
        const bool fresh_preconditioner = rebuild_preconditioner;
        assemble_newton_system(mapping,
                               loads,
                               constraints,
                               iteration == 1 ? &changing_dofs : nullptr,
                               all_covered_constraints,
                               rebuild_preconditioner);
        rebuild_preconditioner = false;
        unsigned int n_changed = 0;
        const auto   linear    = solve_newton_step(mapping,
                                              loads,
                                              B,
                                              slave_dofs,
                                              constraints,
                                              active_set_update,
                                              warm_start,
                                              state,
                                              n_changed);
        warm_start             = linear.converged;
        statistics.cg_iterations += linear.iterations;
        statistics.relative_residual = linear.relative_residual;
        statistics.newton_iterations = iteration;

        print_iteration(iteration,
                        state.n_active(),
                        n_changed,
                        linear,
                        iteration_timer.wall_time());

        if (!linear.converged)
          {
            if (!recover(fresh_preconditioner,
                         n_expansions,
                         expansion_distance,
                         state,
                         active_set_update))
              break;
            rebuild_preconditioner = true;
            continue;
          }
        if (n_changed == 0)
          {
            statistics.converged =
              linear.relative_residual <= parameters.tolerance;
            break;
          }
        active_set_update.update(coupling, state);
      }

    observe_solution(system.solution());
    add_contact_results(coupling, state, statistics);
    return statistics;
  }
} // namespace TKR::Contact
