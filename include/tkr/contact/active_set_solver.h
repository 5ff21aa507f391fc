// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#ifndef tkr_contact_active_set_solver_h
#define tkr_contact_active_set_solver_h

#include <deal.II/base/conditional_ostream.h>
#include <deal.II/base/timer.h>

#include <deal.II/fe/mapping.h>

#include <deal.II/lac/affine_constraints.h>

#include <tkr/elasticity/linear_elasticity.h>
#include <tkr/mortar/mortar_coupling.h>
#include <tkr/parameters/parameters.h>

#include <vector>

namespace TKR::Contact
{
  /**
   * The state of the contact surface (per slave node): the active set and,
   * after a solve, the contact pressure (the multiplier lambda_j, MPa,
   * positive in compression) and the gap after deformation (mm).
   */
  struct ContactState
  {
    std::vector<bool>   active;
    std::vector<double> pressure;
    std::vector<double> gap;
    /** Displacement of each slave node (mm, global frame). */
    std::vector<dealii::Tensor<1, 3>> displacement;

    /** Number of active nodes. */
    unsigned int
    n_active() const;
  };

  /** What a contact solve did. */
  struct ContactStatistics
  {
    bool         converged         = false;
    unsigned int newton_iterations = 0;
    unsigned int linear_iterations = 0;
    double       relative_residual = 0;
    unsigned int n_active          = 0;
    /** Sum of D_jj over active nodes (mm^2). */
    double contact_area = 0;
    /** Resultant of the contact forces on the slave body (N). */
    dealii::Tensor<1, 3> contact_force;
    double               max_pressure = 0;
  };

  /**
   * The DoFs of the contact surfaces, three per slave node and then three
   * per master node: the layout of the surface values that both active-set
   * solvers work with.
   */
  std::vector<dealii::types::global_dof_index>
  surface_dof_indices(const Mortar::MortarCoupling &coupling);

  /**
   * The mortar operator of slave node @p j applied to surface values in
   * that layout, B_j v = D_jj n_j . v_j - n^m_j . sum_k M_jk v^m_k: by how
   * much a displacement v closes the node's weighted gap.
   */
  double
  apply_mortar_operator(const Mortar::MortarCoupling &coupling,
                        const unsigned int            j,
                        const double                 *slave_values,
                        const double                 *master_values);

  /**
   * The covered slave nodes whose initial (weighted) gap exceeds the
   * smallest one by at most @p distance mm: the initial active set when
   * there is no warm start (for a body held only by contact this closes
   * the smallest gap first).
   */
  std::vector<bool>
  nodes_near_closest(const Mortar::MortarCoupling &coupling,
                     const double                  distance);

  /**
   * The state a contact solve starts from: the active set of @p state if
   * it has one (restricted to covered nodes, a warm start), else the nodes
   * near the closest (nodes_near_closest()); pressures and displacements
   * zero, gaps unknown.
   */
  void
  start_state(const Mortar::MortarCoupling &coupling,
              const double                  initial_distance,
              ContactState                 &state);

  /**
   * The active-set update both active-set solvers share. Node j is active
   * next when lambda_j - c_j g_j > 0, with c_j = E / h_j (h_j =
   * sqrt(D_jj)). A set seen before means the iteration cycles: from then on
   * only the node that violates its status most changes per update.
   */
  class ActiveSetUpdate
  {
  public:
    ActiveSetUpdate(const dealii::ConditionalOStream &pcout,
                    const double                      slave_youngs_modulus);

    /**
     * Set the next active set in @p state from its pressures and gaps;
     * returns how many nodes changed status (before any damping).
     */
    unsigned int
    update(const Mortar::MortarCoupling &coupling, ContactState &state);

    /** How many nodes update() would change. */
    unsigned int
    count_changes(const Mortar::MortarCoupling &coupling,
                  const ContactState           &state) const;

    /** Forget the sets seen so far (after the set was changed otherwise). */
    void
    clear_history()
    {
      history.clear();
    }

  private:
    /** The next set and each node's violation of its present status. */
    unsigned int
    next_set(const Mortar::MortarCoupling &coupling,
             const ContactState           &state,
             std::vector<bool>            &next,
             std::vector<double>          &violation) const;

    const dealii::ConditionalOStream &pcout;
    const double                      slave_youngs_modulus;
    std::vector<std::vector<bool>>    history;
    bool                              damped = false;
  };

  /**
   * Active nodes, contact area (sum of their D_jj), contact force on the
   * slave body and peak pressure of @p state, into @p statistics.
   */
  void
  add_contact_results(const Mortar::MortarCoupling &coupling,
                      const ContactState           &state,
                      ContactStatistics            &statistics);

  /**
   * Primal-dual active set method (semismooth Newton, Hueber & Wohlmuth)
   * for frictionless mortar contact between the two linear-elastic bodies
   * (DESIGN.md section 4.4).
   *
   * On an active slave node j the condition
   * n_j . (sum_k M_jk u_k - D_jj u_j) = -g_j becomes one AffineConstraints
   * line on the node's dominant normal component. The condensed system is
   * solved by CG with ML AMG; the multiplier follows from the residual of
   * the unconstrained system, lambda_j = r_j . n_j / D_jj; the active set is
   * updated with the complementarity function lambda_j - c_j g_j(u) with
   * c_j = E_slave / h_j, which makes the update independent of units.
   * Converged when the active set does not change and the linear solve met
   * the tolerance. Repeating active sets (cycles) are detected; the next
   * update then changes only the most violated node.
   */
  class ActiveSetSolver
  {
  public:
    ActiveSetSolver(Elasticity::LinearElasticity     &elasticity,
                    const Mortar::MortarCoupling     &coupling,
                    const Parameters::ContactSolver  &parameters,
                    const double                      slave_youngs_modulus,
                    const MPI_Comm                    mpi_communicator,
                    const dealii::ConditionalOStream &pcout,
                    dealii::TimerOutput              &timer,
                    const bool                        testing);

    /**
     * Set up the sparsity pattern for the current coupling (all covered
     * slave nodes may become active) and the Dirichlet @p dirichlet
     * constraints. Call after every MortarCoupling::reinit().
     */
    void
    setup(const dealii::AffineConstraints<double> &dirichlet);

    /**
     * Solve the contact problem. @p state holds the initial active set (an
     * empty vector: the nodes whose gap exceeds the smallest gap by at most
     * @p initial_distance mm) and returns the final state.
     */
    ContactStatistics
    solve(const dealii::Mapping<3>        &mapping,
          const Elasticity::BoundaryLoads &loads,
          const double                     initial_distance,
          ContactState                    &state);

  private:
    void
    make_constraints(const std::vector<bool>           &active,
                     dealii::AffineConstraints<double> &constraints) const;

    /** Values of a distributed vector at the surface DoFs, on all ranks. */
    std::vector<double>
    gather(const dealii::TrilinosWrappers::MPI::Vector &vector) const;

    Elasticity::LinearElasticity    &elasticity;
    const Mortar::MortarCoupling    &coupling;
    const Parameters::ContactSolver  parameters;
    const double                     slave_youngs_modulus;
    const MPI_Comm                   mpi_communicator;
    const dealii::ConditionalOStream pcout;
    dealii::TimerOutput             &timer;
    const bool                       testing;

    dealii::AffineConstraints<double> dirichlet;
    /** Slave node DoFs (3 per node) followed by master node DoFs. */
    std::vector<dealii::types::global_dof_index> surface_dofs;
  };
} // namespace TKR::Contact

#endif
