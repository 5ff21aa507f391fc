// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#ifndef tkr_contact_condensed_solver_h
#define tkr_contact_condensed_solver_h

#include <deal.II/base/conditional_ostream.h>
#include <deal.II/base/timer.h>

#include <deal.II/fe/mapping.h>

#include <deal.II/lac/affine_constraints.h>

#include <tkr/contact/active_set_solver.h>
#include <tkr/elasticity/direct_solver.h>
#include <tkr/elasticity/linear_elasticity.h>
#include <tkr/mortar/mortar_coupling.h>
#include <tkr/parameters/parameters.h>

#include <vector>

namespace TKR::Contact
{
  /**
   * The primal-dual active set method of ActiveSetSolver on the contact
   * surface only, for a stiffness matrix K that does not change between
   * many contact solves (the gait cycle: the femur lives in its co-rotated
   * frame and the tibia only translates, so K is the same in every step
   * and pose update).
   *
   * With the mortar operator B (row j: D_jj n_j on slave node j,
   * -M_jk n^m_j on master node k) the displacement is
   * u = u_0 - K^{-1} B^T lambda, u_0 = K^{-1} f, and the weighted gaps are
   * g(lambda) = g_0 + W lambda with g_0 = g - B u_0 and the Delassus
   * matrix W = B K^{-1} B^T. A Newton step of the active set A solves the
   * dense system W_AA lambda_A = -g_0,A; the update of the set is the same
   * as ActiveSetSolver's (ActiveSetUpdate), so both solve the same
   * discrete problem. K^{-1} is applied through one sparse LU
   * factorisation (DirectSolver); the columns K^{-1} e that W needs (one
   * per active slave node along its normal, three per master node coupled
   * to it) are computed when first needed and kept for every later solve.
   * So a gait cycle costs one factorisation, a few thousand back
   * substitutions and small dense solves instead of an AMG-CG solve per
   * Newton iteration.
   *
   * Assumes that K does not couple the two bodies (true: they touch only
   * through the contact constraints); a column that does is refused.
   */
  class CondensedActiveSetSolver
  {
  public:
    CondensedActiveSetSolver(Elasticity::LinearElasticity    &elasticity,
                             const Mortar::MortarCoupling    &coupling,
                             const Parameters::ContactSolver &parameters,
                             const double   slave_youngs_modulus,
                             const MPI_Comm mpi_communicator,
                             const dealii::ConditionalOStream &pcout,
                             dealii::TimerOutput              &timer);

    /**
     * Assemble K with the constraints @p dirichlet and the
     * springs of @p loads (they must be the springs of every later
     * solve), factorise it and forget all stored columns.
     */
    void
    factorize(const dealii::Mapping<3>                &mapping,
              const dealii::AffineConstraints<double> &dirichlet,
              const Elasticity::BoundaryLoads         &loads);

    /**
     * Solve the contact problem on the current coupling for the tractions
     * of @p loads; as ActiveSetSolver::solve(). Leaves the full
     * displacement in the LinearElasticity object.
     */
    ContactStatistics
    solve(const dealii::Mapping<3>        &mapping,
          const Elasticity::BoundaryLoads &loads,
          const double                     initial_distance,
          ContactState                    &state);

    /**
     * Add a linear functional of the displacement, w . u, that every solve
     * evaluates from the stored columns (no full solve needed): @p weights
     * is a right-hand side assembled with the factorised constraints (e.g.
     * by LinearElasticity::assemble_rhs() for a traction whose work is the
     * functional), which must be homogeneous. Forgets the stored columns.
     * Returns the functional's index for observation().
     */
    unsigned int
    add_observation(const dealii::TrilinosWrappers::MPI::Vector &weights);

    /** Value of functional @p i for the displacement of the last solve. */
    double
    observation(const unsigned int i) const
    {
      return observed.at(i);
    }

    /**
     * Put the full displacement of the last solve into the
     * LinearElasticity object (one more back substitution; solve() itself
     * computes only the contact surfaces and the observations).
     */
    void
    compute_solution();

    /** Number of stored columns of K^{-1} (slave + 3 x master nodes). */
    unsigned int
    n_columns() const
    {
      return n_stored_columns;
    }

  private:
    /** Compute the missing columns of the slave and master nodes given. */
    void
    compute_columns(const std::vector<unsigned int> &slave,
                    const std::vector<unsigned int> &master);

    /**
     * Values of the columns of @p X at the surface DoFs (slave nodes, then
     * master nodes), on all ranks; column c at offset c * surface size.
     * Constrained DoFs are read from their constraints (without the
     * inhomogeneity) unless X is @p distributed already.
     */
    std::vector<double>
    read_surface(const Epetra_MultiVector &X, const bool distributed) const;

    /** The observations of every column of @p X (column-major, on all ranks).
     */
    std::vector<double>
    observe(const Epetra_MultiVector &X) const;

    /** Add @p value at DoF @p dof of column @p c (through constraints). */
    void
    add_load(Epetra_MultiVector                   &B,
             const unsigned int                    c,
             const dealii::types::global_dof_index dof,
             const double                          value) const;

    Elasticity::LinearElasticity    &elasticity;
    const Mortar::MortarCoupling    &coupling;
    const Parameters::ContactSolver  parameters;
    const double                     slave_youngs_modulus;
    const MPI_Comm                   mpi_communicator;
    const dealii::ConditionalOStream pcout;
    dealii::TimerOutput             &timer;

    dealii::AffineConstraints<double> dirichlet;
    /** The right-hand side of the inhomogeneous Dirichlet values. */
    dealii::TrilinosWrappers::MPI::Vector dirichlet_rhs;
    Elasticity::DirectSolver              direct_solver;
    /** Slave node DoFs (3 per node) followed by master node DoFs. */
    std::vector<dealii::types::global_dof_index> surface_dofs;
    unsigned int                                 n_slave_values  = 0;
    unsigned int                                 n_master_values = 0;
    /**
     * Per slave node: K^{-1} of a unit force along its normal at the slave
     * surface DoFs (empty until needed).
     */
    std::vector<std::vector<double>> slave_columns;
    /** The normal each slave column was computed for. */
    std::vector<dealii::Tensor<1, 3>> slave_column_normals;
    /**
     * Per master node: K^{-1} of unit forces in x, y, z at the master
     * surface DoFs, one after the other (empty until needed).
     */
    std::vector<std::vector<double>> master_columns;
    unsigned int                     n_stored_columns = 0;

    /** Weights of the observed functionals and their value per column. */
    std::vector<dealii::TrilinosWrappers::MPI::Vector> observation_weights;
    std::vector<std::vector<double>> slave_observations, master_observations;
    /** The functionals' values for the last solve. */
    std::vector<double> observed;
    /** Right-hand side and contact state of the last solve. */
    dealii::TrilinosWrappers::MPI::Vector last_rhs;
    ContactState                          last_state;
  };
} // namespace TKR::Contact

#endif
