// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#include <deal.II/lac/dynamic_sparsity_pattern.h>
#include <deal.II/lac/trilinos_solver.h>
#include <deal.II/lac/vector.h>

#include <tkr/elasticity/elastic_system.h>
#include <tkr/elasticity/rigid_body_modes.h>

#include <Epetra_CrsMatrix.h>
#include <Epetra_FEVector.h>
#include <Teuchos_ParameterList.hpp>

#include <algorithm>

namespace TKR::Elasticity
{
  using namespace dealii;

  ElasticSystem::ElasticSystem(const LinearElasticity &elasticity)
    : elasticity(elasticity)
  {}

  // Every rank of a parallel::shared::Triangulation knows all cells and
  // (here) all constraints, so each builds the rows it owns from all cells
  // without communication. That includes rows that contact constraints
  // couple to DoFs far away in the mesh (slave rows eliminated onto master
  // DoFs), which a cell-local pattern plus the usual exchange would miss.
  // Each cell couples its DoFs and all DoFs its constrained DoFs depend
  // on, among each other: that holds the couplings of every subset of the
  // constraints, so the pattern survives changes of the active set.
  void
  ElasticSystem::setup(const AffineConstraints<double> &constraints)
  {
    TimerOutput::Scope     scope(elasticity.get_timer(), "setup system");
    const auto            &dof_handler = elasticity.get_dof_handler();
    const auto            &fe          = elasticity.get_fe();
    const IndexSet        &owned_dofs  = elasticity.locally_owned_dofs();
    DynamicSparsityPattern dsp(dof_handler.n_dofs(),
                               dof_handler.n_dofs(),
                               owned_dofs);
    std::vector<types::global_dof_index> dof_indices(fe.n_dofs_per_cell());
    std::vector<types::global_dof_index> coupled;
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (!cell->is_artificial())
        {
          cell->get_dof_indices(dof_indices);
          coupled = dof_indices;
          for (const auto i : dof_indices)
            if (const auto *entries = constraints.get_constraint_entries(i))
              for (const auto &entry : *entries)
                coupled.push_back(entry.first);
          std::sort(coupled.begin(), coupled.end());
          coupled.erase(std::unique(coupled.begin(), coupled.end()),
                        coupled.end());
          for (const auto row : coupled)
            if (owned_dofs.is_element(row))
              dsp.add_entries(row, coupled.begin(), coupled.end(), true);
        }
    changing_cell.clear();
    kept_rows.clear();
    kept_values.clear();
    const MPI_Comm communicator = elasticity.get_communicator();
    system_matrix.reinit(owned_dofs, owned_dofs, dsp, communicator);
    system_rhs.reinit(owned_dofs, communicator);
    solution_vector = elasticity.make_ghosted_vector();
  }

  // Constraints (Dirichlet data, the contact conditions) are eliminated
  // while copying local to global, which keeps the matrix symmetric and
  // positive definite for CG.
  void
  ElasticSystem::assemble(const Mapping<3>                &mapping,
                          const AffineConstraints<double> &constraints,
                          const BoundaryLoads             &loads)
  {
    TimerOutput::Scope scope(elasticity.get_timer(), "assemble system");
    system_matrix = 0;
    system_rhs    = 0;
    add_cells(mapping, constraints, loads, CellSelection::all);
  }

  // A Newton step of the contact solver changes only the constraint lines
  // of slave DoFs; the condensation of a cell's matrix
  // (distribute_local_to_global) depends only on the lines of the cell's
  // own DoFs. So the contributions of all cells without a slave DoF stay,
  // and a cell with one adds only to its own rows and to the rows of the
  // DoFs its constraints refer to (master and neighbouring slave DoFs):
  // these rows are kept here as the other cells leave them, and restored
  // before the changing cells are added again. That replaces a full
  // assembly per Newton step by one of the contact layer (a few per cent
  // of the cells).
  void
  ElasticSystem::assemble_fixed_cells(
    const Mapping<3>                &mapping,
    const AffineConstraints<double> &constraints,
    const BoundaryLoads             &loads,
    const IndexSet                  &changing_dofs,
    const AffineConstraints<double> &all_constraints)
  {
    {
      TimerOutput::Scope scope(elasticity.get_timer(), "assemble system");
      const auto reached = mark_changing_cells(changing_dofs, all_constraints);
      system_matrix      = 0;
      system_rhs         = 0;
      add_cells(mapping, constraints, loads, CellSelection::fixed);
      keep_rows(reached);
    }
    assemble_changing_cells(mapping, constraints, loads);
  }

  // The changing cells and the rows they can reach, over all cells that
  // this rank knows (their owners may be other ranks).
  std::vector<types::global_dof_index>
  ElasticSystem::mark_changing_cells(
    const IndexSet                  &changing_dofs,
    const AffineConstraints<double> &all_constraints)
  {
    const auto &dof_handler = elasticity.get_dof_handler();
    changing_cell.assign(dof_handler.get_triangulation().n_active_cells(),
                         false);
    std::vector<types::global_dof_index> dof_indices(
      elasticity.get_fe().n_dofs_per_cell());
    std::vector<types::global_dof_index> reached;
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (!cell->is_artificial())
        {
          cell->get_dof_indices(dof_indices);
          if (std::none_of(dof_indices.begin(),
                           dof_indices.end(),
                           [&](const auto i) {
                             return changing_dofs.is_element(i);
                           }))
            continue;
          changing_cell[cell->active_cell_index()] = true;
          for (const auto i : dof_indices)
            {
              reached.push_back(i);
              if (const auto *entries =
                    all_constraints.get_constraint_entries(i))
                for (const auto &entry : *entries)
                  reached.push_back(entry.first);
            }
        }
    std::sort(reached.begin(), reached.end());
    reached.erase(std::unique(reached.begin(), reached.end()), reached.end());
    return reached;
  }

  void
  ElasticSystem::keep_rows(const std::vector<types::global_dof_index> &rows)
  {
    const IndexSet         &owned_dofs = elasticity.locally_owned_dofs();
    const Epetra_CrsMatrix &matrix     = system_matrix.trilinos_matrix();
    const Epetra_FEVector  &rhs        = system_rhs.trilinos_vector();
    kept_rows.clear();
    kept_values.clear();
    for (const auto row : rows)
      if (owned_dofs.is_element(row))
        {
          const auto global =
            static_cast<TrilinosWrappers::types::int_type>(row);
          KeptRow kept;
          kept.matrix_row   = matrix.RowMap().LID(global);
          kept.vector_entry = rhs.Map().LID(global);
          kept.first_value  = kept_values.size();
          kept.rhs          = rhs[0][kept.vector_entry];
          int     n_entries;
          double *values;
          matrix.ExtractMyRowView(kept.matrix_row, n_entries, values);
          kept_values.insert(kept_values.end(), values, values + n_entries);
          kept_rows.push_back(kept);
        }
  }

  void
  ElasticSystem::assemble_changing_cells(
    const Mapping<3>                &mapping,
    const AffineConstraints<double> &constraints,
    const BoundaryLoads             &loads)
  {
    TimerOutput::Scope scope(elasticity.get_timer(), "assemble system");
    Assert(!changing_cell.empty(),
           ExcMessage("Call assemble_fixed_cells() first."));
    // Epetra hands out writable views of a filled matrix's rows (also
    // through a const reference); the pattern is the one of the kept
    // values.
    const Epetra_CrsMatrix &matrix = system_matrix.trilinos_matrix();
    Epetra_FEVector        &rhs    = system_rhs.trilinos_vector();
    for (std::size_t k = 0; k < kept_rows.size(); ++k)
      {
        const KeptRow &kept = kept_rows[k];
        int            n_entries;
        double        *values;
        matrix.ExtractMyRowView(kept.matrix_row, n_entries, values);
        const std::size_t end =
          (k + 1 < kept_rows.size() ? kept_rows[k + 1].first_value :
                                      kept_values.size());
        AssertDimension(static_cast<std::size_t>(n_entries),
                        end - kept.first_value);
        std::copy(kept_values.begin() + kept.first_value,
                  kept_values.begin() + end,
                  values);
        rhs[0][kept.vector_entry] = kept.rhs;
      }
    add_cells(mapping, constraints, loads, CellSelection::changing);
  }

  void
  ElasticSystem::add_cells(const Mapping<3>                &mapping,
                           const AffineConstraints<double> &constraints,
                           const BoundaryLoads             &loads,
                           const CellSelection              selection)
  {
    const bool changing = selection == CellSelection::changing;
    elasticity.for_each_cell_system(
      mapping,
      loads,
      [&](const auto &,
          const auto &cell_matrix,
          auto       &cell_rhs,
          const auto &dofs) {
        constraints.distribute_local_to_global(cell_matrix,
                                               cell_rhs,
                                               dofs,
                                               system_matrix,
                                               system_rhs);
      },
      [&](const auto &cell, const auto &) {
        return selection == CellSelection::all ||
               changing_cell[cell->active_cell_index()] == changing;
      });
    system_matrix.compress(VectorOperation::add);
    system_rhs.compress(VectorOperation::add);
  }

  // Smoothed-aggregation AMG for a vector-valued, elliptic problem. ML is
  // told that there are three unknowns per node and gets the six rigid-body
  // modes (or only the three translations) as near-null space; that is what
  // keeps the iteration count independent of the mesh size for elasticity.
  void
  ElasticSystem::setup_preconditioner(const Mapping<3> &mapping)
  {
    TimerOutput::Scope scope(elasticity.get_timer(), "AMG setup");
    TrilinosWrappers::PreconditionAMG::AdditionalData data;
    data.elliptic                 = true;
    const auto &solver_parameters = elasticity.get_solver_parameters();
    data.higher_order_elements    = (elasticity.get_fe().degree > 1);
    data.smoother_sweeps          = solver_parameters.smoother_sweeps;
    data.aggregation_threshold    = solver_parameters.aggregation_threshold;

    Teuchos::ParameterList              parameters;
    std::unique_ptr<Epetra_MultiVector> translations;
    data.set_parameters(parameters, translations, system_matrix);
    parameters.set("PDE equations", 3);
    if (solver_parameters.rigid_body_modes)
      {
        near_null_space =
          rigid_body_modes(mapping,
                           elasticity.get_dof_handler(),
                           elasticity.locally_owned_dofs(),
                           system_matrix.trilinos_matrix().RowMap());
        parameters.set("null space: type", "pre-computed");
        parameters.set("null space: dimension", near_null_space->NumVectors());
        parameters.set("null space: vectors", near_null_space->Values());
      }
    else
      {
        parameters.set("null space: type", "default vectors");
        parameters.set("null space: dimension", 3);
      }
    preconditioner.initialize(system_matrix, parameters);
  }

  SolverStatistics
  ElasticSystem::solve(const AffineConstraints<double> &constraints)
  {
    return solve(constraints,
                 elasticity.get_solver_parameters().tolerance,
                 false);
  }

  // The stopping criterion is absolute (tolerance times |f|), so a start
  // closer to the solution saves iterations without making the result any
  // less accurate.
  SolverStatistics
  ElasticSystem::solve(const AffineConstraints<double> &constraints,
                       const double                     tolerance,
                       const bool                       start_from_solution)
  {
    TimerOutput::Scope            scope(elasticity.get_timer(), "CG solve");
    const IndexSet               &owned_dofs = elasticity.locally_owned_dofs();
    TrilinosWrappers::MPI::Vector owned_solution(owned_dofs,
                                                 elasticity.get_communicator());
    if (start_from_solution)
      {
        owned_solution = solution_vector;
        for (const auto &line : constraints.get_lines())
          if (owned_dofs.is_element(line.index))
            owned_solution[line.index] = 0.;
        owned_solution.compress(VectorOperation::insert);
      }
    SolverStatistics statistics;
    const double     rhs_norm = system_rhs.l2_norm();
    if (rhs_norm == 0.)
      {
        owned_solution       = 0.;
        statistics.converged = true;
      }
    else
      {
        SolverControl control(elasticity.get_solver_parameters().max_iterations,
                              tolerance * rhs_norm,
                              /*log_history=*/false,
                              /*log_result=*/false);
        TrilinosWrappers::SolverCG cg(control);
        try
          {
            cg.solve(system_matrix, owned_solution, system_rhs, preconditioner);
            statistics.converged = true;
          }
        catch (const SolverControl::NoConvergence &)
          {
            statistics.converged = false;
          }
        catch (const ExceptionBase &)
          {
            // AztecOO reports a breakdown ("loss of precision") this way.
            statistics.converged = false;
          }
        statistics.iterations        = control.last_step();
        statistics.relative_residual = control.last_value() / rhs_norm;
      }
    constraints.distribute(owned_solution);
    solution_vector = owned_solution;
    return statistics;
  }

} // namespace TKR::Elasticity
