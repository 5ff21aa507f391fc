// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#include <deal.II/base/timer.h>

#include <tkr/base/exceptions.h>
#include <tkr/contact/ipopt_qp_loader.h>
#include <tkr/contact/ipopt_solver.h>
#include <tkr/elasticity/elastic_system.h>

#include <cmath>
#include <limits>
#include <memory>

namespace TKR::Contact
{
  using namespace dealii;


  ContactStatistics
  IpoptSolver::solve(const Mapping<3>                &mapping,
                     const Elasticity::BoundaryLoads &loads,
                     const double,
                     ContactState &state)
  {
    AssertThrow(Utilities::MPI::n_mpi_processes(mpi_communicator) == 1,
                ExcInputError("Contact solver/Solver = ipopt (and the Ipopt "
                              "cross-check) run on one MPI rank only."));
    TimerOutput::Scope           scope(timer, "Ipopt solve");
    const Mortar::MortarOperator B(coupling);
    std::vector<unsigned int>    row_of_node;
    const auto qp = make_program(mapping, loads, B, row_of_node);

    solve_with_ipopt(*qp, 1e-2 * parameters.tolerance, 500);

    // The solution and the contact state.
    const unsigned int            n = elasticity.get_dof_handler().n_dofs();
    TrilinosWrappers::MPI::Vector u(elasticity.locally_owned_dofs(),
                                    mpi_communicator);
    for (unsigned int i = 0; i < n; ++i)
      u[i] = qp->x_solution.empty() ? 0. : qp->x_solution[i];
    u.compress(VectorOperation::insert);
    solution = elasticity.make_ghosted_vector();
    solution = u;

    ContactStatistics statistics;
    statistics.converged         = qp->converged();
    statistics.newton_iterations = qp->iterations;
    read_state(*qp, B, row_of_node, state);
    add_contact_results(coupling, state, statistics);
    return statistics;
  }

  // The unconstrained stiffness matrix and load vector; Dirichlet values as
  // fixed bounds; one linear inequality per covered slave node,
  // g_j - B_j u >= 0 (its row in @p row_of_node).
  std::unique_ptr<QuadraticProgram>
  IpoptSolver::make_program(const Mapping<3>                &mapping,
                            const Elasticity::BoundaryLoads &loads,
                            const Mortar::MortarOperator    &B,
                            std::vector<unsigned int>       &row_of_node) const
  {
    const AffineConstraints<double> none;
    Elasticity::ElasticSystem       system(elasticity);
    system.setup(none);
    system.assemble(mapping, none, loads);
    const auto        &K = system.matrix();
    const unsigned int n = elasticity.get_dof_handler().n_dofs();

    // Ipopt itself runs in a plugin (see solve_with_ipopt()).
    auto qp = std::make_unique<QuadraticProgram>();
    qp->f.resize(n);
    for (unsigned int i = 0; i < n; ++i)
      qp->f[i] = system.rhs()[i];
    for (unsigned int row = 0; row < n; ++row)
      for (auto entry = K.begin(row); entry != K.end(row); ++entry)
        if (entry->column() <= row && entry->value() != 0.)
          {
            qp->K_row.push_back(row);
            qp->K_col.push_back(entry->column());
            qp->K_value.push_back(entry->value());
          }

    qp->lower.assign(n, -2e19);
    qp->upper.assign(n, 2e19);
    for (const auto &line : dirichlet.get_lines())
      {
        AssertThrow(line.entries.empty(),
                    ExcMessage("Only Dirichlet constraints are supported."));
        qp->lower[line.index] = qp->upper[line.index] = line.inhomogeneity;
      }

    const auto &nodes = coupling.slave_nodes();
    row_of_node.assign(nodes.size(), numbers::invalid_unsigned_int);
    for (unsigned int j = 0; j < nodes.size(); ++j)
      if (nodes[j].covered)
        {
          const int row  = qp->gap_bound.size();
          row_of_node[j] = row;
          qp->gap_bound.push_back(-nodes[j].weighted_gap);
          for (auto e = B.begin(j); e != B.end(j); ++e)
            {
              qp->B_row.push_back(row);
              qp->B_col.push_back(B.surface_dofs()[e->column]);
              qp->B_value.push_back(-e->value);
            }
        }
    return qp;
  }

  // Multipliers, gaps and the active set of the active-set method.
  void
  IpoptSolver::read_state(const QuadraticProgram          &qp,
                          const Mortar::MortarOperator    &B,
                          const std::vector<unsigned int> &row_of_node,
                          ContactState                    &state) const
  {
    const auto           &nodes = coupling.slave_nodes();
    const ActiveSetUpdate update(pcout, slave_youngs_modulus);
    state.active.assign(nodes.size(), false);
    state.pressure.assign(nodes.size(), 0.);
    state.gap.assign(nodes.size(), std::numeric_limits<double>::quiet_NaN());
    state.displacement.assign(nodes.size(), Tensor<1, 3>());
    state.master_displacement = 0;
    if (qp.lambda_solution.empty())
      return;
    std::vector<double> u_surface(B.n_columns());
    for (unsigned int c = 0; c < B.n_columns(); ++c)
      u_surface[c] = qp.x_solution[B.surface_dofs()[c]];
    for (unsigned int c = B.n_slave_columns(); c < B.n_columns(); c += 3)
      state.master_displacement =
        std::max(state.master_displacement,
                 std::sqrt(u_surface[c] * u_surface[c] +
                           u_surface[c + 1] * u_surface[c + 1] +
                           u_surface[c + 2] * u_surface[c + 2]));
    for (unsigned int j = 0; j < nodes.size(); ++j)
      {
        for (unsigned int e = 0; e < 3; ++e)
          state.displacement[j][e] = u_surface[3 * j + e];
        if (row_of_node[j] == numbers::invalid_unsigned_int)
          continue;
        state.pressure[j] = -qp.lambda_solution[row_of_node[j]];
        state.gap[j]      = B.gap(j, u_surface.data());
        state.active[j] =
          update.complementarity(nodes[j], state.pressure[j], state.gap[j]) > 0;
      }
  }
} // namespace TKR::Contact
