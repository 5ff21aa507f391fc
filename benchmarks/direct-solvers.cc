// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.
//
// Direct solvers for the stiffness matrix of a mesh: factorisation time and
// the time of many right-hand sides at once, as the condensed active set
// uses them (doc/performance.md).
//   cmake --build build/release --target direct-solvers (scripts/run-tests
//   builds it)
//   build/release/direct-solvers FILE.prm SOLVER [N_RHS]
// from the project root (where the parameter file's mesh path starts), with
// SOLVER one of
//   cholmod       Elasticity::DirectSolver (CHOLMOD, the solver tkr-wear uses)
//   Amesos_Klu    Trilinos Amesos KLU (tkr-wear's solver until 2026-12-01)
//   Amesos_Mumps  Trilinos Amesos MUMPS
// (The modes `orderings` and `forward` of doc/performance.md, which
// re-implemented the library's CHOLMOD conversion, were removed on
// 2026-12-05; they are in the history before that date.)
// The matrix is the two-body stiffness of the parameter file's mesh, the
// femur clamped on femur_fixation and the tibia held by springs on
// tibia_inferior. One MPI rank unless run with mpirun (cholmod only).

#include <deal.II/base/mpi.h>
#include <deal.II/base/timer.h>

#include <deal.II/distributed/shared_tria.h>

#include <deal.II/fe/mapping_q1.h>

#include <deal.II/numerics/vector_tools.h>

#include <tkr/elasticity/direct_solver.h>
#include <tkr/elasticity/elastic_system.h>
#include <tkr/elasticity/linear_elasticity.h>
#include <tkr/mesh/mesh.h>
#include <tkr/parameters/parameters.h>

#include <Amesos.h>
#include <Amesos_BaseSolver.h>
#include <Epetra_CrsMatrix.h>
#include <Epetra_LinearProblem.h>
#include <Epetra_MultiVector.h>

#include <iomanip>
#include <iostream>

using namespace dealii;
using namespace TKR;

namespace
{

  /** max over the columns of |A x - b| / |b|. */
  double
  relative_residual(const Epetra_CrsMatrix   &A,
                    const Epetra_MultiVector &X,
                    const Epetra_MultiVector &B)
  {
    Epetra_MultiVector R(B.Map(), B.NumVectors());
    A.Multiply(false, X, R);
    R.Update(-1., B, 1.);
    std::vector<double> r(B.NumVectors()), b(B.NumVectors());
    R.Norm2(r.data());
    B.Norm2(b.data());
    double worst = 0;
    for (int c = 0; c < B.NumVectors(); ++c)
      worst = std::max(worst, r[c] / b[c]);
    return worst;
  }

  void
  print(const std::string &what, const double value)
  {
    if (Utilities::MPI::this_mpi_process(MPI_COMM_WORLD) == 0)
      std::cout << std::left << std::setw(40) << what << ' ' << value
                << std::endl;
  }

  // Time KLU or MUMPS through Amesos, or DirectSolver.
  void
  time_solver(const std::string                    &solver_type,
              Epetra_CrsMatrix                     &A,
              const TrilinosWrappers::SparseMatrix &matrix,
              const unsigned int                    n_rhs)
  {
    Epetra_MultiVector X(A.OperatorDomainMap(), n_rhs),
      B(A.OperatorRangeMap(), n_rhs);
    B.Random();
    Epetra_MultiVector X1(A.OperatorDomainMap(), 1),
      B1(A.OperatorRangeMap(), 1);
    B1.Random();
    Timer t;
    if (solver_type == "cholmod")
      {
        Elasticity::DirectSolver solver;
        solver.factorize(matrix);
        print("factorisation (s)", t.wall_time());
        print("nonzeros of L", solver.n_factor_nonzeros());
        print("reciprocal condition estimate",
              solver.reciprocal_condition_estimate());
        t.restart();
        solver.solve(X, B);
        print(std::to_string(n_rhs) + " right-hand sides (s)", t.wall_time());
        t.restart();
        for (int i = 0; i < 10; ++i)
          solver.solve(X1, B1);
        print("1 right-hand side, mean of 10 (s)", t.wall_time() / 10);
      }
    else
      {
        Epetra_LinearProblem               problem(&A, &X, &B);
        Amesos                             factory;
        std::unique_ptr<Amesos_BaseSolver> solver(
          factory.Create(solver_type, problem));
        AssertThrow(solver != nullptr, ExcMessage("No such Amesos solver."));
        Teuchos::ParameterList list;
        solver->SetParameters(list);
        solver->SymbolicFactorization();
        solver->NumericFactorization();
        print("factorisation (s)", t.wall_time());
        t.restart();
        solver->Solve();
        print(std::to_string(n_rhs) + " right-hand sides (s)", t.wall_time());
        problem.SetLHS(&X1);
        problem.SetRHS(&B1);
        t.restart();
        for (int i = 0; i < 10; ++i)
          solver->Solve();
        print("1 right-hand side, mean of 10 (s)", t.wall_time() / 10);
      }
    print("relative residual, " + std::to_string(n_rhs) + " right-hand sides",
          relative_residual(A, X, B));
    print("relative residual, 1 right-hand side", relative_residual(A, X1, B1));
  }
} // namespace

int
main(int argc, char **argv)
{
  Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  AssertThrow(argc >= 3,
              ExcMessage("Usage: direct-solvers FILE.prm SOLVER [N_RHS]"));
  auto               prm         = Parameters::read_parameters(argv[1]);
  const std::string  solver_type = argv[2];
  const unsigned int n_rhs       = argc > 3 ? std::stoi(argv[3]) : 128;
  TimerOutput timer(std::cout, TimerOutput::never, TimerOutput::wall_times);
  parallel::shared::Triangulation<3> tria(
    MPI_COMM_WORLD,
    Triangulation<3>::none,
    false,
    parallel::shared::Triangulation<3>::partition_metis);
  Mesh::read_mesh(prm.mesh, tria);
  Elasticity::LinearElasticity el(tria,
                                  prm.materials,
                                  prm.linear_solver,
                                  1,
                                  MPI_COMM_WORLD,
                                  timer);
  el.distribute_dofs();
  MappingQ1<3>              mapping;
  AffineConstraints<double> c;
  VectorTools::interpolate_boundary_values(mapping,
                                           el.get_dof_handler(),
                                           Mesh::BoundaryIds::femur_fixation,
                                           Functions::ZeroFunction<3>(3),
                                           c);
  c.close();
  TKR::Elasticity::ElasticSystem system(el);
  system.setup(c);
  Elasticity::BoundaryLoads loads;
  Tensor<2, 3>              S;
  S[0][0] = S[1][1] = S[2][2]                      = 0.1;
  loads.springs[Mesh::BoundaryIds::tibia_inferior] = S;
  system.assemble(mapping, c, loads);
  print("DoFs", el.get_dof_handler().n_dofs());
  print("nonzeros of K", system.matrix().n_nonzero_elements());
  print("MPI ranks", Utilities::MPI::n_mpi_processes(MPI_COMM_WORLD));
  print("BLAS threads (0: not set)", Elasticity::DirectSolver::blas_threads());
  if (Utilities::MPI::this_mpi_process(MPI_COMM_WORLD) == 0)
    std::cout << "BLAS (dgemm_) from "
              << Elasticity::DirectSolver::blas_library() << std::endl;

  Epetra_CrsMatrix &A =
    const_cast<Epetra_CrsMatrix &>(system.matrix().trilinos_matrix());
  time_solver(solver_type, A, system.matrix(), n_rhs);
}
