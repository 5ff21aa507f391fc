// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#include <tkr/base/exceptions.h>
#include <tkr/contact/ipopt_qp.h>
#include <tkr/contact/ipopt_qp_loader.h>

#include <dlfcn.h>

#include <algorithm>
#include <cstdlib>
#include <memory>

namespace TKR::Contact
{
  namespace
  {
    /** The file name of the plugin (CMake target tkr-ipopt). */
    const std::string plugin_file_name = "libtkr-ipopt.so";

    struct DlClose
    {
      void
      operator()(void *handle) const
      {
        dlclose(handle);
      }
    };

    /**
     * The opened plugin. RTLD_NOW: every symbol is bound now, while the
     * lookup scope is the one set up here (nothing left to a later lazy
     * lookup). RTLD_LOCAL: nothing of Ipopt or of its sequential MUMPS
     * enters the global scope, where it could capture other libraries'
     * references (the parallel MUMPS' MPI calls). RTLD_DEEPBIND: the
     * plugin and the libraries it loads look up symbols in their own
     * dependencies before the global scope, so Ipopt's dmumps_c is the
     * sequential one even if the executable has loaded the parallel one
     * first.
     */
    class IpoptPlugin
    {
    public:
      IpoptPlugin()
      {
        std::string tried;
        for (const std::string &path : ipopt_plugin_candidates())
          {
            handle.reset(
              dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL | RTLD_DEEPBIND));
            if (handle != nullptr)
              break;
            const char *error = dlerror();
            tried += "\n  " + path + " (" + (error ? error : "") + ")";
          }
        AssertThrow(handle != nullptr,
                    ExcInputError("The Ipopt solver needs the plugin " +
                                  plugin_file_name +
                                  ", which could not be loaded from:" + tried +
                                  "\nSet TKR_IPOPT_PLUGIN to its path."));

        const auto version = reinterpret_cast<TkrIpoptQPAbiVersion>(
          dlsym(handle.get(), "tkr_ipopt_qp_abi_version"));
        solve_qp = reinterpret_cast<TkrIpoptSolveQP>(
          dlsym(handle.get(), "tkr_ipopt_solve_qp"));
        AssertThrow(version != nullptr && solve_qp != nullptr &&
                      version() == TKR_IPOPT_QP_ABI_VERSION,
                    ExcInputError("The Ipopt plugin " + plugin_file_name +
                                  " does not belong to this libtkr (rebuild "
                                  "both)."));
      }

      TkrIpoptSolveQP solve_qp = nullptr;

    private:
      std::unique_ptr<void, DlClose> handle;
    };
  } // namespace

  std::vector<std::string>
  ipopt_plugin_candidates()
  {
    std::vector<std::string> candidates;
    if (const char *path = std::getenv("TKR_IPOPT_PLUGIN"))
      candidates.emplace_back(path);
    // The folder of the object that holds this function (libtkr.so).
    Dl_info info;
    if (dladdr(reinterpret_cast<void *>(&ipopt_plugin_candidates), &info) !=
          0 &&
        info.dli_fname != nullptr)
      {
        const std::string library = info.dli_fname;
        const auto        slash   = library.rfind('/');
        candidates.push_back((slash == std::string::npos ?
                                std::string(".") :
                                library.substr(0, slash)) +
                             "/" + plugin_file_name);
      }
#ifdef TKR_IPOPT_PLUGIN_PATH
    // The build tree (the same file as above unless libtkr.so was moved).
    if (std::find(candidates.begin(),
                  candidates.end(),
                  TKR_IPOPT_PLUGIN_PATH) == candidates.end())
      candidates.emplace_back(TKR_IPOPT_PLUGIN_PATH);
#endif
    return candidates;
  }

  void
  solve_with_ipopt(QuadraticProgram  &qp,
                   const double       tolerance,
                   const unsigned int max_iterations)
  {
    const IpoptPlugin plugin;

    const int  n = qp.f.size();
    const int  m = qp.gap_bound.size();
    TkrIpoptQP problem;
    problem.n_variables    = n;
    problem.n_K            = qp.K_value.size();
    problem.K_row          = qp.K_row.data();
    problem.K_column       = qp.K_col.data();
    problem.K_value        = qp.K_value.data();
    problem.f              = qp.f.data();
    problem.x_lower        = qp.lower.data();
    problem.x_upper        = qp.upper.data();
    problem.n_constraints  = m;
    problem.n_B            = qp.B_value.size();
    problem.B_row          = qp.B_row.data();
    problem.B_column       = qp.B_col.data();
    problem.B_value        = qp.B_value.data();
    problem.g_lower        = qp.gap_bound.data();
    problem.g_upper        = nullptr;
    problem.tolerance      = tolerance;
    problem.max_iterations = max_iterations;

    std::vector<double> x(n), lambda(m);
    TkrIpoptResult      result;
    result.x        = x.data();
    result.lambda   = lambda.data();
    const int error = plugin.solve_qp(&problem, &result);
    AssertThrow(error == 0, dealii::ExcMessage(result.message));

    qp.solved     = (result.solved != 0);
    qp.status     = result.status;
    qp.iterations = result.iterations;
    qp.x_solution.clear();
    qp.lambda_solution.clear();
    if (result.has_solution != 0)
      {
        qp.x_solution      = std::move(x);
        qp.lambda_solution = std::move(lambda);
      }
  }
} // namespace TKR::Contact
