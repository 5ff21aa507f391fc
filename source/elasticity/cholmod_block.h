// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.
//
// Private to source/elasticity: one block of DirectSolver's matrix (a body)
// factorised by CHOLMOD, and the BLAS threads of its calls.

#ifndef tkr_source_elasticity_cholmod_block_h
#define tkr_source_elasticity_cholmod_block_h

#include <tkr/elasticity/direct_solver.h>

#include <suitesparse/cholmod.h>

#include <vector>

namespace TKR::Elasticity
{
  namespace internal
  {
    using Index = SuiteSparse_long;

    /** OpenBLAS' thread control (null with another BLAS). */
    struct OpenBlasThreads
    {
      using Set = void (*)(int);
      using Get = int (*)();
      Set set;
      Get get;

      OpenBlasThreads();
    };

    /**
     * The BLAS runs with @p n threads while this object lives (nothing
     * happens for n = 0 or with another BLAS than OpenBLAS).
     */
    class ScopedBlasThreads
    {
    public:
      explicit ScopedBlasThreads(const unsigned int n);

      ~ScopedBlasThreads();

    private:
      OpenBlasThreads blas;
      int             previous = 0;
    };
  } // namespace internal

  // One block of the matrix that no other row couples to (a body): its
  // rows, its lower triangle as factorised (to recognise it again) and
  // CHOLMOD's objects, freed in the destructor: the workspace (common), the
  // factor L and the dense buffers that cholmod_l_solve2() reuses for
  // single right-hand sides (batches have their own work space below).
  struct DirectSolver::Block
  {
    cholmod_common  common;
    cholmod_factor *L       = nullptr;
    cholmod_dense *X_buffer = nullptr, *Y_buffer = nullptr, *E_buffer = nullptr;
    /** The global rows, increasing. */
    std::vector<long long> rows;
    /** The lower triangle (compressed columns, local indices). */
    std::vector<internal::Index> column_start, row_index;
    std::vector<double>          values;

    Block()
    {
      cholmod_l_start(&common);
      // The errors become exceptions below; CHOLMOD prints nothing.
      common.print = 0;
      // Supernodal: the dense blocks of L go to the BLAS, where an optimised
      // BLAS makes the difference (doc/performance.md).
      common.supernodal = CHOLMOD_SUPERNODAL;
      // The ordering: CHOLMOD's default strategy, AMD, and METIS as well if
      // AMD's factor is dense (and then the smaller one). On the medium TKR
      // mesh METIS gives 35 % fewer nonzeros in L and a third of the flops
      // (doc/performance.md); on the coarse mesh AMD is as good and cheaper.
      common.nmethods = 0;
    }

    ~Block()
    {
      for (cholmod_dense **buffer : {&X_buffer, &Y_buffer, &E_buffer})
        cholmod_l_free_dense(buffer, &common);
      cholmod_l_free_factor(&L, &common);
      cholmod_l_finish(&common);
    }

    Block(const Block &) = delete;
    Block &
    operator=(const Block &) = delete;

    /** The same rows and the same lower triangle as @p other. */
    bool
    same_matrix(const Block &other) const
    {
      return rows == other.rows && column_start == other.column_start &&
             row_index == other.row_index && values == other.values;
    }

    /**
     * Per row of the permuted matrix: its supernode; per supernode: its
     * parent in the supernodal elimination tree (-1 for a root). Set by
     * factorise().
     */
    std::vector<internal::Index> supernode_of_row, parent_supernode;

    /**
     * The work space of a batch's solve: the permuted right-hand sides
     * and solutions, CHOLMOD's update buffer, the supernodes that the
     * forward solve visits, and the solutions in the block's order.
     */
    std::vector<double> permuted, updates, solutions;
    std::vector<char>   visited;

    /** Order and factorise the lower triangle; refuse a singular one. */
    void
    factorise();

    /**
     * Solve for the @p m columns of @p B (n_rows() x m, column-major);
     * returns the solutions, in the same layout.
     */
    const double *
    solve(const double         *B,
          const internal::Index m,
          const unsigned int    blas_threads);

    /**
     * solve() for m > 1 columns: CHOLMOD's supernodal solve, whose forward
     * substitution visits only the supernodes on the paths from the
     * right-hand sides' nonzero rows to the roots of the elimination tree
     * (the others stay zero; a unit load's column touches a few percent
     * of them); the same operations on those, so the same solutions.
     */
    const double *
    solve_batch(const double *B, const internal::Index m);

    internal::Index
    n_rows() const
    {
      return rows.size();
    }
  };

} // namespace TKR::Elasticity

#endif
