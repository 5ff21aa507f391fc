// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#ifndef tkr_contact_ipopt_qp_h
#define tkr_contact_ipopt_qp_h

/*
 * The plain C interface between libtkr and the Ipopt plugin
 * (libtkr-ipopt.so, source/contact/ipopt_plugin/). Only arrays cross it: no
 * C++ objects, no exceptions, so the plugin can be loaded with dlopen(...,
 * RTLD_LOCAL | RTLD_DEEPBIND) and keep its own sequential MUMPS apart from
 * the parallel MUMPS of Trilinos Amesos (both define dmumps_c and MPI stubs;
 * see IpoptSolver).
 */

#ifdef __cplusplus
extern "C" {
#endif

/** Changed whenever the structs below change. */
#define TKR_IPOPT_QP_ABI_VERSION 1

/**
 * min 1/2 x^T K x - f^T x  s.t.  x_lower <= x <= x_upper,
 *                                 g_lower <= B x <= g_upper.
 * K by its lower triangle as triplets (row >= column), B as triplets; all
 * indices from zero. Bounds at or beyond +-1e19 mean none.
 */
struct TkrIpoptQP
{
  int           n_variables;
  int           n_K;
  const int    *K_row;
  const int    *K_column;
  const double *K_value;
  const double *f;
  const double *x_lower;
  const double *x_upper;

  int           n_constraints;
  int           n_B;
  const int    *B_row;
  const int    *B_column;
  const double *B_value;
  const double *g_lower;
  const double *g_upper;

  /** Ipopt's "tol" and "max_iter". */
  double tolerance;
  int    max_iterations;
};

/** Arrays allocated by the caller. */
struct TkrIpoptResult
{
  /** n_variables values: the minimiser. */
  double *x;
  /** n_constraints values: Ipopt's constraint multipliers. */
  double *lambda;
  /** Ipopt's ApplicationReturnStatus (0: Solve_Succeeded). */
  int status;
  /** 1 if Ipopt's finalize_solution reported SUCCESS, else 0. */
  int solved;
  /** Ipopt's iteration count (0 if unknown). */
  int iterations;
  /** 1 if x and lambda were written, else 0. */
  int has_solution;
  /** Why the call failed (empty if it did not). */
  char message[256];
};

/** Returns TKR_IPOPT_QP_ABI_VERSION of the plugin. */
int
tkr_ipopt_qp_abi_version(void);
typedef int (*TkrIpoptQPAbiVersion)(void);

/**
 * Solve the QP with Ipopt. Returns 0 if Ipopt ran (whatever its status),
 * nonzero (and a message) if it could not be set up or threw.
 */
int
tkr_ipopt_solve_qp(const struct TkrIpoptQP *qp, struct TkrIpoptResult *result);
typedef int (*TkrIpoptSolveQP)(const struct TkrIpoptQP *,
                               struct TkrIpoptResult *);

#define TKR_IPOPT_SOLVE_SUCCEEDED 0

#ifdef __cplusplus
}
#endif

#endif
