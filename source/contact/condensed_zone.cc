// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.
//
// CondensedActiveSetSolver: the contact zone, the stored columns gathered
// and summed on it, and W_AA on it.

#include <tkr/contact/condensed_solver.h>

#include <algorithm>

#include "term_sum.h"

namespace TKR::Contact
{
  using namespace dealii;

  __attribute__((target_clones("avx2", "default"),
                 optimize("vect-cost-model=dynamic"))) void
  add_terms(double *__restrict target,
            const double *const *g,
            const double        *v,
            const unsigned int   n_terms,
            const unsigned int   n)
  {
    const double *__restrict g0 = g[0];
    const double v0             = v[0];
    switch (n_terms)
      {
        case 1:
          for (unsigned int k = 0; k < n; ++k)
            target[k] += v0 * g0[k];
          break;
        case 2:
          {
            const double *__restrict g1 = g[1];
            const double v1             = v[1];
            for (unsigned int k = 0; k < n; ++k)
              target[k] = (target[k] + v0 * g0[k]) + v1 * g1[k];
            break;
          }
        case 3:
          {
            const double *__restrict g1 = g[1], *__restrict g2 = g[2];
            const double v1 = v[1], v2 = v[2];
            for (unsigned int k = 0; k < n; ++k)
              target[k] = ((target[k] + v0 * g0[k]) + v1 * g1[k]) + v2 * g2[k];
            break;
          }
        default:
          {
            Assert(n_terms == 4, ExcInternalError());
            const double *__restrict g1 = g[1], *__restrict g2 = g[2],
                                     *__restrict g3 = g[3];
            const double v1 = v[1], v2 = v[2], v3 = v[3];
            for (unsigned int k = 0; k < n; ++k)
              target[k] =
                (((target[k] + v0 * g0[k]) + v1 * g1[k]) + v2 * g2[k]) +
                v3 * g3[k];
          }
      }
  }


  // The contact zone: the surface values that the rows of covered nodes
  // reference (compact index k, surface value zone[k]), and those rows on
  // it.
  CondensedActiveSetSolver::Zone
  CondensedActiveSetSolver::make_zone(const Mortar::MortarOperator &B,
                                      const std::vector<double>    &u0) const
  {
    const auto        &nodes   = coupling.slave_nodes();
    const unsigned int n_slave = nodes.size();
    Zone               zone;
    // The referenced values in increasing order, and their compact
    // indices, through a table over all surface values.
    constexpr unsigned int    unused = numbers::invalid_unsigned_int;
    std::vector<unsigned int> compact(surface_dofs.size(), unused);
    for (unsigned int j = 0; j < n_slave; ++j)
      if (nodes[j].covered)
        for (auto e = B.begin(j); e != B.end(j); ++e)
          compact[e->column] = 0;
    auto &values = zone.values;
    for (unsigned int c = 0; c < compact.size(); ++c)
      if (compact[c] != unused)
        {
          compact[c] = values.size();
          values.push_back(c);
        }
    zone.n_slave =
      std::lower_bound(values.begin(), values.end(), n_slave_values) -
      values.begin();
    zone.rows.resize(n_slave);
    for (unsigned int j = 0; j < n_slave; ++j)
      if (nodes[j].covered)
        for (auto e = B.begin(j); e != B.end(j); ++e)
          zone.rows[j].push_back({compact[e->column], e->value});
    if (last_gathered != nullptr && values == last_zone_values)
      zone.gathered = last_gathered;
    else
      {
        zone.gathered    = std::make_shared<Zone::Gathered>();
        last_zone_values = values;
        last_gathered    = zone.gathered;
      }
    zone.u0.resize(values.size());
    for (unsigned int k = 0; k < values.size(); ++k)
      zone.u0[k] = u0[values[k]];
    return zone;
  }

  double
  CondensedActiveSetSolver::Zone::apply(const unsigned int         j,
                                        const std::vector<double> &v) const
  {
    double result = 0;
    for (const auto &e : rows[j])
      result += e.value * v[e.column];
    return result;
  }

  // With the columns' values at the zone values that the active rows
  // reference laid out row by row (Z_A^T on them), each row of W_AA is a
  // sum of those rows, in the order of the row's entries.
  std::vector<double>
  CondensedActiveSetSolver::Zone::delassus(
    const std::vector<unsigned int> &active,
    const std::vector<Column>       &z) const
  {
    const unsigned int  n_active = active.size();
    std::vector<int>    slot(values.size(), -1);
    std::vector<double> z_transposed;
    unsigned int        n_slots = 0;
    for (const unsigned int j : active)
      for (const auto &e : rows[j])
        if (slot[e.column] < 0)
          {
            slot[e.column] = n_slots++;
            for (const unsigned int i : active)
              z_transposed.push_back(z[i].surface[e.column]);
          }
    std::vector<double> W(n_active * n_active, 0.);
    for (unsigned int a = 0; a < n_active; ++a)
      {
        TermSum sum(W.data() + a * n_active, n_active);
        for (const auto &e : rows[active[a]])
          sum.add(e.value, z_transposed.data() + slot[e.column] * n_active);
      }
    return W;
  }

  // z_i = sum_c B_ic K^{-1} e_c on the zone: a slave column on the zone's
  // slave values, a master one on its master values.
  CondensedActiveSetSolver::Column
  CondensedActiveSetSolver::zone_column(const Mortar::MortarOperator &B,
                                        const Zone                   &zone,
                                        const unsigned int            i) const
  {
    const unsigned int n_observations = observation_weights.size();
    const unsigned int n_zone         = zone.values.size();
    Column             z;
    z.surface.assign(n_zone, 0.);
    z.observations.assign(n_observations, 0.);
    // The row's slave entries come first, then its master ones: a sum per
    // body.
    TermSum slave_sum(z.surface.data(), zone.n_slave);
    TermSum master_sum(z.surface.data() + zone.n_slave, n_zone - zone.n_slave);
    for (auto e = B.begin(i); e != B.end(i); ++e)
      {
        const Column      &column = node_columns[e->column / 3][e->column % 3];
        const bool         is_slave = e->column < n_slave_values;
        const unsigned int first    = is_slave ? 0 : zone.n_slave;
        const unsigned int last     = is_slave ? zone.n_slave : n_zone;
        const unsigned int offset   = is_slave ? 0 : n_slave_values;
        auto               found    = zone.gathered->find(e->column);
        if (found == zone.gathered->end())
          {
            // the node's three columns at once (the row has all three)
            const unsigned int            node = e->column / 3;
            std::array<double *, 3>       g{};
            std::array<const double *, 3> stored{};
            unsigned int                  n_new = 0;
            for (unsigned int d = 0; d < 3; ++d)
              if (!node_columns[node][d].surface.empty())
                {
                  auto &target = (*zone.gathered)[3 * node + d] =
                    std::unique_ptr<double[]>(new double[last - first]);
                  g[n_new]      = target.get();
                  stored[n_new] = node_columns[node][d].surface.data();
                  ++n_new;
                }
            const unsigned int *values = zone.values.data();
            for (unsigned int k = first; k < last; ++k)
              {
                const unsigned int v = values[k] - offset;
                for (unsigned int d = 0; d < n_new; ++d)
                  g[d][k - first] = stored[d][v];
              }
            found = zone.gathered->find(e->column);
          }
        // (the two sums write apart: their order does not matter)
        (is_slave ? slave_sum : master_sum).add(e->value, found->second.get());
        for (unsigned int o = 0; o < n_observations; ++o)
          z.observations[o] += e->value * column.observations[o];
      }
    slave_sum.flush();
    master_sum.flush();
    return z;
  }

} // namespace TKR::Contact
