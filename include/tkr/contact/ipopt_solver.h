// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#ifndef tkr_contact_ipopt_solver_h
#define tkr_contact_ipopt_solver_h

#include <tkr/contact/contact_solver.h>
#include <tkr/contact/ipopt_qp_loader.h>
#include <tkr/mortar/mortar_operator.h>

#include <memory>
#include <vector>

namespace TKR::Contact
{
  /**
   * The reference solver (DESIGN.md section 4.5): the same discrete contact
   * problem as ActiveSetSolver, written as the convex quadratic program
   *
   *   min 1/2 u^T K u - f^T u
   *   s.t. g_j + n_j . (sum_k M_jk u_k - D_jj u_j) >= 0 for covered nodes j,
   *        u_i = Dirichlet value for constrained DoFs,
   *
   * and solved by the interior-point method Ipopt (with its sequential
   * direct solver MUMPS). Slow and serial, but independent of the active
   * set logic, the constraint elimination and the iterative solver: the
   * tests cross-check the active-set solution with it. The pressure is
   * minus Ipopt's constraint multiplier.
   */
  class IpoptSolver : public ContactSolver
  {
  public:
    using ContactSolver::ContactSolver;

    /** The solve() for a combination of the load basis, too. */
    using ContactSolver::solve;

    /**
     * Solve to 1e-2 x the Contact solver tolerance; the solution is kept
     * for compute_solution(), pressures, gaps and the active set
     * (nodes where lambda_j - c_j g_j > 0, as in the active-set method)
     * into @p state. Only on one MPI rank. @p initial_distance is not used
     * (the interior-point method needs no initial active set).
     */
    ContactStatistics
    solve(const dealii::Mapping<3>        &mapping,
          const Elasticity::BoundaryLoads &loads,
          const double                     initial_distance,
          ContactState                    &state) override;

    /** The displacement of the last solve. */
    dealii::TrilinosWrappers::MPI::Vector
    compute_solution() override
    {
      return solution;
    }

    std::string
    name() const override
    {
      return "Ipopt, interior point";
    }

    std::string
    description() const override
    {
      return name();
    }

  private:
    /**
     * The QP of the contact problem for @p loads on @p mapping; the row of
     * each covered slave node's inequality in @p row_of_node.
     */
    std::unique_ptr<QuadraticProgram>
    make_program(const dealii::Mapping<3>        &mapping,
                 const Elasticity::BoundaryLoads &loads,
                 const Mortar::MortarOperator    &B,
                 std::vector<unsigned int>       &row_of_node) const;

    /** Pressures, gaps, displacements and active set from Ipopt's result. */
    void
    read_state(const QuadraticProgram          &qp,
               const Mortar::MortarOperator    &B,
               const std::vector<unsigned int> &row_of_node,
               ContactState                    &state) const;

    /** The displacement of the last solve (ghosted). */
    dealii::TrilinosWrappers::MPI::Vector solution;
  };
} // namespace TKR::Contact

#endif
