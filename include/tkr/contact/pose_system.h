// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#ifndef tkr_contact_pose_system_h
#define tkr_contact_pose_system_h

#include <deal.II/base/tensor.h>

#include <utility>
#include <vector>

namespace TKR::Contact
{
  /**
   * The rigid unknowns of a body held by contact (the tibial tray's pose,
   * a few numbers q), as the pose Newton (PoseNewton) and its derivatives
   * (PoseDerivatives) see them. The contact solver knows nothing of gaits: the
   * caller says how q moves the geometry, what it does to the loads, and
   * which observed functionals of the displacement must vanish at
   * equilibrium.
   *
   * The equations of the pose are r(u) = 0, r_p = s_p w_{i_p} . u, a scaled
   * selection of the solver's observations (e.g. the mean displacement of
   * the tibia's inferior surface relative to its pose: zero when the
   * applied loads and the restraint springs at q balance the contact's
   * resultant and moment, see doc/gait.md).
   */
  class PoseSystem
  {
  public:
    virtual ~PoseSystem() = default;

    /** The number m of pose unknowns. */
    virtual unsigned int
    n_unknowns() const = 0;

    /**
     * Recompute the contact solver's mortar coupling for the pose @p q (the
     * master body moved by the relative motion of q). Returns false if no
     * slave node is covered there.
     */
    virtual bool
    couple(const std::vector<double> &q) = 0;

    /** The coefficients of the solver's load basis at @p q. */
    virtual std::vector<double>
    load_coefficients(const std::vector<double> &q) const = 0;

    /**
     * The derivative with respect to q_k of the position of the master
     * material point that is at p (slave body's frame) at the pose @p q
     * (mm per unit of q_k): an affine field of p, returned as (L, v_0) with
     * dp/dq_k = L p + v_0 (the master body moves rigidly).
     */
    virtual std::pair<dealii::Tensor<2, 3>, dealii::Tensor<1, 3>>
    master_velocity(const std::vector<double> &q,
                    const unsigned int         k) const = 0;

    /**
     * The pose equations: per equation, the index of the observation and
     * its scale s_p (mm per unit of the observation).
     */
    virtual std::vector<std::pair<unsigned int, double>>
    residual_rows() const = 0;

    /**
     * Per unknown q_k, the index of the solver's load basis column of the
     * unit generalized force that q_k works against. The observations of
     * these columns, G_pk = s_p^-1 r_p(K^-1 f_k), are the compliance of the
     * tray's rigid motions (its restraint and stabilisation springs), and
     * G^-1 S^-1 r is the force the pose equations leave unbalanced: minus
     * the gradient of the potential energy of the step in the pose.
     */
    virtual std::vector<unsigned int>
    force_columns() const = 0;

    /** The size of a change @p dq of the pose, in mm (e.g. at the rim). */
    virtual double
    step_size(const std::vector<double> &dq) const = 0;
  };

  /** What a solve with the pose did. */
  struct PoseStatistics
  {
    /** Newton steps of the pose (PoseNewton). */
    unsigned int n_iterations = 0;
    /**
     * Contact solutions at a pose (the first one, the line search's and the
     * finite differences').
     */
    unsigned int n_solves = 0;
    /** Line search step cuts summed over the iterations. */
    unsigned int n_step_cuts = 0;
    /**
     * Steps taken at the line search's smallest step without a decrease of
     * the merit (the Newton direction did not describe the pose equations
     * there).
     */
    unsigned int n_stalled_steps = 0;
    /**
     * Directions that stayed not gradient related at the largest damping
     * and were replaced by the unbalanced displacement S^-1 r.
     */
    unsigned int n_descent_fallbacks = 0;
    /**
     * Newton matrices that were singular (no active node holds some pose
     * unknown, or with finite differences an unknown that moves no
     * observation) and were regularised.
     */
    unsigned int n_regularised = 0;
    /** The largest |r_p| (mm) of the final solve. */
    double residual = 0;
    /**
     * The pose unknowns one more Newton step on from the converged ones
     * (without a contact solve): a closer estimate of the solution than the
     * accepted pose, whose residual may be up to the tolerance, for
     * predicting the step's pose in the next block (empty if the solve did
     * not converge).
     */
    std::vector<double> refined;
    /** The pose equations hold within the tolerance. */
    bool converged = false;
  };
} // namespace TKR::Contact

#endif
