// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#ifndef tkr_elasticity_direct_solver_h
#define tkr_elasticity_direct_solver_h

#include <deal.II/lac/trilinos_sparse_matrix.h>

#include <Amesos_BaseSolver.h>
#include <Epetra_LinearProblem.h>
#include <Epetra_MultiVector.h>

#include <memory>

namespace TKR::Elasticity
{
  /**
   * A sparse LU factorisation of a (distributed) Trilinos matrix by
   * Trilinos Amesos (KLU), kept for many solves with many right-hand sides
   * at once. Used where the stiffness matrix stays the same for thousands
   * of solves (the contact surface's compliance in the gait, see
   * Contact::CondensedActiveSetSolver). KLU rather than MUMPS: the
   * executable also links Ipopt's sequential MUMPS, whose symbols clash
   * with the parallel one.
   */
  class DirectSolver
  {
  public:
    /**
     * Factorise @p matrix (which must stay alive and unchanged while this
     * object is used). Throws ExcInputError with a sentence if the matrix
     * is singular.
     */
    void
    factorize(const dealii::TrilinosWrappers::SparseMatrix &matrix);

    /** Solve A X = B for all columns of @p B at once. */
    void
    solve(Epetra_MultiVector &X, const Epetra_MultiVector &B);

    /** The map of the matrix's rows (the layout of X and B). */
    const Epetra_Map &
    row_map() const;

    bool
    is_factorized() const
    {
      return solver != nullptr;
    }

  private:
    const dealii::TrilinosWrappers::SparseMatrix *matrix = nullptr;
    std::unique_ptr<Epetra_LinearProblem>         problem;
    std::unique_ptr<Amesos_BaseSolver>            solver;
  };
} // namespace TKR::Elasticity

#endif
