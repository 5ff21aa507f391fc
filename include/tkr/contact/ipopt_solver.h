// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#ifndef tkr_contact_ipopt_solver_h
#define tkr_contact_ipopt_solver_h

#include <deal.II/base/conditional_ostream.h>
#include <deal.II/base/timer.h>

#include <deal.II/fe/mapping.h>

#include <deal.II/lac/affine_constraints.h>

#include <tkr/contact/active_set_solver.h>
#include <tkr/elasticity/linear_elasticity.h>
#include <tkr/mortar/mortar_coupling.h>

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
  class IpoptSolver
  {
  public:
    IpoptSolver(Elasticity::LinearElasticity &elasticity,
                const Mortar::MortarCoupling &coupling,
                const double                  tolerance,
                const double                  slave_youngs_modulus,
                const MPI_Comm                mpi_communicator,
                dealii::TimerOutput          &timer);

    /**
     * Solve; the solution goes into @p elasticity, pressures, gaps and the
     * active set (nodes where lambda_j - c_j g_j > 0, as in the active-set
     * method) into @p state. Only on one MPI rank.
     */
    ContactStatistics
    solve(const dealii::Mapping<3>                &mapping,
          const dealii::AffineConstraints<double> &dirichlet,
          const Elasticity::BoundaryLoads         &loads,
          ContactState                            &state);

  private:
    Elasticity::LinearElasticity &elasticity;
    const Mortar::MortarCoupling &coupling;
    const double                  tolerance;
    const double                  slave_youngs_modulus;
    const MPI_Comm                mpi_communicator;
    dealii::TimerOutput          &timer;
  };
} // namespace TKR::Contact

#endif
