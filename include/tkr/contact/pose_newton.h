// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#ifndef tkr_contact_pose_newton_h
#define tkr_contact_pose_newton_h

#include <deal.II/lac/full_matrix.h>

#include <tkr/contact/contact_state.h>
#include <tkr/contact/pose_system.h>

#include <memory>
#include <vector>

namespace TKR::Contact
{
  /**
   * What the pose Newton (PoseNewton) needs of a contact solver: contact
   * solutions at given poses, and the Newton step of the pose equations at
   * one of them. Two providers: CondensedActiveSetSolver::
   * pose_derivatives() (analytic: the multipliers and the pose linearised
   * together, from the compliance columns) and FiniteDifferencePose (any
   * contact solver: forward differences of contact solves, one per pose
   * unknown).
   */
  class PoseDerivatives
  {
  public:
    /** What a provider keeps of a contact solution at a pose. */
    struct Data
    {
      virtual ~Data() = default;
    };

    /** A contact solution at a pose. */
    struct Point
    {
      /** The pose unknowns. */
      std::vector<double> q;
      /** The pose residual r_p = s_p w_{i_p} . u (mm). */
      std::vector<double> residual;
      /** The contact state and statistics of the solution. */
      ContactState      state;
      ContactStatistics statistics;
      /** The provider's own (its Newton system, for one). */
      std::shared_ptr<Data> data;
    };

    virtual ~PoseDerivatives() = default;

    /**
     * The contact solution at the pose @p point.q from the active set of
     * @p point.state: the mortar coupling there first if @p couple (else the
     * current coupling must be that of the pose), then the solve. Returns
     * false if no slave node is covered there (nothing else of @p point is
     * set then). Counts the solve in n_solves and its iterations in
     * newton_iterations.
     */
    virtual bool
    solve(Point &point, const bool couple) = 0;

    /**
     * The pose part @p dq of the Newton step at @p point (whose coupling
     * must be the current one), with @p damping (Levenberg-Marquardt: mu S
     * subtracted from the pose rows' diagonal, dq scaled by 1 + mu, so that
     * it goes from the Newton step at mu = 0 to S^-1 r as mu grows). False
     * if the matrix is (nearly) singular.
     */
    virtual bool
    newton_step(Point               &point,
                const double         damping,
                std::vector<double> &dq) = 0;

    /**
     * Whether a Newton step costs no contact solve (then the converged pose
     * gets PoseStatistics::refined).
     */
    virtual bool
    newton_step_is_cheap() const = 0;

    /**
     * The metric M of the line search and of the descent test (positive
     * definite): the analytic derivatives use the stiffness G^-1 of the
     * tray's rigid motions against the pose unknowns' unit forces (then
     * the line search's merit is the step's potential energy), the finite
     * differences S^2 (each unknown in mm as its equation measures it).
     */
    virtual dealii::FullMatrix<double>
    metric() const = 0;

    /** Contact solves since the provider was made. */
    unsigned int n_solves = 0;
    /** Their active set iterations. */
    unsigned int newton_iterations = 0;
  };

  /**
   * Newton's method on the pose equations r(q) = 0 of a PoseSystem, each
   * r(q) from a contact solution at the pose q, the Newton steps from a
   * PoseDerivatives (doc/gait.md, "The pose Newton"): at the current
   * contact solution the Newton step (damped until it is gradient related
   * in the metric), then a line search along it on contact solutions at
   * the trial poses, until every |r_p| <= tolerance.
   */
  class PoseNewton
  {
  public:
    PoseNewton(PoseSystem &system, PoseDerivatives &derivatives);

    /**
     * Solve from the pose @p q (updated; the coupling must be that of @p q
     * on entry), the contact from the active set of @p state (returned: the
     * last contact solution's), at most @p max_iterations Newton steps.
     * Returns the last contact solution's statistics with the active set
     * iterations of every solve.
     */
    ContactStatistics
    solve(std::vector<double> &q,
          const double         tolerance,
          const unsigned int   max_iterations,
          ContactState        &state,
          PoseStatistics      &statistics);

  private:
    using Point = PoseDerivatives::Point;

    /** The largest |r_p| of @p point. */
    static double
    largest(const Point &point);

    /** The slope of the line search's merit along @p dq at @p point. */
    double
    slope(const Point &point, const std::vector<double> &dq) const;

    /**
     * The search direction at @p point: its Newton step, damped until it is
     * gradient related in the metric.
     */
    std::vector<double>
    search_direction(Point &point, PoseStatistics &statistics);

    /** What a line search found. */
    struct Step
    {
      /** accepted: the strong Wolfe condition holds; lowered: not, but
       *  the bracket's lower end lowers the merit; stuck: neither. */
      enum Outcome
      {
        accepted,
        lowered,
        stuck
      } outcome = stuck;
      Point point;
    };

    /** The line search along @p dq from @p start. */
    Step
    line_search(const Point               &start,
                const std::vector<double> &dq,
                PoseStatistics            &statistics);

    PoseSystem                                        &system;
    PoseDerivatives                                   &derivatives;
    const dealii::FullMatrix<double>                   stiffness;
    const std::vector<std::pair<unsigned int, double>> rows;
  };
} // namespace TKR::Contact

#endif
