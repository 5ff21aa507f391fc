// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#ifndef tkr_elasticity_direct_solver_h
#define tkr_elasticity_direct_solver_h

#include <deal.II/lac/trilinos_sparse_matrix.h>

#include <Epetra_Map.h>
#include <Epetra_MultiVector.h>

#include <memory>
#include <string>

namespace TKR::Elasticity
{
  /**
   * A sparse Cholesky factorisation K = P^T L L^T P of a symmetric positive
   * definite (distributed) Trilinos matrix by CHOLMOD (SuiteSparse;
   * supernodal, AMD or METIS ordering, whichever fills less; dense kernels
   * from the system BLAS, which must be an optimised one such as OpenBLAS),
   * kept for many solves with many right-hand sides at once. Used where the
   * stiffness matrix stays the same for thousands of solves (the contact
   * surface's compliance in the gait, see Contact::CondensedActiveSetSolver).
   * On the 55,677-DoF medium TKR matrix it factorises in 1.4 to 2.7 s
   * and solves 128 right-hand sides in 0.6 to 0.8 s (on a loaded two-core
   * machine), where Amesos KLU took 127 s and 9.8 s (doc/performance.md).
   *
   * The rows that no entry couples (the bodies of a contact problem: they
   * touch only through the contact constraints) are factorised as separate
   * blocks, at most eight: a right-hand side that is zero on a block's rows
   * costs nothing there (the compliance columns of one body's surface), and
   * factorize() keeps a block's factor when the block is the same as in the
   * last call (the femur's, when only the insert's geometry changed). Rows
   * with nothing but a diagonal entry (constrained DoFs) are divided.
   *
   * CHOLMOD is sequential. With more than one rank in the matrix's
   * communicator, every rank gathers the whole matrix and factorises it
   * (redundantly: the same wall time as one rank, no communication in the
   * solves' critical path); solve() gathers all right-hand sides to every
   * rank, each rank solves a contiguous share of the columns, and one
   * all-gather returns each rank its rows of all solutions.
   *
   * K must be symmetric (only its upper triangle, row i and columns j >= i,
   * is read) and positive definite: constrained rows (AffineConstraints)
   * are diagonal.
   */
  class DirectSolver
  {
  public:
    DirectSolver();
    ~DirectSolver();
    DirectSolver(DirectSolver &&) noexcept;
    DirectSolver &
    operator=(DirectSolver &&) noexcept;

    /**
     * Factorise @p matrix (which must stay alive and unchanged while this
     * object is used). Throws ExcInputError with a sentence if the matrix
     * is singular or not positive definite. The BLAS runs with
     * blas_threads() threads meanwhile.
     */
    void
    factorize(const dealii::TrilinosWrappers::SparseMatrix &matrix);

    /**
     * Solve K X = B for all columns of @p B at once (both with the row
     * map's layout). Many columns per call are much faster per column than
     * one at a time (the supernodal solve then runs on BLAS-3 kernels).
     */
    void
    solve(Epetra_MultiVector &X, const Epetra_MultiVector &B);

    /** The map of the matrix's rows (the layout of X and B). */
    const Epetra_Map &
    row_map() const;

    bool
    is_factorized() const;

    /** The blocks factorised separately. */
    unsigned int
    n_blocks() const;

    /**
     * The blocks whose factor the last factorize() kept from the call
     * before (the same rows and entries).
     */
    unsigned int
    n_kept_blocks() const;

    /** Nonzeros of the factor L (for reports and benchmarks). */
    double
    n_factor_nonzeros() const;

    /**
     * CHOLMOD's estimate of the reciprocal condition number,
     * (min_i L_ii / max_i L_ii)^2.
     */
    double
    reciprocal_condition_estimate() const;

    /**
     * The threads the BLAS (OpenBLAS) gets during the factorisation and
     * solves with many right-hand sides: the cores this process may run on
     * (its CPU affinity) divided by the number of ranks of MPI_COMM_WORLD
     * on the node (OMPI_COMM_WORLD_LOCAL_SIZE or MPI_LOCALNRANKS, else all
     * ranks), at least one, so that the ranks on a node do not
     * oversubscribe its cores. Solves with few right-hand sides use one
     * thread. Returns 0, and the solver leaves the threads alone, if the
     * BLAS is not OpenBLAS or the user set OPENBLAS_NUM_THREADS,
     * GOTO_NUM_THREADS or OMP_NUM_THREADS. The previous setting is
     * restored after each call, so other BLAS users are not affected.
     */
    static unsigned int
    blas_threads();

    /**
     * The file of the library that provides the BLAS routine dgemm_ in
     * this process (to check that it is OpenBLAS and not the reference
     * BLAS).
     */
    static std::string
    blas_library();

  private:
    struct Block;
    struct Factorization;
    const dealii::TrilinosWrappers::SparseMatrix *matrix = nullptr;
    std::unique_ptr<Factorization>                factorization;
  };
} // namespace TKR::Elasticity

#endif
