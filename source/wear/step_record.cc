// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#include <tkr/wear/step_record.h>

#include <algorithm>

namespace TKR::Wear
{
  using namespace dealii;

  StepRecord::ArraySizes
  StepRecord::pack_arrays(std::vector<double> &values) const
  {
    values.insert(values.end(), pressure.begin(), pressure.end());
    const auto add = [&values](const auto &vectors) {
      for (const auto &v : vectors)
        for (unsigned int d = 0; d < 3; ++d)
          values.push_back(v[d]);
    };
    add(femur_point);
    add(displacement);
    add(normal);
    return {{static_cast<unsigned int>(pressure.size()),
             static_cast<unsigned int>(femur_point.size()),
             static_cast<unsigned int>(displacement.size()),
             static_cast<unsigned int>(normal.size())}};
  }

  void
  StepRecord::unpack_arrays(const ArraySizes          &sizes,
                            const std::vector<double> &values,
                            std::size_t               &position)
  {
    const double *v = values.data() + position;
    pressure.assign(v, v + sizes[0]);
    v += sizes[0];
    const auto read = [&v](auto &vectors, const unsigned int n) {
      vectors.resize(n);
      for (auto &vector : vectors)
        for (unsigned int d = 0; d < 3; ++d)
          vector[d] = *v++;
    };
    read(femur_point, sizes[1]);
    read(displacement, sizes[2]);
    read(normal, sizes[3]);
    position = v - values.data();
  }

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
