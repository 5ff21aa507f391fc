// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.
//
// The Ipopt plugin, libtkr-ipopt.so: the contact QP as an Ipopt TNLP and
// the one call of Ipopt, behind the plain C function of
// tkr/contact/ipopt_qp.h. It is the only code that links Ipopt (and so
// Ipopt's sequential MUMPS, libdmumps_seq). libtkr never links it: it opens
// it with dlopen(RTLD_NOW | RTLD_LOCAL | RTLD_DEEPBIND)
// (contact/ipopt_qp_loader.cc), so that Ipopt's references to dmumps_c and
// MUMPS' references to its MPI stubs resolve inside this plugin's own
// dependencies, whatever the executable links and in which order, and the
// sequential MUMPS never enters the global scope, where it would capture
// the parallel MUMPS' MPI calls. Built without deal.II; nothing but arrays
// and an error message leave it.

#include <tkr/contact/ipopt_qp.h>

#include <IpIpoptApplication.hpp>
#include <IpSolveStatistics.hpp>
#include <IpTNLP.hpp>

#include <algorithm>
#include <cstdio>
#include <exception>
#include <vector>

#define TKR_PLUGIN_EXPORT __attribute__((visibility("default")))

namespace
{
  /**
   * The QP of a TkrIpoptQP in Ipopt's TNLP form (the Hessian is K: Ipopt
   * takes its lower triangle).
   */
  class ContactQP : public Ipopt::TNLP
  {
  public:
    using Index  = Ipopt::Index;
    using Number = Ipopt::Number;

    ContactQP(const TkrIpoptQP &qp, TkrIpoptResult &result)
      : qp(qp)
      , result(result)
    {}

    bool
    get_nlp_info(Index          &n,
                 Index          &m,
                 Index          &nnz_jac_g,
                 Index          &nnz_h_lag,
                 IndexStyleEnum &index_style) override
    {
      n           = qp.n_variables;
      m           = qp.n_constraints;
      nnz_jac_g   = qp.n_B;
      nnz_h_lag   = qp.n_K;
      index_style = C_STYLE;
      return true;
    }

    bool
    get_bounds_info(Index   n,
                    Number *x_l,
                    Number *x_u,
                    Index   m,
                    Number *g_l,
                    Number *g_u) override
    {
      std::copy(qp.x_lower, qp.x_lower + n, x_l);
      std::copy(qp.x_upper, qp.x_upper + n, x_u);
      for (Index j = 0; j < m; ++j)
        {
          g_l[j] = qp.g_lower != nullptr ? qp.g_lower[j] : -2e19;
          g_u[j] = qp.g_upper != nullptr ? qp.g_upper[j] : 2e19;
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
        x[i] = std::min(std::max(0., qp.x_lower[i]), qp.x_upper[i]);
      return true;
    }

    /** y = K x with K stored as its lower triangle. */
    void
    multiply(const Number *x, std::vector<Number> &y) const
    {
      y.assign(qp.n_variables, 0.);
      for (Index e = 0; e < qp.n_K; ++e)
        {
          y[qp.K_row[e]] += qp.K_value[e] * x[qp.K_column[e]];
          if (qp.K_row[e] != qp.K_column[e])
            y[qp.K_column[e]] += qp.K_value[e] * x[qp.K_row[e]];
        }
    }

    bool
    eval_f(Index n, const Number *x, bool, Number &value) override
    {
      std::vector<Number> Kx;
      multiply(x, Kx);
      value = 0;
      for (Index i = 0; i < n; ++i)
        value += 0.5 * x[i] * Kx[i] - qp.f[i] * x[i];
      return true;
    }

    bool
    eval_grad_f(Index n, const Number *x, bool, Number *gradient) override
    {
      std::vector<Number> Kx;
      multiply(x, Kx);
      for (Index i = 0; i < n; ++i)
        gradient[i] = Kx[i] - qp.f[i];
      return true;
    }

    bool
    eval_g(Index, const Number *x, bool, Index m, Number *g) override
    {
      std::fill(g, g + m, 0.);
      for (Index e = 0; e < qp.n_B; ++e)
        g[qp.B_row[e]] += qp.B_value[e] * x[qp.B_column[e]];
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
          std::copy(qp.B_row, qp.B_row + qp.n_B, row);
          std::copy(qp.B_column, qp.B_column + qp.n_B, col);
        }
      else
        std::copy(qp.B_value, qp.B_value + qp.n_B, values);
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
          std::copy(qp.K_row, qp.K_row + qp.n_K, row);
          std::copy(qp.K_column, qp.K_column + qp.n_K, col);
        }
      else
        for (Index e = 0; e < qp.n_K; ++e)
          values[e] = obj_factor * qp.K_value[e];
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
      result.solved = (status == Ipopt::SUCCESS) ? 1 : 0;
      std::copy(x, x + n, result.x);
      std::copy(lambda, lambda + m, result.lambda);
      result.has_solution = 1;
    }

  private:
    const TkrIpoptQP &qp;
    TkrIpoptResult   &result;
  };
} // namespace

extern "C" TKR_PLUGIN_EXPORT int
tkr_ipopt_qp_abi_version(void)
{
  return TKR_IPOPT_QP_ABI_VERSION;
}

extern "C" TKR_PLUGIN_EXPORT int
tkr_ipopt_solve_qp(const TkrIpoptQP *qp, TkrIpoptResult *result)
{
  result->status       = -1;
  result->solved       = 0;
  result->iterations   = 0;
  result->has_solution = 0;
  result->message[0]   = '\0';
  // No exception may cross the C interface.
  try
    {
      Ipopt::SmartPtr<ContactQP> nlp = new ContactQP(*qp, *result);
      Ipopt::SmartPtr<Ipopt::IpoptApplication> ipopt =
        IpoptApplicationFactory();
      ipopt->Options()->SetIntegerValue("print_level", 0);
      ipopt->Options()->SetStringValue("sb", "yes");
      ipopt->Options()->SetNumericValue("tol", qp->tolerance);
      ipopt->Options()->SetIntegerValue("max_iter", qp->max_iterations);
      ipopt->Options()->SetStringValue("mu_strategy", "adaptive");
      ipopt->Options()->SetStringValue("hessian_constant", "yes");
      ipopt->Options()->SetStringValue("jac_c_constant", "yes");
      ipopt->Options()->SetStringValue("jac_d_constant", "yes");
      if (ipopt->Initialize() != Ipopt::Solve_Succeeded)
        {
          std::snprintf(result->message,
                        sizeof(result->message),
                        "Ipopt could not be initialised.");
          return 1;
        }
      result->status = ipopt->OptimizeTNLP(nlp);
      if (Ipopt::IsValid(ipopt->Statistics()))
        result->iterations = ipopt->Statistics()->IterationCount();
      return 0;
    }
  catch (const std::exception &e)
    {
      std::snprintf(result->message,
                    sizeof(result->message),
                    "Ipopt threw: %s",
                    e.what());
    }
  catch (...)
    {
      std::snprintf(result->message,
                    sizeof(result->message),
                    "Ipopt threw an exception.");
    }
  return 1;
}
