// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#ifndef tkr_contact_ipopt_qp_loader_h
#define tkr_contact_ipopt_qp_loader_h

#include <string>
#include <vector>

namespace TKR::Contact
{
  /**
   * A convex quadratic program in triplet form, the way IpoptSolver builds
   * it (indices from zero):
   *
   *   min 1/2 x^T K x - f^T x  s.t.  lower <= x <= upper,
   *                                  B x >= gap_bound,
   *
   * K by its lower triangle (K_row >= K_col). solve_with_ipopt() fills the
   * results.
   */
  struct QuadraticProgram
  {
    std::vector<int>    K_row, K_col;
    std::vector<double> K_value, f, lower, upper;
    std::vector<int>    B_row, B_col;
    std::vector<double> B_value, gap_bound;

    /** The minimiser and Ipopt's constraint multipliers (empty if Ipopt
     * returned none). */
    std::vector<double> x_solution, lambda_solution;
    /** Ipopt's finalize_solution() reported SUCCESS. */
    bool solved = false;
    /** Ipopt's ApplicationReturnStatus (0: Solve_Succeeded). */
    int status = -1;
    /** Ipopt's iterations. */
    unsigned int iterations = 0;

    /** Ipopt's status and the solution both say "solved". */
    bool
    converged() const
    {
      return solved && status == 0;
    }
  };

  /**
   * Solve @p qp with Ipopt (interior point, its sequential MUMPS) to the
   * relative tolerance @p tolerance in at most @p max_iterations
   * iterations.
   *
   * Ipopt lives in a plugin, libtkr-ipopt.so, which this function opens
   * with dlopen(RTLD_NOW | RTLD_LOCAL | RTLD_DEEPBIND): Ipopt's sequential
   * MUMPS and the parallel MUMPS that Trilinos Amesos brings along define
   * the same symbols (dmumps_c, MPI stubs), and linked into one executable
   * the loader binds one of them for both, depending on the link order.
   * Loaded this way, the plugin's symbols resolve inside its own
   * dependencies first and never enter the global scope. Throws
   * ExcInputError if the plugin cannot be found or loaded.
   */
  void
  solve_with_ipopt(QuadraticProgram  &qp,
                   const double       tolerance,
                   const unsigned int max_iterations);

  /**
   * Where the plugin is looked for, in this order: the environment variable
   * TKR_IPOPT_PLUGIN (a file), the folder of libtkr.so, the build tree
   * (compiled in).
   */
  std::vector<std::string>
  ipopt_plugin_candidates();
} // namespace TKR::Contact

#endif
