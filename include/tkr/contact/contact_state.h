// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#ifndef tkr_contact_contact_state_h
#define tkr_contact_contact_state_h

#include <deal.II/base/conditional_ostream.h>
#include <deal.II/base/tensor.h>

#include <tkr/mortar/mortar_operator.h>

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
    /**
     * The largest displacement of a master node (mm), or a bound of it
     * (the condensed active set, which does not compute the master
     * surface's displacement).
     */
    double master_displacement = 0;

    /** Number of active nodes. */
    unsigned int
    n_active() const;
  };

  /** What a contact solve did. */
  struct ContactStatistics
  {
    bool         converged         = false;
    unsigned int newton_iterations = 0;
    /** CG iterations summed over the Newton steps (AMG-CG active set). */
    unsigned int cg_iterations = 0;
    /** Columns K^{-1} e computed by this solve (condensed active set). */
    unsigned int computed_columns = 0;
    /**
     * Relative residual of the last linear solve (CG), or of the back
     * substitution (direct solvers).
     */
    double       relative_residual = 0;
    unsigned int n_active          = 0;
    /** Sum of D_jj over active nodes (mm^2). */
    double contact_area = 0;
    /** Resultant of the contact forces on the slave body (N). */
    dealii::Tensor<1, 3> contact_force;
    /**
     * Their moment (N mm) about the origin of the slave body's frame, each
     * nodal force acting at the master point the node touches.
     */
    dealii::Tensor<1, 3> contact_moment;
    double               max_pressure = 0;
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
   * The smallest initial gap (mm, g_j / D_jj) over the covered slave nodes
   * and the node where it is; the node is numbers::invalid_unsigned_int
   * (and the gap +infinity) if no node is covered.
   */
  std::pair<double, unsigned int>
  smallest_gap(const Mortar::MortarCoupling &coupling);

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

    /**
     * The complementarity function lambda_j - c_j g_j of node @p j
     * (positive: active next).
     */
    double
    complementarity(const Mortar::SlaveNode &node,
                    const double             pressure,
                    const double             gap) const;

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
} // namespace TKR::Contact

#endif
