// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#ifndef tkr_contact_finite_difference_pose_h
#define tkr_contact_finite_difference_pose_h

#include <deal.II/fe/mapping.h>

#include <tkr/contact/contact_solver.h>
#include <tkr/contact/pose_newton.h>

namespace TKR::Contact
{
  /**
   * The derivatives of the pose equations of a PoseSystem by forward
   * differences of contact solves, for any contact solver (the AMG-CG
   * active set, and the condensed one where `Gait/Pose derivatives =
   * finite differences` checks its analytic ones): at a contact solution,
   * unknown k moved by 1e-3 mm as its equation measures it (a rotation at
   * the insert's rim), one contact solve each from the solution's active
   * set; a column whose solve fails takes the fixed-point model dr_k/dq_k
   * = -s_k (the pose moves by the displacement it observes). The loads
   * are the solver's load basis with the coefficients
   * system.load_coefficients().
   */
  class FiniteDifferencePose : public PoseDerivatives
  {
  public:
    FiniteDifferencePose(ContactSolver            &solver,
                         PoseSystem               &system,
                         const dealii::Mapping<3> &mapping,
                         const double              initial_distance);

    bool
    solve(Point &point, const bool couple) override;

    /** Costs n_unknowns() contact solves at the first call at a point. */
    bool
    newton_step(Point               &point,
                const double         damping,
                std::vector<double> &dq) override;

    bool
    newton_step_is_cheap() const override
    {
      return false;
    }

    /**
     * S^2: the same for every solver (the AMG-CG active set has no
     * compliance of the tray's rigid motions), so that the condensed and
     * the AMG-CG active set take the same iterates.
     */
    dealii::FullMatrix<double>
    metric() const override;

  private:
    /** The Jacobian dr/dq at a point. */
    struct Jacobian : Data
    {
      dealii::FullMatrix<double> matrix;
    };

    /** The Jacobian at @p point by forward differences. */
    dealii::FullMatrix<double>
    jacobian(const Point &point);

    ContactSolver            &solver;
    PoseSystem               &system;
    const dealii::Mapping<3> &mapping;
    const double              initial_distance;
  };
} // namespace TKR::Contact

#endif
