// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.
//
// Direct solvers for the stiffness matrix of a mesh: factorisation time and
// the time of many right-hand sides at once, as the condensed active set
// uses them (doc/performance.md).
//   make direct-solvers
//   build/direct-solvers FILE.prm Amesos_Klu|Amesos_Mumps N_RHS  (from the
// project root, where the parameter file's mesh path starts)
// The matrix is the two-body stiffness of the parameter file's mesh, the
// femur clamped on femur_fixation and the tibia held by springs on
// tibia_inferior.
#include <Amesos.h>
#include <Amesos_BaseSolver.h>
#include <Epetra_CrsMatrix.h>
#include <Epetra_LinearProblem.h>
#include <Epetra_MultiVector.h>
#include <deal.II/base/mpi.h>
#include <deal.II/base/timer.h>
#include <deal.II/distributed/shared_tria.h>
#include <deal.II/fe/mapping_q1.h>
#include <deal.II/numerics/vector_tools.h>
#include <iostream>
#include <tkr/elasticity/linear_elasticity.h>
#include <tkr/mesh/mesh.h>
#include <tkr/parameters/parameters.h>
using namespace dealii;
using namespace TKR;
int
main(int argc, char **argv)
{
  Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  auto                             prm = Parameters::read_parameters(argv[1]);
  const std::string                solver_type = argv[2];
  const unsigned int               nrhs        = std::stoi(argv[3]);
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
  el.setup_system(c);
  Elasticity::BoundaryLoads loads;
  Tensor<2, 3>              S;
  S[0][0] = S[1][1] = S[2][2]                      = 0.1;
  loads.springs[Mesh::BoundaryIds::tibia_inferior] = S;
  el.assemble_system(mapping, c, loads);
  std::cout << "dofs " << el.get_dof_handler().n_dofs() << " nnz "
            << el.get_system_matrix().n_nonzero_elements() << std::endl;
  Timer             t;
  Epetra_CrsMatrix &A =
    const_cast<Epetra_CrsMatrix &>(el.get_system_matrix().trilinos_matrix());
  Epetra_MultiVector X(A.OperatorDomainMap(), nrhs),
    B(A.OperatorRangeMap(), nrhs);
  B.Random();
  Epetra_LinearProblem               problem(&A, &X, &B);
  Amesos                             factory;
  std::unique_ptr<Amesos_BaseSolver> solver(
    factory.Create(solver_type, problem));
  if (!solver)
    {
      std::cout << "no solver\n";
      return 1;
    }
  Teuchos::ParameterList list;
  solver->SetParameters(list);
  solver->SymbolicFactorization();
  std::cout << "symbolic " << t.wall_time() << std::endl;
  t.restart();
  solver->NumericFactorization();
  std::cout << "numeric " << t.wall_time() << std::endl;
  t.restart();
  solver->Solve();
  std::cout << nrhs << " rhs solve " << t.wall_time() << std::endl;
  t.restart();
  Epetra_MultiVector X1(A.OperatorDomainMap(), 1), B1(A.OperatorRangeMap(), 1);
  B1.Random();
  problem.SetLHS(&X1);
  problem.SetRHS(&B1);
  for (int i = 0; i < 10; ++i)
    solver->Solve();
  std::cout << "10 single solves " << t.wall_time() << std::endl;
  // residual check
  Epetra_MultiVector R(A.OperatorRangeMap(), 1);
  A.Multiply(false, X1, R);
  R.Update(-1., B1, 1.);
  double rn, bn;
  R.Norm2(&rn);
  B1.Norm2(&bn);
  std::cout << "rel res " << rn / bn << std::endl;
}
