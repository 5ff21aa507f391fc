// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.

#include <tkr/base/exceptions.h>
#include <tkr/elasticity/direct_solver.h>

#include <Amesos.h>
#include <Epetra_CrsMatrix.h>
#include <Teuchos_ParameterList.hpp>

namespace TKR::Elasticity
{
  void
  DirectSolver::factorize(const dealii::TrilinosWrappers::SparseMatrix &A)
  {
    matrix = &A;
    // Amesos takes a non-const matrix but does not change it.
    problem = std::make_unique<Epetra_LinearProblem>();
    problem->SetOperator(const_cast<Epetra_CrsMatrix *>(&A.trilinos_matrix()));
    Amesos factory;
    solver.reset(factory.Create("Amesos_Klu", *problem));
    AssertThrow(solver != nullptr,
                ExcInputError("Trilinos Amesos has no KLU direct solver."));
    Teuchos::ParameterList parameters;
    solver->SetParameters(parameters);
    int ierr = solver->SymbolicFactorization();
    if (ierr == 0)
      ierr = solver->NumericFactorization();
    if (ierr != 0)
      {
        solver.reset();
        AssertThrow(false,
                    ExcInputError(
                      "The stiffness matrix is singular (Amesos error " +
                      std::to_string(ierr) +
                      "): a body can move as a rigid body. Check the "
                      "Dirichlet surfaces and the springs."));
      }
  }

  void
  DirectSolver::solve(Epetra_MultiVector &X, const Epetra_MultiVector &B)
  {
    Assert(solver != nullptr, dealii::ExcMessage("Call factorize() first."));
    problem->SetLHS(&X);
    problem->SetRHS(const_cast<Epetra_MultiVector *>(&B));
    const int ierr = solver->Solve();
    AssertThrow(ierr == 0,
                dealii::ExcMessage("Amesos solve failed with error " +
                                   std::to_string(ierr)));
  }

  const Epetra_Map &
  DirectSolver::row_map() const
  {
    return matrix->trilinos_matrix().RowMap();
  }
} // namespace TKR::Elasticity
