// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#include <tkr/wear/archard.h>

namespace TKR::Wear
{
  using namespace dealii;

  namespace
  {
    /** Tangential slip of node j over the interval a -> b from point X. */
    double
    slip_distance(const StepRecord   &a,
                  const StepRecord   &b,
                  const unsigned int  j,
                  const Point<3>     &X,
                  const Tensor<1, 3> &normal)
    {
      const Tensor<1, 3> relative = (b.femur_motion(X) - a.femur_motion(X)) -
                                    (b.displacement[j] - a.displacement[j]);
      return (relative - (relative * normal) * normal).norm();
    }
  } // namespace

  std::vector<double>
  interval_wear_depth(const StepRecord    &a,
                      const StepRecord    &b,
                      const double         k,
                      std::vector<double> *slip)
  {
    const unsigned int  n_nodes = a.pressure.size();
    std::vector<double> depth(n_nodes, 0.);
    if (slip)
      slip->assign(n_nodes, 0.);
    for (unsigned int j = 0; j < n_nodes; ++j)
      {
        const double s_a =
          a.pressure[j] > 0 ?
            slip_distance(a, b, j, a.femur_point[j], a.normal[j]) :
            0.;
        const double s_b =
          b.pressure[j] > 0 ?
            slip_distance(a, b, j, b.femur_point[j], b.normal[j]) :
            0.;
        depth[j] = 0.5 * k * (a.pressure[j] * s_a + b.pressure[j] * s_b);
        if (slip)
          (*slip)[j] = (a.pressure[j] > 0 && b.pressure[j] > 0) ?
                         0.5 * (s_a + s_b) :
                         std::max(s_a, s_b);
      }
    return depth;
  }

  std::vector<double>
  cycle_wear_depth(const std::vector<StepRecord> &steps,
                   const double                   k,
                   std::vector<double>           *slip)
  {
    const unsigned int  n_steps = steps.size();
    const unsigned int  n_nodes = n_steps > 0 ? steps[0].pressure.size() : 0;
    std::vector<double> depth(n_nodes, 0.), interval_slip;
    if (slip)
      slip->assign(n_nodes, 0.);
    for (unsigned int i = 0; i < n_steps; ++i)
      {
        const std::vector<double> increment =
          interval_wear_depth(steps[i],
                              steps[(i + 1) % n_steps],
                              k,
                              &interval_slip);
        for (unsigned int j = 0; j < n_nodes; ++j)
          {
            depth[j] += increment[j];
            if (slip)
              (*slip)[j] += interval_slip[j];
          }
      }
    return depth;
  }

  double
  worn_volume(const std::vector<double>    &depth,
              const Mortar::MortarCoupling &coupling)
  {
    double volume = 0;
    for (unsigned int j = 0; j < depth.size(); ++j)
      volume += depth[j] * coupling.slave_nodes()[j].D;
    return volume;
  }
} // namespace TKR::Wear
