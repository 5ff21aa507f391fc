// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#include <tkr/mortar/mortar_operator.h>

namespace TKR::Mortar
{
  std::vector<dealii::types::global_dof_index>
  surface_dof_indices(const MortarCoupling &coupling)
  {
    std::vector<dealii::types::global_dof_index> dofs;
    for (const auto *surface :
         {&coupling.slave_surface(), &coupling.master_surface()})
      for (const auto &node : surface->nodes())
        dofs.insert(dofs.end(), node.dofs.begin(), node.dofs.end());
    return dofs;
  }

  MortarOperator::MortarOperator(const MortarCoupling &coupling)
    : coupling(coupling)
    , dofs(surface_dof_indices(coupling))
  {
    n_slave_values = 3 * coupling.slave_surface().nodes().size();

    // Row j: D_jj n_j on slave node j, -M_jk n^m_j on master node k
    // (components with a zero coefficient left out).
    const auto &nodes = coupling.slave_nodes();
    row_start.reserve(nodes.size() + 1);
    row_start.push_back(0);
    for (unsigned int j = 0; j < nodes.size(); ++j)
      {
        const auto &node = nodes[j];
        for (unsigned int e = 0; e < 3; ++e)
          if (node.normal[e] != 0.)
            entries.push_back({3 * j + e, node.D * node.normal[e]});
        for (const auto &[k, M] : node.M)
          for (unsigned int e = 0; e < 3; ++e)
            if (M * node.master_normal[e] != 0.)
              entries.push_back(
                {n_slave_values + 3 * k + e, -M * node.master_normal[e]});
        row_start.push_back(entries.size());
      }
  }

  double
  MortarOperator::apply_row(const unsigned int j, const double *v) const
  {
    double result = 0;
    for (const Entry *e = begin(j); e != end(j); ++e)
      result += e->value * v[e->column];
    return result;
  }

  double
  MortarOperator::gap(const unsigned int j, const double *u) const
  {
    const auto &node = coupling.slave_nodes()[j];
    return (node.weighted_gap - apply_row(j, u)) / node.D;
  }

  void
  MortarOperator::add_row_transpose(const unsigned int j,
                                    const double       factor,
                                    double            *v) const
  {
    for (const Entry *e = begin(j); e != end(j); ++e)
      v[e->column] += factor * e->value;
  }
} // namespace TKR::Mortar
