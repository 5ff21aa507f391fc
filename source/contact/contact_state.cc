// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#include <tkr/contact/contact_state.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace TKR::Contact
{
  using namespace dealii;

  unsigned int
  ContactState::n_active() const
  {
    return std::count(active.begin(), active.end(), true);
  }

  void
  add_contact_results(const Mortar::MortarCoupling &coupling,
                      const ContactState           &state,
                      ContactStatistics            &statistics)
  {
    const auto &nodes = coupling.slave_nodes();
    for (unsigned int j = 0; j < nodes.size(); ++j)
      if (state.active[j])
        {
          ++statistics.n_active;
          statistics.contact_area += nodes[j].D;
          const Tensor<1, 3> force =
            -state.pressure[j] * nodes[j].D * nodes[j].normal;
          statistics.contact_force += force;
          statistics.contact_moment +=
            cross_product_3d(nodes[j].master_point, force);
          statistics.max_pressure =
            std::max(statistics.max_pressure, state.pressure[j]);
        }
  }

  std::pair<double, unsigned int>
  smallest_gap(const Mortar::MortarCoupling &coupling)
  {
    const auto  &nodes   = coupling.slave_nodes();
    double       min_gap = std::numeric_limits<double>::infinity();
    unsigned int closest = numbers::invalid_unsigned_int;
    for (unsigned int j = 0; j < nodes.size(); ++j)
      if (nodes[j].covered && nodes[j].weighted_gap / nodes[j].D < min_gap)
        {
          min_gap = nodes[j].weighted_gap / nodes[j].D;
          closest = j;
        }
    return {min_gap, closest};
  }

  std::vector<bool>
  nodes_near_closest(const Mortar::MortarCoupling &coupling,
                     const double                  distance)
  {
    const auto  &nodes = coupling.slave_nodes();
    const double threshold =
      std::max(smallest_gap(coupling).first, 0.) + distance;
    std::vector<bool> near(nodes.size(), false);
    for (unsigned int j = 0; j < nodes.size(); ++j)
      near[j] =
        nodes[j].covered && nodes[j].weighted_gap <= threshold * nodes[j].D;
    return near;
  }

  void
  start_state(const Mortar::MortarCoupling &coupling,
              const double                  initial_distance,
              ContactState                 &state)
  {
    const auto        &nodes   = coupling.slave_nodes();
    const unsigned int n_slave = nodes.size();
    if (state.active.size() != n_slave || state.n_active() == 0)
      state.active = nodes_near_closest(coupling, initial_distance);
    else
      // A warm start from another geometry: only covered nodes may be
      // active.
      for (unsigned int j = 0; j < n_slave; ++j)
        state.active[j] = state.active[j] && nodes[j].covered;
    state.pressure.assign(n_slave, 0.);
    state.gap.assign(n_slave, std::numeric_limits<double>::quiet_NaN());
    state.displacement.assign(n_slave, Tensor<1, 3>());
  }

  ActiveSetUpdate::ActiveSetUpdate(const ConditionalOStream &pcout,
                                   const double slave_youngs_modulus)
    : pcout(pcout)
    , slave_youngs_modulus(slave_youngs_modulus)
  {}

  // The constant c_j = E / h_j makes the complementarity function
  // independent of units: lambda (MPa) and E g / h (MPa mm / mm).
  double
  ActiveSetUpdate::complementarity(const Mortar::SlaveNode &node,
                                   const double             pressure,
                                   const double             gap) const
  {
    return pressure - slave_youngs_modulus / std::sqrt(node.D) * gap;
  }

  unsigned int
  ActiveSetUpdate::next_set(const Mortar::MortarCoupling &coupling,
                            const ContactState           &state,
                            std::vector<bool>            &next,
                            std::vector<double>          &violation) const
  {
    const auto        &nodes   = coupling.slave_nodes();
    const unsigned int n_slave = nodes.size();
    next.assign(n_slave, false);
    violation.assign(n_slave, 0.);
    unsigned int n_changed = 0;
    for (unsigned int j = 0; j < n_slave; ++j)
      if (nodes[j].covered)
        {
          const double lambda = state.pressure[j], gap = state.gap[j];
          const double c = slave_youngs_modulus / std::sqrt(nodes[j].D);
          next[j]        = complementarity(nodes[j], lambda, gap) > 0;
          // How far the node is from satisfying its present status.
          violation[j] =
            state.active[j] ? std::max(0., -lambda) : std::max(0., -c * gap);
        }
    for (unsigned int j = 0; j < n_slave; ++j)
      n_changed += (next[j] != state.active[j]);
    return n_changed;
  }

  unsigned int
  ActiveSetUpdate::count_changes(const Mortar::MortarCoupling &coupling,
                                 const ContactState           &state) const
  {
    std::vector<bool>   next;
    std::vector<double> violation;
    return next_set(coupling, state, next, violation);
  }

  unsigned int
  ActiveSetUpdate::update(const Mortar::MortarCoupling &coupling,
                          ContactState                 &state)
  {
    std::vector<bool>   next;
    std::vector<double> violation;
    const unsigned int  n_changed = next_set(coupling, state, next, violation);
    if (n_changed == 0)
      return 0;

    history.push_back(state.active);
    if (std::find(history.begin(), history.end(), next) != history.end())
      {
        if (!damped)
          pcout << "    the active set cycles: damped updates from now on"
                << std::endl;
        damped = true;
      }
    if (damped)
      {
        const unsigned int worst =
          std::max_element(violation.begin(), violation.end()) -
          violation.begin();
        next        = state.active;
        next[worst] = !next[worst];
      }
    state.active = next;
    return n_changed;
  }
} // namespace TKR::Contact
