// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#ifndef tkr_elasticity_linear_elasticity_h
#define tkr_elasticity_linear_elasticity_h

#include <deal.II/base/index_set.h>
#include <deal.II/base/symmetric_tensor.h>
#include <deal.II/base/timer.h>

#include <deal.II/dofs/dof_handler.h>

#include <deal.II/fe/fe_system.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/fe/mapping.h>

#include <deal.II/lac/affine_constraints.h>
#include <deal.II/lac/full_matrix.h>
#include <deal.II/lac/trilinos_precondition.h>
#include <deal.II/lac/trilinos_sparse_matrix.h>
#include <deal.II/lac/trilinos_vector.h>

#include <tkr/parameters/parameters.h>

#include <functional>
#include <map>
#include <memory>

class Epetra_MultiVector;

namespace TKR::Elasticity
{
  /**
   * Small-strain, isotropic linear elasticity:
   * $\sigma = \lambda\,\mathrm{tr}(\varepsilon) I + 2\mu\varepsilon$.
   * Stresses in MPa for strains that are dimensionless.
   */
  dealii::SymmetricTensor<2, 3>
  stress(const Parameters::Material          &material,
         const dealii::SymmetricTensor<2, 3> &strain);

  /** The material of a cell, by its material id (femur or tibia). */
  const Parameters::Material &
  material_of(const Parameters::Materials     &materials,
              const dealii::types::material_id material_id);

  /**
   * Loads and supports on boundary parts, by boundary id: tractions t (MPa)
   * and distributed linear springs, traction = -S u with S in MPa/mm (a
   * spring of total stiffness k N/mm spread uniformly over an area A has
   * S = k/A in its direction). Uniform ones in `tractions` and `springs`,
   * spatially varying ones as functions of the point in the `..._fields`
   * maps; both may act on the same part.
   */
  struct BoundaryLoads
  {
    using TractionField =
      std::function<dealii::Tensor<1, 3>(const dealii::Point<3> &)>;
    using SpringField =
      std::function<dealii::Tensor<2, 3>(const dealii::Point<3> &)>;

    std::map<dealii::types::boundary_id, dealii::Tensor<1, 3>> tractions;
    std::map<dealii::types::boundary_id, dealii::Tensor<2, 3>> springs;
    std::map<dealii::types::boundary_id, TractionField>        traction_fields;
    std::map<dealii::types::boundary_id, SpringField>          spring_fields;

    /** Does anything act on boundary part @p id? */
    bool
    acts_on(const dealii::types::boundary_id id) const;

    /** The total traction and spring tensor at point @p x of part @p id. */
    dealii::Tensor<1, 3>
    traction(const dealii::types::boundary_id id,
             const dealii::Point<3>          &x) const;
    dealii::Tensor<2, 3>
    spring(const dealii::types::boundary_id id,
           const dealii::Point<3>          &x) const;
  };

  /**
   * The loads with the tractions sum_i c_i of the tractions of
   * @p basis[i] (uniform and field tractions of every boundary part) and
   * the springs of @p springs: loads that are linear in a few parameters.
   */
  BoundaryLoads
  linear_combination(const std::vector<BoundaryLoads> &basis,
                     const std::vector<double>        &coefficients,
                     const BoundaryLoads              &springs);

  /** What a linear solve did. */
  struct SolverStatistics
  {
    unsigned int iterations = 0;
    /** Final residual divided by the norm of the right-hand side. */
    double relative_residual = 0;
    bool   converged         = false;
  };

  /**
   * Two linear-elastic bodies on one DoFHandler with FESystem(FE_Q(p), 3),
   * the material of each cell chosen by its material id. Works on any
   * triangulation whose locally owned cells are known (serial or
   * parallel::shared); the matrix and vectors are Trilinos objects over the
   * locally owned DoFs. The verbs follow step-8/step-40: distribute_dofs(),
   * setup_system(), assemble_system(), solve().
   */
  class LinearElasticity
  {
  public:
    LinearElasticity(const dealii::Triangulation<3> &triangulation,
                     const Parameters::Materials    &materials,
                     const Parameters::LinearSolver &solver_parameters,
                     const unsigned int              fe_degree,
                     const MPI_Comm                  mpi_communicator,
                     dealii::TimerOutput            &timer);

    /** Number the DoFs and set the owned and relevant index sets. */
    void
    distribute_dofs();

    /**
     * Build the sparsity pattern (with the couplings @p constraints
     * introduce) and size the matrix and vectors. Call again when the
     * constraints couple new DoFs.
     */
    void
    setup_system(const dealii::AffineConstraints<double> &constraints);

    /**
     * Assemble the stiffness matrix and the load vector on the geometry
     * given by @p mapping, with the boundary @p loads, eliminating
     * @p constraints (inhomogeneities included) as in step-8.
     */
    void
    assemble_system(const dealii::Mapping<3>                &mapping,
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
     * this again after setup_system().
     */
    void
    assemble_fixed_cells(
      const dealii::Mapping<3>                &mapping,
      const dealii::AffineConstraints<double> &constraints,
      const BoundaryLoads                     &loads,
      const dealii::IndexSet                  &changing_dofs,
      const dealii::AffineConstraints<double> &all_constraints);

    /**
     * The second half of the split assembly: the system of
     * assemble_system() for @p constraints, from the rows kept by
     * assemble_fixed_cells() and the cells with changing DoFs, which are
     * assembled again. The same matrix and vector as assemble_system()
     * up to round-off (the sums run in another order).
     */
    void
    assemble_changing_cells(
      const dealii::Mapping<3>                &mapping,
      const dealii::AffineConstraints<double> &constraints,
      const BoundaryLoads                     &loads);

    /**
     * Only the right-hand side of assemble_system() (the boundary
     * tractions; there are no body forces), condensed with
     * @p constraints, which must be homogeneous. For a matrix that stays
     * the same while the loads change.
     */
    void
    assemble_rhs(const dealii::Mapping<3>                &mapping,
                 const dealii::AffineConstraints<double> &constraints,
                 const BoundaryLoads                     &loads);

    /**
     * The residual r = f - K u of the unconstrained system for the current
     * solution, in @p residual (locally owned entries). At a slave node in
     * contact it is the contact force that the constraints exert.
     */
    void
    compute_residual(const dealii::Mapping<3>              &mapping,
                     const BoundaryLoads                   &loads,
                     dealii::TrilinosWrappers::MPI::Vector &residual) const;

    /**
     * As above, but only the cells that hold one of the DoFs @p rows are
     * visited: the residual is exact in these rows (they get all their
     * contributions) and incomplete elsewhere. The contact solver needs
     * it only at the slave nodes, whose cells are a thin layer.
     */
    void
    compute_residual(const dealii::Mapping<3>              &mapping,
                     const BoundaryLoads                   &loads,
                     const dealii::IndexSet                &rows,
                     dealii::TrilinosWrappers::MPI::Vector &residual) const;

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

    /** The `Linear solver` parameters. */
    const Parameters::LinearSolver &
    get_solver_parameters() const
    {
      return solver_parameters;
    }

    /**
     * Replace the solution by @p owned_solution (locally owned entries,
     * constraints already satisfied), e.g. from another solver.
     */
    void
    set_solution(const dealii::TrilinosWrappers::MPI::Vector &owned_solution)
    {
      solution = owned_solution;
    }

    /** Largest nodal displacement magnitude (mm) in the body @p material. */
    double
    max_displacement(const dealii::types::material_id material) const;

    const dealii::DoFHandler<3> &
    get_dof_handler() const
    {
      return dof_handler;
    }
    const dealii::FESystem<3> &
    get_fe() const
    {
      return fe;
    }
    const dealii::IndexSet &
    locally_owned_dofs() const
    {
      return owned_dofs;
    }
    const dealii::IndexSet &
    locally_relevant_dofs() const
    {
      return relevant_dofs;
    }
    /** The solution with ghost entries (read it, do not write it). */
    const dealii::TrilinosWrappers::MPI::Vector &
    get_solution() const
    {
      return solution;
    }
    const dealii::TrilinosWrappers::SparseMatrix &
    get_system_matrix() const
    {
      return system_matrix;
    }
    const dealii::TrilinosWrappers::MPI::Vector &
    get_system_rhs() const
    {
      return system_rhs;
    }
    const Parameters::Materials &
    get_materials() const
    {
      return materials;
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
     * Add the cells of @p selection to the system, with @p constraints
     * (assemble_system(), assemble_fixed_cells() and
     * assemble_changing_cells()), and compress it.
     */
    void
    add_cells(const dealii::Mapping<3>                &mapping,
              const dealii::AffineConstraints<double> &constraints,
              const BoundaryLoads                     &loads,
              const CellSelection                      selection);

    /**
     * For every locally owned cell that @p select accepts (given the
     * cell and its DoF indices; all cells if it is empty): its matrix and load
     * vector (no constraints applied), handed to @p use with the cell's
     * DoF indices.
     */
    void
    for_each_cell_system(
      const dealii::Mapping<3> &mapping,
      const BoundaryLoads      &loads,
      const std::function<
        void(const dealii::DoFHandler<3>::active_cell_iterator &,
             const dealii::FullMatrix<double> &,
             dealii::Vector<double> &,
             const std::vector<dealii::types::global_dof_index> &)> &use,
      const std::function<bool(
        const dealii::DoFHandler<3>::active_cell_iterator &,
        const std::vector<dealii::types::global_dof_index> &)> &select = {})
      const;

    /** Cell matrix and load vector (no constraints applied). */
    void
    local_assemble(const dealii::DoFHandler<3>::active_cell_iterator &cell,
                   dealii::FEValues<3>                               &fe_values,
                   dealii::FEFaceValues<3>    &fe_face_values,
                   const BoundaryLoads        &loads,
                   dealii::FullMatrix<double> &cell_matrix,
                   dealii::Vector<double>     &cell_rhs) const;

    void
    local_assemble_boundary(
      const dealii::DoFHandler<3>::active_cell_iterator &cell,
      dealii::FEFaceValues<3>                           &fe_face_values,
      const BoundaryLoads                               &loads,
      dealii::FullMatrix<double>                        *cell_matrix,
      dealii::Vector<double>                            &cell_rhs) const;

    const Parameters::Materials    materials;
    const Parameters::LinearSolver solver_parameters;
    const MPI_Comm                 mpi_communicator;
    dealii::TimerOutput           &timer;

    dealii::FESystem<3>   fe;
    dealii::DoFHandler<3> dof_handler;
    dealii::IndexSet      owned_dofs, relevant_dofs;

    dealii::TrilinosWrappers::SparseMatrix    system_matrix;
    dealii::TrilinosWrappers::MPI::Vector     system_rhs;
    dealii::TrilinosWrappers::MPI::Vector     solution;
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
