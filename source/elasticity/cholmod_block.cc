// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.
//
// DirectSolver::Block: CHOLMOD's ordering, factorisation and solves of one
// block of the stiffness matrix (a body).

#include <tkr/base/exceptions.h>

#include <dlfcn.h>

#include <string>

#include "cholmod_block.h"

namespace TKR::Elasticity
{
  using internal::Index;
  using internal::ScopedBlasThreads;

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
  }

  const double *
  DirectSolver::Block::solve(const double      *B,
                             const Index        m,
                             const unsigned int blas_threads)
  {
    SolveBuffers &buffers = (m == 1) ? single : batch;
    // BLAS threads only for many columns: with a few, the supernodal
    // solve is a sequence of matrix-vector products, bound by memory
    // bandwidth, and threads only cost synchronisation (one right-hand
    // side on the medium TKR mesh: 30-37 ms with one thread, 37-92 ms
    // with two; doc/performance.md).
    ScopedBlasThreads threads(m >= 8 ? blas_threads : blas_threads > 0 ? 1 : 0);
    // A header for the right-hand sides (CHOLMOD only reads B).
    cholmod_dense B_header;
    B_header.nrow  = n_rows();
    B_header.ncol  = m;
    B_header.nzmax = n_rows() * m;
    B_header.d     = n_rows();
    B_header.x     = const_cast<double *>(B);
    B_header.z     = nullptr;
    B_header.xtype = CHOLMOD_REAL;
    B_header.dtype = CHOLMOD_DOUBLE;
    const int ok   = cholmod_l_solve2(CHOLMOD_A,
                                    L,
                                    &B_header,
                                    nullptr,
                                    &buffers.X,
                                    nullptr,
                                    &buffers.Y,
                                    &buffers.E,
                                    &common);
    AssertThrow(ok != 0,
                dealii::ExcMessage("CHOLMOD solve failed (status " +
                                   std::to_string(common.status) + ")."));
    return static_cast<const double *>(buffers.X->x);
  }

} // namespace TKR::Elasticity
