// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.
//
// DirectSolver::Block: CHOLMOD's ordering, factorisation and solves of one
// block of the stiffness matrix (a body).

#include <deal.II/lac/lapack_templates.h>

#include <tkr/base/exceptions.h>

#include <dlfcn.h>

#include <algorithm>
#include <string>

#include "cholmod_block.h"

extern "C" {
// The triangular solve that CHOLMOD's supernodal solves call (Fortran
// interface; deal.II's lapack_templates.h has no wrapper for it).
void
dtrsm_(const char                    *side,
       const char                    *uplo,
       const char                    *transa,
       const char                    *diag,
       const dealii::types::blas_int *m,
       const dealii::types::blas_int *n,
       const double                  *alpha,
       const double                  *a,
       const dealii::types::blas_int *lda,
       double                        *b,
       const dealii::types::blas_int *ldb);
}

namespace TKR::Elasticity
{
  using internal::Index;
  using internal::ScopedBlasThreads;

  namespace
  {
    /** A CHOLMOD header for the column-major n_rows x n_columns @p x. */
    cholmod_dense
    dense_view(const double *x, const Index n_rows, const Index n_columns)
    {
      cholmod_dense header;
      header.nrow  = n_rows;
      header.ncol  = n_columns;
      header.nzmax = n_rows * n_columns;
      header.d     = n_rows;
      header.x     = const_cast<double *>(x);
      header.z     = nullptr;
      header.xtype = CHOLMOD_REAL;
      header.dtype = CHOLMOD_DOUBLE;
      return header;
    }

    void
    check_solve(const int ok, const cholmod_common &common)
    {
      AssertThrow(ok != 0,
                  dealii::ExcMessage("CHOLMOD solve failed (status " +
                                     std::to_string(common.status) + ")."));
    }
  } // namespace

  namespace internal
  {
    OpenBlasThreads::OpenBlasThreads()
      : set(reinterpret_cast<Set>(
          dlsym(RTLD_DEFAULT, "openblas_set_num_threads")))
      , get(reinterpret_cast<Get>(
          dlsym(RTLD_DEFAULT, "openblas_get_num_threads")))
    {}

    ScopedBlasThreads::ScopedBlasThreads(const unsigned int n)
    {
      if (n == 0 || blas.set == nullptr || blas.get == nullptr)
        return;
      previous = blas.get();
      if (previous != static_cast<int>(n))
        blas.set(n);
    }

    ScopedBlasThreads::~ScopedBlasThreads()
    {
      if (previous > 0 && previous != blas.get())
        blas.set(previous);
    }
  } // namespace internal

  void
  DirectSolver::Block::factorise()
  {
    const Index    n_block = n_rows();
    cholmod_sparse lower;
    lower.nrow   = n_block;
    lower.ncol   = n_block;
    lower.nzmax  = values.size();
    lower.p      = column_start.data();
    lower.i      = row_index.data();
    lower.nz     = nullptr;
    lower.x      = values.data();
    lower.z      = nullptr;
    lower.stype  = -1;
    lower.itype  = CHOLMOD_LONG;
    lower.xtype  = CHOLMOD_REAL;
    lower.dtype  = CHOLMOD_DOUBLE;
    lower.sorted = true;
    lower.packed = true;
    L            = cholmod_l_analyze(&lower, &common);
    AssertThrow(L != nullptr,
                ExcInputError("CHOLMOD could not order the stiffness matrix "
                              "(status " +
                              std::to_string(common.status) + ")."));
    cholmod_l_factorize(&lower, L, &common);
    AssertThrow(common.status != CHOLMOD_NOT_POSDEF &&
                  static_cast<Index>(L->minor) == n_block,
                ExcInputError(
                  "The stiffness matrix is singular or not positive definite "
                  "(CHOLMOD: pivot " +
                  std::to_string(L->minor) + " of the " +
                  std::to_string(n_block) +
                  " rows of one body): a body can move as a rigid body. Check "
                  "the Dirichlet surfaces and the springs."));
    AssertThrow(common.status >= CHOLMOD_OK,
                ExcInputError("CHOLMOD could not factorise the stiffness "
                              "matrix (status " +
                              std::to_string(common.status) +
                              "; out of memory?)."));
    // A rigid-body mode in floating point need not give a negative pivot,
    // only one at round-off level: (min L_ii / max L_ii)^2 about 1e-16.
    // The gait stiffness matrices of the TKR meshes have 1e-6 (coarse
    // 1.2e-6, medium 3.4e-6).
    const double rcond = cholmod_l_rcond(L, &common);
    AssertThrow(rcond > 1e-14,
                ExcInputError(
                  "The stiffness matrix is singular (CHOLMOD's reciprocal "
                  "condition estimate is " +
                  format_number(rcond) +
                  "): a body can move as a rigid body. Check the Dirichlet "
                  "surfaces and the springs."));

    // The supernodal elimination tree: a supernode's parent holds the
    // first row below its diagonal block.
    supernode_of_row.clear();
    parent_supernode.clear();
    if (L->is_super)
      {
        const Index  n_super = L->nsuper;
        const Index *super   = static_cast<const Index *>(L->super);
        const Index *pi      = static_cast<const Index *>(L->pi);
        const Index *L_rows  = static_cast<const Index *>(L->s);
        supernode_of_row.resize(n_block);
        for (Index s = 0; s < n_super; ++s)
          std::fill(supernode_of_row.begin() + super[s],
                    supernode_of_row.begin() + super[s + 1],
                    s);
        parent_supernode.resize(n_super);
        for (Index s = 0; s < n_super; ++s)
          {
            const Index n_columns = super[s + 1] - super[s];
            parent_supernode[s] =
              pi[s + 1] - pi[s] > n_columns ?
                supernode_of_row[L_rows[pi[s] + n_columns]] :
                -1;
          }
      }
  }

  const double *
  DirectSolver::Block::solve(const double      *B,
                             const Index        m,
                             const unsigned int blas_threads)
  {
    // BLAS threads only for many columns: with a few, the supernodal
    // solve is a sequence of matrix-vector products, bound by memory
    // bandwidth, and threads only cost synchronisation (one right-hand
    // side on the medium TKR mesh: 30-37 ms with one thread, 37-92 ms
    // with two; doc/performance.md).
    ScopedBlasThreads threads(m >= 8 ? blas_threads : blas_threads > 0 ? 1 : 0);
    if (m > 1 && L->is_super && L->is_ll && L->xtype == CHOLMOD_REAL)
      return solve_batch(B, m);
    // (CHOLMOD only reads B)
    cholmod_dense B_header = dense_view(B, n_rows(), m);
    check_solve(cholmod_l_solve2(CHOLMOD_A,
                                 L,
                                 &B_header,
                                 nullptr,
                                 &X_buffer,
                                 nullptr,
                                 &Y_buffer,
                                 &E_buffer,
                                 &common),
                common);
    return static_cast<const double *>(X_buffer->x);
  }

  // As cholmod_l_solve2() with CHOLMOD_A on a supernodal LL' factor:
  // Y = P B, Y = L \ Y (cholmod_super_lsolve()'s steps for several
  // columns, on the visited supernodes), Y = L' \ Y (CHOLMOD's own),
  // X = P' Y.
  const double *
  DirectSolver::Block::solve_batch(const double *B, const Index m)
  {
    const Index   n       = n_rows();
    const Index   n_super = L->nsuper;
    const Index  *perm    = static_cast<const Index *>(L->Perm);
    const Index  *super   = static_cast<const Index *>(L->super);
    const Index  *pi      = static_cast<const Index *>(L->pi);
    const Index  *px      = static_cast<const Index *>(L->px);
    const Index  *L_rows  = static_cast<const Index *>(L->s);
    const double *Lx      = static_cast<const double *>(L->x);

    permuted.resize(n * m);
    visited.assign(n_super, 0);
    for (Index j = 0; j < m; ++j)
      for (Index k = 0; k < n; ++k)
        {
          const double b      = B[perm[k] + j * n];
          permuted[k + j * n] = b;
          if (b != 0.)
            for (Index s = supernode_of_row[k]; s >= 0 && !visited[s];
                 s       = parent_supernode[s])
              visited[s] = 1;
        }

    updates.resize(m * L->maxesize);
    double                       *Y = permuted.data(), *E = updates.data();
    const dealii::types::blas_int n_rhs = m, ld = n;
    const double                  one = 1., minus_one = -1.;
    for (Index s = 0; s < n_super; ++s)
      if (visited[s])
        {
          const Index                   k1        = super[s];
          const dealii::types::blas_int n_columns = super[s + 1] - k1;
          const dealii::types::blas_int n_rows_s  = pi[s + 1] - pi[s];
          const dealii::types::blas_int n_below   = n_rows_s - n_columns;
          const Index                   below     = pi[s] + n_columns;
          for (Index ii = 0; ii < n_below; ++ii)
            for (Index j = 0; j < m; ++j)
              E[ii + j * n_below] = Y[L_rows[below + ii] + j * n];
          dtrsm_("L",
                 "L",
                 "N",
                 "N",
                 &n_columns,
                 &n_rhs,
                 &one,
                 Lx + px[s],
                 &n_rows_s,
                 Y + k1,
                 &ld);
          if (n_below > 0)
            dealii::gemm("N",
                         "N",
                         &n_below,
                         &n_rhs,
                         &n_columns,
                         &minus_one,
                         Lx + px[s] + n_columns,
                         &n_rows_s,
                         Y + k1,
                         &ld,
                         &one,
                         E,
                         &n_below);
          for (Index ii = 0; ii < n_below; ++ii)
            for (Index j = 0; j < m; ++j)
              Y[L_rows[below + ii] + j * n] = E[ii + j * n_below];
        }

    // (E as CHOLMOD's solve allocates it: m x maxesize)
    cholmod_dense Y_header = dense_view(Y, n, m),
                  E_header = dense_view(E, m, L->maxesize);
    check_solve(cholmod_l_super_ltsolve(L, &Y_header, &E_header, &common),
                common);

    solutions.resize(n * m);
    for (Index j = 0; j < m; ++j)
      for (Index k = 0; k < n; ++k)
        solutions[perm[k] + j * n] = Y[k + j * n];
    return solutions.data();
  }

} // namespace TKR::Elasticity
