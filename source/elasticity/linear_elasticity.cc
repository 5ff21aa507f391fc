// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#include <deal.II/base/quadrature_lib.h>

#include <deal.II/dofs/dof_tools.h>

#include <deal.II/fe/fe_q.h>
#include <deal.II/fe/fe_values.h>

#include <deal.II/lac/dynamic_sparsity_pattern.h>
#include <deal.II/lac/full_matrix.h>
#include <deal.II/lac/trilinos_solver.h>
#include <deal.II/lac/vector.h>

#include <tkr/elasticity/linear_elasticity.h>
#include <tkr/elasticity/rigid_body_modes.h>
#include <tkr/mesh/mesh.h>

#include <Epetra_CrsMatrix.h>
#include <Epetra_FEVector.h>
#include <Teuchos_ParameterList.hpp>

#include <algorithm>
#include <set>

namespace TKR::Elasticity
{
  using namespace dealii;

  SymmetricTensor<2, 3>
  stress(const Parameters::Material  &material,
         const SymmetricTensor<2, 3> &strain)
  {
    return material.lambda() * trace(strain) * unit_symmetric_tensor<3>() +
           2. * material.mu() * strain;
  }

  bool
  BoundaryLoads::acts_on(const types::boundary_id id) const
  {
    return tractions.count(id) || springs.count(id) ||
           traction_fields.count(id) || spring_fields.count(id);
  }

  Tensor<1, 3>
  BoundaryLoads::traction(const types::boundary_id id, const Point<3> &x) const
  {
    Tensor<1, 3> t;
    if (const auto it = tractions.find(id); it != tractions.end())
      t += it->second;
    if (const auto it = traction_fields.find(id); it != traction_fields.end())
      t += it->second(x);
    return t;
  }

  Tensor<2, 3>
  BoundaryLoads::spring(const types::boundary_id id, const Point<3> &x) const
  {
    Tensor<2, 3> S;
    if (const auto it = springs.find(id); it != springs.end())
      S += it->second;
    if (const auto it = spring_fields.find(id); it != spring_fields.end())
      S += it->second(x);
    return S;
  }

  BoundaryLoads
  linear_combination(const std::vector<BoundaryLoads> &basis,
                     const std::vector<double>        &coefficients,
                     const BoundaryLoads              &springs)
  {
    AssertDimension(basis.size(), coefficients.size());
    BoundaryLoads loads;
    loads.springs       = springs.springs;
    loads.spring_fields = springs.spring_fields;
    std::set<types::boundary_id> ids;
    for (const auto &b : basis)
      {
        for (const auto &[id, t] : b.tractions)
          ids.insert(id);
        for (const auto &[id, t] : b.traction_fields)
          ids.insert(id);
      }
    for (const types::boundary_id id : ids)
      loads.traction_fields[id] = [basis, coefficients, id](const Point<3> &x) {
        Tensor<1, 3> t;
        for (unsigned int i = 0; i < basis.size(); ++i)
          if (coefficients[i] != 0.)
            t += coefficients[i] * basis[i].traction(id, x);
        return t;
      };
    return loads;
  }

  const Parameters::Material &
  material_of(const Parameters::Materials &materials,
              const types::material_id     material_id)
  {
    return material_id == Mesh::MaterialIds::femur ? materials.femur :
                                                     materials.tibia;
  }

  LinearElasticity::LinearElasticity(
    const Triangulation<3>         &triangulation,
    const Parameters::Materials    &materials,
    const Parameters::LinearSolver &solver_parameters,
    const unsigned int              fe_degree,
    const MPI_Comm                  mpi_communicator,
    TimerOutput                    &timer)
    : materials(materials)
    , solver_parameters(solver_parameters)
    , mpi_communicator(mpi_communicator)
    , timer(timer)
    , fe(FE_Q<3>(fe_degree), 3)
    , dof_handler(triangulation)
  {}

  void
  LinearElasticity::distribute_dofs()
  {
    TimerOutput::Scope scope(timer, "distribute DoFs");
    dof_handler.distribute_dofs(fe);
    owned_dofs = dof_handler.locally_owned_dofs();
    DoFTools::extract_locally_relevant_dofs(dof_handler, relevant_dofs);
  }

  // Every rank of a parallel::shared::Triangulation knows all cells and
  // (here) all constraints, so each builds the rows it owns from all cells
  // without communication. That includes rows that contact constraints
  // couple to DoFs far away in the mesh (slave rows eliminated onto master
  // DoFs), which a cell-local pattern plus the usual exchange would miss.
  // Each cell couples its DoFs and all DoFs its constrained DoFs depend
  // on, among each other: that holds the couplings of every subset of the
  // constraints, so the pattern survives changes of the active set.
  void
  LinearElasticity::setup_system(const AffineConstraints<double> &constraints)
  {
    TimerOutput::Scope                   scope(timer, "setup system");
    DynamicSparsityPattern               dsp(dof_handler.n_dofs(),
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
    system_matrix.reinit(owned_dofs, owned_dofs, dsp, mpi_communicator);
    system_rhs.reinit(owned_dofs, mpi_communicator);
    solution.reinit(owned_dofs, relevant_dofs, mpi_communicator);
  }

  // The bilinear form is $a(u,v) = \int_\Omega \varepsilon(v) : C :
  // \varepsilon(u) + \int_{\Gamma_S} v \cdot S u$ with the material of each
  // cell and the distributed springs S; the load is
  // $\int_{\Gamma_N} t \cdot v$ for the uniform tractions $t$ given per
  // boundary id.
  void
  LinearElasticity::local_assemble(
    const typename DoFHandler<3>::active_cell_iterator &cell,
    FEValues<3>                                        &fe_values,
    FEFaceValues<3>                                    &fe_face_values,
    const BoundaryLoads                                &loads,
    FullMatrix<double>                                 &cell_matrix,
    Vector<double>                                     &cell_rhs) const
  {
    const unsigned int                 dofs_per_cell = fe.n_dofs_per_cell();
    const FEValuesExtractors::Vector   displacement(0);
    std::vector<SymmetricTensor<2, 3>> strain(dofs_per_cell);
    cell_matrix = 0;
    cell_rhs    = 0;
    fe_values.reinit(cell);
    const auto &material = material_of(materials, cell->material_id());
    for (const unsigned int q : fe_values.quadrature_point_indices())
      {
        for (unsigned int i = 0; i < dofs_per_cell; ++i)
          strain[i] = fe_values[displacement].symmetric_gradient(i, q);
        const double JxW = fe_values.JxW(q);
        for (unsigned int i = 0; i < dofs_per_cell; ++i)
          {
            const SymmetricTensor<2, 3> sigma_i = stress(material, strain[i]);
            for (unsigned int j = 0; j <= i; ++j)
              cell_matrix(i, j) += (sigma_i * strain[j]) * JxW;
          }
      }
    for (unsigned int i = 0; i < dofs_per_cell; ++i)
      for (unsigned int j = i + 1; j < dofs_per_cell; ++j)
        cell_matrix(i, j) = cell_matrix(j, i);

    local_assemble_boundary(cell,
                            fe_face_values,
                            loads,
                            &cell_matrix,
                            cell_rhs);
  }

  // The boundary terms: tractions into the right-hand side and, when
  // @p cell_matrix is given, the springs into the matrix.
  void
  LinearElasticity::local_assemble_boundary(
    const typename DoFHandler<3>::active_cell_iterator &cell,
    FEFaceValues<3>                                    &fe_face_values,
    const BoundaryLoads                                &loads,
    FullMatrix<double>                                 *cell_matrix,
    Vector<double>                                     &cell_rhs) const
  {
    const unsigned int               dofs_per_cell = fe.n_dofs_per_cell();
    const FEValuesExtractors::Vector displacement(0);
    for (const auto f : cell->face_indices())
      if (cell->face(f)->at_boundary() &&
          loads.acts_on(cell->face(f)->boundary_id()))
        {
          const auto id = cell->face(f)->boundary_id();
          fe_face_values.reinit(cell, f);
          for (const unsigned int q : fe_face_values.quadrature_point_indices())
            {
              const Point<3>    &x   = fe_face_values.quadrature_point(q);
              const Tensor<1, 3> t   = loads.traction(id, x);
              const double       JxW = fe_face_values.JxW(q);
              const Tensor<2, 3> S =
                cell_matrix ? loads.spring(id, x) : Tensor<2, 3>();
              for (unsigned int i = 0; i < dofs_per_cell; ++i)
                {
                  const Tensor<1, 3> v_i =
                    fe_face_values[displacement].value(i, q);
                  cell_rhs(i) += t * v_i * JxW;
                  if (cell_matrix)
                    for (unsigned int j = 0; j < dofs_per_cell; ++j)
                      (*cell_matrix)(i, j) +=
                        v_i * (S * fe_face_values[displacement].value(j, q)) *
                        JxW;
                }
            }
        }
  }

  void
  LinearElasticity::for_each_cell_system(
    const Mapping<3>    &mapping,
    const BoundaryLoads &loads,
    const std::function<void(const DoFHandler<3>::active_cell_iterator &,
                             const FullMatrix<double> &,
                             Vector<double> &,
                             const std::vector<types::global_dof_index> &)>
      &use,
    const std::function<bool(const DoFHandler<3>::active_cell_iterator &,
                             const std::vector<types::global_dof_index> &)>
      &select) const
  {
    FEValues<3>        fe_values(mapping,
                          fe,
                          QGauss<3>(fe.degree + 1),
                          update_gradients | update_JxW_values);
    FEFaceValues<3>    fe_face_values(mapping,
                                   fe,
                                   QGauss<2>(fe.degree + 1),
                                   update_values | update_quadrature_points |
                                     update_JxW_values);
    FullMatrix<double> cell_matrix(fe.n_dofs_per_cell(), fe.n_dofs_per_cell());
    Vector<double>     cell_rhs(fe.n_dofs_per_cell());
    std::vector<types::global_dof_index> dof_indices(fe.n_dofs_per_cell());
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          cell->get_dof_indices(dof_indices);
          if (select && !select(cell, dof_indices))
            continue;
          local_assemble(cell,
                         fe_values,
                         fe_face_values,
                         loads,
                         cell_matrix,
                         cell_rhs);
          use(cell, cell_matrix, cell_rhs, dof_indices);
        }
  }

  // Constraints (Dirichlet data, the contact conditions) are eliminated
  // while copying local to global, which keeps the matrix symmetric and
  // positive definite for CG.
  void
  LinearElasticity::assemble_system(
    const Mapping<3>                &mapping,
    const AffineConstraints<double> &constraints,
    const BoundaryLoads             &loads)
  {
    TimerOutput::Scope scope(timer, "assemble system");
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
  LinearElasticity::assemble_fixed_cells(
    const Mapping<3>                &mapping,
    const AffineConstraints<double> &constraints,
    const BoundaryLoads             &loads,
    const IndexSet                  &changing_dofs,
    const AffineConstraints<double> &all_constraints)
  {
    {
      TimerOutput::Scope scope(timer, "assemble system");
      const auto         has_changing_dof =
        [&](const std::vector<types::global_dof_index> &dofs) {
          return std::any_of(dofs.begin(), dofs.end(), [&](const auto i) {
            return changing_dofs.is_element(i);
          });
        };

      // The changing cells and the rows they can reach, over all cells
      // that this rank knows (their owners may be other ranks).
      changing_cell.assign(dof_handler.get_triangulation().n_active_cells(),
                           false);
      std::vector<types::global_dof_index> dof_indices(fe.n_dofs_per_cell());
      std::vector<types::global_dof_index> reached;
      for (const auto &cell : dof_handler.active_cell_iterators())
        if (!cell->is_artificial())
          {
            cell->get_dof_indices(dof_indices);
            if (!has_changing_dof(dof_indices))
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

      system_matrix = 0;
      system_rhs    = 0;
      add_cells(mapping, constraints, loads, CellSelection::fixed);

      const Epetra_CrsMatrix &matrix = system_matrix.trilinos_matrix();
      const Epetra_FEVector  &rhs    = system_rhs.trilinos_vector();
      kept_rows.clear();
      kept_values.clear();
      for (const auto row : reached)
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
    assemble_changing_cells(mapping, constraints, loads);
  }

  void
  LinearElasticity::assemble_changing_cells(
    const Mapping<3>                &mapping,
    const AffineConstraints<double> &constraints,
    const BoundaryLoads             &loads)
  {
    TimerOutput::Scope scope(timer, "assemble system");
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
  LinearElasticity::add_cells(const Mapping<3>                &mapping,
                              const AffineConstraints<double> &constraints,
                              const BoundaryLoads             &loads,
                              const CellSelection              selection)
  {
    const bool changing = selection == CellSelection::changing;
    for_each_cell_system(
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

  void
  LinearElasticity::assemble_rhs(const Mapping<3>                &mapping,
                                 const AffineConstraints<double> &constraints,
                                 const BoundaryLoads             &loads)
  {
    TimerOutput::Scope scope(timer, "assemble rhs");
    system_rhs = 0;
    FEFaceValues<3>                      fe_face_values(mapping,
                                   fe,
                                   QGauss<2>(fe.degree + 1),
                                   update_values | update_quadrature_points |
                                     update_JxW_values);
    Vector<double>                       cell_rhs(fe.n_dofs_per_cell());
    std::vector<types::global_dof_index> dof_indices(fe.n_dofs_per_cell());
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (cell->is_locally_owned() && cell->at_boundary())
        {
          cell_rhs = 0;
          local_assemble_boundary(cell,
                                  fe_face_values,
                                  loads,
                                  nullptr,
                                  cell_rhs);
          if (cell_rhs.l2_norm() == 0.)
            continue;
          cell->get_dof_indices(dof_indices);
          constraints.distribute_local_to_global(cell_rhs,
                                                 dof_indices,
                                                 system_rhs);
        }
    system_rhs.compress(VectorOperation::add);
  }

  void
  LinearElasticity::compute_residual(
    const Mapping<3>              &mapping,
    const BoundaryLoads           &loads,
    TrilinosWrappers::MPI::Vector &residual) const
  {
    compute_residual(mapping,
                     loads,
                     complete_index_set(dof_handler.n_dofs()),
                     residual);
  }

  void
  LinearElasticity::compute_residual(
    const Mapping<3>              &mapping,
    const BoundaryLoads           &loads,
    const IndexSet                &rows,
    TrilinosWrappers::MPI::Vector &residual) const
  {
    TimerOutput::Scope scope(timer, "residual");
    const bool         all_rows = (rows.n_elements() == dof_handler.n_dofs());
    residual.reinit(owned_dofs, mpi_communicator);
    Vector<double> cell_u(fe.n_dofs_per_cell()), cell_Ku(fe.n_dofs_per_cell());
    for_each_cell_system(
      mapping,
      loads,
      [&](const auto &cell,
          const auto &cell_matrix,
          auto       &cell_rhs,
          const auto &dofs) {
        cell->get_dof_values(solution, cell_u);
        cell_matrix.vmult(cell_Ku, cell_u);
        cell_rhs -= cell_Ku;
        residual.add(dofs, cell_rhs);
      },
      [&](const auto &, const auto &dofs) {
        return all_rows ||
               std::any_of(dofs.begin(), dofs.end(), [&](const auto i) {
                 return rows.is_element(i);
               });
      });
    residual.compress(VectorOperation::add);
  }

  // Smoothed-aggregation AMG for a vector-valued, elliptic problem. ML is
  // told that there are three unknowns per node and gets the six rigid-body
  // modes (or only the three translations) as near-null space; that is what
  // keeps the iteration count independent of the mesh size for elasticity.
  void
  LinearElasticity::setup_preconditioner(const Mapping<3> &mapping)
  {
    TimerOutput::Scope                                scope(timer, "AMG setup");
    TrilinosWrappers::PreconditionAMG::AdditionalData data;
    data.elliptic              = true;
    data.higher_order_elements = (fe.degree > 1);
    data.smoother_sweeps       = solver_parameters.smoother_sweeps;
    data.aggregation_threshold = solver_parameters.aggregation_threshold;

    Teuchos::ParameterList              parameters;
    std::unique_ptr<Epetra_MultiVector> translations;
    data.set_parameters(parameters, translations, system_matrix);
    parameters.set("PDE equations", 3);
    if (solver_parameters.rigid_body_modes)
      {
        near_null_space =
          rigid_body_modes(mapping,
                           dof_handler,
                           owned_dofs,
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
  LinearElasticity::solve(const AffineConstraints<double> &constraints)
  {
    return solve(constraints, solver_parameters.tolerance, false);
  }

  // The stopping criterion is absolute (tolerance times |f|), so a start
  // closer to the solution saves iterations without making the result any
  // less accurate.
  SolverStatistics
  LinearElasticity::solve(const AffineConstraints<double> &constraints,
                          const double                     tolerance,
                          const bool                       start_from_solution)
  {
    TimerOutput::Scope            scope(timer, "CG solve");
    TrilinosWrappers::MPI::Vector owned_solution(owned_dofs, mpi_communicator);
    if (start_from_solution)
      {
        owned_solution = solution;
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
        SolverControl              control(solver_parameters.max_iterations,
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
    solution = owned_solution;
    return statistics;
  }

  double
  LinearElasticity::max_displacement(const types::material_id material) const
  {
    Vector<double> cell_values(fe.n_dofs_per_cell());
    double         max_norm = 0;
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (cell->is_locally_owned() && cell->material_id() == material)
        {
          cell->get_dof_values(solution, cell_values);
          for (unsigned int node = 0;
               node < fe.base_element(0).n_dofs_per_cell();
               ++node)
            {
              double norm_square = 0;
              for (unsigned int d = 0; d < 3; ++d)
                norm_square += Utilities::fixed_power<2>(
                  cell_values(fe.component_to_system_index(d, node)));
              max_norm = std::max(max_norm, std::sqrt(norm_square));
            }
        }
    return Utilities::MPI::max(max_norm, mpi_communicator);
  }
} // namespace TKR::Elasticity
