// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

// A gait step's pose (GaitCycle::solve_pose()): the protocol's pose
// unknowns as a Contact::PoseSystem, solved by Contact::PoseNewton.

#include <deal.II/lac/full_matrix.h>

#include <tkr/base/exceptions.h>
#include <tkr/contact/finite_difference_pose.h>
#include <tkr/contact/pose_newton.h>
#include <tkr/problems/gait_cycle.h>

#include <algorithm>
#include <cmath>
#include <functional>

namespace TKR::Problems
{
  using namespace dealii;

  namespace
  {
    /**
     * The pose unknowns of a protocol in one step (Gait::PoseEquations) as
     * the contact solver sees them: q are the unknown values of the
     * protocol's Pose, the others follow from them.
     */
    class StepPoseSystem : public Contact::PoseSystem
    {
    public:
      StepPoseSystem(
        const Gait::Protocol                             &protocol,
        const Gait::PoseEquations                        &equations,
        const Gait::StepInput                            &input,
        const Gait::Pose                                 &start,
        const std::vector<std::string>                   &observation_names,
        std::function<bool(const Gait::RelativeMotion &)> couple_at)
        : protocol(protocol)
        , input(input)
        , start(start)
        , equations(equations)
        , couple_at(std::move(couple_at))
      {
        for (const auto &[name, scale] : equations.residuals)
          {
            const auto it = std::find(observation_names.begin(),
                                      observation_names.end(),
                                      name);
            Assert(it != observation_names.end(), ExcInternalError());
            rows.emplace_back(it - observation_names.begin(), scale);
          }
        AssertDimension(rows.size(), equations.unknowns.size());
        AssertDimension(equations.forces.size(), equations.unknowns.size());
      }

      /** The protocol's pose for the unknowns @p q. */
      Gait::Pose
      pose(const std::vector<double> &q) const
      {
        Gait::Pose pose = start;
        for (unsigned int k = 0; k < q.size(); ++k)
          pose.values[equations.unknowns[k]] = q[k];
        equations.complete(pose);
        return pose;
      }

      /** The unknowns of @p pose. */
      std::vector<double>
      unknowns(const Gait::Pose &pose) const
      {
        std::vector<double> q;
        for (const unsigned int i : equations.unknowns)
          q.push_back(pose.values[i]);
        return q;
      }

      unsigned int
      n_unknowns() const override
      {
        return equations.unknowns.size();
      }

      bool
      couple(const std::vector<double> &q) override
      {
        return couple_at(protocol.motion(input, pose(q)));
      }

      std::vector<double>
      load_coefficients(const std::vector<double> &q) const override
      {
        return protocol.load_coefficients(input, pose(q));
      }

      // The master point p belongs to the femur's material point X =
      // M_q^{-1}(p); its velocity along q_k is the central difference of
      // M_{q +- h e_k}(X), an affine function of p (rigid motions).
      std::pair<Tensor<2, 3>, Tensor<1, 3>>
      master_velocity(const std::vector<double> &q,
                      const unsigned int         k) const override
      {
        const double        h    = 1e-5;
        std::vector<double> plus = q, minus = q;
        plus[k] += h;
        minus[k] -= h;
        const Gait::RelativeMotion at   = protocol.motion(input, pose(q));
        const Gait::RelativeMotion up   = protocol.motion(input, pose(plus));
        const Gait::RelativeMotion down = protocol.motion(input, pose(minus));
        const auto                 velocity = [&](const Point<3> &p) {
          const Point<3> X = at.inverse(p);
          return Tensor<1, 3>((up(X) - down(X)) / (2 * h));
        };
        const Tensor<1, 3> v0 = velocity(Point<3>());
        Tensor<2, 3>       L;
        for (unsigned int c = 0; c < 3; ++c)
          {
            Point<3> unit;
            unit[c]                   = 1.;
            const Tensor<1, 3> column = velocity(unit) - v0;
            for (unsigned int i = 0; i < 3; ++i)
              L[i][c] = column[i];
          }
        return {L, v0};
      }

      std::vector<std::pair<unsigned int, double>>
      residual_rows() const override
      {
        return rows;
      }

      std::vector<unsigned int>
      force_columns() const override
      {
        return equations.forces;
      }

      // Each unknown in mm, as its equation measures it (a rotation at the
      // insert's rim).
      double
      step_size(const std::vector<double> &dq) const override
      {
        double size = 0;
        for (unsigned int k = 0; k < dq.size(); ++k)
          size = std::max(size, std::abs(dq[k]) * rows[k].second);
        return size;
      }

    private:
      const Gait::Protocol                             &protocol;
      const Gait::StepInput                            &input;
      const Gait::Pose                                  start;
      const Gait::PoseEquations                        &equations;
      std::function<bool(const Gait::RelativeMotion &)> couple_at;
      std::vector<std::pair<unsigned int, double>>      rows;
    };
  } // namespace

  // Contact::PoseNewton on the protocol's pose equations, with the
  // solver's analytic derivatives where it has them and the entry asks for
  // them, else by finite differences.
  Gait::PoseSolve
  GaitCycle::solve_pose(const unsigned int     step,
                        const Gait::StepInput &input,
                        Gait::Pose            &pose,
                        StepProgress          &progress)
  {
    const auto &parameters = model.parameters();
    bool        narrow     = progress.use_window;
    const auto  couple_at  = [&](const Gait::RelativeMotion &motion) {
      couple(motion, narrow ? &progress.window : nullptr);
      if (narrow && model.coupling().statistics().n_covered_nodes == 0)
        couple(motion, nullptr);
      return model.coupling().statistics().n_covered_nodes > 0;
    };
    StepPoseSystem system(*protocol,
                          pose_equations,
                          input,
                          pose,
                          observation_names,
                          couple_at);
    const double distance = parameters.contact_solver.initial_contact_distance;
    std::unique_ptr<Contact::PoseDerivatives> derivatives;
    if (gait.analytic_pose_derivatives)
      derivatives = solver->pose_derivatives(system, distance);
    if (!derivatives)
      derivatives =
        std::make_unique<Contact::FiniteDifferencePose>(*solver,
                                                        system,
                                                        model.mapping(),
                                                        distance);
    Contact::PoseNewton         newton(system, *derivatives);
    const Contact::ContactState start = progress.state;
    Contact::PoseStatistics     statistics;
    unsigned int                fallbacks = 0;
    for (;;)
      {
        std::vector<double> q = system.unknowns(pose);
        system.couple(q);
        check_coupling(step);
        progress.state      = start;
        progress.statistics = newton.solve(q,
                                           gait.pose_tolerance,
                                           max_pose_iterations,
                                           progress.state,
                                           statistics);
        progress.n_solves += statistics.n_solves;
        fallbacks +=
          statistics.n_descent_fallbacks + statistics.n_stalled_steps;
        progress.newton_iterations += progress.statistics.newton_iterations;
        if (narrow &&
            !model.coupling().window_holds(progress.state.displacement,
                                           progress.state.master_displacement))
          {
            ++window_misses;
            narrow = false;
            continue;
          }
        pose = system.pose(q);
        if (!statistics.refined.empty())
          progress.refined = system.pose(statistics.refined);
        break;
      }
    finish_solve(progress);
    return {statistics.n_iterations,
            statistics.converged,
            statistics.residual,
            fallbacks};
  }

} // namespace TKR::Problems
