// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#ifndef tkr_contact_active_set_solver_h
#define tkr_contact_active_set_solver_h

#include <tkr/contact/contact_solver.h>
#include <tkr/elasticity/elastic_system.h>
#include <tkr/mortar/mortar_operator.h>

#include <vector>

namespace TKR::Contact
{
  /**
   * Primal-dual active set method (semismooth Newton, Hueber & Wohlmuth)
   * for frictionless mortar contact between the two linear-elastic bodies
   * (DESIGN.md section 4.4).
   *
   * On an active slave node j the condition B_j u = g_j (zero gap after
   * deformation, Mortar::MortarOperator) becomes one AffineConstraints
   * line on the node's dominant normal component. The condensed system is
   * solved by CG with ML AMG; the multiplier follows from the residual of
   * the unconstrained system, lambda_j = r_j . n_j / D_jj; the active set is
   * updated with the complementarity function lambda_j - c_j g_j(u) with
   * c_j = E_slave / h_j, which makes the update independent of units
   * (ActiveSetUpdate). Converged when the active set does not change and
   * the linear solve met the tolerance. Repeating active sets (cycles) are
   * detected; the next update then changes only the most violated node.
   */
  class ActiveSetSolver : public ContactSolver
  {
  public:
    ActiveSetSolver(const Elasticity::LinearElasticity &elasticity,
                    const Mortar::MortarCoupling       &coupling,
                    const Parameters::ContactSolver    &parameters,
                    const double                        slave_youngs_modulus,
                    const MPI_Comm                      mpi_communicator,
                    const dealii::ConditionalOStream   &pcout,
                    dealii::TimerOutput                &timer,
                    const bool                          testing = false);

    /** The solve() for a combination of the load basis, too. */
    using ContactSolver::solve;

    /**
     * Solve on the current coupling. The sparsity pattern is built for it
     * first, holding the couplings of every covered slave node, so that
     * the matrix survives the changes of the active set.
     */
    ContactStatistics
    solve(const dealii::Mapping<3>        &mapping,
          const Elasticity::BoundaryLoads &loads,
          const double                     initial_distance,
          ContactState                    &state) override;

    /** The solution of the last Newton step. */
    dealii::TrilinosWrappers::MPI::Vector
    compute_solution() override
    {
      return system.solution();
    }

    std::string
    name() const override
    {
      return "active set";
    }

    std::string
    description() const override
    {
      return "active set, AMG-preconditioned CG";
    }

  private:
    /**
     * The constraints of the active nodes of @p active, merged with the
     * Dirichlet constraints. The mortar condition of node j, B_j u = g_j,
     * is solved for the DoF of the component d in which n_j is largest:
     * u_jd = (g_j - sum_{c != jd} B_jc u_c) / B_j,jd.
     */
    void
    make_constraints(const Mortar::MortarOperator      &B,
                     const std::vector<bool>           &active,
                     dealii::AffineConstraints<double> &constraints) const;

    /**
     * Pressures (multipliers), gaps after deformation and displacements of
     * the slave nodes in @p state from the current solution.
     */
    void
    evaluate_state(const dealii::Mapping<3>        &mapping,
                   const Elasticity::BoundaryLoads &loads,
                   const Mortar::MortarOperator    &B,
                   const dealii::IndexSet          &slave_dofs,
                   ContactState                    &state) const;

    /**
     * Solve the linear system of one Newton step (inexact Newton: as far
     * as the next active set needs, see the .cc file), starting from the
     * last solution if @p warm_start, and evaluate @p state for its
     * solution; @p n_changed is set to the number of nodes that the
     * active-set update would change.
     */
    Elasticity::SolverStatistics
    solve_newton_step(const dealii::Mapping<3>                &mapping,
                      const Elasticity::BoundaryLoads         &loads,
                      const Mortar::MortarOperator            &B,
                      const dealii::IndexSet                  &slave_dofs,
                      const dealii::AffineConstraints<double> &constraints,
                      const ActiveSetUpdate &active_set_update,
                      const bool             warm_start,
                      ContactState          &state,
                      unsigned int          &n_changed);

    /**
     * The sparsity pattern for the constraints of every covered node
     * (@p all_covered_constraints), the DoFs whose constraint lines change
     * with the active set and the slave DoFs.
     */
    void
    setup_system(const Mortar::MortarOperator      &B,
                 dealii::AffineConstraints<double> &all_covered_constraints,
                 dealii::IndexSet                  &changing_dofs,
                 dealii::IndexSet                  &slave_dofs);

    /**
     * The system of a Newton step for @p constraints: the whole split
     * assembly if @p changing_dofs is given (the first step), else only the
     * cells with changing DoFs; a new AMG hierarchy if
     * @p new_preconditioner.
     */
    void
    assemble_newton_system(
      const dealii::Mapping<3>                &mapping,
      const Elasticity::BoundaryLoads         &loads,
      const dealii::AffineConstraints<double> &constraints,
      const dealii::IndexSet                  *changing_dofs,
      const dealii::AffineConstraints<double> &all_covered_constraints,
      const bool                               new_preconditioner);

    /**
     * After a linear solve that did not converge: true if the Newton step
     * is to be repeated with a new preconditioner (a reused one failed, or
     * the active set was widened to the nodes within the growing
     * @p expansion_distance of the closest one), false to give up.
     */
    bool
    recover(const bool       fresh_preconditioner,
            unsigned int    &n_expansions,
            double          &expansion_distance,
            ContactState    &state,
            ActiveSetUpdate &active_set_update) const;

    /** The screen line of a Newton iteration. */
    void
    print_iteration(const unsigned int                  iteration,
                    const unsigned int                  n_active,
                    const unsigned int                  n_changed,
                    const Elasticity::SolverStatistics &linear,
                    const double                        wall_time) const;

    /** Values of a distributed vector at the surface DoFs, on all ranks. */
    std::vector<double>
    gather(const Mortar::MortarOperator                &B,
           const dealii::TrilinosWrappers::MPI::Vector &vector) const;

    /** The linear system of the Newton steps. */
    Elasticity::ElasticSystem system;
  };
} // namespace TKR::Contact

#endif
