// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#ifndef tkr_elasticity_elastic_system_h
#define tkr_elasticity_elastic_system_h

#include <deal.II/base/index_set.h>

#include <deal.II/fe/mapping.h>

#include <deal.II/lac/affine_constraints.h>
#include <deal.II/lac/trilinos_precondition.h>
#include <deal.II/lac/trilinos_sparse_matrix.h>
#include <deal.II/lac/trilinos_vector.h>

#include <tkr/elasticity/linear_elasticity.h>

#include <memory>
#include <vector>

class Epetra_MultiVector;

namespace TKR::Elasticity
{
  /**
   * One linear system K u = f of the two bodies of a LinearElasticity
   * discretisation, with constraints eliminated as in step-8: the matrix,
   * the load vector, the solution and the AMG preconditioner. Whoever
   * solves owns one (a contact solver, the demonstration problem), so no
   * two users ever share the vectors of another: the discretisation
   * (LinearElasticity) holds no solution. The verbs follow
   * step-8/step-40: setup(), assemble(), setup_preconditioner(), solve().
   */
  class ElasticSystem
  {
  public:
    explicit ElasticSystem(const LinearElasticity &elasticity);

    /**
     * Build the sparsity pattern (with the couplings @p constraints
     * introduce) and size the matrix and vectors. Call again when the
     * constraints couple new DoFs.
     */
    void
    setup(const dealii::AffineConstraints<double> &constraints);

    /**
     * Assemble the stiffness matrix and the load vector on the geometry
     * given by @p mapping, with the boundary @p loads, eliminating
     * @p constraints (inhomogeneities included) as in step-8.
     */
    void
    assemble(const dealii::Mapping<3>                &mapping,
             const dealii::AffineConstraints<double> &constraints,
             const BoundaryLoads                     &loads);

    /**
     * The first half of a split assembly, for a sequence of systems whose
     * constraints differ only on the DoFs @p changing_dofs (the contact
     * constraints of an active set; the loads, the mapping and all other
     * constraints stay). Every cell without such a DoF is assembled with
     * @p constraints, once; the values of the rows that the other cells
     * can add to (their DoFs and every DoF the lines of @p
     * all_constraints make these depend on) are kept.
     * assemble_changing_cells() then completes the system for any
     * constraints of the sequence. @p all_constraints holds every line
     * the sequence may use (the sparsity pattern was built for it); call
     * this again after setup().
     */
    void
    assemble_fixed_cells(
      const dealii::Mapping<3>                &mapping,
      const dealii::AffineConstraints<double> &constraints,
      const BoundaryLoads                     &loads,
      const dealii::IndexSet                  &changing_dofs,
      const dealii::AffineConstraints<double> &all_constraints);

    /**
     * The second half of the split assembly: the system of assemble() for
     * @p constraints, from the rows kept by assemble_fixed_cells() and the
     * cells with changing DoFs, which are assembled again. The same matrix
     * and vector as assemble() up to round-off (the sums run in another
     * order).
     */
    void
    assemble_changing_cells(
      const dealii::Mapping<3>                &mapping,
      const dealii::AffineConstraints<double> &constraints,
      const BoundaryLoads                     &loads);

    /**
     * Build the ML AMG preconditioner of the current matrix with the
     * rigid-body modes (evaluated at the support points mapped by
     * @p mapping) as near-null space.
     */
    void
    setup_preconditioner(const dealii::Mapping<3> &mapping);

    /**
     * Solve with CG and the AMG preconditioner (set up by
     * setup_preconditioner()), distribute the constraints and update the
     * ghosted solution. A non-converged solve is reported, not thrown.
     */
    SolverStatistics
    solve(const dealii::AffineConstraints<double> &constraints);

    /**
     * As solve(), but CG stops when the residual is @p tolerance times the
     * norm of the right-hand side (instead of the `Linear solver`
     * tolerance) and, if @p start_from_solution, it starts from the
     * current solution instead of zero (its constrained entries set to
     * zero, the value the condensed system has there): for a sequence of
     * systems with similar solutions, such as the Newton steps of the
     * contact solver.
     */
    SolverStatistics
    solve(const dealii::AffineConstraints<double> &constraints,
          const double                             tolerance,
          const bool                               start_from_solution);

    /** The assembled matrix (constraints eliminated). */
    const dealii::TrilinosWrappers::SparseMatrix &
    matrix() const
    {
      return system_matrix;
    }

    /** The assembled load vector (constraints eliminated). */
    const dealii::TrilinosWrappers::MPI::Vector &
    rhs() const
    {
      return system_rhs;
    }

    /** The solution of the last solve(), with ghost entries. */
    const dealii::TrilinosWrappers::MPI::Vector &
    solution() const
    {
      return solution_vector;
    }

  private:
    /** Which cells add_cells() adds. */
    enum class CellSelection
    {
      all,
      /** Those whose DoFs do not change with the active set. */
      fixed,
      /** Those whose DoFs do (assemble_fixed_cells() marks them). */
      changing
    };

    /**
     * Add the cells of @p selection to the system, with @p constraints,
     * and compress it.
     */
    void
    add_cells(const dealii::Mapping<3>                &mapping,
              const dealii::AffineConstraints<double> &constraints,
              const BoundaryLoads                     &loads,
              const CellSelection                      selection);

    /**
     * Mark the cells with a DoF of @p changing_dofs and return the locally
     * relevant rows they can add to (their DoFs and the DoFs the lines of
     * @p all_constraints make these depend on).
     */
    std::vector<dealii::types::global_dof_index>
    mark_changing_cells(
      const dealii::IndexSet                  &changing_dofs,
      const dealii::AffineConstraints<double> &all_constraints);

    /** Keep the values of the owned rows of @p rows (matrix and vector). */
    void
    keep_rows(const std::vector<dealii::types::global_dof_index> &rows);

    const LinearElasticity &elasticity;

    dealii::TrilinosWrappers::SparseMatrix    system_matrix;
    dealii::TrilinosWrappers::MPI::Vector     system_rhs;
    dealii::TrilinosWrappers::MPI::Vector     solution_vector;
    dealii::TrilinosWrappers::PreconditionAMG preconditioner;

    /**
     * The split assembly (assemble_fixed_cells()): which active cells are
     * assembled again (by active_cell_index()), the locally owned rows
     * they can add to (local row of the matrix and position of the row's
     * first value in @p kept_values), the values of these rows and
     * right-hand side entries from the other cells.
     */
    struct KeptRow
    {
      /** Local index of the row in the matrix and in the vector. */
      int matrix_row, vector_entry;
      /** Where the row's values start in kept_values. */
      std::size_t first_value;
      double      rhs;
    };
    std::vector<bool>    changing_cell;
    std::vector<KeptRow> kept_rows;
    std::vector<double>  kept_values;

    /** Near-null space handed to ML; must outlive the preconditioner. */
    std::unique_ptr<Epetra_MultiVector> near_null_space;
  };
} // namespace TKR::Elasticity

#endif
