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
#include <deal.II/lac/trilinos_sparse_matrix.h>
#include <deal.II/lac/trilinos_vector.h>

#include <tkr/parameters/parameters.h>

#include <functional>
#include <map>
#include <memory>

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
   * The discretisation of two linear-elastic bodies on one DoFHandler with
   * FESystem(FE_Q(p), 3), the material of each cell chosen by its material
   * id: the DoFs, the cell matrices and load vectors, load vectors of
   * boundary tractions, residuals of a given displacement. Works on any
   * triangulation whose locally owned cells are known (serial or
   * parallel::shared); vectors are Trilinos objects over the locally owned
   * DoFs. It holds no system and no solution: a linear system is an
   * ElasticSystem of its own user, and every function that reads a
   * displacement takes it as an argument.
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
     * The load vector of the boundary tractions of @p loads (there are no
     * body forces) on the geometry of @p mapping, condensed with
     * @p constraints, which must be homogeneous: for a matrix that stays
     * the same while the loads change, and for the weights of a linear
     * functional whose work is that of the tractions.
     */
    dealii::TrilinosWrappers::MPI::Vector
    load_vector(const dealii::Mapping<3>                &mapping,
                const dealii::AffineConstraints<double> &constraints,
                const BoundaryLoads                     &loads) const;

    /**
     * The residual r = f - K u of the unconstrained system for the
     * displacement @p solution (ghosted), in @p residual (locally owned
     * entries). Only the cells that hold one of the DoFs @p rows are
     * visited: the residual is exact in these rows (they get all their
     * contributions) and incomplete elsewhere. At a slave node in contact
     * it is the contact force that the constraints exert; the contact
     * solver needs it only there, in a thin layer of cells.
     */
    void
    compute_residual(const dealii::Mapping<3>                    &mapping,
                     const BoundaryLoads                         &loads,
                     const dealii::TrilinosWrappers::MPI::Vector &solution,
                     const dealii::IndexSet                      &rows,
                     dealii::TrilinosWrappers::MPI::Vector &residual) const;

    /**
     * Largest nodal displacement magnitude (mm) of @p solution (ghosted)
     * in the body @p material.
     */
    double
    max_displacement(const dealii::TrilinosWrappers::MPI::Vector &solution,
                     const dealii::types::material_id material) const;

    /** A ghosted vector of all locally relevant DoFs, zero. */
    dealii::TrilinosWrappers::MPI::Vector
    make_ghosted_vector() const;

    /**
     * For every locally owned cell that @p select accepts (given the
     * cell and its DoF indices; all cells if it is empty): its matrix and
     * load vector (no constraints applied), handed to @p use with the
     * cell's DoF indices.
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

    /** The `Linear solver` parameters. */
    const Parameters::LinearSolver &
    get_solver_parameters() const
    {
      return solver_parameters;
    }

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
    const Parameters::Materials &
    get_materials() const
    {
      return materials;
    }
    MPI_Comm
    get_communicator() const
    {
      return mpi_communicator;
    }
    /** The timer of the run (sections of assembly and solvers). */
    dealii::TimerOutput &
    get_timer() const
    {
      return timer;
    }

  private:
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
  };
} // namespace TKR::Elasticity

#endif
