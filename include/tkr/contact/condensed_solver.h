// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#ifndef tkr_contact_condensed_solver_h
#define tkr_contact_condensed_solver_h

#include <tkr/contact/contact_solver.h>
#include <tkr/elasticity/direct_solver.h>
#include <tkr/mortar/mortar_operator.h>

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
   * With the mortar operator B (Mortar::MortarOperator) the displacement is
   * u = u_0 - K^{-1} B^T lambda, u_0 = K^{-1} f, and the weighted gaps are
   * g(lambda) = g_0 + W lambda with g_0 = g - B u_0 and the Delassus
   * matrix W = B K^{-1} B^T. A Newton step of the active set A solves the
   * dense system W_AA lambda_A = -g_0,A; the update of the set is the same
   * as ActiveSetSolver's (ActiveSetUpdate), so both solve the same
   * discrete problem. K^{-1} is applied through one sparse factorisation
   * (DirectSolver); the columns that W needs, K^{-1} of the slave part of
   * B_i^T for every active slave node i and of unit loads in x, y, z at
   * every master node coupled to one, are computed when first needed and
   * kept for every later solve. So a gait cycle costs one factorisation, a
   * few thousand back substitutions and small dense solves instead of an
   * AMG-CG solve per Newton iteration.
   *
   * Assumes that K does not couple the two bodies (true: they touch only
   * through the contact constraints); a column that does is refused.
   */
  class CondensedActiveSetSolver : public ContactSolver
  {
  public:
    using ContactSolver::ContactSolver;

    /**
     * Assemble K with the constraints @p dirichlet and the springs of
     * @p loads (they must be the springs of every later solve), factorise
     * it and forget all stored columns.
     */
    void
    setup(const dealii::Mapping<3>                &mapping,
          const dealii::AffineConstraints<double> &dirichlet,
          const Elasticity::BoundaryLoads         &loads) override;

    /**
     * Solve on the current coupling; the displacement is computed on the
     * contact surfaces and for the observations only (compute_solution()
     * gives the full one).
     */
    ContactStatistics
    solve(const dealii::Mapping<3>        &mapping,
          const Elasticity::BoundaryLoads &loads,
          const double                     initial_distance,
          ContactState                    &state) override;

    /** Also forgets the stored columns (they hold the observations). */
    unsigned int
    add_observation(
      const dealii::TrilinosWrappers::MPI::Vector &weights) override;

    /**
     * u = K^{-1} (f - B^T lambda) for the multipliers of the last solve,
     * into the LinearElasticity object (one more back substitution).
     */
    void
    compute_solution() override;

    std::string
    name() const override
    {
      return "condensed active set";
    }

    std::string
    description() const override
    {
      return "condensed active set (sparse Cholesky of the stiffness)";
    }

    /** Number of stored columns of K^{-1}. */
    unsigned int
    n_columns() const
    {
      return n_stored_columns;
    }

  private:
    /** A stored column: its values at the surface DoFs and observations. */
    struct Column
    {
      std::vector<double> surface;
      std::vector<double> observations;
    };

    /** Forget all stored columns. */
    void
    clear_columns();

    /**
     * Compute the missing columns: of the slave part of B_i^T for the
     * slave nodes @p slave, of unit loads at the master nodes @p master.
     */
    void
    compute_columns(const Mortar::MortarOperator    &B,
                    const std::vector<unsigned int> &slave,
                    const std::vector<unsigned int> &master);

    /**
     * z_i = K^{-1} B_i^T (surface values, then observations) from the
     * stored columns.
     */
    Column
    compliance(const Mortar::MortarOperator &B, const unsigned int i) const;

    /**
     * Values of the columns of @p X at the surface DoFs, on all ranks;
     * column c at offset c * surface size. Constrained DoFs are read from
     * their constraints (without the inhomogeneity) unless X is
     * @p distributed already.
     */
    std::vector<double>
    read_surface(const Epetra_MultiVector &X, const bool distributed) const;

    /** The observations of every column of @p X (column-major, all ranks). */
    std::vector<double>
    observe(const Epetra_MultiVector &X) const;

    /** Add @p value at DoF @p dof of column @p c (through constraints). */
    void
    add_load(Epetra_MultiVector                   &B,
             const unsigned int                    c,
             const dealii::types::global_dof_index dof,
             const double                          value) const;

    /** The right-hand side of the inhomogeneous Dirichlet values. */
    dealii::TrilinosWrappers::MPI::Vector dirichlet_rhs;
    Elasticity::DirectSolver              direct_solver;
    /** Slave node DoFs (3 per node) followed by master node DoFs. */
    std::vector<dealii::types::global_dof_index> surface_dofs;
    unsigned int                                 n_slave_values  = 0;
    unsigned int                                 n_master_values = 0;
    /** Per slave node: the column of the slave part of B_i^T, if stored. */
    std::vector<Column> slave_columns;
    /** The load (slave part of B_i^T, 3 values) each was computed for. */
    std::vector<dealii::Tensor<1, 3>> slave_column_loads;
    /** Per master node: the columns of unit loads in x, y, z. */
    std::vector<std::array<Column, 3>> master_columns;
    unsigned int                       n_stored_columns = 0;

    /** Right-hand side and contact state of the last solve. */
    dealii::TrilinosWrappers::MPI::Vector last_rhs;
    ContactState                          last_state;
  };
} // namespace TKR::Contact

#endif
