// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#include <tkr/wear/step_record.h>

#include <algorithm>

namespace TKR::Wear
{
  using namespace dealii;

  StepRecord
  make_step_record(const Mortar::MortarCoupling &coupling,
                   const Contact::ContactState  &state,
                   const Gait::RelativeMotion   &motion)
  {
    const auto        &nodes = coupling.slave_nodes();
    const unsigned int n     = nodes.size();
    StepRecord         record;
    record.motion = motion;
    record.pressure.assign(n, 0.);
    record.femur_point.assign(n, Point<3>());
    record.displacement.assign(n, Tensor<1, 3>());
    record.normal.assign(n, Tensor<1, 3>());
    for (unsigned int j = 0; j < n; ++j)
      {
        record.normal[j] = nodes[j].normal;
        if (j < state.displacement.size())
          record.displacement[j] = state.displacement[j];
        if (j < state.active.size() && state.active[j])
          {
            record.pressure[j]    = std::max(0., state.pressure[j]);
            record.femur_point[j] = motion.inverse(nodes[j].master_point);
          }
      }
    return record;
  }
} // namespace TKR::Wear
