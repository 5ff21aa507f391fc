// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#include <deal.II/base/timer.h>

#include <tkr/base/exceptions.h>
#include <tkr/contact/ipopt_solver.h>

#include <IpIpoptApplication.hpp>
#include <IpSolveStatistics.hpp>
#include <IpTNLP.hpp>

#include <limits>

namespace TKR::Contact
{
  using namespace dealii;

  namespace
  {
    /**
     * The contact QP in Ipopt's TNLP form. K is given by its lower triangle
     * (Ipopt's convention for the Hessian), the constraints by their sparse
     * rows.
     */
    class ContactQP : public Ipopt::TNLP
    {
    public:
      using Index  = Ipopt::Index;
      using Number = Ipopt::Number;

      std::vector<Index>  K_row, K_col;
      std::vector<Number> K_value, f, lower, upper;
      std::vector<Index>  B_row, B_col;
      std::vector<Number> B_value, gap_bound;
      std::vector<Number> x_solution, lambda_solution;
      bool                solved = false;

      bool
      get_nlp_info(Index          &n,
                   Index          &m,
                   Index          &nnz_jac_g,
                   Index          &nnz_h_lag,
                   IndexStyleEnum &index_style) override
      {
        n           = f.size();
        m           = gap_bound.size();
        nnz_jac_g   = B_value.size();
        nnz_h_lag   = K_value.size();
        index_style = C_STYLE;
        return true;
      }

      bool
      get_bounds_info(Index,
                      Number *x_l,
                      Number *x_u,
                      Index   m,
                      Number *g_l,
                      Number *g_u) override
      {
        std::copy(lower.begin(), lower.end(), x_l);
        std::copy(upper.begin(), upper.end(), x_u);
        for (Index j = 0; j < m; ++j)
          {
            g_l[j] = gap_bound[j];
            g_u[j] = 2e19;
          }
        return true;
      }

      bool
      get_starting_point(Index n,
                         bool,
                         Number *x,
                         bool,
                         Number *,
                         Number *,
                         Index,
                         bool,
                         Number *) override
      {
        for (Index i = 0; i < n; ++i)
          x[i] = std::min(std::max(0., lower[i]), upper[i]);
        return true;
      }

      /** y = K x with K stored as its lower triangle. */
      void
      multiply(const Number *x, std::vector<Number> &y) const
      {
        y.assign(f.size(), 0.);
        for (std::size_t e = 0; e < K_value.size(); ++e)
          {
            y[K_row[e]] += K_value[e] * x[K_col[e]];
            if (K_row[e] != K_col[e])
              y[K_col[e]] += K_value[e] * x[K_row[e]];
          }
      }

      bool
      eval_f(Index n, const Number *x, bool, Number &value) override
      {
        std::vector<Number> Kx;
        multiply(x, Kx);
        value = 0;
        for (Index i = 0; i < n; ++i)
          value += 0.5 * x[i] * Kx[i] - f[i] * x[i];
        return true;
      }

      bool
      eval_grad_f(Index n, const Number *x, bool, Number *gradient) override
      {
        std::vector<Number> Kx;
        multiply(x, Kx);
        for (Index i = 0; i < n; ++i)
          gradient[i] = Kx[i] - f[i];
        return true;
      }

      bool
      eval_g(Index, const Number *x, bool, Index m, Number *g) override
      {
        std::fill(g, g + m, 0.);
        for (std::size_t e = 0; e < B_value.size(); ++e)
          g[B_row[e]] += B_value[e] * x[B_col[e]];
        return true;
      }

      bool
      eval_jac_g(Index,
                 const Number *,
                 bool,
                 Index,
                 Index,
                 Index  *row,
                 Index  *col,
                 Number *values) override
      {
        if (values == nullptr)
          {
            std::copy(B_row.begin(), B_row.end(), row);
            std::copy(B_col.begin(), B_col.end(), col);
          }
        else
          std::copy(B_value.begin(), B_value.end(), values);
        return true;
      }

      bool
      eval_h(Index,
             const Number *,
             bool,
             Number obj_factor,
             Index,
             const Number *,
             bool,
             Index,
             Index  *row,
             Index  *col,
             Number *values) override
      {
        if (values == nullptr)
          {
            std::copy(K_row.begin(), K_row.end(), row);
            std::copy(K_col.begin(), K_col.end(), col);
          }
        else
          for (std::size_t e = 0; e < K_value.size(); ++e)
            values[e] = obj_factor * K_value[e];
        return true;
      }

      void
      finalize_solution(Ipopt::SolverReturn status,
                        Index               n,
                        const Number       *x,
                        const Number *,
                        const Number *,
                        Index m,
                        const Number *,
                        const Number *lambda,
                        Number,
                        const Ipopt::IpoptData *,
                        Ipopt::IpoptCalculatedQuantities *) override
      {
        solved = (status == Ipopt::SUCCESS);
        x_solution.assign(x, x + n);
        lambda_solution.assign(lambda, lambda + m);
      }
    };
  } // namespace

  ContactStatistics
  IpoptSolver::solve(const Mapping<3>                &mapping,
                     const Elasticity::BoundaryLoads &loads,
                     const double,
                     ContactState &state)
  {
    AssertThrow(Utilities::MPI::n_mpi_processes(mpi_communicator) == 1,
                ExcInputError("Contact solver/Solver = ipopt (and the Ipopt "
                              "cross-check) run on one MPI rank only."));
    TimerOutput::Scope scope(timer, "Ipopt solve");

    // The unconstrained stiffness matrix and load vector.
    const AffineConstraints<double> none;
    elasticity.setup_system(none);
    elasticity.assemble_system(mapping, none, loads);
    const auto        &K = elasticity.get_system_matrix();
    const unsigned int n = elasticity.get_dof_handler().n_dofs();

    Ipopt::SmartPtr<ContactQP> qp = new ContactQP();
    qp->f.resize(n);
    for (unsigned int i = 0; i < n; ++i)
      qp->f[i] = elasticity.get_system_rhs()[i];
    for (unsigned int row = 0; row < n; ++row)
      for (auto entry = K.begin(row); entry != K.end(row); ++entry)
        if (entry->column() <= row && entry->value() != 0.)
          {
            qp->K_row.push_back(row);
            qp->K_col.push_back(entry->column());
            qp->K_value.push_back(entry->value());
          }

    // Dirichlet values as fixed bounds.
    qp->lower.assign(n, -2e19);
    qp->upper.assign(n, 2e19);
    for (const auto &line : dirichlet.get_lines())
      {
        AssertThrow(line.entries.empty(),
                    ExcMessage("Only Dirichlet constraints are supported."));
        qp->lower[line.index] = qp->upper[line.index] = line.inhomogeneity;
      }

    // One linear inequality per covered slave node: g_j - B_j u >= 0.
    const auto                  &nodes = coupling.slave_nodes();
    const Mortar::MortarOperator B(coupling);
    std::vector<unsigned int>    row_of_node(nodes.size(),
                                          numbers::invalid_unsigned_int);
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

    Ipopt::SmartPtr<Ipopt::IpoptApplication> ipopt = IpoptApplicationFactory();
    ipopt->Options()->SetIntegerValue("print_level", 0);
    ipopt->Options()->SetStringValue("sb", "yes");
    ipopt->Options()->SetNumericValue("tol", 1e-2 * parameters.tolerance);
    ipopt->Options()->SetIntegerValue("max_iter", 500);
    ipopt->Options()->SetStringValue("mu_strategy", "adaptive");
    ipopt->Options()->SetStringValue("hessian_constant", "yes");
    ipopt->Options()->SetStringValue("jac_c_constant", "yes");
    ipopt->Options()->SetStringValue("jac_d_constant", "yes");
    AssertThrow(ipopt->Initialize() == Ipopt::Solve_Succeeded,
                ExcMessage("Ipopt could not be initialised."));
    const Ipopt::ApplicationReturnStatus status = ipopt->OptimizeTNLP(qp);

    // Back into the elasticity solution and the contact state.
    TrilinosWrappers::MPI::Vector u(elasticity.locally_owned_dofs(),
                                    mpi_communicator);
    for (unsigned int i = 0; i < n; ++i)
      u[i] = qp->x_solution.empty() ? 0. : qp->x_solution[i];
    u.compress(VectorOperation::insert);
    elasticity.set_solution(u);

    ContactStatistics statistics;
    statistics.converged = qp->solved && status == Ipopt::Solve_Succeeded;
    statistics.newton_iterations = Ipopt::IsValid(ipopt->Statistics()) ?
                                     ipopt->Statistics()->IterationCount() :
                                     0;
    // Multipliers, gaps and the active set of the active-set method.
    const ActiveSetUpdate update(pcout, slave_youngs_modulus);
    state.active.assign(nodes.size(), false);
    state.pressure.assign(nodes.size(), 0.);
    state.gap.assign(nodes.size(), std::numeric_limits<double>::quiet_NaN());
    state.displacement.assign(nodes.size(), Tensor<1, 3>());
    if (!qp->lambda_solution.empty())
      {
        std::vector<double> u_surface(B.n_columns());
        for (unsigned int c = 0; c < B.n_columns(); ++c)
          u_surface[c] = qp->x_solution[B.surface_dofs()[c]];
        for (unsigned int j = 0; j < nodes.size(); ++j)
          {
            for (unsigned int e = 0; e < 3; ++e)
              state.displacement[j][e] = u_surface[3 * j + e];
            if (row_of_node[j] == numbers::invalid_unsigned_int)
              continue;
            state.pressure[j] = -qp->lambda_solution[row_of_node[j]];
            state.gap[j]      = B.gap(j, u_surface.data());
            state.active[j]   = update.complementarity(nodes[j],
                                                     state.pressure[j],
                                                     state.gap[j]) > 0;
          }
      }
    add_contact_results(coupling, state, statistics);
    return statistics;
  }
} // namespace TKR::Contact
